"""Issue 13, round 9's leftovers and campaign round 10 (helper r10): one test per pattern fixed, each built
from the case that exposed it."""

from __future__ import annotations

import numpy as np
import pytest

from _robustness_helpers import LAW, one_error_line

import frictionkit as fk
import frictionkit.cli.export  # noqa: F401  (registers the verbs)
import frictionkit.cli.simulate  # noqa: F401
from frictionkit.errors import DataError, ParameterError


def test_the_breakpoint_search_scores_a_breakpoints_candidates_at_once(monkeypatch):
    """Was (round 9 leftover): `identify presliding --elements 32` took 9 min under load — the sweep solved one
    least-squares problem per candidate (80 per breakpoint and sweep: 79·M solves at least) and the Nelder-Mead
    polish ran to 400·M iterations. Now one projection scores a breakpoint's candidates (one exact solve per
    breakpoint and sweep) and the polish has an evaluation budget; the fit still finds the true breakpoints."""
    import frictionkit.identify.presliding as ps

    def curve(breaks, slopes, u):  # an independent construction: the slopes between the breakpoints
        return slopes[0] * u - sum((slopes[i] - slopes[i + 1]) * np.maximum(u - b, 0.0) for i, b in enumerate(breaks))

    class Stop(Exception):
        pass

    seen = {}
    solves = []
    real_sse, real_minimize = ps._pl_sse, ps.minimize

    def polish(*a, **k):
        seen.update(sweep_solves=len(solves), options=k["options"])
        raise Stop

    monkeypatch.setattr(ps, "_pl_sse", lambda *a: solves.append(1) or real_sse(*a))
    monkeypatch.setattr(ps, "minimize", polish)
    u = np.linspace(0.0, 5e-5, 401)
    with pytest.raises(Stop):
        ps.piecewise_linear_fit(u, curve(np.geomspace(2e-6, 3e-5, 12), np.geomspace(5e5, 1e3, 13), u), 12)
    assert seen["sweep_solves"] <= 6 * 12 + 1  # 6 sweeps at most; was 79 per breakpoint and sweep
    assert seen["options"]["maxfev"] == ps._PL_POLISH_MAXFEV
    monkeypatch.setattr(ps, "minimize", real_minimize)
    breaks, slopes = np.array([3e-6, 1e-5, 2.5e-5]), np.array([4e5, 1e5, 2e4, 1e3])
    fit = ps.piecewise_linear_fit(u, curve(breaks, slopes, u), 3)
    assert np.allclose(fit["breaks"], breaks, rtol=1e-3) and np.allclose(fit["slopes"], slopes, rtol=1e-3)


def test_a_bad_free_name_is_refused_before_the_start_search(monkeypatch):
    """Was (round 9 leftover): `--free bogus` was checked only after the start search (minutes on a long
    record). Now the names are checked against the kind's parameters first: the start search never runs."""
    import frictionkit.identify.start_values as sv
    from frictionkit.identify import fit_motion_error

    def no_search(*a, **k):
        raise AssertionError("the start search ran before the names were checked")

    monkeypatch.setattr(sv, "motion_error_start", no_search)
    t = np.arange(2001) * 1e-4
    data = {"t": t, "x": 20e-6 * np.sin(2 * np.pi * 5 * t), "F": np.sin(2 * np.pi * 5 * t)}
    with pytest.raises(ParameterError, match=r"^unknown parameter 'bogus' for LuGre; known: \['Fc'"):
        fit_motion_error(data, "lugre", static=LAW, free=["sigma0", "bogus"])
    with pytest.raises(ParameterError, match=r"^unknown parameter 'sigma0' for GMS; known: \['C'"):
        fit_motion_error(data, "gms", static=LAW, free=["sigma0"], elements=2)
    with pytest.raises(ParameterError, match=r"names a parameter twice$"):
        fit_motion_error(data, "dahl", static=LAW, free=["sigma0", "sigma0"])
    with pytest.raises(ParameterError, match=r"^fit_motion_error: free = 5: must be a sequence of parameter names$"):
        fit_motion_error(data, "lugre", static=LAW, free=5)


