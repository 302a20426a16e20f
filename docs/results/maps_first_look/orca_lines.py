"""The orca agent with and without RVO2's obstacle lines (without: the capsule guard alone), on
seeds 2,000,000 + i (not the test split), Δd 0.5: successes, collisions, collisions against a wall.

    PYTHONPATH=. python docs/results/maps_first_look/orca_lines.py 20
"""

import sys

import gymnasium as gym

import agents
import agents.reactive.orca as orca_agent
import pathplan_env  # noqa: F401  (registers the env)
from pathplan_env.crowds.orca_obstacles import NO_OBSTACLES
from pathplan_env.geometry.walls import capsules_clearance

with_lines = orca_agent.orca_obstacles_of
n = int(sys.argv[1]) if len(sys.argv) > 1 else 20
for preset in ["corridor", "doorway", "cluttered-room", "maze", "corridor-crowd", "doorway-crowd", "maze-crowd"]:
    row = []
    for label, build in (("without lines", lambda segments, memory: NO_OBSTACLES), ("with lines", with_lines)):
        orca_agent.orca_obstacles_of = build
        env = gym.make("DynamicObstacle-v0", scenario=preset, delta_d=0.5)
        agent = agents.make("orca", env, seed=0)
        success = collision = wall = 0
        for s in range(n):
            info = agents.rollout(agent, env, 2_000_000 + s)
            success += bool(info["is_success"])
            collision += bool(info["collision"])
            u = env.unwrapped
            x, y = (float(v) for v in u.world.robot_position)
            wall += bool(info["collision"]) and capsules_clearance(x, y, u.robot_radius, u.scenario.static_segments) < 1e-3
        row.append(f"{label}: success {success}/{n} collision {collision} (wall {wall})")
    print(preset, " | ".join(row), flush=True)
