"""``frictionkit models``: laws from the registry and presets from frictionkit.presets, with sources."""

from __future__ import annotations

import json
from dataclasses import dataclass

from typer.testing import CliRunner

from frictionkit.cli import _register, app
from frictionkit.models import register_law, registered_laws, unregister_law

_register()
runner = CliRunner()


def test_text_lists_laws_presets_and_sources():
    res = runner.invoke(app, ["models"])
    assert res.exit_code == 0, res.output
    out = res.stdout
    for name in registered_laws():
        assert f"  {name} " in out
    # sources as the README's law table gives them
    assert "LuGre" in out and "seed 002 eqs. 5-8" in out
    assert "generalized Maxwell-slip: seed 000 eqs. 1-3, 6, 9" in out
    assert "sigma0 [N/m], sigma1 [N·s/m]" in out  # units in brackets are printed as written
    # the presets shipped today, their builders and where their numbers come from
    assert "emps_machine" in out and "Janot, M. Gautier and M. Brunot" in out
    assert "ballscrew_machine" in out and "Zhu & Fujimoto" in out
    # the reversal compensation laws of the README's table, seed 001 eqs. 5-7
    assert "sigmoid_compensation   (x, F0, sigma)" in out and "Seed 001 eq. 5" in out
    assert "sinc_compensation" in out and "coulomb_compensation" in out


def test_json_on_stdout_and_to_a_file(tmp_path):
    res = runner.invoke(app, ["models", "--json", "-"])
    assert res.exit_code == 0, res.output
    doc = json.loads(res.stdout)
    laws = {law["name"]: law for law in doc["laws"]}
    assert set(laws) == set(registered_laws())
    assert laws["Stribeck"]["family"] == "static"
    assert laws["GMS"]["fields"] == {"static": "", "k": "N/m", "xi": "-", "C": "N/s"}
    presets = {p["name"]: p for p in doc["presets"]}
    assert {"emps", "ballscrew", "zhu_fujimoto"} <= set(presets)
    assert presets["emps"]["module"] == "frictionkit.presets.emps"
    assert doc["status"] == 0 and doc["errors"] == {}
    out = tmp_path / "models.json"
    res = runner.invoke(app, ["models", "--json", str(out)])
    assert res.exit_code == 0 and f"wrote {out}" in res.stdout
    assert json.loads(out.read_text(encoding="utf-8"))["laws"] == doc["laws"]


@dataclass(frozen=True, kw_only=True)
class _Plugin:
    """A law registered by a plug-in, without an entry in LAW_SOURCES."""

    Fc: float

    def steady_state(self, v):
        return self.Fc


def test_a_law_registered_later_is_listed_with_a_fallback_source():
    register_law("PluginLaw", _Plugin, "static")
    try:
        doc = json.loads(runner.invoke(app, ["models", "--json", "-"]).stdout)
    finally:
        unregister_law("PluginLaw")
    law = next(law for law in doc["laws"] if law["name"] == "PluginLaw")
    assert law["fields"] == {"Fc": "N"}
    assert law["source"].startswith("``frictionkit models``")  # this test module's docstring


def test_bad_json_target_is_one_line_error(tmp_path):
    res = runner.invoke(app, ["models", "--json", str(tmp_path / "no" / "such" / "dir" / "m.json")])
    assert res.exit_code == 2
    err = res.stderr.strip()
    assert err.startswith("error: --json") and "\n" not in err, err


def test_help_has_an_example():
    res = runner.invoke(app, ["models", "--help"])
    assert res.exit_code == 0 and "frictionkit models --json -" in res.stdout
