"""The harness for the multi-robot env: every robot driven by a single-robot agent, per robot and per episode.

    from agents.evaluation.multi_robot import evaluate_multi
    rows = evaluate_multi(["astar-spacetime", "orca", "oracle-prioritized"], ["multi-circle-4"], [None], 20, "results/multi")

An agent name may carry settings over its own after ``?`` (``"astar-spacetime?robot_margin=0.4"``, several
joined by ``&``): the variant runs and is labelled by that name.

Each episode is ``pathplan_env.multi_robot.parallel_env(scenario=...)`` reset with the split's seed
(``pathplan_env.scenarios.splits.episode_seeds``: the same disjoint test and validation seeds as the
single-robot harness). An agent entry is a name for every robot (decentralised: each robot its own
instance, built by ``agents.make(name, env.robot_env(agent), seed=seed + i)``) or a mapping robot ->
name (``{"robot_0": "orca", "robot_1": "astar-spacetime"}``; a robot left out takes ``"*"``'s).
``oracle-prioritized`` (``agents.oracles.prioritized``) is the privileged reference: not a bound.

Per robot: success, collision and with what (robot, obstacle, wall), time to goal, path length; per
episode: all arrived, makespan (the last arrival's time, when all arrived), sum of times (each
robot's time to its goal, its contact, or the episode's end). Rates carry Wilson intervals. Episodes are appended to
``multi_episodes.jsonl`` as they finish (``resume=True`` skips those on record; ``workers`` run them
on the single harness's process pool, ``agents.evaluation.executors``, or ``backend="ray"`` on its Ray
executor, ``agents.evaluation.ray_backend``); ``multi_summary.json`` and ``report.html``
(``agents.evaluation.report.multi_page``: the table, the episode list and, recorded, a player of every robot) at the end.
"""

from __future__ import annotations

import json
import math
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from agents.evaluation.episodes import _policy, _seed_global_generators
from agents.evaluation.executors import run_jobs
from agents.evaluation.ray_backend import require_ray
from agents.evaluation.recording import open_multi_records
from agents.evaluation.report.multi_page import write_multi_report
from agents.evaluation.run_log import LogWriter, RunLock, results_on_record, run_folder
from agents.evaluation.settings import BACKENDS
from agents.evaluation.statistics import wilson_interval
from agents.registry import split_settings
from pathplan_env.scenarios.splits import episode_seeds

LOG_NAME, SUMMARY_NAME = "multi_episodes.jsonl", "multi_summary.json"
#: Agents of the multi-robot env only, by name (the single-robot registry's names work too).
MULTI_AGENTS = {"oracle-prioritized": "agents.oracles.prioritized:PrioritizedOracle"}


@dataclass
class RobotResult:
    robot: str
    agent: str
    success: bool
    collision: bool
    collision_with: str | None
    time: float  # s: to the goal, to the contact, or to the episode's end
    path_length: float
    steps: int


@dataclass
class MultiEpisodeResult:
    agent: str  # the entry's label
    scenario: str
    delta_d: float | None
    episode: int
    seed: int
    all_arrived: bool
    makespan: float | None  # the last arrival's time when all arrived, else None
    sum_of_times: float
    robots: list[RobotResult] = field(default_factory=list)
    plan_ms: float = 0.0  # mean planning time per robot step


def agent_label(entry) -> str:
    if isinstance(entry, str):
        return entry
    return "+".join(f"{k}={v}" for k, v in sorted(entry.items()))


def _build(name: str, robot_env, seed: int):
    name, settings = split_settings(name)
    if settings:
        import agents

        return agents.make(name, robot_env, seed=seed, **settings)
    if name in MULTI_AGENTS:
        module, attribute = MULTI_AGENTS[name].split(":")
        import importlib

        return getattr(importlib.import_module(module), attribute)(robot_env, seed=seed)
    import agents

    return agents.make(name, robot_env, seed=seed)


