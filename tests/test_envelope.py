"""Stress envelopes: the stress operators against the stress kernel, the principal
stresses against LAPACK, the envelope of a run against one recomputed independently from
its recorded displacements, and a column under its own weight against the closed form."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import pfeie as pf
from pfeie.assembly import VOIGT, principal_extremes, principal_stresses
from pfeie.element import quadrature, reference
from pfeie.verification._models import block_on_base

G = 9.81


def _voigt(sig: np.ndarray) -> np.ndarray:
    return np.stack([sig[..., i, j] for i, j in VOIGT], axis=-1)


def _models() -> list[pf.Model]:
    """A 2D mesh of quadratic quadrilaterals and triangles (two blocks) and a 3D Tet10
    block, with different materials."""
    m2 = pf.rectangle(2.0, 1.0, 4, 3, cell="quad8")
    m2.add_cell_group("left", lambda x: x[:, 0] < 1.0)
    m2.add_cell_group("right", lambda x: x[:, 0] > 1.0)
    a = pf.Model(m2, [pf.Block("left", pf.Elastic(20e9, 0.2, 2400)),
                      pf.Block("right", pf.Elastic(35e9, 0.3, 2600))])  # fmt: skip
    m3 = pf.box(1.0, 1.0, 2.0, 2, 2, 3, cell="tetra10")
    m3.add_cell_group("b", lambda x: x[:, 0] > -1)
    b = pf.Model(m3, [pf.Block("b", pf.Elastic(30e9, 0.25, 2500))])
    return [a, b]


def _nodal_reference(model: pf.Model, u: np.ndarray) -> np.ndarray:
    """The nodal stress written out cell type by cell type (the corner fit of the
    quadrature-point values, evaluated at the nodes, averaged over the cells)."""
    from pfeie import assembly as asm

    acc = np.zeros((model.mesh.n_points, 3, 3))
    cnt = np.zeros(model.mesh.n_points)
    for ctype, (sig, _) in model.stress(u).items():
        lin = reference(reference(ctype).linear)
        xi, _ = quadrature(ctype, asm.stiffness_degree(ctype))
        extrap = lin.shape_functions(reference(ctype).nodes)[0] @ np.linalg.pinv(
            lin.shape_functions(xi)[0])  # fmt: skip
        conn = model.mesh.cells[ctype]
        nod = np.einsum("nq,cqij->cnij", extrap, sig)
        np.add.at(acc, conn.ravel(), nod.reshape(-1, 3, 3))
        cnt += np.bincount(conn.ravel(), minlength=model.mesh.n_points)
    return acc / np.maximum(cnt, 1)[:, None, None]


@pytest.mark.parametrize("k", [0, 1, 2], ids=["2D Q8", "3D Tet10", "2D plane stress"])
def test_stress_operators_equal_the_kernel(k: int) -> None:
    """``Model.stress_operators`` applied to a random displacement equals the stress
    kernel at the quadrature points (its strain operator and Lamé constants, and the
    operator DB written out over the DOFs) and the nodal fit written out in the test
    (1e-14 of the largest stress; measured 3e-16 to 5e-16)."""
    if k == 2:  # the Q8 mesh in plane stress: σ_zz = 0 and the plane-stress λ
        blocks = [pf.Block("left", pf.Elastic(20e9, 0.2, 2400)),
                  pf.Block("right", pf.Elastic(35e9, 0.3, 2600))]  # fmt: skip
        model = pf.Model(_models()[0].input_mesh, blocks, plane="stress")
    else:
        model = _models()[k]
    u = np.random.default_rng(k).standard_normal(model.n_dof) * 1e-4
    op = model.stress_operators
    ref = np.concatenate([_voigt(sig).reshape(-1, 6) for sig, _ in model.stress(u).values()])
    scale = np.abs(ref).max()
    for got in (op.at_points(u), op.components(u).T, (op.points @ u).reshape(-1, 6)):
        assert np.abs(got - ref).max() < 2e-15 * scale
    if k == 2:
        assert not op.components(u)[2].any()
    nodal = _voigt(_nodal_reference(model, u))
    assert np.abs(op.at_nodes(op.at_points(u)) - nodal).max() < 1e-14 * scale
    assert np.abs(op.nodal_components(op.components(u)).T - nodal).max() < 1e-14 * scale
    assert np.abs(_voigt(model.nodal_stress(u)) - nodal).max() < 1e-14 * scale


def test_principal_stresses_equal_lapack() -> None:
    """Closed-form principal stresses against ``numpy.linalg.eigvalsh`` on 20,000 random
    tensors: plane states (in-plane pair c ± R) to 4e-15 of ‖σ‖ (measured 1.8e-15), general
    ones (the trigonometric cubic) to 1e-13 (measured 1.4e-14); a doubly repeated root
    (uniaxial, 5 Pa) to 2e-7 (the cubic loses half the digits there: measured 2.5e-8)."""
    rng = np.random.default_rng(3)
    A = rng.standard_normal((20000, 3, 3))
    A = A + A.transpose(0, 2, 1)
    ref = np.linalg.eigvalsh(A)[:, ::-1]
    assert np.abs(principal_stresses(_voigt(A)) - ref).max() < 1e-13
    A[:, 0, 2] = A[:, 2, 0] = A[:, 1, 2] = A[:, 2, 1] = 0.0
    ref = np.linalg.eigvalsh(A)[:, ::-1]
    assert np.abs(principal_stresses(_voigt(A)) - ref).max() < 4e-15
    R = np.linalg.qr(rng.standard_normal((3, 3)))[0]
    uni = R @ np.diag([5.0, 0.0, 0.0]) @ R.T
    np.testing.assert_allclose(principal_stresses(_voigt(uni[None]))[0], [5, 0, 0], atol=2e-7)


@pytest.mark.parametrize("rows", ["general", "mixed", "plane"])
def test_principal_extremes_are_those_of_the_sorted_roots(rows: str) -> None:
    """The envelope's σ₁ and σ₃ without the sort equal the first and the last of
    :func:`principal_stresses` to the bit: random general states (the 3D path, no plane
    row), and mixed with plane, hydrostatic, uniaxial-diagonal and zero rows."""
    rng = np.random.default_rng(7)
    s = 1e6 * rng.standard_normal((5000, 6))
    if rows != "general":
        s[:1000, 3:5] = 0.0  # plane states
        s[1000:1100] = 0.0
        s[1100:1200, 1:3] = s[1100:1200, :1]  # hydrostatic
        s[1100:1300, 3:] = 0.0  # diagonal
    if rows == "plane":
        s = s[:1000]
    hi, lo = principal_extremes(s)
    p3 = principal_stresses(s)
    np.testing.assert_array_equal(hi, p3[:, 0])
    np.testing.assert_array_equal(lo, p3[:, 2])


def test_envelope_of_a_run_equals_its_recorded_states() -> None:
    """A bonded block on a base that breaks, slides and sticks under 0.8 g at 2 Hz: the
    envelope the run keeps (every 2nd step) equals the one recomputed from the
    displacements it recorded, stress by the kernel and principal stresses by LAPACK
    (node and cell extremes 1e-11 of the largest stress, measured 2.2e-12: round-off of
    two summation orders; the times equal)."""
    model = block_on_base(joint=pf.Joint(c=2e3, phi=30.0, tensile=1e3, initial="intact"),
                          E=10e9, n=4, width=2.0)  # fmt: skip
    gm = pf.GroundMotion.from_function(lambda t: 0.8 * G * np.sin(4 * np.pi * t), 0.6, 1e-3)
    rows: list[tuple[float, np.ndarray]] = []
    res = pf.Dynamic(model, 0.002).run(
        0.6, start=pf.solve_static(model), ground=[gm], every=2,
        on_record=lambda r: rows.append((r["t"], r["u"].ravel().copy())),
    )  # fmt: skip
    env = res.envelope
    t = np.array([r[0] for r in rows])
    assert t.size == res.t.size and res.broken[-1].all()
    node_hi, node_lo, cell_hi, cell_lo = [], [], [], []
    for _, u in rows:
        node_p = np.linalg.eigvalsh(_nodal_reference(model, u))
        node_hi.append(node_p[:, 2])
        node_lo.append(node_p[:, 0])
        cp = [np.linalg.eigvalsh(sig) for sig, _ in model.stress(u).values()]
        cell_hi.append(np.concatenate([p[:, :, 2].max(axis=1) for p in cp]))
        cell_lo.append(np.concatenate([p[:, :, 0].min(axis=1) for p in cp]))
    active = model.active_nodes
    scale = np.abs(np.array(node_lo)).max()
    for key, series, pick in (("node_max", node_hi, np.argmax), ("node_min", node_lo, np.argmin),
                              ("cell_max", cell_hi, np.argmax),
                              ("cell_min", cell_lo, np.argmin)):  # fmt: skip
        s = np.array(series)
        idx = active if key.startswith("node") else np.arange(s.shape[1])
        ref = s[pick(s, axis=0), np.arange(s.shape[1])][idx]
        assert np.abs(env[key][idx] - ref).max() < 1e-11 * scale, key
        when = t[pick(s, axis=0)][idx]
        # the first time of the extreme; rows with values equal to round-off can tie
        close = np.abs(env[key + "_time"][idx] - when) < 1e-12
        assert close.mean() > 0.99, key


def test_column_under_its_own_weight(tmp_path: Path) -> None:
    """A column 1 m × 4 m (Q8, ν = 0, fixed base) under gravity, run from its static
    state with no excitation: the smallest principal stress is σ_yy = −ρ g (H − y),
    linear, which Q8 reproduces exactly; at every node to 3e-13 of ρ g H (measured
    3.5e-14), the largest principal stress 0 to 1e-13 of ρ g H (measured 1.2e-14)."""
    rho, H = 2500.0, 4.0
    mesh = pf.rectangle(1.0, H, 2, 8, cell="quad8")
    mesh.add_cell_group("col", lambda x: x[:, 0] > -1)
    model = pf.Model(mesh, [pf.Block("col", pf.Elastic(20e9, 0.0, rho))])
    model.fix("ymin")
    model.add_gravity()
    res = pf.Dynamic(model, 0.001).run(0.01, start=pf.solve_static(model))
    env, y = res.envelope, mesh.points[:, 1]
    exact = -rho * G * (H - y)
    assert np.abs(env["node_min"] - exact).max() < 3e-13 * rho * G * H
    assert np.abs(env["node_max"]).max() < 1e-13 * rho * G * H


def test_envelope_through_the_model_file(tmp_path: Path) -> None:
    """``pfeie run``: the envelope in results.h5 (with units), in the summary (the
    extremes, where and when) and in envelope.vtu, read back by meshio equal to the
    results file's; ``output.envelope = false`` writes none. The joint resultants in
    results.h5 and as series of ``pfeie export``'s joints.csv."""
    import json

    import meshio

    from pfeie.cli import main
    from pfeie.io import Results
    from test_cli import SMALL, _write

    p = _write(tmp_path, SMALL, duration=0.3)
    assert main(["run", str(p), "--quiet"]) == 0
    out = tmp_path / "out"
    with Results(out / "results.h5") as res:
        env = res.envelope()
        assert res.units("envelope/nodes/max_principal") == "Pa"
    summary = json.loads((out / "summary.json").read_text())["stress"]
    assert summary["min_principal_Pa"] == np.nanmin(env["node_min"]) < 0
    assert "stress       max principal" in (out / "summary.txt").read_text()
    # the joint resultants: in results.h5 and as series of joints.csv
    with Results(out / "results.h5") as res:
        jr = res.joint_resultants("joint")
        assert res.units("history/joints/moment") == "N*m"
        n_t = res.n_times
    assert jr["force"].shape == (n_t, 2) and jr["moment"].shape == (n_t, 1)
    assert main(["export", str(out / "results.h5"), "--csv", str(tmp_path / "csv")]) == 0
    rows = [r.split(",") for r in (tmp_path / "csv" / "joints.csv").read_text().splitlines()]
    fy = [float(r[3]) for r in rows if r[2] == "force_y"]
    np.testing.assert_allclose(fy, jr["force"][:, 1], rtol=1e-8)  # 9 digits in the CSV
    assert any(r[2] == "moment_z" for r in rows)
    # and in the report: the envelope's extremes, the joints' resultants and minimum FS
    assert main(["report", str(out / "results.h5")]) == 0
    page = (out / "report.html").read_text()
    assert "<h2>Stress envelope</h2>" in page and "peak horizontal |F| (kN)" in page
    assert f"{summary['min_principal_Pa'] / 1e6:.3g} MPa" in page and "min safety factor" in page
    # the probes' peaks and the floating blocks' permanent displacement, as the summary
    full = json.loads((out / "summary.json").read_text())
    for name, pr in full["probes"].items():
        assert f"<td>{name}</td><td>{1e3 * pr['peak_displacement_m']:.4g}</td>" in page
    floating = {k: b for k, b in full["bodies"].items() if b["floating"]}
    assert floating and "Blocks held by their joints: permanent displacement" in page
    for name, b in floating.items():
        assert f"<td>{name}</td><td>{1e3 * b['residual_displacement_m']:.4g}</td>" in page
    vtu = meshio.read(out / "envelope.vtu")
    np.testing.assert_array_equal(vtu.point_data["min_principal"], env["node_min"])
    np.testing.assert_array_equal(np.concatenate(vtu.cell_data["max_principal_time"]),
                                  env["cell_max_time"])  # fmt: skip
    q = tmp_path / "off"
    q.mkdir()
    p = _write(q, SMALL.replace('folder = "out"', 'folder = "out"\nenvelope = false'),
               duration=0.1)  # fmt: skip
    assert main(["run", str(p), "--quiet"]) == 0
    with Results(q / "out" / "results.h5") as res:
        assert res.envelope() == {}
    assert not (q / "out" / "envelope.vtu").exists()


