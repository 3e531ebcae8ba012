"""The HTML report (`pfeie report`): every item an engineer attaches to a review, each in
its section, checked on a run of the Pine Flat mesh with the loads a dam evaluation
needs (gravity, hydrostatic pressure, silt, the finite-element reservoir's added mass,
uplift with drains), two joints and a short record, run with ``--set`` overrides: the
geometry and mesh, the materials and joint laws, the loads (table and figure), the static
state (joint states, safety factors, principal stresses), the input motion and its
spectrum, the modal table (with and without the added mass), the analysis (Δt, solver
statistics), the histories, the joints' results and maps, the stress envelope and the
EM 1110-2-6053 evaluation; the page is self-contained. Without its model file the page
keeps every section and says what is missing and why."""

from __future__ import annotations

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
