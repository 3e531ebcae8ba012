"""Uplift in joints: the distribution of USACE EM 1110-2-2200 §3-3 (linear from headwater
to tailwater, drains, full headwater in the crack), the static crack found with its
uplift, the policies during shaking, the model file.

References: the levels by hand from the guideline's formulas; the static state against
the equilibrium of the dam block (closed forms of the hydrostatic thrust and the uplift
force and moment: the pair forces are effective forces, N' = W − U)."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import pfeie as pf
from pfeie._job import _static_joints
from pfeie.cli import main
from pfeie.coupling import StaticInterfaceProblem
from pfeie.errors import MechanismError, ModelError
from pfeie.interface import OPEN
from pfeie.model import Uplift
from pfeie.solvers._static import solve_pairs
from pfeie.verification._models import block_on_base

RHO_W, G = 1000.0, 9.81
ROOT = Path(__file__).resolve().parents[1]
B, H, Z0 = 10.0, 20.0, 2.0  # dam width and height (m), base joint elevation (m)


def test_levels_by_the_guideline() -> None:
    """h(s) by hand: linear H_w → H_t; drains at s_d with E: h_d = H_t + (1 − E)(H_w −
    H_t)(L − s_d)/L; a crack short of the drains: H_w to the tip, then to h_d; a crack past
    them: H_w to the tip, then linear to H_t (drains no longer work)."""
    s = np.array([0.0, 2.0, 5.0, 10.0])
    up = Uplift("base", headwater=30.0, tailwater=5.0)
    np.testing.assert_allclose(up.level(s, 10.0, 0.0, 0.0), [30.0, 25.0, 17.5, 5.0])
    dr = Uplift("base", headwater=30.0, tailwater=5.0, drains=2.0, efficiency=0.5)
    hd = 5.0 + 0.5 * 25.0 * 8.0 / 10.0  # 15 m
    np.testing.assert_allclose(dr.level(s, 10.0, 0.0, 0.0),
                               [30.0, hd, hd + (5.0 - hd) * 3.0 / 8.0, 5.0])  # fmt: skip
    np.testing.assert_allclose(dr.level(s, 10.0, 1.0, 0.0),
                               [30.0, hd, hd + (5.0 - hd) * 3.0 / 8.0, 5.0])  # fmt: skip
    np.testing.assert_allclose(dr.level(np.array([0.0, 1.0, 1.5, 2.0]), 10.0, 1.0, 0.0),
                               [30.0, 30.0, 30.0 + (hd - 30.0) * 0.5, hd])  # fmt: skip
    np.testing.assert_allclose(dr.level(s, 10.0, 5.0, 0.0), [30.0, 30.0, 30.0, 5.0])
    # no tailwater: the level of the toe (zero pressure there)
    np.testing.assert_allclose(Uplift("b", 30.0).level(s, 10.0, 0.0, 2.0)[-1], 2.0)
    for bad in ({"efficiency": 1.5}, {"shaking": "half"}, {"upstream": "north"},
                {"tailwater": 40.0}, {"drains": -1.0}):  # fmt: skip
        with pytest.raises(ModelError):
            Uplift("base", 30.0, **bad)  # type: ignore[arg-type]


def test_unknown_keyword_names_the_python_keyword() -> None:
    """``add_uplift`` given the model file's ``drain_efficiency`` (or a misspelt keyword)
    says which keyword it takes, instead of the dataclass's bare ``TypeError``."""
    with pytest.raises(ModelError, match="the Python keyword is 'efficiency'"):
        dam(10.0, pf.Joint(phi=45.0), drains=2.0, drain_efficiency=0.5)
    with pytest.raises(ModelError, match=r"unknown keyword 'tail'.*tailwater"):
        dam(10.0, pf.Joint(phi=45.0), tail=2.0)


