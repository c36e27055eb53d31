"""The report builder (frictionkit.report.Report) and its adapters, one test per result kind.

Inputs are made by the package itself at quick sizes (identification fits on synthetic data,
model files, a 12-run study, a 2-axis fleet, simulated traces); the reproductions' JSON
documents are written here in the layout of ``reproduce ... --json`` with numbers chosen so
that each verdict is known (running the reproductions takes minutes; their own tests run them).
Expected values come from the inputs (the files), never from the adapters.
"""

from __future__ import annotations

import base64
import json
import re

import numpy as np
import pandas as pd
import pytest
from typer.testing import CliRunner

import frictionkit as fk
from frictionkit.cli import _register, app
from frictionkit.data import Recording
from frictionkit.errors import DataError, ParameterError
from frictionkit.identify import fit_rigid_body, fit_static_map
from frictionkit.identify.reversal import fit_reversal
from frictionkit.models.rolling import sinc_compensation
from frictionkit.report import Report, Section
from frictionkit.report.adapters import sections_from_file

_register()
runner = CliRunner()
pytestmark = pytest.mark.xdist_group("report_builder")  # module fixtures (fits, study, fleet) built once
PNG = b"\x89PNG\r\n\x1a\n"


def _cells(sec: Section) -> list[list[str]]:
    return [row for _, rows in sec.all_tables() for row in rows]


def _table(sec: Section, caption: str) -> list[list[str]]:
    return next(rows for c, rows in sec.all_tables() if c.startswith(caption))


def assert_self_contained(page: str) -> None:
    """No external asset: every src= is an embedded PNG that decodes; nothing fetched over the network."""
    assert "http://" not in page and "https://" not in page
    srcs = re.findall(r"src=['\"]([^'\"]*)['\"]", page)
    assert srcs, "no images"
    for s in srcs:
        assert s.startswith("data:image/png;base64,"), s[:60]
        assert base64.b64decode(s.split(",", 1)[1]).startswith(PNG)
    assert "<link" not in page and "<script" not in page


