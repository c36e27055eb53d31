"""LuGre kernels: force-driven mass (spanning exponential steps) and motion-driven (exact).

Force-driven scheme
-------------------
State ``(x, v, z)``; the input ``u(t)`` is linear between samples. The friction force is
``F = sigma0 z + sigma1 dz/dt + sigma2 v`` with ``dz/dt = v - sigma0 |v| z / g(v)``, so the
only nonlinearity of the whole system is ``dz/dt`` (through ``|v|`` and ``g``).

:func:`lugre_force` takes steps that span several samples (issue 15). At the step's start
the system is linearised, ``(v, z)' = B (v, z) + r + e_v u / m`` with ``B`` the exact
Jacobian of the side of ``|v|`` the step is on, and ``x' = v``. Pass 1 solves this affine
model exactly from sample to sample (``phi`` functions of ``B dt``, :mod:`._phi2`; the
piecewise-linear input enters exactly), writing the samples as it goes and stopping
before the linearised velocity would change sign. The remainder of ``dz/dt`` along that
path (zero at the start, second order in the motion) is evaluated at the middle and the
last sample and modelled as ``g(s) = ca (s/h) + cb (s/h)^2``; pass 2 adds the exact
solution of the correction ``d' = B d + g(s) w`` (``w = (-sigma1 / m, 1)``: the remainder
enters ``dz/dt`` and, through ``sigma1``, ``F``) to every sample. This is the exponential
Rosenbrock idea (Hochbruck, Ostermann & Schweitzer 2009, SIAM J. Numer. Anal. 47) with the
remainder fitted over the step, and it gives a dense output at every sample for ~20 flops.
The size of the correction at the step's end is the error of pass 1 and serves as the
(conservative) error estimate; measured on the stick-slip benchmark, the corrected path's
local error was 1e-3 ... 1e-2 of it. The pre-sliding oscillation and the stiff bristle
relaxation while sliding are both inside ``B`` and integrated exactly, so a step is
limited only by how fast the linearisation changes: on the 10 s stick-slip benchmark
~990 exponential steps for 40,000 samples (0.17 sub-steps per sample counting the ROS2
sub-steps at velocity reversals).

A single sample that fails the conservative estimate is checked by its own error
(:func:`_sharp_sample`: the remainder at mid-sample gives a two-node fit, whose difference
from the end-only fit plus the Picard difference at the corrected end is the error; the
sample then takes the two-node fit). After a Dahl velocity reversal this replaced ~22
samples of ~30 ROS2 sub-steps each (10 s stick-slip Dahl: 6,907 -> 916 counted steps,
and more accurate). Where the velocity reverses inside the next sample (the kink of
``|v|``), or one sample fails this too, that sample interval is covered by adaptive ROS2 sub-steps
(:func:`_interval`, below), the scheme that covered every interval before.

ROS2 sub-steps
--------------
Two-stage, L-stable Rosenbrock method ROS2 (Verwer, Spee, Blom & Hundsdorfer 1999,
``gamma = 1 + 1/sqrt 2``)::

    (I - gamma h J) k1 = f(y)
    (I - gamma h J) k2 = f(y + h k1) - 2 k1
    y+ = y + 3/2 h k1 + 1/2 h k2,      error estimate  h/2 (k1 + k2)

ROS2 is second order for any matrix ``J`` (a W-method), so the kink of ``|v|``
at ``v = 0`` does not need an exact Jacobian. L-stability makes the bristle
relaxation (rate ``sigma0 |v| / |s(v)|``, up to 1e7 /s when sliding) and a
pre-sliding spring of 1e8 N/m harmless. The 4x4 linear systems are solved in
closed form (rows for ``x`` and ``w`` are trivial). :func:`lugre_force_ros2` and the
batch kernel use these sub-steps in every interval.

Motion-driven scheme
--------------------
Position samples are interpolated linearly, so ``v`` is constant on each
interval and ``dz/dt = v - a z`` with constant ``a = sigma0 |v| / |s(v)|`` has
the exact solution ``z(h) = z_ss + (z0 - z_ss) exp(-a h)``; no error at all
beyond round-off.

Invariant bounds of ``z`` (issue 13): the exact deflection never leaves
``[min(z0, -Fs/sigma0), max(z0, Fs/sigma0)]`` (per direction, :func:`_z_bounds`). Both step
types count an excursion beyond them as local error and project accepted states back onto
them. Without this a ROS2 step across breakaway at ``sigma0 = 1e16`` N/m ran ``sigma0 z`` to
2 N (``Fs`` = 1.5 N) with a filtered error estimate far below 1 and the mass stuck (status 0).

Status codes: 0 ok, 1 non-finite state, 2 sub-step budget exhausted,
3 error control failed (the sub-step fell to ``H_MIN * dt`` and still did not
meet the tolerance: step-size underflow). A step is never accepted with its
error estimate above the tolerance.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import njit, prange
from ._phi2 import phis
from ._stribeck import R_DF, R_FC, R_FS, R_S2, g_row, ig_row, ig_slope_row
from ._stribeck import row as static_row

GAMMA = 1.0 + 1.0 / math.sqrt(2.0)

OK, NONFINITE, BUDGET, TOLERANCE = 0, 1, 2, 3

#: Smallest sub-step as a fraction of ``dt``; below it the error control gives up.
H_MIN = 1e-7

#: ``0.9 / sqrt(e) >= 5`` for ``e <= (0.9 / 5)^2``.
E_GROW = (0.9 / 5.0) ** 2

#: Largest balanced norm of ``dt B`` for a spanning step (``_phi2.phis`` then squares at most
#: 20 times, losing at most ~2^20 eps = 2e-10 relative). Stiffer linearisations -- a bristle
#: rate ``sigma0 |v| / g`` above 2e9 /s at 4 kHz, reached only by a level floored at
#: ``G_FLOOR`` -- take ROS2 sub-steps: at 34 squarings (rate 3e13 /s) the friction force
#: ``sigma0 z + sigma1 dz/dt`` was off by 100 N (tests/kernels/test_vanishing_levels.py).
EXP_NORM_MAX = 2.0**19

#: ROS2 intervals on a lightly damped contact that rings fast against the samples (named
#: assumptions, issue 15): when the linearisation at an interval's start is an oscillation with
#: ``omega dt > RING_FAST`` and damping ratio ``< RING_ZETA``, the interval's sub-steps meet a
#: ``RING_TIGHT`` times tighter tolerance (:func:`_ring_tight`). There a reversal falls every few
#: samples, so most of the run is ROS2 sub-steps (a Dahl on 9.7e6 N/m, 0.74 kg: 7 samples a
#: period, ~50 sub-steps a sample) whose local errors add up over the undamped ringing: 10.1x
#: rtol of the position range against the solve_ivp twin (the error contract is 10x; 16.5x with
#: ROS2 in every interval). 4x tighter: 4.4x / 2.9x (x / F range; 8x: 3.7x, the rest is the
#: spanning steps'), at twice the sub-steps on that run only. RING_FAST = 0.25 (a period shorter
#: than 25 samples) and RING_ZETA = 0.2 leave the benchmarks' contacts (omega dt <= 0.14) and
#: every damped LuGre of the contract's random sets untouched.
RING_FAST = 0.25
RING_ZETA = 0.2
RING_TIGHT = 4.0

#: Spanning steps on a linearisation that rings faster than the samples resolve (named assumption,
#: issue 13): when ``B`` has complex eigenvalues ``mu +- i omega`` with ``omega dt > RING_RESOLVE``, the
#: samples no longer show what happens between them: the parabola test of pass 1 assumes at most one
#: turn of ``v`` per interval, and the remainder fit of ``dz/dt`` sees its values at samples only, while
#: the ringing makes it oscillate in between. Such a step's intervals are checked in closed form
#: (:func:`_ring_path`): a possible reversal inside an interval (:func:`_ring_reverses`, a bound) fails
#: the step, and the remainder's misfit at nodes inside every interval (:func:`_ring_misfit`) is
#: integrated into an error estimate that the step must meet besides its own. 1: up to one radian of
#: phase per sample, where the parabola test still catches a dip through zero (a sinusoid's trough
#: inside the interval is flagged for ``|v_forced| < 1.1 A`` at 1 rad, ``1.4 A`` at 2 rad) and the
#: samples resolve the remainder (6 per period); the benchmarks' contacts (omega dt <= 0.14) and the
#: error contract's sets (<= 0.9) never reach it. Found on a LuGre at omega dt 14.9, damping ratio 0.009
#: (round 8): single-sample spanning steps across 2.4 periods of the pre-sliding ringing were accepted
#: with local errors ~1000 tolerances (the estimate saw the samples only): 4.4 % of the velocity range
#: and 42 rtol of the position range off the twin at every rtol; now 0.075 % and 0.4 rtol (ROS2 there).
RING_RESOLVE = 1.0

#: The friction force's share of the local error (issue 13, helper lugw2's campaign): both step types
#: also bound the error of ``F = sigma0 z + sigma1 dz/dt + sigma2 v`` that their ``v`` and ``z`` errors make,
#: ``|dF/dv ev + dF/dz ez| <= atol_z sigma0 + rtol |F|`` (``atol_z sigma0 = atol_F max(Fc, Fs)``, the friction
#: state's own absolute tolerance in force units). Why: while a heavily damped contact slides, ``dz/dt`` is a
#: small difference of ``v`` and ``sigma0 |v| z / g``, each held to ``rtol`` of itself, and ``sigma1`` times it
#: is in ``F`` -- an overdamped LuGre (sigma1 1.3-1.7x critical, omega dt 0.24-0.28) passed 8.9-10 rtol of its
#: friction range off the twin at the default tolerances and 16 rtol at rtol = atol_F = 1e-7 (x within 0.6
#: rtol); with this term 1.3-3.1 rtol, at 6-9 % more sub-steps there and none more on the benchmarks' runs.
#: 1: the friction force is held to the friction state's own tolerance.
F_ERROR = 1.0

#: Most samples one spanning exponential step covers (the linearisation is refreshed at
#: least this often; 256 samples = 64 ms at 4 kHz).
SPAN_MAX = 256


@njit(inline="always")
def _side(v, p0, p1, d0, d1):
    """Stribeck row tuple and ``(sigma0, sigma1)`` for the direction of ``v`` (row 0: ``v >= 0``)."""
    if v >= 0.0:
        return p0, d0
    return p1, d1


@njit(inline="always")
def _force(v, z, p0, p1, d0, d1):
    """Return ``(dz/dt, F)`` for the parameter row selected by the sign of ``v``.

    ``p0, p1`` are the Stribeck row tuples (``_stribeck.row``) and ``d0, d1`` the
    ``(sigma0, sigma1)`` pairs for ``v >= 0`` and ``v < 0``.
    """
    p, d = _side(v, p0, p1, d0, d1)
    av = abs(v)
    zd = v - d[0] * av * z * ig_row(p, av)
    return zd, d[0] * z + d[1] * zd + p[R_S2] * v


@njit(inline="always")
def _point(v, z, p0, p1, d0, d1):
    """Everything the step needs at one state: ``(zd, F, dzd/dv, dzd/dz, dF/dv, dF/dz)``."""
    p, d = _side(v, p0, p1, d0, d1)
    s0 = d[0]
    s1 = d[1]
    av = abs(v)
    ig, gr = ig_slope_row(p, av)
    a = s0 * av * ig
    zd = v - a * z
    sg = 1.0 if v > 0.0 else (-1.0 if v < 0.0 else 0.0)
    dzd_dv = 1.0 - s0 * z * sg * ig * (1.0 - av * gr * ig)
    return (
        zd,
        s0 * z + s1 * zd + p[R_S2] * v,
        dzd_dv,
        -a,
        s1 * dzd_dv + p[R_S2],
        s0 - s1 * a,
    )


@njit(inline="always")
def _flat(p):
    """A row with ``Fs = Fc`` (Dahl) gets ``v_cut = 0``: ``g = Fc`` without evaluating
    ``(Fs - Fc) exp(...) = 0`` (the same values; ``g_row`` returns ``Fs = Fc`` at rest)."""
    if p[R_DF] == 0.0:
        return (p[0], p[1], p[2], p[3], p[4], p[5], 0.0, p[7], p[8])
    return p


@njit(inline="always")
def _z_bounds(p0, p1, d0, d1, z0):
    """Bounds ``(zlo, zhi)`` that the exact bristle deflection never leaves from ``z0``.

    Moving forward, ``dz/dt = v (1 - sigma0 z / g(v))`` is negative above ``g / sigma0``;
    backward, ``dz/dt = -|v| (1 + sigma0 z / g)`` is positive below ``-g / sigma0``. So
    ``z`` stays in ``[min(z0, -Gmax_1 / sigma0_1), max(z0, Gmax_0 / sigma0_0)]`` with
    ``Gmax`` the larger (floored) level of each row. The kernels keep the numerical ``z``
    inside too: a step that leaves the bounds has a local error of at least the excess
    (counted by :func:`_z_excess`), and an accepted step is projected back onto them
    (clipping onto an interval that holds the exact solution never increases the error).
    Issue 13: at ``sigma0 = 1e16`` N/m a ROS2 step over a whole sample ran ``sigma0 z``
    to 2 N, past ``Fs = 1.5`` N, with a filtered error estimate far below 1, and the mass
    stuck; with the excess counted but no projection, steps crept past the bound by one
    tolerance each (``sigma0 = 1e30``: stuck again).
    """
    zhi = max(p0[R_FC], p0[R_FS]) / d0[0]
    zlo = -max(p1[R_FC], p1[R_FS]) / d1[0]
    return min(z0, zlo), max(z0, zhi)


@njit(inline="always")
def _z_excess(zn, zlo, zhi, atol_z, rtol):
    """How far ``zn`` left the invariant bounds ``[zlo, zhi]``, in tolerances (0 inside)."""
    if zn > zhi:
        return (zn - zhi) / (atol_z + rtol * abs(zhi))
    if zn < zlo:
        return (zlo - zn) / (atol_z + rtol * abs(zlo))
    return 0.0


@njit(inline="always")
def _atol_run(atol_v, v_floor, rtol, vpk):
    """Absolute velocity tolerance that follows the run's range.

    ``min(atol_v, rtol * vpk)`` with ``vpk`` the largest ``|v|`` so far, but at least
    ``v_floor * atol_v``. ``atol_v`` is an a-priori scale (``F / sqrt(K m)``, the
    ringing speed if the whole friction level were released at once); a run that
    never moves that fast -- pre-sliding under a slow input, a heavy mass -- would
    otherwise be integrated with an absolute error comparable to its whole velocity
    range, and an undamped pre-sliding ringing (Dahl, GMS without sigma2) drifts in
    phase by a fraction of a period: measured 2.6 % of the position range on a Dahl
    run against the solve_ivp twin at the default rtol (issue 15).
    """
    return max(v_floor * atol_v, min(atol_v, rtol * vpk))


@njit(inline="always")
def _ring_path(b11, b12, b21, b22, mu, om, det, v0, z0, c0v, c0z, c1v):
    """The linearised path over one sample interval in closed form (issue 13).

    ``y' = B y + c0 + c1 s`` on ``(v, z)`` (``c1 = (c1v, 0)``: the input's slope) with complex
    eigenvalues ``mu +- i om`` of ``B`` (``det = det B``) is the forced path
    ``y_p(s) = p0 + p1 s`` (``p1 = -B^-1 c1``, ``p0 = B^-1 (p1 - c0)``) plus the free ringing
    ``e^(mu s) (a cos(om s) + b sin(om s))`` from ``y(0) - p0``. Returns
    ``(p0v, p1v, av, bv, p0z, p1z, az, bz)``.
    """
    idet = 1.0 / det
    p1v = -b22 * c1v * idet
    p1z = b21 * c1v * idet
    qv = p1v - c0v
    qz = p1z - c0z
    p0v = (b22 * qv - b12 * qz) * idet
    p0z = (b11 * qz - b21 * qv) * idet
    ev = v0 - p0v
    ez = z0 - p0z
    return (p0v, p1v, ev, (b11 * ev + b12 * ez - mu * ev) / om,
            p0z, p1z, ez, (b21 * ev + b22 * ez - mu * ez) / om)


@njit(inline="always")
def _ring_reverses(path, mu, dt, sd):
    """Whether the linearised velocity of :func:`_ring_path` may reach zero inside the interval.

    ``|v - v_p| <= A = sqrt(a^2 + b^2) max(1, e^(mu dt))`` over the interval, so ``v`` keeps the
    side ``sd`` when ``v_p`` (linear in ``s``) stays beyond ``A`` at both ends. Conservative: True
    whenever that bound does not exclude a reversal.
    """
    p0v, p1v, av, bv = path[0], path[1], path[2], path[3]
    amp = math.sqrt(av * av + bv * bv)
    if mu > 0.0:
        amp *= math.exp(mu * dt)
    sg = 1.0 if sd > 0.0 else -1.0
    return min(sg * p0v, sg * (p0v + p1v * dt)) <= amp


@njit  # a call: reached only on a linearisation that rings faster than the samples (RING_RESOLVE)
def _ring_misfit(path, mu, om, dt, s0, hstep, ca, cb, b21, b22, r1, p0, p1, d0, d1, sd):
    """Largest ``|remainder - fit|`` of ``dz/dt`` at nodes inside one sample interval (issue 13).

    ``path``: :func:`_ring_path` of the interval, which starts ``s0`` after the step's start;
    ``ca, cb``: the step's fit ``g(s) = ca (s/hstep) + cb (s/hstep)^2`` of the remainder (module
    docstring), which pass 1 takes from the samples only. Nodes at the middles of
    ``ceil(8 om dt / pi)`` equal parts of the interval: the remainder is quadratic in the ringing
    (frequencies up to ``2 om``), so 8 nodes per ringing period sample its peaks to within
    ``cos(pi / 8)`` = 0.92. Returns ``inf`` when a node's velocity is not on the side ``sd``.
    """
    p0v, p1v, av, bv, p0z, p1z, az, bz = path
    M = int(math.ceil(8.0 * om * dt / math.pi))
    ds = dt / M
    rc = math.cos(om * ds)
    rs = math.sin(om * ds)
    ed = math.exp(mu * ds)
    c = math.cos(0.5 * om * ds)
    sn = math.sin(0.5 * om * ds)
    em = math.exp(0.5 * mu * ds)
    ih = 1.0 / hstep
    worst = 0.0
    for n in range(M):
        s = (n + 0.5) * ds
        vv = p0v + p1v * s + em * (av * c + bv * sn)
        zz = p0z + p1z * s + em * (az * c + bz * sn)
        if vv * sd <= 0.0:
            return np.inf
        th = (s0 + s) * ih
        r = _force(vv, zz, p0, p1, d0, d1)[0] - (b21 * vv + b22 * zz + r1) - (ca + cb * th) * th
        worst = max(worst, abs(r))
        c, sn = c * rc - sn * rs, sn * rc + c * rs
        em *= ed
    return worst


@njit  # a call, not inlined: reached only where a single sample fails the conservative estimate
def _sharp_sample(b11, b12, b21, b22, dt, v0, z0, r0, r1, a0, a1, ge, v1, z1, ev, ez, W2v, W3v, W2z, W3z, X3, X4,
                  p0, p1, d0, d1, sd, tv, tz, q, zlo, zhi):
    """Error of a corrected single-sample spanning step, and a better sample (issue 15).

    Returns ``(e, dx, v, z)``: ``e`` in tolerances (``tv``, ``tz``: the absolute tolerances of
    ``v`` and ``z``; ``q``: the step's bound excess, kept), ``dx`` to add to the sample's
    ``x`` and the new ``v, z``. ``e > 1``: not accepted (``1e10`` if the better sample
    reverses).

    The step's correction (``ev, ez``) is the error of the *uncorrected* sample, a
    first-order bound: after a Dahl/LuGre velocity reversal it read 5-27 tolerances where
    the corrected sample was off by 0.03-0.7, and each such sample took ~30 ROS2 sub-steps.
    The corrected sample's own error has two parts, both measured here. (1) The remainder
    of ``dz/dt`` was modelled as ``ge s^2`` (zero value and slope at the start, ``ge`` at
    the end); its value at mid-sample on the linearised path (``phi`` functions of
    ``B dt / 2``) gives the two-node fit ``ca s + cb s^2``, and the response to the
    difference ``-ca s (1 - s)`` is the fit error. (2) The remainder was taken on the
    uncorrected path; its change at the corrected end, ``ge1 - ge``, scales the correction
    (Picard difference). Measured on the 10 s Dahl stick-slip run against one-sample ROS2
    at rtol 1e-13 over 296 such samples: true error of the end-only fit / this estimate
    0.01-0.993 (median 0.96). Assumption: the sum of both parts, no safety factor. The
    sample then takes the two-node fit (local extrapolation: the estimate bounds the worse
    of the two), so the accepted sample is more accurate than the estimate says.
    """
    h = 0.5 * dt
    Eh, Q1, Q2, _, _ = phis((b11 * h, b12 * h, b21 * h, b22 * h))
    c0 = r0 + a0
    vm = Eh[0] * v0 + Eh[1] * z0 + h * (Q1[0] * c0 + Q1[1] * r1) + h * h * Q2[0] * a1
    zm = Eh[2] * v0 + Eh[3] * z0 + h * (Q1[2] * c0 + Q1[3] * r1) + h * h * Q2[2] * a1
    gm = _force(vm, zm, p0, p1, d0, d1)[0] - (b21 * vm + b22 * zm + r1)
    ca = 4.0 * gm - ge
    ge1 = _force(v1, z1, p0, p1, d0, d1)[0] - (b21 * v1 + b22 * z1 + r1)
    rp = abs(ge1 - ge) / abs(ge) if ge != 0.0 else 0.0
    e = max((abs(ca * (W3v - W2v)) + rp * abs(ev)) / tv, (abs(ca * (W3z - W2z)) + rp * abs(ez)) / tz, q)
    vn = v1 + ca * (W2v - W3v)
    zn = min(max(z1 + ca * (W2z - W3z), zlo), zhi)
    if vn * sd <= 0.0:
        e = 1e10  # the better sample reverses: not this step
    return e, ca * (X3 - X4), vn, zn


@njit(inline="always")
def _ros2_sub(x, v, z, h, w, du, im, zd, F, dzv, dzz, dFv, dFz, p0, p1, d0, d1, tol_v, rtol, atol_z, zlo, zhi):
    """One ROS2 sub-step of ``h`` from ``(x, v, z)`` (input ``w`` at its start, slope ``du``;
    ``zd, F, dzv, ...`` from :func:`_point` there) and its error in tolerances.

    Returns ``(finite, xn, vn, zn, e, v2, z2, gh, a11, a12, a21, a22, idet)``: the new state, ``e``
    (the filtered estimate of the embedded first-order solution and the excess of ``zn`` over
    its invariant bounds ``zlo, zhi``; not accepted above 1), the second stage's state and the
    matrix ``I - gamma h J`` with its inverse determinant -- what :func:`_interval` and the
    sensitivity kernel's W-method (``sensitivity._ros2_sens``) both need. ``finite`` false: the
    new state is inf or NaN (``e`` then 0, meaningless).
    """
    gh = GAMMA * h
    # I - gamma h J on (v, z); rows of x and w are trivial
    a11 = 1.0 + gh * dFv * im
    a12 = gh * dFz * im
    a21 = -gh * dzv
    a22 = 1.0 - gh * dzz
    idet = 1.0 / (a11 * a22 - a12 * a21)
    # stage 1
    b1 = (w - F + gh * du) * im
    k1v = (b1 * a22 - a12 * zd) * idet
    k1z = (a11 * zd - a21 * b1) * idet
    k1x = v + gh * k1v
    # stage 2 at y + h k1 (w advances by h du)
    v2 = v + h * k1v
    z2 = z + h * k1z
    zd2, F2 = _force(v2, z2, p0, p1, d0, d1)
    r_z = zd2 - 2.0 * k1z
    b1 = (w + h * du - F2 - gh * du) * im - 2.0 * k1v
    k2v = (b1 * a22 - a12 * r_z) * idet
    k2z = (a11 * r_z - a21 * b1) * idet
    k2x = v2 - 2.0 * k1x + gh * k2v
    xn = x + h * (1.5 * k1x + 0.5 * k2x)
    vn = v + h * (1.5 * k1v + 0.5 * k2v)
    zn = z + h * (1.5 * k1z + 0.5 * k2z)
    if not math.isfinite(xn + vn + zn):  # inf or NaN in any of them (inf - inf is NaN)
        return False, xn, vn, zn, 0.0, v2, z2, gh, a11, a12, a21, a22, idet
    # Error estimate of the embedded first-order solution, filtered through
    # (I - gamma h J)^-1 so that stiff, quickly damped components (the bristle
    # state while sliding) do not force needlessly small steps (Shampine).
    e1 = 0.5 * h * (k1v + k2v)
    e2 = 0.5 * h * (k1z + k2z)
    ev = (e1 * a22 - a12 * e2) * idet
    ez = (a11 * e2 - a21 * e1) * idet
    e = abs(ev) / (tol_v + rtol * abs(vn))
    q = abs(ez) / (atol_z + rtol * abs(zn))
    if q > e:
        e = q
    # the friction force's share of the error (F_ERROR): its absolute tolerance is atol_z in force units
    q = F_ERROR * abs(dFv * ev + dFz * ez) / (atol_z * max(d0[0], d1[0]) + rtol * abs(F))
    if q > e:
        e = q
    # the filtered estimate can miss a whole-sample step that runs z past its bound
    # (a near-singular I - gamma h J at breakaway, issue 13): the excess is an error too
    q = _z_excess(zn, zlo, zhi, atol_z, rtol)
    if q > e:
        e = q
    return True, xn, vn, zn, e, v2, z2, gh, a11, a12, a21, a22, idet


@njit(inline="always")
def _ring_tight(dFv, dFz, dzv, dzz, im, dt):
    """Error factor of an ROS2 interval: ``RING_TIGHT`` when the linearisation ``B`` at its start
    (``_point``'s derivatives, ``im = 1/m``) is an oscillation with ``omega dt > RING_FAST`` and
    damping ratio below ``RING_ZETA``, else 1 (see ``RING_FAST``)."""
    b11 = -dFv * im
    b22 = dzz
    w2 = b11 * b22 + dFz * im * dzv  # det B
    if w2 > 0.0 and (b11 - b22) * (b11 - b22) < 4.0 * w2:  # complex eigenvalues
        om = math.sqrt(w2)
        if om * dt > RING_FAST and -(b11 + b22) < 2.0 * RING_ZETA * om:
            return RING_TIGHT
    return 1.0


@njit(inline="always")
def _interval(x, v, z, h_try, u0, u1, dt, m, p0, p1, d0, d1, rtol, atol_v, atol_z, max_sub, vpk, v_floor, zlo, zhi):
    """Advance the force-driven state over one sample interval.

    Returns ``(x, v, z, F, h_try, n_substeps, status, vpk)`` with ``F`` the friction
    force at the end of the interval and ``vpk`` the largest ``|v|`` of the run so far
    (see :func:`_atol_run`). ``zlo, zhi``: bounds of ``z`` (:func:`_z_bounds`); a sub-step
    leaving them counts the excess as error. Scalars and tuples only (no arrays): see
    the note on reference counting in :mod:`._stribeck`.
    """
    im = 1.0 / m
    du = (u1 - u0) / dt
    t = 0.0
    w = u0
    n = 0
    zd, F, dzv, dzz, dFv, dFz = _point(v, z, p0, p1, d0, d1)
    tol_v = _atol_run(atol_v, v_floor, rtol, vpk)
    tight = _ring_tight(dFv, dFz, dzv, dzz, im, dt)
    while t < dt:
        h = h_try
        rem = dt - t
        if h >= rem or rem - h < 1e-9 * dt:
            h = rem
        fin, xn, vn, zn, e, _, _, _, _, _, _, _, _ = _ros2_sub(
            x, v, z, h, w, du, im, zd, F, dzv, dzz, dFv, dFz, p0, p1, d0, d1, tol_v, rtol, atol_z, zlo, zhi)
        n += 1
        e *= tight  # lightly damped fast ringing (RING_FAST)
        if not fin:  # inf or NaN in the new state
            if h > H_MIN * dt:
                h_try = 0.1 * h
                continue
            return x, v, z, F, h_try, n, NONFINITE, vpk
        if e > 1.0 and h <= H_MIN * dt:
            # step-size underflow: the tolerance cannot be met (e.g. a mass so small that
            # the velocity follows the force faster than 1e-7 dt); stop, do not accept
            return x, v, z, F, h_try, n, TOLERANCE, vpk
        if e <= 1.0:
            x = xn
            v = vn
            z = min(max(zn, zlo), zhi)  # projected onto the invariant bounds (_z_bounds)
            t += h
            w = u0 + du * t
            if abs(v) > vpk:
                vpk = abs(v)
                tol_v = _atol_run(atol_v, v_floor, rtol, vpk)
            zd, F, dzv, dzz, dFv, dFz = _point(v, z, p0, p1, d0, d1)
        # growth factor 0.9 / sqrt(e) clipped to [0.2, 5]; below E_GROW it is 5 anyway,
        # which spares the sqrt and division on most sliding sub-steps
        fac = 0.9 / math.sqrt(e) if e > E_GROW else 5.0
        h_try = h * min(5.0, max(0.2, fac))
        if n >= max_sub:
            return x, v, z, F, h_try, n, BUDGET, vpk
    return x, v, z, F, h_try, n, OK, vpk


@njit
def lugre_force_ros2(u, dt, m, static, dyn, x0, v0, z0, rtol, atol_v, atol_z, max_sub, x, v, F, z, v_floor=1.0):
    """Force-driven run with ROS2 sub-steps in every sample interval (no spanning steps).

    The scheme of :func:`lugre_force` before the spanning exponential steps; kept as the
    one-step-per-interval reference of ``benchmarks/simulate.py`` (the fixed batch's scheme)
    and of the kernel tests. Fills ``x, v, F, z``; returns ``(status, k, substeps)``.

    ``v_floor`` (<= 1): the velocity tolerance follows the run's largest speed down to
    ``v_floor * atol_v`` (:func:`_atol_run`); 1 keeps ``atol_v`` fixed.
    """
    xs, vs_, zs = x0, v0, z0
    p0 = static_row(static, 0)
    p1 = static_row(static, 1)
    d0 = (dyn[0, 0], dyn[0, 1])
    d1 = (dyn[1, 0], dyn[1, 1])
    x[0] = xs
    v[0] = vs_
    z[0] = zs
    F[0] = _force(vs_, zs, p0, p1, d0, d1)[1]
    h_try = dt
    total = 0
    vpk = abs(v0)
    zlo, zhi = _z_bounds(p0, p1, d0, d1, z0)
    for k in range(u.size - 1):
        xs, vs_, zs, Fs_, h_try, n, st, vpk = _interval(
            xs, vs_, zs, h_try, u[k], u[k + 1], dt, m, p0, p1, d0, d1, rtol, atol_v, atol_z, max_sub,
            vpk, v_floor, zlo, zhi,
        )
        total += n
        x[k + 1] = xs
        v[k + 1] = vs_
        z[k + 1] = zs
        F[k + 1] = Fs_
        if st != OK:
            return st, k + 1, total
    return OK, u.size - 1, total


@njit(inline="always")  # inlined into lugre_force; the sensitivity kernel calls _span_call
def _span(u, k, n_try, xs, vs_, zs, have, pt, vpk, dt, m, p0, p1, d0, d1, rtol, atol_v, atol_z, v_floor, zlo, zhi,
          x, v, F, z):
    """One spanning exponential step from sample ``k`` (state ``xs, vs_, zs``; module docstring).

    Tries ``n_try`` samples (fewer after a failed estimate), writing the accepted samples into
    ``x, v, F, z``. ``have``: ``pt`` holds :func:`_point` at the start (carried over from the
    last accepted step). Returns ``(j, n_try, vpk, tries, pt, lin)``: ``j`` samples accepted
    (0: the step cannot start -- a reversal inside the next sample, a linearisation too stiff
    for the ``phi`` functions, or one sample that fails its estimate and :func:`_sharp_sample`
    -- and an ROS2 interval covers sample ``k``), the next ``n_try``, the largest ``|v|`` so far,
    the step attempts, ``pt`` at the new end (when ``j > 0``) and the step's linearisation
    ``(side, E, phi1, phi2, phi3, b21, b22, w_v)`` that the sensitivity kernel propagates on.
    The one step of both :func:`lugre_force` and ``sensitivity.lugre_force_sens`` (issue 11: it
    held a copy), so their states are the same by construction.
    """
    im = 1.0 / m
    dt2 = dt * dt
    N = u.size
    tries = 0
    sd = vs_  # the side of |v| the step stays on
    if sd == 0.0:
        # at rest: the side the motion starts to (acceleration, else the input's trend)
        ac = u[k] - _force(0.0, zs, p0, p1, d0, d1)[1]
        if ac == 0.0:
            ac = u[k + 1] - u[k]
            sd = math.copysign(1e-300, ac) if ac != 0.0 else 0.0
        else:
            # a force applied at once at rest (u[k] off the bristles' force, e.g. a run whose
            # u[0] != 0): an ROS2 interval covers this sample. Linearised at v = 0 (z = 0:
            # dz/dt = v), the step sees a spring settling without slip, and the remainder
            # -sigma0 |v| z / g(v) is zero at its three nodes when the transient is over before
            # mid-sample; so its estimate passed a wrong sample at every rtol (issue 13, lug13's
            # seed 519: an overdamped LuGre, m/c 0.17 ms, dt 36 ms, x 40 % of its first sample
            # and 3e-5 of its range off at rtol 1e-5 ... 1e-8). Only exact rest with an
            # unbalanced force takes it: a run from rest under u[0] = 0 goes on below.
            sd = 0.0
        have = False
    z4 = (0.0, 0.0, 0.0, 0.0)
    lin = (0.0, z4, z4, z4, z4, 0.0, 0.0, 0.0)
    j = 0
    if sd != 0.0:
        if not have:
            pt = _point(sd if vs_ == 0.0 else vs_, zs, p0, p1, d0, d1)
        zd0, F0, dzv, dzz, dFv, dFz = pt
        s0, s1 = d0 if sd > 0.0 else d1
        s2 = p0[R_S2] if sd > 0.0 else p1[R_S2]
        # linearisation y' = B y + r + e_v u / m on (v, z); x' = v
        b11 = -dFv * im
        b12 = -dFz * im
        b21 = dzv
        b22 = dzz
        if dt * (max(abs(b11), abs(b22)) + math.sqrt(abs(b12 * b21))) > EXP_NORM_MAX:
            sd = 0.0  # too stiff for the phi functions: ROS2 interval (below)
    if sd != 0.0:
        E, P1, P2, P3, P4 = phis((b11 * dt, b12 * dt, b21 * dt, b22 * dt))
        r0 = -F0 * im - (b11 * vs_ + b12 * zs)
        r1 = zd0 - (b21 * vs_ + b22 * zs)
        # one sample of the linearised model (input linear between samples)
        Rv = dt * (P1[0] * r0 + P1[1] * r1)
        Rz = dt * (P1[2] * r0 + P1[3] * r1)
        Av = dt * P1[0] * im
        Az = dt * P1[2] * im
        Bv = dt * P2[0] * im
        Bz = dt * P2[2] * im
        Pxv = dt * P1[0]
        Pxz = dt * P1[1]
        Rx = dt2 * (P2[0] * r0 + P2[1] * r1)
        Ax = dt2 * P2[0] * im
        Bx = dt2 * P3[0] * im
        # one sample of the correction, forced along w = (-sigma1 / m, 1) by the remainder
        # polynomial c0 + c1 (s / dt) + c2 (s / dt)^2
        wv = -s1 * im
        W1v = dt * (P1[0] * wv + P1[1])
        W1z = dt * (P1[2] * wv + P1[3])
        W2v = dt * (P2[0] * wv + P2[1])
        W2z = dt * (P2[2] * wv + P2[3])
        W3v = 2.0 * dt * (P3[0] * wv + P3[1])
        W3z = 2.0 * dt * (P3[2] * wv + P3[3])
        X2 = dt2 * (P2[0] * wv + P2[1])
        X3 = dt2 * (P3[0] * wv + P3[1])
        X4 = 2.0 * dt2 * (P4[0] * wv + P4[1])
        # linearised friction force F = cFv v + cFz z + cF0
        cFv = s1 * b21 + s2
        cFz = s0 + s1 * b22
        cF0 = s1 * r1
        tol_v = _atol_run(atol_v, v_floor, rtol, vpk)
        # a linearisation that rings faster than the samples resolve (RING_RESOLVE): checked
        # between the samples after pass 1 (ring = its angular frequency, else 0)
        ring = 0.0
        det = b11 * b22 - b12 * b21
        mu = 0.5 * (b11 + b22)
        if det > mu * mu:
            ring = math.sqrt(det - mu * mu)
            if ring * dt <= RING_RESOLVE:
                ring = 0.0
        while True:
            n = min(n_try, N - 1 - k)
            xa, va, za = xs, vs_, zs
            vmax = vpk
            flip = False
            j = 0
            acc = (u[k] - F0) * im  # linearised acceleration at the current sample
            acc0 = acc
            # pass 1: the linearised model, sample by sample, up to a reversal
            while j < n:
                uk = u[k + j]
                du = u[k + j + 1] - uk
                # the input's part first, the state's last: the sample-to-sample dependency is
                # one product and two additions (was five additions; ~30 % of the kernel, issue 15)
                fx = Rx + Ax * uk + Bx * du
                fv = Rv + Av * uk + Bv * du
                fz = Rz + Az * uk + Bz * du
                xn = xa + ((Pxv * va + Pxz * za) + fx)
                vn = (E[0] * va + E[1] * za) + fv
                zn = (E[2] * va + E[3] * za) + fz
                if vn * sd <= 0.0 or not math.isfinite(xn + vn + zn):
                    flip = True
                    break
                # a reversal and back between two samples of one sign (a contact ringing
                # at a few samples per period): |v| turns inside the interval and could
                # dip through zero -- up to ~dt |a| / 4 below the nearer end for a parabola
                acn = b11 * vn + b12 * zn + r0 + u[k + j + 1] * im
                if acc * sd < 0.0 < acn * sd and min(abs(va), abs(vn)) < 0.25 * dt * (abs(acc) + abs(acn)):
                    flip = True
                    break
                acc = acn
                j += 1
                x[k + j] = xn
                v[k + j] = vn
                z[k + j] = zn
                xa, va, za = xn, vn, zn
                if abs(vn) > vmax:
                    vmax = abs(vn)
            tries += 1
            if j == 0:
                break
            # remainder of dz/dt along the linearised path, g(s) = ca (s/h) + cb (s/h)^2
            ge = _force(va, za, p0, p1, d0, d1)[0] - (b21 * va + b22 * za + r1)
            if j >= 2:
                jm = j // 2
                th = jm / j
                vm = v[k + jm]
                zm = z[k + jm]
                gm = _force(vm, zm, p0, p1, d0, d1)[0] - (b21 * vm + b22 * zm + r1)
                ca = (gm - th * th * ge) / (th - th * th)
            else:
                ca = 0.0
            cb = ge - ca
            e_ring = 0.0
            if ring != 0.0:
                # the fit sees the remainder at samples only; between them a ringing path makes it
                # oscillate (issue 13): its misfit at nodes inside every interval, integrated, times
                # the largest response of v and z to a unit forcing along w (the ringing's
                # amplitude, damped or grown by mu over the step) bounds what pass 2 leaves
                # (a possible reversal inside an interval, _ring_reverses: the step fails)
                sm = 0.0
                for i in range(j):
                    path = _ring_path(b11, b12, b21, b22, mu, ring, det, v[k + i], z[k + i], r0 + u[k + i] * im, r1,
                                      (u[k + i + 1] - u[k + i]) * im / dt)
                    if _ring_reverses(path, mu, dt, sd):
                        sm = np.inf
                        break
                    sm += _ring_misfit(path, mu, ring, dt, i * dt, j * dt, ca, cb, b21, b22, r1, p0, p1, d0, d1, sd)
                gz_ = (b21 * wv + b22 - mu) / ring
                gv_ = (b11 * wv + b12 - mu * wv) / ring
                gr = dt * sm * (math.exp(mu * j * dt) if mu > 0.0 else 1.0)
                e_ring = max(gr * math.sqrt(wv * wv + gv_ * gv_) / (tol_v + rtol * abs(va)),
                             gr * math.sqrt(1.0 + gz_ * gz_) / (atol_z + rtol * abs(za)))
            # pass 2: add the correction d' = B d + g(s) w, d(0) = 0, sample by sample
            ij = 1.0 / j
            c2 = cb * ij * ij
            ex = 0.0
            ev = 0.0
            ez = 0.0
            ok = True
            zmx = zs
            zmn = zs
            # the forcing of sample i, W1 c0 + W2 c1 + W3 c2 with c0 = al i + c2 i^2, c1 = al + 2 c2 i
            # (al = ca / j, c2 = cb / j^2), as a quadratic in i by Horner: 12 operations per sample
            # instead of ~23 (issue 15); the same for the remainder's share of F below
            al = ca * ij
            G0x, G1x, G2x = X3 * al + X4 * c2, X2 * al + 2.0 * X3 * c2, X2 * c2
            G0v, G1v, G2v = W2v * al + W3v * c2, W1v * al + 2.0 * W2v * c2, W1v * c2
            G0z, G1z, G2z = W2z * al + W3z * c2, W1z * al + 2.0 * W2z * c2, W1z * c2
            Fa = s1 * al
            Fb = s1 * c2
            for i in range(j):
                ti = float(i)
                gx = G0x + ti * (G1x + ti * G2x)  # the forcing first, as in pass 1
                gv = G0v + ti * (G1v + ti * G2v)
                gz = G0z + ti * (G1z + ti * G2z)
                nx = ex + ((Pxv * ev + Pxz * ez) + gx)
                nv = (E[0] * ev + E[1] * ez) + gv
                nz = (E[2] * ev + E[3] * ez) + gz
                ex, ev, ez = nx, nv, nz
                vv = v[k + i + 1] + ev
                zz = z[k + i + 1] + ez
                zmx = max(zmx, zz)
                zmn = min(zmn, zz)
                zz = min(max(zz, zlo), zhi)  # projected onto the invariant bounds (_z_bounds)
                if vv * sd <= 0.0:
                    ok = False  # the corrected path reverses: not this step
                    break
                x[k + i + 1] += ex
                v[k + i + 1] = vv
                z[k + i + 1] = zz
                # linearised F plus sigma1 times the remainder of dz/dt there
                t1 = ti + 1.0  # s1 (ca + cb th) th at th = (i + 1) / j
                F[k + i + 1] = cFv * vv + cFz * zz + cF0 + t1 * (Fa + t1 * Fb)
            # the correction is the error of pass 1 (conservative for the corrected path)
            e = abs(ev) / (tol_v + rtol * abs(va))
            q = abs(ez) / (atol_z + rtol * abs(za))
            if q > e:
                e = q
            q = F_ERROR * abs(cFv * ev + cFz * ez) / (atol_z * s0 + rtol * abs(F0))  # the friction force's
            if q > e:
                e = q
            # z outside its invariant bounds (from the step's start) is error too (issue 13)
            q = max(_z_excess(zmx, zlo, zhi, atol_z, rtol), _z_excess(zmn, zlo, zhi, atol_z, rtol))
            if q > e:
                e = q
            if e_ring > e:
                e = e_ring
            if not ok or not math.isfinite(e):
                e = 1e10
            sharp = False
            # a single sample across which |v| turns (the acceleration changes sign inside it): the
            # remainder of dz/dt, ~ (v - v0)^2, can vanish at the sample's end while it does not
            # inside, so the end-only fit's correction says nothing: the sample's own error is measured
            # (issue 13, helper lugw2's campaign: a LuGre at a velocity peak, omega dt 0.45, took one such
            # sample with e <= 1 that was 30 tolerances off, 16 rtol of its friction range at every rtol)
            turn = j == 1 and acc0 * acc < 0.0
            if j == 1 and (1.0 < e or turn) and e < 1e10 and e_ring <= 1.0:
                # a single sample that fails the conservative estimate: measure the error of
                # the corrected sample itself before falling back to ROS2 (_sharp_sample)
                es, gx, gv, gz = _sharp_sample(
                    b11, b12, b21, b22, dt, vs_, zs, r0, r1, u[k] * im, (u[k + 1] - u[k]) / dt * im, ge,
                    v[k + 1], z[k + 1], ev, ez, W2v, W3v, W2z, W3z, X3, X4, p0, p1, d0, d1, sd,
                    tol_v + rtol * abs(va), atol_z + rtol * abs(za), q, zlo, zhi)
                if es <= 1.0:
                    e = es
                    sharp = True
                    x[k + 1] += gx
                    v[k + 1] = gv
                    z[k + 1] = gz
                elif turn:
                    e = max(e, es)  # fails: an ROS2 interval covers the turn
            if e <= 1.0:
                kn = k + j
                # the next linearisation, at the corrected end (not to first order from the
                # uncorrected one: dF/dz = sigma0 - sigma1 sigma0 |v| / g reaches -1e15 N/m
                # for a level floored at G_FLOOR, so even a 1e-14 m correction would move F)
                pt = _point(v[kn], z[kn], p0, p1, d0, d1)
                F[kn] = pt[1]
                if vmax > vpk:
                    vpk = vmax
                if flip or sharp:
                    n_try = j  # after a sharp single sample: single samples until e <= 1 again
                else:
                    # local error O(h^3): growth 0.9 e^(-1/3) clipped to [0.2, 4]
                    fac = 0.9 / e ** (1.0 / 3.0) if e > 1e-4 else 4.0
                    n_try = max(1, min(SPAN_MAX, int(j * min(4.0, max(0.2, fac)))))
                break
            if j == 1:
                j = 0
                break
            fac = 0.9 / e ** (1.0 / 3.0)
            n_try = max(1, min(j - 1, int(j * max(0.2, fac))))
        lin = (sd, E, P1, P2, P3, b21, b22, wv)
    return j, n_try, vpk, tries, pt, lin


#: :func:`_span` as a call, for ``sensitivity.lugre_force_sens`` (its steps cost far more than a
#: call; inlined there too, the kernel's cold compile took ~12 s CPU more than with its old copy).
#: IEEE division as that kernel (non-finite states are caught by the step logic).
_span_call = njit(error_model="numpy")(_span.py_func)


@njit
def lugre_force(u, dt, m, static, dyn, x0, v0, z0, rtol, atol_v, atol_z, max_sub, x, v, F, z, v_floor=1.0):
    """Force-driven run over all samples; fills ``x, v, F, z``. Returns ``(status, k, substeps)``.

    Spanning exponential steps (module docstring) with one ROS2 interval
    (:func:`_interval`) where a step cannot start (velocity reversal in the next sample)
    or fails its tolerance over a single sample. ``substeps`` counts exponential step
    attempts plus ROS2 sub-steps. ``v_floor`` (<= 1): the velocity tolerance follows the
    run's largest speed down to ``v_floor * atol_v`` (:func:`_atol_run`); 1 keeps
    ``atol_v`` fixed.
    """
    p0 = _flat(static_row(static, 0))
    p1 = _flat(static_row(static, 1))
    d0 = (dyn[0, 0], dyn[0, 1])
    d1 = (dyn[1, 0], dyn[1, 1])
    N = u.size
    xs, vs_, zs = x0, v0, z0
    x[0] = xs
    v[0] = vs_
    z[0] = zs
    F[0] = _force(vs_, zs, p0, p1, d0, d1)[1]
    total = 0
    vpk = abs(v0)
    zlo, zhi = _z_bounds(p0, p1, d0, d1, z0)
    k = 0
    n_try = 1
    have = False  # pt: _point at (vs_, zs) carried over from the last accepted step
    pt = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    h_ros = dt  # ROS2 sub-step carried over consecutive ROS2 intervals
    while k < N - 1:
        j, n_try, vpk, tries, pt, _ = _span(u, k, n_try, xs, vs_, zs, have, pt, vpk, dt, m, p0, p1, d0, d1, rtol,
                                            atol_v, atol_z, v_floor, zlo, zhi, x, v, F, z)
        total += tries
        have = j > 0
        if j > 0:
            k += j
            xs = x[k]
            vs_ = v[k]
            zs = z[k]
            h_ros = dt
            continue
        # one ROS2 interval: a reversal inside the next sample, or one sample too nonlinear
        xs, vs_, zs, Fs_, h_ros, nn, st, vpk = _interval(
            xs, vs_, zs, min(h_ros, dt), u[k], u[k + 1], dt, m, p0, p1, d0, d1, rtol, atol_v, atol_z, max_sub,
            vpk, v_floor, zlo, zhi,
        )
        have = False
        total += nn
        k += 1
        x[k] = xs
        v[k] = vs_
        z[k] = zs
        F[k] = Fs_
        n_try = 1
        if st != OK:
            return st, k, total
    return OK, N - 1, total


@njit(parallel=True)
def lugre_force_batch_sse(
    u, dt, m, static, dyn, rtol, atol_v, atol_z, max_sub, target, which, weight, out_sse, out_status, v_floor=1.0
):
    """ROS2 sub-steps in every interval (:func:`_interval`) for P parameter sets; weighted SSE.

    ``static (P, 2, 6)``, ``dyn (P, 2, 2)``, ``m (P,)``. ``which`` selects the compared
    signal: 0 position, 1 velocity, 2 friction force. ``weight (N,)`` masks samples.
    ``simulate_batch`` runs :func:`lugre_batch_sse` (spanning steps); this is the
    one-step-per-interval scheme of the fixed batch (``kernels.batch``) with error control,
    its twin in tests/kernels/test_batch.py.
    """
    P = m.size
    for j in prange(P):
        xs = 0.0
        vs_ = 0.0
        zs = 0.0
        h_try = dt
        p0 = static_row(static[j], 0)
        p1 = static_row(static[j], 1)
        d0 = (dyn[j, 0, 0], dyn[j, 0, 1])
        d1 = (dyn[j, 1, 0], dyn[j, 1, 1])
        mj = m[j]
        acc = 0.0
        st = OK
        vpk = 0.0
        zlo, zhi = _z_bounds(p0, p1, d0, d1, 0.0)
        for k in range(u.size - 1):
            xs, vs_, zs, Fe, h_try, n, st, vpk = _interval(
                xs, vs_, zs, h_try, u[k], u[k + 1], dt, mj, p0, p1, d0, d1,
                rtol, atol_v, atol_z, max_sub, vpk, v_floor, zlo, zhi,
            )
            if st != OK:
                break
            if which == 0:
                y = xs
            elif which == 1:
                y = vs_
            else:
                y = Fe
            d = y - target[k + 1]
            acc += weight[k + 1] * d * d
        out_sse[j] = acc if st == OK else np.inf
        out_status[j] = st


@njit(parallel=True)
def lugre_batch_sse(
    u, dt, m, static, dyn, rtol, atol_v, atol_z, max_sub, target, which, weight, out_sse, out_status, v_floor=1.0
):
    """:func:`lugre_force` (spanning steps) for P parameter sets; only the weighted squared error.

    Arguments as :func:`lugre_force_batch_sse`, except ``atol_v`` and ``atol_z``: arrays (P,),
    one per set. Each set runs the single-trajectory kernel into its own scratch traces with
    the tolerances ``simulate`` gives it, so a set's result is exactly that of ``simulate``.
    """
    P = m.size
    N = u.size
    for j in prange(P):
        x = np.empty(N)
        v = np.empty(N)
        F = np.empty(N)
        z = np.empty(N)
        st, _, _ = lugre_force(u, dt, m[j], static[j], dyn[j], 0.0, 0.0, 0.0, rtol, atol_v[j], atol_z[j], max_sub,
                               x, v, F, z, v_floor)
        y = x if which == 0 else (v if which == 1 else F)
        acc = 0.0
        for k in range(1, N):
            d = y[k] - target[k]
            acc += weight[k] * d * d
        out_sse[j] = acc if st == OK else np.inf
        out_status[j] = st


@njit
def lugre_motion(xpos, dt, static, dyn, z0, v_out, F_out, z_out):
    """Motion-driven LuGre with piecewise-constant velocity: exact exponential update."""
    N = xpos.size
    z = z0
    p0 = static_row(static, 0)
    p1 = static_row(static, 1)
    d0 = (dyn[0, 0], dyn[0, 1])
    d1 = (dyn[1, 0], dyn[1, 1])
    for k in range(N - 1):
        vk = (xpos[k + 1] - xpos[k]) / dt
        p, (s0, s1) = _side(vk, p0, p1, d0, d1)
        av = abs(vk)
        a = s0 * av / g_row(p, av)
        if a > 0.0:
            # z(dt) = z E + zss (1 - E), zss = vk / a = sgn(v) g / sigma0, with 1 - E from expm1:
            # the form zss + (z - zss) E cancels when a dt < ~1e-16 (g >> sigma0 |dx|, e.g. Fc 1e100
            # or sigma0 1e-10: z stayed put, friction half its range off; campaign round 8).
            e1 = -math.expm1(-a * dt)
            z = z * (1.0 - e1) + vk * (e1 / a)
        else:  # a = 0 (sigma0 = 0 or v = 0): dz/dt = v
            z = z + vk * dt
        if k == 0:
            v_out[0] = vk
            zd0 = vk - a * z0
            F_out[0] = s0 * z0 + s1 * zd0 + p[R_S2] * vk
            z_out[0] = z0
        zd = vk - a * z
        v_out[k + 1] = vk
        z_out[k + 1] = z
        F_out[k + 1] = s0 * z + s1 * zd + p[R_S2] * vk
    return OK
