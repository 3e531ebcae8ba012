"""Findings of the twenty-ninth review.

Each test reproduces the defect and checks the fix against an independent number.
"""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import pfeie as pf
from pfeie.cli import main
from pfeie.io import Results, read_record
from test_checkpoint import run_then_stop
from test_cli import SMALL
from test_review28 import _block_on_a_joint

DATA = Path(__file__).resolve().parents[1] / "examples" / "data"


# -- the absolute form with event sub-steps ------------------------------------------------


@pytest.fixture(scope="module")
def sliding_block() -> tuple[pf.Model, pf.StaticResult, pf.GroundMotion]:
    """The README's block (μ = 0.2) under 2 × El Centro: it slides and sticks again and
    again, so that many steps are events."""
    model, _ = _block_on_a_joint()
    gm = read_record(DATA / "elcentro_1940_ns_chopra.csv", units="g", scale=2.0)
    return model, pf.solve_static(model), gm


def test_absolute_form_with_event_sub_steps_is_the_relative_form(
    sliding_block: tuple[pf.Model, pf.StaticResult, pf.GroundMotion],
) -> None:
    """Over an event step's sub-steps the supports followed the record's exact motion
    plus the coarse grid's drift interpolated, not the scheme's recurrence on the finer
    grid that carries the blocks: a body fixed to the base was strained, and the slip of
    the block differed between the forms by 1.7 % of its peak (108 sub-steps in 3 s).
    Now the supports take the recurrence of the sub-steps and the grid goes on from
    where they end. Independent computation: the relative form (the slips at the joint
    do not depend on the form); measured 1.8e-9 of the peak slip, as without sub-steps
    (2.0e-9: round-off through the stiff contact)."""
    model, static, gm = sliding_block
    slip = {}
    for form in ("relative", "absolute"):
        an = pf.Dynamic(model, 0.01, event_substeps=4)
        res = an.run(3.0, ground=[gm], start=static, form=form)
        slip[form] = res.s[:, :, 0].mean(axis=1)
        assert int(res.solver["substeps"].sum()) > 80  # 27 events in 108 sub-steps (measured)
    peak = np.abs(slip["relative"]).max()
    assert peak > 0.03  # it slides (measured 59 mm)
    assert np.abs(slip["absolute"] - slip["relative"]).max() < 1e-8 * peak


