"""The factorisation of A + U B Uᵀ from that of A (Woodbury; pfeie.linalg), against a
dense LAPACK solve with the matrix written out."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from pfeie.linalg import LowRankTerm, UpdatedFactorization, available_backends, factorize


@pytest.mark.parametrize("backend", available_backends())
def test_woodbury_solve_equals_the_dense_solve(backend: str) -> None:
    """A sparse SPD matrix of two decoupled blocks (as an effective matrix decouples the
    bodies), updated by a negative semi-definite term of rank 3 per block: one and four
    right-hand sides solve to 5e-15 of the dense solution (measured 7e-16; the condition
    number is 4.3), Y = A⁻¹U keeps each
    block's support (no entry off its block), and U B Uᵀ v is the product written out."""
    rng = np.random.default_rng(7)
    n1, n2, k = 40, 30, 3
    blocks = []
    for n in (n1, n2):
        L = sp.random(n, n, density=0.1, random_state=rng)
        blocks.append(L @ L.T + sp.identity(n) * 4.0)
    A = sp.block_diag(blocks, format="csc")
    U = np.zeros((n1 + n2, 2 * k))
    U[:n1, :k] = rng.standard_normal((n1, k))
    U[n1:, k:] = rng.standard_normal((n2, k))
    # −2 times the projector on each block's columns (A's eigenvalues are ≥ 4), as the
    # damping of the deformation only removes α M R (RᵀMR)⁻¹ RᵀM
    dense_B = np.zeros((2 * k, 2 * k))
    dense_B[:k, :k] = -2.0 * np.linalg.inv(U[:n1, :k].T @ U[:n1, :k])
    dense_B[k:, k:] = -2.0 * np.linalg.inv(U[n1:, k:].T @ U[n1:, k:])
    term = LowRankTerm(sp.csc_matrix(U), dense_B)
    full = A.toarray() + U @ dense_B @ U.T
    assert np.all(np.linalg.eigvalsh(full) > 0)
    F = UpdatedFactorization(factorize(A, backend=backend), term)
    assert F.Y[n1:, :k].nnz == 0 and F.Y[:n1, k:].nnz == 0
    for b in (rng.standard_normal(n1 + n2), rng.standard_normal((n1 + n2, 4))):
        ref = np.linalg.solve(full, b)
        assert np.abs(F.solve(b) - ref).max() < 5e-15 * np.abs(ref).max()
    v = rng.standard_normal(n1 + n2)
    assert np.allclose(term @ v, U @ dense_B @ U.T @ v, rtol=1e-14, atol=0)
