"""The smooth part of the nonsmooth generalised-α scheme (method.md §3.1).

The scheme of Chen, Acary, Virlez & Brüls (2013) and Brüls, Acary & Cardona (2014),
fitted to linear blocks with one factorised matrix. The equation of motion holds at
t_{n+1} with the smooth forces only (loads, elastic, damping, and the smooth pair forces
λ):

    M q̈_{n+1} + C ṽ_{n+1} + K q̃_{n+1} = f_{n+1} + Gᵀ λ_{n+1},

and an auxiliary acceleration a carries the generalised-α recurrence (Arnold & Brüls
2007):

    (1 − α_m) a_{n+1} + α_m a_n = (1 − α_f) q̈_{n+1} + α_f q̈_n,
    q̃_{n+1} = q_n + h v_n + h² (½ − β) a_n + h² β a_{n+1},
    ṽ_{n+1} = v_n + h (1 − γ) a_n + h γ a_{n+1},

with α_m, α_f, β, γ of Chung & Hulbert from the spectral radius at infinity ρ∞
(:func:`scheme_parameters`). Eliminating a_{n+1}, q̃ and ṽ:

    Ŝ q̈_{n+1} = s (f_{n+1} − C v̂ − K q̂ + Gᵀ λ),   Ŝ = s M + γ h C + β h² K,
    s = (1 − α_m)/(1 − α_f),

(q̂, v̂ the parts of q̃, ṽ known at t_n), so a step is one back-substitution
(:meth:`NonsmoothAlpha.free_acceleration`) and the pair forces enter through
W = G Ŝ⁻¹ Gᵀ with the weight s. Ŝ is factorised once; it is positive definite for floating
blocks (the M term) and for massless ones held by supports (the K term). The pair work
of the scheme (the acceleration-level problem, the velocity correction on the step
impulse, the position correction) is the driver's (:mod:`._driver`); this class knows
nothing of pairs.

Energy (docs/theory.md, "Energy identity of the smooth step"): with e = a − q̈ and
δ = γ − ½ = (1 − ρ∞)/(1 + ρ∞), a step whose equation of motion holds at both ends
satisfies E*_{n+1} − E*_n = the loads' and pair forces' work (step averages) − the
damping's − D exactly, with the modified energy E* = T + U + Φ,
Φ = (δh/2) vᵀMe + (δ²h²/8)(3aᵀMa + 2aᵀMe + 2eᵀMe) (:meth:`NonsmoothAlpha.modified_energy`)
and D = δh² ēᵀMē ≥ 0 (:meth:`NonsmoothAlpha.dissipation`).

For ρ∞ = 0 (the default with interfaces): α_m = −1, α_f = 0, γ = 3/2, β = 1, Ŝ = 2M +
3/2 h C + h² K. Second order; the algorithmic damping ratio of a mode is ≈ 0.22 % at
ωh = 0.17, 1.4 % at ωh = 0.34 and 12 % at ωh = 1 (method.md §3.1).

Example: free vibration of an oscillator (ω = 2π) over one period at ωh = 0.063:

>>> import numpy as np, scipy.sparse as sp
>>> from pfeie.dynamics import MatrixSystem
>>> w = 2 * np.pi
>>> sys1 = MatrixSystem(M=sp.csr_matrix([[1.0]]), K=sp.csr_matrix([[w * w]]))
>>> ga = NonsmoothAlpha(sys1, dt=0.01, rho_inf=0.0)
>>> st = ga.initial_state(np.array([1.0]), np.zeros(1), np.array([-w * w]))
>>> for _ in range(100):
...     st = ga.advance(st, ga.free_acceleration(st, np.zeros(1)), np.zeros(1))
>>> round(float(st.u[0]), 3)                   # amplitude kept to 0.1 %
0.999
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..errors import ModelError
from ..typing import FloatArray
from ._newmark import (
    SecondOrderSystem,
    State,
    damping_product,
    factorize_step,
    scheme_parameters,
)


class NonsmoothAlpha:
    """The smooth generalised-α step in Arnold & Brüls' form (see the module docstring).

    Parameters
    ----------
    system: the free-DOF operators M, K, C.
    dt: time step h (s).
    rho_inf: spectral radius at infinity in [0, 1] (0: the most dissipative of high
        modes, the default with interfaces).
    backend: sparse factorisation backend (:func:`pfeie.linalg.factorize`).
    """

    def __init__(
        self, system: SecondOrderSystem, dt: float, *, rho_inf: float,
        backend: str = "auto",
    ) -> None:  # fmt: skip
        if not dt > 0:
            raise ModelError(f"time step dt must be > 0 s, got {dt}")
        if not 0.0 <= rho_inf <= 1.0:
            raise ModelError(f"rho_inf must lie in [0, 1], got {rho_inf}")
        self.system, self.dt, self.rho_inf = system, float(dt), float(rho_inf)
        self.beta, self.gamma, self.alpha_m, self.alpha_f = scheme_parameters(rho_inf=rho_inf)
        h, b, g = self.dt, self.beta, self.gamma
        self.s = (1.0 - self.alpha_m) / (1.0 - self.alpha_f)
        S = self.s * system.M + b * h * h * system.K
        if system.C is not None:
            S = S + g * h * system.C
        self.S = sp.csc_matrix(S)
        self.factor = factorize_step(system, self.S, g * h, backend)
        self._known: tuple[State, tuple[FloatArray, FloatArray, FloatArray]] | None = None

    def initial_state(
        self, u: FloatArray, v: FloatArray, acc: FloatArray, f: FloatArray | None = None,
        t: float = 0.0,
    ) -> State:  # fmt: skip
        """The state at t with a consistent acceleration ``acc`` (the auxiliary one
        starts equal to it)."""
        f = np.zeros_like(u) if f is None else f
        return State(t, u, v, acc, f, acc.copy())

    @property
    def weights(self) -> tuple[float, float]:
        """(β h²/s, γ h/s): q̃ = q̂ + β h²/s q̈_{n+1} and ṽ = v̂ + γ h/s q̈_{n+1}."""
        return self.beta * self.dt**2 / self.s, self.gamma * self.dt / self.s

    def known(self, state: State) -> tuple[FloatArray, FloatArray, FloatArray]:
        """(a*, q̂, v̂), the parts known at t_n: a_{n+1} = q̈_{n+1}/s + a*, and q̃, ṽ as in
        :attr:`weights`."""
        hit = self._known
        if hit is not None and hit[0] is state:  # a step asks three times for its start
            return hit[1]
        h, b, g = self.dt, self.beta, self.gamma
        am, af = self.alpha_m, self.alpha_f
        aux = state.a if state.aux is None else state.aux
        a_star = (af * state.a - am * aux) / (1.0 - am)
        q_hat = state.u + h * state.v + h * h * ((0.5 - b) * aux + b * a_star)
        v_hat = state.v + h * ((1.0 - g) * aux + g * a_star)
        self._known = (state, (a_star, q_hat, v_hat))
        return a_star, q_hat, v_hat

    def free_acceleration(self, state: State, f_next: FloatArray) -> FloatArray:
        """q̈_{n+1} without pair forces: Ŝ⁻¹ s (f − C v̂ − K q̂), one back-substitution."""
        _, q_hat, v_hat = self.known(state)
        sys_ = self.system
        both = getattr(sys_, "elastic_and_damping", None)  # a model's system: one sweep of K
        if both is not None:
            r = f_next - both(q_hat, v_hat)
        else:
            r = f_next - sys_.K @ q_hat
            if sys_.C is not None:
                r = r - damping_product(sys_, v_hat)
        return self.factor.solve(self.s * r)

    def advance(self, state: State, acc: FloatArray, f_next: FloatArray) -> State:
        """The smooth state at t_{n+1} (q̃, ṽ, q̈, a) from the accepted acceleration."""
        h, b, g = self.dt, self.beta, self.gamma
        a_star, q_hat, v_hat = self.known(state)
        a_s = acc / self.s
        return State(state.t + h, q_hat + b * h * h * a_s, v_hat + g * h * a_s, acc, f_next,
                     a_s + a_star)  # fmt: skip

    def _lag(self, state: State) -> tuple[FloatArray, FloatArray, FloatArray]:
        """(a, e, M e) of a state: its auxiliary acceleration, the lag e = a − q̈ and M e."""
        a = state.a if state.aux is None else state.aux
        e = a - state.a
        return a, e, np.asarray(self.system.M @ e)

    def modified_energy(self, state: State) -> float:
        """Φ, the terms of the scheme's modified energy E* = T + U + Φ beyond the kinetic
        and the strain energy (J; docs/theory.md, "Energy identity of the smooth
        step"):

            Φ = (δh/2) vᵀM e + (δ²h²/8)(3 aᵀM a + 2 aᵀM e + 2 eᵀM e),

        e = a − q̈ the lag of the auxiliary acceleration behind the true one, and
        δ = γ − ½ = 1 − 2α_f = (1 − ρ∞)/(1 + ρ∞). Φ = 0 for ρ∞ = 1 and whenever a = q̈ = 0;
        the acceleration part is ≥ 0 (3 a² + 2 a e + 2 e² = (a + e)² + 2 a² + e²), the
        velocity part has no sign, O(h²) in smooth motion (e = O(h))."""
        d, h = self.gamma - 0.5, self.dt
        a, e, Me = self._lag(state)
        Ma = np.asarray(self.system.M @ a)
        return (0.5 * d * h * float(state.v @ Me)
                + 0.125 * d * d * h * h * (3.0 * float(a @ Ma) + 2.0 * float(a @ Me)
                                           + 2.0 * float(e @ Me)))  # fmt: skip

    def dissipation(self, cur: State, nxt: State) -> float:
        """D = δ h² ēᵀ M ē ≥ 0, the algorithmic dissipation of the smooth step cur → nxt
        (J; ē = (e_n + e_{n+1})/2, e = a − q̈, δ = γ − ½; docs/theory.md, "Energy
        identity of the smooth step"). For a smooth step, E*_{n+1} − E*_n = external and
        pair work (step averages) − damping work − D exactly."""
        eb = 0.5 * (self._lag(cur)[1] + self._lag(nxt)[1])
        return (self.gamma - 0.5) * self.dt**2 * float(eb @ (self.system.M @ eb))


__all__ = ["NonsmoothAlpha"]
