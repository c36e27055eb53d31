"""``frictionkit report RESULT... -o DIR``: success, --json, bad input, never over an input,
the README's "Report" section run as written, and the page in a real headless browser."""

from __future__ import annotations

import base64
import json
import re
import shlex
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

import frictionkit as fk
from frictionkit.cli import _register, app
from frictionkit.identify import fit_static_map

_register()
runner = CliRunner()
pytestmark = pytest.mark.xdist_group("report_cli")  # module fixtures (inputs, the README run) built once
README = Path(__file__).resolve().parents[2] / "README.md"
PNG = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def inputs(tmp_path_factory):
    d = tmp_path_factory.mktemp("report_in")
    v = np.r_[np.linspace(0.01, 0.2, 12), -np.linspace(0.01, 0.2, 12)]
    fit_static_map(v, np.sign(v) * 2.0 + 10.0 * v, model="coulomb_viscous").save_json(d / "fit.json")
    fk.save_model(fk.Dahl(Fc=1.0, sigma0=1e5), d / "dahl.json", method="catalogue values")
    return d


def _srcs(page: str) -> list[str]:
    return re.findall(r"src=['\"]([^'\"]*)['\"]", page)


def test_report_success(inputs, tmp_path):
    out = tmp_path / "new" / "rep"
    res = runner.invoke(app, ["report", str(inputs / "fit.json"), str(inputs / "dahl.json"), "-o", str(out),
                              "--title", "Axis <3>"])
    assert res.exit_code == 0, res.output
    page = (out / "report.html").read_text(encoding="utf-8")
    assert res.stdout.splitlines()[-1] == f"wrote {out / 'report.html'}"
    assert "<title>Axis &lt;3&gt;</title>" in page and "Axis <3>" not in page
    assert "Static friction map: directional(coulomb_viscous, coulomb_viscous)" in page and "Friction model: Dahl" in page
    # the fit's own numbers (y = 2 sgn v + 10 v exactly) in the parameter table
    assert re.search(r"<td>Fc_pos</td><td>2</td>", page) and re.search(r"<td>sigma2_neg</td><td>10</td>", page)
    # self-contained: two embedded PNGs, nothing external
    assert "http://" not in page and "https://" not in page and "<script" not in page
    srcs = _srcs(page)
    assert len(srcs) == 2 and all(s.startswith("data:image/png;base64,") for s in srcs)
    assert all(base64.b64decode(s.split(",", 1)[1]).startswith(PNG) for s in srcs)
    assert sorted(p.name for p in out.iterdir()) == ["report.html"]


def test_report_json(inputs, tmp_path):
    res = runner.invoke(app, ["report", str(inputs / "dahl.json"), str(inputs / "fit.json"), "-o", str(tmp_path),
                              "--json", "-"])
    assert res.exit_code == 0, res.output
    doc = json.loads(res.stdout)
    assert doc["report"] == str(tmp_path / "report.html") and doc["bytes"] == (tmp_path / "report.html").stat().st_size
    assert [(i["file"], i["kind"]) for i in doc["inputs"]] == [(str(inputs / "dahl.json"), "model"),
                                                                (str(inputs / "fit.json"), "identification")]
    assert [s["figures"] for s in doc["sections"]] == [1, 1]
    res = runner.invoke(app, ["report", str(inputs / "fit.json"), "-o", str(tmp_path), "--json",
                              str(tmp_path / "summary.json")])
    assert res.exit_code == 0, res.output
    assert json.loads((tmp_path / "summary.json").read_text())["title"] == "frictionkit report"


