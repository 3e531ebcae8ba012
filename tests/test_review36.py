"""Toppling rows and wedged blocks in the limit searches; the element core's checks of a
mesh built in Python, curved Tet10 cells and nearly incompressible materials (an
independent audit of the element core and a rock-slope engineer's toppling cases)."""

from __future__ import annotations

import itertools
import logging
import math

import numpy as np
import pytest

import pfeie as pf
from pfeie.assembly import curved_cells, stiffness_degree
from pfeie.errors import MeshError
from pfeie.verification._models import block_on_base
from test_review34 import _failing

# -- the limit searches where the rigid blocks hold at the search's end ------------------


def _failing_from(monkeypatch: pytest.MonkeyPatch, module: str, start: float) -> list[float]:
    """The limit search's analyses made to fail from ``start`` on (k or F); the values
    tried, in order."""
    tried: list[float] = []

    def fails(value: float) -> bool:
        tried.append(value)
        return value >= start

    _failing(monkeypatch, module, fails)
    return tried


def test_no_probe_towards_k_max_where_the_rigid_blocks_hold_there(
    monkeypatch: pytest.MonkeyPatch, caplog: pytest.LogCaptureFixture,
) -> None:  # fmt: skip
    """A block 4 m wide and 1 m tall on a level joint, φ = 80° (the rigid block holds up to
    k = 4, where it tips over, beyond the search's k_max = 2: the rigid check gives ∞),
    its analyses made to fail from k = 0.1 on. The search used to probe from the failure
    towards k_max, where the rigid check bounds nothing, and took an equilibrium it met
    there (eight columns on a stepped base: k_y = 1.677 where the rigid row slides at
    0.47). Now it stops at the failure: no analysis beyond 1 % past it, and no claim
    that the pair solver failed."""
    model = block_on_base(joint=pf.Joint(phi=80.0), width=4.0, n=8)  # (tips over at k = 4)
    tried = _failing_from(monkeypatch, "pfeie.solvers._yield", 0.1)
    with caplog.at_level(logging.WARNING, logger="pfeie"):
        y = pf.yield_coefficient(model)
    assert y.limit == "no equilibrium found" and y.k_y is not None and y.k_y < 0.1
    # once the bracket has closed on 0.1, only the one try 1 % beyond it
    closed = next(i for i, k in enumerate(tried) if abs(k - 0.1) < 1e-4)
    assert max(tried[closed:]) <= 0.1 * 1.01 * (1 + 1e-3)
    assert "failed short of the limit there" not in caplog.text
    assert "while rigid blocks hold up to k_max = 2: k_y = 0.1" in caplog.text


def test_no_probe_towards_f_max_where_the_rigid_blocks_hold_there(
    monkeypatch: pytest.MonkeyPatch, caplog: pytest.LogCaptureFixture,
) -> None:  # fmt: skip
    """The strength reduction's counterpart: a block on a 1° incline, φ = 40° (rigid
    factor tan 40°/tan 1° = 48, beyond f_max = 20), its analyses made to fail from F = 1.5:
    no analysis beyond the failure (before: probes towards 20)."""
    model = block_on_base(joint=pf.Joint(phi=40.0), incline_deg=1.0)
    tried = _failing_from(monkeypatch, "pfeie.solvers._strength", 1.5)
    with caplog.at_level(logging.WARNING, logger="pfeie"):
        r = pf.strength_reduction(model)
    assert r.limit == "no equilibrium found" and r.factor is not None and r.factor < 1.5
    assert "while rigid blocks hold beyond f_max = 20" in caplog.text
    assert "static equilibrium ends between" not in caplog.text  # (no bound: no bracket)
    # (the search tries f_max first, then halves) once the bracket has closed on 1.5: none
    closed = next(i for i, f in enumerate(tried) if abs(f - 1.5) < 1e-3)
    assert max(tried[closed:]) <= 1.5 * (1 + 1e-3)


