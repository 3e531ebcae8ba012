"""The HTML report (`pfeie report`): every item an engineer attaches to a review, each in
its section, checked on a run of the Pine Flat mesh with the loads a dam evaluation
needs (gravity, hydrostatic pressure, silt, the finite-element reservoir's added mass,
uplift with drains), two joints and a short record, run with ``--set`` overrides: the
geometry and mesh, the materials and joint laws, the loads (table and figure), the static
state (joint states, safety factors, principal stresses), the input motion and its
spectrum, the modal table (with and without the added mass), the analysis (Δt, solver
statistics), the histories, the joints' results and maps, the stress envelope and the
EM 1110-2-6053 evaluation; the page is self-contained. Without its model file the page
keeps every section and says what is missing and why.

The report of a 3D model (two stacked Hex8 blocks with a joint, a few steps) holds every
figure in 3D: the mesh's boundary faces, the loads, the static stresses and the envelope
painted on them, each joint in its plane; their numbers are checked against closed forms
(face and pair counts, the hydrostatic pressure) and the results file's envelope."""

from __future__ import annotations

import json
import re
import shutil
from pathlib import Path

import numpy as np
import pytest

from pfeie.cli import main
from pfeie.io import Override, Results, load_job

MESH = Path(__file__).resolve().parents[1] / "examples" / "pine_flat" / "pine_flat.msh"
H = 116.12  # the water level (m)
HS = 17.79507242  # the silt level (m): a corner node of the face (no kink inside a facet)

MODEL = f"""
title = "report test"
plane = "stress"
[mesh]
file = "{MESH.as_posix()}"
[materials.concrete]
E = 22.41e9
nu = 0.2
rho = 2483.0
tensile_strength = 1.5e6
[materials.rock]
E = 22.41e9
nu = 0.33
rho = 25.0
[blocks]
dam_lower = "concrete"
dam_upper = "concrete"
rock = "rock"
[damping]
ratio = 0.05
frequencies = [2.0, 10.0]
[interfaces.dam_rock]
cohesion = 2.0e6
tensile_strength = 1.0e6
friction_angle = 55.0
initial = "intact"
normal_stiffness = 1.0e11
shear_stiffness = 1.0e11
[interfaces.lift]
cohesion = 1.4e6
tensile_strength = 0.7e6
friction_angle = 55.0
initial = "intact"
normal_stiffness = 1.0e11
shear_stiffness = 1.0e11
[[supports]]
group = "rock_bottom"
[loads]
gravity = 9.81
[[loads.hydrostatic]]
groups = ["upstream", "reservoir_floor"]
water_level = {H}
[[loads.silt]]
groups = ["upstream", "reservoir_floor"]
level = {HS}
submerged_unit_weight = 9000.0
friction_angle = 30.0
[[loads.westergaard]]
groups = ["upstream"]
water_level = {H}
model = "fe"
[[loads.uplift]]
interface = "dam_rock"
headwater = {H}
drains = 12.01629
drain_efficiency = 0.5
[[ground_motion]]
file = "pulse.csv"
units = "g"
[analysis]
dt = 0.005
duration = 0.2
[output]
folder = "out"
probes = {{ crest = [1.9812, 121.92] }}
"""
#: the run's overrides: the time step (not the model) and a modulus (the model)
SETS = ["analysis.dt=0.01", "materials.concrete.E=20e9"]


def sections(page: str) -> dict[str, str]:
    """The page cut at its <h2> headings: heading → the HTML up to the next one."""
    parts = re.split(r"<h2>(.*?)</h2>", page)
    return {parts[i]: parts[i + 1] for i in range(1, len(parts) - 1, 2)}


def images(text: str) -> list[str]:
    return re.findall(r"<img alt='([^']+)' src='data:image/png;base64,", text)


def cell(text: str, row: str, column: str) -> str:
    """The cell of a table in ``text`` at the row whose first cell is ``row``."""
    head = re.search(r"<table><tr>(.*?)</tr>", text, re.S)
    assert head is not None
    cols = re.findall(r"<th>(.*?)</th>", head.group(1))
    for tr in re.findall(r"<tr>(<td>.*?)</tr>", text):
        cells = re.findall(r"<td>(.*?)</td>", tr)
        if cells[0] == row:
            return cells[cols.index(column)]
    raise AssertionError(f"no row {row!r}")


