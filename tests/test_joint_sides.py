"""Which face of a joint is side b is set by the geometry alone: the joint's normal points
up (towards +x, then +y, on a joint steeper than 84°), so the upper block is side b on
every mesh of one geometry. Before, the sign of the joint's dominant direction was
LAPACK's eigenvector sign: a block on a 20° plane was side b with hexahedra and side a
with tetrahedra, and its joint force and slip vectors flipped sign between the meshes."""

from __future__ import annotations

import numpy as np
import pytest

import pfeie as pf


def _block_on_a_plane(cell: str, dip: float, n: int) -> pf.Model:
    """A 2 × 2 × 2 m box cut at mid-height into a base and a block, turned about y by
    ``dip`` degrees (the joint dips towards +x)."""
    mesh = pf.box(2.0, 2.0, 2.0, n, n, 2 * n, cell=cell)
    mesh.add_cell_group("base", lambda x: x[:, 2] < 1.0)
    mesh.add_cell_group("block", lambda x: x[:, 2] > 1.0)
    mesh.add_facet_group("joint", lambda x: np.abs(x[:, 2] - 1.0) < 1e-9, boundary_only=False)
    c, s = np.cos(np.radians(dip)), np.sin(np.radians(dip))
    mesh.points[:] = mesh.points @ np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])
    rock = pf.Elastic(10e9, 0.25, 2600.0)
    return pf.Model(mesh, [pf.Block("base", rock), pf.Block("block", rock)],
                    interfaces=[pf.Interface("joint", pf.Joint(phi=30.0))])  # fmt: skip


@pytest.mark.parametrize("dip", [0.0, 20.0, 60.0, 88.0, -88.0])
@pytest.mark.parametrize(("cell", "n"), [("hexahedron", 2), ("tetra", 2), ("tetra", 3)])
def test_the_upper_block_is_side_b_on_every_mesh(cell: str, n: int, dip: float) -> None:
    """Every pair's normal has a positive vertical component (joints up to 84° steep),
    or a positive x component (steeper: ±88°, whose normal lies 2° off the horizontal);
    side b is the block on every mesh up to 84°."""
    model = _block_on_a_plane(cell, dip, n)
    P = model.pairs
    assert P is not None
    normal = P.frame[:, -1, :]
    axis = 2 if abs(dip) <= 84.0 else 0
    assert (normal[:, axis] > 0).all()
    # the block lies along (−sin dip, 0, cos dip) from the joint: side b where the
    # normal points there (the block up to 84°; at 88° the normal points +x, the base)
    into_block = np.array([-np.sin(np.radians(dip)), 0.0, np.cos(np.radians(dip))])
    names = model.body_names()
    side_b = {names[b] for b in model.body_of_node[P.node_b]}
    assert side_b == {"block" if normal[0] @ into_block > 0 else "base"}
    if abs(dip) <= 84.0:
        assert side_b == {"block"}
