"""Planted solutions on pfeie's own Delassus operator (issue 15).

A pfeie model with joints (2D Q4 and Q8, 3D Hex8 and Tet10; hundreds of pairs) gives the
step's W = s G K̂⁻¹ Gᵀ from :class:`pfeie.Dynamic` (the nonsmooth generalised-α step,
its factorised K̂ and force weight s). On it a solution is *planted*: for every pair a
state and forces consistent with the Mohr-Coulomb law of its joint (cohesion c A,
friction μ, tensile strength σ_t A; intact or residual values),

- intact: the relative motion unchanged (s = s_prev), X strictly inside the intact
  strength (tension allowed down to −σ_t A, shear up to c A + μ X_n);
- stick (broken, closed): s_n = 0, the slip unchanged, X strictly inside the residual cone;
- slide: s_n = 0, X_t = −(c_r A + μ_r X_n) ŝ on the cone, the slip increment α ŝ, α > 0;
- open: X = 0, s_n > 0, any tangential motion,

and the relative motions w consistent with it; the problem given to the solver is
w_free = w − W X. The public :meth:`InterfaceSolver.solve` (and the step's
:meth:`InterfaceStep.solve`) must return the planted forces, states and relative motions,
and an answer whose natural-map residual (Alart-Curnier, computed here independently of
the solver) is below the solver's tolerance. W is positive definite on these models (each
pair ties two distinct nodes), and the planted states are strict (margins on the cone and
the gaps), so the answer is the planted one.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import pytest

import pfeie as pf
from pfeie.interface import INTACT, OPEN, SLIDE, STICK, InterfaceSolver, PairLaws, PairState

C_PA, T_PA = 0.3e6, 0.2e6  # intact cohesion and tensile strength (Pa)


def _joints() -> list[pf.Joint]:
    """Three joint laws: bonded with cohesion and tension (residual cohesion c_r), bonded
    with a lower strength (no residual cohesion), and an existing (broken) joint."""
    return [
        pf.Joint(c=C_PA, phi=40.0, tensile=T_PA, c_r=0.05e6, phi_r=35.0, initial="intact"),
        pf.Joint(c=0.5 * C_PA, phi=30.0, tensile=0.5 * T_PA, initial="intact"),
        pf.Joint(phi=35.0),
    ]


def _model_2d(cell: str, nx: int) -> pf.Model:
    """A 60 m × 36 m section cut by three horizontal joints (y = 9, 18, 27 m) into four
    blocks, the lowest fixed at its base."""
    mesh = pf.rectangle(60.0, 36.0, nx, int(0.6 * nx), cell=cell)
    return _jointed(mesh, 1, 36.0)


def _model_3d(cell: str, n: int, joints: list[pf.Joint] | None = None) -> pf.Model:
    """A 20 m × 20 m × 12 m column cut by three horizontal joints (z = 3, 6, 9 m); their
    laws from the bottom up, :func:`_joints` by default."""
    mesh = pf.box(20.0, 20.0, 12.0, n, n, 4, cell=cell)
    return _jointed(mesh, 2, 12.0, joints)


def _jointed(mesh: pf.Mesh, up: int, height: float,
             joints: list[pf.Joint] | None = None) -> pf.Model:  # fmt: skip
    cuts = [0.25 * height, 0.5 * height, 0.75 * height]
    bounds = [-1.0, *cuts, 2 * height]
    blocks = []
    for k in range(4):
        lo, hi = bounds[k], bounds[k + 1]
        mesh.add_cell_group(f"b{k}", lambda x, lo=lo, hi=hi: (x[:, up] > lo) & (x[:, up] < hi))
        blocks.append(pf.Block(f"b{k}", pf.Elastic(25e9, 0.2, 2400.0)))
    interfaces = []
    laws = _joints() if joints is None else joints
    for k, (z, law) in enumerate(zip(cuts, laws, strict=True)):
        mesh.add_facet_group(f"j{k}", lambda x, z=z: np.abs(x[:, up] - z) < 1e-6,
                             boundary_only=False)  # fmt: skip
        interfaces.append(pf.Interface(f"j{k}", law))
    model = pf.Model(mesh, blocks, interfaces=interfaces)
    model.fix("zmin" if up == 2 else "ymin")
    return model


@dataclass
class Planted:
    """A planted problem: the free relative motion, the committed state at the start of
    the step, and the answer (forces, states, broken flags, relative motions)."""

    w_free: np.ndarray
    prev: PairState
    X: np.ndarray
    state: np.ndarray
    broken: np.ndarray
    w: np.ndarray


def plant(W: np.ndarray, laws: PairLaws, d: int, seed: int) -> Planted:
    """A planted solution on W (M × M) for the laws (see the module docstring): about a
    quarter of the pairs intact (where the joint is bonded), the others broken before the
    step, of which 45 % stick, 35 % slide and 20 % open."""
    rng = np.random.default_rng(seed)
    m = laws.n
    broken = laws.initially_broken | (rng.random(m) < 0.7)
    cI, muI, tI = laws.strength(np.zeros(m, dtype=bool), np.zeros(m))
    cR, muR, _ = laws.strength(np.ones(m, dtype=bool), np.zeros(m))
    F = float(np.median(cI[cI > 0]))  # force scale (N)
    delta = F * float(np.mean(np.diag(W)))  # displacement scale (m)
    u = rng.random(m)
    state = np.where(broken, np.where(u < 0.45, STICK, np.where(u < 0.8, SLIDE, OPEN)), INTACT)
    state = state.astype(np.int8)
    prev = laws.initial_state(d)
    prev.broken = broken.copy()
    prev.state[broken] = STICK
    prev.s[:, :-1] = delta * rng.uniform(-1, 1, (m, d - 1))  # slips so far
    prev.w = prev.s.copy()
    X = np.zeros((m, d))
    s = prev.s.copy()
    # intact: X_n in (−σ_t A/2, F), |X_t| ≤ (c A + μ X_n)/2
    it = state == INTACT
    xn = rng.uniform(-0.5 * tI, F)
    xn = np.maximum(xn, -0.5 * cI / np.maximum(muI, 1e-12))
    cap = np.maximum(cI + muI * xn, 0.0)
    X[it, -1] = xn[it]
    X[it, :-1] = _in_disc(rng, m, d, 0.5 * cap)[it]
    # stick: X_n in (0.1 F, F), |X_t| ≤ (c_r A + μ_r X_n)/2, s_n = 0
    sk = state == STICK
    xn = rng.uniform(0.1 * F, F, m)
    X[sk, -1] = xn[sk]
    X[sk, :-1] = _in_disc(rng, m, d, 0.5 * (cR + muR * xn))[sk]
    s[sk, -1] = 0.0
    # slide: X_t = −τ ŝ, Δs_t = α ŝ (α in (0.1, 1) δ), s_n = 0
    sl = state == SLIDE
    dirs = rng.standard_normal((m, d - 1))
    dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
    X[sl, -1] = xn[sl]
    X[sl, :-1] = -(cR + muR * xn)[sl, None] * dirs[sl]
    s[sl, :-1] += rng.uniform(0.1, 1.0, m)[sl, None] * delta * dirs[sl]
    s[sl, -1] = 0.0
    # open: X = 0, s_n in (0.1, 1) δ, any slip
    op = state == OPEN
    s[op, -1] = rng.uniform(0.1, 1.0, m)[op] * delta
    s[op, :-1] += delta * rng.uniform(-1, 1, (m, d - 1))[op]
    w = s - laws.compliance * X  # rigid joints here: w = s
    w[:, -1] -= laws.gap
    w_free = w - (W @ X.ravel()).reshape(m, d)
    return Planted(w_free, prev, X, state, broken, w)


def _in_disc(rng: np.random.Generator, m: int, d: int, radius: np.ndarray) -> np.ndarray:
    """Random vectors (m, d − 1) of length up to ``radius`` (m,)."""
    v = rng.standard_normal((m, d - 1))
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    return v * (radius * rng.random(m))[:, None]


def solve_planted(step: Any, solver: InterfaceSolver, pl: Planted, mode: str) -> PairState:
    """The planted problem through the time step's path (``mode = "step"``: bonded pairs
    break on converged forces) or the solver itself ("bonded"; "iterate": breaking within
    the iterations)."""
    if mode == "step":
        return step.solve(None, pl.w_free, pl.prev, breaking="converged", correct=False).pairs
    trial, _ = solver.solve(pl.w_free, pl.prev, breaking=mode == "iterate")
    return trial


def natural_map(W: np.ndarray, laws: PairLaws, pl: Planted, X: np.ndarray,
                broken: np.ndarray) -> float:  # fmt: skip
    """The natural-map residual of the answer X for the broken flags given, computed here
    from the law (not by the solver), scaled as the solver's tolerance: intact pairs ρ|Δs|
    and any excess over the intact strength; broken pairs the smaller of the open branch's
    |X| + max(0, −ρ s_n) and the closed branch's (Alart-Curnier) ρ|s_n| + max(0,
    −(X_n + σ_t A)) + |X_t − Π_τ(X_t − ρ Δs_t)|, τ = max(0, c A + μ X_n)."""
    m, d = X.shape
    rho = 1.0 / float(np.mean(np.diag(W)))
    s = pl.w_free + (W @ X.ravel()).reshape(m, d) + laws.compliance * X
    s[:, -1] += laws.gap
    ds = s - pl.prev.s
    c, mu, t = laws.strength(broken, pl.prev.path)
    r = np.zeros(m)
    it = ~broken
    Xn, Xt = X[:, -1], X[:, :-1]
    nt = np.linalg.norm(Xt, axis=1)
    r[it] = (rho * np.linalg.norm(ds[it], axis=1) + np.maximum(0, -(Xn + t))[it]
             + np.maximum(0, nt - c - mu * Xn)[it])  # fmt: skip
    # broken: the law of the open branch (X = 0, s_n ≥ 0) or of the closed one (s_n = 0,
    # X_n ≥ −σ_t A, X_t = Π_τ(X_t − ρ Δs_t)), whichever holds better
    r_open = np.linalg.norm(X, axis=1) + np.maximum(0.0, -rho * s[:, -1])
    z = Xt - rho * ds[:, :-1]
    tau = np.maximum(0.0, c + mu * Xn)
    nz = np.maximum(np.linalg.norm(z, axis=1), 1e-300)
    proj = z * np.minimum(1.0, tau / nz)[:, None]
    r_closed = (rho * np.abs(s[:, -1]) + np.maximum(0.0, -(Xn + t))
                + np.linalg.norm(Xt - proj, axis=1))  # fmt: skip
    r[broken] = np.minimum(r_open, r_closed)[broken]
    # the solver's measure (method.md §5.3): relative to the larger of the forces and
    # ρ |s_free|
    scale = max(float(np.abs(X).max()), rho * float(np.abs(pl.w_free).max()), 1e-300)
    return float(r.max() / scale)


_STEPS: dict[tuple[str, int], pf.Dynamic] = {}


def _dynamic(cell: str, n: int) -> pf.Dynamic:
    """The analysis of the model (cached): its step's W and laws."""
    key = (cell, n)
    if key not in _STEPS:
        model = _model_3d(cell, n) if cell in ("hexahedron", "tetra10") else _model_2d(cell, n)
        _STEPS[key] = pf.Dynamic(model, 0.01)
    return _STEPS[key]


