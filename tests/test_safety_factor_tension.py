"""The sliding safety factor counts a pair's normal force with its sign: tension lowers
the capacity, as in the joint law (an intact pair holds c A + μ X_n, down to
c A − μ σ_t A at its tensile strength) and as in the hand computation of a dam's base
under a pseudo-static load (USACE EM 1110-2-2100; FERC Ch. III):

    FS = (c B + μ (W − U)) / (T + k_h W),   T = ρ_w g h_w² / 2,
    U = ρ_w g h_w B / 2 (the head linear from h_w at the heel to 0 at the toe),

W − U the base's resultant normal force by vertical equilibrium, whatever the pairs
that carry tension. Reference: the dam block of tests/test_uplift.py (10 m × 20 m,
Q8, on a bonded base joint at y = 2 m), 12 m of water, the inertia k_h g W of a
horizontal seismic coefficient k_h downstream. Counting the compression only
(Σ (c A + μ N⁺)) overstated this FS by 0.96 % at k_h = 0.1 (5.538 against 5.485)."""

from __future__ import annotations

import numpy as np
import pytest

import pfeie as pf
from pfeie.interface import OPEN
from test_uplift import RHO_W, B, G, H, dam

C, PHI, SIGMA_T = 0.3e6, 40.0, 0.2e6


@pytest.mark.parametrize("kh", [0.0, 0.1])
def test_fs_counts_tension_as_the_hand_computation(kh: float) -> None:
    """Without the seismic load the base is in compression throughout; at k_h = 0.1 its
    three heel pairs carry tension (48 kN at most, below σ_t A: none breaks). Both equal
    the closed form to 1e-14 (measured 7.8e-16 and 2.9e-15: the sums of the pair forces
    balance the loads to round-off)."""
    hw = 12.0
    model, _ = dam(hw, pf.Joint(c=C, phi=PHI, tensile=SIGMA_T, initial="intact"))
    W = 2400.0 * G * B * H
    model.add_inertia([kh * G, 0.0])
    st = pf.solve_static(model)
    P, S = model.pairs, st.pairs
    assert P is not None and S is not None
    assert not S.broken.any()
    tension = S.X[:, -1] < 0
    assert tension.sum() == (3 if kh > 0 else 0)
    U = RHO_W * G * hw * B / 2
    T = RHO_W * G * hw**2 / 2 + kh * W
    assert float(S.X[:, -1].sum()) == pytest.approx(W - U, rel=1e-14)
    exact = (C * P.area.sum() + (W - U) * np.tan(np.radians(PHI))) / T
    fs = model.pair_laws.safety_factor(S.X, S.state == OPEN, S.broken, S.path, P.frame)
    assert fs[0] == pytest.approx(exact, rel=1e-14)
    # each pair's capacity is its cone's radius at its normal force, tension included
    cone = model.pair_laws.cone(S.X[:, -1], S.broken, S.path)
    mu = np.tan(np.radians(PHI))
    np.testing.assert_allclose(cone, C * P.area + mu * S.X[:, -1], rtol=1e-15, atol=0)
