"""Model builders shared by the interface tests: a block on a fixed base."""

from __future__ import annotations

import numpy as np

import pfeie as pf


def block_on_base(
    *,
    joint: pf.Joint,
    width: float = 1.0,
    height: float = 1.0,
    n: int = 2,
    ny: int | None = None,
    incline_deg: float = 0.0,
    E: float = 30e9,
    nu: float = 0.2,
    rho: float = 2400.0,
    gravity: bool = True,
    cell: str = "quad",
    check_units: bool = True,
) -> pf.Model:
    """A width × height block (n × ny cells, ny = n by default) on a fixed base one cell
    thick, joined by the
    interface "joint"; the whole mesh is rotated by ``incline_deg`` (the joint then
    descends towards +x). The base is fixed in all components. ``check_units=False`` for
    deliberately extreme values (a rigid block's E, :class:`pfeie.Model`)."""
    ny = n if ny is None else ny
    hb = height / ny
    mesh = pf.rectangle(width, height + hb, n, ny + 1, cell=cell)
    mesh.points[:, 1] -= hb
    _groups(mesh, 1)
    if incline_deg:
        th = -np.radians(incline_deg)
        R = np.array([[np.cos(th), -np.sin(th)], [np.sin(th), np.cos(th)]])
        mesh.points[:] = mesh.points @ R.T
    return _model(mesh, joint, pf.Elastic(E, nu, rho), gravity, check_units)


def _groups(mesh: pf.Mesh, up: int) -> None:
    mesh.add_cell_group("base", lambda x: x[:, up] < 0)
    mesh.add_cell_group("block", lambda x: x[:, up] > 0)
    mesh.add_facet_group("joint", lambda x: np.abs(x[:, up]) < 1e-9, boundary_only=False)


def _model(mesh: pf.Mesh, joint: pf.Joint, mat: pf.Elastic, gravity: bool,
           check_units: bool = True) -> pf.Model:  # fmt: skip
    model = pf.Model(mesh, [pf.Block("base", mat), pf.Block("block", mat)],
                     interfaces=[pf.Interface("joint", joint)],
                     check_units=check_units)  # fmt: skip
    model.fix("base")
    if gravity:
        model.add_gravity()
    return model


def block_on_base_3d(
    *, joint: pf.Joint, size: float = 1.0, n: int = 2, E: float = 30e9, rho: float = 2400.0,
    gravity: bool = True,
) -> pf.Model:  # fmt: skip
    """A cube of side ``size`` (n³ hexahedra) on a fixed base one cell thick."""
    hb = size / n
    mesh = pf.box(size, size, size + hb, n, n, n + 1, cell="hexahedron")
    mesh.points[:, 2] -= hb
    _groups(mesh, 2)
    return _model(mesh, joint, pf.Elastic(E, 0.2, rho), gravity)


def slip_x(res: pf.DynamicResult, body: int = 1) -> np.ndarray:
    """Centroid displacement along x of a body (m) over time."""
    return res.rigid[:, body, 0]
