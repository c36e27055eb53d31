"""Issue 13, campaign round 4 (helper rob): what the fourth fuzzing round found, one test per
pattern. Round 3's leftovers first: a ball-screw plant or study with an implausible mass failed
every run with a message that missed the cause."""

from __future__ import annotations

import re

import pytest
from _robustness_helpers import STATIC_ARGS, one_error_line

import frictionkit.cli.identify  # noqa: F401  (registers the verbs)
from frictionkit.cli import app
from frictionkit.errors import DataError, ParameterError
from frictionkit.presets.ballscrew import MAX_INERTIA_SPAN, ballscrew_machine, check_plant
from frictionkit.reproduce.zhu_fujimoto import paper_plant
from frictionkit.study import StudySpec


@pytest.mark.parametrize("mass", [1e300, 1e-300, 1e20])
def test_ballscrew_machine_names_an_implausible_table_mass(mass):
    with pytest.raises(ParameterError, match=re.escape(f"M_t = {mass:.4g} kg is not a plausible inertia")):
        ballscrew_machine(paper_plant(M_t=mass))


def test_ballscrew_inertia_span_is_the_cores_bound():
    plant = paper_plant()
    # J_b = 1.0052e-3 kg·m² is the smallest inertia of the preset: just inside / outside the span
    check_plant(paper_plant(M_t=0.5 * MAX_INERTIA_SPAN * plant.J_b))
    with pytest.raises(ParameterError, match="J_b = 1e-20 kg·m²"):
        check_plant(paper_plant(J_b=1e-20))


@pytest.mark.parametrize("mass", [1e300, 1e-300])
def test_ballscrew_study_refuses_the_mass_up_front(mass):
    with pytest.raises(DataError, match=re.escape(f"[machine] mass = {mass!r}") + ".*kg is not a plausible inertia"):
        StudySpec(machine={"preset": "ballscrew", "mass": mass})


def test_ballscrew_study_checks_the_drawn_range():
    # the span ends at J_b x 1e12 = 1.0052e9 kg: 1e8 x 1.5 is inside, 6e8 x 1.9 = 1.14e9 outside
    StudySpec(machine={"preset": "ballscrew", "mass": 1e8}, spread={"mass": 0.5})
    with pytest.raises(DataError, match=r"drawn in \[.*\] with \[spread\] mass = 0.9"):
        StudySpec(machine={"preset": "ballscrew", "mass": 6e8}, spread={"mass": 0.9})


@pytest.mark.parametrize("option", ["--json", "--plot"])
def test_dash_for_a_file_only_output_is_refused_not_written_as_a_file(runner, staircase_csv, tmp_path, monkeypatch,
                                                                      option):
    """`identify ... --json -` wrote a file named '-' in the working folder (other verbs print the
    JSON to stdout for '-'); a verb without stdout output refuses it in one line."""
    monkeypatch.chdir(tmp_path)
    res = runner.invoke(app, ["identify", "static", str(staircase_csv), *STATIC_ARGS, option, "-"])
    assert res.exit_code != 0
    assert f"{option} -: this verb writes {option} to a file, not to stdout" in one_error_line(res)
    assert not (tmp_path / "-").exists()


@pytest.mark.parametrize("section, key, value", [("segmentation", "min_duration", "m"),
                                                 ("segmentation", "window", 2.5),
                                                 ("monitor", "min_periods", ""),
                                                 ("monitor", "alpha", "rad"),
                                                 ("fit", "f_scale", float("nan"))])
def test_fleet_config_numbers_are_checked_naming_the_key(section, key, value):
    """Were: every log failed with "TypeError: '>=' not supported ..." (exit 1), or
    "invalid literal for int() with base 10: ''" / "could not convert string to float: 'rad'"
    naming neither the key nor the file."""
    from frictionkit.fleet.config import config_from_dict

    doc = {"columns": {"time": "t", "velocity": "v", "force": "F"}, section: {key: value}}
    with pytest.raises(DataError, match=re.escape(f"[{section}] {key} = {value!r}: must be a finite")):
        config_from_dict(doc, source="f.toml")


def test_the_atomic_writer_never_replaces_a_device_or_pipe(runner, tmp_path):
    """Found as root: `frictionkit models --json /dev/full` renamed its temporary file over the
    device node (/dev/null the same). A FIFO stands in for the device here."""
    import os
    import stat

    from frictionkit._io import atomic_write_text

    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    with pytest.raises(OSError, match="not a regular file"):
        atomic_write_text(fifo, "x")
    import frictionkit.cli.models  # noqa: F401  (registers the verb)

    res = runner.invoke(app, ["models", "--json", str(fifo)])
    assert res.exit_code != 0
    assert "is not a regular file (a device, pipe or socket)" in one_error_line(res)
    assert stat.S_ISFIFO(os.stat(fifo).st_mode)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["pipe"]  # no temporary file left


