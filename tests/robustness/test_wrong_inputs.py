"""Named wrong inputs, each through the command line (``pfeie.cli.main``, in-process): exit
2, a single ``pfeie: error`` line that holds the words expected (the file, the key, line,
group or gmsh element id, and what was expected), and no traceback.

The cases mutate one small, valid setup (:func:`setup`): a model file that uses every
table (mesh, materials, blocks, interfaces, supports, loads with pressure, hydrostatic,
silt, Westergaard and uplift, ground motion, analysis, damping, output with a probe), its
gmsh mesh (a 2 m × 2 m plate of four quadrilaterals: "rock" below, "dam" above, the joint
between them), two records (CSV, AT2) and a study file. Each case changes one thing: the
model file's text, a file, or the command line. The base setup itself passes ``pfeie
check`` and ``pfeie study`` validation (:func:`test_the_base_setup_is_valid`).
"""

from __future__ import annotations

import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pytest

from pfeie.cli import main

# -- the base setup ----------------------------------------------------------------------
# nodes 1-9 on a 3 × 3 grid of 1 m; quads 20, 21 ("rock", y in [0, 1]) and 22, 23 ("dam",
# y in [1, 2]); lines: "bottom" (y = 0), "joint" (y = 1), "upstream" (x = 0 on the dam),
# "crest" (y = 2)
NODES = [(x, y, 0.0) for y in (0.0, 1.0, 2.0) for x in (0.0, 1.0, 2.0)]
NAMES = {1: (2, "rock"), 2: (2, "dam"), 3: (1, "bottom"), 4: (1, "joint"),
         5: (1, "upstream"), 6: (1, "crest")}  # fmt: skip
ELEMENTS = [(1, 1, 3, [1, 2]), (2, 1, 3, [2, 3]), (3, 1, 4, [4, 5]), (4, 1, 4, [5, 6]),
            (5, 1, 5, [4, 7]), (6, 1, 6, [7, 8]), (7, 1, 6, [8, 9]),
            (20, 3, 1, [1, 2, 5, 4]), (21, 3, 1, [2, 3, 6, 5]),
            (22, 3, 2, [4, 5, 8, 7]), (23, 3, 2, [5, 6, 9, 8])]  # fmt: skip

MODEL = """\
title = "plate"
[mesh]
file = "plate.msh"
[materials.rock]
E = 1e9
nu = 0.25
rho = 2000.0
[materials.concrete]
E = 2e10
nu = 0.2
rho = 2400.0
tensile_strength = 2e6
[blocks]
rock = "rock"
dam = "concrete"
[interfaces.joint]
friction_angle = 35.0
cohesion = 1e5
[[supports]]
group = "bottom"
[loads]
gravity = 9.81
[[loads.pressure]]
group = "crest"
value = 1e4
[[loads.hydrostatic]]
groups = ["upstream"]
water_level = 1.8
[[loads.silt]]
groups = ["upstream"]
level = 1.2
submerged_unit_weight = 9e3
friction_angle = 30.0
[[loads.westergaard]]
groups = ["upstream"]
water_level = 1.8
[[loads.uplift]]
interface = "joint"
headwater = 1.8
[[ground_motion]]
file = "rec.csv"
units = "g"
[analysis]
dt = 0.01
duration = 0.03
[damping]
ratio = 0.05
frequencies = [1.0, 10.0]
[output]
folder = "out"
probes = { crest = [1.0, 2.0] }
"""

CSV = "time,acc\n0,0\n0.01,0.1\n0.02,-0.05\n0.03,0\n"
AT2_HEAD = "PEER NGA STRONG MOTION DATABASE RECORD\nTEST\nACCELERATION TIME SERIES IN UNITS OF G\n"
AT2 = AT2_HEAD + "NPTS=    4, DT=   .0100 SEC\n 0.0 0.1 -0.05 0.0\n"

STUDY = """\
title = "study"
model = "model.toml"
[[records]]
file = "rec.csv"
units = "g"
[intensity]
measure = "pga"
values = [0.1, 0.2]
[output]
folder = "study"
"""


def msh(nodes: Sequence[tuple[float, float, float]] = NODES,
        elements: Sequence[tuple[int, int, int, list[int]]] = ELEMENTS,
        names: Mapping[int, tuple[int, str]] = NAMES) -> str:  # fmt: skip
    """A gmsh MSH 2.2 ASCII file: nodes (x, y, z), elements (gmsh id, gmsh type, physical
    group, nodes)."""
    lines = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", str(len(names))]
    lines += [f'{d} {tag} "{name}"' for tag, (d, name) in names.items()]
    lines += ["$EndPhysicalNames", "$Nodes", str(len(nodes))]
    lines += [f"{i} {x} {y} {z}" for i, (x, y, z) in enumerate(nodes, start=1)]
    lines += ["$EndNodes", "$Elements", str(len(elements))]
    lines += [f"{i} {t} 2 {ph} {ph} " + " ".join(map(str, ns)) for i, t, ph, ns in elements]
    return "\n".join([*lines, "$EndElements"]) + "\n"


def setup(folder: Path) -> None:
    """Write the base setup into ``folder``."""
    (folder / "plate.msh").write_text(msh())
    (folder / "model.toml").write_text(MODEL)
    (folder / "rec.csv").write_text(CSV)
    (folder / "rec.at2").write_text(AT2)
    (folder / "study.toml").write_text(STUDY)


# -- edits -------------------------------------------------------------------------------
Edit = Callable[[str], str]


def sub(old: str, new: str) -> Edit:
    """Replace ``old`` (which must be in the text) by ``new``."""

    def edit(text: str) -> str:
        assert old in text, old
        return text.replace(old, new, 1)

    return edit


def into(header: str, lines: str) -> Edit:
    """Add ``lines`` right after the table header ``header`` (e.g. ``[analysis]``)."""
    return sub(f"{header}\n", f"{header}\n{lines}\n")


def drop(*texts: str) -> Edit:
    """Remove each of ``texts`` from the model file."""

    def edit(text: str) -> str:
        for t in texts:
            assert t in text, t
            text = text.replace(t, "", 1)
        return text

    return edit


def at2(header4: str = "NPTS=    4, DT=   .0100 SEC", data: str = " 0.0 0.1 -0.05 0.0",
        head: str = AT2_HEAD) -> str:  # fmt: skip
    return head + header4 + "\n" + data + "\n"


def use_at2(text: str) -> str:
    return text.replace('file = "rec.csv"\nunits = "g"', 'file = "rec.at2"')


def mesh_of(**kw: object) -> str:
    return msh(**kw)  # type: ignore[arg-type]


def elements_with(gmsh_id: int, element: tuple[int, int, int, list[int]]) -> list:  # type: ignore[type-arg]
    return [element if e[0] == gmsh_id else e for e in ELEMENTS]


@dataclass(frozen=True)
class Case:
    """A wrong input: ``edit`` of the model file's text, ``files`` written over the base
    setup, the command line ``argv`` (run in the setup's folder), and the words that the
    error line must hold."""

    id: str
    words: tuple[str, ...]
    edit: Edit | None = None
    files: Mapping[str, str | bytes] = field(default_factory=dict)
    argv: tuple[str, ...] = ("check", "model.toml")
    prepare: Callable[[Path], None] | None = None


def C(id: str, *words: str, edit: Edit | None = None,
      files: Mapping[str, str | bytes] | None = None,
      argv: Sequence[str] = ("check", "model.toml"),
      prepare: Callable[[Path], None] | None = None) -> Case:  # fmt: skip
    return Case(id, words, edit, files or {}, tuple(argv), prepare)


M = "model.toml"
R = "out/results.h5"


def _results_like(folder: Path) -> None:
    """Files that are not results files: an HDF5 file of something else, a text file."""
    import h5py

    with h5py.File(folder / "other.h5", "w") as f:
        f["x"] = [1.0, 2.0]
    (folder / "text.h5").write_text("not hdf5\n")
    (folder / "afile").write_text("x")


