"""Plots for the ball-screw reproduction (seed 001 Figs. 10 and 15). matplotlib is imported
inside the functions; each takes ``ax=`` and returns it."""

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
    ax.legend()
    ax.grid(True, alpha=0.3)
    return ax


def plot_compensation(table3_result, *, crossing: int = 0, span=(-0.02, 0.02), ax=None):
    """Compensation torques ``u_f`` [N·m] around one reversal (seed 001 Figs. 11, 14)."""
    ax = _ax(ax)
    rev = [c for c in table3_result.crossings if c.reverse]
    c = rev[crossing]
    for law, res in table3_result.runs.items():
        sel = (res.t >= c.t0 + span[0]) & (res.t <= c.t0 + span[1])
        ax.plot((res.t[sel] - c.t0) * 1e3, res.u_f[sel], label=law)
    ax.set_xlabel("time from reversal [ms]")
    ax.set_ylabel("u_f [N·m]")
    ax.legend()
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


def reproduction_figure(result):
    """One figure with Fig. 15 (errors, compensation) and the four Fig. 10 panels."""
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(3, 2, figsize=(11, 11))
    plot_reversal_errors(result.table3, ax=axes[0, 0])
    plot_compensation(result.table3, ax=axes[0, 1])
    for ax, case in zip(axes[1:].ravel(), ("slow_reverse", "fast_reverse", "slow_non_reverse", "fast_non_reverse")):
        plot_deformation_ratio(result.fig10, case, ax=ax)
    fig.suptitle("Zhu & Fujimoto (seed 001) on the simulated elastic stage")
    fig.tight_layout()
    return fig, np.asarray(axes)
