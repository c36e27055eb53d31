"""Plots of fleet results (matplotlib is imported inside the functions; each takes ``ax=``)."""

from __future__ import annotations

import numpy as np


def _unit(df, parameter: str) -> str:
    """Unit of a parameter column from the table's ``unit_F`` / ``unit_v``."""
    if not len(df) or "unit_F" not in df or "unit_v" not in df:
        return ""
    F, v = str(df["unit_F"].iloc[0]), str(df["unit_v"].iloc[0])
    name = parameter.rsplit("_", 1)[0]
    if name in ("Fc", "Fs"):
        return F
    if name == "vs":
        return v
    if name == "sigma2":
        return f"{F}·s/{v[:-2]}" if v.endswith("/s") else f"{F}/({v})"
    if name == "delta":
        from ..identify._advice import DIMENSIONLESS

        return DIMENSIONLESS
    return ""


def plot_parameter_distribution(results, parameter: str = "Fc_pos", *, period: str | None = None, ax=None):
    """Histogram of one parameter over the fleet's axes on one period (default: each axis's latest fit).

    Flagged axes (``drift_flag`` on that row) are stacked in a second colour.

    Parameters
    ----------
    results : pandas.DataFrame
        Results of :func:`~frictionkit.fleet.identify_fleet` (monitored or not).
    parameter : str
        Column to show.
    period : str, optional
        Period to show; default the latest ``ok`` row of every axis.
    ax : matplotlib Axes, optional

    Returns
    -------
    matplotlib Axes
    """
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=(5.0, 3.4))
    df = results[results["ok"].astype(bool)]
    if period is None:
        df = df.sort_values("period").groupby("axis").tail(1)
    else:
        df = df[df["period"] == period]
    vals = df[parameter].to_numpy(float)
    monitored = "drift_flag" in df
    flag = df["drift_flag"].to_numpy(bool) if monitored else np.zeros(vals.size, bool)
    fin = np.isfinite(vals)
    if fin.sum():
        bins = np.histogram_bin_edges(vals[fin], bins=min(30, max(5, int(np.sqrt(fin.sum())))))
        # counts in the legend; an unmonitored table's axes were labelled "not flagged" (README walk)
        n_ok, n_flag = int((fin & ~flag).sum()), int((fin & flag).sum())
        labels = ([f"not flagged ({n_ok})", f"drift flagged ({n_flag})"] if monitored
                  else [f"axes ({n_ok}; not monitored)", "_drift flagged"])
        ax.hist([vals[fin & ~flag], vals[fin & flag]], bins=bins, stacked=True, color=["#4c72b0", "#c44e52"],
                label=labels)
        ax.set_ylim(0, 1.25 * ax.get_ylim()[1])  # headroom: the legend sat on the bars
        ax.legend(fontsize=8, loc="upper center", ncols=2)
    ax.yaxis.get_major_locator().set_params(integer=True)  # counts of axes (ticks were 0.2, 0.4, ...)
    unit = _unit(df, parameter)
    ax.set_xlabel(parameter + (f" [{unit}]" if unit else ""))
    ax.set_ylabel("axes")
    ax.set_title(f"{parameter}, {'latest fit per axis' if period is None else period}", fontsize=10)
    return ax


def plot_axis_history(results, axis: str, parameter: str = "Fc_pos", *, ax=None, legend: bool = True):
    """One axis's parameter over time: daily estimates with 95 % intervals, the fitted trend,
    the temperature-free trend, and the alarm.

    Parameters
    ----------
    results : pandas.DataFrame
        Monitored results (``drift_*`` columns; without them only the estimates are drawn).
    axis : str
        The axis.
    parameter : str
        Column to show.
    ax : matplotlib Axes, optional
    legend : bool
        Draw the legend in the axes (:func:`plot_axis_histories` puts one below its row instead).

    Returns
    -------
    matplotlib Axes
    """
    import matplotlib.pyplot as plt
    import pandas as pd

    if ax is None:
        _, ax = plt.subplots(figsize=(6.4, 3.4))
    df = results[(results["axis"] == axis) & results["ok"].astype(bool)].sort_values("period")
    t = pd.to_datetime(df["period"], errors="coerce")
    x = t if t.notna().all() else np.arange(len(df))
    y = df[parameter].to_numpy(float)
    lo, hi = df.get(f"{parameter}_lo"), df.get(f"{parameter}_hi")
    if lo is not None and hi is not None:
        ax.errorbar(x, y, yerr=[y - lo.to_numpy(float), hi.to_numpy(float) - y], fmt="o", ms=3, lw=0.8,
                    color="#333", label="daily fit, 95 % interval")
    else:
        ax.plot(x, y, "o", ms=3, color="#333", label="daily fit")
    trend = f"drift_{parameter}_trend"
    if trend in df and np.isfinite(df[trend].to_numpy(float)).any():
        tr = df[trend].to_numpy(float)
        ax.plot(x, tr, "-", color="#4c72b0", lw=1, label="trend (temperature + wear)")
        temp_cols = [c for c in df.columns if c.startswith(f"drift_{parameter}_") and c.endswith("_part")
                     and not c.endswith("wear_part")]
        if temp_cols:
            part = np.nansum(np.column_stack([df[c].to_numpy(float) for c in temp_cols]), axis=1)
            log = "drift_scale" in df and df["drift_scale"].iloc[0] == "log"
            base = tr / np.exp(part) if log else tr - part
            ax.plot(x, base, "--", color="#c44e52", lw=1.2, label="wear only (temperature removed)")
    if "drift_alarm_period" in df and df["drift_alarm_period"].notna().any():
        alarm = df["drift_alarm_period"].dropna().iloc[0]
        xa = pd.to_datetime(alarm) if t.notna().all() else int(np.flatnonzero(df["period"] == alarm)[0])
        ax.axvline(xa, color="#c44e52", lw=1, ls=":", label=f"alarm {alarm}")
    unit = _unit(df, parameter)
    ax.set_ylabel(parameter + (f" [{unit}]" if unit else ""))
    ax.set_title(f"{axis}: {parameter}", fontsize=10)
    if legend:
        ax.legend(fontsize=7)
    ax.tick_params(axis="x", labelrotation=30, labelsize=8)
    return ax


def plot_axis_histories(results, axis: str, parameters):
    """:func:`plot_axis_history` of several parameters of one axis in a row, with ONE legend below the
    row (in each 3.6-inch panel a four-entry legend covered daily estimates); returns the Figure."""
    import matplotlib.pyplot as plt

    fig, axs = plt.subplots(1, len(parameters), figsize=(3.6 * len(parameters), 3.4), layout="constrained",
                            squeeze=False)
    for p, ax in zip(parameters, axs[0]):
        plot_axis_history(results, axis, p, ax=ax, legend=False)
    handles, labels = axs[0, 0].get_legend_handles_labels()
    if handles:
        fig.legend(handles, labels, loc="outside lower center", ncols=len(handles), fontsize=8, frameon=False)
    return fig


__all__ = ["plot_axis_histories", "plot_axis_history", "plot_parameter_distribution"]
