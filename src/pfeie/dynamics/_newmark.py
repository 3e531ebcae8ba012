"""Newmark, HHT-α and generalised-α time integration of M ü + C u̇ + K u = f(t).

The integrator sees only matrices and a load function (a :class:`SecondOrderSystem`);
space discretisation lives elsewhere. Displacement form, one factorisation of the
effective matrix per (Δt, model) and one back-substitution per step.

Theory
------
Newmark's relations (Newmark 1959) with Δu = u_{n+1} − u_n:

    a_{n+1} = a₀ Δu − a₂ v_n − a₃ a_n,     v_{n+1} = a₁ Δu − a₄ v_n − a₅ a_n,

    a₀ = 1/(βΔt²), a₁ = γ/(βΔt), a₂ = 1/(βΔt), a₃ = 1/(2β) − 1,
    a₄ = γ/β − 1,  a₅ = Δt (γ/(2β) − 1).

The generalised-α method (Chung & Hulbert 1993) enforces the balance at intermediate
instants, x_{n+1−α} = (1 − α) x_{n+1} + α x_n:

    M a_{n+1−α_m} + C v_{n+1−α_f} + K u_{n+1−α_f} = f_{n+1−α_f}.

Substituting Newmark's relations gives K̂ u_{n+1} = P̂ with

    K̂ = (1 − α_m) a₀ M + (1 − α_f)(K + a₁ C),
    P̂ = (1 − α_f) f_{n+1} + α_f f_n + M[(1 − α_m)(a₀u_n + a₂v_n + a₃a_n) − α_m a_n]
        + C[(1 − α_f)(a₁u_n + a₄v_n + a₅a_n) − α_f v_n] − α_f K u_n.

Members of the family: Newmark (α_m = α_f = 0; β = 1/4, γ = 1/2 by default); HHT-α
(Hilber, Hughes & Taylor 1977) with α ∈ [−1/3, 0]: α_m = 0, α_f = −α, β = (1 − α)²/4,
γ = (1 − 2α)/2; generalised-α from the spectral radius at infinity ρ∞ ∈ [0, 1]:
α_m = (2ρ∞ − 1)/(ρ∞ + 1), α_f = ρ∞/(ρ∞ + 1), γ = 1/2 − α_m + α_f,
β = (1 − α_m + α_f)²/4 (second order, unconditionally stable, with the least low-frequency
dissipation for a given high-frequency one).

The step is split as :meth:`Newmark.predict` (P̂ and one solve: the free response that
the interface solver of PFE/IE corrects) and :meth:`Newmark.advance` (velocities and
accelerations from the accepted u_{n+1}).

Energy: with β = 1/4, γ = 1/2 (average acceleration, the default) the discrete balance
ΔT + ΔU + Δu·C v̄ = Δu·f̄ holds exactly (bars: step averages), so the scheme conserves
T + U in free vibration; γ > 1/2, α ≠ 0 or ρ∞ < 1 dissipate high frequencies.

Example
-------
>>> import numpy as np, scipy.sparse as sp
>>> from pfeie.dynamics import Newmark, MatrixSystem
>>> sys1 = MatrixSystem(M=sp.csr_matrix([[1.0]]), K=sp.csr_matrix([[(2*np.pi)**2]]))
>>> nm = Newmark(sys1, dt=1e-3)
>>> hist = nm.run(1000, nm.initial_state(u0=np.array([1.0])), record=[0])
>>> bool(abs(hist.u[-1, 0] - 1.0) < 1e-4)   # one period later, back at u = 1
True
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Protocol

import numpy as np
import scipy.sparse as sp

from ..errors import ModelError
from ..linalg import Factorization, LowRankTerm, UpdatedFactorization, factorize
from ..typing import FloatArray, IntArray

log = logging.getLogger(__name__)


class SecondOrderSystem(Protocol):
    """What a time integrator needs: M, K, optional damping and f(t). The damping is
    C + U B Uᵀ: ``C`` sparse (n × n) and ``C_update`` an optional symmetric low-rank term
    (:class:`pfeie.linalg.LowRankTerm`; the damping of the deformation only removes the
    floating bodies' rigid modes from C this way, :meth:`pfeie.Model.system`). Integrators
    apply it with :func:`damping_product` and factorise with :func:`factorize_step`
    (a system without the attribute ``C_update`` has none)."""

    @property
    def M(self) -> sp.spmatrix: ...
    @property
    def K(self) -> sp.spmatrix: ...
    @property
    def C(self) -> sp.spmatrix | None: ...

    def load(self, t: float) -> FloatArray: ...


@dataclass(frozen=True)
class MatrixSystem:
    """A :class:`SecondOrderSystem` from explicit matrices and an optional load function."""

    M: sp.spmatrix
    K: sp.spmatrix
    C: sp.spmatrix | None = None
    f: Callable[[float], FloatArray] | None = None
    C_update: LowRankTerm | None = None

    def load(self, t: float) -> FloatArray:
        return np.zeros(self.K.shape[0]) if self.f is None else np.asarray(self.f(t), float)


def damping_product(system: SecondOrderSystem, v: FloatArray) -> FloatArray:
    """The damping force (C + U B Uᵀ) v of ``system`` (N; zero without damping)."""
    if system.C is None:
        return np.zeros_like(v)
    out = np.asarray(system.C @ v)
    update: LowRankTerm | None = getattr(system, "C_update", None)
    if update is not None:
        out = out + update @ v
    return out


def factorize_step(
    system: SecondOrderSystem, A: sp.spmatrix, c: float, backend: str = "auto"
) -> Factorization:
    """Factorise a step's effective matrix A, which holds c C (the sparse damping, c the
    scheme's weight of it); with a low-rank damping term the factor is that of
    A + c U B Uᵀ, by Woodbury on the factor of A (:class:`pfeie.linalg.UpdatedFactorization`)."""
    F = factorize(sp.csc_matrix(A), spd=True, backend=backend)
    update: LowRankTerm | None = getattr(system, "C_update", None)
    if system.C is None or update is None or c == 0.0:
        return F
    return UpdatedFactorization(F, update.scaled(c))


@dataclass
class State:
    """Kinematic state at time t: displacement, velocity, acceleration, and the load;
    ``aux`` the auxiliary acceleration of the nonsmooth generalised-α scheme."""

    t: float
    u: FloatArray
    v: FloatArray
    a: FloatArray
    f: FloatArray
    aux: FloatArray | None = None


@dataclass
class History:
    """Recorded time histories: times (s) and u, v, a at the recorded DOFs (n_t, k),
    and, if tracked, the energy terms (J) kinetic, strain, external work and damping
    dissipation."""

    t: FloatArray
    u: FloatArray
    v: FloatArray
    a: FloatArray
    dofs: IntArray
    energy: dict[str, FloatArray] = field(default_factory=dict)
    final: State | None = None


def scheme_parameters(
    alpha: float = 0.0,
    rho_inf: float | None = None,
    beta: float | None = None,
    gamma: float | None = None,
) -> tuple[float, float, float, float]:
    """(β, γ, α_m, α_f) of the family (see the module docstring): HHT-α from ``alpha``
    (α_m = 0, α_f = −α), or generalised-α from ``rho_inf``; β and γ follow unless given.

    >>> [round(x, 12) for x in scheme_parameters(rho_inf=0.5)]
    [0.444444444444, 0.833333333333, 0.0, 0.333333333333]
    """
    if rho_inf is None:
        am, af = 0.0, -alpha
        gamma = (0.5 - alpha) if gamma is None else gamma
        beta = 0.25 * (1.0 - alpha) ** 2 if beta is None else beta
    else:
        am, af = (2 * rho_inf - 1) / (rho_inf + 1), rho_inf / (rho_inf + 1)
        gamma = 0.5 - am + af if gamma is None else gamma
        beta = 0.25 * (1.0 - am + af) ** 2 if beta is None else beta
    return float(beta), float(gamma), float(am), float(af)


class Newmark:
    """Newmark-β / HHT-α / generalised-α integrator with a once-factorised effective
    matrix (see the module docstring).

    Parameters
    ----------
    system: the free-DOF operators (e.g. ``Model.system()``).
    dt: time step (s).
    beta, gamma: Newmark parameters (default average acceleration 1/4, 1/2).
    alpha: HHT-α parameter in [−1/3, 0]; when not 0, ``beta`` and ``gamma`` default to
        (1 − α)²/4 and (1 − 2α)/2.
    rho_inf: generalised-α spectral radius at infinity in [0, 1] (instead of ``alpha``);
        sets α_m, α_f and the default β, γ.
    backend: sparse solver backend (see :func:`pfeie.linalg.factorize`).
    """

    def __init__(
        self,
        system: SecondOrderSystem,
        dt: float,
        *,
        beta: float | None = None,
        gamma: float | None = None,
        alpha: float = 0.0,
        rho_inf: float | None = None,
        backend: str = "auto",
    ) -> None:
        pairs = getattr(system, "n_pairs", 0)
        if pairs:
            raise ModelError(f"Newmark: the model has {pairs} interface pairs, which its "
                             "block operators do not couple (each block would move alone); "
                             "use pfeie.Dynamic, whose schemes solve the interfaces")  # fmt: skip
        if not dt > 0:
            raise ModelError(f"time step dt must be > 0 s, got {dt}")
        if not -1.0 / 3.0 - 1e-12 <= alpha <= 0.0:
            raise ModelError(f"HHT alpha must lie in [-1/3, 0], got {alpha}")
        if rho_inf is not None and alpha:
            raise ModelError("give either the HHT alpha or rho_inf, not both")
        if rho_inf is not None and not 0.0 <= rho_inf <= 1.0:
            raise ModelError(f"rho_inf must lie in [0, 1], got {rho_inf}")
        beta, gamma, am, af = scheme_parameters(alpha, rho_inf, beta, gamma)
        self.alpha_m, self.alpha_f = float(am), float(af)
        if not (beta > 0 and gamma >= 0.5 and 2 * beta >= gamma - 1e-15):
            log.warning("Newmark beta=%g, gamma=%g is not unconditionally stable", beta, gamma)
        self.system, self.dt = system, float(dt)
        self.beta, self.gamma, self.alpha = float(beta), float(gamma), float(alpha)
        b, g = self.beta, self.gamma
        self.c = (
            1 / (b * dt**2), g / (b * dt), 1 / (b * dt), 1 / (2 * b) - 1, g / b - 1,
            dt * (g / (2 * b) - 1),
        )  # fmt: skip
        a0, a1 = self.c[0], self.c[1]
        s = 1.0 - af
        Khat = (a0 if am == 0.0 else (1.0 - am) * a0) * system.M + s * system.K
        if system.C is not None:
            Khat = Khat + s * a1 * system.C
        self.Khat = sp.csc_matrix(Khat)
        self.factor = factorize_step(system, self.Khat, s * a1, backend)

    @property
    def n(self) -> int:
        return int(self.system.K.shape[0])

    def initial_state(
        self, u0: FloatArray | None = None, v0: FloatArray | None = None, t0: float = 0.0
    ) -> State:
        """State at t0 with the acceleration from equilibrium, a₀ = M⁻¹(f − C v₀ − K u₀)."""
        n = self.n
        u = np.zeros(n) if u0 is None else np.array(u0, dtype=float)
        v = np.zeros(n) if v0 is None else np.array(v0, dtype=float)
        f = self.system.load(t0)
        r = f - self.system.K @ u - damping_product(self.system, v)
        # at rest in equilibrium (the usual start from a static state) no solve is needed
        a = factorize(sp.csc_matrix(self.system.M), spd=True).solve(r) if np.any(r) else 0 * r
        return State(t0, u, v, a, f)

    def effective_load(self, state: State, f_next: FloatArray) -> FloatArray:
        """P̂ of the step from ``state`` when the load at t_{n+1} is ``f_next``."""
        a0, a1, a2, a3, a4, a5 = self.c
        am, af = self.alpha_m, self.alpha_f
        u, v, a = state.u, state.v, state.a
        rhs = (1 - af) * f_next + af * state.f if af else f_next.copy()
        if am:
            rhs += self.system.M @ ((1 - am) * (a0 * u + a2 * v + a3 * a) - am * a)
        else:
            rhs += self.system.M @ (a0 * u + a2 * v + a3 * a)
        if self.system.C is not None:
            rhs += damping_product(self.system, (1 - af) * (a1 * u + a4 * v + a5 * a) - af * v)
        if af:
            rhs -= af * (self.system.K @ u)
        return rhs

    def predict(self, state: State, f_next: FloatArray) -> FloatArray:
        """Displacement u_{n+1} without any extra force: one back-substitution."""
        return self.factor.solve(self.effective_load(state, f_next))

    def advance(self, state: State, u_next: FloatArray, f_next: FloatArray) -> State:
        """The state at t_{n+1} from the accepted displacement u_{n+1}."""
        a0, a1, a2, a3, a4, a5 = self.c
        du = u_next - state.u
        a = a0 * du - a2 * state.v - a3 * state.a
        v = a1 * du - a4 * state.v - a5 * state.a
        return State(state.t + self.dt, u_next, v, a, f_next)

    def step(self, state: State) -> State:
        """One time step."""
        f_next = self.system.load(state.t + self.dt)
        return self.advance(state, self.predict(state, f_next), f_next)

    def energies(self, state: State) -> tuple[float, float]:
        """Kinetic ½ vᵀMv and strain ½ uᵀKu energies (J)."""
        return (0.5 * float(state.v @ (self.system.M @ state.v)),
                0.5 * float(state.u @ (self.system.K @ state.u)))  # fmt: skip

    def run(
        self,
        n_steps: int,
        state: State | None = None,
        *,
        record: Sequence[int] | IntArray | None = None,
        track_energy: bool = False,
        callback: Callable[[State], None] | None = None,
    ) -> History:
        """Integrate ``n_steps`` steps, recording u, v, a at the free DOFs ``record``.

        With ``track_energy`` the kinetic and strain energies, the work of the loads
        (Σ Δu·f̄) and the damping dissipation (Σ Δu·C v̄) are recorded every step.
        """
        if not (isinstance(n_steps, (int, np.integer)) and n_steps >= 0):
            raise ModelError(f"n_steps: expected a whole number of steps >= 0, got "
                             f"{n_steps!r}")  # fmt: skip
        st = self.initial_state() if state is None else state
        dofs = np.asarray([] if record is None else record, dtype=np.int64)
        k = dofs.size
        t = np.empty(n_steps + 1)
        U, V, A = (np.empty((n_steps + 1, k)) for _ in range(3))
        names = ("kinetic", "strain", "external_work", "damping")
        E = {n: np.zeros(n_steps + 1) for n in names} if track_energy else {}

        def put(i: int, s: State) -> None:
            t[i] = s.t
            U[i], V[i], A[i] = s.u[dofs], s.v[dofs], s.a[dofs]

        put(0, st)
        if track_energy:
            E["kinetic"][0], E["strain"][0] = self.energies(st)
        t0 = st.t
        for i in range(1, n_steps + 1):
            new = self.step(st)
            new.t = t0 + i * self.dt  # on the grid, not a running sum of Δt
            if track_energy:
                du = new.u - st.u
                E["kinetic"][i], E["strain"][i] = self.energies(new)
                E["external_work"][i] = E["external_work"][i - 1] + 0.5 * du @ (st.f + new.f)
                damp = 0.5 * du @ damping_product(self.system, st.v + new.v)
                E["damping"][i] = E["damping"][i - 1] + damp
            st = new
            put(i, st)
            if callback is not None:
                callback(st)
        return History(t, U, V, A, dofs, E, st)
