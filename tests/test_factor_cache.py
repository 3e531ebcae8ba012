"""The memory the pair solvers keep: factorised state systems within a byte budget, least
recently used out (a 3D slope of 753 pair components held 2.47 GB after 2 s of record
with caches bounded by count alone, 0.83 GB with the budgets, in the same time)."""

from __future__ import annotations

import numpy as np

from pfeie.interface import FactorCache
from pfeie.io._modelfile import _pair_caches


def test_the_least_recently_used_factors_leave_first() -> None:
    """Four 1 MiB factors in a 3 MiB cache: the first two in, the second used again; the
    fourth evicts the first (the least recently used), the bytes add up exactly."""
    mib = 2**20
    cache = FactorCache(max_bytes=3 * mib, max_count=64)
    a = [(np.zeros(mib // 8), np.zeros(0, dtype=np.int32)) for _ in range(4)]
    cache[b"1"], cache[b"2"], cache[b"3"] = (a[0],), (a[1],), (a[2],)
    assert cache.nbytes == 3 * mib and len(cache) == 3
    assert cache.get(b"1") is not None  # now the most recent
    cache[b"4"] = (a[3],)
    assert cache.get(b"2") is None and cache.get(b"1") is not None
    assert cache.nbytes == 3 * mib and len(cache) == 3
    cache[b"4"] = (a[3],)  # the same key again: counted once
    assert cache.nbytes == 3 * mib
    small = FactorCache(max_bytes=10 * mib, max_count=2)
    for k in (b"x", b"y", b"z"):
        small[k] = (a[0],)
    assert len(small) == 2 and small.get(b"x") is None
    cache.clear()
    assert cache.nbytes == 0 and len(cache) == 0


def test_the_memory_estimate_counts_the_bounded_caches() -> None:
    """``pfeie check``'s estimate: nothing without pairs; M² growth for small M (64
    factors of 8 M² bytes each), then the bounds: 2 × (16 + 128) MiB."""
    assert _pair_caches(0) == 0
    assert _pair_caches(10) == 2 * (64 * 800 + 16 * (3 * 800 + 64 * 800))
    assert _pair_caches(753) == 2 * (16 + 128) * 2**20