def _columns(heights: list[float], step: float, dip: float, phi: float,
             across: int = 2) -> pf.Model:  # fmt: skip
    """A row of 1 m wide rock columns (Q4, ``across`` cells across and about as tall) on a stepped
    foundation, drawn in the frame of the columns' bases (x along them, up the slope;
    gravity tilted by ``dip``): column i stands on the step at y = i·``step``, and the
    riser up to the next step touches the foot of its uphill face. Joints 'bases' (the
    foundation, risers included) and 'sides' (between columns), φ = ``phi``, cohesionless,
    no tension; the foundation fixed."""
    n = len(heights)
    base = [i * step for i in range(n)]
    xs = np.linspace(0.0, n, across * n + 1)
    levels = {
        round(v, 9) for v in [-0.5, *base, *(b + h for b, h in zip(base, heights, strict=True))]
    }
    keys = sorted(levels)
    ys = [keys[0]]
    for a, b in itertools.pairwise(keys):
        ys.extend(np.linspace(a, b, max(1, math.ceil((b - a) * across - 1e-9)) + 1)[1:])
    X, Y = np.meshgrid(xs, np.array(ys), indexing="ij")
    pts = np.stack([X.ravel(), Y.ravel()], 1)
    ids = np.arange(pts.shape[0]).reshape(X.shape)

    def region(x: float, y: float) -> int:  # 0 the foundation, i + 1 column i, −1 air
        i = min(int(x), n - 1)
        return 0 if y < base[i] else (i + 1 if y < base[i] + heights[i] else -1)

    quads, owner = [], []
    for a in range(xs.size - 1):
        for c in range(len(ys) - 1):
            r = region(0.5 * (xs[a] + xs[a + 1]), 0.5 * (ys[c] + ys[c + 1]))
            if r >= 0:
                quads.append([ids[a, c], ids[a + 1, c], ids[a + 1, c + 1], ids[a, c + 1]])
                owner.append(r)
    conn, own = np.array(quads), np.array(owner)
    used = np.unique(conn)
    renum = np.full(pts.shape[0], -1)
    renum[used] = np.arange(used.size)
    groups = {"rock": {"quad": np.flatnonzero(own == 0)}}
    groups |= {f"c{i + 1}": {"quad": np.flatnonzero(own == i + 1)} for i in range(n)}
    mesh = pf.Mesh(pts[used], {"quad": renum[conn]}, cell_groups=groups)

    def kind(c: np.ndarray) -> np.ndarray:  # 1: a column on the rock, 2: two columns
        out = np.zeros(len(c), dtype=int)
        for k, (x, y) in enumerate(c):
            for dx, dy in ((1e-6, 0.0), (0.0, 1e-6)):
                inside = x - dx >= 0 and x + dx <= n and y - dy >= -0.5
                r1 = region(x - dx, y - dy) if inside else -1
                r2 = region(x + dx, y + dy) if inside else -1
                if r1 >= 0 and r2 >= 0 and r1 != r2:
                    out[k] = 1 if 0 in (r1, r2) else 2
        return out

    mesh.add_facet_group("bases", lambda c: kind(c) == 1, boundary_only=False)
    mesh.add_facet_group("sides", lambda c: kind(c) == 2, boundary_only=False)
    rock = pf.Elastic(E=20e9, nu=0.25, rho=2600.0)
    joint = pf.Joint(phi=phi)
    blocks = [pf.Block("rock", rock)] + [pf.Block(f"c{i + 1}", rock) for i in range(n)]
    joints = [pf.Interface("bases", joint), pf.Interface("sides", joint)]
    model = pf.Model(mesh, blocks, interfaces=joints)
    model.fix("rock")
    psi = math.radians(dip)
    model.add_gravity(direction=(-math.sin(psi), -math.cos(psi)))
    return model


