"""Findings of the twenty-eighth review.

Each test reproduces the defect and checks the fix against an independent number.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import pfeie as pf
from pfeie.io import Results, read_record

DATA = Path(__file__).resolve().parents[1] / "examples" / "data"


def _block_on_a_joint(joint: pf.JointLaw | None = None) -> tuple[pf.Model, int]:
    """The README's block (1 m, μ = 0.2, or the law ``joint``) on its fixed base; the
    node at its top right."""
    mesh = pf.rectangle(1.0, 1.5, nx=2, ny=3)
    mesh.add_cell_group("base", lambda x: x[:, 1] < 0.5)
    mesh.add_cell_group("block", lambda x: x[:, 1] > 0.5)
    mesh.add_facet_group("joint", lambda x: abs(x[:, 1] - 0.5) < 1e-9, boundary_only=False)
    concrete = pf.Elastic(E=30e9, nu=0.2, rho=2400)
    law = joint if joint is not None else pf.Joint(phi=np.degrees(np.arctan(0.2)))
    model = pf.Model(mesh, [pf.Block("base", concrete), pf.Block("block", concrete)],
                     interfaces=[pf.Interface("joint", law)])
    model.fix("base")
    model.add_gravity()
    return model, int(np.argmax(mesh.points[:, 1] + 1e-3 * mesh.points[:, 0]))


def test_absolute_form_summary_measures_motion_from_the_supports_the_run_moved(
    tmp_path: Path,
) -> None:
    """In the absolute form the supports follow the scheme's integration of the record on
    the run's grid, not the record's exact displacement; the summary subtracted the exact
    one, so a block's permanent displacement and a probe's peak carried the scheme's
    integration error of the ground (here 2 × El Centro at Δt = 20 ms). Now the run
    records the ground's displacement as the supports followed it (`history/ground`),
    and without damping the absolute form's summary equals the relative form's
    (independent: the relative form never moves the supports): measured 1e-9 of the
    peak, against the grid's drift from the exact ground before (5.1 mm, 8 % of the
    block's 61 mm peak)."""
    model, top = _block_on_a_joint()
    gm = read_record(DATA / "elcentro_1940_ns_chopra.csv", units="g",
                     scale=2.0).baseline_corrected()  # fmt: skip
    static = pf.solve_static(model)
    summary = {}
    for form in ("relative", "absolute"):
        pf.run_to_folder(pf.Dynamic(model, 0.02), 4.0, tmp_path / form, ground=[gm], form=form,
                         start=static, probes={"top": top}, figures=False, paraview=False)
        summary[form] = json.loads((tmp_path / form / "summary.json").read_text())
    rel, ab = summary["relative"], summary["absolute"]
    peak = rel["probes"]["top"]["peak_displacement_m"]
    assert peak > 0.05  # the block slides
    assert ab["probes"]["top"]["peak_displacement_m"] == pytest.approx(peak, rel=1e-8)
    for key in ("peak_displacement_m", "residual_displacement_m"):
        assert ab["bodies"]["block"][key] == pytest.approx(rel["bodies"]["block"][key],
                                                           rel=1e-8)  # fmt: skip
    with Results(tmp_path / "absolute" / "results.h5") as res:
        ground, t = res.ground, res.time
        assert ground is not None and ground.shape == (t.size, 2)
        exact = np.array([gm.motion(ti)[0] for ti in t])
        # the grid's drift from the exact displacement (the error the summary carried
        # before): measured 5.1 mm, the scheme's O(Δt²) integration error at Δt = 20 ms
        drift = float(np.abs(ground[:, 0] - exact).max())
        assert 1e-3 < drift < 1e-2
        assert np.all(ground[:, 1] == 0.0)
    with Results(tmp_path / "relative" / "results.h5") as res:
        ground = res.ground  # the relative form records the record's exact displacement
        assert ground is not None
        assert ground[:, 0] == pytest.approx([gm.motion(ti)[0] for ti in res.time], abs=1e-15)
        q_rel = res.f["history/rigid"][...]
    # the figures (rigid_motion.png showed the base moving with the ground): the motion
    # they draw, relative to the ground, is the relative form's
    from pfeie.plot._plots import _ground_of, plot_rigid

    with Results(tmp_path / "absolute" / "results.h5") as res:
        ground, frame = _ground_of(res)
        assert ground is not None and frame == "relative to the ground"
        q = res.f["history/rigid"][...]
        q[..., :2] -= ground[:, None, :]
        assert np.abs((q - q[:1]) - (q_rel - q_rel[:1])).max() <= 1e-8 * np.abs(q_rel).max()
        assert plot_rigid(res, tmp_path / "rigid.png").stat().st_size > 0