def _check(cell: str, n: int, seeds: range, mode: str) -> tuple[int, int, float, float]:
    """Solve the planted problems of ``seeds`` by ``mode``: "step" (the time step's
    :meth:`InterfaceStep.solve`, bonded pairs breaking on converged forces), "bonded"
    (:meth:`InterfaceSolver.solve` with ``breaking=False``) or "iterate" (breaking within
    the iterations); returns (pairs, solved, worst natural-map residual, worst
    |X − X_planted| / max |X_planted|). Solved: the planted forces, relative motions (to
    1e-6 of their largest), states and broken flags, and a natural-map residual ≤ 1e-8.
    With "iterate" the answer need not be the planted one: an intact pair that an
    intermediate iterate overstresses breaks for good (breaking is monotone within a
    step), and the answer is then another solution of the law, with more pairs broken:
    solved means a natural-map residual ≤ 1e-8 for its broken flags, which include the
    planted ones."""
    an = _dynamic(cell, n)
    step = an.istep
    assert step is not None
    W = step.scale * step.W.matrix()
    laws, d = step.laws, an.d
    solver = InterfaceSolver(W, laws, settings=step.settings)
    worst_r = worst_x = 0.0
    solved = 0
    for seed in seeds:
        pl = plant(W, laws, d, seed)
        trial = solve_planted(step, solver, pl, mode)
        r = natural_map(W, laws, pl, trial.X, trial.broken)
        ex = float(np.abs(trial.X - pl.X).max() / np.abs(pl.X).max())
        ew = float(np.abs(trial.w - pl.w).max() / np.abs(pl.w).max())
        if mode == "iterate":
            ok = r <= 1e-8 and bool(np.all(trial.broken[pl.broken]))
        else:
            ok = (r <= 1e-8 and ex <= 1e-6 and ew <= 1e-6
                  and np.array_equal(trial.state, pl.state)
                  and np.array_equal(trial.broken, pl.broken))  # fmt: skip
            worst_x = max(worst_x, ex)
        solved += ok
        worst_r = max(worst_r, r)
    return laws.n, solved, worst_r, worst_x


