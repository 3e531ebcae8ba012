r"""The factor of safety by strength reduction: the least factor F by which the joints'
strengths must be divided for the structure to lose its static equilibrium.

A joint's sliding safety factor in a static state, Σ capacity / ‖Σ T‖
(:meth:`~pfeie.interface.PairLaws.safety_factor`), measures how much of its strength the
state mobilises. For a plane joint under a rigid block it is the limit-equilibrium factor
of the textbooks, but where the friction can act in more than one direction it is not: an
elastic wedge loaded by its weight from a stress-free state sinks into its V by its own
compression, and the friction on both planes holds it up the dip, at its capacity on
every pair, so each plane reads FS ≈ 1 while the wedge needs a push of a sixth of g to
slide (docs/theory.md, "Two safety factors"). The factor against sliding is a limit, and
pfeie finds it as the finite-element codes of geotechnics do (Dawson, Roth and Drescher
1999; Griffiths and Lane 1999): static analyses of the model, with its loads, water and
uplift, blocks and joints, with every joint law's strength divided by F
(:class:`~pfeie.interface.Reduced`),

.. math::

    c_F = c / F,\qquad \tan φ_F = \tan φ / F,\qquad σ_{t,F} = σ_t / F,

intact and residual alike; the factor of safety is the largest F at which a static
equilibrium holds, within a relative ``tol`` of the least F at which none does. Each
analysis is the static analysis from the model's initial pair state (bonded joints break
where the loads exceed their reduced strength: no loading path is followed), on the
factorisations and the Delassus operator built once for all.

The search: the least joint safety factor at a held F, times F, is where a rigid block's
joints reach their capacity (its margins are affine in 1/F), so a block on a plane takes
four analyses: the static state, one just beyond that estimate (tried from the last state
held, then from the initial state, as every analysis that fails) and one just below it.
Where the estimate creeps (the wedge's friction turning towards the line of
intersection as F grows), the step grows geometrically, or by the estimates'
extrapolation (:func:`~pfeie.solvers._yield._creep`), until the limit is bracketed, then
bisection safeguards the estimate.

A rigid block of weight W on a plane of dip β, with a joint of cohesion c over its area A
and friction tan φ: F = (c A + W cos β tan φ) / (W sin β). A symmetric wedge whose planes
make the angle ξ with the vertical plane through its line of intersection, which plunges
by ψ (Hoek and Bray 1981, ch. 7): F = tan φ / (sin ξ tan ψ).
"""

from __future__ import annotations

import dataclasses
import logging
import time
from dataclasses import dataclass
from functools import partial

import numpy as np

from ..coupling import RIGID_FACTOR_TOL, StaticInterfaceProblem, translations
from ..errors import ModelError, SolverError
from ..interface import SolverSettings
from ..model import Model
from ..typing import FloatArray
from ._static import (
    StaticResult,
    held,
    joint_factors,
    solve_pairs,
    uplift_free,
    warn_junctions,
)
from ._yield import (
    SLIDING_FS,
    YIELD_REOPEN,
    YIELD_RIGID_GAP,
    _creep,
    probe_towards,
    warn_gap,
    warn_pinched,
)

log = logging.getLogger(__name__)

#: the relative width of the final bracket [F, F_fail] (default of ``tol``)
REDUCTION_TOL = 1e-4

#: the largest factor tried; a structure held with its strengths divided by it is reported
#: with factor None (no limit up to it)
REDUCTION_F_MAX = 20.0

#: the static analyses a search may take
REDUCTION_MAX_ANALYSES = 60


