"""pfeie's interface solver on the FCLIB frictional-contact problems of Siconos.

The 22 FCLIB problems (``--data DIR``, by default a ``shared/data/fclib`` beside the
repository; Siconos test data, Apache-2.0: stacked
boxes, capsules, spheres, granular flow, a rover wheel; 2D and 3D, 1 to 2,020 contacts;
see its README) are posed to :class:`pfeie.interface.InterfaceSolver` through its public
API, exactly as a time step poses its pair problem: u = W r + q, pairs closed and broken
(an existing joint without cohesion: Coulomb friction μ per contact, no tension), the
relative motion of a sticking pair held at zero. FCLIB orders the local components
normal first; pfeie normal last, so each problem is permuted on the way in.

Printed per problem: dimension, contacts, the relative natural-map residual of the
README (Siconos' accuracy measure, ρ = 1),

    err = ‖r − P_K(r − û)‖ / max(‖q‖, ‖r‖, ‖u‖),   û = u + μ‖u_T‖ e_N,

the solver's iterations and method, wall time, and the status: ``solved`` (err ≤ 1e-8),
``inaccurate`` (an answer above 1e-8) or the exception raised.

Usage: ``python benchmarks/fclib.py [--data DIR] [--only NAME ...] [--markdown]``.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

from pfeie.errors import PfeieError
from pfeie.interface import (
    InterfaceSolver,
    PairState,
    coulomb_laws,
    load_fclib,
    natural_map_residual,
)

DATA = Path(__file__).resolve().parents[2] / "shared" / "data" / "fclib"
SOLVED = 1e-8


def solve(W: np.ndarray, q: np.ndarray, mu: np.ndarray, d: int) -> dict[str, object]:
    """One problem through :class:`InterfaceSolver`: residual, iterations, time, status."""
    nc = mu.size
    props = coulomb_laws(mu, d)
    prev = PairState.initial(np.ones(nc, dtype=bool), np.zeros(nc), d)
    t0 = time.perf_counter()
    try:
        solver = InterfaceSolver(W, props)
        st, _ = solver.solve(q.reshape(nc, d), prev)
    except PfeieError as exc:
        return {"status": type(exc).__name__, "time": time.perf_counter() - t0,
                "err": float("nan"), "iterations": 0, "method": str(exc)[:60]}  # fmt: skip
    wall = time.perf_counter() - t0
    err = natural_map_residual(W, q, st.X.ravel(), mu, d)
    return {"status": "solved" if err <= SOLVED else "inaccurate", "time": wall, "err": err,
            "iterations": solver.last.iterations, "method": solver.last.method}  # fmt: skip


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=Path, default=DATA)
    ap.add_argument("--only", nargs="*", default=None, help="problem names (without .npz)")
    ap.add_argument("--markdown", action="store_true", help="a Markdown table")
    args = ap.parse_args(argv)
    files = sorted(args.data.glob("*.npz"), key=lambda p: np.load(p)["mu"].size)
    if args.only:
        files = [p for p in files if p.stem in args.only]
    if args.markdown:
        print("| problem | d | contacts | residual | iterations | method | time (s) | status |")
        print("|---|---|---|---|---|---|---|---|")
    solved = 0
    for p in files:
        W, q, mu, d = load_fclib(p)
        out = solve(W, q, mu, d)
        solved += out["status"] == "solved"
        row = [p.stem, str(d), str(mu.size), f"{out['err']:.1e}", str(out["iterations"]),
               str(out["method"]), f"{out['time']:.3g}", str(out["status"])]  # fmt: skip
        print(("| " + " | ".join(row) + " |") if args.markdown else "  ".join(row), flush=True)
    print(f"{solved} of {len(files)} solved to {SOLVED:g}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
