"""The parts a machine is made of: coordinates, nonlinear compliances, loads, controller blocks.

Everything here is a frozen, validated parameter object; :class:`~frictionkit.machines.Machine`
assembles them and :func:`~frictionkit.machines.simulate_machine` packs them for the kernel.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import _validate as val
from ..errors import ParameterError
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from numpy.typing import ArrayLike
    from typing import Any


# --------------------------------------------------------------------------- coordinates
class Coord:
    """A point of a machine: a linear combination of its degrees of freedom and prescribed motions.

    Returned by :meth:`Machine.dof` and :meth:`Machine.motion`; combine them with ``+``, ``-``
    and scalar ``*`` / ``/``. A rigid transmission is such a combination: a table driven by a
    screw of lead ratio ``R`` [m/rad] sits at ``R * theta``; seed 000's worktable at
    ``R * (theta1 + theta2)``.

    Examples
    --------
    >>> import frictionkit as fk
    >>> m = fk.Machine()
    >>> th1 = m.dof("screw", inertia=1e-3, kind="rotational")
    >>> th2 = m.dof("nut", inertia=1e-3, kind="rotational")
    >>> 0.5 * (th1 + th2)
    Coord(0.5*screw + 0.5*nut)
    """

    __slots__ = ("_owner", "dofs", "motions")

    def __init__(self, owner: Any, dofs: dict[int, float], motions: dict[int, float]):
        self._owner = owner
        self.dofs = {i: float(c) for i, c in dofs.items() if c != 0.0}
        self.motions = {i: float(c) for i, c in motions.items() if c != 0.0}

    def _check(self, other) -> "Coord":
        if not isinstance(other, Coord):
            raise ParameterError(
                f"cannot combine a machine coordinate with {type(other).__name__} {other!r}: "
                "add or subtract coordinates, multiply by numbers"
            )
        if other._owner is not self._owner:
            raise ParameterError("cannot combine coordinates of two different machines")
        return other

    def __add__(self, other):
        other = self._check(other)
        d = dict(self.dofs)
        for i, c in other.dofs.items():
            d[i] = d.get(i, 0.0) + c
        mo = dict(self.motions)
        for i, c in other.motions.items():
            mo[i] = mo.get(i, 0.0) + c
        return Coord(self._owner, d, mo)

    def __neg__(self):
        return Coord(self._owner, {i: -c for i, c in self.dofs.items()},
                     {i: -c for i, c in self.motions.items()})

    def __sub__(self, other):
        return self + (-self._check(other))

    def __mul__(self, k):
        if isinstance(k, bool) or not isinstance(k, (int, float, np.integer, np.floating)):
            raise ParameterError(f"a machine coordinate can only be scaled by a number, got {k!r}")
        k = val.finite("Coord", "scale", k)
        return Coord(self._owner, {i: c * k for i, c in self.dofs.items()},
                     {i: c * k for i, c in self.motions.items()})

    __rmul__ = __mul__

    def __truediv__(self, k):
        k = val.finite("Coord", "divisor", k)
        if k == 0.0:
            raise ParameterError("Coord divisor = 0.0: must be non-zero")
        return self * (1.0 / k)

    @property
    def is_empty(self) -> bool:
        return not self.dofs and not self.motions

    @property
    def position(self) -> "CoordSignal":
        """This coordinate's position as a machine input a friction site can read
        (``Machine.friction(..., schedule=coord.position)``)."""
        return CoordSignal(self, "position")

    @property
    def velocity(self) -> "CoordSignal":
        """This coordinate's velocity as a machine input a friction site can read, e.g. a
        TDMSSC's base speed: ``Machine.friction("nut", ..., schedule=(R * theta2).velocity)``."""
        return CoordSignal(self, "velocity")

    def to_dict(self) -> dict:
        """JSON form: ``{name: coefficient}`` over its degrees of freedom, then its motions
        (``Machine.from_dict`` reads it back)."""
        names, mnames = self._owner._dof_names, self._owner._motion_names
        return {**{names[i]: c for i, c in self.dofs.items()}, **{mnames[i]: c for i, c in self.motions.items()}}

    def __repr__(self) -> str:
        names = self._owner._dof_names
        mnames = self._owner._motion_names
        parts = [f"{c:g}*{names[i]}" if c != 1.0 else names[i] for i, c in sorted(self.dofs.items())]
        parts += [f"{c:g}*{mnames[i]}" if c != 1.0 else mnames[i] for i, c in sorted(self.motions.items())]
        return "Coord(" + (" + ".join(parts) if parts else "0") + ")"


