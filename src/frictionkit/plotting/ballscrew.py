"""Plots for the ball-screw reproduction (seed 001 Figs. 5, 10 and 15, Table 2's redesigned
stop). matplotlib is imported inside the functions; each takes ``ax=`` and returns it."""

from __future__ import annotations

import numpy as np


def _ax(ax):
    if ax is None:
        import matplotlib.pyplot as plt

        _, ax = plt.subplots()
    return ax


def plot_reversal_errors(table3_result, *, crossing: int = 0, span=(-0.05, 0.10), ax=None):
    """Fig. 15-like: tracking error [µm] around one reversal for each compensator."""
    ax = _ax(ax)
    rev = [c for c in table3_result.crossings if c.reverse]
    c = rev[crossing]
    for law, res in table3_result.runs.items():
        sel = (res.t >= c.t0 + span[0]) & (res.t <= c.t0 + span[1])
        ax.plot((res.t[sel] - c.t0) * 1e3, res.error[sel] * 1e6,
                label=f"{law} (max {table3_result.max_error_um[law]:.2f} µm)")
    ax.axvline(0.0, color="0.5", lw=0.8)
    ax.set_xlabel("time from reversal [ms]")
    ax.set_ylabel("tracking error [µm]")
    ax.legend(loc="lower right", fontsize="small")  # was centred over the error dip after the reversal
    ax.grid(True, alpha=0.3)
    return ax


def plot_compensation(table3_result, *, crossing: int = 0, span=(-0.02, 0.02), ax=None):
    """Compensation torques ``u_f`` [N·m] around one reversal (seed 001 Figs. 11, 14)."""
    ax = _ax(ax)
    rev = [c for c in table3_result.crossings if c.reverse]
    c = rev[crossing]
    falls = True
    for law, res in table3_result.runs.items():
        sel = (res.t >= c.t0 + span[0]) & (res.t <= c.t0 + span[1])
        ax.plot((res.t[sel] - c.t0) * 1e3, res.u_f[sel], label=law)
        if sel.any():
            falls = bool(res.u_f[sel][0] >= res.u_f[sel][-1])
    ax.set_xlabel("time from reversal [ms]")
    ax.set_ylabel("u_f [N·m]")
    # the laws step from one level to the other: the corner they leave empty (upper right covered sinc's ramp)
    ax.legend(loc="lower left" if falls else "upper left")
    ax.grid(True, alpha=0.3)
    return ax


def plot_deformation_ratio(fig10_result, case: str, *, after: float = 0.03, ax=None):
    """Fig. 10-like: ``l_d / R - 1`` [%] through one zero-speed case."""
    ax = _ax(ax)
    d = fig10_result.ratios[case]
    c = fig10_result.crossings[case][0]
    t0 = fig10_result.decel_start[case]
    sel = (d.t >= t0 - 0.05) & (d.t <= c.t0 + after)
    ax.plot(d.t[sel] - c.t0, (d.ratio[sel] - 1.0) * 100.0, label="l_d / R - 1")
    ax.axvline(0.0, color="k", lw=0.8)
    ax.axvspan(t0 - c.t0, 0.0, color="0.9", label="deceleration")
    ax.set_title(case.replace("_", " "))
    ax.set_xlabel("time from zero speed [s]")
    ax.set_ylabel("l_d / R - 1 [%]")
    ax.set_ylim(-3, 3)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="lower left", fontsize="small")
    return ax


def _around(runs, crossings, span):
    for key, res in runs.items():
        c = crossings[key][0]
        sel = (res.t >= c.t0 + span[0]) & (res.t <= c.t0 + span[1])
        yield key, res, sel, c


def plot_fig5(fig5_result, *, span=(-0.06, 0.08), signal: str = "error", ax=None):
    """Fig. 5-like: conventional (sinc) compensation after a slow and a fast deceleration —
    tracking error [µm] (``signal="error"``) or motor current [A] (``"input"``) against the
    time from zero speed."""
    ax = _ax(ax)
    for case, res, sel, c in _around(fig5_result.runs, fig5_result.crossings, span):
        x = (res.t[sel] - c.t0) * 1e3
        if signal == "error":
            ax.plot(x, res.error[sel] * 1e6, label=f"{case.replace('_', ' ')} (max {fig5_result.max_error_um[case]:.2f} µm)")
        else:
            lead = fig5_result.leads_ms[case]["motor_input"]
            ax.plot(x, res.i[sel], label=f"{case.replace('_', ' ')} (turns {'never' if lead is None else f'{lead:.0f} ms'} "
                                         "before zero speed)")
    ax.axvline(0.0, color="0.5", lw=0.8)
    if signal != "error":
        ax.axhline(0.0, color="0.5", lw=0.8)
    ax.set_xlabel("time from zero speed [ms]")
    ax.set_ylabel("tracking error [µm]" if signal == "error" else "motor current [A]")
    ax.set_title("Fig. 5: sinc compensation, slow vs fast deceleration")
    ax.legend(fontsize="small")
    ax.grid(True, alpha=0.3)
    return ax


