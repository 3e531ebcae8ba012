"""Studies: how the runs are spread (``run.workers``) and the system built once per process.

References: the table of the default study (``workers = "auto"``: a local Dask cluster of
one process per core) equals, bit for bit, the table of the same study run in this
process (``workers = 0``: no Dask, one process, an independent path); the systems a
process builds are counted by the cache itself (:func:`pfeie.study._study.builds`), in
this process and, through the Dask client, in each worker; the step count of a run is
its duration over the Δt of its model (1.99 s at 0.01 s and at 0.005 s: 199 and 398
steps, exact integers).
"""

from __future__ import annotations

import logging
import multiprocessing
import sys
from pathlib import Path

import pytest

import pfeie.study._study as study_mod
from pfeie.cli import main
from pfeie.errors import ModelError
from pfeie.study import Study
from pfeie.study._parallel import available_cores, local_workers
from test_study import STUDY, same, setup

AUTO = STUDY.replace("[run]\nworkers = 0", "[run]")  # the default: workers = "auto"
LOG = "pfeie.study"


@pytest.fixture
def fresh_cache(monkeypatch: pytest.MonkeyPatch) -> None:
    """An empty system cache in this process (another test may have left the same model
    key in it)."""
    monkeypatch.setattr(study_mod, "_SYSTEMS", {})


def _built(caplog: pytest.LogCaptureFixture) -> int:
    """The 'system built' lines logged in this process."""
    return sum("system of" in r.getMessage() and " built in " in r.getMessage()
               for r in caplog.records)  # fmt: skip