def _wet_battered_block(wet: bool) -> tuple[pf.Model, int]:
    """A block 8 m wide and 12 m high whose upstream face is battered 30° from the
    vertical, on rollers (its base fixed along y, its downstream toe along x too), wet to
    its top (``wet``): Westergaard's block μ n nᵀ at the heel couples its free x to its
    prescribed y, so M_fp ≠ 0; a stiffness-proportional damping (C ι = 0). The node at
    its crest."""
    H = 12.0
    mesh = pf.rectangle(8.0, H, 3, 10)
    x, y = mesh.points[:, 0].copy(), mesh.points[:, 1].copy()
    mesh.points[:, 0] = x - (H - y) * np.tan(np.radians(30.0)) * (1 - x / 8.0)
    model = pf.Model(mesh, [pf.Block("all", pf.Elastic(30e9, 0.2, 2400.0))],
                     damping=pf.Rayleigh(0.0, 2e-3))  # fmt: skip
    model.fix("ymin", components=1)
    toe = int(np.argmin(np.abs(mesh.points[:, 0] - 8.0) + np.abs(mesh.points[:, 1])))
    model.fix([toe], components=0)
    if wet:
        model.add_westergaard("xmin", water_level=H)
    return model, int(np.argmax(mesh.points[:, 1] + 1e-3 * mesh.points[:, 0]))


@pytest.mark.parametrize("theta", [0.55, 0.7, 0.9])
@pytest.mark.parametrize("wet", [False, True])
def test_moreau_jean_below_one_absolute_form_equals_the_relative_form(
    theta: float, wet: bool
) -> None:
    """Moreau–Jean with θ < 1 in the absolute form disagreed with the relative form (the
    independent computation: with C ι = 0 the two forms are one equation, so the absolute
    motion less the supports' is the relative motion), for two reasons:

    - the ground's motion read a zero acceleration at the record's first sample, where
      the relative form's load takes the record's a_g(t₀) (−2.2e-5 m/s² for El Centro
      baseline-corrected): the supports' θ-rule started from 0, and the forms differed by
      4e-7 (θ = 0.9) to 2.3e-6 (θ = 0.55) of the peak from the first step on;
    - where the added mass couples a support to its free neighbours (M_fp ≠ 0), the load
      −M_fp a_p took the grid's step average a_θ, which the scheme's θ-blend of the loads
      then averaged again: 6.1e-3 of the peak (θ = 0.7, the crest's x under vertical
      shaking).

    Measured now, the crest's displacement along x and y: at most 3.5e-10 of the peak
    (the dry block's x, a small motion across the shaking; 6.4e-11 wet), its absolute
    acceleration 2e-9, as at θ = 1."""
    from pfeie.dynamics._excitation import GridGround

    model, top = _wet_battered_block(wet)
    gm = read_record(DATA / "elcentro_1940_ns_chopra.csv", units="g",
                     direction=(0.0, 1.0)).baseline_corrected()  # fmt: skip
    assert gm.motion(0.0)[2] == gm(0.0) != 0.0
    an = pf.Dynamic(model, dt=0.005, scheme="moreau-jean", theta=theta)
    assert (an.system.M_fp is not None) == wet
    rel = an.run(3.0, ground=[gm], form="relative", probes=[top])
    ab = an.run(3.0, ground=[gm], form="absolute", probes=[top])
    grid = GridGround(gm, 0.0, 0.005, theta=theta)
    d = np.array([grid.motion(t)[0] for t in ab.t])
    for c in (0, 1):
        u_r = rel.probe_u[:, 0, c]
        u_a = ab.probe_u[:, 0, c] - (d if c == 1 else 0.0)
        assert np.abs(u_a - u_r).max() <= 2e-9 * np.abs(u_r).max()
        a_r, a_a = rel.probe_a_abs[:, 0, c], ab.probe_a_abs[:, 0, c]
        assert np.abs(a_a - a_r).max() <= 1e-8 * np.abs(a_r).max()


