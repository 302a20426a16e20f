"""Crowd steps beside navground (PyPI ``navground``, C++): the same scenes built in both from the same
lists (``pathplan_env.world.navground_peer``), their agreement, then our step time ÷ navground's
(process CPU time, median of ``--repeats``; > 1: navground is faster) for ``World.step`` and for
``DynamicObstacle-v0.step`` (the unwrapped env, the robot holding still), per crowd size of
CrowdNav's circle crossing and for the corridor with 20 humans, from one process, the two taking
turns at going first.

    python scripts/bench_crowds.py [--steps 100] [--repeats 9] [--sizes 2 5 10 15 20]
    python scripts/bench_crowds.py --split [--sizes 2 5]

``--split``: what our ``World.step`` is made of at those sizes (no navground needed): the whole step,
the compiled step called directly, the Python/compiled boundary alone, Chipmunk's step alone.

navground is in the ``crowds-bench`` extra (``pip install -e .[crowds-bench]``); without it the
script says so and stops.
"""

from __future__ import annotations

import argparse
import importlib.util
import sys

import gymnasium as gym

import pathplan_env  # noqa: F401  (registers DynamicObstacle-v0)
from pathplan_env.world.navground_peer import (
    CORRIDOR_HUMANS,
    CROWD_SIZES,
    agreement,
    crowd_scene,
    navground_stepper,
    paired_ratio,
    step_split,
    world_stepper,
)


def env_stepper(scenario):
    """A fresh env of ``scenario`` (reset) and its unwrapped step, the robot holding still."""
    env = gym.make("DynamicObstacle-v0", scenario=scenario)
    env.reset(seed=0)
    unwrapped = env.unwrapped
    hold = unwrapped.waypoint_to_action(scenario.start)
    return lambda: unwrapped.step(hold)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--steps", type=int, default=100, help="steps timed per repeat from a fresh scene (100: 10 s, the crossing)")
    parser.add_argument("--repeats", type=int, default=9)
    parser.add_argument("--sizes", type=int, nargs="+", default=list(CROWD_SIZES))
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--split", action="store_true", help="only what World.step is made of (µs), per size")
    return parser


def parse_args(argv=None) -> argparse.Namespace:
    return build_parser().parse_args(argv)


def main(argv=None) -> None:
    args = parse_args(argv)
    if args.split:
        print("| humans | `World.step` µs | compiled step | call boundary | `cpSpaceStep` |\n|---:|---:|---:|---:|---:|")
        for n in args.sizes:
            parts = step_split(crowd_scene("circle", n, args.seed))
            print(f"| {n} | " + " | ".join(f"{us:.2f}" for us in parts.values()) + " |", flush=True)
        return
    if importlib.util.find_spec("navground") is None:
        print("bench_crowds: navground is not installed (pip install -e .[crowds-bench]); nothing to compare, skipped")
        return
    scenes = [(f"circle, {n}", crowd_scene("circle", n, args.seed)) for n in args.sizes]
    scenes.append((f"corridor, {CORRIDOR_HUMANS}", crowd_scene("corridor", CORRIDOR_HUMANS, args.seed)))
    print(f"dt {scenes[0][1].dt} s, {args.steps} steps a repeat, median of {args.repeats}; ratio = our step time / navground's (> 1: navground faster)\n")
    print("| scene, humans | max deviation after 1 s (mm) | at goal after 20 s: ours / navground |")
    print("|---|---:|---:|")
    for name, scenario in scenes:
        a = agreement(scenario)
        print(f"| {name} | {1e3 * a['deviation']:.1f} | {a['ours_at_goal']:.2f} / {a['navground_at_goal']:.2f} |")
    print("\n| scene, humans | navground µs/step | `World.step` µs | ratio | `DynamicObstacle-v0.step` µs | ratio |")
    print("|---|---:|---:|---:|---:|---:|")
    for name, scenario in scenes:
        world, world_us, peer_us = paired_ratio(lambda s=scenario: world_stepper(s), lambda s=scenario: navground_stepper(s), args.steps, args.repeats)
        env, env_us, _ = paired_ratio(lambda s=scenario: env_stepper(s), lambda s=scenario: navground_stepper(s), args.steps, args.repeats)
        print(f"| {name} | {peer_us:.1f} | {world_us:.1f} | {world:.2f} | {env_us:.1f} | {env:.2f} |", flush=True)


if __name__ == "__main__":
    sys.exit(main())
