r"""The yield coefficient: the pseudo-static seismic coefficient at which a joint slides.

A Newmark sliding-block analysis (Newmark 1965; USACE EM 1110-2-2100 App. G) rests on
the *yield coefficient* k_y: the horizontal acceleration, as a fraction of g, under which
the static state of the structure reaches its limit of equilibrium. pfeie finds it on the
model itself, with its loads, water and uplift, blocks and joints, by static analyses
under the loads f_0 (those of :func:`~pfeie.solve_static` at t = 0, without the
horizontal part of the model's own pseudo-static inertia loads, :meth:`Model.add_inertia`:
k_y is the whole horizontal coefficient, and a vertical coefficient acts with it) plus the
pseudo-static inertia force of a uniform acceleration k g along a horizontal unit
vector ι (normal to gravity):

.. math::

    f(k) = f_0 + k\,g\,M\,ι,

M the mass *with the reservoir's added mass* (Westergaard or a finite-element
reservoir: the hydrodynamic force of EM 1110-2-2100's pseudo-static analysis); without
a reservoir M ι g is the weight turned horizontal (consistent mass: Σ_j N_j = 1). Each
analysis is the static analysis at its k from the model's initial pair state (bonded
joints break where the load exceeds their strength at that k: no loading path is
followed; the pair solver starts from the last state held, which changes its work, not
its answer), and the factorisations and the Delassus operator are built once for all.

The limit is the loss of static equilibrium: ``k_y`` is the last coefficient held, within
a relative ``tol`` of the first one that is not. A joint that reaches its capacity while
the structure holds (a joint between two blocks that slides as they deform) is not the
limit. The analyses are placed by each joint's margin, its capacity less its shear,

.. math::

    m_j(k) = Σ_i max(0, c A + μ N_i) − ‖Σ_i T_i‖    (N),

affine in k while the pair states do not change (a rigid block: exactly): the secant
root of the falling margins from two held analyses (joints at their capacity already left
out), then two analyses just below and just beyond it; where states change, bisection
safeguards the secant. A block on an incline takes 5 analyses.

A rigid block on a plane of dip β with a joint of cohesion c over its length L and
friction μ = tan φ, pushed down the dip: N = W(cos β − k sin β), T = W(sin β + k cos β),
so k_y = (c L / W + μ cos β − sin β) / (cos β + μ sin β), tan(φ − β) without cohesion.
"""

from __future__ import annotations

import dataclasses
import logging
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import partial
from typing import TypeVar

import numpy as np

from ..coupling import RIGID_FACTOR_TOL, StaticInterfaceProblem, Translation, translation_limit
from ..errors import ModelError, SolverError
from ..interface import SolverSettings
from ..model import Model
from ..typing import BoolArray, FloatArray
from ._static import (
    StaticResult,
    held,
    joint_factors,
    solve_pairs,
    uplift_free,
    warn_junctions,
)

log = logging.getLogger(__name__)

T = TypeVar("T")

#: the relative width of the final bracket [k_y, k_fail] (default of ``tol``)
YIELD_TOL = 1e-6

#: a limit counts as sliding when the governing joint's safety factor at k_y is within
#: this of 1 (the margin there is tol-small: measured 1e-7 on a block at tol = 1e-6)
SLIDING_FS = 1e-3

#: a joint whose margin is below this fraction of its capacity slides already (at its capacity, to
#: the pair solver's tolerance): it does not predict the limit
AT_CAPACITY = 1e-9

#: the steps out from a k at which a joint came to its capacity (relative 1e-6/2, then
#: doubling): a limit right there is bracketed by the first; past them the search goes on
#: as before
YIELD_NUDGES = 3

#: a joint that came to its capacity within this (relative) below the limit governs it
YIELD_FRESH = 1e-3

#: the static analyses a search may take (each a pair problem on the factorised blocks)
YIELD_MAX_ANALYSES = 60

