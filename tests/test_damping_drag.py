"""Mass-proportional damping brakes a sliding block (docs/model-file.md, "Damping").

A block launched at v₀ along a level joint of friction coefficient μ decelerates by μg,
and, with the Rayleigh term α M acting on its motion relative to the ground, by α v more:
v' = −μg − α v. It stops after

    d₀ = v₀² / (2 μ g)                                  (α = 0),
    d_α = v₀/α − (μg/α²) ln(1 + α v₀/(μg))              (α > 0),

0.16989 m and 0.11848 m for v₀ = 1 m/s, μ = 0.3, α = 2 1/s: the drag shortens the slide
by 30 %. The deformable block (E = 30 GPa, 2 × 2 Q4, Δt = 1 ms) gives both within 0.4 %
(measured 0.29 % and 0.39 %: the block's elastic response to the launch and the step);
asserted 1 %.

With ``Rayleigh(..., deformation_only=True)`` the mass-proportional part spares the
floating block's rigid motion, C R = 0 (docs/model-file.md, "Damping"): the block slides d₀
again, however large α, while its deformation modes keep the damping of C = αM + βK.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import pfeie as pf
from pfeie.dynamics import DynamicResult, damping_product
from pfeie.verification._models import block_on_base, block_on_base_3d, slip_x

MU, V0, G = 0.3, 1.0, 9.81


def _slide(alpha: float) -> float:
    """The closed-form slide of the launched block (m): d₀ or d_α above."""
    if alpha == 0.0:
        return float(V0**2 / (2 * MU * G))
    return float(V0 / alpha - MU * G / alpha**2 * np.log(1 + alpha * V0 / (MU * G)))


@pytest.mark.parametrize("alpha", [0.0, 2.0])
def test_a_launched_block_stops_where_the_closed_form_says(alpha: float) -> None:
    m = block_on_base(joint=pf.Joint(phi=float(np.degrees(np.arctan(MU)))))
    m.damping = pf.Rayleigh(alpha, 0.0)
    st = pf.solve_static(m)
    an = pf.Dynamic(m, 1e-3)
    v = np.zeros_like(st.u)
    v[m.body_of_node == 1, 0] = V0  # the block, its joint face included
    res = an.run(0.6, start=an.initial(st, v0=v))  # stops at t < v₀/(μg) = 0.34 s
    d = slip_x(res)[-1] - slip_x(res)[0]
    assert d == pytest.approx(_slide(alpha), rel=1e-2)
    assert abs(slip_x(res)[-1] - slip_x(res)[-50]) < 1e-9  # at rest at the end


def _launched(
    alpha: float, deformation_only: bool, **settings: object
) -> tuple[pf.Model, DynamicResult]:
    m = block_on_base(joint=pf.Joint(phi=float(np.degrees(np.arctan(MU)))))
    m.damping = pf.Rayleigh(alpha, 0.0, deformation_only=deformation_only)
    st = pf.solve_static(m)
    an = pf.Dynamic(m, 1e-3, **settings)  # type: ignore[arg-type]
    v = np.zeros_like(st.u)
    v[m.body_of_node == 1, 0] = V0
    return m, an.run(0.6, start=an.initial(st, v0=v))


@pytest.mark.parametrize("alpha", [2.0, 20.0])
def test_damping_of_the_deformation_only_spares_the_slide(alpha: float) -> None:
    """α = 2 and 20 1/s on the deformation only: the block slides d₀ = v₀²/(2μg) as without
    damping (1 %, as above), and the same distance as the undamped run to 1e-10 (measured
    8.9e-12: the drag is gone, not merely small). The energy: friction takes ½ m v₀² (2e-4;
    measured 2.1e-5, the block's elastic energy) and the damping 1e-8 of it at most
    (measured 1.1e-9 at α = 20, the launch's elastic ringing); with the full α M the
    damping takes 1 − d_α/d₀ = 0.3026 of it (2 %; measured 0.3045, 0.6 % above)."""
    _, free = _launched(0.0, False)
    m, res = _launched(alpha, True)
    d, d_free = (slip_x(r)[-1] - slip_x(r)[0] for r in (res, free))
    assert d == pytest.approx(_slide(0.0), rel=1e-2)
    assert d == pytest.approx(d_free, rel=1e-10)
    kinetic = 0.5 * m.body_mass_props[0][1] * V0**2
    assert res.energy["interface"][-1] == pytest.approx(kinetic, rel=2e-4)
    assert 0.0 <= res.energy["damping"][-1] < 1e-8 * kinetic
    if alpha == 2.0:
        _, dragged = _launched(alpha, False)
        assert dragged.energy["damping"][-1] == pytest.approx(
            (1 - _slide(2.0) / _slide(0.0)) * kinetic, rel=0.02)  # the drag's share, as above


@pytest.mark.parametrize("settings", [{"scheme": "moreau-jean"}, {"large_rotation": True}],
                         ids=["moreau-jean", "large rotations"])
def test_damping_of_the_deformation_only_in_the_other_steps(settings: dict[str, object]) -> None:
    """The θ-method and the body frames of large rotations: with α = 2 1/s on the
    deformation only the block slides as far as without damping (1e-10; measured 1.0e-12
    and 2.8e-12), 30 % farther than with the full α M."""
    slides = [slip_x(r)[-1] - slip_x(r)[0]
              for r in (_launched(a, do, **settings)[1]
                        for a, do in ((0.0, False), (2.0, True), (2.0, False)))]  # fmt: skip
    assert slides[1] == pytest.approx(slides[0], rel=1e-10)
    assert slides[2] == pytest.approx(_slide(2.0) / _slide(0.0) * slides[0], rel=1e-2)


@pytest.mark.parametrize("dim", [2, 3])
def test_deformation_only_damping_operator(dim: int) -> None:
    """The operator itself, against its definition: C R_b = 0 on the floating body's rigid
    modes (5e-16 of ‖|C| |R_b|‖, the size of the product's terms; measured ≤ 6e-17), and
    C φ = (α M + β K) φ on its deformation modes φ (generalised eigenvectors of the body's
    K and M, dense LAPACK; 1e-17 of ‖(αM + βK) φ‖, measured ≤ 9e-19: Rᵀ M φ vanishes to
    round-off), so their ratio stays ζ(ω) = α/(2ω) + βω/2 (φᵀCφ = α + βω² for M-normalised
    φ, 2e-14; measured 2.1e-15). Without ``deformation_only`` there is no low-rank part."""
    import scipy.linalg as sla

    joint = pf.Joint(phi=30.0)
    m = block_on_base(joint=joint) if dim == 2 else block_on_base_3d(joint=joint)
    alpha, beta = 3.0, 2e-4
    m.damping = pf.Rayleigh(alpha, beta, deformation_only=True)
    sysd = m.system()
    assert sysd.C_update is not None and sysd.C_update.rank == (3 if dim == 2 else 6)
    full = sysd.C  # the sparse part: α M + β K
    assert full is not None
    r = 3 if dim == 2 else 6
    body = int(m.floating_bodies()[0])
    R = m.rigid_modes()[:, body * r : (body + 1) * r].tocsr()[sysd.free].toarray()
    for j in range(r):  # round-off against the size of the products' terms, |C| |R_j|
        ref = np.linalg.norm(abs(full) @ np.abs(R[:, j]))
        assert np.linalg.norm(damping_product(sysd, R[:, j])) < 5e-16 * ref
    # the body's own DOFs (its nodes are all free): K and M of the body alone
    own = np.flatnonzero(np.repeat(m.body_of_node == body, dim)[sysd.free])
    Kb = sysd.K[own][:, own].toarray()
    Mb = sysd.M[own][:, own].toarray()
    w2, phi = sla.eigh(Kb, Mb)
    deform = w2 > 1e-6 * w2.max()
    assert np.count_nonzero(~deform) == r
    for k in np.flatnonzero(deform)[:6]:
        v = np.zeros(sysd.n)
        v[own] = phi[:, k]
        ref = full @ v
        got = damping_product(sysd, v)
        assert np.linalg.norm(got - ref) < 1e-17 * np.linalg.norm(ref)
        assert v @ got == pytest.approx(alpha + beta * w2[k], rel=2e-14)
    m.damping = pf.Rayleigh(alpha, beta)
    assert m.system().C_update is None


def test_modal_damping_ratios_of_the_demo_dam() -> None:
    """The Koyna demo, joints bonded, 5 % at two frequencies: each mode's ratio
    φᵀCφ/(2ω) is Rayleigh's α/(2ω) + βω/2 (5e-13; measured 8.6e-14, φᵀKφ against the
    eigensolver's ω²), and with ``deformation_only`` it equals the time step's own
    damping operator (C + U B Uᵀ by Woodbury's term, :func:`damping_product`) to 2e-14
    (measured 2.8e-15). The first mode carries 98.9 % of its kinetic energy in the rigid
    motion of the two floating dam blocks, so the deformation-only damping leaves it
    0.75 % instead of 5.09 % (docs/model-file.md, "Damping")."""
    from pfeie.io._modelfile import load_job

    m = load_job(Path(__file__).resolve().parents[1] / "examples" / "koyna" / "koyna.toml").model
    assert m.damping is not None
    a, b = m.damping.alpha, m.damping.beta
    full = pf.modal(m, 4)
    rayleigh = [m.damping.ratio(f) for f in full.frequencies]
    np.testing.assert_allclose(full.damping_ratios, rayleigh, rtol=5e-13)
    m.damping = pf.Rayleigh(a, b, deformation_only=True)
    sysd = m.system()
    spared = pf.modal(m, 4)
    for k in range(4):
        phi = spared.shapes[k].ravel()[sysd.free]
        ref = phi @ damping_product(sysd, phi) / (4 * np.pi * spared.frequencies[k])
        assert spared.damping_ratios[k] == pytest.approx(ref, rel=2e-14)
    assert spared.rigid_share[0] == pytest.approx(0.989, abs=1e-3)
    assert 100 * spared.damping_ratios[0] == pytest.approx(0.75, abs=0.005)
    assert 100 * full.damping_ratios[0] == pytest.approx(5.09, abs=0.005)


def test_deformation_only_with_rollers_and_a_coupling_reservoir() -> None:
    """(1) A 3D block on a level joint whose side y = 0 rides on a roller (u_y = 0 there):
    its supports leave it three rigid motions (along x and z, about y), which the
    deformation-only damping spares: launched along the roller at 1 m/s it slides as far as
    without damping (1e-10; measured 1.9e-11), 30 % farther than under the full α M.
    (2) Pine Flat with its finite-element reservoir, whose added mass couples the two wet
    floating blocks: C R = 0 on their six rigid motions to 5e-15 of |C| |R| (measured
    6.9e-16; the projector is one block over the coupled motions, not one per body)."""
    from pfeie.io._modelfile import load_job, parse_override

    slides = []
    for alpha, spare in ((0.0, False), (2.0, True), (2.0, False)):
        m = block_on_base_3d(joint=pf.Joint(phi=float(np.degrees(np.arctan(MU)))))
        side = (m.mesh.points[:, 1] < 1e-9) & (m.mesh.points[:, 2] > 1e-9)
        m.fix(np.flatnonzero(side), components=1)
        m.damping = pf.Rayleigh(alpha, 0.0, deformation_only=spare)
        assert m.free_rigid_modes().shape[1] == 3 and not m.floating_bodies().size
        st = pf.solve_static(m)
        an = pf.Dynamic(m, 1e-3)
        v = np.zeros_like(st.u)
        v[m.body_of_node == 1, 0] = V0
        res = an.run(0.5, start=an.initial(st, v0=v))
        slides.append(slip_x(res)[-1] - slip_x(res)[0])
    assert slides[1] == pytest.approx(slides[0], rel=1e-10)
    assert slides[2] == pytest.approx(_slide(2.0) / _slide(0.0) * slides[0], rel=1e-2)

    root = Path(__file__).resolve().parents[1] / "examples" / "pine_flat" / "pine_flat.toml"
    job = load_job(root, [parse_override("damping.deformation_only=true")])
    m = job.model
    assert m.fe_reservoirs and m.floating_bodies().size == 2
    sysd = m.system(lumped_mass=True, full_reservoir=True)
    assert sysd.C is not None
    R = m.free_rigid_modes().tocsr()[sysd.free].toarray()
    for j in range(R.shape[1]):
        ref = np.linalg.norm(abs(sysd.C) @ np.abs(R[:, j]))
        assert np.linalg.norm(damping_product(sysd, R[:, j])) < 5e-15 * ref
