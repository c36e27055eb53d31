"""What ``frictionkit reproduce zhang2023`` prints about its run, not only its tables (README walk, walk3).

Before: a quick run of status 1 (WSIM's identifiability flags, ~4,000 characters in the JSON's
"message" and in the report's section) printed nothing of it, and a finding that a failed fit left
unevaluated (``holds`` None, shown "NOT EVALUATED" by ``summary()``) was printed "=no". The
reproduction is a stand-in here: this is about the text.
"""

from __future__ import annotations

from types import SimpleNamespace

import pytest
from typer.testing import CliRunner

import frictionkit.cli.reproduce  # noqa: F401  (registers the command group)
from frictionkit.cli import app

#: A WSIM-style status message longer than the report's clip (400 characters), with a "[...]" that rich
#: would read as markup.
MESSAGE = "WSIM: table3: screw: positive: vs not identifiable [N·m]; " + "; ".join(
    f"item {i}: C is not determined by this record" for i in range(40))


@pytest.fixture
def stand_in(monkeypatch):
    import frictionkit.reproduce.zhang2023 as zr

    summary = {"table7": [], "table8": [], "hysteresis_rms_force_N": {}, "crawling": [], "status": 1,
               "message": MESSAGE}
    monkeypatch.setattr(zr, "run", lambda **kw: SimpleNamespace(to_dict=lambda: dict(summary)))
    monkeypatch.setattr(zr, "findings", lambda s: {"t7_diff0_wsim_better": {"holds": True},
                                                    "t7_diff6_wsim_better": {"holds": False},
                                                    "fig16_reciprocating_m7_better": {"holds": None}})


def test_zhang2023_prints_its_status_and_unevaluated_findings(stand_in, tmp_path):
    res = CliRunner().invoke(app, ["reproduce", "zhang2023", "--quick", "--json", str(tmp_path / "z.json"),
                                   "--no-plot"])
    assert res.exit_code == 0, res.output
    text = " ".join(res.stdout.split())  # rich wraps at the terminal width
    assert "t7_diff0_wsim_better=yes" in text and "t7_diff6_wsim_better=no" in text
    assert "fig16_reciprocating_m7_better=n/a (not evaluated)" in text
    assert "status 1: WSIM: table3: screw: positive: vs not identifiable [N·m]" in text
    assert "more characters: the JSON's \"message\"" in text   # clipped, and says where the rest is
    assert "item 39" not in text
