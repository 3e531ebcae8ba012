"""Defects found in the thirty-second review, each test failing on the code before its fix."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import pfeie as pf
from pfeie.errors import MeshError
from pfeie.mesh import Mesh, check_cells

# -- overlapping regions that share no node ------------------------------------------------


def _two(a: Mesh, shift: list[float], names: tuple[str, str] = ("dam", "rock")) -> Mesh:
    """``a`` and a copy of it moved by ``shift``, each with its own nodes and group."""
    pts = np.vstack([a.points, a.points + np.asarray(shift)])
    cells = {k: np.vstack([c, c + a.n_points]) for k, c in a.cells.items()}
    n = {k: c.shape[0] for k, c in a.cells.items()}
    groups = {names[0]: {k: np.arange(m) for k, m in n.items()},
              names[1]: {k: np.arange(m, 2 * m) for k, m in n.items()}}  # fmt: skip
    return Mesh(pts, cells, cell_groups=groups)


@pytest.mark.parametrize(
    ("cell", "shift", "facets"),
    [("quad", [1.3, 0.0], 4), ("triangle", [0.5, 0.25], 6), ("quad8", [0.1, 0.7], 10),
     ("hexahedron", [1.0, 0.5, 0.3], 4), ("tetra10", [0.3, 0.2, 0.1], 80)],
)  # fmt: skip
def test_regions_that_overlap_with_no_node_in_common_are_refused(
    cell: str, shift: list[float], facets: int
) -> None:
    """Two volumes that overlap, not fragmented (gmsh's BooleanFragments left out), have
    no node in common: no coincident nodes, no shared facet; the overlapped part had
    twice its mass and a block's boundary inside the other, without a word. Refused
    now, naming both cells and their groups. The counts are the boundary facets of the
    copy inside the other block (4 × 2 cells of 0.5 m; in 3D 4 × 2 × 2), counted by hand
    for the quads: the copy at x = 1.3 puts its left side's two edges and its ends
    inside; the Tet10 figure is the check's own (the shift puts 80 of the copy's faces
    inside), kept so that a change of its count is seen."""
    mesh = (pf.rectangle(2.0, 1.0, 4, 2, cell=cell) if len(shift) == 2
            else pf.box(2.0, 1.0, 1.0, 4, 2, 2, cell=cell))  # fmt: skip
    words = (rf"{facets} boundary facet\(s\) reach inside cells of another region, the "
             r"first at .* of 'dam' inside .* of 'rock'\): regions overlap with no node in "
             "common")  # fmt: skip
    with pytest.raises(MeshError, match=words):
        check_cells(_two(mesh, shift))


@pytest.mark.parametrize("cell", ["quad", "triangle", "hexahedron", "tetra10"])
def test_blocks_that_meet_on_coincident_or_hanging_nodes_are_accepted(cell: str) -> None:
    """The overlap checks give no false alarm where blocks meet: side by side and one on
    top of the other on coincident nodes (a joint meshed apart), or a block meshed finer
    on the coarser one's face (hanging nodes: a warning elsewhere, not an overlap)."""
    planar = cell in ("quad", "triangle")
    mesh = (pf.rectangle(2.0, 1.0, 4, 2, cell=cell) if planar
            else pf.box(2.0, 1.0, 1.0, 4, 2, 2, cell=cell))  # fmt: skip
    for shift in ([2.0, 0.0], [0.0, 1.0]) if planar else ([2.0, 0.0, 0.0], [0.0, 0.0, 1.0]):
        check_cells(_two(mesh, shift))
    fine = (pf.rectangle(2.0, 1.0, 12, 6, cell=cell, origin=(0.0, 1.0)) if planar
            else pf.box(2.0, 1.0, 1.0, 12, 6, 6, cell=cell, origin=(0.0, 0.0, 1.0)))  # fmt: skip
    pts = np.vstack([mesh.points, fine.points])
    both = Mesh(pts, {k: np.vstack([c, fine.cells[k] + mesh.n_points])
                      for k, c in mesh.cells.items()})  # fmt: skip
    check_cells(both)


