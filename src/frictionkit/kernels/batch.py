"""Vectorised batch kernel: force-driven LuGre over many parameter sets, fixed ROS2 sub-steps.

``lugre_batch_sse`` in :mod:`frictionkit.kernels.lugre` runs the adaptive
scalar integrator once per parameter set (``lugre_force_batch_sse`` its ROS2-only
form); each set takes its own steps and branches, so nothing vectorises. Here all parameter sets advance *together*,
one sample at a time, with the loop over parameter sets innermost:

* the same two-stage ROS2 equations as ``lugre._interval``, but with ``n_sub``
  equal sub-steps ``h = dt / n_sub`` per sample and no error control, so every
  set does the same arithmetic at the same time;
* structure of arrays: the parameter sets are cut into chunks of :data:`CHUNK`
  lanes; each chunk copies its parameters (per direction, with ``1/vs``,
  ``Fs - Fc`` and ``1/m`` precomputed) and its state into one private buffer,
  and the lane loop reads and writes only that buffer at constant offsets, so
  LLVM needs no run-time alias checks and emits SIMD code. The chunk functions
  ask for 512-bit vectors (:func:`_wide_vectors`; LLVM otherwise stops at 256
  bits on AVX-512 CPUs): measured on a Xeon (Emerald Rapids), the hot loop is 8
  lanes wide (``zmm``) and costs ~12 ns CPU time per set and sub-step, against
  ~20 ns 4 wide and ~90 ns when the loop does not vectorise;
* divisions use IEEE semantics (``njit(simd=True)``, numba's numpy error model):
  the default zero-divisor check is a branch per division that blocks
  vectorisation; ``fastmath`` stays off (not needed: there are no reductions
  across lanes). Measured: allowing FMA contraction (``fastmath={"contract"}``)
  is ~1.4x faster but moves the SSEs of the 10 s benchmark run by up to 8.6e-12
  relative (the kernel and its scalar twin agree to 1.2e-12), over the 1e-12
  budget for such flags, so it is not used;
* the direction row is chosen per lane with selects (``a if v >= 0 else b``
  on already-loaded values compiles to a blend), the special cases of
  ``_stribeck`` (``r == 0``, exponent above :data:`~._stribeck.UNDERFLOW`) are
  selects too; levels of zero are floored once, when a chunk is loaded, exactly as
  in ``_stribeck.row`` (see the note there);
* ``exp`` is :func:`_vexp`, a branch-free Cody–Waite / degree-13 polynomial
  (<= 2 ulp from libm): the libm call cannot be vectorised without SVML.
  One ``exp`` per set per stage, two per sub-step;
* each chunk picks its code path (:func:`chunk_modes`): all sets symmetric with
  the exponential shape and ``delta == 2`` (``r*r``, one row: fastest);
  directional with ``delta == 2`` (both rows loaded, select per lane: as fast);
  anything else (other exponents, Lorentzian shapes) runs the general lane
  code, which branches and calls ``pow`` and so does not vectorise (~10x
  slower) but gives the same numbers as the scalar kernels;
* chunks run in parallel (``prange``); a lane whose state becomes non-finite
  just carries NaN/inf to the end (other lanes are untouched) and is reported
  with status 1 and ``sse = inf``.

Accuracy: the scheme is second order with an L-stable stage, so stiff bristle
dynamics are damped, not resolved. See ``frictionkit.simulation.core.simulate_batch``
for the measured error against the adaptive kernel.
"""

from __future__ import annotations

import math

import numpy as np
from llvmlite import ir
from numba import types
from numba.extending import intrinsic

from .._jit import njit, prange
from ._stribeck import G_FLOOR, UNDERFLOW

GAMMA = 1.0 + 1.0 / math.sqrt(2.0)
OK, NONFINITE = 0, 1

#: Lanes per chunk: one chunk's buffer (29 fields x CHUNK doubles, ~15 kB) stays in L1.
CHUNK = 64

# Buffer layout: field f of lane i is B[f * CHUNK + i].
# Parameters, direction + (v >= 0) then - (v < 0).
_FCP, _DFP, _FSP, _IVSP, _S2P, _S0P, _S1P, _DLP, _SHP = range(0, 9)
_FCN, _DFN, _FSN, _IVSN, _S2N, _S0N, _S1N, _DLN, _SHN = range(9, 18)
_IM = 18
# State and the quantities of the point evaluation at the current state.
_X, _V, _Z, _ZD, _F, _DZV, _DZZ, _DFV, _DFZ, _ACC = range(19, 29)
NFIELDS = 29