#: once the limit is bracketed, coefficients this far beyond the first failure (relative)
#: are tried: one that holds shows a failure of the pair solver short of the limit, and
#: the search goes on from it (at most YIELD_REOPEN times). A new user's slope with a
#: rock bridge read k_y 0.8902 "sliding" where 0.95 and 1.0 held (0.899 holds). A second
#: try at 5 % found no more there and cost Newtons of 100 iterations beyond a block's
#: limit with uplift (tests/test_interface_solver.py)
YIELD_BEYOND = (0.01,)
YIELD_REOPEN = 2

#: where the analyses fail with no joint sliding, the rigid blocks' limit k_rigid
#: (:meth:`StaticInterfaceProblem.rigid_limit`) is computed; if it lies more than this
#: (relative) beyond the failure, coefficients at these fractions of the way from the
#: failure to it are tried, and the search goes on from the first that holds (a masonry
#: arch of 20 voussoirs under a lateral load: the analyses failed at k = 0.14 to 0.145,
#: held at 0.1475, against a rigid limit of 0.149)
YIELD_RIGID_GAP = 0.01
YIELD_RIGID_PROBES = (0.5, 0.8, 0.25, 0.95)

#: the largest coefficient tried (a fraction of g); a structure held at it is reported
#: with k_y = None (no yield up to it)
YIELD_K_MAX = 2.0


@dataclass(frozen=True)
class YieldCoefficient:
    """The yield coefficient along one horizontal direction.

    - ``direction``: the unit vector ι of the pseudo-static acceleration;
    - ``k_y``: the largest coefficient held (a fraction of g), None if the structure is
      held up to ``k_max``;
    - ``k_fail``: the least coefficient found beyond the limit (None with ``k_y`` None;
      where the search went on past a failure of the pair solver, it may be the rigid
      blocks' bound, beyond which no equilibrium exists);
    - ``k_affine``: where the joints' margins, extrapolated affinely from the last two
      coefficients held, vanish (the limit of a rigid block; an estimate where the
      analyses fail short of the limit, see ``limit``); None without two;
    - ``joint``: the joint that governs: the one whose margin gives ``k_affine``, else
      the least safety factor at ``k_y``;
    - ``safety_factors``: each joint's sliding safety factor at ``k_y``, Σ capacity / ‖Σ T‖
      (∞: no shear), with each pair's capacity under its law: max(0, c A + μ N), or on the
      residual cohesion's ramp (:func:`~pfeie.interface.cohesion_ramp`) the part a pair
      that touches with almost no normal force mobilises (the summary's static FS counts
      c A on every pair that touches, as the hand computation);
    - ``limit``: "sliding" (the governing joint's safety factor is 1 at ``k_y``, within
      :data:`SLIDING_FS`), "no equilibrium found" (the static analyses fail beyond
      ``k_y`` while its safety factor is above 1: a mechanism of opening, a bonded joint
      breaking through, or the pair solver failing short of the limit; ``k_affine`` then
      estimates the sliding limit), "none" (held up to ``k_max``) or "not bracketed"
      (``max_analyses`` reached first);
    - ``static``: the static state at ``k_y``; ``analyses``: how many static analyses;
    - ``k_rigid``: with the limit "no equilibrium found", the rigid blocks' limit
      coefficient (:meth:`~pfeie.coupling.StaticInterfaceProblem.rigid_limit`, limit
      equilibrium, to 1e-3): no equilibrium exists beyond it, so the limit lies in
      [``k_y``, ``k_rigid``]; a gap of more than 1 % is warned (the pair solver failing
      short of the limit near a hinge mechanism). None otherwise.
    - ``k_translation``: the least coefficient at which a floating block's rigid
      translation slides (:func:`~pfeie.coupling.translation_limit`: Hoek and Bray's
      plane and wedge sliding, for blocks that rest on supported bodies only; None where
      no block is checked or none slides up to ``k_max``). A ``k_y`` more than 1 % above
      it is warned: the static analyses then lean on friction that the block's sliding
      does not mobilise (a block pinched between its planes), and the dynamic runs
      follow the lower coefficient.
    - ``junction_share``: where the governing joint leans on its pairs at junctions in
      the last state held (:meth:`~pfeie.interface.PairGeometry.junctions`: more than
      20 % of its normal force and five times their share of its area,
      ``pfeie.solvers.JUNCTION_SHARE`` and ``JUNCTION_RATIO``; warned), that share: node
      pairs at a block's corner where joints meet, whose friction grows as the mesh is
      refined. None otherwise.
    """

    direction: FloatArray
    k_y: float | None
    k_fail: float | None
    k_affine: float | None
    joint: str | None
    safety_factors: dict[str, float]
    limit: str
    static: StaticResult
    analyses: int
    k_rigid: float | None = None
    k_translation: float | None = None
    junction_share: float | None = None

    def __repr__(self) -> str:
        """One line: the coefficient, the limit and its joint, the analyses (the static
        state and the arrays are left out)."""
        d = ", ".join(f"{x:.4g}" for x in self.direction)
        k = "None" if self.k_y is None else f"{self.k_y:.6g}"
        return (f"YieldCoefficient(direction=({d}), k_y={k}, limit={self.limit!r}, "
                f"joint={self.joint!r}, analyses={self.analyses})")  # fmt: skip


