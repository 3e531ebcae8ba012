"""The results file (HDF5), written while the run goes, and the :class:`Results` reader.

Layout (every dataset carries a ``units`` attribute; arrays have time first):

- ``/`` attributes: ``pfeie_version``, ``model_file``, ``model_sha256``, ``form``,
  ``completed`` (false until the run ends normally), ``stop_reason``, and JSON strings
  ``model_summary``, ``model_spec`` (the validated model file as run, with its ``--set``
  overrides), ``analysis``, ``units``; ``model_path``, the model file's absolute path;
- ``/mesh``: ``points`` (n, d), ``cells/<type>``, ``body`` (n,), ``body_names``;
  connectivities and indices have units ``index``, codes ``code``, flags ``flag``,
  unit vectors and frames ``1``;
- ``/pairs``: ``x`` (m, d), ``frame`` (m, d, d), ``area`` (m,), ``interface`` (m,),
  ``node_a``, ``node_b``, attribute ``names``;
- ``/records/<i>``: ``time``, ``acceleration``, ``direction``, attribute ``name``;
- ``/static``: ``u`` (n, d) and the pair state ``X``, ``w``, ``s``, ``state``, ``broken``;
- ``/history``: ``time`` (n_t), ``probes/{u,v,a,a_abs}`` (n_t, k, d) with attributes
  ``names`` and ``nodes``, ``rigid`` (n_t, n_bodies, 3 or 6), ``pairs/{X,w,s}``
  (n_t, m, d), ``pairs/state`` (n_t, m; 0 intact, 1 stick, 2 slide, 3 open),
  ``pairs/broken``, ``energy/<term>`` (n_t),
  ``solver/{iterations,fallbacks,residual,newton,substeps}`` (n_t: since the previous row,
  the pair problems' iterations, the steps that needed a fallback, the worst final
  residual, the steps with a solve that the semismooth Newton finished after the state
  iteration, and the sub-steps of the steps taken again as events),
  ``joints/{safety_factor,force,moment}`` (n_t, n_joints[, d or 1 or 3]: the sliding
  safety factor, the resultant force on side b in global axes and its moment about the
  joint's centroid), ``joints/{cracked,open}``
  (n_t, n_joints: the length in 2D, area in 3D, of the broken pairs and of the broken
  pairs that are open);
- ``/envelope``: ``{nodes,cells}/{max,min}_principal`` and their ``_time``: the stress
  envelope; ``cells/{dcr,cid}``: the demand-capacity ratio and the cumulative inelastic
  duration (s) of the cells whose material has a tensile strength (NaN elsewhere);
- ``/fields``: ``time`` (n_f) and ``u``, ``v``, ``a`` (n_f, n, d) every ``field_every``-th
  recorded step (float64, or float32 with ``output.field_precision = "float32"``).

The writer extends its datasets row by row and flushes at least every ``flush_s``
seconds, so a run that is killed leaves a readable file with every completed output row
(and ``completed`` false).

Storage (:class:`Storage`, the keys ``output.compression``, ``compression_level`` and
``field_precision``, recorded as root attributes of the same names): arrays above
:data:`SMALL` bytes are chunked and compressed (gzip with the byte shuffle by default; any
HDF5 reader reads them, h5py transparently). Histories are chunked along time,
:data:`HISTORY_ROWS` rows a chunk (fewer for wide rows: at most :data:`CHUNK_BYTES`), the
fields one row (one time) a chunk. The ParaView series reads the fields where they are
(:mod:`pfeie.io._paraview`), so they are stored as :meth:`Storage.for_paraview` says:
with "lzf", which ParaView cannot read, they are gzip at level 1.
"""

from __future__ import annotations

import json
import math
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .._version import __version__
from ..errors import PfeieError, ResultsError
from ..typing import FloatArray
from ._files import PYTHON_RUN, utf8_text

UNITS = {
    "time": "s", "u": "m", "v": "m/s", "a": "m/s^2", "a_abs": "m/s^2", "X": "N", "w": "m",
    "s": "m", "rigid": "m (translations), rad (rotations)", "energy": "J", "points": "m",
    "area": "m^2 (x thickness in 2D)", "acceleration": "m/s^2", "state": "code",
    "broken": "flag", "index": "index", "direction": "1", "frame": "1",
}  # fmt: skip

#: the layout's version, major.minor: a reader refuses another major version (the layout
#: changed incompatibly); a minor version adds groups or attributes (1.1: /checkpoint,
#: run_key; 1.2: /envelope, history/joints/{force,moment}; 1.3: the attributes
#: compression, compression_level, field_precision, and fields that may be float32;
#: 1.4: history/joints/{cracked,open}, envelope/cells/{dcr,cid}; 1.5: the attributes
#: model_spec and model_path; 1.6: history/solver/newton, and history/solver/fallbacks
#: counts steps, no longer solves, and not those the semismooth Newton finished; 1.7: the
#: group post_earthquake; 1.8: the attribute part_factors and the checkpoint's kin/shift;
#: 1.9: history/solver/substeps; 1.10: history/ground; 1.11: the checkpoint's
#: kin/supports; files without the attribute are 1.0)
FORMAT_VERSION = "1.11"

