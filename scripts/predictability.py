"""How far ahead the obstacles can be known from an observation: the prediction's error, step by step.

The space-time planners predict the obstacles with the env's documented physics
(``agents.planners.prediction``). With many fast obstacles the bounces make the motion chaotic:
a tiny error in the state grows with every bounce. This script measures the largest error over
the obstacles after each step ahead, predicting from the observation (float32, what a planner
sees) and from the world's own float64 state (privileged: what no planner sees), against the
simulator's true future (privileged). A planner cannot use what lies past the step where its
prediction's error exceeds the obstacles' radii, while the clairvoyant limit knows the whole
episode: a gap that no search closes.

    python scripts/predictability.py --n-obstacles 8,30 --delta-d 1,2,4 --scenes 10 --steps 12
"""

from __future__ import annotations

import argparse

import gymnasium as gym
import numpy as np

import pathplan_env  # noqa: F401  (registers DynamicObstacle-v0)
from agents.base import real_obstacles
from agents.planners.prediction import predict_obstacles, substeps_for
from pathplan_env.scenarios.splits import validation_seeds


def errors(n_obstacles: int, delta_d: float, scenes: int, steps: int, warmup: int = 3):
    """(from_observation, from_state): (scenes, steps + 1) arrays of the largest centre error (in
    radii of the smallest obstacle) after each step ahead, ``warmup`` steps into each episode."""
    from_obs, from_state = [], []
    for seed in validation_seeds(11, scenes):
        env = gym.make("DynamicObstacle-v0", scenario="random", n_obstacles=n_obstacles, delta_d=delta_d).unwrapped
        obs, _ = env.reset(seed=seed)
        for _ in range(warmup):  # the robot waits where it is: the obstacles never see it
            obs, *_ = env.step(env.arena.waypoint_to_action(np.asarray(obs["robot_position"], np.float64)))
        world, bounds = env.world, np.array(env.scenario.bounds, np.float64)
        centres, velocities, radii = real_obstacles(obs)
        n = substeps_for(velocities, radii, env.scenario.dt)
        seen = predict_obstacles(centres, velocities, radii, bounds, env.scenario.dt, steps, n)
        state = world.obstacle_state
        exact = predict_obstacles(state[:, :2].copy(), state[:, 2:].copy(), world.radii, bounds, env.scenario.dt, steps, n)
        future = world.obstacle_trajectory(steps)  # the env's own world, run on: the true future (the env is dropped after)
        scale = world.radii.min()
        for predicted, out in ((seen, from_obs), (exact, from_state)):
            gap = np.hypot(*(predicted[::n, :, :2] - future[::n, :, :2]).transpose(2, 0, 1)).max(axis=1)
            out.append(gap / scale)
    return np.array(from_obs), np.array(from_state)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--n-obstacles", default="8,30")
    parser.add_argument("--delta-d", default="1,2,4")
    parser.add_argument("--scenes", type=int, default=20)
    parser.add_argument("--steps", type=int, default=12)
    return parser


def parse_args(argv=None) -> argparse.Namespace:
    return build_parser().parse_args(argv)


def main(argv=None) -> None:
    args = parse_args(argv)
    shown = [s for s in (1, 2, 3, 4, 5, 6, 8, 10, 12, 16, 20) if s <= args.steps]
    print(f"largest centre error over the obstacles k steps ahead, in radii of the smallest obstacle (median over {args.scenes} scenes)")
    print("| obstacles | Δd | predicted from | " + " | ".join(f"k={s}" for s in shown) + " | steps until 0.1 radius |")
    print("|---:|---:|---|" + "---:|" * (len(shown) + 1))
    for count in (int(c) for c in args.n_obstacles.split(",")):
        for delta_d in (float(d) for d in args.delta_d.split(",")):
            for label, table in zip(("observation (float32)", "true state (float64, privileged)"),
                                    errors(count, delta_d, args.scenes, args.steps)):  # fmt: skip
                median = np.median(table, axis=0)
                beyond = np.nonzero(median > 0.1)[0]
                horizon = f"{beyond[0] - 1}" if len(beyond) else f"> {args.steps}"
                cells = " | ".join(f"{median[s]:.2g}" for s in shown)
                print(f"| {count} | {delta_d:g} | {label} | {cells} | {horizon} |", flush=True)


if __name__ == "__main__":
    main()
