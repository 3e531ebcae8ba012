"""Model files and the command line, end to end: validation errors (file, key path,
expected, found), ``pfeie check`` on the demo, ``pfeie run`` on a small model (exit code,
files), a clean stop on SIGINT that keeps the results, ``--version`` and ``--help``."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from pfeie import __version__
from pfeie.cli import main
from pfeie.errors import InputError, RecordError
from pfeie.io import ModelFile, Results, load_job, reference_rows
from pfeie.io._modelfile import reference_markdown

ROOT = Path(__file__).resolve().parents[1]
MESH = Path(__file__).resolve().parent / "data" / "two_blocks_v41.msh"

SMALL = f"""
title = "two blocks"
[mesh]
file = "{MESH}"
[materials.concrete]
E = 30e9
nu = 0.2
rho = 2400.0
[blocks]
rock = "concrete"
dam = "concrete"
[interfaces.joint]
friction_angle = 26.565
[[supports]]
group = "bottom"
[[ground_motion]]
file = "pulse.csv"
units = "g"
[analysis]
dt = 0.005
duration = DURATION
[output]
folder = "out"
probes = {{ top = [1.0, 2.0] }}
"""


def _write(tmp: Path, text: str, duration: float = 0.6) -> Path:
    t = np.arange(0.0, 0.4 + 1e-9, 0.005)
    np.savetxt(tmp / "pulse.csv", np.c_[t, 0.5 * np.sin(np.pi * t / 0.4)], delimiter=",",
               header="time,acc", comments="")  # fmt: skip
    p = tmp / "model.toml"
    p.write_text(text.replace("DURATION", str(duration)))
    return p


def start_run(model: Path, wait: float) -> subprocess.Popen[str]:
    """``pfeie run`` in a subprocess, returned once it has stepped for ``wait`` seconds."""
    env = dict(os.environ, PYTHONUNBUFFERED="1")
    proc = subprocess.Popen([sys.executable, "-m", "pfeie", "run", str(model)], env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)  # fmt: skip
    assert proc.stderr is not None
    t0 = time.time()
    for line in proc.stderr:  # progress lines: the run is stepping
        if (line.startswith("step") and time.time() - t0 > wait) or time.time() - t0 > 60:
            break
    return proc


def test_small_model_runs_and_writes_results(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A block on a joint (μ = 0.5) under a 0.5 g half-sine: exit 0, the files, and the
    slip of the summary equals the rigid-block reference (0.5 g pulse, μ = 0.5: the block
    follows the base, no slip) to 1 mm."""
    p = _write(tmp_path, SMALL)
    assert main(["run", str(p), "--quiet"]) == 0
    out = tmp_path / "out"
    assert {"results.h5", "summary.json", "summary.txt"} <= {f.name for f in out.iterdir()}
    with Results(out / "results.h5") as res:
        assert res.completed and res.time[-1] == pytest.approx(0.6)
        assert res.meta["model_sha256"] == load_job(p).digest
    s = json.loads((out / "summary.json").read_text())
    assert s["joints"]["joint"]["residual_slip_max_m"] < 1e-3
    # the pair solver's counters: every step iterates at least once, and the worst final
    # residual is within the solver's tolerance (1e-8)
    with Results(out / "results.h5") as res:
        it = np.asarray(res.f["history/solver/iterations"])
        assert it.shape == res.time.shape and it[1:].min() >= 1
        newton = np.asarray(res.f["history/solver/newton"])
        fb = np.asarray(res.f["history/solver/fallbacks"])
    assert s["solver"]["worst_residual"] <= 1e-8
    # every recorded row is one step here: the summary counts the file's rows
    assert s["solver"]["fallback_steps"] == np.count_nonzero(fb)
    assert s["solver"]["newton_steps"] == np.count_nonzero(newton)
    assert s["solver"]["iterations_mean"] >= 1.0
    assert "joint joint" in capsys.readouterr().out


def test_check_prints_the_demo_summary(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["check", str(ROOT / "examples" / "koyna" / "koyna.toml")]) == 0
    out = capsys.readouterr().out
    assert "interface    dam_rock: 37 pairs" in out and "interface    neck: 9 pairs" in out
    # the strengths in force, as examples/koyna/koyna.toml gives them (MPa, degrees)
    assert ("dam_rock: 37 pairs; intact: c 1 MPa, φ 45°, tensile 0.5 MPa; residual: c 0 MPa, "
            "φ 40°, tensile 0 MPa") in out  # fmt: skip
    assert "record       elcentro_1940_ns_chopra: PGA 0.191 g" in out
    assert "memory" in out
    assert ("brakes the rigid motion of the floating block(s) dam_lower, dam_upper" in out
            and "deformation_only = true spares it" in out)  # fmt: skip
    koyna = str(ROOT / "examples" / "koyna" / "koyna.toml")
    assert main(["check", koyna, "--set", "damping.deformation_only=true"]) == 0
    out = capsys.readouterr().out
    assert "the rigid motion of the floating block(s) dam_lower, dam_upper is not damped" in out
    assert main(["check", koyna, "--set", "damping.deformation_only=1"]) == 2
    assert "damping.deformation_only (from --set damping.deformation_only=1): expected a " \
        "boolean" in capsys.readouterr().err


