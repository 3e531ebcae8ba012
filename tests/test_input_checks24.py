"""The findings of a new user who ran many records into study folders (nu24) and of a
reader of the docs: the folder lock under a simultaneous start, history folders that two
record names would share, a record copied under two names, study and run folders kept
apart, histories switched on later, the coarse-sampling warning in a study, the median
table's column names in full, and the cut record's note only where the peak is lost.
"""

from __future__ import annotations

import contextlib
import logging
import shutil
import threading
from pathlib import Path
from typing import Any

import h5py
import numpy as np
import pytest

from conftest import cli_fails
from pfeie.cli import main
from pfeie.io import applied_part
from pfeie.model import GroundMotion
from test_study import MODEL, STUDY, setup


def _one_second(text: str) -> str:
    return text + "[analysis]\nduration = 0.3\n"


def _stacked_boxes() -> tuple[Any, Any]:
    """A 2 × 2 × 2 m box of hexahedra cut at z = 1 m into "rock" and "block" by the facet
    group "joint", with "bottom" its base: the mesh and the rock's material."""
    import pfeie as pf

    mesh = pf.box(2.0, 2.0, 2.0, 3, 3, 2)
    mesh.add_cell_group("rock", lambda x: x[:, 2] < 1.0)
    mesh.add_cell_group("block", lambda x: x[:, 2] > 1.0)
    mesh.add_facet_group("joint", lambda x: np.abs(x[:, 2] - 1.0) < 1e-9, boundary_only=False)
    mesh.add_facet_group("bottom", lambda x: x[:, 2] < 1e-9)
    return mesh, pf.Elastic(1e9, 0.25, 2000.0)


