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
2. Only then the run is repeated at ``SUBSTEP_CHECK_FACTOR`` (16) x the sub-steps; when a
   position disagrees by more than 1 % of its range, or a velocity or actuator command by more
   than 10 % (the sub-step check's bounds), or the finer run fails, the result is status 2 (``STATUS_TOLERANCE``) with a message naming the unstable mode, the
   actuator whose loop it is and what to do. A converged run keeps its status and the
   message notes the unstable mode and the time at the limit.

Linearly stable loops cost one eigenvalue problem per run (a 30–60 state matrix).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from .elements import PID, FrictionFeedforward, Saturation, StateSpace, Sum
from .machine import Machine

#: A mode counts as unstable when its magnitude per sample exceeds ``1 + RHO_MARGIN``: it then
#: grows at least e-fold in 1e6 samples (slower growth is no defect any run could show; a free
#: rigid body's double eigenvalue 1 splits by ~1e-8 in floating point).
RHO_MARGIN = 1e-6


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

    @property
    def unstable(self) -> bool:
        return self.closed and math.isfinite(self.radius) and self.radius > 1.0 + RHO_MARGIN

    def describe(self, dt: float) -> str:
        grow = (f"grows x{self.radius:.4g} per sample" if self.radius < 1e3 else
                f"grows x{self.radius:.3g} per sample")
        f = f"{self.frequency_hz:.4g} Hz mode" if self.frequency_hz > 0 else "non-oscillating mode"
        who = (f"the loop of actuator {', '.join(repr(a) for a in self.actuators)}" if self.actuators
               else "the coupled loops")
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


def _produced(machine: Machine) -> set:
    out = {s.name for s in machine.sensors} | {f"{a.name}.applied" for a in machine.actuators}
    for b in machine.blocks:
        out |= set(b.outputs)
    return out


def has_feedback(machine: Machine) -> bool:
    """An actuator follows a controller signal or sensor (not an input array)."""
    produced = _produced(machine)
    return bool(machine.sensors) and any(a.command in produced for a in machine.actuators)


def closed_loop_matrix(machine: Machine, dt: float, *, open_actuator: int | None = None) -> np.ndarray:
    """The linearised one-sample map ``z_{k+1} = A z_k`` of machine + controller.

    ``z`` = ``[q, v`` (the chain), every signal's last value, PID states (integral,
    derivative, last derivative error), StateSpace states, sensor and actuator delay lines``]``.
    Inputs (references, feed-forwards, motions) are zero; noise, quantisation, saturation
    and actuator limits are left out (the operating point is inside the limits).
    ``open_actuator``: that actuator's command is held at zero (its loop opened).
    """
    from .simulate import discretise

    n = machine.n
    Phi, G0, _, _, _ = discretise(machine, dt, site_damping=_site_viscous(machine))
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
    acts: list[str] = []
    if rho > 1.0 + RHO_MARGIN and len(machine.actuators) > 1:
        for ai, a in enumerate(machine.actuators):
            r_open = float(np.max(np.abs(np.linalg.eigvals(closed_loop_matrix(machine, dt, open_actuator=ai)))))
            if r_open <= 1.0 + RHO_MARGIN:
                acts.append(a.name)
    elif rho > 1.0 + RHO_MARGIN and machine.actuators:
        acts.append(machine.actuators[0].name)
    return LoopStability(rho, freq, dof, tuple(acts), True)


def _at_limit(machine: Machine, res) -> dict:
    """Per limited actuator the fraction of samples at its limit."""
    out = {}
    for i, a in enumerate(machine.actuators):
        if math.isfinite(a.limit) and res.u.shape[0]:
            with np.errstate(invalid="ignore"):
                out[a.name] = float(np.mean(np.abs(res.u[:, i]) >= a.limit * (1.0 - 1e-12)))
    return out


def _disagreement(res, fine) -> tuple[float, str]:
    """Largest disagreement of ``res`` with ``fine`` as a multiple of its bound (positions
    ``CHECK_TOL_POSITION``, velocities and actuator commands ``CHECK_TOL_RATE`` of their range in
    ``fine``), and a sentence naming the worst trace."""
    from .simulate import CHECK_TOL_POSITION, CHECK_TOL_RATE

    worst, frac = "", 0.0
    for arr, ref, names, what, tol in ((res.q, fine.q, res.dof_names, "position", CHECK_TOL_POSITION),
                                       (res.v, fine.v, res.dof_names, "velocity", CHECK_TOL_RATE),
                                       (res.u, fine.u, res.actuator_names, "command", CHECK_TOL_RATE)):
        for i, name in enumerate(names):
            with np.errstate(invalid="ignore"):
                d = float(np.nanmax(np.abs(arr[:, i] - ref[:, i]))) if arr.shape[0] else 0.0
                span = float(np.ptp(ref[:, i])) if ref.shape[0] else 0.0
            f = d / (tol * span + 1e-9 * float(np.max(np.abs(ref[:, i]), initial=0.0)) + 1e-300)
            if f > frac:
                frac = f
                worst = (f"{what} of {name!r} moves by {d:.3g} ({100 * d / span if span else math.inf:.3g} % of "
                         f"its range; bound {100 * tol:g} %)")
    return frac, worst


#: largest closed-loop state (DOF positions and velocities plus delay-line samples) the screen
#: linearises: its eigenvalue problem grows as dim^3 (issue 13 round 5: an actuator delay of
#: 10,000 samples spent 648 s here). Assumption: 2,000 keeps the screen under ~5 s.
SCREEN_MAX_DIM = 2000


def loop_check(machine: Machine, res, dt: float, rerun):
    """Flag ``res`` (status 2) when the loop is linearly unstable (:func:`loop_stability`) and
    the run does not converge: at ``SUBSTEP_CHECK_FACTOR`` x the sub-steps (``rerun(substeps)``
    runs the machine again) a position moves by more than 1 % of its range, or a velocity or
    actuator command by more than 10 % (the sub-step check's bounds). A converged run keeps its
    status and the message notes the unstable mode. A stable loop, an open-loop machine or a
    failed run returns ``res`` untouched (one eigenvalue problem, ~0.3-1.5 ms)."""
    from .simulate import STATUS_TOLERANCE, SUBSTEP_CHECK_FACTOR

    if res.status != 0 or res.substeps < 1:
        return res
    dim = (2 * machine.n + sum(s.delay for s in machine.sensors) + sum(a.delay for a in machine.actuators))
    if has_feedback(machine) and dim > SCREEN_MAX_DIM:
        return dataclasses.replace(res, message=f"{res.message}; note: the closed-loop stability screen was skipped "
                                                f"(its state has {dim} > {SCREEN_MAX_DIM} entries, mostly delay-line "
                                                "samples: an eigenvalue problem of that size costs minutes)")
    try:
        stab = loop_stability(machine, dt)
    except Exception as exc:  # a screen must never break a finished run (a TDMSSC site once did)
        return dataclasses.replace(res, message=f"{res.message}; note: the closed-loop stability screen was skipped "
                                                f"({type(exc).__name__}: {exc})")
    if not stab.unstable:
        return res
    detail = stab.describe(dt)
    lim = _at_limit(machine, res)
    limits = "; ".join(f"actuator {a!r} at its limit in {100 * f:.3g} % of the samples"
                       for a, f in lim.items() if f > 0)
    if limits:
        detail = f"{detail}; {limits}"
    fine_n = SUBSTEP_CHECK_FACTOR * res.substeps
    fine = rerun(fine_n)
    if fine.status != 0:
        frac, worst = math.inf, f"check run at {fine_n} sub-steps failed ({fine.message})"
    else:
        frac, worst = _disagreement(res, fine)
    if frac <= 1.0:
        return dataclasses.replace(res, message=f"{res.message}; note: {detail} (a limit cycle; the run converges: "
                                                f"at {fine_n} sub-steps every trace within its bound)")
    message = (f"result not converged: {detail}; at {fine_n} sub-steps the {worst}. "
               "Lower that loop's gains or give the controller the inertias it was designed for "
               "(frictionkit.machines.stability.loop_stability(machine, dt) gives the radius)")
    return dataclasses.replace(res, status=STATUS_TOLERANCE, message=message)
