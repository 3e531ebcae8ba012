"""Structured meshes of rectangles and boxes, for tests, examples and benchmarks.

Node coordinates along each axis are given either by a count (uniform spacing) or by an
explicit increasing array (any grading). Simplices come from splitting each quadrilateral
along one diagonal, or each hexahedron into six tetrahedra around its main diagonal
(Kuhn's split, conforming between neighbours). Quadratic cells add one node at the
middle of every edge, shared between cells.

Facet groups ``xmin``, ``xmax``, ``ymin``, ``ymax`` (and ``zmin``, ``zmax`` in 3D) hold
the boundary facets of each side; the cell group ``all`` holds every cell.

Example
-------
>>> from pfeie.mesh import rectangle
>>> m = rectangle(2.0, 1.0, 4, 2, cell="quad8")
>>> m.n_points, m.n_cells, sorted(m.facet_groups)
(37, 8, ['xmax', 'xmin', 'ymax', 'ymin'])
"""

from __future__ import annotations

from itertools import permutations

import numpy as np

from ..element import reference
from ..errors import MeshArgumentError, MeshError
from ..typing import FloatArray, IntArray
from ._mesh import Mesh

_LINEAR_2D = {"quad": "quad", "quad8": "quad", "quad9": "quad",
              "triangle": "triangle", "triangle6": "triangle"}  # fmt: skip
_LINEAR_3D = {"hexahedron": "hexahedron", "tetra": "tetra", "tetra10": "tetra"}


def _plain(value: object) -> object:
    """A numpy scalar (or 0-d array) as the Python number it holds, for messages."""
    if isinstance(value, (np.ndarray, np.generic)) and value.ndim == 0:
        return value.item()
    return value


def _count(n: object, what: str) -> int:
    """An element count: a whole number >= 1 (not a bool, not 1.5)."""
    n = _plain(n)
    if isinstance(n, (bool, np.bool_)) or not isinstance(n, (int, np.integer, float, np.floating)):
        raise MeshArgumentError(f"{what}: expected a whole number of elements >= 1, got {n!r}")
    if not (np.isfinite(n) and float(n) == int(n) and int(n) >= 1):
        raise MeshArgumentError(f"{what}: expected a whole number of elements >= 1, got {n!r}")
    return int(n)


def _size(value: object, what: str) -> float:
    """A length (m): a finite number > 0."""
    value = _plain(value)
    try:
        x = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        x = float("nan")
    if isinstance(value, (bool, np.bool_, str)) or not (np.isfinite(x) and x > 0):
        raise MeshArgumentError(f"{what}: expected a length > 0 (m), got {value!r}")
    return x


def _origin(origin: object, dim: int, what: str) -> FloatArray:
    try:
        o = np.asarray(origin, dtype=float)
        if isinstance(origin, str):
            raise ValueError
    except (TypeError, ValueError):
        o = np.zeros(0)
    if o.shape != (dim,) or not np.all(np.isfinite(o)):
        raise MeshArgumentError(f"{what}: origin: expected {dim} finite coordinates (m), got "
                                f"{origin!r}")  # fmt: skip
    return o


def _axis(n: int | FloatArray, length: float, origin: float, name: str,
          where: str = "") -> FloatArray:  # fmt: skip
    """The node coordinates of one axis: ``n`` elements over ``length`` from ``origin``, or
    the coordinates ``n``; ``name`` is the count's argument (``nx``), ``where`` the
    generator (for messages)."""
    head = f"{where}: " if where else ""
    if np.ndim(n) == 0:
        count = _count(n, f"{head}{name}")
        size = _size(length, f"{head}l{name[1:]}")
        return origin + np.linspace(0.0, size, count + 1)
    x = np.asarray(n, dtype=float)
    if x.ndim != 1 or x.size < 2 or not np.all(np.isfinite(x)) or np.any(np.diff(x) <= 0):
        raise MeshArgumentError(f"{head}{name}: coordinates must be a strictly increasing 1-D "
                                "array of finite numbers")  # fmt: skip
    return x


def graded(length: float, n: int, ratio: float, origin: float = 0.0) -> FloatArray:
    """Coordinates of ``n`` elements whose sizes grow geometrically by ``ratio`` in total
    (last size / first size)."""
    n = _count(n, "graded: n")
    length = _size(length, "graded: length")
    if isinstance(ratio, (bool, np.bool_)) or not (np.isfinite(ratio) and ratio > 0):
        raise MeshArgumentError(f"graded: ratio: expected a number > 0, got {ratio!r}")
    given: object = origin
    one = isinstance(given, list | tuple) or (isinstance(given, np.ndarray) and given.ndim)
    (o,) = _origin(given if one else [given], 1, "graded")
    q = ratio ** (1.0 / max(n - 1, 1))
    h = q ** np.arange(n)
    return np.asarray(o + np.concatenate([[0.0], np.cumsum(h)]) * length / h.sum())


