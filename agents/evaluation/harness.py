"""The evaluation harness as a library: agents x scenarios x Δd on fixed test episodes, with limits.

    from agents.evaluation import evaluate
    rows = evaluate(["pso-spacetime", "velocity-obstacle"], ["random"], [0.5, 1.0], episodes=100, out="results/mine")
    rows = evaluate([MyPlanner, ("mine-tuned", MyPlanner(gain=2))], ["scenes/corridor.yaml"], [None], 20, "results/own")
    rows = evaluate(["dwa"], ["random"], [0.25], 20, "results/u", EvaluationSettings(workers=2, env_options={"robot": "unicycle"}))

How a run is made (seed, split, workers, backend, env options, resume, plots) is one
:class:`~agents.evaluation.settings.EvaluationSettings` record; its fields may also be given by name.

Agents and scenarios come in many forms (:mod:`agents.evaluation.entrants`), each named by a label.
Every (agent, scenario, Δd) cell runs the same episodes: episode ``i`` uses seed
``pathplan_env.scenarios.splits.heldout_seeds(seed, episodes)[i]`` for the env (scene, directions) and the
agent, so results do not depend on the number of workers (``split="validation"``: the validation
seeds; ``split="crowdnav"``: CrowdNav's test case ``i`` as the scene, the test seeds for the rest).
``env_options`` are ``gym.make`` keywords given to every episode's env. The privileged ``oracle-clairvoyant``
runs on the same episodes to give each cell its physical limit, custom scenarios included. Episodes are appended to
``episodes.jsonl`` as they finish, so a crash loses nothing and ``resume=True`` continues a run
(one run a folder at a time; a killed worker's episodes run again: :mod:`.run_log`, :mod:`.executors`);
``summary.json``, ``episodes.csv``, ``table.md`` (every cell's row) and plots are written at the end. ``scripts/evaluate.py`` is the
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

from agents.evaluation.checks import check_run
from agents.evaluation.entrants import resolve_agents
from agents.evaluation.executors import run_jobs
from agents.evaluation.jobs import Job, result_id
from agents.evaluation.progress import interleaved
from agents.evaluation.ray_backend import require_ray
from agents.evaluation.recording import open_run_records
from agents.evaluation.records import LIMIT_AGENT, EpisodeResult, delta_order
from agents.evaluation.report import write_report
from agents.evaluation.reporting import markdown_table
from agents.evaluation.run_log import LOG_NAME, LogWriter, RunLock, results_on_record, run_folder
from agents.evaluation.settings import EvaluationSettings
from agents.evaluation.statistics import summarize
from agents.provenance import versions
from pathplan_env import _numba_cache

#: The long table of every cell, in the run's folder.
TABLE_NAME = "table.md"


def _summarize(results: list[EpisodeResult]) -> list[dict]:
    # a scenario's own speeds (Δd None) are cells of their own, summarised apart: None and numbers do not sort together
    own = [r for r in results if r.delta_d is None]
    rows = summarize([r for r in results if r.delta_d is not None]) + (summarize(own) if own else [])
    return sorted(rows, key=lambda r: (r["scenario"], r["agent"], delta_order(r["delta_d"])))


def evaluate(
    agent_names: list, scenarios: list, deltas: list[float | None], episodes: int, out: str | Path,
    settings: EvaluationSettings | None = None, **options,
) -> list[dict]:  # fmt: skip
    """Run the cells, write the results to ``out`` and return the summary rows (see the module doc).

    ``agent_names``: registered names, ``"name@model_path"``, ``"module:attribute"``,
    ``"path/to/file.py:attribute"``, classes or factories, or objects with SB3's ``predict``;
    ``scenarios``: preset names, ``Scenario`` objects, their dicts, or JSON/YAML files of them. Each
    may be labelled (``(label, entry)``); results name them by label (:mod:`agents.evaluation.entrants`).
    ``deltas``: Δd values; ``None`` (or ``"own"``) runs a scenario at its own obstacle speeds.
    ``settings``: how the run is made (seed, split, workers, backend, env options, resume, ...):
    an :class:`~agents.evaluation.settings.EvaluationSettings`, the defaults when ``None``.
    ``options``: its fields by name (``workers=4``), replacing the record's; a name that is no field
    is a ``ValueError``. With ``record=True`` every episode's trajectory is kept in ``out/episodes.h5``
    (:mod:`agents.evaluation.recording`) and the rows gain the social-navigation metrics; every run
    writes ``out/report.html``."""
    from pathplan_env.scenarios.episode_sources import source_of

    if settings is not None and not isinstance(settings, EvaluationSettings):
        raise ValueError(f"settings must be an EvaluationSettings, got {type(settings).__name__}")
    settings = (settings or EvaluationSettings()).with_options(**options)
    if settings.backend == "ray":
        require_ray()  # before any work
    seed, split, n_obstacles, workers = settings.seed, settings.split, settings.n_obstacles, settings.workers
    run = check_run(agent_names, scenarios, deltas, episodes, seed=seed, split=split, n_obstacles=n_obstacles,
                    workers=workers, agent_kwargs=settings.agent_kwargs, transport=settings.transport,
                    env_options=settings.env_options)  # fmt: skip
    entrants, own, options = list(run.agents), run.overrides, run.env_options
    limit_spec = resolve_agents([LIMIT_AGENT])[0]
    for spec in entrants:
        if spec.label == LIMIT_AGENT and (spec.target is not limit_spec.target or spec.kwargs):
            raise ValueError(f"agent_names: the label {LIMIT_AGENT!r} is the physical limit's; give this agent another")
    if settings.limit and LIMIT_AGENT not in own:
        entrants.append(limit_spec)
        own[LIMIT_AGENT] = {}  # the kwargs are meant for the agents asked for
    keep = settings.record
    source = source_of(split)
    seeds = source.episode_seeds(seed, episodes)
    jobs = [Job(a, s, d, i, e, s.obstacles(n_obstacles), own[a.label], options, split, keep)
            for a in entrants for s in run.scenarios for d in run.deltas for i, e in enumerate(seeds)]  # fmt: skip
    jobs = interleaved(jobs)  # every cell's first episode early: the progress estimate reads them
    key_of = {job.result_id(): job.key() for job in jobs}
    obstacles = {s.label: s.obstacles(n_obstacles) for s in run.scenarios}  # a preset's own count, else the run's
    existed = Path(out).is_dir()
    if settings.resume and not existed:
        print(f"resume: {out} does not exist, so there is no run to continue; starting a new run there", file=sys.stderr)
    out = run_folder(out)
    log = out / LOG_NAME
    with RunLock(out):
        records = open_run_records(out, settings.resume and log.exists(), keep)
        results, jobs = results_on_record(log, jobs, lambda job: key_of[job.result_id()], lambda record: tuple(record["job"]),
                                          lambda record: EpisodeResult(**record["result"]), settings.resume, existed, records.has)  # fmt: skip
        on_record = len(results)
        if jobs and not _numba_cache.is_warm():
            print("compiling planners once (numba; later runs load them from its cache): the first episodes wait for it", file=sys.stderr)
        start = time.perf_counter()
        sink = LogWriter(log, on_record=len(results))

        def record(res: EpisodeResult) -> None:
            sink.write({"job": list(key_of[result_id(res)]), "result": asdict(res)})
            results.append(res)
            records.write(res, key_of[result_id(res)])

        try:
            if settings.backend == "ray":
                from agents.evaluation.ray_backend import run_jobs_on_ray

                run_jobs_on_ray(jobs, record, address=settings.address, num_cpus=workers)
            else:
                run_jobs(jobs, workers, record)
        except KeyboardInterrupt:
            print(f"\ninterrupted: {sink.count} episodes on record in {log}; the same command with --resume (resume=True) continues",
                  file=sys.stderr)  # fmt: skip
            raise
        finally:
            sink.close()
            records.close()
        elapsed = time.perf_counter() - start
        results.sort(key=lambda r: (r.agent, r.scenario, delta_order(r.delta_d), r.episode))
        rows = _summarize(results)
        rows = records.add_social_metrics(rows)
        config = (settings.config or {}) | {"agents": [a.label for a in entrants], "scenarios": [s.label for s in run.scenarios],
                                   "agent_sources": {a.label: a.source for a in entrants},
                                   "custom_scenarios": {s.label: s.definition for s in run.scenarios if s.definition},
                                   "delta_d": run.deltas, "episodes": episodes,
                                   "seed": seed, "split": split, "n_obstacles": n_obstacles, "scenario_n_obstacles": obstacles, "workers": workers,
                                   "agent_kwargs": settings.agent_kwargs or {}, "env_options": options, "episode_seeds": [seeds[0], seeds[-1]],
                                   **source.describe(episodes),
                                   "wall_seconds": round(elapsed, 1), "episodes_run": len(results) - on_record,
                                   "episodes_on_record": on_record}  # fmt: skip
        (out / "summary.json").write_text(json.dumps({"results": rows, "config": config, "versions": versions()}, indent=2))
        (out / TABLE_NAME).write_text(markdown_table(rows) + "\n")  # every cell's row: the long table a terminal buries the rest under
        with open(out / "episodes.csv", "w", newline="") as f:
            names = [k for k in asdict(results[0]) if k != "plan_ms"] + ["plan_ms_median"]
            writer = csv.DictWriter(f, fieldnames=names)
            writer.writeheader()
            for res in results:
                row = {k: v for k, v in asdict(res).items() if k != "plan_ms"}
                writer.writerow(row | {"plan_ms_median": float(np.median(res.plan_ms))})
        if settings.plots:
            from agents.evaluation.reporting import plot

            plot(rows, out, robot=str(options.get("robot", "holonomic")))
        write_report(out, rows, results, config, records.replays())
    return rows
