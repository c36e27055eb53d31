"""Plots of simulation results (matplotlib imported inside the functions)."""

from __future__ import annotations

import numpy as np


#: Largest travel [m] of a hysteresis axis drawn in µm; beyond it, mm (tick labels in m ran together).
MICRON_AXIS_SPAN = 2e-3


def length_display(x) -> tuple[float, str]:
    """``(factor, unit)`` of a length axis [m]: µm up to :data:`MICRON_AXIS_SPAN` of ``|x|``, else mm."""
    span = float(np.nanmax(np.abs(x), initial=0.0))
    return (1e6, "µm") if span <= MICRON_AXIS_SPAN else (1e3, "mm")


def plot_result(res, ax=None, *, units=None):
    """Hysteresis (F over x) and F over time. Returns the two axes.

    ``units`` (``{"x": ..., "F": ...}``, a model file's; default the run's own, ``simulate(units=)``) labels a
    rotary law's run in rad and N·m (it read 'displacement [µm]' and 'friction force [N]' for radians and
    newton-metres); a length is shown in µm up to 2 mm of travel, else mm.
    """
    import matplotlib.pyplot as plt

    u = {"x": "m", "F": "N", **dict((units if units is not None else getattr(res, "units", None)) or {})}
    if ax is None:
        _, ax = plt.subplots(1, 2, figsize=(10, 3.8), layout="constrained")
    ax = np.atleast_1d(ax)
    dx = res.x - res.x[0]
    # a gross-sliding run (the README's 0.23 m) read "200000" on a µm axis
    scale, unit = length_display(dx) if u["x"] == "m" else (1.0, u["x"])
    friction = f"friction {'torque' if u['F'] == 'N·m' else 'force'} [{u['F']}]"
    ax[0].plot(dx * scale, res.friction, lw=1.0)
    ax[0].set_xlabel(f"displacement [{unit}]")
    ax[0].set_ylabel(friction)
    ax[0].set_title("force–displacement")
    if ax.size > 1:
        ax[1].plot(res.t, res.friction, lw=1.0)
        ax[1].set_xlabel("time [s]")
        ax[1].set_ylabel(friction)
        ax[1].set_title("force over time")
    for a in ax:
        a.grid(True, alpha=0.3)
    return ax


#: Height of one panel of :func:`plot_machine` [in]: six panels (the elastic ball screw: positions and
#: velocities in m and rad, forces in N and N·m) then fit a report page at 8 x 10.8 in; its actuator
#: panel (motor torque [N·m]) makes seven, 12.45 in.
MACHINE_PANEL_HEIGHT = 1.65


def _machine_groups(res) -> list[tuple[str, str, list[tuple[str, np.ndarray]]]]:
    """``(quantity, unit, [(label, samples), ...])`` per panel: positions and velocities per unit (m, rad),
    then site forces per unit (N, N·m)."""
    dofs = res.machine.dofs
    groups = []
    for quantity, arr, suffix in (("position", res.q, ""), ("velocity", res.v, "/s")):
        for unit in dict.fromkeys(d.unit for d in dofs):
            lines = [(d.name, arr[:, i]) for i, d in enumerate(dofs) if d.unit == unit]
            groups.append((quantity, unit + suffix, lines))
    from ..simulation.traces import site_units

    units = site_units(res.machine)
    for unit in dict.fromkeys(units):
        lines = [(name, res.site_forces[:, j]) for j, name in enumerate(res.site_names) if units[j] == unit]
        groups.append(("site torque" if unit == "N·m" else "site force", unit, lines))
    return groups + _actuator_groups(res)


def _actuator_groups(res) -> list[tuple[str, str, list]]:
    """The actuators' panels, one per unit: each actuator's commanded force or torque ``gain * command``
    (dashed) and the applied one ``gain * u`` (after saturation and delay), so a saturated drive shows."""
    from ..machines.machine import site_unit

    acts = {a.name: a for a in getattr(res.machine, "actuators", ())}
    per_unit: dict[str, list] = {}
    for j, name in enumerate(res.actuator_names):
        act = acts.get(name)
        if act is None:
            continue
        unit = site_unit(f"actuator {name!r}", act.at, res.machine.dofs, None)
        lines = per_unit.setdefault(unit, [])
        if act.command in res.signal_names:
            lines.append((f"{name} commanded", act.gain * res.signal(act.command), "--"))
        lines.append((f"{name} applied" + (f" (limit ±{abs(act.gain) * act.limit:.3g})" if np.isfinite(act.limit)
                                            else ""), act.gain * res.u[:, j], "-"))
    return [("actuator torque" if unit == "N·m" else "actuator force", unit, lines) for unit, lines in per_unit.items()]