@pytest.mark.parametrize("lock", ["flock", "no flock", "no fcntl"])
def test_two_runs_started_together_cannot_both_take_the_folder(
    lock: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Two runs that start at the same moment (a job array) race for the output folder's
    lock: at most one takes it, in each of 200 trials with two threads released together
    (a tester's finding: the lock file was created, then its process id written, and a
    second run that read it empty in between removed it as stale and took it: both took
    the lock in 83 of 200 such trials; 56 and 87 of 200 in two runs of this test before
    the change). The same where the operating system has no flock for the file (ENOLCK
    on some network mounts: the file alone, created with its content in one step; 67 of
    200 before) or no fcntl at all."""
    import errno
    import fcntl
    import sys

    from pfeie._job import FolderLock
    from pfeie.errors import InputError

    if lock == "no flock":

        def no_lock(fd: int, op: int) -> None:
            raise OSError(errno.ENOLCK, "No locks available")

        monkeypatch.setattr(fcntl, "flock", no_lock)
    elif lock == "no fcntl":
        monkeypatch.setitem(sys.modules, "fcntl", None)  # import fcntl: ImportError

    both = 0
    for trial in range(200):
        folder = tmp_path / str(trial)
        folder.mkdir()
        gate, done = threading.Barrier(2), threading.Barrier(2)
        taken: list[bool | BaseException] = []

        def take(folder: Path = folder, gate: threading.Barrier = gate,
                 done: threading.Barrier = done,
                 taken: list[bool | BaseException] = taken) -> None:  # fmt: skip
            gate.wait(timeout=30)
            lock = FolderLock(folder, folder / "m.toml")
            try:
                lock.__enter__()
            except InputError:
                taken.append(False)
                done.wait(timeout=30)
                return
            except BaseException as exc:  # reported below, never a hang
                taken.append(exc)
                done.abort()
                return
            taken.append(True)
            with contextlib.suppress(threading.BrokenBarrierError):
                done.wait(timeout=30)  # hold it until both have tried
            lock.__exit__(None, None, None)

        threads = [threading.Thread(target=take) for _ in range(2)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        assert not [x for x in taken if isinstance(x, BaseException)], (trial, taken)
        assert any(taken), trial
        both += all(taken)
        assert not (folder / ".pfeie-run.lock").exists()
    assert both == 0


def test_two_record_names_one_folder_name(tmp_path: Path) -> None:
    """Records `a b.csv` and `a_b.csv` with histories on: before, both runs of an
    intensity wrote `runs/a_b_0.2` (the second run's file in the first's folder, the
    first's history lost); now each has its own folder with a hash of its name and
    value, and the file's attributes name its row, record and intensity."""
    p = setup(tmp_path, _one_second(STUDY.replace("[0.2, 0.5]", "[0.2]")), n=2)
    rec = tmp_path / "rec"
    (rec / "r0.csv").rename(rec / "a b.csv")
    (rec / "r1.csv").rename(rec / "a_b.csv")
    p.write_text(p.read_text().replace('folder = "study"', 'folder = "study"\nhistories = true'))
    assert main(["study", str(p), "--quiet"]) == 0
    runs = sorted((tmp_path / "study" / "runs").iterdir())
    assert len(runs) == 2 and all(r.name.startswith("a_b_0.2-") for r in runs)
    rows = {r.stem for r in (tmp_path / "study" / "rows").glob("*.json")}
    seen = set()
    for r in runs:
        with h5py.File(r / "results.h5", "r") as f:
            assert f.attrs["study_key"] in rows and f.attrs["study_intensity"] == 0.2
            seen.add(str(f.attrs["study_record"]))
            assert len(str(f.attrs["study_record_sha256"])) == 64
    assert seen == {"a b", "a_b"}


def test_a_record_copied_under_two_names(tmp_path: Path,
                                         capsys: pytest.CaptureFixture[str]) -> None:  # fmt: skip
    """Two files with the same bytes (and reading options): before, one run counted as two
    rows of the medians; now refused before any run, naming both files."""
    p = setup(tmp_path, _one_second(STUDY), n=2)
    shutil.copy(tmp_path / "rec" / "r0.csv", tmp_path / "rec" / "r0_copy.csv")
    cli_fails(capsys, ["study", str(p)], "r0_copy.csv: the same record as", "r0.csv",
              "expected each ground motion once")  # fmt: skip
    assert not (tmp_path / "study" / "rows").is_dir() or not any(
        (tmp_path / "study" / "rows").iterdir())  # fmt: skip


def test_study_and_run_folders_kept_apart(tmp_path: Path, caplog: pytest.LogCaptureFixture,
                                          capsys: pytest.CaptureFixture[str]) -> None:  # fmt: skip
    """A study into a folder holding a run's results.h5 is refused, and a run into a
    study's folder (it removed the study's report.html); a study into the folder of a
    study of other settings warns that its histories stay."""
    p = setup(tmp_path, _one_second(STUDY.replace("[0.2, 0.5]", "[0.2]")), n=1)
    model = tmp_path / "model.toml"
    model.write_text(MODEL.replace("friction_angle = 20.0", "friction_angle = 25.0"))
    assert main(["study", str(p), "--quiet"]) == 0
    model.write_text(MODEL.replace('folder = "out"', 'folder = "study"')
                     .replace("[analysis]", "[[ground_motion]]\nfile = \"rec/r0.csv\"\n"
                              "units = \"g\"\n[analysis]\nduration = 0.1"))  # fmt: skip
    cli_fails(capsys, ["run", str(model), "--quiet"], "output.folder",
              "holds the outputs of a `pfeie study` (study.json)")  # fmt: skip
    assert (tmp_path / "study" / "report.html").exists()
    model.write_text(model.read_text().replace('folder = "study"', 'folder = "one"'))
    assert main(["run", str(model), "--quiet"]) == 0
    other = tmp_path / "other.toml"
    other.write_text(p.read_text().replace('folder = "study"', 'folder = "one"'))
    cli_fails(capsys, ["study", str(other)], "output.folder",
              "holds the results of a `pfeie run` (results.h5)")  # fmt: skip
    model.write_text(MODEL)  # another model (friction angle 20°) into the study's folder
    with caplog.at_level(logging.WARNING):
        assert main(["study", str(p), "--quiet"]) == 0
    assert "holds the outputs of a study of another model, other settings or another pfeie" \
           " version" in caplog.text


def test_histories_switched_on_later(tmp_path: Path, caplog: pytest.LogCaptureFixture,
                                     capsys: pytest.CaptureFixture[str]) -> None:  # fmt: skip
    """A study run without histories, then with `histories = true`: before, the kept
    rows counted as done and no history was written; now they are run again (a warning
    with their number), and a third run keeps them all, saying so."""
    p = setup(tmp_path, _one_second(STUDY.replace("[0.2, 0.5]", "[0.2]")), n=2)
    assert main(["study", str(p), "--quiet"]) == 0
    p.write_text(p.read_text().replace('folder = "study"', 'folder = "study"\nhistories = true'))
    with caplog.at_level(logging.WARNING):
        assert main(["study", str(p), "--quiet"]) == 0
    assert "2 run(s) done before have no history of theirs under runs/" in caplog.text
    assert len(list((tmp_path / "study" / "runs").glob("*/results.h5"))) == 2
    capsys.readouterr()
    assert main(["study", str(p)]) == 0
    assert "study: 2 of 2 runs kept from before" in capsys.readouterr().err


def test_a_study_warns_of_a_coarsely_sampled_record(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    """A record sampled every 0.2 s: `pfeie check` of a model file warned (times or dt in
    ms?), a study did not; now it does, naming records[0]."""
    p = setup(tmp_path, _one_second(STUDY.replace("[0.2, 0.5]", "[0.2]")), n=1)
    t = np.arange(0.0, 4.0, 0.2)
    np.savetxt(tmp_path / "rec" / "r0.csv", np.c_[t, 0.3 * np.sin(t)], delimiter=",")
    with caplog.at_level(logging.WARNING):
        assert main(["study", str(p), "--quiet"]) == 0
    assert "records[0]" in caplog.text and "is sampled every 0.2 s" in caplog.text


def test_the_median_table_names_its_columns_in_full(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The terminal's median table cut long names from the left
    (`e.upstream_mid.peak_displacement_m`); now each column is as wide as its name."""
    p = setup(tmp_path, _one_second(STUDY.replace("[0.2, 0.5]", "[0.2]")), n=1)
    assert main(["study", str(p)]) == 0
    out = capsys.readouterr().out.splitlines()
    head = out[out.index("median over the records:") + 1]
    assert "probe.top.peak_displacement_m" in head.split()
    assert len(out[out.index("median over the records:") + 2]) == len(head)


def test_a_peak_just_beyond_the_end_is_no_news() -> None:
    """A record whose peak lies just beyond the end of the run, where the interpolation
    at the end reaches 0.99998 of it: no note (before, a warning that its PGA lies beyond
    the run); at 0.5 of it the note stays."""
    t = np.arange(0.0, 4.0, 0.01)
    a = np.sin(np.pi * t / 4.0)  # the peak at 2.0 s
    gm = GroundMotion.from_samples(a, time=t, units="g")
    assert applied_part(gm, 1.99)[1] is None  # 0.99998 of the PGA applied
    note = applied_part(gm, 0.7)[1]
    assert note is not None and "lies beyond the end of the run" in note


def test_ctrl_c_while_pfeie_loads(monkeypatch: pytest.MonkeyPatch,
                                  capsys: pytest.CaptureFixture[str]) -> None:  # fmt: skip
    """Ctrl-C in the half second in which the `pfeie` command imports numpy and scipy,
    before its handlers are installed: a KeyboardInterrupt traceback before; now the
    console script's module (outside the package) ends with exit 130 and one line. The
    import is interrupted here by a finder that raises KeyboardInterrupt (with a real
    SIGINT 0.05 to 0.6 s after the start: exit 130 and that line each time)."""
    import importlib.abc
    import sys

    import _pfeie_cli

    class Interrupt(importlib.abc.MetaPathFinder):
        def find_spec(self, name: str, path: object, target: object = None) -> None:
            if name == "pfeie.cli":
                raise KeyboardInterrupt
            return None

    monkeypatch.delitem(sys.modules, "pfeie.cli", raising=False)
    monkeypatch.setattr(sys, "meta_path", [Interrupt(), *sys.meta_path])
    assert _pfeie_cli.main() == 130
    err = capsys.readouterr().err
    assert err == "pfeie: interrupted (SIGINT) while starting; nothing was run\n"


def test_a_file_system_without_flock(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Where flock is not supported (ENOLCK on some network mounts) the lock falls back to
    the process id in the file: a run takes the folder, and a live process's lock file is
    still refused (not "cannot take the lock" for every run)."""
    import errno
    import fcntl
    import os

    from pfeie._job import FolderLock
    from pfeie.errors import InputError

    def no_lock(fd: int, op: int) -> None:
        raise OSError(errno.ENOLCK, "No locks available")

    monkeypatch.setattr(fcntl, "flock", no_lock)
    with FolderLock(tmp_path, tmp_path / "m.toml"):
        text = (tmp_path / ".pfeie-run.lock").read_text()
        assert text == f"{os.getpid()}\n{tmp_path / 'm.toml'}\n"
    assert not (tmp_path / ".pfeie-run.lock").exists()
    (tmp_path / ".pfeie-run.lock").write_text(f"{os.getpid()}\nother.toml\n")
    with pytest.raises(InputError, match=r"another pfeie run \(pid \d+, model other.toml\)"):
        FolderLock(tmp_path, tmp_path / "m.toml").__enter__()


@pytest.mark.parametrize("group", ["joint", "bottom"])
def test_facets_of_another_shape_than_the_cells_faces(group: str) -> None:
    """A 3D tester's mesh: a joint (or a support's surface) meshed in triangles on a block
    of hexahedra: a ValueError traceback from the facet matching before; now a MeshError
    naming the group, the facets' type and the cells' faces (a ModelError from the
    Python API, which wraps the mesh's errors; exit 2 from `pfeie check`)."""
    import pfeie as pf
    from pfeie.errors import ModelError

    mesh, rock = _stacked_boxes()
    quads = mesh.facet_groups[group].pop("quad")
    mesh.facet_groups[group]["triangle"] = np.concatenate([quads[:, :3], quads[:, [0, 2, 3]]])
    with pytest.raises(ModelError, match=rf"'{group}': its facets are triangle \(3 corners\), "
                       "but the faces of the block cells have 4 corners"):  # fmt: skip
        model = pf.Model(mesh, [pf.Block("rock", rock), pf.Block("block", rock)],
                         interfaces=[pf.Interface("joint", pf.Joint(phi=30.0))])  # fmt: skip
        model.fix("bottom")


def test_a_record_says_its_direction() -> None:
    """One file applied along x, y and obliquely: the lines of `pfeie check` and of the
    run's summary were the same for each (a 3D tester could not see an x/y swap); the
    record's line now ends with its direction."""
    t = np.arange(0.0, 1.0, 0.01)
    a = np.sin(2 * np.pi * t)
    lines = [GroundMotion.from_samples(a, time=t, units="g", name="ec", direction=e).summary()
             for e in ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.8, 0.6, 0.0])]  # fmt: skip
    assert [line.split("dt 0.01 s, ")[1] for line in lines] == [
        "along x", "along y", "along (0.8, 0.6, 0)"]  # fmt: skip


def test_a_probe_outside_its_block_is_warned(tmp_path: Path,
                                             caplog: pytest.LogCaptureFixture) -> None:  # fmt: skip
    """Probes that the nearest node snapped silently (a 3D tester's: 0.8 m above the top,
    and one in the rock given with the block above it): a warning naming the point, where
    it lies and the node taken; a point on the model, none; the error beyond a cell names
    the block whose nearest node it measured, not a node number of the split mesh."""
    from test_cli import SMALL, _write

    probes = ('probes = { top = [1.0, 2.0], out = [1.0, 2.2], '
              'wrong = { at = [1.0, 0.85], block = "dam" } }')  # fmt: skip
    p = _write(tmp_path, SMALL.replace("probes = { top = [1.0, 2.0] }", probes))
    with caplog.at_level(logging.WARNING):
        assert main(["check", str(p)]) == 0
    assert "output.probes.top" not in caplog.text
    assert ("output.probes.out: the point [1.0, 2.2] lies outside the model's cells; the "
            "nearest node of the mesh, at [1, 2] (0.2 m away), is taken") in caplog.text
    assert ("output.probes.wrong: the point [1.0, 0.85] lies in block 'rock', not in block "
            "'dam'; the nearest node of block 'dam', at [1, 1] (0.15 m away)") in caplog.text


def test_the_static_figure_of_a_3d_joint_is_a_map(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The static figure of a 3D joint joined its pairs along one axis in one polyline (a
    sawtooth of vertical strokes, each row of pairs at one position); now the joint is
    drawn in its plane, as the joint map (no ordering along an axis is asked for)."""
    import pfeie as pf
    from pfeie.plot import _plots

    mesh, rock = _stacked_boxes()
    model = pf.Model(mesh, [pf.Block("rock", rock), pf.Block("block", rock)],
                     interfaces=[pf.Interface("joint", pf.Joint(phi=30.0))])  # fmt: skip
    model.fix("zmin")
    model.add_gravity()
    from pfeie.io import Results

    gm = pf.GroundMotion.from_function(lambda t: 0.0 * t, duration=0.01, dt=0.005,
                                       direction=(1, 0, 0))  # fmt: skip
    pf.run_to_folder(pf.Dynamic(model, 0.005), 0.01, tmp_path / "run", ground=[gm],
                     start=pf.solve_static(model), figures=False, paraview=False)  # fmt: skip

    def no_axis(x: np.ndarray) -> None:
        raise AssertionError("a 3D joint ordered along one axis")

    monkeypatch.setattr(_plots, "_arc", no_axis)
    with Results(tmp_path / "run" / "results.h5") as res:
        out = _plots.plot_static(res, "joint", tmp_path / "static_joint.png")
    assert out.stat().st_size > 10_000


@pytest.mark.parametrize("command", ["check", "run"])
def test_a_study_file_given_as_a_model_file(
    command: str, capsys: pytest.CaptureFixture[str]
) -> None:
    """`pfeie check study.toml`: nine unknown-key and missing-key errors, one per table of
    the study; now one line that names the study file and `pfeie study`."""
    study = Path(__file__).resolve().parents[1] / "examples" / "study" / "study.toml"
    assert main([command, str(study)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "this is a study file (model = '../koyna/koyna.toml'" in err[0]
    assert f"`pfeie study {study}`" in err[0]


def test_a_model_file_given_as_a_study_file(capsys: pytest.CaptureFixture[str]) -> None:
    """`pfeie study koyna.toml`: an error for every table of the model file before; now
    one line that names it and `pfeie run`."""
    model = Path(__file__).resolve().parents[1] / "examples" / "koyna" / "koyna.toml"
    assert main(["study", str(model)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "expected a study file; this is a model file" in err[0]
    assert "`pfeie run`" in err[0]


def test_a_kept_row_with_another_runs_history(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    """A reviewer's finding: a study of model A, then of model B into the same folder
    (B's history replaces A's in runs/r0_0.2), then of A again: A's row was kept beside B's
    history. Now a kept row needs its own history (the file's study_key): A runs again,
    and its history is A's."""
    import json

    p = setup(tmp_path, _one_second(STUDY.replace("[0.2, 0.5]", "[0.2]")), n=1)
    p.write_text(p.read_text().replace('folder = "study"', 'folder = "study"\nhistories = true'))
    model = tmp_path / "model.toml"

    def key() -> str:
        rows = list((tmp_path / "study" / "rows").glob("*.json"))
        with h5py.File(tmp_path / "study" / "runs" / "r0_0.2" / "results.h5", "r") as f:
            assert any(r.stem == f.attrs["study_key"] for r in rows)
            return str(f.attrs["study_key"])

    assert main(["study", str(p), "--quiet"]) == 0
    a = key()
    model.write_text(MODEL.replace("friction_angle = 20.0", "friction_angle = 25.0"))
    assert main(["study", str(p), "--quiet"]) == 0
    b = key()
    model.write_text(MODEL)
    with caplog.at_level(logging.WARNING):
        assert main(["study", str(p), "--quiet"]) == 0
    assert "1 run(s) done before have no history of theirs" in caplog.text
    assert key() == a != b
    assert json.loads((tmp_path / "study" / "study.json").read_text())["runs"] == 1


@pytest.mark.parametrize("argv", [["schema", "--out", "a\x00b"], ["check", "x\x00.toml"],
                                  ["run", "m.toml", "--set", "a=\x00"]])  # fmt: skip
def test_a_nul_character_in_an_argument(argv: list[str],
                                        capsys: pytest.CaptureFixture[str]) -> None:  # fmt: skip
    """The slow fuzzer's `pfeie schema --out 'a\\x00b'`: a ValueError traceback from open;
    now exit 2 naming the command, the argument and the value, for any command."""
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert f"pfeie: error: {argv[0]}: " in err and "holds a NUL character" in err
    assert "Traceback" not in err
