"""Tidy CSV tables of a results file (one observation per row).

A run with histories gives probes.csv, bodies.csv, ground.csv (the ground's displacement
as the run moved it: subtract it from a probe's or a body's motion in the absolute form),
energy.csv, joints.csv (per joint and time: largest and mean slip, largest opening, the
area-mean relative displacement of its faces w_t…, w_n since the start, the sliding
safety factor, the shares broken, sliding and open), joint_pieces.csv (for a joint whose
pairs join more than two blocks, the same per pair of blocks "A | B") and pairs_final.csv
(per pair, its final relative displacement and its blocks among others); a static-only run
(``analysis.dynamic = false``) gives the static state: nodes_static.csv (displacements)
and pairs_static.csv (the pair state of every joint).
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from ..errors import ResultsError
from ._files import output_folder
from ._results import Results

AXES = "xyz"


def export_csv(results: str | Path, folder: str | Path) -> list[Path]:
    """Write probes.csv, bodies.csv, ground.csv, energy.csv, joints.csv,
    joint_pieces.csv and pairs_final.csv (or, for a static-only run, nodes_static.csv and
    pairs_static.csv); ground.csv only from a file that records the ground (format 1.10
    and later), joint_pieces.csv only for a joint whose pairs join more than two blocks."""
    with Results(results) as res:
        if res.n_times == 0:
            return _export_static(res, folder)
        out = output_folder(folder)
        files = []
        t = res.time
        path = out / "probes.csv"
        with path.open("w", newline="", encoding="utf-8") as fh:
            w = csv.writer(fh)
            w.writerow(["time_s", "probe", "quantity", "component", "value", "unit"])
            units = {"u": "m", "v": "m/s", "a": "m/s^2", "a_abs": "m/s^2"}
            for name in res.probe_names:
                p = res.probe(name)
                for q, arr in p.items():
                    for i in range(arr.shape[1]):
                        for ti, val in zip(t, arr[:, i], strict=True):
                            w.writerow([f"{ti:.12g}", name, q, AXES[i], f"{val:.9g}", units[q]])
        files.append(path)
        path = out / "bodies.csv"
        rig = np.asarray(res.f["history/rigid"][...])
        d = int(res.f["mesh/points"].shape[1])
        dof_names = ["ux", "uy", "rz"] if d == 2 else ["ux", "uy", "uz", "rx", "ry", "rz"]
        with path.open("w", newline="", encoding="utf-8") as fh:
            w = csv.writer(fh)
            w.writerow(["time_s", "body", "dof", "value", "unit"])
            for b, name in enumerate(res.body_names):
                for k, dn in enumerate(dof_names):
                    unit = "rad" if dn.startswith("r") else "m"
                    for ti, val in zip(t, rig[:, b, k], strict=True):
                        w.writerow([f"{ti:.12g}", name, dn, f"{val:.9g}", unit])
        files.append(path)
        ground = res.ground
        if ground is not None:
            path = out / "ground.csv"
            with path.open("w", newline="", encoding="utf-8") as fh:
                w = csv.writer(fh)
                w.writerow(["time_s", "component", "value", "unit"])
                for i in range(ground.shape[1]):
                    for ti, val in zip(t, ground[:, i], strict=True):
                        w.writerow([f"{ti:.12g}", AXES[i], f"{val:.9g}", "m"])
            files.append(path)
        path = out / "energy.csv"
        with path.open("w", newline="", encoding="utf-8") as fh:
            w = csv.writer(fh)
            w.writerow(["time_s", "term", "value_J"])
            for term, arr in res.energy().items():
                for ti, val in zip(t, arr, strict=True):
                    w.writerow([f"{ti:.12g}", term, f"{val:.9g}"])
        files.append(path)
        if res.interface_names:
            path = out / "joints.csv"
            final = out / "pairs_final.csv"
            with (
                path.open("w", newline="", encoding="utf-8") as fh,
                final.open("w", newline="", encoding="utf-8") as fh2,
            ):
                w = csv.writer(fh)
                w.writerow(["time_s", "joint", "quantity", "value", "unit"])
                w2 = csv.writer(fh2)
                coords = [f"{a}_m" for a in AXES[:d]]
                axes = [*(f"t{i + 1}" for i in range(d - 1)), "n"]
                w2.writerow(["joint", "pair", *coords, "area_m2", "residual_slip_m",
                             "max_opening_m", *(f"final_w_{a}_m" for a in axes),
                             "final_state", "broken", "blocks"])  # fmt: skip
                pieces: dict[str, dict[str, np.ndarray]] = {}
                for name in res.interface_names:
                    pr = res.pairs(name)
                    A = pr["area"]
                    slip = np.linalg.norm(pr["slip"], axis=-1)
                    by = res.joint_pieces(name)
                    blocks = _blocks(by, A.size)
                    if len(by) > 1:
                        pieces[name] = by
                    share = res.joint_shares(name)
                    series = {
                        ("slip_max", "m"): slip.max(axis=1),
                        ("slip_mean", "m"): (slip * A).sum(axis=1) / A.sum(),
                        ("opening_max", "m"): pr["opening"].max(axis=1),
                        ("broken_share", "-"): share["broken"],
                        ("sliding_share", "-"): share["sliding"],
                        ("open_share", "-"): share["open"],  # (Results.joint_shares)
                    }
                    # the relative displacement of the joint's faces (side b minus side a,
                    # local axes t…, n; n + opening), area mean, since the start of the run
                    rel = (pr["w"] * A[None, :, None]).sum(axis=1) / A.sum()
                    rel = rel - rel[:1]
                    for i, a in enumerate(axes):
                        series[(f"w_{a}_mean", "m")] = rel[:, i]
                    if "history/joints/safety_factor" in res.f:
                        fs = np.asarray(res.f["history/joints/safety_factor"][...])
                        series[("safety_factor", "-")] = fs[:, res.interface_names.index(name)]
                    if "history/joints/force" in res.f:
                        jr = res.joint_resultants(name)
                        for i, a in enumerate("xyz"[: jr["force"].shape[1]]):
                            series[(f"force_{a}", "N")] = jr["force"][:, i]
                        mom = jr["moment"]
                        for i in range(mom.shape[1]):
                            axis = "z" if mom.shape[1] == 1 else "xyz"[i]
                            series[(f"moment_{axis}", "N*m")] = mom[:, i]
                    for (qn, unit), arr in series.items():
                        for ti, val in zip(t, arr, strict=True):
                            w.writerow([f"{ti:.12g}", name, qn, f"{val:.9g}", unit])
                    names = ["intact", "stick", "slide", "open"]
                    for k in range(A.size):
                        xk = [f"{c:.9g}" for c in pr["x"][k]]
                        w2.writerow(
                            [
                                name,
                                k,
                                *xk,
                                f"{A[k]:.9g}",
                                f"{slip[-1, k]:.9g}",
                                f"{pr['opening'][:, k].max():.9g}",
                                # since the start of the run, as residual_slip_m and
                                # joints.csv's w_*_mean (not the springs' closure under
                                # the static loads)
                                *(f"{v:.9g}" for v in pr["w"][-1, k] - pr["w"][0, k]),
                                names[int(pr["state"][-1, k])],
                                int(pr["broken"][-1, k]),
                                blocks[k],
                            ]
                        )
            files += [path, final]
            if pieces:
                files.append(_export_pieces(res, pieces, out / "joint_pieces.csv"))
    return files


def _blocks(pieces: dict[str, np.ndarray], m: int) -> list[str]:
    """The blocks "A | B" that each of a joint's ``m`` pairs joins ("" without
    ``/mesh/body`` in the file)."""
    out = [""] * m
    for label, k in pieces.items():
        for i in k:
            out[int(i)] = label
    return out


def _export_pieces(res: Results, pieces: dict[str, dict[str, np.ndarray]], path: Path) -> Path:
    """joint_pieces.csv: per joint in several pieces (its pairs join more than two blocks:
    a contraction joint cut by a lift joint) and per piece "A | B", over time: the
    largest and the area-mean slip, the largest opening and the broken share."""
    t = res.time
    with path.open("w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow(["time_s", "joint", "blocks", "quantity", "value", "unit"])
        for name, by in pieces.items():
            pr = res.pairs(name)
            slip = np.linalg.norm(pr["slip"], axis=-1)
            for label, k in by.items():
                A = pr["area"][k]
                series = {
                    ("slip_max", "m"): slip[:, k].max(axis=1),
                    ("slip_mean", "m"): (slip[:, k] * A).sum(axis=1) / A.sum(),
                    ("opening_max", "m"): pr["opening"][:, k].max(axis=1),
                    ("broken_share", "-"): (pr["broken"][:, k] * A).sum(axis=1) / A.sum(),
                }
                for (qn, unit), arr in series.items():
                    for ti, val in zip(t, arr, strict=True):
                        w.writerow([f"{ti:.12g}", name, label, qn, f"{val:.9g}", unit])
    return path


def _export_static(res: Results, folder: str | Path) -> list[Path]:
    """The static state of a results file without histories."""
    if not res.has_static:
        raise ResultsError(
            f"{res.path}: nothing to export: no time history and no static "
            "state (expected the results of a static or dynamic run)"
        )
    out = output_folder(folder)
    u = np.asarray(res.f["static/u"][...])
    x = np.asarray(res.f["mesh/points"][...])
    d = x.shape[1]
    path = out / "nodes_static.csv"
    with path.open("w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow(["node", *(f"{a}_m" for a in AXES[:d]), *(f"u{a}_m" for a in AXES[:d])])
        for k in range(x.shape[0]):
            w.writerow([k, *(f"{c:.9g}" for c in x[k]), *(f"{c:.9g}" for c in u[k])])
    files = [path]
    if res.interface_names and "static/X" in res.f:
        path = out / "pairs_static.csv"
        names = ["intact", "stick", "slide", "open"]
        with path.open("w", newline="", encoding="utf-8") as fh:
            w = csv.writer(fh)
            # the shear stress in the pair's axes, signed: along t (2D), t1 and t2 (3D)
            tangents = ["shear_stress_Pa"] if d == 2 else ["shear_stress_t1_Pa",
                                                          "shear_stress_t2_Pa"]  # fmt: skip
            w.writerow(["joint", "pair", *(f"{a}_m" for a in AXES[:d]), "area_m2",
                        "normal_stress_Pa", *tangents, "opening_m", "state",
                        "broken", "blocks"])  # fmt: skip
            for name in res.interface_names:
                pr = res.static_pairs(name)
                blocks = _blocks(res.joint_pieces(name), pr["area"].size)
                for k in range(pr["area"].size):
                    w.writerow([name, k, *(f"{c:.9g}" for c in pr["x"][k]),
                                f"{pr['area'][k]:.9g}", f"{pr['normal_stress'][k]:.9g}",
                                *(f"{c:.9g}" for c in pr["shear_stress"][k]),
                                f"{pr['opening'][k]:.9g}",
                                names[int(pr["state"][k])], int(pr["broken"][k]),
                                blocks[k]])  # fmt: skip
        files.append(path)
    return files
