"""Model files (TOML): the schema, its validation, and the model it builds.

Every key is listed in ``docs/model-file.md`` (generated from :data:`SPEC` by
``describe``; a test checks that the page and the schema agree). Units are SI: m, s, kg,
Pa, N; angles in degrees; accelerations of records in the units the record states.
Relative paths (mesh, records, output folder) are relative to the model file.
"""

from __future__ import annotations

import hashlib
import logging
import tomllib
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError, MeshError, ModelError, PfeieError, RecordError
from ..interface import Joint
from ..model import Block, Elastic, GroundMotion, Interface, Model, Rayleigh
from ._gmsh import read_mesh
from ._records import read_record
from ._schema import (
    Key,
    Many,
    Named,
    Table,
    angle,
    describe,
    non_negative,
    one_of,
    positive,
    validate,
    vector,
)

log = logging.getLogger(__name__)

F, S, B, L, I = (float,), (str,), (bool,), (list,), (int,)

_MATERIAL = Table({
    "E": Key(F, "Young's modulus (Pa)", required=True, check=positive),
    "nu": Key(F, "Poisson's ratio", required=True,
              check=lambda x: None if -1 < x < 0.5 else "a number in (-1, 0.5)"),
    "rho": Key(F, "density (kg/m³)", required=True, check=non_negative),
})  # fmt: skip

_INTERFACE = Table({
    "friction_angle": Key(F, "friction angle φ (degrees)", required=True, check=angle),
    "cohesion": Key(F, "cohesion c of the intact joint (Pa)", default=0.0, check=non_negative),
    "tensile_strength": Key(F, "tensile strength σ_t of the intact joint (Pa)", default=0.0,
                            check=non_negative),
    "residual_cohesion": Key(F, "cohesion once broken (Pa)", default=0.0, check=non_negative),
    "residual_friction_angle": Key(F, "friction angle once broken (degrees); default: "
                                   "friction_angle", check=angle),
    "residual_tensile_strength": Key(F, "tensile strength once broken (Pa)", default=0.0,
                                     check=non_negative),
    "initial": Key(S, "initial state: 'intact' (bonded) or 'broken' (an existing joint)",
                   default="broken", check=one_of("intact", "broken")),
    "normal_stiffness": Key(F, "normal stiffness k_n of a weak layer (Pa/m); none: rigid "
                            "contact", check=positive),
    "shear_stiffness": Key(F, "shear stiffness k_s of a weak layer (Pa/m)", check=positive),
})  # fmt: skip

_COMPONENTS = lambda x: (  # noqa: E731
    None
    if isinstance(x, list) and x and all(c in ("x", "y", "z") for c in x)
    else "an array of 'x', 'y', 'z'"
)

