"""Issue 13, round 10's leftovers and campaign round 11 (helper r11): one test per pattern fixed, each built
from the case that exposed it (``benchmarks/robustness_campaign.py``, families K-R)."""

from __future__ import annotations

import re

import numpy as np
import pytest

from _robustness_helpers import LAW

import frictionkit as fk
from frictionkit.errors import ParameterError

LUGRE = fk.LuGre(LAW, sigma0=1e5, sigma1=30.0)


# ---------------------------------------------------------------- round 10's leftovers (c)
@pytest.mark.parametrize("v", ["abc", None, True, 1 + 2j, [1.0, "a"], [1.0, None], {"a": 1}, [[1.0], [1.0, 2.0]]])
@pytest.mark.parametrize("law", [LAW, LUGRE, fk.Dahl(Fc=1.0, sigma0=1e5), fk.CoulombViscous(Fc=1.0, sigma2=0.4),
                                 fk.GMS(LAW, k=[1e4, 1e5], xi=[0.5, 0.5], C=20.0),
                                 fk.Directional(positive=LAW, negative=LAW)], ids=lambda m: type(m).__name__)
def test_steady_state_refuses_what_is_no_velocity_naming_v(law, v):
    """Was: ``LuGre.steady_state("abc")`` raised numpy's "could not convert string to float"; ``None`` returned
    NaN, ``True`` the force at 1 m/s, ``1+2j`` a TypeError. Now one ParameterError naming the law and ``v``."""
    with pytest.raises(ParameterError, match=rf"{type(law).__name__}\.steady_state: v = .*must be velocities"):
        law.steady_state(v)


def test_steady_state_still_takes_numbers_lists_and_arrays():
    # LAW: Fc 1, Fs 1.5, vs 1e-3, delta 2, sigma2 0.4 -> Fss(0.01) = 1 + 0.5 exp(-100) + 0.004
    assert float(LUGRE.steady_state(0.01)) == pytest.approx(1.004, rel=1e-12)
    assert np.allclose(LUGRE.steady_state([0.01, -0.01]), [1.004, -1.004], rtol=1e-12)
    assert float(LUGRE.steady_state(np.array([1]))[0]) == pytest.approx(1.4, rel=1e-12)  # int array: 1 m/s
    tdmssc = fk.TDMSSC(Fc0=1.0, Fs0=1.5, vs=1e-3)
    with pytest.raises(ParameterError, match=r"TDMSSC\.steady_state: v = 'abc'"):
        tdmssc.steady_state("abc", schedule=0.0)


@pytest.mark.parametrize("kw, match", [
    ({"method": object()}, r"save_model: method = <object object .*must be a string"),
    ({"method": 5}, r"save_model: method = 5: must be a string"),
    ({"provenance": 5}, r"save_model: provenance = 5: must be a mapping"),
    ({"provenance": {"a": object()}}, r"provenance: .*not JSON serializable"),
    ({"units": 5}, r"save_model: units = 5: must be None \(the defaults .*\) or a mapping"),
    ({"data": 5}, r"save_model: data = 5: must be a file path"),
])
def test_save_model_refuses_wrong_types_naming_the_argument(tmp_path, kw, match):
    """Was: ``save_model(method=object())`` wrote "<object object at 0x...>" as the method; ``provenance=5``,
    ``units=5`` and ``data=5`` raised Python's TypeError/AttributeError, ``provenance={"a": object()}`` json's."""
    out = tmp_path / "m.json"
    with pytest.raises(ParameterError, match=match):
        fk.save_model(LUGRE, out, **kw)
    assert not out.exists()


@pytest.mark.parametrize("path", [5, None, b"m.json", ["m.json"]])
def test_model_file_paths_of_the_wrong_type_are_refused_naming_path(path):
    """Was: ``load_model(5)`` / ``save_model(law, None)`` raised pathlib's TypeError (round 10's residual)."""
    with pytest.raises(ParameterError, match=r"load_model: path = .*must be a file path"):
        fk.load_model(path)
    with pytest.raises(ParameterError, match=r"save_model: path = .*must be a file path"):
        fk.save_model(LUGRE, path)


