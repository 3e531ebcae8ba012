"""Checkpoints of a run in its results file, and resuming a stopped run.

Besides its rows, a run writes the group ``/checkpoint`` of its results file: the full
step state of a recorded row (displacements, velocities, accelerations, the load and the
scheme's auxiliary acceleration on the free DOFs; every pair's state, forces, relative
motion, slip direction and path; the smooth pair forces), the stress envelope so far,
the fields of the row when it is off the field grid (they become the final frame if the
run ends there), the running sums of the energy account, the energy the balance is
measured from, the row index, and the rows of the last chunk of every compressed history
(:func:`_tails`: a kill can damage that chunk, and resuming rewrites it). It is replaced
at most every ``interval`` seconds of wall time and at the end of the run (completed,
stopped by Ctrl-C or SIGTERM, or by a step that failed).

``pfeie run --resume`` (:func:`pfeie._job.run_job` with ``resume=True``) opens the results
file of a stopped run, checks that the inputs are the same (the *run key*: the validated
model file with its command-line overrides except the duration, and the bytes of the
mesh and record files), cuts the histories back to the checkpoint's row and continues
from it. The resumed results are the same bits as those of a run that was never stopped
(``tests/test_checkpoint.py``). A longer ``--duration`` extends a completed run the same
way.
"""

from __future__ import annotations

import hashlib
import json
import time
from pathlib import Path
from typing import Any

import numpy as np

from .._version import __version__
from ..dynamics import Checkpoint, DynamicResult, State, StepState
from ..errors import ResultsError
from ..interface import PairState
from ._results import ResultsWriter, _h5py, read_envelope

_KIN = ("u", "v", "a", "f")
_PAIRS = ("state", "broken", "X", "w", "s", "slip_dir", "path")
_UNITS = {"u": "m", "v": "m/s", "a": "m/s^2", "aux": "m/s^2", "f": "N", "shift": "m",
          "ground": "m/s^2", "supports": "m, m/s, m/s^2, m/s^2",
          "state": "code",
          "broken": "flag", "X": "N", "w": "m", "s": "m", "slip_dir": "1", "path": "m",
          "lam": "N", "node_max": "Pa", "node_min": "Pa", "cell_max": "Pa", "cell_min": "Pa",
          "node_max_time": "s", "node_min_time": "s", "cell_max_time": "s",
          "cell_min_time": "s", "cell_dcr": "1", "cell_cid": "s",
          "cid_last_time": "s"}  # fmt: skip


def run_key(job: Any, legacy: bool = False, stack: bool = True) -> str:
    """The SHA-256 of what a run's results depend on, except its duration: the validated
    model file with its overrides, and the bytes of the mesh and record files. The keys
    of the storage that change no value are left out: ``output.compression`` and
    ``compression_level`` (a resumed run keeps the file's own), ``field_precision``
    when it is "float64", the precision of every file written before these keys (so
    their run keys stay the same), ``checkpoint_steps`` (when to checkpoint: a
    resumed run may checkpoint otherwise), and ``damping.deformation_only`` when false
    and ``analysis.position_correction`` when "local" (the defaults, as before the
    options existed). The scale factors that depend on the
    duration (a ``pga`` or ``target_sa`` met by the part of a record up to
    ``analysis.duration``, :attr:`Job.part_factors`) are in it: a run extended to another
    duration with another factor is not continued. The keys that change no value of the
    results file are left out too: ``output.checkpoint_seconds``, ``paraview`` (the
    series is written from the file at the end) and ``folder`` (a results folder may be
    moved, then resumed); ``legacy``: the key with them, as results files written before
    version 0.3.15 hold it (:func:`same_run` takes either). The sparse solver in use,
    :func:`pfeie.linalg.solver_stack`, is in it (the last bits of the results depend on
    it; ``stack=False``: the key without it, as files written before version 0.3.20
    hold it)."""
    spec = _keyed(job.spec, legacy)
    h = hashlib.sha256(json.dumps(spec, sort_keys=True).encode())
    part = getattr(job, "part_factors", None)
    if part:  # none: the key as before these factors existed
        h.update(repr(sorted(part.items())).encode())
    base = Path(job.path).parent
    files = [base / spec["mesh"]["file"]]
    files += [base / g["file"] for g in spec.get("ground_motion", []) if g.get("file")]
    for p in files:
        h.update(p.read_bytes() if p.is_file() else str(p).encode())
    if stack:
        h.update(f"solver {job_solvers(job)}".encode())
    return h.hexdigest()


