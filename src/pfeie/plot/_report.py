"""A single self-contained HTML page that an engineer attaches to a review: the geometry
and mesh, materials, loads, the static state, the input motion and its spectrum, the modal
table, the histories, the joints' results and maps, the stress envelope, the solver's
statistics and the time step (:func:`write_report`)."""

from __future__ import annotations

import base64
import contextlib
import copy
import hashlib
import html
import json
import logging
import math
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..dynamics import envelope_extremes
from ..errors import InputError, PfeieError, ResultsError
from ..interface import OPEN_CRACK_MIN_M
from ..io import PYTHON_RUN, Results, applied_part, output_file
from ..typing import FloatArray
from ._plots import (
    figure_file,
    open_crack,
    plot_all,
    plot_fields,
    plot_fields_3d,
    plot_loads,
    plot_loads_3d,
    plot_static,
    run_title,
)

if TYPE_CHECKING:
    from ..io import Job

log = logging.getLogger(__name__)


def motion_tables(res: Results) -> tuple[list[dict[str, Any]], list[dict[str, Any]]]:
    """From the run's summary: the blocks held by their joints (floating) with their
    permanent displacement (the residual rigid motion of their centroid, the figure a
    Newmark sliding-block analysis estimates), its components, peak and rotation; and
    the probes' peak displacement and absolute acceleration. Empty for a static run."""
    summ = res.meta.get("results_summary") or {}
    axes = "xyz"
    blocks = []
    for name, b in (summ.get("bodies") or {}).items():
        if not b.get("floating"):
            continue
        row: dict[str, Any] = {
            "block": name,
            "residual displacement (mm)": 1e3 * b["residual_displacement_m"],
        }
        for k, v in enumerate(b.get("residual_displacement_xyz_m", [])):
            row[f"{axes[k]} (mm)"] = 1e3 * v
        row["peak (mm)"] = 1e3 * b["peak_displacement_m"]
        row["residual rotation (°)"] = b["residual_rotation_deg"]
        blocks.append(row)
    probes = [{"probe": name, "peak |u| (mm)": 1e3 * p["peak_displacement_m"],
               "peak |u| at (s)": p["peak_displacement_time_s"],
               "peak absolute |a| (g)": p["peak_abs_acceleration_g"],
               "peak |a| at (s)": p["peak_abs_acceleration_time_s"]}
              for name, p in (summ.get("probes") or {}).items()]  # fmt: skip
    return blocks, probes


def _piece_rows(
    res: Results, name: str, pr: dict[str, FloatArray],
    row: Callable[[str, dict[str, FloatArray], Any], dict[str, Any]],
) -> list[dict[str, Any]]:  # fmt: skip
    """The rows "joint: A | B" of the pieces of a joint whose pairs join more than two
    blocks (none for a joint between two), by ``row(label, pairs, positions)``."""
    by = res.joint_pieces(name)
    return [row(f"{name}: {label}", pr, i) for label, i in by.items()] if len(by) > 1 else []


def joint_table(res: Results) -> list[dict[str, Any]]:
    """Per joint: pairs, residual slip (largest, area mean), largest opening, broken share,
    the post-earthquake safety factor (for a static-only run: the static state,
    :func:`static_joint_table`); after the joints, a row "joint: A | B" for each piece of
    a joint whose pairs join more than two blocks (:meth:`Results.joint_pieces`)."""
    if res.n_times == 0:
        return static_joint_table(res)
    rows = []
    pieces: list[dict[str, Any]] = []

    def row_of(label: str, pr: dict[str, FloatArray], k: Any) -> dict[str, Any]:
        A = pr["area"][k]
        slip = np.linalg.norm(pr["slip"][-1, k], axis=-1)
        return {
            "joint": label, "pairs": int(A.size),
            "residual slip, largest (mm)": 1e3 * float(slip.max()),
            "residual slip, mean (mm)": 1e3 * float((slip * A).sum() / A.sum()),
            "largest opening (mm)": 1e3 * float(pr["opening"][:, k].max()),
            "broken (%)": 100 * float((pr["broken"][-1, k] * A).sum() / A.sum()),
        }  # fmt: skip

    for jk, name in enumerate(res.interface_names):
        pr = res.pairs(name)
        rows.append(row_of(name, pr, slice(None)))
        pieces += _piece_rows(res, name, pr, row_of)
        if "joints/safety_factor" in res.f["history"]:
            fs = np.asarray(res.f["history/joints/safety_factor"])[:, jk]
            rows[-1]["min safety factor"] = float(fs.min())
        if "joints/cracked" in res.f["history"]:
            cr = res.joint_cracks(name)
            unit = "m" if res.f["mesh/points"].shape[1] == 2 else "m²"
            rows[-1][f"cracked at the end ({unit})"] = float(cr["cracked"][-1])
            # as the summary: the broken pairs open by more than OPEN_CRACK_MIN_M
            rows[-1][f"largest open crack ({unit})"] = float(open_crack(pr, cr).max())
        if "joints/force" in res.f["history"]:
            jr = res.joint_resultants(name)
            # the horizontal part of the joint's resultant (the shear a dam's joint
            # carries; in 3D both horizontal axes: a wedge sliding along y too)
            horiz = np.linalg.norm(jr["force"][:, :-1], axis=1)
            rows[-1]["peak horizontal |F| (kN)"] = 1e-3 * float(horiz.max())
            rows[-1]["peak |M| (kN m)"] = 1e-3 * float(
                np.linalg.norm(jr["moment"], axis=1).max())  # fmt: skip
    # the post-earthquake static state (analysis.post_earthquake), from the run's summary
    post = (res.meta.get("results_summary") or {}).get("post_earthquake") or {}
    for row in rows:
        if "error" in post:
            row["post-earthquake safety factor"] = "no static equilibrium"
        elif "skipped" in post:  # a block that toppled or slid far
            row["post-earthquake safety factor"] = "not computed (large residual motion)"
        elif row["joint"] in post.get("joints", {}):
            fs = post["joints"][row["joint"]]["safety_factor"]
            row["post-earthquake safety factor"] = "∞" if fs is None else f"{fs:.3g}"
    return rows + pieces


def envelope_rows(res: Results) -> list[tuple[str, str]]:
    """The extremes of the stress envelope: the largest σ₁ and the smallest σ₃ over the
    nodes, where and when (empty without an envelope)."""
    ext = envelope_extremes(res.envelope(), np.asarray(res.f["mesh/points"]))
    if ext is None:
        return []
    out = []
    for name, label in (
        ("max_principal", "largest principal stress σ1 (at the nodes)"),
        ("min_principal", "smallest principal stress σ3 (at the nodes)"),
    ):
        where = ", ".join(f"{x:.4g}" for x in ext[f"{name}_at_m"])
        out.append((label, f"{ext[f'{name}_Pa'] / 1e6:.3g} MPa at ({where}) m, "
                           f"t = {ext[f'{name}_time_s']:.3f} s"))  # fmt: skip
    return out


