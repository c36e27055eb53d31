"""The tuple form of the Stribeck magnitude used in hot loops equals the array form and the model."""

from __future__ import annotations

import numpy as np
import pytest

import frictionkit as fk
from frictionkit.kernels import _stribeck as S


def _laws():
    yield fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, delta=2.0, sigma2=0.4)
    yield fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, delta=1.0)
    yield fk.Stribeck(Fc=2.0, Fs=1.2, vs=3e-2, delta=0.7)  # Fs < Fc, pow path
    yield fk.Stribeck(Fc=0.3, Fs=0.9, vs=2e-3, delta=2.0, shape="lorentzian")
    yield fk.Directional(
        positive=fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3),
        negative=fk.Stribeck(Fc=0.8, Fs=1.1, vs=4e-3, delta=1.5, shape="lorentzian"),
    )


@pytest.mark.parametrize("law", list(_laws()), ids=lambda law: type(law).__name__)
def test_row_tuple_matches_array_form_and_model(law):
    P = np.ascontiguousarray(law.static_rows())
    for i, sign in ((0, 1.0), (1, -1.0)):
        p = S.row(P, i)
        vs = P[i, 2]
        # speeds from rest through the Stribeck range to far past the underflow cut-off,
        # including points just either side of it
        av = np.concatenate([[0.0], np.geomspace(1e-9, 10.0, 400)])
        if P[i, 5] == 0.0:
            cut = vs * S.UNDERFLOW ** (1.0 / P[i, 3])
            av = np.concatenate([av, cut * np.array([1 - 1e-12, 1.0, 1 + 1e-12])])
        for a in av:
            g_arr = S.g_only(P, i, a)
            g_tup = S.g_row(p, a)
            g_s, slope = S.g_slope_row(p, a)
            g_a2, slope_a = S.g_and_slope(P, i, a)
            assert g_tup == pytest.approx(g_arr, rel=1e-14, abs=1e-300)
            assert g_s == pytest.approx(g_arr, rel=1e-14)
            assert slope == pytest.approx(slope_a, rel=1e-12, abs=1e-12 * abs(P[i, 1] - P[i, 0]) / vs)
            assert S.ig_row(p, a) == pytest.approx(1.0 / g_arr, rel=1e-14)
            ig, sl2 = S.ig_slope_row(p, a)
            assert ig == pytest.approx(1.0 / g_arr, rel=1e-14) and sl2 == slope
        # and against the model's own steady-state map (without the viscous term)
        v = sign * np.geomspace(1e-6, 1.0, 50)
        model = law.steady_state(v) - P[i, 4] * v
        assert np.allclose([sign * S.g_row(p, abs(x)) for x in v], model, rtol=1e-12)
