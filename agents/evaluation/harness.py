"""The evaluation harness as a library: agents x scenarios x Δd on fixed test episodes, with limits.

    from agents.evaluation import evaluate
    rows = evaluate(["pso-spacetime", "velocity-obstacle"], ["random"], [0.5, 1.0], episodes=100, out="results/mine")

Every (agent, scenario, Δd) cell runs the same episodes: episode ``i`` uses seed
``pathplan_env.splits.heldout_seeds(seed, episodes)[i]`` for the env (scene, directions) and the
agent, so results do not depend on the number of workers. The privileged ``oracle-clairvoyant``
runs on the same episodes to give each cell its physical limit. Episodes are appended to
``episodes.jsonl`` as they finish, so a crash loses nothing and ``resume=True`` continues a run;
``summary.json``, ``episodes.csv`` and plots are written at the end. ``scripts/evaluate.py`` is the
command line over this module.
"""

from __future__ import annotations

import csv
import json
import sys
import time
from dataclasses import asdict
from pathlib import Path

import numpy as np

from ..provenance import versions
from .checks import check_run, resolve_agent_kwargs
from .executors import run_jobs
from .records import LIMIT_AGENT, EpisodeResult
from .statistics import summarize


def _job_key(job) -> tuple:
    agent, scenario, delta_d, episode, seed, n_obstacles, overrides = job
    n = None if n_obstacles is None else int(n_obstacles)
    return (agent, scenario, float(delta_d), int(episode), int(seed), n, json.dumps(overrides, sort_keys=True))


def evaluate(
    agent_names: list[str], scenarios: list[str], deltas: list[float], episodes: int, out: str | Path, *,
    seed: int = 0, split: str = "test", n_obstacles: int | None = None, workers: int = 1, agent_kwargs: dict | None = None,
    limit: bool = True, resume: bool = False, plots: bool = True, config: dict | None = None,
    backend: str = "process", address: str | None = None,
) -> list[dict]:  # fmt: skip
    """Run the cells, write the results to ``out`` and return the summary rows (see the module doc).

    ``backend``: ``"process"`` (a local pool of ``workers`` processes) or ``"ray"`` (a local Ray, or
    the cluster at ``address``; :mod:`agents.evaluation.ray_backend`). Both run the same jobs: same results."""
    from pathplan_env.splits import heldout_seeds, validation_seeds

    if backend not in ("process", "ray"):
        raise ValueError(f"backend must be 'process' or 'ray', got {backend!r}")
    if backend == "ray":
        try:
            import ray  # noqa: F401  (checked before any work)
        except ImportError:
            raise ValueError('--backend ray needs Ray: pip install -e ".[ray]"') from None

    check_run(agent_names, scenarios, deltas, episodes, seed=seed, split=split, n_obstacles=n_obstacles, workers=workers)
    agent_names = list(agent_names)
    own = resolve_agent_kwargs(agent_names, agent_kwargs or {})
    if limit and LIMIT_AGENT not in agent_names:
        agent_names.append(LIMIT_AGENT)
        own[LIMIT_AGENT] = {}  # the kwargs are meant for the agents asked for
    seeds = (heldout_seeds if split == "test" else validation_seeds)(seed, episodes)
    jobs = [(a, s, d, i, e, n_obstacles, own[a]) for a in agent_names for s in scenarios for d in deltas for i, e in enumerate(seeds)]
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    log = out / "episodes.jsonl"
    results: list[EpisodeResult] = []
    if resume and log.exists():
        wanted = {_job_key(job) for job in jobs}
        for line in log.read_text().splitlines():
            record = json.loads(line)
            key, res = tuple(record["job"]), EpisodeResult(**record["result"])
            if key in wanted:
                results.append(res)
                wanted.discard(key)
        done = {_job_key(job) for job in jobs} - wanted
        jobs = [job for job in jobs if _job_key(job) not in done]
        print(f"resuming: {len(results)} episodes on record, {len(jobs)} to run", file=sys.stderr)
    elif log.exists():
        log.unlink()
    start = time.perf_counter()
    with open(log, "a") as sink:

        def record(res: EpisodeResult) -> None:
            results.append(res)
            job = (res.agent, res.scenario, res.delta_d, res.episode, res.seed, n_obstacles, own[res.agent])
            sink.write(json.dumps({"job": list(_job_key(job)), "result": asdict(res)}) + "\n")
            sink.flush()

        if backend == "ray":
            from .ray_backend import run_jobs_on_ray

            run_jobs_on_ray(jobs, record, address=address, num_cpus=workers)
        else:
            run_jobs(jobs, workers, record)
    elapsed = time.perf_counter() - start
    results.sort(key=lambda r: (r.agent, r.scenario, r.delta_d, r.episode))
    rows = summarize(results)
    config = (config or {}) | {"agents": agent_names, "scenarios": scenarios, "delta_d": deltas, "episodes": episodes,
                               "seed": seed, "split": split, "n_obstacles": n_obstacles, "workers": workers,
                               "agent_kwargs": agent_kwargs or {}, "episode_seeds": [seeds[0], seeds[-1]],
                               "wall_seconds": round(elapsed, 1)}  # fmt: skip
    (out / "summary.json").write_text(json.dumps({"results": rows, "config": config, "versions": versions()}, indent=2))
    with open(out / "episodes.csv", "w", newline="") as f:
        names = [k for k in asdict(results[0]) if k != "plan_ms"] + ["plan_ms_median"]
        writer = csv.DictWriter(f, fieldnames=names)
        writer.writeheader()
        for res in results:
            row = {k: v for k, v in asdict(res).items() if k != "plan_ms"}
            writer.writerow(row | {"plan_ms_median": float(np.median(res.plan_ms))})
    if plots:
        from .reporting import plot

        plot(rows, out)
    return rows
