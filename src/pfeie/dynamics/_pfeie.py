"""The PFE/IE time step: Newmark on the blocks, the interface problem on the pairs.

One step from t_n to t_{n+1} (method.md §5.1):

1. predictor: u_free = K̂⁻¹ P̂ (one back-substitution of the once-factorised blocks);
2. interface: w_free = G u_free, then the pair forces X and states from
   w = w_free + W X with W = s G K̂⁻¹ Gᵀ (computed once) and the joint law;
3. corrector: u_{n+1} = u_free + s K̂⁻¹ Gᵀ X (a product with the stored Z = K̂⁻¹ Gᵀ,
   or a second back-substitution when Z is too large), then v, a by Newmark;
4. contact stabilisation: the relative velocity of the pairs that are closed at t_{n+1}
   is projected to zero, mass-weighted (momentum is kept).

Contact forces in time (the contact-stabilised scheme, default). The smooth forces
(loads, elastic, damping) follow Newmark's rule, but the pair forces are taken constant
over the step, equal to X_{n+1} (an impulse X_{n+1} Δt per step, as in the nonsmooth
θ-method of Moreau and Jean with θ = 1). Newmark's acceleration a then holds only the
smooth part, M a = f − K u − C v, and

    u_{n+1} = ũ + β Δt² a_{n+1} + ½ Δt² M⁻¹ Gᵀ X,   v_{n+1} = ṽ + γ Δt a_{n+1} + Δt M⁻¹ Gᵀ X,

so s = 1/(2β) (2 for the average-acceleration rule); for γ = 2β (β = 1/4, γ = 1/2) the
velocity needs no extra term and the discrete energy balance is exact:

    ΔT + ΔU + Δu·C v̄ = Δu·f̄ + X_{n+1}·Δw.

The pair term is −(dissipation) ≤ 0: friction opposes the slip increment, a closing
pair (Δw_n < 0) is pushed with X_n ≥ 0, an open pair carries nothing, an intact or
sticking one does not move. So the contact cannot pump energy into impacts or rocking,
which the plain rule (forces averaged between t_n and t_{n+1}) does: a friction force
that reverses, or a contact force that appears, is then smeared over a step and a
just-closed pair's relative velocity flips sign every step (v_{n+1} = 2Δw/Δt − v_n with
Δw = 0). The velocity projection of step 4 removes that flip: a perfectly inelastic
impact at the pair level, in the spirit of the contact-stabilised Newmark of Deuflhard,
Krause and Ertel (2008); it needs a diagonal (lumped) mass, which the analysis uses. Its
kinetic-energy loss is reported as ``impact`` and vanishes with the nodal mass at the
contact as the mesh is refined. With ``stabilize=False`` the plain rule is used (the
pair forces averaged like any load, no projection), for comparison.

Commit: the step's pair state is a trial until the step is accepted; then it becomes the
committed state of the next step (the driver never edits a committed state).

Energy (J), accumulated over the run:

    kinetic + strain + damping + interface + impact = external_work (+ initial energy),

``interface`` = −Σ X_{n+1}·Δw (friction and contact work dissipated; the plain rule uses
the step average of X), ``impact`` = kinetic energy removed by the projection.

Large rotations (``large_rotation=True``, method.md §2): each floating body carries a
body frame R_b (the mass-norm best rigid fit of its current configuration, see
:mod:`pfeie.model._frames`); the elastic force is Q K₀ ũ with ũ = R_bᵀ x − X the small
deformation in the frame, and each step is the incremental Newmark step in the
frames predicted for t_{n+1} (where the elastic force is linear in x) with the effective
matrix Q K̂₀ Qᵀ, inverted as Q K̂₀⁻¹ Qᵀ with the once-factorised K̂₀. Pair frames turn
with side a; W = (G Q) F (G Q)ᵀ is gathered every step from the nodal flexibility F of
the pair nodes. The frames are predicted, not iterated, so the energy balance then
closes only to the prediction error (third order in Δt for a spinning block).

Ground motion, two forms (method.md §6):

- ``form="relative"`` (default): a fixed base; each record adds the inertia load
  −M ι a_g(t); outputs are relative to the ground, absolute accelerations a + Σ ι a_g;
- ``form="absolute"``: every prescribed DOF moves with the ground, u_p(t) = ū_p + Σ ι d_g(t),
  d_g integrated exactly from the piecewise-linear record (apply
  :meth:`GroundMotion.baseline_corrected` first to remove drift); the blocks see the
  loads −K_fp u_p − C_fp v_p (the mass is lumped, so M_fp = 0) and the pairs on the base
  the prescribed relative motion; outputs are absolute. The energy balance then includes
  the work of the support reactions (``support_work``).
"""