def job_solvers(job: Any) -> str:
    """The sparse solvers of a run (:func:`pfeie.linalg.solver_stack`): that of the
    static state and the other operators (backend "auto"), and, where
    ``analysis.backend`` names another for the time steps, ``"<auto>; steps <that>"``."""
    from ..linalg import solver_stack

    auto = solver_stack()
    backend = str(job.spec.get("analysis", {}).get("backend", "auto") or "auto")
    steps = solver_stack(backend) if backend != "auto" else auto
    return auto if steps == auto else f"{auto}; steps {steps}"


def same_run(key: str, job: Any) -> bool:
    """Whether the run key ``key`` of a results file is that of ``job``'s inputs: the
    present key, or the key of a file written before version 0.3.15 (:func:`run_key`)."""
    return key in (run_key(job), run_key(job, stack=False),
                   run_key(job, legacy=True, stack=False))  # fmt: skip


def _keyed(spec: Any, legacy: bool = False) -> dict[str, Any]:
    """The model spec as the run key takes it (see :func:`run_key`)."""
    spec = json.loads(json.dumps(spec, default=str))
    spec.get("analysis", {}).pop("duration", None)
    out = spec.get("output", {})
    for key in ("compression", "compression_level"):
        out.pop(key, None)
    if not legacy:  # where and when the file is written, not what it holds
        for key in ("checkpoint_seconds", "paraview", "folder"):
            out.pop(key, None)
    if out.get("field_precision") == "float64":
        out.pop("field_precision")
    out.pop("checkpoint_steps", None)  # when to checkpoint changes no value
    damping = spec.get("damping", {})
    if damping.get("deformation_only") is False:  # the default: keys as before the option
        damping.pop("deformation_only")
    analysis = spec.get("analysis", {})
    if analysis.get("position_correction") == "local":  # the same (since 0.3.25)
        analysis.pop("position_correction")
    return dict(spec)


def _flat(value: Any, key: str = "") -> dict[str, Any]:
    """A nested table as its key paths (``analysis.dt``, ``ground_motion[0].scale``)."""
    if isinstance(value, dict):
        out: dict[str, Any] = {}
        for k, v in value.items():
            out.update(_flat(v, f"{key}.{k}" if key else str(k)))
        return out
    if isinstance(value, list) and any(isinstance(v, dict) for v in value):
        out = {}
        for i, v in enumerate(value):
            out.update(_flat(v, f"{key}[{i}]"))
        return out
    return {key: value}


def _differs(f: Any, job: Any) -> str:
    """What makes a run's inputs differ from those of the run in the results file ``f``
    (their run keys differ): a scale factor met by a record up to the duration, which a
    resume to another duration changes, else the inputs themselves."""
    was = {int(k): float(v) for k, v in json.loads(f.attrs.get("part_factors", "{}")).items()}
    now = dict(getattr(job, "part_factors", None) or {})
    changed = [i for i in sorted(set(was) | set(now)) if was.get(i) != now.get(i)]
    if changed:
        i = changed[0]
        old = "the whole record's" if i not in was else f"×{was[i]:.6g}"
        new = "the whole record's" if i not in now else f"×{now[i]:.6g}"
        return (
            f"ground_motion[{i}]'s pga or target_sa is met by the record up to "
            f"analysis.duration, so its scale factor depends on the duration: {old} for "
            f"the run in the file, {new} for this one (another motion from the start)"
        )
    here = job_solvers(job)
    was_stack = str(f.attrs.get("solver_stack", here))
    if was_stack != here:
        return (
            f"the sparse solver differs: {was_stack!r} for the run in the file, {here!r} "
            "here (the last bits of the results depend on it: install the same extras, "
            "pfeie[fast], or set PFEIE_SOLVER and analysis.backend as the run had them)"
        )
    if "model_spec" in f.attrs:  # the keys that differ (the file's spec as run)
        was_spec = _flat(_keyed(json.loads(f.attrs["model_spec"])))
        now_spec = _flat(_keyed(job.spec))
        keys = [k for k in sorted(set(was_spec) | set(now_spec))
                if was_spec.get(k) != now_spec.get(k)]  # fmt: skip
        if keys:
            shown = "; ".join(
                f"{k}: {was_spec.get(k, '(none)')!r} for the run in the file, "
                f"{now_spec.get(k, '(none)')!r} for this one"
                for k in keys[:4]
            )
            more = f" (and {len(keys) - 4} more)" if len(keys) > 4 else ""
            return f"the inputs differ from those of the run: {shown}{more}"
        return (f"the model file's keys are those of the run, but the contents of the mesh "
                f"or of a record file differ ({job.path})")  # fmt: skip
    return (
        f"the model file, its --set overrides, the mesh or a record differ from those "
        f"of the run ({job.path})"
    )


