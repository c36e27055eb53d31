"""``simulate MACHINE.json --json``: a run on a fast path (steps chosen by its own error control) wrote
``"substeps": 0``, read as a run without steps; it is null there, with the kernel that ran (README walk, walk3:
the EMPS machine file of README "Machine files")."""

from __future__ import annotations

import json

from typer.testing import CliRunner

import frictionkit as fk
from frictionkit.cli import _register, app

_register()


def _run(tmp_path, machine):
    path = fk.save_model(machine, tmp_path / "m.json")
    res = CliRunner().invoke(app, ["simulate", str(path), "--input", "u=2", "--dt", "1e-3", "--duration", "0.05",
                                   "--json", "-"])
    assert res.exit_code == 0, res.output
    return json.loads(res.stdout)


def test_fast_path_run_has_no_substep_count(tmp_path):
    m = fk.Machine("slider")   # 1 kg on a 1 N Coulomb contact, pushed by 2 N: the one-DOF axis kernel
    x = m.dof("x", inertia=1.0)
    m.friction("contact", x, law=fk.CoulombViscous(Fc=1.0))
    m.actuator("push", x, command="u")
    doc = _run(tmp_path, m)
    assert doc["substeps"] is None and doc["kernel"].startswith("axis")

