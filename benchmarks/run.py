"""Benchmark runner: assembly, factorisation, back-substitution and Newmark step cost.

For each problem (2D Q4 plane strain and 3D Hex8, structured, base fixed) it prints:
DOF, nonzeros of K, assembly time of K and M and elements per second, factorisation
time of the Newmark effective matrix K̂ = K + a₀M and the peak resident memory of the
case, the time of one back-substitution, and the Newmark time per step divided by the
back-substitution time. Each case runs in its own process (so peak memory is its own),
with BLAS threads pinned to one.

    python benchmarks/run.py            # 2D to 400k DOF, 3D to 300k DOF
    python benchmarks/run.py --quick    # small sizes, a smoke run
"""

from __future__ import annotations

import argparse
import multiprocessing as mp
import os
import resource
import time

for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(var, "1")

import numpy as np  # noqa: E402

import pfeie as pf  # noqa: E402
from pfeie.dynamics import Newmark  # noqa: E402


def build(dim: int, n: int) -> pf.Model:
    if dim == 2:
        mesh = pf.rectangle(1.0, 1.0, n, n, cell="quad")
        base = "ymin"
    else:
        mesh = pf.box(1.0, 1.0, 1.0, n, n, n, cell="hexahedron")
        base = "zmin"
    model = pf.Model(mesh, [pf.Block("all", pf.Elastic(30e9, 0.2, 2400.0))])
    model.fix(base)
    model.add_gravity(amplitude=lambda t: 1.0 + 0.1 * np.sin(20 * t))
    return model


def best(fn, repeat: int = 5) -> float:  # type: ignore[no-untyped-def]
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return float(np.median(times))


def case(dim: int, n: int, backend: str, out: mp.Queue) -> None:  # type: ignore[type-arg]
    model = build(dim, n)
    t0 = time.perf_counter()
    K = model.stiffness()
    t_k = time.perf_counter() - t0
    t0 = time.perf_counter()
    model.mass()
    t_m = time.perf_counter() - t0
    n_cells = model.mesh.n_cells
    system = model.system()
    dt = 1e-3
    t0 = time.perf_counter()
    nm = Newmark(system, dt=dt, backend=backend)
    t_fact = time.perf_counter() - t0
    b = np.random.default_rng(0).standard_normal(system.n)
    nm.factor.solve(b)
    t_solve = best(lambda: nm.factor.solve(b), 7)
    state = nm.initial_state()
    steps = 20
    t0 = time.perf_counter()
    for _ in range(steps):
        state = nm.step(state)
    t_step = (time.perf_counter() - t0) / steps
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    out.put(dict(dim=dim, dof=system.n, nnz=K.nnz, cells=n_cells, t_k=t_k, t_m=t_m,
                 eps=n_cells / t_k, t_fact=t_fact, mem=peak, t_solve=t_solve,
                 t_step=t_step, backend=nm.factor.backend))  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="small sizes only")
    ap.add_argument("--backend", default="auto", help="solver backend (auto, cholmod, superlu)")
    ap.add_argument("--only", choices=["2d", "3d"], help="one dimension only")
    args = ap.parse_args()
    sizes2 = [50, 110] if args.quick else [110, 223, 316, 446]  # 25k..400k DOF
    sizes3 = [12, 20] if args.quick else [20, 31, 46]  # 28k..300k DOF
    cases = [(2, n) for n in sizes2] + [(3, n) for n in sizes3]
    if args.only:
        cases = [c for c in cases if c[0] == int(args.only[0])]
    hdr = (f"{'dim':>3} {'DOF':>8} {'nnz(K)':>10} {'cells':>8} {'K asm s':>8} {'M asm s':>8} "
           f"{'cells/s':>9} {'fact s':>7} {'peak MB':>8} {'solve ms':>9} {'step ms':>8} "
           f"{'step/solve':>10} backend")  # fmt: skip
    print(hdr)
    print("-" * len(hdr))
    ctx = mp.get_context("spawn")
    for dim, n in cases:
        q: mp.Queue = ctx.Queue()  # type: ignore[type-arg]
        p = ctx.Process(target=case, args=(dim, n, args.backend, q))
        p.start()
        r = q.get()
        p.join()
        print(f"{r['dim']:>3} {r['dof']:>8} {r['nnz']:>10} {r['cells']:>8} {r['t_k']:>8.2f} "
              f"{r['t_m']:>8.2f} {r['eps']:>9.3g} {r['t_fact']:>7.2f} {r['mem']:>8.0f} "
              f"{1e3 * r['t_solve']:>9.1f} {1e3 * r['t_step']:>8.1f} "
              f"{r['t_step'] / r['t_solve']:>10.2f} {r['backend']}", flush=True)  # fmt: skip


if __name__ == "__main__":
    main()
