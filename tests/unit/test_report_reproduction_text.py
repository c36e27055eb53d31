"""Reproduction sections read cleanly: an axis without a status has no '(status ?: )', a long status
message is cut after a whole item and says where the rest is (the walk of 2026-11-24)."""

from __future__ import annotations

from frictionkit.report.adapters import MESSAGE_CHARS, _clip, sdss_sections


def test_axis_without_status_has_a_plain_title(monkeypatch):
    from frictionkit.report import adapters

    monkeypatch.setattr(adapters, "figure_png", lambda fig: b"")
    p = {"value": 1.0, "ci95": [0.9, 1.1]}
    doc = {"paper": "seed 002", "seed": 0, "axes": {
        "azimuth": {"truth": {"Fc": 1.0}, "identified": {"Fc": p}, "status": 0, "message": "ok"},
        "rotator": {"truth": {"Fc": 1.0}, "identified": {"Fc": p}}}}
    titles = [t for t, _ in sdss_sections(doc)[0].tables]
    assert titles == ["azimuth (status 0: ok)", "rotator"]


def test_long_message_cut_after_a_whole_item():
    items = [f"flag {i}: parameter p{i} not identifiable" for i in range(40)]
    msg = "; ".join(items)
    out = _clip(msg)
    kept = out.split("; … (")[0]
    assert len(kept) <= MESSAGE_CHARS and kept.split("; ") == items[:len(kept.split("; "))]
    assert out.endswith(f"({len(msg) - len(kept)} more characters: the JSON's \"message\")")
    assert _clip("short; message") == "short; message"
