"""Findings of the thirty-first review.

Each test reproduces the defect and checks the fix against an independent number.
"""

from __future__ import annotations

import json
import logging
import re
import signal
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

import pfeie as pf
from pfeie.cli import main
from pfeie.io import Results
from pfeie.study import StudyTable
from test_cli import SMALL, _write, start_run

# -- a re-run into the folder of a completed run -------------------------------------------


def _final_u(path: Path) -> tuple[bool, float, np.ndarray]:
    with Results(path) as res:
        return res.completed, float(res.time[-1]), res.probe("top")["a"].copy()


def test_a_rerun_stopped_before_its_end_keeps_the_completed_run(
    tmp_path: Path, caplog: pytest.LogCaptureFixture, monkeypatch: pytest.MonkeyPatch
) -> None:
    """``pfeie run`` into a folder holding a completed run overwrote its results file at
    once: a re-run stopped (Ctrl-C) or failed before its end lost what the first run had
    computed. The completed run is now kept as ``results.previous.h5`` until the re-run
    completes; the test compares its histories with those read before the re-run."""
    out = tmp_path / "out"
    p = _write(tmp_path, SMALL, duration=0.1)
    assert main(["run", str(p), "--quiet"]) == 0
    before = _final_u(out / "results.h5")
    assert before[0] and before[1] == pytest.approx(0.1)
    # a re-run stopped by SIGINT while it steps
    p = _write(tmp_path, SMALL, duration=30.0)
    proc = start_run(p, wait=0.0)
    time.sleep(0.5)  # stepping (about 3 s of the 30 s a second)
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err[-3000:]
    assert "results.previous.h5 holds the completed run that this run was to replace" in err
    kept = _final_u(out / "results.previous.h5")
    assert kept[:2] == before[:2]
    np.testing.assert_array_equal(kept[2], before[2])
    stopped = _final_u(out / "results.h5")
    assert not stopped[0] and stopped[1] < 30.0
    # a re-run whose static state fails keeps it too (the stopped run goes aside as before)
    def fail(*_a: object, **_k: object) -> None:
        raise pf.SolverError("planted failure of the static state")

    monkeypatch.setattr("pfeie._job.solve_static", fail)
    with caplog.at_level(logging.WARNING, logger="pfeie"):
        assert main(["run", str(p), "--quiet"]) == 1  # (a solver failure)
    assert "holds the completed run that this run was to replace" in caplog.text
    assert (out / "results.stopped.h5").is_file()
    np.testing.assert_array_equal(_final_u(out / "results.previous.h5")[2], before[2])
    monkeypatch.undo()
    # the re-run that completes replaces it
    p = _write(tmp_path, SMALL, duration=0.05)
    assert main(["run", str(p), "--quiet"]) == 0
    assert not (out / "results.previous.h5").exists()
    done = _final_u(out / "results.h5")
    assert done[0] and done[1] == pytest.approx(0.05)


# -- a disk short of space under run_to_folder and a study ---------------------------------


def test_run_to_folder_stops_cleanly_when_its_disk_runs_short(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, caplog: pytest.LogCaptureFixture
) -> None:
    """``pfeie run`` stopped on a disk short of space (a tester's full tmpfs: HDF5 lost
    its write errors and the run crashed), ``pf.run_to_folder`` went on writing. It now
    stops as ``pfeie run`` does: the file closed, not completed, its rows those of the
    run never stopped (bit for bit), and a warning names the disk."""
    from test_review30 import _disk_short_after

    model = pf.Model(pf.rectangle(2.0, 1.0, nx=4, ny=2),
                     [pf.Block("all", pf.Elastic(E=1e9, nu=0.2, rho=2000))])  # fmt: skip
    model.fix("ymin")
    g = pf.GroundMotion.from_function(lambda t: np.sin(20 * t), duration=0.5, dt=0.005)
    ref = pf.run_to_folder(pf.Dynamic(model, dt=0.005), 0.5, tmp_path / "ref", ground=[g],
                           probes={"top": 14}, paraview=False, figures=False)  # fmt: skip
    _disk_short_after(monkeypatch, 20)
    with caplog.at_level(logging.WARNING, logger="pfeie"):
        res = pf.run_to_folder(pf.Dynamic(model, dt=0.005), 0.5, tmp_path / "out", ground=[g],
                               probes={"top": 14}, paraview=False, figures=False)  # fmt: skip
    assert not res.completed and "MiB free, less than the" in str(res.stop_reason)
    assert "run it again (results.h5 holds it to where it stopped)" in caplog.text
    with Results(tmp_path / "out" / "results.h5") as f:
        assert not f.completed
        n = f.n_times
        assert 1 < n < ref.t.size
        np.testing.assert_array_equal(f.probe("top")["a"], ref.probe_a[:n, 0])


