"""Results files, ParaView output, plots, CSV export and the report: every stored
quantity round-trips, the ParaView series read back, each command writes its files, and
a killed run leaves a readable file."""

from __future__ import annotations

import signal
from pathlib import Path

import numpy as np
import pytest

from pfeie.cli import main
from pfeie.io import Results, ResultsWriter, load_job, write_paraview
from test_cli import SMALL, _write, start_run


@pytest.fixture(scope="module")
def small_run(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, object, object]:
    """The small two-block model run once, streamed to a results file by hand."""
    import pfeie as pf

    tmp = tmp_path_factory.mktemp("res")
    job = load_job(_write(tmp, SMALL, duration=0.6))
    static = pf.solve_static(job.model)
    path = tmp / "results.h5"
    w = ResultsWriter(path, job, field_every=3)
    w.write_static(static)
    dyn = pf.Dynamic(job.model, 0.005)
    res = dyn.run(0.6, ground=job.records, start=static, probes=list(job.probes.values()),
                  every=2, on_record=w.append)  # fmt: skip
    w.close(res.completed, None, {"note": "test"})
    return path, res, job


def test_every_quantity_round_trips(small_run) -> None:  # type: ignore[no-untyped-def]
    path, res, job = small_run
    with Results(path) as r:
        assert r.completed and r.meta["model_sha256"] == job.digest
        assert r.meta["results_summary"] == {"note": "test"}
        np.testing.assert_array_equal(r.time, res.t)
        p = r.probe("top")
        for key, arr in (("u", res.probe_u), ("v", res.probe_v), ("a", res.probe_a),
                         ("a_abs", res.probe_a_abs)):  # fmt: skip
            np.testing.assert_array_equal(p[key], arr[:, 0])
        np.testing.assert_array_equal(r.f["history/rigid"][...], res.rigid)
        pr = r.pairs()
        for key in ("X", "w", "s", "state", "broken"):
            np.testing.assert_array_equal(pr[key], getattr(res, key))
        np.testing.assert_array_equal(pr["normal_stress"], res.normal_stress)
        np.testing.assert_array_equal(pr["slip"], res.slip)
        np.testing.assert_array_equal(r.joint_safety_factor("joint"), res.safety_factor[:, 0])
        for key, arr in res.energy.items():
            np.testing.assert_allclose(r.energy()[key], arr, rtol=1e-12, atol=1e-9)
        tf, fields = r.fields()
        np.testing.assert_array_equal(tf, res.t[::3])
        assert fields["u"].shape == (tf.size, job.model.mesh.n_points, 2)
        assert r.units("history/pairs/X") == "N" and r.units("history/probes/a") == "m/s^2"
        assert r.rigid("dam").shape == (res.t.size, 3)
        with pytest.raises(Exception, match="no probe"):
            r.probe("nowhere")