_HELD: list[Any] = []  # the folders this process holds for the cases, until it ends


def _live_lock(folder: Path) -> None:
    """The output folder held by another run (here this process, as a run holds it)."""
    from pfeie._job import FolderLock

    (folder / "out").mkdir()
    _HELD.append(FolderLock(folder / "out", Path("other.toml")).__enter__())


# fmt: off
CASES: list[Case] = [
    # -- the model file as a whole ---------------------------------------------------------
    C("toml-syntax", M, "not valid TOML", "line", edit=sub("[mesh]", "[mesh")),
    C("toml-not-utf8", M, "not valid TOML", files={M: b'title = "\xff\xfe"\n'}),
    C("model-file-missing", "none.toml", "model file not found", argv=("check", "none.toml")),
    C("model-file-is-a-folder", "out", "is a folder; expected a model file (.toml)",
      argv=("check", "out"), prepare=lambda d: (d / "out").mkdir()),
    C("top-unknown-key", M, "colour: unknown key", "expected one of",
      edit=sub('title = "plate"', 'title = "plate"\ncolour = 1')),
    C("title-not-string", M, "title: expected a string", edit=sub('"plate"\n[mesh]', "3\n[mesh]")),
    C("plane-unknown", M, "plane: expected one of 'strain', 'stress'",
      edit=sub('title = "plate"', 'title = "plate"\nplane = "axisymmetric"')),
    C("thickness-zero", M, "thickness: expected a number in [1e-06, 1e+06] m, found 0.0",
      edit=sub('title = "plate"', 'title = "plate"\nthickness = 0.0')),
    C("thickness-inf", M, "thickness: expected a finite number",
      edit=sub('title = "plate"', 'title = "plate"\nthickness = inf')),
    # -- [mesh] ----------------------------------------------------------------------------
    C("mesh-table-missing", M, "mesh: missing (required)",
      edit=drop('[mesh]\nfile = "plate.msh"\n')),
    C("mesh-file-missing", M, "mesh.file: missing (required)", edit=drop('file = "plate.msh"\n')),
    C("mesh-file-not-found", M, "mesh.file", "none.msh", "mesh file not found",
      edit=sub('"plate.msh"', '"none.msh"')),
    C("mesh-file-number", M, "mesh.file: expected a string", edit=sub('"plate.msh"', "3")),
    C("mesh-file-nul", M, "mesh.file", "NUL", edit=sub('"plate.msh"', '"pl\\u0000ate.msh"')),
    C("mesh-unknown-key", M, "mesh.format: unknown key", edit=into("[mesh]", 'format = "msh"')),
    # -- [materials] -----------------------------------------------------------------------
    C(
        "materials-missing",
        M,
        "materials: missing (required)",
        edit=drop(
            "[materials.rock]\nE = 1e9\nnu = 0.25\nrho = 2000.0\n",
            "[materials.concrete]\nE = 2e10\nnu = 0.2\nrho = 2400.0\ntensile_strength = 2e6\n",
        ),
    ),
    C("material-E-string", M, "materials.rock.E: expected a number, found a string 'stiff'",
      edit=sub("E = 1e9", 'E = "stiff"')),
    C("material-E-negative", M, "materials.rock.E: expected a number in (0, 1e+16] Pa, found -1",
      edit=sub("E = 1e9", "E = -1e9")),
    C("material-E-zero", M, "materials.rock.E: expected a number in (0, 1e+16] Pa, found 0.0",
      edit=sub("E = 1e9", "E = 0.0")),
    C("material-E-inf", M, "materials.rock.E: expected a finite number, found inf",
      edit=sub("E = 1e9", "E = inf")),
    C("material-E-nan", M, "materials.rock.E: expected a finite number, found nan",
      edit=sub("E = 1e9", "E = nan")),
    C("material-E-1e400", M, "materials.rock.E: expected a finite number, found inf",
      edit=sub("E = 1e9", "E = 1e400")),
    C("material-E-missing", M, "materials.rock.E: missing (required)", edit=drop("E = 1e9\n")),
    # huge but finite: a slip of the exponent, caught by the physical ranges
    C("material-E-1e300", M, "materials.rock.E: expected a number in (0, 1e+16] Pa, found 1e+300",
      edit=sub("E = 1e9", "E = 1e300")),
    C("material-rho-1e300", M, "materials.rock.rho: "
      "expected a number in [0, 1e+06] kg/m³, found 1e+300",
      edit=sub("rho = 2000.0", "rho = 1e300")),
    C("gravity-1e300", M, "loads.gravity: expected a number in [0, 1000] m/s², found 1e+300",
      edit=sub("gravity = 9.81", "gravity = 1e300")),
    C("hydrostatic-level-1e300", M, "loads.hydrostatic[0].water_level: expected a number "
      "in [-1e+06, 1e+06] m, found 1e+300",
      edit=sub("[[loads.hydrostatic]]\ngroups = [\"upstream\"]\n"
                             "water_level = 1.8", "[[loads.hydrostatic]]\ngroups = "
                             "[\"upstream\"]\nwater_level = 1e300")),
    C("pressure-1e300", M, "loads.pressure[0].value: expected a number in [-1e+10, 1e+10] Pa, "
      "found 1e+300", edit=sub("value = 1e4", "value = 1e300")),
    C("silt-level-1e300", M, "loads.silt[0].level: expected a number in [-1e+06, 1e+06] m",
      edit=sub("level = 1.2", "level = 1e300")),
    C("silt-weight-1e300", M, "loads.silt[0].submerged_unit_weight: expected a number in "
      "(0, 1e+06] N/m³, found 1e+300", edit=sub("submerged_unit_weight = 9e3",
                                                "submerged_unit_weight = 1e300")),
    C("silt-k-1e3", M, "loads.silt[0].k: expected a number in (0, 100], found 1000.0",
      edit=sub("friction_angle = 30.0\n[[loads.westergaard]]", "k = 1e3\n[[loads.westergaard]]")),
    C("uplift-headwater-1e300", M, "loads.uplift[0].headwater: expected a number in "
      "[-1e+06, 1e+06] m, found 1e+300", edit=sub("headwater = 1.8", "headwater = 1e300")),
    C("uplift-tailwater-1e300", M, "loads.uplift[0].tailwater: expected a number in "
      "[-1e+06, 1e+06] m", edit=sub("headwater = 1.8", "headwater = 1.8\ntailwater = -1e300")),
    C("joint-cohesion-1e300", M, "interfaces.joint.cohesion: expected a number in [0, 1e+10] Pa, "
      "found 1e+300", edit=sub("cohesion = 1e5", "cohesion = 1e300")),
    C("joint-tension-1e300", M, "interfaces.joint.tensile_strength: expected a number in "
      "[0, 1e+10] Pa", edit=sub("cohesion = 1e5", "cohesion = 1e5\ntensile_strength = 1e300")),
    C("joint-stiffness-1e300", M, "interfaces.joint.normal_stiffness: expected a number in "
      "[1, 1e+20] Pa/m", edit=sub("cohesion = 1e5", "cohesion = 1e5\nnormal_stiffness = 1e300")),
    C("support-value-1e300", M, "supports[0].value: expected a number in [-1000, 1000] m",
      edit=into("[[supports]]", "value = 1e300")),
    C("thickness-1e300", M, "thickness: expected a number in [1e-06, 1e+06] m, found 1e+300",
      edit=sub('title = "plate"', 'title = "plate"\nthickness = 1e300')),
    C("damping-beta-10", M, "damping.beta: expected a number in [0, 1] s, found 10.0",
      edit=sub("ratio = 0.05\nfrequencies = [1.0, 10.0]", "beta = 10.0")),
    C("damping-alpha-1e300", M, "damping.alpha: expected a number in [0, 10000] 1/s",
      edit=sub("ratio = 0.05\nfrequencies = [1.0, 10.0]", "alpha = 1e300")),
    C("damping-ratio-above-1", M, "damping.ratio: expected a number in [0, 1], found 2.0",
      edit=sub("ratio = 0.05", "ratio = 2.0")),
    C("record-pga-50g", M, "ground_motion[0].pga: expected a number in (0, 20] g, found 50.0",
      edit=sub('units = "g"\n[analysis]', 'units = "g"\npga = 50.0\n[analysis]')),
    C("westergaard-length-1e300", M, "loads.westergaard[0].length: expected a number in "
      "(0, 1e+06] m", edit=sub('groups = ["upstream"]\nwater_level = 1.8\n[[loads.uplift]]',
                                'groups = ["upstream"]\nwater_level = 1.8\nmodel = "fe"\n'
                                'length = 1e300\n[[loads.uplift]]')),
    C("material-nu-half", M, "materials.rock.nu: expected a number in (-1, 0.5), found 0.5",
      edit=sub("nu = 0.25", "nu = 0.5")),
    C("material-nu-minus-one", M, "materials.rock.nu: expected a number in (-1, 0.5), found -1.0",
      edit=sub("nu = 0.25", "nu = -1.0")),
    C("material-rho-negative", M, "materials.rock.rho: "
      "expected a number in [0, 1e+06] kg/m³, found -1.0",
      edit=sub("rho = 2000.0", "rho = -1.0")),
    C("material-tensile-zero", M, "materials.concrete.tensile_strength: "
      "expected a number in (0, 1e+10] Pa",
      edit=sub("tensile_strength = 2e6", "tensile_strength = 0.0")),
    C("material-unknown-key", M, "materials.rock.G: unknown key", "expected one of",
      edit=sub("nu = 0.25", "nu = 0.25\nG = 1e8")),
    C("materials-not-a-table", M, "materials.rock", "expected",
      edit=sub("[materials.rock]\nE = 1e9\nnu = 0.25\nrho = 2000.0\n", "[materials]\nrock = 5\n")),
    # -- [blocks] --------------------------------------------------------------------------
    C("blocks-missing", M, "blocks: missing (required)",
      edit=drop('[blocks]\nrock = "rock"\ndam = "concrete"\n')),
    C("block-unknown-material", M, "blocks.dam: unknown material 'steel'",
      edit=sub('dam = "concrete"', 'dam = "steel"')),
    C("block-unknown-group", M, "blocks.dome: no physical group 'dome'", "groups of dimension 2",
      edit=sub('dam = "concrete"', 'dam = "concrete"\ndome = "concrete"')),
    C("block-on-a-line-group", M, "blocks.crest",
      "'crest' is a group of dimension 1, a block needs 2",
      edit=sub('dam = "concrete"', 'dam = "concrete"\ncrest = "concrete"')),
    C("block-material-number", M, "blocks.dam: expected a string",
      edit=sub('dam = "concrete"', "dam = 1")),
    # -- [interfaces] ----------------------------------------------------------------------
    C("joint-friction-90", M, "interfaces.joint.friction_angle: "
      "expected an angle in [0, 90) degrees, found 90.0",
      edit=sub("friction_angle = 35.0", "friction_angle = 90.0")),
    C("joint-friction-negative", M, "interfaces.joint.friction_angle: "
      "expected an angle in [0, 90) degrees, found -5.0",
      edit=sub("friction_angle = 35.0", "friction_angle = -5.0")),
    C("joint-friction-missing", M, "interfaces.joint.friction_angle: missing (required)",
      edit=drop("friction_angle = 35.0\ncohesion = 1e5\n")),
    C("joint-cohesion-negative", M, "interfaces.joint.cohesion: expected a number in [0, 1e+10] Pa",
      edit=sub("cohesion = 1e5", "cohesion = -1e5")),
    C("joint-initial-unknown", M, "interfaces.joint.initial: expected one of 'intact', 'broken'",
      edit=into("[interfaces.joint]", 'initial = "glued"')),
    C("joint-law-unknown", M, "interfaces.joint.law: expected one of 'mohr-coulomb'",
      edit=into("[interfaces.joint]", 'law = "rate-and-state"')),
    C("joint-weakening-missing", M, "interfaces.joint.weakening_distance: missing (required with",
      edit=into("[interfaces.joint]", 'law = "slip-weakening"')),
    C("joint-weakening-without-law", M, "interfaces.joint.weakening_distance: only with law",
      edit=into("[interfaces.joint]", "weakening_distance = 0.01")),
    C("joint-stiffness-zero", M, "interfaces.joint.normal_stiffness: "
      "expected a number in [1, 1e+20] Pa/m",
      edit=into("[interfaces.joint]", "normal_stiffness = 0.0")),
    C("joint-unknown-key", M, "interfaces.joint.friction: unknown key",
      edit=into("[interfaces.joint]", "friction = 0.6")),
    C(
        "joint-unknown-group",
        M,
        "interfaces.fault: no physical group 'fault'",
        "of dimension 1: ['bottom', 'crest', 'joint', 'upstream']",
        edit=sub(
            "[interfaces.joint]\nfriction_angle = 35.0\ncohesion = 1e5\n",
            "[interfaces.joint]\nfriction_angle = 35.0\ncohesion = 1e5\n"
            "[interfaces.fault]\nfriction_angle = 35.0\n",
        ),
    ),
    C(
        "joint-on-a-block-group",
        M,
        "interfaces.rock",
        "'rock' is a group of dimension 2, this needs 1",
        edit=sub(
            "[interfaces.joint]\nfriction_angle = 35.0\ncohesion = 1e5\n",
            "[interfaces.joint]\nfriction_angle = 35.0\ncohesion = 1e5\n"
            "[interfaces.rock]\nfriction_angle = 35.0\n",
        ),
    ),
    C(
        "joint-on-the-boundary",
        M,
        "interface 'bottom' has facets on the mesh boundary",
        "expected facets between two cells",
        edit=sub(
            "[interfaces.joint]\nfriction_angle = 35.0\ncohesion = 1e5\n",
            "[interfaces.joint]\nfriction_angle = 35.0\ncohesion = 1e5\n"
            "[interfaces.bottom]\nfriction_angle = 35.0\n",
        ),
    ),
    # -- [[supports]] ----------------------------------------------------------------------
    C("supports-as-a-table", M, "supports: expected an array of tables ([[supports]])",
      edit=sub("[[supports]]", "[supports]")),
    C("support-group-missing", M, "supports[0].group: missing (required)",
      edit=sub('[[supports]]\ngroup = "bottom"', "[[supports]]\nvalue = 0.0")),
    C("support-unknown-group", M, "supports[0].group: no physical group 'base'",
      edit=sub('group = "bottom"', 'group = "base"')),
    C("support-component-w", M, "supports[0].components: expected an array of 'x', 'y', 'z'",
      edit=into("[[supports]]", 'components = ["x", "w"]')),
    C("support-component-z-2d", M, "supports[0].components: 'z' in a 2D model",
      edit=into("[[supports]]", 'components = ["z"]')),
    C("support-components-empty", M, "supports[0].components", "expected",
      edit=into("[[supports]]", "components = []")),
    C("support-value-inf", M, "supports[0].value: expected a finite number",
      edit=into("[[supports]]", "value = -inf")),
    C("support-unknown-key", M, "supports[0].groups: unknown key",
      edit=into("[[supports]]", 'groups = ["bottom"]')),
    # -- [loads] ---------------------------------------------------------------------------
    C("gravity-negative", M, "loads.gravity: expected a number in [0, 1000] m/s², found -9.81",
      edit=sub("gravity = 9.81", "gravity = -9.81")),
    C("gravity-direction-zero", M, "loads.gravity_direction", "finite non-zero vector",
      edit=into("[loads]", "gravity_direction = [0.0, 0.0]")),
    C("gravity-direction-3d", M, "loads.gravity_direction: expected 2 components",
      edit=into("[loads]", "gravity_direction = [0.0, 0.0, -1.0]")),
    C("gravity-direction-nan", M, "loads.gravity_direction", "finite",
      edit=into("[loads]", "gravity_direction = [nan, -1.0]")),
    C("loads-unknown-key", M, "loads.wind: unknown key", edit=into("[loads]", "wind = 1.0")),
    C("pressure-group-missing", M, "loads.pressure[0].group: missing (required)",
      edit=drop('group = "crest"\n')),
    C("pressure-unknown-group", M, "loads.pressure[0].group: no physical group 'top'",
      edit=sub('group = "crest"', 'group = "top"')),
    C("pressure-on-a-block", M, "loads.pressure[0].group", "'dam' is a group of dimension 2",
      edit=sub('group = "crest"', 'group = "dam"')),
    C("pressure-value-string", M, "loads.pressure[0].value: expected a number",
      edit=sub("value = 1e4", 'value = "1e4"')),
    C("pressure-value-nan", M, "loads.pressure[0].value: expected a finite number",
      edit=sub("value = 1e4", "value = nan")),
    C(
        "hydrostatic-groups-string",
        M,
        "loads.hydrostatic[0].groups: expected an array",
        edit=sub(
            'groups = ["upstream"]\nwater_level = 1.8\n[[loads.silt]]',
            'groups = "upstream"\nwater_level = 1.8\n[[loads.silt]]',
        ),
    ),
    C(
        "hydrostatic-groups-empty",
        M,
        "loads.hydrostatic[0].groups",
        "expected",
        edit=sub(
            'groups = ["upstream"]\nwater_level = 1.8\n[[loads.silt]]',
            "groups = []\nwater_level = 1.8\n[[loads.silt]]",
        ),
    ),
    C(
        "hydrostatic-unknown-group",
        M,
        "loads.hydrostatic[0].groups: no physical group 'face'",
        edit=sub(
            'groups = ["upstream"]\nwater_level = 1.8\n[[loads.silt]]',
            'groups = ["face"]\nwater_level = 1.8\n[[loads.silt]]',
        ),
    ),
    # (water in a joint is [[loads.hydrostatic]] or [[loads.pressure]] on the interface;
    # silt on one is refused)
    C("silt-on-an-interface", M, "loads.silt[0].groups: 'joint' is an interface",
      "expected a group of boundary faces", edit=sub(
          '[[loads.silt]]\ngroups = ["upstream"]', '[[loads.silt]]\ngroups = ["joint"]')),
    C("pressure-inside-a-block", M, "loads.pressure[0].group: pressure on 'joint'",
      "inside a block", "expected facets on the boundary of a block or on an interface",
      edit=lambda t: drop("[interfaces.joint]\nfriction_angle = 35.0\ncohesion = 1e5\n",
                          '[[loads.uplift]]\ninterface = "joint"\nheadwater = 1.8\n')(t).replace(
          'group = "crest"', 'group = "joint"')),
    C("blocks-empty", M, "a model needs at least one block",
      edit=drop('rock = "rock"\ndam = "concrete"\n')),
    C(
        "hydrostatic-level-missing",
        M,
        "loads.hydrostatic[0].water_level: missing (required)",
        edit=sub(
            'groups = ["upstream"]\nwater_level = 1.8\n[[loads.silt]]',
            'groups = ["upstream"]\n[[loads.silt]]',
        ),
    ),
    C("hydrostatic-density-zero", M, "loads.hydrostatic[0].density: "
      "expected a number in (0, 100000] kg/m³",
      edit=into("[[loads.hydrostatic]]", "density = 0.0")),
    C("silt-k-and-angle", M, "loads.silt[0]: give either k or friction_angle, not both",
      edit=into("[[loads.silt]]", "k = 0.4")),
    C("silt-no-coefficient", M, "loads.silt[0].k: missing", "friction_angle",
      edit=drop("friction_angle = 30.0\n")),
    C("silt-weight-zero", M, "loads.silt[0].submerged_unit_weight: "
      "expected a number in (0, 1e+06] N/m³",
      edit=sub("submerged_unit_weight = 9e3", "submerged_unit_weight = 0.0")),
    C("silt-unknown-group", M, "loads.silt[0].groups: no physical group 'floor'",
      edit=sub('groups = ["upstream"]\nlevel', 'groups = ["upstream", "floor"]\nlevel')),
    C("silt-angle-90", M, "loads.silt[0].friction_angle: expected an angle in [0, 90) degrees",
      edit=sub("friction_angle = 30.0", "friction_angle = 90.0")),
    C("silt-level-missing", M, "loads.silt[0].level: missing (required)",
      edit=drop("level = 1.2\n")),
    C("westergaard-model-unknown", M,
      "loads.westergaard[0].model: expected one of 'westergaard', 'fe'",
      edit=into("[[loads.westergaard]]", 'model = "zangar"')),
    C(
        "westergaard-unknown-group",
        M,
        "loads.westergaard[0].groups: no physical group 'face'",
        edit=sub(
            'groups = ["upstream"]\nwater_level = 1.8\n[[loads.uplift]]',
            'groups = ["face"]\nwater_level = 1.8\n[[loads.uplift]]',
        ),
    ),
    C(
        "westergaard-level-missing",
        M,
        "loads.westergaard[0].water_level: missing (required)",
        edit=sub(
            'groups = ["upstream"]\nwater_level = 1.8\n[[loads.uplift]]',
            'groups = ["upstream"]\n[[loads.uplift]]',
        ),
    ),
    C("westergaard-density-negative", M, "loads.westergaard[0].density: "
      "expected a number in (0, 100000] kg/m³",
      edit=into("[[loads.westergaard]]", "density = -1000.0")),
    C("westergaard-length-closed-form", M, "loads.westergaard[0].length: only with model = 'fe'",
      edit=into("[[loads.westergaard]]", "length = 10.0")),
    C("westergaard-refine-zero", M, "loads.westergaard[0].refine: expected an integer >= 1",
      edit=into("[[loads.westergaard]]", 'model = "fe"\nrefine = 0')),
    C("uplift-not-an-interface", M, "loads.uplift[0].interface: 'crest' is not an interface",
      edit=sub('interface = "joint"', 'interface = "crest"')),
    C("uplift-efficiency-above-1", M, "loads.uplift[0].drain_efficiency: "
      "expected a number in [0, 1], found 1.5",
      edit=into("[[loads.uplift]]", "drain_efficiency = 1.5")),
    C("uplift-upstream-z", M, "loads.uplift[0].upstream: expected one of '-x', '+x'",
      edit=into("[[loads.uplift]]", 'upstream = "+z"')),
    C("uplift-upstream-y-2d", M, "loads.uplift[0]", "upstream", "2D",
      edit=into("[[loads.uplift]]", 'upstream = "-y"')),
    C("uplift-shaking-unknown", M, "loads.uplift[0].shaking: expected one of 'keep', 'full'",
      edit=into("[[loads.uplift]]", 'shaking = "half"')),
    C("uplift-drains-negative", M, "loads.uplift[0].drains: expected a number in [0, 1e+06] m",
      edit=into("[[loads.uplift]]", "drains = -1.0")),
    C("uplift-headwater-missing", M, "loads.uplift[0].headwater: missing (required)",
      edit=drop("headwater = 1.8\n")),
    # -- [[ground_motion]] -----------------------------------------------------------------
    C("record-file-missing", M, "ground_motion[0].file: missing (required)",
      edit=drop('file = "rec.csv"\n')),
    C("record-not-found", M, "ground_motion[0]", "none.csv", "record file not found",
      edit=sub('"rec.csv"', '"none.csv"')),
    C("record-units-unknown", M, "ground_motion[0].units: expected one of 'g', 'm/s2', 'cm/s2'",
      edit=sub('units = "g"', 'units = "furlongs"')),
    C("record-units-missing", M, "ground_motion[0]", "rec.csv", "give the units",
      edit=drop('units = "g"\n')),
    C("record-component-z-2d", M, "ground_motion[0].component: 'z' in a 2D model",
      edit=into("[[ground_motion]]", 'component = "z"')),
    C("record-direction-3d", M, "ground_motion[0].direction: expected 2 components",
      edit=into("[[ground_motion]]", "direction = [1.0, 0.0, 0.0]")),
    C("record-direction-zero", M, "ground_motion[0]", "direction", "non-zero",
      edit=into("[[ground_motion]]", "direction = [0.0, 0.0]")),
    C("record-scale-zero", M, "ground_motion[0].scale: a scale of 0 removes the record",
      edit=into("[[ground_motion]]", "scale = 0.0")),
    C("record-scale-and-pga", M, "ground_motion[0]: give either scale or pga, not both",
      edit=into("[[ground_motion]]", "scale = 2.0\npga = 0.3")),
    C("record-pga-negative", M, "ground_motion[0].pga: expected a number in (0, 20] g",
      edit=into("[[ground_motion]]", "pga = -0.3")),
    C("record-target-period-negative", M,
      "ground_motion[0].target_sa.period: expected a number in (0, 100] s",
      edit=into("[[ground_motion]]", "target_sa = {period = -0.3, value = 0.5}")),
    C("record-target-unknown-key", M, "ground_motion[0].target_sa.zeta: unknown key",
      edit=into("[[ground_motion]]", "target_sa = {period = 0.3, value = 0.5, zeta = 0.05}")),
    C("record-target-damping-1", M, "ground_motion[0].target_sa.damping: "
      "expected a number in (0, 1), found 1.0",
      edit=into("[[ground_motion]]", "target_sa = {period = 0.3, value = 0.5, damping = 1.0}")),
    C("record-format-unknown", M, "ground_motion[0].format: expected one of 'auto', 'at2'",
      edit=into("[[ground_motion]]", 'format = "peer"')),
    C("record-dt-two-column", M, "ground_motion[0]", "rec.csv", "do not give dt",
      edit=into("[[ground_motion]]", "dt = 0.01")),
    # a two-column file forced to one column: the table is named (before the missing dt)
    C("record-one-column-no-dt", M, "ground_motion[0]", "rec.csv",
      "a table of time and 1 column(s), not one column of accelerations",
      edit=into("[[ground_motion]]", 'format = "one-column"')),
    C("record-as-a-table", M, "ground_motion: expected an array of tables",
      edit=sub("[[ground_motion]]", "[ground_motion]")),
    C("record-baseline-string", M, "ground_motion[0].baseline: expected a boolean",
      edit=into("[[ground_motion]]", 'baseline = "yes"')),
    C("record-all-zeros-pga", M, "ground_motion[0]", "the record is all zeros",
      edit=into("[[ground_motion]]", "pga = 0.3"), files={"rec.csv": "t,a\n0,0\n0.01,0\n"}),
    C("record-in-cm-s2-read-as-g", M, "ground_motion[0]", "peak ground acceleration is 300 g",
      "expected at most 20 g", "check units", files={"rec.csv": "t,a\n0,0\n0.01,300\n0.02,0\n"}),
    C("record-scale-huge", M, "ground_motion[0]", "expected at most 20 g",
      edit=into("[[ground_motion]]", "scale = 1e300")),
    C("record-shorter-than-a-step", M, "ground_motion[0]", "the record lasts 0.005 s, less "
      "than one step (analysis.dt = 0.01 s)", files={"rec.csv": "t,a\n0,0.1\n0.005,0.2\n"}),
    C("record-three-columns", M, "ground_motion[0]", "rec.csv", "line 2", "3 numbers",
      "a table, not one column", edit=into("[[ground_motion]]", 'format = "one-column"\ndt = 0.01'),
      files={"rec.csv": "t,a,x\n0,0.1,1\n0.01,0.2,1\n"}),
    # -- record files ----------------------------------------------------------------------
    C("at2-value-1e400", "rec.at2", "line 5", "'1e400'", "expected a finite number", edit=use_at2,
      files={"rec.at2": at2(data=" 0.0 1e400 -0.05 0.0")}),
    C("at2-text-in-data", "rec.at2", "line 5", "non-numeric text", edit=use_at2,
      files={"rec.at2": at2(data=" 0.0 abc -0.05 0.0")}),
    C("at2-units-line", "rec.at2", "line 3", "expected the units 'IN UNITS OF G'", edit=use_at2,
      files={"rec.at2": at2(head="PEER\nTEST\nACCELERATION IN FURLONGS\n")}),
    C("at2-npts-line", "rec.at2", "line 4", "expected 'NPTS=..., DT=...'", edit=use_at2,
      files={"rec.at2": at2(header4="4 POINTS AT 0.01 S")}),
    C("at2-npts-mismatch", "rec.at2", "NPTS = 5", "4 sample(s)", edit=use_at2,
      files={"rec.at2": at2(header4="NPTS=    5, DT=   .0100 SEC")}),
    C("at2-dt-zero", "rec.at2", "line 4", "DT: expected a number in (0, 10] s", edit=use_at2,
      files={"rec.at2": at2(header4="NPTS=    4, DT=   0.0 SEC")}),
    C("at2-dt-huge", "rec.at2", "line 4", "DT: expected a number in (0, 10] s", edit=use_at2,
      files={"rec.at2": at2(header4="NPTS=    4, DT=   1e999 SEC")}),
    C("at2-too-short", "rec.at2", "needs 4 header lines", edit=use_at2,
      files={"rec.at2": "PEER\nTEST\n"}),
    C("at2-other-units", "rec.at2", "line 3 states the units g", "units 'cm/s2' were given",
      edit=sub('file = "rec.csv"\nunits = "g"', 'file = "rec.at2"\nunits = "cm/s2"')),
    C("csv-nan", "rec.csv", "line 3", "'nan'", files={"rec.csv": "t,a\n0,0\n0.01,nan\n"}),
    C("csv-1e400", "rec.csv", "line 3", "'1e400'", "expected a finite number",
      files={"rec.csv": "t,a\n0,0\n0.01,1e400\n"}),
    C("csv-times-decrease", "rec.csv", "line 4", "times must increase",
      files={"rec.csv": "t,a\n0,0\n0.02,0.1\n0.01,0\n"}),
    C("csv-three-columns", "rec.csv", "line 3", "expected 2 columns",
      files={"rec.csv": "t,a\n0,0\n0.01,0.1,0.2\n"}),
    C("csv-text-in-data", "rec.csv", "line 3", "non-numeric text",
      files={"rec.csv": "t,a\n0,0\n0.01,zero\n"}),
    C("csv-header-only", "rec.csv", "no numeric data", files={"rec.csv": "time,acc\n"}),
    C("csv-empty", "rec.csv", "no numeric data", files={"rec.csv": ""}),
    C("csv-binary", "rec.csv", "not a text file", files={"rec.csv": b"\x00\xff\xfe" * 20}),
    C("csv-single-sample", "rec.csv", "needs at least 2 samples, got 1",
      files={"rec.csv": "t,a\n0,0.1\n"}),
    C("csv-overflow-scaled", "rec.csv", "overflows", edit=into("[[ground_motion]]", "scale = 1e10"),
      files={"rec.csv": "t,a\n0,0\n0.01,1e300\n"}),
    # -- [analysis] ------------------------------------------------------------------------
    C("dt-zero", M, "analysis.dt: "
      "expected a number in (0, 10] s, found 0.0", edit=sub("dt = 0.01", "dt = 0.0")),
    C("dt-above-10", M, "analysis.dt: "
      "expected a number in (0, 10] s, found 11.0", edit=sub("dt = 0.01", "dt = 11.0")),
    C("dt-1e400", M, "analysis.dt: expected a finite number, found inf",
      edit=sub("dt = 0.01", "dt = 1e400")),
    C("dt-string", M, "analysis.dt: expected a number, found a string",
      edit=sub("dt = 0.01", 'dt = "0.01 s"')),
    C("duration-negative", M, "analysis.duration: expected a number > 0",
      edit=sub("duration = 0.03", "duration = -1.0")),
    C("duration-1e400", M, "analysis.duration: expected a finite number",
      edit=sub("duration = 0.03", "duration = 1e400")),
    C("duration-too-many-steps", M, "analysis.duration", "too many",
      edit=sub("duration = 0.03", "duration = 1e12")),
    C("scheme-unknown", M, "analysis.scheme: expected one of 'nonsmooth-alpha'",
      edit=into("[analysis]", 'scheme = "wilson"')),
    C("theta-below-half", M, "analysis.theta: expected a number in [0.5, 1]",
      edit=into("[analysis]", 'scheme = "moreau-jean"\ntheta = 0.4')),
    C("alpha-below-third", M, "analysis.alpha: expected a number in [-1/3, 0]",
      edit=into("[analysis]", "alpha = -0.5")),
    C("newmark-with-interfaces", M, "analysis.scheme: scheme = 'newmark' (implied by alpha)",
      "runs models without interfaces", "expected scheme = 'nonsmooth-alpha'",
      edit=into("[analysis]", "alpha = -0.1")),
    C("rho-inf-above-1", M, "analysis.rho_inf: expected a number in [0, 1]",
      edit=into("[analysis]", "rho_inf = 2.0")),
    C(
        "rho-inf-without-beta",
        M,
        "analysis.rho_inf: rho_inf = 0.5 with interfaces needs",
        "expected rho_inf = 0, or add damping",
        edit=lambda t: into("[analysis]", "rho_inf = 0.5")(
            t.replace("ratio = 0.05\nfrequencies = [1.0, 10.0]", "alpha = 0.1")
        ),
    ),
    C("tolerance-too-large", M, "analysis.tolerance: expected a number in (0, 0.01]",
      edit=into("[analysis]", "tolerance = 0.1")),
    C("backend-unknown", M, "analysis.backend: expected one of 'auto', 'cholmod', 'superlu'",
      edit=into("[analysis]", 'backend = "mkl"')),
    C("static-integer", M, "analysis.static: expected a boolean, found an integer 1",
      edit=into("[analysis]", "static = 1")),
    C("nothing-to-run", M, "analysis.dynamic", "nothing to run",
      edit=into("[analysis]", "static = false\ndynamic = false")),
    C("form-unknown", M, "analysis.form: expected one of 'relative', 'absolute'",
      edit=into("[analysis]", 'form = "moving"')),
    C(
        "no-record-no-duration",
        M,
        "analysis.duration: missing (required without ground_motion)",
        edit=lambda t: drop(
            '[[ground_motion]]\nfile = "rec.csv"\nunits = "g"\n', "duration = 0.03\n"
        )(t),
    ),
    C("analysis-unknown-key", M, "analysis.dtt: unknown key", edit=into("[analysis]", "dtt = 0.1")),
    C("analysis-stabilize-removed", M, "analysis: stabilize was removed", "delete the key",
      edit=into("[analysis]", "stabilize = true")),
    # -- [damping] -------------------------------------------------------------------------
    C("damping-ratio-no-frequencies", M, "damping.frequencies: missing (required with ratio)",
      edit=drop("frequencies = [1.0, 10.0]\n")),
    C("damping-ratio-and-alpha", M,
      "damping: give either ratio and frequencies or alpha and beta, not both",
      edit=into("[damping]", "alpha = 0.1")),
    C("damping-one-frequency", M, "damping.frequencies: expected an array of 2 numbers",
      edit=sub("frequencies = [1.0, 10.0]", "frequencies = [1.0]")),
    C("damping-equal-frequencies", M,
      "damping.frequencies: expected two distinct frequencies in (0, 1e+04] Hz, found [5.0, 5.0]",
      edit=sub("frequencies = [1.0, 10.0]", "frequencies = [5.0, 5.0]")),
    C("damping-negative-ratio", M, "damping.ratio: expected a number in [0, 1]",
      edit=sub("ratio = 0.05", "ratio = -0.05")),
    C("damping-unknown-key", M, "damping.zeta: unknown key", edit=into("[damping]", "zeta = 0.05")),
    # -- [output] --------------------------------------------------------------------------
    C("output-every-zero", M, "output.every: expected an integer > 0, found 0",
      edit=into("[output]", "every = 0")),
    C("output-every-float", M, "output.every: expected an integer, found a number 2.0",
      edit=into("[output]", "every = 2.0")),
    C("output-field-every-negative", M, "output.field_every: expected an integer > 0",
      edit=into("[output]", "field_every = -1")),
    C("output-paraview-string", M, "output.paraview: expected a boolean",
      edit=into("[output]", 'paraview = "yes"')),
    C("output-checkpoint-negative", M, "output.checkpoint_seconds: expected a number >= 0",
      edit=into("[output]", "checkpoint_seconds = -1.0")),
    C("output-unknown-key", M, "output.format: unknown key",
      edit=into("[output]", 'format = "vtk"')),
    C("output-folder-nul", M, "output.folder", "NUL", edit=sub('"out"', '"o\\u0000ut"')),
    C("probe-3-coordinates-2d", M, "output.probes.crest: expected 2 coordinates",
      edit=sub("[1.0, 2.0]", "[1.0, 2.0, 0.0]")),
    C("probe-far-away", M, "output.probes.crest", "lies", "from the nearest node",
      "expected a point of the model", edit=sub("[1.0, 2.0]", "[50.0, 2.0]")),
    C("probe-nan", M, "output.probes.crest: expected an array of 2 to 3 numbers, each finite",
      edit=sub("[1.0, 2.0]", "[1.0, nan]")),
    C("probe-string", M, "output.probes.crest: expected an array of 2 to 3 numbers",
      edit=sub("[1.0, 2.0]", '"crest"')),
    # -- output folders (pfeie run) ---------------------------------------------------------
    C("output-folder-is-a-file", M, "output.folder", "afile", "is a file, not a folder",
      edit=sub('"out"', '"afile"'), argv=("run", M, "--quiet"), prepare=_results_like),
    C("output-folder-cannot-be-made", M, "output.folder", "afile/sub",
      "cannot create the output folder", edit=sub('"out"', '"afile/sub"'),
      argv=("run", M, "--quiet"), prepare=_results_like),
    C("output-folder-locked", "another pfeie run", f"pid {os.getpid()}", "other.toml",
      argv=("run", M, "--quiet"), prepare=_live_lock),
    # -- meshes ----------------------------------------------------------------------------
    C("msh-not-gmsh", "plate.msh", "cannot read the gmsh file", "2.2 or 4.1",
      files={"plate.msh": "time,acc\n0,0\n"}),
    C("msh-binary-garbage", "plate.msh", "cannot read the gmsh file",
      files={"plate.msh": b"\x00\xff" * 50}),
    C("msh-truncated", "plate.msh", "cannot read the gmsh file",
      files={"plate.msh": "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0\n"}),
    C("msh-empty", "plate.msh", "cannot read the gmsh file", files={"plate.msh": ""}),
    C("msh-no-physical-names", "plate.msh", "no named physical groups",
      files={"plate.msh": mesh_of(names={})}),
    C("msh-lines-only", "plate.msh", "no 2D or 3D cells",
      files={"plate.msh": mesh_of(elements=ELEMENTS[:7])}),
    C("msh-bow-tie", "plate.msh", "inverted or self-intersecting", "gmsh element 23",
      files={"plate.msh": mesh_of(elements=elements_with(23, (23, 3, 2, [5, 6, 8, 9])))}),
    C(
        "msh-degenerate-triangle",
        "plate.msh",
        "degenerate triangle",
        "gmsh element 25",
        files={
            "plate.msh": mesh_of(
                elements=[
                    *elements_with(23, (23, 2, 2, [5, 6, 9])),
                    (24, 2, 2, [5, 9, 8]),
                    (25, 2, 2, [4, 5, 6]),
                ]
            )
        },
    ),
    C("msh-duplicated-cell", "plate.msh", "duplicated", "gmsh element 23 and gmsh element 24",
      files={"plate.msh": mesh_of(elements=[*ELEMENTS, (24, 3, 2, [5, 6, 9, 8])])}),
    C("msh-x-z-plane", "plate.msh", "x-y plane", "expected z = 0",
      files={"plate.msh": mesh_of(nodes=[(x, 0.0, y) for x, y, _ in NODES])}),
    C("msh-missing-node", "plate.msh", "cannot read the gmsh file", "refers to node 99",
      files={"plate.msh": mesh_of(elements=elements_with(23, (23, 3, 2, [5, 6, 99, 8])))}),
    C("msh-non-finite-coordinate", "plate.msh", "non-finite",
      files={"plate.msh": mesh_of(nodes=[*NODES[:8], (2.0, 1e400, 0.0)])}),
    # physical tags are numbered per dimension: the surface 'dam' and a curve 'dam' are
    # two groups of one name (the surface was renamed 'physical_2' before)
    C("msh-name-in-two-dimensions", "plate.msh", "names used for groups of two dimensions: "
      "['dam']", files={"plate.msh": mesh_of(names={**NAMES, 6: (1, "dam")})}),
    C(
        # a cell in two physical groups (MSH 2 writes it once per group) is one cell in
        # both: refused where both groups are blocks
        "msh-cells-in-two-blocks",
        "model.toml",
        "'rock' (block 'rock') and 'dam' (block 'dam') share 1 quad cell(s): gmsh element 23",
        "expected each cell in one block group",
        files={
            "plate.msh": mesh_of(
                elements=[*ELEMENTS[:-1], (23, 3, 1, [5, 6, 9, 8]), (24, 3, 2, [5, 6, 9, 8])]
            )
        },
    ),
    C(
        "msh-3d-with-plane",
        M,
        "plane",
        "3D",
        "remove plane",
        edit=lambda t: (
            'plane = "stress"\n'
            + t.replace('[[loads.uplift]]\ninterface = "joint"\nheadwater = 1.8\n', "")
        ),
        files={
            "plate.msh": mesh_of(
                nodes=[(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)],
                names={2: (3, "dam"), 3: (2, "bottom")},
                elements=[(1, 2, 3, [1, 2, 3]), (2, 4, 2, [1, 2, 3, 4])],
            )
        },
    ),
    # -- the command line ------------------------------------------------------------------
    C("cli-duration-negative", "analysis.duration (from --duration -1)", "expected a number > 0",
      argv=("check", M, "--duration", "-1")),
    C("cli-duration-nan", "--duration nan", "expected a finite number",
      argv=("check", M, "--duration", "nan")),
    C("cli-duration-word", "--duration long", "expected a number, found a string 'long'",
      argv=("run", M, "--duration", "long")),
    C("cli-dt-zero", "analysis.dt (from --dt 0)", "expected a number in (0, 10] s",
      argv=("run", M, "--dt", "0")),
    C("cli-set-no-value", "--set analysis.alpha", "expected KEY=VALUE",
      argv=("check", M, "--set", "analysis.alpha")),
    C("cli-set-bad-key", "--set", "expected KEY=VALUE", argv=("check", M, "--set", "a..b=1")),
    C("cli-set-unknown-key", "analysis.alpa (from --set analysis.alpa=-0.1)", "unknown key",
      argv=("check", M, "--set", "analysis.alpa=-0.1")),
    C("cli-set-no-item", "ground_motion[3].scale", "no item 3 (the file has 1)",
      argv=("check", M, "--set", "ground_motion[3].scale=2")),
    C("cli-set-not-a-table", "title.x", "not a table", argv=("check", M, "--set", "title.x=1")),
    C("cli-modal-zero-modes", "--modes: expected a number of modes >= 1",
      argv=("modal", M, "-n", "0")),
    C("cli-modal-modes-word", "--modes", "invalid int value", argv=("modal", M, "-n", "ten")),
    C("cli-modal-interfaces-unknown", "--interfaces", "invalid choice: 'glued'",
      argv=("modal", M, "--interfaces", "glued")),
    C("cli-unknown-command", "argument COMMAND: invalid choice: 'frobnicate'",
      argv=("frobnicate",)),
    C("cli-no-command", "expected a command", argv=()),
    C(
        "msh-facets-off-the-cells",
        "plate.msh",
        "physical group 'crest'",
        "facets refer to nodes that no cell uses",
        "expected facets on the faces of the cells",
        files={
            "plate.msh": mesh_of(
                nodes=[*NODES, (5.0, 5.0, 0.0)],
                elements=[*ELEMENTS[:6], (7, 1, 6, [8, 10]), *ELEMENTS[7:]],
            )
        },
    ),
    C("theta-with-interfaces", M, "analysis.theta: expected a number in [0.55, 1] with interfaces",
      edit=into("[analysis]", 'scheme = "moreau-jean"\ntheta = 0.5')),
    C("cli-run-without-model", "run", "the following arguments are required: model", argv=("run",)),
    C("cli-unknown-option", "unrecognized arguments: --fast", argv=("run", M, "--fast")),
    C("cli-export-without-csv", "export", "the following arguments are required: --csv",
      argv=("export", R)),
    C("cli-spectrum-damping-1", "--damping: expected a number in [0, 1), found '1'",
      argv=("spectrum", "rec.csv", "--units", "g", "--damping", "1")),
    C("cli-spectrum-periods", "--periods: expected START:STOP:N", "found '4:0.02:200'",
      argv=("spectrum", "rec.csv", "--units", "g", "--periods", "4:0.02:200")),
    C("cli-spectrum-t1-negative", "--t1: expected a number in (0, inf), found '-1'",
      argv=("spectrum", "rec.csv", "--units", "g", "--t1", "-1")),
    C("cli-spectrum-no-units", "rec.csv", "give the units", argv=("spectrum", "rec.csv")),
    C("cli-spectrum-units-unknown", "--units", "invalid choice: 'furlong'",
      argv=("spectrum", "rec.csv", "--units", "furlong")),
    C("cli-spectrum-record-missing", "none.csv", "record file not found",
      argv=("spectrum", "none.csv", "--units", "g")),
    C("cli-spectrum-dt-zero", "--dt: expected a number in (0, inf), found '0'",
      argv=("spectrum", "rec.txt", "--units", "g", "--dt", "0"),
      files={"rec.txt": "0.0\n0.1\n0.0\n"}),
    C("cli-spectrum-out-is-a-file", "afile", "not a folder",
      argv=("spectrum", "rec.csv", "--units", "g", "--out", "afile"), prepare=_results_like),
    C("cli-schema-out-no-folder", "no/such/schema.json", "No such file",
      argv=("schema", "-o", "no/such/schema.json")),
    C("cli-study-workers-word", "--workers: expected a whole number in [0, 4096], found 'two'",
      argv=("study", "study.toml", "--workers", "two")),
    # -- results files (plot, report, export) -----------------------------------------------
    C("report-not-hdf5", "text.h5", "not an HDF5 file", argv=("report", "text.h5"),
      prepare=_results_like),
    C("report-other-hdf5", "other.h5", "not a pfeie results file", "written by `pfeie run`",
      argv=("report", "other.h5"), prepare=_results_like),
    C("plot-results-missing", "none.h5", "not found", argv=("plot", "none.h5")),
    C("export-other-hdf5", "other.h5", "not a pfeie results file",
      argv=("export", "other.h5", "--csv", "csv"), prepare=_results_like),
    C("plot-not-hdf5", "text.h5", "not an HDF5 file", argv=("plot", "text.h5"),
      prepare=_results_like),
    # -- study files (pfeie study) -----------------------------------------------------------
    C("study-missing", "none.toml", "study file not found", argv=("study", "none.toml")),
    C("study-not-toml", "study.toml", "not valid TOML", argv=("study", "study.toml"),
      files={"study.toml": "model = \n"}),
    C("study-unknown-key", "study.toml", "colour: unknown key", argv=("study", "study.toml"),
      files={"study.toml": STUDY.replace('title = "study"', 'title = "study"\ncolour = 1')}),
    C("study-model-missing-key", "study.toml", "model: missing (required)",
      argv=("study", "study.toml"),
      files={"study.toml": STUDY.replace('model = "model.toml"\n', "")}),
    C("study-file-and-folder", "study.toml", "records[0].file: give either file or folder",
      argv=("study", "study.toml"),
      files={"study.toml": STUDY.replace('file = "rec.csv"', 'file = "rec.csv"\nfolder = "."')}),
    C("study-no-match", "study.toml", "records[0]", "no file", "'*.AT9'",
      argv=("study", "study.toml"),
      files={"study.toml": STUDY.replace('file = "rec.csv"', 'folder = "."\npattern = "*.AT9"')}),
    C("study-values-negative", "study.toml", "intensity.values", "expected", "> 0",
      argv=("study", "study.toml"),
      files={"study.toml": STUDY.replace("[0.1, 0.2]", "[0.1, -0.2]")}),
    C("study-measure-unknown", "study.toml", "intensity.measure: expected one of 'scale', 'pga'",
      argv=("study", "study.toml"), files={"study.toml": STUDY.replace('"pga"', '"pgv"')}),
    C("study-model-not-found", "nomodel.toml", "model file not found", argv=("study", "study.toml"),
      files={"study.toml": STUDY.replace('"model.toml"', '"nomodel.toml"')}),
    C("study-model-invalid", M, "materials.rock.E: expected a finite number",
      argv=("study", "study.toml"), edit=sub("E = 1e9", "E = inf")),
    C("study-set-unknown-key", M, "analysis.dtt", "unknown key", argv=("study", "study.toml"),
      files={"study.toml": STUDY + '[analysis]\nset = ["analysis.dtt=0.1"]\n'}),
    C("study-workers-negative", "study.toml", "run.workers: expected an integer in [0, 4096]",
      argv=("study", "study.toml"), files={"study.toml": STUDY + "[run]\nworkers = -1\n"}),
    C("study-limit-state-no-demand", "study.toml", "limit_states[0].demand: missing (required)",
      argv=("study", "study.toml"),
      files={"study.toml": STUDY + '[[limit_states]]\nname = "x"\nthreshold = 0.001\n'}),
    C("study-record-units-missing", "rec.csv", "give the units", argv=("study", "study.toml"),
      files={"study.toml": STUDY.replace('units = "g"\n', "")}),
    C("study-values-twice", "study.toml", "intensity.values[1]", "is already intensity.values[0]",
      argv=("study", "study.toml"),
      files={"study.toml": STUDY.replace("[0.1, 0.2]", "[0.1, 0.1]")}),
    C("study-pga-too-large", "study.toml", "intensity.values[1]: expected a number in (0, 20] g",
      "found 500", argv=("study", "study.toml"),
      files={"study.toml": STUDY.replace("[0.1, 0.2]", "[0.1, 500]")}),
    C("study-record-twice", "study.toml", "records[0].file", "records[1].folder", "rec.csv",
      argv=("study", "study.toml"),
      files={"study.toml": STUDY + '[[records]]\nfolder = "."\npattern = "*.csv"\nunits = "g"\n'}),
    C("study-output-folder-is-a-file", "study.toml", "output.folder", "is a file, not a folder",
      argv=("study", "study.toml"), prepare=_results_like,
      files={"study.toml": STUDY.replace('folder = "study"', 'folder = "afile"')}),
    C("study-limit-state-threshold-negative", "study.toml", "limit_states[0].threshold",
      "expected a number > 0", argv=("study", "study.toml"),
      files={"study.toml": STUDY + '[[limit_states]]\nname = "x"\n'
             'demand = "joint.joint.max_opening_m"\nthreshold = -1\n'}),
    C("study-limit-state-demand-misspelt", "study.toml", "limit_states[0].demand",
      "'joint.jiont.max_opening_m'", "did you mean 'joint.joint.max_opening_m'",
      argv=("study", "study.toml"),
      files={"study.toml": STUDY + '[[limit_states]]\nname = "x"\n'
             'demand = "joint.jiont.max_opening_m"\nthreshold = 0.001\n'}),
    # -- ground_motion[].filter -------------------------------------------------------------
    C("record-filter-above-nyquist", M, "ground_motion[0].filter.lowpass",
      "expected a corner frequency in (0, 50) Hz", "Nyquist", "found 60.0",
      edit=into("[[ground_motion]]", "filter = {lowpass = 60.0}")),
    C("record-filter-highpass-above-nyquist", M, "ground_motion[0].filter.highpass",
      "expected a corner frequency in (0, 50) Hz",
      edit=into("[[ground_motion]]", "filter = {highpass = 60.0}")),
    C("record-filter-corners-swapped", M, "ground_motion[0].filter.lowpass",
      "expected a corner above highpass = 5 Hz", "found 2 Hz",
      edit=into("[[ground_motion]]", "filter = {highpass = 5.0, lowpass = 2.0}")),
    C("record-filter-order-9", M, "ground_motion[0].filter.order",
      "expected an integer from 1 to 8, found 9",
      edit=into("[[ground_motion]]", "filter = {lowpass = 5.0, order = 9}")),
    C("record-filter-highpass-negative", M, "ground_motion[0].filter.highpass",
      "expected a number > 0 Hz, found -0.1",
      edit=into("[[ground_motion]]", "filter = {highpass = -0.1}")),
    C("record-filter-no-corner", M, "ground_motion[0].filter", "expected highpass or lowpass",
      edit=into("[[ground_motion]]", "filter = {order = 4}")),
    C("record-filter-unknown-key", M, "ground_motion[0].filter.bandpass: unknown key",
      edit=into("[[ground_motion]]", "filter = {bandpass = 1.0}")),
    C("record-filter-uneven-times", M, "ground_motion[0].filter", "not equally spaced",
      edit=into("[[ground_motion]]", "filter = {lowpass = 5.0}"),
      files={"rec.csv": "t,a\n0,0\n0.01,0.1\n0.03,0\n"}),
]
# fmt: on


