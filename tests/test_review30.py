"""Findings of the thirtieth review.

Each test reproduces the defect and checks the fix against an independent number.
"""

from __future__ import annotations

import json
import logging
import re
import sys
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

import pfeie as pf
from pfeie.cli import main
from pfeie.errors import InputError, ModelError, PfeieError
from pfeie.io import Results, load_job
from pfeie.plot._report import model_of_run
from pfeie.study import StudyTable
from test_cli import SMALL, _write
from test_review28 import _block_on_a_joint
from test_study import STUDY, setup

# -- joint stiffness and the static state's displacements ----------------------------------


def _soft(k: str) -> str:
    return SMALL.replace("friction_angle = 26.565",
                         f"friction_angle = 26.565\nnormal_stiffness = {k}\n"
                         f"shear_stiffness = {k}")  # fmt: skip


@pytest.mark.parametrize("k", ["1e-300", "0.5"])
def test_a_joint_stiffness_below_one_pascal_a_metre_is_refused(tmp_path: Path, k: str) -> None:
    """normal_stiffness = 1e-300 Pa/m ran into a bare LinAlgError ("SVD did not converge")
    of the pair operators (the compliance 1/k overflows). No joint is softer than 1 Pa/m
    (1 m of closure under 1 Pa): the model file and the Python law refuse it by name."""
    with pytest.raises(InputError, match=r"interfaces\.joint\.normal_stiffness.*\[1, 1e\+20\]"):
        load_job(_write(tmp_path, _soft(k)))
    with pytest.raises(ModelError, match=r"kn must be >= 1 Pa/m"):
        pf.Joint(phi=30.0, kn=float(k))


