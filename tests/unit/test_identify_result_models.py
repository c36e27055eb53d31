"""IdentificationResult JSON round trip for dynamic models (LuGre, GMS, Dahl, Directional)."""

from __future__ import annotations

import numpy as np

import frictionkit as fk
from frictionkit.identify.result import model_from_dict, model_to_dict


def test_dynamic_models_survive_json_round_trip():
    law = fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4, shape="lorentzian")
    for model in (
        fk.LuGre(law, sigma0=1e5, sigma1=63.2),
        fk.GMS(law, k=[1e4, 1e5], xi=[0.6, 0.4], C=20.0),
        fk.Dahl(Fc=1.0, sigma0=1e5, sigma2=0.1),
        fk.Directional(positive=fk.LuGre(law, sigma0=1e5, sigma1=1.0), negative=fk.LuGre(law, sigma0=2e5, sigma1=2.0)),
    ):
        back = model_from_dict(model_to_dict(model))
        assert type(back) is type(model)
        v = np.linspace(-0.01, 0.01, 7)
        np.testing.assert_array_equal(back.steady_state(v), model.steady_state(v))
        assert back == model
