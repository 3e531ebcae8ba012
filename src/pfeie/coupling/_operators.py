"""The pair operator G: block displacements → relative displacements of the pairs.

For pair k joining node a(k) (side a) and node b(k) (side b) with local frame T_k
(rows t₁, [t₂,] n; local = T_k · global),

    w_k = T_k (u_b(k) − u_a(k)),      w = G u,

row k·d + i of G holds component i of pair k (method.md §4). G is split into its columns
on the free DOFs (G_f, acting on the unknowns of the blocks) and on the prescribed DOFs
(G_p, through which supports, or a moving base, move the pairs):

    w = G_f u_f + G_p u_p.

Its transpose maps pair forces to nodal forces: the force X_k on side b (local frame)
loads the blocks with Gᵀ X (+T_kᵀX_k on node b, −T_kᵀX_k on node a).

Body-frame variant (large rotations): the frames of pairs whose side a turns with a block
of rotation R are T_k Rᵀ, so gaps and slips are measured in the turned frames
(:meth:`PairOperator.turned`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import scipy.sparse as sp

from ..interface import PairGeometry
from ..typing import FloatArray, IntArray


def relative_operator(
    pairs: PairGeometry | None, n_dof: int, frame: FloatArray | None = None
) -> sp.csr_matrix:
    """G (m·d × n_dof) on all DOFs (node-major); ``frame`` (m, d, d) replaces the pair
    frames (e.g. frames that turn with a block).

    >>> import pfeie as pf
    >>> mesh = pf.rectangle(1.0, 2.0, 1, 2)
    >>> _ = mesh.add_facet_group("j", lambda x: abs(x[:, 1] - 1.0) < 1e-9, False)
    >>> model = pf.Model(mesh, [pf.Block("all", pf.Elastic(1e9, 0.2, 1e3))],
    ...                  interfaces=[pf.Interface("j", pf.Joint())])
    >>> G = relative_operator(model.pairs, model.n_dof)
    >>> G.shape, float(abs(G).sum())        # 2 pairs × 2 components, ±1 entries
    ((4, 16), 8.0)
    """
    if pairs is None:
        return sp.csr_matrix((0, n_dof))
    d = pairs.dim
    m = pairs.n
    rows = np.repeat(np.arange(m * d), d)
    cols_b = (pairs.node_b[:, None, None] * d + np.arange(d)[None, None, :]).repeat(d, axis=1)
    cols_a = (pairs.node_a[:, None, None] * d + np.arange(d)[None, None, :]).repeat(d, axis=1)
    # (m, i, j): component i of the local vector from global j
    vals = pairs.frame if frame is None else np.asarray(frame, dtype=float)
    G = sp.coo_matrix(
        (np.concatenate([vals.ravel(), -vals.ravel()]),
         (np.concatenate([rows, rows]), np.concatenate([cols_b.ravel(), cols_a.ravel()]))),
        shape=(m * d, n_dof),
    )  # fmt: skip
    return G.tocsr()


@dataclass(frozen=True)
class PairOperator:
    """G split on the free and prescribed DOFs (see the module docstring).

    ``G`` (M × n_free), ``Gp`` (M × n_pres), M = m·d; ``m`` pairs of dimension ``d``.
    """

    G: sp.csr_matrix
    Gp: sp.csr_matrix
    m: int
    d: int
    pairs: PairGeometry | None
    n_dof: int
    free: IntArray
    prescribed: IntArray

    @classmethod
    def build(
        cls,
        pairs: PairGeometry | None,
        n_dof: int,
        free: IntArray,
        prescribed: IntArray,
        frame: FloatArray | None = None,
    ) -> PairOperator:
        """G of the pairs, split on ``free`` and ``prescribed`` DOFs."""
        G = relative_operator(pairs, n_dof, frame)
        m = 0 if pairs is None else pairs.n
        d = 1 if pairs is None else pairs.dim
        return cls(G[:, free].tocsr(), G[:, prescribed].tocsr(), m, d, pairs, n_dof, free,
                   prescribed)  # fmt: skip

    def turned(self, turns: IntArray, R: FloatArray) -> PairOperator:
        """The operator with the frames of the pairs ``turns`` (k,) turned by the
        rotations R (k, d, d) of their side a: T_k ← T_k R_kᵀ."""
        assert self.pairs is not None
        T = self.pairs.frame.copy()
        T[turns] = np.einsum("kij,klj->kil", T[turns], R)
        return PairOperator.build(self.pairs, self.n_dof, self.free, self.prescribed, T)

    @cached_property
    def Gt(self) -> sp.csr_matrix:
        """G_fᵀ (n_free × M), formed once: pair forces → nodal forces on the free DOFs
        (the same sums, in the same order, as ``G.T @ X``)."""
        return sp.csr_matrix(self.G.T.tocsr())

    def relative(self, u: FloatArray, u_pres: FloatArray | None = None) -> FloatArray:
        """w (m, d) = G_f u (+ G_p u_p) of free-DOF displacements u."""
        w = self.G @ u
        if u_pres is not None:
            w = w + self.Gp @ u_pres
        return np.asarray(w).reshape(self.m, self.d)

    def w_prescribed(self, u_pres: FloatArray) -> FloatArray:
        """G_p u_p (M,): the relative motion the prescribed DOFs give the pairs."""
        if not self.prescribed.size:
            return np.zeros(self.G.shape[0])
        return np.asarray(self.Gp @ u_pres)

    def mass_delassus(
        self, comps: IntArray, *, minv: FloatArray | sp.spmatrix | None = None,
        mass_solve: Callable[[FloatArray], FloatArray] | None = None,
    ) -> FloatArray:  # fmt: skip
        """W_m = G_c M⁻¹ G_cᵀ (dense, k × k) of the pair components ``comps`` (G_c their
        rows of G): the operator of an acceleration-level pair problem on the mass alone
        (the consistent start acceleration of a time stepping). M⁻¹ is given as the
        lumped mass's inverse ``minv`` (n,), zero on massless DOFs, or as a sparse matrix
        (a mass block-diagonal by node, inverted node by node), or by ``mass_solve`` (a
        coupled mass: M⁻¹ applied to the columns of G_cᵀ)."""
        Gc = self.G[comps]
        if mass_solve is not None:
            return np.asarray(Gc @ mass_solve(Gc.T.toarray()))
        if sp.issparse(minv):
            return np.asarray((Gc @ minv @ Gc.T).toarray())
        assert minv is not None
        return np.asarray((Gc @ (Gc.multiply(np.asarray(minv)[None, :]).T)).toarray())


__all__ = ["PairOperator", "relative_operator"]
