"""The machine description: degrees of freedom, couplings, sites, actuators, sensors, controller.

A :class:`Machine` is data. You add parts with its methods (each validated on the spot, with
a message naming the part and the value), then run it with
:func:`~frictionkit.machines.simulate_machine`. Presets (the seed 001 ball-screw stage, the
EMPS axis, ...) are functions that build a ``Machine``.
"""

from __future__ import annotations

import math
import re
import weakref
from dataclasses import dataclass

import numpy as np

from .. import _validate as val
from ..errors import ParameterError
from .elements import BLOCK_TYPES, Coord, CoordSignal, HertzContact, NormalLoad, PiecewiseLinearSpring, SineLoad
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from collections.abc import Callable

    from ..models.base import FrictionLaw
    from typing import Any

KINDS = {"translational": "m", "rotational": "rad"}
QUANTITIES = ("position", "velocity")


@dataclass(frozen=True)
class Dof:
    name: str
    inertia: float
    kind: str
    x0: float
    v0: float

    def __post_init__(self) -> None:  # here, not only in Machine.dof: dataclasses.replace passes by it
        val.position(f"Machine.dof({self.name!r})", "x0", self.x0)

    @property
    def unit(self) -> str:
        return KINDS[self.kind]


@dataclass(frozen=True)
class Spring:
    name: str
    at: Coord
    k: float
    c: float


@dataclass(frozen=True)
class Site:
    """A friction site, nonlinear compliance or position-dependent load acting along ``at``.

    Its force ``F`` opposes the site coordinate: the generalised force is ``-at^T F``.
    """

    name: str
    at: Coord
    law: object
    role: str  # "friction", "compliance", "load"
    load: NormalLoad | None = None
    schedule: CoordSignal | None = None
    unit: str = "N"  # of its force: "N" along a length, "N·m" about an angle (labels of plots and traces)


#: Force units a site may carry: a force along a length, a torque about an angle.
SITE_UNITS = ("N", "N·m")


def site_unit(owner: str, at: Coord, dofs: list[Dof], unit: str | None) -> str:
    """The force unit of a site on ``at``: ``unit`` when given (checked), else inferred from the coordinate.

    Inferred: ``"N"`` when a translational DOF (or only prescribed motions) is in it; on rotational DOFs
    only, ``"N·m"`` when one enters with coefficient ±1 (an angle, an angle difference ``th_m - th_s``) and
    ``"N"`` when all are scaled — the package's transmissions to a length, a screw's lead ratio ``R * theta``
    [m/rad] (seed 000's ``R * (theta1 + theta2)``). A coordinate is only numbers, so a scaled *angle* (a gear
    ``theta_m / n``) cannot be told from a length: pass ``unit="N·m"`` there.
    """
    if unit is not None:
        if unit not in SITE_UNITS:
            raise ParameterError(f"{owner}.unit = {unit!r}: must be one of {list(SITE_UNITS)}")
        return unit
    kinds = {dofs[i].kind for i in at.dofs}
    if kinds != {"rotational"}:
        return "N"
    return "N·m" if any(abs(abs(c) - 1.0) <= 1e-12 for c in at.dofs.values()) else "N"


@dataclass(frozen=True)
class Actuator:
    name: str
    at: Coord
    gain: float
    limit: float
    delay: int
    command: str


@dataclass(frozen=True)
class Sensor:
    name: str
    at: Coord
    quantity: str
    resolution: float
    noise: float
    delay: int


def _int(owner: str, name: str, value, *, minimum: int = 0) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise ParameterError(f"{owner}.{name} = {value!r}: must be an integer >= {minimum}")
    return int(value)


#: Most degrees of freedom a machine takes (named assumption, issue 13 round 9). A machine file with 2,000
#: DOFs ran for minutes with no output (a 51-sample run: 150 DOFs 0.8 s, 400 DOFs 9.6 s CPU, 800 DOFs
#: > 300 s, measured under load 10): the set-up grows faster than the cube of the count. The machines this
#: package models are drive trains of 1-6 DOFs (presets) up to a few dozen (a discretised shaft); 200 keeps
#: every such model and a run's set-up within seconds.
MAX_DOFS = 200


