"""Readers: ground-motion records (AT2, two columns, one column) and gmsh meshes, on real
files and on malformed ones; every error names the file and, where it applies, the line."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import pfeie as pf
from pfeie.errors import MeshError, RecordError
from pfeie.io import read_mesh, read_record, write_at2

ROOT = Path(__file__).resolve().parents[1]
ELCENTRO = ROOT / "examples" / "data" / "elcentro_1940_ns_chopra.csv"
DATA = Path(__file__).resolve().parent / "data"
G = 9.81


def _elcentro() -> np.ndarray:
    return np.loadtxt(ELCENTRO, delimiter=",", skiprows=1)


def test_two_column_csv_with_header_is_el_centro() -> None:
    """Chopra's digitisation: 1560 samples at 0.02 s, PGA 0.31882 g at 2.02–2.04 s."""
    gm = read_record(ELCENTRO, units="g")
    assert gm.time.size == 1560 and gm.time[1] == pytest.approx(0.02)
    assert gm.pga / G == pytest.approx(0.31882, abs=1e-5)
    assert "PGA 0.319 g" in gm.summary() and "dt 0.02 s" in gm.summary()


def test_at2_round_trip_and_header_variants(tmp_path: Path) -> None:
    """El Centro written as a PEER AT2 file reads back to 1e-7 g, in both header styles
    (NGA-West1 'NPTS=, DT=' and NGA-West2 '<npts> <dt> NPTS, DT')."""
    data = _elcentro()
    p = tmp_path / "elcentro.AT2"
    write_at2(p, data[:, 1], 0.02, "IMPERIAL VALLEY 5/19/40, EL CENTRO, 180")
    gm = read_record(p)
    np.testing.assert_allclose(gm.acceleration / G, data[:, 1], atol=1e-7)
    assert gm.name.startswith("IMPERIAL VALLEY")
    lines = p.read_text().splitlines()
    lines[3] = "  1560    0.0200    NPTS, DT"
    p2 = tmp_path / "west2.at2"
    p2.write_text("\n".join(lines) + "\n")
    assert read_record(p2).time[-1] == pytest.approx(1559 * 0.02)


@pytest.mark.parametrize(("value", "unit"), [("0.005", "SEC"), ("0.005", ""), ("5.000", "MSEC"),
                                            ("0.005", "S")])  # fmt: skip
def test_at2_dt_unit(tmp_path: Path, value: str, unit: str) -> None:
    """DT's unit after its value: SEC (or none) is seconds, MSEC milliseconds (a header
    'DT= 5.000 MSEC' had been read as a 5 s step: a 2 h record, without a word)."""
    p = tmp_path / "r.at2"
    p.write_text("PEER\nT\nACCELERATION TIME SERIES IN UNITS OF G\n"
                 f"NPTS=    3, DT=   {value} {unit}\n0.1 0.2 0.1\n")  # fmt: skip
    assert read_record(p).time[1] == pytest.approx(0.005, rel=1e-12)


def test_at2_dt_unknown_unit(tmp_path: Path) -> None:
    p = tmp_path / "r.at2"
    p.write_text("PEER\nT\nACCELERATION TIME SERIES IN UNITS OF G\n"
                 "NPTS=    3, DT=   0.5 MIN\n0.1 0.2 0.1\n")  # fmt: skip
    with pytest.raises(RecordError, match="line 4: DT: the unit 'MIN'"):
        read_record(p)


def test_at2_fused_numbers(tmp_path: Path) -> None:
    p = tmp_path / "fused.at2"
    p.write_text("PEER\nT\nACCELERATION TIME SERIES IN UNITS OF G\nNPTS=    4, DT=   .0100 SEC\n"
                 "  .1234E-01-.5678E-02\n1.5-2.5\n")  # fmt: skip
    np.testing.assert_allclose(read_record(p).acceleration / G, [0.01234, -0.005678, 1.5, -2.5])


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("PEER\nT\nACCELERATION TIME SERIES IN UNITS OF G\nNPTS=    5, DT=   .0100 SEC\n"
         "1 2 3\n4\n", "NPTS = 5 but the file has 4"),
        ("PEER\nT\nACCELERATION TIME SERIES IN UNITS OF MG\nNPTS=    2, DT=   .0100 SEC\n"
         "1 2\n", "line 3: expected the units"),
        ("PEER\nT\nACCELERATION TIME SERIES IN UNITS OF G\nNPTS=    2, DT=   .0100 SEC\n"
         "1 x2\n", "line 5: non-numeric"),
        ("PEER\nT\nACCELERATION TIME SERIES IN UNITS OF G\nPOINTS 2\n1 2\n", "line 4: expected"),
        ("PEER\nT\n", "needs 4 header lines"),
    ],
)  # fmt: skip
def test_at2_malformed(tmp_path: Path, text: str, match: str) -> None:
    p = tmp_path / "bad.at2"
    p.write_text(text)
    with pytest.raises(RecordError, match=match) as err:
        read_record(p)
    assert str(p) in str(err.value)


