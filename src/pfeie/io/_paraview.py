"""ParaView output: XDMF + HDF5 time series of the blocks and of the interfaces.

``blocks.xdmf`` (with ``blocks.h5``): the split mesh with, at every field output time,
``displacement``, ``velocity``, ``acceleration`` (point data, m, m/s, m/s², 3 components,
z = 0 in 2D) and the stress (point data, Pa): in 3D ``stress``, the symmetric tensor as
its 6 independent components (XDMF's ``Tensor6``: xx, xy, xz, yy, yz, zz; VTK's XDMF
reader, ParaView's, expands it to the full tensor), in 2D the scalars ``stress_xx``,
``stress_yy``, ``stress_xy``, and ``stress_zz`` in plane strain (zero in plane stress: not
written); plus the cell data ``body``. The displacement, velocity and acceleration are
not copied: each frame's is an HDF5 virtual dataset of ``blocks.h5`` that maps one row of
the results file's ``/fields/u``, ``v``, ``a`` (:meth:`_Series.link`), so the series
needs the results file at the same relative path (beside it, as ``pfeie run`` writes
them).

``interfaces.xdmf``: the interfaces as their own mesh (the side-a faces of each joint,
whose nodes are the pairs) with, at every field output time, point data ``opening`` (m),
``slip`` (m: in 2D the tangential component along the pair's t₁, signed; in 3D the
magnitude, with the components along t₁ and t₂ as the scalars ``slip_t1``, ``slip_t2``),
``normal_stress`` (Pa, compression +), ``shear_stress`` (Pa, the same way, on side b),
``slip_vector`` and ``shear_vector`` (the same two as 3-component vectors in global axes,
through the pairs' frames, for glyphs and Warp By Vector), ``state`` (0 intact, 1 stick,
2 slide, 3 open), ``broken`` (0/1)
and the cell data ``interface`` (index into the names). Open either file in ParaView
(XDMF3 reader) and play the time steps.

The HDF5 files are stored as the results file (:class:`~pfeie.io._results.Storage`: its
compression, gzip for lzf, which ParaView cannot read, and its field precision for the
point data), in the file format of HDF5 1.10 (:data:`LIBVER`); each column of a table is
a chunk, and an array equal to one stored already (the cell data of every frame, a
joint's states while they do not change) is stored once, every frame naming it.
"""

from __future__ import annotations

import contextlib
import hashlib
import os
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import PfeieError
from ._results import Results, Storage, _guess_chunks


