"""The one place numba is configured.

Kernels import :data:`njit` and :data:`prange` from here, so that caching and
fastmath policy live in a single spot. ``fastmath`` stays off: friction laws
compare against zero and rely on IEEE behaviour at sign changes.

``njit(..., simd=True)`` is for kernels written to be vectorised across
parameter sets (``kernels.batch``): it selects numba's ``error_model="numpy"``,
i.e. IEEE division (``x / 0`` gives inf or NaN instead of raising
``ZeroDivisionError``). With the default Python error model every division
carries a zero test and a branch to the exception path, which stops LLVM from
vectorising the loop. It does not change any finite result and does not enable
fastmath; such kernels detect non-finite states themselves.
"""

from __future__ import annotations

import numba

prange = numba.prange


def njit(*args, simd: bool = False, **kwargs):
    kwargs.setdefault("cache", True)
    kwargs.setdefault("nogil", True)
    if simd:
        kwargs.setdefault("error_model", "numpy")
    return numba.njit(*args, **kwargs)


def set_threads(n: int) -> None:
    """Set numba's thread-pool size for this process (fleet workers run one thread each)."""
    numba.set_num_threads(n)
