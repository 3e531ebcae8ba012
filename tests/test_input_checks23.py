"""Wrong inputs and lost results of a new user's test (round 23), each refused or warned
with a message that names the file (key, group, line) and what was expected, or kept:
the last step off the recording grid, a duration shorter than a step, records that start
before t = 0 or are sampled in ms, a PEER record given a contradicting dt, a resumed run
extended to a longer duration, a truncated results file, a lock file that cannot be
removed, units slipped in gravity, joint stiffness and silt, and the Python API's type
errors."""

from __future__ import annotations

import json
import logging
from pathlib import Path

import h5py
import numpy as np
import pytest

import pfeie as pf
from conftest import cli_fails
from pfeie.cli import main
from pfeie.errors import MeshError, ModelError, RecordError, ResultsError
from pfeie.io import Results, read_record, write_at2
from pfeie.verification._models import block_on_base
from test_cli import SMALL, _write


@pytest.fixture(scope="module")
def block() -> tuple[pf.Model, pf.StaticResult, pf.GroundMotion]:
    model = block_on_base(joint=pf.Joint(phi=30.0))
    gm = pf.GroundMotion.from_function(lambda t: 3.0 * np.sin(10.0 * t), 1.0, 1e-3)
    return model, pf.solve_static(model), gm


# -- the run's end is never dropped ---------------------------------------------------------
def test_the_last_step_off_the_grid_is_recorded(
    block: tuple[pf.Model, pf.StaticResult, pf.GroundMotion],
) -> None:
    """Recording every 4th of 10 steps keeps steps 0, 4, 8 and the last, 10, whose state
    is the run's (the same bits as recording every step); `every` beyond the run records
    its start and end."""
    model, static, gm = block
    kw = {"ground": [gm], "start": static}
    sparse = pf.Dynamic(model, 0.01).run(n_steps=10, every=4, **kw)
    dense = pf.Dynamic(model, 0.01).run(n_steps=10, every=1, **kw)
    np.testing.assert_allclose(sparse.t, [0.0, 0.04, 0.08, 0.1], rtol=0, atol=1e-15)
    np.testing.assert_array_equal(sparse.rigid[-1], dense.rigid[-1])
    np.testing.assert_array_equal(sparse.X[-1], dense.X[-1])
    assert pf.Dynamic(model, 0.01).run(n_steps=3, every=400, **kw).t.size == 2


def test_every_beyond_the_run_keeps_its_end(tmp_path: Path) -> None:
    """`output.every` above the number of steps: the summary is the run's end, not its
    start (before: "completed at t = 0.000 s, 0 steps", a crest of 0 mm)."""
    p = _write(tmp_path, SMALL.replace('folder = "out"', 'folder = "out"\nevery = 400'), 0.1)
    assert main(["run", str(p), "--quiet"]) == 0
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert s["time_reached_s"] == pytest.approx(0.1) and s["steps"] == 20
    assert s["probes"]["top"]["peak_abs_acceleration_g"] > 0.1  # (0 at the start alone)


def test_a_duration_shorter_than_a_step(
    block: tuple[pf.Model, pf.StaticResult, pf.GroundMotion], tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
) -> None:  # fmt: skip
    model, _, _ = block
    with pytest.raises(ModelError, match=r"duration 0.001 s is less than half a time step"):
        pf.Dynamic(model, 0.01).run(0.001)
    with pytest.raises(ModelError, match=r"duration: expected a number of seconds, got '1'"):
        pf.Dynamic(model, 0.01).run("1")  # type: ignore[arg-type]
    p = _write(tmp_path, SMALL, 0.001)
    cli_fails(capsys, ["check", str(p)], "analysis.duration", "less than half a time step")


# -- records --------------------------------------------------------------------------------
def test_records_before_zero_or_in_ms(tmp_path: Path, caplog: pytest.LogCaptureFixture,
                                      capsys: pytest.CaptureFixture[str]) -> None:  # fmt: skip
    """A record whose times start before 0 (its part before 0 would be dropped, and a pga
    measured on it), a dt or a time column in ms: refused; a sampling of 0.2 s: a
    warning."""
    t = np.arange(0.0, 2.0, 0.01)
    a = np.sin(5 * t)
    with pytest.raises(ModelError, match=r"the times start at -5 s; a record is applied "
                       r"from t = 0"):  # fmt: skip
        pf.GroundMotion.from_samples(a, time=t - 5.0)
    with pytest.raises(ModelError, match=r"dt must lie in \(0, 10\] s .*dt in ms"):
        pf.GroundMotion.from_samples(a, dt=20.0)
    with pytest.raises(ModelError, match=r"the times step by 20 s .*times in ms"):
        pf.GroundMotion.from_samples(a, time=2000 * t)
    np.savetxt(tmp_path / "coarse.csv", np.c_[np.arange(20) * 0.2, np.sin(np.arange(20))],
               delimiter=",")  # fmt: skip
    # (with a pga key in m/s² beside it: both warnings, neither hiding the other)
    p = _write(tmp_path, SMALL.replace('file = "pulse.csv"', 'file = "coarse.csv"\npga = 5.0'))
    with caplog.at_level(logging.WARNING):
        assert main(["check", str(p)]) == 0
    capsys.readouterr()
    assert "coarse.csv is sampled every 0.2 s" in caplog.text and "in ms?" in caplog.text
    assert "ground_motion[0].pga = 5 g lies above" in caplog.text


