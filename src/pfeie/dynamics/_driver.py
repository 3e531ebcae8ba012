"""The PFE/IE dynamic analysis: a time integrator on the blocks, the interface problem on
the pairs (method.md §3.1, §5.1).

:class:`Dynamic` is built once per model and time step: it factorises the blocks' step
matrix and builds the Delassus operator W, and then runs any number of records (a record
is an argument of :meth:`Dynamic.run`, not of the constructor). Its parts, each with one
job:

- the time integrator, which knows nothing of pairs: :class:`~pfeie.dynamics.NonsmoothAlpha`
  (default), :class:`~pfeie.dynamics.MoreauJean`, or :class:`~pfeie.dynamics.Newmark`
  (Newmark / HHT-α / generalised-α, for models without interfaces);
- the one-step interface problem (:class:`pfeie.coupling.InterfaceStep`: the pair forces
  and states for a free motion, on W; the block correction);
- the excitation of a run (:class:`~pfeie.dynamics.Excitation`: relative or absolute
  form);
- corotation, optional (:class:`~pfeie.dynamics.Corotation`: body frames for large
  rotations);
- the recorder and the energy account (:class:`~pfeie.dynamics.Recorder`).

One step of the default nonsmooth generalised-α scheme from t_n to t_{n+1}
(:meth:`Dynamic._step_nonsmooth_alpha`, docs/theory.md):

1. free acceleration q̈_free = Ŝ⁻¹ r (one back-substitution of the once-factorised
   Ŝ = s M + γ h C + β h² K);
2. smooth pair forces λ at the acceleration level for the pairs closed at t_n (intact
   pairs bilateral, Signorini and Coulomb on G q̈); joints with springs act on the
   displacement at t_{n+1};
3. velocity correction: the Signorini–Coulomb law at the velocity level on the step
   impulse P of the rigid contacts predicted closed (skipped when P = hλ satisfies it);
4. one back-substitution with two right-hand sides for the block response to λ and to
   P − hλ, and a local position correction of penetrating pairs.

Commit: the step's pair state is a trial until the step is accepted; then it becomes the
committed state of the next step (:meth:`PairState.committed`).
"""

from __future__ import annotations

import dataclasses
import logging
import time as _time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp
from pydantic import ValidationError

from ..coupling import InterfaceStep, PairOperator, delassus
from ..errors import InterfaceError, ModelError
from ..interface import INTACT, OPEN, SLIDE, STICK, InterfaceSolver, PairState, law_key
from ..linalg import Factorization, factorize
from ..model import GroundMotion, Model
from ..typing import BoolArray, FloatArray, IntArray, settings_message
from ._corotation import Corotation
from ._excitation import Excitation, shorter_than_a_step
from ._moreau import MoreauJean, impulse_laws
from ._newmark import Newmark, State, damping_product
from ._nsga import NonsmoothAlpha
from ._recorder import DynamicResult, Recorder
from ._settings import DynamicSettings

log = logging.getLogger(__name__)

#: the share of the input energy that the position corrections add above which the run is
#: said not converged in Δt (``pfeie run``'s summary, and a warning of
#: :meth:`Dynamic.run`). Measured (share at
#: Δt = 10, 5, 2.5, 1.25 ms → the residual slip against the finest run): a 60 m dam whose
#: upper block slides 135 mm on its lift joint, 46.6, 14.9, 3.9, 1.1 % → −27, −13, −7 %;
#: a 3D Tet10 monolith rocking on a broken lift joint (El Centro at 0.3 g, ρ∞ = 0.5), 145,
#: 18, 2.9 % → crest 23.1, 21.5, 20.4 mm and slips 3.42, 0.51, 0.97 mm; the Koyna demo
#: 11.0, 2.4, 0.49 % → neck slip −5, +4, +2 % (docs/demo-convergence.md)
CORRECTION_UNRESOLVED = 0.15

#: the share of the static strain energy below which the energy that went through a run
#: is round-off, and neither the scheme's created energy nor the position corrections are
#: judged against it (a share of nothing): the energy terms are sums over the steps of
#: forces that carry the static loads times displacement increments, so the pair
#: solver's tolerance and round-off leave terms of a tiny share of the static energy.
#: A 60 m dam (T6) under an all-zero record: 3.2e-8 J through the run, 1.1e-8 J
#: "created", against a static strain energy of 3.9e4 J (8e-13 of it); the same dam
#: under El Centro scaled to 0.001 g for 4 s: 67 J (1.7e-3 of it; the input scales as
#: the PGA², so the floor is reached at about 2e-5 g); a 1 m block on a 20° plane,
#: stiff and light (3.8e-3 J): its warned 280 J lie 7e10 times above the floor
ENERGY_FLOOR = 1e-6

# a pair whose gap is predicted below this (m) takes part in a Moreau-Jean step
_GAP_TOL = 1e-9


class RunStopped(Exception):
    """Raised by a run callback to stop the run cleanly (e.g. on Ctrl-C); the run
    returns what it has computed, with ``completed = False``."""


@dataclass
class StepState:
    """Everything the next step needs: the kinematic state and the committed pairs."""

    kin: State
    pairs: PairState
    step: int = 0
    lam: FloatArray | None = None  # smooth pair forces λ (nonsmooth-α), (m, d)
    impact: float = 0.0  # energy taken by the step's velocity correction (J)
    dissipation: float = 0.0  # the rigid pairs' dissipation by the law, −P·U⁺ (J)
    correction: float = 0.0  # strain energy stored by its position correction (J)
    shift: FloatArray | None = None  # the step's position correction Δq (nonsmooth-α)
    # the time of step 0 of the state's grid (s): step k is at origin + k h exactly, not
    # at a running sum of h (None: t − step h)
    origin: float | None = None
    # the static result the run started from (None: none): its uplift pressures and open
    # pairs set the pre-earthquake uplift of a run continued from this state
    static: object | None = None
    # Σ ι a_g as the step that made this state applied it (d,), what turns its relative
    # acceleration into the absolute one (relative form; None: a_g(t) of the instant, as
    # the nonsmooth generalised-α's smooth acceleration has it): the Moreau–Jean step's
    # (1 − θ) a_g(t_n) + θ a_g(t_{n+1}) of its own step size (an event's sub-step too), and
    # for the Newmark family the ground acceleration through the scheme's own recurrence,
    # (1 − α_m) g_{n+1} + α_m g_n = (1 − α_f) a_g(t_{n+1}) + α_f a_g(t_n), g₀ = a_g(t₀)
    ground: FloatArray | None = None
    # the acceleration to record for this state where it is not kin.a: the start of the
    # nonsmooth generalised-α, whose kin.a is the scheme's over its first step, records the
    # equation's acceleration at t₀ (None: kin.a)
    a_out: FloatArray | None = None
    # absolute form: the excitation's digest (Excitation.key), the step and the rows of the
    # supports' grids at this state (Excitation.grid_rows), for a run continued from it
    # under the same records and step (``start=result.final``): event sub-steps moved
    # the supports off the grid's own recurrence (None: the grid from its origin)
    supports: tuple[str, float, FloatArray] | None = None
    # the excitation the run that ended at this state was under (Excitation.key: its
    # digest and wording; set on a run's final state and its checkpoints' states; None:
    # unknown): a run started from the state under other records reads them from the
    # state's time, and is told so where that skips their beginning (an aftershock)
    records: tuple[str, str] | None = None


@dataclass
class Checkpoint:
    """Everything a run needs to continue exactly where it was (:meth:`Dynamic.run`):
    the step state, the running sums of the energy account (J), the kinetic and strain
    energy at the start of the run (J; the balance is measured from them), the index
    of the state's recorded row, and the stress envelope so far (None: not recorded)."""

    state: StepState
    energy: dict[str, float]
    origin: tuple[float, float]
    row: int
    envelope: dict[str, FloatArray] | None = None
    #: the run's excitation (:attr:`Excitation.key`: a digest and its wording), which a
    #: resumed run must have; None: not checked (a checkpoint read from a results file,
    #: whose run key the command line checks)
    excitation: tuple[str, str] | None = None
    #: the rows of the supports' grids at the state (absolute form, n_records × 4:
    #: :meth:`Excitation.grid_rows`), where a resumed run's supports go on from; None:
    #: none (the relative form; a checkpoint written before it: the grid from its origin)
    supports: FloatArray | None = None
    #: the analysis that took it (:attr:`Dynamic.key`: a digest and its wording), which a
    #: resumed run must have; None: not checked (a checkpoint read from a results file,
    #: whose run key the command line checks, or one taken before version 0.3.21)
    analysis: tuple[str, str] | None = None