@pytest.fixture(scope="module")
def run(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, str]:
    """The model run once with its overrides, and its report."""
    tmp = tmp_path_factory.mktemp("report")
    t = np.arange(0.0, 0.2 + 1e-9, 0.01)
    np.savetxt(tmp / "pulse.csv", np.c_[t, 0.3 * np.sin(2 * np.pi * t / 0.2)], delimiter=",",
               header="time,acc", comments="")  # fmt: skip
    (tmp / "model.toml").write_text(MODEL)
    args = [a for s in SETS for a in ("--set", s)]
    assert main(["run", str(tmp / "model.toml"), "--quiet", *args]) == 0
    assert main(["report", str(tmp / "out" / "results.h5")]) == 0
    return tmp, (tmp / "out" / "report.html").read_text()


def test_every_section_of_the_report(run: tuple[Path, str]) -> None:
    """Each section by its heading, with a content item checked against an independent
    value where there is one."""
    tmp, page = run
    s = sections(page)
    assert list(s) == [
        "Geometry and mesh", "Materials", "Loads", "Static state (before the shaking)",
        "Input motion", "Modal analysis", "Analysis", "Histories", "Joints", "Joint maps",
        "Stress envelope", "Demand-capacity ratio and cumulative inelastic duration",
    ]  # fmt: skip
    job = load_job(tmp / "model.toml", [Override("materials.concrete.E", 20e9, "test")])
    model = job.model
    # geometry and mesh: the DOF and the mesh figure
    assert f"{model.n_dof} (" in s["Geometry and mesh"]
    assert images(s["Geometry and mesh"]) == ["mesh"]
    assert "plane stress" in s["Geometry and mesh"]
    # materials: the run's modulus (its override), the tensile strength; the joint laws
    m = s["Materials"]
    assert cell(m, "concrete", "E (GPa)") == "20" and cell(m, "rock", "E (GPa)") == "22.41"
    assert cell(m, "concrete", "tensile strength f_t (MPa)") == "1.5"
    assert cell(m.split("<h3>Joints</h3>")[1], "dam_rock", "k_n (Pa/m)") == "1e+11"
    # loads: the hydrostatic load with its water level and its horizontal thrust on the
    # dam, ρ_w g H²/2 (the floor's pressure is vertical); the silt with K0 = 1 − sin 30°;
    # the uplift; the added mass; the figure
    lo = s["Loads"]
    assert f"water level {H:g} m" in cell(lo, "hydrostatic", "parameters")
    assert cell(lo, "hydrostatic", "F_x (kN)") == f"{1e-3 * 1000 * 9.81 * H**2 / 2:.4g}"
    assert "K0 = 1 − sin 30° = 0.5" in cell(lo, "silt", "parameters")
    assert cell(lo, "silt", "F_x (kN)") == f"{1e-3 * 0.5 * 9000 * HS**2 / 2:.4g}"
    assert "drains 12.0163 m" in cell(lo, "uplift", "parameters")
    with Results(tmp / "out" / "results.h5") as res:
        U = float((np.asarray(res.f["static/uplift"]) * np.asarray(res.f["pairs/area"])).sum())
        dt = float(res.meta["analysis"]["dt"])
        fs0 = float(res.f["history/joints/safety_factor"][0, 0])
    assert cell(lo, "uplift", "F_y (kN)") == f"{1e-3 * U:.4g}"  # a horizontal joint
    assert "finite-element reservoir" in cell(lo, "reservoir added mass", "parameters")
    assert images(lo) == ["loads"]
    # the static state: the joint states, the safety factor, the uplift; the stresses
    st = s["Static state (before the shaking)"]
    assert cell(st, "dam_rock", "sliding safety factor") == f"{fs0:.4g}"
    assert cell(st, "dam_rock", "uplift force (kN)") == f"{1e-3 * U:.4g}"
    assert images(st) == ["static_stress", "static_dam_rock", "static_lift"]
    # the input motion and its spectrum
    assert "<td>0.3</td>" in s["Input motion"] and images(s["Input motion"]) == ["input_motion"]
    # the modal table: pf.modal's frequencies with and without the added mass (the joints
    # bonded), to the printed digits
    import copy

    import pfeie as pf

    md = s["Modal analysis"]
    wet = pf.modal(model, 6).frequencies
    dry_model = copy.copy(model)
    dry_model.reservoirs, dry_model.fe_reservoirs = [], []
    dry = pf.modal(dry_model, 6).frequencies
    tables = md.split("<h3>")[1:]
    assert "With the reservoir" in tables[0] and "Without the added mass" in tables[1]
    assert cell(tables[0], "1", "f (Hz)") == f"{wet[0]:.4f}"
    assert cell(tables[1], "1", "f (Hz)") == f"{dry[0]:.4f}"
    assert cell(tables[1], "6", "f (Hz)") == f"{dry[5]:.4f}"
    assert wet[0] < dry[0]
    # the analysis: the Δt as run (its override), the solver's statistics
    an = s["Analysis"]
    assert dt == 0.01 and f"<tr><th>time step Δt</th><td>{dt} s</td></tr>" in an
    assert "iterations a step" in an and "steps</th><td>20 to t = 0.200 s" in an
    # the histories, the joints, the maps, the envelope, the evaluation
    assert {"probe_crest", "joint_dam_rock", "joint_lift", "rigid_motion", "energy"} <= set(
        images(s["Histories"]))  # fmt: skip
    assert "min safety factor" in s["Joints"]
    # the report's open crack and static open share are the summary's (the broken pairs
    # open by more than 0.01 mm; a rock slope's report said 9.3 m against 8.72 m)
    summ = json.loads((tmp / "out" / "summary.json").read_text())
    for name in ("dam_rock", "lift"):
        crack = summ["joints"][name]["max_open_length_m"]
        assert cell(s["Joints"], name, "largest open crack (m)") == f"{crack:.4g}"
        share = 100 * summ["static_joints"][name]["open_share"]
        assert cell(st, name, "open (%)") == f"{share:.4g}"
    assert images(s["Joint maps"]) == ["joint_map", "states_dam_rock", "states_lift"]
    env = s["Stress envelope"]
    assert "largest principal stress σ1" in env and images(env) == ["envelope"]
    assert "EM 1110-2-6053" in s["Demand-capacity ratio and cumulative inelastic duration"]
    # self-contained: every image inlined, no other resource
    assert page.count("<img ") == len(images(page)) == 15
    assert not re.search(r"(src|href)='(?!data:|#)", page)


