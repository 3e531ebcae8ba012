"""A study: one model under many records, each at several intensities.

The model is built, its static state solved and its time stepping set up (the blocks'
effective matrices factorised, the Delassus operator W built) **once per process**; every
run of that process reuses them (:func:`run_one` keeps them in a per-process cache keyed by
the inputs' hash). A run is then only the time stepping: the record scaled, the steps,
the demands. Runs go one after the other in this process (``workers = 0``), or on Dask
(:mod:`pfeie.study._parallel`): a local cluster of worker processes, or a running
scheduler; only the small per-run summaries travel back.

Every run has a key: the SHA-256 of everything its result depends on (the model file
with its overrides, the mesh and record bytes, the reading options of the record, the
scale factor, the duration, pfeie's version). A finished run leaves its row in
``<folder>/rows/<key>.json`` (written atomically); a study started again skips the runs
whose row is there, so a killed study resumes where it stopped and gives the same table.

The table has one row per record and intensity: the record, the intensity and the scale
factor; the intensity measures of the scaled record (PGA, PGV, PGD, Arias intensity, CAV,
D5-95, Sa(T1)); and the demands of the run (per probe the peak relative displacement and
peak absolute acceleration; per joint the peak and residual slip, the maximum opening, the
broken share and the minimum sliding safety factor; the extreme principal stresses; the
solver's worst residual). Columns are ``im.*``, ``probe.<name>.*``, ``joint.<name>.*``,
``stress.*``, SI units in the name.
"""

from __future__ import annotations

import copy
import dataclasses
import hashlib
import json
import logging
import math
import os
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from .._version import __version__
from ..errors import InputError, ModelError, RecordError
from ._table import StudyTable

if TYPE_CHECKING:
    from ..dynamics import Dynamic
    from ..io import Job
    from ..model import GroundMotion
    from ..solvers import StaticResult

log = logging.getLogger(__name__)

G = 9.81  # m/s², the g of intensities given in g (as the model file's pga and target_sa)

#: the intensity measures of a row: column, key of GroundMotion.intensity_measures, divisor
IM_COLUMNS = (
    ("im.pga_g", "pga", G), ("im.pgv_m_s", "pgv", 1.0), ("im.pgd_m", "pgd", 1.0),
    ("im.arias_m_s", "arias", 1.0), ("im.cav_m_s", "cav", 1.0), ("im.d5_95_s", "d5_95", 1.0),
    ("im.sa_t1_g", "sa", G),
)  # fmt: skip


@dataclass(frozen=True)
class RecordSource:
    """A record file of a study and how to read it (as a model file's ``[[ground_motion]]``).

    ``name`` is unique within the study (the file's stem, numbered if two share it)."""

    name: str
    path: Path
    format: str = "auto"
    units: str | None = None
    dt: float | None = None
    component: str = "x"
    direction: tuple[float, ...] | None = None
    baseline: bool = False

    def __post_init__(self) -> None:
        object.__setattr__(self, "path", Path(self.path))

    def direction_in(self, dim: int) -> list[float]:
        """The record's direction vector in a ``dim``-D model (checked against it)."""
        if self.direction is not None:
            if len(self.direction) != dim:
                raise RecordError(f"{self.path}: direction has {len(self.direction)} "
                                  f"components; the model is {dim}D")  # fmt: skip
            return list(self.direction)
        k = "xyz".index(self.component)
        if k >= dim:
            raise RecordError(f"{self.path}: component {self.component!r} in a {dim}D model")
        return [float(i == k) for i in range(dim)]

    def read(self, dim: int) -> GroundMotion:
        """The record as a :class:`~pfeie.model.GroundMotion` along its direction."""
        from ..io import read_record

        direction = self.direction_in(dim)
        return read_record(self.path, fmt=self.format, dt=self.dt, units=self.units,
                           direction=direction, baseline=self.baseline,
                           name=self.name)  # fmt: skip

    def fingerprint(self) -> str:
        """SHA-256 of the record's bytes and reading options."""
        h = hashlib.sha256(self.path.read_bytes())
        opts = dataclasses.asdict(self)
        opts.pop("path"), opts.pop("name")
        h.update(json.dumps(opts, sort_keys=True).encode())
        return h.hexdigest()


@dataclass(frozen=True)
class RunSpec:
    """One run of a study: a record at one intensity (``level`` of the ladder)."""

    record: RecordSource
    level: int
    value: float  # the intensity: a scale factor, or g (pga, sa)
    factor: float  # the scale factor applied to the record's accelerations
    ims: dict[str, float]  # the intensity measures of the scaled record (SI)
    key: str  # SHA-256 of the run's inputs

    @property
    def name(self) -> str:
        return f"{self.record.name}@{self.level:03d}"