# ---------------------------------------------------------------- round 10's leftovers (a)
def _slider_doc() -> dict:
    from frictionkit.machines import Saturation, Sum

    m = fk.Machine("slider")
    x = m.dof("x", inertia=1.0)
    m.friction("contact", x, law=fk.CoulombViscous(Fc=1.0))
    m.sensor("xm", x)
    m.add(Sum("u_c", {"xm": -100.0}), Saturation("u", "u_c", -5.0, 5.0))
    m.actuator("motor", x, command="u", limit=5.0)
    doc = m.to_dict()
    assert fk.Machine.from_dict(doc).to_dict() == doc
    return doc


@pytest.mark.parametrize("where, value", [
    (("dofs", 0, "v0"), 1e200), (("actuators", 0, "gain"), 1e308), (("sensors", 0, "noise"), 1e200),
    (("blocks", 0, "terms", "xm"), -1e300), (("sites", 0, "law", "Fc"), 1e300), (("dofs", 0, "inertia"), 10**200),
], ids=["v0", "gain", "noise", "sum-term", "law-Fc", "200-digit-integer-inertia"])
def test_a_machine_file_number_beyond_any_physical_size_is_refused_naming_its_path(where, value):
    """Was (round 10): a machine file's v0, gains and noise of 1e200-1e308 loaded, while the command line's
    options and data files refuse beyond 1e150 as a unit slip."""
    from frictionkit.errors import DataError

    doc = _slider_doc()
    node = doc
    for k in where[:-1]:
        node = node[k]
    node[where[-1]] = value
    path = "machine" + "".join(f"[{k}]" if isinstance(k, int) else f".{k}" for k in where)
    with pytest.raises(DataError, match=re.escape(path) + r" = .*beyond 1e\+150"):
        fk.Machine.from_dict(doc)


def test_a_machine_files_unbounded_limits_and_start_position_keep_their_own_rules():
    """The bound's exemptions (why 399636c's blanket bound was reverted): a saturation or actuator limit of
    ±1e300 means no limit (JSON has no infinity); x0 = 1e300 keeps its float-spacing message."""
    doc = _slider_doc()
    doc["blocks"][1]["lo"], doc["blocks"][1]["hi"] = -1e300, 1e300
    doc["actuators"][0]["limit"] = 1e300
    m = fk.Machine.from_dict(doc)
    assert m.actuators[0].limit == 1e300
    doc["dofs"][0]["x0"] = 1e300
    with pytest.raises(ParameterError, match=r"x0 = 1e\+300: .*float spacing"):
        fk.Machine.from_dict(doc)


def test_a_law_files_number_beyond_any_physical_size_is_refused(tmp_path):
    """Was: a law file with ``"sigma0": 1e200`` or ``"Fc": 1e300`` loaded (the same unit slip as above)."""
    import json

    from frictionkit.errors import DataError

    p = fk.save_model(LUGRE, tmp_path / "lugre.json")
    doc = json.loads(p.read_text())
    doc["model"]["static"]["Fs"] = 1e300
    p.write_text(json.dumps(doc))
    with pytest.raises(DataError, match=r"lugre\.json': model\.static\.Fs = 1e\+300: beyond 1e\+150"):
        fk.load_model(p)


# ---------------------------------------------------------------- round 10's review leftovers (d)
def test_the_words_as_typed_do_not_outlive_their_invocation(runner, tmp_path, staircase_csv):
    """Was: ``cli._errors.TYPED_ARGS`` was module state set by each parse: after one invocation a library
    caller of a verb's check (or the next in-process call) read the previous command line — a path typed
    once as 'DIR/sub/' still counted as typed with its slash. Now the words live on the invocation's context."""
    from frictionkit.cli import app
    from frictionkit.cli._errors import typed_value

    target = f"{tmp_path}/sub/"
    res = runner.invoke(app, ["identify", "static", str(staircase_csv), "--time", "t_s", "--velocity", "v_ms",
                              "--force", "F_N", "--model", "coulomb_viscous", "--json", target])
    assert res.exit_code == 2 and "ends in '/'" in res.stderr
    assert typed_value("--json", tmp_path / "sub") == f"{tmp_path}/sub"