def test_report_without_the_model_file(run: tuple[Path, str], tmp_path: Path) -> None:
    """The results file alone (its model file gone): every section is there; those that
    need the model say so, the others keep their content."""
    tmp, _ = run
    shutil.copy(tmp / "out" / "results.h5", tmp_path / "results.h5")
    (tmp / "model.toml").rename(tmp / "moved.toml")
    try:
        assert main(["report", str(tmp_path / "results.h5")]) == 0
    finally:
        (tmp / "moved.toml").rename(tmp / "model.toml")
    s = sections((tmp_path / "report.html").read_text())
    assert len(s) == 12
    for name in ("Materials", "Loads", "Modal analysis"):
        assert "not available: the model file" in s[name], name
    assert "Elastic(E=20000000000.0" in s["Materials"]  # the recorded summary
    assert images(s["Joint maps"])[0] == "joint_map" and "time step Δt" in s["Analysis"]


def test_settings_added_by_a_later_version_do_not_stop_the_rebuild() -> None:
    """A run recorded before a setting existed (here ``damping.deformation_only``, whose
    default is false) rebuilds its model: only real changes count, named by their keys."""
    from pfeie.plot._report import _differs

    old = {"ratio": 0.05, "frequencies": [2.5, 15.0]}
    new = {**old, "deformation_only": False}
    assert _differs(new, old, "damping") == []
    assert _differs({**new, "deformation_only": True}, old, "damping") == [
        "damping.deformation_only"]  # fmt: skip
    assert _differs({**new, "frequencies": [2.5, 16.0]}, old, "damping") == [
        "damping.frequencies[1]"]  # fmt: skip


