"""The yield coefficient k_y (pfeie.yield_coefficient; docs/theory.md, "The yield
coefficient"), against limit equilibrium.

A block on a frictional joint reaches its limit when every pair slides, whatever its
elasticity, so the static analyses reproduce the rigid block's closed forms up to the
search's tolerance (the bracket [k_y, k_fail] is 1e-6 relative wide; k_y, the last
coefficient held, is measured 5e-7 below the closed form).
"""

from __future__ import annotations

import json
import re
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

import pfeie as pf
from pfeie.cli import main
from pfeie.coupling import StaticInterfaceProblem
from pfeie.solvers._static import solve_pairs
from pfeie.verification._models import block_on_base, block_on_base_3d
from test_cli import SMALL, _write

TOL = 1e-6  # the search's relative bracket (pfeie.solvers._yield.YIELD_TOL)


def _pushed(m: pf.Model) -> Callable[[float, pf.StaticResult | None], pf.StaticResult]:
    """The static analysis of ``m`` under its loads plus k g M ι (ι: +x made horizontal),
    on one static problem, started from a given state or cold."""
    problem = StaticInterfaceProblem(m, m.system())
    system = problem.system
    g, iota = pf.solvers.horizontal(m)
    f_h = g * (m.mass() @ np.tile(iota, (m.mesh.n_points, 1)).ravel())
    f0, fa, free = system.load(0.0), m.load_vector(0.0), system.free

    def at(k: float, start: pf.StaticResult | None = None) -> pf.StaticResult:
        return solve_pairs(problem, f0 + k * f_h[free], fa + k * f_h,
                           None if start is None else start.pairs)  # fmt: skip

    return at


@pytest.mark.parametrize("beta", [0.0, 10.0, 25.0])
def test_a_block_on_an_incline(beta: float) -> None:
    """φ = 40° on a plane of dip β: pushed down the dip k_y = tan(φ − β), up the dip
    tan(φ + β) (beyond k_max = 2 at β = 25°: held, k_y None). The safety factor of the
    joint at k_y is 1 within 1e-6, and the search takes at most 8 static analyses (the
    margin is affine in k: two analyses put the root, two bracket it; then 1 % beyond the
    failure, tried from the last state held and from the initial one, checks that the
    failure is the limit, YIELD_BEYOND; measured 7)."""
    m = block_on_base(joint=pf.Joint(phi=40.0), incline_deg=beta, n=4)
    down = pf.yield_coefficient(m)
    exact = np.tan(np.radians(40.0 - beta))
    assert down.k_y is not None and down.k_fail is not None
    assert exact * (1 - TOL) <= down.k_y <= exact <= down.k_fail <= exact * (1 + TOL)
    assert down.k_affine == pytest.approx(exact, rel=5e-15)  # measured 7.8e-16
    assert down.limit == "sliding" and down.joint == "joint"
    assert down.safety_factors["joint"] == pytest.approx(1.0, abs=TOL)
    assert down.analyses <= 8
    up = pf.yield_coefficient(m, [-1.0, 0.0])
    exact_up = np.tan(np.radians(40.0 + beta))
    if exact_up > 2.0:
        assert up.k_y is None and up.limit == "none"
    else:
        assert up.k_y is not None
        assert exact_up * (1 - TOL) <= up.k_y <= exact_up
        assert up.limit == "sliding"