def test_the_default_record_direction_is_x_in_3d_too() -> None:
    """`read_record` and `GroundMotion` default to the direction (1, 0), x; a 3D model
    refused it ("direction has 2 components"). x is x in 3D: a run under it equals one
    under (1, 0, 0) bit for bit; another 2D direction, (0, 1), is ambiguous there (the
    vertical of 2D, a horizontal of 3D) and stays refused, naming both verticals."""
    mesh = pf.box(1.0, 1.0, 2.0, 1, 1, 2, cell="hexahedron")
    model = pf.Model(mesh, [pf.Block("all", pf.Elastic(E=30e9, nu=0.2, rho=2400))])
    model.fix("zmin")
    top = int(np.argmax(mesh.points[:, 2] + 1e-3 * mesh.points[:, 0]))
    values = np.sin(np.linspace(0.0, 6.0, 51))
    default = pf.GroundMotion.from_samples(values, dt=0.01, units="g")
    given = pf.GroundMotion.from_samples(values, dt=0.01, units="g", direction=(1, 0, 0))
    an = pf.Dynamic(model, 0.005)
    a = an.run(0.5, ground=[default], probes=[top])
    b = an.run(0.5, ground=[given], probes=[top])
    assert np.abs(a.probe_u[:, 0, 0]).max() > 0
    assert np.array_equal(a.probe_u, b.probe_u) and np.array_equal(a.probe_a_abs, b.probe_a_abs)
    up = pf.GroundMotion.from_samples(values, dt=0.01, units="g", direction=(0, 1))
    with pytest.raises(pf.ModelError, match=r"\(0, 0, 1\) for the vertical"):
        an.run(0.5, ground=[up])


# -- studies (a dam engineer running many records) ----------------------------------------
def test_a_resumed_study_takes_its_intensity_measures_from_the_current_study(
    tmp_path: Path,
) -> None:
    """A study resumed after its `intensity.period` (or `damping`) changed kept every row
    (right: the runs do not depend on them) with the old rows' Sa(T1) column, while
    study.json said the new T1: the Sa of T = 0.5 s under T = 1.0 s. Now a kept row takes
    its intensity measures from the current study: equal to a fresh study's, which
    computes them from the record (independent: the record's own spectrum)."""
    from pfeie.study import Study
    from test_study import STUDY, setup

    study = STUDY.replace('values = [0.2, 0.5]', 'values = [0.2]\nperiod = 0.5')
    p = setup(tmp_path, study, n=1)
    first = Study.from_file(p).run()
    p.write_text(study.replace("period = 0.5", "period = 1.0\ndamping = 0.2"))
    st = Study.from_file(p)
    again = st.run()
    assert st.kept == 1  # the run itself is kept
    rec = st.records[0].read(2)
    f = again.column("scale_factor")[0]
    expect = rec.intensity_measures(1.0, 0.2)["sa"] * abs(f) / 9.81
    assert again.column("im.sa_t1_g")[0] == pytest.approx(expect, rel=1e-12)
    assert abs(first.column("im.sa_t1_g")[0] / expect - 1) > 0.1  # it was T = 0.5 s's


