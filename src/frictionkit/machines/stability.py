"""Closed-loop stability screen of a machine (issue 13: unstable loops were silent).

A machine whose controller makes the loop unstable (a light EMPS axis under the nominal
gains, a ball screw with every inertia x1e-2) runs into its actuator limits and chatters in
a limit cycle that depends on the sub-steps: the traces do not converge, yet the run used
to end with status 0. A loop that is linearly unstable but settles into a bounded, converged
limit cycle (the two-shaft benchmark's first layout, replaced on 2026-11-23: a 1.7 kHz mode
of its motor-coupling resonance, at the current limit half of the time) is a correct simulation
of a poor design.

The screen, in two stages like the sub-step check (:func:`~frictionkit.machines.simulate.site_coupling`):

1. :func:`loop_stability` linearises one controller sample of the machine: the linear chain
   discretised exactly over the sample (actuators held, as the core does), every controller
   block as it runs in the kernel (Sum, PID with its filtered derivative and integrator,
   StateSpace, Saturation unsaturated, FrictionFeedforward by the slope ``sigma2`` of its
   map), sensor and actuator delays, and a signal read before it is written as last
   sample's value. Friction sites enter as sliding: their viscous slope ``sigma2``
   (assumption: the loop's operating point is motion; a sticking site's stiffness and the
   Stribeck slope are left out). Its spectral radius ``rho`` (largest ``|eigenvalue|`` of the
   one-sample map) above ``1 + RHO_MARGIN`` means a disturbance grows.
2. Only then the run is repeated at ``SUBSTEP_CHECK_FACTOR`` (16) x the sub-steps (a loop checked
   only because it can hunt, below: ``HUNT_CHECK_FACTOR`` (4) x); when a
   position disagrees by more than 1 % of its range, or a velocity or actuator command by more
   than 10 % (the sub-step check's bounds), or the finer run fails, the result is status 2 (``STATUS_TOLERANCE``) with a message naming the unstable mode, the
   actuator whose loop it is and what to do. A converged run keeps its status and the
   message notes the unstable mode and the time at the limit.

Two more triggers of stage 2 (issue 13, the screen's blind spots), each from the same matrix:

- Hunting: with each friction site at its steepest steady-state slope (:func:`_steepest_slope`,
  negative on a Stribeck drop) instead of ``sigma2`` the radius ``stribeck_radius`` exceeds 1. The
  run is checked only when a site's speed stays inside its hunting band (``LoopStability.bands``)
  for the samples a disturbance needs to grow ``HUNT_GROWTH``-fold; a converged stick-slip limit
  cycle keeps status 0 with a note.
- A barely damped loop: stable, but its largest mode oscillates with a damping ratio below
  ``ZETA_LIGHT`` and decays by less than ``RHO_BORDER`` per sample.

Linearly stable loops cost one or two eigenvalue problems per run (a 30–60 state matrix); a
hunting-prone loop ~30 more once per machine and dt (remembered, ``SCREEN_CACHE``).
"""

from __future__ import annotations

import dataclasses
import math
from collections import OrderedDict
from dataclasses import dataclass

import numpy as np

from .._lru import remember
from .elements import PID, FrictionFeedforward, Saturation, StateSpace, Sum
from .machine import Machine

#: A mode counts as unstable when its magnitude per sample exceeds ``1 + RHO_MARGIN``: it then
#: grows at least e-fold in 1e6 samples (slower growth is no defect any run could show; a free
#: rigid body's double eigenvalue 1 splits by ~1e-8 in floating point).
RHO_MARGIN = 1e-6

#: A stable loop is still checked for convergence when its largest mode is oscillating with a
#: damping ratio below ``ZETA_LIGHT`` and decays by less than ``RHO_BORDER`` per sample
#: (assumptions, issue 13): the held site forces of the sub-steps shift such a mode's decay rate
#: by a small amount, which decides whether it rings down. Measured: the seed 001 ball screw with
#: the loop gain x3 (radius 0.99586, zeta 0.0098 at 134.6 Hz) moved a position by 1.19 % of its
#: range between 40 and 640 sub-steps; the stable loops of the EMPS, the ball screw at its paper
#: gains and the SDSS axes have zeta >= 0.086 on their largest modes and are not checked (their runs
#: cost nothing more).
ZETA_LIGHT = 0.02
RHO_BORDER = 0.01


