"""The fleet section of ``make demo``: a simulated fleet identified, monitored and its fleet page
linked from the demo report (run here on a 2-axis fleet to stay fast)."""

from __future__ import annotations

import frictionkit.report.demo as demo


def test_demo_fleet_section_writes_and_links_the_fleet_page(tmp_path, monkeypatch):
    monkeypatch.setattr(demo, "FLEET_DEMO", {**demo.FLEET_DEMO, "axes": 2, "days": 2, "drifting": 0.5})
    sec = demo.section_fleet(tmp_path)
    page = (tmp_path / "fleet.html").read_text(encoding="utf-8")
    assert "fleet report" in page and "Files that failed (1)" in page
    assert (tmp_path / "fleet_results.parquet").is_file() and not (tmp_path / "fleet_results.parquet.parts").exists()
    assert [r[0] for r in sec.table[1:]] == ["axis-0001", "axis-0002"]
    assert "3 logs" in sec.text[0] and "1 broken file" in sec.text[0]  # 2 x 2 files, one broken
    html = demo._render([sec], 1.0)
    assert "<a href='fleet.html'>" in html and "<a href='fleet_results.parquet'>" in html