@pytest.mark.parametrize(("cell", "n", "seeds"), [("quad", 100, 10), ("hexahedron", 10, 3)])
@pytest.mark.parametrize("mode", ["step", "bonded", "iterate"])
def test_planted_solutions(cell: str, n: int, seeds: int, mode: str) -> None:
    """Every planted problem solved (see :func:`_check`): 2D Q4, 303 pairs, 10 seeds;
    3D Hex8, 363 pairs, 3 seeds; measured: residuals ≤ 8e-9 (the 3D state iteration stops
    at the tolerance), forces to ≤ 1.1e-7 of the largest."""
    m, solved, r, ex = _check(cell, n, range(seeds), mode)
    assert m >= 300
    assert solved == seeds, (solved, r, ex)


@pytest.mark.slow
@pytest.mark.parametrize(("cell", "n"),
                         [("quad8", 60), ("tetra10", 6)])
@pytest.mark.parametrize("mode", ["step", "bonded", "iterate"])
def test_planted_solutions_large(cell: str, n: int, mode: str) -> None:
    """As above, 20 seeds each: 2D Q8 (363 pairs) and 3D Tet10 (507 pairs)."""
    m, solved, r, ex = _check(cell, n, range(20), mode)
    assert m >= 300
    assert solved == 20, (solved, r, ex)


