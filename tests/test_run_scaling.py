"""``pfeie run`` scales a model file's record to its ``pga`` or ``target_sa`` on the motion
applied, the record up to ``analysis.duration`` (:func:`pfeie.io.applied_part`, as a
study scales its ladders), and says so when the record's peak lies beyond the duration.

The record: 0.2 g × sin(2π · 2.5 t) for 2.9 s, then 0, with one sample of 1 g at t = 3 s;
its whole peak (1 g) lies beyond a duration of 2 s, where the first 2 s peak at 0.2 g."""

from __future__ import annotations

import json
import logging
from pathlib import Path

import numpy as np
import pytest

from pfeie.cli import main
from pfeie.io import applied_part, load_job, run_key
from test_robustness import model

G = 9.81


def _late_peak(tmp: Path) -> float:
    """Write the record (``rec.csv``, two columns, g); returns the peak of its first 2 s
    (g): 0.2 sin(π/2) as the samples give it."""
    t = np.round(np.arange(0.0, 4.0 + 1e-9, 0.01), 12)
    a = np.where(t < 2.9, 0.2 * np.sin(2 * np.pi * 2.5 * t), 0.0)
    a[np.flatnonzero(t == 3.0)] = 1.0
    np.savetxt(tmp / "rec.csv", np.c_[t, a], delimiter=",")
    return float(np.abs(a[t <= 2.0]).max())


def _model(tmp: Path, target: str, duration: str = "duration = 2.0") -> Path:
    """The plate of test_robustness, dynamic (Δt = 10 ms), under the record with
    ``target`` (``pga = 0.1``) in its ``[[ground_motion]]``."""
    p = model(tmp, extra=f"dt = 0.01\n{duration}")
    p.write_text(p.read_text() + f'[[ground_motion]]\nfile = "rec.csv"\nunits = "g"\n{target}\n')
    return p


def test_pga_scales_the_motion_applied(
    tmp_path: Path, caplog: pytest.LogCaptureFixture, capsys: pytest.CaptureFixture[str]
) -> None:
    """``pga = 0.1`` with ``duration = 2.0``: the factor is 0.1 / 0.2 = 0.5 (before: 0.1 /
    1 = 0.1 over the whole record, so the motion applied peaked at 0.02 g), the motion
    applied peaks at 0.1 g (to 1e-12, measured 0), a warning says that the record's PGA, 1 g
    at 3.00 s, lies beyond the duration, and the record's line of ``pfeie run`` and of the
    summary states the factor and the part it was measured on. ``--duration 2`` does the
    same; without a duration the whole record is applied and scaled ×0.1."""
    head = _late_peak(tmp_path)
    p = _model(tmp_path, "pga = 0.1")
    with caplog.at_level(logging.WARNING, logger="pfeie"):
        job = load_job(p)
    rec = job.records[0]
    factor = 0.1 / head
    assert factor == pytest.approx(0.5, rel=1e-12)
    assert applied_part(rec, 2.0)[0].pga / G == pytest.approx(0.1, rel=1e-12)
    assert rec.pga / G == pytest.approx(factor, rel=1e-12)  # the late 1 g, scaled
    assert (f"{p}: ground_motion[0]: the record's PGA, 1 g at 3.00 s, lies beyond the end of "
            "the run (duration 2 s): the motion applied, up to 2 s, peaks at 0.2 g: pga "
            "scales that part") in caplog.text  # fmt: skip
    line = ("scaled ×0.5 to a PGA of 0.1 g in the motion applied, up to 2 s (analysis.duration; "
            "the PGA above lies beyond it)")
    assert line in rec.summary()
    assert main(["run", str(p), "--quiet"]) == 0
    out = capsys.readouterr()
    assert "record: rec: PGA 0.500 g" in out.err and line in out.err
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert line in s["model"]["records"][0]
    assert s["time_reached_s"] == pytest.approx(2.0)
    # the report rebuilds the model of the run: its key holds the factor (new-user
    # finding: the report said the record had changed, and left out its model sections)
    from pfeie.io import Results
    from pfeie.plot._report import model_of_run

    with Results(tmp_path / "out" / "results.h5") as res:
        job, why = model_of_run(res)
    assert job is not None, why
    # extended to 4 s the factor would be 0.1: the resume is refused, saying why
    assert main(["run", str(p), "--quiet", "--resume", "--duration", "4"]) == 2
    err = capsys.readouterr().err
    assert ("cannot resume: ground_motion[0]'s pga or target_sa is met by the record up to "
            "analysis.duration, so its scale factor depends on the duration: ×0.5 for the run "
            "in the file, the whole record's for this one") in err, err  # fmt: skip
    # the spectra of the model file: of the motion applied
    assert main(["spectrum", str(p), "--out", str(tmp_path / "sp")]) == 0
    out = capsys.readouterr()
    assert "(the motion applied: up to 2 s, analysis.duration)" in out.out
    assert "PGA 0.100 g" in out.out
    # the same duration from the command line
    p = _model(tmp_path, "pga = 0.1", duration="")
    assert main(["check", str(p), "--duration", "2"]) == 0
    assert line in capsys.readouterr().out
    # no duration: the run applies the whole record, scaled on its peak of 1 g
    caplog.clear()
    with caplog.at_level(logging.WARNING, logger="pfeie"):
        whole = load_job(p).records[0]
    assert whole.pga / G == pytest.approx(0.1, rel=1e-12)
    assert whole.summary().endswith("scaled ×0.1 to a PGA of 0.1 g")
    assert "lies beyond" not in caplog.text


