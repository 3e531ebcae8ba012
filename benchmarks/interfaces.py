"""PFE/IE benchmark: a jointed gravity-dam section under El Centro.

A 100 m × 60 m section (Q4, plane strain): a rock block fixed at its base, and a concrete
dam cut by a bonded dam-rock joint (y = 20 m) and a lift joint (y = 40 m), gravity, then
El Centro scaled ×2 in the relative form (Δt = 0.01 s). For each size it prints: DOF,
pairs, the static analysis time, the set-up time (factorisation of K̂ and the Delassus
operator from one multi-right-hand-side solve), the time of one back-substitution, the
mean step time and its ratio to the back-substitution (method.md §5.1: the floor is about
two), the share of the step spent in the interface solver, and the pair counts at the end,
for the default nonsmooth generalised-α scheme (two pair problems per step), or
Moreau–Jean (one). The contact-stabilised Newmark step that this benchmark compared
before was removed; its figures stay in docs/benchmarks.md.

    python benchmarks/interfaces.py           # nx = 100, 200 (12k, 49k DOF)
    python benchmarks/interfaces.py --quick   # nx = 50
    python benchmarks/interfaces.py --large-rotation   # with body frames (method.md §2)
    python benchmarks/interfaces.py --large-rotation --compare-small --nx 100 --cpu --repeat 3
                                  # small and large rotations alternating, CPU time, ratio
    python benchmarks/interfaces.py --scheme moreau-jean
    python benchmarks/interfaces.py --repeat 5          # medians of 5 runs (a shared machine)
    python benchmarks/interfaces.py --no-envelope       # without the stress envelope's sweeps
    python benchmarks/interfaces.py --event-substeps 4  # events taken in four sub-steps

With ``--repeat N`` each case runs N times and the table gives the medians of the step
time, of the back-substitution time and of their ratio (each run's ratio uses its own
back-substitution, measured just before it). ``--cpu`` times with the process's CPU time
(time.process_time) instead of the wall clock: on a shared machine a ratio of CPU times is
the steadier measure. With large rotations the table adds the factorisations of the
interface solver's W_c per 100 steps (W changes with the rotations at the pairs; the
solver refines on the last factorised W_c⁻¹ and factorises anew only when the refinement
contracts too slowly, :class:`pfeie.coupling.InterfaceStep`).
"""

from __future__ import annotations

import argparse
import cProfile
import os
import pstats
import time
from pathlib import Path
from typing import Any

for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(var, "1")

import numpy as np  # noqa: E402

import pfeie as pf  # noqa: E402

RECORD = Path(__file__).resolve().parents[1] / "examples" / "data" / "elcentro_1940_ns_chopra.csv"


def build(nx: int) -> pf.Model:
    mesh = pf.rectangle(100.0, 60.0, nx, int(0.6 * nx), cell="quad")
    mesh.add_cell_group("rock", lambda x: x[:, 1] < 20)
    mesh.add_cell_group("dam", lambda x: x[:, 1] > 20)
    mesh.add_facet_group("base", lambda x: np.abs(x[:, 1] - 20) < 1e-6, boundary_only=False)
    mesh.add_facet_group("lift", lambda x: np.abs(x[:, 1] - 40) < 1e-6, boundary_only=False)
    rock, concrete = pf.Elastic(30e9, 0.25, 2600), pf.Elastic(25e9, 0.2, 2400)
    model = pf.Model(
        mesh,
        [pf.Block("rock", rock), pf.Block("dam", concrete)],
        interfaces=[
            pf.Interface("base", pf.Joint(c=0.3e6, phi=45, tensile=0.3e6, initial="intact")),
            pf.Interface("lift", pf.Joint(c=0.2e6, phi=40, tensile=0.1e6, initial="intact")),
        ],
    )
    model.fix("ymin")
    model.add_gravity()
    return model


CLOCK = time.perf_counter  # time.process_time with --cpu


def measure(model: pf.Model, an: pf.Dynamic, steps: int, t_static: float, t_setup: float,
            profile: int = 0, **run: Any) -> dict[str, float]:  # fmt: skip
    """Run ``an`` for ``steps`` steps (``run``: the keywords of :meth:`pf.Dynamic.run`) and
    time it: one back-substitution (median of 7), the step, their ratio, the share of the
    pair solves, the end state's counts (and a cProfile's top ``profile`` lines)."""
    b = np.random.default_rng(0).standard_normal(an.system.n)
    an.factor.solve(b)
    ts = []
    for _ in range(7):
        t0 = CLOCK()
        an.factor.solve(b)
        ts.append(CLOCK() - t0)
    t_solve = float(np.median(ts))
    t_iface = 0.0
    cls = pf.interface.InterfaceSolver
    solve_fn = cls.solve  # with large rotations a new solver is made every step

    def timed(*args, **kw):  # type: ignore[no-untyped-def]
        nonlocal t_iface
        t1 = CLOCK()
        out = solve_fn(*args, **kw)
        t_iface += CLOCK() - t1
        return out

    cls.solve = timed  # type: ignore[method-assign]
    prof = cProfile.Profile() if profile else None
    try:
        t0 = CLOCK()
        if prof is not None:
            prof.enable()
        res = an.run(n_steps=steps, **run)
        if prof is not None:
            prof.disable()
        t_run = CLOCK() - t0
    finally:
        cls.solve = solve_fn  # type: ignore[method-assign]
    if prof is not None:
        pstats.Stats(prof).sort_stats("tottime").print_stats(profile)
    counts = res.final.pairs.counts() if res.final else {}
    slip = float(np.abs(res.final.pairs.s[:, :-1]).max()) if res.final else 0.0
    # factorisations of W_c per 100 steps after the set-up's (large rotations; NaN for a
    # version of pfeie that does not count them)
    n_fact = getattr(an.istep, "factorizations", float("nan"))
    fact = 100.0 * (n_fact - 1) / steps if an.istep is not None else 0.0
    return dict(dof=an.system.n, pairs=model.pairs.n if model.pairs else 0, t_static=t_static,
                t_setup=t_setup, t_solve=t_solve, t_step=t_run / steps,
                ratio=t_run / steps / t_solve, iface=t_iface / t_run, slip=slip, fact=fact,
                **{k: float(v) for k, v in counts.items()})  # fmt: skip