TR_PA = 0.03e6  # residual tensile strength (Pa) of the first joint in the tension cases


def _joints_tension() -> list[pf.Joint]:
    """As :func:`_joints`, the first joint with a residual tensile strength σ_t,r = 0.03 MPa
    (short of the apex of its residual cone, c_r / tan φ_r = 0.071 MPa)."""
    first = _joints()[0]
    return [pf.Joint(c=first.c, phi=first.phi, tensile=first.tensile, c_r=first.c_r,
                     phi_r=first.phi_r, tensile_r=TR_PA, initial="intact"),
            *_joints()[1:]]  # fmt: skip


def plant_tension(W: np.ndarray, laws: PairLaws, d: int, seed: int, opening: bool) -> Planted:
    """:func:`plant`, then about half of the broken sticking and sliding pairs with a
    residual tensile strength moved into tension, X_n in (−0.8, −0.2) σ_t,r A: sticking
    inside the cone c_r A + μ_r X_n (friction in tension too), sliding on it. Without
    ``opening`` the open pairs with a residual tensile strength are closed (sticking at
    X_n = σ_t,r A / 2): such a pair's law, closed down to X_n = −σ_t,r A but open at X = 0,
    is not monotone."""
    pl = plant(W, laws, d, seed)
    rng = np.random.default_rng(1000 + seed)
    m = laws.n
    cR, muR, tR = laws.strength(np.ones(m, dtype=bool), np.zeros(m))
    state, X = pl.state.copy(), pl.X.copy()
    s = pl.w + laws.compliance * pl.X
    s[:, -1] += laws.gap
    pick = ((state == STICK) | (state == SLIDE)) & (tR > 0) & (rng.random(m) < 0.5)
    xn = -rng.uniform(0.2, 0.8, m) * tR
    cap = cR + muR * xn
    sk, sl = pick & (state == STICK), pick & (state == SLIDE)
    X[pick, -1] = xn[pick]
    X[sk, :-1] = _in_disc(rng, m, d, 0.5 * cap)[sk]
    X[sl, :-1] = pl.X[sl, :-1] * (cap[sl] / np.linalg.norm(pl.X[sl, :-1], axis=1))[:, None]
    if not opening:
        op = (state == OPEN) & (tR > 0)
        state[op] = STICK
        X[op] = 0.0
        X[op, -1] = 0.5 * tR[op]
        s[op] = pl.prev.s[op]
        s[op, -1] = 0.0
    assert sk.any() and sl.any()
    w = s - laws.compliance * X
    w[:, -1] -= laws.gap
    w_free = w - (W @ X.ravel()).reshape(m, d)
    return Planted(w_free, pl.prev, X, state, pl.broken, w)