def demand_capacity_rows(res: Results) -> list[tuple[str, str]]:
    """The EM 1110-2-6053 evaluation of the run's stresses (the results summary's
    ``stress.demand_capacity``, :func:`pfeie.dynamics.demand_capacity`): the largest
    demand-capacity ratio, the largest cumulative inelastic duration, the overstressed
    share and the verdict against the manual's acceptance (empty without tensile
    strengths)."""
    dc = (res.meta.get("results_summary") or {}).get("stress", {}).get("demand_capacity")
    if not dc:
        return []
    from ..dynamics import CID_LIMIT, DCR_LIMIT, OVERSTRESSED_LIMIT

    def at(key: str) -> str:
        return "(" + ", ".join(f"{x:.4g}" for x in dc[key]) + ") m"

    words = {
        "linear": "linear: the stresses stay below the tensile strength (DCR ≤ 1)",
        "acceptable": f"acceptable by the linear analysis: DCR ≤ {DCR_LIMIT:g}, CID ≤ "
                      f"{CID_LIMIT:g} s, overstressed ≤ {100 * OVERSTRESSED_LIMIT:g} %",
        "nonlinear analysis required": f"beyond the linear criteria (DCR ≤ {DCR_LIMIT:g}, "
                      f"CID ≤ {CID_LIMIT:g} s, overstressed ≤ {100 * OVERSTRESSED_LIMIT:g} "
                      "%): a nonlinear analysis is required",
    }  # fmt: skip
    return [
        ("largest demand-capacity ratio σ1/f_t (per cell: its largest σ1 at its quadrature "
         "points, where the nodes' values are extrapolated)",
         f"{dc['max_dcr']:.3g} at {at('max_dcr_at_m')} (the cell's centre), t = "
         f"{dc['max_dcr_time_s']:.3f} s"),
        ("largest cumulative inelastic duration",
         f"{dc['max_cid_s']:.3g} s at {at('max_cid_at_m')}" if dc["max_cid_s"] > 0
         else "0 s (no cell beyond its tensile strength)"),
        ("overstressed share (DCR > 1)",
         f"{100 * dc['overstressed_share']:.3g} % of the cells with a tensile strength"),
        ("EM 1110-2-6053", words.get(dc["verdict"], dc["verdict"])),
    ]  # fmt: skip


def per_thickness(summary: dict[str, Any], job: Job | None = None) -> str:
    """What a 2D model's forces are for: " a metre" (of its thickness) or " for t m"; ""
    in 3D (the run's summary's ``model``, or the model of ``job``). The summary's text and
    the report's columns say it alike."""
    m = summary.get("model") or {}
    dim = m.get("dimension", None if job is None else job.model.dim)
    if dim != 2:
        return ""
    t = float(m.get("thickness", 1.0 if job is None else job.model.thickness))
    return " a metre" if t == 1.0 else f" for {t:g} m"


def static_joint_table(res: Results, job: Job | None = None) -> list[dict[str, Any]]:
    """Per joint, the static state: pairs, mean normal stress, largest opening, shares
    sliding, open and broken, the sliding safety factor (of the first recorded row, or
    from the static pair forces and the model's joint laws, ``job``), the uplift, and from
    the run's summary the normal and shear resultants, the share in contact, its mean
    stress and the point of the normal resultant (empty without a static pair state);
    after the joints, a row "joint: A | B" for each piece
    of a joint whose pairs join more than two blocks."""
    if "static/X" not in res.f:
        return []
    fs_static = None
    if job is not None and job.model.pairs is not None:
        from ..interface import FS_ROUNDOFF, OPEN

        X = np.asarray(res.f["static/X"])
        P = job.model.pairs
        noise = FS_ROUNDOFF * np.array([np.abs(X[P.of(n)]).sum() for n in P.names])
        fs_static = job.model.pair_laws.safety_factor(
            X, np.asarray(res.f["static/state"]) == OPEN, np.asarray(res.f["static/broken"]),
            np.zeros(X.shape[0]), P.frame, noise,
            opening=np.asarray(res.f["static/s"][:, -1]))  # fmt: skip
    rows = []
    pieces: list[dict[str, Any]] = []

    def static_row(label: str, pr: dict[str, FloatArray], k: Any) -> dict[str, Any]:
        A = pr["area"][k]
        opened = (pr["state"][k] == 3) & (pr["opening"][k] > OPEN_CRACK_MIN_M)
        return {
            "joint": label, "pairs": int(A.size),
            "static normal stress, mean (MPa)": 1e-6 * float(pr["X"][k, -1].sum() / A.sum()),
            # to 0.01 mm (OPEN_CRACK_MIN_M), as the summary prints it: a closed pair's
            # opening is round-off
            "largest opening (mm)": round(1e3 * float(pr["opening"][k].max()), 2),
            "sliding (%)": 100 * float(((pr["state"][k] == 2) * A).sum() / A.sum()),
            # as the summary: open by more than OPEN_CRACK_MIN_M (the corner pairs of
            # quadratic facets part by microns under compression)
            "open (%)": 100 * float((opened * A).sum() / A.sum()),
            "broken (%)": 100 * float((pr["broken"][k] * A).sum() / A.sum()),
        }  # fmt: skip

    for k, name in enumerate(res.interface_names):
        pr = res.static_pairs(name)
        rows.append(static_row(name, pr, slice(None)))
        pieces += _piece_rows(res, name, pr, static_row)
        if "history/joints/safety_factor" in res.f and res.n_times:
            rows[-1]["sliding safety factor"] = float(res.f["history/joints/safety_factor"][0, k])
        elif fs_static is not None:
            rows[-1]["sliding safety factor"] = float(fs_static[k])
        if "static/uplift" in res.f:
            idx = np.flatnonzero(np.asarray(res.f["pairs/interface"]) == k)
            p = np.asarray(res.f["static/uplift"])[idx]
            if p.any():
                U = float((p * np.asarray(res.f["pairs/area"])[idx]).sum())
                rows[-1]["uplift force (kN)"] = 1e-3 * U
                rows[-1]["uplift at heel (kPa)"] = 1e-3 * float(p.max())
            cracks = json.loads(res.f["static"].attrs.get("cracks", "{}"))
            if name in cracks:
                rows[-1]["crack from the heel (m)"] = float(cracks[name])
    # the joint's resultants and its base in compression, as the summary gives them (the
    # gravity method's reading, EM 1110-2-2100: the normal and shear resultants, the share
    # in contact and its mean stress, the point of the normal resultant)
    summ = res.meta.get("results_summary") or {}
    per = per_thickness(summ, job)
    for row in rows:
        j = (summ.get("static_joints") or {}).get(row["joint"])
        if not j:
            continue
        row[f"normal force (kN{per})"] = 1e-3 * float(j["normal_force_N"])
        row[f"shear force (kN{per})"] = 1e-3 * float(j["shear_force_N"])
        if "contact_share" in j:
            row["in contact (%)"] = 100 * float(j["contact_share"])
            mean = j.get("mean_contact_stress_Pa")
            row["mean stress in contact (MPa)"] = "—" if mean is None else 1e-6 * float(mean)
            at = j.get("normal_resultant_at_m")
            row["normal resultant at (m)"] = (
                "— (tension)" if at is None else "(" + ", ".join(f"{v:.4g}" for v in at) + ")"
            )
    # the yield coefficient (analysis.yield_coefficient) on the joint that governs it
    yields = summ.get("yield_coefficient") or {}
    for row in rows:
        for label, y in yields.items():
            if y.get("joint") == row["joint"] and y.get("k_y") is not None:
                row[f"yield coefficient k_y along {label}"] = f"{y['k_y']:.4g} ({y['limit']})"
    # the factor of safety by strength reduction (analysis.strength_reduction), on the joint
    # that governs it
    sr = summ.get("strength_reduction") or {}
    for row in rows:
        if sr.get("joint") == row["joint"] and sr.get("factor") is not None:
            row["FS by strength reduction"] = f"{sr['factor']:.4g} ({sr['limit']})"
    return rows + pieces