@pytest.mark.parametrize("where", ["header", "row"])
def test_a_csv_row_of_millions_of_fields_is_refused_before_parsing(tmp_path, where):
    """A 60 MB CSV whose one data row had 30 million fields under a 3-name header grew to 13.5 GB
    in pandas (a 30-million-level row index) and ran for 9 minutes. 3 million fields here (6 MB)."""
    import tracemalloc

    import pandas  # noqa: F401  (imported before tracing: the loader imports it lazily)

    from frictionkit.data.loaders import MAX_CSV_COLUMNS, read_table

    path = tmp_path / "wide.csv"
    many = ",".join(["1"] * 3_000_000)
    path.write_text(f"{many}\n1,2,3\n" if where == "header" else f"t,v,F\n{many}\n")
    tracemalloc.start()
    with pytest.raises(DataError, match=f"{'the header' if where == 'header' else 'data row 1'} has more than "
                                        f"{MAX_CSV_COLUMNS:,} fields"):
        read_table(path)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert peak < 50e6  # the counting reads 64 kB chunks; the file itself is 6 MB


def test_a_complex_mat_column_is_refused_not_cast_to_its_real_part(tmp_path):
    """Was: exit 0 with numpy's 'Casting complex values to real discards the imaginary part'."""
    import numpy as np
    import scipy.io as sio

    from frictionkit.data import load_recording

    t = np.arange(50) * 1e-3
    sio.savemat(tmp_path / "c.mat", {"t": t, "v": t + 1j * t, "w": t + 0j, "F": t})
    with pytest.raises(DataError, match="column 'v' .* complex values with a non-zero imaginary part"):
        load_recording(tmp_path / "c.mat", time="t", velocity="v", force="F")
    rec = load_recording(tmp_path / "c.mat", time="t", velocity="w", force="F")  # imaginary part 0: fine
    assert np.array_equal(rec.v, t)


def test_simulate_machine_file_of_an_unstable_loop_exits_1_with_status_2(runner, tmp_path):
    """The EMPS axis at 5 kg under its nominal controller (issue 13: status 0 before)."""
    import json

    import numpy as np

    import frictionkit as fk
    import frictionkit.cli.simulate  # noqa: F401  (registers the verb)
    from frictionkit.presets.emps import emps_machine

    fk.save_model(emps_machine(M=5.0, friction=fk.CoulombViscous(Fc=20.0, sigma2=200.0)), tmp_path / "m.json")
    t = np.arange(1501) * 1e-3
    s = np.clip(t - 0.1, 0.0, 0.5) / 0.5
    np.savetxt(tmp_path / "qg.csv", np.column_stack([t, 0.05 * s * s * (3 - 2 * s)]), delimiter=",",
               header="t,qg", comments="")
    res = runner.invoke(app, ["simulate", str(tmp_path / "m.json"), "--input", f"qg={tmp_path / 'qg.csv'}:qg",
                              "--json", "-"])
    assert res.exit_code == 1
    doc = json.loads(res.stdout)
    assert doc["status"] == 2 and "the closed loop is unstable" in doc["message"]


def test_a_start_sigma0_that_cannot_simulate_is_named():
    """Issue 13: initial={'sigma0': 1e16 | 1e300} read 'sigma0 unidentifiable' — the fit had wandered
    to sigma0 ~ 1e-96 from a start the kernel stops (ringing far faster than the samples)."""
    import warnings

    import numpy as np

    import frictionkit as fk
    from frictionkit.identify import fit_output_error

    law = fk.LuGre(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, delta=2.0, sigma2=0.4), sigma0=1e5, sigma1=63.2)
    t = np.arange(3000) * 1e-3  # over 1.5 s the 1e16 start simulates (stopped at 1.16 s) and the fit succeeds
    u = 2 * np.sin(2 * np.pi * t)
    rec = fk.data.Recording(t=t, v=fk.simulate(law, plant=fk.Mass(1), force=u, dt=1e-3).v, F=u)
    for s0 in (1e16, 1e300):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            res = fit_output_error(rec, "lugre", static=law.static, inertia=1.0,
                                   initial={"sigma0": s0, "sigma1": 63.2})
        assert res.status != 0 and not res.success
        # either the start does not simulate, or (1e16: since this session's tighter-tolerance
        # start from rest it may) the fit climbs further and fails at the optimum — both must
        # name the stiff sigma0 on this mass and what to do, never 'unidentifiable'
        assert (f"the start values do not simulate (sigma0 = {s0:g} N/m on a mass of 1 kg" in res.message
                or ("the simulation fails at the optimum" in res.message
                    and "N/m on a mass of 1 kg" in res.message
                    and "sigma0 is too stiff for this mass and dt" in res.message)), res.message
        assert "unidentifiable" not in res.message
