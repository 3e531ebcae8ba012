"""Wrong inputs of a new user's test (round 16), each refused or warned with a message that
names the file (key, group, line) and what was expected: corrupt meshes, a mesh given as
the model file, records in the wrong units or with decimal commas, joint strengths beyond
the Mohr-Coulomb apex, undeclared cracks, unwritable report paths, ``--set`` errors, mesh
generator arguments, numpy scalars in messages, water levels that disagree."""

from __future__ import annotations

import logging
import warnings
from pathlib import Path

import numpy as np
import pytest

import pfeie as pf
from conftest import cli_fails
from pfeie.cli import main
from pfeie.errors import MeshError, ModelError, RecordError
from pfeie.io import implausible_pga, load_job, read_mesh, read_record

DATA = Path(__file__).parent / "data"




# -- 1. a truncated or corrupt .msh file ----------------------------------------------------
def _cut(src: Path, dst: Path, lines: slice) -> Path:
    dst.write_text("".join(src.read_text().splitlines(keepends=True)[lines]))
    return dst


@pytest.mark.parametrize("name", ["two_blocks_v22.msh", "two_blocks_v41.msh"])
def test_a_truncated_mesh_names_the_section_not_closed(tmp_path: Path, name: str) -> None:
    text = (DATA / name).read_text()
    p = tmp_path / name
    p.write_text(text[: len(text) // 2])
    with pytest.raises(MeshError) as exc:
        read_mesh(p)
    msg = str(exc.value)
    assert msg.startswith(f"{p}: cannot read the gmsh file: the file is truncated: the section $")
    assert "is not closed by $End" in msg and "expected a gmsh .msh file" in msg
    assert "reshape" not in msg and "index" not in msg


def test_a_garbage_line_in_nodes_is_named(tmp_path: Path) -> None:
    lines = (DATA / "two_blocks_v22.msh").read_text().splitlines(keepends=True)
    k = lines.index("$Nodes\n") + 3
    lines[k] = "garbage here\n"
    p = tmp_path / "g.msh"
    p.write_text("".join(lines))
    with pytest.raises(MeshError, match=rf"line {k + 1} \(section \$Nodes\): 'garbage here' is "
                       "not numbers: the file is corrupt"):  # fmt: skip
        read_mesh(p)


def test_a_node_line_short_of_a_coordinate_is_named(tmp_path: Path) -> None:
    lines = (DATA / "two_blocks_v22.msh").read_text().splitlines(keepends=True)
    k = lines.index("$Nodes\n") + 3
    lines[k] = " ".join(lines[k].split()[:3]) + "\n"
    p = tmp_path / "s.msh"
    p.write_text("".join(lines))
    with pytest.raises(MeshError, match=rf"line {k + 1} \(section \$Nodes\): expected 4 numbers"):
        read_mesh(p)


def test_an_element_on_a_missing_node_is_named(tmp_path: Path) -> None:
    lines = (DATA / "two_blocks_v22.msh").read_text().splitlines(keepends=True)
    k = lines.index("$Elements\n") + 2
    fields = lines[k].split()
    lines[k] = " ".join([*fields[:-1], "9999"]) + "\n"
    p = tmp_path / "n.msh"
    p.write_text("".join(lines))
    with pytest.raises(MeshError, match=rf"gmsh element {fields[0]} refers to node 9999, which "
                       r"is not in the section \$Nodes"):  # fmt: skip
        read_mesh(p)


@pytest.mark.parametrize(
    ("content", "words"),
    [(b"", "the file is empty"),
     (bytes(range(256)) * 8, "not a gmsh file: it begins with binary data, not $MeshFormat"),
     (b"time,acc\n0,0\n", "not a gmsh file: it begins with 'time,acc', not $MeshFormat")],
)  # fmt: skip
def test_an_empty_or_foreign_mesh_file_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], content: bytes, words: str
) -> None:
    p = tmp_path / "m.msh"
    p.write_bytes(content)
    with pytest.raises(MeshError) as exc:
        read_mesh(p)
    assert str(exc.value) == (f"{p}: cannot read the gmsh file: {words}; expected a gmsh .msh "
                              "file, format 2.2 or 4.1 (export it again from gmsh)")  # fmt: skip
    assert capsys.readouterr().err == ""


