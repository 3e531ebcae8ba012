"""Study benchmark: many records on a jointed dam section of about 50k DOF.

The section of benchmarks/interfaces.py (100 m × 60 m, Q4, plane strain; a rock block
fixed at its base, a dam cut by a bonded dam-rock joint at y = 20 m and a bonded lift
joint at y = 40 m; nx = 200: 48.6k DOF, 402 pairs), written as a gmsh file and a model
file, under synthetic records (Kanai-Tajimi noise in the envelope of Jennings et al.,
examples/study/make_records.py; 30 s each, Δt = 0.01 s), each scaled to a PGA of 0.5 g,
run as a study on a local Dask cluster, each worker stepping up to ``--batch`` records
together (their block solves made in one call a step). It prints the problem size; the
set-up a process pays once (model, static state, factorisation and W); per run: the
steps, the wall time, the step time and its ratio to one back-substitution; the study's
total against the same records run as separate `pfeie run` processes (measured for two
of them, extrapolated).

    python benchmarks/study.py                   # 100 records (the issue's benchmark (a))
    python benchmarks/study.py --records 6       # a quick estimate
    python benchmarks/study.py --nx 100 --records 4 --duration 10
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(var, "1")

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "examples" / "study"))
import make_records  # noqa: E402

import pfeie as pf  # noqa: E402

MODEL = """
title = "study benchmark: jointed dam section, nx = {nx}"
[mesh]
file = "dam.msh"
[materials.rock]
E = 30e9
nu = 0.25
rho = 2600.0
[materials.concrete]
E = 25e9
nu = 0.2
rho = 2400.0
[blocks]
rock = "rock"
dam = "concrete"
[interfaces.base]
cohesion = 0.3e6
friction_angle = 45.0
tensile_strength = 0.3e6
initial = "intact"
[interfaces.lift]
cohesion = 0.2e6
friction_angle = 40.0
tensile_strength = 0.1e6
initial = "intact"
[[supports]]
group = "bottom"
[loads]
gravity = 9.81
[analysis]
dt = 0.01
[output]
folder = "run"
field_every = 100
paraview = false
probes = {{ crest = [50.0, 60.0] }}
"""


def write_mesh(path: Path, nx: int) -> None:
    """A gmsh 2.2 file of the 100 m × 60 m section: nx × 0.6 nx Q4 cells, the cell
    groups rock (y < 20) and dam, the line groups base (y = 20), lift (y = 40) and
    bottom (y = 0)."""
    ny = int(0.6 * nx)
    x, y = np.linspace(0.0, 100.0, nx + 1), np.linspace(0.0, 60.0, ny + 1)
    X, Y = np.meshgrid(x, y)
    ids = np.arange(1, X.size + 1).reshape(ny + 1, nx + 1)
    q = np.stack([ids[:-1, :-1], ids[:-1, 1:], ids[1:, 1:], ids[1:, :-1]], -1).reshape(-1, 4)
    yc = 0.5 * (y[:-1] + y[1:])
    phys_q = np.repeat(np.where(yc < 20.0, 1, 2), nx)
    rows = {3: 0, 4: round(20.0 / 60.0 * ny), 5: round(40.0 / 60.0 * ny)}
    lines = [(tag, np.stack([ids[j, :-1], ids[j, 1:]], -1)) for tag, j in rows.items()]
    out = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", "5",
           '2 1 "rock"', '2 2 "dam"', '1 3 "bottom"', '1 4 "base"', '1 5 "lift"',
           "$EndPhysicalNames", "$Nodes", str(X.size)]  # fmt: skip
    nodes = zip(ids.ravel(), X.ravel(), Y.ravel(), strict=True)
    out += [f"{i} {a:.12g} {b:.12g} 0" for i, a, b in nodes]
    n_el = len(q) + sum(len(c) for _, c in lines)
    out += ["$EndNodes", "$Elements", str(n_el)]
    k = 0
    for tag, conn in lines:
        for c in conn:
            k += 1
            out.append(f"{k} 1 2 {tag} {tag} {c[0]} {c[1]}")
    for tag, c in zip(phys_q, q, strict=True):
        k += 1
        out.append(f"{k} 3 2 {tag} {tag} {c[0]} {c[1]} {c[2]} {c[3]}")
    out.append("$EndElements")
    path.write_text("\n".join(out) + "\n")


def write_records(folder: Path, n: int, duration: float) -> None:
    """``n`` synthetic records of ``duration`` s: the example's four ground filters and
    envelopes, in turn, with seeds 1 … n."""
    folder.mkdir(parents=True, exist_ok=True)
    for i in range(n):
        _, fg, zg, t1, t2, c = make_records.RECORDS[i % len(make_records.RECORDS)]
        stretch = duration / make_records.DURATION
        rec = make_records.record(i + 1, fg, zg, t1 * stretch, t2 * stretch, c / stretch,
                                  duration=duration)  # fmt: skip
        np.savetxt(folder / f"r{i + 1:03d}.csv", rec, delimiter=",", fmt="%.6g")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--records", type=int, default=100, help="number of records (100)")
    ap.add_argument("--duration", type=float, default=30.0, help="record length (s)")
    ap.add_argument("--nx", type=int, default=200, help="cells across (200: 48.6k DOF)")
    ap.add_argument("--workers", type=int, default=2, help="Dask worker processes (2)")
    ap.add_argument("--pga", type=float, default=0.5, help="PGA of every record (g)")
    ap.add_argument("--batch", type=int, default=pf.Study.batch,
                    help=f"runs a worker steps together ({pf.Study.batch}; 1: one after "
                    "the other)")  # fmt: skip
    ap.add_argument("--separate", type=int, default=2,
                    help="records also run as separate pfeie run processes (2)")  # fmt: skip
    args = ap.parse_args()
    with tempfile.TemporaryDirectory(prefix="pfeie-study-bench-") as tmp:
        work = Path(tmp)
        write_mesh(work / "dam.msh", args.nx)
        (work / "model.toml").write_text(MODEL.format(nx=args.nx))
        write_records(work / "records", args.records, args.duration)
        (work / "study.toml").write_text(
            f'model = "model.toml"\n[[records]]\nfolder = "records"\npattern = "*.csv"\n'
            f'units = "g"\n[intensity]\nmeasure = "pga"\nvalues = [{args.pga}]\n'
            f'[output]\nfolder = "study"\nparquet = false\n'
        )  # fmt: skip
        from pfeie.io import Override, load_job

        t0 = time.perf_counter()
        job = load_job(work / "model.toml", [Override("analysis.duration", 1.0, "bench")])
        static = pf.solve_static(job.model)
        an = pf.Dynamic(job.model, 0.01)
        t_setup = time.perf_counter() - t0
        b = np.random.default_rng(0).standard_normal(an.system.n)
        ts = []
        for _ in range(9):
            t1 = time.perf_counter()
            an.factor.solve(b)
            ts.append(time.perf_counter() - t1)
        t_solve = float(np.median(ts))
        n_dof, n_pairs = an.system.n, job.model.pairs.n if job.model.pairs else 0
        del an, static, job
        print(f"model: {n_dof} DOF, {n_pairs} pairs; {args.records} records x "
              f"{args.duration:g} s at dt = 0.01 s, PGA {args.pga:g} g; {args.workers} workers, "
              f"batches of at most {args.batch}")
        print(f"set-up once per process (model, static state, factorisation, W): "
              f"{t_setup:.2f} s; one back-substitution {1e3 * t_solve:.2f} ms")
        st = pf.Study.from_file(work / "study.toml")
        st.batch = args.batch
        t0 = time.perf_counter()
        table = st.run(workers=args.workers)
        total = time.perf_counter() - t0
        walls, steps = table.column("wall_s"), table.column("steps")
        per_step = walls / steps
        print(f"study: {total:.1f} s in all, {total / args.records:.2f} s per record "
              f"(wall of a run: mean {walls.mean():.2f} s, {steps.mean():.0f} steps; step "
              f"{1e3 * per_step.mean():.2f} ms = {per_step.mean() / t_solve:.2f} "
              "back-substitutions; runs in lockstep share their wall)")
        rec_step = total * max(args.workers, 1) / float(steps.sum())
        print(f"a record's step, the study's wall x workers / all records' steps: "
              f"{1e3 * rec_step:.2f} ms = {rec_step / t_solve:.2f} back-substitutions "
              "(set-up included)")
        print(f"runs completed: {int(table.column('completed').sum())}/{len(table)}; "
              f"slip of the lift joint: median "
              f"{1e3 * np.median(table.column('joint.lift.residual_slip_max_m')):.2f} mm")
        seps = []
        files = sorted((work / "records").glob("*.csv"))[: args.separate]
        for f in files:
            (work / "one.toml").write_text(MODEL.format(nx=args.nx).replace(
                "[output]", f'[[ground_motion]]\nfile = "{f}"\nunits = "g"\n'
                            f"pga = {args.pga}\n[output]"))  # fmt: skip
            t1 = time.perf_counter()
            subprocess.run([sys.executable, "-m", "pfeie", "run", str(work / "one.toml"),
                            "--quiet"], check=True, stdout=subprocess.DEVNULL)  # fmt: skip
            seps.append(time.perf_counter() - t1)
        if seps:
            sep = float(np.mean(seps))
            est = sep * args.records / args.workers
            print(f"separate pfeie run: {sep:.1f} s per record (a process: import, model, "
                  f"static, factorisation, run, results file); {args.records} records on "
                  f"{args.workers} cores: {est:.0f} s, {est / total:.2f} x the study")


if __name__ == "__main__":
    main()
