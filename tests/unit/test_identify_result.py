"""IdentificationResult: statistics helper, JSON round trip with units and provenance, plots."""

from __future__ import annotations

import json

import matplotlib

matplotlib.use("Agg")

import numpy as np
import pytest

from frictionkit import Directional, Stribeck
from frictionkit.data import Recording
from frictionkit.errors import DataError
from frictionkit.identify import IdentificationResult, fit_rigid_body, fit_static_map, parameter_statistics


def _static_result():
    law = Directional(positive=Stribeck(Fc=1.0, Fs=1.5, vs=0.02, sigma2=3.0),
                      negative=Stribeck(Fc=1.2, Fs=1.4, vs=0.03, sigma2=2.0))
    v = np.r_[np.geomspace(0.003, 0.3, 15), -np.geomspace(0.003, 0.3, 15)]
    F = law.steady_state(v) + 1e-3 * np.random.default_rng(0).standard_normal(v.size)
    return fit_static_map(v, F, model="exponential", delta=2.0, units={"v": "rad/s", "F": "N·m"})


def test_parameter_statistics_closed_form():
    cov = np.array([[4.0, 1.0], [1.0, 1.0]])
    s = parameter_statistics([10.0, 5.0], cov, dof=1000)
    assert s["stderr"].tolist() == [2.0, 1.0]
    assert s["correlation"][0, 1] == pytest.approx(0.5)
    assert s["ci"][0].tolist() == pytest.approx([10 - 1.9623 * 2, 10 + 1.9623 * 2], rel=1e-4)


def test_static_json_round_trip(tmp_path):
    res = _static_result()
    p = res.save_json(tmp_path / "fit.json")
    raw = json.loads(p.read_text(encoding="utf-8"))
    assert raw["parameters"]["vs_pos"]["unit"] == "rad/s"
    assert raw["parameters"]["sigma2_neg"]["unit"] == "N·m·s/rad"
    assert raw["model"]["type"] == "Directional"
    back = IdentificationResult.load_json(p)
    assert back.names == res.names and back.units == res.units
    assert np.array_equal(back.values, res.values)
    assert np.array_equal(back.stderr, res.stderr)
    assert np.array_equal(back.ci95, res.ci95)
    assert np.allclose(back.correlation, res.correlation)
    assert back.model == res.model
    assert back.parts["negative"].model == res.parts["negative"].model
    assert dict(back.provenance) == json.loads(json.dumps(dict(res.provenance)))
    assert np.array_equal(back.data["F"], res.data["F"])
    assert back.rms == res.rms


def test_rigid_body_json_keeps_provenance(tmp_path):
    t = np.arange(3000) * 1e-3
    x = 0.05 * np.sin(2 * np.pi * 0.5 * t)
    v = 0.05 * np.pi * np.cos(2 * np.pi * 0.5 * t)
    rec = Recording(t=t, x=x, F=10 * v + 2 * np.sign(v), provenance={"file": "sim.csv", "note": "unit test"})
    res = fit_rigid_body(rec, q=5)
    back = IdentificationResult.load_json(res.save_json(tmp_path / "rb.json", include_data=False))
    assert back.provenance["file"] == "sim.csv" and back.provenance["note"] == "unit test"
    assert back.provenance["procedure"]["decimation"] == 5
    assert back.model == res.model
    assert back.parameter("Fv")["unit"] == "N·s/m"
    assert not back.data


def test_load_rejects_foreign_json(tmp_path):
    p = tmp_path / "x.json"
    p.write_text('{"hello": 1}')
    with pytest.raises(DataError, match=r"not a frictionkit identification result"):
        IdentificationResult.load_json(p)


def test_plot_returns_axes_with_data_and_curve():
    import matplotlib.pyplot as plt

    res = _static_result()
    fig, ax = plt.subplots()
    out = res.plot(ax=ax)
    assert out is ax
    assert len(ax.lines) >= 2  # fitted curve per direction (points may be an errorbar container)
    plt.close(fig)
    ax2 = res.plot()
    assert ax2.get_xlabel() == "velocity [rad/s]"
    plt.close(ax2.figure)


def test_unknown_parameter_name():
    res = _static_result()
    with pytest.raises(KeyError, match=r"'Fx': not a parameter"):
        res["Fx"]
    assert "Fc_pos" in res.summary()
