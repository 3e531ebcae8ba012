"""Element-level verification: shape functions, quadrature, patch tests, mass, loads.

Patch test (Irons & Razzaque 1972; Zienkiewicz & Taylor, The Finite Element Method,
vol. 1, ch. 9): on a distorted mesh, a displacement that is linear in x is the exact
solution of the homogeneous problem with that displacement on the boundary, so every
conforming isoparametric element must reproduce it, with constant stress, to round-off.
"""

from __future__ import annotations

from math import factorial

import numpy as np
import pytest

import pfeie as pf
from conftest import CELLS_2D, distort, unit_mesh
from pfeie.element import SUPPORTED, quadrature, reference

MAT = pf.Elastic(E=210e9, nu=0.3, rho=7800.0)


@pytest.mark.parametrize("name", [s for s in SUPPORTED if s != "vertex"])
def test_shape_functions_interpolate_and_sum_to_one(name: str) -> None:
    """Lagrange property, partition of unity and linear completeness, to round-off
    (measured: 0, 2.2e-16, 4.4e-16, 2.2e-16)."""
    ref = reference(name)
    N, dN = ref.shape_functions(ref.nodes)
    np.testing.assert_allclose(N, np.eye(ref.n_nodes), rtol=0, atol=1e-15)
    xi, _ = quadrature(name, 3)
    N, dN = ref.shape_functions(xi)
    np.testing.assert_allclose(N.sum(axis=1), 1.0, rtol=0, atol=2e-15)
    np.testing.assert_allclose(dN.sum(axis=1), 0.0, rtol=0, atol=4e-15)
    # linear completeness: Σ N_a ξ_a = ξ
    np.testing.assert_allclose(N @ ref.nodes, xi, rtol=0, atol=2e-15)


@pytest.mark.parametrize("name", ["triangle", "tetra"])
@pytest.mark.parametrize("degree", [1, 2, 3, 4, 5])
def test_simplex_quadrature_is_exact(name: str, degree: int) -> None:
    """∫ x^a y^b (z^c) over the unit simplex = a! b! c! / (a + b + c + d)!, to 1e-14
    (measured 1.0e-15)."""
    xi, w = quadrature(name, degree)
    dim = xi.shape[1]
    for exps in np.ndindex(*(degree + 1,) * dim):
        if sum(exps) > degree:
            continue
        exact = np.prod([factorial(e) for e in exps]) / factorial(sum(exps) + dim)
        got = np.sum(w * np.prod(xi ** np.asarray(exps), axis=1))
        assert got == pytest.approx(exact, rel=1e-14)


def _grad(dim: int) -> np.ndarray:
    g = np.array([[1.0, 0.4, -0.3], [-0.2, 0.5, 0.25], [0.3, -0.1, 0.7]])[:dim, :dim]
    return 1e-3 * g


def test_displacement_patch(cell: str) -> None:
    """The linear field and its constant stress, to 1e-14 of the largest displacement
    (measured 2.0e-15) and 1e-13 of the stress (measured 1.8e-14)."""
    mesh = distort(unit_mesh(cell, 3), 0.08)
    dim = mesh.dim
    H = _grad(dim)
    c = np.array([1e-3, -2e-3, 5e-4])[:dim]
    exact = mesh.points @ H.T + c
    model = pf.Model(mesh, [pf.Block("all", MAT)], plane="strain")
    boundary = np.unique(np.concatenate([mesh.group_nodes(g) for g in mesh.facet_groups]))
    for i in range(dim):
        for node in boundary:  # each boundary node gets its own prescribed value
            model.fix([node], i, exact[node, i])
    res = pf.solve_static(model)
    np.testing.assert_allclose(res.u, exact, rtol=0, atol=1e-14 * np.abs(exact).max())
    eps = 0.5 * (H + H.T)
    lam, mu = MAT.lame(dim, "strain")
    sig = np.zeros((3, 3))
    sig[:dim, :dim] = 2 * mu * eps + lam * np.trace(eps) * np.eye(dim)
    if dim == 2:
        sig[2, 2] = lam * np.trace(eps)
    scale = np.abs(sig).max()
    for s, _x in model.stress(res.u).values():
        np.testing.assert_allclose(s, np.broadcast_to(sig, s.shape), rtol=0, atol=1e-13 * scale)
    np.testing.assert_allclose(res.stress(), np.broadcast_to(sig, (mesh.n_points, 3, 3)),
                               rtol=0, atol=1e-13 * scale)  # fmt: skip