def _check_tension(cell: str, n: int, seeds: range, mode: str, opening: bool) -> int:
    """The planted problems of :func:`plant_tension` solved as in :func:`_check` (forces,
    relative motions, states and broken flags; natural-map residual ≤ 1e-8): how many."""
    joints = _joints_tension()
    if cell == "hexahedron":
        model = _model_3d(cell, n, joints)
    else:
        model = _jointed(pf.rectangle(60.0, 36.0, n, int(0.6 * n), cell=cell), 1, 36.0, joints)
    an = pf.Dynamic(model, 0.01)
    step = an.istep
    assert step is not None
    W = step.scale * step.W.matrix()
    laws, d = step.laws, an.d
    solver = InterfaceSolver(W, laws, settings=step.settings)
    solved = 0
    for seed in seeds:
        pl = plant_tension(W, laws, d, seed, opening)
        trial = solve_planted(step, solver, pl, mode)
        r = natural_map(W, laws, pl, trial.X, trial.broken)
        ex = float(np.abs(trial.X - pl.X).max() / np.abs(pl.X).max())
        solved += (r <= 1e-8 and ex <= 1e-6 and np.array_equal(trial.state, pl.state)
                   and np.array_equal(trial.broken, pl.broken))  # fmt: skip
    return solved


@pytest.mark.parametrize(("cell", "n", "opening"),
                         [("quad", 100, True), ("hexahedron", 10, False),
                          ("hexahedron", 10, True)])  # fmt: skip
@pytest.mark.parametrize("mode", ["step", "bonded"])
def test_planted_residual_tension(cell: str, n: int, opening: bool, mode: str) -> None:
    """Broken pairs with a residual tensile strength, in tension (sticking and sliding,
    friction reducing the cone there: c_r A + μ_r X_n), and open: every planted problem
    solved, 2D Q4 (303 pairs, 4 seeds; the state iteration), 3D Hex8 (363 pairs, 2 seeds;
    the Newton) with such pairs open or not. Before, the Newtons took the cone as
    c_r A + μ_r X_n⁺ (no friction term in tension) and the 3D problems without open pairs
    ended in an InterfaceError (residual 7.8e-3), another law than the residual's; with
    open pairs they ended so (residual 1.4e-2) until the Newtons debonded the pairs their
    map held apart at X_n = −σ_t,r A (:meth:`InterfaceSolver._parting`)."""
    seeds = 4 if cell == "quad" else 2
    assert _check_tension(cell, n, range(seeds), mode, opening) == seeds