@dataclass(frozen=True)
class Context:
    """What a worker needs to build the system (small: sent with every task; the system
    itself is built once per process, :func:`system`)."""

    model: Path
    overrides: tuple[tuple[str, Any, str], ...]
    duration: float | None
    folder: Path
    histories: bool
    model_key: str  # SHA-256 of the model, its overrides and its mesh


@dataclass
class _System:
    job: Job
    dyn: Dynamic
    static: StaticResult | None


_SYSTEMS: dict[str, _System] = {}


def system(ctx: Context) -> _System:
    """The model, its static state and its dynamic analysis, built once per process for
    a model key (and kept: a worker builds them for its first run only)."""
    hit = _SYSTEMS.get(ctx.model_key)
    if hit is None:
        from .._job import dynamic_analysis
        from ..io import Override, load_job
        from ..solvers import solve_static

        t0 = time.perf_counter()
        job = load_job(ctx.model, [Override(*o) for o in ctx.overrides])
        static = solve_static(job.model, settings=_solver_settings(job)) \
            if job.analysis.static else None  # fmt: skip
        hit = _System(job, dynamic_analysis(job), static)
        _SYSTEMS.clear()  # one model per process at a time
        _SYSTEMS[ctx.model_key] = hit
        log.info("pid %d: system of %s built in %.2f s", os.getpid(), ctx.model,
                 time.perf_counter() - t0)  # fmt: skip
    return hit


def _solver_settings(job: Job) -> Any:
    from ..interface import SolverSettings

    return SolverSettings(tolerance=job.analysis.tolerance)


def run_one(ctx: Context, spec: RunSpec) -> dict[str, Any]:
    """Run one record at one intensity on the process's system; returns its table row
    (also written to ``<folder>/rows/<key>.json``)."""
    from .._job import summarize

    sysm = system(ctx)
    job, dyn = sysm.job, sysm.dyn
    rec = spec.record.read(job.model.dim)
    rec = dataclasses.replace(rec, acceleration=rec.acceleration * spec.factor,
                              scaling=f"scaled ×{spec.factor:.6g}")  # fmt: skip
    run_job = _job_of_run(job, spec, rec)
    duration = ctx.duration if ctx.duration is not None else rec.duration
    t0 = time.perf_counter()
    writer = None
    if ctx.histories:
        from ..io import ResultsWriter

        folder = ctx.folder / "runs" / spec.name.replace("@", "_")
        folder.mkdir(parents=True, exist_ok=True)
        writer = ResultsWriter(folder / "results.h5", run_job,
                               field_every=job.output.field_every)  # fmt: skip
        if sysm.static is not None:
            writer.write_static(sysm.static)
    res = dyn.run(duration, ground=[rec], form=job.analysis.form, start=sysm.static,
                  probes=list(job.probes.values()), every=job.output.every,
                  on_record=None if writer is None else writer.append,
                  envelope=True)  # fmt: skip
    summary = summarize(run_job, sysm.static, res)
    summary["stopped"] = res.stop_reason
    if writer is not None:
        writer.write_envelope(res.envelope)
        writer.close(res.completed, res.stop_reason, summary)
    row = _row(spec, summary, time.perf_counter() - t0)
    write_row(ctx.folder, row)
    return row


def _job_of_run(job: Job, spec: RunSpec, rec: GroundMotion) -> Job:
    """The job of one run: the model's, with the study's record as its only
    ``[[ground_motion]]`` (so that a results file names what was run)."""
    spec_ = copy.deepcopy(job.spec)
    r = spec.record
    spec_["ground_motion"] = [{
        "file": str(r.path), "format": r.format, "units": r.units, "dt": r.dt,
        "scale": spec.factor, "component": r.component,
        "direction": None if r.direction is None else list(r.direction),
        "baseline": r.baseline,
    }]  # fmt: skip
    return dataclasses.replace(job, spec=spec_, records=[rec])


