"""The tuple form of the Stribeck magnitude used in the kernels' hot loops against the model.

The reference is the model's own Stribeck curve (``models.static``, numpy code written
separately from the kernels); the slope is checked against a central
difference of that reference.
"""

from __future__ import annotations

import numpy as np
import pytest

import frictionkit as fk
from frictionkit.kernels import _stribeck as S


def _laws():
    yield fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, delta=2.0, sigma2=0.4)
    yield fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, delta=1.0)
    yield fk.Stribeck(Fc=2.0, Fs=1.2, vs=3e-2, delta=0.7)  # Fs < Fc, pow path
    yield fk.Stribeck(Fc=0.3, Fs=0.9, vs=2e-3, delta=2.0, shape="lorentzian")
    yield fk.Directional(
        positive=fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3),
        negative=fk.Stribeck(Fc=0.8, Fs=1.1, vs=4e-3, delta=1.5, shape="lorentzian"),
    )


def _g_model(law, P, i, av):
    """``|s(v)|`` from the model's steady-state map, in the direction of row ``i``."""
    v = np.asarray(av, float) * (1.0 if i == 0 else -1.0)
    return np.abs(law.stribeck(v))


@pytest.mark.parametrize("law", list(_laws()), ids=lambda law: type(law).__name__)
def test_row_tuple_matches_the_model(law):
    P = np.ascontiguousarray(law.static_rows())
    for i in (0, 1):
        p = S.row(P, i)
        vs = P[i, 2]
        # speeds from rest through the Stribeck range to far past the underflow cut-off,
        # including points just either side of the cut
        av = np.geomspace(1e-9, 10.0, 400)
        if P[i, 5] == 0.0:
            cut = vs * S.UNDERFLOW ** (1.0 / P[i, 3])
            assert p[S.R_VCUT] == pytest.approx(cut, rel=1e-15)
            av = np.concatenate([av, cut * np.array([1 - 1e-12, 1.0, 1 + 1e-12])])
        else:
            assert p[S.R_VCUT] == np.inf
        g_ref = _g_model(law, P, i, av)
        g = np.array([S.g_row(p, a) for a in av])
        assert np.allclose(g, g_ref, rtol=1e-13, atol=0.0)
        gs = np.array([S.g_slope_row(p, a) for a in av])
        igs = np.array([S.ig_slope_row(p, a) for a in av])
        ig = np.array([S.ig_row(p, a) for a in av])
        assert np.allclose(gs[:, 0], g_ref, rtol=1e-13, atol=0.0)
        assert np.allclose(ig, 1.0 / g_ref, rtol=1e-13, atol=0.0)
        assert np.allclose(igs[:, 0], 1.0 / g_ref, rtol=1e-13, atol=0.0) and np.array_equal(igs[:, 1], gs[:, 1])
        # slope against a central difference of the model, away from rest and from
        # delta < 1's infinite slope at 0
        a = np.geomspace(0.05 * vs, 20 * vs, 60)
        h = 1e-6 * a
        fd = (_g_model(law, P, i, a + h) - _g_model(law, P, i, a - h)) / (2 * h)
        slope = np.array([S.g_slope_row(p, x)[1] for x in a])
        scale = abs(P[i, 1] - P[i, 0]) / vs
        assert np.allclose(slope, fd, rtol=1e-5, atol=1e-7 * scale)
        # at rest: g = Fs and no slope; past the cut: g = Fc exactly
        assert S.g_row(p, 0.0) == pytest.approx(P[i, 1], rel=1e-15)
        assert S.g_slope_row(p, 0.0) == (P[i, 1], 0.0)
        if P[i, 5] == 0.0:
            assert S.g_row(p, 2 * p[S.R_VCUT]) == P[i, 0] and S.g_slope_row(p, 2 * p[S.R_VCUT]) == (P[i, 0], 0.0)