@dataclass(frozen=True)
class LoopStability:
    """Linearised closed-loop stability of a machine at its sample period.

    Attributes
    ----------
    radius : float — spectral radius of the one-sample map (> 1: unstable).
    frequency_hz : float — frequency of the largest mode (0 for a real eigenvalue).
    dof : str — the degree of freedom whose velocity dominates that mode (scaled by
        ``sqrt(inertia)``: its kinetic-energy share).
    actuators : tuple[str] — actuators whose feedback alone makes the mode unstable: with
        that actuator's command held at zero the radius drops to ``<= 1 + RHO_MARGIN``
        (empty when no single actuator does).
    closed : bool — the machine has a feedback loop at all (an actuator commanded by a
        sensor-driven block); open-loop machines are ``radius = nan``.
    """

    radius: float
    frequency_hz: float
    dof: str
    actuators: tuple
    closed: bool
    #: the radius with each friction site at its steepest steady-state slope (:func:`_steepest_slope`,
    #: negative on a Stribeck drop) instead of ``sigma2``: > 1 means the loop can hunt at low speed
    #: (nan when no site's curve falls below its viscous slope)
    stribeck_radius: float = math.nan
    #: damping ratio of the largest mode (1 for a real eigenvalue, nan without feedback)
    zeta: float = math.nan
    #: per site the speed band ``(v_lo, v_hi)`` [m/s or rad/s] where its slope is below the
    #: critical one (all sites' slopes moved together from ``sigma2`` toward their steepest, the
    #: loop turns unstable at that fraction); ``None`` for a site without such a band. Empty
    #: unless ``stribeck_unstable``.
    bands: tuple = ()

    @property
    def unstable(self) -> bool:
        return self.closed and math.isfinite(self.radius) and self.radius > 1.0 + RHO_MARGIN

    @property
    def stribeck_unstable(self) -> bool:
        """Stable with the viscous slopes, unstable at the steepest Stribeck slopes (hunting)."""
        return (self.closed and not self.unstable and math.isfinite(self.stribeck_radius)
                and self.stribeck_radius > 1.0 + RHO_MARGIN)

    @property
    def borderline(self) -> bool:
        """Stable, but the largest mode is lightly damped and decays slowly (``ZETA_LIGHT``, ``RHO_BORDER``)."""
        return (self.closed and not self.unstable and math.isfinite(self.radius)
                and self.radius > 1.0 - RHO_BORDER and self.zeta < ZETA_LIGHT)

    @property
    def suspect(self) -> bool:
        """Any of the three: the run's convergence must be checked (:func:`loop_check`)."""
        return self.unstable or self.stribeck_unstable or self.borderline

    def describe(self, dt: float) -> str:
        grow = (f"grows x{self.radius:.4g} per sample" if self.radius < 1e3 else
                f"grows x{self.radius:.3g} per sample")
        f = f"{self.frequency_hz:.4g} Hz mode" if self.frequency_hz > 0 else "non-oscillating mode"
        who = (f"the loop of actuator {', '.join(repr(a) for a in self.actuators)}" if self.actuators
               else "the coupled loops")
        if self.stribeck_unstable:
            return (f"the closed loop can hunt at low speed: linearised at the sample period {dt:.3g} s it is "
                    f"stable with friction as its viscous slope (radius {self.radius:.5g}) but unstable at the "
                    f"steepest Stribeck slope of its friction (radius {self.stribeck_radius:.5g} per sample)")
        if self.borderline:
            return (f"the closed loop is barely damped: linearised at the sample period {dt:.3g} s a {f} decays "
                    f"only x{self.radius:.5g} per sample (damping ratio {self.zeta:.3g}), mostly in {self.dof!r}")
        return (f"the closed loop is unstable: linearised at the sample period {dt:.3g} s (friction as "
                f"its viscous slope), a {f} {grow}, mostly in {self.dof!r}, through {who}")


def _sigma2(law) -> np.ndarray:
    """A law's sliding slope ``sigma2`` per direction (row 0: v >= 0, row 1: v < 0); scheduled
    static laws (``TDMSSC``) through their schedule rows, whose slope does not depend on the schedule."""
    from ..models.tdmssc import schedule_rows
    from .simulate import _static_rows, law_family

    if law_family(law) == "static":
        return schedule_rows(law)[:, 6]
    return _static_rows(law)[:, 4]