@pytest.mark.parametrize("make, message", [
    (lambda d: d / "missing.json", "error: result file '{p}': no such file"),
    (lambda d: (d / "x.json").write_text("{oops") and d / "x.json", "error: result file '{p}': not valid JSON"),
    (lambda d: (d / "s.toml").write_text("[a]") and d / "s.toml", "error: result file '{p}': unknown file type '.toml'"),
    (lambda d: (d / "o.json").write_text('{"x": 1}') and d / "o.json",
     "error: result file '{p}': a JSON object of no kind frictionkit report reads (keys: x)"),
])
def test_bad_input_is_one_line(tmp_path, make, message):
    p = make(tmp_path)
    res = runner.invoke(app, ["report", str(p), "-o", str(tmp_path / "out")])
    assert res.exit_code == 2
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(message.format(p=p)), res.stderr
    assert not (tmp_path / "out" / "report.html").exists()


def test_machine_file_and_empty_out_are_refused_with_the_reason(tmp_path, monkeypatch):
    """Issue 13 round 3: a machine model file read as 'malformed content (ParameterError ...)';
    ``-o ''`` wrote report.html into the working folder (typer turns '' into '.')."""
    import frictionkit as fk

    m = fk.Machine("slider")
    m.friction("contact", m.dof("x", inertia=1.0), law=fk.CoulombViscous(Fc=1.0))
    path = fk.save_model(m, tmp_path / "machine.json")
    res = runner.invoke(app, ["report", str(path), "-o", str(tmp_path / "out")])
    assert res.exit_code == 2 and "a machine model file" in res.stderr and "frictionkit simulate" in res.stderr
    monkeypatch.chdir(tmp_path)
    res = runner.invoke(app, ["report", str(path), "-o", ""])
    assert res.exit_code == 2 and "-o/--out ''" in res.stderr, res.stderr
    assert not (tmp_path / "report.html").exists()


def test_a_simulate_summary_is_reported_through_its_traces(tmp_path, monkeypatch):
    """Issue 13 round 4: the --json of 'simulate' read as a law file ("law 'LuGre': unknown field
    'model'"). It carries a format now; the report follows it to the traces it names."""
    monkeypatch.chdir(tmp_path)
    law = fk.LuGre(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, delta=2.0, sigma2=0.4), sigma0=1e5, sigma1=316.0)
    fk.save_model(law, "law.json")
    t = np.arange(500) * 1e-3
    np.savetxt("f.csv", np.column_stack([t, 2 * np.sin(2 * np.pi * 2 * t)]), delimiter=",", header="t,F",
               comments="")
    res = runner.invoke(app, ["simulate", "law.json", "--force", "f.csv", "--mass", "1", "--json", "sim.json",
                              "--out", "tr.csv"])
    assert res.exit_code == 0, res.output
    doc = json.loads(Path("sim.json").read_text())
    assert doc["format"] == "frictionkit.simulation/1" and doc["outputs"]["traces"] == "tr.csv"
    res = runner.invoke(app, ["report", "sim.json", "-o", "out"])
    assert res.exit_code == 0, res.stderr
    assert "Simulated traces: 500 samples" in (tmp_path / "out" / "report.html").read_text()
    Path("tr.csv").unlink()
    res = runner.invoke(app, ["report", "sim.json", "-o", "out2"])
    assert res.exit_code == 2 and "the summary of a simulate run; its traces 'tr.csv' are not there" in res.stderr
    old = {k: v for k, v in doc.items() if k not in ("format", "outputs")}  # written before the format field
    Path("old.json").write_text(json.dumps(old))
    res = runner.invoke(app, ["report", "old.json", "-o", "out3"])
    assert res.exit_code == 2 and "without traces; run simulate with --out" in res.stderr, res.stderr


def test_refuses_to_overwrite_an_input(inputs, tmp_path):
    page = tmp_path / "report.html"
    shutil.copy(inputs / "fit.json", page)  # an identification result that happens to be called report.html
    before = page.read_bytes()
    res = runner.invoke(app, ["report", str(page), "-o", str(tmp_path)])
    assert res.exit_code == 2 and "refusing to overwrite an input" in res.stderr
    res = runner.invoke(app, ["report", str(inputs / "fit.json"), "-o", str(tmp_path / "o"), "--json",
                              str(inputs / "fit.json")])
    assert res.exit_code == 2 and "refusing to overwrite an input" in res.stderr
    res = runner.invoke(app, ["report", str(inputs / "fit.json"), "-o", str(inputs / "fit.json")])
    assert res.exit_code == 2 and "is an existing file, not a folder" in res.stderr
    assert page.read_bytes() == before


