"""The limit of static equilibrium of a block on a frictional joint.

A block on a plane of dip θ with a joint of friction angle φ (no cohesion) is held iff
tan θ ≤ tan φ (limit equilibrium; the pseudo-static coefficient k_h of a block on a plane
of dip β adds atan k_h to the dip). Tilting gravity by θ on a flat base poses the same
problem. The static analysis must hold the block up to the limit, with the joint's
resultant shear over normal force equal to tan θ (equilibrium), and refuse the load just
beyond it with a message that names the block and the joint. Near the limit most pairs
slide, and trial state patterns that leave the block free (every pair sliding) used to end
the 3D analysis with a mechanism at a factor of safety of 1.01.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import pfeie as pf
from pfeie.cli import main
from pfeie.errors import InterfaceError, MechanismError
from pfeie.interface import OPEN
from pfeie.verification._models import block_on_base, block_on_base_3d
from test_cli import SMALL, _write
from test_study import ELEMENTS, NAMES, NODES

PHI = 30.0


def _tilted(dim: int, theta: float) -> pf.Model:
    t = np.radians(theta)
    if dim == 2:
        m = block_on_base(joint=pf.Joint(phi=PHI), gravity=False, n=4)
        m.add_gravity(direction=[np.sin(t), -np.cos(t)])
    else:
        m = block_on_base_3d(joint=pf.Joint(phi=PHI), gravity=False, n=3)
        m.add_gravity(direction=[np.sin(t), 0.0, -np.cos(t)])
    return m


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("theta", [29.0, 29.9, 29.99])
def test_held_up_to_the_limit(dim: int, theta: float) -> None:
    """Held at factors of safety tan φ / tan θ = 1.042, 1.0035 and 1.0003: ‖ΣT‖/ΣN = tan θ
    to 4e-15 (equilibrium of the block; measured 4.4e-16 at most), every pair within its
    cone (to 1e-10 of the largest force)."""
    st = pf.solve_static(_tilted(dim, theta))
    assert st.pairs is not None
    X = st.pairs.X
    ratio = np.linalg.norm(X[:, :-1].sum(axis=0)) / X[:, -1].sum()
    assert ratio == pytest.approx(np.tan(np.radians(theta)), rel=4e-15)
    mu = np.tan(np.radians(PHI))
    excess = np.linalg.norm(X[:, :-1], axis=1) - mu * np.maximum(X[:, -1], 0.0)
    # within the interface solver's tolerance (1e-8 of the forces' scale by the natural-map
    # residual); measured 7.7e-12 (3D at 29.99°, solved by the Newton) and round-off
    assert excess.max() <= 1e-10 * np.abs(X).max()


@pytest.mark.parametrize("dim", [2, 3])
def test_refused_beyond_the_limit(dim: int) -> None:
    """θ = 30.5° > φ: no equilibrium; the message names the floating block, its joint and
    what to check."""
    # the rigid-block check's share: sin θ − cos θ tan φ of the weight (1.01 %)
    with pytest.raises(MechanismError, match=r"floating block\(s\) \('block' on 'joint': "
                       r"unbalanced by about 1\.01 % of its load\).*friction angles"):  # fmt: skip
        pf.solve_static(_tilted(dim, 30.5))


def test_refused_when_the_solver_finds_no_pattern() -> None:
    """A Tet10 block at θ = 35° > φ: the state iteration and the Newtons end without an
    answer (no singular pattern on the way); the static analysis says that no equilibrium
    holds the floating block on its joint (the rigid-block check proves it), and gives no
    time-step advice (a time step means nothing there)."""
    from pfeie.verification._models import _groups, _model

    mesh = pf.box(1.0, 1.0, 1.5, 3, 3, 4, cell="tetra10")
    mesh.points[:, 2] -= 0.375
    _groups(mesh, 2)
    m = _model(mesh, pf.Joint(phi=PHI), pf.Elastic(30e9, 0.2, 2400.0), False)
    t = np.radians(35.0)
    m.add_gravity(direction=[np.sin(t), 0.0, -np.cos(t)])
    with pytest.raises(InterfaceError) as info:  # a solver's failure, with what to check
        pf.solve_static(m)
    msg = str(info.value)
    assert "did not converge" in msg and "time step" not in msg
    # the rigid-block check proves that none exists: sin 35° − cos 35° tan 30° = 10.1 %
    assert ("No static equilibrium holds the floating block(s) ('block' on 'joint': "
            "unbalanced by about 10.1 % of its load)") in msg  # fmt: skip


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("theta", [29.0, 30.5, 35.0, 45.0])
def test_rigid_block_check(dim: int, theta: float) -> None:
    """The rigid-block check of the tilted block: the share of its weight W that the
    joint cannot balance is max(0, sin θ − cos θ tan φ) (limit equilibrium: N = W cos θ,
    T ≤ N tan φ); 3D with the tilt along x, a side of the cone's octagon. To 3e-15
    (measured 3e-16: the linear programme's answer is a vertex)."""
    m = _tilted(dim, theta)
    problem = pf.coupling.StaticInterfaceProblem(m, m.system())
    share = problem.rigid_check(m.system().load(0.0)).share
    t = np.radians(theta)
    ref = max(0.0, np.sin(t) - np.cos(t) * np.tan(np.radians(PHI)))
    block = m.body_names().index("block")
    assert share[block] == pytest.approx(ref, abs=3e-15)
    assert np.isnan(np.delete(share, block)).all()  # the supported base: not checked


def _l1_to_octagon(p: np.ndarray, r: float) -> float:
    """The L1 distance from the point p (2,) to the octagon circumscribed about the circle
    of radius r with sides normal to 0°, 45°, …: on each side, |p − q|₁ is piecewise
    linear, so its least value is at a corner or where q_x = p_x or q_y = p_y."""
    th = np.arange(8) * np.pi / 4
    corners = r / np.cos(np.pi / 8) * np.column_stack([np.cos(th + np.pi / 8),
                                                       np.sin(th + np.pi / 8)])  # fmt: skip
    best = np.inf
    for a, b in zip(corners, np.roll(corners, -1, axis=0), strict=True):
        ts = [0.0, 1.0]
        for k in range(2):
            if b[k] != a[k]:
                ts.append(float(np.clip((p[k] - a[k]) / (b[k] - a[k]), 0.0, 1.0)))
        best = min(best, min(float(np.abs(p - (a + t * (b - a))).sum()) for t in ts))
    return best


def test_rigid_block_check_3d_between_the_octagons_sides() -> None:
    """3D, the tilt turned 22.5° in plan, towards a corner of the octagon circumscribed
    about the Coulomb cone's section (which bounds the capacity from outside: never a
    block named that an equilibrium could hold): the share is the L1 distance from the
    load's shear W sin θ (cos 22.5°, sin 22.5°) to the octagon of radius μ W cos θ, over W
    (an independent computation, :func:`_l1_to_octagon`: 8.06 % at θ = 35°, against 10.06 %
    beyond the circle along the load). To 3e-15 (measured 2.6e-16)."""
    m = block_on_base_3d(joint=pf.Joint(phi=PHI), gravity=False, n=3)
    t, a = np.radians(35.0), np.pi / 8
    m.add_gravity(direction=[np.sin(t) * np.cos(a), np.sin(t) * np.sin(a), -np.cos(t)])
    check = pf.coupling.StaticInterfaceProblem(m, m.system()).rigid_check(m.system().load(0.0))
    share = check.share
    p = np.sin(t) * np.array([np.cos(a), np.sin(a)])
    ref = _l1_to_octagon(p, np.cos(t) * np.tan(np.radians(PHI)))
    assert share[m.body_names().index("block")] == pytest.approx(ref, abs=3e-15)


def _side_by_side(kh: float) -> pf.Model:
    """Two blocks side by side on a rock (4 m × 1 m, each 2 m × 1 m): 'A' on a joint of
    φ = 45°, 'B' on one of φ = 10°, a frictionless joint between them, and a
    pseudo-static coefficient k_h along x (towards 'B' when positive)."""
    mesh = pf.rectangle(4.0, 2.0, 8, 4, cell="quad")
    mesh.add_cell_group("rock", lambda x: x[:, 1] < 1)
    mesh.add_cell_group("A", lambda x: (x[:, 1] > 1) & (x[:, 0] < 2))
    mesh.add_cell_group("B", lambda x: (x[:, 1] > 1) & (x[:, 0] > 2))
    on_base = lambda x: np.abs(x[:, 1] - 1) < 1e-9  # noqa: E731
    mesh.add_facet_group("jA", lambda x: on_base(x) & (x[:, 0] < 2 - 1e-9), boundary_only=False)
    mesh.add_facet_group("jB", lambda x: on_base(x) & (x[:, 0] > 2 + 1e-9), boundary_only=False)
    mesh.add_facet_group("jAB", lambda x: (np.abs(x[:, 0] - 2) < 1e-9) & (x[:, 1] > 1 - 1e-9),
                         boundary_only=False)  # fmt: skip
    mat = pf.Elastic(30e9, 0.2, 2500)
    m = pf.Model(mesh, [pf.Block(n, mat) for n in ("rock", "A", "B")],
                 interfaces=[pf.Interface("jA", pf.Joint(phi=45)),
                             pf.Interface("jB", pf.Joint(phi=10)),
                             pf.Interface("jAB", pf.Joint(phi=0.0))])  # fmt: skip
    m.fix("ymin")
    m.add_gravity()
    m.add_inertia([kh * 9.81, 0.0])
    return m


def test_the_failing_block_is_named_among_floating_blocks() -> None:
    """Of two floating blocks, the one that slides is named: pushed towards 'B' (k_h =
    0.3), 'B' pulls away from 'A' (the joint between them carries no tension) and needs
    k_h ≤ tan 10° = 0.176 on its own: unbalanced by (k_h − tan 10°)/√(1 + k_h²) = 11.8 % of
    its load, while 'A' (tan 45° = 1) holds. Pushed the other way, 'B' leans on 'A', and
    both are held: the joint between them carries B's k_h W − μ_B W (limit equilibrium
    of 'B' sliding on its joint; to 1e-6 of it, the interface solver's tolerance, measured
    2e-15)."""
    with pytest.raises(MechanismError) as info:
        pf.solve_static(_side_by_side(0.3))
    msg = str(info.value)
    share = (0.3 - np.tan(np.radians(10.0))) / np.hypot(1.0, 0.3)
    assert f"('B' on 'jB', 'jAB': unbalanced by about {100 * share:.3g} % of its load)" in msg
    assert "'A' on" not in msg and "press on" not in msg  # A does not press on B: B pulls away
    m = _side_by_side(-0.3)
    st = pf.solve_static(m)
    assert st.pairs is not None
    W = 2500 * 9.81 * 2.0  # B's weight per metre
    push = st.pairs.X[m.pairs.of("jAB"), -1].sum()  # compression +
    assert push == pytest.approx(W * (0.3 - np.tan(np.radians(10.0))), rel=1e-6)


def test_blocks_that_press_on_the_failing_one_are_named() -> None:
    """The same blocks, 'B' on φ = 20°, pushed towards 'B' (k_h = 0.3): 'A' (tan 10° =
    0.176) leans on 'B' (tan 20° = 0.364) through the frictionless joint between them, and
    together they carry at most (0.176 + 0.364) W_each against the 0.6 W_each asked: no
    rigid equilibrium, 0.06 W_each short, (0.6 − 0.540)/√(1 + 0.3²) = 5.75 % of one block's
    load; the check puts it on one of them and the message says that the other presses
    on it through 'jAB' (a new user's toe block was named alone, the upper block that
    drove it left out). Pushed the other way, 'B' cannot help 'A' (the joint carries no
    tension): each is named with its own shortfall, (0.3 − tan 10°)/√1.09 = 11.9 % for
    'A', and 'B' holds."""
    def pushed(kh: float) -> str:
        m = _side_by_side(0.0)
        laws = [pf.Interface("jA", pf.Joint(phi=10)), pf.Interface("jB", pf.Joint(phi=20)),
                pf.Interface("jAB", pf.Joint(phi=0.0))]  # fmt: skip
        model = pf.Model(m.input_mesh, m.blocks, interfaces=laws)
        model.fix("ymin")
        model.add_gravity()
        model.add_inertia([kh * 9.81, 0.0])
        with pytest.raises(MechanismError) as info:
            pf.solve_static(model)
        return str(info.value)

    msg = pushed(0.3)
    share = (0.6 - np.tan(np.radians(10.0)) - np.tan(np.radians(20.0))) / np.hypot(1.0, 0.3)
    for failing, other in (("A", "B"), ("B", "A")):
        said = (f"('{failing}' on 'j{failing}', 'jAB': unbalanced by about {100 * share:.3g} % "
                f"of its load)")  # fmt: skip
        if said in msg:
            assert f"Floating blocks press on it ('{other}' on '{failing}' through 'jAB')" in msg
            break
    else:
        raise AssertionError(msg)
    msg = pushed(-0.3)
    own = (0.3 - np.tan(np.radians(10.0))) / np.hypot(1.0, 0.3)
    assert f"('A' on 'jA', 'jAB': unbalanced by about {100 * own:.3g} % of its load)" in msg
    assert "'B' on 'jB'" not in msg and "press on" not in msg


def test_the_message_when_rigid_blocks_could_be_held() -> None:
    """Where the rigid-block check finds an equilibrium but the elastic problem found
    none, the message says so, and says what that means."""
    from pfeie.solvers._static import _floating

    m = _tilted(2, 30.5)
    share = np.full(m.n_bodies, np.nan)
    share[m.body_names().index("block")] = 0.0
    msg = _floating(m, found=False, share=pf.coupling.RigidCheck(share, np.zeros(m.pairs.n)))
    assert msg.startswith("No static equilibrium was found for the floating block(s) "
                          "('block' on 'joint'), although rigid blocks with these joints' "
                          "strengths can be balanced")  # fmt: skip


def test_cohesion_of_a_joint_that_starts_broken_is_flagged(
    caplog: pytest.LogCaptureFixture,
) -> None:
    """A joint given a cohesion and a tensile strength of 10 kPa but starting broken (the
    default) holds a block on 35° with φ = 30° only by friction, so the static analysis
    finds no equilibrium (tan 35° > tan 30°); the same joint intact holds it (c A = 10 kN
    > W (sin 35° − cos 35° tan 30°) = 2.4 kN for the 1 m block of 2400 kg), the joint's
    shear over normal force tan 35° to 1e-13 (equilibrium), its heel pair broken in
    tension. The broken one
    gets a warning that names the interface and says what to set."""
    def tilted(joint: pf.Joint) -> pf.Model:
        m = block_on_base(joint=joint, gravity=False, n=2)
        t = np.radians(35.0)
        m.add_gravity(direction=[np.sin(t), -np.cos(t)])
        return m

    with caplog.at_level("WARNING"):
        broken = tilted(pf.Joint(c=1e4, phi=PHI, tensile=1e4))
    said = ("interface 'joint': cohesion = 10000 Pa and tensile strength = 10000 Pa given, "
            "but the joint starts broken")
    assert said in caplog.text and "initial = 'intact'" in caplog.text
    with pytest.raises(MechanismError):
        pf.solve_static(broken)
    caplog.clear()
    with caplog.at_level("WARNING"):
        intact = tilted(pf.Joint(c=1e4, phi=PHI, tensile=1e4, initial="intact"))
    assert "starts broken" not in caplog.text
    with caplog.at_level("WARNING"):  # the residual cohesion given: the user knows
        tilted(pf.Joint(c=1e4, c_r=1e4, phi=PHI))
    assert "starts broken" not in caplog.text
    st = pf.solve_static(intact)  # held: shear over normal tan 35° > tan φ, by cohesion
    assert st.pairs is not None
    X = st.pairs.X
    assert st.pairs.broken.tolist() == [True, False, False]  # the heel (x = 0), in tension
    assert abs(X[:, 0].sum()) / X[:, 1].sum() == pytest.approx(np.tan(np.radians(35.0)),
                                                               rel=1e-13)  # fmt: skip


@pytest.mark.parametrize(("kh", "kv"), [(0.2, 0.0), (0.3, 0.1), (0.1, -0.1)])
def test_pseudo_static_coefficients_in_a_model_file(
    tmp_path: Path, kh: float, kv: float
) -> None:
    """``loads.pseudo_static = {kh, kv}`` on two blocks cut by a level joint with
    φ = 26.565° (μ = tan φ ≈ 0.5): the joint carries N = W (1 − k_v) and T = k_h W, so the
    static safety factor in summary.json is μ (1 − k_v) / k_h (limit equilibrium; to
    1e-12, measured at round-off); k_h = μ (1 − k_v) is the yield coefficient. A direction that
    is not horizontal is refused."""
    text = SMALL.replace("[[ground_motion]]\nfile = \"pulse.csv\"\nunits = \"g\"\n", "")
    text = text.replace("[analysis]", f"[loads]\npseudo_static = {{ kh = {kh}, kv = {kv} }}\n"
                        "[analysis]\ndynamic = false")  # fmt: skip
    p = _write(tmp_path, text)
    assert main(["run", str(p), "--quiet"]) == 0
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    j = s["static_joints"]["joint"]
    mu = np.tan(np.radians(26.565))
    assert j["safety_factor"] == pytest.approx(mu * (1 - kv) / kh, rel=1e-12)
    assert j["shear_force_N"] / j["normal_force_N"] == pytest.approx(kh / (1 - kv), rel=1e-12)
    bad = _write(tmp_path, text.replace("kv = ", "direction = [1.0, 1.0], kv = "))
    assert main(["run", str(bad), "--quiet"]) == 2


def test_pseudo_static_with_a_tilted_gravity_and_the_report(tmp_path: Path) -> None:
    """With ``gravity_direction = [0.1, -1]`` the default direction of k_h W is +x made
    normal to gravity, so the total body force turns by atan k_h from gravity: on the
    level joint T/N = (0.1 + k_h)/(1 − 0.1 k_h) (0.306122 for k_h = 0.2; to 1e-12). The
    report's loads table lists the pseudo-static load with its resultant."""
    from pfeie.plot import write_report

    text = SMALL.replace("[[ground_motion]]\nfile = \"pulse.csv\"\nunits = \"g\"\n", "")
    text = text.replace("[analysis]", "[loads]\ngravity_direction = [0.1, -1.0]\n"
                        "pseudo_static = { kh = 0.2 }\n[analysis]\ndynamic = false")  # fmt: skip
    p = _write(tmp_path, text)
    assert main(["run", str(p), "--quiet"]) == 0
    j = json.loads((tmp_path / "out" / "summary.json").read_text())["static_joints"]["joint"]
    assert j["shear_force_N"] / j["normal_force_N"] == pytest.approx(0.3 / 0.98, rel=1e-12)
    html = Path(write_report(tmp_path / "out" / "results.h5")).read_text()
    assert "pseudo-static" in html and "k_h = 0.2 along +x" in html


@pytest.mark.parametrize("cell", ["tetra10", "hexahedron"])
def test_safety_factor_of_a_joint_with_round_off_in_its_normals(cell: str) -> None:
    """A level 3D joint whose node heights carry round-off (1e-13 m, as gmsh writes them),
    gravity tilted by θ = 20° along y: every pair shares the interface's frame (one t₁),
    so the joint's shear adds up and FS = tan φ / tan θ = 1.58626 (3e-12; measured 3.3e-13
    and 2.0e-13). With one frame per pair, from the axis least aligned with each pair's
    own normal, t₁ flipped between x and y from pair to pair and FS read 2.19 and 2.13."""
    from pfeie.verification._models import _groups, _model

    mesh = pf.box(1.0, 1.0, 1.5, 4, 4, 6, cell=cell)
    mesh.points[:, 2] -= 0.5
    on = np.abs(mesh.points[:, 2]) < 1e-9
    mesh.points[on, 2] += 1e-13 * np.random.default_rng(1).standard_normal(on.sum())
    _groups(mesh, 2)
    m = _model(mesh, pf.Joint(phi=PHI), pf.Elastic(30e9, 0.2, 2400.0), False)
    t = np.radians(20.0)
    m.add_gravity(direction=[0.0, np.sin(t), -np.cos(t)])
    assert m.pairs is not None
    assert len(np.unique(np.round(m.pairs.frame[:, 0], 9), axis=0)) == 1
    st = pf.solve_static(m)
    assert st.pairs is not None
    P = st.pairs
    fs = m.pair_laws.safety_factor(P.X, P.state == OPEN, P.broken, P.path)[0]
    assert fs == pytest.approx(np.tan(np.radians(PHI)) / np.tan(t), rel=3e-12)


@pytest.mark.parametrize("cell", ["quad8", "quad9", "triangle6"])
def test_cohesion_of_a_touching_end_pair_counts_in_the_safety_factor(cell: str) -> None:
    """A 2 m × 0.5 m block on an existing joint (c_r = 20 kPa, φ = 30°) under gravity
    tilted by 35°: the resultant stays within the base's middle third, so the whole base
    is in compression and the hand computation gives FS = (c B + μ W cos θ)/(W sin θ)
    = 3.786565. On quadratic faces the pair at the joint's upslope end carries no force
    and parts by 3e-8 m (the corner effect of node-to-node pairs); counted as cracked, its
    c A dropped out of the capacity and FS read 3.724856 (−1.6 %). Touching pairs (open by
    less than OPEN_CRACK_MIN_M, the threshold of the open share) keep their cohesion: FS
    equals the hand value to 1e-14 (measured 1.1e-15), in the law and in the summary."""
    from pfeie._job import _static_joints
    from pfeie.interface import OPEN_CRACK_MIN_M

    c, theta, B, H = 2e4, np.radians(35.0), 2.0, 0.5
    m = block_on_base(joint=pf.Joint(phi=PHI, c_r=c, initial="broken"), gravity=False,
                      width=B, height=H, n=8, ny=2, cell=cell)  # fmt: skip
    m.add_gravity(direction=[np.sin(theta), -np.cos(theta)])
    st = pf.solve_static(m)
    assert st.pairs is not None
    P = st.pairs
    gap = P.w[P.state == OPEN, -1]
    assert gap.size == 1 and 0.0 < gap[0] < 1e-2 * OPEN_CRACK_MIN_M  # the touching end pair
    W = 2400.0 * 9.81 * B * H
    hand = (c * B + np.tan(np.radians(PHI)) * W * np.cos(theta)) / (W * np.sin(theta))
    fs = m.pair_laws.safety_factor(P.X, P.state == OPEN, P.broken, P.path,
                                   opening=P.w[:, -1])[0]  # fmt: skip
    assert fs == pytest.approx(hand, rel=1e-14)
    assert _static_joints(m, st)["joint"]["safety_factor"] == pytest.approx(hand, rel=1e-14)
    cracked = m.pair_laws.safety_factor(P.X, P.state == OPEN, P.broken, P.path)[0]
    assert cracked < hand * (1 - 0.01)  # the cohesion of the end pair, when it counts open


@pytest.mark.parametrize(("cell", "n"), [("quad8", 8), ("quad", 4)])
def test_a_lifting_end_on_a_cohesive_broken_joint(cell: str, n: int) -> None:
    """A 2 m × 1 m block (n × 2 cells) on an existing joint with c_r = 20 kPa, φ = 30°,
    gravity tilted by 35°: the resultant leaves the middle third (e = 0.35 m > B/6), so
    the base lifts over its last centimetres, far from sliding (FS 2.3 by hand). Without
    the cohesion ramp a broken pair's capacity jumped from c A to 0 as it parted, the
    pairs at the edge of the lift would have had to touch with no normal force while
    carrying shear, and no state pattern solved the problem (each leaves a pair in
    tension or penetrating; both meshes failed). With it (pfeie.interface.cohesion_ramp)
    the analysis holds the block: ΣN = W cos θ and ΣT = W sin θ to 1e-14 (measured
    1.1e-15), every pair within its ramped cone, and the pairs on the ramp carry their
    shear on a normal force below κ c A."""
    from pfeie.interface import COHESION_RAMP, OPEN, cohesion_ramp

    c, t = 2e4, np.radians(35.0)
    m = block_on_base(joint=pf.Joint(phi=PHI, c_r=c, initial="broken"), gravity=False,
                      width=2.0, height=1.0, n=n, ny=2, cell=cell)  # fmt: skip
    m.add_gravity(direction=[np.sin(t), -np.cos(t)])
    st = pf.solve_static(m)
    assert st.pairs is not None and m.pairs is not None
    P = st.pairs
    X, W = P.X, 2400.0 * 9.81 * 2.0
    assert X[:, -1].sum() == pytest.approx(W * np.cos(t), rel=1e-14)
    assert -X[:, 0].sum() == pytest.approx(W * np.sin(t), rel=1e-14)
    cA, mu, tA = m.pair_laws.strength(P.broken, P.path)
    on, tau, _ = cohesion_ramp(cA, mu, tA, X[:, -1], P.broken)
    cap = np.where(on, tau, cA + mu * np.maximum(X[:, -1], 0.0))
    closed = P.state != OPEN
    # within the cone to the solver's tolerance (1e-8 of the forces' scale)
    assert (np.abs(X[closed, 0]) <= cap[closed] + 1e-8 * np.abs(X).max()).all()
    assert (on & closed).any()  # a pair at the edge of the lift touches, on the ramp
    assert (X[on & closed, -1] < COHESION_RAMP * cA[on & closed]).all()


@pytest.mark.parametrize(("cell", "n"), [("quad8", 8), ("quad", 4)])
def test_the_dynamics_hold_a_static_state_on_the_cohesion_ramp(cell: str, n: int) -> None:
    """The block of the test above, its heel pairs on the residual cohesion's ramp in the
    static state, analysed dynamically from that state under the same constant loads for
    0.2 s (Δt = 1 ms, the velocity-level law, whose strengths are the forces' times h):
    an equilibrium of the static law is one of the dynamic law, so the block stays still
    (its centroid within 5e-16 m; measured 5.1e-17) and the pairs on the ramp keep their
    forces (to 1e-9 of the largest force; measured 1.9e-10), without a fallback."""
    from pfeie.interface import cohesion_ramp

    t = np.radians(35.0)
    m = block_on_base(joint=pf.Joint(phi=PHI, c_r=2e4, initial="broken"), gravity=False,
                      width=2.0, height=1.0, n=n, ny=2, cell=cell)  # fmt: skip
    m.add_gravity(direction=[np.sin(t), -np.cos(t)])
    st = pf.solve_static(m)
    assert st.pairs is not None
    cA, mu, tA = m.pair_laws.strength(st.pairs.broken, st.pairs.path)
    on = cohesion_ramp(cA, mu, tA, st.pairs.X[:, -1], st.pairs.broken)[0]
    assert on.any()
    res = pf.Dynamic(m, dt=1e-3).run(0.2, start=st)
    assert res.completed and int(res.solver["fallbacks"].sum()) == 0
    assert np.abs(res.rigid[:, 1] - res.rigid[0, 1]).max() <= 5e-16
    X = res.final.pairs.X
    assert np.abs(X - st.pairs.X).max() <= 1e-9 * np.abs(st.pairs.X).max()


def test_safety_factor_sums_the_shears_as_global_vectors() -> None:
    """Two pairs of one 3D joint whose frames differ by a quarter turn about the normal
    (as on a joint that turns, where a pair takes its own axis): the same global shear of
    10 N along x reads (10, 0) and (0, −10) in their frames. Added as global vectors the
    shear is 20 N and FS = (2 × 100 N × tan 45°)/20 = 10; adding local components would
    give 200/14.14."""
    from pfeie.interface import MohrCoulomb, PairLaws

    law = PairLaws.from_interfaces(np.ones(2), np.zeros(2, dtype=np.int64),
                                   [MohrCoulomb(phi=45.0)], 3)  # fmt: skip
    frames = np.array([np.eye(3), [[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]])
    X = np.array([[10.0, 0.0, 100.0], [0.0, -10.0, 100.0]])
    no = np.zeros(2, dtype=bool)
    assert law.safety_factor(X, no, ~no, np.zeros(2), frames)[0] == pytest.approx(10.0, 1e-15)
    assert law.safety_factor(X, no, ~no, np.zeros(2))[0] == pytest.approx(200 / np.sqrt(200))


# test_study's two 2 m x 1 m rows (a fixed base, a block on a joint), the block's
# upstream face (x = 0) a line group of its own
WET_NAMES = {**NAMES, 5: (1, "upstream")}
WET_ELEMENTS = [*ELEMENTS, (5, 1, 5, [4, 7])]
WET_MODEL = """
[mesh]
file = "wet.msh"
[materials.concrete]
E = 30e9
nu = 0.2
rho = 2400.0
[blocks]
base = "concrete"
block = "concrete"
[interfaces.joint]
friction_angle = 40.0
[[supports]]
group = "bottom"
[loads]
pseudo_static = { kh = 0.2, kv = 0.1 }
[[loads.hydrostatic]]
groups = ["upstream"]
water_level = 2.0
[[loads.westergaard]]
groups = ["upstream"]
water_level = 2.0
[analysis]
dynamic = false
[output]
folder = "out"
"""


def test_pseudo_static_load_includes_the_hydrodynamic_force(tmp_path: Path) -> None:
    """A 2 m × 1 m block on a level joint (φ = 40°), water 1 m deep on its vertical
    upstream face, ``pseudo_static = {kh = 0.2, kv = 0.1}`` with Westergaard's added mass:
    per metre the joint carries N = W (1 − k_v) and T = T₀ + k_h (W + W_a), T₀ = ρ_w g h²/2
    the hydrostatic thrust and W_a = (7/12) ρ_w g h² Westergaard's hydrodynamic force per
    unit k_h (EM 1110-2-2100; on this vertical face the added mass acts along x only,
    so k_v adds nothing on the water). To 2e-15 (measured 2.2e-16). The Python API's
    ``Model.add_inertia`` gives the same load; before, the coefficients loaded the blocks
    only (T = T₀ + k_h W, 11 % less here). The report lists the load on the added mass."""
    from pfeie.plot import write_report
    from test_robustness import msh22

    msh22(tmp_path / "wet.msh", NODES, WET_ELEMENTS, WET_NAMES)
    p = tmp_path / "model.toml"
    p.write_text(WET_MODEL)
    assert main(["run", str(p), "--quiet"]) == 0
    j = json.loads((tmp_path / "out" / "summary.json").read_text())["static_joints"]["joint"]
    g, rho, rho_w, h, kh, kv = 9.81, 2400.0, 1000.0, 1.0, 0.2, 0.1
    W, T0, Wa = rho * g * 2.0, rho_w * g * h**2 / 2, 7.0 / 12.0 * rho_w * g * h**2
    assert j["normal_force_N"] == pytest.approx(W * (1 - kv), rel=2e-15)  # measured 2.2e-16
    assert j["shear_force_N"] == pytest.approx(T0 + kh * (W + Wa), rel=2e-15)  # measured 0
    html = Path(write_report(tmp_path / "out" / "results.h5")).read_text()
    assert "all blocks and the reservoirs" in html
    # the same load from the Python API
    from pfeie.io import load_job

    model = load_job(p).model
    f = model.inertia_load([kh * g, 0.0]).reshape(-1, 2).sum(axis=0)  # both blocks
    assert f[0] == pytest.approx(kh * (2 * W + Wa), rel=2e-15) and abs(f[1]) < 1e-15 * W
