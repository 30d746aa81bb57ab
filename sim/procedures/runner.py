"""One job runner for the experiment and the grader (docs/design.md, "Jobs").

A job is a picklable callable and its arguments, with a key that says where its result belongs.
`run_jobs` runs a batch of them in one of three places, with the same results (every job carries
its own seed):
- here, one after the other (jobs=1 and no mp_context);
- in a local pool of `jobs` worker processes that die with this process (prctl PR_SET_PDEATHSIG:
  a killed server, CLI or test leaves no trial running behind it);
- on an existing Dask cluster (`scheduler="tcp://HOST:8786"`), one task per job. `distributed` is
  imported only then, so nothing else pays for it.

A worker process that dies under a job (a local pool breaks, a Dask worker is lost) costs only
that job: it is retried (`RETRIES` times; Dask reschedules a lost worker's task itself, up to its
`distributed.scheduler.allowed-failures`), and then its `lost(reason)` stands in for its result.
"""

from __future__ import annotations

import ctypes
import os
import signal
import sys
import uuid
from collections.abc import Callable, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass
from multiprocessing.context import BaseContext
from typing import Any, Generic, TypeVar

T = TypeVar("T")
PR_SET_PDEATHSIG = 1  # linux/prctl.h
RETRIES = 1  # times a job whose worker died is run again before it counts as lost


class ClusterUnreachable(RuntimeError):
    """No Dask scheduler answers at the address given (the message says which and why)."""


class JobLost(RuntimeError):
    """A job whose worker process died, again on every retry (and the job has no `lost`)."""


@dataclass(frozen=True)
class Job(Generic[T]):
    """fn(*args) -> T, run wherever the runner sends it. fn and args are pickled (to a local worker
    or a Dask worker); `key` stays here and says where the result belongs. `size`: how many
    things the job's result counts as (a progress bar's units); `first`: hand it out before the
    others (the long ones, so that workers end together); `lost(reason)`: the result that stands in
    for the job when its worker died on every try (None: the batch fails with JobLost)."""

    key: object
    fn: Callable[..., T]
    args: tuple[Any, ...] = ()
    size: int = 1
    first: bool = False
    lost: Callable[[str], T] | None = None

    def run(self) -> T:
        return self.fn(*self.args)

    def stand_in(self, reason: str) -> T:
        if self.lost is None:
            raise JobLost(f"job {self.key!r}: {reason}")
        return self.lost(reason)


def never() -> bool:
    return False


def run_jobs(
    work: Sequence[Job[T]],
    jobs: int = 1,
    on_result: Callable[[Job[T], T], None] | None = None,
    cancelled: Callable[[], bool] = never,
    mp_context: BaseContext | None = None,
    scheduler: str | None = None,
) -> list[T | None]:
    """The results of `work`, in its order; on_result(job, result) as each ends (in the order they end).
    Once `cancelled()`, no further job starts (None in its place); the running ones finish.
    scheduler: a Dask scheduler's address (then `jobs` and mp_context are not used)."""
    if scheduler:
        return _on_cluster(work, scheduler, on_result, cancelled)
    if jobs <= 1 and mp_context is None:
        return _here(work, on_result, cancelled)
    return _in_pool(work, jobs, on_result, cancelled, mp_context)


def _order(work: Sequence[Job[T]]) -> list[int]:
    """The order jobs are handed out: those marked `first`, then the rest, each in work order."""
    return sorted(range(len(work)), key=lambda i: not work[i].first)


def _here(
    work: Sequence[Job[T]], on_result: Callable[[Job[T], T], None] | None, cancelled: Callable[[], bool]
) -> list[T | None]:
    results: list[T | None] = [None] * len(work)
    for i, job in enumerate(work):
        if cancelled():
            break
        result = results[i] = job.run()
        if on_result:
            on_result(job, result)
    return results


# --- a local pool --------------------------------------------------------------------------------
def die_with_parent(parent_pid: int) -> None:
    """Pool initializer: SIGKILL this worker when its parent dies; exit now if it already has."""
    if sys.platform.startswith("linux"):
        libc = ctypes.CDLL(None, use_errno=True)
        if libc.prctl(PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0) != 0:
            raise OSError(ctypes.get_errno(), "prctl(PR_SET_PDEATHSIG) failed")
    if os.getppid() != parent_pid:  # the parent died before prctl took effect
        os._exit(1)