#: Extra room above the drive-force traces of :func:`plot_redesign`, as a fraction of their range: the legend's
#: two lines sit there (without it they covered the original stop's ringing after zero speed).
LEGEND_HEADROOM = 0.3


def plot_redesign(redesign_result, *, span=(-0.13, 0.08), signal: str = "error", ax=None):
    """Table 2, fast non-reverse: the original fast stop against the redesigned Pattern I stop —
    tracking error [µm] (``signal="error"``) or drive force ``F_bn`` [N] (``"drive_force"``)."""
    ax = _ax(ax)
    for key, res, sel, c in _around(redesign_result.runs, redesign_result.crossings, span):
        x = (res.t[sel] - c.t0) * 1e3
        if signal == "error":
            ax.plot(x, res.error[sel] * 1e6, label=f"{key} stop, {redesign_result.stop_ms[key]:.0f} ms "
                                                   f"(max {redesign_result.max_error_um[key]:.2f} µm)")
        else:
            # the same stop names as the error panel beside it, with the kind Table 2's rule gives each
            # stop (it read 'original (fast non reverse)' beside 'original stop, 51 ms')
            ax.plot(x, res.drive_force[sel], label=f"{key} stop, {redesign_result.stop_ms[key]:.0f} ms: "
                                                   f"{redesign_result.kind[key].replace('_', ' ')}")
    ax.axvline(0.0, color="0.5", lw=0.8)
    if signal != "error":
        ax.axhline(0.0, color="0.5", lw=0.8)
    ax.set_xlabel("time from zero speed [ms]")
    ax.set_ylabel("tracking error [µm]" if signal == "error" else "drive force F_bn [N]")
    ax.set_title("Table 2, fast non-reverse: redesigned stop")
    if signal != "error":  # the force fills its axes (600 N held, ringing after the stop): headroom for the legend
        lo, hi = ax.get_ylim()
        ax.set_ylim(lo, hi + LEGEND_HEADROOM * (hi - lo))
    ax.legend(fontsize="small", loc="upper left")
    ax.grid(True, alpha=0.3)
    return ax


def reproduction_figure(result):
    """One figure with Fig. 15 (errors, compensation), the four Fig. 10 panels, Fig. 5 and
    Table 2's redesigned fast non-reverse stop (when the result has them)."""
    import matplotlib.pyplot as plt

    extra = result.fig5 is not None and result.redesign is not None
    rows = 5 if extra else 3
    fig, axes = plt.subplots(rows, 2, figsize=(11, 3.7 * rows))
    plot_reversal_errors(result.table3, ax=axes[0, 0])
    plot_compensation(result.table3, ax=axes[0, 1])
    axes[0, 0].set_title("Table 3: tracking error around the reversal")
    axes[0, 1].set_title("compensation u_f around the reversal")
    for ax, case in zip(axes[1:3].ravel(), ("slow_reverse", "fast_reverse", "slow_non_reverse", "fast_non_reverse")):
        plot_deformation_ratio(result.fig10, case, ax=ax)
    if extra:
        plot_fig5(result.fig5, ax=axes[3, 0])
        plot_fig5(result.fig5, signal="input", ax=axes[3, 1])
        plot_redesign(result.redesign, ax=axes[4, 0])
        plot_redesign(result.redesign, signal="drive_force", ax=axes[4, 1])
    fig.suptitle(f"Zhu & Fujimoto (seed 001) on the simulated elastic stage (stage {result.stage!r})")
    fig.tight_layout(rect=(0, 0, 1, 1 - 0.4 / fig.get_figheight()))  # room for the suptitle (it sat on row 1)
    return fig, np.asarray(axes)
