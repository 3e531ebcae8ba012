"""Mass-proportional damping brakes a sliding block (docs/model-file.md, "Damping").

A block launched at v₀ along a level joint of friction coefficient μ decelerates by μg,
and, with the Rayleigh term α M acting on its motion relative to the ground, by α v more:
v' = −μg − α v. It stops after

    d₀ = v₀² / (2 μ g)                                  (α = 0),
    d_α = v₀/α − (μg/α²) ln(1 + α v₀/(μg))              (α > 0),

0.16989 m and 0.11848 m for v₀ = 1 m/s, μ = 0.3, α = 2 1/s: the drag shortens the slide
by 30 %. The deformable block (E = 30 GPa, 2 × 2 Q4, Δt = 1 ms) gives both within 0.4 %
(measured 0.29 % and 0.39 %: the block's elastic response to the launch and the step);
asserted 1 %.
"""

from __future__ import annotations

import numpy as np
import pytest

import pfeie as pf
from pfeie.verification._models import block_on_base, slip_x

MU, V0, G = 0.3, 1.0, 9.81


@pytest.mark.parametrize("alpha", [0.0, 2.0])
def test_a_launched_block_stops_where_the_closed_form_says(alpha: float) -> None:
    m = block_on_base(joint=pf.Joint(phi=float(np.degrees(np.arctan(MU)))))
    m.damping = pf.Rayleigh(alpha, 0.0)
    st = pf.solve_static(m)
    an = pf.Dynamic(m, 1e-3)
    v = np.zeros_like(st.u)
    v[m.body_of_node == 1, 0] = V0  # the block, its joint face included
    res = an.run(0.6, start=an.initial(st, v0=v))  # stops at t < v₀/(μg) = 0.34 s
    d = slip_x(res)[-1] - slip_x(res)[0]
    if alpha == 0.0:
        ref = V0**2 / (2 * MU * G)
    else:
        ref = V0 / alpha - MU * G / alpha**2 * np.log(1 + alpha * V0 / (MU * G))
    assert d == pytest.approx(ref, rel=1e-2)
    assert abs(slip_x(res)[-1] - slip_x(res)[-50]) < 1e-9  # at rest at the end
