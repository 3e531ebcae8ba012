"""Corotation: finite rotations of floating blocks in body frames (method.md §2).

Each floating body carries a body frame R_b (the mass-norm best rigid fit of its current
configuration, :class:`pfeie.model.BodyFrames`). The elastic force is Q K₀ ũ with
ũ = R_bᵀ x − X the small deformation in the frame (Q the block-diagonal matrix of the
nodal rotations), and each step is the incremental Newmark step in the frames predicted
for t_{n+1}, where the elastic force is linear in x:

    Q K̂₀ Qᵀ Δu = f_{n+1} − Q K₀ (Qᵀ x_n − X) + M (a₂ v_n + a₃ a_n) + Q C₀ Qᵀ (a₄ v_n + a₅ a_n),

inverted as Q K̂₀⁻¹ Qᵀ with the once-factorised K̂₀ (so a step is still one
back-substitution). Pair frames turn with side a; W = (G Q) F (G Q)ᵀ comes from the
nodal flexibility F of the pair nodes (one multi-RHS solve at set-up), and only when the
rotations of the bodies at the pairs change. With T_k the frame of pair k, its turned
frame T_k R_aᵀ and Q the nodal rotations, the rows of G Q are T_k R_aᵀ(R_b u_b − R_a u_a)
= P_k T_k u_b − T_k u_a with P_k = T_k R_aᵀ R_b T_kᵀ: the side-a part of G Q is G_a, that
of the reference, and the side-b part P G_b, so W = H_a + P H_ba + H_ab Pᵀ + P H_b Pᵀ
(:class:`SideFlexibility`, the H formed once). W is not a congruence R W₀ Rᵀ of the
reference: the two sides of a pair whose blocks turn differently (or a block on a fixed
one) contribute their flexibilities in different frames. The interface solver of the
turned W refines on the last factorised W_c⁻¹ (:class:`pfeie.coupling.InterfaceStep`).

The frames are predicted, not iterated: the energy balance closes to the prediction
error (see docs/theory.md for the measured order).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import scipy.sparse as sp

from ..coupling import GatheredDelassus, NodalFlexibility, PairOperator
from ..linalg import Factorization
from ..model import BodyFrames, LinearSystem, Model
from ..typing import FloatArray, IntArray
from ._newmark import damping_product

log = logging.getLogger(__name__)


@dataclass
class SideFlexibility:
    """W = G̃ F G̃ᵀ split by the sides of the pairs, G = G_a + G_b (G_a: the columns of the
    nodes of side a, with their sign), for operators G̃ = G_a + P G_b whose side-b rows
    are turned by an orthogonal d × d matrix P_k per pair (block-diagonal P):

        W(P) = H_a + P H_ba + H_ab Pᵀ + P H_b Pᵀ,
        H_a = G_a F G_aᵀ,  H_ab = G_a F G_bᵀ = H_baᵀ,  H_b = G_b F G_bᵀ,

    formed once; W(P) then costs three block-diagonal products of M × M arrays (O(d M²)),
    not the products with the nodal flexibility F. The products go to work arrays kept
    between calls (fresh M × M arrays cost more to map than to fill). Memory: the three H
    and three work arrays, 6 M² doubles (17 MB at M = 600; 430 MB at M = 3,000, a 3D
    model of 1,000 pairs), beside W and its inverse.

    >>> import numpy as np, scipy.sparse as sp
    >>> F = np.array([[2.0, 0.5], [0.5, 1.0]])              # two DOFs, one 1D pair
    >>> Ga, Gb = sp.csr_matrix([[-1.0, 0.0]]), sp.csr_matrix([[0.0, 1.0]])
    >>> sf = SideFlexibility.build(F, Ga, Gb, 1)            # w = u₂ − u₁
    >>> float(sf.matrix(None)[0, 0]), float(sf.matrix(-np.ones((1, 1, 1)))[0, 0])
    (2.0, 4.0)
    """

    Ha: FloatArray
    Hba: FloatArray
    Hb: FloatArray
    d: int
    _work: list[FloatArray] = field(default_factory=list, repr=False)

    @classmethod
    def build(cls, F: FloatArray, Ga: sp.csr_matrix, Gb: sp.csr_matrix, d: int) -> SideFlexibility:
        """From the nodal flexibility F and the two sides' columns G_a, G_b (M × |F|)."""
        FGa = np.asarray(Ga @ F).T  # F G_aᵀ (F symmetric)
        FGb = np.asarray(Gb @ F).T
        Ha, Hb = np.asarray(Ga @ FGa), np.asarray(Gb @ FGb)
        return cls(0.5 * (Ha + Ha.T), np.asarray(Gb @ FGa), 0.5 * (Hb + Hb.T), d)

    def matrix(self, P: FloatArray | None) -> FloatArray:
        """W(P) (M, M) (a new array); None for P = I (the reference operators)."""
        if P is None:
            W = self.Ha + self.Hba
            W += self.Hba.T
            W += self.Hb
            return W
        M, m, d = self.Ha.shape[0], P.shape[0], self.d
        if not self._work:
            self._work = [np.empty((m, d, M)) for _ in range(3)]
        X, Y, Z = self._work
        np.matmul(P, self.Hba.reshape(m, d, M), out=X)  # P H_ba
        np.matmul(P, self.Hb.reshape(m, d, M), out=Y)  # P H_b
        Z.reshape(M, M)[...] = Y.reshape(M, M).T  # H_b Pᵀ
        np.matmul(P, Z, out=Y)  # P H_b Pᵀ
        Xm = X.reshape(M, M)
        W = self.Ha + Xm
        W += Xm.T
        W += Y.reshape(M, M)
        return W


