"""Recording a run: time histories, the energy account, and the result.

Energy (J), accumulated over the run (method.md §8):

    kinetic + strain + modified + damping + interface + impact + algorithmic
        = external_work + correction (+ initial energy),

- ``modified``: for the default nonsmooth generalised-α, the change since the start of
  the terms Φ of the scheme's modified energy E* = T + U + Φ beyond the kinetic and
  strain energy (:meth:`NonsmoothAlpha.modified_energy`; docs/theory.md, "Energy
  identity of the smooth step"): Φ = (δh/2) vᵀMe + (δ²h²/8)(3aᵀMa + 2aᵀMe + 2eᵀMe),
  e = a − q̈ the lag of the auxiliary acceleration, δ = γ − ½; zero for the other
  schemes;
- ``external_work``: Σ Δu·f̄ of the loads (f̄ the step average; in the absolute form it
  includes the work of the moving base through the joints, and that of the supports'
  reactions on their motion, elastic and viscous: the strain energy and the damping are
  those of the whole model, supports included, so that a model moving rigidly with the
  ground holds no strain energy and dissipates nothing by a stiffness-proportional
  damping);
- ``damping``: Σ Δu·C v̄;
- ``interface``: the work dissipated (friction, contact) or stored (joint springs) at
  the pairs: for the nonsmooth generalised-α the rigid contacts' dissipation by the
  velocity-level law, −P·U⁺ a step (P = hX the step impulse, U⁺ the relative velocity
  at t_{n+1}; ≥ 0 at every step), and the springs' step-average force on the smooth
  motion; the impulses on the θ-velocity, −P·U_θ, for Moreau-Jean;
- ``impact``: the energy the impulses of the velocity correction beyond hλ take from the
  relative motion, ½Λ·(U⁺ − U⁻) = ½sΛᵀWΛ ≥ 0 (nonsmooth generalised-α);
- ``algorithmic``: the dissipation of the time scheme itself, (θ − ½)(ΔvᵀMΔv + ΔuᵀKΔu)
  per step for Moreau-Jean; for the Newmark family the rest of the balance (round-off
  for the average-acceleration rule, whose balance the trapezoidal rule closes exactly;
  the numerical dissipation of ρ∞ < 1 or HHT's α); for the default nonsmooth
  generalised-α the residual that closes the balance with the modified energy: on a
  step without impulses, position corrections
  or working pair forces exactly the scheme's dissipation D = δh²ēᵀMē ≥ 0
  (:meth:`NonsmoothAlpha.dissipation`), plus, on the other steps, what the velocity and
  position corrections leave and K = hλ_{n+1}·U⁺ − ½(λ_n + λ_{n+1})·Δw, the recorded
  right-endpoint pair work less the step average (docs/theory.md lists these terms;
  they have no sign);
- ``correction``: the potential energy that the position correction of the nonsmooth
  generalised-α adds when it moves penetrating pair nodes apart by Δq: the strain energy
  it stores less the work of the step-average load over Δq (an input: it is then
  radiated or dissipated by the scheme; ∝ Δt² as the penetrations are O(Δt));
- ``balance``: the residual of the equation above (zero to round-off with the average
  acceleration rule).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from ..assembly import principal_extremes
from ..interface import FS_ROUNDOFF, OPEN
from ..typing import FloatArray, IntArray
from ._excitation import Excitation
from ._newmark import State

if TYPE_CHECKING:
    from ._driver import Checkpoint, Dynamic, StepState

ENERGY_TERMS = ("kinetic", "strain", "modified", "external_work", "damping", "interface",
                "impact", "algorithmic", "correction")  # fmt: skip
_INPUTS = ("external_work", "correction")  # the right-hand side of the balance


def _balance(E: Mapping[str, Any], origin: tuple[float, float]) -> Any:
    """The balance of the energy terms ``E`` (numbers, or arrays over rows): the terms
    less the start's kinetic and strain energy less the inputs, summed in one order, so
    that a row streamed to a file and the run's histories hold the same bits."""
    held = sum(E[key] for key in ENERGY_TERMS if key not in _INPUTS)
    return held - sum(origin) - sum(E[key] for key in _INPUTS)


