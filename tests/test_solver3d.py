"""The 3D interface solver at scale: the semismooth Newton through the once-inverted W_c
(its Jacobian kept per pair, J = L + R W_c) and the bordered static problem on W_c⁻¹.

References, independent of the path under test:

- planted solutions on pfeie's own W (:mod:`test_planted`: forces, states and relative
  motions consistent with the Mohr-Coulomb law, and a natural-map residual computed from
  the law outside the solver);
- the dense path of the same solver (``NEWTON_WOODBURY_MIN`` raised: the state iteration,
  a semismooth Newton on the formed Jacobian with dense LU, the bordered system's LU per
  state pattern), which this path replaces at ≥ 1,500 components in 3D.

The model: a 20 m × 20 m × 12 m Hex8 column (12 × 12 × 4), three joints, 507 pairs,
M = 1,521 components (above ``NEWTON_WOODBURY_MIN``). Its static problem (three floating
blocks, the top joint existing with a residual cohesion) is also solved on the large
path, where capacitance systems of ``LARGE_CAPACITANCE`` rows or more are gathered into
work arrays and solved by a single-precision LU refined in double precision: against the
default and the dense paths and the blocks' equilibrium summed from the pair geometry.
"""

from __future__ import annotations

import copy

import numpy as np
import pytest

import pfeie as pf
import pfeie.interface._solver as solver_module
from pfeie.coupling import SolveStats
from pfeie.coupling._static import StaticInterfaceProblem
from pfeie.interface import (
    COHESION_RAMP,
    INTACT,
    OPEN,
    SLIDE,
    STICK,
    InterfaceSolver,
    SolveInfo,
    cohesion_ramp,
)
from pfeie.interface._solver import _rownorm
from test_planted import _joints, _model_3d, natural_map, plant, solve_planted


@pytest.fixture(scope="module")
def dynamic() -> pf.Dynamic:
    """The step's operators of the Hex8 column (507 pairs)."""
    return pf.Dynamic(_model_3d("hexahedron", 12), 0.01)


def _no_dense_newton(monkeypatch: pytest.MonkeyPatch) -> list[int]:
    """Count the calls of the dense Newton (none expected on the path under test)."""
    calls: list[int] = []
    dense = InterfaceSolver._newton

    def counted(self, *args, **kw):  # type: ignore[no-untyped-def]
        calls.append(1)
        return dense(self, *args, **kw)

    monkeypatch.setattr(InterfaceSolver, "_newton", counted)
    return calls


def _same_states(st: pf.interface.PairState, ref: pf.interface.PairState) -> None:
    """The same states where the broken flags agree, and these differ at one pair at
    most: an intact pair at its strength may break on one path and not on the other
    (breaking is monotone within the iterations; both answers meet the law)."""
    same = st.broken == ref.broken
    assert int((~same).sum()) <= 1
    np.testing.assert_array_equal(st.state[same], ref.state[same])


@pytest.mark.parametrize("mode", ["step", "bonded", "iterate"])
def test_planted_3d_through_the_inverse(
    dynamic: pf.Dynamic, mode: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Planted problems (3 seeds) solved by the Newton through W_c⁻¹, without the dense
    Newton: the planted states and broken flags, forces to 5e-8 of the largest (measured
    5.8e-9: the Newton stops at 0.1 of the tolerance), relative motions likewise, and a
    natural-map residual (computed from the law) ≤ 1e-8, the solver's tolerance (measured
    5.2e-10)."""
    step = dynamic.istep
    assert step is not None
    W = step.scale * step.W.matrix()
    laws, d = step.laws, dynamic.d
    assert W.shape[0] >= solver_module.NEWTON_WOODBURY_MIN
    solver = InterfaceSolver(W, laws, settings=step.settings)
    assert solver.woodbury
    calls = _no_dense_newton(monkeypatch)
    for seed in range(3):
        pl = plant(W, laws, d, seed)
        trial = solve_planted(step, solver, pl, mode)
        assert natural_map(W, laws, pl, trial.X, trial.broken) <= 1e-8
        np.testing.assert_allclose(trial.X, pl.X, rtol=0, atol=5e-8 * np.abs(pl.X).max())
        np.testing.assert_allclose(trial.w, pl.w, rtol=0, atol=5e-8 * np.abs(pl.w).max())
        np.testing.assert_array_equal(trial.state, pl.state)
        np.testing.assert_array_equal(trial.broken, pl.broken)
    assert not calls


def test_newton_through_the_inverse_equals_the_dense_path(
    dynamic: pf.Dynamic, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Problems without a known answer (planted ones with a random extra shear and
    closing motion, so that many pairs change state and slide in new directions; bonded
    pairs kept bonded, so that the answer is unique): the answer through W_c⁻¹, by the
    Newton, equals that of the dense path to 2e-8 of the largest force (both stop at
    the tolerance 1e-8 of the residual; measured 2.2e-9), with the same states."""
    step = dynamic.istep
    assert step is not None
    W = step.scale * step.W.matrix()
    laws, d = step.laws, dynamic.d
    solver = InterfaceSolver(W, laws)
    for seed in range(3):
        pl = plant(W, laws, d, seed)
        rng = np.random.default_rng(50 + seed)
        scale = float(np.abs(pl.w_free).max())
        w_free = pl.w_free + 0.3 * scale * rng.standard_normal(pl.w_free.shape)
        calls = _no_dense_newton(monkeypatch)
        st, _ = solver.solve(w_free, pl.prev, breaking=False)
        assert not calls and solver.last.residual <= 1e-8
        assert solver.last.method == "semismooth Newton"
        stats = SolveStats()  # the designed second stage, not a fallback
        stats.add(solver.last)
        assert (stats.newton, stats.fallbacks, stats.solves) == (1, 0, 1)
        monkeypatch.undo()
        with monkeypatch.context() as mp:
            mp.setattr(solver_module, "NEWTON_WOODBURY_MIN", 10**9)
            ref_solver = InterfaceSolver(W, laws)
            ref, _ = ref_solver.solve(w_free, pl.prev, breaking=False)
        assert ref_solver.last.residual <= 1e-8
        np.testing.assert_allclose(st.X, ref.X, rtol=0, atol=2e-8 * np.abs(ref.X).max())
        np.testing.assert_array_equal(st.state, ref.state)