SPEC = Table({
    "title": Key(S, "title of the analysis, for summaries and reports", default=""),
    "mesh": Table({
        "file": Key(S, "gmsh mesh (.msh 2.2 or 4.1) whose physical groups name the blocks "
                    "(surfaces in 2D, volumes in 3D) and the interfaces and faces (curves in "
                    "2D, surfaces in 3D)", required=True),
    }, required=True),
    "plane": Key(S, "2D hypothesis: 'strain' or 'stress'", default="strain",
                 check=one_of("strain", "stress")),
    "thickness": Key(F, "out-of-plane thickness in 2D (m)", default=1.0, check=positive),
    "materials": Named(_MATERIAL, "isotropic elastic materials by name", required=True),
    "blocks": Named(Key(S, "material of the block (the block is the physical group of this "
                        "name)"), "blocks: physical group = material name", required=True),
    "damping": Table({
        "alpha": Key(F, "Rayleigh mass coefficient α (1/s)", default=0.0, check=non_negative),
        "beta": Key(F, "Rayleigh stiffness coefficient β (s)", default=0.0,
                    check=non_negative),
        "ratio": Key(F, "damping ratio ζ at the two frequencies (instead of alpha, beta)",
                     check=non_negative),
        "frequencies": Key(L, "the two frequencies (Hz) for 'ratio'", check=vector(2, 2),
                           expect="an array of 2 numbers"),
    }),
    "interfaces": Named(_INTERFACE, "interfaces: physical group = joint properties"),
    "supports": Many(Table({
        "group": Key(S, "physical group whose nodes are supported", required=True),
        "components": Key(L, "supported components, e.g. ['x', 'y']; default: all",
                          check=_COMPONENTS),
        "value": Key(F, "prescribed displacement (m)", default=0.0),
    }), "supports (fixed or prescribed displacements)"),
    "loads": Table({
        "gravity": Key(F, "gravitational acceleration (m/s²); 0 for none", default=9.81,
                       check=non_negative),
        "gravity_direction": Key(L, "unit vector of gravity; default −y (2D), −z (3D)",
                                 check=vector()),
        "pressure": Many(Table({
            "group": Key(S, "physical group of faces", required=True),
            "value": Key(F, "pressure (Pa), positive pushing into the body", required=True),
        }), "uniform pressures"),
        "hydrostatic": Many(Table({
            "groups": Key(L, "physical groups of wetted faces", required=True,
                          check=lambda x: None if x and all(isinstance(g, str) for g in x)
                          else "an array of group names"),
            "water_level": Key(F, "water level (m, on the vertical axis)", required=True),
            "density": Key(F, "water density (kg/m³)", default=1000.0, check=positive),
        }), "hydrostatic pressure ρ_w g (level − z)⁺ on faces"),
    }),
    "ground_motion": Many(Table({
        "file": Key(S, "record file", required=True),
        "format": Key(S, "'auto', 'at2', 'two-column' or 'one-column'", default="auto",
                      check=one_of("auto", "at2", "two-column", "one-column")),
        "units": Key(S, "units of the record: 'g', 'm/s2' or 'cm/s2' (AT2: g)",
                     check=one_of("g", "m/s2", "cm/s2")),
        "dt": Key(F, "time step of a one-column record (s)", check=positive),
        "scale": Key(F, "scale factor", default=1.0),
        "component": Key(S, "direction of the motion: 'x', 'y' or 'z'", default="x",
                         check=one_of("x", "y", "z")),
        "direction": Key(L, "direction vector (instead of component)", check=vector()),
        "baseline": Key(B, "remove the drift of the final velocity (absolute form)",
                        default=False),
    }), "ground-motion records (several components act together)"),
    "analysis": Table({
        "static": Key(B, "solve the static state (gravity, water) first", default=True),
        "dynamic": Key(B, "run the dynamic analysis", default=True),
        "dt": Key(F, "time step (s)", default=0.01, check=positive),
        "duration": Key(F, "duration (s); default: the longest record", check=positive),
        "beta": Key(F, "Newmark β", default=0.25, check=positive),
        "gamma": Key(F, "Newmark γ", default=0.5, check=positive),
        "alpha": Key(F, "HHT α in [−1/3, 0]", default=0.0,
                     check=lambda x: None if -1 / 3 - 1e-12 <= x <= 0 else "a number in "
                     "[-1/3, 0]"),
        "form": Key(S, "ground motion: 'relative' (fixed base) or 'absolute' (moving "
                    "supports)", default="relative", check=one_of("relative", "absolute")),
        "stabilize": Key(B, "contact-stabilised Newmark (see docs/theory.md)", default=True),
        "large_rotation": Key(B, "carry finite rotations of the floating blocks in body "
                              "frames (rocking, toppling; see docs/theory.md)", default=False),
        "tolerance": Key(F, "interface complementarity tolerance", default=1e-8,
                         check=positive),
    }),
    "output": Table({
        "folder": Key(S, "output folder", default="results"),
        "every": Key(I, "record the histories every n-th step", default=1, check=positive),
        "field_every": Key(I, "store the nodal fields (u, v, a) every n-th recorded step",
                           default=10, check=positive),
        "paraview": Key(B, "write the ParaView series (blocks.xdmf, interfaces.xdmf)",
                        default=True),
        "probes": Named(Key(L, "probe point coordinates (m); the nearest node is used",
                            check=vector()), "named probe points"),
    }),
})  # fmt: skip


def reference_rows() -> list[tuple[str, str, str]]:
    """(key, expected, meaning) of every key of a model file."""
    return describe(SPEC)


def reference_markdown() -> str:
    """The key reference of docs/model-file.md, as a Markdown table."""
    lines = ["| key | expected | meaning |", "|---|---|---|"]
    for key, exp, doc in reference_rows():
        lines.append(f"| `{key}` | {exp} | {doc} |")
    return "\n".join(lines)