def write_paraview(
    results: str | Path, model: Any, folder: str | Path, *, storage: Storage | None = None
) -> list[Path]:
    """Write the blocks and interfaces series of a results file; returns the XDMF paths.
    The blocks series links the results file's fields (:meth:`_Series.link`: the results
    file must stay at the same path relative to the series, beside it as ``pfeie run``
    writes them); the other arrays of both HDF5 files are stored as ``storage``, by
    default the results file's (with gzip at level 1 for lzf: :meth:`Storage.for_paraview`)."""
    try:
        import meshio  # noqa: F401 - the cell types' XDMF names
    except ImportError:  # pragma: no cover
        raise PfeieError("ParaView output needs meshio: pip install 'pfeie[io]'") from None
    out = Path(folder)
    out.mkdir(parents=True, exist_ok=True)
    written = []
    with Results(results) as res:
        st = (Storage.of_file(res.f) if storage is None else storage).for_paraview()
        dt = st.field_dtype
        tf = np.asarray(res.f["fields/time"][...])
        hist_t = res.time
        mesh = model.mesh
        cells = [(t, c) for t, c in mesh.cells.items()]
        body = model.body_of_node
        components = stress_components(mesh.dim, getattr(model, "plane", "strain"))
        with _Series(out / "blocks.xdmf", mesh.points, cells, st) as s:
            cell_body = s.store("body", np.concatenate([body[c[:, 0]] for _, c in cells]))
            for i, t in enumerate(tf):
                sig = model.nodal_stress(np.asarray(res.f["fields/u"][i]).ravel())
                point = {name: s.link(res.f, res.path, key, i, f"{name}_{i}")
                         for name, key in LINKED.items()}  # fmt: skip
                for name, ij in components.items():
                    rows, cols = [a for a, _ in ij], [b for _, b in ij]
                    point[name] = s.store(f"{name}_{i}", _squeeze(sig[:, rows, cols]).astype(dt))
                s.frame(float(t), point, {"body": cell_body})
        written.append(s.xdmf)
        if res.has_envelope:
            written.append(_write_envelope(res.envelope(), mesh, cells, out))
        if model.pairs is not None and res.interface_names:
            pts, icells, cell_iface, order = _interface_mesh(model)
            pairs = res.pairs()
            tangent = model.pairs.frame[:, :-1, :]  # (m, d − 1, d): the tangential rows
            with _Series(out / "interfaces.xdmf", pts, icells, st) as s:
                iface = s.store("interface", np.concatenate(cell_iface))
                for i, t in enumerate(tf):
                    j = int(np.argmin(np.abs(hist_t - t)))
                    data = {
                        "opening": pairs["opening"][j],
                        **_tangential("slip", pairs["slip"][j]),
                        "normal_stress": pairs["normal_stress"][j],
                        **_tangential("shear_stress", pairs["shear_stress"][j]),
                        "state": pairs["state"][j].astype(float),
                        "broken": pairs["broken"][j].astype(float),
                        "slip_vector": _global(tangent, pairs["slip"][j]),
                        "shear_vector": _global(tangent, pairs["shear_stress"][j]),
                    }
                    point = {k: s.store(f"{k}_{i}", _on_points(v, order).astype(dt))
                             for k, v in data.items()}  # fmt: skip
                    s.frame(float(t), point, {"interface": iface})
            written.append(s.xdmf)
    return written


