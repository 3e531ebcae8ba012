"""Δt convergence of the demo dam (examples/koyna/koyna.toml) under the default time scheme.

Runs the demo through the command line at halved time steps and prints, per
configuration, a markdown table of the quantities an engineer reads (crest peak
displacement and absolute acceleration; per joint the residual slip, the largest opening,
the broken share and the time of the first break), each with its change from the previous
Δt in % of its value, and the wall time:

1. record scale 0.6 (the demo), ρ∞ = 0.5 (the demo's setting) and ρ∞ = 0;
2. unbreakable joints (cohesion and tensile strength 1e10 Pa), ρ∞ = 0 and 0.5: the crest
   peaks against the finest Δt (the elastic response the scheme must not damp);
3. record scale 1.0, ρ∞ = 0.5, down to Δt = 0.625 ms;
4. record scales 0.98, 1.0, 1.02 at Δt = 1.25 ms (the physical sensitivity);
5. scales 0.6 and 1.0 with event sub-steps (``analysis.event_substeps = 4``), with the
   rule of criterion 6.

With ``--fine`` it adds, at record scale 0.6 (about 40 min more on one core):

6. ρ∞ = 0.5 down to Δt = 0.3125 ms and ρ∞ = 0 down to 0.625 ms, and with event
   sub-steps down to 0.625 ms;
7. record scales 0.588, 0.594, 0.6, 0.606, 0.612 (±1 % and ±2 %) at Δt = 2.5 and 1.25 ms,
   with the spread of each quantity in % of its value at 0.6;
8. the time each dam–rock pair breaks during the record, per Δt and per record scale, and
   the first time the runs at coarser Δt part from the finest one (broken set, largest
   slip, largest opening).

    python benchmarks/demo_convergence.py            # everything but 6-8 (about 40 min)
    python benchmarks/demo_convergence.py --quick    # Δt = 20 and 10 ms only
    python benchmarks/demo_convergence.py --fine --out docs/demo-convergence-tables.md

Runs are kept in a work folder (``--work``, default /tmp/pfeie-demo-convergence) and reused
when present, so an interrupted study continues.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import h5py
import numpy as np

ROOT = Path(__file__).resolve().parents[1]
MODEL = ROOT / "examples" / "koyna" / "koyna.toml"
PFEIE = str(Path(sys.executable).with_name("pfeie"))
FINER = [0.000625, 0.0003125]  # --fine: the scale-0.6 study below 1.25 ms
SCALES = (0.588, 0.594, 0.6, 0.606, 0.612)  # --fine: the record's ±1 % and ±2 % at 0.6
# joints made unbreakable: cohesion and tensile strength at the model file's upper bound,
# 1e10 Pa, four orders above the joints' stresses in the demo
UNBREAKABLE = [f"interfaces.{j}.{k}=1e10" for j in ("dam_rock", "neck")
               for k in ("cohesion", "tensile_strength")]  # fmt: skip


# a step in which a pair changes state taken again in four sub-steps (docs/theory.md)
EVENTS = ["analysis.event_substeps=4"]


def run(work: Path, tag: str, dt: float, sets: list[str], scale: float) -> dict[str, Any]:
    """One run (reused if its summary exists): the summary, the first-break times and the
    wall time."""
    out = work / f"{tag}_{dt:g}"
    summary = out / "summary.json"
    if not summary.is_file():
        text = MODEL.read_text().replace("scale = 0.6", f"scale = {scale}")
        model = MODEL.with_name(f"_study_{tag}_{dt:g}.toml")  # beside the mesh and record
        model.write_text(text)
        args = [PFEIE, "run", str(model), "--quiet", "--dt", f"{dt}", "--set",
                f'output.folder="{out}"', "--set", "output.field_every=1000000"]  # fmt: skip
        for s in sets:
            args += ["--set", s]
        env = {**os.environ, "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1"}
        t0 = time.perf_counter()
        proc = subprocess.run(args, capture_output=True, text=True, env=env, check=False)
        wall = time.perf_counter() - t0
        model.unlink()
        if proc.returncode != 0 or not summary.is_file():
            return {"failed": proc.stderr.strip().splitlines()[-1:] or ["no summary"]}
        (out / "wall.txt").write_text(f"{wall}\n")
    s = json.loads(summary.read_text())
    s["wall"] = float((out / "wall.txt").read_text())
    s["first_break"] = first_breaks(out / "results.h5")
    return s


def first_breaks(path: Path) -> dict[str, float]:
    """The time of each joint's first pair that breaks during the record (s), NaN if none
    does (pairs broken in the static state do not count)."""
    out: dict[str, float] = {}
    with h5py.File(path, "r") as f:
        t = f["history/time"][:]
        broken = f["history/pairs/broken"][:]
        names = json.loads(f["pairs"].attrs.get("names", "[]"))
        joint = f["pairs/interface"][:] if "pairs/interface" in f else None
    if joint is None or not names:
        return out
    for k, name in enumerate(names):
        cols = broken[:, joint == k]
        cols = cols & ~cols[:1]  # pairs broken already in the static state do not count
        hit = np.flatnonzero(cols.any(axis=1))
        out[name] = float(t[hit[0]]) if hit.size else float("nan")
    return out


def break_times(path: Path, joint: str) -> tuple[np.ndarray, np.ndarray]:
    """The position along the joint (m, the pair's first coordinate) and the time each pair
    of ``joint`` breaks during the record (s; NaN if it does not, or is broken in the
    static state), sorted by position."""
    with h5py.File(path, "r") as f:
        t = f["history/time"][:]
        names = json.loads(f["pairs"].attrs.get("names", "[]"))
        idx = f["pairs/interface"][:] == names.index(joint)
        broken = f["history/pairs/broken"][:, idx]
        x = f["pairs/x"][:, 0][idx]
    new = broken & ~broken[:1]
    hit = new.any(axis=0)
    when = np.where(hit, t[np.argmax(new, axis=0)], np.nan)
    order = np.argsort(x)
    return x[order], when[order]


def parting(coarse: Path, fine: Path, joint: str) -> dict[str, float]:
    """The first time (s) the run at the coarser Δt parts from the finer one on ``joint``,
    both read at the coarser run's times: its broken set differs; its largest slip
    max|s_t − s_t(0)| differs by more than 2 % of the finer run's final value; its largest
    opening so far, max over pairs and time of max(s_n, 0), by more than 2 % of the finer
    run's. NaN when they do not part."""
    series = []
    for path in (coarse, fine):
        with h5py.File(path, "r") as f:
            t = f["history/time"][:]
            names = json.loads(f["pairs"].attrs.get("names", "[]"))
            idx = f["pairs/interface"][:] == names.index(joint)
            broken = f["history/pairs/broken"][:, idx]
            s = f["history/pairs/s"][:, idx, :]
        slip = np.linalg.norm(s[:, :, :-1] - s[:1, :, :-1], axis=-1).max(axis=1)
        opening = np.maximum.accumulate(np.maximum(s[:, :, -1], 0.0).max(axis=1))
        series.append((t, broken, slip, opening))
    (tc, b0, s0, o0), (tf, b1, s1, o1) = series
    at = np.minimum(np.searchsorted(tf, tc - 1e-9), tf.size - 1)  # the finer run at tc
    b1, s1, o1 = b1[at], s1[at], o1[at]

    def first(mask: np.ndarray) -> float:
        hit = np.flatnonzero(mask)
        return float(tc[hit[0]]) if hit.size else float("nan")

    return {"broken set": first((b0 != b1).any(axis=1)),
            "largest slip": first(np.abs(s0 - s1) > 0.02 * abs(s1[-1])),
            "largest opening": first(np.abs(o0 - o1) > 0.02 * abs(o1[-1]))}  # fmt: skip


def quantities(s: dict[str, Any]) -> dict[str, float]:
    if "failed" in s:
        return {}
    crest = s["probes"]["crest"]  # the horizontal (x) peaks, as in the tables
    q = {"crest disp (mm)": 1e3 * crest["peak_displacement_xyz_m"][0],
         "crest acc (g)": crest.get("peak_abs_acceleration_xyz_g",
                                    [crest["peak_abs_acceleration_g"]])[0]}  # fmt: skip
    for name, j in s.get("joints", {}).items():
        q[f"{name} slip (mm)"] = 1e3 * j.get("residual_slip_max_m", 0.0)
        q[f"{name} opening (mm)"] = 1e3 * j.get("max_opening_m", 0.0)
        if "broken_share" in j:
            q[f"{name} broken"] = j["broken_share"]
        if name in s["first_break"]:
            q[f"{name} first break (s)"] = s["first_break"][name]
    return q


def criterion(rows: list[tuple[float, dict[str, Any]]]) -> list[str]:
    """Markdown rows: the convergence rule of the demo (issue 21, criterion 6) per quantity
    (crest peak displacement, each joint's largest opening, residual slip and first-break
    time). With c_k the change in % of the value from the k-th halving, the rule asks
    |c_k| ≤ 0.7 |c_(k−1)| whenever |c_k| > 0.5 %, and |c| ≤ 2 % between Δt = 5 and
    2.5 ms."""
    qs = [quantities(s) for _, s in rows]
    dts = [dt for dt, _ in rows]
    keys = [k for k in next((list(q) for q in qs if q), [])
            if k.startswith("crest disp") or k.endswith(("opening (mm)", "slip (mm)",
                                                          "first break (s)"))]  # fmt: skip
    lines = ["| quantity | changes (%) | shrinking | 5 → 2.5 ms | met |", "|---|---|---|---|---|"]
    for k in keys:
        v = np.array([q.get(k, np.nan) for q in qs])
        c = 100 * np.diff(v) / np.abs(v[:-1])
        bad = [
            f"{1e3 * dts[i + 1]:g} ms"
            for i in range(1, c.size)
            if abs(c[i]) > 0.5 and abs(c[i]) > 0.7 * abs(c[i - 1])
        ]
        mid = [c[i - 1] for i in range(1, len(dts)) if (dts[i - 1], dts[i]) == (0.005, 0.0025)]
        ok_mid = not mid or abs(mid[0]) <= 2.0
        cells = [
            k,
            ", ".join(f"{x:+.2f}" for x in c),
            "yes" if not bad else "no at " + ", ".join(bad),
            f"{mid[0]:+.2f} %" if mid else "–",
            "yes" if not bad and ok_mid else "no",
        ]
        lines.append("| " + " | ".join(cells) + " |")
    return lines


def table(rows: list[tuple[float, dict[str, Any]]], against_last: bool = False) -> list[str]:
    """Markdown rows: each quantity and its change from the previous Δt (or, with
    ``against_last``, its difference from the finest Δt), in %."""
    qs = [quantities(s) for _, s in rows]
    keys = next((list(q) for q in qs if q), [])
    if against_last:  # unbreakable joints: the crest only (the joints do not move)
        keys = [k for k in keys if k.startswith("crest")]
    head = ["Δt (ms)", *keys, "wall (s)"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    ref = qs[-1] if against_last else None
    prev: dict[str, float] = {}
    for (dt, s), q in zip(rows, qs, strict=True):
        if not q:
            lines.append(f"| {1e3 * dt:g} | failed: {s['failed'][0]} |")
            continue
        cells = [f"{1e3 * dt:g}"]
        for k in keys:
            v = q.get(k, float("nan"))
            base = (ref or {}).get(k) if against_last else prev.get(k)
            if base is not None and base != 0 and np.isfinite(v):
                cells.append(f"{v:.4g} ({100 * (v - base) / abs(base):+.2f} %)")
            else:
                cells.append(f"{v:.4g}")
        cells.append(f"{s['wall']:.1f}")
        lines.append("| " + " | ".join(cells) + " |")
        prev = q
    return lines


def sensitivity(
    work: Path, scales: tuple[float, ...], dt: float, base: float, tags: dict[float, str]
) -> list[str]:
    """Markdown rows: each quantity per record scale at one Δt (ρ∞ = 0.5), and the spread
    (max − min) in % of its value at the ``base`` scale."""
    rows = [(sc, run(work, tags.get(sc, f"sens{sc:g}"), dt, ["analysis.rho_inf=0.5"], sc))
            for sc in scales]  # fmt: skip
    qs = [quantities(s) for _, s in rows]
    keys = list(qs[scales.index(base)])
    lines = ["| scale | " + " | ".join(keys) + " |", "|" + "---|" * (len(keys) + 1),
             *[f"| {sc:g} | " + " | ".join(f"{q.get(k, float('nan')):.4g}" for k in keys)
               + " |" for (sc, _), q in zip(rows, qs, strict=True)]]  # fmt: skip
    ref = qs[scales.index(base)]
    spread = []
    for k in keys:
        v = np.array([q.get(k, np.nan) for q in qs])
        spread.append(f"{100 * (np.nanmax(v) - np.nanmin(v)) / abs(ref[k]):.2f} %"
                      if ref[k] != 0 and np.isfinite(v).any() else "–")  # fmt: skip
    lines.append("| spread | " + " | ".join(spread) + " |")
    return lines


def break_table(work: Path, runs: list[tuple[str, str]], joint: str) -> list[str]:
    """Markdown rows: the time each pair of ``joint`` breaks during the record (s), one row
    per run (label, folder name), one column per pair that breaks in any of them (its
    position along the joint, m)."""
    got = [(label, break_times(work / folder / "results.h5", joint)) for label, folder in runs
           if (work / folder / "results.h5").is_file()]  # fmt: skip
    if not got:
        return []
    x = got[0][1][0]
    cols = np.flatnonzero(np.any([np.isfinite(w) for _, (_, w) in got], axis=0))
    lines = ["| run \\ x (m) | " + " | ".join(f"{x[c]:.1f}" for c in cols) + " |",
             "|" + "---|" * (cols.size + 1)]  # fmt: skip
    for label, (_, w) in got:
        lines.append(f"| {label} | " + " | ".join("–" if np.isnan(w[c]) else f"{w[c]:.4g}"
                                                  for c in cols) + " |")  # fmt: skip
    return lines


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="Δt = 20 and 10 ms only")
    ap.add_argument("--work", type=Path, default=Path("/tmp/pfeie-demo-convergence"))
    ap.add_argument("--out", type=Path, default=None, help="also write the tables here")
    ap.add_argument("--fresh", action="store_true", help="discard earlier runs")
    ap.add_argument("--fine", action="store_true",
                    help="scale 0.6 down to 0.3125 ms, its record-scale sensitivity and "
                    "break times (about 35 min more)")  # fmt: skip
    args = ap.parse_args()
    if args.fresh and args.work.exists():
        shutil.rmtree(args.work)
    args.work.mkdir(parents=True, exist_ok=True)
    full = [0.02, 0.01, 0.005, 0.0025, 0.00125]
    dts = full[:2] if args.quick else full
    fine = args.fine and not args.quick
    studies: list[tuple[str, str, list[float], list[str], float, bool]] = [
        ("Scale 0.6 (the demo), ρ∞ = 0.5", "s06r05", [*dts, *FINER] if fine else dts,
         ["analysis.rho_inf=0.5"], 0.6, False),
        ("Scale 0.6, ρ∞ = 0", "s06r0", [*dts, *FINER[:1]] if fine else dts,
         ["analysis.rho_inf=0"], 0.6, False),
        ("Unbreakable joints, scale 0.6, ρ∞ = 0 (difference from the finest Δt)", "u0",
         dts[1:], ["analysis.rho_inf=0", *UNBREAKABLE], 0.6, True),
        ("Unbreakable joints, scale 0.6, ρ∞ = 0.5 (difference from the finest Δt)", "u05",
         dts[1:], ["analysis.rho_inf=0.5", *UNBREAKABLE], 0.6, True),
        ("Scale 1.0, ρ∞ = 0.5", "s10r05", dts if args.quick else [*full, 0.000625],
         ["analysis.rho_inf=0.5"], 1.0, False),
        ("Scale 0.6, ρ∞ = 0.5, event sub-steps (k = 4)", "s06r05e4",
         [*dts, *FINER[:1]] if fine else dts, ["analysis.rho_inf=0.5", *EVENTS], 0.6, False),
        ("Scale 1.0, ρ∞ = 0.5, event sub-steps (k = 4)", "s10r05e4",
         dts if args.quick else [*full, 0.000625], ["analysis.rho_inf=0.5", *EVENTS], 1.0,
         False),
    ]  # fmt: skip
    text = ["# Δt convergence of the demo dam", "",
            "Generated by `python benchmarks/demo_convergence.py "
            + ("--fine " if fine else "") + "--out docs/demo-convergence-tables.md` on a "
            "2-core machine shared with other jobs (one core used; the wall times vary with "
            "the load). Each cell: the value and its change from the previous Δt "
            "(unbreakable joints: its difference from the finest Δt).", ""]  # fmt: skip
    for title, tag, steps, sets, scale, last in studies:
        rows = [(dt, run(args.work, tag, dt, sets, scale)) for dt in steps]
        block = [f"## {title}", "", *table(rows, last), ""]
        if (fine and not last and scale == 0.6) or tag.endswith("e4"):
            block += ["The rule of criterion 6 (a change above 0.5 % at most 0.7 of the "
                      "previous one; at most 2 % between 5 and 2.5 ms):", "",
                      *criterion(rows), ""]  # fmt: skip
        print("\n".join(block), flush=True)
        text += block
    if not args.quick:
        block = ["## Record scale 0.98, 1.0, 1.02 at Δt = 1.25 ms, ρ∞ = 0.5", "",
                 *sensitivity(args.work, (0.98, 1.0, 1.02), 0.00125, 1.0, {1.0: "s10r05"}),
                 ""]  # fmt: skip
        print("\n".join(block), flush=True)
        text += block
    if fine:
        for dt in (0.0025, 0.00125):
            block = [
                f"## Record scale 0.588 to 0.612 at Δt = {1e3 * dt:g} ms, ρ∞ = 0.5",
                "",
                *sensitivity(args.work, SCALES, dt, 0.6, {0.6: "s06r05"}),
                "",
            ]
            print("\n".join(block), flush=True)
            text += block
        steps = [dt for dt in [*full, *FINER] if dt <= 0.005]
        runs = [(f"Δt = {1e3 * dt:g} ms", f"s06r05_{dt:g}") for dt in steps]
        runs += [(f"ρ∞ = 0, Δt = {1e3 * dt:g} ms", f"s06r0_{dt:g}") for dt in steps[:-1]]
        runs += [(f"scale {sc:g}, {1e3 * dt:g} ms", f"sens{sc:g}_{dt:g}")
                 for dt in (0.0025, 0.00125) for sc in SCALES if sc != 0.6]  # fmt: skip
        block = ["## Scale 0.6: when each dam–rock pair breaks during the record (s; ρ∞ = 0.5 "
                 "unless said)",
                 "", *break_table(args.work, runs, "dam_rock"), ""]  # fmt: skip
        head = [
            "Δt (ms)",
            *(
                f"{j}: {k}"
                for j in ("dam_rock", "neck")
                for k in ("broken set", "largest slip", "largest opening")
            ),
        ]
        block += ["## Scale 0.6, ρ∞ = 0.5: the first time (s) a run parts from the finest "
                  "(broken set differs; largest slip or largest opening so far differs by "
                  "more than 2 %)", "", "| " + " | ".join(head) + " |",
                  "|" + "---|" * len(head)]  # fmt: skip
        finest = args.work / f"s06r05_{steps[-1]:g}" / "results.h5"
        for dt in steps[:-1]:
            here = args.work / f"s06r05_{dt:g}" / "results.h5"
            if here.is_file() and finest.is_file():
                cells = [v for j in ("dam_rock", "neck") for v in parting(here, finest, j).values()]
                block.append(
                    f"| {1e3 * dt:g} | "
                    + " | ".join(f"{c:.4g}" if np.isfinite(c) else "never" for c in cells)
                    + " |"
                )
        block.append("")
        print("\n".join(block), flush=True)
        text += block
    if args.out is not None:
        args.out.write_text("\n".join(text) + "\n")


if __name__ == "__main__":
    main()
