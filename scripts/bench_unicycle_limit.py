"""The unicycle limit (``oracle-clairvoyant`` with ``robot="unicycle"``) on chosen random-scene episodes:
its verdict, which stage found the plan (the receding scheme, search 1-3, the last resort), the nodes it
expanded and the seconds it took, and whether the env reached the goal flying its plan.

    python scripts/bench_unicycle_limit.py --delta 0.5 --seeds 1000000024 [--set max_expansions=100000 ...]
    python scripts/bench_unicycle_limit.py --delta 1 --seeds 1000000003 1000000022 1000000025 1000000031 1000000039
"""

from __future__ import annotations

import argparse
import ast

import gymnasium as gym

import agents
import pathplan_env  # noqa: F401


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--delta", type=float, required=True, help="Δd of the random scenes")
    parser.add_argument("--seeds", type=int, nargs="+", required=True, help="episode seeds (the test split's start at 1000000000)")
    parser.add_argument("--obstacles", type=int, default=8)
    parser.add_argument("--set", nargs="*", default=[], metavar="KEY=VALUE", help="the oracle's keyword arguments")
    return parser


def parse_args(argv=None) -> argparse.Namespace:
    return build_parser().parse_args(argv)


def main(argv=None) -> None:
    args = parse_args(argv)
    overrides = {key: ast.literal_eval(value) for key, value in (item.split("=", 1) for item in args.set)}
    env = gym.make("DynamicObstacle-v0", scenario="random", delta_d=args.delta, n_obstacles=args.obstacles, robot="unicycle")
    print("| seed | verdict | found by | nodes expanded | seconds | flown: success |")
    print("|---:|---|---|---:|---:|---|")
    for seed in args.seeds:
        oracle = agents.make("oracle-clairvoyant", env, seed=seed, **overrides)
        info = agents.rollout(oracle, env, seed=seed)
        s = oracle.last_search
        print(f"| {seed} | {s['verdict']} | {s['found_by'] or '-'} | {s['expansions']} | {s['seconds']:.1f} | {info['is_success']} |", flush=True)


if __name__ == "__main__":
    main()
