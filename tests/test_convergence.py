"""Spatial convergence against a manufactured solution.

u_i(x) = Π_d sin(k_id π x_d) on the unit square/cube vanishes on the boundary; the body
force b = −div σ = −[μ Δu + (λ + μ) ∇(∇·u)] is derived from its exact Hessian. For
smooth solutions the L2 error of degree-p Lagrange elements decays as h^(p+1) and the
energy-norm error as h^p (Ciarlet, The Finite Element Method for Elliptic Problems,
Thm 3.2.2 and §3.2); the observed rates on the two finest meshes must lie within a
tolerance per element set within 10× of the measured deviation (written beside it).
"""

from __future__ import annotations

import numpy as np
import pytest

import pfeie as pf
from conftest import unit_mesh
from pfeie import assembly as asm
from pfeie.element import reference

MAT = pf.Elastic(E=1.0, nu=0.3, rho=0.0)
WAVE = np.array([[1, 1, 1], [2, 1, 1], [1, 1, 2]])  # k_id: component i, direction d


def exact(x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """u (…, d), ∇u (…, i, p) and the Hessian (…, i, p, q) of the manufactured field."""
    d = x.shape[-1]
    k = np.pi * WAVE[:d, :d]  # (i, d)
    s = np.sin(k * x[..., None, :])  # (…, i, d)
    c = np.cos(k * x[..., None, :])
    u = s.prod(axis=-1)
    grad = np.empty((*x.shape[:-1], d, d))
    hess = np.empty((*x.shape[:-1], d, d, d))
    for p in range(d):
        fp = s.copy()
        fp[..., p] = k[:, p] * c[..., p]
        grad[..., p] = fp.prod(axis=-1)
        for q in range(d):
            fq = fp.copy()
            fq[..., q] = -(k[:, p] ** 2) * s[..., p] if q == p else k[:, q] * c[..., q]
            hess[..., p, q] = fq.prod(axis=-1)
    return u, grad, hess


def body_force(x: np.ndarray) -> np.ndarray:
    lam, mu = MAT.lame(x.shape[-1], "strain")
    _, _, h = exact(x)
    lap = np.einsum("...ipp->...i", h)
    grad_div = np.einsum("...jij->...i", h)
    return -(mu * lap + (lam + mu) * grad_div)


def errors(cell: str, n: int) -> tuple[float, float]:
    mesh = unit_mesh(cell, n)
    model = pf.Model(mesh, [pf.Block("all", MAT)], plane="strain")
    for g in mesh.facet_groups:
        model.fix(g)
    model.add_body_force(body_force)
    u = pf.solve_static(model).u
    deg = 2 * reference(cell).degree + 2
    cv = asm.cell_values(mesh.points, cell, mesh.cells[cell], deg)
    ue = u[mesh.cells[cell]]
    uh = np.einsum("qn,cnd->cqd", cv.N, ue)
    gh = np.einsum("cqnp,cni->cqip", cv.dNdx, ue)
    uex, gex, _ = exact(cv.x)
    l2 = np.sqrt(np.sum(cv.dV * np.sum((uh - uex) ** 2, axis=-1)))
    h1 = np.sqrt(np.sum(cv.dV * np.sum((gh - gex) ** 2, axis=(-1, -2))))
    return float(l2), float(h1)


# cell, mesh sizes, tolerances of the L2 and energy-norm rates (measured deviations from
# p + 1 and p on the two finest meshes in the comments)
CASES = [
    ("triangle", [8, 16, 32], 0.1, 0.01),  # 0.031, 0.0025
    ("quad", [8, 16, 32], 0.005, 0.005),  # 7.3e-4, 8.7e-4
    ("triangle6", [4, 8, 16], 0.05, 0.05),  # 0.0082, 0.018
    ("quad8", [4, 8, 16], 0.05, 0.01),  # 0.015, 0.0020
    ("quad9", [4, 8, 16], 0.05, 0.02),  # 0.015, 0.0060
    ("hexahedron", [4, 8, 12], 0.05, 0.01),  # 0.019, 0.0022
    ("tetra10", [4, 6, 8], 0.1, 0.1),  # 0.025, 0.081 (coarse meshes: pre-asymptotic)
]


@pytest.mark.parametrize(("cell", "sizes", "tol_l2", "tol_h1"), CASES)
def test_convergence_rates(cell: str, sizes: list[int], tol_l2: float, tol_h1: float) -> None:
    p = reference(cell).degree
    e = np.array([errors(cell, n) for n in sizes])
    h = 1.0 / np.asarray(sizes, dtype=float)
    rate_l2 = np.log(e[-2, 0] / e[-1, 0]) / np.log(h[-2] / h[-1])
    rate_h1 = np.log(e[-2, 1] / e[-1, 1]) / np.log(h[-2] / h[-1])
    assert rate_l2 == pytest.approx(p + 1, abs=tol_l2), (cell, e[:, 0])
    assert rate_h1 == pytest.approx(p, abs=tol_h1), (cell, e[:, 1])


@pytest.mark.slow
@pytest.mark.parametrize(("cell", "sizes"), [("tetra", [8, 16, 24])])
def test_convergence_rates_tet4(cell: str, sizes: list[int]) -> None:
    test_convergence_rates(cell, sizes, 0.1, 0.02)  # measured 0.055, 0.0048
