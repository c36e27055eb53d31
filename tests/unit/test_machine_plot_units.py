"""A machine run plots positions, velocities and site forces on one time axis, and every site force
carries its own unit (N along a length, N·m about an angle) in the plot, the traces and the summary.

Was (the new-user walk of 2026-11-23): ``MachineResult.plot`` drew the positions only, and every site
force was labelled ``[N|N·m]``.
"""

from __future__ import annotations

import numpy as np
import pytest

import frictionkit as fk
from frictionkit.errors import ParameterError
from frictionkit.simulation.traces import machine_trace_table

R = 0.005 / (2 * np.pi)  # a 5 mm lead [m/rad]


def _machine():
    m = fk.Machine("motor and table")
    th = m.dof("motor", inertia=1e-4, kind="rotational")
    x = m.dof("table", inertia=5.0)
    m.spring(R * th, x, k=1e7, c=1e3, name="screw")
    m.friction("bearing", th, law=fk.CoulombViscous(Fc=0.02, sigma2=1e-4))      # about the motor axis: N·m
    m.friction("nut", R * th - x, law=fk.CoulombViscous(Fc=3.0, sigma2=10.0))   # along the screw: N
    m.friction("guide", x, law=fk.CoulombViscous(Fc=5.0, sigma2=20.0))          # N
    m.actuator("drive", th)
    return m


@pytest.fixture(scope="module")
def run():
    t = np.arange(401) * 1e-3
    return fk.simulate_machine(_machine(), dt=1e-3, inputs={"drive": 0.3 * np.sin(2 * np.pi * 2.0 * t)})


def test_site_units_inferred_and_given():
    m = _machine()
    assert [s.unit for s in m.sites] == ["N·m", "N", "N"]
    th1 = m.dof("screw2", inertia=1e-4, kind="rotational")
    th2 = m.dof("nut2", inertia=1e-4, kind="rotational")
    m.friction("coupling", th1 - th2, law=fk.CoulombViscous(Fc=0.01, sigma2=0.0))        # angle difference
    m.friction("ball", R * (th1 + th2), law=fk.CoulombViscous(Fc=1.0, sigma2=0.0))       # seed 000's R(θ1 + θ2)
    m.friction("gear", th1 / 50.0, law=fk.CoulombViscous(Fc=0.5, sigma2=0.0), unit="N·m")  # a geared angle
    assert [s.unit for s in m.sites[3:]] == ["N·m", "N", "N·m"]
    with pytest.raises(ParameterError, match=r"Machine.friction\('bad'\).unit = 'Nm': must be one of"):
        m.friction("bad", th1, law=fk.CoulombViscous(Fc=0.5, sigma2=0.0), unit="Nm")
    back = fk.Machine.from_dict(m.to_dict())
    assert [s.unit for s in back.sites] == ["N·m", "N", "N", "N·m", "N", "N·m"]
    d = m.to_dict()
    for s in d["sites"]:  # a file written before the unit existed infers it again
        s.pop("unit")
    assert [s.unit for s in fk.Machine.from_dict(d).sites] == ["N·m", "N", "N", "N·m", "N", "N"]


def test_traces_and_summary_carry_each_sites_unit(run):
    cols = [c for c in machine_trace_table(run) if c.startswith("force.")]
    assert cols == ["force.bearing [N·m]", "force.nut [N]", "force.guide [N]"]
    text = run.summary()
    assert "bearing: max |F| = " in text and text.split("bearing: max |F| = ")[1].split("\n")[0].endswith(" N·m")
    assert text.split("guide: max |F| = ")[1].split("\n")[0].endswith(" N")


def _shown(y, unit):
    """The display unit and factor of a length or speed: µ below 1e-3, m(illi) below 1 (the rule written out)."""
    pk = np.max(np.abs(y))
    return (f"µ{unit}", 1e6) if pk < 1e-3 else (f"m{unit}", 1e3) if pk < 1.0 else (unit, 1.0)


def test_plot_has_positions_velocities_and_forces_on_one_time_axis(run):
    import matplotlib.pyplot as plt

    (xu, _), (vu, vk) = _shown(run.position("table"), "m"), _shown(run.velocity("table"), "m/s")
    assert (xu, vu) == ("mm", "mm/s")  # this run's table moves mm at mm/s: both panels rescaled
    axes = run.plot()
    try:
        assert [a.get_ylabel() for a in axes] == ["position\n[rad]", f"position\n[{xu}]", "velocity\n[rad/s]",
                                                  f"velocity\n[{vu}]", "site torque\n[N·m]", "site force\n[N]",
                                                  "actuator torque\n[N·m]"]
        assert all(a.get_shared_x_axes().joined(axes[0], a) for a in axes)
        assert axes[-1].get_xlabel() == "time [s]"
        # each panel draws the samples it names: the table's velocity, the nut's and guide's forces
        np.testing.assert_allclose(axes[3].lines[0].get_ydata(), vk * run.velocity("table"), rtol=1e-15)
        assert [ln.get_label() for ln in axes[5].lines] == ["nut", "guide"]
        np.testing.assert_array_equal(axes[5].lines[1].get_ydata(), run.force("guide"))
        fig = axes[0].figure
        fig.canvas.draw()
        for a in axes:  # legends right of the data, never over it
            assert a.get_legend().get_window_extent().x0 >= a.get_window_extent().x1
    finally:
        plt.close(axes[0].figure)
    fig, ax = plt.subplots()
    try:
        assert run.plot(ax=ax) is ax and ax.get_ylabel() == "position\n[rad]"
    finally:
        plt.close(fig)


def test_report_reads_machine_traces(run, tmp_path, monkeypatch):
    """``simulate MACHINE.json --out traces.csv`` becomes a report section (it was refused as 'a table of no
    kind' while the refusal of a machine file said to report exactly these traces)."""
    import matplotlib.pyplot as plt

    from frictionkit.report import adapters
    from frictionkit.simulation.traces import write_traces

    figs = []
    monkeypatch.setattr(adapters, "figure_png", lambda fig: figs.append(fig) or b"")
    kind, (sec,) = adapters.sections_from_file(write_traces(run, tmp_path / "traces.csv"))
    try:
        assert kind == "machine-traces" and "2 degree(s) of freedom" in sec.title
        axes = figs[0].axes
        assert [a.get_ylabel() for a in axes] == ["position\n[rad]", "position\n[mm]", "velocity\n[rad/s]",
                                                  "velocity\n[mm/s]", "site torque\n[N·m]", "site force\n[N]"]
        np.testing.assert_allclose(axes[5].lines[0].get_ydata(), run.force("nut"), rtol=1e-15)
    finally:
        plt.close("all")
