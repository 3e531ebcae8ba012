"""Body frames for large rotations: rigid motion of each block plus small deformation.

Every floating body b (a block with no supports) carries a frame (c_b, R_b): the current
position of its mass centroid and a rotation. The frame is the best rigid placement of
the reference body in the current configuration in the mass norm (the Procrustes or
Kabsch fit)::

    R_b = argmin_R Σ_j m_j |x̄_j − R X̄_j|²,   X̄ = X − X_c,  x̄ = x − x_c,

with x = X + u the current nodal positions. In 2D the minimiser is the angle

    θ_b = atan2(Σ m (X̄ × x̄), Σ m X̄ · x̄);

in 3D it comes from the SVD of H = Σ m X̄ x̄ᵀ = U S Vᵀ: R = V diag(1, 1, det V Uᵀ) Uᵀ.

The deformation measured in the body frame (local displacement)

    ũ_j = R_bᵀ x_j − X_j      (a rigid translation remains, which K annihilates)

is small even when θ is large, so the reference stiffness K₀ applies to it: the elastic
force in the current configuration is Q K₀ ũ, and the tangent stiffness Q K₀ Qᵀ, with
Q the block-diagonal matrix of the nodal rotations (identity on supported bodies). Its
effective matrix is Q K̂₀ Qᵀ, whose inverse is Q K̂₀⁻¹ Qᵀ: the once-factorised blocks stay
valid for the whole run (method.md §2).

Axis convention: nodal fields are (n_points, d) or flat free-DOF vectors ordered
node-major (node·d + component); rotations are (n_bodies, d, d), R @ X maps body to
global coordinates.

Example
-------
A rigid rotation by 0.3 rad of a square is found exactly and leaves no deformation:

>>> import numpy as np, pfeie as pf
>>> from pfeie.model._frames import BodyFrames
>>> mesh = pf.rectangle(1.0, 1.0, 2, 2)
>>> model = pf.Model(mesh, [pf.Block("all", pf.Elastic(1e9, 0.2, 2000.0))])
>>> frames = BodyFrames(model, free=np.arange(model.n_dof))
>>> c, s = np.cos(0.3), np.sin(0.3)
>>> x = mesh.points @ np.array([[c, -s], [s, c]]).T
>>> u = (x - mesh.points).ravel()
>>> R = frames.rotations(u)
>>> round(float(frames.angles(R)[0]), 12)
0.3
>>> K = model.stiffness()
>>> float(np.abs(K @ u).max()) > 1e7        # K u: large spurious forces (N)
True
>>> float(np.abs(K @ frames.local_displacement(u, R)).max()) < 1e-4   # K ũ: none
True
"""

from __future__ import annotations

import numpy as np

from ..typing import FloatArray, IntArray
from ._model import Model