from __future__ import annotations

import logging
import time as _time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..element._reference import FloatArray, IntArray
from ..errors import InterfaceError, ModelError
from ..interface import (
    INTACT,
    OPEN,
    SLIDE,
    STICK,
    InterfaceSolver,
    PairState,
    delassus,
)  # fmt: skip
from ..model import GroundMotion, Model
from ..model._frames import BodyFrames
from ._newmark import Newmark, State

log = logging.getLogger(__name__)


class RunStopped(Exception):
    """Raised by a run callback to stop the run cleanly (e.g. on Ctrl-C); the run
    returns what it has computed, with ``completed = False``."""


@dataclass
class StepState:
    """Everything the next step needs: the kinematic state and the committed pairs."""

    kin: State
    pairs: PairState
    step: int = 0
    v_raw: FloatArray | None = None  # velocity before the contact projection


@dataclass
class DynamicResult:
    """Time histories of a PFE/IE run.

    Arrays have time first. ``probe_u``, ``probe_v``, ``probe_a`` (n_t, k, d): motion of
    the probe nodes relative to the ground (m, m/s, m/s²); ``probe_a_abs`` absolute
    accelerations. ``rigid`` (n_t, n_bodies, r): centroid translation (m) and rotation
    (rad) of every body. Pair histories (n_t, m, d) in the local frames (t…, n):
    ``X`` forces on side b (N, normal + in compression), ``w`` relative displacements
    (m, normal + opening), ``s`` slip and gap; ``state`` (n_t, m) codes 0 intact,
    1 stick, 2 slide, 3 open; ``broken`` (n_t, m). ``energy``: kinetic, strain,
    external_work, damping, interface, impact (J) and ``balance`` (their residual).
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


class Dynamic:
    """A PFE/IE dynamic analysis of a model with (or without) interfaces.

    Parameters
    ----------
    model: the model (blocks, interfaces, supports, loads).
    dt: time step (s); K̂ is factorised once for it.
    beta, gamma, alpha: Newmark / HHT-α parameters (default average acceleration).
    ground: ground-motion records.
    form: "relative" (fixed base, inertia loads) or "absolute" (the supports move).
    stabilize: the contact stabilisation of the module docstring (default True).
    tol: complementarity residual tolerance of the interface solver.
    large_rotation: carry finite rotations of the floating blocks in body frames (see
        "Large rotations" in the module docstring); default False (small displacements).

    Example
    -------
    A block on a horizontal joint (μ = 0.2) under a base acceleration of 0.5 g for 0.2 s
    slides back by V²/(2gμ)(1 − μ/A) = 0.147 m (V2a of the verification cases):

    >>> import numpy as np, pfeie as pf
    >>> mesh = pf.rectangle(1.0, 1.5, 2, 3)
    >>> _ = mesh.add_cell_group("base", lambda x: x[:, 1] < 0.5)
    >>> _ = mesh.add_cell_group("block", lambda x: x[:, 1] > 0.5)
    >>> _ = mesh.add_facet_group("joint", lambda x: abs(x[:, 1] - 0.5) < 1e-9, False)
    >>> mat = pf.Elastic(30e9, 0.2, 2400)
    >>> model = pf.Model(mesh, [pf.Block("base", mat), pf.Block("block", mat)],
    ...     interfaces=[pf.Interface("joint", pf.Joint(phi=np.degrees(np.arctan(0.2))))])
    >>> model.fix("base"); model.add_gravity()
    >>> pulse = pf.GroundMotion.from_samples([4.905, 4.905, 0.0, 0.0],
    ...                                      time=[0.0, 0.2, 0.2 + 1e-9, 1.0])  # m/s²
    >>> res = Dynamic(model, 0.004, ground=[pulse]).run(0.8, start=pf.solve_static(model))
    >>> round(float(res.rigid[0, 1, 0] - res.rigid[-1, 1, 0]), 2)   # m
    0.15
    """

    def __init__(
        self,
        model: Model,
        dt: float,
        *,
        beta: float | None = None,
        gamma: float | None = None,
        alpha: float = 0.0,
        ground: Sequence[GroundMotion] = (),
        form: str = "relative",
        stabilize: bool = True,
        tol: float = 1e-8,
        backend: str = "auto",
        large_rotation: bool = False,
    ) -> None:
        self.model = model
        self.system = model.system(lumped_mass=True)
        self.nm = Newmark(self.system, dt, beta=beta, gamma=gamma, alpha=alpha, backend=backend)
        self.dt = float(dt)
        self.ground = list(ground)
        d = model.dim
        for g in self.ground:
            if g.direction.size != d:
                raise ModelError(f"ground motion {g.name!r}: direction has {g.direction.size} "
                                 f"components, the model is {d}D")  # fmt: skip
        if form not in ("relative", "absolute"):
            raise ModelError(f"ground-motion form must be 'relative' or 'absolute', got {form!r}")
        self.form = form
        free, pres = self.system.free, self.system.prescribed
        # massless blocks (e.g. a massless foundation, the usual dam model) have no inertia:
        # their nodes take no part in the velocity projection (M⁻¹ = 0 there)
        self.mass = np.asarray(self.system.M.diagonal(), dtype=float)
        self.minv = np.divide(1.0, self.mass, out=np.zeros_like(self.mass),
                              where=self.mass > 0)  # fmt: skip
        iota = [np.tile(g.direction, model.mesh.n_points) for g in self.ground]
        self._iota_M = [self.system.M @ i[free] for i in iota] if form == "relative" else []
        self._iota_p = [i[pres] for i in iota] if form == "absolute" else []
        self._drive: list[tuple[FloatArray, FloatArray | None]] = []
        if form == "absolute" and self.ground:
            if not pres.size:
                raise ModelError("the absolute form needs supports that move with the ground")
            K_fp = model.stiffness()[free][:, pres]
            C_fp = None
            if model.damping is not None and (model.damping.alpha or model.damping.beta):
                M_full = model.mass(lumped=True)
                C_full = model.damping.alpha * M_full + model.damping.beta * model.stiffness()
                C_fp = C_full[free][:, pres]
            for ip in self._iota_p:
                self._drive.append((-(K_fp @ ip), None if C_fp is None else -(C_fp @ ip)))
        G = model.relative_operator()
        self.G = G[:, free].tocsr()
        if stabilize and self.G.shape[0]:
            touched = np.flatnonzero(np.abs(self.G).sum(axis=0).A1 > 0)
            if np.any(self.mass[touched] <= 0):
                raise ModelError(
                    "the contact-stabilised scheme needs mass on both sides of every "
                    "interface: give massless blocks a small density (e.g. 1 % of the "
                    "structure's) to model a massless foundation"
                )
        self.Gp = G[:, pres].tocsr()
        self.w_pres = (self.Gp @ self.system.prescribed_values) if pres.size else np.zeros(
            G.shape[0])  # fmt: skip
        self.stabilize = stabilize
        self._proj_cache: dict[bytes, tuple[Any, ...]] = {}
        self.m = 0 if model.pairs is None else model.pairs.n
        self.d = d
        t0 = _time.perf_counter()
        pairs = model.pairs
        self.frames: BodyFrames | None = None
        if large_rotation:
            if alpha:
                raise ModelError("large_rotation supports the Newmark rule only (alpha = 0)")
            self.frames = BodyFrames(model, free)
        if pairs is not None and self.m:
            if self.frames is not None:
                W = self._setup_corotation()
                self.Z = None
            else:
                W, self.Z = delassus(self.nm.factor, self.G)
            # stabilised: X constant over the step (factor 1/(2β)); plain: Newmark load
            s = 0.5 / self.nm.beta if stabilize else 1.0 + alpha
            self.isolver_reg = pairs.regularization
            self.isolver: InterfaceSolver | None = InterfaceSolver(
                s * W, model.pair_properties, tol=tol, regularize=pairs.regularization
            )
            self._scale = s
            GM = self.G.multiply(self.minv[None, :]).tocsr()
            self.H = (GM @ self.G.T).tocsc()
            # components with no free mass on either side (e.g. a wall against rollers)
            self._movable = self.H.diagonal() > 0
            self._junction = pairs.redundant
        else:
            self.isolver, self.Z = None, None
        self._tol = tol
        self.setup_time = _time.perf_counter() - t0

    # -- large rotations --------------------------------------------------------------------
    def _setup_corotation(self) -> FloatArray:
        """Nodal flexibility F = K̂₀⁻¹ restricted to the pair nodes' DOFs I (one
        multi-right-hand-side solve); W in any configuration is gathered from it."""
        assert self.frames is not None and self.model.pairs is not None
        P, d, fr = self.model.pairs, self.d, self.frames
        free = self.system.free
        pos = np.full(self.model.n_dof, -1, dtype=np.int64)
        pos[free] = np.arange(free.size)
        nodes = np.unique(np.concatenate([P.node_a, P.node_b]))
        dofs = pos[(nodes[:, None] * d + np.arange(d)).ravel()]
        I = dofs[dofs >= 0]
        sel = sp.csr_matrix((np.ones(I.size), (np.arange(I.size), I)), shape=(I.size, free.size))
        self._F, self._Y = delassus(self.nm.factor, sel)
        self._I = I
        loc = np.full(free.size, -1, dtype=np.int64)
        loc[I] = np.arange(I.size)
        on_pairs = np.isin(fr.nodes, nodes)
        self._I_rot = loc[fr.dofs[on_pairs]]  # (k, d) positions in I of rotating nodes
        self._I_body = fr.body[on_pairs]
        self._I_fix = np.setdiff1d(np.arange(I.size), self._I_rot.ravel())
        body = np.full(self.model.mesh.n_points, -1, dtype=np.int64)
        body[fr.nodes] = fr.body
        self._a_body = body[P.node_a]  # frames turn with side a
        self._last: tuple[bytes, sp.csr_matrix] | None = None  # operators of the last step
        Gi = self.G[:, I]
        return np.asarray(Gi @ (Gi @ self._F).T)

    def _turn(self, R: FloatArray) -> sp.csr_matrix:
        """Q restricted to the pair DOFs I (sparse, block-diagonal by node)."""
        d = self.d
        k = self._I_rot.shape[0]
        rows = np.concatenate([self._I_fix, np.repeat(self._I_rot, d, axis=1).ravel()])
        cols = np.concatenate([self._I_fix, np.tile(self._I_rot, (1, d)).ravel()])
        vals = np.concatenate([np.ones(self._I_fix.size),
                               R[self._I_body].reshape(k, d * d).ravel()])  # fmt: skip
        n = self._I.size
        return sp.csr_matrix((vals, (rows, cols)), shape=(n, n))

    def _corotate(self, u: FloatArray) -> tuple[FloatArray, sp.csr_matrix | None]:
        """Body rotations R of the configuration u; when frames turn with a rotating side
        a, the pair operators G (and H, w_pres) follow; then W = G Q K̂₀⁻¹ Qᵀ Gᵀ and a new
        interface solver. Returns R and G̃ = (G Q) restricted to I (None without pairs).
        While the rotations of the bodies at the pairs do not change (none rotates, or the
        structure is at rest) the operators of the previous step are kept."""
        assert self.frames is not None
        R = self.frames.rotations(u)
        if not self.m:
            return R, None
        key = R[self._I_body].tobytes() + R[self._a_body[self._a_body >= 0]].tobytes()
        if self._last is not None and self._last[0] == key:
            return R, self._last[1]
        turns = self._a_body >= 0
        if turns.any():
            assert self.model.pairs is not None
            T = self.model.pairs.frame.copy()
            T[turns] = np.einsum("kij,klj->kil", T[turns], R[self._a_body[turns]])
            G = self.model.relative_operator(T)
            free, pres = self.system.free, self.system.prescribed
            self.G, self.Gp = G[:, free].tocsr(), G[:, pres].tocsr()
            self.H = (self.G.multiply(self.minv[None, :]).tocsr() @ self.G.T).tocsc()
            self._proj_cache.clear()
            if pres.size:
                self.w_pres = self.Gp @ self.system.prescribed_values
        Gt = (self.G[:, self._I] @ self._turn(R)).tocsr()
        W = np.asarray(Gt @ (Gt @ self._F).T)
        assert self.isolver is not None
        self.isolver = InterfaceSolver(self._scale * W, self.model.pair_properties,
                                       tol=self._tol, regularize=self.isolver_reg)  # fmt: skip
        self._last = (key, Gt)
        return R, Gt

    def elastic_force(self, u: FloatArray, R: FloatArray | None = None) -> FloatArray:
        """Elastic nodal force on the free DOFs (N): K u, or Q K₀ ũ with large rotations,
        ũ = Rᵀx − X measured in the frames R (default: those of u itself)."""
        if self.frames is None:
            return np.asarray(self.system.K @ u)
        R = self.frames.rotations(u) if R is None else R
        return self.frames.rotate(self.system.K @ self.frames.local_displacement(u, R), R)

    def strain_energy(self, u: FloatArray, R: FloatArray | None = None) -> float:
        """½ uᵀ K u, or ½ ũᵀ K₀ ũ in the body frames R (default: those of u) (J)."""
        if self.frames is not None:
            R = self.frames.rotations(u) if R is None else R
            u = self.frames.local_displacement(u, R)
        return 0.5 * float(u @ (self.system.K @ u))

    def damping_force(
        self, v: FloatArray, u: FloatArray, R: FloatArray | None = None
    ) -> FloatArray:
        """C v, or Q C₀ Qᵀ v with the frames R (default: those of the configuration u) (N)."""
        C = self.system.C
        if C is None:
            return np.zeros_like(v)
        if self.frames is None:
            return np.asarray(C @ v)
        R = self.frames.rotations(u) if R is None else R
        return self.frames.rotate(C @ self.frames.rotate(v, R, transpose=True), R)

    # -- loads ------------------------------------------------------------------------------
    def load(self, t: float) -> FloatArray:
        """External load on the free DOFs at t (N): model loads and ground inertia."""
        f = self.system.load(t)
        for g, mi in zip(self.ground, self._iota_M, strict=False):
            f = f - mi * g(t)
        for g, (kg, cg) in zip(self.ground, self._drive, strict=False):
            d, v, _ = g.motion(t)
            f = f + kg * d
            if cg is not None:
                f = f + cg * v
        return f

    def prescribed(self, t: float) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Displacement, velocity and acceleration of the prescribed DOFs at t."""
        u = self.system.prescribed_values.copy()
        v, a = np.zeros_like(u), np.zeros_like(u)
        for g, ip in zip(self.ground, self._iota_p, strict=False):
            dg, vg, ag = g.motion(t)
            u += ip * dg
            v += ip * vg
            a += ip * ag
        return u, v, a

    def _w_pres(self, t: float) -> FloatArray:
        if not self._iota_p:
            return self.w_pres
        return self.Gp @ self.prescribed(t)[0]

    # -- start ------------------------------------------------------------------------------
    def initial(
        self,
        static: object | None = None,
        t0: float = 0.0,
        *,
        u0: FloatArray | None = None,
        v0: FloatArray | None = None,
    ) -> StepState:
        """The start of the run: from a static result (which the run keeps exactly when
        there is no excitation), or from given nodal displacements ``u0`` and velocities
        ``v0`` ((n_points, d) arrays, default zero; e.g. a bar moving towards a wall). Pairs
        of broken joints whose gap is positive start open."""
        d, m = self.d, self.m
        n = self.system.n
        free = self.system.free
        props = self.model.pair_properties if m else None
        if static is not None:
            u = np.asarray(static.u).ravel()[free]  # type: ignore[attr-defined]
        else:
            u = np.zeros(n) if u0 is None else np.asarray(u0, dtype=float).ravel()[free]
        if self.frames is not None:
            self._corotate(u)
        if static is not None:
            ps = static.pairs.copy() if m else None  # type: ignore[attr-defined]
        else:
            ps = PairState.initial(props, d) if props is not None else None
            if ps is not None and props is not None and u0 is not None:
                ps.w = (self.G @ u + self._w_pres(t0)).reshape(m, d)
                ps.s = ps.w.copy()
                ps.s[:, -1] += props.gap
                ps.state[ps.broken & (ps.s[:, -1] > 0)] = OPEN
        if ps is None:
            ps = PairState(np.zeros(0, np.int8), np.zeros(0, bool), *(np.zeros((0, d)),) * 3,
                           np.zeros((0, d - 1)))  # fmt: skip
        f_ext = self.load(t0)
        GX = self.G.T @ ps.X.ravel() if m else 0.0
        # smooth acceleration (stabilised) or total (plain rule)
        f = f_ext if self.stabilize else f_ext + GX
        v = np.zeros(n) if v0 is None else np.asarray(v0, dtype=float).ravel()[free]
        if self.system.C is not None:
            f = f - self.damping_force(v, u)
        a = self.minv * (f - self.elastic_force(u))
        kin = State(t0, u, v, a, f)
        return StepState(kin, ps, 0)

    # -- one step ---------------------------------------------------------------------------
    def _closed(self, ps: PairState) -> np.ndarray:
        c = np.zeros((self.m, self.d), dtype=bool)
        full = (ps.state == INTACT) | (ps.state == STICK)
        c[full] = True
        c[ps.state == SLIDE, -1] = True
        return c.ravel()

    def _project(
        self, x: FloatArray, ps: PairState, offset: FloatArray | None = None
    ) -> tuple[FloatArray, FloatArray]:
        """Mass-weighted projection of x so that G_c x + offset_c = 0 on the closed
        components (offset: the prescribed side's part, absolute form); returns the
        projected field and the multipliers λ per component (M,)."""
        closed = self._closed(ps) & self._movable
        lam = np.zeros(self.m * self.d)
        if not closed.any():
            return x, lam
        key = closed.tobytes()
        hit = self._proj_cache.get(key)
        if hit is None:
            c = np.flatnonzero(closed)
            Gc = self.G[c].tocsr()
            GcT = Gc.T.tocsr()
            Hc = self.H[c][:, c].tocsc()
            if self._junction:
                eps = 1e-12 * float(Hc.diagonal().mean())
                solve = spla.factorized((Hc + eps * sp.eye(c.size)).tocsc())
            elif Hc.nnz == c.size:
                hd = Hc.diagonal()
                hinv = np.divide(1.0, hd, out=np.zeros_like(hd), where=hd > 0)
                solve = lambda g: g * hinv  # noqa: E731
            else:
                solve = spla.factorized(Hc)
            if len(self._proj_cache) > 256:
                self._proj_cache.clear()
            hit = (c, Gc, GcT, solve)
            self._proj_cache[key] = hit
        c, Gc, GcT, solve = hit
        g = Gc @ x
        if offset is not None:
            g = g + offset[c]
        lam_c = solve(g)
        lam[c] = lam_c
        return x - self.minv * (GcT @ lam_c), lam

    def step(self, cur: StepState) -> tuple[StepState, float]:
        """One step; returns the next state (the committed pair state of the next step)
        and the kinetic energy removed by the stabilisation (J)."""
        kin = cur.kin
        t1 = kin.t + self.dt
        f_ext = self.load(t1)
        m, d = self.m, self.d
        prev = cur.pairs
        R: FloatArray | None = None
        Gt: sp.csr_matrix | None = None
        if self.frames is None:
            u_free = self.nm.predict(kin, f_ext)
        else:
            # the frames of the step: those of the configuration Newmark's explicit part
            # predicts for t_{n+1}, so that the elastic force at t_{n+1} is taken in frames
            # within O(Δt³) of its own (frames held at t_n would make the step first order)
            dt = self.dt
            R, Gt = self._corotate(kin.u + dt * kin.v + (0.5 - self.nm.beta) * dt**2 * kin.a)
            u_free = kin.u + self._rotated_solve(self._increment_load(kin, f_ext, R), R)
            if m and (self._a_body >= 0).any():
                # the committed relative motion, seen in the turned frames
                prev = cur.pairs.copy()
                prev.w = (self.G @ kin.u + self._w_pres(kin.t)).reshape(m, d)
                props = self.model.pair_properties
                prev.s = prev.w + props.compliance * prev.X
                prev.s[:, -1] += props.gap
        if not m:
            new = self.nm.advance(kin, u_free, f_ext)
            return StepState(new, cur.pairs, cur.step + 1), 0.0
        assert self.isolver is not None
        w_free = (self.G @ u_free + self._w_pres(t1)).reshape(m, d)
        trial, _ = self.isolver.solve(w_free, prev, label=f"step {cur.step + 1} "
                                      f"(t = {t1:.6g} s)")  # fmt: skip
        X = trial.X.ravel() * self._scale
        if self.frames is not None and R is not None:
            if self._Y is not None and Gt is not None:
                du = self.frames.rotate(self._Y @ (Gt.T @ X), R)
            else:
                du = self._rotated_solve(self.G.T @ X, R)
        elif self.Z is not None:
            du = self.Z @ X
        else:
            du = self.nm.factor.solve(self.G.T @ X)
        u = u_free + du
        GX = self.G.T @ trial.X.ravel()
        lost = 0.0
        if self.stabilize:
            new = self.nm.advance(kin, u, f_ext)
            impulse = self.minv * GX
            new.a = new.a - self._scale * impulse
            extra = 1.0 - self.nm.gamma * self._scale
            if extra:
                new.v = new.v + self.dt * extra * impulse
            mass = self.mass
            v_raw = new.v.copy()
            ke0 = 0.5 * float(new.v @ (mass * new.v))
            vp = self.Gp @ self.prescribed(t1)[1] if self._iota_p else None
            new.v, _ = self._project(new.v, trial, vp)
            lost = ke0 - 0.5 * float(new.v @ (mass * new.v))
        else:
            new = self.nm.advance(kin, u, f_ext + GX)
            v_raw = None
        return StepState(new, trial, cur.step + 1, v_raw), lost

    def _increment_load(self, kin: State, f_ext: FloatArray, R: FloatArray) -> FloatArray:
        """Right-hand side of Q K̂₀ Qᵀ Δu = f − Q K₀ (Qᵀx_n − X) + M(a₂ v + a₃ a)
        + Q C₀ Qᵀ (a₄ v + a₅ a): the incremental Newmark step with the elastic force taken
        in the frames R of the step (large rotations), in which it is linear in x."""
        _, _, a2, a3, a4, a5 = self.nm.c
        r = f_ext - self.elastic_force(kin.u, R) + self.mass * (a2 * kin.v + a3 * kin.a)
        if self.system.C is not None:
            r = r + self.damping_force(a4 * kin.v + a5 * kin.a, kin.u, R)
        return r

    def _rotated_solve(self, r: FloatArray, R: FloatArray) -> FloatArray:
        """(Q K̂₀ Qᵀ)⁻¹ r = Q K̂₀⁻¹ Qᵀ r: one back-substitution of the reference factor."""
        assert self.frames is not None
        fr = self.frames
        return fr.rotate(self.nm.factor.solve(fr.rotate(r, R, transpose=True)), R)

    def rigid(self, u_full: FloatArray, R: FloatArray | None = None) -> FloatArray:
        """Rigid motion of every body (n_bodies, r): centroid translation (m) and
        rotation (rad); with large rotations the rotation of the body frames R."""
        q = self.model.rigid_motion(u_full)
        if self.frames is not None and self.frames.n and R is not None:
            ang = self.frames.angles(R)
            q[self.frames.bodies, self.d :] = ang.reshape(self.frames.n, -1)
        return q

    # -- run --------------------------------------------------------------------------------
    def run(
        self,
        duration: float | None = None,
        *,
        n_steps: int | None = None,
        start: StepState | object | None = None,
        probes: Sequence[int] | IntArray = (),
        every: int = 1,
        callback: Callable[[StepState], None] | None = None,
        on_record: Callable[[dict[str, Any]], None] | None = None,
    ) -> DynamicResult:
        """Integrate over ``duration`` (s) or ``n_steps`` steps, recording every
        ``every`` steps. ``start`` is a :class:`StepState`, a static result or None.
        ``on_record`` receives every recorded row (probe, rigid, pair and energy values,
        and the full nodal u, v, a), e.g. to stream them to a results file.

        If a step fails (the interface problem does not converge), the histories up to
        the last completed step are returned with ``completed = False`` and the error is
        logged; nothing computed is lost.
        """
        if (duration is None) == (n_steps is None):
            raise ModelError("give either duration or n_steps")
        n = int(n_steps) if n_steps is not None else round(float(duration or 0.0) / self.dt)
        cur = start if isinstance(start, StepState) else self.initial(start)
        model, d, m = self.model, self.d, self.m
        probes = np.asarray(probes, dtype=np.int64)
        n_out = n // every + 2  # one spare row for a stop between recorded steps
        r = 3 if d == 2 else 6
        out_t = np.zeros(n_out)
        pu, pv, pa, paa = (np.zeros((n_out, probes.size, d)) for _ in range(4))
        rigid = np.zeros((n_out, model.n_bodies, r))
        HX, Hw, Hs = (np.zeros((n_out, m, d)) for _ in range(3))
        Hst = np.zeros((n_out, m), dtype=np.int8)
        Hbr = np.zeros((n_out, m), dtype=bool)
        iters = np.zeros(n + 1, dtype=np.int32)
        names = ("kinetic", "strain", "external_work", "damping", "interface", "impact")
        E = {k: np.zeros(n_out) for k in names}
        acc = dict.fromkeys(names, 0.0)
        mass = self.mass
        C = self.system.C

        def record(i: int, st: StepState) -> None:
            k = st.kin
            out_t[i] = k.t
            full_u = self.system.expand(k.u)
            full_v = self.system.expand(k.v, prescribed=False)
            full_a = self.system.expand(k.a, prescribed=False)
            if self.form == "absolute":
                pres = self.system.prescribed
                full_u[pres], full_v[pres], full_a[pres] = self.prescribed(k.t)
            U = full_u.reshape(-1, d)
            pu[i] = U[probes]
            pv[i] = full_v.reshape(-1, d)[probes]
            A = full_a.reshape(-1, d)[probes]
            if self.stabilize and m:  # a holds the smooth part; add the pair forces
                A = A + self.system.expand(self.minv * (self.G.T @ st.pairs.X.ravel()),
                                           prescribed=False).reshape(-1, d)[probes]  # fmt: skip
            pa[i] = A
            if self.form == "relative":
                ag = sum((g.direction * g(k.t) for g in self.ground), np.zeros(d))
                paa[i] = A + ag
            else:
                paa[i] = A
            R = self.frames.rotations(k.u) if self.frames is not None else None
            rigid[i] = self.rigid(full_u, R)
            if m:
                HX[i], Hw[i], Hs[i] = st.pairs.X, st.pairs.w, st.pairs.s
                Hst[i], Hbr[i] = st.pairs.state, st.pairs.broken
            E["kinetic"][i] = 0.5 * float(k.v @ (mass * k.v))
            E["strain"][i] = self.strain_energy(k.u, R)
            for key in names[2:]:
                E[key][i] = acc[key]
            if on_record is not None:
                full_a_out = full_a
                if self.stabilize and m:
                    full_a_out = full_a + self.system.expand(
                        self.minv * (self.G.T @ st.pairs.X.ravel()), prescribed=False
                    )
                e_row = {key: float(E[key][i]) for key in names}
                e_row["balance"] = (
                    sum(e_row[key] for key in names if key != "external_work")
                    - E["kinetic"][0]
                    - E["strain"][0]
                    - e_row["external_work"]
                )
                on_record({
                    "t": k.t, "probe_u": pu[i], "probe_v": pv[i], "probe_a": pa[i],
                    "probe_a_abs": paa[i], "rigid": rigid[i], "X": st.pairs.X, "w": st.pairs.w,
                    "s": st.pairs.s, "state": st.pairs.state, "broken": st.pairs.broken,
                    "energy": e_row, "u": full_u.reshape(-1, d), "v": full_v.reshape(-1, d),
                    "a": full_a_out.reshape(-1, d),
                })  # fmt: skip

        if m and start is not None and not isinstance(start, StepState):
            cur.pairs.w = (self.G @ cur.kin.u + self._w_pres(cur.kin.t)).reshape(m, d)
        record(0, cur)
        t_wall = _time.perf_counter()
        completed = True
        reason: str | None = None
        j = 0
        for i in range(1, n + 1):
            try:
                nxt, lost = self.step(cur)
            except InterfaceError as exc:
                log.error("run stopped: %s", exc)
                completed, reason = False, str(exc)
                break
            du = nxt.kin.u - cur.kin.u
            f0 = cur.kin.f - (self.G.T @ cur.pairs.X.ravel() if m and not self.stabilize else 0.0)
            f1 = nxt.kin.f - (self.G.T @ nxt.pairs.X.ravel() if m and not self.stabilize else 0.0)
            acc["external_work"] += 0.5 * float(du @ (f0 + f1))
            if C is not None:
                # Newmark's equilibrium holds with the velocities before the projection
                acc["damping"] += 0.5 * float(
                    du @ self.damping_force(_raw(cur) + _raw(nxt), cur.kin.u)
                )
            if m:
                dw = (self.G @ du).reshape(m, d)
                Xw = nxt.pairs.X if self.stabilize else 0.5 * (cur.pairs.X + nxt.pairs.X)
                if self.form == "absolute" and self.ground:
                    # the moving base works on the blocks through the joints
                    dwp = (self._w_pres(nxt.kin.t) - self._w_pres(cur.kin.t)).reshape(m, d)
                    acc["external_work"] -= float(np.sum(Xw * dwp))
                    dw = dw + dwp
                acc["interface"] -= float(np.sum(Xw * dw))
                acc["impact"] += lost
                iters[i] = self.isolver.last.iterations if self.isolver else 0
            cur = nxt
            if i % every == 0:
                j = i // every
                record(j, cur)
            if callback is not None:
                try:
                    callback(cur)
                except RunStopped as exc:
                    log.warning("run stopped at step %d (t = %.4g s): %s", i, cur.kin.t, exc)
                    completed, reason = False, f"stopped: {exc}"
                    if i % every:
                        j += 1
                        record(j, cur)
                    break
        wall = _time.perf_counter() - t_wall
        keep = slice(0, j + 1)
        tot = E["kinetic"] + E["strain"] + E["damping"] + E["interface"] + E["impact"]
        E["balance"] = tot - (E["kinetic"][0] + E["strain"][0]) - E["external_work"]
        return DynamicResult(
            out_t[keep], probes, pu[keep], pv[keep], pa[keep], paa[keep], rigid[keep],
            HX[keep], Hw[keep], Hs[keep], Hst[keep], Hbr[keep],
            {k: v[keep] for k, v in E.items()}, cur, iters, wall, completed,
            model.pairs.area if model.pairs is not None else np.zeros(0), reason,
        )  # fmt: skip


def _raw(st: StepState) -> FloatArray:
    return st.kin.v if st.v_raw is None else st.v_raw


__all__ = ["Dynamic", "DynamicResult", "RunStopped", "StepState"]
