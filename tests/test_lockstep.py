"""Runs in lockstep (:func:`pfeie.linalg.run_lockstep`): their block solves made together
on a shared factor, each run the same bits as alone where the block solves are
batch-invariant (OpenBLAS's Haswell kernels), and the same to round-off where the sharing
is forced on a machine whose are not (its SkylakeX kernels).

References: the computations run alone (the same functions, in the calling thread), and
the factor's own block solve of each request. The physics case: the jointed section of
``benchmarks/interfaces.py`` at nx = 60 (4,758 DOF, 122 pairs: W not stored as K̂⁻¹Gᵀ, so
each step solves a two-column block), El Centro scaled ×1.5 to ×3.5 so that the upper
block slides in the last runs; the block thresholds are lowered for this size (the
default path takes blocks from 20,000 DOF).
"""

from __future__ import annotations

import sys
import threading
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import pfeie as pf
import pfeie.linalg._block as blk
from pfeie.linalg import LockstepStats, factorize, run_lockstep, shares_block_solves

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
from interfaces import RECORD, build
from test_block_solve import _stiffness


@pytest.fixture
def blocks_everywhere(monkeypatch: pytest.MonkeyPatch) -> None:
    """Two-column blocks from 0 DOF (the size rule only; the kernels are the same)."""
    monkeypatch.setattr(blk, "BLOCK_MIN_DOF", 0)
    monkeypatch.setattr(blk, "SMALL_BLOCK_MIN_DOF", 0)


def _invariant_or_forced(F: Any, monkeypatch: pytest.MonkeyPatch) -> bool:
    """Whether the block solves of ``F`` are batch-invariant here. Where they are not
    (OpenBLAS's SkylakeX kernels solve columns four at a time, and a column of a block of
    eight takes other bits than in a block of two), the sharing is forced, so that the
    lockstep's machinery is tested on every machine, and the answers are compared to
    round-off instead of to the bit."""
    base = getattr(F, "base", F)
    if base.batch_invariant():
        return True
    monkeypatch.setattr(type(base), "batch_invariant", lambda self: True)
    return False


def test_tasks_run_in_order_and_errors_come_back() -> None:
    """Tasks without solves run one after the other, in order; a task's exception is
    returned in its place, the others finish."""
    seen: list[int] = []

    def task(k: int) -> Any:
        def run() -> int:
            seen.append(k)
            if k == 1:
                raise ValueError("task 1 fails")
            return 10 * k

        return run

    out = run_lockstep([task(0), task(1), task(2)])
    assert seen == [0, 1, 2]
    assert out[0] == 0 and out[2] == 20
    assert isinstance(out[1], ValueError)


