"""The interface solver on its own: pairs held open inside the full solver against the
sub-problem of the other pairs (an independent computation on the sub-block of W)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from pfeie.errors import InterfaceError
from pfeie.interface import OPEN, InterfaceSolver, Joint, PairLaws, PairState, coulomb_laws


def _problem(m: int, d: int, seed: int) -> tuple[np.ndarray, PairLaws, np.ndarray]:
    """A random SPD W of m pairs (a well-conditioned Delassus-like operator), friction
    laws (μ = 0.3 to 0.8, half the pairs bonded with cohesion and tension), and a free
    motion that closes most pairs, pushes some apart and shears all."""
    rng = np.random.default_rng(seed)
    A = rng.standard_normal((m * d, m * d))
    W = A @ A.T / (m * d) + np.eye(m * d)
    laws = [Joint(phi=20.0), Joint(phi=35.0), Joint(c=0.5, phi=40.0, tensile=0.3,
                                                    initial="intact")]  # fmt: skip
    props = PairLaws.from_interfaces(np.ones(m), rng.integers(0, 3, m), laws, d)
    w_free = rng.standard_normal((m, d))
    w_free[:, -1] -= 0.5
    return W, props, w_free


@pytest.mark.parametrize("d", [2, 3])
def test_held_open_pairs_equal_the_sub_problem(d: int) -> None:
    """Pairs held open (``inactive``) inside the full solver, with its once-inverted W, give
    the forces and states of the sub-problem of the other pairs solved on its own sub-block
    of W, to 5e-14 of the largest force (round-off of two factorisations; measured
    5.9e-15), carry no force, and stay open even where their gap is closed; for 2D and 3D,
    with bonded pairs that break, for several patterns (every state met)."""
    m = 16
    for seed in range(4):
        W, props, w_free = _problem(m, d, seed)
        prev = props.initial_state(d)
        inactive = np.random.default_rng(100 + seed).random(m) < 0.35
        inactive[0] = True
        full = InterfaceSolver(W, props)
        assert full.woodbury
        st, _ = full.solve(w_free, prev, inactive=inactive)
        idx = np.flatnonzero(~inactive)
        comps = (idx[:, None] * d + np.arange(d)).ravel()
        sub = InterfaceSolver(W[np.ix_(comps, comps)], props.subset(idx))
        ref, _ = sub.solve(w_free[idx], prev.select(idx))
        scale = float(np.abs(ref.X).max())
        assert scale > 0
        np.testing.assert_allclose(st.X[idx], ref.X, rtol=0, atol=5e-14 * scale)
        np.testing.assert_array_equal(st.state[idx], ref.state)
        np.testing.assert_array_equal(st.broken[idx], ref.broken)
        assert np.all(st.X[inactive] == 0.0) and np.all(st.state[inactive] == OPEN)
        # the held pairs are not free to open: some would close (negative gap) if active
        assert (st.s[inactive, -1] < 0).any() or seed


def _coulomb(m: int, d: int) -> tuple[np.ndarray, PairLaws, np.ndarray, PairState]:
    rng = np.random.default_rng(0)
    A = rng.standard_normal((m * d, m * d))
    W = A @ A.T + m * d * np.eye(m * d)
    prev = PairState.initial(np.ones(m, dtype=bool), np.zeros(m), d)
    return W, coulomb_laws(np.full(m, 0.5), d), rng.standard_normal((m, d)), prev


@pytest.mark.parametrize("scale", [1e-200, 1e90, 1e200, 1e300])
def test_forces_beyond_double_precision_are_never_accepted(scale: float) -> None:
    """Coulomb friction without cohesion is positively homogeneous: the answer to w_free
    scaled by ``scale`` is ``scale`` times the answer at scale 1 (20 pairs, 3D). At 1e90
    it is found (forces within 1e-15 of the scaled ones; measured 1.1e-16). Beyond 1e±100
    the squares of the law leave double precision: before, at 1e200 and 1e300 the row
    norms overflowed, the residual took a sticking pair that moves for settled, and an
    answer 0.15 % wrong by the natural map was returned, with numpy's overflow warnings;
    now an :class:`InterfaceError` names the force scale (at once above 1e100 N; at
    1e-200 after the solve fails), and no warning is raised."""
    W, laws, w_free, prev = _coulomb(20, 3)
    ref, _ = InterfaceSolver(W, laws).solve(w_free, prev)
    solver = InterfaceSolver(W, laws)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        if 1e-100 <= scale <= 1e100:
            big, _ = solver.solve(scale * w_free, prev)
            err = np.abs(big.X / scale - ref.X).max() / np.abs(ref.X).max()
            assert err <= 1e-15, err  # measured 1.1e-16
        else:
            with pytest.raises(InterfaceError, match=r"force scale.*double precision"):
                solver.solve(scale * w_free, prev)


def _count_newtons(monkeypatch: pytest.MonkeyPatch) -> list[int]:
    """The iterations of each semismooth Newton run from now on (appended as they end)."""
    from pfeie.interface import _solver

    counts: list[int] = []
    newton = _solver.InterfaceSolver._newton

    def counted(self: InterfaceSolver, *args: object, **kw: object) -> object:
        out = newton(self, *args, **kw)  # type: ignore[arg-type]
        counts.append(out[2])
        return out

    monkeypatch.setattr(_solver.InterfaceSolver, "_newton", counted)
    return counts


def test_a_newton_without_descent_stops(monkeypatch: pytest.MonkeyPatch) -> None:
    """A static problem with no equilibrium (a rigid-friction block on a 10° incline, φ =
    40°, pushed down the dip by k_h = 0.6 > tan 30° = 0.577, its yield coefficient): the
    semismooth Newtons reach a point where no step along their direction lowers the
    residual and stop after LINE_SEARCH_FAILS such iterations instead of crawling to
    their limit (measured: 5 and 8 iterations, 22 and 100 before, 0.27 → 0.04 s); the
    MechanismError stands."""
    import pfeie as pf
    from pfeie.errors import MechanismError
    from pfeie.interface import _solver
    from pfeie.verification._models import block_on_base

    counts = _count_newtons(monkeypatch)
    model = block_on_base(joint=pf.Joint(phi=40.0), incline_deg=10.0)
    model.add_inertia([0.6 * 9.81, 0.0])
    with pytest.raises(MechanismError):
        pf.solve_static(model)
    assert counts and max(counts) <= 2 * _solver.LINE_SEARCH_FAILS, counts


def test_a_crawling_newton_stops(monkeypatch: pytest.MonkeyPatch) -> None:
    """The yield search of a block on a 30° joint with uplift (10 m × 2 m, φ = 35°,
    c_r = 20 kPa, headwater 1 m above the heel): beyond the limit the semismooth Newtons
    crawl (line-search steps below 2⁻¹⁰) and stop after LINE_SEARCH_CRAWL such
    iterations: measured at most 27 iterations a Newton, 156 in all with the search's try
    1 % beyond the failure (YIELD_BEYOND; 90 before it), against 100 and 269 without the
    criterion; k_y the same to the bit. How far a Newton crawls moves with the round-off
    of the BLAS underneath: on a machine with an AMD EPYC (AVX-512; the same wheels as
    before) at most 32 iterations a
    Newton, 232 in all (244 without the criterion)."""
    import pfeie as pf
    from pfeie.interface import _solver
    from pfeie.verification._models import block_on_base

    counts = _count_newtons(monkeypatch)
    k_y = []
    for crawl in (10**9, _solver.LINE_SEARCH_CRAWL):
        monkeypatch.setattr(_solver, "LINE_SEARCH_CRAWL", crawl)
        counts.clear()
        m = block_on_base(joint=pf.Joint(phi=35.0, c_r=2e4), width=10.0, height=2.0, n=10,
                          ny=2, incline_deg=30.0, E=50e9)  # fmt: skip
        m.add_uplift("joint", headwater=1.0)  # the heel at y = 0
        y = pf.yield_coefficient(m)
        assert y.limit == "sliding"
        k_y.append(y.k_y)
    assert max(counts) <= 40 and sum(counts) <= 300, counts  # measured 27/156, 32/232
    assert k_y[0] == k_y[1]
