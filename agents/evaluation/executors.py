"""The local executor: ``run_episode`` jobs on a process pool, results streamed as they finish
(``ray_backend`` is the other executor, over the same jobs)."""

from __future__ import annotations

import os
import sys
from multiprocessing import get_context

from tqdm import tqdm

from agents.evaluation.episodes import run_episode
from agents.evaluation.records import EpisodeResult


def _init_worker() -> None:
    os.environ["OMP_NUM_THREADS"] = "1"  # one torch thread per worker: the workers already fill the cores


def _run_job(job) -> EpisodeResult:
    return run_episode(*job)


def run_jobs(jobs: list[tuple], workers: int, on_result) -> None:
    """Run ``jobs`` (``run_episode``'s arguments) on a local process pool, calling ``on_result``
    with each finished episode as it arrives (any order)."""
    if workers > 1:
        with get_context("spawn").Pool(workers, initializer=_init_worker) as pool:
            for res in tqdm(pool.imap_unordered(_run_job, jobs, chunksize=1), total=len(jobs), desc="episodes", file=sys.stderr):
                on_result(res)
    else:
        for job in tqdm(jobs, desc="episodes", file=sys.stderr):
            on_result(_run_job(job))