def dam(hw: float, joint: pf.Joint, **uplift: object) -> tuple[pf.Model, float]:
    """A 10 m x 20 m concrete block (Q8) on a rock block on a base joint at y = 2 m, the
    reservoir at hw (m above the base) on its upstream face x = 0, uplift in the joint."""
    mesh = pf.rectangle(B, H + Z0, 10, 22, cell="quad8")
    mesh.add_cell_group("rock", lambda x: x[:, 1] < Z0)
    mesh.add_cell_group("dam", lambda x: x[:, 1] > Z0)
    mesh.add_facet_group("base", lambda x: np.abs(x[:, 1] - Z0) < 1e-9, boundary_only=False)
    mesh.add_facet_group("upstream", lambda x: (x[:, 0] < 1e-9) & (x[:, 1] > Z0 - 1e-9))
    concrete = pf.Elastic(30e9, 0.2, 2400.0)
    model = pf.Model(mesh, [pf.Block("rock", concrete), pf.Block("dam", concrete)],
                     interfaces=[pf.Interface("base", joint)])  # fmt: skip
    model.fix("ymin")
    model.add_gravity()
    level = Z0 + hw
    model.add_pressure("upstream", lambda x: RHO_W * G * np.maximum(level - x[..., 1], 0.0))
    model.add_uplift("base", headwater=level, **uplift)  # type: ignore[arg-type]
    return model, level


def base_resultant(model: pf.Model, st: pf.StaticResult) -> tuple[float, float, float]:
    """The contact force on the dam (F_x, F_y) and its moment about the base centroid."""
    P = model.pairs
    assert P is not None and st.pairs is not None
    F, M = P.resultants(st.pairs.X)
    sign = 1.0 if P.frame[P.of("base")[0], -1, 1] > 0 else -1.0  # side b the dam?
    return sign * F[0, 0], sign * F[0, 1], sign * M[0, 0]


def test_static_uplift_equilibrium() -> None:
    """Uncracked (resultant inside the kern: e = 0.92 m < B/6), no tailwater, 12 m of
    water: the base carries F_x = −ρ g h²/2, F_y = W − U with U = ρ g h B/2, and the
    moment T h/3 + U B/6 about its centroid (the uplift triangle's centroid at B/3 from
    the heel); to 1e-12 (Simpson's rule on the Q8 base is exact for the linear uplift:
    round-off, measured 3.5e-14; the margin is for other BLAS builds). Without uplift
    F_y = W."""
    hw = 12.0
    model, _ = dam(hw, pf.Joint(phi=45.0))
    st = pf.solve_static(model)
    W = 2400.0 * G * B * H
    T, U = RHO_W * G * hw**2 / 2, RHO_W * G * hw * B / 2
    fx, fy, mz = base_resultant(model, st)
    assert st.cracks == (0.0,)
    assert fx == pytest.approx(-T, rel=1e-12)
    assert fy == pytest.approx(W - U, rel=1e-12)
    assert mz == pytest.approx(T * hw / 3 + U * B / 6, rel=1e-12)
    assert st.uplift is not None
    assert st.uplift.max() == pytest.approx(RHO_W * G * hw, rel=1e-12)
    plain, _ = dam(hw, pf.Joint(phi=45.0))
    plain.uplifts.clear()
    assert base_resultant(plain, pf.solve_static(plain))[1] == pytest.approx(W, rel=1e-12)


def test_drains_and_tailwater() -> None:
    """Drains 2 m from the heel at E = 0.5 and 3 m of tailwater: U is the area under the
    piecewise linear head (closed form) times ρ g, to 1e-12 (the kink at the drains is a
    corner node: exact but for round-off)."""
    hw, tw, sd, E = 12.0, 3.0, 2.0, 0.5
    model, _ = dam(hw, pf.Joint(phi=45.0), tailwater=Z0 + tw, drains=sd, efficiency=E)
    st = pf.solve_static(model)
    hd = tw + (1 - E) * (hw - tw) * (B - sd) / B
    U = RHO_W * G * (0.5 * (hw + hd) * sd + 0.5 * (hd + tw) * (B - sd))
    W = 2400.0 * G * B * H
    fy = base_resultant(model, st)[1]
    # the tailwater's pressure on the downstream face is not applied here: only the uplift
    assert fy == pytest.approx(W - U, rel=1e-12)


