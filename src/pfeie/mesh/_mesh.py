"""The in-memory mesh: points, cells by type, named cell groups and named facet groups.

The type maps one to one onto :class:`meshio.Mesh`: cells are meshio cell blocks (one per
cell type, meshio's names and node orders); a cell group is a meshio ``cell_set`` over the
volume blocks; a facet group is a set of lower-dimensional cell blocks (lines in 2D,
triangles or quads in 3D) with a ``cell_set`` of the same name. Groups of gmsh physical
names arrive as such ``cell_sets``.

Sign convention: the facets of a facet group carry no trusted orientation; where a normal
is needed (pressure), it is oriented away from the adjacent cell.
"""

from __future__ import annotations

import hashlib
import logging
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..element import reference
from ..errors import MeshError
from ..typing import BoolArray, FloatArray, IntArray
from ._quality import check_cells

log = logging.getLogger(__name__)


def _mask(where: Callable[[FloatArray], Any], x: FloatArray, what: str) -> BoolArray:
    """``where(x)`` as a boolean mask of one entry per row of ``x`` (centroids (n, dim)):
    a scalar (``lambda x: True``, which would select the first cell alone) or a mask of
    another length is a :class:`MeshError` naming the group, as is a ``where`` that is
    not a function."""
    if not callable(where):
        raise MeshError(f"{what}: where: expected a function of the centroids x (n, dim), "
                        "e.g. lambda x: x[:, 1] > 0, got "
                        f"{type(where).__name__} {where!r}")  # fmt: skip
    raw = np.asarray(where(x))
    if raw.shape != (x.shape[0],):
        raise MeshError(
            f"{what}: where(x) must return one boolean per centroid, shape "
            f"({x.shape[0]},) for x of shape {x.shape}; got shape {raw.shape} "
            "(select every cell with where=None, or e.g. lambda x: x[:, 1] > 0)"
        )
    if raw.dtype != bool and raw.size:
        raise MeshError(
            f"{what}: where(x) must return booleans, one per centroid; got values of type "
            f"{raw.dtype} (e.g. lambda x: x[:, 1] > 0 selects the cells above y = 0, where "
            "lambda x: x[:, 1] would select every cell off y = 0)"
        )
    mask: BoolArray = raw.astype(bool)
    return mask


