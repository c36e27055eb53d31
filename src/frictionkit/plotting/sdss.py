"""Figures of the seed 002 (SDSS telescope) reproduction: analogues of Figs. 3, 4a–c, 6a–b, 7, 8."""

from __future__ import annotations

import numpy as np


def _map_panel(ax, law, pts, title, vmax, screen=None):
    vv = np.linspace(-vmax, vmax, 1201)
    if pts is not None:
        keep = np.ones(np.size(pts["v"]), bool) if screen is None else screen.accepted
        v, F = np.asarray(pts["v"]), np.asarray(pts["F"])
        ax.plot(v[keep], F[keep], "k*", ms=5, label="data (run means)")
        if not keep.all():
            ax.plot(v[~keep], F[~keep], "rx", ms=7,
                    label=f"rejected: ripple > {screen.max_ripple_percent:g} % (not fitted)")
    ax.plot(vv, law.steady_state(vv), "-", lw=1.2, label="model")
    ax.set_xlabel("ω [rad/s]")
    ax.set_ylabel("T_f [N·m]")
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=7)  # 'best': "upper left" (the empty quadrant) is too narrow on a symlog axis


def _velocity_panel(ax, run, model, inertia, title):
    from ..identify.two_step import simulate_run

    t = run["t"]
    ax.plot(t, run["v"] * 206264.806, "k.", ms=2, label="measured")
    ax.plot(t, simulate_run(model, run, inertia) * 206264.806, "-", lw=1.0, label="model")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("ω [arcsec/s]")
    ax2 = ax.twinx()
    ax2.plot(t, run["F"] - run["load"], color="0.7", lw=0.8, label="input torque − G (right axis)")
    ax2.set_ylabel("input torque − G [N·m]", color="0.5", fontsize=7)
    ax.set_title(title, fontsize=9)
    # no legend here: the runs fill their panels (an 'upper left' one hid the first peak); one figure
    # legend above the grid names the three traces (reproduction_figure)
    return [*ax.get_lines(), *ax2.get_lines()]


def reproduction_figure(rep):
    """One 3×3 figure; returns ``(fig, axes)``."""
    import matplotlib.pyplot as plt

    fig, axs = plt.subplots(3, 3, figsize=(15, 11))
    traces = []
    az, alt, rot = rep.axes["azimuth"], rep.axes["altitude"], rep.axes["rotator"]
    if az.fit is not None and az.fit.model is not None:
        _map_panel(axs[0, 0], az.fit.model.static, az.steady, "Fig. 3 analogue: azimuth static map (eq. 10)",
                   float(np.max(np.abs(az.steady["v"]))), az.extra.get("screen"))
        axs[0, 0].set_xscale("symlog", linthresh=1e-4)
        for ax, k, ttl in ((axs[0, 1], "fig4a_triangle", "Fig. 4a: azimuth, triangle below breakaway"),
                           (axs[0, 2], "fig4b_sine", "Fig. 4b: azimuth, sine below breakaway"),
                           (axs[1, 0], "fig4c_above", "Fig. 4c: azimuth, slightly above breakaway")):
            traces = _velocity_panel(ax, az.runs[k], az.fit.model, az.fit.inertia,
                                     f"{ttl} (NRMSE {az.nrmse.get(k, float('nan')):.2f} %)")
    if alt.fit is not None and alt.fit.model is not None:
        for ax, k, ttl in ((axs[1, 1], "fig6a_triangle", "Fig. 6a: altitude, triangle below breakaway"),
                           (axs[1, 2], "fig6b_above", "Fig. 6b: altitude, slightly above breakaway")):
            traces = _velocity_panel(ax, alt.runs[k], alt.fit.model, alt.fit.inertia,
                                     f"{ttl} (NRMSE {alt.nrmse.get(k, float('nan')):.2f} %)")
        _map_panel(axs[2, 0], alt.fit.model.static, None, "Fig. 7: altitude static curve (computed)", 0.01)
    res = rot.extra.get("static_result")
    if res is not None and res.model is not None:
        _map_panel(axs[2, 1], res.model, rot.steady, "Fig. 8 analogue: rotator static map (eq. 13b)",
                   float(np.max(np.abs(rot.steady["v"]))), rot.extra.get("screen"))
        axs[2, 1].set_xscale("symlog", linthresh=1e-4)
    ax = axs[2, 2]
    trk = rep.tracking
    ax.bar(["PID, no\ncompensation", "PID + LuGre\nfeed-forward"],
           [trk["no_compensation"], trk["lugre_feedforward"]], color=["C3", "C2"])
    ax.set_ylabel("RMS tracking error [arcsec]")
    ax.set_title("Extension (ours): azimuth at sidereal rate", fontsize=9)
    fig.suptitle("Seed 002, SDSS 2.5 m telescope: simulated reproduction" + (" (quick)" if rep.quick else ""))
    if traces:
        fig.legend(traces, [ln.get_label() for ln in traces], loc="upper center", bbox_to_anchor=(0.5, 0.965),
                   ncols=3, fontsize=9, frameon=False, title="Figs. 4 and 6:", title_fontsize=9,
                   alignment="left")
    fig.tight_layout(rect=(0.0, 0.0, 1.0, 0.94 if traces else 0.97))
    return fig, axs