def agents_for(entry, possible_agents: list[str]) -> dict[str, str]:
    """Each robot's agent name from an entry (a name, or a mapping robot -> name with ``"*"`` for the rest).

    :raises ValueError: naming the robot that has no agent, or a robot the env does not have.
    """
    if isinstance(entry, str):
        return dict.fromkeys(possible_agents, entry)
    if not isinstance(entry, dict):
        raise ValueError(f"agent must be a name or a mapping robot -> name, got {entry!r}")
    unknown = sorted(set(entry) - set(possible_agents) - {"*"})
    if unknown:
        raise ValueError(f"agent: no robots {unknown} in this env (robots: {possible_agents})")
    out = {}
    for robot in possible_agents:
        name = entry.get(robot, entry.get("*"))
        if not isinstance(name, str):
            raise ValueError(f"agent[{robot!r}]: no agent for this robot (give it one, or '*')")
        out[robot] = name
    return out


def run_multi_episode(entry, scenario, delta_d: float | None, episode: int, seed: int, env_options: dict | None = None,
                      record: bool = False, watch=None) -> MultiEpisodeResult:  # fmt: skip
    """One episode: every robot driven by its own agent (built for its robot env, seeded ``seed + i``).

    ``record``: the result carries the episode as ``result.trajectory`` (a
    :class:`pathplan_env.records.multi.MultiEpisode`; not a field, so the row is the same either way).
    ``watch(env, plans)``, if given, is called before each step with each live robot's plan (its agent's
    ``last_plan``) and once at the end with ``None`` (``scripts/render_multi_robot.py`` draws frames so)."""
    from pathplan_env.multi_robot import parallel_env

    env = parallel_env(scenario=scenario, delta_d=delta_d, **(env_options or {}))
    observations, reset_infos = env.reset(seed=seed)
    names = agents_for(entry, env.possible_agents)
    _seed_global_generators(seed)
    policies, built = {}, {}
    for i, robot in enumerate(env.possible_agents):
        policy = built[robot] = _build(names[robot], env.robot_env(robot), seed + i)
        if callable(getattr(policy, "reset", None)):
            policy.reset()
        policies[robot] = [_policy(policy), None, np.ones(1, dtype=bool)]
    recorder = None
    if record:
        from pathplan_env.records.multi import MultiEpisodeRecorder

        recorder = MultiEpisodeRecorder(env, reset_infos, names)
    results: dict[str, RobotResult] = {}
    plan_seconds, plan_calls = 0.0, 0
    steps = 0
    while env.agents:
        actions = {}
        for robot in env.agents:
            call, state, start = policies[robot]
            begin = time.perf_counter()
            actions[robot], policies[robot][1] = call(observations[robot], state, start)
            plan_seconds += time.perf_counter() - begin
            plan_calls += 1
            policies[robot][2] = np.zeros(1, dtype=bool)
        if recorder is not None or watch is not None:
            plans = {robot: getattr(built[robot], "last_plan", None) for robot in env.agents}
            if watch is not None:
                watch(env, plans)
            if recorder is not None:
                recorder.before_step(actions, plans)
        observations, _, terminations, truncations, infos = env.step(actions)
        if recorder is not None:
            recorder.after_step(terminations, truncations, infos)
        steps += 1
        for robot, info in infos.items():
            if terminations[robot] or truncations[robot]:
                results[robot] = RobotResult(robot, names[robot], bool(info["is_success"]), bool(info["collision"]), info["collision_with"],
                                             float(info["time"]), float(info["path_length"]), steps)  # fmt: skip
    if watch is not None:
        watch(env, None)
    robots = [results[robot] for robot in env.possible_agents]
    arrived = all(r.success for r in robots)
    result = MultiEpisodeResult(agent_label(entry), scenario_label(scenario), delta_d, episode, seed, arrived,
                                max(r.time for r in robots) if arrived else None, sum(r.time for r in robots), robots,
                                1000.0 * plan_seconds / max(plan_calls, 1))  # fmt: skip
    if recorder is not None:
        row = asdict(result)
        row.pop("plan_ms")  # (the record's bytes are the same on every run: its checksum too)
        result.trajectory = recorder.finish(row)
    return result