class Machine:
    """A drive as degrees of freedom, couplings, friction sites, actuators, sensors and a controller.

    Parameters
    ----------
    name : str — shown in results and reports.

    Examples
    --------
    A 1 kg slider on a LuGre contact, pushed by a force input ``"u"``, with a position scale:

    >>> import frictionkit as fk
    >>> m = fk.Machine("slider")
    >>> x = m.dof("x", inertia=1.0)
    >>> m.friction("contact", x, law=fk.LuGre(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4),
    ...                                          sigma0=1e5, sigma1=316.0))
    >>> m.actuator("u", x)
    >>> m.sensor("scale", x, resolution=1e-6)
    >>> m
    Machine('slider': 1 dof, 0 springs, 1 site, 1 actuator, 1 sensor, 0 blocks)
    """

    def __init__(self, name: str = "machine"):
        if not isinstance(name, str) or not name.strip():
            # "" (or blanks) was accepted and printed as Machine('') (issue 13 round 8 leftover)
            raise ParameterError(f"Machine name = {name!r}: must be a non-empty string")
        self.name = name
        self.dofs: list[Dof] = []
        self.inertias: list[tuple[Coord, float]] = []
        self.springs: list[Spring] = []
        self.sites: list[Site] = []
        self.actuators: list[Actuator] = []
        self.sensors: list[Sensor] = []
        self.blocks: list = []
        self._dof_names: list[str] = []
        self._motion_names: list[str] = []
        self._names: set[str] = set()

    # ------------------------------------------------------------------ helpers
    def _new_name(self, what: str, name) -> str:
        if not isinstance(name, str) or not name.strip():
            raise ParameterError(f"Machine.{what} name = {name!r}: must be a non-empty string")
        if name in self._names:
            raise ParameterError(f"Machine.{what}: the name {name!r} is already used in machine {self.name!r}")
        self._names.add(name)
        return name

    def _coord(self, what: str, a, b=None, *, kinematic: bool = False) -> Coord:
        if not isinstance(a, Coord) or a._owner is not self:
            raise ParameterError(f"Machine.{what}: {a!r} is not a coordinate of machine {self.name!r} "
                                 "(use the values returned by dof() or motion())")
        if b is not None:
            if not isinstance(b, Coord) or b._owner is not self:
                raise ParameterError(f"Machine.{what}: {b!r} is not a coordinate of machine {self.name!r}")
            a = a - b
        if not a.dofs and not (kinematic and a.motions):
            raise ParameterError(f"Machine.{what}: {a!r} does not move with any degree of freedom")
        return a

    # ------------------------------------------------------------------ parts
    def dof(self, name: str, *, inertia: float, kind: str = "translational", x0: float = 0.0,
            v0: float = 0.0) -> Coord:
        """Add a degree of freedom; returns its coordinate.

        Parameters
        ----------
        name : str
        inertia : float — mass [kg] or moment of inertia [kg·m²], >= 0 (a massless DOF needs
            inertia from :meth:`mass` or the machine cannot be simulated).
        kind : {"translational", "rotational"} — unit m or rad.
        x0, v0 : float — initial position [m or rad] and velocity.
        """
        if kind not in KINDS:
            raise ParameterError(f"Machine.dof({name!r}).kind = {kind!r}: must be one of {sorted(KINDS)}")
        if len(self.dofs) >= MAX_DOFS:
            raise ParameterError(f"Machine.dof({name!r}): machine {self.name!r} already has {MAX_DOFS} degrees of "
                                 "freedom, the most a machine takes (a drive train is a handful; the set-up cost "
                                 "grows faster than the cube of the count: see MAX_DOFS)")
        d = Dof(name, val.nonnegative(f"Machine.dof({name!r})", "inertia", inertia), kind,
                val.finite(f"Machine.dof({name!r})", "x0", x0), val.finite(f"Machine.dof({name!r})", "v0", v0))
        self._new_name("dof", name)
        self.dofs.append(d)
        self._dof_names.append(name)
        return Coord(self, {len(self.dofs) - 1: 1.0}, {})

    def coord(self, name: str) -> Coord:
        """The coordinate of a degree of freedom or prescribed motion by name."""
        if name in self._dof_names:
            return Coord(self, {self._dof_names.index(name): 1.0}, {})
        if name in self._motion_names:
            return Coord(self, {}, {self._motion_names.index(name): 1.0})
        raise ParameterError(f"Machine {self.name!r} has no degree of freedom or motion {name!r}; "
                             f"it has {self._dof_names + self._motion_names}")

    def motion(self, name: str) -> Coord:
        """A prescribed position (an input array of that name at simulation) to attach springs
        and sites to, e.g. the far end of the spring that pulls a block (Canudas et al. 1995)."""
        name = self._new_name("motion", name)
        self._motion_names.append(name)
        return Coord(self, {}, {len(self._motion_names) - 1: 1.0})

    def inertia(self, at: Coord, inertia: float) -> None:
        """Attach a rigid inertia at a point, e.g. a worktable of ``inertia`` kg at ``R * (theta1 + theta2)``
        (kg on a translational coordinate, kg·m² on a rotational one, as :meth:`dof`'s ``inertia``)."""
        at = self._coord("inertia", at)
        self.inertias.append((at, val.positive("Machine.inertia", "inertia", inertia)))

    def spring(self, a: Coord, b: Coord | None = None, *, k: float = 0.0, c: float = 0.0,
               name: str | None = None) -> None:
        """Linear spring ``k`` [N/m] and damper ``c`` [N·s/m] on ``a - b`` (``b`` None: ground)."""
        at = self._coord("spring", a, b)
        name = self._new_name("spring", name or f"spring{len(self.springs)}")
        k = val.nonnegative(f"Machine.spring({name!r})", "k", k)
        c = val.nonnegative(f"Machine.spring({name!r})", "c", c)
        if k == 0.0 and c == 0.0:
            raise ParameterError(f"Machine.spring({name!r}): k = c = 0 couples nothing")
        self.springs.append(Spring(name, at, k, c))

    def damper(self, a: Coord, b: Coord | None = None, *, c: float, name: str | None = None) -> None:
        """Linear damper on ``a - b``."""
        self.spring(a, b, c=c, name=name)

    def friction(self, name: str, a: Coord, b: Coord | None = None, *, law: FrictionLaw,
                 load: NormalLoad | None = None, schedule: CoordSignal | None = None,
                 unit: str | None = None) -> None:
        """A friction site on the motion of ``a`` relative to ``b`` (ground when None).

        ``law`` is any friction law: ``Stribeck``, ``CoulombViscous``, ``Directional``,
        ``Dahl``, ``LuGre``, ``GMS`` or ``TDMSSC``. Its force opposes the relative motion.
        ``load`` (:class:`NormalLoad`) makes its levels follow a state-dependent normal load;
        the spring or compliance it names must exist when the machine is simulated.
        ``schedule`` (:class:`CoordSignal`: ``coord.velocity`` or ``coord.position``) is the
        scheduling variable of a law that reads one (``TDMSSC``: levels affine in it, e.g. the
        nut's base speed ``(R * theta2).velocity``); required for such a law, refused for the
        others. A site on prescribed motions only (no degree of freedom) is kinematic: it is
        driven by the motion and acts on nothing — a motion-driven friction experiment inside a
        machine. ``unit`` (``"N"`` or ``"N·m"``) labels its force in plots and traces; default from the
        coordinate (:func:`site_unit`).
        """
        from ..models.tdmssc import is_scheduled
        from .simulate import law_family

        o = f"Machine.friction({name!r})"
        at = self._coord("friction", a, b, kinematic=True)
        law_family(law, f"{o}.law")
        if load is not None and not isinstance(load, NormalLoad):
            raise ParameterError(f"{o}.load = {type(load).__name__}: must be a NormalLoad")
        if is_scheduled(law):
            if schedule is None:
                raise ParameterError(f"{o}.schedule = None: {type(law).__name__} reads a scheduling variable; "
                                     "pass schedule=<coordinate>.velocity (or .position)")
            if not isinstance(schedule, CoordSignal):
                raise ParameterError(f"{o}.schedule = {schedule!r}: must be <coordinate>.velocity or "
                                     "<coordinate>.position")
            if schedule.at._owner is not self:
                raise ParameterError(f"{o}.schedule: {schedule.at!r} is not a coordinate of machine {self.name!r}")
            if schedule.at.is_empty:
                raise ParameterError(f"{o}.schedule: {schedule.at!r} moves with nothing")
        elif schedule is not None:
            raise ParameterError(f"{o}.schedule = {schedule!r}: {type(law).__name__} reads no scheduling variable")
        unit = site_unit(o, at, self.dofs, unit)
        name = self._new_name("friction", name)
        self.sites.append(Site(name, at, law, "friction", load, schedule, unit))

    def compliance(self, name: str, a: Coord, b: Coord | None = None, *, law: Any, c: float = 0.0,
                   unit: str | None = None) -> None:
        """A nonlinear spring on ``a - b``: :class:`HertzContact` or :class:`PiecewiseLinearSpring`
        (a harmonic drive's torque-dependent stiffness), with an optional linear damper ``c``;
        ``unit`` as in :meth:`friction`."""
        if not isinstance(law, (HertzContact, PiecewiseLinearSpring)):
            raise ParameterError(f"Machine.compliance({name!r}).law = {type(law).__name__}: "
                                 "must be HertzContact or PiecewiseLinearSpring")
        at = self._coord("compliance", a, b)
        unit = site_unit(f"Machine.compliance({name!r})", at, self.dofs, unit)
        name = self._new_name("compliance", name)
        self.sites.append(Site(name, at, law, "compliance", unit=unit))
        if c:
            self.damper(a, b, c=c, name=f"{name}.damper")

    def load(self, name: str, at: Coord, *, law: SineLoad, unit: str | None = None) -> None:
        """A position-dependent load, e.g. gravity imbalance ``m g X sin(theta)`` (:class:`SineLoad`);
        ``unit`` as in :meth:`friction`."""
        if not isinstance(law, SineLoad):
            raise ParameterError(f"Machine.load({name!r}).law = {type(law).__name__}: must be SineLoad")
        at = self._coord("load", at)
        unit = site_unit(f"Machine.load({name!r})", at, self.dofs, unit)
        name = self._new_name("load", name)
        self.sites.append(Site(name, at, law, "load", unit=unit))

    def actuator(self, name: str, at: Coord, *, gain: float = 1.0, limit: float = math.inf,
                 delay: int = 0, command: str | None = None) -> None:
        """A force/torque source ``gain * clip(command, -limit, limit)`` acting along ``at``.

        ``command`` names the signal it follows (default: the actuator's own name — give an
        input array of that name for open-loop runs, interpolated linearly between samples,
        or let a controller block write it; then it is held over the sample). ``delay`` whole
        samples of transport delay. Its applied value is the signal ``"<name>.applied"``.
        """
        at = self._coord("actuator", at)
        name = self._new_name("actuator", name)
        o = f"Machine.actuator({name!r})"
        lim = float(limit) if limit is not None else math.inf
        if not lim > 0:
            raise ParameterError(f"{o}.limit = {limit!r}: must be > 0")
        cmd = name if command is None else command
        if not isinstance(cmd, str) or not cmd:
            raise ParameterError(f"{o}.command = {command!r}: must be a signal name")
        self._names.add(f"{name}.applied")
        self.actuators.append(Actuator(name, at, val.finite(o, "gain", gain), lim, _int(o, "delay", delay), cmd))

    def sensor(self, name: str, at: Coord, *, quantity: str = "position", resolution: float = 0.0,
               noise: float = 0.0, delay: int = 0) -> None:
        """A measured signal: position or velocity of ``at``, quantised to ``resolution``
        (``floor(x / q) q``; an encoder of N counts/rev: ``2 pi / N``), white noise of std
        ``noise`` before quantisation, ``delay`` whole samples."""
        o = f"Machine.sensor({name!r})"
        at = self._coord("sensor", at, kinematic=True)
        name = self._new_name("sensor", name)
        if quantity not in QUANTITIES:
            raise ParameterError(f"{o}.quantity = {quantity!r}: must be one of {QUANTITIES}")
        self.sensors.append(Sensor(name, at, quantity, val.nonnegative(o, "resolution", resolution),
                                   val.nonnegative(o, "noise", noise), _int(o, "delay", delay)))

    def add(self, *blocks: Any) -> None:
        """Append controller blocks (:class:`Sum`, :class:`PID`, :class:`StateSpace`,
        :class:`Saturation`, :class:`FrictionFeedforward`); they run in this order each sample."""
        sensors = {s.name for s in self.sensors}
        for b in blocks:
            if not isinstance(b, BLOCK_TYPES):
                raise ParameterError(f"Machine.add: {type(b).__name__} is not a controller block; "
                                     f"use one of {[t.__name__ for t in BLOCK_TYPES]}")
            written = {o: type(w).__name__ for w in self.blocks for o in w.outputs}
            for out in b.outputs:
                if out in self._dof_names or out in self._motion_names:
                    raise ParameterError(f"Machine.add: block output {out!r} clashes with a dof/motion name")
                # issue 13, round 10: a second writer silently overrode the first every sample
                if out in written:
                    raise ParameterError(f"Machine.add: {type(b).__name__} writes signal {out!r}, which a "
                                         f"{written[out]} block already writes; the later would override the "
                                         "earlier every sample: give each its own name and add them with a Sum")
                if out in sensors:
                    raise ParameterError(f"Machine.add: block output {out!r} clashes with a sensor's name")
            self.blocks.append(b)

    # ------------------------------------------------------------------ JSON form (machine files)
    def input_names(self) -> list[str]:
        """The input arrays a run needs (``simulate_machine(..., inputs={name: array})``):
        prescribed motions, actuator commands no block writes, and block inputs nothing
        produces (references, feed-forwards, disturbances), in that order."""
        produced = {s.name for s in self.sensors} | {f"{a.name}.applied" for a in self.actuators}
        for b in self.blocks:
            produced |= set(b.outputs)
        names = list(self._motion_names)
        names += [a.command for a in self.actuators if a.command not in produced]
        names += [s for b in self.blocks for s in b.inputs if s not in produced]
        return list(dict.fromkeys(names))

    def read_inputs(self, inputs: dict) -> dict:
        """The entries of ``inputs`` this machine reads (:meth:`input_names`): for a caller that feeds
        variants of one machine the same signals (a run without a compensator does not read the
        reference speed the compensated runs feed forward), as :func:`simulate_machine` refuses an
        input nothing reads."""
        if not isinstance(inputs, dict):
            raise ParameterError(f"Machine.read_inputs: inputs = {type(inputs).__name__}: must be a dict name -> array")
        need = set(self.input_names())
        return {k: a for k, a in inputs.items() if k in need}

    def to_dict(self) -> dict:
        """The machine as JSON-ready data: every part in the order it was added, friction laws
        in the law registry's JSON form, other parts by :func:`~frictionkit.machines.elements.element_to_dict`.
        Infinite actuator limits are written as ``null``. Inverse: :meth:`from_dict`."""
        from ..models.base import law_to_dict
        from .elements import element_to_dict

        def site(s: Site) -> dict:
            return {"name": s.name, "role": s.role, "at": s.at.to_dict(),
                    "law": law_to_dict(s.law) if s.role == "friction" else element_to_dict(s.law),
                    "load": None if s.load is None else element_to_dict(s.load),
                    "schedule": None if s.schedule is None else {"at": s.schedule.at.to_dict(),
                                                                 "quantity": s.schedule.quantity},
                    "unit": s.unit}

        return {
            "name": self.name,
            "dofs": [{"name": d.name, "kind": d.kind, "inertia": d.inertia, "x0": d.x0, "v0": d.v0} for d in self.dofs],
            "motions": list(self._motion_names),
            "inertias": [{"at": at.to_dict(), "inertia": j} for at, j in self.inertias],
            "springs": [{"name": s.name, "at": s.at.to_dict(), "k": s.k, "c": s.c} for s in self.springs],
            "sites": [site(s) for s in self.sites],
            "actuators": [{"name": a.name, "at": a.at.to_dict(), "gain": a.gain,
                           "limit": None if math.isinf(a.limit) else a.limit, "delay": a.delay, "command": a.command}
                          for a in self.actuators],
            "sensors": [{"name": s.name, "at": s.at.to_dict(), "quantity": s.quantity, "resolution": s.resolution,
                         "noise": s.noise, "delay": s.delay} for s in self.sensors],
            "blocks": [element_to_dict(b) for b in self.blocks],
        }

    @classmethod
    def from_dict(cls, data) -> "Machine":
        """Rebuild a machine from :meth:`to_dict`'s form through the same validating methods
        (:meth:`dof`, :meth:`spring`, :meth:`friction` ...). A missing or unknown key, an
        unknown name in a coordinate or a wrong type raises ``DataError`` naming the part; a
        value that breaks its rule raises ``ParameterError`` as when built in Python."""
        from ..errors import DataError
        from ..models.base import law_from_dict
        from .elements import element_from_dict

        def obj(d, where: str, required: tuple, optional: tuple = ()) -> dict:
            if not isinstance(d, dict):
                raise DataError(f"{where}: a JSON {type(d).__name__}, expected an object")
            unknown = sorted(set(d) - set(required) - set(optional))
            if unknown:
                raise DataError(f"{where}: unknown key(s) {unknown}; known: {sorted(required + optional)}")
            missing = [k for k in required if k not in d]
            if missing:
                raise DataError(f"{where}: missing key(s) {missing}")
            return d

        def seq(d, key: str) -> list:
            v = d.get(key, [])
            if not isinstance(v, list):
                raise DataError(f"machine.{key}: a JSON {type(v).__name__}, expected a list")
            return v

        top = obj(data, "machine", ("name", "dofs"), ("motions", "inertias", "masses", "springs", "sites",
                                                       "actuators", "sensors", "blocks"))
        val.no_huge_number(top, "machine", skip=_own_rule_field)
        m = cls(top["name"])

        def coord(d, where: str) -> Coord:
            if not isinstance(d, dict) or not d:
                raise DataError(f"{where}.at = {d!r}: expected an object {{dof or motion name: coefficient}}")
            dofs, mot = {}, {}
            for name, c in d.items():
                if isinstance(c, bool) or not isinstance(c, (int, float)) or not math.isfinite(c):
                    raise DataError(f"{where}.at[{name!r}] = {c!r}: must be a finite number")
                if name in m._dof_names:
                    dofs[m._dof_names.index(name)] = c
                elif name in m._motion_names:
                    mot[m._motion_names.index(name)] = c
                else:
                    raise DataError(f"{where}.at: {name!r} is no degree of freedom or motion of the machine "
                                    f"(has {m._dof_names + m._motion_names})")
            return Coord(m, dofs, mot)

        for i, d in enumerate(seq(top, "dofs")):
            d = obj(d, f"machine.dofs[{i}]", ("name", "inertia"), ("kind", "x0", "v0"))
            m.dof(d["name"], inertia=d["inertia"], kind=d.get("kind", "translational"), x0=d.get("x0", 0.0),
                  v0=d.get("v0", 0.0))
        for name in seq(top, "motions"):
            m.motion(name)
        for i, d in enumerate(seq(top, "inertias")):
            w = f"machine.inertias[{i}]"
            d = obj(d, w, ("at", "inertia"))
            m.inertia(coord(d["at"], w), d["inertia"])
        for i, d in enumerate(seq(top, "masses")):  # files of 2026-11-23 before Machine.mass became .inertia
            w = f"machine.masses[{i}]"
            d = obj(d, w, ("at", "mass"))
            m.inertia(coord(d["at"], w), d["mass"])
        for i, d in enumerate(seq(top, "springs")):
            w = f"machine.springs[{i}]"
            d = obj(d, w, ("at",), ("name", "k", "c"))
            m.spring(coord(d["at"], w), k=d.get("k", 0.0), c=d.get("c", 0.0), name=d.get("name"))
        for i, d in enumerate(seq(top, "sites")):
            w = f"machine.sites[{i}]"
            d = obj(d, w, ("name", "role", "at", "law"), ("load", "schedule", "unit"))
            at, role = coord(d["at"], w), d["role"]
            if role == "friction":
                sch = d.get("schedule")
                if sch is not None:
                    sch = obj(sch, f"{w}.schedule", ("at", "quantity"))
                    sch = CoordSignal(coord(sch["at"], f"{w}.schedule"), sch["quantity"])
                load = d.get("load")
                load = None if load is None else element_from_dict(load, f"{w}.load")
                m.friction(d["name"], at, law=law_from_dict(d["law"]), load=load, schedule=sch, unit=d.get("unit"))
            elif role in ("compliance", "load"):
                for k in ("load", "schedule"):
                    if d.get(k) is not None:
                        raise DataError(f"{w}: a {role} site has no {k!r}")
                law = element_from_dict(d["law"], f"{w}.law")
                (m.compliance if role == "compliance" else m.load)(d["name"], at, law=law, unit=d.get("unit"))
            else:
                raise DataError(f"{w}.role = {role!r}: must be 'friction', 'compliance' or 'load'")
        for i, d in enumerate(seq(top, "actuators")):
            w = f"machine.actuators[{i}]"
            d = obj(d, w, ("name", "at"), ("gain", "limit", "delay", "command"))
            lim = d.get("limit")
            m.actuator(d["name"], coord(d["at"], w), gain=d.get("gain", 1.0), limit=math.inf if lim is None else lim,
                       delay=d.get("delay", 0), command=d.get("command"))
        for i, d in enumerate(seq(top, "sensors")):
            w = f"machine.sensors[{i}]"
            d = obj(d, w, ("name", "at"), ("quantity", "resolution", "noise", "delay"))
            m.sensor(d["name"], coord(d["at"], w), quantity=d.get("quantity", "position"),
                     resolution=d.get("resolution", 0.0), noise=d.get("noise", 0.0), delay=d.get("delay", 0))
        m.add(*[element_from_dict(b, f"machine.blocks[{i}]") for i, b in enumerate(seq(top, "blocks"))])
        return m

    # ------------------------------------------------------------------ views
    @property
    def n(self) -> int:
        return len(self.dofs)

    def row(self, at: Coord) -> tuple[np.ndarray, np.ndarray]:
        """``(dof coefficients (n,), motion coefficients (n_motion,))`` of a coordinate."""
        c = np.zeros(self.n)
        for i, w in at.dofs.items():
            c[i] = w
        cm = np.zeros(len(self._motion_names))
        for i, w in at.motions.items():
            cm[i] = w
        return c, cm

    def mass_matrix(self) -> np.ndarray:
        Mm = np.diag([d.inertia for d in self.dofs]).astype(float)
        for at, j in self.inertias:
            c, _ = self.row(at)
            Mm += j * np.outer(c, c)
        return Mm

    def __repr__(self) -> str:
        def n(k, word):
            return f"{k} {word}{'' if k == 1 else 's'}"
        return (f"Machine({self.name!r}: {n(self.n, 'dof')}, {n(len(self.springs), 'spring')}, "
                f"{n(len(self.sites), 'site')}, {n(len(self.actuators), 'actuator')}, "
                f"{n(len(self.sensors), 'sensor')}, {n(len(self.blocks), 'block')})")