def _gravity(model: Model) -> FloatArray:
    """The model's gravity vector (m/s²): the sum of its constant gravity loads."""
    gvec = np.zeros(model.dim)
    for ld in model.loads:
        if ld.kind == "gravity" and ld.amplitude is None:
            gvec = gvec + np.asarray(ld.value, dtype=float)
    return gvec


def horizontal(
    model: Model, direction: Sequence[float] | FloatArray | None = None, axis: int = 0
) -> tuple[float, FloatArray]:
    """The magnitude g (m/s²) of the model's gravity and a horizontal unit vector ι:
    ``direction`` made unit (it must be normal to gravity), or the coordinate axis ``axis``
    (0: +x, 1: +y) made normal to gravity. :class:`ModelError` without gravity or with a
    direction that is not horizontal."""
    gvec = _gravity(model)
    g = float(np.linalg.norm(gvec))
    if not g > 0:
        raise ModelError("yield coefficient: the model has no gravity (the coefficient is a "
                         "fraction of g; add_gravity first)")  # fmt: skip
    up = -gvec / g
    if direction is None:
        iota = np.eye(model.dim)[axis] - up[axis] * up
    else:
        given: object = direction
        try:
            iota = np.asarray(given, dtype=float)
            if isinstance(given, str):
                raise ValueError
        except (TypeError, ValueError):
            iota = np.full(0, np.nan)
        if iota.shape != (model.dim,) or not np.all(np.isfinite(iota)):
            raise ModelError(f"yield coefficient: expected a direction of {model.dim} finite "
                             f"components, got {direction!r}")  # fmt: skip
    norm = float(np.linalg.norm(iota))
    if not norm > 0:
        raise ModelError(f"yield coefficient: the direction is zero (or {'xyz'[axis]} is "
                         "vertical)")  # fmt: skip
    iota = iota / norm
    if abs(float(iota @ up)) > 1e-9:
        raise ModelError(f"yield coefficient: the direction {np.round(iota, 6).tolist()} is not "
                         "horizontal (normal to gravity)")  # fmt: skip
    return g, iota


