"""Findings of the thirty-third session's reviews and testers, each a test that failed on
the code before its fix."""

from __future__ import annotations

import re

import numpy as np
import pytest

import pfeie as pf
from pfeie.errors import SettingsError
from pfeie.verification._models import block_on_base, block_on_base_3d, slip_x

G = 9.81


# -- typed settings: a wrong field is a ModelError naming it, not pydantic's error -------


_GT0 = "Input should be greater than 0"


@pytest.mark.parametrize(
    ("cls", "kw", "said"),
    [
        (pf.DynamicSettings, {"dt": -1.0}, f"DynamicSettings: dt: {_GT0}, got -1.0"),
        (pf.DynamicSettings, {"dt": "0.01"},
         "DynamicSettings: dt: Input should be a valid number, got '0.01'"),
        (pf.DynamicSettings, {"dtt": 0.01}, "DynamicSettings: dtt: Extra inputs"),
        (pf.SolverSettings, {"tolerance": 0.0}, f"SolverSettings: tolerance: {_GT0}"),
        (pf.SolverSettings, {"max_iter": 2.5},
         "SolverSettings: max_iter: Input should be a valid integer"),
    ],
)  # fmt: skip
def test_settings_errors_are_typed(cls: type, kw: dict[str, object], said: str) -> None:
    """Built directly, the settings raise a SettingsError (a ModelError and a ValueError)
    with the message of the analyses that take them; strict, as there (a string for a
    number is refused). Before: pydantic's ValidationError, and '0.01' taken as 0.01."""
    with pytest.raises(SettingsError) as info:
        cls(**kw)
    assert isinstance(info.value, pf.ModelError) and isinstance(info.value, ValueError)
    assert str(info.value).startswith(said)
    assert cls(**{}) == cls()  # the defaults still build


# -- a static analysis that finds no equilibrium gives the rigid blocks' factor of safety --


def _tilted(dim: int, theta: float, joint: pf.Joint) -> pf.Model:
    t = np.radians(theta)
    if dim == 2:
        m = block_on_base(joint=joint, gravity=False, n=4)
        m.add_gravity(direction=[np.sin(t), -np.cos(t)])
    else:
        m = block_on_base_3d(joint=joint, gravity=False, n=3)
        m.add_gravity(direction=[np.sin(t), 0.0, -np.cos(t)])
    return m


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize(("theta", "c_r"), [(35.0, 0.0), (45.0, 0.0), (40.0, 2000.0)])
def test_rigid_factor_of_safety_in_the_message(dim: int, theta: float, c_r: float) -> None:
    """A block of weight W (1 m, 2400 kg/m³) on a plane tilted by θ beyond φ = 30°, with a
    residual cohesion c_r over its area A: limit equilibrium gives F = (c_r A + W cos θ
    tan φ) / (W sin θ) < 1 (0.824, 0.577; 0.861 with cohesion). The message says the
    strengths would have to be multiplied by 1/F and gives F, to the bisection's 1e-3 (the
    3D cone's octagon is exact along x, a side's normal). Before: the unbalanced share of
    the load only, which is no factor of safety."""
    joint = pf.Joint(phi=30.0, c_r=c_r)
    model = _tilted(dim, theta, joint)
    W = 2400.0 * G  # the block's weight (1 m³, or 1 m² × 1 m thick)
    A = 1.0
    t = np.radians(theta)
    F = (c_r * A + W * np.cos(t) * np.tan(np.radians(30.0))) / (W * np.sin(t))
    assert F < 1.0
    with pytest.raises(pf.PfeieError) as info:
        pf.solve_static(model)
    msg = str(info.value)
    found = re.search(r"multiplied by ([0-9.]+): a rigid-block factor of safety of ([0-9.]+)",
                      msg)  # fmt: skip
    assert found is not None, msg
    assert float(found.group(2)) == pytest.approx(F, rel=2e-3)  # 4 digits printed, bracket 1e-3
    assert float(found.group(1)) == pytest.approx(1.0 / F, rel=2e-3)
    assert ("octagon" in msg) == (dim == 3)