# -- a 3D model: every section holds its figure, drawn in 3D ---------------------------------
#: two stacked blocks of Hex8 cells (a rock block and a dam block), NX × NY × NZ cells each
NX, NY, NZ = 4, 3, 2
LX, LY, LZ = 4.0, 3.0, 2.0
H3 = 3.5  # the water level on the dam block's upstream face x = 0 (m)

MODEL_3D = f"""
title = "3D report test"
[mesh]
file = "blocks.msh"
[materials.concrete]
E = 20e9
nu = 0.2
rho = 2400.0
tensile_strength = 1.5e6
[blocks]
rock = "concrete"
dam = "concrete"
[interfaces.joint]
cohesion = 0.0
friction_angle = 30.0
[[supports]]
group = "bottom"
[loads]
gravity = 9.81
[[loads.hydrostatic]]
groups = ["upstream"]
water_level = {H3}
[[ground_motion]]
file = "pulse.csv"
units = "g"
[analysis]
dt = 0.01
duration = 0.1
[output]
folder = "out"
probes = {{ crest = [0.0, 0.0, {2 * LZ}] }}
"""


def write_blocks_msh(path: Path) -> None:
    """Two stacked NX × NY × NZ blocks of Hex8 cells (gmsh MSH 2.2, conforming at z = LZ):
    physical volumes 'rock' (below) and 'dam' (above), surfaces 'bottom' (z = 0),
    'joint' (z = LZ) and 'upstream' (the dam's face x = 0)."""
    from pfeie.mesh import box

    m = box(LX, LY, 2 * LZ, NX, NY, 2 * NZ)
    x, hexa = m.points, m.cells["hexahedron"]
    lower = x[hexa].mean(axis=1)[:, 2] < LZ
    xmin = m.facet_groups["xmin"]["quad"]
    groups = [
        (2, "bottom", m.facet_groups["zmin"]["quad"]),
        (2, "joint", hexa[lower & (x[hexa[:, 4:], 2] == LZ).all(axis=1)][:, 4:]),
        (2, "upstream", xmin[x[xmin].mean(axis=1)[:, 2] > LZ]),
        (3, "rock", hexa[lower]), (3, "dam", hexa[~lower]),
    ]  # fmt: skip
    lines = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", str(len(groups))]
    lines += [f'{d} {t} "{name}"' for t, (d, name, _) in enumerate(groups, start=1)]
    lines += ["$EndPhysicalNames", "$Nodes", str(len(x))]
    lines += [f"{i} {a!r} {b!r} {c!r}" for i, (a, b, c) in enumerate(x.tolist(), start=1)]
    els = [(5 if d == 3 else 3, t, row) for t, (d, _, conn) in enumerate(groups, start=1)
           for row in (conn + 1).tolist()]  # fmt: skip
    lines += ["$EndNodes", "$Elements", str(len(els))]
    lines += [f"{k} {kind} 2 {t} {t} " + " ".join(map(str, row))
              for k, (kind, t, row) in enumerate(els, start=1)]  # fmt: skip
    path.write_text("\n".join([*lines, "$EndElements"]) + "\n")


def png(data: bytes) -> tuple[tuple[int, int], dict[str, str]]:
    """The pixel size and the text chunks of a PNG (refused if it is not a valid one)."""
    import io

    from PIL import Image

    with Image.open(io.BytesIO(data)) as im:
        assert im.format == "PNG"
        im.verify()
    with Image.open(io.BytesIO(data)) as im:
        im.load()
        return im.size, dict(im.text)


@pytest.fixture(scope="module")
def run3d(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, str]:
    """The 3D model run once (10 steps), and its report."""
    tmp = tmp_path_factory.mktemp("report3d")
    write_blocks_msh(tmp / "blocks.msh")
    t = np.arange(0.0, 0.2 + 1e-9, 0.01)
    np.savetxt(tmp / "pulse.csv", np.c_[t, 0.5 * np.sin(2 * np.pi * t / 0.2)], delimiter=",",
               header="time,acc", comments="")  # fmt: skip
    (tmp / "model.toml").write_text(MODEL_3D)
    assert main(["run", str(tmp / "model.toml"), "--quiet"]) == 0
    assert main(["report", str(tmp / "out" / "results.h5")]) == 0
    return tmp, (tmp / "out" / "report.html").read_text()