def _site_viscous(machine: Machine) -> np.ndarray:
    """Per friction site its sliding slope ``sigma2`` (the larger of the two directions)."""
    out = np.zeros(len(machine.sites))
    for j, s in enumerate(machine.sites):
        if s.role == "friction":
            out[j] = float(np.max(np.abs(_sigma2(s.law))))
    return out


#: Speeds (as multiples ``r = |v|/vs``) over which a Stribeck curve's steepest slope is sought
#: (assumption): below ``vs/1000`` a dynamic law is in pre-sliding and a static law in its stick
#: band, so a curve with ``delta < 1`` (infinite slope at 0) is read from ``r = 1e-3``; above
#: ``30 vs`` the curve is flat to ``exp(-30)``.
STRIBECK_R = np.geomspace(1e-3, 30.0, 600)


def _steepest_slope(law) -> float:
    """The most negative ``dF/dv`` of a law's steady-state curve (``sigma2`` minus the Stribeck
    drop's steepest descent), over both directions: the damping the loop sees at the worst
    low sliding speed. Scheduled levels (``TDMSSC``) at schedule 0, as the kernel's live rows."""
    from ..models.tdmssc import schedule_rows
    from .simulate import _static_rows, law_family

    if law_family(law) == "static":
        r9 = schedule_rows(law)
        rows = np.column_stack([r9[:, 0], r9[:, 2], r9[:, 4], r9[:, 5], r9[:, 6], r9[:, 7]])
    else:
        rows = _static_rows(law)
    r = STRIBECK_R
    worst = math.inf
    for Fc, Fs, vs, delta, sigma2, shape in rows:
        with np.errstate(over="ignore", under="ignore"):
            # -dphi/dr of exp(-r^delta) or 1/(1 + r^2)
            dphi = (delta * r ** (delta - 1.0) * np.exp(-(r ** delta)) if shape == 0.0
                    else 2.0 * r / (1.0 + r * r) ** 2)
        worst = min(worst, float(sigma2 - (Fs - Fc) / vs * float(np.max(dphi))))
    return worst


def _site_stribeck(machine: Machine) -> np.ndarray:
    """Per friction site its steepest steady-state slope (:func:`_steepest_slope`; may be < 0)."""
    out = np.zeros(len(machine.sites))
    for j, s in enumerate(machine.sites):
        if s.role == "friction":
            out[j] = _steepest_slope(s.law)
    return out


def _produced(machine: Machine) -> set:
    out = {s.name for s in machine.sensors} | {f"{a.name}.applied" for a in machine.actuators}
    for b in machine.blocks:
        out |= set(b.outputs)
    return out


def has_feedback(machine: Machine) -> bool:
    """An actuator follows a controller signal or sensor (not an input array)."""
    produced = _produced(machine)
    return bool(machine.sensors) and any(a.command in produced for a in machine.actuators)