def test_paraview_series_read_back(small_run, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    import meshio

    path, res, job = small_run
    files = write_paraview(path, job.model, tmp_path)
    assert [f.name for f in files] == ["blocks.xdmf", "interfaces.xdmf"]
    with meshio.xdmf.TimeSeriesReader(str(tmp_path / "blocks.xdmf")) as rd:
        points, _cells = rd.read_points_cells()
        assert points.shape[0] == job.model.mesh.n_points
        assert rd.num_steps == res.t[::3].size
        _t, pd, _cd = rd.read_data(rd.num_steps - 1)
        stress = {"stress_xx", "stress_yy", "stress_xy", "stress_zz"}  # plane strain
        assert {"displacement", "velocity", "acceleration", *stress} == set(pd)
        assert all(pd[k].shape == (points.shape[0],) for k in stress)
    with meshio.xdmf.TimeSeriesReader(str(tmp_path / "interfaces.xdmf")) as rd:
        points, _cells = rd.read_points_cells()
        assert points.shape[0] >= job.model.pairs.n
        _t, pd, _cd = rd.read_data(0)
        assert {"opening", "slip", "normal_stress", "shear_stress", "state", "broken",
                "slip_vector", "shear_vector"} <= set(pd)  # fmt: skip
        _t, pd, _cd = rd.read_data(rd.num_steps - 1)
        # the global vectors (3 components, for glyphs) have the local components' size
        for vec, loc in (("slip_vector", "slip"), ("shear_vector", "shear_stress")):
            v, w = pd[vec], pd[loc].reshape(pd[loc].shape[0], -1)
            ok = np.isfinite(w).all(axis=1)
            assert v.shape == (points.shape[0], 3) and np.abs(w[ok]).max() > 0
            np.testing.assert_allclose(np.linalg.norm(v[ok], axis=1),
                                       np.linalg.norm(w[ok], axis=1), rtol=1e-6)  # fmt: skip


def test_plot_export_report_commands(small_run, tmp_path: Path,  # type: ignore[no-untyped-def]
                                     capsys: pytest.CaptureFixture[str]) -> None:  # fmt: skip
    path, _, _ = small_run
    assert main(["plot", str(path), "--out", str(tmp_path / "fig")]) == 0
    pngs = sorted(p.name for p in (tmp_path / "fig").iterdir())
    # (the loads and static figures too: the run's model file is beside its results)
    assert pngs == ["energy.png", "input_motion.png", "joint_joint.png", "joint_map.png",
                    "loads.png", "mesh.png", "probe_top.png", "rigid_motion.png",
                    "states_joint.png", "static_joint.png", "static_stress.png"]  # fmt: skip
    assert all((tmp_path / "fig" / p).stat().st_size > 10_000 for p in pngs)
    assert main(["export", str(path), "--csv", str(tmp_path / "csv")]) == 0
    probes = (tmp_path / "csv" / "probes.csv").read_text().splitlines()
    assert probes[0] == "time_s,probe,quantity,component,value,unit"
    assert len(probes) == 1 + 4 * 2 * 61  # 4 quantities × 2 components × 61 times
    # the joint's relative displacement series: the area mean of w − w(0) from the stored
    # pair history (an independent computation), to round-off of the CSV's 9 digits
    import csv

    with Results(path) as res:
        pr = res.pairs("joint")
    A = pr["area"]
    ref = ((pr["w"][-1] - pr["w"][0]) * A[:, None]).sum(axis=0) / A.sum()
    rows = list(csv.DictReader((tmp_path / "csv" / "joints.csv").open()))
    for i, axis in enumerate(("t1", "n")):
        last = [r for r in rows if r["quantity"] == f"w_{axis}_mean"][-1]
        assert float(last["value"]) == pytest.approx(ref[i], rel=1e-8, abs=1e-15)
    # the open share: the pairs open by more than OPEN_CRACK_MIN_M (the summary's rule),
    # by area, at every row
    from pfeie.interface import OPEN_CRACK_MIN_M

    opened = (pr["state"] == 3) & (pr["opening"] > OPEN_CRACK_MIN_M)
    share = [float(r["value"]) for r in rows if r["quantity"] == "open_share"]
    np.testing.assert_allclose(share, (opened * A).sum(axis=1) / A.sum(), rtol=1e-8, atol=0)
    final = list(csv.DictReader((tmp_path / "csv" / "pairs_final.csv").open()))
    assert float(final[0]["final_w_n_m"]) == pytest.approx(pr["w"][-1, 0, -1], rel=1e-8,
                                                            abs=1e-15)  # fmt: skip
    assert main(["report", str(path), "--out", str(tmp_path / "r.html")]) == 0
    html = (tmp_path / "r.html").read_text()
    # the figures of `pfeie plot` and those that need the model: the loads, the static
    # principal stresses, the static stresses along the joint
    assert "<h2>Joints</h2>" in html and html.count("data:image/png;base64") == 8 + 3
    assert main(["plot", str(tmp_path / "none.h5")]) == 2
    capsys.readouterr()


def test_run_writes_everything(tmp_path: Path) -> None:
    """The files of a run; the interfaces series (one facet type: a uniform XDMF topology)
    reads back with meshio, its last frame at the final time, its opening equal to the
    results file's to round-off; the HDF5 of the series is gzip-compressed."""
    import h5py
    import meshio

    p = _write(tmp_path, SMALL)
    assert main(["run", str(p), "--quiet"]) == 0
    names = {f.name for f in (tmp_path / "out").iterdir()}
    assert {"results.h5", "blocks.xdmf", "blocks.h5", "interfaces.xdmf", "interfaces.h5",
            "summary.json", "summary.txt"} <= names  # fmt: skip
    with Results(tmp_path / "out" / "results.h5") as res:
        t_end, opening = res.time[-1], res.pairs()["opening"][-1]
    with meshio.xdmf.TimeSeriesReader(str(tmp_path / "out" / "interfaces.xdmf")) as r:
        _, cells = r.read_points_cells()
        assert len(cells) == 1  # one facet type (the mesh's: linear lines here)
        t, pd, _ = r.read_data(r.num_steps - 1)
    assert t == pytest.approx(t_end, abs=1e-12)
    np.testing.assert_allclose(pd["opening"][: opening.size], opening, rtol=0, atol=1e-15)
    # the repacking of a series' HDF5 file: datasets above 8 kB compressed, all equal
    from pfeie.io._paraview import _compress

    h5 = tmp_path / "series.h5"
    big = np.tile(np.arange(3000.0), (3, 1)).T  # 72 kB
    with h5py.File(h5, "w") as f:
        f["data0"], f["data1"] = big, np.arange(4.0)
    _compress(h5)
    with h5py.File(h5, "r") as f:
        assert f["data0"].compression == "gzip" and f["data1"].compression is None
        np.testing.assert_array_equal(f["data0"][...], big)
        np.testing.assert_array_equal(f["data1"][...], np.arange(4.0))


def test_killed_run_leaves_a_readable_file(tmp_path: Path) -> None:
    """SIGKILL in the middle of a run: results.h5 opens and holds the rows written so far,
    marked not completed."""
    proc = start_run(_write(tmp_path, SMALL, duration=400.0), wait=6.0)
    proc.send_signal(signal.SIGKILL)
    proc.communicate(timeout=60)
    with Results(tmp_path / "out" / "results.h5") as r:
        assert not r.completed
        n = r.time.size
        assert n > 0 and r.probe("top")["u"].shape == (n, 2)
        assert r.pairs()["X"].shape[0] == n
