"""Storage of the results file and the ParaView series (``output.compression``,
``compression_level``, ``field_precision``): every setting reads back to the same arrays
(float64 bit for bit; float32 fields the float32 rounding of the float64 run), the
settings are recorded in the file, the ParaView series link the results file's fields
(HDF5 virtual datasets that meshio and VTK read back to the same values; NaN without the
results file) and hold the stress as its independent components (2D scalars, a 3D
Tensor6), the files shrink, the same inputs give the same data,
a resumed run keeps the file's storage and gives the same bits (a last chunk damaged by a
kill rewritten from the checkpoint), files written before these keys still read and
resume, and a bad value is refused with the key path, what was expected and what was
found."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from pfeie.cli import main
from pfeie.errors import InputError
from pfeie.io import Results, load_job, run_key, write_paraview
from pfeie.io._results import FORMAT_VERSION, HISTORY_ROWS, Storage
from test_cli import SMALL, _write
from test_robustness import msh22

#: the small model of test_cli (two blocks of 2 m × 1 m stacked, a joint between them) on
#: a mesh of 0.05 m quadrilaterals (1,722 nodes, the demo's 1,922); 0.6 s at 5 ms, fields
#: every 2nd step
TEXT = SMALL.replace('folder = "out"', 'folder = "out"\nfield_every = 2\nOUTPUT')
TEXT = re.sub(r'file = ".*\.msh"', 'file = "plate.msh"', TEXT)
SERIES = ("blocks.h5", "interfaces.h5")


def _plate(path: Path, n: int = 40) -> Path:
    """The mesh: a 2 m × 2 m square of n × n quadrilaterals, physical surfaces "rock"
    (y < 1) and "dam", lines "bottom" (y = 0) and "joint" (y = 1)."""
    h = 2.0 / n
    nodes = [(i * h, j * h, 0.0) for j in range(n + 1) for i in range(n + 1)]

    def node(i: int, j: int) -> int:
        return j * (n + 1) + i + 1

    names = {1: (2, "rock"), 2: (2, "dam"), 3: (1, "bottom"), 4: (1, "joint")}
    elements = [(len(nodes), 1, 3, [node(i, 0), node(i + 1, 0)]) for i in range(n)]
    elements += [(0, 1, 4, [node(i, n // 2), node(i + 1, n // 2)]) for i in range(n)]
    elements += [(0, 3, 1 if j < n // 2 else 2,
                  [node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)])
                 for j in range(n) for i in range(n)]  # fmt: skip
    elements = [(k + 1, t, ph, ns) for k, (_, t, ph, ns) in enumerate(elements)]
    return msh22(path, nodes, elements, names)


def _model(folder: Path, output: str = "", duration: float = 0.6) -> Path:
    folder.mkdir(exist_ok=True)
    _plate(folder / "plate.msh")
    return _write(folder, TEXT.replace("OUTPUT", output), duration=duration)


def _run(folder: Path, output: str = "", *extra: str, duration: float = 0.6) -> Path:
    assert main(["run", str(_model(folder, output, duration)), "--quiet", *extra]) == 0
    return folder / "out"


def _datasets(path: Path) -> dict[str, Any]:
    """Every dataset of an HDF5 file (names, values, dtypes), following hard links."""
    import h5py

    out: dict[str, Any] = {}
    with h5py.File(path, "r") as f:
        f.visititems(lambda n, o: out.__setitem__(n, o[...]) if isinstance(o, h5py.Dataset)
                     else None)  # fmt: skip
        for name in f:  # visititems visits a hard-linked dataset once
            if isinstance(f[name], h5py.Dataset):
                out[name] = f[name][...]
    return out


def _frames(xdmf: Path) -> list[tuple[float, dict[str, Any]]]:
    """Every frame of a series as meshio reads it: its time and point data."""
    import meshio

    with meshio.xdmf.TimeSeriesReader(str(xdmf)) as rd:
        rd.read_points_cells()
        return [rd.read_data(k)[:2] for k in range(rd.num_steps)]


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """The model run with each storage: the default (gzip 4) twice (the same inputs into
    the same folder: the first run's files copied away), no compression, gzip with float32
    fields (the demo's setting), lzf with float32 fields."""
    import shutil

    tmp = tmp_path_factory.mktemp("storage")
    first = _run(tmp / "gzip")
    shutil.copytree(first, tmp / "first")
    return {
        "first": tmp / "first",
        "gzip": _run(tmp / "gzip"),  # the same run again, into the same folder
        "none": _run(tmp / "none", 'compression = "none"'),
        "gzip32": _run(tmp / "gzip32", 'field_precision = "float32"'),  # the demo's
        "lzf32": _run(tmp / "lzf32", 'compression = "lzf"\nfield_precision = "float32"'),
    }


def test_every_storage_reads_back_the_same_arrays(runs: dict[str, Path]) -> None:
    """gzip, lzf and none store the same arrays (float64 bit for bit, the checkpoint
    included, which holds the last chunk of each compressed history besides); float32
    fields are the float32 rounding of the float64 run's; each file records its storage
    and is of format 1.3 or later; the filters and chunks are as set."""
    ref = _datasets(runs["none"] / "results.h5")
    assert not any(k.startswith("checkpoint/tail/") for k in ref)  # uncompressed: no tails
    for name in ("gzip", "lzf32"):
        got = _datasets(runs[name] / "results.h5")
        tails = {k for k in got if k.startswith("checkpoint/tail/")}
        assert "checkpoint/tail/history/pairs/X" in tails  # the last chunks (compressed)
        assert got.keys() - tails == ref.keys()
        for key, value in ref.items():
            if name == "lzf32" and key in ("fields/u", "fields/v", "fields/a"):
                assert got[key].dtype == np.float32
                np.testing.assert_array_equal(got[key], value.astype(np.float32), err_msg=key)
            else:
                assert got[key].dtype == value.dtype, key
                np.testing.assert_array_equal(got[key], value, err_msg=f"{name}: {key}")
    expected = {"gzip": ("gzip", 4, "float64"), "none": ("none", 0, "float64"),
                "lzf32": ("lzf", 0, "float32")}  # fmt: skip
    for name, (comp, level, precision) in expected.items():
        with Results(runs[name] / "results.h5") as res:
            meta = res.meta
            assert (meta["compression"], meta["compression_level"], meta["field_precision"]) \
                == (comp, level, precision)  # fmt: skip
            assert meta["format_version"] == FORMAT_VERSION  # 1.3 on
            f = res.f
            filt = None if comp == "none" else comp
            for key in ("history/pairs/X", "history/time", "fields/u", "mesh/points"):
                # (the fields, which the ParaView series links: gzip 1 for lzf)
                want = "gzip" if filt == "lzf" and key == "fields/u" else filt
                assert f[key].compression == want, (name, key)
                assert f[key].shuffle == (filt is not None)
            if comp != "none":
                assert f["fields/u"].compression_opts == (level if comp == "gzip" else 1)
            assert f["history/pairs/X"].chunks[0] == HISTORY_ROWS  # along time
            assert f["fields/u"].chunks == (1, *f["fields/u"].shape[1:])  # one row a chunk
            t, fields = res.fields()
            assert fields["u"].dtype == np.dtype(precision) and t.dtype == np.float64
            assert res.pairs()["X"].dtype == np.float64


def test_paraview_series_storage(runs: dict[str, Path]) -> None:
    """The series' HDF5 files: gzip (lzf becomes gzip at level 1: ParaView's HDF5 has no
    LZF filter), each table chunked by column, the cell data of every frame stored once;
    the displacement, velocity and acceleration of every frame virtual datasets that map
    the results file's fields (no copy); float32 point data (XDMF Precision 4) that VTK's
    XDMF reader (ParaView's) reads back equal to the results file's fields; the float64
    series equal whatever the filter."""
    import h5py
    import vtk  # type: ignore[import-untyped]
    from vtk.util.numpy_support import vtk_to_numpy  # type: ignore[import-untyped]

    for name in SERIES:
        ref, got = _datasets(runs["none"] / name), _datasets(runs["gzip"] / name)
        assert got.keys() == ref.keys()
        for key, value in ref.items():
            np.testing.assert_array_equal(got[key], value, err_msg=f"{name}: {key}")
    with h5py.File(runs["gzip"] / "blocks.h5", "r") as f, \
            h5py.File(runs["lzf32"] / "blocks.h5", "r") as g:  # fmt: skip
        n_f = len([k for k in f if k.startswith("velocity_")])
        for h, key in ((f, "u"), (f, "a"), (g, "v")):
            name = {"u": "displacement", "v": "velocity", "a": "acceleration"}[key]
            for i in (0, n_f - 1):
                ds = h[f"{name}_{i}"]
                assert ds.is_virtual and ds.shape[1] == 3
                sources = {(v.file_name, v.dset_name) for v in ds.virtual_sources()}
                assert sources == {("results.h5", f"fields/{key}"), (".", f"zero_{ds.dtype}")}
        stored = [k for k in f if not f[k].is_virtual]
        big = [k for k in stored if f[k].size * f[k].dtype.itemsize > 1024]
        assert big and all(f[k].compression == "gzip" for k in big)
        assert all(g[k].compression == "gzip" and g[k].compression_opts == 1
                   for k in big if k in g)  # fmt: skip
        assert all(f[k].ndim == 1 or f[k].chunks[1] == 1 for k in big)
    xdmf = (runs["lzf32"] / "blocks.xdmf").read_text()
    assert set(re.findall(r'Name="body".*?>blocks.h5:/(\w+)<', xdmf)) == {"body"}  # once
    assert re.search(r'Name="displacement".*?Precision="4"', xdmf)
    assert re.search(r'Name="stress_xx".*?Precision="4"', xdmf)
    with Results(runs["lzf32"] / "results.h5") as res:
        tf, fields = res.fields()
    r = vtk.vtkXdmfReader()
    r.SetFileName(str(runs["lzf32"] / "blocks.xdmf"))
    r.UpdateInformation()
    r.UpdateTimeStep(float(tf[-1]))
    grid = r.GetOutputDataObject(0)
    u = vtk_to_numpy(grid.GetPointData().GetArray("displacement"))
    body = vtk_to_numpy(grid.GetCellData().GetArray("body"))
    assert u.dtype == np.float32 and body.size == grid.GetNumberOfCells()
    np.testing.assert_array_equal(u[:, :2], fields["u"][-1])
    np.testing.assert_array_equal(u[:, 2], 0.0)
    names = {grid.GetPointData().GetArrayName(k)
             for k in range(grid.GetPointData().GetNumberOfArrays())}  # fmt: skip
    assert names == {"displacement", "velocity", "acceleration", "stress_xx", "stress_yy",
                     "stress_xy", "stress_zz"}  # fmt: skip


def test_series_read_back_with_meshio(runs: dict[str, Path]) -> None:
    """meshio reads every frame of the blocks series (float64 and float32 fields): the
    displacement, velocity and acceleration are the results file's fields, value for
    value (z = 0); the stress components those of the nodal stress of the stored
    displacement (for float32, its float32 rounding: to 1e-7 relative); and the float32
    series' stress, computed from float32 displacements, is the float64 series' to
    1e-5 of the frame's largest stress (measured 1.7e-6, the demo 1.7e-5: the
    displacements' rounding, 6e-8 relative, grows by their ratio to the differences
    between neighbouring nodes that make the strain)."""
    import meshio

    from pfeie.io._paraview import stress_components

    model = load_job(runs["gzip"].parent / "model.toml").model
    comps = stress_components(2, model.plane)
    assert list(comps) == ["stress_xx", "stress_yy", "stress_xy", "stress_zz"]
    stress = {}
    for name in ("gzip", "gzip32"):
        with Results(runs[name] / "results.h5") as res:
            tf, fields = res.fields()
        precision = fields["u"].dtype
        with meshio.xdmf.TimeSeriesReader(str(runs[name] / "blocks.xdmf")) as rd:
            points, _ = rd.read_points_cells()
            assert rd.num_steps == tf.size and points.shape[0] == model.mesh.n_points
            frames = [rd.read_data(k) for k in range(rd.num_steps)]
        stress[name] = []
        for k, (t, pd, cd) in enumerate(frames):
            assert t == tf[k] and set(cd) == {"body"}
            for attr, key in (("displacement", "u"), ("velocity", "v"), ("acceleration", "a")):
                assert pd[attr].dtype == precision and pd[attr].shape == (points.shape[0], 3)
                np.testing.assert_array_equal(pd[attr][:, :2], fields[key][k])
                np.testing.assert_array_equal(pd[attr][:, 2], 0.0)
            sig = model.nodal_stress(fields["u"][k].ravel())
            got = np.stack([pd[c] for c in comps], axis=1)
            ref = np.stack([sig[:, i, j] for (i, j), in comps.values()], axis=1)
            assert got.dtype == precision
            np.testing.assert_allclose(got, ref, rtol=1e-7 if precision == np.float32 else 0,
                                       atol=0)  # fmt: skip
            stress[name].append(got)
    a, b = np.array(stress["gzip"]), np.array(stress["gzip32"], dtype=float)
    scale = np.abs(a).max(axis=(1, 2), keepdims=True)  # each frame's largest stress
    assert (np.abs(b - a) / scale).max() < 1e-5


def test_series_without_the_results_file(runs: dict[str, Path], tmp_path: Path) -> None:
    """The series copied away from its results file: its fields read as NaN (the virtual
    datasets' fill value), never as zeros that would look like a dam at rest; its stress
    (stored in the series) is still there."""
    import shutil

    import h5py

    for name in ("blocks.xdmf", "blocks.h5"):
        shutil.copy(runs["gzip"] / name, tmp_path / name)
    with h5py.File(tmp_path / "blocks.h5", "r") as f:
        u = f["displacement_1"][...]
        assert np.isnan(u[:, :2]).all() and (u[:, 2] == 0).all()
    with h5py.File(runs["gzip"] / "blocks.h5", "r") as f:
        assert np.isfinite(f["displacement_1"][...]).all()


def test_3d_stress_is_one_tensor6(tmp_path: Path) -> None:
    """In 3D the series' stress is one attribute, its 6 independent components in XDMF's
    Tensor6 order (xx, xy, xz, yy, yz, zz), which VTK's XDMF reader (ParaView's) expands
    to the symmetric 3 × 3 tensor equal to the nodal stress; the 3-component fields map
    the results file's without padding. The results file here is written by hand: random
    fields on a box of hexahedra."""
    import h5py
    import vtk  # type: ignore[import-untyped]
    from vtk.util.numpy_support import vtk_to_numpy  # type: ignore[import-untyped]

    import pfeie as pf

    mesh = pf.box(1.0, 1.0, 2.0, 2, 2, 3, cell="hexahedron")
    mesh.add_cell_group("b", lambda x: x[:, 0] > -1)
    model = pf.Model(mesh, [pf.Block("b", pf.Elastic(30e9, 0.25, 2500))])
    rng = np.random.default_rng(3)
    n_f, n = 3, mesh.n_points
    path = tmp_path / "results.h5"
    with h5py.File(path, "w") as f:
        f.attrs.update(pfeie_version="test", format_version="1.3", **Storage.of().attrs)
        f["mesh/points"] = mesh.points
        for key in ("history/time", "history/rigid", "history/energy/kinetic"):
            f[key] = np.zeros(0)
        f.create_group("history/probes")
        f["fields/time"] = np.arange(n_f) * 0.1
        for key in ("u", "v", "a"):
            f[f"fields/{key}"] = rng.normal(size=(n_f, n, 3)) * 1e-3
        u = f["fields/u"][...]
    write_paraview(path, model, tmp_path / "pv")
    with h5py.File(tmp_path / "pv" / "blocks.h5", "r") as f:
        assert {v.dset_name for v in f["displacement_2"].virtual_sources()} == {"fields/u"}
    r = vtk.vtkXdmfReader()
    r.SetFileName(str(tmp_path / "pv" / "blocks.xdmf"))
    r.UpdateInformation()
    r.UpdateTimeStep(0.2)
    pd = r.GetOutputDataObject(0).GetPointData()
    sig = vtk_to_numpy(pd.GetArray("stress")).reshape(-1, 3, 3)
    np.testing.assert_array_equal(sig, model.nodal_stress(u[2].ravel()))
    np.testing.assert_array_equal(vtk_to_numpy(pd.GetArray("displacement")), u[2])
    text = (tmp_path / "pv" / "blocks.xdmf").read_text()
    assert re.search(r'Name="stress" AttributeType="Tensor6"', text)


def test_the_files_shrink(runs: dict[str, Path]) -> None:
    """The files of the run (results.h5, the series' HDF5 and XDMF) against those that
    the series would make if it still copied the fields (3 components) and the full
    stress tensor (9), float64 and uncompressed, as before the series linked the results
    file: measured 2.68 times smaller with the defaults, 4.96 times with gzip and float32
    fields (the demo's setting; the demo: 2.53 and 4.20 before the interfaces' global
    vectors, docs/results.md), 4.84 times with lzf and float32; without compression 2.09
    (2.73, 5.13, 5.00 and 2.12 before the slip and shear vectors were added to the
    interfaces series). Asserted with a margin of 3 %."""
    import h5py

    files = ("results.h5", *SERIES, "blocks.xdmf", "interfaces.xdmf")

    def size(name: str) -> int:
        return sum((runs[name] / f).stat().st_size for f in files)

    with h5py.File(runs["none"] / "results.h5", "r") as f:
        n_f, n = f["fields/u"].shape[:2]
    copied = n_f * n * (3 * 3 + 9) * 8  # displacement, velocity, acceleration, stress
    before = size("none") + copied - (runs["none"] / "blocks.h5").stat().st_size
    measured = {"none": 2.09, "gzip": 2.68, "gzip32": 4.96, "lzf32": 4.84}
    for name, ratio in measured.items():
        assert before / size(name) > ratio / 1.03, name


def test_same_inputs_same_data(runs: dict[str, Path]) -> None:
    """Two runs of the same inputs store the same data (compression is deterministic; the
    attributes differ only by the wall time in the summary)."""
    import h5py

    for name in ("results.h5", *SERIES):
        a, b = _datasets(runs["first"] / name), _datasets(runs["gzip"] / name)
        assert a.keys() == b.keys()
        for key, value in a.items():
            np.testing.assert_array_equal(b[key], value, err_msg=f"{name}: {key}")
    with h5py.File(runs["first"] / "results.h5") as f, h5py.File(runs["gzip"] / "results.h5") as g:
        differ = {k for k in f.attrs if str(f.attrs[k]) != str(g.attrs[k])}
    assert differ <= {"results_summary"}


def test_resume_keeps_the_files_storage(runs: dict[str, Path], tmp_path: Path) -> None:
    """A run with lzf and float32 fields stopped at 0.25 s, the last chunk of four of its
    histories then damaged (as a kill while a block is written can leave them: HDF5 may
    reuse the place of a compressed chunk that grew before its index is on disk), and
    resumed with another compression in the model file: the file's own storage is kept,
    the damaged chunks are rewritten from the checkpoint, and the file holds the same bits
    as the uninterrupted run. The storage keys but field_precision = "float32" leave the
    run key as it was before they existed (older files resume)."""
    import h5py

    out = _run(tmp_path / "part", 'compression = "lzf"\nfield_precision = "float32"',
               "--duration", "0.25")  # fmt: skip
    damaged = ("history/probes/u", "history/pairs/broken", "history/energy/kinetic",
               "fields/time")  # fmt: skip
    with h5py.File(out / "results.h5", "r") as f:
        assert all(f"checkpoint/tail/{k}" in f for k in damaged)
        spans = [f[k].id.get_chunk_info(f[k].id.get_num_chunks() - 1) for k in damaged]
    with open(out / "results.h5", "r+b") as fh:
        for info in spans:
            fh.seek(info.byte_offset)
            fh.write(b"\xa5" * info.size)
    with h5py.File(out / "results.h5", "r") as f:
        for k in damaged:
            with pytest.raises(OSError):
                f[k][...]
    p = out.parent / "model.toml"
    p.write_text(p.read_text().replace('compression = "lzf"', 'compression = "none"'))
    assert main(["run", str(p), "--quiet", "--resume"]) == 0
    ref, got = _datasets(runs["lzf32"] / "results.h5"), _datasets(out / "results.h5")
    for key, value in ref.items():
        if not key.startswith("checkpoint"):
            np.testing.assert_array_equal(got[key], value, err_msg=key)
    with Results(out / "results.h5") as res:
        assert res.meta["compression"] == "lzf" and res.f["history/time"].compression == "lzf"
        assert res.f["checkpoint/kin/u"].dtype == np.float64
    job = load_job(_model(tmp_path / "key"))
    key = run_key(job)
    for k in ("compression", "compression_level", "field_precision"):
        del job.spec["output"][k]
    assert run_key(job) == key  # as a model file written before these keys
    job.spec["output"].update(compression="lzf", compression_level=9)
    assert run_key(job) == key
    job.spec["output"]["field_precision"] = "float32"
    assert run_key(job) != key


def test_a_file_of_format_1_2_reads(runs: dict[str, Path], tmp_path: Path) -> None:
    """A results file without the storage attributes (format 1.2, gzip-compressed
    histories) is read, exported and turned into ParaView series with the defaults."""
    import shutil

    import h5py

    path = tmp_path / "old.h5"
    shutil.copy(runs["gzip"] / "results.h5", path)
    with h5py.File(path, "r+") as f:
        for k in ("compression", "compression_level", "field_precision"):
            del f.attrs[k]
        f.attrs["format_version"] = "1.2"
        assert Storage.of_file(f) == Storage.of()
    with Results(path) as res:
        assert res.fields()[1]["u"].dtype == np.float64 and res.n_times > 0
    job = load_job(runs["gzip"].parent / "model.toml")
    write_paraview(path, job.model, tmp_path / "pv")
    for name in SERIES:
        ref, got = _datasets(runs["gzip"] / name), _datasets(tmp_path / "pv" / name)
        for key, value in ref.items():
            np.testing.assert_array_equal(got[key], value, err_msg=f"{name}: {key}")
    assert main(["export", str(path), "--csv", str(tmp_path / "csv")]) == 0


def test_lzf_fields_of_an_older_file_are_copied(runs: dict[str, Path], tmp_path: Path) -> None:
    """A results file whose fields are lzf (written before the fields were stored with
    gzip for the series): its series copies them (gzip), as ParaView could not read them
    through a link, and they read back the same."""
    import shutil

    import h5py

    path = tmp_path / "results.h5"
    shutil.copy(runs["lzf32"] / "results.h5", path)
    with h5py.File(path, "r+") as f:
        for key in ("u", "v", "a"):
            data = f[f"fields/{key}"][...]
            del f[f"fields/{key}"]
            f.create_dataset(f"fields/{key}", data=data, chunks=(1, *data.shape[1:]),
                             compression="lzf", shuffle=True)  # fmt: skip
    job = load_job(runs["lzf32"].parent / "model.toml")
    write_paraview(path, job.model, tmp_path)
    ref, got = _frames(runs["lzf32"] / "blocks.xdmf"), _frames(tmp_path / "blocks.xdmf")
    assert len(got) == len(ref)
    for (t, pd), (t_ref, pd_ref) in zip(got, ref, strict=True):
        assert t == t_ref and pd.keys() == pd_ref.keys()
        for key, value in pd_ref.items():
            np.testing.assert_array_equal(pd[key], value, err_msg=key)
    with h5py.File(tmp_path / "blocks.h5", "r") as f:
        ds = f["velocity_3"]
        assert not ds.is_virtual and ds.compression == "gzip" and ds.dtype == np.float32


@pytest.mark.parametrize(
    ("line", "match"),
    [
        ('compression = "zip"',
         r"output\.compression: expected one of 'gzip', 'lzf', 'none', found 'zip'"),
        ("compression_level = 0", r"output\.compression_level: expected an integer from 1 to "
         r"9, found 0"),
        ("compression_level = 10", r"output\.compression_level: expected an integer from 1 to "
         r"9, found 10"),
        ("compression_level = 4.0", r"output\.compression_level: expected an integer, found "
         r"a number 4\.0"),
        ('field_precision = "float16"',
         r"output\.field_precision: expected one of 'float64', 'float32', found 'float16'"),
    ],
)  # fmt: skip
def test_bad_values_are_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], line: str, match: str
) -> None:
    p = _model(tmp_path, line)
    with pytest.raises(InputError, match=match) as err:
        load_job(p)
    assert str(err.value).startswith(str(p))
    assert main(["check", str(p)]) == 2
    err_text = capsys.readouterr().err
    assert "pfeie: error" in err_text and "Traceback" not in err_text
