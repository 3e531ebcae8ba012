"""A symmetric low-rank term U B Uᵀ and the factorisation of A + U B Uᵀ from that of A.

The rigid motions that the supports leave free make such a term: mass-proportional
damping of the deformation only subtracts α M R (Rᵀ M R)⁻¹ Rᵀ M (:meth:`pfeie.Model.system`),
rank 3 in 2D and 6 in 3D per floating body. The effective matrix of a time step then differs from
the sparse one by a low-rank term, and the Sherman–Morrison–Woodbury identity

    (A + U B Uᵀ)⁻¹ = A⁻¹ − Y (B⁻¹ + Uᵀ Y)⁻¹ Yᵀ,   Y = A⁻¹ U,

keeps the sparse factor of A: Y is r back-substitutions once, and a solve costs one
back-substitution of A plus two products with the n × r matrices U and Y (Y is sparse when
A decouples the bodies, as an effective matrix does: A⁻¹ U of one body lives on its DOFs).
The capacitance B⁻¹ + Uᵀ Y (r × r) is factorised once (LU: it is indefinite when B is
negative); it is regular whenever A and A + U B Uᵀ are.

>>> import numpy as np, scipy.sparse as sp
>>> from pfeie.linalg import factorize
>>> A = sp.csc_matrix(np.diag([2.0, 3.0, 4.0]))
>>> term = LowRankTerm(sp.csc_matrix(np.ones((3, 1))), np.array([[-1.0]]))
>>> F = UpdatedFactorization(factorize(A), term)
>>> b = np.array([1.0, 2.0, 3.0])
>>> bool(np.allclose((A.toarray() - 1.0) @ F.solve(b), b))
True
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from ..typing import FloatArray
from ._factor import Factorization

# the columns of U solved at once when Y = A⁻¹ U is formed (bounds the dense temporary)
_CHUNK = 64


@dataclass(frozen=True)
class LowRankTerm:
    """The symmetric term U B Uᵀ: U (n × r, sparse), B (r × r, dense, symmetric)."""

    U: sp.csc_matrix
    B: FloatArray

    @property
    def rank(self) -> int:
        return int(self.U.shape[1])

    def scaled(self, c: float) -> LowRankTerm:
        """The term c U B Uᵀ."""
        return LowRankTerm(self.U, c * self.B)

    def __matmul__(self, v: FloatArray) -> FloatArray:
        """U B Uᵀ v for v of shape (n,) or (n, m)."""
        return np.asarray(self.U @ (self.B @ np.asarray(self.U.T @ v)))


class UpdatedFactorization:
    """The factorisation of A + U B Uᵀ from a factorisation of A (Woodbury; see the
    module docstring). ``solve`` takes one or many right-hand sides, as the base does."""

    def __init__(self, base: Factorization, term: LowRankTerm) -> None:
        self.base, self.term = base, term
        self.backend, self.n = base.backend, base.n
        U = term.U
        cols = []
        for j in range(0, term.rank, _CHUNK):
            Yj = base.solve(U[:, j : j + _CHUNK].toarray())
            cols.append(sp.csc_matrix(Yj))  # exact zeros off the bodies' DOFs drop out
        self.Y = sp.hstack(cols, format="csc") if cols else sp.csc_matrix((self.n, 0))
        self._cap = sla.lu_factor(np.linalg.inv(term.B) + (U.T @ self.Y).toarray())

    def __deepcopy__(self, memo: dict[int, object]) -> UpdatedFactorization:
        return self  # never changes: copies of what holds it share it

    def solve(self, b: FloatArray) -> FloatArray:
        x = self.base.solve(b)
        z = sla.lu_solve(self._cap, np.asarray(self.term.U.T @ x))
        return np.asarray(x - self.Y @ z)


__all__ = ["LowRankTerm", "UpdatedFactorization"]