@dataclass
class Mesh:
    """A finite element mesh.

    Parameters
    ----------
    points: node coordinates, shape (n_points, dim), dim = 2 or 3.
    cells: connectivity per cell type, each of shape (n_cells, n_nodes_per_cell).
    cell_groups: group name → cell type → indices into ``cells[type]``.
    facet_groups: group name → facet type → facet connectivity (n_facets, n_nodes); a
        facet given twice to the constructor (on both of its cells) is stored once, while
        :meth:`add_facet_group` with ``boundary_only=False`` keeps an interior facet once
        per cell it bounds (as the interface split reads a joint: a facet a side).
    cell_ids: cell type → the id of each cell in the file it was read from (gmsh element
        ids), for messages; empty for a mesh built in Python (cells are then named by type
        and index).
    empty_groups: physical groups named in the file that hold no cell of the mesh's
        dimension and no facet (empty, or of a lower dimension): name → the group's
        dimension in the file; only for messages.
    """

    points: FloatArray
    cells: dict[str, IntArray]
    cell_groups: dict[str, dict[str, IntArray]] = field(default_factory=dict)
    facet_groups: dict[str, dict[str, IntArray]] = field(default_factory=dict)
    cell_ids: dict[str, IntArray] = field(default_factory=dict)
    empty_groups: dict[str, int] = field(default_factory=dict)
    #: the fingerprint of the points and cells that :meth:`check` passed (see
    #: :attr:`checked`)
    _check_key: bytes | None = field(default=None, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        self.points = np.ascontiguousarray(self.points, dtype=float)
        if self.points.ndim != 2 or self.points.shape[1] not in (2, 3):
            raise MeshError(f"points must have shape (n, 2) or (n, 3), got {self.points.shape}")
        self.cells = {k: np.ascontiguousarray(v, dtype=np.int64) for k, v in self.cells.items()}
        for ctype, conn in self.cells.items():
            ref = reference(ctype)
            if ref.dim != self.dim:
                raise MeshError(f"cell type {ctype!r} has dimension {ref.dim}, mesh is {self.dim}D")
            if conn.ndim != 2 or conn.shape[1] != ref.n_nodes:
                raise MeshError(f"cells {ctype!r} need {ref.n_nodes} nodes each, got {conn.shape}")
            if conn.size and (conn.min() < 0 or conn.max() >= self.n_points):
                raise MeshError(f"cells {ctype!r} refer to nodes outside 0..{self.n_points - 1}")
        for name, grp in self.cell_groups.items():
            for ctype, idx in grp.items():
                if ctype not in self.cells:
                    raise MeshError(f"cell group {name!r} refers to absent cell type {ctype!r}")
                grp[ctype] = np.asarray(idx, dtype=np.int64)
                n = self.cells[ctype].shape[0]
                if grp[ctype].size and (grp[ctype].min() < 0 or grp[ctype].max() >= n):
                    raise MeshError(f"cell group {name!r}: {ctype} indices outside 0..{n - 1}")
        for name, fgrp in self.facet_groups.items():
            for ftype, conn in fgrp.items():
                if reference(ftype).dim != self.dim - 1:
                    raise MeshError(f"facet group {name!r}: {ftype!r} is not a facet type")
                conn = np.asarray(conn, dtype=np.int64)
                if conn.ndim == 2 and conn.shape[0] > 1:  # each facet once
                    _, first = np.unique(facet_keys(conn, ftype), axis=0, return_index=True)
                    if first.size < conn.shape[0]:
                        conn = conn[np.sort(first)]
                fgrp[ftype] = conn
        self._raise_facet_order()
        for ctype, ids in list(self.cell_ids.items()):
            ids = np.asarray(ids, dtype=np.int64)
            if ctype not in self.cells or ids.shape != (self.cells[ctype].shape[0],):
                raise MeshError(f"cell_ids of {ctype!r} must give one id per cell")
            self.cell_ids[ctype] = ids

    def _raise_facet_order(self) -> None:
        """Facets of a group given by their corners only on quadratic cells (gmsh's 2-node
        lines on 6-node triangles, when the boundary was exported at first order) become
        the cells' own faces, mid-side nodes included: a support on such a group held the
        corners alone and left the mid-side nodes free; a load on it was refused. A
        facet that is a face of a cell of its own order, or of none, is kept."""
        if not self.facet_groups or all(reference(c).linear == c for c in self.cells):
            return  # (no quadratic cell: nothing to raise)
        table = None
        for fgrp in self.facet_groups.values():
            for ftype in [t for t in fgrp if reference(t).linear == t]:
                conn = fgrp[ftype]
                if not conn.size:
                    continue
                if table is None:
                    table = self._facet_table()
                keys = facet_keys(conn, ftype)
                own = np.zeros(keys.shape[0], dtype=bool)
                for ft, _, _, fkeys, _, _ in table:
                    if ft == ftype:
                        own |= match_rows(fkeys, keys)[1]
                for ft, fconn, _, fkeys, _, _ in table:
                    if ft == ftype or reference(ft).linear != ftype:
                        continue
                    rows, found = match_rows(fkeys, keys)
                    up = found & ~own
                    if up.any():
                        raised = fconn[rows[up]]
                        fgrp[ft] = (np.concatenate([fgrp[ft], raised]) if ft in fgrp
                                    else raised)  # fmt: skip
                        keep = ~up
                        conn, keys, own = conn[keep], keys[keep], own[keep]
                if conn.shape[0]:
                    fgrp[ftype] = conn
                else:
                    del fgrp[ftype]

    def hanging_nodes(self, nodes: IntArray | None = None, rel_tol: float = 1e-6) -> IntArray:
        """Nodes that lie on a boundary facet of the cells (a face, in 3D; an edge, in 2D)
        without being one of its nodes (sorted), among ``nodes`` (default: the nodes of
        the cells). A conforming mesh has none
        (its facets inside are shared, and its boundary carries only their nodes); parts
        meshed separately at other sizes and then merged leave them where they meet (the
        finer side's nodes on the coarser side's edges: that side hangs on the shared
        corners), and so does a linear cell beside a quadratic one (the mid-side node).
        A node counts when it lies within ``rel_tol`` × the facet's size of the facet's
        corners' chord or plane, inside it, and apart from each of its nodes (the copies
        of a split interface's nodes coincide with nodes of the other side's facets)."""
        from scipy.spatial import cKDTree

        if nodes is None:
            nodes = np.unique(np.concatenate([c.ravel() for c in self.cells.values()] or
                                             [np.zeros(0, dtype=np.int64)]))  # fmt: skip
        nodes = np.asarray(nodes, dtype=np.int64)
        out: list[IntArray] = []
        if nodes.size < 2:
            return np.zeros(0, dtype=np.int64)
        tree = cKDTree(self.points[nodes])
        table = self._facet_table()
        for ftype, fconn, _, keys, _, mult in table:
            # free facets, and those shared with a facet of another order (a 2-node edge
            # of a linear cell on the 3-node edge of a quadratic one: mult counts corners)
            free = mult == 1
            for ft, _, _, other, _, _ in table:
                if ft != ftype and other.shape[1] == keys.shape[1]:
                    free |= match_rows(other, keys)[1]
            fc = fconn[free]
            if not fc.shape[0]:
                continue
            nc = reference(reference(ftype).linear).n_nodes
            X = self.points[fc]  # (f, nodes, dim)
            corners = X[:, :nc]
            centre = corners.mean(axis=1)
            radius = np.linalg.norm(corners - centre[:, None], axis=2).max(axis=1)
            size = np.where(radius > 0, radius, 1.0)
            hits = tree.query_ball_point(centre, radius * (1 + 1e-9) + 1e-12)
            counts = np.fromiter((len(h) for h in hits), dtype=np.int64, count=len(hits))
            if not counts.sum():
                continue
            fi = np.repeat(np.arange(len(hits)), counts)
            nj = nodes[np.concatenate([np.asarray(h, dtype=np.int64) for h in hits])]
            p = self.points[nj]
            tol = rel_tol * size[fi]
            # apart from every node of the facet (its own nodes, and coincident copies)
            apart = (np.linalg.norm(X[fi] - p[:, None, :], axis=2) > tol[:, None]).all(axis=1)
            if nc == 2:  # an edge: on the chord, strictly between its corners
                a, b = corners[fi, 0], corners[fi, 1]
                ab = b - a
                L2 = np.einsum("kd,kd->k", ab, ab)
                s_ = np.einsum("kd,kd->k", p - a, ab) / np.where(L2 > 0, L2, 1.0)
                off = np.linalg.norm(p - a - s_[:, None] * ab, axis=1)
                on = (off <= tol) & (s_ > 0.0) & (s_ < 1.0)
            else:  # a face: in its plane, inside a triangle of its corners
                on = np.zeros(fi.size, dtype=bool)
                tris = [(0, 1, 2)] if nc == 3 else [(0, 1, 2), (0, 2, 3)]
                for i0, i1, i2 in tris:
                    a, b, c = corners[fi, i0], corners[fi, i1], corners[fi, i2]
                    e1, e2, w = b - a, c - a, p - a
                    nrm = np.cross(e1, e2)
                    area2 = np.linalg.norm(nrm, axis=1)
                    ok = area2 > 0
                    unit = nrm / np.where(ok, area2, 1.0)[:, None]
                    height = np.abs(np.einsum("kd,kd->k", w, unit))
                    d00, d01, d11 = (np.einsum("kd,kd->k", u, v)
                                     for u, v in ((e1, e1), (e1, e2), (e2, e2)))  # fmt: skip
                    d20, d21 = np.einsum("kd,kd->k", w, e1), np.einsum("kd,kd->k", w, e2)
                    den = np.where(ok, d00 * d11 - d01 * d01, 1.0)
                    v_ = (d11 * d20 - d01 * d21) / den
                    w_ = (d00 * d21 - d01 * d20) / den
                    eps = tol / size[fi]
                    on |= ok & (height <= tol) & (v_ >= -eps) & (w_ >= -eps) & (v_ + w_ <= 1 + eps)
            hit = on & apart
            if hit.any():
                out.append(nj[hit])
        return np.unique(np.concatenate(out)) if out else np.zeros(0, dtype=np.int64)

    def cell_label(self, ctype: str, index: int) -> str:
        """A cell for messages: its gmsh element id, or its type and index."""
        ids = self.cell_ids.get(ctype)
        if ids is not None:
            return f"gmsh element {int(ids[index])}"
        return f"{ctype} cell {index}"

    def check(self, where: str = "") -> None:
        """Raise :class:`MeshError` on degenerate, inverted or duplicated cells, each named
        (see :func:`pfeie.mesh.check_cells`)."""
        check_cells(self, where)
        self._check_key = self._fingerprint()

    @property
    def checked(self) -> bool:
        """Whether :meth:`check` passed on the points and cells as they are now (the gmsh
        reader checks; :class:`pfeie.Model` checks a mesh that was not, or was edited
        since: a BLAKE2b digest of the arrays, about a millisecond at 20,000 nodes against
        the check's 0.4 s)."""
        return self._check_key is not None and self._check_key == self._fingerprint()

    def _fingerprint(self) -> bytes:
        """A BLAKE2b digest (128 bits) of the points and of each cell type's connectivity."""
        h = hashlib.blake2b(self.points.tobytes(), digest_size=16)
        h.update(str(self.points.shape).encode())
        for t, c in sorted(self.cells.items()):
            h.update(f"|{t}{c.shape}|".encode())
            h.update(c.tobytes())
        return h.digest()

    def facet_multiplicity(self, ftype: str, conn: IntArray) -> IntArray:
        """How many cells share each facet (1 on the boundary, 2 inside; 0 if the facet
        is no face of a cell)."""
        keys = facet_keys(np.asarray(conn, dtype=np.int64), ftype)
        out = np.zeros(keys.shape[0], dtype=np.int64)
        for _, _, _, tkeys, _, count in self._facet_table():
            if tkeys.shape[1] != keys.shape[1] or keys.shape[0] == 0:
                continue
            at, found = match_rows(tkeys, keys)
            out[found] = count[at[found]]
        return out

    def coincident_nodes(self, nodes: IntArray | None = None, rel_tol: float = 1e-3) -> IntArray:
        """Pairs of distinct nodes at the same place, (k, 2) with i < j, among ``nodes``
        (default: the nodes of the cells): closer than ``rel_tol`` × the smallest distance
        between two nodes of one cell (a KD-tree search). A conforming mesh has none; a
        mesh split along its interfaces has its pairs; blocks meshed separately leave them
        along the line where they meet without sharing their nodes."""
        from scipy.spatial import cKDTree

        if nodes is None:
            nodes = np.unique(np.concatenate([c.ravel() for c in self.cells.values()] or
                                             [np.zeros(0, dtype=np.int64)]))  # fmt: skip
        nodes = np.asarray(nodes, dtype=np.int64)
        h = np.inf
        for conn in self.cells.values():
            if conn.shape[0] == 0:
                continue
            x = self.points[conn]  # (cells, nodes, dim)
            for a in range(conn.shape[1] - 1):
                d = np.linalg.norm(x[:, a + 1 :] - x[:, a : a + 1], axis=2)
                h = min(h, float(d.min()))
        if nodes.size < 2 or not np.isfinite(h) or h <= 0.0:
            return np.zeros((0, 2), dtype=np.int64)
        pairs = cKDTree(self.points[nodes]).query_pairs(rel_tol * h, output_type="ndarray")
        out = np.sort(nodes[np.asarray(pairs, dtype=np.int64).reshape(-1, 2)], axis=1)
        return out[np.lexsort((out[:, 1], out[:, 0]))]

    @property
    def dim(self) -> int:
        return int(self.points.shape[1])

    @property
    def n_points(self) -> int:
        return int(self.points.shape[0])

    @property
    def n_cells(self) -> int:
        return int(sum(c.shape[0] for c in self.cells.values()))

    def cell_group(self, name: str) -> dict[str, IntArray]:
        """Cells of a named group, by type; a clear error lists the groups there are."""
        if name not in self.cell_groups:
            raise MeshError(f"no cell group {name!r}{self.empty_note(name)}; the mesh has: "
                            f"{sorted(self.cell_groups) or 'none'}")  # fmt: skip
        return self.cell_groups[name]

    def facet_group(self, name: str) -> dict[str, IntArray]:
        """Facets of a named group, by type; a clear error lists the groups there are."""
        if name not in self.facet_groups:
            raise MeshError(f"no facet group {name!r}{self.empty_note(name)}; the mesh has: "
                            f"{sorted(self.facet_groups) or 'none'}")  # fmt: skip
        return self.facet_groups[name]

    def empty_note(self, name: str) -> str:
        """For messages about a missing group: why a group named in the file is not one
        of the mesh's (empty, or of a lower dimension); empty if the file has no such name."""
        if name not in self.empty_groups:
            return ""
        d = self.empty_groups[name]
        if d < self.dim - 1:
            return (
                f" ({name!r} is a physical group of dimension {d} in the mesh file; "
                f"blocks are of dimension {self.dim}, faces and joints of {self.dim - 1})"
            )
        return (
            f" ({name!r} is a physical group of dimension {d} in the mesh file, but it "
            "holds no elements: add its entities to it before meshing, or mesh them)"
        )

    def group_nodes(self, name: str) -> IntArray:
        """Sorted unique node indices of a facet group or a cell group."""
        if name in self.facet_groups:
            parts = [c.ravel() for c in self.facet_groups[name].values()]
        elif name in self.cell_groups:
            parts = [self.cells[t][i].ravel() for t, i in self.cell_groups[name].items()]
        else:
            raise MeshError(
                f"no group {name!r}{self.empty_note(name)}; cell groups: "
                f"{sorted(self.cell_groups) or 'none'}, facet groups: "
                f"{sorted(self.facet_groups) or 'none'}"
            )
        return np.unique(np.concatenate(parts)) if parts else np.zeros(0, dtype=np.int64)

    def add_cell_group(
        self, name: str, where: Callable[[FloatArray], Any] | None = None
    ) -> dict[str, IntArray]:
        """Add a cell group of the cells whose centroid satisfies ``where(x)``.

        ``where`` receives centroids of shape (n, dim) and returns a boolean mask; ``None``
        selects every cell.
        """
        grp: dict[str, IntArray] = {}
        for ctype, conn in self.cells.items():
            if where is None:
                grp[ctype] = np.arange(conn.shape[0])
                continue
            mask = _mask(where, self.points[conn].mean(axis=1), f"cell group {name!r}")
            grp[ctype] = np.flatnonzero(mask)
        if not any(g.size for g in grp.values()):
            log.warning("cell group %r: where(x) selected no cell", name)
        old = self.cell_groups.get(name)
        if old is not None and (old.keys() != grp.keys() or any(
                not np.array_equal(old[t], grp[t]) for t in grp)):  # fmt: skip
            log.warning("cell group %r: replaced by the new selection", name)
        self.cell_groups[name] = grp
        return grp

    def add_facet_group(
        self, name: str, where: Callable[[FloatArray], Any], boundary_only: bool = True,
        interior_only: bool = False,
    ) -> dict[str, IntArray]:  # fmt: skip
        """Add a facet group of the (boundary) facets whose centroid satisfies ``where(x)``.
        With ``boundary_only=False`` an interior facet is taken once per cell it bounds
        (both sides of a joint; :meth:`facets`), so a joint of k faces holds 2k; with
        ``interior_only=True`` the interior facets alone (a joint chosen by a test that
        the mesh's boundary also meets, such as the radial lines of an arch's voussoirs,
        whose ends lie on the intrados and extrados).

        >>> import pfeie as pf
        >>> mesh = pf.rectangle(2.0, 1.0, 2, 1)
        >>> vertical = lambda x: abs(x[:, 0] - x[:, 0].round()) < 1e-9   # x = 0, 1, 2
        >>> {t: c.shape[0] for t, c in mesh.add_facet_group("j", vertical, False).items()}
        {'line': 4}
        >>> {t: c.shape[0] for t, c in mesh.add_facet_group("j", vertical,
        ...                                                 interior_only=True).items()}
        {'line': 2}
        """
        grp: dict[str, IntArray] = {}
        table = self.facets(boundary_only=boundary_only and not interior_only,
                            interior_only=interior_only)  # fmt: skip
        for ftype, conn in table.items():
            mask = _mask(where, self.points[conn].mean(axis=1), f"facet group {name!r}")
            if mask.any():
                grp[ftype] = conn[mask]
        if not grp:
            log.warning("facet group %r: where(x) selected no %sfacet", name,
                        "interior " if interior_only else "boundary " if boundary_only
                        else "")  # fmt: skip
        old_f = self.facet_groups.get(name)
        if old_f is not None and (old_f.keys() != grp.keys() or any(
                not np.array_equal(old_f[t], grp[t]) for t in grp)):  # fmt: skip
            # (a generator's own 'xmin' redefined: the faces it held are no longer in it)
            log.warning("facet group %r: replaced by the new selection", name)
        self.facet_groups[name] = grp
        return grp

    def facets(
        self, boundary_only: bool = True, interior_only: bool = False
    ) -> dict[str, IntArray]:
        """All facets (or those on the boundary: owned by exactly one cell; or, with
        ``interior_only``, those inside: owned by two or more, once per owner), by type."""
        out: dict[str, list[IntArray]] = {}
        for ftype, conn, _, _, _, count in self._facet_table():
            keep = (conn[count > 1] if interior_only else conn if not boundary_only
                    else conn[count == 1])  # fmt: skip
            out.setdefault(ftype, []).append(keep)
        return {k: np.concatenate(v) for k, v in out.items()}

    def facet_cell_centres(self, ftype: str, facets: IntArray) -> FloatArray:
        """The centroid of one cell adjacent to each facet, the cells of any type (a facet
        group may run along cells of several types: quadrilaterals and triangles)."""
        keys = facet_keys(facets, ftype)
        centre = np.zeros((keys.shape[0], self.points.shape[1]))
        todo = np.ones(keys.shape[0], dtype=bool)
        for table in self._facet_table():
            if table[0] != ftype or not todo.any():
                continue
            at, found = match_rows(table[3], keys)
            hit = found & todo
            cells = self.cells[table[4]][table[2][at[hit]]]
            centre[hit] = self.points[cells].mean(axis=1)
            todo &= ~found
        if todo.any():
            raise MeshError(f"{int(todo.sum())} facet(s) of type {ftype!r} are not faces of any "
                            "cell of the mesh")  # fmt: skip
        return centre

    def _facet_table(self) -> list[tuple[str, IntArray, IntArray, IntArray, str, IntArray]]:
        """Per cell type: (facet type, facet connectivity, owner cell, sorted corner keys,
        cell type, multiplicity of each facet over the whole mesh)."""
        parts = []
        for ctype, conn in self.cells.items():
            ref = reference(ctype)
            fconn = conn[:, np.asarray(ref.facets)].reshape(-1, len(ref.facets[0]))
            owner = np.repeat(np.arange(conn.shape[0]), len(ref.facets))
            parts.append((ref.facet_type, fconn, owner, facet_keys(fconn, ref.facet_type), ctype))
        out = []
        for width in {p[3].shape[1] for p in parts}:
            same = [p for p in parts if p[3].shape[1] == width]
            pool = np.concatenate([p[3] for p in same])
            _, inv, counts = np.unique(pool, axis=0, return_inverse=True, return_counts=True)
            mult = counts[inv.ravel()]
            start = 0
            for p in same:
                n = p[3].shape[0]
                out.append((*p, mult[start : start + n]))
                start += n
        return out

    def orient(self) -> int:
        """Make 2D cells counter-clockwise (positive Jacobian), as meshers such as gmsh
        may store clockwise surfaces; returns the number of cells flipped."""
        if self.dim != 2:
            return 0
        flipped = 0
        for ctype, conn in self.cells.items():
            perm = _FLIP_2D.get(ctype)
            if perm is None:
                continue
            x = self.points[conn[:, :3]]
            a, b = x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]
            area = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
            bad = area < 0
            if bad.any():
                conn[bad] = conn[bad][:, perm]
                flipped += int(bad.sum())
        return flipped

    def restrict(self, groups: list[str]) -> Mesh:
        """The mesh of the cells of the named cell groups only (points and facet groups
        kept; cell groups re-indexed, cells outside every listed group dropped)."""
        keep = {t: np.zeros(c.shape[0], dtype=bool) for t, c in self.cells.items()}
        for g in groups:
            for t, idx in self.cell_group(g).items():
                keep[t][idx] = True
        if all(k.all() for k in keep.values()):
            return self
        new_index = {t: np.cumsum(k) - 1 for t, k in keep.items()}
        cells = {t: c[keep[t]] for t, c in self.cells.items() if keep[t].any()}
        cgroups = {
            name: {t: new_index[t][idx[keep[t][idx]]] for t, idx in grp.items() if t in cells}
            for name, grp in self.cell_groups.items()
        }
        ids = {t: i[keep[t]] for t, i in self.cell_ids.items() if t in cells}
        return Mesh(self.points, cells, cgroups, {k: dict(v) for k, v in self.facet_groups.items()},
                    ids, dict(self.empty_groups))  # fmt: skip

    # -- meshio ---------------------------------------------------------------------------
    def to_meshio(self) -> Any:
        """The same mesh as a :class:`meshio.Mesh` (cell blocks, then facet blocks)."""
        import meshio

        blocks: list[tuple[str, IntArray]] = list(self.cells.items())
        cell_sets: dict[str, list[IntArray]] = {}
        ctypes = list(self.cells)
        facet_blocks: list[tuple[str, str]] = []
        for gname, fgrp in self.facet_groups.items():
            for ftype, conn in fgrp.items():
                blocks.append((ftype, conn))
                facet_blocks.append((gname, ftype))
        for gname, grp in self.cell_groups.items():
            sets = [np.asarray(grp.get(t, np.zeros(0, np.int64))) for t in ctypes]
            sets += [np.zeros(0, np.int64) for _ in facet_blocks]
            cell_sets[gname] = sets
        for i, (gname, _) in enumerate(facet_blocks):
            sets = [np.zeros(0, np.int64) for _ in ctypes]
            for j, (g2, _) in enumerate(facet_blocks):
                n = blocks[len(ctypes) + j][1].shape[0]
                sets.append(np.arange(n) if (g2 == gname and j == i) else np.zeros(0, np.int64))
            if gname in cell_sets:
                raise MeshError(f"name {gname!r} is both a cell group and a facet group")
            prev = cell_sets.get(gname)
            cell_sets[gname] = (
                sets
                if prev is None
                else [np.union1d(a, b) for a, b in zip(prev, sets, strict=True)]
            )
        return meshio.Mesh(self.points, blocks, cell_sets=cell_sets)

    @classmethod
    def from_meshio(cls, m: Any, dim: int | None = None) -> Mesh:
        """Build a mesh from a :class:`meshio.Mesh` whose ``cell_sets`` name the groups.

        Blocks of the top dimension are cells; blocks one dimension lower are facets,
        which belong to the facet groups whose ``cell_sets`` select them.
        """
        dims = [reference(b.type).dim for b in m.cells]
        top = max(dims) if dim is None else dim
        points = planar_points(np.asarray(m.points, dtype=float), top)
        cells: dict[str, list[IntArray]] = {}
        offsets: list[int] = []
        for b, d in zip(m.cells, dims, strict=True):
            if d == top:
                prev = sum(c.shape[0] for c in cells.get(b.type, []))
                offsets.append(prev)
                cells.setdefault(b.type, []).append(np.asarray(b.data))
            else:
                offsets.append(0)
        cgroups: dict[str, dict[str, IntArray]] = {}
        fgroups: dict[str, dict[str, IntArray]] = {}
        for name, sets in getattr(m, "cell_sets", {}).items():
            for b, d, off, idx in zip(m.cells, dims, offsets, sets, strict=True):
                idx = np.asarray(idx, dtype=np.int64)
                if idx.size == 0:
                    continue
                if d == top:
                    g = cgroups.setdefault(name, {})
                    g[b.type] = np.concatenate([g.get(b.type, np.zeros(0, np.int64)), idx + off])
                elif d == top - 1:
                    f = fgroups.setdefault(name, {})
                    data = np.asarray(b.data)[idx]
                    f[b.type] = np.concatenate([f[b.type], data]) if b.type in f else data
        return cls(points, {k: np.concatenate(v) for k, v in cells.items()}, cgroups, fgroups)