def test_a_peer_record_refuses_another_dt(tmp_path: Path) -> None:
    p = tmp_path / "r.AT2"
    write_at2(p, 0.1 * np.sin(np.arange(100) * 0.1), 0.02)
    assert read_record(p, dt=0.02).time[1] == pytest.approx(0.02)  # the same: accepted
    with pytest.raises(RecordError, match=r"states its own time step \(DT = 0.02 s in its "
                       r"header\); do not give dt \(given 0.005\)"):  # fmt: skip
        read_record(p, dt=0.005)


# -- results files ----------------------------------------------------------------------------
def test_a_resumed_run_extended_says_its_duration(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """`--resume --duration` extends a run: the file's settings, summary and spec give the
    new duration (the report's record line reads it); a shorter duration than the run
    reached is said to leave nothing to continue."""
    p = _write(tmp_path, SMALL, 0.1)
    assert main(["run", str(p), "--quiet"]) == 0
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    with h5py.File(tmp_path / "out" / "results.h5") as f:  # (from the run's own histories)
        assert s["energy_J"]["balance"] == f["history/energy/balance"][-1]
    assert main(["run", str(p), "--quiet", "--resume", "--duration", "0.2"]) == 0
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    with h5py.File(tmp_path / "out" / "results.h5") as f:
        assert json.loads(f.attrs["analysis"])["duration"] == 0.2
        assert json.loads(f.attrs["model_spec"])["analysis"]["duration"] == 0.2
        assert f["history/time"][-1] == pytest.approx(0.2)
        # the summary's balance is the file's, to the bit (one order of summation; before,
        # a run's own histories summed it in another order)
        assert s["energy_J"]["balance"] == f["history/energy/balance"][-1]
    summary = (tmp_path / "out" / "summary.json").read_bytes()
    # shorter than the run reached: refused, the file and the summaries left as they are
    # (they were written again for the shorter duration, a second reviewer's finding)
    assert main(["run", str(p), "--quiet", "--resume", "--duration", "0.05"]) == 2
    assert "the run reached t = 0.2 s, beyond the duration asked (0.05 s): nothing to " \
           "continue; expected --duration of at least 0.2 s" in capsys.readouterr().err
    with h5py.File(tmp_path / "out" / "results.h5") as f:  # the file's own, still
        assert json.loads(f.attrs["analysis"])["duration"] == 0.2
        assert f.attrs["completed"] and "results_summary" in f.attrs
    assert (tmp_path / "out" / "summary.json").read_bytes() == summary


def test_a_truncated_results_file_is_not_called_locked(tmp_path: Path) -> None:
    p = _write(tmp_path, SMALL, 0.05)
    assert main(["run", str(p), "--quiet"]) == 0
    path = tmp_path / "out" / "results.h5"
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])
    with pytest.raises(ResultsError, match="a truncated or damaged HDF5 file") as exc:
        Results(path)
    assert "pfeie run" in str(exc.value) and "lock" not in str(exc.value).split("(")[0]


def test_a_lock_file_that_cannot_go(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                    caplog: pytest.LogCaptureFixture) -> None:  # fmt: skip
    """A folder made read-only during a run: the lock file stays (a warning); the run's
    own outcome is what the user sees (before: a PermissionError traceback over it)."""
    from pfeie._job import FolderLock

    def refuse(self: Path, missing_ok: bool = False) -> None:
        raise PermissionError(13, "Permission denied")

    with caplog.at_level(logging.WARNING), FolderLock(tmp_path, tmp_path / "m.toml"):
        monkeypatch.setattr(Path, "unlink", refuse)
    assert "could not remove the lock file" in caplog.text
    assert "takes it over" in caplog.text


