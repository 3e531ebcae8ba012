"""Joint laws behind the protocol: Mohr-Coulomb, linear slip weakening, and a law written
in a test (the solver and the time stepping are not touched by a new law).

References: the rigid block on a horizontal joint under a constant base acceleration A,
whose relative slip δ obeys δ'' = A − μ(δ) g while it slides (elementary mechanics):

- slip weakening μ(δ) = μ_s − (μ_s − μ_d) δ/D_c for δ < D_c (Ida 1972): with
  a₀ = A − μ_s g and k = (μ_s − μ_d) g/D_c, δ = (a₀/k)(cosh √k t − 1) until δ = D_c at
  t₁ = arccosh(1 + k D_c/a₀)/√k, then δ'' = A − μ_d g from the velocity
  v₁ = (a₀/√k) sinh √k t₁;
- a constant shear strength c (Tresca): δ'' = A − c A_j/m.
"""

from __future__ import annotations

import numpy as np
import pytest

import pfeie as pf
from pfeie.interface import JointLaw, PairLaws, Strength
from pfeie.typing import BoolArray, FloatArray
from pfeie.verification._models import block_on_base, slip_x

G = 9.81


def _slip_weakening_reference(A: float, mus: float, mud: float, dc: float):  # type: ignore[no-untyped-def]
    a0, k = A - mus * G, (mus - mud) * G / dc
    sk = np.sqrt(k)
    t1 = np.arccosh(1.0 + k * dc / a0) / sk
    v1 = a0 / sk * np.sinh(sk * t1)

    def delta(t: FloatArray) -> FloatArray:
        early = a0 / k * (np.cosh(sk * np.minimum(t, t1)) - 1.0)
        late = dc + v1 * (t - t1) + 0.5 * (A - mud * G) * (t - t1) ** 2
        return np.where(t < t1, early, late)

    return delta, t1


def test_slip_weakening_friction_and_strength() -> None:
    """μ(δ) falls linearly from tan φ to tan φ_r over D_c and stays there; an intact pair
    has the peak strength c A + tan φ σ A; the laws of two interfaces are gathered per
    pair."""
    law = pf.SlipWeakening(c=1e5, phi=40.0, phi_r=30.0, dc=0.02, initial="intact")
    path = np.array([0.0, 0.01, 0.02, 0.5])
    mu_p, mu_r = np.tan(np.radians(40.0)), np.tan(np.radians(30.0))
    expected = [mu_p, 0.5 * (mu_p + mu_r), mu_r, mu_r]
    np.testing.assert_allclose(law.residual_friction(path), expected, rtol=1e-15)
    st = law.strength(np.full(4, 2.0), np.array([False, False, True, True]), path)
    np.testing.assert_allclose(st.friction, [mu_p, mu_p, mu_r, mu_r], rtol=1e-15)
    np.testing.assert_allclose(st.cohesion, [2e5, 2e5, 0.0, 0.0], rtol=1e-15)
    laws = PairLaws.from_interfaces(np.ones(3), np.array([0, 1, 1]),
                                    [pf.MohrCoulomb(phi=20.0), law], 2)  # fmt: skip
    _, mu, _ = laws.strength(np.ones(3, dtype=bool), np.array([0.0, 0.0, 0.02]))
    np.testing.assert_allclose(mu, [np.tan(np.radians(20.0)), mu_p, mu_r], rtol=1e-15)
    with pytest.raises(pf.ModelError, match="dc must be > 0"):
        pf.SlipWeakening(phi=40.0, phi_r=30.0, dc=0.0)
    with pytest.raises(pf.ModelError, match="residual friction angle"):
        pf.SlipWeakening(phi=40.0, dc=0.01)
    # a residual angle above the peak hardens with slip (a new user's law took it)
    with pytest.raises(pf.ModelError, match="phi_r = 45° exceeds phi = 40°"):
        pf.SlipWeakening(phi=40.0, phi_r=45.0, dc=0.01)


