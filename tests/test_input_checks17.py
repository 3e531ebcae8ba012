"""Wrong inputs of a new user's test (round 17), each refused or warned with a message that
names the file, the key or group, and what was expected: a physical group that is named
in the mesh file but holds no elements (or elements of a lower dimension), a block drawn
in millimetres, a time step too coarse to apply an earthquake record."""

from __future__ import annotations

import logging
from pathlib import Path

import pytest

from conftest import cli_fails
from pfeie.cli import main
from pfeie.errors import MeshError
from pfeie.io import load_job, read_mesh


def _quads(scale: float = 1.0) -> str:
    """MSH 2.2: two quads, "rock" (y in [0, 1]) and "dam" (y in [1, 2]) sharing their
    nodes, "bottom" at y = 0; the group "crest" (dimension 0, a point) and the surface
    group "gallery" (no element) are named but hold no cell or facet."""
    nodes = [(0, 0), (1, 0), (1, 1), (0, 1), (1, 2), (0, 2)]
    lines = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", "5",
             '2 1 "rock"', '2 2 "dam"', '1 3 "bottom"', '0 4 "crest"', '2 5 "gallery"',
             "$EndPhysicalNames", "$Nodes", "6"]  # fmt: skip
    lines += [f"{i} {scale * x} {scale * y} 0" for i, (x, y) in enumerate(nodes, start=1)]
    lines += ["$EndNodes", "$Elements", "4", "1 15 2 4 4 6", "2 1 2 3 3 1 2",
              "3 3 2 1 1 1 2 3 4", "4 3 2 2 2 4 3 5 6", "$EndElements"]  # fmt: skip
    return "\n".join(lines) + "\n"


