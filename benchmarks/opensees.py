"""pfeie beside OpenSees on one problem: a deformable block shaken on a frictional plane.

A 2 m × 1 m concrete block (E = 30 GPa, ν = 0.2, ρ = 2400 kg/m³; plane strain, Q4) rests
on a rigid plane with Coulomb friction μ = 0.2 and is shaken along x by the plane,
a_g(t) = 0.4 g sin(2π 2 t), for 500 steps of Δt = 2 ms (1 s). It slides back and forth;
the reference is the exact rigid-block solution (pfeie.verification's event-driven
integrator; Newmark 1965), which the deformable block follows to its deformability floor.
Error: max_t |x − x_ref| / max_t |x_ref| of the block's mean horizontal displacement
relative to the plane.

- pfeie: the block on a fixed base joined by an interface (the default nonsmooth
  generalised-α, ρ∞ = 0; no penalty: rigid contact), the factorisation once;
- OpenSees (OpenSeesPy): the same mesh of `quad` elements with lumped nodal masses; each
  bottom node tied to a fixed ground node by a `zeroLengthContact2D` element (penalty
  contact with Coulomb friction; Kn = Kt = 10 E Δx per node), gravity by a static step,
  then Newmark (average acceleration) with Newton iterations on the tangent (UmfPack),
  the ground motion as a `UniformExcitation`.

Prints DOF, wall time, time per step, and the error, for each solver and size.

    python benchmarks/opensees.py               # 5k and 20k DOF
    python benchmarks/opensees.py --sizes 5000 20000 80000

OpenSeesPy is an optional extra (``pip install 'pfeie[bench]'``); on Debian its wheel
needs the system BLAS and LAPACK (``apt-get install libblas3 liblapack3``).
"""

from __future__ import annotations

import argparse
import math
import os
import time

for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(var, "1")

import numpy as np  # noqa: E402

import pfeie as pf  # noqa: E402
from pfeie.verification._models import block_on_base  # noqa: E402
from pfeie.verification._rigid import RigidBlock  # noqa: E402

G, MU = 9.81, 0.2
WIDTH, HEIGHT = 2.0, 1.0
E, NU, RHO = 30e9, 0.2, 2400.0
A, FREQ = 0.4 * G, 2.0
DT, STEPS = 0.002, 500


def ground(t: np.ndarray) -> np.ndarray:
    return A * np.sin(2 * np.pi * FREQ * t)


def reference(t: np.ndarray) -> np.ndarray:
    """The rigid block's displacement relative to the plane (m) at ``t``."""
    tt = np.linspace(0.0, t[-1], 20001)
    rb = RigidBlock(tt, ground(tt), MU * G, t_end=float(t[-1]))
    return np.asarray(rb.displacement(t))


def error(t: np.ndarray, x: np.ndarray) -> float:
    ref = reference(t)
    return float(np.abs(x - ref).max() / np.abs(ref).max())


def grid(n_dof: int) -> tuple[int, int]:
    """nx × ny cells (nx = 2 ny) of the block for about ``n_dof`` DOF."""
    ny = max(round(math.sqrt(n_dof / 4.0)), 2)
    return 2 * ny, ny


def run_pfeie(nx: int, ny: int) -> dict[str, float]:
    model = block_on_base(joint=pf.Joint(phi=math.degrees(math.atan(MU))), width=WIDTH,
                          height=HEIGHT, n=nx, ny=ny, E=E, nu=NU, rho=RHO)  # fmt: skip
    t0 = time.perf_counter()
    static = pf.solve_static(model)
    an = pf.Dynamic(model, DT)
    t_setup = time.perf_counter() - t0
    gm = pf.GroundMotion.from_function(lambda t: A * math.sin(2 * math.pi * FREQ * t),
                                       STEPS * DT, DT / 4)  # fmt: skip
    t0 = time.perf_counter()
    res = an.run(n_steps=STEPS, ground=[gm], start=static)
    wall = time.perf_counter() - t0
    x = res.rigid[:, 1, 0] - res.rigid[0, 1, 0]
    n_block = int(np.count_nonzero(model.body_of_node == 1)) * 2
    return {"dof": n_block, "setup": t_setup, "wall": wall, "error": error(res.t, x)}


