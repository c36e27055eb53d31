"""One spelling for a dimensionless parameter (δ, ξ): "-" in fit tables, model files and the law listing;
TDMSSC's levels, slopes and quadratic term carry their units. Was (the new-user walk of 2026-11-23): a
static fit's δ printed "1", every other place "-"; TDMSSC's Fc0 ... eps were "-" in model files."""

from __future__ import annotations

import numpy as np

import frictionkit as fk
from frictionkit.identify import fit_static_map
from frictionkit.models.files import parameter_units


def test_static_fit_delta_is_dash():
    law = fk.Stribeck(Fc=1.0, Fs=1.5, vs=0.01, delta=2.0, sigma2=0.4)
    v = np.r_[np.geomspace(1e-3, 0.2, 25), -np.geomspace(1e-3, 0.2, 25)]
    res = fit_static_map(v, law.steady_state(v), model="exponential")
    units = dict(zip(res.names, res.units))
    assert units["delta_pos"] == units["delta_neg"] == "-"
    assert units["Fc_pos"] == "N" and units["vs_neg"] == "m/s"


def test_model_file_units_of_gms_and_tdmssc():
    gms = fk.GMS(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3), k=[1e4, 1e5], xi=[0.5, 0.5], C=20.0)
    u = parameter_units(gms)
    assert u["xi"] == "-" and u["static.delta"] == "-" and u["k"] == "N/m" and u["C"] == "N/s"
    t = parameter_units(fk.TDMSSC(Fc0=1.0, Fs0=1.2, vs=1e-3, Fc1=10.0, Fs1=10.0, eps=5.0),
                        {"F": "N·m", "x": "rad", "v": "rad/s"})
    assert (t["Fc0"], t["Fs0"], t["Fc1"], t["Fs1"], t["eps"], t["delta"]) == \
        ("N·m", "N·m", "N·m·s/rad", "N·m·s/rad", "N·m·s²/rad²", "-")


def test_fleet_plots_label_delta_dash():
    import pandas as pd

    from frictionkit.plotting.fleet import _unit

    df = pd.DataFrame({"unit_F": ["N"], "unit_v": ["m/s"]})
    assert (_unit(df, "delta_pos"), _unit(df, "Fc_neg"), _unit(df, "sigma2_pos")) == ("-", "N", "N·s/m")