def test_joint_resultants_of_a_block_on_an_incline(tmp_path: Path) -> None:
    """A block 2 m × 1 m resting on a 20° incline (φ = 35°: it sticks), run from its
    static state: the resultant of its joint's pair forces on the block balances its
    weight, F = (0, ρ g A) to 1e-12 of W (measured 1.1e-13), and the moment about the
    joint's centroid balances the weight's, M = (x_g − c)_x W to 5e-13 of W × 1 m
    (measured 7e-14); constant over the run."""
    rho, w, h, th = 2400.0, 2.0, 1.0, np.radians(20.0)
    model = block_on_base(joint=pf.Joint(phi=35.0), incline_deg=20, n=4, width=w, height=h,
                          rho=rho)  # fmt: skip
    P = model.pairs
    assert P is not None
    res = pf.Dynamic(model, 0.01).run(0.2, start=pf.solve_static(model))
    W = rho * G * w * h
    # side b of the pairs: the block (above the joint) or the base
    normal = P.frame[:, -1]
    up = np.einsum("kd,kd->k", model.mesh.points[P.node_b] - model.mesh.points[P.node_a],
                   normal)  # fmt: skip
    rot = np.array([[np.cos(-th), -np.sin(-th)], [np.sin(-th), np.cos(-th)]])
    x_g = rot @ np.array([w / 2, h / 2])
    c = P.centroids[0]
    sign = 1.0 if model.body_of_node[P.node_b[0]] == model.body_of_node[
        model.nearest_node(x_g)] else -1.0  # fmt: skip
    assert np.all(up == 0)  # pairs join coincident nodes
    F, M = res.joint_force[:, 0], res.joint_moment[:, 0, 0]
    assert np.abs(F - sign * np.array([0.0, W])).max() < 1e-12 * W
    assert np.abs(M - sign * (x_g - c)[0] * W).max() < 5e-13 * W