def analysis_rows(res: Results) -> list[tuple[str, str]]:
    """The analysis as run: scheme, Δt, ρ∞, form, duration and steps, the pair solver's
    statistics, the wall time."""
    meta = res.meta
    a = meta.get("analysis", {})
    out = [("scheme", str(a.get("scheme", ""))), ("time step Δt", f"{a.get('dt')} s")]
    if a.get("scheme") == "nonsmooth-alpha":
        rho = a.get("rho_inf")
        out.append(("ρ∞ (numerical dissipation)", "0 (default)" if rho is None else str(rho)))
    out.append(("ground motion form", str(meta.get("form", ""))))
    summ = meta.get("results_summary") or {}
    if "steps" in summ:
        out.append(("steps", f"{summ['steps']} to t = {summ.get('time_reached_s', 0):.3f} s"))
    if a.get("tolerance") is not None:
        out.append(("pair solver tolerance", f"{a['tolerance']:g}"))
    sv = summ.get("solver")
    if sv:
        out.append(("pair solver", solver_line(sv)))
    e = summ.get("energy_J")
    if e:  # the energy account at the end (J), as the text summary's line
        out.append(("energy (J)", ", ".join(
            f"{label} {e[key]:.4g}" for key, label in (
                ("external_work", "input"), ("interface", "friction/contact"),
                ("impact", "impact"), ("damping", "damping"), ("algorithmic", "algorithmic"),
                ("correction", "position corrections"), ("balance", "balance"))
            if key in e)))  # fmt: skip
    if "wall_time_s" in summ:
        out.append(("wall time", f"{summ['wall_time_s']:.1f} s"))
    return out


def solver_line(sv: dict[str, Any]) -> str:
    """The pair solver's statistics in words, as the summary and the report give them.

    >>> print(solver_line({"iterations_mean": 7.8, "fallback_steps": 0, "newton_steps": 446,
    ...                    "worst_residual": 8.1e-9}))  # doctest: +NORMALIZE_WHITESPACE
    7.8 iterations a step; the semismooth Newton finished 446 step(s);
    0 step(s) needed a fallback; worst residual 8.1e-09
    """
    newton = ""
    if "newton_steps" in sv:
        newton = f"the semismooth Newton finished {sv['newton_steps']} step(s); "
    if sv.get("event_steps"):
        newton += f"{sv['event_steps']} event step(s) taken again in sub-steps; "
    return (f"{sv['iterations_mean']:.1f} iterations a step; {newton}"
            f"{sv['fallback_steps']} step(s) needed a fallback; worst residual "
            f"{sv['worst_residual']:.1e}")  # fmt: skip


def record_rows(res: Results) -> list[dict[str, Any]]:
    """Intensity measures of the records of the run (as scaled), of the motion applied:
    a record that goes on beyond the run's duration up to it
    (:func:`~pfeie.io.applied_part`), as ``pfeie spectrum`` and a study measure them."""
    if "records" not in res.f:
        return []
    from ..model import GroundMotion, intensity_measures

    end = res.meta.get("analysis", {}).get("duration")
    rows = []
    for key in sorted(res.f["records"], key=int):
        g = res.f[f"records/{key}"]
        t, a = np.asarray(g["time"]), np.asarray(g["acceleration"])
        name = str(g.attrs.get("name", key))
        if end is not None and res.n_times and t[-1] > float(end) > t[0]:
            part = applied_part(GroundMotion.from_samples(a, time=t), float(end))[0]
            t, a = part.time, part.acceleration
            name += f" (up to {float(end):g} s, the run's duration)"
        im = intensity_measures(t, a)
        rows.append({
            "record": name, "PGA (g)": im["pga"] / 9.81,
            "PGV (m/s)": im["pgv"], "PGD (m)": im["pgd"], "Arias (m/s)": im["arias"],
            "CAV (m/s)": im["cav"], "D5-95 (s)": im["d5_95"],
        })  # fmt: skip
    return rows


#: the parts of a model file that build the model (not the analysis, records or output)
STRUCTURE = ("mesh", "plane", "thickness", "materials", "blocks", "interfaces", "supports",
             "loads", "damping")  # fmt: skip


def _differs(new: Any, old: Any, key: str) -> list[str]:
    """The dotted keys where the settings ``new`` (as this pfeie reads the model file)
    differ from ``old`` (as the run recorded them); a key that only one side has, with a
    value that means "not given" (None, False, 0, empty) on the other, is a setting added
    or dropped by a pfeie version, not a change."""
    unset: tuple[object, ...] = (None, False, 0, 0.0, "", [], {})
    if isinstance(new, dict) and isinstance(old, dict):
        out = []
        for k in sorted(set(new) | set(old)):
            if (k not in old and new[k] in unset) or (k not in new and old[k] in unset):
                continue
            out += _differs(new.get(k), old.get(k), f"{key}.{k}")
        return out
    if isinstance(new, list) and isinstance(old, list) and len(new) == len(old):
        return [d for i, (a, b) in enumerate(zip(new, old, strict=True))
                for d in _differs(a, b, f"{key}[{i}]")]  # fmt: skip
    return [] if new == old else [key]


@contextlib.contextmanager
def _quiet() -> Iterator[None]:
    """Warnings and lower off while a run's model is rebuilt for its report or figures
    (its warnings were given by the run and are in its summary); the earlier
    ``logging.disable`` level comes back after."""
    before = logging.root.manager.disable
    logging.disable(max(before, logging.WARNING))
    try:
        yield
    finally:
        logging.disable(before)


