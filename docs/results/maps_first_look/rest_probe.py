"""Why pso-spacetime stalls behind humans in maze-crowd: what Eq. 4 on the rest of the path past the
horizon charges the way the cost-to-go points out (pso-spacetime's default; ``rest_obstacles=False``,
as in pso-crowd / abc-crowd, leaves it out where there are walls).

    PYTHONPATH=. python docs/results/maps_first_look/rest_probe.py --episode 12 --delta-d 0.5 --steps 25,35
    PYTHONPATH=. python docs/results/maps_first_look/rest_probe.py --episode 12 --delta-d 0.5 --steps 25,35 --rest-off

Flies pso-spacetime on a maze-crowd validation episode and, at the given steps, prices candidate plans
with the objective (:func:`agents.planners.objective.timed_path_cost`): the cost-to-go's route (its first
2 corners as the waypoints, the first segment at several speeds, the rest at top speed) and the replan's
best. For each it prints the cost and penalty and, apart, the Eq. 4 the rest's straight pieces are charged
for the humans they pass where the prediction leaves them (from where the horizon leaves the robot through
the waypoints to the goal, through walls or not).
"""

from __future__ import annotations

import argparse
import math

import gymnasium as gym
import numpy as np

import agents
import pathplan_env  # noqa: F401  (registers the env)
from agents.planners.costtogo import route, waypoints_on
from agents.planners.objective import timed_path_cost, walk_along
from pathplan_env.scenarios.splits import episode_seeds


def rest_charge(x: np.ndarray, scene) -> float:
    """Eq. 4 (circumference + penalty_weight x depth), as the default objective charges it, on every obstacle the rest's straight pieces cut at
    its last predicted position, for a plan that does not reach the goal within the horizon; 0 if it does."""
    k = (len(x) - 1) // 3
    pts = np.vstack([scene.robot, x[: 2 * k].reshape(-1, 2), scene.goal])
    seg, px, py = 0, *scene.robot
    for step in range(scene.horizon_steps):
        seg, px, py = walk_along(pts, seg, px, py, x[2 * k + seg] * scene.reach)
        if math.hypot(px - scene.goal[0], py - scene.goal[1]) <= scene.goal_radius:
            return 0.0
    last = scene.trajectory[scene.horizon_steps * scene.substeps, :, :2]
    pieces = np.vstack([[px, py], pts[seg + 1 :]])
    charge = 0.0
    for o, (cx, cy) in enumerate(last):
        r = scene.contact_radii[o] + scene.robot_radius
        depth = 0.0
        for (ax, ay), (bx, by) in zip(pieces[:-1], pieces[1:]):
            ex, ey = bx - ax, by - ay
            t = min(max(((cx - ax) * ex + (cy - ay) * ey) / max(ex * ex + ey * ey, 1e-12), 0.0), 1.0)
            depth = max(depth, r - math.hypot(ax + t * ex - cx, ay + t * ey - cy))
        if depth > 0.0:
            charge += 2 * math.pi * r + scene.penalty_weight * depth
    return charge


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--episode", type=int, default=12, help="validation episode of maze-crowd")
    parser.add_argument("--delta-d", type=float, default=0.5)
    parser.add_argument("--steps", default="25,35")
    parser.add_argument("--rest-off", action="store_true", help="fly and price with rest_obstacles=False")
    args = parser.parse_args()
    steps = sorted(int(s) for s in args.steps.split(","))
    seed = episode_seeds("validation", 0, args.episode + 1)[args.episode]
    env = gym.make("DynamicObstacle-v0", scenario="maze-crowd", delta_d=args.delta_d)
    obs, _ = env.reset(seed=seed)
    agent = agents.make("pso-spacetime", env, seed, rest_obstacles=not args.rest_off)
    agent.reset()
    for t in range(steps[-1] + 1):
        if t in steps:
            scene = agent.timed_problem(obs, dict(agent._memory[0]) if agent._memory else {})
            around = waypoints_on(route(scene.cost_to_go, scene.robot, scene.goal, 0.1), agent.n_waypoints)
            print(f"step {t}: robot at {np.round(scene.robot, 2).tolist()}")
            for speed in (1.0, 0.5, 0.25, 0.1, 0.0):
                x = np.concatenate([around.ravel(), [speed, 1.0, 1.0]])
                cost, penalty = timed_path_cost(x, scene)
                print(f"  route, first segment at {speed:4.2f}: cost {cost:8.2f} penalty {penalty:8.2f}  rest charge {rest_charge(x, scene):6.2f}")
        action, _ = agent.predict(obs, episode_start=np.array([t == 0]))
        if t in steps:
            best = agent._memory[0]["best"]
            cost, penalty = timed_path_cost(best, scene)
            print(f"  the replan's best:            cost {cost:8.2f} penalty {penalty:8.2f}  rest charge {rest_charge(best, scene):6.2f}")
        obs, _, terminated, truncated, _ = env.step(action)
        if terminated or truncated:
            break


if __name__ == "__main__":
    main()