@dataclass
class DynamicResult:
    """Time histories of a PFE/IE run.

    Arrays have time first. ``probe_u``, ``probe_v``, ``probe_a`` (n_t, k, d): motion of
    the probe nodes relative to the ground (m, m/s, m/s²); ``probe_a_abs`` absolute
    accelerations. ``rigid`` (n_t, n_bodies, r): centroid translation (m) and rotation
    (rad) of every body. Pair histories (n_t, m, d) in the local frames (t…, n):
    ``X`` forces on side b (N, normal + in compression), ``w`` relative displacements
    (m, normal + opening), ``s`` slip and gap; ``state`` (n_t, m) codes 0 intact,
    1 stick, 2 slide, 3 open; ``broken`` (n_t, m). Per joint (n_t, n_joints):
    ``safety_factor``, ``joint_force`` and ``joint_moment`` (…, d and 1 or 3; N, N·m), the
    cracked extent ``joint_cracked`` (the broken pairs) and the open crack ``joint_open``
    (the broken pairs that are open), lengths in 2D (m), areas in 3D (m²;
    :meth:`pfeie.Model.joint_extent`). ``energy``: kinetic, strain, modified,
    external_work, damping, interface, impact, algorithmic, correction (J) and ``balance``
    (their residual). ``ground`` (n_t, d): the ground's displacement Σ ι d_g (m), in the
    absolute form as the supports followed it (the time scheme's integration of the
    records on the run's grid, :class:`~pfeie.dynamics.GridGround`), in the relative form
    the records' exact displacement; u − ground is a probe's motion relative to the
    ground in the absolute form.
    """

    t: FloatArray
    probes: IntArray
    probe_u: FloatArray
    probe_v: FloatArray
    probe_a: FloatArray
    probe_a_abs: FloatArray
    rigid: FloatArray
    X: FloatArray
    w: FloatArray
    s: FloatArray
    state: np.ndarray
    broken: np.ndarray
    energy: dict[str, FloatArray] = field(default_factory=dict)
    final: StepState | None = None
    iterations: np.ndarray | None = None
    wall_time: float = 0.0
    completed: bool = True
    pair_area: FloatArray = field(default_factory=lambda: np.zeros(0))
    stop_reason: str | None = None
    solver: dict[str, np.ndarray] = field(default_factory=dict)
    safety_factor: FloatArray = field(default_factory=lambda: np.zeros((0, 0)))
    envelope: dict[str, FloatArray] = field(default_factory=dict)
    joint_force: FloatArray = field(default_factory=lambda: np.zeros((0, 0, 0)))
    joint_moment: FloatArray = field(default_factory=lambda: np.zeros((0, 0, 0)))
    joint_cracked: FloatArray = field(default_factory=lambda: np.zeros((0, 0)))
    joint_open: FloatArray = field(default_factory=lambda: np.zeros((0, 0)))
    ground: FloatArray = field(default_factory=lambda: np.zeros((0, 0)))

    @property
    def normal_stress(self) -> FloatArray:
        """Joint normal stress σ = X_n/A (n_t, m), Pa, compression positive."""
        return self.X[:, :, -1] / self.pair_area

    @property
    def shear_stress(self) -> FloatArray:
        """Joint shear stress τ = X_t/A (n_t, m, d − 1), Pa, local tangent axes."""
        return self.X[:, :, :-1] / self.pair_area[None, :, None]

    @property
    def opening(self) -> FloatArray:
        """Joint opening max(s_n, 0) (n_t, m), m."""
        return np.maximum(self.s[:, :, -1], 0.0)

    @property
    def slip(self) -> FloatArray:
        """Joint slip since the start of the run, s_t − s_t(0) (n_t, m, d − 1), m."""
        return self.s[:, :, :-1] - self.s[:1, :, :-1]


ENVELOPE_KEYS = ("node_max", "node_max_time", "node_min", "node_min_time",
                 "cell_max", "cell_max_time", "cell_min", "cell_min_time")  # fmt: skip
#: the keys of an envelope with tensile strengths: the demand-capacity ratio and the
#: cumulative inelastic duration per cell, and the last time folded in (for a resume)
DCR_KEYS = ("cell_dcr", "cell_cid", "cid_last_time")

#: the acceptance of a linear time-history analysis of a gravity dam by USACE EM
#: 1110-2-6053 (2007): largest DCR, cumulative inelastic duration (s) and overstressed
#: share of the section
DCR_LIMIT, CID_LIMIT, OVERSTRESSED_LIMIT = 2.0, 0.3, 0.15