@pytest.mark.parametrize("cell", ["triangle", "tetra"])
def test_a_region_meshed_twice_on_its_own_boundary_is_refused(cell: str) -> None:
    """A square (a cube) meshed twice on the same boundary mesh but with other cells
    inside (two volumes on one surface loop): each boundary facet is shared by two cells
    on the same side of it, where the two cells of a facet inside a mesh lie on either
    side. No facet has three cells, so the earlier checks passed it: a block of twice its
    mass. The count is every boundary facet (4 edges; the cube's 12 triangles)."""
    if cell == "triangle":  # the square's two diagonals
        pts = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
        conn = np.array([[0, 1, 2], [0, 2, 3], [0, 1, 3], [1, 2, 3]])
        count = 4
    else:  # the cube of five tetrahedra, and again as 12 from a centre node on its faces
        pts = np.array([[x, y, z] for z in (0.0, 1.0) for y in (0.0, 1.0) for x in (0.0, 1.0)]
                       + [[0.5, 0.5, 0.5]])  # fmt: skip
        five = np.array([[0, 1, 2, 4], [1, 3, 2, 7], [1, 4, 5, 7], [2, 6, 4, 7], [1, 2, 4, 7]])
        faces = five[:, [[1, 2, 3], [0, 2, 3], [0, 1, 3], [0, 1, 2]]].reshape(-1, 3)
        keys, count_of = np.unique(np.sort(faces, axis=1), axis=0, return_counts=True)
        outer = keys[count_of == 1]
        conn = np.vstack([five, np.column_stack([outer, np.full(len(outer), 8)])])
        conn = np.array([c if np.linalg.det(pts[c[1:]] - pts[c[0]]) > 0 else c[[0, 2, 1, 3]]
                         for c in conn])  # fmt: skip
        count = len(outer)
    mesh = Mesh(pts, {cell: conn}, cell_groups={"dam": {cell: np.arange(conn.shape[0])}})
    words = (rf"{count} facet\(s\) shared by two cells on the same side of it, the first "
             r"at .*'dam'.*: two regions meshed over one another")  # fmt: skip
    with pytest.raises(MeshError, match=words):
        check_cells(mesh)


# -- joint laws of one's own -----------------------------------------------------------------


class _Frozen:
    """Mohr-Coulomb (c, μ, no tension) written as a user would, with its areas frozen at
    the model's pairs: it ignores the ``area`` argument, so it is right only if the scheme
    asks at the true areas and scales the forces itself."""

    def __init__(self, c: float, c_r: float, mu: float, area: np.ndarray) -> None:
        self.c, self.c_r, self.mu, self.area = c, c_r, mu, area
        self.initial, self.kn, self.ks, self.gap = "intact", None, None, 0.0

    def strength(self, area: np.ndarray, broken: np.ndarray, path: np.ndarray) -> pf.Strength:
        c = np.where(broken, self.c_r, self.c) * self.area
        return pf.Strength(c, np.full(area.shape, self.mu), np.zeros(area.shape))