# --------------------------------------------------------------------------- builder
def test_page_escapes_everything_and_embeds_figures(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots()
    ax.plot([0, 1], [0, 1])
    sec = Section("<script>alert(1)</script> & title", text=["a < b & c > d"],
                  table=[["parameter", "verdict"], ["<img src=x onerror=alert(1)>", "holds"], ["Fc", "does not hold"]],
                  tables=[("caption <i>", [["h"], ["<b>cell</b>"]])], links=[("fleet.html", "the <fleet> page")])
    sec.add_figure("plot.png", fig)
    rep = Report("R & <D>", intro=["intro <x>"]).add(sec, None)
    page = rep.html()
    for raw in ("<script>alert(1)</script>", "<img src=x", "<b>cell</b>", "caption <i>", "<fleet>", "<x>", "<D>"):
        assert raw not in page, raw
    assert "&lt;img src=x onerror=alert(1)&gt;" in page and "&lt;b&gt;cell&lt;/b&gt;" in page
    assert "<td class='ok'>holds</td>" in page and "<td class='bad'>does not hold</td>" in page
    assert "<a href='fleet.html'>the &lt;fleet&gt; page</a>" in page
    assert_self_contained(page.replace("<a href='fleet.html'>", ""))
    text = rep.text()
    assert "== <script>alert(1)</script> & title" in text and "<b>cell</b>" in text  # the text digest is plain


def test_marks_only_in_verdict_columns():
    page = Report("t").add(Section("s", table=[["item", "value"], ["failed", "flagged"]])).html()
    assert "<td>failed</td>" in page and "<td>flagged</td>" in page


def test_write_is_atomic_and_refuses_an_input(tmp_path):
    rep = Report("t").add(Section("s", text=["x"]))
    p = rep.write(tmp_path / "out")
    assert p == tmp_path / "out" / "report.html" and p.read_text(encoding="utf-8").startswith("<!doctype html>")
    assert not [q for q in p.parent.iterdir() if q.name.endswith(".tmp")]
    inp = tmp_path / "in" / "report.html"
    inp.parent.mkdir()
    inp.write_text("{}")
    with pytest.raises(DataError, match="refusing to overwrite an input"):
        rep.write(tmp_path / "in", inputs=[inp])
    assert inp.read_text() == "{}"


@pytest.mark.parametrize("title", ["", "two\nlines", 3])
def test_bad_title(title):
    with pytest.raises(ParameterError, match="Report.title"):
        Report(title)


def test_add_refuses_non_sections():
    with pytest.raises(ParameterError, match="dict is not a Section"):
        Report("t").add({"title": "x"})


# --------------------------------------------------------------------------- inputs
@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """One small file of each identification kind, a model file and traces."""
    d = tmp_path_factory.mktemp("results")
    rng = np.random.default_rng(0)
    # static map, per direction (exponential Stribeck), clean data
    v = np.r_[np.geomspace(1e-4, 0.05, 14), -np.geomspace(1e-4, 0.05, 14)]
    law = fk.Directional(positive=fk.Stribeck(Fc=1.0, Fs=1.5, vs=2e-3, sigma2=10.0),
                         negative=fk.Stribeck(Fc=1.2, Fs=1.6, vs=2e-3, sigma2=12.0))
    fit_static_map(v, law.steady_state(v) + rng.normal(0, 0.01, v.size)).save_json(d / "static.json")
    # rigid body M a + Fv v + Fc sgn v, no offset
    t = np.arange(0, 6.0, 1e-3)
    w = 2 * np.pi * 0.5
    x, vel, acc = 0.05 * np.sin(w * t), 0.05 * w * np.cos(w * t), -0.05 * w**2 * np.sin(w * t)
    F = 10 * acc + 20 * vel + 2 * np.sign(vel) + rng.normal(0, 0.05, t.size)
    fit_rigid_body(Recording(t=t, x=x, F=F, name="sim")).save_json(d / "rigid.json")
    # reversal: seed 001 Fig. 13's sinc law (F0 = 2.431 N·m, xs = 10 µm) around the turning points
    tt = np.arange(6000) * 1e-3
    xr = 50e-6 * np.sin(2 * np.pi * 0.5 * tt)
    t0 = (np.arange(0, tt[-1] + 1) + 0.5)
    k = np.abs(tt[:, None] - t0[None, :]).argmin(1)
    x0 = 50e-6 * np.sin(2 * np.pi * 0.5 * t0[k])
    xi = np.sign(tt - t0[k]) * np.abs(xr - x0)
    Fr = -np.sign(x0) * sinc_compensation(xi, F0=2.431, xs=10e-6) + rng.normal(0, 0.02, tt.size)
    fit_reversal(Recording(t=tt, x=xr, F=Fr, name="rev", units={"F": "N·m"})).save_json(d / "rev.json")
    # model file and traces of a position-driven LuGre run (a hysteresis loop)
    lugre = fk.LuGre(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4), sigma0=1e5, sigma1=63.2)
    fk.save_model(lugre, d / "lugre.json", method="test <model>")
    from frictionkit.simulation.traces import write_traces

    sim = fk.simulate(lugre, position=30e-6 * np.sin(np.linspace(0, 4 * np.pi, 801)), dt=1e-3)
    write_traces(sim, d / "traces.csv")
    write_traces(sim, d / "traces.parquet")
    return d


def test_static_map(files):
    kind, (sec,) = sections_from_file(files / "static.json")
    doc = json.loads((files / "static.json").read_text())
    assert kind == "identification" and sec.kind == "identification" and sec.source == "static.json"
    params = _table(sec, "Parameters")
    assert [r[0] for r in params[1:]] == list(doc["parameters"])
    fc = doc["parameters"]["Fc_pos"]
    row = next(r for r in params if r[0] == "Fc_pos")
    assert row[1] == f"{fc['value']:.6g}" and row[4] == fc["unit"] == "N" and row[5] == "ok"
    assert any(r[0] == "velocity [m/s]" for r in _table(sec, "Data overview"))
    assert len(sec.figures) == 1 and sec.figures[0][1].startswith(PNG)
    assert any(t.startswith("positive direction: exponential") for t in sec.text)