def test_site_force_spans_does_not_hide_a_failing_coordinate_row(monkeypatch):
    """Was: ``site_force_spans`` wrapped ``machine.row`` in ``except Exception`` — a bug there made the
    convergence checks judge a site on its own force range without a word. Every site's coordinate belongs to
    its machine, so the row exists; a failure now surfaces. The spans themselves: a site's own range, or the
    largest range on a shared degree of freedom."""
    from types import SimpleNamespace

    from frictionkit.machines.simulate import site_force_spans

    m = fk.Machine("two")
    x = m.dof("x", inertia=1.0)
    m.compliance("spring", x, law=fk.machines.HertzContact(preload=1.0, stiffness=1e6))
    m.friction("contact", x, law=LUGRE)
    fine = SimpleNamespace(site_names=("spring", "contact"), site_forces=np.array([[0.0, -1.0], [10.0, 1.0]]))
    assert site_force_spans(m, fine) == [10.0, 10.0]  # both on x: the larger range (10 N) judges both

    def broken(at):
        raise RuntimeError("row failed")

    monkeypatch.setattr(m, "row", broken)
    with pytest.raises(RuntimeError, match="row failed"):
        site_force_spans(m, fine)


# ---------------------------------------------------------------- round 10's leftovers (b)
def test_an_interrupted_fleet_simulation_says_what_is_there_and_the_same_call_resumes_it(tmp_path):
    """Was (round 10): Ctrl-C in `fleet simulate --axes 1000` left 139 axes' logs behind "error: interrupted",
    without saying what they were or whether to start over. Now the interrupt names the complete logs and how
    to go on; the same call keeps them and writes the rest; the folder equals an uninterrupted run's.
    (The SIGINT to the command line: tests/robustness/test_interrupts.py.)"""
    import hashlib

    from frictionkit.fleet import simulate_fleet
    from frictionkit.fleet.simulate import UNFINISHED

    def stop_after_3(done, total):
        if done == 3:
            raise KeyboardInterrupt

    folder = tmp_path / "fleet"
    with pytest.raises(KeyboardInterrupt, match=rf"3 of 4 log files are in '{re.escape(str(folder))}', each "
                                                 r"complete; no fleet.toml yet .*same arguments to resume"):
        simulate_fleet(folder, axes=2, days=2, seed=3, progress=stop_after_3)
    assert not (folder / "fleet.toml").exists() and (folder / UNFINISHED).exists()
    from frictionkit.errors import DataError
    from frictionkit.fleet.identify import resolve_config

    with pytest.raises(DataError, match=r"an interrupted 'fleet simulate' \(unfinished.json, no fleet.toml yet\); "
                                        r"run the same 'fleet simulate' again"):  # was "no configuration"
        resolve_config(folder, None)
    seen = []
    fleet = simulate_fleet(folder, axes=2, days=2, seed=3, progress=lambda d, n: seen.append(d))
    assert fleet.resumed == 3 and seen == [1, 2, 3, 4] and "3 of them kept" in fleet.summary()
    assert (folder / "fleet.toml").exists() and not (folder / UNFINISHED).exists()
    fresh = simulate_fleet(tmp_path / "fresh", axes=2, days=2, seed=3)
    assert fresh.resumed == 0

    def digest(root):
        return {p.relative_to(root).as_posix(): hashlib.sha256(p.read_bytes()).hexdigest()
                for p in sorted(root.rglob("*")) if p.is_file()}

    assert digest(folder) == digest(tmp_path / "fresh")


def test_a_resumed_fleet_run_does_not_keep_an_earlier_fleets_logs(tmp_path):
    """A folder holding a finished fleet of other arguments, then an interrupted run of new ones: resuming keeps
    only what the interrupted run wrote (an old log of the same name is rewritten), and the old fleet.toml is
    gone as soon as the new run starts (a half-rewritten folder is no fleet)."""
    from frictionkit.fleet import simulate_fleet

    folder = tmp_path / "fleet"
    old = simulate_fleet(folder, axes=1, days=2, seed=1, broken=0)
    old_log = (folder / old.files[1]).read_bytes()

    def stop_after_1(done, total):
        if done == 1:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt, match="1 of 2 log files"):
        simulate_fleet(folder, axes=1, days=2, seed=2, broken=0, progress=stop_after_1)
    assert not (folder / "fleet.toml").exists()
    new = simulate_fleet(folder, axes=1, days=2, seed=2, broken=0)
    assert new.resumed == 1 and (folder / new.files[1]).read_bytes() != old_log


# ---------------------------------------------------------------- round 11: L (FIFOs, devices)
@pytest.fixture
def fifo(tmp_path):
    """A named pipe no one writes to (reading it blocks for ever), with a guard that fails instead of hanging."""
    import os
    import signal

    p = tmp_path / "pipe.json"
    os.mkfifo(p)

    def hung(signum, frame):
        raise TimeoutError("the reader blocked on the FIFO")

    old = signal.signal(signal.SIGALRM, hung)
    signal.alarm(10)
    yield p
    signal.alarm(0)
    signal.signal(signal.SIGALRM, old)


