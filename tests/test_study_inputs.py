"""Studies: the ladder's levels over a resumed folder, record names, wrong study inputs,
SIGTERM, and the documented columns.

References: ``level`` is the index of the intensity in the current ladder
(docs/study.md), checked against the ladder itself; a row reused from an earlier ladder
is the same computation, so it must equal, bit for bit, the row of a fresh study in
another folder; the medians printed per level are recomputed here with ``np.median``
from the table; a study stopped by SIGTERM and started again gives the table of an
uninterrupted study, bit for bit; the columns of a 2D and a 3D table are each listed in
docs/study.md.
"""

from __future__ import annotations

import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from pfeie.cli import main
from pfeie.errors import InputError, ModelError
from pfeie.study import RecordSource, Study, StudyTable
from pfeie.study._study import JOINT_KEYS, record_names
from test_robustness import msh22
from test_study import MODEL, STUDY, same, setup

DOCS = Path(__file__).resolve().parents[1] / "docs"


def _one_second(text: str) -> str:
    """The study with runs of 1 s (short tests)."""
    return text + "[analysis]\nduration = 1.0\n"


def _err(capsys: pytest.CaptureFixture[str]) -> str:
    err = capsys.readouterr().err
    assert "Traceback" not in err, err
    return err


def test_levels_follow_the_current_ladder(tmp_path: Path,
                                          capsys: pytest.CaptureFixture[str]) -> None:  # fmt: skip
    """A folder run with the ladder [0.2, 0.5], then with [0.1, 0.2, 0.5]: the kept rows
    are reused (their files untouched) and numbered from the new ladder (levels 0, 1, 2
    per record); the table equals a fresh study of the new ladder bit for bit; the
    printed medians are one line per level, each the median of the table's rows there."""
    p = setup(tmp_path, _one_second(STUDY), n=2)
    assert main(["study", str(p), "--quiet"]) == 0
    rows = tmp_path / "study" / "rows"
    stamp = {f.name: f.stat().st_mtime_ns for f in rows.iterdir()}
    p.write_text(_one_second(STUDY.replace("[0.2, 0.5]", "[0.1, 0.2, 0.5]")))
    capsys.readouterr()
    assert main(["study", str(p), "--quiet"]) == 0
    out = capsys.readouterr().out
    assert {f.name: f.stat().st_mtime_ns for f in rows.iterdir() if f.name in stamp} == stamp
    table = StudyTable.read(tmp_path / "study" / "table.csv")
    ladder = [0.1, 0.2, 0.5]
    assert table.column("level").tolist() == [0, 1, 2] * 2
    assert table.column("intensity").tolist() == ladder * 2
    np.testing.assert_allclose(table.column("im.pga_g"), ladder * 2, rtol=1e-14)
    fresh = Study.from_file(p)
    fresh.folder = tmp_path / "fresh"
    same(fresh.run(), table)
    lines = out.splitlines()
    head = lines.index("median over the records:")
    body = [ln.split() for ln in lines[head + 2 : head + 5]]
    col = table.column("probe.top.peak_displacement_m")
    for k, cells in enumerate(body):
        assert int(cells[0]) == k and float(cells[1]) == ladder[k]
        assert float(cells[2]) == pytest.approx(np.median(col[k::3]), rel=5e-4)  # 4 digits
    assert "median" not in "".join(lines[head + 5 : head + 6])


def test_a_resumed_row_takes_its_level_in_python(tmp_path: Path) -> None:
    """The same through the Python API: a row kept from a ladder where it was level 0
    is level 1 of a ladder with a smaller value before it."""
    p = setup(tmp_path, _one_second(STUDY.replace("[0.2, 0.5]", "[0.2]")), n=1)
    assert Study.from_file(p).run().column("level").tolist() == [0]
    p.write_text(_one_second(STUDY.replace("[0.2, 0.5]", "[0.15, 0.2]")))
    seen: list[object] = []
    t = Study.from_file(p).run(progress=lambda d, n, row: seen.append(row["intensity"]))
    assert seen == [0.15]  # only the new value runs
    assert t.column("level").tolist() == [0, 1] and t.column("intensity").tolist() == [0.15, 0.2]


