"""Plots of simulation results (matplotlib imported inside the functions)."""

from __future__ import annotations

import numpy as np


def plot_result(res, ax=None):
    """Hysteresis (F over x, in µm up to 2 mm of travel, else mm) and F over time. Returns the two axes."""
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(1, 2, figsize=(10, 3.8), layout="constrained")
    ax = np.atleast_1d(ax)
    dx = res.x - res.x[0]
    span = float(np.nanmax(np.abs(dx), initial=0.0))
    # a gross-sliding run (the README's 0.23 m) read "200000" on a µm axis
    scale, unit = (1e6, "µm") if span <= 2e-3 else (1e3, "mm")
    ax[0].plot(dx * scale, res.friction, lw=1.0)
    ax[0].set_xlabel(f"displacement [{unit}]")
    ax[0].set_ylabel("friction force [N]")
    ax[0].set_title("force–displacement")
    if ax.size > 1:
        ax[1].plot(res.t, res.friction, lw=1.0)
        ax[1].set_xlabel("time [s]")
        ax[1].set_ylabel("friction force [N]")
        ax[1].set_title("force over time")
    for a in ax:
        a.grid(True, alpha=0.3)
    return ax