@dataclass(frozen=True)
class StrengthReduction:
    """The factor of safety by strength reduction (see the module docstring).

    - ``factor``: the largest factor F held (strengths divided by it), None if the
      structure holds up to ``f_max``;
    - ``factor_fail``: the least factor found beyond the limit (None with ``factor`` None;
      where the search went on past a failure of the pair solver, it may be the rigid
      blocks' bound, beyond which no equilibrium exists);
    - ``joint``: the joint that governs, the least safety factor at ``factor`` under the
      reduced strengths;
    - ``safety_factors``: each joint's sliding safety factor at ``factor`` under the
      reduced strengths, Σ capacity / ‖Σ T‖ (∞: no shear); about 1 on the joints that
      slide at the limit;
    - ``limit``: "sliding" (the governing joint's safety factor is 1 within
      :data:`~pfeie.solvers.SLIDING_FS`), "no equilibrium found" (the analyses fail beyond
      ``factor`` while every joint is short of its reduced capacity: a mechanism of
      opening, a bonded joint breaking through, or the pair solver failing short of the
      limit), "none" (held up to ``f_max``) or "not bracketed" (``max_analyses`` first);
    - ``static``: the static state at ``factor``; ``analyses``: how many static analyses;
    - ``rigid_factor``: with the limit "no equilibrium found", the rigid blocks' factor of
      safety (:meth:`~pfeie.coupling.StaticInterfaceProblem.rigid_factor`, limit
      equilibrium, to 1e-3): no equilibrium exists beyond it, so the factor lies in
      [``factor``, ``rigid_factor``]; a gap of more than 1 % is warned. None otherwise.
    - ``translation_factor``: the least factor of the floating blocks' rigid translations
      (:func:`~pfeie.coupling.translations`: Hoek and Bray's plane and wedge sliding,
      for blocks that rest on supported bodies only; None where no block is checked). A
      ``factor`` more than 1 % above it is warned: the static analyses then lean on
      friction that the block's sliding does not mobilise (a block pinched between its
      planes), and the dynamic runs follow the lower factor.
    - ``junction_share``: as :class:`~pfeie.YieldCoefficient`'s, where the governing joint
      leans on its pairs at junctions (warned). None otherwise.
    """

    factor: float | None
    factor_fail: float | None
    joint: str | None
    safety_factors: dict[str, float]
    limit: str
    static: StaticResult
    analyses: int
    rigid_factor: float | None = None
    translation_factor: float | None = None
    junction_share: float | None = None

    def __repr__(self) -> str:
        """One line: the factor, the limit and its joint, the analyses."""
        f = "None" if self.factor is None else f"{self.factor:.6g}"
        return (f"StrengthReduction(factor={f}, limit={self.limit!r}, joint={self.joint!r}, "
                f"analyses={self.analyses})")  # fmt: skip


