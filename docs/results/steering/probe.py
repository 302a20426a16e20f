"""Does :class:`agents.planners.steering.SteeringCheck` tell bouncing bodies from humans who steer?

    PYTHONPATH=. python docs/results/steering/probe.py --episodes 100

Flies ``velocity-obstacle`` (cheap; the check reads only the obstacles) on validation episodes of scenes
whose obstacles bounce and scenes whose obstacles steer. Prints per scene: the steps, the largest change
of an obstacle's speed between two observations (÷ the robot's speed), the share of steps with a change
above the check's tolerance, the episodes where the check fires and the median step at which it fires.
"""

from __future__ import annotations

import argparse

import gymnasium as gym
import numpy as np
from tqdm import tqdm

import agents
import pathplan_env  # noqa: F401  (registers the env)
from agents.planners.steering import SURPRISES, TOLERANCE, SteeringCheck
from pathplan_env.scenarios.splits import episode_seeds
from pathplan_env.facts import EnvFacts

BOUNCING = [("random", 0.25, {}), ("random", 1.0, {}), ("random", 2.0, {}), ("random", 2.0, {"n_obstacles": 30}),
            ("random", 4.0, {"n_obstacles": 50}), ("paper-case-1", 1.0, {}), ("paper-case-3", 1.0, {}), ("corridor", 1.0, {}),
            ("doorway", 1.0, {}), ("intersection", 1.0, {}), ("cluttered-room", 1.0, {}), ("maze", 1.0, {})]  # fmt: skip
STEERING = [("corridor-crowd", 1.0, {}), ("doorway-crowd", 1.0, {}), ("intersection-crowd", 1.0, {}), ("cluttered-room-crowd", 1.0, {}),
            ("maze-crowd", 0.25, {}), ("maze-crowd", 1.0, {}), ("crowdnav-circle-crossing", 0.8333333333333334, {}),
            ("crowdnav-square-crossing", 0.8333333333333334, {})]  # fmt: skip


def probe(scenario: str, delta_d: float, kwargs: dict, episodes: int) -> dict:
    env = gym.make("DynamicObstacle-v0", scenario=scenario, delta_d=delta_d, **kwargs)
    facts = EnvFacts.of(env)
    check = SteeringCheck(facts.robot_speed)
    agent = agents.make("velocity-obstacle", env, seed=0)
    steps, worst, changed, fired = 0, 0.0, 0, []
    for seed in episode_seeds("validation", 0, episodes):
        obs, _ = env.reset(seed=seed)
        agent.reset()
        memory, before, first = {}, None, None
        for t in range(10_000):
            speeds = np.hypot(*obs["obstacle_velocities"].astype(np.float64).T)
            if before is not None:
                both = (obs["obstacle_mask"] > 0) & (before[1] > 0)
                change = np.abs(speeds - before[0])[both] / facts.robot_speed
                if change.size:
                    worst = max(worst, float(change.max()))
                    changed += int(change.max() > TOLERANCE)
                steps += 1
            before = (speeds, obs["obstacle_mask"].copy())
            if check.steering(memory, obs) and first is None:
                first = t
            action, _ = agent.predict(obs, deterministic=True)
            obs, _, terminated, truncated, _ = env.step(action)
            if terminated or truncated:
                break
        if first is not None:
            fired.append(first)
    env.close()
    return {"steps": steps, "worst": worst, "changed": changed / max(steps, 1), "fired": fired}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--episodes", type=int, default=100)
    args = parser.parse_args()
    print(f"tolerance {TOLERANCE} x the robot's speed, fires at {SURPRISES} surprises; {args.episodes} validation episodes a scene\n")
    print("| obstacles | scene | Δd | steps | largest speed change ÷ robot speed | steps with a change | episodes fired | median step fired |")
    print("|---|---|---:|---:|---:|---:|---:|---:|")
    for kind, scenes in (("bounce", BOUNCING), ("steer", STEERING)):
        for scenario, delta_d, kwargs in tqdm(scenes, desc=kind, leave=False):
            r = probe(scenario, delta_d, kwargs, args.episodes)
            label = scenario + "".join(f" {k}={v}" for k, v in kwargs.items())
            median = f"{np.median(r['fired']):.0f}" if r["fired"] else "–"
            print(f"| {kind} | {label} | {delta_d:g} | {r['steps']} | {r['worst']:.1e} | {r['changed']:.3f} | {len(r['fired'])} / {args.episodes} | {median} |",
                  flush=True)  # fmt: skip


if __name__ == "__main__":
    main()