_LOG2E = 1.4426950408889634
_LN2_HI = 6.93147180369123816490e-01  # fdlibm split of ln 2: n * _LN2_HI is exact
_LN2_LO = 1.90821492927058770002e-10


@intrinsic
def _i64_as_f64(typingctx, n):
    """Reinterpret the bits of an int64 as a float64 (an LLVM bitcast; vectorises)."""
    sig = types.float64(types.int64)

    def codegen(context, builder, signature, args):
        return builder.bitcast(args[0], ir.DoubleType())

    return sig, codegen


@intrinsic
def _wide_vectors(typingctx):
    """Let LLVM use 512-bit vectors in the calling function (no code of its own).

    LLVM's X86 tuning caps auto-vectorisation at 256 bits on AVX-512 CPUs
    (``prefer-vector-width``); the lane loops here are pure arithmetic and run
    markedly faster 8 wide. Sets the function attribute
    ``"prefer-vector-width"="512"`` on the function being generated; harmless on
    CPUs without AVX-512 (the target then has no 512-bit registers).
    """
    sig = types.none()

    def codegen(context, builder, signature, args):
        # llvmlite validates attribute names against a fixed list that lacks string
        # attributes, hence the plain set.add; if a future llvmlite changes that
        # container, fall back to LLVM's default vector width (slower, same results).
        try:
            set.add(builder.function.attributes, '"prefer-vector-width"="512"')
        except Exception:  # pragma: no cover - depends on the llvmlite version
            pass
        return context.get_dummy_value()

    return sig, codegen


@njit(inline="always", simd=True)
def _vexp(x):
    """``exp(x)`` for ``-708 <= x <= 0`` without branches or library calls.

    Cody–Waite reduction ``x = n ln2 + r``, ``|r| <= ln2/2``, Taylor polynomial to
    ``r^13`` (truncation < 5e-18 relative), scaling by ``2^n`` through the exponent
    bits. Within 2 ulp of libm's ``exp`` on that range (tested).
    """
    fn = math.floor(x * _LOG2E + 0.5)
    r = (x - fn * _LN2_HI) - fn * _LN2_LO
    # Estrin's scheme: short dependency chains, same terms as Horner
    r2 = r * r
    r4 = r2 * r2
    r8 = r4 * r4
    c01 = 1.0 + r
    c23 = 0.5 + r * (1.0 / 6.0)
    c45 = 1.0 / 24.0 + r * (1.0 / 120.0)
    c67 = 1.0 / 720.0 + r * (1.0 / 5040.0)
    c89 = 1.0 / 40320.0 + r * (1.0 / 362880.0)
    cab = 1.0 / 3628800.0 + r * (1.0 / 39916800.0)
    ccd = 1.0 / 479001600.0 + r * (1.0 / 6227020800.0)
    lo = (c01 + r2 * c23) + r4 * (c45 + r2 * c67)
    hi = (c89 + r2 * cab) + r4 * ccd
    p = lo + r8 * hi
    return p * _i64_as_f64((np.int64(fn) + 1023) << 52)


@njit(inline="always", simd=True)
def _phi(r, dl, sh, general):
    """``(phi, dphi/dr, rd)`` of the Stribeck shape at ``r >= 0``; exponential selects on ``rd``."""
    if general:
        if sh != 0.0:
            q = 1.0 / (1.0 + r * r)
            return q, -2.0 * r * q * q, 0.0
        if dl == 2.0:
            rd = r * r
            rdr = r
        elif dl == 1.0:
            rd = r
            rdr = 1.0
        else:
            rd = r**dl
            rdr = rd / r
        rc = rd if rd < UNDERFLOW else UNDERFLOW
        ph = _vexp(-rc)
        return ph, -dl * rdr * ph, rd
    rd = r * r
    rc = rd if rd < UNDERFLOW else UNDERFLOW
    ph = _vexp(-rc)
    return ph, -2.0 * r * ph, rd


