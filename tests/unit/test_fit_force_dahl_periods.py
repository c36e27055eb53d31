"""Force-driven output error: Dahl is a first-class model, records may have different sample periods (issue 11).

Truths are the simulated plants' own parameters (set here, not read from the code under test).
"""

from __future__ import annotations

import numpy as np
import pytest
from typer.testing import CliRunner

import frictionkit as fk
import frictionkit.cli.identify  # noqa: F401  (registers the ``identify`` group)
from frictionkit.cli import app
from frictionkit.errors import ParameterError
from frictionkit.identify.output_error import OUTPUT_ERROR_OPTIONS, fit_output_error

TRUE = fk.Dahl(Fc=1.0, sigma0=5e4, sigma2=0.4)   # omega dt = sqrt(5e4) 1e-3 = 0.22: resolved by both periods
MAP = fk.CoulombViscous(Fc=1.0, sigma2=0.4)


def _record(dt: float, n: int, amp: float, law=TRUE) -> dict:
    t = np.arange(n) * dt
    u = amp * np.sin(np.pi * t)
    return {"t": t, "F": u, "v": fk.simulate(law, plant=fk.Mass(1.0), force=u, dt=dt).v}


@pytest.fixture(scope="module")
def records():
    """1 ms and 0.5 ms records of the same 1 kg Dahl slider (different amplitudes)."""
    return [_record(1e-3, 3001, 2.0), _record(5e-4, 5001, 1.6)]


@pytest.mark.parametrize("jacobian", ["auto", "fd"])
def test_dahl_from_auto_start_over_records_of_different_periods(records, jacobian):
    res = fit_output_error(records, "dahl", static=MAP, inertia=1.0, rests=None, jacobian=jacobian)
    assert res.success and res.names == ("sigma0",) and isinstance(res.model, fk.Dahl)
    assert res["sigma0"] == pytest.approx(5e4, rel=1e-4)
    lo, hi = res.ci95[0]
    assert lo < 5e4 * (1 + 1e-4) and hi > 5e4 * (1 - 1e-4)
    assert res.diagnostics["initial"]["branches"] >= 2  # sigma0 started from the sub-breakaway slope
    assert res.diagnostics["sensitivity_runs"] > 0 if jacobian == "auto" else res.diagnostics["sensitivity_runs"] == 0
    assert [s["dt"] for s in res.diagnostics["segments"].values()] == pytest.approx([1e-3, 5e-4])


def test_each_record_is_simulated_at_its_own_period(records):
    res = fit_output_error(records, "dahl", static=MAP, inertia=1.0, rests=None, initial={"sigma0": 4e4})
    n0 = records[0]["t"].size
    for rec, part, dt in ((records[0], slice(1, n0), 1e-3), (records[1], slice(n0 + 1, None), 5e-4)):
        own = fk.simulate(res.model, plant=fk.Mass(1.0), force=rec["F"], dt=dt, options=OUTPUT_ERROR_OPTIONS).v
        np.testing.assert_allclose(res.data["y_pred"][part], own[1:], rtol=0, atol=1e-12)
    # the time axis puts the second record one of its own samples after the first
    assert res.data["t"][n0] - res.data["t"][n0 - 1] == pytest.approx(5e-4)


def test_dahl_levels_per_direction_and_refused_fields(records):
    st = fk.Directional(positive=fk.CoulombViscous(Fc=0.9, sigma2=0.4), negative=fk.CoulombViscous(Fc=1.1, sigma2=0.4))
    res = fit_output_error(records, "dahl", static=st, inertia=1.0, rests=None, free=("sigma0", "Fc_pos", "Fc_neg"))
    assert res.success and isinstance(res.model, fk.Directional)
    np.testing.assert_allclose([res["sigma0"], res["Fc_pos"], res["Fc_neg"]], [5e4, 1.0, 1.0], rtol=1e-4)
    with pytest.raises(ParameterError, match="Dahl has no 'vs'"):
        fit_output_error(records, "dahl", static=MAP, inertia=1.0, rests=None, free=("sigma0", "vs"))
    with pytest.raises(ParameterError, match="must share sigma0"):
        fit_output_error(records, fk.Directional(positive=fk.Dahl(Fc=1, sigma0=1e4), negative=fk.Dahl(Fc=1, sigma0=2e4)),
                         inertia=1.0, rests=None)


def test_dahl_map_levels_free_exact_and_difference_jacobians_agree(records):
    """From a poor start the first trust-region step lands at sigma0 ~ 7e7 N/m (omega dt 4.3-8.6,
    ringing faster than the samples): the exact fit stopped there (sigma0 = 7.4e7; its sensitivities
    grew to 1e79 while the state stayed bounded) until such points were left to plain simulations."""
    start = fk.Dahl(Fc=0.8, sigma0=2e4, sigma2=0.3)
    fits = [fit_output_error(records, start, inertia=1.0, rests=None, free=("sigma0", "Fc", "sigma2"), jacobian=j)
            for j in ("auto", "fd")]
    for res in fits:
        assert res.success
        np.testing.assert_allclose([res["sigma0"], res["Fc"], res["sigma2"]], [5e4, 1.0, 0.4], rtol=1e-4)
    assert fits[0].diagnostics["sensitivity_runs"] > 0 and fits[1].diagnostics["sensitivity_runs"] == 0


def test_exact_jacobian_leaves_a_contact_faster_than_the_samples_to_simulate():
    from frictionkit.identify import _jacobian
    from frictionkit.simulation.core import FAST_LIMIT

    u = 0.5 * np.ones(50)
    for s0, dt in ((7.4e7, 5e-4), (5e4, 1e-3)):  # omega dt = 4.3 and 0.22 on 1 kg
        law = fk.Dahl(Fc=0.9, sigma0=s0, sigma2=1.3)
        *_, status = _jacobian.force_driven(lambda th: (fk.Dahl(Fc=0.9, sigma0=th[0], sigma2=1.3), 1.0, 0.0),
                                            np.array([s0]), u, dt, OUTPUT_ERROR_OPTIONS, [(0, u.size)])
        fast = np.sqrt(law.sigma0 / 1.0) * dt > FAST_LIMIT
        assert status == (_jacobian.UNRESOLVED if fast else 0)


def test_cli_force_drive_dahl(tmp_path, records):
    import pandas as pd

    rec = records[0]
    path = tmp_path / "d.csv"
    pd.DataFrame({"t": rec["t"], "F": rec["F"], "v": rec["v"]}).to_csv(path, index=False)
    base = ["identify", "output-error", str(path), "--time", "t", "--velocity", "v", "--force", "F",
            "--drive", "force", "--mass", "1", "--model", "dahl", "--Fc", "1", "--sigma2", "0.4", "--rests", "none"]
    res = CliRunner().invoke(app, [*base, "--json", str(tmp_path / "D.json")])
    assert res.exit_code == 0, res.output
    assert "initial guess: sigma0" in res.stdout and "sigma1" not in res.stdout.split("\n")[0]
    law = fk.identify.IdentificationResult.load_json(tmp_path / "D.json").model
    assert isinstance(law, fk.Dahl) and law.sigma0 == pytest.approx(5e4, rel=1e-3)
    bad = CliRunner().invoke(app, [*base, "--sigma1", "3"])
    assert bad.exit_code == 2 and bad.output.strip().splitlines()[-1] == \
        "error: --sigma1 applies to --model lugre only (Dahl has no bristle damping)"