class StressEnvelope:
    """The running extremes of the principal stresses over a run, at every recorded row:
    per node the largest σ₁ and the smallest σ₃ of the nodal stress
    (:meth:`pfeie.Model.nodal_stress`), per cell those over its quadrature points, each
    with the time it was reached (Pa, tension positive; s). The stress is the small-strain
    stress of the total displacement (the static state included), a row's cost the sparse
    products of :attr:`pfeie.Model.stress_operators` (the strains at the points, then the
    nodes from the point stresses) and the principal extremes over contiguous rows;
    cells of no block and their nodes hold NaN.

    Where the cells' materials have a tensile strength f_t
    (:attr:`pfeie.Model.cell_tensile_strength`), the envelope also keeps the measures of
    USACE EM 1110-2-6053 per cell: the demand-capacity ratio DCR = max σ₁ / f_t
    (``cell_dcr``, σ₁ the largest over the cell's quadrature points; negative if the cell
    never is in tension) and the cumulative inelastic duration (``cell_cid``, s): the sum
    of the intervals h = t − t_prev between recorded rows at whose end σ₁ > f_t (one row's
    comparison on the σ₁ the envelope has just found; within h of the exact time above
    f_t per excursion). NaN for cells without f_t.

    >>> import pfeie as pf
    >>> mesh = pf.rectangle(1.0, 1.0, 1, 1, cell="quad")
    >>> _ = mesh.add_cell_group("b", lambda x: x[:, 0] > -1)
    >>> model = pf.Model(mesh, [pf.Block("b", pf.Elastic(1e9, 0.0, 2000.0))])
    >>> env = StressEnvelope(model)
    >>> u = np.zeros(model.n_dof); u[0::2] = 1e-3 * mesh.points[:, 0]   # ε_xx = 1e-3
    >>> env.update(0.5, u); env.update(1.0, -u)
    >>> env.values["cell_max"], env.values["cell_max_time"], env.values["cell_min_time"]
    (array([1000000.]), array([0.5]), array([1.]))
    """

    def __init__(self, model: Any, values: dict[str, FloatArray] | None = None) -> None:
        self.op = model.stress_operators
        cell = self.op.cell
        self._starts = np.flatnonzero(np.r_[True, cell[1:] != cell[:-1]])
        self._cells = cell[self._starts]
        n_cells = sum(len(c) for c in model.mesh.cells.values())
        n_nodes = model.mesh.n_points
        self._nodes = np.asarray(model.active_nodes)
        # the per-row cost: cells of one number of points fold by a reshape, and when every
        # node and cell is in a block the extremes update in place (views, not gathers)
        n_pts = cell.size
        nq = n_pts // max(self._starts.size, 1)
        self._nq = nq if nq * self._starts.size == n_pts and np.array_equal(
            self._starts, np.arange(0, n_pts, max(nq, 1))) else 0  # fmt: skip
        self._node_idx: np.ndarray | slice = (
            slice(None) if np.array_equal(self._nodes, np.arange(n_nodes)) else self._nodes
        )
        self._cell_idx: np.ndarray | slice = (
            slice(None) if np.array_equal(self._cells, np.arange(n_cells)) else self._cells
        )
        # plane states: the yz and xz components vanish (σ₁, σ₃ in closed form, from the
        # centre, half-difference and shear of Mohr's circle and σ_zz at each point)
        self._plane = self.op.plane
        if self._plane:
            op = self.op
            self._centre = op.lam + op.mu  # c = (λ + μ) tr ε
            self._mohr = np.empty((4 if op.plane_strain else 3, op.n_q))
        ft = np.asarray(model.cell_tensile_strength)
        self._ft = ft[self._cells] if np.isfinite(ft).any() else None
        self.tensile = ft
        self._last_t = np.nan
        if values is not None:
            self.values = {k: np.array(values[k], dtype=float) for k in ENVELOPE_KEYS}
            if self._ft is not None:
                self.values["cell_cid"] = np.array(values["cell_cid"], dtype=float)
                self._last_t = float(np.asarray(values["cid_last_time"]).ravel()[0])
            return
        nan_n, nan_c = np.full(n_nodes, np.nan), np.full(n_cells, np.nan)
        self.values = {k: (nan_n if k.startswith("node") else nan_c).copy()
                       for k in ENVELOPE_KEYS}  # fmt: skip
        if self._ft is not None:
            self.values["cell_cid"] = np.where(np.isfinite(ft), 0.0, np.nan)
        for k in ("node_max", "cell_max"):
            self.values[k][self._nodes if k == "node_max" else self._cells] = -np.inf
        for k in ("node_min", "cell_min"):
            self.values[k][self._nodes if k == "node_min" else self._cells] = np.inf

    def _extremes(self, s: FloatArray) -> tuple[FloatArray, FloatArray]:
        """σ₁ and σ₃ of the component-major Voigt rows ``s`` (6, N)
        (:func:`principal_extremes`)."""
        return principal_extremes(s.T)

    @staticmethod
    def _plane_extremes(m: FloatArray) -> tuple[FloatArray, FloatArray]:
        """σ₁ and σ₃ of plane states from the rows ``m`` (3 or 4, N) of Mohr's circle in
        the plane, its centre c = (σ_xx + σ_yy)/2, half-difference a = (σ_xx − σ_yy)/2 and
        shear b = σ_xy, and σ_zz (a fourth row; zero without it, plane stress):
        σ₁ = max(c + R, σ_zz), σ₃ = min(c − R, σ_zz), R = √(a² + b²)."""
        c, a, b = m[0], m[1], m[2]
        R = a * a
        R += b * b
        np.sqrt(R, out=R)
        hi, lo = c + R, c - R
        zz = m[3] if m.shape[0] == 4 else 0.0
        return np.maximum(hi, zz, out=hi), np.minimum(lo, zz, out=lo)

    def _point_and_node_extremes(self, u: FloatArray) -> tuple[FloatArray, ...]:
        """σ₁ and σ₃ at the points and at the (active) nodes of the full displacement
        vector ``u``. In plane states from the strains ε = B u: Mohr's circle at each point
        is c = (λ + μ) tr ε, a = μ (ε_xx − ε_yy), b = μ γ_xy, with σ_zz = λ tr ε in plane
        strain; these rows are linear in σ, so the nodes take the same extrapolation of
        them (:meth:`~pfeie.model.StressOperators.nodal_values`) as of the stress."""
        op = self.op
        if self._plane:
            n = op.n_q
            e = op.strain @ u
            m = self._mohr
            c = m[0]
            np.add(e[:n], e[n : 2 * n], out=c)  # tr ε
            if m.shape[0] == 4:
                np.multiply(op.lam, c, out=m[3])  # σ_zz, plane strain
            c *= self._centre
            np.subtract(e[:n], e[n : 2 * n], out=m[1])
            m[1] *= op.mu
            np.multiply(op.mu, e[2 * n :], out=m[2])
            mn = op.nodal_values(m)
            if not isinstance(self._node_idx, slice):
                mn = mn[:, self._nodes]
            return (*self._plane_extremes(m), *self._plane_extremes(mn))
        sq = op.components(u)
        sn = op.nodal_components(sq)
        if not isinstance(self._node_idx, slice):
            sn = sn[:, self._nodes]
        return (*self._extremes(sq), *self._extremes(sn))

    def update(self, t: float, u: FloatArray) -> None:
        """Fold in the stress of the full displacement vector ``u`` at time ``t``."""
        v = self.values
        hi_q, lo_q, hi_n, lo_n = self._point_and_node_extremes(u)
        if self._nq:  # point by point, in the order of reduceat (the same bits)
            hi_c, lo_c = hi_q[:: self._nq].copy(), lo_q[:: self._nq].copy()
            for j in range(1, self._nq):
                np.maximum(hi_c, hi_q[j :: self._nq], out=hi_c)
                np.minimum(lo_c, lo_q[j :: self._nq], out=lo_c)
        else:
            hi_c = np.maximum.reduceat(hi_q, self._starts)
            lo_c = np.minimum.reduceat(lo_q, self._starts)
        for key, idx, new, up in (("node_max", self._node_idx, hi_n, True),
                                  ("node_min", self._node_idx, lo_n, False),
                                  ("cell_max", self._cell_idx, hi_c, True),
                                  ("cell_min", self._cell_idx, lo_c, False)):  # fmt: skip
            if isinstance(idx, slice):  # every node (cell): in place
                old = v[key]
                better = new > old if up else new < old
                np.copyto(old, new, where=better)
                v[key + "_time"][better] = t
                continue
            old = v[key][idx]
            better = new > old if up else new < old
            v[key][idx[better]] = new[better]
            v[key + "_time"][idx[better]] = t
        if self._ft is not None:  # the time above f_t: the interval since the last row
            h = t - self._last_t if np.isfinite(self._last_t) else 0.0
            if h > 0:
                above = hi_c > self._ft
                if isinstance(self._cell_idx, slice):
                    v["cell_cid"][above] += h
                else:
                    v["cell_cid"][self._cells[above]] += h
            self._last_t = t

    def snapshot(self) -> dict[str, FloatArray]:
        """A copy of the current envelope (for a checkpoint or a result); with tensile
        strengths also ``cell_dcr`` and ``cid_last_time`` (:data:`DCR_KEYS`)."""
        out = {k: a.copy() for k, a in self.values.items()}
        if self._ft is not None:
            out["cell_dcr"] = self.values["cell_max"] / self.tensile
            out["cid_last_time"] = np.array([self._last_t])
        return out


