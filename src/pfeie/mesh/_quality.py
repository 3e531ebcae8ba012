"""Mesh checks before any work: degenerate, inverted and duplicated cells.

:func:`check_cells` evaluates the Jacobian determinant of every cell at the points of
its quadrature rule and at its nodes (a bow-tie quadrilateral has a positive Jacobian at
some of them and a negative one at others):

- *degenerate*: repeated corner nodes, or a largest |det J| below 1e-10 of the cell's
  size to the power of the dimension (collinear or coplanar nodes: zero area or volume);
- *inverted or self-intersecting*: det J < 0 somewhere (after the 2D cells were turned
  counter-clockwise, :meth:`Mesh.orient`);
- *duplicated*: two cells on the same corner nodes (a cell written twice in one physical
  group; a cell in two groups, which MSH 2 writes once per group, is merged by the gmsh
  reader);
- *overlapping*: two cells on coincident corner nodes (a region meshed twice, each time
  with its own nodes), a facet shared by three or more cells, or by two on the same side
  of it (a region meshed twice on shared boundary nodes), or a boundary facet reaching
  inside another cell (regions that overlap with no node in common: volumes not
  fragmented);
- node coordinates that are not finite.

and warns (``logging``, the run goes on) about *poorly shaped* cells, whose shape quality
:func:`shape_quality` is below :data:`POOR`: their stiffness is ill-conditioned and the
stresses near them are less accurate.

Shape quality. At each point the map's Jacobian J is compared with that of the ideal cell
of the same type (a square or cube, an equilateral triangle or a regular tetrahedron) by
the mean ratio of T = J W⁻¹ (W the ideal cell's Jacobian on the reference cell; Knupp
2001, "Algebraic mesh quality metrics", SIAM J. Sci. Comput. 23(1)),

    η = d det(T)^{2/d} / ‖T‖²_F ∈ (0, 1],

1 for the ideal shape whatever its size, → 0 as the cell flattens; a rectangle of aspect
ratio r has η = 2r/(1 + r²) (0.198 at r = 10, 0.0998 at r = 20). The cell's quality is
the smallest η over its quadrature points and its nodes (a curved or skewed quadratic
cell is judged where it is worst).

Cells are named by their gmsh element id when the mesh was read from gmsh
(:attr:`Mesh.cell_ids`), else by cell type and index.
"""

from __future__ import annotations

import logging
from typing import TYPE_CHECKING

import numpy as np

from ..element import quadrature, reference
from ..errors import MeshError

if TYPE_CHECKING:
    from ._mesh import Mesh

log = logging.getLogger(__name__)

#: relative size of |det J| below which a cell is degenerate
DEGENERATE = 1e-10
#: shape quality (mean ratio, 1 for the ideal cell) below which a cell gets a warning: a
#: rectangle of aspect ratio 40, a triangle with an angle of about 3°
POOR = 0.05
_SHOW = 5
_CHUNK = 8192  # cells a batch in shape_quality (Tet10: about 25 MB a batch)
# the Jacobian of the ideal cell on each reference simplex (its edge vectors from the
# first vertex as columns): the equilateral triangle and the regular tetrahedron
_IDEAL = {
    2: np.array([[1.0, 0.5], [0.0, np.sqrt(3.0) / 2.0]]),
    3: np.array([[1.0, 0.5, 0.5], [0.0, np.sqrt(3.0) / 2.0, np.sqrt(3.0) / 6.0],
                 [0.0, 0.0, np.sqrt(2.0 / 3.0)]]),
}  # fmt: skip


def _names(mesh: Mesh, ctype: str, idx: np.ndarray) -> str:
    shown = ", ".join(mesh.cell_label(ctype, int(i)) for i in idx[:_SHOW])
    more = f" and {idx.size - _SHOW} more" if idx.size > _SHOW else ""
    return shown + more


def jacobians(points: np.ndarray, ctype: str, conn: np.ndarray) -> np.ndarray:
    """det J of every cell at its quadrature points and its nodes, shape (c, q + n)."""
    ref = reference(ctype)
    xi, _ = quadrature(ctype, 2 * ref.degree)
    xi = np.concatenate([xi, ref.nodes])
    _, dN = ref.shape_functions(xi)
    X = points[conn]  # (c, n, d)
    J = np.einsum("cnd,qne->cqde", X, dN)
    return np.asarray(np.linalg.det(J), dtype=float)