def test_absolute_form_resumed_after_events_gives_the_same_bits(
    sliding_block: tuple[pf.Model, pf.StaticResult, pf.GroundMotion],
) -> None:
    """A checkpoint keeps the supports' grid row (events moved it off the grid's own
    recurrence); a run resumed from it after events gives the bits of the run that never
    stopped. Before, the resumed supports restarted from the grid's own recurrence: a
    jump of the ground's displacement at the resume."""
    model, static, gm = sliding_block
    cks: list[pf.dynamics.Checkpoint] = []
    full = pf.Dynamic(model, 0.01, event_substeps=4).run(
        2.0, ground=[gm], start=static, form="absolute", on_checkpoint=cks.append)
    events = np.flatnonzero(full.solver["substeps"])
    row = int(events[len(events) // 2]) + 1  # after half of the events
    ck = cks[row - 1]
    assert ck.state.step == row and ck.supports is not None and ck.supports.shape == (1, 4)
    rest = pf.Dynamic(model, 0.01, event_substeps=4).run(
        n_steps=200 - row, resume=ck, ground=[gm], form="absolute")  # fmt: skip
    for key in ("rigid", "X", "s", "state", "ground"):
        np.testing.assert_array_equal(getattr(rest, key), getattr(full, key)[row:],
                                      err_msg=key)  # fmt: skip
    for key, values in full.energy.items():
        np.testing.assert_array_equal(rest.energy[key], values[row:], err_msg=key)


def test_absolute_form_with_events_resumed_from_the_results_file(tmp_path: Path) -> None:
    """``pfeie run --resume`` of a run in the absolute form with event sub-steps: the
    checkpoint in results.h5 holds ``kin/supports`` and the resumed file equals the
    uninterrupted run's, history for history."""
    text = SMALL.replace("[analysis]", '[analysis]\nform = "absolute"\nevent_substeps = 4')
    text = text.replace('units = "g"', 'units = "g"\nscale = 2.0')
    p = run_then_stop(tmp_path, text, 0.8, 0.4)
    ref_dir, ext_dir = tmp_path / "ref", tmp_path / "ext"
    with Results(ext_dir / "out" / "results.h5") as res:
        assert "kin/supports" in res.f["checkpoint"]
        assert res.f["history/solver/substeps"][:].sum() > 0  # events before the resume
    assert main(["run", str(p), "--quiet", "--resume"]) == 0
    with Results(ref_dir / "out" / "results.h5") as ref, \
            Results(ext_dir / "out" / "results.h5") as got:  # fmt: skip
        for name in ("ground", "time", "solver/substeps", "energy/balance", "energy/interface"):
            np.testing.assert_array_equal(got.f[f"history/{name}"][:], ref.f[f"history/{name}"][:],
                                          err_msg=name)  # fmt: skip
        for key, value in ref.pairs().items():
            np.testing.assert_array_equal(got.pairs()[key], value, err_msg=key)


def test_csv_export_has_the_ground(
    tmp_path: Path, sliding_block: tuple[pf.Model, pf.StaticResult, pf.GroundMotion]
) -> None:
    """``pfeie export --csv`` left out ``/history/ground``, so a probe's motion relative
    to the ground could not be had from the CSV tables of an absolute-form run. Now
    ground.csv holds it: the absolute run's probe u less the ground equals the relative
    run's probe u, relative to the ground (independent computation; measured 1.5e-8 of
    the 61 mm peak: the tables' nine significant digits of a 0.26 m ground)."""
    model, static, gm = sliding_block
    top = int(np.argmax(model.mesh.points[:, 1] + 1e-3 * model.mesh.points[:, 0]))
    u = {}
    for form in ("relative", "absolute"):
        pf.run_to_folder(pf.Dynamic(model, 0.02), 2.0, tmp_path / form, ground=[gm], form=form,
                         start=static, probes={"top": top}, figures=False, paraview=False)
        csv_dir = tmp_path / f"{form}_csv"
        assert main(["export", str(tmp_path / form / "results.h5"), "--csv", str(csv_dir)]) == 0
        probe = np.genfromtxt(csv_dir / "probes.csv", delimiter=",", names=True, dtype=None,
                              encoding="utf-8")  # fmt: skip
        sel = (probe["quantity"] == "u") & (probe["component"] == "x")
        ground = np.genfromtxt(csv_dir / "ground.csv", delimiter=",", names=True, dtype=None,
                               encoding="utf-8")  # fmt: skip
        gx = ground["value"][ground["component"] == "x"]
        np.testing.assert_array_equal(ground["time_s"][ground["component"] == "x"],
                                      probe["time_s"][sel])  # fmt: skip
        # (the relative form's probes are relative to the ground already)
        u[form] = probe["value"][sel] - (gx if form == "absolute" else 0.0)
        assert np.abs(gx).max() > 0.05  # the ground's displacement (measured 0.26 m)
    peak = np.abs(u["relative"] - u["relative"][0]).max()
    assert peak > 0.03  # the block slides
    assert np.abs(u["absolute"] - u["relative"]).max() < 1e-7 * peak


def test_a_3d_run_records_the_direction_it_ran_under(tmp_path: Path) -> None:
    """A 3D run of a record with the default direction (1, 0) runs along x, but its
    results file recorded the direction as given, ``records/0/direction = [1, 0]``: two
    components in a 3D file (a reader scaling the record by it would not broadcast).
    Now it records (1, 0, 0), as a run given that direction does (independent: the
    same run with the direction given in 3D; the histories equal bit for bit)."""
    mesh = pf.box(1.0, 1.0, 2.0, 1, 1, 2, cell="hexahedron")
    model = pf.Model(mesh, [pf.Block("all", pf.Elastic(E=30e9, nu=0.2, rho=2400))])
    model.fix("zmin")
    top = int(np.argmax(mesh.points[:, 2]))
    values = np.sin(np.linspace(0.0, 6.0, 51))
    for name, direction in (("default", (1.0, 0.0)), ("given", (1.0, 0.0, 0.0))):
        gm = pf.GroundMotion.from_samples(values, dt=0.01, units="g", direction=direction)
        pf.run_to_folder(pf.Dynamic(model, 0.005), 0.3, tmp_path / name, ground=[gm],
                         probes={"top": top}, figures=False, paraview=False)  # fmt: skip
    with Results(tmp_path / "default" / "results.h5") as a, \
            Results(tmp_path / "given" / "results.h5") as b:  # fmt: skip
        assert a.f["records/0/direction"][:].tolist() == [1.0, 0.0, 0.0]
        np.testing.assert_array_equal(a.probe("top")["u"], b.probe("top")["u"])
        np.testing.assert_array_equal(a.ground, b.ground)
        assert np.abs(a.ground[:, 0]).max() > 0 and not a.ground[:, 1:].any()


# -- studies -------------------------------------------------------------------------------


def test_a_worker_does_not_repeat_the_model_files_warnings(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    """The study's own process checks the model file and logs its warnings once; each
    Dask worker that built the system logged them again (a fresh process knew nothing of
    that check). Now the context sent to the workers says the file was checked. A fresh
    Python process stands for a worker (independent of this process's state): it builds
    the system from the pickled context and logs nothing of the model file, while the
    study's process did log the warning (loads.gravity = 98.1: given in dm/s²?)."""
    import pickle
    import subprocess
    import sys

    from pfeie.study import Study
    from test_study import STUDY, setup

    p = setup(tmp_path, STUDY, n=1)
    model = tmp_path / "model.toml"
    model.write_text(model.read_text().replace("gravity = 9.81", "gravity = 98.1"))
    with caplog.at_level("WARNING", logger="pfeie"):
        ctx = Study.from_file(p).context()
    assert "loads.gravity: g = 98.1 m/s²" in caplog.text
    (tmp_path / "ctx.pkl").write_bytes(pickle.dumps(ctx))
    script = ("import logging, pickle, sys\n"
              "logging.basicConfig(stream=sys.stdout, level=logging.WARNING)\n"
              "from pfeie.study._study import system, builds\n"
              f"system(pickle.loads(open({str(tmp_path / 'ctx.pkl')!r}, 'rb').read()))\n"
              "print('built', builds())\n")  # fmt: skip
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                         timeout=300, check=True).stdout  # fmt: skip
    assert "built 1" in out and "loads.gravity" not in out, out



# -- the yield coefficient (a dam engineer's findings) ------------------------------------

DAM_Q8 = Path(__file__).resolve().parent / "data" / "dam_q8_lift.msh"


def dam_q8(E: float) -> str:
    """The model file's mesh, materials (E in Pa, the rock light) and blocks of the dam
    of dam_q8_lift.msh."""
    return f"""
[mesh]
file = "{DAM_Q8}"
[materials.concrete]
E = {E!r}
nu = 0.2
rho = 2400.0
[materials.rock]
E = {E!r}
nu = 0.25
rho = 24.0
[blocks]
dam_lower = "concrete"
dam_upper = "concrete"
rock = "rock"
"""


def test_yield_coefficient_names_the_joint_that_slides(tmp_path: Path) -> None:
    """A stiff dam block on a friction base (μ = 0.3, no water) under a bonded lift joint
    (c = 20 MPa): k_y = μ = 0.3 both ways (a rigid block; closed form), sliding on the
    base. Along −x the last analysis held put the base at its capacity (within the pair
    solver's tolerance), its margin left out, and the search followed the lift joint's
    margin (root 48.5): 54 analyses, "no equilibrium found", the lift joint named with
    FS 156. Now a joint that comes to its capacity has its root there: 8 analyses,
    "sliding" on 'base' with FS 1 (measured 1 + 1.5e-7 and 1 − 1.5e-7)."""
    from pfeie.io import load_job

    model = tmp_path / "dam.toml"
    model.write_text(dam_q8(2.5e12) + """
[interfaces.base]
friction_angle = 16.69924423
[interfaces.lift]
cohesion = 20.0e6
friction_angle = 45.0
tensile_strength = 10.0e6
initial = "intact"
[[supports]]
group = "rock_bottom"
[analysis]
dynamic = false
""")
    job = load_job(model)
    iota = pf.solvers.horizontal(job.model, axis=0)[1]
    for sign in (1.0, -1.0):
        y = pf.yield_coefficient(job.model, sign * iota)
        # μ = tan φ (tol: the search's 1e-6 bracket)
        assert y.k_y == pytest.approx(np.tan(np.radians(16.69924423)), rel=2e-6)
        assert (y.limit, y.joint) == ("sliding", "base")
        assert y.safety_factors["base"] == pytest.approx(1.0, abs=1e-6)
        assert y.analyses <= 10  # (measured 7 and 8; 54 along −x before)


def test_a_static_mechanism_names_the_joint_that_fails(tmp_path: Path) -> None:
    """The dam of dam_q8_lift.msh after an earthquake, by hand: base and lift joints
    broken (φ = 40°), full headwater (55 m) as uplift on the whole base, and a 10 m
    tailwater. By hand the base cannot hold: its shear 14.35 MN against tan 40° × 12.06 MN
    = 10.1 MN; the lift joint holds: 3.07 MN against tan 40° × 11.12 MN = 9.33 MN. The
    error named 'dam_upper' on 'lift' (the rigid-block check's unbalance, which may land
    on any block of a stack): it now checks each joint alone, the others unbreakable, and
    names 'base' as the joint that cannot hold and 'lift' as holding. Independent check:
    with the base at φ = 60° (capacity 20.9 MN) the static analysis holds."""
    from pfeie.io import load_job

    model = tmp_path / "pe.toml"
    text = 'plane = "strain"\n' + dam_q8(25e9) + """
[interfaces.base]
friction_angle = PHI
[interfaces.lift]
friction_angle = 40.0
[[supports]]
group = "rock_bottom"
[[loads.hydrostatic]]
groups = ["upstream_lower", "upstream_upper", "reservoir_floor"]
water_level = 55.0
[[loads.hydrostatic]]
groups = ["downstream_lower", "tail_floor"]
water_level = 10.0
[[loads.pressure]]
group = "base"
value = 539550.0
[analysis]
dynamic = false
"""
    model.write_text(text.replace("PHI", "40.0"))
    with pytest.raises(pf.MechanismError) as info:
        pf.solve_static(load_job(model).model)
    msg = str(info.value)
    assert "'base' cannot hold the blocks on it even with every other joint unbreakable" in msg
    assert "'lift' holds alone" in msg and "'dam_upper' on 'lift': unbalanced" not in msg
    model.write_text(text.replace("PHI", "60.0"))
    st = pf.solve_static(load_job(model).model)
    assert st.pairs is not None and np.isfinite(st.pairs.X).all()


def test_summary_components_are_not_rounded_to_a_micrometre(tmp_path: Path) -> None:
    """The summary rounded the components of a block's residual displacement and of a
    probe's peaks to 1 µm (and 1e-6 g), not their magnitudes: a block that slid 6.8 µm
    (the README's block under 0.66 × El Centro, just above μ g) read x = 7e-6 m against a
    magnitude of 6.79e-6 m. Now the components are given in full: their norm is the
    magnitude (independent: the same summary's magnitude, computed from the same rigid
    motion; measured to 1e-16)."""
    model, top = _block_on_a_joint()
    gm = read_record(DATA / "elcentro_1940_ns_chopra.csv", units="g", scale=0.66)
    pf.run_to_folder(pf.Dynamic(model, 0.01), 4.0, tmp_path, ground=[gm],
                     start=pf.solve_static(model), probes={"top": top}, figures=False,
                     paraview=False)  # fmt: skip
    block = json.loads((tmp_path / "summary.json").read_text())["bodies"]["block"]
    assert 1e-6 < block["residual_displacement_m"] < 2e-5  # micrometres (measured 6.8 µm)
    assert float(np.hypot(*block["residual_displacement_xyz_m"])) == pytest.approx(
        block["residual_displacement_m"], rel=1e-12)


# -- the Python API: wrong arguments (a researcher's findings) -----------------------------


def _plate() -> pf.Model:
    mesh = pf.rectangle(1.0, 1.0, 2, 2)
    mesh.add_facet_group("none", lambda x: x[:, 0] < -5.0, boundary_only=False)
    return pf.Model(mesh, [pf.Block("all", pf.Elastic(1e9, 0.2, 2000.0))])


@pytest.mark.parametrize("call, words", [
    # a support or load on an empty group was dropped unseen
    (lambda m: m.fix("none"), "fix: the group 'none' has no nodes"),
    (lambda m: m.add_pressure("none", 1e3), "pressure on 'none': the facet group has no facets"),
    (lambda m: m.add_traction("none", [1.0, 0.0]), "traction on 'none': the facet group has no"),
    (lambda m: m.fix([]), "fix: no nodes given"),
    # two supports of one DOF at two values: the last one won, unseen
    (lambda m: (m.fix("xmin", 0, value=0.01), m.fix("ymin")),
     "fix ymin: its nodes share component(s) ['x'] with the support on xmin"),
    (lambda m: m.add_nodal_force("none", [1.0, 0.0]), "add_nodal_force: the group 'none' has"),
    # a mask of the nodes, or fractional indices, were taken as indices (nodes 0 and 1)
    (lambda m: m.fix(m.mesh.points[:, 0] < 1e-9), "for a mask of the nodes, np.flatnonzero"),
    (lambda m: m.fix([0.7, 3.2]), "fix: expected a group's name or integer node indices"),
    (lambda m: m.add_pressure("xmax", "1e3"), "expected a finite number or a function"),
    (lambda m: pf.solve_static(None), "solve_static: expected a pfeie.Model"),
    (lambda m: pf.solve_static(m, t=float("nan")), "solve_static: t: expected a finite time"),
    (lambda m: pf.solve_static(m, settings=[1e-8]), "settings: expected a pfeie"),
    (lambda m: pf.run_to_folder(m, 0.01, "out"), "run_to_folder: analysis: expected a pfeie"),
    (lambda m: pf.Dynamic(m, settings=3), "Dynamic: settings: expected a pfeie.DynamicSettings"),
    (lambda m: pf.Dynamic(m, 0.01).run(0.02, callback=3), "callback: expected a function"),
    (lambda m: pf.Interface("j", None), "interface 'j': joint: expected a joint law"),
    (lambda m: pf.GroundMotion.from_samples([0.0, 1.0], dt=0.01, direction="x"),
     "direction: expected the 2 or 3 components"),
    (lambda m: pf.GroundMotion.from_samples([0.0, 1.0], dt="0.01"), "dt: expected a number"),
    (lambda m: pf.GroundMotion.from_function(5.0, 1.0, 0.01), "expected a function a(t)"),
    (lambda m: pf.Rayleigh(0.1, 0.01).ratio(0), "Rayleigh.ratio: expected a frequency > 0"),
    (lambda m: pf.modal(m, 1, shift=float("nan")), "modal: shift: expected a finite"),
    (lambda m: pf.factorize("K"), "factorize: expected a sparse matrix"),
    (lambda m: m.mesh.add_facet_group("g", 5), "where: expected a function of the centroids"),
    (lambda m: pf.graded(1.0, 3, 2.0, origin="a"), "graded: origin: expected 1 finite"),
    (lambda m: pf.rectangle("2", 1.0, 2, 2), "rectangle: lx: expected a length > 0"),
])  # fmt: skip
def test_wrong_api_arguments_are_refused_by_name(call: Any, words: str) -> None:
    """Each of these gave a bare AttributeError, TypeError, ValueError or
    ZeroDivisionError from inside the library, or was accepted silently (a load on an
    empty group, '1e3' as a pressure); now a pfeie error names the argument."""
    with pytest.raises(pf.errors.PfeieError, match=re.escape(words)):
        call(_plate())


def test_a_results_reader_names_what_it_has(tmp_path: Path) -> None:
    """``Results.rigid``, ``joint_resultants``, ``joint_cracks``, ``joint_safety_factor``
    and ``units`` of an unknown name gave ValueError, IndexError or KeyError; now a
    ResultsError lists the names the file has."""
    model, top = _block_on_a_joint()
    pf.run_to_folder(pf.Dynamic(model, 0.01), 0.05, tmp_path, probes={"top": top},
                     figures=False, paraview=False)  # fmt: skip
    with Results(tmp_path / "results.h5") as res:
        for call, words in ((lambda: res.rigid("nope"), "no body 'nope'; bodies:"),
                            (lambda: res.rigid(99), "body: expected a name of"),
                            (lambda: res.joint_resultants("nope"), "no interface 'nope'"),
                            (lambda: res.joint_cracks("nope"), "no interface 'nope'"),
                            (lambda: res.joint_safety_factor("nope"), "no interface 'nope'"),
                            (lambda: res.units("history/nope"), "no dataset 'history/"),
                            ):  # fmt: skip
            with pytest.raises(pf.errors.ResultsError, match=re.escape(words)):
                call()
        assert res.rigid("block").shape == res.rigid(1).shape  # the names still work


# -- model files (a careless user's findings) ----------------------------------------------

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


@pytest.mark.parametrize("source, edit", [
    # MSH 2.2: the element count one short of the lines
    ("tests/data/two_blocks_v22.msh", lambda t: t.replace("$Elements\n184\n", "$Elements\n183\n")),
    # MSH 4.1: a block's count one short (koyna.msh's line 4161)
    ("examples/koyna/koyna.msh", lambda t: t.replace("\n2 3 16 340\n", "\n2 3 16 339\n")),
])  # fmt: skip
def test_a_mesh_with_more_elements_than_declared_is_refused(
    tmp_path: Path, source: str, edit: Any
) -> None:
    """The gmsh reader reads the declared number of elements and drops the rest, unseen:
    a crest pressure applied on half the crest (the static joint force 49.24 kN instead
    of 59.24 kN), a dam of 582 cells instead of 583. Now the counts are checked against
    the section's lines and the file is refused, naming the section; the file as gmsh
    wrote it reads (independent: the same file unedited)."""
    from pfeie.io import read_mesh

    text = (Path(__file__).resolve().parents[1] / source).read_text()
    assert edit(text) != text
    bad = tmp_path / "bad.msh"
    bad.write_text(edit(text))
    with pytest.raises(pf.errors.MeshError, match=r"bad\.msh: .*section \$Elements"):
        read_mesh(bad)
    good = tmp_path / "good.msh"
    good.write_text(text)
    assert read_mesh(good).n_points > 0


@pytest.mark.parametrize("edit, words", [
    # the same record twice: the crest acceleration doubled (0.152 g against 0.076 g)
    (lambda t: t + '[[ground_motion]]\nfile = "pulse.csv"\nunits = "g"\n',
     "ground_motion[1]: pulse.csv along [1.0, 0.0] is ground_motion[0] again"),
    # a pseudo-static load kept on under the record (the static FS 12.85 → 5.00)
    (lambda t: t.replace("[[supports]]", "[loads]\npseudo_static = { kh = 0.1 }\n[[supports]]"),
     "loads.pseudo_static with [[ground_motion]] and analysis.dynamic = true"),
    # a record whose times start after the run's end: a run without ground motion
    (lambda t: t.replace('file = "pulse.csv"', 'file = "late.csv"'),
     "late.csv: the record starts at 5 s, at or after the end of the run"),
])  # fmt: skip
def test_model_files_that_ran_something_else_are_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], edit: Any, words: str
) -> None:
    """Three model files that `pfeie run` ran to the end, exit 0, without a word, giving
    another analysis than the file meant: now each is refused at `pfeie check`, naming
    the key. Independent check: the unedited file checks."""
    from test_cli import SMALL, _write

    p = _write(tmp_path, SMALL)
    (tmp_path / "late.csv").write_text("time,acc\n5,0\n5.01,0.1\n5.02,-0.05\n5.03,0\n")
    assert main(["check", str(p)]) == 0
    p.write_text(edit(p.read_text()))
    capsys.readouterr()
    assert main(["check", str(p)]) == 2
    assert words in capsys.readouterr().err