def closed_loop_matrix(machine: Machine, dt: float, *, open_actuator: int | None = None,
                       site_slopes: np.ndarray | None = None) -> np.ndarray:
    """The linearised one-sample map ``z_{k+1} = A z_k`` of machine + controller.

    ``z`` = ``[q, v`` (the chain), every signal's last value, PID states (integral,
    derivative, last derivative error), StateSpace states, sensor and actuator delay lines``]``.
    Inputs (references, feed-forwards, motions) are zero; noise, quantisation, saturation
    and actuator limits are left out (the operating point is inside the limits).
    ``open_actuator``: that actuator's command is held at zero (its loop opened).
    ``site_slopes``: each friction site's slope ``dF/dv`` (default: its viscous ``sigma2``).
    """
    from .simulate import discretise

    n = machine.n
    slopes = _site_viscous(machine) if site_slopes is None else site_slopes
    Phi, G0, _, _, _ = discretise(machine, dt, site_damping=slopes)
    nact = len(machine.actuators)
    names: list[str] = []

    def add(nm):
        if nm not in names:
            names.append(nm)

    for s in machine.sensors:
        add(s.name)
    for b in machine.blocks:
        for nm in (*b.outputs, *b.inputs):
            add(nm)
    for a in machine.actuators:
        add(a.command)
        add(f"{a.name}.applied")
    dim = 2 * n
    sig0 = dim
    dim += len(names)
    boff = []
    for b in machine.blocks:
        boff.append(dim)
        if isinstance(b, PID):
            dim += 3
        elif isinstance(b, StateSpace):
            dim += np.atleast_2d(np.asarray(b.A, dtype=float)).shape[0]
    soff = []
    for s in machine.sensors:
        soff.append(dim)
        dim += s.delay
    aoff = []
    for a in machine.actuators:
        aoff.append(dim)
        dim += a.delay
    eye = np.eye(dim)
    new = np.zeros((dim, dim))
    produced = _produced(machine)
    cur = {nm: (eye[sig0 + i].copy() if nm in produced else np.zeros(dim)) for i, nm in enumerate(names)}

    def delay_line(o: int, d: int, y: np.ndarray) -> np.ndarray:
        if d == 0:
            return y
        new[o] = y
        for q in range(1, d):
            new[o + q] = eye[o + q - 1]
        return eye[o + d - 1].copy()

    for i, s in enumerate(machine.sensors):
        row, _ = machine.row(s.at)
        y = np.zeros(dim)
        y[(n if s.quantity == "velocity" else 0):][:n] = row
        cur[s.name] = delay_line(soff[i], s.delay, y)
    for bi, b in enumerate(machine.blocks):
        o = boff[bi]
        if isinstance(b, Sum):
            y = np.zeros(dim)
            for k, w in b.terms.items():
                y = y + w * cur[k]
            cur[b.out] = y
        elif isinstance(b, PID):
            e, ed = cur[b.error], cur[b.derivative_error or b.error]
            dterm = (b.tau_d * eye[o + 1] + b.Kd * (ed - eye[o + 2])) / (b.tau_d + dt)
            new[o + 1] = dterm
            new[o + 2] = ed
            cur[b.out] = b.Kp * e + eye[o] + dterm
        elif isinstance(b, StateSpace):
            A = np.atleast_2d(np.asarray(b.A, dtype=float))
            B = np.atleast_2d(np.asarray(b.B, dtype=float))
            C = np.atleast_2d(np.asarray(b.C, dtype=float))
            D = np.atleast_2d(np.asarray(b.D, dtype=float))
            nx = A.shape[0]
            U = np.array([cur[k] for k in b.inputs])
            Xs = eye[o:o + nx]
            new[o:o + nx] = A @ Xs + B @ U
            for r, nm in enumerate(b.outputs):
                cur[nm] = C[r] @ Xs + D[r] @ U
        elif isinstance(b, Saturation):
            cur[b.out] = cur[b.inp].copy()
        elif isinstance(b, FrictionFeedforward):
            slope = float(np.mean(_sigma2(b.law)))
            cur[b.out] = b.scale * slope * cur[b.velocity]
    U = np.zeros((nact, dim))
    for i, a in enumerate(machine.actuators):
        u = cur[a.command] if (a.command in produced and i != open_actuator) else np.zeros(dim)
        u = delay_line(aoff[i], a.delay, u)
        U[i] = u
        cur[f"{a.name}.applied"] = u
    for bi, b in enumerate(machine.blocks):
        if isinstance(b, PID):  # the integrator after the actuators, on this sample's error
            o = boff[bi]
            new[o] = eye[o] + b.Ki * dt * cur[b.error]
    for i, nm in enumerate(names):
        new[sig0 + i] = cur[nm]
    new[:2 * n, :2 * n] += Phi
    new[:2 * n] += G0[:, :nact] @ U
    return new