# node permutations that reverse the orientation of 2D cells (meshio / VTK order)
_FLIP_2D: dict[str, list[int]] = {
    "triangle": [0, 2, 1],
    "triangle6": [0, 2, 1, 5, 4, 3],
    "quad": [0, 3, 2, 1],
    "quad8": [0, 3, 2, 1, 7, 6, 5, 4],
    "quad9": [0, 3, 2, 1, 7, 6, 5, 4, 8],
}


def planar_points(points: FloatArray, dim: int, where: str = "") -> FloatArray:
    """The first ``dim`` coordinates of ``points``; for a plane mesh (``dim`` 2) given
    with z, z must be the same everywhere (a plane parallel to x-y, usually z = 0), else
    :class:`MeshError` (dropping z would distort the mesh)."""
    if dim == 2 and points.ndim == 2 and points.shape[1] == 3 and points.shape[0]:
        z = points[:, 2]
        extent = max(float(np.ptp(points[:, 0])), float(np.ptp(points[:, 1])), 1e-300)
        if not np.all(np.isfinite(points)):
            raise MeshError(f"{where or 'mesh'}: non-finite node coordinates")
        if float(np.ptp(z)) > 1e-9 * extent:
            k = int(np.argmax(np.abs(z - z[0])))
            raise MeshError(
                f"{where or 'mesh'}: a plane (2D) mesh must lie in the x-y plane, but z "
                f"ranges from {z.min():.6g} to {z.max():.6g} (e.g. node at "
                f"{np.round(points[k], 6).tolist()}); expected z = 0: draw the section in "
                "x-y (a section in x-z or y-z would lose a coordinate); a 3D model whose "
                "mesh has no volume cells reads as a plane one: mesh the volumes (gmsh -3)"
            )
    return np.ascontiguousarray(points[:, :dim], dtype=float)


def facet_keys(conn: IntArray, ftype: str) -> IntArray:
    """Sorted corner node ids of facets: a key equal for the two sides of a facet."""
    ncorner = reference(reference(ftype).linear).n_nodes
    return np.sort(conn[:, :ncorner], axis=1)


def match_rows(table: IntArray, keys: IntArray) -> tuple[IntArray, np.ndarray]:
    """Row index in ``table`` of each row of ``keys`` (first match) and a found-mask (none
    found where the rows differ in length: facets of another shape)."""
    if table.shape[1] != keys.shape[1]:
        return np.full(keys.shape[0], -1, dtype=np.int64), np.zeros(keys.shape[0], dtype=bool)
    both = np.concatenate([table, keys])
    _, inv = np.unique(both, axis=0, return_inverse=True)
    inv = inv.ravel()
    first = np.full(inv.max() + 1, -1, dtype=np.int64)
    first[inv[: table.shape[0]][::-1]] = np.arange(table.shape[0])[::-1]
    found_at = first[inv[table.shape[0] :]]
    return found_at, found_at >= 0