@pytest.mark.parametrize(("kx", "ky"), [(0.0, 0.0), (0.6, 0.3)])
def test_bordered_static_problem_on_the_inverse(
    kx: float, ky: float, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The static problem with floating blocks (three blocks held by their joints only,
    18 rigid amplitudes), gravity and a lateral load of kx, ky times the weight (at
    0.6, 0.3 most pairs of the existing joint slide): the state systems and the Newton on
    W_c⁻¹ with the r × r border system give the forces and rigid amplitudes of the dense
    bordered path to 5e-10 of the largest (measured 5e-11), without the dense Newton (the
    sliding case by the Newton on W_c⁻¹, the other by the state iteration)."""
    model = _model_3d("hexahedron", 12)
    model.add_gravity()
    system = model.system()
    problem = StaticInterfaceProblem(model, system)
    assert problem.solver.woodbury and problem.solver.E is not None
    f = np.zeros(model.n_dof)
    f[system.free] = system.load(0.0)
    f[0::3] -= kx * f[2::3]
    f[1::3] -= ky * f[2::3]
    f_free = f[system.free]
    calls = _no_dense_newton(monkeypatch)
    _, st = problem.solve(f_free)
    assert problem.solver.last.residual <= 1e-8 and not calls
    if kx:  # the sliding case goes through the Newton on W_c⁻¹ with the border
        assert problem.solver.last.method == "semismooth Newton"
    monkeypatch.undo()
    # the same problem on the dense path
    keep, Phi = problem.keep, problem.Phi
    u_pin = np.zeros(system.free.size)
    u_pin[keep] = problem.factor.solve(f_free[keep])
    w_free = (problem.op.G @ u_pin + problem.w_pres).reshape(-1, 3)
    e = -(Phi.T @ f_free)
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(solver_module, "NEWTON_WOODBURY_MIN", 10**9)
        ref_solver = InterfaceSolver(problem.W.matrix(), model.pair_laws,
                                     border=problem.op.G @ Phi,
                                     regularize=model.pairs.regularization)  # fmt: skip
        assert not ref_solver.woodbury
        ref, q_ref = ref_solver.solve(w_free, model.pair_laws.initial_state(3), e)
    _, q = problem.solver.solve(w_free, model.pair_laws.initial_state(3), e)
    np.testing.assert_allclose(st.X, ref.X, rtol=0, atol=5e-10 * np.abs(ref.X).max())
    np.testing.assert_allclose(q, q_ref, rtol=0, atol=5e-10 * np.abs(q_ref).max())
    _same_states(st, ref)
    if kx:
        assert (st.state == pf.interface.SLIDE).sum() > 100


def test_solve_statistics_tell_the_newton_from_the_fallbacks() -> None:
    """The per-step counters: the state iteration counts as neither, the semismooth
    Newton after it and the proximal-point Newton as the 3D second stage
    (PROXIMAL_FIRST_3D) as ``newton``, the cold start, the proximal-point Newton after the
    Newtons and projected Gauss-Seidel as fallbacks; iterations add up, the residual is
    the worst."""
    from pfeie.interface import SECOND_STAGE_PROXIMAL

    stats = SolveStats()
    methods = ["state iteration", "semismooth Newton", "semismooth Newton (cold start)",
               "proximal Newton", "projected Gauss-Seidel", "semismooth Newton",
               SECOND_STAGE_PROXIMAL]  # fmt: skip
    for k, method in enumerate(methods):
        stats.add(SolveInfo(k + 1, 1e-10 * (k + 1), method))
    assert (stats.newton, stats.fallbacks, stats.solves, stats.iterations) == (3, 3, 7, 28)
    assert stats.residual == 1e-10 * 7
    stats.reset()
    assert (stats.newton, stats.fallbacks, stats.solves, stats.residual) == (0, 0, 0, 0.0)


@pytest.mark.parametrize(("held_pairs", "sliding"), [(0, 200), (60, 200), (300, 100)])
def test_newton_step_with_held_rows_equals_the_dense_solve(
    dynamic: pf.Dynamic, held_pairs: int, sliding: int
) -> None:
    """One Newton step through W_c⁻¹ (J x = b, J = L + R W_c, L and R block diagonal)
    with rows X_j = 0 (pairs held open, separated pairs: L a unit row, R = 0), sliding
    rows (random L and R) and kinematic rows (L = 0, R = ρI), by the capacitance system
    of the rows that are not kinematic: equal to the dense solve of the formed J to
    5e-14 of the largest entry of x (measured ≤ 1.1e-14), and W_c x the returned one to
    2e-13 (measured ≤ 2.5e-14), without and with held rows, a few or most of o."""
    step = dynamic.istep
    assert step is not None
    W = step.scale * step.W.matrix()
    solver = InterfaceSolver(W, step.laws)
    m, d, r = solver.m, solver.d, solver.rho
    rng = np.random.default_rng(7)
    kind = rng.permutation(np.repeat([0, 1, 2], [held_pairs, sliding, m - held_pairs - sliding]))
    L, R = np.zeros((m, d, d)), np.zeros((m, d, d))
    kin = np.zeros((m, d), dtype=bool)
    L[kind == 0] = np.eye(d)  # held open or separated: X = 0
    sl = np.flatnonzero(kind == 1)  # sliding: tangential rows L = I − P, R = ρP, normal ρ
    for p in sl:
        z = rng.standard_normal(d - 1)
        z /= np.linalg.norm(z)
        P = rng.uniform(0.1, 0.9) * (np.eye(d - 1) - np.outer(z, z))
        L[p, :-1, :-1], R[p, :-1, :-1] = np.eye(d - 1) - P, r * P
        L[p, :-1, -1] = -0.6 * z
    R[sl, -1, -1] = r
    kin[sl, -1] = True
    R[kind == 2] = r * np.eye(d)  # intact or sticking: the rows of ρ W_c
    kin[kind == 2] = True
    B = rng.standard_normal((m * d, 1))
    x, ds = solver._woodbury_step(L, R, kin, B)
    J = np.zeros((m * d, m * d))
    for p in range(m):
        J[p * d:(p + 1) * d, p * d:(p + 1) * d] = L[p]
    Rb = np.zeros_like(J)
    for p in range(m):
        Rb[p * d:(p + 1) * d, p * d:(p + 1) * d] = R[p]
    J += Rb @ solver.Wc
    ref = np.linalg.solve(J, B)
    assert np.abs(x - ref).max() <= 5e-14 * np.abs(ref).max()
    assert np.abs(ds - solver.Wc @ x).max() <= 2e-13 * np.abs(ds).max()


def _large_state(laws: pf.interface.PairLaws, d: int, seed: int) -> tuple[
        pf.interface.PairState, pf.interface.PairState, np.ndarray, np.ndarray]:  # fmt: skip
    """A state pattern of the Hex8 column with a capacitance system of 1,300 rows (300
    open pairs, 200 sliding in random directions, the rest sticking, all broken) and a
    closing w_free: the previous and the trial state, the kind of each pair and w_free."""
    m = laws.n
    rng = np.random.default_rng(seed)
    prev = laws.initial_state(d)
    prev.broken[:] = True
    st = prev.copy()
    kind = rng.permutation(np.repeat([0, 1, 2], [300, 200, m - 500]))
    st.state[kind == 0] = pf.interface.OPEN
    st.state[kind == 1] = pf.interface.SLIDE
    st.state[kind == 2] = pf.interface.STICK
    sdir = rng.standard_normal((m, d - 1))
    st.slip_dir = sdir / np.linalg.norm(sdir, axis=1)[:, None]
    w_free = rng.standard_normal((m, d)) * 1e-4
    w_free[:, -1] = -np.abs(w_free[:, -1])  # closing: compressive normal forces
    # a last iterate in compression, off the residual cohesion's ramp (its steep cone near
    # X_n = 0 is not what these tests are about)
    st.X[:, -1] = 1e12
    return prev, st, kind, w_free


def _spy_mixed(mp: pytest.MonkeyPatch) -> list[int]:
    """Record the sizes of the systems the solver gives to the single-precision LU."""
    used: list[int] = []
    mixed = solver_module.MixedLU

    class Spy(mixed):  # type: ignore[misc, valid-type]
        def __init__(self, a, *args, **kw):  # type: ignore[no-untyped-def]
            used.append(a.shape[0])
            super().__init__(a, *args, **kw)

    mp.setattr(solver_module, "MixedLU", Spy)
    return used


def test_large_state_system_equals_the_cached_lu_path(
    dynamic: pf.Dynamic, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A state system of more than ``LARGE_CAPACITANCE`` open and sliding components (300
    open pairs, 200 sliding in random directions, the rest sticking: k = 1,300 of
    M = 1,521), assembled in work arrays with the sliding rows last and solved by the
    single-precision LU refined in double, equals the LU path that smaller systems take
    (the capacitance gathered from W_c⁻¹ and factorised in double precision) to 1e-14 of
    the largest force (measured 1.1e-15), and the state system's rows hold: the open
    components carry no force (exactly), the sliding ones X_t = −(c + μ X_n) ŝ (to 1e-14;
    measured 1.0e-15)."""
    step = dynamic.istep
    assert step is not None
    W = step.scale * step.W.matrix()
    laws = step.laws
    prev, st, kind, w_free = _large_state(laws, dynamic.d, 11)
    solver = InterfaceSolver(W, laws)
    with monkeypatch.context() as mp:
        used = _spy_mixed(mp)
        X, _ = solver._linear(st, prev, w_free, None)
    assert used == [1300]  # the large path was taken
    with monkeypatch.context() as mp:
        mp.setattr(solver_module, "LARGE_CAPACITANCE", 10**9)
        ref_solver = InterfaceSolver(W, laws)
        ref, _ = ref_solver._linear(st, prev, w_free, None)
    assert np.abs(X - ref).max() <= 1e-14 * np.abs(ref).max()
    scale = np.abs(ref).max()
    assert not X[kind == 0].any()
    c, mu, _ = laws.strength(st.broken, prev.path)
    sl = kind == 1
    expect = -mu[sl, None] * X[sl, -1:] * st.slip_dir[sl] - c[sl, None] * st.slip_dir[sl]
    assert np.abs(X[sl, :-1] - expect).max() <= 1e-14 * scale


def test_solvers_sharing_work_arrays_keep_their_own_gathers(dynamic: pf.Dynamic) -> None:
    """The solvers of :meth:`InterfaceSolver.with_laws` (the smooth forces and the step
    impulses of one step) share their work arrays: a Newton step of one between two
    equal steps of the other (k = 1,100 rows, the large path, whose gather is kept while
    the set and pattern stay) leaves the other's second step equal to its first, to the
    bit."""
    step = dynamic.istep
    assert step is not None
    W = step.scale * step.W.matrix()
    a = InterfaceSolver(W, step.laws)
    b = a.with_laws(step.laws)
    assert b._work is a._work
    m, d, r = a.m, a.d, a.rho

    def system(seed: int) -> tuple[np.ndarray, ...]:
        rng = np.random.default_rng(seed)
        kind = rng.permutation(np.repeat([0, 1, 2], [300, 100, m - 400]))
        L, R = np.zeros((m, d, d)), np.zeros((m, d, d))
        kin = np.zeros((m, d), dtype=bool)
        L[kind == 0] = np.eye(d)
        sl = kind == 1
        L[sl, :-1, :-1] = 0.5 * np.eye(d - 1)
        R[sl, :-1, :-1] = 0.5 * r * np.eye(d - 1)
        R[sl, -1, -1] = r
        kin[sl, -1] = True
        R[kind == 2] = r * np.eye(d)
        kin[kind == 2] = True
        return L, R, kin, rng.standard_normal((m * d, 1))

    first = a._woodbury_step(*system(1))[0]
    b._woodbury_step(*system(2))
    again = a._woodbury_step(*system(1))[0]
    np.testing.assert_array_equal(again, first)


def test_large_state_system_refined_on_a_reference(
    dynamic: pf.Dynamic, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The large state system (k = 1,300, as above) of a W that differs from the
    reference's by 0.1 % (large rotations turn the pair frames), refined on the
    reference's W_c⁻¹ with its capacitance system in work arrays and the single-precision
    LU, equals the solve of this W's own factorisation on the cached-LU path to 2e-14 of
    the largest force (measured 3.1e-15)."""
    step = dynamic.istep
    assert step is not None
    W = step.scale * step.W.matrix()
    laws = step.laws
    rng = np.random.default_rng(12)
    D = 1.0 + 1e-3 * rng.uniform(-1.0, 1.0, W.shape[0])
    W2 = D[:, None] * W * D[None, :]  # symmetric, positive definite, 0.1 % away
    prev, st, _, w_free = _large_state(laws, dynamic.d, 12)
    refined = InterfaceSolver(W2, laws, reference=InterfaceSolver(W, laws))
    assert refined.refined
    with monkeypatch.context() as mp:
        used = _spy_mixed(mp)
        X, _ = refined._linear(st, prev, w_free, None)
    assert refined.refined and used == [1300]  # refined on the reference, the large path
    with monkeypatch.context() as mp:
        mp.setattr(solver_module, "LARGE_CAPACITANCE", 10**9)
        ref, _ = InterfaceSolver(W2, laws)._linear(st, prev, w_free, None)
    assert np.abs(X - ref).max() <= 2e-14 * np.abs(ref).max()


def _cohesive_top() -> list[pf.Joint]:
    """The column's joints with its top joint existing (broken) and a residual cohesion of
    20 kPa: its pairs that close, from open or from X_n = 0, pass the cohesion ramp."""
    bonded, weak, _ = _joints()
    return [bonded, weak, pf.Joint(phi=35.0, c_r=0.02e6, initial="broken")]


@pytest.fixture(scope="module")
def static() -> StaticInterfaceProblem:
    """The static problem of the Hex8 column (its top joint :func:`_cohesive_top`) under
    gravity: three floating blocks held by their joints only (18 rigid amplitudes),
    507 pairs, M = 1,521 (above ``SYMMETRIC_MIN``, the size of the large path)."""
    model = _model_3d("hexahedron", 12, _cohesive_top())
    model.add_gravity()
    return StaticInterfaceProblem(model, model.system())


def _static_inputs(problem: StaticInterfaceProblem, f: np.ndarray) -> tuple[np.ndarray, ...]:
    """The free relative motion w_free (the floating blocks pinned) and the border's
    right-hand side e = −Φᵀ f of the static problem under the loads ``f`` (all DOFs), as
    :meth:`StaticInterfaceProblem.solve` forms them."""
    f_free = f[problem.system.free]
    u_pin = np.zeros(f_free.size)
    u_pin[problem.keep] = problem.factor.solve(f_free[problem.keep])
    w_free = (problem.op.G @ u_pin + problem.w_pres).reshape(-1, 3)
    return w_free, -(problem.Phi.T @ f_free)


def _eccentric_load(problem: StaticInterfaceProblem, kx: float, ky: float, a: float) -> np.ndarray:
    """Gravity with its vertical loads shifted towards x = 0, f_z (1 − a (x − 10 m)/10 m)
    (the same weight, its resultant 3.3a m off the centre: beyond the middle third for
    a > 1, so that the joints lift on one side), and lateral loads kx, ky times the
    weight: the load vector on all DOFs."""
    model, system = problem.model, problem.system
    f = np.zeros(model.n_dof)
    f[system.free] = system.load(0.0)
    fz = f[2::3].copy()
    f[0::3] -= kx * fz
    f[1::3] -= ky * fz
    f[2::3] = fz * (1.0 - a * (model.mesh.points[:, 0] - 10.0) / 10.0)
    return f


def _block_balance(problem: StaticInterfaceProblem, f: np.ndarray, X: np.ndarray) -> tuple[
        float, float]:  # fmt: skip
    """The out-of-balance force and moment of the floating blocks (those without a
    support) under the loads ``f`` (all DOFs) and the pair forces X, summed here from the
    pair geometry, not through G, Φ or the border: each pair's force T_kᵀ X_k on its node
    b and the opposite on its node a, at the nodes' positions, the moments about each
    block's node centroid. The largest component over the blocks, relative to the sum of
    the magnitudes of the forces in the block's balance (its loads and its pairs' forces)
    and to that sum times the block's width (20 m)."""
    model = problem.model
    P = model.pairs
    assert P is not None
    body, x = model.body_of_node, model.mesh.points
    fixed = np.unique(body[problem.system.prescribed // 3])
    F = np.einsum("kji,kj->ki", P.frame, X)  # local = T_k global: the force on side b
    fn = f.reshape(-1, 3)
    worst_f = worst_m = 0.0
    for b in np.setdiff1d(np.arange(model.n_bodies), fixed):
        nodes = np.flatnonzero(body == b)
        c = x[nodes].mean(axis=0)
        on_b, on_a = body[P.node_b] == b, body[P.node_a] == b
        force = fn[nodes].sum(axis=0) + F[on_b].sum(axis=0) - F[on_a].sum(axis=0)
        moment = (np.cross(x[nodes] - c, fn[nodes]).sum(axis=0)
                  + np.cross(x[P.node_b[on_b]] - c, F[on_b]).sum(axis=0)
                  - np.cross(x[P.node_a[on_a]] - c, F[on_a]).sum(axis=0))  # fmt: skip
        total = float(_rownorm(fn[nodes]).sum() + _rownorm(F[on_b | on_a]).sum())
        worst_f = max(worst_f, float(np.abs(force).max()) / total)
        worst_m = max(worst_m, float(np.abs(moment).max()) / (20.0 * total))
    return worst_f, worst_m


def _spy_bordered(mp: pytest.MonkeyPatch) -> tuple[list[tuple[str, int, int]],
                                                   list[tuple[int, int]], list[int]]:  # fmt: skip
    """Record what the solver gives to the single-precision LU (its name, rows and
    right-hand sides at each solve), the rows of each bordered state system's capacitance
    system with its sliding rows, and at each Newton iterate the pairs in contact on the
    cohesion ramp."""
    solves: list[tuple[str, int, int]] = []
    systems: list[tuple[int, int]] = []
    ramp: list[int] = []
    mixed = solver_module.MixedLU

    class Spy(mixed):  # type: ignore[misc, valid-type]
        def __init__(self, a, work, name, *args, **kw):  # type: ignore[no-untyped-def]
            self.label = name
            super().__init__(a, work, name, *args, **kw)

        def solve(self, b):  # type: ignore[no-untyped-def]
            solves.append((self.label, b.shape[0], b.shape[1] if b.ndim == 2 else 1))
            return super().solve(b)

    bordered = InterfaceSolver._woodbury_bordered

    def recorded(self, key, fr, coef, x0, target, w_free, oth, *args):  # type: ignore[no-untyped-def]
        systems.append((oth.size, fr.size))
        return bordered(self, key, fr, coef, x0, target, w_free, oth, *args)

    local_map = InterfaceSolver._local_map

    def on_ramp(self, X, s_, broken, prev, jac):  # type: ignore[no-untyped-def]
        if jac:  # an iterate, not a trial point of the line search
            c, mu, t = self.props.strength(broken, prev.path)
            on = cohesion_ramp(c, mu, t, X[:, -1], broken)[0]
            ramp.append(int((on & (X[:, -1] + t - self.rho * s_[:, -1] > 0)).sum()))
        return local_map(self, X, s_, broken, prev, jac)

    mp.setattr(solver_module, "MixedLU", Spy)
    mp.setattr(InterfaceSolver, "_woodbury_bordered", recorded)
    mp.setattr(InterfaceSolver, "_local_map", on_ramp)
    return solves, systems, ramp


def test_large_bordered_static_problem(
    static: StaticInterfaceProblem, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The static problem with floating blocks on the large path (``LARGE_CAPACITANCE``
    lowered to 100; M = 1,521 is above ``SYMMETRIC_MIN``): two load steps, gravity shifted
    towards x = 0 and lateral loads (:func:`_eccentric_load`, a = 1.5, kx = 0.2, then
    a = 1.8, kx = 0.3, ky = 0.1, from the first answer): the top joint lifts on one side
    and slides, the bonded joints hold. Reached: intact, sticking, sliding and open pairs
    (338/93/13/63, then 338/67/24/78); state systems of 117 to 176 rows (a first of 78
    below the threshold) through work arrays and the single-precision LU, the second
    step's first, from the start, with 26 sliding rows; Newton steps of 163 to 282 rows;
    each solve for the 1 + 18 columns [b, E]; at the second step's first Newton iterate
    27 pairs in contact on the top joint's cohesion ramp (none at the answers). Checked:

    - the same problem on the default path (the capacitance systems gathered from W_c⁻¹,
      LU in double precision): forces to 1e-11 of the largest (measured 1.4e-12), rigid
      amplitudes to 2e-12 (1.7e-13), the same states: the two paths take the same
      iterates to round-off, the ramp's steep cone included;
    - the first step on the dense bordered path (state iteration and Newton on the
      formed (M + 18)-square system; the second step, from a start, breaks two more pairs
      of the bonded joint there, another answer of the law): forces to 5e-10 (measured
      3.6e-11), rigid amplitudes to 1e-11 (7.5e-13), the same states;
    - the equilibrium of each floating block summed from the pair geometry
      (:func:`_block_balance`): force to 2e-15, moment to 5e-16 (measured 3.3e-16,
      9.1e-17)."""
    problem = static
    laws, pairs = problem.model.pair_laws, problem.model.pairs
    assert pairs is not None
    loads = [_eccentric_load(problem, 0.2, 0.0, 1.5), _eccentric_load(problem, 0.3, 0.1, 1.8)]
    inputs = [_static_inputs(problem, f) for f in loads]
    large, default = copy.deepcopy(problem.solver), copy.deepcopy(problem.solver)
    assert large.E is not None and large.E.shape == (1521, 18)

    def run(solver: InterfaceSolver, steps: int) -> list[tuple[pf.interface.PairState,
                                                               np.ndarray]]:  # fmt: skip
        out, start = [], None
        for w_free, e in inputs[:steps]:
            st, q = solver.solve(w_free, laws.initial_state(3), e, start=start)
            assert solver.last.residual <= 1e-8
            out.append((st, q))
            start = st
        return out

    with monkeypatch.context() as mp:
        mp.setattr(solver_module, "LARGE_CAPACITANCE", 100)
        solves, systems, ramp = _spy_bordered(mp)
        calls = _no_dense_newton(mp)
        answers = run(large, 2)
        assert large.last.method == "semismooth Newton" and not calls
    # the large path ran with the border: state systems (one with sliding rows) and
    # Newton steps, each solved for the 1 + 18 columns [b, E]
    assert {name for name, _, _ in solves} == {"state single", "newton"}
    assert all(c == 19 for _, _, c in solves)
    assert any(k >= 100 and nf for k, nf in systems)
    assert max(ramp) > 0
    with monkeypatch.context() as mp:
        mp.setattr(solver_module, "LARGE_CAPACITANCE", 10**9)
        used = _spy_mixed(mp)
        refs = run(default, 2)
        assert not used
    with monkeypatch.context() as mp:
        mp.setattr(solver_module, "NEWTON_WOODBURY_MIN", 10**9)
        dense = InterfaceSolver(problem.W.matrix(), laws, border=problem.op.G @ problem.Phi,
                                regularize=pairs.regularization)  # fmt: skip
        assert not dense.woodbury
        refs_dense = run(dense, 1)
    for (st, q), (ref, q_ref) in zip(answers, refs, strict=True):
        np.testing.assert_allclose(st.X, ref.X, rtol=0, atol=1e-11 * np.abs(ref.X).max())
        np.testing.assert_allclose(q, q_ref, rtol=0, atol=2e-12 * np.abs(q_ref).max())
        np.testing.assert_array_equal(st.state, ref.state)
    (st, q), (ref, q_ref) = answers[0], refs_dense[0]
    np.testing.assert_allclose(st.X, ref.X, rtol=0, atol=5e-10 * np.abs(ref.X).max())
    np.testing.assert_allclose(q, q_ref, rtol=0, atol=1e-11 * np.abs(q_ref).max())
    np.testing.assert_array_equal(st.state, ref.state)
    for f, (st, _) in zip(loads, answers, strict=True):
        assert all(np.isin([INTACT, STICK, SLIDE, OPEN], st.state))
        force, moment = _block_balance(problem, f, st.X)
        assert force <= 2e-15 and moment <= 5e-16


@pytest.mark.parametrize("on_ramp", [0, 20])
def test_large_bordered_state_system_equals_the_cached_lu_path(
    static: StaticInterfaceProblem, on_ramp: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A bordered state system above ``LARGE_CAPACITANCE`` at the default thresholds:
    every pair broken, per joint 79 open, 60 sliding in random directions and 30 sticking
    (which hold the floating blocks): k = 1,071 of M = 1,521, with the border of gravity's
    equilibrium (18 rigid amplitudes); the last iterate in compression, or with 20 of the
    sliding pairs that keep a residual cohesion on its ramp (X_n = κ c A/2: their cone's
    tangent there, τ ≈ c A/4 + (μ + 1/κ) X_n, of slope 1/κ = 1,000 and more). Solved in
    work arrays by the single-precision LU, for the 1 + 18 columns [b, E] (on the ramp
    its refinement stops short of round-off, at 2.2e-13 of the solution, and it
    factorises in double precision), it equals

    - the cached-LU path (``LARGE_CAPACITANCE`` raised): forces to 2e-12 of the largest
      and rigid amplitudes to 5e-12 off the ramp (measured 2.8e-13, 7.0e-13), to 1e-10
      and 2e-10 on it (measured 1.1e-11, 2.5e-11);
    - the dense bordered path (an LU of the (M − k + 18)-square system, W_c not
      inverted): to 1e-11 and 2e-11 off the ramp (measured 1.7e-12, 2.6e-12), 2e-10 and
      2e-10 on it (measured 2.2e-11, 2.3e-11). On the ramp the dense and the cached
      paths differ as much as the large and the cached (measured 0.8 to 3e-11 over four
      patterns): the spread of a system that the ramp's slope makes sensitive, not the
      single-precision LU's;

    and its rows hold: the open pairs carry no force (exactly); the sliding ones
    X_t = −(c + μ X_n) ŝ, with the ramp's c and μ where it applies, to 2e-12 of the
    largest force off the ramp and 5e-12 on it (measured 2.2e-13, 7.1e-13: X = X₀ − T q
    carries the round-off of T q, as on the cached path; the dense path 1e-16); the
    kinematic rows (sticking pairs, the sliding normals) s = s_prev to 2e-11 of the
    largest force in ρ s (measured 2.4e-12, 2.9e-12; the cached path 4.8e-12, 9.7e-13);
    the floating blocks' equilibrium Eᵀ X = e to 1e-15 of the largest entry of |E|ᵀ|X|
    (measured 1.2e-16, 5.0e-17), and summed from the pair geometry
    (:func:`_block_balance`) force to 2e-15, moment to 5e-16 (measured 2.6e-16,
    7.2e-17)."""
    problem = static
    model = problem.model
    laws, P = model.pair_laws, model.pairs
    assert P is not None
    m, d = laws.n, 3
    rng = np.random.default_rng(31)
    prev = laws.initial_state(d)
    prev.broken[:] = True
    st = prev.copy()
    kind = np.zeros(m, dtype=np.int64)  # 0 open, 1 sliding, 2 sticking
    for j in range(3):
        idx = P.of(f"j{j}")
        kind[idx] = rng.permutation(np.repeat([0, 1, 2], [79, idx.size - 109, 30]))
    st.state[kind == 0] = OPEN
    st.state[kind == 1] = SLIDE
    st.state[kind == 2] = STICK
    sdir = rng.standard_normal((m, d - 1))
    st.slip_dir = sdir / np.linalg.norm(sdir, axis=1)[:, None]
    c, mu, t = laws.strength(st.broken, prev.path)
    st.X[:, -1] = 1e12
    ramp = rng.choice(np.flatnonzero((kind == 1) & (c > 0)), on_ramp, replace=False)
    st.X[ramp, -1] = 0.5 * COHESION_RAMP * c[ramp]
    f = np.zeros(model.n_dof)
    f[problem.system.free] = problem.system.load(0.0)
    w_free, e = _static_inputs(problem, f)
    large, cached = copy.deepcopy(problem.solver), copy.deepcopy(problem.solver)
    with monkeypatch.context() as mp:
        solves = _spy_bordered(mp)[0]
        X, q = large._linear(st, prev, w_free, e)
    assert solves == [("state single", 1071, 19)]  # the large path, with the border
    with monkeypatch.context() as mp:
        mp.setattr(solver_module, "LARGE_CAPACITANCE", 10**9)
        ref_cached = cached._linear(st, prev, w_free, e)
        mp.setattr(solver_module, "NEWTON_WOODBURY_MIN", 10**9)
        dense = InterfaceSolver(problem.W.matrix(), laws, border=problem.op.G @ problem.Phi,
                                regularize=P.regularization)  # fmt: skip
        assert not dense.woodbury
        ref_dense = dense._linear(st, prev, w_free, e)
    tols = [(1e-10, 2e-10), (2e-10, 2e-10)] if on_ramp else [(2e-12, 5e-12), (1e-11, 2e-11)]
    for (ref, q_ref), (tol_x, tol_q) in zip([ref_cached, ref_dense], tols, strict=True):
        np.testing.assert_allclose(X, ref, rtol=0, atol=tol_x * np.abs(ref).max())
        np.testing.assert_allclose(q, q_ref, rtol=0, atol=tol_q * np.abs(q_ref).max())
    scale = np.abs(X).max()
    assert not X[kind == 0].any()
    # the sliding rows, with the ramp's tangent where the last iterate is on it: at
    # u = X_n/(κ c) = 1/2, τ = μ X_n + c (2u − u²) ≈ c/4 + (μ + 1/κ) X_n
    on = cohesion_ramp(c, mu, t, st.X[:, -1], st.broken)[0]
    assert on[kind == 1].sum() == on_ramp
    sl = kind == 1
    c_s = np.where(on, 0.25 * c, c)[sl]
    mu_s = np.where(on, mu + 1.0 / COHESION_RAMP, mu)[sl]
    expect = -(c_s + mu_s * X[sl, -1])[:, None] * st.slip_dir[sl]
    assert np.abs(X[sl, :-1] - expect).max() <= (5e-12 if on_ramp else 2e-12) * scale
    kin = np.zeros((m, d), dtype=bool)
    kin[kind == 2] = True
    kin[sl, -1] = True
    E, x = problem.op.G @ problem.Phi, X.ravel()
    s = (w_free.ravel() + large.Wc @ x + E @ q).reshape(m, d)
    assert large.rho * np.abs(s[kin] - prev.s[kin]).max() <= 2e-11 * scale
    assert np.abs(E.T @ x - e).max() <= 1e-15 * (np.abs(E).T @ np.abs(x)).max()
    force, moment = _block_balance(problem, f, X)
    assert force <= 2e-15 and moment <= 5e-16


def test_a_load_that_stalled_the_newton_at_the_ramps_corner(
    static: StaticInterfaceProblem, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The column's static problem under :func:`_eccentric_load` (k_x, k_y, a) =
    (0.3, 0.2, 1.5), from rest. With a straight cohesion ramp (slope 1/κ up to
    X_n = κ c A, μ beyond) the Newton's iterates stepped from one piece to the other at
    that corner while the line search stopped them, and every start failed: an
    ``InterfaceError`` after 92 s, residual 3.9e-4. With the ramp's C¹ end
    (:func:`~pfeie.interface.cohesion_ramp`) the first Newton solves it (measured 25
    iterations, asserted ≤ 40), its iterates passing over the ramp (a pair in contact on
    it); at the answer the top joint lifts (58 pairs open) and slides at its
    edge (25 pairs), and each floating block is in balance, summed from the pair
    geometry, to 5e-16 of its forces (measured 4.3e-16 and 1.2e-16 for the moment)."""
    problem = static
    laws = problem.model.pair_laws
    f = _eccentric_load(problem, 0.3, 0.2, 1.5)
    w_free, e = _static_inputs(problem, f)
    solver = copy.deepcopy(problem.solver)
    with monkeypatch.context() as mp:
        ramp = _spy_bordered(mp)[2]
        st, _ = solver.solve(w_free, laws.initial_state(3), e)
    assert solver.last.method == "semismooth Newton"
    assert solver.last.iterations <= 40 and solver.last.residual <= 1e-8
    assert max(ramp) >= 1
    assert (st.state == OPEN).sum() >= 40 and (st.state == SLIDE).sum() >= 10
    force, moment = _block_balance(problem, f, st.X)
    assert force <= 5e-15 and moment <= 5e-15


def test_the_load_continuation(static: StaticInterfaceProblem) -> None:
    """The load continuation (the last stage of a static problem with floating blocks)
    on the column under (k_x, k_y, a) = (0.4, 0.2, 1.5), from rest, whose Newtons failed
    on a machine with an AMD EPYC (residual 8.8e-4): called directly, so that it is
    tested whatever the Newtons do on an installation: each fraction solved from the
    last (measured 46 iterations in all, asserted ≤ 100), the answer within the
    tolerance, 52 pairs open, and each floating block in balance to 3e-15 of its forces
    (measured 3.0e-16, 1.1e-16 for the moment)."""
    problem = static
    laws = problem.model.pair_laws
    f = _eccentric_load(problem, 0.4, 0.2, 1.5)
    w_free, e = _static_inputs(problem, f)
    solver = copy.deepcopy(problem.solver)
    out = solver._continuation(w_free, laws.initial_state(3), e, "", 0, None, True, None)
    assert out is not None
    st, _ = out
    assert solver.last.method == "semismooth Newton (load continuation)"
    assert solver.last.residual <= 1e-8 and solver.last.iterations <= 100
    force, moment = _block_balance(problem, f, st.X)
    assert force <= 3e-15 and moment <= 3e-15
    assert (st.state == OPEN).sum() >= 40


@pytest.mark.slow
def test_eccentric_loads_on_the_cohesive_column(static: StaticInterfaceProblem) -> None:
    """72 static problems of the column (:func:`_eccentric_load`, k_x 0.1 to 0.4, k_y 0 to
    0.2, a 1.5 to 2; from rest and from the answer at (0.2, 0, 1.5)): with the straight
    ramp, 5 ended in ``InterfaceError`` and 9 took 210 to 310 Newton iterations (18 to
    40 s, their first Newtons running to the limit of 100 iterations). With the ramp's C¹
    end and the Newtons that hand over when they stall (``NEWTON_STALL``): all solved, the
    most iterations 142 (a cold start after two stalled ones). On a machine with an AMD EPYC
    (AVX-512; the same wheels as before) the Newtons' paths moved with the round-off,
    and 5 of the 72 ended in
    ``InterfaceError`` again (residuals 4e-4 to 1.5e-3; the same with the code of before);
    the load continuation (``CONTINUATION``: the problem at 0.5, 0.75, 0.9 and 1 of its
    loads, each answer the start of the next) solves them: all 72 solved, the most
    iterations 376 (a continuation after the Newtons, the work of both counted), asserted
    < 500; each floating block in balance to 5e-15."""
    problem = static
    laws = problem.model.pair_laws
    w1, e1 = _static_inputs(problem, _eccentric_load(problem, 0.2, 0.0, 1.5))
    first, _ = copy.deepcopy(problem.solver).solve(w1, laws.initial_state(3), e1)
    most = 0
    for kx in (0.1, 0.2, 0.3, 0.4):
        for ky in (0.0, 0.1, 0.2):
            for a in (1.5, 1.8, 2.0):
                f = _eccentric_load(problem, kx, ky, a)
                w_free, e = _static_inputs(problem, f)
                for start in (None, first):
                    solver = copy.deepcopy(problem.solver)
                    st, _ = solver.solve(w_free, laws.initial_state(3), e, start=start)
                    assert solver.last.residual <= 1e-8
                    most = max(most, solver.last.iterations)
                    force, moment = _block_balance(problem, f, st.X)
                    assert force <= 5e-15 and moment <= 5e-15
    assert most < 500