class CoordSignal:
    """The position or velocity of a machine coordinate, read by a friction site as an input.

    Made by :attr:`Coord.position` / :attr:`Coord.velocity`; passed as ``schedule=`` to
    :meth:`Machine.friction` for a law with a scheduling variable (:class:`~frictionkit.TDMSSC`:
    its levels are affine in it). Units are the coordinate's (m, rad; per second for a
    velocity): scale the coordinate to the unit the law expects, e.g. ``(R * theta2).velocity``
    for a nut's linear-equivalent speed [m/s]. In the compiled loop it is read at the start of
    every sub-step.

    Examples
    --------
    >>> import frictionkit as fk
    >>> m = fk.Machine()
    >>> th2 = m.dof("nut", inertia=5e-4, kind="rotational")
    >>> (0.5 * th2).velocity
    CoordSignal(Coord(0.5*nut).velocity)
    """

    __slots__ = ("at", "quantity")

    def __init__(self, at: Coord, quantity: str):
        if not isinstance(at, Coord):
            raise ParameterError(f"CoordSignal.at = {at!r}: must be a machine coordinate")
        if quantity not in ("position", "velocity"):
            raise ParameterError(f"CoordSignal.quantity = {quantity!r}: must be 'position' or 'velocity'")
        self.at = at
        self.quantity = quantity

    def __repr__(self) -> str:
        return f"CoordSignal({self.at!r}.{self.quantity})"


# --------------------------------------------------------------------------- compliances and loads
@dataclass(frozen=True, kw_only=True)
class HertzContact:
    """Two preloaded Hertzian contact sets (a preloaded ball nut or bearing pair).

    ``F(d) = c (d0 + d)_+^1.5 - c (d0 - d)_+^1.5`` with ``c d0^1.5 = preload`` and the
    stiffness at zero load ``dF/dd(0) = 3 c d0^0.5 = stiffness``, so ``d0 = 3 P / k`` and
    ``c = P / d0^1.5``. Beyond ``|F| = 2^1.5 P`` one set unloads (seed 001 nut model
    ``"hertz"``). The linear part ``stiffness * d`` is solved exactly with the chain; the
    rest is a site force.

    Parameters
    ----------
    preload : float — preload ``P`` of each set [N], > 0.
    stiffness : float — axial stiffness of the preloaded pair at zero load [N/m], > 0.
    """

    preload: float
    stiffness: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "preload", val.positive("HertzContact", "preload", self.preload))
        object.__setattr__(self, "stiffness", val.positive("HertzContact", "stiffness", self.stiffness))

    @property
    def d0(self) -> float:
        """Preload deflection of each set [m]."""
        return 3.0 * self.preload / self.stiffness

    @property
    def c(self) -> float:
        """Hertz constant [N/m^1.5]."""
        return self.preload / self.d0**1.5

    @property
    def linear_stiffness(self) -> float:
        return self.stiffness

    def force(self, d: ArrayLike) -> np.ndarray:
        """Net contact force [N] at deflection ``d`` [m] (NumPy)."""
        d = np.asarray(d, dtype=float)
        a = np.clip(self.d0 + d, 0.0, None)
        b = np.clip(self.d0 - d, 0.0, None)
        return self.c * (a**1.5 - b**1.5)

    def pack(self) -> list[float]:
        return [self.c, self.d0, self.stiffness]