def test_rigid_factor_bisection() -> None:
    """The factor itself, to its tolerance: the 2D block pushed by k = 0.7 g on a level
    joint of φ = 30°: F = tan φ / k = 0.8248 (limit equilibrium), bracketed to 1e-3; a
    held block (k = 0.3 g) gives F = tan φ / k = 1.925 > 1."""
    from pfeie.coupling import StaticInterfaceProblem

    for k in (0.7, 0.3):
        model = block_on_base(joint=pf.Joint(phi=30.0))
        model.add_inertia([k * G, 0.0])
        problem = StaticInterfaceProblem(model, model.system())
        F = problem.rigid_factor(model.system().load(0.0))
        exact = np.tan(np.radians(30.0)) / k
        assert F is not None and exact / (1 + 1e-3) <= F <= exact


# -- the apex of the cone is checked on the strengths a pair can have ----------------------


def test_unused_intact_tension_of_an_existing_joint_runs() -> None:
    """A bonded joint and an existing one (initial 'broken') given a tensile strength
    beyond c / tan φ, which it never has (pf.Joint and the model file accept it): the
    solver asks every pair's intact strength while a joint is intact, and 0.3.21 stopped
    the run on the existing joint's unused value. It runs, and the bonded joint's own
    apex is still checked."""
    mesh = pf.rectangle(1.0, 3.0, nx=2, ny=6)
    mesh.points[:, 1] -= 1.0
    mesh.add_cell_group("base", lambda x: x[:, 1] < 0)
    mesh.add_cell_group("mid", lambda x: (x[:, 1] > 0) & (x[:, 1] < 1))
    mesh.add_cell_group("top", lambda x: x[:, 1] > 1)
    mesh.add_facet_group("bond", lambda x: np.abs(x[:, 1]) < 1e-9, boundary_only=False)
    mesh.add_facet_group("old", lambda x: np.abs(x[:, 1] - 1) < 1e-9, boundary_only=False)
    mat = pf.Elastic(30e9, 0.2, 2400.0)
    bond = pf.Joint(c=1e6, phi=45.0, tensile=1e5, initial="intact")
    old = pf.Joint(phi=30.0, tensile=1e5, initial="broken")
    m = pf.Model(mesh, [pf.Block(g, mat) for g in ("base", "mid", "top")],
                 interfaces=[pf.Interface("bond", bond), pf.Interface("old", old)])  # fmt: skip
    m.fix("base")
    m.add_gravity()
    st = pf.solve_static(m)
    gm = pf.GroundMotion.from_function(lambda t: 0.8 * G * np.sin(4 * np.pi * t), 0.5, 1e-3)
    res = pf.Dynamic(m, 2e-3).run(n_steps=60, ground=[gm], start=st)
    assert res.completed and res.t[-1] == pytest.approx(0.12)
    # the top block slides on the existing joint (0.8 g > tan 30°): its law was used
    top, mid = (m.body_names().index(b) for b in ("top", "mid"))
    assert np.ptp(slip_x(res, top) - slip_x(res, mid)) > 1e-4


class _Apex:
    """A law whose intact strength lies beyond the apex (tension 2 MPa, c 1 MPa, μ 1)."""

    initial, kn, ks, gap = "intact", None, None, 0.0

    def strength(self, area: np.ndarray, broken: np.ndarray, path: np.ndarray) -> pf.Strength:
        return pf.Strength(np.where(broken, 0.0, 1e6 * area), np.ones_like(area),
                           np.where(broken, 0.0, 2e6 * area))  # fmt: skip


def test_apex_of_an_intact_joint_is_still_refused() -> None:
    m = block_on_base(joint=_Apex())  # type: ignore[arg-type]
    with pytest.raises(pf.ModelError, match="beyond the apex"):
        pf.solve_static(m)


# -- uplift under shaking = "full" in 3D: the crack across the joint's face ----------------