class Dynamic:
    """A PFE/IE dynamic analysis of a model with (or without) interfaces.

    Parameters
    ----------
    model: the model (blocks, interfaces, supports, loads).
    dt: time step (s); K̂ is factorised once for it. None: that of ``settings``, or
        :class:`DynamicSettings`' default (0.01 s) — choose it for the model and check it
        by halving (docs/results.md).
    settings: a :class:`DynamicSettings`; or its fields as keywords (``scheme``,
        ``rho_inf``, ``theta``, ``beta``, ``gamma``, ``alpha``, ``large_rotation``,
        ``event_substeps``, ``tolerance``, ``backend``): every option and its default is
        documented there.

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
    >>> an = Dynamic(model, 0.004)                 # factorised once
    >>> res = an.run(0.8, ground=[pulse], start=pf.solve_static(model))
    >>> round(float(res.rigid[0, 1, 0] - res.rigid[-1, 1, 0]), 2)   # m
    0.15
    """

    def __init__(
        self,
        model: Model,
        dt: float | None = None,
        *,
        settings: DynamicSettings | None = None,
        **options: Any,
    ) -> None:
        if not isinstance(model, Model):
            raise ModelError(f"Dynamic: expected a pfeie.Model (that of a model file is "
                             f"pfeie.io.load_job(path).model), got {type(model).__name__} "
                             f"{model!r}")  # fmt: skip
        given: object = settings
        if isinstance(given, dict):  # the settings' fields as a mapping
            settings, options = None, {**given, **options}
        elif given is not None and not isinstance(given, DynamicSettings):
            raise ModelError(f"Dynamic: settings: expected a pfeie.DynamicSettings (or its "
                             f"fields as keywords), got {type(given).__name__} "
                             f"{given!r}")  # fmt: skip
        base = {} if settings is None else settings.model_dump()
        if settings is None or dt is not None or options:
            given = {**base, **options, **({} if dt is None else {"dt": dt})}
            try:  # strict: a string for a number is refused, not converted
                settings = DynamicSettings.model_validate(given, strict=True)
            except ValidationError as exc:
                raise ModelError(f"Dynamic: {settings_message(exc)}") from None
        assert settings is not None
        massless = model.massless_floating_bodies()
        if massless.size:
            names = model.body_names()
            raise ModelError("Dynamic: the block(s) " + ", ".join(repr(names[b]) for b in massless)
                             + " float (no support) and have no mass (rho = 0): the step's "
                             "matrix is singular on their rigid motion; expected a density "
                             "(e.g. 1 % of the rock's for a practically massless foundation) "
                             "or a support")  # fmt: skip
        self.settings = settings
        self.model = model
        self._key: tuple[str, str] | None = None
        self._revision = model.revision  # the model as built (see _check_model)
        # the blocks' mass lumped; the reservoirs' added mass kept as a matrix where it
        # couples DOFs (a finite-element reservoir's M_a, Westergaard's nodal blocks on an
        # inclined face: the integrators factorise a general M)
        self.system = model.system(lumped_mass=True, full_reservoir=True)
        self._full_mass = model.added_mass_coupled()
        beta, gamma, alpha = settings.newmark()
        self.dt = settings.dt
        self.mj: MoreauJean | None = None
        self.ga: NonsmoothAlpha | None = None
        if settings.scheme == "nonsmooth-alpha":
            self.ga = NonsmoothAlpha(self.system, settings.dt, rho_inf=settings.nonsmooth_alpha(),
                                     backend=settings.backend)  # fmt: skip
        elif settings.scheme == "moreau-jean":
            self.mj = MoreauJean(self.system, settings.dt, theta=settings.theta,
                                 backend=settings.backend)  # fmt: skip
        else:
            n_pairs = 0 if model.pairs is None else int(model.pairs.n)
            if n_pairs:
                raise ModelError(
                    f"scheme = 'newmark' runs models without interfaces; this model has "
                    f"{n_pairs} interface pairs: use scheme = 'nonsmooth-alpha' (the default; "
                    "rho_inf for numerical damping) or 'moreau-jean'"
                )
            self.nm = Newmark(self.system, settings.dt, beta=beta, gamma=gamma, alpha=alpha,
                              rho_inf=settings.rho_inf, backend=settings.backend)  # fmt: skip
        self.d = model.dim
        # massless blocks (e.g. a massless foundation, the usual dam model) have no inertia:
        # their nodes take no part in the position correction (M⁻¹ = 0 there)
        # M lumped on its diagonal: the metric of the position correction (M⁻¹) and the
        # products M x, unless the reservoirs' added mass couples DOFs (a finite-element
        # reservoir's M_a, Westergaard's on an inclined face: the products use M itself)
        self.mass = np.asarray((model.mass(lumped=True).diagonal()[self.system.free]
                                if self._full_mass else self.system.M.diagonal()),
                               dtype=float)  # fmt: skip
        self.minv = np.divide(1.0, self.mass, out=np.zeros_like(self.mass),
                              where=self.mass > 0)  # fmt: skip
        free, pres = self.system.free, self.system.prescribed
        self.op = PairOperator.build(model.pairs, model.n_dof, free, pres)
        self.m = self.op.m
        self._w_pres0 = self.op.w_prescribed(self.system.prescribed_values)
        t0 = _time.perf_counter()
        self.istep: InterfaceStep | None = None
        self.vstep: InterfaceStep | None = None  # the velocity correction (nonsmooth-α)
        self.velocity_corrections = 0  # steps whose velocity correction was solved
        # event sub-steps: the analysis at dt/k that takes a step again in which a pair
        # changes state (built on first need), and the number of such steps so far
        self._fine: Dynamic | None = None
        self.event_steps = 0
        self._last_strain: list[tuple[FloatArray, float]] = []
        self._last_vmv: list[tuple[FloatArray, float]] = []
        # the next step's free acceleration, computed ahead (nonsmooth-α): (state, excitation,
        # t_{n+1}, load, q̈_free)
        self._ahead: tuple[State, Excitation, float, FloatArray, FloatArray] | None = None
        self._rigid: tuple[sp.csr_matrix, FloatArray, BoolArray] | None = None
        self.corot: Corotation | None = None
        self._mass_factor: tuple[IntArray, Factorization] | None = None  # full M (M_a)
        self._mass_blocks: sp.csr_matrix | None = None  # M⁻¹ by node (Westergaard's blocks)
        if settings.large_rotation:
            self.corot = Corotation(model, self.system, self.factor,
                                    self.op if self.m else None)  # fmt: skip
        if self.m and self.ga is not None:
            assert model.pairs is not None
            self._setup_nonsmooth_alpha(model, self.ga, settings)
        elif self.m and self.mj is not None:
            assert model.pairs is not None
            if self.mj.theta < 0.55:
                raise ModelError(
                    f"the Moreau-Jean scheme with interfaces needs theta in [0.55, 1], got "
                    f"{self.mj.theta}: theta = 1/2 does not dissipate impacts and lets blocks hop"
                )
            laws = impulse_laws(model.pair_laws, self.dt)
            W = (self.corot.reference_delassus() if self.corot is not None
                 else delassus(self.mj.factor, self.op.G))  # fmt: skip
            self.istep = InterfaceStep(self.op, W, laws, 1.0, settings=settings.solver(),
                                       regularize=model.pairs.regularization)  # fmt: skip
        self.setup_time = _time.perf_counter() - t0

    def _setup_nonsmooth_alpha(
        self, model: Model, ga: NonsmoothAlpha, settings: DynamicSettings
    ) -> None:
        """The two pair problems of the nonsmooth generalised-α step on W = G Ŝ⁻¹ Gᵀ with
        the weight s = (1 − α_m)/(1 − α_f): smooth forces (strengths as forces) and step
        impulses (strengths times h); and the local position correction's G M⁻¹ Gᵀ."""
        assert model.pairs is not None
        laws = model.pair_laws
        if ga.rho_inf > 0 and not (model.damping is not None and model.damping.beta > 0):
            raise ModelError(
                f"rho_inf = {ga.rho_inf} with interfaces needs stiffness-proportional "
                "damping (a Rayleigh beta > 0): without it the blocks hop at contacts "
                "(docs/theory.md); use rho_inf = 0 or add damping"
            )
        W = (self.corot.reference_delassus() if self.corot is not None
             else delassus(ga.factor, self.op.G))  # fmt: skip
        reg = model.pairs.regularization
        # both pair problems are posed in displacement units, on the position increment
        # c_q G q̈ (c_q = β h²/s): a rigid contact's law on G q̈ is the same law on c_q G q̈,
        # and a spring's law acts on the displacement G q_{n+1} = G q̂ + c_q G q̈; the
        # velocity problem is scaled by c_q likewise (its law is positively homogeneous)
        self._spring = laws.springs
        self.istep = InterfaceStep(self.op, W, laws.scaled(1.0), ga.s * ga.weights[0],
                                   settings=settings.solver(), regularize=reg)  # fmt: skip
        self.vstep = self.istep.with_laws(laws.scaled(self.dt))
        G = self.op.G
        self._gmg = np.asarray(G.multiply(G) @ self.minv).reshape(self.m, self.d)[:, -1]

    def twin(self) -> Dynamic:
        """A second analysis of the same system for another run beside this one: it
        shares what never changes (the model, its system, the factorised step matrix, the
        Delassus operator W) and copies the rest (the pair solvers with their caches, the
        scheme's last step), so that runs of the two never touch each other's state and
        each gives the bits it gives alone. For runs in lockstep (a study's batch of
        records, :func:`pfeie.linalg.run_lockstep`); not with large rotations, whose step
        updates the shared operators."""
        import copy

        if self.corot is not None:
            raise ModelError("twin: not with large_rotation (its operators change a step)")
        memo: dict[int, Any] = {id(self.model): self.model, id(self.system): self.system}
        if self.settings.event_substeps > 1 and self.m:
            fine = self.fine()  # built once, its factor shared by the twins
            memo[id(fine.system)] = fine.system
        return copy.deepcopy(self, memo)

    @property
    def factor(self) -> Factorization:
        """The factorised matrix of the blocks' step (K̂, Ŝ of the nonsmooth-α scheme, or
        Ŵ of Moreau-Jean)."""
        if self.ga is not None:
            return self.ga.factor
        return self.mj.factor if self.mj is not None else self.nm.factor

    @property
    def frames(self) -> Any:
        """The body frames (large rotations), or None."""
        return None if self.corot is None else self.corot.frames

    def _check_state(self, st: StepState, what: str) -> None:
        """Refuse a step state of another model (``what``: the argument): its free DOFs,
        pairs or dimension differ from this analysis'."""
        n, m = self.system.n, self.m
        got_n = int(np.shape(st.kin.u)[0]) if np.ndim(st.kin.u) == 1 else -1
        X = st.pairs.X
        got_m, got_d = (X.shape[0], X.shape[1]) if X.ndim == 2 else (-1, -1)
        if got_n != n or got_m != m or (m and got_d != self.d):
            raise ModelError(f"{what}: the state is of another model ({got_n} free DOFs and "
                             f"{got_m} pairs; this analysis has {n} free DOFs and {m} pairs): "
                             "expected a state of a run of this analysis' model (its "
                             "result.final, or a checkpoint of it)")  # fmt: skip

    def _records_from(self, start: StepState, ex: Excitation, n: int) -> None:
        """The records of a run started from ``start``, a state at t₀ = ``start.kin.t``:
        the run reads them at its own time, from t₀ on, so that a run under the records of
        the state's own run continues it (after a record's end too: the ground at rest).
        Where the state ended a run under other records (``start.records``): refused where
        a record ends by t₀ (nothing of it would act: an aftershock whose times start at 0
        after a mainshock that ended at 5 s ran with the ground at rest, silently), warned
        where a record starts before t₀ (its beginning is skipped); where the state's
        records are unknown (a state built or read elsewhere), a record that ends by t₀ is
        warned. :meth:`~pfeie.GroundMotion.shifted` moves a record to start at t₀."""
        t0 = float(start.kin.t)
        if not t0 > 0.0 or (start.records is not None and start.records[0] == ex.key[0]):
            return
        tol = 1e-9 * max(1.0, t0)
        known = start.records is not None
        runs = f"a run under {start.records[1]}" if start.records is not None else "a run"
        if ex.moves_supports and ex.ground:
            # the supports would jump from the state's ground motion to the new records'
            text = (f"start: this run's records move the supports (the absolute form) and "
                    f"its start state ended {runs}: the supports would jump at t = {t0:g} "
                    "s from where that run's ground left them to where these records put "
                    "them; run a sequence of records (an aftershock after its mainshock) "
                    "in the relative form, or as one record")  # fmt: skip
            if known:
                raise ModelError(text)
            log.warning("%s", text)
        for g in ex.ground:
            first, last = float(g.time[0]), float(g.time[-1])
            fix = (f"to apply it after that state (an aftershock), shift it to start there: "
                   f"record.shifted({t0:g})")  # fmt: skip
            if last <= t0 + tol:
                text = (
                    f"ground motion {g.name!r}: the record ends at {last:g} s, and this run "
                    f"starts at t = {t0:g} s, the time of its start state, which ended "
                    f"{runs} (a run from a state goes on at the state's time and reads its "
                    f"records there): nothing of the record would act; {fix}"
                )
                if known:
                    raise ModelError(text)
                log.warning("%s", text)
            elif known and first < t0 - tol:
                end = t0 + n * self.dt
                log.warning(
                    "ground motion %r: this run starts at t = %g s, the time of its start "
                    "state, which ended %s; it reads the record from there, from %g s to "
                    "%g s, and skips its first %g s; %s",
                    g.name, t0, runs, t0, min(end, last), t0 - first, fix)  # fmt: skip

    def _rigid_correction(self) -> tuple[sp.csr_matrix, FloatArray, BoolArray] | None:
        """The rigid-body metric of the position correction (``position_correction =
        'rigid'``; None for 'local'): Φ, the rigid modes of the floating blocks that have
        mass and no support, on the free DOFs (n_free × r·B'), the inverse of their mass
        matrix ΦᵀMΦ (block diagonal; M lumped), and the pairs that touch such a block (the
        others keep the local correction). Built once."""
        if self.settings.position_correction != "rigid":
            return None
        if self._rigid is None:
            model, d = self.model, self.d
            r = 3 if d == 2 else 6
            Phi = sp.csr_matrix(model.rigid_modes()[self.system.free])
            C = (Phi.T @ sp.diags(self.mass) @ Phi).toarray()
            held = np.zeros(model.n_bodies, dtype=bool)
            body = model.body_of_node[np.asarray(self.system.prescribed) // d]
            held[body[body >= 0]] = True
            mass = np.array([C[b * r, b * r] for b in range(model.n_bodies)])
            free_body = ~held & (mass > 0.0)
            keep = np.repeat(free_body, r)
            Phi, C = Phi[:, keep], C[np.ix_(keep, keep)]
            P = model.pairs
            assert P is not None
            touch = (free_body[model.body_of_node[P.node_a]]
                     | free_body[model.body_of_node[P.node_b]])  # fmt: skip
            self._rigid = (sp.csr_matrix(Phi), np.linalg.inv(C) if keep.any()
                           else np.zeros((0, 0)), touch)  # fmt: skip
        return self._rigid

    def _rigid_shift(self, rigid: tuple[sp.csr_matrix, FloatArray, BoolArray],
                     pen: BoolArray, gap: FloatArray) -> FloatArray:  # fmt: skip
        """The position correction Δq = Φ C⁻¹ Bᵀν of the penetrating pairs ``pen`` moved
        apart by rigid motions of their floating blocks, B = G_n Φ the pairs' normal rows
        of the rigid modes and ν the least-squares solution of B C⁻¹ Bᵀ ν = −g (the
        penetration removed where rigid motions can remove it; the smallest ν where
        several pairs constrain the same motion): the least kinetic-metric motion that
        closes the gaps, with no strain stored."""
        Phi, Cinv, _ = rigid
        rows = np.flatnonzero(pen) * self.d + (self.d - 1)
        B = np.asarray((self.op.G[rows] @ Phi).todense())
        A = B @ Cinv @ B.T
        nu = np.linalg.lstsq(A, -gap[pen], rcond=1e-12)[0]
        return np.asarray(Phi @ (Cinv @ (B.T @ nu)))

    def _warn_corrections(self, rec: Recorder) -> None:
        """A warning where the position corrections of penetrating pairs added more than
        :data:`CORRECTION_UNRESOLVED` of the input energy over the run (``pfeie run``'s
        summary says it too; a script's run said nothing): on a block dropped 50 mm onto
        a base at Δt = 4 ms they added 3.1e5 J against the fall's 1,177 J, and it bounced
        65 mm back."""
        acc = rec.account.acc
        work, corr = abs(acc.get("external_work", 0.0)), acc.get("correction", 0.0)
        floor = ENERGY_FLOOR * abs(rec.origin[1] if rec.origin is not None else 0.0)
        if not (work > floor and abs(corr) > CORRECTION_UNRESOLVED * work):
            return
        rigid = ("position_correction = 'rigid' (a block landing on a few pairs, not a "
                 "structure resting on its joints) or " if
                 self.settings.position_correction == "local" else "")  # fmt: skip
        log.warning(
            "the position corrections of penetrating pairs %s %.4g J, %.0f %% of the input "
            "energy: impacts this time step does not resolve, and the results are not "
            "converged in Δt (a block dropped onto a base can bounce back higher than it "
            "fell): halve Δt and compare; for drops, rockfall and rocking impacts take "
            "%sscheme = 'moreau-jean' (docs/theory.md, 'Drops and bounces')",
            "added" if corr > 0 else "took", abs(corr), 100 * abs(corr) / work,
            rigid)  # fmt: skip

    def _check_model(self) -> None:
        """Refuse a run of a model changed since this analysis was built (supports, loads,
        reservoirs, uplifts or damping added or replaced; :attr:`Model.revision`): its
        factorised operators and loads are those of the model then, and the change would
        be ignored without a word."""
        now = self.model.revision
        if now == self._revision:
            return
        what = [k for k in now if now[k] != self._revision[k]]
        raise ModelError(f"the model changed after this analysis was built ({', '.join(what)} "
                         "changed: a fix or add_* call, or a new damping): the analysis "
                         "holds the operators and loads of the model as it was; build a new "
                         "pfeie.Dynamic(model, ...) after the change")  # fmt: skip

    # -- operators of the current configuration ------------------------------------------------
    @property
    def key(self) -> tuple[str, str]:
        """What identifies this analysis, for a checkpoint (a run resumed by another
        analysis would not continue the run): a digest of its settings (Δt, scheme and
        the rest), its stiffness, mass and damping, its pairs and their joint laws
        (:func:`pfeie.interface.law_key`), and its wording; hashed once."""
        if self._key is not None:
            return self._key
        import hashlib

        h = hashlib.sha256(self.settings.model_dump_json().encode())
        for mat in (self.system.K, self.system.M, self.system.C):
            if mat is not None:
                h.update(np.ascontiguousarray(mat.data).tobytes())
                h.update(np.ascontiguousarray(mat.indices).tobytes())
        P = self.model.pairs
        if P is not None:
            h.update(np.ascontiguousarray(P.x).tobytes())
            for it in self.model.interfaces:
                h.update(it.group.encode() + b"\0" + law_key(it.joint))
        laws = ", ".join(f"{it.group!r}: {type(it.joint).__name__}" for it in self.model.interfaces)
        self._key = (h.hexdigest()[:16], f"Δt = {self.dt:g} s, the {self.settings.scheme} "
                     f"scheme, {self.system.n} free DOFs"
                     + (f", joint laws {laws}" if laws else ""))  # fmt: skip
        return self._key

    def excitation(self, ground: Sequence[GroundMotion] = (), form: str = "relative",
                   start: object | None = None) -> Excitation:  # fmt: skip
        """The excitation of a run by the records ``ground`` in the given form; the uplift
        in joints, if any, is the pre-earthquake one of the static state ``start`` (its
        pressures and open pairs; default the uncracked joints')."""
        pairs = getattr(start, "pairs", None)
        open0 = None if pairs is None else pairs.state == OPEN
        return Excitation(self.model, self.system, ground, form,
                          getattr(start, "uplift", None), open0)  # fmt: skip

    def _supports_on_grid(self, ex: Excitation, origin: float, *, trial: bool = False) -> None:
        """In the absolute form, the supports moved as this analysis's scheme integrates
        the records on the run's grid of steps from ``origin`` (:meth:`Excitation.on_grid`),
        so that a resumed run reads the same support motion. The nonsmooth
        generalised-α starts from the acceleration it finds over a trial first step
        (:meth:`_initial`): for the supports that is a_g(t₀ + h), which their grid starts
        from (``trial``: the grid of that trial step, from a_g(t₀))."""
        if not ex.moves_supports:
            return
        if self.mj is not None:
            ex.on_grid(origin, self.dt, theta=self.mj.theta)
        elif self.ga is not None:
            ga = self.ga
            ex.on_grid(origin, self.dt, beta=ga.beta, gamma=ga.gamma, alpha_m=ga.alpha_m,
                       alpha_f=ga.alpha_f, auxiliary=True, start_ahead=not trial)  # fmt: skip
        else:  # HHT-α and generalised-α balance a_g at (α_m, α_f): the auxiliary recurrence
            nm = self.nm
            ex.on_grid(origin, self.dt, beta=nm.beta, gamma=nm.gamma, alpha_m=nm.alpha_m,
                       alpha_f=nm.alpha_f, auxiliary=True)  # fmt: skip

    def w_pres(self, t: float, ex: Excitation) -> FloatArray:
        """G_p u_p(t) (M,): the relative motion the prescribed DOFs give the pairs."""
        if not ex.moves_supports:
            return self._w_pres0
        return self.op.w_prescribed(ex.prescribed(t)[0])

    def _use(self, op: PairOperator) -> None:
        """Make ``op`` the current pair operator (pair frames turned)."""
        if op is self.op:
            return
        self.op = op
        self._w_pres0 = op.w_prescribed(self.system.prescribed_values)

    def _corotate(self, u: FloatArray) -> FloatArray:
        """Body rotations R of the configuration u; the pair operators follow them."""
        assert self.corot is not None
        R = self.corot.rotations(u)
        ops = self.corot.operators(R)
        if ops is not None:
            op, W, changed = ops
            if changed:
                self._use(op)
                assert self.istep is not None
                self.istep.update(op, W)
                if self.vstep is not None:
                    self.vstep = self.istep.with_laws(self.vstep.laws)
        return R

    def elastic_force(self, u: FloatArray, R: FloatArray | None = None) -> FloatArray:
        """Elastic nodal force on the free DOFs (N): K u, or Q K₀ ũ with large rotations."""
        if self.corot is None:
            return np.asarray(self.system.K @ u)
        return self.corot.elastic_force(u, R)

    def damping_force(
        self, v: FloatArray, u: FloatArray, R: FloatArray | None = None
    ) -> FloatArray:
        """C v, or Q C₀ Qᵀ v with large rotations (N)."""
        if self.corot is not None:
            return self.corot.damping_force(v, u, R)
        return damping_product(self.system, v)

    def mass_product(self, v: FloatArray) -> float:
        """vᵀ M v (twice the kinetic energy, J; M lumped, with the reservoirs' added mass
        as a matrix where it couples DOFs), kept for the last two vectors asked (the
        energy account and the recorder ask for the same ones)."""
        for vec, value in self._last_vmv:
            if vec is v:
                return value
        value = float(v @ (self.system.M @ v if self._full_mass else self.mass * v))
        self._last_vmv = [(v, value), *self._last_vmv[:1]]
        return value

    def strain_energy(self, u: FloatArray, R: FloatArray | None = None) -> float:
        """½ uᵀ K u, or ½ ũᵀ K₀ ũ in the body frames (J)."""
        if self.corot is not None:
            return self.corot.strain_energy(u, R)
        # the step (position correction), the energy account and the recorder ask for the
        # same vectors: the last three answers are kept (by identity: the states' vectors
        # are never modified in place)
        for vec, value in self._last_strain:
            if vec is u:
                return value
        value = 0.5 * float(u @ (self.system.K @ u))
        self._last_strain = [(u, value), *self._last_strain[:2]]
        return value

    def _strain_added(self, u1: FloatArray, dq: FloatArray) -> float:
        """U(u1) − U(u1 − dq), the strain energy a position correction dq adds (J).

        With small rotations, dqᵀK u1 − ½ dqᵀK dq: one product K u1, whose U(u1) the
        energy account and the recorder then find kept (:meth:`strain_energy`), and the
        rows of K at the few DOFs dq moves (K symmetric: dqᵀK dq = dq_I · (K_I: dq)), where
        ½(u1 − dq)ᵀK(u1 − dq) would be a second sweep of K."""
        if self.corot is not None:
            return self.strain_energy(u1) - self.strain_energy(u1 - dq)
        K = self.system.K
        Ku = K @ u1
        U1 = 0.5 * float(u1 @ Ku)
        self._last_strain = [(u1, U1), *self._last_strain[:2]]
        moved = np.flatnonzero(dq)
        return float(dq @ Ku) - 0.5 * float(dq[moved] @ (K[moved] @ dq))

    def rigid(self, u_full: FloatArray, R: FloatArray | None = None) -> FloatArray:
        """Rigid motion of every body (n_bodies, r): centroid translation (m) and
        rotation (rad); with large rotations the rotation of the body frames R."""
        q = self.model.rigid_motion(u_full)
        if self.corot is not None and self.corot.frames.n and R is not None:
            fr = self.corot.frames
            q[fr.bodies, self.d :] = fr.angles(R).reshape(fr.n, -1)
        return q

    # -- start ---------------------------------------------------------------------------------
    def initial(
        self,
        static: object | None = None,
        t0: float = 0.0,
        *,
        u0: FloatArray | None = None,
        v0: FloatArray | None = None,
        ground: Sequence[GroundMotion] = (),
        form: str = "relative",
    ) -> StepState:
        """The start of a run: from a static result (which the run keeps exactly when
        there is no excitation), or from given nodal displacements ``u0`` and velocities
        ``v0`` ((n_points, d) arrays, default zero; e.g. a bar moving towards a wall). Pairs
        of broken joints whose gap is positive start open. ``ground`` and ``form`` give
        the excitation at t0 (the initial acceleration)."""
        self._check_model()
        ex = self.excitation(ground, form, static)
        self._supports_on_grid(ex, t0, trial=True)  # (the start's trial step)
        return self._initial(ex, static, t0, u0=u0, v0=v0)

    def _initial(
        self, ex: Excitation, static: object | None, t0: float = 0.0, *,
        u0: FloatArray | None = None, v0: FloatArray | None = None,
    ) -> StepState:  # fmt: skip
        d, m = self.d, self.m
        n = self.system.n
        free = self.system.free
        laws = self.model.pair_laws if m else None
        u0, v0 = self._nodal("u0", u0), self._nodal("v0", v0)
        if static is not None and not hasattr(static, "u"):
            raise ModelError(f"start: expected a static result (pfeie.solve_static), got "
                             f"{type(static).__name__}")  # fmt: skip
        if static is not None:
            shape = np.shape(static.u)
            npairs = getattr(getattr(static, "pairs", None), "X", np.zeros((0, d))).shape[0]
            if shape != (self.model.mesh.n_points, d) or npairs != m:
                raise ModelError(f"start: the static result is of another model ({shape[0]} "
                                 f"nodes and {npairs} pairs; this model has "
                                 f"{self.model.mesh.n_points} nodes and {m} pairs): expected "
                                 "pfeie.solve_static(model) of this model")  # fmt: skip
            u = np.asarray(static.u).ravel()[free]
        else:
            u = np.zeros(n) if u0 is None else np.asarray(u0, dtype=float).ravel()[free]
        if self.corot is not None:
            self._corotate(u)
        ps: PairState | None
        if static is not None:
            ps = static.pairs.copy() if m else None  # type: ignore[attr-defined]
        else:
            ps = laws.initial_state(d) if laws is not None else None
            if ps is not None and laws is not None and u0 is not None:
                ps.w = (self.op.G @ u + self.w_pres(t0, ex)).reshape(m, d)
                ps.s = ps.w.copy()
                ps.s[:, -1] += laws.gap
                ps.state[ps.broken & (ps.s[:, -1] > 0)] = OPEN
        if ps is None:
            ps = PairState.empty(d)
        f_ext = ex.load(t0)
        f = f_ext + (self.op.G.T @ ps.X.ravel() if m else 0.0)
        v = np.zeros(n) if v0 is None else np.asarray(v0, dtype=float).ravel()[free]
        if self.system.C is not None:
            f = f - self.damping_force(v, u)
        a = self._mass_solve(f - self.elastic_force(u))
        if self.mj is not None:
            # Moreau-Jean's load is the external load only: pair impulses and damping are
            # the step's own (the acceleration above is the total one, for the output)
            f = f_ext
        if self.ga is not None:
            a = self._consistent_acceleration(ex, t0, u, v, f_ext, ps, static is not None)
            first = StepState(self.ga.initial_state(u, v, a, f_ext, t0), ps, 0)
            # start: the acceleration the scheme itself finds over the first step (blocks
            # whose contact nodes stick at t0 while the rest accelerates would otherwise
            # carry that instant's acceleration, which lasts only as long as an elastic
            # wave crosses the block, into an O(Δt) velocity error; for smooth motion the
            # start costs one local O(Δt²) error and the scheme stays second order). Models
            # without pairs start the same way, so that intact joints give the monolithic
            # response to round-off.
            q0 = a
            a = self._step_nonsmooth_alpha(first, ex, self.ga, t0, ahead_next=False).kin.a
            return StepState(self.ga.initial_state(u, v, a, f_ext, t0), ps, 0, static=static,
                             a_out=q0)  # fmt: skip
        return StepState(State(t0, u, v, a, f), ps, 0, static=static)

    def _probes(self, probes: Sequence[int] | IntArray) -> IntArray:
        """Probe node indices, checked: whole numbers in [0, n_points)."""
        n = self.model.mesh.n_points
        arr = np.asarray(probes)
        if arr.size == 0:
            return np.zeros(0, dtype=np.int64)
        if arr.ndim != 1 or not np.issubdtype(arr.dtype, np.integer) or (
                arr.min() < 0 or arr.max() >= n):  # fmt: skip
            raise ModelError(f"probes: expected node indices in [0, {n}) (whole numbers, "
                             f"one list), got {arr.tolist()}")  # fmt: skip
        return arr.astype(np.int64)

    def _nodal(self, key: str, value: FloatArray | None) -> FloatArray | None:
        """A nodal field given to :meth:`initial`, checked: (n_points, d), finite."""
        if value is None:
            return None
        shape = (self.model.mesh.n_points, self.d)
        try:
            arr = np.asarray(value, dtype=float)
        except (TypeError, ValueError):
            raise ModelError(f"{key}: expected numbers of shape {shape}") from None
        if arr.shape != shape or not np.isfinite(arr).all():
            raise ModelError(f"{key}: expected finite values of shape {shape} (n_points, d), "
                             f"got shape {arr.shape}")  # fmt: skip
        return arr

    def _consistent_acceleration(
        self, ex: Excitation, t0: float, u: FloatArray, v: FloatArray, f_ext: FloatArray,
        ps: PairState, static: bool,
    ) -> FloatArray:  # fmt: skip
        """q̈₀ = M⁻¹(f − K u − C v + Gᵀ λ₀) with the smooth pair forces λ₀ of the pairs
        closed at t0 from the acceleration-level law on G q̈₀ (M lumped; massless DOFs get
        no acceleration). From a static state without ground acceleration at t0, λ₀ = X
        and q̈₀ = 0. Without
        it a load switched on at t0 would leave an O(Δt) velocity error in the rigid
        modes."""
        r = f_ext - self.elastic_force(u)
        if self.system.C is not None:
            r = r - self.damping_force(v, u)
        m, d = self.m, self.d
        if not m:
            return self._mass_solve(r)
        G = self.op.G
        spring = self._spring  # a spring's force is known from the state: X
        closed = (ps.state != OPEN) & ~spring
        at_rest = not np.any(ex.ground_acceleration(t0)) and not ex.moves_supports
        if (static and at_rest) or not closed.any():
            X = ps.X if static else np.where(spring[:, None], ps.X, 0.0)
            return self._mass_solve(r + G.T @ X.ravel())
        idx = np.flatnonzero(closed)
        comps = (idx[:, None] * d + np.arange(d)).ravel()
        minv = self._mass_inverse() if self._full_mass else None
        if minv is not None:  # sparse: M⁻¹ node by node
            Wm = self.op.mass_delassus(comps, minv=minv)
        elif self._full_mass:
            Wm = self.op.mass_delassus(comps, mass_solve=self._mass_solve)
        else:
            Wm = self.op.mass_delassus(comps, minv=self.minv)
        a_pres = self.op.Gp @ ex.prescribed(t0)[2] if ex.moves_supports else np.zeros(m * d)
        w_free = (G[comps] @ self._mass_solve(r) + a_pres[comps]).reshape(-1, d)
        zero = np.zeros((idx.size, d))
        start = PairState(ps.state[idx], ps.broken[idx], zero, zero, zero,
                          ps.slip_dir[idx], ps.path[idx])  # fmt: skip
        laws = self.model.pair_laws.subset(idx).scaled(1.0)
        sol, _ = InterfaceSolver(Wm, laws).solve(w_free, start, label=f"t = {t0:g} s")
        X = np.where(spring[:, None], ps.X, 0.0)
        X[idx] = sol.X
        return self._mass_solve(r + G.T @ X.ravel())

    def _mass_inverse(self) -> sp.csr_matrix | None:
        """M⁻¹ node by node (:func:`_node_block_pinv`), formed once, where the coupled
        mass is block-diagonal by node (Westergaard's blocks, no finite-element
        reservoir); None otherwise."""
        if self._mass_blocks is None and self._full_mass and not self.model.fe_reservoirs:
            self._mass_blocks = _node_block_pinv(self.system.M, self.system.free, self.d)
        return self._mass_blocks

    def _mass_solve(self, r: FloatArray) -> FloatArray:
        """M⁻¹ r on the DOFs with mass (zero on massless ones): the lumped diagonal, or,
        with a reservoir's added mass as a matrix, M itself: without a finite-element
        reservoir M is block-diagonal by node (Westergaard's d × d blocks), inverted node
        by node (:func:`_node_block_pinv`: a massless node of an inclined wet face has
        mass along the face's normal only, and no acceleration across it); else factorised
        once, on its DOFs with mass. ``r`` (n,) or (n, k)."""
        if not self._full_mass:
            return self.minv * r if r.ndim == 1 else self.minv[:, None] * r
        blocks = self._mass_inverse()
        if blocks is not None:
            return np.asarray(blocks @ r)
        if self._mass_factor is None:
            M = sp.csc_matrix(self.system.M)
            keep = np.flatnonzero(M.diagonal() > 0)
            self._mass_factor = (keep, factorize(sp.csc_matrix(M[keep][:, keep]), spd=True))
        keep, fac = self._mass_factor
        out = np.zeros_like(r, dtype=float)
        out[keep] = fac.solve(r[keep])
        return out

    # -- one step ------------------------------------------------------------------------------
    def step(self, cur: StepState, ex: Excitation | None = None) -> StepState:
        """One step; returns the next state (with the committed pair state of the
        step). Step k of a run is at t₀ + k h (t₀ the start's time), not at a running sum
        of h, so that a run of N steps ends at t₀ + N h to the rounding of one product."""
        ex = self.excitation() if ex is None else ex
        origin = cur.kin.t - cur.step * self.dt
        if cur.origin is not None:  # the state's grid, if its time is on it (an edited
            # start state, another step or time, falls back to t − step h)
            tol = 8 * np.spacing(max(abs(cur.kin.t), self.dt))
            if abs(cur.origin + cur.step * self.dt - cur.kin.t) <= tol:
                origin = cur.origin
        if self.mj is not None:
            nxt = self._step_moreau_jean(cur, ex, self.mj, origin)
        elif self.ga is not None:
            nxt = self._step_nonsmooth_alpha(cur, ex, self.ga, origin)
        else:
            nxt = self._step_newmark(cur, ex, origin)
        nxt.kin.t = origin + nxt.step * self.dt
        nxt.origin = origin
        nxt.static = cur.static
        if ex.form == "relative" and ex.ground and self.ga is None:
            nxt.ground = self._ground_applied(cur, nxt, ex)
        return nxt

    def _ground_applied(self, cur: StepState, nxt: StepState, ex: Excitation) -> FloatArray:
        """Σ ι a_g as the step cur → nxt applied it (:attr:`StepState.ground`): the
        Moreau–Jean load (1 − θ) f_n + θ f_{n+1} gives a free body the relative step-average
        acceleration −[(1 − θ) a_g(t_n) + θ a_g(t_{n+1})]; the Newmark family's balance at
        (α_m, α_f) gives it −g_{n+1} of the recurrence."""
        a1 = ex.ground_acceleration(nxt.kin.t)
        if self.mj is not None:
            th = self.mj.theta
            return a1 if th == 1.0 else (1.0 - th) * ex.ground_acceleration(cur.kin.t) + th * a1
        am, af = self.nm.alpha_m, self.nm.alpha_f
        if not am and not af:
            return a1
        a0 = ex.ground_acceleration(cur.kin.t)
        mixed = (1.0 - af) * a1 + af * a0
        g0 = a0 if cur.ground is None else cur.ground  # the recurrence's last value
        return mixed if not am else (mixed - am * g0) / (1.0 - am)

    def _step_newmark(self, cur: StepState, ex: Excitation, origin: float) -> StepState:
        """One step of the Newmark family (models without interfaces)."""
        kin = cur.kin
        t1 = origin + (cur.step + 1) * self.dt
        f_ext = ex.load(t1)
        if self.corot is None:
            u_free = self.nm.predict(kin, f_ext)
        else:
            # the frames of the step: those of the configuration Newmark's explicit part
            # predicts for t_{n+1}, so that the elastic force at t_{n+1} is taken in frames
            # close to its own (frames held at t_n would make the step first order)
            dt = self.dt
            R = self._corotate(kin.u + dt * kin.v + (0.5 - self.nm.beta) * dt**2 * kin.a)
            u_free = kin.u + self.corot.rotated_solve(self._increment_load(kin, f_ext, R), R)
        return StepState(self.nm.advance(kin, u_free, f_ext), cur.pairs, cur.step + 1)

    def _step_moreau_jean(
        self, cur: StepState, ex: Excitation, mj: MoreauJean, origin: float
    ) -> StepState:
        """One Moreau-Jean step (see :mod:`._moreau`): the free velocity, the pair impulses
        of the pairs predicted closed (and the intact ones) at the velocity level, then
        the positions. The committed pair state holds X = P/h, the step-average force."""
        kin, h, th = cur.kin, self.dt, mj.theta
        op0 = self.op  # the pair operator of the start (large rotations may turn it below)
        t1 = origin + (cur.step + 1) * h
        f1 = ex.load(t1)
        f_theta = (1 - th) * kin.f + th * f1
        if self.corot is None:
            v_free = mj.free_velocity(kin, f_theta)
        else:
            # in the frames R of the configuration predicted for t_{n+θ}, u_n + θh v_n, the
            # elastic force at u_θ = û + θ²h² v_{n+1} (û = u_n + θ(1 − θ)h v_n) is linear,
            # F(û) + Q K₀ Qᵀ θ²h² v_{n+1}, and Ŵ = Q Ŵ₀ Qᵀ (M lumped by node):
            # v_free = Q Ŵ₀⁻¹ Qᵀ (M v_n − h F(û) − (1 − θ)h C v_n + h f_θ); the damping
            # acts on v_θ in the frames R (the energy account takes its work there)
            R = self._corotate(kin.u + th * h * kin.v)
            u_hat = kin.u + th * (1 - th) * h * kin.v
            r = self.system.M @ kin.v + h * (f_theta - self.elastic_force(u_hat, R))
            if self.system.C is not None:
                r = r - (1 - th) * h * self.damping_force(kin.v, kin.u, R)
            v_free = self.corot.rotated_solve(r, R)
        m, d = self.m, self.d
        if not m:
            return StepState(mj.advance(kin, v_free, f1), cur.pairs, cur.step + 1)
        assert self.istep is not None
        prev = cur.pairs
        moving = ex.moves_supports
        U0 = self.op.relative(kin.v, ex.prescribed(kin.t)[1] if moving else None)
        active = (prev.s[:, -1] + 0.5 * h * U0[:, -1] <= _GAP_TOL) | ~prev.broken
        start = PairState(np.where(active, prev.state, OPEN).astype(np.int8), prev.broken,
                          prev.X * h, np.zeros_like(prev.w), np.zeros_like(prev.s),
                          prev.slip_dir, prev.path)  # fmt: skip
        U_pres = self.op.Gp @ ex.prescribed(t1)[1] if moving else np.zeros(m * d)
        sol = self.istep.solve(v_free, U_pres, start, inactive=~active,
                               label=f"step {cur.step + 1} (t = {t1:.6g} s)")  # fmt: skip
        new = mj.advance(kin, v_free + sol.du, f1)
        laws = self.model.pair_laws
        P = sol.pairs
        if moving:
            # the supports' share of the relative motion by the step's own θ-rule, as the
            # blocks' (u_{n+1} = u_n + h v_θ): with the exact prescribed displacement the
            # gap of a block resting on a base that moves drifts by h v_g(t_{n+1}) − ∫v_g a
            # step (O(h² a_g), up to 5e-5 m at Δt = 2 ms under 0.2 g vertical shaking), and
            # the pairs it opens drop out for a step of free fall and a landing. The share
            # at t_n is what the blocks' part G u_n leaves of w_n (in the start's frames)
            vp = (1.0 - th) * ex.prescribed(kin.t)[1] + th * ex.prescribed(t1)[1]
            share = prev.w.ravel() - op0.G @ kin.u + h * (self.op.Gp @ vp)
            w = (self.op.G @ new.u + share).reshape(m, d)
        else:
            w = (self.op.G @ new.u + self.w_pres(t1, ex)).reshape(m, d)
        s = w.copy()
        s[:, -1] += laws.gap
        trial = PairState(P.state, P.broken, P.X / h, w, s, P.slip_dir, prev.path)
        return StepState(new, trial.committed(prev), cur.step + 1)

    def _step_nonsmooth_alpha(
        self, cur: StepState, ex: Excitation, ga: NonsmoothAlpha, origin: float,
        ahead_next: bool = True,
    ) -> StepState:  # fmt: skip
        """One nonsmooth generalised-α step (method.md §3.1):

        1. smooth step: q̈_free (one back-substitution), then the smooth pair forces λ of
           the pairs closed at t_n from the acceleration-level law on G q̈_{n+1}
           (intact pairs bilateral; sliding pairs keep X_t = −(c A + μ X_n) ŝ; breaks
           decided on converged forces), q̈ = q̈_free + s Ŝ⁻¹Gᵀλ, and q̃, ṽ;
        2. velocity correction on the pairs predicted closed (g(q̃) ≤ tol), pushed
           (λ_n > 0) or intact: the velocity-level law (e = 0) on the step impulse P,
           v_{n+1} = ṽ + s Ŝ⁻¹Gᵀ(P − hλ);
        3. position correction: the pairs that penetrate at q̃ are moved apart along
           their normal in the lumped-mass metric, one pair at a time.

        The committed pair state holds X = P/h (the step-average force) and the
        relative motion at q_{n+1}; the recorded acceleration is the smooth q̈."""
        kin, h = cur.kin, self.dt
        t1 = origin + (cur.step + 1) * h
        ahead = self._ahead
        if ahead is not None and ahead[0] is kin and ahead[1] is ex and ahead[2] == t1:
            # computed at the end of the previous step, right after its block solve (see
            # below): the same numbers, from a factor still in the cache
            f1, acc_free = ahead[3], ahead[4]
        elif self.corot is None:
            f1 = ex.load(t1)
            acc_free = ga.free_acceleration(kin, f1)
        else:
            f1 = ex.load(t1)
            # the frames of the configuration predicted for t_{n+1} (q̂ + β h²/s q̈_n), in
            # which the elastic force at q̃ is linear: F(q̂) + Q K₀ Qᵀ (β h²/s) q̈
            _, q_hat, v_hat = ga.known(kin)
            R = self._corotate(q_hat + ga.weights[0] * kin.a)
            r = f1 - self.elastic_force(q_hat, R) - self.damping_force(v_hat, q_hat, R)
            acc_free = self.corot.rotated_solve(ga.s * r, R)
        m, d = self.m, self.d
        if not m:
            return StepState(ga.advance(kin, acc_free, f1), cur.pairs, cur.step + 1)
        assert self.istep is not None and self.vstep is not None
        label = f"step {cur.step + 1} (t = {t1:.6g} s)"
        prev = cur.pairs
        moving = ex.moves_supports
        pres = ex.prescribed(t1) if moving else None
        # G_p u_p(t_{n+1}), once a step (the frames do not turn within it)
        wp1 = self.op.w_prescribed(pres[0]) if pres is not None else self._w_pres0
        Gp = self.op.Gp
        zero = np.zeros((m, d))
        # 1. the smooth pair forces at the acceleration level, posed in displacement units:
        # rigid contacts on the increment c_q G q̈, springs on G q_{n+1} (see the set-up)
        G = self.op.G
        laws = self.model.pair_laws
        spring = self._spring
        closed = (prev.state != OPEN) & ~spring  # the rigid contacts closed at t_n
        # the strength at t_{n+1}: slip-dependent laws at the path predicted for t_{n+1}
        # from the slip rate at t_n (second order in the path; the committed path is kept)
        U0 = self.op.relative(kin.v, ex.prescribed(kin.t)[1] if moving else None)
        rate = np.where(prev.state == SLIDE, np.linalg.norm(U0[:, :-1], axis=1), 0.0)
        path = prev.path + h * rate
        _, q_hat, v_hat = ga.known(kin)
        cq, cv = ga.weights
        a_pres = Gp @ pres[2] if pres is not None else zero.ravel()
        g_free = G @ acc_free
        w_free = cq * (g_free + a_pres)
        if spring.any():
            # springs: G q_{n+1} = G q̂ + c_q G q̈ (with the prescribed side at t_{n+1}),
            # and the committed s, their elastic reference
            w_known = G @ q_hat + wp1
            sc = np.repeat(spring, d)
            w_free[sc] = w_known[sc] + cq * g_free[sc]
            sw, ss = np.where(spring[:, None], prev.w, 0.0), np.where(spring[:, None], prev.s, 0.0)
        else:
            sw = ss = zero
        start = PairState(prev.state, prev.broken, prev.X, sw, ss, prev.slip_dir, path)
        sol = self.istep.solve(None, w_free, start, label, inactive=~(closed | spring),
                               fixed=(prev.state == SLIDE) & ~spring, breaking="converged",
                               correct=False)  # fmt: skip
        lam = sol.pairs.X
        # the relative motion of the smooth step from G q̈ (no block solve yet)
        w_sol = sol.pairs.w.ravel()
        g_acc = w_sol / cq - a_pres
        if spring.any():
            g_acc[sc] = (w_sol[sc] - w_known[sc]) / cq
        gap = (G @ q_hat + cq * g_acc + wp1).reshape(m, d)[:, -1] + laws.gap
        u_pres = Gp @ pres[1] if pres is not None else zero.ravel()
        U_minus = G @ v_hat + cv * g_acc + u_pres  # G ṽ (+ the supports' velocity)
        # 2. the velocity correction on the step impulse P (U = G ṽ + s W (P − hλ)), for
        # the rigid contacts (a spring takes no impulse), scaled by c_q as the smooth problem
        broken = sol.pairs.broken
        part = ~spring & (~broken | (gap <= _GAP_TOL) | (lam[:, -1] > 0))
        state = np.where(part | spring, sol.pairs.state, OPEN).astype(np.int8)
        P = PairState(state, broken, h * lam, zero, zero, sol.pairs.slip_dir, path)
        if not self._impulse_is_smooth(P, closed, part, U_minus.reshape(m, d)):
            w_free = cq * (U_minus - self.vstep.W.apply(ga.s * h * lam.ravel()))
            P = self.vstep.solve(None, w_free, P, label, inactive=~part, breaking="converged",
                                 correct=False).pairs  # fmt: skip
            P.X[spring] = h * lam[spring]
            P.state[spring] = sol.pairs.state[spring]
            self.velocity_corrections += 1
        # one block solve for both: q̈ = q̈_free + sŜ⁻¹Gᵀλ, v = ṽ + sŜ⁻¹Gᵀ(P − hλ)
        W = self.vstep.W
        Lam = P.X - h * lam  # the impulses beyond hλ
        cols = [c for c in (lam.ravel(), Lam.ravel()) if c.any()]
        Z = None
        if cols:
            rhs = ga.s * np.column_stack(cols)
            Z = np.asarray(W.correct(rhs))
        parts = iter(range(len(cols)))
        acc = acc_free + Z[:, next(parts)] if Z is not None and lam.any() else acc_free
        dv = Z[:, next(parts)] if Z is not None and Lam.any() else 0.0
        smooth = ga.advance(kin, acc, f1)
        v1 = smooth.v + dv
        # 3. the position correction: the pairs that penetrate at q̃ are moved apart along
        # their normal in the lumped-mass metric, one pair at a time (method.md §3.1)
        u1 = smooth.u
        dq: FloatArray | None = None
        pen = P.broken & (gap < 0.0) & (self._gmg > 0) & ~spring
        if pen.any():
            metric = self._rigid_correction()
            by_rigid = pen & metric[2] if metric is not None else np.zeros(m, dtype=bool)
            nu = np.zeros((m, d))
            local = pen & ~by_rigid
            nu[local, -1] = -gap[local] / self._gmg[local]
            dq = self.minv * (self.op.Gt @ nu.ravel())
            if metric is not None and by_rigid.any():
                dq = dq + self._rigid_shift(metric, by_rigid, gap)
            u1 = u1 + dq
        # the energy of the impulses, split so that each part has its sign (docs/theory.md,
        # "The signs of impact and interface"): the rigid pairs' dissipation −P·U⁺ (≥ 0 by
        # the velocity-level law that P and U⁺ = U⁻ + sWΛ satisfy), the impact
        # ½Λ·(U⁺ − U⁻) = ½sΛᵀWΛ (≥ 0, W positive), and the strain energy the position
        # correction stores
        U_plus = self.op.relative(v1, pres[1] if pres is not None else None)
        rigid = ~spring
        dissipation = -float(np.sum(P.X[rigid] * U_plus[rigid]))
        impact = correction = 0.0
        if Lam.any():  # U⁺ − U⁻ = G δv with δv = sŜ⁻¹GᵀΛ: ½Λ·Gδv = ½sΛᵀWΛ ≥ 0
            impact = 0.5 * float(Lam.ravel() @ (G @ dv))
        if dq is not None:
            # the potential energy it adds: strain, and the loads' (the step-average load
            # over Δq, as the external work counts it)
            correction = self._strain_added(u1, dq) - 0.5 * float(dq @ (kin.f + f1))
        new = State(t1, u1, v1, acc, f1, smooth.aux)
        if ahead_next and self.corot is None and not ex.follows_pairs:
            # (not where an uplift follows the pairs: the load of t_{n+2} is that of the
            # pairs open at t_{n+1}, set after this step)
            # the next step's free acceleration (it depends on this step's state and the
            # load at t_{n+2} only) now, while the factor is in the processor's cache from
            # the block solve above: after the recorder's sweeps it would be read from
            # memory again (a back-substitution costs up to twice as much there)
            t2 = origin + (cur.step + 2) * h
            f2 = ex.load(t2)
            self._ahead = (new, ex, t2, f2, ga.free_acceleration(new, f2))
        w = (G @ u1 + wp1).reshape(m, d)
        X = P.X / h
        trial = PairState(P.state, P.broken, X, w, laws.s_of(w, X), P.slip_dir, prev.path)
        return StepState(new, trial.committed(prev), cur.step + 1, lam=lam, impact=impact,
                         dissipation=dissipation, correction=correction, shift=dq)  # fmt: skip

    def _impulse_is_smooth(
        self, P: PairState, closed: BoolArray, part: BoolArray, U: FloatArray
    ) -> bool:
        """Whether the step impulse P = hλ already satisfies the velocity-level law, so
        that the velocity correction can be skipped: the same pairs take part as carried
        smooth forces (nothing new touches), and at U = G ṽ the intact and sticking pairs
        do not move, the sliding ones keep sliding along their direction and the open
        ones separate (to the solver's tolerance)."""
        if not np.array_equal(part, closed):
            return False
        d = self.d
        Up = U[part]
        if not Up.size:
            return True
        tol = self.settings.tolerance * max(float(np.abs(U).max()), 1e-300)
        st = P.state[part]
        still = (st == INTACT) | (st == STICK)
        if np.abs(Up[still]).max(initial=0.0) > tol:
            return False
        if (Up[st == OPEN, -1] < -tol).any():
            return False
        sl = st == SLIDE
        if sl.any():
            if np.abs(Up[sl, -1]).max() > tol:
                return False
            sdir = P.slip_dir[part][sl]
            along = np.einsum("kj,kj->k", Up[sl, :-1], sdir)
            if (along <= tol).any():
                return False
            if d == 3:
                across = Up[sl, :-1] - along[:, None] * sdir
                if np.abs(across).max() > tol:
                    return False
        return True

    # -- event sub-steps -----------------------------------------------------------------------
    def _is_event(self, cur: StepState, nxt: StepState) -> bool:
        """Whether the step cur → nxt is an event to be taken again in sub-steps: a pair
        changes state (breaks, opens, closes, starts or stops sliding)."""
        if self.settings.event_substeps == 1 or not self.m:
            return False
        a, b = cur.pairs, nxt.pairs
        return bool((a.state != b.state).any() or (a.broken != b.broken).any())

    def fine(self) -> Dynamic:
        """The analysis of the same model at dt/k (k = ``event_substeps``) that takes an
        event's sub-steps: its step matrix factorised once, on first need."""
        if self._fine is None:
            k = self.settings.event_substeps
            t0 = _time.perf_counter()
            settings = self.settings.model_copy(update={"dt": self.dt / k, "event_substeps": 1})
            self._fine = Dynamic(self.model, settings=settings)
            self.setup_time += _time.perf_counter() - t0
            log.info("event sub-steps: the step matrix factorised for dt/%d = %.4g s", k,
                     self.dt / k)  # fmt: skip
        return self._fine

    def substeps(
        self, cur: StepState, ex: Excitation, on_substep: Callable[[StepState, StepState], None]
    ) -> StepState:  # fmt: skip
        """The step after ``cur`` taken as k sub-steps of dt/k by :meth:`fine`: the
        state at the end of the step, on the grid of dt. ``on_substep(a, b)`` is called
        after each sub-step a → b (the energy account, the uplift of the pairs that
        open). The sub-steps start from the step's own state: the nonsmooth generalised-α
        carries its auxiliary acceleration, a weighted acceleration that does not depend
        on h, from one step size to the other."""
        fine = self.fine()
        k = self.settings.event_substeps
        sub = StepState(cur.kin, cur.pairs, 0, lam=cur.lam, origin=cur.kin.t)
        with ex.refined(cur.kin.t, k):  # the supports' grid too (absolute form)
            for _ in range(k):
                nxt = fine.step(sub, ex)
                on_substep(sub, nxt)
                sub = nxt
        origin = cur.kin.t - cur.step * self.dt if cur.origin is None else cur.origin
        sub.kin.t = origin + (cur.step + 1) * self.dt  # the grid of dt, not a sum of dt/k
        self.event_steps += 1
        return StepState(sub.kin, sub.pairs, cur.step + 1, lam=sub.lam, impact=sub.impact,
                         dissipation=sub.dissipation, correction=sub.correction,
                         shift=sub.shift, origin=origin, static=cur.static,
                         ground=sub.ground)  # fmt: skip

    def _event_step(
        self, cur: StepState, ex: Excitation, rec: Recorder
    ) -> tuple[StepState, tuple[int, int, float, int]]:  # fmt: skip
        """An event step of a run taken in sub-steps (:meth:`substeps`), each added to
        the run's energy account by the sub-steps' analysis and followed by the uplift of
        the pairs it opens; with the sub-steps' solver counters (iterations, steps with
        a fallback, the worst residual, solves the semismooth Newton finished)."""
        fine = self.fine()
        fstats = fine.istep.stats if fine.istep is not None else None
        counts = [0, 0, 0.0, 0]
        if fstats is not None:
            fstats.reset()
        account = dict(rec.account.acc)
        corrections = fine.velocity_corrections

        def on_substep(a: StepState, b: StepState) -> None:
            rec.account.add_step(a, b, fine)
            if ex.follows_pairs:
                ex.follow(b.pairs.state == OPEN)
            if fstats is not None:
                counts[0] += fstats.iterations
                counts[1] += fstats.fallbacks > 0
                counts[2] = max(counts[2], fstats.residual)
                counts[3] += fstats.newton
                fstats.reset()

        try:
            nxt = self.substeps(cur, ex, on_substep)
        except InterfaceError:
            # a sub-step's pair problem failed: the sub-steps are undone (the energy
            # account, the uplift of the pairs they opened) and the caller keeps the step
            # of dt it took first
            rec.account.acc.update(account)
            if ex.follows_pairs:
                ex.follow(cur.pairs.state == OPEN)
            raise
        finally:
            self.velocity_corrections += fine.velocity_corrections - corrections
        return nxt, (int(counts[0]), int(counts[1]), float(counts[2]), int(counts[3]))

    def _increment_load(self, kin: State, f_ext: FloatArray, R: FloatArray) -> FloatArray:
        """Right-hand side of the corotational step (see :mod:`._corotation`)."""
        _, _, a2, a3, a4, a5 = self.nm.c
        w = a2 * kin.v + a3 * kin.a
        r = f_ext - self.elastic_force(kin.u, R) + (self.system.M @ w if self._full_mass
                                                     else self.mass * w)  # fmt: skip
        if self.system.C is not None:
            r = r + self.damping_force(a4 * kin.v + a5 * kin.a, kin.u, R)
        return r

    # -- run -----------------------------------------------------------------------------------
    def run(
        self,
        duration: float | None = None,
        *,
        n_steps: int | None = None,
        ground: Sequence[GroundMotion] = (),
        form: str = "relative",
        start: StepState | object | None = None,
        probes: Sequence[int] | IntArray = (),
        every: int = 1,
        callback: Callable[[StepState], None] | None = None,
        on_record: Callable[[dict[str, Any]], None] | None = None,
        resume: Checkpoint | None = None,
        on_checkpoint: Callable[[Checkpoint], None] | None = None,
        envelope: bool = True,
    ) -> DynamicResult:
        """Integrate over ``duration`` (s) or ``n_steps`` steps under the records
        ``ground`` (relative or absolute ``form``), recording the steps whose number is a
        multiple of ``every``, and the last step. ``start`` is a :class:`StepState`, a
        static result or None. A run from a state (``start=result.final``) goes on at the
        state's time t₀ and reads its records there: an aftershock recorded from t = 0 is
        given as ``aftershock.shifted(t0)`` in the relative form (a record that ends by t₀
        is refused after a run under other records, and so is the absolute form, whose
        supports would jump).
        ``on_record`` receives every recorded row (probe, rigid, pair and energy values,
        and the full nodal u, v, a), e.g. to stream them to a results file.

        ``envelope`` keeps the running extremes of the principal stresses at every
        recorded row (:class:`~pfeie.dynamics.StressEnvelope`; ``result.envelope``; one
        sparse product a row; not with ``large_rotation``, whose total displacement holds
        rigid rotations).

        Checkpoint and resume: ``on_checkpoint`` is called at every recorded row after
        the first with a :class:`Checkpoint` (the state, the energy account, the row
        index; cheap: it holds references); a run given ``resume=checkpoint`` continues
        from it exactly (the same bits as a run that was never stopped; its row 0, the
        checkpoint's, is not passed to ``on_record`` again), for ``duration`` or
        ``n_steps`` more steps.

        If a step fails (the interface problem does not converge), the histories up to
        the last completed step are returned with ``completed = False`` and the error is
        logged; nothing computed is lost.
        """
        self._check_model()
        if (duration is None) == (n_steps is None):
            raise ModelError("give either duration or n_steps")
        given: Any = n_steps  # the API takes what a caller gives: a float too
        if given is not None and not (isinstance(given, (int, np.integer)) or (
                isinstance(given, float) and given.is_integer())):  # fmt: skip
            raise ModelError(f"n_steps: expected a whole number of steps, got {given!r}")
        if duration is not None and (isinstance(duration, bool) or not isinstance(
                duration, int | float | np.integer | np.floating)):  # fmt: skip
            raise ModelError(f"duration: expected a number of seconds, got {duration!r}")
        try:
            n = int(n_steps) if n_steps is not None else self.settings.steps(float(duration or 0))
        except ValueError as exc:
            raise ModelError(str(exc)) from None
        if n < 0:
            raise ModelError(f"n_steps must be >= 0, got {n}")
        if isinstance(every, bool) or not isinstance(every, int | np.integer) or every < 1:
            raise ModelError(f"every: expected a whole number of steps >= 1, got {every!r}")
        for arg, fn in (("callback", callback), ("on_record", on_record),
                        ("on_checkpoint", on_checkpoint)):  # fmt: skip
            if fn is not None and not callable(fn):
                raise ModelError(f"{arg}: expected a function (or None), got "
                                 f"{type(fn).__name__} {fn!r}")  # fmt: skip
        if isinstance(start, StepState):
            self._check_state(start, "start")  # (before its uplift is read)
        # the pre-earthquake uplift: that of the static result the run starts from (a
        # StepState's own, e.g. Dynamic.initial(static) or a previous run's final state)
        ex = self.excitation(ground, form, start.static if isinstance(start, StepState)
                             else start)  # fmt: skip
        for g in ex.ground:
            why = shorter_than_a_step(g, self.dt)
            if why is not None:
                raise ModelError(f"ground motion {g.name!r}: {why}")
            self.model.warn_along_gravity(g.name, g.direction)
        if isinstance(start, StepState) and resume is None:
            self._records_from(start, ex, n)
        if resume is not None:
            if not isinstance(resume, Checkpoint):
                raise ModelError(f"resume: expected a pfeie Checkpoint (from on_checkpoint), "
                                 f"got {type(resume).__name__}")  # fmt: skip
            key = ex.key
            if resume.excitation is not None and resume.excitation[0] != key[0]:
                raise ModelError(
                    f"resume: the checkpoint was taken under {resume.excitation[1]}; this "
                    f"run is given {key[1]} (or the records' samples differ): a resumed run "
                    "continues the same run, so give it the same records and form (to "
                    "continue under another record, start from the state: "
                    "start=checkpoint.state)")  # fmt: skip
            if resume.analysis is not None and resume.analysis[0] != self.key[0]:
                raise ModelError(
                    f"resume: the checkpoint was taken by another analysis "
                    f"({resume.analysis[1]}); this one has {self.key[1]} (or their "
                    "settings, matrices or laws' parameters differ): a resumed run continues "
                    "the same run, so resume it with the analysis that took the checkpoint "
                    "(to go on with another, start from the state: "
                    "start=checkpoint.state)")  # fmt: skip
            cur, row0 = resume.state, resume.row
            self._check_state(cur, "resume")
            if self.corot is not None:
                self._corotate(cur.kin.u)
            if self.m and ex.follows_pairs:  # the uplift of the pairs open at the checkpoint
                ex.follow(cur.pairs.state == OPEN)
        else:
            if isinstance(start, StepState):
                cur = start
            else:
                self._supports_on_grid(ex, 0.0, trial=True)  # (the start's trial step)
                cur = self._initial(ex, start)
            row0 = 0
            if isinstance(start, StepState) and self.m and ex.follows_pairs:
                ex.follow(cur.pairs.state == OPEN)  # as on resume: the pairs open now
        self._supports_on_grid(ex, cur.kin.t - cur.step * self.dt if cur.origin is None
                               else cur.origin)  # fmt: skip
        # (from a state: only under the same records and Δt, the grid its rows are of)
        rows = resume.supports if resume is not None else (
            cur.supports[2] if cur.supports is not None and cur.supports[0] == ex.key[0]
            and cur.supports[1] == self.dt else None)  # fmt: skip
        if rows is not None:
            try:  # (where event sub-steps moved them off the grid's own recurrence)
                ex.restart_grid(cur.kin.t, rows)
            except ValueError as exc:
                raise ModelError(f"{'resume' if resume is not None else 'start'}: {exc}") from None
        m, d = self.m, self.d
        probes = self._probes(probes)
        # rows: the start, the steps on the grid of `every`, a spare one for a stop
        rec = Recorder(self, ex, probes, n // every + 3, on_record,
                       origin=None if resume is None else resume.origin, envelope=envelope,
                       envelope_values=None if resume is None else resume.envelope)  # fmt: skip
        if resume is not None:
            rec.account.acc.update(resume.energy)
        # the cost of the pair problems of every step: iterations, whether a solve needed
        # a fallback, the worst residual, whether the semismooth Newton finished a solve
        # (summed per recorded row for the results file: steps since the previous row)
        iters = np.zeros(n + 1, dtype=np.int32)
        falls = np.zeros(n + 1, dtype=np.int32)
        resid = np.zeros(n + 1)
        newton = np.zeros(n + 1, dtype=np.int32)
        substeps = np.zeros(n + 1, dtype=np.int32)  # sub-steps of an event step (0: none)
        stats = self.istep.stats if m and self.istep is not None else None
        first = 1  # the first step of the row being gathered

        def since(i: int) -> list[Any]:
            """The solver's counters of steps ``first`` to i, for their recorded row."""
            rows = slice(first, i + 1)
            return [int(iters[rows].sum()), int(falls[rows].sum()),
                    float(resid[rows].max(initial=0.0)), int(newton[rows].sum()),
                    int(substeps[rows].sum())]  # fmt: skip

        if m and start is not None and not isinstance(start, StepState) and resume is None:
            cur.pairs.w = (self.op.G @ cur.kin.u + self.w_pres(cur.kin.t, ex)).reshape(m, d)
        rec.record(0, cur, emit=resume is None)
        t_wall = _time.perf_counter()
        completed = True
        reason: str | None = None
        j = 0

        def checkpoint() -> None:
            if on_checkpoint is not None:
                # (for a run from the checkpoint's state; not written on the caller's start)
                state = dataclasses.replace(cur) if cur is start else cur
                state.records = ex.key
                on_checkpoint(rec.checkpoint(state, row0 + j))

        for i in range(1, n + 1):
            if stats is not None:
                stats.reset()
            event = False
            try:
                nxt = self.step(cur, ex)
                if self._is_event(cur, nxt):
                    # taken again in sub-steps; the solver's counters hold the work of both
                    work = ((stats.iterations, stats.fallbacks, stats.newton)
                            if stats is not None else (0, 0, 0))  # fmt: skip
                    try:
                        nxt, sub_counts = self._event_step(cur, ex, rec)
                        event = True
                    except InterfaceError as exc:
                        log.warning("step %d (t = %.6g s): the event's sub-steps failed (%s); "
                                    "the step of dt is kept", cur.step + 1,
                                    cur.kin.t + self.dt, exc)  # fmt: skip
            except InterfaceError as exc:
                # the pairs it names, by joint and place
                reason = f"{exc}{self.model.pair_text(exc.pairs)}"
                log.error("run stopped: %s", reason)
                completed = False
                if cur.step % every:  # keep the last completed step, with its counters
                    j += 1
                    rec.record(j, cur, solver=since(i - 1))
                    checkpoint()
                break
            if event:
                substeps[i] = self.settings.event_substeps
                iters[i] = work[0] + sub_counts[0]
                falls[i], resid[i] = work[1] + sub_counts[1] > 0, sub_counts[2]
                newton[i] = work[2] + sub_counts[3] > 0
            else:
                rec.account.add_step(cur, nxt)
                if m and ex.follows_pairs:
                    ex.follow(nxt.pairs.state == OPEN)
                if stats is not None:
                    iters[i], resid[i] = stats.iterations, stats.residual
                    falls[i], newton[i] = stats.fallbacks > 0, stats.newton > 0
            cur = nxt
            on_grid = cur.step % every == 0
            if on_grid:
                j += 1
                rec.record(j, cur, solver=since(i))
                first = i + 1
            stop: str | None = None
            if callback is not None:
                try:
                    callback(cur)
                except RunStopped as exc:
                    log.warning("run stopped at step %d (t = %.4g s): %s", cur.step,
                                cur.kin.t, exc)  # fmt: skip
                    stop = f"stopped: {exc}"
            if stop is not None:
                completed, reason = False, stop
                if not on_grid:
                    j += 1
                    rec.record(j, cur, solver=since(i))
                checkpoint()
                break
            if on_grid:
                checkpoint()
        else:
            if cur.step % every and j < rec.t.size - 1 and n:
                # the last step off the grid of `every`: recorded, so that the run's end
                # (and what the summary reads from it) is never a step that was dropped;
                # not a checkpoint: a run extended from this one continues from the last
                # row on the grid, and its rows are those of a run that never stopped
                j += 1
                rec.record(j, cur, solver=since(n))
        wall = _time.perf_counter() - t_wall
        if cur is start:  # (no step taken: the caller's start state is not written on)
            cur = dataclasses.replace(cur)
        if ex.moves_supports and (grid := ex.grid_rows(cur.kin.t)) is not None:
            cur.supports = (ex.key[0], self.dt, grid)  # (for a run from it: start=final)
        cur.records = ex.key
        self._warn_corrections(rec)
        solver: dict[str, np.ndarray] = {"iterations": iters, "fallbacks": falls,
                                         "residual": resid, "newton": newton,
                                         "substeps": substeps}  # fmt: skip
        return rec.result(j + 1, cur, iters, wall, completed, reason, solver)


__all__ = [
    "CORRECTION_UNRESOLVED",
    "ENERGY_FLOOR",
    "Checkpoint",
    "Dynamic",
    "RunStopped",
    "StepState",
]


def _node_block_pinv(M: sp.csr_matrix, free: IntArray, d: int) -> sp.csr_matrix:
    """The pseudo-inverse of a mass matrix ``M`` on the free DOFs ``free`` that is
    block-diagonal by node (the blocks' lumped mass and Westergaard's d × d nodal
    blocks), node by node: each node's block over its free components is inverted on its
    eigenvalues above 1e-12 of its largest (zero blocks, massless nodes, stay zero; a
    massless node of an inclined wet face, m_a n nᵀ, gets n nᵀ/m_a)."""
    coo = M.tocoo()
    node, comp = free // d, free % d
    assert np.all(node[coo.row] == node[coo.col]), "M couples DOFs of different nodes"
    n_nodes = int(node.max()) + 1 if node.size else 0
    blocks = np.zeros((n_nodes, d, d))
    np.add.at(blocks, (node[coo.row], comp[coo.row], comp[coo.col]), coo.data)
    w, vec = np.linalg.eigh(blocks)
    big = w.max(axis=1, keepdims=True)
    winv = np.divide(1.0, w, out=np.zeros_like(w), where=(w > 1e-12 * big) & (big > 0))
    inv = np.einsum("pik,pk,pjk->pij", vec, winv, vec)
    # every pair of free DOFs of a node
    index = np.full((n_nodes, d), -1)
    index[node, comp] = np.arange(free.size)
    rows = np.broadcast_to(index[:, :, None], inv.shape)
    cols = np.broadcast_to(index[:, None, :], inv.shape)
    keep = (rows >= 0) & (cols >= 0) & (inv != 0.0)
    return sp.csr_matrix((inv[keep], (rows[keep], cols[keep])), shape=(free.size, free.size))
