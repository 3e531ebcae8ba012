"""Products with large dense symmetric matrices (pfeie.linalg.symmetric_product).

The reference is the plain product A @ X of NumPy: the same sums in another order, so
the two agree to round-off, measured ≤ 6e-17 of max|A| Σ|x| here; the bound is 5e-16."""

from __future__ import annotations

import numpy as np
import pytest

from pfeie.linalg import SYMMETRIC_MIN, symmetric_columns, symmetric_product


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