def envelope_extremes(envelope: dict[str, FloatArray],
                      points: FloatArray) -> dict[str, Any] | None:  # fmt: skip
    """The extremes of a stress envelope over the nodes: the largest σ₁ and the smallest
    σ₃ (Pa), where (m) and when (s); None without an envelope."""
    if not envelope or not np.isfinite(envelope["node_max"]).any():
        return None
    out: dict[str, Any] = {}
    for key, name, pick in (("node_max", "max_principal", np.nanargmax),
                            ("node_min", "min_principal", np.nanargmin)):  # fmt: skip
        k = int(pick(envelope[key]))
        out[f"{name}_Pa"] = float(envelope[key][k])
        out[f"{name}_at_m"] = points[k].round(4).tolist()
        out[f"{name}_time_s"] = float(envelope[key + "_time"][k])
    return out


def demand_capacity(envelope: dict[str, FloatArray], volumes: FloatArray,
                    centres: FloatArray) -> dict[str, Any] | None:  # fmt: skip
    """The EM 1110-2-6053 measures of a stress envelope with tensile strengths (None
    without): the largest demand-capacity ratio DCR = σ₁/f_t over the cells, where (the
    cell's centre ``centres``, m) and when; the largest cumulative inelastic duration
    (s) and where; the overstressed share, the volume (2D: area) of the cells with
    DCR > 1 over that of the cells with a tensile strength (``volumes`` per cell); and
    the verdict of a linear time-history evaluation of a gravity dam: "linear" (DCR ≤ 1),
    "acceptable" (DCR ≤ 2, CID ≤ 0.3 s and at most 15 % overstressed), else "nonlinear
    analysis required".

    >>> env = {"cell_dcr": np.array([0.5, 1.5, np.nan]), "cell_cid": np.array([0, .1, np.nan]),
    ...        "cell_max_time": np.array([1.0, 2.0, 0.0])}
    >>> d = demand_capacity(env, np.array([3.0, 1.0, 5.0]), np.zeros((3, 2)))
    >>> d["max_dcr"], d["max_cid_s"], d["overstressed_share"], d["verdict"]
    (1.5, 0.1, 0.25, 'nonlinear analysis required')
    """
    dcr = envelope.get("cell_dcr")
    if dcr is None or not np.isfinite(dcr).any():
        return None
    cid = envelope["cell_cid"]
    have = np.isfinite(dcr)
    k, j = int(np.nanargmax(dcr)), int(np.nanargmax(cid))
    over = have & (dcr > 1.0)
    share = float(volumes[over].sum() / volumes[have].sum())
    out: dict[str, Any] = {
        "max_dcr": float(dcr[k]), "max_dcr_at_m": centres[k].round(4).tolist(),
        "max_dcr_time_s": float(envelope["cell_max_time"][k]),
        "max_cid_s": float(cid[j]), "max_cid_at_m": centres[j].round(4).tolist(),
        "overstressed_share": share,
    }  # fmt: skip
    if out["max_dcr"] <= 1.0:
        out["verdict"] = "linear"
    elif (out["max_dcr"] <= DCR_LIMIT and out["max_cid_s"] <= CID_LIMIT
          and share <= OVERSTRESSED_LIMIT):  # fmt: skip
        out["verdict"] = "acceptable"
    else:
        out["verdict"] = "nonlinear analysis required"
    return out


