"""Do the humans get through? Per crowd family, over seeded episodes with the robot invisible to them
(so that where it stands does not matter): the fraction of humans that reach their goals within the
time limit (200 steps, 20 s at dt 0.1 s), and the count of humans stuck (not at the goal, moving less
than 0.25 m in 5 s) at some point.

    python scripts/crowd_throughput.py [--seeds 100] [--steps 200] [--families corridor-crowd doorway-crowd ...]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import pathplan_env
from pathplan_env.scenarios.crowd_families import CROWD_FAMILIES
from pathplan_env.world.simulation import World

STEPS = 200
STUCK_SECONDS = 5.0
STUCK_DISTANCE = 0.25


def episode(name: str, seed: int, steps: int = STEPS) -> tuple[int, int, int, float]:
    """``(humans, reached, stuck, min human-wall gap)`` of one seeded episode of ``name``."""
    scenario = pathplan_env.make_scenario(name, np.random.default_rng(seed))
    world = World(scenario)
    n, dt = scenario.n_obstacles, scenario.dt
    track = world.obstacle_trajectory(steps)[:: world.substeps]  # (steps + 1, n, 4), one row a step
    xy, goals = track[:, :, :2], np.array([ob.goal for ob in scenario.obstacles])
    at_goal = np.hypot(*(xy - goals).transpose(2, 0, 1)) <= scenario.obstacles[0].radius
    reached = at_goal.any(axis=0)
    window = int(round(STUCK_SECONDS / dt))
    moved = np.hypot(*(xy[window:] - xy[:-window]).transpose(2, 0, 1))  # over every 5 s window
    stuck = ((moved < STUCK_DISTANCE) & ~at_goal[window:] & ~at_goal[:-window]).any(axis=0)
    from pathplan_env.geometry.walls import points_clearance

    gap = points_clearance(xy.reshape(-1, 2), scenario.static_segments).min() - scenario.obstacles[0].radius if len(scenario.static_segments) else np.inf
    return n, int(reached.sum()), int(stuck.sum()), float(gap)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--seeds", type=int, default=100)
    parser.add_argument("--steps", type=int, default=STEPS, help="episode length (200: the env's limit; more shows who is late, not lost)")
    parser.add_argument("--families", nargs="+", default=[f for f in CROWD_FAMILIES if f.endswith("-crowd")])
    return parser


def parse_args(argv=None) -> argparse.Namespace:
    return build_parser().parse_args(argv)


def main(argv=None) -> None:
    args = parse_args(argv)
    print(f"{'family':22s} {'humans':>7s} {'reached':>8s} {'fraction':>8s} {'stuck>5s':>8s} {'min wall gap (m)':>16s} {'s':>6s}")
    for name in args.families:
        start = time.perf_counter()
        rows = np.array([episode(name, seed, args.steps) for seed in range(args.seeds)])
        humans, reached, stuck = rows[:, 0].sum(), rows[:, 1].sum(), rows[:, 2].sum()
        gap, seconds = rows[:, 3].min(), time.perf_counter() - start
        print(f"{name:22s} {int(humans):7d} {int(reached):8d} {reached / humans:8.3f} {int(stuck):8d} {gap:16.3f} {seconds:6.1f}")


if __name__ == "__main__":
    main()