@pytest.mark.parametrize("verb", ["static", "export", "simulate"])
def test_a_result_path_ending_in_a_slash_is_refused_not_written_as_a_file(runner, tmp_path, staircase_csv,
                                                                          static_json, verb):
    """Was (round 9 leftover): `--json DIR/sub/` wrote a file named 'sub' (a Path option drops the slash).
    Now the text as typed is checked: a name ending in '/' names a folder, and the verb refuses it."""
    from frictionkit.cli import app

    target = f"{tmp_path}/sub/"
    argv = {"static": ["identify", "static", str(staircase_csv), "--time", "t_s", "--velocity", "v_ms", "--force",
                       "F_N", "--model", "coulomb_viscous", "--json", target],
            "export": ["export", str(static_json), "--format", "c", "--out", target],
            "simulate": ["simulate", str(static_json), "--position", str(staircase_csv), "--json", target]}[verb]
    option = "--out" if verb == "export" else "--json"
    res = runner.invoke(app, argv)
    assert res.exit_code == 2
    assert one_error_line(res) == f"error: {option} '{target}' ends in '/', the name of a folder; give a file name"
    assert not (tmp_path / "sub").exists()


def test_a_constant_machine_input_follows_the_rule_of_an_input_file(runner, tmp_path):
    """Was (round 9 leftover): `simulate MACHINE --input u=1e200` ran (status 0) while the same value in an
    input file is refused as a unit slip. Now every number option has that bound (cli._common._finite), naming
    the option."""
    from frictionkit.cli import app
    from frictionkit.presets.emps import PUBLISHED, emps_machine

    m = emps_machine(M=PUBLISHED["M"], friction=fk.CoulombViscous(Fc=PUBLISHED["Fc"], sigma2=PUBLISHED["Fv"]),
                     offset=PUBLISHED["offset"])
    path = fk.save_model(m, tmp_path / "emps.json") or tmp_path / "emps.json"
    res = runner.invoke(app, ["simulate", str(path), "--input", "qg=1e200", "--dt", "1e-3", "--duration", "0.01"])
    assert res.exit_code == 2
    assert one_error_line(res) == "error: --input qg 1e+200: beyond 1e+150, a unit slip (its square overflows)"
    ref = tmp_path / "ref.csv"
    ref.write_text("t,qg\n0,0\n0.001,1e200\n0.002,0\n")
    res = runner.invoke(app, ["simulate", str(path), "--input", f"qg={ref}:qg"])
    assert res.exit_code == 2 and "beyond 1e+150" in one_error_line(res)
    res = runner.invoke(app, ["simulate", str(path), "--input", "qg=1e-3", "--dt", "1e-3", "--duration", "0.01"])
    assert res.exit_code == 0, res.output


@pytest.mark.parametrize("extra,want", [
    (["--Fc", "1", "--Fs", "1e308"], "error: --Fs 1e+308: beyond 1e+150, a unit slip (its square overflows)"),
    (["--Fc", "-1"], "error: --Fc -1.0: must be >= 0"),
    (["--Fc", "1", "--vs", "0"], "error: --vs 0.0: must be > 0"),
    (["--Fs", "1.5", "--vs", "1e-3"], "error: --Fs, --vs without --Fc: the static map needs its Coulomb level --Fc "
                                      "(or give --static-json)"),
])
def test_the_static_map_options_are_named_at_the_boundary(runner, gms_csv, extra, want):
    """Was (campaign round 10): `identify presliding --Fs 1e308` failed as "GMS.C = inf", `--Fc -1` as
    "Stribeck.Fc = -1.0" (not the option), and --Fs/--vs without --Fc were dropped without a word."""
    from frictionkit.cli import app

    res = runner.invoke(app, ["identify", "presliding", str(gms_csv), "--time", "t_s", "--position", "x_m",
                              "--force", "F_N", "--elements", "2", *extra])
    assert res.exit_code == 2
    assert one_error_line(res) == want


@pytest.mark.parametrize("value,want", [("1e308", "beyond 1e+150, a unit slip (its square overflows)"),
                                        ("1e-320", "below 1e-150, a unit slip (its reciprocal overflows)")])