@pytest.mark.parametrize("scheme", ["nonsmooth-alpha", "moreau-jean"])
def test_a_law_is_asked_at_the_areas_in_square_metres(scheme: str) -> None:
    """The default scheme asked a law at the velocity level for its strength at the
    areas times Δt (a law whose cohesion force is not c × area, a capped cohesion, was
    25 times too strong there), where Moreau-Jean asked at the areas and scaled the
    forces. Both now ask at the areas in m² and multiply the forces by Δt themselves: a
    bonded block with a residual cohesion that breaks and slides under a base acceleration
    above its strength gives, with a law that ignores its area argument, the bits of
    pf.Joint."""
    from pfeie.verification._models import block_on_base

    c, c_r, phi = 2e3, 1e3, 30.0
    ref = block_on_base(joint=pf.Joint(c=c, c_r=c_r, phi=phi, initial="intact"), n=4)
    assert ref.pairs is not None
    area = ref.pairs.area.copy()
    own = block_on_base(joint=_Frozen(c, c_r, np.tan(np.radians(phi)), area), n=4)  # type: ignore[arg-type]
    gm = pf.GroundMotion.from_function(lambda t: 0.9 * 9.81 * np.sin(4 * np.pi * t), 0.5, 1e-3)
    runs = []
    for model in (ref, own):
        an = pf.Dynamic(model, 0.002, scheme=scheme)
        runs.append(an.run(duration=0.5, start=pf.solve_static(model), ground=[gm]))
    assert runs[0].broken[-1].all()  # it breaks, and slides: its slip by the law
    assert np.abs(runs[0].s[-1, :, 0]).min() > 2e-4  # measured 0.35 and 0.24 mm
    for got, want in ((runs[1].s, runs[0].s), (runs[1].X, runs[0].X)):
        np.testing.assert_array_equal(got, want)


def test_the_contact_data_and_answers_of_a_law_are_checked() -> None:
    """A law of one's own was taken with a state 'bonded' (read as intact), kn = 0 (a bare
    ZeroDivisionError), kn < 0 (a run), a negative gap; its answers negative, NaN, of the
    wrong shape or a tuple went into the solver (a frictionless joint, a NaN residual, a
    numpy broadcast error). Each is now a ModelError naming the interface, the law and
    the value."""
    from pfeie.verification._models import block_on_base

    good = {"initial": "broken", "kn": None, "ks": None, "gap": 0.0}

    def law(answer: object = None, **data: object) -> object:
        cls = type("Mine", (), {**good, **data, "strength": lambda self, a, b, p: answer})
        return cls()

    for data, words in [
        ({"initial": "bonded"}, r"initial: expected 'intact' or 'broken', got str 'bonded'"),
        ({"kn": 0.0}, r"kn: expected None \(a rigid contact\) or a number >= 1 Pa/m, got "
                      r"float 0.0"),
        ({"ks": -1e9}, r"ks: expected None .* got float -1000000000.0"),
        ({"kn": np.ones(2)}, r"kn: expected None .* got ndarray"),
        ({"gap": -1e-3}, r"gap: expected a number >= 0 \(m\), got float -0.001"),
        ({"initial": "intact", "gap": 1e-3}, r"gap = 0.001 m on an intact \(bonded\) joint"),
    ]:  # fmt: skip
        with pytest.raises(pf.ModelError, match=r"interface 'joint': joint law Mine: " + words):
            pf.Interface("joint", law(**data))  # type: ignore[arg-type]
    no_gap = type("NoGap", (), {"initial": "broken", "kn": None, "ks": None,
                                "strength": lambda self, a, b, p: None})  # fmt: skip
    with pytest.raises(pf.ModelError, match=r"got NoGap .*, which lacks gap"):
        pf.Interface("joint", no_gap())  # type: ignore[arg-type]
    k = 5  # pairs of the block below
    z = np.zeros(k)
    for answer, words in [
        ((z, z, z), r"returned tuple; expected a pfeie.interface.Strength"),
        (pf.Strength(z, -np.ones(k), z), r"friction \(-: μ\) must be finite and >= 0; got "
                                         r"-1.0 at 5 of its 5 pairs"),
        (pf.Strength(z, np.full(k, np.nan), z), r"friction .* got nan"),
        (pf.Strength(z, np.ones(k + 1), z), r"friction has shape \(6,\); expected \(5,\)"),
        (pf.Strength(z, np.ones(k), np.ones(k)), r"tension 1 N lies beyond the apex"),
    ]:  # fmt: skip
        model = block_on_base(joint=law(answer), n=4)  # type: ignore[arg-type]
        with pytest.raises(
            pf.ModelError,
            match=r"interface 'joint': joint law Mine: "
            r"strength\(area, broken, path\).*" + words,
        ):
            pf.solve_static(model)