@pytest.mark.slow
def test_a_toppling_row_on_a_stepped_base_is_not_wedged_up_to_k_max(
    caplog: pytest.LogCaptureFixture,
) -> None:  # fmt: skip
    """A rock-slope engineer's Goodman–Bray row (eight columns 1 to 4 m tall on a base
    stepped 0.2 m a column, bases dipping 25°, φ = 50°), pushed out of the slope. With
    φ > 45° a column wedged between a riser and its base balances any load (the riser's
    friction adds more base friction than the riser's push: tan² φ > 1), so the rigid
    blocks' check holds up to k_max and bounds nothing. The yield search gave k_y = 1.677
    ("no equilibrium found at k = 0.385, but one at 1.677"), 3.6 times the coefficient at
    which the whole rigid row slides on its bases, tan(φ − 25°) = 0.4663, a bound any
    answer must respect (the risers face downhill and cannot hold the row). Now 0.385:
    below that bound, without the claim."""
    model = _columns([1.0, 1.6, 2.2, 2.8, 3.4, 4.0, 3.4, 2.8], 0.2, 25.0, 50.0)
    psi = math.radians(25.0)
    with caplog.at_level(logging.WARNING, logger="pfeie"):
        y = pf.yield_coefficient(model, [-math.cos(psi), math.sin(psi)])
    assert y.k_y is not None and 0.3 < y.k_y < math.tan(math.radians(25.0))
    assert "failed short of the limit" not in caplog.text


def test_a_toppling_row_leaning_on_its_feet_is_warned(caplog: pytest.LogCaptureFixture) -> None:
    """Three columns (2.5, 3.5 and 3 m tall, 1 m wide) on a flat base dipping 20°, φ = 50°:
    Goodman and Bray's limit equilibrium has the row topple (F = 0.606 < 1), and so did
    pfeie's static analysis with two cells across a column (no equilibrium at F = 1); with
    four, strength reduction read F = 1.289 "sliding" on 'sides' and said nothing. Each
    column's foot presses into its neighbour's at the T-junction of the joints, and the
    friction of that node pair holds the row (a tester's runs: frictionless, those pairs
    let the rows topple, and the factors of a five-column row stopped growing with the
    mesh). Now warned: the feet's pairs carry 48 % of the normal force of 'sides' on 4.5 %
    of its area (the threshold: 20 % and five times the area's share)."""
    from pfeie.solvers._static import junction_share

    model = _columns([2.5, 3.5, 3.0], 0.0, 20.0, 50.0, across=4)
    with caplog.at_level(logging.WARNING, logger="pfeie"):
        r = pf.strength_reduction(model)
    assert r.factor is not None and r.joint == "sides"
    force, area = junction_share(model, r.static, "sides")
    assert 0.4 < force < 0.6 and area == pytest.approx(1 / 22)  # (the feet: 1 m of 22 m)
    assert "the pairs of 'sides' at junctions" in caplog.text
    assert r.junction_share == force  # (summary.json's junction_share)


def test_the_summary_says_where_a_limit_leans_on_junctions() -> None:
    """summary.txt's caveat from summary.json's junction_share (null: none)."""
    from pfeie._job import _junction_text

    text = _junction_text({"joint": "sides", "junction_share": 0.481})
    assert text.startswith("; but 'sides' leans on its pairs at junctions (48 % of its normal")
    assert text.endswith("refine it and compare")
    assert _junction_text({"joint": "sides", "junction_share": None}) == ""


def test_the_pairs_at_junctions() -> None:
    """PairGeometry.junctions: two blocks side by side on a base (a T-junction): the pairs
    at the foot of their vertical joint and the two base pairs under it; the pairs away
    from it, none; a single block on a base, none."""
    mesh = pf.rectangle(2.0, 2.0, 4, 4)
    mesh.add_cell_group("base", lambda x: x[:, 1] < 0.5)
    mesh.add_cell_group("left", lambda x: (x[:, 1] > 0.5) & (x[:, 0] < 1.0))
    mesh.add_cell_group("right", lambda x: (x[:, 1] > 0.5) & (x[:, 0] > 1.0))
    mesh.add_facet_group("bed", lambda c: np.abs(c[:, 1] - 0.5) < 1e-9, boundary_only=False)
    mesh.add_facet_group("gap", lambda c: (np.abs(c[:, 0] - 1.0) < 1e-9) & (c[:, 1] > 0.5),
                         boundary_only=False)  # fmt: skip
    rock = pf.Elastic(30e9, 0.2, 2400.0)
    joint = pf.Joint(phi=30.0)
    blocks = [pf.Block(b, rock) for b in ("base", "left", "right")]
    joints = [pf.Interface("bed", joint), pf.Interface("gap", joint)]
    model = pf.Model(mesh, blocks, interfaces=joints)
    assert model.pairs is not None
    at = model.pairs.junctions()
    where = model.pairs.x[at]
    assert np.allclose(where, [1.0, 0.5]) and at.sum() == 3  # two bed pairs and a gap pair
    single = block_on_base(joint=joint)
    assert single.pairs is not None and not single.pairs.junctions().any()


