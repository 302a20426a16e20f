"""A planner's step that grazes a wall corner: its clearance against the walls as the observation gives
them (float32) and as the env holds them (float64).

    PYTHONPATH=. python docs/results/maps_first_look/wall_graze.py --agent pso-crowd --episode 14 --delta-d 1

Flies the agent on an episode (maze-crowd validation by default) as the harness does and, at the step that ends in
contact, prints the step's chord (robot -> the waypoint the env receives) and its smallest surface gap to
the nearest wall rows, observed and exact (``pathplan_env.geometry.walls.swept_capsule``; negative: overlap).
"""

from __future__ import annotations

import argparse

import numpy as np

import pathplan_env  # noqa: F401  (registers the env)
from agents.base import real_static_segments
from agents.evaluation.entrants import resolve_agents, resolve_scenarios
from agents.evaluation.episodes import episode_policy, make_episode_env
from pathplan_env.scenarios.splits import episode_seeds
from pathplan_env.geometry.walls import swept_capsule


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--agent", default="pso-crowd")
    parser.add_argument("--scenario", default="maze-crowd")
    parser.add_argument("--episode", type=int, default=14)
    parser.add_argument("--delta-d", type=float, default=1.0)
    parser.add_argument("--split", default="validation")
    parser.add_argument("--seed", type=int, default=0, help="split seed")
    args = parser.parse_args()
    spec, scene = resolve_agents([args.agent])[0], resolve_scenarios([args.scenario])[0]
    seed = episode_seeds(args.split, args.seed, args.episode + 1)[args.episode]
    env = make_episode_env(scene, args.delta_d, None, None, args.split, args.episode)
    obs, _ = env.reset(seed=seed)
    policy, act = episode_policy(spec, env, seed, {})
    exact = env.unwrapped._world.static_segments  # the env's own rows (float64), read here only to compare
    for t in range(10_000):
        robot = np.asarray(obs["robot_position"], np.float64)
        observed = real_static_segments(obs)
        action = act(obs)
        obs, _, terminated, truncated, info = env.step(action)
        if terminated or truncated:
            break
    if not info["collision"]:
        print(f"{args.agent} episode {args.episode}: no collision ({'success' if info['is_success'] else 'timeout'} at step {t + 1})")
        return
    waypoint = policy.arena.action_to_waypoint(action)
    print(f"{args.agent} episode {args.episode}: contact at step {t + 1}, chord {robot.round(6).tolist()} -> {waypoint.round(6).tolist()}")
    for label, rows in (("observed (float32)", observed), ("exact (float64)", exact)):
        gaps = np.array([swept_capsule(robot[0], robot[1], waypoint[0], waypoint[1], policy.facts.robot_radius, *row)[0] for row in rows])
        print(f"  {label:18s} smallest gap to a wall {gaps.min():+.2e} m (row {np.round(rows[gaps.argmin()], 6).tolist()})")


if __name__ == "__main__":
    main()