def test_cracked_base_gets_full_headwater() -> None:
    """A joint without tensile strength under a high reservoir (19 m on a 10 m wide
    block): the heel opens; the static analysis settles the crack and its uplift together.
    Every open pair from the heel carries full headwater; the crack equals the open part;
    the vertical equilibrium holds with U = ρ g h (c + (B − c)/2) to 1e-12 when the crack
    tip is a corner node (kink integrated exactly by Simpson's rule; measured: c = 7 m, a
    corner, error 0)."""
    hw = 19.0
    model, _ = dam(hw, pf.Joint(phi=45.0, initial="broken"))
    st = pf.solve_static(model)
    P = model.pairs
    assert P is not None and st.pairs is not None and st.uplift is not None
    c = st.cracks[0]
    assert 0.5 < c < B  # measured 7 m
    idx = P.of("base")
    s = P.x[idx, 0]
    open_ = st.pairs.state[idx] == OPEN
    assert np.all(open_[s < c - 1e-9]) and np.all(s[open_] <= c + 1e-9)
    np.testing.assert_allclose(st.uplift[idx][s <= c], RHO_W * G * hw, rtol=1e-12)
    U = RHO_W * G * hw * (c + (B - c) / 2)
    W = 2400.0 * G * B * H
    on_corner = abs(c / 1.0 - round(c / 1.0)) < 1e-9  # Q8 corner nodes every 1 m
    fy = base_resultant(model, st)[1]
    assert fy == pytest.approx(W - U, rel=1e-12 if on_corner else 2e-3)
    assert model.uplift_pressure(st.pairs.state == OPEN)[1] == [c]  # settled


def test_policies_follow_the_opening_pairs() -> None:
    """The excitation's uplift load: 'keep' stays pre-earthquake; 'full' gives the pairs
    that open during the shaking in the crack from the heel ρ g (H_w − z) (here the
    static crack of 7 m grows to 8 m: the pairs at 7.5 and 8 m), and leaves the toe that
    lifts apart from it at its pre-earthquake pressure (the reservoir's water does not
    reach it; before version 0.3.21 it got ρ g (H_w − z) too); 'zero' takes the pressure
    of every pair that opens; the crack open before the shaking keeps its uplift; a closed
    pair its pre-earthquake value."""
    from pfeie.dynamics import Excitation

    for policy in ("keep", "full", "zero"):
        model, level = dam(19.0, pf.Joint(phi=45.0, initial="broken"), shaking=policy)
        st = pf.solve_static(model)
        P = model.pairs
        assert P is not None and st.pairs is not None and st.uplift is not None
        assert st.cracks == (7.0,)
        system = model.system(lumped_mass=True)
        ex = Excitation(model, system, uplift=st.uplift, open0=st.pairs.state == OPEN)
        base = ex.load(0.0)
        now = st.pairs.state == OPEN
        idx = P.of("base")
        s = P.x[idx, 0]
        toe, grow = idx[s == s.max()], idx[(s > 7.0) & (s < 8.0 + 1e-9)]
        assert toe.size == 1 and grow.size == 2
        for opened in (toe, np.concatenate([toe, grow])):
            new = np.zeros_like(now)
            new[opened] = True
            ex.follow(now | new)
            p = st.uplift.copy()
            if policy == "full":
                full = grow if opened.size > 1 else opened[:0]
                p[full] = RHO_W * G * (level - P.x[full, 1])
            elif policy == "zero":
                p[opened] = 0.0
            want = base - model.uplift_load(st.uplift)[system.free] + \
                model.uplift_load(p)[system.free]  # fmt: skip
            np.testing.assert_allclose(ex.load(0.0), want, rtol=0, atol=1e-9 * np.abs(base).max())


