"""Checkpoint and resume: a stopped run continues from the checkpoint in its results file
and gives the same bits as a run that was never stopped (the reference is that run, an
independent computation); inputs that changed are refused."""

from __future__ import annotations

import json
import signal
import time
from pathlib import Path

import h5py
import numpy as np
import pytest

import pfeie as pf
from pfeie.cli import main
from pfeie.io import Results
from pfeie.verification._models import block_on_base
from test_cli import SMALL, _write, start_run

G = 9.81
_HISTORY = ("rigid", "X", "w", "s", "state", "broken", "probe_u", "probe_a")


def test_resume_gives_the_same_bits() -> None:
    """A bonded block (c = 2 kPa, σ_t = 1 kPa) shaken at 0.8 g, 2 Hz: it breaks, slides and
    sticks. Run for 1 s at once, and for 0.5 s then resumed from its last checkpoint by a
    new analysis object (as a new process would): every history, the energy terms and the
    recorded times are identical (recording every 3rd step, so that the stop falls off
    the recording grid)."""
    model = block_on_base(joint=pf.Joint(c=2e3, phi=30.0, tensile=1e3, initial="intact"),
                          E=10e9, n=4, width=2.0)  # fmt: skip
    gm = pf.GroundMotion.from_function(lambda t: 0.8 * G * np.sin(4 * np.pi * t), 1.5, 1e-3)
    static = pf.solve_static(model)
    node = [model.nearest_node([1.0, 1.5])]
    kw = {"ground": [gm], "every": 3, "probes": node}
    full = pf.Dynamic(model, 0.002).run(1.0, start=static, **kw)
    cks: list[pf.dynamics.Checkpoint] = []
    part = pf.Dynamic(model, 0.002).run(0.5, start=static, on_checkpoint=cks.append, **kw)
    ck = cks[-1]
    # the last checkpoint at the last row on the grid; the run's last step, 250, is
    # recorded after it (a run's end is never dropped) but is no checkpoint
    assert ck.state.step == 249 and ck.row == part.t.size - 2
    assert part.t[-1] == pytest.approx(0.5)
    rest = pf.Dynamic(model, 0.002).run(n_steps=500 - ck.state.step, resume=ck, **kw)
    assert full.broken[-1].all() and np.abs(full.slip[-1]).max() > 1e-5  # it did slide
    k = ck.row + 1
    np.testing.assert_array_equal(np.r_[part.t[:k], rest.t[1:]], full.t)
    for key in _HISTORY:
        both = np.concatenate([getattr(part, key)[:k], getattr(rest, key)[1:]])
        np.testing.assert_array_equal(both, getattr(full, key), err_msg=key)
    for key, values in full.energy.items():
        np.testing.assert_array_equal(np.r_[part.energy[key][:k], rest.energy[key][1:]],
                                      values, err_msg=key)  # fmt: skip


def _histories(path: Path) -> dict[str, np.ndarray]:
    with Results(path) as res:
        out = {"time": res.time, **{f"pairs/{k}": v for k, v in res.pairs().items()}}
        out.update({f"energy/{k}": v for k, v in res.energy().items()})
        out.update({f"probe/{k}": v for k, v in res.probe("top").items()})
        out["rigid"] = res.rigid(1)
        t_f, fields = res.fields()
        out["fields/time"] = t_f
        out.update({f"envelope/{k}": v for k, v in res.envelope().items()})
        out.update({f"fields/{k}": v for k, v in fields.items()})
        assert res.completed
    return out


def run_then_stop(tmp_path: Path, text: str, duration: float, first: float) -> Path:
    """``pfeie run`` of the model file ``text`` for ``duration`` in ``tmp_path/ref`` (the
    reference), and in ``tmp_path/ext`` for ``first`` only (a run to resume): the model
    file of the latter."""
    ref_dir, ext_dir = tmp_path / "ref", tmp_path / "ext"
    ref_dir.mkdir()
    ext_dir.mkdir()
    assert main(["run", str(_write(ref_dir, text, duration=duration)), "--quiet"]) == 0
    p = _write(ext_dir, text, duration=duration)
    assert main(["run", str(p), "--quiet", "--duration", str(first)]) == 0
    return p