# ---------------------------------------------------------------------- content fingerprint memo
#: Types whose values cannot change in place (a part holding only these, tuples of them and
#: frozen dataclasses of them needs no re-check); exact types, a subclass may carry attributes.
_SCALARS = frozenset((str, int, float, bool, complex, bytes, type(None)))
#: Deepest nesting the watch follows (deeper: not memoised, the fingerprint is recomputed).
_WATCH_DEPTH = 40


def _snap_seq(obj) -> tuple:  # list, set
    return tuple(obj)


def _snap_dict(obj: dict) -> tuple:
    return (*obj.keys(), None, *obj.values())


def _snap_coord(c: Coord) -> tuple:  # its coefficient dicts folded in (one entry per coordinate)
    d, m = c.dofs, c.motions
    return (c._owner, d, m, len(d), *d.keys(), *d.values(), None, *m.keys(), *m.values())


def _snap_signal(s: CoordSignal) -> tuple:
    return (s.at, s.quantity)


def _snap_array(a: np.ndarray) -> tuple:  # compared by value
    return (a.shape, a.dtype.str, a.tobytes())


def _snap_vars(obj) -> tuple:  # the Machine itself
    v = vars(obj)
    return (*v.keys(), None, *v.values())


def _watch(obj, out: list, seen: set, depth: int) -> bool:
    """Append to ``out`` every mutable object reachable from ``obj`` as ``(object, snapshot
    function, snapshot)``; False when ``obj`` holds an object whose edits the watch cannot see
    (a plain class instance, a non-frozen dataclass, an object array): such a machine is not
    memoised."""
    if type(obj) in _SCALARS or isinstance(obj, (np.number, np.bool_)):
        return True
    if id(obj) in seen:
        return True
    if depth > _WATCH_DEPTH:
        return False
    seen.add(id(obj))
    t = type(obj)
    if t is tuple or t is frozenset:
        return all(_watch(x, out, seen, depth + 1) for x in obj)
    if t is list or t is set:
        out.append((obj, _snap_seq, _snap_seq(obj)))
        return all(_watch(x, out, seen, depth + 1) for x in obj)
    if t is dict:
        out.append((obj, _snap_dict, _snap_dict(obj)))
        return all(_watch(x, out, seen, depth + 1) for x in (*obj.keys(), *obj.values()))
    if t is Coord:  # its owner is the machine (watched at the top), not followed
        out.append((obj, _snap_coord, _snap_coord(obj)))
        return all(_watch(x, out, seen, depth + 1) for x in (*obj.dofs.values(), *obj.motions.values()))
    if t is CoordSignal:
        out.append((obj, _snap_signal, _snap_signal(obj)))
        return _watch(obj.at, out, seen, depth + 1)
    if isinstance(obj, np.ndarray):
        if obj.dtype.hasobject:
            return False
        out.append((obj, _snap_array, _snap_array(obj)))
        return True
    params = getattr(t, "__dataclass_params__", None)
    if params is not None and params.frozen:
        import dataclasses

        if set(getattr(obj, "__dict__", {})) - {f.name for f in dataclasses.fields(obj)}:
            return False  # attributes beyond the fields (set around the frozen guard)
        return all(_watch(getattr(obj, f.name), out, seen, depth + 1) for f in dataclasses.fields(obj))
    return False


