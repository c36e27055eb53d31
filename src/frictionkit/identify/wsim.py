"""WSIM and ACIM: friction identification of a two-axis differential micro-feed system (seed 000).

A TDMS (two-axis differential micro-feed system, seed 000 §2) drives one ball screw from
both ends: the screw motor turns the screw (angle ``theta1``), the nut motor the nut
(``theta2``), and the worktable moves at ``x_t = (theta1 + theta2) R - e_g``, ``R = P_h/2pi``
(§2.3 sign convention: co-rotation at equal speed is ``theta1' = -theta2'`` and holds the
table still). The procedures here take the logs of such a machine — simulated
(:mod:`frictionkit.presets.zhang2023`) or real — as :class:`TDMSRun` objects and return
result objects with ``status``, ``message``, ``summary()`` and ``plot(ax=None)``.

WSIM (whole-system identification method, seed 000 §3 and Fig. 6), four steps
-----------------------------------------------------------------------------
1. :func:`cospeed_static` — both shafts co-rotate at a sequence of constant speeds (the table
   stands still); per shaft and per direction the plateau means of ``K_t i_q`` against the
   shaft speed (eqs. 17-18) are fitted with the package's static-map fitter
   (:func:`~frictionkit.identify.fit_static_map`, exponential Stribeck curve, eq. 4).
   Table 3 layout.
2. :func:`cospeed_presliding` — both shafts co-rotate back and forth within a few µm (screw
   ~10 µm, nut ~30 µm of linear equivalent); per shaft and direction the torque–angle curve of
   the virgin branch gives the breakpoints P1..P3 (M = 3), ``xi_i`` by eq. 19 with
   ``s = s(v)`` of step 1 at the creep speed (= T_S), ``C`` chosen for fast convergence and a
   simulation-error polish (:func:`~frictionkit.identify.fit_presliding`). Table 4 layout.
3. :func:`differential_static` — at each base speed ``b >= 0`` the nut is held at the base speed
   and the screw speed is raised (table speed ``v3 > 0``, screw driving, eq. 11) or lowered
   (``v3 < 0``) through plateaus (§5.2.2). The lumped per-motor torques are taken against the
   **table speed** (eq. 20: ``T_s = T_fs + T_fbs + F_ft R``, ``T_n = T_fn - T_fbn``), each curve
   is first described by a second-order Fourier series (the paper's pre-fit,
   :func:`fourier2_fit`, when a direction has >= 7 plateaus), and then
   * the screw's curve per base speed as an offset plus a friction, ``c(b) + D_b(v3)`` (the
     screw's own support keeps turning one way while ball pair and guide reverse with ``v3``),
     ``D_b`` by the static-map fitter; Table 5's screw columns are the lumped levels at
     ``screw_base_speed`` (the paper: 4 mm/s);
   * the nut's curve per base speed (constant levels) and synthesised into TDMSSC (eq. 21,
     :class:`~frictionkit.models.TDMSSC`): levels affine in the nut speed, ``sigma2``,
     ``- eps v3 |v3|``, over the base speeds > 0 (at ``b = 0`` the nut stands and its support
     sticks; that case keeps its own fit). Table 5 layout.
4. :func:`differential_presliding` — nut held still, the screw reciprocates within microns;
   the screw torque is the friction; breakpoints as in step 2. Table 6 layout.

:func:`wsim` runs the four steps and returns a :class:`WSIMResult`.

Choices the paper does not make (documented assumptions)
--------------------------------------------------------
* **Fitting the nut's lumped curve.** The lumped nut torque ``T_fn - T_fbn`` is not a
  friction (the ball pair pulls the nut along) and crosses zero; the static-map fitter bounds
  levels and viscous slope at >= 0 by design, so the nut's TDMSSC is fitted by *variable
  projection*: for each ``(v_s, delta)`` of a fixed grid the remaining coefficients (levels,
  their base-speed slopes, ``sigma``, ``eps``) enter linearly and follow from one linear least
  squares; the grid point of least residual is kept (the grid is the parameter
  ``shape_grid``). No new nonlinear optimiser.
* **Fourier pre-fit.** ``a0 + sum_j a_j cos(j w v) + b_j sin(j w v)``, ``j = 1, 2`` (MATLAB
  ``fourier2``), per direction; ``w`` on a grid (period 1.1-20 times the speed span), the
  coefficients by linear least squares. The Stribeck/TDMSSC fits use the Fourier curve at the
  measured plateau speeds, as the paper does ("to avoid fitting mistakes"); with fewer than
  seven plateaus in a direction the raw plateau means are used and the result says so.
* **Linear equivalents.** The paper prints torques in N and speeds in mm/s: the tables here
  give torque / R [N], speed x R [mm/s], stiffness / R**2 [N/µm], viscous / R**2 [N·s/m]
  (the fits themselves run in rad, rad/s, N·m).
* **Base speed** ``b`` [m/s] >= 0 is the common speed both shafts reach before the sweep; the
  nut is then held at ``theta2' = -b/R`` (§2.3 signs) and the screw raised or lowered. The "+"
  columns of Tables 5-6 are ``v3 > 0``, the "-" columns ``v3 < 0``. TDMSSC's schedule is the
  nut's measured linear-equivalent speed ``R theta2'`` (signed), as
  :class:`~frictionkit.models.TDMSSC` defines it.

ACIM (all-components identification method, Feng/Du [25])
----------------------------------------------------------
The paper gives neither procedure nor values. :func:`acim` implements the assumption
documented there: each component (screw support bearings, nut support bearings, ball-screw
pair, guide) is tested **in isolation**, as in a component test rig — the component alone,
driven at speed plateaus (static map, static-map fitter) and by a µm reciprocation (GMS,
pre-sliding fitter; one virgin branch, used for both directions) — at its *catalogue* condition: the ball pair with its preload only and no
external axial load (a TDMS cannot be taken apart to load it with the guide's force). The
component laws are then summed into eq. 16's feed-forward terms
(``T*_fs + T*_fbs + R F*_ft`` on the screw, ``T*_fbn - T*_fn`` on the nut; the signs of the
terms are those of the motion each component sees).
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import _validate as val
from ..data.recording import Recording
from ..data.segmentation import Segment, find_plateaus
from ..data.signals import derivative
from ..errors import DataError, IdentificationError, ParameterError, warn_renamed
from ..models.gms import GMS, GMSWeightWarning
from ..models.static import Directional, Stribeck
from .presliding import fit_presliding
from .static_map import fit_static_map, stribeck_model

__all__ = [
    "ACIMResult",
    "COMPONENTS",
    "SHAFTS",
    "TDMSRun",
    "WSIMResult",
    "WSIMStep",
    "acim",
    "cospeed_presliding",
    "cospeed_static",
    "differential_presliding",
    "differential_static",
    "fourier2_fit",
    "wsim",
]

#: The two driven shafts of a TDMS, in the order of the paper's tables.
SHAFTS = ("screw", "nut")
#: The components ACIM identifies one by one (seed 000 eq. 16's feed-forward terms).
COMPONENTS = ("screw_support", "nut_support", "ball_pair", "guide")
#: Table columns: shaft and co-rotation direction ("+": screw turns positive, nut negative).
COLUMNS = ("screw +", "nut +", "screw -", "nut -")

#: Default ``(v_s [m/s], delta)`` grid of the nut's TDMSSC fit (variable projection).
SHAPE_GRID = (tuple(np.geomspace(2e-5, 2e-2, 31).tolist()), tuple(np.linspace(0.5, 6.0, 12).tolist()))

#: Fewest plateaus per direction for the second-order Fourier pre-fit (6 coefficients + 1 spare).
FOURIER_MIN_POINTS = 7


# --------------------------------------------------------------------------- data
@dataclass(frozen=True, kw_only=True, eq=False)
class TDMSRun:
    """One experiment on a TDMS: both motors' encoder angles and torques, and the table scale.

    Parameters
    ----------
    t : array_like
        Time [s], uniformly sampled.
    theta1, theta2 : array_like
        Screw and nut motor angles [rad] (§2.3 sign convention).
    T1, T2 : array_like
        Motor torques ``K_t i_q`` [N·m] of the screw and the nut motor.
    R : float
        Lead ratio ``P_h / 2 pi`` [m/rad].
    x_t : array_like, optional
        Worktable position from the linear scale [m].
    base_speed : float, optional
        Base speed ``b`` [m/s] of a differential run (co-rotation speed in the screw's sign;
        the nut turns at ``-b/R``).
    plateaus : sequence of (start, stop), optional
        Sample ranges of the commanded constant-speed plateaus (a drive log knows its command);
        the last ``settled`` fraction of each is averaged. Without them the plateaus are found
        in the screw encoder's speed (:func:`~frictionkit.data.find_plateaus`).
    settled : float
        Fraction of each given plateau averaged (its end), default 0.5.
    name : str
        Label.
    """

    t: np.ndarray
    theta1: np.ndarray
    theta2: np.ndarray
    T1: np.ndarray
    T2: np.ndarray
    R: float
    x_t: np.ndarray | None = None
    base_speed: float | None = None
    plateaus: tuple = ()
    settled: float = 0.5
    name: str = "tdms run"

    def __post_init__(self) -> None:
        owner = f"TDMSRun('{self.name}')"
        t = np.asarray(self.t, float)
        n = t.size
        if n < 3 or not np.all(np.isfinite(t)) or np.any(np.diff(t) <= 0):
            raise DataError(f"{owner}.t: need >= 3 finite, strictly increasing time stamps")
        object.__setattr__(self, "t", t)
        for nm in ("theta1", "theta2", "T1", "T2", "x_t"):
            a = getattr(self, nm)
            if a is None:
                continue
            a = np.asarray(a, float)
            if a.shape != (n,):
                raise DataError(f"{owner}.{nm}: {a.shape[0] if a.ndim else 0} samples, t has {n}")
            if not np.all(np.isfinite(a)):
                i = int(np.flatnonzero(~np.isfinite(a))[0])
                raise DataError(f"{owner}.{nm}[{i}] = {a[i]!r}: must be finite")
            object.__setattr__(self, nm, a)
        val.positive(owner, "R", self.R)
        if self.base_speed is not None and not math.isfinite(self.base_speed):
            raise ParameterError(f"{owner}.base_speed = {self.base_speed!r}: must be finite")
        pl = []
        for i, ab in enumerate(self.plateaus):
            a, b = int(ab[0]), int(ab[1])
            if not 0 <= a < b <= n:
                raise ParameterError(f"{owner}.plateaus[{i}] = {tuple(ab)!r}: need 0 <= start < stop <= {n}")
            pl.append((a, b))
        object.__setattr__(self, "plateaus", tuple(pl))
        if not 0.0 < self.settled <= 1.0:
            raise ParameterError(f"{owner}.settled = {self.settled!r}: must be in (0, 1]")

    @classmethod
    def from_recording(cls, rec, *, R: float, base_speed: float | None = None, name: str | None = None) -> "TDMSRun":
        """The logged signals of any object with ``t``, ``theta1``, ``theta2``, ``torque1``,
        ``torque2`` and optionally ``x_scale`` (e.g. a simulated
        :class:`~frictionkit.presets.zhang2023.TDMSRecording`); its truth is not read."""
        x = getattr(rec, "x_scale", None)
        segs = tuple((a, b) for a, b, *_ in getattr(rec, "segments", ()))
        return cls(t=rec.t, theta1=rec.theta1, theta2=rec.theta2, T1=rec.torque1, T2=rec.torque2, R=R,
                   x_t=x, base_speed=base_speed, plateaus=segs,
                   name=name or getattr(getattr(rec, "reference", None), "description", "tdms run"))

    @property
    def dt(self) -> float:
        return float(np.median(np.diff(self.t)))

    def shaft(self, name: str) -> Recording:
        """The ``"screw"`` or ``"nut"`` motor as a one-axis :class:`~frictionkit.data.Recording`
        (``x`` angle [rad], ``v`` speed [rad/s], ``F`` torque [N·m])."""
        if name not in SHAFTS:
            raise ParameterError(f"TDMSRun.shaft: name = {name!r}: must be one of {SHAFTS}")
        th, T = (self.theta1, self.T1) if name == "screw" else (self.theta2, self.T2)
        return Recording(t=self.t, x=th, v=derivative(th, self.dt), F=T, name=f"{self.name}: {name}",
                         units={"x": "rad", "v": "rad/s", "F": "N·m"})

    def table_speed(self) -> np.ndarray:
        """``v3 = R (theta1' + theta2')`` [m/s] from the encoders (the TDMSSC argument, eq. 21)."""
        return self.R * derivative(self.theta1 + self.theta2, self.dt)


# --------------------------------------------------------------------------- results
@dataclass(frozen=True, kw_only=True, eq=False)
class WSIMStep:
    """One step of WSIM (or one component of ACIM): the fits and the table in the paper's layout.

    Attributes
    ----------
    name : str
        ``"table3"`` ... ``"table6"`` (WSIM steps) or an ACIM component.
    status : int
        0 success, 1 finished with warnings (see ``message``), 2 failed.
    message : str
    table : dict
        Column -> row -> value, in the paper's units (N, mm/s, N/µm, N·s/m).
    fits : dict
        The underlying :class:`~frictionkit.identify.IdentificationResult` objects.
    laws : dict
        Identified laws in SI rotational units (N·m, rad/s), by column.
    curves : dict
        Data and model curves for plotting.
    """

    name: str
    status: int
    message: str
    table: dict
    fits: dict = field(default_factory=dict)
    laws: dict = field(default_factory=dict)
    curves: dict = field(default_factory=dict)
    diagnostics: dict = field(default_factory=dict)

    def summary(self) -> str:
        """One line per column of the identified table."""
        lines = [f"{self.name}: status {self.status} ({self.message})"]
        for col, row in self.table.items():
            if isinstance(row, dict):
                cells = ", ".join(f"{k} {v:.4g}" if isinstance(v, float) else f"{k} {v}" for k, v in row.items())
            else:
                cells = str(row)
            lines.append(f"  {col}: {cells}")
        return "\n".join(lines)

    def to_dict(self) -> dict:
        return {"name": self.name, "status": self.status, "message": self.message,
                "table": _plain(self.table), "diagnostics": _plain(self.diagnostics)}

    def plot(self, ax=None):
        """Measured points and identified curves, one line per column."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots()
        for col, c in self.curves.items():
            (ln,) = ax.plot(c["x"], c["y"], ".", label=f"{col} data")
            if "x_fit" in c:
                ax.plot(c["x_fit"], c["y_fit"], "-", color=ln.get_color(), label=f"{col} fit")
        ax.set_xlabel(next(iter(self.curves.values()), {}).get("xlabel", ""))
        ax.set_ylabel(next(iter(self.curves.values()), {}).get("ylabel", ""))
        ax.set_title(self.name)
        ax.legend(fontsize="small")
        return ax


