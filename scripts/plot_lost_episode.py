"""Picture of an episode the physical limit proves lost: the obstacles' true paths and the shrinking
set of positions the robot could still occupy (the outer approximation behind the "lost" verdict).

    python scripts/plot_lost_episode.py --delta-d 2 --out docs/img/lost_episode.png

Takes the first test episode (random scenes, 8 obstacles) that ``oracle-clairvoyant`` proves lost.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import gymnasium as gym
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import agents
from agents.planners.reachable_set import provably_lost
from agents.planners.spacetime.astar import SpacetimeProblem
from pathplan_env.scenarios.splits import heldout_seeds
from pathplan_env.world.simulation import World


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--delta-d", type=float, default=2.0)
    parser.add_argument("--search", type=int, default=500, help="test episodes to look through")
    parser.add_argument("--out", default="docs/img/lost_episode.png")
    return parser


def parse_args(argv=None) -> argparse.Namespace:
    return build_parser().parse_args(argv)


def main(argv=None) -> None:
    args = parse_args(argv)

    env = gym.make("DynamicObstacle-v0", delta_d=args.delta_d)
    oracle = agents.make("oracle-clairvoyant", env)
    for seed in heldout_seeds(0, args.search):
        obs, _ = env.reset(seed=seed)
        oracle.reset()
        oracle.predict(obs)
        if oracle.verdict == "lost":
            break
    else:
        raise SystemExit(f"no lost episode among the first {args.search} test episodes at Δd {args.delta_d}")
    scenario = env.unwrapped.scenario
    world = World(scenario)
    n = world.substeps
    lost_at = oracle.last_search["lost_at_step"]
    trajectory = world.obstacle_trajectory(lost_at + 1)
    r = scenario.robot_radius
    xmin, ymin, xmax, ymax = scenario.bounds
    history: list = []
    problem = SpacetimeProblem(trajectory, n, r, world.radii, np.array(scenario.start), np.array(scenario.goal), scenario.goal_radius,
                               env.unwrapped.arena.box, env.unwrapped.robot_step_length)  # fmt: skip
    provably_lost(problem, history=history)

    fig, axes = plt.subplots(1, 2, figsize=(11, 5.4))
    zoom = 1.6  # the right panel: the robot's neighbourhood
    for ax, point_size in zip(axes, (0.3, 4.0)):
        colours = plt.cm.viridis(np.linspace(0, 1, len(history)))
        for (cx, cy, kept), colour in zip(history, colours):  # the reachable set after each substep
            ix, iy = np.nonzero(kept)
            ax.scatter(cx[ix], cy[iy], s=point_size, color=colour, alpha=0.35, linewidths=0)
        for o, radius in enumerate(world.radii):
            path = trajectory[: lost_at * n + 1, o, :2]
            ax.plot(path[:, 0], path[:, 1], color="#b03a2e", lw=1)
            for k in range(0, lost_at + 1):
                centre = trajectory[k * n, o, :2]
                ax.add_patch(plt.Circle(centre, radius, color="#d6604d", alpha=0.12 + 0.5 * k / max(lost_at, 1), lw=0))
        ax.add_patch(plt.Circle(scenario.start, r, fill=False, color="#3465a4", lw=1.5))
        ax.add_patch(plt.Circle(scenario.goal, scenario.goal_radius, fill=False, color="#2ea043", lw=2))
        ax.set_aspect("equal")
    axes[0].set_xlim(xmin, xmax), axes[0].set_ylim(ymin, ymax)
    sx, sy = scenario.start
    axes[1].set_xlim(max(xmin, sx - zoom), min(xmax, sx + zoom)), axes[1].set_ylim(max(ymin, sy - zoom), min(ymax, sy + zoom))
    axes[0].set_title(f"test seed {seed}, Δd = {args.delta_d:g}: lost within {lost_at} step(s)\n"
                      "obstacles over those steps (darker = later); robot (blue), goal (green)", fontsize=9)  # fmt: skip
    axes[1].set_title("around the robot: where it could still be after each substep\n"
                      "(outer approximation; purple = first, yellow = last before it empties)", fontsize=9)  # fmt: skip
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    print(f"seed {seed}: lost within {lost_at} steps -> {out}")


if __name__ == "__main__":
    try:
        main()
    except ValueError as error:  # bad input, named by the library: one line, not a traceback
        sys.exit(f"plot_lost_episode.py: {error}")
