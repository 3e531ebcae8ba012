"""A study: one model under many records, each at several intensities.

The model is built, its static state solved and its time stepping set up (the blocks'
effective matrices factorised, the Delassus operator W built) **once per process**; every
run of that process reuses them (:func:`system` keeps them in a per-process cache keyed by
the inputs' hash). A run is then only the time stepping: the record scaled, the steps,
the demands. Runs go on Dask (:mod:`pfeie.study._parallel`): by default a local cluster
of one worker process per available core (``workers = "auto"``), or a running scheduler;
only the small per-run summaries travel back. With ``workers = 0`` (and by default when
Dask is not installed, or with one core or one run) they go one after the other in this
process. :func:`builds` counts the systems a process has built. A process takes the runs
in groups (``run.batch``) and, from 20,000 DOF, steps the runs of a group together, their
block solves made in one call a step (:func:`run_batch`): each row the same bits as the
run alone.

Every run has a key: the SHA-256 of everything its result depends on (the model file
with its overrides, the mesh and record bytes, the reading options of the record, the
scale factor, the duration, pfeie's version). A finished run leaves its row in
``<folder>/rows/<key>.json`` (written atomically); a study started again skips the runs
whose row is there, so a killed study resumes where it stopped and gives the same table.
A row found by its key is the same computation whatever ladder it was run for: it is
given the current study's record name, level (the index in the current ladder) and
intensity, so that a ladder changed between two runs of a study (a value added, say)
numbers its levels from the current ladder.

The table has one row per record and intensity: the record, the intensity and the scale
factor; the intensity measures of the scaled record as applied, that is cut at the run's
duration (PGA, PGV, PGD, Arias intensity, CAV, D5-95, Sa(T1)), which also set the scaling
to a PGA or Sa ladder; and the demands of the run (per probe the peak relative
displacement and peak absolute acceleration; per joint the peak and residual slip, the
maximum opening, the broken share and the minimum sliding safety factor; the extreme
principal stresses; the solver's worst residual); and its reliability (per joint the peak
slip over the spacing of its pairs, the energy shares of the position corrections and of
the time scheme, the ``warnings`` of ``pfeie run``'s summary). Columns are ``im.*``,
``probe.<name>.*``, ``joint.<name>.*``, ``stress.*``, ``energy.*``, SI units in the name.
Every record is read and checked before any run (:meth:`Study.runs`), and one study at a
time writes to a folder (a lock file, :meth:`Study.run`).
"""

from __future__ import annotations

import collections
import copy
import dataclasses
import difflib
import functools
import hashlib
import json
import logging
import math
import multiprocessing
import os
import re
import socket
import time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from .._version import __version__
from ..errors import InputError, ModelError, PfeieError, RecordError, ResultsError
from ..io import BATCH, MAX_BATCH, MAX_WORKERS, abrupt_end, applied_part, utf8_text
from ..linalg import solver_stack
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


#: the columns of a probe, of a joint (2D: the ``length_m`` pair; 3D: the ``area_m2``
#: pair), of the stress envelope (the demand-capacity ones with tensile strengths) and of
#: the pair solver, after ``probe.<name>.``, ``joint.<name>.``, ``stress.``, ``solver.``
PROBE_KEYS = ("peak_displacement_m", "peak_abs_acceleration_g")
JOINT_KEYS = ("peak_slip_max_m", "peak_slip_to_spacing", "residual_slip_max_m",
              "residual_slip_mean_m", "max_opening_m", "broken_share", "cracked_length_m",
              "cracked_area_m2", "max_open_length_m", "max_open_area_m2",
              "min_safety_factor")  # fmt: skip
JOINT_KEYS_2D = tuple(k for k in JOINT_KEYS if not k.endswith("_area_m2"))
JOINT_KEYS_3D = tuple(k for k in JOINT_KEYS if not k.endswith("_length_m"))
STRESS_KEYS = ("max_principal_Pa", "min_principal_Pa", "max_dcr", "max_cid_s",
               "overstressed_share")  # fmt: skip
SOLVER_KEYS = ("fallback_steps", "newton_steps", "worst_residual")
#: the reliability measures of a run's energy balance, after ``energy.``: the share of the
#: input energy (the external work) that the position corrections of penetrating pairs
#: added (< 0: took), the share of the energy through the run that the time scheme
#: created (a negative algorithmic term; 0 when it took energy), and the share of the
#: input it dissipated (a positive algorithmic term), as in ``pfeie run``'s summary (its
#: "corrections" and "scheme" lines)
ENERGY_KEYS = ("correction_share", "scheme_created_share", "scheme_dissipated_share")
#: the demand-capacity columns of the stress envelope: only with tensile strengths
DCR_KEYS = ("max_dcr", "max_cid_s", "overstressed_share")

#: demand columns that hold a signed value: the principal stresses (tension > 0,
#: compression < 0), so that a threshold of either sign is meaningful. Every other
#: numeric column is a magnitude (a peak, a norm, a length, a share, a ratio, a count):
#: never negative, so a threshold <= 0 would be reached by every run ("above") or by none
#: ("below"), and is refused.
SIGNED_COLUMNS = frozenset({"stress.max_principal_Pa", "stress.min_principal_Pa"})

#: how the runs are spread: worker processes of a local Dask cluster (0: in this process),
#: or "auto" (:func:`pfeie.study._parallel.local_workers`)
Workers = int | Literal["auto"]


def check_workers(workers: object) -> Workers:
    """``workers`` if it is "auto" or a whole number in [0, 4096] (the study file's
    ``run.workers``), else a :class:`ModelError` that names that key."""
    if workers == "auto":
        return "auto"
    if type(workers) is int and 0 <= workers <= MAX_WORKERS:
        return workers
    raise ModelError(f"run.workers: expected an integer in [0, {MAX_WORKERS}] or 'auto', "
                     f"found {workers!r}")  # fmt: skip


#: the largest intensity of a ``pga`` or ``sa`` ladder (g): the model file's bound on
#: ``ground_motion[].pga`` and ``target_sa.value``
MAX_INTENSITY_G = 20.0


def record_names(paths: list[Path], base: Path) -> list[str]:
    """Unique, stable names of record files: the file's stem when no other record of the
    study shares it, else the file's path relative to ``base`` (POSIX, with its
    suffix). A name depends on the file alone, not on the order of the records.

    >>> record_names([Path("a/r1.csv"), Path("b/r1.csv"), Path("a/r2.csv")], Path("."))
    ['a/r1.csv', 'b/r1.csv', 'r2']
    """
    stems = [p.stem for p in paths]
    root = base.resolve()
    return [
        stem if stems.count(stem) == 1 else
        Path(os.path.relpath(p.resolve(), root)).as_posix()
        for p, stem in zip(paths, stems, strict=True)
    ]  # fmt: skip