class _StepsResult:
    """summary(), to_dict() and plot() of a result made of named steps (each with the same three)."""

    def summary(self) -> str:
        return "\n".join([f"{type(self).__name__}: status {self.status} ({self.message})",
                          *(s.summary() for s in self.steps.values())])

    def to_dict(self) -> dict:
        return {"status": self.status, "message": self.message,
                **{k: s.to_dict() for k, s in self.steps.items()}}

    def plot(self, ax=None):
        import matplotlib.pyplot as plt

        if ax is None:
            _, axs = plt.subplots(2, 2, figsize=(10, 7))
            ax = axs.ravel()
        for a, s in zip(np.ravel(ax), self.steps.values()):
            s.plot(ax=a)
        return ax


@dataclass(frozen=True, kw_only=True, eq=False)
class WSIMResult(_StepsResult):
    """The four WSIM steps (seed 000 Fig. 6), Tables 3-6."""

    steps: dict
    R: float
    status: int
    message: str

    def tables(self) -> dict:
        return {k: s.table for k, s in self.steps.items()}


@dataclass(frozen=True, kw_only=True, eq=False)
class ACIMResult(_StepsResult):
    """Component laws identified in isolation and their eq. 16 sums."""

    steps: dict
    status: int
    message: str

    @property
    def laws(self) -> dict:
        """Component -> identified law (GMS on the component's static map when pre-sliding
        data were given, else the static map), SI units of the component's coordinate."""
        return {k: s.laws.get("dynamic", s.laws.get("static")) for k, s in self.steps.items()}