def test_command_line_resume_after_sigint_and_extension(tmp_path: Path) -> None:
    """``pfeie run --resume``: (a) a run stopped by SIGINT continues to its duration; (b) a
    completed run of 1 s extended with ``--duration 3``. Both results files equal, array
    for array, that of one uninterrupted run of 3 s (fields included), and their times
    increase strictly (no row written twice)."""
    ref_dir, ext_dir, sig_dir = (tmp_path / k for k in ("ref", "ext", "sig"))
    for d in (ref_dir, ext_dir, sig_dir):
        d.mkdir()
    text = SMALL.replace('folder = "out"', 'folder = "out"\nfield_every = 7')
    assert main(["run", str(_write(ref_dir, text, duration=3.0)), "--quiet"]) == 0
    ref = _histories(ref_dir / "out" / "results.h5")
    p = _write(ext_dir, text, duration=3.0)
    assert main(["run", str(p), "--quiet", "--duration", "1.0"]) == 0
    assert main(["run", str(p), "--quiet", "--resume"]) == 0
    p = _write(sig_dir, text, duration=3.0)
    proc = start_run(p, wait=0.0)
    proc.send_signal(signal.SIGINT)
    proc.communicate(timeout=120)
    with Results(sig_dir / "out" / "results.h5") as res:
        stopped_at = float(res.time[-1])
        assert not res.completed
    assert main(["run", str(p), "--quiet", "--resume"]) == 0
    for d in (ext_dir, sig_dir):
        got = _histories(d / "out" / "results.h5")
        assert np.all(np.diff(got["time"]) > 0)
        assert got.keys() == ref.keys()
        for key, value in ref.items():
            np.testing.assert_array_equal(got[key], value, err_msg=f"{d.name}: {key}")
    assert 0 < stopped_at < 3.0  # the signal stopped the run inside its duration
    # the summaries of the resumed runs are that of the uninterrupted one, its static state
    # included (new-user finding: a resume dropped the static joints from the summary)
    want = json.loads((ref_dir / "out" / "summary.json").read_text())
    assert "static_joints" in want
    for d in (ext_dir, sig_dir):
        got = json.loads((d / "out" / "summary.json").read_text())
        assert got.keys() == want.keys(), d.name
        assert got["static_joints"] == want["static_joints"], d.name


def _wait_for_checkpoint(path: Path, row: int, timeout: float = 120.0) -> None:
    """Poll the results file of a running ``pfeie run`` (read without HDF5's file lock)
    until its checkpoint holds at least ``row``."""
    import h5py

    t0 = time.time()
    while time.time() - t0 < timeout:
        try:
            with h5py.File(path, "r", locking=False) as f:
                if "checkpoint" in f and int(f["checkpoint"].attrs["row"]) >= row:
                    return
        except (OSError, KeyError, RuntimeError):  # not created yet, or caught mid-write
            # (h5py raises RuntimeError, e.g. "addr overflow", on a file read mid-write)
            pass
        time.sleep(0.02)
    raise AssertionError(f"{path}: no checkpoint of row {row} within {timeout} s")


@pytest.mark.slow  # 20 s; resume after SIGINT stays in the default run
def test_command_line_resume_after_kill_9(tmp_path: Path) -> None:
    """``pfeie run --resume`` after SIGKILL (no handler runs: the file is left as the
    process had it) at two moments of the run, checkpoints every 0.05 s: early (row 5) and
    at a random step (a row drawn anew at every run of the test, named in a failure); each
    resumed results file equals, array for array, that of one uninterrupted run (fields
    and the final frame included). Measured besides: 10 of 10 kills at random times
    resumed to the same bits."""
    import random
    import subprocess
    import sys

    text = SMALL.replace('folder = "out"', 'folder = "out"\nfield_every = 7\n'
                         "checkpoint_seconds = 0.05")  # fmt: skip
    (tmp_path / "ref").mkdir()
    assert main(["run", str(_write(tmp_path / "ref", text, duration=6.0)), "--quiet"]) == 0
    ref = _histories(tmp_path / "ref" / "out" / "results.h5")
    for row in (5, random.randint(6, 600)):
        d = tmp_path / f"kill{row}"
        d.mkdir()
        p = _write(d, text, duration=6.0)
        proc = subprocess.Popen([sys.executable, "-m", "pfeie", "run", str(p), "--quiet"],
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)  # fmt: skip
        _wait_for_checkpoint(d / "out" / "results.h5", row)
        proc.kill()
        proc.wait(timeout=60)
        assert proc.returncode == -signal.SIGKILL
        with Results(d / "out" / "results.h5") as res:
            assert not res.completed and 0 < res.time[-1] < 6.0, row  # killed inside the run
        assert main(["run", str(p), "--quiet", "--resume"]) == 0
        got = _histories(d / "out" / "results.h5")
        assert got.keys() == ref.keys()
        for key, value in ref.items():
            np.testing.assert_array_equal(got[key], value, err_msg=f"kill at row {row}: {key}")