@njit(inline="always", simd=True)
def _lane_point(B, i, general, sym):
    """Point evaluation at lane ``i``'s state (``lugre._point``); stores zd, F and the Jacobian entries."""
    v = B[_V * CHUNK + i]
    z = B[_Z * CHUNK + i]
    # both rows loaded unconditionally, then a select (a conditional load would not vectorise)
    up = sym or v >= 0.0
    Fc = B[_FCP * CHUNK + i]
    Fc_n = B[_FCN * CHUNK + i]
    Fc = Fc if up else Fc_n
    dF = B[_DFP * CHUNK + i]
    dF_n = B[_DFN * CHUNK + i]
    dF = dF if up else dF_n
    Fs = B[_FSP * CHUNK + i]
    Fs_n = B[_FSN * CHUNK + i]
    Fs = Fs if up else Fs_n
    ivs = B[_IVSP * CHUNK + i]
    ivs_n = B[_IVSN * CHUNK + i]
    ivs = ivs if up else ivs_n
    s2 = B[_S2P * CHUNK + i]
    s2_n = B[_S2N * CHUNK + i]
    s2 = s2 if up else s2_n
    s0 = B[_S0P * CHUNK + i]
    s0_n = B[_S0N * CHUNK + i]
    s0 = s0 if up else s0_n
    s1 = B[_S1P * CHUNK + i]
    s1_n = B[_S1N * CHUNK + i]
    s1 = s1 if up else s1_n
    dl = (B[_DLP * CHUNK + i] if up else B[_DLN * CHUNK + i]) if general else 2.0
    sh = (B[_SHP * CHUNK + i] if up else B[_SHN * CHUNK + i]) if general else 0.0
    av = abs(v)
    r = av * ivs
    ph, dph, rd = _phi(r, dl, sh, general)
    g = Fc + dF * ph
    gr = dF * dph * ivs
    flat = r == 0.0
    cut = (rd > UNDERFLOW) & (sh == 0.0)
    # two-way selects in sequence (a three-way merge is left as branches)
    g = Fc if cut else g
    g = Fs if flat else g
    gr = 0.0 if (flat | cut) else gr
    ig = 1.0 / g
    a = s0 * av * ig
    zd = v - a * z
    sg = -1.0 if v < 0.0 else 0.0
    sg = 1.0 if v > 0.0 else sg
    dzv = 1.0 - s0 * z * sg * ig * (1.0 - av * gr * ig)
    B[_ZD * CHUNK + i] = zd
    B[_F * CHUNK + i] = s0 * z + s1 * zd + s2 * v
    B[_DZV * CHUNK + i] = dzv
    B[_DZZ * CHUNK + i] = -a
    B[_DFV * CHUNK + i] = s1 * dzv + s2
    B[_DFZ * CHUNK + i] = s0 - s1 * a


