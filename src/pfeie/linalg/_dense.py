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

import logging

import numpy as np
from scipy.linalg import blas
from scipy.linalg.lapack import dgetrf, dgetrs, sgetrf, sgetrs

from ..typing import FloatArray

SYMMETRIC_MIN = 1500
"""Rows from which :func:`symmetric_product` reads one triangle (``dsymv``) and
:func:`symmetric_columns` gathers along the contiguous axis; below, a product costs less
than the noise of a step (docs/benchmarks.md has the timings)."""

log = logging.getLogger(__name__)

MIXED_TOL = 1e-15
"""A refinement of :class:`MixedLU` has converged when its last correction is at most
this fraction of the solution (max norms): round-off."""
MIXED_FLOOR = 1e-12
"""Corrections that stop contracting (shrink by less than half) below this fraction of
the solution are taken for the round-off floor of the residual and accepted."""
MIXED_MAX_ITER = 10
"""Corrections of a refinement before :class:`MixedLU` factorises in double precision."""

_COLUMN_LOOP_MAX = 8
"""Up to this many right-hand sides, one ``dsymv`` per column (each half a sweep); beyond,
``dsymm`` (docs/benchmarks.md: ``dsymm`` is slower than ``dsymv`` column by column for
few columns)."""


def null_space(C: FloatArray, rtol: float) -> FloatArray:
    """An orthonormal basis (k, r) of the null space of C (m × k, k small): the right
    singular vectors of the singular values at most ``rtol`` times the largest; the
    identity for a C without rows or entries. Only Vᵀ is formed: the left singular vectors
    of a C with many rows are never needed (a block's rigid modes on its 13,000 supported
    DOFs: 13,000² doubles, 1.4 GB and 11 s, for a 6 × 6 answer).

    >>> null_space(np.array([[1.0, 0.0, 0.0], [2.0, 0.0, 0.0]]), 1e-10).shape
    (3, 2)
    >>> null_space(np.zeros((0, 2)), 1e-10).tolist()
    [[1.0, 0.0], [0.0, 1.0]]
    """
    m, k = C.shape
    if m == 0 or not np.any(C):
        return np.eye(k)
    _, sv, vt = np.linalg.svd(C, full_matrices=m < k)  # Vᵀ is k × k either way
    rank = int((sv > rtol * float(sv.max())).sum())
    return np.asarray(vt[rank:].T)


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


class Workspace:
    """Work arrays kept between calls, one per name, for the large temporaries of a
    repeated dense computation (the 3D Newton's capacitance systems). A fresh array of
    hundreds of MB is mapped anew by the allocator at each call, and its first touch
    costs page faults that, on a virtual machine, can exceed the arithmetic done in it
    (docs/benchmarks.md); a work array is mapped once. :meth:`get` returns a view of the
    array ``name``, grown when a larger shape is asked for; its contents are undefined,
    and the view is valid until the next :meth:`get` of the same name (:meth:`uses`).

    >>> w = Workspace()
    >>> a = w.get("x", (2, 3)); a[:] = 1.0
    >>> b = w.get("x", (3, 2))
    >>> bool(np.shares_memory(a, b)), b.shape
    (True, (3, 2))
    """

    def __init__(self) -> None:
        self._arrays: dict[str, np.ndarray] = {}
        self._uses: dict[str, int] = {}

    def get(self, name: str, shape: tuple[int, ...], dtype: type = np.float64) -> np.ndarray:
        """A C-ordered array of ``shape`` and ``dtype`` in the work array ``name``."""
        self._uses[name] = self._uses.get(name, 0) + 1
        n = int(np.prod(shape))
        a = self._arrays.get(name)
        if a is None or a.size < n or a.dtype != dtype:
            grow = int(1.25 * a.size) if a is not None and a.dtype == dtype else n
            a = np.empty(max(n, grow), dtype=dtype)
            self._arrays[name] = a
        return a[:n].reshape(shape)

    def uses(self, name: str) -> int:
        """How many views of the work array ``name`` were handed out: a view kept beyond
        one call (a cache) is still valid while this count has not changed, also when
        the workspace is shared by several owners."""
        return self._uses.get(name, 0)

    def __getstate__(self) -> dict[str, object]:
        return {"_arrays": {}, "_uses": {}}  # work arrays are not state: a copy starts empty


