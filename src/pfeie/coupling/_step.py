"""The one-step interface problem: predictor → interface solve → corrector (method.md §5.1).

Any time integrator whose step, for fixed pair forces X, is linear in the blocks,

    K̂ u_{n+1} = P̂ + s Gᵀ X,

(K̂ the integrator's effective matrix, P̂ its right-hand side, s the weight of the pair
forces in the step) calls this problem once per step:

1. predictor: the integrator gives u_free = K̂⁻¹ P̂ (one back-substitution);
2. interface: w_free = G u_free + w_p (w_p: the prescribed side's motion), and the pair
   forces X and states from w = w_free + s W X and the joint law, W = G K̂⁻¹ Gᵀ;
3. corrector: u_{n+1} = u_free + s K̂⁻¹ Gᵀ X (:meth:`Delassus.correct`).

The problem knows nothing of time: the integrator owns K̂, P̂ and s.

When the operators change a little from step to step (pair frames that turn with their
blocks, large rotations: W changes by the order of the rotation increment), :meth:`update`
does not factorise the new W_c: its solver keeps the W_c⁻¹ of the last factorised one and
refines each state system on it (:class:`InterfaceSolver`, ``reference``), to round-off.
W_c is factorised anew at the next update when a refinement's contraction factor exceeded
:data:`REFACTOR_CONTRACTION` (the accumulated rotation has grown: each correction would
gain too few digits), and at once when one stops contracting (the solver then factorises
by itself);
:attr:`InterfaceStep.factorizations` counts the factorisations.
"""

from __future__ import annotations

import copy
from collections import OrderedDict
from dataclasses import dataclass, field

import numpy as np

from ..errors import InterfaceError
from ..interface import (
    OPEN,
    SECOND_STAGE_PROXIMAL,
    STICK,
    InterfaceSolver,
    PairLaws,
    PairState,
    SolveInfo,
    SolverSettings,
)
from ..typing import BoolArray, FloatArray
from ._delassus import Delassus
from ._operators import PairOperator

REFACTOR_CONTRACTION = 0.02
"""The first contraction factor of a refinement on the reference W_c⁻¹ above which the
next :meth:`InterfaceStep.update` factorises W_c anew (at 0.02 a state system is solved
to round-off in about nine corrections of two M × M products each)."""

#: sub-problems (one per pattern of active pairs) kept with their factorisations
SUBSOLVERS = 16
#: bytes at most in the kept sub-problems' operators (W, W_c, W_c⁻¹) and factor caches
#: (:data:`~pfeie.interface.FACTOR_CACHE_BYTES` each): 16 of a 3D problem of 753
#: components held 4.7 GB before there was a bound
SUBSOLVER_BYTES = 128 * 2**20


def _footprint(solver: InterfaceSolver) -> int:
    """The memory a kept sub-problem holds: its dense operators and its factor cache."""
    arrays = (solver.W, solver.Wc, getattr(solver, "_winv", None))
    dense = sum(int(a.nbytes) for a in arrays if isinstance(a, np.ndarray))
    return dense + int(solver.cache_bytes)


@dataclass
class _Reference:
    """The factorised solvers the updated ones refine on, shared by the problems made by
    :meth:`InterfaceStep.with_laws`: the solver of the full W and those of sub-blocks (per
    pattern of active pairs), the largest contraction seen on them since, and the number
    of factorisations made."""

    solver: InterfaceSolver | None = None
    subs: dict[bytes, InterfaceSolver] = field(default_factory=dict)
    contraction: float = 0.0
    factorizations: int = 0

    def track(self, solver: InterfaceSolver, before: int) -> None:
        """Account for a solve of ``solver`` (``before``: its factorisations before it)."""
        self.factorizations += solver.factorizations - before
        self.contraction = max(self.contraction, solver.contraction)


@dataclass
class SolveStats:
    """What the pair problems of one time step cost: solver iterations, the solves that
    the semismooth Newton finished after the state iteration (``newton``: its second
    stage, in 3D from 300 components the Newton through W_c⁻¹, else in 3D the
    proximal-point Newton, :data:`~pfeie.interface.PROXIMAL_FIRST_3D`), the solves that
    needed a fallback beyond it (the Newton from a cold start, the proximal-point Newton
    after the Newtons, or projected Gauss-Seidel), and the worst final residual (scaled,
    as the solver's tolerance)."""

    iterations: int = 0
    fallbacks: int = 0
    residual: float = 0.0
    solves: int = 0
    newton: int = 0

    def reset(self) -> None:
        self.iterations = self.fallbacks = self.solves = self.newton = 0
        self.residual = 0.0

    def add(self, info: SolveInfo) -> None:
        """Account for one solve (its :class:`~pfeie.interface.SolveInfo`)."""
        self.iterations += info.iterations
        second = info.method in ("semismooth Newton", SECOND_STAGE_PROXIMAL)
        self.newton += second
        self.fallbacks += not second and info.method not in ("state iteration", "none")
        self.residual = max(self.residual, info.residual)
        self.solves += 1


