"""One small least-recently-used memo for the package's caches of derived objects (packed machines,
matrix exponentials, stage machines, feed-forwards)."""

from __future__ import annotations

from collections import OrderedDict
from typing import Callable, Hashable, TypeVar

T = TypeVar("T")


def remember(cache: OrderedDict, key: Hashable | None, make: Callable[[], T], size: int) -> T:
    """``cache[key]``, made by ``make()`` on a miss; the ``size`` most recently used entries kept.

    A ``key`` of None (content that cannot be keyed safely) is never cached: ``make()`` every call.
    Safe under threads (a Dask worker's): an entry evicted or emptied by another thread meanwhile
    costs at most a second ``make()``, never a wrong entry — the caller's key fixes the content."""
    if key is None:
        return make()
    hit = cache.get(key)
    if hit is None:
        hit = cache[key] = make()
        while len(cache) > size:
            try:
                cache.popitem(last=False)
            except KeyError:  # emptied by another thread meanwhile
                break
    else:
        try:
            cache.move_to_end(key)
        except KeyError:  # evicted by another thread meanwhile: hit is still valid
            pass
    return hit