def worker_pool(jobs: int, mp_context: BaseContext | None = None) -> ProcessPoolExecutor:
    """A ProcessPoolExecutor of `jobs` workers that die with this process."""
    return ProcessPoolExecutor(
        max_workers=max(1, jobs), mp_context=mp_context, initializer=die_with_parent, initargs=(os.getpid(),)
    )


def _in_pool(
    work: Sequence[Job[T]],
    jobs: int,
    on_result: Callable[[Job[T], T], None] | None,
    cancelled: Callable[[], bool],
    mp_context: BaseContext | None,
) -> list[T | None]:
    """At most `jobs` jobs in flight (a cancel stops handing them out); a pool that breaks (a worker
    died) is replaced and the jobs it was running are run again, RETRIES times, then lost."""
    results: list[T | None] = [None] * len(work)
    queue, tries = _order(work), [0] * len(work)
    pool = worker_pool(jobs, mp_context)
    try:
        running: dict[Future[T], int] = {}
        while queue or running:
            while queue and len(running) < max(1, jobs) and not cancelled():
                i = queue.pop(0)
                running[pool.submit(work[i].fn, *work[i].args)] = i
            if not running:
                break
            done, _ = wait(running, return_when=FIRST_COMPLETED)
            broken = False
            for future in done:
                i = running.pop(future)
                try:
                    result = future.result()
                except BrokenProcessPool as exc:
                    broken = True
                    tries[i] += 1
                    if tries[i] <= RETRIES:
                        queue.insert(0, i)
                        continue
                    result = work[i].stand_in(f"the worker process died ({exc})")
                results[i] = result
                if on_result:
                    on_result(work[i], result)
            if broken:  # every job still in flight died with the pool: run them again in a new one
                for future, i in running.items():
                    future.cancel()
                    queue.insert(0, i)
                running.clear()
                pool.shutdown(wait=True, cancel_futures=True)
                pool = worker_pool(jobs, mp_context)
    finally:
        pool.shutdown(wait=True, cancel_futures=True)
    return results


# --- a Dask cluster ------------------------------------------------------------------------------
def _on_cluster(
    work: Sequence[Job[T]],
    scheduler: str,
    on_result: Callable[[Job[T], T], None] | None,
    cancelled: Callable[[], bool],
) -> list[T | None]:
    """One task per job on the cluster at `scheduler`, all submitted at once (the scheduler
    balances them; `first` ones at a higher priority); results as the cluster completes them.
    A task whose workers died (KilledWorker) is lost; Ctrl+C (or any error here) cancels the
    futures still pending, so the cluster stops working on this batch."""
    from distributed import Client, as_completed
    from distributed.scheduler import KilledWorker

    results: list[T | None] = [None] * len(work)
    batch = uuid.uuid4().hex[:8]
    try:
        client = Client(scheduler, set_as_default=False, timeout="20s")
    except (OSError, ValueError, TypeError) as exc:  # a timeout, a refused connection, a malformed address
        raise ClusterUnreachable(f"no Dask scheduler answers at {scheduler}: {exc}") from None
    with client:
        futures = {
            client.submit(
                work[i].fn,
                *work[i].args,
                key=f"hri-lab-{batch}-{i}",
                pure=False,
                retries=RETRIES,
                priority=1 if work[i].first else 0,
            ): i
            for i in _order(work)
        }
        try:
            for future in as_completed(list(futures), loop=client.loop):
                i = futures.pop(future)
                if future.status == "error" and isinstance(future.exception(), KilledWorker):
                    result = work[i].stand_in(f"the worker processes running it died ({future.exception()})")
                else:
                    result = future.result()
                results[i] = result
                if on_result:
                    on_result(work[i], result)
                if cancelled() and futures:
                    client.cancel(list(futures))
                    break
        finally:
            if futures:
                client.cancel(list(futures))
    return results
