"""The interface problem of one step (method.md §5): find the pair forces and states.

With the Delassus operator W (M × M, M = m·d, row ``k·d + i`` for component i of pair k)
and the free relative displacement w_free (m, d), the pairs obey

    w = w_free + W X (+ E q),      s = w + C X,

with the pair law of method.md §4: the strength of each pair comes from its joint law
through :class:`PairLaws`; states, breaking and the friction cone are handled here.
Optional border (statics, §5.2): the rigid-mode amplitudes q of floating blocks with
equilibrium Eᵀ X = e.

Algorithm (the paper's state iteration, §5.3): assume states; solve the reduced linear
system (intact and stick pairs: s = s_prev in all components, closed normal s_n = 0;
sliding pairs: s_n = 0 and X_t = −(c A + μ X_n) ŝ; open pairs: X = 0); check the law;
update states (breaking is irreversible and monotone within the step; 3D slip directions
ŝ follow the slip increment); repeat until no state changes and the directions settle.

Two modes for the time stepping at the rate levels (method.md §3.1), arguments of
:meth:`InterfaceSolver.solve`: ``fixed`` pairs slide in a given direction ŝ (a pair
already sliding at the start of the step keeps X_t = −(c A + μ X_n) ŝ at the acceleration
level: it may open but not stick), and ``breaking=False`` keeps intact pairs intact
whatever their force (the caller decides breaks on the converged forces, see
:meth:`PairLaws.overstressed`). Pairs marked ``inactive`` are held open (X = 0, whatever
their gap): the time stepping solves the problem of the other pairs without a new
factorisation, since an open pair is one more row of the capacitance system of the
once-inverted W_c (Woodbury).
The answer is accepted only when the complementarity residual

    r_k = ρ|Δs_k| (intact, stick), |X_t − Π_{τ_max}(X_t − ρ Δs_t)| (broken, closed),
          max(0, −ρ s_n) (open), plus any strength violation,

scaled by max(|X|, ρ |w_free|), is below ``tol`` (ρ = 1/mean diag W). When the states
cycle or the iteration limit is hit, a semismooth Newton on the Alart-Curnier map takes
over from the last iterate, then from X = 0. If both fail (redundant pairs: a singular
or badly scaled W on which the Newton stalls on round-off), the proximal-point Newton of
:mod:`._proximal` (the law for W + σ I and the proximal term, σ lowered as the residual
falls: regular, well-conditioned Newton systems whatever the rank of W) starts from the
best iterate, then from X = 0; then a projected Gauss-Seidel sweep over the pairs with
exact local solutions; if all fail, :class:`InterfaceError` names the pairs that kept
changing and the residual. Each answer is judged by the residual above. When the
state iteration or the first Newton succeeds, nothing of this path changes: the
fallbacks only run after them.

A solver made for a W that changed a little (pair frames that turned with their blocks,
large rotations) may keep the W_c⁻¹ of a ``reference`` solver instead of factorising its
own: each state system A X = b (the rows of W_c, those of the open and sliding components
replaced by their constraints) is solved on the reference's A_ref⁻¹ (its Woodbury form)
and refined with the residual of the exact A,

    X₀ = A_ref⁻¹ b,    X_{j+1} = X_j + A_ref⁻¹ (b − A X_j),

which contracts by q ≈ ‖A_ref⁻¹ (A − A_ref)‖, of the order of the rotation since the
reference was factorised. It runs until the correction falls to round-off
(:data:`REFINE_TOL` of X; or, on an ill-conditioned W_c whose corrections stall at the
residual's own round-off, below :data:`REFINE_FLOOR` of X), so the state iteration, its
residual and its tolerance are those of a solver that factorised W_c itself. When the
corrections stop contracting (q > :data:`REFINE_MAX_CONTRACTION`) or do not reach
round-off in :data:`REFINE_MAX_ITER` corrections, the solver factorises its own W_c and
solves again; the largest first contraction factor is kept in
:attr:`InterfaceSolver.contraction` for the caller to decide when to factorise anew.

A large 3D problem (at least :data:`NEWTON_WOODBURY_MIN` components, W_c inverted once)
takes another path. Its slip directions follow the slip increments, a fixed point that
converges linearly or not at all (neighbouring sliding pairs turn each other), so the
state iteration hands over to the semismooth Newton as soon as a direction turns. The
Newton's map F(X) of the pairs depends on each pair's own (X_k, s_k), s = s_free + W_c X,
so its generalised Jacobian is

    J = L + R W_c,   L_k = ∂F_k/∂X_k,  R_k = ∂F_k/∂s_k   (d × d per pair),

and a step J x = b is solved without forming J: the rows o that are not those of ρ W_c
(separated normals, sliding and fixed tangents, held-open pairs) give a capacitance
system of k = |o| unknowns,

    x = W_c⁻¹ (b₀ + E_o y)/ρ,   (L_o W_c⁻¹[:, o] + R_o[:, o]) y/ρ = b_o − L_o z − R_o b₀/ρ,

(b₀: b with its rows o zeroed, z = W_c⁻¹ b₀/ρ), gathered pair by pair; W_c x =
(b₀ + E_o y)/ρ is known without a product, so a Newton iteration costs one product with
W_c⁻¹ (O(M²)), and an iterate that meets the tolerance is judged again on s recomputed.
With a border (statics, r rigid amplitudes), the state systems and the Newton steps are
the same Woodbury solves for [b, E] plus an r × r system for q (:meth:`_woodbury_bordered`,
:meth:`_bordered_step`), instead of an LU of the bordered (M + r)-square system per
pattern. Every answer is judged by the same residual and tolerance.

A large sparse W (at least :data:`SPARSE_MIN` rows and at most :data:`SPARSE_FILL`
nonzeros, e.g. granular media: many blocks, each with a few pairs) is kept sparse: the
state systems are factorised by a sparse LU, W is not inverted, and a failed state
iteration goes to the proximal-point Newton with sparse LU at once (the dense Newton
would cost a dense factorisation per iteration). A dense W takes the path above.
"""

from __future__ import annotations

import copy
import logging
import warnings
from collections import OrderedDict
from dataclasses import dataclass
from typing import cast

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.linalg.lapack import dgetrf as _getrf
from scipy.linalg.lapack import dgetrs as _getrs

from ..errors import InterfaceError, MechanismError, ModelError
from ..linalg import SYMMETRIC_MIN, MixedLU, Workspace, symmetric_columns, symmetric_product
from ..typing import FloatArray
from ._laws import PairLaws, cohesion_ramp, cohesion_ramp_tangent, cone
from ._proximal import PairLaw, ShiftedOperator, proximal_newton
from ._settings import SolverSettings
from ._state import INTACT, OPEN, SLIDE, STATE_NAMES, STICK, PairState

log = logging.getLogger(__name__)

SPARSE_MIN = 1000
"""Smallest W (rows) kept sparse when it is sparse enough (:data:`SPARSE_FILL`)."""
SPARSE_FILL = 0.05
"""Largest fraction of nonzeros of a W kept sparse."""
#: the load fractions of the continuation that a static problem with floating blocks
#: takes where its Newtons fail on the whole load (:meth:`InterfaceSolver._continuation`)
CONTINUATION = (0.5, 0.75, 0.9, 1.0)
#: the method of a solve that the proximal Newton finished as the second stage of a 3D
#: problem (:data:`PROXIMAL_FIRST_3D`), after the state iteration: not a fallback
SECOND_STAGE_PROXIMAL = "proximal Newton (second stage)"

#: the most unknowns (pair components and rigid amplitudes) on which the static problem
#: tries the bordered proximal Newton (dense (M + k)-square Newton systems: 0.4 s each at
#: 2,400 on one core; it needed 28 to 42 of them near an arch's hinge mechanism)
BORDERED_PROXIMAL_MAX = 2400

#: the bordered proximal Newton's caps: Newton iterations, and outer iterations in a row
#: without halving the residual (where it succeeded, near an arch's hinge mechanism and a
#: plane failure's limit, it took at most 50 and 10; where no equilibrium exists it ran to
#: its caps, and a limit search meets tens of such analyses)
BORDERED_PROXIMAL_NEWTON = 150
BORDERED_PROXIMAL_STALL = 8

PROXIMAL_FIRST_3D = True
"""Where the state iteration does not settle a 3D problem without a border that the Newton
through W_c⁻¹ does not take (fewer than :data:`NEWTON_WOODBURY_MIN` components, or a W_c⁻¹
shared from the step's other problem), the proximal-point Newton
(:mod:`._proximal`) goes first and the dense semismooth Newtons follow only if it fails.
Measured: a Tet4 rock wedge of 107 pairs under El Centro, 200 steps: all 400 pair problems
solved by it, 19 s against 47 s for the dense Newton first, which stalled at the kinks of
pairs on their cone's edge (sticking at the limit of friction, an elastic wedge's static
state) and needed its cold start or the proximal Newton on 114 of them; FCLIB 22 of 22
solved either way."""

NEWTON_WOODBURY_MIN = 300
"""Smallest W (rows) whose semismooth-Newton steps go through the once-inverted W_c (in 3D,
with the Jacobian kept per pair and the Newton taking over from the state iteration as
soon as a slip direction turns; a 3D border problem is then solved on W_c⁻¹ too)."""
LARGE_CAPACITANCE = 1000
"""Rows of a capacitance system (open and sliding components) from which, in a W of
:data:`~pfeie.linalg.SYMMETRIC_MIN` rows or more, the Newton step through W_c⁻¹ and the
state systems gather and solve it in work arrays, by a single-precision LU refined in
double (:meth:`InterfaceSolver._woodbury_step_large`; below, the O(k³) of its LU costs
less than the refinement and the second product: docs/benchmarks.md)."""
_SINGULAR = (
    "the interface system is singular: with the current pair states some block is "
    "not restrained (a mechanism)"
)
REFINE_TOL = 1e-15
"""Iterative refinement on a reference W_c⁻¹: the state system is solved when the last
correction, or the error it predicts (q/(1 − q) of it), is at most this fraction of X
(max norms): round-off."""
REFINE_FLOOR = 1e-12
"""A refinement whose corrections stop contracting below this fraction of X has reached
the round-off of the residual (ε times the condition of W_c) and is accepted there."""
REFINE_MAX_CONTRACTION = 0.5
"""A refinement whose corrections shrink by less than this factor (above
:data:`REFINE_FLOOR`) is abandoned: the solver factorises its own W_c."""
REFINE_MAX_ITER = 40
"""Corrections of one refinement before the solver factorises its own W_c."""
NEWTON_STALL = 20
"""A semismooth Newton whose residual has not halved over this many iterations has
stalled (far from the answer, its line search crawls across the kinks of the law, a
pair state at a time) and hands over to the next start (the dense Newton from the same
iterate after the one through W_c⁻¹, the given first iterate, then a cold start, which
runs to its limit unless its line search fails, :data:`LINE_SEARCH_FAILS`) or fallback,
instead of running to its iteration limit."""


LINE_SEARCH_FAILS = 4
"""A semismooth Newton whose line search finds no decrease of the residual (30 halvings
of the step) this many iterations in a row stops there: along its directions the
residual's norm does not fall, at a kink of the law it cannot cross or at a local minimum
of that norm (as beyond the limit of equilibrium, where no answer exists), and the next
start or fallback takes over. Measured: converging Newtons met at most two such
iterations in a row (the default tests, the slow 3D, wedge and planted-solution tests, the
FCLIB set); the yield search of a Tet4 block on an intact joint on a 20° plane (31 pairs,
80 static analyses, 26 without equilibrium) took 16.7 s CPU instead of 22.4."""


LINE_SEARCH_CRAWL = 10
"""A semismooth Newton whose line search accepts steps shorter than
:data:`CRAWL_STEP` this many iterations in a row stops there, as one that finds no descent
(:data:`LINE_SEARCH_FAILS`): it crawls along the kinks of the law, a sliver of a step at a
time, and does not reach an answer that way. Measured on the Newtons of the interface,
planted-solution, wedge, FCLIB and yield tests, the slow planted, wedge, 3D-solver and
verification tests, and a new user's yield search with uplift (2,485 Newtons): a
converging Newton (2,070) took at most 7 such steps in a row; 200 of the 415 that failed
crawled 10 in a row, and stopping them there saves 30 to 44 % of the Newton iterations
of the test sets where Newtons fail (that yield search, 34
static analyses, 69 of its 74 Newtons failing: 8.9 → 3.1 s, the same k_y)."""

CRAWL_STEP = 2.0**-10
"""The step of the Newton's line search below which an iteration crawls
(:data:`LINE_SEARCH_CRAWL`)."""


def _stalled(history: list[float]) -> bool:
    """Whether a Newton's residual norms ``history`` (one per iteration) have not halved
    over the last :data:`NEWTON_STALL` iterations."""
    return len(history) > NEWTON_STALL and history[-1] > 0.5 * history[-1 - NEWTON_STALL]


#: bytes at most in one solver's cache of factorised state systems (one per pattern of
#: pair states met): a pattern costs an M × M factor (M = pairs × d), so a count alone
#: lets the caches of a step's solvers grow with M² (4.7 GB at M = 753 in 3D, measured);
#: the least recently used factors go first
FACTOR_CACHE_BYTES = 16 * 2**20
#: factors at most in one solver's cache, whatever their size
FACTOR_CACHE_COUNT = 64


def _nbytes(value: object) -> int:
    """The memory of a cached factor: its arrays (a SuperLU object by its nonzeros)."""
    if isinstance(value, np.ndarray):
        return int(value.nbytes)
    if isinstance(value, tuple):
        return sum(_nbytes(v) for v in value)
    nnz = getattr(value, "nnz", None)
    return 12 * int(nnz) if nnz is not None else 0


