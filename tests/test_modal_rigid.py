"""Rigid-body modes of floating blocks (``pf.modal(..., interfaces="free")``).

A block resting on a fixed base, its joint ignored, floats: K has a null space of
dimension 3 in 2D (two translations, one rotation) and 6 in 3D (three and three), so
exactly that many of the lowest eigenvalues are zero, and the solve returns them as
round-off (measured: ω² up to 1.3e-8 rad²/s² against ω²_scale = max diag K / max diag M
≈ 3e8 rad²/s²). All of them must be flagged rigid with an infinite period, also when no
elastic mode is computed (the largest computed ω² is then itself round-off), and the
first elastic mode must not be. The rigid modes span the block's translations, so their
effective masses along each axis add up to the block's mass ρ V exactly (a closed form:
2400 kg/m³ × 1 m³, or × 1 m² × 1 m thickness in 2D), to round-off (1e-9).
"""

from __future__ import annotations

import numpy as np
import pytest

import pfeie as pf
from pfeie.verification._models import block_on_base, block_on_base_3d

RHO = 2400.0  # kg/m³, the blocks' density (the builders' default)


@pytest.mark.parametrize(("dim", "n_rigid"), [(3, 6), (2, 3)])
@pytest.mark.parametrize("extra", [0, 2])
def test_free_block_rigid_modes(dim: int, n_rigid: int, extra: int) -> None:
    """A free unit block: ``n_rigid`` rigid modes (6 in 3D, 3 in 2D), asked for alone
    (``extra`` = 0) or with 2 elastic modes beyond them, which are not rigid."""
    if dim == 3:
        model = block_on_base_3d(joint=pf.Joint(phi=30.0), n=2, gravity=False)
        mass = RHO * 1.0**3
    else:
        model = block_on_base(joint=pf.Joint(phi=30.0), n=2, gravity=False)
        mass = RHO * 1.0 * 1.0 * model.thickness
    res = pf.modal(model, n_rigid + extra, interfaces="free")
    expected = np.arange(n_rigid + extra) < n_rigid
    np.testing.assert_array_equal(res.rigid, expected)
    assert np.all(np.isinf(res.periods[:n_rigid]))
    assert np.all(np.isfinite(res.periods[n_rigid:]))
    np.testing.assert_allclose(res.effective_mass[res.rigid].sum(axis=0), mass, rtol=1e-9)


def test_bonded_block_has_no_rigid_mode() -> None:
    """The same 3D block with its joint bonded (rigid pairs tie it to the fixed base):
    no mode is rigid, and its lowest frequency is far above the rigid threshold
    (ω² ≥ 1e-10 ω²_scale, 1000 times the threshold of 1e-13)."""
    model = block_on_base_3d(joint=pf.Joint(phi=30.0), n=2, gravity=False)
    res = pf.modal(model, 4)
    assert not res.rigid.any()
    w2 = (2 * np.pi * res.frequencies) ** 2
    assert w2.min() > 1e-10 * res.omega2_scale


def test_a_slender_cantilever_has_no_rigid_mode() -> None:
    """A clamped column 50 m × 0.5 m on 2 × 800 Q4 cells: its first bending mode (about
    0.12 Hz; the mesh's highest frequencies are near 1e5 Hz) is elastic, not rigid. Under
    the earlier threshold, 1e-10 of ω²_scale (0.17 Hz here), it was called rigid."""
    mesh = pf.rectangle(0.5, 50.0, 2, 800)
    model = pf.Model(mesh, [pf.Block("all", pf.Elastic(30e9, 0.2, 2400.0))])
    model.fix("ymin")
    res = pf.modal(model, 2)
    assert not res.rigid.any() and np.all(np.isfinite(res.periods))
    assert res.frequencies[0] < 0.2
    assert (2 * np.pi * res.frequencies[0]) ** 2 < 1e-10 * res.omega2_scale  # the old cut