def test_the_gmsh_readers_warning_is_logged_not_printed(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], caplog: pytest.LogCaptureFixture
) -> None:
    """A file that lacks its last line ($EndElements) is read (its elements are complete);
    meshio's warning is logged, naming the file, not printed."""
    p = _cut(DATA / "two_blocks_v22.msh", tmp_path / "e.msh", slice(0, -1))
    with caplog.at_level(logging.WARNING):
        read_mesh(p)
    assert capsys.readouterr().err == ""
    assert (f"{p}: the section $Elements is not closed by $EndElements: the file may be "
            "truncated") in caplog.text  # fmt: skip


def test_a_nan_node_tag_is_named_and_numpy_warnings_are_not_shown(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    lines = (DATA / "two_blocks_v22.msh").read_text().splitlines(keepends=True)
    k = lines.index("$Nodes\n") + 2
    lines[k] = "nan " + " ".join(lines[k].split()[1:]) + "\n"
    p = tmp_path / "nan.msh"
    p.write_text("".join(lines))
    with warnings.catch_warnings(record=True) as shown:
        warnings.simplefilter("always")
        with pytest.raises(MeshError, match=rf"line {k + 1} \(section \$Nodes\): 'nan .*' is not "
                           "finite numbers: the file is corrupt"):  # fmt: skip
            read_mesh(p)
    assert [str(w.message) for w in shown] == []  # numpy's, inside the reader
    assert capsys.readouterr().err == ""


# -- 2. a mesh given where a model file is expected -----------------------------------------
@pytest.mark.parametrize("command", ["check", "run"])
def test_a_mesh_given_as_the_model_file_is_named_a_mesh(
    capsys: pytest.CaptureFixture[str], command: str
) -> None:
    p = DATA / "two_blocks_v22.msh"
    err = cli_fails(capsys, [command, str(p)])
    assert err.strip() == (f"pfeie: error: {p}: expected a model file (.toml); this looks like a "
                           "gmsh mesh, which a model file names under [mesh] file")  # fmt: skip


def test_a_mesh_given_as_the_study_file_is_named_a_mesh(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    p = tmp_path / "dam.txt"  # by its content, whatever its name
    p.write_text((DATA / "two_blocks_v41.msh").read_text())
    cli_fails(capsys, ["study", str(p)], f"{p}: expected a study file (.toml); this looks like a "
          "gmsh mesh")  # fmt: skip


def test_a_mesh_given_as_a_record_is_named_a_mesh() -> None:
    p = DATA / "two_blocks_v41.msh"
    with pytest.raises(RecordError) as exc:
        read_record(p, units="g", dt=0.01)
    assert str(exc.value) == f"{p}: expected a ground-motion record; this looks like a gmsh mesh"


# -- a small model: two blocks on a joint (tests/data/two_blocks_v41.msh) --------------------
MODEL = f"""
[mesh]
file = "{DATA / "two_blocks_v41.msh"}"
[materials.concrete]
E = 30e9
nu = 0.2
rho = 2400.0
[blocks]
rock = "concrete"
dam = "concrete"
[interfaces.joint]
friction_angle = 30.0
[[supports]]
group = "bottom"
[[ground_motion]]
file = "rec.csv"
units = "UNITS"
[analysis]
dt = 0.01
[output]
folder = "out"
"""


def _model(tmp: Path, units: str = "g", record: str = "", text: str = MODEL) -> Path:
    (tmp / "rec.csv").write_text(record or "".join(
        f"{0.01 * k:.2f},{0.2 * (k % 3 - 1):.4f}\n" for k in range(40)))  # fmt: skip
    p = tmp / "model.toml"
    p.write_text(text.replace("UNITS", units))
    return p


# -- 3. a record in g declared in cm/s2 -------------------------------------------------------
def test_a_record_in_g_declared_in_cm_s2_is_warned(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    p = _model(tmp_path, units="cm/s2")
    with caplog.at_level(logging.WARNING):
        load_job(p)
    assert (f"{p}: ground_motion[0]: rec.csv: the record's PGA is 0.000204 g with its values "
            "read in cm/s2 (units = 'cm/s2'): below the plausible 0.001 to 2.5 g; are its "
            "values in g? (units = 'g' gives 0.2 g)") in caplog.text  # fmt: skip


@pytest.mark.parametrize(("units", "extra"), [("g", ""), ("cm/s2", "pga = 0.2")])
def test_a_plausible_or_rescaled_record_is_not_warned(
    tmp_path: Path, caplog: pytest.LogCaptureFixture, units: str, extra: str
) -> None:
    p = _model(tmp_path, units=units, text=MODEL.replace('units = "UNITS"',
                                                         f'units = "UNITS"\n{extra}'))  # fmt: skip
    with caplog.at_level(logging.WARNING):
        load_job(p)
    assert "the plausible" not in caplog.text  # (the folder's name has "plausible")


def test_a_record_too_strong_names_the_likely_units() -> None:
    msg = implausible_pga("r.csv", 9.81 * 98.1, "m/s2")  # 981 cm/s2 read as m/s2: 98 g
    assert msg == ("r.csv: the record's PGA is 98.1 g with its values read in m/s2 (units = "
                   "'m/s2'): above the plausible 0.001 to 2.5 g; are its values in cm/s2? "
                   "(units = 'cm/s2' gives 0.981 g)")  # fmt: skip


def test_a_record_in_m_s2_read_as_g_is_warned() -> None:
    """El Centro's 0.319 g written in m/s² (3.13) and read as g: 3.13 g, beyond the
    strongest motions recorded (2 to 3 g): warned, with the units that fit (a new user's
    AT2 file ran without a word when the limit was 10 g)."""
    msg = implausible_pga("r.AT2", 9.81 * 3.13, "g")
    assert msg is not None and "above the plausible 0.001 to 2.5 g" in msg
    assert "are its values in m/s2? (units = 'm/s2' gives 0.319 g)" in msg


def test_a_record_cut_short_is_warned(tmp_path: Path, caplog: pytest.LogCaptureFixture) -> None:
    """A record that ends before analysis.duration with its last sample at its PGA (a new
    user's study padded a final −0.115 g with zeros, without a word): a warning names the
    file, the time and the step; a run of the record's own length has none."""
    p = _model(tmp_path, text=MODEL.replace("dt = 0.01", "dt = 0.01\nduration = 1.0"))
    with caplog.at_level(logging.WARNING):
        load_job(p)
    assert (f"{p}: ground_motion[0]: rec.csv: the record ends at 0.39 s with -0.2 g (100 % of "
            "its PGA), before the end of the run (1 s): from there the ground acceleration is "
            "zero, a step of -0.2 g (a record cut short?)") in caplog.text  # fmt: skip
    caplog.clear()
    with caplog.at_level(logging.WARNING):
        load_job(_model(tmp_path))
    assert "cut short" not in caplog.text


# -- 4. decimal commas in a record ----------------------------------------------------------
@pytest.mark.parametrize(
    ("text", "dt", "line", "shown"),
    [("0,0000\n0,0123\n-0,0150\n", 0.01, 1, "0,0000"),
     ("acc (g)\n0,0000\n0,0123\n-0,0150\n", None, 2, "0,0000"),
     ("0,5\n-0,3\n0,25\n", 0.01, 1, "0,5"),
     ("0,5\n-0,3\n0,25\n", None, 1, "0,5"),
     ("0\t0,0\n0,01\t0,1\n", None, 1, "0\\t0,0")],
)  # fmt: skip
def test_decimal_commas_are_named(tmp_path: Path, text: str, dt: float | None, line: int,
                                  shown: str) -> None:  # fmt: skip
    p = tmp_path / "r.txt"
    p.write_text(text)
    with pytest.raises(RecordError) as exc:
        read_record(p, units="g", dt=dt)
    assert str(exc.value) == (f"{p}: line {line}: decimal commas in '{shown}'; expected "
                              "numbers with a decimal point (0.0123, not 0,0123)")  # fmt: skip


@pytest.mark.parametrize("text", ["0,0\n1,5\n2,3\n", "0, 0\n0.01, 0.1\n0.02, 0.0\n"])
def test_commas_between_columns_are_not_decimal_commas(tmp_path: Path, text: str) -> None:
    p = tmp_path / "r.csv"
    p.write_text(text)
    assert read_record(p, units="m/s2").time.size == 3


# -- 5. a tensile strength beyond the apex of the Mohr-Coulomb cone --------------------------
@pytest.mark.parametrize(
    ("joint", "words"),
    [('cohesion = 0.5e6\ntensile_strength = 3.0e6\ninitial = "intact"',
      "interfaces.joint.tensile_strength: 3e+06 Pa lies beyond the apex of the intact "
      "strength, cohesion / tan(friction_angle) = 500000 Pa (cohesion = 500000 Pa, "
      "friction_angle = 45°): an intact pair in tension beyond it has no shear capacity; "
      "expected tensile_strength <= 500000 Pa (0 without cohesion)"),
     ("residual_cohesion = 1e5\nresidual_tensile_strength = 1e6\nresidual_friction_angle = 40.0",
      "interfaces.joint.residual_tensile_strength: 1e+06 Pa lies beyond the apex of the "
      "residual strength, residual_cohesion / tan(residual_friction_angle) = 119175 Pa "
      "(residual_cohesion = 100000 Pa, residual_friction_angle = 40°): a broken pair in "
      "tension beyond it has no shear capacity; expected residual_tensile_strength <= "
      "119175 Pa (0 without residual_cohesion)"),
     # a cohesion in MPa beside a tensile strength in Pa: the unit is said first
     ('cohesion = 0.5\ntensile_strength = 0.3e6\ninitial = "intact"',
      "interfaces.joint.tensile_strength: cohesion = 0.5 Pa is very low: given in MPa "
      "(500000 Pa) or kPa (500 Pa)? pfeie takes SI units. 300000 Pa lies beyond the apex of "
      "the intact strength, cohesion / tan(friction_angle) = 0.5 Pa")],
)  # fmt: skip
def test_a_tensile_strength_beyond_the_apex_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], joint: str, words: str
) -> None:
    text = MODEL.replace("friction_angle = 30.0", f"friction_angle = 45.0\n{joint}")
    p = _model(tmp_path, text=text)
    cli_fails(capsys, ["check", str(p)], f"{p}: {words}")


def test_a_tensile_strength_at_the_apex_or_of_a_broken_joint_is_accepted(tmp_path: Path) -> None:
    for joint in ('cohesion = 0.5e6\ntensile_strength = 0.5e6\ninitial = "intact"',
                  "cohesion = 0.5e6\ntensile_strength = 3.0e6"):  # starts broken: not acting
        text = MODEL.replace("friction_angle = 30.0", f"friction_angle = 45.0\n{joint}")
        load_job(_model(tmp_path, text=text))


# -- 6. coincident nodes that no cell and no declared joint joins ----------------------------
def _two_quads_unshared() -> str:
    """MSH 2.2: quads "rock" (y in [0, 1]) and "dam" (y in [1, 2]) meshed apart: the dam's
    nodes 5 and 6 lie on the rock's nodes 4 and 3 without being them; "bottom" at y = 0."""
    nodes = [(0, 0), (1, 0), (1, 1), (0, 1), (0, 1), (1, 1), (1, 2), (0, 2)]
    lines = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", "3",
             '2 1 "rock"', '2 2 "dam"', '1 3 "bottom"', "$EndPhysicalNames", "$Nodes", "8"]
    lines += [f"{i} {x} {y} 0" for i, (x, y) in enumerate(nodes, start=1)]
    lines += ["$EndNodes", "$Elements", "3", "1 1 2 3 3 1 2", "2 3 2 1 1 1 2 3 4",
              "3 3 2 2 2 5 6 7 8", "$EndElements"]  # fmt: skip
    return "\n".join(lines) + "\n"