def test_at2_units_conflict(tmp_path: Path) -> None:
    p = tmp_path / "r.at2"
    write_at2(p, np.array([0.1, 0.2]), 0.01)
    with pytest.raises(RecordError, match="line 3 states the units g"):
        read_record(p, units="m/s2")


def test_two_column_whitespace_no_header_and_units(tmp_path: Path) -> None:
    p = tmp_path / "r.txt"
    p.write_text("0.0 0.0\n0.005\t1.5\n0.010   -3.0\n")
    gm = read_record(p, units="cm/s2", scale=2.0)
    np.testing.assert_allclose(gm.acceleration, [0.0, 0.03, -0.06])


def test_one_column_needs_dt(tmp_path: Path) -> None:
    p = tmp_path / "r.txt"
    p.write_text("acc\n0.0\n0.1\n-0.1\n")
    with pytest.raises(RecordError, match="needs its time step dt"):
        read_record(p, units="g")
    gm = read_record(p, units="g", dt=0.01)
    assert gm.time[-1] == pytest.approx(0.02) and gm.pga == pytest.approx(0.981)


def test_a_blank_separated_table_is_not_one_column(tmp_path: Path) -> None:
    """Time, acceleration and velocity separated by blanks (a new user's pulse): with or
    without dt it is refused as a table (given dt it was read as one interleaved series,
    PGA 5 m/s² at 15 s of a 5 s record); accelerations wrapped five a line (as AT2 data)
    stay one column."""
    t = np.arange(0.0, 1.0, 0.01)
    p = tmp_path / "r.txt"
    p.write_text("".join(f"{x:.6f} {np.sin(x):.6f} {np.cos(x):.6f}\n" for x in t))
    for dt in (None, 0.01):
        with pytest.raises(RecordError, match=r"line 1: 3 numbers a line .* step on like "
                           r"times \(0, 0\.01, 0\.02, \.\.\.\): a table of time and 2 column\(s\)"):
            read_record(p, units="m/s2", dt=dt)
    a = np.sin(7.0 * t)
    q = tmp_path / "w.txt"
    q.write_text("".join(" ".join(f"{x:.6f}" for x in a[i : i + 5]) + "\n"
                         for i in range(0, a.size, 5)))  # fmt: skip
    gm = read_record(q, units="m/s2", dt=0.01)
    np.testing.assert_allclose(gm.acceleration, np.round(a, 6))


@pytest.mark.parametrize(
    ("text", "kw", "match"),
    [
        ("t,a\n0,0\n0.01,0.1\n", {}, "give the units"),
        ("t,a\n0,0\n0.01,0.1\n0.01,0.2\n", {"units": "g"}, "line 4: times must increase"),
        ("t,a\n0,0\n0.01,0.1,3\n", {"units": "g"}, "line 3: expected 2 columns"),
        ("t,a\n0,0\n0.01,abc\n", {"units": "g"}, "line 3: non-numeric"),
        ("", {"units": "g"}, "no numeric data"),
    ],
)  # fmt: skip
def test_column_records_malformed(tmp_path: Path, text: str, kw: dict, match: str) -> None:  # type: ignore[type-arg]
    p = tmp_path / "r.csv"
    p.write_text(text)
    with pytest.raises(RecordError, match=match):
        read_record(p, **kw)


@pytest.mark.parametrize(("header", "units", "named"), [
    ("time,acc (g)", "m/s2", "g"), ("t [s], a [m/s2]", "g", "m/s2"),
    ("Time(s) Acc(cm/s²)", "g", "cm/s2"), ("time, accel in g", "cm/s2", "g"),
    ("time,acc (g)", "g", None), ("time,acc", "m/s2", None), ("acc (gal)", "gal", None),
    ("t, a (m/s^2)", "m/s^2", None), ("a (cm/s2)", "gal", None),
])  # fmt: skip
def test_header_units_that_contradict_the_given_ones_are_warned(
    tmp_path: Path, caplog: pytest.LogCaptureFixture, header: str, units: str,
    named: str | None,
) -> None:  # fmt: skip
    """A header naming other units than those given (a record in g read as m/s² is 9.81
    times too weak) gets a warning naming the file, the line and both units."""
    p = tmp_path / "rec.csv"
    p.write_text(f"{header}\n0,0\n0.01,0.1\n0.02,-0.2\n")
    with caplog.at_level("WARNING"):
        read_record(p, units=units)
    if named is None:
        assert "check the units" not in caplog.text
    else:
        assert (f"rec.csv: line 1: the header {header!r} names the units {named} but the "
                f"record is read in {units}") in caplog.text  # fmt: skip


