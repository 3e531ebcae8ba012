"""Vectorised element kernels of isotropic linear elasticity.

All kernels work on every cell of one cell type at once and follow the axis convention
``(c, q, n, d)``: cell, quadrature point, node, spatial component. Element matrices are
returned as ``(c, n·d, n·d)`` with node-major local DOFs (a·d + i for node a,
component i), matching the global numbering ``dof = node·dim + component``.

Theory
------
Isotropic Hooke's law σ = λ tr(ε) I + 2μ ε, with λ = Eν/((1 + ν)(1 − 2ν)),
μ = E/(2(1 + ν)). Plane strain uses λ, μ as they are (σ_zz = λ(ε_xx + ε_yy)); plane
stress replaces λ by λ* = 2λμ/(λ + 2μ) (σ_zz = 0). The element stiffness, written in
index form without a B matrix,

    K^e_{ai,bj} = Σ_q w_q |J_q| t [ λ ∂_i N_a ∂_j N_b + μ ∂_j N_a ∂_i N_b
                                     + μ δ_ij ∂_k N_a ∂_k N_b ],

the consistent mass M^e_{ai,bj} = Σ_q w_q |J_q| t ρ N_a N_b δ_ij, and the load
f^e_{ai} = Σ_q w_q |J_q| t N_a b_i, where t is the thickness in 2D (1 in 3D).
Units: SI throughout (m, kg, s, N, Pa).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..element import quadrature, reference
from ..errors import MeshError
from ..typing import FloatArray, IntArray


@dataclass(frozen=True)
class CellValues:
    """Geometry of one cell type evaluated at its quadrature points.

    Attributes: ``N`` (q, n) shape functions; ``dNdx`` (c, q, n, d) spatial gradients;
    ``dV`` (c, q) quadrature weight × |J| × thickness; ``x`` (c, q, d) the points.
    """

    cell_type: str
    conn: IntArray
    N: FloatArray
    dNdx: FloatArray
    dV: FloatArray
    x: FloatArray

    @property
    def dim(self) -> int:
        return int(self.dNdx.shape[-1])


def cell_values(
    points: FloatArray, cell_type: str, conn: IntArray, degree: int, thickness: float = 1.0
) -> CellValues:
    """Evaluate shape functions, gradients and volume measures on every cell at once."""
    xi, w = quadrature(cell_type, degree)
    N, dN = reference(cell_type).shape_functions(xi)
    X = points[conn]  # (c, n, d)
    J = np.tensordot(X, dN, axes=([1], [1])).transpose(0, 2, 1, 3)  # (c, q, d, e) = ∂x_d/∂ξ_e
    det, Jinv = _det_inv(J)
    if np.any(det <= 0.0):
        bad = np.flatnonzero((det <= 0.0).any(axis=1))
        raise MeshError(
            f"{bad.size} {cell_type} cell(s) are inverted or degenerate "
            f"(non-positive Jacobian), first at cell index {int(bad[0])}"
        )
    dNdx = np.matmul(dN[None], Jinv)  # (c, q, n, d)
    x = np.tensordot(X, N, axes=([1], [1])).transpose(0, 2, 1)
    return CellValues(cell_type, conn, N, dNdx, det * w * thickness, x)


def _det_inv(J: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Determinants and inverses of stacks of 2 × 2 or 3 × 3 matrices by cofactors
    (LAPACK's per-matrix overhead dominates at this size)."""
    d = J.shape[-1]
    if d == 2:
        a, b, c, e = J[..., 0, 0], J[..., 0, 1], J[..., 1, 0], J[..., 1, 1]
        det = a * e - b * c
        adj = np.stack([np.stack([e, -b], -1), np.stack([-c, a], -1)], -2)
    elif d == 3:
        cof = np.empty_like(J)
        for i in range(3):
            for j in range(3):
                i1, i2 = (i + 1) % 3, (i + 2) % 3
                j1, j2 = (j + 1) % 3, (j + 2) % 3
                cof[..., j, i] = J[..., i1, j1] * J[..., i2, j2] - J[..., i1, j2] * J[..., i2, j1]
        det = np.einsum("...j,...j->...", J[..., 0, :], cof[..., :, 0])
        adj = cof
    else:
        return np.asarray(np.linalg.det(J), float), np.asarray(np.linalg.inv(J), float)
    with np.errstate(divide="ignore", invalid="ignore"):
        inv: FloatArray = adj / det[..., None, None]
    return det, inv


