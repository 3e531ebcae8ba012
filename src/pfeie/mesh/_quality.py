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
  with its own nodes), or a facet shared by three or more cells (a region meshed twice on
  shared boundary nodes);
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
    """Cells that overlap: two cells at the same place on coincident nodes (a region
    meshed twice with its own nodes: two surfaces on one curve loop, two identical
    volumes), or a facet shared by three or more cells (no facet of a mesh that fills the
    plane or the space once has more than two). Coincident nodes count as one here, so
    that the nodes doubled along a joint (blocks meshed apart) give no false alarm."""
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
    facets: dict[int, list[tuple[np.ndarray, np.ndarray]]] = {}
    for ctype, conn in mesh.cells.items():
        if conn.shape[0] == 0:
            continue
        ref = reference(ctype)
        key = np.sort(canon[conn[:, : ref.n_corners]], axis=1)
        cells.setdefault(key.shape[1], []).append((key, ctype, np.arange(conn.shape[0])))
        fref = reference(reference(ref.facet_type).linear)
        f = canon[conn[:, np.asarray(ref.facets)][..., : fref.n_nodes]].reshape(-1, fref.n_nodes)
        facets.setdefault(f.shape[1], []).append((np.sort(f, axis=1), f))
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
    for same_f in facets.values():
        keys = np.concatenate([k for k, _ in same_f])
        corners = np.concatenate([f for _, f in same_f])
        _, first, counts = np.unique(keys, axis=0, return_index=True, return_counts=True)
        over = np.flatnonzero(counts > 2)
        if over.size:
            at = np.round(mesh.points[corners[first[over[0]]]].mean(axis=0), 6).tolist()
            out.append(
                f"{over.size} facet(s) shared by three or more cells, the first at {at} "
                f"({int(counts[over[0]])} cells): cells overlap there (a region meshed "
                "twice, or overlapping surfaces or volumes not fragmented); expected at most "
                "two cells on a facet"
            )  # fmt: skip
    return out


def _measure(dim: int) -> str:
    return "area" if dim == 2 else "volume"
