"""A joint's safety factor with a shear at the round-off of its forces is ∞ (no shear),
in the static summary as in the histories (:data:`pfeie.interface.FS_ROUNDOFF`, 1e-10 of
the sum of its pair forces): a frictionless contact between blocks at rest printed
"FS 0.00" (capacity 0 over a shear of 8e-12 of its normal force)."""

from __future__ import annotations

import numpy as np
import pytest

import pfeie as pf
from pfeie._job import _static_joints
from pfeie.interface import FS_ROUNDOFF


def _block_on_a_frictionless_base() -> tuple[pf.Model, pf.StaticResult]:
    mesh = pf.rectangle(2.0, 2.0, 2, 2)
    mesh.add_cell_group("base", lambda x: x[:, 1] < 1.0)
    mesh.add_cell_group("block", lambda x: x[:, 1] > 1.0)
    mesh.add_facet_group("joint", lambda x: np.abs(x[:, 1] - 1.0) < 1e-9, boundary_only=False)
    rock = pf.Elastic(10e9, 0.25, 2600.0)
    model = pf.Model(mesh, [pf.Block("base", rock), pf.Block("block", rock)],
                     interfaces=[pf.Interface("joint", pf.Joint(phi=0.0))])  # fmt: skip
    model.fix("ymin")
    model.add_gravity()
    return model, pf.solve_static(model)


@pytest.mark.parametrize(("shear", "fs"), [(0.0, None), (0.5, None), (2.0, 0.0)])
def test_a_round_off_shear_is_no_shear(shear: float, fs: float | None) -> None:
    """The block's weight 2 m × 1 m × 2600 kg/m³ × g = 51.0 kN on the joint; a shear of
    ``shear`` × FS_ROUNDOFF × Σ|X| added to one pair: below the threshold FS is ∞ (None
    in the summary), above it the frictionless joint's capacity 0 gives FS 0."""
    model, st = _block_on_a_frictionless_base()
    assert st.pairs is not None
    X = st.pairs.X
    assert float(X[:, -1].sum()) == pytest.approx(2600.0 * 9.81 * 2.0, rel=1e-12)
    X[0, 0] += shear * FS_ROUNDOFF * float(np.abs(X).sum())
    assert _static_joints(model, st)["joint"]["safety_factor"] == fs
