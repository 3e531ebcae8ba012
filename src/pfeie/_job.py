"""Running a model file: static state, dynamic run, results on disk, a summary.

Outputs in the folder of ``[output]``:

- ``results.h5``: the results file, written while the run goes (see
  :mod:`pfeie.io._results`): metadata (model file and hash, pfeie version, settings,
  units), histories (probes, block rigid motions, every pair, energy), nodal fields;
- ``blocks.xdmf``, ``interfaces.xdmf`` (+ ``.h5``): the ParaView series;
- ``summary.json`` and ``summary.txt``: the model summary and the results summary (peak
  probe motions: the largest magnitude |u| and |a| and the per-axis peaks; per joint:
  residual slip, maximum opening, broken share and the share broken from the start,
  cracked extent and largest open crack; see :func:`summarize`).

A run stopped by Ctrl-C or SIGTERM, or by an interface step that does not converge,
keeps everything computed so far, and says so (``completed = false``).
"""

from __future__ import annotations

import contextlib
import errno
import json
import logging
import os
import re
import shutil
import signal
import sys
import threading
import time
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TextIO

import numpy as np
from scipy.spatial import cKDTree

from ._version import __version__
from .coupling import StaticInterfaceProblem
from .dynamics import (
    CORRECTION_UNRESOLVED,
    ENERGY_FLOOR,
    Checkpoint,
    Dynamic,
    DynamicResult,
    DynamicSettings,
    RunStopped,
    StepState,
    demand_capacity,
    envelope_extremes,
)  # fmt: skip
from .errors import (
    InputError,
    InterfaceError,
    MechanismError,
    ModelError,
    PfeieError,
    ResultsError,
    SolverError,
)
from .interface import FS_ROUNDOFF, OPEN, OPEN_CRACK_MIN_M, SLIDE, block_pieces
from .io import (
    PYTHON_RUN,
    CheckpointWriter,
    Job,
    NothingToResume,
    Results,
    ResultsWriter,
    history,
    output_folder,
    reopen_results,
    resumable,
    run_key,
    utf8_text,
    write_paraview,
    yield_label,
)  # fmt: skip
from .model import GroundMotion, Model
from .plot import per_thickness, plot_run, solver_line
from .solvers import (
    REDUCTION_F_MAX,
    YIELD_K_MAX,
    YIELD_RIGID_GAP,
    StaticResult,
    horizontal,
    junction_share,
    leans_on_junctions,
    solve_static,
    strength_reduction,
    yield_coefficient,
)
from .typing import FloatArray, IntArray

log = logging.getLogger(__name__)

#: the share of the input energy above which the summary gives the position correction's
#: energy (the Koyna demo's: 11.1, 2.4 and 0.49 % at Δt = 10, 5 and 2.5 ms)
CORRECTION_SHARE = 0.01

#: the share of the energy that went through a run (the input, or what the joints and the
#: damping took, the larger) beyond which energy *created* by the time scheme (a negative
#: algorithmic term) makes the summary say that the run is not converged in Δt. A block
#: on a 20° plane (φ = 30°) under El Centro: −0.8 % at Δt = 5 ms (residual slip 10.7 mm
#: against 10.8 mm for the rigid block), −21 % at 20 ms (8.0 mm) and −134 % at 100 ms
#: (18 mm, up the slope)
SCHEME_CREATED = 0.05

#: the share of the input beyond which energy *dissipated* by the time scheme (a positive
#: algorithmic term: numerical damping of the response and of contact events the step
#: does not resolve) makes the summary say that the run is damped by the scheme and not
#: converged in Δt. Measured (share at Δt = 10, 5, 2.5, 1.25 ms → the residual slip
#: against the finest default run): the 60 m dam above, default scheme 53, 19, 5.7, 1.4 %
#: → −27, −13, −7 %; Moreau–Jean (θ = 1) 47, 28, 19, 14 % → −76, −54, −34, −19 %; the
#: Koyna demo 7.7, 1.3, 0.26 % (default) and 65 % by Moreau–Jean at 10 ms (neck slip
#: 1.16 mm against 3.85)
SCHEME_DISSIPATED = 0.10

#: the share of the input that the joints must take (friction, contact and impact) for
#: the scheme's dissipation to be judged: a run without contact events whose scheme damps
#: modes the step does not resolve (a stiff undamped block at Δt = 10 ms, its ~100 Hz
#: vibration annihilated by ρ∞ = 0: 313 % of an input of 1.3e-5 J) is a choice of Δt for
#: the elastic response (docs/results.md, "The elastic response"), not of its joints
CONTACT_ACTIVITY = 0.01

#: a yield coefficient found where no equilibrium holds beyond it is read as a sliding
#: limit that the pair solver fell short of when the joints' margins vanish within this
#: share above it and the least safety factor there is within it of 1 (a new user's four
#: rock columns on 15° bases: k_y 0.2655, FS 1.009, the margins' root 0.2679 = tan 15°)
NEAR_SLIDING = 0.02

#: a joint whose static safety factor is within this of 1 is at its capacity in a state that
#: holds (a wedge whose planes hold it by friction up their dip: 1.03 where Hoek and Bray's
#: factor is 1.41): its line points to the factor against sliding, the strength reduction's
AT_CAPACITY_FS = 0.05

#: a joint whose slip exceeds this share of the spacing of its pairs (the distance from a
#: pair to the nearest other pair of the joint) gets a line in the summary: the faces are
#: paired node to node (small sliding, docs/theory.md), and past half a spacing a node
#: faces its neighbour's partner more than its own
LARGE_SLIP = 0.5

#: the post-earthquake static state takes the undeformed geometry: it is not computed
#: where a floating block's residual rotation exceeds this (degrees) or its residual
#: displacement this share of its size (its largest extent), e.g. a column that toppled
POST_EQ_ROTATION_MAX_DEG = 5.0
POST_EQ_MOVE_MAX = 0.1

#: a floating block whose rigid rotation passes this (degrees) at some recorded time, or
#: whose displacement passes LARGE_MOVE × its size, gets a line in the summary: the joints
#: pair the faces' nodes as they were meshed (small sliding, no contact search), so a
#: block that topples or leaves its joint is not followed (it passes through the blocks
#: it meets); a rocking block that stays up turns by a few degrees
LARGE_TURN_DEG = 30.0
LARGE_MOVE = 0.5
#: degrees: the rotation of a floating block beyond which a run with small rotations
#: (``analysis.large_rotation = false``) is warned: its pairs' frames and lever arms stay
#: as meshed, an error of the order of the rotation against the angles that matter (a
#: 1 m × 4 m column rocking on its corner, slenderness 14°, turned 2.3° by 2 s where the
#: rigid rocking solution and a large-rotation run turn 4.4°)
SMALL_TURN_DEG = 1.0

#: a joint's minimum safety factor is dated at the first recorded time within this
#: share of it: the values of a sliding joint are 1 to round-off (1 − 1e-15) at every
#: step it slides; a minimum within it of 1 is given as 1 (the joint slid: a study's
#: limit state FS ≤ 1 counts it, which 1 + 4.7e-14 missed)
MIN_FS_TIES = 1e-9

#: the floating blocks (held by their joints) whose motion the text summary lists; all
#: bodies are in summary.json
BODY_LINES = 10

#: m/s², the g of the accelerations the summary gives in g (as the records' units)
G = 9.81


class Progress:
    """A one-line progress report on a stream: step, time, elapsed, ETA, pair counts.
    ``n_steps`` is the last step of the run and ``first`` the step it starts from (a
    resumed run's checkpoint): the report counts the run's steps as they are numbered,
    and the ETA from the pace of this process's steps."""

    def __init__(
        self, n_steps: int, dt: float, stream: TextIO | None = None, first: int = 0
    ) -> None:
        self.n, self.dt, self.first = n_steps, dt, first
        self.stream = stream or sys.stderr
        self.t0 = time.perf_counter()
        self.last = -1.0
        self.tty = self.stream.isatty()

    def __call__(self, st: StepState) -> None:
        now = time.perf_counter()
        if now - self.last < (0.25 if self.tty else 5.0) and st.step < self.n:
            return
        self.last = now
        el = now - self.t0
        eta = el / max(st.step - self.first, 1) * max(self.n - st.step, 0)
        p = st.pairs
        c = (f" open {int((p.state == OPEN).sum())} slide {int((p.state == SLIDE).sum())} "
             f"broken {int(p.broken.sum())}") if p.state.size else ""  # fmt: skip
        line = (f"step {st.step}/{self.n}  t {st.kin.t:.3f} s  elapsed {el:.1f} s  "
                f"ETA {eta:.1f} s {c}")  # fmt: skip
        if self.tty:
            self.stream.write("\r" + line.ljust(100))
            if st.step >= self.n:
                self.stream.write("\n")
        else:
            self.stream.write(line + "\n")
        self.stream.flush()


#: what a run writes beside results.h5, removed when a new run starts in the folder (with
#: ParaView off, an earlier run's series would stand beside the new results as if theirs)
STALE_OUTPUTS = ("summary.json", "summary.txt", "report.html", "blocks.xdmf", "blocks.h5",
                 "interfaces.xdmf", "interfaces.h5", "envelope.vtu")  # fmt: skip


def run_job(
    job: Job, *, progress: bool = True, duration: float | None = None,
    stream: TextIO | None = None, resume: bool = False, checkpoint_s: float | None = None,
    resume_with: str | None = None,
) -> dict[str, Any]:  # fmt: skip
    """Run a validated model file; returns the results summary (also written to disk).

    A checkpoint is written to the results file every ``checkpoint_s`` seconds (default
    ``output.checkpoint_seconds``) and at the end (:mod:`pfeie.io._checkpoint`);
    ``resume`` continues a stopped run from it (or extends a completed one to a longer
    duration); ``resume_with``, the command that does so (the command line's own, with
    its options), is what the messages of a stop give. One run at a time writes to an
    output folder (a lock file with its process id; another run gets a clear error)."""
    out = output_folder(job.folder, f"{job.path}: output.folder")
    if (why := study_outputs(out)) is not None:  # a run's summaries would replace the study's
        raise InputError(f"{job.path}: output.folder: {out} holds the outputs of a `pfeie "
                         f"study` ({why}); a run writes its own results, summary and "
                         "report: choose another output.folder")  # fmt: skip
    with FolderLock(out, job.path):
        try:
            return _run(job, out, progress, duration, stream, resume, checkpoint_s,
                        resume_with or "`pfeie run --resume`")  # fmt: skip
        except OSError as exc:  # a full disk, a quota, a folder removed under the run
            import gc

            gc.collect()  # close the results file that the run left open
            where = exc.filename if exc.filename else out
            if exc.errno in (errno.EACCES, errno.EPERM, errno.EROFS):
                fix = ("the file or folder is not writable (permissions, a read-only file "
                       "system): make it writable or choose another output.folder")  # fmt: skip
            else:
                fix = "free some room (a full disk or a quota)"
            raise ResultsError(
                f"{where}: cannot write the results ({exc.strerror or exc}): {fix}; what was "
                "written before stays readable (pfeie report, pfeie export), and then "
                f"{resume_with or '`pfeie run --resume`'} continues from the last checkpoint"
            ) from None


_ROW_FILE = re.compile(r"[0-9a-f]{64}\.json")


def study_outputs(folder: Path) -> str | None:
    """What shows that ``folder`` holds a study's outputs: its ``study.json`` (written
    when a study ends), or the rows of its runs (``rows/<key>.json``, written as each run
    ends: an interrupted study, which ``pfeie study`` resumes); None for another folder."""
    if (folder / "study.json").exists():
        return "study.json"
    rows = folder / "rows"
    if rows.is_dir() and any(_ROW_FILE.fullmatch(p.name) for p in rows.iterdir()):
        return "the rows of its runs under rows/"
    return None