def test_resume_refuses_other_inputs(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], caplog: pytest.LogCaptureFixture
) -> None:
    """``--resume`` without a results file, or of a run of the same inputs killed before
    its first checkpoint: the run starts from the beginning (a warning says so; nothing
    is lost: the run is deterministic) and gives the bits of a plain run. With another
    friction angle (--set) than the run's, or a file without a checkpoint from other
    inputs: exit 2 and a ``pfeie: error`` line naming the file and the cause."""
    import h5py

    p = _write(tmp_path, SMALL, duration=0.1)
    assert main(["run", str(p), "--quiet", "--resume"]) == 0
    assert "nothing to resume: no results file; running from the start" in caplog.text
    res = next(tmp_path.rglob("results.h5"))
    ref = _histories(res)
    with h5py.File(res, "r+") as f:  # as a run killed before its first checkpoint leaves it
        del f["checkpoint"]
    assert main(["run", str(p), "--quiet", "--resume"]) == 0
    assert "stopped before its first checkpoint; running from the start" in caplog.text
    got = _histories(res)
    assert got.keys() == ref.keys()
    for key, value in ref.items():
        np.testing.assert_array_equal(got[key], value, err_msg=key)
    with h5py.File(res, "r+") as f:
        del f["checkpoint"]
        f.attrs["run_key"] = "another run"
    assert main(["run", str(p), "--quiet", "--resume"]) == 2
    assert "no checkpoint (a run of an older pfeie, or of other inputs)" in (
        capsys.readouterr().err)  # fmt: skip
    assert main(["run", str(p), "--quiet"]) == 0
    capsys.readouterr()
    assert main(["run", str(p), "--quiet", "--resume", "--set",
                 "interfaces.joint.friction_angle=30.0"]) == 2  # fmt: skip
    err = capsys.readouterr().err
    assert "pfeie: error: " in err and "results.h5: cannot resume" in err, err
    assert main(["run", str(p), "--quiet", "--resume"]) == 0  # same inputs: nothing to do
    # a checkpoint of an earlier pfeie, whose energy account had no 'modified' term (its
    # algorithmic sum holds Φ): continuing it would mix two accounts
    import json

    with h5py.File(res, "r+") as f:
        g = f["checkpoint"]
        energy = json.loads(g.attrs["energy"])
        del energy["modified"]
        g.attrs["energy"] = json.dumps(energy)
    capsys.readouterr()
    assert main(["run", str(p), "--quiet", "--resume"]) == 2
    err = capsys.readouterr().err
    assert "cannot resume" in err and "no 'modified' term" in err, err
    # a checkpoint of the earlier account of interface and impact
    assert main(["run", str(p), "--quiet"]) == 0
    with h5py.File(res, "r+") as f:
        del f["checkpoint"].attrs["energy_account"]
    capsys.readouterr()
    assert main(["run", str(p), "--quiet", "--resume"]) == 2
    err = capsys.readouterr().err
    assert "recorded 'interface' and 'impact' otherwise" in err, err
    # a run of another pfeie version (which may compute other numbers): not continued
    assert main(["run", str(p), "--quiet"]) == 0
    with h5py.File(res, "r+") as f:
        f.attrs["pfeie_version"] = "0.0.9"
    capsys.readouterr()
    assert main(["run", str(p), "--quiet", "--resume"]) == 2
    err = capsys.readouterr().err
    assert "written by pfeie 0.0.9, this is pfeie" in err, err