def test_a_study_keeps_its_rows_when_the_model_files_unused_record_changes(
    tmp_path: Path,
) -> None:
    """The model file's own [[ground_motion]] is not run by a study (its records are the
    study's), but the bytes of its file were in the study's key: editing that file threw
    every row away ("a study of another model"). Now the rows are kept; the runs' results
    are those of the study's records, the same as before."""
    from pfeie.study import Study
    from test_study import MODEL, STUDY, setup

    p = setup(tmp_path, STUDY, n=1)
    np.savetxt(tmp_path / "unused.csv", np.c_[[0.0, 0.01, 0.02], [0.0, 0.1, 0.0]],
               delimiter=",")  # fmt: skip
    (tmp_path / "model.toml").write_text(
        MODEL + '[[ground_motion]]\nfile = "unused.csv"\nunits = "g"\n')
    first = Study.from_file(p).run()
    with (tmp_path / "unused.csv").open("a") as fh:
        fh.write("0.03,0.5\n")
    st = Study.from_file(p)
    again = st.run()
    assert st.kept == 2
    np.testing.assert_array_equal(again.column("probe.top.peak_displacement_m"),
                                  first.column("probe.top.peak_displacement_m"))  # fmt: skip


def test_a_run_into_an_interrupted_studys_folder_is_refused(tmp_path: Path) -> None:
    """A study marks its folder with study.json when it ends; an interrupted study's
    folder held only its rows, and `pfeie run` into it was accepted: the study could not
    resume there afterwards. The rows now mark it too."""
    from pfeie.cli import main
    from pfeie.study import Study
    from test_study import STUDY, setup

    p = setup(tmp_path, STUDY, n=1)
    Study.from_file(p).run()
    (tmp_path / "study" / "study.json").unlink()  # as a study stopped before its end
    code = main(["run", str(tmp_path / "model.toml"), "--set", "output.folder='study'",
                 "--duration", "0.02"])  # fmt: skip
    assert code == 2
    assert not (tmp_path / "study" / "results.h5").exists()
    with pytest.raises(pf.PfeieError, match="the rows of its runs under rows/"):
        pf.run_to_folder(pf.Dynamic(_block_on_a_joint()[0], 0.01), 0.02, tmp_path / "study")
    again = Study.from_file(p)
    again.run()
    assert again.kept == 2