@pytest.mark.parametrize("edit, words", [
    ("values = [0.2, 0.5]\n", ["intensity.values[2]", "0.2 is already intensity.values[0]",
                               "distinct"]),
    ('measure = "pga"', ["intensity.values[1]", "expected a number in (0, 20] g",
                         "measure 'pga'", "found 500"]),
    ('measure = "sa"', ["intensity.values[1]", "(0, 20] g", "measure 'sa'", "found 500"]),
])  # fmt: skip
def test_bad_ladders(tmp_path: Path, capsys: pytest.CaptureFixture[str], edit: str,
                     words: list[str]) -> None:  # fmt: skip
    """A value twice in the ladder; a PGA or Sa beyond the model file's 20 g."""
    text = {
        "values = [0.2, 0.5]\n": STUDY.replace("[0.2, 0.5]", "[0.2, 0.5, 0.2]"),
        'measure = "pga"': STUDY.replace("[0.2, 0.5]", "[0.2, 500]"),
        'measure = "sa"': STUDY.replace("[0.2, 0.5]", "[0.2, 500]").replace('"pga"', '"sa"'),
    }[edit]
    p = setup(tmp_path, text, n=1)
    assert main(["study", str(p)]) == 2
    err = _err(capsys)
    assert err.startswith(f"pfeie: error: {p}: ")
    for w in words:
        assert w in err, err
    assert not (tmp_path / "study").exists()  # refused before any work


def test_ladder_checks_in_python(tmp_path: Path) -> None:
    """The Python API refuses the same ladders, naming the key; a scale ladder has no
    upper bound (a factor), but must be finite."""
    rec = [tmp_path / "r.csv"]
    with pytest.raises(ModelError, match=r"intensity\.values\[1\]: 0\.1 is already"):
        Study(tmp_path / "m.toml", rec, measure="pga", values=[0.1, 0.1])
    with pytest.raises(ModelError, match=r"intensity\.values\[0\]: expected a number in"):
        Study(tmp_path / "m.toml", rec, measure="pga", values=[20.5])
    assert Study(tmp_path / "m.toml", rec, measure="pga", values=[20.0]).values == [20.0]
    assert Study(tmp_path / "m.toml", rec, values=[500.0]).values == [500.0]
    with pytest.raises(ModelError, match="a finite number > 0"):
        Study(tmp_path / "m.toml", rec, values=[float("nan")])


def test_the_same_record_twice_is_refused(tmp_path: Path,
                                          capsys: pytest.CaptureFixture[str]) -> None:  # fmt: skip
    """A folder of records and one of its files again: both entries are named."""
    p = setup(tmp_path, STUDY + '[[records]]\nfile = "rec/r1.csv"\nunits = "g"\n', n=2)
    assert main(["study", str(p)]) == 2
    err = _err(capsys)
    for w in (f"{p}: ", "records[0].folder", "records[1].file", "r1.csv", "once"):
        assert w in err, err
    with pytest.raises(ModelError, match="same file"):
        again = RecordSource("x", tmp_path / "rec" / ".." / "rec" / "r0.csv")
        Study(tmp_path / "model.toml", [tmp_path / "rec" / "r0.csv", again])