@pytest.mark.parametrize(
    ("name", "opened", "wet"),
    [
        ("heel band, whole width", lambda x, y: x <= 0.5, 10),
        ("heel band, half the width", lambda x, y: (x <= 0.5) & (y >= 1.0), 6),
        ("heel band but one heel pair",
         lambda x, y: (x <= 0.5) & ~((x < 0.1) & (abs(y - 1) < 0.1)), 9),
        ("lateral edge, heel to toe", lambda x, y: y >= 2.0, 5),
        ("toe band (lifts as it rocks)", lambda x, y: x >= 1.5, 0),
        ("an island in the middle", lambda x, y: (abs(x - 1) < 0.1) & (abs(y - 1) < 0.1), 0),
    ],
)  # fmt: skip
def test_full_uplift_follows_the_crack_across_a_3d_joint(name: str, opened, wet: int) -> None:  # type: ignore[no-untyped-def]
    """A 2 m cube on a 4 × 4 joint (25 pairs, heel x = 0) with uplift 'full': the pairs that
    open get the headwater pressure ρ_w g (H_w − z) where the crack reaches them from the
    heel through open pairs, across the face. 0.3.21 wet 3 of 6, 4 of 9 and 1 of 5 pairs
    in the second to fourth cases (its crack was the static line rule)."""
    m = block_on_base_3d(joint=pf.Joint(phi=40.0), size=2.0, n=4)
    m.add_uplift("joint", headwater=3.0, shaking="full")
    st = pf.solve_static(m)
    ex = pf.Dynamic(m, 1e-3).excitation((), "relative", st)
    seen: dict[str, np.ndarray] = {}
    load = m.uplift_load
    m.uplift_load = lambda p: (seen.__setitem__("p", p.copy()), load(p))[1]  # type: ignore[method-assign]
    P = m.pairs
    assert P is not None
    open_ = opened(np.round(P.x[:, 0], 9), np.round(P.x[:, 1], 9))
    ex.follow(open_.copy())
    full = 1000.0 * G * (3.0 - P.x[:, -1])
    assert int((np.isclose(seen["p"], full, rtol=1e-12) & open_).sum()) == wet
    # the others keep their static pressure
    assert np.array_equal(seen["p"][~open_], st.uplift[~open_])


def _zoned(fields: str, prelude: str = "") -> str:
    """The code of a process that prints the digest of law_key of a law of one's own,
    ``Zoned``, with the dataclass ``fields`` (lines of its body) before the law's own, and
    ``prelude`` (classes it uses) before it."""
    return f"""
import hashlib
from dataclasses import dataclass, field
import numpy as np
import pfeie as pf
from pfeie.interface import law_key
{prelude}
@dataclass(frozen=True)
class Zoned:
{fields}
    initial: str = "broken"
    kn: float | None = None
    ks: float | None = None
    gap: float = 0.0

    def strength(self, area, broken, path):
        z = np.zeros_like(area)
        return pf.Strength(z, np.full_like(area, 0.6), z)

print(hashlib.sha256(law_key(Zoned())).hexdigest())
"""


def seed_keys(code: str, seeds: tuple[str, ...]) -> set[str]:
    """What the process ``code`` prints under each hash seed (PYTHONHASHSEED)."""
    import os
    import subprocess
    import sys
    from pathlib import Path

    src = str(Path(pf.__file__).resolve().parents[1])
    keys = set()
    for seed in seeds:
        env = {**os.environ, "PYTHONHASHSEED": seed, "PYTHONPATH": src}
        out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                             text=True, check=True)  # fmt: skip
        keys.add(out.stdout.strip())
    return keys


def test_law_key_is_the_same_in_every_process() -> None:
    """A law of one's own with a set and a mapping among its fields: its key (and so the
    run's digest and Dynamic.key) is the same under any hash seed. 0.3.21 hashed their
    repr, whose order follows the seed (three seeds, three digests)."""
    code = _zoned(
        '    weak: frozenset = frozenset({"heel", "toe", "gallery", "drain", "core"})\n'
        '    table: dict = field(default_factory=lambda: {"b": {1, 2, 3}, "a": (0.5, {"x", "y"})})'
    )  # fmt: skip
    assert len(seed_keys(code, ("1", "2", "3"))) == 1


# -- Westergaard's added mass on a level face is warned ----------------------------------