def test_result_saved_without_data_has_no_plot(tmp_path):
    v = np.r_[np.linspace(0.01, 0.2, 12), -np.linspace(0.01, 0.2, 12)]
    fit_static_map(v, np.sign(v) * 2.0 + 10.0 * v, model="coulomb_viscous").save_json(tmp_path / "f.json",
                                                                                        include_data=False)
    _, (sec,) = sections_from_file(tmp_path / "f.json")
    assert sec.figures == [] and sec.text[-1].startswith("The file holds no fitted data")
    assert [r[0] for r in _table(sec, "Parameters")[1:]] == ["Fc_pos", "sigma2_pos", "Fc_neg", "sigma2_neg"]


def test_flagged_parameter_is_marked(files, tmp_path):
    doc = json.loads((files / "rigid.json").read_text())
    doc["warnings"] = ["Fv not identifiable: its interval spans more than a decade"]
    (tmp_path / "flag.json").write_text(json.dumps(doc))
    _, (sec,) = sections_from_file(tmp_path / "flag.json")
    flags = {r[0]: r[5] for r in _table(sec, "Parameters")[1:]}
    assert flags == {"M": "ok", "Fv": "flagged", "Fc": "ok", "offset": "ok"}
    assert "Flag: Fv not identifiable: its interval spans more than a decade" in sec.text
    assert "<td class='bad'>flagged</td>" in Report("t").add(sec).html()


def test_rigid_body_and_reversal_overlays(files):
    for name, kind in (("rigid.json", "rigid_body"), ("rev.json", "reversal")):
        _, (sec,) = sections_from_file(files / name)
        doc = json.loads((files / name).read_text())
        assert doc["kind"] == kind and [r[0] for r in _table(sec, "Parameters")[1:]] == list(doc["parameters"])
        assert len(sec.figures) == 1 and sec.figures[0][1].startswith(PNG)


def test_model_file(files):
    kind, (sec,) = sections_from_file(files / "lugre.json")
    assert kind == "model" and sec.title == "Friction model: LuGre"
    rows = {r[0]: r for r in sec.table}
    assert rows["sigma0"][1:] == ["100000", "N/m"] and rows["static.Fc"][1:] == ["1", "N"]
    assert ["method", "test <model>"] in _table(sec, "Provenance")
    assert "test &lt;model&gt;" in Report("t").add(sec).html()
    # the hysteresis loop over 5 pre-sliding distances: 5 x Fs / sigma0 = 5 x 1.5 N / 1e5 N/m = 75 µm
    assert sec.text == ["Hysteresis loop: the law driven along a slow sine of ±75 µm (5 × its pre-sliding "
                        "distance, level / stiffness) from the unloaded state."]
    assert len(sec.figures) == 1


def test_static_model_file_has_no_loop(tmp_path):
    fk.save_model(fk.CoulombViscous(Fc=2.0, sigma2=10.0), tmp_path / "cv.json")
    kind, (sec,) = sections_from_file(tmp_path / "cv.json")
    assert kind == "model" and sec.text == [] and len(sec.figures) == 1


@pytest.mark.parametrize("name", ["traces.csv", "traces.parquet"])
def test_traces(files, name):
    kind, (sec,) = sections_from_file(files / name)
    assert kind == "traces" and sec.title.startswith("Simulated traces: 801 samples")
    assert [r[0] for r in sec.table[1:]] == ["t [s]", "x [m]", "v [m/s]", "friction [N]", "z [m]"]
    assert sec.table[2][1:] == ["-3e-05", "3e-05"]  # the position drive's amplitude, 30 µm
    assert len(sec.figures) == 1


