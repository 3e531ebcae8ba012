"""The runs of a study on Dask: a local cluster of worker processes, or a scheduler.

Each task is a group of runs (:func:`pfeie.study._study.run_batch`, at most the study's
``batch``, :func:`batches`) with the small :class:`~pfeie.study._study.Context`, which the
worker steps together where the system gains from it; a worker builds the model, its
static state and its factorised time stepping on its first task and keeps them for the
next ones (the factorisation is never shipped). Only the rows come back. Every row is
also written by the worker to ``<folder>/rows/`` as the run ends, so that a study killed
at any moment keeps its finished runs; on a cluster, the output folder must be on a file
system that the workers share with the client.

``workers = "auto"`` (the default of the study file and of :class:`~pfeie.study.Study`)
is one process per core this process may run on (:func:`available_cores`), at most one
per run, and the runs stay in this process, one after the other, when that cannot help:
Dask not installed, one core, one run to do, or a daemonic process (which may not start
others); an INFO line says which (:func:`local_workers`).

A local cluster has ``workers`` processes of one thread each, with ``OMP_NUM_THREADS=1``
(a run is sequential; the processes are the parallelism). Its workers log only critical
errors (a run's error comes back with its task), and an interrupted study (Ctrl-C,
SIGTERM) closes the cluster without the warnings of workers stopped in the middle of a
run. With ``scheduler``, the runs
go to a running Dask scheduler (``dask scheduler`` and ``dask worker ADDRESS`` on the
machines, or dask-jobqueue on SLURM or PBS, see docs/study.md); its workers need pfeie
installed.
"""

from __future__ import annotations

import contextlib
import logging
import math
import multiprocessing
import os
import signal
import threading
from collections.abc import Callable, Iterator, Sequence
from typing import Any

from ..errors import InputError, PfeieError
from ._study import Context, RunSpec, Workers, run_batch

log = logging.getLogger(__name__)


#: the Dask settings of a local cluster's workers that differ from Dask's defaults.
#: Dask's nanny sets ``MALLOC_TRIM_THRESHOLD_=65536`` in its workers, which also turns
#: off glibc's adaptive mmap threshold: every array above 128 kB (a vector of 16k DOF)
#: is then mapped and unmapped anew, its pages faulted in zero-filled, and a time step of
#: the 49k-DOF study benchmark took 56 ms instead of 38 (measured in one process with and
#: without the variable; 65 ms in a worker). Unset here (None removes it). The workers'
#: sampling profiler (every 10 ms, for the dashboard) cost about 10 % more (65 → 58 ms);
#: off here.
WORKER_CONFIG: dict[str, Any] = {
    "distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None,
    "distributed.worker.profile.enabled": False,
}


def available_cores() -> int:
    """The cores this process may run on: ``os.sched_getaffinity`` (which honours
    ``taskset``, a container's or a batch job's CPU set), else ``os.cpu_count()`` (on
    platforms without it), at least 1."""
    try:
        return max(len(os.sched_getaffinity(0)), 1)
    except AttributeError:  # macOS, Windows
        return max(os.cpu_count() or 1, 1)


def local_workers(workers: Workers, runs: int) -> int:
    """The worker processes of the local cluster for ``runs`` runs (0: in this process).

    A number is kept as given. ``"auto"`` is ``min(available_cores(), runs)``, or 0 with
    an INFO line giving the reason when a cluster cannot help: one run (or none) to do,
    one core, Dask not installed (the study extra), or a daemonic process (it may not
    start processes)."""
    if workers != "auto":
        return int(workers)
    cores = available_cores()
    why = None
    if runs <= 1:
        why = f"{runs} run to do"
    elif cores <= 1:
        why = "one core available"
    elif multiprocessing.current_process().daemon:
        why = "a daemonic process cannot start worker processes"
    else:
        try:
            import distributed  # noqa: F401
        except ImportError:
            why = "Dask is not installed (pip install 'pfeie[study]')"
    if why is not None:
        log.info("study: workers = 'auto': the runs go in this process, one after the "
                 "other (%s)", why)  # fmt: skip
        return 0
    n = min(cores, runs)
    log.info("study: workers = 'auto': a local Dask cluster of %d processes (%d cores, "
             "%d runs)", n, cores, runs)  # fmt: skip
    return n