@pytest.mark.parametrize("dim", [2, 3])
def test_westergaard_on_a_level_face_is_warned(dim: int, caplog: pytest.LogCaptureFixture) -> None:
    """A reservoir floor listed among Westergaard's wet faces (a 3D dam engineer copied the
    hydrostatic groups) added 14,700 t of vertical added mass, 15 times the foundation's
    mass, with no word. The level face is warned, naming the group; the dam's face is not."""
    import logging

    if dim == 2:
        mesh = pf.rectangle(2.0, 10.0, 2, 4)
        face, floor = "xmin", "ymin"
    else:
        mesh = pf.box(2.0, 2.0, 10.0, 2, 2, 4)
        face, floor = "xmin", "zmin"
    m = pf.Model(mesh, [pf.Block("all", pf.Elastic(30e9, 0.2, 2400.0))])
    with caplog.at_level(logging.WARNING, logger="pfeie.model._model"):
        m.add_westergaard(face, water_level=10.0)
        assert "level" not in caplog.text
        m.add_westergaard([face, floor], water_level=10.0, bottom=-1.0)
    said = [r.getMessage() for r in caplog.records if "Westergaard's added mass" in r.getMessage()]
    assert len(said) == 1 and said[0].startswith(f"westergaard on {floor!r}: 100 % of its wet")


# -- a 2D habit in a 3D model file: the vertical record on y -----------------------------