def loop_stability(machine: Machine, dt: float) -> LoopStability:
    """Spectral radius of :func:`closed_loop_matrix` and which loop makes it (see the module)."""
    if not has_feedback(machine):
        return LoopStability(math.nan, 0.0, "", (), False)
    A = closed_loop_matrix(machine, dt)
    if not np.all(np.isfinite(A)):
        return LoopStability(math.inf, 0.0, "", (), True)
    lam, V = np.linalg.eig(A)
    i = int(np.argmax(np.abs(lam)))
    rho = float(abs(lam[i]))
    n = machine.n
    w = np.sqrt(np.abs(np.diag(machine.mass_matrix())))
    vel = np.abs(V[n:2 * n, i]) * w
    dof = machine.dofs[int(np.argmax(vel))].name if n else ""
    freq = abs(float(np.angle(lam[i]))) / (2.0 * math.pi * dt)
    zeta = 1.0
    if freq > 0.0 and rho > 0.0:  # s = ln(lambda)/dt; zeta = -Re s / |s|
        sre, sim = math.log(rho), float(np.angle(lam[i]))
        zeta = -sre / math.hypot(sre, sim)
    visc, steep = _site_viscous(machine), _site_stribeck(machine)
    srho = math.nan
    if rho <= 1.0 + RHO_MARGIN and np.any(steep < visc):
        B = closed_loop_matrix(machine, dt, site_slopes=np.minimum(steep, visc))
        if np.all(np.isfinite(B)):
            srho = float(np.max(np.abs(np.linalg.eigvals(B))))
    bands: tuple = ()
    if math.isfinite(srho) and srho > 1.0 + RHO_MARGIN:
        bands = _hunting_bands(machine, dt, visc, np.minimum(steep, visc))
    acts: list[str] = []
    if rho > 1.0 + RHO_MARGIN and len(machine.actuators) > 1:
        for ai, a in enumerate(machine.actuators):
            r_open = float(np.max(np.abs(np.linalg.eigvals(closed_loop_matrix(machine, dt, open_actuator=ai)))))
            if r_open <= 1.0 + RHO_MARGIN:
                acts.append(a.name)
    elif rho > 1.0 + RHO_MARGIN and machine.actuators:
        acts.append(machine.actuators[0].name)
    return LoopStability(rho, freq, dof, tuple(acts), True, srho, zeta, bands)


def _hunting_bands(machine: Machine, dt: float, visc: np.ndarray, steep: np.ndarray) -> tuple:
    """Per site the speeds where its steady-state slope lies below the loop's critical slope:
    the fraction ``a`` with slopes ``visc + a (steep - visc)`` at radius 1 by bisection (30
    eigenvalue problems, only for a loop :attr:`LoopStability.stribeck_unstable`), then each
    site's curve on :data:`STRIBECK_R` read against its critical slope."""
    from ..models.tdmssc import schedule_rows
    from .simulate import _static_rows, law_family

    def radius(a):
        A = closed_loop_matrix(machine, dt, site_slopes=visc + a * (steep - visc))
        return float(np.max(np.abs(np.linalg.eigvals(A))))

    lo, hi = 0.0, 1.0
    for _ in range(30):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if radius(mid) > 1.0 + RHO_MARGIN else (mid, hi)
    out = []
    r = STRIBECK_R
    for j, s in enumerate(machine.sites):
        if s.role != "friction" or not steep[j] < visc[j]:
            out.append(None)
            continue
        crit = visc[j] + hi * (steep[j] - visc[j])
        if law_family(s.law) == "static":
            r9 = schedule_rows(s.law)
            rows = np.column_stack([r9[:, 0], r9[:, 2], r9[:, 4], r9[:, 5], r9[:, 6], r9[:, 7]])
        else:
            rows = _static_rows(s.law)
        vlo, vhi = math.inf, 0.0
        for Fc, Fs, vs, delta, sigma2, shape in rows:
            with np.errstate(over="ignore", under="ignore"):
                dphi = (delta * r ** (delta - 1.0) * np.exp(-(r ** delta)) if shape == 0.0
                        else 2.0 * r / (1.0 + r * r) ** 2)
            inside = r[sigma2 - (Fs - Fc) / vs * dphi < crit] * vs
            if inside.size:
                vlo, vhi = min(vlo, float(inside.min())), max(vhi, float(inside.max()))
        out.append((vlo, vhi) if vhi > 0.0 else None)
    return tuple(out)


def _hunting_samples(machine: Machine, res, stab: LoopStability) -> int:
    """Samples of ``res`` with some site's speed inside its hunting band (:attr:`LoopStability.bands`)."""
    inside = np.zeros(res.v.shape[0], dtype=bool)
    for j, band in enumerate(stab.bands):
        if band is None:
            continue
        row, _ = machine.row(machine.sites[j].at)
        sv = np.abs(res.v @ np.asarray(row, dtype=float))
        inside |= (sv >= band[0]) & (sv <= band[1])
    return int(inside.sum())


#: A loop that can hunt (:attr:`LoopStability.stribeck_unstable`) is checked for convergence only
#: when its sites spend at least the samples a disturbance needs to grow by this factor at the
#: Stribeck radius inside their hunting bands (assumption: from float rounding, ~1e-9 of a trace,
#: to 1e-3 of it, below which no bound of the check can see it). The SDSS reproduction's
#: constant-velocity runs outside the band pay nothing (measured: with the check on every run of a
#: hunting-prone axis, `frictionkit reproduce sdss --quick` went from 6.3 to 47 s).
HUNT_GROWTH = 1e6

