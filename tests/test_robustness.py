"""Wrong inputs and edge models through the command line: each ends in exit 2 with a
``pfeie: error`` line naming the file (and key, group, gmsh element id or line) and what
was expected, never a traceback; a static-only run goes through plot, report and export;
every dataset of a results file has units."""

from __future__ import annotations

import logging
from pathlib import Path

import numpy as np
import pytest

import pfeie as pf
from conftest import cli_fails
from pfeie.cli import main
from pfeie.errors import MeshError, ModelError, RecordError, ResultsError
from pfeie.io import Results, read_mesh, read_record

# a 2 m × 1 m plate of two quadrilaterals (gmsh ids 10 and 11) on a line "bottom"; "mid"
# is the interior line between them
NODES = [(0, 0, 0), (1, 0, 0), (2, 0, 0), (0, 1, 0), (1, 1, 0), (2, 1, 0)]
NAMES = {1: (2, "all"), 3: (1, "bottom"), 4: (1, "mid"), 5: (1, "top")}
ELEMENTS = [(1, 1, 3, [1, 2]), (2, 1, 3, [2, 3]), (3, 1, 4, [2, 5]), (4, 1, 5, [4, 5]),
            (5, 1, 5, [5, 6]), (10, 3, 1, [1, 2, 5, 4]), (11, 3, 1, [2, 3, 6, 5])]  # fmt: skip

MODEL = """
[mesh]
file = "plate.msh"
[materials.rock]
E = 1e9
nu = 0.25
rho = 2000.0
[blocks]
all = "rock"
[[supports]]
group = "bottom"
[analysis]
EXTRA
[output]
folder = "out"
"""


def msh22(path: Path, nodes=NODES, elements=ELEMENTS, names=NAMES) -> Path:  # type: ignore[no-untyped-def]
    """A gmsh MSH 2.2 ASCII file: nodes (x, y, z), elements (id, gmsh type, physical, nodes)."""
    lines = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", str(len(names))]
    lines += [f'{d} {tag} "{name}"' for tag, (d, name) in names.items()]
    lines += ["$EndPhysicalNames", "$Nodes", str(len(nodes))]
    lines += [f"{i} {x} {y} {z}" for i, (x, y, z) in enumerate(nodes, start=1)]
    lines += ["$EndNodes", "$Elements", str(len(elements))]
    lines += [f"{i} {t} 2 {ph} {ph} " + " ".join(map(str, ns)) for i, t, ph, ns in elements]
    lines += ["$EndElements"]
    path.write_text("\n".join(lines) + "\n")
    return path


def model(tmp: Path, extra: str = "dynamic = false", text: str = MODEL, **mesh) -> Path:  # type: ignore[no-untyped-def]
    msh22(tmp / "plate.msh", **mesh)
    p = tmp / "model.toml"
    p.write_text(text.replace("EXTRA", extra))
    return p




# -- item: a static-only run goes through plot, report and export ---------------------------
def test_static_only_run_plots_reports_and_exports(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A static-only run of a model with a joint: plot writes the static joint figure,
    report the page with the static joint table, export the static tables."""
    text = MODEL.replace('all = "rock"', 'all = "rock"\n[interfaces.mid]\nfriction_angle = 30.0')
    msh22(tmp_path / "plate.msh")
    # "mid" splits the plate in two bodies, both on the support "bottom"
    p = tmp_path / "model.toml"
    p.write_text(text.replace("EXTRA", "dynamic = false"))
    assert main(["run", str(p), "--quiet"]) == 0
    res = tmp_path / "out" / "results.h5"
    with Results(res) as r:
        assert r.n_times == 0 and r.has_static
    assert main(["plot", str(res)]) == 0
    assert (tmp_path / "out" / "figures" / "static_mid.png").stat().st_size > 1000
    assert main(["report", str(res)]) == 0
    page = (tmp_path / "out" / "report.html").read_text()
    assert "static state only" in page and "static normal stress" in page
    assert main(["export", str(res), "--csv", str(tmp_path / "csv")]) == 0
    rows = (tmp_path / "csv" / "pairs_static.csv").read_text().splitlines()
    assert rows[0].startswith("joint,pair") and len(rows) == 1 + 2  # two pairs on "mid"
    # the shear stress signed, along t: the results file's X_t / A to the CSV's 9 digits
    import csv

    table = list(csv.DictReader((tmp_path / "csv" / "pairs_static.csv").open()))
    with Results(res) as r:
        tau = r.static_pairs("mid")["shear_stress"][:, 0]
    np.testing.assert_allclose([float(t["shear_stress_Pa"]) for t in table], tau, rtol=1e-8,
                               atol=1e-12)  # fmt: skip
    assert (tmp_path / "csv" / "nodes_static.csv").is_file()


def test_static_only_run_without_interfaces(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Without interfaces there is nothing to plot (exit 2, said so); report and export
    still work."""
    p = model(tmp_path)
    assert main(["run", str(p), "--quiet"]) == 0
    res = str(tmp_path / "out" / "results.h5")
    capsys.readouterr()
    cli_fails(capsys, ["plot", res], "results.h5", "nothing to plot", "static-only")
    assert main(["report", res]) == 0
    assert main(["export", res, "--csv", str(tmp_path / "csv")]) == 0
    assert [f.name for f in sorted((tmp_path / "csv").iterdir())] == ["nodes_static.csv"]


# -- item: files that are not results files ------------------------------------------------
@pytest.mark.parametrize("command", ["plot", "report", "export"])
def test_not_a_results_file(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], command: str
) -> None:
    import h5py

    other = tmp_path / "other.h5"
    with h5py.File(other, "w") as f:
        f["x"] = [1.0, 2.0]
    text = tmp_path / "text.h5"
    text.write_text("not hdf5\n")
    extra = ["--csv", str(tmp_path / "csv")] if command == "export" else []
    cli_fails(capsys, [command, str(other), *extra], "other.h5", "not a pfeie results file",
          "pfeie_version", "written by `pfeie run`")  # fmt: skip
    cli_fails(capsys, [command, str(text), *extra], "text.h5", "not an HDF5 file")
    cli_fails(capsys, [command, str(tmp_path / "none.h5"), *extra], "none.h5", "not found")
    with pytest.raises(ResultsError, match="lacks"):
        Results(other)


