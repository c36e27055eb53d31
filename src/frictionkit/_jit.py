"""The one place numba is configured.

Kernels import :data:`njit` and :data:`prange` from here, so that caching and
fastmath policy live in a single spot. ``fastmath`` stays off: friction laws
compare against zero and rely on IEEE behaviour at sign changes.
"""

from __future__ import annotations

import numba

prange = numba.prange


def njit(*args, **kwargs):
    kwargs.setdefault("cache", True)
    kwargs.setdefault("nogil", True)
    return numba.njit(*args, **kwargs)