def test_a_study_stops_cleanly_when_its_disk_runs_short(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """A study had no guard of its disk: with histories kept it wrote on into a full
    disk, and a run stopped there would have left a row as if it were done. Now a run is
    not started on a disk short of space, a run with histories stops as ``pfeie run``
    does, without a row, and the study exits 2 naming the disk; the study run again
    goes on with the runs left and its table equals that of a study never stopped."""
    from test_review30 import _disk_short_after
    from test_study import STUDY, setup

    text = STUDY.replace('folder = "study"', 'folder = "study"\nhistories = true')
    for d in ("ref", "s"):
        (tmp_path / d).mkdir()
    ref = setup(tmp_path / "ref", text, n=2, seconds=0.5)
    assert main(["study", str(ref), "--quiet"]) == 0
    p = setup(tmp_path / "s", text, n=2, seconds=0.5)
    _disk_short_after(monkeypatch, 5)  # (a look before each run, then one each step)
    assert main(["study", str(p), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "MiB free, less than the" in err and "run the study again" in err
    rows = [json.loads(r.read_text()) for r in (tmp_path / "s" / "study" / "rows").glob("*.json")]
    assert len(rows) < 4 and all(r["completed"] for r in rows)  # none for a stopped run
    monkeypatch.undo()
    assert main(["study", str(p), "--quiet"]) == 0
    a = StudyTable.read(tmp_path / "s" / "study" / "table.csv")
    b = StudyTable.read(tmp_path / "ref" / "study" / "table.csv")
    assert a.columns == b.columns
    for c in set(a.columns) - {"file", "wall_s"}:  # (the records' folders differ)
        x, y = a.column(c), b.column(c)
        if x.dtype == object:
            assert list(x) == list(y), c
        else:
            np.testing.assert_array_equal(x, y, err_msg=c)


# -- the command that resumes a stopped run ------------------------------------------------


@pytest.mark.slow
def test_a_stopped_run_names_the_command_that_resumes_it(tmp_path: Path) -> None:
    """A run stopped by Ctrl-C said "STOPPED" and nothing of how to go on; a plain
    ``--resume`` is refused for a run with ``--set`` options or an extension's own
    ``--duration`` (another run key, or a duration short of where it stopped). The stop
    now gives the whole command, and that command, run as given, completes the run."""
    import os
    import shlex
    import subprocess
    import sys

    p = _write(tmp_path, SMALL, duration=0.2)
    assert main(["run", str(p), "--quiet", "--set", "output.every=2"]) == 0
    env = dict(os.environ, PYTHONUNBUFFERED="1")
    proc = subprocess.Popen([sys.executable, "-m", "pfeie", "run", str(p), "--resume",
                             "--duration", "30", "--set", "output.every=2"], env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)  # fmt: skip
    assert proc.stderr is not None
    for line in proc.stderr:  # stepping
        if line.startswith("step"):
            break
    time.sleep(0.5)
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130
    said = re.search(r"the run stopped at t = ([\d.]+) s; `([^`]+)` continues it", err)
    assert said is not None, err[-2000:]
    words = shlex.split(said[2])
    assert words[:2] == ["pfeie", "run"] and words[2:] == [
        str(p), "--resume", "--duration", "30", "--set", "output.every=2"]
    assert main(["run", "--quiet", *words[2:]]) == 0
    with Results(tmp_path / "out" / "results.h5") as res:
        assert res.completed and float(res.time[-1]) == pytest.approx(30.0)


# -- overlapping cells ---------------------------------------------------------------------

_SQUARES = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (1.0, 1.0, 0.0), (0.0, 1.0, 0.0),
            (2.0, 0.0, 0.0), (2.0, 1.0, 0.0)]  # fmt: skip


@pytest.mark.parametrize("case", ["meshed twice, own nodes", "meshed twice, shared nodes"])
def test_a_region_meshed_twice_is_refused(tmp_path: Path, case: str) -> None:
    """A surface defined twice on one curve loop (a copy-paste slip in a .geo file) gave
    a block of twice its mass without an error: 28,800 kg for 19,200 (a tester's mesh;
    the only word was a warning of coincident nodes). The left unit square is meshed
    twice here: its mass would be 2 × 2000 kg + 2000 kg for the right one; the mesh is
    refused, naming the cells that overlap, or the facet that three cells share."""
    from pfeie.errors import MeshError
    from pfeie.io import read_mesh
    from test_robustness import msh22

    names = {1: (2, "all")}
    right = [(3, 2, 1, [2, 5, 6]), (4, 2, 1, [2, 6, 3])]
    if case == "meshed twice, own nodes":  # a centre node of each copy, at (0.5, 0.5)
        nodes = [*_SQUARES, (0.5, 0.5, 0.0), (0.5, 0.5, 0.0)]
        fan = [[1, 2], [2, 3], [3, 4], [4, 1]]
        cells = [(10 + k, 2, 1, [a, b, 7]) for k, (a, b) in enumerate(fan)]
        cells += [(20 + k, 2, 1, [a, b, 8]) for k, (a, b) in enumerate(fan)]
        words = r"4 cell\(s\) at the same place as others, on coincident nodes: gmsh element 10"
    else:  # the two diagonals of the same square, on its own four nodes
        nodes = _SQUARES
        cells = [(1, 2, 1, [1, 2, 3]), (2, 2, 1, [1, 3, 4]),
                 (5, 2, 1, [1, 2, 4]), (6, 2, 1, [2, 3, 4])]  # fmt: skip
        words = (r"1 facet\(s\) shared by three or more cells, the first at \[1.0, 0.5\] "
                 r"\(3 cells\): cells overlap")  # fmt: skip
    path = msh22(tmp_path / "twice.msh", nodes, cells + right, names)
    with pytest.raises(MeshError, match=words):
        read_mesh(path)
    # the squares meshed once read, with the mass of 2 m² (the check's reference)
    once = msh22(tmp_path / "once.msh", _SQUARES,
                 [(1, 2, 1, [1, 2, 3]), (2, 2, 1, [1, 3, 4]), *right], names)  # fmt: skip
    model = pf.Model(read_mesh(once), [pf.Block("all", pf.Elastic(E=1e9, nu=0.2, rho=2000))])
    assert model.total_mass() == pytest.approx(4000.0, rel=1e-12)


def test_a_mesh_group_named_as_a_joint_face_is_refused() -> None:
    """A mesh group that a user named ``joint:a`` (the block's left face here) took the
    place of the joint's face a after the split: water in the joint
    (``[[loads.pressure]] group = "joint"``) then pushed on the left face and on face b
    only, a net 20 kN where a pressure inside a joint balances itself (a tester's
    mesh). The name is now refused, naming the group and the joint."""
    mesh = pf.rectangle(2.0, 2.0, 2, 2)
    mesh.add_facet_group("mid", lambda x: abs(x[:, 1] - 1.0) < 1e-9, boundary_only=False)
    mesh.add_facet_group("mid:a", lambda x: x[:, 0] < 1e-9)
    with pytest.raises(pf.ModelError, match=r"physical group 'mid:a' of the mesh has the name of "
                       r"a face of the interface 'mid'"):  # fmt: skip
        pf.Model(mesh, [pf.Block("all", pf.Elastic(E=1e9, nu=0.2, rho=2000))],
                 interfaces=[pf.Interface("mid", pf.Joint(phi=30.0))])  # fmt: skip


# -- gmsh files: what a message names ------------------------------------------------------


def test_msh22_saved_with_save_all_is_named(tmp_path: Path) -> None:
    """An MSH 2.2 file saved with Mesh.SaveAll = 1 (gmsh 4.x: physical tag 0 on every
    element) was refused as "'dam' ... holds no elements: add its entities to it before
    meshing", advice that does not apply. It now gets the MSH 4.1 file's own advice."""
    from test_robustness import msh22

    nodes = _SQUARES[:4]
    cells = [(1, 2, 0, [1, 2, 3]), (2, 2, 0, [1, 3, 4])]
    path = msh22(tmp_path / "all.msh", nodes, cells, {1: (2, "all")})
    with pytest.raises(pf.MeshError, match=r"physical tag 0 on every element: gmsh's "
                       r"Mesh.SaveAll = 1 in MSH 2.2\); save it again with Mesh.SaveAll = 0"):
        pf.read_mesh(path)


def test_a_third_order_mesh_names_its_block_and_the_order(tmp_path: Path) -> None:
    """A mesh of the third order (Mesh.ElementOrder = 3) was refused on its first line4
    cells: the message named a curve's group (or a point's, of the same tag), counted
    every line4 of the file, and advised tetrahedra for a 2D mesh. It now names the
    block's cells and the setting to change."""
    from test_robustness import msh22

    nodes = [(x, y, 0.0) for y in (0.0, 1 / 3, 2 / 3, 1.0) for x in (0.0, 1 / 3, 2 / 3, 1.0)]
    # a triangle10 (corners, two nodes an edge, the centre) and two line4 of its edges
    tri = [1, 4, 13, 2, 3, 7, 10, 9, 5, 6]
    cells = [(1, 26, 2, [1, 4, 2, 3]), (2, 26, 3, [4, 13, 7, 10]), (3, 21, 1, tri)]
    names = {1: (2, "all"), 2: (1, "bottom"), 3: (1, "side")}
    with pytest.raises(pf.MeshError, match=r"physical group 'all': 1 triangle10 cell\(s\) "
                       r"\(gmsh element 3\); the mesh is of the third order \(gmsh's "
                       r"Mesh.ElementOrder = 3\)"):  # fmt: skip
        pf.read_mesh(msh22(tmp_path / "o3.msh", nodes, cells, names))


def test_cells_in_no_block_are_named_with_their_place(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    """Cells of physical tag 0 inside a block's region (a surface left out of its
    physical group) were a warning with a count only, and the run went on with a hole
    (17,971 kg for 19,200, a tester's mesh). The warning now names the cells and where
    the first lies: here gmsh element 11, the right square, centred at (1.5, 0.5)."""
    from pfeie.io import load_job
    from test_robustness import ELEMENTS, model

    cells = [e if e[0] != 11 else (11, 3, 0, e[3]) for e in ELEMENTS]
    with caplog.at_level(logging.WARNING, logger="pfeie"):
        load_job(model(tmp_path, elements=cells))
    assert ("1 cell(s) of the mesh belong to no block and are left out of the model "
            "(gmsh element 11; the first at [1.5, 0.5]): cells in no physical group") in caplog.text


# -- outputs that disagreed ----------------------------------------------------------------


def test_the_joint_figure_counts_the_open_share_as_the_csv(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The joint figure's "open" curve counted every pair in the open state, where the
    CSV export, the summary and the report count those open by more than 0.01 mm (the
    corner pairs of quadratic facets part by microns in compression): 20.8 % against
    4.2 % at the demo's neck (a tester's reading). Planted here: of the joint's pairs
    at the last row, one open by 1 mm and one by 0.1 µm; the figure's and the CSV's
    open share are both the first pair's area share."""
    import csv

    import h5py
    from matplotlib.figure import Figure

    from pfeie.plot import plot_all

    p = _write(tmp_path, SMALL, duration=0.05)
    assert main(["run", str(p), "--quiet"]) == 0
    path = tmp_path / "out" / "results.h5"
    with h5py.File(path, "r+") as f:
        f["history/pairs/state"][-1, :2] = 3
        s = f["history/pairs/s"]
        last = s[-1]
        last[0, -1], last[1, -1] = 1e-3, 1e-7
        s[-1] = last
        area = f["pairs/area"][()]
    want = area[0] / area.sum()
    drawn: list[Figure] = []
    monkeypatch.setattr(Figure, "savefig", lambda self, *a, **k: drawn.append(self))
    plot_all(path, tmp_path / "fig")
    fig = next(f for f in drawn if any("open (>" in (ln.get_label() or "")
                                       for ax in f.axes for ln in ax.lines))  # fmt: skip
    line = next(ln for ax in fig.axes for ln in ax.lines if "open (>" in str(ln.get_label()))
    assert line.get_ydata()[-1] == pytest.approx(100 * want, rel=1e-12)
    monkeypatch.undo()
    assert main(["export", str(path), "--csv", str(tmp_path / "csv")]) == 0
    with (tmp_path / "csv" / "joints.csv").open() as fh:
        rows = [r for r in csv.DictReader(fh) if r["quantity"] == "open_share"]
    assert float(rows[-1]["value"]) == pytest.approx(want, rel=1e-12)


@pytest.mark.slow
def test_the_report_of_a_stopped_run_and_of_a_run_without_its_model_file(
    tmp_path: Path,
) -> None:
    """The report of a stopped run showed raw HTML in its table ("<b>stopped</b>:
    stopped: SIGINT"); a report without the model file dropped the joints' strengths,
    which the results file's model summary holds; a static factor of safety without
    shear read "inf" where the text summary reads ∞ (a tester's findings)."""
    import h5py

    p = _write(tmp_path, SMALL, duration=0.05)
    assert main(["run", str(p), "--quiet"]) == 0
    path = tmp_path / "out" / "results.h5"
    with h5py.File(path, "r+") as f:  # as a run stopped by Ctrl-C leaves it
        f.attrs["completed"], f.attrs["stop_reason"] = False, "stopped: SIGINT"
    assert main(["report", str(path), "--out", str(tmp_path / "with.html")]) == 0

    def laws(page: str) -> str:
        part = page[page.index("<h3>Joints</h3>"):]
        return part[: part.index("</table>")]

    p.rename(tmp_path / "elsewhere.toml")  # the model file is gone
    assert main(["report", str(path), "--out", str(tmp_path / "r.html")]) == 0
    page = (tmp_path / "r.html").read_text()
    # the joint's law from the summary as from the model file: φ = 26.565°, no
    # cohesion, rigid springs (the residual φ given as the intact one's value)
    row = "<td>joint</td><td>mohr-coulomb</td><td>broken</td><td>0</td><td>26.57</td><td>0</td>"
    assert row in laws(page) and row in laws((tmp_path / "with.html").read_text())
    assert laws(page).endswith("<td>26.57</td><td>rigid</td><td>rigid</td></tr>\n")
    assert "<th>run</th><td>stopped: SIGINT at t = 0.050 s</td>" in page
    assert "&lt;b&gt;" not in page and "run <b>stopped</b>: SIGINT at t = 0.050 s" in page
    assert "<td>∞</td>" in page and ">inf<" not in page


# -- the disk guard and the kept run (a reviewer's findings) -------------------------------


def _disk_free(monkeypatch: pytest.MonkeyPatch, free: Callable[[], int]) -> None:
    """The output disk has ``free()`` bytes free, as the guard sees it (each look)."""
    import shutil
    from collections import namedtuple

    import pfeie._job as job_module

    usage = namedtuple("usage", "total used free")
    monkeypatch.setattr(job_module, "DISK_CHECK_S", 0.0)
    monkeypatch.setattr(job_module.shutil, "disk_usage",
                        lambda _p: usage(1 << 40, 0, free()))  # fmt: skip
    assert shutil.disk_usage is job_module.shutil.disk_usage


def test_a_rerun_short_of_disk_gives_up_the_kept_run_first(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, caplog: pytest.LogCaptureFixture,
    capsys: pytest.CaptureFixture[str],
) -> None:
    """Keeping the completed run while its re-run goes needs room for both, and a re-run
    that completed before stopped for want of space (a reviewer's tmpfs). The guard now
    deletes the kept run, with a warning, before it stops a run; a re-run that would not
    start for want of space is refused before anything in the folder changes; a folder
    in the kept file's place is not an error; and every stop names the command that
    resumes the run, with its options."""
    import h5py

    out = tmp_path / "out"
    p = _write(tmp_path, SMALL, duration=0.05)
    assert main(["run", str(p), "--quiet"]) == 0
    ref = _final_u(out / "results.h5")
    # the disk is short while the kept run is there: it goes, the re-run completes
    _disk_free(monkeypatch, lambda: (10 if (out / "results.previous.h5").exists() else 900) << 20)
    with caplog.at_level(logging.WARNING, logger="pfeie"):
        assert main(["run", str(p), "--quiet"]) == 0
    assert "results.previous.h5 deleted: the disk of" in caplog.text
    assert not (out / "results.previous.h5").exists()
    done = _final_u(out / "results.h5")
    assert done[:2] == ref[:2]
    np.testing.assert_array_equal(done[2], ref[2])
    # 1 MiB free: refused, the former run and its summaries as they were
    _disk_free(monkeypatch, lambda: 1 << 20)
    capsys.readouterr()
    assert main(["run", str(p), "--quiet"]) == 2
    assert "the run is not started: the disk of" in capsys.readouterr().err
    assert (out / "summary.json").is_file() and _final_u(out / "results.h5")[0]
    # a stopped run there is not moved aside by a re-run refused for want of space
    _disk_free(monkeypatch, lambda: 1 << 20)
    with h5py.File(out / "results.h5", "r+") as f:  # (as a stop leaves it, checkpoint kept)
        f.attrs["completed"] = False
    assert main(["run", str(p), "--quiet"]) == 2
    assert (out / "results.h5").is_file() and not (out / "results.stopped.h5").exists()
    with h5py.File(out / "results.h5", "r+") as f:
        f.attrs["completed"] = True
    # a folder where the kept file goes: the re-run overwrites, with a warning
    monkeypatch.undo()
    (out / "results.previous.h5").mkdir()
    with caplog.at_level(logging.WARNING, logger="pfeie"):
        assert main(["run", str(p), "--quiet"]) == 0
    assert "cannot be kept as results.previous.h5" in caplog.text
    # a disk stop of a run with options names the command with them
    from test_review30 import _disk_short_after

    _disk_short_after(monkeypatch, 1)
    capsys.readouterr()
    assert main(["run", str(p), "--set", "output.every=2"]) == 130
    said = capsys.readouterr()
    command = f"`pfeie run {p} --resume --set output.every=2`"
    assert f"then {command} continues the run" in said.out + said.err
    assert "`pfeie run --resume" not in said.out + said.err


def test_a_study_without_histories_needs_little_room(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """A study that keeps no histories writes a row of a few kB a run, and it was refused
    on a disk with 30 MiB free for want of "the 64 MiB a checkpoint and the summaries
    need" (a reviewer's tmpfs). Its margin is 1 MiB now."""
    from test_study import STUDY, setup

    p = setup(tmp_path, STUDY, n=1, seconds=0.3)
    _disk_free(monkeypatch, lambda: 30 << 20)
    assert main(["study", str(p), "--quiet"]) == 0
    _disk_free(monkeypatch, lambda: 1 << 19)
    capsys.readouterr()
    assert main(["study", str(p), "--quiet", "--restart"]) == 2
    assert "less than the 1 MiB the study's rows and tables need" in capsys.readouterr().err


# -- provenance (a determinism tester's findings) ------------------------------------------


def test_the_sparse_solver_is_recorded_and_never_mixed(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str],
    caplog: pytest.LogCaptureFixture,
) -> None:
    """The sparse solver changes the last bits of a run (CHOLMOD against SuperLU: 38 of
    70 datasets of the demo, 1e-13 relative), and nothing recorded it: a resume under
    another solver wrote one file with two, and a study gathered from machines with
    different installs mixed their rows (22 cells of a table differed from the one
    machine's). The solver is now in the results file and in the run key: the resume is
    refused naming it, a study's rows of another solver are run again, and a study
    worker with another solver refuses to run."""
    import dataclasses

    from pfeie.linalg import solver_stack
    from pfeie.study import Study
    from pfeie.study._study import system
    from test_study import STUDY, setup

    here = solver_stack()
    if here == "superlu":
        pytest.skip("needs CHOLMOD (pfeie[fast]) besides SuperLU")
    p = _write(tmp_path, SMALL, duration=0.05)
    monkeypatch.setenv("PFEIE_SOLVER", "superlu")
    assert main(["run", str(p), "--quiet"]) == 0
    with Results(tmp_path / "out" / "results.h5") as res:
        assert res.f.attrs["solver_stack"] == "superlu"
    monkeypatch.delenv("PFEIE_SOLVER")
    capsys.readouterr()
    assert main(["run", str(p), "--quiet", "--resume", "--duration", "0.1"]) == 2
    assert (f"cannot resume: the sparse solver differs: 'superlu' for the run in the file, "
            f"{here!r} here") in capsys.readouterr().err  # fmt: skip
    # a study's rows of SuperLU are not kept by a study on CHOLMOD
    (tmp_path / "st").mkdir()
    s = setup(tmp_path / "st", STUDY, n=1, seconds=0.3)
    monkeypatch.setenv("PFEIE_SOLVER", "superlu")
    assert main(["study", str(s), "--quiet"]) == 0
    monkeypatch.delenv("PFEIE_SOLVER")
    with caplog.at_level(logging.WARNING, logger="pfeie"):
        assert main(["study", str(s), "--quiet"]) == 0
    assert f"a study of another sparse solver ('superlu', here {here!r})" in caplog.text
    rows = list((tmp_path / "st" / "study" / "rows").glob("*.json"))
    assert len(rows) == 4  # two keys a run: SuperLU's and CHOLMOD's
    # the time steps' own backend (analysis.backend) is named beside the static state's
    steps = tmp_path / "steps"
    steps.mkdir()
    p = _write(steps, SMALL.replace("[analysis]", '[analysis]\nbackend = "superlu"'),
               duration=0.05)  # fmt: skip
    assert main(["run", str(p), "--quiet"]) == 0
    with Results(steps / "out" / "results.h5") as res:
        assert res.f.attrs["solver_stack"] == f"{here}; steps superlu"
    # a worker whose solver is not the study's refuses
    ctx = Study.from_file(s).context()
    assert ctx.solver == here
    with pytest.raises(pf.PfeieError, match=r"this worker's sparse solver is .*, the "
                       r"study's 'superlu'"):  # fmt: skip
        system(dataclasses.replace(ctx, solver="superlu", model_key="other"))


def test_the_digest_of_a_python_run_holds_its_start_state(tmp_path: Path) -> None:
    """``run_to_folder(start=...)`` recorded the same ``model_sha256`` for two runs from
    different start states (the ends of runs under 1 g and 3 g), whose histories differ
    (a tester's finding): the digest, "of what determines the run", now holds the start
    state's arrays. The same start gives the same digest, bit for bit."""
    from pfeie.io import Job
    from test_checkpoint import block_on_base

    model = block_on_base(joint=pf.Joint(phi=30.0))
    dyn = pf.Dynamic(model, 0.005)
    g = [pf.GroundMotion.from_function(lambda t, k=k: k * 9.81, duration=0.1, dt=0.005)
         for k in (1.0, 3.0)]  # fmt: skip
    st = pf.solve_static(model)
    ends = [dyn.run(0.05, ground=[gk], start=st).final for gk in g]

    def digest(start: object) -> str:
        return Job.of_run(model, dyn.settings, records=g[:1], duration=0.1, start=start,
                          system=dyn.system).digest  # fmt: skip

    assert digest(ends[0]) != digest(ends[1])
    assert digest(ends[0]) == digest(dyn.run(0.05, ground=g[:1], start=st).final)
    assert len({digest(ends[0]), digest(st), digest(None)}) == 3
    # the results files of run_to_folder from the two ends, and from the first again
    shas = []
    for k, start in enumerate([ends[0], ends[1], dyn.run(0.05, ground=g[:1], start=st).final]):
        pf.run_to_folder(dyn, 0.05, tmp_path / str(k), ground=g[:1], start=start,
                         paraview=False, figures=False)  # fmt: skip
        with Results(tmp_path / str(k) / "results.h5") as f:
            shas.append(f.meta["model_sha256"])
    assert shas[0] != shas[1] and shas[0] == shas[2]


def test_the_summary_gives_the_run_key(tmp_path: Path) -> None:
    """``model_sha256``, the only digest of the summaries, is of the model file's own
    bytes: a changed mesh, record or ``--set`` left it as it was (documented, but the
    summaries carried nothing else). They now give the run key, which holds them."""
    import json

    p = _write(tmp_path, SMALL, duration=0.05)
    keys = []
    for extra in ([], ["--set", "materials.concrete.E=2e9"]):
        assert main(["run", str(p), "--quiet", *extra]) == 0
        s = json.loads((tmp_path / "out" / "summary.json").read_text())
        with Results(tmp_path / "out" / "results.h5") as res:
            assert s["model"]["run_key"] == res.f.attrs["run_key"]
        keys.append((s["model"]["sha256"], s["model"]["run_key"]))
        text = (tmp_path / "out" / "summary.txt").read_text()
        assert f"run key {s['model']['run_key'][:12]}" in text
    assert keys[0][0] == keys[1][0] and keys[0][1] != keys[1][1]


# -- water loads (a hydraulic-loads reviewer's findings) -----------------------------------


def test_westergaard_puts_no_mass_below_the_reservoir_bottom() -> None:
    """A wet face that reaches below the reservoir's ``bottom`` (into the foundation or
    the silt) took Westergaard's mass there too, with depths beyond H: 65.4 t of 202.1 t
    on a reviewer's dam with its bottom 5 m up the face. The mass now stops at the
    bottom: the total is the closed form 7/12 ρ_w H² with H = h − z_b, and the nodes
    below the bottom carry none."""
    mesh = pf.rectangle(1.0, 20.0, 1, 8)  # nodes every 2.5 m: one at the bottom, 5 m
    model = pf.Model(mesh, [pf.Block("all", pf.Elastic(30e9, 0.2, 2400.0))])
    model.add_westergaard("xmin", water_level=20.0, bottom=5.0)
    m = model.added_mass().reshape(-1, 2)[:, 0]
    assert m.sum() == pytest.approx(7 / 12 * 1000.0 * 15.0**2, rel=1e-12)  # measured 0
    assert m[mesh.points[:, 1] < 5.0 - 1e-9].sum() == 0.0
    whole = pf.Model(mesh, [pf.Block("all", pf.Elastic(30e9, 0.2, 2400.0))])
    whole.add_westergaard("xmin", water_level=20.0)  # the bottom at the face's foot
    assert whole.added_mass().sum() == pytest.approx(7 / 12 * 1000.0 * 20.0**2, rel=1e-12)


def test_water_loads_under_a_tilted_gravity_are_warned(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    """Hydrostatic, uplift and Westergaard loads take the mesh's y (z in 3D) as the
    vertical; under a tilted ``gravity_direction`` (a mesh drawn in a slope's own axes)
    their heads were those of the untilted model without a word (a reviewer's 20° tilt:
    the heel's head 12.0 m where cos 20° × 12.0 = 11.3 m lies along gravity). Warned
    now, naming the loads and the tilt."""
    from pfeie.io import load_job
    from test_robustness import MODEL, model

    text = MODEL.replace("[analysis]", "[loads]\ngravity = 9.81\ngravity_direction = "
                         "[0.3420201433, -0.9396926208]\n[[loads.hydrostatic]]\n"
                         'groups = ["top"]\nwater_level = 3.0\n[analysis]')  # fmt: skip
    with caplog.at_level(logging.WARNING, logger="pfeie"):
        load_job(model(tmp_path, text=text))
    assert ("loads.gravity_direction is tilted 20° from −y, and the water loads "
            "(hydrostatic) take y as the vertical") in caplog.text
