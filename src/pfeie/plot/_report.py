"""A single self-contained HTML page: model, records, figures, joint results."""

from __future__ import annotations

import base64
import html
import json
import tempfile
from pathlib import Path
from typing import Any

import numpy as np

from ..dynamics import envelope_extremes
from ..errors import InputError, ResultsError
from ..io import Results, output_file
from ._plots import plot_all


def joint_table(res: Results) -> list[dict[str, Any]]:
    """Per joint: pairs, residual slip (largest, area mean), largest opening, broken share
    (for a static-only run: the static state, :func:`static_joint_table`)."""
    if res.n_times == 0:
        return static_joint_table(res)
    rows = []
    for name in res.interface_names:
        pr = res.pairs(name)
        A = pr["area"]
        slip = np.linalg.norm(pr["slip"][-1], axis=-1)
        rows.append({
            "joint": name, "pairs": int(A.size),
            "residual slip, largest (mm)": 1e3 * float(slip.max()),
            "residual slip, mean (mm)": 1e3 * float((slip * A).sum() / A.sum()),
            "largest opening (mm)": 1e3 * float(pr["opening"].max()),
            "broken (%)": 100 * float((pr["broken"][-1] * A).sum() / A.sum()),
        })  # fmt: skip
        if "joints/safety_factor" in res.f["history"]:
            fs = np.asarray(res.f["history/joints/safety_factor"])[:, len(rows) - 1]
            rows[-1]["min safety factor"] = float(fs.min())
        if "joints/cracked" in res.f["history"]:
            cr = res.joint_cracks(name)
            unit = "m" if res.f["mesh/points"].shape[1] == 2 else "m²"
            rows[-1][f"cracked at the end ({unit})"] = float(cr["cracked"][-1])
            rows[-1][f"largest open crack ({unit})"] = float(cr["open"].max())
        if "joints/force" in res.f["history"]:
            jr = res.joint_resultants(name)
            rows[-1]["peak |F_x| (kN)"] = 1e-3 * float(np.abs(jr["force"][:, 0]).max())
            rows[-1]["peak |M| (kN m)"] = 1e-3 * float(
                np.linalg.norm(jr["moment"], axis=1).max())  # fmt: skip
    return rows


def envelope_rows(res: Results) -> list[tuple[str, str]]:
    """The extremes of the stress envelope: the largest σ₁ and the smallest σ₃ over the
    nodes, where and when (empty without an envelope)."""
    ext = envelope_extremes(res.envelope(), np.asarray(res.f["mesh/points"]))
    if ext is None:
        return []
    out = []
    for name, label in (("max_principal", "largest principal stress σ1"),
                        ("min_principal", "smallest principal stress σ3")):  # fmt: skip
        where = ", ".join(f"{x:g}" for x in ext[f"{name}_at_m"])
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
        return "(" + ", ".join(f"{x:g}" for x in dc[key]) + ") m"

    words = {
        "linear": "linear: the stresses stay below the tensile strength (DCR ≤ 1)",
        "acceptable": f"acceptable by the linear analysis: DCR ≤ {DCR_LIMIT:g}, CID ≤ "
                      f"{CID_LIMIT:g} s, overstressed ≤ {100 * OVERSTRESSED_LIMIT:g} %",
        "nonlinear analysis required": f"beyond the linear criteria (DCR ≤ {DCR_LIMIT:g}, "
                      f"CID ≤ {CID_LIMIT:g} s, overstressed ≤ {100 * OVERSTRESSED_LIMIT:g} "
                      "%): a nonlinear analysis is required",
    }  # fmt: skip
    return [
        ("largest demand-capacity ratio σ1/f_t",
         f"{dc['max_dcr']:.3g} at {at('max_dcr_at_m')}, t = {dc['max_dcr_time_s']:.3f} s"),
        ("largest cumulative inelastic duration",
         f"{dc['max_cid_s']:.3g} s at {at('max_cid_at_m')}"),
        ("overstressed share (DCR > 1)",
         f"{100 * dc['overstressed_share']:.3g} % of the cells with a tensile strength"),
        ("EM 1110-2-6053", words.get(dc["verdict"], dc["verdict"])),
    ]  # fmt: skip