def test_a_static_state_beyond_small_displacements_is_a_warning(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A weak layer of 1e3 Pa/m (a stiffness given in kPa/m, or a typo) closed under the
    dam block by 23.5 m, 12 times the joint's length, and the run's summary said nothing
    of it: the static state, the slips and the safety factors were read as results. The
    summary now warns. Independent number: the closure of a uniform layer under a rigid
    block, the mean normal stress over k: 23,544 Pa / 1e3 Pa/m = 23.5 m."""
    assert main(["run", str(_write(tmp_path, _soft("1e3"), duration=0.01)), "--quiet"]) == 0
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    sigma = s["static_joints"]["joint"]["mean_normal_stress_Pa"]
    assert s["static_far_moved"] == [
        f"joint 'joint': its faces moved {sigma / 1e3:.3g} m against each other (2 m long)"
    ]
    assert [w["label"] for w in s["warnings"]] == ["static"]
    text = (tmp_path / "out" / "summary.txt").read_text()
    assert "static       the static state: joint 'joint'" in text and "Pa/m" in text
    # the joint at its documented stiffness: no warning
    assert main(["run", str(_write(tmp_path, _soft("1e10"), duration=0.01)), "--quiet"]) == 0
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert "static_far_moved" not in s and s["warnings"] == []
    # a block carried 0.3 m down by its foundation's settlement (a support's value; a
    # reviewer's case): its joint does not move, no warning
    settled = SMALL.replace('group = "bottom"',
                            'group = "bottom"\ncomponents = ["y"]\nvalue = -0.3')  # fmt: skip
    settled = settled.replace("[[ground_motion]]", '[[supports]]\ngroup = "bottom"\n'
                              'components = ["x"]\n[[ground_motion]]')  # fmt: skip
    assert main(["run", str(_write(tmp_path, settled, duration=0.01)), "--quiet"]) == 0
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert "static_far_moved" not in s


# -- keys asked for that cannot run ----------------------------------------------------------


@pytest.mark.parametrize(
    ("analysis", "why"),
    [("static = false\npost_earthquake = true", "analysis.static = false"),
     ("static = true\ndynamic = false\npost_earthquake = true", "analysis.dynamic = false")],
)  # fmt: skip
def test_post_earthquake_asked_where_it_cannot_run_is_said(
    tmp_path: Path, caplog: pytest.LogCaptureFixture, analysis: str, why: str
) -> None:
    """``post_earthquake = true`` written in a file with ``static = false`` (or without a
    dynamic analysis) was ignored without a word. On by default, it is still skipped
    quietly where it has no meaning; written, a WARNING names it (not an error: files
    that ran with it must still resume and report)."""
    text = SMALL.replace("dt = 0.005", f"dt = 0.005\n{analysis}")
    with caplog.at_level(logging.WARNING, logger="pfeie"):
        load_job(_write(tmp_path, text))
    assert f"analysis.post_earthquake = true is not computed with {why}" in caplog.text
    caplog.clear()
    with caplog.at_level(logging.WARNING, logger="pfeie"):
        job = load_job(_write(tmp_path, text.replace("post_earthquake = true", "")))
    assert job.analysis.post_earthquake and "analysis.post_earthquake" not in caplog.text


def test_solve_static_takes_its_settings_as_a_dict() -> None:
    """``pfeie.Dynamic(settings={...})`` takes the settings' fields as a dict, and
    ``solve_static(settings={...})`` refused them. Now both do; the result is that of
    the typed settings, bit for bit, and a wrong field is named."""
    m = pf.Model(pf.rectangle(2.0, 1.0, 4, 2), [pf.Block("all", pf.Elastic(1e6, 0.0))])
    m.fix("xmin", 0)
    m.fix("ymin", 1)
    m.add_traction("xmax", [1e3, 0.0])
    u = pf.solve_static(m, settings={"tolerance": 1e-10}).u
    assert (u == pf.solve_static(m, settings=pf.SolverSettings(tolerance=1e-10)).u).all()
    assert abs(u[:, 0].max() - 2e-3) < 1e-15  # σ L / E
    with pytest.raises(ModelError, match="solve_static: settings: tol: Extra inputs"):
        pf.solve_static(m, settings={"tol": 1e-10})
    with pytest.raises(ModelError, match="tolerance: Input should be a valid number"):
        pf.solve_static(m, settings={"tolerance": "1e-10"})


# -- from a reader of the docs ---------------------------------------------------------------


def test_the_model_of_a_run_with_analysis_overrides_rebuilds(tmp_path: Path) -> None:
    """A static run with a pseudo-static load (``--set analysis.dynamic=false --set
    loads.pseudo_static=...``): ``plot`` and ``report`` said the model "does not build"
    (the run's loads against the file's [analysis], dynamic with a record), and left out
    the loads and the static stresses. The run's analysis table is applied with its
    structure now. Independent check: the rebuilt model's pseudo-static coefficient and
    static flag are the run's."""
    p = _write(tmp_path, SMALL)
    assert main(["run", str(p), "--quiet", "--set", "analysis.dynamic=false", "--set",
                 "loads.pseudo_static={kh=0.2, kv=0.1}"]) == 0  # fmt: skip
    with Results(tmp_path / "out" / "results.h5") as res:
        job, why = model_of_run(res)
    assert job is not None, why
    assert not job.analysis.dynamic
    assert job.spec["loads"]["pseudo_static"]["kh"] == 0.2


def test_a_study_without_pyarrow_writes_its_csv_table_and_report(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, caplog: pytest.LogCaptureFixture
) -> None:
    """``output.parquet`` is on by default and pyarrow is an extra: without it every run
    of a study finished, then the study stopped with exit 2, no report and no study.json,
    and an earlier study's table.parquet stayed beside the new table.csv. Now a WARNING
    before the runs, the CSV table, the report, and no stale Parquet file."""
    p = setup(tmp_path, STUDY.replace("[0.2, 0.5]", "[0.2]") + "[analysis]\nduration = 0.3\n",
              n=1)  # fmt: skip
    assert main(["study", str(p), "--quiet"]) == 0
    folder = tmp_path / "study"
    first = StudyTable.read(folder / "table.parquet")
    (folder / "report.html").unlink()
    monkeypatch.setitem(sys.modules, "pyarrow", None)  # (import pyarrow: ImportError)
    with caplog.at_level(logging.WARNING):
        assert main(["study", str(p), "--quiet", "--restart"]) == 0
    assert "output.parquet: pyarrow is not installed" in caplog.text
    assert not (folder / "table.parquet").exists()
    assert (folder / "report.html").exists() and (folder / "study.json").exists()
    again = StudyTable.read(folder / "table.csv")
    column = "joint.joint.residual_slip_max_m"
    assert column in again.columns
    np.testing.assert_array_equal(again.column(column), first.column(column))


def test_run_to_folder_without_h5py_keeps_the_former_run(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Without h5py, ``run_to_folder`` removed a former run's summaries, ParaView files and
    figures before it failed on the results file, and the former results.h5 stood alone.
    Now it fails before it touches the folder."""
    model, _ = _block_on_a_joint()
    gm = pf.io.read_record(Path(__file__).resolve().parents[1] / "examples" / "data"
                           / "elcentro_1940_ns_chopra.csv", units="g")  # fmt: skip
    an = pf.Dynamic(model, 0.01)
    pf.run_to_folder(an, 0.05, tmp_path, ground=gm, start=pf.solve_static(model))
    before = sorted(f.name for f in tmp_path.iterdir())
    assert "summary.json" in before
    monkeypatch.setitem(sys.modules, "h5py", None)
    with pytest.raises(PfeieError, match="results files need h5py"):
        pf.run_to_folder(an, 0.05, tmp_path, ground=gm, start=pf.solve_static(model))
    assert sorted(f.name for f in tmp_path.iterdir()) == before


def test_a_path_for_the_records_is_refused_by_name() -> None:
    """``Dynamic.run(ground="x.csv")`` iterated the string: "ground[0]: … got str 'x'",
    and ``run_to_folder`` listed ['str', 'str', …]. Both name the argument now."""
    model, _ = _block_on_a_joint()
    an = pf.Dynamic(model, 0.01)
    with pytest.raises(ModelError, match=r"ground: expected a pfeie.GroundMotion or a list "
                       r"of them .* got str 'x.csv'"):  # fmt: skip
        an.run(0.02, ground="x.csv")
    with pytest.raises(ModelError, match=r"ground: expected .* got str 'x.csv'"):
        pf.run_to_folder(an, 0.02, "out", ground="x.csv")  # type: ignore[arg-type]


@pytest.mark.parametrize(("key", "found"), [("mesh.file", '""'), ("mesh.file", '" "'),
                                            ("ground_motion[0].file", '""')])  # fmt: skip
def test_an_empty_path_is_refused_by_name(tmp_path: Path, key: str, found: str) -> None:
    """``mesh.file = ""`` read as the folder ".": ".: mesh file not found"."""
    with pytest.raises(InputError, match=re.escape(key) + r" \(from test\): expected a "
                       "path, found an? (empty|blank) string"):  # fmt: skip
        load_job(_write(tmp_path, SMALL), [pf.io.Override(key, json.loads(found), "test")])


def test_help_names_every_exit_code(capsys: pytest.CaptureFixture[str]) -> None:
    """The help's exit codes left out 141 (docs/errors.md lists it)."""
    assert main(["--help"]) == 0
    assert "141 the reader of the output closed it" in capsys.readouterr().out


# -- from a tester of long runs ----------------------------------------------------------------


def _stopped(tmp_path: Path, wait: float = 0.0, duration: float = 3.0) -> tuple[Path, float]:
    """A model file and its run stopped by SIGINT (``duration`` asked) once it has stepped
    for ``wait`` seconds, and the time it reached."""
    import signal

    from test_cli import start_run

    p = _write(tmp_path, SMALL, duration=duration)
    proc = start_run(p, wait=0.0)
    time.sleep(wait)  # stepping
    proc.send_signal(signal.SIGINT)
    proc.communicate(timeout=120)
    with Results(tmp_path / "out" / "results.h5") as res:
        assert not res.completed
        return p, float(res.time[-1])


def test_a_stopped_run_of_other_inputs_is_kept(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    """A stopped run whose resume was refused for a changed input (here output.every),
    then run again without --resume as the message says: the stopped run was overwritten
    without a word (only one of the same inputs was kept). It is moved aside now."""
    p, t = _stopped(tmp_path)
    assert main(["run", str(p), "--quiet", "--resume", "--set", "output.every=2"]) == 2
    with caplog.at_level(logging.WARNING, logger="pfeie"):
        assert main(["run", str(p), "--quiet", "--duration", "0.05",
                     "--set", "output.every=2"]) == 0  # fmt: skip
    assert "held a stopped run of other inputs" in caplog.text
    with Results(tmp_path / "out" / "results.stopped.h5") as res:
        assert not res.completed and float(res.time[-1]) == t
    # and its own inputs resume it, moved back
    (tmp_path / "out" / "results.stopped.h5").replace(tmp_path / "out" / "results.h5")
    assert main(["run", str(p), "--quiet", "--resume"]) == 0
    with Results(tmp_path / "out" / "results.h5") as res:
        assert res.completed and float(res.time[-1]) == pytest.approx(3.0)


def test_a_resume_short_of_where_the_run_stopped_leaves_the_file(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """``--resume --duration`` below the time a stopped run reached marked the file
    ``completed`` (its histories at that time, its spec at the run's own duration). Now
    refused before the file is touched."""
    p, t = _stopped(tmp_path, wait=0.3, duration=20.0)  # (about 3 s of 20 reached)
    assert t > 0.02  # (the run stepped before the signal)
    assert main(["run", str(p), "--quiet", "--resume", "--duration", "0.01"]) == 2
    assert "beyond the duration asked (0.01 s): nothing to continue" in capsys.readouterr().err
    with Results(tmp_path / "out" / "results.h5") as res:
        assert not res.completed and float(res.time[-1]) == t


def test_a_study_runs_again_a_history_written_in_part(tmp_path: Path) -> None:
    """A study restarted (``--restart``) and stopped while it wrote a history again left
    a part of it (no results summary, the rows so far), and the next run of the study
    kept it for good beside a row that says the run completed. A history counts only
    once its run wrote the summary it ends with."""
    import h5py

    p = setup(tmp_path, STUDY.replace("[0.2, 0.5]", "[0.2]").replace(
        'folder = "study"', 'folder = "study"\nhistories = true') + "[analysis]\nduration = 0.3\n",
        n=1)  # fmt: skip
    assert main(["study", str(p), "--quiet"]) == 0
    (h,) = (tmp_path / "study" / "runs").glob("*/results.h5")
    with h5py.File(h, "r") as f:
        rows = f["history/time"].shape[0]
    with h5py.File(h, "r+") as f:  # as a run stopped while it wrote leaves it
        del f.attrs["results_summary"]
        for name in ("history/time",):
            f[name].resize(rows // 2, axis=0)
    assert main(["study", str(p), "--quiet"]) == 0
    with h5py.File(h, "r") as f:
        assert "results_summary" in f.attrs and f["history/time"].shape[0] == rows


def test_a_read_error_of_a_results_file_is_named(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """HDF5's read errors (a file that a run still writes, opened with file locking off,
    as the locked file's message offers) came out as a bare OSError traceback."""
    import pfeie.io

    def fails(*_: object) -> None:
        raise OSError("Can't synchronously read data (addr overflow, addr = 9, size = 8)")

    monkeypatch.setattr(pfeie.io, "export_csv", fails)
    assert main(["export", str(tmp_path / "results.h5"), "--csv", str(tmp_path / "c")]) == 2
    err = capsys.readouterr().err
    assert "reading the results file failed (Can't synchronously read data" in err
    assert "read reliably only when the run ends" in err


def test_a_resumed_run_killed_leaves_no_summary_of_the_stop(tmp_path: Path) -> None:
    """A stopped run resumed, then killed (SIGKILL, no handler): the summaries, the
    ParaView files, the stress envelope and the results summary of the first stop stayed
    beside the resumed run's longer histories, and the report mixed the two (steps to
    the first stop, histories to the kill). They go when the resume starts now; the run's
    end writes them anew."""
    import os
    import signal
    import subprocess

    import h5py

    p, t = _stopped(tmp_path, wait=0.3, duration=20.0)
    out = tmp_path / "out"
    assert (out / "summary.txt").exists()
    with h5py.File(out / "results.h5", "r") as f:
        assert "envelope" in f and "results_summary" in f.attrs
    env = dict(os.environ, PYTHONUNBUFFERED="1")
    proc = subprocess.Popen([sys.executable, "-m", "pfeie", "run", str(p), "--resume"],
                            env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True)  # fmt: skip
    assert proc.stderr is not None
    for line in proc.stderr:  # stepping again
        if line.startswith("step"):
            break
    proc.send_signal(signal.SIGKILL)
    proc.communicate(timeout=60)
    assert not (out / "summary.txt").exists() and not (out / "summary.json").exists()
    with h5py.File(out / "results.h5", "r") as f:
        assert "envelope" not in f and "results_summary" not in f.attrs
        assert not f.attrs["completed"] and f["history/time"][-1] >= t


def _disk_short_after(monkeypatch: pytest.MonkeyPatch, looks: int) -> Callable[[], None]:
    """The output disk looks nearly full (10 MiB free) to the run's guard after ``looks``
    looks at it, each step; returns the function that gives the disk back."""
    import shutil
    from collections import namedtuple

    import pfeie._job as job_module

    usage = namedtuple("usage", "total used free")
    calls = {"n": 0}
    real = shutil.disk_usage

    def short(path: object) -> object:
        calls["n"] += 1
        return usage(1, 1, 10 * 2**20) if calls["n"] > looks else real(path)  # type: ignore[arg-type]

    monkeypatch.setattr(job_module, "DISK_CHECK_S", 0.0)
    monkeypatch.setattr(job_module.shutil, "disk_usage", short)
    return lambda: monkeypatch.setattr(job_module.shutil, "disk_usage", real)


def test_a_run_stops_cleanly_when_its_disk_runs_short(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """A full disk under a run: HDF5 lost its write errors in cached chunks, the run went
    on stepping and then crashed, leaving rows of zeros counted as data and a checkpoint
    half written (a tester's 3 MiB tmpfs). The run now looks at the free space each second
    and stops as Ctrl-C stops it, checkpoint and rows kept, when less than a checkpoint
    and the summaries would need is left; ``--resume`` then continues it to the bits of a
    run never stopped. (The disk is made short here by shutil.disk_usage's answer.)"""
    p = _write(tmp_path, SMALL, duration=0.5)
    ref = tmp_path / "ref"
    assert main(["run", str(p), "--quiet", "--set", f"output.folder={str(ref)!r}"]) == 0
    give_back = _disk_short_after(monkeypatch, 1)
    assert main(["run", str(p), "--quiet"]) == 130
    assert "MiB free, less than the" in capsys.readouterr().out
    with Results(tmp_path / "out" / "results.h5") as res:
        assert not res.completed and 0 < float(res.time[-1]) < 0.5
    give_back()
    assert main(["run", str(p), "--quiet", "--resume"]) == 0
    with Results(tmp_path / "out" / "results.h5") as a, Results(ref / "results.h5") as b:
        assert a.completed
        np.testing.assert_array_equal(a.f["history/rigid"][()], b.f["history/rigid"][()])


@pytest.mark.slow
def test_run_to_folder_takes_its_records_from_a_generator(tmp_path: Path) -> None:
    """Records given as a generator were used up by the argument check, and the run went
    on without them, quietly (a reviewer's finding). The run of a generator is now the
    run of the list, bit for bit."""
    model, _ = _block_on_a_joint()
    gm = pf.io.read_record(Path(__file__).resolve().parents[1] / "examples" / "data"
                           / "elcentro_1940_ns_chopra.csv", units="g", scale=2.0)  # fmt: skip
    an = pf.Dynamic(model, 0.01)
    st = pf.solve_static(model)
    pf.run_to_folder(an, 3.0, tmp_path / "a", ground=[gm], start=st)
    pf.run_to_folder(an, 3.0, tmp_path / "b", ground=(g for g in [gm]), start=st)
    with Results(tmp_path / "a" / "results.h5") as a, Results(tmp_path / "b" / "results.h5") as b:
        x = a.f["history/rigid"][()]
        assert np.abs(x[-1] - x[0]).max() > 1e-2  # it slid (El Centro × 2 on μ = 0.2)
        np.testing.assert_array_equal(x, b.f["history/rigid"][()])


def test_a_mechanism_of_a_joint_far_too_soft_names_its_stiffness() -> None:
    """A joint stiffness written in GPa/m as Pa/m (10): the static solve finds no
    equilibrium and its message sent the user to the friction angles and cohesions only
    (a reviewer's finding). It names the stiffness now."""
    model, _ = _block_on_a_joint(pf.Joint(phi=30.0, kn=10.0, ks=10.0))
    with pytest.raises(pf.MechanismError, match=r"and the joint stiffnesses \('joint': "
                       r"normal_stiffness 10 Pa/m; 'joint': shear_stiffness 10 Pa/m\)"):
        pf.solve_static(model)


def test_a_stopped_extension_names_its_own_duration(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """A completed run extended by ``--resume --duration 1.0`` and stopped on the way:
    a plain ``--resume`` (the model file's 0.6 s) is refused, and the message named "the
    model file's" duration, the one it refused (a second reviewer's finding). It names
    the run's own now, and that resume finishes it."""
    p = _write(tmp_path, SMALL, duration=0.6)
    assert main(["run", str(p), "--quiet"]) == 0
    give_back = _disk_short_after(monkeypatch, 30)  # (0.15 s into the extension)
    assert main(["run", str(p), "--quiet", "--resume", "--duration", "1.0"]) == 130
    # (the command line's own command: its model file and options)
    assert f"`pfeie run {p} --resume --duration 1.0` continues the run" in capsys.readouterr().out
    give_back()
    capsys.readouterr()
    assert main(["run", str(p), "--quiet", "--resume"]) == 2
    assert "(the run's own: --duration 1)" in capsys.readouterr().err
    assert main(["run", str(p), "--quiet", "--resume", "--duration", "1.0"]) == 0
    with Results(tmp_path / "out" / "results.h5") as res:
        assert res.completed and float(res.time[-1]) == pytest.approx(1.0)