@dataclass
class Job:
    """A validated model file and what it builds."""

    path: Path
    spec: dict[str, Any]
    model: Model
    records: list[GroundMotion]
    probes: dict[str, int]
    digest: str
    interface_names: list[str] = field(default_factory=list)

    @property
    def folder(self) -> Path:
        return (self.path.parent / self.spec["output"]["folder"]).resolve()

    @property
    def duration(self) -> float:
        a = self.spec["analysis"]
        if a["duration"] is not None:
            return float(a["duration"])
        return max((g.time[-1] for g in self.records), default=0.0)

    def summary(self) -> dict[str, Any]:
        """Blocks, DOF, pairs per interface, records, estimated memory."""
        m = self.model
        s = m.summary()
        pairs = {}
        if m.pairs is not None:
            for name in m.pairs.names:
                pairs[name] = int(m.pairs.of(name).size)
        n_pairs = sum(pairs.values())
        M = n_pairs * m.dim
        dof = s["free_dof"]
        n_steps = round(self.duration / self.spec["analysis"]["dt"]) if self.records else 0
        n_out = n_steps // self.spec["output"]["every"] + 1
        fill = 60 if m.dim == 2 else 400  # factor entries per DOF, measured order of magnitude
        mem = (dof * fill * 8 + 3 * M * M * 8 + n_out * (3 * M + m.dim * 4 * len(self.probes)) * 8
               + 40 * dof * 8)  # fmt: skip
        return {
            "title": self.spec["title"], "file": str(self.path), "sha256": self.digest,
            "dimension": m.dim, "blocks": {b.name: b.material for b in m.blocks},
            "bodies": m.n_bodies, "cells": s["cells"], "nodes": s["nodes"], "dof": s["dof"],
            "free_dof": dof, "pairs": pairs,
            "records": [g.summary() for g in self.records], "steps": n_steps,
            "dt": self.spec["analysis"]["dt"], "duration": self.duration,
            "estimated_memory_mb": round(mem / 2**20, 1),
        }  # fmt: skip