def static_joint_table(res: Results) -> list[dict[str, Any]]:
    """Per joint, the static state: pairs, mean normal stress, largest opening, shares
    sliding, open and broken (empty without a static pair state)."""
    if "static/X" not in res.f:
        return []
    rows = []
    for name in res.interface_names:
        pr = res.static_pairs(name)
        A = pr["area"]
        rows.append({
            "joint": name, "pairs": int(A.size),
            "static normal stress, mean (MPa)": 1e-6 * float((pr["X"][:, -1]).sum() / A.sum()),
            "largest opening (mm)": 1e3 * float(pr["opening"].max()),
            "sliding (%)": 100 * float(((pr["state"] == 2) * A).sum() / A.sum()),
            "open (%)": 100 * float(((pr["state"] == 3) * A).sum() / A.sum()),
            "broken (%)": 100 * float((pr["broken"] * A).sum() / A.sum()),
        })  # fmt: skip
        k = len(rows) - 1
        if "history/joints/safety_factor" in res.f and res.n_times:
            rows[-1]["sliding safety factor"] = float(res.f["history/joints/safety_factor"][0, k])
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
    return rows


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
    sv = summ.get("solver")
    if sv:
        out.append(("pair solver", f"{sv['iterations_mean']} iterations a step; "
                    f"{sv['fallback_steps']} step(s) needed a fallback; worst residual "
                    f"{sv['worst_residual']:.1e}"))  # fmt: skip
    if "wall_time_s" in summ:
        out.append(("wall time", f"{summ['wall_time_s']:.1f} s"))
    return out


def record_rows(res: Results) -> list[dict[str, Any]]:
    """Intensity measures of the records of the run (as scaled)."""
    if "records" not in res.f:
        return []
    from ..model import intensity_measures

    rows = []
    for key in sorted(res.f["records"], key=int):
        g = res.f[f"records/{key}"]
        im = intensity_measures(np.asarray(g["time"]), np.asarray(g["acceleration"]))
        rows.append({
            "record": str(g.attrs.get("name", key)), "PGA (g)": im["pga"] / 9.81,
            "PGV (m/s)": im["pgv"], "PGD (m)": im["pgd"], "Arias (m/s)": im["arias"],
            "CAV (m/s)": im["cav"], "D5-95 (s)": im["d5_95"],
        })  # fmt: skip
    return rows


def _table(rows: list[dict[str, Any]]) -> list[str]:
    """An HTML table of rows of equal keys (floats with 3 significant digits)."""
    esc = html.escape
    if not rows:
        return []
    keys = list(dict.fromkeys(k for r in rows for k in r))
    out = ["<table><tr>" + "".join(f"<th>{esc(k)}</th>" for k in keys) + "</tr>"]
    for row in rows:
        cells = "".join(
            f"<td>{row[k]:.4g}</td>" if isinstance(row.get(k), float)
            else f"<td>{esc(str(row.get(k, '')))}</td>" for k in keys
        )  # fmt: skip
        out.append(f"<tr>{cells}</tr>")
    out.append("</table>")
    return out


