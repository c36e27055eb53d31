"""EMPS beyond the reference: closed-loop simulation and a per-direction Stribeck map.

Reference numbers (``shared/data/emps/README.md``, from EMPS_Description.pdf §3.5 and the
curator's RK4 cross-check): the published rigid-body model scores 0.229 % (velocity) and
5.85 % (force) in closed loop; IDIM-LS inverse errors 4.08 % (symmetric), 3.11 %
(asymmetric, 3.19 % with scipy's decimate).

Regression of the move onto the machine core (issue 8, part 6). ``BEFORE``: the errors of
the private numba loop this replaced (RK4, 10 sub-steps of 0.1 ms, ``sgn(0) = 0``, no stick
model), measured on this record just before its deletion. ``BEFORE_FINE``: the same loop at
1000 sub-steps (1 µs), its step-converged limit: the 10-sub-step values carried up to
0.006 percentage points of integration error (RK4 chattering across v = 0).
"""

from __future__ import annotations

import numpy as np
import pytest

from frictionkit import CoulombViscous, Directional, Stribeck
from frictionkit.data import load_recording
from frictionkit.identify.emps_dynamic import emps_closed_loop, emps_closed_loop_errors, emps_compare

# the module-scoped fixtures below are costly: keep this module on one xdist worker so they are
# built once (`make test` runs --dist loadgroup; see tests/conftest.py for pytest 9)
pytestmark = pytest.mark.xdist_group("emps_dynamic_runs")

GTAU = 35.15065188248547
MODELS = ("published", "asymmetric", "stribeck")
# (velocity %, force %) of the deleted private loop, 10 RK4 sub-steps (the shipped default)
BEFORE = {"published": (0.228814, 5.850316), "asymmetric": (0.228502, 5.219881),
          "stribeck": (0.210720, 4.674624)}
# the same loop at 1000 RK4 sub-steps
BEFORE_FINE = {"published": (0.229085, 5.855113), "asymmetric": (0.228815, 5.225766),
               "stribeck": (0.211112, 4.681003)}
# The Stribeck map is identified from the record, and since lowpass pads over the filter's settling
# time (its end transient, a -22 N residual at the last sample, no longer enters the fit) the refitted
# map's errors moved by this much: (velocity, force) percentage points, the machine core at 40 and at 80
# sub-steps alike (0.211116 / 4.681076 on abc898a, 0.211044 / 4.688036 after). Same loop, another map.
STRIBECK_REFIT = (-0.000072, 0.006960)
for _before in (BEFORE, BEFORE_FINE):
    _before["stribeck"] = tuple(b + d for b, d in zip(_before["stribeck"], STRIBECK_REFIT))


@pytest.fixture(scope="module")
def emps(shared_data):
    return load_recording(shared_data / "emps" / "DATA_EMPS.csv", time="t_s", position="qm_m", force="vir_V",
                          reference="qg_m", command="vir_V", scales={"force": GTAU})


@pytest.fixture(scope="module")
def compared(emps):
    return emps_compare(emps)


def test_published_model_reproduces_reference_errors(compared):
    pub = compared["published"]
    assert pub["velocity_error_percent"] == pytest.approx(0.229, abs=0.003)
    assert pub["force_error_percent"] == pytest.approx(5.85, abs=0.03)


def test_closed_loop_tracks_reference(emps):
    out = emps_closed_loop(emps.reference, M=95.1089, friction=CoulombViscous(Fc=20.3935, sigma2=203.5034),
                           offset=-3.1648)
    assert abs(out["nu"]).max() < 10.0  # the record stays within -4.33 ... +4.14 V, no saturation
    assert abs(out["q"] - emps.reference).max() < 2e-3  # 20 Hz loop: mm-level lag at 0.12 m/s


def test_stribeck_lowers_inverse_and_closed_loop_errors(compared):
    st, asym, pub = compared["stribeck"], compared["asymmetric"], compared["published"]
    assert st["inverse_error_percent"] < asym["inverse_error_percent"] < 3.3
    assert st["velocity_error_percent"] < pub["velocity_error_percent"]
    assert st["force_error_percent"] < pub["force_error_percent"]
    assert st["force_error_percent"] < asym["force_error_percent"]
    law = st["model"]
    assert isinstance(law.positive, Stribeck)
    assert 94.5 < st["M"] < 95.8  # within a few published standard errors of 95.15 kg


@pytest.fixture(scope="module")
def sweep(emps, compared):
    """Errors of each model at 10, 20, 40 and 80 core sub-steps per 1 ms sample."""
    pub = (95.1089, CoulombViscous(Fc=20.3935, sigma2=203.5034), -3.1648)
    asym = (95.1540, Directional(positive=CoulombViscous(Fc=20.1440, sigma2=166.7061),
                                 negative=CoulombViscous(Fc=20.6277, sigma2=240.4236)), 0.0)
    st = (compared["stribeck"]["M"], compared["stribeck"]["model"], 0.0)
    out = {}
    for name, (M, law, off) in zip(MODELS, (pub, asym, st)):
        for ns in (10, 20, 40, 80):
            e = emps_closed_loop_errors(emps, M=M, friction=law, offset=off, substeps=ns)
            out[name, ns] = (e["velocity_error_percent"], e["force_error_percent"])
    return out


@pytest.mark.parametrize("name", MODELS)
def test_errors_converged_in_substeps(sweep, name):
    """The two finest sub-steps (40, 80) agree within 0.003 percentage points."""
    for i, what in enumerate(("velocity", "force")):
        assert abs(sweep[name, 80][i] - sweep[name, 40][i]) < 0.003, (name, what, sweep)


@pytest.mark.parametrize("name", MODELS)
def test_errors_within_0p01_of_before(compared, sweep, name):
    """Within 0.01 pp of the deleted loop's shipped numbers, at the default and at 80 sub-steps."""
    for i, key in enumerate(("velocity_error_percent", "force_error_percent")):
        assert abs(compared[name][key] - BEFORE[name][i]) < 0.01, (name, key, compared[name][key])
        assert abs(sweep[name, 80][i] - BEFORE[name][i]) < 0.01, (name, key, sweep[name, 80])


@pytest.mark.parametrize("name", MODELS)
def test_core_agrees_with_fine_step_old_loop(sweep, name):
    """Exact stick (core) and RK4 chatter across v = 0 (old loop, 1 µs) reach the same limit."""
    for i in range(2):
        assert abs(sweep[name, 80][i] - BEFORE_FINE[name][i]) < 0.002, (name, i, sweep[name, 80])


def test_closed_loop_force_is_delayed_controller_output(emps):
    out = emps_closed_loop(emps.reference[:3000], M=95.1089,
                           friction=CoulombViscous(Fc=20.3935, sigma2=203.5034), offset=-3.1648)
    assert out["tau"][0] == 0.0
    assert np.array_equal(out["tau"][1:], GTAU * out["nu"][:-1])