def test_a_number_option_beyond_any_physical_size_is_refused(runner, tmp_path, value, want):
    """Was (campaign round 10): `simulate LUGRE --force F.csv --mass 1e308` ended in "unexpected
    ZeroDivisionError ... a bug"; `--mass 1e-320` (a subnormal) ran 83 s into a non-finite state."""
    from frictionkit.cli import app

    model = tmp_path / "lugre.json"
    fk.save_model(fk.LuGre(LAW, sigma0=1e5, sigma1=30.0), model)
    force = tmp_path / "u.csv"
    force.write_text("t,u\n" + "".join(f"{1e-3 * i},{np.sin(i / 50):.6f}\n" for i in range(200)))
    res = runner.invoke(app, ["simulate", str(model), "--force", str(force), "--mass", value])
    assert res.exit_code == 2
    assert one_error_line(res) == f"error: --mass {float(value)!r}: {want}"


def test_complex_or_text_arrays_are_refused_naming_the_argument():
    """Was (campaign round 10): `fk.simulate(law, position=x + 1j)` ran on the real part (a ComplexWarning
    only); `fit_static_map(["a"], ["b"])` raised numpy's "could not convert string to float"."""
    from frictionkit.identify import fit_static_map

    lugre = fk.LuGre(LAW, sigma0=1e5, sigma1=30.0)
    x = 20e-6 * np.sin(np.linspace(0, 6, 200))
    with pytest.raises(DataError, match=r"^position: holds complex numbers; a signal must be real numbers$"):
        fk.simulate(lugre, position=x + 1j, dt=1e-3)
    with pytest.raises(DataError, match=r"^fit_static_map: v: cannot be read as an array of numbers$"):
        fit_static_map(["a"], ["b"])
    with pytest.raises(ParameterError, match=r"entries must be real numbers, not complex numbers$"):
        fk.GMS(LAW, k=np.array([1e4 + 1j]), xi=[1.0], C=1.0)


def test_the_piecewise_linear_fit_names_its_bad_arguments():
    """Was (campaign round 10): a NaN abscissa raised LinAlgError ("SVD did not converge"), u and f of different
    lengths a broadcast ValueError, and n_breaks = 2.7 ran as 2."""
    from frictionkit.identify import piecewise_linear_fit

    u = np.linspace(0, 1, 50)
    with pytest.raises(DataError, match=r"^piecewise_linear_fit: u\[50\] = nan: samples must be finite"):
        piecewise_linear_fit(np.r_[u, np.nan], np.r_[u, 1.0], 2)
    with pytest.raises(DataError, match=r"^piecewise_linear_fit: u has 50 samples, f has 40: one force per abscissa$"):
        piecewise_linear_fit(u, u[:40], 2)
    with pytest.raises(ParameterError, match=r"^piecewise_linear_fit: n_breaks = 2.7: must be an integer >= 1$"):
        piecewise_linear_fit(u, u, 2.7)
    with pytest.raises(ParameterError, match=r"^piecewise_linear_fit: grid = 1: must be an integer >= 2"):
        piecewise_linear_fit(u, u, 2, grid=1)


def test_a_result_written_over_a_folder_is_named_a_folder(tmp_path):
    """Was (campaign round 10): `fk.save_model(law, FOLDER)` failed with "not a regular file (a device, pipe or
    socket)"."""
    (tmp_path / "out").mkdir()
    with pytest.raises(IsADirectoryError, match=r"it is a folder; give a file name"):
        fk.save_model(LAW, tmp_path / "out")
    assert (tmp_path / "out").is_dir() and not any((tmp_path / "out").iterdir())


def test_an_output_folder_that_is_a_dangling_link_is_named_as_such(tmp_path):
    """Was (campaign round 10): `report FIT -o LINK` with LINK a link to a missing folder failed late with
    "'LINK': File exists"."""
    from frictionkit._io import check_output_dir

    link = tmp_path / "rep"
    link.symlink_to(tmp_path / "gone")
    with pytest.raises(DataError, match=rf"^-o '{link}' is a link to '{tmp_path}/gone', which does not exist; "
                                        r"create that folder or give another$"):
        check_output_dir(link, option="-o")
    (tmp_path / "gone").mkdir()
    assert check_output_dir(link, option="-o") == link  # a live link to a folder is a folder