def stiffness_degree(cell_type: str, curved: bool = False) -> int:
    """Quadrature degree integrating the stiffness of an undistorted cell exactly; for
    ``curved`` simplices (:func:`curved_cells`) at least the degree that keeps the patch
    test exact.

    The internal forces of a constant stress σ are ∫ σ ∇N dV = ∫ σ adj(J)ᵀ ∇_ξN dξ, J
    the map's Jacobian: on a straight-sided simplex J is constant and the integrand of
    degree p − 1 (p the cell's order), on a curved one J has degree p − 1, its adjugate
    (d − 1)(p − 1) and the integrand d(p − 1). In 2D that is 2(p − 1), the stiffness's own
    degree; a curved Tet10 needs 3 where its stiffness rule has 2 (a curved Tet10 patch
    of 0.5 m cells, mid-edge nodes moved by 0.04 m: displacements off by 1.8e-4 with the
    4-point rule, exact to round-off with degree 3). Tensor cells (Q8, Q9, Hex8) take
    2p per variable, enough for their curved shapes' patch tests.
    """
    ref = reference(cell_type)
    if not ref.simplex:
        return 2 * ref.degree
    own = 2 * (ref.degree - 1)
    return max(own, ref.dim * (ref.degree - 1)) if curved else own


def curved_cells(points: FloatArray, cell_type: str, conn: IntArray, rtol: float = 1e-9) -> bool:
    """Whether any cell of a quadratic (or higher) type is curved: a node off the
    position that the cell's corners map it to (their affine image on a simplex, the
    bilinear or trilinear one on a tensor cell), by more than ``rtol``
    of the cell's size. Cells of the first order are never curved."""
    ref = reference(cell_type)
    if ref.degree == 1 or not conn.shape[0]:
        return False
    lin = reference(ref.linear)
    N, _ = lin.shape_functions(ref.nodes)  # (n, corners): each node from the corners
    X = points[conn]  # (c, n, d)
    corners = X[:, : ref.n_corners]
    off = np.abs(np.einsum("nk,ckd->cnd", N, corners) - X).max(axis=(1, 2))
    size = np.ptp(corners, axis=1).max(axis=1)
    return bool((off > rtol * size).any())


def mass_degree(cell_type: str) -> int:
    """Quadrature degree integrating the consistent mass exactly."""
    return 2 * reference(cell_type).degree


def stiffness(cv: CellValues, lam: FloatArray, mu: FloatArray) -> FloatArray:
    """Element stiffness matrices (c, n·d, n·d) for per-cell Lamé constants (c,)."""
    c, q, n, d = cv.dNdx.shape
    G = (cv.dNdx * cv.dV[:, :, None, None]).reshape(c, q, n * d)
    P = np.matmul(G.transpose(0, 2, 1), cv.dNdx.reshape(c, q, n * d)).reshape(c, n, d, n, d)
    S = sum(P[:, :, k, :, k] for k in range(d)) * mu[:, None, None]
    K = P * lam[:, None, None, None, None]
    K += P.transpose(0, 1, 4, 3, 2) * mu[:, None, None, None, None]
    for i in range(d):
        K[:, :, i, :, i] += S
    return K.reshape(c, n * d, n * d)


def scalar_mass(cv: CellValues, rho: FloatArray) -> FloatArray:
    """Scalar consistent mass ∫ ρ N_a N_b (c, n, n); the vector mass is this ⊗ I_d."""
    return np.einsum("cq,qa,qb->cab", cv.dV * rho[:, None], cv.N, cv.N)


def lump_hrz(me: FloatArray) -> FloatArray:
    """Row-scaled diagonal lumping (Hinton, Rock & Zienkiewicz 1976) of scalar masses.

    m_a = diag(M)_a · Σ M / Σ diag(M): positive for every element, total mass kept.
    Returns the lumped nodal masses (c, n).
    """
    diag = np.einsum("caa->ca", me)
    dsum = diag.sum(axis=1)
    scale = np.divide(me.sum(axis=(1, 2)), dsum, out=np.zeros_like(dsum), where=dsum != 0)
    return diag * scale[:, None]


def load(cv: CellValues, values: FloatArray) -> FloatArray:
    """Element load vectors (c, n, d) of a force density given at quadrature points.

    ``values`` has shape (c, q, d) (or broadcasts to it): force per unit volume in
    3D and in 2D (the thickness is in ``dV``).
    """
    return np.einsum("cq,qa,cqd->cad", cv.dV, cv.N, np.broadcast_to(values, cv.x.shape))


