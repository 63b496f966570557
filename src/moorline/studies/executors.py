"""Executors of a sweep: local worker processes and a Dask cluster. Each takes the case runner as
an argument, hands every finished case to ``finished`` or ``failed`` as it completes, and moves
a progress bar.

Local workers (:func:`run_local`) are spawned processes that take one case at a time from a
shared queue as they become free (no fixed chunks: a worker given short cases takes more of them,
and no worker waits while cases are queued). They import the same moorline, so they load the
compiled kernels from the same numba cache (``__pycache__`` beside the sources, or
``NUMBA_CACHE_DIR``, which they inherit): a kernel is compiled once per machine, not once per
worker. Each worker is held to its share of the CPUs for threaded libraries (OpenBLAS, MKL,
OpenMP: the thread-count variables set for the children, unless already set), so that N workers
on N cores do not run N x N threads.
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import logging
import multiprocessing
import os

from ..errors import StudyError

log = logging.getLogger("moorline")


#: thread-count variables of the threaded libraries numpy and scipy may load
THREAD_VARIABLES = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "BLIS_NUM_THREADS",
                    "VECLIB_MAXIMUM_THREADS", "NUMEXPR_NUM_THREADS")


def available_cpus() -> int:
    """CPUs this process may run on (its affinity mask where the platform has one, which a
    ``taskset`` or a container's cpuset narrows; else ``os.cpu_count()``)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):
        return os.cpu_count() or 1


@contextlib.contextmanager
def _worker_threads(n_workers: int):
    """Set the thread-count variables (those not set already) to the workers' share of the CPUs
    while worker processes start: a spawned process reads them when it loads its BLAS."""
    share = str(max(1, available_cpus() // max(1, n_workers)))
    added = [k for k in THREAD_VARIABLES if k not in os.environ]
    for k in added:
        os.environ[k] = share
    try:
        yield
    finally:
        for k in added:
            os.environ.pop(k, None)


def run_local(runner, pending, n, finished, failed, bar) -> None:
    """Run ``runner(spec)`` for every pending case on ``n`` local worker processes (spawned),
    each taking the next queued case when it is free."""
    ctx = multiprocessing.get_context("spawn")  # no fork of a process with threads (tqdm, numba)
    workers = min(n, len(pending))
    pool = cf.ProcessPoolExecutor(max_workers=workers, mp_context=ctx)
    try:
        with _worker_threads(workers):  # the pool starts its processes as the cases are submitted
            futs = {pool.submit(runner, s): s for s in pending}
        _collect(futs, cf.as_completed(futs), finished, failed, bar)
    except BaseException:  # interrupted: drop the queued cases, do not wait for the running ones
        pool.shutdown(wait=False, cancel_futures=True)
        raise
    pool.shutdown()


def _collect(futs, done, finished, failed, bar) -> None:
    """Hand every finished future (local or Dask) to ``finished`` or ``failed`` as it completes."""
    for f in done:
        s = futs[f]
        try:
            ds = f.result()
        except Exception as e:  # reported per case; the others go on
            failed(s, e)
        else:
            finished(s, ds)
        bar.update(1)


def run_dask(runner, pending, scheduler, finished, failed, bar) -> None:
    """Run ``runner(spec)`` for every pending case on a Dask cluster (a scheduler address or a
    ``distributed.Client``)."""
    try:
        from distributed import Client, as_completed
    except ImportError:
        raise StudyError("a Dask scheduler was given but dask.distributed is not installed "
                         "(pip install 'moorline[cluster]')") from None
    own = not isinstance(scheduler, Client)
    client = Client(scheduler) if own else scheduler
    try:
        futs = {client.submit(runner, s, pure=False): s for s in pending}
        _collect(futs, as_completed(list(futs)), finished, failed, bar)
    finally:
        if own:
            client.close()
