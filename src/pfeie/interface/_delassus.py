"""The Delassus operator W = G K̂⁻¹ Gᵀ (method.md §5.1) from one multi-RHS solve.

G (M × n) maps block displacements to pair relative displacements (local frames).
Columns of Gᵀ are solved in chunks; W is kept (dense, M × M). The solutions
Z = K̂⁻¹ Gᵀ are kept too when n·M is small (``keep`` entries, default 1e6, 8 MB): then the
corrector u = u_free + Z X is a matrix-vector product instead of a second
back-substitution. Above that the product costs as much as the solve (both stream about
n·M or nnz(L) numbers), so the corrector solves K̂ Δu = Gᵀ X.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..element._reference import FloatArray
from ..solvers import Factorization


def delassus(
    factor: Factorization, G: sp.csr_matrix, *, chunk: int = 256, keep: float = 1e6
) -> tuple[FloatArray, FloatArray | None]:
    """W (M, M) and, if small enough, Z = K̂⁻¹ Gᵀ (n, M).

    >>> import numpy as np, scipy.sparse as sp
    >>> from pfeie.solvers import factorize
    >>> K = sp.csr_matrix(np.array([[2.0, -1.0], [-1.0, 2.0]]))
    >>> G = sp.csr_matrix(np.array([[-1.0, 1.0]]))   # w = u₂ − u₁
    >>> W, Z = delassus(factorize(K), G)
    >>> round(float(W[0, 0]), 12)   # G K⁻¹ Gᵀ = (1, −1)·(1/3)[[2, 1], [1, 2]]·(1, −1)ᵀ
    0.666666666667
    """
    M, n = G.shape
    W = np.zeros((M, M))
    Z = np.zeros((n, M)) if n * M <= keep else None
    Gt = G.T.tocsc()
    for j0 in range(0, M, chunk):
        j1 = min(M, j0 + chunk)
        rhs = Gt[:, j0:j1].toarray()
        sol = factor.solve(rhs)
        W[:, j0:j1] = G @ sol
        if Z is not None:
            Z[:, j0:j1] = sol
    W = 0.5 * (W + W.T)
    return W, Z