def test_result_objects(files, study):
    """Report.add_result takes the objects themselves: the same sections as their files."""
    from frictionkit.identify import IdentificationResult

    rep = Report("objects")
    res = IdentificationResult.load_json(files / "static.json")
    (sec,) = rep.add_result(res, name="static fit")
    (from_file,) = sections_from_file(files / "static.json")[1]
    assert sec.source == "static fit" and _table(sec, "Parameters") == _table(from_file, "Parameters")
    lugre = fk.load_model(files / "lugre.json")
    assert rep.add_result(lugre)[0].title == "Friction model: LuGre"
    sim = fk.simulate(lugre, position=30e-6 * np.sin(np.linspace(0, 4 * np.pi, 801)), dt=1e-3)
    assert rep.add_result(sim)[0].table == sections_from_file(files / "traces.csv")[1][0].table
    assert rep.add_result(pd.read_parquet(study / "study.parquet"))[0].kind == "study"
    assert [i["kind"] for i in rep.inputs] == ["identification", "model", "traces", "study"]
    with pytest.raises(ParameterError, match="a int is not a result the report knows"):
        rep.add_result(3)
    with pytest.raises(DataError, match=r"result dict: a JSON object of no kind .* \(keys: x\)"):
        rep.add_result({"x": 1})


# --------------------------------------------------------------------------- reproductions, compensation
def _zf_doc(sigmoid: float) -> dict:
    """The layout of ``reproduce zhu-fujimoto --json``; Table 3 paper values are seed 001 Table 3 [µm]."""
    return {"paper": "Zhu & Fujimoto, ... (seed 001)", "quick": True, "seed": 0, "stage": "fig2", "nut_model": "sliding",
            "table3": {"sinc": {"max_error_um": 2.4, "paper_um": 4.24}, "coulomb": {"max_error_um": 2.8, "paper_um": 5.44},
                       "sigmoid": {"max_error_um": sigmoid, "paper_um": 1.65},
                       "sigmoid_post_only": {"max_error_um": 1.5, "paper_um": None}},
            "fig5b": {"motor_input_reverses_before_zero_ms": 55.0, "drive_force_reverses_before_zero_ms": 17.0},
            "ld": {k: {"min_ratio_before_zero": m, "max_ratio_before_zero": 1.01} for k, m in
                   (("slow_reverse", 0.99), ("fast_reverse", 0.98))},
            "selector": {"mixed_max_error_um": 2.6, "best_fixed_max_error_um": 2.5},
            "fig5": {"slow_reverse": {"max_error_um": 3.1}, "fast_reverse": {"max_error_um": 2.4}},
            "table2_fast_non_reverse": {"original": {"max_error_um": 4.4}, "redesigned": {"max_error_um": 2.7}},
            "fig2": {"gain_offset_vs_eq1_db": [-0.16, 0.09]}}


@pytest.mark.parametrize("sigmoid, verdict", [(2.2, "holds"), (2.5, "does not hold")])
def test_zhu_fujimoto_verdicts(tmp_path, sigmoid, verdict):
    (tmp_path / "zf.json").write_text(json.dumps(_zf_doc(sigmoid)))
    kind, (sec,) = sections_from_file(tmp_path / "zf.json")
    assert kind == "reproduce-zhu-fujimoto"
    claims = {r[0]: r[2] for r in sec.table[1:]}
    assert claims["Table 3 order: sigmoid < sinc < Coulomb"] == verdict
    assert claims["the sigmoid's pre-zero reduction helps (sigmoid < post-only)"] == "does not hold"  # 2.2 / 2.5 > 1.5
    assert claims["Fig. 5(b): the motor input brakes before zero speed"] == "holds"
    assert claims["Fig. 5: sinc worse after a fast deceleration"] == "does not hold"  # 2.4 < 3.1
    assert claims["Fig. 10: l_d/R drops before zero speed in fast deceleration"] == "holds"  # 0.98 < 0.99
    assert claims["Table 2: the selector beats every fixed law"] == "does not hold"  # 2.6 > 2.5
    numbers = _table(sec, "Numbers beside the paper")
    assert ["Table 3 sinc [µm] (paper 4.24)", "2.40"] in numbers