def test_target_sa_on_the_motion_applied_and_the_run_key(tmp_path: Path) -> None:
    """``target_sa = {period = 0.3, value = 0.5}`` with ``duration = 2.0`` on a record
    that resonates at 0.3 s after 2.5 s (1 g × sin(2π t / 0.3) from 2.5 to 3.5 s, after
    the 0.2 g at 2.5 Hz): Sa(0.3 s, 5 %) of the motion applied is 0.5 g (to 1e-12; the
    spectrum is linear in the record; measured 1.1e-16), the whole record's 5.15 g. A
    factor measured on the part depends on the duration, so the run key (which leaves the
    duration out) holds it: 2 s and 4 s give two keys under ``pga = 0.1`` (factors 0.5
    and 0.1); a record whose peak lies within 2 s keeps one key (one factor)."""
    t = np.round(np.arange(0.0, 4.0 + 1e-9, 0.01), 12)
    late = (t >= 2.5) & (t <= 3.5)
    a = np.where(t < 2.0, 0.2 * np.sin(2 * np.pi * 2.5 * t), 0.0)
    a[late] = np.sin(2 * np.pi * (t[late] - 2.5) / 0.3)
    np.savetxt(tmp_path / "rec.csv", np.c_[t, a], delimiter=",")
    p = _model(tmp_path, "target_sa = {period = 0.3, value = 0.5}")
    rec = load_job(p).records[0]
    assert applied_part(rec, 2.0)[0].sa(0.3, 0.05) / G == pytest.approx(0.5, rel=1e-12)
    assert rec.sa(0.3, 0.05) / G > 1.0  # the whole record, scaled by the part's factor: 5.15
    assert "to Sa(0.3 s, 5 %) = 0.5 g in the motion applied, up to 2 s" in rec.summary()
    _late_peak(tmp_path)
    keys = [run_key(load_job(_model(tmp_path, "pga = 0.1", f"duration = {d}"))) for d in (2, 4)]
    assert keys[0] != keys[1]
    t = np.round(np.arange(0.0, 4.0 + 1e-9, 0.01), 12)
    np.savetxt(tmp_path / "rec.csv", np.c_[t, np.exp(-t) * np.sin(2 * np.pi * 2.5 * t)],
               delimiter=",")  # fmt: skip
    keys = [run_key(load_job(_model(tmp_path, "pga = 0.1", f"duration = {d}"))) for d in (2, 4)]
    assert keys[0] == keys[1]


def test_target_sa_warns_when_the_part_changes_the_factor(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    """A record whose PGA (a 0.5 g spike at 0.5 s) lies within a run of 2 s while its
    later part (0.3 g at the period 0.3 s from 2.5 to 3.5 s) drives Sa(0.3 s): the part's
    factor differs from the whole record's by more than 5 %, and a warning gives both
    Sa values and both factors (the review's finding: a tenfold factor without a word)."""
    t = np.round(np.arange(0.0, 4.0 + 1e-9, 0.01), 12)
    a = np.where(t == 0.5, 0.5, 0.0)
    late = (t >= 2.5) & (t <= 3.5)
    a[late] = 0.3 * np.sin(2 * np.pi * (t[late] - 2.5) / 0.3)
    np.savetxt(tmp_path / "rec.csv", np.c_[t, a], delimiter=",")
    p = _model(tmp_path, "target_sa = {period = 0.3, value = 0.5}")
    with caplog.at_level(logging.WARNING, logger="pfeie"):
        rec = load_job(p).records[0]
    part = applied_part(rec, 2.0)[0]
    assert part.sa(0.3, 0.05) / G == pytest.approx(0.5, rel=1e-12)
    whole = rec.sa(0.3, 0.05) / G  # the whole record, scaled by the part's factor
    assert whole > 1.5
    assert (f"{p}: ground_motion[0]: Sa(0.3 s) of the motion applied, up to 2 s "
            "(analysis.duration), is") in caplog.text, caplog.text
    assert "target_sa scales that part" in caplog.text