def yield_coefficient(
    model: Model,
    direction: Sequence[float] | FloatArray | None = None,
    *,
    tol: float = YIELD_TOL,
    k_max: float = YIELD_K_MAX,
    backend: str = "auto",
    settings: SolverSettings | None = None,
    problem: StaticInterfaceProblem | None = None,
    max_analyses: int = YIELD_MAX_ANALYSES,
) -> YieldCoefficient:
    """The yield coefficient k_y of ``model`` along a horizontal ``direction`` (default +x
    made normal to gravity; see the module docstring). ``problem``: a
    :class:`~pfeie.coupling.StaticInterfaceProblem` of the model to reuse (for both
    directions). The static state at k = 0 must exist (else its error is raised).

    >>> import numpy as np, pfeie as pf
    >>> from pfeie.verification._models import block_on_base
    >>> m = block_on_base(joint=pf.Joint(phi=40.0), incline_deg=10.0)  # dip towards +x
    >>> y = pf.yield_coefficient(m)                 # pushed down the dip: tan(40° − 10°)
    >>> round(y.k_y, 5), y.joint
    (0.57735, 'joint')
    >>> y  # doctest: +ELLIPSIS
    YieldCoefficient(direction=(1, 0), k_y=0.57735..., limit='sliding', joint='joint', analyses=...)
    >>> round(pf.yield_coefficient(m, [-1.0, 0.0]).k_y, 5)   # up the dip: tan(50°)
    1.19175
    """
    if model.pairs is None:
        raise ModelError("yield coefficient: the model has no interfaces (no joint to slide)")
    if not (0 < tol < 1e-2 and 0 < k_max <= 10):
        raise ModelError(f"yield coefficient: expected 0 < tol < 0.01 and 0 < k_max <= 10, "
                         f"got tol = {tol}, k_max = {k_max}")  # fmt: skip
    g, iota = horizontal(model, direction)
    t0 = time.perf_counter()
    if problem is None:
        problem = StaticInterfaceProblem(model, model.system(), backend=backend,
                                         settings=settings)  # fmt: skip
    system = problem.system
    free = system.free
    f0_free, f0_all = system.load(0.0), model.load_vector(0.0)
    # the model's own pseudo-static coefficients (Model.add_inertia, loads.pseudo_static):
    # their horizontal part is left out, so that k_y is the whole horizontal coefficient
    # (a model under k_h = 0.1 read k_y 0.41 for a limit at 0.51); a vertical one acts
    # with it
    up = -_gravity(model) / g
    a_h = np.zeros(model.dim)
    for ld in model.loads:
        if ld.kind == "inertia":
            a = np.asarray(ld.value, dtype=float)
            scale = 1.0 if ld.amplitude is None else float(ld.amplitude(0.0))
            a_h = a_h + scale * (a - (a @ up) * up)
    if np.any(a_h):
        f_own = model.inertia_load(a_h)
        f0_free, f0_all = f0_free - f_own[free], f0_all - f_own
        log.info("yield coefficient: the model's horizontal pseudo-static acceleration %s "
                 "m/s² is left out (k_y is the whole horizontal coefficient)",
                 np.round(a_h, 6).tolist())  # fmt: skip
    # the inertia of a uniform acceleration g ι
    f_h = model.inertia_load(g * iota)
    names = list(model.pairs.names)
    laws = model.pair_laws
    frames = model.pairs.frame
    count = 0

    def analyse(
        k: float, start: StaticResult | None = None
    ) -> tuple[StaticResult, FloatArray, FloatArray] | None:
        """The static state at k, each joint's relative margin and safety factor; None
        where no static equilibrium is found. The pair solver starts from the state
        ``start`` (the last coefficient held), then, if that fails, from the initial state;
        the answer does not depend on the start (:meth:`InterfaceSolver.solve`)."""
        nonlocal count
        st, n = held(problem, f0_free + k * f_h[free], f0_all + k * f_h, start,
                     f"yield coefficient along {_direction(iota)} at k = {k:.9g}")  # fmt: skip
        count += n
        if st is None:
            return None
        capacity, shear, fs = joint_factors(laws, st, frames)
        # the margin, capacity − shear (N, affine in k while no state changes); NaN where
        # the joint is at its capacity already (relatively, to AT_CAPACITY) or has none:
        # it does not predict the limit
        margin = capacity - shear
        margin[~(margin > AT_CAPACITY * capacity)] = np.nan
        return st, margin, fs

    base = analyse(0.0)
    if base is None:
        # the static state itself: its own error, with the solver's explanation
        solve_pairs(problem, f0_free, f0_all)
        raise SolverError("yield coefficient: no static equilibrium at k = 0")
    lo, (st_lo, m_lo, fs_lo) = 0.0, base
    hi: float | None = None
    prev: tuple[float, FloatArray] | None = None  # a held (k, margins) below lo
    widths: list[float] = []
    targets: list[float] = []  # the predicted roots aimed at (see _creep)
    reopened = 0
    k_rigid: float | None = None  # the rigid blocks' limit (asked only if needed)
    gap: tuple[float, float, float] | None = None  # (warned at the end, see _translated)
    rigid_done = False
    # the k at which each joint came to its capacity during the search (NaN: not at it,
    # or at it from k = 0 on: a joint that slides while the structure holds), and the
    # relative steps out from a k where one just came to it (see below)
    k_came = np.full(len(names), np.nan)
    nudge, nudges = tol / 2, 0
    while True:
        while hi is None or hi - lo > tol * max(hi, 1e-3):
            if count >= max_analyses:
                log.warning("yield coefficient: the limit bracketed to [%.6g, %s] only, in %d "
                            "static analyses", lo, hi, count)  # fmt: skip
                break
            target = _root(lo, m_lo, prev)[0]
            fresh = _fresh(k_came, lo, tol)
            if (hi is None and fresh.any() and nudges < YIELD_NUDGES
                    and (target is None or not target > lo)):  # fmt: skip
                # a joint came to its capacity at (or just below) lo: the limit may lie
                # just above; a few steps out that double, not a doubling of k (then
                # bisected back down: 54 analyses where 8)
                k_try = min(lo * (1 + nudge), k_max)
                nudge, nudges = 2 * nudge, nudges + 1
            elif target is None or not target > lo or (hi is not None and not target < hi):
                k_try = min(2 * max(lo, 0.025), k_max) if hi is None else 0.5 * (lo + hi)
            else:  # aim just below the predicted root, then, once there, just beyond it
                below = lo >= target * (1 - tol)
                k_try = target * (1 + tol / 4) if below else target * (1 - tol / 2)
                ahead = None if below else _creep(targets, target, tol)
                if ahead is not None:
                    k_try = ahead if hi is None or ahead < hi else 0.5 * (target + hi)
                if hi is not None and len(widths) >= 3 and widths[-1] > 0.5 * widths[-3]:
                    k_try = 0.5 * (lo + hi)  # the bracket did not halve in two steps: bisect
                k_try = min(k_try, k_max)
                if hi is not None and not lo < k_try < hi:
                    k_try = 0.5 * (lo + hi)
            if hi is None and lo >= k_max:
                log.info("yield coefficient along %s: held up to k = %g, %d static analyses "
                         "in %.1f s", _direction(iota), k_max, count,
                         time.perf_counter() - t0)  # fmt: skip
                none = _result(iota, None, None, names, fs_lo, st_lo, count, None, "none")
                return _translated(problem, f0_free, f_h[free], k_max, none)
            out = analyse(k_try, st_lo)
            if out is None:  # no equilibrium: beyond the limit
                hi = k_try
            else:
                prev = (lo, m_lo)
                lo, (st_lo, m_lo, fs_lo) = k_try, out
                came = np.isnan(m_lo) & np.isfinite(prev[1]) & np.isnan(k_came)
                k_came[came] = lo
            if hi is not None:
                widths.append(hi - lo)
        # the bracket's failure may be the pair solver's: try a little beyond it
        if hi is None or reopened >= YIELD_REOPEN or count >= max_analyses:
            break
        beyond = None
        for rel in YIELD_BEYOND:
            k_b = min(hi * (1 + rel), k_max)
            if not k_b > hi:
                break
            out = analyse(k_b, st_lo)
            if out is not None:
                beyond = (k_b, out)
                break
        if beyond is None and not np.nanmin(fs_lo, initial=np.inf) <= 1 + SLIDING_FS:
            # no joint slides at the last coefficient held, so the failure may be the pair
            # solver's (near a hinge mechanism): the rigid blocks' limit bounds the true
            # one from above; coefficients between the failure and it are tried
            if k_rigid is None and not rigid_done:
                up = uplift_free(model, st_lo, free)
                k_rigid, rigid_done = problem.rigid_limit(f0_free + up, f_h[free], k_max), True
            # not where the rigid blocks hold at k_max (k_rigid = ∞): frictional forces
            # that wedge a block against a step (tan² φ > 1) or pinch it between its planes
            # balance any load, so the check bounds nothing, and a probe towards k_max met
            # such a wedged equilibrium (eight columns on a stepped base: k = 1.677 held
            # after every analysis from 0.385 on had failed, the rigid row sliding at 0.47)
            bound = k_rigid if k_rigid is not None and k_rigid < k_max else None
            if bound is not None and bound > hi * (1 + YIELD_RIGID_GAP):
                beyond = probe_towards(partial(analyse, start=st_lo), hi, bound)
        if beyond is None:
            break
        log.warning("yield coefficient along %s: no equilibrium found at k = %.6g, but one "
                    "at %.6g: the pair solver failed short of the limit there; the search "
                    "goes on from %.6g", _direction(iota), hi, beyond[0], beyond[0])  # fmt: skip
        reopened += 1
        prev = (lo, m_lo)
        lo, (st_lo, m_lo, fs_lo) = beyond
        hi, widths, targets, nudge, nudges = None, [], [], tol / 2, 0
        if k_rigid is not None and lo < k_rigid * (1 + 2 * RIGID_FACTOR_TOL) < k_max:
            # no equilibrium beyond the rigid blocks' limit (to its bracket): the bound
            hi = k_rigid * (1 + 2 * RIGID_FACTOR_TOL)
    estimate, joint = _root(lo, m_lo, prev)
    if hi is None:
        limit = "not bracketed"
    else:
        gov = joint if joint is not None else (
            int(np.argmin(fs_lo)) if np.isfinite(fs_lo).any() else None)  # fmt: skip
        # (a bracket of a relative tol leaves the factor up to 1 + tol at k_y)
        at_one = 1 + max(SLIDING_FS, 2 * tol)
        fresh = _fresh(k_came, lo, tol) & (fs_lo <= at_one)
        if (gov is None or not fs_lo[gov] <= at_one) and fresh.any():
            # a joint that came to its capacity at the limit governs: its margin, NaN at
            # its capacity, left the roots to another joint's (a bonded lift joint far
            # from its strength), though it slides there; not one that came to it long
            # before, sliding while the structure held (a limit of rocking, say)
            gov = int(np.argmin(np.where(fresh, fs_lo, np.inf)))
        limit = ("sliding" if gov is not None and fs_lo[gov] <= at_one
                 else "no equilibrium found")  # fmt: skip
        joint = gov
        if limit != "sliding" and not rigid_done:
            k_rigid = problem.rigid_limit(f0_free + uplift_free(model, st_lo, free), f_h[free],
                                          k_max)  # fmt: skip
        if k_rigid is not None and not np.isfinite(k_rigid):
            k_rigid = None  # the rigid blocks hold at k_max: no bound below it
            if limit != "sliding":
                log.warning(
                    "yield coefficient along %s: the static analyses fail from k = %.6g with "
                    "no joint sliding, while rigid blocks hold up to k_max = %g: k_y = %.6g "
                    "may lie below the limit (a pair solver that failed short of it; "
                    "coefficients beyond are not tried, since blocks wedged by friction "
                    "against a step or between planes hold there whatever the load), or "
                    "the blocks topple or open; a dynamic run at a larger k tells",
                    _direction(iota), hi, k_max, lo)  # fmt: skip
        if limit != "sliding" and k_rigid is not None and k_rigid > hi * (1 + YIELD_RIGID_GAP):
            gap = (hi, k_rigid, lo)
    log.info("yield coefficient along %s: k_y = %.6g (%s), %d static analyses in %.1f s",
             _direction(iota), lo, limit, count, time.perf_counter() - t0)  # fmt: skip
    out_ = _result(iota, lo, hi, names, fs_lo, st_lo, count, estimate, limit, joint)
    out_ = dataclasses.replace(out_, k_rigid=k_rigid) if limit != "sliding" else out_
    return _translated(problem, f0_free, f_h[free], k_max, out_, gap)


