"""Dense linear algebra of the interface solver (pfeie.linalg): products with large
symmetric matrices, the mixed-precision LU, the work arrays.

The references: the plain product A @ X of NumPy (the same sums in another order, so the
two agree to round-off, measured ≤ 6e-17 of max|A| Σ|x| here; the bound is 5e-16); the
double-precision LU of SciPy for :class:`~pfeie.linalg.MixedLU`."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla

from pfeie.linalg import (
    SYMMETRIC_MIN,
    MixedLU,
    Workspace,
    symmetric_columns,
    symmetric_product,
)


def _symmetric(M: int, order: str) -> np.ndarray:
    rng = np.random.default_rng(M)
    A = rng.standard_normal((M, M))
    A = A + A.T
    return np.asfortranarray(A) if order == "F" else np.ascontiguousarray(A)


@pytest.mark.parametrize("order", ["C", "F"])
@pytest.mark.parametrize("k", [0, 1, 3, 12])  # 0: a vector; 3: dsymv per column; 12: dsymm
def test_symmetric_product_equals_the_plain_product(order: str, k: int) -> None:
    M = SYMMETRIC_MIN + 17
    A = _symmetric(M, order)
    rng = np.random.default_rng(1)
    X = rng.standard_normal(M) if k == 0 else rng.standard_normal((M, k))
    ref = A @ X
    got = symmetric_product(A, X)
    assert got.shape == ref.shape
    bound = 5e-16 * np.abs(A).max() * np.abs(X).sum(axis=0)
    assert np.all(np.abs(got - ref) <= bound)
    # only one triangle is read: a matrix that differs below the diagonal gives the
    # product of its upper (Fortran) triangle's symmetric extension
    B = A.copy(order="K")
    if order == "F":
        B[np.tril_indices(M, -1)] = 0.0
        full = np.triu(B) + np.triu(B, 1).T
    else:  # a C-ordered array is read through its transpose: its lower triangle
        B[np.triu_indices(M, 1)] = 0.0
        full = np.tril(B) + np.tril(B, -1).T
    assert np.all(np.abs(symmetric_product(B, X) - full @ X) <= bound)


def test_small_matrices_keep_the_plain_products_bits() -> None:
    """Below SYMMETRIC_MIN rows the product is A @ X itself (bit for bit)."""
    A = _symmetric(SYMMETRIC_MIN - 1, "C")
    x = np.random.default_rng(2).standard_normal(A.shape[0])
    assert np.array_equal(symmetric_product(A, x), A @ x)


@pytest.mark.parametrize("M", [300, SYMMETRIC_MIN])
@pytest.mark.parametrize("order", ["C", "F"])
def test_symmetric_columns(order: str, M: int) -> None:
    """The columns, gathered along the contiguous axis from SYMMETRIC_MIN rows; below,
    bit for bit what the callers took before (the columns, or the rows transposed: a
    computed inverse is symmetric only to round-off, so the two differ in the last
    bits)."""
    A = _symmetric(M, order)
    A[0, 1] += 1e-3  # no longer symmetric: which entries are read shows
    idx = np.array([3, 0, M - 1, 17, 17])
    if M < SYMMETRIC_MIN:
        np.testing.assert_array_equal(symmetric_columns(A, idx), A[:, idx])
        np.testing.assert_array_equal(symmetric_columns(A, idx, small="rows"), A[idx].T)
    else:  # along the contiguous axis, whatever the caller's habit
        ref = A[:, idx] if order == "F" else A[idx].T
        for small in ("columns", "rows"):
            np.testing.assert_array_equal(symmetric_columns(A, idx, small=small), ref)


def _backward_error(a: np.ndarray, y: np.ndarray, b: np.ndarray) -> float:
    """‖b − a y‖∞ / (‖a‖∞ ‖y‖∞ + ‖b‖∞): the normwise backward error (Higham 2002, 7.1)."""
    r = np.abs(b - a @ y).max()
    return float(r / (np.abs(a).sum(axis=1).max() * np.abs(y).max() + np.abs(b).max()))


@pytest.mark.parametrize("order", ["C", "F"])
def test_mixed_lu_equals_the_double_lu(order: str) -> None:
    """The single-precision LU refined in double precision solves a system of condition
    1e4 as a double-precision LU does: backward error at round-off (bound 2.2e-16 = ε;
    measured 1.9e-17 and 2.5e-17, SciPy's LU 9e-17), and the same solution to the
    condition times ε (bound 2e-12 relative; measured 4.4e-13), C- or Fortran-ordered,
    one or several right-hand sides, rows permuted; the LU stays single (5 corrections)."""
    rng = np.random.default_rng(3)
    k = 400
    q1, _ = np.linalg.qr(rng.standard_normal((k, k)))
    q2, _ = np.linalg.qr(rng.standard_normal((k, k)))
    a = (q1 * np.logspace(0, -4, k)) @ q2.T
    b = rng.standard_normal((k, 3))
    ref = sla.solve(a, b)
    f = MixedLU(np.array(a, order=order), Workspace(), "lu")
    y = f.solve(b.copy())
    assert f.single and 1 <= f.refinements <= 10
    assert _backward_error(a, y, b) <= 2.2e-16
    assert np.abs(y - ref).max() <= 2e-12 * np.abs(ref).max()
    perm = rng.permutation(k)  # the rows of the stored array in this order
    fp = MixedLU(np.array(a[perm], order=order), Workspace(), "lu", perm)
    yp = fp.solve(b[:, 0].copy())
    assert _backward_error(a, yp, b[:, 0]) <= 2.2e-16


def test_mixed_lu_falls_back_to_double_precision() -> None:
    """Where single precision cannot resolve the system (condition 1e9 > 1/ε_single), the
    refinement does not contract and the system is factorised in double precision: the
    answer of a double-precision LU to their accuracy (bound 1e-7 relative, the condition
    1e9 times ε; measured 1.2e-8)."""
    rng = np.random.default_rng(4)
    k = 200
    q1, _ = np.linalg.qr(rng.standard_normal((k, k)))
    q2, _ = np.linalg.qr(rng.standard_normal((k, k)))
    a = (q1 * np.logspace(0, -9, k)) @ q2.T
    b = rng.standard_normal(k)
    ref = sla.solve(a, b)
    f = MixedLU(a.copy(), Workspace(), "lu")
    y = f.solve(b.copy())
    assert not f.single
    assert np.abs(y - ref).max() <= 1e-7 * np.abs(ref).max()


def test_workspace_reuses_its_arrays() -> None:
    """A work array is allocated once and grown only for a larger shape; a copy of its
    owner starts without work arrays (they are not state)."""
    import copy

    w = Workspace()
    a = w.get("x", (100, 10))
    b = w.get("x", (50, 20))
    assert np.shares_memory(a, b) and b.shape == (50, 20) and b.flags.c_contiguous
    c = w.get("x", (200, 10))
    assert not np.shares_memory(a, c)
    assert w.get("y", (3,), np.float32).dtype == np.float32
    assert copy.deepcopy(w)._arrays == {}


@pytest.mark.parametrize(("sa", "sb"), [(1.0, 1e-46), (1e-45, 1.0), (1e40, 1e-30)])
def test_mixed_lu_is_scaled_for_single_precision(sa: float, sb: float) -> None:
    """A system or right-hand side far outside single precision's range (1e-46 is below
    its smallest number, 1e40 above its largest) is scaled before the cast: the answer
    of a double-precision LU to round-off (bound 5e-15 relative; measured 5.6e-16 to
    8.5e-16),
    still by the single-precision LU."""
    rng = np.random.default_rng(5)
    k = 120
    a = (rng.standard_normal((k, k)) + 15.0 * np.eye(k)) * sa
    b = rng.standard_normal(k) * sb
    ref = sla.solve(a, b)
    f = MixedLU(a.copy(), Workspace(), "lu")
    y = f.solve(b)
    assert f.single
    assert np.abs(y - ref).max() <= 5e-15 * np.abs(ref).max()


@pytest.mark.parametrize(("m", "k", "rank"), [(5000, 6, 6), (5000, 6, 4), (3, 6, 3), (1, 3, 1)])
def test_null_space_against_scipy(m: int, k: int, rank: int) -> None:
    """pfeie.linalg.null_space (Vᵀ only) spans scipy's null space (full SVD) of tall and
    wide matrices of rank ``rank``: the same dimension, orthonormal columns (to 5e-15;
    measured 4.4e-16 at most), C N = 0 (to 5e-15 of |C|; measured 3.2e-16) and the two
    bases' projectors equal (to 1e-14; measured 0)."""
    from pfeie.linalg import null_space

    rng = np.random.default_rng(7)
    C = rng.standard_normal((m, rank)) @ rng.standard_normal((rank, k))
    N = null_space(C, max(m, k) * float(np.finfo(float).eps))
    ref = sla.null_space(C)
    assert N.shape == ref.shape == (k, k - rank)
    np.testing.assert_allclose(N.T @ N, np.eye(k - rank), atol=5e-15)
    assert np.abs(C @ N).max(initial=0.0) <= 5e-15 * np.abs(C).max()
    np.testing.assert_allclose(N @ N.T, ref @ ref.T, atol=1e-14)