# -- units ------------------------------------------------------------------------------------
def test_units_slipped(tmp_path: Path, caplog: pytest.LogCaptureFixture,
                       capsys: pytest.CaptureFixture[str]) -> None:  # fmt: skip
    """Gravity in g or cm/s², a joint stiffness in MPa/m: warnings naming the key; a silt's
    unit weight in kN/m³: refused."""
    text = SMALL.replace("friction_angle = 26.565", "friction_angle = 26.565\n"
                         "normal_stiffness = 1e5\nshear_stiffness = 4e4")  # fmt: skip
    text = text.replace("[analysis]", "[loads]\ngravity = 981.0\n[analysis]")
    p = _write(tmp_path, text)
    with caplog.at_level(logging.WARNING):
        assert main(["check", str(p)]) == 0
    capsys.readouterr()
    assert "loads.gravity: g = 981 m/s² is not the Earth's 9.81 m/s²" in caplog.text
    assert "interfaces.joint.normal_stiffness = 100000 Pa/m is very low" in caplog.text
    assert "interfaces.joint.shear_stiffness = 40000 Pa/m is very low" in caplog.text
    silt = SMALL.replace("[analysis]", '[[loads.silt]]\ngroups = ["bottom"]\nlevel = 0.5\n'
                         "submerged_unit_weight = 9.0\nk = 0.5\n[analysis]")  # fmt: skip
    cli_fails(capsys, ["check", str(_write(tmp_path, silt))],
              "loads.silt[0].submerged_unit_weight: 9 N/m³ is below 1000 N/m³",
              "did you mean 9000 (kN/m³)?")  # fmt: skip


# -- the Python API -------------------------------------------------------------------------
def test_api_types(block: tuple[pf.Model, pf.StaticResult, pf.GroundMotion],
                   caplog: pytest.LogCaptureFixture) -> None:  # fmt: skip
    model, _, _ = block
    mesh = pf.rectangle(1.0, 1.5, 2, 3)
    with pytest.raises(ModelError, match=r"mesh: expected a pfeie mesh .*got str 'a.msh'"):
        pf.Model("a.msh", [pf.Block("all", pf.Elastic(30e9, 0.2, 2400))])  # type: ignore[arg-type]
    with pytest.raises(ModelError, match=r"Dynamic: expected a pfeie.Model .*got str"):
        pf.Dynamic("model.toml", 0.01)  # type: ignore[arg-type]
    with pytest.raises(ModelError, match=r"gravity: expected an acceleration in m/s² .*'down'"):
        model.add_gravity("down")  # type: ignore[arg-type]
    with pytest.raises(MeshError, match=r"cell group 'x': where\(x\) must return booleans"):
        mesh.add_cell_group("x", lambda x: x[:, 1])
    with caplog.at_level(logging.WARNING):
        assert mesh.add_facet_group("none", lambda x: x[:, 1] > 9.0) == {}
        assert mesh.add_cell_group("top", lambda x: x[:, 1] > 1.0)
        pf.Model(mesh, [pf.Block("top", pf.Elastic(30e9, 0.2, 2400))])
        pf.Model(pf.rectangle(1.0, 1.0, 1, 1), [pf.Block("all", pf.Elastic(30e9, 0.2, 2400))]
                 ).add_gravity(1.0)  # fmt: skip
    assert "facet group 'none': where(x) selected no boundary facet" in caplog.text
    assert "4 cell(s) of the mesh are in no block's group" in caplog.text
    assert "g = 1 m/s² is not the Earth's 9.81 m/s²" in caplog.text