def test_at_least_a_hundred_named_cases() -> None:
    ids = [c.id for c in CASES]
    assert len(ids) == len(set(ids)), "case ids are unique"
    assert len(ids) >= 100


def _prepare(folder: Path, case: Case | None = None) -> None:
    setup(folder)
    if case is None:
        return
    if case.edit is not None:
        (folder / M).write_text(case.edit(MODEL))
    for name, content in case.files.items():
        target = folder / name
        if isinstance(content, bytes):
            target.write_bytes(content)
        else:
            target.write_text(content)
    if case.prepare is not None:
        case.prepare(folder)


def test_the_base_setup_is_valid(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                 capsys: pytest.CaptureFixture[str]) -> None:  # fmt: skip
    """The setup that the cases mutate passes `pfeie check` (and its study file loads):
    each case's error is its own mutation's."""
    from pfeie.study import Study

    monkeypatch.chdir(tmp_path)
    _prepare(tmp_path)
    assert main(["check", M]) == 0, capsys.readouterr().err
    assert len(Study.from_file("study.toml").runs()) == 2


@pytest.mark.parametrize("case", CASES, ids=[c.id for c in CASES])
def test_wrong_input(case: Case, tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                     capsys: pytest.CaptureFixture[str]) -> None:  # fmt: skip
    monkeypatch.chdir(tmp_path)
    _prepare(tmp_path, case)
    code = main(list(case.argv))
    err = capsys.readouterr().err
    assert code == 2, (code, err)
    assert "Traceback" not in err, err
    lines = [ln for ln in err.splitlines() if ln.startswith("pfeie: error: ")]
    assert len(lines) == 1, err
    missing = [w for w in case.words if w not in lines[0]]
    assert not missing, (missing, lines[0])
