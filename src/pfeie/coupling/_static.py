"""The static interface problem with rigid unknowns (method.md §5.2).

A floating block (one that its supports do not hold) has a singular stiffness: its rigid
modes Φ are removed by temporary pins (a pivoted QR picks well-separated pin DOFs), the
pinned flexibility W_pin = G K_pin⁻¹ Gᵀ is formed (:func:`pfeie.coupling.delassus`), and
the rigid amplitudes q join the pair forces X in the bordered system

    [ W_pin  E ] [X]   [ −w_free,pin ]        E = G Φ,
    [ Eᵀ     0 ] [q] = [ −Φᵀ f       ]

solved with the pair law (the interface solver's state iteration). Then

    u = u_pin + K_pin⁻¹ Gᵀ X + Φ q.

A balanced load on a pinned body leaves zero pin reactions, so u is exact. When the pairs
cannot hold a body (it would slide or fall), :class:`~pfeie.errors.MechanismError` says so.
"""

from __future__ import annotations

import copy
import logging
from typing import NamedTuple

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from ..errors import InterfaceError, MechanismError
from ..interface import InterfaceSolver, PairLaws, PairState, SolverSettings
from ..linalg import factorize
from ..model import LinearSystem, Model
from ..typing import FloatArray, IntArray
from ._delassus import delassus
from ._operators import PairOperator

log = logging.getLogger(__name__)


#: the share of its load below which the rigid-block check counts a block as balanced (its
#: linear programme is solved to about 1e-9 of the loads)
RIGID_SHARE_MIN = 1e-6

#: the relative width of the bracket of :meth:`StaticInterfaceProblem.rigid_factor`
RIGID_FACTOR_TOL = 1e-3

#: the factors of :meth:`StaticInterfaceProblem.rigid_factor` lie in [1/R, R]
RIGID_FACTOR_RANGE = 64.0


class RigidCheck(NamedTuple):
    """The rigid-block check of :meth:`StaticInterfaceProblem.rigid_check`."""

    share: FloatArray
    normal: FloatArray
    #: joint by joint, the total share of the check with only that joint's strength
    #: limited and the other joints unbreakable (name → share; empty: not asked): a joint
    #: that cannot hold alone is where the blocks fail (:func:`pfeie.solve_pairs`'s error)
    alone: tuple[tuple[str, float], ...] = ()
    #: the rigid blocks' factor of safety by strength reduction, where the check was asked
    #: for it (:meth:`StaticInterfaceProblem.rigid_factor`; None: not asked or not found)
    factor: float | None = None


def pair_strengths(laws: PairLaws, damage: PairState | None) -> tuple[FloatArray, ...]:
    """(c A, μ, σ_t A) of every pair for the limit checks: broken where the laws start
    broken or ``damage`` (a pair state left by an earlier load) broke them, with the slip
    paths of ``damage``; every other pair intact."""
    broken = laws.initially_broken.copy()
    path = np.zeros(laws.n)
    if damage is not None:
        broken |= damage.broken
        path = damage.path
    return tuple(laws.strength(broken, path))


def pins(F: FloatArray, avoid: np.ndarray | None = None) -> IntArray:
    """Rows of F (n, k) whose k × k block is best conditioned (pivoted QR of Fᵀ), chosen
    among the rows not flagged in ``avoid`` (n,) when these still span the k modes.

    Pins must avoid the DOFs of pair nodes: a pinned DOF has no flexibility, so its pair
    component would look prescribed to the interface solver, which then cannot hold the
    joint closed there through the rigid unknowns."""
    if F.shape[1] == 0:
        return np.zeros(0, dtype=np.int64)
    k = F.shape[1]
    if avoid is not None and avoid.any():
        rows = np.flatnonzero(~avoid)
        if rows.size >= k and np.linalg.matrix_rank(F[rows]) == k:
            _, _, piv = sla.qr(F[rows].T, mode="economic", pivoting=True)
            return np.sort(rows[piv[:k]])
    _, _, piv = sla.qr(F.T, mode="economic", pivoting=True)
    return np.sort(piv[:k])