def _unchanged(watched: list) -> bool:
    """True when every watched object still holds the very objects (arrays: the bytes) it held."""
    from operator import is_

    for obj, snap_fn, snap in watched:
        now = snap_fn(obj)
        if snap_fn is _snap_array:
            if now != snap:
                return False
        elif len(now) != len(snap) or not all(map(is_, now, snap)):
            return False
    return True


def memo_fingerprint(machine: Machine, compute: Callable[[Machine], str | None]) -> str | None:
    """``compute(machine)`` (the machine's content as a key, e.g. its JSON form), remembered
    on the machine until any part of it changes.

    The memo watches every mutable object the machine's content is made of — the machine's
    attributes and part lists, each coordinate's coefficient dicts, a ``Sum``'s terms, arrays
    (by their bytes) — and recomputes when any of them holds another object than when the key
    was computed: a part added, removed or replaced in its list (``dataclasses.replace``), a
    coefficient or term edited in place, an array written to. The parts themselves are frozen
    dataclasses (laws, springs, sensors, blocks), whose values cannot change. A machine holding
    anything else (a plain object, a non-frozen dataclass, an object array) is not memoised:
    ``compute`` runs every time. Not seen (named assumption): edits that go around Python's
    frozen guard (``object.__setattr__`` on a frozen part after it was built).

    Checking the memo costs one identity comparison per watched object (~30 µs for the ball
    screw stage) instead of the JSON form (~0.4 ms for the EMPS axis, ~0.7 ms for the stage).
    """
    memo = _MEMO.get(machine)
    if memo is not None and _unchanged(memo[0]):
        return memo[1]
    watched: list = []
    ok = _watch_machine(machine, watched)
    fp = compute(machine)
    if ok and fp is not None:
        try:
            _MEMO[machine] = (watched, fp)
        except TypeError:  # not weakly referenceable (a subclass with __slots__): no memo
            pass
    return fp