def strength_reduction(
    model: Model,
    *,
    tol: float = REDUCTION_TOL,
    f_max: float = REDUCTION_F_MAX,
    backend: str = "auto",
    settings: SolverSettings | None = None,
    problem: StaticInterfaceProblem | None = None,
    max_analyses: int = REDUCTION_MAX_ANALYSES,
) -> StrengthReduction:
    """The factor of safety of ``model`` against sliding on its joints by strength
    reduction (see the module docstring): static analyses under the loads at t = 0 with
    every joint's strength divided by F. ``problem``: a
    :class:`~pfeie.coupling.StaticInterfaceProblem` of the model to reuse. The static
    state itself (F = 1) must exist (else its error is raised).

    >>> import pfeie as pf
    >>> from pfeie.verification._models import block_on_base
    >>> m = block_on_base(joint=pf.Joint(phi=40.0), incline_deg=20.0)
    >>> r = pf.strength_reduction(m)          # tan 40° / tan 20°
    >>> round(r.factor, 3), r.limit, r.analyses
    (2.305, 'sliding', 4)
    """
    if model.pairs is None:
        raise ModelError("strength reduction: the model has no interfaces (no joint to slide)")
    if not (0 < tol < 1e-2 and 1 < f_max <= 1000):
        raise ModelError(f"strength reduction: expected 0 < tol < 0.01 and 1 < f_max <= 1000, "
                         f"got tol = {tol}, f_max = {f_max}")  # fmt: skip
    t0 = time.perf_counter()
    if problem is None:
        problem = StaticInterfaceProblem(model, model.system(), backend=backend,
                                         settings=settings)  # fmt: skip
    system = problem.system
    f0_free, f0_all = system.load(0.0), model.load_vector(0.0)
    names = list(model.pairs.names)
    laws = model.pair_laws
    frames = model.pairs.frame
    count = 0

    def analyse(
        F: float, start: StaticResult | None = None
    ) -> tuple[StaticResult, FloatArray] | None:
        """The static state with the strengths divided by F and each joint's safety
        factor under them; None where no static equilibrium is found. The pair solver
        starts from ``start``'s state (the last factor held), then from the initial
        state."""
        nonlocal count
        reduced = laws if F == 1.0 else laws.reduced(F)
        prob = problem if F == 1.0 else problem.with_laws(reduced)
        st, n = held(prob, f0_free, f0_all, start, f"strength reduction at F = {F:.9g}")
        count += n
        if st is None:
            return None
        fs = joint_factors(reduced, st, frames)[2]
        return st, fs

    base = analyse(1.0)
    if base is None:
        solve_pairs(problem, f0_free, f0_all)  # the static state's own error
        raise SolverError("strength reduction: no static equilibrium with the joints' own "
                          "strengths")  # fmt: skip
    lo, (st_lo, fs_lo) = 1.0, base
    hi: float | None = None
    grow = 2.0 * tol  # the least relative step while the limit is not bracketed
    widths: list[float] = []
    targets: list[float] = []  # the estimates aimed at while the limit is not bracketed
    reopened = 0
    rigid: float | None = None  # the rigid blocks' factor (asked only if needed)
    rigid_done = False
    gap: tuple[float, float, float] | None = None  # (warned at the end, see _translated)
    while True:
        while hi is None or hi - lo > tol * lo:
            if count >= max_analyses:
                log.warning("strength reduction: the limit bracketed to [%.6g, %s] only, in %d "
                            "static analyses", lo, hi, count)  # fmt: skip
                break
            finite = fs_lo[np.isfinite(fs_lo)]
            est = lo * float(finite.min()) if finite.size else np.inf
            if hi is None:
                if lo >= f_max:
                    log.info("strength reduction: held up to F = %g, %d static analyses in %.1f s",
                             f_max, count, time.perf_counter() - t0)  # fmt: skip
                    none = _result(None, None, names, fs_lo, st_lo, count, "none")
                    return _translated(problem, f0_free, none, f_max)
                f_try = max(est * (1 + tol / 4), lo * (1 + grow))
                grow *= 2.0
                ahead = _creep(targets, est, tol)  # estimates that creep up: extrapolated
                if ahead is not None:
                    f_try = max(f_try, ahead)
            elif lo * (1 + tol) < est < hi:
                # the estimate inside the bracket and a step ahead (else it creeps: bisect):
                # just below it once the bracket is that close above it, else just beyond it
                f_try = est * (1 - tol / 4) if hi <= est * (1 + tol / 2) else est * (1 + tol / 4)
                if len(widths) >= 3 and widths[-1] > 0.5 * widths[-3]:
                    f_try = 0.5 * (lo + hi)  # the bracket did not halve in two steps: bisect
            else:
                f_try = 0.5 * (lo + hi)
            f_try = min(f_try, f_max)
            if hi is not None and not lo < f_try < hi:
                f_try = 0.5 * (lo + hi)
            out = analyse(f_try, st_lo)
            if out is None:  # no equilibrium: beyond the limit
                hi = f_try
            else:
                lo, (st_lo, fs_lo) = f_try, out
            if hi is not None:
                widths.append(hi - lo)
        # the failure may be the pair solver's where no joint slides (a hinge mechanism):
        # the rigid blocks' factor bounds the true one from above; factors between the
        # failure and it are tried, and the search goes on from the first that holds
        if (hi is None or reopened >= YIELD_REOPEN or count >= max_analyses
                or np.nanmin(fs_lo, initial=np.inf) <= 1 + SLIDING_FS):  # fmt: skip
            break
        if not rigid_done:
            rigid = problem.rigid_factor(f0_free + uplift_free(model, st_lo, problem.system.free))
            rigid_done = True
        # (not where the rigid blocks hold beyond f_max: wedged blocks, see _yield)
        bound = rigid if rigid is not None and rigid < f_max else None
        if bound is None or not bound > hi * (1 + YIELD_RIGID_GAP):
            break
        beyond = probe_towards(partial(analyse, start=st_lo), hi, bound)
        if beyond is None:
            break
        log.warning("strength reduction: no equilibrium found at F = %.6g, but one at %.6g: "
                    "the pair solver failed short of the limit there; the search goes on "
                    "from %.6g", hi, beyond[0], beyond[0])  # fmt: skip
        reopened += 1
        lo, (st_lo, fs_lo) = beyond
        assert rigid is not None
        top = rigid * (1 + 2 * RIGID_FACTOR_TOL)  # no equilibrium beyond (to its bracket)
        hi = max(top, lo * (1 + 2 * tol)) if top < f_max else None
        widths, targets, grow = [], [], 2.0 * tol
    if hi is None:
        limit = "not bracketed"
    else:
        gov = int(np.argmin(fs_lo)) if np.isfinite(fs_lo).any() else None
        limit = ("sliding" if gov is not None and fs_lo[gov] <= 1 + SLIDING_FS
                 else "no equilibrium found")  # fmt: skip
        if limit != "sliding" and not rigid_done:
            rigid = problem.rigid_factor(f0_free + uplift_free(model, st_lo, problem.system.free))
            rigid_done = True
        if limit != "sliding" and (rigid is None or rigid >= f_max):
            log.warning(
                "strength reduction: the static analyses fail from F = %.6g with no joint "
                "sliding, while rigid blocks hold beyond f_max = %g: F = %.6g may lie below "
                "the limit (a pair solver that failed short of it; factors beyond are not "
                "tried, since blocks wedged by friction against a step or between planes "
                "hold there whatever the strength), or the blocks topple or open; a dynamic "
                "run with the strengths divided by a larger F tells", hi, f_max, lo)  # fmt: skip
        elif limit != "sliding" and rigid is not None and rigid > hi * (1 + YIELD_RIGID_GAP):
            gap = (hi, rigid, lo)
    log.info("strength reduction: F = %.6g (%s), %d static analyses in %.1f s", lo, limit,
             count, time.perf_counter() - t0)  # fmt: skip
    out_ = _result(lo, hi, names, fs_lo, st_lo, count, limit)
    out_ = dataclasses.replace(out_, rigid_factor=rigid) if limit != "sliding" else out_
    return _translated(problem, f0_free, out_, f_max, gap)


