"""A full disk during a run (the results file's writes fail with ENOSPC): exit 2 with a
``pfeie: error`` line naming the output folder and the cause, no traceback; the results
file stays readable (``pfeie report``), and with room again ``pfeie run --resume`` ends the
run."""

from __future__ import annotations

import errno
from pathlib import Path

import pytest
from test_wrong_inputs import MODEL, setup

from pfeie.cli import main
from pfeie.io import Results
from pfeie.io._results import ResultsWriter


def test_full_disk(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                   capsys: pytest.CaptureFixture[str]) -> None:  # fmt: skip
    monkeypatch.chdir(tmp_path)
    setup(tmp_path)
    (tmp_path / "model.toml").write_text(MODEL.replace("duration = 0.03", "duration = 0.2"))
    flush = ResultsWriter.flush
    calls = []

    def full(self: ResultsWriter) -> None:  # the disk fills after 5 writes
        calls.append(1)
        if len(calls) > 5:
            raise OSError(errno.ENOSPC, "No space left on device")
        flush(self)

    monkeypatch.setattr(ResultsWriter, "flush", full)
    every_row = ["--set", "output.checkpoint_seconds=0"]
    assert main(["run", "model.toml", "--quiet", *every_row]) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err
    line = next(ln for ln in err.splitlines() if ln.startswith("pfeie: error: "))
    for words in ("out: cannot write the results (No space left on device)",
                  "what was written before stays readable", "--resume"):  # fmt: skip
        assert words in line, line
    monkeypatch.setattr(ResultsWriter, "flush", flush)
    with Results("out/results.h5") as res:
        assert not res.completed and 0 < res.time[-1] < 0.2
    assert main(["report", "out/results.h5"]) == 0
    capsys.readouterr()
    assert main(["run", "model.toml", "--quiet", "--resume", *every_row]) == 0
    with Results("out/results.h5") as res:
        assert res.completed and res.time[-1] == pytest.approx(0.2)


def test_results_file_not_writable(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                   capsys: pytest.CaptureFixture[str]) -> None:  # fmt: skip
    """A results file that cannot be written (a read-only file: EPERM, as a new user's
    `chattr +i`) names the file and says that it is not writable, not "room"."""
    monkeypatch.chdir(tmp_path)
    setup(tmp_path)
    (tmp_path / "model.toml").write_text(MODEL)

    def denied(self: ResultsWriter) -> None:
        raise OSError(errno.EPERM, "Operation not permitted", "out/results.h5")

    monkeypatch.setattr(ResultsWriter, "flush", denied)
    assert main(["run", "model.toml", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err
    line = next(ln for ln in err.splitlines() if ln.startswith("pfeie: error: "))
    assert "out/results.h5: cannot write the results (Operation not permitted)" in line, line
    assert "not writable" in line and "room" not in line, line