@dataclass(frozen=True, kw_only=True)
class PiecewiseLinearSpring:
    """An odd spring whose stiffness changes with deflection: ``stiffness[i]`` between breaks.

    The catalogue model of a harmonic drive (stiffness ``K1`` up to torque ``T1``, ``K2`` up
    to ``T2``, ``K3`` beyond): build it with :meth:`from_torque_breaks`. Real harmonic drives
    stiffen with load (K1 < K2 < K3); any positive values are accepted.

    Parameters
    ----------
    stiffness : sequence of float — ``k_0 .. k_{m-1}`` [N/m or N·m/rad], each > 0.
    breaks : sequence of float — deflections ``|d|`` where the stiffness changes [m or rad],
        increasing, ``m - 1`` of them.
    """

    stiffness: tuple
    breaks: tuple = ()

    def __post_init__(self) -> None:
        o = "PiecewiseLinearSpring"
        k = val.vector(o, "stiffness", self.stiffness, rule="positive")
        b = np.array(self.breaks, dtype=float, ndmin=1) if len(self.breaks) else np.zeros(0)
        if b.size != k.size - 1:
            raise ParameterError(f"{o}: {k.size} stiffnesses need {k.size - 1} breaks, got {b.size}")
        if b.size:
            b = val.vector(o, "breaks", b, rule="positive")
            if np.any(np.diff(b) <= 0):
                raise ParameterError(f"{o}.breaks = {b.tolist()}: must be strictly increasing")
        object.__setattr__(self, "stiffness", tuple(k.tolist()))
        object.__setattr__(self, "breaks", tuple(b.tolist()))

    @classmethod
    def from_torque_breaks(cls, stiffness, torques) -> "PiecewiseLinearSpring":
        """From catalogue values: ``stiffness = (K1, K2, K3)``, ``torques = (T1, T2)``."""
        k = val.vector("PiecewiseLinearSpring", "stiffness", stiffness, rule="positive")
        T = val.vector("PiecewiseLinearSpring", "torques", torques, rule="positive")
        if T.size != k.size - 1:
            raise ParameterError(f"PiecewiseLinearSpring: {k.size} stiffnesses need {k.size - 1} torques")
        d, prev_T, prev_d = [], 0.0, 0.0
        for i, Ti in enumerate(T):
            prev_d = prev_d + (Ti - prev_T) / k[i]
            prev_T = Ti
            d.append(prev_d)
        return cls(stiffness=tuple(k), breaks=tuple(d))

    @property
    def linear_stiffness(self) -> float:
        return self.stiffness[0]

    def force(self, d: ArrayLike) -> np.ndarray:
        d = np.asarray(d, dtype=float)
        ad = np.abs(d)
        f = np.zeros_like(ad)
        lo = 0.0
        edges = list(self.breaks) + [math.inf]
        for k, hi in zip(self.stiffness, edges):
            f += k * np.clip(np.minimum(ad, hi) - lo, 0.0, None)
            lo = hi
        return np.sign(d) * f

    def pack(self) -> list[float]:
        return [self.stiffness[0], float(len(self.stiffness)), *self.stiffness, *self.breaks]


@dataclass(frozen=True, kw_only=True)
class SineLoad:
    """A position-dependent load ``F = amplitude sin(s + phase)`` (gravity imbalance).

    On a rotary axis whose centre of mass sits ``X`` from the axis, ``amplitude = m g X``
    [N·m]; ``s`` is the axis angle [rad] from the balanced position.
    """

    amplitude: float
    phase: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "amplitude", val.finite("SineLoad", "amplitude", self.amplitude))
        object.__setattr__(self, "phase", val.finite("SineLoad", "phase", self.phase))

    @property
    def linear_stiffness(self) -> float:
        return 0.0

    def force(self, s: ArrayLike) -> np.ndarray:
        return self.amplitude * np.sin(np.asarray(s, dtype=float) + self.phase)

    def pack(self) -> list[float]:
        return [self.amplitude, self.phase]


@dataclass(frozen=True, kw_only=True)
class NormalLoad:
    """A friction site's normal load as a function of the machine state.

    The site's law is given at the load ``reference``; at load ``N`` its levels, stiffnesses
    and damping (not its viscous ``sigma2``) scale by ``N / reference``. ``y`` is the force in
    the spring or compliance named ``on`` (its linear and nonlinear part plus its damper):

    * ``N = max(preload + gain y, floor_gain y, 0)`` — a load linear in ``y`` (seed 000: ball
      pair friction grows with axial load plus preload; ``gain = 1``), or one flank of a
      preloaded nut with the equal-stiffness split (``preload = P``, ``gain = s/2``,
      ``floor_gain = s`` for the flank ``s = +1/-1``: the set unloads beyond ``|y| = 2P``);
    * ``hertz_set = s`` (``on`` a :class:`HertzContact`): ``N = c (d0 + s d)_+^1.5``, the ball
      load of that contact set.

    When the load falls the contacts lose traction with it; when it rises the new contact area
    starts without traction (the friction force is kept) — the friction-law contract, item 5.
    """

    on: str
    reference: float
    preload: float = 0.0
    gain: float = 1.0
    floor_gain: float = 0.0
    hertz_set: int = 0

    def __post_init__(self) -> None:
        o = "NormalLoad"
        _name(o, "on", self.on)
        object.__setattr__(self, "reference", val.positive(o, "reference", self.reference))
        for f in ("preload", "gain", "floor_gain"):
            object.__setattr__(self, f, val.finite(o, f, getattr(self, f)))
        if self.hertz_set not in (0, 1, -1):
            raise ParameterError(f"{o}.hertz_set = {self.hertz_set!r}: must be 0 (linear load), +1 or -1")