class BodyFrames:
    """Rigid frames of the floating bodies of a model (see the module docstring).

    Parameters
    ----------
    model: the model.
    free: the free DOFs (flat indices node·d + i); vectors passed to the methods are
        free-DOF vectors. Bodies with a prescribed DOF do not rotate (R = I).
    """

    def __init__(self, model: Model, free: IntArray) -> None:
        d = model.dim
        self.dim = d
        n_dof = model.n_dof
        body = model.body_of_node
        is_free = np.zeros(n_dof, dtype=bool)
        is_free[np.asarray(free)] = True
        pinned = np.zeros(model.n_bodies, dtype=bool)
        used = np.flatnonzero(body >= 0)
        node_pinned = ~is_free.reshape(-1, d)[used].all(axis=1)
        pinned[np.unique(body[used][node_pinned])] = True
        self.bodies: IntArray = np.flatnonzero(~pinned)  # the bodies that rotate
        nodes = np.flatnonzero(np.isin(body, self.bodies))
        self.nodes: IntArray = nodes
        compact = np.full(model.n_bodies, -1, dtype=np.int64)
        compact[self.bodies] = np.arange(self.bodies.size)
        self.body: IntArray = compact[body[nodes]]  # (k,) compact body of each node
        pos = np.full(n_dof, -1, dtype=np.int64)
        pos[np.asarray(free)] = np.arange(len(free))
        self.dofs: IntArray = pos[(nodes[:, None] * d + np.arange(d)).ravel()].reshape(-1, d)
        self.w: FloatArray = model.body_weights[nodes]
        self.X: FloatArray = model.mesh.points[nodes, :d]
        wsum = np.bincount(self.body, self.w, self.bodies.size)
        self._wsum = wsum
        self.Xc: FloatArray = self._sum(self.w[:, None] * self.X) / wsum[:, None]
        self.Xbar: FloatArray = self.X - self.Xc[self.body]

    @property
    def n(self) -> int:
        """Number of rotating bodies."""
        return int(self.bodies.size)

    def _sum(self, v: FloatArray) -> FloatArray:
        """Per-body sums of a nodal array (k, ...) → (n, ...)."""
        flat = v.reshape(v.shape[0], int(np.prod(v.shape[1:])))  # (k = 0 included)
        cols = [np.bincount(self.body, flat[:, j], self.n) for j in range(flat.shape[1])]
        return np.stack(cols, axis=1).astype(float).reshape(self.n, *v.shape[1:])

    def positions(self, u: FloatArray) -> FloatArray:
        """Current positions x = X + u (k, d) of the rotating nodes."""
        return self.X + np.asarray(u)[self.dofs]

    def centroids(self, u: FloatArray) -> FloatArray:
        """Current mass centroids c_b (n, d)."""
        return self._sum(self.w[:, None] * self.positions(u)) / self._wsum[:, None]

    def rotations(self, u: FloatArray) -> FloatArray:
        """R_b (n, d, d) of the mass-norm best rigid fit of the current configuration."""
        x = self.positions(u)
        xbar = x - self.centroids(u)[self.body]
        Xb, w = self.Xbar, self.w
        if self.dim == 2:
            cross = self._sum(w * (Xb[:, 0] * xbar[:, 1] - Xb[:, 1] * xbar[:, 0]))
            dot = self._sum(w * np.einsum("ki,ki->k", Xb, xbar))
            th = np.arctan2(cross, dot)
            c, s = np.cos(th), np.sin(th)
            return np.stack([np.stack([c, -s], -1), np.stack([s, c], -1)], -2)
        H = self._sum(w[:, None, None] * Xb[:, :, None] * xbar[:, None, :])
        U, _, Vt = np.linalg.svd(H)
        V = np.swapaxes(Vt, -1, -2)
        det = np.linalg.det(V @ np.swapaxes(U, -1, -2))
        D = np.broadcast_to(np.eye(3), H.shape).copy()
        D[:, 2, 2] = det
        return V @ D @ np.swapaxes(U, -1, -2)

    @staticmethod
    def angles(R: FloatArray) -> FloatArray:
        """Rotation of each body: θ (n,) in 2D (rad, counter-clockwise), the rotation
        vector θ·axis (n, 3) in 3D."""
        if R.shape[-1] == 2:
            return np.asarray(np.arctan2(R[:, 1, 0], R[:, 0, 0]))
        tr = np.clip((np.trace(R, axis1=1, axis2=2) - 1.0) / 2.0, -1.0, 1.0)
        th = np.arccos(tr)
        ax = np.stack([R[:, 2, 1] - R[:, 1, 2], R[:, 0, 2] - R[:, 2, 0], R[:, 1, 0] - R[:, 0, 1]],
                      axis=1)  # fmt: skip
        sin = np.sin(th)
        scale = np.where(sin > 1e-12, th / np.maximum(2.0 * sin, 1e-300), 0.5)
        return np.asarray(ax * scale[:, None])

    def rotate(self, v: FloatArray, R: FloatArray, transpose: bool = False) -> FloatArray:
        """Q v (or Qᵀ v) of a free-DOF vector or matrix (n_free, ...)."""
        out = np.array(v, dtype=float, copy=True)
        if not self.n:
            return out
        Rn = R[self.body]
        sub = out[self.dofs]  # (k, d, ...)
        eq = "kji,kj...->ki..." if transpose else "kij,kj...->ki..."
        out[self.dofs] = np.einsum(eq, Rn, sub)
        return out

    def local_displacement(self, u: FloatArray, R: FloatArray) -> FloatArray:
        """ũ: u on the bodies that do not rotate, R_bᵀ x − X on those that do."""
        out = np.array(u, dtype=float, copy=True)
        if self.n:
            x = self.positions(u)
            out[self.dofs] = np.einsum("kji,kj->ki", R[self.body], x) - self.X
        return out


__all__ = ["BodyFrames"]