@pytest.mark.parametrize("reader", ["load_model", "load_study", "load_config", "CompensationTest.load",
                                    "read_json_object"])
def test_an_input_file_that_is_a_fifo_is_refused_not_waited_for(fifo, reader):
    """Was (round 11, family L): a model file, study, fleet configuration, compensation test or result file that
    is a named pipe blocked the command for ever (`export fifo.json` hung); ``/dev/zero`` as a model file read
    until the memory ran out (15 GB in the campaign); the study and fleet loaders called a device "not found".
    Now each says the path is not a regular file."""
    from frictionkit.compensate import CompensationTest
    from frictionkit.errors import DataError
    from frictionkit.fleet import load_config
    from frictionkit.identify.result import read_json_object
    from frictionkit.study import load_study

    call = {"load_model": fk.load_model, "load_study": load_study, "load_config": load_config,
            "CompensationTest.load": CompensationTest.load, "read_json_object": read_json_object}[reader]
    with pytest.raises(DataError, match=rf"'{re.escape(str(fifo))}': is not a regular file \(a device, pipe"):
        call(fifo)


def test_a_text_input_beyond_the_size_limit_is_refused(tmp_path, monkeypatch):
    """The whole-file readers stop at MAX_TEXT_INPUT (256 MB: the largest file the package writes is ~10 MB)."""
    import frictionkit._io as io_

    p = fk.save_model(LUGRE, tmp_path / "m.json")
    monkeypatch.setattr(io_, "MAX_TEXT_INPUT", 100)
    from frictionkit.errors import DataError

    with pytest.raises(DataError, match=r"m\.json': 0 MB, beyond the 0 MB a text input file may have"):
        fk.load_model(p)


# ---------------------------------------------------------------- round 11: T (wrong types into the Python API)
@pytest.mark.parametrize("call, match", [
    (lambda: fk.find_plateaus(np.ones(50), 1e-3, min_samples="abc"), r"find_plateaus\.min_samples = 'abc': must be an "
                                                                      r"integer"),
    (lambda: fk.find_plateaus(np.ones(50), 1e-3, trim=None), r"find_plateaus\.trim = None: must be a real number"),
    (lambda: fk.decimate(np.ones(50), 2, zero_phase="abc"), r"decimate\.zero_phase = 'abc': must be True or False"),
    (lambda: fk.derivative(np.ones(50), 1e-3, window=None), r"derivative\.window = None: must be an integer"),
    (lambda: fk.lowpass(np.ones(50), 1e3, "50"), r"lowpass\.cutoff = '50': must be a real number"),
    (lambda: fk.fit_static_map(np.ones(5), np.ones(5), units="N"), r"fit_static_map\.units = 'N': must be a mapping"),
    (lambda: fk.load_csv(None, time="t"), r"load_csv\.path = None: must be a string or a file path"),
    (lambda: fk.load_recording("x.csv", time="t", current_gain="2"), r"load_recording\.current_gain = '2': must be a "
                                                                       r"real number \(or None\)"),
    (lambda: fk.simulate(LUGRE, position=np.zeros(5), dt=1e-3, x0="abc"), r"simulate\.x0 = 'abc': must be a real"),
    (lambda: fk.ModelFile(model=LUGRE, provenance="x"), r"ModelFile.provenance = 'x': must be a mapping"),
], ids=["int", "float-None", "bool", "int-None", "float-str", "mapping", "path", "optional-float", "simulate-x0",
        "modelfile-provenance"])
def test_public_entry_points_name_an_argument_of_the_wrong_type(call, match):
    """Was (round 11, family T: every public entry point with a wrong type in each argument, 731 calls): 133 ended
    in Python's or numpy's own TypeError/ValueError/AttributeError ("'>=' not supported between instances of
    'int' and 'str'", "dictionary update sequence element #0 ..."), 64 ran (``decimate(zero_phase="abc")``,
    ``simulate(x0="abc")`` on a motion-driven run). Now the annotated simple types are checked at the boundary
    (``_validate.typed_arguments``) and the error names the function, the argument and the value."""
    with pytest.raises(ParameterError, match=match):
        call()