class _Plain:
    """A law of one's own without a repr of its parameters (the default object repr
    holds its address)."""

    def __init__(self, mu: float) -> None:
        self.mu = mu
        self.initial, self.kn, self.ks, self.gap = "broken", None, None, 0.0

    def strength(self, area: np.ndarray, broken: np.ndarray, path: np.ndarray) -> pf.Strength:
        return pf.Strength(np.zeros(area.shape), np.full(area.shape, self.mu),
                           np.zeros(area.shape))  # fmt: skip


def test_a_law_of_ones_own_is_hashed_and_recorded_by_its_fields() -> None:
    """The digest of a Python run hashed repr(law), which for a class of one's own holds
    its address: the same model built twice hashed differently. It now hashes the law's
    class, contact data and fields: the same law built again hashes the same, another μ
    differently; the shipped laws keep their digests (their repr). The model summary
    gave only the class name: it now gives the class's module and name, the contact data
    and the plain fields."""
    from pfeie.io._modelfile import _joint_laws, _model_digest
    from pfeie.verification._models import block_on_base

    spec: dict[str, dict[str, float]] = {"analysis": {}}

    def digest(law: object) -> str:
        return _model_digest(block_on_base(joint=law, n=2), spec, [])  # type: ignore[arg-type]

    assert digest(_Plain(0.5)) == digest(_Plain(0.5)) != digest(_Plain(0.6))
    assert digest(pf.Joint(phi=30.0)) == digest(pf.Joint(phi=30.0)) != digest(pf.Joint(phi=31.0))
    entry = _joint_laws(block_on_base(joint=_Plain(0.5), n=2))["joint"]  # type: ignore[arg-type]
    assert entry == {"law": "_Plain", "initial": "broken", "class": "test_review32._Plain",
                     "gap": 0.0, "fields": {"mu": 0.5, "initial": "broken", "kn": None,
                                            "ks": None, "gap": 0.0}}  # fmt: skip


def test_a_python_resume_by_another_analysis_is_refused() -> None:
    """Dynamic.run(resume=checkpoint) took a checkpoint of a run with another joint law
    (a tester resumed a softening run of μ 0.6 → 0.35 with μ = 0.1: 0.17 m of slip the
    other way) or another Δt without a word; the command line's resume checks its run
    key, the Python one checked the records only. A checkpoint now carries the analysis'
    key (settings, matrices, pairs and laws): a run resumed by an analysis of the same
    model built again continues to the bits of the run never stopped; another law, or
    another Δt, is refused, naming both."""
    from pfeie.verification._models import block_on_base

    gm = pf.GroundMotion.from_function(lambda t: 0.5 * 9.81 * np.sin(4 * np.pi * t), 0.4, 1e-3)

    def analysis(mu: float, dt: float = 0.002) -> pf.Dynamic:
        return pf.Dynamic(block_on_base(joint=_Plain(mu), n=2), dt)  # type: ignore[arg-type]

    an = analysis(0.3)
    kept: list[object] = []
    whole = an.run(duration=0.4, ground=[gm])
    an.run(duration=0.2, ground=[gm], on_checkpoint=kept.append)
    cp = kept[-1]
    again = analysis(0.3).run(duration=0.2, ground=[gm], resume=cp)  # type: ignore[arg-type]
    np.testing.assert_array_equal(again.s[-1], whole.s[-1])
    for other, words in ((analysis(0.1), r"joint laws 'joint': _Plain \(or their settings"),
                         (analysis(0.3, 0.001), r"this one has Δt = 0.001 s")):  # fmt: skip
        head = r"resume: the checkpoint was taken by another analysis \(Δt = 0.002 s, .*"
        with pytest.raises(pf.ModelError, match=head + words):
            other.run(duration=0.2, ground=[gm], resume=cp)  # type: ignore[arg-type]


