"""The local executor: ``run_episode`` jobs on a process pool, results streamed as they finish
(``ray_backend`` is the other executor, over the same jobs).

A worker that dies (the OOM killer, a segfault) breaks the pool; the episodes it had not returned
run again in a new pool, up to :data:`MAX_POOL_RESTARTS` times, after which the run ends with a
:class:`WorkerLost` error naming how many episodes are left (those finished are on record).
"""

from __future__ import annotations

import os
import signal
import sys
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from multiprocessing import get_context

from agents.evaluation.episodes import run_episode
from agents.evaluation.progress import Progress
from agents.evaluation.records import EpisodeResult

#: How many times a broken pool is replaced before the run gives up.
MAX_POOL_RESTARTS = 3


class WorkerLost(RuntimeError):
    """A worker process died more often than the pool restarts allow."""


def _init_worker() -> None:
    os.environ["OMP_NUM_THREADS"] = "1"  # one torch thread per worker: the workers already fill the cores
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the parent's to handle: one message, not a traceback a worker


def _run_job(job) -> EpisodeResult:
    return run_episode(*job)


def run_jobs(jobs: list, workers: int, on_result, runner=_run_job) -> None:
    """Run ``jobs`` (``run_episode``'s arguments, e.g. :class:`~agents.evaluation.jobs.Job`) on a
    local pool of ``workers`` processes, calling ``on_result`` with each finished episode as it
    arrives (any order). ``runner(job)`` runs one job (tests pass one whose worker dies)."""
    if workers <= 1:
        with Progress(jobs, 1) as bar:
            for job in jobs:
                result = runner(job)
                on_result(result)
                bar.update(result)
        return
    left = list(jobs)
    with Progress(jobs, workers) as bar:
        for restart in range(MAX_POOL_RESTARTS + 1):
            left = _run_pool(left, workers, on_result, runner, bar)
            if not left:
                return
            if restart < MAX_POOL_RESTARTS:
                print(f"a worker process died (killed, or out of memory?); running its {len(left)} unfinished episodes again", file=sys.stderr)
    raise WorkerLost(f"worker processes died {MAX_POOL_RESTARTS + 1} times; {len(left)} episodes did not finish (the finished ones are "
                     f"on record: rerun with --resume, or with fewer --workers if memory ran out)")  # fmt: skip


def _run_pool(jobs: list, workers: int, on_result, runner, bar) -> list:
    """Run ``jobs`` on one pool; the jobs left unfinished if the pool broke."""
    pool = ProcessPoolExecutor(min(workers, len(jobs)), mp_context=get_context("spawn"), initializer=_init_worker)
    pending = {pool.submit(runner, job): job for job in jobs}
    interrupted = False
    try:
        while pending:
            done, _ = wait(pending, return_when=FIRST_COMPLETED)
            broken = []
            for future in done:
                job = pending.pop(future)
                if isinstance(future.exception(), BrokenProcessPool):
                    broken.append(job)  # not finished: runs again
                    continue
                result = future.result()  # an agent's own error ends the run, as with one worker
                on_result(result)
                bar.update(result)
            if broken:
                for future in list(pending):  # keep what finished before the break
                    if future.done() and future.exception() is None:
                        on_result(future.result())
                        bar.update(future.result())
                        del pending[future]
                return broken + list(pending.values())
        return []
    except KeyboardInterrupt:
        # the running episodes are lost either way: stop their workers now rather than wait for them
        # (ProcessPoolExecutor has no public way before Python 3.14's terminate_workers)
        for process in list(getattr(pool, "_processes", {}).values()):
            process.terminate()
        interrupted = True
        raise
    finally:  # not waiting for killed workers: one killed mid-write leaves the pool's queues locked
        pool.shutdown(wait=not interrupted, cancel_futures=True)