MODEL = """
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


def _model(tmp: Path, text: str = MODEL, scale: float = 1.0) -> Path:
    (tmp / "quads.msh").write_text(_quads(scale))
    p = tmp / "model.toml"
    p.write_text(text)
    return p


# -- 1. a group named in the file that holds no elements ------------------------------------
def test_the_reader_keeps_the_names_of_empty_groups(tmp_path: Path) -> None:
    p = tmp_path / "quads.msh"
    p.write_text(_quads())
    mesh = read_mesh(p)
    assert mesh.empty_groups == {"crest": 0, "gallery": 2}
    assert set(mesh.cell_groups) == {"rock", "dam"} and set(mesh.facet_groups) == {"bottom"}
    with pytest.raises(MeshError, match="no cell group 'gallery' \\('gallery' is a physical "
                       "group of dimension 2 in the mesh file, but it holds no elements"):
        mesh.cell_group("gallery")  # fmt: skip


def test_an_empty_block_group_is_named_empty_not_missing(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    p = _model(tmp_path, MODEL.replace('dam = "concrete"', 'gallery = "concrete"'))
    cli_fails(capsys, ["check", str(p)], "blocks.gallery: no physical group 'gallery' of the "
          "right dimension in the mesh ('gallery' is a physical group of dimension 2 in the "
          "mesh file, but it holds no elements: add its entities to it before meshing, or "
          "mesh them)")  # fmt: skip


def test_a_point_group_used_as_a_support_names_its_dimension(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    p = _model(tmp_path, MODEL.replace('group = "bottom"', 'group = "crest"'))
    cli_fails(capsys, ["check", str(p)], "supports[0].group: no physical group 'crest'",
          "('crest' is a physical group of dimension 0 in the mesh file; blocks are of "
          "dimension 2, faces and joints of 1)")  # fmt: skip


# -- 2. a block drawn in millimetres ---------------------------------------------------------
@pytest.mark.parametrize(("scale", "warned"), [(1.0, False), (500.0, False), (1500.0, True)])
def test_a_block_metres_tall_drawn_in_millimetres_is_warned(
    tmp_path: Path, caplog: pytest.LogCaptureFixture, scale: float, warned: bool
) -> None:
    """The two quads are 2 × scale tall: 3 m drawn in mm reads 3,000 m, above the 2 km
    that no dam or rock slope with its foundation reaches; 1,000 m is still warned not."""
    p = _model(tmp_path, scale=scale)
    with caplog.at_level(logging.WARNING):
        load_job(p)
    text = (f"the mesh is {2 * scale:g} m tall (along y); pfeie takes coordinates in "
            "metres (a mesh drawn in millimetres must be scaled by 1e-3")  # fmt: skip
    assert (text in caplog.text) is warned, caplog.text


# -- 3. a time step that cannot apply an earthquake ------------------------------------------
@pytest.mark.parametrize(("dt", "refused"), [("0.5", False), ("0.6", True), ("5", True)])
def test_a_step_that_applies_nothing_above_1_hz_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], dt: str, refused: bool
) -> None:
    (tmp_path / "rec.csv").write_text("".join(f"{0.01 * k:.2f},{0.1 * (k % 3 - 1):.4f}\n"
                                              for k in range(3000)))  # fmt: skip
    p = _model(tmp_path, MODEL.replace("dynamic = false", "dt = 0.01").replace(
        "[analysis]", '[[ground_motion]]\nfile = "rec.csv"\nunits = "g"\n[analysis]'))  # fmt: skip
    if not refused:
        assert main(["check", str(p), "--dt", dt]) == 0
        return
    cli_fails(capsys, ["check", str(p), "--dt", dt], f"analysis.dt (from --dt {dt}): steps of "
          f"{dt} s apply only the content of ground_motion[0] below", "expected analysis.dt "
          "≤ 0.5 s, typically the record's sampling (0.01 s) or finer")  # fmt: skip


# -- 4. a record along a global axis under a tilted gravity ---------------------------------
@pytest.mark.parametrize(("gravity", "warned"), [("[0.3420201, -0.9396926]", True),
                                                 ("[0.0, -1.0]", False)])  # fmt: skip
def test_a_component_along_a_tilted_gravity_is_warned(
    tmp_path: Path, caplog: pytest.LogCaptureFixture, gravity: str, warned: bool
) -> None:
    """Gravity tilted 20° (a mesh drawn in a slope's axes): component = "x" shakes 0.342
    of the record along gravity; the warning gives x made normal to gravity, (cos 20°,
    sin 20°) = (0.939693, 0.34202), the direction the yield coefficient takes. A new
    user's block on a 20° plane drawn flat slid 31.2 mm along x and 53.1 mm along that
    direction, as on the inclined mesh (53.1 mm; rigid block 53.4 mm)."""
    (tmp_path / "rec.csv").write_text("".join(f"{0.01 * k:.2f},{0.1 * (k % 3 - 1):.4f}\n"
                                              for k in range(300)))  # fmt: skip
    text = MODEL.replace("dynamic = false", "dt = 0.01").replace("[analysis]", (
        f"[loads]\ngravity = 9.81\ngravity_direction = {gravity}\n"
        '[[ground_motion]]\nfile = "rec.csv"\nunits = "g"\ncomponent = "x"\n[analysis]'))
    p = _model(tmp_path, text)
    with caplog.at_level(logging.WARNING):
        load_job(p)
    words = ("ground_motion[0].component = 'x' is the global x axis, which has 0.342 of its "
             "length along the tilted gravity (loads.gravity_direction): the record shakes "
             "partly along gravity; for horizontal shaking give direction = [0.939693, "
             "0.34202] (the axis made normal to gravity)")  # fmt: skip
    assert (words in caplog.text) is warned, caplog.text


# -- 5. a pressure function written for a list of points ------------------------------------
def test_a_pressure_function_indexing_a_list_of_points_is_named() -> None:
    """``lambda x: ... x[:, 1]`` on the points (facets, quadrature points, d): the error
    names the load and the shape to expect and says to write x[..., k], instead of
    numpy's broadcasting traceback; written so, the load is ρ g h²/2 (the doctest of
    Model.add_pressure checks it to 1e-14)."""
    import numpy as np

    import pfeie as pf
    from pfeie.errors import ModelError

    m = pf.Model(pf.rectangle(2.0, 10.0, 1, 3), [pf.Block("all", pf.Elastic(30e9, 0.2, 2400.0))])
    m.add_pressure("xmin", lambda x: 9810.0 * np.maximum(5.0 - x[:, 1], 0.0))
    with pytest.raises(ModelError, match=r"pressure on 'xmin': a function of the points "
                       r"receives x of shape \(3, 3, 2\) \(facets or cells, quadrature points, "
                       r"coordinates\): index it as x\[\.\.\., k\]; expected one value per "
                       r"point, an array of shape \(3, 3\)"):  # fmt: skip
        m.load_vector()