def test_version_and_help(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--version"]) == 0
    assert f"pfeie {__version__}" in capsys.readouterr().out
    for cmd in (["--help"], ["run", "--help"], ["check", "--help"], ["schema", "--help"]):
        assert main(cmd) == 0
        out = capsys.readouterr().out
        assert "usage: pfeie" in out
        assert "results.npz" not in out
    assert main(["run", "--help"]) == 0
    out = capsys.readouterr().out
    assert "results.h5" in out and "--set KEY=VALUE" in out and "--dt" in out
    assert main(["frobnicate"]) == 2


@pytest.mark.parametrize(
    ("edit", "error", "match"),
    [
        (lambda s: s.replace("[mesh]", "[mesh\n"), InputError, "not valid TOML"),
        (lambda s: s.replace("nu = 0.2", "nu = 0.2\nnuu = 0.3"), InputError,
         r"materials\.concrete\.nuu: unknown key; expected one of: E, nu, rho"),
        (lambda s: s.replace('file = "pulse.csv"', ""), InputError,
         r"ground_motion\[0\]\.file: missing \(required\)"),
        (lambda s: s.replace("E = 30e9", 'E = "stiff"'), InputError,
         r"materials\.concrete\.E: expected a number, found a string 'stiff'"),
        (lambda s: s.replace("dt = 0.005", "dt = -0.005"), InputError,
         r"analysis\.dt: expected a number in \(0, 10\] s, found -0.005"),
        (lambda s: s.replace('dam = "concrete"', 'dam = "steel"'), InputError,
         r"blocks\.dam: unknown material 'steel'"),
        (lambda s: s.replace('dam = "concrete"', 'dome = "concrete"'), InputError,
         r"blocks\.dome: no physical group 'dome'.*dimension 2: \['dam', 'rock'\]"),
        (lambda s: s.replace('dam = "concrete"', 'joint = "concrete"'), InputError,
         r"'joint' is a group of dimension 1, a block needs 2"),
        (lambda s: s.replace("[interfaces.joint]", "[interfaces.rock]"), InputError,
         r"'rock' is a group of dimension 2, this needs 1"),
        (lambda s: s.replace('units = "g"', 'units = "g"\ncomponent = "z"'), InputError,
         r"ground_motion\[0\]\.component: 'z' in a 2D model"),
        (lambda s: s.replace('file = "pulse.csv"', 'file = "none.csv"'), RecordError,
         r"ground_motion\[0\]: .*none.csv: record file not found"),
        (lambda s: s.replace('units = "g"', 'units = "furlongs"'), InputError,
         r"ground_motion\[0\]\.units: expected one of 'g', 'm/s2', 'cm/s2'"),
        (lambda s: s + "[damping]\nratio = 0.05\n", InputError, r"damping\.frequencies: missing"),
    ],
)  # fmt: skip
def test_model_file_errors(tmp_path: Path, edit, error: type, match: str) -> None:  # type: ignore[no-untyped-def]
    p = _write(tmp_path, edit(SMALL))
    with pytest.raises(error, match=match) as err:
        load_job(p)
    assert str(p) in str(err.value)
    assert main(["check", str(p)]) == 2


def test_every_key_is_documented() -> None:
    """docs/model-file.md lists every key of the model file (it is generated from the
    typed settings), each with what it expects, its default and its meaning."""
    text = (ROOT / "docs" / "model-file.md").read_text()
    rows = reference_rows()
    assert len(rows) > 40
    missing = [r.key for r in rows if f"`{r.key}`" not in text]
    assert not missing
    assert all(r.expected and r.default and r.meaning for r in rows)
    assert reference_markdown() in text  # regenerate with docs/make_model_file_doc.py
    keys = {r.key for r in rows}
    assert {"analysis.alpha", "analysis.backend", "interfaces.<name>.law"} <= keys
    assert set(ModelFile.model_fields) == {r.key.split(".")[0].split("[")[0] for r in rows}


def test_interrupted_run_keeps_its_results(tmp_path: Path) -> None:
    """SIGINT during a run: exit code 130, and results.h5 holds the steps computed so
    far, marked as not completed."""
    proc = start_run(_write(tmp_path, SMALL, duration=400.0), wait=0.0)
    proc.send_signal(signal.SIGINT)
    out, _ = proc.communicate(timeout=120)
    assert proc.returncode == 130
    with Results(tmp_path / "out" / "results.h5") as res:
        assert not res.completed and "SIGINT" in res.meta["stop_reason"]
        assert 0 < res.time[-1] < 400.0
    assert "STOPPED" in out


def test_large_rotation_key_runs_the_body_frames(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """``analysis.large_rotation = true`` reaches the analysis (the run has body frames),
    and for the small rotations of this model (μm) its block motion equals the
    small-displacement run's to 2e-5 of the motion (the geometric terms are of the order
    of the rotation, 1e-6 rad; measured 2.2e-6)."""
    import pfeie._job as job_module

    made: list[object] = []
    real = job_module.Dynamic

    def spy(*args, **kw):  # type: ignore[no-untyped-def]
        an = real(*args, **kw)
        made.append(an.frames)
        return an

    monkeypatch.setattr(job_module, "Dynamic", spy)
    runs = []
    for flag in ("false", "true"):
        folder = tmp_path / flag
        folder.mkdir()
        text = SMALL.replace("duration = DURATION",
                             f"duration = 0.3\nlarge_rotation = {flag}")
        p = _write(folder, text)
        assert main(["run", str(p), "--quiet"]) == 0
        with Results(folder / "out" / "results.h5") as res:
            runs.append(res.rigid(1))
    assert made[0] is None and made[1] is not None
    scale = np.abs(runs[0]).max()
    assert scale > 1e-6
    assert np.abs(runs[1] - runs[0]).max() < 2e-5 * scale


def test_modal_needs_no_record_nor_duration(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A model file without a record and without analysis.duration: ``pfeie modal`` runs
    (a modal analysis needs neither; its frequencies are those of the same model with
    its record, to round-off), while ``pfeie check`` and ``pfeie run`` say what is
    missing and how to ask for a static analysis alone (exit 2)."""
    p = _write(tmp_path, SMALL)
    assert main(["modal", str(p), "-n", "2", "--out", str(tmp_path / "a")]) == 0
    ref = capsys.readouterr().out
    bare = SMALL.replace('[[ground_motion]]\nfile = "pulse.csv"\nunits = "g"\n', "")
    bare = bare.replace("duration = DURATION\n", "")
    q = tmp_path / "bare.toml"
    q.write_text(bare)
    assert main(["modal", str(q), "-n", "2", "--out", str(tmp_path / "b")]) == 0
    assert capsys.readouterr().out.replace(f"{tmp_path / 'b'}", "") == ref.replace(
        f"{tmp_path / 'a'}", "")  # fmt: skip
    for cmd in ("check", "run"):
        assert main([cmd, str(q)]) == 2
        err = capsys.readouterr().err
        assert "analysis.duration: missing (required without ground_motion); for a static " \
               "analysis alone, analysis.dynamic = false" in err


def test_modal_command(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """``pfeie modal``: the table, modes.csv (the frequencies of :func:`pfeie.modal` on the
    same model to round-off, effective-mass shares in [0, 1] whose running sum stays below
    the free mass) and the ParaView series of the shapes (one frame per mode, read back
    with meshio, each scaled to a largest displacement of 1); ``-n 0`` exits 2."""
    import csv

    import meshio

    import pfeie as pf

    p = _write(tmp_path, SMALL)
    assert main(["modal", str(p), "-n", "4", "--out", str(tmp_path / "m")]) == 0
    out = capsys.readouterr().out
    assert out.splitlines()[0].split()[:3] == ["mode", "f", "(Hz)"]
    rows = list(csv.DictReader((tmp_path / "m" / "modes.csv").open()))
    ref = pf.modal(load_job(p).model, 4).frequencies
    f = np.array([float(r["frequency_hz"]) for r in rows])
    np.testing.assert_allclose(f, ref, rtol=1e-8)
    for axis in "xy":
        share = np.array([float(r[f"share_{axis}"]) for r in rows])
        assert np.all(share >= 0) and np.cumsum(share)[-1] <= 1 + 1e-12
    with meshio.xdmf.TimeSeriesReader(str(tmp_path / "m" / "modes.xdmf")) as r:
        r.read_points_cells()
        assert r.num_steps == 4
        t, pd, _ = r.read_data(0)
    assert t == 1.0
    assert np.linalg.norm(pd["shape"], axis=1).max() == pytest.approx(1.0, rel=1e-12)
    assert main(["modal", str(p), "-n", "0"]) == 2
    assert "--modes: expected a number of modes >= 1" in capsys.readouterr().err
    # the upper block free on its joint: three rigid-body modes, marked so (they printed
    # as 0.0000 Hz and periods of 1e5 s), then the first elastic one
    assert main(["modal", str(p), "-n", "4", "--interfaces", "free", "--out",
                 str(tmp_path / "f")]) == 0  # fmt: skip
    lines = capsys.readouterr().out.splitlines()[2:6]
    assert [ln.split()[1] for ln in lines[:3]] == ["rigid"] * 3 and float(lines[3].split()[1]) > 1
    rows = list(csv.DictReader((tmp_path / "f" / "modes.csv").open()))
    assert [r["period_s"] for r in rows[:3]] == ["inf"] * 3 and float(rows[3]["period_s"]) < 1
    # the rigid modes are the floating block's rigid motion (share 1), the elastic mode is
    # M-orthogonal to it (share 0; both to round-off)
    share = np.array([float(r["rigid_share"]) for r in rows])
    np.testing.assert_allclose(share, [1, 1, 1, 0], atol=2e-15)  # measured 2.2e-16


def test_solver_counters_count_steps_through_a_resume(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The pair solver's counters count steps, whatever the recorded rows: the solves of
    every 4th step relabelled as finished by the semismooth Newton and those of every
    10th step (from the 4th) as needing the proximal fallback give the summary 30 and 12
    steps over the 120 steps of 0.6 s, with ``output.every = 3`` (a row holds 3 steps);
    a run of 0.3 s extended to 0.6 s by ``--resume`` (its summary read back from the
    file's rows) gives the same counters and mean iterations a step as one run."""
    from pfeie.dynamics import Dynamic
    from pfeie.interface import InterfaceSolver, SolveInfo

    current = {"step": 0}
    real_step, real_solve = Dynamic.step, InterfaceSolver.solve

    def step(self, cur, ex):  # type: ignore[no-untyped-def]
        current["step"] = cur.step + 1
        return real_step(self, cur, ex)

    def solve(self, *args, **kw):  # type: ignore[no-untyped-def]
        out = real_solve(self, *args, **kw)
        k, last = current["step"], self.last
        if k % 4 == 1:
            self.last = SolveInfo(last.iterations, last.residual, "semismooth Newton")
        elif k % 10 == 4:  # (never a 4th step's: 4, 14, 24, ... are not 1 modulo 4)
            self.last = SolveInfo(last.iterations, last.residual, "proximal Newton")
        return out

    monkeypatch.setattr(Dynamic, "step", step)
    monkeypatch.setattr(InterfaceSolver, "solve", solve)
    text = SMALL.replace('folder = "out"', 'folder = "out"\nevery = 3')
    summaries = []
    for name, runs in (("one", [[]]), ("resumed", [["--duration", "0.3"], ["--resume"]])):
        (tmp_path / name).mkdir()
        p = _write(tmp_path / name, text, duration=0.6)
        for extra in runs:
            current["step"] = 0
            assert main(["run", str(p), "--quiet", *extra]) == 0
        summaries.append(json.loads((tmp_path / name / "out" / "summary.json").read_text()))
        with Results(tmp_path / name / "out" / "results.h5") as res:
            assert len(res.time) == 41  # 120 steps in rows of 3
            newton = np.asarray(res.f["history/solver/newton"])
            fallbacks = np.asarray(res.f["history/solver/fallbacks"])
        assert newton.sum() == 30 and fallbacks.sum() == 12 and newton.max() == 1
    one, resumed = summaries
    assert one["steps"] == resumed["steps"] == 120
    for s in summaries:
        assert s["solver"]["newton_steps"] == 30 and s["solver"]["fallback_steps"] == 12
    assert resumed["solver"]["iterations_mean"] == one["solver"]["iterations_mean"] >= 1.0
    assert "the semismooth Newton finished 30 step(s); 12 step(s) needed a fallback" in (
        tmp_path / "one" / "out" / "summary.txt").read_text()


@pytest.mark.parametrize(("dt", "line"), [
    # 0.6 s / 0.035 s = 17.14: 17 steps reach 17 × 0.035 = 0.595 s, 0.005 s short
    ("0.035", "time steps   17 of 0.035 s, to t = 0.595 s (the duration, 0.6 s, is not a "
              "multiple of Δt: the last 0.005 s is not run)"),
    # 0.6 / 0.07 = 8.57: 9 steps reach 0.63 s, 0.03 s beyond
    ("0.07", "time steps   9 of 0.07 s, to t = 0.63 s (the duration, 0.6 s, is not a "
             "multiple of Δt: the run goes 0.03 s beyond it)"),
    ("0.005", "time steps   120 of 0.005 s, to t = 0.6 s\n"),
])  # fmt: skip
def test_check_gives_the_time_the_run_reaches(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], dt: str, line: str
) -> None:
    """``check --dt 0.03`` on a 4 s record said "(4.00 s)" where the run ends at 3.99 s
    (new-user finding): the line gives steps × Δt, the time the run reaches, as the run's
    own end (``completed at t = ...``), and what Δt leaves out or adds."""
    p = _write(tmp_path, SMALL)
    assert main(["check", "--dt", dt, str(p)]) == 0
    assert line in capsys.readouterr().out
