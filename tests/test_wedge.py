"""A rock wedge on two joint planes (3D): the pairs on its keel, its yield coefficient
against the limit equilibrium of Hoek and Bray, and its sliding against the rigid wedge's.

The wedge: a structured Hex8 box (2 m × 3 m × 2 m) cut at mid-height, whose points are
then mapped z → z + |x − 1| (two planes at 45° from the vertical plane through the keel,
x = 1) and turned about x so that the keel plunges by ψ towards +y. The lower part (the
rock) is fixed at its base; the wedge rests in the V, φ = 30° on both planes, named as one
joint or as two (``left``, ``right``).

Hoek and Bray (Rock Slope Engineering, 1981, ch. 7), a symmetric wedge of half-angle ξ
between each plane and the vertical plane through the keel: the two normal forces sum to
K W (cos ψ − k sin ψ), K = 1 / sin ξ = √2, under a horizontal acceleration k g along the
keel's plunge, against the driving force W (sin ψ + k cos ψ), so

    k_y = (K tan φ cos ψ − sin ψ) / (cos ψ + K tan φ sin ψ),

0.8165 at ψ = 0 and 0.1625 at ψ = 30°.
"""

from __future__ import annotations

import numpy as np
import pytest

import pfeie as pf

PHI = 30.0


def _wedge(psi: float, groups: int, E: float = 10e9) -> pf.Model:
    mesh = pf.box(2.0, 3.0, 2.0, 4, 3, 4, cell="hexahedron")
    mesh.add_cell_group("rock", lambda x: x[:, 2] < 1.0)
    mesh.add_cell_group("wedge", lambda x: x[:, 2] > 1.0)
    plane = np.abs(mesh.points[:, 2] - 1.0) < 1e-9
    if groups == 2:
        mesh.add_facet_group("left", lambda x: (np.abs(x[:, 2] - 1.0) < 1e-9)
                             & (x[:, 0] < 1.0 + 1e-9), boundary_only=False)  # fmt: skip
        mesh.add_facet_group("right", lambda x: (np.abs(x[:, 2] - 1.0) < 1e-9)
                             & (x[:, 0] > 1.0 - 1e-9), boundary_only=False)  # fmt: skip
        names = ["left", "right"]
    else:
        mesh.add_facet_group("joint", lambda x: np.abs(x[:, 2] - 1.0) < 1e-9,
                             boundary_only=False)  # fmt: skip
        names = ["joint"]
    assert plane.any()
    p = mesh.points.copy()
    p[:, 2] += np.abs(p[:, 0] - 1.0)
    mesh.points[:] = p @ _turn(psi).T
    rock = pf.Elastic(E, 0.25, 2600.0)
    model = pf.Model(mesh, [pf.Block("rock", rock), pf.Block("wedge", rock)],
                     interfaces=[pf.Interface(n, pf.Joint(phi=PHI)) for n in names])  # fmt: skip
    model.fix("zmin")
    model.add_gravity()
    return model


def _turn(psi: float) -> np.ndarray:
    """The rotation about x that plunges +y by ψ (degrees)."""
    c, s = np.cos(np.radians(psi)), np.sin(np.radians(psi))
    return np.array([[1.0, 0.0, 0.0], [0.0, c, s], [0.0, -s, c]])


def _hoek_bray(psi: float) -> float:
    k_tan, ps = np.sqrt(2.0) * np.tan(np.radians(PHI)), np.radians(psi)
    return float((k_tan * np.cos(ps) - np.sin(ps)) / (np.cos(ps) + k_tan * np.sin(ps)))


@pytest.mark.parametrize("groups", [1, 2])
@pytest.mark.parametrize("psi", [0.0, 30.0, -30.0])
def test_keel_pairs_keep_their_planes_and_one_side(psi: float, groups: int) -> None:
    """Each pair's normal is its own plane's (to 1e-12), the keel's node couples carry one
    pair per plane, and every pair has the wedge on the same side. Before: at ψ = 0 the
    keel's 4 couples were one pair each, normal 45° off both planes (the mean), and at
    ψ = ±30° the two planes faced opposite ways (their shear forces cancelled in the
    joint's resultant: safety factor 7.05 where the hand computation gives 1.17)."""
    model = _wedge(psi, groups)
    P, split = model.pairs, model.split
    assert P is not None and split is not None
    R = _turn(psi)
    planes = np.stack([R @ np.array([1.0, 0.0, 1.0]), R @ np.array([-1.0, 0.0, 1.0])]) / np.sqrt(2)
    cos = np.abs(P.frame[:, -1] @ planes.T).max(axis=1)
    assert np.all(cos >= 1.0 - 1e-12), cos.min()
    keel = np.abs((P.x @ R)[:, 0] - 1.0) < 1e-9
    assert keel.sum() == 8  # 4 couples along the keel, two pairs each
    assert np.unique(split.body[P.node_b]).size == 1
    assert P.n == 24