def _translated(
    problem: StaticInterfaceProblem, f0: FloatArray, f1: FloatArray, k_max: float,
    out_: YieldCoefficient, gap: tuple[float, float, float] | None = None,
) -> YieldCoefficient:  # fmt: skip
    """``out_`` with the floating blocks' translational limit, and the warning where the
    static analyses' k_y lies above it by more than :data:`YIELD_RIGID_GAP`; else the
    warning of a ``gap`` (the first failure, the rigid blocks' limit, the last held)
    between the analyses and the rigid blocks' limit (an upper bound on static
    equilibrium, which a block pinched between its planes exceeds)."""
    f0 = f0 + uplift_free(problem.model, out_.static, problem.system.free)
    found = translation_limit(problem, f0, f1, k_max)
    ky = out_.k_y
    where = _direction(out_.direction)
    if found is not None and (k_max if ky is None else ky) > found[0] * (1 + YIELD_RIGID_GAP):
        k_t, t = found
        warn_pinched(f"yield coefficient along {where}", problem, t, f"from k = {k_t:.6g}",
                     f"k_y > {k_max:g}" if ky is None else f"k_y = {ky:.6g}",
                     "coefficient", k_t)  # fmt: skip
    elif gap is not None:
        warn_gap(f"yield coefficient along {where}", "limit k", gap)
    if ky is not None:
        share = warn_junctions(f"yield coefficient along {where}", problem.model, out_.static,
                               out_.joint, f"k_y = {ky:.6g}")  # fmt: skip
        out_ = dataclasses.replace(out_, junction_share=share)
    return out_ if found is None else dataclasses.replace(out_, k_translation=found[0])