def test_an_implausible_pga_warning_names_the_units_the_at2_header_states(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    """An AT2 whose header states CM/SEC/SEC holding values in g (a PGA of 0.3 "cm/s²")
    was warned about as "read in g (units = 'g')": the units the warning named were
    the default, not those read. Now it names the header's cm/s2 and the units that would
    make the PGA plausible (g)."""
    from pfeie.io import implausible_pga, read_record

    p = tmp_path / "rec.AT2"
    p.write_text("PEER NGA STRONG MOTION DATABASE RECORD\nSYNTH\n"
                 "ACCELERATION TIME SERIES IN UNITS OF CM/SEC/SEC\n"
                 "NPTS=    6, DT= .0100 SEC\n"
                 "  .0000000E+00  .1000000E+00 -.3000000E+00  .2000000E+00 -.1000000E+00\n"
                 "  .0000000E+00\n")  # fmt: skip
    rec = read_record(p)
    assert rec.read_units == "cm/s2" and rec.pga == pytest.approx(0.3 * 0.01, rel=1e-15)
    msg = implausible_pga(p, rec.pga, rec.read_units)
    assert msg is not None and "read in cm/s2" in msg and "(units = 'cm/s2')" in msg
    from pfeie.cli import main

    with caplog.at_level("WARNING"):
        assert main(["spectrum", str(p), "-o", str(tmp_path / "s")]) == 0
    assert "read in cm/s2" in caplog.text


def test_study_api_refuses_wrong_arguments_by_name(tmp_path: Path) -> None:
    """The Python API took an empty record list (it wrote an empty table, then failed on
    its missing column), and gave bare TypeErrors for `values=0.1` and `records=[3]`;
    each is now a ModelError naming the argument."""
    from pfeie.study import Study

    model = tmp_path / "model.toml"
    with pytest.raises(pf.ModelError, match=r"records: expected at least one record"):
        Study(model, [], measure="pga", values=[0.1])
    with pytest.raises(pf.ModelError, match=r"intensity.values: expected a list of numbers"):
        Study(model, [tmp_path / "r.csv"], values=0.1)  # type: ignore[arg-type]
    with pytest.raises(pf.ModelError, match=r"records\[0\]: expected a record file's path"):
        Study(model, [3])  # type: ignore[list-item]
    assert not (tmp_path / "study").exists()


def test_study_table_keeps_integer_and_boolean_columns(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    """`StudyTable.column` gave floats for `completed`, `level` and `steps`, so that
    `~t.column("completed")` failed; read back from the CSV and the Parquet file they are
    booleans and integers, as in memory. The model file's warnings of a study are logged
    once (they were logged twice, by the study's check of the model and again by its
    runs' build, with the file's absolute path)."""
    from pfeie.study import Study, StudyTable
    from test_study import MODEL, STUDY, setup

    p = setup(tmp_path, STUDY, n=1)
    (tmp_path / "model.toml").write_text(MODEL.replace("friction_angle = 20.0",
                                                       "friction_angle = 2.0"))  # fmt: skip
    with caplog.at_level("WARNING"):
        t = Study.from_file(p).run()
    said = [r.getMessage() for r in caplog.records if "friction_angle = 2" in r.getMessage()]
    assert len(said) == 1, said
    for table in (t, StudyTable.read(tmp_path / "study" / "table.csv"),
                  StudyTable.read(tmp_path / "study" / "table.parquet")):  # fmt: skip
        assert table.column("completed").dtype == bool
        assert not (~table.column("completed")).any()
        assert table.column("level").dtype == np.int64
        assert table.column("level").tolist() == [0, 1]
        assert table.column("steps").dtype == np.int64
    assert StudyTable([{"a": 1}, {"a": 2.5}]).column("a").dtype == float
    assert np.isnan(StudyTable([{"a": 1}, {"b": 2}]).column("a")[1])


def test_a_run_recording_every_other_step_ends_off_its_grid_and_resumes(
    tmp_path: Path,
) -> None:
    """`pfeie run` with `output.every = 2` over 5 steps failed at its end ("checkpoint of
    row 2 with 4 rows on disk": the last step, off the grid of `every`, is recorded in a
    row of its own after the latest checkpoint), losing the run and leaving an earlier
    run's summary in the folder. Now it completes, and a resume to a longer duration
    gives the histories of a run that never stopped (independent: that run), bit for
    bit."""
    from pfeie.cli import main
    from pfeie.io import Results
    from test_study import MODEL, setup

    setup(tmp_path, n=1)
    model = MODEL.replace('folder = "out"', 'folder = "out"\nevery = 2') + (
        '[[ground_motion]]\nfile = "rec/r0.csv"\nunits = "g"\n')
    (tmp_path / "model.toml").write_text(model)
    (tmp_path / "whole.toml").write_text(model.replace('folder = "out"', 'folder = "whole"'))
    assert main(["run", str(tmp_path / "model.toml"), "--duration", "0.05"]) == 0
    with Results(tmp_path / "out" / "results.h5") as res:
        assert res.completed and res.time[-1] == pytest.approx(0.05, abs=1e-12)
        assert res.n_times == 4  # rows at steps 0, 2, 4 and the last, 5
    assert main(["run", str(tmp_path / "model.toml"), "--duration", "0.1", "--resume"]) == 0
    assert main(["run", str(tmp_path / "whole.toml"), "--duration", "0.1"]) == 0
    with Results(tmp_path / "out" / "results.h5") as a, \
            Results(tmp_path / "whole" / "results.h5") as b:  # fmt: skip
        assert np.array_equal(a.time, b.time)
        assert np.array_equal(a.probe("top")["u"], b.probe("top")["u"])
        assert np.array_equal(a.f["history/pairs/X"][...], b.f["history/pairs/X"][...])


def _column_3d(tmp: Path) -> None:
    """A 1 m cube of rock ("base", its bottom face "bottom") under a 1 m cube ("block")
    across the face "joint" at z = 1 m; "upstream" the block's face at x = 0."""
    from test_robustness import msh22

    nodes = [(x, y, z) for z in (0.0, 1.0, 2.0) for y in (0.0, 1.0) for x in (0.0, 1.0)]
    layer = [[1, 2, 4, 3], [5, 6, 8, 7], [9, 10, 12, 11]]  # x fastest, four a layer
    elements = [(1, 3, 3, layer[0]), (2, 3, 4, layer[1]), (3, 3, 5, [5, 7, 11, 9]),
                (4, 5, 1, layer[0] + layer[1]), (5, 5, 2, layer[1] + layer[2])]  # fmt: skip
    names = {1: (3, "base"), 2: (3, "block"), 3: (2, "bottom"), 4: (2, "joint"),
             5: (2, "upstream")}  # fmt: skip
    msh22(tmp / "col.msh", nodes, elements, names)


COLUMN = """
[mesh]
file = "col.msh"
[materials.rock]
E = 30e9
nu = 0.2
rho = 2400.0
[blocks]
base = "rock"
block = "rock"
[interfaces.joint]
friction_angle = 35.0
[[supports]]
group = "bottom"
[loads]
gravity = 9.81
LOADS
[analysis]
dynamic = false
[output]
folder = "out"
"""


@pytest.mark.parametrize("upstream, warned", [("-x", False), ("+y", True), ("-y", True)])
def test_an_uplift_laid_across_a_3d_valley_is_warned(
    tmp_path: Path, caplog: pytest.LogCaptureFixture, upstream: str, warned: bool
) -> None:
    """In 3D, `loads.uplift.upstream = "+y"` on a dam whose reservoir wets its face at
    x = 0 laid the uplift across the valley, without the warning that `"+x"` gets: the
    check compared the wet faces along the axis named only, where they lie mid-joint.
    Now the other horizontal axis is compared too, and the warning names the side."""
    from pfeie.io import load_job

    _column_3d(tmp_path)
    loads = ('hydrostatic = [{groups = ["upstream"], water_level = 1.8}]\n'
             f'uplift = [{{interface = "joint", headwater = 1.8, upstream = "{upstream}"}}]')
    p = tmp_path / "col.toml"
    p.write_text(COLUMN.replace("LOADS", loads))
    with caplog.at_level("WARNING"):
        load_job(p)
    said = f"loads.uplift[0].upstream = '{upstream}' runs the uplift of 'joint' along y"
    assert (said in caplog.text) == warned, caplog.text
    if warned:
        assert "wets faces about x = 0 m" in caplog.text
        assert "expected upstream = '-x'?" in caplog.text


def test_3d_figures_and_report_of_water_in_a_joint(tmp_path: Path) -> None:
    """A hydrostatic load in a 3D joint (the model file's `loads.hydrostatic` on an
    interface: the water pushes both faces apart) ran right, but `pfeie plot` and
    `pfeie report` stopped with "no facet group 'joint'": the 3D load figure looked the
    group up without the interface's first face, `joint:a`, which the 2D figure took.
    Now both end with exit 0 and draw the load; the run's normal force is the weight
    less the water's push, ρ_w g (1.5 − 1) over 1 m² (closed form)."""
    from pfeie.cli import main
    from pfeie.io import Results

    _column_3d(tmp_path)
    (tmp_path / "col.toml").write_text(COLUMN.replace(
        "LOADS", 'hydrostatic = [{groups = ["joint"], water_level = 1.5}]'))
    assert main(["run", str(tmp_path / "col.toml")]) == 0
    out = tmp_path / "out"
    with Results(out / "results.h5") as res:
        N = float(res.static_pairs("joint")["X"][:, -1].sum())
    assert pytest.approx(2400.0 * 9.81 - 1000.0 * 9.81 * 0.5, rel=1e-9) == N
    assert main(["plot", str(out / "results.h5")]) == 0
    assert (out / "figures" / "loads.png").stat().st_size > 0
    assert main(["report", str(out / "results.h5")]) == 0
    assert (out / "report.html").stat().st_size > 0
