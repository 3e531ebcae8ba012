"""Wrong inputs of a new user's test (round 16), each refused or warned with a message that
names the file (key, group, line) and what was expected: corrupt meshes, a mesh given as
the model file, records in the wrong units or with decimal commas, joint strengths beyond
the Mohr-Coulomb apex, undeclared cracks, unwritable report paths, ``--set`` errors, mesh
generator arguments, numpy scalars in messages, water levels that disagree."""

from __future__ import annotations

import logging
from pathlib import Path

import pytest

from pfeie.cli import main
from pfeie.errors import MeshError
from pfeie.io import read_mesh

DATA = Path(__file__).parent / "data"


def fails(capsys: pytest.CaptureFixture[str], argv: list[str], *words: str) -> str:
    """Exit 2, a ``pfeie: error`` line holding every word, no traceback."""
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert "pfeie: error" in err and "Traceback" not in err, err
    for w in words:
        assert w in err, (w, err)
    return err


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


# -- 2. a mesh given where a model file is expected -----------------------------------------
@pytest.mark.parametrize("command", ["check", "run"])
def test_a_mesh_given_as_the_model_file_is_named_a_mesh(
    capsys: pytest.CaptureFixture[str], command: str
) -> None:
    p = DATA / "two_blocks_v22.msh"
    err = fails(capsys, [command, str(p)])
    assert err.strip() == (f"pfeie: error: {p}: expected a model file (.toml); this looks like a "
                           "gmsh mesh, which a model file names under [mesh] file")  # fmt: skip


def test_a_mesh_given_as_the_study_file_is_named_a_mesh(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    p = tmp_path / "dam.txt"  # by its content, whatever its name
    p.write_text((DATA / "two_blocks_v41.msh").read_text())
    fails(capsys, ["study", str(p)], f"{p}: expected a study file (.toml); this looks like a "
          "gmsh mesh")  # fmt: skip