def batches(specs: Sequence[RunSpec], batch: int, workers: int) -> list[list[RunSpec]]:
    """``specs`` in groups a worker runs together (:func:`~pfeie.study._study.run_batch`),
    in order: at most ``batch`` each, their number a multiple of ``workers`` (every round
    of groups keeps every worker busy) and their sizes within one of each other.

    >>> [len(g) for g in batches(list(range(10)), 8, 2)]
    [5, 5]
    >>> [len(g) for g in batches(list(range(20)), 8, 2)]
    [5, 5, 5, 5]
    >>> [len(g) for g in batches(list(range(5)), 8, 1)]
    [5]
    """
    n = len(specs)
    if n == 0:
        return []
    w, b = max(workers, 1), max(batch, 1)
    groups = min(w * math.ceil(n / (b * w)), n)
    size, extra = divmod(n, groups)
    out, i = [], 0
    for g in range(groups):
        k = size + (g < extra)
        out.append(list(specs[i : i + k]))
        i += k
    return out


@contextlib.contextmanager
def _interrupts_ignored() -> Iterator[None]:
    """SIGINT ignored while the local cluster starts its processes, which inherit that
    (Python keeps an ignored SIGINT ignored; a blocked one is not enough, as the workers
    are started from the cluster's own thread): Ctrl-C in a terminal reaches the whole
    process group, and the workers, interrupted mid-run, printed their tracebacks; the
    study's own process takes it and stops them. A Ctrl-C during the start (a second or
    two) is lost. Nothing changes off the main thread."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    before = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, before)


def run_parallel(
    ctx: Context,
    specs: Sequence[RunSpec],
    finished: Callable[[dict[str, Any]], None],
    *,
    workers: int = 2,
    scheduler: str | None = None,
    batch: int = 1,
) -> None:
    """Run ``specs`` on Dask in groups of at most ``batch`` (:func:`batches`; each a task
    that a worker runs together, :func:`~pfeie.study._study.run_batch`), calling
    ``finished(row)`` as each group ends (in the order they end). An error of a run (a
    :class:`PfeieError`) is raised after the runs already finished have been
    reported."""
    try:
        from distributed import Client, LocalCluster, as_completed
    except ImportError:
        raise InputError("running a study on workers needs Dask (pip install "
                         "'pfeie[study]'); or run it with workers = 0") from None  # fmt: skip
    logging.getLogger("distributed").setLevel(logging.WARNING)  # not its start-up chatter
    # the event loop's own callbacks: a Ctrl-C that interrupts distributed's cancellation
    # made one of them fail with a traceback on stderr (a NameError inside distributed,
    # seen once in ten interrupts), from the loop's thread before the interrupt reached
    # the code below; the runs' own errors come back through their futures
    logging.getLogger("tornado.application").setLevel(logging.CRITICAL)
    cluster = None
    if scheduler:
        try:
            client = Client(scheduler, timeout="20s")
        except (OSError, TimeoutError, ValueError) as exc:  # (ValueError: no port)
            raise InputError(f"cannot reach the Dask scheduler at {scheduler!r}: {exc}") from None
    else:
        import dask

        env = {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}
        try:
            with dask.config.set(WORKER_CONFIG), _interrupts_ignored():
                cluster = LocalCluster(n_workers=max(int(workers), 1), threads_per_worker=1,
                                       processes=True, dashboard_address=":0",
                                       scheduler_kwargs={"dashboard": False},
                                       silence_logs=logging.CRITICAL, env=env)  # fmt: skip
        except RuntimeError as exc:  # a worker process that failed to start
            raise InputError(
                f"the local Dask cluster could not start its {int(workers)} worker "
                f"processes ({exc}); a Python script that runs a study on workers needs its "
                "code under 'if __name__ == \"__main__\":' (each worker starts by importing "
                "the script), or run the study with workers = 0"
            ) from None
        client = Client(cluster)
    log.info("study on Dask: %s (%d runs)", client.dashboard_link or scheduler, len(specs))
    error: BaseException | None = None
    try:
        n_workers = workers if not scheduler else len(client.scheduler_info()["workers"])
        futures = [client.submit(run_batch, ctx, g, key=f"pfeie-runs-{g[0].key[:24]}",
                                 pure=False)
                   for g in batches(specs, batch, n_workers)]  # fmt: skip
        for fut in as_completed(futures):
            try:
                outcomes = fut.result()
            except PfeieError as exc:
                error = error or exc
                continue
            for r in outcomes:
                if isinstance(r, PfeieError):
                    error = error or r
                else:
                    finished(r)
    except BaseException:  # Ctrl-C, SIGTERM: the workers are stopped mid-run, as asked
        logging.getLogger("distributed").setLevel(logging.CRITICAL)
        raise
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    if error is not None:
        raise error


__all__ = ["available_cores", "local_workers", "run_parallel"]