class EnergyAccount:
    """The running sums of the energy terms (see the module docstring)."""

    def __init__(self, an: Dynamic, excitation: Excitation) -> None:
        self.an, self.ex = an, excitation
        self.acc = dict.fromkeys(ENERGY_TERMS[2:], 0.0)
        # the last state's Φ, by the identity of the state and of the analysis whose step
        # size it is taken in
        self._phi: tuple[State, Dynamic, float] | None = None

    def modified(self, state: State, an: Dynamic | None = None) -> float:
        """Φ of a state of the nonsmooth generalised-α (J) in the scheme of ``an``
        (default the run's; Φ depends on the step size), the last one kept: a step asks
        for its start, which the previous step of the same size asked for as its end."""
        an = self.an if an is None else an
        if self._phi is not None and self._phi[0] is state and self._phi[1] is an:
            return self._phi[2]
        assert an.ga is not None
        value = an.ga.modified_energy(state)
        self._phi = (state, an, value)
        return value

    def add_step(self, cur: StepState, nxt: StepState, an: Dynamic | None = None) -> None:
        """Add the work of the step cur → nxt, taken by the analysis ``an`` (default the
        run's; an event's sub-steps are taken by its analysis at dt/k). For the nonsmooth
        generalised-α, the step's change of Φ is taken in its own step size at both ends
        (``modified`` sums these changes; the difference of Φ between the two step sizes at
        an event's ends is no step's, so ``algorithmic`` stays D plus the corrections'
        terms; the balance closes either way)."""
        an = self.an if an is None else an
        acc = self.acc
        ex, k0, k1 = self.ex, cur.kin, nxt.kin
        if ex.supports_work:
            # the supports' share, where they are displaced: the strain energy of the
            # whole model and the damping's work on the supports' motion, both added to
            # the external work too (the reactions' work on the supports' motion), which
            # leaves the other terms of the balance as the free DOFs give them
            extra = ex.support_energy(k1.t, k1.u) - ex.support_energy(k0.t, k0.u)
            damp = ex.support_damping_work(k0.t, k1.t, k0.u, k1.u, k0.v, k1.v)
            acc["external_work"] += extra + damp
            acc["damping"] += damp
        if an.mj is not None:
            self._add_moreau_jean(an, cur, nxt)
            return
        if an.ga is not None:
            self._add_nonsmooth_alpha(an, cur, nxt)
            return
        # the Newmark family (no interfaces): loads and damping by the trapezoidal rule,
        # and ``algorithmic`` the rest of the balance: round-off for the average
        # acceleration (β = 1/4, γ = 1/2, whose balance the trapezoidal rule closes
        # exactly), the scheme's numerical dissipation for ρ∞ < 1 or HHT's α
        du = nxt.kin.u - cur.kin.u
        ext = 0.5 * float(du @ (cur.kin.f + nxt.kin.f))
        damp = _damping_work(an, du, cur.kin, nxt.kin) if an.system.C is not None else 0.0
        dT = 0.5 * (an.mass_product(nxt.kin.v) - an.mass_product(cur.kin.v))
        dU = an.strain_energy(nxt.kin.u) - an.strain_energy(cur.kin.u)
        acc["external_work"] += ext
        acc["damping"] += damp
        acc["algorithmic"] += ext - dT - dU - damp

    def _add_nonsmooth_alpha(self, an: Dynamic, cur: StepState, nxt: StepState) -> None:
        """The nonsmooth generalised-α step: loads and damping by the trapezoidal rule;
        ``interface`` the rigid pairs' dissipation by the velocity-level law, −P·U⁺ with
        P = hX the step impulse and U⁺ the relative velocity at t_{n+1} (≥ 0: friction
        and contact), and for joints with springs −½(λ_n + λ_{n+1})·Δw on the smooth
        motion, which is the change of their elastic energy exactly while they stick (a
        spring is a smooth force); ``impact`` the energy the impulses beyond hλ take from
        the relative motion, ½Λ·(U⁺ − U⁻) = ½sΛᵀWΛ ≥ 0 with Λ = P − hλ;
        ``modified`` the change of Φ (:meth:`NonsmoothAlpha.modified_energy`) and
        ``algorithmic`` what closes the balance with it: D ≥ 0 on a smooth step, plus
        what the corrections leave (docs/theory.md, "Energy identity of the smooth
        step")."""
        acc = self.acc
        k0, k1 = cur.kin, nxt.kin
        du = k1.u - k0.u
        ext = 0.5 * float(du @ (k0.f + k1.f))
        damp = 0.0
        if an.system.C is not None:
            damp = _damping_work(an, du, k0, k1)
        pair = nxt.dissipation  # the rigid pairs: −P·U⁺
        if an.m:
            m, d = an.m, an.d
            spring = an.model.pair_laws.springs
            absolute = self.ex.form == "absolute" and self.ex.ground
            if absolute:
                dwp = (an.w_pres(k1.t, self.ex) - an.w_pres(k0.t, self.ex)).reshape(m, d)
                ext -= float(np.sum(nxt.pairs.X * dwp))
            if spring.any():
                # springs: their smooth force, step-averaged, on the smooth motion (not on
                # the position correction): the change of their elastic energy while they
                # stick
                lam0 = cur.pairs.X if cur.lam is None else cur.lam
                lam1 = nxt.pairs.X if nxt.lam is None else nxt.lam
                smooth_du = du if nxt.shift is None else du - nxt.shift
                dw = (an.op.G @ smooth_du).reshape(m, d)
                if absolute:
                    dw = dw + dwp
                pair -= float(np.sum((0.5 * (lam0 + lam1) * dw)[spring]))
        dT = 0.5 * (an.mass_product(k1.v) - an.mass_product(k0.v))
        U0 = an.strain_energy(k0.u)  # first: the recorder has just asked for it
        dU = an.strain_energy(k1.u) - U0
        acc["external_work"] += ext
        acc["damping"] += damp
        acc["interface"] += pair
        acc["impact"] += nxt.impact
        acc["correction"] += nxt.correction
        phi0 = self.modified(k0, an)
        dphi = self.modified(k1, an) - phi0
        acc["modified"] += dphi
        acc["algorithmic"] += ext + nxt.correction - dT - dU - damp - pair - nxt.impact - dphi

    def _add_moreau_jean(self, an: Dynamic, cur: StepState, nxt: StepState) -> None:
        """The terms of the θ-method's exact balance (see :mod:`._moreau`)."""
        acc = self.acc
        assert an.mj is not None
        th = an.mj.theta
        du = nxt.kin.u - cur.kin.u
        v_th = (1 - th) * cur.kin.v + th * nxt.kin.v
        ext = float(du @ ((1 - th) * cur.kin.f + th * nxt.kin.f))
        acc["external_work"] += ext
        damp = pair = 0.0
        if an.system.C is not None:
            if an.corot is None:
                damp = float(du @ an.damping_force(v_th, cur.kin.u))
            else:  # C v_θ in the frames of u_n + θh v_n, as the step applies it
                frames_at = cur.kin.u + th * an.dt * cur.kin.v
                damp = float(du @ an.damping_force(v_th, frames_at))
            acc["damping"] += damp
        if an.m:
            P = nxt.pairs.X * an.dt
            U_th = an.op.relative(v_th)
            if self.ex.moves_supports:
                # the moving base works on the blocks through the joints
                vp = (1 - th) * self.ex.prescribed(cur.kin.t)[1] + th * self.ex.prescribed(
                    nxt.kin.t)[1]  # fmt: skip
                wp = (an.op.Gp @ vp).reshape(U_th.shape)
                acc["external_work"] -= float(np.sum(P * wp))
                ext -= float(np.sum(P * wp))
                U_th = U_th + wp
            pair = -float(np.sum(P * U_th))
            acc["interface"] += pair
        if an.corot is None:  # (θ − ½)(ΔvᵀMΔv + ΔuᵀKΔu), exact
            acc["algorithmic"] += an.mj.dissipation(cur.kin, nxt.kin)
        else:  # the rest of the balance: the strain energy is the body frames' ½ũᵀK₀ũ
            dT = 0.5 * (an.mass_product(nxt.kin.v) - an.mass_product(cur.kin.v))
            dU = an.strain_energy(nxt.kin.u) - an.strain_energy(cur.kin.u)
            acc["algorithmic"] += ext - dT - dU - damp - pair


