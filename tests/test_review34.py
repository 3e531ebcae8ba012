"""Findings of the thirty-fourth session's reviews and testers, each a test that failed on
the code before its fix."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest

import pfeie as pf
from pfeie.io import Results

G = 9.81


# -- a joint in pieces between different blocks: each piece in the CSV and the report ----


def _monoliths() -> pf.Model:
    """Four monoliths on a rock block: a contraction joint ``cj`` cut by a lift joint
    ``lift`` (each joint in two pieces between different blocks), a bonded base."""
    mesh = pf.rectangle(2.0, 3.0, 4, 6)
    mesh.points[:, 1] -= 1.0
    mesh.add_cell_group("rock", lambda x: x[:, 1] < 0)
    for name, xs, ys in (("ll", 0, 0), ("lr", 1, 0), ("ul", 0, 1), ("ur", 1, 1)):
        mesh.add_cell_group(name, lambda x, xs=xs, ys=ys: (x[:, 1] > 0)
                            & ((x[:, 0] > 1) == bool(xs))
                            & ((x[:, 1] > 1) == bool(ys)))  # fmt: skip
    mesh.add_facet_group("base", lambda x: np.abs(x[:, 1]) < 1e-9, boundary_only=False)
    mesh.add_facet_group("lift", lambda x: np.abs(x[:, 1] - 1) < 1e-9, boundary_only=False)
    mesh.add_facet_group("cj", lambda x: (np.abs(x[:, 0] - 1) < 1e-9) & (x[:, 1] > 0),
                         boundary_only=False)  # fmt: skip
    mat = pf.Elastic(30e9, 0.2, 2400.0)
    weak = pf.Joint(phi=20.0)
    model = pf.Model(mesh, [pf.Block(b, mat) for b in ("rock", "ll", "lr", "ul", "ur")],
                     interfaces=[pf.Interface("base", pf.Joint(phi=45.0, c=1e6, tensile=1e6,
                                                                initial="intact")),
                                 pf.Interface("lift", weak), pf.Interface("cj", weak)])  # fmt: skip
    model.fix("rock")
    model.add_gravity()
    return model


def _rows(path: Path) -> list[dict[str, str]]:
    with path.open(newline="", encoding="utf-8") as fh:
        return list(csv.DictReader(fh))


def test_joint_pieces_in_the_csv_and_the_report(tmp_path: Path) -> None:
    """The summary gave each piece of a joint in pieces (a 3D dam engineer's finding of
    the last session), the CSV export and the report's joint table did not. Now
    pairs_final.csv names the blocks of every pair, joint_pieces.csv gives each piece's
    histories, and the report's table a row per piece; each agrees with summary.json."""
    from pfeie.cli import main
    from pfeie.plot import joint_table

    model = _monoliths()
    gm = pf.GroundMotion.from_function(lambda t: 0.6 * G * np.sin(2 * np.pi * 4 * t), 0.25, 1e-3)
    out = tmp_path / "out"
    pf.run_to_folder(pf.Dynamic(model, 2e-3), 0.25, out, ground=[gm],
                     start=pf.solve_static(model), figures=False, paraview=False)  # fmt: skip
    s = json.loads((out / "summary.json").read_text())
    assert main(["export", str(out / "results.h5"), "--csv", str(tmp_path / "csv")]) == 0
    final = _rows(tmp_path / "csv" / "pairs_final.csv")
    pieces = _rows(tmp_path / "csv" / "joint_pieces.csv")
    for joint in ("cj", "lift", "base"):
        want = s["joints"][joint]["pieces"]
        mine = [r for r in final if r["joint"] == joint]
        assert {r["blocks"] for r in mine} == set(want)
        for label, q in want.items():
            assert sum(r["blocks"] == label for r in mine) == q["pairs"]
            rows = [r for r in pieces if r["joint"] == joint and r["blocks"] == label]
            opening = [float(r["value"]) for r in rows if r["quantity"] == "opening_max"]
            slip = [float(r["value"]) for r in rows if r["quantity"] == "slip_max"]
            assert len(opening) == len(slip) == 1 + round(0.25 / 2e-3)  # every step, t = 0 too
            # 9 significant digits in the CSV
            assert max(opening) == pytest.approx(q["max_opening_m"], rel=1e-8, abs=1e-15)
            assert slip[-1] == pytest.approx(q["residual_slip_max_m"], rel=1e-8, abs=1e-15)
    with Results(out / "results.h5") as res:
        table = joint_table(res)
    by_name = {r["joint"]: r for r in table}
    q = s["joints"]["cj"]["pieces"]["ul | ur"]
    row = by_name["cj: ul | ur"]
    assert row["pairs"] == q["pairs"]
    assert row["largest opening (mm)"] == pytest.approx(1e3 * q["max_opening_m"], rel=1e-12)
    # the joints first, in their order, then the pieces
    assert [r["joint"] for r in table[:3]] == ["base", "lift", "cj"]
    assert "min safety factor" in by_name["cj"] and "min safety factor" not in row


def test_joint_pieces_in_the_static_export(tmp_path: Path) -> None:
    """The static state: pairs_static.csv names the blocks of each pair, and the static
    joint table has a row per piece whose pairs add up to the joint's."""
    from pfeie.io._export import _export_static
    from pfeie.plot import static_joint_table

    model = _monoliths()
    gm = pf.GroundMotion.from_function(lambda t: 0.0 * t, 0.01, 1e-3)
    out = tmp_path / "out"
    pf.run_to_folder(pf.Dynamic(model, 2e-3), 0.004, out, ground=[gm],
                     start=pf.solve_static(model), figures=False, paraview=False)  # fmt: skip
    with Results(out / "results.h5") as res:
        _export_static(res, tmp_path / "csv")
        table = static_joint_table(res)
    rows = _rows(tmp_path / "csv" / "pairs_static.csv")
    cj = [r for r in rows if r["joint"] == "cj"]
    assert {r["blocks"] for r in cj} == {"ll | lr", "ul | ur"}
    whole = next(r for r in table if r["joint"] == "cj")
    parts = [r for r in table if r["joint"].startswith("cj: ")]
    assert sum(r["pairs"] for r in parts) == whole["pairs"] == len(cj)
    assert [r["joint"] for r in table[:3]] == ["base", "lift", "cj"]