class CheckpointWriter:
    """Writes the checkpoints of a run into its results file (see the module doc): call
    it with every :class:`~pfeie.dynamics.Checkpoint` of the run (``on_checkpoint`` of
    :meth:`pfeie.Dynamic.run`); it keeps the latest and writes it when ``interval``
    seconds have passed since the last one, or ``steps`` time steps (when > 0), and on
    :meth:`close`."""

    def __init__(self, writer: ResultsWriter, key: str, interval: float = 30.0,
                 steps: int = 0, part_factors: dict[int, float] | None = None) -> None:  # fmt: skip
        self.writer, self.key, self.interval = writer, key, float(interval)
        self.steps = int(steps)
        self._pending: Checkpoint | None = None
        self._last = time.perf_counter()
        self._last_step: int | None = None
        self.written: list[int] = []  # the time steps of the checkpoints written
        writer.f.attrs["run_key"] = key
        # the scale factors met by the records up to the duration (Job.part_factors): a
        # resume to another duration that changes one is told so
        writer.f.attrs["part_factors"] = json.dumps(
            {str(i): v for i, v in sorted((part_factors or {}).items())}
        )

    def __call__(self, ck: Checkpoint) -> None:
        self._pending = ck
        if self._last_step is None:  # the first step of this run (or of its resumption)
            self._last_step = ck.state.step - 1
        # every N steps: at the first recorded row at or after each multiple of N
        due = self.steps > 0 and ck.state.step // self.steps > self._last_step // self.steps
        if due or time.perf_counter() - self._last >= self.interval:
            self.write()

    def close(self) -> None:
        """Write the latest checkpoint, if it is not on disk yet. A run whose last step
        lies off the grid of ``output.every`` has recorded that step in a row of its
        own after the latest checkpoint's (not a checkpoint: a run extended from this one
        continues from the last row on the grid, :meth:`pfeie.Dynamic.run`); the
        checkpoint is written all the same, and a resumed run drops that row."""
        self.write(final=True)

    def write(self, final: bool = False) -> None:
        ck = self._pending
        if ck is None:
            return
        w = self.writer
        w.flush()
        f = w.f
        on_disk = f["history/time"].shape[0]
        if on_disk != ck.row + 1 and not (final and on_disk == ck.row + 2):
            raise ResultsError(f"{w.path}: checkpoint of row {ck.row} with "
                               f"{on_disk} rows on disk")  # fmt: skip
        if "checkpoint_new" in f:
            del f["checkpoint_new"]
        g = f.create_group("checkpoint_new")
        st = ck.state
        kin = st.kin
        g.attrs.update(
            row=ck.row, step=st.step, t=kin.t, fields_rows=f["fields/time"].shape[0],
            energy=json.dumps(ck.energy), origin=json.dumps(list(ck.origin)),
            run_key=self.key, energy_account=ENERGY_ACCOUNT,
        )  # fmt: skip
        if st.origin is not None or st.step == 0:  # the time grid: step k at origin + k h
            g.attrs["time_origin"] = kin.t if st.origin is None else st.origin
        if st.records is not None:  # the records of the run (for a run from the state)
            g.attrs["records"] = json.dumps(list(st.records))
        data = {f"kin/{k}": getattr(kin, k) for k in _KIN}
        data.update({f"pairs/{k}": getattr(st.pairs, k) for k in _PAIRS})
        if kin.aux is not None:
            data["kin/aux"] = kin.aux
        if st.lam is not None:
            data["pairs/lam"] = st.lam
        if st.shift is not None:  # the row's stress envelope excludes it (the recorder)
            data["kin/shift"] = st.shift
        if st.ground is not None:  # the ground acceleration the step applied (a_abs)
            data["kin/ground"] = st.ground
        if ck.supports is not None:  # the supports' grid rows (absolute form)
            data["kin/supports"] = ck.supports
        for k, v in (ck.envelope or {}).items():
            data[f"envelope/{k}"] = v
        if w._last is not None:  # the row's fields, when it is off the field grid
            g.attrs["last_t"] = w._last[0]
            data.update({f"last/{k}": v for k, v in w._last[1].items()})
        for name, value in data.items():  # float64 whatever the field precision, compressed
            # as the results file (lossless: the resumed run continues from the same bits)
            w.storage.create(g, name, value, _UNITS[name.split("/")[1]])
        for name, (value, units) in _tails(f, ck.row + 1).items():
            w.storage.create(g, f"tail/{name}", value, units)
        # on disk before the old checkpoint's space is freed (and may be reused)
        f.flush()
        if "checkpoint" in f:
            del f["checkpoint"]
        f.move("checkpoint_new", "checkpoint")
        f.flush()
        self._pending = None
        self._last = time.perf_counter()
        self._last_step = st.step
        self.written.append(st.step)