def warn_gap(what: str, bound: str, gap: tuple[float, float, float]) -> None:
    """The warning of a limit search whose analyses fail below the rigid blocks' bound:
    ``gap`` = (the first failure, the bound, the last held); ``bound`` names it ("limit
    k", "factor")."""
    fail, rigid, held_ = gap
    sym = bound[-1] if bound.endswith(" k") else "F"
    log.warning(
        "%s: the static analyses fail from %s = %.6g, below the rigid blocks' %s = %.6g "
        "(limit equilibrium: no equilibrium exists beyond it): the pair solver may have "
        "failed short of the limit (a hinge mechanism, an arch), or a row of columns "
        "topples, which the rigid blocks' check does not see (it may put the forces low "
        "on a column's face); static equilibrium ends between %.6g and %.6g",
        what, sym, fail, bound, rigid, held_, rigid)  # fmt: skip


def warn_pinched(what: str, problem: StaticInterfaceProblem, t: Translation, at: str,
                 held_text: str, quantity: str, value: float) -> None:  # fmt: skip
    """The warning of a limit search whose static analyses hold beyond the limit of a
    block's rigid translation ``t`` (:func:`pfeie.coupling.translations`): ``what`` names
    the search, ``at`` where the block slides, ``held_text`` the analyses' answer."""
    name = problem.model.body_names()[t.body]
    where = f"on {', '.join(map(repr, t.planes))}" if t.planes else "off its planes"
    log.warning(
        "%s: block %r slides as a rigid block %s %s (limit equilibrium of its translations, "
        "Hoek and Bray's plane and wedge sliding: a plane parallel to the sliding carries "
        "no force), below the static analyses' %s: they pinch the block between its "
        "planes and lean on friction that its sliding does not mobilise, and the dynamic "
        "runs follow the lower %s; take %.6g (docs/theory.md, 'Two safety factors')",
        what, name, where, at, held_text, quantity, value)  # fmt: skip