def strain(cv: CellValues, ue: FloatArray) -> FloatArray:
    """Small strains (c, q, d, d) from element displacements ue (c, n, d)."""
    grad = np.einsum("cqnj,cni->cqij", cv.dNdx, ue)
    return 0.5 * (grad + grad.transpose(0, 1, 3, 2))


def stress(eps: FloatArray, lam: FloatArray, mu: FloatArray, plane: str | None) -> FloatArray:
    """Cauchy stress (c, q, 3, 3) from strains (c, q, d, d); ``plane`` in 2D is
    "strain" or "stress" (σ_zz = λ(ε_xx + ε_yy) or 0), with ``lam`` already the
    effective λ of the plane state."""
    c, q, d, _ = eps.shape
    full = np.zeros((c, q, 3, 3))
    tr = np.trace(eps, axis1=2, axis2=3)
    full[:, :, :d, :d] = 2.0 * mu[:, None, None, None] * eps
    for i in range(d):
        full[:, :, i, i] += lam[:, None] * tr
    if d == 2 and plane == "strain":
        full[:, :, 2, 2] = lam[:, None] * tr
    return full


@dataclass(frozen=True)
class FacetValues:
    """Facets evaluated at quadrature points: ``N`` (q, n), ``dA`` (f, q) area measure ×
    thickness, ``normal`` (f, q, d) unit normal (orientation from the node order),
    ``x`` (f, q, d)."""

    conn: IntArray
    N: FloatArray
    dA: FloatArray
    normal: FloatArray
    x: FloatArray


def facet_values(
    points: FloatArray, facet_type: str, conn: IntArray, degree: int, thickness: float = 1.0
) -> FacetValues:
    """Area measure and normals of facets (lines in 2D, triangles or quads in 3D)."""
    xi, w = quadrature(facet_type, degree)
    N, dN = reference(facet_type).shape_functions(xi)
    X = points[conn]
    T = np.einsum("fnd,qne->fqde", X, dN)  # tangents (f, q, d, dim-1)
    if X.shape[2] == 2:
        t = T[..., 0]
        nvec = np.stack([t[..., 1], -t[..., 0]], axis=-1)
    else:
        nvec = np.cross(T[..., 0], T[..., 1])
    jac = np.linalg.norm(nvec, axis=-1)
    if np.any(jac <= 0.0):
        raise MeshError(f"degenerate {facet_type} facet(s) of zero size")
    x = np.einsum("qn,fnd->fqd", N, X)
    return FacetValues(conn, N, jac * w * thickness, nvec / jac[..., None], x)


def facet_load(fv: FacetValues, traction: FloatArray) -> FloatArray:
    """Facet load vectors (f, n, d) of a traction (f, q, d), force per unit area."""
    return np.einsum("fq,qa,fqd->fad", fv.dA, fv.N, np.broadcast_to(traction, fv.x.shape))


VOIGT = ((0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1))
"""The order of the six stress components of a Voigt vector: xx, yy, zz, yz, xz, xy."""


def _radius(half_difference: FloatArray, shear: FloatArray) -> FloatArray:
    """Mohr's circle radius R = √(((σ_xx − σ_yy)/2)² + τ_xy²) from its two legs: the
    square root of the sum of squares (a seventh of the time of ``np.hypot``, whose guard
    against overflow is not needed below 1e150 Pa; the stress envelope's plane form
    repeats these operations, to the same bits)."""
    r = half_difference * half_difference
    r += shear * shear
    return np.sqrt(r, out=r)