class StaticInterfaceProblem:
    """The static problem of a model with interfaces (see the module docstring): the
    pinned factorisation, W_pin and the border are built once; :meth:`solve` solves for
    any load vector.

    >>> import numpy as np, pfeie as pf
    >>> mesh = pf.rectangle(1.0, 2.0, 1, 2)
    >>> _ = mesh.add_cell_group("base", lambda x: x[:, 1] < 1)
    >>> _ = mesh.add_cell_group("top", lambda x: x[:, 1] > 1)
    >>> _ = mesh.add_facet_group("j", lambda x: abs(x[:, 1] - 1.0) < 1e-9, False)
    >>> mat = pf.Elastic(1e9, 0.2, 1000.0)
    >>> model = pf.Model(mesh, [pf.Block("base", mat), pf.Block("top", mat)],
    ...                  interfaces=[pf.Interface("j", pf.Joint(phi=30.0))])
    >>> model.fix("base"); model.add_gravity()
    >>> problem = StaticInterfaceProblem(model, model.system())
    >>> u, pairs = problem.solve(model.system().load(0.0))
    >>> round(float(pairs.X[:, -1].sum() / 9810.0), 9)   # the joint carries the weight
    1.0
    """

    def __init__(
        self,
        model: Model,
        system: LinearSystem,
        *,
        backend: str = "auto",
        settings: SolverSettings | None = None,
    ) -> None:
        if model.pairs is None:
            raise MechanismError("the static interface problem needs interfaces")
        self.model, self.system = model, system
        free, pres = system.free, system.prescribed
        Phi = model.free_rigid_modes()  # the rigid motions the supports (pres) leave free
        self.mode_body = model.free_rigid_mode_bodies()
        self.Phi = np.ascontiguousarray(Phi[free].toarray())  # C order: the same round-off
        k = self.Phi.shape[1]
        self.op = PairOperator.build(model.pairs, model.n_dof, free, pres)
        on_pairs = np.asarray(abs(self.op.G).sum(axis=0)).ravel() > 0
        self.keep = np.setdiff1d(np.arange(free.size), pins(self.Phi, on_pairs) if k else [])
        Kp = system.K[self.keep][:, self.keep]
        try:
            self.factor = factorize(Kp, spd=True, backend=backend)
        except MechanismError as exc:
            raise MechanismError(f"static analysis: {exc}") from None
        self.w_pres = self.op.w_prescribed(system.prescribed_values)
        self.W = delassus(self.factor, self.op.G[:, self.keep].tocsr())
        E = self.op.G @ self.Phi if k else None
        self.laws = model.pair_laws
        self.solver = InterfaceSolver(self.W.matrix(), model.pair_laws, border=E,
                                      settings=settings,
                                      regularize=model.pairs.regularization,
                                      hint="")  # fmt: skip

    def solve(
        self, f_free: FloatArray, label: str = "static analysis", start: PairState | None = None,
        damage: PairState | None = None,
    ) -> tuple[FloatArray, PairState]:  # fmt: skip
        """Free-DOF displacements and the pair state under the free-DOF loads ``f_free``;
        ``start``: the pair solver's first iterate (the state under nearby loads), else
        the initial state; ``damage``: a pair state left by an earlier load (an
        earthquake's last), whose broken pairs (besides those of joints that start broken)
        carry their residual strength and whose slip paths set the strength of
        slip-dependent laws."""
        d = self.model.dim
        keep, Phi = self.keep, self.Phi
        u_pin = np.zeros(self.system.free.size)
        u_pin[keep] = self.factor.solve(f_free[keep])
        w_free = (self.op.G @ u_pin + self.w_pres).reshape(-1, d)
        e = -(Phi.T @ f_free) if Phi.shape[1] else None
        laws = self.laws
        prev = laws.initial_state(d)
        if damage is not None:
            prev = PairState.initial(laws.initially_broken | damage.broken, laws.gap, d)
            prev.path = damage.path.copy()
        try:
            st, q = self.solver.solve(w_free, prev, e, label=label, start=start)
        except (InterfaceError, MechanismError) as exc:
            # near a hinge mechanism the state iteration meets singular systems and the
            # Newtons stall; where the rigid blocks can balance the loads, an equilibrium
            # may exist and the bordered proximal Newton looks for it (otherwise, or if it
            # fails too, the first error stands)
            if e is None or not self._balances(f_free, damage):
                raise
            try:
                st, q = self.solver.solve_bordered_proximal(w_free, prev, e, label, start)
            except InterfaceError:
                raise exc from None
        u_free = u_pin
        u_free[keep] += self.W.correct(st.X.ravel())
        if Phi.shape[1]:
            u_free = u_free + Phi @ q
        return u_free, st

    def rigid_check(
        self, f_free: FloatArray, damage: PairState | None = None,
        strong: np.ndarray | None = None, factor: float = 1.0,
    ) -> RigidCheck:  # fmt: skip
        """Limit equilibrium of the floating blocks as rigid bodies: per body (n_bodies,),
        the least share of its load that no pair forces within the joints' strength can
        balance (``share``; 0: a rigid-block equilibrium exists; NaN for a body with a
        support), and the normal pair forces of the answer (``normal``, N, compression +;
        zero on pairs that touch no floating body; all NaN where the check failed).

        The linear programme: find X and slacks s = s⁺ − s⁻ ≥ 0 with

            Eᵀ X − s = e,    X_n ≥ −σ_t A,    n_k · X_t ≤ c A + μ X_n  (each pair),

        minimising Σ_j |s_j| / S_j, where E = G Φ and e = −Φᵀ f are the border's
        (the module docstring), n_k the outward normals of the Coulomb cone's section (two
        in 2D; in 3D eight, a polygon circumscribed about the circle), and S_j the size of
        mode j's load: the body's translational load ‖Σ f‖ times the mode's RMS
        displacement over the body's nodes (1 for a translation; the radius of gyration
        of the nodes for a rotation, m). A body's share is Σ_j |s_j| / S_j over its modes
        (for a load beyond the cone along one axis, the unbalanced force over the load;
        along no axis, a weighted L1 norm of it). The cone is the law's outer bound (no
        cohesion ramp, no gap, every pair
        that is not broken by ``damage`` or from the start taken intact), so a share above
        zero proves that no static equilibrium exists, elastic or rigid; a share of zero
        leaves open whether the elastic one does (the elastic problem may part a joint
        that the rigid blocks keep closed). ``strong`` (n_pairs,): pairs taken unbreakable
        (no cone, no tensile bound), to test the other joints alone. ``factor``: every
        strength (c, tan φ, σ_t) divided by it, as in :meth:`PairLaws.reduced`.

        >>> import pfeie as pf
        >>> from pfeie.verification._models import block_on_base
        >>> model = block_on_base(joint=pf.Joint(phi=30.0))   # a block on a level joint
        >>> model.add_inertia([0.7 * 9.81, 0.0])                # pushed sideways by 0.7 g
        >>> problem = StaticInterfaceProblem(model, model.system())
        >>> share = problem.rigid_check(model.system().load(0.0)).share
        >>> round(float(share[model.body_names().index("block")]), 6)  # (0.7 − tan 30°)/√1.49
        0.100479
        """
        from scipy.optimize import linprog

        model, d = self.model, self.model.dim
        share = np.full(model.n_bodies, np.nan)
        failed = RigidCheck(share, np.full(self.laws.n, np.nan))
        k = self.Phi.shape[1]
        if not k:
            return failed
        E = np.asarray(self.op.G @ self.Phi)
        e = -(self.Phi.T @ f_free)
        # the load size of each mode: the translational load on its body times the mode's
        # RMS displacement over the body's free DOFs
        free = self.system.free
        body = model.body_of_node[free // d]
        comp = free % d
        S = np.zeros(k)
        for j in range(k):
            b = self.mode_body[j]
            on = body == b
            force = np.bincount(comp[on], weights=f_free[on], minlength=d)
            nodes = max(int(on.sum()) // d, 1)
            S[j] = float(np.linalg.norm(force)) * float(
                np.sqrt((self.Phi[on, j] ** 2).sum() / nodes))  # fmt: skip
        S = np.where(S > 0, S, max(float(S.max(initial=0.0)), 1.0))
        # the pairs that act on a floating body
        rows = np.abs(E).reshape(-1, d, k).sum(axis=(1, 2)) > 0
        idx = np.flatnonzero(rows)
        laws = self.laws
        c, mu, t = pair_strengths(laws, damage)
        c, mu, t = c[idx] / factor, mu[idx] / factor, t[idx] / factor
        limited = np.ones(idx.size, dtype=bool) if strong is None else ~strong[idx]
        n = idx.size
        if d == 2:
            normals = np.array([[1.0], [-1.0]])
        else:
            th = np.arange(8) * (np.pi / 4)
            normals = np.column_stack([np.cos(th), np.sin(th)])
        nk = normals.shape[0]
        # n_k · X_t − μ X_n ≤ c A, pair by pair: rows (pair, k), columns (pair, component)
        r_idx = np.repeat(np.arange(n * nk), d)
        c_idx = (np.arange(n)[:, None, None] * d + np.arange(d)[None, None, :]
                 + np.zeros((1, nk, 1), dtype=np.int64)).ravel()  # fmt: skip
        vals = np.concatenate([normals[None, :, :].repeat(n, axis=0),
                               -mu[:, None, None].repeat(nk, axis=1)], axis=2).ravel()  # fmt: skip
        # scaled to entries of order one: forces X = F x (F the largest mode load), the
        # equilibrium rows and their slacks by S_j
        F = max(float(np.abs(e).max(initial=0.0)), float(c.max(initial=0.0)), 1.0)
        A_ub = sp.csr_matrix((vals, (r_idx, c_idx)), shape=(n * nk, n * d + 2 * k))
        b_ub = np.repeat(c / F, nk)
        keep = np.repeat(limited, nk)  # (the cone rows of the pairs whose strength counts)
        A_ub, b_ub = A_ub[keep], b_ub[keep]
        cols = (idx[:, None] * d + np.arange(d)).ravel()
        rows = sp.diags(F / S) @ sp.csr_matrix(E[cols].T)
        A_eq = sp.hstack([rows, -sp.eye(k), sp.eye(k)]).tocsr()
        lo = np.full(n * d, -np.inf)
        lo[d - 1 :: d] = np.where(limited, -t / F, -np.inf)
        bounds = np.column_stack([np.r_[lo, np.zeros(2 * k)], np.full(n * d + 2 * k, np.inf)])
        cost = np.r_[np.zeros(n * d), np.ones(2 * k)]
        for presolve in (True, False):  # HiGHS's presolve took a bounded problem for an
            # unbounded one (a new user's two blocks on 40° and 10° planes): without it
            res = linprog(cost, A_ub=A_ub if keep.any() else None,
                          b_ub=b_ub if keep.any() else None, A_eq=A_eq, b_eq=e / S,
                          bounds=bounds,
                          method="highs", options={"presolve": presolve})  # fmt: skip
            if res.status == 0:
                break
            log.debug("rigid-block check: linprog status %d: %s", res.status, res.message)
        else:  # the check gives no answer: said, not a silent NaN in the diagnosis
            log.warning("rigid-block check of the floating blocks failed (linprog status %d: "
                        "%s); the diagnosis goes without it", res.status, res.message)  # fmt: skip
            return failed
        s = np.abs(res.x[n * d : n * d + k] - res.x[n * d + k :])
        for b in np.unique(self.mode_body):
            share[b] = float(s[self.mode_body == b].sum())
        normal = np.zeros(self.laws.n)
        normal[idx] = F * res.x[d - 1 : n * d : d]
        return RigidCheck(share, normal)

    def _balances(
        self, f_free: FloatArray, damage: PairState | None, factor: float = 1.0
    ) -> bool | None:
        """Whether the :meth:`rigid_check` of the loads ``f_free`` (strengths divided by
        ``factor``) balances every floating block, to :data:`RIGID_SHARE_MIN`; None where
        the check fails."""
        check = self.rigid_check(f_free, damage, factor=factor)
        if not np.isfinite(check.normal).all():
            return None
        return not bool(np.nansum(check.share) > RIGID_SHARE_MIN)

    def rigid_factor(
        self, f_free: FloatArray, damage: PairState | None = None, tol: float = RIGID_FACTOR_TOL,
    ) -> float | None:  # fmt: skip
        """The factor of safety of the floating blocks as rigid bodies, by strength
        reduction: the largest F in [1/RIGID_FACTOR_RANGE, RIGID_FACTOR_RANGE] at which the
        :meth:`rigid_check` of the loads ``f_free`` with every strength divided by F
        balances them, within a relative ``tol`` (bisection of log F); None where even the
        strengths multiplied by RIGID_FACTOR_RANGE leave them unbalanced (a mechanism of
        opening that tension does not hold), the check fails, or F exceeds the range.

        It is limit equilibrium on the blocks as the model cuts them (rigid, with their
        loads and water), the factor a hand computation gives for one plane:
        F = (c A + W cos β tan φ) / (W sin β) for a block on a plane of dip β. In 3D the
        cone is the octagon circumscribed about the circle, so F may be up to 1/cos 22.5°
        − 1 = 8.2 % high where the block slides between the octagon's corners.

        >>> import pfeie as pf
        >>> from pfeie.verification._models import block_on_base
        >>> model = block_on_base(joint=pf.Joint(phi=30.0))
        >>> model.add_inertia([0.7 * 9.81, 0.0])                # pushed sideways by 0.7 g
        >>> problem = StaticInterfaceProblem(model, model.system())
        >>> F = problem.rigid_factor(model.system().load(0.0))
        >>> round(F, 3), round(float(np.tan(np.radians(30.0)) / 0.7), 3)   # tan φ / k
        (0.825, 0.825)
        """
        f_lo, f_hi = 1.0 / RIGID_FACTOR_RANGE, RIGID_FACTOR_RANGE

        def holds(F: float) -> bool | None:
            return self._balances(f_free, damage, F)

        at_one = holds(1.0)
        if at_one is None:
            return None
        # steps of 4 away from 1 (up where F = 1 holds, down where it does not) until the
        # answer changes: the bracket [lo, hi], lo held
        step = 4.0 if at_one else 0.25
        F = 1.0
        while True:
            nxt = min(max(F * step, f_lo), f_hi)
            ok = None if nxt == F else holds(nxt)  # (the range ends: no factor in it)
            if ok is None:
                return None
            if ok != at_one:
                break
            F = nxt
        lo, hi = (F, nxt) if at_one else (nxt, F)
        while hi / lo - 1.0 > tol:
            mid = float(np.sqrt(lo * hi))
            ok = holds(mid)
            if ok is None:
                return None
            lo, hi = (mid, hi) if ok else (lo, mid)
        return lo

    def rigid_limit(
        self, f0: FloatArray, f1: FloatArray, k_max: float, tol: float = RIGID_FACTOR_TOL,
        damage: PairState | None = None,
    ) -> float | None:  # fmt: skip
        """The rigid-block limit load factor: the largest k in [0, ``k_max``] at which the
        :meth:`rigid_check` of the loads f0 + k f1 (free DOFs) balances them, within a
        relative ``tol`` (bisection); ∞ where they balance at ``k_max`` (no limit up to
        it), None where they do not balance at k = 0 or the check fails.

        Any static equilibrium, elastic or rigid, has pair forces within the joints'
        strength that balance the floating blocks, so no static equilibrium exists beyond
        it: it bounds from above the limit that static analyses of the elastic blocks
        find (:func:`pfeie.yield_coefficient`), and equals it for stiff blocks where the
        analyses hold up to the limit (a pair solver that fails short of the limit near a
        hinge mechanism shows as a gap between the two).

        >>> import pfeie as pf
        >>> from pfeie.verification._models import block_on_base
        >>> model = block_on_base(joint=pf.Joint(phi=30.0))   # a block on a level joint
        >>> problem = StaticInterfaceProblem(model, model.system())
        >>> f0 = model.system().load(0.0)                       # its weight
        >>> f1 = model.inertia_load([9.81, 0.0])[model.system().free]  # 1 g sideways
        >>> k = problem.rigid_limit(f0, f1, 2.0)
        >>> bool(abs(k / np.tan(np.radians(30.0)) - 1) < 1e-3)  # tan φ
        True
        """

        def holds(k: float) -> bool | None:
            return self._balances(f0 + k * f1, damage)

        at_zero = holds(0.0)
        if not at_zero:
            return None
        at_max = holds(k_max)
        if at_max is None:
            return None
        if at_max:
            return float("inf")
        lo, hi = 0.0, k_max
        while hi - lo > tol * max(hi, 1e-3):
            mid = 0.5 * (lo + hi)
            ok = holds(mid)
            if ok is None:
                return None
            lo, hi = (mid, hi) if ok else (lo, mid)
        return lo

    def with_laws(self, laws: PairLaws) -> StaticInterfaceProblem:
        """This problem (its factorisation, W_pin and border, built once) for other laws of
        the same pairs, e.g. the model's strengths divided by a factor
        (:meth:`PairLaws.reduced`; :meth:`InterfaceSolver.with_laws`)."""
        other = copy.copy(self)
        other.laws = laws
        other.solver = self.solver.with_laws(laws)
        return other

    @property
    def operator(self) -> sp.csr_matrix:
        """G on the free DOFs."""
        return self.op.G


__all__ = [
    "RIGID_FACTOR_RANGE",
    "RIGID_FACTOR_TOL",
    "RIGID_SHARE_MIN",
    "RigidCheck",
    "StaticInterfaceProblem",
    "pair_strengths",
    "pins",
]
