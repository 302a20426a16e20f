"""Step time of the multi-robot env from 4 to 20 robots, and beside navground-learning's PettingZoo env
(docs/results/multi_robot.md quotes both).

    python scripts/bench_multi_robot.py [--robots 4,8,12,16,20] [--steps 100] [--repeats 3]
    python scripts/bench_multi_robot.py --navground [--steps 100] [--repeats 9]

Every robot of ``multi-circle-<n>`` turns about the circle's centre at a quarter of its top speed (a
quarter turn in 100 steps: no robot reaches its goal), so every robot moves every step and none
touches another (all ``n`` stay in the world: the step pays for every pair's swept test and every
robot's observation of the ``n - 1`` others). Scenes with obstacles are left out: robots circling
among them collide and leave, and fewer robots step faster. Prints the median
step time over ``--repeats`` episodes, per robot, and the ratio to the first row against the ratio of robots
(growth no worse than linear: the ratio stays at or below the robots' ratio).

``--navground``: 10 robots among 10 ORCA humans (``pathplan_env.multi_robot.navground_peer``: the
same scene built in both, every robot holding still and observing every other body) in our env and in
navground-learning's ``shared_parallel_env``; the step time of each (process CPU time, median of
``--repeats`` rounds from fresh envs, the two taking turns at going first, from one process) and our
step time ÷ navground's (< 1: ours is faster). navground and navground-learning are in the
``multi-robot-bench`` extra; without them the script says so and stops.
"""

from __future__ import annotations

import argparse
import importlib.util
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
    parser.add_argument("--repeats", type=int, default=None, help="episodes (3) or, with --navground, rounds (9)")
    parser.add_argument("--navground", action="store_true", help="10 robots and 10 ORCA humans beside navground-learning's env")
    parser.add_argument("--humans", type=int, default=10, help="with --navground: the humans (the robots are --robots' first count, 10 by default)")
    return parser


def parse_args(argv=None) -> argparse.Namespace:
    return build_parser().parse_args(argv)


def navground_comparison(robots: int, humans: int, steps: int, repeats: int) -> None:
    """Print our step time and navground-learning's on the same scene, and the ratio."""
    if importlib.util.find_spec("navground") is None or importlib.util.find_spec("navground.learning") is None:
        print("bench_multi_robot: navground-learning is not installed (pip install -e .[multi-robot-bench]); nothing to compare, skipped")
        return
    from pathplan_env.multi_robot.navground_peer import crowd_scene, navground_stepper, ours_stepper
    from pathplan_env.world.navground_peer import paired_ratio

    scene = crowd_scene(robots, humans)
    ratio, ours_us, peer_us = paired_ratio(lambda: ours_stepper(scene), lambda: navground_stepper(scene), steps, repeats)
    print(f"{robots} robots and {humans} ORCA humans, dt {scene.world.dt} s, {steps} steps a round, median of {repeats} rounds (process CPU time)\n")
    print("| env | step (µs) |\n|---|---:|")
    print(f"| pathplan_env.multi_robot (ours) | {ours_us:.0f} |\n| navground-learning shared_parallel_env | {peer_us:.0f} |")
    print(f"\nratio (our step time / navground's): {ratio:.2f} (ours {1 / ratio:.2f}x navground's speed)")


def main(argv=None) -> None:
    args = parse_args(argv)
    counts = [int(n) for n in args.robots.split(",")]
    if args.navground:
        robots = counts[0] if args.robots != build_parser().get_default("robots") else 10
        navground_comparison(robots, args.humans, args.steps, 9 if args.repeats is None else args.repeats)
        return
    args.repeats = 3 if args.repeats is None else args.repeats
    print("| scene | robots | step (ms) | per robot (ms) | time ratio | robots ratio |")
    print("|---|---|---|---|---|---|")
    first = None
    for n in counts:
        seconds = step_seconds(f"multi-circle-{n}", args.steps, args.repeats)
        first = first or (seconds, n)
        print(f"| multi-circle-{n} | {n} | {1000 * seconds:.2f} | {1000 * seconds / n:.3f} | {seconds / first[0]:.2f} | {n / first[1]:.2f} |", flush=True)


if __name__ == "__main__":
    main()
