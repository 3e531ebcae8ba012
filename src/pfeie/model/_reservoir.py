"""The finite-element reservoir: incompressible water on a mesh of its own, condensed onto
the dam's wet face as a full added-mass matrix (Kuo 1982). Two-dimensional.

Theory
------
The water is inviscid and incompressible and moves little; its hydrodynamic pressure p (Pa,
positive in compression, on top of the hydrostatic pressure) obeys

    ∇²p = 0                      in the water Ω,
    p = 0                        on the free surface (surface waves neglected),
    ∂p/∂n_Ω = 0                  on the bottom (rigid),
    p = 0                        at the far end, a distance L upstream (truncation),
    ∂p/∂n_Ω = ρ_w ü·n            on the wet face Γ,

where n_Ω is the unit normal out of the water and n = −n_Ω the one out of the dam: a face
that accelerates towards the water (ü·n > 0) compresses it (Euler: ρ_w ∂v/∂t = −∇p).
Galerkin with the shape functions N_i of the water mesh gives

    H p = ρ_w Q ü,   H_ij = ∫_Ω ∇N_i·∇N_j dΩ,   Q_{i,(b,k)} = ∫_Γ N_i N_b n_k dΓ,

N_b being the shape functions of the dam's wet facets and ü the accelerations of their
nodes (global DOF b·d + k). The pressure pushes on the dam with the traction −p n, i.e. the
nodal forces f = −Qᵀ p = −M_a ü: the water is the added mass

    M_a = ρ_w t Qᵀ H⁻¹ Q      (kg; symmetric, positive semi-definite),

H restricted to the nodes where p is free (not the surface, not the far end), t the model's
thickness in 2D. M_a is dense over the wet DOFs and couples the two components of a node
and of neighbouring nodes (for an inclined face a horizontal acceleration also gives a
vertical force). The water mesh shares the geometry of the dam's wet facets: its nodes on
Γ are the points of the facets (each facet cut into ``refine`` pieces), and Q is integrated
on the facets with the dam's own shape functions, so that faces whose nodes are split by
joints, and the facet cut by the water level, need no special case.

Mesh. A structured mesh of quadrilaterals (Q4 on linear faces, Q9 on quadratic ones), the
same order as the dam's faces: its rows are horizontal lines through the points of the
wet face, from the face to a vertical far end at a distance L (default 3 H) upstream of the
most upstream point of the face; the columns are as wide as the face's pieces are tall next
to the face and, for Q9, grow by 1.2 up to H/4 (Q4 cells stay square). Setting it up costs
a sparse factorisation of the water's Laplacian and one solve a face node (e.g. 1 s for
256 face nodes and 14 000 water nodes).

Truncation. With p = 0 at the far end, the pressure of the k-th vertical mode cos(λ_k z) of
a vertical face is multiplied by tanh(λ_k L), λ_k = (2k − 1)π/(2H), so the relative error of
the added mass is at most 1 − tanh(πL/(2H)) ≈ 2 e^{−πL/H}: 1.6e-4 for L = 3 H (measured in
tests/test_reservoir.py: doubling L changes the added mass by less than 2e-4).

Units: SI (m, kg, s, Pa). References: Westergaard (1933), Trans. ASCE 98, 418-433; Kuo
(1982), Fluid-structure interactions: added mass computations for incompressible fluid,
UCB/EERC-82/09; Zangar (1953), USBR Engineering Monograph 11.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import scipy.sparse as sp

from .. import assembly as asm
from ..element import quadrature, reference
from ..errors import MeshError, ModelError
from ..linalg import Factorization, factorize
from ..mesh import Mesh
from ..typing import FloatArray, IntArray

#: the most nodes of the water mesh: its condensation onto the face takes about 25 s at
#: 480,000 (measured; 2.5 s at 120,000, the time grows as the square), and more is a refine
#: or a length beyond any need (a reservoir 5 depths long on a face of 1000 pieces holds
#: about 1e5)
WATER_NODES_MAX = 500_000

#: growth of the water columns' widths away from the face; their largest width, as a
#: fraction of H and as a multiple of the first one, by element order: Q9 columns grow to
#: H/4 (the far field's share of the error is then about 2e-6 of the added mass);
#: bilinear cells stay square (columns of H/4 would hold the error near 1e-3)
_GROWTH = 1.2
_WIDEST = 0.25
_SPAN = {1: 1.0, 2: np.inf}


class Reservoir:
    """An incompressible finite-element reservoir on a dam's wet face (2D), condensed to
    an added-mass matrix (see the module's docstring for the equations).

    Built by :meth:`pfeie.Model.add_reservoir`, which hands it the wet facets.

    Parameters
    ----------
    points: the dam mesh's points (n, 2), m.
    facets: the wet facets as (facet type, connectivity (f, n), outward sign (f,)): +1
        where the normal of the facet's node order (t_y, −t_x) points out of the dam, −1
        otherwise. Linear ("line") or quadratic ("line3") facets, one type.
    water_level: the elevation h of the free surface (m, on the vertical axis y).
    n_dof: the number of DOFs of the dam model (2 per point).
    density: the water density ρ_w (kg/m³).
    thickness: the model's out-of-plane thickness t (m).
    length: the reservoir length L (m) from the most upstream point of the wet face to
        the far end; default 3 H.
    refine: each wet facet is cut into this many pieces of the water mesh (≥ 1).

    Attributes
    ----------
    mesh: the water mesh (cell group ``water``; facet groups ``wet``, ``surface``,
        ``bottom``, ``far``), e.g. for ParaView (``reservoir.mesh.to_meshio()``).
    bottom, depth, length: the bottom elevation z_b (the lowest point of the wet faces),
        H = h − z_b and L (m).
    dofs: the wet DOFs of the dam (node · 2 + component), sorted.
    matrix: M_a on :attr:`dofs` (dense, kg).
    face: the water mesh's nodes on the wet face, from the bottom up.

    Example
    -------
    A rigid vertical face 10 m deep accelerated by 1 m/s² towards the water: the force is
    Westergaard's exact 14 ζ(3)/π³ ρ_w a H² = 0.5428 ρ_w a H² (per metre):

    >>> import numpy as np, pfeie as pf
    >>> m = pf.Model(pf.rectangle(1.0, 10.0, 1, 16, cell="quad8"),
    ...              [pf.Block("all", pf.Elastic(30e9, 0.2, 2400.0))])
    >>> res = m.add_reservoir("xmin", water_level=10.0)
    >>> a = np.zeros(m.n_dof); a[0::2] = -1.0        # towards the water (at x < 0)
    >>> force = float(-(m.added_mass_matrix() @ a)[0::2].sum())   # N, along +x
    >>> round(force / (1000.0 * 10.0**2), 4)     # 2.5e-4 below: the mesh and the length
    0.5426
    >>> p = res.pressure(a)[res.face]           # Pa, bottom up: 0.7425 ρ_w a H at the bottom
    >>> round(float(p[0]) / (1000.0 * 10.0), 4), float(p[-1])
    (0.7423, 0.0)
    """

    def __init__(
        self,
        points: FloatArray,
        facets: Sequence[tuple[str, IntArray, FloatArray]],
        water_level: float,
        *,
        n_dof: int,
        density: float = 1000.0,
        thickness: float = 1.0,
        length: float | None = None,
        refine: int = 1,
    ) -> None:
        points = np.asarray(points, dtype=float)
        if points.shape[1] != 2:
            raise ModelError("reservoir: the finite-element reservoir is 2D only; in 3D use "
                             "Westergaard's added mass (add_westergaard; model = 'westergaard' "
                             "in a model file)")  # fmt: skip
        if not (np.isfinite(density) and density > 0):
            raise ModelError(f"reservoir: the water density must be > 0 kg/m³, got {density}")
        if not (isinstance(refine, int | np.integer) and refine >= 1):
            shown = refine.item() if isinstance(refine, np.generic) else refine
            raise ModelError(f"reservoir: refine must be an integer >= 1, got {shown!r}")
        if not np.isfinite(water_level):
            raise ModelError(f"reservoir: the water level must be finite, got {water_level}")
        self.density = float(density)
        self.thickness = float(thickness)
        self.level = float(water_level)
        self.refine = int(refine)
        self.n_dof = int(n_dof)
        ftype, X, conn, t_lo, t_hi, sign = _chain(points, facets, self.level)
        self.bottom = float(_on_facets(ftype, X[:1], t_lo[:1, None])[0][0, 0, 1])
        self.depth = H = self.level - self.bottom
        if length is None:
            length = 3.0 * H
        if not (np.isfinite(length) and length > 0):
            raise ModelError(f"reservoir: the length must be > 0 m, got {length}")
        self.length = float(length)
        p = reference(ftype).degree
        # the face: the points of every facet from its lower end t_lo to its upper end
        # t_hi (the level on the facet the surface cuts), `refine` pieces a facet
        r = self.refine
        s = np.linspace(0.0, 1.0, p * r + 1)
        T = t_lo[:, None] + (t_hi - t_lo)[:, None] * s[None, :]  # (F, p r + 1)
        xs, tangent, _ = _on_facets(ftype, X, T)
        column = np.concatenate([xs[:, :-1].reshape(-1, 2), xs[-1:, -1]])  # bottom → top
        column[-1, 1] = self.level
        # the side of the water: along the facets' outward normals
        nx = sign[:, None] * tangent[..., 1]  # n_x |dx/dt| at the points
        side = float(np.sign((nx * np.abs(t_hi - t_lo)[:, None]).sum()))
        if side == 0.0 or not np.any(np.abs(nx) > 1e-12 * H):
            raise ModelError("reservoir: the wet faces face no water sideways (horizontal "
                             "faces); expected the dam's upstream face")  # fmt: skip
        far = side * (float((side * column[:, 0]).max()) + self.length)
        self.mesh, ij = _water_mesh(column, far, p, _face_size(column), H)
        NI, NJ = ij
        ids = np.arange(NI * NJ).reshape(NI, NJ)
        self.face: IntArray = ids[0].copy()
        pts = self.mesh.points
        ctype = "quad" if p == 1 else "quad9"
        conn_w = self.mesh.cells[ctype]
        try:
            cv = asm.cell_values(pts, ctype, conn_w, asm.stiffness_degree(ctype) + 2)
        except MeshError:
            raise ModelError("reservoir: the water mesh drawn from the wet face has inverted "
                             "cells (the far end, at the given length, cuts the water?); "
                             "expected a face that rises from the bottom to the water "
                             "level with the water on one side") from None  # fmt: skip
        Ke = np.einsum("cq,cqad,cqbd->cab", cv.dV, cv.dNdx, cv.dNdx)
        Hm = asm.assemble_matrix(conn_w, Ke, pts.shape[0])
        fixed = np.zeros((NI, NJ), dtype=bool)
        fixed[:, -1] = True  # the free surface
        fixed[-1, :] = True  # the far end
        self._free: IntArray = np.flatnonzero(~fixed.ravel())
        Q = _coupling(ftype, X, conn, T, sign, self.face, p, pts.shape[0], self.n_dof)
        Qf = Q[self._free].tocsc()
        Qf.eliminate_zeros()  # e.g. the y DOFs of a vertical face
        self.dofs: IntArray = np.flatnonzero(np.diff(Qf.indptr) > 0).astype(np.int64)
        self._Q = Qf[:, self.dofs].tocsr()
        Hff = Hm[self._free][:, self._free].tocsc()
        self._factor: Factorization = factorize(Hff, spd=True)
        # M_a = ρ_w t Q_Γᵀ (H⁻¹)_ΓΓ Q_Γ, Γ the free water nodes on the face: the face block
        # of H⁻¹, solved for a few columns at a time (memory: free nodes × 128)
        gamma = np.flatnonzero(np.diff(self._Q.indptr) > 0)
        Hinv = np.empty((gamma.size, gamma.size))
        for c in range(0, gamma.size, 128):
            cols = gamma[c : c + 128]
            E = np.zeros((self._free.size, cols.size))
            E[cols, np.arange(cols.size)] = 1.0
            Hinv[:, c : c + cols.size] = self._factor.solve(E).reshape(E.shape)[gamma]
        Qg = self._Q[gamma].toarray()
        Ma = self.density * self.thickness * (Qg.T @ Hinv @ Qg)
        self.matrix: FloatArray = 0.5 * (Ma + Ma.T)

    # -- the added mass -------------------------------------------------------------------
    def full(self) -> sp.csr_matrix:
        """M_a on all the dam's DOFs (n_dof × n_dof, kg; non-zero on the wet block)."""
        w = self.dofs
        rows = np.repeat(w, w.size)
        cols = np.tile(w, w.size)
        return sp.csr_matrix((self.matrix.ravel(), (rows, cols)), shape=(self.n_dof,) * 2)

    def lumped(self) -> FloatArray:
        """The added mass lumped on the diagonal (n_dof,), kg: each DOF gets the row sum
        of M_a over the DOFs of its own component, m_(a,k) = Σ_b M_a[(a,k),(b,k)], the
        force along k on node a under a unit acceleration of the whole face along k. A
        negative sum (a quadratic facet's corner node where the pressure varies fast, e.g.
        above the water on the facet the surface cuts) is set to 0 and the others of its
        component scaled to keep their total, 1ᵀ M_a 1 along x and along y. Lumping drops
        the coupling between components (the vertical force a horizontal acceleration
        gives an inclined face) and the spreading of the pressure of one node's motion
        over the face (a flexible dam's modes)."""
        out = np.zeros(self.n_dof)
        comp = self.dofs % 2
        for k in range(2):
            sel = np.flatnonzero(comp == k)
            rows = self.matrix[np.ix_(sel, sel)].sum(axis=1)
            kept = np.maximum(rows, 0.0)
            if kept.sum() > 0:
                kept *= max(rows.sum(), 0.0) / kept.sum()
            out[self.dofs[sel]] = kept
        return out

    # -- pressures ------------------------------------------------------------------------
    def pressure(self, acceleration: FloatArray) -> FloatArray:
        """The hydrodynamic pressure (Pa, compression positive) at the water mesh's
        points for the dam's nodal accelerations (m/s²; a vector of n_dof or an array
        (n_points, 2)): p = ρ_w H⁻¹ Q ü, zero on the surface and at the far end.
        ``pressure(a)[reservoir.face]`` is the pressure on the wet face, bottom up."""
        a = np.asarray(acceleration, dtype=float).ravel()
        if a.size != self.n_dof:
            raise ModelError(f"reservoir.pressure: expected {self.n_dof} accelerations, got "
                             f"{a.size}")  # fmt: skip
        out = np.zeros(self.mesh.n_points)
        rhs = self.density * (self._Q @ a[self.dofs])
        out[self._free] = self._factor.solve(rhs).ravel()
        return out


def _on_facets(
    ftype: str, X: FloatArray, t: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Points x (F, K, 2), tangents dx/dt (F, K, 2) and shape functions (F, K, n) of F
    facets of nodes X (F, n, 2) at reference coordinates t (F, K) in [−1, 1]."""
    F, K = t.shape
    N, dN = reference(ftype).shape_functions(t.reshape(-1, 1))
    N = N.reshape(F, K, -1)
    dN = dN[..., 0].reshape(F, K, -1)
    return np.einsum("fkn,fnd->fkd", N, X), np.einsum("fkn,fnd->fkd", dN, X), N


def _chain(
    points: FloatArray, facets: Sequence[tuple[str, IntArray, FloatArray]], level: float
) -> tuple[str, FloatArray, IntArray, FloatArray, FloatArray, FloatArray]:
    """The wet facets below the water level as one chain from the bottom up: the facet
    type, nodes X (F, n, 2), connectivity (F, n), the reference coordinates of their lower
    ends t_lo and of their upper ends or of the water level t_hi (F,), and outward signs."""
    types = {ft for ft, c, _ in facets if c.shape[0]}
    if not types:
        raise ModelError("reservoir: the wet face groups hold no facets")
    if len(types) > 1 or not types <= {"line", "line3"}:
        raise ModelError(f"reservoir: expected wet facets of one type, line or line3, got "
                         f"{sorted(types)}")  # fmt: skip
    ftype = types.pop()
    conn = np.concatenate([c for ft, c, _ in facets if c.shape[0]]).astype(np.int64)
    sign = np.concatenate([np.asarray(o, dtype=float) for _, c, o in facets if c.shape[0]])
    X = points[conn]  # (F, n, 2)
    extent = float(np.ptp(points, axis=0).max()) or 1.0
    tol = 1e-9 * max(extent, abs(level))
    z0, z1 = X[:, 0, 1], X[:, 1, 1]
    flat = np.abs(z1 - z0) <= tol
    if flat.any():
        x = X[np.flatnonzero(flat)[0], :2].mean(axis=0)
        raise ModelError(f"reservoir: a horizontal wet facet at {np.round(x, 6).tolist()}; the "
                         "finite-element reservoir needs a wet face that rises from the bottom "
                         "to the water level")  # fmt: skip
    up = z1 > z0
    t_lo = np.where(up, -1.0, 1.0)
    t_hi = -t_lo
    zlo, zhi = np.minimum(z0, z1), np.maximum(z0, z1)
    order = np.argsort(zlo, kind="stable")
    X, conn, t_lo, t_hi, sign = X[order], conn[order], t_lo[order], t_hi[order], sign[order]
    zlo, zhi = zlo[order], zhi[order]
    lo_pt = np.where(up[order, None], X[:, 0], X[:, 1])
    hi_pt = np.where(up[order, None], X[:, 1], X[:, 0])
    if not level > zlo[0] + tol:
        raise ModelError(f"reservoir: the water level {level} m must lie above the lowest "
                         f"point of the wet faces, z = {zlo[0]:.6g} m (the reservoir "
                         "bottom)")  # fmt: skip
    gap = np.linalg.norm(lo_pt[1:] - hi_pt[:-1], axis=1) > tol
    wet = zlo < level - tol
    broken = np.flatnonzero(gap & wet[1:])
    if broken.size:
        k = int(broken[0])
        raise ModelError(
            f"reservoir: the wet faces do not form one chain from the bottom up: the facet "
            f"ending at {np.round(hi_pt[k], 6).tolist()} is followed by one starting at "
            f"{np.round(lo_pt[k + 1], 6).tolist()}; expected one face (overlapping, "
            "branching or disjoint faces are not supported)"
        )
    keep = np.flatnonzero(wet)
    X, conn, t_lo, t_hi, sign = X[keep], conn[keep], t_lo[keep], t_hi[keep], sign[keep]
    top = zhi[keep[-1]]
    if top < level - tol:
        raise ModelError(f"reservoir: the water level {level} m is above the top of the wet "
                         f"faces, z = {top:.6g} m; expected a face up to the water "
                         "level")  # fmt: skip
    if top > level + tol:  # the surface cuts the last facet: t_hi where z(t) = level
        a, b = float(t_lo[-1]), float(t_hi[-1])
        za, zb = float(zlo[keep[-1]]), float(top)
        t = np.array([[a + (b - a) * (level - za) / (zb - za)]])
        for _ in range(30):  # Newton (exact in one step on a straight facet)
            x, dx, _ = _on_facets(ftype, X[-1:], t)
            step = (x[0, 0, 1] - level) / dx[0, 0, 1]
            t = t - step
            if abs(step) < 1e-14:
                break
        t_hi = t_hi.copy()
        t_hi[-1] = float(t[0, 0])
    return ftype, X, conn, t_lo, t_hi, sign


def _face_size(column: FloatArray) -> float:
    """The mean length of the face's pieces between vertices."""
    seg = np.linalg.norm(np.diff(column, axis=0), axis=1)
    return float(seg.sum()) / max(seg.size, 1)


def _water_mesh(
    column: FloatArray, far: float, p: int, size: float, H: float
) -> tuple[Mesh, tuple[int, int]]:
    """The structured water mesh between the face's points ``column`` (bottom → top, the
    nodes of order-p pieces) and the vertical line x = ``far``; returns it and its node
    grid's shape (columns of points away from the face, points a column)."""
    D = float(np.abs(far - column[:, 0]).mean())
    h0 = p * size  # the width of the first column: the face pieces' length
    wide = max(min(_WIDEST * H, _SPAN[p] * h0), h0)
    n_grow = int(np.ceil(np.log(wide / h0) / np.log(_GROWTH))) + 1 if wide > h0 else 0
    with np.errstate(over="ignore"):  # (the growth beyond `wide` is cut at it)
        widths = np.minimum(h0 * _GROWTH ** np.arange(n_grow + int(np.ceil(D / wide)) + 2),
                            wide)  # fmt: skip
    n = int(np.searchsorted(np.cumsum(widths), D)) + 1
    widths = widths[:n]
    xi_v = np.concatenate([[0.0], np.cumsum(widths)]) / widths.sum()
    if p == 2:
        xi = np.empty(2 * xi_v.size - 1)
        xi[0::2] = xi_v
        xi[1::2] = 0.5 * (xi_v[:-1] + xi_v[1:])
    else:
        xi = xi_v
    NI, NJ = xi.size, column.shape[0]
    if NI * NJ > WATER_NODES_MAX:  # (before the arrays that would fill the memory)
        raise ModelError(
            f"reservoir: the water mesh would have {NI} × {NJ} = {NI * NJ:.3g} nodes, more "
            f"than {WATER_NODES_MAX:.0e}: expected a smaller refine (pieces a wet facet) or "
            f"length ({D:.4g} m from the face; 3 to 5 depths, H = {H:.4g} m, reach the "
            "far-field)"
        )
    far_pts = np.column_stack([np.full(NJ, far), column[:, 1]])
    pts = column[None] + xi[:, None, None] * (far_pts - column)[None]
    ids = np.arange(NI * NJ).reshape(NI, NJ)
    I = p * np.arange(n)
    J = p * np.arange((NJ - 1) // p)
    Ig, Jg = (g.ravel() for g in np.meshgrid(I, J, indexing="ij"))
    flip = far < column[:, 0].mean()  # the water at −x: i runs towards −x
    if p == 1:
        corners = [(0, 0), (1, 0), (1, 1), (0, 1)]
        if flip:
            corners = [(0, 0), (0, 1), (1, 1), (1, 0)]
        ctype, offs = "quad", corners
    else:
        if not flip:
            offs = [(0, 0), (2, 0), (2, 2), (0, 2), (1, 0), (2, 1), (1, 2), (0, 1), (1, 1)]
        else:
            offs = [(0, 0), (0, 2), (2, 2), (2, 0), (0, 1), (1, 2), (2, 1), (1, 0), (1, 1)]
        ctype = "quad9"
    conn = np.stack([ids[Ig + a, Jg + b] for a, b in offs], axis=1)
    ftype = "line" if p == 1 else "line3"

    def side(a: IntArray) -> IntArray:  # facets along a line of points (end, end, middle)
        seg = np.arange(0, a.size - 1, p)
        cols = [a[seg], a[seg + p]] + ([a[seg + 1]] if p == 2 else [])
        return np.stack(cols, axis=1)

    groups = {"wet": {ftype: side(ids[0])}, "surface": {ftype: side(ids[:, -1])},
              "bottom": {ftype: side(ids[:, 0])}, "far": {ftype: side(ids[-1])}}  # fmt: skip
    mesh = Mesh(pts.reshape(-1, 2), {ctype: conn},
                cell_groups={"water": {ctype: np.arange(conn.shape[0])}},
                facet_groups=groups)  # fmt: skip
    return mesh, (NI, NJ)


def _coupling(
    ftype: str, X: FloatArray, conn: IntArray, T: FloatArray, sign: FloatArray,
    face: IntArray, p: int, n_water: int, n_dof: int,
) -> sp.csr_matrix:  # fmt: skip
    """Q_{i,(b,k)} = ∫_Γ N_i N_b n_k dΓ (n_water × n_dof) on the pieces of the facets: the
    piece j of facet f spans T[f, p j] .. T[f, p j + p] of the facet's reference coordinate;
    its water nodes are ``face`` at p (f r + j) + (0, p[, 1]) (line3 order: ends, middle),
    n is the facet's outward normal."""
    F, K = T.shape
    r = (K - 1) // p
    ta = T[:, 0:-1:p]  # (F, r) the lower ends of the pieces
    tb = T[:, p::p]
    tau, w = quadrature("line", 3 * p + 1)
    Nw, _ = reference(ftype).shape_functions(tau)  # the water's shape functions (q, n)
    tq = 0.5 * (ta + tb)[..., None] + 0.5 * (tb - ta)[..., None] * tau[:, 0]  # (F, r, q)
    nq = tau.shape[0]
    _, dx, Nd = _on_facets(ftype, X, tq.reshape(F, r * nq))
    dx = dx.reshape(F, r, nq, 2)
    Nd = Nd.reshape(F, r, nq, -1)
    # n dΓ = sign (t_y, −t_x) |dt/dτ| w
    jac = 0.5 * np.abs(tb - ta)[..., None] * w  # (F, r, q)
    ndG = sign[:, None, None, None] * np.stack([dx[..., 1], -dx[..., 0]], -1) * jac[..., None]
    Qe = np.einsum("qa,frqb,frqk->frabk", Nw, Nd, ndG)  # (F, r, n_w, n_d, 2)
    base = p * (np.arange(F)[:, None] * r + np.arange(r)[None, :])  # (F, r)
    local = np.array([0, p] + ([1] if p == 2 else []))
    rows = face[base[..., None] + local]  # (F, r, n_w)
    dofs = (conn[:, :, None] * 2 + np.arange(2)).reshape(F, -1)  # (F, n_d · 2)
    nw, nd = rows.shape[-1], dofs.shape[-1]
    R = np.broadcast_to(rows[..., None], (F, r, nw, nd))
    C = np.broadcast_to(dofs[:, None, None, :], (F, r, nw, nd))
    Q = sp.coo_matrix((Qe.reshape(F, r, nw, nd).ravel(), (R.ravel(), C.ravel())),
                      shape=(n_water, n_dof)).tocsr()  # fmt: skip
    Q.sum_duplicates()
    return Q


__all__ = ["Reservoir"]