@pytest.mark.parametrize(("psi", "groups"), [
    (0.0, 2),
    (30.0, 1),
    pytest.param(0.0, 1, marks=pytest.mark.slow),
    pytest.param(30.0, 2, marks=pytest.mark.slow),
])  # fmt: skip
def test_yield_coefficient_against_hoek_and_bray(psi: float, groups: int) -> None:
    """k_y along the keel's plunge within 1e-3 of Hoek and Bray's (the search's own
    tolerance; measured 5.5e-5 at ψ = 0 with two joints, 1.9e-4 at ψ = 30° with one), and
    the limit is sliding. Before: 0.7217 at ψ = 0 (−11.6 %: the keel's pairs, normal to
    neither plane, held the wedge up), and at ψ = 30° with one joint the limit was taken
    for "no equilibrium found" (its factor of safety summed shears that faced opposite
    ways)."""
    model = _wedge(psi, groups)
    y = pf.yield_coefficient(model, [0.0, 1.0, 0.0], tol=1e-3)
    assert y.k_y is not None
    assert abs(y.k_y / _hoek_bray(psi) - 1.0) <= 1e-3, (y.k_y, _hoek_bray(psi))
    assert y.limit == "sliding"


def _sliding_wedge(dt: float, E: float) -> tuple[float, float, pf.DynamicResult]:
    """The wedge (ψ = 30°, two joints, the rock fixed throughout) under a constant ground
    acceleration of 0.3 g along −y, so that the inertia of the wedge pushes it along the
    keel's trend (k = 0.3 > k_y = 0.1625), for 0.3 s: the whole-history error of its
    slip along the keel against the rigid wedge's ½ a t², relative to the largest, and its
    largest opening (m)."""
    psi, k, g = 30.0, 0.3, 9.81
    model = _wedge(psi, 2, E)
    model.fix("rock")
    t = np.arange(0.0, 0.3 + dt / 2, dt)
    gm = pf.GroundMotion.from_samples(np.full(t.size, -k * g), time=t, direction=[0.0, 1.0, 0.0])
    res = pf.Dynamic(model, dt).run(0.3, start=pf.solve_static(model), ground=[gm])
    keel = _turn(psi) @ np.array([0.0, 1.0, 0.0])
    x = (res.rigid[:, 1, :3] - res.rigid[0, 1, :3]) @ keel
    s, c, mu = np.sin(np.radians(psi)), np.cos(np.radians(psi)), np.tan(np.radians(PHI))
    a = g * ((s + k * c) - np.sqrt(2.0) * mu * (c - k * s))  # Hoek and Bray's normal forces
    ref = 0.5 * a * res.t**2
    return float(np.abs(x - ref).max() / np.abs(ref).max()), float(res.opening.max()), res


def test_a_wedge_slides_as_the_rigid_wedge() -> None:
    """The rigid wedge slides along its keel with a = g [(sin ψ + k cos ψ) − K tan φ
    (cos ψ − k sin ψ)], K = 1/sin ξ = √2 (the normal forces of Hoek and Bray under the
    inertia k g): 1.718 m/s² at k = 0.3. The elastic wedge, every pair of both planes
    sliding from the first step and none opening (largest opening 1e-17 m: round-off;
    asserted 1 µm), follows it with a whole-history error that falls with Δt:

    - E = 100 GPa: 0.66, 0.36, 0.23 % at Δt = 2, 1, 0.5 ms (first order less what the
      onset costs: the least-squares rate 0.76, asserted ≥ 0.6; the last asserted ≤ 0.3 %);
    - E = 10 GPa, the wedge of the static tests: 1.4, 0.83, 0.61, 0.67 % at Δt = 4, 2, 1,
      0.5 ms, a floor of its elasticity (the static state's friction, held up the dip at
      every pair, lets go as the wedge starts: the slip runs 2 mm/s ahead by 0.05 s, then
      the two accelerate alike); at 2 ms asserted ≤ 1 %."""
    err, opening, res = _sliding_wedge(0.002, 10e9)
    assert err <= 1e-2, err
    assert opening <= 1e-6 and np.all(res.state[1:] == pf.interface.SLIDE)
    dts = [0.002, 0.001, 0.0005]
    errs = [_sliding_wedge(dt, 1e11)[0] for dt in dts]
    rate = float(np.polyfit(np.log(dts), np.log(errs), 1)[0])
    assert rate >= 0.6 and errs[-1] <= 3e-3, (errs, rate)
