"""Executors of a sweep: local worker processes and a Dask cluster. Each takes the case runner as
an argument, hands every finished case to ``finished`` or ``failed`` as it completes, and moves
a progress bar."""

from __future__ import annotations

import concurrent.futures as cf
import logging
import multiprocessing

from ..errors import StudyError

log = logging.getLogger("moorline")


def run_local(runner, pending, n, finished, failed, bar) -> None:
    """Run ``runner(spec)`` for every pending case on ``n`` local worker processes (spawned)."""
    ctx = multiprocessing.get_context("spawn")  # no fork of a process with threads (tqdm, numba)
    pool = cf.ProcessPoolExecutor(max_workers=min(n, len(pending)), mp_context=ctx)
    try:
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