def test_typed_arguments_leaves_legal_values_alone():
    from frictionkit._validate import typed_arguments

    @typed_arguments
    def f(y, q: "int", *, path: "str | Path" = "x", m: "Mapping[str, float] | None" = None, flag: "bool" = True,
          a: "ArrayLike" = 1, r: "float | None" = None):
        return q

    assert f(0, np.int64(3), path=__import__("pathlib").Path("p"), m={"a": 1.0}, flag=np.bool_(False), a="anything",
             r=np.float32(2.0)) == 3
    with pytest.raises(TypeError, match="missing 1 required positional argument: 'q'"):  # Python's own words
        f(0)


# ---------------------------------------------------------------- round 11: S (help of every verb)
def test_the_verbs_answer_dash_h_with_their_usage():
    """Was (round 11, family S): ``--help`` worked on all 23 commands but ``-h`` was "No such option: -h" on every
    one. Now both print the usage (exit 0)."""
    import typer
    from typer.testing import CliRunner

    from frictionkit.cli import _register, app

    _register()

    def walk(cmd, path):
        yield path
        for name, sub in sorted(getattr(cmd, "commands", {}).items()):
            yield from walk(sub, path + [name])

    paths = list(walk(typer.main.get_command(app), []))
    assert len(paths) >= 20 and ["identify", "static"] in paths and ["fleet", "simulate"] in paths
    runner = CliRunner()
    # the top, a group, a verb of each group and two plain verbs (the names reach every verb through click's
    # context; the campaign's family S runs all 23 commands)
    for path in ([], ["identify"], ["identify", "static"], ["fleet", "simulate"], ["reproduce", "sdss"], ["export"],
                 ["simulate"]):
        res = runner.invoke(app, path + ["-h"])
        assert res.exit_code == 0 and res.output.startswith(" ".join(["Usage: frictionkit"] + path)), (path, res.output)


def test_a_fleet_glob_matching_nothing_says_so_before_asking_for_a_configuration(tmp_path):
    """Was (round 11, family P): `fleet identify 'EMPTY/*/*.csv'` said "no configuration; pass config=" — the
    user adds --config and only then learns that the pattern matches no file."""
    from frictionkit.errors import DataError
    from frictionkit.fleet.identify import resolve_config

    with pytest.raises(DataError, match=r"\*/\*\.csv': the pattern matches no file"):
        resolve_config(f"{tmp_path}/*/*.csv", None)


# ---------------------------------------------------------------- round 11: O (huge but legal arrays)
def test_a_static_fit_of_many_points_does_not_build_an_n_by_n_matrix(monkeypatch):
    """Was (round 11, family O): fit_static_map on 1e6 points raised numpy's MemoryError "Unable to allocate
    1.82 TiB for an array with shape (500000, 500000)" — the rank check took the full SVD of the Jacobian (U is
    n x n; 20,000 points per direction already took 3.2 GB). Now only V is full, and only when n < p."""
    shapes = []
    real_svd = np.linalg.svd

    def spy(a, *args, **kwargs):
        out = real_svd(a, *args, **kwargs)
        shapes.append((np.shape(a), np.shape(out[0]) if kwargs.get("compute_uv", True) else None))
        return out

    monkeypatch.setattr(np.linalg, "svd", spy)
    v = np.r_[np.geomspace(1e-4, 0.2, 3000), -np.geomspace(1e-4, 0.2, 3000)]
    res = fk.fit_static_map(v, LAW.steady_state(v), model="coulomb_viscous")
    assert res.names == ("Fc_pos", "sigma2_pos", "Fc_neg", "sigma2_neg")
    big = [(a, u) for a, u in shapes if a[0] >= 3000]  # the Jacobians (3000 x 2) and their U
    assert big and all(u is None or u[1] <= a[1] for a, u in big), shapes  # was (3000, 3000)


@pytest.mark.parametrize("law, arg", [(lambda a: fk.coulomb_compensation(a, F0=1.0), "v"),
                                      (lambda a: fk.sinc_compensation(a, F0=1.0, xs=2e-6), "x"),
                                      (lambda a: fk.sigmoid_compensation(a, F0=1.0, sigma=2e-6), "x")])
@pytest.mark.parametrize("value", ["abc", None])
def test_the_compensation_laws_refuse_what_is_no_number_naming_their_argument(law, arg, value):
    """Was (round 11, family T): ``coulomb_compensation("abc", F0=1)`` raised numpy's ValueError and
    ``coulomb_compensation(None, F0=1)`` returned a number (NaN compared as "not positive": -F0)."""
    with pytest.raises(ParameterError, match=rf"_compensation: {arg} = {value!r}: must be "):
        law(value)