def test_a_stopped_run_is_kept_when_run_again_from_the_start(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    """A run stopped by SIGINT, then run again without --resume (new-user finding: the
    stopped run's results were overwritten without a word): the stopped run is moved to
    results.stopped.h5 with a warning naming its time and how to resume it, and the new
    run completes in results.h5."""
    p = _write(tmp_path, SMALL, duration=3.0)
    proc = start_run(p, wait=0.0)
    proc.send_signal(signal.SIGINT)
    proc.communicate(timeout=120)
    out = tmp_path / "out"
    with Results(out / "results.h5") as res:
        stopped_at = float(res.time[-1])
        assert not res.completed
    with caplog.at_level("WARNING", logger="pfeie"):
        assert main(["run", str(p), "--quiet"]) == 0
    assert "results.stopped.h5" in caplog.text and "--resume" in caplog.text
    with Results(out / "results.stopped.h5") as res:
        assert not res.completed and float(res.time[-1]) == stopped_at
    with Results(out / "results.h5") as res:
        assert res.completed and float(res.time[-1]) == pytest.approx(3.0)


def test_one_run_per_output_folder(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """A run holds a lock on its output folder: a second run while the first is alive
    exits 2 naming the other run's process; a lock left by a process that is gone (a
    killed run) is taken over, even where its process id is in use again; the lock is
    removed at the end of a run."""
    import os

    from conftest import hold_folder

    p = _write(tmp_path, SMALL, duration=0.05)
    (tmp_path / "out").mkdir()
    lock = tmp_path / "out" / ".pfeie-run.lock"
    other = hold_folder(tmp_path / "out")  # another run, alive
    try:
        assert main(["run", str(p), "--quiet"]) == 2
    finally:
        other.kill()
        other.wait()
    err = capsys.readouterr().err
    assert f"another pfeie run (pid {other.pid}, model other.toml)" in err
    # a killed run's lock: the file stays, the operating system's lock went with it
    assert lock.read_text() == f"{other.pid}\nother.toml\n"
    assert main(["run", str(p), "--quiet", "--set", "output.checkpoint_seconds=0"]) == 0
    assert not lock.exists()
    # a lock file that no process holds, whose process id is now this process's (a
    # killed container's run was pid 1, and so is the next): taken over
    lock.write_text(f"{os.getpid()}\nkilled.toml\n")
    assert main(["run", str(p), "--quiet", "--set", "output.checkpoint_seconds=0"]) == 0
    assert not lock.exists()


@pytest.mark.parametrize("scheme", ["nonsmooth-alpha", "moreau-jean", "newmark"])
def test_steps_lie_on_the_time_grid(scheme: str) -> None:
    """Step k of a run is at t₀ + k h, one product, not a running sum of h (which ended a
    10 s demo run at 9.999999999999831 s): 1000 steps of 1 ms end at 1.0 exactly, and
    every recorded time is k·h to the bit, for each scheme (Newmark without joints)."""
    import pfeie as pf

    mesh = pf.rectangle(1.0, 1.0, 1, 2)
    mesh.add_cell_group("base", lambda x: x[:, 1] < 0.5)
    mesh.add_cell_group("block", lambda x: x[:, 1] > 0.5)
    joints = scheme != "newmark"
    if joints:
        mesh.add_facet_group("joint", lambda x: abs(x[:, 1] - 0.5) < 1e-9, boundary_only=False)
    mat = pf.Elastic(1e9, 0.2, 2000.0)
    joint = [pf.Interface("joint", pf.Joint(phi=30.0))] if joints else []
    m = pf.Model(mesh, [pf.Block("base", mat), pf.Block("block", mat)], interfaces=joint)
    m.fix("base")
    m.add_gravity()
    h = 1e-3
    an = pf.Dynamic(m, h, scheme=scheme)
    res = an.run(n_steps=1000, start=pf.solve_static(m))
    assert res.t[-1] == 1.0
    np.testing.assert_array_equal(res.t, np.arange(1001) * h)
    # a start state continues its grid; one edited off it (another step number) goes on
    # from its own time, never back
    import dataclasses

    assert res.final is not None
    more = an.run(n_steps=3, start=res.final)
    np.testing.assert_array_equal(more.t, np.arange(1000, 1004) * h)
    moved = an.run(n_steps=3, start=dataclasses.replace(res.final, step=0))
    assert np.all(np.diff(moved.t) > 0) and moved.t[1] == pytest.approx(1.0 + h, abs=1e-15)


def test_checkpoints_every_n_steps(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """``output.checkpoint_steps = 25`` with a wall-time interval that never comes: a run of
    120 steps writes its checkpoints at steps 25, 50, 75 and 100 and at its end (120); the
    last one on disk is the end's; the key is not part of the run key (a run resumes
    with another N)."""
    from pfeie.io import _checkpoint, load_job, parse_override

    seen: list[_checkpoint.CheckpointWriter] = []
    init = _checkpoint.CheckpointWriter.__init__

    def spy(self: _checkpoint.CheckpointWriter, *a: object, **k: object) -> None:
        init(self, *a, **k)  # type: ignore[arg-type]
        seen.append(self)

    monkeypatch.setattr(_checkpoint.CheckpointWriter, "__init__", spy)
    p = _write(tmp_path, SMALL, duration=0.6)
    assert main(["run", str(p), "--quiet", "--set", "output.checkpoint_steps=25",
                 "--set", "output.checkpoint_seconds=1e6"]) == 0  # fmt: skip
    assert seen[0].written == [25, 50, 75, 100, 120]
    with Results(tmp_path / "out" / "results.h5") as res:
        assert int(res.f["checkpoint"].attrs["step"]) == 120
    plain = load_job(p, [])
    for n in (0, 25):  # when to checkpoint changes no value: a run resumes with any N
        other = load_job(p, [parse_override(f"output.checkpoint_steps={n}")])
        assert _checkpoint.run_key(other) == _checkpoint.run_key(plain)


def test_progress_of_a_resumed_run_counts_its_steps() -> None:
    """The progress line of a run resumed at step 10 of 20 (new-user finding: it showed
    ``step 11/10`` and, past the remaining count, every step with a negative ETA): the
    steps as numbered against the run's last step, the ETA from this process's pace,
    never negative."""
    from io import StringIO
    from types import SimpleNamespace

    from pfeie._job import Progress

    out = StringIO()
    bar = Progress(20, 0.01, out, first=10)
    pairs = SimpleNamespace(state=np.zeros(0, dtype=np.int8), broken=np.zeros(0, dtype=bool))
    for k in range(11, 21):
        bar(SimpleNamespace(step=k, kin=SimpleNamespace(t=0.01 * k), pairs=pairs))  # type: ignore[arg-type]
    lines = out.getvalue().splitlines()
    assert lines[0].startswith("step 11/20  t 0.110 s"), lines
    assert lines[-1].startswith("step 20/20  t 0.200 s") and "ETA 0.0 s" in lines[-1], lines
    assert len(lines) == 2  # not a line a step (a stream that is not a terminal: every 5 s)


def test_resumed_envelope_after_a_position_correction(tmp_path: Path) -> None:
    """The dam block of the small model thrown up by the ground (vertical, −2 g for 0.05 s,
    then +2 g for 0.05 s: the base falls away from it and comes back) lands on the joint:
    a step penetrates and takes a position correction, which the stress envelope leaves
    out (its row takes the displacement before it). Run to that step, then extended with
    ``--resume``: the envelope equals that of one run, array for array (the checkpoint
    keeps the step's correction, ``kin/shift``: without it the resumed run's first row,
    the checkpoint's, took the corrected displacement)."""
    t = np.round(np.arange(0.0, 0.3 + 1e-9, 0.005), 12)
    a = np.where(t < 0.05, -2.0, np.where(t < 0.1, 2.0, 0.0))
    text = (SMALL.replace('file = "pulse.csv"', 'file = "drop.csv"\ncomponent = "y"')
            .replace("dt = 0.005", "dt = 0.0025"))  # fmt: skip
    ref_dir, ext_dir = tmp_path / "ref", tmp_path / "ext"
    for d in (ref_dir, ext_dir):
        d.mkdir()
        np.savetxt(d / "drop.csv", np.c_[t, a], delimiter=",")
    assert main(["run", str(_write(ref_dir, text, duration=0.3)), "--quiet"]) == 0
    with Results(ref_dir / "out" / "results.h5") as res:
        corr, time_ = res.energy()["correction"], res.time
    k = int(np.flatnonzero(np.diff(corr) != 0)[0]) + 1  # the first corrected step
    p = _write(ext_dir, text, duration=0.3)
    assert main(["run", str(p), "--quiet", "--duration", f"{time_[k]:.6g}"]) == 0
    with h5py.File(ext_dir / "out" / "results.h5") as f:
        assert np.abs(f["checkpoint/kin/shift"][()]).max() > 0  # its last step corrected
    assert main(["run", str(p), "--quiet", "--resume", "--duration", "0.3"]) == 0
    ref, ext = ref_dir / "out" / "results.h5", ext_dir / "out" / "results.h5"
    with Results(ref) as ra, Results(ext) as rb:
        ea, eb = ra.envelope(), rb.envelope()
        assert ea.keys() == eb.keys()
        for key, value in ea.items():
            np.testing.assert_array_equal(eb[key], value, err_msg=key)
