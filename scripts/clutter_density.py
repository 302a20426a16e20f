"""The space-time planners in denser static clutter than the ``clutter`` preset's 200 cylinders
(``clutter_scenario(n_cylinders=...)``: the field's cluttered benchmarks hold 181-365): each episode flown by
``oracle-static`` and by each agent, success, collisions and the flown length ÷ ``oracle-static``'s on the
episodes both reach (issue 46: >= 0.99 of the episodes the static oracle solves, within 5 % of its length).

    python scripts/clutter_density.py [--cylinders 300] [--seeds 5000:5020] [--agents pso-spacetime,abc-spacetime]

Prints one line an agent, and the seeds it did not reach the goal in.
"""

from __future__ import annotations

import argparse

import gymnasium as gym
import numpy as np

import agents
import pathplan_env  # noqa: F401  (registers the env)
from pathplan_env.scenarios.clutter import clutter_scenario


def fly(name: str, seed: int, n_cylinders: int) -> tuple[bool, bool, float]:
    """One episode of ``name`` on the clutter episode drawn from ``seed``: ``(success, collision, path length)``."""
    env = gym.make("DynamicObstacle-v0", scenario=clutter_scenario(np.random.default_rng(seed), n_cylinders=n_cylinders))
    obs, info = env.reset(seed=seed)
    base, settings = agents.registry.split_settings(name)
    agent = agents.make(base, env, seed=0, **settings)
    while True:
        action, _ = agent.predict(obs, deterministic=True)
        obs, _, terminated, truncated, info = env.step(action)
        if terminated or truncated:
            return bool(info["is_success"]), bool(info["collision"]), float(info["path_length"])


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--cylinders", type=int, default=300)
    parser.add_argument("--seeds", default="5000:5020", help="first:end (end excluded)")
    parser.add_argument("--agents", default="pso-spacetime,abc-spacetime")
    return parser


def parse_args(argv=None) -> argparse.Namespace:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        first, end = (int(part) for part in args.seeds.split(":"))
    except ValueError:
        parser.error(f"--seeds must be first:end, got {args.seeds!r}")
    if end <= first or args.cylinders < 1:
        parser.error("--seeds must hold at least one seed and --cylinders be >= 1")
    args.seed_range = range(first, end)
    args.agent_names = [name for name in args.agents.split(",") if name]
    return args


def main(argv=None) -> None:
    args = parse_args(argv)
    oracle = {seed: fly("oracle-static", seed, args.cylinders) for seed in args.seed_range}
    solved = [seed for seed, (success, _, _) in oracle.items() if success]
    n = len(args.seed_range)
    print(f"{args.cylinders} cylinders, seeds {args.seeds}: oracle-static {len(solved)}/{n}")
    for name in args.agent_names:
        flown = {seed: fly(name, seed, args.cylinders) for seed in args.seed_range}
        ratios = [flown[seed][2] / oracle[seed][2] for seed in solved if flown[seed][0]]
        reached = sum(flown[seed][0] for seed in solved)
        line = f"{name}: {reached}/{len(solved)} of the oracle's, {sum(c for _, c, _ in flown.values())} collisions"
        if ratios:
            line += f", length ÷ oracle-static's mean {np.mean(ratios):.4f}, largest {max(ratios):.3f}"
        print(line + f"; not reached: {[seed for seed in args.seed_range if not flown[seed][0]]}", flush=True)


if __name__ == "__main__":
    main()