def test_block_solves_together_give_each_its_own_bits(
    blocks_everywhere: None, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Three computations ask, in turn, for solves of 2, 4 and 2 columns, then of 1 and 3
    (odd: solved alone, in the computation's turn): the even requests of a round go to
    one call (8 columns, then none), and every answer equals that of the computation run
    alone, to the bit where the block solves are batch-invariant (else to 5e-15 of the
    largest: measured 5.5e-16)."""
    pytest.importorskip("cvxopt")
    if blk.block_solver() is None:
        pytest.skip("no block solve here")
    F = factorize(_stiffness(50), backend="cholmod")  # 5,000 DOF
    exact = _invariant_or_forced(F, monkeypatch)
    assert shares_block_solves(F)
    rng = np.random.default_rng(7)
    rhs = [[rng.standard_normal((F.n, k)) for k in widths]
           for widths in ((2, 1), (4, 3), (2, 1))]  # fmt: skip

    def task(bs: list[np.ndarray]) -> Any:
        return lambda: [F.solve(b) for b in bs]

    alone = [task(bs)() for bs in rhs]
    stats = LockstepStats()
    together = run_lockstep([task(bs) for bs in rhs], stats)
    assert (stats.calls, stats.columns, stats.widest) == (1, 8, 8)
    for a, b in zip(alone, together, strict=True):
        assert not isinstance(b, BaseException)
        for x, y in zip(a, b, strict=True):
            if exact:
                np.testing.assert_array_equal(x, y)
            else:
                assert np.abs(x - y).max() <= 5e-15 * np.abs(x).max()
    # the block of 8 differs from lone columns by round-off: the equality is not trivial
    lone = F._solve_columns(rhs[0][0])  # type: ignore[attr-defined]
    assert not np.array_equal(lone, alone[0][0])
    assert np.abs(lone - alone[0][0]).max() < 1e-12 * np.abs(lone).max()


def test_records_in_lockstep_equal_separate_runs(
    blocks_everywhere: None, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Four records on one factorised system in lockstep (:meth:`pfeie.Dynamic.twin`
    analyses): every history equals that of the record run alone, to the bit where the
    block solves are batch-invariant (else to 3e-12 of each history's scale: measured
    3.1e-13), with the upper block sliding in the last two; one block solve
    of 8 columns a step."""
    pytest.importorskip("cvxopt")
    if blk.block_solver() is None:
        pytest.skip("no block solve here")
    model = build(60)
    static = pf.solve_static(model)
    an = pf.Dynamic(model, 0.01, backend="cholmod")
    exact = _invariant_or_forced(an.factor, monkeypatch)
    assert shares_block_solves(an.factor)
    data = np.loadtxt(RECORD, delimiter=",", skiprows=1)
    gms = [pf.GroundMotion.from_samples(f * data[:, 1], time=data[:, 0], units="g")
           for f in (1.5, 2.5, 3.0, 3.5)]  # fmt: skip
    steps = 200

    def run(a: pf.Dynamic, g: pf.GroundMotion) -> Any:
        return lambda: a.run(n_steps=steps, ground=[g], start=static)

    twins = [an] + [an.twin() for _ in gms[1:]]
    assert all(t.factor is an.factor and t.istep.W is an.istep.W for t in twins)
    assert len({id(t.istep) for t in twins}) == len(twins)
    stats = LockstepStats()
    together = run_lockstep([run(a, g) for a, g in zip(twins, gms, strict=True)], stats)
    assert stats.calls == steps + 1 and stats.widest == 2 * len(gms)
    alone = [run(pf.Dynamic(model, 0.01, backend="cholmod"), g)() for g in gms]
    sliding, worst = [], 0.0
    for a, b in zip(alone, together, strict=True):
        assert not isinstance(b, BaseException)
        assert a.completed and b.completed
        # each history against its own scale: lengths against the rigid motion's (the
        # pair motions of bonded joints are round-off), energies against the largest
        length = np.abs(a.rigid).max()
        energy = max(np.abs(v).max() for v in a.energy.values())
        pairs = [(a.rigid, b.rigid, length), (a.w, b.w, length), (a.X, b.X, np.abs(a.X).max()),
                 (a.envelope["node_max"], b.envelope["node_max"],
                  np.abs(a.envelope["node_max"]).max())]  # fmt: skip
        pairs += [(value, b.energy[key], energy) for key, value in a.energy.items()]
        if a.probe_a.size:
            pairs += [(a.probe_a, b.probe_a, np.abs(a.probe_a).max())]
        for x, y, scale in pairs:
            if exact:
                np.testing.assert_array_equal(x, y)
            else:
                worst = max(worst, np.abs(x - y).max() / scale)
        np.testing.assert_array_equal(a.state, b.state)  # the same states either way
        sliding.append(int((a.state == 2).sum()))
    assert sliding[0] == 0 and sliding[-1] > 0 and sliding[-2] > 0
    assert worst < 3e-12  # measured 3.1e-13 (the pair forces)


def test_twin_refuses_large_rotation() -> None:
    mesh = pf.rectangle(1.0, 1.0, 1, 1)
    mesh.add_cell_group("b", lambda x: x[:, 0] > -1)
    model = pf.Model(mesh, [pf.Block("b", pf.Elastic(1e9, 0.2, 2000))])
    model.fix(model.nodes_at(lambda x: x[:, 1] < 1e-9))
    an = pf.Dynamic(model, 0.01, large_rotation=True)
    with pytest.raises(pf.ModelError, match="large_rotation"):
        an.twin()


class _Fake:
    """A factor whose shared solve doubles its columns, or raises ``error``."""

    def __init__(self, error: BaseException | None = None) -> None:
        self.error, self.calls = error, 0

    def solve_block(self, cols: np.ndarray) -> np.ndarray:
        self.calls += 1
        if self.error is not None:
            raise self.error
        return 2.0 * cols


def test_a_failed_shared_solve_is_raised_in_each_computation_that_asked() -> None:
    """The shared solve of one factor fails: the two computations that asked for it get
    its error; the one that asked another factor finishes; no thread is left behind."""
    from pfeie.linalg._lockstep import pending_solve

    bad, good = _Fake(MemoryError("no room")), _Fake()

    def task(factor: _Fake) -> Any:
        return lambda: pending_solve(factor, np.ones((3, 2)))

    out = run_lockstep([task(bad), task(good), task(bad)])
    assert isinstance(out[0], MemoryError) and isinstance(out[2], MemoryError)
    np.testing.assert_array_equal(out[1], 2.0 * np.ones((3, 2)))
    assert bad.calls == 1 and good.calls == 1
    assert not [t for t in threading.enumerate() if t.name.startswith("lockstep-")]


def test_an_interrupt_unwinds_every_computation() -> None:
    """A KeyboardInterrupt in the caller (here from the shared solve) leaves
    run_lockstep, and every computation's thread ends."""
    from pfeie.linalg._lockstep import pending_solve

    stop = _Fake(KeyboardInterrupt())
    ran_on: list[int] = []

    def task(k: int) -> Any:
        def run() -> None:
            pending_solve(stop, np.ones((3, 2)))
            ran_on.append(k)  # never reached

        return run

    with pytest.raises(KeyboardInterrupt):
        run_lockstep([task(0), task(1)])
    assert ran_on == []
    assert not [t for t in threading.enumerate() if t.name.startswith("lockstep-")]
