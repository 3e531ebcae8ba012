"""PFE/IE benchmark in 3D: a stack of Tet10 blocks on a base, thousands of pairs.

A 10 m × 10 m × 10 m column meshed with quadratic tetrahedra (pfeie's structured
generator: each hexahedron of an n × n × 10 grid split into six Tet10, Kuhn's split),
cut by four horizontal joints into a base (2 m, fixed at its bottom) and four blocks of
2 m: the base joint bonded (c = 0.3 MPa, σ_t = 0.2 MPa, φ = 40°), the three joints above
existing ones (φ = 30°, no cohesion). Every node of a joint is a pair: (2n + 1)² pairs a
joint, 2,116 pairs at n = 11 (the default). Gravity, then El Centro × 2 along x and the
same record, 1.5 s later, × 1.4 along y (relative form, Δt = 0.01 s). It prints, as
``benchmarks/interfaces.py`` does: DOF, pairs, the static analysis time, the set-up time
(factorisation of K̂ and the Delassus operator), the time of one back-substitution, the
mean step time and its ratio to the back-substitution, the share of the step spent in
the interface solver, the pair problems per step, the solver iterations per step and the
share of the problems that the state iteration did not settle (solved by the semismooth
Newton or a later fallback), and the pair counts at the end. Times are CPU times
(``time.process_time``): the machine may be shared.

    python benchmarks/interfaces3d.py                 # n = 11: 2,116 pairs
    python benchmarks/interfaces3d.py --n 6           # 676 pairs (quick)
    python benchmarks/interfaces3d.py --scheme moreau-jean
    python benchmarks/interfaces3d.py --profile 20    # cProfile of the run, top 20
"""

from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(var, "1")

import numpy as np  # noqa: E402

import interfaces  # noqa: E402
import pfeie as pf  # noqa: E402
from interfaces import measure  # noqa: E402

interfaces.CLOCK = time.process_time  # CPU time: the machine may be shared

RECORD = Path(__file__).resolve().parents[1] / "examples" / "data" / "elcentro_1940_ns_chopra.csv"
JOINTS = (2.0, 4.0, 6.0, 8.0)


def build(n: int) -> pf.Model:
    mesh = pf.box(10.0, 10.0, 10.0, n, n, 10, cell="tetra10")
    bounds = (-1.0, *JOINTS, 11.0)
    blocks = []
    for k in range(len(bounds) - 1):
        lo, hi = bounds[k], bounds[k + 1]
        mesh.add_cell_group(f"b{k}", lambda x, lo=lo, hi=hi: (x[:, 2] > lo) & (x[:, 2] < hi))
        blocks.append(pf.Block(f"b{k}", pf.Elastic(25e9, 0.2, 2400.0)))
    interfaces = []
    for k, z in enumerate(JOINTS):
        mesh.add_facet_group(f"j{k}", lambda x, z=z: np.abs(x[:, 2] - z) < 1e-6,
                             boundary_only=False)  # fmt: skip
        law = (pf.Joint(c=0.3e6, phi=40.0, tensile=0.2e6, initial="intact") if k == 0
               else pf.Joint(phi=30.0))  # fmt: skip
        interfaces.append(pf.Interface(f"j{k}", law))
    model = pf.Model(mesh, blocks, interfaces=interfaces)
    model.fix("zmin")
    model.add_gravity()
    return model


def records() -> list[pf.GroundMotion]:
    data = np.loadtxt(RECORD, delimiter=",", skiprows=1)
    t, a = data[:, 0], data[:, 1]
    late = np.interp(t - 1.5, t, a, left=0.0)
    return [pf.GroundMotion.from_samples(2.0 * a, time=t, units="g", direction=(1, 0, 0)),
            pf.GroundMotion.from_samples(1.4 * late, time=t, units="g",
                                         direction=(0, 1, 0))]  # fmt: skip


def case(n: int, steps: int, scheme: str = "nonsmooth-alpha", envelope: bool = True,
         profile: int = 0) -> dict[str, float]:  # fmt: skip
    model = build(n)
    t0 = time.process_time()
    static = pf.solve_static(model)
    t_static = time.process_time() - t0
    t0 = time.process_time()
    an = pf.Dynamic(model, 0.01, scheme=scheme)
    t_setup = time.process_time() - t0
    # the pair problems of the steps: how many, their iterations, how many the state
    # iteration did not settle
    cls = pf.interface.InterfaceSolver
    solve_fn = cls.solve
    count = {"solves": 0.0, "iters": 0.0, "unsettled": 0.0}

    def counted(self, *args, **kw):  # type: ignore[no-untyped-def]
        out = solve_fn(self, *args, **kw)
        count["solves"] += 1
        count["iters"] += self.last.iterations
        count["unsettled"] += self.last.method != "state iteration"
        return out

    cls.solve = counted  # type: ignore[method-assign]
    try:
        r = measure(model, an, steps, t_static, t_setup, profile, ground=records(),
                    start=static, envelope=envelope)  # fmt: skip
    finally:
        cls.solve = solve_fn  # type: ignore[method-assign]
    r["problems"] = count["solves"] / steps
    r["iters"] = count["iters"] / steps
    r["unsettled"] = count["unsettled"] / max(count["solves"], 1.0)
    return r


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=11, help="cells along x and y (pairs: 4 (2n+1)²)")
    ap.add_argument("--steps", type=int, default=300, help="time steps")
    ap.add_argument("--scheme", choices=["nonsmooth-alpha", "moreau-jean"],
                    default="nonsmooth-alpha", help="the time scheme")  # fmt: skip
    ap.add_argument("--repeat", type=int, default=1, help="runs (medians)")
    ap.add_argument("--no-envelope", action="store_true", help="without the stress envelope")
    ap.add_argument("--profile", type=int, default=0, help="print the top N of a cProfile")
    args = ap.parse_args()
    hdr = (f"{'scheme':>16} {'DOF':>7} {'pairs':>6} {'static s':>9} {'setup s':>8} "
           f"{'solve ms':>9} {'step ms':>8} {'step/solve':>10} {'iface %':>8}  "
           "end state")  # fmt: skip
    runs = [case(args.n, args.steps, args.scheme, not args.no_envelope, args.profile)
            for _ in range(max(args.repeat, 1))]  # fmt: skip
    print(hdr)
    print("-" * len(hdr))
    r = {k: float(np.median([x[k] for x in runs])) for k in runs[0]}
    end = ", ".join(f"{k} {int(r[k])}" for k in ("intact", "stick", "slide", "open", "broken"))
    print(f"{args.scheme:>16} {int(r['dof']):>7} {int(r['pairs']):>6} {r['t_static']:>9.2f} "
          f"{r['t_setup']:>8.2f} {1e3 * r['t_solve']:>9.1f} {1e3 * r['t_step']:>8.1f} "
          f"{r['ratio']:>10.2f} {100 * r['iface']:>8.0f}  {end}; largest slip "
          f"{1e3 * r['slip']:.1f} mm", flush=True)  # fmt: skip
    print(f"pair problems a step {r['problems']:.2f}, solver iterations a step "
          f"{r['iters']:.1f}, not settled by the state iteration "
          f"{100 * r['unsettled']:.0f} %", flush=True)  # fmt: skip
    if len(runs) > 1:
        print("ratios of the runs:", ", ".join(f"{x['ratio']:.2f}" for x in runs))


if __name__ == "__main__":
    main()
