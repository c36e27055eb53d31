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
