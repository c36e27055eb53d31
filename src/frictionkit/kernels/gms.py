"""GMS kernels: force-driven mass (spanning steps, sub-steps with located switches) and motion-driven (exact).

State: position ``x``, velocity ``v``, element forces ``F_i`` and stick flags.

* sticking element: ``F_i' = k_i v``
* slipping element: ``F_i' = sgn(v) C (xi_i - F_i / s(v)) = C (xi_i sgn(v) - F_i / g)``
  with ``g = |s(v)|``
* a sticking element breaks away when ``sgn(v) F_i >= xi_i g``; every slipping
  element sticks when ``v`` changes sign.

Force-driven sub-steps
----------------------
Between switches the sticking elements are springs: ``F_i = F_i0 + k_i (x - x0)``
exactly, so the stiff part of the problem is a linear mass–spring–damper
(``K = sum of sticking k_i``, damping ``sigma2``) that ``kernels._oscillator``
solves exactly for an affine load — stiffness 1e8 N/m costs nothing and rings
with the right frequency and amplitude. Only the slipping elements (rate
``C/|s|``, slow) are approximated: their total force enters as an affine-in-time
load, predicted from their rates and corrected twice with the secant of their
exact exponential update at the mean velocity; the change between passes is the
error estimate that sizes the adaptive sub-step. In pure pre-sliding the step is
exact and one sub-step covers a sample interval — except that, since switches are
tested at the ends of a sub-step, an underdamped oscillation with a breakaway
within reach (or with slipping elements that a reversal would re-stick) is crossed
in sub-steps of at most an eighth of its period ``2 pi sqrt(m / K)``, so that a
swing out and back inside one sub-step cannot hide a switch.

Switches are located inside the sample interval instead of on the step grid:
when a trial sub-step crosses a breakaway or velocity-reversal surface, the event
function is interpolated linearly, the sub-step is shortened to land just past
the crossing (within ``1e-6 dt``) and retried; the switch is applied on the
accepted state. A trial step across a reversal while elements slip that the error
control rejects lands at the reversal (the slip targets change sign there). An element
that breaks away inside the accepted sub-step leaves stick at its
threshold ``xi_i s(v)``: the spring's overshoot past the crossing (up to ``k_i |v| 1e-6 dt``) is
not kept as slip force, where a slow slip (``C / g`` small) would carry it on (issue 13). Since the breakaway level ``xi_i g(v)`` falls with ``|v|``, a sticking force can
cross it mid-step and be below it again at an end where the mass is slow (``g ~ Fs``): a step
whose ends show no switch but whose force reaches ``xi_i min(Fc, Fs)`` is searched on its cubic
Hermite (:func:`_interior_breakaway`), and a span sample tests the force against the lowest ``g``
over the interval's speeds (:func:`_g_low`), not ``g`` at its end (issue 13).

Spanning steps (issue 15)
-------------------------
Between switches, with the Stribeck magnitude frozen at ``g0 = g(v0)``, the whole force-driven
GMS is linear: the sticking elements are springs (``F_i = F_i0 + k_i X``, ``X`` the displacement
since the span's start) and every slipping element relaxes with the one rate
``lam = C / g0`` towards ``xi_i sgn(v) g0``, so their sum is
``P_inf + (P0 - P_inf) exp(-lam t)``. A span therefore solves the mass on the sticking springs
exactly (``_oscillator.coefficients``) under the piecewise-linear input and that exponential load
(``_gms_span.exp_load``), sample to sample with ~20 flops and the same coefficients for every
sample; the element forces at each sample are ``a_i + b_i X + e_i exp(-lam t)``. A span is set
up at a sample (coefficients cached on ``(K, c, lam)``) and runs until a sample shows

* a velocity reversal, or ``|v|`` turning inside the interval close enough to dip through zero
  (``min |v| < dt (|a0| + |a1|) / 4``) -- except when every element sticks and the law has no
  direction, where the motion does not see the sign of ``v`` and the span rings on;
* a breakaway (tested exactly only once ``X`` nears the level ``xi_i min(Fc, Fs)`` of some
  sticking element; with every element sticking, the bound covers ``X`` between the samples);
* the frozen ``g`` costing too much: the neglected rate ``C |F_i| |1/g(v) - 1/g0|`` of the
  slipping elements, integrated over the span (trapezoid on the samples), above
  ``SPAN_SAFETY * rtol * sum |F_i|`` (or its effect on ``v`` above ``SPAN_SAFETY`` of the
  velocity tolerance): a new span starts at the last sample (zero where ``g = Fc`` exactly);
* a contact ringing faster than ``SPAN_OMEGA_DT`` (8 samples per period): sub-steps.

A sample a span cannot take is covered by the adaptive sub-steps below, which locate the switch;
after a span that failed on its first sample, the next attempts back off (1, 2, 4 ... 16
intervals). On the 10 s stick-slip benchmark (GMS-4) ~96 % of the samples are span samples
(0.05 steps per sample, counting span set-ups and sub-steps; 1.02 with sub-steps alone).
``span=False`` (kernel argument) gives the sub-steps alone. The samples of a span run in
:func:`_span_run`, a small function of its own (called once per span): the same loop inside
:func:`_drive` cost ~74 ns per sample against ~33 ns there (pure sliding, GMS-4); pure sliding
past the Stribeck range (no sticking element, ``g = Fc``) has a loop of its own there without the
breakaway and frozen-``g`` tests (~16 -> ~11 ns a sample with the element forces written).

Motion-driven scheme
--------------------
Piecewise-linear position: ``v`` is constant on each interval, so a sticking
element is linear in time, its breakaway instant is found in closed form, and a
slipping element relaxes exactly as ``xi s + (F - xi s) exp(-C t / g)``.

Structure
---------
The sample loop and the sub-step loop live in one non-inlined function,
:func:`_drive`, which receives the arrays once per run: passing an array into
another numba function -- even an inlined one -- costs an ``NRT_incref`` /
``NRT_decref`` call pair per call and spills the floating-point registers (see
:mod:`._stribeck`). Inside the loops the Stribeck rows are tuples
(``_stribeck.row`` / ``g_row``) and ``C`` is two floats; the only call left is
``_oscillator.coefficients`` (scalars, and only when ``K``, ``c`` or ``h`` change).

Status codes: 0 ok, 1 non-finite state, 2 sub-step budget exhausted,
3 error control failed (step-size underflow at ``H_MIN * dt`` with the error
estimate still above the tolerance; the step is not accepted).
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import njit, prange
from ._oscillator import coefficients
from ._gms_span import exp_load
from ._stribeck import R_DF, R_FC, R_FS, R_S2, g_row
from ._stribeck import row as static_row
from .lugre import _atol_run

OK, NONFINITE, BUDGET, TOLERANCE = 0, 1, 2, 3
H_MIN = 1e-7  # smallest sub-step as a fraction of dt (kernels.lugre.H_MIN)
EVENT_TOL = 1e-6  # fraction of dt within which a switch is located
#: Largest ``omega dt`` of an underdamped sticking contact for a spanning step (8 samples per
#: period, as the sub-steps' cap of an eighth of a period): switches are tested at samples.
SPAN_OMEGA_DT = 0.785
#: Fraction of the tolerance the frozen-``g`` bound of a span may use. Not a loose margin: at 0.1
#: the 10 s GMS-4 stick-slip run ends 3.6 um off the twin (0.299 um at 0.01; 1.0: 58 um). The local
#: error stays within the velocity tolerance (5e-9 m/s at v ~ 3.6e-5 m/s, creep with one element
#: slipping, t = 0.18 s), but the later switches are that sensitive to it (gms, 2026-11-23).
SPAN_SAFETY = 0.01
#: Below this ``a = C h / g`` the moving-target factor ``(1 + e^-a)/2 - (1 - e^-a)/a`` of the slip-force
#: error estimate is taken as its series ``a^2 / 12`` (the closed form cancels: ~1e-16 / a absolute).
SLIP_SERIES_A = 1e-3
#: Sub-steps of anti-damped sliding (the slipping elements' force falls with the speed faster than
#: sigma2 damps it: ``sigma2 + P g'(|v|) / g < 0``, P their total force) meet this many times tighter
#: tolerances. Why (issue 13, gmsw2): the linearised mass-and-slip system then has a growing mode, so
#: at-tolerance local errors add up and grow over the slip; gmsw's seed 1047 (C dt / g ~ 0.3, ~90
#: samples of such sliding) ended 27 rtol off the twin in x and 34 in the friction, 13 / 21 rtol with
#: this factor alone, 5.4 / 8.2 with the moving-target estimate above too (that estimate alone: 24 /
#: 37).
SLIP_UNSTABLE_TIGHT = 10.0
#: ... only where the slip relaxes fast over the sub-step, ``a = C h / g > SLIP_UNSTABLE_A`` (assumption,
#: measured): the cases found wrong had a = 0.27-0.33 (1047) and > 1 (campaign seed 2016); everywhere in
#: anti-damped sliding the tightening cost the GMS-4 / GMS-16 stick-slip benchmark +5.6 % / +1 % sub-steps
#: (a <= 0.004 there) and moved a GMS force-drive fit from one start to another minimum
#: (tests/kernels/test_sensitivity_gms.py, a <= 0.02). Slower slip follows its targets' drift
#: closely, so the local errors the factor guards against are small there.
SLIP_UNSTABLE_A = 0.05
#: Most samples per span (the model is refreshed at least this often).
SPAN_MAX = 1024
#: Longest back-off (intervals) after spans that failed on their first sample.
SKIP_MAX = 16


@njit(inline="always")
def _sgn(v):
    return 1.0 if v > 0.0 else (-1.0 if v < 0.0 else 0.0)


@njit(inline="always")
def _sticking_may_reach(M, st_, Fi, k, row, xi_n, ext, xi_lo, g):
    """Whether a sticking element's force, over a step moving ``xi_n`` (plus ``ext`` of speed
    overshoot), can reach its lowest breakaway threshold ``xi_lo[i] * g``."""
    for i in range(M):
        if st_[i]:
            kr = k[row, i]
            if max(abs(Fi[i]), abs(Fi[i] + kr * xi_n)) + kr * ext >= xi_lo[i] * g:
                return True
    return False


@njit(inline="always")
def _side(v, p0, p1, C0, C1):
    """``(row, Stribeck row tuple, C)`` for the direction of ``v`` (row 0: ``v >= 0``)."""
    if v >= 0.0:
        return 0, p0, C0
    return 1, p1, C1


#: Grid points (per sub-step) on which :func:`_interior_breakaway` looks for a breakaway between the
#: step's ends. Named assumption (issue 13): the dip of the event function that the ends miss lasts
#: while ``|v|`` is above the Stribeck range and the sticking force is between ``xi Fc`` and
#: ``xi Fs``; a sub-step near a breakaway is at most an eighth of a ringing period, so such a dip
#: is a sizeable part of it. A dip narrower than ``h / INTERIOR_GRID`` can pass unseen; its force
#: overshoot is then at most ``k |v| h / INTERIOR_GRID``.
INTERIOR_GRID = 16


@njit
def _interior_breakaway(M, st_, Fi, k, xi, row, p0, p1, xi_lo, g_lo, v, vn, a0, an, Xn, h):
    """Step fraction of the first breakaway inside a sub-step, or 2.0 when there is none.

    The sub-step's displacement ``X(s)`` and velocity ``v(s)`` (``s`` in ``[0, 1]``) are taken as
    cubic Hermites of their end values and slopes (``X``: 0, ``Xn`` with slopes ``h v``, ``h vn``;
    ``v``: ``v``, ``vn`` with slopes ``h a0``, ``h an``), and a sticking element's event function
    ``xi_i g(v(s)) - sgn(v(s)) (F_i + k_i X(s))`` is evaluated on ``INTERIOR_GRID`` points; the first
    sign change is placed by the secant between its grid neighbours. The ends are tested exactly
    by the caller. First the range of ``|v|`` and of ``X`` on the grid screens the step: with ``g``
    monotone in ``|v|`` its lowest value is at an end of that range, and an element whose force
    stays below ``xi_i`` times it cannot break away anywhere in the step.
    """
    ng = INTERIOR_GRID
    hv = h * v
    hvn = h * vn
    ha0 = h * a0
    han = h * an
    vmin = min(abs(v), abs(vn))
    vmax = max(abs(v), abs(vn))
    Xmin = min(0.0, Xn)
    Xmax = max(0.0, Xn)
    for j in range(1, ng):
        s = j / ng
        s2 = s * s
        s3 = s2 * s
        h00 = 2.0 * s3 - 3.0 * s2 + 1.0
        h10 = s3 - 2.0 * s2 + s
        h01 = 1.0 - h00
        h11 = s3 - s2
        vj = h00 * v + h10 * ha0 + h01 * vn + h11 * han
        Xj = h01 * Xn + h10 * hv + h11 * hvn
        avj = abs(vj)
        if avj < vmin:
            vmin = avj
        if avj > vmax:
            vmax = avj
        if Xj < Xmin:
            Xmin = Xj
        if Xj > Xmax:
            Xmax = Xj
    glo = min(min(g_row(p0, vmin), g_row(p0, vmax)), min(g_row(p1, vmin), g_row(p1, vmax)))
    need = False
    for i in range(M):
        if st_[i]:
            kr = k[row, i]
            if max(abs(Fi[i] + kr * Xmin), abs(Fi[i] + kr * Xmax)) >= xi_lo[i] * glo:
                need = True
                break
    if not need:
        return 2.0
    # the scan: event functions on the grid, in order
    best = 2.0
    for i in range(M):
        if not st_[i]:
            continue
        kr = k[row, i]
        e_prev = math.inf
        if v != 0.0:
            r0 = 0 if v > 0.0 else 1
            e_prev = xi[r0, i] * g_row(p0 if r0 == 0 else p1, abs(v)) - (1.0 if v > 0.0 else -1.0) * Fi[i]
        for j in range(1, ng):
            s = j / ng
            if s >= best:
                break
            s2 = s * s
            s3 = s2 * s
            h00 = 2.0 * s3 - 3.0 * s2 + 1.0
            h10 = s3 - 2.0 * s2 + s
            h01 = 1.0 - h00
            h11 = s3 - s2
            vj = h00 * v + h10 * ha0 + h01 * vn + h11 * han
            if vj == 0.0:
                e_prev = math.inf
                continue
            Xj = h01 * Xn + h10 * hv + h11 * hvn
            rj = 0 if vj > 0.0 else 1
            sj = 1.0 if vj > 0.0 else -1.0
            ej = xi[rj, i] * g_row(p0 if rj == 0 else p1, abs(vj)) - sj * (Fi[i] + kr * Xj)
            if ej <= 0.0:
                th = s
                if 0.0 < e_prev < math.inf:
                    th = s - (1.0 / ng) * (1.0 - e_prev / (e_prev - ej))
                if th < best:
                    best = th
                break
            e_prev = ej
    return best


@njit(inline="always")
def _is_directional(static, k, xi, C):
    if C[0] != C[1]:
        return True
    for j in range(static.shape[1]):
        if static[0, j] != static[1, j]:
            return True
    for i in range(k.shape[1]):
        if k[0, i] != k[1, i] or xi[0, i] != xi[1, i]:
            return True
    return False


@njit(inline="always")
def _g_low(p, v, vn, a0, an, h):
    """Lowest ``g`` of row ``p`` over a step ``h`` with end speeds ``v, vn`` (one sign) and end
    accelerations ``a0, an``: the breakaway level a sticking element's force must stay below
    throughout the step, not at its end only (issue 13: ``g`` falls with ``|v|``, so a force below
    ``xi g(vn)`` at a slow end can have crossed ``xi g`` where the mass was faster).

    ``g`` is monotone in ``|v|`` (rising when ``Fs < Fc``), so one evaluation at the end of the
    speed range. Unless the cubic Hermite of ``v`` is monotone (Fritsch-Carlson: end slopes of the
    chord's sign, ``alpha^2 + beta^2 <= 9``), ``|v|`` may overshoot its end values, by at most
    ``h (|a0| + |an|) / 4`` on that cubic."""
    lo = min(abs(v), abs(vn))
    hi = max(abs(v), abs(vn))
    dv = vn - v
    mono = False
    if dv != 0.0:
        al = h * a0 / dv
        be = h * an / dv
        mono = al >= 0.0 and be >= 0.0 and al * al + be * be <= 9.0
    if not mono:
        ov = 0.25 * h * (abs(a0) + abs(an))
        lo = max(0.0, lo - ov)
        hi += ov
    return g_row(p, hi if p[R_DF] >= 0.0 else lo)


# IEEE division (``error_model="numpy"``): no zero test and exception branch per division in the
# per-sample loop (~2.5 ns of ~18 per pure-sliding sample); the divisors here (dt, g) are positive.
@njit(error_model="numpy")
def _span_run(
    u, dt, N, kk, record, x_out, v_out, F_out, Fel, stick_out, which, target, weight, acc,
    st_, xi, srow, sa_, sb_, se_, sp, sv, sCr, sc, sg0, sva, free, slipping,
    L0, Ks, D0, Tabs, Dabs, Xcross, Xlo, Xhi, xa, coef,
    X, v, Dfac, est, r_prev, sacc, jsp, vpk, tol_v, rtol, atol_v, v_floor,
):
    """Samples ``kk, kk + 1, ...`` of one span (module docstring) in a loop of its own.

    Kept out of :func:`_drive` so that the per-sample loop is small (inside the large function
    the same code cost ~3x per sample). Returns
    ``(kk, X, v, Dfac, est, r_prev, sacc, jsp, why, vpk, tol_v, acc)``: ``why`` 0 when the span
    closed after sample ``kk - 1`` (``SPAN_MAX``, ``g`` reached ``Fc``, or the record ended),
    1 when interval ``kk`` needs the sub-steps, 2 when it needs a new span.
    """
    M = sa_.size
    sE12, sE22, sq1, sr1, sq2, sr2, sqe, sre, sed, im = coef
    k0 = kk
    D_in = Dfac
    why = 0
    if record and slipping and Ks == 0.0 and sg0 == sp[R_FC]:
        # Pure sliding past the Stribeck range (every element slipping, g = Fc frozen exactly while
        # |v| >= |v| at the span's start; the frozen-g bound is then 0): only a reversal, a turn of |v|
        # inside an interval or a non-finite state can end the span, so these samples run in a loop of
        # their own without the breakaway and frozen-g tests; the first sample it leaves is taken by
        # the general loop below, from the same state (issue 15, gms15: ~96 % of the GMS-4 stick-slip
        # benchmark's samples; 16.1 -> 10.6 ns a sample in pure sliding, kernel 1.29 -> 1.12 ms).
        idt = 1.0 / dt
        u0 = u[kk - 1]
        while kk < N and jsp < SPAN_MAX:
            u1 = u[kk]
            f0 = (u0 - L0) * im
            fe = -D0 * Dfac * im
            f1 = (u1 - u0) * idt * im
            xi_n = sE12 * v + sq1 * f0 + sq2 * f1 + sqe * fe
            vn = sE22 * v + sr1 * f0 + sr2 * f1 + sre * fe
            Dn = Dfac * sed
            avn = abs(vn)
            if not (vn * sv > 0.0 and avn >= sva and math.isfinite(xi_n + vn)):
                break
            accn = (u1 - L0 - D0 * Dn - sc * vn) * im
            if sacc * sv < 0.0 < accn * sv and min(abs(v), avn) < 0.25 * dt * (abs(sacc) + abs(accn)):
                break
            X += xi_n
            v = vn
            Dfac = Dn
            sacc = accn
            r_prev = 0.0
            jsp += 1
            if avn > vpk:
                vpk = avn
                tol_v = _atol_run(atol_v, v_floor, rtol, vpk)
            x_out[kk] = xa + X
            v_out[kk] = vn
            F_out[kk] = X
            kk += 1
            u0 = u1
    while kk < N:
        if jsp >= SPAN_MAX:
            break
        u0 = u[kk - 1]
        du = (u[kk] - u0) / dt
        # one sample of the frozen linear model, exact for the piecewise-linear input
        f0 = (u0 - L0 - Ks * X) * im
        fe = -D0 * Dfac * im
        f1 = du * im
        xi_n = sE12 * v + sq1 * f0 + sq2 * f1 + sqe * fe
        vn = sE22 * v + sr1 * f0 + sr2 * f1 + sre * fe
        Xn = X + xi_n
        Dn = Dfac * sed
        why = 0  # 0 accept, 1 sub-steps for this interval, 2 new span here
        end_after = False
        accn = 0.0
        est_n = est
        r = 0.0
        if not math.isfinite(Xn + vn):
            why = 1
        elif free:
            accn = (u[kk] - L0 - Ks * Xn - sc * vn) * im
            # X between the samples: within the ends, or past one by at most the distance
            # covered at the end speeds where v turns inside the interval
            reach = 0.5 * dt * (abs(v) + abs(vn))
            if min(X, Xn) - reach <= Xlo or max(X, Xn) + reach >= Xhi:
                svv = 1.0 if v > 0.0 else -1.0
                if vn * v <= 0.0 or (sacc * svv < 0.0 < accn * svv
                                     and min(abs(v), abs(vn)) < 0.25 * dt * (abs(sacc) + abs(accn))):
                    why = 1  # a turn near a breakaway level: sub-steps
                else:
                    svn = 1.0 if vn > 0.0 else -1.0
                    gn = _g_low(sp, v, vn, sacc, accn, dt)
                    for i in range(M):
                        if st_[i] and svn * (sa_[i] + sb_[i] * Xn) >= xi[srow, i] * gn:
                            why = 1  # a breakaway (at the sample or inside): located by the sub-steps
                            break
        elif not vn * sv > 0.0:
            why = 1  # reversal: located by the sub-steps
        else:
            accn = (u[kk] - L0 - Ks * Xn - D0 * Dn - sc * vn) * im
            if sacc * sv < 0.0 < accn * sv and min(abs(v), abs(vn)) < 0.25 * dt * (abs(sacc) + abs(accn)):
                why = 1  # |v| turns inside the interval and may dip through zero
            elif sv * Xn >= Xcross:
                gn = _g_low(sp, v, vn, sacc, accn, dt)
                for i in range(M):
                    if st_[i] and sv * (sa_[i] + sb_[i] * Xn) >= xi[srow, i] * gn:
                        why = 1  # a breakaway (at the sample or inside): located by the sub-steps
                        break
            if why == 0 and slipping:
                # the frozen g: the neglected rate C (1/g0 - 1/g(v)) F_i of the slipping
                # elements, integrated over the span (trapezoid on the samples), bounds
                # what freezing cost their forces
                avn = abs(vn)
                if not (sg0 == sp[R_FC] and avn >= sva):  # g is monotone in |v|: g = g0 here
                    gn = g_row(sp, avn)
                    r = sCr * (Tabs + Dabs * Dn) * abs(1.0 / gn - 1.0 / sg0)
                    est_n = est + 0.5 * dt * (r_prev + r)
                    if gn == sp[R_FC] and sg0 != gn:
                        # past the Stribeck range: the next span, from this sample, has g0 = Fc
                        # and needs no g(v) (a re-span at the sample before would not)
                        end_after = True
                    if (est_n > SPAN_SAFETY * rtol * (Tabs + Dabs * Dn)
                            or est_n * (jsp + 1) * dt * im > SPAN_SAFETY * (tol_v + rtol * abs(vn))):
                        why = 2
        if why != 0:
            break
        if True:
            X = Xn
            v = vn
            Dfac = Dn
            est = est_n
            r_prev = r
            sacc = accn
            jsp += 1
            x = xa + X
            if abs(v) > vpk:
                vpk = abs(v)
                tol_v = _atol_run(atol_v, v_floor, rtol, vpk)
            if record:
                x_out[kk] = x
                v_out[kk] = v
                F_out[kk] = X  # the friction and element forces are written after the loop
            else:
                if which == 0:
                    y = x
                elif which == 1:
                    y = v
                else:
                    y = L0 + Ks * X + D0 * Dfac + sc * v
                dd = y - target[kk]
                acc += weight[kk] * dd * dd
            kk += 1
            if jsp >= SPAN_MAX or end_after:
                break
    if record:
        # Forces and flags of the span's samples in a loop of their own, from X (kept in F_out) and
        # the same decay products: element stores inside the sample loop cost it ~3x (GMS-4 pure
        # sliding ~42 -> ~15 ns per sample; the stores may alias the arrays it reads).
        # The stick flags are constant over a span and ``stick_out`` arrives zeroed (gms_force), so
        # only a span with a sticking element writes them (pure sliding: ~3 ns per sample less).
        nst = False
        for i in range(M):
            nst = nst or st_[i]
        D = D_in
        for j in range(k0, kk):
            D *= sed
            Xj = F_out[j]
            for i in range(M):
                Fel[j, i] = sa_[i] + sb_[i] * Xj + se_[i] * D
            if nst:
                for i in range(M):
                    stick_out[j, i] = st_[i]
            F_out[j] = L0 + Ks * Xj + D0 * D + sc * v_out[j]
    return kk, X, v, Dfac, est, r_prev, sacc, jsp, why, vpk, tol_v, acc


@njit
def _drive(
    u, dt, m, static, k, xi, C, x0, v0, F0, stick0, rtol, atol_v, atol_F, max_sub,
    record, x_out, v_out, F_out, Fel, stick_out, which, target, weight, v_floor, span,
):
    """Run the force-driven GMS over all sample intervals; returns ``(status, k, substeps, sse)``.

    ``record`` true: fill the traces ``x_out, v_out, F_out`` (N,), ``Fel`` and ``stick_out``
    (N, M) for every sample (``which``, ``target``, ``weight`` unused) and stop after
    recording the sample at which a failure occurred. ``record`` false: accumulate
    ``sum weight_k (y_k - target_k)^2`` of position (``which`` 0), velocity (1) or
    force (2) over samples 1..N-1 (the trace arrays are unused and may have size 1)
    and stop before the failing sample.

    Each sub-step solves the mass on the springs of the sticking elements exactly
    (``kernels._oscillator``), with the slipping elements' total force as an
    affine-in-time load: predicted from their rates, then corrected with the
    secant of their exact exponential update at the mean velocity (twice). The
    difference between the passes is the error estimate. Everything inside the
    loops is scalars, tuples and direct indexing of the arrays received here.
    """
    N = u.size
    M = F0.size
    Fi = F0.copy()
    st_ = stick0.copy()
    sa = np.empty(M)  # slip forces after the first corrector pass
    sb = np.empty(M)  # ... after the second (accepted) pass
    p0 = static_row(static, 0)
    p1 = static_row(static, 1)
    C0 = C[0]
    C1 = C[1]
    directional = _is_directional(static, k, xi, C)
    # smallest |s| of either direction and, per element, the smallest weight and largest
    # stiffness: a direction-free test whether a breakaway is within reach (see below)
    g_lo = min(min(p0[R_FC], p0[R_FS]), min(p1[R_FC], p1[R_FS]))
    xi_lo = np.empty(M)
    k_hi = np.empty(M)
    for i in range(M):
        xi_lo[i] = min(xi[0, i], xi[1, i])
        k_hi[i] = max(k[0, i], k[1, i])
    im = 1.0 / m
    h_ev = EVENT_TOL * dt
    # oscillator coefficients cached across sub-steps and intervals: key (K, c, h)
    cK = -1.0
    cc_ = -1.0
    cH = -1.0
    # last slip decay exp(-a), a = C h / g: while sliding past the Stribeck range g = Fc,
    # so the four decays of a sub-step (two corrector passes, both trapezoid ends) and
    # those of the following sub-steps share one argument and one exp
    ea = -1.0
    ed = 1.0
    E12 = 0.0
    E22 = 0.0
    q1 = 0.0
    r1 = 0.0
    q2 = 0.0
    r2 = 0.0
    x = x0
    v = v0
    # absolute velocity tolerance following the run's largest speed (lugre._atol_run)
    vpk = abs(v0)
    tol_v = _atol_run(atol_v, v_floor, rtol, vpk)
    h_try = dt
    total = 0
    acc = 0.0
    status = OK
    # ---- spanning steps (module docstring): per element F = a + b X + e D over a span
    sa_ = np.empty(M)
    sb_ = np.empty(M)
    se_ = np.empty(M)
    span_on = False
    skip = 0  # intervals to leave to the sub-steps before the next span attempt
    nskip = 1
    kS = -1.0  # key of the cached span coefficients (K, c, lam)
    kC = -1.0
    kL = -2.0
    sE12 = sE22 = sq1 = sr1 = sq2 = sr2 = sqe = sre = 0.0
    sed = 1.0
    sv = 0.0
    srow = 0
    sp = p0
    sCr = C0
    sc = 0.0
    sg0 = 1.0
    slam = 0.0
    Ks = 0.0
    L0 = 0.0
    Pinf = 0.0
    D0 = 0.0
    Tabs = 0.0
    Dabs = 0.0
    Xcross = 0.0
    Xlo = 0.0
    Xhi = 0.0
    free = False
    slipping = np.bool_(False)
    xa = x0
    sva = 0.0
    X = 0.0
    Dfac = 1.0
    est = 0.0
    r_prev = 0.0
    sacc = 0.0
    jsp = np.int64(0)
    if record and N > 0:
        pr = p0 if v >= 0.0 else p1
        tot = 0.0
        for i in range(M):
            tot += Fi[i]
            Fel[0, i] = Fi[i]
            stick_out[0, i] = st_[i]
        x_out[0] = x
        v_out[0] = v
        F_out[0] = tot + pr[R_S2] * v
    # kk, jsp, slipping start as np scalars, not literals: a literal start types the call of
    # _span_run first with Literal[int](1) / Literal[bool](False) arguments, then again once
    # the loop unifies them (two compiles of _span_run, ~3.5 s CPU each)
    kk = np.int64(1)
    while kk < N:
        # ------------------------------------------------ spans from sample kk - 1, then one
        # interval of sub-steps where a span cannot go
        u0 = u[kk - 1]
        # ------------------------------------------------ spanning step: this sample exactly
        was_on = span_on
        while True:
            if not span_on:
                if skip > 0 or v == 0.0 or not span:
                    if skip > 0:
                        skip -= 1
                    break
                # set up a span at the current state: flags, direction and g frozen
                sv = 1.0 if v > 0.0 else -1.0
                srow, sp, sCr = _side(v, p0, p1, C0, C1)
                sc = sp[R_S2]
                sg0 = g_row(sp, abs(v))
                slam = sCr / sg0
                glo = min(sp[R_FC], sp[R_FS])  # g >= glo at any speed: a safe breakaway bound
                Ks = 0.0
                L0 = 0.0
                Pinf = 0.0
                D0 = 0.0
                Tabs = 0.0
                Dabs = 0.0
                Xcross = math.inf
                Xlo = -math.inf
                Xhi = math.inf
                slipping = np.bool_(False)
                for i in range(M):
                    if st_[i]:
                        kr = k[srow, i]
                        Ks += kr
                        L0 += Fi[i]
                        sa_[i] = Fi[i]
                        sb_[i] = kr
                        se_[i] = 0.0
                        lim = xi[srow, i] * glo
                        if kr > 0.0:
                            q = (lim - sv * Fi[i]) / kr
                            if q < Xcross:
                                Xcross = q
                            q = (lim - Fi[i]) / kr
                            if q < Xhi:
                                Xhi = q
                            q = (-lim - Fi[i]) / kr
                            if q > Xlo:
                                Xlo = q
                        elif abs(Fi[i]) >= lim:
                            Xcross = -math.inf
                            Xhi = -math.inf
                    else:
                        slipping = True
                        tg = xi[srow, i] * sv * sg0
                        Pinf += tg
                        D0 += Fi[i] - tg
                        sa_[i] = tg
                        sb_[i] = 0.0
                        se_[i] = Fi[i] - tg
                        Tabs += abs(tg)
                        Dabs += abs(Fi[i] - tg)
                if Ks > 0.0 and sc * sc < 4.0 * Ks * m and Ks * dt * dt > SPAN_OMEGA_DT**2 * m:
                    # a contact ringing at fewer than ~8 samples per period: a swing out and
                    # back between two samples could hide a switch; sub-steps (capped) instead
                    break
                L0 += Pinf
                # every element sticks and the law has no direction: the motion does not see
                # the sign of v, so the span runs through reversals (ringing) until an element
                # nears its breakaway level
                free = not slipping and not directional
                lkey = slam if slipping else -1.0
                if Ks != kS or sc != kC or lkey != kL:
                    _, sE12, _, sE22, sq1, sr1, sq2, sr2 = coefficients(Ks, sc, m, dt)
                    if slipping:
                        sqe, sre = exp_load(Ks, sc, m, slam, dt)
                        sed = math.exp(-slam * dt)
                    else:
                        sqe = 0.0
                        sre = 0.0
                        sed = 1.0
                    kS = Ks
                    kC = sc
                    kL = lkey
                xa = x
                sva = abs(v)
                X = 0.0
                Dfac = 1.0
                est = 0.0
                r_prev = 0.0
                sacc = (u[kk - 1] - L0 - D0 - sc * v) * im
                jsp = np.int64(0)
                total += 1
                span_on = True
            kk, X, v, Dfac, est, r_prev, sacc, jsp, why, vpk, tol_v, acc = _span_run(
                u, dt, N, kk, record, x_out, v_out, F_out, Fel, stick_out, which, target, weight, acc,
                st_, xi, srow, sa_, sb_, se_, sp, sv, sCr, sc, sg0, sva, free, slipping,
                L0, Ks, D0, Tabs, Dabs, Xcross, Xlo, Xhi, xa,
                (sE12, sE22, sq1, sr1, sq2, sr2, sqe, sre, sed, im),
                X, v, Dfac, est, r_prev, sacc, jsp, vpk, tol_v, rtol, atol_v, v_floor,
            )
            x = xa + X
            # end the span at the last accepted sample
            for i in range(M):
                Fi[i] = sa_[i] + sb_[i] * X + se_[i] * Dfac
            span_on = False
            if kk >= N:
                break
            if why == 0 or (why == 2 and jsp > 0):
                nskip = 1
                continue  # a new span from sample kk - 1
            if jsp == 0:
                skip = nskip
                nskip = min(2 * nskip, SKIP_MAX)
            else:
                nskip = 1
            break
        if kk >= N:
            break
        u0 = u[kk - 1]
        du = (u[kk] - u0) / dt
        if was_on:
            h_try = dt
        t = 0.0
        n = 0
        while t < dt:
            h = h_try
            h_prop = h_try
            rem = dt - t
            clipped = False
            if h >= rem or rem - h < 1e-9 * dt:
                clipped = h > rem
                h = rem
            w = u0 + du * t
            row, p, Cr = _side(v, p0, p1, C0, C1)
            c = p[R_S2]
            sv = _sgn(v)
            g0 = g_row(p, abs(v))
            K = 0.0
            S0 = 0.0
            P0 = 0.0
            R0 = 0.0
            any_slip = False
            for i in range(M):
                if st_[i]:
                    K += k[row, i]
                    S0 += Fi[i]
                else:
                    any_slip = True
                    P0 += Fi[i]
                    R0 += Cr * (xi[row, i] * sv - Fi[i] / g0)
            if K > 0.0 and c * c < 4.0 * K * m:
                # The sticking springs are solved exactly, so one sub-step may span a large
                # part of an oscillation while the switches are tested at its ends only: a
                # breakaway or reversal in the middle (velocity swinging out and back) would
                # go unseen. When an element could reach its breakaway within the step (the
                # oscillation amplitude about the moving equilibrium bounds the excursion),
                # or some element slips (a reversal re-sticks it), the sub-step is capped at an
                # eighth of the period 2 pi sqrt(m / K). Only an underdamped oscillator can swing
                # back within a step (an overdamped one crosses its equilibrium at most once).
                # Found by the issue-13 property test.
                om = math.sqrt(K * im)
                h_cap = 0.785 / om
                if h > h_cap:
                    near = any_slip
                    if not near:
                        dxe = (w - S0 - P0) / K
                        amp = math.sqrt(dxe * dxe + (v / om) * (v / om))
                        reach = 2.0 * amp + (abs(du) + abs(R0)) * h / K
                        for i in range(M):
                            if st_[i] and xi_lo[i] * g_lo - abs(Fi[i]) <= k_hi[i] * reach:
                                near = True
                                break
                    if near:
                        h = h_cap
            if K != cK or c != cc_ or h != cH:
                _, E12, _, E22, q1, r1, q2, r2 = coefficients(K, c, m, h)
                cK = K
                cc_ = c
                cH = h
            f0 = (w - S0 - P0) * im
            # predictor: slip forces linear in time with their initial rates
            f1 = (du - R0) * im
            xi_n = E12 * v + q1 * f0 + q2 * f1
            vn = E22 * v + r1 * f0 + r2 * f1
            e = 0.0
            g_n = -1.0  # g at the trial end, when the slip update needs it
            if any_slip:
                v_prev = vn
                for sweep in range(2):
                    vb = xi_n / h  # mean velocity over the sub-step (exact for the current pass)
                    rb, pb, Cb = _side(vb, p0, p1, C0, C1)
                    gb = g_row(pb, abs(vb))
                    sgb = _sgn(vb) * gb
                    a = Cb * h / gb
                    if a != ea:
                        ea = a
                        ed = math.exp(-a)
                    decay = ed
                    P = 0.0
                    if sweep == 0:
                        for i in range(M):
                            if not st_[i]:
                                tgt = xi[rb, i] * sgb
                                val = tgt + (Fi[i] - tgt) * decay
                                sa[i] = val
                                P += val
                    else:
                        for i in range(M):
                            if not st_[i]:
                                tgt = xi[rb, i] * sgb
                                val = tgt + (Fi[i] - tgt) * decay
                                sb[i] = val
                                P += val
                    f1 = (du - (P - P0) / h) * im
                    v_prev = vn
                    xi_n = E12 * v + q1 * f0 + q2 * f1
                    vn = E22 * v + r1 * f0 + r2 * f1
                a_b = a
                d_b = decay
                e = abs(vn - v_prev) / (tol_v + rtol * abs(vn))
                # truncation indicator: frozen s at the mean velocity (midpoint) against
                # the mean of the updates frozen at both ends (trapezoid); both second
                # order, their gap measures how much s(v) varies over the sub-step
                r_n, pn_, Cn = _side(vn, p0, p1, C0, C1)
                g_n = g_row(pn_, abs(vn))
                s_0 = sv * g0
                s_n = _sgn(vn) * g_n
                a = Cr * h / g0
                if a != ea:
                    ea = a
                    ed = math.exp(-a)
                d_0 = ed
                a = Cn * h / g_n
                if a != ea:
                    ea = a
                    ed = math.exp(-a)
                d_n = ed
                # the load was taken affine between P0 and P(h); a cubic Hermite with the
                # end rates differs from it by (h^2/12)(R0 - Rh) in impulse: its effect
                # on the velocity is the coupling error
                svn_ = _sgn(vn)
                Rh = 0.0
                for i in range(M):
                    if not st_[i]:
                        Rh += Cn * (xi[r_n, i] * svn_ - sb[i] / g_n)
                q = (h * h / 12.0) * abs(R0 - Rh) * im / (tol_v + rtol * abs(vn))
                if q > e:
                    e = q
                # the target xi_i s(v) moves over the sub-step (Stribeck range): the update frozen at
                # the mean velocity misses |T_n - T_0| ((1 + e^-a)/2 - (1 - e^-a)/a) ~ |dT| a^2/12 of
                # it, the exact response to a linearly moving target -- first order in the slope
                # of s, which the midpoint/trapezoid gap sees only to second order (issue 13, gmsw2)
                fT = 0.0
                if svn_ == sv and g_n != g0:  # g_n = g0 (past the Stribeck range): the target stands still
                    fT = a_b * a_b / 12.0 if a_b < SLIP_SERIES_A else abs(0.5 * (1.0 + d_b) - (1.0 - d_b) / a_b)
                for i in range(M):
                    if not st_[i]:
                        t0_ = xi[row, i] * s_0
                        tn_ = xi[r_n, i] * s_n
                        trap = 0.5 * (t0_ + (Fi[i] - t0_) * d_0 + tn_ + (Fi[i] - tn_) * d_n)
                        num = max(max(abs(sb[i] - sa[i]), abs(sb[i] - trap)), fT * abs(tn_ - t0_))
                        den = atol_F + rtol * abs(sb[i])
                        if num > e * den:  # divide only when this element can raise e
                            q = num / den
                            if q > e:
                                e = q
                # anti-damped sliding: the slipping elements' force falls with the speed faster than
                # sigma2 damps it (c + P g'/g < 0, g' the secant over the step; multiplied out by the
                # run squared: no division), so their local errors grow instead of decaying; such
                # sub-steps meet SLIP_UNSTABLE_TIGHT times tighter tolerances (issue 13, gmsw2)
                dav = abs(vn) - abs(v)
                if (a_b > SLIP_UNSTABLE_A and svn_ == sv and g_n != g0
                        and (c * g_n * dav + svn_ * P * (g_n - g0)) * dav < 0.0):
                    e *= SLIP_UNSTABLE_TIGHT
            n += 1
            if n >= max_sub:
                status = BUDGET
                break
            if not (math.isfinite(xi_n) and math.isfinite(vn)):
                if h > H_MIN * dt:
                    h_try = 0.1 * h
                    continue
                status = NONFINITE
                break
            if e > 1.0:
                if any_slip and ((v > 0.0 and vn <= 0.0) or (v < 0.0 and vn >= 0.0)):
                    # A trial step across a reversal while elements slip: their targets xi_i s(v) and
                    # rates change sign at v = 0, which the error estimate reads as a truncation error
                    # however short the step (with fast slip, C / g ~ 2e4 /s, every crossing step was
                    # rejected down to H_MIN dt: status 3 inside the contract's ranges, issue 13,
                    # campaign seeds 5010, 5011, 5054). Every slipping element sticks at the reversal:
                    # land just before it (at most 0.9 h: a chord that puts the reversal near the step's
                    # end cannot stall the approach), and once it is within EVENT_TOL dt of the step's
                    # start, apply it there (the landing rule of the accepted steps below). Until issue 15
                    # (gms15) only once the error-based shrinking (x 0.2 a rejection) had reached 1e-4 dt:
                    # every reversal of the GMS-4 stick-slip benchmark then marched to it in ~8 rejected
                    # and ~6 accepted sub-steps; with the landing everywhere (capped at 0.9 h) 1843 -> 1733
                    # sub-steps, GMS-16 15710 -> 13675, GMS-4 closer to the reference (max |dx| 0.203 ->
                    # 0.175 um; GMS-16 0.0949 -> 0.0951 um; benchmarks/peers.py, 2026-11-24).
                    th_r = v / (v - vn)
                    if th_r * h <= h_ev:
                        for i in range(M):
                            st_[i] = True
                        continue
                    h_try = min(th_r * h - 0.5 * h_ev, 0.9 * h)
                    continue
                if h > H_MIN * dt:
                    h_try = h * max(0.2, 0.9 / math.sqrt(e))
                    continue
                status = TOLERANCE  # step-size underflow: never accept an over-tolerance step
                break
            # --- switching surfaces crossed inside this trial step?
            theta = 2.0
            reversed_ = (v > 0.0 and vn <= 0.0) or (v < 0.0 and vn >= 0.0)
            if reversed_ and v != 0.0:
                th_r = v / (v - vn)
                if th_r * h > h_ev:
                    # A sticking element's force peaks where v = 0 (the displacement
                    # extremum), so a breakaway can fall between the step's ends and go
                    # unseen (grazing). If one could be within reach, first land just
                    # *before* the reversal, where the breakaway test below applies in the
                    # old direction; the next sub-step then crosses v = 0.
                    reach = abs(v) * h
                    for i in range(M):
                        if st_[i] and xi[row, i] * g0 - sv * Fi[i] <= k[row, i] * reach:
                            theta = th_r - h_ev / h
                            break
                if theta > 1.0 and (any_slip or directional):
                    theta = th_r
            rown, pn, _ = _side(vn, p0, p1, C0, C1)
            gn = g_n if g_n >= 0.0 else g_row(pn, abs(vn))
            svn = _sgn(vn)
            if reversed_ and theta > 1.0 and vn != 0.0:
                # A breakaway in the new direction after a reversal inside this step would
                # only be applied at the step's end, late and past its threshold (found by the
                # issue-13 property test: 1.5 % of the stroke off the twin). Land at the
                # reversal first; the next sub-step locates the breakaway.
                # The threshold is tested at the lower of g at the step's end and g(0+), where the
                # new direction begins: with Fs < Fc an element whose force at the reversal is above
                # xi Fs breaks away right there, although at the step's end (faster, g ~ Fc) it is
                # below its threshold again -- a window of |v| < vs·O(1) after the reversal that
                # _interior_breakaway's grid can step over (issue 13, seed 2102: 3.3e-3 of the
                # friction range off at rtol 1e-7). svn F is lowest at the reversal, so the force
                # at the end bounds it: a landing at the reversal then decides exactly.
                gz = min(gn, g_row(pn, 0.0))
                for i in range(M):
                    if st_[i] and svn * (Fi[i] + k[row, i] * xi_n) >= xi[rown, i] * gz:
                        theta = th_r
                        break
            if vn != 0.0 and not reversed_:
                for i in range(M):
                    if st_[i]:
                        Fe = Fi[i] + k[row, i] * xi_n
                        e1 = xi[rown, i] * gn - svn * Fe
                        if e1 <= 0.0:
                            e0 = xi[row, i] * g0 - svn * Fi[i]
                            th = e0 / (e0 - e1) if e0 > 0.0 else 0.0
                            if th < theta:
                                theta = th
            # A breakaway INSIDE the step that the ends do not show: the threshold xi_i g(v) falls
            # with |v| (Stribeck) while the sticking force climbs, so the event function can dip
            # below zero mid-step and be positive again at an end where |v| is small and
            # g ~ Fs (issue 13, round 8: a landing just before a reversal ended at |v| << vs and
            # missed a breakaway at |v| ~ 30 vs; x 0.44 %, friction 1.7 % of their ranges off the
            # twin at status 0). Only an element whose force can reach the lowest threshold
            # xi_lo g_lo anywhere in the step is looked at, on the step's cubic Hermite
            # (x, v and the accelerations at both ends; see _interior_breakaway). Only a step
            # whose ends show no switch: one that does is shortened to it anyway, and the
            # shorter step is looked at again.
            if theta > 1.0:
                ext = h * max(abs(v), abs(vn)) if reversed_ else 0.0
                cand = _sticking_may_reach(M, st_, Fi, k, row, xi_n, ext, xi_lo, g_lo)
                if cand:
                    Pn = 0.0
                    if any_slip:
                        for i in range(M):
                            if not st_[i]:
                                Pn += sb[i]
                    a0_ = (w - S0 - P0 - c * v) * im
                    an_ = (w + du * h - S0 - K * xi_n - Pn - c * vn) * im
                    # cheap screen first: the lowest g over the step's speeds (both directions
                    # when the step reverses); most such steps are slow sticking, g ~ Fs
                    if reversed_:
                        gl = min(g_row(p0, 0.0), g_row(p1, 0.0))
                        gl = min(gl, min(_g_low(p0, v, vn, a0_, an_, h), _g_low(p1, v, vn, a0_, an_, h)))
                    else:
                        gl = _g_low(pn, v, vn, a0_, an_, h)
                    cand = _sticking_may_reach(M, st_, Fi, k, row, xi_n, ext, xi_lo, gl)
                if cand:
                    th_i = _interior_breakaway(
                        M, st_, Fi, k, xi, row, p0, p1, xi_lo, g_lo, v, vn, a0_, an_, xi_n, h
                    )
                    if th_i < theta:
                        theta = th_i
            if theta < 1.0 and (1.0 - theta) * h > h_ev:
                # land just past the first crossing (just before a reversal) and try again
                h_try = max(theta * h + 0.5 * h_ev, 0.5 * h_ev)
                continue
            # accept
            for i in range(M):
                if st_[i]:
                    Fi[i] += k[row, i] * xi_n
                else:
                    Fi[i] = sb[i]
            x += xi_n
            v = vn
            t += h
            if abs(v) > vpk:
                vpk = abs(v)
                tol_v = _atol_run(atol_v, v_floor, rtol, vpk)
            if theta <= 1.0:
                if reversed_:
                    for i in range(M):
                        st_[i] = True
                if vn != 0.0:
                    for i in range(M):
                        if st_[i]:
                            lvl = xi[rown, i] * gn
                            if svn * Fi[i] >= lvl:
                                st_[i] = False
                                # crossed inside this sub-step (below the threshold at its start): leave
                                # stick AT the threshold. The landing is up to EVENT_TOL dt past the
                                # crossing; keeping the spring's overshoot k |v| EVENT_TOL dt as slip force
                                # left it unrelaxed where C / g is small (issue 13, campaign seed 2092:
                                # sum k 1.7e8 N/m, C / g 0.06 /s, 6.6e-5 N carried into later breakaway
                                # cascades, the friction 1.2e-3 of its range off the twin at every rtol;
                                # 1.1e-6 with this). An element already at or past it at the start (an
                                # initial state) slips from its own force.
                                if not reversed_ and svn * (Fi[i] - k[row, i] * xi_n) < xi[row, i] * g0:
                                    Fi[i] = svn * lvl
            fac = 0.9 / math.sqrt(e) if e > 0.0 else 5.0
            h_try = h * min(5.0, max(0.2, fac))
            if clipped and theta > 1.0 and h_try < h_prop:
                # the step was cut to the interval's end, not by its error: the next interval starts
                # from the step proposed (before, a short last piece shrank the next interval's
                # first steps and every new h recomputed the oscillator coefficients: GMS-4
                # stick-slip 1941 -> 1843 steps, 0.299 -> 0.216 um off the twin)
                h_try = h_prop
        # ------------------------------------------------ end of the interval
        total += n
        pr = p0 if v >= 0.0 else p1
        if record:
            tot = 0.0
            for i in range(M):
                tot += Fi[i]
                Fel[kk, i] = Fi[i]
                stick_out[kk, i] = st_[i]
            x_out[kk] = x
            v_out[kk] = v
            F_out[kk] = tot + pr[R_S2] * v
            if status != OK:
                return status, kk, total, acc
        else:
            if status != OK:
                return status, kk, total, acc
            if which == 0:
                y = x
            elif which == 1:
                y = v
            else:
                tot = 0.0
                for i in range(M):
                    tot += Fi[i]
                y = tot + pr[R_S2] * v
            dd = y - target[kk]
            acc += weight[kk] * dd * dd
        kk += 1
    return OK, N - 1, total, acc


@njit
def gms_force(
    u, dt, m, static, k, xi, C, x0, v0, F0, stick0, rtol, atol_v, atol_F, max_sub,
    x, v, F, Fel, stick_out, v_floor=1.0, span=True,
):
    """Force-driven run; fills ``x, v, F`` (N,), ``Fel`` (N, M) and ``stick_out`` (N, M).

    ``stick_out`` must arrive zeroed (all False): spans write the flags only where an element
    sticks (``simulation.core._gms_block`` zeroes it; the motion path's ``_gms_buffers`` uses ``np.zeros``).

    ``v_floor``: as in :func:`frictionkit.kernels.lugre.lugre_force`. ``span``: spanning steps
    (module docstring); False gives the adaptive sub-steps in every interval (tests compare)."""
    dummy = np.empty(1)
    status, kk, total, _ = _drive(
        u, dt, m, static, k, xi, C, x0, v0, F0, stick0, rtol, atol_v, atol_F, max_sub,
        True, x, v, F, Fel, stick_out, 0, dummy, dummy, v_floor, span,
    )
    return status, kk, total


@njit(parallel=True)
def gms_force_batch_sse(
    u, dt, m, static, k, xi, C, rtol, atol_v, atol_F, max_sub, target, which, weight, out_sse, out_status,
    v_floor=1.0, span=True,
):
    """P parameter sets on one input; weighted squared error of position (0), velocity (1) or force (2)."""
    P = m.size
    M = k.shape[2]
    for j in prange(P):
        F0 = np.zeros(M)
        stick0 = np.ones(M, dtype=np.bool_)
        d1 = np.empty(1)
        d2 = np.empty((1, M))
        d3 = np.empty((1, M), dtype=np.bool_)
        status, _, _, acc = _drive(
            u, dt, m[j], static[j], k[j], xi[j], C[j], 0.0, 0.0, F0, stick0, rtol, atol_v, atol_F, max_sub,
            False, d1, d1, d1, d2, d3, which, target, weight, v_floor, span,
        )
        out_sse[j] = acc if status == OK else np.inf
        out_status[j] = status


@njit
def gms_motion(xpos, dt, static, k, xi, C, F0, stick0, v_out, F_out, Fel, stick_out):
    """Motion-driven GMS, exact for piecewise-linear position."""
    N = xpos.size
    M = F0.size
    Fi = F0.copy()
    st_ = stick0.copy()
    p0 = static_row(static, 0)
    p1 = static_row(static, 1)
    last_sign = 0.0
    for kk in range(N):
        if kk == 0:
            vk = (xpos[1] - xpos[0]) / dt
        else:
            vk = (xpos[kk] - xpos[kk - 1]) / dt
            sv = _sgn(vk)
            if sv != last_sign:
                # reversal or rest: every slipping element sticks again
                for i in range(M):
                    st_[i] = True
                last_sign = sv
            if sv != 0.0:
                row = 0 if vk >= 0.0 else 1
                g = g_row(p0 if row == 0 else p1, abs(vk))
                s = sv * g
                decay = math.exp(-C[row] * dt / g)
                for i in range(M):
                    target = xi[row, i] * s
                    if st_[i]:
                        Fe = Fi[i] + k[row, i] * vk * dt
                        if sv * Fe >= xi[row, i] * g:
                            if sv * Fi[i] >= xi[row, i] * g:
                                # already past the (lowered) limit: slips the whole interval
                                Fi[i] = target + (Fi[i] - target) * decay
                            else:
                                # breaks away inside the interval at F = xi s, then stays there
                                Fi[i] = target
                            st_[i] = False
                        else:
                            Fi[i] = Fe
                    else:
                        Fi[i] = target + (Fi[i] - target) * decay
        row = 0 if vk >= 0.0 else 1
        tot = 0.0
        for i in range(M):
            tot += Fi[i]
            Fel[kk, i] = Fi[i]
            stick_out[kk, i] = st_[i]
        v_out[kk] = vk
        F_out[kk] = tot + (p0 if row == 0 else p1)[R_S2] * vk
    return OK
