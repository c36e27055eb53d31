"""TRO2021 screw drives (Mablekos-Alexiou et al. 2021): per-record averaging and static maps.

Targets from ``shared/data/tro2021_screw_drives/README.md`` ("How to check ...").
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from frictionkit.data import load_groups, steady_state_points
from frictionkit.identify import fit_static_map
from frictionkit.units import RPM

# the module-scoped fixtures below are costly: keep this module on one xdist worker so they are
# built once (`make test` runs --dist loadgroup; see tests/conftest.py for pytest 9)
pytestmark = pytest.mark.xdist_group("screw_drives_fits")


def _records(shared_data, drive):
    return load_groups(shared_data / "tro2021_screw_drives" / "steady_state_records.csv",
                       group="source_file", where={"drive_id": drive}, time="t_s",
                       velocity="motor_velocity_rad_per_s", force="motor_torque_N_m",
                       units={"v": "rad/s", "F": "N·m"})


@pytest.fixture(scope="module")
def points(shared_data):
    return {d: steady_state_points(_records(shared_data, d)) for d in (1, 2, 3)}


@pytest.fixture(scope="module")
def fits(points):
    return {d: fit_static_map(p) for d, p in points.items()}


@pytest.mark.parametrize("drive", [1, 2, 3])
def test_whole_record_means_reproduce_the_map(shared_data, points, drive):
    ref = pd.read_csv(shared_data / "tro2021_screw_drives" / "steady_state_map.csv")
    ref = ref[ref.drive_id == drive].set_index("source_file")
    pts = points[drive]
    assert sorted(pts.labels) == sorted(ref.index)
    ref = ref.loc[list(pts.labels)]
    assert (pts.n == ref.n_samples.to_numpy()).all()
    # the map is written with 10 significant digits
    np.testing.assert_allclose(pts.v, ref.mean_motor_velocity_rad_per_s, rtol=1e-8)
    np.testing.assert_allclose(pts.F, ref.mean_motor_torque_N_m, rtol=1e-8)
    np.testing.assert_allclose(pts.v_std, ref.std_motor_velocity_rad_per_s, rtol=1e-8)
    np.testing.assert_allclose(pts.F_std, ref.std_motor_torque_N_m, rtol=1e-8)


@pytest.mark.parametrize("drive", [1, 2, 3])
def test_per_direction_fits_have_intervals_and_small_residuals(points, fits, drive):
    res = fits[drive]
    assert set(res.parts) == {"positive", "negative"}
    for label, part in res.parts.items():
        sel = np.sign(points[drive].v) == (1 if label == "positive" else -1)
        assert np.isfinite(part.stderr).all() and (part.stderr > 0).all()
        assert ((part.ci95[:, 0] < part.values) & (part.values < part.ci95[:, 1])).all()
        assert part.units[0] == "N·m"
        # RMS residual small compared with the within-record torque std
        assert part.rms < 0.3 * np.median(points[drive].F_std[sel]), (label, part.rms)
        # Coulomb level inside the measured range of that direction
        assert np.min(np.abs(part.data["F"])) * 0.5 < part.values[0] < np.max(np.abs(part.data["F"]))


def test_drive1_direction_asymmetry_at_100_rpm(fits):
    pos, neg = fits[1].model.steady_state(np.array([100.0, -100.0]) * RPM)
    # README: drive 1 at +-100 rpm: +2.66 / -3.40 mN·m
    assert pos == pytest.approx(2.66e-3, abs=0.08e-3)
    assert neg == pytest.approx(-3.40e-3, abs=0.08e-3)
    assert abs(neg) - abs(pos) > 0.5e-3


def test_drive3_rise_of_torque_at_low_negative_speed(fits):
    f1, f10 = fits[3].model.steady_state(np.array([-1.0, -10.0]) * RPM)
    # README: -2.26 mN·m at -1 rpm, -1.83 mN·m at -10 rpm
    assert f1 == pytest.approx(-2.26e-3, abs=0.1e-3)
    assert f10 == pytest.approx(-1.83e-3, abs=0.1e-3)
    assert abs(f1) - abs(f10) > 0.3e-3
    neg = fits[3].parts["negative"]
    assert neg.model_name in ("exponential", "lorentzian")
    assert neg["Fs"] > neg["Fc"]