def run_opensees(nx: int, ny: int) -> dict[str, float]:
    import openseespy.opensees as ops

    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 2)
    xs, ys = np.linspace(0.0, WIDTH, nx + 1), np.linspace(0.0, HEIGHT, ny + 1)
    dx, dy = WIDTH / nx, HEIGHT / ny
    tag = np.arange(1, (nx + 1) * (ny + 1) + 1).reshape(ny + 1, nx + 1)
    wx = np.full(nx + 1, dx)
    wx[[0, -1]] = dx / 2
    wy = np.full(ny + 1, dy)
    wy[[0, -1]] = dy / 2
    mass = RHO * np.outer(wy, wx)  # lumped nodal masses (kg per m of thickness)
    for j in range(ny + 1):
        for i in range(nx + 1):
            ops.node(int(tag[j, i]), float(xs[i]), float(ys[j]))
            ops.mass(int(tag[j, i]), float(mass[j, i]), float(mass[j, i]))
    ops.nDMaterial("ElasticIsotropic", 1, E, NU, 0.0)
    e = 0
    for j in range(ny):
        for i in range(nx):
            e += 1
            ops.element("quad", e, int(tag[j, i]), int(tag[j, i + 1]), int(tag[j + 1, i + 1]),
                        int(tag[j + 1, i]), 1.0, "PlaneStrain", 1)  # fmt: skip
    gtag = int(tag.max())
    k = 10.0 * E * dx
    for i in range(nx + 1):
        g = gtag + 1 + i
        ops.node(g, float(xs[i]), 0.0)
        ops.fix(g, 1, 1)
        e += 1
        # the block's node first, the normal (0, 1): the orientation that closes the
        # contacts under gravity (the other two tried diverge in the gravity step)
        ops.element("zeroLengthContact2D", e, int(tag[0, i]), g, k, k, MU, "-normal", 0, 1)
    ops.timeSeries("Constant", 1)
    ops.pattern("Plain", 1, 1)
    for j in range(ny + 1):
        for i in range(nx + 1):
            ops.load(int(tag[j, i]), 0.0, float(-mass[j, i] * G))
    ops.system("UmfPack")
    ops.numberer("RCM")
    ops.constraints("Plain")
    ops.test("NormDispIncr", 1e-10, 50)
    ops.algorithm("Newton")
    ops.integrator("LoadControl", 0.1)
    ops.analysis("Static")
    t0 = time.perf_counter()
    if ops.analyze(10) != 0:
        raise RuntimeError("OpenSees: the gravity step did not converge")
    ops.loadConst("-time", 0.0)
    t_setup = time.perf_counter() - t0
    tt = np.arange(0.0, STEPS * DT + DT / 2, DT / 4)
    ops.timeSeries("Path", 2, "-dt", DT / 4, "-values", *ground(tt).tolist())
    ops.pattern("UniformExcitation", 2, 1, "-accel", 2)
    ops.wipeAnalysis()
    ops.system("UmfPack")
    ops.numberer("RCM")
    ops.constraints("Plain")
    ops.test("NormDispIncr", 1e-9, 50)
    ops.algorithm("Newton")
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")
    nodes = tag.ravel()
    w = mass.ravel() / mass.sum()
    u0 = float(sum(wi * ops.nodeDisp(int(n), 1) for n, wi in zip(nodes, w, strict=True)))
    x = [0.0]
    t0 = time.perf_counter()
    for _ in range(STEPS):
        if ops.analyze(1, DT) != 0:
            raise RuntimeError(f"OpenSees: no convergence at t = {ops.getTime():.4f} s")
        x.append(float(sum(wi * ops.nodeDisp(int(n), 1) for n, wi in zip(nodes, w,
                                                                          strict=True))) - u0)
    wall = time.perf_counter() - t0
    t = np.arange(STEPS + 1) * DT
    return {"dof": 2 * nodes.size, "setup": t_setup, "wall": wall,
            "error": error(t, np.asarray(x))}  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[5000, 20000],
                    help="approximate DOF of the block (default 5000 20000)")  # fmt: skip
    ap.add_argument("--pfeie-only", action="store_true",
                    help="run pfeie alone (OpenSees takes hours at 80k DOF)")  # fmt: skip
    args = ap.parse_args()
    solvers: tuple[str, ...] = ("pfeie",)
    if not args.pfeie_only:
        try:
            import openseespy.opensees  # noqa: F401

            solvers = ("pfeie", "OpenSees")
        except (ImportError, RuntimeError) as exc:
            print(f"OpenSeesPy not available ({exc}); pfeie only")
    hdr = (f"{'solver':>9} {'DOF':>7} {'setup s':>8} {'wall s':>8} {'ms/step':>8} "
           f"{'error vs rigid':>15}")  # fmt: skip
    print(f"block {WIDTH} m x {HEIGHT} m on a plane, mu = {MU}, a_g = 0.4 g sin(2 pi 2 t), "
          f"{STEPS} steps of {1e3 * DT:g} ms")
    print(hdr)
    print("-" * len(hdr))
    for n in args.sizes:
        nx, ny = grid(n)
        for s in solvers:
            r = run_pfeie(nx, ny) if s == "pfeie" else run_opensees(nx, ny)
            print(f"{s:>9} {int(r['dof']):>7} {r['setup']:>8.2f} {r['wall']:>8.1f} "
                  f"{1e3 * r['wall'] / STEPS:>8.2f} {100 * r['error']:>14.2f}%", flush=True)


if __name__ == "__main__":
    main()
