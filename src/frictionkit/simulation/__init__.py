"""Simulation: the ``simulate()`` entry point, batched runs, and the solve_ivp reference twin."""

from .core import BatchResult, SimOptions, SimulationResult, simulate, simulate_batch

__all__ = ["BatchResult", "SimOptions", "SimulationResult", "simulate", "simulate_batch"]
