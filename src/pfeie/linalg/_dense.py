"""Products with large dense symmetric matrices (the Delassus operator W, W_c and W_c⁻¹).

A product ``A @ x`` with a dense (M, M) matrix streams all M² entries from memory; at the
sizes where this matters (thousands of pair components, 3D) the product is bound by
memory bandwidth, not arithmetic. A symmetric matrix needs only one triangle: BLAS's
``dsymv`` reads the upper triangle and gives the same product in about half the time
(docs/benchmarks.md, "Dense products on one triangle").

:func:`symmetric_product` takes that route from :data:`SYMMETRIC_MIN` rows on, and the
plain product below, by size only: one installation always takes the same path for one
model, so its results are the same bits run after run (the two routes sum in different
orders and differ in the last bits). Small models, where the product costs microseconds,
keep the bits of the plain product.

The matrix must be symmetric to round-off: only its upper triangle (as stored in
Fortran order; the lower triangle of a C-ordered array) is read.

>>> import numpy as np
>>> rng = np.random.default_rng(0)
>>> A = rng.standard_normal((2000, 2000)); A = A + A.T
>>> x = rng.standard_normal(2000)
>>> bool(np.allclose(symmetric_product(A, x), A @ x, rtol=0, atol=1e-10))
True
"""

from __future__ import annotations

import numpy as np
from scipy.linalg import blas

from ..typing import FloatArray

SYMMETRIC_MIN = 1500
"""Rows from which :func:`symmetric_product` reads one triangle (``dsymv``) and
:func:`symmetric_columns` gathers along the contiguous axis; below, a product costs less
than the noise of a step (docs/benchmarks.md has the timings)."""

_COLUMN_LOOP_MAX = 8
"""Up to this many right-hand sides, one ``dsymv`` per column (each half a sweep); beyond,
``dsymm`` (docs/benchmarks.md: ``dsymm`` is slower than ``dsymv`` column by column for
few columns)."""


def symmetric_product(A: FloatArray, X: FloatArray) -> FloatArray:
    """A X for a symmetric (M, M) float64 array ``A`` and X (M,) or (M, k).

    From :data:`SYMMETRIC_MIN` rows, one triangle of ``A`` is read (BLAS ``dsymv``, or
    ``dsymm`` for more than :data:`_COLUMN_LOOP_MAX` columns); below, ``A @ X``."""
    M = A.shape[0]
    if M < SYMMETRIC_MIN or A.dtype != np.float64:
        return np.asarray(A @ X)
    # a Fortran-ordered view without a copy: the transpose of a C-ordered A is A itself
    # to round-off (symmetric)
    AF = A if A.flags.f_contiguous else (A.T if A.flags.c_contiguous else np.asfortranarray(A))
    Xf = np.asarray(X, dtype=np.float64)
    if Xf.ndim == 1:
        return np.asarray(blas.dsymv(1.0, AF, Xf))
    if Xf.shape[1] <= _COLUMN_LOOP_MAX:
        out = np.empty((M, Xf.shape[1]))
        for j in range(Xf.shape[1]):  # a few columns, each half a sweep of A
            out[:, j] = blas.dsymv(1.0, AF, np.ascontiguousarray(Xf[:, j]))
        return out
    return np.asarray(blas.dsymm(1.0, AF, np.asfortranarray(Xf)))


def symmetric_columns(A: FloatArray, idx: np.ndarray, small: str = "columns") -> FloatArray:
    """The columns ``idx`` of a symmetric array ``A``, (M, len(idx)), gathered along its
    contiguous axis from :data:`SYMMETRIC_MIN` rows on: in a C-ordered array its rows
    (equal to the columns to round-off), in a Fortran-ordered one its columns (a strided
    gather costs ten times more: docs/benchmarks.md). Below, the columns themselves
    (``small = "columns"``) or the rows transposed (``"rows"``), as the caller took them
    before, so that small problems keep their bits (a computed inverse is symmetric only
    to round-off)."""
    if A.shape[0] < SYMMETRIC_MIN:
        return np.asarray(A[idx].T if small == "rows" else A[:, idx])
    if A.flags.f_contiguous and not A.flags.c_contiguous:
        return np.asarray(A[:, idx])
    return np.asarray(A[idx].T)
