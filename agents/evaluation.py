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
import math
import os
import platform
import subprocess
import sys
import time
from dataclasses import asdict, dataclass, field
from multiprocessing import get_context
from pathlib import Path

import numpy as np
from tqdm import tqdm

from pathplan_env.crowdnav import DISCOMFORT_DISTANCE  # CrowdNav's: a step closer than this is one in danger

from .statistics import LIMIT_AGENT, summarize

#: Preset runs (``scripts/evaluate.py --suite``); the clairvoyant limit is added to every one.
SUITES = {
    "default": dict(  # oracle-static (blind to motion, slow) is in "large" only: make demo stays within 3 minutes
        agents="straight,velocity-obstacle,pso,abc,pso-predictive,abc-predictive,astar-spacetime,pso-spacetime,abc-spacetime,ppo",
        scenarios="random,paper-case-3",
        delta_d="0,0.1,0.25,0.5,1,2",
        episodes=50,
    ),
    # CrowdNav's protocol (Chen et al. 2019): its 500 test episodes per setting, humans at their own
    # 1 m/s (Δd = 1 m/s x 0.25 s / 0.3 m = 5/6), robot invisible and visible
    "crowdnav": dict(
        agents="straight,velocity-obstacle,orca,pso,abc,pso-predictive,abc-predictive,astar-spacetime,pso-spacetime,abc-spacetime,"
        "astar-crowd,ppo",
        scenarios="crowdnav-circle-crossing,crowdnav-square-crossing,crowdnav-circle-crossing-visible,crowdnav-square-crossing-visible",
        delta_d="0.8333333333333334",
        episodes=500,
    ),
    "large": dict(
        agents="straight,velocity-obstacle,oracle-static,pso,abc,pso-vanilla,abc-vanilla,pso-predictive,abc-predictive,"
        "astar-spacetime,pso-spacetime,abc-spacetime,ppo",
        scenarios="random,paper-case-1,paper-case-2,paper-case-3",
        delta_d="0,0.1,0.125,0.25,0.5,1,2",
        episodes=100,
    ),
}


@dataclass
class EpisodeResult:
    agent: str
    scenario: str
    delta_d: float
    episode: int
    seed: int
    success: bool
    collision: bool
    timeout: bool
    steps: int
    path_length: float
    shortest_path: float  # exact static shortest path from start to the goal's centre (m)
    path_length_ratio: float
    time_to_goal: float
    min_clearance: float
    plan_ms: list[float] = field(repr=False)
    verdict: str = ""  # the clairvoyant oracle's: plan, lost, undetermined, or reactive (no limit)
    # CrowdNav's discomfort: steps (before the last) whose clearance fell below DISCOMFORT_DISTANCE
    discomfort_steps: int = 0
    discomfort_clearance_sum: float = 0.0  # of those steps' smallest clearances (m)



_WARMED: set[str] = set()  # agents whose compiled code this process has already loaded


def warm_up(agent_name: str, overrides: dict) -> None:
    """One plan on a throwaway episode, so that numba's compilation or cache load (seconds) and
    torch's first call never land in an episode's planning times."""
    if agent_name in _WARMED:
        return
    import gymnasium as gym

    import agents

    env = gym.make("DynamicObstacle-v0", delta_d=0.5)
    obs, _ = env.reset(seed=0)
    agents.make(agent_name, env, seed=0, **overrides).predict(obs, deterministic=True)
    _WARMED.add(agent_name)


def run_episode(agent_name: str, scenario: str, delta_d: float, episode: int, seed: int, n_obstacles: int, overrides: dict) -> EpisodeResult:
    """One episode of one agent (the unit of work every executor runs)."""
    import gymnasium as gym

    import agents
    from pathplan_env.geometry import shortest_path_to_goal

    warm_up(agent_name, overrides)
    env = gym.make("DynamicObstacle-v0", scenario=scenario, delta_d=delta_d, n_obstacles=n_obstacles)
    obs, info = env.reset(seed=seed)
    agent = agents.make(agent_name, env, seed=seed, **overrides)
    scenario_of_episode = env.unwrapped.scenario
    reference = shortest_path_to_goal(scenario_of_episode)  # to the goal's disc, where an episode ends
    plan_ms, clearance, steps, discomfort_steps, discomfort_sum = [], math.inf, 0, 0, 0.0
    while True:
        action, _ = agent.predict(obs, deterministic=True)
        plan_ms.append(1e3 * agent.last_plan_seconds)
        obs, _, terminated, truncated, info = env.step(action)
        clearance = min(clearance, info["min_clearance"])
        steps += 1
        if terminated or truncated:
            break
        if info["min_clearance"] < DISCOMFORT_DISTANCE:  # CrowdNav counts danger on steps that end nothing
            discomfort_steps += 1
            discomfort_sum += info["min_clearance"]
    env.close()
    success = bool(info["is_success"])
    return EpisodeResult(
        agent=agent_name, scenario=scenario, delta_d=delta_d, episode=episode, seed=seed,
        success=success, collision=bool(info["collision"]), timeout=not terminated,
        steps=steps, path_length=info["path_length"], shortest_path=reference + scenario_of_episode.goal_radius,
        path_length_ratio=info["path_length"] / reference if success and np.isfinite(reference) and reference > 0 else math.nan,
        time_to_goal=info["time"] if success else math.nan, min_clearance=clearance, plan_ms=plan_ms,
        verdict=getattr(agent, "verdict", None) or "", discomfort_steps=discomfort_steps, discomfort_clearance_sum=discomfort_sum,
    )  # fmt: skip