def test_report_of_a_3d_model(run3d: tuple[Path, str]) -> None:
    """Every section of the report of a 3D model holds its figure, each a valid PNG; the
    3D figures draw what they should: the mesh's boundary faces, 2 (nx ny + ny nz +
    nz nx) per block (each block its own, the joint's nodes split); the joint's pairs in
    the joint's plane, one per node of the joint, (nx + 1)(ny + 1), as the model has
    them, on the axes (x, y) of the horizontal joint; the envelope's extremes those of
    the results file; the largest face pressure ρ_w g (H − z) at the centroid of the
    lowest wet faces."""
    import base64

    from pfeie.dynamics import envelope_extremes

    tmp, page = run3d
    s = sections(page)
    assert len(s) == 12
    expect = {
        "Geometry and mesh": ["mesh"], "Loads": ["loads"],
        "Static state (before the shaking)": ["static_stress", "static_joint"],
        "Input motion": ["input_motion"], "Joint maps": ["joint_map", "states_joint"],
        "Stress envelope": ["envelope"],
    }  # fmt: skip
    for name, figs in expect.items():
        assert images(s[name]) == figs, name
    assert {"probe_crest", "joint_joint", "rigid_motion", "energy"} == set(images(s["Histories"]))
    assert "3D" in s["Geometry and mesh"] and "seen from upstream" in s["Geometry and mesh"]
    # the extent along each of the three axes
    assert all(f"{a} from" in s["Geometry and mesh"] for a in "xyz")
    data = {name: base64.b64decode(b64) for name, b64 in re.findall(
        r"<img alt='([^']+)' src='data:image/png;base64,([^']+)'", page)}  # fmt: skip
    assert len(data) == page.count("<img ") == 12
    meta = {}
    for name, raw in data.items():
        (w, h), text = png(raw)
        assert 500 <= w <= 2500 and 350 <= h <= 2500, (name, w, h)
        if "Description" in text:
            meta[name] = json.loads(text["Description"])
    assert set(meta) == {"mesh", "loads", "static_stress", "joint_map", "envelope"}
    # the mesh: boundary faces per block (closed form), the pairs and the probe drawn
    faces = 2 * 2 * (NX * NY + NY * NZ + NZ * NX)
    assert meta["mesh"] == {"boundary_faces": faces, "pairs": (NX + 1) * (NY + 1), "probes": 1,
                            "view": [25.0, -135.0]}  # fmt: skip
    # the joint map: the model's pairs of the joint, in the plane z = LZ (normal ±z, exact
    # for a plane joint: 1e-12), on the axes x and y
    model = load_job(tmp / "model.toml").model
    assert model.pairs is not None
    jm = meta["joint_map"]["joints"]["joint"]
    assert jm["pairs"] == model.pairs.of("joint").size == (NX + 1) * (NY + 1)
    assert np.allclose(np.abs(jm["normal"]), [0.0, 0.0, 1.0], rtol=0, atol=1e-12)
    assert jm["axes"] == ["x", "y"]
    # the envelope: the painted extremes and their nodes are the results file's (the
    # colour bar spans ± the largest |value| over the nodes): the same numbers, exactly
    # (JSON keeps a float); the positions to the 4 decimals envelope_extremes rounds to
    with Results(tmp / "out" / "results.h5") as res:
        env = res.envelope()
        ext = envelope_extremes(env, np.asarray(res.f["mesh/points"]))
    assert ext is not None
    hi, lo = meta["envelope"]["panels"]
    assert hi["extreme_MPa"] == 1e-6 * ext["max_principal_Pa"]
    assert lo["extreme_MPa"] == 1e-6 * ext["min_principal_Pa"]
    assert np.allclose(hi["at_m"], ext["max_principal_at_m"], rtol=0, atol=5e-5)
    assert np.allclose(lo["at_m"], ext["min_principal_at_m"], rtol=0, atol=5e-5)
    # the colours as the 2D maps': the boundary faces' means between their 0.5th and
    # 99.5th percentiles, symmetric about zero, or one-sided where the values keep one
    # sign to a twentieth of their range (σ₃ here: compression)
    from pfeie.plot._plots import _faces_of

    with Results(tmp / "out" / "results.h5") as res:
        faces = _faces_of(res)[1]
    for panel, key in ((hi, "node_max"), (lo, "node_min")):
        v = 1e-6 * env[key]
        mean = np.concatenate([v[f].mean(axis=1) for f in faces])
        p_lo, p_hi = np.percentile(mean[np.isfinite(mean)], [0.5, 99.5])
        c_lo, c_hi = panel["colour_range_MPa"]
        if p_lo >= -0.05 * abs(p_hi):
            assert (c_lo, c_hi) == (0.0, pytest.approx(p_hi, rel=1e-9))
        elif p_hi <= 0.05 * abs(p_lo):
            assert (c_lo, c_hi) == (pytest.approx(p_lo, rel=1e-9), 0.0)
        else:
            assert -c_lo == c_hi == pytest.approx(max(-p_lo, p_hi), rel=1e-9)
    assert lo["colour_range_MPa"][1] == 0.0  # σ₃: compression only, blue
    # the loads: the upstream faces of the dam (NY × NZ) loaded; the largest face pressure
    # at the centroid of the lowest ones, z = LZ + LZ / (2 NZ): ρ_w g (H − z) (reached
    # exactly here; 1e-15 for round-off)
    ld = meta["loads"]
    assert ld["loaded_faces"] == NY * NZ
    z = LZ + LZ / (2 * NZ)
    assert ld["largest_face_pressure_kPa"] == pytest.approx(1e-3 * 1000 * 9.81 * (H3 - z),
                                                            rel=1e-15)  # fmt: skip
    assert ld["supported_nodes"] == (NX + 1) * (NY + 1)


