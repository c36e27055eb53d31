"""Standard excitations used by the demo, the tests and the benchmarks.

Each returns samples at ``t_k = k·dt`` in SI units.
"""

from __future__ import annotations

import numpy as np

from .. import _validate as val


def _time(duration: float, dt: float) -> np.ndarray:
    duration = val.positive("input", "duration", duration)
    dt = val.positive("input", "dt", dt)
    n = int(round(duration / dt)) + 1
    return np.arange(n) * dt


def stick_slip_force(*, duration: float = 10.0, dt: float = 2.5e-4, amplitude: float = 2.0, frequency: float = 0.5) -> np.ndarray:
    """Sinusoidal force ``amplitude·sin(2π f t)`` [N].

    With an amplitude above the breakaway force the mass sticks while ``|u|`` is
    below it, breaks away, slides, stops and reverses twice a period: the
    stick–slip run of the benchmarks and parity tests (1 kg, Fs = 1.5 N, 2 N, 0.5 Hz).
    """
    t = _time(duration, dt)
    return val.finite("stick_slip_force", "amplitude", amplitude) * np.sin(
        2.0 * np.pi * val.positive("stick_slip_force", "frequency", frequency) * t
    )


def reversal_position(*, duration: float = 4.0, dt: float = 2.5e-4, amplitude: float = 2e-5, frequency: float = 0.5) -> np.ndarray:
    """Sinusoidal position ``amplitude·sin(2π f t)`` [m]: repeated velocity reversals.

    With an amplitude of tens of µm the stroke spans pre-sliding and gross sliding,
    giving the classic hysteresis loop of force over displacement.
    """
    t = _time(duration, dt)
    return val.finite("reversal_position", "amplitude", amplitude) * np.sin(
        2.0 * np.pi * val.positive("reversal_position", "frequency", frequency) * t
    )


def nested_loop_position(*, major: float = 20e-6, minor: float = 4e-6, dt: float = 1e-3, speed: float = 1e-4) -> np.ndarray:
    """Triangle path with a minor loop inside the major loop [m].

    Goes ``0 → +major → -major``, then on the way back up stops at 0, goes
    down by ``minor`` and back up to 0 (the minor loop), then continues to ``+major``.
    Constant speed ``speed`` [m/s]. Used to show non-local memory (seed 000 §5.3).
    """
    major = val.positive("nested_loop_position", "major", major)
    minor = val.positive("nested_loop_position", "minor", minor)
    speed = val.positive("nested_loop_position", "speed", speed)
    dt = val.positive("nested_loop_position", "dt", dt)
    corners = [0.0, major, -major, 0.0, -minor, 0.0, major]
    step = speed * dt
    pts = [np.array([0.0])]
    for a, b in zip(corners[:-1], corners[1:]):
        n = max(int(round(abs(b - a) / step)), 1)
        pts.append(np.linspace(a, b, n + 1)[1:])
    return np.concatenate(pts)


def example_law():
    """The example Stribeck law of the issue tracker and README: Fc 1 N, Fs 1.5 N, vs 1 mm/s, sigma2 0.4 N·s/m."""
    from ..models import Stribeck

    return Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, delta=2.0, sigma2=0.4)


def example_gms(M: int, C: float = 20.0):
    """A GMS model with ``M`` elements over :func:`example_law` for tests and benchmarks.

    Stiffnesses spaced logarithmically over 1e4 … 1e6 N/m (element ``i = 0`` the softest),
    weights proportional to ``1/(M - i)`` and normalised to sum 1: the STIFFEST element
    carries the most (GMS-16: ξ from 0.018 to 0.296). ``M = 3`` is the exception, kept as
    first written: k = 1e4, 1e5, 1e6 N/m with ξ = 0.5, 0.3, 0.2 (the softest carries the
    most). The benchmarks' GMS-4 and GMS-16 are built here, so the weights stay as they are.
    """
    from ..models import GMS

    if M == 3:
        return GMS(example_law(), k=[1e4, 1e5, 1e6], xi=[0.5, 0.3, 0.2], C=C)
    i = np.arange(M)
    k = 1e4 * 100.0 ** (i / max(M - 1, 1))
    w = 1.0 / (M - i)
    return GMS(example_law(), k=k, xi=w / w.sum(), C=C)


def example_lugre():
    """LuGre over :func:`example_law`: sigma0 1e5 N/m, sigma1 63.2 N·s/m (0.1 of critical on 1 kg)."""
    from ..models import LuGre

    return LuGre(example_law(), sigma0=1e5, sigma1=63.2)