def _damping_work(an: Dynamic, du: FloatArray, k0: Any, k1: Any) -> float:
    """The damping's work over a step by the trapezoidal rule, ½ Δu·(C v_n + C v_{n+1}) (J).
    With large rotations each force is taken in the frames of its own configuration,
    Q C₀ Qᵀ v: a block spinning rigidly has C₀ Qᵀ v = 0 at either end, where the frames
    of u_n for both ends put the turn of a step, (ωh) × a dilatation, into C₀ Qᵀ v_{n+1}
    (a new user's free block at 2 rad/s with β = 4.6e-4 s "dissipated" 9,041 J of its
    31,200 J at Δt = 4 ms, balanced by an algorithmic −9,039 J)."""
    if an.corot is None:  # C is constant: one product
        return 0.5 * float(du @ an.damping_force(k0.v + k1.v, k0.u))
    return 0.5 * float(du @ (an.damping_force(k0.v, k0.u) + an.damping_force(k1.v, k1.u)))


class Recorder:
    """Histories of a run at ``n_out`` instants: probes, rigid motions, pairs, energy."""

    def __init__(
        self, an: Dynamic, excitation: Excitation, probes: IntArray, n_out: int,
        on_record: Callable[[dict[str, Any]], None] | None = None,
        origin: tuple[float, float] | None = None, envelope: bool = False,
        envelope_values: dict[str, FloatArray] | None = None,
    ) -> None:  # fmt: skip
        self.an, self.ex, self.probes, self.on_record = an, excitation, probes, on_record
        # the probes' prescribed components (n_probes, d): supports move with the ground
        dofs = (an.d * np.asarray(probes, dtype=np.int64)[:, None] + np.arange(an.d)).ravel()
        self._fixed = np.isin(dofs, an.system.prescribed).reshape(-1, an.d)
        self.envelope = (StressEnvelope(an.model, envelope_values)
                         if envelope and an.corot is None else None)  # fmt: skip
        # the kinetic and strain energy the balance is measured from (those of row 0 of
        # this run, or of the start of the run it resumes)
        self.origin = origin
        model, d, m = an.model, an.d, an.m
        r = 3 if d == 2 else 6
        self.t = np.zeros(n_out)
        self.pu, self.pv, self.pa, self.paa = (np.zeros((n_out, probes.size, d)) for _ in range(4))
        self.rigid = np.zeros((n_out, model.n_bodies, r))
        self.X, self.w, self.s = (np.zeros((n_out, m, d)) for _ in range(3))
        self.state = np.zeros((n_out, m), dtype=np.int8)
        n_joints = len(model.pair_laws.index) if m else 0
        self.fs = np.full((n_out, n_joints), np.inf)  # sliding safety factor per joint
        # the resultant force (global axes) and moment of each joint's pair forces
        self.jf = np.zeros((n_out, n_joints, d))
        self.jm = np.zeros((n_out, n_joints, 1 if d == 2 else 3))
        # the cracked extent (broken pairs) and the open crack (broken and open) per joint
        self.jc, self.jo = np.zeros((n_out, n_joints)), np.zeros((n_out, n_joints))
        self.ground = np.zeros((n_out, d))  # the ground's displacement as the run applied it
        self.broken = np.zeros((n_out, m), dtype=bool)
        self.E = {k: np.zeros(n_out) for k in ENERGY_TERMS}
        self.account = EnergyAccount(an, excitation)

    def record(self, i: int, st: StepState, emit: bool = True,
               solver: list[Any] | None = None) -> None:  # fmt: skip
        """Row i of the histories from the state ``st``; ``emit`` False keeps it from
        ``on_record`` (the row a resumed run starts from is already on disk); ``solver``
        the pair problems' iterations, fallbacks, worst residual, solves finished by
        the semismooth Newton and event sub-steps since the last row."""
        an, ex, probes, d, m = self.an, self.ex, self.probes, self.an.d, self.an.m
        system = an.system
        k = st.kin
        self.t[i] = k.t
        full_u = system.expand(k.u)
        full_v = system.expand(k.v, prescribed=False)
        full_a = system.expand(k.a if st.a_out is None else st.a_out, prescribed=False)
        if ex.form == "absolute":
            pres = system.prescribed
            full_u[pres], full_v[pres], full_a[pres] = ex.prescribed(k.t)
        U = full_u.reshape(-1, d)
        if self.envelope is not None:  # idempotent for the row a resumed run starts from
            # the stress of the step's smooth configuration, before its position
            # correction (as the recorded acceleration is the smooth one): the correction
            # moves the nodes of penetrating pairs alone, and the strain it puts in their
            # cells for a step is the scheme's (a 60 m dam whose upper block rocks on its
            # lift joint, Δt = 10 ms: −51.2 MPa at the joint's toe with it, −7.6 without,
            # −5.1 to −5.4 by Moreau–Jean at every Δt)
            self.envelope.update(k.t, full_u if st.shift is None else
                                 full_u - system.expand(st.shift, prescribed=False))  # fmt: skip
        self.pu[i] = U[probes]
        self.ground[i] = ex.ground_displacement(k.t)
        self.pv[i] = full_v.reshape(-1, d)[probes]
        A = full_a.reshape(-1, d)[probes]
        self.pa[i] = A
        if ex.form == "relative":
            # the ground acceleration the step applied (StepState.ground) at the free DOFs,
            # that of the instant at the supports, which move with the ground
            now = ex.ground_acceleration(k.t)
            self.paa[i] = A + (now if st.ground is None else
                               np.where(self._fixed, now, st.ground))  # fmt: skip
        else:
            self.paa[i] = A
        R = an.corot.rotations(k.u) if an.corot is not None else None
        self.rigid[i] = an.rigid(full_u, R)
        if m:
            pg = an.model.pairs
            assert pg is not None
            # the frames the pair forces are in, and where the pairs are: with large
            # rotations turned with side a's body, and moved with their nodes
            frame, x = pg.frame, None
            if an.corot is not None and R is not None and an.corot.op0 is not None:
                frame = an.corot.pair_frames(R)
                x = pg.x + 0.5 * (U[pg.node_a] + U[pg.node_b])
            self.X[i], self.w[i], self.s[i] = st.pairs.X, st.pairs.w, st.pairs.s
            self.fs[i] = self._safety_factor(an, st, frame)
            self.state[i], self.broken[i] = st.pairs.state, st.pairs.broken
            self.jf[i], self.jm[i] = pg.resultants(st.pairs.X, frame, x)
            broken = st.pairs.broken
            self.jc[i], self.jo[i] = an.model.joint_extent(
                np.stack([broken, broken & (st.pairs.state == OPEN)]))  # fmt: skip
        E = self.E
        E["kinetic"][i] = 0.5 * an.mass_product(k.v)
        E["strain"][i] = an.strain_energy(k.u, R) + ex.support_energy(k.t, k.u)
        if self.origin is None:
            self.origin = (float(E["kinetic"][i]), float(E["strain"][i]))
        for key in ENERGY_TERMS[2:]:
            E[key][i] = self.account.acc[key]
        if self.on_record is not None and emit:
            e_row = {key: float(E[key][i]) for key in ENERGY_TERMS}
            e_row["balance"] = float(_balance(e_row, self.origin))
            self.on_record({
                "t": k.t, "probe_u": self.pu[i], "probe_v": self.pv[i], "probe_a": self.pa[i],
                "probe_a_abs": self.paa[i], "rigid": self.rigid[i], "X": st.pairs.X,
                "w": st.pairs.w, "s": st.pairs.s, "state": st.pairs.state,
                "broken": st.pairs.broken, "energy": e_row, "u": U, "v": full_v.reshape(-1, d),
                "a": full_a.reshape(-1, d),
                "solver": [0, 0, 0.0, 0, 0] if solver is None else list(solver),
                "safety_factor": self.fs[i].copy(), "joint_force": self.jf[i].copy(),
                "joint_moment": self.jm[i].copy(), "joint_cracked": self.jc[i].copy(),
                "joint_open": self.jo[i].copy(), "ground": self.ground[i].copy(),
            })  # fmt: skip

    @staticmethod
    def _safety_factor(an: Dynamic, st: StepState,
                       frame: FloatArray | None = None) -> FloatArray:  # fmt: skip
        """The sliding safety factor of each joint at the state ``st``
        (:meth:`~pfeie.interface.PairLaws.safety_factor`), on the smooth pair forces λ
        where the scheme has them (an impact's impulses aside), else on the step's forces
        X. A joint whose smooth shear is round-off (below
        :data:`~pfeie.interface.FS_ROUNDOFF` of its pair forces, e.g. a pair that closes by
        an impulse in this step while its smooth force is zero) takes its factor from X:
        the step's impulses meet the
        velocity-level law, so the factor is that of the force it carried.

        The smooth forces λ are the scheme's acceleration-level forces, which the pair
        law does not bound: a pair that slides or sticks in a step may have a λ beyond
        its Coulomb cone, ‖λ_t‖ > τ = max(0, c A + μ λ_n) (the dam of docs/results.md
        sliding at Δt = 2.5 ms: FS 0.91). Such a pair's shear is taken on its cone, λ_t τ /
        ‖λ_t‖ (the largest shear it carries at that normal force, in the direction of its
        smooth shear; :meth:`~pfeie.interface.PairLaws.cone`), so every pair's shear is
        within its capacity and, by the triangle inequality ‖Σ T‖ ≤ Σ ‖T_i‖ ≤
        Σ max(0, c A + μ N), FS ≥ 1 (1 while the joint slides); and the factor is
        continuous as a pair's λ crosses its cone (taking the step's force X there instead
        made the factor jump with round-off that moved a pair to either side). ``frame``:
        the pairs' frames where they have turned (large rotations), for the shears' vector
        sum."""
        assert an.model.pairs is not None
        P, laws = st.pairs, an.model.pair_laws
        size = np.abs(P.X).sum(axis=1)
        if st.lam is not None:
            size = size + np.abs(st.lam).sum(axis=1)
        noise = FS_ROUNDOFF * np.array([size[idx].sum() for idx in laws.index])
        args = (
            P.state == OPEN,
            P.broken,
            P.path,
            an.model.pairs.frame if frame is None else frame,
            noise,
        )
        on_x = laws.safety_factor(P.X, *args, opening=P.s[:, -1])
        if st.lam is None:
            return on_x
        # the pairs whose smooth force lies outside their cone: the shear on the cone
        lam = st.lam
        shear = np.linalg.norm(lam[:, :-1], axis=1)
        tau = laws.cone(lam[:, -1], P.broken, P.path)
        beyond = shear > tau
        if beyond.any():
            lam = lam.copy()
            lam[beyond, :-1] *= (tau[beyond] / shear[beyond])[:, None]
        on_lam = laws.safety_factor(lam, *args, opening=P.s[:, -1])
        return np.where(np.isinf(on_lam), on_x, on_lam)

    def checkpoint(self, st: StepState, row: int) -> Checkpoint:
        """A :class:`Checkpoint` of the state ``st``, recorded as row ``row`` of the
        whole run."""
        from ._driver import Checkpoint

        assert self.origin is not None
        env = self.envelope.snapshot() if self.envelope is not None else None
        return Checkpoint(st, dict(self.account.acc), self.origin, row, env, self.ex.key,
                          self.ex.grid_rows(st.kin.t), self.an.key)  # fmt: skip

    def result(
        self, rows: int, final: StepState, iterations: np.ndarray, wall: float,
        completed: bool, reason: str | None, solver: dict[str, np.ndarray] | None = None,
    ) -> DynamicResult:  # fmt: skip
        """The histories of the first ``rows`` rows."""
        keep = slice(0, rows)
        E = self.E
        assert self.origin is not None
        E["balance"] = _balance(E, self.origin)
        P = self.an.model.pairs
        return DynamicResult(
            self.t[keep], self.probes, self.pu[keep], self.pv[keep], self.pa[keep],
            self.paa[keep], self.rigid[keep], self.X[keep], self.w[keep], self.s[keep],
            self.state[keep], self.broken[keep], {k: v[keep] for k, v in E.items()}, final,
            iterations, wall, completed, P.area if P is not None else np.zeros(0), reason,
            solver or {}, self.fs[keep],
            self.envelope.snapshot() if self.envelope is not None else {},
            self.jf[keep], self.jm[keep], self.jc[keep], self.jo[keep], self.ground[keep],
        )  # fmt: skip


__all__ = [
    "CID_LIMIT", "DCR_KEYS", "DCR_LIMIT", "ENVELOPE_KEYS", "OVERSTRESSED_LIMIT", "DynamicResult",
    "EnergyAccount", "Recorder", "StressEnvelope", "demand_capacity", "envelope_extremes",
]  # fmt: skip
