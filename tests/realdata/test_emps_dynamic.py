"""EMPS beyond the reference: closed-loop simulation and a per-direction Stribeck map.

Reference numbers (``shared/data/emps/README.md``, from EMPS_Description.pdf §3.5 and the
curator's RK4 cross-check): the published rigid-body model scores 0.229 % (velocity) and
5.85 % (force) in closed loop; IDIM-LS inverse errors 4.08 % (symmetric), 3.11 %
(asymmetric, 3.19 % with scipy's decimate).
"""

from __future__ import annotations

import pytest

from frictionkit import CoulombViscous, Stribeck
from frictionkit.data import load_recording
from frictionkit.identify.emps_dynamic import emps_closed_loop, emps_compare

GTAU = 35.15065188248547


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