@pytest.mark.parametrize("plane", ["strain", "stress"])
@pytest.mark.parametrize("name", CELLS_2D)
def test_pressure_patch_2d(name: str, plane: str) -> None:
    """Uniform pressure p on all sides: σ = −p I in the plane, exact strain everywhere.

    Plane strain: ε = −p(1 + ν)(1 − 2ν)/E; plane stress: ε = −p(1 − ν)/E. Displacements
    to 2e-13 of |ε| (measured 4.9e-14), reactions to 5e-14 of p (measured 5.4e-15).
    """
    mesh = distort(pf.rectangle(2.0, 1.0, 4, 3, cell=name), 0.05)
    p, E, nu = 1e6, MAT.E, MAT.nu
    model = pf.Model(mesh, [pf.Block("all", MAT)], plane=plane)
    for side in ("xmin", "xmax", "ymin", "ymax"):
        model.add_pressure(side, p)
    origin = model.nearest_node([0.0, 0.0])
    model.fix([origin])
    model.fix([model.nearest_node([2.0, 0.0])], 1)
    res = pf.solve_static(model)
    e = -p * (1 + nu) * (1 - 2 * nu) / E if plane == "strain" else -p * (1 - nu) / E
    np.testing.assert_allclose(res.u, e * mesh.points, rtol=0, atol=2e-13 * abs(e))
    np.testing.assert_allclose(np.abs(res.reactions).max(), 0.0, rtol=0, atol=5e-14 * p)


@pytest.mark.parametrize("name", ["tetra", "hexahedron", "tetra10"])
def test_traction_patch_3d(name: str) -> None:
    """Uniaxial traction σ on x-faces: ε_xx = σ/E, ε_yy = ε_zz = −ν σ/E; displacements to
    1e-12 of σ/E (measured 1.1e-13)."""
    mesh = distort(pf.box(2.0, 1.0, 1.0, 3, 2, 2, cell=name), 0.05)
    s = 2e6
    model = pf.Model(mesh, [pf.Block("all", MAT)])
    model.add_traction("xmax", [s, 0.0, 0.0])
    model.add_pressure("xmin", -s)  # a negative pressure pulls outward: tension σ
    model.fix([model.nearest_node([0, 0, 0])])
    model.fix([model.nearest_node([2, 0, 0])], [1, 2])
    model.fix([model.nearest_node([0, 1, 0])], 2)
    res = pf.solve_static(model)
    strain = np.array([s / MAT.E, -MAT.nu * s / MAT.E, -MAT.nu * s / MAT.E])
    np.testing.assert_allclose(res.u, mesh.points * strain, rtol=0, atol=1e-12 * s / MAT.E)


def test_mass_and_gravity_totals(cell: str) -> None:
    """Total mass ρV (consistent and lumped) and weight ρgV, to 2e-15 (measured 3.8e-16);
    no horizontal load, to 1e-12 of the weight (measured 0)."""
    mesh = distort(unit_mesh(cell, 2), 0.05)
    model = pf.Model(mesh, [pf.Block("all", MAT)])
    volume = 1.0
    m_exact = MAT.rho * volume
    assert model.total_mass() == pytest.approx(m_exact, rel=2e-15)
    d = mesh.dim
    for lumped in (False, True):
        M = model.mass(lumped=lumped)
        ones_x = np.zeros(model.n_dof)
        ones_x[0::d] = 1.0
        assert ones_x @ (M @ ones_x) == pytest.approx(m_exact, rel=2e-15)
    assert np.all(model.mass(lumped=True).diagonal()[model.active_nodes * d] > 0)
    model.add_gravity(9.81)
    f = model.load_vector().reshape(-1, d)
    assert f[:, -1].sum() == pytest.approx(-m_exact * 9.81, rel=2e-15)
    np.testing.assert_allclose(f[:, :-1].sum(axis=0), 0.0, rtol=0, atol=1e-12 * m_exact * 9.81)


def test_stiffness_is_symmetric_with_rigid_kernel(cell: str) -> None:
    """K is symmetric (to 5e-16 of its largest entry; measured 6.3e-17) and its null space
    is exactly the rigid motions (3 in 2D, 6 in 3D): those eigenvalues vanish to 2e-15 of
    the largest (measured 2.0e-16), the next is above 1e-3 of it (measured 0.010)."""
    mesh = distort(unit_mesh(cell, 1), 0.05)
    K = pf.Model(mesh, [pf.Block("all", MAT)]).stiffness().toarray()
    np.testing.assert_allclose(K, K.T, rtol=0, atol=5e-16 * np.abs(K).max())
    w = np.linalg.eigvalsh(K)
    n_rigid = 3 if mesh.dim == 2 else 6
    assert np.all(np.abs(w[:n_rigid]) < 2e-15 * w.max())
    assert w[n_rigid] > 1e-3 * w.max()


def test_inverted_cell_is_reported() -> None:
    mesh = pf.rectangle(1.0, 1.0, 1, 1)
    mesh.cells["quad"] = mesh.cells["quad"][:, ::-1].copy()
    with pytest.raises(pf.MeshError, match="inverted"):  # (pf.Model checks the mesh)
        pf.Model(mesh, [pf.Block("all", MAT)])


def test_unknown_groups_are_named() -> None:
    mesh = pf.rectangle(1.0, 1.0, 1, 1)
    with pytest.raises(pf.ModelError, match=r"no cell group .dam.*all"):
        pf.Model(mesh, [pf.Block("dam", MAT)])
    model = pf.Model(mesh, [pf.Block("all", MAT)])
    with pytest.raises(pf.ModelError, match="no group 'base'"):
        model.fix("base")
    with pytest.raises(pf.MechanismError):
        pf.solve_static(model)