class FactorCache:
    """Factorised state systems by key (the pattern of pair states), least recently
    used first out beyond :data:`FACTOR_CACHE_BYTES` or :data:`FACTOR_CACHE_COUNT`
    entries. A hit returns the factor of the same matrix, so the cache changes the time
    of a solve, never its bits."""

    def __init__(self, max_bytes: int = FACTOR_CACHE_BYTES,
                 max_count: int = FACTOR_CACHE_COUNT) -> None:  # fmt: skip
        self.max_bytes, self.max_count = max_bytes, max_count
        self._items: OrderedDict[bytes, tuple[tuple[object, ...], int]] = OrderedDict()
        self.nbytes = 0

    def get(self, key: bytes) -> tuple[object, ...] | None:
        hit = self._items.get(key)
        if hit is None:
            return None
        self._items.move_to_end(key)
        return hit[0]

    def __setitem__(self, key: bytes, value: tuple[object, ...]) -> None:
        size = _nbytes(value)
        old = self._items.pop(key, None)
        if old is not None:
            self.nbytes -= old[1]
        self._items[key] = (value, size)
        self.nbytes += size
        while len(self._items) > 1 and (self.nbytes > self.max_bytes
                                        or len(self._items) > self.max_count):  # fmt: skip
            _, (_, gone) = self._items.popitem(last=False)
            self.nbytes -= gone

    def __len__(self) -> int:
        return len(self._items)

    def clear(self) -> None:
        self._items.clear()
        self.nbytes = 0


def _lu_factor(a: FloatArray) -> tuple[FloatArray, np.ndarray]:
    """LAPACK's getrf, as :func:`scipy.linalg.lu_factor` calls it (the same bits), without
    its per-call wrappers (the state systems are small and many)."""
    if not a.size:
        return sla.lu_factor(a, check_finite=False)
    lu, piv, info = _getrf(a)
    if info < 0:
        raise ValueError(f"illegal value in {-info}th argument of internal getrf (lu_factor)")
    if info > 0:
        warnings.warn(f"Diagonal number {info} is exactly zero. Singular matrix.",
                      sla.LinAlgWarning, stacklevel=2)  # fmt: skip
    return lu, piv


def _lu_solve(lu: tuple[FloatArray, np.ndarray], b: FloatArray) -> FloatArray:
    """LAPACK's getrs, as :func:`scipy.linalg.lu_solve` calls it (the same bits); ``b``
    is overwritten."""
    if not b.size:
        return sla.lu_solve(lu, b, check_finite=False)
    x, info = _getrs(lu[0], lu[1], b, overwrite_b=True)
    if info != 0:
        raise ValueError(f"illegal value in {-info}th argument of internal gesv|posv")
    return x


def _cap_solve(f: tuple[FloatArray, np.ndarray] | MixedLU, b: FloatArray) -> FloatArray:
    """The solution of a capacitance system (:meth:`InterfaceSolver._capacitance`) for
    ``b`` (which the LU path overwrites); a singular system found by a
    :class:`~pfeie.linalg.MixedLU` raises :class:`MechanismError`, as the state systems
    do."""
    if not isinstance(f, MixedLU):
        return _lu_solve(f, b)
    try:
        return f.solve(b)
    except np.linalg.LinAlgError as exc:
        raise MechanismError(_SINGULAR) from exc


def _rownorm(a: FloatArray) -> FloatArray:
    """The Euclidean norm of each row of ``a`` (what ``np.linalg.norm(a, axis=1)``
    computes, to the bit, without its argument handling)."""
    return np.sqrt(np.add.reduce(a * a, axis=1))


def _rownorm_scaled(a: FloatArray) -> FloatArray:
    """:func:`_rownorm` without overflow or underflow of the squares: each row scaled by
    its largest entry first (for the residual of a problem whose forces lie beyond
    1e±100, where X·X would leave the double range and fool the residual)."""
    amax = np.abs(a).max(axis=1, initial=0.0)
    unit = a / np.where(amax > 0.0, amax, 1.0)[:, None]
    return amax * np.sqrt(np.add.reduce(unit * unit, axis=1))


#: the force scales between which the residual squares forces directly (beyond, its row
#: norms are scaled first: see _rownorm_scaled)
SAFE_SCALE = (1e-100, 1e100)


@dataclass
class SolveInfo:
    """How a step's interface problem was solved."""

    iterations: int
    residual: float
    method: str


