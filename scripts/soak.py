"""Soak test: a million random-action steps with resets, printing the process's memory as it goes.

    python scripts/soak.py [--steps 1000000] [--n-obstacles 8] [--delta-d 1]

Memory should stay flat (pymunk's batch buffers used to leak 0.5 KiB per reset). Prints resident
memory (Linux ``/proc/self/statm``) every tenth of the run and the growth per 100k steps after
the first tenth (warm-up: numba, allocator pools).
"""

from __future__ import annotations

import argparse
import os
import time

import gymnasium as gym
import numpy as np

import pathplan_env  # noqa: F401


def resident_mib() -> float:
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2**20


def soak(steps: int, n_obstacles: int, delta_d: float, report=print) -> tuple[float, int]:
    """Run ``steps`` steps; returns ``(MiB grown after the warm-up tenth, resets)``."""
    env = gym.make("DynamicObstacle-v0", n_obstacles=n_obstacles, delta_d=delta_d)
    env.action_space.seed(0)
    env.reset(seed=0)
    resets, start = 0, time.perf_counter()
    baseline = None
    for step in range(1, steps + 1):
        _, _, terminated, truncated, _ = env.step(env.action_space.sample())
        if terminated or truncated:
            env.reset(seed=step)
            resets += 1
        if step % max(1, steps // 10) == 0:
            rss = resident_mib()
            baseline = rss if baseline is None else baseline
            report(f"{step:>9,} steps, {resets:>7,} resets: {rss:7.1f} MiB ({time.perf_counter() - start:.0f} s)")
    return (resident_mib() - baseline) if baseline is not None else 0.0, resets


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--steps", type=int, default=1_000_000)
    parser.add_argument("--n-obstacles", type=int, default=8)
    parser.add_argument("--delta-d", type=float, default=1.0)
    return parser


def parse_args(argv=None) -> argparse.Namespace:
    return build_parser().parse_args(argv)


def main(argv=None) -> None:
    args = parse_args(argv)
    grown, resets = soak(args.steps, args.n_obstacles, args.delta_d)
    per = grown / max(1, args.steps * 0.9) * 1e5
    print(f"grew {grown:.2f} MiB after the warm-up ({per:.3f} MiB per 100k steps, {resets:,} resets in all)")


if __name__ == "__main__":
    np.seterr(all="raise")
    main()