@pytest.mark.parametrize("extra,want", [
    (["--model", "{d}"], "error: --model '{d}' is a folder; give a data file"),
    (["--compensator", "none", "--compensator", "none"], "error: --compensator none given twice; each compensator "
                                                         "runs once"),
])
def test_compensate_names_a_folder_and_a_repeated_compensator(runner, tmp_path, extra, want):
    """Was (campaign round 10): `compensate emps --model FOLDER` said "no such file"; `--compensator none
    --compensator none` ran it twice into a table of two equal rows (a study refuses the same list)."""
    import frictionkit.cli.compensate  # noqa: F401  (registers the verb)
    from frictionkit.cli import app

    res = runner.invoke(app, ["compensate", "emps", "--quick", *[a.format(d=tmp_path) for a in extra]])
    assert res.exit_code == 2
    assert one_error_line(res) == want.format(d=tmp_path)


def test_a_usage_error_before_the_verb_is_one_line(runner):
    """Was (campaign round 10): `frictionkit --bogus` printed click's usage block and 'Error: No such option'
    (three lines, capitalised) while every verb's usage error is one 'error:' line."""
    from frictionkit.cli import app

    res = runner.invoke(app, ["--bogus"])
    assert res.exit_code == 2
    assert one_error_line(res) == "error: No such option: --bogus (see 'frictionkit --help')"
    assert runner.invoke(app, ["--version"]).exit_code == 0


@pytest.mark.parametrize("argv,want", [
    (["reversal", "--position", "x_m", "--min-travel", "1e-320"],
     "error: --min-travel 1e-320: below 1e-150, a unit slip (its reciprocal overflows)"),
    (["rigid-body", "--position", "x_m", "--cutoff", "1e308"],
     "error: --cutoff 1e+308: beyond 1e+150, a unit slip (its square overflows)"),
    (["presliding", "--position", "x_m", "--elements", "2", "--Fc", "1", "--C", "1e-320"],
     "error: --C 1e-320: below 1e-150, a unit slip (its reciprocal overflows)"),
])
def test_an_identify_option_of_no_physical_size_is_named(runner, gms_csv, argv, want):
    """Was (campaign round 10): `identify reversal --min-travel 1e-320` failed as "window = None; need at
    least 3 after and 1 before" (a reversal at every sample); `--cutoff 1e308` was named 'lowpass.cutoff';
    `identify presliding --C 1e-320` (a time constant beyond any record) fitted with exit status 0."""
    from frictionkit.cli import app

    res = runner.invoke(app, ["identify", argv[0], str(gms_csv), "--time", "t_s", "--force", "F_N", *argv[1:]])
    assert res.exit_code == 2
    assert one_error_line(res) == want


@pytest.mark.parametrize("argv,want", [
    (["export", "{model}", "--format", "csv", "--out", "{d}/t.csv", "--v-max", "1e308"],
     "error: --v-max 1e+308: must be in 1e-12 ... 1e+12 ([m/s or rad/s]; outside it the grid's steps lose "
     "precision or the map overflows)"),
    (["identify", "static", "{csv}", "--time", "t_s", "--velocity", "v_ms", "--force", "F_N", "--model", "exponential",
      "--delta", "1000"],
     "error: --delta 1000.0: must be in 0 ... 50 (a fixed Stribeck exponent; above the top (|v|/vs)**delta "
     "overflows within the fit's vs range)"),
])
def test_a_library_bound_on_an_option_is_reported_with_the_option(runner, tmp_path, staircase_csv, static_json,
                                                                   argv, want):
    """Was (campaign round 10): `export --v-max 1e308` failed as "export: v_max = 1e+308 ...", `identify static
    --delta 1000` as "fit_static_map.delta = 1000.0 ..." — the library's names, not the options typed."""
    from frictionkit.cli import app

    res = runner.invoke(app, [a.format(model=static_json, d=tmp_path, csv=staircase_csv) for a in argv])
    assert res.exit_code == 2
    assert one_error_line(res) == want


