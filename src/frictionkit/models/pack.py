"""Flatten parameter objects into the arrays the numba kernels read.

Row 0 of every array holds the parameters for ``v >= 0``, row 1 for ``v < 0``.

* ``static``: ``(2, 6)`` — ``Fc, Fs, vs, delta, sigma2, shape`` (shape 0 exponential, 1 Lorentzian)
* LuGre ``dyn``: ``(2, 2)`` — ``sigma0, sigma1``
* GMS: ``k (2, M)``, ``xi (2, M)``, ``C (2,)``
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError
from .base import kernel_family
from .static import Directional


@dataclass(frozen=True)
class PackedLuGre:
    static: np.ndarray
    dyn: np.ndarray


@dataclass(frozen=True)
class PackedGMS:
    static: np.ndarray
    k: np.ndarray
    xi: np.ndarray
    C: np.ndarray


def kind_of(model) -> str:
    """``"lugre"`` (LuGre, Dahl) or ``"gms"``: the kernel family of a dynamic law.

    Raises for static laws and non-laws: :func:`frictionkit.simulate` and the
    ``solve_ivp`` twins need a law with state (see ``models.base.kernel_family``).
    """
    try:
        family = kernel_family(model)
    except ParameterError:
        family = None
    if family in ("lugre", "gms"):
        return family
    raise ParameterError(
        f"model = {type(model).__name__}: simulate() needs a dynamic law "
        "(LuGre, Dahl, GMS or Directional of one of them)"
    )


def pack_lugre(model) -> PackedLuGre:
    if isinstance(model, Directional):
        p, n = pack_lugre(model.positive), pack_lugre(model.negative)
        return PackedLuGre(np.array([p.static[0], n.static[1]]), np.array([p.dyn[0], n.dyn[1]]))
    return PackedLuGre(
        np.ascontiguousarray(model.static.static_rows()), np.ascontiguousarray(model.dynamic_rows())
    )


def pack_gms(model) -> PackedGMS:
    if isinstance(model, Directional):
        p, n = pack_gms(model.positive), pack_gms(model.negative)
        return PackedGMS(
            np.array([p.static[0], n.static[1]]),
            np.array([p.k[0], n.k[1]]),
            np.array([p.xi[0], n.xi[1]]),
            np.array([p.C[0], n.C[1]]),
        )
    return PackedGMS(
        np.ascontiguousarray(model.static.static_rows()),
        np.array([model.k, model.k], dtype=float),
        np.array([model.xi, model.xi], dtype=float),
        np.array([model.C, model.C], dtype=float),
    )
