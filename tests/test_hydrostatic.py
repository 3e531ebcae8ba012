"""The hydrostatic load p = ρ g (h − z)⁺ on faces the water level cuts
(:meth:`pfeie.Model.add_pressure` with ``level``): the facet the level crosses is
integrated on its wet part alone, so the thrust and its moment about the base match the
closed forms ρ g h²/2 and ρ g h³/6 (per metre of width) to round-off at any level, on
linear and quadratic 2D and 3D meshes, also on an inclined face. A Gauss rule over the
whole cut facet misses them by 1e-6 to 5e-2 (the kink of p inside the facet)."""

from __future__ import annotations

import numpy as np
import pytest

import pfeie as pf

GW = 1000.0 * 9.81  # ρ g, N/m³
HEIGHT = 10.0  # the face, m (3 cells: nodes at 0, 3.33, 6.67, 10 m)


def thrust(mesh: pf.Mesh, level: float, width: float) -> tuple[float, float, float]:
    """The horizontal thrust, the vertical force and the moment about the base (z = 0)
    of the horizontal loads, each per metre of width, of the hydrostatic pressure on the
    face group xmin."""
    dim = mesh.points.shape[1]
    up = dim - 1
    model = pf.Model(mesh, [pf.Block("all", pf.Elastic(30e9, 0.2, 2400.0))])
    model.add_pressure("xmin", lambda x: GW * np.maximum(level - x[..., up], 0.0),
                       level=level)  # fmt: skip
    f = model.load_vector().reshape(-1, dim)
    z = mesh.points[:, up]
    return f[:, 0].sum() / width, f[:, up].sum() / width, (f[:, 0] * z).sum() / width


@pytest.mark.parametrize("cell", ["quad", "quad8", "quad9", "triangle", "triangle6"])
@pytest.mark.parametrize("level", [5.0, 7.3, 9.99])
def test_thrust_and_moment_2d(cell: str, level: float) -> None:
    """Levels inside the second and third cells and just below the crest: F = ρgh²/2
    and M = ρgh³/6 to 1e-15 (measured ≤ 2.3e-16; a whole-facet Gauss rule: up to 1.5e-2
    and 4.6e-2)."""
    fx, fy, m = thrust(pf.rectangle(2.0, HEIGHT, 1, 3, cell=cell), level, 1.0)
    assert fx == pytest.approx(GW * level**2 / 2, rel=1e-15, abs=0)
    assert m == pytest.approx(GW * level**3 / 6, rel=1e-15, abs=0)
    assert abs(fy) <= 1e-15 * fx


@pytest.mark.parametrize("cell", ["quad", "quad8", "triangle6"])
def test_inclined_face_2d(cell: str) -> None:
    """The face sheared to x = 0.3 y (an upstream batter): the horizontal thrust is
    still ρgh²/2, the water's weight on the face −0.3 ρgh²/2 (vertical, downward), to
    1e-15 (measured ≤ 4.4e-16)."""
    mesh = pf.rectangle(2.0, HEIGHT, 1, 3, cell=cell)
    mesh.points[:, 0] += 0.3 * mesh.points[:, 1]
    level = 5.0
    fx, fy, m = thrust(mesh, level, 1.0)
    assert fx == pytest.approx(GW * level**2 / 2, rel=1e-15, abs=0)
    assert fy == pytest.approx(-0.3 * GW * level**2 / 2, rel=1e-15, abs=0)
    assert m == pytest.approx(GW * level**3 / 6, rel=1e-15, abs=0)


@pytest.mark.parametrize("cell", ["hexahedron", "tetra", "tetra10"])
@pytest.mark.parametrize("level", [5.0, 7.3])
def test_thrust_and_moment_3d(cell: str, level: float) -> None:
    """A 3 m wide face of quads or triangles (linear and quadratic): per metre of width
    F = ρgh²/2 and M = ρgh³/6 to 2e-15 (measured ≤ 4.4e-16; a whole-facet rule: up to
    1.5e-2 and 4.6e-2)."""
    fx, _, m = thrust(pf.box(2.0, 3.0, HEIGHT, 1, 2, 3, cell=cell), level, 3.0)
    assert fx == pytest.approx(GW * level**2 / 2, rel=2e-15, abs=0)
    assert m == pytest.approx(GW * level**3 / 6, rel=2e-15, abs=0)


def test_silt_level_cuts_a_facet() -> None:
    """Silt up to 5 m (inside the second cell) on a Q8 face at rest, K0 = 1 − sin 30° =
    0.5: the thrust K γ' h²/2 to 1e-15 (measured 0)."""
    mesh = pf.rectangle(2.0, HEIGHT, 1, 3, cell="quad8")
    model = pf.Model(mesh, [pf.Block("all", pf.Elastic(30e9, 0.2, 2400.0))])
    k = model.add_silt("xmin", level=5.0, submerged_unit_weight=9000.0, friction_angle=30.0)
    fx = model.load_vector()[0::2].sum()
    assert fx == pytest.approx(k * 9000.0 * 5.0**2 / 2, rel=1e-15, abs=0)