def test_reproduction_format_dispatches(tmp_path):
    """A document that says what it is (``format`` + ``reproduction``) is read as that, whatever
    its ``paper`` string; an unknown reproduction name is refused in one line."""
    doc = dict(_zf_doc(2.2), format="frictionkit.reproduction/1", reproduction="zhu-fujimoto", paper="renamed")
    (tmp_path / "zf.json").write_text(json.dumps(doc))
    assert sections_from_file(tmp_path / "zf.json")[0] == "reproduce-zhu-fujimoto"
    doc["reproduction"] = "seed-999"
    (tmp_path / "zf.json").write_text(json.dumps(doc))
    with pytest.raises(DataError, match="a reproduction of 'seed-999'"):
        sections_from_file(tmp_path / "zf.json")


def test_sdss_truth_inside_interval(tmp_path):
    doc = {"paper": "seed 002, Friction Model of the 2.5 m SDSS Telescope", "quick": True, "seed": 0,
           "axes": {"rotator": {"truth": {"Fc_pos": 90.0, "vs_pos": 4e-4},
                                "identified": {"Fc_pos": {"value": 90.1, "ci95": [89.9, 90.2]},
                                               "vs_pos": {"value": 4.2e-4, "ci95": [4.1e-4, 4.3e-4]}},
                                "status": 0, "message": "ok"}},
           "sidereal_tracking_rms_arcsec": {"no_compensation": 0.1, "lugre_feedforward": 0.07}}
    (tmp_path / "sdss.json").write_text(json.dumps(doc))
    kind, (sec,) = sections_from_file(tmp_path / "sdss.json")
    rows = {r[0]: r for r in _table(sec, "rotator")[1:]}
    assert kind == "reproduce-sdss"
    assert rows["Fc_pos"][4:] == ["+0.11", "holds"] and rows["vs_pos"][4:] == ["+5.00", "does not hold"]


def test_zhang2023_findings(tmp_path):
    row = {"speeds": "same", "base_speed_mm_s": 6, "structure": "worktable", "mean_um": 0.001, "std_um": 0.01,
           "status": 0, "paper_mean_um": -0.328, "paper_std_um": 0.102}
    doc = {"paper": "Zhang et al., Actuators 2023 (seed 000)", "quick": True, "seed": 0, "status": 0, "message": "ok",
           "table7": [{**row, "method": "ACIM"}, {**row, "method": "WSIM"}],
           "table8": [{**row, "model": "LuGre"}, {**row, "model": "GMS"}],
           "findings": {"t7_same6_acim_better": {"holds": False, "ACIM": [0.001, 0.01], "WSIM": [0.001, 0.01]},
                        "fig16_reciprocating_gms_better": {"holds": True, "LuGre": 23.6, "GMS": 5.7}}}
    (tmp_path / "zh.json").write_text(json.dumps(doc))
    kind, (sec,) = sections_from_file(tmp_path / "zh.json")
    assert kind == "reproduce-zhang2023"
    assert [r[2] for r in sec.table[1:]] == ["does not hold", "holds"]
    assert "LuGre 23.6; GMS 5.7" in sec.table[2][1]
    assert ["same", "6", "ACIM", "+0.0010 (0.0100)", "-0.328 (0.102)"] in _table(sec, "Table 7")


@pytest.mark.parametrize("unit, error, label, shown", [
    ("m", 2.5e-6, "µm", "2.5"),
    ("rad", 2 * np.pi / 1296000, "arcsec", "1"),  # one arcsecond = 2 pi / (360 * 3600) rad
])
def test_compensation_units(tmp_path, unit, error, label, shown):
    """The layout of ``compensate --json``; errors in SI, shown in µm (linear) or arcsec (rotary)."""
    row = {"ok": True, "message": "ok", "max_error": error, "rms_error": error, "reversal_error": None}
    doc = {"preset": "p", "quick": True, "model": None, "duration_s": 1.0, "reversals_s": [], "units": {"error": unit},
           "compensators": {"none": row, "x": {**row, "ok": False, "message": "diverged"}}, "status": 0,
           "message": "ok"}
    (tmp_path / "c.json").write_text(json.dumps(doc))
    kind, (sec,) = sections_from_file(tmp_path / "c.json")
    assert kind == "compensation" and sec.table[0][1] == f"max [{label}]"
    assert sec.table[1:] == [["none", shown, shown, "–", "ok"], ["x", shown, shown, "–", "failed"]]
    assert "Compensator x failed: diverged" in sec.text
    assert "<td class='bad'>failed</td>" in Report("t").add(sec).html()