def trace_groups(columns) -> list[tuple[str, str, list[tuple[str, str]]]]:
    """The panels of a machine's trace table (``simulate --out``): ``(quantity, unit, [(label, column)])``
    for ``x.<dof> [u]``, ``v.<dof> [u]`` and ``force.<site> [u]`` (``F.<site>`` in older files), one
    panel per quantity and unit, in the order of :func:`plot_machine`."""
    import re

    kinds = (("x.", "position"), ("v.", "velocity"), ("force.", "site force"), ("F.", "site force"))
    groups: dict[tuple[str, str], list[tuple[str, str]]] = {}
    for c in map(str, columns):
        m = re.fullmatch(r"(x\.|v\.|force\.|F\.)(.+) \[([^\]]*)\]", c)
        if m:
            quantity = dict(kinds)[m.group(1)]
            if quantity == "site force" and m.group(3) == "N·m":
                quantity = "site torque"
            groups.setdefault((quantity, m.group(3)), []).append((m.group(2), c))
    order = {"position": 0, "velocity": 1, "site force": 2, "site torque": 2}
    return [(q, u, lines) for (q, u), lines in sorted(groups.items(), key=lambda kv: order[kv[0][0]])]


#: Display prefixes of a length (and speed) panel by its largest magnitude: a ball screw's table moves
#: by µm in the zero-speed region, and in m its axis read '1e-7' above the ticks.
_LENGTH_PREFIXES = ((1e-3, 1e6, "µ"), (1.0, 1e3, "m"))


def _display(unit: str, lines) -> tuple[float, str]:
    """``(factor, unit shown)`` of a panel: lengths and speeds in µm or mm when their peak is below 1 mm
    or 1 m (µm/s, mm/s likewise); other units as they are."""
    if unit not in ("m", "m/s"):
        return 1.0, unit
    peak = max((float(np.nanmax(np.abs(y), initial=0.0)) for _, y in lines), default=0.0)
    for below, k, prefix in _LENGTH_PREFIXES:
        if 0.0 < peak < below:
            return k, prefix + unit
    return 1.0, unit


def plot_panels(t, groups, *, title: str, ax=None):
    """Time histories, one panel per ``(quantity, unit, [(label, samples)])`` group, sharing the time
    axis, legends outside on the right, lengths and speeds in µm or mm when small (:func:`_display`);
    on a given ``ax`` the first group only. Returns the Axes (the array of them on a new figure)."""
    import matplotlib.pyplot as plt

    if ax is not None:
        groups, axes = groups[:1], np.array([ax])
    else:
        _, axes = plt.subplots(len(groups), 1, sharex=True, squeeze=False,
                               figsize=(8.0, 0.9 + MACHINE_PANEL_HEIGHT * len(groups)), layout="constrained")
        axes = axes[:, 0]
    for a, (quantity, unit, lines) in zip(axes, groups):
        factor, shown = _display(unit, lines)
        for k, (label, y, *style) in enumerate(lines):  # (label, samples[, line style])
            a.plot(t, factor * np.asarray(y, dtype=float), *style, lw=1.0, color=f"C{k % 10}", label=label)
        a.set_ylabel(f"{quantity}\n[{shown}]")
        a.grid(True, alpha=0.3)
        a.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize="small", frameon=False)
    axes[-1].set_xlabel("time [s]")
    axes[0].set_title(title, fontsize="medium")
    return axes[0] if ax is not None else axes


def plot_machine(res, ax=None):
    """A machine run over time: positions, velocities, site forces and actuator forces, one panel per
    quantity and unit.

    Parameters
    ----------
    res : MachineResult
        A run of :func:`frictionkit.simulate_machine` (or the twin's result).
    ax : matplotlib Axes, optional
        Draw only the positions (one unit: the first DOF's) on it.

    Returns
    -------
    ndarray of Axes (a new figure: one panel per quantity and unit — positions [m], [rad],
    velocities [m/s], [rad/s], site forces [N], torques [N·m], then, when the machine has actuators,
    each actuator's commanded (dashed) and applied force or torque, after saturation and delay —
    sharing the time axis, legends outside on the right) or the given Axes.
    """
    status = "ok" if res.status == 0 else f"status {res.status}"
    return plot_panels(res.t, _machine_groups(res), title=f"{res.machine.name} ({status})", ax=ax)