def _grows(obj: Any) -> bool:
    """Whether an HDF5 object is a dataset that grows along time (a history, the fields)."""
    return hasattr(obj, "resize") and bool(obj.maxshape) and obj.maxshape[0] is None


def _tails(f: Any, rows: int) -> dict[str, tuple[Any, str]]:
    """The rows in the last chunk of every compressed history up to the checkpoint's
    ``rows`` (and of ``fields/time``, up to its last row on disk), from the chunk's first
    row, with their units: a checkpoint
    keeps them. A compressed chunk that gains rows is written elsewhere in the file and
    its old place freed, and HDF5 may reuse that place before the file's index is
    flushed: a run killed then leaves a file whose index points the last chunk at other
    data. Resuming rewrites that chunk from these rows (:func:`reopen_results`); every
    earlier chunk was complete at the checkpoint and is never written again."""
    out: dict[str, tuple[Any, str]] = {}

    def visit(name: str, obj: Any) -> None:
        if _grows(obj) and obj.compression and obj.chunks[0] > 1 and obj.size:
            end = obj.shape[0] if name.startswith("fields/") else min(rows, obj.shape[0])
            start = (end - 1) // obj.chunks[0] * obj.chunks[0]
            out[name] = (np.asarray(obj[start:end]), str(obj.attrs.get("units", "")))

    for top in ("history", "fields"):
        f[top].visititems(lambda n, o, top=top: visit(f"{top}/{n}", o))
    return out


def _restore_tail(ds: Any, keep: int, tail: Any) -> None:
    """Rewrite the chunk of ``ds`` that holds its row ``keep - 1`` from ``tail`` (its rows
    from the chunk's first, :func:`_tails`), written whole so that HDF5 does not read the
    chunk on disk (which a kill may have left pointing at other data)."""
    r = ds.chunks[0]
    start = (keep - 1) // r * r
    if keep < 1 or tail.shape[0] != keep - start or tail.shape[1:] != ds.shape[1:]:
        return
    ds.resize(max(ds.shape[0], start + r), axis=0)
    block = np.zeros((r, *ds.shape[1:]), dtype=ds.dtype)
    block[: tail.shape[0]] = tail
    ds[start : start + r] = block


def read_checkpoint(f: Any) -> Checkpoint:
    """The checkpoint of an open results file."""
    g = f["checkpoint"]
    u, v, a, f_ = (np.asarray(g[f"kin/{k}"]) for k in _KIN)
    aux = np.asarray(g["kin/aux"]) if "kin/aux" in g else None
    kin = State(float(g.attrs["t"]), u, v, a, f_, aux)
    pairs = PairState(*(np.asarray(g[f"pairs/{k}"]) for k in _PAIRS))
    lam = np.asarray(g["pairs/lam"]) if "pairs/lam" in g else None
    shift = np.asarray(g["kin/shift"]) if "kin/shift" in g else None
    ground = np.asarray(g["kin/ground"]) if "kin/ground" in g else None
    t0 = g.attrs.get("time_origin")  # (older files have none: t − step h)
    records = g.attrs.get("records")  # (files written before 0.3.25 have none)
    st = StepState(kin, pairs, int(g.attrs["step"]), lam=lam, shift=shift,
                   origin=None if t0 is None else float(t0), ground=ground,
                   records=None if records is None else tuple(json.loads(records)))  # fmt: skip
    energy = {k: float(v) for k, v in json.loads(g.attrs["energy"]).items()}
    o0, o1 = json.loads(g.attrs["origin"])
    env = ({k: np.asarray(v) for k, v in g["envelope"].items()} if "envelope" in g
           else None)  # fmt: skip
    supports = np.asarray(g["kin/supports"]) if "kin/supports" in g else None
    return Checkpoint(st, energy, (float(o0), float(o1)), int(g.attrs["row"]), env,
                      supports=supports)  # fmt: skip