def _dropped(dt: float) -> float:
    """The least principal stress of the envelope (Pa) of a 1 m square block (8 × 8 Q4,
    concrete) dropped flat from a gap of 1 mm onto a 1 m base fixed at its bottom, over
    0.03 s (it lands at 0.0143 s at 0.140 m/s), by the default scheme at step ``dt``."""
    mesh = pf.rectangle(1.0, 2.0, 8, 16)
    mesh.add_cell_group("base", lambda x: x[:, 1] < 1.0)
    mesh.add_cell_group("block", lambda x: x[:, 1] > 1.0)
    mesh.add_facet_group("joint", lambda x: np.abs(x[:, 1] - 1.0) < 1e-9, boundary_only=False)
    concrete = pf.Elastic(30e9, 0.2, 2400.0)
    model = pf.Model(mesh, [pf.Block("base", concrete), pf.Block("block", concrete)],
                     interfaces=[pf.Interface("joint", pf.Joint(phi=30.0, gap=1e-3))])  # fmt: skip
    model.fix("ymin")
    model.add_gravity()
    env = pf.Dynamic(model, dt).run(0.03).envelope
    return float(np.nanmin(env["node_min"]))


def test_an_impact_envelope_holds_no_position_correction() -> None:
    """The position correction of the default scheme moves the nodes of penetrating pairs
    alone, and for its step their cells hold a strain of the scheme's: the envelope takes
    the stress of the step's smooth configuration, before the correction. Reference: the
    same landing at Δt = 62.5 µs (−1.77 MPa; the closed-form scale is the impact stress
    ρ c_p v = 1.25 MPa that the fixed bottom reflects, c_p = 3,727 m/s the plane-strain
    wave speed, v = 0.140 m/s, plus the wave front's overshoot on the mesh). At Δt = 1 and
    0.25 ms, steps that do not resolve the impact, the envelope stays within it (measured
    0.397 and 0.883 of it; Moreau–Jean: 0.24 and 0.48, and −1.41 MPa at 62.5 µs); with
    the correction's strain it read −13.8 and −4.12 MPa, 7.8 and 2.3 times the converged
    value."""
    fine = _dropped(6.25e-5)
    # the scale by hand: ρ c_p v, the plane-strain wave speed and the landing speed
    E, nu, rho = 30e9, 0.2, 2400.0
    c_p = np.sqrt(E * (1 - nu) / ((1 + nu) * (1 - 2 * nu) * rho))  # 3,727 m/s
    impact = rho * c_p * np.sqrt(2 * G * 1e-3)  # 1.251 MPa
    # measured 1.418: above the reflected wave, below it plus the front's overshoot of half
    assert 1.0 < -fine / impact < 1.5
    # the steps are deterministic; the tolerances leave room for the last bits of a BLAS
    assert fine == pytest.approx(-1.7742e6, rel=1e-4)  # measured −1.77423 MPa
    for dt, share in ((1e-3, 0.3974), (2.5e-4, 0.8828)):  # measured 0.39744, 0.88284
        ratio = _dropped(dt) / fine
        assert ratio == pytest.approx(share, abs=1e-3), (dt, ratio)