def versions() -> dict:
    import gymnasium
    import numba
    import pymunk

    import pathplan_env

    info = {
        "python": platform.python_version(),
        "numpy": np.__version__,
        "gymnasium": gymnasium.__version__,
        "pymunk": pymunk.version,
        "numba": numba.__version__,
        "pathplan_env": pathplan_env.__version__,
        "machine": f"{platform.machine()} {os.cpu_count()} cores",
    }
    try:
        info["git_commit"] = subprocess.run(["git", "rev-parse", "HEAD"], capture_output=True, text=True, cwd=Path(__file__).parent).stdout.strip()
    except OSError:
        pass
    return info



# -- running ------------------------------------------------------------------------------------
def check_run(agent_names, scenarios, deltas, episodes, *, seed=0, split="test", n_obstacles=None, workers=1) -> None:
    """Refuse a run that could not finish, naming the argument, before anything is written: an
    unknown agent or preset, a bad count, and any scene the env would reject (every scenario and Δd
    is built once, at the run's first episode seed)."""
    import gymnasium as gym

    import agents
    import pathplan_env
    from pathplan_env.splits import heldout_seeds, validation_seeds

    def whole(value, name, minimum):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
            raise ValueError(f"{name} must be an integer >= {minimum}, got {value!r}")

    for name, values in (("agent_names", agent_names), ("scenarios", scenarios), ("deltas", deltas)):
        if isinstance(values, str) or not len(values):
            raise ValueError(f"{name} must be a non-empty list, got {values!r}")
    unknown = [a for a in agent_names if a not in agents.available()]
    if unknown:
        raise ValueError(f"agent_names: unknown {unknown}; available: {agents.available()}")
    unknown = [s for s in scenarios if s not in pathplan_env.PRESETS]
    if unknown:
        raise ValueError(f"scenarios: unknown {unknown}; presets: {sorted(pathplan_env.PRESETS)}")
    if any(isinstance(d, bool) or not isinstance(d, (int, float, np.number)) or not math.isfinite(d) or d < 0 for d in deltas):
        raise ValueError(f"deltas: values must be finite numbers >= 0, got {list(deltas)}")
    whole(episodes, "episodes", 1)
    whole(seed, "seed", 0)
    whole(workers, "workers", 1)
    if split not in ("test", "validation"):
        raise ValueError(f"split must be 'test' or 'validation', got {split!r}")
    first_seed = (heldout_seeds if split == "test" else validation_seeds)(seed, 1)[0]
    for scenario in scenarios:
        for delta_d in deltas:
            try:
                gym.make("DynamicObstacle-v0", scenario=scenario, delta_d=float(delta_d), n_obstacles=n_obstacles).reset(seed=first_seed)
            except ValueError as error:
                raise ValueError(f"scenario {scenario!r} at delta_d {delta_d}: {error}") from None


def resolve_agent_kwargs(agent_names: list[str], agent_kwargs: dict) -> dict[str, dict]:
    """Per-agent overrides from either form, checked by building each agent once (before any work).

    ``{"n_waypoints": 3}`` goes to every agent; ``{"pso": {"n_waypoints": 3}}`` to ``pso`` only.
    :raises ValueError: naming the agent and the argument it does not take.
    """
    import gymnasium as gym

    import agents

    if not isinstance(agent_kwargs, dict):
        raise ValueError(f"agent kwargs must be a JSON object, got {agent_kwargs!r}")
    per_agent = bool(agent_kwargs) and all(isinstance(v, dict) for v in agent_kwargs.values())
    if per_agent:
        unknown = sorted(set(agent_kwargs) - set(agent_names))
        if unknown:
            raise ValueError(f"agent kwargs for agents not in the run: {unknown}")
        own = {name: dict(agent_kwargs.get(name, {})) for name in agent_names}
    else:
        own = {name: dict(agent_kwargs) for name in agent_names}
    env = gym.make("DynamicObstacle-v0")
    for name, kwargs in own.items():
        if kwargs:
            try:
                agents.make(name, env, seed=0, **kwargs)
            except TypeError as error:
                raise ValueError(f"agent {name!r} does not take {sorted(kwargs)}: {error}") from None
    return own


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
    the cluster at ``address``; :mod:`agents.ray_backend`). Both run the same jobs: same results."""
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
