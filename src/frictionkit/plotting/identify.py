"""Plots of identification results (matplotlib is imported inside the functions)."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

#: Height of the fit panel over the residual panel in the two-panel time-series plot (a residual is
#: read for its size and pattern, not its detail; 2:1 keeps the fit readable at the report's 8 x 5 in).
RESIDUAL_PANEL_RATIO = 2.0


def fitted_signal(result) -> tuple[str, str]:
    """``(quantity, unit)`` of the signal a time-series fit compares: an output-error fit's velocity or
    position (force drive, ``compare``), else the force or torque (rigid body, pre-sliding, motion drive)."""
    prov = result.provenance
    units = prov.get("units") if isinstance(prov.get("units"), Mapping) else {}
    compare = prov.get("procedure", {}).get("compare") if result.kind == "output_error" else None
    unit = units.get(compare if compare in ("v", "x") else "F", "N")
    return {"v": "velocity", "x": "position"}.get(compare, "torque" if "·m" in unit else "force"), unit


def _plot_loop(ax, result, x, y, y_pred) -> None:
    """A pre-sliding fit as the force–displacement (hysteresis) loop: measured and predicted against the
    position (µm up to 2 mm of travel, else mm; a rotary record's as it is)."""
    from .simulation import length_display

    _, unit = fitted_signal(result)
    xu = result.provenance.get("units", {}).get("x", "m") if isinstance(result.provenance.get("units"),
                                                                          Mapping) else "m"
    k, xu_shown = length_display(x[np.isfinite(x)]) if xu == "m" else (1.0, xu)
    ax.plot(k * x, y, "-", lw=0.8, color="C0", label="measured")
    ax.plot(k * x, y_pred, "-", lw=0.8, color="C1", label="predicted")
    ax.set_xlabel(f"position [{xu_shown}]")
    ax.set_ylabel(f"{'torque' if '·m' in unit else 'force'} [{unit}]")
    ax.set_title("force–displacement loop", fontsize="medium")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper left", fontsize="small")


def plot_identification(result, ax=None):
    """Draw an :class:`~frictionkit.identify.IdentificationResult`.

    Static maps: averaged data points and the fitted steady-state curve for each
    direction. Rigid body and pre-sliding: measured and predicted force against
    time. Output error: measured and simulated velocity (or position; the force in the
    motion drive) against time. Drawn on a new figure, a time-series fit gets a second
    panel below, sharing the time axis: the residual ``measured − predicted``
    (``ax.figure.axes[1]``); a pre-sliding fit that saved its positions (``data["x"]``)
    also the force–displacement loop beside them (``ax.figure.axes[2]``). On a given
    ``ax`` only the fit over time is drawn.

    Parameters
    ----------
    result : IdentificationResult
        A result from :func:`~frictionkit.identify.fit_static_map` or
        :func:`~frictionkit.identify.fit_rigid_body`.
    ax : matplotlib Axes, optional
        Axes to draw on; default a new figure.

    Returns
    -------
    matplotlib Axes
        The Axes of the fit (the residual panel, when drawn, is the figure's second Axes).

    Examples
    --------
    >>> ax = plot_identification(res)  # doctest: +SKIP
    >>> ax.figure.savefig("fit.png")  # doctest: +SKIP
    """
    import matplotlib.pyplot as plt

    d = result.data
    series = result.kind not in ("static_map", "reversal")
    y, y_pred = d.get("y", np.zeros(0)), d.get("y_pred", np.zeros(0))
    res_ax = loop_ax = None
    new_figure = ax is None
    if ax is None:
        loop = result.kind == "presliding" and y.size and d.get("x", np.zeros(0)).size == y.size
        if series and y.size and y.size == y_pred.size and loop:  # beside it, the F(x) hysteresis loop
            fig = plt.figure(figsize=(11.5, 5.2))
            grid = fig.add_gridspec(2, 2, height_ratios=[RESIDUAL_PANEL_RATIO, 1], width_ratios=[1.45, 1])
            ax = fig.add_subplot(grid[0, 0])
            res_ax = fig.add_subplot(grid[1, 0], sharex=ax)
            ax.tick_params(labelbottom=False)
            loop_ax = fig.add_subplot(grid[:, 1])
        elif series and y.size and y.size == y_pred.size:  # the fit over its residual, one time axis
            fig, (ax, res_ax) = plt.subplots(2, 1, figsize=(7.5, 5.2), sharex=True,
                                             gridspec_kw={"height_ratios": [RESIDUAL_PANEL_RATIO, 1]})
        elif result.kind == "static_map":  # room for the legend right of the axes
            _, ax = plt.subplots(figsize=(8.6, 4.0))
        else:
            _, ax = plt.subplots(figsize=(6.4, 4.0))
    prov = result.provenance
    if result.kind == "static_map":
        v, F = d.get("v", np.zeros(0)), d.get("F", np.zeros(0))
        if "F_std" in d and np.any(d["F_std"] > 0):
            ax.errorbar(v, F, yerr=d["F_std"], fmt="o", ms=4, color="C0", ecolor="0.7", label="measured (mean ± std)")
        else:
            ax.plot(v, F, "o", ms=4, color="C0", label="measured")
        if result.model is not None and v.size:
            for sign in (1, -1):
                sel = np.sign(v) == sign
                if not sel.any():
                    continue
                hi = float(np.max(np.abs(v[sel])))
                vv = sign * np.linspace(hi * 1e-3, hi * 1.05, 400)
                ax.plot(vv, result.model.steady_state(vv), "-", color="C1",
                        label=f"fit ({result.model_name})" if sign == 1 or not (np.sign(v) == 1).any() else None)
        ax.axhline(0.0, color="0.8", lw=0.8)
        ax.axvline(0.0, color="0.8", lw=0.8)
        ax.set_xlabel(f"velocity [{prov.get('units', {}).get('v', 'm/s')}]")
        ax.set_ylabel(f"friction [{prov.get('units', {}).get('F', 'N')}]")
        ax.set_title(f"static map, RMS residual {result.rms:.3g} {prov.get('units', {}).get('F', 'N')}")
    elif result.kind == "reversal":  # friction in the new direction against the displacement (seed 001 Fig. 13)
        xu = prov.get("units", {}).get("x", "m")
        # µm on a linear axis (the displacements are a few µm; in m the axis read '1e-5' beside the ticks)
        k, xu_shown = (1e6, "µm") if xu == "m" else (1.0, xu)
        xi, F = d.get("xi", np.zeros(0)), d.get("F", np.zeros(0))
        ax.plot(k * xi, F, ".", ms=2, color="C0", label="measured around the reversals")
        if result.model is not None and xi.size:
            from ..models.rolling import sigmoid_compensation, sinc_compensation

            c = result.model
            xx = np.linspace(float(xi.min()), float(xi.max()), 800)
            ax.plot(k * xx, sinc_compensation(xx, F0=c.F0, xs=c.xs), "-", color="C1",
                    label=f"sinc, xs = {k * c.xs:.3g} {xu_shown}")
            xp = xx[xx >= 0]
            ax.plot(k * xp, sigmoid_compensation(xp, F0=c.F0, sigma=c.sigma), "--", color="C2",
                    label=f"sigmoid, sigma = {k * c.sigma:.3g} {xu_shown}")
        ax.axvline(0.0, color="0.8", lw=0.8)
        ax.set_xlabel(f"displacement from the reversal point [{xu_shown}]")
        ax.set_ylabel(f"friction in the new direction [{prov.get('units', {}).get('F', 'N')}]")
        Fu = prov.get("units", {}).get("F", "N")
        ax.set_title(f"reversal fit: F0 = {result['F0']:.4g} {Fu}, RMS residual {result.rms:.3g} {Fu}",
                     fontsize="medium")
    else:
        t = d.get("t", np.arange(d.get("y", np.zeros(0)).size))
        y, y_pred, y_static = d.get("y", np.zeros(0)), d.get("y_pred", np.zeros(0)), d.get("y_static")
        x = d.get("x", np.zeros(0))
        if t.size > 2:  # break the lines across rests and between records (gaps in time)
            gap = np.flatnonzero(np.diff(t) > 1.5 * np.median(np.diff(t))) + 1
            t, y, y_pred = (np.insert(np.asarray(a, float), gap, np.nan) for a in (t[:], y, y_pred))
            if y_static is not None:
                y_static = np.insert(np.asarray(y_static, float), gap, np.nan)
            if loop_ax is not None:
                x = np.insert(np.asarray(x, float), gap, np.nan)
        if loop_ax is not None:
            _plot_loop(loop_ax, result, x, y, y_pred)
        ax.plot(t, y, "-", lw=0.8, color="C0", label="measured")
        if res_ax is not None:
            res_ax.plot(t, y - y_pred, "-", lw=0.6, color="C3")
            res_ax.axhline(0.0, color="0.6", lw=0.8)
        ax.plot(t, y_pred, "-", lw=0.8, color="C1", label="predicted")
        if y_static is not None:
            ax.plot(t, y_static, "--", lw=0.8, color="C2", label="static map")
        (res_ax or ax).set_xlabel("time [s]")
        quantity, unit = fitted_signal(result)
        ax.set_ylabel(f"{quantity} [{unit}]")
        if res_ax is not None:
            res_ax.set_ylabel(f"residual [{unit}]")
            res_ax.set_title("measured − predicted", fontsize="small", loc="left")
        title = f"{result.model_name}: relative error {result.relative_error_percent:.3g} %"
        if "static_rms" in result.diagnostics:
            title += f", RMS {result.rms:.3g} (static map {result.diagnostics['static_rms']:.3g}) {unit}"
        ax.set_title(title, fontsize="medium")
    # dense traces fill the axes (the EMPS fit's legend hid its peaks), and a static map's long fit label
    # ("fit (directional(lorentzian, exponential))") reached from the empty v < 0, F > 0 quadrant over the
    # breakaway points at v ≈ 0+ (TRO2021 drives 1 and 3 in the demo report): legend outside, right
    if series or result.kind == "static_map":
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize="small", frameon=False)
    else:
        ax.legend(loc="best", fontsize="small")
    if new_figure:  # the legends outside the axes inside the figure, for a plain savefig too (no layout
        ax.figure.tight_layout()  # engine: the CLI's and the report's own tight_layout must not clash with one)
    return ax