def model_of_run(res: Results) -> tuple[Job | None, str]:
    """The model of a run rebuilt from its model file, or None and why not.

    The file is looked for where the results file records it (its absolute path, then
    the path given to ``pfeie run``, relative to the current folder) and then, by its
    name, in the folders above the results file (the output folder is usually beside the
    model file).
    It is taken only if its SHA-256 equals the recorded one and the run key
    (:func:`pfeie.io.run_key`: the model file with its ``--set`` overrides, the bytes of
    the mesh and the records) of the validated model file the results file records
    (``model_spec``) equals the recorded one: the mesh and records are those of the run.
    The run's overrides of the parts that build the model (:data:`STRUCTURE`) are then
    applied again, so the model is the one that was run. A results file without
    ``model_spec`` (older) needs the model file's own run key to match."""
    from types import SimpleNamespace

    from ..io import Override, load_job, same_run

    meta = res.meta
    if meta.get("model_file") == PYTHON_RUN:
        return None, ("the run was made through the Python API (pfeie.run_to_folder), "
                      "without a model file to rebuild the model from")  # fmt: skip
    given = Path(str(meta.get("model_file", "")))
    here = res.path.resolve().parent
    candidates = [
        Path(str(meta.get("model_path", given))),
        given,
        *[d / given.name for d in (here, *list(here.parents)[:3])],
    ]
    seen = set()
    for path in candidates:
        if not path.name or not path.is_file() or str(path.resolve()) in seen:
            continue
        seen.add(str(path.resolve()))
        if hashlib.sha256(path.read_bytes()).hexdigest() != meta.get("model_sha256"):
            continue
        spec = json.loads(meta["model_spec"]) if "model_spec" in meta else None
        key = meta.get("run_key")
        # the scale factors a pga or target_sa took from the records cut at the duration
        # are in the run key (results format 1.8 records them)
        part = {int(k): float(v) for k, v in json.loads(meta.get("part_factors", "{}")).items()}
        ran = SimpleNamespace(spec=spec, path=path, part_factors=part)
        if key is not None and spec is not None and not same_run(key, ran):
            return None, (f"the mesh or a record file of the model file {path} changed since "
                          "the run")  # fmt: skip
        try:
            with _quiet():  # the model's warnings were the run's; not again for a figure
                job = load_job(path)
            if spec is not None:
                plain = json.loads(json.dumps(job.spec, default=str))
                changed = [k for k in STRUCTURE if _differs(plain.get(k), spec.get(k), k)]
                if changed and _differs(plain.get("analysis"), spec.get("analysis"), "analysis"):
                    # the analysis table as run too: the checks across tables (a pseudo-
                    # static load without a dynamic analysis, ρ∞ > 0 with damping) hold
                    # for the tables as run, not for the run's model with the file's
                    changed.append("analysis")
                if changed:
                    with _quiet():
                        job = load_job(path, [Override(k, spec[k], "the results file")
                                              for k in changed if k in spec])  # fmt: skip
                    plain = json.loads(json.dumps(job.spec, default=str))
                    still = [d for k in STRUCTURE for d in _differs(plain.get(k), spec.get(k), k)]
                    if still:
                        return None, (f"the model of {path} does not rebuild as run: "
                                      f"{', '.join(still[:3])} differ(s) from the run's "
                                      f"settings (written by pfeie "
                                      f"{meta.get('pfeie_version', '?')})")  # fmt: skip
        except PfeieError as exc:
            return None, f"the model file {path} does not build: {exc}"
        if spec is None and key is not None and not same_run(key, job):
            return None, (f"the model file {path} differs from the run's model: the run had "
                          "--set overrides, or its mesh or a record file changed")  # fmt: skip
        return job, str(path)
    return None, (f"the model file {given} (SHA-256 {str(meta.get('model_sha256'))[:12]}) "
                  "is not found beside the results file, or it changed since the run")  # fmt: skip


def model_rows(res: Results, job: Job | None) -> list[tuple[str, str]]:
    """The geometry and mesh: model file, dimension, blocks, bodies, cells, DOF, pairs,
    the 2D hypothesis and thickness, the damping."""
    meta = res.meta
    summ = meta["model_summary"]
    x = np.asarray(res.f["mesh/points"])
    lo, hi = x.min(axis=0), x.max(axis=0)
    extent = " × ".join(f"{h - l_:.4g}" for l_, h in zip(lo, hi, strict=True))
    rows = [
        ("model file", str(meta["model_file"])), ("SHA-256", str(meta["model_sha256"])),
        ("pfeie", str(meta["pfeie_version"])), ("dimension", f"{summ['dimension']}D"),
        ("extent", f"{extent} m ("
                   + ", ".join(f"{a} from {lo[i]:.4g} to {hi[i]:.4g} m"
                               for i, a in enumerate("xyz"[: len(lo)])) + ")"),
        ("blocks", ", ".join(summ["blocks"])), ("bodies", str(summ["bodies"])),
        ("cells", ", ".join(f"{v} {k}" for k, v in summ["cells"].items())),
        ("nodes", str(summ.get("nodes", x.shape[0]))),
        ("DOF", f"{summ['dof']} ({summ['free_dof']} free)"),
        ("pairs", ", ".join(f"{k}: {v}" for k, v in summ["pairs"].items()) or "none"),
    ]  # fmt: skip
    if job is not None:
        spec = job.spec
        if summ["dimension"] == 2:
            rows.append(("2D hypothesis", f"plane {spec['plane']}, thickness "
                         f"{spec['thickness']:g} m (forces and masses per this "
                         "thickness)"))  # fmt: skip
        d = spec.get("damping", {})
        spared = (
            ", the deformation only (the floating blocks' rigid motion undamped)"
            if d.get("deformation_only")
            else ""
        )
        if d.get("ratio") is not None and d.get("frequencies") is not None:
            f1, f2 = d["frequencies"]
            rows.append(("damping", f"Rayleigh, {100 * d['ratio']:g} % at {f1:g} and "
                         f"{f2:g} Hz{spared}"))  # fmt: skip
        elif d.get("alpha") or d.get("beta"):
            rows.append(("damping", f"Rayleigh, α = {d['alpha']:g} 1/s, β = {d['beta']:g} s"
                         f"{spared}"))  # fmt: skip
        else:
            rows.append(("damping", "none"))
    return rows


def material_rows(res: Results, job: Job | None) -> list[dict[str, Any]]:
    """The materials of the blocks: E, ν, ρ and the tensile strength, and the blocks that
    use each (from the recorded model summary when the model file is not available)."""
    if job is None:
        blocks = res.meta["model_summary"]["blocks"]
        return [{"block": b, "material": str(m)} for b, m in blocks.items()]
    spec = job.spec
    rows = []
    for name, m in spec["materials"].items():
        ft = m.get("tensile_strength")
        rows.append({
            "material": name,
            "blocks": ", ".join(b for b, mat in spec["blocks"].items() if mat == name),
            "E (GPa)": 1e-9 * m["E"], "ν": float(m["nu"]), "ρ (kg/m³)": float(m["rho"]),
            "tensile strength f_t (MPa)": "none" if ft is None else f"{1e-6 * ft:.4g}",
        })  # fmt: skip
    return rows


