"""ParaView output: XDMF + HDF5 time series of the blocks and of the interfaces.

``blocks.xdmf`` (with ``blocks.h5``): the split mesh with, at every field output time,
``displacement``, ``velocity``, ``acceleration`` (point data, m, m/s, m/s²) and ``stress``
(point data, the 3 × 3 tensor as 9 components, Pa), plus the cell data ``body``.

``interfaces.xdmf``: the interfaces as their own mesh (the side-a faces of each joint,
whose nodes are the pairs) with, at every field output time, point data ``opening`` (m),
``slip`` (m, tangential components), ``normal_stress`` (Pa, compression +),
``shear_stress`` (Pa), ``state`` (0 intact, 1 stick, 2 slide, 3 open), ``broken`` (0/1)
and the cell data ``interface`` (index into the names). Open either file in ParaView
(XDMF3 reader) and play the time steps.

The HDF5 files are stored as the results file (:class:`~pfeie.io._results.Storage`: its
compression, gzip for lzf, which ParaView cannot read, and its field precision for the
point data); each column of a table is a chunk, and a dataset equal to an earlier one
(the cell data of every frame) is stored once, the later names hard links to it.
"""

from __future__ import annotations

import contextlib
import hashlib
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import PfeieError
from ._results import Results, Storage, _guess_chunks


def write_paraview(
    results: str | Path, model: Any, folder: str | Path, *, storage: Storage | None = None
) -> list[Path]:
    """Write the blocks and interfaces series of a results file; returns the XDMF paths.
    Their HDF5 files are stored as ``storage``, by default the results file's (with gzip
    at level 1 for lzf: :meth:`Storage.for_paraview`)."""
    try:
        from meshio.xdmf import TimeSeriesWriter
    except ImportError:  # pragma: no cover
        raise PfeieError("ParaView output needs meshio: pip install 'pfeie[io]'") from None
    out = Path(folder)
    out.mkdir(parents=True, exist_ok=True)
    written = []
    with Results(results) as res:
        st = (Storage.of_file(res.f) if storage is None else storage).for_paraview()
        dt = st.field_dtype
        tf, fields = res.fields()
        hist_t = res.time
        mesh = model.mesh
        cells = [(t, c) for t, c in mesh.cells.items()]
        body = model.body_of_node
        cell_body = [body[c[:, 0]] for _, c in cells]
        path = out / "blocks.xdmf"
        with contextlib.chdir(out), TimeSeriesWriter(path.name) as w:  # meshio writes the .h5
            # beside the working directory's file name
            w.write_points_cells(mesh.points, cells)
            for i, t in enumerate(tf):
                u = fields["u"][i]
                sig = model.nodal_stress(u.ravel()).reshape(-1, 9)
                w.write_data(float(t), point_data={
                    "displacement": _pad3(u, dt), "velocity": _pad3(fields["v"][i], dt),
                    "acceleration": _pad3(fields["a"][i], dt), "stress": sig.astype(dt),
                }, cell_data={"body": cell_body})  # fmt: skip
        _compress(out / "blocks.h5", st)
        _one_grid(out / "blocks.xdmf")
        written.append(path)
        if res.has_envelope:
            written.append(_write_envelope(res.envelope(), mesh, cells, out))
        if model.pairs is not None and res.interface_names:
            path = out / "interfaces.xdmf"
            pts, icells, cell_iface, order = _interface_mesh(model)
            pairs = res.pairs()
            with contextlib.chdir(out), TimeSeriesWriter(path.name) as w:
                w.write_points_cells(pts, icells)
                for t in tf:
                    j = int(np.argmin(np.abs(hist_t - t)))
                    data = {
                        "opening": pairs["opening"][j],
                        "slip": pairs["slip"][j],
                        "normal_stress": pairs["normal_stress"][j],
                        "shear_stress": pairs["shear_stress"][j],
                        "state": pairs["state"][j].astype(float),
                        "broken": pairs["broken"][j].astype(float),
                    }
                    pd = {k: _on_points(v, order).astype(dt) for k, v in data.items()}
                    w.write_data(float(t), point_data=pd, cell_data={"interface": cell_iface})
            _compress(out / "interfaces.h5", st)
            _one_grid(out / "interfaces.xdmf")
            written.append(path)
    return written


