"""The reservoir's added mass (Westergaard 1933), against its closed forms.

On a rigid vertical face of water depth H the pressure per unit normal acceleration is
C(y) = 7/8 ρ_w √(H y), y the depth; its integrals give the added mass and its first and
second moments about the bottom, per metre of face:

    ∫ C dy = 7/12 ρ_w H²,   ∫ C (H − y) dy = 7/30 ρ_w H³,   ∫ C (H − y)² dy = 2/15 ρ_w H⁴.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla
import scipy.sparse as sp
from scipy.integrate import quad

import pfeie as pf

RHO_W = 1000.0


def _consistent_loads(ys: np.ndarray, p: int, level: float, H: float) -> np.ndarray:
    """∫ N_a C dy on a vertical face with facet corners ``ys`` (bottom up, degree p
    Lagrange facets), by adaptive quadrature (scipy's QUADPACK, independent of pfeie's
    Gauss rules), per face node bottom up, per unit normal acceleration (kg/m)."""
    def C(z: float) -> float:
        return 0.875 * RHO_W * np.sqrt(H * max(level - z, 0.0))

    out = np.zeros(p * (ys.size - 1) + 1)
    for k in range(ys.size - 1):
        nodes = np.linspace(ys[k], ys[k + 1], p + 1)
        cut = [v for v in (level,) if nodes[0] < v < nodes[-1]]
        for j in range(p + 1):
            def f(z: float, j: int = j, nodes: np.ndarray = nodes) -> float:
                others = [i for i in range(p + 1) if i != j]
                N = np.prod([(z - nodes[i]) / (nodes[j] - nodes[i]) for i in others])
                return float(N) * C(z)

            out[p * k + j] += quad(f, nodes[0], nodes[-1], points=cut or None, epsabs=0.0,
                                   epsrel=1e-13, limit=200)[0]  # fmt: skip
    return out


@pytest.mark.parametrize(("cell", "n", "level"),
                         [("quad", 16, 10.0), ("quad8", 16, 10.0), ("quad8", 5, 10.0),
                          ("quad", 16, 9.3)])  # fmt: skip
def test_westergaard_loads_are_the_closed_form_pressures(cell: str, n: int, level: float) -> None:
    """A rigid vertical face accelerated by a uniformly along its normal: the nodal forces
    m_a a are the consistent loads ∫ N_a p dy of Westergaard's p = 7/8 ρ_w a √(H y) (y
    the depth), computed here by adaptive quadrature, to 1e-6 of the largest (measured
    7e-13 to 5e-12: the facet that meets the surface is integrated with the square root
    of p mapped out); their sum is 7/12 ρ_w a H² (Westergaard's total) to 1e-12
    (measured 4e-15 to 2e-13). Linear and quadratic facets, a level at a node and one between
    nodes (9.3 m, on the linear face: the bottom at 0, H = 9.3 m)."""
    H = level
    mesh = pf.rectangle(1.0, 10.0, 1, n, cell=cell)
    m = pf.Model(mesh, [pf.Block("all", pf.Elastic(30e9, 0.2, 2400.0))])
    m.add_westergaard("xmin", water_level=level)
    a = 1.7  # m/s², towards the water
    force = (m.added_mass() * a).reshape(-1, 2)
    assert np.all(force[:, 1] == 0.0) and np.all(force[:, 0] >= 0.0)
    face = np.flatnonzero(mesh.points[:, 0] < 1e-9)
    face = face[np.argsort(mesh.points[face, 1])]
    p = 1 if cell == "quad" else 2
    ref = a * _consistent_loads(np.linspace(0.0, 10.0, n + 1), p, level, H)
    err = np.abs(force[face, 0] - ref).max() / ref.max()
    assert err < 5e-11, err  # the bound is 1e-6; 10× the worst measured
    total = force[:, 0].sum() / (7 / 12 * RHO_W * a * H**2) - 1
    assert abs(total) < 1e-12, total
    # the nodes of the facets wholly above the level carry nothing
    assert np.all(force[face[mesh.points[face, 1] > level + 10.0 / n], 0] == 0.0)


@pytest.mark.parametrize("theta", [15.0, 30.0, 45.0])
def test_westergaard_on_an_inclined_face(theta: float) -> None:
    """The normal-direction form on a planar face inclined θ from the vertical (Kuo 1982;
    USACE EM 1110-2-6051's generalised Westergaard): m_ab = ∫ C(z) N_a N_b n nᵀ dA, with
    dA = dz/cos θ along the face and n = (cos θ, sin θ) for a face leaning downstream
    (the water above it): the horizontal added mass totals cos θ ∫ C dz = 7/12 ρ_w H² cos θ
    and the vertical one sin²θ/cos θ 7/12 ρ_w H², to round-off (asserted 1e-13, measured
    1.3e-14 at most)."""
    H = 10.0
    t = np.radians(theta)
    # (a base of 12 m: narrower, the face at 45° crosses the back and inverts the cells)
    mesh = pf.rectangle(12.0, H, 3, 8, cell="quad8")
    x, y = mesh.points[:, 0], mesh.points[:, 1]
    mesh.points[:, 0] = x + (H - y) * np.tan(t) * (1 - x / 12.0)  # left face leans over the toe
    m = pf.Model(mesh, [pf.Block("all", pf.Elastic(30e9, 0.2, 2400.0))])
    m.add_westergaard("xmin", water_level=H)
    am = m.added_mass().reshape(-1, 2)
    total = 7 / 12 * RHO_W * H**2
    assert am[:, 0].sum() == pytest.approx(total * np.cos(t), rel=1e-13)
    assert am[:, 1].sum() == pytest.approx(total * np.sin(t) ** 2 / np.cos(t), rel=1e-13)


def _battered(cell: str, theta: float, height: float = 12.0) -> pf.Mesh:
    """An 8 m wide block (3 × 10 cells) whose upstream face (the group ``xmin``) runs
    straight from (−height tan θ, 0) to (0, height): inclined θ from the vertical,
    battered (the water above it, outward normal n = (−cos θ, sin θ)) for θ > 0,
    overhanging for θ < 0."""
    mesh = pf.rectangle(8.0, height, 3, 10, cell=cell)
    x, y = mesh.points[:, 0].copy(), mesh.points[:, 1].copy()
    mesh.points[:, 0] = x - (height - y) * np.tan(np.radians(theta)) * (1 - x / 8.0)
    return mesh


# the largest relative errors measured over the cases of the next test, 2D and 3D
# (closed-form totals; nodal forces off the normal, of the largest)
RIGID_FACE = {"total": 3.3e-16, "across": 4.5e-16, "3d": 1.8e-15, "3d_nodal": 4.3e-15}


@pytest.mark.parametrize("cell", ["quad", "quad8"])
@pytest.mark.parametrize("theta", [30.0, np.degrees(np.arctan(0.5)), -20.0])
@pytest.mark.parametrize("level", [12.0, 9.3])
def test_westergaard_inclined_face_pushes_along_its_normal(
    cell: str, theta: float, level: float
) -> None:
    """A rigid plane face inclined θ from the vertical, wet to the depth H = h (the
    bottom at z = 0, the level h at the top or cutting a facet), accelerated uniformly
    by a along x. Westergaard's pressure C(z) (a·n) acts along the normal
    n = (−cos θ, sin θ) (θ > 0 battered: the water above the face; θ < 0 overhanging),
    and the nodal forces of the added mass sum to its resultant: along the face
    dA = dz/cos θ per metre, so

        ∫ C dA = (1/cos θ) ∫₀ᴴ 7/8 ρ_w √(H (H − z)) dz = 7/12 ρ_w H² / cos θ,
        Σ_a m_a a = ∫ C (a·n) n dA = a n_x n ∫ C dA = 7/12 ρ_w H² a (cos θ, −sin θ),

    both components (the water's force on the face is minus that). Before the blocks
    kept n nᵀ the vertical part was 0: with tan θ = 0.5, H = 10 m, a = g, (511.8, 0) kN
    instead of (511.8, −255.9) kN (add_westergaard's example). Asserted to
    10 × RIGID_FACE["total"] (measured 3.3e-16 at most) of each component; every nodal
    force lies along n, m_a a = μ_a (a·n) n with μ_a the node's scalar mass (the trace
    of its block, the diagonal's sum: added_mass()), to 10 × RIGID_FACE["across"] of the
    largest (measured 4.5e-16); the blocks are symmetric, the time stepping keeps them
    (added_mass_coupled)."""
    t = np.radians(theta)
    mesh = _battered(cell, theta)
    m = pf.Model(mesh, [pf.Block("all", pf.Elastic(30e9, 0.2, 2400.0))])
    m.add_westergaard("xmin", water_level=level)
    a = np.array([1.7, 0.0])
    Ma = m.added_mass_matrix()
    assert abs(Ma - Ma.T).max() == 0.0
    f = (Ma @ np.tile(a, mesh.n_points)).reshape(-1, 2)
    H = level
    ref = 7 / 12 * RHO_W * H**2 * a[0] * np.array([np.cos(t), -np.sin(t)])
    err = np.abs(f.sum(axis=0) / ref - 1)
    assert err.max() < 10 * RIGID_FACE["total"], err
    n = np.array([-np.cos(t), np.sin(t)])
    mu = m.added_mass().reshape(-1, 2).sum(axis=1)
    nodal = np.abs(f - (mu * (a @ n))[:, None] * n).max() / np.abs(f).max()
    assert nodal < 10 * RIGID_FACE["across"], nodal
    # the lumped mass keeps the coupling beside its diagonal, as the time stepping does
    lumped = m.mass(lumped=True)
    assert m.added_mass_coupled() and lumped.nnz > np.count_nonzero(lumped.diagonal())
    assert abs(lumped - m.mass(lumped=True, full_reservoir=True)).max() == 0.0


def _curved_face_force(mesh: pf.Mesh, level: float, a: np.ndarray) -> np.ndarray:
    """∫ C (a·n) n dA over the curved 3-node facets of ``xmin`` (bottom at z = 0, H =
    level), independently of pfeie: each facet x(s) = Σ N_i(s) X_i with the closed-form
    quadratic Lagrange functions (ends s = ∓1, middle node s = 0), n from x'(s), dA =
    |x'(s)| ds, by QUADPACK with a break where the facet crosses the level."""
    out = np.zeros(2)
    for conn in mesh.facet_group("xmin").values():
        for facet in conn:
            X = mesh.points[facet]

            def f(s: float, k: int, X: np.ndarray = X) -> float:
                N = np.array([s * (s - 1) / 2, s * (s + 1) / 2, 1 - s * s])
                t = np.array([s - 0.5, s + 0.5, -2 * s]) @ X
                J = float(np.linalg.norm(t))
                n = np.array([t[1], -t[0]]) / J
                C = 0.875 * RHO_W * np.sqrt(level * max(level - float(N @ X[:, 1]), 0.0))
                return float(C * (a @ n) * n[k] * J)

            s = np.linspace(-1.0, 1.0, 2001)
            z = (np.column_stack([s * (s - 1) / 2, s * (s + 1) / 2, 1 - s * s]) @ X)[:, 1]
            cut = [float(s[i]) for i in np.flatnonzero((z[:-1] - level) * (z[1:] - level) < 0)]
            for k in range(2):
                out[k] += quad(f, -1.0, 1.0, args=(k,), points=cut or None, epsabs=0.0,
                               epsrel=1e-13, limit=400)[0]  # fmt: skip
    return out


@pytest.mark.parametrize("amp", [0.4, 1.5])
@pytest.mark.parametrize("level", [10.0, 9.0, 7.7])
def test_westergaard_on_a_curved_face(amp: float, level: float) -> None:
    """A battered face (0.3 H : 1 V) bulging by amp · sin(π z/10) (Q8: curved 3-node
    facets, their normal turning along them), at the top, at 9 m and 7.7 m (cutting
    facets): the blocks ∫ C N_a n nᵀ dA (the normal of each quadrature point) under a
    uniform a = (1, 0) total ∫ C (a·n) n dA by QUADPACK on the same quadratic facets
    (_curved_face_force) to 4e-15 of the largest component (measured 3.9e-16 at most),
    and every block is positive semi-definite (its least eigenvalue ≥ 0; measured ≥ 7e-6
    of its trace). On a strongly curved facet (the middle node 1.5 m off a 2 m chord)
    the consistent blocks would be indefinite (N_a < 0 where n turns): the facet then
    shares its ∫ C n nᵀ dA by the scalar masses, all blocks ≥ 0, the total kept to
    4e-15 (measured 3.7e-16)."""
    from pfeie import assembly as asm
    from pfeie.model._model import _westergaard_add

    mesh = pf.rectangle(3.0, 10.0, 3, 5, cell="quad8")
    x, y = mesh.points[:, 0].copy(), mesh.points[:, 1].copy()
    mesh.points[:, 0] = x - (amp * np.sin(np.pi * y / 10.0) + 0.3 * (10.0 - y)) * (1 - x / 3)
    m = pf.Model(mesh, [pf.Block("all", pf.Elastic(30e9, 0.2, 2400.0))])
    m.add_westergaard("xmin", water_level=level)
    a = np.array([1.0, 0.0])
    F = (m.added_mass_matrix() @ np.tile(a, mesh.n_points)).reshape(-1, 2).sum(axis=0)
    ref = _curved_face_force(mesh, level, a)
    assert np.abs(F - ref).max() < 4e-15 * np.abs(ref).max()
    blocks = m._westergaard_blocks()
    assert np.linalg.eigvalsh(blocks).min() >= 0.0
    # one strongly curved facet, through the private kernel
    pts = np.array([[0.0, 0.0], [0.0, 2.0], [-1.5, 1.0]])
    conn = np.array([[0, 1, 2]])
    fv = asm.facet_values(pts, "line3", conn, 40, 1.0)
    N = np.broadcast_to(fv.N, (*fv.dA.shape, fv.N.shape[1]))
    out = np.zeros((3, 2, 2))
    _westergaard_add(out, conn, N, fv.dA, fv.x, fv.normal, 5.0, 5.0, RHO_W, pts[conn[:, :2]])
    c = 0.875 * RHO_W * np.sqrt(5.0 * (5.0 - fv.x[..., 1])) * fv.dA
    per = np.einsum("fqa,fq,fqi,fqj->aij", N, c, fv.normal, fv.normal)
    whole = per.sum(axis=0)
    assert np.linalg.eigvalsh(per).min() < -0.02 * np.trace(whole)  # indefinite
    assert np.linalg.eigvalsh(out).min() > 0.0
    assert np.abs(out.sum(axis=0) - whole).max() < 4e-15 * np.abs(whole).max()


def _wet_block(ny: int, westergaard: bool = True) -> pf.Model:
    """A stiff 1 m block (E = 1e14 Pa) on joint springs k_n = k_s = 1e9 Pa/m, its left face
    wet up to its top (H = 1 m), on a fixed base."""
    mesh = pf.rectangle(1.0, 1.5, 4, ny + ny // 2)
    mesh.add_cell_group("base", lambda x: x[:, 1] < 0.5)
    mesh.add_cell_group("block", lambda x: x[:, 1] > 0.5)
    mesh.add_facet_group("joint", lambda x: np.abs(x[:, 1] - 0.5) < 1e-9, False)
    mesh.add_facet_group("wet", lambda x: (x[:, 0] < 1e-9) & (x[:, 1] > 0.5 - 1e-9))
    mat = pf.Elastic(1e14, 0.2, 2400.0)
    joint = pf.Joint(phi=30.0, kn=1e9, ks=1e9)
    m = pf.Model(mesh, [pf.Block("base", mat), pf.Block("block", mat)],
                 interfaces=[pf.Interface("joint", joint)])  # fmt: skip
    m.fix("base")
    if westergaard:
        m.add_westergaard("wet", water_level=1.5)
    return m


def test_added_mass_in_the_modes_of_a_block_on_springs() -> None:
    """The sliding-rocking modes of the wet block: the 2 × 2 rigid-body problem about the
    joint's centre with the block's mass and the added mass's closed-form moments,
    M = [[m + m_a, m h + S_a], [m h + S_a, I + I_a]] (m_a = 7/12 ρ_w H², S_a = 7/30 ρ_w H³,
    I_a = 2/15 ρ_w H⁴), K = diag(k_s A, Σ k_n A_i x_i²); the vertical mode does not see
    the added mass (it acts along x). The lumped added mass (row sums: the consistent
    loads of the pressure) has Westergaard's total m_a and first moment S_a to round-off
    (asserted 1e-11; measured 4e-12 at most), its second moment to O(h²) (4.6e-2 to 7.1e-4
    on 4 to 32 cells): errors fall at second order with the face's cells (measured 2.0e-3,
    4.9e-4, 1.2e-4, 3.3e-5 for the first mode, 4.8e-3 to 7.9e-5 for the third: rates 1.93
    to 2.00; asserted rates ≥ 1.8, 5e-5 and 1e-4 on 32 cells); the vertical mode within
    2e-6 of √(k_n A/m)/2π (measured 1.6e-6, the block's own deformability)."""
    m_b, h, H = 2400.0, 0.5, 1.0
    m_a, s_a, i_a = 7 / 12 * RHO_W * H**2, 7 / 30 * RHO_W * H**3, 2 / 15 * RHO_W * H**4
    errs = []
    ns = [4, 8, 16, 32]
    for ny in ns:
        model = _wet_block(ny)
        P = model.pairs
        assert P is not None
        x = model.mesh.points[P.node_a, 0] - 0.5
        Mr = np.array([[m_b + m_a, m_b * h + s_a], [m_b * h + s_a, m_b / 6 + m_b * h * h + i_a]])
        Kr = np.diag([1e9 * P.area.sum(), float((1e9 * P.area * x**2).sum())])
        f_hr = np.sqrt(sla.eigh(Kr, Mr, eigvals_only=True)) / (2 * np.pi)
        f_v = np.sqrt(1e9 * P.area.sum() / m_b) / (2 * np.pi)
        f = pf.modal(model, 3).frequencies
        errs.append([abs(f[0] / f_hr[0] - 1), abs(f[2] / f_hr[1] - 1)])
        am = model.added_mass().reshape(-1, 2)[:, 0]
        z = model.mesh.points[:, 1] - 0.5  # height above the joint (the bottom)
        assert am.sum() == pytest.approx(m_a, rel=1e-11)
        assert (am * z).sum() == pytest.approx(s_a, rel=1e-11)
        assert f[1] == pytest.approx(f_v, rel=2e-6)
    e = np.array(errs)
    rates = np.log2(e[:-1] / e[1:])
    assert rates.min() >= 1.8, rates
    assert e[-1, 0] < 5e-5 and e[-1, 1] < 1e-4, e[-1]
    dry = pf.modal(_wet_block(8, westergaard=False), 1).frequencies[0]
    assert dry > 1.05 * pf.modal(_wet_block(8), 1).frequencies[0]  # the water slows it (7 %)


def test_added_mass_errors_and_model_file(tmp_path) -> None:  # type: ignore[no-untyped-def]
    """A water level at or below the reservoir bottom, or a group of cells, is refused
    with the key named; through a model file the added mass reaches the run's M."""
    model = _wet_block(4, westergaard=False)
    with pytest.raises(pf.ModelError, match="must lie above the reservoir bottom"):
        model.add_westergaard("wet", water_level=0.2)
    with pytest.raises(pf.ModelError, match="inside a block"):
        mesh = pf.rectangle(2.0, 1.0, 2, 1)
        mesh.add_facet_group("mid", lambda x: np.abs(x[:, 0] - 1.0) < 1e-9, False)
        pf.Model(mesh, [pf.Block("all", pf.Elastic(1e9, 0.2, 1.0))]).add_westergaard("mid", 1.0)
    from pfeie.io import load_job
    from test_cli import SMALL, _write

    text = SMALL.replace("[[supports]]", "[[loads.westergaard]]\ngroups = [\"bottom\"]\n"
                         "water_level = 0.5\n\n[[supports]]")  # fmt: skip
    job = load_job(_write(tmp_path, text))
    assert job.model.added_mass().sum() > 0
    bad = text.replace("water_level = 0.5", "water_level = -5.0")
    with pytest.raises(pf.errors.InputError, match=r"loads.westergaard\[0\]: westergaard"):
        load_job(_write(tmp_path, bad))


# -- the finite-element reservoir (Model.add_reservoir; Kuo 1982) ---------------------------
#
# References, per unit acceleration a of a rigid face towards the water, water density ρ_w
# and depth H (y the depth below the surface):
#
# - Westergaard (1933), the exact series for incompressible water in front of a rigid
#   vertical face, derived again here: with λ_m = mπ/(2H), m odd, the pressure
#   p = Σ A_m e^{−λ_m x} cos(λ_m z) (z from the bottom) has ∂p/∂x = −ρ_w a on the face for
#   A_m = 2 ρ_w a (−1)^{(m−1)/2} / (H λ_m²), so that on the face
#       p(y) = 8 ρ_w a H/π² Σ_{m odd} sin(mπy/(2H))/m²,
#   0.7425 ρ_w a H (8 G/π², G Catalan's constant) at the bottom, and the force
#       F = ∫ p dy = 16 ρ_w a H²/π³ Σ_{m odd} 1/m³ = 14 ζ(3)/π³ ρ_w a H² = 0.54275 ρ_w a H².
#   With p = 0 at a far end x = L (the finite-element model's truncation) each term is
#   multiplied by tanh(λ_m L): the exact solution of the truncated problem.
# - Inclined faces: the exact potential solution by conformal mapping (as in Chwang 1978,
#   J. Fluid Mech. 87, 343-348; derived here, see _inclined_exact), and Zangar's (1953,
#   USBR Engineering Monograph 11) electric-analogue results in the form design texts use:
#   the largest pressure coefficient of a face at θ from the vertical,
#   C_m = 0.735 (1 − θ/90°), p = C ρ_w a H, at the bottom (USACE EM 1110-2-2200).

M_ODD = np.arange(1, 400_001, 2)


def _westergaard(y: np.ndarray, H: float, L: float | None = None) -> np.ndarray:
    """Westergaard's series p(y)/(ρ_w a H) on a rigid vertical face (y the depth), with
    the tanh factors of a far end at L where p = 0 when L is given."""
    lam = M_ODD * np.pi / (2 * H)
    f = np.tanh(lam * L) if L is not None else 1.0
    s = np.sin(np.outer(np.atleast_1d(y), lam)) * (f / M_ODD**2)
    return np.asarray(8 / np.pi**2 * s.sum(axis=1))


def _westergaard_force(H: float, L: float | None = None) -> float:
    """∫ p dy /(ρ_w a H²) of the series (14 ζ(3)/π³ without truncation)."""
    f = np.tanh(M_ODD * np.pi * L / (2 * H)) if L is not None else 1.0
    return float((16 / np.pi**3 * f / M_ODD**3).sum())


def _face_model(H: float, ny: int, cell: str = "quad8", theta: float = 0.0,
                top: float | None = None) -> pf.Model:  # fmt: skip
    """A block 5 m wide whose left face (group xmin), from (0, 0) to its top, leans by
    theta degrees from the vertical towards the block (the water over the face)."""
    top = H if top is None else top
    mesh = pf.rectangle(1.0, top, 2, ny, cell=cell)
    x, y = mesh.points[:, 0].copy(), mesh.points[:, 1].copy()
    mesh.points[:, 0] = y * np.tan(np.radians(theta)) + 5.0 * x
    return pf.Model(mesh, [pf.Block("all", pf.Elastic(30e9, 0.2, 2400.0))])


def _rigid(model: pf.Model) -> np.ndarray:
    """A unit acceleration of every node along −x (towards the water)."""
    a = np.zeros(model.n_dof)
    a[0::2] = -1.0
    return a


def test_fe_reservoir_on_a_vertical_face_matches_westergaards_series() -> None:
    """A rigid vertical face 10 m deep accelerated towards the water: the pressure at the
    depths H/4, H/2, 3H/4, H and the force match Westergaard's exact series within 1 %
    from 4 quadratic face cells on (measured at 8 cells: 4.3e-4 at most, at H/4; force
    5.2e-4); against the series truncated as the model is (p = 0 at L = 3 H) the
    force converges at second order, for bilinear water cells too (measured: Q9 1.6e-3,
    3.6e-4, 9.2e-5, 2.3e-5 on 4 to 32 cells, rates 2.02, 1.98, 1.99; Q4 2.6e-2 to 6.1e-4,
    rates 1.78 to 1.83); the pressure vanishes at the surface; a face cut into 4 pieces
    a cell (refine) is the face of 4 times as many cells."""
    H, rho = 10.0, 1000.0
    depths = np.array([0.25, 0.5, 0.75, 1.0]) * H
    exact = _westergaard(depths, H)
    F_inf, F_3H = _westergaard_force(H), _westergaard_force(H, 3 * H)
    assert F_inf == pytest.approx(0.54275, abs=1e-5)
    assert exact[-1] == pytest.approx(0.74245, abs=1e-5)
    ns = [4, 8, 16, 32]
    for cell, rate_min in (("quad8", 1.9), ("quad", 1.7)):
        errs = []
        for ny in ns:
            m = _face_model(H, ny, cell)
            res = m.add_reservoir("xmin", water_level=H)
            a = _rigid(m)
            F = float(-(m.added_mass_matrix() @ a)[0::2].sum()) / (rho * H * H)
            p = res.pressure(a)[res.face] / (rho * H)
            y = H - res.mesh.points[res.face, 1]
            at = [int(np.argmin(np.abs(y - d))) for d in depths]
            assert p[-1] == 0.0 and np.allclose(y[at], depths)
            if cell == "quad8":
                assert np.abs(p[at] / exact - 1).max() < 0.01
                assert abs(F / F_inf - 1) < 0.01
                if ny == 8:
                    assert np.abs(p[at] / exact - 1).max() < 5e-4 and abs(F / F_inf - 1) < 6e-4
            errs.append(abs(F / F_3H - 1))
        rates = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
        assert rates.min() >= rate_min, (cell, errs, rates)
    forces = []
    for ny, refine in ((4, 4), (16, 1)):
        m = _face_model(H, ny)
        m.add_reservoir("xmin", H, refine=refine)
        forces.append(float((m.added_mass_matrix() @ _rigid(m)).sum()))
    assert forces[0] == pytest.approx(forces[1], rel=1e-10)


def test_fe_reservoir_length_and_a_level_between_nodes() -> None:
    """The truncation: doubling the length from 3 H to 6 H changes the added mass by the
    1 − tanh(λ L) factors of the series, 1.53e-4 (measured 1.47e-4); a water level that
    cuts a facet (10.5 m on a face of 2 m cells) gives the series of its depth (force
    within 5e-4, measured 3.6e-4)."""
    H, rho = 10.0, 1000.0
    forces = []
    for L in (3 * H, 6 * H):
        m = _face_model(H, 8)
        res = m.add_reservoir("xmin", water_level=H, length=L)
        assert res.length == L and res.depth == H and res.bottom == 0.0
        forces.append(float(-(m.added_mass_matrix() @ _rigid(m))[0::2].sum()))
    predicted = _westergaard_force(H, 3 * H) / _westergaard_force(H, 6 * H) - 1
    assert predicted == pytest.approx(-1.53e-4, abs=1e-6)
    assert forces[0] / forces[1] - 1 == pytest.approx(predicted, abs=1e-5)
    m = _face_model(10.5, 6, top=12.0)
    res = m.add_reservoir("xmin", water_level=10.5)
    assert res.depth == 10.5
    F = float(-(m.added_mass_matrix() @ _rigid(m))[0::2].sum()) / (rho * 10.5**2)
    assert abs(F / _westergaard_force(10.5, 31.5) - 1) < 5e-4
    top = res.mesh.points[res.face[-1]]
    assert top[1] == 10.5 and top[0] == pytest.approx(0.0, abs=1e-12)


def _inclined_exact(depth: float, theta: float) -> float:
    """p/(ρ_w a H) at ``depth``/H (0 at the surface, 1 at the heel) on a rigid face at
    ``theta`` degrees from the vertical, the water over it, accelerated horizontally by a
    towards the water (infinite reservoir of constant depth, incompressible water).

    Derivation (the method of Chwang 1978). With H = 1 and α = πk the face's angle with
    the bottom, the Schwarz-Christoffel map dz/dζ = −(1/π)(ζ + 1)^{−k}(ζ − 1)^{k−1} takes
    the upper half-plane onto the water: the bottom to ζ < −1, the face to −1 < ζ < 1
    (heel at −1), the surface to ζ > 1. The complex pressure W = p + iq has q = 0 on the
    bottom (∂p/∂n = 0), q = y (the elevation: ∂q/∂s = ∂p/∂n = sin α along the face) on the
    face, and p = 0 on the surface; W/√(ζ − 1) then has a known real part on the whole real
    axis (0 on ζ > 1, y/√(1 − ξ) below) and vanishes at infinity, so it is its Schwarz
    integral, and on the face

        p(ξ) = √(1 − ξ)/π · PV ∫_{−1}^{1} y(t) dt / (√(1 − t) (t − ξ)),

    y(t) = I_{(1+t)/2}(1 − k, k) (the regularised incomplete beta function) the elevation
    of the face point of t. For k = 1/2 this is Westergaard's series (asserted below)."""
    import warnings

    from scipy import integrate, special

    k = (90.0 - theta) / 180.0

    def y(t: np.ndarray | float) -> np.ndarray | float:
        return special.betainc(1 - k, k, np.clip((1 + np.asarray(t)) / 2, 0.0, 1.0))

    b = np.sqrt(2.0)  # t = 1 − v²: the square root at the surface's end goes away
    with warnings.catch_warnings():  # near the heel QUADPACK doubts a result it has (1e-8)
        warnings.simplefilter("ignore", integrate.IntegrationWarning)
        if depth >= 1.0:  # the heel, ξ = −1: no principal value
            val = integrate.quad(lambda v: 2 * y(1 - v * v) / (2 - v * v), 0, b, limit=200)[0]
            return float(b / np.pi * val)
        xi = 2 * special.betaincinv(1 - k, k, 1 - depth) - 1
        v0 = np.sqrt(1 - xi)  # PV ∫ g(v)/(v − v0) dv, g = −2 y(1 − v²)/(v0 + v), less g(v0)

        def g(v: float) -> float:
            return float(-2 * y(1 - v * v) / (v0 + v))

        g0 = g(v0)
        val = integrate.quad(lambda v: (g(v) - g0) / (v - v0), 0, b, points=[v0], limit=200)[0]
        return float(v0 / np.pi * (val + g0 * np.log((b - v0) / v0)))


def test_fe_reservoir_on_inclined_faces_matches_the_exact_solution_and_zangar() -> None:
    """Rigid faces at 15°, 30° and 45° from the vertical, the water over them (upstream
    batter), accelerated horizontally: the pressures at H/4, H/2, 3H/4 and at the heel
    and the horizontal force match the exact potential solution within 3e-4 (measured
    1.3e-4 at most, mostly the truncation at 3 H; the solution's formula gives
    Westergaard's series on a vertical face to 1e-8); the largest pressure, at the heel
    (0.595, 0.467, 0.351 ρ_w a H), is within 5 % of Zangar's C_m = 0.735 (1 − θ/90°)
    (measured −2.9 %, −4.6 %, −4.6 %); the pressure acts along the face's normal
    (F_y/F_x = −tan θ: the water pushes the face down), and the lumped added mass gives
    the horizontal force of a horizontal acceleration exactly (its vertical one is what
    lumping drops). An overhanging face (−20°) matches the exact solution within 1e-3
    (measured 4.9e-4, at H/4)."""
    H, rho = 10.0, 1000.0
    for d in (0.25, 0.5, 1.0):
        assert _inclined_exact(d, 0.0) == pytest.approx(_westergaard(d, 1.0)[0], abs=1e-8)
    gauss, weights = np.polynomial.legendre.leggauss(24)
    for theta, measured in ((15.0, -0.029), (30.0, -0.046), (45.0, -0.046)):
        m = _face_model(H, 16, theta=theta)
        res = m.add_reservoir("xmin", water_level=H)
        a = _rigid(m)
        f = -(m.added_mass_matrix() @ a).reshape(-1, 2).sum(axis=0) / (rho * H * H)
        p = res.pressure(a)[res.face] / (rho * H)
        depth = (H - res.mesh.points[res.face, 1]) / H
        for d in (0.25, 0.5, 0.75, 1.0):
            i = int(np.argmin(np.abs(depth - d)))
            assert p[i] == pytest.approx(_inclined_exact(d, theta), rel=3e-4), (theta, d)
        y = 0.5 * (gauss + 1)
        F_exact = 0.5 * sum(
            w * _inclined_exact(1 - yy, theta) for yy, w in zip(y, weights, strict=True)
        )
        assert f[0] == pytest.approx(F_exact, rel=3e-4), theta
        assert f[1] / f[0] == pytest.approx(-np.tan(np.radians(theta)), rel=1e-9)
        zangar = 0.735 * (1 - theta / 90)
        assert abs(p[0] / zangar - 1) < 0.05 and p[0] / zangar - 1 == pytest.approx(
            measured, abs=2e-3)
        lumped = m.added_mass().reshape(-1, 2)
        assert lumped[:, 0].sum() / (rho * H * H) == pytest.approx(f[0], rel=1e-12)
    m = _face_model(H, 16, theta=-20.0)  # overhanging: the water under the face
    res = m.add_reservoir("xmin", water_level=H)
    p = res.pressure(_rigid(m))[res.face] / (rho * H)
    depth = (H - res.mesh.points[res.face, 1]) / H
    for d in (0.25, 0.5, 1.0):
        i = int(np.argmin(np.abs(depth - d)))
        assert p[i] == pytest.approx(_inclined_exact(d, -20.0), rel=1e-3), d


def _dam(westergaard: bool = False, fe: bool = False) -> pf.Model:
    """A gravity dam 100 m high (base 80 m, crest 10 m, vertical upstream face at x = 0,
    E = 25 GPa, ν = 0.2, ρ = 2400 kg/m³, 8 × 20 Q8 cells), fixed at its base, the water
    at 92 m (the level cuts a face cell)."""
    mesh = pf.rectangle(1.0, 1.0, 8, 20, cell="quad8")
    xi, eta = mesh.points[:, 0].copy(), mesh.points[:, 1].copy()
    mesh.points[:, 0] = xi * (80.0 - 70.0 * eta)
    mesh.points[:, 1] = 100.0 * eta
    m = pf.Model(mesh, [pf.Block("all", pf.Elastic(25e9, 0.2, 2400.0))])
    m.fix("ymin")
    if westergaard:
        m.add_westergaard("xmin", water_level=92.0)
    if fe:
        m.add_reservoir("xmin", water_level=92.0)
    return m


def test_fe_reservoir_in_the_modes_of_a_dam_and_its_total() -> None:
    """The dam's frequencies: dry 3.969 Hz; with the finite-element reservoir 3.535 Hz
    (full M_a, as `pfeie modal` uses it), with Westergaard's added mass 3.384 Hz, 4.3 %
    lower (its parabola holds 7.5 % more water: 7/12 against 14 ζ(3)/π³ ρ_w H², the
    measured ratio of the totals 1.0751; the total is the series' within 2e-4, measured
    3.7e-5). The total of M_a equals the integral of its pressure field on the face (to
    round-off), and the time stepping's lumped M_a (row
    sums per component) keeps the total but lowers the first two frequencies by 2.9 %
    and 4.0 % (measured with the dam's consistent mass)."""
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    rho, H = 1000.0, 92.0
    dry = pf.modal(_dam(), 2).frequencies
    w = _dam(westergaard=True)
    f_w = pf.modal(w, 2).frequencies
    m = _dam(fe=True)
    f_fe = pf.modal(m, 2).frequencies
    assert dry[0] == pytest.approx(3.969, abs=1e-3)
    assert f_fe[0] == pytest.approx(3.535, abs=1e-3) and f_w[0] == pytest.approx(3.384, abs=1e-3)
    assert f_w[0] / f_fe[0] - 1 == pytest.approx(-0.043, abs=1e-3)
    res = m.fe_reservoirs[0]
    ones = np.zeros(m.n_dof)
    ones[0::2] = 1.0
    total = float(ones @ (m.added_mass_matrix() @ ones))
    assert w.added_mass().sum() / total == pytest.approx(1.0751, abs=2e-4)
    assert total / (rho * H * H) == pytest.approx(_westergaard_force(H, 3 * H), rel=2e-4)
    # ∫ p n_x dΓ over the water mesh's wet edges for a unit acceleration along +x
    p = res.pressure(ones)
    conn = res.mesh.facet_groups["wet"]["line3"]
    from pfeie import assembly as asm

    fv = asm.facet_values(res.mesh.points, "line3", conn, 8)
    integral = float(np.einsum("fq,qa,fa,fq->", fv.dA, fv.N, p[conn], np.abs(fv.normal[..., 0])))
    assert integral == pytest.approx(-total, rel=1e-10)  # the dam moving away: suction
    # lumping the added mass (what Dynamic's lumped mass holds) against the full matrix
    s = m.system()
    lumped = m.added_mass()
    assert lumped.sum() == pytest.approx(total, rel=1e-12)
    assert np.array_equal(m.mass(lumped=True).diagonal(),
                          m.mass(lumped=True, added=False).diagonal() + lumped)  # fmt: skip
    M = (m.mass(added=False) + sp.diags(lumped))[s.free][:, s.free]
    w2 = spla.eigsh(s.K, 2, M.tocsc(), sigma=0, which="LM")[0]
    f_lumped = np.sqrt(np.sort(w2)) / (2 * np.pi)
    assert f_lumped / f_fe - 1 == pytest.approx([-0.029, -0.040], abs=1e-3)


def test_fe_reservoir_across_a_joint_is_the_uncut_one() -> None:
    """A wet face cut by a joint (its nodes split in two) carries the same added mass as
    the uncut face: the water mesh joins the facets by position."""
    mesh = pf.rectangle(2.0, 4.0, 2, 8, cell="quad8")
    mesh.add_cell_group("low", lambda x: x[:, 1] < 2.0)
    mesh.add_cell_group("high", lambda x: x[:, 1] > 2.0)
    mesh.add_facet_group("joint", lambda x: np.abs(x[:, 1] - 2.0) < 1e-9, False)
    mat = pf.Elastic(30e9, 0.2, 2400.0)
    cut = pf.Model(mesh, [pf.Block("low", mat), pf.Block("high", mat)],
                   interfaces=[pf.Interface("joint", pf.Joint(phi=30.0))])  # fmt: skip
    whole = pf.Model(pf.rectangle(2.0, 4.0, 2, 8, cell="quad8"), [pf.Block("all", mat)])
    totals = []
    for model in (cut, whole):
        model.add_reservoir("xmin", water_level=3.0)
        ones = np.zeros(model.n_dof)
        ones[0::2] = 1.0
        totals.append(float(ones @ (model.added_mass_matrix() @ ones)))
    assert cut.mesh.n_points > whole.mesh.n_points
    assert totals[0] == pytest.approx(totals[1], rel=1e-12)


def test_fe_reservoir_errors_and_model_file(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    """Faces the water mesh cannot be drawn from, and bad options, are refused with what
    was expected; through a model file, model = 'fe' builds the reservoir (and `pfeie
    modal` uses it), its options only with it, each error named by its key."""
    m = _face_model(10.0, 4)
    with pytest.raises(pf.ModelError, match="above the top of the wet faces"):
        m.add_reservoir("xmin", water_level=11.0)
    with pytest.raises(pf.ModelError, match="must lie above the lowest point"):
        m.add_reservoir("xmin", water_level=0.0)
    with pytest.raises(pf.ModelError, match="horizontal wet facet"):
        m.add_reservoir(["xmin", "ymin"], water_level=5.0)
    with pytest.raises(pf.ModelError, match="one chain from the bottom up"):
        m.add_reservoir(["xmin", "xmax"], water_level=5.0)
    with pytest.raises(pf.ModelError, match="refine must be an integer >= 1"):
        m.add_reservoir("xmin", water_level=5.0, refine=0)
    with pytest.raises(pf.ModelError, match="length must be > 0"):
        m.add_reservoir("xmin", water_level=5.0, length=-1.0)
    with pytest.raises(pf.ModelError, match="density must be > 0"):
        m.add_reservoir("xmin", water_level=5.0, density=0.0)
    with pytest.raises(pf.ModelError, match="inside a block"):
        mesh = pf.rectangle(2.0, 1.0, 2, 1)
        mesh.add_facet_group("mid", lambda x: np.abs(x[:, 0] - 1.0) < 1e-9, False)
        pf.Model(mesh, [pf.Block("all", pf.Elastic(1e9, 0.2, 1.0))]).add_reservoir("mid", 1.0)
    with pytest.raises(pf.ModelError, match="2D only"):
        pf.Model(pf.box(1.0, 1.0, 1.0, 1, 1, 1), [pf.Block("all", pf.Elastic(1e9, 0.2, 1.0))]
                 ).add_reservoir("xmin", 0.5)  # fmt: skip
    assert not m.fe_reservoirs
    from conftest import cli_fails as fails
    from pfeie.cli import main
    from pfeie.io import load_job
    from test_robustness import ELEMENTS, NAMES, model

    names = {**NAMES, 6: (1, "upstream")}
    elements = [*ELEMENTS, (6, 1, 6, [1, 4])]  # the plate's left side, x = 0
    fe = 'dynamic = false\n\n[[loads.westergaard]]\ngroups = ["upstream"]\nwater_level = 1.0\n'
    p = model(tmp_path, fe + 'model = "fe"\nlength = 4.0\nrefine = 2',
              elements=elements, names=names)  # fmt: skip
    job = load_job(p)
    (res,) = job.model.fe_reservoirs
    assert res.length == 4.0 and res.refine == 2 and res.depth == 1.0
    assert main(["modal", str(p), "--modes", "2"]) == 0
    capsys.readouterr()
    for extra, words in (
        ('model = "fe"\nwater_level = 2.0', ["loads.westergaard[0]", "above the top"]),
        ("length = 4.0", ["loads.westergaard[0].length", "only with model = 'fe'"]),
        ("refine = 2", ["loads.westergaard[0].refine", "only with model = 'fe'"]),
        ('model = "fe"\nbottom = 0.0', ["loads.westergaard[0].bottom", "not with model = 'fe'"]),
        ('model = "fem"', ["loads.westergaard[0].model", "'westergaard', 'fe'"]),
        ('model = "fe"\nrefine = 0', ["loads.westergaard[0].refine", ">= 1"]),
    ):
        text = fe.replace("water_level = 1.0\n", "") if "water_level" in extra else fe
        p = model(tmp_path, text + extra, elements=elements, names=names)
        fails(capsys, ["check", str(p)], *words)


def test_time_stepping_keeps_the_full_added_mass() -> None:
    """The time integration uses the finite-element reservoir's M_a full (beside the
    blocks' lumped mass): released from the first mode shape of (K, M) with that M, the
    crest vibrates at that mode's period (zero crossings over 5 periods, to 1e-3: the
    period error of generalised-α with ρ∞ = 0 at Δt = T/200; measured 4.5e-4), not at
    the lumped M_a's (measured 3.0 % off before the time stepping kept M_a full)."""
    import scipy.sparse.linalg as spla

    from pfeie.solvers import StaticResult

    m = _dam(fe=True)
    full = m.system(lumped_mass=True, full_reservoir=True)
    lump = m.system(lumped_mass=True)
    f = []
    for s in (full, lump):
        w2, phi = spla.eigsh(s.K.tocsc(), 1, s.M.tocsc(), sigma=0.0)
        f.append(float(np.sqrt(w2[0]) / (2 * np.pi)))
        if s is full:
            mode = phi[:, 0]
    assert abs(f[1] / f[0] - 1) > 0.02
    T = 1.0 / f[0]
    u = full.expand(0.01 * mode / np.abs(mode).max())
    start = StaticResult(m, u.reshape(-1, 2), np.zeros((m.mesh.n_points, 2)))
    crest = m.nearest_node([0.0, 100.0])
    res = pf.Dynamic(m, T / 200).run(n_steps=1100, start=start, probes=[crest])
    x = res.probe_u[:, 0, 0]
    k = np.flatnonzero(np.sign(x[1:]) != np.sign(x[:-1]))
    tz = res.t[k] - x[k] * (res.t[k + 1] - res.t[k]) / (x[k + 1] - x[k])
    period = 2 * (tz[10] - tz[0]) / 10
    assert period == pytest.approx(T, rel=1e-3)


def test_start_acceleration_with_the_full_added_mass() -> None:
    """The consistent start acceleration q̈₀ = M⁻¹(f − K u − C v) uses the full M (the
    blocks' lumped mass and the reservoir's full M_a), as the time stepping does: under
    gravity switched on at t0, with Rayleigh damping and ρ∞ = 0.5, M q̈₀ equals the load
    to round-off (measured 1.5e-16 of it; the lumped diagonal left 2 % before)."""
    m = _dam(fe=True)
    m.add_gravity(9.81)
    m.damping = pf.Rayleigh(0.1, 1e-3)
    an = pf.Dynamic(m, 0.002, rho_inf=0.5)
    ex = an.excitation()
    n = an.system.M.shape[0]
    v = np.full(n, 1e-3)
    f = ex.load(0.0)
    a0 = an._consistent_acceleration(ex, 0.0, np.zeros(n), v, f, an.initial().pairs, False)
    r = f - an.damping_force(v, np.zeros(n))
    assert np.abs(an.system.M @ a0 - r).max() < 1.5e-15 * np.abs(r).max()


@pytest.mark.parametrize("cell", ["quad", "quad8"])
@pytest.mark.parametrize("level", [10.0, 8.75 + 1e-8, 8.76, 9.3, 8.1, 7.0, 12.0])
def test_westergaard_resultant_and_moment_at_any_level(cell: str, level: float) -> None:
    """Wherever the water level lies (at a node, 1e-8 m above one, cutting a facet, above
    the face's top, on a face of 8 Q4 or 5 Q8 cells), the lumped added mass of a vertical
    face has Westergaard's total ∫ C dz and first moment ∫ C z dz over the wet part, the
    closed forms' base shear and overturning moment under a uniform acceleration: to 1e-13
    (measured 4e-16 at most; before the square root was mapped out near the level, 4e-5
    and 1e-4 just above a node). A quadratic facet cut by the surface, whose consistent
    loads would give a corner a negative mass, keeps its total and centre of pressure on
    its corners."""
    n = 8 if cell == "quad" else 5
    mesh = pf.rectangle(1.0, 10.0, 1, n, cell=cell)
    m = pf.Model(mesh, [pf.Block("all", pf.Elastic(30e9, 0.2, 2400.0))])
    m.add_westergaard("xmin", water_level=level)
    am = m.added_mass().reshape(-1, 2)
    assert np.all(am >= 0.0) and np.all(am[:, 1] == 0.0)
    H, top = level, min(level, 10.0)  # the bottom at z = 0
    # ∫ 7/8 ρ √(H (h − z)) dz and ∫ … z dz over [0, top], by hand (u = h − z)
    def prim(u: float, k: int) -> float:  # ∫ u^{1/2} (h − u)^k du, k = 0, 1
        return (2 / 3 * u**1.5) if k == 0 else (2 / 3 * level * u**1.5 - 2 / 5 * u**2.5)

    c = 0.875 * RHO_W * np.sqrt(H)
    total = c * (prim(level, 0) - prim(level - top, 0))
    moment = c * (prim(level, 1) - prim(level - top, 1))
    z = mesh.points[:, 1]
    assert am[:, 0].sum() == pytest.approx(total, rel=1e-13)
    assert (am[:, 0] * z).sum() == pytest.approx(moment, rel=1e-13)


def _rotate(mesh: pf.Mesh, axis: int, degrees: float) -> None:
    """Rotate the mesh's points in place about the x (0) or y (1) axis."""
    t = np.radians(degrees)
    i, j = (1, 2) if axis == 0 else (2, 0)
    a, b = mesh.points[:, i].copy(), mesh.points[:, j].copy()
    mesh.points[:, i] = np.cos(t) * a - np.sin(t) * b
    mesh.points[:, j] = np.sin(t) * a + np.cos(t) * b


def _plane_coordinates(corners: np.ndarray, p: np.ndarray) -> np.ndarray:
    """Coordinates of the plane points p (k, 2) in a straight facet from its corners
    (3: a triangle, its barycentric λ₁, λ₂; 4: a parallelogram, a, b ∈ [0, 1])."""
    e = np.stack([corners[1] - corners[0], corners[-1] - corners[0]], axis=1)
    return np.linalg.solve(e, (p - corners[0]).T).T


def _lagrange(coords: np.ndarray, node: np.ndarray, kind: str) -> np.ndarray:
    """The shape function of the node at ``node`` at the points ``coords`` (k, 2), by
    its closed form: λ_i, λ_i (2λ_i − 1) and 4 λ_i λ_j on triangles (barycentric λ),
    bilinear on parallelograms."""
    if kind == "quad":
        a, b = coords.T
        return (a if node[0] > 0.5 else 1 - a) * (b if node[1] > 0.5 else 1 - b)
    lam = np.column_stack([1 - coords.sum(axis=1), coords])
    at = np.concatenate([[1 - node.sum()], node])
    big = np.flatnonzero(at > 0.25)
    if kind == "triangle":
        return lam[:, big[0]]
    if big.size == 1:
        return lam[:, big[0]] * (2 * lam[:, big[0]] - 1)
    return 4 * lam[:, big[0]] * lam[:, big[1]]


def _face_masses(mesh: pf.Mesh, group: str, level: float) -> np.ndarray:
    """Westergaard's lumped added masses (nodes, 3) on the straight facets of a planar
    face, independently of pfeie: in plane coordinates (u horizontal, v up the slope),
    ∫ N_a C dA = ∫ C(z(v)) ∫ N_a du dv, the inner integral of a polynomial (degree ≤ 2)
    by a 4-point Gauss rule (exact), the outer by QUADPACK with the corners' heights as
    break points and the wet part's top as its end; shape functions by their closed
    forms. A facet with a negative row sum takes the corner split of _westergaard_add,
    from its total and its centre of pressure Σ m_a x_a / Σ m_a."""
    zb = min(float(mesh.points[c, 2].min()) for c in mesh.facet_group(group).values())
    H = level - zb
    out = np.zeros((mesh.points.shape[0], 3))
    gu, gw = np.polynomial.legendre.leggauss(4)
    for ftype, conn in mesh.facet_group(group).items():
        nc = 4 if ftype == "quad" else 3
        for facet in conn:
            X = mesh.points[facet]
            n = np.cross(X[1] - X[0], X[nc - 1] - X[0])
            n /= np.linalg.norm(n)
            e2 = np.array([0.0, 0.0, 1.0]) - n[2] * n
            e2 /= np.linalg.norm(e2)
            uv = np.column_stack([(X - X[0]) @ np.cross(e2, n), (X - X[0]) @ e2])
            corners, nodes = uv[:nc], _plane_coordinates(uv[:nc], uv)
            vs = np.sort(corners[:, 1])
            top = min(vs[-1], (level - X[0, 2]) / e2[2])
            if top <= vs[0]:
                continue

            def row(v: float, j: int, corners: np.ndarray = corners, X: np.ndarray = X,
                    nodes: np.ndarray = nodes, e2: np.ndarray = e2, ftype: str = ftype,
                    nc: int = nc) -> float:  # fmt: skip
                ends = [a[0] + (v - a[1]) / (b[1] - a[1]) * (b[0] - a[0])
                        for a, b in zip(corners, np.roll(corners, -1, axis=0), strict=True)
                        if a[1] != b[1] and (a[1] - v) * (b[1] - v) <= 0]  # fmt: skip
                lo, hi = min(ends), max(ends)
                u = 0.5 * (lo + hi) + 0.5 * (hi - lo) * gu
                N = _lagrange(_plane_coordinates(corners, np.column_stack(
                    [u, np.full_like(u, v)])), nodes[j], ftype)  # fmt: skip
                depth = max(level - X[0, 2] - v * e2[2], 0.0)
                return 0.5 * (hi - lo) * float(gw @ N) * 0.875 * RHO_W * np.sqrt(H * depth)

            cuts = [v for v in vs if vs[0] < v < top] or None
            m = np.array([quad(row, vs[0], top, args=(j,), points=cuts, epsabs=0.0,
                               epsrel=1e-13, limit=200, full_output=1)[0]
                          for j in range(len(facet))])  # fmt: skip
            if (m < 0).any():
                lam = _plane_coordinates(corners, (m @ uv / m.sum())[None])[0]
                split = np.zeros_like(m)
                split[:3] = m.sum() * np.array([1 - lam.sum(), *lam])
                beta = max(-m[j] / (split[j] - m[j]) for j in range(len(m)) if m[j] < 0)
                m = m + beta * (split - m)
            out[facet] += m[:, None] * n**2
    return out


def _closed_form(level: float, top: float, k: int) -> float:
    """∫ 7/8 ρ_w √(H (h − z)) z^k dz over [0, top] per metre of width, k = 0, 1 (the
    bottom at 0, H = h), by hand with u = h − z."""
    def prim(u: float) -> float:  # ∫ u^{1/2} (h − u)^k du
        return (2 / 3 * u**1.5) if k == 0 else (2 / 3 * level * u**1.5 - 2 / 5 * u**2.5)

    return 0.875 * RHO_W * np.sqrt(level) * (prim(level) - prim(level - top))


# the nodal errors against _face_masses (of the largest) are 1.5e-15 at most, but 2.5e-13
# with the level 1e-8 m above a row of nodes, where QUADPACK's reference reaches no better
# (the root of C lies just beyond the end of its interval): 2e-12 there
NODAL_3D = {7.5 + 1e-8: 2e-12}


@pytest.mark.parametrize("cell", ["hexahedron", "tetra", "tetra10"])
@pytest.mark.parametrize("level", [10.0, 7.5 + 1e-8, 7.3, 12.0])
def test_westergaard_nodal_masses_in_3d(cell: str, level: float) -> None:
    """A rigid vertical 3D face 3 m wide and 10 m deep (4 rows of cells; Q4 facets of
    hexahedra, 3- and 6-node triangles of tetrahedra) with the level on a row of nodes,
    1e-8 m above one, cutting facets, above the face: every nodal mass equals the
    consistent load ∫ N_a C dA by adaptive quadrature (_face_masses) to 1.5e-14 of the
    largest (measured 1.5e-15; 2e-12 just above a row: see NODAL_3D), and the masses
    total 7/12 ρ_w H² and have the first moment ∫ C z dz per metre of width (7/30 ρ_w H³
    about the bottom with the level at the top), to 1e-14 (measured 1.3e-15 at most;
    before the square root was mapped out in 3D, 4e-4 of the total and 1e-5 of the
    moment). Every mass ≥ 0, none off the normal."""
    mesh = pf.box(2.0, 3.0, 10.0, 1, 2, 4, cell=cell)
    m = pf.Model(mesh, [pf.Block("all", pf.Elastic(30e9, 0.2, 2400.0))])
    m.add_westergaard("xmin", water_level=level)
    am = m.added_mass().reshape(-1, 3)
    assert np.all(am >= 0.0) and np.all(am[:, 1:] == 0.0)
    ref = _face_masses(mesh, "xmin", level)
    err = np.abs(am - ref).max() / ref.max()
    assert err < NODAL_3D.get(level, 1.5e-14), err
    top = min(level, 10.0)
    assert am[:, 0].sum() / 3.0 == pytest.approx(_closed_form(level, top, 0), rel=1e-14)
    moment = (am[:, 0] * mesh.points[:, 2]).sum() / 3.0
    assert moment == pytest.approx(_closed_form(level, top, 1), rel=1e-14)


@pytest.mark.parametrize("cell", ["hexahedron", "tetra10"])
def test_westergaard_on_an_inclined_face_in_3d(cell: str) -> None:
    """A 3D face tilted 30° from the vertical (a box rotated about y; its bottom edge
    level) with the level cutting facets: the horizontal masses total 7/12 ρ_w H² cos θ
    per metre of width and the vertical ones 7/12 ρ_w H² sin²θ/cos θ, as on the 2D
    inclined face (test_westergaard_on_an_inclined_face), to 1e-14 and 2e-14 (measured
    1.7e-15 and 2.4e-15), and every nodal mass is _face_masses' to 2e-14 of the largest
    (measured 2.8e-15)."""
    theta = 30.0
    mesh = pf.box(2.0, 3.0, 10.0, 1, 2, 4, cell=cell)
    _rotate(mesh, 1, -theta)  # the face x = 0 leans over its toe, normal (cos θ, 0, ∓sin θ)
    level = 7.3
    m = pf.Model(mesh, [pf.Block("all", pf.Elastic(30e9, 0.2, 2400.0))])
    m.add_westergaard("xmin", water_level=level)
    am = m.added_mass().reshape(-1, 3)
    H, t = level - mesh.points[:, 2].min(), np.radians(theta)
    total = 7 / 12 * RHO_W * H**2 * 3.0
    assert am[:, 0].sum() == pytest.approx(total * np.cos(t), rel=1e-14)
    assert am[:, 2].sum() == pytest.approx(total * np.sin(t) ** 2 / np.cos(t), rel=2e-14)
    ref = _face_masses(mesh, "xmin", level)
    assert np.abs(am - ref).max() < 2e-14 * ref.max()


def _rotation(axis: int, degrees: float) -> np.ndarray:
    """The matrix of _rotate (about x: 0, y: 1), for vectors."""
    t = np.radians(degrees)
    i, j = (1, 2) if axis == 0 else (2, 0)
    R = np.eye(3)
    R[i, i], R[i, j], R[j, i], R[j, j] = np.cos(t), -np.sin(t), np.sin(t), np.cos(t)
    return R


@pytest.mark.parametrize("cell", ["hexahedron", "tetra", "tetra10"])
def test_westergaard_inclined_3d_face_pushes_along_its_normal(cell: str) -> None:
    """The 3D rigid-face check. (1) The face x = 0 of a 2 × 3 × 10 m box tilted 30° about
    y (overhanging: n = (−cos θ, 0, −sin θ), its bottom edge level, the level 7.3 m
    cutting facets): the wet part is 3 m wide and H/cos θ long (H the level above the
    bottom edge), so ∫ C dA = 3 · 7/12 ρ_w H² / cos θ and a uniform acceleration a gives
    Σ_a m_a a = (a·n) n ∫ C dA, for a = (1, 0, 0) and a = (0.4, −0.7, 1.3) m/s², to
    10 × RIGID_FACE["3d"] of the largest component (measured 1.8e-15 at most). (2) The
    box turned 20° about y and then 25° about x, so that n has three components, the
    level 8.3 m crossing facets at a slant: every nodal force is μ_a (a·n) n, μ_a the
    consistent load ∫ N_a C dA by adaptive quadrature (_face_masses, the trace of its
    n² masses), to 10 × RIGID_FACE["3d_nodal"] of the largest (measured 4.3e-15)."""
    theta, level = 30.0, 7.3
    mesh = pf.box(2.0, 3.0, 10.0, 1, 2, 4, cell=cell)
    _rotate(mesh, 1, -theta)
    m = pf.Model(mesh, [pf.Block("all", pf.Elastic(30e9, 0.2, 2400.0))])
    m.add_westergaard("xmin", water_level=level)
    H, t = level - mesh.points[:, 2].min(), np.radians(theta)
    n = np.array([-np.cos(t), 0.0, -np.sin(t)])
    Ma = m.added_mass_matrix()
    for a in (np.array([1.0, 0.0, 0.0]), np.array([0.4, -0.7, 1.3])):
        f = (Ma @ np.tile(a, mesh.n_points)).reshape(-1, 3).sum(axis=0)
        ref = 7 / 12 * RHO_W * H**2 * 3.0 / np.cos(t) * (a @ n) * n
        err = np.abs(f - ref).max() / np.abs(ref).max()
        assert err < 10 * RIGID_FACE["3d"], err
    mesh = pf.box(2.0, 3.0, 10.0, 1, 2, 4, cell=cell)
    _rotate(mesh, 1, 20.0)
    _rotate(mesh, 0, 25.0)
    n = _rotation(0, 25.0) @ _rotation(1, 20.0) @ np.array([-1.0, 0.0, 0.0])
    assert np.abs(n).min() > 0.1
    m = pf.Model(mesh, [pf.Block("all", pf.Elastic(30e9, 0.2, 2400.0))])
    m.add_westergaard("xmin", water_level=8.3)
    mu = _face_masses(mesh, "xmin", 8.3).sum(axis=1)
    a = np.array([0.4, -0.7, 1.3])
    f = (m.added_mass_matrix() @ np.tile(a, mesh.n_points)).reshape(-1, 3)
    ref = (mu * (a @ n))[:, None] * n
    err = np.abs(f - ref).max() / np.abs(ref).max()
    assert err < 10 * RIGID_FACE["3d_nodal"], err


@pytest.mark.parametrize("cell", ["hexahedron", "tetra", "tetra10"])
def test_westergaard_with_the_level_across_facets_diagonally(cell: str) -> None:
    """A face rotated 25° about x (its edges no longer level: the height varies along
    both facet directions and the level crosses the facets diagonally, splitting the
    outer integral where it crosses their edges) and tilted 20° about y, at three levels
    (on no node: every facet near it is cut at a slant; above the face): every nodal mass
    is _face_masses' to 3e-14 of the largest (measured 3.4e-15 at most)."""
    for level in (4.9, 8.3, 13.0):
        mesh = pf.box(2.0, 3.0, 10.0, 1, 2, 4, cell=cell)
        _rotate(mesh, 0, 25.0)
        _rotate(mesh, 1, 20.0)
        m = pf.Model(mesh, [pf.Block("all", pf.Elastic(30e9, 0.2, 2400.0))])
        m.add_westergaard("xmin", water_level=level)
        am = m.added_mass().reshape(-1, 3)
        assert np.all(am >= 0.0)
        ref = _face_masses(mesh, "xmin", level)
        err = np.abs(am - ref).max() / ref.max()
        assert err < 3e-14, (level, err)


@pytest.mark.parametrize(("cell", "amp", "tol_moment"),
                         [("hexahedron", 1.0, 5e-15), ("tetra", 1.0, 5e-15),
                          ("tetra10", 0.5, 2e-4)])  # fmt: skip
def test_westergaard_on_a_distorted_3d_face(cell: str, amp: float, tol_moment: float) -> None:
    """A vertical face 3 m × 10 m whose nodes are moved in its plane by a smooth field
    that vanishes on its boundary (trapezoidal Q4, skewed triangles, and 6-node triangles
    with curved edges: z quadratic along their lines), at levels between nodes, 5 mm
    above a corner and 1e-9 m below one: the masses total ∫ C dA over the rectangle,
    3 ∫ C dz, to 5e-15 (measured 8.9e-16 on the Q4 and 4.4e-16 on the 3-node triangles,
    exact there; 1.3e-15 on the curved 6-node triangles, where the rule converges; 3.1e-4,
    9.3e-5 and 2.5e-2 before the square root was mapped out in 3D), and have its first
    moment, to 5e-15 on the straight facets (measured as the totals). On a curved facet
    the centre of pressure can lie outside the triangle of its corners, and the corner
    split of a facet with a negative row sum, clipped to masses ≥ 0, then moves it:
    2e-4 (measured 2.5e-5)."""
    for level in (2.0 + 5e-3, 4.15, 5.0 - 1e-9, 6.47, 8.004, 10.0):
        mesh = pf.box(2.0, 3.0, 10.0, 1, 3, 5, cell=cell)
        y, z = mesh.points[:, 1], mesh.points[:, 2]
        bump = amp * np.sin(np.pi * y / 3.0) * np.sin(np.pi * z / 10.0)  # 0 on the boundary
        mesh.points[:, 1] = y + 0.25 * bump * np.cos(z)
        mesh.points[:, 2] = z + 0.6 * bump * np.sin(1.3 * y + 0.4)
        m = pf.Model(mesh, [pf.Block("all", pf.Elastic(30e9, 0.2, 2400.0))])
        m.add_westergaard("xmin", water_level=level)
        am = m.added_mass().reshape(-1, 3)
        assert np.all(am >= 0.0)
        top = min(level, 10.0)
        assert am[:, 0].sum() / 3.0 == pytest.approx(_closed_form(level, top, 0), rel=5e-15)
        moment = (am[:, 0] * mesh.points[:, 2]).sum() / 3.0
        assert moment == pytest.approx(_closed_form(level, top, 1), rel=tol_moment)


@pytest.mark.parametrize("cell", ["quad", "quad8", "hexahedron", "tetra", "tetra10"])
def test_westergaard_on_faces_along_the_axes_stays_diagonal(cell: str) -> None:
    """Faces whose normals lie along the axes (a vertical face with the level cutting
    facets and the reservoir floor in 2D; a vertical face in 3D, and one whose points
    are moved off its plane by 1e-14 m, normals along x to round-off): the blocks have
    no off-diagonal entry (round-off coupling, at most 1e-12 of a block's trace, is
    dropped), added_mass_matrix() is diag(added_mass()) and the time stepping's mass
    mass(lumped=True, full_reservoir=True) is mass(lumped=True), both exactly, and the
    integrator keeps its diagonal path. (The masses are the previous code's bit for bit
    on these models and on test_reservoir's wet block and dam, whose added_mass(),
    added_mass_matrix(), masses, modes, inertia loads and a time history were compared
    by hash when the blocks were introduced.)"""
    if cell.startswith("quad"):
        mesh = pf.rectangle(1.0, 10.0, 2, 5, cell=cell)
        groups: tuple[str, ...] = ("xmin", "ymin")
    else:
        mesh = pf.box(2.0, 3.0, 10.0, 1, 2, 4, cell=cell)
        groups = ("xmin",)
    variants = [mesh]
    if cell == "tetra":
        noisy = pf.box(2.0, 3.0, 10.0, 1, 2, 4, cell=cell)
        face = noisy.points[:, 0] < 1e-9
        noisy.points[face, 0] += 1e-14 * np.random.default_rng(0).standard_normal(face.sum())
        variants.append(noisy)
    for msh in variants:
        m = pf.Model(msh, [pf.Block("all", pf.Elastic(30e9, 0.2, 2400.0))])
        m.add_westergaard(groups, water_level=9.3)
        m.fix("xmax")
        assert not m.added_mass_coupled()
        Ma = m.added_mass_matrix()
        assert (Ma - sp.diags(Ma.diagonal())).nnz == 0
        assert np.array_equal(Ma.diagonal(), m.added_mass())
        assert Ma.diagonal().sum() > 0
        full, lumped = m.mass(lumped=True, full_reservoir=True), m.mass(lumped=True)
        assert (full != lumped).nnz == 0 and full.nnz == lumped.nnz
        assert not pf.Dynamic(m, 1e-3)._full_mass


def _battered_block(theta: float, kn: float = 1e12) -> pf.Model:
    """A stiff block (E = 1e14 Pa, ρ = 2400 kg/m³) 1 m wide at its crest and 1 m high on
    a level joint (k_n = k_s = ``kn`` Pa/m, φ = 30°) over a fixed base, its upstream
    face battered θ from the vertical (from (−tan θ, 0.5) to (0, 1.5)) and wet up to
    its top: H = 1 m above the joint, Westergaard's bottom at the joint."""
    t = np.radians(theta)
    mesh = pf.rectangle(1.0, 1.5, 4, 12)
    x, y = mesh.points[:, 0].copy(), mesh.points[:, 1].copy()
    mesh.points[:, 0] = x - (1.5 - np.maximum(y, 0.5)) * np.tan(t) * (1 - x)
    mesh.add_cell_group("base", lambda p: p[:, 1] < 0.5)
    mesh.add_cell_group("block", lambda p: p[:, 1] > 0.5)
    mesh.add_facet_group("joint", lambda p: np.abs(p[:, 1] - 0.5) < 1e-9, False)
    mesh.add_facet_group("wet", lambda p: (np.abs(p[:, 0] + (1.5 - p[:, 1]) * np.tan(t))
                                           < 1e-9) & (p[:, 1] > 0.5 - 1e-9))  # fmt: skip
    mat = pf.Elastic(1e14, 0.2, 2400.0)
    m = pf.Model(mesh, [pf.Block("base", mat), pf.Block("block", mat)],
                 interfaces=[pf.Interface("joint", pf.Joint(phi=30.0, kn=kn, ks=kn))])  # fmt: skip
    m.fix("base")
    m.add_westergaard("wet", water_level=1.5)
    return m


def test_pseudo_static_load_on_a_battered_wet_face() -> None:
    """The battered block (θ = 30°, H = 1 m) under gravity and the pseudo-static load
    k_h = 0.2 (Model.add_inertia, a = k_h g along +x, the water upstream at x < 0): the
    load f = M (1 ⊗ a) puts on the water's added mass the force 7/12 ρ_w H² k_h g
    (cos θ, −sin θ) per metre (test_westergaard_inclined_face_pushes_along_its_normal):
    downstream and down on the battered face, the normal pressure's resultant. The
    block's equilibrium gives the joint's force on the block, R = (−k_h g (m +
    7/12 ρ_w H² cos θ), W + k_h g 7/12 ρ_w H² sin θ), m = ρ (1 + tan θ/2) its mass per
    metre and W = m g: to 3e-15 (measured 0 and 3.3e-16: a static equilibrium); the
    load's vertical part on the block is −7/12 ρ_w g H² k_h sin θ = −572.25 N, to 3e-15
    (measured 0). That vertical part was 0 before the blocks kept n nᵀ."""
    theta, g, kh, H = 30.0, 9.81, 0.2, 1.0
    t = np.radians(theta)
    m = _battered_block(theta)
    m.add_gravity(g)
    m.add_inertia([kh * g, 0.0])
    mass = 2400.0 * (1.0 + 0.5 * np.tan(t))
    wa = 7 / 12 * RHO_W * H**2
    ref = np.array([-kh * g * (mass + wa * np.cos(t)), mass * g + kh * g * wa * np.sin(t)])
    assert m.pairs is not None
    F, _ = m.pairs.resultants(pf.solve_static(m).pairs.X)  # type: ignore[union-attr]
    assert F[0] == pytest.approx(ref, rel=3e-15)
    f = m.inertia_load([kh * g, 0.0]).reshape(-1, 2)
    assert f[m.body_of_node == 1, 1].sum() == pytest.approx(-kh * g * wa * np.sin(t),
                                                            rel=3e-15)  # fmt: skip


def test_time_stepping_keeps_the_coupling_of_a_battered_face() -> None:
    """The battered block (θ = 30°, H = 1 m, k_n = k_s = 1e12 Pa/m: joint modes above
    1 kHz) under a horizontal ground acceleration a_g(t) = 2 sin³(2π t) m/s² (a smooth
    start; relative form), from its static state under gravity. The block moves with
    the ground (relative accelerations of order (f/f_n)² of the ground's, f ≤ 3 Hz), so
    its absolute acceleration is a_g ι and the water's force −M_a ι a_g: with the
    block's Newton's law m a_g ι = −W e_y − M_a ι a_g + R, the joint's force on the block
    is R = W e_y + (m + M_a) ι a_g, whose vertical part changes by

        ΔN(t) = a_g (M_a ι)_y = −7/12 ρ_w H² sin θ a_g(t)

    (the suction on the battered face lifts the block when the ground moves away from the
    water), and the horizontal one by ΔT = (m + 7/12 ρ_w H² cos θ) a_g. Asserted to
    5e-5 of their largest (measured 5.7e-6 and 6.3e-6: the quasi-static approximation;
    with k_n = 1e11 Pa/m, 2.8e-5 and 3.6e-5). With the diagonal added mass ΔN was 0. The
    run keeps the coupled mass (Dynamic._full_mass), and its energy balances to 5e-15
    of the external work (measured 5.5e-16)."""
    theta, g, H = 30.0, 9.81, 1.0
    t = np.radians(theta)
    m = _battered_block(theta)
    m.add_gravity(g)
    st = pf.solve_static(m)
    assert m.pairs is not None and st.pairs is not None
    F0, _ = m.pairs.resultants(st.pairs.X)
    tt = np.arange(0.0, 1.0 + 1e-12, 1e-3)
    ag = 2.0 * np.sin(np.pi * tt / 0.5) ** 3
    an = pf.Dynamic(m, 1e-3)
    assert an._full_mass
    res = an.run(1.0, ground=[pf.GroundMotion.from_samples(ag, time=tt)], start=st)
    assert res.completed
    a = np.interp(res.t, tt, ag)
    wa = 7 / 12 * RHO_W * H**2
    dT, dN = (res.joint_force[:, 0] - F0[0]).T  # x, y
    ref_n = -wa * np.sin(t) * a
    ref_t = (2400.0 * (1.0 + 0.5 * np.tan(t)) + wa * np.cos(t)) * a
    assert np.abs(dN - ref_n).max() < 5e-5 * np.abs(ref_n).max()
    assert np.abs(dT - ref_t).max() < 5e-5 * np.abs(ref_t).max()
    e = res.energy
    assert np.abs(e["balance"]).max() < 5e-15 * np.abs(e["external_work"]).max()


def test_mass_inverse_by_node_with_a_massless_wet_foundation() -> None:
    """A massless foundation whose face, battered with the block's (θ = 30°), is wet:
    its face nodes' mass is Westergaard's block μ_a n nᵀ alone, singular across the
    face. The time stepping's M⁻¹ (the start acceleration) is taken node by node on the
    blocks' eigenvalues (no acceleration across the face there), as the pseudo-inverse
    of the whole M: to 1e-15 (measured 1.2e-16); the run completes with its energy
    balanced to 5e-14 of the external work (measured 4.3e-15). (A factorisation of M
    on its DOFs with mass would find it singular.)"""
    t = np.radians(30.0)
    mesh = pf.rectangle(1.0, 1.5, 4, 12)
    x, y = mesh.points[:, 0].copy(), mesh.points[:, 1].copy()
    mesh.points[:, 0] = x - (1.5 - y) * np.tan(t) * (1 - x)
    mesh.add_cell_group("base", lambda p: p[:, 1] < 0.5)
    mesh.add_cell_group("block", lambda p: p[:, 1] > 0.5)
    mesh.add_facet_group("joint", lambda p: np.abs(p[:, 1] - 0.5) < 1e-9, False)
    mesh.add_facet_group("wet", lambda p: np.abs(p[:, 0] + (1.5 - p[:, 1]) * np.tan(t)) < 1e-9)
    joint = pf.Interface("joint", pf.Joint(phi=30.0, kn=1e11, ks=1e11))
    m = pf.Model(mesh, [pf.Block("base", pf.Elastic(1e10, 0.2, 0.0)),
                        pf.Block("block", pf.Elastic(1e10, 0.2, 2400.0))],
                 interfaces=[joint])  # fmt: skip
    m.fix("ymin")
    m.add_westergaard("wet", water_level=1.5)
    m.add_gravity()
    an = pf.Dynamic(m, 1e-3)
    assert an._full_mass
    r = np.random.default_rng(1).standard_normal(an.system.M.shape[0])
    ref = np.linalg.pinv(an.system.M.toarray(), rcond=1e-12, hermitian=True) @ r
    assert np.abs(an._mass_solve(r) - ref).max() < 1e-15 * np.abs(ref).max()
    tt = np.arange(0.0, 0.2 + 1e-12, 1e-3)
    gm = pf.GroundMotion.from_samples(2.0 * np.sin(np.pi * tt / 0.2) ** 3, time=tt)
    res = an.run(0.2, ground=[gm], start=pf.solve_static(m))
    assert res.completed
    e = res.energy
    assert np.abs(e["balance"]).max() < 5e-14 * np.abs(e["external_work"]).max()


def test_a_roller_supported_wet_node_feels_the_moving_ground() -> None:
    """The battered block of :func:`_battered` (Q4, θ = 30°, H = 12 m, wet to its top) on
    rollers (its base fixed along y, its downstream toe also along x), shaken vertically
    by a_g. The heel is wet with its y prescribed and its x free, and Westergaard's block
    μ n nᵀ couples the two: M_fp ≠ 0 there. The ground acts through it, and the water's
    horizontal push is the closed form's: Σ m_a a = 7/12 ρ_w H² / cos θ (a·n) n with
    n = (−cos θ, sin θ), a = (0, a_g), so the relative form's inertia load
    −(M_ff ι_f + M_fp ι_p) a_g sums along x, over the free DOFs (the toe is dry), to
    7/12 ρ_w H² a_g sin θ: to 2e-15 (measured 2.2e-16; the free DOFs' M_ff ι_f alone
    missed the heel's share, μ_heel cos θ sin θ a_g, 7.4 % of it). The absolute form
    loads the heel by −M_fp a_p beside −K_fp u_p: with the stiffness's load taken off,
    the same μ_heel cos θ sin θ a_g along x, to 1e-10 (measured 2.6e-11: K_fp u_p is
    10⁶ times larger and cancels), and nothing elsewhere (measured 0)."""
    from pfeie.dynamics import Excitation

    theta, H, a_g = np.radians(30.0), 12.0, 2.0
    mesh = _battered("quad", 30.0)
    m = pf.Model(mesh, [pf.Block("all", pf.Elastic(30e9, 0.2, 2400.0))])
    m.fix("ymin", components=1)
    x = mesh.points
    toe = int(np.argmin(np.abs(x[:, 0] - 8.0) + np.abs(x[:, 1])))
    heel = int(np.argmin(np.abs(x[:, 0] + H * np.tan(theta)) + np.abs(x[:, 1])))
    m.fix([toe], components=0)
    m.add_westergaard("xmin", water_level=H)
    system = m.system(lumped_mass=True, full_reservoir=True)
    assert system.M_fp is not None
    record = pf.GroundMotion.from_samples([a_g] * 3, dt=1.0, direction=(0.0, 1.0))
    static = system.load(0.0)
    rel = Excitation(m, system, [record], "relative").load(0.0) - static
    expect = 7 / 12 * 1000.0 * H**2 * a_g * np.sin(theta)
    free_x = system.free % 2 == 0
    assert rel[free_x].sum() == pytest.approx(expect, rel=2e-15)
    mu_heel = m.added_mass()[2 * heel : 2 * heel + 2].sum()  # the trace of its block
    share = mu_heel * np.cos(theta) * np.sin(theta) * a_g
    assert 0.05 * expect < share < 0.1 * expect
    row = int(np.flatnonzero(system.free == 2 * heel)[0])
    # at t = 1 s the base has moved by d_g = a_g/2 (a constant a_g): its stiffness load
    # −K_fp ι_p d_g taken off, what is left is the mass's
    ab = Excitation(m, system, [record], "absolute").load(1.0) - static
    pres = system.prescribed
    ab += m.stiffness()[system.free][:, pres] @ (pres % 2 == 1).astype(float) * (a_g / 2)
    assert ab[row] == pytest.approx(share, rel=1e-10)
    assert np.abs(np.delete(ab, row)).max() <= 1e-12 * share