def case(nx: int, steps: int, large_rotation: bool = False,
         scheme: str = "nonsmooth-alpha", envelope: bool = True,
         event_substeps: int = 1) -> dict[str, float]:  # fmt: skip
    model = build(nx)
    t0 = CLOCK()
    static = pf.solve_static(model)
    t_static = CLOCK() - t0
    data = np.loadtxt(RECORD, delimiter=",", skiprows=1)
    gm = pf.GroundMotion.from_samples(2.0 * data[:, 1], time=data[:, 0], units="g")
    t0 = CLOCK()
    an = pf.Dynamic(model, 0.01, large_rotation=large_rotation, scheme=scheme,
                    event_substeps=event_substeps)  # fmt: skip
    if event_substeps > 1:
        an.fine()  # the sub-steps' factorisation and W: set-up, not steps
    t_setup = CLOCK() - t0
    out = measure(model, an, steps, t_static, t_setup, ground=[gm], start=static,
                  envelope=envelope)  # fmt: skip
    out["events"] = an.event_steps / steps  # the share of steps taken in sub-steps
    return out


def main() -> None:
    global CLOCK
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="small size only")
    ap.add_argument("--nx", type=int, nargs="+", help="the sizes (cells across; default 100 200)")
    ap.add_argument("--steps", type=int, default=300, help="time steps per case")
    ap.add_argument("--large-rotation", action="store_true", help="body frames (method.md §2)")
    ap.add_argument("--compare-small", action="store_true",
                    help="with --large-rotation: small and large rotations alternating, and "
                    "the ratio of their step times")  # fmt: skip
    ap.add_argument("--cpu", action="store_true", help="CPU time (time.process_time)")
    ap.add_argument("--scheme", choices=["nonsmooth-alpha", "moreau-jean"],
                    default="nonsmooth-alpha", help="the time scheme")  # fmt: skip
    ap.add_argument("--repeat", type=int, default=1, help="runs per case (medians)")
    ap.add_argument("--no-envelope", action="store_true",
                    help="without the stress envelope (a sweep of the stress operators a step)")
    ap.add_argument("--event-substeps", type=int, default=1,
                    help="event sub-steps (analysis.event_substeps; their factorisation "
                    "counts in the set-up)")  # fmt: skip
    args = ap.parse_args()
    if args.cpu:
        CLOCK = time.process_time
    sizes = args.nx or ([50] if args.quick else [100, 200])
    schemes = [args.scheme]
    kinds = [False, True] if args.large_rotation and args.compare_small else [args.large_rotation]
    hdr = (f"{'scheme':>16} {'rot':>5} {'DOF':>7} {'pairs':>6} {'static s':>9} {'setup s':>8} "
           f"{'solve ms':>9} {'step ms':>8} {'step/solve':>10} {'iface %':>8} {'fact/100':>8}  "
           "end state")  # fmt: skip
    print(hdr)
    print("-" * len(hdr))
    for nx, scheme in ((nx, sc) for nx in sizes for sc in schemes):
        runs: dict[bool, list[dict[str, float]]] = {k: [] for k in kinds}
        for _ in range(max(args.repeat, 1)):  # alternating: the same load on both
            for large in kinds:
                runs[large].append(case(nx, args.steps, large, scheme, not args.no_envelope,
                                        args.event_substeps))  # fmt: skip
        step = {}
        for large, rs in runs.items():
            r = {k: float(np.median([x[k] for x in rs])) for k in rs[0]}
            step[large] = r["t_step"]
            end = ", ".join(f"{k} {int(r[k])}" for k in ("intact", "stick", "slide", "open",
                                                          "broken"))  # fmt: skip
            print(f"{scheme:>16} {'large' if large else 'small':>5} {int(r['dof']):>7} "
                  f"{int(r['pairs']):>6} {r['t_static']:>9.2f} "
                  f"{r['t_setup']:>8.2f} {1e3 * r['t_solve']:>9.1f} {1e3 * r['t_step']:>8.1f} "
                  f"{r['ratio']:>10.2f} {100 * r['iface']:>8.0f} {r['fact']:>8.1f}  {end}"
                  + (f"; event steps {100 * r['events']:.1f} %" if args.event_substeps > 1
                     else ""), flush=True)  # fmt: skip
        if len(kinds) == 2:
            each = [lg["t_step"] / sm["t_step"] for sm, lg in zip(runs[False], runs[True],
                                                                   strict=True)]  # fmt: skip
            print(f"large / small step time: {step[True] / step[False]:.2f} (medians); per "
                  f"pair of runs {', '.join(f'{x:.2f}' for x in each)}", flush=True)


if __name__ == "__main__":
    main()