@pytest.mark.slow
def test_a_probe_named_with_a_slash_is_drawn(tmp_path: Path) -> None:
    """`pfeie plot` and `pfeie report` stopped with FileNotFoundError on a probe named
    "my crest/probe" (its figure's file name made a folder of it); `run` and `export`
    worked. Now the figure is probe_my crest_probe-5a3301.png (a digest of the name keeps
    "a/b" and "a_b" apart), and both commands end with 0."""
    from test_cli import SMALL, _write

    p = _write(tmp_path, SMALL.replace("probes = { top", 'probes = { "my crest/probe"'))
    assert main(["run", str(p), "--quiet"]) == 0
    res = tmp_path / "out" / "results.h5"
    assert main(["plot", str(res), "--out", str(tmp_path / "figs")]) == 0
    assert (tmp_path / "figs" / "probe_my crest_probe-5a3301.png").is_file()
    assert main(["report", str(res), "--out", str(tmp_path / "report.html")]) == 0


def test_a_model_in_a_folder_whose_name_is_not_utf8(tmp_path: Path) -> None:
    """A model file in a folder named in Latin-1 (b'lat\\xe9 dir'): `pfeie run` stopped
    with UnicodeEncodeError writing its path to results.h5 (a 6 KB file left), and a
    study whose record file is so named could never write its table. Now the path is
    kept with its byte escaped (\\xe9), and the run equals the same run in a UTF-8
    folder (independent: that run's histories)."""
    import os
    import subprocess
    import sys

    from test_cli import SMALL, _write

    odd = tmp_path / os.fsdecode(b"lat\xe9 dir")
    plain = tmp_path / "plain"
    for d in (odd, plain):
        d.mkdir()
        # (in a process of its own: its messages name the folder, which this process's
        # captured logs could not pass on to pytest's workers)
        run = subprocess.run([sys.executable, "-m", "pfeie", "run", str(_write(d, SMALL)),
                              "--quiet"], capture_output=True, timeout=300)  # fmt: skip
        assert run.returncode == 0, run.stderr.decode("utf-8", "replace")
    with Results(odd / "out" / "results.h5") as a, Results(plain / "out" / "results.h5") as b:
        assert "lat\\xe9 dir" in a.meta["model_path"]
        np.testing.assert_array_equal(a.pairs()["X"], b.pairs()["X"])
    from pfeie.study import StudyTable

    table = StudyTable([{"record": os.fsdecode(b"caf\xe9"), "x": 1.0}])
    table.to_csv(tmp_path / "table.csv")
    assert "caf\\xe9" in (tmp_path / "table.csv").read_text()