def test_plot_writes_the_3d_figures(run3d: tuple[Path, str], tmp_path: Path) -> None:
    """`pfeie plot` of a 3D run writes the 3D mesh, joint map and envelope beside the
    histories (the names of the module docstring of pfeie.plot._plots), and, as the
    report has them, the loads and the static stresses (the model file found beside the
    results) and the joint's static state; without the model file, all but the loads and
    the static stresses."""
    tmp, _ = run3d
    assert main(["plot", str(tmp / "out" / "results.h5"), "--out", str(tmp_path)]) == 0
    names = {p.name for p in tmp_path.iterdir()}
    common = {"mesh.png", "joint_map.png", "envelope.png", "input_motion.png",
              "probe_crest.png", "joint_joint.png", "states_joint.png", "rigid_motion.png",
              "energy.png", "static_joint.png"}  # fmt: skip
    assert common | {"loads.png", "static_stress.png"} == names
    for name in ("mesh.png", "joint_map.png", "envelope.png", "loads.png", "static_stress.png"):
        (w, h), text = png((tmp_path / name).read_bytes())
        assert w >= 500 and h >= 350 and "Description" in text
    alone = tmp_path / "alone"  # the results file without its model file
    alone.mkdir()
    (alone / "results.h5").write_bytes((tmp / "out" / "results.h5").read_bytes())
    import h5py

    with h5py.File(alone / "results.h5", "r+") as f:  # a model file moved away
        f.attrs["model_path"] = f.attrs["model_file"] = str(tmp_path / "gone" / "model.toml")
    assert main(["plot", str(alone / "results.h5"), "--out", str(alone / "fig")]) == 0
    assert {p.name for p in (alone / "fig").iterdir()} == common