def probe_towards(analyse: Callable[[float], T | None], fail: float,
                  bound: float) -> tuple[float, T] | None:  # fmt: skip
    """The first of the values at :data:`YIELD_RIGID_PROBES` of the way from a ``fail``
    (a value the analyses did not hold) to the rigid blocks' ``bound`` at which
    ``analyse`` holds, with its answer; None if none holds (a limit search's way past a
    pair solver that failed short of the limit)."""
    for frac in YIELD_RIGID_PROBES:
        value = fail + frac * (bound - fail)
        out = analyse(value)
        if out is not None:
            return value, out
    return None


def _fresh(k_came: FloatArray, lo: float, tol: float) -> BoolArray:
    """The joints that came to their capacity at ``lo`` or just below it (within
    :data:`YIELD_FRESH`, or 8 ``tol`` where that is more: the steps out included), not
    at k = 0."""
    near = max(YIELD_FRESH, 8 * tol)
    with np.errstate(invalid="ignore"):
        return np.asarray(np.isfinite(k_came) & (k_came >= lo * (1 - near)) & (lo > 0))


def _creep(targets: list[float], target: float, tol: float) -> float | None:
    """Where to aim when the predicted roots creep up: a margin that falls faster as k
    grows (a joint whose pairs turn their shear as they slide, the planes of a wedge)
    puts each secant root short of the limit, and the roots approach it linearly (by a
    ratio r of about 0.6 a step on a wedge: 30 analyses to reach the limit). Aitken's
    extrapolation of the last three roots, t + Δ r / (1 − r), overshot by a fifth so
    that it brackets the limit; None where the roots do not creep (an affine margin, a
    rigid block: its first root is the limit) (``targets`` gains ``target``)."""
    targets.append(target)
    if len(targets) < 3:
        return None
    d1, d2 = targets[-2] - targets[-3], targets[-1] - targets[-2]
    if not (d1 > tol * target and tol * target < d2 < d1):
        return None
    r = d2 / d1
    return target + 1.2 * d2 * r / (1.0 - r)