def test_a_jump_in_the_time_column_is_warned(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    """A two-column record with a gap in its times (El Centro with 1 s of samples cut out
    between 5 and 6 s: one step of 1.02 s among steps of 0.02 s) gets a warning naming the
    file, the line after the gap and its length; the record itself reads as written.
    El Centro as it is gets none."""
    data = _elcentro()
    cut = data[(data[:, 0] <= 5.0 + 1e-9) | (data[:, 0] >= 6.02 - 1e-9)]
    p = tmp_path / "gap.csv"
    np.savetxt(p, cut, delimiter=",", header="time,acc", comments="")
    with caplog.at_level("WARNING"):
        gm = read_record(p, units="g")
    assert gm.time.size == cut.shape[0]
    line = 2 + int(np.flatnonzero(cut[:, 0] > 5.0 + 1e-9)[0])  # the header is line 1
    assert (f"gap.csv: the time step jumps beyond 2.5 × its median of 0.02 s at 1 place(s) "
            f"(line {line}: 1.02 s after t = 5 s)") in caplog.text, caplog.text
    caplog.clear()
    with caplog.at_level("WARNING"):
        read_record(ELCENTRO, units="g")
    assert "time step jumps" not in caplog.text


def test_missing_record_file(tmp_path: Path) -> None:
    with pytest.raises(RecordError, match="not found"):
        read_record(tmp_path / "none.at2")


def test_baseline_correction_zeroes_final_velocity() -> None:
    gm = read_record(ELCENTRO, units="g", baseline=True)
    assert abs(gm.motion(gm.time[-1])[1]) < 1e-12


@pytest.mark.parametrize("name", ["two_blocks_v41.msh", "two_blocks_v22.msh"])
def test_gmsh_reader_groups(name: str) -> None:
    """Both MSH versions give the same groups: blocks (surfaces) and faces (curves)."""
    mesh = read_mesh(DATA / name)
    assert mesh.dim == 2
    assert set(mesh.cell_groups) == {"rock", "dam"}
    assert set(mesh.facet_groups) == {"joint", "bottom"}
    joint = mesh.group_nodes("joint")
    np.testing.assert_allclose(mesh.points[joint, 1], 1.0)
    model = pf.Model(mesh, [pf.Block("rock", pf.Elastic(1e9, 0.2, 1.0)),
                            pf.Block("dam", pf.Elastic(1e9, 0.2, 1.0))])  # fmt: skip
    assert model.total_mass() == pytest.approx(4.0)  # area 2 × 2 m², ρ = 1


def test_gmsh_reader_errors(tmp_path: Path) -> None:
    with pytest.raises(MeshError, match="not found"):
        read_mesh(tmp_path / "none.msh")
    bad = tmp_path / "bad.msh"
    bad.write_text("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\ngarbage\n")
    with pytest.raises(MeshError, match="cannot read"):
        read_mesh(bad)


def test_non_conforming_interface_is_located() -> None:
    """Two blocks meshed apart (nodes duplicated at y = 1): the interface is not shared by
    two cells, and the error says where."""
    lower = pf.rectangle(2.0, 1.0, 2, 1)
    upper = pf.rectangle(2.0, 1.0, 3, 1)
    upper.points[:, 1] += 1.0
    n = lower.n_points
    pts = np.vstack([lower.points, upper.points])
    cells = {"quad": np.vstack([lower.cells["quad"], upper.cells["quad"] + n])}
    groups = {"lower": {"quad": np.arange(2)}, "upper": {"quad": np.arange(2, 5)}}
    mesh = pf.Mesh(pts, cells, groups,
                   {"joint": {"line": lower.facet_groups["ymax"]["line"]}})  # fmt: skip
    mat = pf.Elastic(1e9, 0.2, 1000.0)
    with pytest.raises(pf.ModelError, match=r"interface 'joint'.*at \[") as err:
        pf.Model(mesh, [pf.Block("lower", mat), pf.Block("upper", mat)],
                 interfaces=[pf.Interface("joint", pf.Joint())])  # fmt: skip
    assert "only one cell" in str(err.value)