class Corotation:
    """Body frames of the floating blocks and the operators that follow them.

    Parameters
    ----------
    model, system: the model and its free-DOF operators (lumped mass).
    factor: the factorised effective matrix K̂₀ of the reference configuration.
    op: the pair operator in the reference frames (None without pairs).
    """

    def __init__(
        self, model: Model, system: LinearSystem, factor: Factorization, op: PairOperator | None
    ) -> None:
        self.model, self.system, self.factor = model, system, factor
        self.frames = BodyFrames(model, system.free)
        if not self.frames.n:
            log.warning("large_rotation: every block has a support (a prescribed "
                        "component), so no block's frame rotates; the run is the "
                        "small-rotation one")  # fmt: skip
        self.d = model.dim
        self.op0 = op
        self._last: tuple[bytes, Any] | None = None
        self._last_rot: list[tuple[FloatArray, FloatArray]] = []
        self._last_strain: list[tuple[FloatArray, FloatArray, float]] = []
        # the free DOFs of the rotating nodes, one array per direction (for :meth:`rotate`)
        self._dof_cols = [np.ascontiguousarray(self.frames.dofs[:, j]) for j in range(self.d)]
        if op is None or not op.m:
            return
        P, d, fr = model.pairs, self.d, self.frames
        assert P is not None
        free = system.free
        pos = np.full(model.n_dof, -1, dtype=np.int64)
        pos[free] = np.arange(free.size)
        nodes = np.unique(np.concatenate([P.node_a, P.node_b]))
        dofs = pos[(nodes[:, None] * d + np.arange(d)).ravel()]
        I = dofs[dofs >= 0]
        self.flex = NodalFlexibility.build(factor, I, free.size)
        self._I = I
        loc = np.full(free.size, -1, dtype=np.int64)
        loc[I] = np.arange(I.size)
        on_pairs = np.isin(fr.nodes, nodes)
        self._I_rot: IntArray = loc[fr.dofs[on_pairs]]  # (k, d) positions in I of rotating nodes
        self._I_body: IntArray = fr.body[on_pairs]
        self._I_fix = np.setdiff1d(np.arange(I.size), self._I_rot.ravel())
        body = np.full(model.mesh.n_points, -1, dtype=np.int64)
        body[fr.nodes] = fr.body
        self.a_body: IntArray = body[P.node_a]  # frames turn with side a
        self.b_body: IntArray = body[P.node_b]
        # W split by the sides of the pairs: the columns of G on I of the nodes of side b
        Gi = op.G[:, I].tocoo()
        pair = Gi.row // d
        side_b = free[I[Gi.col]] // d == P.node_b[pair]
        Gs = [sp.csr_matrix((Gi.data[k], (Gi.row[k], Gi.col[k])), shape=Gi.shape)
              for k in (~side_b, side_b)]  # fmt: skip
        self.sides = SideFlexibility.build(self.flex.F, Gs[0], Gs[1], d)
        # the turned G and G_p share the structure of the reference ones: each stored
        # entry is ± one entry of the frames (m, d, d), found by building them from the
        # entry numbers 1, 2, ... (m·d·d) as frames
        ids = np.arange(1, P.n * d * d + 1, dtype=float).reshape(P.n, d, d)
        tag = PairOperator.build(P, op.n_dof, op.free, op.prescribed, ids)
        self._g_src = [(np.abs(M.data).astype(np.int64) - 1, np.sign(M.data), M)
                       for M in (tag.G, tag.Gp)]  # fmt: skip

    def reference_delassus(self) -> GatheredDelassus:
        """W in the reference frames, from the nodal flexibility (P = I)."""
        assert self.op0 is not None
        return GatheredDelassus(self.sides.matrix(None),
                                lambda X: self.factor.solve(self.op0.G.T @ X))  # type: ignore[union-attr]  # fmt: skip

    def _turned_op(self, frame: FloatArray) -> PairOperator:
        """The pair operator with the frames ``frame`` (m, d, d): the reference's structure
        with the entries ± frame (what :meth:`PairOperator.turned` builds)."""
        op0 = self.op0
        assert op0 is not None
        flat = frame.ravel()
        G, Gp = (sp.csr_matrix((sign * flat[src], M.indices, M.indptr), shape=M.shape)
                 for src, sign, M in self._g_src)  # fmt: skip
        return PairOperator(G, Gp, op0.m, op0.d, op0.pairs, op0.n_dof, op0.free, op0.prescribed)

    # -- frames ---------------------------------------------------------------------------
    def rotations(self, u: FloatArray) -> FloatArray:
        """R_b (n, d, d) of the configuration u (free DOFs). The step, the energy account
        and the recorder ask for the same vectors: the last four answers are kept (by
        identity: the states' vectors are never modified in place)."""
        for vec, R in self._last_rot:
            if vec is u:
                return R
        R = self.frames.rotations(u)
        self._last_rot = [(u, R), *self._last_rot[:3]]
        return R

    def _turn(self, R: FloatArray) -> sp.csr_matrix:
        """Q restricted to the pair DOFs I (sparse, block-diagonal by node)."""
        d = self.d
        k = self._I_rot.shape[0]
        rows = np.concatenate([self._I_fix, np.repeat(self._I_rot, d, axis=1).ravel()])
        cols = np.concatenate([self._I_fix, np.tile(self._I_rot, (1, d)).ravel()])
        vals = np.concatenate([np.ones(self._I_fix.size),
                               R[self._I_body].reshape(k, d * d).ravel()])  # fmt: skip
        n = self._I.size
        return sp.csr_matrix((vals, (rows, cols)), shape=(n, n))

    def pair_frames(self, R: FloatArray) -> FloatArray:
        """The pairs' frames (m, d, d) in the configuration of the body rotations R, those
        in which the pair forces are expressed: T_k R_aᵀ, turned with the body of side a
        (the reference T_k where side a does not turn)."""
        assert self.op0 is not None and self.op0.pairs is not None
        T0 = self.op0.pairs.frame
        turns = self.a_body >= 0
        if not turns.any():
            return T0
        Ra = np.broadcast_to(np.eye(self.d), (self.a_body.size, self.d, self.d)).copy()
        Ra[turns] = R[self.a_body[turns]]
        return np.asarray(T0 @ np.swapaxes(Ra, 1, 2))

    def operators(self, R: FloatArray) -> tuple[PairOperator, GatheredDelassus, bool] | None:
        """The pair operator with frames turned by R, its Delassus operator gathered from
        the nodal flexibility (the corrector through the rotated factor), and whether they
        changed since the last call; None without pairs. While the rotations of the bodies
        at the pairs do not change (none rotates, or the structure is at rest) the
        operators of the last call are returned."""
        if self.op0 is None or not self.op0.m:
            return None
        key = R[self._I_body].tobytes() + R[self.a_body[self.a_body >= 0]].tobytes()
        if self._last is not None and self._last[0] == key:
            op, W = self._last[1]
            return op, W, False
        turns = self.a_body >= 0
        Ra = np.broadcast_to(np.eye(self.d), (self.a_body.size, self.d, self.d)).copy()
        Ra[turns] = R[self.a_body[turns]]
        op = self.op0
        assert op.pairs is not None
        T0 = op.pairs.frame
        if turns.any():  # T_k ← T_k R_aᵀ
            op = self._turned_op(T0 @ np.swapaxes(Ra, 1, 2))
        # P_k = T_k R_aᵀ R_b T_kᵀ: the turn of side b in the turned frame of pair k
        Rb = np.broadcast_to(np.eye(self.d), Ra.shape).copy()
        on_b = self.b_body >= 0
        Rb[on_b] = R[self.b_body[on_b]]
        Pk = T0 @ np.swapaxes(Ra, 1, 2) @ Rb @ np.swapaxes(T0, 1, 2)
        W = self.sides.matrix(Pk)
        if self.flex.Y is not None:
            Gt = (op.G[:, self._I] @ self._turn(R)).tocsr()

            def correct(X: FloatArray) -> FloatArray:
                return self.rotate(self.flex.response(Gt.T @ X), R)
        else:

            def correct(X: FloatArray) -> FloatArray:
                return self.rotated_solve(op.G.T @ X, R)

        out = (op, GatheredDelassus(W, correct))
        self._last = (key, out)
        return out[0], out[1], True

    # -- forces and energies in the frames ----------------------------------------------------
    def rotated_solve(self, r: FloatArray, R: FloatArray) -> FloatArray:
        """(Q K̂₀ Qᵀ)⁻¹ r = Q K̂₀⁻¹ Qᵀ r: one back-substitution of the reference factor
        (one for all the columns of r (n, k))."""
        return self.rotate(self.factor.solve(self.rotate(r, R, transpose=True)), R)

    def rotate(self, v: FloatArray, R: FloatArray, transpose: bool = False) -> FloatArray:
        """Q v (or Qᵀ v) of a free-DOF vector v (n,) or matrix (n, k): the products of
        :meth:`BodyFrames.rotate` as d² multiply-adds of whole arrays, (Q v)_i =
        Σ_j R_ij v_j over the rotating nodes."""
        fr = self.frames
        if np.ndim(v) == 2:  # column by column: faster than on the (n, k) array
            return np.column_stack([self.rotate(c, R, transpose) for c in np.asarray(v).T])
        out = np.array(v, dtype=float, copy=True)
        if not fr.n:
            return out
        x = [out[c] for c in self._dof_cols]
        for i, ci in enumerate(self._dof_cols):
            acc = None
            for j, xj in enumerate(x):
                rij = (R[:, j, i] if transpose else R[:, i, j])[fr.body]
                if acc is None:
                    acc = rij * xj
                else:
                    acc += rij * xj
            out[ci] = acc
        return out

    def local_displacement(self, u: FloatArray, R: FloatArray) -> FloatArray:
        """ũ (:meth:`BodyFrames.local_displacement`): u on the bodies that do not rotate,
        R_bᵀ x − X on those that do (as :meth:`rotate`)."""
        fr = self.frames
        if not fr.n:
            return np.array(u, dtype=float, copy=True)
        x = np.array(u, dtype=float, copy=True)
        x[fr.dofs] = fr.positions(u)
        out = self.rotate(x, R, transpose=True)
        out[fr.dofs] -= fr.X
        return out

    def elastic_force(self, u: FloatArray, R: FloatArray | None = None) -> FloatArray:
        """Q K₀ ũ (N), ũ = Rᵀx − X in the frames R (default: those of u itself)."""
        R = self.rotations(u) if R is None else R
        return self.rotate(self.system.K @ self.local_displacement(u, R), R)

    def damping_force(
        self, v: FloatArray, u: FloatArray, R: FloatArray | None = None
    ) -> FloatArray:
        """Q C₀ Qᵀ v (N) with the frames R (default: those of the configuration u)."""
        if self.system.C is None:
            return np.zeros_like(v)
        R = self.rotations(u) if R is None else R
        return self.rotate(damping_product(self.system, self.rotate(v, R, transpose=True)), R)

    def strain_energy(self, u: FloatArray, R: FloatArray | None = None) -> float:
        """½ ũᵀ K₀ ũ in the body frames R (default: those of u) (J); the last four
        answers are kept (by identity of u and R, as :meth:`rotations`)."""
        R = self.rotations(u) if R is None else R
        for vec, Rv, value in self._last_strain:
            if vec is u and (Rv is R or np.array_equal(Rv, R)):
                return value
        ut = self.local_displacement(u, R)
        value = 0.5 * float(ut @ (self.system.K @ ut))
        self._last_strain = [(u, R, value), *self._last_strain[:3]]
        return value

    def angles(self, R: FloatArray) -> FloatArray:
        """Rotation of each rotating body (see :meth:`BodyFrames.angles`)."""
        return self.frames.angles(R)


__all__ = ["Corotation", "SideFlexibility"]
