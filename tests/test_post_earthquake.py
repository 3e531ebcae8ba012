"""The post-earthquake static state (``pf.solve_static(model, damage=...)``; the run's
``post_earthquake`` summary): the static loads on the joints as an earthquake left them,
the pairs it broke at their residual strength, an uplift's crack at full headwater.

Reference: the limit equilibrium of the dam block of tests/test_uplift.py (10 m wide,
20 m tall, on a base joint at y = 2 m, the reservoir h_w above the base, no tailwater),
cracked from the heel over a length a by the earthquake (USACE EM 1110-2-6053 §7; FERC
Engineering Guidelines, Chapter III): the crack at full headwater, the head linear from
h_w at its tip to zero at the toe, so

    U = ρ_w g h_w (a + (B − a)/2),   T = ρ_w g h_w² / 2,   W = ρ_c g B H,
    FS = (c A_intact + (W − U) tan φ) / T

with the residual friction angle equal to the intact one and no residual cohesion, while
every pair is in compression (then Σ μ N⁺ = μ (W − U) by vertical equilibrium)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import h5py
import numpy as np
import pytest

import pfeie as pf
from pfeie.cli import main
from pfeie.errors import MechanismError, ModelError
from pfeie.interface import OPEN, PairState
from test_uplift import RHO_W, B, G, H, dam

C, PHI = 0.3e6, 40.0


def _damage(model: pf.Model, a: float) -> PairState:
    """The pairs of the base joint within a (m) of the heel broken, as an earthquake
    leaves them (no slip path)."""
    assert model.pairs is not None
    st = model.pair_laws.initial_state(model.dim)
    st.broken = model.pairs.x[:, 0] <= a + 1e-9
    return st


@pytest.mark.parametrize("a", [0.0, 3.0, 6.0])
def test_post_earthquake_fs_against_limit_equilibrium(a: float) -> None:
    """FS of the cracked base against the closed form, to 1e-14 (measured 0.8e-15 to
    1.6e-15: the uplift's kink at the crack tip is a corner node, where Simpson's rule on
    the Q8 base is exact, and the sums of the pair forces balance the loads to
    round-off); the crack of the uplift is a; every pair is in compression; a = 0 is the
    static state itself."""
    hw = 12.0
    joint = pf.Joint(c=C, phi=PHI, tensile=0.2e6, initial="intact")  # φ_r = φ, c_r = 0
    model, _ = dam(hw, joint)
    P = model.pairs
    assert P is not None
    damage = _damage(model, a) if a > 0 else None
    post = pf.solve_static(model, damage=damage)
    assert post.pairs is not None
    assert len(post.cracks) == 1 and post.cracks[0] == pytest.approx(a, abs=1e-12)
    X = post.pairs.X
    assert (X[:, -1] > 0).all()  # every pair in compression: the closed form holds
    intact = ~post.pairs.broken
    W = 2400.0 * G * B * H
    U = RHO_W * G * hw * (a + (B - a) / 2)
    T = RHO_W * G * hw**2 / 2
    exact = (C * P.area[intact].sum() + (W - U) * np.tan(np.radians(PHI))) / T
    fs = model.pair_laws.safety_factor(X, post.pairs.state == OPEN, post.pairs.broken,
                                       post.pairs.path, P.frame)  # fmt: skip
    assert fs[0] == pytest.approx(exact, rel=1e-14)
    assert float(X[:, -1].sum()) == pytest.approx(W - U, rel=1e-14)
    if a == 0.0:  # no damage: the static state, to the bit
        np.testing.assert_array_equal(X, pf.solve_static(model).pairs.X)  # type: ignore[union-attr]


def test_a_base_broken_through_with_a_low_residual_friction_slides() -> None:
    """The whole base broken, φ_r = 20°, full headwater under it (U = ρ_w g h B): at 12 m
    of water (W − U) tan φ_r = (4.709 − 1.177) MN × 0.364 = 1.29 MN holds T = 0.71 MN (FS
    1.82); at 19 m, 1.04 MN against T = 1.77 MN (FS 0.58): no equilibrium, a
    MechanismError that names the floating block and its joint, and the share of its load
    that no forces within the joint's strength balance (the rigid-block check):
    (T − (W − U) tan φ_r) / ‖(T, W − U)‖ = 21.9 %."""
    joint = pf.Joint(c=C, phi=PHI, tensile=0.2e6, phi_r=20.0, initial="intact")
    model, _ = dam(12.0, joint)
    post = pf.solve_static(model, damage=_damage(model, B))
    assert len(post.cracks) == 1 and post.cracks[0] == pytest.approx(B)
    model, _ = dam(19.0, joint)
    with pytest.raises(MechanismError, match="'dam' on 'base'") as err:
        pf.solve_static(model, damage=_damage(model, B))
    # the message speaks of the damage, not of a joint that should start intact (a new
    # user was told to set initial = "intact" on joints that had started so)
    assert "This is the post-earthquake state" in str(err.value)
    assert "full headwater" in str(err.value) and 'initial = "intact"' not in str(err.value)
    W, U, T = 2400.0 * G * B * H, RHO_W * G * 19.0 * B, RHO_W * G * 19.0**2 / 2
    share = (T - (W - U) * np.tan(np.radians(20.0))) / np.hypot(T, W - U)
    assert f"('dam' on 'base': unbalanced by about {100 * share:.3g} % of its load)" in str(
        err.value)  # fmt: skip


def test_a_damage_of_another_model_is_refused() -> None:
    model, _ = dam(12.0, pf.Joint(c=C, phi=PHI, initial="intact"))
    with pytest.raises(ModelError, match="the damage is a state of 3 pairs; this model has"):
        pf.solve_static(model, damage=PairState.initial(np.zeros(3, dtype=bool),
                                                        np.zeros(3), 2))  # fmt: skip


MODEL = """
title = "a block on a bonded joint, shaken"
[mesh]
file = "{mesh}"
[materials.concrete]
E = 30e9
nu = 0.2
rho = 2400.0
[blocks]
rock = "concrete"
dam = "concrete"
[interfaces.joint]
cohesion = 5e3
friction_angle = 35.0
tensile_strength = 5e3
residual_friction_angle = 30.0
initial = "intact"
[[supports]]
group = "bottom"
[loads]
gravity = 9.81
[[ground_motion]]
file = "rec.csv"
units = "g"
scale = {scale}
[analysis]
dt = 0.005
[output]
folder = "out"
paraview = false
"""


def _run(tmp: Path, scale: float, *runs: list[str]) -> dict[str, Any]:
    """The summary of the model run with the record scaled by ``scale`` (``runs``: the
    options of each run, one after the other)."""
    mesh = Path(__file__).parent / "data" / "two_blocks_v41.msh"
    # two cycles of a 2 Hz sine at 1 g
    t = np.arange(0.0, 1.0 + 1e-9, 0.005)
    (tmp / "rec.csv").write_text("".join(f"{a:.4f},{b:.6f}\n" for a, b in
                                         zip(t, np.sin(4 * np.pi * t), strict=True)))  # fmt: skip
    (tmp / "model.toml").write_text(MODEL.format(mesh=mesh, scale=scale))
    for options in runs or ([],):
        assert main(["run", str(tmp / "model.toml"), "--quiet", *options]) == 0
    return json.loads((tmp / "out" / "summary.json").read_text())


def test_a_run_reports_the_post_earthquake_state(tmp_path: Path) -> None:
    """A 2 m × 1 m block (47 kN) on a bonded joint (c = 5 kPa, σ_t = 5 kPa, φ = 35°)
    shaken at 1 g (47 kN against a capacity of 2 m × 5 kPa + tan 35° × 47 kN = 43 kN): the
    joint breaks through; the post-earthquake FS is the residual friction's, tan 30° × N / T
    with T = 0 (no static shear): ∞, printed as such; the results file holds the state,
    every pair broken; a record scaled to almost nothing breaks nothing, and the
    post-earthquake state is the static one (FS ∞ too, all intact)."""
    s = _run(tmp_path, 1.0)
    post = s["post_earthquake"]["joints"]["joint"]
    assert s["joints"]["joint"]["broken_share"] == pytest.approx(1.0)
    assert post["broken_share"] == pytest.approx(1.0)
    assert post["normal_force_N"] == pytest.approx(s["static_joints"]["joint"]["normal_force_N"],
                                                   rel=1e-9)  # fmt: skip
    with h5py.File(tmp_path / "out" / "results.h5") as f:
        assert f["post_earthquake/broken"][()].all()
        assert not f["static/broken"][()].any()
    text = (tmp_path / "out" / "summary.txt").read_text()
    assert "post-EQ joint    FS ∞, normal" in text and "broken 100 %" in text
    # the base in compression as the static line reads it: all of it in contact, the
    # normal resultant under the block's centre of gravity, as before the record (no shear
    # is left to move it)
    line = next(x for x in text.splitlines() if x.strip().startswith("post-EQ joint"))
    at = post["normal_resultant_at_m"]
    assert post["contact_share"] == pytest.approx(1.0)
    assert at == pytest.approx(s["static_joints"]["joint"]["normal_resultant_at_m"], abs=1e-9)
    assert ("in contact 100 %" in line
            and "normal resultant at (" + ", ".join(f"{v:.4g}" for v in at) + ") m" in line)
    # a run of 0.4 s extended to 1 s by --resume: the post-earthquake state of the
    # extension's last state (written over the 0.4 s one), the same bits
    parts = tmp_path / "parts"
    parts.mkdir()
    s2 = _run(parts, 1.0, ["--duration", "0.4"], ["--resume", "--duration", "1.0"])
    assert s2["post_earthquake"] == s["post_earthquake"]
    calm = tmp_path / "calm"
    calm.mkdir()
    s = _run(calm, 1e-4)
    assert s["post_earthquake"]["joints"]["joint"]["broken_share"] == 0.0
    assert s["post_earthquake"]["joints"]["joint"] == s["static_joints"]["joint"]


def test_no_post_earthquake_state_for_a_block_that_slid_far(tmp_path: Path) -> None:
    """The block pushed at 1 g for 1 s: the bonded joint breaks through, the block slides
    on its residual friction at (1 − tan 30°) g, about ½ × 0.42 g × (1 s)² = 2 m, far
    beyond a tenth of its 2 m (POST_EQ_MOVE_MAX): the post-earthquake state of the
    undeformed geometry would describe a block that is no longer there, so it is not
    computed, and the summary and the report say why (a new user's column that toppled,
    123° and 4.25 m, read FS ∞ on its joint)."""
    from pfeie.plot import write_report

    mesh = Path(__file__).parent / "data" / "two_blocks_v41.msh"
    t = np.arange(0.0, 1.0 + 1e-9, 0.005)
    (tmp_path / "rec.csv").write_text("".join(f"{a:.4f},1.0\n" for a in t))
    (tmp_path / "model.toml").write_text(MODEL.format(mesh=mesh, scale=1.0))
    assert main(["run", str(tmp_path / "model.toml"), "--quiet"]) == 0
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    moved = s["bodies"]["dam"]["residual_displacement_m"]
    assert moved > 0.1 * 2.0  # the block's residual motion, far beyond a tenth of its size
    why = s["post_earthquake"]["skipped"]
    assert why.startswith("block 'dam' rotated ") and f"moved {moved:.3g} m (2 m across)" in why
    assert "joints" not in s["post_earthquake"]
    text = (tmp_path / "out" / "summary.txt").read_text()
    assert "post-EQ      not computed: block 'dam'" in text
    with h5py.File(tmp_path / "out" / "results.h5") as f:
        assert "post_earthquake" not in f
    html = write_report(tmp_path / "out" / "results.h5", tmp_path / "report.html")
    assert "not computed (large residual motion)" in Path(html).read_text()


def test_a_joint_that_starts_broken_is_not_cracked_through_by_the_record() -> None:
    """A pre-existing joint (initial = "broken", no cohesion, φ = 40°) under the uplift,
    and a record that broke nothing, as a record of zeros leaves it: the post-earthquake
    state is the static state (the tester's 3D dam read its normal force 23.8 % and its FS
    24 % low: every pair of the joint counted cracked, the whole base at full headwater).
    Closed form: every pair in compression, N = W − U with U = ρ_w g h_w B / 2 (the linear
    uplift of an uncracked base), to 1e-14 (the limit equilibrium above), and the same
    bits as the static state."""
    hw = 12.0
    model, _ = dam(hw, pf.Joint(phi=PHI, initial="broken"))
    assert model.pairs is not None and model.pair_laws.initially_broken.all()
    static = pf.solve_static(model)
    assert static.pairs is not None
    post = pf.solve_static(model, damage=static.pairs)
    assert post.pairs is not None and post.cracks == static.cracks
    np.testing.assert_array_equal(post.pairs.X, static.pairs.X)
    W, U = 2400.0 * G * B * H, RHO_W * G * hw * B / 2
    assert (post.pairs.X[:, -1] > 0).all()
    assert float(post.pairs.X[:, -1].sum()) == pytest.approx(W - U, rel=1e-14)