# --------------------------------------------------------------------------- controller blocks
def _name(owner: str, field_: str, value) -> str:
    if not isinstance(value, str) or not value:
        raise ParameterError(f"{owner}.{field_} = {value!r}: must be a non-empty signal name")
    return value


@dataclass(frozen=True)
class Sum:
    """``out = bias + sum_i w_i signal_i`` — error signals, gains, constants, cross-axis distribution.

    Examples
    --------
    >>> from frictionkit.machines import Sum
    >>> Sum("e", {"r": 1.0, "scale": -1.0})
    Sum(out='e', terms={'r': 1.0, 'scale': -1.0}, bias=0.0)
    """

    out: str
    terms: dict
    bias: float = 0.0

    def __post_init__(self) -> None:
        _name("Sum", "out", self.out)
        if not isinstance(self.terms, dict):
            raise ParameterError(f"Sum.terms = {self.terms!r}: must be a dict signal -> weight "
                                 "(empty for a constant: Sum('c', {}, bias=1.0))")
        terms = {_name("Sum", "terms", k): val.finite("Sum", f"terms[{k!r}]", w) for k, w in self.terms.items()}
        object.__setattr__(self, "terms", terms)
        object.__setattr__(self, "bias", val.finite("Sum", "bias", self.bias))

    @property
    def inputs(self) -> tuple:
        return tuple(self.terms)

    @property
    def outputs(self) -> tuple:
        return (self.out,)


def Gain(out: str, inp: str, k: float) -> Sum:
    """``out = k * inp`` (a :class:`Sum` with one term)."""
    return Sum(out, {inp: k})


@dataclass(frozen=True)
class PID:
    """Discrete PID at the sample period: backward-Euler integral, filtered derivative.

    ``out = Kp e + I + D``, ``D_k = (tau_d D_{k-1} + Kd (ed_k - ed_{k-1})) / (tau_d + T)``,
    ``I += Ki T e`` after the sample unless ``antiwindup`` names an actuator that saturated
    (conditional integration). ``derivative_error`` (default ``error``) lets the derivative
    act on another signal, e.g. the motor encoder for collocated damping (seed 001).
    """

    out: str
    error: str
    Kp: float
    Ki: float = 0.0
    Kd: float = 0.0
    tau_d: float = 0.0
    derivative_error: str | None = None
    antiwindup: str | None = None

    def __post_init__(self) -> None:
        _name("PID", "out", self.out)
        _name("PID", "error", self.error)
        for f in ("Kp", "Ki", "Kd", "tau_d"):
            object.__setattr__(self, f, val.nonnegative("PID", f, getattr(self, f)))
        if self.derivative_error is not None:
            _name("PID", "derivative_error", self.derivative_error)
        if self.antiwindup is not None:
            _name("PID", "antiwindup", self.antiwindup)

    @property
    def inputs(self) -> tuple:
        return (self.error,) if self.derivative_error is None else (self.error, self.derivative_error)

    @property
    def outputs(self) -> tuple:
        return (self.out,)