# -- meshes built in Python are checked as files are ---------------------------------------


@pytest.mark.parametrize(("cell", "node", "at"), [("quad8", 4, 0.2), ("triangle6", 3, 0.2)])
def test_a_python_mesh_with_a_cell_inverted_at_a_corner_is_refused(
    cell: str, node: int, at: float
) -> None:
    """A Q8 whose mid-side node sits at 0.2 of its edge (det J = −0.05 at a corner) and a
    T6 likewise were solved without a word: their Jacobian is positive at the stiffness
    rule's points, and only the gmsh reader checked the nodes. pfeie.Model now checks a
    mesh that was not checked: a MeshError naming the cell."""
    mesh = pf.rectangle(1.0, 1.0, 1, 1, cell=cell)
    conn = mesh.cells[cell][0]
    a, b = mesh.points[conn[0]], mesh.points[conn[1]]
    mesh.points[conn[node]] = a + at * (b - a)  # the mid-side node of the edge 0–1
    with pytest.raises(
        MeshError, match=rf"inverted or self-intersecting {cell} cell.*{cell} cell 0"
    ):
        pf.Model(mesh, [pf.Block("all", pf.Elastic(30e9, 0.2, 2400.0))])


def test_a_mesh_is_checked_once(monkeypatch: pytest.MonkeyPatch) -> None:
    """A mesh that passed its check (the gmsh reader's, or a first model's) is not checked
    again by the next model: the check costs 0.4 s at 20,000 nodes."""
    import pfeie.mesh._mesh as mod

    calls: list[int] = []
    real = mod.check_cells

    def spy(mesh: pf.Mesh, where: str = "") -> None:
        calls.append(1)
        real(mesh, where)

    monkeypatch.setattr(mod, "check_cells", spy)
    mesh = pf.rectangle(2.0, 1.0, 4, 2)
    for _ in range(2):
        pf.Model(mesh, [pf.Block("all", pf.Elastic(30e9, 0.2, 2400.0))])
    assert len(calls) == 1 and mesh.checked


# -- curved Tet10 cells -----------------------------------------------------------------


def _tet10_patch(offset: float) -> tuple[pf.Model, float]:
    """The displacement patch test on 2 × 2 × 2 cubes of Tet10 (0.5 m) whose interior
    mid-edge nodes moved by ``offset`` (m) in a fixed pseudo-random direction: every
    boundary node given the linear field u = H x; the relative error of u inside."""
    mesh = pf.box(1.0, 1.0, 1.0, 2, 2, 2, cell="tetra10")
    conn = mesh.cells["tetra10"]
    rng = np.random.default_rng(1)
    boundary = np.unique(np.concatenate([mesh.group_nodes(g) for g in mesh.facet_groups]))
    inner = np.setdiff1d(np.unique(conn[:, 4:]), boundary)
    mesh.points[inner] += offset * rng.standard_normal((inner.size, 3)) / np.sqrt(3.0)
    H = 1e-3 * np.array([[1.0, 0.4, -0.3], [-0.2, 0.5, 0.25], [0.3, -0.1, 0.7]])
    exact = mesh.points @ H.T
    model = pf.Model(mesh, [pf.Block("all", pf.Elastic(200e9, 0.3, 7800.0))])
    for i in range(3):
        for node in boundary:
            model.fix([int(node)], i, float(exact[node, i]))
    u = pf.solve_static(model).u.reshape(-1, 3)
    return model, float(np.abs(u - exact).max() / np.abs(exact).max())


