"""Start values of the force-driven output-error fit, and the static map it builds on.

What ``identify output-error --drive force`` used to work out in the CLI belongs to the
library (``fit_output_error(..., initial="auto")``), so that a Python user gets the same
fit as the command line:

* the static map: a law, a static-map :class:`~frictionkit.identify.IdentificationResult`,
  or the JSON file ``identify static --json`` wrote (:func:`load_static_law`: every way
  the file can be wrong is one :class:`~frictionkit.DataError` naming the file);
* the dynamic start values that were not given (:func:`output_error_start`): LuGre
  ``sigma0`` from the slope of the friction force over the displacement on the
  sub-breakaway branches (:func:`~frictionkit.identify.initial_guess_lugre`, seed 002
  §3.1), ``sigma1`` from critical damping of the linearised pre-sliding oscillator;
  GMS ``k_i`` sharing that total stiffness;
* the default free parameters (:data:`FORCE_DRIVE_FREE`);
* the start model of the motion-driven fit with some values given
  (:func:`motion_error_start`, over :func:`~frictionkit.identify.motion_start`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from .. import _validate as val
from ..errors import DataError, FrictionKitError, ParameterError
from ..models.gms import GMS
from ..models.lugre import LuGre
from .initial_guess import initial_guess_lugre

__all__ = ["FORCE_DRIVE_FREE", "GMS_C_START", "load_static_law", "motion_error_start", "output_error_start",
           "static_law"]

#: Parameters the force-driven fit frees by default: LuGre ``sigma0, sigma1``; GMS the
#: stiffnesses ``k`` (a force-driven velocity record rarely pins ``C`` or the weights).
FORCE_DRIVE_FREE = {"lugre": ("sigma0", "sigma1"), "gms": ("k",), "dahl": ("sigma0",)}

#: Start (and, unless freed, fixed) GMS attraction constant [N/s] when none is given: the
#: value ``identify output-error --model gms`` has always used. Assumption, not a
#: measurement: ``C`` sets how fast a slipping element's force follows ``s(v)`` and
#: force-driven velocity records rarely pin it; free it (``"C"``) when the data can.
GMS_C_START = 20.0

_GIVEN = {"lugre": ("sigma0", "sigma1"), "gms": ("k", "xi", "C"), "dahl": ("sigma0",)}


# --------------------------------------------------------------------------- static map
def load_static_law(path: str | Path, *, where: str | None = None):
    """The static map (``Directional`` of two ``Stribeck``) in a JSON written by ``identify static --json``.

    Every way the file can be wrong ends in one :class:`~frictionkit.DataError` naming the
    file (``where``, default ``"static map 'PATH'"``) and what is wrong: not UTF-8 text,
    not JSON, not an object, not a frictionkit static-map result, a missing key, a value
    of the wrong type, a parameter that breaks its rule, or a file edited in one place
    only (the top-level ``model``, the ``parameters`` table and the per-direction
    ``parts`` must agree).
    """
    from .result import JSON_FORMAT, IdentificationResult, model_from_dict, read_json_object
    from .static_map import stribeck_model

    where = where or f"static map '{path}'"
    try:
        doc = read_json_object(path, where)  # UTF-8, JSON, an object
    except DataError as exc:
        raise DataError(f"{exc}; expected the JSON of 'frictionkit identify static --json'") from None
    if doc.get("format") != JSON_FORMAT:
        raise DataError(f"{where}: not a frictionkit identification result "
                        f"(\"format\" is {doc.get('format')!r}, expected {JSON_FORMAT!r})")
    if doc.get("kind") != "static_map":
        raise DataError(f"{where}: not a static-map result (\"kind\" is {doc.get('kind')!r}, expected 'static_map')")
    try:
        res = IdentificationResult.from_dict(doc)  # types, keys, model fields
        law = stribeck_model(res)
        top = model_from_dict(doc["model"]) if doc.get("model") is not None else None
    except KeyError as exc:
        raise DataError(f"{where}: missing key {exc.args[0]!r}") from None
    except FrictionKitError as exc:
        raise DataError(f"{where}: {' '.join(str(exc).split())}") from None
    except RecursionError:
        raise DataError(f"{where}: JSON nested too deeply") from None
    except (TypeError, ValueError, AttributeError, IndexError, OverflowError) as exc:
        raise DataError(f"{where}: malformed content ({type(exc).__name__}: {' '.join(str(exc).split())})") from None
    # the numbers stated twice (top-level model, parameter tables, parts) agree: IdentificationResult.from_dict
    if top is not None:
        for side in ("positive", "negative"):
            if getattr(top, side, None) is None:
                raise DataError(f"{where}: the top-level \"model\" ({type(top).__name__}) has no {side} direction")
    return law


def static_law(static, owner: str = "fit_output_error"):
    """The static map from a law, a static-map result, or the path of its JSON file."""
    from ..models.static import CoulombViscous, Directional, Stribeck
    from .result import IdentificationResult
    from .static_map import stribeck_model

    if static is None:
        raise ParameterError(f"{owner}: give the static map: static = a Stribeck/Directional law, the result of "
                             "fit_static_map, or the path of its JSON ('identify static --json')")
    if isinstance(static, (str, Path)):
        return load_static_law(static)
    if isinstance(static, IdentificationResult):
        if static.kind != "static_map":
            raise ParameterError(f"{owner}: static is a {static.kind!r} result; give a static-map result")
        return stribeck_model(static)
    if isinstance(static, (Stribeck, CoulombViscous, Directional)):
        return static
    raise ParameterError(f"{owner}: static = {type(static).__name__}: must be a Stribeck, CoulombViscous or "
                         "Directional law, a static-map result, or a JSON path")


# --------------------------------------------------------------------------- dynamic start values
def _mean_sigma2(law) -> float:
    return float(np.mean(np.asarray(law.static_rows(), float)[:, 4]))


def _given_starts(owner: str, kind: str, given, allowed: Mapping[str, tuple], bad_kind: str) -> dict:
    """The user's start values for ``kind``: ``kind`` one of ``allowed`` (else ``bad_kind`` is the
    error), every key one of its parameters, scalars finite (:func:`_scalar_starts`)."""
    if kind not in allowed:
        raise ParameterError(f"{owner}: {bad_kind}")
    given = dict(given or {})
    unknown = sorted(set(given) - set(allowed[kind]))
    if unknown:
        raise ParameterError(f"{owner}: initial has {unknown[0]!r}, not a start value of {kind}; "
                             f"give {', '.join(allowed[kind])}")
    return _scalar_starts(owner, given)


def _scalar_starts(owner: str, given: dict) -> dict:
    """``given`` with its scalar start values (sigma0, sigma1, C) as finite floats: a boolean, a list or
    NaN is refused naming the key (``True`` became 1 N/m; a list raised a bare TypeError)."""
    out = dict(given)
    for name in ("sigma0", "sigma1", "C"):
        if name in out:
            out[name] = val.finite(f"{owner}: initial", name, out[name])
    return out


def _stiffness_guess(segments: Sequence[Mapping[str, np.ndarray]], mass: float, sigma2: float,
                     owner: str) -> dict[str, float]:
    """``initial_guess_lugre`` on every segment that has a usable branch; median ``sigma0``."""
    got, errors = [], []
    for seg in segments:
        x = seg.get("x")
        if x is None:  # assumption: a velocity log integrated by the trapezoidal rule is the position
            v = np.asarray(seg["v"], float)
            x = np.concatenate([[0.0], np.cumsum(0.5 * (v[1:] + v[:-1]) * np.diff(seg["t"]))])
        try:
            got.append(initial_guess_lugre({"t": seg["t"], "x": x, "F": seg["F"]}, mass=mass, sigma2=sigma2))
        except DataError as exc:
            errors.append(str(exc))
    if not got:
        raise DataError(f"{owner}: initial='auto' found no pre-sliding branch for the stiffness start value "
                        f"({errors[0] if errors else 'no data'}); give sigma0 (LuGre) or k and xi (GMS) in "
                        "initial={...}, or record a sub-breakaway run")
    sigma0 = float(np.median([g["sigma0"] for g in got]))
    return {"sigma0": sigma0, "sigma1": max(2.0 * math.sqrt(sigma0 * mass) - sigma2, 0.0),
            "branches": int(sum(g["branches"] for g in got))}


def output_error_start(kind: str, static, segments: Sequence[Mapping[str, np.ndarray]], *, inertia: float,
                       given: Mapping[str, Any] | None = None, elements: int = 3,
                       owner: str = "fit_output_error") -> tuple[Any, dict]:
    """Start model of a force-driven fit: the given values, the rest from the data.

    Parameters
    ----------
    kind : {"lugre", "gms", "dahl"}
    static : law
        The static map (Dahl takes its Coulomb level ``Fc`` and ``sigma2``, per direction).
    segments : sequence of mappings
        The runs the fit simulates, each with ``t`` [s], force ``F`` and position ``x``
        (or velocity ``v``, then integrated by the trapezoidal rule).
    inertia : float
        Moving mass [kg] (inertia correction and damping guess).
    given : mapping, optional
        Start values the caller fixes: LuGre ``sigma0``, ``sigma1``; GMS ``k``, ``xi``
        (sequences of the same length) and ``C``; Dahl ``sigma0``.
    elements : int
        GMS elements when ``k`` and ``xi`` are not given.

    Returns
    -------
    (model, info)
        The start law, and what was computed: ``{"sigma0": ..., "sigma1": ...,
        "branches": ...}`` (empty when everything was given).

    Notes
    -----
    LuGre: ``sigma0`` is the median over the runs of the force–displacement slope at
    zero bristle deflection (:func:`~frictionkit.identify.initial_guess_lugre`);
    ``sigma1 = max(2 sqrt(sigma0 m) - sigma2, 0)`` (critical damping of the linearised
    pre-sliding oscillator, ``sigma2`` the static map's mean viscous coefficient).
    Dahl: ``sigma0`` as LuGre's; ``Fc``, ``sigma2`` from the map (assumption: the map's
    Coulomb level — Dahl has no Stribeck hump).
    GMS: that slope is the total stiffness ``sum k_i`` (all elements stick at a
    reversal); assumption: equal weights ``xi_i = 1/M`` and breakaway displacements a
    factor √10 apart, so ``k_i`` is proportional to ``10^(-i/2)``; ``C`` defaults to
    :data:`GMS_C_START`.
    """
    given = _given_starts(owner, kind, given, _GIVEN,
                          f"model0 = {kind!r}: must be 'lugre', 'gms', 'dahl' or a LuGre/GMS/Dahl law")
    sigma2 = _mean_sigma2(static)
    info: dict = {}
    if kind == "dahl":
        from ..models.lugre import Dahl
        from ..models.static import Directional

        if "sigma0" not in given:
            info = _stiffness_guess(segments, inertia, sigma2, owner)
            info = {"sigma0": info["sigma0"], "branches": info["branches"]}
        s0 = float(given.get("sigma0", info.get("sigma0", 0.0)))

        def dahl(law):  # assumption: Dahl's level is the map's Coulomb level (it has no Stribeck hump)
            return Dahl(Fc=float(getattr(law, "Fc")), sigma0=s0, sigma2=float(getattr(law, "sigma2", 0.0)))
        if isinstance(static, Directional):
            return Directional(positive=dahl(static.positive), negative=dahl(static.negative)), info
        return dahl(static), info
    if kind == "lugre":
        if "sigma0" not in given:
            info = _stiffness_guess(segments, inertia, sigma2, owner)
            sigma0 = info["sigma0"]
        else:
            sigma0 = float(given["sigma0"])
        sigma1 = float(given["sigma1"]) if "sigma1" in given else max(2.0 * math.sqrt(max(sigma0, 0.0) * inertia)
                                                                       - sigma2, 0.0)
        if "sigma1" not in given:
            info["sigma1"] = sigma1
        return LuGre(static, sigma0=sigma0, sigma1=sigma1), info
    if ("k" in given) != ("xi" in given):
        raise ParameterError(f"{owner}: initial gives {'k' if 'k' in given else 'xi'} without "
                             f"{'xi' if 'k' in given else 'k'}; give both, or neither (then both come from the data)")
    C = float(given.get("C", GMS_C_START))
    if "k" in given:
        return GMS(static, k=list(given["k"]), xi=list(given["xi"]), C=C), info
    M = int(elements)
    if M < 1:
        raise ParameterError(f"{owner}: elements = {elements!r}: must be >= 1")
    info = _stiffness_guess(segments, inertia, sigma2, owner)
    share = 10.0 ** (-0.5 * np.arange(M))
    k = info["sigma0"] * share / share.sum()
    info = {"k_total": info["sigma0"], "branches": info["branches"]}
    return GMS(static, k=k.tolist(), xi=[1.0 / M] * M, C=C), info


def motion_error_start(kind: str, static, data, *, given: Mapping[str, Any] | None = None, elements: int = 3,
                       max_presliding: float | None = None, drive: str = "auto", integration: str = "held",
                       rests="auto", min_rest: int = 3):
    """Start model of a motion-driven fit: the given values, the rest from :func:`.motion_error.motion_start`.

    Parameters
    ----------
    kind : {"lugre", "gms", "dahl"}
    static : law, static-map result, or path
        The static map (see :func:`static_law`).
    data
        The records, or their :class:`~.motion_data.MotionData`.
    given : mapping, optional
        Start values the caller fixes: LuGre ``sigma0``, ``sigma1``; GMS ``k``, ``xi``
        (both or neither), ``C``; Dahl ``sigma0`` (both directions).
    elements : int
        GMS elements when ``k`` and ``xi`` are not given.
    max_presliding, drive, integration, rests, min_rest
        As in :func:`~.motion_error.fit_motion_error`.

    Returns
    -------
    law
        LuGre, GMS, Dahl or a ``Directional`` of two Dahl laws.
    """
    from ..models.lugre import Dahl
    from ..models.static import Directional
    from .motion_data import MotionData, motion_data
    from .motion_error import motion_start

    owner = "motion_error_start"
    given = _given_starts(owner, kind, given, {**_GIVEN, "dahl": ("sigma0",)},
                          f"kind = {kind!r}: must be 'lugre', 'gms' or 'dahl'")
    law = static_law(static, owner)
    md = data if isinstance(data, MotionData) else motion_data(data, drive=drive, integration=integration,
                                                                rests=rests, min_rest=min_rest)
    if kind == "lugre":
        start = motion_start("lugre", law, md, max_presliding=max_presliding)
        return LuGre(law, sigma0=float(given.get("sigma0", start.sigma0)), sigma1=float(given.get("sigma1", start.sigma1)))
    if kind == "gms":
        if ("k" in given) != ("xi" in given):
            raise ParameterError(f"{owner}: initial gives {'k' if 'k' in given else 'xi'} without "
                                 f"{'xi' if 'k' in given else 'k'}; give both, or neither (then elements sets the start)")
        M = len(given["k"]) if "k" in given else elements
        start = motion_start("gms", law, md, elements=M, max_presliding=max_presliding)
        return GMS(law, k=list(given.get("k", start.k)), xi=list(given.get("xi", start.xi)),
                   C=float(given.get("C", start.C)))
    start = motion_start("dahl", law, md, max_presliding=max_presliding)
    if "sigma0" not in given:
        return start
    s0 = float(given["sigma0"])

    def dahl(d):
        return Dahl(Fc=d.Fc, sigma0=s0, sigma2=d.sigma2)
    if isinstance(start, Directional):
        return Directional(positive=dahl(start.positive), negative=dahl(start.negative))
    return dahl(start)