def joint_property_rows(res: Results, job: Job | None) -> list[dict[str, Any]]:
    """The joints' laws: strengths intact and residual, initial state, stiffnesses (from
    the recorded model summary, its ``joint_laws``, when the model file is not
    available; a key it lacks is a strength or stiffness the law does not have)."""
    if job is not None:
        laws = job.spec["interfaces"]
    else:
        laws = res.meta.get("model_summary", {}).get("joint_laws", {})
    rows = []
    for name, given in laws.items():
        js = {k: given.get(k) for k in ("cohesion", "tensile_strength", "residual_cohesion",
                                        "residual_friction_angle", "normal_stiffness",
                                        "shear_stiffness")}  # fmt: skip
        js |= {k: given.get(k, "") for k in ("law", "initial", "friction_angle")}
        # (the summary names the law's class: the model file's name for it)
        js["law"] = {"MohrCoulomb": "mohr-coulomb", "SlipWeakening": "slip-weakening"}.get(
            str(js["law"]), js["law"])  # fmt: skip
        if js["friction_angle"] == "":  # (a law without Mohr-Coulomb's keys: its name)
            rows.append({"joint": name, "law": str(js["law"]), "initial": "—", "c (MPa)": "—",
                         "φ (°)": "—", "f_t (MPa)": "—", "residual c (MPa)": "—",
                         "residual φ (°)": "—", "k_n (Pa/m)": "—", "k_s (Pa/m)": "—"})  # fmt: skip
            continue

        def mpa(v: Any) -> str:
            return "none" if v is None else f"{1e-6 * v:.4g}"

        def stiff(v: Any) -> str:
            return "rigid" if v is None else f"{v:.4g}"

        rows.append({
            "joint": name, "law": str(js.get("law", "")), "initial": str(js["initial"]),
            "c (MPa)": mpa(js["cohesion"]), "φ (°)": float(js["friction_angle"]),
            "f_t (MPa)": mpa(js["tensile_strength"]),
            "residual c (MPa)": mpa(js["residual_cohesion"]),
            "residual φ (°)": "as intact" if js["residual_friction_angle"] is None
                              else f"{js['residual_friction_angle']:.4g}",
            "k_n (Pa/m)": stiff(js["normal_stiffness"]),
            "k_s (Pa/m)": stiff(js["shear_stiffness"]),
        })  # fmt: skip
    return rows


def load_rows(res: Results | None, job: Job) -> list[dict[str, Any]]:
    """The loads of the model file, one row per table of ``[loads]``: what, where, its
    parameters and its resultant force (kN; in 2D per the model's thickness): the loads
    of the static state from the model's load patterns (gravity, pressures, hydrostatic
    pressure, silt; in the order the model file builds them), the uplift from the static
    state of the results file ``res`` (without one, as in ``pfeie check``, its parameters
    only), the reservoir's added mass (kg)."""
    model = job.model
    d = model.dim
    spec = job.spec["loads"]
    pats, _ = model.load_patterns()
    cols = iter(range(pats.shape[1]))
    axes = "xyz"[:d]

    def force(n_cols: int) -> dict[str, Any]:
        f = sum((pats[:, next(cols)] for _ in range(n_cols)), np.zeros(pats.shape[0]))
        F = np.asarray(f).reshape(-1, d).sum(axis=0)
        return {f"F_{a} (kN)": 1e-3 * float(F[i]) for i, a in enumerate(axes)}

    def groups(g: list[str]) -> str:
        return ", ".join(g)

    rows: list[dict[str, Any]] = []
    ps = spec.get("pseudo_static") if spec["gravity"] else None
    n_ps = 0 if ps is None else int(bool(ps["kh"])) + int(bool(ps.get("kv")))
    consistent = len(model.loads) == (int(bool(spec["gravity"])) + n_ps + len(spec["pressure"])
                                      + sum(len(h["groups"]) for h in spec["hydrostatic"])
                                      + sum(len(s_["groups"]) for s_ in spec["silt"]))  # fmt: skip
    if not consistent:  # not built by a model file as known here: the resultants omitted
        cols = iter([])

    def resultant(n: int) -> dict[str, Any]:
        return force(n) if consistent else {}

    if spec["gravity"]:
        where = "-" + axes[-1] if spec["gravity_direction"] is None else str(
            spec["gravity_direction"])  # fmt: skip
        rows.append({"load": "gravity", "where": "all blocks",
                     "parameters": f"g = {spec['gravity']:g} m/s² along {where}",
                     **resultant(1)})  # fmt: skip
    if n_ps and ps is not None:  # added right after gravity (io._modelfile)
        towards = "+x" if ps["direction"] is None else str(ps["direction"])
        on = "all blocks" + (" and the reservoirs' added mass"
                             if model.reservoirs or model.fe_reservoirs else "")  # fmt: skip
        rows.append({"load": "pseudo-static", "where": on,
                     "parameters": f"k_h = {ps['kh']:g} along {towards}, k_v = "
                                   f"{ps.get('kv', 0.0):g} (upward +)",
                     **resultant(n_ps)})  # fmt: skip
    for pr in spec["pressure"]:
        rows.append({"load": "pressure", "where": pr["group"],
                     "parameters": f"{pr['value']:g} Pa", **resultant(1)})  # fmt: skip
    for hy in spec["hydrostatic"]:
        rows.append({"load": "hydrostatic", "where": groups(hy["groups"]),
                     "parameters": f"water level {hy['water_level']:g} m, ρ_w = "
                                   f"{hy['density']:g} kg/m³",
                     **resultant(len(hy["groups"]))})  # fmt: skip
    for sl in spec["silt"]:
        coef = (f"K = {sl['k']:g}" if sl["k"] is not None else
                f"K0 = 1 − sin {sl['friction_angle']:g}° = "
                f"{1 - np.sin(np.radians(sl['friction_angle'])):.4g}")  # fmt: skip
        rows.append({"load": "silt", "where": groups(sl["groups"]),
                     "parameters": f"silt level {sl['level']:g} m, γ' = "
                                   f"{sl['submerged_unit_weight']:g} N/m³, {coef}",
                     **resultant(len(sl["groups"]))})  # fmt: skip
    static_uplift = res is not None and "static/uplift" in res.f
    if static_uplift and spec["uplift"]:
        assert res is not None
        p = np.asarray(res.f["static/uplift"])
        A = np.asarray(res.f["pairs/area"])
        normal = np.asarray(res.f["pairs/frame"])[:, -1, :]
        iface = np.asarray(res.f["pairs/interface"])
        cracks = json.loads(res.f["static"].attrs.get("cracks", "{}"))
    for ut in spec["uplift"]:
        text = f"headwater {ut['headwater']:g} m, " + (
            "no tailwater" if ut["tailwater"] is None else f"tailwater {ut['tailwater']:g} m"
        )
        if ut["drains"] is not None:
            text += (f", drains {ut['drains']:g} m from the heel, efficiency "
                     f"{100 * ut['drain_efficiency']:g} %")  # fmt: skip
        text += f"; during the shaking: {ut['shaking']}"
        row: dict[str, Any] = {"load": "uplift", "where": ut["interface"], "parameters": text}
        if static_uplift and res is not None and ut["interface"] in res.interface_names:
            sel = iface == res.interface_names.index(ut["interface"])
            n = normal[sel]
            n = np.where((n[:, -1] < 0)[:, None], -n, n)  # the force on the upper side
            F = ((p[sel] * A[sel])[:, None] * n).sum(axis=0)
            row.update({f"F_{a} (kN)": 1e-3 * float(F[i]) for i, a in enumerate(axes)})
            if ut["interface"] in cracks:
                row["parameters"] += f"; static crack {cracks[ut['interface']]:.4g} m"
        rows.append(row)
    dry = copy.copy(model)
    wet = iter(model.reservoirs)
    fe = iter(model.fe_reservoirs)
    for wg in spec["westergaard"]:
        if wg["model"] == "fe":
            r = next(fe)
            mass = r.lumped().reshape(-1, d).sum(axis=0)
            what = "finite-element reservoir (incompressible)"
        else:
            dry.reservoirs, dry.fe_reservoirs = [next(wet)], []
            mass = dry.added_mass().reshape(-1, d).sum(axis=0)
            what = "Westergaard"
        rows.append({"load": "reservoir added mass", "where": groups(wg["groups"]),
                     "parameters": f"{what}, water level {wg['water_level']:g} m; added mass "
                                   + ", ".join(f"{1e-3 * mass[i]:.4g} t along {a}"
                                               for i, a in enumerate(axes))})  # fmt: skip
    return rows