def test_dynamic_keep_holds_the_static_state() -> None:
    """Without shaking, a run from the cracked static state stays there (the excitation
    carries the same uplift as the static solve): u within 1e-9 of the static u."""
    model, _ = dam(19.0, pf.Joint(phi=45.0, initial="broken"))
    st = pf.solve_static(model)
    res = pf.Dynamic(model, 0.01).run(n_steps=20, start=st)
    assert res.final is not None
    drift = np.abs(res.final.kin.u - st.u.ravel()[model.system().free]).max()
    assert drift < 1e-9 * np.abs(st.u).max()


def test_model_file_and_report(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """[[loads.uplift]] through the command line: the results file holds the static
    uplift and the crack; the report shows the analysis, the record's intensity measures
    (PGA as in the record), the static state with the uplift force Σ p A and the figures
    of the mesh and the input motion; a wrong interface name is an input error naming
    the key."""
    from test_robustness import msh22

    nodes = [(x, y, 0) for y in (0, 1, 2) for x in (0, 1, 2)]
    names = {1: (2, "rock"), 2: (2, "dam"), 3: (1, "bottom"), 4: (1, "base")}
    els = [(1, 1, 3, [1, 2]), (2, 1, 3, [2, 3]), (3, 1, 4, [4, 5]), (4, 1, 4, [5, 6]),
           (10, 3, 1, [1, 2, 5, 4]), (11, 3, 1, [2, 3, 6, 5]),
           (12, 3, 2, [4, 5, 8, 7]), (13, 3, 2, [5, 6, 9, 8])]  # fmt: skip
    msh22(tmp_path / "m.msh", nodes, els, names)
    text = """
[mesh]
file = "m.msh"
[materials.c]
E = 30e9
nu = 0.2
rho = 2400.0
[blocks]
rock = "c"
dam = "c"
[interfaces.base]
friction_angle = 45.0
[[supports]]
group = "bottom"
[loads]
gravity = 9.81
[[loads.uplift]]
interface = "INTERFACE"
headwater = 3.0
drains = 0.5
drain_efficiency = 0.4
[[ground_motion]]
file = "pulse.csv"
units = "g"
[analysis]
dt = 0.01
duration = 0.2
[output]
folder = "out"
"""
    (tmp_path / "pulse.csv").write_text("time,acc\n0,0\n0.1,0.25\n0.2,-0.1\n0.3,0\n")
    p = tmp_path / "model.toml"
    p.write_text(text.replace("INTERFACE", "base"))
    assert main(["run", str(p), "--quiet"]) == 0
    from pfeie.io import Results

    with Results(tmp_path / "out" / "results.h5") as res:
        up = np.asarray(res.f["static/uplift"])
        assert up.max() == pytest.approx(RHO_W * 9.81 * 2.0)
        assert res.units("static/uplift") == "Pa"
        U = float((up * np.asarray(res.f["pairs/area"])).sum())
        # the crack lengths are an attribute of the groups /static and /post_earthquake,
        # not of their uplift datasets (docs/results.md said /static/uplift)
        for group in ("static", "post_earthquake"):
            assert set(json.loads(res.f[group].attrs["cracks"])) == {"base"}
            assert "cracks" not in res.f[f"{group}/uplift"].attrs
    rows = (ROOT / "docs" / "results.md").read_text()
    assert "the attribute `cracks` of the group `/static`" in rows
    assert "(and `uplift`; the group's attribute `cracks`)" in rows
    assert main(["report", str(tmp_path / "out" / "results.h5")]) == 0
    page = (tmp_path / "out" / "report.html").read_text()
    for words in ("<h2>Analysis</h2>", "nonsmooth-alpha", "<h2>Static state",
                  f"<td>{1e-3 * U:.4g}</td>", "crack from the heel (m)", "<td>0.25</td>",
                  "alt='mesh'", "alt='input_motion'"):  # fmt: skip
        assert words in page, words
    p.write_text(text.replace("INTERFACE", "neck"))
    assert main(["check", str(p)]) == 2
    err = capsys.readouterr().err
    assert "loads.uplift[0].interface" in err and "'neck'" in err
    # drains beyond the joint's far end would have no effect: refused, with its length
    p.write_text(text.replace("INTERFACE", "base").replace("drains = 0.5", "drains = 3.0"))
    assert main(["check", str(p)]) == 2
    err = capsys.readouterr().err
    assert (
        "loads.uplift[0]: uplift in 'base': the drains at 3 m from the heel lie beyond "
        "the joint, whose pairs reach 2 m from the heel along the flow (-x upstream)"
    ) in err
    # drains at the heel, drains without their efficiency, an efficiency without drains:
    # each changed nothing, silently
    for old, new, words in (
        ("drains = 0.5", "drains = 0.0", "the drains at 0 m from the heel lie at the heel"),
        ("drain_efficiency = 0.4\n", "", "loads.uplift[0].drain_efficiency: missing (required "
         "with drains"),
        ("drains = 0.5\n", "", "loads.uplift[0].drains: missing (required with "
         "drain_efficiency"),
    ):  # fmt: skip
        p.write_text(text.replace("INTERFACE", "base").replace(old, new))
        assert main(["check", str(p)]) == 2
        assert words in capsys.readouterr().err, words


def test_resume_with_uplift_that_follows() -> None:
    """A run with the 'full' policy stopped and resumed from its checkpoint (a new
    analysis, the static state given again, as `pfeie run --resume` does) gives the same
    bits as the run that was never stopped: the uplift of the pairs open at the
    checkpoint is restored."""
    model, _ = dam(19.0, pf.Joint(phi=45.0, initial="broken"), shaking="full")
    st = pf.solve_static(model)
    gm = pf.GroundMotion.from_function(lambda t: 0.4 * G * np.sin(2 * np.pi * 3 * t), 1.0, 1e-3)
    full = pf.Dynamic(model, 0.005).run(0.6, ground=[gm], start=st)
    cks: list[pf.dynamics.Checkpoint] = []
    pf.Dynamic(model, 0.005).run(0.3, ground=[gm], start=st, on_checkpoint=cks.append)
    rest = pf.Dynamic(model, 0.005).run(0.3, ground=[gm], start=st, resume=cks[-1])
    assert st.pairs is not None
    assert int((full.state == OPEN).sum(axis=1).max()) > int((st.pairs.state == OPEN).sum())
    np.testing.assert_array_equal(rest.rigid[-1], full.rigid[-1])
    np.testing.assert_array_equal(rest.X[-1], full.X[-1])
    # resumed from the rows where pairs open beyond the static crack (the uplift changes
    # with them): the next step's load is that of the pairs open at its start (before, the
    # load computed ahead of the uplift's change was kept, one step late, and a resumed
    # run differed by 0.64 mm)
    cks = []
    full = pf.Dynamic(model, 0.005).run(0.6, ground=[gm], start=st, on_checkpoint=cks.append)
    new = (full.state == OPEN) & (st.pairs.state != OPEN)[None, :]
    changes = np.flatnonzero(np.any(np.diff(new, axis=0), axis=1)) + 1
    assert changes.size >= 3
    for row in changes[:3]:
        rest = pf.Dynamic(model, 0.005).run(n_steps=full.t.size - 1 - row, ground=[gm],
                                            start=st, resume=cks[row - 1])  # fmt: skip
        np.testing.assert_array_equal(rest.rigid, full.rigid[row:], err_msg=str(row))
        np.testing.assert_array_equal(rest.X, full.X[row:], err_msg=str(row))


def test_a_crack_that_runs_through_under_its_own_uplift() -> None:
    """The limit of the cracked base: with full headwater in the crack and none beyond
    the toe, the 10 m × 20 m block overturns about its toe once the crack reaches it, when
    W B/2 = U B/2 + T h/3 with W = ρ_c g H B, U = ρ_w g h B and T = ρ_w g h²/2:
    h* = 20.26 m (rigid block, no-tension base). Elastic blocks, 1 m pairs: at h = 20.2 m
    (0.3 % below) the crack settles at 9 m, the last pair before the toe; at h = 20.3 m
    (0.2 % above) it runs on, and the static analysis says so (a relaxed step of the crack
    iteration could not shorten it), naming the block and its joint."""
    h_star = 20.0  # the root of 2400 H B²/2 − 1000 (h B²/2 + h³/6) = 0, by bisection
    lo, hi = 20.0, 21.0
    for _ in range(60):
        h_star = 0.5 * (lo + hi)
        if 2400 * H * B**2 / 2 - 1000 * (h_star * B**2 / 2 + h_star**3 / 6) > 0:
            lo = h_star
        else:
            hi = h_star
    assert h_star == pytest.approx(20.26, abs=0.005)
    model, _ = dam(h_star - 0.06, pf.Joint(phi=45.0, initial="broken"))
    st = pf.solve_static(model)
    assert st.cracks == (9.0,)
    model, _ = dam(h_star + 0.04, pf.Joint(phi=45.0, initial="broken"))
    with pytest.raises(MechanismError, match=r"the crack from the heel grows under its own "
                       r"uplift .* floating block\(s\) \('dam' on 'base'\)"):  # fmt: skip
        pf.solve_static(model)


DAM_TOML = """
title = "20 m gravity dam, lift joint at 10 m, reservoir 18 m, uplift"
plane = "strain"
[mesh]
file = "{mesh}"
[materials.concrete]
E = 25.0e9
nu = 0.2
rho = 2400.0
[materials.rock]
E = 20.0e9
nu = 0.25
rho = 2600.0
[blocks]
dam_lower = "concrete"
dam_upper = "concrete"
rock = "rock"
[interfaces.dam_rock]
friction_angle = 45.0
cohesion = 0.5e6
tensile_strength = 0.2e6
initial = "intact"
[interfaces.lift]
friction_angle = 40.0
initial = "broken"
[[supports]]
group = "rock_bottom"
[loads]
gravity = 9.81
[[loads.hydrostatic]]
groups = ["upstream", "reservoir_floor"]
water_level = 18.0
[[loads.westergaard]]
groups = ["upstream"]
water_level = 18.0
[[loads.uplift]]
interface = "dam_rock"
headwater = 18.0
[analysis]
dynamic = false
"""


@pytest.mark.parametrize(("k", "solves", "newton"), [(0.2190, 7, 1000), (0.2220, 10, 2000)])
def test_a_crack_that_comes_back_under_its_uplift_ends_the_analysis(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, k: float, solves: int, newton: int
) -> None:
    """The 20 m dam of tests/data/dam_lift_joint.msh on a bonded base (c = 0.5 MPa, σ_t =
    0.2 MPa) with full headwater (18 m) in its crack, pushed by k g (its mass and
    Westergaard's added mass), just beyond its yield coefficient (0.2182): the crack of
    6 m, held under its full uplift, opens 7 m, whose full uplift nothing holds; a relaxed
    step holds and gives 6 m again: a cycle, and the analysis ends with the crack running
    on to 7 m. Measured: at k = 0.2190, 7 pair solves and 268 Newton iterations (the
    former crack iteration went round the cycle to its 50th solve: 99 pair solves, 41 s,
    and a SolverError); at k = 0.2220, 10 pair solves and 632 Newton iterations (8,059
    and 28 s when each failing pair solve ran its cold Newton to 100 iterations once per
    pair that its unconverged iterates overloaded). The yield coefficient of this model
    did not end in 15 minutes; it takes 33 static analyses along +x now."""
    from pfeie.interface._solver import InterfaceSolver
    from pfeie.io import load_job

    mesh = Path(__file__).parent / "data" / "dam_lift_joint.msh"
    (tmp_path / "dam.toml").write_text(DAM_TOML.format(mesh=mesh))
    m = load_job(tmp_path / "dam.toml").model
    problem = StaticInterfaceProblem(m, m.system())
    g, iota = pf.solvers.horizontal(m)
    f_h = m.inertia_load(k * g * iota)
    work = {"solves": 0, "newton": 0}
    solve, newton_ = problem.solve, InterfaceSolver._newton

    def counted_solve(*a: Any, **kw: Any) -> Any:
        work["solves"] += 1
        return solve(*a, **kw)

    def counted_newton(self: InterfaceSolver, *a: Any, **kw: Any) -> Any:
        out = newton_(self, *a, **kw)
        work["newton"] += out[2]
        return out

    monkeypatch.setattr(problem, "solve", counted_solve)
    monkeypatch.setattr(InterfaceSolver, "_newton", counted_newton)
    system = problem.system
    with pytest.raises(MechanismError, match=r"the crack from the heel grows under its own "
                       r"uplift .* to 7 m"):  # fmt: skip
        solve_pairs(problem, system.load(0.0) + f_h[system.free], m.load_vector(0.0) + f_h)
    assert work["solves"] <= solves, work
    assert work["newton"] <= newton, work


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM])
def test_a_signal_during_the_yield_search_ends_the_run_cleanly(
    tmp_path: Path, sig: signal.Signals
) -> None:
    """Ctrl-C or SIGTERM while the yield coefficient is searched (before any time step; on
    the dam above the search takes about 25 s): exit 130, one line naming the signal, no
    traceback, and the results file closed as not completed with the reason. Before,
    SIGINT printed a traceback and SIGTERM killed the run silently."""
    mesh = Path(__file__).parent / "data" / "dam_lift_joint.msh"
    text = DAM_TOML.format(mesh=mesh).replace(
        "[analysis]\ndynamic = false", "[analysis]\ndynamic = false\nyield_coefficient = true"
    )
    text += '[output]\nfolder = "out"\n'
    (tmp_path / "dam.toml").write_text(text)
    env = dict(os.environ, PYTHONUNBUFFERED="1")
    proc = subprocess.Popen([sys.executable, "-m", "pfeie", "run", str(tmp_path / "dam.toml")],
                            env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True)  # fmt: skip
    assert proc.stderr is not None
    lines = []
    for line in proc.stderr:  # the search has started
        lines.append(line)
        if line.startswith("yield coefficient +x: static analyses"):
            break
    time.sleep(1.0)
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=120)
    err = "".join(lines) + err
    assert proc.returncode == 130, err
    assert f"pfeie: interrupted ({sig.name})" in err
    assert "Traceback" not in err
    from pfeie.io import Results

    with Results(tmp_path / "out" / "results.h5") as res:
        assert not res.completed
        assert f"interrupted ({sig.name}) before the time stepping" in res.meta["stop_reason"]