@pytest.mark.parametrize("offset", [0.0, 0.02, 0.04])
def test_curved_tet10_cells_pass_the_patch_test(offset: float) -> None:
    """A curved Tet10's internal forces of a constant stress, ∫ σ adj(J)ᵀ ∇_ξN dξ, are
    cubic in ξ (the adjugate of a linear J is quadratic), which the 4-point rule of the
    stiffness (degree 2) does not integrate: the patch test failed by 4.7e-5 and 1.8e-4
    at offsets of 0.02 and 0.04 m. Curved Tet10 cells now take a degree-3 rule (8
    points): exact to round-off (measured 3e-16 to 5e-16); straight ones keep theirs."""
    model, err = _tet10_patch(offset)
    assert err < 5e-15  # (measured 3e-16 to 5e-16)
    cs = model._cellsets[0]
    assert cs.kdeg == (2 if offset == 0.0 else 3)


def test_curved_cells_and_their_stiffness_degree() -> None:
    """curved_cells: a quadratic cell whose mid-side node is off the image of its corners
    by more than 1e-9 of its size; first-order cells never. The stiffness degree rises
    only for curved 3D simplices (d(p − 1) = 3 against 2(p − 1) = 2)."""
    mesh = pf.rectangle(1.0, 1.0, 1, 1, cell="triangle6")
    conn = mesh.cells["triangle6"]
    assert not curved_cells(mesh.points, "triangle6", conn)
    mesh.points[conn[0, 3]] += [0.0, 1e-6]
    assert curved_cells(mesh.points, "triangle6", conn)
    square = pf.rectangle(1.0, 1.0, 1, 1)
    assert not curved_cells(square.points, "quad", square.cells["quad"])
    assert stiffness_degree("triangle6", curved=True) == stiffness_degree("triangle6") == 2
    assert (stiffness_degree("tetra10"), stiffness_degree("tetra10", curved=True)) == (2, 3)
    assert stiffness_degree("quad8", curved=True) == stiffness_degree("quad8") == 4


# -- nearly incompressible materials ---------------------------------------------------------


def test_a_nearly_incompressible_material_is_warned() -> None:
    """ν = 0.4999 locks first-order cells (a plane-strain Q4 cantilever kept 8 to 24 % of its
    deflection, the auditor's measure): warned, at the caller's line, as the wrong units
    are; ν = 0.35 is not."""
    mesh = pf.rectangle(2.0, 1.0, 2, 1)
    with pytest.warns(UserWarning, match=r"block 'all': nu = 0.4999 is nearly incompressible"):
        pf.Model(mesh, [pf.Block("all", pf.Elastic(30e9, 0.4999, 2400.0))])
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        pf.Model(mesh, [pf.Block("all", pf.Elastic(30e9, 0.35, 2400.0))])


# -- the rigid checks of the limit searches take the uplift ----------------------------------


def _wet_block() -> pf.Model:
    """A dam engineer's block (10 × 10 m, ρ = 2400 kg/m³, Q8) on rock, its base joint
    φ = 40° without cohesion, water 8 m deep on its upstream face and a linear uplift
    from 8 m of head at the heel to none at the toe."""
    mesh = pf.rectangle(10.0, 14.0, nx=4, ny=7, cell="quad8")
    mesh.add_cell_group("rock", lambda x: x[:, 1] < 4.0)
    mesh.add_cell_group("dam", lambda x: x[:, 1] > 4.0)
    mesh.add_facet_group("base", lambda x: abs(x[:, 1] - 4.0) < 1e-9, boundary_only=False)
    mesh.add_facet_group("up", lambda x: (abs(x[:, 0]) < 1e-9) & (x[:, 1] > 4.0 - 1e-9))
    blocks = [pf.Block("rock", pf.Elastic(25e9, 0.2, 10.0)),
              pf.Block("dam", pf.Elastic(25e9, 0.2, 2400.0))]  # fmt: skip
    m = pf.Model(mesh, blocks, interfaces=[pf.Interface("base", pf.Joint(phi=40.0))],
                 check_units=False)  # fmt: skip
    m.fix("ymin")
    m.add_gravity()
    m.add_pressure("up", lambda x: 9810.0 * np.maximum(12.0 - x[..., 1], 0.0), level=12.0)
    m.add_uplift("base", headwater=12.0)
    return m