def shape_quality(points: np.ndarray, ctype: str, conn: np.ndarray) -> np.ndarray:
    """The shape quality of each cell (c,): the smallest mean ratio η = d det(T)^{2/d} /
    ‖T‖²_F, T = J W⁻¹, over its quadrature points and nodes (module doc); ≤ 0 where the
    cell is inverted.

    >>> import numpy as np
    >>> square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    >>> long = square * [10.0, 1.0]                      # aspect ratio 10: 20/101
    >>> [round(float(shape_quality(p, "quad", np.arange(4)[None])[0]), 4) for p in (square, long)]
    [1.0, 0.198]
    """
    ref = reference(ctype)
    xi, _ = quadrature(ctype, 2 * ref.degree)
    xi = np.concatenate([xi, ref.nodes])
    _, dN = ref.shape_functions(xi)
    out = np.empty(conn.shape[0])
    for c0 in range(0, conn.shape[0], _CHUNK):  # bounded memory on large meshes
        J = np.einsum("cnd,qne->cqde", points[conn[c0 : c0 + _CHUNK]], dN)  # (c, q, d, d)
        d = J.shape[-1]
        T = J @ np.linalg.inv(_IDEAL[d]) if ref.simplex else J
        det = np.linalg.det(T)
        norm2 = np.einsum("cqij,cqij->cq", T, T)
        eta = d * np.sign(det) * np.abs(det) ** (2.0 / d) / np.maximum(norm2, np.finfo(float).tiny)
        out[c0 : c0 + _CHUNK] = eta.min(axis=1)
    return out


def check_cells(mesh: Mesh, where: str = "") -> None:
    """Raise :class:`MeshError` on degenerate, inverted or duplicated cells (see the
    module doc); ``where`` (the file) leads the message."""
    head = f"{where}: " if where else ""
    bad = np.flatnonzero(~np.isfinite(mesh.points).all(axis=1))
    if bad.size:
        raise MeshError(f"{head}{bad.size} node(s) with non-finite coordinates, e.g. "
                        f"{mesh.points[bad[0]].tolist()}; expected finite numbers (m)")  # fmt: skip
    problems: list[str] = []
    keys, owners = [], []
    for ctype, conn in mesh.cells.items():
        if conn.shape[0] == 0:
            continue
        ref = reference(ctype)
        corners = np.sort(conn[:, : ref.n_corners], axis=1)
        repeated = np.flatnonzero((np.diff(corners, axis=1) == 0).any(axis=1))
        X = mesh.points[conn[:, : ref.n_corners]]
        size = np.ptp(X, axis=1).max(axis=1)  # largest extent of each cell
        det = jacobians(mesh.points, ctype, conn)
        scale = np.maximum(size, np.finfo(float).tiny) ** mesh.dim
        flat = np.abs(det).max(axis=1) <= DEGENERATE * scale
        degenerate = np.union1d(repeated, np.flatnonzero(flat))
        if degenerate.size:
            problems.append(
                f"{degenerate.size} degenerate {ctype} cell(s) (zero {_measure(mesh.dim)}: "
                f"coincident, collinear or coplanar nodes): {_names(mesh, ctype, degenerate)}"
            )
        inverted = np.setdiff1d(np.flatnonzero((det < -DEGENERATE * scale[:, None]).any(axis=1)),
                                degenerate)  # fmt: skip
        if inverted.size:
            problems.append(
                f"{inverted.size} inverted or self-intersecting {ctype} cell(s) (negative "
                f"Jacobian determinant: nodes in the wrong order, or a bow-tie): "
                f"{_names(mesh, ctype, inverted)}"
            )
        keys.append(corners)
        owners.append([(ctype, i) for i in range(conn.shape[0])])
        bad_cells = np.union1d(degenerate, inverted)
        eta = shape_quality(mesh.points, ctype, conn)
        poor = np.setdiff1d(np.flatnonzero(eta < POOR), bad_cells)
        if poor.size:
            worst = poor[np.argsort(eta[poor])]
            log.warning("%s%d poorly shaped %s cell(s) (shape quality below %g, 1 for a square, "
                        "cube or equilateral simplex; worst %.3g): %s; their stiffness is "
                        "ill-conditioned and the stresses near them less accurate",
                        head, poor.size, ctype, POOR, float(eta[worst[0]]),
                        _names(mesh, ctype, worst))  # fmt: skip
    for width in {k.shape[1] for k in keys}:
        same = [(k, o) for k, o in zip(keys, owners, strict=True) if k.shape[1] == width]
        twins = _twins(mesh, np.concatenate([k for k, _ in same]),
                       [w for _, o in same for w in o])  # fmt: skip
        if twins is not None:
            problems.append(
                f"{twins[0]} duplicated cell(s) on the same nodes (written twice in one "
                f"physical group, or in none?): {twins[1]}"
            )
    if not problems:
        problems += _overlaps(mesh)
    if problems:
        raise MeshError("\n".join(head + p for p in problems))