def test_vertical_record_on_y_in_3d_is_explained(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    """One record given along y twice in a 3D model (a cross-stream component and, by a
    2D habit, the vertical one): refused as a copy that would count twice, and now told
    that in 3D the vertical is z."""
    from pfeie.cli import main
    from test_cli import _write
    from test_robustness import msh22

    nodes = [(x, y, z) for z in (0.0, 1.0) for y in (0.0, 1.0) for x in (0.0, 1.0)]
    names = {1: (3, "cube"), 2: (2, "bottom")}
    elements = [(1, 3, 2, [1, 2, 4, 3]), (2, 5, 1, [1, 2, 4, 3, 5, 6, 8, 7])]
    msh22(tmp_path / "cube.msh", nodes, elements, names)
    text = """
[mesh]
file = "cube.msh"
[materials.c]
E = 30e9
nu = 0.2
rho = 2400.0
[blocks]
cube = "c"
[[supports]]
group = "bottom"
[[ground_motion]]
file = "pulse.csv"
units = "g"
component = "y"
scale = 0.5
[[ground_motion]]
file = "pulse.csv"
units = "g"
component = "y"
scale = 0.667
[analysis]
dt = 0.005
duration = DURATION
[output]
folder = "out"
"""
    path = _write(tmp_path, text)
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err
    assert "is ground_motion[0] again" in err and "in 3D the vertical axis is z" in err


# -- a joint in pieces between different blocks: each piece in the summary --------------


def test_joint_pieces_in_the_summary(tmp_path) -> None:  # type: ignore[no-untyped-def]
    """A contraction joint cut by a lift joint: its two pieces join other blocks (the
    lower and the upper monoliths) and open differently, and the summary merged them (a
    3D dam engineer: 0.21 mm below the lift joint, 1.10 mm above, only 1.10 mm given).
    Each piece is now in summary.json and the summary's text, named by its blocks; the
    pieces' pairs make up the joint's, and its largest opening is the largest piece's."""
    import json

    from test_review34 import _monoliths

    model = _monoliths()
    gm = pf.GroundMotion.from_function(lambda t: 0.6 * G * np.sin(2 * np.pi * 4 * t), 0.25, 1e-3)
    pf.run_to_folder(pf.Dynamic(model, 2e-3), 0.25, tmp_path / "out", ground=[gm],
                     start=pf.solve_static(model), figures=False, paraview=False)  # fmt: skip
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    cj = s["joints"]["cj"]
    assert set(cj["pieces"]) == {"ll | lr", "ul | ur"}
    assert sum(q["pairs"] for q in cj["pieces"].values()) == cj["pairs"]
    assert max(q["max_opening_m"] for q in cj["pieces"].values()) == cj["max_opening_m"]
    assert set(s["joints"]["lift"]["pieces"]) == {"ll | ul", "lr | ur"}
    assert set(s["joints"]["base"]["pieces"]) == {"rock | ll", "rock | lr"}
    # the upper monoliths rock on the weak lift joint: their piece of cj opens more
    q = cj["pieces"]
    assert q["ul | ur"]["max_opening_m"] != q["ll | lr"]["max_opening_m"]


# -- pfeie check lists the loads ----------------------------------------------------------


def test_check_lists_the_loads(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    """`pfeie check` gave no word of the loads (a 3D dam engineer could verify them only
    after a run, in the report): each table of [loads] is now a line with its resultant;
    gravity's is the model's weight, m g (the mass of the check's own extent line), and
    the uplift (no static state yet) its parameters."""
    import json

    from pfeie.cli import main
    from test_cli import SMALL, _write

    text = SMALL.replace("[analysis]", "[[loads.uplift]]\ninterface = \"joint\"\n"
                         "headwater = 3.0\n[analysis]")  # fmt: skip
    path = _write(tmp_path, text)
    assert main(["check", str(path)]) == 0
    out = capsys.readouterr().out
    mass = float(re.search(r"mass ([0-9.e+]+) kg", out).group(1))  # type: ignore[union-attr]
    line = next(ln for ln in out.splitlines() if ln.startswith("load         gravity"))
    fy = float(re.search(r"y (-?[0-9.e+]+) kN", line).group(1))  # type: ignore[union-attr]
    assert fy == pytest.approx(-mass * G / 1e3, rel=1e-3)  # both printed to 4 digits
    assert "load         uplift on joint: headwater 3 m, no tailwater" in out
    assert main(["check", "--json", str(path)]) == 0
    s = json.loads(capsys.readouterr().out)
    assert [r["load"] for r in s["loads"]] == ["gravity", "uplift"]


# -- one region meshed twice with different meshes ---------------------------------------


@pytest.mark.parametrize("dim", [2, 3])
def test_a_region_meshed_twice_with_different_meshes_is_refused(dim: int) -> None:
    """The same square (cube) meshed 4 × 4 and 3 × 3, no node in common: every point of
    one's boundary facets lies on the other's boundary (depth 0), so the overlap check
    passed it (twice the mass and stiffness). The centroids of the cells along the
    boundary show it."""
    from pfeie.errors import MeshError
    from pfeie.mesh import Mesh, check_cells

    if dim == 2:
        a, b = pf.rectangle(1.0, 1.0, 4, 4), pf.rectangle(1.0, 1.0, 3, 3)
    else:
        a, b = pf.box(1.0, 1.0, 1.0, 3, 3, 3), pf.box(1.0, 1.0, 1.0, 2, 2, 2)
    pts = np.vstack([a.points, b.points])
    cells = {k: np.vstack([c, b.cells[k] + a.n_points]) for k, c in a.cells.items()}
    n_a = {k: c.shape[0] for k, c in a.cells.items()}
    groups = {"r0": {k: np.arange(m) for k, m in n_a.items()},
              "r1": {k: np.arange(m, cells[k].shape[0]) for k, m in n_a.items()}}  # fmt: skip
    with pytest.raises(MeshError, match=r"cells along a region's boundary lie inside cells of "
                       r"another region \(the regions' boundaries coincide"):  # fmt: skip
        check_cells(Mesh(pts, cells, cell_groups=groups))


def test_uplift_on_a_vertical_joint_is_warned(caplog: pytest.LogCaptureFixture) -> None:
    """Uplift given on a vertical contraction joint (a 3D dam engineer's slip) put every
    pair at the heel (its extent along the upstream axis is 0), so at full headwater, with
    no word. Warned now; a level joint is not."""
    import logging

    mesh = pf.rectangle(2.0, 2.0, 4, 4)
    mesh.add_cell_group("left", lambda x: x[:, 0] < 1)
    mesh.add_cell_group("right", lambda x: x[:, 0] > 1)
    mesh.add_facet_group("cj", lambda x: np.abs(x[:, 0] - 1) < 1e-9, boundary_only=False)
    mat = pf.Elastic(30e9, 0.2, 2400.0)
    m = pf.Model(mesh, [pf.Block("left", mat), pf.Block("right", mat)],
                 interfaces=[pf.Interface("cj", pf.Joint(phi=30.0))])  # fmt: skip
    with caplog.at_level(logging.WARNING, logger="pfeie.model._model"):
        m.add_uplift("cj", headwater=5.0)
    assert "uplift in 'cj': the joint is steep (its mean plane 90° from level)" in (
        caplog.text)  # (since 0.3.23 by its normal: a review of the extent rule)
    caplog.clear()
    base = block_on_base(joint=pf.Joint(phi=30.0))
    with caplog.at_level(logging.WARNING, logger="pfeie.model._model"):
        base.add_uplift("joint", headwater=5.0)
    assert "steep" not in caplog.text and "spans" not in caplog.text
