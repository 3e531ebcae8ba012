"""Static analysis: K u = f on the free DOFs, with interfaces and floating blocks.

Without interfaces this is the linear solve K u = f. With interfaces it is the static
interface problem of method.md §5.2 with the rigid unknowns of the floating blocks
(:class:`pfeie.coupling.StaticInterfaceProblem`); the support reactions follow.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from pydantic import ValidationError

from ..coupling import (
    RIGID_FACTOR_RANGE,
    RIGID_SHARE_MIN,
    RigidCheck,
    StaticInterfaceProblem,
    relative_operator,
)
from ..errors import InterfaceError, MechanismError, ModelError, SolverError
from ..interface import FS_ROUNDOFF, OPEN, PairLaws, PairState, SolverSettings
from ..linalg import factorize
from ..model import STIFFNESS_MIN, Model
from ..typing import FloatArray, is_number, settings_message

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class StaticResult:
    """Displacements (n_points, dim) in m and support reactions (n_points, dim) in N; with
    interfaces, the pair state (forces, states) and the rigid motion of each body."""

    model: Model
    u: FloatArray
    reactions: FloatArray
    pairs: PairState | None = None
    uplift: FloatArray | None = None  # the uplift pressure at every pair (Pa), if any
    cracks: tuple[float, ...] = ()  # the crack length of each uplift (m), from its heel

    def stress(self) -> FloatArray:
        """Nodal stresses (n_points, 3, 3), Pa."""
        return self.model.nodal_stress(self.u)

    def rigid_motion(self) -> FloatArray:
        """Rigid motion of every body (n_bodies, 3 or 6): centroid translation, rotation."""
        return self.model.rigid_motion(self.u)


def solve_static(
    model: Model, *, t: float = 0.0, backend: str = "auto",
    settings: SolverSettings | dict[str, Any] | None = None, damage: PairState | None = None,
) -> StaticResult:  # fmt: skip
    """Solve the static problem under the loads at time ``t``.

    The reactions are r = K u − f − Gᵀ X on the prescribed DOFs (zero elsewhere); their
    sum balances the applied loads.

    ``settings``: the interface solver's :class:`~pfeie.SolverSettings`, or its fields as
    a dict (``{"tolerance": 1e-10}``), as :class:`pfeie.Dynamic` takes its own.

    ``damage``: the pair state an earthquake left (``DynamicResult.final.pairs``), for the
    **post-earthquake** static state (USACE EM 1110-2-6053, §7; FERC Engineering
    Guidelines, Chapter III): the same static loads on the joints as the earthquake left
    them, each pair it broke at its residual strength (c_r, φ_r, no tension), its slip
    path carried over, and an uplift's crack from the heel (the pairs it broke from the
    heel, and those open; a joint that starts broken, ``initial = "broken"``, cracks where
    it opens, as in the static state) at full headwater. The residual slips and openings are small
    beside the blocks, so the geometry is the undeformed one.

    >>> import pfeie as pf
    >>> m = pf.Model(pf.rectangle(2.0, 1.0, 4, 2), [pf.Block("all", pf.Elastic(1e6, 0.0))])
    >>> m.fix("xmin", 0); m.fix("ymin", 1); m.add_traction("xmax", [1e3, 0.0])
    >>> r = pf.solve_static(m)
    >>> round(float(r.u[:, 0].max()), 9)  # = σ L / E
    0.002
    """
    if not isinstance(model, Model):
        raise ModelError(f"solve_static: expected a pfeie.Model (that of a model file is "
                         f"pfeie.io.load_job(path).model), got {type(model).__name__}")  # fmt: skip
    if not is_number(t) or not np.isfinite(t):
        raise ModelError(f"solve_static: t: expected a finite time (s), got {t!r}")
    if isinstance(settings, dict):  # its fields as a mapping, as pfeie.Dynamic takes them
        try:
            settings = SolverSettings.model_validate(settings, strict=True)
        except ValidationError as exc:
            raise ModelError(f"solve_static: settings: {settings_message(exc)}") from None
    if settings is not None and not isinstance(settings, SolverSettings):
        raise ModelError(f"solve_static: settings: expected a pfeie.SolverSettings (or its "
                         f"fields as a dict), got {type(settings).__name__} "
                         f"{settings!r}")  # fmt: skip
    if damage is not None and not isinstance(damage, PairState):
        raise ModelError(f"solve_static: damage: expected the pair state a run left "
                         f"(DynamicResult.final.pairs), got {type(damage).__name__}")  # fmt: skip
    system = model.system()
    f_free = system.load(t)
    d = model.dim
    if model.pairs is None:
        try:
            F = factorize(system.K, spd=True, backend=backend)
        except MechanismError as exc:
            free = model.unrestrained_modes()
            if not free:
                raise
            raise MechanismError(f"{exc}: {free}") from None
        u_free = F.solve(f_free)
        u = system.expand(u_free)
        r = model.stiffness() @ u - model.load_vector(t)
        reactions = np.zeros_like(r)
        reactions[system.prescribed] = r[system.prescribed]
        return StaticResult(model, u.reshape(-1, d), reactions.reshape(-1, d))
    problem = StaticInterfaceProblem(model, system, backend=backend, settings=settings)
    return solve_pairs(problem, f_free, model.load_vector(t), damage=damage)


def solve_pairs(
    problem: StaticInterfaceProblem, f_free: FloatArray, f_all: FloatArray,
    start: PairState | None = None, *, damage: PairState | None = None, explain: bool = True,
) -> StaticResult:  # fmt: skip
    """The static state of a model with interfaces under the free-DOF loads ``f_free``
    (those of :meth:`LinearSystem.load`, the prescribed displacements included) whose
    values on all DOFs are ``f_all`` (N; for the reactions), with ``problem`` built once
    (its factorisations serve any number of load cases): the pair problem, and with
    uplifts the crack and its uplift settled together. ``start``: the pair state under
    nearby loads, the pair solver's first iterate (a load step; see
    :meth:`~pfeie.interface.InterfaceSolver.solve`); ``damage``: the pair state an
    earthquake left (:func:`solve_static`). Where no equilibrium holds floating blocks,
    the error names the blocks that not even rigid blocks with the joints' strengths can
    balance (:meth:`~pfeie.coupling.StaticInterfaceProblem.rigid_check`; ``explain``
    False leaves that check out, for the limit searches, which expect failures)."""
    model, system = problem.model, problem.system
    d = model.dim
    cracked = None
    if damage is not None:
        n = 0 if model.pairs is None else model.pairs.n
        if damage.broken.shape != (n,) or damage.path.shape != (n,):
            raise ModelError(f"post-earthquake static state: the damage is a state of "
                             f"{damage.broken.size} pairs; this model has {n}")  # fmt: skip
        # the pairs the loads broke (not those of joints that start broken, initial =
        # "broken", whose crack the uplift follows where they open, as in the static state:
        # counted cracked end to end at full headwater, a pre-existing joint of a dam
        # under a record of zeros lost 24 % of its normal force and of its FS)
        cracked = damage.broken & ~model.pair_laws.initially_broken

    def share(f: FloatArray) -> RigidCheck | None:
        """The rigid-block check of the loads ``f`` (None: not asked, or it failed)."""
        if not explain:
            return None
        try:
            check = problem.rigid_check(f, damage)
            P = model.pairs
            assert P is not None
            touched = [n for n in P.names if np.isfinite(check.normal[P.of(n)]).all()
                       and _touches_floating(model, n)]  # fmt: skip
            if len(touched) > 1 and np.nansum(check.share) > RIGID_SHARE_MIN:
                # where the blocks fail: each joint alone, the others unbreakable (a
                # stack of floating blocks: the check's unbalance may land on any of them)
                alone: list[tuple[str, float]] = []
                for name in touched:
                    strong = np.ones(P.n, dtype=bool)
                    strong[P.of(name)] = False
                    one = problem.rigid_check(f, damage, strong=strong)
                    if not np.isfinite(one.normal).all():  # the check failed: unknown
                        alone = []
                        break
                    alone.append((name, float(np.nansum(one.share))))
                check = check._replace(alone=tuple(alone))
            if np.nansum(check.share) > RIGID_SHARE_MIN:
                check = check._replace(factor=problem.rigid_factor(f, damage))
            return check
        except (ValueError, RuntimeError, np.linalg.LinAlgError) as exc:
            log.debug("static analysis: the rigid-block check failed: %s", exc)
            return None

    def solve(f: FloatArray) -> tuple[FloatArray, PairState]:
        try:
            return problem.solve(f, start=start, damage=damage)
        except MechanismError as exc:
            why = _floating(model, damaged=damage is not None, share=share(f))
            raise MechanismError(f"{exc}. {why}") from None
        except InterfaceError as exc:
            where = model.pair_text(exc.pairs)  # the pairs it names, by joint and place
            if not model.floating_bodies().size:
                raise InterfaceError(f"{exc}{where}", exc.pairs) from None
            # with floating blocks, a static problem without a solution ends here too (no
            # pattern balances them), as may one the solver fails on: say what to check,
            # with the rigid-block check's verdict where it has one
            why = _floating(model, found=False, damaged=damage is not None, share=share(f))
            raise InterfaceError(f"{exc}{where} {why}", exc.pairs) from None

    # the crack of an uplift: its pairs open from the heel (and, after an earthquake, the
    # pairs it broke from the heel)
    p, cracks = model.uplift_pressure(cracked)
    f_up = model.uplift_load(p)
    u_free, st = solve(f_free + f_up[system.free])
    # a crack whose full uplift nothing held (then p is a relaxed step towards its
    # pressure, not the pressure of ``cracks``); every such crack met so far; and the
    # cracks whose full uplift was held: from such a step on, the iteration depends on
    # the crack alone, so reaching one again is a cycle
    unheld: tuple[float, ...] | None = None
    not_held: set[tuple[float, ...]] = set()
    held: dict[tuple[float, ...], tuple[FloatArray, FloatArray, FloatArray, PairState]] = {}
    for _ in range(_CRACK_ITERATIONS if model.uplifts else 0):
        # the uplift follows the crack and the crack the uplift: full headwater in the part
        # open from the heel, until the crack settles
        p_new, new = model.uplift_pressure(
            st.state == OPEN if cracked is None else (st.state == OPEN) | cracked
        )
        if new == cracks and unheld is None:
            break
        if unheld is not None and all(a >= b for a, b in zip(new, unheld, strict=True)):
            # a relaxed step did not shorten the crack: it runs on under its own uplift
            log.debug("static analysis: the relaxed step towards the crack %s m gave %s m",
                      _lengths(unheld), _lengths(new))  # fmt: skip
            raise MechanismError(_runs_on(model, new))
        # a full step can overshoot the settled crack into loads that no equilibrium
        # holds (the whole base opening at once); then relax: p + ω (p_new − p), ω halved
        # down to 1/16, before concluding that the joint cannot hold its block
        omega = 1.0
        while True:
            p_try = p_new if omega == 1.0 else p + omega * (p_new - p)
            f_try = model.uplift_load(p_try)
            try:
                u_free, st = solve(f_free + f_try[system.free])
                break
            except (MechanismError, InterfaceError):
                if omega <= 1.0 / 16.0:
                    raise
                omega *= 0.5
                log.info("static analysis: uplift of the crack %s m not held; relaxed step "
                         "%g", _lengths(new), omega)  # fmt: skip
        unheld = None if omega == 1.0 else tuple(new)
        if unheld is not None:
            not_held.add(unheld)
        elif tuple(new) in held:
            # a cycle (going round it cost minutes of failing pair solves): through a
            # crack whose full uplift nothing held, the crack runs on once it reaches it;
            # else it alternates between lengths that each hold
            log.debug("static analysis: the crack %s m, held under its full uplift, again",
                      _lengths(new))  # fmt: skip
            if not_held:
                raise MechanismError(_runs_on(model, max(not_held)))
            # it alternates between lengths that each hold under their full uplift (the
            # tip between two pairs, at the verge of opening further): the cycle's longest
            # (on every joint with uplift), with full headwater in it, is an equilibrium
            # under more uplift than the tip's, and is taken (a dam engineer's section on
            # stiff rock got no answer); the cracks before the cycle are passing steps
            order = list(held)
            cycle = order[order.index(tuple(new)) :]
            longest = tuple(max(c[i] for c in cycle) for i in range(len(new)))
            if longest not in held:  # no state of the cycle is the longest on every joint
                raise SolverError(
                    f"uplift: the crack from the heel alternates between lengths that each "
                    f"hold under their full uplift ({'; '.join(_lengths(c, model) for c in cycle)}"
                    " m): the joints are on the verge of opening further")  # fmt: skip
            p, f_up, u_free, st = held[longest]
            cracks = list(longest)
            (log.warning if explain else log.debug)(
                "uplift: the crack from the heel alternates between lengths that each hold "
                "under their full uplift (%s m; its tip between two pairs, on the verge of "
                "opening further): the longest, %s m, is taken with full headwater in it "
                "(on the safe side)", "; ".join(_lengths(c, model) for c in sorted(cycle)),
                _lengths(longest, model))  # fmt: skip
            break
        else:
            held[tuple(new)] = (p_try, f_try, u_free, st)
        p, cracks, f_up = p_try, new, f_try
    else:
        if model.uplifts:
            raise SolverError(
                f"uplift: the crack from the heel did not settle in {_CRACK_ITERATIONS} "
                f"static solves (crack lengths {_lengths(cracks, model)} m): "
                "the joint may be on the verge of opening through"
            )
    G = relative_operator(model.pairs, model.n_dof)
    pres = system.prescribed
    u = system.expand(u_free)
    st.w = (G @ u).reshape(-1, d)
    r = model.stiffness() @ u - f_all - f_up - G.T @ st.X.ravel()
    reactions = np.zeros_like(r)
    reactions[pres] = r[pres]
    return StaticResult(model, u.reshape(-1, d), reactions.reshape(-1, d), st,
                        p if model.uplifts else None, tuple(cracks))  # fmt: skip


#: static solves at most to settle the crack and its uplift together
_CRACK_ITERATIONS = 50


def _runs_on(model: Model, cracks: Sequence[float]) -> str:
    """The message of a crack that runs on under its own uplift from ``cracks`` (m)."""
    return ("static analysis: the crack from the heel grows under its own uplift (full "
            f"headwater in the open part) to {_lengths(cracks, model)} m, where no equilibrium "
            f"holds. {_floating(model, found=False)}")  # fmt: skip


def _lengths(cracks: Sequence[float], model: Model | None = None) -> str:
    """Crack lengths for a message (m, the unit after them): each named by its uplift's
    joint when ``model`` is given and has more than one uplift."""
    if model is not None and len(model.uplifts) > 1:
        return ", ".join(f"{u.interface!r} {c:.4g}"
                         for u, c in zip(model.uplifts, cracks, strict=True))  # fmt: skip
    return ", ".join(f"{c:.4g}" for c in cracks)


#: what an unbalance in the rigid-block check means, in the mechanism's message
_NOT_RIGID = (
    "not even as rigid blocks can pair forces within their joints' strength "
    "balance the static loads, so they would slide, open or overturn."
)


def _touches_floating(model: Model, joint: str) -> bool:
    """Whether the joint ``joint`` has a floating block on one of its sides."""
    P = model.pairs
    assert P is not None
    body = model.body_of_node
    idx = P.of(joint)
    floating = np.isin(np.r_[body[P.node_a[idx]], body[P.node_b[idx]]],
                       model.floating_bodies())  # fmt: skip
    return bool(floating.any())


def _floating(model: Model, found: bool = True, damaged: bool = False,
              share: RigidCheck | None = None) -> str:  # fmt: skip
    """What a static mechanism means for this model: the floating bodies (no support)
    and the joints that must hold them, with what to check; ``found`` False when the
    solver ended without an answer rather than on a singular pattern (then the loads are
    beyond the limit of equilibrium, or so near it that no answer was found);
    ``damaged``: the post-earthquake state (the joints as a record left them);
    ``share``: the rigid-block check per body
    (:meth:`~pfeie.coupling.StaticInterfaceProblem.rigid_check`), which names the blocks
    that no equilibrium can hold, or says that rigid blocks could be held."""
    assert model.pairs is not None
    body = model.body_of_node
    names = model.body_names()
    P = model.pairs
    parts, on_joints = [], {}
    for b in model.floating_bodies():
        on = (body[P.node_a] == b) | (body[P.node_b] == b)
        joints = [n for n in P.names if on[P.of(n)].any()]
        on_joints[b] = f"{names[b]!r} on {', '.join(repr(j) for j in joints) or 'no joint'}"
        parts.append(on_joints[b])
    which = "; ".join(parts) if parts else "none found"
    unheld = model.unsupported_bodies()
    if unheld.size:
        # no joint strength can help: name the blocks that nothing holds
        return (
            "No support holds the block(s) " + ", ".join(repr(names[b]) for b in unheld)
            + ": neither they nor the blocks they touch through joints have a support, so "
            "the static loads move them as rigid bodies. Add [[supports]] (Model.fix) to "
            "the foundation's outer faces"
        )  # fmt: skip
    partly = model.partly_supported_groups()
    if partly:
        # nor here: the supports themselves leave a rigid motion free
        return "The supports leave free the rigid motion of " + "; ".join(
            f"the block(s) {', '.join(repr(n) for n in group)} ({'; '.join(modes)})"
            for group, modes in partly
        ) + (": no joint can hold it. Support the foundation in every component "
             "(components of [[supports]], or Model.fix), or on two faces")  # fmt: skip
    shares = {} if share is None else {b: float(share.share[b]) for b in on_joints}
    unbalanced = [b for b, v in shares.items() if np.isfinite(v) and v > RIGID_SHARE_MIN]
    if unbalanced:
        assert share is not None
        fails = [(j, v) for j, v in share.alone if v > RIGID_SHARE_MIN]
        holds = [j for j, v in share.alone if not v > RIGID_SHARE_MIN]
        if fails:
            # the joints that cannot hold even with every other joint unbreakable: where
            # the blocks fail, with all the blocks on them
            head = (
                "No static equilibrium holds the floating block(s) ("
                + "; ".join(on_joints[b] for b in on_joints)
                + f"): {_NOT_RIGID} "
                + "; ".join(f"{j!r} cannot hold the blocks on it even with every other "
                            "joint unbreakable" for j, _ in fails)
                + (f"; {', '.join(repr(j) for j in holds)} "
                   f"{'holds' if len(holds) == 1 else 'hold'} alone" if holds else "")
                + "."
            )  # fmt: skip
        else:
            # the floating blocks that lean on a named one: their loads reach it through the
            # joint between them (the unbalance lands where the check can put it)
            leaning = []
            for b in unbalanced:
                for c in on_joints:
                    if c in unbalanced:
                        continue
                    both = ((body[P.node_a] == b) & (body[P.node_b] == c)) | (
                        (body[P.node_a] == c) & (body[P.node_b] == b))  # fmt: skip
                    # in compression in the check's answer: a joint that parts bears nothing
                    pressed = both & (share.normal > RIGID_SHARE_MIN * np.abs(share.normal).max())
                    via = [n for n in P.names if pressed[P.of(n)].any()]
                    if via:
                        leaning.append(f"{names[c]!r} on {names[b]!r} through "
                                       f"{', '.join(repr(j) for j in via)}")  # fmt: skip
            head = (
                "No static equilibrium holds the floating block(s) ("
                + "; ".join(f"{on_joints[b]}: unbalanced by about {100 * shares[b]:.3g} % "
                            "of its load" for b in unbalanced)
                + f"): {_NOT_RIGID}"
                + (f" Floating blocks press on it ({'; '.join(leaning)}): the unbalance is "
                   "theirs together, placed where the check could put it." if leaning
                   else "")
            )  # fmt: skip
        if share.factor is not None:
            head += (
                f" As rigid blocks they balance only with every joint strength (c, tan φ, "
                f"σ_t) multiplied by {1.0 / share.factor:.4g}: a rigid-block factor of safety "
                f"of {share.factor:.4g} by strength reduction (limit equilibrium"
                + ("; its 3D friction cone is an octagon, up to 8 % high" if model.dim == 3
                   else "") + ")."
            )  # fmt: skip
        else:  # not even with every strength multiplied by RIGID_FACTOR_RANGE
            head += (
                f" As rigid blocks they do not balance even with every joint strength "
                f"multiplied by {RIGID_FACTOR_RANGE:g}: a mechanism that friction and "
                "cohesion cannot hold, as a block overturning (its weight's line outside "
                "its base, or pushed over by the lateral loads) or a hinge mechanism (an "
                "arch or a wall too thin for its loads)."
            )  # fmt: skip
    elif any(np.isfinite(v) for v in shares.values()):
        head = (
            "No static equilibrium was found for the floating block(s) (" + which + "), "
            "although rigid blocks with these joints' strengths can be balanced: the "
            "loads are at the limit of equilibrium (the elastic blocks may open or slide a "
            "joint that rigid ones keep closed), blocks topple (the rigid check may put "
            "the forces low on a column's face, where a toppling column bears on its "
            "neighbour's top corner, or wedge a block against a step with friction), or "
            "the pair solver failed on them."
        )  # fmt: skip
    else:
        head = ("No static equilibrium holds the floating block(s) (" + which + ") under "
                "the static loads: their joints' strength is exceeded, so they would slide, "
                "open or overturn." if found else
                "No static equilibrium was found for the floating block(s) (" + which + "): "
                "the static loads may exceed their joints' strength (they would slide, open "
                "or overturn), or be at the limit of equilibrium.")  # fmt: skip
    if damaged:
        return (
            head + " This is the post-earthquake state: the pairs the record broke carry "
            "their residual strength (residual cohesion and friction angle, no tension) "
            "and each uplift's crack, broken or open from the heel, takes the full "
            "headwater; a joint that its broken pairs' residual strength and its intact "
            "ligament cannot hold under the static loads leaves the structure unstable "
            "after the earthquake (a post-earthquake sliding safety factor below 1): "
            "broken through, or with a crack from the heel that grows under its own "
            "uplift until the ligament is gone (the effective normal resultant inside the "
            "crack)"
        )  # fmt: skip
    soft = [f"{i.group!r}: {key} {float(v):g} Pa/m" for i in model.interfaces
            for key, v in (("normal_stiffness", i.joint.kn), ("shear_stiffness", i.joint.ks))
            if v is not None and float(v) < STIFFNESS_MIN]  # fmt: skip
    return (
        head + " Check the friction angles and cohesions (a joint that starts broken, "
        'initial = "broken", the default, has only its residual strength: '
        'initial = "intact" for a bonded joint), the loads, and the blocks\' shape (a '
        "block whose weight falls outside its base overturns whatever the friction)"
        + (
            f"; and the joint stiffnesses ({'; '.join(soft)}), far below rock and concrete "
            "joints' 1e9 to 1e12 Pa/m: a layer that soft carries the blocks only after "
            "closing by metres, beyond the small displacements the analysis takes (given in "
            "MPa/m or GPa/m?)"
            if soft
            else ""
        )
    )


def held(
    problem: StaticInterfaceProblem, f_free: FloatArray, f_all: FloatArray,
    start: StaticResult | None, what: str,
) -> tuple[StaticResult | None, int]:  # fmt: skip
    """The static state under the loads (:func:`solve_pairs`), None where no static
    equilibrium is found, and the analyses it took: the pair solver starts from
    ``start``'s pair state (under nearby loads or strengths), then, if that fails, from the
    initial state; the answer does not depend on the start
    (:meth:`~pfeie.interface.InterfaceSolver.solve`). ``what`` names the analysis in the
    debug log. The step of the limit searches (:func:`pfeie.yield_coefficient`,
    :func:`pfeie.strength_reduction`)."""
    count = 0
    for first in ([start.pairs] if start is not None else []) + [None]:
        count += 1
        log.debug("%s: static analysis", what)
        try:
            return solve_pairs(problem, f_free, f_all, first, explain=False), count
        except (MechanismError, InterfaceError, SolverError) as exc:
            log.debug("%s: no equilibrium found (%s): %s", what,
                      "warm" if first is not None else "cold", exc)  # fmt: skip
    return None, count


#: a limit search warns where, in its last state held, the pairs at junctions
#: (:meth:`~pfeie.interface.PairGeometry.junctions`) carry more than this share of the
#: governing joint's normal force and :data:`JUNCTION_RATIO` times their share of its
#: area: node-to-node friction at a corner, which grows as the mesh is refined (a row of
#: five toppling columns, φ = 50°: F = 1.386, 1.610, 1.744, 1.823 with 2, 4, 8, 16 cells
#: across a column, their feet's pairs carrying 17 to 66 % of a side joint's normal
#: force; with those pairs frictionless 1.332, 1.357, 1.362, 1.363; Goodman and Bray's
#: limit equilibrium 1.2826; dynamic runs toppled just above each mesh's factor)
JUNCTION_SHARE = 0.2
JUNCTION_RATIO = 5.0


def leans_on_junctions(force: float, area: float) -> bool:
    """Whether a joint whose pairs at junctions carry the share ``force`` of its normal
    force on the share ``area`` of its area leans on them (:data:`JUNCTION_SHARE`,
    :data:`JUNCTION_RATIO`): the test of the limit searches' warning and of the static
    state's (:func:`junction_share` gives the shares)."""
    return force > JUNCTION_SHARE and force > JUNCTION_RATIO * area