@njit(inline="always", simd=True)
def _lane_step(B, i, h, gh, w, du, general, sym):
    """One ROS2 sub-step of lane ``i`` (``lugre._interval`` without error control)."""
    x = B[_X * CHUNK + i]
    v = B[_V * CHUNK + i]
    z = B[_Z * CHUNK + i]
    zd = B[_ZD * CHUNK + i]
    F = B[_F * CHUNK + i]
    dzv = B[_DZV * CHUNK + i]
    dzz = B[_DZZ * CHUNK + i]
    dFv = B[_DFV * CHUNK + i]
    dFz = B[_DFZ * CHUNK + i]
    im = B[_IM * CHUNK + i]
    a11 = 1.0 + gh * dFv * im
    a12 = gh * dFz * im
    a21 = -gh * dzv
    a22 = 1.0 - gh * dzz
    idet = 1.0 / (a11 * a22 - a12 * a21)
    b1 = (w - F + gh * du) * im
    k1v = (b1 * a22 - a12 * zd) * idet
    k1z = (a11 * zd - a21 * b1) * idet
    k1x = v + gh * k1v
    v2 = v + h * k1v
    z2 = z + h * k1z
    # stage 2: friction at (v2, z2) (lugre._force)
    up = sym or v2 >= 0.0
    Fc = B[_FCP * CHUNK + i]
    Fc_n = B[_FCN * CHUNK + i]
    Fc = Fc if up else Fc_n
    dF = B[_DFP * CHUNK + i]
    dF_n = B[_DFN * CHUNK + i]
    dF = dF if up else dF_n
    Fs = B[_FSP * CHUNK + i]
    Fs_n = B[_FSN * CHUNK + i]
    Fs = Fs if up else Fs_n
    ivs = B[_IVSP * CHUNK + i]
    ivs_n = B[_IVSN * CHUNK + i]
    ivs = ivs if up else ivs_n
    s2 = B[_S2P * CHUNK + i]
    s2_n = B[_S2N * CHUNK + i]
    s2 = s2 if up else s2_n
    s0 = B[_S0P * CHUNK + i]
    s0_n = B[_S0N * CHUNK + i]
    s0 = s0 if up else s0_n
    s1 = B[_S1P * CHUNK + i]
    s1_n = B[_S1N * CHUNK + i]
    s1 = s1 if up else s1_n
    dl = (B[_DLP * CHUNK + i] if up else B[_DLN * CHUNK + i]) if general else 2.0
    sh = (B[_SHP * CHUNK + i] if up else B[_SHN * CHUNK + i]) if general else 0.0
    av = abs(v2)
    r = av * ivs
    ph, dph, rd = _phi(r, dl, sh, general)
    g = Fc + dF * ph
    expo = sh == 0.0
    g = Fc if ((rd > UNDERFLOW) & expo) else g
    g = Fs if ((r == 0.0) & expo) else g
    zd2 = v2 - s0 * av * z2 / g
    F2 = s0 * z2 + s1 * zd2 + s2 * v2
    r_z = zd2 - 2.0 * k1z
    b1 = (w + h * du - F2 - gh * du) * im - 2.0 * k1v
    k2v = (b1 * a22 - a12 * r_z) * idet
    k2z = (a11 * r_z - a21 * b1) * idet
    k2x = v2 - 2.0 * k1x + gh * k2v
    B[_X * CHUNK + i] = x + h * (1.5 * k1x + 0.5 * k2x)
    B[_V * CHUNK + i] = v + h * (1.5 * k1v + 0.5 * k2v)
    B[_Z * CHUNK + i] = z + h * (1.5 * k1z + 0.5 * k2z)


@njit(inline="always", simd=True)
def _run_chunk(B, u, dt, n_sub, target, which, weight, general, sym):
    """Advance the CHUNK lanes of ``B`` over all samples, accumulating the weighted SSE."""
    _wide_vectors()
    for i in range(CHUNK):
        _lane_point(B, i, general, sym)
    h = dt / n_sub
    gh = GAMMA * h
    sx = 1.0 if which == 0 else 0.0
    sv = 1.0 if which == 1 else 0.0
    sf = 1.0 if which == 2 else 0.0
    for k in range(u.size - 1):
        u0 = u[k]
        du = (u[k + 1] - u0) / dt
        t = 0.0
        for _ in range(n_sub):
            w = u0 + du * t
            for i in range(CHUNK):
                _lane_step(B, i, h, gh, w, du, general, sym)
                _lane_point(B, i, general, sym)
            t += h
        y = target[k + 1]
        wk = weight[k + 1]
        for i in range(CHUNK):
            # which is 0, 1 or 2: exactly one of sx, sv, sf is 1 (0 * inf would be NaN,
            # but then the lane is non-finite anyway)
            d = sx * B[_X * CHUNK + i] + sv * B[_V * CHUNK + i] + sf * B[_F * CHUNK + i] - y
            B[_ACC * CHUNK + i] += wk * d * d


@njit(simd=True)
def _chunk_d2_sym(B, u, dt, n_sub, target, which, weight):
    _run_chunk(B, u, dt, n_sub, target, which, weight, False, True)


@njit(simd=True)
def _chunk_d2(B, u, dt, n_sub, target, which, weight):
    _run_chunk(B, u, dt, n_sub, target, which, weight, False, False)


@njit(simd=True)
def _chunk_general(B, u, dt, n_sub, target, which, weight):
    _run_chunk(B, u, dt, n_sub, target, which, weight, True, False)