class _Series:
    """A ParaView time series being written: ``<name>.xdmf`` and ``<name>.h5`` (the XDMF
    path's stem) in one folder. One temporal collection of uniform grids (the frames),
    each with the Topology and Geometry of the one stored mesh (meshio's layout would add
    the mesh as a grid of its own, which ParaView shows as a second, static block) and its
    attributes, each a dataset of the HDF5 file written once (a dataset that every frame
    shows, such as the cell data ``body``, is stored once and named by every frame).
    meshio's and VTK's XDMF readers (ParaView's) read it."""

    def __init__(self, xdmf: Path, points: np.ndarray, cells: list[tuple[str, np.ndarray]],
                 storage: Storage) -> None:  # fmt: skip
        import xml.etree.ElementTree as ET

        import h5py

        self.xdmf, self.h5 = xdmf, xdmf.with_suffix(".h5")
        self.storage = storage
        self.g = h5py.File(self.h5, "w", libver=LIBVER)
        self._shapes: dict[str, tuple[tuple[int, ...], np.dtype[Any]]] = {}
        self._seen: dict[tuple[str, tuple[int, ...], bytes], str] = {}
        root = ET.Element("Xdmf", Version="3.0")
        self.tree = ET.ElementTree(root)
        self.series = ET.SubElement(ET.SubElement(root, "Domain"), "Grid", Name="TimeSeries",
                                    GridType="Collection", CollectionType="Temporal")  # fmt: skip
        self.mesh = [self._geometry(np.asarray(points)), self._topology(cells)]

    def __enter__(self) -> _Series:
        return self

    def __exit__(self, *exc: object) -> None:
        self.g.close()
        if exc[0] is None:
            self.tree.write(self.xdmf, encoding="unicode")

    def store(self, name: str, data: np.ndarray) -> str:
        """Store ``data`` as the dataset ``name`` (compressed as the storage says if it has
        more than :data:`SERIES_SMALL` bytes, a table one column a chunk) and return its
        name; or, if an equal array is stored already (a joint's states while they do not
        change), return that one's."""
        key = (data.dtype.str, data.shape, hashlib.sha256(data.tobytes()).digest())
        if key in self._seen:
            return self._seen[key]
        self.storage.create(self.g, name, data, chunks=_column_chunks(data), small=SERIES_SMALL)
        self._shapes[name] = (data.shape, data.dtype)
        self._seen[key] = name
        return name

    def link(self, f: Any, results: Path, key: str, i: int, name: str) -> str:
        """The virtual dataset ``name`` (n, 3) whose first d columns map row ``i`` of
        the results file's ``/fields/<key>`` (u, v or a) and whose other columns (2D) a
        stored column of zeros: the field of frame i without a copy. The results file is
        named by its path relative to the series' (HDF5 resolves it from the series'
        folder, wherever the reader runs). Where it cannot be found, a reader gets the
        fill value NaN, not zeros that would look like a dam at rest. Every XDMF reader
        (ParaView and VTK, meshio with h5py) reads a virtual dataset as an ordinary one
        (HDF5 1.10 and later). Fields that ParaView cannot read (lzf, in a file written
        before the fields were stored for the series) are copied instead."""
        import h5py

        ds = f[f"fields/{key}"]
        n, d = ds.shape[1:]
        if ds.compression not in (None, "gzip"):
            return self.store(name, _pad3(ds[i], ds.dtype))
        layout = h5py.VirtualLayout(shape=(n, 3), dtype=ds.dtype)
        layout[:, :d] = h5py.VirtualSource(self._relative(results), f"fields/{key}",
                                           shape=ds.shape, dtype=ds.dtype)[i]  # fmt: skip
        if d < 3:  # (the name of the zeros as stored: an equal array may have been first)
            zero = self.store(f"zero_{ds.dtype.name}", np.zeros(n, dtype=ds.dtype))
            for c in range(d, 3):
                layout[:, c] = h5py.VirtualSource(".", zero, shape=(n,), dtype=ds.dtype)
        self.g.create_virtual_dataset(name, layout, fillvalue=np.nan)
        self._shapes[name] = ((n, 3), ds.dtype)
        return name

    def _relative(self, path: Path) -> str:
        try:
            return Path(os.path.relpath(path.resolve(), self.h5.parent.resolve())).as_posix()
        except ValueError:  # pragma: no cover - another drive (Windows): the absolute path
            return path.resolve().as_posix()

    def frame(self, t: float, point_data: dict[str, str], cell_data: dict[str, str]) -> None:
        """A frame at time ``t`` showing the named datasets as node- and cell-centred
        attributes."""
        import copy
        import xml.etree.ElementTree as ET

        grid = ET.SubElement(self.series, "Grid", GridType="Uniform")
        grid.extend(copy.deepcopy(e) for e in self.mesh)
        ET.SubElement(grid, "Time", Value=repr(float(t)))
        for center, data in (("Node", point_data), ("Cell", cell_data)):
            for attr, name in data.items():
                shape = self._shapes[name][0]
                width = 1 if len(shape) == 1 else shape[1]
                kind = {1: "Scalar", 2: "Vector", 3: "Vector", 6: "Tensor6"}.get(width, "Tensor")
                a = ET.SubElement(grid, "Attribute", Name=attr, AttributeType=kind,
                                  Center=center)  # fmt: skip
                a.append(self._item(name))

    def _item(self, name: str) -> Any:
        """The DataItem of a stored dataset."""
        import xml.etree.ElementTree as ET

        shape, dtype = self._shapes[name]
        kind = {"f": "Float", "i": "Int", "u": "UInt"}[dtype.kind]
        item = ET.Element("DataItem", DataType=kind, Dimensions=" ".join(map(str, shape)),
                          Format="HDF", Precision=str(dtype.itemsize))  # fmt: skip
        item.text = f"{self.h5.name}:/{name}"
        return item

    def _geometry(self, points: np.ndarray) -> Any:
        import xml.etree.ElementTree as ET

        geo = ET.Element("Geometry", GeometryType="XYZ" if points.shape[1] == 3 else "XY")
        geo.append(self._item(self.store("points", points)))
        return geo

    def _topology(self, cells: list[tuple[str, np.ndarray]]) -> Any:
        """The cells as XDMF's Topology: one cell type as its own topology, several as
        "Mixed" (each cell its type's XDMF index, the node count for a polyline, then its
        nodes), as meshio writes them."""
        import xml.etree.ElementTree as ET

        from meshio.xdmf.common import meshio_to_xdmf_type, meshio_type_to_xdmf_index

        n = sum(len(c) for _, c in cells)
        if len(cells) == 1:
            ctype, conn = cells[0]
            topo = ET.Element("Topology", TopologyType=meshio_to_xdmf_type[ctype][0],
                              NumberOfElements=str(n))  # fmt: skip
            if ctype == "line":
                topo.set("NodesPerElement", "2")
            topo.append(self._item(self.store("topology", np.asarray(conn))))
            return topo
        parts = []
        for ctype, conn in cells:
            head = [meshio_type_to_xdmf_index[ctype]] + ([2] if ctype == "line" else [])
            lead = np.broadcast_to(np.asarray(head, dtype=conn.dtype), (len(conn), len(head)))
            parts.append(np.hstack([lead, conn]).ravel())
        topo = ET.Element("Topology", TopologyType="Mixed", NumberOfElements=str(n))
        topo.append(self._item(self.store("topology", np.concatenate(parts))))
        return topo