#: what makes an HDF5 file a pfeie results file
REQUIRED = ("mesh/points", "history/time", "history/probes", "history/rigid", "history/energy")


#: arrays of at most this many bytes are stored as they are (a filter costs more than it
#: saves on them)
SMALL = 8192
#: the largest chunk (bytes) of an array that is not one row of fields: h5py caches 1 MiB
#: of chunks per dataset
CHUNK_BYTES = 1 << 20
#: rows (times) per chunk of a history
HISTORY_ROWS = 256


@dataclass(frozen=True)
class Storage:
    """How the arrays of a results file and of its ParaView series are stored.

    ``compression``: "gzip" (deflate at ``level`` 1 to 9, with the byte shuffle, which
    groups the bytes of equal significance of the floats), "lzf" (with the shuffle; an
    h5py filter) or "none"; ``field_precision``: "float64" or "float32", of the nodal
    fields u, v, a (m, m/s, m/s²) and of the ParaView point data. Compression is lossless
    and deterministic: the same arrays give the same bytes. The defaults are those of the
    model file's ``[output]`` table (:meth:`of`)."""

    compression: str
    level: int
    field_precision: str

    @classmethod
    def of(cls, output: Any = None) -> Storage:
        """The storage of an ``[output]`` table (:class:`pfeie.io.ModelFile`'s ``output``;
        None: its defaults)."""
        if output is None:
            from ._schema import Output

            output = Output()
        return cls(output.compression, int(output.compression_level), output.field_precision)

    @classmethod
    def of_file(cls, f: Any) -> Storage:
        """The storage recorded in an open results file (the defaults for a file of format
        1.2 or older, which records none)."""
        a, default = f.attrs, cls.of()
        if "compression" not in a:
            return default
        return cls(_text(a["compression"]), int(a.get("compression_level", default.level)),
                   _text(a.get("field_precision", default.field_precision)))  # fmt: skip

    @property
    def field_dtype(self) -> Any:
        """The dtype of the nodal fields."""
        return np.dtype(self.field_precision)

    @property
    def attrs(self) -> dict[str, Any]:
        """The root attributes that record it (``compression_level`` 0 without gzip)."""
        return {"compression": self.compression, "field_precision": self.field_precision,
                "compression_level": self.level if self.compression == "gzip" else 0}  # fmt: skip

    def for_paraview(self) -> Storage:
        """The storage of the ParaView series and of the fields it links: ParaView's HDF5
        has no LZF filter, so "lzf" becomes gzip at level 1 (the fastest)."""
        return Storage("gzip", 1, self.field_precision) if self.compression == "lzf" else self

    def filters(self, nbytes: int | None = None, small: int = SMALL) -> dict[str, Any]:
        """The ``create_dataset`` keywords of the filters for an array of ``nbytes`` bytes
        (none for a small one, of at most ``small`` bytes, or without compression;
        None: an array that grows)."""
        if self.compression == "none" or (nbytes is not None and nbytes <= small):
            return {}
        out: dict[str, Any] = {"compression": self.compression, "shuffle": True}
        if self.compression == "gzip":
            out["compression_opts"] = self.level
        return out

    def create(self, g: Any, name: str, data: Any, units: str | None = None,
               chunks: tuple[int, ...] | None = None, small: int = SMALL) -> Any:  # fmt: skip
        """A fixed dataset ``g[name]`` of ``data``, compressed if it has more than
        ``small`` bytes; chunked as ``chunks``, by default whole trailing axes and as many
        leading rows as fit in :data:`CHUNK_BYTES`; the attribute ``units`` if given."""
        data = np.asarray(data)
        kw = self.filters(data.nbytes, small)
        if kw and data.ndim:
            kw["chunks"] = chunks or _guess_chunks(data.shape, data.itemsize)
        ds = g.create_dataset(name, data=data, **kw)
        if units is not None:
            ds.attrs["units"] = units
        return ds


def _text(v: Any) -> str:
    """An HDF5 string attribute as str."""
    return v.decode() if isinstance(v, bytes) else str(v)