def rectangle(
    lx: float = 1.0,
    ly: float = 1.0,
    nx: int | FloatArray = 1,
    ny: int | FloatArray = 1,
    cell: str = "quad",
    origin: tuple[float, float] = (0.0, 0.0),
) -> Mesh:
    """A structured mesh of the rectangle [x0, x0 + lx] × [y0, y0 + ly].

    ``nx``/``ny`` are element counts or explicit coordinate arrays (then ``lx``/``ly``
    are ignored). ``cell`` is one of quad, quad8, quad9, triangle, triangle6.
    """
    if cell not in _LINEAR_2D:
        raise MeshError(f"rectangle: unsupported cell {cell!r}; use one of {sorted(_LINEAR_2D)}")
    o = _origin(origin, 2, "rectangle")
    x = _axis(nx, lx, o[0], "nx", "rectangle")
    y = _axis(ny, ly, o[1], "ny", "rectangle")
    X, Y = np.meshgrid(x, y, indexing="ij")
    pts = np.stack([X.ravel(), Y.ravel()], axis=1)
    ids = np.arange(x.size * y.size).reshape(x.size, y.size)
    quads = np.stack([ids[:-1, :-1], ids[1:, :-1], ids[1:, 1:], ids[:-1, 1:]], -1).reshape(-1, 4)
    sides = {
        "xmin": np.stack([ids[0, 1:], ids[0, :-1]], 1),
        "xmax": np.stack([ids[-1, :-1], ids[-1, 1:]], 1),
        "ymin": np.stack([ids[:-1, 0], ids[1:, 0]], 1),
        "ymax": np.stack([ids[1:, -1], ids[:-1, -1]], 1),
    }
    if _LINEAR_2D[cell] == "triangle":
        conn = np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
        linear = "triangle"
    else:
        conn, linear = quads, "quad"
    return _finish(pts, conn, linear, cell, sides, "line")


def box(
    lx: float = 1.0,
    ly: float = 1.0,
    lz: float = 1.0,
    nx: int | FloatArray = 1,
    ny: int | FloatArray = 1,
    nz: int | FloatArray = 1,
    cell: str = "hexahedron",
    origin: tuple[float, float, float] = (0.0, 0.0, 0.0),
) -> Mesh:
    """A structured mesh of a box; ``cell`` is one of hexahedron, tetra, tetra10."""
    if cell not in _LINEAR_3D:
        raise MeshError(f"box: unsupported cell {cell!r}; use one of {sorted(_LINEAR_3D)}")
    o = _origin(origin, 3, "box")
    x = _axis(nx, lx, o[0], "nx", "box")
    y = _axis(ny, ly, o[1], "ny", "box")
    z = _axis(nz, lz, o[2], "nz", "box")
    X, Y, Z = np.meshgrid(x, y, z, indexing="ij")
    pts = np.stack([X.ravel(), Y.ravel(), Z.ravel()], axis=1)
    ids = np.arange(pts.shape[0]).reshape(x.size, y.size, z.size)

    def corner(i: int, j: int, k: int) -> IntArray:
        sx = slice(i, x.size - 1 + i)
        sy = slice(j, y.size - 1 + j)
        sz = slice(k, z.size - 1 + k)
        return ids[sx, sy, sz].ravel()

    c = {(i, j, k): corner(i, j, k) for i in (0, 1) for j in (0, 1) for k in (0, 1)}
    hexa = np.stack([c[0, 0, 0], c[1, 0, 0], c[1, 1, 0], c[0, 1, 0],
                     c[0, 0, 1], c[1, 0, 1], c[1, 1, 1], c[0, 1, 1]], axis=1)  # fmt: skip

    def quad_side(a: IntArray) -> IntArray:
        return np.stack([a[:-1, :-1], a[1:, :-1], a[1:, 1:], a[:-1, 1:]], -1).reshape(-1, 4)

    sides = {
        "xmin": quad_side(ids[0, :, :]), "xmax": quad_side(ids[-1, :, :]),
        "ymin": quad_side(ids[:, 0, :]), "ymax": quad_side(ids[:, -1, :]),
        "zmin": quad_side(ids[:, :, 0]), "zmax": quad_side(ids[:, :, -1]),
    }  # fmt: skip
    if cell == "hexahedron":
        return _finish(pts, hexa, "hexahedron", cell, sides, "quad")
    # Kuhn split: one tetrahedron per permutation of the axes, all sharing the diagonal.
    bit = {(0, 0, 0): 0, (1, 0, 0): 1, (1, 1, 0): 2, (0, 1, 0): 3,
           (0, 0, 1): 4, (1, 0, 1): 5, (1, 1, 1): 6, (0, 1, 1): 7}  # fmt: skip
    tets = []
    for perm in permutations(range(3)):
        v = [0, 0, 0]
        path = [bit[tuple(v)]]  # type: ignore[index]
        for axis in perm:
            v[axis] = 1
            path.append(bit[tuple(v)])  # type: ignore[index]
        tets.append(hexa[:, path])
    conn = np.concatenate(tets)
    tri_sides = {k: np.concatenate([q[:, [0, 1, 2]], q[:, [0, 2, 3]]]) for k, q in sides.items()}
    # the face diagonals of the Kuhn split all run from the lowest to the highest corner;
    # split each side quad along the diagonal that the adjacent tetrahedra use.
    for k, q in sides.items():
        p = pts[q]
        lo = np.argmin(p.sum(axis=2), axis=1)
        use_02 = (lo == 0) | (lo == 2)
        tri_sides[k] = np.concatenate([
            np.where(use_02[:, None], q[:, [0, 1, 2]], q[:, [0, 1, 3]]),
            np.where(use_02[:, None], q[:, [0, 2, 3]], q[:, [1, 2, 3]]),
        ])  # fmt: skip
    return _finish(pts, conn, "tetra", cell, tri_sides, "triangle")