def _slug(name: str) -> str:
    """A folder name for a run: the record name and intensity, other characters as ``_``."""
    return re.sub(r"[^A-Za-z0-9.-]+", "_", name).strip("_.") or "run"


@dataclass(frozen=True)
class RecordSource:
    """A record file of a study and how to read it (as a model file's ``[[ground_motion]]``).

    ``name`` is unique within the study (the file's stem; the path relative to the study
    file when two records share a stem, :func:`record_names`)."""

    name: str
    path: Path
    format: str = "auto"
    units: str | None = None
    dt: float | None = None
    component: str = "x"
    direction: tuple[float, ...] | None = None
    baseline: bool = False
    highpass: float | None = None  # Hz: a zero-phase Butterworth filter, as read_record
    lowpass: float | None = None
    order: int = 4

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

    def read(self, dim: int, quiet: bool = False) -> GroundMotion:
        """The record as a :class:`~pfeie.model.GroundMotion` along its direction; with
        ``quiet`` the reader's warnings are logged at DEBUG (a run reads again the record
        that the study's plan read and warned about)."""
        from ..io import read_record

        direction = self.direction_in(dim)
        return read_record(self.path, fmt=self.format, dt=self.dt, units=self.units,
                           direction=direction, baseline=self.baseline, name=self.name,
                           highpass=self.highpass, lowpass=self.lowpass, order=self.order,
                           quiet=quiet)  # fmt: skip

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
    folder: str = ""  # the history's folder under runs/ (:func:`run_folders`)

    @property
    def name(self) -> str:
        return f"{self.record.name}@{self.level:03d}"


def run_folders(runs: list[tuple[str, float]]) -> list[str]:
    """The folders of the runs' histories under ``runs/``, one per (record name,
    intensity value): ``<record>@<value>`` with characters other than letters, digits,
    ``.`` and ``-`` as ``_`` (:func:`_slug`); where two runs would share a folder (records
    ``a b`` and ``a_b``, or ``EQ`` and ``eq`` on a case-insensitive file system), each of
    them gets the first 8 hex digits of the SHA-256 of its
    record name and value appended, so that a folder never holds another run's history.

    >>> run_folders([("a b", 0.5), ("a_b", 0.5), ("c", 0.5)])
    ['a_b_0.5-8631bc54', 'a_b_0.5-9edcd68d', 'c_0.5']
    """
    plain = [_slug(f"{name}@{value:.6g}") for name, value in runs]
    # one folder on a case-insensitive file system
    folded = collections.Counter(f.lower() for f in plain)
    out = []
    for (name, value), f in zip(runs, plain, strict=True):
        if folded[f.lower()] > 1:
            f += "-" + hashlib.sha256(f"{name}@{value!r}".encode()).hexdigest()[:8]
        out.append(f)
    return out


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
    resume: bool = True  # a run whose row is on disk is not run again (False: --restart)
    # the study's own process checked the model file and logged its warnings
    # (:meth:`Study.context`): the processes that build its system do not repeat them
    checked: bool = False
    # the sparse solver of the study's own process (pfeie.linalg.solver_stack, in the
    # model key): a worker with another one would give rows of other bits; it refuses
    solver: str = ""


@dataclass
class _System:
    job: Job
    dyn: Dynamic
    static: StaticResult | None
    twins: list[Dynamic] = field(default_factory=list)

    def analyses(self, k: int) -> list[Dynamic]:
        """``k`` analyses of the system for runs in lockstep: the system's own and
        :meth:`~pfeie.Dynamic.twin` copies (made once, kept for the next batches)."""
        while len(self.twins) < k - 1:
            self.twins.append(self.dyn.twin())
        return [self.dyn, *self.twins[: k - 1]]

    def lockstep(self) -> bool:
        """Whether this system's runs gain from stepping together
        (:func:`pfeie.linalg.shares_block_solves`; not with large rotations)."""
        from ..linalg import shares_block_solves

        return self.dyn.corot is None and shares_block_solves(self.dyn.factor)


_SYSTEMS: dict[str, _System] = {}
_BUILDS = [0]  # the systems this process has built (:func:`builds`)


def builds() -> int:
    """How many times this process has built a system (:func:`system`): once for the
    first run of a model key, and again only when another model key (another model file,
    override or Δt) came in between; a worker answers for itself (``client.run``)."""
    return _BUILDS[0]


def system(ctx: Context) -> _System:
    """The model, its static state and its dynamic analysis, built once per process for
    a model key (and kept: a worker builds them for its first run only)."""
    here = solver_stack()
    if ctx.solver and here != ctx.solver:
        raise ResultsError(f"{socket.gethostname()} (pid {os.getpid()}): this worker's sparse "
                           f"solver is {here!r}, the study's {ctx.solver!r}: the last bits of "
                           "its rows would differ from the others'; expected the same "
                           "install on every worker (pfeie[fast], PFEIE_SOLVER)")  # fmt: skip
    hit = _SYSTEMS.get(ctx.model_key)
    if hit is None:
        from .._job import dynamic_analysis
        from ..io import Override, load_job
        from ..solvers import solve_static

        t0 = time.perf_counter()
        # the study's own process has checked the model file (Study.context) and logged
        # its warnings: they are not repeated when its runs build the system here, in
        # that process or a worker's
        quiet = ctx.checked
        previous = logging.root.manager.disable
        if quiet:
            logging.disable(logging.WARNING)
        try:
            job = load_job(ctx.model, [Override(*o) for o in ctx.overrides], records=False)
        finally:
            if quiet:
                logging.disable(previous)
        static = solve_static(job.model, settings=job.analysis.solver()) \
            if job.analysis.static else None  # fmt: skip
        hit = _System(job, dynamic_analysis(job), static)
        _SYSTEMS.clear()  # one model per process at a time
        _SYSTEMS[ctx.model_key] = hit
        _BUILDS[0] += 1
        log.info("pid %d: system of %s built in %.2f s (build %d of this process)",
                 os.getpid(), ctx.model, time.perf_counter() - t0, _BUILDS[0])  # fmt: skip
    return hit


def kept_row(ctx: Context, spec: RunSpec) -> dict[str, Any] | None:
    """The row of ``spec`` written before (``rows/<key>.json``, :func:`read_row`), None
    if there is none, or if histories are kept and the run's history is not there (a
    study run before without them): then it is run again."""
    row = read_row(ctx.folder, spec.key)
    if row is not None and ctx.histories and spec.folder and not _history_of(
            ctx.folder / "runs" / spec.folder / "results.h5", spec.key):  # fmt: skip
        return None
    return row


def _history_of(path: Path, key: str) -> bool:
    """Whether ``path`` is the whole history of the run of ``key``: its attribute
    ``study_key`` (a folder is named by the record and the intensity, so a study of
    another model, or a changed record, into the same folder leaves another run's file
    there), and the results summary its run writes as it ends (a run interrupted while
    it wrote the history again, ``--restart``, left a part of it)."""
    if not path.is_file():
        return False
    import h5py

    try:
        with h5py.File(path, "r") as f:
            return bool(f.attrs.get("study_key", "") == key and "results_summary" in f.attrs)
    except OSError:  # damaged, or not HDF5
        return False