def test_robustness_sweep(tmp_path):
    doc = {"runtime_s": 1.0, "variants": [], "holds_fraction": {"t7_diff0_wsim_better": 1.0, "crawling": 0.25},
           "sensitivity": {}, "ranking": ["loop_bandwidth", "ball_preload"], "quick": True, "failed": ["v3"],
           "computed": 4, "skipped": 0}
    (tmp_path / "rob.json").write_text(json.dumps(doc))
    kind, (sec,) = sections_from_file(tmp_path / "rob.json")
    assert kind == "robustness" and sec.table[1:] == [["t7_diff0_wsim_better", "1"], ["crawling", "0.25"]]
    assert "Sensitivity ranking (most sensitive first): loop_bandwidth, ball_preload." in sec.text
    assert "Failed variants: v3." in sec.text


# --------------------------------------------------------------------------- bad input
@pytest.mark.parametrize("content, suffix, message", [
    (None, ".json", "no such file"),
    (b"\xff\xfe", ".json", "not UTF-8 text"),
    (b"{not json", ".json", "not valid JSON"),
    (b"[1, 2]", ".json", "the top level is a JSON list"),
    (b'{"a": 1}', ".json", "a JSON object of no kind frictionkit report reads (keys: a)"),
    (b'{"format": "frictionkit.model/9", "model": {}}', ".json", "written by a newer frictionkit"),
    (b'{"format": "frictionkit.fleet/1"}', ".json", "not one frictionkit report reads"),
    (b'{"format": "frictionkit.identification/1", "kind": "static_map"}', ".json", "missing key"),
    (b'{"paper": "x (seed 001)", "table3": {}}', ".json", "malformed content (KeyError"),
    (b"a,b\n1,2\n", ".csv", "a table of no kind frictionkit report reads (columns: a, b)"),
    (b"PAR1 broken", ".parquet", "not a readable Parquet file"),
    (b"[report]", ".toml", "unknown file type '.toml'"),
])
def test_bad_input_one_line_naming_the_file(tmp_path, content, suffix, message):
    p = tmp_path / f"bad{suffix}"
    if content is not None:
        p.write_bytes(content)
    with pytest.raises(DataError) as exc:
        sections_from_file(p)
    msg = str(exc.value)
    assert message in msg and str(p) in msg and "\n" not in msg, msg


def test_folder_is_refused(tmp_path):
    with pytest.raises(DataError, match="is a folder"):
        sections_from_file(tmp_path)


# --------------------------------------------------------------------------- study, fleet
STUDY = """
[reference]
duration = 1.0
[study]
draws = 4
seeds = 1
compensators = ["none", "coulomb", "static"]
"""


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    d = tmp_path_factory.mktemp("study")
    (d / "study.toml").write_text(STUDY)
    res = runner.invoke(app, ["study", str(d / "study.toml"), "--out", str(d / "study.parquet"), "--workers", "0",
                              "--no-progress", "--json", str(d / "summary.json")])
    assert res.exit_code == 0, res.output
    return d