#: the HDF5 file format of the series' files: that of HDF5 1.10 (which every reader since
#: 2017 reads, ParaView's and VTK's included): virtual datasets, and chunk indexes and
#: object headers far smaller than 1.8's (the demo's float64 blocks.h5: 1.4 MB less)
LIBVER = ("v110", "v110")

#: the datasets of the series' files above this many bytes are compressed (far less than
#: the results file's :data:`~pfeie.io._results.SMALL`: one frame of one stress component
#: is a dataset, about 7 kB in float32 on the demo (1,922 nodes), and the file format of
#: :data:`LIBVER` indexes a dataset of one chunk at no cost)
SERIES_SMALL = 1024

#: the attributes of the blocks series linked to the results file's fields
LINKED = {"displacement": "u", "velocity": "v", "acceleration": "a"}


def stress_components(dim: int, plane: str = "strain") -> dict[str, list[tuple[int, int]]]:
    """The stress attributes of the blocks series and the (row, column) of the 3 × 3
    tensor that each holds: in 3D ``stress``, the 6 independent components in the order
    of XDMF's ``Tensor6`` (xx, xy, xz, yy, yz, zz); in 2D the scalars ``stress_xx``,
    ``stress_yy``, ``stress_xy`` and, in plane strain, ``stress_zz`` (xz and yz are zero,
    and zz too in plane stress).

    >>> list(stress_components(2, "stress"))
    ['stress_xx', 'stress_yy', 'stress_xy']
    >>> stress_components(3)["stress"][:3]
    [(0, 0), (0, 1), (0, 2)]
    """
    if dim == 3:
        return {"stress": [(0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)]}
    out = {"stress_xx": [(0, 0)], "stress_yy": [(1, 1)], "stress_xy": [(0, 1)]}
    if plane == "strain":
        out["stress_zz"] = [(2, 2)]
    return out


def _squeeze(a: np.ndarray) -> np.ndarray:
    """(n, 1) → (n,): a scalar attribute."""
    return a[:, 0] if a.shape[1] == 1 else a


