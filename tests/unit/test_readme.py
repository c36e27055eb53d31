"""The README's Python example runs as written and gives what it says."""

from __future__ import annotations

import re
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

README = Path(__file__).resolve().parents[2] / "README.md"


def test_readme_example_runs():
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(), re.S)
    assert blocks, "README lost its Python example"
    ns: dict = {}
    exec(compile(blocks[0], "README.md", "exec"), ns)
    assert ns["res"].success and ns["res"].x.shape == (40001,)
    assert ns["batch"].sse.shape == (1000,) and (ns["batch"].status == 0).all()
    assert (ns["batch"].sse > 0).all() and ns["batch"].rms.max() < 0.1  # LuGre sweep vs the GMS trace [m/s]


def test_readme_error_message_is_the_real_one():
    import frictionkit as fk

    text = README.read_text()
    law = fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, delta=2.0, sigma2=0.4)
    try:
        fk.GMS(law, k=[1e4, -2.0], xi=[0.5, 0.5], C=20.0)
    except fk.ParameterError as exc:
        assert f"ParameterError: {exc}" in text
    else:  # pragma: no cover
        raise AssertionError("negative stiffness accepted")


def test_readme_machine_example_runs():
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(), re.S)
    src = next(b for b in blocks if "fk.Machine(" in b)
    ns: dict = {}
    exec(compile(src, "README.md", "exec"), ns)
    res = ns["res"]
    assert res.success and res.q.shape == (4001, 2)
    # the PID holds the table within a few micrometres of a 1 mm sine; the reversal spikes are friction
    assert 1e-7 < abs(ns["err"][200:]).max() < 1e-5
    assert abs(res.u).max() < 10.0  # the 10 A limit was not needed