#: modes of the report's modal table
N_MODES = 6


def modal_tables(
    job: Job, n_modes: int = N_MODES
) -> tuple[list[tuple[str, list[dict[str, Any]]]], str]:
    """The modal table of the model with its joints bonded (:func:`pfeie.modal`): per
    mode its frequency, period and effective modal mass along each axis (share of the
    free mass, and cumulative); with and without the reservoir's added mass when the
    model has one (titles and rows), and why there is none when the modal analysis is
    not possible (a model of fewer DOFs than modes, joints with one stiffness only)."""
    from ..solvers import modal

    model = job.model
    variants = [("", model)]
    if model.reservoirs or model.fe_reservoirs:
        dry = copy.copy(model)
        dry.reservoirs, dry.fe_reservoirs = [], []
        variants = [("with the reservoir's added mass", model),
                    ("without the added mass (empty reservoir)", dry)]  # fmt: skip
    out = []
    axes = "xyz"[: model.dim]
    for label, m in variants:
        try:
            r = modal(m, n_modes, interfaces="bonded")
        except (PfeieError, RuntimeError, ValueError) as exc:  # (ARPACK's: RuntimeError)
            log.info("report: no modal table: %s", exc)
            return [], str(exc)
        cum = np.cumsum(r.effective_mass, axis=0)
        total = np.maximum(r.total_mass, 1e-300)
        rows = []
        rigid, periods = r.rigid, r.periods
        for k, f in enumerate(r.frequencies):
            row: dict[str, Any] = {"mode": k + 1,
                                   "f (Hz)": "rigid" if rigid[k] else f"{f:.4f}",
                                   "T (s)": "∞" if rigid[k] else f"{periods[k]:.4f}"}  # fmt: skip
            for i, a in enumerate(axes):
                row[f"m_{a} (%)"] = f"{100 * r.effective_mass[k, i] / total[i]:.2f}"
                row[f"cumulative {a} (%)"] = f"{100 * cum[k, i] / total[i]:.2f}"
            if np.isfinite(r.damping_ratios).any():
                z = r.damping_ratios[k]
                row["ζ (%)"] = f"{100 * z:.2f}" if np.isfinite(z) else "–"
            rows.append(row)
        out.append((label, rows))
    return out, ""


def static_stress(res: Results, job: Job) -> list[tuple[str, np.ndarray]]:
    """The principal stresses of the static state at the nodes (σ₁ and σ₃, MPa, tension
    positive; :meth:`pfeie.Model.nodal_stress` of the static displacements)."""
    from ..assembly import VOIGT, principal_extremes

    u = np.asarray(res.f["static/u"])
    S = job.model.nodal_stress(u)
    voigt = np.stack([S[:, i, j] for i, j in VOIGT], axis=1)
    hi, lo = principal_extremes(voigt)
    return [
        ("static σ1 (largest principal stress)", 1e-6 * hi),
        ("static σ3 (smallest principal stress)", 1e-6 * lo),
    ]


def _table(rows: list[dict[str, Any]]) -> list[str]:
    """An HTML table of rows of equal keys (floats with 4 significant digits; an
    infinite one, a safety factor without shear, as ∞, as the text summary gives it)."""
    esc = html.escape
    if not rows:
        return []

    def number(x: float) -> str:
        return ("∞" if x > 0 else "−∞") if math.isinf(x) else f"{x:.4g}"

    keys = list(dict.fromkeys(k for r in rows for k in r))
    out = ["<table><tr>" + "".join(f"<th>{esc(k)}</th>" for k in keys) + "</tr>"]
    for row in rows:
        cells = "".join(
            f"<td>{number(row[k])}</td>" if isinstance(row.get(k), float)
            else f"<td>{esc(str(row.get(k, '')))}</td>" for k in keys
        )  # fmt: skip
        out.append(f"<tr>{cells}</tr>")
    out.append("</table>")
    return out


def _history_caption(name: str) -> str:
    """The caption of a history figure of the report, by its file's stem."""
    if name.startswith("probe_"):
        return (f"Probe {name[len('probe_'):]}: displacement relative to the ground from the "
                "start of the run (the static state subtracted) and absolute acceleration, "
                "per component.")  # fmt: skip
    if name.startswith("joint_"):
        return (f"Joint {name[len('joint_'):]} over time: the largest and the area-mean slip "
                "since the start of the run, the largest opening, the shares of its area "
                "broken, sliding and open, the cracked length and the open crack, and the "
                "sliding safety factor.")  # fmt: skip
    return {"rigid_motion": "Rigid motion of each block's centroid from the start of the "
                            "run: translations and rotation (one colour per block).",
            "energy": "The energy account: the work of the loads and where it went (kinetic, "
                      "strain, damping, friction and contact, impact, the time scheme's), "
                      "and the balance."}.get(name, "")  # fmt: skip


def _warnings(meta: dict[str, Any]) -> list[str]:
    """The run's reliability warnings (the summary's, ``warnings``: a block thrown off its
    joints, a large slip, the scheme's dissipation, the position corrections' energy),
    first on the page, where a reader of the figures meets them."""
    warns = (meta.get("results_summary") or {}).get("warnings") or []
    if not warns:
        return []
    esc = html.escape
    items = [
        f"<li><b>{esc(str(w.get('label', '')))}</b>: "
        f"{esc(str(w.get('text', ''))).replace(chr(10), '<br>')}</li>"
        for w in warns
    ]
    return [
        "<div class='note'><p><b>Warnings on the reliability of these results</b> (as "
        "the run's summary gives them):</p><ul>",
        *items,
        "</ul></div>",
    ]


def _heading(level: int, text: str, anchor: str) -> str:
    return f"<a id='{anchor}'></a><h{level}>{html.escape(text)}</h{level}>"


def _pairs_table(rows: list[tuple[str, str]]) -> list[str]:
    esc = html.escape
    return ["<table>", *[f"<tr><th>{esc(k)}</th><td>{esc(str(v))}</td></tr>" for k, v in rows],
            "</table>"]  # fmt: skip


def _image(name: str, data: str, caption: str = "") -> str:
    esc = html.escape
    cap = f"<figcaption>{esc(caption)}</figcaption>" if caption else ""
    return f"<figure><img alt='{esc(name)}' src='data:image/png;base64,{data}'>{cap}</figure>"


