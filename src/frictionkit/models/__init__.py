"""Friction laws: frozen, validated parameter objects with NumPy reference evaluation."""

from .gms import GMS
from .lugre import Dahl, LuGre
from .rolling import coulomb_compensation, sigmoid_compensation, sinc_compensation
from .static import CoulombViscous, Directional, Stribeck

__all__ = [
    "CoulombViscous",
    "Dahl",
    "Directional",
    "GMS",
    "LuGre",
    "Stribeck",
    "coulomb_compensation",
    "sigmoid_compensation",
    "sinc_compensation",
]