class InterfaceSolver:
    """Solves the interface problem for a fixed Delassus operator W (see module doc).

    Parameters
    ----------
    W: Delassus operator (M, M), N → m.
    laws: the joint laws of the pairs.
    border: optional E (M, r) for statics with floating blocks.
    settings: tolerance and iteration limit (:class:`SolverSettings`).
    regularize: relative compliance added to W for redundant constraints.
    reference: a solver of a nearby W of the same size whose W_c⁻¹ is kept: the state
        systems are solved on it by iterative refinement (see the module docstring)
        instead of a factorisation of this W_c; ignored (this W_c is factorised) when the
        reference has no W_c⁻¹, or with a border, a regularisation or a sparse W.
    hint: what the message of a problem that does not converge advises (a time step, in
        dynamics; statics pass "").
    """

    def __init__(
        self,
        W: FloatArray,
        laws: PairLaws,
        *,
        border: FloatArray | None = None,
        settings: SolverSettings | None = None,
        regularize: float = 0.0,
        reference: InterfaceSolver | None = None,
        hint: str = "Try a smaller time step.",
    ) -> None:
        self.hint = hint
        settings = SolverSettings() if settings is None else settings
        props = laws
        self.props = laws
        self.m = props.n
        self.d = props.compliance.shape[1] if props.n else 1
        self.W = np.asarray(W, dtype=float)
        size = self.m * (self.d if self.m else 0)
        if self.W.shape != (size, size):
            raise ModelError(f"InterfaceSolver: W has shape {self.W.shape}; the laws have "
                             f"{self.m} pair(s) of {self.d} component(s): expected "
                             f"({size}, {size})")  # fmt: skip
        diag = np.diag(self.W)
        self.rho = 1.0 / float(diag.mean()) if diag.size else 1.0
        reg = regularize * float(diag.mean()) if diag.size else 0.0
        self.Wc = self.W + np.diag(props.compliance.ravel() + reg)
        # components prescribed on both sides (e.g. a pair on a fixed boundary) cannot
        # move: a unit compliance keeps the system regular and their force at zero
        dead = diag <= 1e-12 * float(diag.max(initial=0.0))
        if dead.any():
            self.Wc[np.flatnonzero(dead), np.flatnonzero(dead)] += float(diag[~dead].mean())
            log.info("%d pair component(s) are prescribed on both sides", int(dead.sum()))
        # the border is scaled to the size of W so that the LU pivots are comparable
        self._escale = float(diag.mean()) if diag.size else 1.0
        self.E = None if border is None else np.asarray(border, dtype=float) * self._escale
        self.tol, self.max_iter = settings.tolerance, settings.max_iter
        self._gapv = np.zeros((self.m, self.d))
        if self.m:
            self._gapv[:, -1] = props.gap
        self._cache = FactorCache()
        self._patterns: dict[bytes, tuple[np.ndarray, ...]] = {}
        self.last = SolveInfo(0, 0.0, "none")
        self._fixed = np.zeros(self.m, dtype=bool)
        self._inactive = np.zeros(self.m, dtype=bool)
        self._breaking = True
        self._continuing = False  # within a load continuation (see _continuation)
        self._debonded = np.zeros(self.m, dtype=bool)  # (see _parting)
        self._all_broken: np.ndarray | None = None
        self._wref: FloatArray | None = None
        self._wscale = 0.0
        self._eye: FloatArray | None = None
        self._gathered: tuple[bytes, FloatArray, FloatArray] | None = None
        self._work = Workspace()
        # dynamics without redundant constraints: W_c⁻¹ once, then each state pattern costs
        # a k × k capacitance system, k = open + sliding-tangential components (Woodbury)
        self._winv: FloatArray | None = None
        # a large and sparse W (many blocks, each with few pairs: granular media) is kept
        # sparse: sparse LU for the state systems and the robust fallback, no inverse
        M = self.Wc.shape[0]
        self._sparse: sp.csr_array | None = None
        if border is None and M >= SPARSE_MIN and np.count_nonzero(self.Wc) <= SPARSE_FILL * M * M:
            self._sparse = sp.csr_array(self.Wc)
            self._cdiag = np.diag(self.Wc) - diag
            log.info("W is sparse (%d × %d, %d nonzeros)", M, M, self._sparse.nnz)
        self.factorizations = 0  # of W_c by this solver (one, or none on a reference)
        self.contraction = 0.0  # the largest first contraction of its refinements
        self.refined = False  # whether the state systems are refined on a reference W_c⁻¹
        if (border is not None and self.d == 3 and M >= NEWTON_WOODBURY_MIN
                and self._sparse is None):  # fmt: skip
            # a large 3D problem with a border (statics with floating blocks): W_c⁻¹ once,
            # each state pattern a capacitance system plus an r × r border system
            self._invert(diag)
        elif border is None and regularize == 0.0 and self.m and self._sparse is None:
            if (reference is not None and reference._winv is not None
                    and reference._winv.shape == self.Wc.shape):  # fmt: skip
                self._winv, self.refined = reference._winv, True
                # the capacitance factors depend on W_c⁻¹ and the pattern only: shared
                self._cache = reference._cache
            else:
                self._invert(diag)

    #: the operators of a solver, never written once it is built: W, W_c, W_c⁻¹, the
    #: sparse W_c and the border E (a new W_c is a new array, :meth:`_invert`)
    _OPERATORS = frozenset({"W", "Wc", "_winv", "_sparse", "E"})

    def __deepcopy__(self, memo: dict[int, object]) -> InterfaceSolver:
        """A copy for another run beside this one (:meth:`pfeie.Dynamic.twin`): the
        operators (:data:`_OPERATORS`) shared, their arrays made read-only (a write
        would fail rather than reach the other run); the rest (the last solve's state,
        the capacitance caches, the work arrays) copied."""
        new = object.__new__(type(self))
        memo[id(self)] = new
        for key, value in self.__dict__.items():
            if key in self._OPERATORS:
                if isinstance(value, np.ndarray):
                    value.flags.writeable = False
                new.__dict__[key] = value
            else:
                new.__dict__[key] = copy.deepcopy(value, memo)
        return new

    def _invert(self, diag: FloatArray) -> None:
        """W_c⁻¹ from a Cholesky factorisation of W_c (shifted when W is singular)."""
        try:
            cf = sla.cho_factor(self.Wc, check_finite=False)
        except (np.linalg.LinAlgError, sla.LinAlgError):
            # redundant pairs (more constraints than the blocks' motions they tie, as
            # in FCLIB's stacked boxes): W is singular, the forces are not unique but
            # the relative motions are. A proximal shift ε I with ε = 1e-12 of the
            # mean diagonal picks one answer; it moves the relative motions by ε X,
            # far below the solver's tolerance
            eps = 1e-12 * float(diag.mean())
            self.Wc = self.Wc + eps * np.eye(self.Wc.shape[0])
            log.info("W is singular (redundant pairs): shifted by %.1e", eps)
            try:
                cf = sla.cho_factor(self.Wc, check_finite=False)
            except (np.linalg.LinAlgError, sla.LinAlgError):
                cf = None
        self._gathered = None  # blocks of an earlier W_c⁻¹
        if cf is not None:
            # the identity is overwritten by the inverse (one M × M array less at the peak)
            self._winv = sla.cho_solve(cf, np.eye(self.Wc.shape[0]), overwrite_b=True,
                                       check_finite=False)  # fmt: skip
            self.factorizations += 1

    @property
    def _vectorised_newton(self) -> bool:
        """Whether the semismooth Newton runs through the stored W_c⁻¹ with its Jacobian
        kept per pair (:meth:`_newton_woodbury`): 3D, at least
        :data:`NEWTON_WOODBURY_MIN` components, W_c inverted by this solver (with or
        without a border). It then takes over from the state iteration as soon as a
        slip direction turns."""
        return (self.d == 3 and self._winv is not None and not self.refined
                and self.m * self.d >= NEWTON_WOODBURY_MIN)  # fmt: skip

    @property
    def woodbury(self) -> bool:
        """Whether W_c was inverted once (each state pattern is then a capacitance system
        of its open and sliding components)."""
        return self._winv is not None

    def with_laws(self, laws: PairLaws) -> InterfaceSolver:
        """This solver (W, its factorisation, settings) for other laws with the same joint
        compliance, without factorising W again."""
        if not np.array_equal(laws.compliance, self.props.compliance):
            raise ModelError("with_laws needs the same joint compliance (the same pairs and "
                             "springs): W_c = W + C is factorised with it")  # fmt: skip
        other = copy.copy(self)
        other.props = laws
        # on a reference W_c⁻¹ the capacitance factors (W_c⁻¹ and the pattern only) are
        # shared with the reference's other solvers
        other._cache = self._cache if self.refined else FactorCache()
        other._gapv = np.zeros_like(self._gapv)
        if other.m:
            other._gapv[:, -1] = laws.gap
        other.last = SolveInfo(0, 0.0, "none")
        return other

    # -- reduced linear system for given states ---------------------------------------------
    def _pattern(self, state: np.ndarray) -> tuple[np.ndarray, ...]:
        """The index arrays of a state pattern (cached): the components ``flat`` (0 kin, 1
        zero, 2 friction), ``kin``, ``fr`` (sliding tangential), their pairs, the column of
        each sliding pair's normal among ``kin``, the rows of the capacitance system
        (open and sliding components) with the position of ``fr`` among them and the
        normal component of each sliding pair, the open components, the sliding pairs,
        and the key prefix of the state systems."""
        skey = state.tobytes()
        hit = self._patterns.get(skey)
        if hit is not None:
            return hit
        m, d = self.m, self.d
        comp = np.zeros((m, d), dtype=np.int8)  # 0 kin, 1 zero, 2 friction
        comp[state == OPEN] = 1
        sl = state == SLIDE
        comp[sl, :-1] = 2
        flat = comp.ravel()
        kin = np.flatnonzero(flat == 0)
        fr = np.flatnonzero(flat == 2)
        pair_fr = fr // d
        pos = np.full(m * d, -1)
        pos[kin] = np.arange(kin.size)
        ncol = pos[pair_fr * d + d - 1]
        oth = np.flatnonzero(flat != 0)
        rows_fr = np.searchsorted(oth, fr)
        nidx = pair_fr * d + d - 1
        zero = flat == 1
        prefix = np.frombuffer(kin.tobytes() + ncol.tobytes(), dtype=np.uint8)
        out = (flat, kin, fr, pair_fr, ncol, oth, rows_fr, nidx, zero, sl, prefix)
        if len(self._patterns) >= 256:
            self._patterns.clear()
        self._patterns[skey] = out
        return out

    # -- reduced linear system for given states ---------------------------------------------
    def _linear(
        self, st: PairState, prev: PairState, w_free: FloatArray, e: FloatArray | None
    ) -> tuple[FloatArray, FloatArray]:
        m, d = self.m, self.d
        state = st.state
        c, mu, t = self.props.strength(st.broken, prev.path)
        ramp, c_l, mu_l = cohesion_ramp_tangent(c, mu, t, st.X[:, -1], st.broken)
        if ramp.any():  # on the cohesion ramp at the last iterate: its tangent there
            c = np.where(ramp, c_l, c)
            mu = np.where(ramp, mu_l, mu)
        _, kin, fr, pair_fr, ncol, oth, rows_fr, nidx, zero, sl, prefix = self._pattern(state)
        target = prev.s.copy()
        closed_broken = st.broken | (state != INTACT)
        target[closed_broken, -1] = 0.0
        tdir = st.slip_dir[sl].ravel() if d > 1 else np.zeros(0)
        coef = -mu[pair_fr] * tdir  # X_t = coef · X_n + x0
        x0 = -c[pair_fr] * tdir
        key = prefix.tobytes() + np.round(coef, 14).tobytes()
        if self.E is not None and self._winv is not None:
            return self._woodbury_bordered(key, fr, coef, x0, target, w_free, oth, rows_fr,
                                           nidx, zero, e)  # fmt: skip
        if self.refined:
            Xr = self._refine(key, kin, fr, coef, x0, target, w_free, oth, rows_fr, nidx)
            if Xr is not None:
                Xr.reshape(-1)[zero] = 0.0
                return Xr, np.zeros(0)
        if self._winv is not None:
            X = self._woodbury(key, kin, fr, coef, x0, target, w_free, oth, rows_fr, nidx)
            X.reshape(-1)[zero] = 0.0  # open: zero, not the round-off of the update
            return X, np.zeros(0)
        if self._sparse is not None:
            return self._linear_sparse(key, kin, fr, ncol, coef, x0, target, w_free, zero)
        r = 0 if self.E is None else self.E.shape[1]
        cached = self._cache.get(key)
        Wk = self.Wc[kin]
        if cached is None:
            A = Wk[:, kin].copy()
            if fr.size:
                np.add.at(A.T, ncol, (Wk[:, fr] * coef[None, :]).T)
            if r:
                assert self.E is not None
                Ek = self.E[kin].copy()
                if fr.size:
                    np.add.at(Ek, ncol, self.E[fr] * coef[:, None])
                A = np.block([[A, self.E[kin]], [Ek.T, np.zeros((r, r))]])
            if A.size == 0:
                lu = None
            else:
                with warnings.catch_warnings():  # a singular system is reported below
                    warnings.simplefilter("ignore", sla.LinAlgWarning)
                    lu = sla.lu_factor(A, check_finite=False)
                piv = np.abs(np.diag(lu[0]))
                if piv.min() <= 1e-15 * piv.max():
                    raise MechanismError(
                        "the interface system is singular: with the current pair states some "
                        "block is not restrained (a mechanism)"
                    )
            self._cache[key] = (lu,)
            cached = (lu,)
        (lu,) = cached
        rhs = target.ravel()[kin] - w_free.ravel()[kin]
        if fr.size:
            rhs -= Wk[:, fr] @ x0
        if r:
            assert self.E is not None and e is not None
            rhs = np.concatenate([rhs, self._escale * e - (self.E[fr].T @ x0 if fr.size else 0.0)])
        y = sla.lu_solve(lu, rhs, check_finite=False) if lu is not None else np.zeros(0)
        X = np.zeros(m * d)
        X[kin] = y[: kin.size]
        if fr.size:
            X[fr] = coef * X[kin[ncol]] + x0  # the normal component of each sliding pair
        q = y[kin.size :] * self._escale
        return X.reshape(m, d), q

    def _linear_sparse(
        self, key: bytes, kin: np.ndarray, fr: np.ndarray, ncol: np.ndarray,
        coef: FloatArray, x0: FloatArray, target: FloatArray, w_free: FloatArray,
        zero: np.ndarray,
    ) -> tuple[FloatArray, FloatArray]:  # fmt: skip
        """The state system of :meth:`_linear` with a sparse W: (W_kk + W_kf C) y = b,
        C (f × k) the sliding pairs' X_t = coef X_n, factorised by a sparse LU."""
        Ws = self._sparse
        assert Ws is not None
        Wk = Ws[kin]
        cached = self._cache.get(b"s" + key)
        if cached is None:
            A = sp.csc_array(Wk[:, kin])
            if fr.size:
                C = sp.csr_array((coef, (np.arange(fr.size), ncol)), shape=(fr.size, kin.size))
                A = sp.csc_array(A + Wk[:, fr] @ C)
            lu = None
            if kin.size:
                try:
                    with warnings.catch_warnings():
                        warnings.simplefilter("ignore", spla.MatrixRankWarning)
                        lu = spla.splu(A)
                except RuntimeError as exc:
                    raise MechanismError(
                        "the interface system is singular: with the current pair states some "
                        "block is not restrained (a mechanism)"
                    ) from exc
            self._cache[b"s" + key] = (lu,)
            cached = (lu,)
        lu = cached[0]
        rhs = target.ravel()[kin] - w_free.ravel()[kin]
        if fr.size:
            rhs -= Wk[:, fr] @ x0
        X = np.zeros(self.m * self.d)
        if isinstance(lu, spla.SuperLU):
            y = lu.solve(rhs)
            if not np.all(np.isfinite(y)):
                raise MechanismError("the interface system is singular (a mechanism)")
            X[kin] = y
        if fr.size:
            X[fr] = coef * X[kin[ncol]] + x0
        X[zero] = 0.0
        return X.reshape(self.m, self.d), np.zeros(0)

    def _woodbury(
        self, key: bytes, kin: np.ndarray, fr: np.ndarray, coef: FloatArray, x0: FloatArray,
        target: FloatArray, w_free: FloatArray, oth: np.ndarray, rows_fr: np.ndarray,
        nidx: np.ndarray,
    ) -> FloatArray:  # fmt: skip
        """The state system A X = b with A = W_c + U V (U V replaces the rows of the open
        and sliding-tangential components ``oth``): X = y − W_c⁻¹U Cap⁻¹ (C y − b_o),
        y = W_c⁻¹ b, Cap = C W_c⁻¹ U (the rows C: X_j = 0 or X_t − coef X_n = x₀)."""
        Winv = self._winv
        assert Winv is not None
        d = self.d
        b = target.ravel() - w_free.ravel()
        # the replaced rows take no part in y (any value would do): zero, not the forces
        # x₀ of their constraints, which W_c⁻¹ would blow up to be cancelled in the
        # correction (relative errors of 1e-5 with a residual cohesion)
        b[oth] = 0.0
        y = symmetric_product(Winv, b)
        if oth.size == 0:
            return y.reshape(self.m, d)
        Wo = self._columns(Winv, oth)
        lu = self._capacitance(key, Winv, Wo, oth, fr, coef, rows_fr, nidx)
        cy = y[oth]
        if fr.size:
            cy[rows_fr] -= coef * y[nidx]
            cy[rows_fr] -= x0  # the constraints' right-hand side b_o
        corr = _cap_solve(lu, cy)
        return (y - Wo @ corr).reshape(self.m, d)

    def _woodbury_bordered(
        self, key: bytes, fr: np.ndarray, coef: FloatArray, x0: FloatArray, target: FloatArray,
        w_free: FloatArray, oth: np.ndarray, rows_fr: np.ndarray, nidx: np.ndarray,
        zero: np.ndarray, e: FloatArray | None,
    ) -> tuple[FloatArray, FloatArray]:  # fmt: skip
        """The state system with the border (statics, :meth:`_linear`) through W_c⁻¹: the
        rows ``kin`` W_c X + E q = b, the constraints C X = b_o in the rows ``oth`` and the
        equilibrium Eᵀ X = e. With S the Woodbury solve of :meth:`_woodbury` (affine in
        b, the constraints' x₀ in it), X₀ = S(b) and T = S(E) − S(0) (M × r, r border
        columns, one product W_c⁻¹ [b, E]):

            X = X₀ − T q,   (Eᵀ T) q = Eᵀ X₀ − e   (r × r),

        instead of an LU of the (M + r)-square bordered system per pattern. A singular
        Eᵀ T (a floating block that its pairs do not hold) raises :class:`MechanismError`."""
        Winv, E = self._winv, self.E
        assert Winv is not None and E is not None and e is not None
        B = np.column_stack([target.ravel() - w_free.ravel(), E])
        B[oth] = 0.0  # the replaced rows take no part (as in :meth:`_woodbury`)
        Y = symmetric_product(Winv, B)
        if oth.size:
            Wo = self._columns(Winv, oth, small="rows")
            lu = self._capacitance(key, Winv, Wo, oth, fr, coef, rows_fr, nidx)
            cy = Y[oth]
            if fr.size:
                cy[rows_fr] -= coef[:, None] * Y[nidx]
                cy[rows_fr, 0] -= x0
            Y -= Wo @ _cap_solve(lu, cy)
        Y[zero] = 0.0  # open: zero, not the round-off of the update
        X0, T = Y[:, 0], Y[:, 1:]
        S = E.T @ T
        with warnings.catch_warnings():  # a singular system is reported below
            warnings.simplefilter("ignore", sla.LinAlgWarning)
            luS = sla.lu_factor(S, check_finite=False)
        piv = np.abs(np.diag(luS[0]))
        if piv.min(initial=np.inf) <= 1e-15 * piv.max(initial=0.0):
            raise MechanismError(
                "the interface system is singular: with the current pair states some "
                "block is not restrained (a mechanism)"
            )
        qs = sla.lu_solve(luS, E.T @ X0 - self._escale * e, check_finite=False)
        return (X0 - T @ qs).reshape(self.m, self.d), qs * self._escale

    def _columns(self, Winv: FloatArray, oth: np.ndarray, small: str = "columns") -> FloatArray:
        """The columns ``oth`` of W_c⁻¹ (:func:`~pfeie.linalg.symmetric_columns`); for
        :data:`LARGE_CAPACITANCE` columns or more of a Fortran-ordered W_c⁻¹ of
        :data:`~pfeie.linalg.SYMMETRIC_MIN` rows or more, the same entries gathered into a
        work array (Fortran-ordered, valid until the next call): M × k entries,
        hundreds of MB at a few thousand open and sliding components."""
        M = Winv.shape[0]
        if M < SYMMETRIC_MIN or oth.size < LARGE_CAPACITANCE or not Winv.flags.f_contiguous:
            return symmetric_columns(Winv, oth, small=small)
        # the rows oth of the C-ordered Winvᵀ (whole rows, contiguous), transposed
        out = self._work.get("columns of the state system", (oth.size, M))
        return np.take(Winv.T, oth, axis=0, out=out, mode="clip").T

    def _capacitance(
        self, key: bytes, Winv: FloatArray, Wo: FloatArray, oth: np.ndarray, fr: np.ndarray,
        coef: FloatArray, rows_fr: np.ndarray, nidx: np.ndarray,
    ) -> tuple[FloatArray, np.ndarray] | MixedLU:  # fmt: skip
        """The factors of the capacitance system C W_c⁻¹ Cᵀ of the replaced rows ``oth``
        (their constraints C: X_j = 0, or X_t − coef X_n for the sliding rows ``rows_fr``
        of normals ``nidx``; solved by :func:`_cap_solve`). ``Wo``: the columns ``oth``
        of W_c⁻¹ (:func:`~pfeie.linalg.symmetric_columns`), which the caller gathered for
        its correction.

        LU factors cached by the pattern ``key`` (they depend on W_c⁻¹, the pattern and
        coef only; a refined solver shares its reference's); but from
        :data:`LARGE_CAPACITANCE` rows in a W_c⁻¹ of :data:`~pfeie.linalg.SYMMETRIC_MIN`
        rows or more, where the patterns seldom repeat (3 cache hits in 610 systems of
        ``benchmarks/interfaces3d.py``), the system is assembled in a work array, valid
        until the next system: its transpose gathered from the rows of Woᵀ (the
        contiguous axis), the sliding rows last (their correction a slice), factorised by
        :class:`~pfeie.linalg.MixedLU`."""
        if (Winv.shape[0] >= SYMMETRIC_MIN and oth.size >= LARGE_CAPACITANCE
                and Wo.flags.f_contiguous):  # fmt: skip
            k, nf = oth.size, fr.size
            WoT = Wo.T
            perm = np.r_[np.setdiff1d(np.arange(k), rows_fr, assume_unique=True), rows_fr]
            capT = self._work.get("state", (k, k))
            np.take(WoT, oth[perm], axis=1, out=capT, mode="clip")
            if nf:
                corr = np.take(WoT, nidx, axis=1, out=self._work.get("scaled", (k, nf)),
                               mode="clip")  # fmt: skip
                corr *= coef[None, :]
                capT[:, k - nf :] -= corr
            try:
                return MixedLU(capT.T, self._work, "state single", perm)
            except np.linalg.LinAlgError as exc:
                raise MechanismError(_SINGULAR) from exc
        cached = self._cache.get(b"w" + key)
        if cached is not None:
            return cast("tuple[FloatArray, np.ndarray]", cached[0])
        cap = Winv[np.ix_(oth, oth)]
        if fr.size:
            cap[rows_fr] -= coef[:, None] * Winv[np.ix_(nidx, oth)]
        lu = _lu_factor(cap)
        self._cache[b"w" + key] = (lu,)
        return lu

    def _refine(
        self, key: bytes, kin: np.ndarray, fr: np.ndarray, coef: FloatArray, x0: FloatArray,
        target: FloatArray, w_free: FloatArray, oth: np.ndarray, rows_fr: np.ndarray,
        nidx: np.ndarray,
    ) -> FloatArray | None:  # fmt: skip
        """The state system of :meth:`_woodbury` on the reference W_c⁻¹ by iterative
        refinement (module docstring): X_{j+1} = X_j + A_ref⁻¹ (b − A X_j), with A this
        W_c in the rows ``kin`` and the constraints C X = b_o (X_j = 0, X_t − coef X_n =
        x₀) in the rows ``oth``, A_ref⁻¹ the Woodbury solve of :meth:`_woodbury` on the
        reference. Until round-off (:data:`REFINE_TOL`); when it stops contracting, W_c is
        factorised (None is returned: the caller solves on the new inverse)."""
        Winv = self._winv
        assert Winv is not None
        b = target.ravel() - w_free.ravel()
        b[oth] = 0.0
        bo = np.zeros(oth.size)
        if fr.size:
            bo[rows_fr] = x0
        lu: tuple[FloatArray, np.ndarray] | MixedLU | None = None
        Wo = self._columns(Winv, oth)
        if oth.size:
            lu = self._capacitance(key, Winv, Wo, oth, fr, coef, rows_fr, nidx)

        def constraints(X: FloatArray) -> FloatArray:
            cx = X[oth]
            if fr.size:
                cx[rows_fr] -= coef * X[nidx]
            return cx

        def ref_solve(r: FloatArray, ro: FloatArray) -> FloatArray:
            """A_ref⁻¹ (r, ro): r on the rows ``kin`` (zero in ``oth``), ro the constraints'."""
            y = symmetric_product(Winv, r)
            if lu is None:
                return np.asarray(y)
            return np.asarray(y - Wo @ _cap_solve(lu, constraints(y) - ro))

        X = ref_solve(b, bo)
        last = 0.0
        for it in range(REFINE_MAX_ITER):
            r = b - symmetric_product(self.Wc, X)
            r[oth] = 0.0
            dX = ref_solve(r, bo - constraints(X))
            X += dX
            nX, nd = float(np.abs(X).max(initial=0.0)), float(np.abs(dX).max(initial=0.0))
            if nd <= REFINE_TOL * nX:
                return X.reshape(self.m, self.d)
            q = nd / (last if it else nX)
            if not it:
                self.contraction = max(self.contraction, q)
            if q > REFINE_MAX_CONTRACTION:
                if it and nd <= REFINE_FLOOR * nX:  # round-off: the residual's floor
                    return X.reshape(self.m, self.d)
                break
            if it and nd * q / (1.0 - q) <= REFINE_TOL * nX:
                return X.reshape(self.m, self.d)
            last = nd
        if q > REFINE_MAX_CONTRACTION:
            log.debug("refinement on the reference W_c⁻¹ stopped contracting (q = %.2e): "
                      "W_c factorised", q)  # fmt: skip
        else:
            log.debug("refinement on the reference W_c⁻¹ not at round-off after %d "
                      "corrections (q = %.2e): W_c factorised", REFINE_MAX_ITER, q)  # fmt: skip
        self._refactorize()
        return None

    def _refactorize(self) -> None:
        """Leave the reference: factorise this W_c (a new capacitance cache with it)."""
        self.refined, self.contraction = False, 0.0
        self._cache = FactorCache()
        self._winv = None
        self._invert(np.diag(self.W))

    @property
    def cache_bytes(self) -> int:
        """The memory of the factorised state systems kept (bytes)."""
        return self._cache.nbytes

    def relative(self, X: FloatArray, q: FloatArray, w_free: FloatArray) -> FloatArray:
        """w = w_free + W X (+ E q)."""
        if self._sparse is not None:  # the same W (no compliance: W_c − W is diagonal)
            return (w_free.ravel() + self._sparse @ X.ravel()
                    - self._cdiag * X.ravel()).reshape(self.m, self.d)  # fmt: skip
        w = w_free.ravel() + symmetric_product(self.W, X.ravel())
        if self.E is not None and q.size:
            w = w + self.E @ (q / self._escale)
        return w.reshape(self.m, self.d)

    # -- the law ------------------------------------------------------------------------------
    def _scale(self, X: FloatArray, w_free: FloatArray) -> float:
        if w_free is self._wref:  # the problem being solved: its scale is known
            ws = self._wscale
        else:
            ws = self.rho * float(np.abs(w_free).max(initial=0.0))
        return max(float(np.abs(X).max(initial=0.0)), ws, 1e-300)

    def _update(self, st: PairState, prev: PairState, fscale: float) -> PairState:
        """New states from a solution (X, s) under the current states. The new state
        shares X, w, s and path with ``st`` (the iteration replaces them) and, when they
        do not change, its broken flags and slip directions."""
        X, s = st.X, st.s
        Xn, Xt = X[:, -1], X[:, :-1]
        nt = _rownorm(Xt)
        tolF = 1e-10 * fscale
        tolD = tolF / self.rho
        c, mu, t = self.props.strength(st.broken, prev.path)
        tau = cone(c, mu, t, Xn, st.broken)[0]
        state = st.state
        new_state = state.copy()
        broken, sdir = st.broken, st.slip_dir
        # intact → broken
        if self._breaking:
            it = state == INTACT
            ten = it & (Xn < -t - tolF)
            she = it & ~ten & (nt > tau + tolF)
            if ten.any() or she.any():
                broken = broken | ten | she
                new_state[ten] = OPEN
                new_state[she] = SLIDE
                sdir = sdir.copy()
                sdir[she] = -Xt[she] / nt[she, None]
        # the residual cone: a broken pair's own, and that of an intact pair breaking now
        cr, mur, t_r = self._residual_strength(prev.path)
        assert self._all_broken is not None
        tau_r = cone(cr, mur, t_r, Xn, self._all_broken)[0]
        # stick
        sk = state == STICK
        op = sk & (Xn < -t_r - tolF)
        sd = sk & ~op & (nt > tau_r + tolF)
        new_state[op] = OPEN
        if sd.any():
            new_state[sd] = SLIDE
            sdir = sdir.copy() if sdir is st.slip_dir else sdir
            sdir[sd] = -Xt[sd] / nt[sd, None]
        # slide
        sl = state == SLIDE
        if sl.any():
            ds = s[:, :-1] - prev.s[:, :-1]
            op = sl & (Xn < -t_r - tolF)
            proj = np.einsum("mj,mj->m", ds, st.slip_dir)
            fixed = self._fixed
            back = sl & ~op & (proj < -tolD) & ~fixed
            new_state[op] = OPEN
            new_state[back] = STICK
            if self.d == 3:
                nds = _rownorm(ds)
                upd = sl & ~op & ~back & (nds > tolD) & ~fixed
                if upd.any():
                    sdir = sdir.copy() if sdir is st.slip_dir else sdir
                    # halfway between the last direction and that of the slip increment
                    # (the plain update flips the directions of neighbouring pairs back
                    # and forth; the fixed point is the same)
                    h = st.slip_dir[upd] + ds[upd] / nds[upd, None]
                    sdir[upd] = h / _rownorm(h)[:, None]
        # open
        cl = (state == OPEN) & (s[:, -1] < -tolD) & ~self._inactive
        if cl.any():
            new_state[cl] = np.where(self._fixed[cl], SLIDE, STICK)
        return PairState(new_state, broken, st.X, st.w, st.s, sdir, st.path)

    def _residual_strength(self, path: FloatArray) -> tuple[FloatArray, ...]:
        """(c A, μ, σ_t A) of every pair once broken, for the slip paths ``path``."""
        if self._all_broken is None:
            self._all_broken = np.ones(self.m, dtype=bool)
        return self.props.strength(self._all_broken, path)

    def residual(self, st: PairState, prev: PairState, w_free: FloatArray) -> FloatArray:
        """Scaled complementarity residual per pair (see module doc)."""
        X, s = st.X, st.s
        fscale = self._scale(X, w_free)
        norm = _rownorm if SAFE_SCALE[0] <= fscale <= SAFE_SCALE[1] else _rownorm_scaled
        rho = self.rho
        c, mu, t = self.props.strength(st.broken, prev.path)
        Xn, Xt = X[:, -1], X[:, :-1]
        tau = cone(c, mu, t, Xn, st.broken)[0]
        ds = s - prev.s
        r = np.zeros(self.m)
        state = st.state
        it = state == INTACT
        any_it = bool(it.any())
        if any_it:
            r[it] = rho * norm(ds[it])
            if self._breaking:
                r[it] += np.maximum(0.0, -(Xn[it] + t[it])) + np.maximum(
                    0.0, norm(Xt[it]) - tau[it]
                )
        op = state == OPEN
        any_op = bool(op.any())
        if any_op:
            r[op] = np.maximum(0.0, -rho * s[op, -1]) + norm(X[op])
        cl = ~it & ~op if any_it or any_op else np.ones(self.m, dtype=bool)
        z = Xt[cl] - rho * ds[cl, :-1]
        nz = norm(z)
        proj = z * np.minimum(1.0, tau[cl] / np.maximum(nz, 1e-300))[:, None]
        fx = cl & self._fixed
        if fx.any():
            proj[fx[cl]] = -tau[fx, None] * st.slip_dir[fx]  # sliding along the given ŝ
        r[cl] = norm(Xt[cl] - proj) + rho * np.abs(s[cl, -1])
        r[cl] += np.maximum(0.0, -(Xn[cl] + t[cl]))
        off = self._inactive
        if off.any():
            r[off] = norm(X[off])
        return r / fscale

    # -- driver -------------------------------------------------------------------------------
    def solve(
        self,
        w_free: FloatArray,
        prev: PairState,
        e: FloatArray | None = None,
        label: str = "",
        *,
        fixed: np.ndarray | None = None,
        breaking: bool = True,
        inactive: np.ndarray | None = None,
        start: PairState | None = None,
    ) -> tuple[PairState, FloatArray]:
        """Trial pair state for the step and the border unknowns q (empty without border).

        ``prev`` is the committed state at the start of the step; it is not modified.
        ``start``: the iteration's first iterate (states, forces and slip directions),
        ``prev`` by default: the answer to a nearby problem (a load step). The answer does
        not depend on it: its pairs that are broken but intact in ``prev`` start intact.
        ``fixed`` (m,) marks sliding pairs whose slip direction ``prev.slip_dir`` is held
        (they slide or open, never stick); with ``breaking=False`` intact pairs stay intact;
        ``inactive`` (m,) pairs are held open with X = 0 (see the module docstring).

        An iterate far from the answer (a Newton that diverges before a fallback takes
        over) may overflow: every answer is judged by the residual, which inf or NaN
        fails, so the floating-point warnings of the iterates are silenced here.
        """
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            return self._solve(w_free, prev, e, label, fixed=fixed, breaking=breaking,
                               inactive=inactive, start=start)  # fmt: skip

    def _prepare(
        self, w_free: FloatArray, prev: PairState, label: str, fixed: np.ndarray | None,
        breaking: bool, inactive: np.ndarray | None,
    ) -> FloatArray:  # fmt: skip
        """Set the solve's pair flags and scales; returns s_free (w_free plus the gaps),
        with which the internal routines work."""
        self._fixed = (np.zeros(self.m, dtype=bool) if fixed is None
                       else np.asarray(fixed, dtype=bool) & (prev.state == SLIDE))  # fmt: skip
        self._inactive = (np.zeros(self.m, dtype=bool) if inactive is None
                          else np.asarray(inactive, dtype=bool))  # fmt: skip
        self._fixed &= ~self._inactive
        self._breaking = bool(breaking)
        self._debonded = np.zeros(self.m, dtype=bool)  # (see _parting)
        w_free = w_free + self._gapv
        self._wref, self._wscale = w_free, self.rho * float(np.abs(w_free).max(initial=0.0))
        if not self._wscale <= SAFE_SCALE[1]:  # inf or NaN too: no iteration can help
            raise InterfaceError(
                f"{label}: the interface problem cannot be solved: its force scale, "
                f"ρ max|w_free| = {self._wscale:.1e} N, exceeds {SAFE_SCALE[1]:.0e} N, where "
                "the squares of the law leave double precision: check the units, or "
                "whether the motion diverged before this step.")  # fmt: skip
        return w_free

    def solve_bordered_proximal(
        self, w_free: FloatArray, prev: PairState, e: FloatArray, label: str = "",
        start: PairState | None = None,
    ) -> tuple[PairState, FloatArray]:  # fmt: skip
        """Statics with floating blocks (the border): the bordered proximal-point Newton
        (:func:`._proximal.proximal_newton`) alone, from ``start``'s forces (else from X =
        0); the fallback where :meth:`solve` meets singular systems and
        stalls near a hinge mechanism. The caller judges first that an equilibrium can
        exist (the rigid-block check, :class:`~pfeie.coupling.StaticInterfaceProblem`):
        where none does, the iterations stall at their caps. Returns the trial state and
        q; :class:`InterfaceError` where it does not reach the tolerance."""
        if self.E is None:
            raise InterfaceError(f"{label}: the bordered proximal Newton needs a border")
        size = self.Wc.shape[0] + self.E.shape[1]
        if size > BORDERED_PROXIMAL_MAX:
            raise InterfaceError(f"{label}: the bordered proximal Newton is not tried on "
                                 f"{size} unknowns (above {BORDERED_PROXIMAL_MAX})")  # fmt: skip
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            s_free = self._prepare(w_free, prev, label, None, True, None)
            if start is not None and np.all(np.isfinite(start.X)):
                first = start.copy()
                fresh = first.broken & ~prev.broken
                first.broken[fresh] = False
                first.state[fresh] = prev.state[fresh]
            else:
                first = prev.copy()
                first.X[:] = 0.0
            # one start (the limit searches call again from the cold start)
            st, n, q = self._proximal(first, prev, s_free, e,
                                      max_newton=BORDERED_PROXIMAL_NEWTON,
                                      max_stall=BORDERED_PROXIMAL_STALL)  # fmt: skip
            res = float(self.residual(st, prev, s_free).max(initial=0.0))
        if res <= self.tol and self._balanced(st.X, e, rows=True):
            self.last = SolveInfo(n, res, "bordered proximal Newton")
            log.debug("%s: solved by the bordered proximal Newton, residual %.2e", label, res)
            return st, q
        raise InterfaceError(f"{label}: the bordered proximal Newton reached a residual of "
                             f"{res:.1e} only (tolerance {self.tol:.0e})")  # fmt: skip

    def _solve(
        self,
        w_free: FloatArray,
        prev: PairState,
        e: FloatArray | None,
        label: str,
        *,
        fixed: np.ndarray | None,
        breaking: bool,
        inactive: np.ndarray | None,
        start: PairState | None,
    ) -> tuple[PairState, FloatArray]:
        w_free = self._prepare(w_free, prev, label, fixed, breaking, inactive)
        first = None if start is None else start.copy()
        if first is not None:  # breaking is the iteration's, from prev's flags
            fresh = first.broken & ~prev.broken
            first.broken[fresh] = False
            first.state[fresh] = prev.state[fresh]
        st = (prev if first is None else first).copy()
        reopen = (st.state == OPEN) & (w_free[:, -1] < 0)
        st.state[reopen] = STICK
        st.state[self._inactive] = OPEN
        seen: dict[bytes, int] = {}
        q = np.zeros(0)
        history: list[np.ndarray] = []
        turn: list[float] = []  # 3D: the largest change of a slip direction, per iteration
        s_known: FloatArray | None = None
        singular: MechanismError | None = None
        it = 0
        for it in range(1, self.max_iter + 1):
            xn_used = st.X[:, -1].copy()  # where _linear takes the cohesion ramp's tangent
            try:
                X, q = self._linear(st, prev, w_free, e)
            except MechanismError as exc:
                # a singular system for these states: redundant pairs, or (statics) a
                # floating block that these states leave free, e.g. every pair of its
                # joint sliding on a trial pattern near the limit of equilibrium; the
                # Newton below works on the whole law instead, and in statics the error
                # stands if it finds no equilibrium either
                singular = exc
                log.debug("%s: singular state system, to the Newton fallback", label)
                break
            st.X = X
            st.s = self.relative(X, q, w_free) + self.props.compliance * X
            s_known = st.s  # s of the iterate X (the Newton may start from it)
            st.w = st.s - self.props.compliance * X - self._gapv
            new = self._update(st, prev, self._scale(X, w_free))
            same = bool((new.state == st.state).all()) and (
                new.broken is st.broken or bool((new.broken == st.broken).all())
            )
            # the directions settled: as np.allclose(rtol=0, atol=1e-9), NaN never settled;
            # in 3D, where the directions converge linearly, the residual also judges an
            # iterate whose states settled while its directions still turn
            settled = same and bool((np.abs(new.slip_dir - st.slip_dir) <= 1e-9).all())
            # sliding pairs on the cohesion ramp's curve: the system took its tangent at
            # the last iterate, so they settle only when their normal force does (a
            # Newton iteration on the curve, which the states alone do not see)
            bend = (self._bending(st, prev, xn_used, self._scale(X, w_free)) if same
                    else np.zeros(self.m, dtype=bool))  # fmt: skip
            if settled or (same and self.d == 3):
                res = float(self.residual(st, prev, w_free).max(initial=0.0))
                if res <= self.tol:
                    self.last = SolveInfo(it, res, "state iteration")
                    return st, q
                if settled and not bend.any():
                    log.debug("%s: states settled but residual %.2e > tol", label, res)
                    break
            if self.d == 3:
                # the slip directions of 3D pairs follow their slip increments, a fixed
                # point that converges linearly or not at all (neighbouring pairs that
                # slide apart flip each other's direction): when the directions have not
                # halved their change over four iterations, the Newton takes over; the
                # Newton through W_c⁻¹ costs what a state iteration costs and converges
                # superlinearly: it takes over as soon as a direction turns
                turn.append(float(np.abs(new.slip_dir - st.slip_dir).max(initial=0.0)))
                if not turn[-1] <= 0.0 if self._vectorised_newton else (
                        it >= 8 and not turn[-1] <= 0.5 * turn[-5]):  # fmt: skip
                    log.debug("%s: slip directions do not settle after %d iterations",
                              label, it)  # fmt: skip
                    break
            key = new.state.tobytes() + new.broken.tobytes() + np.round(
                X[bend, -1], 12).tobytes()  # fmt: skip
            if self.d == 3:
                # the same resolution as the settle test above (1e-9), so that directions
                # still turning are not taken for a cycle
                key += np.round(new.slip_dir[new.state == SLIDE], 9).tobytes()
            history.append(new.state.copy())
            if key in seen:
                log.debug("%s: pair states cycle after %d iterations", label, it)
                break
            seen[key] = it
            new.X, new.w, new.s = st.X, st.w, st.s
            st = new
        if self._sparse is not None:
            # a large sparse W: no dense Newton; the sparse proximal Newton at once
            res_si = float(self.residual(st, prev, w_free).max(initial=0.0))
            return self._fallback(label, history, [(res_si, st)], prev, w_free, it)
        if PROXIMAL_FIRST_3D and self.d == 3 and self.E is None and not self._vectorised_newton:
            # 3D without the Newton through W_c⁻¹: the proximal Newton first, the dense
            # Newtons after it
            st6, n6, _ = self._proximal(st, prev, w_free)
            it += n6
            res6 = float(self.residual(st6, prev, w_free).max(initial=0.0))
            if res6 <= self.tol:
                self.last = SolveInfo(it, res6, SECOND_STAGE_PROXIMAL)
                log.debug("%s: solved by the proximal Newton, residual %.2e", label, res6)
                return st6, np.zeros(0)
        if self._vectorised_newton:
            try:
                st1, q1, n1 = self._newton_woodbury(st, q, prev, w_free, e, s0=s_known)
            except np.linalg.LinAlgError:
                log.debug("%s: singular Newton system through W_c⁻¹", label)
            else:
                it += n1
                res1 = float(self.residual(st1, prev, w_free).max(initial=0.0))
                if res1 <= self.tol and self._balanced(st1.X, e):
                    self.last = SolveInfo(it, res1, "semismooth Newton")
                    log.debug("%s: solved by semismooth Newton, residual %.2e", label, res1)
                    return st1, q1
        st2, q2, n_it = self._newton(st, q, prev, w_free, e)
        res = float(self.residual(st2, prev, w_free).max(initial=0.0))
        # statics: the law's residual does not see the floating blocks' equilibrium
        if res <= self.tol and self._balanced(st2.X, e):
            # after the Newton through W_c⁻¹ (its second stage here), the dense one is a
            # fallback
            method = "dense semismooth Newton" if self._vectorised_newton else (
                "semismooth Newton")  # fmt: skip
            self.last = SolveInfo(it + n_it, res, method)
            log.debug("%s: solved by semismooth Newton, residual %.2e", label, res)
            return st2, q2
        if first is not None:  # the given first iterate, the answer to a nearby problem
            st5, q5, n5 = self._newton(first, np.zeros_like(q), prev, w_free, e)
            n_it += n5
            res5 = float(self.residual(st5, prev, w_free).max(initial=0.0))
            if res5 <= self.tol and self._balanced(st5.X, e):
                self.last = SolveInfo(it + n_it, res5, "semismooth Newton (from the start)")
                return st5, q5
        # a cold start (X = 0, every closed pair sticking) where the last iterate failed
        cold = prev.copy()
        cold.X[:] = 0.0
        st4, q4, n4 = self._newton(cold, np.zeros_like(q), prev, w_free, e, stall=False)
        res4 = float(self.residual(st4, prev, w_free).max(initial=0.0))
        if res4 <= self.tol and self._balanced(st4.X, e):
            self.last = SolveInfo(it + n_it + n4, res4, "semismooth Newton (cold start)")
            return st4, q4
        if self.E is None:
            return self._fallback(label, history, [(res, st2), (res4, st4)], prev, w_free,
                                  it + n_it + n4)  # fmt: skip
        if singular is not None:  # statics: no equilibrium that holds the floating blocks
            raise singular
        if res4 < res:
            st2, q2, res = st4, q4, res4
        if not self._continuing and e is not None:
            # statics with floating blocks: a continuation in the load, the answer at
            # each fraction the start of the next (the problem's data, w_free and e, are
            # linear in the loads)
            out = self._continuation(w_free, prev, e, label, it + n_it + n4, fixed,
                                     breaking, inactive)  # fmt: skip
            if out is not None:
                return out
        raise self._diagnose(label, history, st2, prev, w_free)

    def _continuation(
        self, w_free: FloatArray, prev: PairState, e: FloatArray, label: str, work: int,
        fixed: np.ndarray | None, breaking: bool, inactive: np.ndarray | None,
    ) -> tuple[PairState, FloatArray] | None:  # fmt: skip
        """The static problem with floating blocks solved along its load, at the
        fractions :data:`CONTINUATION` of it, each answer the first iterate of the next:
        where the Newtons stall on the whole load from rest (measured: 5 of 72 eccentric
        loads of a 3D column, tests/test_solver3d.py, all solved this way). None if a
        fraction fails."""
        self._continuing = True
        start: PairState | None = None
        total = work
        try:
            for frac in CONTINUATION:
                try:
                    st, q = self._solve(frac * w_free, prev, frac * e, label,
                                        fixed=fixed, breaking=breaking, inactive=inactive,
                                        start=start)  # fmt: skip
                except InterfaceError:
                    return None
                total += self.last.iterations
                start = st
        finally:
            self._continuing = False
        self.last = SolveInfo(total, self.last.residual, "semismooth Newton (load continuation)")
        log.debug("%s: solved by a continuation in the load", label)
        return st, q

    def _bending(
        self, st: PairState, prev: PairState, xn_used: FloatArray, fscale: float
    ) -> np.ndarray:
        """The sliding pairs on the curve of the cohesion ramp (0 < X_n + t < κ c) whose
        normal force moved, beyond 1e-12 of the force scale, from ``xn_used``, where the
        state system took the ramp's tangent: (m,) mask."""
        sl = st.state == SLIDE
        if not sl.any():
            return sl
        c, mu, t = self.props.strength(st.broken, prev.path)
        Xn = st.X[:, -1]
        on = cohesion_ramp(c, mu, t, Xn, st.broken)[0] & (Xn + t > 0)
        return np.asarray(sl & on & (np.abs(Xn - xn_used) > 1e-12 * fscale))

    def _fallback(
        self, label: str, history: list[np.ndarray], tried: list[tuple[float, PairState]],
        prev: PairState, w_free: FloatArray, n_before: int,
    ) -> tuple[PairState, FloatArray]:  # fmt: skip
        """After the state iteration and the Newton: the proximal-point Newton
        (:mod:`._proximal`) from the best iterate so far, then from X = 0, then projected
        Gauss-Seidel (dense W only) from the best answer; :class:`InterfaceError` if none
        reaches the tolerance."""
        res, st2 = min(tried, key=lambda t: t[0])
        n_total = n_before
        starts = [st2.copy()] if np.all(np.isfinite(st2.X)) else []
        cold = prev.copy()
        cold.X[:] = 0.0
        starts.append(cold)
        for start in starts:
            st5, n5, _ = self._proximal(start, prev, w_free)
            n_total += n5
            res5 = float(self.residual(st5, prev, w_free).max(initial=0.0))
            if res5 <= self.tol:
                self.last = SolveInfo(n_total, res5, "proximal Newton")
                log.debug("%s: solved by the proximal Newton, residual %.2e", label, res5)
                return st5, np.zeros(0)
            if res5 < res:
                st2, res = st5, res5
        if self._sparse is not None:
            raise self._diagnose(label, history, st2, prev, w_free)
        st3 = self._gauss_seidel(st2, prev, w_free)
        res3 = float(self.residual(st3, prev, w_free).max(initial=0.0))
        if res3 <= self.tol:
            self.last = SolveInfo(n_total, res3, "projected Gauss-Seidel")
            log.debug("%s: solved by projected Gauss-Seidel, residual %.2e", label, res3)
            return st3, np.zeros(0)
        raise self._diagnose(label, history, st3 if res3 < res else st2, prev, w_free)

    def _proximal(
        self, st: PairState, prev: PairState, w_free: FloatArray,
        e: FloatArray | None = None, max_newton: int = 1500, max_stall: int = 30,
    ) -> tuple[PairState, int, FloatArray]:  # fmt: skip
        """The proximal-point Newton (:func:`._proximal.proximal_newton`) from ``st``, with
        intact pairs breaking where the answer exceeds their strength (then solved again);
        with the border (statics: ``e``) the bordered variant, its rigid amplitudes from
        zero (the pinned position). Returns the trial state, the Newton iterations and q
        (empty without a border)."""
        m = self.m
        bordered = self.E is not None and e is not None
        op = ShiftedOperator(self.Wc, self._sparse, self.E if bordered else None)
        X = np.where(np.isfinite(st.X), st.X, 0.0)
        X[self._inactive] = 0.0
        z = np.zeros(op.k)
        eb = self._escale * e if bordered and e is not None else None
        broken = st.broken.copy()
        sdir = st.slip_dir.copy()
        total = 0
        s_ = w_free
        for _ in range(m + 1):
            c, mu, t = self._newton_strength(broken, prev.path)
            law = PairLaw(c, mu, t, broken, self._fixed, self._inactive, prev.s,
                          prev.slip_dir)  # fmt: skip
            # the measure of :meth:`residual`: relative to the larger of the forces and
            # ρ |s_free|; the forces at the start stand for those of the answer
            fscale = self._scale(X, w_free)
            out = proximal_newton(op, w_free, X, law, self.rho, 0.1 * self.tol, fscale,
                                  e=eb, z0=z, max_newton=max_newton,
                                  max_stall=max_stall)  # fmt: skip
            total += out.iterations
            X, s_, z = out.X, out.s, out.z
            if not self._breaking:
                break
            Xn, nt = X[:, -1], np.linalg.norm(X[:, :-1], axis=1)
            tolF = 1e-10 * self._scale(X, w_free)
            cI, muI, tI = self.props.strength(np.zeros(m, dtype=bool), prev.path)
            fail = ~broken & ((Xn < -tI - tolF) | (nt > cI + muI * Xn + tolF))
            if not fail.any():
                break
            broken = broken | fail
        # s = s_free + W_c X (+ E z): the relative displacement w adds no compliance term
        return self._classify(st, X, broken, s_, prev, sdir), total, z * self._escale

    def _newton(
        self,
        st: PairState,
        q0: FloatArray,
        prev: PairState,
        w_free: FloatArray,
        e: FloatArray | None,
        max_iter: int = 100,
        stall: bool = True,
    ) -> tuple[PairState, FloatArray, int]:
        """Semismooth Newton on the Alart-Curnier natural map (all pairs at once).

        For broken pairs, with r = ρ, g = s_n, Δs_t = s_t − s_t,prev, Y = X_n + σ_t,r A:
        F_n = Y − max(0, Y − r g), F_t = X_t − Π_{B(τ)}(X_t − r Δs_t), τ = max(0, c_r A +
        μ_r X_n) (the cone; near the tension cut-off the cohesion ramp,
        :func:`~pfeie.interface.cohesion_ramp`);
        intact pairs: F = r (s − s_prev). A pair that exceeds its strength at the solution
        breaks and the Newton solve is repeated (at most once per pair). With a border
        (statics) the unknowns include q and the rows ρ (Eᵀ X − e). With ``stall``, it
        stops when its residual has not halved over :data:`NEWTON_STALL` iterations
        (another start follows); the last start runs to ``max_iter``. Every start stops
        when its line search finds no descent :data:`LINE_SEARCH_FAILS` iterations in a
        row, or crawls (steps below :data:`CRAWL_STEP`) :data:`LINE_SEARCH_CRAWL` in a
        row.
        """
        m, d = self.m, self.d
        M = m * d
        Wc = self.Wc if self.E is None else np.hstack([self.Wc, self.E])
        z_q = q0 / self._escale if self.E is not None and q0.size else np.zeros(
            0 if self.E is None else self.E.shape[1])  # fmt: skip
        X = st.X.copy()
        broken = st.broken.copy()
        total = 0
        sdir = st.slip_dir.copy()
        stalled = False
        for _ in range(m + 1):
            fscale = self._scale(X, w_free)
            Xv = np.concatenate([X.ravel(), z_q])
            F, J = self._natural_map(Xv, broken, w_free, prev, e)
            norms: list[float] = []
            flat = 0  # iterations in a row whose line search found no descent
            crawl = 0  # iterations in a row whose line search took a sliver of a step
            for _ in range(max_iter):
                total += 1
                nF = float(np.linalg.norm(F))
                norms.append(nF)
                if nF <= 0.1 * self.tol * fscale:
                    break
                if stall and _stalled(norms):
                    stalled = True
                    break
                try:
                    assert J is not None
                    dX = self._newton_step(J, -F)
                except np.linalg.LinAlgError:
                    dX = np.linalg.lstsq(J, -F, rcond=None)[0]  # type: ignore[arg-type]
                step = 1.0
                for _ in range(30):
                    F2, _ = self._natural_map(Xv + step * dX, broken, w_free, prev, e, False)
                    if np.linalg.norm(F2) <= (1 - 1e-4 * step) * nF:
                        flat = 0
                        break
                    step *= 0.5
                else:  # no descent along dX
                    flat += 1
                    if flat >= LINE_SEARCH_FAILS:
                        stalled = True
                        break
                crawl = crawl + 1 if step < CRAWL_STEP else 0
                if crawl >= LINE_SEARCH_CRAWL:
                    stalled = True
                    break
                Xv = Xv + step * dX
                F, J = self._natural_map(Xv, broken, w_free, prev, e)
            X = Xv[:M].reshape(m, d)
            z_q = Xv[M:]
            s_ = (w_free.ravel() + Wc @ Xv).reshape(m, d)
            # intact pairs that exceed their strength at the solution break; repeat. Not
            # at an iterate the Newton left unconverged: breaking the pairs it overloads
            # there and starting again found no solution, at 100 iterations a round and
            # one round per pair (a static problem without equilibrium took 5 s for 32
            # pairs that way)
            converged = float(np.linalg.norm(F)) <= 0.1 * self.tol * fscale
            fail = self._overstressed(X, broken, prev, fscale) & self._breaking
            # and pairs with a residual tensile strength held apart at −σ_t,r A debond
            parting = self._parting(X, s_, broken, prev) if converged else np.zeros_like(fail)
            if stalled or not converged or not (fail.any() or parting.any()):
                break
            broken = broken | fail
            self._debonded = self._debonded | parting
        return self._classify(st, X, broken, s_, prev, sdir), z_q * self._escale, total

    def _balanced(self, X: FloatArray, e: FloatArray | None, rows: bool = False) -> bool:
        """Whether forces X meet the border's equilibrium Eᵀ X = e (the floating blocks'
        rigid modes; always without a border) to the tolerance of the largest term of
        |E|ᵀ|X|: the pair law's residual does not see it. ``rows``: each row to the
        tolerance of its own |E|ᵀ|X| or |e| (a rotation's lever arms do not set a
        translation's measure)."""
        if self.E is None or e is None:
            return True
        x = X.ravel()
        gap = np.abs(self.E.T @ x - self._escale * e)
        if rows:
            size = np.maximum(np.abs(self.E).T @ np.abs(x), self._escale * np.abs(e))
            size = np.maximum(size, 1e-12 * float(size.max(initial=0.0)) + 1e-300)
            return bool((gap <= self.tol * size).all())
        scale = float((np.abs(self.E).T @ np.abs(x)).max(initial=0.0))
        return bool(gap.max(initial=0.0) <= self.tol * max(scale, 1e-300))

    def _newton_strength(self, broken: np.ndarray, path: FloatArray) -> tuple[FloatArray, ...]:
        """(c A, μ, σ_t A) of the pairs as the Newtons solve them: the residual tensile
        strength of the pairs debonded in this solve (:meth:`_parting`) taken as 0."""
        c, mu, t = self.props.strength(broken, path)
        if self._debonded.any():
            t = np.where(self._debonded & broken, 0.0, t)
        return c, mu, t

    def _parting(
        self, X: FloatArray, s_: FloatArray, broken: np.ndarray, prev: PairState
    ) -> np.ndarray:
        """The broken pairs with a residual tensile strength σ_t,r A that a Newton's answer
        holds separated, at X_n = −σ_t,r A (Y − ρ g ≤ 0, Y = X_n + σ_t,r A). The law of
        such a pair is not monotone: closed, it carries tension down to −σ_t,r A; open, no
        force. The natural map in Y represents the closed branch only; so these pairs are
        debonded (their tensile strength taken as 0 for the rest of the solve, in which
        they may stay open at X = 0 or close in compression, both states of their law)
        and the Newton runs again, as for pairs that break."""
        _, _, t = self._newton_strength(broken, prev.path)
        return np.asarray(broken & (t > 0) & (X[:, -1] + t - self.rho * s_[:, -1] <= 0))

    def _overstressed(
        self, X: FloatArray, broken: np.ndarray, prev: PairState, fscale: float
    ) -> np.ndarray:
        """The intact pairs whose forces X exceed their strength (tension beyond t, or
        shear beyond c + μ X_n), to 1e-10 of the force scale: they break."""
        Xn, nt = X[:, -1], _rownorm(X[:, :-1])
        tolF = 1e-10 * fscale
        cI, muI, tI = self.props.strength(np.zeros(self.m, dtype=bool), prev.path)
        return np.asarray(~broken & ((Xn < -tI - tolF) | (nt > cI + muI * Xn + tolF)))

    def _map_parts(
        self, X: FloatArray, s_: FloatArray, broken: np.ndarray, prev: PairState
    ) -> tuple[FloatArray, tuple[np.ndarray, ...], tuple[FloatArray, ...]]:
        """The Alart-Curnier residual F (m, d) of the pairs' forces X and relative motions
        s_ (one home for :meth:`_natural_map` and :meth:`_local_map`), with the masks
        (intact, broken, in contact, sticking, sliding, sliding in a fixed direction, cut:
        separated pairs, which carry no shear whatever their residual cohesion) and the
        arrays their Jacobians need (c, dτ/dX_n, the cone radius τ, |z| and ẑ of the trial
        tangential force z = X_t − ρ(s_t − s_t,prev); τ with the residual cohesion's ramp,
        :func:`~pfeie.interface.cohesion_ramp`). Inactive pairs are the callers'."""
        m, d, r = self.m, self.d, self.rho
        c, mu, t = self._newton_strength(broken, prev.path)
        F = np.zeros((m, d))
        it = ~broken
        F[it] = r * (s_[it] - prev.s[it])
        br = broken
        Y = X[:, -1] + t
        g = s_[:, -1]
        contact = br & (Y - r * g > 0)
        F[br, -1] = np.where(contact[br], r * g[br], Y[br])
        Xt = X[:, :-1]
        z = Xt - r * (s_[:, :-1] - prev.s[:, :-1])
        nz = _rownorm(z)
        # the Mohr-Coulomb cone as the state iteration and the residual take it (friction
        # in tension too: with a residual tensile strength, X_n⁺ here made the Newton solve
        # another law, whose answers the residual refused)
        # dτ/dX_n: μ where the cone is open (c + μ X_n > 0), the cohesion ramp's slope on it
        tau, dtau = cone(c, mu, t, X[:, -1], br)
        cut = br & ~contact & (c > 0)
        tau[cut] = 0.0
        dtau[cut] = 0.0
        fixed = br & self._fixed
        stick = br & (nz <= tau) & ~fixed
        slide = br & ~stick & ~fixed
        F[stick, :-1] = Xt[stick] - z[stick]
        with np.errstate(invalid="ignore", divide="ignore"):
            zh = z / nz[:, None]
        F[slide, :-1] = Xt[slide] - tau[slide, None] * zh[slide]
        # fixed slide: X_t = −τ ŝ with the given direction
        F[fixed, :-1] = Xt[fixed] + tau[fixed, None] * prev.slip_dir[fixed]
        return F, (it, br, contact, stick, slide, fixed, cut), (c, dtau, tau, nz, zh)

    # -- the semismooth Newton through W_c⁻¹ (3D) -------------------------------------------
    def _local_map(
        self, X: FloatArray, s_: FloatArray, broken: np.ndarray, prev: PairState, jac: bool
    ) -> tuple[FloatArray, FloatArray, FloatArray, np.ndarray]:
        """The Alart-Curnier map of :meth:`_natural_map` (its pair rows) as a function of each
        pair's own (X_k, s_k), s = s_free + W_c X: F (m, d) and, if ``jac``, its partial
        derivatives per pair, L_k = ∂F_k/∂X_k and R_k = ∂F_k/∂s_k (m, d, d), so that the
        generalised Jacobian of F(X) is J = L + R W_c (L, R block diagonal), and the mask
        (m, d) of the rows that equal those of ρ W_c (L = 0, R = ρ eᵢᵀ: intact, contact
        normal and sticking tangential rows)."""
        m, d, r = self.m, self.d, self.rho
        F, (it, br, contact, stick, slide, fixed, _), (_, dtau, tau, nz, zh) = self._map_parts(
            X, s_, broken, prev)  # fmt: skip
        off = self._inactive
        F[off] = X[off]
        if not jac:
            return F, np.zeros(0), np.zeros(0), np.zeros(0, dtype=bool)
        L = np.zeros((m, d, d))
        R = np.zeros((m, d, d))
        kin = np.zeros((m, d), dtype=bool)
        eye = np.eye(d)
        R[it] = r * eye
        kin[it] = True
        R[contact, -1, -1] = r
        kin[contact, -1] = True
        sep = br & ~contact
        L[sep, -1, -1] = 1.0
        R[stick, :-1, :-1] = r * eye[:-1, :-1]
        kin[stick, :-1] = True
        grows = dtau != 0
        L[fixed, :-1, :-1] = eye[:-1, :-1]
        fg = fixed & grows
        L[fg, :-1, -1] = dtau[fg, None] * prev.slip_dir[fg]
        # sliding: F_t = X_t − τ ẑ, dF_t = dX_t − ẑ dτ − P dz, P = (τ/|z|)(I − ẑẑᵀ),
        # dz = dX_t − ρ ds_t
        zk = zh[slide]
        P = (eye[None, :-1, :-1] - zk[:, :, None] * zk[:, None, :]) * (
            tau[slide] / nz[slide])[:, None, None]  # fmt: skip
        L[slide, :-1, :-1] = eye[None, :-1, :-1] - P
        L[slide, :-1, -1] = -dtau[slide, None] * zk
        R[slide, :-1, :-1] = r * P
        L[off] = eye
        R[off] = 0.0
        kin[off] = False
        return F, L, R, kin

    def _woodbury_step(
        self, L: FloatArray, R: FloatArray, kin: np.ndarray, B: FloatArray
    ) -> tuple[FloatArray, FloatArray]:
        """The solution of J x = b, J = L + R W_c (:meth:`_local_map`), for each column b
        of ``B`` (M, c), through the stored W_c⁻¹ and a capacitance system of the other
        rows o only: with b₀ = b off o and 0 on o, x = W_c⁻¹ (b₀ + E_o y)/ρ solves the
        kinematic rows, and y (k = |o|) the rows o,

            Cap y = b_o − L_o z − R_o b₀/ρ,   z = W_c⁻¹ b₀/ρ,
            Cap = (L_o W_c⁻¹[:, o] + R_o[:, o])/ρ,

        gathered pair by pair (L and R are block diagonal): O(c M² + M k + k³), and
        W_c x = (b₀ + E_o y)/ρ exactly, without a product. Returns x and W_c x (M, c)."""
        Winv = self._winv
        assert Winv is not None
        m, d, r = self.m, self.d, self.rho
        o = np.flatnonzero(~kin.ravel())
        b0 = B.copy()
        b0[o] = 0.0
        z = symmetric_product(Winv, b0) / r
        ds = b0 / r
        if not o.size:
            return z, ds
        k = o.size
        po = o // d  # the pair of each row o
        cols = (po[:, None] * d + np.arange(d)).ravel()  # the components of those pairs
        Lo = L.reshape(m * d, d)[o]  # (k, d): row o of L_k on its pair's components
        Ro = R.reshape(m * d, d)[o]
        if Winv.shape[0] >= SYMMETRIC_MIN and o.size >= LARGE_CAPACITANCE:
            return self._woodbury_step_large(Winv, o, cols, Lo, Ro, B, b0, z, ds)
        okey = o.tobytes()
        if self._gathered is None or self._gathered[0] != okey:
            # the blocks of W_c⁻¹ that the rows o need, kept while o does not change (the
            # Newton's last iterations): its columns o, gathered along the contiguous
            # axis, and W_c⁻¹[cols, o] from them
            cols_o = symmetric_columns(Winv, o, small="rows")
            self._gathered = (okey, cols_o[cols].reshape(k, d, k), cols_o)
        _, Wco, Wo = self._gathered
        cap = np.einsum("kj,kjl->kl", Lo, Wco)
        rhs = self._close_capacitance(cap, o, cols, Lo, Ro, B, z, ds)
        y = np.linalg.solve(cap, rhs)
        x = z + (Wo @ y) / r
        ds[o] += y / r
        if not (np.all(np.isfinite(x)) and np.all(np.isfinite(ds))):
            raise np.linalg.LinAlgError("singular Newton capacitance system")
        return x, ds

    def _close_capacitance(
        self, cap: FloatArray, o: np.ndarray, cols: np.ndarray, Lo: FloatArray,
        Ro: FloatArray, B: FloatArray, z: FloatArray, ds: FloatArray,
    ) -> FloatArray:  # fmt: skip
        """The Newton's capacitance system of :meth:`_woodbury_step` from ``cap`` =
        L_o W_c⁻¹[:, o]: R_o's entries in the columns o added, divided by ρ (in place);
        returns its right-hand side b_o − L_o z − R_o b₀/ρ (k, c), ``ds`` = b₀/ρ."""
        d, k, c = self.d, o.size, B.shape[1]
        pos = np.full(self.m * d, -1)
        pos[o] = np.arange(k)
        pc = pos[cols].reshape(k, d)
        has = pc >= 0
        rows = np.broadcast_to(np.arange(k)[:, None], pc.shape)
        np.add.at(cap, (rows[has], pc[has]), Ro[has])
        cap /= self.rho
        return np.asarray(B[o] - np.einsum("kj,kjc->kc", Lo, z[cols].reshape(k, d, c))
                          - np.einsum("kj,kjc->kc", Ro, ds[cols].reshape(k, d, c)))  # fmt: skip

    def _woodbury_step_large(
        self, Winv: FloatArray, o: np.ndarray, cols: np.ndarray, Lo: FloatArray,
        Ro: FloatArray, B: FloatArray, b0: FloatArray, z: FloatArray, ds: FloatArray,
    ) -> tuple[FloatArray, FloatArray]:  # fmt: skip
        """:meth:`_woodbury_step` with :data:`LARGE_CAPACITANCE` rows o or more in a W_c⁻¹
        of :data:`~pfeie.linalg.SYMMETRIC_MIN` rows or more, where the capacitance
        system's k × k entries and the M × k columns of W_c⁻¹ cost more to gather than to
        use, and its LU dominates: the system is gathered by the nonzeros of L_o only (a
        row of a held-open component is one row of W_c⁻¹, a sliding one at most d), along
        W_c⁻¹'s contiguous axis (W_c⁻¹[j, o] = W_c⁻¹[o, j] to round-off), with the gather
        kept while o and L_o's pattern do not change; it is solved by an LU in single
        precision refined in double (:class:`~pfeie.linalg.MixedLU`: the same answer to
        round-off, the LU in half the time); and x = W_c⁻¹ (b₀ + E_o y)/ρ is a second
        product with W_c⁻¹ instead of a product with its gathered columns. The large
        temporaries live in work arrays kept between calls
        (:class:`~pfeie.linalg.Workspace`): fresh arrays of hundreds of MB cost page
        faults that can exceed the arithmetic (docs/benchmarks.md)."""
        d, r = self.d, self.rho
        k = o.size
        # the nonzeros of L_o by level: level t holds the t-th nonzero of each row that
        # has more than t (level 0: every row), so that each level adds a slice of the
        # gathered rows to distinct rows of the system
        nzi, nzj = np.nonzero(Lo)
        first = np.r_[True, nzi[1:] != nzi[:-1]]
        level = np.arange(nzi.size) - np.maximum.accumulate(np.where(first, np.arange(nzi.size), 0))
        order = np.argsort(level, kind="stable")
        nzi, nzj, level = nzi[order], nzj[order], level[order]
        # the gather is kept while o and L_o's pattern stay and its work array was not
        # handed out again (the workspace is shared with the solvers of :meth:`with_laws`)
        key = o.tobytes() + nzi.tobytes() + nzj.tobytes()
        if self._gathered is None or self._gathered[0] != key + b"%d" % self._work.uses(
                "gathered"):  # fmt: skip
            WT = Winv.T if Winv.flags.f_contiguous else Winv  # rows along the contiguous axis
            src = cols.reshape(k, d)[nzi, nzj]
            # W_c⁻¹[src, o] in two gathers into work arrays (the columns o of every row,
            # then the rows src): a third of the time of one fancy-indexed gather
            cols_o = np.take(WT, o, axis=1, out=self._work.get("columns", (WT.shape[0], k)),
                           mode="clip")  # fmt: skip
            G = np.take(cols_o, src, axis=0, out=self._work.get("gathered", (src.size, k)),
                        mode="clip")  # fmt: skip
            self._gathered = (key + b"%d" % self._work.uses("gathered"), G, np.zeros(0))
        G = self._gathered[1]
        coef = Lo[nzi, nzj][:, None]
        ends = np.searchsorted(level, np.arange(1, d + 1))
        cap = self._work.get("capacitance", (k, k))
        if ends[0] == k:  # every row o has an L (all rows in the laws of :meth:`_local_map`)
            np.multiply(G[:k], coef[:k], out=cap)
        else:
            cap[:] = 0.0
            cap[nzi[: ends[0]]] = G[: ends[0]] * coef[: ends[0]]
        for t in range(1, d):
            lo, hi = ends[t - 1], ends[t]
            if hi > lo:
                scaled = self._work.get("scaled", (hi - lo, k))
                cap[nzi[lo:hi]] += np.multiply(G[lo:hi], coef[lo:hi], out=scaled)
        rhs = self._close_capacitance(cap, o, cols, Lo, Ro, B, z, ds)
        y = MixedLU(cap, self._work, "newton").solve(rhs)
        e = b0.copy()
        e[o] += y
        x = symmetric_product(Winv, e) / r
        ds[o] += y / r
        if not (np.all(np.isfinite(x)) and np.all(np.isfinite(ds))):
            raise np.linalg.LinAlgError("singular Newton capacitance system")
        return x, ds

    def _bordered_step(
        self, L: FloatArray, R: FloatArray, kin: np.ndarray, bF: FloatArray, beq: FloatArray
    ) -> tuple[FloatArray, FloatArray, FloatArray]:
        """The Newton step with the border (statics): J_X x + R E dq = b_F (pair rows),
        ρ Eᵀ x = b_eq (equilibrium); with x = x_F − T dq (x_F, T: :meth:`_woodbury_step`
        for b_F and for R E), the r × r system ρ Eᵀ T dq = ρ Eᵀ x_F − b_eq. Returns x, dq
        and the change of s, W_c x + E dq."""
        E = self.E
        assert E is not None
        m, d, r = self.m, self.d, self.rho
        RE = np.einsum("kij,kjc->kic", R, E.reshape(m, d, -1)).reshape(m * d, -1)
        x, ds = self._woodbury_step(L, R, kin, np.column_stack([bF, RE]))
        xF, T = x[:, 0], x[:, 1:]
        S = r * (E.T @ T)
        dq = np.asarray(np.linalg.solve(S, r * (E.T @ xF) - beq), dtype=float)
        return xF - T @ dq, dq, ds[:, 0] - ds[:, 1:] @ dq + E @ dq

    def _newton_woodbury(
        self, st: PairState, q0: FloatArray, prev: PairState, w_free: FloatArray,
        e: FloatArray | None, max_iter: int = 100, s0: FloatArray | None = None,
    ) -> tuple[PairState, FloatArray, int]:  # fmt: skip
        """The semismooth Newton of :meth:`_newton` with its steps through the stored
        W_c⁻¹ (:meth:`_woodbury_step`, :meth:`_bordered_step` with the border): the
        Jacobian is never formed, and the relative motion of a step is s + t W_c x, W_c x
        known from the step. An iterate that meets the tolerance is judged again on
        s = s_free + W_c X (+ E q) recomputed (no drift of the updates is accepted).
        ``s0``: s of the starting iterate when known (the state iteration's)."""
        m, d, r = self.m, self.d, self.rho
        E = self.E
        nq = 0 if E is None else E.shape[1]
        zq = q0 / self._escale if nq and q0.size else np.zeros(nq)
        X = st.X.copy()
        X[self._inactive] = 0.0
        broken = st.broken.copy()
        sdir = st.slip_dir.copy()
        total = 0

        def exact_s(X: FloatArray, zq: FloatArray) -> FloatArray:
            sv = w_free.ravel() + symmetric_product(self.Wc, X.ravel())
            if E is not None:
                sv += E @ zq
            return sv.reshape(m, d)

        def equilibrium(X: FloatArray, zq: FloatArray) -> FloatArray:
            if E is None:
                return np.zeros(0)
            assert e is not None
            return r * (E.T @ X.ravel() - self._escale * e)

        s_ = w_free
        stalled = False
        for _ in range(m + 1):
            fscale = self._scale(X, w_free)
            exact = s0 is None  # whether s was computed from X here, not updated or given
            s_ = exact_s(X, zq) if s0 is None else s0
            s0 = None
            F, L, R, kin = self._local_map(X, s_, broken, prev, True)
            Feq = equilibrium(X, zq)
            norms: list[float] = []
            converged = False
            flat = 0  # iterations in a row whose line search found no descent
            for _ in range(max_iter):
                total += 1
                nF = float(np.sqrt(np.sum(F * F) + Feq @ Feq))
                norms.append(nF)
                if nF <= 0.1 * self.tol * fscale:
                    if exact:
                        converged = True
                        break
                    s_ = exact_s(X, zq)
                    F, L, R, kin = self._local_map(X, s_, broken, prev, True)
                    exact = True
                    nF = float(np.sqrt(np.sum(F * F) + Feq @ Feq))
                    if nF <= 0.1 * self.tol * fscale:
                        converged = True
                        break
                if _stalled(norms):
                    stalled = True
                    break
                if E is None:
                    dX, dS = (a[:, 0] for a in self._woodbury_step(L, R, kin, -F.reshape(-1, 1)))
                    dq = np.zeros(0)
                else:
                    dX, dq, dS = self._bordered_step(L, R, kin, -F.ravel(), -Feq)
                dX, dS = dX.reshape(m, d), dS.reshape(m, d)
                step = 1.0
                for _ in range(30):
                    X2, zq2 = X + step * dX, zq + step * dq
                    F2 = self._local_map(X2, s_ + step * dS, broken, prev, False)[0]
                    F2eq = equilibrium(X2, zq2)
                    if np.sqrt(np.sum(F2 * F2) + F2eq @ F2eq) <= (1 - 1e-4 * step) * nF:
                        flat = 0
                        break
                    step *= 0.5
                else:  # no descent along (dX, dq)
                    flat += 1
                    if flat >= LINE_SEARCH_FAILS:
                        stalled = True
                        break
                X, zq = X + step * dX, zq + step * dq
                X[self._inactive] = 0.0  # held open: exactly, not the step's round-off
                s_ = s_ + step * dS
                exact = False
                F, L, R, kin = self._local_map(X, s_, broken, prev, True)
                Feq = equilibrium(X, zq)
            if not exact:  # the iteration limit or a stall: the answer on the exact s
                s_ = exact_s(X, zq)
            fail = self._overstressed(X, broken, prev, fscale) & self._breaking
            parting = self._parting(X, s_, broken, prev) if converged else np.zeros_like(fail)
            # unlike the dense Newton, this one breaks pairs at an unconverged iterate too:
            # its rounds are cut by the stall test, and requiring convergence here made the
            # 72 eccentric loads of tests/test_solver3d.py 4 × slower (349 s against 90 s)
            if stalled or not (fail.any() or parting.any()):
                break
            broken = broken | fail
            self._debonded = self._debonded | parting
        return self._classify(st, X, broken, s_, prev, sdir), zq * self._escale, total

    def _newton_step(self, J: FloatArray, b: FloatArray) -> FloatArray:
        """The Newton step J x = b. Without a border, on a large W inverted once
        (:data:`NEWTON_WOODBURY_MIN` components or more), through W_c⁻¹: J = ρ W_c except
        in the rows ``oth`` of separated, sliding, fixed and held-open components, so with
        z = W_c⁻¹ b / ρ, x = z − W_c⁻¹[:, oth] y / ρ, Cap y = J[oth] z − b[oth],
        Cap = J[oth] W_c⁻¹[:, oth] / ρ (k × k): O(k² M) instead of the O(M³) of a dense
        solve, when k ≤ M/2. Otherwise, or when the capacitance system is singular, or on a
        reference's W_c⁻¹ (not this W_c's), the dense solve."""
        Winv, M = self._winv, self.m * self.d
        if Winv is None or self.refined or self.E is not None or M < NEWTON_WOODBURY_MIN:
            return np.asarray(np.linalg.solve(J, b))
        r = self.rho
        oth = np.flatnonzero((r * self.Wc != J).any(axis=1))
        if 2 * oth.size > M:
            return np.asarray(np.linalg.solve(J, b))
        z = symmetric_product(Winv, b) / r
        if not oth.size:
            return z
        Wo = symmetric_columns(Winv, oth)
        cap = (J[oth] @ Wo) / r
        y = np.linalg.solve(cap, J[oth] @ z - b[oth])
        x = z - (Wo @ y) / r
        if not np.all(np.isfinite(x)):
            raise np.linalg.LinAlgError("singular Newton capacitance system")
        return np.asarray(x)

    def _classify(
        self, st: PairState, X: FloatArray, broken: np.ndarray, s_: FloatArray,
        prev: PairState, sdir: FloatArray,
    ) -> PairState:  # fmt: skip
        """The trial state of the forces X and relative displacements s (states and slip
        directions from the law, ``sdir`` updated in place)."""
        m = self.m
        out = st.copy()
        out.X, out.broken = X, broken
        out.w = self.props.w_of(s_, X)
        out.s = s_
        g = s_[:, -1]
        state = np.full(m, INTACT, dtype=np.int8)
        c, mu, t = self._newton_strength(broken, prev.path)
        opened = broken & (X[:, -1] + t - self.rho * g <= 0)
        nt = np.linalg.norm(X[:, :-1], axis=1)
        tau = cone(c, mu, t, X[:, -1], broken)[0]
        sliding = broken & ~opened & (nt >= tau * (1 - 1e-9)) & (nt > 0) & ~self._fixed
        state[broken] = STICK
        state[sliding] = SLIDE
        state[broken & self._fixed] = SLIDE
        state[opened | self._inactive] = OPEN
        with np.errstate(invalid="ignore", divide="ignore"):
            sdir[sliding] = -X[sliding, :-1] / nt[sliding, None]
        out.state, out.slip_dir = state, sdir
        return out

    def _diagnose(
        self,
        label: str,
        history: list[np.ndarray],
        st: PairState,
        prev: PairState,
        w_free: FloatArray,
    ) -> InterfaceError:
        """The error of a problem the solver did not converge on: the residual, the pairs
        that kept changing state and those of the largest residuals (``pairs``: both,
        the cycling ones first)."""
        res = self.residual(st, prev, w_free)
        if len(history) > 1:
            H = np.array(history[-8:])
            cyc = np.flatnonzero((H[-1] != H).any(axis=0))
        else:
            cyc = np.zeros(0, dtype=np.int64)
        worst = np.argsort(res)[::-1][:5]
        cyc_txt = ", ".join(f"{k} ({'/'.join(STATE_NAMES[s] for s in sorted(set(H[:, k])))})"
                            for k in cyc[:10]) if cyc.size else "none"  # fmt: skip
        scale = self.rho * float(np.abs(w_free).max(initial=0.0))  # ρ w_free (N)
        rng = ("" if not 0.0 < scale < SAFE_SCALE[0] else
               f" Its force scale, ρ max|w_free| = {scale:.1e} N, lies below"
               f" {SAFE_SCALE[0]:.0e} N, where the squares of the law leave double"
               " precision: check the units.")  # fmt: skip
        named = tuple(dict.fromkeys(int(k) for k in (*cyc[:10], *worst)))
        return InterfaceError(
            f"{label}: the interface problem did not converge: residual "
            f"{float(res.max(initial=0.0)):.3e} > {self.tol:.1e}; pairs changing state: "
            f"{cyc_txt}; largest residuals at pairs {worst.tolist()}."
            + rng
            + (f" {self.hint}" if self.hint else ""),
            named,
        )

    def _natural_map(
        self, zv: FloatArray, broken: np.ndarray, w_free: FloatArray, prev: PairState,
        e: FloatArray | None = None, jac: bool = True,
    ) -> tuple[FloatArray, FloatArray | None]:  # fmt: skip
        """Alart-Curnier residual F(z) and, if ``jac``, a generalised Jacobian; z = X, or
        (X, q / scale) with the border, whose equilibrium rows are appended."""
        m, d, r = self.m, self.d, self.rho
        M = m * d
        Wc = self.Wc if self.E is None else np.hstack([self.Wc, self.E])
        N = Wc.shape[1]
        I = self._eye if self._eye is not None and self._eye.shape == (M, N) else np.eye(M, N)
        self._eye = I  # read only: kept for the next call
        Xv = zv[:M]
        Xm = Xv.reshape(m, d)
        sv = w_free.ravel() + Wc @ zv
        s_ = sv.reshape(m, d)
        F, (it, br, contact, stick, slide, fixed, _), (_, dtau, tau, nz, zh) = self._map_parts(
            Xm, s_, broken, prev)  # fmt: skip
        J = np.zeros((m, d, N if jac else 0))
        Wr = Wc.reshape(m, d, N)
        Ir = I.reshape(m, d, N)
        if jac:
            J[it] = r * Wr[it]
        if jac:
            J[contact, -1] = r * Wr[contact, -1]
            sep = br & ~contact
            J[sep, -1] = Ir[sep, -1]
        if jac:
            # the cone radius τ grows with X_n (dτ/dX_n: μ, or the cohesion ramp's slope)
            grows = dtau != 0
            nrm = np.arange(m) * d + d - 1  # the column of each pair's normal force
            fk = np.flatnonzero(fixed)
            J[fk, :-1] = Ir[fk, :-1]
            kk = fk[grows[fk]]
            J[kk, :-1, nrm[kk]] += dtau[kk, None] * prev.slip_dir[kk]
            J[stick, :-1] = r * Wr[stick, :-1]
            # sliding: F_t = X_t − τ ẑ, dF_t = dX_t − ẑ dτ − (τ/|z|)(I − ẑẑᵀ) dz
            sk = np.flatnonzero(slide)
            dz = Ir[sk, :-1] - r * Wr[sk, :-1]  # (k, d-1, N)
            zk = zh[sk]
            P = (np.eye(d - 1)[None] - zk[:, :, None] * zk[:, None, :]) * (
                tau[sk] / nz[sk])[:, None, None]  # fmt: skip
            A = Ir[sk, :-1]
            gk = np.flatnonzero(grows[sk])
            A[gk, :, nrm[sk[gk]]] -= zk[gk] * dtau[sk[gk], None]
            J[sk, :-1] = A - P @ dz
        off = self._inactive
        F[off] = Xm[off]
        if jac:
            J[off] = Ir[off]
        Fv, Jv = F.ravel(), (J.reshape(M, N) if jac else None)
        if self.E is None:
            return Fv, Jv
        assert e is not None
        Feq = r * (self.E.T @ Xv - self._escale * e)
        Fv = np.concatenate([Fv, Feq])
        if Jv is not None:
            Jeq = np.hstack([r * self.E.T, np.zeros((self.E.shape[1],) * 2)])
            Jv = np.vstack([Jv, Jeq])
        return Fv, Jv

    def _gauss_seidel(
        self, st: PairState, prev: PairState, w_free: FloatArray, sweeps: int = 500
    ) -> PairState:
        """Projected Gauss-Seidel with exact local solutions, from the iterate ``st``."""
        m, d = self.m, self.d
        Wc = self.Wc.reshape(m, d, m, d)
        X = st.X.copy()
        broken = st.broken.copy()
        state = st.state.copy()
        sdir = st.slip_dir.copy()
        b_all = w_free + np.einsum("kilj,lj->ki", Wc, X)
        intact = self.props.strength(np.zeros(m, dtype=bool), prev.path)
        residual = self.props.strength(np.ones(m, dtype=bool), prev.path)
        trial = st.copy()
        active = np.flatnonzero(~self._inactive).tolist()
        X[self._inactive] = 0.0
        state[self._inactive] = OPEN
        for sweep in range(1, sweeps + 1):
            for k in active:
                Wkk = Wc[k, :, k, :]
                b = b_all[k] - Wkk @ X[k]
                strength = tuple(float(a[k]) for a in (*intact, *residual))
                fixed_k = bool(self._fixed[k])
                Xk, _, state[k], broken[k], sdir[k] = self._local(
                    k, Wkk, b, prev, broken[k], sdir[k], strength, fixed_k)  # fmt: skip
                dX = Xk - X[k]
                if np.any(dX):
                    b_all += np.einsum("lik,k->li", Wc[:, :, k, :], dX)
                    X[k] = Xk
            if sweep % 5 == 0:
                trial.X, trial.state, trial.broken, trial.slip_dir = X, state, broken, sdir
                trial.w = self.relative(X, np.zeros(0), w_free) - self._gapv
                trial.s = self.props.s_of(trial.w, X)
                if self.residual(trial, prev, w_free).max(initial=0.0) <= self.tol:
                    break
        out = st.copy()
        out.X, out.state, out.broken, out.slip_dir = X, state, broken, sdir
        out.w = self.relative(X, np.zeros(0), w_free) - self._gapv
        out.s = self.props.s_of(out.w, X)
        return out

    def _local(
        self, k: int, Wkk: FloatArray, b: FloatArray, prev: PairState, broken: bool,
        sdir: FloatArray, strength: tuple[float, ...], fixed: bool = False,
    ) -> tuple[FloatArray, FloatArray, int, bool, FloatArray]:  # fmt: skip
        """Exact solution of pair k's law for s = b + Wkk X (others frozen); ``strength``
        is (c A, μ, σ_t A) intact, then broken, of the pair; a ``fixed`` pair slides
        along ``sdir``."""
        d = self.d
        cI, muI, tI, cA, mu, tA = strength
        target = prev.s[k].copy()
        if not broken:
            X = np.linalg.solve(Wkk, target - b)
            tau = cI + muI * X[-1]
            if not self._breaking or (X[-1] >= -tI and np.linalg.norm(X[:-1]) <= tau):
                return X, b + Wkk @ X, INTACT, False, sdir
            broken = True
        if b[-1] >= 0:
            return np.zeros(d), b.copy(), OPEN, broken, sdir
        target[-1] = 0.0

        one = np.array([True])

        def cap(xn: float) -> float:  # the cone radius at X_n, the cohesion ramp's below κ c
            on, tr, _ = cohesion_ramp(np.array([cA]), np.array([mu]), np.array([tA]),
                                      np.array([xn]), one)  # fmt: skip
            return float(tr[0]) if on[0] else cA + mu * xn

        def tangent(xn: float) -> tuple[float, float]:  # the cone radius' tangent at X_n
            on, cl, ml = cohesion_ramp_tangent(np.array([cA]), np.array([mu]),
                                               np.array([tA]), np.array([xn]), one)  # fmt: skip
            return (float(cl[0]), float(ml[0])) if on[0] else (cA, mu)

        if fixed:
            sh = sdir.copy()
        else:
            X = np.linalg.solve(Wkk, target - b)
            if X[-1] >= -tA and np.linalg.norm(X[:-1]) <= cap(float(X[-1])):
                return X, b + Wkk @ X, STICK, broken, sdir
            sh = -X[:-1] / max(float(np.linalg.norm(X[:-1])), 1e-300)
        c_s, mu_s = cA, mu  # the cone's coefficients, X_t = −(c_s + μ_s X_n) ŝ
        for _ in range(50):
            # unknown X_n; X_t = −τ(X_n) ŝ; normal row: (Wkk X)_n + b_n = 0, solved by
            # Newton's method on the cone radius' tangent τ ≈ c_s + μ_s X_n (one step off
            # the cohesion ramp, where the tangent is the cone)
            beta = float(Wkk[-1, :-1] @ sh)
            xn = (-b[-1] + c_s * beta) / (Wkk[-1, -1] - mu_s * beta)
            for _ in range(30):
                c_s, mu_s = tangent(xn) if cA > 0 else (cA, mu)
                x2 = (-b[-1] + c_s * beta) / (Wkk[-1, -1] - mu_s * beta)
                done = abs(x2 - xn) <= 1e-14 * max(abs(xn), cA)
                xn = x2
                if done:
                    break
            X = np.concatenate([-(c_s + mu_s * xn) * sh, [xn]])
            s = b + Wkk @ X
            ds = s[:-1] - prev.s[k, :-1]
            nds = float(np.linalg.norm(ds))
            if fixed or nds == 0 or np.allclose(ds / nds, sh, atol=1e-12):
                break
            sh = ds / nds
        if X[-1] < -tA:
            return np.zeros(d), b.copy(), OPEN, broken, sdir
        return X, s, SLIDE, broken, sh


__all__ = ["InterfaceSolver", "SolveInfo"]