#: A loop checked only because it can hunt (stable with the viscous slopes, not barely damped) is
#: rerun at this factor x its sub-steps, not ``SUBSTEP_CHECK_FACTOR`` (16): the check asks whether
#: the stick-slip limit cycle depends on the sub-steps, and with first-order convergence the run at
#: 4x sees 3/4 of the distance to the converged trace (16x: 15/16), so a bound of 1 % checked at 4x
#: holds the trace to ~1.33 % of its range (assumption, issue 13). Measured 2026-11-23 (lead): on
#: the zhang2023 quick reproduction 25 of 33 runs are hunting-checked; the reruns took 46.7 of its
#: 67.7 s CPU at 16x.
HUNT_CHECK_FACTOR = 4


def _at_limit(machine: Machine, res) -> dict:
    """Per limited actuator the fraction of samples at its limit."""
    out = {}
    for i, a in enumerate(machine.actuators):
        if math.isfinite(a.limit) and res.u.shape[0]:
            with np.errstate(invalid="ignore"):
                out[a.name] = float(np.mean(np.abs(res.u[:, i]) >= a.limit * (1.0 - 1e-12)))
    return out


def _disagreement(res, fine, machine: Machine | None = None) -> tuple[float, str]:
    """Largest disagreement of ``res`` with ``fine`` as a multiple of its bound (positions
    ``CHECK_TOL_POSITION``, velocities and actuator commands ``CHECK_TOL_RATE`` of their range in
    ``fine``; with ``machine``, also its dynamic site forces at ``CHECK_TOL_RATE`` of the range the
    sub-step check judges them by, :func:`.simulate.site_force_spans`), and a sentence naming the worst
    trace. Site forces (issue 13, helper lugw2's campaign): zhang2023's two-shaft drive with perturbed
    assumptions (15 kg table, 1.2e7 N/m axial chain) hunts in a limit cycle whose positions, velocities
    and commands agree within their bounds at every sub-step count while its support and ball-load
    frictions stay 13-20 % of their ranges apart (20, 40, 160, 640 sub-steps): "the run converges" was
    said of forces that do not."""
    from .simulate import CHECK_TOL_POSITION, CHECK_TOL_RATE, site_force_spans

    worst, frac = "", 0.0
    traces = [(res.q, fine.q, res.dof_names, "position", CHECK_TOL_POSITION, None),
              (res.v, fine.v, res.dof_names, "velocity", CHECK_TOL_RATE, None),
              (res.u, fine.u, res.actuator_names, "command", CHECK_TOL_RATE, None)]
    if machine is not None and fine.site_forces.shape[0]:
        traces.append((res.site_forces, fine.site_forces, res.site_names, "force", CHECK_TOL_RATE,
                       site_force_spans(machine, fine)))
    for arr, ref, names, what, tol, fspan in traces:
        for i, name in enumerate(names):
            if fspan is not None and fspan[i] is None:
                continue  # a static site's force: a sub-step mean (site_force_spans)
            with np.errstate(invalid="ignore"):
                d = float(np.nanmax(np.abs(arr[:, i] - ref[:, i]))) if arr.shape[0] else 0.0
                span = (float(np.ptp(ref[:, i])) if ref.shape[0] else 0.0) if fspan is None else fspan[i]
            f = d / (tol * span + 1e-9 * float(np.max(np.abs(ref[:, i]), initial=0.0)) + 1e-300)
            if f > frac:
                frac = f
                worst = (f"{what} of {name!r} moves by {d:.3g} ({100 * d / span if span else math.inf:.3g} % of "
                         f"its range{'' if fspan is None else ' (the largest force range on its bodies)'}; "
                         f"bound {100 * tol:g} %)")
    return frac, worst


#: largest closed-loop state (DOF positions and velocities plus delay-line samples) the screen
#: linearises: its eigenvalue problem grows as dim^3 (issue 13 round 5: an actuator delay of
#: 10,000 samples spent 648 s here). Assumption: 2,000 keeps the screen under ~5 s.
SCREEN_MAX_DIM = 2000


_SCREENS: OrderedDict = OrderedDict()
#: screens remembered (by the machine's JSON form and dt): a hunting-prone loop's bands cost ~30
#: eigenvalue problems, paid once for the many runs of one machine (the SDSS speed sweeps)
SCREEN_CACHE = 16