@pytest.mark.parametrize("plane", ["strain", "stress"])
@pytest.mark.parametrize("cell", ["quad", "triangle", "quad8"])
def test_plane_envelope_from_mohrs_circle(plane: str, cell: str) -> None:
    """The plane envelope's σ₁ and σ₃ from the rows of Mohr's circle (c, a, b, σ_zz,
    extrapolated to the nodes as rows) equal the principal extremes of the stress
    components at the points and at the nodes (:meth:`StressOperators.components`,
    :meth:`~StressOperators.nodal_components`), for a random displacement with shear,
    ν = 0.3, two materials, plane strain (σ_zz = λ tr ε) and plane stress (σ_zz = 0): to
    2e-15 of the largest stress (measured up to 3.9e-16, round-off)."""
    from pfeie.dynamics._recorder import StressEnvelope

    mesh = pf.rectangle(2.0, 1.0, 4, 3, cell=cell)
    mesh.add_cell_group("a", lambda x: x[:, 0] < 1.0)
    mesh.add_cell_group("b", lambda x: x[:, 0] > 1.0)
    model = pf.Model(mesh, [pf.Block("a", pf.Elastic(30e9, 0.3, 2400.0)),
                            pf.Block("b", pf.Elastic(10e9, 0.2, 2000.0))],
                     plane=plane)  # fmt: skip
    u = 1e-4 * np.random.default_rng(3).standard_normal(model.n_dof)
    env = StressEnvelope(model)
    hi_q, lo_q, hi_n, lo_n = env._point_and_node_extremes(u)
    op = model.stress_operators
    sq = op.components(u)
    ref_q = principal_extremes(sq.T)
    ref_n = principal_extremes(op.nodal_components(sq).T)
    scale = np.abs(sq).max()
    for got, ref in ((hi_q, ref_q[0]), (lo_q, ref_q[1]), (hi_n, ref_n[0]), (lo_n, ref_n[1])):
        assert np.abs(got - ref).max() < 2e-15 * scale
    assert np.abs(sq[5]).max() > 0.1 * scale  # the shear takes part
