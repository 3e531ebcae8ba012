"""Studies: one model under many records and intensities.

References: a study's row equals a separate ``pfeie run`` of the model with that record
scaled the same way (an independent run: a new process, a new factorisation) to 1e-12
relative (the Dask paths, which give the serial table bit for bit, are in
test_study_workers.py); a study killed (SIGKILL) and started again gives the same table.
"""

from __future__ import annotations

import json
import math
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from pfeie.cli import main
from pfeie.errors import InputError, ModelError, RecordError
from pfeie.study import RecordSource, Study, StudyTable
from test_robustness import msh22

# two 2 m x 1 m rows of two quadrilaterals: a fixed base and a block on a frictional joint
NODES = [(x, y, 0) for y in (0, 1, 2) for x in (0, 1, 2)]
NAMES = {1: (2, "base"), 2: (2, "block"), 3: (1, "bottom"), 4: (1, "joint")}
ELEMENTS = [(1, 1, 3, [1, 2]), (2, 1, 3, [2, 3]), (3, 1, 4, [4, 5]), (4, 1, 4, [5, 6]),
            (10, 3, 1, [1, 2, 5, 4]), (11, 3, 1, [2, 3, 6, 5]),
            (12, 3, 2, [4, 5, 8, 7]), (13, 3, 2, [5, 6, 9, 8])]  # fmt: skip

MODEL = """
[mesh]
file = "blocks.msh"
[materials.rock]
E = 1e9
nu = 0.25
rho = 2000.0
[blocks]
base = "rock"
block = "rock"
[interfaces.joint]
friction_angle = 20.0
cohesion = 2000.0
tensile_strength = 1000.0
initial = "intact"
[[supports]]
group = "base"
[loads]
gravity = 9.81
[analysis]
dt = 0.01
[output]
folder = "out"
probes = { top = [1.0, 2.0] }
"""

STUDY = """
title = "three records at two intensities"
model = "model.toml"
[run]
workers = 0   # in this process: the tests of the local cluster remove this line
[[records]]
folder = "rec"
pattern = "*.csv"
units = "g"
[intensity]
measure = "pga"
values = [0.2, 0.5]
[output]
folder = "study"
"""


def setup(tmp: Path, study: str = STUDY, n: int = 3, seconds: float = 2.0) -> Path:
    """The model, ``n`` decaying sine records (two-column, g) and the study file."""
    msh22(tmp / "blocks.msh", NODES, ELEMENTS, NAMES)
    (tmp / "model.toml").write_text(MODEL)
    (tmp / "rec").mkdir(exist_ok=True)
    t = np.arange(0.0, seconds, 0.01)
    for k in range(n):
        a = np.sin(2 * np.pi * (1.5 + k) * t) * np.exp(-t) * (0.5 + 0.2 * k)
        np.savetxt(tmp / "rec" / f"r{k}.csv", np.c_[t, a], delimiter=",")
    p = tmp / "study.toml"
    p.write_text(study)
    return p


def same(a: StudyTable, b: StudyTable) -> None:
    """Tables equal bit for bit, but for the wall time and the file column's spelling."""
    assert a.columns == b.columns
    for c in a.columns:
        if c in ("wall_s",):
            continue
        x, y = a.column(c), b.column(c)
        if x.dtype == object:
            assert list(x) == list(y), c
        else:
            np.testing.assert_array_equal(x, y, err_msg=c)