def _plain(x: Any) -> Any:
    if isinstance(x, Mapping):
        return {str(k): _plain(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_plain(v) for v in x]
    if isinstance(x, np.ndarray):
        return _plain(x.tolist())
    if isinstance(x, (np.floating, float)):
        return float(x) if math.isfinite(float(x)) else None
    if isinstance(x, np.integer):
        return int(x)
    return x


def _status(warns: Sequence[str], ok: bool = True) -> tuple[int, str]:
    if not ok:
        return 2, "; ".join(warns) or "failed"
    return (1, "; ".join(warns)) if warns else (0, "ok")


# --------------------------------------------------------------------------- helpers
def _plateau_means(run: TDMSRun, drive: np.ndarray, *, min_samples: int = 40, trim: float = 0.2,
                   rel_tol: float = 0.02) -> dict[str, np.ndarray]:
    """Means of shaft speeds, table speed and both torques over the constant-speed plateaus
    (the run's commanded ones, else those found in ``drive``, a speed signal of the run)."""
    if run.plateaus:
        segs = [Segment(start=b - max(int((b - a) * run.settled), 2), stop=b, direction=1)
                for a, b in run.plateaus]
    else:
        segs = find_plateaus(drive, run.dt, window=21, rel_tol=rel_tol, min_samples=min_samples, trim=trim,
                             min_speed=0.0)
    if not segs:
        raise DataError(f"run '{run.name}': no constant-speed plateau found")
    w1 = derivative(run.theta1, run.dt)
    w2 = derivative(run.theta2, run.dt)
    out = {k: [] for k in ("w1", "w2", "v3", "T1", "T2", "T1_std", "T2_std", "n")}
    for s in segs:
        sl = s.slice
        n = sl.stop - sl.start
        dtot = run.t[sl.stop - 1] - run.t[sl.start]
        # Mean speeds from the angle change over the plateau (exact for encoder data).
        out["w1"].append((run.theta1[sl.stop - 1] - run.theta1[sl.start]) / dtot if dtot > 0 else w1[sl].mean())
        out["w2"].append((run.theta2[sl.stop - 1] - run.theta2[sl.start]) / dtot if dtot > 0 else w2[sl].mean())
        out["v3"].append(run.R * (out["w1"][-1] + out["w2"][-1]))
        out["T1"].append(float(np.mean(run.T1[sl])))
        out["T2"].append(float(np.mean(run.T2[sl])))
        out["T1_std"].append(float(np.std(run.T1[sl])))
        out["T2_std"].append(float(np.std(run.T2[sl])))
        out["n"].append(n)
    return {k: np.asarray(v, float) for k, v in out.items()}


def _stribeck_column(law, R: float, sign: int) -> dict:
    """A Table 3/5 column (linear equivalents) from a one-direction Stribeck law in N·m, rad/s."""
    if not isinstance(law, Stribeck):  # CoulombViscous
        return {"T_C_N": law.Fc / R, "T_S_N": law.Fc / R, "vs_mm_s": None, "delta": None,
                "sigma_N_s_m": law.sigma2 / R**2}
    return {"T_C_N": law.Fc / R, "T_S_N": law.Fs / R, "vs_mm_s": sign * law.vs * R * 1e3,
            "delta": law.delta, "sigma_N_s_m": law.sigma2 / R**2}


def _gms_column(law, R: float) -> dict:
    """A Table 4/6 column from a GMS in N·m/rad (stiffness in N/µm, C in N/s of linear equivalent)."""
    col = {}
    for i, (k, xi) in enumerate(zip(law.k, law.xi), start=1):
        col[f"k{i}_N_um"] = float(k) / R**2 * 1e-6
    for i, xi in enumerate(law.xi, start=1):
        col[f"xi{i}"] = float(xi)
    col["C_N_s"] = float(law.C) / R
    col["sum_xi"] = float(np.sum(law.xi))
    return col


def _side(law, sign: int):
    if isinstance(law, Directional):
        return law.positive if sign > 0 else law.negative
    return law


# --------------------------------------------------------------------------- Fourier pre-fit
def _fourier_basis(v: np.ndarray, w: float) -> np.ndarray:
    return np.column_stack([np.ones_like(v), np.cos(w * v), np.sin(w * v), np.cos(2 * w * v), np.sin(2 * w * v)])


def fourier2_fit(v, y, *, periods=None) -> dict:
    """Second-order Fourier series ``a0 + sum_{j=1,2} a_j cos(j w v) + b_j sin(j w v)`` fitted to
    ``(v, y)`` (MATLAB ``fourier2``; seed 000 §5.2.2's pre-fit).

    ``w`` is chosen on a grid of periods (default 1.1-20 times the span of ``v``), the five
    coefficients by linear least squares for each.

    Returns
    -------
    dict
        ``w`` [1/unit of v], ``coef`` (a0, a1, b1, a2, b2), ``rms``, ``predict`` (callable).

    Examples
    --------
    >>> import numpy as np
    >>> v = np.linspace(0.0, 1.0, 12)
    >>> fit = fourier2_fit(v, 1.0 + 0.5 * np.sin(2.0 * v))
    >>> bool(fit["rms"] < 1e-3)
    True
    """
    v = np.asarray(v, float).ravel()
    y = np.asarray(y, float).ravel()
    if v.size != y.size or v.size < 6:
        raise DataError(f"fourier2_fit: need >= 6 matching points, got {v.size} and {y.size}")
    span = float(np.ptp(v)) or 1.0
    periods = np.geomspace(1.1, 20.0, 60) * span if periods is None else np.asarray(periods, float)
    best = None
    for P in periods:
        w = 2 * np.pi / P
        A = _fourier_basis(v, w)
        coef, *_ = np.linalg.lstsq(A, y, rcond=None)
        r = y - A @ coef
        sse = float(r @ r)
        if best is None or sse < best[0] * (1 - 1e-12):
            best = (sse, w, coef)
    sse, w, coef = best
    return {"w": float(w), "coef": coef, "rms": math.sqrt(sse / v.size),
            "predict": lambda x, w=w, c=coef: _fourier_basis(np.asarray(x, float), w) @ c}


# --------------------------------------------------------------------------- TDMSSC fit
_TDMSSC_LIN = ("Fc0", "Fc1", "Fs0", "Fs1", "sigma2", "eps")


def _tdmssc_columns(v3, s, vs, delta):
    sg = np.sign(v3)
    phi = np.exp(-np.abs(v3 / vs) ** delta)
    return np.column_stack([sg * (1 - phi), sg * (1 - phi) * s, sg * phi, sg * phi * s, v3, -v3 * np.abs(v3)])


def _fit_tdmssc(v3, s, y, shape_grid, *, affine: bool) -> dict:
    """Variable projection for :class:`~frictionkit.models.TDMSSC` (eq. 21): for each
    ``(vs, delta)`` of the grid, levels, their schedule slopes, ``sigma2`` and ``eps`` by linear
    least squares; the grid point of least residual is kept."""
    best = None
    vs_grid, d_grid = shape_grid
    keep = list(range(6)) if affine else [0, 2, 4, 5]

    def _supported(vs, d):
        # the Stribeck part is identifiable only with >= 2 points inside its transition
        phi = np.exp(-np.abs(v3 / vs) ** d)
        return int(np.sum((phi > 0.05) & (phi < 0.95))) >= 2

    for vs in vs_grid:
        for d in d_grid:
            if not _supported(vs, d):
                continue
            A = _tdmssc_columns(v3, s, vs, d)[:, keep]
            coef, *_ = np.linalg.lstsq(A, y, rcond=None)
            r = y - A @ coef
            sse = float(r @ r)
            if best is None or sse < best[0]:
                best = (sse, vs, d, coef)
    if best is None:
        # no Stribeck transition in the data: Coulomb + viscous + quadratic (Fs = Fc)
        sg = np.sign(v3)
        cols = [sg, sg * s, v3, -v3 * np.abs(v3)] if affine else [sg, v3, -v3 * np.abs(v3)]
        coef, *_ = np.linalg.lstsq(np.column_stack(cols), y, rcond=None)
        r = y - np.column_stack(cols) @ coef
        c = dict(zip(("Fc0", "Fc1", "sigma2", "eps") if affine else ("Fc0", "sigma2", "eps"), coef.tolist()))
        p = {"Fc0": c["Fc0"], "Fc1": c.get("Fc1", 0.0), "Fs0": c["Fc0"], "Fs1": c.get("Fc1", 0.0),
             "sigma2": c["sigma2"], "eps": c["eps"], "vs": float(vs_grid[-1]), "delta": 1.0}
        return {"params": p, "rms": math.sqrt(float(r @ r) / max(y.size, 1)), "at_grid_edge": False,
                "no_transition": True}
    # second pass: a 9 x 9 grid over the neighbouring cells of the best point
    iv, idl = list(vs_grid).index(best[1]), list(d_grid).index(best[2])
    vlo, vhi = vs_grid[max(iv - 1, 0)], vs_grid[min(iv + 1, len(vs_grid) - 1)]
    dlo, dhi = d_grid[max(idl - 1, 0)], d_grid[min(idl + 1, len(d_grid) - 1)]
    for vs in np.geomspace(vlo, vhi, 9):
        for d in np.linspace(dlo, dhi, 9):
            if not _supported(vs, d):
                continue
            A = _tdmssc_columns(v3, s, vs, d)[:, keep]
            coef, *_ = np.linalg.lstsq(A, y, rcond=None)
            r = y - A @ coef
            sse = float(r @ r)
            if sse < best[0]:
                best = (sse, vs, d, coef)
    sse, vs, d, coef = best
    p = dict.fromkeys(_TDMSSC_LIN, 0.0)
    for j, c in zip(keep, coef):
        p[_TDMSSC_LIN[j]] = float(c)
    p.update(vs=float(vs), delta=float(d))
    at_edge = bool(np.isclose(vs, vs_grid[0]) or np.isclose(vs, vs_grid[-1]) or np.isclose(d, d_grid[0])
                   or np.isclose(d, d_grid[-1]))
    return {"params": p, "rms": math.sqrt(sse / max(y.size, 1)), "at_grid_edge": bool(at_edge)}


def _tdmssc_law(p: Mapping[str, float]):
    from ..models.tdmssc import TDMSSC

    return TDMSSC(**{k: p[k] for k in ("Fc0", "Fc1", "Fs0", "Fs1", "vs", "delta", "sigma2", "eps")})


# --------------------------------------------------------------------------- step 1
def cospeed_static(run: TDMSRun | Sequence[TDMSRun], *, model: str = "exponential",
                   min_samples: int = 40) -> WSIMStep:
    """WSIM step 1 (seed 000 §5.2.1, eqs. 17-18, Table 3): per shaft and direction, the
    Stribeck curve of ``K_t i_q`` against the shaft speed from co-speed plateaus.

    Parameters
    ----------
    run : TDMSRun or sequence of TDMSRun
        Co-speed runs: both shafts co-rotate (``theta1' = -theta2'``) through constant-speed
        plateaus in both directions.
    model : str
        Structure for :func:`~frictionkit.identify.fit_static_map` (default the paper's
        exponential Stribeck curve, eq. 4, delta free).
    min_samples : int
        Fewest samples of a plateau.

    Returns
    -------
    WSIMStep
        ``table`` in the Table 3 layout (columns ``"screw +"``, ``"nut +"``, ``"screw -"``,
        ``"nut -"``; ``"+"`` is the co-rotation with the screw turning positive), ``laws``
        ``{"screw": Directional, "nut": Directional}`` in N·m and rad/s (shaft coordinates).
    """
    runs = [run] if isinstance(run, TDMSRun) else list(run)
    if not runs:
        raise DataError("cospeed_static: no run given")
    R = runs[0].R
    pts = [_plateau_means(r, derivative(r.theta1, r.dt), min_samples=min_samples) for r in runs]
    w1 = np.concatenate([p["w1"] for p in pts])
    w2 = np.concatenate([p["w2"] for p in pts])
    T1 = np.concatenate([p["T1"] for p in pts])
    T2 = np.concatenate([p["T2"] for p in pts])
    warns, fits, laws, table, curves = [], {}, {}, {}, {}
    for shaft, w, T in (("screw", w1, T1), ("nut", w2, T2)):
        try:
            fit = fit_static_map(w, T, model=model, units={"v": "rad/s", "F": "N·m"})
        except IdentificationError as exc:
            warns.append(f"{shaft}: {exc}; structure chosen by AIC among those the points allow")
            fit = fit_static_map(w, T, model="auto", units={"v": "rad/s", "F": "N·m"})
        fits[shaft] = fit
        warns += [f"{shaft}: {m}" for m in fit.warnings]
        try:
            laws[shaft] = stribeck_model(fit)
        except IdentificationError as exc:
            warns.append(f"{shaft}: {exc}")
            continue
        vv = np.linspace(w.min(), w.max(), 400)
        curves[shaft] = {"x": w * R * 1e3, "y": T / R, "x_fit": vv * R * 1e3,
                         "y_fit": laws[shaft].steady_state(vv) / R,
                         "xlabel": "shaft speed (linear equivalent) [mm/s]", "ylabel": "K_t i_q / R [N]"}
    for col in COLUMNS:
        shaft, d = col.split()
        co = 1 if d == "+" else -1
        # the nut turns opposite to the screw in co-rotation: its '+' column is its negative speed
        sgn = co if shaft == "screw" else -co
        if shaft in laws:
            table[col] = _stribeck_column(_side(laws[shaft], sgn), R, sgn)
    st, msg = _status(warns)
    return WSIMStep(name="table3", status=st, message=msg, table=table, fits=fits, laws=laws, curves=curves,
                    diagnostics={"points": {"w1": w1, "w2": w2, "T1": T1, "T2": T2}})


# --------------------------------------------------------------------------- steps 2 and 4
#: Retries of a pre-sliding fit that fails on a noisy record: (block-mean target samples, polish).
#: Heavier averaging first, then the eq. 19 breakpoints without the simulation-error polish.
PRESLIDING_RETRIES = ((120, True), (60, False))


def _polish_arg(owner: str, polish, refine) -> bool:
    """``polish`` (a bool), or the former name ``refine`` for one release (warned): one meaning per
    name — :class:`~.fit_options.FitOptions`' ``refine`` counts optimised starts."""
    if refine is not None:
        warn_renamed(owner, "refine", "polish", stacklevel=4)
        polish = refine
    if not val.is_bool(polish):
        raise ParameterError(f"{owner}: polish = {polish!r}: must be True or False")
    return bool(polish)


def _usable(fit) -> None:
    """Raise where the pre-sliding fit gave nothing WSIM can use (the retries below then run); a polish
    stopped by its evaluation limit below its start cost is used, as before fit_presliding returned results."""
    if not fit.success and fit.diagnostics.get("polish") != "stopped":
        raise IdentificationError(f"fit_presliding: {fit.message}")


def _fit_micro(rec: Recording, max_samples, *, elements, static, polish, max_nfev):
    """fit_presliding on the thinned record; on failure retried per :data:`PRESLIDING_RETRIES`.
    Returns (fit, notes, the record fitted)."""
    notes = []
    attempts = [(max_samples, polish)] + [(m, r and polish) for m, r in PRESLIDING_RETRIES
                                          if max_samples is None or m < max_samples]
    last = None
    for m, ref in attempts:
        try:
            used = _thin(rec, m)
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always", GMSWeightWarning)
                fit = fit_presliding(used, elements=elements, static=static, branch="virgin", polish=ref,
                                     max_nfev=max_nfev)
            _usable(fit)
            seen = sorted({str(w.message) for w in caught if issubclass(w.category, GMSWeightWarning)})
            if seen:
                notes.append(f"during the fit: {seen[-1]} (the stroke ends before the curve reaches s(v))")
            if notes:
                notes.append(f"fitted with block means to {m} samples, polish={ref}")
            return fit, notes, used
        except (IdentificationError, DataError) as exc:
            last = exc
            notes.append(f"{m} samples, polish={ref}: {exc}")
    # fewer elements, padded back to M by splitting the last one (k/2, xi/2 twice breaks away at
    # the same stroke: the same force curve), so that both directions keep M elements
    m = PRESLIDING_RETRIES[0][0]
    for e in range(int(elements) - 1, 0, -1):
        try:
            used = _thin(rec, m)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", GMSWeightWarning)     # the table reports sum_xi
                fit = fit_presliding(used, elements=e, static=static, branch="virgin", polish=polish,
                                     max_nfev=max_nfev)
            _usable(fit)
            notes.append(f"fitted with M = {e} elements (block means to {m} samples), padded to M = {elements} "
                         "by splitting the last element")
            g = fit.model
            k, xi = list(g.k), list(g.xi)
            while len(k) < elements:
                k[-1:] = [k[-1] / 2, k[-1] / 2]
                xi[-1:] = [xi[-1] / 2, xi[-1] / 2]
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", GMSWeightWarning)
                padded = GMS(g.static, k=k, xi=xi, C=g.C)
            fit = dataclasses.replace(fit, model=padded, model_name=f"gms_M{e}_padded_to_M{elements}")
            return fit, notes, used
        except (IdentificationError, DataError) as exc:
            last = exc
            notes.append(f"M = {e}: {exc}")
    raise IdentificationError("; ".join(notes)) from last


def _presliding_columns(shaft_runs: Mapping[str, Recording], static_of: Callable[[str], Any], R: float,
                        elements: int, polish: bool, max_nfev: int, label: str,
                        max_samples: int | None = 300) -> WSIMStep:
    warns, fits, laws, table, curves = [], {}, {}, {}, {}
    ok = True
    for col, rec0 in shaft_runs.items():
        static = static_of(col)
        try:
            fit, notes, rec = _fit_micro(rec0, max_samples, elements=elements, static=static, polish=polish,
                                    max_nfev=max_nfev)
            warns += [f"{col}: {n}" for n in notes]
        except (IdentificationError, DataError) as exc:
            warns.append(f"{col}: {exc}")
            ok = False
            continue
        fits[col] = fit
        laws[col] = fit.model
        warns += [f"{col}: {m}" for m in fit.warnings]
        table[col] = _gms_column(fit.model, R)
        # eq. 19 from the breakpoints alone, before the simulation-error polish
        table[col]["eq19_k_N_um"] = [float(k) / R**2 * 1e-6 for k in fit.diagnostics["initial_k"]]
        table[col]["eq19_xi"] = [float(v) for v in fit.diagnostics["initial_xi"]]
        x = np.asarray(rec.x)
        F = np.asarray(rec.force())
        # P-points of the virgin branch (seed 000 §5.2.1): (displacement [µm], torque / R [N]) at
        # each breakpoint, signed as the stroke
        a, b = fit.provenance["procedure"]["samples"]
        sgn = 1.0 if x[b] > x[a] else -1.0
        pts = []
        for bp in fit.diagnostics["breakpoints"]:
            i = a + int(np.argmin(np.abs(sgn * (x[a:b + 1] - x[a]) - bp)))
            pts.append([float(sgn * bp * R * 1e6), float(F[i] / R)])
        table[col]["P_points_um_N"] = pts
        curves[col] = {"x": (x - x[0]) * R * 1e6, "y": F / R, "x_fit": (x - x[0]) * R * 1e6,
                       "y_fit": np.asarray(fit.data["y_pred"]) / R,
                       "xlabel": "displacement (linear equivalent) [µm]", "ylabel": "torque / R [N]"}
    st, msg = _status(warns, ok=ok or bool(fits))
    if not ok and fits:
        st = 1
    return WSIMStep(name=label, status=st, message=msg, table=table, fits=fits, laws=laws, curves=curves)


def _as_shaft_record(rec, shaft: str, max_samples: int | None = None) -> Recording:
    if isinstance(rec, TDMSRun):
        rec = rec.shaft(shaft)
    elif not isinstance(rec, Recording):
        raise DataError(f"expected a TDMSRun or a Recording, got {type(rec).__name__}")
    return _thin(rec, max_samples)


def _thin(rec: Recording, max_samples: int | None) -> Recording:
    """The record from the start of the motion (the rest before it dropped: an encoder's count
    jitter at standstill would be taken for tiny branches), then block means of ``k`` samples
    of angle and torque so that about ``max_samples`` remain (a creep-speed reciprocation is
    sampled far finer than its force-displacement curve needs; the breakpoint search and the
    simulation-error polish cost grows with the samples, and the means remove the count
    jitter and most of the current noise)."""
    x = np.asarray(rec.x, float)
    F = np.asarray(rec.force(), float)
    d = np.abs(x - x[0])
    span = float(d.max())
    start = max(int(np.argmax(d > 1e-3 * span)) - 1, 0) if span > 0 else 0
    x, F, t = x[start:], F[start:], rec.t[start:]
    # block size from the virgin stroke (up to the first turn): about max_samples / 2 blocks on it
    u = x - x[0]
    sg = np.sign(u[np.argmax(np.abs(u) > 0.01 * span)]) if span > 0 else 1.0
    run = np.maximum.accumulate(sg * u)
    back = np.flatnonzero(sg * u < run - 0.05 * span)
    n_virgin = int(back[0]) if back.size else x.size
    k = 1 if max_samples is None or n_virgin <= max_samples // 2 else int(math.ceil(n_virgin / (max_samples // 2)))
    n = (x.size // k) * k
    if k > 1:
        x = np.r_[x[0], x[:n].reshape(-1, k).mean(axis=1)]
        F = np.r_[F[0], F[:n].reshape(-1, k).mean(axis=1)]
        t = t[0] + np.arange(x.size) * k * rec.dt
    if start == 0 and k == 1:
        return rec
    return Recording(t=t, x=x, F=F, name=rec.name, units=rec.units,
                     provenance={**rec.provenance, "block_mean": k, "from_sample": start})


def cospeed_presliding(runs: Mapping[str, TDMSRun | Recording], static: Mapping[str, Any], *, elements: int = 3,
                       polish: bool = True, max_nfev: int = 40, max_samples: int | None = 300,
                       refine: bool | None = None) -> WSIMStep:
    """WSIM step 2 (seed 000 §5.2.1, eq. 19, Table 4): GMS of each shaft from µm co-speed
    reciprocation.

    Parameters
    ----------
    runs : mapping
        Column (``"screw +"``, ``"nut +"``, ``"screw -"``, ``"nut -"``) -> the run whose first
        stroke, starting from rest and unloaded, goes in that column's direction (a
        :class:`TDMSRun`, from which the column's shaft is taken, or that shaft's
        :class:`~frictionkit.data.Recording` with angle ``x`` [rad] and torque ``F`` [N·m]).
    static : mapping
        ``{"screw": law, "nut": law}``: step 1's static maps (the ``s(v)`` of eq. 19 and of the
        GMS; at the creep speed of the test ``s`` equals T_S, as in the paper).
    elements : int
        Number of GMS elements (the paper: M = 3).
    polish, max_nfev
        Simulation-error polish (see :func:`~frictionkit.identify.fit_presliding`).
    max_samples : int, optional
        Longer records are thinned to about this many samples (every k-th angle, the torque
        averaged over k samples) before the fit; None keeps every sample.
    refine : bool, optional
        The former name of ``polish`` (works for one release, with a deprecation warning;
        :class:`~.fit_options.FitOptions`' ``refine`` counts optimised starts).

    Returns
    -------
    WSIMStep
        Table 4 layout per column: ``k_i`` [N/µm], ``xi_i``, ``C`` [N/s], ``sum_xi``, the
        P-points (µm, N); ``laws`` column -> GMS (N·m, rad).
    """
    polish = _polish_arg("cospeed_presliding", polish, refine)
    if not runs:
        raise DataError("cospeed_presliding: no run given")
    R = next(iter(runs.values())).R if isinstance(next(iter(runs.values())), TDMSRun) else None
    recs = {}
    for col, r in runs.items():
        if col not in COLUMNS:
            raise ParameterError(f"cospeed_presliding: column {col!r}: must be one of {COLUMNS}")
        recs[col] = _as_shaft_record(r, col.split()[0], None)
    if R is None:
        raise DataError("cospeed_presliding: pass TDMSRun objects (their lead ratio R sets the table's units)")
    return _presliding_columns(recs, lambda col: static[col.split()[0]], R, elements, polish, max_nfev, "table4",
                               max_samples)


def differential_presliding(runs: Mapping[str, TDMSRun], static, *, elements: int = 3, polish: bool = True,
                            max_nfev: int = 40, max_samples: int | None = 300,
                            refine: bool | None = None) -> WSIMStep:
    """WSIM step 4 (seed 000 §5.2.2, Table 6): the nut held still, the screw reciprocating
    within microns; the screw motor's torque is the lumped friction.

    Parameters
    ----------
    runs : mapping
        ``{"positive": run, "negative": run}``: runs whose first screw stroke from rest goes in
        that direction.
    static : law
        The screw's lumped differential static map (step 3, N·m and rad/s).
    elements, polish, max_nfev, max_samples, refine
        As :func:`cospeed_presliding` (``refine``: the former name of ``polish``).

    Returns
    -------
    WSIMStep
        Table 6 layout (columns ``"positive"``, ``"negative"``).
    """
    polish = _polish_arg("differential_presliding", polish, refine)
    if not runs:
        raise DataError("differential_presliding: no run given")
    recs = {}
    for col, r in runs.items():
        if col not in ("positive", "negative"):
            raise ParameterError(f"differential_presliding: column {col!r}: must be 'positive' or 'negative'")
        recs[col] = _as_shaft_record(r, "screw", None)
    R = next(iter(runs.values())).R
    return _presliding_columns(recs, lambda col: static, R, elements, polish, max_nfev, "table6", max_samples)


# --------------------------------------------------------------------------- step 3
def differential_static(runs: Sequence[TDMSRun], *, screw_base_speed: float = 4e-3, smooth: bool = True,
                        shape_grid=SHAPE_GRID, min_samples: int = 40) -> WSIMStep:
    """WSIM step 3 (seed 000 §5.2.2, eqs. 20-21, Table 5, Figs. 11-12): lumped per-motor
    friction against the table speed, at several base speeds, screw driving.

    Parameters
    ----------
    runs : sequence of TDMSRun
        One or more runs per base speed (``run.base_speed`` set, >= 0): the nut is held at the
        base speed while the screw speed is raised (table speed v3 > 0, screw driving) or
        lowered (v3 < 0) through plateaus (§5.2.2: "hold the nut at it, and raise or lower the
        screw speed").
    screw_base_speed : float
        Base speed [m/s] whose screw curve gives the screw's Table 5 columns (the paper: 4 mm/s);
        the base speed of the runs nearest to it (in magnitude, per direction) is used.
    smooth : bool
        Fit the second-order Fourier pre-fit first and fit the curves to it (paper).
    shape_grid : (sequence, sequence)
        ``(v_s [m/s], delta)`` grid of the nut's TDMSSC variable projection.

    Returns
    -------
    WSIMStep
        ``table``: columns ``"screw +"``, ``"screw -"`` (Stribeck in N, mm/s, N·s/m) and
        ``"nut +"``, ``"nut -"`` (TDMSSC: ``Tc0_N``, ``Tc1_N_s_mm``, ``Ts0_N``, ``Ts1_N_s_mm``,
        ``vs_mm_s``, ``delta``, ``sigma_N_s_m``, ``eps_N_s2_m2``), plus ``"per_base_speed"``
        rows (the per-base-speed fits before synthesis). ``laws["screw_by_base"]``: base speed
        [m/s] -> ``(c, D)``, the screw's lumped torque ``c + D(v3)`` [N·m] (``D`` Directional
        Stribeck against the table speed v3 [m/s]); ``laws["screw"]``/``laws["screw_offset"]``
        the pair at ``screw_base_speed``;  ``laws["nut"]`` (Directional TDMSSC, N·m against
        v3 [m/s], schedule the nut's linear-equivalent speed ``R theta2'`` [m/s]; synthesised over
        the base speeds > 0) and ``laws["nut_by_base"]`` (base speed -> Directional TDMSSC with
        constant levels, the per-base-speed fits; b = 0 is only there).
    """
    runs = list(runs)
    if not runs:
        raise DataError("differential_static: no run given")
    R = runs[0].R
    rows = []
    for r in runs:
        if r.base_speed is None:
            raise DataError(f"differential_static: run '{r.name}' has no base_speed")
        p = _plateau_means(r, derivative(r.theta1, r.dt), min_samples=min_samples)
        sel = np.abs(p["v3"]) > 1e-9
        for i in np.flatnonzero(sel):
            rows.append((r.base_speed, p["v3"][i], p["T1"][i], p["T2"][i], p["w1"][i], p["w2"][i]))
    if not rows:
        raise DataError("differential_static: no plateau with a moving table")
    A = np.array(rows)
    bases = np.unique(A[:, 0])
    warns: list[str] = []
    table: dict = {"per_base_speed": []}
    curves, fits, laws, fourier = {}, {}, {}, {}
    # smoothed values (Fourier pre-fit per base speed and direction)
    T1s, T2s = A[:, 2].copy(), A[:, 3].copy()
    for b in bases:
        for sgn in (1, -1):
            m = (A[:, 0] == b) & (np.sign(A[:, 1]) == sgn)
            if not m.any():
                continue
            key = f"b={b * 1e3:g}mm/s {'+' if sgn > 0 else '-'}"
            if smooth and m.sum() >= FOURIER_MIN_POINTS:
                f1 = fourier2_fit(A[m, 1], A[m, 2])
                f2 = fourier2_fit(A[m, 1], A[m, 3])
                T1s[m] = f1["predict"](A[m, 1])
                T2s[m] = f2["predict"](A[m, 1])
                fourier[key] = {"screw": {"w": f1["w"], "coef": f1["coef"], "rms_N": f1["rms"] / R},
                                "nut": {"w": f2["w"], "coef": f2["coef"], "rms_N": f2["rms"] / R}}
            elif smooth:
                warns.append(f"{key}: {int(m.sum())} plateaus < {FOURIER_MIN_POINTS}: no Fourier pre-fit, raw means used")
    # screw, per base speed: lumped torque = offset c(b) + a friction D_b(v3) odd in v3. With the
    # nut held at b and the screw raised (v3 > 0) or lowered (v3 < 0), the screw's own support
    # keeps turning one way (for |v3| < b) while ball pair and guide reverse with v3, so the
    # curve is not a friction about zero: c(b) is half the sum of its limits at v3 -> 0+ and
    # 0- (from a signed-level fit, variable projection), D_b the static-map fitter's
    # Directional Stribeck curve of T - c (Table 5's screw columns at ``screw_base_speed``:
    # the lumped levels c + D). At b = 0 c is the direction asymmetry only.
    screw_by_base = {}
    for b in bases:
        m = A[:, 0] == b
        pos, neg = m & (A[:, 1] > 0), m & (A[:, 1] < 0)
        if pos.sum() < 5 or neg.sum() < 5:
            warns.append(f"screw, b = {b * 1e3:g} mm/s: needs >= 5 plateaus in each direction")
            continue
        lim = []
        for mm in (pos, neg):
            f = _fit_tdmssc(A[mm, 1], np.zeros(int(mm.sum())), T1s[mm], shape_grid, affine=False)["params"]
            lim.append(f["Fs0"])
        c = 0.5 * (lim[0] - lim[1])
        try:
            try:
                fit = fit_static_map(A[m, 1], T1s[m] - c, model="exponential", units={"v": "m/s", "F": "N·m"})
            except IdentificationError as exc:
                warns.append(f"screw, b = {b * 1e3:g} mm/s: {exc}; structure chosen by AIC")
                fit = fit_static_map(A[m, 1], T1s[m] - c, model="auto", units={"v": "m/s", "F": "N·m"})
            law = stribeck_model(fit)
        except IdentificationError as exc:
            warns.append(f"screw, b = {b * 1e3:g} mm/s: {exc}")
            continue
        screw_by_base[float(b)] = (float(c), law)
        fits[f"screw b={b * 1e3:g}mm/s"] = fit
    laws["screw_by_base"] = screw_by_base
    if not screw_by_base:
        warns.append("screw: no base speed with plateaus in both directions")
    else:
        b = min(screw_by_base, key=lambda x: abs(x - screw_base_speed))
        c, law = screw_by_base[b]
        laws["screw"], laws["screw_offset"] = law, c
        m = A[:, 0] == b
        warns += [f"screw (b = {b * 1e3:g} mm/s): {w}" for w in fits[f"screw b={b * 1e3:g}mm/s"].warnings]
        for sgn, col in ((1, "screw +"), (-1, "screw -")):
            side = _side(law, sgn)
            # lumped levels c + D against table speed: N·m -> /R N; vs in m/s; sigma N·m·s/m -> /R N·s/m
            table[col] = {"T_C_N": (sgn * c + side.Fc) / R, "T_S_N": (sgn * c + side.Fs) / R,
                          "vs_mm_s": sgn * side.vs * 1e3, "delta": side.delta, "sigma_N_s_m": side.sigma2 / R,
                          "structure": fits[f"screw b={b * 1e3:g}mm/s"].model_name,
                          "offset_c_N": c / R, "base_speed_mm_s": b * 1e3}
            mm = m & (np.sign(A[:, 1]) == sgn)
            vv = np.linspace(A[mm, 1].min(), A[mm, 1].max(), 200)
            curves[col] = {"x": A[mm, 1] * 1e3, "y": A[mm, 2] / R, "x_fit": vv * 1e3,
                           "y_fit": (c + law.steady_state(vv)) / R,
                           "xlabel": "table speed v3 [mm/s]", "ylabel": "lumped motor torque / R [N]"}
    # nut: per base speed (levels constant), then synthesis with affine levels (TDMSSC, eq. 21).
    # The schedule is the nut's measured linear-equivalent speed s = R theta2' [m/s], signed
    # (the convention of frictionkit.models.TDMSSC).
    sched = R * A[:, 5]
    nut_laws, nut_by_base = {}, {}
    for sgn, col in ((1, "nut +"), (-1, "nut -")):
        md = np.sign(A[:, 1]) == sgn
        if not md.any():
            continue
        groups = np.unique(A[md, 0])
        for b in groups:
            m = md & (A[:, 0] == b)
            if m.sum() < 5:
                continue
            f = _fit_tdmssc(A[m, 1], sched[m], T2s[m], shape_grid, affine=False)
            p = f["params"]
            try:
                nut_by_base.setdefault(float(b), {})[sgn] = _tdmssc_law(p)
            except ParameterError as exc:
                warns.append(f"{col}, b = {b * 1e3:g} mm/s: {exc}")
            table["per_base_speed"].append({"column": col, "base_speed_mm_s": b * 1e3,
                                            "nut_speed_mm_s": float(np.mean(sched[m])) * 1e3,
                                            "T_C_N": p["Fc0"] / R, "T_S_N": p["Fs0"] / R,
                                            "vs_mm_s": sgn * p["vs"] * 1e3, "delta": p["delta"],
                                            "sigma_N_s_m": p["sigma2"] / R, "eps_N_s2_m2": p["eps"] / R,
                                            "rms_N": f["rms"] / R})
        # synthesis over the base speeds > 0: at b = 0 the nut does not turn, its support friction
        # sticks instead of sliding at a level, which no affine level can join (that case keeps its
        # own per-base-speed law, laws["nut_by_base"][0.0])
        ms = md & (A[:, 0] > 0) if np.any(groups > 0) else md
        groups = np.unique(A[ms, 0])
        f = _fit_tdmssc(A[ms, 1], sched[ms], T2s[ms], shape_grid, affine=groups.size >= 2)
        if f.get("no_transition"):
            warns.append(f"{col}: no plateau inside a Stribeck transition; Coulomb + viscous + eps fitted (Fs = Fc)")
        if groups.size < 2:
            warns.append(f"{col}: one base speed only; the levels' base-speed slopes are not identifiable (set 0)")
        if f["at_grid_edge"]:
            warns.append(f"{col}: (vs, delta) at the edge of the grid; widen shape_grid")
        p = f["params"]
        try:
            nut_laws[col] = _tdmssc_law(p)
        except ParameterError as exc:
            warns.append(f"{col}: {exc}")
        # linear equivalents; slopes per mm/s of nut speed, as the paper's "6.45 theta2'" (theta2' in mm/s)
        table[col] = {"Tc0_N": p["Fc0"] / R, "Tc1_N_per_mm_s": p["Fc1"] / R * 1e-3, "Ts0_N": p["Fs0"] / R,
                      "Ts1_N_per_mm_s": p["Fs1"] / R * 1e-3, "vs_mm_s": sgn * p["vs"] * 1e3, "delta": p["delta"],
                      "sigma_N_s_m": p["sigma2"] / R, "eps_N_s2_m2": p["eps"] / R, "rms_N": f["rms"] / R}
        if col in nut_laws:
            xs, ys = [], []
            for b in groups:
                m = md & (A[:, 0] == b)
                vv = np.linspace(A[m, 1].min(), A[m, 1].max(), 100)
                xs.append(np.r_[vv * 1e3, np.nan])
                ys.append(np.r_[nut_laws[col].steady_state(vv, schedule=float(np.mean(sched[m]))) / R, np.nan])
            curves[col] = {"x": A[md, 1] * 1e3, "y": A[md, 3] / R, "xlabel": "table speed v3 [mm/s]",
                           "ylabel": "lumped motor torque / R [N]", "x_fit": np.concatenate(xs),
                           "y_fit": np.concatenate(ys)}
    if len(nut_laws) == 2:
        laws["nut"] = Directional(positive=nut_laws["nut +"], negative=nut_laws["nut -"])
    laws["nut_by_base"] = {b: Directional(positive=d[1], negative=d[-1]) for b, d in nut_by_base.items()
                           if 1 in d and -1 in d}
    st, msg = _status(warns)
    return WSIMStep(name="table5", status=st, message=msg, table=table, fits=fits, laws=laws, curves=curves,
                    diagnostics={"fourier": fourier, "points": {"b": A[:, 0], "v3": A[:, 1], "T1": A[:, 2],
                                                                 "T2": A[:, 3], "w1": A[:, 4], "w2": A[:, 5],
                                                                 "s": sched},
                                 "base_speeds_mm_s": bases * 1e3})


# --------------------------------------------------------------------------- WSIM
def wsim(*, cospeed: TDMSRun | Sequence[TDMSRun], cospeed_micro: Mapping[str, TDMSRun],
         differential: Sequence[TDMSRun], differential_micro: Mapping[str, TDMSRun] | None = None,
         elements: int = 3, screw_base_speed: float = 4e-3, polish: bool = True, max_nfev: int = 40,
         progress=None, refine: bool | None = None) -> WSIMResult:
    """The four WSIM steps of seed 000 Fig. 6 on a TDMS's logs (see the module docstring).

    Parameters
    ----------
    cospeed : TDMSRun or sequence
        Step 1 runs (co-speed plateaus, both directions).
    cospeed_micro : mapping
        Step 2 runs by column (``"screw +"`` ...), µm co-speed reciprocation.
    differential : sequence of TDMSRun
        Step 3 runs (screw driving, nut held at ``base_speed``).
    differential_micro : mapping, optional
        Step 4 runs ``{"positive": ..., "negative": ...}`` (nut still, screw reciprocating).
    elements : int
        GMS elements (the paper: 3).
    polish, max_nfev
        Simulation-error polish of the pre-sliding fits (:func:`cospeed_presliding`).
    refine : bool, optional
        The former name of ``polish`` (one release, with a deprecation warning).

    Returns
    -------
    WSIMResult
    """
    polish = _polish_arg("wsim", polish, refine)
    step = progress or (lambda label: None)
    steps = {}
    step("WSIM step 1: co-speed static (Table 3)")
    steps["table3"] = cospeed_static(cospeed)
    step("WSIM step 2: co-speed pre-sliding (Table 4)")
    steps["table4"] = cospeed_presliding(cospeed_micro, steps["table3"].laws, elements=elements, polish=polish,
                                         max_nfev=max_nfev)
    step("WSIM step 3: differential static (Table 5)")
    steps["table5"] = differential_static(differential, screw_base_speed=screw_base_speed)
    if differential_micro:
        step("WSIM step 4: differential pre-sliding (Table 6)")
        by_base = steps["table5"].laws.get("screw_by_base") or {}
        if not by_base:
            raise IdentificationError("wsim: step 3 gave no screw law; step 4 needs one")
        # step 4 runs with the nut still: the static map is step 3's screw curve at the base
        # speed nearest 0 (against the table speed; the fit runs on the screw angle)
        b0 = min(by_base, key=abs)
        steps["table6"] = differential_presliding(differential_micro, _to_shaft(by_base[b0][1], _run_R(cospeed)),
                                                  elements=elements, polish=polish, max_nfev=max_nfev)
    worst = max(s.status for s in steps.values())
    msgs = [f"{k}: {s.message}" for k, s in steps.items() if s.status]
    return WSIMResult(steps=steps, R=_run_R(cospeed), status=min(worst, 1) if worst < 2 else 2,
                      message="; ".join(msgs) if msgs else "ok")


def _run_R(run) -> float:
    r = run if isinstance(run, TDMSRun) else next(iter(run))
    return float(r.R)


def _to_shaft(law, R: float):
    """A table-speed law (N·m vs m/s) as a law of the shaft's own speed (N·m vs rad/s)."""
    if isinstance(law, Directional):
        return Directional(positive=_to_shaft(law.positive, R), negative=_to_shaft(law.negative, R))
    if isinstance(law, Stribeck):
        return Stribeck(Fc=law.Fc, Fs=law.Fs, vs=law.vs / R, delta=law.delta, sigma2=law.sigma2 * R,
                        shape=law.shape)
    from ..models.static import CoulombViscous

    return CoulombViscous(Fc=law.Fc, sigma2=law.sigma2 * R)


# --------------------------------------------------------------------------- ACIM
def acim(components: Mapping[str, Mapping[str, Any]], *, elements: int = 3, polish: bool = False,
         max_nfev: int = 40, max_samples: int | None = 300, refine: bool | None = None) -> ACIMResult:
    """ACIM: every component identified in isolation (documented assumption, module docstring).

    Parameters
    ----------
    components : mapping
        Component name (:data:`COMPONENTS`) -> ``{"static": ..., "presliding": Recording}``
        (either may be missing), in the component's own **linear-equivalent** coordinate (m,
        m/s, N; a rotating component at the lead ratio, as the paper's tables).
        ``static``: a :class:`~frictionkit.data.Recording` of the component alone driven
        through constant-speed plateaus in both directions, or its
        :class:`~frictionkit.data.SteadyStatePoints`. ``presliding``: a µm reciprocation from
        rest (virgin branch first; ``x`` and ``F``).

    elements, polish, max_nfev, max_samples
        As :func:`cospeed_presliding` (``polish`` off by default here).
    refine : bool, optional
        The former name of ``polish`` (one release, with a deprecation warning).

    Returns
    -------
    ACIMResult
        ``steps[component]`` with ``laws["static"]`` (Directional Stribeck) and, with
        pre-sliding data, ``laws["dynamic"]`` (GMS on that map); tables in N, mm/s, N/µm.
    """
    polish = _polish_arg("acim", polish, refine)
    steps = {}
    for name, recs in components.items():
        if name not in COMPONENTS:
            raise ParameterError(f"acim: component {name!r}: must be one of {COMPONENTS}")
        warns, fits, laws, table, curves = [], {}, {}, {}, {}
        if "static" in recs:
            fit = fit_static_map(recs["static"], model="exponential")
            fits["static"] = fit
            warns += list(fit.warnings)
            law = stribeck_model(fit)
            laws["static"] = law
            for sgn, col in ((1, "+"), (-1, "-")):
                table[col] = _stribeck_column(_side(law, sgn), 1.0, sgn)
            vv = np.linspace(float(np.min(fit.data["v"])), float(np.max(fit.data["v"])), 300)
            curves["static"] = {"x": fit.data["v"] * 1e3, "y": fit.data["F"], "x_fit": vv * 1e3,
                                "y_fit": law.steady_state(vv), "xlabel": "speed [mm/s]", "ylabel": "friction [N]"}
        if "presliding" in recs:
            try:
                pf, notes, _ = _fit_micro(recs["presliding"], max_samples, elements=elements,
                                          static=laws.get("static"), polish=polish, max_nfev=max_nfev)
                warns += notes
                fits["presliding"] = pf
                laws["dynamic"] = pf.model
                warns += list(pf.warnings)
                table["gms"] = _gms_column(pf.model, 1.0)
            except (IdentificationError, DataError) as exc:
                warns.append(f"presliding: {exc}")
        st, msg = _status(warns, ok=bool(laws))
        steps[name] = WSIMStep(name=name, status=st, message=msg, table=table, fits=fits, laws=laws, curves=curves)
    worst = max((s.status for s in steps.values()), default=2)
    msgs = [f"{k}: {s.message}" for k, s in steps.items() if s.status]
    return ACIMResult(steps=steps, status=worst, message="; ".join(msgs) if msgs else "ok")
