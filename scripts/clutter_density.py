"""The space-time planners in denser clutter than the ``clutter`` preset's 200 cylinders
(``clutter_scenario(n_cylinders=...)``: the field's cluttered benchmarks hold 181-365): each episode flown by a
reference and by each agent, success, collisions and the flown length ÷ the reference's on the episodes both
reach. With the cylinders alone the reference is ``oracle-static`` (issue 46: >= 0.99 of the episodes the static
oracle solves, within 5 % of its length); with ``--n-obstacles`` bouncing discs at ``--delta-d``, the clairvoyant
limit ``oracle-clairvoyant`` (issue 46: ``pso-`` and ``abc-spacetime`` >= 0.95 x the limit at Δd 0.25 and 0.5).

    python scripts/clutter_density.py [--cylinders 300] [--seeds 5000:5020] [--agents pso-spacetime,abc-spacetime]
                                      [--n-obstacles 5 --delta-d 0.5] [--workers 2] [--csv episodes.csv]

Prints one line an agent: the episodes it reached of those the reference reached, its success ÷ the reference's,
its length ÷ ``oracle-static``'s (mean, largest, how many over 1.05) and the seeds it did not reach the goal in.
``--csv`` writes every episode (agent, seed, success, collision, steps, length, the reference's length), an agent's
rows as soon as its episodes are flown.
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


def fly(name: str, seed: int, n_cylinders: int, n_obstacles: int = 0, delta_d: float = 0.25) -> tuple[bool, bool, float, int]:
    """One episode of ``name`` on the clutter episode drawn from ``seed``: ``(success, collision, path length, steps)``."""
    scenario = clutter_scenario(np.random.default_rng(seed), n_obstacles, delta_d, n_cylinders=n_cylinders)
    env = gym.make("DynamicObstacle-v0", scenario=scenario)
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
    parser.add_argument("--n-obstacles", type=int, default=0, help="bouncing discs crossing the clutter (then the reference is the limit)")
    parser.add_argument("--delta-d", type=float, default=0.25, help="the bouncing discs' Δd")
    parser.add_argument("--workers", type=int, default=1, help="processes flying episodes (each episode is one process's)")
    parser.add_argument("--csv", type=Path, default=None, help="write every episode here")
    return parser


def parse_args(argv=None) -> argparse.Namespace:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        first, end = (int(part) for part in args.seeds.split(":"))
    except ValueError:
        parser.error(f"--seeds must be first:end, got {args.seeds!r}")
    if end <= first or args.cylinders < 1 or args.workers < 1 or args.n_obstacles < 0:
        parser.error("--seeds must hold at least one seed, --cylinders and --workers be >= 1, --n-obstacles >= 0")
    if not (np.isfinite(args.delta_d) and args.delta_d >= 0.0):
        parser.error(f"--delta-d must be a finite number >= 0, got {args.delta_d!r}")
    args.seed_range = range(first, end)
    args.agent_names = [name for name in args.agents.split(",") if name]
    args.reference = "oracle-clairvoyant" if args.n_obstacles else "oracle-static"
    return args


def _fly_all(name: str, args, pool) -> dict[int, tuple[bool, bool, float, int]]:
    seeds = list(args.seed_range)
    scene = (args.cylinders, args.n_obstacles, args.delta_d)
    if pool is None:
        return {seed: fly(name, seed, *scene) for seed in seeds}
    return dict(zip(seeds, pool.map(fly, [name] * len(seeds), seeds, *([value] * len(seeds) for value in scene))))


def main(argv=None) -> None:
    args = parse_args(argv)
    pool = ProcessPoolExecutor(args.workers) if args.workers > 1 else None
    writer = handle = None
    if args.csv is not None:
        args.csv.parent.mkdir(parents=True, exist_ok=True)
        handle = args.csv.open("w", newline="")
        writer = csv.writer(handle)
        writer.writerow(["agent", "seed", "success", "collision", "steps", "path_length", "reference_length"])
    try:
        reference = _fly_all(args.reference, args, pool)
        solved = [seed for seed, flown in reference.items() if flown[0]]
        n = len(args.seed_range)
        movers = f", {args.n_obstacles} bouncing discs at Δd {args.delta_d:g}" if args.n_obstacles else ""
        print(f"{args.cylinders} cylinders{movers}, seeds {args.seeds}: {args.reference} {len(solved)}/{n}", flush=True)
        for name in [args.reference, *args.agent_names]:
            flown = reference if name == args.reference else _fly_all(name, args, pool)
            if writer is not None:
                for seed, (success, collision, length, steps) in flown.items():
                    writer.writerow([name, seed, int(success), int(collision), steps, f"{length:.6f}", f"{reference[seed][2]:.6f}"])
                handle.flush()
            if name == args.reference:
                continue
            ratios = [flown[seed][2] / reference[seed][2] for seed in solved if flown[seed][0]]
            reached = sum(flown[seed][0] for seed in solved)
            line = f"{name}: {reached}/{len(solved)} of the {args.reference}'s"
            if solved:
                line += f" (success ÷ its {sum(f[0] for f in flown.values()) / len(solved):.3f})"
            line += f", {sum(f[1] for f in flown.values())} collisions"
            if ratios and not args.n_obstacles:  # (the limit's paths are no shortest ones: no length target there)
                line += f", length ÷ {args.reference}'s mean {np.mean(ratios):.4f}, largest {max(ratios):.3f}"
                line += f", {sum(r > 1.05 for r in ratios)} over 1.05"
            print(line + f"; not reached: {[seed for seed in args.seed_range if not flown[seed][0]]}", flush=True)
    finally:
        if pool is not None:
            pool.shutdown()
        if handle is not None:
            handle.close()


if __name__ == "__main__":
    main()
