"""Replan CPU time of pso-spacetime and abc-spacetime per configuration, robust to a shared machine.

    python docs/results/dense_planners/time_replans.py --episodes 8 --delta-d 2,4 --n-obstacles 30

``scripts/evaluate.py`` times each replan on the wall clock, which on a machine shared with other
jobs measures the queue as much as the planner. This measures the process's CPU time
(``time.process_time``; the planners are single-threaded compiled code) of every replan of the
first ``--episodes`` validation episodes at each Δd, after a warm-up plan, for each configuration
in :data:`CONFIGS` (the rows of the ablation table).
"""

from __future__ import annotations

import argparse
import time

import gymnasium as gym
import numpy as np

import agents
import pathplan_env  # noqa: F401  (registers the env)
from pathplan_env.scenarios.splits import episode_seeds

# every row names its options in full (the defaults are the last row's)
BASE = {"violation": "contacts", "constraint": "penalty", "stall": 0}
CONFIGS = {
    "baseline": BASE,
    "fc": BASE | {"violation": "first-contact"},
    "deb": BASE | {"constraint": "deb"},
    "fc-deb": BASE | {"violation": "first-contact", "constraint": "deb"},
    "fc-adaptive": BASE | {"violation": "first-contact", "constraint": "adaptive"},
    "fc-deb-s5": {"violation": "first-contact", "constraint": "deb", "stall": 5},
}


def replan_ms(name: str, options: dict, delta_d: float, n_obstacles: int, episodes: int) -> np.ndarray:
    env = gym.make("DynamicObstacle-v0", scenario="random", delta_d=delta_d, n_obstacles=n_obstacles)
    obs, _ = env.reset(seed=0)
    agents.make(name, env, seed=0, **options).predict(obs)  # warm-up: the compile cache's load is not a replan
    times = []
    for seed in episode_seeds("validation", 0, episodes):
        agent = agents.make(name, env, seed=seed, **options)
        obs, _ = env.reset(seed=seed)
        while True:
            begin = time.process_time()
            action, _ = agent.predict(obs, deterministic=True)
            times.append((time.process_time() - begin) * 1e3)
            obs, _, terminated, truncated, _ = env.step(action)
            if terminated or truncated:
                break
    return np.array(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes", type=int, default=8)
    parser.add_argument("--delta-d", default="2,4")
    parser.add_argument("--n-obstacles", type=int, default=30)
    parser.add_argument("--configs", default=",".join(CONFIGS))
    args = parser.parse_args()
    print("| configuration | agent | Δd | replans | CPU ms median / p95 |")
    print("|---|---|---:|---:|---:|")
    for config in args.configs.split(","):
        for name in ("pso-spacetime", "abc-spacetime"):
            for delta_d in (float(d) for d in args.delta_d.split(",")):
                ms = replan_ms(name, CONFIGS[config], delta_d, args.n_obstacles, args.episodes)
                print(f"| {config} | {name} | {delta_d:g} | {len(ms)} | {np.median(ms):.1f} / {np.percentile(ms, 95):.1f} |", flush=True)


if __name__ == "__main__":
    main()