@dataclass(frozen=True)
class StateSpace:
    """A discrete state-space block at the sample period — the way to add your own controller.

    ``y_k = C x_k + D u_k``, ``x_{k+1} = A x_k + B u_k``, with ``u`` the named ``inputs`` and
    ``y`` the named ``outputs``. Filters, observers, lead-lag compensators and discretised
    continuous controllers (``scipy.signal.cont2discrete``) all fit; it runs in the compiled
    loop, no numba needed.

    Examples
    --------
    A first-order low-pass of the scale signal at 1 kHz with pole 0.9:

    >>> from frictionkit.machines import StateSpace
    >>> lp = StateSpace(outputs=("y_f",), inputs=("scale",), A=[[0.9]], B=[[0.1]], C=[[1.0]], D=[[0.0]])
    >>> lp.A.shape
    (1, 1)
    """

    outputs: tuple
    inputs: tuple
    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    x0: np.ndarray | None = None

    def __post_init__(self) -> None:
        o = "StateSpace"
        outs = tuple(_name(o, "outputs", s) for s in (self.outputs if not isinstance(self.outputs, str) else (self.outputs,)))
        ins = tuple(_name(o, "inputs", s) for s in (self.inputs if not isinstance(self.inputs, str) else (self.inputs,)))
        if not outs or not ins:
            raise ParameterError(f"{o}: needs at least one input and one output")

        def mat(name, v, shape):
            try:
                a = np.array(v, dtype=float, ndmin=2)
            except (TypeError, ValueError):
                raise ParameterError(f"{o}.{name}: must be a matrix of numbers") from None
            if shape[0] == 0 or shape[1] == 0:
                a = np.zeros(shape)
            if a.shape != shape:
                raise ParameterError(f"{o}.{name} has shape {a.shape}: must be {shape}")
            if not np.all(np.isfinite(a)):
                raise ParameterError(f"{o}.{name}: entries must be finite")
            a.setflags(write=False)
            return a

        A = np.array(self.A, dtype=float, ndmin=2) if np.size(self.A) else np.zeros((0, 0))
        nx = A.shape[0]
        object.__setattr__(self, "outputs", outs)
        object.__setattr__(self, "inputs", ins)
        object.__setattr__(self, "A", mat("A", self.A, (nx, nx)))
        object.__setattr__(self, "B", mat("B", self.B, (nx, len(ins))))
        object.__setattr__(self, "C", mat("C", self.C, (len(outs), nx)))
        object.__setattr__(self, "D", mat("D", self.D, (len(outs), len(ins))))
        x0 = np.zeros(nx) if self.x0 is None else val.vector(o, "x0", self.x0)
        if x0.size != nx:
            raise ParameterError(f"{o}.x0 has {x0.size} entries: must have {nx}")
        object.__setattr__(self, "x0", x0)


@dataclass(frozen=True)
class Saturation:
    """``out = clip(inp, lo, hi)``."""

    out: str
    inp: str
    lo: float
    hi: float

    def __post_init__(self) -> None:
        _name("Saturation", "out", self.out)
        _name("Saturation", "inp", self.inp)
        lo = float(self.lo)
        hi = float(self.hi)
        if math.isnan(lo) or math.isnan(hi) or lo > hi:
            raise ParameterError(f"Saturation: lo = {self.lo!r}, hi = {self.hi!r}: need lo <= hi")
        object.__setattr__(self, "lo", lo)
        object.__setattr__(self, "hi", hi)

    @property
    def inputs(self) -> tuple:
        return (self.inp,)

    @property
    def outputs(self) -> tuple:
        return (self.out,)


@dataclass(frozen=True)
class FrictionFeedforward:
    """``out = scale * Fss(signal)``: a friction law's steady-state map evaluated in the loop.

    Feed it the reference velocity (model-based feed-forward) or a measured velocity. For a
    dynamic law (LuGre, GMS, Dahl) its static map is used. ``scale`` converts the force into
    the actuator's command (e.g. ``1 / K_t`` for a current command). A law with a scheduling
    variable (:class:`~frictionkit.TDMSSC`) needs ``schedule``, the name of the signal that
    carries it (a reference base speed input, a sensor, a block output); its levels are set
    from that signal every sample.
    """

    out: str
    velocity: str
    law: object
    scale: float = 1.0
    schedule: str | None = None

    def __post_init__(self) -> None:
        from ..models.tdmssc import is_scheduled

        o = "FrictionFeedforward"
        _name(o, "out", self.out)
        _name(o, "velocity", self.velocity)
        object.__setattr__(self, "scale", val.finite(o, "scale", self.scale))
        if not hasattr(self.law, "steady_state"):
            raise ParameterError(f"{o}.law = {type(self.law).__name__}: must be a friction law")
        if is_scheduled(self.law):
            if self.schedule is None:
                raise ParameterError(f"{o}({self.out!r}).schedule = None: {type(self.law).__name__} reads a "
                                     "scheduling variable; name the signal that carries it (e.g. the base speed)")
            _name(o, "schedule", self.schedule)
        elif self.schedule is not None:
            raise ParameterError(f"{o}({self.out!r}).schedule = {self.schedule!r}: "
                                 f"{type(self.law).__name__} reads no scheduling variable")

    @property
    def inputs(self) -> tuple:
        return (self.velocity,) if self.schedule is None else (self.velocity, self.schedule)

    @property
    def outputs(self) -> tuple:
        return (self.out,)


