"""Valid but unusual models, end to end through the command line: ``pfeie run``, then
``plot``, ``report`` and ``export`` on its results file, each exit 0 (``plot`` of a
static-only run without joints: exit 2, "nothing to plot", said). The models: the setup of
:mod:`test_wrong_inputs` (every table; a load on a face along cells of two types), without
probes, without interfaces, static only, without a record, a single block, and a 3D block on
a joint held by rollers on two sides and shaken along them."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import pytest
from test_wrong_inputs import ELEMENTS, MODEL, drop, into, msh, setup

from pfeie.cli import main
from pfeie.io import Results

UPLIFT = '[[loads.uplift]]\ninterface = "joint"\nheadwater = 1.8\n'
JOINT = "[interfaces.joint]\nfriction_angle = 35.0\ncohesion = 1e5\n"

# a 1 m × 1 m × 2 m column of two hexahedra (gmsh ids 30, 31): "base" below z = 1, "block"
# above, the joint between them; "bottom" at z = 0; "sides": the block's faces x = 0 and x = 1
BOX_NODES = [(x, y, z) for z in (0.0, 1.0, 2.0) for y in (0.0, 1.0) for x in (0.0, 1.0)]
BOX_NAMES = {1: (3, "base"), 2: (3, "block"), 3: (2, "bottom"), 4: (2, "joint"), 5: (2, "sides")}
BOX_ELEMENTS = [(1, 3, 3, [1, 3, 4, 2]), (2, 3, 4, [5, 6, 8, 7]),
                (3, 3, 5, [5, 7, 11, 9]), (4, 3, 5, [6, 10, 12, 8]),
                (30, 5, 1, [1, 2, 4, 3, 5, 6, 8, 7]),
                (31, 5, 2, [5, 6, 8, 7, 9, 10, 12, 11])]  # fmt: skip
BOX = """\
[mesh]
file = "plate.msh"
[materials.concrete]
E = 3e10
nu = 0.2
rho = 2400.0
[blocks]
base = "concrete"
block = "concrete"
[interfaces.joint]
friction_angle = 30.0
[[supports]]
group = "bottom"
[[supports]]
group = "sides"
components = ["x"]
[[ground_motion]]
file = "rec.csv"
units = "g"
component = "y"
[analysis]
dt = 0.01
[output]
folder = "out"
probes = { top = [0.5, 0.5, 2.0] }
"""


def _mixed(folder: Path) -> None:
    """The dam's cell 22 as two triangles: the crest (pressure) and the upstream face (water,
    silt) run along a quadrilateral and a triangle."""
    els = [e for e in ELEMENTS if e[0] != 22] + [(22, 2, 2, [4, 5, 8]), (24, 2, 2, [4, 8, 7])]
    (folder / "plate.msh").write_text(msh(elements=els))


def _box(folder: Path) -> None:
    (folder / "plate.msh").write_text(msh(BOX_NODES, BOX_ELEMENTS, BOX_NAMES))
    (folder / "model.toml").write_text(BOX)


EDGE: dict[str, tuple[Callable[[str], str], Callable[[Path], None] | None]] = {
    "every-table-mixed-cells": (lambda t: t, _mixed),
    "no-probes": (drop("probes = { crest = [1.0, 2.0] }\n"), None),
    "no-interfaces": (drop(JOINT, UPLIFT), None),
    "static-only": (into("[analysis]", "dynamic = false"), None),
    "no-record": (drop('[[ground_motion]]\nfile = "rec.csv"\nunits = "g"\n'), None),
    "single-block": (
        lambda t: drop(JOINT, UPLIFT, 'rock = "rock"\n')(t).replace(
            'group = "bottom"', 'group = "joint"'
        ),
        None,
    ),
    "3d-block-on-rollers": (lambda t: t, _box),
}


@pytest.mark.parametrize("name", list(EDGE))
def test_edge_model_end_to_end(name: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                               capsys: pytest.CaptureFixture[str]) -> None:  # fmt: skip
    edit, prepare = EDGE[name]
    monkeypatch.chdir(tmp_path)
    setup(tmp_path)
    (tmp_path / "model.toml").write_text(edit(MODEL))
    if prepare is not None:
        prepare(tmp_path)
    assert main(["run", "model.toml", "--quiet"]) == 0, capsys.readouterr().err
    res = "out/results.h5"
    with Results(res) as r:
        assert r.completed
        static_only = r.n_times == 0
    assert static_only == (name == "static-only")
    assert main(["report", res]) == 0, capsys.readouterr().err
    assert Path("out/report.html").stat().st_size > 1000
    assert main(["export", res, "--csv", "csv"]) == 0, capsys.readouterr().err
    assert any(Path("csv").iterdir())
    capsys.readouterr()
    assert main(["plot", res]) == 0, capsys.readouterr().err
    assert any(Path("out/figures").glob("*.png"))
    err = capsys.readouterr().err
    assert "Traceback" not in err