#: the energy account's definition, kept in every checkpoint: 2 records the rigid pairs'
#: dissipation −P·U⁺ as ``interface`` and ½sΛᵀWΛ as ``impact`` (1: the smooth forces' work
#: on the smooth motion and −½Λ·(U⁻ + U⁺)); a resumed run continues only its own account
ENERGY_ACCOUNT = 2


class NothingToResume(ResultsError):
    """The run to resume left no checkpoint: no results file, or one of the same inputs
    stopped before its first checkpoint. Nothing is lost by running it again from the
    start (the run is deterministic), which :func:`pfeie.run_job` then does."""


def resumable(path: str | Path, job: Any, *, same_inputs: bool = True,
              completed: bool = False) -> float | None:  # fmt: skip
    """The time (s) of the checkpoint of a stopped run of ``job``'s inputs (the same run
    key) in the results file ``path``, which ``pfeie run --resume`` would continue; None
    for a completed run, a run of other inputs, a file without a checkpoint or one that
    does not open. ``same_inputs=False``: of any inputs (its own resume continues it);
    ``completed=True``: of a completed run too (``--resume --duration`` extends it)."""
    p = Path(path)
    if not p.is_file():
        return None
    try:
        with _h5py().File(p, "r") as f:
            name = next((g for g in ("checkpoint", "checkpoint_new") if g in f), None)
            other = same_inputs and not same_run(f.attrs.get("run_key", ""), job)
            done = not completed and bool(f.attrs.get("completed", False))
            if name is None or done or other:
                return None
            return float(f[name].attrs["t"])
    except (OSError, KeyError, ValueError):
        return None


def reopen_results(path: str | Path, job: Any) -> tuple[ResultsWriter, Checkpoint]:
    """The results file of a stopped run opened to continue it: the inputs checked against
    the run key, the histories cut back to the checkpoint's row. Errors
    (:class:`ResultsError`) name the file and what was expected."""
    p = Path(path)
    if not p.is_file():
        raise NothingToResume(f"{p}: nothing to resume: no results file")
    try:
        f = _h5py().File(p, "r+")
    except OSError as exc:
        raise ResultsError(f"{p}: cannot open the results file to resume it ({exc})") from None
    try:
        if "checkpoint" not in f and "checkpoint_new" in f and "compression" in f.attrs:
            # killed while the new checkpoint replaced the old: it was on disk, complete,
            # before the old one was deleted (format 1.3 on)
            try:
                f.move("checkpoint_new", "checkpoint")
            except (OSError, ValueError, KeyError) as exc:  # not on disk whole after all
                raise ResultsError(
                    f"{p}: cannot resume: its last checkpoint was not written whole (a disk "
                    f"that was full, or a file damaged while the run wrote it: {exc}); run "
                    "without --resume (the rows written before are read by plot, export "
                    "and report)"
                ) from None
        same = same_run(f.attrs.get("run_key", ""), job)
        if "checkpoint" not in f:
            if same:  # the same run, stopped before a checkpoint
                raise NothingToResume(f"{p}: nothing to resume: the run stopped before its "
                                      "first checkpoint")  # fmt: skip
            raise ResultsError(f"{p}: nothing to resume: the file has no checkpoint (a "
                               "run of an older pfeie, or of other inputs); run without "
                               "--resume")  # fmt: skip
        if not same:
            raise ResultsError(f"{p}: cannot resume: {_differs(f, job)}; run without --resume")
        written = str(f.attrs.get("pfeie_version", "?"))
        if written != __version__:  # another version may compute other numbers
            raise ResultsError(f"{p}: cannot resume: the run was written by pfeie {written}, "
                               f"this is pfeie {__version__} (results of two versions are not "
                               "mixed in one file); run without --resume")  # fmt: skip
        ck = read_checkpoint(f)
        if "modified" not in ck.energy:  # its algorithmic sum holds Φ: not to be continued
            raise ResultsError(f"{p}: cannot resume: the checkpoint was written by an earlier "
                               "pfeie, whose energy account had no 'modified' term; run "
                               "without --resume")  # fmt: skip
        if int(f["checkpoint"].attrs.get("energy_account", 1)) != ENERGY_ACCOUNT:
            raise ResultsError(f"{p}: cannot resume: the checkpoint was written by an earlier "
                               "pfeie, whose energy account recorded 'interface' and "
                               "'impact' otherwise (docs/results.md); run without "
                               "--resume")  # fmt: skip
        rows, frows = ck.row + 1, int(f["checkpoint"].attrs["fields_rows"])
        tails = f["checkpoint"].get("tail")

        def cut(name: str, obj: Any) -> None:
            # (a history of zero-width rows, the pairs of a model without interfaces,
            # never grows: it keeps its 0 rows, as in a run never stopped)
            if _grows(obj) and not (len(obj.shape) > 1 and 0 in obj.shape[1:]):
                keep = frows if name.startswith("fields") else rows
                if tails is not None and name in tails:  # the last chunk, as checkpointed
                    _restore_tail(obj, keep, np.asarray(tails[name]))
                obj.resize(keep, axis=0)

        for top in ("history", "fields"):
            f[top].visititems(lambda n, o, top=top: cut(f"{top}/{n}", o))
        f.attrs["completed"] = False
        f.attrs["stop_reason"] = ""
        # the envelope, the summary and the post-earthquake state of the stop are the
        # run's up to there: a resumed run killed before it writes its own must not leave
        # them as if they were its
        for group in ("envelope", "post_earthquake"):
            if group in f:
                del f[group]
        if "results_summary" in f.attrs:
            del f.attrs["results_summary"]
        f.flush()
    except BaseException:
        f.close()
        raise
    writer = ResultsWriter.reopen(f, rows, job)
    if "last" in f["checkpoint"]:  # the final frame, if the run ends at the checkpoint
        g = f["checkpoint/last"]
        t_last = float(f["checkpoint"].attrs["last_t"])
        writer._last = (t_last, {k: np.asarray(g[k]) for k in ("u", "v", "a")})
    return writer, ck