def junction_share(model: Model, st: StaticResult, joint: str) -> tuple[float, float]:
    """The share of ``joint``'s normal force (compression) that its pairs at junctions
    carry in the static state ``st``, and their share of its area; (0, 0) without pairs
    at junctions or without compression."""
    pairs, P = model.pairs, st.pairs
    if pairs is None or P is None or joint not in pairs.names:
        return 0.0, 0.0
    idx = pairs.of(joint)
    at = pairs.at_junction[idx]
    N = np.maximum(P.X[idx, -1], 0.0)
    total = float(N.sum())
    if not at.any() or not total > 0.0:
        return 0.0, 0.0
    return float(N[at].sum()) / total, float(pairs.area[idx][at].sum() / pairs.area[idx].sum())


def warn_junctions(what: str, model: Model, st: StaticResult | None, joint: str | None,
                   value: str) -> float | None:  # fmt: skip
    """The warning of a limit search (``what``, its answer ``value``) whose governing
    ``joint`` leans on its pairs at junctions in the last state held ``st``
    (:data:`JUNCTION_SHARE`); returns their share of its normal force where warned, else
    None."""
    if st is None or joint is None:
        return None
    force, area = junction_share(model, st, joint)
    if not leans_on_junctions(force, area):
        return None
    log.warning(
        "%s: at %s the pairs of %r at junctions (a block's corner where joints meet) "
        "carry %.0f %% of its normal force on %.1f %% of its area: the limit leans on "
        "node-to-node friction at corners, which grows as the mesh is refined (a "
        "loaded corner presses into the pair across it; a row of toppling columns "
        "read F = 1.39, 1.61, 1.74, 1.82 as its cells were halved, against 1.36 with "
        "its feet's pairs frictionless); refine the mesh to see whether it moves, or "
        "give the joint's end facets a joint of their own without friction "
        "(docs/theory.md, 'Two safety factors')",
        what, value, joint, 100 * force, 100 * area)  # fmt: skip
    return force


