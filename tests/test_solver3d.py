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
M = 1,521 components (above ``NEWTON_WOODBURY_MIN``).
"""

from __future__ import annotations

import numpy as np
import pytest

import pfeie as pf
import pfeie.interface._solver as solver_module
from pfeie.coupling import SolveStats
from pfeie.coupling._static import StaticInterfaceProblem
from pfeie.interface import InterfaceSolver, SolveInfo
from test_planted import _model_3d, natural_map, plant, solve_planted


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
    Newton after it as ``newton``, the cold start, the proximal-point Newton and projected
    Gauss-Seidel as fallbacks; iterations add up, the residual is the worst."""
    stats = SolveStats()
    methods = ["state iteration", "semismooth Newton", "semismooth Newton (cold start)",
               "proximal Newton", "projected Gauss-Seidel", "semismooth Newton"]
    for k, method in enumerate(methods):
        stats.add(SolveInfo(k + 1, 1e-10 * (k + 1), method))
    assert (stats.newton, stats.fallbacks, stats.solves, stats.iterations) == (2, 3, 6, 21)
    assert stats.residual == 6e-10
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