def _row(spec: RunSpec, s: dict[str, Any], wall: float) -> dict[str, Any]:
    """The flat table row of a run from its results summary."""
    row: dict[str, Any] = {
        "record": spec.record.name, "file": str(spec.record.path), "level": spec.level,
        "intensity": spec.value, "scale_factor": spec.factor,
    }  # fmt: skip
    for col, k, div in IM_COLUMNS:
        if k in spec.ims:
            row[col] = spec.ims[k] / div
    row["completed"] = bool(s.get("completed", False))
    if s.get("stopped"):
        row["stop_reason"] = s["stopped"]
    row["time_reached_s"] = s.get("time_reached_s", 0.0)
    row["steps"] = s.get("steps", 0)
    for name, p in s.get("probes", {}).items():
        row[f"probe.{name}.peak_displacement_m"] = p["peak_displacement_m"]
        row[f"probe.{name}.peak_abs_acceleration_g"] = p["peak_abs_acceleration_g"]
    for name, j in s.get("joints", {}).items():
        for k in ("peak_slip_max_m", "residual_slip_max_m", "residual_slip_mean_m",
                  "max_opening_m", "broken_share", "cracked_length_m", "cracked_area_m2",
                  "max_open_length_m", "max_open_area_m2", "min_safety_factor"):  # fmt: skip
            if k in j:
                row[f"joint.{name}.{k}"] = j[k]
    if "stress" in s:
        row["stress.max_principal_Pa"] = s["stress"]["max_principal_Pa"]
        row["stress.min_principal_Pa"] = s["stress"]["min_principal_Pa"]
        if "demand_capacity" in s["stress"]:
            dc = s["stress"]["demand_capacity"]
            row["stress.max_dcr"], row["stress.max_cid_s"] = dc["max_dcr"], dc["max_cid_s"]
            row["stress.overstressed_share"] = dc["overstressed_share"]
    if "solver" in s:
        row["solver.fallback_steps"] = s["solver"]["fallback_steps"]
        row["solver.worst_residual"] = s["solver"]["worst_residual"]
    row["wall_s"] = round(wall, 3)
    row["key"] = spec.key
    return row


def write_row(folder: Path, row: dict[str, Any]) -> None:
    """Write a run's row to ``<folder>/rows/<key>.json`` atomically (a temporary file,
    then a rename), so that a killed study never leaves half a row."""
    rows = folder / "rows"
    rows.mkdir(parents=True, exist_ok=True)
    tmp = rows / f".{row['key']}.{os.getpid()}.tmp"
    tmp.write_text(json.dumps(row, indent=1) + "\n")
    os.replace(tmp, rows / f"{row['key']}.json")


def read_row(folder: Path, key: str) -> dict[str, Any] | None:
    """The row of a finished run, or None."""
    p = folder / "rows" / f"{key}.json"
    if not p.is_file():
        return None
    try:
        row: dict[str, Any] = json.loads(p.read_text())
    except (OSError, ValueError):
        return None
    return row if row.get("key") == key else None


