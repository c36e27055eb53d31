"""Numba kernel of the machine core: any linear mechanical chain, sites holding any
friction law or nonlinear compliance, sensors, a block-diagram controller and actuators,
in one compiled closed loop.

Flat arrays and floats in, arrays and a status code out; no validation here (the public
wrapper :func:`frictionkit.machines.simulate_machine` validates and packs).

Integration scheme (one sub-step ``h = dt / n_sub``)
----------------------------------------------------
The generalised coordinates ``q`` (n) obey ``M q'' + D q' + K q = Bw w(t) - sum_j c_j F_j``.
The linear part is advanced *exactly*: ``X+ = Phi X + G0 w0 + G1 (w1 - w0) + Gf Fbar``
(``X = [q, q']``; ``w`` affine over the sub-step: actuator forces, prescribed motions and
their rates; ``Fbar`` the site forces held over the sub-step). Stiff springs cost nothing.

Site ``j`` (dynamic friction law, nonlinear compliance or position-dependent load) moves by
``ds_j = a_j - sum_i G_ji Fbar_i`` over the sub-step, with ``a_j`` its free motion and
``G = -Cq Gf_q`` the sub-step compliance between sites. Each site's law returns the *mean*
force over the sub-step for a site moving at the constant velocity ``ds / h`` (exact
exponential updates for LuGre/Dahl, closed-form breakaway and slip for GMS, Simpson's rule
for memoryless elastic forces), and the coupled equations ``Fbar_j = law_j(ds_j)`` are
solved *implicitly* (Gauss-Seidel over sites, a bracketed Illinois root per site). So a
bristle stiffness of 1e8 N/m or a sticking GMS element is stable at any sub-step. A static
(Stribeck/Coulomb) site has no state and is coupled through its *end velocity* instead
(``v_j = b_j - sum_i H_ji Fbar_i``, ``H = -Cq Gf_v``), implicit Euler in the friction: it
sticks exactly (``v_j = 0``) while the holding force lies inside ``[-Fs-, Fs+]`` and slides
with ``F = s(v_j) + sigma2 v_j`` otherwise (Karnopp's stick model, made exact in discrete time).

The scheme is first order in ``h`` overall (site forces held over the sub-step); raise
``n_sub`` for accuracy. The parity tests against the ``solve_ivp`` twin measure it.

Sample-spanning step. When every site is a flat static law (``CoulombViscous``: EMPS), the
wrapper folds the viscous terms into the chain, so a sliding site's force is a constant
``+-Fc`` and the sub-steps are exact; a sample in which every site keeps sliding one way at
every sub-step end (checked with precomputed rows, :func:`merge_maps`) is then advanced by one
map instead of ``n_sub`` sub-steps — the same result to round-off (:func:`_merged_step`).

Controller (once per sample, before the plant step)
---------------------------------------------------
``sig`` holds every named signal; a signal keeps its value until written again, so a block
that reads a signal written later in the order (or an actuator's applied value) sees the
previous sample's value. Order: inputs, sensors (quantised, noisy, delayed), blocks in
order, actuators (saturate, delay), PID integrators (frozen while their actuator
saturates).

Normal loads
------------
A friction site may carry a normal load that depends on the state (a ball nut's flank load
follows the drive force; seed 000's ball pair grows with axial load): see :func:`_loads`.
Its law's levels, stiffnesses and damping scale with ``lam = N / N_ref``; its viscous term
``sigma2 v`` does not. The load is evaluated at the start of each sub-step.

Status codes: 0 ok, 1 non-finite state (run stopped at ``k_end``).

Every function here is compiled with numba's IEEE error model (``error_model="numpy"``: a
division by zero gives inf/NaN instead of raising), which drops a zero test and branch from
every division — about a third of the per-sample cost of the EMPS loop. No division here can
be by zero on a valid state, and the loop checks the state for non-finite values itself.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import njit

STATUS_OK = 0
STATUS_NONFINITE = 1

#: Bound on a coarse step's error estimate in ``run`` [site unit: m, or rad for a rotational
#: site]: a site's force deviation from its held mean over the step, times the site's effective
#: compliance over the step. A numerical tolerance, not a physical assumption: at 1e-12 the
#: ball-screw stages (Dahl sliding / flank / Hertz nut, GMS-4) and the two-shaft drive keep the
#: 10-sub-step runs' errors against 640 sub-steps to 1e-3 nm (ideal sensors); at 1e-10 the
#: Hertz stage (0.28 -> 0.34 nm) and the two-shaft drive (0.08 -> 0.17 nm) lose accuracy.
COARSE_PTOL = 1e-12

#: Sub-steps at which a coarse step's bound is :data:`COARSE_PTOL`; at ``n_sub`` above it the
#: bound is ``COARSE_PTOL * COARSE_PTOL_SUBSTEPS / n_sub`` (the scheme is first order: the
#: sub-steps' error falls as ``1 / n_sub``, so the coarse steps' must too). Without it a run at
#: more sub-steps (the loop check's rerun at 4x, the sub-step check's at 16x) kept the same coarse
#: steps as the run it checks (99 % of the two-shaft drive's samples), so "at 40 sub-steps" meant
#: the 1 % of sub-stepped samples only. 10 = the default ``substeps``: its runs are unchanged.
#: Measured 2026-11-24 on the two-shaft benchmark drive (2.5 s): the check's rerun at 40 keeps
#: 9,832 of 10,001 samples as one step (9,916 before), CPU 29 -> 32 ms; its verdict is unchanged
#: (the run against the rerun 0.107 -> 0.101 of the bound; against 40 sub-steps without coarse
#: steps 0.127, against 640 0.127: the quantised loop's own spread, not the scheme's).
COARSE_PTOL_SUBSTEPS = 10

#: Tolerance of a site's solve in ``run`` (the residual of ``ds = a - Gjj Fbar(ds)``, and the
#: input change that makes the Gauss-Seidel sweeps solve a site again) [site unit, as
#: :data:`COARSE_PTOL`; m/s for a static site's velocity form], plus ``1e-13 |a|``. Tied to the
#: coarse steps' bound and scaled with it above :data:`COARSE_PTOL_SUBSTEPS` (a run at 4x the
#: sub-steps solves 4x as tightly). It was 1e-18 (forces converged to ~5e-9 N, 1e6x below the
#: bound): ~1.5 law evaluations a solve, ~2 sweeps a sample. Measured 2026-11-24 (mtol; same run,
#: kernel CPU of the benchmark workloads, one tolerance for every run; 1e-18 -> 1e-16 / 1e-15 /
#: 1e-14 / 1e-13 / 1e-12): two-shaft drive with its loop check's rerun -24 / -34 / -35 / -35 /
#: -36 %, Dahl sliding stage -3 / -4 / -5 / -6 / -9 %, GMS-4 -4 / -7 / -9 / -11 / -13 %, flank
#: -3 / -15 / -38 / -40 / -41 %, Hertz -5 / -19 / -39 / -41 / -41 %. Accuracy (ideal sensors,
#: 2 s, table against 640 sub-steps without coarse steps: sliding 0.208, GMS-4 0.924, flank
#: 0.247, Hertz 0.246 nm): the table moves from the 1e-18 run by 2e-16 m (float rounding: 1e-19
#: and 1e-17 alike) / 2e-16 / 5e-15 / 3e-14 / 2e-13 / 1e-11 m; at 1e-12 the flank and Hertz
#: errors grow 2 % and the two-shaft drive's screw error (ideal sensors) falls 17 %. 1e-15, not
#: 1e-14: at 1e-14 the zhang2023 preset's co-speed pre-sliding run at 2 sub-steps passes its
#: sub-step check (its table moved 1.08 % of its range against 32 sub-steps, bound 1 %; below
#: 1 % at 1e-14: a quantised loop, a count flips), which tests/reference/zhang2023 holds as the
#: reason for the preset's default of 3. At 1e-15 (this constant, scaled): the two-shaft drive's
#: coarse law evaluations 10.9 -> 4.3, solves 7.1 -> 4.1, sweeps 2.03 -> 1.05 a sample; its
#: errors (ideal sensors, 2 s) screw 9.981e-8 -> 9.979e-8 rad, nut 5.821e-9 rad unchanged; its
#: loop check at 0.101 of its bound either way.
SITE_XTOL = 1e-3 * COARSE_PTOL

#: A rejected coarse step is tried again at the next sample up to this many times in a row;
#: after that the tries back off (2, 4, ... 32 samples) until one passes. A rejected try costs
#: its coarse step on top of the sub-steps: ~1.5 us against ~7.6 us for a sample's 10 sub-steps
#: (``benchmarks/machine_profile.py``, flank stage), so trying again at once pays while ~1 in 5
#: such tries passes. With the back-off from the first rejection the flank and Hertz stages
#: (paper sensors: short runs of rejected samples, 1-4 long, where a command jump rings the
#: motor coupling) kept 53 / 38 % of their samples as one step while 82 / 73 % pass when every
#: sample is tried. Measured 2026-11-24 (same process, captured benchmark workloads, least of 6
#: runs, load ~5; retries 0 / 2 / 4 / 8): flank 47.1 / 39.0 / 45.2 / 38.3 ms (53 / 72 / 64 / 74 %
#: one step: the quantised loop's counts make single runs jumpy), Hertz 71.7 / 57.9 / 62.3 /
#: 56.9 ms (38 / 62 / 60 / 65 %); the Dahl sliding stage 7.2 / 6.6 / 6.6 / 6.4 ms, GMS-4 12.5 /
#: 12.2 / 12.0 / 12.2 ms, the two-shaft drive 15.6 / 15.6 / 15.4 / 15.4 ms (their rejections:
#: ~20-sample runs at reversals). A running pass share instead (retry while > 1/4 of the last
#: ~10 tries passed) kept as many but retried through those reversal runs: sliding +15 %.
COARSE_RETRIES = 8

# Site kinds
S_STATIC, S_LUGRE, S_GMS, S_HERTZ, S_PWL, S_SINE = 0, 1, 2, 3, 4, 5
#: Memoryless site kinds whose force is a smooth function of the site coordinate: a Hertz
#: contact (``(d0 + d)_+^1.5`` keeps a continuous slope through contact loss) and a sine. Their
#: coarse steps use a linear force profile whose slope is extrapolated from the recorded forces
#: (see ``run``, "Coarse steps"). Not the piecewise-linear spring (kinks at its breaks), nor
#: the friction laws' own dynamics: a kink (a GMS element's breakaway) or a bristle ringing
#: inside the step lets a linear profile match the ends while the force between them does not.
#: Measured on the twin parity cases with the extrapolated profile on every site: "ballscrew"
#: (GMS-4 nut, LuGre guide) 1.19e-7 rad against 1.61e-8 held, "hertz_stage" 8.8e-6 rad with it
#: on its LuGre sites. A friction site with a normal load gets only its load's ramp instead; a
#: GMS site a profile its law predicts, kept only while no element changes its mode (``run``).
SMOOTH = (False, False, False, True, False, True)
# Block codes
B_LINEAR, B_PID, B_SS, B_SAT, B_FFF = 0, 1, 2, 3, 4

#: Offsets of a packed static row (6 floats per direction) inside a site's parameters.
N_ROW = 6
#: Floats of a static law's parameters (site or feed-forward block), see :func:`_static_force`.
N_STATIC_SITE = 22


# --------------------------------------------------------------------------- Stribeck
@njit(error_model="numpy")
def _g(par, o, av):
    """``g = |s(v)|`` at speed ``av >= 0`` of the packed row ``par[o:o+6]``."""
    Fc = par[o]
    Fs = par[o + 1]
    if Fs == Fc:  # flat (Dahl, Coulomb): no shape to evaluate, the same value
        return Fc
    r = av / par[o + 2]
    if r == 0.0:
        return Fs
    if par[o + 5] == 0.0:
        d = par[o + 3]
        # the exponents of the laws in use without pow (measured 45-70 ns a call under load
        # against 1-3 ns: the two-shaft drive's nut (3) and ball pair (1.5) evaluate it once per
        # law evaluation); these differ from pow by a few ulp
        if d == 2.0:
            e = r * r
        elif d == 1.0:
            e = r
        elif d == 3.0:
            e = r * r * r
        elif d == 1.5:
            e = r * math.sqrt(r)
        elif d == 0.5:
            e = math.sqrt(r)
        else:
            e = r**d
        if e > 700.0:
            return Fc
        return Fc + (Fs - Fc) * math.exp(-e)
    return Fc + (Fs - Fc) / (1.0 + r * r)


@njit(error_model="numpy")
def _static_force(par, o, v, lam):
    """``lam s(v) + sigma2 v - eps v |v|`` with the row of the direction of ``v`` (row 0 for
    ``v >= 0``). Static-law layout at ``o`` (``N_STATIC_SITE`` floats): live rows (12), eps+,
    eps-, then the schedule rows Fc0+, Fc1+, Fs0+, Fs1+, Fc0-, Fc1-, Fs0-, Fs1- (see
    :func:`_set_levels`). Levels are signed: a negative level pushes along the motion."""
    if v >= 0.0:
        return lam * _g(par, o, v) * (1.0 if v > 0.0 else 0.0) + par[o + 4] * v - par[o + 12] * v * v
    return -lam * _g(par, o + N_ROW, -v) + par[o + N_ROW + 4] * v + par[o + 13] * v * v


@njit(inline="always", error_model="numpy")
def _set_levels(par, o, s):
    """Write the live levels ``Fc = Fc0 + Fc1 s``, ``Fs = Fs0 + Fs1 s`` of both directions of
    the static law at ``o`` for the schedule value ``s`` (a TDMSSC's base speed)."""
    par[o] = par[o + 14] + par[o + 15] * s
    par[o + 1] = par[o + 16] + par[o + 17] * s
    par[o + N_ROW] = par[o + 18] + par[o + 19] * s
    par[o + N_ROW + 1] = par[o + 20] + par[o + 21] * s


# --------------------------------------------------------------------------- site laws
@njit(inline="always", error_model="numpy")
def _relax(x):
    """``(exp(-x), (1 - exp(-x)) / x)`` for ``x > 0``: end and mean factor of an exponential
    relaxation over an interval; one ``exp``, a series for small ``x``, none past underflow."""
    if x > 700.0:
        return 0.0, 1.0 / x
    e = math.exp(-x)
    if x < 1e-3:  # (1 - e^-x) / x to O(x^4)
        return e, 1.0 - x * (0.5 - x * (1.0 / 6.0 - x * (1.0 / 24.0)))
    return e, (1.0 - e) / x


@njit(error_model="numpy")
def _lugre_mean(par, o, z0, ds, h, lam, dl=0.0):
    """Mean force over ``h`` and end state for a site moving at ``v = ds / h``.

    ``dl``: the normal-load scale's change over ``h`` (linear in time from ``lam``; a coarse
    step's prediction, else 0). The state is load-normalised: a falling load scales the force
    with it (``F = lam(t) s0 z(t)``, ``z`` relaxing as at a fixed load); a rising one adds no
    traction (the continuous form of :func:`_loads`' rescaling, ``(lam z)' = lam z'_dyn``:
    ``y = lam z`` obeys ``y' = lam(t) v - r y``). Both are integrated exactly; the end state
    returned is normalised by the end load ``lam + dl``.

    Layout at ``o``: static rows (12), sigma0+, sigma1+, sigma0-, sigma1-.
    """
    v = ds / h
    if v >= 0.0:
        ro = o
        s0 = par[o + 12]
        s1 = par[o + 13]
    else:
        ro = o + N_ROW
        s0 = par[o + 14]
        s1 = par[o + 15]
    s2 = par[ro + 4]
    if v == 0.0:
        return lam * s0 * z0, z0
    av = abs(v)
    g = _g(par, ro, av)
    sg = 1.0 if v > 0.0 else -1.0
    if g <= 0.0:  # no friction level: the bristles relax at once
        return lam * s1 * (0.0 - z0) / h + s2 * v, 0.0
    zss = sg * g / s0
    x = s0 * av * h / g
    e, frac = _relax(x)
    if dl == 0.0:
        z1 = zss + (z0 - zss) * e
        zbar = zss + (z0 - zss) * frac
        return lam * (s0 * zbar + s1 * (z1 - z0) / h) + s2 * v, z1
    lm = lam + 0.5 * dl
    l1 = lam + dl
    if dl < 0.0:  # falling: mean of lam(t) z(t); m1 = (1/h) int (t/h) e^(-r t) dt = (frac - e) / x
        m1 = (frac - e) / x if x >= 1e-3 else 0.5 - x * (1.0 / 3.0 - x * 0.125)
        z1 = zss + (z0 - zss) * e
        ybar = lm * zss + (z0 - zss) * (lam * frac + dl * m1)
    else:  # rising: y = lam z, q = (1 - frac) / x
        q = (1.0 - frac) / x if x >= 1e-3 else 0.5 - x * (1.0 / 6.0 - x * (1.0 / 24.0))
        c0 = lam * z0 - lam * zss
        ybar = lm * zss + c0 * frac - zss * dl * q
        z1 = (l1 * zss + c0 * e - zss * dl * frac) / l1
    return s0 * ybar + lm * s1 * (z1 - z0) / h + s2 * v, z1


@njit(inline="always", error_model="numpy")
def _sgn(v):
    """Sign of ``v`` (0 at 0), as :func:`_gms_el` takes it."""
    return 1.0 if v > 0.0 else (-1.0 if v < 0.0 else 0.0)


@njit(inline="always", error_model="numpy")
def _gms_el(F0, mode, k, xi, g, e, frac, ds, dur, va, vb):
    """One GMS element over ``dur``: ``(F1, mean, mode)``.

    The site moves by ``ds`` with its velocity linear from ``va`` to ``vb`` (one sign; mean
    ``ds / dur``), so a sticking element's force is quadratic in time and its breakaway
    instant is the root of a quadratic. A slipping element relaxes towards ``xi s(v)`` at the
    rate ``C / g``, with ``g`` at the mean speed: ``(e, frac) = _relax(C dur / g)``, the same for
    every element of the site, so the caller evaluates it once per phase (only read here when
    the element keeps slipping).
    """
    v = ds / dur
    sg = _sgn(v)
    if mode != 0.0 and mode == sg:  # keeps slipping: relaxes to xi s(v) at rate C / g
        Fst = sg * xi * g
        if g <= 0.0:
            return Fst, Fst, mode
        return Fst + (F0 - Fst) * e, Fst + (F0 - Fst) * frac, mode
    # sticking (a slipping element sticks when the motion stops or reverses)
    if sg == 0.0:
        return F0, F0, 0.0
    Fb = sg * xi * g
    if sg * F0 >= xi * g:  # already at its limit: slips for the whole interval
        return Fb, Fb, sg
    # direction-normalised: speeds a (start), b (end) >= 0, reach xb >= 0 to break away
    a = sg * va
    b = sg * vb
    if a < 0.0:
        a = 0.0
    if b < 0.0:
        b = 0.0
    if a + b <= 0.0:
        a = sg * v
        b = a
    c2 = (b - a) / (2.0 * dur)  # x(t) = a t + c2 t^2 (x(dur) = |ds| when a + b = 2|v|)
    xb = (xi * g - sg * F0) / k
    disc = a * a + 4.0 * c2 * xb
    tb = dur
    if disc >= 0.0:
        den = a + math.sqrt(disc)
        if den > 0.0:
            tb = 2.0 * xb / den
    if tb >= dur:
        # mean of x over the interval: a dur / 2 + c2 dur^2 / 3
        return F0 + k * ds, F0 + sg * k * (0.5 * a * dur + c2 * dur * dur / 3.0), 0.0
    # breaks away at tb, then stays on xi s(v)
    xint = 0.5 * a * tb * tb + c2 * tb * tb * tb / 3.0  # integral of x over [0, tb]
    return Fb, (F0 * tb + sg * k * xint + Fb * (dur - tb)) / dur, sg


@njit(inline="always", error_model="numpy")
def _gms_rows(par, o, M, d):
    """Offsets of the static row and of k, xi, and C for motion ``d`` (row 0: ``d >= 0``)."""
    if d >= 0.0:
        return o, o + 13, o + 13 + M, par[o + 13 + 4 * M]
    return o + N_ROW, o + 13 + 2 * M, o + 13 + 3 * M, par[o + 14 + 4 * M]


@njit(error_model="numpy")
def _gms_mean(par, o, st, so, ds, h, out, lam, v0):
    """Mean GMS force over ``h`` for a site moving by ``ds`` from velocity ``v0``; element
    states written to ``out`` (at ``so``; ``out`` may be ``st`` itself: each element reads its
    own state before writing it).

    The site's velocity is taken as linear in time over the sub-step, from ``v0`` with mean
    ``ds / h`` (end velocity ``v1 = 2 ds / h - v0``). When it changes sign inside the sub-step,
    the reversal instant ``tr = h v0 / (v0 - v1)`` splits the sub-step into two
    constant-velocity phases, so the slipping elements stick again at the reversal, not at a
    sub-step boundary.

    Layout at ``o``: static rows (12), M, k+ (M), xi+ (M), k- (M), xi- (M), C+, C-.
    State at ``so``: F_i (M), mode_i (M: 0 sticking, +1/-1 slipping in that direction).
    """
    M = int(par[o + 12])
    v1 = 2.0 * ds / h - v0  # end velocity of the linear-velocity model
    two = v0 * v1 < 0.0
    tr = h
    if two:
        tr = h * v0 / (v0 - v1)
        if not (0.0 < tr < h):
            two = False
    if two:
        d1 = 0.5 * v0 * tr
        d2 = ds - d1
        dur1 = tr
        dur2 = h - tr
        va1 = v0
        vb1 = 0.0
    else:
        d1 = ds
        dur1 = h
        d2 = 0.0
        dur2 = 0.0
        va1 = v0
        vb1 = v1
    # direction rows of the phases
    ro1, ko1, xo1, C1 = _gms_rows(par, o, M, d1)
    g1 = _g(par, ro1, abs(d1) / dur1)
    ro2, ko2, xo2, C2 = ro1, ko1, xo1, C1
    g2 = g1
    if two:
        ro2, ko2, xo2, C2 = _gms_rows(par, o, M, d2)
        g2 = _g(par, ro2, abs(d2) / dur2)
    w1 = dur1 / h
    w2 = dur2 / h
    # the slip relaxation factors of each phase, evaluated once, when an element first needs them
    sg1 = _sgn(d1 / dur1)
    sg2 = _sgn(d2 / dur2) if two else 0.0
    e1 = fr1 = e2 = fr2 = 0.0
    have1 = have2 = False
    fric = 0.0
    for i in range(M):
        mode = st[so + M + i]
        if not have1 and mode != 0.0 and mode == sg1 and g1 > 0.0:
            e1, fr1 = _relax(C1 * dur1 / g1)
            have1 = True
        F1, m1, mode = _gms_el(st[so + i], mode, par[ko1 + i], par[xo1 + i], g1, e1, fr1, d1, dur1,
                               va1, vb1)
        mean = m1 * w1
        if two:
            if not have2 and mode != 0.0 and mode == sg2 and g2 > 0.0:
                e2, fr2 = _relax(C2 * dur2 / g2)
                have2 = True
            F1, m2, mode = _gms_el(F1, mode, par[ko2 + i], par[xo2 + i], g2, e2, fr2, d2, dur2, 0.0, v1)
            mean += m2 * w2
        fric += mean
        out[so + i] = F1
        out[so + M + i] = mode
    visc = par[ro1 + 4] * d1 / h + (par[ro2 + 4] * d2 / h if two else 0.0)
    return lam * fric + visc


@njit(error_model="numpy")
def _elastic(kind, par, o, d):
    """Memoryless site force at site coordinate ``d``."""
    if kind == S_HERTZ:  # c (d0 + d)_+^1.5 - c (d0 - d)_+^1.5 - k_lin d
        c = par[o]
        d0 = par[o + 1]
        a = d0 + d
        b = d0 - d
        fa = c * a * math.sqrt(a) if a > 0.0 else 0.0
        fb = c * b * math.sqrt(b) if b > 0.0 else 0.0
        return fa - fb - par[o + 2] * d
    if kind == S_PWL:  # odd piecewise-linear spring minus k_lin d
        # layout: k_lin, nseg, k_0..k_{nseg-1}, b_1..b_{nseg-1} (|d| breaks, increasing)
        nseg = int(par[o + 1])
        ad = abs(d)
        f = 0.0
        lo = 0.0
        for i in range(nseg):
            k = par[o + 2 + i]
            hi = par[o + 2 + nseg + i] if i < nseg - 1 else math.inf
            if ad <= hi:
                f += k * (ad - lo)
                break
            f += k * (hi - lo)
            lo = hi
        sg = 1.0 if d > 0.0 else (-1.0 if d < 0.0 else 0.0)
        return sg * f - par[o] * d
    # S_SINE: amplitude sin(d + phase)
    return par[o] * math.sin(d + par[o + 1])


@njit(error_model="numpy")
def _site_mean(kind, par, o, st, stw, so, s0, ds, h, lam, v0, dl):
    """``(mean force, LuGre end state)`` over the sub-step for displacement ``ds`` from ``s0``.

    ``lam``: normal-load scale of a friction law (its state is load-normalised, see run);
    ``dl`` its change over ``h`` (a LuGre/Dahl site in a coarse step, :func:`_lugre_mean`).
    """
    if kind == S_STATIC:
        return _static_force(par, o, ds / h, lam), 0.0
    if kind == S_LUGRE:
        return _lugre_mean(par, o, st[so], ds, h, lam, dl)
    if kind == S_GMS:
        # the element states at ``ds`` go to the scratch ``stw``; 1.0 says they are there, so
        # the commit in run copies them instead of evaluating the law once more
        return _gms_mean(par, o, st, so, ds, h, stw, lam, v0), 1.0
    f0 = _elastic(kind, par, o, s0)
    fm = _elastic(kind, par, o, s0 + 0.5 * ds)
    f1 = _elastic(kind, par, o, s0 + ds)
    return (f0 + 4.0 * fm + f1) / 6.0, 0.0


@njit(error_model="numpy")
def _site_now(kind, par, o, st, so, s, v, lam):
    """Instantaneous force of a dynamic or memoryless site at coordinate ``s``, velocity ``v``."""
    if kind == S_LUGRE:
        z = st[so]
        if v >= 0.0:
            ro = o
            s0 = par[o + 12]
            s1 = par[o + 13]
        else:
            ro = o + N_ROW
            s0 = par[o + 14]
            s1 = par[o + 15]
        g = _g(par, ro, abs(v))
        zd = v - s0 * abs(v) * z / g if g > 0.0 else v
        return lam * (s0 * z + s1 * zd) + par[ro + 4] * v
    if kind == S_GMS:
        M = int(par[o + 12])
        F = 0.0
        for i in range(M):
            F += st[so + i]
        return lam * F + (par[o + 4] if v >= 0.0 else par[o + N_ROW + 4]) * v
    return _elastic(kind, par, o, s)


@njit(error_model="numpy")
def _solve_site(kind, par, o, st, stw, so, s0, a, Gjj, h, Fguess, xtol, lam, kt, v0, xg, dl, F0g, z0g):
    """Solve ``ds = a - Gjj Fbar(ds)`` for the site; returns ``(ds, Fbar, kt, z1)`` (state untouched;
    ``z1`` the LuGre end state at ``ds``, NaN when the last evaluation was elsewhere).

    ``kt`` is the site's last secant slope ``dFbar/dds`` (a Newton-like first step from the
    explicit guess ``a - Gjj Fguess``, or from ``xg`` when it is finite: the caller's
    linearised update of the site's last solution when only ``a`` moved); secant steps follow
    until the root is bracketed, then Illinois regula falsi. Most sub-steps converge in two or
    three law evaluations. ``F0g``, ``z0g``: the law's value at that first point when the caller
    evaluated it already (``run``'s inline first step of a LuGre/Dahl solve), else NaN.
    """
    if Gjj <= 0.0:  # kinematic site (moved by prescribed motion only)
        Fa, za = _site_mean(kind, par, o, st, stw, so, s0, a, h, lam, v0, dl)
        return a, Fa, kt, za
    if kind == S_STATIC:
        # velocity form (see run): ``a`` is the free end velocity, ``Gjj`` the velocity
        # compliance; v_end = a - Gjj F with F = s(v_end) + sigma2 v_end - eps v_end |v_end|
        # (implicit Euler), or v_end = 0 while the holding force stays inside [-Fs-, Fs+].
        # Levels are signed (TDMSSC): a negative Fs+ means the law pushes forward at +0.
        fs_pos = lam * _g(par, o, 0.0)
        fs_neg = lam * _g(par, o + N_ROW, 0.0)
        f_hold = a / Gjj
        up = f_hold > fs_pos
        dn = f_hold < -fs_neg
        if not (up or dn):
            return 0.0, f_hold, kt, math.nan
        if up and dn:  # empty stick band (negative levels): slip the way the free motion goes
            if a > 0.0:
                dn = False
            elif a < 0.0:
                up = False
            else:  # at rest with nothing pushing: no direction is preferred, it stays at rest
                return 0.0, 0.0, kt, math.nan
        d = 1.0 if up else -1.0
        # bracket the root of f(x) = x + Gjj F(x) - a on the side d, in u = d x > 0:
        # d f(0 d) = d (Gjj F(0 d) - a) < 0; march out by fixed-point steps u <- d (a - Gjj F)
        # (monotone: each step adds -d f > 0), doubling when they stall, until d f > 0
        ulo = 0.0
        gulo = d * (Gjj * (fs_pos if up else -fs_neg)) - d * a
        u = d * a if d * a > 0.0 else 0.0
        uhi = -1.0
        guhi = 0.0
        Fu = 0.0
        for it in range(80):
            if u > 0.0:
                Fu = _static_force(par, o, d * u, lam)
                gu = d * (d * u + Gjj * Fu - a)
                if gu > 0.0:
                    uhi = u
                    guhi = gu
                    break
                ulo = u
                gulo = gu
                if gu >= -xtol:
                    return d * u, Fu, kt, math.nan
                un = d * (a - Gjj * Fu)
            else:
                un = -gulo  # the fixed-point step from rest
            if it >= 8 and un < 2.0 * u:
                un = 2.0 * u
            u = un
        if uhi < 0.0:  # no root within reach (a level falling faster than the inertia): explicit
            return d * u, Fu, kt, math.nan
        if d > 0.0:
            lo = ulo
            flo = gulo
            hi = uhi
            fhi = guhi
        else:
            lo = -uhi
            flo = -guhi
            hi = -ulo
            fhi = -gulo
        # first guess: the level at the free velocity, viscous term solved exactly (exact for
        # a Coulomb-viscous law or past the Stribeck range)
        if d > 0.0:
            x1 = (a - Gjj * lam * _g(par, o, abs(a))) / (1.0 + Gjj * par[o + 4])
        else:
            x1 = (a + Gjj * lam * _g(par, o + N_ROW, abs(a))) / (1.0 + Gjj * par[o + N_ROW + 4])
        if lo < x1 < hi:
            F1 = _static_force(par, o, x1, lam)
            f1 = x1 + Gjj * F1 - a
            if abs(f1) <= xtol:
                return x1, F1, kt, math.nan
            if f1 < 0.0:
                lo = x1
                flo = f1
            else:
                hi = x1
                fhi = f1
    else:
        x0 = xg if math.isfinite(xg) else a - Gjj * Fguess
        if math.isfinite(F0g):  # the caller evaluated the law at x0 already (run's inline first step)
            F0, z0e = F0g, z0g
        else:
            F0, z0e = _site_mean(kind, par, o, st, stw, so, s0, x0, h, lam, v0, dl)
        f0 = x0 + Gjj * F0 - a
        if abs(f0) <= xtol:
            return x0, F0, kt, z0e
        lo = -math.inf
        hi = math.inf
        flo = -1.0
        fhi = 1.0
        if f0 < 0.0:
            lo = x0
            flo = f0
        else:
            hi = x0
            fhi = f0
        slope = 1.0 + Gjj * kt
        if not slope >= 0.05:
            slope = 1.0
        x1 = x0 - f0 / slope
        n = 0
        while n < 80:
            F1, z1e = _site_mean(kind, par, o, st, stw, so, s0, x1, h, lam, v0, dl)
            f1 = x1 + Gjj * F1 - a
            n += 1
            if x1 != x0:
                kt_new = (F1 - F0) / (x1 - x0)
            else:
                kt_new = kt
            if abs(f1) <= xtol:
                return x1, F1, kt_new, z1e
            if f1 < 0.0:
                if x1 > lo:
                    lo = x1
                    flo = f1
            else:
                if x1 < hi:
                    hi = x1
                    fhi = f1
            if lo > -math.inf and hi < math.inf:
                break
            # not bracketed yet: secant (or Newton-like) step, growing if it stalls
            sl = (f1 - f0) / (x1 - x0) if x1 != x0 else slope
            if not sl >= 0.05:
                sl = slope
            x2 = x1 - f1 / sl
            if abs(x2 - x1) < abs(x1 - x0) and n > 4:
                x2 = x1 - 4.0 * (x1 - x0) if (x1 - x0) * f1 < 0.0 else x1 + 4.0 * (x1 - x0)
            x0 = x1
            f0 = f1
            F0 = F1
            x1 = x2
        if lo == -math.inf or hi == math.inf:
            return x1, (a - x1) / Gjj, kt, z1e
        # a secant step from the last two points if it lands inside the bracket
        if x1 != x0 and f1 != f0:
            x2 = x1 - f1 * (x1 - x0) / (f1 - f0)
            if lo < x2 < hi:
                F2, z2e = _site_mean(kind, par, o, st, stw, so, s0, x2, h, lam, v0, dl)
                f2 = x2 + Gjj * F2 - a
                if abs(f2) <= xtol:
                    return x2, F2, (F2 - F1) / (x2 - x1) if x2 != x1 else kt, z2e
                if f2 < 0.0:
                    lo = x2
                    flo = f2
                else:
                    hi = x2
                    fhi = f2
    # Illinois (modified regula falsi) on [lo, hi], flo < 0 < fhi
    side = 0
    x = lo
    zx = math.nan
    for _ in range(100):
        x = (lo * fhi - hi * flo) / (fhi - flo)
        if not (lo < x < hi):
            x = 0.5 * (lo + hi)
        if kind == S_STATIC:
            fx = x + Gjj * _static_force(par, o, x, lam) - a
        else:
            Fx, zx = _site_mean(kind, par, o, st, stw, so, s0, x, h, lam, v0, dl)
            fx = x + Gjj * Fx - a
        if fx == 0.0:
            break
        if fx < 0.0:
            lo = x
            flo = fx
            if side == -1:
                fhi *= 0.5
            side = -1
        else:
            hi = x
            fhi = fx
            if side == 1:
                flo *= 0.5
            side = 1
        if hi - lo <= xtol or abs(fx) <= 0.25 * xtol:
            break
    return x, (a - x) / Gjj, kt, zx


@njit(error_model="numpy")
def _loads(X, mvals, site_kind, site_po, site_so, par, st, Cq, Cm, s_off,
           ld_mode, ld_row, ld_mrow, ld_site, ld_par, lam):
    """Normal-load scales ``lam`` of the friction sites at state ``X`` (motions at ``mvals``).

    A site's friction laws are given at the reference load ``ld_par[j, 3]``; its load is
    ``max(N0 + a y, b y, 0)`` (mode 1; ``y`` the force of a spring/compliance) or the Hertz
    load of one contact set ``c (d0 + a d)_+^1.5`` (mode 2; ``d`` the compliance deflection).
    The law's state is load-normalised (``F = lam F(state)``), so when the load falls the
    force falls with it (contacts shrink, Mindlin); when it rises the new contact area carries
    no traction: the state is scaled by ``lam_old / lam_new`` so the force is kept.
    """
    n = X.size // 2
    for j in range(lam.size):
        mode = ld_mode[j]
        if mode == 0:
            continue
        y = 0.0
        for b in range(2 * n):
            y += ld_row[j, b] * X[b]
        for m in range(mvals.size):
            y += ld_mrow[j, m] * mvals[m]
        c = ld_site[j]
        N = 0.0
        if c >= 0:
            d = s_off[c]
            for b in range(n):
                d += Cq[c, b] * X[b]
            for m in range(mvals.size):
                d += Cm[c, m] * mvals[m]
            if mode == 1:
                y += _elastic(site_kind[c], par, site_po[c], d)
            else:
                a1 = par[site_po[c] + 1] + ld_par[j, 1] * d
                N = par[site_po[c]] * a1 * math.sqrt(a1) if a1 > 0.0 else 0.0
        if mode == 1:
            N = ld_par[j, 0] + ld_par[j, 1] * y
            if ld_par[j, 2] * y > N:
                N = ld_par[j, 2] * y
            if N < 0.0:
                N = 0.0
        new = N / ld_par[j, 3]
        old = lam[j]
        if new > old:
            f = old / new
            kind = site_kind[j]
            if kind == S_LUGRE:
                st[site_so[j]] *= f
            elif kind == S_GMS:
                for i in range(int(par[site_po[j] + 12])):
                    st[site_so[j] + i] *= f
        lam[j] = new


@njit(error_model="numpy")
def merge_maps(Phi, G0, G1, Gf, Cq, Cm, n_sub, o_rate):
    """Rows of the sample-spanning step (see ``machines.simulate._merge_maps``), over
    ``[X, w_start, w_end - w_start, F]``: ``R[i, j]`` site ``j``'s velocity at the end of
    sub-step ``i + 1`` with the site forces ``F`` held, ``M`` the state at the end of the
    sample. ``o_rate``: offset of the motion rates in ``w``. The recursion is the sub-step
    scheme's own: ``X_i = Phi X_(i-1) + G0 w_(i-1) + G1 (w_i - w_(i-1)) + Gf F``."""
    n2 = Phi.shape[0]
    n = n2 // 2
    nw = G0.shape[1]
    ns = Cq.shape[0]
    nmot = Cm.shape[1]
    L = n2 + 2 * nw + ns
    M = np.zeros((n2, L))
    T = np.zeros((n2, L))
    for r in range(n2):
        M[r, r] = 1.0
    R = np.zeros((n_sub, ns, L))
    for i in range(n_sub):
        for r in range(n2):  # T = Phi M + [0, G0, G0 i/n + G1/n, Gf]
            for c in range(L):
                y = 0.0
                for q in range(n2):
                    y += Phi[r, q] * M[q, c]
                T[r, c] = y
            for c in range(nw):
                T[r, n2 + c] += G0[r, c]
                T[r, n2 + nw + c] += G0[r, c] * (i / n_sub) + G1[r, c] / n_sub
            for c in range(ns):
                T[r, n2 + 2 * nw + c] += Gf[r, c]
        for j in range(ns):
            for c in range(L):
                y = 0.0
                for b in range(n):
                    y += Cq[j, b] * T[n + b, c]
                R[i, j, c] = y
            for m in range(nmot):
                R[i, j, n2 + o_rate + m] += Cm[j, m]
        for r in range(n2):
            for c in range(L):
                M[r, c] = T[r, c]
    return R, M


@njit(inline="always", error_model="numpy")
def _merged_step(k, kn, dt, n_sub, X, mot, inputs, u_now, act_foh, act_col, act_delay, act_lim,
                 Cq, Cm, par, site_po, RT, Mx, wA, wB, Fh, Xn, z, Fbar, V):
    """Advance ``X`` over the whole sample ``k`` in one map if every site keeps sliding one way.

    Every site is a flat static law (force ``+Fc+`` / ``-Fc-`` while sliding, viscous term in
    the chain). The site velocities at every sub-step end (rows ``R``) must keep their sign
    under the held forces (rows ``RT[j, :, i]``, sub-step ``i + 1``; ``V`` scratch of ``n_sub``):
    exactly the sub-step scheme's own decision to keep sliding, so the
    result is the sub-steps' to round-off. Returns False (``X``, ``Fbar`` untouched) when an
    input is not affine over the sample (a clipped FOH actuator), a site is at rest, or a site
    would stop or turn (the sub-steps then stick it exactly).
    """
    n2 = X.size
    n = n2 // 2
    nact = u_now.size
    nmot = mot.shape[1]
    nw = wA.size
    ns = Fh.size
    for i in range(nact):
        if act_foh[i]:
            d = act_delay[i]
            ua = inputs[k - d, act_col[i]] if k >= d else 0.0
            ub = inputs[kn - d, act_col[i]] if kn >= d else 0.0
            lim = act_lim[i]
            if not (-lim <= ua <= lim and -lim <= ub <= lim):
                return False
            wA[i] = ua
            wB[i] = ub
        else:
            wA[i] = u_now[i]
            wB[i] = u_now[i]
    for m in range(nmot):
        pa = mot[k, m]
        pb = mot[kn, m]
        wA[nact + m] = pa
        wB[nact + m] = pb
        wA[nact + nmot + m] = (pb - pa) / dt
        wB[nact + nmot + m] = (pb - pa) / dt
    # z = [X, w_start, w_end - w_start, F]: every map is a row over it
    L = z.size
    for r in range(n2):
        z[r] = X[r]
    for c in range(nw):
        z[n2 + c] = wA[c]
        z[n2 + nw + c] = wB[c] - wA[c]
    for j in range(ns):
        vj = 0.0
        for b in range(n):
            vj += Cq[j, b] * X[n + b]
        for m in range(nmot):
            vj += Cm[j, m] * wA[nact + nmot + m]
        if vj > 0.0:
            Fh[j] = par[site_po[j]]
        elif vj < 0.0:
            Fh[j] = -par[site_po[j] + N_ROW]
        else:
            return False  # at rest: the sub-steps decide (stick, or break away inside the sample)
        z[n2 + 2 * nw + j] = Fh[j]
    # every sub-step end's velocity of site j at once (``RT[j, c, i] = R[i, j, c]``): column by
    # column, each velocity summed in the same order as a row-by-row product (same numbers)
    for j in range(ns):
        for i in range(n_sub):
            V[i] = 0.0
        for c in range(L):
            zc = z[c]
            for i in range(n_sub):
                V[i] += RT[j, c, i] * zc
        fj = Fh[j]
        for i in range(n_sub):
            if not V[i] * fj > 0.0:
                return False
    for r in range(n2):
        y = 0.0
        for c in range(L):
            y += Mx[r, c] * z[c]
        Xn[r] = y
    for r in range(n2):
        X[r] = Xn[r]
    for j in range(ns):
        Fbar[j] = Fh[j]
    return True


@njit(error_model="numpy")
def _ramp_maps(Phi, Gf, Cq, n_sub):
    """``(GrT, Rss)``: the sample's response to a zero-mean force ramp ``dF (t / dt - 1/2)`` per
    site (a coarse step's linear force profile, see ``run``), as ``n_sub`` sub-steps hold it (at
    each sub-step's mid value ``(i + 1/2) / n_sub - 1/2``), transposed, and its site compliance
    ``Rss = -Cq GrT_q^T``. Zeros for ``n_sub = 0`` (no coarse steps)."""
    n2 = Phi.shape[0]
    n = n2 // 2
    ns = Cq.shape[0]
    GrT = np.zeros((ns, n2))
    Rss = np.zeros((ns, ns))
    Yr = np.zeros((n2, ns))
    Yn = np.zeros((n2, ns))
    for i in range(n_sub):
        ci = (i + 0.5) / n_sub - 0.5
        for r in range(n2):
            for c in range(ns):
                y = Gf[r, c] * ci
                for q in range(n2):
                    y += Phi[r, q] * Yr[q, c]
                Yn[r, c] = y
        for r in range(n2):
            for c in range(ns):
                Yr[r, c] = Yn[r, c]
    for j in range(ns):
        for r in range(n2):
            GrT[j, r] = Yr[r, j]
    for j in range(ns):
        for i in range(ns):
            for b in range(n):
                Rss[j, i] -= Cq[j, b] * Yr[b, i]
    return GrT, Rss


@njit(inline="always", error_model="numpy")
def _predict_profile(Xf, GfT, Fbar, Gss, mvals, Fk, site_kind, site_po, site_so, par, st, Cq, Cm, s_off,
                     ld_mode, ld_row, ld_mrow, ld_site, ld_par, lam, has_load, Xp, lamx, stx, dFp, dlam, X, w0, nact,
                     dt):
    """A coarse step's linear force profile (see ``run``): its end predicted at the sample's end
    state ``Xp`` = the free end ``Xf`` plus the last held forces ``Fbar`` (this sample's actuator
    commands included; motions at ``mvals``): a smooth compliance's force there (``dFp = f - F_k``),
    a loaded LuGre/Dahl site's load there (``dlam``; ``dFp`` its law's end minus start force
    under the load ramp, over the step to the predicted end, as a GMS site's), on scratch copies
    (``lamx``, ``stx``: :func:`_loads` rescales states). ``Fk``: the forces recorded at ``t_k``.

    A GMS site: its law's end force over the step from its start (``X``; motion positions and
    rates ``w0[nact:]``) to the predicted end, at the mean velocity (``dFp = F_end - F_start``;
    the elements' end states go to the scratch ``stx``).

    Inlined into ``run`` (numba IR, like :func:`_merged_step`): as a call, its 25 array arguments
    cost a reference-count update each on entry and exit once per coarse step (measured
    2026-11-24, same run, bit-identical: GMS-4 stage kernel 14.88 -> 13.58 ms CPU; cold compile
    unchanged within the load's noise)."""
    n2 = Xf.size
    n = n2 // 2
    ns = Fbar.size
    for r in range(n2):
        Xp[r] = Xf[r]
    for j in range(ns):
        fj = Fbar[j]
        for r in range(n2):
            Xp[r] += GfT[j, r] * fj
    if has_load:
        for j in range(ns):
            lamx[j] = lam[j]
        for r in range(st.size):
            stx[r] = st[r]
        _loads(Xp, mvals, site_kind, site_po, site_so, par, stx, Cq, Cm, s_off,
               ld_mode, ld_row, ld_mrow, ld_site, ld_par, lamx)
    for j in range(ns):
        dFp[j] = 0.0
        if Gss[j, j] <= 0.0:
            continue
        if SMOOTH[site_kind[j]]:
            se = s_off[j]
            for b in range(n):
                se += Cq[j, b] * Xp[b]
            for m in range(mvals.size):
                se += Cm[j, m] * mvals[m]
            dFp[j] = _elastic(site_kind[j], par, site_po[j], se) - Fk[j]
        elif site_kind[j] == S_GMS or (ld_mode[j] != 0 and site_kind[j] == S_LUGRE):
            # the law's own end force minus its start force over the step to the predicted end
            o = site_po[j]
            so = site_so[j]
            nmot = mvals.size
            sa = se = va = ve = 0.0
            for b in range(n):
                sa += Cq[j, b] * X[b]
                se += Cq[j, b] * Xp[b]
                va += Cq[j, b] * X[n + b]
                ve += Cq[j, b] * Xp[n + b]
            for m in range(nmot):
                sa += Cm[j, m] * w0[nact + m]
                se += Cm[j, m] * mvals[m]
                va += Cm[j, m] * w0[nact + nmot + m]
                # a prescribed motion is linear over the sample (its rate (p_k+1 - p_k) / dt, the
                # same in w0 and w1), so its rate at the step's end is its start rate: the end
                # velocity the step itself integrates and checks (its end check reads w1's rate)
                ve += Cm[j, m] * w0[nact + nmot + m]
            if site_kind[j] == S_GMS:
                M = int(par[o + 12])
                _gms_mean(par, o, st, so, se - sa, dt, stx, lam[j], va)
                fa = fe = 0.0
                for i in range(so, so + M):
                    fa += st[i]
                    fe += stx[i]
                dFp[j] = lam[j] * (fe - fa) + (par[o + 4] if ve >= 0.0 else par[o + N_ROW + 4]) * ve - (
                    par[o + 4] if va >= 0.0 else par[o + N_ROW + 4]) * va
            else:  # loaded LuGre/Dahl: under the load ramp to the load there (a rising load's force lags it)
                dlam[j] = lamx[j] - lam[j]
                stx[so] = _lugre_mean(par, o, st[so], se - sa, dt, lam[j], dlam[j])[1]
                dFp[j] = (_site_now(S_LUGRE, par, o, stx, so, se, ve, lamx[j])
                          - _site_now(S_LUGRE, par, o, st, so, sa, va, lam[j]))


@njit(inline="always", error_model="numpy")
def _quantise(x, q):
    if q > 0.0:
        return math.floor(x / q) * q
    return x


# --------------------------------------------------------------------------- main loop
# Compile time (issue 8; the ball-screw stage's first call, empty cache, CPU at load 8-11, 2026-11-23):
# 38-42 s at NUMBA_OPT=3, 29-30 s at NUMBA_OPT=0; of it LLVM 15 s and numba's front end (typing,
# rewrites, lowering to LLVM IR) 23-27 s, so a free LLVM would still leave the front end above 10 s
# (~14-16 s on a quiet machine): the target needs less code for numba to type, not another
# arrangement of it. ``run`` stays ONE function on purpose: numba keeps an NRT incref/decref pair
# per array argument of every call to a numba function, even when LLVM inlines it
# (``forceinline=True``). Measured: run_axis's controller blocks as two such calls made the EMPS
# fast path 1.5-2.3x slower (8 more incref and decref sites in its loop); ``run`` split into
# forceinline sections (record, sensors, blocks, actuators, PID integrators, _merged_step) was
# bit-identical but compiled no faster in total (38.9-42.0 s vs 36.3-39.7 s: each function's fixed
# cost ate the front end's saving) and ran the EMPS general loop 1.29x slower. (A forceinline
# function's callees also inherit forceinline unless they set it.)
@njit(error_model="numpy")
def run(
    n_sub, dt, Phi, G0, G1, Gf, Gss, Hss, Cq, Cm, s_off, s_visc, mg_on, mg_R, mg_M,
    site_kind, site_po, site_so, par, st, xtol,
    ld_mode, ld_row, ld_mrow, ld_site, ld_par,
    sch_mode, sch_row, sch_mrow,
    X, mot,
    act_sig, act_lim, act_delay, act_foh, act_applied_sig, act_col, inputs, in_sig,
    sen_row, sen_mrow, sen_qty, sen_res, sen_delay, sen_sig, noise,
    blk_code, blk_iptr, blk_idx, blk_fptr, blk_par, blk_sptr, blk_st,
    sig,
    q_out, v_out, F_out, sig_out, u_out, coarse=True,
):
    """Run ``N = q_out.shape[0]`` samples. ``X``, ``st``, ``sig``, ``blk_st`` are updated in place.

    ``s_visc[j]``: a static site's viscous coefficient, folded into the chain (``Phi ...``) by
    the wrapper; added to the recorded force. ``mg_on``: every site is a flat static law
    (``machines.simulate._merge_maps``): a sample in which every site keeps sliding one way
    at every sub-step end is advanced by the one map ``mg_M`` (rows over ``[X, w_start,
    w_end - w_start, F]``) after checking the site velocities ``mg_R`` at the sub-step ends;
    otherwise by the ``n_sub`` sub-steps (same result, to round-off).

    ``sch_mode[j]`` (0 none, 1 position, 2 velocity) gives a static site a schedule input
    ``s = sch_row[j] . q`` (or ``. q'``) ``+ sch_mrow[j] . p`` (motion positions, or their
    rates); its levels are set from ``s`` at the start of every sub-step (:func:`_set_levels`).

    Coarse steps (when no site is a static law and ``n_sub > 1``): each sample is first
    advanced in ONE step of ``dt`` by the same scheme, with the sample map of the sub-step maps
    (:func:`merge_maps`: exact for a held site force, as the sub-step maps are). The scheme's
    error comes from holding each site's mean force ``Fbar`` over a step; after the coarse step
    every site's force at its start and end is compared with it: ``|F - Fbar|`` times the
    site's effective compliance ``Gjj / (1 + Gjj kt)`` (``kt`` the law's secant slope, so a
    stiff site's own spring is counted) must stay within :data:`COARSE_PTOL` at both ends, and
    the site's velocity must keep one sign over the step (start, mean and end: a motion turning
    inside the step is seen by the law as one mean velocity).

    Linear force profile (2026-11-23): a site whose force changes smoothly over the sample is
    advanced with the profile ``Fbar + dF (t / dt - 1/2)`` instead of the held ``Fbar`` (the
    zero-mean ramp's response ``GrTC``/``RssC``, composed from the sub-step maps as the
    sub-steps would hold it), and its error bound compares the force at the step's start and
    end with the profile's ends ``Fbar -+ dF / 2`` (``dF = 0``: the held bound above). The
    profile's end is predicted at the sample's end state advanced with the last held forces
    (so this sample's actuator commands count): for a memoryless smooth compliance
    (:data:`SMOOTH`: Hertz, sine) ``dF = f(s_end) - F_k``; a LuGre/Dahl site with a normal load
    instead gets the load's ramp: its load scale is taken linear in time from ``lam_k`` to the
    load there, the law integrates it exactly (:func:`_lugre_mean` with ``dl``),
    ``dF`` is the law's end force minus its start force under that ramp (2026-11-24; it was
    ``F_k dl / lam``, a force that follows its load at once), and the bound adds the mean force's
    error from the predicted end load, ``|lam_end - lam_pred| |Fbar| / (2 lam_mid)``.
    (Extrapolating ``dF`` and the load from the recorded samples instead kept 0 % with quantised
    sensors: the commands jump.)
    Why the bound holds: the error of the step is the chain's response to the law's force minus
    the profile; both have the same mean (the law's ``Fbar``), so for a deviation quadratic in
    time (a force smooth over the step) its largest value is at an end, and the bound is that
    value times the site's compliance, as for the held force. Piecewise-linear springs and
    unloaded LuGre/Dahl sites keep the held force (a kink or a bristle ringing inside the step
    breaks the quadratic assumption; see :data:`SMOOTH`). Measured: the flank and Hertz
    ball-screw stages kept 1 % of their samples as coarse steps before (their flank sites'
    loads follow the drive force, 1.3e-11 m median deviation from a held force), 59 % with it
    (ideal sensors; errors against 640 sub-steps unchanged: 0.274 / 0.281 nm without, 0.274 /
    0.280 with). With the paper's quantised sensors and noise 7-10 %: each sample's command
    jump rings the motor coupling, the flank loads follow it inside the sample, and the bound
    (rightly) rejects those steps. The flank profile's start was off: under a rising load a
    Dahl force lags the load (the new contact carries no traction; ``y' = lam v - r y``: flat at
    first, its mean ``Fc dl q`` below the load's line, ``q = (1 - frac) / x`` of
    :func:`_lugre_mean`: 0.2-0.5 of the load's change at the stage's 1-3 relaxations per
    sample), so ``dF = F_k dl / lam`` failed the start bound by that much where the law's own
    end-minus-start passes (residual ``Fc dl |frac / 2 - q|``, <= 0.07 of the change). Measured
    2026-11-24 (flk; same run against abc898a, the benchmark's workloads: paper sensors, 5 s):
    one-step samples flank 10.7 -> 53 %, Hertz 5.1 -> 38 %; kernel CPU 67.9 -> 45.5 ms, 89.2
    -> 69.4 ms; ideal sensors, 1 s, table error against 640 sub-steps 0.274 -> 0.269 nm (flank),
    0.280 -> 0.275 nm (Hertz) with 59 -> 93 % one-step samples.

    GMS sites (2026-11-24) take the profile too, predicted by the law itself: ``dF`` is the
    law's end force minus its start force over the step from the sample's start to the
    predicted end (:func:`_predict_profile`). While every element keeps its mode (sticking
    elements follow the site's quadratic path ``F_i + k_i x(t)``, slipping ones relax
    exponentially) the force is smooth over the step; a step in which an element breaks away
    or sticks (a kink) is rejected (without that check the "gms_slider" parity case's force
    error stopped falling with the sub-step: 1.07e-4, 2.07e-4, 2.04e-4 N at 10, 20, 40). Held,
    a GMS site's force failed the bound wherever the motion accelerates (its viscous term, its
    slipping elements' Stribeck targets) or sticks (the pre-sliding stroke): the ball screw with
    GMS-4 at nut and guide kept 88 % of its samples as coarse steps (the rest: ~50 ms after each
    reversal), the two-shaft drive 93 % (its start and the table's reversals: 40 % of its kernel
    time at 10 sub-steps, ~75 % in the hunting check's rerun at 40). With the profile: 97 % and
    99 % (measured 2026-11-24; errors against 640 sub-steps without coarse steps, ideal sensors,
    2 s: the GMS-4 stage 1.005 nm table and 1.865e-7 rad motor with and without coarse steps,
    as held; the two-shaft drive's screw 1.93e-6 rad, 1.98e-6 held, 1.76e-6 without).

    Otherwise the sample is restored
    (state, site states, forces, loads) and run again in the ``n_sub`` sub-steps; after a
    rejected sample the next sample tries again (up to :data:`COARSE_RETRIES` times in a
    row), then the next try waits 2, 4, ... up to 32 samples (doubling
    while they are rejected; a transient lasts several samples, and a machine whose sites never
    qualify pays ~1/32 of a coarse step per sample). ``coarse=False`` turns them off.

    Returns ``(status, k_end, n_unconverged, n_one_step, n_sweeps)``: samples ``k >= k_end`` are
    left untouched; ``n_one_step`` counts the samples advanced in one step of ``dt`` (a kept coarse
    step or a sample-spanning step), the rest ran in the ``n_sub`` sub-steps; ``n_sweeps`` the
    Gauss-Seidel sweeps over the sites (every step, coarse or sub-step: a work count).
    """
    n2 = X.size
    n = n2 // 2
    ns = Cq.shape[0]
    nw = G0.shape[1]
    nact = act_sig.size
    nmot = mot.shape[1]
    nsen = sen_sig.size
    nin = in_sig.size
    nb = blk_code.size
    N = q_out.shape[0]
    h = dt / n_sub
    # the coarse steps' error bound tightens with the sub-steps asked for (never loosens below
    # COARSE_PTOL_SUBSTEPS): a run at 4x the sub-steps is 4x as strict in its coarse steps too,
    # and in its site solves (SITE_XTOL)
    xscale = min(1.0, COARSE_PTOL_SUBSTEPS / n_sub)
    ptol = COARSE_PTOL * xscale

    # transposed copies of the sub-step maps (the state update runs column by column)
    PhiT = np.ascontiguousarray(Phi.T)
    G0T = np.ascontiguousarray(G0.T)
    G1T = np.ascontiguousarray(G1.T)
    GfT = np.ascontiguousarray(Gf.T)
    # coarse steps: the sample's map from the sub-step maps (rows over [X, w0, w1 - w0, F])
    n_c = 0
    if coarse and n_sub > 1:
        n_c = 1
        for j in range(ns):
            if site_kind[j] == S_STATIC:
                n_c = 0
    _, Ms = merge_maps(Phi, G0, G1, Gf, Cq, Cm, n_sub if n_c else 1, G0.shape[1] - nmot)
    PhiTC = np.ascontiguousarray(Ms[:, :n2].T)
    G0TC = np.ascontiguousarray(Ms[:, n2:n2 + nw].T)
    G1TC = np.ascontiguousarray(Ms[:, n2 + nw:n2 + 2 * nw].T)
    GfTC = np.ascontiguousarray(Ms[:, n2 + 2 * nw:].T)
    GssC = np.zeros((ns, ns))  # site compliances over the sample, as Gss / Hss over a sub-step
    HssC = np.zeros((ns, ns))
    for j in range(ns):
        for i in range(ns):
            for b in range(n):
                GssC[j, i] -= Cq[j, b] * GfTC[i, b]
                HssC[j, i] -= Cq[j, b] * GfTC[i, n + b]
    # the sample's response to a zero-mean force ramp ``dF (t / dt - 1/2)`` per site (coarse
    # steps' linear force profile), as the sub-step scheme applies it: held at each sub-step's
    # mid value ``(i + 1/2) / n_sub - 1/2``; ``GrTC`` transposed, ``RssC`` its site compliance
    GrTC, RssC = _ramp_maps(Phi, Gf, Cq, n_sub if n_c else 0)
    dFp = np.zeros(ns)  # a coarse step's predicted force change over the sample, per site
    dlam = np.zeros(ns)  # ... and its predicted load change (LuGre/Dahl sites; 0 in sub-steps)
    lpred = np.zeros(ns)  # the predicted load at a coarse step's end
    Xp = np.zeros(n2)  # a coarse step's predicted end state (last held forces)
    lamx = np.zeros(ns)  # ... its loads, and scratch site states for them
    stx = np.zeros(st.size)
    n_prof = 0  # sites that take a linear force profile in coarse steps
    for j in range(ns):
        if SMOOTH[site_kind[j]] or site_kind[j] == S_GMS or (ld_mode[j] != 0 and site_kind[j] == S_LUGRE):
            n_prof += 1
    Xs = np.empty(n2)  # a sample's start, restored when its coarse steps are rejected
    sts = np.empty(st.size)
    Fbs = np.empty(ns)
    kts = np.empty(ns)
    lams = np.empty(ns)
    dev = np.zeros(ns)
    k_try = 0  # the next sample to try a coarse step at, and the back-off after a rejection
    gap = 1
    # rejected coarse tries in a row (COARSE_RETRIES); in an array, not a scalar: one more
    # variable carried through the sample loop made its machine code slower everywhere (measured
    # 2026-11-24, same run, with the retries switched off: Dahl sliding stage 6.5 -> 8.1 ms)
    n_fail = np.zeros(1, dtype=np.int64)
    Fbar = np.zeros(ns)
    Fprev = np.zeros(ns)  # the sub-step mean before the last (sub-step force extrapolation)
    n_run = 0  # consecutive sub-steps taken (of size h) up to the current one
    ds = np.zeros(ns)
    a = np.zeros(ns)
    s0 = np.zeros(ns)
    v0s = np.zeros(ns)  # site velocities at the start of the sub-step
    Xf = np.empty(n2)
    w0 = np.zeros(nw)
    w1 = np.zeros(nw)
    dw = np.zeros(nw)
    u_now = np.zeros(nact)
    sat = np.zeros(nact, dtype=np.bool_)
    # delay lines: actuators and sensors, ring buffers of length delay
    maxd_a = 0
    for i in range(nact):
        if act_delay[i] > maxd_a:
            maxd_a = act_delay[i]
    abuf = np.zeros((nact, maxd_a + 1))
    maxd_s = 0
    for i in range(nsen):
        if sen_delay[i] > maxd_s:
            maxd_s = sen_delay[i]
    sbuf = np.zeros((nsen, maxd_s + 1))
    n_bad = 0
    n_one = 0
    n_sw = 0
    lam = np.ones(ns)
    has_sched = False
    for j in range(ns):
        if sch_mode[j] != 0:
            has_sched = True
    # np.bool_, not a literal False: a literal types the call of _predict_profile first with
    # Literal[bool](False), then again with bool once the loop below unifies it (two compiles)
    has_load = np.bool_(False)
    for j in range(ns):
        if ld_mode[j] != 0:
            has_load = True
    stw = np.zeros(st.size)  # scratch: GMS element states of a site's last evaluation
    zend = np.zeros(ns)  # LuGre end state of the converged solve (GMS: 1.0, states in stw)
    aused = np.zeros(ns)  # a site's input at its last solve in this sub-step, and its tolerance
    tused = np.zeros(ns)
    kt = np.zeros(ns)  # last secant slope dFbar/dds per site (first guess of the next solve)
    for j in range(ns):
        if ld_mode[j] != 0:
            lam[j] = 0.0  # contacts start without traction; set from the state below
    _loads(X, mot[0], site_kind, site_po, site_so, par, st, Cq, Cm, s_off,
           ld_mode, ld_row, ld_mrow, ld_site, ld_par, lam)

    # memoryless sites start at their static force
    for j in range(ns):
        kind = site_kind[j]
        if kind >= S_HERTZ:
            sj = s_off[j]
            for b in range(n):
                sj += Cq[j, b] * X[b]
            for m in range(nmot):
                sj += Cm[j, m] * mot[0, m]
            Fbar[j] = _elastic(kind, par, site_po[j], sj)

    mv = np.zeros(nmot)
    wA = np.zeros(nw)
    wB = np.zeros(nw)
    Fh = np.zeros(ns)
    Xn = np.zeros(n2)
    zm = np.zeros(n2 + 2 * nw + ns)
    # the sample-spanning step's velocity rows, site-major and sub-step last (see _merged_step)
    mg_RT = np.empty((mg_R.shape[1], mg_R.shape[2], mg_R.shape[0]))
    for i in range(mg_R.shape[0]):
        for j in range(mg_R.shape[1]):
            for c in range(mg_R.shape[2]):
                mg_RT[j, c, i] = mg_R[i, j, c]
    Vm = np.zeros(mg_R.shape[0])
    for k in range(N):
        kn = k + 1 if k + 1 < N else k
        # the rate of a prescribed motion at t_k (it is piecewise linear, so its rate jumps at
        # the samples): the arriving one, over [t_k-1, t_k]; at t_0 the first interval's
        ka = k - 1 if k > 0 else 0
        kb = ka + 1 if ka + 1 < N else ka
        if k > 0 and has_load:
            _loads(X, mot[k], site_kind, site_po, site_so, par, st, Cq, Cm, s_off,
                   ld_mode, ld_row, ld_mrow, ld_site, ld_par, lam)
        # ---- record the state at t_k
        for b in range(n):
            q_out[k, b] = X[b]
            v_out[k, b] = X[n + b]
        for j in range(ns):
            kind = site_kind[j]
            if kind == S_STATIC:
                F_out[k, j] = Fbar[j]
                if s_visc[j] != 0.0:
                    vj = 0.0
                    for b in range(n):
                        vj += Cq[j, b] * X[n + b]
                    for m in range(nmot):
                        vj += Cm[j, m] * (mot[kb, m] - mot[ka, m]) / dt
                    F_out[k, j] += s_visc[j] * vj
                continue
            sj = s_off[j]
            vj = 0.0
            for b in range(n):
                sj += Cq[j, b] * X[b]
                vj += Cq[j, b] * X[n + b]
            for m in range(nmot):
                sj += Cm[j, m] * mot[k, m]
                vj += Cm[j, m] * (mot[kb, m] - mot[ka, m]) / dt
            F_out[k, j] = _site_now(kind, par, site_po[j], st, site_so[j], sj, vj, lam[j])
        # ---- inputs and sensors
        for i in range(nin):
            sig[in_sig[i]] = inputs[k, i]
        for i in range(nsen):
            y = 0.0
            off = n if sen_qty[i] == 1 else 0
            for b in range(n):
                y += sen_row[i, b] * X[off + b]
            for m in range(nmot):
                if sen_qty[i] == 1:
                    y += sen_mrow[i, m] * (mot[kb, m] - mot[ka, m]) / dt
                else:
                    y += sen_mrow[i, m] * mot[k, m]
            y = _quantise(y + noise[k, i], sen_res[i])
            d = sen_delay[i]
            if d > 0:
                slot = k % d
                out = sbuf[i, slot] if k >= d else 0.0
                sbuf[i, slot] = y
                y = out
            sig[sen_sig[i]] = y
        # ---- blocks
        for bi in range(nb):
            code = blk_code[bi]
            ip = blk_iptr[bi]
            fp = blk_fptr[bi]
            sp = blk_sptr[bi]
            if code == B_LINEAR:  # idx: out, nin, in...; par: bias, w...
                nin_b = blk_idx[ip + 1]
                y = blk_par[fp]
                for r in range(nin_b):
                    y += blk_par[fp + 1 + r] * sig[blk_idx[ip + 2 + r]]
                sig[blk_idx[ip]] = y
            elif code == B_PID:  # idx: out, e, ed, act; par: Kp Ki Kd tau_d T; st: integ, dterm, ed_prev, started
                e = sig[blk_idx[ip + 1]]
                ed = sig[blk_idx[ip + 2]]
                Kp = blk_par[fp]
                Kd = blk_par[fp + 2]
                taud = blk_par[fp + 3]
                T = blk_par[fp + 4]
                if blk_st[sp + 3] == 0.0:
                    blk_st[sp + 2] = ed
                    blk_st[sp + 3] = 1.0
                blk_st[sp + 1] = (taud * blk_st[sp + 1] + Kd * (ed - blk_st[sp + 2])) / (taud + T)
                blk_st[sp + 2] = ed
                sig[blk_idx[ip]] = Kp * e + blk_st[sp] + blk_st[sp + 1]
            elif code == B_SS:  # idx: nin, nout, in..., out...; par: nx, A, B, C, D
                nu = blk_idx[ip]
                ny = blk_idx[ip + 1]
                nx = int(blk_par[fp])
                pA = fp + 1
                pB = pA + nx * nx
                pC = pB + nx * nu
                pD = pC + ny * nx
                for r in range(ny):
                    y = 0.0
                    for c in range(nx):
                        y += blk_par[pC + r * nx + c] * blk_st[sp + c]
                    for c in range(nu):
                        y += blk_par[pD + r * nu + c] * sig[blk_idx[ip + 2 + c]]
                    sig[blk_idx[ip + 2 + nu + r]] = y
                # state update x+ = A x + B u (scratch after the states)
                for r in range(nx):
                    y = 0.0
                    for c in range(nx):
                        y += blk_par[pA + r * nx + c] * blk_st[sp + c]
                    for c in range(nu):
                        y += blk_par[pB + r * nu + c] * sig[blk_idx[ip + 2 + c]]
                    blk_st[sp + nx + r] = y
                for r in range(nx):
                    blk_st[sp + r] = blk_st[sp + nx + r]
            elif code == B_SAT:  # idx: out, in; par: lo, hi
                y = sig[blk_idx[ip + 1]]
                if y > blk_par[fp + 1]:
                    y = blk_par[fp + 1]
                elif y < blk_par[fp]:
                    y = blk_par[fp]
                sig[blk_idx[ip]] = y
            else:  # B_FFF: idx: out, in, schedule (-1: none); par: scale, static law (N_STATIC_SITE)
                if blk_idx[ip + 2] >= 0:
                    _set_levels(blk_par, fp + 1, sig[blk_idx[ip + 2]])
                sig[blk_idx[ip]] = blk_par[fp] * _static_force(blk_par, fp + 1, sig[blk_idx[ip + 1]], 1.0)
        # ---- actuators
        for i in range(nact):
            if act_foh[i]:
                u = inputs[k, act_col[i]]
            else:
                u = sig[act_sig[i]]
            sat[i] = False
            if u > act_lim[i]:
                u = act_lim[i]
                sat[i] = True
            elif u < -act_lim[i]:
                u = -act_lim[i]
                sat[i] = True
            d = act_delay[i]
            if d > 0:
                slot = k % d
                out = abuf[i, slot] if k >= d else 0.0
                abuf[i, slot] = u
                u = out
            u_now[i] = u
            u_out[k, i] = u
            if act_applied_sig[i] >= 0:
                sig[act_applied_sig[i]] = u
        # ---- PID integrators (conditional integration)
        for bi in range(nb):
            if blk_code[bi] == B_PID:
                ip = blk_iptr[bi]
                ai = blk_idx[ip + 3]
                if ai < 0 or not sat[ai]:
                    blk_st[blk_sptr[bi]] += blk_par[blk_fptr[bi] + 1] * blk_par[blk_fptr[bi] + 4] * sig[blk_idx[ip + 1]]
        for r in range(sig.size):
            sig_out[k, r] = sig[r]
        if k == N - 1:
            break
        # ---- plant: one sample-spanning step when every (flat static) site keeps sliding
        if mg_on and _merged_step(k, kn, dt, n_sub, X, mot, inputs, u_now, act_foh, act_col, act_delay, act_lim,
                                  Cq, Cm, par, site_po, mg_RT, mg_M, wA, wB, Fh, Xn, zm, Fbar, Vm):
            n_one += 1
            for r in range(n2):
                if not math.isfinite(X[r]):
                    return STATUS_NONFINITE, k + 1, n_bad, n_one, n_sw
            continue
        # ---- plant: first one coarse step of dt (maps *C), kept when every site's force stayed
        # within the error bound of its held mean (see "Coarse steps" above); else the sample
        # again from its start in n_sub sub-steps
        try_c = n_c > 0 and k >= k_try
        if try_c:
            for r in range(n2):
                Xs[r] = X[r]
            for r in range(st.size):
                sts[r] = st[r]
            for j in range(ns):
                Fbs[j] = Fbar[j]
                kts[j] = kt[j]
                lams[j] = lam[j]
        # the attempt counter starts at a run-time value, so the compiler cannot unroll this loop
        # into two copies of the whole sub-step body (an unrolled range(2) doubled the code: the
        # compile time, and the sub-step path of machines that never keep a coarse step ran slower)
        attempt = 0 if try_c else 1
        while attempt < 2:
            coarse_now = attempt == 0
            attempt += 1
            if coarse_now:
                nsa, ha, PhiTa, G0Ta, G1Ta, GfTa, Gssa, Hssa = 1, dt, PhiTC, G0TC, G1TC, GfTC, GssC, HssC
            else:
                nsa, ha, PhiTa, G0Ta, G1Ta, GfTa, Gssa, Hssa = n_sub, h, PhiT, G0T, G1T, GfT, Gss, Hss
            ok = True
            for sub in range(nsa):
                f0 = sub / nsa
                f1 = (sub + 1) / nsa
                if sub > 0 and has_load:
                    for m in range(nmot):
                        mv[m] = mot[k, m] + (mot[kn, m] - mot[k, m]) * f0
                    _loads(X, mv, site_kind, site_po, site_so, par, st, Cq, Cm, s_off,
                           ld_mode, ld_row, ld_mrow, ld_site, ld_par, lam)
                for i in range(nact):
                    if act_foh[i]:  # the input array, delayed by whole samples, linear in between
                        d = act_delay[i]
                        ua = inputs[k - d, act_col[i]] if k >= d else 0.0
                        ub = inputs[kn - d, act_col[i]] if kn >= d else 0.0
                        va = ua + (ub - ua) * f0
                        vb = ua + (ub - ua) * f1
                        lim = act_lim[i]
                        va = min(max(va, -lim), lim)
                        vb = min(max(vb, -lim), lim)
                        w0[i] = va
                        w1[i] = vb
                    else:
                        w0[i] = u_now[i]
                        w1[i] = u_now[i]
                for m in range(nmot):
                    pa = mot[k, m]
                    pb = mot[kn, m]
                    w0[nact + m] = pa + (pb - pa) * f0
                    w1[nact + m] = pa + (pb - pa) * f1
                    w0[nact + nmot + m] = (pb - pa) / dt
                    w1[nact + nmot + m] = (pb - pa) / dt
                for c in range(nw):
                    dw[c] = w1[c] - w0[c]
                # Xf = Phi X + G0 w0 + G1 dw, column by column over the transposed matrices: each
                # row sums its terms in the same order as a row-by-row product (same numbers), but
                # the rows are independent lanes (vectorised, no chain of dependent additions)
                for r in range(n2):
                    Xf[r] = 0.0
                for c in range(n2):
                    xc = X[c]
                    for r in range(n2):
                        Xf[r] += PhiTa[c, r] * xc
                for c in range(nw):
                    wc = w0[c]
                    dc = dw[c]
                    for r in range(n2):
                        Xf[r] += G0Ta[c, r] * wc + G1Ta[c, r] * dc
                if coarse_now and n_prof:
                    _predict_profile(Xf, GfTa, Fbar, Gss, mot[kn], F_out[k], site_kind, site_po, site_so, par, st,
                                     Cq, Cm, s_off, ld_mode, ld_row, ld_mrow, ld_site, ld_par, lam, has_load,
                                     Xp, lamx, stx, dFp, dlam, X, w0, nact, dt)
                if has_sched:
                    for j in range(ns):
                        if sch_mode[j] != 0:
                            sv = 0.0
                            off = n if sch_mode[j] == 2 else 0
                            for b in range(n):
                                sv += sch_row[j, b] * X[off + b]
                            for m in range(nmot):
                                if sch_mode[j] == 2:
                                    sv += sch_mrow[j, m] * w0[nact + nmot + m]
                                else:
                                    sv += sch_mrow[j, m] * w0[nact + m]
                            _set_levels(par, site_po[j], sv)
                if ns > 0:
                    for j in range(ns):
                        aj = 0.0
                        sj = s_off[j]
                        if site_kind[j] == S_STATIC:  # free end velocity of the site
                            for b in range(n):
                                aj += Cq[j, b] * Xf[n + b]
                            for m in range(nmot):
                                aj += Cm[j, m] * w1[nact + nmot + m]
                        else:  # free displacement over the sub-step
                            for b in range(n):
                                aj += Cq[j, b] * (Xf[b] - X[b])
                            for m in range(nmot):
                                aj += Cm[j, m] * (w1[nact + m] - w0[nact + m])
                        vj = 0.0
                        for b in range(n):
                            sj += Cq[j, b] * X[b]
                            vj += Cq[j, b] * X[n + b]
                        for m in range(nmot):
                            sj += Cm[j, m] * w0[nact + m]
                            vj += Cm[j, m] * w0[nact + nmot + m]
                        if coarse_now:  # the ramp part of the linear force profile
                            for i in range(ns):
                                aj -= RssC[j, i] * dFp[i]
                        a[j] = aj
                        s0[j] = sj
                        v0s[j] = vj
                    if coarse_now:
                        # first guesses of the held forces (only the sweeps' starting point: their
                        # converged forces do not depend on it): the force recorded at t_k plus half
                        # the profile's predicted change, else extrapolated linearly through the last
                        # mean (~t_k - dt/2). With the last means as guesses the first sweep's inputs
                        # were off by a sample's change of the forces: measured 2026-11-24 (same run
                        # against f22475c, kernel CPU): two-shaft 2.94 -> 2.03 sweeps, 13.7 -> 10.9 law
                        # evaluations a sample, 27.4 -> 26.1 ms; Dahl sliding stage 7.7 -> 7.0 ms
                        for j in range(ns):
                            if dFp[j] != 0.0:
                                Fbar[j] = F_out[k, j] + 0.5 * dFp[j]
                            else:
                                Fbar[j] = 2.0 * F_out[k, j] - Fbar[j]
                        n_run = 0
                    else:
                        # a sub-step: extrapolated linearly through the last two sub-steps' means once
                        # two of this size ran in a row (measured 2026-11-24, same run: the two-shaft
                        # drive without coarse steps 2.01 -> 1.33 sweeps a sub-step; kernel CPU flank
                        # stage -5.6 %, Hertz -2.5 %, the two-shaft run with its loop check's rerun
                        # -5 to -10 %)
                        if n_run >= 2:
                            for j in range(ns):
                                fl = Fbar[j]
                                Fbar[j] = 2.0 * fl - Fprev[j]
                                Fprev[j] = fl
                        else:
                            for j in range(ns):
                                Fprev[j] = Fbar[j]
                        n_run += 1
                    # Gauss-Seidel over the sites, lazily: a site is solved again only when the
                    # other sites' forces have moved its input ``aj`` by more than its tolerance since
                    # its last solve, and the sweeps end when no input has (every site's equation then
                    # holds to its tolerance with the final forces)
                    for sweep in range(60):
                        n_sw += 1
                        for j in range(ns):
                            aj = a[j]
                            if site_kind[j] == S_STATIC:
                                for i in range(ns):
                                    if i != j:
                                        aj -= Hssa[j, i] * Fbar[i]
                                Gjj = Hssa[j, j]
                            else:
                                for i in range(ns):
                                    if i != j:
                                        aj -= Gssa[j, i] * Fbar[i]
                                Gjj = Gssa[j, j]
                            if sweep > 0 and abs(aj - aused[j]) <= tused[j]:
                                continue
                            tj = xscale * xtol[j] + 1e-13 * abs(aj)
                            xg = math.nan
                            if sweep > 0:  # same law and state, only aj moved: a Newton step from the last root
                                slope = 1.0 + Gjj * kt[j]
                                if slope >= 0.05:
                                    xg = ds[j] + (aj - aused[j]) / slope
                            done_j = False
                            F0 = z0e = math.nan
                            if (site_kind[j] == S_LUGRE or site_kind[j] == S_GMS) and Gjj > 0.0:
                                # _solve_site's first step inline, same numbers: one call instead of
                                # three nested ones (each array argument of a call costs a reference-
                                # count update on entry and exit: _lugre_mean takes one array,
                                # _solve_site and _site_mean three). Most LuGre/Dahl and GMS solves end
                                # here (measured 2026-11-24: flank stage 1.20x kernel CPU with LuGre's)
                                x0 = xg if math.isfinite(xg) else aj - Gjj * Fbar[j]
                                if site_kind[j] == S_LUGRE:
                                    F0, z0e = _lugre_mean(par, site_po[j], st[site_so[j]], x0, ha, lam[j], dlam[j])
                                else:  # element states to stw, as _site_mean (z0e = 1.0 says so)
                                    F0 = _gms_mean(par, site_po[j], st, site_so[j], x0, ha, stw, lam[j], v0s[j])
                                    z0e = 1.0
                                if abs(x0 + Gjj * F0 - aj) <= tj:
                                    dsj, Fj, ktj, zj = x0, F0, kt[j], z0e
                                    done_j = True
                            if not done_j:
                                dsj, Fj, ktj, zj = _solve_site(site_kind[j], par, site_po[j], st, stw, site_so[j], s0[j],
                                                               aj, Gjj, ha, Fbar[j], tj, lam[j], kt[j], v0s[j], xg,
                                                               dlam[j], F0, z0e)
                            kt[j] = ktj
                            zend[j] = zj
                            aused[j] = aj
                            tused[j] = tj
                            Fbar[j] = Fj
                            ds[j] = dsj
                        if ns == 1:
                            break
                        done = True
                        for j in range(ns):
                            aj = a[j]
                            if site_kind[j] == S_STATIC:
                                for i in range(ns):
                                    if i != j:
                                        aj -= Hssa[j, i] * Fbar[i]
                            else:
                                for i in range(ns):
                                    if i != j:
                                        aj -= Gssa[j, i] * Fbar[i]
                            if abs(aj - aused[j]) > tused[j]:
                                done = False
                                break
                        if done:
                            break
                        if sweep == 59:
                            if coarse_now:
                                ok = False
                            else:
                                n_bad += 1
                    if coarse_now:  # the held mean against the site's force at the step's start ...
                        for j in range(ns):
                            Gjj = Gssa[j, j]
                            if Gjj > 0.0:
                                if nmot == 0:  # the force recorded at t_k: same state, velocity and load
                                    Fs_j = F_out[k, j]
                                else:  # a motion's rate here is the departing one, the record's the arriving one
                                    Fs_j = _site_now(site_kind[j], par, site_po[j], sts, site_so[j], s0[j], v0s[j],
                                                     lams[j])
                                dev[j] = abs(Fs_j - (Fbar[j] - 0.5 * dFp[j])) * Gjj / (1.0 + Gjj * max(kt[j], 0.0))
                    for j in range(ns):  # commit the states (static and memoryless sites have none)
                        if site_kind[j] == S_LUGRE:
                            if math.isfinite(zend[j]):
                                st[site_so[j]] = zend[j]
                            else:
                                st[site_so[j]] = _lugre_mean(par, site_po[j], st[site_so[j]], ds[j], ha, lam[j], dlam[j])[1]
                        elif site_kind[j] == S_GMS:
                            so_j = site_so[j]
                            if zend[j] == 1.0:  # the last evaluation was at ds[j]: its states are in stw
                                for i in range(2 * int(par[site_po[j] + 12])):
                                    st[so_j + i] = stw[so_j + i]
                            else:
                                _gms_mean(par, site_po[j], st, so_j, ds[j], ha, st, lam[j], v0s[j])
                for r in range(n2):
                    X[r] = Xf[r]
                for j in range(ns):
                    fj = Fbar[j]
                    for r in range(n2):
                        X[r] += GfTa[j, r] * fj
                if coarse_now:
                    for j in range(ns):
                        fj = dFp[j]
                        if fj != 0.0:
                            for r in range(n2):
                                X[r] += GrTC[j, r] * fj
                if coarse_now:  # ... and at its end, with the normal loads of the end state
                    if has_load:
                        for j in range(ns):  # the end states are normalised by the predicted end loads
                            lam[j] += dlam[j]
                            lpred[j] = lam[j]
                        _loads(X, mot[kn], site_kind, site_po, site_so, par, st, Cq, Cm, s_off,
                               ld_mode, ld_row, ld_mrow, ld_site, ld_par, lam)
                    for j in range(ns):
                        Gjj = Gssa[j, j]
                        if Gjj <= 0.0:
                            continue
                        vj = 0.0
                        for b in range(n):
                            vj += Cq[j, b] * X[n + b]
                        for m in range(nmot):
                            vj += Cm[j, m] * w1[nact + nmot + m]
                        Fe_j = _site_now(site_kind[j], par, site_po[j], st, site_so[j], s0[j] + ds[j], vj, lam[j])
                        dF_j = abs(Fe_j - (Fbar[j] + 0.5 * dFp[j]))
                        lmid = lams[j] + 0.5 * dlam[j]
                        if has_load and lmid > 0.0:  # the mean's error from the load's predicted end
                            dF_j += 0.5 * abs(lam[j] - lpred[j]) * abs(Fbar[j]) / lmid
                        e_j = dF_j * Gjj / (1.0 + Gjj * max(kt[j], 0.0))
                        if not (dev[j] <= ptol and e_j <= ptol):  # NaN rejects too
                            ok = False
                        if site_kind[j] == S_GMS:  # an element broke away or stuck: a kink in its force
                            so_j = site_so[j]
                            Mj = int(par[site_po[j] + 12])
                            for i in range(so_j + Mj, so_j + 2 * Mj):
                                if st[i] != sts[i]:
                                    ok = False
                        # a site whose motion turns inside the step: the law saw one mean velocity
                        # there, so its ends can agree with the mean while the force dipped between
                        v0j = v0s[j]
                        if not ((v0j * vj > 0.0 and v0j * ds[j] > 0.0) or (v0j == 0.0 and vj == 0.0 and ds[j] == 0.0)):
                            ok = False
                    if not ok:
                        break
            if coarse_now:
                for j in range(ns):
                    dlam[j] = 0.0
                if ok:
                    gap = 1
                    n_fail[0] = 0
                    n_one += 1
                elif n_fail[0] < COARSE_RETRIES:  # try again at the next sample
                    n_fail[0] += 1
                    k_try = k + 1
                else:  # back off: the next try after 2, 4, ... 32 samples
                    gap = min(2 * gap, 32)
                    k_try = k + gap
                if not ok:
                    for r in range(n2):
                        X[r] = Xs[r]
                    for r in range(st.size):
                        st[r] = sts[r]
                    for j in range(ns):
                        Fbar[j] = Fbs[j]
                        kt[j] = kts[j]
                        lam[j] = lams[j]
                    continue
            break
        for r in range(n2):
            if not math.isfinite(X[r]):
                return STATUS_NONFINITE, k + 1, n_bad, n_one, n_sw
    return STATUS_OK, N, n_bad, n_one, n_sw
