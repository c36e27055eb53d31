"""Data of the force-driven output-error fit, and the LuGre start values from a sub-breakaway test.

Part of :mod:`.output_error` (split from it without a change of behaviour); the public
name stays importable as ``frictionkit.identify.output_error.initial_guess_lugre``."""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from .. import _validate as val
from ..data.recording import Recording
from ..errors import DataError
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = ["initial_guess_lugre"]


def _arrays(data) -> tuple[np.ndarray, np.ndarray, np.ndarray | None, np.ndarray | None, dict, str]:
    """``t, u, x, v, provenance, name`` from a Recording or a mapping of arrays."""
    if isinstance(data, Recording):
        rec = data
    elif isinstance(data, Mapping):
        d = dict(data)
        if "u" in d and "F" not in d:
            d["F"] = d.pop("u")
        unknown = set(d) - {"t", "x", "v", "F"}
        if unknown:
            raise DataError(f"fit_output_error: unknown signal(s) {sorted(unknown)}; use t, F (or u), x, v")
        rec = Recording(**d, name="arrays")
    else:
        raise DataError(f"fit_output_error: data = {type(data).__name__}: give a Recording or a mapping of arrays")
    if not rec.is_regular:
        raise DataError(f"recording '{rec.name}': irregular sampling; call Recording.resample() first")
    return rec.t, np.asarray(rec.force(), dtype=float), rec.x, rec.v, dict(rec.provenance), rec.name


# --------------------------------------------------------------------------- initial guess
def initial_guess_lugre(data: Mapping[str, ArrayLike] | Recording, *, mass: float = 0.0, zeta: float = 1.0, sigma2: float = 0.0,
                        load_fraction: float = 0.3) -> dict[str, float]:
    """Initial ``sigma0``, ``sigma1`` of a LuGre model from a sub-breakaway test (seed 002 §3.1).

    With a driving force below the breakaway level the axis stays in pre-sliding and
    the friction force ``F = u - m a`` over the displacement ``x`` draws hysteresis
    branches. Where the bristle deflection is zero (the friction force crosses 0
    on a branch, or at the virgin start) the slope ``dF/dx`` equals ``sigma0``
    exactly; it is estimated by a straight-line fit over the samples of each
    monotone branch whose friction force lies within ``load_fraction`` of the
    branch's force range around zero, and the median over branches is returned.
    ``sigma1`` follows from a damping-ratio guess of the linearised pre-sliding
    oscillator ``m x'' + (sigma1 + sigma2) x' + sigma0 x = u``:
    ``sigma1 = max(2 zeta sqrt(sigma0 m) - sigma2, 0)``.

    Parameters
    ----------
    data : Recording or mapping
        Time ``t`` [s], position ``x`` [m] and force ``F`` (or ``u``) [N].
    mass : float
        Moving mass [kg] (>= 0) for the inertia correction and the damping guess.
        With 0 the inertia is ignored and ``sigma1`` is returned as 0.
    zeta : float
        Damping-ratio guess [-] (1 = critical).
    sigma2 : float
        Viscous coefficient [N·s/m] already known from the static map.
    load_fraction : float
        Half-width of the force window around zero, as a fraction of the branch's range.

    Returns
    -------
    dict
        ``sigma0`` [N/m], ``sigma1`` [N·s/m], ``branches`` (number of branches used).

    Raises
    ------
    DataError
        No position, or no branch with enough distinct positions.

    Examples
    --------
    >>> import numpy as np, frictionkit as fk
    >>> from frictionkit.identify.output_error import initial_guess_lugre
    >>> dt = 1e-3; t = np.arange(4001) * dt
    >>> u = 1.0 * (2 / np.pi) * np.arcsin(np.sin(2 * np.pi * 0.5 * t))  # 1 N triangle < Fs
    >>> res = fk.simulate(fk.LuGre(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3), sigma0=1e5, sigma1=63.2),
    ...                   plant=fk.Mass(1.0), force=u, dt=dt)
    >>> g = initial_guess_lugre({"t": t, "x": res.x, "F": u}, mass=1.0)
    >>> bool(abs(g["sigma0"] / 1e5 - 1) < 0.1)
    True
    """
    t, u, x, _, _, name = _arrays(data)
    if x is None:
        raise DataError(f"recording '{name}': initial_guess_lugre needs the position x")
    mass = val.nonnegative("initial_guess_lugre", "mass", mass)
    zeta = val.nonnegative("initial_guess_lugre", "zeta", zeta)
    dt = float(np.median(np.diff(t)))
    F = u.copy()
    if mass > 0:
        F = F - mass * np.gradient(np.gradient(x, dt), dt)
    # monotone branches of x (direction changes of the smoothed increments)
    dx = np.diff(x)
    sgn = np.sign(dx)
    nz = np.flatnonzero(sgn != 0)
    if nz.size < 2:
        raise DataError(f"recording '{name}': the position does not move; no pre-sliding branch to fit")
    # fill zero increments with the previous direction
    s_full = sgn.copy()
    last = sgn[nz[0]]
    for i in range(s_full.size):
        if s_full[i] == 0:
            s_full[i] = last
        else:
            last = s_full[i]
    cuts = np.flatnonzero(np.diff(s_full) != 0) + 1
    edges = np.r_[0, cuts, dx.size]
    slopes, weights = [], []
    for a, b in zip(edges[:-1], edges[1:]):
        seg = slice(a, b + 1)
        xs, Fs_ = x[seg], F[seg]
        rng = float(Fs_.max() - Fs_.min())
        if rng <= 0:
            continue
        sel = np.abs(Fs_) <= load_fraction * rng / 2.0 if a > 0 else np.abs(Fs_) <= load_fraction * rng
        if np.unique(xs[sel]).size < 3:
            continue
        A = np.column_stack([xs[sel], np.ones(sel.sum())])
        coef, *_ = np.linalg.lstsq(A, Fs_[sel], rcond=None)
        if coef[0] > 0:
            slopes.append(coef[0])
            weights.append(sel.sum())
    if not slopes:
        raise DataError(
            f"recording '{name}': no pre-sliding branch with at least 3 distinct positions near zero force; "
            "use a sub-breakaway triangle-wave test with a finer position resolution"
        )
    sigma0 = float(np.median(slopes))
    sigma1 = max(2.0 * zeta * math.sqrt(sigma0 * mass) - sigma2, 0.0) if mass > 0 else 0.0
    return {"sigma0": sigma0, "sigma1": sigma1, "branches": len(slopes)}