def _guess_chunks(shape: tuple[int, ...], itemsize: int) -> tuple[int, ...]:
    """Whole trailing axes, as many leading rows as fit in :data:`CHUNK_BYTES` (at least
    one)."""
    row = itemsize * math.prod(max(s, 1) for s in shape[1:])
    return (max(1, min(shape[0], CHUNK_BYTES // row)), *[max(s, 1) for s in shape[1:]])


def _h5py() -> Any:
    try:
        import h5py
    except ImportError:  # pragma: no cover - h5py is in the io extra
        raise PfeieError("results files need h5py: pip install 'pfeie[io]'") from None
    return h5py


def _run_attrs(job: Any) -> dict[str, str]:
    """The attributes of the run's settings: ``analysis`` (as run: β, γ resolved from α,
    HHT-α, when not given), ``model_summary`` and ``model_spec`` (JSON)."""
    an = job.analysis
    settings = an.model_dump()
    settings["beta"], settings["gamma"], settings["alpha"] = an.newmark()
    return {"analysis": json.dumps(settings),
            "model_summary": json.dumps(job.summary(), default=str),
            "model_spec": json.dumps(job.spec, default=str)}  # fmt: skip


class ResultsWriter:
    """Streams a run into an HDF5 results file (see the module doc)."""

    @staticmethod
    def require() -> None:
        """A :class:`PfeieError` naming the extra to install where h5py is missing:
        checked before a run touches its output folder (it removes a former run's
        summaries and figures, which a run that cannot write its results must keep)."""
        _h5py()

    def __init__(
        self, path: str | Path, job: Any, *, field_every: int = 10, flush_s: float = 2.0,
        storage: Storage | None = None,
    ) -> None:  # fmt: skip
        """Create the results file ``path`` of ``job`` (a :class:`pfeie.io.Job`), its
        arrays stored as ``storage`` (default: the job's ``[output]`` keys)."""
        h5py = _h5py()
        self.path = Path(path)
        self.storage = Storage.of(job.output) if storage is None else storage
        try:
            self.f = h5py.File(self.path, "w")
        except OSError as exc:
            raise ResultsError(
                f"{self.path}: cannot write the results file ({exc}); "
                "expected a writable file in the output folder"
            ) from None
        self.field_every, self.flush_s = max(int(field_every), 1), flush_s
        self.rows = 0
        self._buf: list[dict[str, Any]] = []
        self._last: tuple[float, dict[str, Any]] | None = None
        self._last_flush = time.perf_counter()
        from ._checkpoint import job_solvers

        model = job.model
        d = model.dim
        f = self.f
        f.attrs.update(
            pfeie_version=__version__, format_version=FORMAT_VERSION,
            solver_stack=job_solvers(job),
            model_file=utf8_text(str(job.path)), model_sha256=job.digest,
            form=job.analysis.form, completed=False, stop_reason="",
            model_path=utf8_text(str(job.path) if str(job.path) == PYTHON_RUN
                                 else str(Path(job.path).resolve())),
            **_run_attrs(job),
            units=json.dumps(UNITS), **self.storage.attrs,
        )  # fmt: skip
        g = f.create_group("mesh")
        self._ds(g, "points", model.mesh.points, "m")
        for ctype, conn in model.mesh.cells.items():
            self._ds(g, f"cells/{ctype}", conn, UNITS["index"])
        self._ds(g, "body", model.body_of_node, UNITS["index"])
        g.attrs["body_names"] = json.dumps(model.body_names())
        P = model.pairs
        m = 0 if P is None else P.n
        if P is not None:
            pg = f.create_group("pairs")
            self._ds(pg, "x", P.x, "m")
            self._ds(pg, "frame", P.frame, UNITS["frame"])
            self._ds(pg, "area", P.area, UNITS["area"])
            for key in ("interface", "node_a", "node_b"):
                self._ds(pg, key, getattr(P, key), UNITS["index"])
            pg.attrs["names"] = json.dumps(list(P.names))
        for i, rec in enumerate(job.records):
            rg = f.create_group(f"records/{i}")
            self._ds(rg, "time", rec.time, "s")
            self._ds(rg, "acceleration", rec.acceleration, "m/s^2")
            self._ds(rg, "direction", rec.direction, UNITS["direction"])
            rg.attrs["name"] = utf8_text(rec.name)
        k = len(job.probes)
        nb = model.n_bodies
        r = 3 if d == 2 else 6
        n = model.mesh.n_points
        h = f.create_group("history")
        self._grow(h, "time", (), "s")
        pr = h.create_group("probes")
        pr.attrs["names"] = json.dumps(list(job.probes))
        pr.attrs["nodes"] = json.dumps([int(v) for v in job.probes.values()])
        for key in ("u", "v", "a", "a_abs"):
            self._grow(pr, key, (k, d), UNITS[key])
        self._grow(h, "rigid", (nb, r), UNITS["rigid"])
        self._grow(h, "ground", (d,), "m")
        hp = h.create_group("pairs")
        for key in ("X", "w", "s"):
            self._grow(hp, key, (m, d), UNITS[key])
        if P is not None:
            hj = h.create_group("joints")
            self._grow(hj, "safety_factor", (len(P.names),), "1")
            self._grow(hj, "force", (len(P.names), d), "N")
            self._grow(hj, "moment", (len(P.names), 1 if d == 2 else 3), "N*m")
            for key in ("cracked", "open"):
                self._grow(hj, key, (len(P.names),), "m" if d == 2 else "m^2")
            hj.attrs["names"] = json.dumps(list(P.names))
        self._grow(hp, "state", (m,), "code", np.int8)
        self._grow(hp, "broken", (m,), "flag", np.bool_)
        hs = h.create_group("solver")
        self._grow(hs, "iterations", (), "count", np.int64)
        self._grow(hs, "fallbacks", (), "count", np.int64)
        self._grow(hs, "residual", (), "1")
        self._grow(hs, "newton", (), "count", np.int64)
        self._grow(hs, "substeps", (), "count", np.int64)
        he = h.create_group("energy")
        for key in ("kinetic", "strain", "modified", "external_work", "damping", "interface",
                    "impact", "algorithmic", "correction", "balance"):  # fmt: skip
            self._grow(he, key, (), "J")
        fg = f.create_group("fields")
        self._grow(fg, "time", (), "s")
        for key in ("u", "v", "a"):  # (lzf: gzip at level 1, for the ParaView series that
            # links them, pfeie.io._paraview)
            self._grow(fg, key, (n, d), UNITS[key], self.storage.field_dtype, chunk_rows=1,
                       storage=self.storage.for_paraview())  # fmt: skip
        f.flush()

    @classmethod
    def reopen(cls, f: Any, rows: int, job: Any, *, flush_s: float = 2.0) -> ResultsWriter:
        """A writer that appends to the open results file ``f`` holding ``rows`` rows (a
        run resumed from its checkpoint, :mod:`pfeie.io._checkpoint`)."""
        self = cls.__new__(cls)
        self.path, self.f = Path(f.filename), f
        # the file's own storage (a file of format 1.2 or older: the job's, for its new
        # datasets: the checkpoint, the envelope)
        self.storage = Storage.of_file(f) if "compression" in f.attrs else Storage.of(job.output)
        self.field_every, self.flush_s = max(int(job.output.field_every), 1), flush_s
        self.rows = int(rows)
        self._buf = []
        self._last = None
        self._last_flush = time.perf_counter()
        return self

    def set_run(self, job: Any) -> None:
        """The settings, summary and spec of ``job`` for the run the file holds: a resumed
        run's inputs are the file's (the run key), but ``--duration`` may extend it."""
        self.f.attrs.update(**_run_attrs(job))

    def _ds(self, g: Any, name: str, data: Any, units: str) -> None:
        self.storage.create(g, name, data, units)

    def _grow(
        self, g: Any, name: str, shape: tuple[int, ...], units: str, dtype: Any = np.float64,
        chunk_rows: int = HISTORY_ROWS, storage: Storage | None = None,
    ) -> None:  # fmt: skip
        """A dataset of shape (0, *shape) that grows along its first axis (time), chunked
        ``chunk_rows`` rows at a time, or fewer if such a chunk would exceed
        :data:`CHUNK_BYTES` (a row of fields is one chunk whatever its size); filtered as
        ``storage`` (default: the file's)."""
        row = [max(s, 1) for s in shape]
        nbytes = np.dtype(dtype).itemsize * math.prod(row)
        chunk = (max(1, min(chunk_rows, CHUNK_BYTES // nbytes)), *row)
        # an empty axis (a model without probes or pairs) is left resizable: a chunk may
        # not exceed a fixed axis
        maxshape = (None, *[s if s else None for s in shape])
        g.create_dataset(name, shape=(0, *shape), maxshape=maxshape, dtype=dtype,
                         chunks=chunk, **(storage or self.storage).filters())  # fmt: skip
        g[name].attrs["units"] = units

    @staticmethod
    def _extend(ds: Any, values: list[Any]) -> None:
        if not values:
            return
        n = ds.shape[0]
        ds.resize(n + len(values), axis=0)
        # converted here (float64 fields to float32: rounded to nearest, as numpy does)
        ds[n:] = np.stack([np.asarray(v) for v in values]).astype(ds.dtype, copy=False)

    def write_static(self, static: Any, group: str = "static") -> None:
        """The static state (``group`` static) or the post-earthquake one
        (``post_earthquake``; that of a run extended by ``--resume`` is written again):
        displacements and pair state."""
        if group in self.f:
            del self.f[group]
        g = self.f.create_group(group)
        self._ds(g, "u", static.u, "m")
        if static.pairs is not None:
            for key in ("X", "w", "s"):
                self._ds(g, key, getattr(static.pairs, key), UNITS[key])
            self._ds(g, "state", static.pairs.state, UNITS["state"])
            self._ds(g, "broken", static.pairs.broken, UNITS["broken"])
        if getattr(static, "uplift", None) is not None:
            self._ds(g, "uplift", static.uplift, "Pa")
            names = [u.interface for u in static.model.uplifts]
            g.attrs["cracks"] = json.dumps(dict(zip(names, static.cracks, strict=True)))
        self.f.flush()

    def append(self, row: dict[str, Any]) -> None:
        """One recorded time (the ``on_record`` rows of :meth:`Dynamic.run`); rows are
        buffered and written in blocks, at least every ``flush_s`` seconds, and when the
        rows fill a chunk of the histories (:data:`HISTORY_ROWS`; after a timed write the
        blocks come back to the chunks' ends): a compressed chunk written part-full is
        written again, larger, when it fills, and the file may keep the room of the
        first."""
        keep = {k: (np.array(v, copy=True) if isinstance(v, np.ndarray) else v)
                for k, v in row.items() if k not in ("u", "v", "a")}  # fmt: skip
        if self.rows % self.field_every == 0:
            keep["fields"] = {k: np.array(row[k], copy=True) for k in ("u", "v", "a")}
            self._last = None
        else:  # the fields of the last row are written at the end (the final frame)
            self._last = (row["t"], {k: row[k] for k in ("u", "v", "a")})
        self._buf.append(keep)
        self.rows += 1
        now = time.perf_counter()
        if self.rows % HISTORY_ROWS == 0 or now - self._last_flush > self.flush_s:
            self.flush()

    def flush(self) -> None:
        """Write the buffered rows and flush the file."""
        f, buf = self.f, self._buf
        if buf:
            self._extend(f["history/time"], [r["t"] for r in buf])
            for key in ("u", "v", "a", "a_abs"):
                self._extend(f[f"history/probes/{key}"], [r[f"probe_{key}"] for r in buf])
            self._extend(f["history/rigid"], [r["rigid"] for r in buf])
            if "ground" in f["history"]:  # (files of format 1.9 and older lack it)
                self._extend(f["history/ground"], [r["ground"] for r in buf])
            if buf[0]["X"].size:
                for key in ("X", "w", "s", "state", "broken"):
                    self._extend(f[f"history/pairs/{key}"], [r[key] for r in buf])
            if "joints" in f["history"]:
                self._extend(f["history/joints/safety_factor"],
                             [r["safety_factor"] for r in buf])  # fmt: skip
                if "force" in f["history/joints"]:  # (files of format 1.1 lack them)
                    self._extend(f["history/joints/force"], [r["joint_force"] for r in buf])
                    self._extend(f["history/joints/moment"], [r["joint_moment"] for r in buf])
                if "cracked" in f["history/joints"]:  # (files of format 1.3 and older lack them)
                    self._extend(f["history/joints/cracked"], [r["joint_cracked"] for r in buf])
                    self._extend(f["history/joints/open"], [r["joint_open"] for r in buf])
            if "solver" in f["history"]:
                hs = f["history/solver"]
                keys = ("iterations", "fallbacks", "residual", "newton", "substeps")
                for k, key in enumerate(keys):
                    if key in hs:  # (files of format 1.5 and older lack `newton`, 1.8 and
                        # older `substeps`)
                        self._extend(hs[key], [r.get("solver", [0, 0, 0.0, 0, 0])[k]
                                               for r in buf])  # fmt: skip
            for key in buf[0]["energy"]:
                if key in f["history/energy"]:  # (older files lack `modified`)
                    self._extend(f[f"history/energy/{key}"], [r["energy"][key] for r in buf])
            fr = [r for r in buf if "fields" in r]
            self._extend(f["fields/time"], [r["t"] for r in fr])
            for key in ("u", "v", "a"):
                self._extend(f[f"fields/{key}"], [r["fields"][key] for r in fr])
            self._buf = []
        f.flush()
        self._last_flush = time.perf_counter()

    def write_envelope(self, envelope: dict[str, Any]) -> None:
        """The stress envelope of the run (``/envelope/{nodes,cells}/{max,min}_principal``
        and their ``_time``; Pa and s; NaN outside the blocks), replacing any earlier one
        (a resumed run writes the whole run's)."""
        if not envelope:
            return
        if "envelope" in self.f:
            del self.f["envelope"]
        g = self.f.create_group("envelope")
        for where in ("node", "cell"):
            for ext, name in (("max", "max_principal"), ("min", "min_principal")):
                self._ds(g, f"{where}s/{name}", envelope[f"{where}_{ext}"], "Pa")
                self._ds(g, f"{where}s/{name}_time", envelope[f"{where}_{ext}_time"], "s")
        if "cell_dcr" in envelope:
            self._ds(g, "cells/dcr", envelope["cell_dcr"], "1")
            self._ds(g, "cells/cid", envelope["cell_cid"], "s")

    def close(self, completed: bool, reason: str | None = None,
              summary: dict[str, Any] | None = None) -> None:  # fmt: skip
        """Write the fields of the last row if they are not on disk yet (the final frame
        of the ParaView series is the final time), mark the file completed (or not, with
        the reason) and close it."""
        self.flush()
        if self._last is not None:
            t, fl = self._last
            self._extend(self.f["fields/time"], [t])
            for key in ("u", "v", "a"):
                self._extend(self.f[f"fields/{key}"], [fl[key]])
            self._last = None
        self.f.attrs["completed"] = bool(completed)
        self.f.attrs["stop_reason"] = utf8_text(reason or "")
        if summary is not None:
            self.f.attrs["results_summary"] = json.dumps(summary, default=str)
        self.f.close()


def read_envelope(f: Any) -> dict[str, FloatArray]:
    """The stress envelope of an open results file, keyed as
    :data:`pfeie.dynamics.ENVELOPE_KEYS` (empty if the run kept none)."""
    if "envelope" not in f:
        return {}
    g = f["envelope"]
    out = {}
    for where in ("node", "cell"):
        for ext in ("max", "min"):
            name = f"{where}s/{ext}_principal"
            out[f"{where}_{ext}"] = np.asarray(g[name][...])
            out[f"{where}_{ext}_time"] = np.asarray(g[name + "_time"][...])
    if "cells/dcr" in g:
        out["cell_dcr"], out["cell_cid"] = np.asarray(g["cells/dcr"]), np.asarray(g["cells/cid"])
    return out


def _locked(path: Path) -> str:
    """The message for a results file that HDF5 keeps locked: a run writes it (the folder
    lock of ``pfeie run`` names its process)."""
    lock = path.parent / ".pfeie-run.lock"
    who = "a running `pfeie run`"
    if lock.is_file():
        pid = lock.read_text(errors="replace").split("\n")[0].strip()
        who = f"a running `pfeie run` (pid {pid})"
    return (
        f"{path}: being written by {who}, which locks it: read it when the run ends "
        "(Ctrl-C stops a run and keeps what it computed; `pfeie run --resume` continues "
        "it), or now with HDF5_USE_FILE_LOCKING=FALSE in the environment (the rows "
        "written so far, as far as they read: those being appended may fail to read, and "
        "the last one may be incomplete)"
    )


class Results:
    """A results file opened for reading; arrays come with their times and units.

    Example (after ``make demo``; ``tests/test_results.py`` checks every array)::

        res = Results("examples/koyna/results/results.h5")
        t, u = res.time, res.probe("crest")["u"]
        res.units("history/probes/u")      # 'm'
    """

    def __init__(self, path: str | Path) -> None:
        h5py = _h5py()
        self.path = Path(path)
        what = "expected a results file (results.h5) written by `pfeie run`"
        if not self.path.is_file():
            raise ResultsError(f"{self.path}: results file not found ({what})")
        try:
            self.f = h5py.File(self.path, "r")
        except OSError as exc:
            text = str(exc).lower()
            if "unable to lock file" in text:  # (not "sblock", in a truncated file's error)
                raise ResultsError(_locked(self.path)) from None
            if "truncated" in text or "eof" in text:
                raise ResultsError(f"{self.path}: a truncated or damaged HDF5 file ({what}; a "
                                   f"run killed while the file was written keeps it readable "
                                   f"up to its last flush unless the disk lost data: {exc})"
                                   ) from None  # fmt: skip
            raise ResultsError(f"{self.path}: not an HDF5 file ({what}; {exc})") from None
        lacks = [f"/{k}" for k in REQUIRED if k not in self.f]
        if "pfeie_version" not in self.f.attrs:
            lacks.insert(0, "the attribute pfeie_version")
        if lacks:
            self.f.close()
            raise ResultsError(f"{self.path}: not a pfeie results file ({what}; it lacks "
                               f"{', '.join(lacks)})")  # fmt: skip
        version = str(self.f.attrs.get("format_version", "1.0"))
        if version.split(".")[0] != FORMAT_VERSION.split(".")[0]:
            writer = str(self.f.attrs.get("pfeie_version", "?"))
            self.f.close()
            raise ResultsError(
                f"{self.path}: results format {version}, but this pfeie ({__version__}) reads "
                f"format {FORMAT_VERSION.split('.')[0]}.x; use the pfeie that wrote it "
                f"({writer}) or run the model again"
            )

    def close(self) -> None:
        self.f.close()

    def __enter__(self) -> Results:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # -- metadata --------------------------------------------------------------------------
    @property
    def meta(self) -> dict[str, Any]:
        """Version, model file and hash, completed flag, stop reason, summaries."""
        out: dict[str, Any] = {}
        for k, v in self.f.attrs.items():
            val = v.decode() if isinstance(v, bytes) else v
            if k in ("model_summary", "analysis", "units", "results_summary"):
                val = json.loads(val)
            out[k] = val.item() if isinstance(val, np.generic) else val
        return out

    @property
    def n_times(self) -> int:
        """Number of recorded times (0 for a static-only run)."""
        return int(self.f["history/time"].shape[0])

    @property
    def has_static(self) -> bool:
        """Whether the file holds the static state (``/static``)."""
        return "static/u" in self.f

    def static_pairs(self, interface: str | None = None) -> dict[str, FloatArray]:
        """The static state of the pairs of one interface or all: x, area, X, w, s,
        state, broken, and normal_stress, shear_stress (Pa, compression +), opening (m)."""
        if "pairs" not in self.f:
            raise ResultsError(f"{self.path}: the model has no interfaces")
        if "static/X" not in self.f:
            raise ResultsError(f"{self.path}: no static pair state (expected /static/X: the "
                               "run had analysis.static = false)")  # fmt: skip
        sel = self._select(interface)
        out = {k: np.asarray(self.f[f"pairs/{k}"][...])[sel] for k in ("x", "area", "frame")}
        for k in ("X", "w", "s", "state", "broken"):
            out[k] = np.asarray(self.f[f"static/{k}"][...])[sel]
        A = out["area"]
        out["normal_stress"] = out["X"][..., -1] / A
        out["shear_stress"] = out["X"][..., :-1] / A[:, None]
        out["opening"] = np.maximum(out["s"][..., -1], 0.0)
        return out

    def _select(self, interface: str | None) -> Any:
        if interface is None:
            return slice(None)
        return np.flatnonzero(self.f["pairs/interface"][...] == self._joint(interface))

    def _joint(self, interface: str) -> int:
        """The index of the interface ``interface``; a :class:`ResultsError` naming the
        file's interfaces if it has none of that name."""
        names = self.interface_names
        if interface not in names:
            raise ResultsError(f"{self.path}: no interface {interface!r}; interfaces: {names}")
        return names.index(interface)

    @property
    def completed(self) -> bool:
        return bool(self.f.attrs["completed"])

    def units(self, dataset: str) -> str:
        """Units of a dataset, e.g. ``units("history/pairs/X")`` → 'N'."""
        if dataset not in self.f or "units" not in self.f[dataset].attrs:
            raise ResultsError(f"{self.path}: no dataset {dataset!r} with units (e.g. "
                               "'history/pairs/X'; docs/results.md lists them)")  # fmt: skip
        return str(self.f[dataset].attrs["units"])

    # -- histories -------------------------------------------------------------------------
    @property
    def time(self) -> FloatArray:
        """Times of the recorded steps (s)."""
        return np.asarray(self.f["history/time"][...])

    @property
    def probe_names(self) -> list[str]:
        return list(json.loads(self.f["history/probes"].attrs["names"]))

    def probe(self, name: str) -> dict[str, FloatArray]:
        """u, v, a, a_abs (n_t, d) of a named probe (relative to the ground in the
        relative form)."""
        names = self.probe_names
        if name not in names:
            raise ResultsError(f"{self.path}: no probe {name!r}; probes: {names}")
        k = names.index(name)
        return {key: np.asarray(self.f[f"history/probes/{key}"][:, k])
                for key in ("u", "v", "a", "a_abs")}  # fmt: skip

    @property
    def ground(self) -> FloatArray | None:
        """The ground's displacement (n_t, d) at the recorded rows (m): in the absolute
        form as the supports followed it, in the relative form the records' exact one;
        None for a file of format 1.9 or older."""
        h = self.f["history"]
        return np.asarray(h["ground"][...]) if "ground" in h else None

    @property
    def body_names(self) -> list[str]:
        return list(json.loads(self.f["mesh"].attrs["body_names"]))

    def rigid(self, body: str | int) -> FloatArray:
        """Rigid motion (n_t, 3 or 6) of a body: centroid translation (m), rotation (rad)."""
        names = self.body_names
        if isinstance(body, str):
            if body not in names:
                raise ResultsError(f"{self.path}: no body {body!r}; bodies: {names}")
            idx = names.index(body)
        elif isinstance(body, int | np.integer) and not isinstance(body, bool) and (
                0 <= body < len(names)):  # fmt: skip
            idx = int(body)
        else:
            raise ResultsError(f"{self.path}: body: expected a name of {names} or an index "
                               f"in 0..{len(names) - 1}, got {body!r}")  # fmt: skip
        return np.asarray(self.f["history/rigid"][:, idx])

    @property
    def interface_names(self) -> list[str]:
        return list(json.loads(self.f["pairs"].attrs["names"])) if "pairs" in self.f else []

    def pairs(self, interface: str | None = None) -> dict[str, FloatArray]:
        """Pair geometry and histories, for one interface or all: x, area, frame; X, w, s
        (n_t, m, d); state, broken (n_t, m); and derived normal_stress, shear_stress (Pa,
        compression +), opening (m), slip (m, since the start of the run)."""
        if "pairs" not in self.f:
            raise ResultsError(f"{self.path}: the model has no interfaces")
        sel = self._select(interface)
        out = {k: np.asarray(self.f[f"pairs/{k}"][...])[sel] for k in ("x", "area", "frame")}
        for k in ("X", "w", "s", "state", "broken"):
            out[k] = np.asarray(self.f[f"history/pairs/{k}"][...])[:, sel]
        A = out["area"]
        out["normal_stress"] = out["X"][..., -1] / A
        out["shear_stress"] = out["X"][..., :-1] / A[None, :, None]
        out["opening"] = np.maximum(out["s"][..., -1], 0.0)
        out["slip"] = out["s"][..., :-1] - out["s"][:1, :, :-1]
        return out

    def joint_pieces(self, interface: str) -> dict[str, np.ndarray]:
        """A joint's pairs grouped by the two blocks they join, "A | B" → the positions
        among the joint's pairs (:func:`pfeie.interface.block_pieces`; one entry for a
        joint between two blocks, none for a file without ``/mesh/body``)."""
        from ..interface import block_pieces

        sel = self._select(interface)
        if "body" not in self.f["mesh"] or "node_a" not in self.f["pairs"]:
            return {}
        body = np.asarray(self.f["mesh/body"][...])
        a = np.asarray(self.f["pairs/node_a"][...])[sel]
        b = np.asarray(self.f["pairs/node_b"][...])[sel]
        return block_pieces(body[a], body[b], self.body_names)

    def joint_shares(self, interface: str) -> dict[str, FloatArray]:
        """The area shares (n_t,) of a joint's pairs that are ``broken``, ``sliding`` and
        ``open``, the last by more than :data:`pfeie.interface.OPEN_CRACK_MIN_M` (a
        corner pair of a quadratic facet parts by microns in compression): the shares of
        the joint figure, the CSV export and the summary."""
        from ..interface import OPEN, OPEN_CRACK_MIN_M, SLIDE

        pr = self.pairs(interface)
        A = pr["area"] / pr["area"].sum()
        opened = (pr["state"] == OPEN) & (pr["opening"] > OPEN_CRACK_MIN_M)
        return {"broken": (pr["broken"] * A).sum(axis=1),
                "sliding": ((pr["state"] == SLIDE) * A).sum(axis=1),
                "open": (opened * A).sum(axis=1)}  # fmt: skip

    def energy(self) -> dict[str, FloatArray]:
        """Energy terms (n_t,) in J."""
        return {k: np.asarray(v[...]) for k, v in self.f["history/energy"].items()}

    def joint_resultants(self, interface: str) -> dict[str, FloatArray]:
        """The resultant of a joint's pair forces over time: ``force`` (n_t, d; N, on side b
        in global axes: for a dam–rock joint its horizontal component is the base shear)
        and ``moment`` (n_t, 1 in 2D or 3; N·m, about the joint's area centroid
        ``centroid`` (d,), m) (:meth:`pfeie.interface.PairGeometry.resultants`)."""
        if "joints/force" not in self.f["history"]:
            raise ResultsError(f"{self.path}: no joint resultants (a results file of "
                               f"format {self.f.attrs.get('format_version', '1.0')})")  # fmt: skip
        k = self._joint(interface)
        g = self.f["history/joints"]
        x, a = np.asarray(self.f["pairs/x"]), np.asarray(self.f["pairs/area"])
        sel = np.asarray(self.f["pairs/interface"]) == k
        c = (x[sel] * a[sel, None]).sum(axis=0) / a[sel].sum()
        return {"force": np.asarray(g["force"][:, k]), "moment": np.asarray(g["moment"][:, k]),
                "centroid": c}  # fmt: skip

    def joint_cracks(self, interface: str) -> dict[str, FloatArray]:
        """The cracked extent of a joint over time: ``cracked`` (n_t; its broken pairs) and
        ``open`` (n_t; its broken pairs that are open), lengths in 2D (m), areas in 3D (m²)
        (:meth:`pfeie.Model.joint_extent`)."""
        if "joints/cracked" not in self.f["history"]:
            raise ResultsError(f"{self.path}: no cracked-length histories (a results file of "
                               f"format {self.f.attrs.get('format_version', '1.0')})")  # fmt: skip
        k = self._joint(interface)
        g = self.f["history/joints"]
        return {key: np.asarray(g[key][:, k]) for key in ("cracked", "open")}

    def joint_safety_factor(self, interface: str) -> FloatArray | None:
        """The sliding safety factor FS(t) of a joint (n_t; ``inf`` while it carries no
        shear; docs/results.md), or None in a results file without it."""
        if "joints/safety_factor" not in self.f["history"]:
            return None
        k = self._joint(interface)
        return np.asarray(self.f["history/joints/safety_factor"][:, k])

    @property
    def has_envelope(self) -> bool:
        return "envelope" in self.f

    def envelope(self) -> dict[str, FloatArray]:
        """The stress envelope of the run: ``node_max``, ``node_min`` (n_points,) and
        ``cell_max``, ``cell_min`` (n_cells, over the mesh's cells type after type) the
        largest σ₁ and the smallest σ₃ (Pa, tension positive; NaN outside the blocks),
        and the times they were reached (``…_time``, s); with tensile strengths
        ``cell_dcr`` and ``cell_cid`` (1, s; NaN for cells without). Empty if the run kept
        none."""
        return read_envelope(self.f)

    def fields(self) -> tuple[FloatArray, dict[str, FloatArray]]:
        """Times (n_f,) and the nodal fields u, v, a (n_f, n, d), in the precision they
        were stored in (float64, or float32 with ``output.field_precision``)."""
        g = self.f["fields"]
        return np.asarray(g["time"][...]), {k: np.asarray(g[k][...]) for k in ("u", "v", "a")}
