"""Helpers shared by the robustness tests (imported by name: the test folders have no __init__.py)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

import frictionkit as fk

LAW = fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, delta=2.0, sigma2=0.4)
DT = 1e-3
STATIC_ARGS = ["--time", "t_s", "--velocity", "v_ms", "--force", "F_N", "--model", "coulomb_viscous"]  # fast fit
PRESLIDING_ARGS = ["--time", "t_s", "--position", "x_m", "--force", "F_N", "--elements", "3"]


def write_csv(path: Path, **cols) -> Path:
    names = list(cols)
    arr = np.column_stack([cols[n] for n in names])
    np.savetxt(path, arr, delimiter=",", header=",".join(names), comments="", fmt="%.17g")
    return path


def stderr_of(res) -> str:
    try:
        return res.stderr
    except ValueError:  # older click mixes the streams
        return res.output


def one_error_line(res) -> str:
    """The single ``error: ...`` line on stderr (asserts there is exactly one and no traceback)."""
    err = stderr_of(res).strip()
    assert "Traceback" not in err, err
    assert len(err.splitlines()) == 1, err
    assert err.startswith("error: "), err
    return err