# -- item: output folders --------------------------------------------------------------------
def test_output_folder_that_cannot_be_made(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    (tmp_path / "afile").write_text("x")
    p = model(tmp_path, text=MODEL.replace('folder = "out"', 'folder = "afile"'))
    cli_fails(capsys, ["run", str(p), "--quiet"], "model.toml", "output.folder", "afile",
          "is a file, not a folder")  # fmt: skip
    p.write_text(MODEL.replace("EXTRA", "dynamic = false").replace(
        'folder = "out"', 'folder = "afile/sub"'))  # fmt: skip
    cli_fails(capsys, ["run", str(p), "--quiet"], "output.folder", "afile/sub",
          "cannot create the output folder")  # fmt: skip
    p.write_text(MODEL.replace("EXTRA", "dynamic = false").replace(
        'folder = "out"', 'folder = "o\\u0000ut"'))  # fmt: skip
    cli_fails(capsys, ["check", str(p)], "output.folder", "NUL")
    p.write_text(MODEL.replace("EXTRA", "dynamic = false"))
    assert main(["run", str(p), "--quiet"]) == 0
    res = str(tmp_path / "out" / "results.h5")
    cli_fails(capsys, ["export", res, "--csv", str(tmp_path / "afile")], "afile", "not a folder")
    cli_fails(capsys, ["report", res, "--out", str(tmp_path / "afile" / "r.html")], "afile")
    cli_fails(capsys, ["report", res, "--out", str(tmp_path)], str(tmp_path), "is a folder")


# -- item: meshes ----------------------------------------------------------------------------
def test_bow_tie_and_degenerate_cells_are_named_by_gmsh_id(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    bow = [e if e[0] != 11 else (11, 3, 1, [2, 3, 5, 6]) for e in ELEMENTS]
    p = model(tmp_path, elements=bow)
    cli_fails(capsys, ["check", str(p)], "plate.msh", "inverted or self-intersecting",
          "gmsh element 11")  # fmt: skip
    nodes = [*NODES[:5], (3.0, 0.0, 0.0)]  # node 6 on the line of nodes 2, 3: a flat quad
    flat = [e if e[0] != 11 else (11, 3, 1, [2, 3, 6, 5]) for e in ELEMENTS]
    flat[-1] = (11, 2, 1, [2, 3, 6])  # a triangle on three collinear nodes
    p = model(tmp_path, nodes=nodes, elements=flat)
    cli_fails(capsys, ["check", str(p)], "plate.msh", "degenerate triangle", "gmsh element 11")
    twice = [*ELEMENTS, (12, 3, 1, [2, 3, 6, 5])]
    p = model(tmp_path, elements=twice)
    cli_fails(capsys, ["check", str(p)], "duplicated", "gmsh element 11 and gmsh element 12")


def test_cell_type_without_element_is_refused(tmp_path: Path) -> None:
    """A prism (gmsh type 6, id 11) in a physical volume with a tetrahedron: pfeie has no
    prism element, so the mesh is refused, naming the group, the gmsh id and the types it
    has (it dropped the prism without a word)."""
    nodes = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, -1), (0, 0, 1), (1, 0, 1), (0, 1, 1)]
    elements = [(10, 4, 1, [1, 2, 3, 4]), (11, 6, 1, [1, 2, 3, 5, 6, 7])]
    path = msh22(tmp_path / "p.msh", nodes=nodes, elements=elements, names={1: (3, "all")})
    with pytest.raises(MeshError, match=r"p\.msh: physical group 'all': 1 wedge cell\(s\) "
                       r"\(gmsh element 11\); pfeie has elements for .*tetra10"):  # fmt: skip
        read_mesh(path)


def test_shape_quality_closed_forms_and_the_warning(
    tmp_path: Path, caplog: pytest.LogCaptureFixture, capsys: pytest.CaptureFixture[str]
) -> None:
    """The mean-ratio shape quality (Knupp 2001) against its closed forms: 1 for a square,
    an equilateral triangle, a cube and a regular tetrahedron (to round-off); a rectangle
    of aspect ratio r gives 2r/(1 + r²), a right isosceles triangle √3/2 (its mean ratio,
    4√3 A/Σl² = 0.866025), whatever their size and orientation. A mesh with a cell of
    aspect ratio 50 (quality 0.04 < 0.05) passes ``check`` with a warning that names the
    gmsh element and the worst quality; ``pfeie check`` prints the worst quality per cell
    type, naming the cell."""
    from pfeie.mesh import shape_quality

    one = np.arange(4)[None]
    sq = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    rot = np.array([[np.cos(0.3), -np.sin(0.3)], [np.sin(0.3), np.cos(0.3)]])
    for r in (1.0, 4.0, 50.0):
        q = shape_quality(3.7 * (sq * [r, 1.0]) @ rot.T, "quad", one)[0]
        assert q == pytest.approx(2 * r / (1 + r * r), rel=1e-14)
    tri = np.array([[0.0, 0.0], [2.0, 0.0], [1.0, np.sqrt(3.0)]])
    assert shape_quality(tri, "triangle", np.arange(3)[None])[0] == pytest.approx(1.0, rel=1e-14)
    right = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    assert shape_quality(right, "triangle", np.arange(3)[None])[0] == pytest.approx(
        np.sqrt(3.0) / 2, rel=1e-14)  # fmt: skip
    cube = pf.box(1.0, 1.0, 1.0, 1, 1, 1, cell="hexahedron")
    assert shape_quality(cube.points, "hexahedron", cube.cells["hexahedron"]) == pytest.approx(1.0)
    reg = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, np.sqrt(3) / 2, 0.0],
                    [0.5, np.sqrt(3) / 6, np.sqrt(2.0 / 3.0)]])  # fmt: skip
    assert shape_quality(reg, "tetra", np.arange(4)[None])[0] == pytest.approx(1.0, rel=1e-14)
    # a sliver: 50 × 1 cells in a gmsh file
    nodes = [(0.0, 0.0, 0.0), (50.0, 0.0, 0.0), (50.0, 1.0, 0.0), (0.0, 1.0, 0.0)]
    path = msh22(tmp_path / "sliver.msh", nodes=nodes, elements=[(7, 3, 1, [1, 2, 3, 4])],
                 names={1: (2, "all")})  # fmt: skip
    with caplog.at_level("WARNING"):
        read_mesh(path)
    assert "1 poorly shaped quad cell(s)" in caplog.text and "gmsh element 7" in caplog.text
    assert "worst 0.04" in caplog.text
    p = model(tmp_path)
    assert main(["check", str(p)]) == 0
    out = capsys.readouterr().out
    assert "shape        quad: worst quality" in out and "gmsh element" in out


def test_cells_named_by_index_without_gmsh() -> None:
    import pfeie as pf

    mesh = pf.rectangle(2.0, 1.0, 2, 1)
    mesh.cells["quad"][1] = mesh.cells["quad"][1][[0, 1, 3, 2]]
    with pytest.raises(MeshError, match="quad cell 1"):
        mesh.check()