def _twins(mesh: Mesh, keys: np.ndarray, who: list[tuple[str, int]]) -> tuple[int, str] | None:
    """The cells whose sorted corner keys (rows of ``keys``; cell ``who[i]`` for row i)
    repeat an earlier cell's: their count and the first pairs named; None if none."""
    _, first, inv, counts = np.unique(keys, axis=0, return_index=True, return_inverse=True,
                                      return_counts=True)  # fmt: skip
    inv = inv.ravel()
    dup = np.flatnonzero(counts[inv] > 1)
    dup = dup[dup != first[inv[dup]]]
    if not dup.size:
        return None
    pairs = [f"{mesh.cell_label(*who[int(first[inv[j]])])} and {mesh.cell_label(*who[int(j)])}"
             for j in dup[:_SHOW]]  # fmt: skip
    more = f" and {dup.size - _SHOW} more" if dup.size > _SHOW else ""
    return int(dup.size), "; ".join(pairs) + more


def _overlaps(mesh: Mesh) -> list[str]:
    """Cells that overlap (the module doc), in four tests, coincident nodes counting as one
    (so that the nodes doubled along a joint, blocks meshed apart, give no false alarm):

    - two cells at the same place on coincident nodes (a region meshed twice with its own
      nodes: two surfaces on one curve loop, two identical volumes);
    - a facet shared by three or more cells (no facet of a mesh that fills the plane or
      the space once has more than two);
    - a facet shared by two cells on the same side of it (two regions meshed on the same
      boundary nodes, their interiors apart: the cells of a joint lie on either side);
    - a boundary facet (of one cell) whose centre, or a point halfway from it to a
      corner, or the centroid of its cell, lies inside another cell, deeper than
      :data:`INSIDE` of that cell's size (regions that overlap with no node in common:
      volumes not fragmented; a region meshed twice with different meshes, whose
      boundaries coincide).

    The last two judge a cell by the polygon or polyhedron of its corners (each face by
    the plane through its corners' centre, normal to its diagonals)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    pairs = mesh.coincident_nodes()
    n = mesh.n_points
    canon = np.arange(n)
    if pairs.size:  # each node to the first of its group of coincident nodes
        g = coo_matrix((np.ones(pairs.shape[0]), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
        _, label = connected_components(g, directed=False)
        first = np.full(label.max() + 1, n, dtype=np.int64)
        np.minimum.at(first, label, np.arange(n))
        canon = first[label]
    out: list[str] = []
    cells: dict[int, list[tuple[np.ndarray, str, np.ndarray]]] = {}
    facets: dict[int, list[_Facets]] = {}
    for t, (ctype, conn) in enumerate(mesh.cells.items()):
        if conn.shape[0] == 0:
            continue
        ref = reference(ctype)
        key = np.sort(canon[conn[:, : ref.n_corners]], axis=1)
        cells.setdefault(key.shape[1], []).append((key, ctype, np.arange(conn.shape[0])))
        nf = reference(reference(ref.facet_type).linear).n_nodes
        local = np.asarray(ref.facets)[:, :nf]  # (faces, corners of a face)
        facets.setdefault(nf, []).append(_Facets(t, conn[:, local], canon))
    if pairs.size:
        for same in cells.values():
            twins = _twins(mesh, np.concatenate([k for k, _, _ in same]),
                           [(t, int(i)) for _, t, idx in same for i in idx])  # fmt: skip
            if twins is not None:
                out.append(
                    f"{twins[0]} cell(s) at the same place as others, on coincident nodes: "
                    f"{twins[1]}; a region meshed twice (two surfaces on one curve loop, "
                    "two identical volumes)? expected each region meshed once"
                )  # fmt: skip
    if out:
        return out
    boundary: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []  # points, cells, facets
    offset = 0  # of the facets of each width, numbering the boundary facets
    for same_f in facets.values():
        keys = np.sort(np.concatenate([f.canon for f in same_f]), axis=1)
        corners = np.concatenate([f.corners for f in same_f])
        owner = np.concatenate([f.owner for f in same_f])  # (type, cell) a row
        _, first, inv, counts = np.unique(keys, axis=0, return_index=True,
                                          return_inverse=True, return_counts=True)  # fmt: skip
        inv = inv.ravel()
        over = np.flatnonzero(counts > 2)
        if over.size:
            at = np.round(mesh.points[corners[first[over[0]]]].mean(axis=0), 6).tolist()
            out.append(
                f"{over.size} facet(s) shared by three or more cells, the first at {at} "
                f"({int(counts[over[0]])} cells): cells overlap there (a region meshed "
                "twice, or overlapping surfaces or volumes not fragmented); expected at most "
                "two cells on a facet"
            )  # fmt: skip
            continue
        order = np.argsort(inv, kind="stable")
        two = order[counts[inv[order]] == 2]  # the rows of each such facet next to each other
        a, b = two[0::2], two[1::2]
        centre, normal = _planes(mesh.points[corners[a]])  # (facets, dim) each
        mid = _centroids(mesh, owner[two])  # the sides of both cells against a's plane
        side = np.einsum("rd,rd->r", mid - np.repeat(centre, 2, axis=0),
                         np.repeat(normal, 2, axis=0))  # fmt: skip
        same_side = np.flatnonzero(side[0::2] * side[1::2] > 0.0)
        if same_side.size:
            ia, ib = a[same_side[0]], b[same_side[0]]
            at = np.round(centre[same_side[0]], 6).tolist()
            out.append(
                f"{same_side.size} facet(s) shared by two cells on the same side of it, the "
                f"first at {at} ({_cell_of(mesh, owner[ia])} and {_cell_of(mesh, owner[ib])}):"
                " two regions meshed over one another on the same boundary nodes? expected "
                "the cells of a facet on either side of it"
            )  # fmt: skip
            continue
        one = np.flatnonzero(counts[inv] == 1)  # boundary facets: their centres and the
        X = mesh.points[corners[one]]  # points halfway to their corners (a point alone can
        mid_one = X.mean(axis=1)[:, None]
        # and the centroid of the facet's cell: where two regions fill the same place with
        # different meshes, their boundaries coincide and only the cells' insides show it
        own_c = _centroids(mesh, owner[one])[:, None]
        samples = np.concatenate([mid_one, (X + mid_one) / 2, own_c], axis=1)
        label = np.repeat(one + offset, samples.shape[1]).reshape(samples.shape[:2])
        label[:, -1] = -1  # (a cell's centroid: not a facet's point)
        boundary.append((samples.reshape(-1, mesh.dim),  # fall on another mesh's edges)
                         np.repeat(owner[one], samples.shape[1], axis=0),
                         label.ravel()))  # fmt: skip
        offset += keys.shape[0]
    if out or not boundary:
        return out
    facet = np.concatenate([f for _, _, f in boundary])
    inside = _inside_other_cells(mesh, np.concatenate([p for p, _, _ in boundary]),
                                 np.concatenate([o for _, o, _ in boundary]))  # fmt: skip
    if inside is not None:
        hits, host, own = inside
        on_facets = facet[hits][facet[hits] >= 0]
        count = np.unique(on_facets).size
        at = np.concatenate([p for p, _, _ in boundary])[hits[0]]
        what = (f"{count} boundary facet(s) reach inside cells of another region" if count
                else "cells along a region's boundary lie inside cells of another region "
                "(the regions' boundaries coincide: one region meshed twice?)")  # fmt: skip
        out.append(
            f"{what}, the first at {np.round(at, 6).tolist()} (a "
            f"{'facet of ' if facet[hits[0]] >= 0 else ''}{_cell_of(mesh, own)} inside "
            f"{_cell_of(mesh, host)}): regions overlap with no node in common (surfaces or "
            "volumes not fragmented: gmsh's BooleanFragments, or Coherence in a .geo file)? "
            "expected regions that meet on shared or coincident facets"
        )  # fmt: skip
    return out


#: how deep, as a share of the cell's largest extent, a point of a boundary facet must lie
#: inside another cell to count as an overlap (a conforming mesh puts it on a face: 0)
INSIDE = 1e-3


class _Facets:
    """The corner facets of the cells of one type (the ``t``-th of ``mesh.cells``):
    ``corners`` (cells × faces, k) node indices, ``canon`` the same with coincident nodes
    merged, ``owner`` (cells × faces, 2): ``t`` and the cell of each facet."""

    def __init__(self, t: int, corners: np.ndarray, canon: np.ndarray) -> None:
        c, f, k = corners.shape
        self.corners = corners.reshape(c * f, k)
        self.canon = canon[self.corners]
        self.owner = np.stack([np.full(c * f, t, dtype=np.int64), np.repeat(np.arange(c), f)],
                              axis=1)  # fmt: skip


def _planes(X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The centre and unit normal (either sign) of each facet of corners X (rows, k,
    dim): an edge's perpendicular in 2D; in 3D the normal to a triangle, or to a quad's
    diagonals."""
    centre = X.mean(axis=1)
    if X.shape[2] == 2:
        t = X[:, 1] - X[:, 0]
        nrm = np.stack([-t[:, 1], t[:, 0]], axis=1)
    elif X.shape[1] == 3:
        nrm = np.cross(X[:, 1] - X[:, 0], X[:, 2] - X[:, 0])
    else:
        nrm = np.cross(X[:, 2] - X[:, 0], X[:, 3] - X[:, 1])
    size = np.linalg.norm(nrm, axis=1)
    return centre, nrm / np.where(size > 0, size, 1.0)[:, None]


