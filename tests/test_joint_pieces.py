"""3D joint maps of joints in several pieces or with a re-entrant corner
(:func:`pfeie.plot._plots.joint_patches`).

One physical group may hold several parallel joints (a dam's contraction joints); drawn
on one plane their pairs lay on top of each other, one plane's values hiding the other's.
Each connected piece is now drawn in its own plane, and each pair's cell is clipped to the
joint's faces. Reference: the pairs' tributary areas, which pfeie's interface split lumps
from the faces independently of the figures; on a uniform grid of square faces the
Voronoi cell of a node is exactly its lumped share.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import pfeie as pf

pytest.importorskip("h5py")
pytest.importorskip("matplotlib")


def _run(tmp: Path, mesh: pf.Mesh, blocks: list[str],
         interfaces: list[pf.Interface]) -> Path:  # fmt: skip
    concrete = pf.Elastic(30e9, 0.2, 2400)
    model = pf.Model(mesh, [pf.Block(b, concrete) for b in blocks], interfaces=interfaces)
    model.fix("zmin")
    model.add_gravity()
    gm = pf.GroundMotion.from_function(lambda t: 2.0 * np.sin(2 * np.pi * 3 * t), duration=0.02,
                                       dt=0.005, direction=(1, 0, 0))  # fmt: skip
    pf.run_to_folder(pf.Dynamic(model, 0.005), 0.02, tmp / "out", ground=[gm],
                     start=pf.solve_static(model), figures=False, paraview=False)  # fmt: skip
    return tmp / "out" / "results.h5"


def test_two_parallel_joints_in_one_group_are_drawn_apart(tmp_path: Path) -> None:
    from pfeie.io import Results
    from pfeie.plot._plots import _polygon_area, joint_patches, plot_joint_map_3d, plot_static

    mesh = pf.box(3.0, 1.0, 1.0, 6, 2, 2, cell="hexahedron")
    for name, lo, hi in (("a", 0, 1), ("b", 1, 2), ("c", 2, 3)):
        mesh.add_cell_group(name, lambda x, lo=lo, hi=hi: (x[:, 0] > lo) & (x[:, 0] < hi))
    mesh.add_facet_group("cj", lambda x: np.isclose(x[:, 0], 1) | np.isclose(x[:, 0], 2),
                         boundary_only=False)  # fmt: skip
    joint = pf.Joint(phi=35, c=1e5, tensile=1e5, initial="intact")
    path = _run(tmp_path, mesh, ["a", "b", "c"], [pf.Interface("cj", joint)])
    with Results(path) as res:
        pieces = joint_patches(res, "cj")
        area = res.pairs("cj")["area"]
        assert [p.members.size for p in pieces] == [9, 9]  # 3 × 3 nodes on each 1 m² plane
        assert [round(float(p.centre[0]), 12) for p in pieces] == [1.0, 2.0]
        for p in pieces:
            assert p.labels == ["y", "z"] and len(p.outline) == 4  # four 0.5 m faces
            cells = np.array([_polygon_area(c) for c in p.cells])
            # the Voronoi cell of each node is its lumped share of the faces (¼ of a face
            # at a corner, ½ on an edge, 1 inside: 1/16, 1/8, 1/4 m²), to round-off
            np.testing.assert_allclose(cells, area[p.members], rtol=1e-12)
        out = plot_joint_map_3d(res, tmp_path / "map.png")
        plot_static(res, "cj", tmp_path / "static.png")
    from PIL import Image

    joints = json.loads(Image.open(out).info["Description"])["joints"]
    assert joints["cj"]["pairs"] == 18
    assert [q["pairs"] for q in joints["cj"]["pieces"]] == [9, 9]
    assert [q["centre"][0] for q in joints["cj"]["pieces"]] == pytest.approx([1.0, 2.0])


def test_an_l_shaped_joint_is_drawn_over_its_faces_only(tmp_path: Path) -> None:
    """An L-shaped frictional joint beside a bonded square on one plane z = 1 m: the seam's
    nodes belong to one of the two interfaces, and their tributary area spans faces of
    both; the cells tile each joint as the areas do, and none enters the other joint."""
    from pfeie.io import Results
    from pfeie.plot._plots import _polygon_area, joint_patches

    mesh = pf.box(2.0, 2.0, 2.0, 4, 4, 4, cell="hexahedron")
    mesh.add_cell_group("low", lambda x: x[:, 2] < 1)
    mesh.add_cell_group("up", lambda x: x[:, 2] > 1)
    corner = lambda x: (x[:, 0] > 1) & (x[:, 1] > 1)  # noqa: E731
    mesh.add_facet_group("j", lambda x: np.isclose(x[:, 2], 1) & ~corner(x), boundary_only=False)
    mesh.add_facet_group("rest", lambda x: np.isclose(x[:, 2], 1) & corner(x),
                         boundary_only=False)  # fmt: skip
    bonded = pf.Joint(phi=35, c=1e6, tensile=1e6, initial="intact")
    path = _run(tmp_path, mesh, ["low", "up"],
                [pf.Interface("j", pf.Joint(phi=35)), pf.Interface("rest", bonded)])  # fmt: skip
    with Results(path) as res:
        total = 0.0
        for name in ("j", "rest"):
            (piece,) = joint_patches(res, name)  # each in one piece
            area = res.pairs(name)["area"]
            cells = np.array([_polygon_area(c) for c in piece.cells])
            np.testing.assert_allclose(cells, area[piece.members], rtol=1e-12)
            total += cells.sum()
            # every cell inside the joint's faces (the box of its outline), none in the
            # other joint's square beyond the seam's half faces
            pts = np.vstack(piece.cells)
            if name == "j":
                assert not ((pts[:, 0] > 1.25 + 1e-9) & (pts[:, 1] > 1.25 + 1e-9)).any()
            else:
                # the seam at 1 m less half a face (0.5 m): its pairs' share of j's faces
                assert pts.min() == pytest.approx(1.0 - 0.5 / 2)
        assert total == pytest.approx(4.0, rel=1e-12)  # the plane, 2 m × 2 m


def test_two_lift_joints_in_one_2d_group_are_two_pieces(tmp_path: Path) -> None:
    """Two horizontal lift joints of a 4 m wide column named as one group: along one axis
    their pairs interleave (a line through them zigzagged between the joints); each is
    now its own piece and panel. Reference: the static normal force on each is the weight
    above it, γ h b (h = 2 and 1 m), to round-off."""
    from pfeie.io import Results
    from pfeie.plot._plots import joint_pieces, plot_joint_map, plot_states, plot_static

    mesh = pf.rectangle(4.0, 3.0, 8, 6, cell="quad")
    for name, lo, hi in (("a", 0, 1), ("b", 1, 2), ("c", 2, 3)):
        mesh.add_cell_group(name, lambda x, lo=lo, hi=hi: (x[:, 1] > lo) & (x[:, 1] < hi))
    mesh.add_facet_group("lifts", lambda x: np.isclose(x[:, 1], 1) | np.isclose(x[:, 1], 2),
                         boundary_only=False)  # fmt: skip
    concrete = pf.Elastic(30e9, 0.2, 2400)
    model = pf.Model(mesh, [pf.Block(b, concrete) for b in "abc"],
                     interfaces=[pf.Interface("lifts", pf.Joint(phi=30))])  # fmt: skip
    model.fix("ymin")
    model.add_gravity()
    gm = pf.GroundMotion.from_function(lambda t: 2.0 * np.sin(2 * np.pi * 3 * t), duration=0.02,
                                       dt=0.005)  # fmt: skip
    pf.run_to_folder(pf.Dynamic(model, 0.005), 0.02, tmp_path / "out", ground=[gm],
                     start=pf.solve_static(model), figures=False, paraview=False)  # fmt: skip
    with Results(tmp_path / "out" / "results.h5") as res:
        pieces = joint_pieces(res, "lifts")
        pr = res.static_pairs("lifts")
        assert [p.size for p in pieces] == [9, 9]
        assert [float(pr["x"][p, 1].mean()) for p in pieces] == pytest.approx([1.0, 2.0])
        gamma = 2400 * 9.81
        for p, h in zip(pieces, (2.0, 1.0), strict=True):
            # measured 2e-16: the static problem is linear here (all pairs stick)
            assert float(pr["X"][p, -1].sum()) == pytest.approx(gamma * h * 4.0, rel=1e-14)
        for fig in (plot_joint_map(res, tmp_path / "map.png"),
                    plot_states(res, "lifts", tmp_path / "states.png"),
                    plot_static(res, "lifts", tmp_path / "static.png")):  # fmt: skip
            assert fig.stat().st_size > 10_000


@pytest.mark.parametrize("cell, sizes", [("hexahedron", [18, 9]), ("tetra10", [50, 25])])
def test_a_t_junction_in_one_group_is_two_pieces(tmp_path: Path, cell: str,
                                                 sizes: list[int]) -> None:  # fmt: skip
    """A foundation joint H (z = 1 m) and a contraction joint V (x = 1 m) above it, named
    as one group: two pieces, H and V. At the junction a side-a node carries pairs of
    both joints; keeping one pair per node had split H into a piece of 15 pairs and three
    single pairs (Tet10: a single-pair piece for every midside pair)."""
    from pfeie.io import Results
    from pfeie.plot._plots import joint_patches

    mesh = pf.box(2.0, 1.0, 2.0, 4, 2, 4, cell=cell)
    mesh.add_cell_group("low", lambda x: x[:, 2] < 1)
    mesh.add_cell_group("ul", lambda x: (x[:, 2] > 1) & (x[:, 0] < 1))
    mesh.add_cell_group("ur", lambda x: (x[:, 2] > 1) & (x[:, 0] > 1))
    mesh.add_facet_group("T", lambda x: np.isclose(x[:, 2], 1)
                         | (np.isclose(x[:, 0], 1) & (x[:, 2] > 1 - 1e-9)),
                         boundary_only=False)  # fmt: skip
    joint = pf.Joint(phi=35, c=1e5, tensile=1e5, initial="intact")
    path = _run(tmp_path, mesh, ["low", "ul", "ur"], [pf.Interface("T", joint)])
    with Results(path) as res:
        pieces = joint_patches(res, "T")
    assert [p.members.size for p in pieces] == sizes
    np.testing.assert_allclose([p.basis[-1] for p in pieces], [[0, 0, 1], [1, 0, 0]],
                               atol=1e-12)  # fmt: skip
    assert [len(p.outline) for p in pieces] == ([8, 4] if cell == "hexahedron" else [16, 8])


def test_a_crack_inside_a_block_is_drawn_to_its_front(tmp_path: Path) -> None:
    """A crack over x ≤ 1 m of a 2 m block's mid-plane: the faces along its front hold
    whole nodes (of no pair) and had been left out, so the map covered x ≤ 0.5 m (1 m² of
    the 2 m²). Now every face of the crack is drawn: its cells cover 2 m²."""
    from pfeie.io import Results
    from pfeie.plot._plots import _polygon_area, joint_patches

    mesh = pf.box(2.0, 2.0, 2.0, 4, 4, 4, cell="hexahedron")
    mesh.add_cell_group("all", lambda x: x[:, 2] > -1)
    mesh.add_facet_group("crack", lambda x: np.isclose(x[:, 2], 1) & (x[:, 0] < 1 + 1e-9),
                         boundary_only=False)  # fmt: skip
    joint = pf.Joint(phi=35, c=1e5, tensile=1e5, initial="intact")
    path = _run(tmp_path, mesh, ["all"], [pf.Interface("crack", joint)])
    with Results(path) as res:
        (piece,) = joint_patches(res, "crack")
    outline = np.vstack(piece.outline)
    assert len(piece.outline) == 8  # 2 × 4 faces of 0.5 m
    assert outline[:, 0].min() == pytest.approx(0.0) and outline[:, 0].max() == pytest.approx(1.0)
    assert sum(_polygon_area(c) for c in piece.cells) == pytest.approx(2.0, rel=1e-12)


def test_a_cross_in_one_2d_group_is_four_arms(tmp_path: Path) -> None:
    """Two joints crossing at (2, 2) m, named as one group: each arm is a straight piece
    (a piece of the two arms below and left had been drawn along a diagonal, compressed
    and open pairs on one line)."""
    from pfeie.io import Results
    from pfeie.plot._plots import joint_pieces

    mesh = pf.rectangle(4.0, 4.0, 4, 4, cell="quad")
    for name, fx, fy in (("q1", 1, 1), ("q2", -1, 1), ("q3", -1, -1), ("q4", 1, -1)):
        mesh.add_cell_group(name, lambda x, fx=fx, fy=fy: (fx * (x[:, 0] - 2) > 0)
                            & (fy * (x[:, 1] - 2) > 0))  # fmt: skip
    mesh.add_facet_group("X", lambda x: np.isclose(x[:, 0], 2) | np.isclose(x[:, 1], 2),
                         boundary_only=False)  # fmt: skip
    concrete = pf.Elastic(30e9, 0.2, 2400)
    model = pf.Model(mesh, [pf.Block(b, concrete) for b in ("q1", "q2", "q3", "q4")],
                     interfaces=[pf.Interface("X", pf.Joint(phi=30))])  # fmt: skip
    model.fix("ymin")
    model.add_gravity()
    gm = pf.GroundMotion.from_function(lambda t: 0.0 * t, duration=0.01, dt=0.005)
    pf.run_to_folder(pf.Dynamic(model, 0.005), 0.01, tmp_path / "out", ground=[gm],
                     start=pf.solve_static(model), figures=False, paraview=False)  # fmt: skip
    with Results(tmp_path / "out" / "results.h5") as res:
        x = res.pairs("X")["x"]
        pieces = joint_pieces(res, "X")
    for p in pieces:  # each piece straight: its pairs on one line x = 2 or y = 2
        assert np.ptp(x[p, 0]) < 1e-12 or np.ptp(x[p, 1]) < 1e-12
    assert sum(p.size for p in pieces) == x.shape[0] and len(pieces) == 4