def write_modes(result: Any, model: Any, folder: str | Path) -> list[Path]:
    """The mode shapes of a :class:`~pfeie.solvers.ModalResult` as a ParaView series
    (``modes.xdmf``: one frame per mode, "time" = the mode number; point data ``shape``,
    scaled to a largest displacement of 1, and cell data ``body``) and ``modes.csv``
    (mode, frequency (Hz), period (s), effective modal mass (kg) and its share of the free
    mass along each axis)."""
    try:
        from meshio.xdmf import TimeSeriesWriter
    except ImportError:  # pragma: no cover
        raise PfeieError("ParaView output needs meshio: pip install 'pfeie[io]'") from None
    out = Path(folder)
    out.mkdir(parents=True, exist_ok=True)
    mesh = model.mesh
    cells = [(t, c) for t, c in mesh.cells.items()]
    cell_body = [model.body_of_node[c[:, 0]] for _, c in cells]
    path = out / "modes.xdmf"
    with contextlib.chdir(out), TimeSeriesWriter(path.name) as w:
        w.write_points_cells(mesh.points, cells)
        for k, shape in enumerate(result.shapes):
            peak = float(np.linalg.norm(shape, axis=1).max())
            w.write_data(float(k + 1), point_data={"shape": _pad3(shape / max(peak, 1e-300))},
                         cell_data={"body": cell_body})  # fmt: skip
    _compress(out / "modes.h5")
    _one_grid(out / "modes.xdmf")
    axes = "xyz"[: mesh.dim]
    csv_path = out / "modes.csv"
    total = np.asarray(result.total_mass)
    rows = ["mode,frequency_hz,period_s," + ",".join(
        f"mass_{a}_kg,share_{a}" for a in axes)]  # fmt: skip
    for k, f in enumerate(result.frequencies):
        me = result.effective_mass[k]
        share = me / np.maximum(total, 1e-300) if total.size else np.full(me.shape, np.nan)
        rows.append(f"{k + 1},{f:.9g},{1 / f:.9g}," + ",".join(
            f"{m:.9g},{s:.6g}" for m, s in zip(me, share, strict=True)))  # fmt: skip
    csv_path.write_text("\n".join(rows) + "\n")
    return [path, csv_path]


def _write_envelope(env: dict[str, np.ndarray], mesh: Any, cells: list[Any], out: Path) -> Path:
    """``envelope.vtu``: the stress envelope of the run on the mesh (point data from the
    nodal stress, cell data over each cell's quadrature points): ``max_principal`` and
    ``min_principal`` (Pa, tension positive) and the times they were reached (s); with
    tensile strengths the cell data ``dcr`` and ``cid`` (1, s)."""
    import meshio

    sizes = np.cumsum([len(c) for _, c in cells])[:-1]
    point_data, cell_data = {}, {}
    for ext in ("max", "min"):
        for suffix in ("", "_time"):
            name = f"{ext}_principal{suffix}"
            point_data[name] = env[f"node_{ext}{suffix}"]
            cell_data[name] = np.split(env[f"cell_{ext}{suffix}"], sizes)
    for key in ("dcr", "cid"):  # with tensile strengths (EM 1110-2-6053)
        if f"cell_{key}" in env:
            cell_data[key] = np.split(env[f"cell_{key}"], sizes)
    path = out / "envelope.vtu"
    meshio.write(path, meshio.Mesh(_pad3(mesh.points), cells, point_data=point_data,
                                   cell_data=cell_data), binary=True)  # fmt: skip
    return path


def _one_grid(path: Path) -> None:
    """Rewrite meshio's XDMF so that its only grid is the time series: meshio writes the
    mesh as a grid of its own beside the series (ParaView shows it as a second, static
    block) and points every frame at it with an XInclude. Here every frame carries the
    Topology and Geometry elements themselves (they point at the same HDF5 datasets: the
    mesh is stored once) and is marked ``GridType="Uniform"``, which meshio's reader and
    VTK's XDMF reader both read."""
    import copy
    import xml.etree.ElementTree as ET

    xi = "{http://www.w3.org/2003/XInclude}include"
    tree = ET.parse(path)
    domain = tree.getroot().find("Domain")
    if domain is None:  # pragma: no cover - meshio always writes one
        return
    mesh = next((g for g in domain.findall("Grid") if g.get("Name") == "mesh"), None)
    series = next((g for g in domain.findall("Grid") if g.get("GridType") == "Collection"),
                  None)  # fmt: skip
    if mesh is None or series is None:  # pragma: no cover
        return
    parts = [e for e in mesh if e.tag in ("Topology", "Geometry")]
    for frame in series.findall("Grid"):
        frame.set("GridType", "Uniform")
        for k, inc in enumerate(e for e in list(frame) if e.tag == xi):
            frame.remove(inc)
            if k == 0:
                for j, part in enumerate(parts):
                    frame.insert(j, copy.deepcopy(part))
    domain.remove(mesh)
    ET.register_namespace("xi", "http://www.w3.org/2003/XInclude")
    tree.write(path, encoding="unicode")