def _centroids(mesh: Mesh, owner: np.ndarray) -> np.ndarray:
    """The centre of the corners of each cell ``owner`` (rows of type position, cell)."""
    out = np.empty((owner.shape[0], mesh.dim))
    for t, (ctype, conn) in enumerate(mesh.cells.items()):
        rows = np.flatnonzero(owner[:, 0] == t)
        if rows.size:
            corners = conn[owner[rows, 1], : reference(ctype).n_corners]
            out[rows] = mesh.points[corners].mean(axis=1)
    return out


def _cell_of(mesh: Mesh, row: np.ndarray) -> str:
    """A cell (type position, cell) for messages: its label and its groups."""
    ctype = list(mesh.cells)[int(row[0])]
    i = int(row[1])
    groups = [name for name, grp in mesh.cell_groups.items()
              if ctype in grp and np.any(grp[ctype] == i)]  # fmt: skip
    where = f" of {', '.join(repr(g) for g in groups)}" if groups else ""
    return mesh.cell_label(ctype, i) + where


def _inside_other_cells(
    mesh: Mesh, points: np.ndarray, own: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """The points of boundary facets ``points`` (m, dim) that lie inside a cell other
    than their own (``own``, rows of type position, cell) by more than :data:`INSIDE` of
    its size: their indices, the first one's host cell and own cell; None if none.
    Candidates by a KD-tree of the centres within each cell's circumradius."""
    from scipy.spatial import cKDTree

    tree = cKDTree(points)
    deep_of = np.full(points.shape[0], -1, dtype=np.int64)  # the type position of a host
    host_of = np.zeros(points.shape[0], dtype=np.int64)
    for t, (ctype, conn) in enumerate(mesh.cells.items()):
        if conn.shape[0] == 0:
            continue
        ref = reference(ctype)
        X = mesh.points[conn[:, : ref.n_corners]]  # (cells, corners, dim)
        C = X.mean(axis=1)
        R = np.linalg.norm(X - C[:, None], axis=2).max(axis=1) * (1.0 + 1e-9)
        counts = np.asarray(tree.query_ball_point(C, R, return_length=True), dtype=np.int64)
        cand = np.flatnonzero(counts)
        if not cand.size:
            continue
        hits = tree.query_ball_point(C[cand], R[cand])
        ci = np.repeat(cand, counts[cand])
        pj = np.concatenate([np.asarray(h, dtype=np.int64) for h in hits])
        nf = reference(reference(ref.facet_type).linear).n_nodes
        local = np.asarray(ref.facets)[:, :nf]  # (faces, corners of a face)
        F = mesh.points[conn[ci][:, local]]  # (pairs, faces, corners, dim)
        centre, normal = _planes(F.reshape(-1, nf, mesh.dim))
        centre = centre.reshape(F.shape[0], F.shape[1], -1)
        normal = normal.reshape(F.shape[0], F.shape[1], -1)
        inward = np.sign(np.einsum("pfd,pfd->pf", C[ci][:, None] - centre, normal))
        depth = (inward * np.einsum("pfd,pfd->pf", points[pj][:, None] - centre, normal)).min(
            axis=1
        )
        size = np.ptp(X[ci], axis=1).max(axis=1)
        mine = (own[pj, 0] == t) & (own[pj, 1] == ci)
        deep = np.flatnonzero((depth > INSIDE * size) & ~mine)
        new = deep[deep_of[pj[deep]] < 0]
        deep_of[pj[new]] = t
        host_of[pj[new]] = ci[new]
    flagged = np.flatnonzero(deep_of >= 0)
    if not flagged.size:
        return None
    j = flagged[0]
    return flagged, np.array([deep_of[j], host_of[j]]), own[j]


def _measure(dim: int) -> str:
    return "area" if dim == 2 else "volume"