def test_empty_paths_and_a_folder_for_a_file(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """An empty output folder or CSV folder (before: the model's or the current folder
    taken); a folder given as the model file (before: "model file not found")."""
    p = _write(tmp_path, SMALL, 0.05)
    cli_fails(capsys, ["check", str(p), "--set", 'output.folder=""'], "output.folder",
              "expected a folder path, found an empty string")  # fmt: skip
    cli_fails(capsys, ["check", str(tmp_path)], "is a folder; expected a model file (.toml)",
              "model.toml here")  # fmt: skip
    assert main(["run", str(p), "--quiet"]) == 0
    capsys.readouterr()
    cli_fails(capsys, ["export", str(tmp_path / "out" / "results.h5"), "--csv", ""],
              "--csv: expected an output folder, got an empty path")  # fmt: skip


def test_interrupted_after_the_stepping(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                        capsys: pytest.CaptureFixture[str]) -> None:  # fmt: skip
    """Ctrl-C while the ParaView files are written, after the time stepping: exit 130, the
    message says the results file holds the run and how to get the rest; `--resume`
    writes the summary and the series."""
    import pfeie._job as job_module

    p = _write(tmp_path, SMALL, 0.05)
    write = job_module.write_paraview

    def interrupted(*args: object, **kw: object) -> None:
        raise KeyboardInterrupt("SIGINT")

    monkeypatch.setattr(job_module, "write_paraview", interrupted)
    assert main(["run", str(p), "--quiet"]) == 130
    err = capsys.readouterr().err
    assert "the time stepping had finished and results.h5 holds the run" in err, err
    assert not (tmp_path / "out" / "summary.json").exists()
    monkeypatch.setattr(job_module, "write_paraview", write)
    assert main(["run", str(p), "--quiet", "--resume"]) == 0
    capsys.readouterr()
    assert (tmp_path / "out" / "summary.json").is_file()
    assert (tmp_path / "out" / "blocks.xdmf").is_file()


def test_water_below_its_faces_and_a_long_free_tail(
    tmp_path: Path, caplog: pytest.LogCaptureFixture, capsys: pytest.CaptureFixture[str]
) -> None:
    """A water level at or below the faces it loads (no water on them), and a duration
    more than twice the longest record and 20 s beyond it: warnings naming the key."""
    water = SMALL.replace("[analysis]", '[[loads.hydrostatic]]\ngroups = ["bottom"]\n'
                          "water_level = -1.0\n[analysis]")  # fmt: skip
    p = _write(tmp_path, water, 30.0)  # the pulse lasts 0.4 s
    with caplog.at_level(logging.WARNING):
        assert main(["check", str(p)]) == 0
    capsys.readouterr()
    assert ("loads.hydrostatic[0].water_level = -1 m lies at or below the lowest point of "
            "its faces ['bottom'] (0 m): no water on them") in caplog.text  # fmt: skip
    assert ("analysis.duration = 30 s is 75 times the longest record (0.4 s): the run goes "
            "on for 29.6 s of free vibration") in caplog.text  # fmt: skip
    caplog.clear()
    with caplog.at_level(logging.WARNING):
        assert main(["check", str(_write(tmp_path, SMALL, 10.0))]) == 0  # 9.6 s: no warning
    capsys.readouterr()
    assert "free vibration" not in caplog.text


def test_an_unknown_option_gets_its_commands_usage(capsys: pytest.CaptureFixture[str]) -> None:
    """An option a command does not have: that command's usage line, not the top level's
    (before: `usage: pfeie [-h] [--version] [-v] COMMAND ...`)."""
    assert main(["run", "m.toml", "--bogus"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("usage: pfeie run ") and "unrecognized arguments: --bogus" in err
    assert main(["--bogus"]) == 2
    assert capsys.readouterr().err.startswith("usage: pfeie [-h]")


def test_a_refused_resume_names_what_differs(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """`--resume` with another Δt: the message names the key and both values (before:
    "the model file, its --set overrides, the mesh or a record differ")."""
    p = _write(tmp_path, SMALL, 0.05)
    assert main(["run", str(p), "--quiet"]) == 0
    capsys.readouterr()
    cli_fails(capsys, ["run", str(p), "--quiet", "--resume", "--dt", "0.0025"],
              "cannot resume: the inputs differ from those of the run: analysis.dt: 0.005 "
              "for the run in the file, 0.0025 for this one")  # fmt: skip


def test_two_names_on_one_physical_group(tmp_path: Path) -> None:
    """Two names of one (dimension, tag) in $PhysicalNames: refused, naming both (before:
    one of them taken silently)."""
    from test_input_checks16 import DATA

    text = (DATA / "two_blocks_v22.msh").read_text()
    text = text.replace('$PhysicalNames\n4\n1 3 "joint"\n',
                        '$PhysicalNames\n5\n1 3 "joint"\n1 3 "crack"\n')  # fmt: skip
    p = tmp_path / "m.msh"
    p.write_text(text)
    with pytest.raises(MeshError, match=r"the physical group of dimension 1 and tag 3 has two "
                       r"names, 'joint' and 'crack'"):  # fmt: skip
        pf.io.read_mesh(p)


def test_a_utf16_record_is_read(tmp_path: Path) -> None:
    """A record saved as UTF-16 (with its byte-order mark, as some Windows editors write
    it) reads as its UTF-8 twin (before: "not a text file (it holds NUL bytes)")."""
    t = np.arange(0.0, 1.0, 0.01)
    text = "\n".join(f"{a:.4f} {b:.6f}" for a, b in zip(t, np.sin(t), strict=True))
    (tmp_path / "u16.csv").write_text(text, encoding="utf-16")
    (tmp_path / "u8.csv").write_text(text, encoding="utf-8")
    a = read_record(tmp_path / "u16.csv", units="g")
    b = read_record(tmp_path / "u8.csv", units="g")
    np.testing.assert_array_equal(a.time, b.time)
    np.testing.assert_array_equal(a.acceleration, b.acceleration)


def test_a_binary_file_for_the_model_file(tmp_path: Path,
                                          capsys: pytest.CaptureFixture[str]) -> None:  # fmt: skip
    """A binary file named .csv given as the model file: "a binary file" (before: "this
    looks like a ground-motion record")."""
    p = tmp_path / "data.csv"
    p.write_bytes(bytes(range(256)) * 4)
    cli_fails(capsys, ["check", str(p)], "expected a model file (.toml); this looks like a "
              "binary file")  # fmt: skip