class MixedLU:
    """A large dense square system a y = b for a few solves: an LU of ``a`` in single
    precision (LAPACK sgetrf, about half the time of dgetrf), each solve refined in double
    precision, y ← y + LU⁻¹ (b − a y), until the correction is at the round-off of y
    (:data:`MIXED_TOL`, or :data:`MIXED_FLOOR` where it stops contracting): the answer
    of a double-precision LU wherever cond(a) ε_single < 1, at a few products with ``a``
    (Higham, *Accuracy and Stability of Numerical Algorithms*, 2002, ch. 12). Where the
    refinement does not contract, ``a`` is factorised in double precision, in place.

    ``a`` (k, k), C- or Fortran-ordered, is kept (not copied) until then; the single
    factors live in the work array ``name`` of ``work``, so the object is valid until the
    next one of that name; a fallback to double precision overwrites ``a``. ``perm``: the
    rows of ``a`` are those of the system in this order (rows only: ``solve`` takes b in
    the system's order and returns y in the unknowns' order). A singular ``a`` raises
    :class:`numpy.linalg.LinAlgError`.

    >>> rng = np.random.default_rng(1)
    >>> a = rng.standard_normal((300, 300)) + 30 * np.eye(300); b = rng.standard_normal(300)
    >>> f = MixedLU(a.copy(), Workspace(), "lu")
    >>> y = f.solve(b)
    >>> f.single, bool(np.abs(a @ y - b).max() < 1e-12)
    (True, True)
    """

    def __init__(self, a: FloatArray, work: Workspace, name: str,
                 perm: np.ndarray | None = None) -> None:  # fmt: skip
        self.a, self.perm = a, perm
        k = a.shape[0]
        a32 = work.get(name, (k, k), np.float32)
        # LAPACK factorises a Fortran-ordered array in place: a C-ordered one is its
        # transpose, factorised as such, its solves transposed
        self.trans = 0 if a.flags.f_contiguous and not a.flags.c_contiguous else 1
        # scaled to a largest entry of one, so that single precision neither overflows
        # nor underflows
        self.scale = max(float(a.max(initial=0.0)), -float(a.min(initial=0.0)))  # no |a| copy
        np.multiply(a, 1.0 / self.scale if self.scale > 0 else 1.0,
                    out=a32.T if self.trans == 0 else a32, casting="same_kind")  # fmt: skip
        self.lu, self.piv, info = sgetrf(a32.T, overwrite_a=True)
        self.single = info == 0 and self.scale > 0 and bool(np.isfinite(self.scale))
        self.refinements = 0
        if not self.single:
            self._double()

    def _double(self) -> None:
        a = self.a
        lu, piv, info = dgetrf(a if self.trans == 0 else a.T, overwrite_a=True)
        if info > 0:
            raise np.linalg.LinAlgError("singular system")
        self.lu, self.piv, self.single = lu, piv, False

    def _single_solve(self, r: FloatArray) -> FloatArray:
        """a⁻¹ r through the single-precision factors, r scaled to a largest entry of
        one per column before the cast (no underflow of a small residual)."""
        s = np.abs(r).max(axis=0)
        s = np.where(s > 0, s, 1.0)
        x = sgetrs(self.lu, self.piv, (r / s).astype(np.float32), trans=self.trans)[0]
        return np.asarray(x, dtype=np.float64) * (s / self.scale)

    def solve(self, b: FloatArray) -> FloatArray:
        """y of a y = b (b (k,) or (k, c), not modified; y in the unknowns' order)."""
        if self.perm is not None:
            b = b[self.perm]
        if self.single:
            a = self.a
            y = self._single_solve(b)
            last = np.full(y.shape[1:], np.inf)
            nd = ny = np.full(y.shape[1:], np.inf)
            for _ in range(MIXED_MAX_ITER):
                dy = self._single_solve(b - a @ y)
                self.refinements += 1
                y += dy
                if not np.all(np.isfinite(y)):
                    break
                # per column: at round-off, or stalled at the residual's round-off floor;
                # a column that stalls above that floor stops the refinement
                ny, nd = np.abs(y).max(axis=0), np.abs(dy).max(axis=0)
                stalled = nd > 0.5 * last
                done = (nd <= MIXED_TOL * ny) | (stalled & (nd <= MIXED_FLOOR * ny))
                if np.all(done):
                    return y
                if np.any(stalled & ~done):
                    break
                last = nd
            log.debug("single-precision LU of %d rows: the refinement stopped at %.1e of the "
                      "solution; factorised in double precision", a.shape[0],
                      float(np.max(nd / np.maximum(ny, 1e-300))))  # fmt: skip
            self._double()
        return np.asarray(dgetrs(self.lu, self.piv, b, trans=self.trans)[0])
