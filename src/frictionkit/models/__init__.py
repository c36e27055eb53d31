"""Friction laws: frozen, validated parameter objects with NumPy reference evaluation.

:class:`FrictionLaw` (in ``base.py``) is the contract every law fulfils; each law
registers itself at the bottom of its own module (:func:`register_law`).
"""

from .base import (
    FrictionLaw,
    LawEntry,
    kernel_family,
    law_entry,
    law_from_dict,
    law_to_dict,
    register_law,
    registered_laws,
    unregister_law,
)
from .gms import GMS
from .lugre import Dahl, LuGre
from .rolling import coulomb_compensation, sigmoid_compensation, sinc_compensation
from .static import CoulombViscous, Directional, Stribeck
from .tdmssc import TDMSSC

__all__ = [
    "CoulombViscous",
    "Dahl",
    "Directional",
    "FrictionLaw",
    "GMS",
    "LawEntry",
    "LuGre",
    "Stribeck",
    "TDMSSC",
    "coulomb_compensation",
    "kernel_family",
    "law_entry",
    "law_from_dict",
    "law_to_dict",
    "register_law",
    "registered_laws",
    "sigmoid_compensation",
    "sinc_compensation",
    "unregister_law",
]