def write_report(results: str | Path, out: str | Path | None = None) -> Path:
    """Write ``report.html`` beside the results file (or at ``out``); figures embedded."""
    rpath = Path(results)
    target = Path(out) if out is not None else rpath.parent / "report.html"
    with Results(rpath) as res:  # a file that is not a results file is refused first
        meta = res.meta
        summ = meta["model_summary"]
        joints = joint_table(res)
        static = static_joint_table(res) if res.n_times else []
        analysis = analysis_rows(res)
        recs = record_rows(res)
        envelope = envelope_rows(res)
        dcr = demand_capacity_rows(res)
        t_end = float(res.time[-1]) if res.time.size else 0.0
        static_only = res.n_times == 0
    output_file(target)
    with tempfile.TemporaryDirectory() as tmp:
        try:
            figs = plot_all(rpath, tmp)
        except ResultsError:  # nothing to plot (static run without interfaces)
            figs = []
        images = [(f.stem, base64.b64encode(f.read_bytes()).decode()) for f in figs]
    esc = html.escape
    title = summ.get("title") or Path(meta["model_file"]).stem
    status = ("completed" if meta["completed"] else
              f"<b>stopped</b>: {esc(str(meta.get('stop_reason', '')))}")  # fmt: skip
    model_rows = [
        ("model file", meta["model_file"]), ("SHA-256", meta["model_sha256"]),
        ("pfeie", meta["pfeie_version"]), ("dimension", f"{summ['dimension']}D"),
        ("blocks", ", ".join(summ["blocks"])), ("bodies", summ["bodies"]),
        ("cells", summ["cells"]), ("DOF", f"{summ['dof']} ({summ['free_dof']} free)"),
        ("pairs", ", ".join(f"{k}: {v}" for k, v in summ["pairs"].items()) or "none"),
        ("time step", f"{summ['dt']} s"),
        ("run", "static state only" if static_only else f"{status} at t = {t_end:.3f} s"),
        ("ground motion form", meta.get("form", "")),
    ]  # fmt: skip
    parts = [
        "<!DOCTYPE html><html><head><meta charset='utf-8'>",
        f"<title>{esc(title)}</title>",
        "<style>body{font-family:sans-serif;max-width:960px;margin:2em auto;color:#222}"
        "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #ccc;"
        "padding:4px 8px;text-align:left}th{background:#f3f3f3}img{max-width:100%}"
        "</style></head><body>",
        f"<h1>{esc(title)}</h1>",
        "<h2>Model</h2><table>",
        *[f"<tr><th>{esc(k)}</th><td>{esc(str(v))}</td></tr>" for k, v in model_rows],
        "</table><h2>Analysis</h2><table>",
        *[f"<tr><th>{esc(k)}</th><td>{esc(v)}</td></tr>" for k, v in analysis],
        "</table><h2>Ground motion</h2><ul>",
        *[f"<li>{esc(r)}</li>" for r in summ.get("records", [])],
        "</ul>",
        *_table(recs),
    ]
    if static:
        parts.append("<h2>Static state (before the shaking)</h2>")
        parts += _table(static)
    parts.append("<h2>Joints</h2>")
    if joints:
        parts += _table(joints)
    else:
        parts.append("<p>No interfaces.</p>")
    if envelope:
        parts.append("<h2>Stress envelope</h2><table>")
        parts += [f"<tr><th>{esc(k)}</th><td>{esc(v)}</td></tr>" for k, v in envelope]
        parts.append("</table><p>Per node and cell in results.h5 (/envelope) and "
                     "envelope.vtu.</p>")  # fmt: skip
    if dcr:
        parts.append("<h2>Demand-capacity ratio and cumulative inelastic duration</h2><table>")
        parts += [f"<tr><th>{esc(k)}</th><td>{esc(v)}</td></tr>" for k, v in dcr]
        parts.append("</table><p>USACE EM 1110-2-6053, linear time-history evaluation of a "
                     "gravity dam: DCR = σ1/f_t per cell (the total stress, static state "
                     "included; f_t the materials' tensile_strength); CID the time during "
                     "which σ1 > f_t. Per cell in results.h5 (/envelope/cells/dcr, cid) and "
                     "envelope.vtu.</p>")  # fmt: skip
    parts.append("<h2>Figures</h2>")
    for name, data in images:
        parts.append(f"<h3>{esc(name.replace('_', ' '))}</h3>"
                     f"<img alt='{esc(name)}' src='data:image/png;base64,{data}'>")  # fmt: skip
    parts.append("</body></html>")
    try:
        target.write_text("\n".join(parts))
    except OSError as exc:
        raise InputError(f"{target}: cannot write the report: {exc.strerror or exc}") from None
    return target