#: the captions of the figures of a 3D model (drawn by :mod:`pfeie.plot._plots`: the
#: boundary faces in the view :data:`pfeie.plot._plots.VIEW_3D`, the joints in their planes)
CAPTIONS_3D = {
    "mesh": "The boundary faces of the mesh coloured by body, seen from upstream (−x), the "
            "−y side and above, equal scaling; the interface pairs (drawn through the faces) "
            "and the probes.",
    "loads": "The loads on the boundary faces: each face shaded by the normal pressure the "
             "loads put on it (hydrostatic, silt, pressures; kPa); the faces with the "
             "reservoir's added mass edged in cyan; the water levels; the pairs with a static "
             "uplift; gravity at the centre of mass; the supports.",
    "static_stress": "Principal stresses of the static state (MPa, tension positive) "
                     "painted on the boundary faces (a face: the mean of its corner nodes); "
                     "the stars mark the extremes over all the nodes, inside ones included.",
    "joint_map": "Each joint in its own plane (a pair: its tributary cell, the Voronoi cell "
                 "of its point within the joint): the "
                 "pair states of the static state and at the end (broken pairs crossed), the "
                 "largest opening of the run and the residual slip.",
    "envelope": "The largest σ1 and the smallest σ3 of the run (MPa, tension positive; static "
                "state included) painted on the boundary faces (a face: the mean of its corner "
                "nodes); the colour bar spans the extremes over all the nodes, which the stars "
                "mark.",
}  # fmt: skip

#: the sections of the report, in order: anchor and heading
SECTIONS = (
    ("mesh", "Geometry and mesh"), ("materials", "Materials"), ("loads", "Loads"),
    ("static", "Static state (before the shaking)"), ("input", "Input motion"),
    ("modal", "Modal analysis"), ("analysis", "Analysis"), ("histories", "Histories"),
    ("joints", "Joints"), ("joint-maps", "Joint maps"), ("envelope", "Stress envelope"),
    ("dcr", "Demand-capacity ratio and cumulative inelastic duration"),
)  # fmt: skip


def model_figures(
    res: Results, job: Job | None, folder: Path, title: str, joints: bool = True
) -> dict[str, Path]:
    """The figures of a run beyond :func:`~pfeie.plot.plot_all`'s, written into
    ``folder`` and returned by name: with the model of the run (``job``,
    :func:`model_of_run`) the loads (``loads.png``) and the principal stresses of the
    static state (``static_stress.png``); with a static state and ``joints``, each
    joint's static pair states and forces (``static_<joint>.png``; a static-only run has
    them from ``plot_all``)."""
    two_d = res.f["mesh/points"].shape[1] == 2
    extra: dict[str, Path] = {}
    if job is not None:
        extra["loads"] = (plot_loads if two_d else plot_loads_3d)(
            res, job.model, job.spec, folder / "loads.png", title)  # fmt: skip
        if "static/u" in res.f:
            head = f"{title}\nprincipal stresses of the static state (tension +)"
            extra["static_stress"] = (
                plot_fields(res, static_stress(res, job), folder / "static_stress.png",
                            head) if two_d else
                plot_fields_3d(res, static_stress(res, job),
                               folder / "static_stress.png", f"{head}, on the "
                               "boundary faces"))  # fmt: skip
    if joints:
        for name in res.interface_names if "static/X" in res.f else []:
            extra[f"static_{name}"] = plot_static(res, name, folder / figure_file("static", name),
                                                  title)  # fmt: skip
    return extra


def plot_run(results: str | Path, folder: str | Path) -> list[Path]:
    """``pfeie plot``: every figure of a results file (:func:`~pfeie.plot.plot_all`) and
    those of :func:`model_figures` (the loads and the static stresses where the model
    file of the run is found, the static joint states), into ``folder``; returns the
    files written. Where the model file is not found, the log says why its figures are
    missing."""
    files = plot_all(results, folder)
    with Results(results) as res:
        job, source = model_of_run(res)
        if job is None:
            log.info("%s: no loads or static-stress figures: %s", res.path, source)
        title = run_title(res.meta)
        extra = model_figures(res, job, Path(folder), title, joints=res.n_times > 0)
    return files + list(extra.values())