def test_ctrl_c_while_the_command_line_is_parsed_is_one_line(runner, monkeypatch):
    """Was (campaign round 10): Ctrl-C 2.3-2.4 s into `frictionkit identify static ...` (typer importing
    pydantic to convert the options) exited 130 without a word in 2 of 10 tries: typer turns an interrupt
    during parsing into a silent exit 130. Now it prints 'error: interrupted' as everywhere else."""
    from typer.core import TyperGroup

    from frictionkit.cli import app

    def interrupted(self, ctx, args):
        raise KeyboardInterrupt

    monkeypatch.setattr(TyperGroup, "parse_args", interrupted)
    res = runner.invoke(app, ["models"])
    assert res.exit_code == 130
    assert one_error_line(res) == "error: interrupted"


# --------------------------------------------------------------------------- lead, after round 10
def test_a_machine_input_nothing_reads_is_refused():
    """Was: simulate_machine(inputs={"zz": ...}) ran as if the input were not given (a misspelt reference or
    command went unnoticed)."""
    m = fk.Machine("slider")
    x = m.dof("x", inertia=1.0)
    m.friction("contact", x, law=fk.CoulombViscous(Fc=1.0))
    m.actuator("u", x)
    good = fk.simulate_machine(m, dt=1e-3, inputs={"u": np.full(11, 0.5)})
    assert good.status == 0
    with pytest.raises(DataError, match=r"\['zz'\] are read by nothing.*it reads \['u'\]"):
        fk.simulate_machine(m, dt=1e-3, inputs={"u": np.full(11, 0.5), "zz": np.zeros(11)})
    assert list(m.read_inputs({"u": np.full(11, 0.5), "zz": np.zeros(11)})) == ["u"]
    with pytest.raises(ParameterError, match="Machine.read_inputs: inputs = NoneType"):
        m.read_inputs(None)


def test_simulate_refuses_options_that_are_not_simoptions_and_an_overflowing_time_axis():
    """Were: options="fast" ran at the defaults; dt = 1e308 gave a time axis of inf at status 0."""
    u = np.full(5, 0.5)
    law = fk.LuGre(LAW, sigma0=1e5, sigma1=300.0)
    with pytest.raises(ParameterError, match="simulate: options = 'fast'"):
        fk.simulate(law, plant=fk.Mass(1.0), force=u, dt=1e-3, options="fast")
    with pytest.raises(ParameterError, match="simulate_batch: options = 'fast'"):
        fk.simulate_batch([law], masses=1.0, force=u, dt=1e-3, target=np.zeros(5), options="fast")
    for kw in ({"force": u, "plant": fk.Mass(1.0)}, {"velocity": u}):
        with pytest.raises(ParameterError, match="dt = 1e.308 s: 5 samples of it pass the largest float"):
            fk.simulate(law, dt=1e308, **kw)


def test_toml_files_with_a_byte_order_mark_are_read_as_the_json_loaders_read_them(tmp_path):
    """Was: a study/fleet TOML saved with a BOM (Windows editors) was refused as 'Invalid statement (line 1,
    column 1)' while the JSON loaders accept a BOM."""
    from frictionkit.fleet.config import load_config
    from frictionkit.study import load_study

    p = tmp_path / "s.toml"
    p.write_bytes(b"\xef\xbb\xbf" + b"[machine]\nlimit = 20.0\n[reference]\nduration = 0.2\n[study]\ndraws = 1\n"
                  b"seeds = 1\ncompensators = ['none']\n")
    assert load_study(p).machine["limit"] == 20.0
    from pathlib import Path

    src = Path(__file__).parents[2] / "examples" / "fleet" / "tro2021_steady_state.toml"
    q = tmp_path / "f.toml"
    q.write_bytes(b"\xef\xbb\xbf" + src.read_bytes())
    import dataclasses

    assert dataclasses.replace(load_config(q), source=load_config(src).source) == load_config(src)


def test_two_blocks_writing_one_signal_are_refused():
    """Was: a machine with two blocks writing the same signal (e.g. two Sum -> 'qf') loaded, and the second
    silently overrode the first every sample."""
    from frictionkit.machines import Sum

    m = fk.Machine("slider")
    m.dof("x", inertia=1.0)
    m.add(Sum("qf", {"a": 1.0}))
    with pytest.raises(ParameterError, match="writes signal 'qf', which a Sum block already writes"):
        m.add(Sum("qf", {"b": 1.0}))