BLOCK_TYPES = (Sum, PID, StateSpace, Saturation, FrictionFeedforward)


# --------------------------------------------------------------------------- JSON form (machine files)
#: Parts with a JSON form of their own, by the name written in their ``"type"`` key.
#: Friction laws are not here: they use the law registry (:func:`frictionkit.models.law_to_dict`).
ELEMENT_TYPES = {cls.__name__: cls for cls in (HertzContact, PiecewiseLinearSpring, SineLoad, NormalLoad,
                                               *BLOCK_TYPES)}
#: Fields written as ``null`` when infinite (JSON has no infinity): ``None`` reads back as ``-inf`` / ``+inf``.
_UNBOUNDED = {("Saturation", "lo"): -math.inf, ("Saturation", "hi"): math.inf}


def element_to_dict(obj) -> dict:
    """JSON form ``{"type": <class>, <field>: <value>, ...}`` of a compliance, load, normal load or
    controller block; a :class:`FrictionFeedforward`'s law in the law registry's JSON form.

    Examples
    --------
    >>> from frictionkit.machines import Saturation
    >>> from frictionkit.machines.elements import element_to_dict
    >>> element_to_dict(Saturation("u", "u_c", -10.0, float("inf")))
    {'type': 'Saturation', 'out': 'u', 'inp': 'u_c', 'lo': -10.0, 'hi': None}
    """
    import dataclasses

    from ..models.base import law_to_dict

    name = type(obj).__name__
    if ELEMENT_TYPES.get(name) is not type(obj):
        raise ParameterError(f"element_to_dict: {name} has no JSON form; known: {sorted(ELEMENT_TYPES)}")
    out: dict = {"type": name}
    for f in dataclasses.fields(obj):
        v = getattr(obj, f.name)
        if name == "FrictionFeedforward" and f.name == "law":
            v = law_to_dict(v)
        elif isinstance(v, np.ndarray):
            v = v.tolist()
        elif isinstance(v, tuple):
            v = list(v)
        elif isinstance(v, dict):
            v = dict(v)
        elif (name, f.name) in _UNBOUNDED and isinstance(v, float) and math.isinf(v):
            v = None
        out[f.name] = v
    return out


def element_from_dict(data, where: str = "element"):
    """Inverse of :func:`element_to_dict`; the part validates itself (``ParameterError``), an unknown
    type, a missing or unknown field raises ``DataError`` naming ``where``."""
    import dataclasses

    from ..errors import DataError
    from ..models.base import law_from_dict

    if not isinstance(data, dict):
        raise DataError(f"{where}: a JSON {type(data).__name__}, expected an object {{\"type\": ..., ...}}")
    name = data.get("type")
    cls = ELEMENT_TYPES.get(name) if isinstance(name, str) else None
    if cls is None:
        raise DataError(f"{where}: type {name!r} unknown; known: {sorted(ELEMENT_TYPES)}")
    fields = {f.name: f for f in dataclasses.fields(cls) if f.init}
    unknown = sorted(set(data) - set(fields) - {"type"})
    if unknown:
        raise DataError(f"{where} ({name}): unknown field(s) {unknown}; known: {sorted(fields)}")
    missing = [k for k, f in fields.items() if k not in data and f.default is dataclasses.MISSING]
    if missing:
        raise DataError(f"{where} ({name}): missing field(s) {missing}")
    kw = {}
    for k in fields:
        if k not in data:
            continue
        v = data[k]
        if name == "FrictionFeedforward" and k == "law":
            v = law_from_dict(v)
        elif (name, k) in _UNBOUNDED and v is None:
            v = _UNBOUNDED[(name, k)]
        kw[k] = v
    try:
        return cls(**kw)
    except ParameterError as exc:
        raise ParameterError(f"{where}: {exc}") from None
