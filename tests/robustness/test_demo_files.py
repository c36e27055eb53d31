"""``frictionkit demo``: sections left out for missing data are said so; files are written atomically."""

from __future__ import annotations

import frictionkit.report.demo as demo
from frictionkit.cli import app


def _fast_sections(monkeypatch):
    def tiny(title):
        return lambda *a, **k: demo._Section(title, text=["ok"], figures=[(f"{title}.png", b"\x89PNG fake")])

    monkeypatch.setattr(demo, "section_laws", tiny("laws"))
    monkeypatch.setattr(demo, "section_parity", tiny("parity"))
    monkeypatch.setattr(demo, "section_zhu_fujimoto", tiny("zf"))
    monkeypatch.setattr(demo, "section_fleet", tiny("fleet"))


def test_missing_real_data_is_reported(tmp_path, monkeypatch):
    _fast_sections(monkeypatch)
    missing = tmp_path / "no-shared-data"
    res = demo.run_demo(tmp_path / "out", shared=missing)
    assert res["skipped"] == [f"EMPS identification: left out, its data were not found under '{missing}'",
                              f"screw-drive static maps: left out, its data were not found under '{missing}'"]
    summary = (tmp_path / "out" / "summary.txt").read_text(encoding="utf-8")
    assert "== Left out" in summary and "EMPS identification: left out" in summary
    assert "Left out" in (tmp_path / "out" / "report.html").read_text(encoding="utf-8")
    assert not [p for p in (tmp_path / "out").iterdir() if p.name.endswith(".tmp")]


def test_cli_warns_about_left_out_sections(runner, tmp_path, monkeypatch):
    _fast_sections(monkeypatch)
    real = demo.run_demo
    monkeypatch.setattr(demo, "run_demo", lambda out, **k: real(out, shared=tmp_path / "none", **k))
    res = runner.invoke(app, ["demo", "--out", str(tmp_path / "out")])
    assert res.exit_code == 0, res.output
    assert "warning: EMPS identification: left out" in res.stderr
    assert "wrote" in res.stdout
