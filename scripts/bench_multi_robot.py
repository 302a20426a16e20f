"""Step time of the multi-robot env from 4 to 20 robots (docs/results/multi_robot.md quotes it).

    python scripts/bench_multi_robot.py [--robots 4,8,12,16,20] [--steps 100] [--repeats 3]

Every robot of ``multi-circle-<n>`` turns about the circle's centre at a quarter of its top speed (a
quarter turn in 100 steps: no robot reaches its goal), so every robot moves every step and none
touches another (all ``n`` stay in the world: the step pays for every pair's swept test and every
robot's observation of the ``n - 1`` others). Scenes with obstacles are left out: robots circling
among them collide and leave, and fewer robots step faster. Prints the median
step time over ``--repeats`` episodes, per robot, and the ratio to the first row against the ratio of robots
(growth no worse than linear: the ratio stays at or below the robots' ratio).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from pathplan_env.multi_robot import parallel_env


def tangent_actions(env) -> dict:
    actions = {}
    for agent in env.agents:
        i = env.possible_agents.index(agent)
        x, y = env.multi.robots[i].xy
        angle = 0.25 * env.robot_scenario(agent).robot_speed * env.robot_scenario(agent).dt / max(np.hypot(x, y), 1e-9)
        c, s = np.cos(angle), np.sin(angle)
        actions[agent] = env.robot_env(agent).waypoint_to_action(np.array([c * x - s * y, s * x + c * y]))
    return actions


def step_seconds(scenario: str, steps: int, repeats: int) -> float:
    """The median step time over ``repeats`` episodes of ``steps`` steps (the median: the machine is shared)."""
    env = parallel_env(scenario=scenario)
    times = []
    for repeat in range(repeats + 1):  # the first warms the compiled kernels up
        env.reset(seed=repeat)
        for _ in range(steps):
            if len(env.agents) < len(env.possible_agents):
                raise RuntimeError(f"{scenario}: a robot left the world; the benchmark times all of them")
            actions = tangent_actions(env)  # (not timed: a policy's work)
            begin = time.perf_counter()
            env.step(actions)
            if repeat:
                times.append(time.perf_counter() - begin)
    return float(np.median(times))


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--robots", default="4,8,12,16,20", help="robot counts, comma-separated")
    parser.add_argument("--steps", type=int, default=100)
    parser.add_argument("--repeats", type=int, default=3)
    return parser


def parse_args(argv=None) -> argparse.Namespace:
    return build_parser().parse_args(argv)


def main(argv=None) -> None:
    args = parse_args(argv)
    counts = [int(n) for n in args.robots.split(",")]
    print("| scene | robots | step (ms) | per robot (ms) | time ratio | robots ratio |")
    print("|---|---|---|---|---|---|")
    first = None
    for n in counts:
        seconds = step_seconds(f"multi-circle-{n}", args.steps, args.repeats)
        first = first or (seconds, n)
        print(f"| multi-circle-{n} | {n} | {1000 * seconds:.2f} | {1000 * seconds / n:.3f} | {seconds / first[0]:.2f} | {n / first[1]:.2f} |", flush=True)


if __name__ == "__main__":
    main()