def principal_stresses(s: FloatArray) -> FloatArray:
    """Principal stresses (N, 3), largest first (Pa, tension positive), of N symmetric
    stress tensors given as Voigt vectors ``s`` (N, 6) in the order :data:`VOIGT`.

    Closed forms, no per-tensor loop. Where the shear components out of the x–y plane
    vanish (every 2D state: σ_zz is then principal) the in-plane pair is exact to
    round-off, c ± R with c = (σ_xx + σ_yy)/2 and R = √(((σ_xx − σ_yy)/2)² + τ_xy²).
    Otherwise the trigonometric solution of the characteristic cubic (Smith 1961):
    with q = tr σ/3, p = √(‖σ − qI‖²_F/6) and r = det((σ − qI)/p)/2 ∈ [−1, 1],
    σ_k = q + 2p cos(arccos(r)/3 − 2πk/3), k = 0, 1, 2 (accurate to about 1e-8 of ‖σ‖
    where two principal stresses nearly coincide).

    >>> principal_stresses(np.array([[1.0, -1.0, 0.0, 0.0, 0.0, 0.0],    # uniaxial pair
    ...                              [0.0, 0.0, 0.0, 0.0, 0.0, 2.0]]))   # pure shear
    array([[ 1.,  0., -1.],
           [ 2.,  0., -2.]])
    """
    s = np.asarray(s, dtype=float)
    xx, yy, zz, yz, xz, xy = s.T
    out = np.empty((s.shape[0], 3))
    plane = (yz == 0.0) & (xz == 0.0)
    if plane.any():
        c = 0.5 * (xx[plane] + yy[plane])
        R = _radius(0.5 * (xx[plane] - yy[plane]), xy[plane])
        three = np.stack([c + R, c - R, zz[plane]], axis=1)
        out[plane] = -np.sort(-three, axis=1)
    gen = ~plane
    if gen.any():
        out[gen] = -np.sort(-np.stack(_cubic_roots(s[gen]), axis=1), axis=1)
    return out


def _cubic_roots(a: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The three roots q + 2p cos(φ − 2πk/3), k = 0, 1, 2, of general Voigt vectors
    ``a`` (N, 6) (:func:`principal_stresses`); for φ ∈ [0, π/3] k = 0 is the largest and
    k = 2 the smallest (they coincide where p = 0)."""
    q = a[:, :3].sum(axis=1) / 3.0
    d = a[:, :3] - q[:, None]
    off2 = (a[:, 3:] ** 2).sum(axis=1)
    p = np.sqrt(((d**2).sum(axis=1) + 2.0 * off2) / 6.0)
    safe = np.where(p > 0, p, 1.0)
    b = d / safe[:, None]
    o = a[:, 3:] / safe[:, None]  # yz, xz, xy over p
    det = (b[:, 0] * (b[:, 1] * b[:, 2] - o[:, 0] ** 2)
           - o[:, 2] * (o[:, 2] * b[:, 2] - o[:, 0] * o[:, 1])
           + o[:, 1] * (o[:, 2] * o[:, 0] - b[:, 1] * o[:, 1]))  # fmt: skip
    phi = np.arccos(np.clip(0.5 * det, -1.0, 1.0)) / 3.0
    two_p = 2.0 * p
    k = np.arange(3) * (2.0 * np.pi / 3.0)
    r0, r1, r2 = (q + two_p * np.cos(phi - k[j]) for j in range(3))
    return r0, r1, r2


def principal_extremes(s: FloatArray) -> tuple[FloatArray, FloatArray]:
    """The largest and the smallest principal stress (σ₁, σ₃), each (N,), of Voigt
    vectors ``s`` (N, 6): the closed forms of :func:`principal_stresses` without the
    sort (the per-row cost of a stress envelope), to the same bits. In plane states
    σ₁ = max(c + R, σ_zz), σ₃ = min(c − R, σ_zz); otherwise the extremes of the three
    trigonometric roots (k = 0 gives σ₁ and k = 2 gives σ₃ unless p = 0, where the
    roots coincide).

    >>> principal_extremes(np.array([[0.0, 0.0, 0.5, 0.0, 0.0, 2.0]]))
    (array([2.]), array([-2.]))
    """
    s = np.asarray(s, dtype=float)
    xx, yy, zz, yz, xz, xy = s.T
    general = (yz != 0.0) | (xz != 0.0)
    if general.all():  # 3D: no row is plane; no plane forms, no gather or scatter
        return _cubic_extremes(s)
    c = 0.5 * (xx + yy)
    R = _radius(0.5 * (xx - yy), xy)
    hi = np.maximum(c + R, zz)
    lo = np.minimum(c - R, zz)
    gen = np.flatnonzero(general)
    if gen.size:
        hi[gen], lo[gen] = _cubic_extremes(s[gen])
    return hi, lo


def _cubic_extremes(a: FloatArray) -> tuple[FloatArray, FloatArray]:
    """σ₁ and σ₃ of general Voigt vectors ``a`` (N, 6): the extremes of
    :func:`_cubic_roots` without a sort."""
    r0, r1, r2 = _cubic_roots(a)
    return np.maximum(np.maximum(r0, r1), r2), np.minimum(np.minimum(r0, r1), r2)