def test_pressure_in_a_joint_by_its_name() -> None:
    """A uniform water pressure p in an inclined joint, given by the interface's name
    (``add_pressure("joint", p)``: both faces): the block's normal force is W cos ψ − p L
    and its sliding safety factor (c L + (W cos ψ − p L) tan φ)/(W sin ψ), the planar
    sliding formula (Hoek and Bray), to round-off."""
    psi, phi, c, p = 30.0, 35.0, 2e4, 1e4  # degrees, degrees, Pa, Pa
    # 4 m wide and 1 m high: the effective normal force's eccentricity, (W sin ψ · ½ m) /
    # (W cos ψ − p L) = 0.57 m, stays within the kern (L/6 = 0.67 m), so no pair opens
    model = block_on_base(joint=pf.Joint(phi=phi, c_r=c), width=4.0, height=1.0, n=8, ny=2,
                          incline_deg=psi, E=1e12, check_units=False)  # fmt: skip
    model.add_pressure("joint", p)
    assert [ld.target for ld in model.loads if ld.kind == "pressure"] == ["joint"]
    st = pf.solve_static(model)
    W, L = 2400.0 * G * 4.0, 4.0  # N/m and m (1 m thick, plane strain)
    b = np.radians(psi)
    X = st.pairs.X.sum(axis=0)
    assert X[-1] == pytest.approx(W * np.cos(b) - p * L, rel=1e-14)  # measured 0 (round-off)
    fs_hand = (c * L + (W * np.cos(b) - p * L) * np.tan(np.radians(phi))) / (W * np.sin(b))
    P = st.pairs
    # the upslope end pair parts by 4e-9 m (the free end of the joint): it touches and
    # keeps its c A (opening below OPEN_CRACK_MIN_M), as in the hand computation
    fs = model.pair_laws.safety_factor(P.X, P.state == OPEN, P.broken, P.path,
                                       model.pairs.frame, opening=P.w[:, -1])  # fmt: skip
    assert fs[0] == pytest.approx(fs_hand, rel=2e-15)  # measured 3.3e-16


