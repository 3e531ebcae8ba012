"""The generalised-α member of the integrator family (Chung & Hulbert 1993).

References: the one-step map of the method written from its defining equations (the
balance at t_{n+1−α_m} / t_{n+1−α_f} and Newmark's relations, solved here as a 3 × 3
linear system, independently of the integrator's displacement form); its spectral radius
at infinity ρ∞ and its second-order accuracy (Chung & Hulbert 1993, eqs. 25-27).
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

import pfeie as pf
from pfeie.dynamics import MatrixSystem, Newmark
from pfeie.verification._models import block_on_base


def _map_from_definition(omega: float, h: float, rho: float) -> np.ndarray:
    """The 3 × 3 map (u, v, a)_n → (u, v, a)_{n+1} of generalised-α for ü + ω²u = 0."""
    am, af = (2 * rho - 1) / (rho + 1), rho / (rho + 1)
    g, b = 0.5 - am + af, 0.25 * (1 - am + af) ** 2
    w2 = omega**2
    # unknowns (u1, v1, a1); rows: balance, Newmark u, Newmark v
    L = np.array([[(1 - af) * w2, 0.0, 1 - am], [1.0, 0.0, -b * h * h], [0.0, 1.0, -g * h]])
    R = np.array([[-af * w2, 0.0, -am], [1.0, h, (0.5 - b) * h * h], [0.0, 1.0, (1 - g) * h]])
    return np.linalg.solve(L, R)


def _map_of_integrator(omega: float, h: float, rho: float) -> np.ndarray:
    nm = Newmark(MatrixSystem(M=sp.csr_matrix([[1.0]]), K=sp.csr_matrix([[omega**2]])), h,
                 rho_inf=rho)  # fmt: skip
    A = np.zeros((3, 3))
    for j in range(3):
        x = np.eye(3)[j]
        st = pf.State(0.0, x[:1].copy(), x[1:2].copy(), x[2:].copy(), np.zeros(1))
        new = nm.step(st)
        A[:, j] = [new.u[0], new.v[0], new.a[0]]
    return A


@pytest.mark.parametrize("rho", [0.0, 0.5, 0.8, 1.0])
def test_one_step_map_and_spectral_radius(rho: float) -> None:
    """The integrator's one-step map equals the map from the defining equations to 1e-12
    (measured 4e-16) at Ω = ωh from 0.1 to 1e4, and its spectral radius tends to ρ∞ as
    Ω → ∞: at Ω = 1e6 within 3e-4 (measured 1.0e-4 and less; the radius approaches ρ∞
    like Ω^(−2/3), the eigenvalue at infinity being defective, 1e-2 at Ω = 1e3)."""
    h = 0.01
    for Om in (0.1, 1.0, 10.0, 1e4):
        A = _map_of_integrator(Om / h, h, rho)
        B = _map_from_definition(Om / h, h, rho)
        assert np.abs(A - B).max() <= 1e-12 * np.abs(B).max()
    radius = float(np.abs(np.linalg.eigvals(_map_of_integrator(1e6 / h, h, rho))).max())
    assert radius == pytest.approx(rho, abs=3e-4)


@pytest.mark.parametrize("rho", [0.0, 0.5, 0.9])
def test_second_order_accuracy(rho: float) -> None:
    """Free vibration u = cos ωt over one period at ωh = 2π/40, 2π/80, 2π/160: the
    observed order is 2 (asserted ≥ 1.95; Chung & Hulbert's accuracy condition
    γ = 1/2 − α_m + α_f)."""
    omega = 2 * np.pi
    errs = []
    for n in (40, 80, 160):
        h = 1.0 / n
        nm = Newmark(MatrixSystem(M=sp.csr_matrix([[1.0]]), K=sp.csr_matrix([[omega**2]])), h,
                     rho_inf=rho)  # fmt: skip
        hist = nm.run(n, nm.initial_state(u0=np.array([1.0])), record=[0])
        errs.append(float(np.abs(hist.u[:, 0] - np.cos(omega * hist.t)).max()))
    orders = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert orders.min() >= 1.95, orders


def test_generalized_alpha_settings_and_contacts() -> None:
    """ρ∞ sets β and γ through the settings; it excludes HHT's α; the Newmark family
    (generalised-α included) refuses interfaces, the default scheme takes ρ∞ with them: a
    block resting on a joint keeps its static state over 10 steps to 1e-17 m (measured
    1.3e-18 m; the block centroid moves by round-off only); the removed ``stabilize``
    option gets a message of its own."""
    s = pf.DynamicSettings(rho_inf=0.0)
    am, af = s.generalized_alpha()
    assert (am, af) == (-1.0, 0.0)
    assert s.newmark()[:2] == pytest.approx((1.0, 1.5), rel=1e-15)
    with pytest.raises(ValueError, match="either alpha"):
        pf.DynamicSettings(rho_inf=0.5, alpha=-0.1)
    model = block_on_base(joint=pf.Joint(phi=30.0), n=1, E=1e9, rho=1000.0)  # one cell each
    with pytest.raises(pf.ModelError, match="without interfaces"):
        pf.Dynamic(model, 0.01, rho_inf=0.0, scheme="newmark")
    with pytest.raises(pf.ModelError, match="stabilize was removed"):
        pf.Dynamic(model, 0.01, stabilize=False)
    res = pf.Dynamic(model, 0.01, rho_inf=0.0).run(0.1, start=pf.solve_static(model))
    assert res.completed and np.abs(res.rigid[:, 1, :2] - res.rigid[0, 1, :2]).max() < 1e-17