@pytest.mark.parametrize("cell", ["hexahedron", "tetra", "tetra10"])
def test_boundary_faces_of_a_box(cell: str) -> None:
    """The boundary faces of a structured 2 × 3 × 4 box: 2 (nx ny + ny nz + nz nx) quads,
    twice as many triangles for the tetrahedra (each side quad cut in two), every face on
    a side of the box (its corners share the side's coordinate)."""
    from pfeie.mesh import box
    from pfeie.plot._plots import boundary_faces

    m = box(2.0, 3.0, 4.0, 2, 3, 4, cell=cell)
    (faces,) = boundary_faces(m.points, m.cells)
    n_quads = 2 * (2 * 3 + 3 * 4 + 4 * 2)
    assert faces.shape == ((n_quads, 4) if cell == "hexahedron" else (2 * n_quads, 3))
    p = m.points[faces]
    lo, hi = m.points.min(axis=0), m.points.max(axis=0)
    on_side = ((p == lo).all(axis=1) | (p == hi).all(axis=1)).any(axis=1)
    assert on_side.all()


def test_joint_plane_of_an_inclined_joint() -> None:
    """An inclined plane joint (normal (sin 30°, 0, cos 30°)): the normal found to
    round-off, the axes ≈x and y orthonormal, in the order of a level joint's (x, y) (a
    dip along x read (y, ≈x): the map of a dam's base turned by a slight dip), and the
    map an isometry: the distances between the pairs in the plane are the distances in
    space (1e-14 m on 10 m)."""
    from pfeie.plot._plots import joint_plane

    n = np.array([np.sin(np.pi / 6), 0.0, np.cos(np.pi / 6)])
    t1, t2 = np.array([0.0, 1.0, 0.0]), np.cross(n, [0.0, 1.0, 0.0])
    ab = np.random.default_rng(3).uniform(0.0, 10.0, (30, 2))
    x = np.array([1.0, 2.0, 3.0]) + ab[:, :1] * t1 + ab[:, 1:] * t2
    frame = np.broadcast_to(np.stack([t1, t2, n]), (30, 3, 3))
    uv, basis, labels = joint_plane(x, frame)
    assert np.allclose(basis[-1], n, rtol=0, atol=1e-15)  # reached: 1.7e-16
    assert np.allclose(basis @ basis.T, np.eye(3), rtol=0, atol=1e-16)  # reached: 1.5e-17
    assert labels == ["≈x", "y"]
    level = np.broadcast_to(np.eye(3), (30, 3, 3))
    assert joint_plane(x, level)[2] == ["x", "y"]
    d3 = np.linalg.norm(x[:, None] - x[None], axis=-1)
    d2 = np.linalg.norm(uv[:, None] - uv[None], axis=-1)
    assert np.abs(d2 - d3).max() < 1e-14  # reached: 1.8e-15


def test_the_input_motion_is_the_motion_applied(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A run shorter than its record (0.1 s of a 0.4 s pulse 0.5 g sin(π t / 0.4)): the
    run's record line says that the motion applied ends at the duration, and the report's
    intensity measures are those of that part (PGA 0.5 sin(π/4) = 0.35355 g and Arias,
    to 1e-14, measured exact: the cut interpolates the record's samples at 0.1 s, where a
    sample lies), as
    ``pfeie spectrum`` and a study measure them (a new user's report gave the whole
    record's Arias 1.53 m/s beside the study's 0.898 for the run's 6 s)."""
    from pfeie.model import intensity_measures
    from pfeie.plot._report import record_rows
    from test_cli import SMALL, _write

    p = _write(tmp_path, SMALL, duration=0.1)
    assert main(["run", str(p), "--quiet"]) == 0
    err = capsys.readouterr().err
    assert "(the motion applied: up to 0.1 s, analysis.duration)" in err, err
    with Results(tmp_path / "out" / "results.h5") as res:
        rows = record_rows(res)
    assert rows[0]["record"].endswith("(up to 0.1 s, the run's duration)")
    assert rows[0]["PGA (g)"] == pytest.approx(0.5 * np.sin(np.pi / 4), rel=1e-14)
    t = np.arange(0.0, 0.1 + 1e-9, 0.005)
    ref = intensity_measures(t, 9.81 * 0.5 * np.sin(np.pi * t / 0.4))
    assert rows[0]["Arias (m/s)"] == pytest.approx(ref["arias"], rel=1e-14)