def history(writer: ResultsWriter, completed: bool, reason: str | None) -> DynamicResult:
    """The whole run's histories as a :class:`~pfeie.dynamics.DynamicResult`, read back
    from the file (a resumed run holds only its own part in memory)."""
    writer.flush()
    f = writer.f
    h = f["history"]

    def arr(name: str) -> Any:
        return np.asarray(h[name])

    nodes = np.asarray(json.loads(h["probes"].attrs["nodes"]), dtype=np.int64)
    area = np.asarray(f["pairs/area"]) if "pairs" in f else np.zeros(0)
    energy = {k: arr(f"energy/{k}") for k in h["energy"]}
    solver = {k: arr(f"solver/{k}") for k in h["solver"]} if "solver" in h else {}
    fs = arr("joints/safety_factor") if "joints" in h else np.zeros((0, 0))
    jf = arr("joints/force") if "joints/force" in h else np.zeros((0, 0, 0))
    jm = arr("joints/moment") if "joints/moment" in h else np.zeros((0, 0, 0))
    jc = arr("joints/cracked") if "joints/cracked" in h else np.zeros((0, 0))
    jo = arr("joints/open") if "joints/open" in h else np.zeros((0, 0))
    return DynamicResult(
        t=arr("time"), probes=nodes, probe_u=arr("probes/u"), probe_v=arr("probes/v"),
        probe_a=arr("probes/a"), probe_a_abs=arr("probes/a_abs"), rigid=arr("rigid"),
        X=arr("pairs/X"), w=arr("pairs/w"), s=arr("pairs/s"), state=arr("pairs/state"),
        broken=arr("pairs/broken"), energy=energy, completed=completed, pair_area=area,
        stop_reason=reason, solver=solver, safety_factor=fs, envelope=read_envelope(f),
        joint_force=jf, joint_moment=jm, joint_cracked=jc, joint_open=jo,
        ground=arr("ground") if "ground" in h else np.zeros((0, 0)),
    )  # fmt: skip


__all__ = [
    "CheckpointWriter",
    "NothingToResume",
    "history",
    "read_checkpoint",
    "reopen_results",
    "run_key",
]
