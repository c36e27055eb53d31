"""Issue 13: a position whose float spacing swallows the motion is refused, naming the value.

Campaign round 5's reproducer: the EMPS machine file with ``dofs[0].x0 = 1e300`` ran with
status 0 (x stayed 1e300 while v reached 1.59 m/s). The same for simulate()'s x0 and for a
prescribed position carrying an offset (its velocity is its difference over dt).
"""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest
from typer.testing import CliRunner

import frictionkit as fk
from frictionkit.cli import _register, app
from frictionkit.errors import ParameterError

_register()

LAW = fk.LuGre(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4), sigma0=1e5, sigma1=300.0)


def test_machine_file_x0_1e300_refused(tmp_path):
    from frictionkit.presets.emps import PUBLISHED, emps_machine

    m = emps_machine(M=PUBLISHED["M"], friction=fk.CoulombViscous(Fc=PUBLISHED["Fc"], sigma2=PUBLISHED["Fv"]),
                     offset=PUBLISHED["offset"])
    path = fk.save_model(m, tmp_path / "emps.json", method="EMPS published")
    doc = json.loads(path.read_text(encoding="utf-8"))
    doc["model"]["dofs"][0]["x0"] = 1e300
    path.write_text(json.dumps(doc), encoding="utf-8")
    t = np.arange(11) * 1e-3
    ref = tmp_path / "ref.csv"
    np.savetxt(ref, np.column_stack([t, 0.01 * t]), delimiter=",", header="t,qg", comments="")
    res = CliRunner().invoke(app, ["simulate", str(path), "--input", f"qg={ref}:qg", "--out",
                                   str(tmp_path / "tr.csv")])
    assert res.exit_code not in (0, None) and isinstance(res.exception, SystemExit), res.output  # no traceback
    assert "x0 = 1e+300" in res.output and "float spacing" in res.output, res.output
    with pytest.raises(ParameterError, match=r"x0 = 1e\+300"):  # the in-Python edit is refused too
        dataclasses.replace(m.dofs[0], x0=1e300)


def test_simulate_x0_bound():
    u = np.full(101, 2.0)
    res = fk.simulate(LAW, plant=fk.Mass(1.0), force=u, dt=1e-3, x0=-1e6)  # the bound itself runs
    assert res.status == 0
    with pytest.raises(ParameterError, match=r"simulate\.x0 = 1e\+300.*float spacing"):
        fk.simulate(LAW, plant=fk.Mass(1.0), force=u, dt=1e-3, x0=1e300)


@pytest.mark.parametrize("offset, ok", [(0.0, True), (1e3, True), (1e9, False), (1e300, False)])
def test_position_offset(offset, ok):
    t = np.arange(1001) * 1e-3
    pos = offset + 1e-3 * np.sin(6.0 * t)  # largest motion per sample 6e-6 m
    if ok:
        assert fk.simulate(LAW, position=pos, dt=1e-3).status == 0
    else:  # 1e9: spacing 1.2e-7 m is 2 % of the motion per sample; 1e300 + sine is a constant
        with pytest.raises(ParameterError, match="float spacing.*subtract the offset"):
            fk.simulate(LAW, position=pos, dt=1e-3)