def test_help_has_an_example():
    res = runner.invoke(app, ["report", "--help"])
    assert res.exit_code == 0
    assert "frictionkit report fit.json lugre.json compensate.json -o report/" in res.stdout
    assert "[µm]" in res.stdout  # units in brackets survive the help text


def _readme_commands() -> list[str]:
    text = README.read_text(encoding="utf-8")
    start = text.index("## Report\n")
    sec = text[start:text.index("\n## ", start + 5)]
    return re.search(r"```sh\n(.*?)```", sec, re.S).group(1).strip().splitlines()


@pytest.fixture(scope="module")
def readme_page(tmp_path_factory):
    """The README's "Report" section, every command run as written in a fresh folder."""
    import os

    d = tmp_path_factory.mktemp("readme_report")
    cwd = os.getcwd()
    os.chdir(d)
    try:
        for line in _readme_commands():
            argv = shlex.split(line)
            if argv[0] == "python":
                assert argv[1] == "-c" and len(argv) == 3, line
                exec(compile(argv[2], "README.md", "exec"), {})  # noqa: S102 - the README's own one-liner
                continue
            assert argv[0] == "frictionkit", line
            res = runner.invoke(app, argv[1:])
            assert res.exit_code == 0, f"{line}\n{res.output}"
    finally:
        os.chdir(cwd)
    return d / "report" / "report.html"


def test_readme_report_section_runs_as_written(readme_page):
    page = readme_page.read_text(encoding="utf-8")
    assert "Friction model: LuGre" in page and "Compensation on the ballscrew preset" in page
    assert page.count("<img") == 2


def test_page_in_headless_chromium(readme_page, tmp_path):
    """The page loads in a real browser with no console errors, every image decodes and the tables are there.

    A probe script is added to a copy of the page (the page itself has none); it writes what it finds
    into the DOM, which ``--dump-dom`` prints after the load event. A screenshot is kept beside it.
    """
    chromium = shutil.which("chromium") or shutil.which("chromium-browser")
    if chromium is None:  # pragma: no cover - .ci/run installs it
        pytest.skip("no chromium (make test installs Debian's chromium; it could not here)")
    probe = ("<script>window.addEventListener('load', () => { const im = [...document.images];"
             "document.body.setAttribute('data-probe', im.filter(i => i.complete && i.naturalWidth > 0).length + '/'"
             " + im.length + '/' + document.querySelectorAll('table').length); });</script></body>")
    page = tmp_path / "probe.html"
    page.write_text(readme_page.read_text(encoding="utf-8").replace("</body>", probe), encoding="utf-8")
    flags = ["--headless", "--no-sandbox", "--disable-gpu", "--enable-logging=stderr", "--v=0"]
    run = subprocess.run([chromium, *flags, "--dump-dom", page.as_uri()], capture_output=True, text=True, timeout=120)
    m = re.search(r'data-probe="(\d+)/(\d+)/(\d+)"', run.stdout)
    assert m, run.stdout[:300] + run.stderr[-500:]
    ok, images, tables = map(int, m.groups())
    assert images == 2 and ok == images and tables >= 3
    assert not re.search(r"CONSOLE\(\d+\)", run.stderr), run.stderr[-800:]
    shot = readme_page.parent / "report_screenshot.png"  # the test artefact, beside the report
    subprocess.run([chromium, "--headless", "--no-sandbox", "--disable-gpu", f"--screenshot={shot}",
                    "--window-size=1200,2400", readme_page.as_uri()], capture_output=True, timeout=120)
    assert shot.read_bytes().startswith(PNG)