def _orient(points: FloatArray, conn: IntArray, linear: str) -> IntArray:
    """Reorder simplices to a positive Jacobian (swap the first two vertices)."""
    if linear not in ("triangle", "tetra"):
        return conn
    p = points[conn]
    edges = p[:, 1:] - p[:, :1]
    det = np.linalg.det(edges)
    neg = det < 0
    conn = conn.copy()
    conn[neg, 0], conn[neg, 1] = conn[neg, 1], conn[neg, 0].copy()
    return conn


def _finish(
    pts: FloatArray,
    conn: IntArray,
    linear: str,
    cell: str,
    sides: dict[str, IntArray],
    facet_linear: str,
) -> Mesh:
    conn = _orient(pts, conn, linear)
    facets = {k: {facet_linear: v} for k, v in sides.items()}
    if cell != linear:
        pts, conn, facets = elevate(pts, conn, linear, cell, facets)
    mesh = Mesh(pts, {cell: conn}, {}, facets)
    mesh.add_cell_group("all")
    return mesh


def elevate(
    points: FloatArray,
    conn: IntArray,
    linear: str,
    target: str,
    facet_groups: dict[str, dict[str, IntArray]],
) -> tuple[FloatArray, IntArray, dict[str, dict[str, IntArray]]]:
    """Add mid-edge (and, for quad9, mid-face) nodes to linear cells and their facets."""
    ref = reference(target)
    edges = np.asarray(reference(linear).edges)
    ev = np.sort(conn[:, edges], axis=2).reshape(-1, 2)
    uniq, inv = np.unique(ev, axis=0, return_inverse=True)
    inv = inv.ravel()
    mids = 0.5 * (points[uniq[:, 0]] + points[uniq[:, 1]])
    new_ids = points.shape[0] + inv.reshape(conn.shape[0], edges.shape[0])
    blocks = [conn, new_ids]
    out_pts = [points, mids]
    if target == "quad9":
        out_pts.append(points[conn].mean(axis=1))
        blocks.append((points.shape[0] + uniq.shape[0] + np.arange(conn.shape[0]))[:, None])
    new_conn = np.concatenate(blocks, axis=1)
    assert new_conn.shape[1] == ref.n_nodes
    fref = reference(ref.facet_type)
    fedges = np.asarray(reference(fref.linear).edges) if fref.dim > 1 else np.array([[0, 1]])
    new_facets: dict[str, dict[str, IntArray]] = {}
    for name, grp in facet_groups.items():
        new_facets[name] = {}
        for _, fc in grp.items():
            fev = np.sort(fc[:, fedges], axis=2).reshape(-1, 2)
            at = _row_index(uniq, fev)
            fmid = points.shape[0] + at.reshape(fc.shape[0], fedges.shape[0])
            new_facets[name][ref.facet_type] = np.concatenate([fc, fmid], axis=1)
    return np.concatenate(out_pts), new_conn, new_facets


def _row_index(table: IntArray, rows: IntArray) -> IntArray:
    """Index in ``table`` (sorted unique rows of two ints) of each of ``rows``."""
    scale = int(max(table.max(initial=0), rows.max(initial=0))) + 1
    tk = table[:, 0] * scale + table[:, 1]
    rk = rows[:, 0] * scale + rows[:, 1]
    at = np.searchsorted(tk, rk)
    if np.any(at >= tk.size) or np.any(tk[np.minimum(at, tk.size - 1)] != rk):
        raise MeshError("a facet edge is not an edge of any cell")
    return at.astype(np.int64)