def write_modes(result: Any, model: Any, folder: str | Path) -> list[Path]:
    """The mode shapes of a :class:`~pfeie.solvers.ModalResult` as a ParaView series
    (``modes.xdmf``: one frame per mode, "time" = the mode number; point data ``shape``,
    scaled to a largest displacement of 1, and cell data ``body``) and ``modes.csv``
    (mode, frequency (Hz), period (s), effective modal mass (kg) and its share of the free
    mass along each axis, the Rayleigh damping ratio (empty without damping or for a rigid
    mode) and the share of the mode's kinetic energy in the floating bodies' rigid
    motion)."""
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
        f"mass_{a}_kg,share_{a}" for a in axes) + ",damping_ratio,rigid_share"]  # fmt: skip
    periods = result.periods
    n = len(result.frequencies)
    zeta = np.asarray(result.damping_ratios) if len(result.damping_ratios) else np.full(n, np.nan)
    rigid = np.asarray(result.rigid_share) if len(result.rigid_share) else np.zeros(n)
    for k, f in enumerate(result.frequencies):
        me = result.effective_mass[k]
        share = me / np.maximum(total, 1e-300) if total.size else np.full(me.shape, np.nan)
        z = f"{zeta[k]:.6g}" if np.isfinite(zeta[k]) else ""
        rows.append(f"{k + 1},{f:.9g},{periods[k]:.9g}," + ",".join(
            f"{m:.9g},{s:.6g}" for m, s in zip(me, share, strict=True))
            + f",{z},{rigid[k]:.6g}")  # fmt: skip
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
    """Rewrite the HDF5 file that meshio wrote (uncompressed; the mode shapes of
    :func:`write_modes`) with the filters of ``storage`` (default: the ``[output]``
    defaults, gzip), dataset for dataset under the same names, so that the XDMF still
    points at them. Each column of a table is a chunk (the zero z components of 2D
    vectors then compress to almost nothing); a dataset equal to an earlier one (the cell
    data ``body`` of every frame) becomes a hard link to it, stored once."""
    import h5py

    st = Storage.of() if storage is None else storage
    tmp = path.with_name(path.name + ".tmp")
    seen: dict[tuple[str, tuple[int, ...], bytes], str] = {}
    with h5py.File(path, "r") as src, h5py.File(tmp, "w", libver=LIBVER) as dst:
        for name in sorted(src, key=lambda k: (len(k), k)):  # data0, data1, …, data10, …
            data = np.asarray(src[name][...])
            key = (data.dtype.str, data.shape, hashlib.sha256(data.tobytes()).digest())
            if key in seen:
                dst[name] = dst[seen[key]]  # a hard link: the same dataset
                continue
            seen[key] = name
            st.create(dst, name, data, chunks=_column_chunks(data), small=SERIES_SMALL)
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


def _tangential(name: str, local: np.ndarray) -> dict[str, np.ndarray]:
    """A tangential quantity's point data: in 2D its component along t₁ (``name``,
    signed); in 3D its magnitude (``name``) and its components along t₁ and t₂ as scalars
    (``name_t1``, ``name_t2``). Two components written as one array would be read by
    ParaView as a vector (t₁, t₂, 0) in global axes, which it is not (a tester's slip
    down a 20° plane along x read (0, −0.013, 0), towards −y)."""
    v = local.reshape(local.shape[0], -1)
    if v.shape[1] == 1:
        return {name: local}  # (as it was written before 0.3.25: (m, 1))
    return {name: np.linalg.norm(v, axis=1), f"{name}_t1": v[:, 0], f"{name}_t2": v[:, 1]}


def _global(tangent: np.ndarray, local: np.ndarray) -> np.ndarray:
    """Tangential components (m, d − 1) in the pairs' frames as 3-component vectors in
    global axes (m, 3), z = 0 in 2D: Σ_k t_k v_k, for ParaView's glyphs and Warp By
    Vector, which take 3-component arrays."""
    g = np.einsum("mkd,mk->md", tangent, local.reshape(tangent.shape[0], -1))
    return np.pad(g, ((0, 0), (0, 3 - g.shape[1])))


def _on_points(values: np.ndarray, order: np.ndarray) -> np.ndarray:
    """Pair values on the interface points (NaN on crack-tip points)."""
    shape = (order.size, *values.shape[1:])
    out = np.full(shape, np.nan)
    ok = order >= 0
    out[ok] = values[order[ok]]
    return out