@dataclass
class Study:
    """One model under many records, each at the intensities of a ladder.

    Parameters
    ----------
    model: the model file (its own ``[[ground_motion]]`` tables are not used).
    records: record files (:class:`RecordSource`, or paths read with the defaults).
    measure: ``"scale"`` (``values`` are scale factors), ``"pga"`` (``values`` in g) or
        ``"sa"`` (``values`` are Sa(``period``, ``damping``) in g).
    values: the intensities (> 0).
    period: T1 (s) of Sa (the ``sa`` measure and the ``im.sa_t1_g`` column); default the
        model's first period with its joints bonded.
    duration: of every run (s); default each record's length.
    overrides: ``KEY=VALUE`` settings of the model file (as ``pfeie run --set``).
    folder: output folder (the rows, the table).

    Example
    -------
    >>> import pfeie as pf                                      # doctest: +SKIP
    >>> st = pf.Study("dam.toml", ["r1.AT2", "r2.AT2"], measure="pga",
    ...               values=[0.1, 0.2, 0.4])                   # doctest: +SKIP
    >>> table = st.run(workers=2)                               # doctest: +SKIP
    >>> table.column("joint.neck.residual_slip_max_m")          # doctest: +SKIP
    """

    model: Path
    records: list[RecordSource]
    measure: str = "scale"
    values: list[float] = field(default_factory=lambda: [1.0])
    period: float | None = None
    damping: float = 0.05
    duration: float | None = None
    overrides: list[str] = field(default_factory=list)
    folder: Path = Path("study")
    histories: bool = False
    parquet: bool = True
    title: str = ""
    workers: int = 0
    scheduler: str | None = None
    limit_states: list[dict[str, Any]] = field(default_factory=list)

    def __post_init__(self) -> None:
        self.model = Path(self.model)
        self.folder = Path(self.folder)
        self.records = [r if isinstance(r, RecordSource) else
                        RecordSource(Path(r).stem, Path(r)) for r in self.records]  # fmt: skip
        if self.measure not in ("scale", "pga", "sa"):
            raise ModelError(f"study: measure must be 'scale', 'pga' or 'sa', got "
                             f"{self.measure!r}")  # fmt: skip
        bad = [v for v in self.values if not (math.isfinite(v) and v > 0)]
        if bad or not self.values:
            raise ModelError(f"study: intensity values must be finite and > 0, got "
                             f"{self.values!r}")  # fmt: skip
        names = [r.name for r in self.records]
        if len(set(names)) != len(names):
            raise ModelError(f"study: two records have the same name: {names}")
        self._context: Context | None = None
        self._specs: list[RunSpec] | None = None
        self._read: dict[RecordSource, GroundMotion] = {}

    @classmethod
    def from_file(cls, path: str | Path) -> Study:
        """The study of a study file (:mod:`pfeie.io._studyfile`)."""
        from ..io import read_study_file

        p = Path(path)
        cfg = read_study_file(p)
        base = p.parent
        records: list[RecordSource] = []
        for i, r in enumerate(cfg.records):
            if r.file is not None:
                files = [base / r.file]
                if not files[0].is_file():
                    raise InputError(f"{p}: records[{i}].file: {files[0]} not found")
            else:
                folder = base / (r.folder or ".")
                if not folder.is_dir():
                    raise InputError(f"{p}: records[{i}].folder: {folder} is not a folder")
                files = sorted(q for q in folder.glob(r.pattern) if q.is_file())
                if not files:
                    raise InputError(f"{p}: records[{i}]: no file in {folder} matches "
                                     f"{r.pattern!r}")  # fmt: skip
            for f in files:
                records.append(RecordSource(
                    f.stem, f, r.format, r.units, r.dt, r.component,
                    None if r.direction is None else tuple(r.direction), r.baseline,
                ))  # fmt: skip
        seen: dict[str, int] = {}
        for k, rs in enumerate(records):  # unique names: stem, stem-2, stem-3, ...
            n = seen.get(rs.name, 0) + 1
            seen[rs.name] = n
            if n > 1:
                records[k] = dataclasses.replace(rs, name=f"{rs.name}-{n}")
        it = cfg.intensity
        try:
            return cls(base / cfg.model, records, it.measure, list(it.values), it.period,
                       it.damping, cfg.analysis.duration, list(cfg.analysis.set),
                       base / cfg.output.folder, cfg.output.histories, cfg.output.parquet,
                       cfg.title, cfg.run.workers, cfg.run.scheduler,
                       [ls.model_dump() for ls in cfg.limit_states])  # fmt: skip
        except ModelError as exc:
            raise InputError(f"{p}: {exc}") from None

    # -- set-up (in the calling process) ---------------------------------------------------

    def context(self) -> Context:
        """The model key and what a worker needs; validates the model file and the
        overrides here, before any work is sent."""
        if self._context is None:
            from ..io import Override, load_job, parse_override, parse_value, run_key

            ovs = [parse_override(s, f"study set {s!r}") for s in self.overrides]
            if self.duration is not None:
                ovs.append(Override("analysis.duration", parse_value(repr(self.duration)),
                                    "study duration"))  # fmt: skip
            elif not any(o.key == "analysis.duration" for o in ovs):
                longest = max(self._record(r).duration for r in self.records)
                ovs.append(Override("analysis.duration", longest, "the longest record"))
            job = load_job(self.model, ovs)
            if not job.analysis.dynamic:
                raise InputError(f"{self.model}: analysis.dynamic = false; a study runs "
                                 "the dynamic analysis")  # fmt: skip
            key = hashlib.sha256((run_key(job) + __version__).encode()).hexdigest()
            self._job = job
            self._context = Context(self.model.resolve(),
                                    tuple((o.key, o.value, o.source) for o in ovs),
                                    self.duration, self.folder.resolve(), self.histories,
                                    key)  # fmt: skip
        return self._context

    def _record(self, r: RecordSource) -> GroundMotion:
        """The record, read once: its time and accelerations (its duration, its intensity
        measures) do not depend on the model's dimension, which the direction is checked
        against in :meth:`runs`."""
        hit = self._read.get(r)
        if hit is None:
            hit = self._read[r] = r.read(len(r.direction or "xyz"))
        return hit

    def t1(self) -> float:
        """T1 (s): the given period, or the model's first period with its joints bonded."""
        if self.period is not None:
            return float(self.period)
        from ..solvers import modal

        self.context()
        f = modal(self._job.model, 1, interfaces="bonded").frequencies[0]
        self.period = float(1.0 / f)
        return self.period

    def runs(self) -> list[RunSpec]:
        """Every run of the study, records outer, intensities inner; each with its scale
        factor, the intensity measures of its scaled record and its key."""
        if self._specs is not None:
            return self._specs
        ctx = self.context()
        t1 = self.t1()
        specs = []
        for r in self.records:
            r.direction_in(self._job.model.dim)
            rec = self._record(r)
            ims = rec.intensity_measures(t1, self.damping)
            ref = {"scale": 1.0, "pga": ims["pga"] / G, "sa": ims["sa"] / G}[self.measure]
            if not ref > 0:
                raise RecordError(f"{r.path}: the record is all zeros; it cannot be scaled "
                                  f"to a {self.measure}")  # fmt: skip
            fp = r.fingerprint()
            for level, v in enumerate(self.values):
                factor = v / ref
                scaled = {k: x * (factor * factor if k == "arias" else
                                  (abs(factor) if k in ("pga", "pgv", "pgd", "cav", "sa")
                                   else 1.0)) for k, x in ims.items()}  # fmt: skip
                key = hashlib.sha256(json.dumps(
                    [ctx.model_key, fp, repr(factor), repr(self.duration)]).encode()
                ).hexdigest()  # fmt: skip
                specs.append(RunSpec(r, level, float(v), float(factor), scaled, key))
        self._specs = specs
        return specs

    # -- running ---------------------------------------------------------------------------

    def run(
        self,
        *,
        workers: int | None = None,
        scheduler: str | None = None,
        resume: bool = True,
        progress: Callable[[int, int, dict[str, Any]], None] | None = None,
    ) -> StudyTable:
        """Run every run not already done (``resume``: rows in ``<folder>/rows`` with
        the same key are kept) and write the table (``table.csv``, ``table.parquet``).

        ``workers`` worker processes of a local Dask cluster (0: in this process, one
        after the other), or the Dask ``scheduler`` at an address; the study file's
        ``[run]`` values by default. ``progress(done, total, row)`` is called after each
        run."""
        specs = self.runs()
        # the output options as they are now (they may be changed after the set-up)
        ctx = dataclasses.replace(self.context(), folder=Path(self.folder).resolve(),
                                  histories=self.histories)  # fmt: skip
        ctx.folder.mkdir(parents=True, exist_ok=True)
        workers = self.workers if workers is None else workers
        scheduler = self.scheduler if scheduler is None else scheduler
        done: dict[str, dict[str, Any]] = {}
        if resume:
            for s in specs:
                row = read_row(ctx.folder, s.key)
                if row is not None:
                    done[s.key] = row
        todo = [s for s in specs if s.key not in done]
        log.info("study: %d runs, %d done before, %d to run", len(specs), len(done), len(todo))
        n_done = len(done)

        def finished(row: dict[str, Any]) -> None:
            nonlocal n_done
            done[row["key"]] = row
            n_done += 1
            if progress is not None:
                progress(n_done, len(specs), row)

        if todo:
            if scheduler or workers > 0:
                from ._parallel import run_parallel

                run_parallel(ctx, todo, finished, workers=workers, scheduler=scheduler)
            else:
                for s in todo:
                    finished(run_one(ctx, s))
        table = StudyTable([done[s.key] for s in specs])
        table.to_csv(ctx.folder / "table.csv")
        if self.parquet:
            table.to_parquet(ctx.folder / "table.parquet")
        meta = {"title": self.title, "model": str(self.model), "model_key": ctx.model_key,
                "measure": self.measure, "values": self.values, "period_s": self.period,
                "damping": self.damping, "records": [r.name for r in self.records],
                "runs": len(specs), "pfeie_version": __version__}  # fmt: skip
        (ctx.folder / "study.json").write_text(json.dumps(meta, indent=2) + "\n")
        self._outputs = [ctx.folder / "table.csv"] + (
            [ctx.folder / "table.parquet"] if self.parquet else [])  # fmt: skip
        from ._report import write_study_outputs

        try:
            self._outputs += write_study_outputs(self, table, ctx.folder)
        except ModelError as exc:  # a limit state on a column the table does not have
            raise InputError(f"{self.model}: study: {exc} (the table is written)") from None
        return table

    def outputs(self) -> list[Path]:
        """The files the last :meth:`run` wrote (besides the rows)."""
        return list(getattr(self, "_outputs", []))


__all__ = ["Context", "RecordSource", "RunSpec", "Study", "read_row", "run_one", "system",
           "write_row"]  # fmt: skip