def test_the_translations_take_the_uplift() -> None:
    """The translational check beside the limit searches took the loads without the uplift
    (a dam engineer's finding): translation_factor 6.2932 = W tan φ / P and k_translation
    0.7058 for this block, where the uplift U = ½ γ_w 8 m · 10 m lowers them, as the
    analyses found (F = 5.2442). Now: (W − U) tan φ / P = 5.24440 with the static state's
    uplift (no crack), and k_translation = ((W − U′) tan φ − P)/W with U′ the uplift of the
    last state held (its crack from the heel under full headwater), the static analyses'
    k_y itself."""
    m = _wet_block()
    W, P = 2400 * 9.81 * 100.0, 0.5 * 9810 * 8.0**2
    mu = math.tan(math.radians(40.0))
    sr = pf.strength_reduction(m)
    assert sr.static.cracks == (0.0,)
    U = 0.5 * 9810 * 8.0 * 10.0
    assert sr.translation_factor == pytest.approx((W - U) * mu / P, rel=1e-9)
    assert sr.factor == pytest.approx((W - U) * mu / P, rel=1e-4)  # (the search's tol)
    y = pf.yield_coefficient(m)
    assert m.pairs is not None and y.static.uplift is not None and y.k_translation is not None
    U_lim = float((y.static.uplift * m.pairs.area).sum())  # (Pa × m² a metre of dam)
    assert U_lim > U  # the heel cracked at the limit
    assert y.k_translation == pytest.approx(((W - U_lim) * mu - P) / W, rel=1e-5)
    assert y.k_y == pytest.approx(y.k_translation, rel=1e-5)


def test_a_mesh_edited_after_its_check_is_checked_again() -> None:
    """The check is remembered by a hash of the points and cells: a mesh edited after a
    first model (a Q8's mid-side node moved to 0.2 of its edge) is checked again."""
    mesh = pf.rectangle(1.0, 1.0, 1, 1, cell="quad8")
    rock = pf.Elastic(30e9, 0.2, 2400.0)
    pf.Model(mesh, [pf.Block("all", rock)])
    assert mesh.checked
    conn = mesh.cells["quad8"][0]
    mesh.points[conn[4]] = mesh.points[conn[0]] + 0.2 * (
        mesh.points[conn[1]] - mesh.points[conn[0]]
    )
    assert not mesh.checked
    with pytest.raises(MeshError, match="inverted"):
        pf.Model(mesh, [pf.Block("all", rock)])


@pytest.mark.parametrize(("cell", "plane", "warned"), [("quad", "strain", True),
                                                      ("quad", "stress", False),
                                                      ("quad8", "strain", False)])  # fmt: skip
def test_the_incompressibility_warning_only_where_cells_lock(
    cell: str, plane: str, warned: bool
) -> None:
    """ν = 0.495 is warned where first-order cells lock: not on quadratic cells, nor in
    plane stress (λ* = 2λμ/(λ + 2μ) stays finite as ν → ½)."""
    import warnings

    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        pf.Model(pf.rectangle(2.0, 1.0, 2, 1, cell=cell),
                 [pf.Block("all", pf.Elastic(30e9, 0.495, 2400.0))], plane=plane)  # fmt: skip
    assert any("nearly incompressible" in str(w.message) for w in said) == warned


