"""A simulation's samples as a table, written to CSV or Parquet (atomically).

Columns, with the unit in the name: ``t [s]``, ``x [m]``, ``v [m/s]``, ``friction [N]`` (the
friction force), then the friction states — ``z [m]`` (LuGre, Dahl) or ``friction_1 [N]`` ...
``friction_M [N]`` and ``stick_1`` ... ``stick_M`` (GMS elements; 1 sticking, 0 slipping).
Rotary axes pass ``units={"F": "N·m", "v": "rad/s"}`` (labels only; the numbers are SI; ``"F"``
is the force unit's key, as in model files).

Older files (before the 2026-11-23 rename, README conventions) named the friction column ``F [N]`` (GMS
elements ``F_1 [N]`` ...) and a machine's site forces ``F.<site> [N|N·m]`` (now ``force.<site> [N]`` or
``[N·m]``, each site's own unit); ``frictionkit report``
reads a single-axis trace file in either spelling, and a machine's (positions, velocities, site forces).
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import DataError

__all__ = ["RUN_FORMAT", "TRACE_FORMATS", "machine_trace_table", "site_units", "trace_table", "write_traces"]

#: File formats of :func:`write_traces`, by suffix.
TRACE_FORMATS = {".csv": "csv", ".parquet": "parquet", ".pq": "parquet"}
#: ``"format"`` of the ``--json`` summary of ``frictionkit simulate`` (a law's or a machine's run);
#: the report reads the traces that summary names (``outputs.traces``), not the summary.
RUN_FORMAT = "frictionkit.simulation/1"


def trace_table(result: Any, *, units: Mapping[str, str] | None = None) -> dict[str, np.ndarray]:
    """``{column name with unit: samples}`` of a :class:`~frictionkit.SimulationResult`, labelled in
    ``units`` (default the run's own, ``simulate(units=)``).

    Examples
    --------
    >>> import numpy as np, frictionkit as fk
    >>> from frictionkit.simulation.traces import trace_table
    >>> law = fk.Dahl(Fc=1.0, sigma0=1e5)
    >>> res = fk.simulate(law, position=1e-5 * np.sin(np.linspace(0, 6, 61)), dt=1e-3)
    >>> list(trace_table(res))
    ['t [s]', 'x [m]', 'v [m/s]', 'friction [N]', 'z [m]']
    """
    from ..models.files import _axis_units

    if hasattr(result, "dof_names"):  # a MachineResult
        return machine_trace_table(result)
    u = _axis_units(units if units is not None else getattr(result, "units", None))
    out = {"t [s]": result.t, f"x [{u['x']}]": result.x, f"v [{u['v']}]": result.v, f"friction [{u['F']}]": result.friction}
    states = result.states or {}
    if "z" in states:
        out[f"z [{u['x']}]"] = states["z"]
    if "F_elements" in states:
        Fel = np.asarray(states["F_elements"])
        for i in range(Fel.shape[1]):
            out[f"friction_{i + 1} [{u['F']}]"] = Fel[:, i]
    if "stick" in states:
        st = np.asarray(states["stick"])
        for i in range(st.shape[1]):
            out[f"stick_{i + 1}"] = st[:, i].astype(np.int8)
    return out


def machine_trace_table(result: Any) -> dict[str, np.ndarray]:
    """``{column: samples}`` of a :class:`~frictionkit.machines.MachineResult`: ``t [s]``, per
    degree of freedom ``x.<dof> [m|rad]`` and ``v.<dof> [m/s|rad/s]``, per site ``force.<site> [N]``
    or ``[N·m]`` (the site's unit: N along a length, N·m about an angle, ``Machine.friction(unit=)``;
    files written before 2026-11-24 labelled every site ``[N|N·m]``), per actuator ``u.<actuator>`` (applied command), then every controller
    signal by its name (units as the machine's blocks define them)."""
    out = {"t [s]": result.t}
    for i, d in enumerate(result.machine.dofs):
        out[f"x.{d.name} [{d.unit}]"] = result.q[:, i]
        out[f"v.{d.name} [{d.unit}/s]"] = result.v[:, i]
    for j, (name, unit) in enumerate(zip(result.site_names, site_units(result.machine))):
        out[f"force.{name} [{unit}]"] = result.site_forces[:, j]
    for j, name in enumerate(result.actuator_names):
        out[f"u.{name}"] = result.u[:, j]
    for j, name in enumerate(result.signal_names):
        out.setdefault(name, result.signals[:, j])
    return out


def site_units(machine: Any) -> list[str]:
    """The force unit of each site of ``machine`` — a :class:`~frictionkit.Machine` or a run of it
    (``MachineResult``, in the order of its ``site_names``) — ``"N"`` or ``"N·m"``.

    Examples
    --------
    >>> import frictionkit as fk
    >>> from frictionkit.simulation.traces import site_units
    >>> m = fk.Machine("axis")
    >>> th = m.dof("motor", inertia=1e-4, kind="rotational")
    >>> m.friction("bearing", th, law=fk.CoulombViscous(Fc=0.02, sigma2=0.0))
    >>> site_units(m)
    ['N·m']
    """
    machine = getattr(machine, "machine", machine)  # a MachineResult: its machine's sites
    return [getattr(s, "unit", "N") for s in machine.sites]


def write_traces(result: Any, path: str | Path, *, units: Mapping[str, str] | None = None) -> Path:
    """Write :func:`trace_table` to ``path`` (``.csv`` or ``.parquet``), atomically; returns the path.

    CSV numbers carry 17 significant digits, so the file reads back exactly.
    """
    from .._io import atomic_open

    p = Path(path)
    kind = TRACE_FORMATS.get(p.suffix.lower())
    if kind is None:
        raise DataError(f"traces file '{p}': unknown suffix {p.suffix!r}; use one of {', '.join(TRACE_FORMATS)}")
    table = trace_table(result, units=units)
    if kind == "parquet":
        import pandas as pd

        with atomic_open(p, "wb") as f:
            pd.DataFrame(table).to_parquet(f, index=False)
        return p
    cols = list(table)
    data = np.column_stack([np.asarray(c, dtype=float) for c in table.values()])
    fmt = ["%d" if c.startswith("stick_") else "%.17g" for c in cols]
    with atomic_open(p, "w") as f:
        f.write(",".join(cols) + "\n")
        np.savetxt(f, data, fmt=fmt, delimiter=",")
    return p
