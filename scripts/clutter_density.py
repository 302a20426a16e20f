"""The space-time planners in denser static clutter than the ``clutter`` preset's 200 cylinders
(``clutter_scenario(n_cylinders=...)``: the field's cluttered benchmarks hold 181-365): each episode flown by
``oracle-static`` and by each agent, success, collisions and the flown length ÷ ``oracle-static``'s on the
episodes both reach (issue 46: >= 0.99 of the episodes the static oracle solves, within 5 % of its length).

    python scripts/clutter_density.py [--cylinders 300] [--seeds 5000:5020] [--agents pso-spacetime,abc-spacetime]
                                      [--workers 2] [--csv episodes.csv]

Prints one line an agent, and the seeds it did not reach the goal in; ``--csv`` writes every episode
(agent, seed, success, collision, steps, length, the oracle's length), row by row as they finish.
"""

from __future__ import annotations

import argparse
import csv
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import gymnasium as gym
import numpy as np

import agents
import pathplan_env  # noqa: F401  (registers the env)
from pathplan_env.scenarios.clutter import clutter_scenario


def fly(name: str, seed: int, n_cylinders: int) -> tuple[bool, bool, float, int]:
    """One episode of ``name`` on the clutter episode drawn from ``seed``: ``(success, collision, path length, steps)``."""
    env = gym.make("DynamicObstacle-v0", scenario=clutter_scenario(np.random.default_rng(seed), n_cylinders=n_cylinders))
    obs, info = env.reset(seed=seed)
    base, settings = agents.registry.split_settings(name)
    agent = agents.make(base, env, seed=0, **settings)
    steps = 0
    while True:
        action, _ = agent.predict(obs, deterministic=True)
        obs, _, terminated, truncated, info = env.step(action)
        steps += 1
        if terminated or truncated:
            return bool(info["is_success"]), bool(info["collision"]), float(info["path_length"]), steps


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--cylinders", type=int, default=300)
    parser.add_argument("--seeds", default="5000:5020", help="first:end (end excluded)")
    parser.add_argument("--agents", default="pso-spacetime,abc-spacetime")
    parser.add_argument("--workers", type=int, default=1, help="processes flying episodes (each episode is one process's)")
    parser.add_argument("--csv", type=Path, default=None, help="write every episode here as it finishes")
    return parser


def parse_args(argv=None) -> argparse.Namespace:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        first, end = (int(part) for part in args.seeds.split(":"))
    except ValueError:
        parser.error(f"--seeds must be first:end, got {args.seeds!r}")
    if end <= first or args.cylinders < 1 or args.workers < 1:
        parser.error("--seeds must hold at least one seed, --cylinders and --workers be >= 1")
    args.seed_range = range(first, end)
    args.agent_names = [name for name in args.agents.split(",") if name]
    return args


def _fly_all(name: str, args, pool) -> dict[int, tuple[bool, bool, float, int]]:
    seeds = list(args.seed_range)
    if pool is None:
        return {seed: fly(name, seed, args.cylinders) for seed in seeds}
    return dict(zip(seeds, pool.map(fly, [name] * len(seeds), seeds, [args.cylinders] * len(seeds))))


def main(argv=None) -> None:
    args = parse_args(argv)
    pool = ProcessPoolExecutor(args.workers) if args.workers > 1 else None
    writer = None
    if args.csv is not None:
        args.csv.parent.mkdir(parents=True, exist_ok=True)
        handle = args.csv.open("w", newline="")
        writer = csv.writer(handle)
        writer.writerow(["agent", "seed", "success", "collision", "steps", "path_length", "oracle_length"])
    try:
        oracle = _fly_all("oracle-static", args, pool)
        solved = [seed for seed, flown in oracle.items() if flown[0]]
        n = len(args.seed_range)
        print(f"{args.cylinders} cylinders, seeds {args.seeds}: oracle-static {len(solved)}/{n}", flush=True)
        for name in ["oracle-static", *args.agent_names]:
            flown = oracle if name == "oracle-static" else _fly_all(name, args, pool)
            if writer is not None:
                for seed, (success, collision, length, steps) in flown.items():
                    writer.writerow([name, seed, int(success), int(collision), steps, f"{length:.6f}", f"{oracle[seed][2]:.6f}"])
                handle.flush()
            if name == "oracle-static":
                continue
            ratios = [flown[seed][2] / oracle[seed][2] for seed in solved if flown[seed][0]]
            reached = sum(flown[seed][0] for seed in solved)
            line = f"{name}: {reached}/{len(solved)} of the oracle's, {sum(f[1] for f in flown.values())} collisions"
            if ratios:
                line += f", length ÷ oracle-static's mean {np.mean(ratios):.4f}, largest {max(ratios):.3f}"
            print(line + f"; not reached: {[seed for seed in args.seed_range if not flown[seed][0]]}", flush=True)
    finally:
        if pool is not None:
            pool.shutdown()
        if writer is not None:
            handle.close()


if __name__ == "__main__":
    main()