def _cached_stability(machine: Machine, dt: float) -> LoopStability:
    from .simulate import _fingerprint

    fp = _fingerprint(machine)
    return remember(_SCREENS, None if fp is None else (fp, float(dt)), lambda: loop_stability(machine, dt), SCREEN_CACHE)


def screen(machine: Machine, dt: float) -> tuple:
    """``(stability, "")`` — the machine's :class:`LoopStability` at ``dt`` (remembered, see
    ``SCREEN_CACHE``) — or ``(None, note)`` when the screen is skipped: a state larger than
    ``SCREEN_MAX_DIM`` or a screen that fails (it must never break a run: a TDMSSC site once did).
    Used by :func:`loop_check` and by the one-DOF fast path's dispatch."""
    dim = (2 * machine.n + sum(s.delay for s in machine.sensors) + sum(a.delay for a in machine.actuators))
    if has_feedback(machine) and dim > SCREEN_MAX_DIM:
        return None, (f"note: the closed-loop stability screen was skipped (its state has {dim} > {SCREEN_MAX_DIM} "
                      "entries, mostly delay-line samples: an eigenvalue problem of that size costs minutes)")
    try:
        return _cached_stability(machine, dt), ""
    except Exception as exc:
        return None, f"note: the closed-loop stability screen was skipped ({type(exc).__name__}: {exc})"


def loop_check(machine: Machine, res, dt: float, rerun):
    """Flag ``res`` (status 2) when the loop is linearly unstable, hunting-prone inside its band or
    barely damped (:attr:`LoopStability.suspect`, see the module) and the run does not converge: at ``SUBSTEP_CHECK_FACTOR`` x the sub-steps (``rerun(substeps)``
    runs the machine again) a position moves by more than 1 % of its range, or a velocity or
    actuator command by more than 10 % (the sub-step check's bounds). A converged run keeps its
    status and the message notes the unstable mode. A stable loop, an open-loop machine or a
    failed run returns ``res`` untouched (one eigenvalue problem, ~0.3-1.5 ms)."""
    from .simulate import STATUS_TOLERANCE, SUBSTEP_CHECK_FACTOR

    if res.status != 0 or res.substeps < 1:
        return res
    stab, note = screen(machine, dt)
    if stab is None:
        return dataclasses.replace(res, message=f"{res.message}; {note}")
    if not stab.suspect:
        return res
    if stab.stribeck_unstable and not stab.borderline:
        need = math.log(HUNT_GROWTH) / math.log(stab.stribeck_radius)
        if _hunting_samples(machine, res, stab) < need:
            return res
    detail = stab.describe(dt)
    lim = _at_limit(machine, res)
    limits = "; ".join(f"actuator {a!r} at its limit in {100 * f:.3g} % of the samples"
                       for a, f in lim.items() if f > 0)
    if limits:
        detail = f"{detail}; {limits}"
    hunting_only = stab.stribeck_unstable and not stab.unstable and not stab.borderline
    fine_n = (HUNT_CHECK_FACTOR if hunting_only else SUBSTEP_CHECK_FACTOR) * res.substeps
    fine = rerun(fine_n)
    if fine.status != 0:
        frac, worst = math.inf, f"check run at {fine_n} sub-steps failed ({fine.message})"
    else:
        frac, worst = _disagreement(res, fine, machine)
    if frac <= 1.0:
        what = "a limit cycle; " if stab.unstable or stab.stribeck_unstable else ""
        return dataclasses.replace(res, message=f"{res.message}; note: {detail} ({what}the run converges: "
                                                f"at {fine_n} sub-steps every trace within its bound)")
    todo = ("Run it with more substeps= (or atol=) until it converges, or give the loop more damping"
            if stab.borderline else
            "Lower that loop's gains or give the controller the inertias it was designed for"
            if stab.unstable else
            "Run it with more substeps= (or atol=) until it converges; the hunting itself is the friction's "
            "physics (more derivative gain or friction feed-forward reduces it)")
    message = (f"result not converged: {detail}; at {fine_n} sub-steps the {worst}. {todo} "
               "(frictionkit.machines.stability.loop_stability(machine, dt) gives the radii)")
    return dataclasses.replace(res, status=STATUS_TOLERANCE, message=message)
