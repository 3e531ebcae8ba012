"""Corotation: finite rotations of floating blocks in body frames (method.md §2).

Each floating body carries a body frame R_b (the mass-norm best rigid fit of its current
configuration, :class:`pfeie.model.BodyFrames`). The elastic force is Q K₀ ũ with
ũ = R_bᵀ x − X the small deformation in the frame (Q the block-diagonal matrix of the
nodal rotations), and each step is the incremental Newmark step in the frames predicted
for t_{n+1}, where the elastic force is linear in x:

    Q K̂₀ Qᵀ Δu = f_{n+1} − Q K₀ (Qᵀ x_n − X) + M (a₂ v_n + a₃ a_n) + Q C₀ Qᵀ (a₄ v_n + a₅ a_n),

inverted as Q K̂₀⁻¹ Qᵀ with the once-factorised K̂₀ (so a step is still one
back-substitution). Pair frames turn with side a; W = (G Q) F (G Q)ᵀ is gathered from the
nodal flexibility F of the pair nodes (one multi-RHS solve at set-up), and only when the
rotations of the bodies at the pairs change.

The frames are predicted, not iterated: the energy balance closes to the prediction
error (see docs/theory.md for the measured order).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.sparse as sp

from ..coupling import GatheredDelassus, NodalFlexibility, PairOperator
from ..linalg import Factorization
from ..model import BodyFrames, LinearSystem, Model
from ..typing import FloatArray, IntArray


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
        self.d = model.dim
        self.op0 = op
        self._last: tuple[bytes, Any] | None = None
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

    def reference_delassus(self) -> GatheredDelassus:
        """W in the reference frames, gathered from the nodal flexibility."""
        assert self.op0 is not None
        Gi = self.op0.G[:, self._I]
        return GatheredDelassus(np.asarray(Gi @ (Gi @ self.flex.F).T),
                                lambda X: self.factor.solve(self.op0.G.T @ X))  # type: ignore[union-attr]  # fmt: skip

    # -- frames ---------------------------------------------------------------------------
    def rotations(self, u: FloatArray) -> FloatArray:
        """R_b (n, d, d) of the configuration u (free DOFs)."""
        return self.frames.rotations(u)

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
        op = self.op0.turned(np.flatnonzero(turns), R[self.a_body[turns]]) if turns.any() \
            else self.op0  # fmt: skip
        Gt = (op.G[:, self._I] @ self._turn(R)).tocsr()
        W = self.flex.gather(Gt)
        if self.flex.Y is not None:

            def correct(X: FloatArray) -> FloatArray:
                return self.frames.rotate(self.flex.response(Gt.T @ X), R)
        else:

            def correct(X: FloatArray) -> FloatArray:
                return self.rotated_solve(op.G.T @ X, R)

        out = (op, GatheredDelassus(W, correct))
        self._last = (key, out)
        return out[0], out[1], True

    # -- forces and energies in the frames ----------------------------------------------------
    def rotated_solve(self, r: FloatArray, R: FloatArray) -> FloatArray:
        """(Q K̂₀ Qᵀ)⁻¹ r = Q K̂₀⁻¹ Qᵀ r: one back-substitution of the reference factor."""
        fr = self.frames
        return fr.rotate(self.factor.solve(fr.rotate(r, R, transpose=True)), R)

    def elastic_force(self, u: FloatArray, R: FloatArray | None = None) -> FloatArray:
        """Q K₀ ũ (N), ũ = Rᵀx − X in the frames R (default: those of u itself)."""
        R = self.frames.rotations(u) if R is None else R
        return self.frames.rotate(self.system.K @ self.frames.local_displacement(u, R), R)

    def damping_force(
        self, v: FloatArray, u: FloatArray, R: FloatArray | None = None
    ) -> FloatArray:
        """Q C₀ Qᵀ v (N) with the frames R (default: those of the configuration u)."""
        C = self.system.C
        if C is None:
            return np.zeros_like(v)
        R = self.frames.rotations(u) if R is None else R
        return self.frames.rotate(C @ self.frames.rotate(v, R, transpose=True), R)

    def strain_energy(self, u: FloatArray, R: FloatArray | None = None) -> float:
        """½ ũᵀ K₀ ũ in the body frames R (default: those of u) (J)."""
        R = self.frames.rotations(u) if R is None else R
        ut = self.frames.local_displacement(u, R)
        return 0.5 * float(ut @ (self.system.K @ ut))

    def angles(self, R: FloatArray) -> FloatArray:
        """Rotation of each rotating body (see :meth:`BodyFrames.angles`)."""
        return self.frames.angles(R)


__all__ = ["Corotation"]