def load_job(path: str | Path) -> Job:
    """Read, validate and build a model file. Errors are :class:`InputError` (model
    file), :class:`MeshError` or :class:`RecordError`, each naming the file."""
    p = Path(path)
    if not p.is_file():
        raise InputError(f"{p}: model file not found")
    raw = p.read_bytes()
    try:
        data = tomllib.loads(raw.decode("utf-8"))
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise InputError(f"{p}: not valid TOML: {exc}") from None
    spec = validate(SPEC, data, str(p))
    digest = hashlib.sha256(raw).hexdigest()
    base = p.parent
    mesh = read_mesh(base / spec["mesh"]["file"])
    mats = {}
    for name, mt in spec["materials"].items():
        mats[name] = Elastic(mt["E"], mt["nu"], mt["rho"])
    blocks = []
    for group, mat in spec["blocks"].items():
        if mat not in mats:
            raise InputError(f"{p}: blocks.{group}: unknown material {mat!r}; materials: "
                             f"{sorted(mats)}")  # fmt: skip
        if group not in mesh.cell_groups:
            raise InputError(_group_msg(p, f"blocks.{group}", group, mesh, mesh.dim))
        blocks.append(Block(group, mats[mat]))
    interfaces = []
    for group, js in spec["interfaces"].items():
        if group not in mesh.facet_groups:
            raise InputError(_group_msg(p, f"interfaces.{group}", group, mesh, mesh.dim - 1))
        try:
            joint = Joint(c=js["cohesion"], phi=js["friction_angle"],
                          tensile=js["tensile_strength"], c_r=js["residual_cohesion"],
                          phi_r=js["residual_friction_angle"],
                          tensile_r=js["residual_tensile_strength"], initial=js["initial"],
                          kn=js["normal_stiffness"], ks=js["shear_stiffness"])  # fmt: skip
        except ModelError as exc:
            raise InputError(f"{p}: interfaces.{group}: {exc}") from None
        interfaces.append(Interface(group, joint))
    damp = spec["damping"]
    damping = None
    if damp["ratio"] is not None:
        if damp["frequencies"] is None:
            raise InputError(f"{p}: damping.frequencies: missing (required with ratio)")
        if damp["alpha"] or damp["beta"]:
            raise InputError(f"{p}: damping: give either ratio and frequencies or alpha and "
                             "beta, not both")  # fmt: skip
        f1, f2 = damp["frequencies"]
        try:
            damping = Rayleigh.from_ratio(damp["ratio"], float(f1), float(f2))
        except ModelError as exc:
            raise InputError(f"{p}: damping: {exc}") from None
    elif damp["alpha"] or damp["beta"]:
        damping = Rayleigh(damp["alpha"], damp["beta"])
    try:
        model = Model(mesh, blocks, plane=spec["plane"], thickness=spec["thickness"],
                      damping=damping, interfaces=interfaces)  # fmt: skip
    except (ModelError, MeshError) as exc:
        raise InputError(f"{p}: {exc}") from None
    axes = {"x": 0, "y": 1, "z": 2}
    for i, sup in enumerate(spec["supports"]):
        g = sup["group"]
        if g not in model.mesh.cell_groups and g not in model.mesh.facet_groups:
            raise InputError(_group_msg(p, f"supports[{i}].group", g, model.mesh, None))
        comps = None
        if sup["components"] is not None:
            comps = [axes[c] for c in sup["components"]]
            if max(comps) >= mesh.dim:
                raise InputError(f"{p}: supports[{i}].components: 'z' in a 2D model")
        model.fix(g, comps, sup["value"])
    loads = spec["loads"]
    if loads["gravity"]:
        direction = loads["gravity_direction"]
        if direction is not None and len(direction) != mesh.dim:
            raise InputError(f"{p}: loads.gravity_direction: expected {mesh.dim} components")
        model.add_gravity(loads["gravity"], direction=direction)
    for i, pr in enumerate(loads["pressure"]):
        if pr["group"] not in model.mesh.facet_groups:
            raise InputError(_group_msg(p, f"loads.pressure[{i}].group", pr["group"],
                                        model.mesh, mesh.dim - 1))  # fmt: skip
        model.add_pressure(pr["group"], pr["value"])
    up = mesh.dim - 1
    g_acc = loads["gravity"] or 9.81
    for i, hy in enumerate(loads["hydrostatic"]):
        for g in hy["groups"]:
            if g not in model.mesh.facet_groups:
                raise InputError(_group_msg(p, f"loads.hydrostatic[{i}].groups", g, model.mesh,
                                            mesh.dim - 1))  # fmt: skip
            model.add_pressure(g, _hydrostatic(hy["water_level"], hy["density"], g_acc, up))
    records = []
    for i, gm in enumerate(spec["ground_motion"]):
        if gm["direction"] is not None:
            direction = [float(v) for v in gm["direction"]]
            if len(direction) != mesh.dim:
                raise InputError(f"{p}: ground_motion[{i}].direction: expected {mesh.dim} "
                                 "components")  # fmt: skip
        else:
            k = axes[gm["component"]]
            if k >= mesh.dim:
                raise InputError(f"{p}: ground_motion[{i}].component: 'z' in a 2D model")
            direction = [0.0] * mesh.dim
            direction[k] = 1.0
        try:
            rec = read_record(base / gm["file"], fmt=gm["format"], dt=gm["dt"],
                              units=gm["units"], scale=gm["scale"], direction=direction,
                              baseline=gm["baseline"])  # fmt: skip
        except RecordError as exc:
            raise RecordError(f"{p}: ground_motion[{i}]: {exc}") from None
        records.append(rec)
    probes = {}
    for name, xyz in spec["output"]["probes"].items():
        if len(xyz) != mesh.dim:
            raise InputError(f"{p}: output.probes.{name}: expected {mesh.dim} coordinates")
        probes[name] = model.nearest_node([float(v) for v in xyz])
    if spec["analysis"]["dynamic"] and not records and spec["analysis"]["duration"] is None:
        raise InputError(f"{p}: analysis.duration: missing (required without ground_motion)")
    return Job(p, spec, model, records, probes, digest, [i.group for i in interfaces])


def _hydrostatic(level: float, rho_w: float, g: float, up: int) -> Callable[[Any], Any]:
    """Pressure ρ_w g (level − z)⁺ (Pa) at points (..., d); z the vertical axis."""

    def pressure(x: Any) -> Any:
        return rho_w * g * np.maximum(level - x[..., up], 0.0)

    return pressure


def _group_msg(p: Path, key: str, name: str, mesh: Any, dim: int | None) -> str:
    cells, facets = sorted(mesh.cell_groups), sorted(mesh.facet_groups)
    where = ""
    if dim == mesh.dim and name in mesh.facet_groups:
        where = f" ({name!r} is a group of dimension {mesh.dim - 1}, a block needs {mesh.dim})"
    elif dim == mesh.dim - 1 and name in mesh.cell_groups:
        where = f" ({name!r} is a group of dimension {mesh.dim}, this needs {mesh.dim - 1})"
    return (
        f"{p}: {key}: no physical group {name!r} of the right dimension in the mesh{where}; "
        f"groups of dimension {mesh.dim}: {cells}; of dimension {mesh.dim - 1}: {facets}"
    )


__all__ = ["SPEC", "Job", "PfeieError", "load_job", "reference_markdown", "reference_rows"]