@dataclass
class StepSolution:
    """The trial pair state of the step and the block correction Δu = s K̂⁻¹ Gᵀ X."""

    pairs: PairState
    du: FloatArray


class InterfaceStep:
    """The interface problem of one step for the operators ``op`` (G), ``W`` (its
    Delassus operator through the integrator's K̂) and the force weight ``scale`` (s).

    Parameters
    ----------
    op: the pair operator G on the free and prescribed DOFs.
    W: the Delassus operator of G through K̂.
    laws: the joint laws of the pairs.
    scale: s, the weight of the pair forces in the step's equation.
    settings: the interface solver's settings.
    regularize: relative compliance for redundant constraints (T and X junctions).

    ``reuse`` (default True): :meth:`update` refines on the last factorised W_c⁻¹ (module
    docstring); False factorises every new W_c.
    """

    reuse: bool = True

    def __init__(
        self,
        op: PairOperator,
        W: Delassus,
        laws: PairLaws,
        scale: float,
        *,
        settings: SolverSettings | None = None,
        regularize: float = 0.0,
    ) -> None:
        self.laws, self.scale = laws, float(scale)
        self.settings = SolverSettings() if settings is None else settings
        self.regularize = regularize
        self.stats = SolveStats()  # shared with the problems made by with_laws
        self._ref = _Reference()  # likewise
        self.update(op, W)

    @property
    def factorizations(self) -> int:
        """The factorisations of W_c (and of its sub-blocks) made for this problem and
        those made by :meth:`with_laws` since its creation."""
        return self._ref.factorizations

    def update(self, op: PairOperator, W: Delassus) -> None:
        """New operators (e.g. pair frames that turned). The solver for them refines on
        the last factorised W_c⁻¹ while that contracts by at most
        :data:`REFACTOR_CONTRACTION` (and :attr:`reuse`); otherwise it factorises W_c."""
        self.op, self.W = op, W
        ref = self._ref
        base = ref.solver
        if not self.reuse or (base is not None and ref.contraction > REFACTOR_CONTRACTION):
            base = None
        self.solver = InterfaceSolver(self.scale * W.matrix(), self.laws, settings=self.settings,
                                      regularize=self.regularize, reference=base)  # fmt: skip
        ref.track(self.solver, 0)
        if not self.solver.refined:  # factorised: the reference of the next updates
            ref.solver, ref.subs, ref.contraction = self.solver, {}, 0.0
        self._last = self.solver
        self._subsolvers: OrderedDict[bytes, InterfaceSolver] = OrderedDict()

    def with_laws(self, laws: PairLaws) -> InterfaceStep:
        """The same problem (operators, weight, settings) for other laws with the same
        joint compliance, sharing the factorised W (e.g. the smooth forces and the step
        impulses of one time step)."""
        other = copy.copy(self)
        other.solver = self.solver.with_laws(laws)  # (the same compliance, or refused)
        other.laws = laws
        other._last = other.solver
        other._subsolvers = OrderedDict()
        return other

    def _held_open(self, inactive: BoolArray) -> bool:
        """Whether to solve with the ``inactive`` pairs held open inside the full solver
        (one more row each in its capacitance system, on the once-inverted W) rather than
        on the sub-block of the active pairs (a new factorisation per pattern): when W was
        inverted once and the held pairs are at most half of them."""
        return self.solver.woodbury and 2 * int(inactive.sum()) <= inactive.size

    def _subsolver(self, active: np.ndarray) -> InterfaceSolver:
        """The solver of the sub-problem of the ``active`` pairs (cached per pattern)."""
        key = active.tobytes()
        hit = self._subsolvers.get(key)
        if hit is None:
            d = self.op.d
            idx = np.flatnonzero(active)
            comps = (idx[:, None] * d + np.arange(d)).ravel()
            Wa = self.scale * self.W.matrix()[np.ix_(comps, comps)]
            ref = self._ref
            base = ref.subs.get(key) if self.solver.refined else None
            hit = InterfaceSolver(Wa, self.laws.subset(idx), settings=self.settings,
                                  regularize=self.regularize, reference=base)  # fmt: skip
            ref.track(hit, 0)
            if not hit.refined:
                if len(ref.subs) >= SUBSOLVERS:
                    ref.subs.clear()
                ref.subs[key] = hit
            self._subsolvers[key] = hit
            # at most SUBSOLVERS, and their operators and factor caches within
            # SUBSOLVER_BYTES: the least recently used go first
            while len(self._subsolvers) > 1 and (
                len(self._subsolvers) > SUBSOLVERS
                or sum(_footprint(v) for v in self._subsolvers.values()) > SUBSOLVER_BYTES
            ):
                self._subsolvers.popitem(last=False)
        else:
            self._subsolvers.move_to_end(key)
        return hit

    def solve(
        self,
        u_free: FloatArray | None,
        w_pres: FloatArray,
        prev: PairState,
        label: str = "",
        inactive: BoolArray | None = None,
        *,
        fixed: BoolArray | None = None,
        breaking: str = "iterate",
        correct: bool = True,
    ) -> StepSolution:
        """The trial pair state and the block correction for the predictor ``u_free``
        (free DOFs); ``w_pres`` (M,) is G_p u_p at t_{n+1} (or, with ``u_free`` None, the
        whole free relative motion); ``prev`` the committed state. The trial state's ``w``
        is the relative motion at the solution. With ``correct=False`` the block
        correction is left to the caller (``du`` empty).
        Pairs marked ``inactive`` (m,) take no part: they are held open and carry
        nothing, and the problem is solved on the other pairs (inside the full solver, or
        on the sub-block of W when many are inactive, :meth:`_held_open`).
        ``fixed`` (m,) marks sliding pairs that keep their slip direction
        (:meth:`InterfaceSolver.solve`). ``breaking``: "iterate" lets the solver break
        intact pairs within its iterations; "converged" solves with the intact pairs
        bonded, breaks those whose converged force exceeds their strength
        (:meth:`PairLaws.overstressed`; they restart closed and unbonded), and solves again
        until no pair breaks."""
        m, d = self.op.m, self.op.d
        w_free = (w_pres if u_free is None else self.op.G @ u_free + w_pres).reshape(m, d)
        if breaking == "iterate":
            return self._solve(w_free, prev, label, inactive, fixed, True, correct)
        start = prev
        for _ in range(self.op.m + 1):
            sol = self._solve(w_free, start, label, inactive, fixed, False, correct)
            if sol.pairs.broken.all():  # nothing left to break
                return sol
            X, laws = sol.pairs.X, self.laws
            tol = 1e-10 * max(float(np.abs(X).max(initial=0.0)), 1e-300)
            over = ~sol.pairs.broken & laws.overstressed(X, prev.path, tol)
            if inactive is not None:
                over &= ~inactive
            if not over.any():
                return sol
            start = start.copy()
            start.broken = start.broken | over
            start.state[over] = STICK
        return sol

    def _solve(
        self, w_free: FloatArray, prev: PairState, label: str, inactive: BoolArray | None,
        fixed: BoolArray | None, breaking: bool, correct: bool,
    ) -> StepSolution:  # fmt: skip
        m, d = self.op.m, self.op.d
        if inactive is None or not inactive.any() or self._held_open(inactive):
            n0 = self.solver.factorizations
            trial, _ = self.solver.solve(w_free, prev, label=label, fixed=fixed,
                                         breaking=breaking, inactive=inactive)  # fmt: skip
            self._track(self.solver, n0)
            self._last = self.solver
            self.stats.add(self.solver.last)
        else:
            active = ~inactive
            trial = prev.copy()
            trial.X[:] = 0.0
            trial.state[inactive] = OPEN
            if active.any():
                sub = self._subsolver(active)
                n0 = sub.factorizations
                try:
                    part, _ = sub.solve(w_free[active], prev.select(active), label=label,
                                        fixed=None if fixed is None else fixed[active],
                                        breaking=breaking)  # fmt: skip
                except InterfaceError as exc:
                    # the sub-problem's pairs in the model's numbering
                    on = np.flatnonzero(active)
                    raise InterfaceError(
                        f"{exc} (pair numbers above among the {on.size} active pairs)",
                        tuple(int(on[k]) for k in exc.pairs)) from None  # fmt: skip
                self._track(sub, n0, active.tobytes())
                self._last = sub
                self.stats.add(sub.last)
                for name in ("state", "broken", "X", "slip_dir"):
                    getattr(trial, name)[active] = getattr(part, name)
            X = trial.X.ravel()
            w = w_free.ravel() + self.scale * self.W.apply(X)
            trial.s = self.laws.s_of(w.reshape(m, d), trial.X)
            trial.w = self.laws.w_of(trial.s, trial.X)
        if not correct:
            return StepSolution(trial, np.zeros(0))
        du = self.W.correct(trial.X.ravel() * self.scale)
        return StepSolution(trial, np.asarray(du))

    def _track(self, solver: InterfaceSolver, before: int, sub: bytes | None = None) -> None:
        """Account for a solve of ``solver`` (a sub-block's for the pattern ``sub``): its
        contraction, and, when it left the reference and factorised its W_c, it becomes
        the reference of the next updates."""
        ref = self._ref
        ref.track(solver, before)
        if solver.factorizations == before or not self.reuse:
            return
        if sub is None:
            ref.solver, ref.subs, ref.contraction = solver, {}, 0.0
        else:
            ref.subs[sub] = solver

    @property
    def iterations(self) -> int:
        """Iterations of the last solve."""
        return self._last.last.iterations


__all__ = ["InterfaceStep", "SolveStats", "StepSolution"]
