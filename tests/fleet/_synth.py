"""Results tables made directly at the parameter level (no logs): fast monitor tests."""

from __future__ import annotations

import numpy as np
import pandas as pd

PARAMS = ("Fc_pos", "Fc_neg", "Fs_pos", "Fs_neg", "sigma2_pos", "sigma2_neg")


def results_table(axes: int, days: int, seed: int, *, drifting=(), rate=0.01, onset=None, t_trend=0.08,
                  k_visc=0.02, jitter=0.003) -> pd.DataFrame:
    """One row per axis-day like ``identify_fleet``'s: parameters with standard errors and a temperature.

    Temperature: seasonal swing + ``t_trend`` °C/day + N(0, 2 °C); sigma2 ∝ exp(-k_visc ΔT),
    Fc, Fs ∝ (1 - 0.004 ΔT); a common lubrication jitter; standard errors of fits with
    ~5 residual degrees of freedom (noisy). Axes in ``drifting`` wear from ``onset`` on.
    """
    rng = np.random.default_rng(seed)
    rows = []
    onset = days // 3 if onset is None else onset
    for a in range(axes):
        base = {p: rng.uniform(10, 40) if not p.startswith("sigma2") else rng.uniform(100, 400) for p in PARAMS}
        phase = rng.uniform(0, 60)
        for d in range(days):
            T = 22 + 3 * np.sin(2 * np.pi * (d + phase) / 60) + t_trend * d + rng.normal(0, 2)
            lub = rng.normal(0, jitter)
            wear = rate * max(0, d - onset) if a in drifting else 0.0
            r = {"axis": f"axis-{a:04d}", "period": str(pd.Timestamp("2026-01-05").date() + pd.Timedelta(days=d))[:10],
                 "ok": True, "model_pos": "exponential", "model_neg": "exponential", "temperature": T}
            for p, b in base.items():
                if p.startswith("sigma2"):
                    true, se = b * np.exp(-k_visc * (T - 22)) * (1 + rng.normal(0, 0.005)), 0.006 * b
                else:
                    true = b * (1 - 0.004 * (T - 22)) * (1 + lub) * (1 + wear * (1.5 if p.startswith("Fs") else 1))
                    se = 0.004 * b
                r[p] = true + rng.normal(0, se)
                r[f"{p}_se"] = se * np.sqrt(rng.chisquare(5) / 5)
            rows.append(r)
    return pd.DataFrame(rows)