@pytest.mark.slow
def test_slip_weakening_block_against_the_closed_form() -> None:
    """A 1 m block (μ_s = 0.6 → μ_d = 0.4 over D_c = 5 cm) under A = 0.65 g for 0.8 s:
    the slip follows the closed form of the module docstring (δ(0.8 s) = 0.447515 m,
    weakening ends at t₁ = 0.36596 s). The strength of a step is taken at the slip path
    predicted for its end from the slip rate at its start: measured 0.17 %, 0.17 %, 0.12 %,
    0.059 % of δ(0.8 s) at Δt = 2, 1, 0.5, 0.25 ms (the end of the weakening is a kink
    inside a step: not monotone; asserted ≤ 0.25 % and a threefold fall over the three
    halvings, measured 2.96). A very stiff block (E = 300 GPa) keeps the block's own
    elastic response below these errors."""
    mus, mud, dc, A, T = 0.6, 0.4, 0.05, 0.65 * G, 0.8
    delta, t1 = _slip_weakening_reference(A, mus, mud, dc)
    assert (t1, float(delta(np.array(T)))) == pytest.approx((0.365959, 0.447515), abs=1e-6)
    law = pf.SlipWeakening(phi=np.degrees(np.arctan(mus)), phi_r=np.degrees(np.arctan(mud)),
                           dc=dc)  # fmt: skip
    gm = pf.GroundMotion.from_samples([A, A], time=[0.0, 10.0])
    errs = []
    for dt in (2e-3, 1e-3, 5e-4, 2.5e-4):
        model = block_on_base(joint=law, E=300e9)
        res = pf.Dynamic(model, dt).run(T, ground=[gm], start=pf.solve_static(model))
        x = -(slip_x(res) - slip_x(res)[0])
        errs.append(float(np.abs(x - delta(res.t)).max() / delta(np.array(T))))
        assert res.final is not None
        path = res.final.pairs.path  # the slip path of the pairs that stayed in contact
        assert path.max() == pytest.approx(x[-1], rel=1e-6)
    assert max(errs) < 2.5e-3, errs  # measured 1.74e-3
    assert errs[0] / errs[-1] > 2.5, errs  # measured 2.96


class Tresca:
    """A law written here, not in pfeie: a constant shear strength τ_c (Pa) and no
    friction (cohesive soil, ice), behind the :class:`pfeie.interface.JointLaw` protocol."""

    initial, kn, ks, gap = "broken", None, None, 0.0

    def __init__(self, tau: float) -> None:
        self.tau = tau

    def strength(self, area: FloatArray, broken: BoolArray, path: FloatArray) -> Strength:
        z = np.zeros(area.shape)
        return Strength(self.tau * area, z, z)


def test_a_new_law_needs_no_change_of_the_solver() -> None:
    """A Tresca joint (τ_c = 0.1 ρ g h, so that the block slides like a Coulomb block with
    μ = 0.1) under a 0.5 g pulse of 0.2 s: the permanent slip is Newmark's closed form
    V²/(2 g μ)(1 − μ/A) = 0.392400 m (V = A g t₀), to the same accuracy as the
    Mohr-Coulomb block: measured, the two agree to 1.2e-4 (the pairs' normal forces shift
    with the overturning moment, which the Coulomb pairs feel and a constant strength does
    not) and the closed form holds to 1.2e-3 (the end of the pulse and the stop of the
    slide fall inside steps: first order in Δt)."""
    assert isinstance(Tresca(1.0), JointLaw)
    A, mu, t0, dt = 0.5, 0.1, 0.2, 0.002
    u_ref = (A * G * t0) ** 2 / (2 * G * mu) * (1 - mu / A)
    assert u_ref == pytest.approx(0.392400, abs=1e-6)
    t = np.arange(round(1.5 / dt) + 1) * dt
    a = np.where(t < t0 - 1e-12, A * G, np.where(t < t0 + 1e-12, 0.5 * A * G, 0.0))
    gm = pf.GroundMotion.from_samples(a, time=t)
    slips = []
    for law in (Tresca(mu * 2400.0 * G * 1.0), pf.MohrCoulomb(phi=np.degrees(np.arctan(mu)))):
        model = block_on_base(joint=law)  # type: ignore[arg-type]
        res = pf.Dynamic(model, dt).run(1.5, ground=[gm], start=pf.solve_static(model))
        slips.append(-float(slip_x(res)[-1] - slip_x(res)[0]))
    assert slips[0] == pytest.approx(slips[1], rel=5e-4)
    assert slips[0] == pytest.approx(u_ref, rel=3e-3)