def _direction(iota: FloatArray) -> list[float]:
    """The direction for a message: rounded, without negative zeros."""
    return [round(float(v), 6) + 0.0 for v in iota]


def _root(
    lo: float, m_lo: FloatArray, prev: tuple[float, FloatArray] | None
) -> tuple[float | None, int | None]:
    """The least root over the joints of their margins (N) taken affine in k from the
    held point ``prev`` and ``lo``, and its joint; a joint that came to its capacity at
    ``lo`` (its margin NaN there, not at ``prev``) has its root at ``lo``; joints at
    their capacity at both (a joint that slides while the structure holds) or whose
    margin does not fall are left out. (None, None) without two points or such a
    joint."""
    if prev is None:
        return None, None
    k0, m0 = prev
    came = np.isnan(m_lo) & np.isfinite(m0)
    if came.any():  # (the search steps out from lo, :func:`yield_coefficient`)
        return lo, int(np.flatnonzero(came)[0])
    slope = (m_lo - m0) / (lo - k0)
    ok = np.isfinite(m_lo) & np.isfinite(m0) & (slope < 0)
    if not ok.any():
        return None, None
    roots = np.where(ok, lo - m_lo / np.where(ok, slope, -1.0), np.inf)
    j = int(np.argmin(roots))
    return float(roots[j]), j


def _result(
    iota: FloatArray, k_y: float | None, k_fail: float | None, names: list[str],
    fs: FloatArray, st: StaticResult, count: int, estimate: float | None, limit: str,
    joint: int | None = None,
) -> YieldCoefficient:  # fmt: skip
    if joint is None and np.isfinite(fs).any():
        joint = int(np.argmin(fs))
    return YieldCoefficient(iota, k_y, k_fail, estimate, None if joint is None else names[joint],
                            {n: float(f) for n, f in zip(names, fs, strict=True)}, limit, st,
                            count)  # fmt: skip


__all__ = ["SLIDING_FS", "YIELD_K_MAX", "YIELD_MAX_ANALYSES", "YIELD_TOL", "YieldCoefficient",
           "horizontal", "yield_coefficient"]  # fmt: skip
