"""Digests of the wall crowd families' episodes, to check that speed work changes no episode.

For maze-crowd, corridor-crowd with 20 humans and doorway-crowd, seeds 0, 1, 2 and 7: 300 steps of
random actions, then 250 with the robot held still (zero action), resets included; every scene drawn
(start, goal, walls, polygons, obstacles) and every step's observation, reward, terminated,
truncated and info (its repr) is hashed. Prints one digest per family and seed, then one of them all.

Usage (run before and after a change; the lines must be equal):

    python scripts/crowd_digest.py [--random-steps 300] [--still-steps 250] [--seeds 0 1 2 7]
"""

from __future__ import annotations

import argparse
import hashlib

import gymnasium as gym
import numpy as np

import pathplan_env  # noqa: F401  (registers DynamicObstacle-v0)

# the wall crowds, then open ones (the world's plain compiled call, and humans who see the robot)
FAMILIES = (("maze-crowd", None), ("corridor-crowd", 20), ("doorway-crowd", None), ("crowdnav-circle-crossing", None),
            ("crowdnav-square-crossing-visible", None))


def episode_digest(scenario: str, n_obstacles: int | None, seed: int, random_steps: int, still_steps: int) -> str:
    env = gym.make("DynamicObstacle-v0", scenario=scenario, n_obstacles=n_obstacles)
    env.action_space.seed(seed)
    h = hashlib.sha256()

    def record(obs, info) -> None:
        for key in sorted(obs):
            h.update(key.encode())
            h.update(np.ascontiguousarray(obs[key]).tobytes())
        h.update(repr(sorted(info.items())).encode())

    def scene() -> None:
        s = env.unwrapped.scenario
        h.update(repr((s.start, s.goal, s.walls, s.polygons, s.obstacles, s.n_obstacles)).encode())

    obs, info = env.reset(seed=seed)
    scene()
    record(obs, info)
    still = np.zeros(env.action_space.shape, dtype=env.action_space.dtype)
    for t in range(random_steps + still_steps):
        action = env.action_space.sample() if t < random_steps else still
        obs, reward, terminated, truncated, info = env.step(action)
        record(obs, info)
        h.update(repr((reward, terminated, truncated)).encode())
        if terminated or truncated:
            obs, info = env.reset()
            scene()
            record(obs, info)
    return h.hexdigest()


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--random-steps", type=int, default=300)
    parser.add_argument("--still-steps", type=int, default=250)
    parser.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2, 7])
    return parser


def parse_args(argv=None) -> argparse.Namespace:
    return build_parser().parse_args(argv)


def main(argv=None) -> None:
    args = parse_args(argv)
    whole = hashlib.sha256()
    for scenario, n in FAMILIES:
        for seed in args.seeds:
            digest = episode_digest(scenario, n, seed, args.random_steps, args.still_steps)
            whole.update(digest.encode())
            print(f"{scenario} n={n} seed={seed} {digest}")
    print(f"all {whole.hexdigest()}")


if __name__ == "__main__":
    main()