def test_sizes_beyond_any_need_are_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A finite-element reservoir refined 100,000 times (447 GiB asked, or 24 GB and
    minutes at 10,000) and `pfeie spectrum --periods 0.01:4:100000000` (a MemoryError
    traceback) are refused at once with what to give instead."""
    mesh = pf.rectangle(1.0, 10.0, 1, 4)
    m = pf.Model(mesh, [pf.Block("all", pf.Elastic(30e9, 0.2, 2400.0))])
    with pytest.raises(pf.ModelError, match=r"the water mesh would have .* nodes, more than"):
        m.add_reservoir("xmin", water_level=10.0, refine=100_000)
    assert m.add_reservoir("xmin", water_level=10.0, refine=2).depth == 10.0  # (the floor)
    rec = DATA / "elcentro_1940_ns_chopra.csv"
    capsys.readouterr()
    assert main(["spectrum", str(rec), "--units", "g", "--periods", "0.01:4:100000000",
                 "--out", str(tmp_path)]) == 2  # fmt: skip
    assert "2 <= N <= 10000" in capsys.readouterr().err


def _block_held_by_a_stop(beta: float, phi: float) -> pf.Model:
    """A 1.5 m block on a plane dipping β (φ) held by a stop (φ = 40°) of the fixed base:
    the plane's joint is at its capacity from k = 0 on (β > φ), the stop holds it."""
    mat = pf.Elastic(30e9, 0.2, 2400.0)
    mesh = pf.rectangle(2.0, 1.5, 4, 3)
    mesh.points[:, 1] -= 0.5
    mesh.add_cell_group("base", lambda x: (x[:, 1] < 0) | (x[:, 0] > 1.5))
    mesh.add_cell_group("block", lambda x: (x[:, 1] > 0) & (x[:, 0] < 1.5))
    mesh.add_facet_group("joint", lambda x: (np.abs(x[:, 1]) < 1e-9) & (x[:, 0] < 1.5),
                         boundary_only=False)  # fmt: skip
    mesh.add_facet_group("stop", lambda x: (np.abs(x[:, 0] - 1.5) < 1e-9) & (x[:, 1] > 1e-9),
                         boundary_only=False)  # fmt: skip
    th = -np.radians(beta)
    mesh.points[:] = mesh.points @ np.array([[np.cos(th), np.sin(th)], [-np.sin(th), np.cos(th)]])
    m = pf.Model(mesh, [pf.Block("base", mat), pf.Block("block", mat)],
                 interfaces=[pf.Interface("joint", pf.Joint(phi=phi)),
                             pf.Interface("stop", pf.Joint(phi=40.0))])  # fmt: skip
    m.fix("base")
    m.add_gravity()
    return m