def scenario_label(scenario) -> str:
    return str(scenario) if isinstance(scenario, str) else getattr(scenario, "name", "custom")


def job_key(job) -> tuple:
    """A job's (or its result's) identity in the log and the record file: agent label, scenario, Δd, episode."""
    if isinstance(job, MultiEpisodeResult):
        return (job.agent, job.scenario, job.delta_d, job.episode)
    return (agent_label(job[0]), scenario_label(job[1]), job[2], job[3])


def _run_job(job) -> MultiEpisodeResult:
    return run_multi_episode(*job)


def _execute(jobs: list, on_result, workers: int, backend: str, address: str | None) -> None:
    if backend == "ray":
        from agents.evaluation.ray_backend import run_jobs_on_ray

        run_jobs_on_ray(jobs, on_result, address=address, num_cpus=workers, runner=_run_job, decode=_from_json)
    else:
        run_jobs(jobs, workers, on_result, runner=_run_job)


def _from_json(row: dict) -> MultiEpisodeResult:
    row = dict(row)
    row["robots"] = [RobotResult(**r) for r in row["robots"]]
    return MultiEpisodeResult(**row)


def summarize_multi(results: list[MultiEpisodeResult]) -> list[dict]:
    """Per (scenario, Δd, agent): all-arrived and per-robot rates with Wilson intervals, makespan
    (mean over the episodes where all arrived), sum of times, collisions by kind."""
    cells: dict[tuple, list[MultiEpisodeResult]] = {}
    for r in results:
        cells.setdefault((r.scenario, r.delta_d, r.agent), []).append(r)
    rows = []
    for (scenario, delta_d, agent), episodes in sorted(cells.items(), key=lambda kv: (kv[0][0], -1 if kv[0][1] is None else kv[0][1], kv[0][2])):
        n = len(episodes)
        robots = [robot for e in episodes for robot in e.robots]
        arrived = sum(e.all_arrived for e in episodes)
        successes = sum(r.success for r in robots)
        makespans = [e.makespan for e in episodes if e.all_arrived]
        rows.append({
            "scenario": scenario, "delta_d": delta_d, "agent": agent, "episodes": n,
            "all_arrived": arrived / n, "all_arrived_ci95": list(wilson_interval(arrived, n)),
            "robot_success": successes / len(robots), "robot_success_ci95": list(wilson_interval(successes, len(robots))),
            "collisions": {kind: sum(r.collision_with == kind for r in robots) / len(robots) for kind in ("robot", "obstacle", "wall")},
            "makespan": float(np.mean(makespans)) if makespans else math.nan,
            "sum_of_times": float(np.mean([e.sum_of_times for e in episodes])),
            "path_length": float(np.mean([r.path_length for r in robots if r.success])) if successes else math.nan,
            "plan_ms": float(np.mean([e.plan_ms for e in episodes])),
        })  # fmt: skip
    return rows