def _translated(
    problem: StaticInterfaceProblem, f0_free: FloatArray, out_: StrengthReduction,
    f_max: float, gap: tuple[float, float, float] | None = None,
) -> StrengthReduction:  # fmt: skip
    """``out_`` with the floating blocks' translational factor, and the warning where the
    static analyses' factor lies above it by more than :data:`YIELD_RIGID_GAP`; else the
    warning of a ``gap`` (the first failure, the rigid blocks' factor, the last held)
    between the analyses and the rigid blocks' factor (an upper bound on static
    equilibrium, which a block pinched between its planes exceeds)."""
    f0_free = f0_free + uplift_free(problem.model, out_.static, problem.system.free)
    found = [t for t in translations(problem, f0_free) if np.isfinite(t.factor)]
    t = min(found, key=lambda t: t.factor) if found else None
    held_f = out_.factor
    if t is not None and (f_max if held_f is None else held_f) > t.factor * (1 + YIELD_RIGID_GAP):
        warn_pinched("strength reduction", problem, t, f"at F = {t.factor:.6g}",
                     f"F > {f_max:g}" if held_f is None else f"F = {held_f:.6g}",
                     "factor", t.factor)  # fmt: skip
    elif gap is not None:
        warn_gap("strength reduction", "factor", gap)
    if held_f is not None:
        share = warn_junctions("strength reduction", problem.model, out_.static, out_.joint,
                               f"F = {held_f:.6g}")  # fmt: skip
        out_ = dataclasses.replace(out_, junction_share=share)
    return out_ if t is None else dataclasses.replace(out_, translation_factor=t.factor)


def _result(
    factor: float | None, fail: float | None, names: list[str], fs: FloatArray,
    st: StaticResult, count: int, limit: str,
) -> StrengthReduction:  # fmt: skip
    joint = int(np.argmin(fs)) if np.isfinite(fs).any() else None
    return StrengthReduction(factor, fail, None if joint is None else names[joint],
                             {n: float(f) for n, f in zip(names, fs, strict=True)}, limit, st,
                             count)  # fmt: skip


__all__ = ["REDUCTION_F_MAX", "REDUCTION_MAX_ANALYSES", "REDUCTION_TOL", "StrengthReduction",
           "strength_reduction"]  # fmt: skip