@pytest.mark.slow
def test_the_yield_search_from_a_joint_at_its_capacity_at_rest() -> None:
    """The diff reviewer's cases against the first fix of the yield search. (a) A block on
    a 40° plane with φ = 10° held by a stop: the plane's joint slides from k = 0, and the
    steps out from a joint at its capacity stepped from k = 0 by nothing (k_y = 0, "not
    bracketed", 60 analyses). Closed form: pushed up the dip, k_y = tan(β + φ) = 1.19175,
    sliding; pushed down it, the stop holds to k = 2. (b) Two 3 m blocks side by side on
    a φ = 60° base, their vertical joint (φ = 30°) at its capacity from k = 0.05 on: the
    limit is rocking (k_y 0.335, the base's FS 5.17), not sliding on that joint."""
    m = _block_held_by_a_stop(40.0, 10.0)
    up = pf.yield_coefficient(m, [-1.0, 0.0])
    assert up.k_y == pytest.approx(np.tan(np.radians(50.0)), rel=2e-6)
    assert (up.limit, up.joint) == ("sliding", "joint") and up.analyses <= 20  # (15)
    assert pf.yield_coefficient(m, [1.0, 0.0]).limit == "none"  # held up to k = 2
    from test_yield import two_blocks

    two = two_blocks(3.0, 60.0, 30.0)
    y = pf.yield_coefficient(two)
    assert y.limit == "no equilibrium found" and 0.33 < y.k_y < 0.34  # (measured 0.335)


