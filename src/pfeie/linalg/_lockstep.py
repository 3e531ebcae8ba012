"""Several computations in lockstep, their block solves on a shared factor made together.

A study runs many records on one once-factorised system. Each record's time step asks
for block solves (the block response to the pair forces and impulses: two columns) on
the same factor, and a block of k columns costs much less than k separate ones (per
column at 49k DOF: 0.73 of one column for two columns, 0.19 for sixteen;
docs/benchmarks.md). :func:`run_lockstep` runs the records' computations in turn, each in
a thread of its own, but never two at once: a computation runs until it asks for a
block solve (:func:`pending_solve`, called by the factor), or ends; when every live one
has asked or ended, the requests on each factor are solved in one call, the columns
side by side in the order of the computations, and the computations resume in order.
Nothing runs concurrently and the order is fixed, so a run is deterministic. A failed
shared solve raises its error in each computation that asked for it (the others go on);
an interrupt of the caller unwinds every computation's thread. A computation must not
hold a lock that another one needs across a block solve (the others would wait for it
while it waits for them): none in pfeie does.

A column's bits do not depend on the columns beside it where the factor is
*batch-invariant* (``_Cholmod.batch_invariant`` in :mod:`._factor`: CHOLMOD's block solve, with
level-3 BLAS, gives each column of an even-width block the same bits wherever it sits;
checked on each factor before it is used, and on this installation true); then each
computation gets exactly what it would get alone, and a record of a study equals its
separate run to the bit. Requests of an odd width, and requests on a factor that is not
batch-invariant, are solved alone, in the computation's turn.

>>> log = []
>>> def task(k):
...     def run():
...         log.append(("start", k))
...         return k * k
...     return run
>>> run_lockstep([task(1), task(2)])
[1, 4]
>>> log
[('start', 1), ('start', 2)]
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any, Protocol, TypeVar

import numpy as np

from ..typing import FloatArray

log = logging.getLogger(__name__)

T = TypeVar("T")


class BatchedFactor(Protocol):
    """A factor whose block solve the lockstep calls for the columns of all
    computations together."""

    def solve_block(self, cols: FloatArray) -> FloatArray: ...


@dataclass
class _Request:
    factor: BatchedFactor
    cols: FloatArray
    result: FloatArray | None = None
    error: BaseException | None = None


class _Aborted(BaseException):
    """Raised in a computation whose lockstep was abandoned (an interrupt of the caller):
    it unwinds the computation's thread."""


@dataclass
class _Task:
    run: Callable[[], Any]
    turn: threading.Event = field(default_factory=threading.Event)
    request: _Request | None = None
    done: bool = False
    value: Any = None
    error: BaseException | None = None


@dataclass
class LockstepStats:
    """Block solves made for computations in lockstep: calls and columns (a column in a
    call of c columns saves c − 1 factor sweeps against solving it alone)."""

    calls: int = 0
    columns: int = 0
    widest: int = 0


_local = threading.local()


class _Lockstep:
    def __init__(self, tasks: Sequence[_Task]) -> None:
        self.tasks = list(tasks)
        self.yielded = threading.Event()
        self.stats = LockstepStats()
        self.aborted = False

    def ask(self, task: _Task, request: _Request) -> FloatArray:
        """From a computation's thread: leave ``request`` and wait for its answer (the
        shared solve's error, if it failed, is raised here, in each computation)."""
        task.request = request
        task.turn.clear()
        if self.aborted:  # abandoned while this computation ran
            raise _Aborted
        self.yielded.set()
        task.turn.wait()
        task.request = None
        if self.aborted:
            raise _Aborted
        if request.error is not None:
            raise request.error
        assert request.result is not None
        return request.result

    def _turn(self, task: _Task) -> None:
        """Let ``task`` run until it asks for a solve or ends."""
        self.yielded.clear()
        task.turn.set()
        self.yielded.wait()

    def run(self) -> None:
        threads = []
        for i, task in enumerate(self.tasks):
            th = threading.Thread(target=self._body, args=(task,), name=f"lockstep-{i}",
                                  daemon=True)  # fmt: skip
            threads.append(th)
            th.start()
        try:
            while True:
                live = [t for t in self.tasks if not t.done]
                if not live:
                    break
                for task in live:
                    self._turn(task)
                self._solve([t.request for t in self.tasks if not t.done and t.request])
        finally:  # an interrupt here: every waiting computation unwinds (_Aborted)
            if any(not t.done for t in self.tasks):
                self.aborted = True
                for t in self.tasks:
                    t.turn.set()
            for th in threads:
                th.join(timeout=60.0)

    def _solve(self, requests: list[_Request]) -> None:
        """The requests of one round: on each factor, one block solve of their columns
        side by side (in the order of the computations)."""
        by_factor: dict[int, list[_Request]] = {}
        for r in requests:
            by_factor.setdefault(id(r.factor), []).append(r)
        for group in by_factor.values():
            try:
                cols = np.hstack([r.cols for r in group]) if len(group) > 1 else group[0].cols
                X = group[0].factor.solve_block(cols)
            except Exception as exc:  # each computation of the group raises it in its turn
                for r in group:
                    r.error = exc
                continue
            self.stats.calls += 1
            self.stats.columns += cols.shape[1]
            self.stats.widest = max(self.stats.widest, cols.shape[1])
            j = 0
            for r in group:
                k = r.cols.shape[1]
                r.result = X[:, j : j + k]
                j += k

    def _body(self, task: _Task) -> None:
        task.turn.wait()
        _local.current = (self, task)
        try:
            task.value = task.run()
        except _Aborted:
            pass
        except BaseException as exc:  # handed to the caller with the others' results
            task.error = exc
        finally:
            _local.current = None
            task.done = True
            self.yielded.set()


def in_lockstep() -> bool:
    """Whether this thread runs one of the computations of :func:`run_lockstep`."""
    return getattr(_local, "current", None) is not None


def pending_solve(factor: BatchedFactor, cols: FloatArray) -> FloatArray | None:
    """The block solve of ``cols`` (n, k) on ``factor`` made together with the other
    computations in lockstep, when this thread runs one of them (:func:`run_lockstep`);
    None otherwise (the caller solves alone)."""
    here = getattr(_local, "current", None)
    if here is None:
        return None
    step, task = here
    return step.ask(task, _Request(factor, cols))


def run_lockstep(
    tasks: Sequence[Callable[[], T]], stats: LockstepStats | None = None
) -> list[T | BaseException]:
    """Run ``tasks`` in lockstep (module docstring); their results in order, or the
    exception a task raised in its place. ``stats`` receives the block solves made
    together. One task runs in the calling thread's stead: nothing is gained, and
    nothing changes."""
    if len(tasks) == 1:
        try:
            return [tasks[0]()]
        except Exception as exc:  # handed back like the others'
            return [exc]
    step = _Lockstep([_Task(t) for t in tasks])
    step.run()
    if stats is not None:
        stats.calls += step.stats.calls
        stats.columns += step.stats.columns
        stats.widest = max(stats.widest, step.stats.widest)
    out: list[Any] = []
    log.debug("lockstep of %d computations: %d block solves of %d columns (widest %d)",
              len(tasks), step.stats.calls, step.stats.columns, step.stats.widest)  # fmt: skip
    for t in step.tasks:
        if t.error is not None and not isinstance(t.error, Exception):
            raise t.error  # KeyboardInterrupt, SystemExit: not a task's own failure
        out.append(t.error if t.error is not None else t.value)
    return out


__all__ = ["BatchedFactor", "LockstepStats", "pending_solve", "run_lockstep"]