def uplift_free(model: Model, st: StaticResult | None, free: np.ndarray) -> FloatArray:
    """The nodal load of the uplift of the static state ``st`` on the free DOFs (zero
    without uplift): the rigid-block and translational checks of a limit search take it
    with the loads (a block on a joint with uplift: W tan φ / P = 6.29 without it, 5.24
    with it, as the analyses)."""
    if st is None or st.uplift is None:
        return np.zeros(free.size)
    return np.asarray(model.uplift_load(st.uplift)[free])


def joint_factors(
    laws: PairLaws, st: StaticResult, frames: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Each joint's shear capacity and shear force (N) in the static state ``st`` and
    their ratio, its sliding safety factor (∞ without shear, or with a shear at the round-off
    of its forces, :data:`~pfeie.interface.FS_ROUNDOFF`), with each pair's capacity
    under ``laws`` (the residual cohesion's ramp included:
    :meth:`~pfeie.interface.PairLaws.capacity_and_shear`)."""
    P = st.pairs
    assert P is not None
    capacity, shear = laws.capacity_and_shear(P.X, P.state == OPEN, P.broken, P.path, frames,
                                              P.s[:, -1], ramp=True)  # fmt: skip
    # a shear of the round-off of the joint's forces is none (∞, as the summary's FS)
    size = np.abs(P.X).sum(axis=1)
    noise = FS_ROUNDOFF * np.array([size[idx].sum() for idx in laws.index])
    # (and below FS_ROUNDOFF of the capacity: a factor beyond 1e10 is ∞, as the run's)
    noise = np.maximum(noise, FS_ROUNDOFF * capacity)
    with np.errstate(divide="ignore", invalid="ignore"):
        fs = np.where((shear > noise) & (shear > 0), capacity / shear, np.inf)
    return capacity, shear, fs