def test_absolute_form_continued_from_a_final_state_after_events(
    sliding_block: tuple[pf.Model, pf.StaticResult, pf.GroundMotion],
) -> None:
    """A run continued with ``start=result.final`` rebuilt the supports' grid from its
    origin, without the sub-steps' rebases: a 0.4 mm jump of the ground at the seam and
    the slip 0.7 % of its peak off (the diff reviewer's case). The final state now carries
    the supports' rows (for the same records): the continued run is the uninterrupted
    one, bit for bit (independent: that run)."""
    model, static, gm = sliding_block
    kw: dict[str, Any] = {"ground": [gm], "form": "absolute"}
    full = pf.Dynamic(model, 0.01, event_substeps=4).run(2.0, start=static, **kw)
    a = pf.Dynamic(model, 0.01, event_substeps=4).run(1.0, start=static, **kw)
    assert a.solver["substeps"].sum() > 0  # events before the seam
    b = pf.Dynamic(model, 0.01, event_substeps=4).run(1.0, start=a.final, **kw)
    np.testing.assert_array_equal(b.ground, full.ground[100:])
    np.testing.assert_array_equal(b.s, full.s[100:])


def test_a_damaged_results_file_and_a_manual_into_a_file(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """`pfeie plot`, `report` and `export` of a results file that lacks a dataset
    (pairs/area here) stopped with a KeyError traceback; `pfeie verify --manual` into a
    file failed after running its cases. Both now end with exit 2 and a message naming
    the file (the verify one before any case runs)."""
    import h5py

    from test_cli import SMALL, _write

    assert main(["run", str(_write(tmp_path, SMALL)), "--quiet"]) == 0
    res = tmp_path / "out" / "results.h5"
    with h5py.File(res, "r+") as f:
        del f["pairs/area"]
    capsys.readouterr()
    for cmd in (["plot", str(res), "--out", str(tmp_path / "figs")],
                ["export", str(res), "--csv", str(tmp_path / "csv")],
                ["report", str(res), "--out", str(tmp_path / "r.html")]):  # fmt: skip
        assert main(cmd) == 2, cmd
        assert "the results file is incomplete or damaged" in capsys.readouterr().err
    afile = tmp_path / "afile"
    afile.write_text("")
    assert main(["verify", "--case", "V1a", "--manual", str(afile)]) == 2
    err = capsys.readouterr()
    assert "--manual" in err.err and "V1a" not in err.out  # refused before the case ran


def test_a_mesh_saved_with_a_byte_order_mark(tmp_path: Path) -> None:
    """A gmsh file that an editor saved with a UTF-8 byte-order mark was called "not a
    gmsh file: it begins with binary data"; the message now says what it is."""
    from pfeie.io import read_mesh

    text = (Path(__file__).resolve().parent / "data" / "two_blocks_v22.msh").read_bytes()
    bom = tmp_path / "bom.msh"
    bom.write_bytes(b"\xef\xbb\xbf" + text)
    with pytest.raises(pf.errors.MeshError, match="begins with a UTF-8 byte-order mark"):
        read_mesh(bom)


def test_second_review_of_the_day() -> None:
    """The second diff reviewer's cases: (a) a run continued from an absolute-form final
    state with another Δt was refused (the supports' rows are of the first run's grid:
    now used only under the same Δt); (b) the yield search at tol = 5e-3 read the sliding
    of two blocks on a φ = 30° base as "no equilibrium found" (a joint just at its
    capacity is 'fresh' within 8 tol); (c) redefining a group identically warned that it
    was replaced; (d) one node index given alone is a node."""
    from test_yield import two_blocks

    model, _ = _block_on_a_joint()
    gm = read_record(DATA / "elcentro_1940_ns_chopra.csv", units="g", scale=0.05)
    a = pf.Dynamic(model, 0.01).run(1.0, ground=[gm], form="absolute")
    b = pf.Dynamic(model, 0.003).run(0.3, start=a.final, ground=[gm], form="absolute")
    assert b.completed and b.t[-1] == pytest.approx(1.3)
    y = pf.yield_coefficient(two_blocks(1.0, 30.0, 30.0), tol=5e-3)
    assert (y.limit, y.joint) == ("sliding", "joint")
    assert y.k_y == pytest.approx(np.tan(np.radians(30.0)), rel=5e-3)
    mesh = pf.rectangle(1.0, 1.0, 2, 2)
    import logging

    logger = logging.getLogger("pfeie.mesh._mesh")
    seen: list[str] = []
    handler = logging.Handler()
    handler.emit = lambda r: seen.append(r.getMessage())  # type: ignore[method-assign]
    logger.addHandler(handler)
    try:
        mesh.add_cell_group("all", lambda x: x[:, 0] > -1.0)  # the same cells
        assert not seen
        mesh.add_cell_group("all", lambda x: x[:, 0] > 0.5)  # others
        assert seen == ["cell group 'all': replaced by the new selection"]
    finally:
        logger.removeHandler(handler)
    m = _plate()
    m.add_nodal_force(5, [1.0, 0.0])
    assert m.loads[-1].nodes.tolist() == [5]


def test_numbers_given_as_numpy_scalars_and_0d_arrays() -> None:
    """The day's argument checks refused numbers given as 0-d numpy arrays (the second
    reviewer); they are numbers (pfeie.typing.is_number), each giving what the float
    gives."""
    model = _plate()
    model.fix("xmin")
    model.add_gravity()
    assert np.array_equal(pf.solve_static(model, t=np.array(0.0)).u, pf.solve_static(model).u)
    r = pf.Rayleigh(0.1, 0.01)
    assert r.ratio(np.array(2.0)) == r.ratio(2.0)
    a = pf.GroundMotion.from_samples([0.0, 1.0, 0.0], dt=np.array(0.01), scale=np.float32(2.0))
    b = pf.GroundMotion.from_samples([0.0, 1.0, 0.0], dt=0.01, scale=2.0)
    assert np.array_equal(a.acceleration, b.acceleration) and np.array_equal(a.time, b.time)
    assert np.array_equal(pf.graded(1.0, 3, 2.0, origin=np.array(3.0)),
                          pf.graded(1.0, 3, 2.0, origin=3.0))  # fmt: skip


def test_a_mesh_with_a_latin1_group_name(tmp_path: Path) -> None:
    """A physical name written in Latin-1 ("dém") was reported as a truncated or corrupt
    file; the message now names the text that is not UTF-8."""
    from pfeie.io import read_mesh

    raw = (Path(__file__).resolve().parent / "data" / "two_blocks_v22.msh").read_bytes()
    p = tmp_path / "latin1.msh"
    p.write_bytes(raw.replace(b'"dam"', b'"d\xe9m"'))
    with pytest.raises(pf.errors.MeshError, match="holds text that is not UTF-8"):
        read_mesh(p)
