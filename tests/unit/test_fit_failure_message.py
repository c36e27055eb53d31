"""fit_output_error names simulate's own message when the simulation fails at the optimum (issue 13:
with several records the message was lost — the records' results were joined without status)."""

import numpy as np
import pytest

import frictionkit as fk
from frictionkit.identify import FitOptions, fit_output_error

DT = 1e-3
LAW = fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, delta=2.0, sigma2=0.4)


@pytest.fixture(scope="module")
def records():
    true = fk.LuGre(LAW, sigma0=1e5, sigma1=63.2)
    out = []
    for amp, n in ((2.0, 600), (1.8, 500)):
        u = amp * np.sin(np.pi * np.arange(n) * DT * 2 + 0.2)
        sim = fk.simulate(true, plant=fk.Mass(1.0), force=u, dt=DT)
        out.append({"t": np.arange(n) * DT, "x": sim.x, "v": sim.v, "F": u})
    return out


@pytest.mark.parametrize("n_records", [1, 2])
def test_the_failing_simulations_message_is_in_the_result(records, n_records):
    # sigma0 1e12 N/m on 1 mg: ringing at omega dt = 1e6, which the integrator refuses to follow
    res = fit_output_error(records[:n_records], "lugre", static=LAW, inertia=1e-6,
                           initial={"sigma0": 1e12, "sigma1": 0.0}, free=["sigma1"],
                           fit=FitOptions(max_nfev=3, raise_on_failure=False))
    assert not res.success
    assert "the simulation fails at the optimum (" in res.message
    assert "sigma0 = 1e+12" in res.message  # simulate's own diagnosis, not only "fails"
    if n_records == 2:
        assert "record 1 of 2:" in res.message