def test_model_file_water_in_a_joint(tmp_path: Path) -> None:
    """The model file takes an interface as the group of ``[[loads.pressure]]`` and of
    ``[[loads.hydrostatic]]``: the pressure acts on both faces of the joint (the Koyna
    demo with 0.05 MPa in its neck joint and water to 30 m in the dam–rock joint):
    the loads are on the split faces, equal and opposite, so the joint's water adds
    nothing to the whole model's resultant."""
    from pfeie.io import load_job

    root = Path(__file__).resolve().parents[1] / "examples"
    text = (root / "koyna" / "koyna.toml").read_text()
    text = text.replace('file = "../data/', f'file = "{root.as_posix()}/data/')
    text = text.replace('file = "koyna.msh"', f'file = "{(root / "koyna").as_posix()}/koyna.msh"')
    extra = ('[[loads.pressure]]\ngroup = "neck"\nvalue = 5e4\n\n'
             '[[loads.hydrostatic]]\ngroups = ["dam_rock"]\nwater_level = 30.0\n\n')  # fmt: skip
    text = text.replace("[[ground_motion]]", extra + "[[ground_motion]]", 1)
    p = tmp_path / "koyna.toml"
    p.write_text(text)
    model = load_job(p).model
    targets = [ld.target for ld in model.loads if ld.kind == "pressure"]
    assert {"neck", "dam_rock"} <= set(targets)
    # the joints' water alone: equal and opposite on the two faces of each joint
    model.loads = [ld for ld in model.loads if ld.target in ("neck", "dam_rock")]
    f = model.load_vector().reshape(-1, 2)
    assert np.abs(f.sum(axis=0)).max() < 1e-9 * np.abs(f).sum()
    assert np.abs(f).sum() > 1e6  # 0.05 MPa over the neck's ~15 m, and the base's water
    # a static run and its report (whose loads figure draws the joint's water; it had found
    # no group 'neck' and stopped): the water in the neck takes p L off its normal force,
    # against the static state of the same model without the joints' water
    length = float(model.pairs.area[model.pairs.of("neck")].sum())  # m (1 m thick)
    dry = tmp_path / "dry.toml"
    dry.write_text(text.replace(extra, ""))
    dry_model = load_job(dry).model
    n_dry = _static_joints(dry_model, pf.solve_static(dry_model))["neck"]["normal_force_N"]
    assert n_dry is not None
    text = text.replace("[analysis]\n", "[analysis]\ndynamic = false\n", 1)
    text = text.replace("[output]\n", "[output]\nparaview = false\n", 1)
    p.write_text(text)
    assert main(["run", str(p), "--quiet"]) == 0
    out = json.loads((tmp_path / "results" / "summary.json").read_text())["static_joints"]
    assert main(["report", str(tmp_path / "results" / "results.h5")]) == 0
    # the upper block's equilibrium: to round-off (measured 6.7e-16)
    assert out["neck"]["normal_force_N"] == pytest.approx(n_dry - 5e4 * length, rel=5e-15)