def _watch_machine(machine: Machine, out: list) -> bool:
    out.append((machine, _snap_vars, _snap_vars(machine)))
    seen = {id(machine)}
    return all(_watch(v, out, seen, 1) for v in vars(machine).values())


#: Machine-file fields exempt from the file-wide magnitude bound (``_validate.no_huge_number``): an actuator's
#: ``limit`` (a huge value means no limit: JSON has no infinity) and a dof's start position ``x0``, whose own,
#: stricter bound names the cause (``_validate.position``: float spacing beyond 1e6 m).
_OWN_RULE_PATH = re.compile(r"machine\.actuators\[\d+\]\.limit|machine\.dofs\[\d+\]\.x0")


def _own_rule_field(path: str, parent: dict) -> bool:
    """True for a field the magnitude bound leaves alone: :data:`_OWN_RULE_PATH`, and a Saturation block's
    ``lo``/``hi`` (an unbounded side written as -1e300 / 1e300, as tests/robustness/test_loop_stability does)."""
    return bool(_OWN_RULE_PATH.fullmatch(path)) or (parent.get("type") == "Saturation"
                                                     and path.rsplit(".", 1)[-1] in ("lo", "hi"))


#: Fingerprints remembered per machine object (:func:`memo_fingerprint`); dropped with the machine.
_MEMO: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()
