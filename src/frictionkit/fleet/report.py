"""The fleet page: one self-contained HTML file (plots embedded) from a results table.

Sections: the fleet in numbers; the distribution of the friction parameters over the axes;
the flagged axes with their alarm and the monitor's one-line reason, and each flagged
axis's parameters over time (daily fits with intervals, the trend, the trend with the
temperature effect removed, the alarm); the files that failed.
"""

from __future__ import annotations

import base64
import html
import io
from pathlib import Path
from typing import Any
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from collections.abc import Sequence
    import pandas as pd

#: Parameters drawn for each flagged axis, and in the distribution panel.
HISTORY = ("Fc_pos", "Fs_pos", "sigma2_pos", "Fc_neg")


def _png(fig) -> str:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=100)
    return base64.b64encode(buf.getvalue()).decode()


def _table(header: list[str], rows: list[list[Any]]) -> str:
    out = ["<table><tr>" + "".join(f"<th>{html.escape(h)}</th>" for h in header) + "</tr>"]
    for r in rows:
        out.append("<tr>" + "".join(f"<td>{html.escape('' if c is None else str(c))}</td>" for c in r) + "</tr>")
    out.append("</table>")
    return "\n".join(out)


def fleet_report(results: pd.DataFrame | str | Path, out: str | Path, *, max_axes: int = 20, parameters: Sequence[str]=HISTORY) -> dict[str, Any]:
    """Write the fleet page.

    Parameters
    ----------
    results : pandas.DataFrame or str or Path
        Results of :func:`~frictionkit.fleet.identify_fleet` (monitored; if the ``drift_*``
        columns are missing, :func:`~frictionkit.fleet.monitor_drift` runs first).
    out : str or Path
        HTML file, written atomically.
    max_axes : int
        Flagged axes drawn over time (the earliest alarms first); all are listed.
    parameters : sequence of str
        Parameters drawn (default :data:`HISTORY`).

    Returns
    -------
    dict
        ``axes``, ``rows``, ``ok``, ``errors``, ``flagged`` (list), ``drawn`` (list), ``out``.

    Examples
    --------
    >>> from frictionkit.fleet import fleet_report
    >>> fleet_report("results.parquet", "fleet.html")  # doctest: +SKIP
    """
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt
    import pandas as pd

    from .._io import atomic_write_text
    from ..plotting.fleet import plot_axis_histories, plot_parameter_distribution
    from .drift import drift_summary, monitor_drift

    df = results if isinstance(results, pd.DataFrame) else pd.read_parquet(results)
    if "drift_flag" not in df:
        df = monitor_drift(df)
    params = [p for p in parameters if p in df and df[p].notna().any()]
    axes = drift_summary(df)
    flagged = axes[axes["drift_flag"]].sort_values("drift_alarm_period", kind="stable")
    ok = df["ok"].astype(bool)
    periods = sorted(df["period"].astype(str).unique())
    parts = [
        "<!doctype html><html><head><meta charset='utf-8'><title>frictionkit fleet report</title>",
        "<style>body{font-family:system-ui,sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;color:#222}"
        "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #ccc;padding:4px 8px;font-size:13px;"
        "vertical-align:top}th{background:#f3f3f3}img{max-width:100%;border:1px solid #eee;margin:.5em 0}"
        "h2{border-bottom:1px solid #ddd}</style></head><body><h1>frictionkit — fleet report</h1>",
    ]
    method = df["drift_method"].dropna().iloc[0] if "drift_method" in df and df["drift_method"].notna().any() else "?"
    parts.append(_table(["item", "value"], [  # was an empty header row
        ["axes", len(axes)], ["axis-periods", len(df)], ["periods", f"{periods[0]} … {periods[-1]}" if periods else ""],
        ["identified", int(ok.sum())], ["failed (see below)", int((~ok).sum())],
        ["drift flagged", f"{len(flagged)} {axes_word(len(flagged))} (monitor: {method})"],
        ["frictionkit", ", ".join(sorted(df["frictionkit_version"].dropna().astype(str).unique()))],
    ]))

    parts.append("<h2>Friction parameters over the fleet</h2>")
    if params:
        fig, axs = plt.subplots(1, len(params), figsize=(3.4 * len(params), 3.0), layout="constrained", squeeze=False)
        for p, ax in zip(params, axs[0]):
            plot_parameter_distribution(df, p, ax=ax)
        parts.append(f"<img alt='distribution' src='data:image/png;base64,{_png(fig)}'>")
        plt.close(fig)

    parts.append(f"<h2>Flagged axes ({len(flagged)})</h2>")
    if len(flagged):
        parts.append(_table(["axis", "alarm", "why"], [[r["axis"], r["drift_alarm_period"], r["drift_detail"]]
                                                        for _, r in flagged.iterrows()]))
    else:
        parts.append("<p>None: every axis's change is within what its intervals and temperature explain.</p>")
    drawn = []
    for axis in flagged["axis"].head(int(max_axes)):
        fig = plot_axis_histories(df, axis, params)
        parts.append(f"<h3>{html.escape(axis)}</h3><img alt='{html.escape(axis)}' "
                     f"src='data:image/png;base64,{_png(fig)}'>")
        plt.close(fig)
        drawn.append(axis)
    if len(flagged) > len(drawn):
        more = len(flagged) - len(drawn)
        parts.append(f"<p>{more} more flagged {axes_word(more)} not drawn (max_axes = {max_axes}).</p>")

    bad = df[~ok]
    parts.append(f"<h2>Files that failed ({len(bad)})</h2>")
    if len(bad):
        parts.append(_table(["axis", "period", "file", "error"], [[r["axis"], r["period"], r["file"], r["error"]]
                                                                  for _, r in bad.head(200).iterrows()]))
    parts.append("</body></html>")
    out = Path(out)
    atomic_write_text(out, "\n".join(parts))
    return {"out": str(out), "axes": int(len(axes)), "rows": int(len(df)), "ok": int(ok.sum()),
            "errors": int((~ok).sum()), "flagged": flagged["axis"].tolist(), "drawn": drawn}


def axes_word(n: int) -> str:
    """``"axis"`` for one, else ``"axes"`` (the page said "1 axes")."""
    return "axis" if n == 1 else "axes"


__all__ = ["HISTORY", "fleet_report"]