def run_batch(ctx: Context, specs: Sequence[RunSpec]) -> list[dict[str, Any] | PfeieError]:
    """Run ``specs`` on the process's system, stepping together where the system gains
    from it (:meth:`_System.lockstep`: their block solves made in one call per step,
    :func:`pfeie.linalg.run_lockstep`; each row the same bits as the run alone), else
    one after the other. Returns each run's row, or the :class:`PfeieError` that
    stopped it; the rows are written as the runs end. A run whose row is already on disk
    is not run again (unless the study restarts, ``ctx.resume`` false): a batch the
    scheduler gives anew (a worker lost after some of its runs ended, whose batch Dask
    recomputes) runs only what is left."""
    done = {s.key: kept_row(ctx, s) if ctx.resume else None for s in specs}
    todo = [s for s in specs if done[s.key] is None]
    if len(todo) < len(specs):
        log.info("pid %d: %d of the batch's %d runs have their rows already", os.getpid(),
                 len(specs) - len(todo), len(specs))  # fmt: skip
    ran = iter(_run_batch(ctx, todo) if todo else [])
    return [row if (row := done[s.key]) is not None else next(ran) for s in specs]


def _run_batch(ctx: Context, specs: Sequence[RunSpec]) -> list[dict[str, Any] | PfeieError]:
    """:func:`run_batch` on runs that have no row yet."""
    sysm = system(ctx)
    if len(specs) > 1 and sysm.lockstep():
        from ..linalg import LockstepStats, run_lockstep

        stats = LockstepStats()
        out = run_lockstep([functools.partial(_run_on, ctx, s, sysm, d)
                            for s, d in zip(specs, sysm.analyses(len(specs)), strict=True)],
                           stats)  # fmt: skip
        log.info("pid %d: %d runs in lockstep, %d block solves of %.1f columns on average",
                 os.getpid(), len(specs), stats.calls,
                 stats.columns / max(stats.calls, 1))  # fmt: skip
        for r in out:
            if isinstance(r, BaseException) and not isinstance(r, PfeieError):
                raise r
        return out  # type: ignore[return-value]
    rows: list[dict[str, Any] | PfeieError] = []
    for s in specs:
        try:
            rows.append(_run_on(ctx, s, sysm, sysm.dyn))
        except PfeieError as exc:
            rows.append(exc)
    return rows


def _run_on(ctx: Context, spec: RunSpec, sysm: _System, dyn: Dynamic) -> dict[str, Any]:
    """Run one record at one intensity with the analysis ``dyn`` of ``sysm``."""
    from .._job import DISK_FREE_MIN, DiskGuard, summarize

    job = sysm.job
    rec = spec.record.read(job.model.dim, quiet=True)  # (the plan warned about it)
    duration = ctx.duration if ctx.duration is not None else rec.duration
    how = f"scaled ×{spec.factor:.6g}"
    part, cut = applied_part(rec, duration)
    if cut is not None:  # the record line gives the whole record's PGA: say so
        how += (f" (the PGA above lies beyond the end of the run, {duration:g} s: the "
                f"motion applied peaks at {spec.factor * part.pga / 9.81:.4g} g)")  # fmt: skip
    rec = dataclasses.replace(rec, acceleration=rec.acceleration * spec.factor, scaling=how)
    run_job = _job_of_run(job, spec, rec)
    t0 = time.perf_counter()
    # a disk short of space stops the study before a run (its rows are small) or, with
    # histories kept, within one (as `pfeie run` stops); the study run again goes on
    # (without histories a run writes its row, a few kB: a margin of 1 MiB)
    disk = DiskGuard(ctx.folder, job.model.n_dof if ctx.histories else 0, duration,
                     then="run the study again: it goes on with the runs left",
                     free_min=DISK_FREE_MIN if ctx.histories else 2**20,
                     what=("a history's rows and its summaries" if ctx.histories else
                           "the study's rows and tables"))  # fmt: skip
    if (why := disk.short()) is not None:
        raise ResultsError(f"{spec.record.name}, {spec.value:g}: not run: "
                           f"{disk.stop_text(why)}")  # fmt: skip
    writer = None
    if ctx.histories:
        from ..io import ResultsWriter

        # named by the record and the intensity's value, not the level's index: a value
        # added to the ladder renumbers the levels, and a kept history would then sit
        # under another level's name (or be overwritten by another run)
        folder = (
            ctx.folder / "runs" / (spec.folder or run_folders([(spec.record.name, spec.value)])[0])
        )
        folder.mkdir(parents=True, exist_ok=True)
        writer = ResultsWriter(folder / "results.h5", run_job,
                               field_every=job.output.field_every)  # fmt: skip
        # the history traced to its row (rows/<key>.json) and its record
        writer.f.attrs.update({"study_key": spec.key, "study_record": utf8_text(spec.record.name),
                               "study_intensity": spec.value,
                               "study_record_sha256": spec.record.fingerprint()})  # fmt: skip
        if sysm.static is not None:
            writer.write_static(sysm.static)
    res = dyn.run(duration, ground=[rec], form=job.analysis.form, start=sysm.static,
                  probes=list(job.probes.values()), every=job.output.every,
                  on_record=None if writer is None else writer.append,
                  callback=None if writer is None else lambda _st: disk.check(),
                  envelope=True)  # fmt: skip
    if disk.tripped is not None and writer is not None:  # no row: the run is not done
        writer.close(False, disk.tripped)
        raise ResultsError(f"{spec.record.name}, {spec.value:g}: stopped at t = "
                           f"{float(res.t[-1]):.6g} s: {disk.tripped}")  # fmt: skip
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
        "filter": (None if r.highpass is None and r.lowpass is None else
                   {"highpass": r.highpass, "lowpass": r.lowpass, "order": r.order}),
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
    row["stop_reason"] = str(s.get("stopped") or "")  # empty when the run completed
    row["time_reached_s"] = s.get("time_reached_s", 0.0)
    row["steps"] = s.get("steps", 0)
    for name, p in s.get("probes", {}).items():
        row[f"probe.{name}.peak_displacement_m"] = p["peak_displacement_m"]
        row[f"probe.{name}.peak_abs_acceleration_g"] = p["peak_abs_acceleration_g"]
    for name, j in s.get("joints", {}).items():
        for k in JOINT_KEYS:
            if k in j:  # a joint that never carries shear has no FS: NaN in the table
                row[f"joint.{name}.{k}"] = float("nan") if j[k] is None else j[k]
    if "stress" in s:
        row["stress.max_principal_Pa"] = s["stress"]["max_principal_Pa"]
        row["stress.min_principal_Pa"] = s["stress"]["min_principal_Pa"]
        if "demand_capacity" in s["stress"]:
            dc = s["stress"]["demand_capacity"]
            row["stress.max_dcr"], row["stress.max_cid_s"] = dc["max_dcr"], dc["max_cid_s"]
            row["stress.overstressed_share"] = dc["overstressed_share"]
    if "solver" in s:
        for k in SOLVER_KEYS:
            if k in s["solver"]:
                row[f"solver.{k}"] = s["solver"][k]
    notes = _reliability(s, row)
    row["warnings"] = "; ".join(notes)
    row["wall_s"] = round(wall, 3)
    row["key"] = spec.key
    return row