def test_a_missing_model_names_the_study_file(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A study whose model file is missing: the error names the study file, the key and
    the path it looked for (it named the path alone)."""
    p = setup(tmp_path, STUDY.replace('model = "model.toml"', 'model = "nomodel.toml"'), n=2)
    assert main(["study", str(p)]) == 2
    err = _err(capsys)
    assert f"{p}: model: {tmp_path / 'nomodel.toml'}: model file not found" in err, err


def test_records_sharing_a_stem_get_stable_names(tmp_path: Path) -> None:
    """Two different files named r0.csv (in rec/ and other/): each is named by its path,
    in either order of the entries; both appear in the table, with their own demands."""
    extra = '[[records]]\nfile = "other/r0.csv"\nunits = "g"\n'
    p = setup(tmp_path, _one_second(STUDY.replace("[0.2, 0.5]", "[0.5]")) + extra, n=2)
    (tmp_path / "other").mkdir()
    t = np.arange(0.0, 2.0, 0.01)
    np.savetxt(tmp_path / "other" / "r0.csv", np.c_[t, np.sin(9 * t) * 0.3], delimiter=",")
    st = Study.from_file(p)
    assert [r.name for r in st.records] == ["rec/r0.csv", "r1", "other/r0.csv"]
    text = p.read_text()
    q = tmp_path / "swapped.toml"  # the same records, the other order of the entries
    q.write_text(text.replace(extra, "").replace("[[records]]", extra + "[[records]]", 1))
    swapped = {r.name: r.path.resolve() for r in Study.from_file(q).records}
    assert swapped == {r.name: r.path.resolve() for r in st.records}
    table = st.run()
    assert table.column("record").tolist() == ["rec/r0.csv", "r1", "other/r0.csv"]
    disp = table.column("probe.top.peak_displacement_m")
    assert disp[0] != disp[2]  # two records, two runs
    assert record_names([Path("a/r1.csv"), Path("a/r1.AT2")], Path(".")) == [
        "a/r1.csv", "a/r1.AT2"]  # fmt: skip


@pytest.mark.parametrize("folder, words", [
    ("afile", ["is a file, not a folder"]),
    ("afile/study", ["cannot create the output folder"]),
    ("/proc/pfeie-study", ["cannot create the output folder"]),
])  # fmt: skip
def test_unusable_output_folder(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                folder: str, words: list[str]) -> None:  # fmt: skip
    """An output folder that is a file, under a file, or where no folder can be made:
    exit 2 with the study file and ``output.folder``, before any run."""
    if folder.startswith("/proc") and not Path("/proc/self").exists():
        pytest.skip("no /proc here")
    p = setup(tmp_path, STUDY.replace('folder = "study"', f'folder = "{folder}"'), n=1)
    (tmp_path / "afile").write_text("x")
    assert main(["study", str(p)]) == 2
    err = _err(capsys)
    assert err.startswith(f"pfeie: error: {p}: output.folder: "), err
    for w in words:
        assert w in err, err
    with pytest.raises(InputError, match=r"output\.folder"):
        Study.from_file(p).run()


LS = '\n[[limit_states]]\nname = "x"\ndemand = "{demand}"\nthreshold = {threshold}\n{more}'


@pytest.mark.parametrize("demand, threshold, more, words", [
    ("joint.joint.max_opening_m", -1, "", ["limit_states[0].threshold",
                                           "expected a number > 0", "found -1"]),
    ("joint.joint.min_safety_factor", 0.0, 'exceed = "below"', ["limit_states[0].threshold",
                                                                "short of"]),
    ("joint.nope.max_opening_m", 0.001, "", ["limit_states[0].demand",
                                             "'joint.nope.max_opening_m'",
                                             "did you mean 'joint.joint.max_opening_m'"]),
    ("joint.joint.cracked_area_m2", 0.1, "", ["limit_states[0].demand",  # 3D only
                                              "did you mean 'joint.joint.cracked_length_m'"]),
])  # fmt: skip
def test_bad_limit_states(tmp_path: Path, capsys: pytest.CaptureFixture[str], demand: str,
                          threshold: float, more: str, words: list[str]) -> None:  # fmt: skip
    """A threshold <= 0 on a magnitude, a misspelt demand, a 3D column in a 2D model: exit
    2 with the study file and the key, before any run."""
    p = setup(tmp_path, STUDY + LS.format(demand=demand, threshold=threshold, more=more), n=1)
    assert main(["study", str(p)]) == 2
    err = _err(capsys)
    assert err.startswith(f"pfeie: error: {p}: limit_states[0]."), err
    for w in words:
        assert w in err, err
    assert not (tmp_path / "study" / "rows").is_dir() or not any(
        (tmp_path / "study" / "rows").iterdir()
    )


def test_a_signed_demand_takes_a_negative_threshold(tmp_path: Path) -> None:
    """The minimum principal stress is signed (compression < 0): a threshold of -1 kPa
    "below" is accepted and fitted like any other."""
    text = _one_second(STUDY.replace("[0.2, 0.5]", "[0.2, 0.35, 0.5]")) + LS.format(
        demand="stress.min_principal_Pa", threshold=-1e3, more='exceed = "below"')  # fmt: skip
    p = setup(tmp_path, text, n=2)
    st = Study.from_file(p)
    assert st.limit_states[0]["threshold"] == -1e3
    table = st.run()
    assert (table.column("stress.min_principal_Pa") < 0).all()
    assert (tmp_path / "study" / "fragility.csv").is_file()


def test_sigterm_keeps_the_rows_and_resumes(tmp_path: Path) -> None:
    """SIGTERM to `pfeie study` after its first row: exit 130, the message, the rows kept;
    the same command then finishes to the table of an uninterrupted study."""
    p = setup(tmp_path, n=2)
    ref = Study.from_file(p)
    ref.folder = tmp_path / "ref"
    want = ref.run()
    proc = subprocess.Popen([sys.executable, "-m", "pfeie", "study", str(p), "--quiet"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)  # fmt: skip
    rows = tmp_path / "study" / "rows"
    t0 = time.monotonic()
    while not (rows.is_dir() and any(rows.glob("*.json"))):
        assert proc.poll() is None and time.monotonic() - t0 < 60
        time.sleep(0.01)
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130, err
    assert "pfeie: interrupted (SIGTERM); the runs finished so far are kept" in err
    assert "Traceback" not in err
    done = len(list(rows.glob("*.json")))
    assert 1 <= done < 4 and not (tmp_path / "study" / "table.csv").exists()
    seen: list[int] = []
    got = Study.from_file(p).run(progress=lambda d, n, r: seen.append(d))
    assert seen == list(range(done + 1, 5))
    same(want, got)


def _documented() -> set[str]:
    """The column names of docs/study.md's table of columns (``<name>`` kept)."""
    text = (DOCS / "study.md").read_text()
    part = text[text.index("| column | meaning |") :]
    part = part[: part.index("\n\n")]
    return {c for c in re.findall(r"`([^`]+)`", part) if "." in c or c.isidentifier()}


def _generic(column: str) -> str:
    return re.sub(r"^(probe|joint)\.[^.]+\.", r"\1.<name>.", column)


def test_2d_table_columns_are_documented(tmp_path: Path) -> None:
    """Every column of a 2D study (with tensile strengths: the demand-capacity columns)
    is in docs/study.md's table; and every joint column that a row can have."""
    text = MODEL.replace("rho = 2000.0", "rho = 2000.0\ntensile_strength = 1e5")
    p = setup(tmp_path, _one_second(STUDY.replace("[0.2, 0.5]", "[0.5]")), n=1)
    (tmp_path / "model.toml").write_text(text)
    cols = {_generic(c) for c in Study.from_file(p).run().columns}
    assert {"joint.<name>.max_open_length_m", "stress.max_dcr"} <= cols
    docs = _documented()
    assert cols - docs == set()
    assert {f"joint.<name>.{k}" for k in JOINT_KEYS} - docs == set()


# a 1 m cube on a 1 m cube (hexahedra), a frictional joint between them
NODES_3D = [(x, y, z) for z in (0, 1, 2) for y in (0, 1) for x in (0, 1)]
NAMES_3D = {1: (3, "base"), 2: (3, "block"), 3: (2, "bottom"), 4: (2, "joint")}
ELEMENTS_3D = [(1, 3, 3, [1, 2, 4, 3]), (2, 3, 4, [5, 6, 8, 7]),
               (10, 5, 1, [1, 2, 4, 3, 5, 6, 8, 7]),
               (11, 5, 2, [5, 6, 8, 7, 9, 10, 12, 11])]  # fmt: skip


def test_3d_table_columns_are_documented(tmp_path: Path) -> None:
    """Every column of a 3D study (the joint areas: cracked_area_m2, max_open_area_m2)
    is in docs/study.md's table."""
    p = setup(tmp_path, _one_second(STUDY.replace("[0.2, 0.5]", "[0.3]")), n=1)
    msh22(tmp_path / "blocks.msh", NODES_3D, ELEMENTS_3D, NAMES_3D)
    (tmp_path / "model.toml").write_text(MODEL.replace("top = [1.0, 2.0]", "top = [0.5, 0.5, 2.0]"))
    cols = {_generic(c) for c in Study.from_file(p).run().columns}
    assert {"joint.<name>.cracked_area_m2", "joint.<name>.max_open_area_m2"} <= cols
    assert cols - _documented() == set()


def test_a_record_warning_is_given_once(tmp_path: Path, caplog: pytest.LogCaptureFixture) -> None:
    """A record whose header names other units than the study's (``t, a (m/s2)`` read in
    g) is warned once, when the study reads it to plan the runs, not again by each of its
    runs (two intensities: it was printed by every run too)."""
    p = setup(tmp_path, _one_second(STUDY), n=1)
    rec = tmp_path / "rec" / "r0.csv"
    rec.write_text("t, a (m/s2)\n" + rec.read_text())
    with caplog.at_level("WARNING"):
        Study.from_file(p).run()
    said = [r for r in caplog.records if "names the units m/s2" in r.getMessage()]
    assert len(said) == 1, [r.getMessage() for r in said]


def test_the_model_files_own_records_are_not_read(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    """A study brings its records: the model file's ``[[ground_motion]]`` is not read (a
    new user's model named a record file that no longer existed, and the study stopped on
    it), and the study's record sampled finer than the step gets the model file's
    warning, naming the study file and the record (it named the model's unused record)."""
    import logging

    p = setup(tmp_path, _one_second(STUDY), n=1)
    model = tmp_path / "model.toml"
    model.write_text(MODEL + '[[ground_motion]]\nfile = "gone.csv"\nunits = "g"\n')
    t = np.arange(0.0, 2.0, 0.005)
    np.savetxt(tmp_path / "rec" / "r0.csv", np.c_[t, 0.3 * np.sin(9.0 * t)], delimiter=",")
    with caplog.at_level(logging.WARNING, logger="pfeie"):
        runs = Study.from_file(p).runs()
    assert len(runs) == 2
    said = [r.getMessage() for r in caplog.records if "coarser" in r.getMessage()]
    assert said == [f"{p}: records[0]: r0: analysis.dt = 0.01 s is coarser than the "
                    "record's sampling (0.005 s): the record is read at the steps, and its "
                    "content above 50 Hz is not applied"]  # fmt: skip
