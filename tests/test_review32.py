"""Defects found in the thirty-second review, each test failing on the code before its fix."""

from __future__ import annotations

import numpy as np
import pytest

import pfeie as pf
from pfeie.errors import MeshError
from pfeie.mesh import Mesh, check_cells

# -- overlapping regions that share no node ------------------------------------------------


def _two(a: Mesh, shift: list[float], names: tuple[str, str] = ("dam", "rock")) -> Mesh:
    """``a`` and a copy of it moved by ``shift``, each with its own nodes and group."""
    pts = np.vstack([a.points, a.points + np.asarray(shift)])
    cells = {k: np.vstack([c, c + a.n_points]) for k, c in a.cells.items()}
    n = {k: c.shape[0] for k, c in a.cells.items()}
    groups = {names[0]: {k: np.arange(m) for k, m in n.items()},
              names[1]: {k: np.arange(m, 2 * m) for k, m in n.items()}}  # fmt: skip
    return Mesh(pts, cells, cell_groups=groups)


@pytest.mark.parametrize(
    ("cell", "shift", "facets"),
    [("quad", [1.3, 0.0], 4), ("triangle", [0.5, 0.25], 6), ("quad8", [0.1, 0.7], 10),
     ("hexahedron", [1.0, 0.5, 0.3], 4), ("tetra10", [0.3, 0.2, 0.1], 80)],
)  # fmt: skip
def test_regions_that_overlap_with_no_node_in_common_are_refused(
    cell: str, shift: list[float], facets: int
) -> None:
    """Two volumes that overlap, not fragmented (gmsh's BooleanFragments left out), have
    no node in common: no coincident nodes, no shared facet; the overlapped part had
    twice its mass and a block's boundary inside the other, without a word. Refused
    now, naming both cells and their groups. The counts are the boundary facets of the
    copy inside the other block (4 × 2 cells of 0.5 m; in 3D 4 × 2 × 2), counted by hand
    for the quads: the copy at x = 1.3 puts its left side's two edges and its ends
    inside; the Tet10 figure is the check's own (the shift puts 80 of the copy's faces
    inside), kept so that a change of its count is seen."""
    mesh = (pf.rectangle(2.0, 1.0, 4, 2, cell=cell) if len(shift) == 2
            else pf.box(2.0, 1.0, 1.0, 4, 2, 2, cell=cell))  # fmt: skip
    words = (rf"{facets} boundary facet\(s\) reach inside cells of another region, the "
             r"first at .* of 'dam' inside .* of 'rock'\): regions overlap with no node in "
             "common")  # fmt: skip
    with pytest.raises(MeshError, match=words):
        check_cells(_two(mesh, shift))


@pytest.mark.parametrize("cell", ["quad", "triangle", "hexahedron", "tetra10"])
def test_blocks_that_meet_on_coincident_or_hanging_nodes_are_accepted(cell: str) -> None:
    """The overlap checks give no false alarm where blocks meet: side by side and one on
    top of the other on coincident nodes (a joint meshed apart), or a block meshed finer
    on the coarser one's face (hanging nodes: a warning elsewhere, not an overlap)."""
    planar = cell in ("quad", "triangle")
    mesh = (pf.rectangle(2.0, 1.0, 4, 2, cell=cell) if planar
            else pf.box(2.0, 1.0, 1.0, 4, 2, 2, cell=cell))  # fmt: skip
    for shift in ([2.0, 0.0], [0.0, 1.0]) if planar else ([2.0, 0.0, 0.0], [0.0, 0.0, 1.0]):
        check_cells(_two(mesh, shift))
    fine = (pf.rectangle(2.0, 1.0, 12, 6, cell=cell, origin=(0.0, 1.0)) if planar
            else pf.box(2.0, 1.0, 1.0, 12, 6, 6, cell=cell, origin=(0.0, 0.0, 1.0)))  # fmt: skip
    pts = np.vstack([mesh.points, fine.points])
    both = Mesh(pts, {k: np.vstack([c, fine.cells[k] + mesh.n_points])
                      for k, c in mesh.cells.items()})  # fmt: skip
    check_cells(both)


@pytest.mark.parametrize("cell", ["triangle", "tetra"])
def test_a_region_meshed_twice_on_its_own_boundary_is_refused(cell: str) -> None:
    """A square (a cube) meshed twice on the same boundary mesh but with other cells
    inside (two volumes on one surface loop): each boundary facet is shared by two cells
    on the same side of it, where the two cells of a facet inside a mesh lie on either
    side. No facet has three cells, so the earlier checks passed it: a block of twice its
    mass. The count is every boundary facet (4 edges; the cube's 12 triangles)."""
    if cell == "triangle":  # the square's two diagonals
        pts = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
        conn = np.array([[0, 1, 2], [0, 2, 3], [0, 1, 3], [1, 2, 3]])
        count = 4
    else:  # the cube of five tetrahedra, and again as 12 from a centre node on its faces
        pts = np.array([[x, y, z] for z in (0.0, 1.0) for y in (0.0, 1.0) for x in (0.0, 1.0)]
                       + [[0.5, 0.5, 0.5]])  # fmt: skip
        five = np.array([[0, 1, 2, 4], [1, 3, 2, 7], [1, 4, 5, 7], [2, 6, 4, 7], [1, 2, 4, 7]])
        faces = five[:, [[1, 2, 3], [0, 2, 3], [0, 1, 3], [0, 1, 2]]].reshape(-1, 3)
        keys, count_of = np.unique(np.sort(faces, axis=1), axis=0, return_counts=True)
        outer = keys[count_of == 1]
        conn = np.vstack([five, np.column_stack([outer, np.full(len(outer), 8)])])
        conn = np.array([c if np.linalg.det(pts[c[1:]] - pts[c[0]]) > 0 else c[[0, 2, 1, 3]]
                         for c in conn])  # fmt: skip
        count = len(outer)
    mesh = Mesh(pts, {cell: conn}, cell_groups={"dam": {cell: np.arange(conn.shape[0])}})
    words = (rf"{count} facet\(s\) shared by two cells on the same side of it, the first "
             r"at .*'dam'.*: two regions meshed over one another")  # fmt: skip
    with pytest.raises(MeshError, match=words):
        check_cells(mesh)