def test_the_natural_maps_jacobian_on_the_cohesion_ramp() -> None:
    """The proximal Newton's natural map (pfeie.interface._proximal.natural_map) and its
    blocks A = ∂F/∂s, B = ∂F/∂X against central differences (h = 1e-7), in 3D, for
    broken pairs on the residual cohesion's ramp (X_n < κ c A), on the cone, without
    cohesion, and an intact pair: to 1e-6 of each entry's size (measured 2.6e-7: the
    differences' own error, the ramp's slope being up to 2/κ = 2000)."""
    from pfeie.interface import COHESION_RAMP
    from pfeie.interface._proximal import PairLaw, natural_map

    rng = np.random.default_rng(0)
    m, d = 6, 3
    c = np.array([100.0, 100.0, 100.0, 100.0, 0.0, 100.0])
    law = PairLaw(c, np.full(m, 0.6), np.zeros(m), np.arange(m) != 5, np.zeros(m, dtype=bool),
                  np.zeros(m, dtype=bool), np.zeros((m, d)), np.zeros((m, d - 1)))  # fmt: skip
    X = np.zeros((m, d))
    X[:, -1] = [0.05, 0.05, 5.0, 0.02, 0.05, 0.05]  # κ c = 0.1: pairs 0, 1, 3 on the ramp
    assert (X[:4, -1] < COHESION_RAMP * c[:4]).sum() == 3
    X[:, :-1] = rng.normal(size=(m, d - 1)) * 200.0
    s = np.zeros((m, d))
    s[:, -1] = [-1e-3, 1e-3, -1e-3, -1e-3, -1e-3, 0.0]  # pair 1 separated: no shear
    s[:, :-1] = rng.normal(size=(m, d - 1)) * 1e-2
    r = np.full(m, 1e3)
    _, A, B = natural_map(X, s, law, r)
    h = 1e-7
    worst = 0.0
    for k in range(m):
        for j in range(d):
            for arr, jac in ((X, B), (s, A)):
                up, dn = arr.copy(), arr.copy()
                up[k, j] += h
                dn[k, j] -= h
                args_up = (up, s) if arr is X else (X, up)
                args_dn = (dn, s) if arr is X else (X, dn)
                fd = (natural_map(*args_up, law, r, jac=False)[0][k]
                      - natural_map(*args_dn, law, r, jac=False)[0][k]) / (2 * h)  # fmt: skip
                err = np.abs(fd - jac[k, :, j]).max() / max(1.0, np.abs(fd).max())
                worst = max(worst, float(err))
    assert worst <= 1e-6


def test_the_cohesion_ramp_with_a_residual_tensile_strength() -> None:
    """The ramp of a broken pair with c = 100 N, μ = 0.6, t = 20 N (c̃ = c − μ t = 88 N at
    the cut-off X_n = −t): 0 where the pair parts (X_n = −t); at the ramp's end, X_n =
    −t + κ c̃, the cone c + μ X_n (friction in tension too) and its slope μ, to round-off;
    the slope against central differences inside (h = 1e-9 of the band); without tensile
    strength the former form μ X_n + c (2u − u²), u = X_n/(κ c), to round-off. A tensile
    strength beyond the residual cone's apex c_r / tan φ_r is refused, naming both; a
    slip-weakening law checks it with its peak friction, where a broken pair starts."""
    from pfeie.errors import ModelError
    from pfeie.interface import COHESION_RAMP as K
    from pfeie.interface import cohesion_ramp

    one = np.ones(1, dtype=bool)

    def ramp(xn: float, t: float = 20.0) -> tuple[bool, float, float]:
        on, tau, slope = cohesion_ramp(np.array([100.0]), np.array([0.6]), np.array([t]),
                                       np.array([xn]), one)  # fmt: skip
        return bool(on[0]), float(tau[0]), float(slope[0])

    ct = 100.0 - 0.6 * 20.0
    assert ramp(-20.0) == (True, 0.0, 0.0)
    end = -20.0 + K * ct
    on, tau, slope = ramp(end * (1 + 1e-15))  # just inside the band
    assert on and tau == pytest.approx(100.0 + 0.6 * end, rel=2e-15)  # measured 1.6e-16
    assert slope == pytest.approx(0.6, abs=1e-9)
    assert not ramp(end + 1e-9)[0]
    for u in (0.1, 0.5, 0.9):
        xn, h = -20.0 + u * K * ct, 1e-9 * K * ct
        fd = (ramp(xn + h)[1] - ramp(xn - h)[1]) / (2 * h)
        assert fd == pytest.approx(ramp(xn)[2], rel=1e-5)  # the differences' own error
        # u recovered from X_n + t: measured 8.7e-14 at u = 0.1
        assert ramp(xn)[1] == pytest.approx(0.6 * (xn + 20.0) + ct * u * (2 - u), rel=5e-13)
        x0 = u * K * 100.0
        assert ramp(x0, 0.0)[1] == 0.6 * x0 + 100.0 * u * (2.0 - u)
    with pytest.raises(ModelError, match=r"tensile_r = 60000 Pa lies beyond the apex of the "
                       r"residual strength, c_r / tan φ_r = 50000 Pa"):  # fmt: skip
        pf.Joint(c_r=0.05e6, phi_r=45.0, tensile_r=0.06e6)
    pf.Joint(c_r=0.05e6, phi_r=45.0, tensile_r=0.05e6)  # at the apex: allowed
    with pytest.raises(ModelError, match=r"c_r / tan φ \(the peak\) = 41955"):  # tan 50°
        pf.SlipWeakening(phi=50.0, phi_r=30.0, c_r=0.05e6, tensile_r=0.05e6)