def test_auto_is_the_default_and_a_local_cluster_gives_the_serial_table(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    """A study file without ``run.workers`` runs on a local Dask cluster of min(cores,
    runs) processes (the INFO line says so), and its table equals the in-process one
    (``workers = 0``) bit for bit."""
    pytest.importorskip("distributed")
    cores = available_cores()
    if cores < 2:
        pytest.skip("one core: 'auto' runs in this process (test_auto_falls_back_...)")
    p = setup(tmp_path, AUTO)
    st = Study.from_file(p)
    assert st.workers == "auto"
    with caplog.at_level(logging.INFO, logger=LOG):
        table = st.run()
    msgs = [r.getMessage() for r in caplog.records]
    n = min(cores, 6)
    assert f"study: workers = 'auto': a local Dask cluster of {n} processes ({cores} cores, " \
           "6 runs)" in msgs, msgs  # fmt: skip
    assert any(m.startswith("study on Dask:") for m in msgs), msgs
    serial = Study.from_file(p)
    serial.folder = tmp_path / "serial"
    same(table, serial.run(workers=0))


@pytest.mark.parametrize("cores, dask, runs, want, why", [
    (2, True, 6, 2, "a local Dask cluster of 2 processes (2 cores, 6 runs)"),
    (8, True, 3, 3, "a local Dask cluster of 3 processes (8 cores, 3 runs)"),
    (1, True, 6, 0, "in this process, one after the other (one core available)"),
    (4, True, 1, 0, "in this process, one after the other (1 run to do)"),
    (4, False, 6, 0, "in this process, one after the other (Dask is not installed"),
])  # fmt: skip
def test_auto_workers(monkeypatch: pytest.MonkeyPatch, caplog: pytest.LogCaptureFixture,
                      cores: int, dask: bool, runs: int, want: int, why: str) -> None:  # fmt: skip
    """Workers "auto" is one process per available core, at most one per run; in this process,
    with an INFO line giving the reason, with one core, one run, or no Dask. A number is
    kept as given, whatever the cores."""
    monkeypatch.setattr("os.sched_getaffinity", lambda pid: set(range(cores)), raising=False)
    if dask:
        pytest.importorskip("distributed")
    else:
        monkeypatch.setitem(sys.modules, "distributed", None)  # import raises ImportError
    with caplog.at_level(logging.INFO, logger=LOG):
        assert local_workers("auto", runs) == want
    assert any(why in r.getMessage() for r in caplog.records), caplog.text
    assert local_workers(0, runs) == 0 and local_workers(3, runs) == 3


def test_auto_in_a_daemonic_process(monkeypatch: pytest.MonkeyPatch) -> None:
    """A daemonic process (a worker of a process pool) may not start processes: "auto"
    runs there."""
    monkeypatch.setattr(multiprocessing.current_process(), "daemon", True, raising=False)
    monkeypatch.setattr("os.sched_getaffinity", lambda pid: {0, 1, 2, 3}, raising=False)
    assert local_workers("auto", 6) == 0


@pytest.mark.usefixtures("fresh_cache")
def test_auto_without_dask_runs_here(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                     caplog: pytest.LogCaptureFixture) -> None:  # fmt: skip
    """The default study without Dask installed runs in this process (one system built
    here) and gives the in-process table; `pfeie study --workers auto` is accepted."""
    monkeypatch.setitem(sys.modules, "distributed", None)
    p = setup(tmp_path, AUTO.replace("[0.2, 0.5]", "[0.5]"), n=2)
    before = study_mod.builds()
    with caplog.at_level(logging.INFO, logger=LOG):
        table = Study.from_file(p).run()
    assert study_mod.builds() - before == 1 and _built(caplog) == 1
    assert "Dask is not installed" in caplog.text
    serial = Study.from_file(p)
    serial.folder = tmp_path / "serial"
    same(table, serial.run(workers=0))
    assert main(["study", str(p), "--workers", "auto", "--restart", "--quiet"]) == 0


def test_bad_workers(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """A wrong ``workers`` names the key and what is expected, in Python and on the
    command line (exit 2)."""
    p = setup(tmp_path)
    for bad in (-1, 4097, 2.0, True, "many"):
        with pytest.raises(ModelError, match=r"run\.workers: expected an integer in "
                           r"\[0, 4096\] or 'auto', found"):  # fmt: skip
            Study(tmp_path / "model.toml", [tmp_path / "rec" / "r0.csv"], workers=bad)  # type: ignore[arg-type]
    st = Study.from_file(p)
    with pytest.raises(ModelError, match=r"run\.workers"):
        st.run(workers=-2)
    assert main(["study", str(p), "--workers", "-1"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("pfeie: error: --workers: expected a whole number in [0, 4096]")
    assert "'auto'" in err and "Traceback" not in err


@pytest.mark.usefixtures("fresh_cache")
def test_system_built_once_in_process(tmp_path: Path, caplog: pytest.LogCaptureFixture) -> None:
    """3 records x 2 intensities in this process: one system built (counted by the cache
    and by its log line), six runs; a second study of the same model in the same
    process builds none."""
    p = setup(tmp_path)
    before = study_mod.builds()
    with caplog.at_level(logging.INFO, logger=LOG):
        table = Study.from_file(p).run()
    assert len(table) == 6 and all(table.column("completed"))
    assert study_mod.builds() - before == 1 and _built(caplog) == 1
    again = Study.from_file(p)
    again.folder = tmp_path / "again"
    same(table, again.run())
    assert study_mod.builds() - before == 1


@pytest.mark.usefixtures("fresh_cache")
def test_a_second_dt_builds_a_second_system(tmp_path: Path) -> None:
    """A study file has one Δt (``analysis.set``; a record's ``dt`` is its sampling, not
    the time step), so a second Δt is a second study: in the same process it builds a
    second system (the cache key holds the model's settings), whose runs take the new
    Δt: the record's duration over Δt, 398 steps at 0.005 s, 199 at 0.01 s; a third study back at
    0.01 s builds again (one system per process at a time) and gives the first table."""
    p = setup(tmp_path, STUDY.replace("[0.2, 0.5]", "[0.5]"), n=1)
    q = tmp_path / "half.toml"
    q.write_text(p.read_text().replace('folder = "study"', 'folder = "half"')
                 + '[analysis]\nset = ["analysis.dt=0.005"]\n')  # fmt: skip
    before = study_mod.builds()
    first = Study.from_file(p).run()
    assert study_mod.builds() - before == 1
    half = Study.from_file(q).run()
    assert study_mod.builds() - before == 2
    dur = Study.from_file(p).records[0].read(2).duration  # 1.99 s: 200 samples at 0.01 s
    assert first.column("steps").tolist() == [round(dur / 0.01)]
    assert half.column("steps").tolist() == [round(dur / 0.005)]
    back = Study.from_file(p)
    back.folder = tmp_path / "back"
    same(first, back.run())
    assert study_mod.builds() - before == 3


def test_system_built_at_most_once_per_worker(tmp_path: Path) -> None:
    """3 records x 2 intensities on a two-worker local cluster (processes): each worker
    reports (through the client) at most one system built, though the six runs all ran
    on them; the table equals the in-process one bit for bit."""
    distributed = pytest.importorskip("distributed")
    p = setup(tmp_path)
    serial = Study.from_file(p).run()
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None,
                                  env={"OMP_NUM_THREADS": "1"}) as cluster, \
            distributed.Client(cluster) as client:  # fmt: skip
        st = Study.from_file(p)
        st.folder = tmp_path / "dask"
        same(serial, st.run(scheduler=cluster.scheduler_address))
        counts = client.run(study_mod.builds)
    assert len(counts) == 2 and all(c <= 1 for c in counts.values()), counts
    assert sum(counts.values()) >= 1, counts


def test_ctrl_c_on_a_local_cluster_prints_no_traceback(tmp_path: Path) -> None:
    """Ctrl-C in a terminal (SIGINT to the whole process group) while a study runs on two
    local Dask workers: exit 130 with the one message and the rows kept, and no traceback
    from the workers (a new user saw three or four: each worker took the SIGINT mid-run;
    they now start with it ignored, and the study's process stops them)."""
    import os
    import signal
    import subprocess
    import time

    pytest.importorskip("distributed")
    p = setup(tmp_path, STUDY.replace("workers = 0", "workers = 2"), n=3, seconds=6.0)
    proc = subprocess.Popen([sys.executable, "-m", "pfeie", "study", str(p), "--quiet"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True)  # fmt: skip
    rows = tmp_path / "study" / "rows"
    t0 = time.monotonic()
    while not (rows.is_dir() and any(rows.glob("*.json"))):
        assert proc.poll() is None and time.monotonic() - t0 < 120
        time.sleep(0.01)
    os.killpg(proc.pid, signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    assert "pfeie: interrupted (SIGINT); the runs finished so far are kept" in err
    assert "Traceback" not in err and "Exception ignored" not in err, err