def test_a_crack_that_alternates_takes_the_longest(caplog: pytest.LogCaptureFixture) -> None:
    """A dam engineer's 60 m section (tests/data/dam60_q8.msh) on rock 100 times stiffer
    than the concrete, pool at the crest with its pressure on the reservoir floor, full
    uplift without drains, a residual cohesion of 0.5 MPa and φ = 40°: the crack from the
    heel went 13.5, 18, 16.5 and 18 m again, each held under its full uplift, and the
    static analysis stopped with no answer (a SolverError, exit 1). Now the longest is
    taken with full headwater in it, and warned. Its state balances the dam: the base's
    normal forces and the uplift carry the weight, ρ g × the section's area, to
    round-off."""
    from pathlib import Path

    mesh = pf.read_mesh(Path(__file__).parent / "data" / "dam60_q8.msh")
    blocks = [pf.Block("dam", pf.Elastic(25e9, 0.2, 2400.0)),
              pf.Block("rock", pf.Elastic(2.5e12, 0.25, 10.0))]  # fmt: skip
    joint = pf.Joint(phi=40.0, c_r=0.5e6)
    m = pf.Model(mesh, blocks, interfaces=[pf.Interface("base", joint)], check_units=False)
    m.fix("rock_bottom")
    m.add_gravity(9.81)
    for face in ("upstream", "reservoir_floor"):
        m.add_pressure(face, lambda x: 9810.0 * np.maximum(60.0 - x[..., 1], 0.0), level=60.0)
    m.add_uplift("base", headwater=60.0)
    with caplog.at_level(logging.WARNING, logger="pfeie"):
        st = pf.solve_static(m)
    assert st.cracks == (18.0,)
    assert "(16.5; 18 m; its tip between two pairs" in caplog.text  # (the cycle alone)
    assert "the longest, 18 m, is taken" in caplog.text
    assert m.pairs is not None and st.pairs is not None and st.uplift is not None
    base = m.pairs.of("base")
    N = float(st.pairs.X[base, -1].sum())
    U = float((st.uplift[base] * m.pairs.area[base]).sum())
    # the section (the mesh's README): x from 0 to B − 0.8 y up to the kink at y_k =
    # 52.5 m, then the crest column 6 m wide up to 60 m; its area and first moment about
    # the heel, ∫ x_r dy and ∫ x_r²/2 dy
    B, y_k, crest, h = 48.0, 52.5, 6.0, 60.0
    area = B * y_k - 0.4 * y_k**2 + crest * (h - y_k)
    moment = (B**3 - (B - 0.8 * y_k) ** 3) / (6 * 0.8) + crest**2 / 2 * (h - y_k)
    W = 2400.0 * 9.81 * area
    carried = N + U
    assert carried == pytest.approx(W, rel=1e-14)  # (measured 2e-16; the solve's round-off)
    # the summary's gravity-method quantities (EM 1110-2-2100), against the dam's
    # equilibrium by hand with this crack: N' = W − U, and the moments about the heel of
    # the weight, the headwater (½γh² at h/3) and the uplift (γh over the crack c, then
    # linear to the toe)
    from pfeie._job import _compression_text, _static_joints

    j = _static_joints(m, st)["base"]
    gh, c = 9810.0 * h, 18.0
    H = 0.5 * 9810.0 * h**2
    U_hand = gh * c + 0.5 * gh * (B - c)
    x_U = (gh * c * c / 2 + 0.5 * gh * (B - c) * (c + (B - c) / 3)) / U_hand
    x_R = (W * moment / area + H * h / 3 - U_hand * x_U) / (W - U_hand)
    uplift = U
    assert j["crack_m"] == 18.0 and uplift == pytest.approx(U_hand, rel=1e-14)
    assert j["normal_resultant_at_m"][0] == pytest.approx(x_R, rel=1e-14)  # (measured 2e-16)
    assert abs(j["normal_resultant_at_m"][1]) < 1e-12
    # in contact: under the 18 m crack's full uplift the base opens over less than 18 m
    # (hence the cycle) and more than the first 13.5 m
    assert 1 - c / B <= j["contact_share"] <= 1 - 13.5 / B
    text = _compression_text(j, " a metre")
    assert (
        "crack at full uplift 18.00 m (normal: effective, the uplift apart); forces a metre" in text
    )