@pytest.mark.parametrize("direction", [None, [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
def test_a_cube_in_3d(direction: list[float] | None) -> None:
    """A cube (2 × 2 × 2 hexahedra) on a level joint, φ = 35°: k_y = tan φ along ±x and y
    (the shears summed as vectors in the pairs' frames)."""
    m = block_on_base_3d(joint=pf.Joint(phi=35.0), n=2)
    y = pf.yield_coefficient(m, direction)
    exact = np.tan(np.radians(35.0))
    assert y.k_y is not None
    assert exact * (1 - TOL) <= y.k_y <= exact
    assert y.limit == "sliding"


def test_westergaard_water_adds_its_hydrodynamic_force() -> None:
    """A 4 m × 3 m block on a level joint (φ = 35°, no cohesion), water 2.5 m deep on
    its upstream face with Westergaard's added mass. Per metre: W = ρ g B H_b, the
    hydrostatic thrust T₀ = ρ_w g h²/2 (+x), and the pseudo-static inertia of a uniform
    acceleration k g, k (W + (7/12) ρ_w g h²) (the Westergaard mass on a vertical face
    integrates to 7/12 ρ_w h²; EM 1110-2-2100). The limits: downstream (+x)
    k_y = (μ W − T₀)/(W + W_a), upstream (−x) (μ W + T₀)/(W + W_a), both to 1e-6."""
    B, Hb, h, rho, rho_w, g = 4.0, 3.0, 2.5, 2400.0, 1000.0, 9.81
    m = block_on_base(joint=pf.Joint(phi=35.0), width=B, height=Hb, n=8, ny=6)
    m.mesh.add_facet_group("upstream", lambda x: (np.abs(x[:, 0]) < 1e-9) & (x[:, 1] > 0))
    m.add_pressure("upstream", lambda x: rho_w * g * np.maximum(h - x[..., 1], 0.0))
    m.add_westergaard("upstream", h, bottom=0.0)
    mu = np.tan(np.radians(35.0))
    W, T0, Wa = rho * g * B * Hb, rho_w * g * h**2 / 2, 7.0 / 12.0 * rho_w * g * h**2
    for direction, exact in ((None, (mu * W - T0) / (W + Wa)),
                             ([-1.0, 0.0], (mu * W + T0) / (W + Wa))):  # fmt: skip
        y = pf.yield_coefficient(m, direction)
        assert y.k_y is not None and y.limit == "sliding"
        assert exact * (1 - TOL) <= y.k_y <= exact * (1 + TOL)  # measured −5e-7
        assert y.k_affine == pytest.approx(exact, rel=5e-15)  # measured 6.7e-16


def test_a_cohesive_joint_and_its_heel() -> None:
    """A 4 m × 0.25 m block (16 Q4) on a plane of dip 10° with an existing joint c_r = 5 kPa,
    φ = 30°. The rigid block's limit is k = (c L/W + μ cos β − sin β)/(cos β + μ sin β) =
    1.146849; in the elastic block the heel pair touches with almost no normal force and,
    on the cohesion ramp, mobilises 326 N of its c A = 625 N (more shear there lifts it),
    so the joint slides as a whole 1 % earlier: limit equilibrium with that shortfall ΔC,
    k = k_rigid − ΔC / (W (cos β + μ sin β)), gives k_y to the search's bracket TOL
    (measured 1.9e-9 and 5.0e-7 with OpenBLAS's Haswell and SkylakeX kernels: where the
    bisection stops inside its bracket depends on the last bits), the joint's safety factor
    under its law 1 at k_y."""
    from pfeie.interface import cohesion_ramp

    c, beta, phi, B, H = 5e3, np.radians(10.0), np.radians(30.0), 4.0, 0.25
    m = block_on_base(joint=pf.Joint(phi=30.0, c_r=c, initial="broken"), incline_deg=10.0,
                      n=16, ny=1, width=B, height=H)  # fmt: skip
    y = pf.yield_coefficient(m)
    assert y.k_y is not None and y.limit == "sliding"
    assert y.safety_factors["joint"] == pytest.approx(1.0, abs=1e-6)
    P = y.static.pairs
    assert P is not None
    cA, mu, tA = m.pair_laws.strength(P.broken, P.path)
    on, tau, _ = cohesion_ramp(cA, mu, tA, P.X[:, -1], P.broken)
    assert on.sum() == 1 and (P.state != pf.interface.OPEN).all()
    shortfall = float((cA - (tau - mu * np.maximum(P.X[:, -1], 0.0)))[on].sum())
    assert 250.0 < shortfall < 350.0  # of c A = 625 N
    W, muv = 2400.0 * 9.81 * B * H, np.tan(phi)
    rigid = (c * B / W + muv * np.cos(beta) - np.sin(beta)) / (np.cos(beta) + muv * np.sin(beta))
    assert y.k_y == pytest.approx(rigid - shortfall / (W * (np.cos(beta) + muv * np.sin(beta))),
                                  rel=TOL)  # fmt: skip


def two_blocks(height: float, phi_base: float, phi_vert: float) -> pf.Model:
    """Two 1 m blocks ``height`` tall side by side on a base joint (φ_base), cut by a
    vertical joint (φ_vert), on a fixed base 0.5 m thick (Q4 of 0.5 m)."""
    mat = pf.Elastic(30e9, 0.2, 2400.0)
    mesh = pf.rectangle(2.0, height + 0.5, 4, round(2 * height) + 1, cell="quad")
    mesh.points[:, 1] -= 0.5
    mesh.add_cell_group("base", lambda x: x[:, 1] < 0)
    mesh.add_cell_group("L", lambda x: (x[:, 1] > 0) & (x[:, 0] < 1))
    mesh.add_cell_group("R", lambda x: (x[:, 1] > 0) & (x[:, 0] > 1))
    mesh.add_facet_group("joint", lambda x: np.abs(x[:, 1]) < 1e-9, boundary_only=False)
    mesh.add_facet_group("vert", lambda x: (np.abs(x[:, 0] - 1) < 1e-9) & (x[:, 1] > 1e-9),
                         boundary_only=False)  # fmt: skip
    m = pf.Model(mesh, [pf.Block("base", mat), pf.Block("L", mat), pf.Block("R", mat)],
                 interfaces=[pf.Interface("joint", pf.Joint(phi=phi_base)),
                             pf.Interface("vert", pf.Joint(phi=phi_vert))])  # fmt: skip
    m.fix("base")
    m.add_gravity()
    return m


def test_a_joint_at_its_capacity_does_not_end_the_search() -> None:
    """Two blocks side by side on a base joint (φ = 30°), cut by a vertical joint: the
    vertical joint reaches its capacity early (FS 1 at k ≈ 0.07, it slides while the two
    blocks stay in equilibrium), which is not the structure's limit: k_y = tan 30° along
    +x and −x, governed by the base joint."""
    m = two_blocks(1.0, 30.0, 30.0)
    exact = np.tan(np.radians(30.0))
    for direction in (None, [-1.0, 0.0]):
        y = pf.yield_coefficient(m, direction)
        assert y.k_y is not None and exact * (1 - TOL) <= y.k_y <= exact
        assert y.joint == "joint" and y.limit == "sliding"
        # it slides: at its capacity to round-off (measured ±1.9e-12)
        assert y.safety_factors["vert"] == pytest.approx(1.0, abs=2e-11)


def test_the_former_failure_band_of_a_cohesive_joint() -> None:
    """A 2 m × 0.5 m block (8 × 2 Q4) on a plane of dip 10° with an existing joint
    c_r = 20 kPa, φ = 30°, pushed down the dip by k g: before the cohesion ramp every
    static analysis of 0.498 ≤ k ≤ 0.565 failed (the heel pair's force passes through
    zero there, far from sliding: FS 3.3). Now each is solved, the block in equilibrium
    (ΣX = the applied load on the block, to 1.5e-15; measured 1.5e-16) and the heel pair,
    with no normal force to speak of, carries shear on the ramp."""
    from pfeie.interface import cohesion_ramp

    m = block_on_base(joint=pf.Joint(phi=30.0, c_r=2e4, initial="broken"), incline_deg=10.0,
                      n=8, ny=2, width=2.0, height=0.5)  # fmt: skip
    at = _pushed(m)
    g, iota = pf.solvers.horizontal(m)
    fa = m.load_vector(0.0) + g * (m.mass() @ np.tile(iota, (m.mesh.n_points, 1)).ravel())
    block = np.flatnonzero(m.body_of_node == m.body_of_node[m.pairs.node_b[0]])  # type: ignore[union-attr]
    on_ramp = 0
    for k in (0.50, 0.53, 0.56):
        st = at(k, None)
        P = st.pairs
        assert P is not None and m.pairs is not None
        F = m.pairs.resultants(P.X)[0][0]  # the joint's force on side b (global)
        load = (m.load_vector(0.0) + k * (fa - m.load_vector(0.0))).reshape(-1, 2)[block].sum(
            axis=0)  # fmt: skip
        assert np.abs(F + load).max() <= 1.5e-15 * np.abs(load).max()
        cA, mu, tA = m.pair_laws.strength(P.broken, P.path)
        on_ramp += int(cohesion_ramp(cA, mu, tA, P.X[:, -1], P.broken)[0].sum())
    assert on_ramp > 0


def test_a_start_from_a_nearby_state_gives_the_same_answer() -> None:
    """The pair solver started from the state under another load (as the search does)
    finds the answer of a cold start, and leaves the start untouched: on a bonded joint
    (c = 3 kPa, σ_t = 1 kPa) the state at k = 0.5 has two broken pairs; started from it,
    the analysis at k = 0.05 breaks none, as the cold one (the same bits here)."""
    m = block_on_base(joint=pf.Joint(phi=30.0, c=3e3, tensile=1e3, initial="intact"),
                      width=2.0, height=1.0, n=8, ny=2)  # fmt: skip
    at = _pushed(m)
    far = at(0.5, None)
    assert far.pairs is not None and far.pairs.broken.sum() == 2
    kept = far.pairs.copy()
    warm, cold = at(0.05, far), at(0.05, None)
    assert warm.pairs is not None and cold.pairs is not None
    assert not warm.pairs.broken.any() and not cold.pairs.broken.any()
    assert np.abs(warm.pairs.X - cold.pairs.X).max() <= 1e-8 * np.abs(cold.pairs.X).max()
    for name in ("X", "state", "broken", "slip_dir", "w", "s"):
        assert np.array_equal(getattr(far.pairs, name), getattr(kept, name))


def test_the_yield_coefficient_in_a_model_file(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """``analysis.yield_coefficient = true`` on two blocks cut by a level joint with
    φ = 26.565° (μ = 0.5): summary.json gives k_y = μ = 0.5 along +x and −x (to 1e-6),
    sliding, the text a line per direction and the report's static joint table a column;
    the progress a line as each direction's search starts and ends.
    Without the static state it is refused, naming the key."""
    text = SMALL.replace("[analysis]", "[analysis]\nyield_coefficient = true\ndynamic = false")
    text = text.replace("[[ground_motion]]\nfile = \"pulse.csv\"\nunits = \"g\"\n", "")
    p = _write(tmp_path, text)
    capsys.readouterr()
    assert main(["run", str(p)]) == 0
    # the search's progress: a line as each direction starts and ends
    err = capsys.readouterr().err
    assert "yield coefficient +x: static analyses ..." in err
    line = re.search(r"yield coefficient -x: k_y ([\d.]+) \(sliding\), \d+ static "
                     r"analyses in [\d.]+ s", err)  # fmt: skip
    assert line is not None, err
    assert float(line.group(1)) == pytest.approx(np.tan(np.radians(26.565)), rel=2e-6)
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    mu = np.tan(np.radians(26.565))
    for label, sign in (("+x", 1.0), ("-x", -1.0)):
        y = s["yield_coefficient"][label]
        assert mu * (1 - TOL) <= y["k_y"] <= mu
        assert y["limit"] == "sliding" and y["joint"] == "joint"
        assert y["direction"] == [sign, 0.0]
    txt = (tmp_path / "out" / "summary.txt").read_text()
    assert "yield +x" in txt and "yield -x" in txt and "sliding" in txt
    from pfeie.plot import write_report

    html = Path(write_report(tmp_path / "out" / "results.h5")).read_text()
    k_plus = s["yield_coefficient"]["+x"]["k_y"]
    assert "yield coefficient k_y along +x" in html and f"{k_plus:.4g} (sliding)" in html
    bad = _write(tmp_path, text.replace("dynamic = false", "dynamic = true\nstatic = false"))
    capsys.readouterr()
    assert main(["run", str(bad), "--quiet"]) == 2
    assert "analysis.yield_coefficient" in capsys.readouterr().err


def test_directions_listed_in_a_model_file(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """``analysis.yield_coefficient = ["-x"]`` searches that direction only (k_y = μ = 0.5
    on the level joint); a 2D model asked for '+y' (its vertical axis) is refused, naming
    the key, by ``pfeie check`` as by ``pfeie run`` (check passed it once); a repeated
    direction too; a value of neither type in one line that says what is expected."""
    text = SMALL.replace("[analysis]", '[analysis]\nyield_coefficient = ["-x"]\ndynamic = false')
    text = text.replace("[[ground_motion]]\nfile = \"pulse.csv\"\nunits = \"g\"\n", "")
    p = _write(tmp_path, text)
    assert main(["run", str(p), "--quiet"]) == 0
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert list(s["yield_coefficient"]) == ["-x"]
    mu = np.tan(np.radians(26.565))
    assert mu * (1 - TOL) <= s["yield_coefficient"]["-x"]["k_y"] <= mu
    either = ("expected true, false or an array of '+x', '-x' (in 3D also '+y', '-y') or of "
              "horizontal vectors such as [0.6, 0.8, 0.0], found")
    for bad, words in (('["+y"]', "names y, the vertical axis of a 2D model"),
                       ('["-x", "-x"]', "distinct directions"),
                       ('"x"', f"{either} a string 'x'"),
                       ('["+z"]', f"{either} an array ['+z']")):  # fmt: skip
        q = _write(tmp_path, text.replace('["-x"]', bad))
        for command in ("check", "run"):
            capsys.readouterr()
            quiet = ["--quiet"] if command == "run" else []
            assert main([command, str(q), *quiet]) == 2
            err = capsys.readouterr().err
            assert "analysis.yield_coefficient" in err and words in err, err
            assert err.count("pfeie: error") == 1, err


def test_horizontal_axis_y_in_3d() -> None:
    """In 3D, ``horizontal(model, axis=1)`` is +y made normal to gravity: a cube on a
    level joint (φ = 30°) yields at k_y = tan 30° along +y as along +x."""
    m = block_on_base_3d(joint=pf.Joint(phi=30.0))
    _, iota = pf.solvers.horizontal(m, axis=1)
    assert iota.tolist() == [0.0, 1.0, 0.0]
    y = pf.yield_coefficient(m, iota)
    assert np.tan(np.radians(30.0)) * (1 - TOL) <= y.k_y <= np.tan(np.radians(30.0))


def test_a_failure_short_of_the_limit_does_not_end_the_search(
    monkeypatch: pytest.MonkeyPatch, caplog: pytest.LogCaptureFixture
) -> None:
    """A search on a simulated static problem: equilibrium (the level block's own static
    state, so the margins do not predict the limit and the search doubles k) for k < 1,
    none beyond, and a pair solver that fails short of the limit for k in (0.399, 0.402):
    the search brackets 0.399, finds equilibrium 1 % beyond it (YIELD_BEYOND), goes on, and
    ends at the limit 1 within its tolerance, saying so (a new user's rock bridge read
    k_y 0.8902 "sliding" where 0.95 held)."""
    from pfeie.solvers import _yield

    real = _yield.held
    state: dict[str, object] = {}

    def fake(problem, f_free, f_all, start, what):  # type: ignore[no-untyped-def]
        k = float(what.rsplit("k = ", 1)[1])
        if "base" not in state:
            state["base"] = real(problem, f_free, f_all, start, what)[0]
        if k >= 1.0 or 0.399 < k < 0.402:
            return None, 1
        return state["base"], 1

    monkeypatch.setattr(_yield, "held", fake)
    m = block_on_base(joint=pf.Joint(phi=40.0), n=2)
    with caplog.at_level("WARNING"):
        y = pf.yield_coefficient(m)
    assert y.k_y is not None and y.k_fail is not None
    assert y.k_y <= 1.0 <= y.k_fail and y.k_fail - y.k_y <= TOL * 1.0
    assert "no equilibrium found at k = 0.399, but one at 0.40299: the pair solver failed " \
        "short of the limit there; the search goes on" in caplog.text
