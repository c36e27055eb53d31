"""Settings of the simulation fits, in one frozen, validated object.

:func:`~frictionkit.identify.fit_output_error` (force drive: the force drives a mass,
the motion is compared) and :func:`~frictionkit.identify.fit_motion_error` (motion drive:
the motion drives the law, the force is compared) search their parameters the same
way — start points screened by cost, the best ones refined by a least-squares
optimiser, intervals, a result that says whether it converged. How they search is one
:class:`FitOptions`; each fitter has its defaults (:data:`OUTPUT_ERROR_FIT`,
:data:`MOTION_ERROR_FIT`), and keyword arguments of the fitters (``starts=5``,
``max_nfev=50`` ...) are replacements of single fields, validated by the same object.

The integrator tolerances stay in :class:`~frictionkit.SimOptions` (``options=``):
one name per concept — *options* of a simulation, *fit* settings of a search.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from .. import _validate as val
from ..errors import ParameterError

__all__ = ["FitOptions", "MOTION_ERROR_FIT", "OUTPUT_ERROR_FIT", "fit_settings"]

#: The one optimiser: scipy's least_squares trf. A hand-written batched Levenberg–Marquardt
#: ("lm") was removed on 2026-11-23: it did not beat trf with either Jacobian on
#: benchmarks/identify.py (cost equal, CPU 0.59 vs 0.42 s exact, 0.55 vs 0.52 s FD).
_OPTIMISERS = ("trf",)


@dataclass(frozen=True, kw_only=True)
class FitOptions:
    """How a simulation fit searches its parameters (shared by the output-error fitters).

    Parameters
    ----------
    starts : int or "auto"
        Start points. An integer ``n``: the start model and ``n - 1`` random
        perturbations (factor e^±1.5 for log-scale parameters, ±50 % otherwise),
        screened by cost. ``"auto"`` (motion drive only): the start's dynamic
        parameters scaled together by 10^-2 … 10^4.
    refine : int
        How many of the best-screened starts are optimised to convergence (>= 1).
    seed : int
        Seed of the random start points (>= 0).
    max_nfev : int
        Evaluation limit per refined start (>= 1).
    ftol, xtol : float
        Relative cost-reduction and step tolerances of the optimiser (> 0).
    optimiser : {"trf"}
        :func:`scipy.optimize.least_squares` trust-region reflective (the only one; the
        former ``"lm"`` is refused with the reason).
    diff_step : float
        Forward-difference step of the transformed parameters (> 0; relative for
        log-scale parameters).
    jacobian : {"auto", "fd", "sensitivity"}
        ``"auto"``: exact Jacobians from forward sensitivities (one augmented run
        instead of one simulation per parameter) for the laws that have them (LuGre,
        Dahl, a ``Directional`` of them; GMS in the motion drive), forward differences
        for the others (GMS in the force drive).
        ``"fd"``: forward differences always.
        ``"sensitivity"``: as ``"auto"``, and GMS in the force drive from forward
        sensitivities along the simulated trajectory (not the exact derivative of the
        kernel's discrete map; within ~1e-3 of central differences, but measured ~2x the
        CPU of differences per Jacobian: opt-in).
    workers : int or None
        Threads for the Jacobian simulations of the force drive (None: CPU count).
    profile : bool
        Motion drive: likelihood profiles of the positive parameters (intervals and
        flat-profile flags).
    raise_on_failure : bool
        Raise :class:`~frictionkit.IdentificationError` when the fit does not
        converge; by default the result says ``success=False``, its ``status`` and why.

    Examples
    --------
    >>> from frictionkit.identify import FitOptions, OUTPUT_ERROR_FIT
    >>> OUTPUT_ERROR_FIT.replace(starts=5).starts
    5
    >>> FitOptions(refine=0)
    Traceback (most recent call last):
    ...
    frictionkit.errors.ParameterError: FitOptions.refine = 0: must be >= 1
    """

    starts: int | str = 1
    refine: int = 1
    seed: int = 0
    max_nfev: int = 200
    ftol: float = 1e-8
    xtol: float = 1e-8
    optimiser: str = "trf"
    diff_step: float = 1e-3
    jacobian: str = "auto"
    workers: int | None = None
    profile: bool = False
    raise_on_failure: bool = False

    def __post_init__(self) -> None:
        own = "FitOptions"
        put = object.__setattr__
        if isinstance(self.starts, str):
            if self.starts != "auto":
                raise ParameterError(f"{own}.starts = {self.starts!r}: must be 'auto' or an integer >= 1")
        else:
            put(self, "starts", val.integer(own, "starts", self.starts, minimum=1))
        put(self, "refine", val.integer(own, "refine", self.refine, minimum=1))
        put(self, "seed", val.integer(own, "seed", self.seed, minimum=0))
        put(self, "max_nfev", val.integer(own, "max_nfev", self.max_nfev, minimum=1))
        for name in ("ftol", "xtol", "diff_step"):
            put(self, name, val.positive(own, name, getattr(self, name)))
        if self.diff_step >= 1.0:
            raise ParameterError(f"{own}.diff_step = {self.diff_step!r}: must be < 1 (a step of the "
                                 "transformed parameters; 1e-3 is typical)")
        if self.jacobian not in ("auto", "fd", "sensitivity"):
            raise ParameterError(f"{own}.jacobian = {self.jacobian!r}: must be 'auto', 'fd' or 'sensitivity'")
        if self.optimiser == "lm":
            raise ParameterError(f"{own}.optimiser = 'lm': the hand-written Levenberg–Marquardt was removed "
                                 "(it did not beat least_squares trf on benchmarks/identify.py); use 'trf'")
        if self.optimiser not in _OPTIMISERS:
            raise ParameterError(f"{own}.optimiser = {self.optimiser!r}: must be 'trf'")
        if self.workers is not None:
            put(self, "workers", val.integer(own, "workers", self.workers, minimum=1))
        for name in ("profile", "raise_on_failure"):
            if not val.is_bool(getattr(self, name)):
                raise ParameterError(f"{own}.{name} = {getattr(self, name)!r}: must be True or False")
            put(self, name, bool(getattr(self, name)))

    def replace(self, **changes: Any) -> FitOptions:
        """A copy with some fields changed (validated; an unknown name is a one-line error)."""
        known = [f.name for f in dataclasses.fields(self)]
        unknown = sorted(set(changes) - set(known))
        if unknown:
            raise ParameterError(f"FitOptions has no setting {unknown[0]!r}; known: {', '.join(known)}")
        return dataclasses.replace(self, **changes)

    def to_dict(self) -> dict:
        """The settings as plain values (for the result's provenance)."""
        return {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}


#: Defaults of the force-driven fit (:func:`~frictionkit.identify.fit_output_error`).
OUTPUT_ERROR_FIT = FitOptions()

#: Defaults of the motion-driven fit (:func:`~frictionkit.identify.fit_motion_error`).
MOTION_ERROR_FIT = FitOptions(starts="auto", refine=2, max_nfev=300, ftol=1e-10, xtol=1e-10, diff_step=1e-4,
                              profile=True)


def fit_settings(owner: str, default: FitOptions, fit: FitOptions | None, changes: Mapping[str, Any],
                 *, unused: Mapping[str, str] = {}) -> FitOptions:
    """The settings of one fit: ``fit`` (or the fitter's ``default``) with ``changes`` applied.

    ``unused`` maps the fields this fitter does not read to the reason; a value there
    that differs from ``default`` is refused (a setting that would silently do nothing).
    """
    base = default if fit is None else fit
    if not isinstance(base, FitOptions):
        raise ParameterError(f"{owner}: fit = {fit!r}: must be a FitOptions or None")
    try:
        out = base.replace(**changes) if changes else base
    except ParameterError as exc:
        raise ParameterError(f"{owner}: {exc}") from None
    for name, why in unused.items():
        a, b = getattr(out, name), getattr(default, name)
        same = a == b or (isinstance(a, float) and isinstance(b, float) and math.isclose(a, b))
        if not same:
            raise ParameterError(f"{owner}: {name} = {a!r} is not used here ({why})")
    return out