@njit(inline="always", simd=True)
def _load(B, static, dyn, m, j0, nl):
    """Fill a chunk buffer: lanes ``0 .. nl-1`` from sets ``j0 ..``; padding lanes copy set ``j0``."""
    for i in range(CHUNK):
        j = j0 + i if i < nl else j0
        # levels floored as in ``_stribeck.row``: g > 0 even where Fc or Fs is 0
        lo = G_FLOOR * max(max(static[j, 0, 0], static[j, 0, 1]), max(static[j, 1, 0], static[j, 1, 1]))
        for row in range(2):
            o = 0 if row == 0 else 9
            Fc = max(static[j, row, 0], lo)
            Fs = max(static[j, row, 1], lo)
            B[(o + _FCP) * CHUNK + i] = Fc
            B[(o + _DFP) * CHUNK + i] = Fs - Fc
            B[(o + _FSP) * CHUNK + i] = Fs
            B[(o + _IVSP) * CHUNK + i] = 1.0 / static[j, row, 2]
            B[(o + _DLP) * CHUNK + i] = static[j, row, 3]
            B[(o + _S2P) * CHUNK + i] = static[j, row, 4]
            B[(o + _SHP) * CHUNK + i] = static[j, row, 5]
            B[(o + _S0P) * CHUNK + i] = dyn[j, row, 0]
            B[(o + _S1P) * CHUNK + i] = dyn[j, row, 1]
        B[_IM * CHUNK + i] = 1.0 / m[j]
        B[_X * CHUNK + i] = 0.0
        B[_V * CHUNK + i] = 0.0
        B[_Z * CHUNK + i] = 0.0
        B[_ACC * CHUNK + i] = 0.0


#: Per-chunk code paths (see :func:`chunk_modes`).
MODE_SYM, MODE_DIR, MODE_GENERAL = 0, 1, 2


@njit(parallel=True, simd=True)
def lugre_fixed_batch_sse(u, dt, m, static, dyn, n_sub, target, which, weight, modes, out_sse, out_status):
    """Fixed-step ROS2 LuGre over P parameter sets at once; weighted SSE per set.

    Arguments as ``lugre.lugre_force_batch_sse`` (``static (P, 2, 6)``, ``dyn (P, 2, 2)``,
    ``m (P,)``, ``which`` 0 position / 1 velocity / 2 force, ``weight (N,)``), plus
    ``n_sub >= 1`` equal sub-steps per sample and ``modes``, the code path of each
    chunk of :data:`CHUNK` sets from :func:`chunk_modes`. All runs start at rest with
    ``z = 0``. Status 0 ok, 1 non-finite (``sse = inf``).
    """
    P = m.size
    nch = (P + CHUNK - 1) // CHUNK
    for c in prange(nch):
        j0 = c * CHUNK
        nl = min(CHUNK, P - j0)
        B = np.empty(NFIELDS * CHUNK)
        _load(B, static, dyn, m, j0, nl)
        mode = modes[c]
        if mode == MODE_SYM:
            _chunk_d2_sym(B, u, dt, n_sub, target, which, weight)
        elif mode == MODE_DIR:
            _chunk_d2(B, u, dt, n_sub, target, which, weight)
        else:
            _chunk_general(B, u, dt, n_sub, target, which, weight)
        for i in range(nl):
            acc = B[_ACC * CHUNK + i]
            fin = (
                math.isfinite(acc)
                and math.isfinite(B[_X * CHUNK + i])
                and math.isfinite(B[_V * CHUNK + i])
                and math.isfinite(B[_Z * CHUNK + i])
            )
            out_sse[j0 + i] = acc if fin else np.inf
            out_status[j0 + i] = OK if fin else NONFINITE


def chunk_modes(static: np.ndarray, dyn: np.ndarray) -> np.ndarray:
    """Code path per chunk of :data:`CHUNK` parameter sets.

    ``MODE_SYM`` when every set of the chunk is symmetric (row + equals row -) with the
    exponential shape and ``delta == 2``; ``MODE_DIR`` when directional but still
    exponential with ``delta == 2``; ``MODE_GENERAL`` otherwise (other exponents,
    Lorentzian shape: not vectorised, see the module notes).
    """
    P = static.shape[0]
    fast = (static[:, :, 5] == 0.0) & (static[:, :, 3] == 2.0)
    fast = fast.all(axis=1)
    sym = (static[:, 0] == static[:, 1]).all(axis=1) & (dyn[:, 0] == dyn[:, 1]).all(axis=1)
    nch = (P + CHUNK - 1) // CHUNK
    modes = np.empty(nch, dtype=np.int64)
    for c in range(nch):
        sl = slice(c * CHUNK, min(P, (c + 1) * CHUNK))
        modes[c] = MODE_GENERAL if not fast[sl].all() else (MODE_SYM if sym[sl].all() else MODE_DIR)
    return modes
