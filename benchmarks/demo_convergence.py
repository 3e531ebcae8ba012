"""Δt convergence of the demo dam (examples/koyna/koyna.toml) under the default time scheme.

Runs the demo through the command line at halved time steps and prints, per
configuration, a markdown table of the quantities an engineer reads (crest peak
displacement and absolute acceleration; per joint the residual slip, the largest opening,
the broken share and the time of the first break), each with its change from the previous
Δt in % of its value, and the wall time:

1. record scale 0.6 (the demo), ρ∞ = 0.5 (the demo's setting) and ρ∞ = 0;
2. unbreakable joints (cohesion and tensile strength 1e12 Pa), ρ∞ = 0 and 0.5: the crest
   peaks against the finest Δt (the elastic response the scheme must not damp);
3. record scale 1.0, ρ∞ = 0.5, down to Δt = 0.625 ms;
4. record scales 0.98, 1.0, 1.02 at Δt = 1.25 ms (the physical sensitivity).

    python benchmarks/demo_convergence.py            # everything (about 30 min, one core)
    python benchmarks/demo_convergence.py --quick    # Δt = 20 and 10 ms only
    python benchmarks/demo_convergence.py --out docs/demo-convergence-tables.md

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
UNBREAKABLE = [f"interfaces.{j}.{k}=1e12" for j in ("dam_rock", "neck")
               for k in ("cohesion", "tensile_strength")]  # fmt: skip


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


def quantities(s: dict[str, Any]) -> dict[str, float]:
    if "failed" in s:
        return {}
    q = {"crest disp (mm)": 1e3 * s["probes"]["crest"]["peak_displacement_m"],
         "crest acc (g)": s["probes"]["crest"]["peak_abs_acceleration_g"]}  # fmt: skip
    for name, j in s.get("joints", {}).items():
        q[f"{name} slip (mm)"] = 1e3 * j.get("residual_slip_max_m", 0.0)
        q[f"{name} opening (mm)"] = 1e3 * j.get("max_opening_m", 0.0)
        if "broken_share" in j:
            q[f"{name} broken"] = j["broken_share"]
        if name in s["first_break"]:
            q[f"{name} first break (s)"] = s["first_break"][name]
    return q


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


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="Δt = 20 and 10 ms only")
    ap.add_argument("--work", type=Path, default=Path("/tmp/pfeie-demo-convergence"))
    ap.add_argument("--out", type=Path, default=None, help="also write the tables here")
    ap.add_argument("--fresh", action="store_true", help="discard earlier runs")
    args = ap.parse_args()
    if args.fresh and args.work.exists():
        shutil.rmtree(args.work)
    args.work.mkdir(parents=True, exist_ok=True)
    full = [0.02, 0.01, 0.005, 0.0025, 0.00125]
    dts = full[:2] if args.quick else full
    studies: list[tuple[str, str, list[float], list[str], float, bool]] = [
        ("Scale 0.6 (the demo), ρ∞ = 0.5", "s06r05", dts, ["analysis.rho_inf=0.5"], 0.6, False),
        ("Scale 0.6, ρ∞ = 0", "s06r0", dts, ["analysis.rho_inf=0"], 0.6, False),
        ("Unbreakable joints, scale 0.6, ρ∞ = 0 (difference from the finest Δt)", "u0",
         dts[1:], ["analysis.rho_inf=0", *UNBREAKABLE], 0.6, True),
        ("Unbreakable joints, scale 0.6, ρ∞ = 0.5 (difference from the finest Δt)", "u05",
         dts[1:], ["analysis.rho_inf=0.5", *UNBREAKABLE], 0.6, True),
        ("Scale 1.0, ρ∞ = 0.5", "s10r05", dts if args.quick else [*full, 0.000625],
         ["analysis.rho_inf=0.5"], 1.0, False),
    ]  # fmt: skip
    text = ["# Δt convergence of the demo dam", "",
            "Generated by `python benchmarks/demo_convergence.py --out "
            "docs/demo-convergence-tables.md` on a 2-core machine (one core used). Each cell: the "
            "value and its change from the previous Δt (unbreakable joints: its difference "
            "from the finest Δt).", ""]  # fmt: skip
    for title, tag, steps, sets, scale, last in studies:
        rows = [(dt, run(args.work, tag, dt, sets, scale)) for dt in steps]
        block = [f"## {title}", "", *table(rows, last), ""]
        print("\n".join(block), flush=True)
        text += block
    if not args.quick:
        rows = [(sc, run(args.work, f"sens{sc:g}", 0.00125, ["analysis.rho_inf=0.5"], sc))
                for sc in (0.98, 1.0, 1.02)]  # fmt: skip
        qs = [quantities(s) for _, s in rows]
        keys = list(qs[1])
        block = ["## Record scale 0.98, 1.0, 1.02 at Δt = 1.25 ms, ρ∞ = 0.5", "",
                 "| scale | " + " | ".join(keys) + " |", "|" + "---|" * (len(keys) + 1),
                 *[f"| {sc:g} | " + " | ".join(f"{q.get(k, float('nan')):.4g}" for k in keys)
                   + " |" for (sc, _), q in zip(rows, qs, strict=True)], ""]  # fmt: skip
        print("\n".join(block), flush=True)
        text += block
    if args.out is not None:
        args.out.write_text("\n".join(text) + "\n")


if __name__ == "__main__":
    main()
