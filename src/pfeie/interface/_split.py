"""Cutting a conforming mesh along interfaces into blocks joined by point pairs.

A node that lies on an interface facet is duplicated once per group of cells around it
that remain connected through facets which are not interface facets. So an interface
that crosses the mesh separates two bodies; one that ends inside a body (a crack tip)
leaves its tip node whole; at a T junction three copies meet and at an X junction four.
Every couple of copies that face each other across an interface facet becomes a *pair*.

Conventions (all arrays have the pair index first):

- side a and side b: the unit normal n of a pair points from side a into side b;
- local frame ``frame`` (m, d, d), rows (t₁, n) in 2D and (t₁, t₂, n) in 3D, so a local
  vector is ``frame @ global``; in 2D t₁ = (n_y, −n_x), in 3D t₁ is the normalised
  projection on the pair's plane of one global axis per interface, the axis least
  aligned with the interface's mean normal (so that the pairs of a plane joint share
  their frame, whatever the round-off in their normals, and their local components add
  up), and t₂ = n × t₁; a pair whose normal lies within 25° of that axis (a joint that
  turns) takes the axis least aligned with its own normal;
- ``area`` (m,): tributary area of the pair, the HRZ-lumped facet "mass" ∫ N_a N_b dA
  (× thickness in 2D), positive for linear and quadratic facets;
- sides: every facet normal is first oriented on the side of its interface's dominant
  direction, made to point up (towards +x, +y on a joint steeper than 84°), so that a
  joint's upper block is its side b whatever the mesh; then all the facets between the
  same two regions (cells connected through facets that are not interface facets), of
  one interface or several, take the same region as side a, the one that holds the
  larger area of them (so that the two planes of a wedge, or a joint that turns by 90°
  or more, face one way and their shear forces add up in the joint's resultant);
- sharp edges: where the facets at a node couple meet at more than
  :data:`EDGE_ANGLE` (the keel of a wedge, a stepped joint), the couple becomes one pair
  per side of the edge, each with its own plane's normal and area, a redundant
  constraint like a T junction; elsewhere a couple is one pair, its normal the
  area-weighted mean of its facets' (a curved joint).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from ..assembly import facet_values, lump_hrz
from ..element import reference
from ..errors import InterfaceError, MeshError
from ..mesh import Mesh, facet_keys, match_rows
from ..typing import BoolArray, FloatArray, IntArray

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class PairGeometry:
    """The point pairs of all interfaces of a split mesh (see the module docstring)."""

    names: tuple[str, ...]
    interface: IntArray  # (m,) index into names
    node_a: IntArray  # (m,)
    node_b: IntArray  # (m,)
    frame: FloatArray  # (m, d, d)
    area: FloatArray  # (m,)
    x: FloatArray  # (m, d)

    @property
    def n(self) -> int:
        return int(self.node_a.size)

    @property
    def dim(self) -> int:
        return int(self.x.shape[1])

    @property
    def redundant(self) -> bool:
        """True when a node belongs to several pairs (T and X junctions): the intact
        constraints there are redundant."""
        nodes = np.concatenate([self.node_a, self.node_b])
        return bool(np.unique(nodes).size < nodes.size)

    def junctions(self, angle: float | None = None) -> BoolArray:
        """(m,) bool: the pairs at a junction, which share a node with a pair whose normal
        turns from theirs by more than ``angle`` degrees (:data:`EDGE_ANGLE` by default;
        the corner of a block where two
        joints meet: a column's foot on its base beside its neighbour's face, a wedge's
        line of intersection). Their node-to-node friction is mesh dependent: a loaded
        corner presses into the pair across it (docs/theory.md, "Two safety factors")."""
        m = self.n
        nodes = np.concatenate([self.node_a, self.node_b])
        who = np.concatenate([np.arange(m), np.arange(m)])
        inc = sp.csr_array(
            (np.ones(2 * m), (nodes, who)), shape=(int(nodes.max(initial=-1)) + 1, m)
        )
        near = sp.coo_array(inc.T @ inc)  # pairs that share a node (and each pair itself)
        i, j = near.row, near.col
        n = self.frame[:, -1, :]
        limit = np.cos(np.radians(EDGE_ANGLE if angle is None else angle))
        turned = np.abs(np.einsum("kd,kd->k", n[i], n[j])) < limit
        out = np.zeros(m, dtype=bool)
        out[i[turned]] = True
        return out

    @cached_property
    def at_junction(self) -> BoolArray:
        """:meth:`junctions` at the default angle, computed once (the static state's
        summary asks it of every joint)."""
        return self.junctions()

    @property
    def regularization(self) -> float:
        """Relative compliance that keeps redundant constraints solvable (1e-12), else 0."""
        return 1e-12 if self.redundant else 0.0

    def of(self, name: str) -> IntArray:
        """Indices of the pairs of one interface."""
        if name not in self.names:
            raise InterfaceError(f"no interface {name!r}; the model's interfaces are "
                                 f"{', '.join(repr(n) for n in self.names) or 'none'}")  # fmt: skip
        return np.flatnonzero(self.interface == self.names.index(name))

    @property
    def centroids(self) -> FloatArray:
        """The area centroid of every interface (n_interfaces, d), m."""
        return self._centroids(self.x)

    def _centroids(self, x: FloatArray) -> FloatArray:
        """The area centroid of every interface (n_interfaces, d) of pairs at ``x``."""
        n = len(self.names)
        A = np.bincount(self.interface, self.area, minlength=n)
        c = np.stack([np.bincount(self.interface, self.area * x[:, i], minlength=n)
                      for i in range(self.dim)], axis=1)  # fmt: skip
        return c / np.maximum(A, 1e-300)[:, None]

    def resultants(
        self, X: FloatArray, frame: FloatArray | None = None, x: FloatArray | None = None
    ) -> tuple[FloatArray, FloatArray]:  # fmt: skip
        """The resultant of the pair forces ``X`` (m, d; local frames, normal + in
        compression, on side b) over each interface: the force on side b in global axes,
        F_j = Σ_k T_kᵀ X_k (n_interfaces, d; N), and its moment about the interface's
        area centroid c_j, M_j = Σ_k (x_k − c_j) × T_kᵀ X_k (n_interfaces, 1 in 2D, the z
        component; 3 in 3D; N·m). For a dam–rock joint, F's horizontal component is the
        base shear and M the overturning moment about the base's centroid; about another
        point p, M_p = M_j + (c_j − p) × F_j. ``frame`` (m, d, d) and ``x`` (m, d): the
        pairs' frames and positions where they are not the reference ones (large
        rotations: the frames turned with the bodies, the pairs where they have moved).

        >>> g = PairGeometry(("base",), np.zeros(2, dtype=np.int64), np.zeros(2, dtype=np.int64),
        ...                  np.ones(2, dtype=np.int64), np.tile(np.eye(2), (2, 1, 1)),
        ...                  np.ones(2), np.array([[-1.0, 0.0], [1.0, 0.0]]))
        >>> F, M = g.resultants(np.array([[0.0, 10.0], [0.0, 30.0]]))  # frames: t = x, n = y
        >>> F.tolist(), M.tolist()     # 40 N up on side b, its moment (1 m × 30 − 1 m × 10)
        ([[0.0, 40.0]], [[20.0]])
        """
        n, d = len(self.names), self.dim
        frame = self.frame if frame is None else frame
        x = self.x if x is None else x
        f = np.einsum("kji,kj->ki", frame, X)  # T_kᵀ X_k
        F = np.stack([np.bincount(self.interface, f[:, i], minlength=n) for i in range(d)],
                     axis=1)  # fmt: skip
        r = x - self._centroids(x)[self.interface]
        mk = (r[:, 0] * f[:, 1] - r[:, 1] * f[:, 0])[:, None] if d == 2 else np.cross(r, f)
        M = np.stack([np.bincount(self.interface, mk[:, i], minlength=n)
                      for i in range(mk.shape[1])], axis=1)  # fmt: skip
        return F.astype(float), M.astype(float)


def block_pieces(
    body_a: IntArray, body_b: IntArray, names: list[str] | tuple[str, ...]
) -> dict[str, IntArray]:
    """The pieces of a joint by the blocks its pairs join (a contraction joint cut by a
    lift joint, a lift joint across monoliths): ``body_a``, ``body_b`` (m,) the blocks of
    the pairs' two sides (indices into ``names``) → ``{"A | B": positions}``, the blocks
    in the order of ``names``, the pieces in that order too. One entry for a joint between
    two blocks.

    >>> block_pieces(np.array([0, 0, 1]), np.array([2, 2, 2]), ["dam", "mid", "rock"])
    {'dam | rock': array([0, 1]), 'mid | rock': array([2])}
    """
    a, b = np.asarray(body_a), np.asarray(body_b)
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    n = len(names)
    key = lo * n + hi
    out: dict[str, IntArray] = {}
    for k in np.unique(key):
        i, j = divmod(int(k), n)
        out[f"{names[i]} | {names[j]}"] = np.flatnonzero(key == k)
    return out


@dataclass(frozen=True)
class SplitMesh:
    """A mesh cut along its interfaces, the pairs, and the bodies (connected parts)."""

    mesh: Mesh
    pairs: PairGeometry
    parent: IntArray  # (n_points,) original node of every node of the split mesh
    body: IntArray  # (n_points,) connected body of every node (-1: unused node)
    n_bodies: int


def _frames(normal: FloatArray, which: IntArray) -> FloatArray:
    """The local frames (m, d, d) of pairs with unit normals (m, d) on the interfaces
    ``which`` (m,) (see the module docstring)."""
    m, d = normal.shape
    F = np.zeros((m, d, d))
    F[:, -1] = normal
    if d == 2:
        F[:, 0, 0], F[:, 0, 1] = normal[:, 1], -normal[:, 0]
        return F
    n_if = int(which.max(initial=-1)) + 1
    mean = np.stack([np.bincount(which, normal[:, i], n_if) for i in range(3)], axis=1)
    size = np.abs(mean)
    size[size < 1e-9 * size.max(axis=1, keepdims=True)] = 0.0  # round-off: ties go to x, y
    axis = np.argmin(size, axis=1)[which]
    own = np.argmin(np.abs(normal), axis=1)
    axis = np.where(np.abs(normal[np.arange(m), axis]) > np.cos(np.radians(25.0)), own, axis)
    e = np.zeros((m, 3))
    e[np.arange(m), axis] = 1.0
    t1 = e - np.einsum("md,md->m", e, normal)[:, None] * normal
    t1 /= np.linalg.norm(t1, axis=1)[:, None]
    F[:, 0] = t1
    F[:, 1] = np.cross(normal, t1)
    return F


#: facets that meet at a node with normals further apart than this (degrees) are a sharp
#: edge of the interface (the keel of a wedge): each side of it keeps its own pair there
EDGE_ANGLE = 30.0


#: the least component of a joint's dominant direction that fixes its sign: the vertical
#: one where it is at least this (a joint not steeper than 84°), else the first
#: horizontal one that is
UPWARD_MIN = 0.1


def _upward(ref: FloatArray) -> FloatArray:
    """The unit vector ``ref`` (d,) or its opposite, chosen by the geometry alone: its
    vertical component (the last axis) positive where it is at least
    :data:`UPWARD_MIN` in magnitude, else its first horizontal component that is (x,
    then y). An eigenvector's sign is LAPACK's, which two meshes of one joint can give
    either way; so a joint's normal points up (towards +x, +y on steep joints) and its
    upper block is side b on every mesh."""
    big = np.flatnonzero(np.abs(ref) >= UPWARD_MIN)
    axis = ref.size - 1 if abs(ref[-1]) >= UPWARD_MIN else int(big[0])
    return ref if ref[axis] > 0 else -ref


def _one_side(
    nrm: FloatArray, ca: IntArray, cb: IntArray, area: FloatArray, link: IntArray,
    owner: IntArray, twin: IntArray, n_cells: int,
) -> tuple[FloatArray, IntArray, IntArray]:  # fmt: skip
    """Interface facets (f,) with their normals ``nrm`` (f, d) pointing from cell ``ca``
    into cell ``cb``, turned so that every facet between the same two regions (cells
    connected through facets that are not interface facets) has the same region on its
    side a: the side that holds the larger area of them (ties: the region of the lower
    index). The normals of one interface are oriented by its dominant direction, which a
    joint that turns by 90° (the two planes of a wedge) leaves undecided, and two
    interfaces (the two planes, named apart) each have their own; a side that changes
    along a joint would make its shear forces cancel in the joint's resultant and its
    pairs at a common node face opposite ways."""
    a, b = owner[link], owner[twin[link]]
    G = sp.coo_matrix((np.ones(a.size), (a, b)), shape=(n_cells, n_cells))
    _, region = connected_components(G, directed=False)
    ra, rb = region[ca], region[cb]
    lo, hi = np.minimum(ra, rb), np.maximum(ra, rb)
    between = lo != hi  # a crack inside one region keeps its orientation
    if not between.any():
        return nrm, ca, cb
    _, key = np.unique(np.stack([lo, hi], axis=1)[between], axis=0, return_inverse=True)
    key = key.ravel()
    low_a = ra[between] < rb[between]
    vote = np.bincount(key, np.where(low_a, area[between], -area[between]))
    turn = np.zeros(ca.size, dtype=bool)
    turn[between] = low_a != (vote >= 0.0)[key]
    if not turn.any():
        return nrm, ca, cb
    nrm = np.where(turn[:, None], -nrm, nrm)
    return nrm, np.where(turn, cb, ca), np.where(turn, ca, cb)


def _edge_sides(pa: IntArray, pb: IntArray, unit: FloatArray) -> IntArray:
    """For every facet corner (c,) at the node couple (``pa``, ``pb``) with its facet's
    unit normal ``unit`` (c, d): 0 where the facets at that couple share a plane (within
    :data:`EDGE_ANGLE` of their mean), else the index of the corner's side of the sharp
    edge (facets within :data:`EDGE_ANGLE` of the first facet of the side), so that the
    couple becomes one pair per side, each with its own normal and area. A single pair
    there would take the mean normal, which on a wedge's keel points 45° off either plane
    and holds the wedge up. The pairs of one couple are redundant constraints (as at a T
    junction: see :attr:`PairGeometry.regularization`)."""
    side = np.zeros(pa.size, dtype=np.int64)
    _, couple = np.unique(np.stack([pa, pb], axis=1), axis=0, return_inverse=True)
    couple = couple.ravel()
    n_c = int(couple.max(initial=-1)) + 1
    mean = np.stack([np.bincount(couple, unit[:, i], n_c) for i in range(unit.shape[1])], axis=1)
    mean = mean / np.maximum(np.linalg.norm(mean, axis=1), 1e-300)[:, None]
    cos = np.einsum("cd,cd->c", unit, mean[couple])
    edge = np.unique(couple[cos < np.cos(np.radians(0.5 * EDGE_ANGLE))])
    if edge.size == 0:
        return side
    limit = np.cos(np.radians(EDGE_ANGLE))
    order = np.argsort(couple, kind="stable")
    start = np.searchsorted(couple[order], edge)
    stop = np.searchsorted(couple[order], edge, side="right")
    for i0, i1 in zip(start.tolist(), stop.tolist(), strict=True):  # sharp edges: set-up only
        firsts: list[FloatArray] = []
        for i in order[i0:i1].tolist():
            near = [j for j, f in enumerate(firsts) if float(unit[i] @ f) >= limit]
            if not near:
                firsts.append(unit[i])
            side[i] = near[0] if near else len(firsts) - 1
    return side


def _same_shape(what: str, ftype: str, corners: int) -> None:
    """A :class:`MeshError` when the facets of ``what``, of type ``ftype``, have another
    number of corners than the faces of the block cells (``corners``): triangles on
    hexahedra, quadrilaterals (a recombined surface) on tetrahedra."""
    n = reference(reference(ftype).linear).n_nodes  # as facet_keys counts them
    if n != corners:
        raise MeshError(
            f"{what}: its facets are {ftype} ({n} corners), but the faces of the block "
            f"cells have {corners} corners; expected facets of the cells' own face type "
            "(mesh the surface as the volume: triangles on tetrahedra, quadrilaterals on "
            "hexahedra)"
        )


def split(mesh: Mesh, names: list[str] | tuple[str, ...], thickness: float = 1.0) -> SplitMesh:
    """Duplicate the nodes of the named facet groups and pair the copies (see module doc).

    Facet groups that are not interfaces keep their facets on the copies of the cell
    they bound; an interface group ``j`` is replaced by ``j:a`` and ``j:b``, its facets
    on either side (e.g. for water pressure inside a joint).

    Example
    -------
    >>> import pfeie as pf
    >>> mesh = pf.rectangle(2.0, 2.0, 2, 2)
    >>> _ = mesh.add_facet_group("mid", lambda x: abs(x[:, 1] - 1.0) < 1e-9, boundary_only=False)
    >>> s = split(mesh, ["mid"])
    >>> s.mesh.n_points - mesh.n_points, s.pairs.n, s.n_bodies
    (3, 3, 2)
    """
    taken = [
        f"{n}:{side}"
        for n in names
        for side in "ab"
        if f"{n}:{side}" in mesh.facet_groups or f"{n}:{side}" in mesh.cell_groups
    ]
    if taken:  # the split would replace it with the joint's face, silently
        raise MeshError(f"physical group {taken[0]!r} of the mesh has the name of a face of "
                        f"the interface {taken[0][:-2]!r} ('<joint>:a' and '<joint>:b' name "
                        "its two faces after the split); expected another name for the "
                        "group")  # fmt: skip
    dim = mesh.dim
    n0 = mesh.n_points
    table = mesh._facet_table()
    ctypes = list(mesh.cells)
    offset = dict(zip(ctypes, np.cumsum([0] + [mesh.cells[t].shape[0] for t in ctypes])[:-1],
                      strict=True))  # fmt: skip
    n_cells = mesh.n_cells
    # every facet of every cell: key, global owner cell, local facet nodes
    keys, owner, fnodes, width = [], [], [], []
    for ftype, fconn, own, key, ctype, _ in table:
        keys.append(key)
        owner.append(own + offset[ctype])
        fnodes.append(fconn)
        width.append(ftype)
    if len({k.shape[1] for k in keys}) > 1:
        raise MeshError("interfaces between cells with different facet shapes are not supported")
    K = np.concatenate(keys)
    O = np.concatenate(owner)
    _, fid, fcount = np.unique(K, axis=0, return_inverse=True, return_counts=True)
    fid = fid.ravel()
    # interface membership of every facet instance
    iface = np.full(K.shape[0], -1, dtype=np.int64)
    for j, name in enumerate(names):
        for ftype, conn in mesh.facet_group(name).items():
            _same_shape(f"interface {name!r}", ftype, K.shape[1])
            at, found = match_rows(K, facet_keys(conn, ftype))
            if not found.all():
                raise MeshError(f"interface {name!r}: {int((~found).sum())} facet(s) are not faces "
                                "of the model's cells (are they faces of cells in no block, or "
                                "is the mesh not conforming across the joint?)")  # fmt: skip
            hit = np.isin(fid, fid[at])
            other = np.unique(iface[hit & (iface >= 0) & (iface != j)])
            if other.size:
                shared = int(np.unique(fid[hit & (iface == other[0])]).size)
                raise MeshError(
                    f"interfaces {names[int(other[0])]!r} and {name!r} share {shared} "
                    "facet(s): a facet belongs to one joint; expected facet groups that do "
                    "not overlap (a group that holds both planes of a wedge is one joint, "
                    "or its planes are two)"
                )  # fmt: skip
            iface[hit] = j
        if not (iface == j).any():
            raise MeshError(
                f"interface {name!r}: its facet group holds no facets (the selection matched "
                "none: a facet group made with boundary_only=True holds no inner facets, and "
                "a joint needs a row of element edges or faces along it); expected the facets "
                "between the two blocks"
            )  # fmt: skip
        inner = np.isin(fid, fid[iface == j]) & (fcount[fid] == 2)
        if not inner[iface == j].all():
            raise MeshError(
                f"interface {name!r} has facets on the mesh boundary (only one cell); at "
                f"{np.round(mesh.points[K[(iface == j) & ~inner][0]].mean(axis=0), 6).tolist()}"
                "; expected facets between two cells (a joint inside the mesh; a support or "
                "a load goes on boundary facets)"
            )
    # the two instances of every interior facet: (first, second) in instance order
    order = np.argsort(fid, kind="stable")
    sf = fid[order]
    twin = np.full(K.shape[0], -1, dtype=np.int64)
    starts = np.flatnonzero(np.r_[True, sf[1:] != sf[:-1]])
    has2 = np.diff(np.r_[starts, sf.size]) == 2
    a_inst, b_inst = order[starts[has2]], order[starts[has2] + 1]
    twin[a_inst], twin[b_inst] = b_inst, a_inst
    F = np.concatenate(fnodes) if len({f.shape[1] for f in fnodes}) == 1 else None
    if F is None:
        widths = {f"{ct} ({reference(ct).facet_type}, {f.shape[1]} nodes)"
                  for ct, f in zip(ctypes, fnodes, strict=True)}  # fmt: skip
        raise MeshError(
            "cells of two element orders (their faces have "
            f"{', '.join(sorted(widths))}): the mesh of a jointed model takes one order "
            "throughout (all linear or all quadratic: gmsh's Mesh.ElementOrder for the "
            "whole model); a linear cell beside a quadratic one is not conforming either"
        )
    iface_nodes = np.unique(F[iface >= 0]) if (iface >= 0).any() else np.zeros(0, np.int64)
    # incidences (node, cell) of interface nodes, and their links through non-interface facets
    cell_conn = [(mesh.cells[t], offset[t]) for t in ctypes]
    inc_node = np.concatenate([c.ravel() for c, _ in cell_conn])
    inc_cell = np.concatenate(
        [np.repeat(np.arange(c.shape[0]) + o, c.shape[1]) for c, o in cell_conn]
    )
    on_iface = np.isin(inc_node, iface_nodes)
    sel = np.flatnonzero(on_iface)
    key_ic = inc_node[sel] * n_cells + inc_cell[sel]
    srt = np.argsort(key_ic)
    key_sorted = key_ic[srt]

    def inc_index(node: IntArray, cell: IntArray) -> IntArray:
        return srt[np.searchsorted(key_sorted, node * n_cells + cell)]

    link = np.flatnonzero((twin >= 0) & (iface < 0))
    link = link[O[link] < O[twin[link]]]
    ln = F[link]  # (l, k) facet nodes
    la = np.repeat(O[link], ln.shape[1])
    lb = np.repeat(O[twin[link]], ln.shape[1])
    lnode = ln.ravel()
    keep = np.isin(lnode, iface_nodes)
    ea = inc_index(lnode[keep], la[keep])
    eb = inc_index(lnode[keep], lb[keep])
    ninc = sel.size
    G = sp.coo_matrix((np.ones(ea.size), (ea, eb)), shape=(ninc, ninc))
    ncomp, comp = connected_components(G, directed=False)
    # a new node per component; the first component of each node keeps its id
    comp_node = np.zeros(ncomp, dtype=np.int64)
    comp_node[comp] = inc_node[sel]
    o = np.lexsort((np.arange(ncomp), comp_node))
    is_first = np.r_[True, comp_node[o][1:] != comp_node[o][:-1]]
    new_id = np.empty(ncomp, dtype=np.int64)
    new_id[o[is_first]] = comp_node[o[is_first]]
    extra = o[~is_first]
    new_id[extra] = n0 + np.arange(extra.size)
    parent = np.concatenate([np.arange(n0), comp_node[extra]])
    flat = inc_node.copy()
    flat[sel] = new_id[comp]
    cells: dict[str, IntArray] = {}
    start = 0
    for t in ctypes:
        c = mesh.cells[t]
        cells[t] = flat[start : start + c.size].reshape(c.shape)
        start += c.size
    points = mesh.points[parent]

    def copy_of(node: IntArray, cell: IntArray) -> IntArray:
        out = node.copy()
        m = np.isin(node, iface_nodes)
        out[m] = new_id[comp[inc_index(node[m], cell[m])]]
        return out

    # pairs: the two instances of every interface facet, node by node
    ftype = width[0]
    inst = np.flatnonzero((iface >= 0) & (twin >= 0))
    inst = inst[O[inst] < O[twin[inst]]]
    fv = facet_values(mesh.points, ftype, F[inst], 2 * reference(ftype).degree, thickness)
    nrm = np.einsum("fq,fqd->fd", fv.dA, fv.normal)
    nrm /= np.linalg.norm(nrm, axis=1)[:, None]
    for j in range(len(names)):
        m = iface[inst] == j
        if m.any():
            S = nrm[m].T @ nrm[m]
            ref = _upward(np.linalg.eigh(S)[1][:, -1])
            nrm[m] *= np.where(nrm[m] @ ref < 0, -1.0, 1.0)[:, None]
    cen = np.zeros((n_cells, dim))
    for c, o_ in cell_conn:
        cen[o_ : o_ + c.shape[0]] = mesh.points[c].mean(axis=1)
    ca, cb = O[inst], O[twin[inst]]
    flip = np.einsum("fd,fd->f", cen[cb] - cen[ca], nrm) < 0
    ca, cb = np.where(flip, cb, ca), np.where(flip, ca, cb)
    nrm, ca, cb = _one_side(nrm, ca, cb, fv.dA.sum(axis=1), link, O, twin, n_cells)
    me = np.einsum("fq,qa,qb->fab", fv.dA, fv.N, fv.N)
    lumped = lump_hrz(me)  # (f, k)
    fn = F[inst]
    k = fn.shape[1]
    pa = copy_of(fn.ravel(), np.repeat(ca, k))
    pb = copy_of(fn.ravel(), np.repeat(cb, k))
    pj = np.repeat(iface[inst], k)
    w_area = lumped.ravel()
    w_norm = (lumped.sum(axis=1)[:, None] * nrm).repeat(k, axis=0)
    real = pa != pb  # a crack tip stays one node: no pair
    pa, pb, pj, w_area, w_norm = pa[real], pb[real], pj[real], w_area[real], w_norm[real]
    unit = nrm.repeat(k, axis=0)[real]
    pk = np.stack([pa, pb, _edge_sides(pa, pb, unit)], axis=1)
    uniq, pinv = np.unique(pk, axis=0, return_inverse=True)
    pinv = pinv.ravel()
    m_pairs = uniq.shape[0]
    area = np.bincount(pinv, w_area, m_pairs).astype(float)
    summed = np.stack([np.bincount(pinv, w_norm[:, i], m_pairs) for i in range(dim)], axis=1)
    normal: FloatArray = summed / np.linalg.norm(summed, axis=1)[:, None]
    which = np.zeros(m_pairs, dtype=np.int64)
    which[pinv] = pj
    pairs = PairGeometry(tuple(names), which, uniq[:, 0], uniq[:, 1], _frames(normal, which),
                         area,
                         points[uniq[:, 0]])  # fmt: skip
    # facet groups on the split mesh
    cell_a = np.full(fcount.size, -1, dtype=np.int64)
    cell_b = cell_a.copy()
    cell_a[fid[inst]], cell_b[fid[inst]] = ca, cb
    fgroups: dict[str, dict[str, IntArray]] = {}
    for gname, grp in mesh.facet_groups.items():
        for gtype, conn in grp.items():
            _same_shape(f"physical group {gname!r}", gtype, K.shape[1])
            at, found = match_rows(K, facet_keys(conn, gtype))
            if not found.any():
                continue
            conn, at = conn[found], at[found]  # facets of cells in no block are dropped
            kk = conn.shape[1]
            if gname in names:
                for side, owner_of in (("a", cell_a), ("b", cell_b)):
                    c_ = np.repeat(owner_of[fid[at]], kk)
                    fgroups.setdefault(f"{gname}:{side}", {})[gtype] = copy_of(
                        conn.ravel(), c_).reshape(conn.shape)  # fmt: skip
            else:
                on = iface[at] >= 0
                if on.any():  # a second group on a joint's faces: one side only
                    joint = names[int(iface[at][on][0])]
                    log.warning(
                        "physical group %r: %d of its facets lie on the interface %r, where "
                        "they keep the face of one side only (the cells of either side, "
                        "facet by facet); a load or a support meant for the joint's faces "
                        "takes the interface's own group: %r (both faces: water in the "
                        "joint), %r or %r (one face)", gname, np.unique(fid[at[on]]).size,
                        joint, joint,
                        f"{joint}:a", f"{joint}:b")  # fmt: skip
                c_ = np.repeat(O[at], kk)
                fgroups.setdefault(gname, {})[gtype] = copy_of(conn.ravel(), c_).reshape(conn.shape)
    out = Mesh(points, cells, {k_: dict(v) for k_, v in mesh.cell_groups.items()}, fgroups,
               cell_ids={t: i for t, i in mesh.cell_ids.items() if t in cells},
               empty_groups=dict(mesh.empty_groups))  # fmt: skip
    # bodies: connected components of the split mesh
    used = np.concatenate([c.ravel() for c in cells.values()])
    cid = np.concatenate([np.repeat(np.arange(c.shape[0]) + offset[t], c.shape[1])
                          for t, c in cells.items()])  # fmt: skip
    Bg = sp.coo_matrix((np.ones(used.size), (used, cid + points.shape[0])),
                       shape=(points.shape[0] + n_cells,) * 2)  # fmt: skip
    _nb, lab = connected_components(Bg, directed=False)
    body = np.full(points.shape[0], -1, dtype=np.int64)
    body[used] = lab[used]
    _, body_used = np.unique(body[used], return_inverse=True)
    body[used] = body_used.ravel()
    return SplitMesh(out, pairs, parent, body, int(body[used].max()) + 1 if used.size else 0)
