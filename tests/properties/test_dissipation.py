"""Dissipation: over any closed displacement cycle the friction does non-negative work.

Cycles are random turning-point sequences that return to the start, each leg at
its own constant speed (motion-driven, piecewise-linear position). For LuGre the
property holds only while ``|v| <= 4 g(v) / sigma1`` (Barabanov & Ortega 2000: the
``sigma1 dz/dt`` term can return energy faster than that), so leg speeds are
drawn inside that bound; GMS needs no bound.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import frictionkit as fk

DT = 1e-3


def _cycle(turns, speeds) -> np.ndarray:
    pts = [np.array([0.0])]
    corners = [0.0, *turns, 0.0]
    for (a, b), sp in zip(zip(corners[:-1], corners[1:]), speeds):
        n = max(int(np.ceil(abs(b - a) / (sp * DT))), 1)
        pts.append(np.linspace(a, b, n + 1)[1:])
    return np.concatenate(pts)


def _work(res) -> float:
    """∮ F dx with F on each interval taken at the interval's end (exact for the
    linear pre-sliding branch in the limit, conservative otherwise) — trapezoid."""
    dx = np.diff(res.x)
    return float(np.sum(0.5 * (res.friction[1:] + res.friction[:-1]) * dx))


laws = st.builds(
    lambda Fc, ratio, vs, delta, sigma2, lor: fk.Stribeck(
        Fc=Fc, Fs=Fc * ratio, vs=vs, delta=delta, sigma2=sigma2, shape="lorentzian" if lor else "exponential"
    ),
    Fc=st.floats(0.1, 10.0),
    ratio=st.floats(0.7, 2.0),
    vs=st.floats(1e-4, 1e-2),
    delta=st.floats(0.5, 2.5),
    sigma2=st.floats(0.0, 5.0),
    lor=st.booleans(),
)
turns = st.lists(st.floats(-50e-6, 50e-6).filter(lambda a: abs(a) > 1e-8), min_size=1, max_size=6)


# Random weights on purpose (dissipation must hold for any sum): the weight-sum warning is expected.
@pytest.mark.filterwarnings("ignore::frictionkit.models.gms.GMSWeightWarning")
@settings(max_examples=60, deadline=None)
@given(law=laws, turn_points=turns, k=st.lists(st.floats(1e3, 1e8), min_size=1, max_size=6), data=st.data())
def test_gms_dissipates_over_closed_cycles(law, turn_points, k, data):
    xi = data.draw(st.lists(st.floats(0.01, 1.0), min_size=len(k), max_size=len(k)))
    C = data.draw(st.floats(1.0, 1e4))
    speeds = data.draw(st.lists(st.floats(1e-6, 1e-2), min_size=len(turn_points) + 1, max_size=len(turn_points) + 1))
    model = fk.GMS(law, k=k, xi=xi, C=C)
    res = fk.simulate(model, position=_cycle(turn_points, speeds), dt=DT)
    scale = max(law.Fc, law.Fs) * sum(abs(a) for a in turn_points)
    assert _work(res) >= -1e-9 * scale


@settings(max_examples=60, deadline=None)
@given(law=laws, turn_points=turns, sigma0=st.floats(1e3, 1e8), data=st.data())
def test_lugre_dissipates_over_closed_cycles(law, turn_points, sigma0, data):
    sigma1 = data.draw(st.floats(0.0, 2.0 * np.sqrt(sigma0)))
    gmin = min(law.Fc, law.Fs)
    vmax = 1e-2 if sigma1 == 0.0 else min(1e-2, 4.0 * gmin / sigma1)
    speeds = data.draw(
        st.lists(st.floats(1e-6, 1.0), min_size=len(turn_points) + 1, max_size=len(turn_points) + 1)
    )
    speeds = [max(1e-7, s * vmax) for s in speeds]
    model = fk.LuGre(law, sigma0=sigma0, sigma1=sigma1)
    res = fk.simulate(model, position=_cycle(turn_points, speeds), dt=DT)
    scale = max(law.Fc, law.Fs) * sum(abs(a) for a in turn_points)
    assert _work(res) >= -1e-9 * scale