def evaluate_multi(entries: list, scenarios: list, deltas: list[float | None], episodes: int, out: str | Path | None = None, *,
                   seed: int = 0, split: str = "test", workers: int = 1, resume: bool = False,
                   env_options: dict | None = None, backend: str = "process", address: str | None = None,
                   record: bool = False) -> list[dict]:  # fmt: skip
    """Run every (entry, scenario, Δd) cell on the split's episodes; write them to ``out`` (if given)
    and return :func:`summarize_multi`'s rows. ``backend``: ``"process"`` (a local pool of ``workers``)
    or ``"ray"`` (a local Ray of ``workers`` CPUs, or the cluster at ``address``), as ``evaluate``'s.
    ``record``: every episode is kept in ``out/multi_episodes.h5`` as it finishes (``pathplan_env.records``,
    as ``evaluate``'s ``record``; with ``resume`` an episode on the log but not in the file runs again)."""
    if record and out is None:
        raise ValueError("record=True (--record) needs an out folder (--out) to keep the records in")
    if backend not in BACKENDS:
        raise ValueError(f"backend must be 'process' or 'ray', got {backend!r}")
    if backend == "ray":
        require_ray()  # before any work
    if split == "crowdnav":
        raise ValueError("split: the multi-robot scenes are drawn from the seeds: use 'test' or 'validation'")
    seeds = episode_seeds(split, seed, episodes)
    jobs = [(entry, scenario, delta_d, i, s, env_options, record) for entry in entries for scenario in scenarios for delta_d in deltas
            for i, s in enumerate(seeds)]  # fmt: skip
    results: list[MultiEpisodeResult] = []
    if out is None:
        _execute(jobs, results.append, workers, backend, address)
        return summarize_multi(results)
    existed = Path(out).is_dir()
    try:
        folder = run_folder(out)
    except OSError as error:  # (a folder that cannot be made: before any work, as other bad input)
        raise ValueError(f"out: cannot make the run folder {out} ({error.strerror})") from None
    log = folder / LOG_NAME
    began = time.perf_counter()
    with RunLock(folder):
        records = open_multi_records(folder, resume and log.exists(), record)  # a bad or unwritable file is refused here, before any episode
        try:
            results, left = results_on_record(log, jobs, job_key, lambda line: (line["agent"], line["scenario"], line["delta_d"], line["episode"]),
                                              _from_json, resume, existed, records.has, fields=("agent", "robots"))  # fmt: skip
            sink = LogWriter(log, on_record=len(results))

            def keep(result: MultiEpisodeResult) -> None:
                # the log line first, as the single-robot harness: a run killed before the record is written runs
                # that episode again on --resume; the other order would append its record a second time
                sink.write(asdict(result))
                results.append(result)
                records.write(result, job_key(result))  # (takes the trajectory off the result)

            try:
                _execute(left, keep, workers, backend, address)
            finally:
                sink.close()
        finally:
            records.close()
        rows = summarize_multi(results)
        (folder / SUMMARY_NAME).write_text(json.dumps({"split": split, "seed": seed, "episodes": episodes, "rows": rows}, indent=1, default=str))
        config = {"agents": [agent_label(e) for e in entries], "scenarios": [scenario_label(s) for s in scenarios], "delta_d": list(deltas),
                  "episodes": episodes, "seed": seed, "split": split, "wall_seconds": round(time.perf_counter() - began, 1)}  # fmt: skip
        write_multi_report(folder, table(rows), results, config, records.replays())
    return rows


def table(rows: list[dict]) -> str:
    """The summary rows as a Markdown table."""
    lines = ["| scenario | Δd | agent | episodes | all arrived (95% CI) | robots arrived | robot collisions | makespan (s) | sum of times (s) |",
             "|---|---|---|---|---|---|---|---|---|"]  # fmt: skip
    for r in rows:
        lo, hi = r["all_arrived_ci95"]
        c = r["collisions"]
        delta = "own" if r["delta_d"] is None else r["delta_d"]
        collisions = f"robot {c['robot']:.2f}, obstacle {c['obstacle']:.2f}, wall {c['wall']:.2f}"
        lines.append(f"| {r['scenario']} | {delta} | {r['agent']} | {r['episodes']} | {r['all_arrived']:.2f} ({lo:.2f}-{hi:.2f}) | "
                     f"{r['robot_success']:.2f} | {collisions} | {r['makespan']:.1f} | {r['sum_of_times']:.1f} |")  # fmt: skip
    return "\n".join(lines)


__all__ = [
    "MULTI_AGENTS", "MultiEpisodeResult", "RobotResult", "agents_for", "evaluate_multi", "run_multi_episode", "split_settings",
    "summarize_multi", "table",
]  # fmt: skip
