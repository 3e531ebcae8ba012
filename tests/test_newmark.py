"""Newmark / HHT-α verification on oscillators and a small finite element model.

References: the exact solution u = cos ωt of the undamped oscillator; the amplification
matrix of the Newmark recurrence (Hughes, The Finite Element Method, 2000, §9.1), derived
here independently of the integrator; HHT-α's spectral radius at ωΔt → ∞,
ρ∞ = (1 + α)/(1 − α) (Hilber, Hughes & Taylor 1977).
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

import pfeie as pf
from pfeie.dynamics import MatrixSystem, Newmark

OMEGA = 2 * np.pi


def oscillator(omega: float = OMEGA, c: float = 0.0) -> MatrixSystem:
    return MatrixSystem(M=sp.csr_matrix([[1.0]]), K=sp.csr_matrix([[omega**2]]),
                        C=sp.csr_matrix([[c]]) if c else None)  # fmt: skip


def amplification(omega: float, dt: float, beta: float, gamma: float, alpha: float) -> np.ndarray:
    """A with (u, v, a)_{n+1} = A (u, v, a)_n for u'' + ω²u = 0 (HHT-α form)."""
    w2 = omega**2
    lhs = np.array([[1.0, 0.0, -beta * dt**2], [0.0, 1.0, -gamma * dt], [(1 + alpha) * w2, 0, 1]])
    rhs = np.array([[1.0, dt, (0.5 - beta) * dt**2], [0.0, 1.0, (1 - gamma) * dt],
                    [alpha * w2, 0.0, 0.0]])  # fmt: skip
    return np.linalg.solve(lhs, rhs)


@pytest.mark.parametrize("alpha", [0.0, -0.1])
def test_second_order_in_time(alpha: float) -> None:
    """Undamped oscillator against u = cos ωt: the observed orders log2(e(2Δt)/e(Δt)) for
    n = 40 to 320 steps per period are 2 ± 5e-3 (measured 1.9989 to 2.0004), on the two
    finest steps 2 ± 2e-3 (measured 1.99993 and 2.0004)."""
    errs = []
    steps = np.array([40, 80, 160, 320])
    for n in steps:
        nm = Newmark(oscillator(), dt=1.0 / n, alpha=alpha)
        # end at t = 1.3 s, away from the instants where the phase error cancels
        h = nm.run(int(13 * n // 10), nm.initial_state(u0=np.array([1.0])), record=[0])
        errs.append(abs(h.u[-1, 0] - np.cos(OMEGA * h.t[-1])))
    rates = np.log(np.array(errs[:-1]) / errs[1:]) / np.log(2.0)
    np.testing.assert_allclose(rates, 2.0, rtol=0, atol=5e-3)
    assert rates[-1] == pytest.approx(2.0, abs=2e-3), rates


@pytest.mark.parametrize(("beta", "gamma", "alpha"),
                         [(0.25, 0.5, 0.0), (0.3025, 0.6, 0.0), (None, None, -0.3)])  # fmt: skip
def test_integrator_follows_its_amplification_matrix(beta, gamma, alpha) -> None:  # type: ignore[no-untyped-def]
    """200 steps equal the amplification-matrix recurrence (Hughes §9.1, built here) to
    round-off: u within 1e-12 (measured 2.0e-13), v within 1e-11 (measured 1.2e-12)."""
    dt, n = 0.05, 200
    nm = Newmark(oscillator(), dt=dt, beta=beta, gamma=gamma, alpha=alpha)
    h = nm.run(n, nm.initial_state(u0=np.array([1.0]), v0=np.array([0.3])), record=[0])
    A = amplification(OMEGA, dt, nm.beta, nm.gamma, nm.alpha)
    z = np.array([1.0, 0.3, -(OMEGA**2)])
    ref = [z]
    for _ in range(n):
        ref.append(A @ ref[-1])
    ref_arr = np.array(ref)
    np.testing.assert_allclose(h.u[:, 0], ref_arr[:, 0], rtol=0, atol=1e-12)
    np.testing.assert_allclose(h.v[:, 0], ref_arr[:, 1], rtol=0, atol=1e-11)


def test_energy_conserved_by_average_acceleration() -> None:
    """β = 1/4, γ = 1/2, no damping: T + U constant (the average-acceleration rule
    conserves it exactly) to 5e-14 over 10⁴ steps of an FE model (measured 6.1e-15)."""
    mesh = pf.rectangle(4.0, 0.5, 16, 2, cell="quad")
    model = pf.Model(mesh, [pf.Block("all", pf.Elastic(1e7, 0.3, 1000.0))], plane="stress")
    model.fix("xmin")
    system = model.system()
    nm = Newmark(system, dt=2e-3)
    rng = np.random.default_rng(1)
    st = nm.initial_state(u0=1e-3 * rng.standard_normal(system.n),
                          v0=1e-2 * rng.standard_normal(system.n))  # fmt: skip
    h = nm.run(10_000, st, track_energy=True)
    total = h.energy["kinetic"] + h.energy["strain"]
    assert np.abs(total / total[0] - 1).max() < 5e-14


@pytest.mark.parametrize("gamma", [0.6, 0.7])
def test_numerical_damping_for_gamma_above_half(gamma: float) -> None:
    """γ > 1/2 with β = (γ + 1/2)²/4: energy decays at the amplification matrix's rate
    (Hughes §9.1, built here): to 5e-13 after 100 steps (measured 5.9e-14); γ = 1/2
    conserves it to 1e-13 (measured 2.0e-14)."""
    beta = (gamma + 0.5) ** 2 / 4
    dt = 0.1  # ωΔt ≈ 0.63
    nm = Newmark(oscillator(), dt=dt, beta=beta, gamma=gamma)
    h = nm.run(100, nm.initial_state(u0=np.array([1.0])), record=[0], track_energy=True)
    e = h.energy["kinetic"] + h.energy["strain"]
    rho = max(abs(np.linalg.eigvals(amplification(OMEGA, dt, beta, gamma, 0.0))))
    assert rho < 1.0
    period = round(1.0 / dt)  # T = 1 s
    assert np.all(e[period:] < e[:-period])  # decays over every period
    # the energy follows the amplification matrix's recurrence and has lost most of itself
    z = np.linalg.matrix_power(amplification(OMEGA, dt, beta, gamma, 0.0), 100) @ [
        1,
        0,
        -(OMEGA**2),
    ]
    assert e[-1] == pytest.approx(0.5 * z[1] ** 2 + 0.5 * OMEGA**2 * z[0] ** 2, rel=5e-13)
    assert e[-1] < 0.5 * e[0]
    nm0 = Newmark(oscillator(), dt=dt)
    h0 = nm0.run(100, nm0.initial_state(u0=np.array([1.0])), track_energy=True)
    e0 = h0.energy["kinetic"] + h0.energy["strain"]
    assert e0[-1] == pytest.approx(e0[0], rel=1e-13)


def test_hht_spectral_radius_at_infinity() -> None:
    """ρ at ωΔt = 1e4 is (1 + α)/(1 − α) (Hilber et al. 1977, ωΔt → ∞) to 2e-5 (measured
    2.8e-6, the distance of ωΔt = 1e4 from infinity)."""
    alpha = -0.3
    nm = Newmark(oscillator(omega=1e4), dt=1.0, alpha=alpha)
    A = amplification(1e4, 1.0, nm.beta, nm.gamma, alpha)
    rho = max(abs(np.linalg.eigvals(A)))
    assert rho == pytest.approx((1 + alpha) / (1 - alpha), rel=2e-5)


def test_rayleigh_damping_ratio_from_free_decay() -> None:
    """Free decay of a damped oscillator: logarithmic decrement 2πζ/√(1 − ζ²) to 2e-5
    (measured 4.3e-6 at ωΔt = 0.006); the energy balance with the damping work closes to
    2e-11 (measured 2.5e-12)."""
    zeta = 0.05
    f1 = 1.0
    ray = pf.Rayleigh.from_ratio(zeta, f1, 3.0)
    c = ray.alpha + ray.beta * OMEGA**2  # C = αM + βK on m = 1, k = ω²
    nm = Newmark(oscillator(c=c), dt=1e-3)
    h = nm.run(5000, nm.initial_state(u0=np.array([1.0])), record=[0], track_energy=True)
    u = h.u[:, 0]
    peaks = np.flatnonzero((u[1:-1] > u[:-2]) & (u[1:-1] > u[2:])) + 1
    dec = np.log(u[peaks[0]] / u[peaks[1]])
    assert dec == pytest.approx(2 * np.pi * zeta / np.sqrt(1 - zeta**2), rel=2e-5)
    balance = h.energy["kinetic"] + h.energy["strain"] + h.energy["damping"]
    assert balance[-1] == pytest.approx(balance[0], rel=2e-11)


def test_forced_response_energy_balance() -> None:
    """A damped FE model under a time-varying load: T + U + D = W to round-off (γ = 1/2):
    1e-10 of the largest work (measured 1.8e-11)."""
    mesh = pf.rectangle(4.0, 0.5, 16, 2, cell="quad8")
    model = pf.Model(mesh, [pf.Block("all", pf.Elastic(1e7, 0.3, 1000.0))],
                     damping=pf.Rayleigh.from_ratio(0.05, 1.0, 10.0))  # fmt: skip
    model.fix("xmin")
    model.add_traction("xmax", [0.0, -1e3], amplitude=lambda t: np.sin(2 * np.pi * 3 * t))
    model.add_gravity()
    nm = Newmark(model.system(), dt=2e-3)
    h = nm.run(500, track_energy=True)
    e = h.energy
    lhs = e["kinetic"] + e["strain"] + e["damping"] - e["external_work"]
    scale = np.abs(e["external_work"]).max()
    assert np.abs(lhs - lhs[0]).max() < 1e-10 * scale