def _compress(path: Path, storage: Storage | None = None) -> None:
    """Rewrite the HDF5 file that meshio wrote (uncompressed) with the filters of
    ``storage`` (default: the ``[output]`` defaults, gzip), dataset for dataset under the
    same names, so that the XDMF still points at them. Each column of a table is a chunk
    (the zero z components of 2D vectors and the zero components of a 2D stress then
    compress to almost nothing); a dataset equal to an earlier one (the cell data ``body``
    or ``interface`` of every frame) becomes a hard link to it, stored once (the demo's
    blocks.h5: 42.0 MB → 23.9 MB with the defaults)."""
    import h5py

    st = Storage.of() if storage is None else storage
    tmp = path.with_name(path.name + ".tmp")
    seen: dict[tuple[str, tuple[int, ...], bytes], str] = {}
    with h5py.File(path, "r") as src, h5py.File(tmp, "w") as dst:
        for name in sorted(src, key=lambda k: (len(k), k)):  # data0, data1, …, data10, …
            data = np.asarray(src[name][...])
            key = (data.dtype.str, data.shape, hashlib.sha256(data.tobytes()).digest())
            if key in seen:
                dst[name] = dst[seen[key]]  # a hard link: the same dataset
                continue
            seen[key] = name
            st.create(dst, name, data, chunks=_column_chunks(data))
    tmp.replace(path)


def _column_chunks(data: np.ndarray) -> tuple[int, ...] | None:
    """Chunks of one column (at most :data:`~pfeie.io._results.CHUNK_BYTES`) for a table;
    None (:meth:`Storage.create`'s default: whole rows) otherwise."""
    if data.ndim != 2 or not data.size:
        return None
    return _guess_chunks((data.shape[0], 1), data.itemsize)


def _pad3(a: np.ndarray, dtype: Any = float) -> np.ndarray:
    """2D vectors padded to 3 components (ParaView's vectors), as ``dtype``."""
    a = np.asarray(a, dtype=dtype)
    if a.shape[1] == 3:
        return a
    return np.hstack([a, np.zeros((a.shape[0], 3 - a.shape[1]), dtype=a.dtype)])


def _interface_mesh(model: Any) -> tuple[np.ndarray, list[tuple[str, np.ndarray]], list[Any], Any]:
    """Points (one per pair, plus crack-tip nodes), the side-a faces as cells, the
    interface index per cell, and the map from points to pairs (−1: no pair)."""
    P = model.pairs
    mesh = model.mesh
    pair_of_node = np.full(mesh.n_points, -1, dtype=np.int64)
    pair_of_node[P.node_a] = np.arange(P.n)
    cells, tags = [], []
    extra: list[int] = []
    for j, name in enumerate(P.names):
        for ftype, conn in mesh.facet_groups.get(f"{name}:a", {}).items():
            ids = pair_of_node[conn]
            missing = np.unique(conn[ids < 0])
            for node in missing:  # crack-tip nodes: points without a pair
                if node not in extra:
                    extra.append(int(node))
            cells.append((ftype, conn))
            tags.append(np.full(conn.shape[0], j))
    nodes = np.concatenate([P.node_a, np.asarray(extra, dtype=np.int64)])
    local = np.full(mesh.n_points, -1, dtype=np.int64)
    local[nodes] = np.arange(nodes.size)
    # one cell block per facet type (the joints' blocks merged): a single type is written as
    # a uniform XDMF topology, which every XDMF reader (meshio's included) reads
    types = list(dict.fromkeys(t for t, _ in cells))
    merged = [(t, np.concatenate([local[c] for tt, c in cells if tt == t])) for t in types]
    tags = [np.concatenate([g for (tt, _), g in zip(cells, tags, strict=True) if tt == t])
            for t in types]  # fmt: skip
    cells = merged
    order = np.concatenate([np.arange(P.n), np.full(len(extra), -1)])
    return mesh.points[nodes], cells, tags, order


def _on_points(values: np.ndarray, order: np.ndarray) -> np.ndarray:
    """Pair values on the interface points (NaN on crack-tip points)."""
    shape = (order.size, *values.shape[1:])
    out = np.full(shape, np.nan)
    ok = order >= 0
    out[ok] = values[order[ok]]
    return out
