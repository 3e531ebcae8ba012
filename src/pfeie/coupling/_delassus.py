"""The Delassus operator W = G K̂⁻¹ Gᵀ: the interface flexibility (method.md §5.1).

W_kl is the relative displacement of pair k under a unit force on pair l, through the
once-factorised blocks K̂. It is built once from unit-load solves at the pair points (one
multi-right-hand-side back-substitution, in chunks) and reused every step. Besides W, the
step needs the block response to the pair forces, the corrector

    Δu = K̂⁻¹ Gᵀ X,

a product with the stored Z = K̂⁻¹ Gᵀ when Z is small, a back-substitution otherwise.

Storage strategies, behind the :class:`Delassus` protocol:

- :class:`DenseDelassus`: W dense (M × M, M = m·d); Z kept when n·M ≤ ``keep`` entries
  (default 1e6, 8 MB): above that the product costs as much as the solve (both stream
  about n·M or nnz(L) numbers);
- :class:`MatrixFreeDelassus`: Z kept, W never stored: W X = G (Z X); the dense W is
  formed only on request;
- :class:`BlockDelassus`: W stored per joint: the diagonal block of each joint dense, the
  coupling of two joints as a truncated SVD (kept singular values above ``rank_tol`` of
  the largest), exact to that tolerance; the interaction of distant joints through an
  elastic body is smooth, so it compresses;
- :class:`GatheredDelassus`: W gathered from a stored nodal flexibility (the pair nodes'
  block of K̂⁻¹) for pair frames that change, with no new solve (large rotations).

``delassus(factor, G, strategy=...)`` builds one. The same builder serves statics (with
the pinned stiffness, §5.2), dynamics (K̂) and the stiffness-scaled variants.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, Literal, Protocol

import numpy as np
import scipy.sparse as sp

from ..errors import ModelError
from ..linalg import Factorization, symmetric_product
from ..typing import FloatArray


class Delassus(Protocol):
    """The interface flexibility of a set of pairs (see the module docstring)."""

    @property
    def size(self) -> int:
        """M = m·d, the number of pair components."""
        ...

    def matrix(self) -> FloatArray:
        """W as a dense symmetric (M, M) array."""
        ...

    def apply(self, X: FloatArray) -> FloatArray:
        """W X for X (M,) or (M, k)."""
        ...

    def correct(self, X: FloatArray) -> FloatArray:
        """The block response Δu = K̂⁻¹ Gᵀ X (n,) to pair forces X (M,)."""
        ...


def _solve_columns(
    factor: Factorization, G: sp.csr_matrix, chunk: int, keep_z: bool, want_w: bool = True
) -> tuple[FloatArray, FloatArray | None]:
    """W = G K̂⁻¹ Gᵀ (symmetrised; empty unless ``want_w``) and optionally Z = K̂⁻¹ Gᵀ,
    column chunks at a time."""
    M, n = G.shape
    W = np.zeros((M, M) if want_w else (0, 0))
    Z = np.zeros((n, M)) if keep_z else None
    Gt = G.T.tocsc()
    for j0 in range(0, M, chunk):
        j1 = min(M, j0 + chunk)
        sol = factor.solve(Gt[:, j0:j1].toarray())
        if want_w:
            W[:, j0:j1] = G @ sol
        if Z is not None:
            Z[:, j0:j1] = sol
    return 0.5 * (W + W.T), Z


class _StoredW:
    """W held as a dense array: size, the matrix and its product."""

    def __deepcopy__(self, memo: dict[int, object]) -> Any:
        return self  # W never changes: copies of what holds it share it

    W: FloatArray

    @property
    def size(self) -> int:
        return int(self.W.shape[0])

    def matrix(self) -> FloatArray:
        return self.W

    def apply(self, X: FloatArray) -> FloatArray:
        return symmetric_product(self.W, X)


@dataclass
class DenseDelassus(_StoredW):
    """W stored dense; the corrector through Z or a back-substitution."""

    W: FloatArray
    Z: FloatArray | None
    factor: Factorization
    G: sp.csr_matrix
    _Gt: sp.csr_matrix | None = field(default=None, repr=False)

    def correct(self, X: FloatArray) -> FloatArray:
        if self.Z is not None:
            return np.asarray(self.Z @ X)
        if self._Gt is None:  # Gᵀ formed once (the same sums as G.T @ X)
            self._Gt = sp.csr_matrix(self.G.T.tocsr())
        return self.factor.solve(self._Gt @ X)


@dataclass
class MatrixFreeDelassus:
    """W applied through the stored Z = K̂⁻¹ Gᵀ: W X = G (Z X); O(n·M) memory, no M²."""

    Z: FloatArray
    G: sp.csr_matrix
    _W: FloatArray | None = field(default=None, repr=False)

    def __deepcopy__(self, memo: dict[int, object]) -> Any:
        return self  # W never changes: copies of what holds it share it

    @property
    def size(self) -> int:
        return int(self.G.shape[0])

    def matrix(self) -> FloatArray:
        if self._W is None:
            W = np.asarray(self.G @ self.Z)
            self._W = 0.5 * (W + W.T)
        return self._W

    def apply(self, X: FloatArray) -> FloatArray:
        return np.asarray(self.G @ (self.Z @ X))

    def correct(self, X: FloatArray) -> FloatArray:
        return np.asarray(self.Z @ X)


@dataclass
class BlockDelassus:
    """W per joint (see the module docstring): ``parts`` (M,) labels each component with
    its joint; ``blocks[(i, i)]`` dense, ``blocks[(i, j)]`` (i < j) the pair (U S, V) of the
    truncated SVD W_ij ≈ (U S) Vᵀ; the corrector by a back-substitution."""

    index: list[np.ndarray]
    diag: list[FloatArray]
    coupling: dict[tuple[int, int], tuple[FloatArray, FloatArray]]
    factor: Factorization
    G: sp.csr_matrix

    def __deepcopy__(self, memo: dict[int, object]) -> Any:
        return self  # W never changes: copies of what holds it share it

    @property
    def size(self) -> int:
        return int(self.G.shape[0])

    @property
    def stored(self) -> int:
        """Number of stored floats (against M² for the dense W)."""
        return sum(b.size for b in self.diag) + sum(a.size + b.size for a, b in
                                                    self.coupling.values())  # fmt: skip

    def matrix(self) -> FloatArray:
        W = np.zeros((self.size, self.size))
        for idx, B in zip(self.index, self.diag, strict=True):
            W[np.ix_(idx, idx)] = B
        for (i, j), (US, V) in self.coupling.items():
            Wij = US @ V.T
            W[np.ix_(self.index[i], self.index[j])] = Wij
            W[np.ix_(self.index[j], self.index[i])] = Wij.T
        return W

    def apply(self, X: FloatArray) -> FloatArray:
        out = np.zeros((self.size, *X.shape[1:]))
        for idx, B in zip(self.index, self.diag, strict=True):
            out[idx] += B @ X[idx]
        for (i, j), (US, V) in self.coupling.items():
            a, b = self.index[i], self.index[j]
            out[a] += US @ (V.T @ X[b])
            out[b] += V @ (US.T @ X[a])
        return out

    def correct(self, X: FloatArray) -> FloatArray:
        return self.factor.solve(self.G.T @ X)


@dataclass
class GatheredDelassus(_StoredW):
    """W = G̃ F G̃ᵀ gathered from the nodal flexibility F of the pair nodes, with the
    corrector given by the caller (e.g. through rotated frames)."""

    W: FloatArray
    corrector: Callable[[FloatArray], FloatArray]

    def correct(self, X: FloatArray) -> FloatArray:
        return self.corrector(X)


@dataclass(frozen=True)
class NodalFlexibility:
    """F = S K̂⁻¹ Sᵀ, the flexibility of the DOFs ``dofs`` (the pair nodes' DOFs), and
    Y = K̂⁻¹ Sᵀ when small; S selects ``dofs``. Any W = G̃ F G̃ᵀ with G̃ acting on these
    DOFs only is then a gather, and K̂⁻¹ Sᵀ y a product with Y (or a back-substitution)."""

    F: FloatArray
    Y: FloatArray | None
    dofs: np.ndarray
    factor: Factorization

    @classmethod
    def build(
        cls, factor: Factorization, dofs: np.ndarray, n: int, *, keep: float = 1e6
    ) -> NodalFlexibility:
        S = sp.csr_matrix((np.ones(dofs.size), (np.arange(dofs.size), dofs)),
                          shape=(dofs.size, n))  # fmt: skip
        F, Y = _solve_columns(factor, S, 256, n * dofs.size <= keep)
        return cls(F, Y, dofs, factor)

    def gather(self, Gt: sp.csr_matrix) -> FloatArray:
        """W = G̃ F G̃ᵀ for G̃ (M × |dofs|) acting on the selected DOFs."""
        return np.asarray(Gt @ (Gt @ self.F).T)

    def response(self, y: FloatArray) -> FloatArray:
        """K̂⁻¹ Sᵀ y (n,) for nodal forces y on the selected DOFs (or (n, k) for y (|dofs|,
        k))."""
        if self.Y is not None:
            return np.asarray(self.Y @ y)
        b = np.zeros((self.factor.n, *np.shape(y)[1:]))
        b[self.dofs] = y
        return self.factor.solve(b)


Strategy = Literal["auto", "dense", "matrix-free", "blocks"]


def delassus(
    factor: Factorization,
    G: sp.csr_matrix,
    *,
    strategy: Strategy = "auto",
    chunk: int = 256,
    keep: float = 1e6,
    parts: np.ndarray | None = None,
    rank_tol: float = 1e-12,
) -> DenseDelassus | MatrixFreeDelassus | BlockDelassus:
    """The Delassus operator of the pairs G (M × n) through the factor of K̂ (n × n).

    ``strategy``: "dense" (W stored; Z too when n·M ≤ ``keep``), "matrix-free" (Z stored,
    W applied as G Z X), "blocks" (per joint, ``parts`` (M,) the joint of each component;
    couplings compressed to ``rank_tol``), "auto" (= "dense").

    >>> import numpy as np, scipy.sparse as sp
    >>> from pfeie.linalg import factorize
    >>> K = sp.csr_matrix(np.array([[2.0, -1.0], [-1.0, 2.0]]))
    >>> G = sp.csr_matrix(np.array([[-1.0, 1.0]]))   # w = u₂ − u₁
    >>> W = delassus(factorize(K), G)
    >>> round(float(W.matrix()[0, 0]), 12)   # (1, −1)·(1/3)[[2, 1], [1, 2]]·(1, −1)ᵀ
    0.666666666667
    >>> mf = delassus(factorize(K), G, strategy="matrix-free")
    >>> bool(np.allclose(mf.apply(np.ones(1)), W.apply(np.ones(1))))
    True
    """
    M, n = G.shape
    if strategy == "blocks":
        if parts is None:
            raise ModelError("delassus: the 'blocks' strategy needs the joint of each "
                             "component (parts)")  # fmt: skip
        return _blocks(factor, G, np.asarray(parts), chunk, rank_tol)
    if strategy == "matrix-free":
        _, Z = _solve_columns(factor, G, chunk, True, want_w=False)
        assert Z is not None
        return MatrixFreeDelassus(Z, G)
    W, Z = _solve_columns(factor, G, chunk, n * M <= keep)
    return DenseDelassus(W, Z, factor, G)


def _blocks(
    factor: Factorization, G: sp.csr_matrix, parts: np.ndarray, chunk: int, rank_tol: float
) -> BlockDelassus:
    labels = np.unique(parts)
    index = [np.flatnonzero(parts == p) for p in labels]
    Gt = G.T.tocsc()
    diag: list[FloatArray] = []
    coupling: dict[tuple[int, int], tuple[FloatArray, FloatArray]] = {}
    scale = 0.0
    for j, cols in enumerate(index):
        Zj = np.hstack([factor.solve(Gt[:, cols[k : k + chunk]].toarray())
                        for k in range(0, cols.size, chunk)])  # fmt: skip
        Wj = np.asarray(G @ Zj)  # column block j: rows of every joint
        B = Wj[index[j]]
        diag.append(0.5 * (B + B.T))
        scale = max(scale, float(np.abs(np.diag(B)).max(initial=0.0)))
        for i in range(j):
            U, S, Vt = np.linalg.svd(Wj[index[i]], full_matrices=False)
            r = int((rank_tol * max(scale, S.max(initial=0.0)) < S).sum())
            coupling[(i, j)] = (U[:, :r] * S[:r], Vt[:r].T)
    return BlockDelassus(index, diag, coupling, factor, G)


__all__ = [
    "BlockDelassus",
    "Delassus", "DenseDelassus", "GatheredDelassus", "MatrixFreeDelassus", "NodalFlexibility",
    "delassus",
]  # fmt: skip