UNSHARED = """
[mesh]
file = "quads.msh"
[materials.concrete]
E = 30e9
nu = 0.2
rho = 2400.0
[blocks]
rock = "concrete"
dam = "concrete"
[[supports]]
group = "bottom"
[analysis]
dynamic = false
[output]
folder = "out"
"""


def test_coincident_unshared_nodes_are_warned(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    (tmp_path / "quads.msh").write_text(_two_quads_unshared())
    p = tmp_path / "model.toml"
    p.write_text(UNSHARED)
    with caplog.at_level(logging.WARNING):
        load_job(p)
    assert (f"{p}: 2 pair(s) of coincident nodes between the blocks 'rock' and 'dam' are not "
            "shared (the first at [1, 1]): the sides are not joined there, a crack that no "
            "[interfaces] table declares (meshed separately?); expected shared nodes (gmsh: "
            "fragment the geometry), with an [interfaces] table for a joint"
            ) in caplog.text  # fmt: skip


def test_a_joint_declared_on_unshared_nodes_names_them(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    text = _two_quads_unshared().replace('"bottom"\n', '"bottom"\n1 4 "joint"\n').replace(
        "$PhysicalNames\n3", "$PhysicalNames\n4").replace("$Elements\n3", "$Elements\n4")
    (tmp_path / "quads.msh").write_text(text.replace("$EndElements", "4 1 2 4 4 4 3\n$EndElements"))
    p = tmp_path / "model.toml"
    p.write_text(UNSHARED.replace("[[supports]]", "[interfaces.joint]\nfriction_angle = 30.0\n"
                                  "[[supports]]"))  # fmt: skip
    cli_fails(capsys, ["check", str(p)], "interface 'joint' has facets on the mesh boundary",
          "; the mesh has 2 pair(s) of coincident nodes that are not shared (the first at [1, "
          "1]): blocks meshed separately? (gmsh: fragment the geometry, so that they share the "
          "joint's nodes)")  # fmt: skip


def test_the_nodes_of_a_declared_joint_are_not_counted(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    with caplog.at_level(logging.WARNING):
        job = load_job(_model(tmp_path))
    assert job.model.pairs is not None and job.model.pairs.n > 0
    assert job.model.unshared_coincident_nodes() == []
    assert "coincident" not in caplog.text


def test_a_crack_inside_one_block_is_found() -> None:
    a = pf.rectangle(1.0, 1.0, 2, 2)
    b = pf.rectangle(1.0, 1.0, 2, 2)
    pts = np.vstack([a.points, b.points + np.array([1.0, 0.0])])  # side by side, x = 1 twice
    cells = {"quad": np.vstack([a.cells["quad"], b.cells["quad"] + a.n_points])}
    mesh = pf.Mesh(pts, cells, {"all": {"quad": np.arange(8)}})
    model = pf.Model(mesh, [pf.Block("all", pf.Elastic(E=1e9, nu=0.2, rho=2000.0))])
    ((ga, gb, n, x),) = model.unshared_coincident_nodes()
    assert (ga, gb, n) == ("all", "all", 3) and x.tolist() == [1.0, 0.0]
    assert pf.rectangle(2.0, 1.0, 4, 2).coincident_nodes().shape == (0, 2)


# -- 7. an unwritable report path is refused before the report is built ----------------------
def test_an_unwritable_report_path_fails_before_any_work(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    p = tmp_path / "model.toml"
    p.write_text(UNSHARED.replace('"quads.msh"', f'"{DATA / "two_blocks_v22.msh"}"'))
    assert main(["run", str(p), "--quiet"]) == 0
    capsys.readouterr()
    import pfeie.plot._report as report

    def no_work(*args: object) -> None:
        raise AssertionError("the report was built before its output was checked")

    monkeypatch.setattr(report, "model_of_run", no_work)
    (tmp_path / "afile").write_text("")
    out = tmp_path / "afile" / "report.html"
    cli_fails(capsys, ["report", str(tmp_path / "out" / "results.h5"), "--out", str(out)],
          f"pfeie: error: --out: {out}: cannot write the file: {tmp_path / 'afile'}: is a file, "
          "not a folder")  # fmt: skip


# -- 8. errors at a key that --set gave say so -------------------------------------------------
@pytest.mark.parametrize(
    ("setting", "words"),
    [("blocks.dam=steel", "blocks.dam (from --set blocks.dam=steel): unknown material 'steel'"),
     ("mesh.file=none.msh", "mesh.file (from --set mesh.file=none.msh): "),
     ('supports[0].group="nope"', "supports[0].group (from --set supports[0].group=\"nope\"): "
      "no physical group 'nope'"),
     ("ground_motion[3].scale=2", "ground_motion[3].scale (from --set ground_motion[3].scale=2):"
      " no item 3 (the file has 1)"),
     ("analysis.dtt=0.1", "analysis.dtt (from --set analysis.dtt=0.1): unknown key"),
     ("colour.x=1", "colour (from --set colour.x=1): unknown key"),
     ("interfaces.other.cohesion=1e5", "interfaces.other.friction_angle (from --set "
      "interfaces.other.cohesion=1e5): missing (required)"),
     ("ground_motion[0].file=none.csv", "ground_motion[0] (with --set "
      "ground_motion[0].file=none.csv): ")],
)  # fmt: skip
def test_an_error_at_a_key_set_on_the_command_line_names_the_setting(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], setting: str, words: str
) -> None:
    p = _model(tmp_path)
    cli_fails(capsys, ["check", str(p), "--set", setting], f"pfeie: error: {p}: {words}")


def test_an_error_elsewhere_does_not_name_the_setting(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    p = _model(tmp_path, text=MODEL.replace('dam = "concrete"', 'dam = "steel"'))
    err = cli_fails(capsys, ["check", str(p), "--set", "analysis.dt=0.02"], "blocks.dam: unknown")
    assert "--set" not in err


# -- 9. the mesh generators refuse sizes <= 0 and counts < 1 ---------------------------------
@pytest.mark.parametrize(
    ("make", "words"),
    [(lambda: pf.box(-1, 1, 1), "box: lx: expected a length > 0 (m), got -1"),
     (lambda: pf.box(1, 1, 0.0), "box: lz: expected a length > 0 (m), got 0.0"),
     (lambda: pf.rectangle(1, float("nan")), "rectangle: ly: expected a length > 0 (m), got nan"),
     (lambda: pf.rectangle(1, 1, 0), "rectangle: nx: expected a whole number of elements >= 1, "
      "got 0"),
     (lambda: pf.box(1, 1, 1, 2, np.int64(-3)), "box: ny: expected a whole number of elements "
      ">= 1, got -3"),
     (lambda: pf.rectangle(1, 1, 1.5), "rectangle: nx: expected a whole number of elements >= "
      "1, got 1.5"),
     (lambda: pf.rectangle(1, 1, origin=(0.0,)), "rectangle: origin: expected 2 finite "
      "coordinates (m), got (0.0,)")],
)  # fmt: skip
def test_a_mesh_generator_refuses_a_size_or_count_out_of_range(make, words: str) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(ValueError) as exc:
        make()
    assert str(exc.value) == words
    assert isinstance(exc.value, MeshError)


# -- 10. numpy scalars in messages are printed as plain numbers ------------------------------
def test_numpy_scalars_in_messages_print_as_plain_numbers() -> None:
    model = pf.Model(pf.rectangle(1.0, 1.0), [pf.Block("all", pf.Elastic(1e9, 0.2, 2000.0))])
    with pytest.raises(ModelError) as exc:
        model.fix("xmin", components=np.array([2]))
    assert str(exc.value).endswith("components: expected integers in 0..1 (0 = x), got [2]")
    with pytest.raises(ModelError) as exc:
        model.fix("xmin", components=["w"])  # type: ignore[list-item]
    assert str(exc.value).endswith("got ['w']")
    with pytest.raises(ModelError, match=r"refine must be an integer >= 1, got 0$"):
        model.add_reservoir(["xmax"], water_level=1.0, refine=np.int64(0))


# -- 11. the water levels of one reservoir, and the uplift's upstream side --------------------
DAM = f"""
[mesh]
file = "{DATA / "dam_lift_joint.msh"}"
[materials.concrete]
E = 25e9
nu = 0.2
rho = 2400.0
[blocks]
dam_lower = "concrete"
dam_upper = "concrete"
rock = "concrete"
[interfaces.dam_rock]
friction_angle = 45.0
cohesion = 0.5e6
tensile_strength = 0.2e6
initial = "intact"
[interfaces.lift]
friction_angle = 45.0
cohesion = 0.5e6
initial = "intact"
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
[output]
folder = "out"
"""


@pytest.mark.parametrize(
    ("edit", "words"),
    [(("headwater = 18.0", "headwater = 16.0"),
      "loads.uplift[0].headwater = 16 m differs from loads.hydrostatic[0].water_level = 18 m "
      "(the reservoir: the highest water on the faces): one reservoir, two levels; intended?"),
     (("water_level = 18.0\n[[loads.uplift]]", "water_level = 17.0\n[[loads.uplift]]"),
      "loads.westergaard[0].water_level = 17 m differs from loads.hydrostatic[0].water_level = "
      "18 m on the same face(s) 'upstream': one reservoir, two levels; intended?"),
     (("headwater = 18.0", 'headwater = 18.0\nupstream = "+x"'),
      "loads.uplift[0].upstream = '+x' puts the heel of 'dam_rock' at x = 15 m, but the water "
      "of loads.hydrostatic[0] wets faces about x = -5.526 m, past the joint's other end (x = 0 "
      "m); expected upstream = '-x'?")],
)  # fmt: skip
def test_two_levels_of_one_reservoir_or_the_wrong_side_are_warned(
    tmp_path: Path, caplog: pytest.LogCaptureFixture, edit: tuple[str, str], words: str
) -> None:
    p = tmp_path / "dam.toml"
    p.write_text(DAM.replace(*edit))
    with caplog.at_level(logging.WARNING):
        load_job(p)
    assert f"{p}: {words}" in caplog.text


def test_one_reservoir_at_one_level_is_not_warned(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    p = tmp_path / "dam.toml"
    p.write_text(DAM)
    with caplog.at_level(logging.WARNING):
        load_job(p)
    assert "two levels" not in caplog.text and "upstream =" not in caplog.text


def test_an_intact_joint_beyond_its_apex_is_refused_in_python() -> None:
    """The same rule through the Python API (pf.Joint): an intact joint's tensile strength
    beyond c / tan φ is refused, naming both; at the apex, or for a broken joint (whose
    intact strength is never used), it is accepted."""
    from pfeie.errors import ModelError

    with pytest.raises(ModelError, match=r"tensile = 3e\+06 Pa lies beyond the apex.*500000 Pa"):
        pf.Joint(c=0.5e6, phi=45.0, tensile=3e6, initial="intact")
    pf.Joint(c=0.5e6, phi=45.0, tensile=0.5e6, initial="intact")
    pf.Joint(c=0.5e6, phi=45.0, tensile=3e6)


def test_a_results_file_being_written_is_named_so(tmp_path: Path) -> None:
    """A results file that a run holds open (HDF5's lock) read by `pfeie plot`, `report`
    or `Results` (new-user finding: "not an HDF5 file ... unable to lock file"): the error
    says that a run writes it, with the process id of the folder's lock, and how to read
    it."""
    import subprocess
    import sys

    import h5py

    f = h5py.File(tmp_path / "results.h5", "w")  # this process holds the write lock
    try:
        (tmp_path / ".pfeie-run.lock").write_text("12345\nm.toml\n")
        code = ("from pfeie.io import Results\n"
                f"try:\n    Results(r'{tmp_path / 'results.h5'}')\n"
                "except Exception as e:\n    print(type(e).__name__, e)\n")  # fmt: skip
        out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                             check=True).stdout  # fmt: skip
    finally:
        f.close()
    assert out.startswith("ResultsError")
    assert "being written by a running `pfeie run` (pid 12345)" in out
    assert "HDF5_USE_FILE_LOCKING=FALSE" in out


@pytest.mark.parametrize(("pga", "warned"), [(3.0, True), (0.5, False)])
def test_a_pga_key_in_m_s2_is_warned(tmp_path: Path, caplog: pytest.LogCaptureFixture,
                                     pga: float, warned: bool) -> None:  # fmt: skip
    """``pga = 3.0`` meant as m/s² runs at 3 g (new-user finding): above 2 g it is warned,
    giving the value in g of the same number in m/s²."""
    p = _model(tmp_path, text=MODEL.replace('units = "UNITS"', f'units = "g"\npga = {pga}'))
    with caplog.at_level(logging.WARNING):
        load_job(p)
    assert ("ground_motion[0].pga = 3 g lies above 2 g (strong records: 0.1 to 1.5 g); pga is "
            "in g: for 3 m/s² give pga = 0.306" in caplog.text) == warned  # fmt: skip


def test_a_header_line_of_another_format_is_quoted_whole(tmp_path: Path) -> None:
    """Text in a record's data is quoted as it stands (new-user finding: the quote dropped
    the letters e and d, 'SAMPLING_INTRVAL_S:'), with the formats pfeie reads."""
    from pfeie.errors import RecordError

    (tmp_path / "r.asc").write_text("0.0 0.1\nSAMPLING_INTERVAL_S: 0.01\n0.02 0.3\n")
    with pytest.raises(RecordError, match=r"line 2: non-numeric text .SAMPLING_INTERVAL_S:. in "
                       r"the data: "
                       r"'SAMPLING_INTERVAL_S: 0.01'; expected numbers \(pfeie reads PEER"):
        read_record(tmp_path / "r.asc", units="g")


def test_a_zero_gravity_direction_without_gravity_is_read_quietly(tmp_path: Path) -> None:
    """``loads.gravity = 0`` with ``gravity_direction = [0, 0]`` (the slow fuzz's input):
    the model file is read without a NumPy RuntimeWarning (the record's check against a
    tilted gravity divided by the direction's zero length)."""
    p = _model(tmp_path, text=MODEL + "[loads]\ngravity = 0.0\ngravity_direction = [0.0, 0.0]\n")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        job = load_job(p)
    assert job.records
