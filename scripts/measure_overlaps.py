"""How deep obstacles overlap at contacts, in radii of the smaller disc of the pair, per scene size and Δd.

    python scripts/measure_overlaps.py [--obstacles 8,50,100] [--delta-d 1,2,4] [--seeds 20] [--steps 100]

For each cell: random scenes (``DynamicObstacle-v0``'s ``random`` preset, seeds 0..seeds-1), their
obstacles simulated ``--steps`` steps, the deepest overlap of any pair read after every physics
substep. Prints the largest over all seeds, the 99th percentile of the per-scene maxima and the
share of substeps with any overlap. docs/limitations.md quotes this table.
"""

from __future__ import annotations

import argparse

import gymnasium as gym
import numpy as np

import pathplan_env  # noqa: F401 (registers the env)
from pathplan_env.world.overlaps import scene_overlaps


def numbers(text: str, kind=float) -> list:
    try:
        return [kind(part) for part in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected comma-separated numbers, got {text!r}") from None


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--obstacles", type=lambda t: numbers(t, int), default=[8, 50, 100], help="obstacle counts")
    parser.add_argument("--delta-d", type=numbers, default=[1.0, 2.0, 4.0], help="obstacle speed / robot speed")
    parser.add_argument("--seeds", type=int, default=20, help="scenes a cell")
    parser.add_argument("--steps", type=int, default=100, help="steps a scene")
    return parser


def main(argv=None) -> None:
    args = build_parser().parse_args(argv)
    print("| obstacles | Δd | substeps | deepest overlap (radii) | 99th pct of scene maxima | substeps with overlap |")
    print("|---:|---:|---:|---:|---:|---:|")
    for n in args.obstacles:
        for delta_d in args.delta_d:
            env = gym.make("DynamicObstacle-v0", scenario="random", n_obstacles=n, delta_d=delta_d)
            maxima, overlapping, total, substeps = [], 0, 0, 0
            for seed in range(args.seeds):
                env.reset(seed=seed)
                deepest = scene_overlaps(env.unwrapped.scenario, args.steps)
                maxima.append(deepest.max())
                overlapping += int((deepest > 0).sum())
                total += len(deepest)
                substeps = env.unwrapped.world.substeps
            print(f"| {n} | {delta_d:g} | {substeps} | {max(maxima):.3f} | {np.percentile(maxima, 99):.3f} | "
                  f"{overlapping / total:.3f} |", flush=True)


if __name__ == "__main__":
    main()