def test_rows_equal_separate_runs(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """Each row equals `pfeie run` of the model with the record scaled to the same PGA
    (a separate process state: a new model, factorisation and W) to 1e-12 relative; the
    intensity measures are the scaled record's (PGA exactly the target)."""
    p = setup(tmp_path)
    table = Study.from_file(p).run()
    assert len(table) == 6 and all(table.column("completed"))
    np.testing.assert_allclose(table.column("im.pga_g"), [0.2, 0.5] * 3, rtol=1e-14)
    slip = table.column("joint.joint.residual_slip_max_m")
    assert slip[1] > 1e-3 and slip[0] < 1e-12  # 0.5 g breaks and slides; 0.2 g does not
    for k, row in enumerate(table.rows):
        if k % 2 == 0 and k != 0:
            continue  # the 0.5 g runs and the first 0.2 g run
        text = MODEL.replace("[output]", f"""[[ground_motion]]
file = "{row['file']}"
units = "g"
pga = {row['intensity']!r}
[output]""").replace('folder = "out"', f'folder = "out{k}"')  # fmt: skip
        (tmp_path / "one.toml").write_text(text)
        assert main(["run", str(tmp_path / "one.toml"), "--quiet"]) == 0
        s = json.loads((tmp_path / f"out{k}" / "summary.json").read_text())
        j, pr = s["joints"]["joint"], s["probes"]["top"]
        ref = {
            "joint.joint.residual_slip_max_m": j["residual_slip_max_m"],
            "joint.joint.peak_slip_max_m": j["peak_slip_max_m"],
            "joint.joint.max_opening_m": j["max_opening_m"],
            "joint.joint.min_safety_factor": j["min_safety_factor"],
            "probe.top.peak_displacement_m": pr["peak_displacement_m"],
            "probe.top.peak_abs_acceleration_g": pr["peak_abs_acceleration_g"],
            "stress.max_principal_Pa": s["stress"]["max_principal_Pa"],
        }
        for col, value in ref.items():
            assert row[col] == pytest.approx(value, rel=1e-12, abs=1e-15), (k, col)
        # the cracked length is the broken share of the 2 m joint (unit thickness)
        assert row["joint.joint.cracked_length_m"] == pytest.approx(
            2.0 * row["joint.joint.broken_share"], rel=1e-12, abs=1e-15)
    capsys.readouterr()


def test_command_line_and_resume(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """`pfeie study` writes the table (CSV and Parquet, read back to the same bits); run
    again it reruns nothing (every row kept); --restart runs all again to the same
    table."""
    p = setup(tmp_path)
    assert main(["study", str(p), "--quiet"]) == 0
    out = capsys.readouterr().out
    assert "6 runs" in out and "table.parquet" in out
    # the medians over the three records per intensity, as the table gives them
    table = StudyTable.read(tmp_path / "study" / "table.csv")
    med = np.median(table.column("probe.top.peak_displacement_m")[1::2])
    assert "median over the records:" in out and f"{med:.4g}" in out
    csv = StudyTable.read(tmp_path / "study" / "table.csv")
    same(csv, StudyTable.read(tmp_path / "study" / "table.parquet"))
    rows = tmp_path / "study" / "rows"
    stamp = {f.name: f.stat().st_mtime_ns for f in rows.iterdir()}
    assert main(["study", str(p)]) == 0
    assert {f.name: f.stat().st_mtime_ns for f in rows.iterdir()} == stamp
    assert "/6 runs" not in capsys.readouterr().err  # nothing ran again
    assert main(["study", str(p), "--restart"]) == 0
    err = capsys.readouterr().err  # a progress line a run (no terminal here)
    assert "[" + "#" * 24 + "] 6/6 runs" in err and err.count(" runs  elapsed ") == 6
    same(csv, StudyTable.read(tmp_path / "study" / "table.csv"))


@pytest.mark.slow  # 19 s; test_command_line_and_resume keeps a resume in the default run
def test_killed_study_resumes_to_the_same_table(tmp_path: Path) -> None:
    """SIGKILL a `pfeie study` after its second row; the same command finishes it and the
    table equals an uninterrupted study's (the rows are written atomically, each once)."""
    p = setup(tmp_path, n=4, seconds=6.0)
    ref = Study.from_file(p)
    ref.folder = tmp_path / "ref"
    want = ref.run()
    proc = subprocess.Popen([sys.executable, "-m", "pfeie", "study", str(p), "--quiet"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)  # fmt: skip
    rows = tmp_path / "study" / "rows"
    t0 = time.monotonic()
    while not (rows.is_dir() and len(list(rows.glob("*.json"))) >= 2):
        assert proc.poll() is None and time.monotonic() - t0 < 60
        time.sleep(0.01)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    done = len(list(rows.glob("*.json")))
    assert 2 <= done < 8 and not (tmp_path / "study" / "table.csv").exists()
    assert main(["study", str(p), "--quiet"]) == 0
    same(want, StudyTable.read(tmp_path / "study" / "table.csv"))


def test_interrupt_keeps_finished_runs(tmp_path: Path) -> None:
    """An interrupt after two runs keeps their rows; the next run of the study does the
    other four only."""
    p = setup(tmp_path)
    st = Study.from_file(p)

    def stop(done: int, total: int, row: dict[str, object]) -> None:
        if done == 2:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        st.run(progress=stop)
    seen: list[int] = []
    Study.from_file(p).run(progress=lambda d, n, r: seen.append(d))
    assert seen == [3, 4, 5, 6]


def test_sa_ladder_and_intensity_measures(tmp_path: Path) -> None:
    """An Sa(T1) ladder: T1 is the model's first period (joints bonded) unless given; the
    Sa column equals the target; Arias intensity scales with the factor squared, PGV and
    CAV with the factor (checked against the record's own measures)."""
    p = setup(tmp_path, STUDY.replace('measure = "pga"', 'measure = "sa"'), n=1)
    st = Study.from_file(p)
    t = st.run()
    assert st.period is not None and 0.0 < st.period < 1.0
    np.testing.assert_allclose(t.column("im.sa_t1_g"), [0.2, 0.5], rtol=1e-12)
    f = t.column("scale_factor")
    rec = st.records[0].read(2)
    ims = rec.intensity_measures(st.period)
    np.testing.assert_allclose(t.column("im.arias_m_s"), ims["arias"] * f**2, rtol=1e-12)
    np.testing.assert_allclose(t.column("im.pgv_m_s"), ims["pgv"] * f, rtol=1e-12)
    np.testing.assert_allclose(t.column("im.cav_m_s"), ims["cav"] * f, rtol=1e-12)


def test_histories_kept_on_request(tmp_path: Path) -> None:
    """With output.histories, each run leaves its results file, which names its record
    and scale factor and holds the same residual slip as the table."""
    from pfeie.io import Results

    p = setup(tmp_path, STUDY.replace('folder = "study"', 'folder = "study"\nhistories = true'),
              n=1)  # fmt: skip
    t = Study.from_file(p).run()
    # named by the intensity, not the level's index (which a value added to the ladder
    # would renumber)
    f = tmp_path / "study" / "runs" / f"r0_{t.column('intensity')[1]:g}" / "results.h5"
    with Results(f) as res:
        assert res.completed
        slip = np.linalg.norm(res.pairs("joint")["s"][-1], axis=-1).max()
    assert slip == t.column("joint.joint.residual_slip_max_m")[1]


_OVERRIDE = '[analysis]\nset = [{}]\n[output]'


@pytest.mark.parametrize("edit, bad, words", [
    ('model = "model.toml"', "", ["model", "required"]),
    ('pattern = "*.csv"', 'pattern = "*.txt"', ["no file", "*.txt"]),
    ("values = [0.2, 0.5]", "values = [0.2, -0.5]", ["intensity.values", "numbers, each > 0"]),
    ('measure = "pga"', 'measure = "pgv"',
     ["intensity.measure", "one of 'scale', 'pga', 'sa'"]),
    ('units = "g"', 'units = "g"\nrainbow = 1', ["records[0]", "rainbow"]),
    ('folder = "rec"', 'folder = "rec"\nfile = "rec/r0.csv"',
     ["records[0]", "either file or folder"]),
    ("workers = 0 ", 'workers = "many" ',
     ["run.workers", "expected an integer in [0, 4096] or 'auto'", "'many'"]),
    ("[run]", "[run]\nbatch = 0", ["run.batch", "expected an integer in [1, 64]", "found 0"]),
    # found by a study tester (twenty-eighth review): an empty [[records]] was told "not
    # both", `file = ""` ". not found", a folder given as `file` "rec not found"; an
    # override without '=' named no study file nor key; overrides of the model's ground
    # motions and output folder, and a duration given twice, were silently ignored
    ('folder = "rec"\npattern = "*.csv"\nunits = "g"', 'units = "g"',
     ["records[0].file", "found neither"]),
    ('folder = "rec"\npattern = "*.csv"', 'file = ""', ["records[0].file", "empty string"]),
    ('folder = "rec"\npattern = "*.csv"', 'file = "rec"',
     ["records[0].file", "is a folder", "folder = ..."]),
    ("[output]", _OVERRIDE.format('"output.paraview false"'),
     ["analysis.set[0]", "expected KEY=VALUE"]),
    ("[output]", _OVERRIDE.format('"ground_motion[0].scale = 2.0"'),
     ["analysis.set[0]", "[[records]] replace the model's [[ground_motion]]"]),
    ("[output]", _OVERRIDE.format('"output.folder = \'x\'"'),
     ["analysis.set[0]", "its own [output] folder"]),
    ("[output]", '[analysis]\nduration = 1.0\nset = ["analysis.duration = 2.0"]\n[output]',
     ["analysis.set[0]", "both give the runs' duration"]),
    # twenty-ninth review: an absolute pattern gave a NotImplementedError traceback
    ('pattern = "*.csv"', 'pattern = "/etc/*"',
     ["records[0].pattern", "'/etc/*'", "within records[0].folder"]),
])  # fmt: skip
def test_bad_study_files(tmp_path: Path, capsys: pytest.CaptureFixture[str], edit: str,
                         bad: str, words: list[str]) -> None:  # fmt: skip
    """Each wrong study file ends in exit 2 with `pfeie: error` lines that name the file
    and the key."""
    assert edit in STUDY
    p = setup(tmp_path, STUDY.replace(edit, bad))
    assert main(["study", str(p)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("pfeie: error: ") and str(p) in err
    for w in words:
        assert w in err, err


def test_bad_arguments(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    p = setup(tmp_path)
    assert main(["study", str(p), "--workers", "two"]) == 2
    assert "--workers" in capsys.readouterr().err
    assert main(["study", str(p), "--scheduler", "not an address"]) == 2  # (a traceback)
    assert "cannot reach the Dask scheduler at 'not an address'" in capsys.readouterr().err
    assert main(["study", str(p), "--batch", "0"]) == 2
    assert "--batch: expected a whole number in [1, 64], found '0'" in capsys.readouterr().err
    with pytest.raises(ModelError, match=r"run\.batch: expected an integer in \[1, 64\]"):
        Study(tmp_path / "model.toml", [tmp_path / "rec" / "r0.csv"], batch=65)
    assert main(["study", str(tmp_path / "none.toml")]) == 2
    assert "study file not found" in capsys.readouterr().err
    with pytest.raises(ModelError, match=r"intensity\.values\[0\]: expected a finite number > 0"):
        Study(tmp_path / "model.toml", [tmp_path / "rec" / "r0.csv"], values=[math.inf])
    with pytest.raises(ModelError, match="same name"):
        Study(tmp_path / "model.toml", [RecordSource("a", tmp_path / "rec" / "r0.csv"),
                                        RecordSource("a", tmp_path / "rec" / "r1.csv")])
    with pytest.raises(InputError, match="no column"):
        StudyTable([{"a": 1}]).column("b")


def test_limit_states_give_ida_fragility_and_report(tmp_path: Path) -> None:
    """With limit states the study writes fragility.csv (equal to fitting the table
    afresh with pfeie.study.fit_limit_states), the IDA and fragility figures and a report
    that embeds them; a limit state on a missing column is an input error naming it."""
    from pfeie.study import LimitState, fit_limit_states

    text = STUDY.replace("values = [0.2, 0.5]", "values = [0.2, 0.35, 0.5, 0.65]") + """
[[limit_states]]
name = "slides 2 mm"
demand = "joint.joint.residual_slip_max_m"
threshold = 0.002
"""
    p = setup(tmp_path, text)
    st = Study.from_file(p)
    table = st.run()
    out = {f.name for f in st.outputs()}
    assert {"fragility.csv", "fragility.png", "report.html",
            "ida_joint_joint_residual_slip_max_m.png"} <= out  # fmt: skip
    fit = fit_limit_states(table, [LimitState("slides 2 mm", "joint.joint.residual_slip_max_m",
                                              0.002)], intensity="intensity")["slides 2 mm"]
    row = StudyTable.read(tmp_path / "study" / "fragility.csv").rows[0]
    assert row["theta"] == fit.theta and row["beta"] == fit.beta
    assert 0.2 < fit.theta < 0.65 and row["n_records"] == 3
    page = (tmp_path / "study" / "report.html").read_text()
    assert page.count("data:image/png;base64,") == 2 and "slides 2 mm" in page
    # what was run and scaled (a new user's report gave the records' names only): the
    # step, the duration, each record's units, its applied PGA before scaling (the
    # table's PGA over its factor) and its factors; the limit state's demand, threshold
    assert "<th>time step Δt</th><td>0.01 s</td>" in page
    assert "<th>duration of each run</th><td>each record&#x27;s own length</td>" in page
    r0 = sorted((r for r in table.rows if r["record"] == "r0"), key=lambda r: r["level"])
    pga = r0[0]["im.pga_g"] / r0[0]["scale_factor"]
    factors = ", ".join(f"{r['scale_factor']:.4g}" for r in r0)
    assert f"<td>g</td><td>{pga:.4g}</td><td>{factors}</td>" in page
    assert "<td>joint.joint.residual_slip_max_m</td><td>&gt;= 0.002</td>" in page
    # an earlier study's figures in the folder go when this one does not write them
    stale = tmp_path / "study" / "ida_joint_other.png"
    stale.write_bytes(b"")
    st.run()  # the rows are kept: only the outputs are written again
    assert not stale.exists()
    p.write_text(text.replace('demand = "joint.joint.residual_slip_max_m"',
                              'demand = "joint.neck.slip"'))  # fmt: skip
    with pytest.raises(InputError, match=r"joint\.neck\.slip"):
        Study.from_file(p).run()


def test_study_records_are_filtered_as_a_model_files(tmp_path: Path) -> None:
    """A study's ``[[records]]`` take the same ``filter`` table as a model file's
    ``[[ground_motion]]``: the records a study reads equal, bit for bit, the API's
    ``read_record(...).filtered(...)``, and a study of one record at one PGA gives the
    row of `pfeie run` on the model file with that record, filter and PGA (to 1e-12, as
    the unfiltered rows above). A corner above the record's Nyquist frequency (50 Hz at
    Δt = 0.01 s) is refused, naming the file."""
    from pfeie.io import read_record

    study = STUDY.replace('units = "g"\n', 'units = "g"\nfilter = { highpass = 0.5, order = 2 }\n')
    study = study.replace("values = [0.2, 0.5]", "values = [0.3]")
    p = setup(tmp_path, study, n=1)
    st = Study.from_file(p)
    rec = st.records[0]
    assert (rec.highpass, rec.lowpass, rec.order) == (0.5, None, 2)
    raw = read_record(tmp_path / "rec" / "r0.csv", units="g", direction=[1.0, 0.0])
    np.testing.assert_array_equal(rec.read(2).acceleration,
                                  raw.filtered(highpass=0.5, order=2).acceleration)
    table = st.run()
    model = (tmp_path / "model.toml").read_text() + (
        '[[ground_motion]]\nfile = "rec/r0.csv"\nunits = "g"\npga = 0.3\n'
        "filter = { highpass = 0.5, order = 2 }\n"
    )
    (tmp_path / "one.toml").write_text(model.replace('folder = "out"', 'folder = "one"'))
    assert main(["run", str(tmp_path / "one.toml"), "--quiet"]) == 0
    s = json.loads((tmp_path / "one" / "summary.json").read_text())
    got = table.column("joint.joint.residual_slip_max_m")[0]
    assert got == pytest.approx(s["joints"]["joint"]["residual_slip_max_m"], rel=1e-12)
    (tmp_path / "bad").mkdir()
    bad = setup(tmp_path / "bad", study.replace("highpass = 0.5", "highpass = 60.0"), n=1)
    with pytest.raises(RecordError, match=r"r0\.csv"):
        Study.from_file(bad).run()


def test_runs_in_lockstep_give_the_rows_of_runs_alone(tmp_path: Path,
                                                      monkeypatch: pytest.MonkeyPatch) -> None:
    """A study whose runs step together (its 6 runs in two groups of 3, at most 4 a group,
    each on a twin of the system's analysis) gives the table of its runs one after
    the other, bit for bit. (This model is far below the 20,000 DOF from which a
    study steps its runs together, and its W is stored with K̂⁻¹Gᵀ, so no block
    solve is shared here: the shared solves are tested in test_lockstep.py; this
    test holds the study's side: the twins, the rows as each run ends, the table.)"""
    import pfeie.linalg as la
    from pfeie.study import _study

    p = setup(tmp_path)
    ref = Study.from_file(p)
    ref.folder, ref.batch = tmp_path / "ref", 1
    want = ref.run()
    calls: list[int] = []
    real = la.run_lockstep

    def spy(tasks, stats=None):  # type: ignore[no-untyped-def]
        calls.append(len(tasks))
        return real(tasks, stats)

    monkeypatch.setattr(_study._System, "lockstep", lambda self: True)
    monkeypatch.setattr(Study, "_may_step_together", lambda self: True)
    monkeypatch.setattr(la, "run_lockstep", spy)
    st = Study.from_file(p)
    st.batch = 4
    same(want, st.run())
    assert calls == [3, 3]  # six runs in two groups of at most four
    assert len(list((tmp_path / "study" / "rows").glob("*.json"))) == 6


def test_a_kept_history_says_when_the_records_peak_lies_beyond_the_run(tmp_path: Path) -> None:
    """A record whose peak comes after the run's end: the kept history's record line
    gives the whole record's PGA (its summary), and says that it lies beyond the run and
    what the motion applied peaks at: the study's target (a new user's history read
    "PGA 2.608 g at 29.14 s" for a 4 s run that peaked at 0.37 g)."""
    import json

    import h5py

    p = setup(tmp_path, STUDY.replace('folder = "study"', 'folder = "study"\nhistories = true')
              .replace("values = [0.2, 0.5]", "values = [0.5]\n[analysis]\nduration = 0.5"),
              n=1)  # fmt: skip
    t = np.arange(0.0, 2.0, 0.01)
    np.savetxt(tmp_path / "rec" / "r0.csv", np.c_[t, t * np.sin(2 * np.pi * 2.0 * t)],
               delimiter=",")  # fmt: skip
    Study.from_file(p).run()
    with h5py.File(tmp_path / "study" / "runs" / "r0_0.5" / "results.h5") as f:
        line = json.loads(f.attrs["results_summary"])["model"]["records"][0]
    assert "the PGA above lies beyond the end of the run, 0.5 s: the motion applied peaks " \
           "at 0.5 g" in line, line


def test_a_batch_given_anew_runs_only_what_is_left(tmp_path: Path) -> None:
    """A batch whose runs have rows on disk (a lost Dask worker's batch, recomputed after
    some of its runs ended: a new user's killed worker had three finished runs run again)
    returns those rows without running them; a restarted study (``resume`` false) runs
    them again."""
    import dataclasses
    import json

    from pfeie.study._study import run_batch

    p = setup(tmp_path, n=1)
    st = Study.from_file(p)
    st.run()
    specs = st.runs()
    ctx = dataclasses.replace(st.context(), folder=tmp_path / "study")
    row_file = tmp_path / "study" / "rows" / f"{specs[0].key}.json"
    row = json.loads(row_file.read_text())
    row["wall_s"] = -1.0  # a mark: a run made again writes its own wall time
    row_file.write_text(json.dumps(row))
    out = run_batch(ctx, specs)
    assert [r["key"] for r in out] == [s.key for s in specs]  # type: ignore[index]
    assert out[0]["wall_s"] == -1.0  # type: ignore[index]
    again = run_batch(dataclasses.replace(ctx, resume=False), specs[:1])
    assert again[0]["wall_s"] > 0.0  # type: ignore[index]