def test_a_block_turning_in_a_small_rotation_run_is_warned() -> None:
    """A rock tester's column rocking on its corner turned 2.3° by 2 s in the default
    small-rotation run, where the rigid rocking solution and a large-rotation run turn
    4.4°, with no word (the "large motion" line starts at 30°). A floating block of a
    small-rotation run that turns past 1° now gets the line "rotation", naming the
    setting; the same column in a large-rotation run gets none. Here the column of
    tests/test_summary.py (1 m × 4 m on a 20° plane, b/h < tan 20°: it topples) for
    0.4 s: 1.7° in both runs."""
    from pathlib import Path

    from pfeie._job import SMALL_TURN_DEG, Job, format_summary, reliability, summarize
    from pfeie.verification._models import block_on_base

    model = block_on_base(joint=pf.Joint(phi=45.0), width=1.0, height=4.0, n=2, ny=4,
                          incline_deg=20.0, E=30e9)  # fmt: skip
    top = int(np.argmax(model.mesh.points[:, 1]))
    for large in (False, True):
        res = pf.Dynamic(model, 4e-3, large_rotation=large).run(0.4, probes=[top])
        spec = {"title": "t", "analysis": {"dt": 4e-3, "large_rotation": large}, "output": {}}
        job = Job(Path("t.toml"), spec, model, [], {"top": top}, "0" * 64)
        s = summarize(job, None, res)
        b = s["bodies"]["block"]
        turn = np.degrees(np.abs(res.rigid[:, 1, 2] - res.rigid[0, 1, 2]))
        assert 1.5 < turn.max() < 30.0  # measured 1.68°: short of "large motion"
        if large:
            assert "small_rotation_beyond_s" not in b
            assert not [w for w in reliability(s) if w.label == "rotation"]
            continue
        assert b["small_rotation_beyond_s"] == res.t[np.argmax(turn > SMALL_TURN_DEG)]
        (w,) = [w for w in reliability(s) if w.label == "rotation"]
        assert w.text.startswith(f"block block turned by up to {turn.max():.3g}° (past 1°")
        assert "take analysis.large_rotation = true" in w.text
        assert "  rotation     block block turned by up to" in format_summary(s)


def test_the_coupling_operators_refuse_wrong_arguments_by_name() -> None:
    """A code review found untyped errors: an InterfaceSolver given a W of the wrong size
    failed in a numpy broadcast; with_laws of other springs raised a bare ValueError (in
    two places, the same check). Both are ModelErrors now, the size named."""
    from pfeie.interface import InterfaceSolver, PairLaws

    laws = PairLaws.from_interfaces(np.ones(2), np.zeros(2, dtype=np.int64), [pf.Joint()], 2)
    with pytest.raises(pf.ModelError, match=r"W has shape \(3, 3\); the laws have 2 pair\(s\) "
                                            r"of 2 component\(s\): expected \(4, 4\)"):  # fmt: skip
        InterfaceSolver(np.eye(3), laws)
    solver = InterfaceSolver(np.eye(4), laws)
    soft = PairLaws.from_interfaces(np.ones(2), np.zeros(2, dtype=np.int64),
                                    [pf.Joint(kn=1e9, ks=1e9)], 2)  # fmt: skip
    with pytest.raises(pf.ModelError, match="with_laws needs the same joint compliance"):
        solver.with_laws(soft)


def test_a_modal_run_says_nothing_of_the_time_step(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    """``pfeie modal`` printed the warning that analysis.dt is coarser than the record's
    sampling (a rock tester's model), though a modal analysis takes no time step. The
    run still says it."""
    import logging

    from pfeie.io import load_job
    from test_cli import SMALL, _write

    p = _write(tmp_path, SMALL.replace("dt = 0.005", "dt = 0.02"))
    with caplog.at_level(logging.WARNING):
        load_job(p, modal=True)
    assert "coarser than the record's sampling" not in caplog.text
    with caplog.at_level(logging.WARNING):
        load_job(p)
    assert "analysis.dt = 0.02 s is coarser than the record's sampling (0.005 s)" in caplog.text