def test_study_summary(study):
    kind, (sec,) = sections_from_file(study / "study.parquet")
    df = pd.read_parquet(study / "study.parquet")
    assert kind == "study" and sec.title == "Monte-Carlo study: 12 run(s), 3 compensator(s)"
    rows = {r[0]: r for r in sec.table[1:]}
    med = df[df["ok"]].groupby("compensator")["max_error"].median()
    assert list(rows) == sorted(["none", "coulomb", "static"], key=med.get)  # best first
    for comp, r in rows.items():
        g = df[(df["compensator"] == comp) & df["ok"]]
        assert r[1:3] == ["4", "0"]
        assert r[3] == f"{1e6 * g['max_error'].median():.4g}" and r[5] == f"{1e6 * g['max_error'].max():.4g}"
    assert sec.figures[0][0] == "study_errors.png" and sec.figures[0][1].startswith(PNG)
    drawn = {r[0] for r in _table(sec, "Drawn plant parameters")[1:]}
    assert {"Fc", "Fs", "sigma2", "sigma0"} <= drawn and "max_error" not in drawn
    kind, (s2,) = sections_from_file(study / "summary.json")
    summary = json.loads((study / "summary.json").read_text())
    assert kind == "study-summary" and [r[0] for r in s2.table[1:]] == list(summary["compensators"])


@pytest.fixture(scope="module")
def fleet(tmp_path_factory):
    d = tmp_path_factory.mktemp("fleet")
    res = runner.invoke(app, ["fleet", "simulate", "--axes", "2", "--days", "2", "--out", str(d / "logs"), "--seed", "1"])
    assert res.exit_code == 0, res.output
    res = runner.invoke(app, ["fleet", "identify", str(d / "logs"), "--out", str(d / "fleet.parquet"), "--workers", "0"])
    assert res.exit_code == 0, res.output
    return d


def test_fleet(fleet):
    # the numbers, then (when any) the flagged axes with their histories, then the failed files,
    # each its own section: in one section the flagged axes' history plots came after the failed
    # files' table (a section draws its tables before its figures), far from the flagged table
    kind, (sec, *rest) = sections_from_file(fleet / "fleet.parquet")
    broken = (fleet / "logs" / "broken.txt").read_text().split()
    assert kind == "fleet" and sec.title == "Fleet: 2 axes, 4 axis-periods"
    numbers = dict(sec.table[1:])
    assert numbers["failed"] == str(len(broken)) and numbers["identified"] == str(4 - len(broken))
    assert rest[-1].title == f"Fleet: files that failed ({len(broken)})" and not rest[-1].figures
    failed = _table(rest[-1], "Files that failed")
    assert [r[2] for r in failed[1:]] == broken
    assert sec.figures and all(png.startswith(PNG) for _, png in sec.figures)


def test_fleet_flagged_axes_section_holds_their_histories():
    from frictionkit.report.adapters import fleet_sections

    df = pd.DataFrame({"axis": ["a", "a", "b", "b"], "period": ["2026-01-01", "2026-02-01"] * 2, "ok": [True, True, True, False],
                       "Fc_pos": [1.0, 1.5, 1.0, np.nan], "file": ["f1", "f2", "f3", "f4"],
                       "error": [None, None, None, "bad header"],
                       "drift_flag": [False, True, False, False], "drift_alarm_period": [None, "2026-02-01", None, None],
                       "drift_detail": [None, "drift from 2026-02-01", None, None]})
    main, flagged, failed = fleet_sections(df)
    assert flagged.title == "Fleet: flagged axes (1)"
    assert [c for c, _ in flagged.tables] == ["Flagged axes (1)"] and [n for n, _ in flagged.figures] == ["fleet_a.png"]
    assert failed.title == "Fleet: files that failed (1)" and failed.tables[0][1][1] == ["b", "2026-02-01", "f4", "bad header"]
    assert [c for c, _ in main.tables] == []


def test_all_kinds_on_one_page(files, study, fleet, tmp_path):
    rep = Report("all")
    for p in (files / "static.json", files / "lugre.json", files / "traces.csv", study / "study.parquet",
              fleet / "fleet.parquet"):
        rep.add_file(p)
    page = rep.write(tmp_path).read_text(encoding="utf-8")
    assert_self_contained(page)
    assert page.count("<section") == 6 and "<nav>" in page  # the fleet: numbers, then its failed files
    assert [i["kind"] for i in rep.to_dict()["inputs"]] == ["identification", "model", "traces", "study", "fleet"]
