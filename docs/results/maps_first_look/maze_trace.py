"""Trace a planner's episode as the harness flies it: where the robot goes, how fast, and who it meets.

    PYTHONPATH=. python docs/results/maps_first_look/maze_trace.py --agent pso-crowd --scenario maze-crowd --delta-d 1 --episodes 3,8,12 --split validation

For each episode prints the outcome, then one line every ``--every`` steps (and every step of the last
``--last``): the robot's place, its step as a fraction of the top speed, the static cost-to-go to the goal
(the way round the walls), the nearest human (index, surface gap, speed) and whether the replan's best
plan was predicted free of contact (its penalty). A timeout shows as the cost-to-go standing still; a
collision as the last line's gap and the human's speed.
"""

from __future__ import annotations

import argparse
import math

import numpy as np

import pathplan_env  # noqa: F401  (registers the env)
from agents.base import real_obstacles
from agents.evaluation.entrants import resolve_agents, resolve_scenarios
from agents.evaluation.episodes import episode_policy, make_episode_env
from agents.planners.costtogo import distance_to_goal
from pathplan_env.scenarios.splits import episode_seeds


def trace(agent: str, scenario: str, delta_d: float, episode: int, split: str, split_seed: int, every: int, last: int,
          overrides: dict) -> None:  # fmt: skip
    spec, scene = resolve_agents([agent])[0], resolve_scenarios([scenario])[0]
    seed = episode_seeds(split, split_seed, episode + 1)[episode]
    env = make_episode_env(scene, delta_d, None, None, split, episode)
    obs, info = env.reset(seed=seed)
    policy, act = episode_policy(spec, env, seed, overrides)
    facts = policy.facts
    lines = []
    for t in range(10_000):
        robot = np.asarray(obs["robot_position"], np.float64)
        action = act(obs)
        memory = policy._memory[0] if getattr(policy, "_memory", None) else {}
        ctg = memory.get("cost_to_go")
        goal = np.asarray(obs["goal"], np.float64)
        to_go = distance_to_goal(ctg, robot[0], robot[1], goal[0], goal[1], facts.goal_radius) if ctg is not None else math.nan
        obs, _, terminated, truncated, info = env.step(action)
        moved = float(np.hypot(*(np.asarray(obs["robot_position"]) - robot)))
        centers, velocities, radii = real_obstacles(obs)
        gaps = np.hypot(*(centers - np.asarray(obs["robot_position"])).T) - radii - facts.robot_radius
        o = int(np.argmin(gaps)) if len(gaps) else -1
        near = f"human {o} gap {gaps[o]:5.2f} speed {np.hypot(*velocities[o]):4.2f}" if o >= 0 else ""
        penalty = getattr(policy, "last_penalty", math.nan)
        lines.append(f"  t {t:3d} robot ({robot[0]:5.2f}, {robot[1]:5.2f}) step {moved / policy.step_length:4.2f} "
                     f"to go {to_go:5.2f}  {near}  best's penalty {penalty:7.1f}")  # fmt: skip
        if terminated or truncated:
            break
    outcome = "success" if info["is_success"] else "collision" if info["collision"] else "timeout"
    print(f"{agent} {scenario} Δd {delta_d:g} episode {episode} (seed {seed}): {outcome} at step {t + 1}")
    print("\n".join(line for i, line in enumerate(lines) if i % every == 0 or i >= len(lines) - last))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--agent", default="pso-crowd")
    parser.add_argument("--scenario", default="maze-crowd")
    parser.add_argument("--delta-d", type=float, default=1.0)
    parser.add_argument("--episodes", default="0")
    parser.add_argument("--split", default="validation")
    parser.add_argument("--seed", type=int, default=0, help="split seed")
    parser.add_argument("--every", type=int, default=10)
    parser.add_argument("--last", type=int, default=5)
    parser.add_argument("--agent-kwargs", default="{}", help="JSON overrides for the agent")
    args = parser.parse_args()
    import json

    for episode in (int(e) for e in args.episodes.split(",")):
        trace(args.agent, args.scenario, args.delta_d, episode, args.split, args.seed, args.every, args.last, json.loads(args.agent_kwargs))


if __name__ == "__main__":
    main()
