"""The contract every friction law fulfils, and the registry of laws.

:class:`FrictionLaw` states what a law provides (read its docstring before writing
one); :func:`register_law` records a law's name, class, kernel family and JSON form,
so that simulation (:func:`kernel_family`, ``models.pack``), identification results
(``identify.result``) and the machine core find every law in one place.

Each law registers itself with one line at the bottom of its own module
(``static.py``: Stribeck, CoulombViscous, Directional; ``tdmssc.py``: TDMSSC;
``lugre.py``: LuGre, Dahl; ``gms.py``: GMS). Importing any part of :mod:`frictionkit.models` imports those
modules, so the registry is complete as soon as this module can be used.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any, Protocol, runtime_checkable

import numpy as np

from ..errors import DataError, ParameterError
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

#: The kernel families: how a law is packed and which state it carries.
FAMILIES = ("static", "lugre", "gms")


@runtime_checkable
class FrictionLaw(Protocol):
    """A friction law: a frozen, validated parameter object.

    The numbered points below are the contract for implementers. A new law provides
    all six and registers itself (see *Registering a law*); everything else —
    simulation, the machine core, identification results, JSON files — then
    accepts it without further changes. Units are SI throughout (m, s, N; rad and
    N·m for rotary axes).

    1. **Steady state.** ``steady_state(v)`` takes an array of velocities [m/s] and
       returns, in NumPy and without side effects, the friction force [N] in steady
       sliding at each velocity, ``Fss(v) = s(v) + sigma2 v`` for laws over a Stribeck
       map ``s``. It is the law's reference evaluation: the kernels are tested
       against it and the dynamic laws settle on it at constant velocity.

    2. **Kernel family and packing.** Every law belongs to one kernel family, which
       fixes how it is flattened into the arrays the numba kernels read
       (:mod:`frictionkit.models.pack`; row 0 of each array holds the parameters
       for ``v >= 0``, row 1 for ``v < 0``):

       * ``"static"`` — a memoryless map ``F = Fss(v)``: ``Stribeck``,
         ``CoulombViscous``, ``TDMSSC`` and ``Directional`` of those. Packed as
         ``static_rows()``, shape ``(2, 6)``: ``Fc, Fs, vs, delta, sigma2, shape``
         (shape 0 exponential, 1 Lorentzian); the machine core packs every static law
         by ``schedule_rows`` (item 4), which adds the schedule slopes and ``eps``.
       * ``"lugre"`` — one bristle state per friction site: ``LuGre`` and ``Dahl``
         (a LuGre without Stribeck dip or micro-damping). Packed by ``pack_lugre``
         into the static rows ``(2, 6)`` of its map and the dynamic rows ``(2, 2)``
         ``sigma0, sigma1``.
       * ``"gms"`` — M Maxwell-slip elements: ``GMS``. Packed by ``pack_gms`` into
         the static rows ``(2, 6)``, ``k (2, M)``, ``xi (2, M)`` and ``C (2,)``.

       ``Directional(positive=..., negative=...)`` has the family of the laws it
       holds (both are of one class); :func:`kernel_family` unwraps it.

    3. **State layout and initial state.** Per friction site, by family:

       * ``"static"``: no state.
       * ``"lugre"``: the bristle deflection ``z`` [m]; the friction force is
         ``sigma0 z + sigma1 dz/dt + sigma2 v``.
       * ``"gms"``: the M element forces ``F_i`` [N] and M stick flags (true:
         element sticking); the friction force is ``sum F_i + sigma2 v``.

       The initial, unloaded state is ``z = 0``, respectively every ``F_i = 0`` with
       every element sticking.

    4. **Machine inputs.** The machine signals a law reads besides the sliding
       velocity of its own site. Every law reads none, except a law with a
       **scheduling variable** ``s``: ``TDMSSC`` (seed 000 eq. 21; its Coulomb and
       static levels are affine in the base speed) and ``Directional`` of it
       (:func:`frictionkit.models.tdmssc.is_scheduled`). Such a law

       * takes it in its steady state as a required keyword,
         ``steady_state(v, schedule=s)`` (no silent default);
       * is packed for the kernels by :func:`frictionkit.models.tdmssc.schedule_rows`,
         ``(2, 9)``: ``Fc0, Fc1, Fs0, Fs1, vs, delta, sigma2, shape, eps`` (every
         static law has such rows, with zero slopes and ``eps = 0``);
       * is wired in the machine core by ``Machine.friction(..., schedule=
         <coordinate>.velocity)`` (or ``.position``; a :class:`CoordSignal` of any
         coordinate, prescribed motions included), which the compiled loop reads at the
         start of every sub-step and turns into the site's levels
         (``kernels/machine.py``, ``_set_levels``); a ``FrictionFeedforward`` block
         reads it from a named signal (``schedule="<signal>"``) every sample. Both are
         required for a scheduled law and refused for any other. Today the static family
         only: a scheduled law sticks and slips by the same discrete Karnopp treatment
         as every static site, with signed levels (a negative level pushes along the
         motion).

    5. **Change of normal load.** A law is given at a reference load ``N_ref``. At
       load ``N`` every force term of the friction scales by ``lam = N / N_ref``:
       the levels (``Fc``, ``Fs``, hence ``s(v)``), the stiffnesses and the
       micro-damping (``sigma0``, ``sigma1``, ``k_i``), so pre-sliding *lengths*
       (``Fc / sigma0``, ``xi_i Fs / k_i``) do not change; the viscous term
       ``sigma2 v`` (lubricant shear) does not scale. The state is kept as a
       deflection (``z``; GMS element forces at ``N_ref``), so:

       * when the load falls, the friction force falls with it (the contacts shrink
         and lose their traction, Mindlin);
       * when it rises, the new contact area carries no traction yet: the state is
         scaled by ``N_old / N_new`` so that the force is kept;
       * ``"static"``: nothing to carry over.

       Only the machine core applies this rule (``frictionkit.machines.NormalLoad``,
       ``kernels/machine.py``); it is stated here so that every law means the same
       by it. It reproduces the seed-001 flank model of the former ball-screw kernel
       (constant pre-sliding length, traction lost with the load).

    6. **JSON form.** ``{"law": <registered name>, <field>: <value>, ...}``, one
       entry per constructor field; nested laws (the ``static`` map of ``LuGre`` and
       ``GMS``, both sides of ``Directional``) are nested dicts of the same form and
       arrays are lists. ``law_from_dict(json.loads(json.dumps(law_to_dict(law))))``
       equals ``law`` exactly.

    Registering a law
    -----------------
    One line at the bottom of the law's module::

        register_law("LuGre", LuGre, "lugre")

    The default JSON form is derived from the frozen dataclass fields; pass
    ``to_dict`` / ``from_dict`` when a law's fields do not map one-to-one. A law of
    a new family also needs its kernel function.

    Examples
    --------
    >>> import frictionkit as fk
    >>> from frictionkit.models import FrictionLaw, kernel_family, law_to_dict
    >>> lugre = fk.LuGre(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3), sigma0=1e5, sigma1=63.2)
    >>> isinstance(lugre, FrictionLaw), kernel_family(lugre)
    (True, 'lugre')
    >>> law_to_dict(lugre)["static"]["law"]
    'Stribeck'
    """

    def steady_state(self, v: ArrayLike) -> np.ndarray: ...


# --------------------------------------------------------------------------- registry
@dataclass(frozen=True)
class LawEntry:
    """One registered law.

    Parameters
    ----------
    name : str
        The name in the JSON form (``{"law": name, ...}``).
    cls : type
        The law's class.
    family : str or callable
        One of :data:`FAMILIES`, or ``law -> family`` for a law that wraps others
        (``Directional``).
    to_dict : callable
        ``law -> {field: JSON value}`` (without the ``"law"`` key).
    from_dict : callable
        ``{field: JSON value} -> law`` (without the ``"law"`` key).
    """

    name: str
    cls: type
    family: str | Callable[[Any], str]
    to_dict: Callable[[Any], dict[str, Any]]
    from_dict: Callable[[Mapping[str, Any]], Any]


_REGISTRY: dict[str, LawEntry] = {}


def register_law(
    name: str,
    cls: type,
    family: str | Callable[[Any], str],
    to_dict: Callable[[Any], dict[str, Any]] | None = None,
    from_dict: Callable[[Mapping[str, Any]], Any] | None = None,
) -> LawEntry:
    """Register a friction law under ``name`` (see :class:`FrictionLaw`, point 6).

    Parameters
    ----------
    name : str
        Registered name, unique.
    cls : type
        The law's class: a frozen dataclass unless both ``to_dict`` and
        ``from_dict`` are given.
    family : {"static", "lugre", "gms"} or callable
        Its kernel family, or ``law -> family`` for a wrapper of other laws.
    to_dict, from_dict : callable, optional
        JSON form without the ``"law"`` key. Default: one entry per dataclass field;
        arrays and tuples become lists, nested laws nested dicts.

    Returns
    -------
    LawEntry

    Raises
    ------
    ParameterError
        ``name`` already taken by another class, ``family`` unknown, or no way to
        derive the JSON form.
    """
    if not isinstance(name, str) or not name:
        raise ParameterError(f"register_law: name = {name!r}: must be a non-empty string")
    if not callable(family) and family not in FAMILIES:
        raise ParameterError(
            f"register_law({name!r}): family = {family!r}: must be one of {list(FAMILIES)} or a callable"
        )
    old = _REGISTRY.get(name)
    if old is not None and old.cls is not cls:
        raise ParameterError(
            f"register_law({name!r}): the name is already registered for {old.cls.__module__}.{old.cls.__qualname__}"
        )
    if (to_dict is None or from_dict is None) and not dataclasses.is_dataclass(cls):
        raise ParameterError(
            f"register_law({name!r}): {cls.__name__} is not a dataclass; pass to_dict and from_dict"
        )
    entry = LawEntry(
        name=name,
        cls=cls,
        family=family,
        to_dict=to_dict if to_dict is not None else _fields_to_dict,
        from_dict=from_dict if from_dict is not None else _fields_from_dict(name, cls),
    )
    _REGISTRY[name] = entry
    return entry


def unregister_law(name: str) -> None:
    """Remove a registered law (for tests and plug-ins that registered one)."""
    if name not in _REGISTRY:
        raise ParameterError(f"unregister_law: {name!r} is not registered; known laws: {sorted(_REGISTRY)}")
    del _REGISTRY[name]


def registered_laws() -> Mapping[str, LawEntry]:
    """Read-only view ``{name: LawEntry}`` of the registered laws.

    Examples
    --------
    >>> from frictionkit.models import registered_laws
    >>> sorted(registered_laws())
    ['CoulombViscous', 'Dahl', 'Directional', 'GMS', 'LuGre', 'Stribeck', 'TDMSSC']
    """
    return MappingProxyType(_REGISTRY)


def law_entry(obj_or_name: Any) -> LawEntry:
    """The :class:`LawEntry` of a law object, a law class or a registered name.

    Raises
    ------
    ParameterError
        Not a registered law; the message lists the known names.
    """
    if isinstance(obj_or_name, str):
        entry = _REGISTRY.get(obj_or_name)
        if entry is None:
            raise ParameterError(f"law {obj_or_name!r} is not registered; known laws: {sorted(_REGISTRY)}")
        return entry
    cls = obj_or_name if isinstance(obj_or_name, type) else type(obj_or_name)
    for entry in _REGISTRY.values():
        if entry.cls is cls:
            return entry
    raise ParameterError(
        f"{cls.__name__} is not a registered friction law; known laws: {sorted(_REGISTRY)}"
    )


def kernel_family(law: Any) -> str:
    """``"static"``, ``"lugre"`` or ``"gms"``: the kernel family of a law (point 2).

    ``Directional`` is unwrapped to the family of the laws it holds.

    Raises
    ------
    ParameterError
        ``law`` is not a registered friction law.

    Examples
    --------
    >>> import frictionkit as fk
    >>> from frictionkit.models import kernel_family
    >>> law = fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3)
    >>> kernel_family(law), kernel_family(fk.Dahl(Fc=1.0, sigma0=1e5))
    ('static', 'lugre')
    """
    if isinstance(law, type):
        raise ParameterError(f"kernel_family: got the class {law.__name__}; pass a law object")
    entry = law_entry(law)
    return entry.family(law) if callable(entry.family) else entry.family


def law_to_dict(law: Any) -> dict[str, Any]:
    """JSON form ``{"law": <name>, <field>: <value>, ...}`` of a law (point 6).

    Examples
    --------
    >>> import frictionkit as fk
    >>> from frictionkit.models import law_to_dict
    >>> law_to_dict(fk.CoulombViscous(Fc=2.0, sigma2=10.0))
    {'law': 'CoulombViscous', 'Fc': 2.0, 'sigma2': 10.0}
    """
    entry = law_entry(law)
    return {"law": entry.name, **entry.to_dict(law)}


def law_from_dict(data: Mapping[str, Any]) -> Any:
    """Rebuild a law from its JSON form (inverse of :func:`law_to_dict`).

    Raises
    ------
    DataError
        ``data`` is not a mapping, has no ``"law"`` key, names an unregistered law,
        misses a required field or has an unknown one; the message names it.
    ParameterError
        A field value breaks the law's rule (raised by the law's constructor).

    Examples
    --------
    >>> from frictionkit.models import law_from_dict
    >>> law_from_dict({"law": "Dahl", "Fc": 1.0, "sigma0": 1e5, "sigma2": 0.0})
    Dahl(Fc=1.0, sigma0=100000.0, sigma2=0.0)
    """
    if not isinstance(data, Mapping):
        raise DataError(f"a friction law in JSON form is an object {{\"law\": ..., ...}}, got {type(data).__name__}")
    if "law" not in data:
        raise DataError(f"friction law without a 'law' key (keys: {sorted(data)}); known laws: {sorted(_REGISTRY)}")
    name = data["law"]
    entry = _REGISTRY.get(name) if isinstance(name, str) else None
    if entry is None:
        raise DataError(f"law {name!r} is not registered; known laws: {sorted(_REGISTRY)}")
    return entry.from_dict({k: v for k, v in data.items() if k != "law"})


def is_law_dict(data: Any) -> bool:
    """True for a mapping in the JSON form of a law (has a ``"law"`` key)."""
    return isinstance(data, Mapping) and "law" in data


# --------------------------------------------------------------------------- default JSON form
def _json_value(x: Any) -> Any:
    if isinstance(x, np.ndarray):
        return [_json_value(v) for v in x.tolist()]
    if isinstance(x, (list, tuple)):
        return [_json_value(v) for v in x]
    if isinstance(x, np.generic):
        return x.item()
    if dataclasses.is_dataclass(x) and not isinstance(x, type):
        return law_to_dict(x)
    return x


def _fields_to_dict(law: Any) -> dict[str, Any]:
    return {f.name: _json_value(getattr(law, f.name)) for f in dataclasses.fields(law) if f.init}


def _fields_from_dict(name: str, cls: type) -> Callable[[Mapping[str, Any]], Any]:
    fields = [f for f in dataclasses.fields(cls) if f.init]
    names = [f.name for f in fields]
    required = [f.name for f in fields
                if f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING]

    def from_dict(data: Mapping[str, Any]) -> Any:
        unknown = [k for k in data if k not in names]
        if unknown:
            raise DataError(f"law {name!r}: unknown field {unknown[0]!r}; {name} takes {names}")
        missing = [k for k in required if k not in data]
        if missing:
            raise DataError(f"law {name!r}: field {missing[0]!r} missing; {name} takes {names}")
        kw = {k: (law_from_dict(v) if is_law_dict(v) else v) for k, v in data.items()}
        return cls(**kw)

    return from_dict