def test_plane_mesh_outside_x_y(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    xz = [(x, 0.0, y) for x, y, _ in NODES]  # the plate drawn in the x-z plane
    p = model(tmp_path, nodes=xz)
    cli_fails(capsys, ["check", str(p)], "plate.msh", "x-y plane", "expected z = 0")
    tilted = [(x, y, 0.1 * y) for x, y, _ in NODES]
    with pytest.raises(MeshError, match="x-y plane"):
        read_mesh(msh22(tmp_path / "t.msh", nodes=tilted))
    flat = [(x, y, 5.0) for x, y, _ in NODES]  # parallel to x-y: z dropped
    assert read_mesh(msh22(tmp_path / "f.msh", nodes=flat)).dim == 2


def test_3d_mesh_with_plane_stress(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    nodes = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
    names = {1: (3, "all"), 3: (2, "bottom")}
    elements = [(1, 2, 3, [1, 2, 3]), (2, 4, 1, [1, 2, 3, 4])]
    p = model(tmp_path, nodes=nodes, elements=elements, names=names,
              text='plane = "stress"\n' + MODEL)  # fmt: skip
    cli_fails(capsys, ["check", str(p)], "model.toml", "plane", "3D", "remove plane")
    p.write_text(MODEL.replace("EXTRA", "dynamic = false"))
    assert main(["check", str(p)]) == 0
    import pfeie as pf

    with pytest.raises(ModelError, match="2D hypothesis"):
        pf.Model(read_mesh(tmp_path / "plate.msh"),
                 [pf.Block("all", pf.Elastic(1e9, 0.2, 1.0))], plane="stress")  # fmt: skip


def test_cells_in_two_block_groups(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """Cell 11 of two physical surfaces: gmsh writes it once per group (MSH 2.2)."""
    names = {**NAMES, 2: (2, "dam")}
    els = [*ELEMENTS[:-1], (11, 3, 2, [2, 3, 6, 5])]
    text = MODEL.replace('all = "rock"', 'all = "rock"\ndam = "rock"')
    p = model(tmp_path, names=names, elements=els, text=text)
    assert main(["check", str(p)]) == 0  # distinct groups: fine
    import pfeie as pf

    mesh = read_mesh(tmp_path / "plate.msh")
    mesh.cell_groups["dam"] = {"quad": np.array([1])}
    mesh.cell_groups["all"] = {"quad": np.array([0, 1])}
    with pytest.raises(ModelError, match=r"'all' .* and 'dam' .* share 1 quad cell\(s\): gmsh "
                       r"element 11"):  # fmt: skip
        pf.Model(mesh, [pf.Block("all", pf.Elastic(1e9, 0.2, 1.0)),
                        pf.Block("dam", pf.Elastic(1e9, 0.2, 1.0))])  # fmt: skip
    capsys.readouterr()
    # the cell written once per group (MSH 2: elements 11 and 12, tags 1 and 2) is one cell
    # in both groups, as MSH 4 gives it: two blocks on it share it
    cli_fails(capsys, ["check", str(model(tmp_path, names=names, text=text,
                                      elements=[*ELEMENTS, (12, 3, 2, [2, 3, 6, 5])]))],
              "'all'", "'dam'", "share 1 quad cell(s): gmsh element 11")  # fmt: skip
    mesh = read_mesh(tmp_path / "plate.msh")
    assert mesh.cells["quad"].shape == (2, 4)
    assert mesh.cell_groups["all"]["quad"].tolist() == [0, 1]
    assert mesh.cell_groups["dam"]["quad"].tolist() == [1]
    # with one block on 'all', 'dam' another name of its cell (a material zone): runs
    p = model(tmp_path, names=names, elements=[*ELEMENTS, (12, 3, 2, [2, 3, 6, 5])])
    assert main(["check", str(p)]) == 0
    # a cell written twice in one group is still refused as duplicated
    cli_fails(capsys, ["check", str(model(tmp_path, names=names, text=text,
                                      elements=[*ELEMENTS, (12, 3, 1, [2, 3, 6, 5])]))],
              "duplicated", "gmsh element 11 and gmsh element 12",
              "written twice in one physical group")  # fmt: skip
    # both in one file: the cell in two groups merges, the copies in one group alone are
    # named
    both = [*ELEMENTS, (12, 3, 2, [1, 2, 5, 4]), (13, 3, 1, [2, 3, 6, 5])]
    err = cli_fails(capsys, ["check", str(model(tmp_path, names=names, elements=both))],
                    "1 duplicated cell(s)", "gmsh element 11 and gmsh element 13")  # fmt: skip
    assert "gmsh element 12" not in err


def test_pressure_on_interior_facets(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """A facet group with facets inside a block is refused for a pressure; a facet given
    twice (on both of its cells) is stored once."""
    text = MODEL + '[[loads.pressure]]\ngroup = "mid"\nvalue = 1e5\n'
    text = text.replace("[analysis]", "[analysis]").replace(
        '[[loads.pressure]]', '[loads]\n[[loads.pressure]]')  # fmt: skip
    p = model(tmp_path, text=text)
    cli_fails(capsys, ["check", str(p)], "model.toml", "loads.pressure[0].group", "'mid'",
          "inside a block", "expected facets on the boundary")  # fmt: skip
    import pfeie as pf

    mesh = pf.rectangle(2.0, 1.0, 2, 1)
    grp = mesh.add_facet_group("mid", lambda x: abs(x[:, 0] - 1.0) < 1e-9, boundary_only=False)
    assert sum(c.shape[0] for c in grp.values()) == 2  # both cells' copies of one facet
    mesh = pf.Mesh(mesh.points, mesh.cells, mesh.cell_groups, mesh.facet_groups)
    assert mesh.facet_groups["mid"]["line"].shape[0] == 1


def test_unreadable_msh(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    p = model(tmp_path)
    (tmp_path / "plate.msh").write_text("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0\n")
    cli_fails(capsys, ["check", str(p)], "plate.msh", "cannot read the gmsh file", "expected")
    (tmp_path / "plate.msh").write_bytes(b"\x00\xff" * 50)
    cli_fails(capsys, ["run", str(p)], "plate.msh", "gmsh")
    (tmp_path / "plate.msh").write_text("time,acc\n0,0\n")  # meshio.read would exit
    cli_fails(capsys, ["check", str(p)], "plate.msh", "cannot read the gmsh file", "2.2 or 4.1")


# -- item: records ---------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("name", "text", "words"),
    [
        ("r.at2", "PEER\nt\nACCELERATION IN UNITS OF G\nNPTS= 3, DT= 0.01 SEC\n0.1 1e400 0.2\n",
         ["r.at2", "line 5", "'1e400'", "expected a finite number"]),
        ("r.at2", "PEER\nt\nACCELERATION IN UNITS OF G\nNPTS= 3, DT= 1e999 SEC\n0.1 0.2 0.3\n",
         ["r.at2", "line 4", "DT", "expected a number in (0, 10] s"]),
        ("r.at2", "PEER\nt\nACCELERATION IN UNITS OF G\nNPTS= 3, DT= 1e30 SEC\n0.1 0.2 0.3\n",
         ["r.at2", "line 4", "DT", "expected a number in (0, 10] s", "'1e30'"]),
        # tables read as one column would interleave their columns
        ("r.txt", "0.0,0.0,1\n0.02,0.0063,1\n",
         ["r.txt", "line 1", "3 numbers", "a table, not one column"]),
        ("r.txt", "0,00;0,50\n0,02;0,60\n", ["r.txt", "line 1", "decimal commas"]),
        ("r.at2", "PEER\nt\nACCELERATION IN UNITS OF G\nNPTS= 3, DT= .. SEC\n0.1 0.2 0.3\n",
         ["r.at2", "line 4", "DT: expected a number"]),
        ("r.csv", "t,a\n0,0\n0.01,nan\n", ["r.csv", "line 3", "'nan'"]),
        ("r.csv", "t,a\n0,0\n1e400,0.1\n", ["r.csv", "line 3", "'1e400'"]),
        ("r.txt", "0.1\n-1e309\n", ["r.txt", "line 2", "'-1e309'"]),
    ],
)  # fmt: skip
def test_non_finite_record_values(tmp_path: Path, name: str, text: str, words: list[str]) -> None:
    p = tmp_path / name
    p.write_text(text)
    with pytest.raises(RecordError) as err:
        read_record(p, units="g", dt=0.01 if name.endswith(".txt") else None)
    for w in words:
        assert w in str(err.value)


def test_record_encodings(tmp_path: Path) -> None:
    """A byte-order mark before a numeric first line keeps that line as data (it made a
    header of it); a Latin-1 AT2 title is read (it was 'not a text file'); a file with NUL
    bytes is refused."""
    p = tmp_path / "bom.csv"
    p.write_bytes("\ufeff0,0.5\n0.02,0.25\n".encode())
    gm = read_record(p, units="g")
    assert gm.time.size == 2 and gm.acceleration[0] == pytest.approx(0.5 * 9.81)
    at2 = tmp_path / "d.at2"
    at2.write_bytes("PEER\nDÜZCE 11/12/99\nACCELERATION IN UNITS OF G\nNPTS= 2, DT= 0.01 "
                    "SEC\n0.1 0.2\n".encode("latin-1"))  # fmt: skip
    assert read_record(at2).name == "DÜZCE 11/12/99"
    (tmp_path / "b.csv").write_bytes(b"0,1\n\0\0")
    with pytest.raises(RecordError, match=r"b\.csv: not a text file"):
        read_record(tmp_path / "b.csv", units="g")


def test_record_scale_overflow(tmp_path: Path) -> None:
    p = tmp_path / "r.csv"
    p.write_text("t,a\n0,0\n0.01,1e300\n")
    with pytest.raises(RecordError, match=r"r\.csv.*overflows"):
        read_record(p, units="g", scale=1e10)


# -- item: units of every dataset ------------------------------------------------------------
def test_every_dataset_has_units(tmp_path: Path) -> None:
    """A dynamic run with a joint and a probe: every dataset of results.h5 has units."""
    import h5py

    text = MODEL.replace('all = "rock"', 'all = "rock"\n[interfaces.mid]\nfriction_angle = 30.0')
    text = text.replace('folder = "out"', 'folder = "out"\nprobes = { p = [1.0, 1.0] }')
    p = model(tmp_path, extra="dt = 0.001\nduration = 0.003", text=text)
    assert main(["run", str(p), "--quiet"]) == 0
    missing: list[str] = []
    with h5py.File(tmp_path / "out" / "results.h5") as f:
        f.visititems(lambda name, obj: missing.append(name)
                     if isinstance(obj, h5py.Dataset) and "units" not in obj.attrs else None)
        n = []
        f.visititems(lambda name, obj: n.append(name) if isinstance(obj, h5py.Dataset) else None)
    assert not missing
    assert {"mesh/cells/quad", "mesh/body", "pairs/frame", "pairs/node_a", "static/state",
            "history/pairs/state"} <= set(n)  # fmt: skip


def test_msh41_entity_in_two_physical_surfaces(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """MSH 4.1: the upper surface in the groups 'dam' and 'rock' (meshio keeps the first
    group of an entity in its tags): both groups hold its cells, and two blocks on them
    are refused, naming gmsh element ids."""
    src = (Path(__file__).parent / "data" / "two_blocks_v41.msh").read_text()
    line = next(ln for ln in src.splitlines() if ln.startswith("2 -9.999999994736442e-08 0.99"))
    assert " 1e-07 1 2 4 " in line
    both = line.replace(" 1e-07 1 2 4 ", " 1e-07 2 2 1 4 ")
    (tmp_path / "plate.msh").write_text(src.replace(line, both))
    mesh = read_mesh(tmp_path / "plate.msh")
    assert mesh.cell_groups["dam"]["triangle"].size == 84
    assert mesh.cell_groups["rock"]["triangle"].size == 168
    p = tmp_path / "model.toml"
    p.write_text(MODEL.replace("EXTRA", "").replace('all = "rock"', 'rock = "rock"\ndam = "rock"'))
    cli_fails(capsys, ["check", str(p)], "model.toml", "'rock'", "'dam'", "share 84 triangle",
          "gmsh element")  # fmt: skip


@pytest.mark.parametrize("direction", ["[0.0, 0.0]", "[1e308, 1e308]"])
def test_gravity_direction(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], direction: str
) -> None:
    """A zero direction is refused (it made NaN loads); a huge one is normalised without
    overflow."""
    p = model(tmp_path, text=MODEL + f"[loads]\ngravity_direction = {direction}\n")
    if direction == "[0.0, 0.0]":
        cli_fails(capsys, ["check", str(p)], "model.toml", "loads.gravity_direction",
              "finite non-zero vector")  # fmt: skip
    else:
        assert main(["check", str(p)]) == 0


def test_nothing_to_run(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    p = model(tmp_path, extra="dynamic = false\nstatic = false")
    cli_fails(capsys, ["check", str(p)], "model.toml", "analysis.dynamic", "nothing to run")


def test_non_finite_coordinates(tmp_path: Path) -> None:
    nodes = [*NODES[:5], (2.0, 1e400, 0.0)]
    with pytest.raises(MeshError, match=r"plate\.msh: .*non-finite"):
        read_mesh(msh22(tmp_path / "plate.msh", nodes=nodes))
    import pfeie as pf

    mesh = pf.box(1.0, 1.0, 1.0, 1, 1, 1)
    mesh.points[0, 2] = np.nan
    with pytest.raises(MeshError, match="1 node"):
        mesh.check()


def test_probe_outside_scale_zero_and_massless_blocks(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], caplog: pytest.LogCaptureFixture
) -> None:
    """A probe point far from the model, and a record scaled by 0, exit 2 naming the key
    and what was expected; a probe on the model passes; a density of 0 (a massless block,
    legitimate for a foundation) is said, not silent."""
    p = model(tmp_path)
    text = p.read_text()
    p.write_text(text + "probes = { far = [50.0, 0.5] }\n")
    assert main(["check", str(p)]) == 2
    err = capsys.readouterr().err
    assert "output.probes.far: the point [50.0, 0.5] lies 48 m from the nearest node" in err
    p.write_text(text + "probes = { near = [2.05, 1.0] }\n")
    assert main(["check", str(p)]) == 0
    capsys.readouterr()
    np.savetxt(tmp_path / "rec.csv", np.c_[[0.0, 0.1], [0.0, 1.0]], delimiter=",")
    p.write_text(text + '[[ground_motion]]\nfile = "rec.csv"\nunits = "g"\nscale = 0.0\n')
    assert main(["check", str(p)]) == 2
    assert "ground_motion[0].scale: a scale of 0 removes the record" in capsys.readouterr().err
    p.write_text(text.replace("rho = 2000.0", "rho = 0.0"))
    assert main(["check", str(p)]) == 0
    assert "materials.rock.rho = 0: the blocks all are massless" in caplog.text


def test_last_paraview_frame_is_the_final_time(tmp_path: Path) -> None:
    """Fields every 4th row of a 0.1 s run at 0.01 s (rows 0, 4, 8): the final frame is
    added, at t = 0.1 s, and equals the last state (read back by meshio from the XDMF of a
    single-cell-type mesh)."""
    import meshio

    p = model(tmp_path, "duration = 0.1\ndt = 0.01")
    p.write_text(p.read_text() + "field_every = 4\n[loads]\ngravity = 9.81\n")
    assert main(["run", str(p), "--quiet"]) == 0
    with Results(tmp_path / "out" / "results.h5") as res:
        tf, fields = res.fields()
        np.testing.assert_allclose(tf, [0.0, 0.04, 0.08, 0.1], atol=1e-12)
        assert np.abs(fields["u"][-1]).max() > 0
    with meshio.xdmf.TimeSeriesReader(str(tmp_path / "out" / "blocks.xdmf")) as r:
        r.read_points_cells()
        t, pd, _ = r.read_data(r.num_steps - 1)
        assert t == pytest.approx(0.1)
        np.testing.assert_allclose(pd["displacement"][:, :2], fields["u"][-1], rtol=1e-15)


def test_results_format_version(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The results file says its format (1.9); a file of another major version is refused
    with a message naming both versions (exit 2 from ``pfeie report``)."""
    import h5py

    p = model(tmp_path, "duration = 0.02\ndt = 0.01")
    assert main(["run", str(p), "--quiet"]) == 0
    path = tmp_path / "out" / "results.h5"
    with Results(path) as res:
        assert res.f.attrs["format_version"] == "1.11"
    with h5py.File(path, "r+") as f:
        f.attrs["format_version"] = "2.0"
    with pytest.raises(ResultsError, match=r"format 2.0, but this pfeie .* reads format 1.x"):
        Results(path)
    capsys.readouterr()
    assert main(["report", str(path)]) == 2
    assert "results format 2.0" in capsys.readouterr().err


def test_3d_block_on_roller_sides_slides(caplog: pytest.LogCaptureFixture) -> None:
    """A 3D block held on two sides by rollers (u_x = 0) slides along y on its joint under
    a base acceleration of 8 sin(4πt) m/s² (μ = tan 30°): it runs (the old contact
    projection met a singular system here), the rollers hold (u_x at round-off, 1e-15 m;
    measured 8e-17 m), and the slip follows the exact rigid block within 1 % of its peak
    (measured 0.25 %: the elastic block's heel lifts)."""
    import pfeie as pf
    from pfeie.verification._rigid import RigidBlock

    mesh = pf.box(1.0, 1.0, 1.5, 2, 2, 3)
    mesh.add_cell_group("base", lambda x: x[:, 2] < 0.5)
    mesh.add_cell_group("block", lambda x: x[:, 2] > 0.5)
    mesh.add_facet_group("joint", lambda x: abs(x[:, 2] - 0.5) < 1e-9, False)
    mat = pf.Elastic(30e9, 0.2, 2400)
    m = pf.Model(mesh, [pf.Block("base", mat), pf.Block("block", mat)],
                 interfaces=[pf.Interface("joint", pf.Joint(phi=30.0))])  # fmt: skip
    m.fix("base")
    m.fix(m.nodes_at(lambda x: (x[:, 2] > 0.5) & ((x[:, 0] < 1e-9) | (x[:, 0] > 1 - 1e-9))), 0)
    m.add_gravity()
    t = np.arange(0, 0.5 + 1e-12, 0.002)
    a = 8.0 * np.sin(4 * np.pi * t)
    gm = pf.GroundMotion.from_samples(a, time=t, direction=[0.0, 1.0, 0.0])
    res = pf.Dynamic(m, 0.002).run(0.5, ground=[gm], start=pf.solve_static(m))
    assert res.completed
    ref = RigidBlock(t, a, np.tan(np.radians(30.0)) * 9.81, t_end=0.5).displacement(res.t)
    y = res.rigid[:, 1, 1] - res.rigid[0, 1, 1]
    assert np.abs(ref).max() > 0.02
    assert np.abs(y - ref).max() < 1e-2 * np.abs(ref).max()
    assert np.abs(res.rigid[:, 1, 0]).max() < 1e-15
    # with large rotations: every block has a support, so no frame turns (a warning says
    # so; it crashed on the empty set of rotating bodies) and the run is the small-rotation
    # one to round-off (measured 0 m)
    with caplog.at_level(logging.WARNING, logger="pfeie"):
        big = pf.Dynamic(m, 0.002, large_rotation=True).run(0.1, ground=[gm],
                                                            start=pf.solve_static(m))
    assert "no block's frame rotates" in caplog.text
    n = big.t.size
    assert np.abs(big.rigid[:, 1] - res.rigid[:n, 1]).max() < 1e-12 * np.abs(ref).max()


def test_mechanism_names_the_free_modes(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """A block whose supports leave rigid modes free (rollers along x only on its bottom, or
    a 3D box on rollers): the static analysis says which body and which modes, through the
    API and the command line (exit 1, the analysis failed)."""
    import pfeie as pf

    box = pf.box(1.0, 1.0, 1.0, 1, 1, 1)
    m = pf.Model(box, [pf.Block("all", pf.Elastic(1e9, 0.2, 2000.0))])
    m.fix(m.nodes_at(lambda x: x[:, 2] < 1e-9), 2)  # rollers: z only
    m.add_gravity()
    with pytest.raises(pf.errors.MechanismError, match=r"body 'all' can move freely \(") as exc:
        pf.solve_static(m)
    for mode in ("translation x", "translation y", "rotation about z"):
        assert mode in str(exc.value)
    assert "rotation about x" not in str(exc.value)  # the rollers hold the rocking
    p = model(tmp_path)
    p.write_text(p.read_text().replace('group = "bottom"', 'group = "bottom"\ncomponents = ["x"]'))
    assert main(["run", str(p), "--quiet"]) == 1
    err = capsys.readouterr().err
    assert "body 'all' can move freely (" in err and "translation y" in err, err


def test_record_scaled_to_a_target_pga(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                      caplog: pytest.LogCaptureFixture) -> None:  # fmt: skip
    """``pga = 0.3`` scales a record to a peak of 0.3 g (to round-off); ``scale = -1``
    beside it flips the record first (its polarity, named in the record's line); with
    another ``scale`` too, or on a record of zeros, exit 2 naming the record. A static-only
    model (analysis.dynamic = false) does not use its records: the record of zeros is
    warned there, as not used, and the check passes."""
    from pfeie.io import load_job

    p = model(tmp_path)
    text = p.read_text()
    np.savetxt(tmp_path / "rec.csv", np.c_[[0.0, 0.1, 0.2], [0.0, -0.12, 0.05]], delimiter=",")
    p.write_text(text + '[[ground_motion]]\nfile = "rec.csv"\nunits = "g"\npga = 0.3\n')
    rec = load_job(p).records[0]
    assert rec.pga == pytest.approx(0.3 * 9.81, rel=1e-14)
    assert rec.acceleration[1] < 0  # the sign is kept
    p.write_text(text + '[[ground_motion]]\nfile = "rec.csv"\nunits = "g"\npga = 0.3\n'
                 "scale = -1\n")  # fmt: skip
    flipped = load_job(p).records[0]
    np.testing.assert_array_equal(flipped.acceleration, -rec.acceleration)
    assert "flipped (scale -1), scaled ×2.5 to a PGA of 0.3 g" in flipped.summary()
    p.write_text(text + '[[ground_motion]]\nfile = "rec.csv"\nunits = "g"\npga = 0.3\n'
                 "scale = 2.0\n")  # fmt: skip
    assert main(["check", str(p)]) == 2
    assert "ground_motion[0]: give either scale or pga, not both" in capsys.readouterr().err
    np.savetxt(tmp_path / "rec.csv", np.c_[[0.0, 0.1], [0.0, 0.0]], delimiter=",")
    zeros = '[[ground_motion]]\nfile = "rec.csv"\nunits = "g"\npga = 0.3\n'
    p.write_text(text.replace("dynamic = false", "duration = 0.1") + zeros)
    assert main(["check", str(p)]) == 2
    assert "the record is all zeros" in capsys.readouterr().err
    p.write_text(text + zeros)
    with caplog.at_level("WARNING"):
        assert main(["check", str(p)]) == 0
    assert "the record is all zeros" in caplog.text
    assert "(not used: analysis.dynamic = false)" in caplog.text
    caplog.clear()  # a record file missing: the static-only run goes on (a new user's case)
    p.write_text(text + zeros.replace("rec.csv", "gone.csv"))
    with caplog.at_level("WARNING"):
        assert main(["run", str(p), "--quiet"]) == 0
    assert "gone.csv: record file not found (not used: analysis.dynamic = false)" in caplog.text


def test_output_file_with_a_nul_character(tmp_path: Path,
                                          capsys: pytest.CaptureFixture[str]) -> None:  # fmt: skip
    """`pfeie report RESULTS --out 'a\\x00b'` (found by the long CLI fuzzing): exit 2 with
    an error naming the path, not a ValueError."""
    text = MODEL.replace('all = "rock"', 'all = "rock"\n[interfaces.mid]\nfriction_angle = 30.0')
    msh22(tmp_path / "plate.msh")
    p = tmp_path / "model.toml"
    p.write_text(text.replace("EXTRA", "dynamic = false"))
    assert main(["run", str(p), "--quiet"]) == 0
    capsys.readouterr()
    cli_fails(capsys, ["report", str(tmp_path / "out" / "results.h5"), "--out", "a\x00b"],
          "NUL character")  # fmt: skip


def _two_blocks() -> pf.Model:
    """A 1 m × 1 m plate (Q4, 1 × 2 cells) cut at y = 0.5 m into the blocks 'base' and
    'block' (E = 1 GPa, ρ = 2000 kg/m³) on the joint 'joint' (φ = 30°): no support, no
    load."""
    mesh = pf.rectangle(1.0, 1.0, 1, 2)
    mesh.add_cell_group("base", lambda x: x[:, 1] < 0.5)
    mesh.add_cell_group("block", lambda x: x[:, 1] > 0.5)
    mesh.add_facet_group("joint", lambda x: abs(x[:, 1] - 0.5) < 1e-9, boundary_only=False)
    mat = pf.Elastic(1e9, 0.2, 2000.0)
    return pf.Model(mesh, [pf.Block("base", mat), pf.Block("block", mat)],
                    interfaces=[pf.Interface("joint", pf.Joint(phi=30.0))])  # fmt: skip


def test_python_api_mistakes_get_typed_errors() -> None:
    """Wrong types through the Python API end in a ModelError naming the argument (they
    ended in TypeError or AttributeError deep inside); one record may be given alone; the
    plain Newmark integrator refuses a model with interface pairs (it left the block in
    free fall); a 3D model refuses a thickness."""
    import pfeie as pf
    from pfeie.dynamics import Newmark

    with pytest.raises(ModelError, match=r"Elastic: E: expected a number \(Pa\), got str '30e9'"):
        pf.Elastic(E="30e9", nu=0.2, rho=2400)  # type: ignore[arg-type]
    with pytest.raises(ModelError, match=r"block 'b': material: expected a pfeie.Elastic"):
        pf.Block("b", 3.0)  # type: ignore[arg-type]
    m = _two_blocks()
    mat = pf.Elastic(1e9, 0.2, 2000.0)
    with pytest.raises(ModelError, match=r"fix base: components: expected integers in 0..1"):
        m.fix("base", components=["w"])  # type: ignore[list-item]
    m.fix("base")
    m.add_gravity()
    with pytest.raises(ModelError, match=r"Newmark: the model has 2 interface pairs"):
        Newmark(m.system(), 1e-3)
    pulse = pf.GroundMotion.from_function(lambda t: 0.1 * t, duration=0.01, dt=0.001)
    an = pf.Dynamic(m, 1e-3)
    one = an.run(0.01, ground=pulse)  # type: ignore[arg-type]
    assert np.array_equal(one.rigid, an.run(0.01, ground=[pulse]).rigid)
    with pytest.raises(ModelError, match=r"ground\[0\]: expected a pfeie.GroundMotion"):
        an.run(0.01, ground=["rec.csv"])  # type: ignore[list-item]
    blip = pf.GroundMotion.from_samples([0.1, 0.2], time=[0.0, 5e-4], name="blip")
    with pytest.raises(ModelError, match=r"ground motion 'blip': the record lasts 0.0005 s, "
                       r"less than one step \(analysis.dt = 0.001 s\)"):  # fmt: skip
        an.run(0.01, ground=[blip])
    with pytest.raises(ModelError, match=r"thickness = 2.0 m is a 2D setting"):
        pf.Model(pf.box(1.0, 1.0, 1.0, 1, 1, 1), [pf.Block("all", mat)], thickness=2.0)


def test_plausibility_warnings(
    tmp_path: Path, caplog: pytest.LogCaptureFixture, capsys: pytest.CaptureFixture[str]
) -> None:
    """Valid input that is probably not what was meant gets a warning naming the key: a
    surface group (2D) in no block (its cells left out), a modulus written in GPa without its
    exponent, a mesh drawn in millimetres, a water level above the whole model; the
    summary of ``check`` gives the model's extent and mass (a 2 m × 1 m plate of
    2000 kg/m³, 1 m thick: 4000 kg)."""
    names = {1: (2, "left"), 2: (2, "right"), 3: (1, "bottom"), 4: (1, "mid"), 5: (1, "top")}
    elements = [*ELEMENTS[:-2], (10, 3, 1, [1, 2, 5, 4]), (11, 3, 2, [2, 3, 6, 5])]
    text = MODEL.replace('all = "rock"', 'left = "rock"\nright = "rock"')
    p = model(tmp_path, text=text, elements=elements, names=names)
    assert main(["check", str(p)]) == 0
    assert "extent       2 x 1 m; mass 4000 kg" in capsys.readouterr().out
    cases = [
        (text.replace('right = "rock"\n', ""), {},
         "the mesh's surface group(s) 'right' (1 cells) are in no block"),
        (text.replace("E = 1e9", "E = 25"), {},
         "materials.rock.E = 25 Pa lies below 1e+06 Pa (concrete and rock: 1e9 to 1e11 Pa); "
         "pfeie takes SI units: did you mean 2.5e+10 (GPa)"),
        (text.replace("E = 1e9", "E = 3e14"), {}, "materials.rock.E = 3e+14 Pa lies above"),
        (text, {"nodes": [(2e4 * x, 2e4 * y, 0) for x, y, _ in NODES]},
         "the mesh spans 4e+04 m; pfeie takes coordinates in metres"),
        (text.replace("[analysis]", '[[loads.hydrostatic]]\ngroups = ["top"]\nwater_level = '
                      "3.0\n[analysis]"), {},
         "loads.hydrostatic[0].water_level = 3 m lies 2 m above the top of the model (1 m)"),
        (text, {}, "the mesh's facet group 'mid' lies between the blocks 'left' and 'right' "
         "but is not in [interfaces]: the blocks share its nodes and move as one body there "
         "(add [interfaces.mid] to model it as a joint)"),
        (text.replace("rho = 2000.0", "rho = 2.6"), {},
         "materials.rock.rho = 2.6 kg/m³ lies below 500 kg/m³ (concrete and rock: 1800 to "
         "3200); pfeie takes SI units: did you mean 2600 kg/m³ (t/m³ × 1000)?"),
        (text.replace("[[supports]]", "[interfaces.mid]\nfriction_angle = 30.0\n"
                      '[[loads.uplift]]\ninterface = "mid"\nheadwater = 0.0\ntailwater = 0.0\n'
                      '[[supports]]'), {},
         "loads.uplift[0]: the uplift in 'mid' is zero at every pair: the joint (y from 0 to "
         "1 m) lies above the headwater (0 m) and tailwater (0 m) levels"),
        # no tailwater (None): the warning still formats (it raised a logging error)
        (text.replace("[[supports]]", "[interfaces.mid]\nfriction_angle = 30.0\n"
                      '[[loads.uplift]]\ninterface = "mid"\nheadwater = -5.0\n'
                      '[[supports]]'), {},
         "loads.uplift[0]: the uplift in 'mid' is zero at every pair: the joint (y from 0 to "
         "1 m) lies above the headwater (-5 m) and tailwater (none) levels"),
        (text.replace('[[supports]]\ngroup = "bottom"\n', ""), {},
         "no [[supports]]: nothing holds the model, every block floats"),
        (text.replace("[[supports]]", "[interfaces.mid]\nfriction_angle = 30.0\n"
                      "residual_friction_angle = 40.0\n[[supports]]"), {},
         "interfaces.mid.residual_friction_angle = 40° exceeds its friction_angle = 30°"),
        (text.replace("[[supports]]", "[interfaces.mid]\nfriction_angle = 0.6\n[[supports]]"),
         {}, "interfaces.mid.friction_angle = 0.6° is very low (joints in concrete and rock: "
         "20° to 60°); the angle is in degrees: a friction coefficient μ = 0.6 is φ = 31.0°"),
    ]  # fmt: skip
    for text_k, mesh_k, warning in cases:
        caplog.clear()
        p = model(tmp_path, text=text_k, elements=elements, names=names, **mesh_k)
        # (without supports the static state is a mechanism: check exits 1)
        unheld = "[[supports]]" not in text_k
        with caplog.at_level("WARNING"):
            assert main(["check", str(p)]) == (1 if unheld else 0)
        assert warning in caplog.text
        # a declared joint, or one block only: no warning
        between = 'right = "rock"' in text_k and "[interfaces.mid]" not in text_k
        assert ("'mid' lies between" in caplog.text) == between
        capsys.readouterr()
    # a joint between a block and a group forgotten under [blocks]: the error says which
    p = model(tmp_path, text=text.replace('right = "rock"\n', "").replace(
        "[[supports]]", "[interfaces.mid]\nfriction_angle = 30.0\n[[supports]]"),
        elements=elements, names=names)  # fmt: skip
    assert main(["check", str(p)]) == 2
    err = capsys.readouterr().err
    assert ("interface 'mid' has facets on the mesh boundary" in err
            and "the mesh's group(s) 'right' are in no block, so a joint between them and a "
            "block lies on the model's boundary: list them under [blocks]" in err), err
    caplog.clear()  # a group the model file uses (here as a support) is no joint left out
    p = model(tmp_path, text=text.replace('group = "bottom"', 'group = "mid"'),
              elements=elements, names=names)  # fmt: skip
    with caplog.at_level("WARNING"):
        assert main(["check", str(p)]) == 0
    assert "lies between" not in caplog.text
    caplog.clear()
    two = (text.replace('right = "rock"', 'right = "soft"')
           + "[materials.soft]\nE = 1e9\nnu = 0.25\nrho = 20.0\n")
    p = model(tmp_path, text=two, elements=elements, names=names)
    with caplog.at_level("WARNING"):
        assert main(["check", str(p)]) == 0
    assert "rho" not in caplog.text  # a practically massless block beside a normal one
    caplog.clear()  # but a density that reads as t/m³ is warned beside a normal one too
    p = model(tmp_path, text=two.replace("rho = 20.0", "rho = 2.4"), elements=elements,
              names=names)  # fmt: skip
    with caplog.at_level("WARNING"):
        assert main(["check", str(p)]) == 0
    assert ("materials.soft.rho = 2.4 kg/m³ lies below 500 kg/m³ (concrete and rock: 1800 "
            "to 3200); pfeie takes SI units: did you mean 2400 kg/m³") in caplog.text


def test_new_user_mistakes_of_the_fourteenth_session(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Mistakes a new user met that ran silently or ended in a traceback: ``component``
    beside ``direction`` (direction won silently); a face group listed twice under
    ``groups`` (its water load counted twice: FS 1.27 instead of 6.70) in the model file
    and in Python; ``GroundMotion.from_function`` with dt = 0 (ZeroDivisionError). Each is
    now refused with a message naming the key."""
    p = model(tmp_path)
    text = p.read_text()
    np.savetxt(tmp_path / "rec.csv", np.c_[[0.0, 0.1, 0.2], [0.0, -0.12, 0.05]], delimiter=",")
    p.write_text(text + '[[ground_motion]]\nfile = "rec.csv"\nunits = "g"\ncomponent = "y"\n'
                 "direction = [1.0, 0.0]\n")  # fmt: skip
    assert main(["check", str(p)]) == 2
    assert "ground_motion[0]: give either component or direction, not both" in (
        capsys.readouterr().err)  # fmt: skip
    p.write_text(text.replace("[analysis]", '[[loads.hydrostatic]]\ngroups = ["top", "top"]\n'
                              "water_level = 0.5\n[analysis]"))  # fmt: skip
    assert main(["check", str(p)]) == 2
    assert ("loads.hydrostatic[0].groups: 'top' listed twice: a group's load would count "
            "twice; expected each group once") in capsys.readouterr().err  # fmt: skip
    mesh = pf.rectangle(1.0, 10.0, 1, 4)
    m = pf.Model(mesh, [pf.Block("all", pf.Elastic(30e9, 0.2, 2400.0))])
    with pytest.raises(pf.errors.ModelError, match="westergaard: 'xmin' given twice"):
        m.add_westergaard(["xmin", "xmin"], water_level=10.0)
    with pytest.raises(pf.errors.ModelError, match=r"dt must be > 0 s, got 0\.0"):
        pf.GroundMotion.from_function(lambda t: 1.0, duration=1.0, dt=0.0)


def test_a_closed_output_pipe_ends_without_a_traceback(tmp_path: Path) -> None:
    """``pfeie check model.toml | true`` (the reader closes the pipe before pfeie writes):
    exit 141 (128 + SIGPIPE, as a shell reports it) and nothing on standard error; it was
    a BrokenPipeError's traceback and exit 1, which means a failed analysis."""
    import subprocess
    import sys

    p = model(tmp_path)
    proc = subprocess.Popen([sys.executable, "-m", "pfeie", "check", str(p)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)  # fmt: skip
    assert proc.stdout is not None and proc.stderr is not None
    proc.stdout.close()
    err = proc.stderr.read().decode()
    assert proc.wait(timeout=120) == 141
    assert "Traceback" not in err and "Error" not in err


def test_a_model_without_supports_says_so_in_statics() -> None:
    """Two blocks on a joint and no support: the static analysis fails naming the blocks
    that nothing holds and what to add (it blamed the joints' strength); with the base
    supported the joint carries the block's weight (ρ g A, to 2e-15; measured 2.2e-16)."""
    from pfeie.errors import MechanismError

    def two_blocks(fixed: bool) -> pf.Model:
        m = _two_blocks()
        if fixed:
            m.fix("ymin")
        m.add_gravity()
        return m

    with pytest.raises(MechanismError, match=r"No support holds the block\(s\) 'base', "
                       r"'block': .* Add \[\[supports\]\] \(Model.fix\)"):  # fmt: skip
        pf.solve_static(two_blocks(False))
    st = pf.solve_static(two_blocks(True))  # held: the joint carries the block's weight
    assert st.pairs is not None
    weight = 2000.0 * 9.81 * 0.5  # (N per metre of thickness)
    assert st.pairs.X[:, -1].sum() == pytest.approx(weight, rel=2e-15)


def test_check_names_the_floating_and_the_unsupported_blocks(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """``pfeie check`` on two blocks cut by the joint 'mid': with the left block on a
    support, the right one floats, held by the joint only; without the support, both are
    named as held by nothing."""
    names = {1: (2, "left"), 2: (2, "right"), 3: (1, "bottom"), 4: (1, "mid"), 5: (1, "top")}
    elements = [(1, 1, 3, [1, 2]), (3, 1, 4, [2, 5]), (4, 1, 5, [4, 5]),
                (10, 3, 1, [1, 2, 5, 4]), (11, 3, 2, [2, 3, 6, 5])]  # fmt: skip
    text = (MODEL.replace('all = "rock"', 'left = "rock"\nright = "rock"')
            .replace("[[supports]]", "[interfaces.mid]\nfriction_angle = 30.0\n[[supports]]"))
    p = model(tmp_path, text=text, elements=elements, names=names)
    capsys.readouterr()
    assert main(["check", str(p)]) == 0
    out = capsys.readouterr().out
    assert "bodies       2; floating (held by their joints only): right\n" in out
    assert "unsupported" not in out
    p = model(tmp_path, text=text.replace('[[supports]]\ngroup = "bottom"\n', ""),
              elements=elements, names=names)  # fmt: skip
    # the static state would stop as a mechanism (pfeie run: exit 1): check says so
    assert main(["check", str(p)]) == 1
    cap = capsys.readouterr()
    out = cap.out
    assert "bodies       2\n" in out
    assert ("unsupported  left, right: no support, and no joint to a supported block (add "
            "[[supports]])") in out
    assert "the static state cannot be solved: left, right has no support" in cap.err


def test_analyses_that_the_model_cannot_make_are_refused_before_work(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Two blocks cut by the joint 'mid' without a support, run dynamically alone
    (analysis.static = false): nothing holds them, and the run would let them fall freely
    (a new user's block meshed apart from its base fell 1.23 m in 0.5 s, ½ g t², exit 0):
    ``pfeie check`` and ``pfeie run`` refuse it, naming the blocks and what to add. A
    strength reduction or a yield coefficient on a model without joints is refused by
    ``pfeie check`` too (it was found by the run only), naming a block that nothing holds
    where there is one. ``pfeie modal`` of the free blocks still runs (free-free modes)."""
    names = {1: (2, "left"), 2: (2, "right"), 3: (1, "bottom"), 4: (1, "mid"), 5: (1, "top")}
    elements = [(1, 1, 3, [1, 2]), (3, 1, 4, [2, 5]), (4, 1, 5, [4, 5]),
                (10, 3, 1, [1, 2, 5, 4]), (11, 3, 2, [2, 3, 6, 5])]  # fmt: skip
    text = (MODEL.replace('all = "rock"', 'left = "rock"\nright = "rock"')
            .replace("[[supports]]", "[interfaces.mid]\nfriction_angle = 30.0\n[[supports]]")
            .replace('[[supports]]\ngroup = "bottom"\n', "")
            .replace("EXTRA", "static = false\nduration = 0.01\ndt = 0.001"))  # fmt: skip
    p = model(tmp_path, text=text, elements=elements, names=names)
    capsys.readouterr()
    for cmd in ("check", "run"):
        cli_fails(capsys, [cmd, str(p)], "analysis.static: false, and the block(s) 'left', "
                  "'right' have no support and no joint to a supported block: the dynamic "
                  "analysis would let them fall freely", "expected [[supports]]")  # fmt: skip
    assert main(["modal", str(p), "-n", "2", "--out", str(tmp_path / "m")]) == 0
    # no joint: the limit searches refused by check, the unheld block named
    plain = model(tmp_path, text=MODEL.replace('[[supports]]\ngroup = "bottom"\n', ""),
                  extra="dynamic = false\nstrength_reduction = true")  # fmt: skip
    cli_fails(capsys, ["check", str(plain)], "analysis.strength_reduction: the model has no "
              "interfaces (no joint to slide; the block(s) 'all' have no support and no joint "
              "to a supported block); expected [interfaces], or analysis.strength_reduction = "
              "false")  # fmt: skip
    held = model(tmp_path, extra="dynamic = false\nyield_coefficient = true")
    cli_fails(capsys, ["check", str(held)], "analysis.yield_coefficient: the model has no "
              "interfaces (no joint to slide); expected [interfaces], or "
              "analysis.yield_coefficient = false")  # fmt: skip


def test_a_failed_run_leaves_no_former_summary(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A static run, then a run of a model whose static analysis fails, into the same
    folder: the former run's summaries go with its results (they stood beside the new
    results as if they were theirs), and the report says that the run stopped and why
    (it said "static state only" and "No static state (analysis.static = false)")."""
    names = {1: (2, "left"), 2: (2, "right"), 3: (1, "bottom"), 4: (1, "mid"), 5: (1, "top")}
    elements = [(1, 1, 3, [1, 2]), (2, 1, 3, [2, 3]), (3, 1, 4, [2, 5]), (4, 1, 5, [4, 5]),
                (10, 3, 1, [1, 2, 5, 4]), (11, 3, 2, [2, 3, 6, 5])]  # fmt: skip
    text = (MODEL.replace('all = "rock"', 'left = "rock"\nright = "rock"')
            .replace("[[supports]]", "[interfaces.mid]\nfriction_angle = 30.0\n[loads]\n"
                     "gravity = 9.81\n[[supports]]"))  # fmt: skip
    p = model(tmp_path, text=text, elements=elements, names=names)
    assert main(["run", str(p), "--quiet"]) == 0
    out = p.parent / "out"
    assert (out / "summary.json").exists() and (out / "summary.txt").exists()
    assert main(["report", str(out / "results.h5")]) == 0
    p = model(tmp_path, text=text.replace('[[supports]]\ngroup = "bottom"\n', ""),
              elements=elements, names=names)  # fmt: skip
    capsys.readouterr()
    assert main(["run", str(p), "--quiet"]) == 1
    assert "No support holds the block(s) 'left', 'right'" in capsys.readouterr().err
    assert not (out / "summary.json").exists() and not (out / "summary.txt").exists()
    assert not (out / "report.html").exists()
    assert main(["report", str(out / "results.h5")]) == 0
    page = (out / "report.html").read_text()
    assert "<b>stopped</b>: static analysis failed" in page
    assert "No static state: the run stopped before it was written" in page
    assert "static state only" not in page


def test_a_massless_floating_block_is_named() -> None:
    """A block on a joint with no support and ρ = 0 (a massless foundation put on the wrong
    side): the dynamic analysis is refused naming it (it failed in the factorisation with
    "the matrix is not positive definite ... check supports"); with a density it runs."""
    mesh = pf.rectangle(1.0, 1.0, 1, 2)
    mesh.add_cell_group("base", lambda x: x[:, 1] < 0.5)
    mesh.add_cell_group("block", lambda x: x[:, 1] > 0.5)
    mesh.add_facet_group("joint", lambda x: abs(x[:, 1] - 0.5) < 1e-9, boundary_only=False)

    def build(rho: float) -> pf.Model:
        m = pf.Model(mesh, [pf.Block("base", pf.Elastic(1e9, 0.2, 2000.0)),
                            pf.Block("block", pf.Elastic(1e9, 0.2, rho))],
                     interfaces=[pf.Interface("joint", pf.Joint(phi=30.0))])  # fmt: skip
        m.fix("ymin")
        return m

    m = build(0.0)
    assert [m.body_names()[b] for b in m.massless_floating_bodies()] == ["block"]
    with pytest.raises(ModelError, match=r"Dynamic: the block\(s\) 'block' float \(no "
                       r"support\) and have no mass \(rho = 0\)"):  # fmt: skip
        pf.Dynamic(m, 0.01)
    assert not build(2000.0).massless_floating_bodies().size
    pf.Dynamic(build(2000.0), 0.01)


def test_a_support_in_one_component_is_diagnosed() -> None:
    """Two blocks on a joint, the base held along x only on its bottom line: the static
    analysis names the blocks and the rigid motions the supports leave free (vertical
    translation; the rotation about the line with its x translation) instead of blaming
    the joint's strength; held in both components there is no such group."""
    from pfeie.errors import MechanismError

    m = _two_blocks()
    m.fix("ymin", components=[0])
    m.add_gravity()
    groups = m.partly_supported_groups()
    assert groups == [(["base", "block"], ["translation x + rotation about z",
                                           "translation y"])]  # fmt: skip
    words = r"the rigid motion of the block\(s\) 'base', 'block' \(.*translation y\): no joint"
    with pytest.raises(MechanismError, match=r"The supports leave free " + words):
        pf.solve_static(m)
    held = _two_blocks()
    held.fix("ymin")
    assert held.partly_supported_groups() == []