def _reliability(s: dict[str, Any], row: dict[str, Any]) -> list[str]:
    """The run's reliability warnings, as ``pfeie run``'s summary gives them
    (:func:`pfeie._job.reliability`, one line each); puts the ``energy.*`` shares into
    ``row``."""
    from .._job import energy_shares, reliability

    if s.get("energy_J") is not None:
        share, created, dissipated = energy_shares(s)
        row["energy.correction_share"], row["energy.scheme_created_share"] = share, created
        row["energy.scheme_dissipated_share"] = dissipated
    return [w.short for w in reliability(s)]


def _as_run(row: dict[str, Any], spec: RunSpec) -> dict[str, Any]:
    """The row of a run found by its key, as a row of ``spec``: the key fixes the
    computation (the model, the record's bytes and options, the scale factor, the
    duration), not the record's name in the study, nor its level or intensity in the
    ladder, nor its intensity measures (Sa at the study's T1 and damping, which the
    computation does not depend on), which come from the current study."""
    out = dict(row)
    out.setdefault("stop_reason", "")
    out.update(record=spec.record.name, file=str(spec.record.path), level=spec.level,
               intensity=spec.value)  # fmt: skip
    for col, k, div in IM_COLUMNS:
        if k in spec.ims:
            out[col] = spec.ims[k] / div
    return out


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
    values: the intensities, each once: scale factors > 0, or in (0, 20] g for ``pga`` and
        ``sa`` (the model file's range); ``level`` k of the table is ``values[k]``.
    period: T1 (s) of Sa (the ``sa`` measure and the ``im.sa_t1_g`` column); default the
        model's first period with its joints bonded.
    damping: the damping ratio ζ of Sa (the ``sa`` measure and ``im.sa_t1_g``).
    duration: of every run (s); default each record's length. A record longer than the
        run is cut at its end: the intensity measures and the scaling to a ``pga`` or
        ``sa`` describe the motion applied, the record up to ``duration``.
    overrides: ``KEY=VALUE`` settings of the model file (as ``pfeie run --set``).
    folder: output folder (the rows, the table; one study at a time: a lock file).
    histories: also keep every run's results file
        (``runs/<record>_<intensity>/results.h5``, the intensity's value as ``%g``).
    parquet: write ``table.parquet`` (pyarrow) beside ``table.csv``.
    title: the study's title (in ``study.json`` and the report).
    workers: worker processes of a local Dask cluster (0: every run in this process, one
        after the other); ``"auto"`` (the default): one per core available, at most one
        per run, and in this process when Dask is not installed or with one core or one
        run. A Python script that runs a study on workers has its code under
        ``if __name__ == "__main__":`` (each worker process starts by importing it).
    scheduler: address of a running Dask scheduler, instead of a local cluster.
    batch: the runs a worker steps together (in lockstep, their block solves made in
        one call a step: each run's row the same bits as alone; only where the system
        gains from it, 20,000 DOF and more, :func:`run_batch`); 1 runs them one after
        the other.
    limit_states: ``{"name", "demand", "threshold", "exceed"}`` dicts (the study file's
        ``[[limit_states]]``); a threshold > 0 unless the demand is a principal stress.
    source: the study file (its name starts the messages about the study's keys).

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
    workers: Workers = "auto"
    scheduler: str | None = None
    limit_states: list[dict[str, Any]] = field(default_factory=list)
    source: Path | None = None
    batch: int = BATCH

    def __post_init__(self) -> None:
        """Check the study; a :class:`ModelError` names the key of the study file that
        is wrong (``intensity.values[1]: ...``), which :meth:`from_file` prefixes with the
        file."""
        self.model = Path(self.model)
        self.folder = Path(self.folder)
        given: dict[str, object] = {
            "records": self.records,
            "values": self.values,
            "set": self.overrides,
        }  # (what a caller passed)
        if isinstance(given["records"], (str, os.PathLike)) or not isinstance(
                given["records"], Iterable):  # fmt: skip
            raise ModelError(f"records: expected a list of record files (or RecordSource), "
                             f"found {self.records!r}")  # fmt: skip
        raw: list[Any] = list(self.records)  # RecordSource, or a path read with the defaults
        if not raw:
            raise ModelError("records: expected at least one record, found []")
        for k, r in enumerate(raw):
            if not isinstance(r, (RecordSource, str, os.PathLike)):
                raise ModelError(f"records[{k}]: expected a record file's path (or a "
                                 f"RecordSource), found {type(r).__name__} {r!r}")  # fmt: skip
        if isinstance(given["values"], (str, bytes)) or not isinstance(
                given["values"], (Sequence, np.ndarray)):  # fmt: skip
            raise ModelError(f"intensity.values: expected a list of numbers, found "
                             f"{self.values!r}")  # fmt: skip
        self.values = list(self.values)
        if isinstance(given["set"], str) or not isinstance(given["set"], Sequence):
            raise ModelError(f"analysis.set: expected a list of 'KEY=VALUE' strings, found "
                             f"{self.overrides!r}")  # fmt: skip
        self._check_overrides()
        plain = [k for k, r in enumerate(raw) if not isinstance(r, RecordSource)]
        for k, name in zip(plain, record_names([Path(raw[k]) for k in plain], Path.cwd()),
                           strict=True):  # fmt: skip
            raw[k] = RecordSource(name, Path(raw[k]))
        self.records = raw
        if self.measure not in ("scale", "pga", "sa"):
            raise ModelError(f"intensity.measure: expected one of 'scale', 'pga', 'sa', "
                             f"found {self.measure!r}")  # fmt: skip
        self._check_values()
        first: dict[Path, int] = {}
        for k, r in enumerate(self.records):
            j = first.setdefault(r.path.resolve(), k)
            if j != k:
                raise ModelError(f"records: records {j} ({self.records[j].name}) and {k} "
                                 f"({r.name}) are the same file {r.path}; expected each "
                                 "record file once")  # fmt: skip
        names = [r.name for r in self.records]
        if len(set(names)) != len(names):
            raise ModelError(f"records: two records have the same name: {names}")
        self._check_limit_states()
        self.workers = check_workers(self.workers)
        if not (type(self.batch) is int and 1 <= self.batch <= MAX_BATCH):
            raise ModelError(f"run.batch: expected an integer in [1, {MAX_BATCH}], found "
                             f"{self.batch!r}")  # fmt: skip
        self.source = None if self.source is None else Path(self.source)
        self._context: Context | None = None
        self._specs: list[RunSpec] | None = None
        self._read: dict[RecordSource, GroundMotion] = {}
        self.kept = 0  # the runs of the last :meth:`run` whose rows were kept from before
        self._entries: list[str] | None = None  # the [[records]] key of each record

    def _entry(self, r: RecordSource) -> str:
        """``FILE: records[i]`` of a record: the study file's ``[[records]]`` table that
        gave it (a folder's records share theirs), or its index in :attr:`records`."""
        k = self.records.index(r)
        return self._where(self._entries[k] if self._entries is not None else f"records[{k}]")

    def _check_overrides(self) -> None:
        """Each override ``KEY=VALUE`` (the study file's ``analysis.set``): not of a key
        the study sets itself (the records, the output folder) and, with
        ``duration``, not ``analysis.duration`` too (two durations, one silently
        ignored)."""
        from ..io import parse_override

        for i, text in enumerate(self.overrides):
            key = f"analysis.set[{i}]"
            if not isinstance(text, str):
                raise ModelError(f"{key}: expected a 'KEY=VALUE' string, found {text!r}")
            try:
                o = parse_override(text, key)
            except PfeieError as exc:
                raise ModelError(str(exc)) from None
            if o.key.startswith("ground_motion") or o.key == "output.folder":
                what = ("the study's [[records]] replace the model's [[ground_motion]]"
                        if o.key.startswith("ground_motion") else
                        "the study writes to its own [output] folder")  # fmt: skip
                raise ModelError(f"{key}: {text!r}: a study does not take this key ({what}); "
                                 "expected a key of the model's analysis, materials, "
                                 "interfaces or loads")  # fmt: skip
            if o.key == "analysis.duration" and self.duration is not None:
                raise ModelError(f"{key}: {text!r} and analysis.duration = {self.duration:g} "
                                 "both give the runs' duration; expected one of them")  # fmt: skip

    def _check_values(self) -> None:
        """The ladder: finite values > 0 (scale factors), or in (0, 20] g (``pga``,
        ``sa``: the model file's range), each once (a value is a level)."""
        if not self.values:
            raise ModelError("intensity.values: expected at least one value, found []")
        top = math.inf if self.measure == "scale" else MAX_INTENSITY_G
        expect = ("a finite number > 0 (a scale factor)" if self.measure == "scale" else
                  f"a number in (0, {top:g}] g (measure {self.measure!r})")  # fmt: skip
        seen: dict[float, int] = {}
        for i, v in enumerate(self.values):
            if not (isinstance(v, (int, float)) and math.isfinite(v) and 0 < v <= top):
                found = f"{v:g}" if isinstance(v, (int, float)) else repr(v)
                raise ModelError(f"intensity.values[{i}]: expected {expect}, found {found}")
            j = seen.setdefault(float(v), i)
            if j != i:
                raise ModelError(f"intensity.values[{i}]: {v!r} is already "
                                 f"intensity.values[{j}]; expected distinct values (each is "
                                 "one level of the ladder)")  # fmt: skip

    def _check_limit_states(self) -> None:
        """Each limit state: a name used once, a finite threshold, and > 0 on a demand that
        is a magnitude (every column but the signed principal stresses,
        :data:`SIGNED_COLUMNS`)."""
        names: dict[str, int] = {}
        for i, ls in enumerate(self.limit_states):
            key = f"limit_states[{i}]"
            for k in ("name", "demand", "threshold"):
                if k not in ls:
                    raise ModelError(f"{key}.{k}: missing (required)")
            j = names.setdefault(str(ls["name"]), i)
            if j != i:
                raise ModelError(f"{key}.name: {ls['name']!r} is already limit_states[{j}]"
                                 ".name; expected distinct names")  # fmt: skip
            if ls.get("exceed", "above") not in ("above", "below"):
                raise ModelError(f"{key}.exceed: expected one of 'above', 'below', found "
                                 f"{ls['exceed']!r}")  # fmt: skip
            t = ls["threshold"]
            if not (isinstance(t, (int, float)) and math.isfinite(t)):
                raise ModelError(f"{key}.threshold: expected a finite number, found {t!r}")
            if t <= 0 and ls["demand"] not in SIGNED_COLUMNS:
                raise ModelError(
                    f"{key}.threshold: expected a number > 0 for the demand "
                    f"{ls['demand']!r}, found {t!r} (a magnitude, never negative: every run "
                    f"would be {'beyond' if ls.get('exceed', 'above') == 'above' else 'short of'}"
                    " it; only the principal stresses take a signed threshold)"
                )

    def _where(self, key: str) -> str:
        """``FILE: KEY`` for a message (the key alone for a study made in Python)."""
        return f"{self.source}: {key}" if self.source is not None else key

    @classmethod
    def from_file(cls, path: str | Path) -> Study:
        """The study of a study file (:mod:`pfeie.io._studyfile`)."""
        from ..io import read_study_file

        p = Path(path)
        cfg = read_study_file(p)
        base = p.parent
        records: list[RecordSource] = []
        entries: list[str] = []  # per record, the key of its [[records]] table
        origin: dict[Path, str] = {}  # resolved file: the entry that gave it
        for i, r in enumerate(cfg.records):
            if r.file is not None:
                files = [base / r.file]
                entry = f"records[{i}].file"
                if files[0].is_dir():
                    raise InputError(f"{p}: records[{i}].file: {files[0]} is a folder; "
                                     "expected a record file (for the records of a folder: "
                                     "folder = ... with pattern = ...)")  # fmt: skip
                if not files[0].is_file():
                    raise InputError(f"{p}: records[{i}].file: {files[0]} not found")
            else:
                folder = base / (r.folder or ".")
                entry = f"records[{i}].folder ({r.pattern!r} in {r.folder})"
                if not folder.is_dir():
                    raise InputError(f"{p}: records[{i}].folder: {folder} is not a folder")
                if Path(r.pattern).is_absolute() or not r.pattern.strip():
                    raise InputError(f"{p}: records[{i}].pattern: {r.pattern!r}: expected a "
                                     f"pattern of file names within records[{i}].folder, "
                                     "e.g. '*.AT2' (the folder goes in folder = ...)")  # fmt: skip
                try:
                    files = sorted(q for q in folder.glob(r.pattern) if q.is_file())
                except (ValueError, NotImplementedError) as exc:
                    raise InputError(f"{p}: records[{i}].pattern: {r.pattern!r}: {exc}; "
                                     "expected a pattern such as '*.AT2'") from None  # fmt: skip
                if not files:
                    raise InputError(f"{p}: records[{i}]: no file in {folder} matches "
                                     f"{r.pattern!r}")  # fmt: skip
            for f in files:
                first = origin.setdefault(f.resolve(), entry)
                if first != entry:
                    raise InputError(f"{p}: {first} and {entry} both give the record file "
                                     f"{f}; expected each record file once")  # fmt: skip
                flt = r.filter
                entries.append(f"records[{i}]")
                records.append(RecordSource(
                    f.stem, f, r.format, r.units, r.dt, r.component,
                    None if r.direction is None else tuple(r.direction), r.baseline,
                    None if flt is None else flt.highpass, None if flt is None else flt.lowpass,
                    4 if flt is None else flt.order,
                ))  # fmt: skip
        names = record_names([r.path for r in records], base)
        records = [dataclasses.replace(r, name=n) for r, n in zip(records, names, strict=True)]
        it = cfg.intensity
        if not (base / cfg.model).is_file():
            raise InputError(f"{p}: model: {base / cfg.model}: model file not found; expected "
                             "the path of a model file, relative to the study file")  # fmt: skip
        try:
            st = cls(base / cfg.model, records, it.measure, list(it.values), it.period,
                       it.damping, cfg.analysis.duration, list(cfg.analysis.set),
                       base / cfg.output.folder, cfg.output.histories, cfg.output.parquet,
                       cfg.title, cfg.run.workers, cfg.run.scheduler,
                       [ls.model_dump() for ls in cfg.limit_states], p,
                       cfg.run.batch)  # fmt: skip
        except ModelError as exc:
            raise InputError(f"{p}: {exc}") from None
        st._entries = entries
        return st

    # -- set-up (in the calling process) ---------------------------------------------------

    def context(self) -> Context:
        """The model key and what a worker needs; validates the model file and the
        overrides here, before any work is sent."""
        if self._context is None:
            from ..io import Override, load_job, parse_override, parse_value, run_key

            ovs = [parse_override(s, f"study set {s!r}") for s in self.overrides]
            given = [o for o in ovs if o.key == "analysis.duration"]
            duration = self.duration
            if self.duration is not None:
                ovs.append(Override("analysis.duration", parse_value(repr(self.duration)),
                                    "study duration"))  # fmt: skip
            elif not any(o.key == "analysis.duration" for o in ovs):
                longest = max(self._record(r).duration for r in self.records)
                ovs.append(Override("analysis.duration", longest, "the longest record"))
            job = load_job(self.model, ovs, records=False)
            if not job.analysis.dynamic:
                raise InputError(f"{self.model}: analysis.dynamic = false; a study runs "
                                 "the dynamic analysis")  # fmt: skip
            if (job.spec.get("loads") or {}).get("pseudo_static"):
                raise InputError(f"{self.model}: loads.pseudo_static: a study runs records, "
                                 "and the pseudo-static load would stay on throughout each "
                                 "of them, the earthquake counted twice; expected the model "
                                 "without loads.pseudo_static")  # fmt: skip
            # the model file's own [[ground_motion]] is not run (records=False): its
            # files out of the key, so that editing them keeps the study's rows
            bare = dataclasses.replace(job, spec={**job.spec, "ground_motion": []})
            key = hashlib.sha256((run_key(bare) + __version__).encode()).hexdigest()
            if duration is None and given:  # analysis.set = ["analysis.duration=..."]
                duration = job.analysis.duration
            self._job = job
            self._context = Context(self.model.resolve(),
                                    tuple((o.key, o.value, o.source) for o in ovs),
                                    duration, self.folder.resolve(), self.histories,
                                    key, checked=True, solver=solver_stack())  # fmt: skip
        return self._context

    def _may_step_together(self) -> bool:
        """Whether the workers may step this study's runs together (:func:`run_batch`):
        the model has the DOF of two-column block solves
        (:data:`pfeie.linalg.SMALL_BLOCK_MIN_DOF`, counted on all DOF here, where nothing
        is factorised) and small rotations. Otherwise each run is a task of its own,
        which Dask balances over the workers."""
        from ..linalg import SMALL_BLOCK_MIN_DOF

        self.context()
        return (self.batch > 1 and not self._job.analysis.large_rotation
                and self._job.model.n_dof >= SMALL_BLOCK_MIN_DOF)  # fmt: skip

    def _record(self, r: RecordSource) -> GroundMotion:
        """The record, read once: its time and accelerations (its duration, its intensity
        measures) do not depend on the model's dimension, which the direction is checked
        against in :meth:`runs`."""
        hit = self._read.get(r)
        if hit is None:
            try:
                hit = self._read[r] = r.read(len(r.direction or "xyz"))
            except RecordError as exc:
                raise RecordError(f"{self._entry(r)}: {exc}") from None
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
        factor, the intensity measures of its scaled record as applied (cut at the run's
        end, :meth:`_applied`) and its key. Every record is read and checked here, before
        any run (:meth:`_check_record`)."""
        if self._specs is not None:
            return self._specs
        ctx = self.context()
        self._check_demands()
        t1 = self.t1()
        dim = self._job.model.dim
        specs = []
        seen: dict[str, RecordSource] = {}
        for r in self.records:
            try:
                r.direction_in(dim)
            except RecordError as exc:
                raise RecordError(f"{self._entry(r)}: {exc}") from None
            rec = self._record(r)
            applied = self._applied(r, rec, ctx.duration)
            ims = applied.intensity_measures(t1, self.damping)
            ref = {"scale": 1.0, "pga": ims["pga"] / G, "sa": ims["sa"] / G}[self.measure]
            if not ref > 0:
                within = "" if applied is rec else f" within the runs' {applied.time[-1]:g} s"
                raise RecordError(f"{self._entry(r)}: {r.path}: the record is all zeros"
                                  f"{within}; it cannot be scaled to a "
                                  f"{self.measure}")  # fmt: skip
            factors = [v / ref for v in self.values]
            self._check_record(r, rec, ims["pga"], factors)
            fp = r.fingerprint()
            if (twin := seen.setdefault(fp, r)) is not r:
                raise RecordError(
                    f"{self._entry(r)}: {r.path}: the same record as {twin.path} (record "
                    f"{twin.name!r}: the same bytes and reading options); expected each "
                    "ground motion once (a copy would count twice in the medians and the "
                    "fragility fits)"
                )  # fmt: skip
            for level, (v, factor) in enumerate(zip(self.values, factors, strict=True)):
                scaled = {k: x * (factor * factor if k == "arias" else
                                  (abs(factor) if k in ("pga", "pgv", "pgd", "cav", "sa")
                                   else 1.0)) for k, x in ims.items()}  # fmt: skip
                key = hashlib.sha256(json.dumps(
                    [ctx.model_key, fp, repr(factor), repr(ctx.duration)]).encode()
                ).hexdigest()  # fmt: skip
                specs.append(RunSpec(r, level, float(v), float(factor), scaled, key))
        folders = run_folders([(s.record.name, s.value) for s in specs])
        specs = [dataclasses.replace(s, folder=f) for s, f in zip(specs, folders, strict=True)]
        self._specs = specs
        return specs

    def _applied(self, r: RecordSource, rec: GroundMotion, duration: float | None) -> GroundMotion:
        """The part of the record a run applies (:func:`pfeie.io.applied_part`, as a model
        file's ``pga`` and ``target_sa`` are measured): the run steps from t = 0 to its
        duration (the study's, else the record's length), so a record that goes on beyond
        is cut there. A WARNING names the record and the duration when the cut leaves out
        the record's peak."""
        end = rec.duration if duration is None else float(duration)
        try:
            cut, note = applied_part(rec, end)
        except RecordError as exc:
            raise RecordError(f"{self._entry(r)}: {r.path}: {exc}") from None
        if note is not None:
            log.warning("%s: %s: %s: the intensity measures and the scaling describe that "
                        "part", self._entry(r), r.name, note)  # fmt: skip
        if (short := abrupt_end(rec, end)) is not None:
            log.warning("%s: %s: %s", self._entry(r), r.name, short)
        return cut

    def _check_record(self, r: RecordSource, rec: GroundMotion, pga: float,
                      factors: list[float]) -> None:  # fmt: skip
        """The checks of a model file's ``[[ground_motion]]`` (``pfeie run``, ``pfeie
        check``) on a study's record: its PGA as read (``rec``, in its units) at most
        :data:`~pfeie.io.MAX_PGA_G` (a record in cm/s² read as g is 981 times
        too strong) and plausible (:func:`~pfeie.io.implausible_pga`, a WARNING); the PGA
        of every scaled run (``pga``, m/s², of the part applied, times each factor) at most
        that bound; a record the steps can see (at least one step long), and a WARNING
        where the step is coarser than its sampling (:func:`~pfeie.io.coarse_step`)."""
        from ..dynamics import shorter_than_a_step
        from ..io import MAX_PGA_G, coarse_sampling, coarse_step, implausible_pga

        where, units = self._entry(r), rec.read_units
        why = shorter_than_a_step(rec, self._job.analysis.dt)
        if why is not None:
            raise InputError(f"{where}: {r.path}: {why}")
        if (coarse := coarse_step(rec, self._job.analysis.dt)) is not None:
            log.warning("%s: %s: %s", where, r.name, coarse)
        if (sparse := coarse_sampling(r.path, rec)) is not None:
            log.warning("%s: %s", where, sparse)
        if rec.pga > MAX_PGA_G * G:
            raise InputError(f"{where}: {r.path}: the record's peak ground acceleration is "
                             f"{rec.pga / G:.4g} g as read (units = {units!r}); expected at "
                             f"most {MAX_PGA_G:g} g: check units (a record in cm/s2 read as g "
                             "is 981 times too strong)")  # fmt: skip
        odd = implausible_pga(r.path, rec.pga, units)
        if odd is not None:
            log.warning("%s: %s", where, odd)
        for k, f in enumerate(factors):
            if pga * abs(f) > MAX_PGA_G * G * (1 + 1e-12):
                raise InputError(f"{where}: {r.path}: at intensity.values[{k}] = "
                                 f"{self.values[k]:g} the record's peak ground acceleration "
                                 f"is {pga * abs(f) / G:.4g} g (as read and scaled "
                                 f"×{abs(f):.6g}); expected at most {MAX_PGA_G:g} g: check "
                                 "units and the intensities")  # fmt: skip

    def demand_columns(self) -> list[str]:
        """The numeric columns that a row of this model can have (the model's probes and
        joints, its dimension's joint columns, the demand-capacity columns only with
        tensile strengths in its materials): what a limit state's demand may name."""
        self.context()
        model, probes = self._job.model, self._job.probes
        joints = [] if model.pairs is None else list(model.pairs.names)
        keys = JOINT_KEYS_2D if model.dim == 2 else JOINT_KEYS_3D
        stress = STRESS_KEYS if self._has_tensile() else tuple(
            k for k in STRESS_KEYS if k not in DCR_KEYS)  # fmt: skip
        return (["intensity", "scale_factor"] + [c for c, _, _ in IM_COLUMNS]
                + [f"probe.{p}.{k}" for p in probes for k in PROBE_KEYS]
                + [f"joint.{j}.{k}" for j in joints for k in keys]
                + [f"stress.{k}" for k in stress]
                + [f"energy.{k}" for k in ENERGY_KEYS]
                + [f"solver.{k}" for k in SOLVER_KEYS])  # fmt: skip

    def _has_tensile(self) -> bool:
        """Whether a material of the model gives a tensile strength (the demand-capacity
        columns, ``stress.max_dcr`` ...)."""
        return bool(np.isfinite(self._job.model.cell_tensile_strength).any())

    def _check_demands(self) -> None:
        """Every limit state names a column of this model's table (before any run)."""
        if not self.limit_states:
            return
        cols = self.demand_columns()
        for i, ls in enumerate(self.limit_states):
            col = str(ls["demand"])
            if col in (f"stress.{k}" for k in DCR_KEYS) and col not in cols:
                raise InputError(
                    f"{self._where(f'limit_states[{i}].demand')}: {col!r} is a "
                    f"demand-capacity column: it needs the tensile strength of the concrete, "
                    f"and no material of {self.model} gives one; expected tensile_strength "
                    "in [materials.<name>] (Pa), or another demand"
                )
            if col not in cols:
                near = difflib.get_close_matches(col, cols, n=1)
                hint = f" (did you mean {near[0]!r}?)" if near else ""
                raise InputError(
                    f"{self._where(f'limit_states[{i}].demand')}: no column {col!r} in the "
                    f"table of {self.model}{hint}; expected one of: {', '.join(cols)}"
                )

    def prepare_folder(self) -> Path:
        """Create the output folder (and its ``rows``) if needed and check that it can be
        written; an :class:`InputError` names the study file and ``output.folder``."""
        from ..io import output_folder

        where = self._where("output.folder")
        folder = output_folder(self.folder, where)
        output_folder(folder / "rows", where)
        return folder

    # -- running ---------------------------------------------------------------------------

    def run(
        self,
        *,
        workers: Workers | None = None,
        scheduler: str | None = None,
        resume: bool = True,
        progress: Callable[[int, int, dict[str, Any]], None] | None = None,
    ) -> StudyTable:
        """Run every run not already done (``resume``: rows in ``<folder>/rows`` with
        the same key are kept) and write the table (``table.csv``, ``table.parquet``).

        ``workers`` worker processes of a local Dask cluster (0: in this process, one
        after the other; "auto": one per available core, in this process when Dask is
        not installed or with one core or one run to do,
        :func:`~pfeie.study._parallel.local_workers`), or the Dask ``scheduler`` at an
        address; the study's ``workers`` and ``scheduler`` by default (the study file's
        ``[run]``). ``progress(done, total, row)`` is called after each
        run. One study at a time writes to a folder (a lock file with its process id, as
        ``pfeie run``'s output folder; another gets an :class:`InputError` naming it)."""
        from .._job import FolderLock

        if getattr(multiprocessing.current_process(), "_inheriting", False):
            # a worker process of a study's cluster that imports the script which started
            # the study, a script without the __main__ guard: the worker leaves quietly,
            # and the study's own process alone says why its workers did not start
            raise SystemExit(1)
        folder = self.prepare_folder().resolve()
        specs = self.runs()
        try:
            lock = FolderLock(folder, self.source if self.source is not None else self.model)
            lock.__enter__()
        except InputError as exc:
            raise InputError(f"{self._where('output.folder')}: {exc}") from None
        try:
            self._check_folder(folder)
            # (said before the runs, not after them)
            parquet = self.parquet and self._parquet_possible()
            return self._run(specs, folder, workers, scheduler, resume, progress, parquet)
        finally:
            lock.__exit__()

    def _parquet_possible(self) -> bool:
        """Whether ``table.parquet`` can be written: pyarrow is the ``study`` extra, and
        without it the table is the CSV alone (a WARNING says so before the runs), not a
        failed study after every run."""
        try:
            import pyarrow  # noqa: F401
        except ImportError:
            log.warning("%s: pyarrow is not installed (pip install 'pfeie[study]'): the "
                        "table is written as table.csv only, not table.parquet",
                        self._where("output.parquet"))  # fmt: skip
            return False
        return True

    def _check_folder(self, folder: Path) -> None:
        """The output folder holds no single run's results (``results.h5`` of ``pfeie
        run``: an :class:`InputError`, the two would mix their summaries and reports); a
        folder of a study of another model (``study.json`` with another model key) gets a
        WARNING: its histories under ``runs/`` that this study does not write again stay
        beside this study's outputs."""
        where = self._where("output.folder")
        if (folder / "results.h5").exists():
            raise InputError(f"{where}: {folder} holds the results of a `pfeie run` "
                             "(results.h5); a study writes its own table, report and "
                             "histories: choose another output.folder")  # fmt: skip
        try:
            old = json.loads((folder / "study.json").read_text())
        except (OSError, ValueError):
            return
        key = old.get("model_key") if isinstance(old, dict) else None
        ctx = self.context()
        if key is not None and key != ctx.model_key:
            solver = old.get("solver_stack")
            why = (f"another sparse solver ({solver!r}, here {ctx.solver!r})"
                   if solver is not None and solver != ctx.solver else
                   "another model, other settings or another pfeie version")  # fmt: skip
            log.warning("%s: %s holds the outputs of a study of %s (study.json: %r, pfeie "
                        "%s); its rows are not reused, and its histories under runs/ that "
                        "this study does not write again stay there: choose another "
                        "output.folder to keep the two apart", where, folder, why,
                        old.get("title") or old.get("model"),
                        old.get("pfeie_version", "?"))  # fmt: skip

    def _run(
        self,
        specs: list[RunSpec],
        folder: Path,
        workers: Workers | None,
        scheduler: str | None,
        resume: bool,
        progress: Callable[[int, int, dict[str, Any]], None] | None,
        parquet: bool,
    ) -> StudyTable:
        """:meth:`run` with the folder locked; ``parquet``: ``table.parquet`` written."""
        # the output options as they are now (they may be changed after the set-up)
        ctx = dataclasses.replace(self.context(), folder=folder, histories=self.histories,
                                  resume=resume)  # fmt: skip
        workers = self.workers if workers is None else check_workers(workers)
        scheduler = self.scheduler if scheduler is None else scheduler
        done: dict[str, dict[str, Any]] = {}
        missing = 0  # kept rows whose history is wanted and not there: run again
        if resume:
            for s in specs:
                row = kept_row(ctx, s)
                if row is not None:
                    done[s.key] = row
                elif ctx.histories and read_row(ctx.folder, s.key) is not None:
                    missing += 1
        if missing:
            log.warning("%s: %d run(s) done before have no history of theirs under runs/ "
                        "(output.histories was off, or their folder holds another run's "
                        "file, a part of one that was stopped, or has a new name): run "
                        "again to write it", ctx.folder,
                        missing)  # fmt: skip
        # one run per key: two records with the same bytes and options share their runs
        todo = list({s.key: s for s in specs if s.key not in done}.values())
        total = len({s.key for s in specs})
        log.info("study: %d runs, %d done before, %d to run", total, len(done), len(todo))
        self.kept = len({s.key for s in specs if s.key in done})
        n_done = len(done)

        def finished(row: dict[str, Any]) -> None:
            nonlocal n_done
            done[row["key"]] = row
            n_done += 1
            if progress is not None:
                progress(n_done, total, row)

        if todo:
            from ._parallel import batches, local_workers, run_parallel

            n = 0 if scheduler else local_workers(workers, len(todo))
            batch = self.batch if self._may_step_together() else 1
            if scheduler or n > 0:
                run_parallel(ctx, todo, finished, workers=n, scheduler=scheduler,
                             batch=batch)  # fmt: skip
            else:  # in this process: each group's rows reported, then its first error
                for group in batches(todo, batch, 1):
                    outcomes = run_batch(ctx, group)
                    for r in outcomes:
                        if not isinstance(r, PfeieError):
                            finished(r)
                    for r in outcomes:
                        if isinstance(r, PfeieError):
                            raise r
        table = StudyTable([_as_run(done[s.key], s) for s in specs])
        table.to_csv(ctx.folder / "table.csv")
        if parquet:
            table.to_parquet(ctx.folder / "table.parquet")
        else:  # an earlier study's table must not stand beside this one's
            (ctx.folder / "table.parquet").unlink(missing_ok=True)
        meta = {"title": self.title, "model": str(self.model), "model_key": ctx.model_key,
                "measure": self.measure, "values": self.values, "period_s": self.period,
                "damping": self.damping, "records": [r.name for r in self.records],
                "runs": len(specs), "pfeie_version": __version__,
                "solver_stack": ctx.solver}  # fmt: skip
        (ctx.folder / "study.json").write_text(json.dumps(meta, indent=2) + "\n")
        self._outputs = [ctx.folder / "table.csv"] + (
            [ctx.folder / "table.parquet"] if parquet else [])  # fmt: skip
        from ._report import write_study_outputs

        try:
            self._outputs += write_study_outputs(self, table, ctx.folder)
        except ModelError as exc:  # a limit state on a column the table does not have
            raise InputError(f"{self._where(str(exc))} (the table is written)") from None
        return table

    def outputs(self) -> list[Path]:
        """The files the last :meth:`run` wrote (besides the rows)."""
        return list(getattr(self, "_outputs", []))


__all__ = ["Context", "RecordSource", "RunSpec", "Study", "Workers", "builds", "check_workers",
           "read_row", "run_batch", "system", "write_row"]  # fmt: skip