class FolderLock:
    """One run at a time per output folder: a lock file holding the process id and the
    model, locked by the operating system (``flock``; released when the process ends, so a
    killed run's lock is taken over, whatever process now has its id). The file is written
    only while locked, and a lock taken on a file that another run has just removed (and
    maybe created again) is tried again: two runs started at the same moment cannot both
    take it. Where there is no ``flock`` (another operating system, some network file
    systems) the file itself is the lock: created with its content in one step (a hard
    link of a written file), refused while its process runs, and a stale one (its process
    gone) taken over."""

    def __init__(self, folder: Path, model: Path) -> None:
        self.path, self.model = folder / ".pfeie-run.lock", model
        self._fd: int | None = None

    def __enter__(self) -> FolderLock:
        import os

        flock = self._flock_works()
        if flock:
            import fcntl
        for _ in range(100):
            if not flock:
                if self._take_by_pid():
                    return self
                continue
            fd = os.open(self.path, os.O_CREAT | os.O_RDWR, 0o644)
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError as exc:
                os.close(fd)
                if exc.errno in (errno.EAGAIN, errno.EWOULDBLOCK, errno.EACCES):
                    self._refuse(held=True)
                    time.sleep(0.05)  # its holder ended while we read it: again
                    continue
                log.debug("%s: flock failed (%s): the file alone", self.path, exc)
                flock = False
                continue
            try:
                same = os.fstat(fd).st_ino == os.stat(self.path).st_ino
            except FileNotFoundError:
                same = False
            if not same:  # removed by the run that held it: lock the new file
                os.close(fd)
                continue
            # locked: whatever the file says is a run that has ended
            os.ftruncate(fd, 0)
            os.write(fd, self._text().encode())
            self._fd = fd
            return self
        raise InputError(f"{self.path}: cannot take the output folder's lock")

    def _flock_works(self) -> bool:
        """Whether this system and the folder's file system lock files (``flock``), tried
        on a file of this process's own, so that no empty lock file is left where it
        does not."""
        import os
        import threading

        try:
            import fcntl
        except ImportError:  # not a POSIX system
            return False
        probe = self.path.with_name(
            f"{self.path.name}.probe.{os.getpid()}.{threading.get_ident()}")  # fmt: skip
        fd = os.open(probe, os.O_CREAT | os.O_RDWR, 0o644)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError as exc:
            log.debug("%s: no flock on this file system (%s)", self.path, exc)
            return False
        finally:
            os.close(fd)
            probe.unlink(missing_ok=True)
        return True

    def _text(self) -> str:
        import os

        return f"{os.getpid()}\n{utf8_text(str(self.model))}\n"

    def _take_by_pid(self) -> bool:
        """The lock without flock: True when taken; False to try again (a stale lock
        removed); an :class:`InputError` while its process runs (this one's included: two
        threads of one process are two runs)."""
        import os
        import threading

        tmp = self.path.with_name(f"{self.path.name}.{os.getpid()}.{threading.get_ident()}")
        tmp.write_text(self._text())
        try:
            try:
                os.link(tmp, self.path)  # the lock and its content in one step
                return True
            except FileExistsError:
                pass
            except OSError:  # no hard links here: create it exclusively, then write
                try:
                    fd = os.open(self.path, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
                except FileExistsError:
                    pass
                else:
                    with os.fdopen(fd, "w") as fh:
                        fh.write(self._text())
                    return True
        finally:
            tmp.unlink(missing_ok=True)
        try:
            text = self.path.read_text(errors="replace")
            age = time.time() - self.path.stat().st_mtime
        except FileNotFoundError:
            return False
        if not text and age < 2.0:  # being written (a file system without hard links
            # creates it, then writes it): wait for it; an empty one older is a crash's
            time.sleep(0.05)
            return False
        self._refuse(text, own_alive=True)
        # stale: move it aside, and put it back if it was not the one read (another run
        # took the folder meanwhile)
        grave = self.path.with_name(
            f"{self.path.name}.stale.{os.getpid()}.{threading.get_ident()}")  # fmt: skip
        try:
            os.rename(self.path, grave)
            if grave.read_text(errors="replace") != text:
                with contextlib.suppress(OSError):
                    os.link(grave, self.path)
        except FileNotFoundError:
            pass
        grave.unlink(missing_ok=True)
        return False

    def _refuse(self, text: str | None = None, held: bool = False,
                own_alive: bool = False) -> None:  # fmt: skip
        """Raise the error that names the run holding the lock (its process id and model
        file, as it wrote them, or ``text``); return if that process is gone (``held``:
        the operating system says the lock is held, so refuse whatever the file says, once
        it can be read). ``own_alive``: this process's id counts as a run."""
        import os

        if text is None:
            try:
                text = self.path.read_text(errors="replace")
            except FileNotFoundError:
                return
        lines = text.split("\n")
        pid = lines[0].strip() or "?"
        if not held and (not _alive(pid) or (pid == str(os.getpid()) and not own_alive)):
            return
        raise InputError(
            f"{self.path.parent}: another pfeie run (pid {pid}, model "
            f"{lines[1] if len(lines) > 1 and lines[1] else '?'}) writes to this output "
            "folder; wait for it to end, or choose another output.folder"
        ) from None

    def __exit__(self, *exc: object) -> None:
        import os

        try:
            self.path.unlink(missing_ok=True)
        except OSError as err:  # a folder made read-only during the run: the run's own
            # error (or its results) matter, not the lock file left behind
            log.warning("could not remove the lock file %s (%s); the next run into this "
                        "folder takes it over", self.path, err.strerror or err)  # fmt: skip
        finally:
            if self._fd is not None:
                os.close(self._fd)  # releases the lock
                self._fd = None


def _alive(pid: str) -> bool:
    """Whether the process of the decimal id ``pid`` runs (False for no number)."""
    import os

    if not pid.isdigit():
        return False
    try:
        os.kill(int(pid), 0)
    except (ProcessLookupError, OverflowError):
        return False
    except PermissionError:  # another user's process: it runs
        pass
    return True


#: bytes kept free on the output folder's disk besides the checkpoint's own: the
#: summaries, the envelope and the file's metadata as a stopped run is closed
DISK_FREE_MIN = 64 * 2**20
#: seconds between two looks at the free space (a statvfs call)
DISK_CHECK_S = 1.0


class DiskGuard:
    """Stops a run cleanly (:class:`RunStopped`, its checkpoint and rows kept, ``pfeie
    run --resume`` continues it) when the disk of its output folder runs short: HDF5 does
    not always say when a write fails for want of space (the chunks it caches are written
    later, and an error there is lost), and a run that goes on writing leaves rows never
    written, a checkpoint half written, or no file at all. The margin: ``free_min``
    (default :data:`DISK_FREE_MIN`) plus four checkpoints of ``n_dof`` (u, v, a, f, the
    auxiliary acceleration: five float64 vectors each), looked at every
    :data:`DISK_CHECK_S` seconds. ``then`` ends the message: what continues the run (by
    default ``pfeie run --resume --duration`` with ``duration``); ``what`` names what
    the margin is for. A ``spare`` file (the completed run that a re-run replaces, kept
    until the re-run completes) is deleted, with a warning, before the run is stopped
    for want of the space it holds."""

    def __init__(self, folder: Path, n_dof: int, duration: float, then: str | None = None,
                 free_min: int = DISK_FREE_MIN,
                 what: str = "a checkpoint and the summaries") -> None:  # fmt: skip
        self.folder = folder
        self.need = free_min + 4 * 5 * 8 * int(n_dof)
        self.then = then or f"`pfeie run --resume --duration {duration:g}` continues the run"
        self.what = what
        self.spare: Path | None = None
        self.tripped: str | None = None  # the message of the stop, once it stopped the run
        self._next = 0.0

    def short(self, *replaced: Path | None) -> str | None:
        """The message of a disk short of the margin now, or None; the files ``replaced``
        (those the run overwrites or may delete) count as free space."""
        try:
            free = shutil.disk_usage(self.folder).free
        except OSError:  # (a file system that does not say: nothing to guard)
            return None
        for p in replaced:
            with contextlib.suppress(OSError):
                free += p.stat().st_size if p is not None and p.is_file() else 0
        if free >= self.need:
            return None
        return (f"the disk of {utf8_text(str(self.folder))} has {free / 2**20:.0f} MiB free, "
                f"less than the {self.need / 2**20:.0f} MiB {self.what} need")  # fmt: skip

    def free_spare(self, why: str) -> bool:
        """Delete the spare file, if there is one, saying ``why``; whether it was."""
        spare, self.spare = self.spare, None
        if spare is None or not spare.is_file():
            return False
        try:
            spare.unlink()
        except OSError:
            return False
        log.warning("%s deleted: %s; it held the completed run that this run replaces", spare,
                    why)  # fmt: skip
        return True

    def stop_text(self, why: str) -> str:
        """The message of a stop for ``why`` (:meth:`short`'s), with what continues."""
        return f"{why}: free some space, then {self.then}"

    def check(self) -> None:
        """Raise :class:`RunStopped` when the disk is short (a look every
        :data:`DISK_CHECK_S` s at most), after deleting the spare file if there is one."""
        now = time.perf_counter()
        if now < self._next:
            return
        self._next = now + DISK_CHECK_S
        if (why := self.short()) is None:
            return
        if self.free_spare(why) and (why := self.short()) is None:
            return
        self.tripped = self.stop_text(why)
        raise RunStopped(self.tripped)


def _beyond_duration(job: Job, path: Path, duration: float | None) -> None:
    """A run in ``path`` whose checkpoint lies beyond the duration asked is not resumed:
    an :class:`InputError` before the file is touched (resumed, a stopped run's file read
    ``completed`` short of its own duration, and a completed run's summaries were
    written again for a duration its histories pass)."""
    t = resumable(path, job, completed=True)
    if t is None:
        return
    try:
        n = job.analysis.steps(job.duration if duration is None else duration)
    except ValueError:
        return  # (said by the run itself)
    if round(t / job.analysis.dt) > n:
        try:  # the duration the run was asked for (a run extended by --duration)
            with Results(path) as res:
                asked = json.loads(res.meta.get("model_spec", "{}"))["analysis"]["duration"]
        except (PfeieError, OSError, KeyError, TypeError, ValueError):
            asked = None
        own = f" (the run's own: --duration {asked:g})" if asked and asked > t else ""
        raise InputError(f"{path}: the run reached t = {t:.6g} s, beyond the duration "
                         f"asked ({n * job.analysis.dt:.6g} s): nothing to continue; "
                         f"expected --duration of at least {t:.6g} s{own} (the file is "
                         "left as it is)")  # fmt: skip


def _run(
    job: Job, out: Path, progress: bool, duration: float | None, stream: TextIO | None,
    resume: bool, checkpoint_s: float | None, resume_with: str,
) -> dict[str, Any]:  # fmt: skip
    a = job.analysis
    t0 = time.perf_counter()
    # the dynamic analysis first: a setting it refuses is an input error, found before work
    dyn = dynamic_analysis(job) if a.dynamic else None
    if resume and dyn is None:
        raise InputError(f"{job.path}: analysis: --resume continues a dynamic run; this "
                         "model file has none (analysis.dynamic = false)")  # fmt: skip
    ck: Checkpoint | None = None
    previous: Path | None = None  # a completed run replaced by this one, kept until its end
    if resume:
        _beyond_duration(job, out / "results.h5", duration)
        try:
            writer, ck = reopen_results(out / "results.h5", job)
            # the stop's summaries and ParaView files are written again at the end: a
            # resumed run killed before then must not leave them beside its longer rows
            for stale in STALE_OUTPUTS:
                (out / stale).unlink(missing_ok=True)
        except NothingToResume as exc:
            log.warning("%s; running from the start", exc)
            resume = False
    disk = DiskGuard(out, job.model.n_dof, job.duration if duration is None else duration,
                     then=f"{resume_with} continues the run")  # fmt: skip
    if ck is None:
        # a new run: the summaries and the report of a former run in this folder go (after a
        # failure they would stand beside the new results as if they were theirs)
        ResultsWriter.require()
        path = out / "results.h5"
        keep = True  # the completed run there, until this one completes, if there is room
        if disk.short() is not None:  # before anything in the folder changes
            stopped = resumable(path, job, same_inputs=False) is not None  # (moved aside)
            if (why := disk.short(None if stopped else path, out / PREVIOUS_RUN)) is not None:
                raise ResultsError(f"{job.path}: the run is not started: {why}: free some "
                                   "space")  # fmt: skip
            disk.spare = out / PREVIOUS_RUN  # (one a former re-run kept goes first)
            disk.free_spare("the disk is short")
            keep = disk.short() is None
        _keep_stopped_run(path, job)
        for stale in STALE_OUTPUTS:
            (out / stale).unlink(missing_ok=True)
        previous = _keep_completed_run(path) if keep else None
        writer = ResultsWriter(out / "results.h5", job, field_every=job.output.field_every)
    if previous is None and (out / PREVIOUS_RUN).is_file():
        previous = out / PREVIOUS_RUN  # kept by a re-run that did not complete (or resumed)
    disk.spare = previous
    try:
        summary = _steps(job, dyn, out, writer, ck, progress, duration, stream, checkpoint_s,
                         t0, disk, resume_with)  # fmt: skip
    except BaseException:
        _previous_kept(previous)
        raise
    if previous is not None and summary["stopped"] is None:  # replaced now
        previous.unlink(missing_ok=True)
    else:
        _previous_kept(previous)
    return summary


def _steps(
    job: Job, dyn: Dynamic | None, out: Path, writer: ResultsWriter, ck: Checkpoint | None,
    progress: bool, duration: float | None, stream: TextIO | None,
    checkpoint_s: float | None, t0: float, disk: DiskGuard, resume_with: str,
) -> dict[str, Any]:  # fmt: skip
    """The run of :func:`_run` once its results file is open: the static state, the
    searches, the time stepping and the summaries."""
    a = job.analysis
    model = job.model
    static: StaticResult | None = None
    yields: dict[str, dict[str, Any]] = {}
    reduction: dict[str, Any] = {}
    every_s = job.output.checkpoint_seconds if checkpoint_s is None else checkpoint_s
    ckw = CheckpointWriter(writer, run_key(job), every_s, job.output.checkpoint_steps,
                           job.part_factors)  # fmt: skip
    ystream = (stream or sys.stderr) if progress else None  # the yield search's progress
    settings = a.solver()
    try:
        if a.static and ck is None:
            static = solve_static(model, settings=settings)
            writer.write_static(static)
            log.info("static state solved in %.2f s", time.perf_counter() - t0)
        elif a.static:  # resumed: the static state again, for the summary and the uplift
            static = solve_static(model, settings=settings)
        if a.yield_coefficient or a.strength_reduction:  # (resumed too: the summary keeps them)
            # one static problem (factorisations, W) for both searches
            problem = StaticInterfaceProblem(model, model.system(), settings=settings)
            if a.yield_coefficient:
                yields = _yield_coefficients(job, problem, ystream)
            if a.strength_reduction:
                reduction = _strength_reduction(job, problem, ystream)
    except PfeieError as exc:
        writer.close(False, f"static analysis failed: {exc}")
        raise
    except KeyboardInterrupt as exc:
        writer.close(False, f"interrupted ({str(exc) or 'SIGINT'}) before the time stepping")
        raise
    result: DynamicResult | None = None
    final: StepState | None = None  # the last state of this process's steps
    stopped: str | None = None
    if dyn is not None:
        try:
            n = a.steps(job.duration if duration is None else duration)
        except ValueError as exc:
            writer.close(False, f"invalid duration: {exc}")
            raise InputError(f"{job.path}: duration: {exc}") from None
        first = 0
        if ck is not None:
            log.info("resuming at step %d (t = %.6g s) of %d", ck.state.step, ck.state.kin.t, n)
            first = ck.state.step
            if n < first:
                log.warning("%s: the run reached t = %.6g s (step %d), beyond the duration "
                            "%.6g s asked: nothing to continue; its results to t = %.6g s "
                            "are kept", out / "results.h5", ck.state.kin.t, first,
                            n * a.dt, ck.state.kin.t)  # fmt: skip
            else:  # the run goes on, to this job's duration
                writer.set_run(job)
            n = max(n - first, 0)
        flag: dict[str, str] = {}

        def on_signal(signum: int, _frame: Any) -> None:
            flag["why"] = signal.Signals(signum).name

        old = {s: signal.signal(s, on_signal) for s in (signal.SIGINT, signal.SIGTERM)}
        bar = Progress(first + n, a.dt, stream, first) if progress else None

        def callback(st: StepState) -> None:
            if bar is not None:
                bar(st)
            if flag:
                raise RunStopped(flag["why"])
            disk.check()

        try:
            # a resumed run starts from its checkpoint; the static state only gives it the
            # uplift of the pairs open there
            start = static if ck is None or model.uplifts else None
            result = dyn.run(n_steps=n, ground=job.records, form=a.form, start=start,
                             probes=list(job.probes.values()), every=job.output.every,
                             callback=callback, on_record=writer.append, resume=ck,
                             on_checkpoint=ckw, envelope=job.output.envelope)  # fmt: skip
        finally:
            for s, h in old.items():
                signal.signal(s, h)
        ckw.close()
        writer.write_envelope(result.envelope)
        if not result.completed:
            stopped = result.stop_reason or "stopped"
        final = result.final
        if ck is not None:  # the summary of the whole run, not of its resumed part
            result = history(writer, result.completed, result.stop_reason)
    try:
        summary = _run_summary(
            job,
            static,
            result,
            final,
            writer,
            stopped,
            t0,
            yield_coefficient=yields,
            strength_reduction=reduction,
        )
        writer.close(stopped is None, stopped, summary)
        if job.output.paraview and result is not None:
            write_paraview(out / "results.h5", model, out)
        _write_summaries(out, summary)
    except KeyboardInterrupt as exc:  # after the time stepping: results.h5 holds the run
        why = str(exc) or "SIGINT"
        if writer.f.id.valid:  # (not closed yet)
            writer.close(False, f"interrupted ({why}) after the time stepping")
        if stopped is not None and result is not None:  # a second signal after the first
            raise KeyboardInterrupt(
                f"{why}; the run had stopped at t = {float(result.t[-1]):.6g} s ({stopped}) "
                f"and results.h5 holds it to there; {resume_with} continues it"
            ) from None
        raise KeyboardInterrupt(
            f"{why}; the time stepping had finished and results.h5 holds the run; "
            f"{resume_with} writes the summary and the ParaView files"
        ) from None
    return summary


def _run_summary(
    job: Job, static: StaticResult | None, result: DynamicResult | None,
    final: StepState | None, writer: ResultsWriter, stopped: str | None, t0: float,
    **extra: dict[str, Any],
) -> dict[str, Any]:  # fmt: skip
    """The summary of a run (:func:`summarize`) with its post-earthquake static state
    (written to ``writer``), the non-empty ``extra`` entries (the limit searches), why it
    stopped, the reliability warnings as the text summary gives them (for the report and
    for readers of summary.json) and the wall time since ``t0``."""
    summary = summarize(job, static, result)
    post = _post_earthquake(job, static, result, final, writer, summary.get("bodies", {}))
    if post:
        summary["post_earthquake"] = post
    summary.update({k: v for k, v in extra.items() if v})
    summary["stopped"] = stopped
    summary["warnings"] = [{"label": w.label, "text": w.text} for w in reliability(summary)]
    summary["wall_time_s"] = round(time.perf_counter() - t0, 3)
    return summary


def _write_summaries(out: Path, summary: dict[str, Any]) -> None:
    """``summary.json`` (strict JSON) and ``summary.txt`` of a run into ``out``."""
    (out / "summary.json").write_text(
        json.dumps(summary, indent=2, default=str, allow_nan=False) + "\n"
    )
    # (UTF-8; a path that is not UTF-8 keeps its bytes as \xe9 escapes)
    (out / "summary.txt").write_text(format_summary(summary) + "\n", encoding="utf-8",
                                     errors="backslashreplace")  # fmt: skip


def run_to_folder(
    analysis: Dynamic, duration: float, folder: str | Path, *,
    ground: Sequence[GroundMotion] | GroundMotion | None = (), form: str = "relative",
    start: StaticResult | StepState | None = None,
    probes: Mapping[str, int] | Sequence[int] | None = None,
    every: int | None = None, field_every: int | None = None, envelope: bool | None = None,
    paraview: bool | None = None, figures: bool = True, title: str = "",
) -> DynamicResult:  # fmt: skip
    """Run ``analysis`` (a :class:`~pfeie.Dynamic`) for ``duration`` s under ``ground``
    and write what ``pfeie run`` writes of a model file into ``folder``: ``results.h5``
    (docs/results.md; the static state too when ``start`` is a static result or a step
    state that carries one, and the post-earthquake static state of a completed run with
    joints), ``summary.json`` and ``summary.txt``, the ParaView series (``paraview``;
    needs meshio) and the figures in ``folder/figures`` (``figures``; needs matplotlib;
    those of ``pfeie plot``). Returns the run's :class:`~pfeie.DynamicResult`, the same
    bits as ``analysis.run`` with the same arguments. ``probes`` names nodes (name → node
    index), or lists node indices (named ``node<i>``), whose histories are kept;
    ``every``, ``field_every``, ``envelope`` and ``paraview`` are the ``[output]`` keys
    of a model file, with their defaults (docs/model-file.md: 1, 10, true, true) where
    not given. The results file records ``<python>`` as its model file and, as its digest,
    the SHA-256 of what determines the run (:meth:`pfeie.io.Job.of_run`). ``pfeie plot``,
    ``pfeie export`` and ``pfeie report`` read the folder (the report without the model
    file's sections).

    Nothing in the folder changes before the run has checked its arguments and taken its
    first row; a stopped ``pfeie run`` there that ``--resume`` would continue is moved
    aside to ``results.stopped.h5``. A run whose step fails keeps its histories up to the
    last completed step (the file says why it stopped, ``completed`` false). Ctrl-C (in
    the main thread) stops the run at the end of a step, writes the files of what was
    computed and then raises :class:`KeyboardInterrupt`.

    >>> import pfeie as pf, tempfile
    >>> mesh = pf.rectangle(1.0, 1.0, nx=2, ny=2)
    >>> model = pf.Model(mesh, [pf.Block("all", pf.Elastic(E=1e9, nu=0.2, rho=2000))])
    >>> model.fix("ymin")
    >>> g = pf.GroundMotion.from_function(lambda t: 1.0, duration=0.05, dt=0.01)
    >>> with tempfile.TemporaryDirectory() as out:
    ...     res = pf.run_to_folder(pf.Dynamic(model, dt=0.01), 0.05, out, ground=[g],
    ...                            probes={"top": 8}, paraview=False, figures=False)
    ...     with pf.io.Results(f"{out}/results.h5") as f:
    ...         print(f.n_times, f.probe_names, f.meta["model_file"])
    6 ['top'] <python>
    """
    if not isinstance(analysis, Dynamic):
        raise ModelError(f"run_to_folder: analysis: expected a pfeie.Dynamic (e.g. "
                         f"pf.Dynamic(model, dt=0.01)), got {type(analysis).__name__}")  # fmt: skip
    static = start if isinstance(start, StaticResult) else None
    if isinstance(start, StepState) and isinstance(start.static, StaticResult):
        static = start.static
    if ground is None:
        ground = ()
    elif isinstance(ground, GroundMotion):
        ground = [ground]
    elif isinstance(ground, str | bytes | os.PathLike) or not isinstance(ground, Iterable):
        raise ModelError("ground: expected a pfeie.GroundMotion or a list of them (a file "
                         f"is read with pfeie.io.read_record), got {type(ground).__name__} "
                         f"{ground!r}")  # fmt: skip
    else:  # (a generator is read once: listed first, or the check would use it up)
        ground = list(ground)
    if not all(isinstance(g, GroundMotion) for g in ground):
        raise ModelError("ground: expected a list of pfeie.GroundMotion records (e.g. "
                         "pfeie.io.read_record), got "
                         f"{[type(g).__name__ for g in ground]}")  # fmt: skip
    names = _probe_names(probes, analysis.model.mesh.n_points)
    given = {"every": every, "field_every": field_every, "envelope": envelope,
             "paraview": paraview}  # fmt: skip
    output = {**{k: v for k, v in given.items() if v is not None}, "folder": "."}
    job = Job.of_run(analysis.model, analysis.settings, records=ground, probes=names,
                     duration=duration, form=form, static=static is not None, title=title,
                     output=output, system=analysis.system, start=start)  # fmt: skip
    # the [output] defaults of the schema where not given
    every, field_every = job.output.every, job.output.field_every
    envelope, paraview = job.output.envelope, job.output.paraview
    ResultsWriter.require()  # before the folder is touched (or made)
    out = output_folder(folder, "run_to_folder: folder")
    if (why := study_outputs(out)) is not None:
        raise InputError(f"run_to_folder: folder: {out} holds the outputs of a study "
                         f"({why}): choose another folder")  # fmt: skip
    path = out / "results.h5"
    opened: list[ResultsWriter] = []

    def on_record(row: dict[str, Any]) -> None:
        # the folder is touched at the first row, once the run has accepted its inputs
        if not opened:
            for stale in STALE_OUTPUTS:
                (out / stale).unlink(missing_ok=True)
            for png in (out / "figures").glob("*.png") if figures else ():
                png.unlink(missing_ok=True)  # (the figures this function writes there)
            _keep_stopped_model_run(path)
            opened.append(ResultsWriter(path, job, field_every=field_every))
            if static is not None:
                opened[0].write_static(static)
        opened[0].append(row)

    flag: dict[str, str] = {}

    def on_signal(signum: int, _frame: Any) -> None:
        flag["why"] = signal.Signals(signum).name

    disk = DiskGuard(out, analysis.model.n_dof, duration,
                     then="run it again (results.h5 holds it to where it stopped)")  # fmt: skip

    def callback(_st: StepState) -> None:
        if flag:
            raise RunStopped(flag["why"])
        disk.check()

    main = threading.current_thread() is threading.main_thread()
    with FolderLock(out, job.path):
        t0 = time.perf_counter()
        old = signal.signal(signal.SIGINT, on_signal) if main else None
        try:
            result = analysis.run(duration, ground=ground, form=form, start=start,
                                  probes=list(job.probes.values()), every=every,
                                  on_record=on_record, callback=callback,
                                  envelope=envelope)  # fmt: skip
        except BaseException as exc:
            if opened:
                opened[0].close(False, f"the run failed: {exc}")
            raise
        finally:
            if old is not None:
                signal.signal(signal.SIGINT, old)
        writer = opened[0]
        try:
            writer.write_envelope(result.envelope)
            stopped = None if result.completed else (result.stop_reason or "stopped")
            summary = _run_summary(job, static, result, result.final, writer, stopped, t0)
            writer.close(stopped is None, stopped, summary)
        except BaseException as exc:
            if writer.f.id.valid:  # the histories stay readable
                writer.close(False, f"interrupted after the time stepping ({exc!r})")
            raise
        _write_summaries(out, summary)
        # what needs an optional library (meshio, matplotlib) comes last and warns where
        # it is missing: the run and its results file are not lost to it
        try:
            if paraview:
                write_paraview(path, analysis.model, out)
        except PfeieError as exc:
            log.warning("%s: ParaView series not written: %s", out, exc)
        try:
            if figures:
                plot_run(path, out / "figures")
        except PfeieError as exc:
            log.warning("%s: figures not written: %s", out, exc)
    if flag:
        raise KeyboardInterrupt(f"{flag['why']}: the run stopped at t = {result.t[-1]:.6g} s; "
                                f"{path} holds it to there")  # fmt: skip
    if disk.tripped is not None:
        log.warning("%s: the run stopped at t = %.6g s: %s", path, float(result.t[-1]),
                    disk.tripped)  # fmt: skip
    return result


def _probe_names(probes: Mapping[str, int] | Sequence[int] | None, n_nodes: int) -> dict[str, int]:
    """The probes of :func:`run_to_folder` as name → node: a mapping as given, a sequence
    of node indices named ``node<i>``; checked (node indices in [0, n_nodes))."""
    if probes is None:
        return {}
    if isinstance(probes, Mapping):
        names = dict(probes)
    elif isinstance(probes, Sequence | np.ndarray) and not isinstance(probes, str | bytes):
        names = {f"node{int(n)}" if isinstance(n, int | np.integer) else str(n): n
                 for n in probes}  # fmt: skip
    else:
        raise ModelError(f"probes: expected a mapping of names to node indices or a list of "
                         f"node indices, got {type(probes).__name__}")  # fmt: skip
    for name, node in names.items():
        if isinstance(node, bool) or not isinstance(node, int | np.integer) or not (
                0 <= int(node) < n_nodes):  # fmt: skip
            raise ModelError(f"probes: {name!r}: expected a node index in [0, {n_nodes}), "
                             f"got {node!r}")  # fmt: skip
    return {str(k): int(v) for k, v in names.items()}


def _keep_stopped_model_run(path: Path) -> None:
    """A stopped ``pfeie run`` in ``path`` (its model file's, not completed: ``--resume``
    continues it) is moved aside to ``results.stopped.h5`` (``.1``, … if taken) before a
    Python run writes there, with a warning."""
    if not path.is_file():
        return
    try:
        with Results(path) as res:
            meta = res.meta
            if meta.get("model_file") == PYTHON_RUN or res.completed:
                return
    except (PfeieError, OSError):
        return  # not a results file: overwritten, as by `pfeie run`
    keep = _move_aside(path)
    log.warning("%s held a stopped run of %s, which `pfeie run --resume` continues; it is "
                "kept as %s (move it back to results.h5 to resume it)", path,
                meta.get("model_file"), keep.name)  # fmt: skip


def _move_aside(path: Path) -> Path:
    """Rename the results file ``path`` to ``results.stopped.h5`` beside it (``.1``,
    ``.2``, … if taken); returns the new path."""
    keep = path.with_name("results.stopped.h5")
    k = 0
    while keep.exists():
        k += 1
        keep = path.with_name(f"results.stopped.{k}.h5")
    path.rename(keep)
    return keep


PREVIOUS_RUN = "results.previous.h5"


def _keep_completed_run(path: Path) -> Path | None:
    """A completed run in ``path`` is moved to ``results.previous.h5`` beside it (an older
    one there goes) while a new run starts in its folder; the new run deletes it once it
    completes, so that a re-run stopped or failed before its end loses nothing computed.
    Returns the kept file, or None (no completed run there)."""
    keep = path.with_name(PREVIOUS_RUN)
    if not path.is_file():
        return None
    try:
        with Results(path) as res:
            if not res.completed:
                return None
    except (PfeieError, OSError):
        return None  # not a results file, or one that does not open: overwritten
    try:
        path.replace(keep)
    except OSError as exc:  # (a folder of that name, a file not writable)
        log.warning("%s: the completed run there cannot be kept as %s (%s): this run "
                    "overwrites it", path, keep.name, exc.strerror or exc)  # fmt: skip
        return None
    log.info("%s: the completed run there is kept as %s until this run completes", path,
             keep.name)  # fmt: skip
    return keep


def _previous_kept(previous: Path | None) -> None:
    """Say where the completed run that a run which did not complete was to replace is."""
    if previous is not None and previous.is_file():
        log.warning("%s holds the completed run that this run was to replace; move it back "
                    "to results.h5 to keep it (`pfeie plot`, `report` and `export` read it "
                    "where it is, with --out or --csv in another folder)", previous)  # fmt: skip


def _keep_stopped_run(path: Path, job: Job) -> None:
    """A stopped run in ``path`` that ``--resume`` would continue, of these inputs or of
    others (a resume refused for a changed key, then a run without ``--resume``), is not
    overwritten by a run from the start: it is moved beside it, to
    ``results.stopped.h5`` (``.1``, ``.2``, … if taken), with a warning saying so."""
    t = resumable(path, job)
    if t is not None:
        keep = _move_aside(path)
        log.warning("%s held this model's run, stopped at t = %.6g s, which `pfeie run "
                    "--resume` continues; this run starts again from t = 0, and that one is "
                    "kept as %s (move it back to results.h5 to resume it)", path, t,
                    keep.name)  # fmt: skip
    elif (t := resumable(path, job, same_inputs=False)) is not None:
        keep = _move_aside(path)
        log.warning("%s held a stopped run of other inputs (stopped at t = %.6g s), which "
                    "`pfeie run --resume` with its own inputs continues; it is kept as %s "
                    "(move it back to results.h5 to resume it)", path, t,
                    keep.name)  # fmt: skip


def dynamic_analysis(job: Job) -> Dynamic:
    """The dynamic analysis of a job, built from the :class:`DynamicSettings` part of its
    ``[analysis]`` table (so ``alpha`` alone runs HHT-α: β and γ are derived from it by
    :meth:`~pfeie.dynamics.DynamicSettings.newmark` unless given). The records are the
    run's (:func:`run_job`)."""
    a = job.analysis
    settings = DynamicSettings.model_validate(
        a.model_dump(include=set(DynamicSettings.model_fields))
    )
    try:
        return Dynamic(job.model, settings=settings)
    except ModelError as exc:
        raise InputError(f"{job.path}: analysis: {exc}") from None


def _yield_coefficients(
    job: Job, problem: StaticInterfaceProblem, stream: TextIO | None = None
) -> dict[str, dict[str, Any]]:
    """The yield coefficient along +x and −x, or the directions listed, each made
    horizontal (``analysis.yield_coefficient``; :func:`pfeie.yield_coefficient`), on the
    model's static ``problem`` for all: per direction its
    unit vector, ``k_y`` (the last coefficient held, None if held up to the largest tried),
    ``k_affine`` (the margins' affine root from the last two held), ``k_fail``, ``limit``,
    the governing ``joint`` and its safety factor at k_y, and the analyses it took. With a
    ``stream``, a line on it as each direction starts and ends (the search takes tens of
    static analyses)."""
    model = job.model
    out: dict[str, dict[str, Any]] = {}
    asked = job.analysis.yield_coefficient
    wanted: list[str | list[float]] = ["+x", "-x"] if asked is True else list(asked or [])
    for given in wanted:
        label = yield_label(given)
        t0 = time.perf_counter()
        if stream is not None:
            stream.write(f"yield coefficient {label}: static analyses ...\n")
            stream.flush()
        try:
            if isinstance(given, str):
                sign, axis = (1.0 if given[0] == "+" else -1.0), "xy".index(given[1])
                _, iota = horizontal(model, axis=axis)
                iota = sign * iota
            else:
                _, iota = horizontal(model, direction=given)
            y = yield_coefficient(model, iota, problem=problem)
        except ModelError as exc:
            raise InputError(f"{job.path}: analysis.yield_coefficient: {exc}") from None
        out[label] = {
            "direction": [round(float(v), 12) + 0.0 for v in y.direction],
            "k_y": y.k_y, "k_affine": y.k_affine, "k_fail": y.k_fail, "limit": y.limit,
            "k_rigid": y.k_rigid, "k_translation": y.k_translation,
            "junction_share": y.junction_share, "joint": y.joint,
            "safety_factor": None if y.joint is None else y.safety_factors[y.joint],
            # every joint's FS at k_y (None: no shear)
            "safety_factors": {n: (float(f) if np.isfinite(f) else None)
                               for n, f in y.safety_factors.items()},
            "analyses": y.analyses, "k_max": YIELD_K_MAX, **_most_open(model, y.static),
        }  # fmt: skip
        if stream is not None:  # (the library logs it at INFO too)
            k_y = f"none up to {YIELD_K_MAX:g}" if y.k_y is None else f"{y.k_y:.6g}"
            stream.write(f"yield coefficient {label}: k_y {k_y} ({y.limit}), {y.analyses} "
                         f"static analyses in {time.perf_counter() - t0:.1f} s\n")  # fmt: skip
            stream.flush()
    return out


def _compression_text(j: dict[str, Any], per: str) -> str:
    """A static joint's compression, resultant and crack for the summary text."""
    out = f", in contact {100 * j['contact_share']:.0f} %"
    if j.get("mean_contact_stress_Pa") is not None:
        out += f" (mean {j['mean_contact_stress_Pa'] / 1e6:.3g} MPa there)"
    at = j.get("normal_resultant_at_m")
    if at is not None:
        out += ", normal resultant at (" + ", ".join(f"{v:.4g}" for v in at) + ") m"
    if "uplift_force_N" in j:
        out += f", uplift {j['uplift_force_N'] / 1e3:.4g} kN"
    if "crack_m" in j:
        crack = f"crack at full uplift {j['crack_m']:.2f} m" if j["crack_m"] > 0 else "no crack"
        out += f", {crack} (normal: effective, the uplift apart)"
    elif "uplift_force_N" in j:
        out += " (normal: effective, the uplift apart)"
    return out + (f"; forces{per}" if per else "")


def _junction_text(result: dict[str, Any]) -> str:
    """The summary's caveat of a limit search (summary.json's ``yield_coefficient`` item or
    ``strength_reduction``) whose governing joint leans on its pairs at junctions."""
    share = result.get("junction_share")
    if share is None:
        return ""
    return (
        f"; but {result['joint']!r} leans on its pairs at junctions ({100 * share:.0f} % "
        "of its normal force at a block's corner where joints meet), whose friction "
        "grows as the mesh is refined: refine it and compare"
    )


def _strength_reduction(
    job: Job, problem: StaticInterfaceProblem, stream: TextIO | None = None
) -> dict[str, Any]:
    """The factor of safety by strength reduction (``analysis.strength_reduction``;
    :func:`pfeie.strength_reduction`, on the model's static ``problem``): ``factor`` (the
    largest held, None if held up to ``f_max``), ``factor_fail``, ``limit``, the governing
    ``joint``, each joint's safety factor under the reduced strengths and the analyses it
    took. With a ``stream``, a
    line on it as it starts and ends."""
    t0 = time.perf_counter()
    if stream is not None:
        stream.write("strength reduction: static analyses ...\n")
        stream.flush()
    r = strength_reduction(job.model, problem=problem)
    out = {
        "factor": r.factor, "factor_fail": r.factor_fail, "limit": r.limit, "joint": r.joint,
        "rigid_factor": r.rigid_factor, "translation_factor": r.translation_factor,
        "junction_share": r.junction_share,
        "safety_factors": {n: (f if np.isfinite(f) else None)
                           for n, f in r.safety_factors.items()},
        "analyses": r.analyses, "f_max": REDUCTION_F_MAX, **_most_open(job.model, r.static),
    }  # fmt: skip
    lost = _open_cohesion(job.model, r.static)
    if lost:
        out["open_cohesion"] = lost
    if stream is not None:
        f = (f"held up to F = {REDUCTION_F_MAX:g}" if r.factor is None
             else f"F {r.factor:.4g} ({r.limit})")  # fmt: skip
        stream.write(f"strength reduction: {f}, {r.analyses} static analyses in "
                     f"{time.perf_counter() - t0:.1f} s\n")  # fmt: skip
        stream.flush()
    return out


def _most_open(model: Model, st: StaticResult) -> dict[str, Any]:
    """The joint with the largest open share of its area in the static state ``st`` (at a
    yield coefficient: the joint that opens, where a block rocks or overturns on it), as
    ``open_joint`` and ``open_share``; empty where no pair is open by more than
    :data:`~pfeie.interface.OPEN_CRACK_MIN_M` (the summary's open share)."""
    P, S = model.pairs, st.pairs
    if P is None or S is None:
        return {}
    # open as in the summary's joint lines: by more than OPEN_CRACK_MIN_M
    opened = ((S.state == OPEN) & (S.s[:, -1] > OPEN_CRACK_MIN_M)).astype(float) * P.area
    shares = {n: float(opened[P.of(n)].sum() / P.area[P.of(n)].sum()) for n in P.names}
    name = max(shares, key=lambda n: shares[n])
    return {"open_joint": name, "open_share": shares[name]} if shares[name] > 0 else {}


def _open_cohesion(model: Model, st: StaticResult | None) -> dict[str, dict[str, float]]:
    """Per joint with cohesion, where pairs are open at the limit ``st`` (by any opening:
    an open pair carries no force, so its c A is lost, however small the gap): the share
    of the joint's cohesive capacity Σ c A that they hold (``share``) and their largest
    opening (``max_opening_m``). Why an elastic strength reduction can fall below the
    rigid-block factor with cohesion: a wedge whose corner pairs part by a micrometre."""
    P = model.pairs
    S = None if st is None else st.pairs
    if P is None or S is None:
        return {}
    c = model.pair_laws.strength(S.broken, S.path)[0]  # c A (N)
    is_open = S.state == OPEN
    out = {}
    for n in P.names:
        idx = P.of(n)
        total = float(c[idx].sum())
        lost = is_open[idx] & (c[idx] > 0)
        if total > 0 and lost.any():
            out[n] = {"share": float(c[idx][lost].sum() / total),
                      "max_opening_m": float(S.s[idx][lost, -1].max())}  # fmt: skip
    return out


#: the share of a joint's area open at a limit from which the summary says that the block
#: on it rocks or overturns (most of its base lifted)
ROCKING_OPEN_SHARE = 0.5


def _open_text(y: dict[str, Any]) -> str:
    """The most open joint at a yield coefficient, for the summary's yield line ("" when
    no joint is open): its open share, and from :data:`ROCKING_OPEN_SHARE` on that the
    block on it rocks or overturns (the open joint may be the one at its least FS)."""
    joint, share = y.get("open_joint"), y.get("open_share")
    if joint is None or share is None:
        return ""
    out = f"; at k_y {joint!r} is the most open, {100 * share:.0f} % of its area"
    if share >= ROCKING_OPEN_SHARE:
        out += ": the block on it rocks or overturns"
    return out


def _least_fs(y: dict[str, Any]) -> str:
    """The least joint FS at k_y of a yield search's summary entry, and the joint whose
    margin the search followed where it is another (its FS beside)."""
    if "safety_factors" not in y:  # (summaries before version 0.3.16: the joint's own)
        f = y.get("safety_factor")
        return f"least FS {'∞' if f is None else f'{f:.4g}'} on {y.get('joint')!r}"
    finite = {n: f for n, f in y["safety_factors"].items() if f is not None}
    least = min(finite, key=finite.__getitem__) if finite else None
    text = f"least FS {finite[least]:.4g} on {least!r}" if least else "least FS ∞"
    if y.get("joint") is not None and y["joint"] != least:
        f = y.get("safety_factor")
        text += (f" (the margins followed {y['joint']!r}, FS "
                 f"{'∞' if f is None else f'{f:.4g}'})")  # fmt: skip
    return text


def _reduction_text(sr: dict[str, Any]) -> str:
    """The summary's line of the factor of safety by strength reduction."""
    if sr["factor"] is None:
        why = ("; no joint carries shear under the static loads"
               if all(f is None for f in sr["safety_factors"].values()) else "")  # fmt: skip
        return (f"FS > {sr.get('f_max', REDUCTION_F_MAX):g} by strength reduction (held with "
                f"the joints' strengths divided by the largest factor tried{why})")  # fmt: skip
    fs = ", ".join(f"{n} {'∞' if f is None else f'{f:.3g}'}"
                   for n, f in sr["safety_factors"].items())  # fmt: skip
    lost = "".join(
        f"; cohesion lost on open pairs: {n!r} {100 * v['share']:.2g} % of its c·A (openings "
        f"up to {_length_text(v['max_opening_m'])})" for n, v in sr.get("open_cohesion", {}).items()
    )  # fmt: skip
    if sr["limit"] == "sliding":
        what = (f"FS {sr['factor']:.4g} by strength reduction (sliding on {sr['joint']!r}; "
                f"joint FS with the strengths / {sr['factor']:.4g}: {fs}")  # fmt: skip
        if sr.get("open_joint"):  # a block that also lifts on its joint at the limit
            what += (f"; {sr['open_joint']!r} is open over {100 * sr['open_share']:.0f} % of "
                     "its area there")  # fmt: skip
        return what + lost + ")"
    what = (f"FS {sr['factor']:.4g} by strength reduction ({sr['limit']} beyond it, not a "
            "sliding limit: a joint breaking through, opening or rocking, or the pair solver "
            f"failing short of the limit; joint FS with the strengths / {sr['factor']:.4g}: "
            f"{fs}")  # fmt: skip
    if sr.get("open_joint"):
        what += (f"; {sr['open_joint']!r} is the most open, {100 * sr['open_share']:.0f} % "
                 "of its area")  # fmt: skip
    rigid = sr.get("rigid_factor")
    ft = sr.get("translation_factor")
    pinched = ft is not None and sr["factor"] > ft * (1 + YIELD_RIGID_GAP)  # (said after)
    if rigid is not None and rigid > sr["factor"] * (1 + YIELD_RIGID_GAP) and not pinched:
        what += (f"; the rigid blocks' factor is {rigid:.4g} (limit equilibrium, an upper "
                 f"bound): the factor lies between {sr['factor']:.4g} and {rigid:.4g}")  # fmt: skip
    return what + lost + ")"


def _length_text(w: float) -> str:
    """A small length for a message: µm below a millimetre, else mm."""
    return f"{w * 1e6:.2g} µm" if w < 1e-3 else f"{w * 1e3:.3g} mm"


def energy_shares(s: dict[str, Any]) -> tuple[float, float, float]:
    """Of a run's summary: the energy the position corrections stored over the input
    (signed), the energy the time scheme created over the energy that went through the
    run (≥ 0), and the energy it dissipated over the input (≥ 0); 0 where those flows lie
    below :data:`ENERGY_FLOOR` × the static strain energy, the scale of their round-off.
    The summary's "corrections" and "scheme" lines and a study's ``energy.*`` columns
    judge these."""
    e = s.get("energy_J") or {}
    work, corr = abs(e.get("external_work", 0.0)), e.get("correction", 0.0)
    alg = e.get("algorithmic", 0.0)
    flow = max(work, sum(e.get(k, 0.0) for k in ("interface", "impact", "damping")))
    floor = ENERGY_FLOOR * s.get("static_strain_energy_J", 0.0)
    share = corr / work if work > floor else 0.0
    created = -alg / flow if flow > floor and alg < 0 else 0.0
    dissipated = alg / work if work > floor and alg > 0 else 0.0
    return share, created, dissipated


def damped_by_scheme(s: dict[str, Any]) -> bool:
    """Whether a run's summary says that the time scheme damped it: it dissipated more
    than :data:`SCHEME_DISSIPATED` of the input while the joints took more than
    :data:`CONTACT_ACTIVITY` of it (the "scheme" line of the summary and of a study)."""
    e = s.get("energy_J") or {}
    work = abs(e.get("external_work", 0.0))
    contact = e.get("interface", 0.0) + e.get("impact", 0.0)
    return energy_shares(s)[2] > SCHEME_DISSIPATED and contact > CONTACT_ACTIVITY * work


@dataclass(frozen=True)
class RunWarning:
    """A warning on the reliability of a run's results: ``label`` the summary line's
    label ("large slip", "scheme", "corrections"), ``text`` the summary's wording (lines
    after the first indented to its column), ``short`` a study table's one-line form."""

    label: str
    text: str
    short: str


def reliability(s: dict[str, Any]) -> list[RunWarning]:
    """The reliability warnings of a run's summary, in the order the text summary gives
    them: a joint whose slip passes :data:`LARGE_SLIP` × the spacing of its pairs; the
    scheme's dissipation (:func:`damped_by_scheme`) and created energy
    (:data:`SCHEME_CREATED`); the position corrections' energy (:data:`CORRECTION_SHARE`,
    "not converged" beyond :data:`CORRECTION_UNRESOLVED`). ``pfeie run``'s summary and a
    study's ``warnings`` column are both written from it."""
    out = []
    for what in s.get("static_far_moved", []):
        out.append(
            RunWarning(
                "static",
                f"the static state: {what}, beyond the small displacements that the analysis "
                f"takes (up to {100 * STATIC_MOVE_MAX:g} % of the joint's length): a joint "
                "stiffness in the wrong unit? (normal_stiffness and shear_stiffness in Pa/m); "
                "the results are not reliable",
                f"static: {what}: beyond small displacements, check the stiffness units",
            )
        )
    for name, j in s.get("static_joints", {}).items():
        if "junction_share" not in j:
            continue
        share, area = 100 * j["junction_share"], 100 * j["junction_area_share"]
        out.append(
            RunWarning(
                "static",
                f"the static state: joint {name!r} leans on its pairs at junctions, a "
                f"block's corner where joints meet ({share:.0f} % of its normal force on "
                f"{area:.1f} % of its area): the node-to-node friction there has no area to "
                "bound it and grows as the mesh is refined (a row of three columns that "
                "limit equilibrium has toppling, F = 0.61, held at F = 1 by it); the "
                "equilibrium may hold only by that corner friction: refine the mesh and "
                "compare, or give the joint's end facets a frictionless joint "
                "(docs/theory.md, 'Two safety factors')",
                f"static: {name!r} leans on its pairs at junctions ({share:.0f} % of its "
                "normal force): refine the mesh and compare",
            )
        )
    # a summary written before the key (before version 0.3.12) is read as undamped
    beta = float((s.get("damping") or {}).get("beta_s", 0.0))
    for name, b in s.get("bodies", {}).items():
        if not b.get("airborne_rows"):
            continue
        head = (f"block {name} lost contact with all its joints at {b['airborne_rows']} "
                f"recorded time(s), first at {b['first_airborne_s']:.3f} s. A record seldom "
                "throws a block (a vertical acceleration beyond g; on a plane dipping ψ, a "
                "horizontal one beyond g cot ψ); ")  # fmt: skip
        short = (f"airborne: block {name} lost contact with all its joints (first at "
                 f"{b['first_airborne_s']:.3g} s)")  # fmt: skip
        if beta > 0:  # damped: rocking and impacts of the model, or a coarse step
            out.append(RunWarning(
                "airborne", head + "here the blocks' modes are damped (β = "
                f"{beta:.3g} s): a block that rocks or bounces off its joints (impacts), "
                "or a step too coarse for the impacts; compare two Δt, and for a block "
                "that rocks take analysis.scheme = \"moreau-jean\" with large_rotation = "
                "true (docs/theory.md)",
                short + ": rocking or impacts? compare two Δt"))  # fmt: skip
        else:
            out.append(RunWarning(
                "airborne", head + "an elastic block without stiffness-proportional damping "
                "can be thrown by its own friction-excited vibration, which grows as Δt "
                "falls (docs/results.md): add damping ([damping] beta) or take "
                "analysis.scheme = \"moreau-jean\", and compare two Δt",
                short + ": friction-excited vibration? add damping"))  # fmt: skip
    for name, b in s.get("bodies", {}).items():
        if "beyond_pairs_s" not in b:
            continue
        what = (
            f"block {name} turned by up to {b['peak_rotation_deg']:.3g}° and moved up to "
            f"{b['peak_displacement_m']:.3g} m ({b['size_m']:.3g} m across), past "
            f"{LARGE_TURN_DEG:g}° or half its size first at {b['beyond_pairs_s']:.3f} s"
        )
        out.append(RunWarning(
            "large motion",
            f"{what}: it toppled or left its joints? The joints pair the faces' nodes as "
            "meshed (small sliding, no contact search), so a block that topples or leaves "
            "its joint passes through the blocks it meets: the results from that time on "
            "are not reliable (docs/results.md)",
            f"large motion: {what}: toppled or left its joints, not followed by the "
            "node-to-node pairs"))  # fmt: skip
    for name, b in s.get("bodies", {}).items():
        if "small_rotation_beyond_s" not in b or "beyond_pairs_s" in b:
            continue
        what = (
            f"block {name} turned by up to {b['peak_rotation_deg']:.3g}° (past "
            f"{SMALL_TURN_DEG:g}° first at {b['small_rotation_beyond_s']:.3f} s)"
        )
        out.append(RunWarning(
            "rotation",
            f"{what} with small rotations (analysis.large_rotation = false): the pairs' "
            "frames and the blocks' lever arms stay as meshed, an error of the order of "
            "the rotation against the angles that matter (a slender block rocking on its "
            "corner: the rotation against its slenderness, atan(width/height)); take "
            "analysis.large_rotation = true for a block that rocks or topples "
            "(docs/theory.md, large rotations)",
            f"rotation: {what}, small-rotation run: take analysis.large_rotation = "
            "true"))  # fmt: skip
    for name, j in s.get("joints", {}).items():
        ratio = j.get("peak_slip_to_spacing", 0.0)
        if ratio > LARGE_SLIP:
            spacing = j.get("pair_spacing_m", 0.0)
            out.append(RunWarning(
                "large slip",
                f"joint {name}: the slip reaches {ratio:.2g} × the spacing of its pairs "
                f"({spacing:.3g} m); the faces are paired node to node (small sliding), so "
                "past half a spacing the result is not reliable (docs/results.md)",
                f"large slip: joint {name}'s slip reaches {ratio:.2g} × the spacing of its "
                f"pairs ({spacing:.3g} m), beyond {LARGE_SLIP:g}: its faces are paired node "
                "to node (small sliding), the result is not reliable"))  # fmt: skip
    e = s.get("energy_J")
    if e is None:
        return out
    share, created, dissipated = energy_shares(s)
    if damped_by_scheme(s):
        out.append(RunWarning(
            "scheme",
            f"WARNING: the time scheme dissipated {e['algorithmic']:.4g} J, "
            f"{100 * dissipated:.0f} % of the input: numerical damping of contact events "
            "(impacts, stick and slip) and of modes that this time step does not resolve; "
            "the slips, openings and peaks are damped by the scheme and not converged in "
            "Δt: run again with Δt halved and compare (docs/results.md)",
            f"scheme: the time scheme dissipated {100 * dissipated:.0f} % of the input: "
            "damped by the scheme, not converged in Δt, halve Δt"))  # fmt: skip
    if created > SCHEME_CREATED:
        out.append(RunWarning(
            "scheme",
            f"WARNING: the time scheme created {-e['algorithmic']:.4g} J, "
            f"{100 * created:.0f} % of the energy that went through the run: contact events "
            "(impacts, stick and slip) that this time step does not resolve; the slips and "
            "displacements are not converged in Δt: run again with Δt halved and compare "
            "(docs/results.md)",
            f"scheme: the time scheme created {100 * created:.0f} % of the energy through "
            "the run: not converged in Δt, halve Δt"))  # fmt: skip
    if abs(share) > CORRECTION_SHARE:
        corr = e["correction"]
        verb = "added" if share > 0 else "took"
        unresolved = abs(share) > CORRECTION_UNRESOLVED
        out.append(RunWarning(
            "corrections",
            f"the position corrections of penetrating pairs {verb} {abs(corr):.4g} J, "
            f"{100 * abs(share):.1f} % of the input: impacts this time step does not "
            "resolve (the share falls with Δt; docs/results.md)"
            + (f"\nmore than {100 * CORRECTION_UNRESOLVED:.0f} % of the input: the results "
               "are not converged in Δt; run again with Δt halved and compare (for drops, "
               "rockfall and rocking impacts, analysis.scheme = \"moreau-jean\"; docs/theory.md, "
               "'Drops and bounces')"
               if unresolved else ""),
            f"corrections: the position corrections of penetrating pairs {verb} "
            f"{100 * abs(share):.1f} % of the input energy, impacts this Δt does not resolve"
            + (f" (more than {100 * CORRECTION_UNRESOLVED:.0f} %: not converged in Δt, halve "
               "Δt)" if unresolved else "")))  # fmt: skip
    return out


def _warning_lines(warnings: list[RunWarning], label: str) -> list[str]:
    """The summary's lines of the warnings ``label``: the label in the first line's
    column, the text's further lines indented to it."""
    lines = []
    for w in warnings:
        if w.label == label:
            first, *rest = w.text.split("\n")
            lines.append(f"  {w.label:<12} {first}")
            lines += [f"  {'':<12} {line}" for line in rest]
    return lines


def _post_earthquake(
    job: Job, static: StaticResult | None, result: DynamicResult | None,
    final: StepState | None, writer: ResultsWriter, bodies: dict[str, dict[str, Any]],
) -> dict[str, Any]:  # fmt: skip
    """The post-earthquake static state of a completed run with joints
    (:func:`~pfeie.solve_static` with the last pair state ``final`` as its ``damage``; a
    resumed run's own last state), written to
    the results' ``post_earthquake`` group: per joint its sliding safety factor and forces
    (as the static state's), the broken share, and each uplift's crack; or, where no
    static equilibrium holds the blocks after the record, ``error`` says why; or, where a
    floating block ended far from where it started (beyond
    :data:`POST_EQ_ROTATION_MAX_DEG` or :data:`POST_EQ_MOVE_MAX` of its size), ``skipped``
    says why: the static state of the undeformed geometry would describe blocks that are
    no longer there (a new user's column that toppled, 123° and 4.25 m, read FS ∞ on its
    joint). ``bodies``: the summary's body motions (:func:`_body_motions`)."""
    model = job.model
    if (not job.analysis.post_earthquake or static is None or result is None
            or not result.completed or final is None or model.pairs is None):  # fmt: skip
        return {}
    # the blocks' motion from the undeformed geometry, relative to the ground: a run
    # started from another run's final state has moved since before its own row 0
    moved = _far_moved(model, _total_motions(job, result) or bodies)
    if moved:
        why = (f"{'; '.join(moved)}: the post-earthquake static state takes the undeformed "
               "geometry, which holds where the residual motions are small beside the "
               f"blocks (a rotation up to {POST_EQ_ROTATION_MAX_DEG:g}°, a displacement up "
               f"to {100 * POST_EQ_MOVE_MAX:g} % of the block's size)")  # fmt: skip
        log.warning("post-earthquake static state not computed: %s", why)
        return {"skipped": why}
    t0 = time.perf_counter()
    try:
        post = solve_static(model, settings=job.analysis.solver(),
                            damage=final.pairs)  # fmt: skip
    except (MechanismError, InterfaceError, SolverError) as exc:
        log.warning("post-earthquake static state: %s", exc)
        return {"error": str(exc)}
    writer.write_static(post, group="post_earthquake")
    log.info("post-earthquake static state solved in %.2f s", time.perf_counter() - t0)
    out: dict[str, Any] = {"joints": _static_joints(model, post)}
    if model.uplifts:
        out["cracks_m"] = {u.interface: float(c)
                           for u, c in zip(model.uplifts, post.cracks, strict=True)}  # fmt: skip
    return out


def _total_motions(job: Job, res: DynamicResult) -> dict[str, dict[str, Any]]:
    """Per body, its rigid motion at the end of the run from the undeformed geometry
    (relative to the ground in the absolute form), as :func:`_body_motions`' residual
    keys: what the post-earthquake static state's geometry is judged by, whatever state
    the run started from."""
    model, d = job.model, job.model.dim
    if not res.rigid.size:
        return {}
    q = res.rigid[-1].copy()
    if job.analysis.form == "absolute":
        q[:, :d] -= _ground_displacement(job, res)[-1]
    return {name: {"residual_displacement_m": float(np.linalg.norm(q[b, :d])),
                   "residual_rotation_deg": float(np.degrees(np.linalg.norm(q[b, d:])))}
            for b, name in enumerate(model.body_names())}  # fmt: skip


#: the static state's relative displacement across a joint judged beyond small
#: displacements: this share of the joint's length (its pairs' extent)
STATIC_MOVE_MAX = 0.1


def _static_far_moved(model: Model, static: StaticResult) -> list[str]:
    """The joints whose faces moved apart, into each other or along each other by more
    than :data:`STATIC_MOVE_MAX` of the joint's length in the static state, each as
    "joint 'name': its faces moved … m against each other (… m long)": the pairs'
    relative displacement w, so that a block carried by its foundation's settlement is
    not counted (a joint stiffness in kPa/m read as Pa/m closes a joint by metres)."""
    P, st = model.pairs, static.pairs
    if P is None or st is None or not P.n:
        return []
    out = []
    for name in P.names:
        idx = P.of(name)
        if not idx.size:
            continue
        length = float(np.ptp(P.x[idx], axis=0).max())
        move = float(np.linalg.norm(st.w[idx], axis=1).max())
        if length > 0 and move > STATIC_MOVE_MAX * length:
            out.append(f"joint {name!r}: its faces moved {move:.3g} m against each other "
                       f"({length:.3g} m long)")  # fmt: skip
    return out


def _far_moved(model: Model, motions: dict[str, dict[str, Any]]) -> list[str]:
    """The floating blocks whose residual rigid motion (``motions``: the summary's, of
    :func:`_body_motions`) passes :data:`POST_EQ_ROTATION_MAX_DEG` or
    :data:`POST_EQ_MOVE_MAX` of their size, each as "block 'name' rotated …° and moved …
    m (… m across)"."""
    floating = model.floating_bodies()
    if not floating.size or not motions:
        return []
    names = model.body_names()
    body = model.body_of_node
    out = []
    for b in floating:
        m = motions[names[b]]
        pts = model.mesh.points[body == b]
        size = float(np.ptp(pts, axis=0).max()) if pts.size else 0.0
        rot, move = m["residual_rotation_deg"], m["residual_displacement_m"]
        if rot > POST_EQ_ROTATION_MAX_DEG or move > POST_EQ_MOVE_MAX * size:
            out.append(f"block {names[b]!r} rotated {rot:.3g}° and moved {move:.3g} m "
                       f"({size:.3g} m across)")  # fmt: skip
    return out


def _static_joints(model: Model, static: StaticResult) -> dict[str, dict[str, Any]]:
    """Per joint, the static state before any shaking: the sliding safety factor
    Σ max(0, cA + μN)/‖ΣT‖ (None without shear, or with a shear at the forces' round-off),
    the normal and shear resultants (N; compression +), the mean normal stress (Pa), the
    largest opening (m) and the shares of the joint's area that slide, are open (by more
    than ``pfeie.plot.OPEN_CRACK_MIN_M``, 0.01 mm) and are broken; the share in
    contact (not open by more than the crack threshold), the mean normal stress over it
    (Pa) and the point of the normal resultant (m; None where the normal forces sum to
    tension), as a gravity-method stability check reads
    them (EM 1110-2-2100: the resultant's location, the base in compression); and for a
    joint with uplift its crack from the heel under full headwater (m)."""
    P, st = model.pairs, static.pairs
    assert P is not None and st is not None
    cracks = {u.interface: float(c) for u, c in zip(model.uplifts, static.cracks, strict=True)}
    # a shear at the round-off of the joint's forces (FS_ROUNDOFF of their sum) is no shear
    noise = FS_ROUNDOFF * np.array([np.abs(st.X[P.of(name)]).sum() for name in P.names])
    fs = model.pair_laws.safety_factor(st.X, st.state == OPEN, st.broken, st.path, P.frame,
                                       noise, opening=st.s[:, -1])  # fmt: skip
    out: dict[str, dict[str, Any]] = {}
    for k, name in enumerate(P.names):
        idx = P.of(name)
        A = P.area[idx]
        X = st.X[idx]
        shear = float(np.linalg.norm(X[:, :-1].sum(axis=0)))
        shear = shear if shear > noise[k] else 0.0  # (4e-13 N under a 47 kN block)
        out[name] = {  # no shear (or at the round-off of the forces): no FS, null (∞)
            "safety_factor": float(fs[k]) if np.isfinite(fs[k]) else None,
            "normal_force_N": float(X[:, -1].sum()),
            "shear_force_N": shear,
            "mean_normal_stress_Pa": float(X[:, -1].sum() / A.sum()),
            # s_n, the gap (w_n with the initial gap and the springs' compliance), as the
            # results file's openings (pfeie.io.Results.static_pairs)
            "max_opening_m": float(np.maximum(st.s[idx, -1], 0.0).max(initial=0.0)),
            "sliding_share": float(A[st.state[idx] == SLIDE].sum() / A.sum()),
            # open by more than the crack threshold: a quadratic facet's corner pairs, which
            # carry little of a uniform pressure, part by microns (1e-6 m) under
            # compression
            "open_share": float(
                A[(st.state[idx] == OPEN) & (st.w[idx, -1] > OPEN_CRACK_MIN_M)].sum() / A.sum()
            ),
            "broken_share": float(A[st.broken[idx]].sum() / A.sum()),
        }
        # in contact: not open by more than the crack threshold (as open_share: the corner
        # pairs of quadratic facets carry little or nothing of a uniform pressure)
        touch = ~((st.state[idx] == OPEN) & (st.w[idx, -1] > OPEN_CRACK_MIN_M))
        total = float(X[:, -1].sum())
        out[name] |= {
            "contact_share": float(A[touch].sum() / A.sum()),
            "mean_contact_stress_Pa": (float(X[touch, -1].sum() / A[touch].sum())
                                       if touch.any() else None),
            # (of the normal forces, tension included: none where they sum to tension)
            "normal_resultant_at_m": ([float(v) for v in X[:, -1] @ P.x[idx] / total]
                                      if total > 0 else None),
        }  # fmt: skip
        if name in cracks:
            out[name]["crack_m"] = cracks[name]
        force, area = junction_share(model, static, name)
        if leans_on_junctions(force, area):
            # the joint leans on its pairs at junctions (a block's corner where joints
            # meet), whose node-to-node friction grows as the mesh is refined: a row of
            # toppling columns holds at F = 1 by it (reliability's "static" warning)
            out[name]["junction_share"] = force
            out[name]["junction_area_share"] = area
        if static.uplift is not None and (up := static.uplift[idx]).any():
            # the uplift's resultant on the joint (N; its pressures times the pairs'
            # areas, as the model applies it): W − U is the effective normal force
            out[name]["uplift_force_N"] = float(up @ A)
    return out


def summarize(job: Job, static: StaticResult | None, res: DynamicResult | None) -> dict[str, Any]:
    """The results summary (the dict of ``summary.json``).

    Per probe: ``peak_displacement_m``, the largest magnitude |u| (m) of the probe's
    displacement relative to the ground and to its start, and when
    (``peak_displacement_time_s``); ``peak_displacement_xyz_m``, the largest |u_x|,
    |u_y| (, |u_z|), each at its own time; the same for the absolute acceleration in g
    (``peak_abs_acceleration_g``: the largest |a|, ``..._time_s``, ``..._xyz_g``).

    Per joint: slips (m; the magnitude of the tangential relative displacement since
    the start), ``max_opening_m``, ``broken_share`` (at the end) and
    ``initially_broken_share`` (the pairs of ``initial = "broken"`` laws) and, for a run
    from another run's state (its first row after t = 0), ``broken_at_start_share`` (at
    that row: the cracks it started with), shares of the
    joint's area; ``cracked_length_m`` (2D) or ``cracked_area_m2`` (3D), the broken
    pairs at the end; ``max_open_length_m`` or ``max_open_area_m2``, the largest extent
    of the broken pairs that are open by more than ``pfeie.plot.OPEN_CRACK_MIN_M``
    (1e-5 m), and when.
    """
    s: dict[str, Any] = {"model": job.summary(), "version": __version__}
    if "mesh" in job.spec:  # a model file's: its digest covers its own bytes only
        s["model"]["run_key"] = run_key(job)
    model = job.model
    if static is not None and static.pairs is not None:
        s["static_joints"] = _static_joints(model, static)
        far = _static_far_moved(model, static)
        if far:  # (a joint stiffness in the wrong unit: metres of closure)
            s["static_far_moved"] = far
    if res is None:
        if static is not None and static.pairs is not None:
            s["static_pairs"] = static.pairs.counts()
        return s
    s["completed"] = res.completed
    s["time_reached_s"] = _time(res.t[-1])
    # steps, not recorded rows (output.every may be above 1)
    s["steps"] = round(float(res.t[-1] - res.t[0]) / job.analysis.dt)
    s["form"] = job.analysis.form
    probes = {}
    for k, (name, _node) in enumerate(job.probes.items()):
        u = res.probe_u[:, k]
        if job.analysis.form == "absolute":
            u = u - _ground_displacement(job, res)
        u = u - u[0]
        a = res.probe_a_abs[:, k] / G
        u_mag, a_mag = np.linalg.norm(u, axis=-1), np.linalg.norm(a, axis=-1)
        ku, ka = int(np.argmax(u_mag)), int(np.argmax(a_mag))
        probes[name] = {
            "peak_displacement_m": float(u_mag[ku]),
            "peak_displacement_time_s": _time(res.t[ku]),
            # (the components in full, as the magnitudes: a lab-scale model's micrometres
            # read 0 when rounded to 1 µm)
            "peak_displacement_xyz_m": np.abs(u).max(axis=0).tolist(),
            "peak_abs_acceleration_g": float(a_mag[ka]),
            "peak_abs_acceleration_time_s": _time(res.t[ka]),
            "peak_abs_acceleration_xyz_g": np.abs(a).max(axis=0).tolist(),
        }
    s["probes"] = probes
    s["bodies"] = _body_motions(job, res)
    rd = model.damping
    s["damping"] = {"alpha_per_s": rd.alpha if rd else 0.0, "beta_s": rd.beta if rd else 0.0,
                    "deformation_only": bool(rd and rd.deformation_only)}  # fmt: skip
    joints: dict[str, dict[str, Any]] = {}
    if model.pairs is not None and res.X.shape[1]:
        at_start = model.pair_laws.initially_broken
        # the open crack: broken pairs open, and open by more than OPEN_CRACK_MIN_M
        open_crack = model.joint_extent(
            res.broken & (res.state == OPEN) & (res.opening > OPEN_CRACK_MIN_M))  # fmt: skip
        for name in model.pairs.names:
            idx = model.pairs.of(name)
            area = model.pairs.area[idx]
            slip = res.slip[:, idx]
            slip_mag = np.linalg.norm(slip, axis=-1)
            spacing = _pair_spacing(model.pairs.x[idx])
            ratio = slip_mag.max(axis=0) / spacing  # finite: spacing > 0 (∞ gives 0)
            k_big = int(np.argmax(ratio)) if ratio.size else 0
            joints[name] = {
                "pairs": int(idx.size),
                "peak_slip_max_m": float(slip_mag.max()),
                # the largest slip over the spacing of the pairs (node to node: small
                # sliding), at the pair where it is largest
                "peak_slip_to_spacing": float(ratio[k_big]) if ratio.size else 0.0,
                "pair_spacing_m": float(spacing[k_big]) if ratio.size else 0.0,
                "residual_slip_max_m": float(slip_mag[-1].max()),
                "residual_slip_mean_m": float((slip_mag[-1] * area).sum() / area.sum()),
                "max_opening_m": float(res.opening[:, idx].max()),
                "broken_share": float((res.broken[-1, idx] * area).sum() / area.sum()),
                "initially_broken_share": float((at_start[idx] * area).sum() / area.sum()),
            }
            if float(res.t[0]) > 0.0:
                # a run from another run's state (an aftershock after its mainshock; a run
                # from the static state starts at t = 0, its static cracks the static
                # line's): broken at its first row
                joints[name]["broken_at_start_share"] = float(
                    (res.broken[0, idx] * area).sum() / area.sum())  # fmt: skip
            pieces = _joint_pieces(model, idx)
            if len(pieces) > 1:  # the joint's pieces between two blocks each
                joints[name]["pieces"] = {
                    label: {
                        "pairs": int(k.size),
                        "peak_slip_max_m": float(slip_mag[:, k].max()),
                        "residual_slip_max_m": float(slip_mag[-1, k].max()),
                        "max_opening_m": float(res.opening[:, idx[k]].max()),
                        "broken_share": float((res.broken[-1, idx[k]] * area[k]).sum()
                                              / area[k].sum()),
                    }
                    for label, k in pieces.items()
                }  # fmt: skip
            # the cracked extent at the end: the broken pairs' length (2D) or area (3D);
            # the largest open crack (broken pairs open by more than OPEN_CRACK_MIN_M)
            jk = model.pairs.names.index(name)
            if res.joint_cracked.size:
                cracked = res.joint_cracked[:, jk]
            else:  # a result without the series
                cracked = model.joint_extent(res.broken)[..., jk]
            opened = open_crack[:, jk]
            kind = "length_m" if model.dim == 2 else "area_m2"
            joints[name][f"cracked_{kind}"] = float(cracked[-1])
            k_open = int(np.argmax(opened))
            joints[name][f"max_open_{kind}"] = float(opened[k_open])
            # (null where no crack opens: no time to give)
            joints[name]["max_open_time_s"] = (_time(res.t[k_open]) if opened[k_open] > 0.0
                                               else None)  # fmt: skip
            if res.safety_factor.size:
                fs = res.safety_factor[:, model.pairs.names.index(name)]
                # the first time within round-off of the minimum: a sliding joint sits at
                # FS = 1 to round-off at every step it slides, and argmin would pick any of
                # them (a block on a plane: 9.11, 14.07, 1.39 s as Δt fell, sliding from
                # 1.315 s in every run)
                k = int(np.argmax(fs <= fs.min() * (1.0 + MIN_FS_TIES)))
                # a joint that never carries shear has no FS: null (printed ∞); one that
                # slides has FS 1, its values 1 to round-off (1 + 4.7e-14 was seen): 1, so
                # that a limit state FS ≤ 1 counts it
                fs_min = float(fs[k])
                if abs(fs_min - 1.0) <= MIN_FS_TIES:
                    fs_min = 1.0
                joints[name]["min_safety_factor"] = fs_min if np.isfinite(fs_min) else None
                joints[name]["min_safety_factor_time_s"] = _time(res.t[k])
    s["joints"] = joints
    stress = envelope_extremes(res.envelope, model.mesh.points)
    if stress is not None:
        s["stress"] = stress
        centres = np.concatenate([model.mesh.points[c].mean(axis=1)
                                  for c in model.mesh.cells.values()])  # fmt: skip
        dc = demand_capacity(res.envelope, model.cell_volumes, centres)
        if dc is not None:
            s["stress"]["demand_capacity"] = dc
    s["energy_J"] = {k: float(v[-1]) for k, v in res.energy.items()}
    if static is not None:
        # the static strain energy (Clapeyron: half the work of the static loads on the
        # static displacements), the scale of the energy terms' round-off (ENERGY_FLOOR)
        f0 = model.load_vector(0.0)
        s["static_strain_energy_J"] = 0.5 * abs(float(f0 @ static.u.reshape(-1)))
    if res.solver:
        # per step in a run's own result, per recorded row in one read back from its file
        # (a resumed run): sums of steps and of iterations are the same in both
        fb, it = res.solver["fallbacks"], res.solver["iterations"]
        steps = max(s["steps"], 1)
        s["solver"] = {
            "fallback_steps": int(fb.sum()),
            "iterations_mean": round(float(it.sum()) / steps, 2),
            "worst_residual": float(res.solver["residual"].max(initial=0.0)),
        }
        if "newton" in res.solver:  # (results files of format 1.5 and older lack it)
            s["solver"]["newton_steps"] = int(res.solver["newton"].sum())
        sub = res.solver.get("substeps")
        if sub is not None and sub.any():  # (1.8 and older lack it; none without events)
            s["solver"]["event_steps"] = int(sub.sum()) // job.analysis.event_substeps
    return s


def _body_motions(job: Job, res: DynamicResult) -> dict[str, dict[str, Any]]:
    """Per body (its blocks' names), the rigid motion of its centroid relative to the
    start of the run (and to the ground in the absolute form): the peak and the residual
    displacement magnitude (m), the residual per axis, and the residual rotation (degrees;
    in 2D signed, counter-clockwise +; in 3D the magnitude of the rotation vector). The
    permanent displacement of a block that slides on its joints, the result a Newmark
    sliding-block analysis estimates."""
    model, d = job.model, job.model.dim
    if not res.rigid.size:
        return {}
    q = res.rigid - res.rigid[:1]
    if job.analysis.form == "absolute":
        base = _ground_displacement(job, res)
        q[..., :d] -= (base - base[:1])[:, None, :]
    u = np.linalg.norm(q[..., :d], axis=-1)  # (n_t, bodies)
    # the rotation: in 2D signed (counter-clockwise +, as history/rigid), in 3D the
    # rotation vector's magnitude
    turn = np.degrees(q[..., d] if d == 2 else np.linalg.norm(q[..., d:], axis=-1))
    out = {}
    floating = set(model.floating_bodies().tolist())
    flying = _airborne(model, res)
    body = model.body_of_node
    for b, name in enumerate(model.body_names()):
        out[name] = {
            "floating": b in floating,
            "peak_displacement_m": float(u[:, b].max()),
            "residual_displacement_m": float(u[-1, b]),
            "residual_displacement_xyz_m": (q[-1, b, :d] + 0.0).tolist(),  # no -0.0
            "residual_rotation_deg": float(turn[-1, b]) + 0.0,  # (no -0.0)
            "peak_rotation_deg": float(np.abs(turn[:, b]).max()),
        }
        if b in flying:  # rows at which every pair of the body was open, and the first
            out[name]["airborne_rows"], out[name]["first_airborne_s"] = flying[b]
        if b not in floating:
            continue
        turned = np.abs(turn[:, b]) > SMALL_TURN_DEG
        if not job.analysis.large_rotation and turned.any():
            out[name]["small_rotation_beyond_s"] = _time(res.t[int(np.argmax(turned))])
        pts = model.mesh.points[body == b]
        size = float(np.ptp(pts, axis=0).max()) if pts.size else 0.0
        far = (np.abs(turn[:, b]) > LARGE_TURN_DEG) | (u[:, b] > LARGE_MOVE * size)
        if far.any():  # beyond what node-to-node pairs can follow
            out[name]["size_m"] = size
            out[name]["beyond_pairs_s"] = _time(res.t[int(np.argmax(far))])
    return out


def _airborne(model: Model, res: DynamicResult) -> dict[int, tuple[int, float]]:
    """The floating bodies that lost contact with every joint they touch at some recorded
    row (every pair of theirs open) after touching one: the number of such rows and the
    first one's time (a block that starts apart, across a gap, flies until it lands)."""
    P = model.pairs
    if P is None or not res.state.size:
        return {}
    body = model.body_of_node
    out = {}
    for b in model.floating_bodies():
        on = (body[P.node_a] == b) | (body[P.node_b] == b)
        if not on.any():
            continue
        apart = (res.state[:, on] == OPEN).all(axis=1)
        touched = np.flatnonzero(~apart)
        rows = np.flatnonzero(apart)
        rows = rows[rows > touched[0]] if touched.size else rows[:0]
        if rows.size:
            out[int(b)] = (int(rows.size), _time(res.t[rows[0]]))
    return out


def _ground_displacement(job: Job, res: DynamicResult) -> FloatArray:
    """The ground's displacement (n_t, d) at the rows of ``res``: as the supports
    followed it in the run (the time scheme's integration of the records on its grid,
    ``res.ground``), or, for histories read from a file of format 1.9 or older, the
    records' exact displacement (they differ by the scheme's integration error: 6e-5 m
    over El Centro at Δt = 5 ms, 9e-4 m at 20 ms)."""
    if res.ground.shape == (res.t.size, job.model.dim):
        return res.ground
    return np.array([sum((g.direction * g.motion(ti)[0] for g in job.records),
                         np.zeros(job.model.dim)) for ti in res.t])  # fmt: skip


#: the pieces of a joint listed in the run's summary text (the rest in summary.json)
PIECE_LINES = 6


def _joint_pieces(model: Model, idx: IntArray) -> dict[str, IntArray]:
    """The pieces of the joint whose pairs are ``idx`` by the blocks they join
    (:func:`pfeie.interface.block_pieces`): "A | B" → positions in ``idx``."""
    P = model.pairs
    assert P is not None
    body = model.body_of_node
    return block_pieces(body[P.node_a[idx]], body[P.node_b[idx]], model.body_names())


def _pair_spacing(x: FloatArray) -> FloatArray:
    """The distance from each pair (positions ``x`` (m, d) of one joint) to the nearest
    pair of the joint at another position (∞ for a joint of one position). Pairs at one
    point (where a joint meets two blocks on one side: a pair for each) are not a
    spacing: positions within 1e-9 of the joint's extent are one."""
    if x.shape[0] < 2:
        return np.full(x.shape[0], np.inf)
    tol = 1e-9 * max(float(np.ptp(x, axis=0).max()), 1e-300)
    _, first, at = np.unique(np.round(x / tol), axis=0, return_index=True,
                             return_inverse=True)  # fmt: skip
    if first.size < 2:
        return np.full(x.shape[0], np.inf)
    points = x[first]  # one pair for each position
    dist, _ = cKDTree(points).query(points, k=2)
    return np.asarray(dist[at.ravel(), 1], dtype=float)


def _components(p: dict[str, Any], key: str, scale: float, fmt: str, unit: str) -> str:
    """The per-axis peaks of a probe, ``" (x 1.0, y 0.2 mm)"``; empty without them."""
    if key not in p:
        return ""
    parts = ", ".join(f"{ax} {scale * v:{fmt}}" for ax, v in zip("xyz", p[key], strict=False))
    return f" ({parts} {unit})"


def _broken(j: dict[str, Any]) -> str:
    """The broken share of a joint, saying which part was broken from the start (a
    pre-existing joint, ``initial = "broken"``), so that it is not read as a failure."""
    now, start = 100 * j["broken_share"], 100 * j.get("initially_broken_share", 0.0)
    before = 100 * j.get("broken_at_start_share", 0.0)
    if before > start + 1e-9:  # a run from another run's state: broken before this one
        law = f"; {start:.0f} % a pre-existing joint" if start > 0.0 else ""
        return (f"broken {now:.0f} % ({before:.0f} % when this run started, from its start "
                f"state{law})")  # fmt: skip
    if start <= 0.0:
        return f"broken {now:.0f} %"
    if start >= 100.0:
        return f"broken {now:.0f} % (starts broken: a pre-existing joint)"
    return f"broken {now:.0f} % ({start:.0f} % broken from the start)"


def _time(t: float) -> float:
    """A time of the run's grid for the summary (s), to the nanosecond: t₀ + k h carries
    the rounding of the product (2.5500000000000003 s), which summary.json would show."""
    return round(float(t), 9)


def format_summary(s: dict[str, Any]) -> str:
    """The results summary as aligned text lines."""
    mdl = s["model"]
    lines = [f"{mdl['title'] or Path(mdl['file']).stem}  (pfeie {s['version']})"]
    key = f", run key {mdl['run_key'][:12]}" if "run_key" in mdl else ""
    lines.append(f"  model file   {mdl['file']}  sha256 {mdl['sha256'][:12]}{key}")
    for ov in mdl.get("overrides", []):  # the run's settings over the file's
        lines.append(f"  override     {ov}")
    lines.append(f"  blocks {len(mdl['blocks'])}, bodies {mdl['bodies']}, DOF {mdl['dof']}, "
                 f"pairs {sum(mdl['pairs'].values())}")  # fmt: skip
    for r in mdl["records"]:
        lines.append(f"  record       {r}")
    if "completed" in s:
        state = "completed" if s["completed"] else f"STOPPED ({s.get('stopped')})"
        form = (", ground motion in the absolute form (the supports move; a mass-"
                "proportional damping acts on absolute velocities)"
                if s.get("form") == "absolute" else "")  # fmt: skip
        lines.append(f"  run          {state} at t = {s['time_reached_s']:.3f} s, "
                     f"{s['steps']} steps{form}")  # fmt: skip
    for name, p in s.get("probes", {}).items():
        lines.append(
            f"  {name:<12} peak |u| {1e3 * p['peak_displacement_m']:.1f} mm"
            + _components(p, "peak_displacement_xyz_m", 1e3, ".1f", "mm")
            + f", peak absolute |a| {p['peak_abs_acceleration_g']:.3f} g"
            + _components(p, "peak_abs_acceleration_xyz_g", 1.0, ".3f", "g")
        )
    floating = [(n, b) for n, b in s.get("bodies", {}).items() if b["floating"]]
    for name, b in floating[:BODY_LINES]:
        xyz = ", ".join(f"{ax} {1e3 * v:.1f}" for ax, v in
                        zip("xyz", b["residual_displacement_xyz_m"], strict=False))  # fmt: skip
        lines.append(
            f"  block {name:<10} residual displacement {1e3 * b['residual_displacement_m']:.1f} "
            f"mm ({xyz} mm), peak {1e3 * b['peak_displacement_m']:.1f} mm, rotation "
            f"{b['residual_rotation_deg']:.3g}°"
        )
    if len(floating) > BODY_LINES:
        lines.append(f"  blocks       {len(floating) - BODY_LINES} more floating block(s) in "
                     "summary.json (bodies)")  # fmt: skip
    per = per_thickness(s)
    for name, j in s.get("static_joints", {}).items():
        fs = j["safety_factor"]
        at_capacity = (fs is not None and fs <= 1 + AT_CAPACITY_FS
                       and "strength_reduction" not in s)  # fmt: skip
        lines.append(
            f"  static {name:<9} FS {'∞' if fs is None else f'{fs:.2f}'}, normal "
            f"{j['normal_force_N'] / 1e3:.4g} kN, shear {j['shear_force_N'] / 1e3:.4g} kN "
            f"(mean normal stress {j['mean_normal_stress_Pa'] / 1e6:.3g} MPa), max opening "
            f"{1e3 * j['max_opening_m']:.2f} mm, sliding {100 * j['sliding_share']:.0f} %, "
            f"open {100 * j['open_share']:.0f} %"
            + _compression_text(j, per)
            + (
                "; at its capacity in the static state, which holds: the factor against "
                "sliding is analysis.strength_reduction's"
                if at_capacity
                else ""
            )
        )
    lines += _warning_lines(reliability(s), "static")
    for label, y in s.get("yield_coefficient", {}).items():
        k, fs = y["k_y"], y["safety_factor"]
        if k is None:
            what = f"k_y > {y.get('k_max', YIELD_K_MAX):g} (held at the largest coefficient tried)"
        elif y["limit"] == "sliding":
            what = f"k_y {k:.4g} (sliding on {y['joint']!r})"
        elif (
            y["k_affine"] is not None
            and fs is not None
            and k < y["k_affine"] <= (1 + NEAR_SLIDING) * k
            and fs <= 1 + NEAR_SLIDING
        ):
            # the margins vanish just beyond: a sliding limit that the pair solver did not
            # reach (a new user's four columns on 15° bases: 0.2655 against tan 15° = 0.2679)
            what = (f"k_y {k:.4g} ({y['limit']} beyond it; {y['joint']!r} reaches its "
                    f"capacity at {y['k_affine']:.4g}, the margins' affine estimate (FS "
                    f"{fs:.4g} at k_y): probably a sliding limit there, short of which the "
                    "pair solver found no equilibrium)")  # fmt: skip
        elif fs is not None and fs <= 1 + AT_CAPACITY_FS:
            # at k_y a joint is at its sliding capacity, and beyond it the joint opens or
            # breaks further (a crack that grows under its uplift lowers its normal force):
            # a sliding limit with a growing opening (a new user's cracked dam base)
            what = (f"k_y {k:.4g} ({y['limit']} beyond it; {y['joint']!r} is at its "
                    f"sliding capacity there, FS {fs:.4g}: sliding as the joint opens or "
                    "breaks further")  # fmt: skip
            what += _open_text(y) + ")"
        else:
            what = (f"k_y {k:.4g} ({y['limit']} beyond it, not a sliding limit: a joint "
                    f"breaking through, opening or rocking, or the pair solver failing short "
                    f"of the limit; {_least_fs(y)}")  # fmt: skip
            if y["k_affine"] is not None:
                what += f", the margins' affine estimate {y['k_affine']:.4g}"
            rigid = y.get("k_rigid")
            kt = y.get("k_translation")
            pinched = kt is not None and k > kt * (1 + YIELD_RIGID_GAP)  # (said below)
            if rigid is not None and rigid > k * (1 + YIELD_RIGID_GAP) and not pinched:
                what += (f"; the rigid blocks' limit is {rigid:.4g} (limit equilibrium, an "
                         f"upper bound): k_y lies between {k:.4g} and {rigid:.4g}")  # fmt: skip
            what += _open_text(y) + ")"
        kt = y.get("k_translation")
        if kt is not None and (k is None or k > kt * (1 + YIELD_RIGID_GAP)):
            what += (f"; but a block slides as a rigid block from k = {kt:.4g} (Hoek and "
                     "Bray's plane and wedge sliding; the static analyses pinch it between "
                     "its planes): take that")  # fmt: skip
        what += _junction_text(y)
        lines.append(f"  yield {label:<10} {what}")
    sr = s.get("strength_reduction")
    if sr:
        text = _reduction_text(sr)
        ft = sr.get("translation_factor")
        held = sr.get("f_max", REDUCTION_F_MAX) if sr["factor"] is None else sr["factor"]
        if ft is not None and held > ft * (1 + YIELD_RIGID_GAP):
            text += (f"; but a block slides as a rigid block at FS {ft:.4g} (Hoek and Bray's "
                     "plane and wedge sliding; the static analyses pinch it between its "
                     "planes): take that")  # fmt: skip
        text += _junction_text(sr)
        lines.append(f"  reduction    {text}")
    for name, j in s.get("joints", {}).items():
        lines.append(
            f"  joint {name:<10} residual slip {1e3 * j['residual_slip_max_m']:.2f} mm "
            f"(mean {1e3 * j['residual_slip_mean_m']:.2f}), max opening "
            f"{1e3 * j['max_opening_m']:.2f} mm, {_broken(j)}"
            + (f", open crack up to {j['max_open_length_m']:.2f} m"
               if "max_open_length_m" in j else "")
            + (f", open crack up to {j['max_open_area_m2']:.3g} m²"
               if "max_open_area_m2" in j else "")
            + (", min FS ∞" if j.get("min_safety_factor", 0.0) is None else
               f", min FS {j['min_safety_factor']:.2f} at {j['min_safety_factor_time_s']:.2f} s"
               if "min_safety_factor" in j else "")
        )  # fmt: skip
        pieces = j.get("pieces", {})
        for label, q in list(pieces.items())[:PIECE_LINES]:
            lines.append(
                f"    {label:<20} residual slip {1e3 * q['residual_slip_max_m']:.2f} mm, max "
                f"opening {1e3 * q['max_opening_m']:.2f} mm, broken "
                f"{100 * q['broken_share']:.0f} %"
            )
        if len(pieces) > PIECE_LINES:
            lines.append(f"    {len(pieces) - PIECE_LINES} more piece(s) in summary.json "
                         f"(joints.{name}.pieces)")  # fmt: skip
    warnings = reliability(s)
    lines += _warning_lines(warnings, "airborne")
    lines += _warning_lines(warnings, "large motion")
    lines += _warning_lines(warnings, "rotation")
    lines += _warning_lines(warnings, "large slip")
    post = s.get("post_earthquake", {})
    if "error" in post:
        lines.append(f"  post-EQ      no static equilibrium after the record: {post['error']}")
    if "skipped" in post:
        lines.append(f"  post-EQ      not computed: {post['skipped']}")
    for name, j in post.get("joints", {}).items():
        fs = j["safety_factor"]
        crack = post.get("cracks_m", {}).get(name)
        lines.append(
            f"  post-EQ {name:<8} FS {'∞' if fs is None else f'{fs:.2f}'}, normal "
            f"{j['normal_force_N'] / 1e3:.4g} kN, shear {j['shear_force_N'] / 1e3:.4g} kN, "
            f"broken {100 * j['broken_share']:.0f} %"
            + ("" if crack is None or "crack_m" in j else f", crack at full uplift {crack:.2f} m")
            + f", sliding {100 * j['sliding_share']:.0f} %"
            + (_compression_text(j, per) if "contact_share" in j else "")
        )
    if "stress" in s:
        st = s["stress"]

        def where(key: str) -> str:
            return "(" + ", ".join(f"{x:g}" for x in st[key + "_at_m"]) + ") m"

        lines.append(
            f"  stress       max principal {st['max_principal_Pa'] / 1e6:.3g} MPa at "
            f"{where('max_principal')}, t = {st['max_principal_time_s']:.2f} s; min "
            f"{st['min_principal_Pa'] / 1e6:.3g} MPa at {where('min_principal')}, "
            f"t = {st['min_principal_time_s']:.2f} s"
        )
        if "demand_capacity" in st:
            dc = st["demand_capacity"]
            lines.append(
                f"  DCR          max {dc['max_dcr']:.3g} (σ1/f_t) at "
                f"({', '.join(f'{x:g}' for x in dc['max_dcr_at_m'])}) m, "
                f"t = {dc['max_dcr_time_s']:.2f} s; max CID {dc['max_cid_s']:.3f} s; "
                f"overstressed {100 * dc['overstressed_share']:.1f} %: {dc['verdict']} "
                "(EM 1110-2-6053)"
            )
    if "energy_J" in s:
        e = s["energy_J"]
        lines.append(
            f"  energy       input {e.get('external_work', 0):.4g} J; friction/contact "
            f"{e.get('interface', 0):.4g}, impact {e.get('impact', 0):.4g}, damping "
            f"{e.get('damping', 0):.4g}, algorithmic {e.get('algorithmic', 0):.4g} J; balance "
            f"{e.get('balance', 0):.2e} J"
        )
        lines += _warning_lines(warnings, "scheme")
        lines += _warning_lines(warnings, "corrections")
    if "solver" in s:
        lines.append(f"  pair solver  {solver_line(s['solver'])}")
    if "wall_time_s" in s:
        lines.append(f"  wall time    {s['wall_time_s']:.1f} s")
    return "\n".join(lines)


Callback = Callable[[StepState], None]