def write_report(results: str | Path, out: str | Path | None = None, where: str = "") -> Path:
    """Write ``report.html`` beside the results file (or at ``out``): one self-contained
    page (figures embedded as PNG) with the sections of :data:`SECTIONS`: the geometry and
    mesh, the materials and joint laws, the loads (table and figure), the static state
    (joint states, safety factors, principal stresses), the input motion and its
    spectrum, the modal table, the analysis (Δt, scheme, solver statistics), the
    histories, the joints' results and maps, the stress envelope and the EM 1110-2-6053
    evaluation. The sections that need the model (the materials' values, the loads, the
    modal table, the static stresses) rebuild it from the model file of the run
    (:func:`model_of_run`); without it the page says why they are missing. A 3D model's
    figures are drawn in 3D (:mod:`pfeie.plot._plots`: the boundary faces in a fixed
    view, the loads and the stress fields on them, each joint in its own plane), with the
    captions of :data:`CAPTIONS_3D`.

    The output location is checked before any work (after the results file): an
    :class:`~pfeie.errors.InputError` names it (after ``where``, e.g. ``--out``)."""
    rpath = Path(results)
    target = Path(out) if out is not None else rpath.parent / "report.html"
    with Results(rpath) as res:  # a file that is not a results file is refused first
        output_file(target, where)  # then an output that cannot be written, before the work
        meta = res.meta
        summ = meta["model_summary"]
        job, source = model_of_run(res)
        two_d = res.f["mesh/points"].shape[1] == 2
        has_static = "static/u" in res.f
        joints = joint_table(res)
        blocks, probes = motion_tables(res)
        static = static_joint_table(res, job) if res.n_times else []
        if not res.n_times:
            joints = static_joint_table(res, job)
        analysis = analysis_rows(res)
        recs = record_rows(res)
        envelope = envelope_rows(res)
        dcr = demand_capacity_rows(res)
        t_end = float(res.time[-1]) if res.time.size else 0.0
        static_only = res.n_times == 0
        mesh_rows = model_rows(res, job)
        materials = material_rows(res, job)
        joint_laws = joint_property_rows(res, job)
        loads = load_rows(res, job) if job is not None else []
        modes, why = modal_tables(job) if job is not None else ([], "")
        title = run_title(meta)
        extra: dict[str, Path] = {}
        with tempfile.TemporaryDirectory() as tmp:
            folder = Path(tmp)
            extra = model_figures(res, job, folder, title, joints=not static_only)
            try:
                figs = plot_all(rpath, folder / "all")
            except ResultsError:  # nothing to plot (static run without interfaces)
                figs = []
            images = {f.stem: base64.b64encode(f.read_bytes()).decode()
                      for f in [*extra.values(), *figs]}  # fmt: skip
    esc = html.escape
    # the reason as the file gives it ("stopped: SIGINT", or the failure's own words)
    reason = str(meta.get("stop_reason", "")).removeprefix("stopped: ")
    status = "completed" if meta["completed"] else f"stopped: {reason}"
    if static_only:  # a static analysis that failed says so, not "static state only"
        run = "static state only" if meta["completed"] else status
    else:
        run = f"{status} at t = {t_end:.3f} s"
    # (bold in the line under the title; plain text in the table, which escapes it)
    run_html = esc(run).replace("stopped:", "<b>stopped</b>:", 1)
    used: set[str] = set()

    def figure(name: str, caption: str = "") -> list[str]:
        if name not in images:
            return []
        used.add(name)
        return [_image(name, images[name], caption if two_d else CAPTIONS_3D.get(name, caption))]

    def missing(what: str) -> list[str]:
        return [f"<p class='note'>{esc(what)}: not available: {esc(source)}.</p>"]

    parts = [
        "<!DOCTYPE html><html><head><meta charset='utf-8'>",
        f"<title>{esc(title)}</title>",
        "<style>body{font-family:sans-serif;max-width:1000px;margin:2em auto;color:#222}"
        "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #ccc;"
        "padding:4px 8px;text-align:left}th{background:#f3f3f3}img{max-width:100%}"
        "figure{margin:1em 0}figcaption{font-size:90%;color:#555}.note{color:#a33}"
        "h2{border-bottom:1px solid #ccc;margin-top:2em}</style></head><body>",
        f"<h1>{esc(title or 'a run of the Python API')}</h1>",
        f"<p>pfeie {esc(str(meta['pfeie_version']))}; run {run_html}; Δt = "
        f"{esc(str(summ['dt']))} s; model file {esc(str(meta['model_file']))}.</p>",
        *_warnings(meta),
        "<nav><ol>",
        *[f"<li><a href='#{a}'>{esc(h)}</a></li>" for a, h in SECTIONS],
        "</ol></nav>",
        # -- geometry and mesh
        _heading(2, "Geometry and mesh", "mesh"),
        *_pairs_table([*mesh_rows, ("time step Δt", f"{summ['dt']} s"), ("run", run)]),
        *figure("mesh", "The mesh coloured by body, the interface pairs and the probes."),
        # -- materials
        _heading(2, "Materials", "materials"),
        *_table(materials),
    ]
    if job is None:
        parts += missing("the materials' table from the model file")
    if joint_laws:
        parts += ["<h3>Joints</h3>", *_table(joint_laws)]
    parts.append(_heading(2, "Loads", "loads"))
    if job is None:
        parts += missing("the loads")
    else:
        parts += _table(loads)
        if summ["dimension"] == 2:
            t = job.spec["thickness"]
            parts.append(f"<p>Resultants of the loads on the model (in 2D per the thickness "
                         f"{t:g} m); the uplift's on the upper side of its joint, from the "
                         "static state.</p>")  # fmt: skip
        parts += figure("loads", "The loads: the pressure diagrams (hydrostatic, silt) on the "
                        "faces they push on, drawn on the side of the water, to one scale; the "
                        "faces with the reservoir's added mass; the static uplift along its "
                        "joint; gravity at the centre of mass; the supports.")  # fmt: skip
    parts.append(_heading(2, "Static state (before the shaking)", "static"))
    if static:
        parts += _table(static)
    elif static_only and joints:
        parts += _table(joints)
    elif not has_static and not meta["completed"]:
        parts.append(f"<p>No static state: the run stopped before it was written "
                     f"({esc(str(meta.get('stop_reason', '')))}).</p>")  # fmt: skip
    elif not has_static:
        parts.append("<p>No static state (analysis.static = false).</p>")
    parts += figure("static_stress", "Principal stresses of the static state at the nodes "
                    "(MPa, tension positive).")  # fmt: skip
    for name in [k for k in images if k.startswith("static_") and k != "static_stress"]:
        parts += figure(name, f"Normal and shear stress of the static state along "
                        f"{name[len('static_'):]}, with the pair states.")  # fmt: skip
    parts += [
        _heading(2, "Input motion", "input"),
        "<ul>",
        *[f"<li>{esc(r)}</li>" for r in summ.get("records", [])],
        "</ul>",
        *_table(recs),
    ]
    if not summ.get("records"):
        parts.append("<p>No ground motion.</p>")
    parts += figure("input_motion", "Ground acceleration and its elastic response spectrum "
                    "(PSa, 5 % damping).")  # fmt: skip
    parts.append(_heading(2, "Modal analysis", "modal"))
    if job is None:
        parts += missing("the modal table")
    elif not modes:
        parts.append(f"<p>No modal analysis: {esc(why)}.</p>")
    for label, rows in modes:
        if label:
            parts.append(f"<h3>{esc(label[0].upper() + label[1:])}</h3>")
        parts += _table(rows)
    if modes:
        parts.append("<p>The joints bonded (rigid joints tie their faces, joints with "
                     "stiffnesses act as springs); effective modal masses as shares of the "
                     "free mass; ζ the Rayleigh damping ratio of each mode "
                     "(<code>pfeie modal</code> gives more modes and their "
                     "shapes).</p>")  # fmt: skip
    parts += [_heading(2, "Analysis", "analysis"), *_pairs_table(analysis)]
    parts.append(_heading(2, "Histories", "histories"))
    hist = [k for k in images if k.startswith(("probe_", "joint_")) and k != "joint_map"]
    hist += [k for k in ("rigid_motion", "energy") if k in images]
    if not hist:
        parts.append("<p>No histories (a static-only run).</p>")
    for name in hist:
        parts += figure(name, _history_caption(name))
    if probes:
        parts += ["<h3>Probes</h3>", *_table(probes)]
    if blocks:
        parts += ["<h3>Blocks held by their joints: permanent displacement</h3>",
                  *_table(blocks)]  # fmt: skip
    parts.append(_heading(2, "Joints", "joints"))
    if joints:
        parts += _table(joints)
    else:
        parts.append("<p>No interfaces.</p>")
    parts.append(_heading(2, "Joint maps", "joint-maps"))
    parts += figure("joint_map", "Along each joint: the largest opening and slip of the run, "
                    "the residual slip, and the pair states of the static state and at the "
                    "end.")  # fmt: skip
    for name in [k for k in images if k.startswith("states_")]:
        parts += figure(name, "Pair states along the joint over time.")
    if "joint_map" not in images:
        parts.append("<p>No joint maps (no interfaces, or no histories).</p>")
    parts.append(_heading(2, "Stress envelope", "envelope"))
    if envelope:
        parts += _pairs_table(envelope)
        parts.append("<p>Per node and cell in results.h5 (/envelope) and envelope.vtu.</p>")
        parts += figure("envelope", "The largest σ1 and the smallest σ3 of the run at every "
                        "node (MPa, tension positive; static state included); the stars mark "
                        "the extremes.")  # fmt: skip
    else:
        parts.append("<p>No stress envelope (a static-only run, or output.envelope = "
                     "false).</p>")  # fmt: skip
    parts.append(_heading(2, "Demand-capacity ratio and cumulative inelastic duration", "dcr"))
    if dcr:
        parts += _pairs_table(dcr)
        parts.append("<p>USACE EM 1110-2-6053, linear time-history evaluation of a "
                     "gravity dam: DCR = σ1/f_t per cell (the total stress, static state "
                     "included; f_t the materials' tensile_strength); CID the time during "
                     "which σ1 > f_t. Per cell in results.h5 (/envelope/cells/dcr, cid) and "
                     "envelope.vtu.</p>")  # fmt: skip
    else:
        parts.append("<p>No evaluation (no material with a tensile_strength, or no "
                     "envelope).</p>")  # fmt: skip
    rest = [k for k in images if k not in used]
    if rest:
        parts.append("<h2>Other figures</h2>")
        for name in rest:
            parts += figure(name)
    parts.append("</body></html>")
    try:
        target.write_text("\n".join(parts), encoding="utf-8", errors="backslashreplace")
    except OSError as exc:
        raise InputError(f"{target}: cannot write the report: {exc.strerror or exc}") from None
    return target
