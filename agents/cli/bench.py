"""Env speed: steps per second with random actions and no rendering, as a ratio to CartPole-v1.

Both are measured in the same run, through ``gym.make`` (the same wrappers), on the same machine,
so the ratio means something on a noisy shared machine where the raw rates do not. A second table
splits the cost: a step without resets (the robot holds still), and a reset. A robot table sets the
unicycle (``robot="unicycle"``, random (speed, turn rate) targets) beside the holonomic robot.

    pathplan-env bench [--steps 20000] [--repeats 3] [--robots-only] [--clock cpu] [--episode-split]

``--clock cpu`` times both with this thread's CPU time instead of the wall clock: on a machine whose
other jobs take the CPU away mid-run, the wall clock charges their time to whichever of the pair was
running; CPU time charges each only its own (cache and memory contention remain, shared by both).
``--episode-split`` prints only how many steps an episode lasts under random actions and the resets'
share of the time, per robot (what the unicycle's ratio depends on: its episodes end sooner).

``python scripts/bench_env.py`` is the same command, with the same flags.
"""

from __future__ import annotations

import argparse
import os
import time

import gymnasium as gym
import numpy as np

import pathplan_env  # (registers DynamicObstacle-v0)

#: The clock every rate is timed with (``--clock``): the wall clock, or this thread's CPU time.
CLOCKS = {"wall": time.perf_counter, "cpu": time.thread_time}
clock = CLOCKS["wall"]


def steps_per_second(env: gym.Env, steps: int, seed: int = 0) -> float:
    env.reset(seed=seed)
    env.action_space.seed(seed)
    actions = [env.action_space.sample() for _ in range(steps)]
    start = clock()
    for action in actions:
        _, _, terminated, truncated, _ = env.step(action)
        if terminated or truncated:
            env.reset()
    return steps / (clock() - start)


def best_of(make, steps: int, repeats: int) -> float:
    env = make()
    steps_per_second(env, min(steps, 2000))  # warm-up (numba cache load, allocator)
    return max(steps_per_second(env, steps, seed=i) for i in range(repeats))


def paired_ratio(make, reference: gym.Env, steps: int, repeats: int) -> tuple[float, float]:
    """``(steps/s, median ratio to the reference)``: each repeat times the env and then the reference
    back to back, so that the machine's load, which drifts over a run, cancels in each ratio."""
    env = make()
    steps_per_second(env, min(steps, 2000))  # warm-up (numba cache load, allocator)
    rates, ratios = [], []
    for i in range(repeats):
        rate = steps_per_second(env, steps, seed=i)
        rates.append(rate)
        ratios.append(rate / steps_per_second(reference, steps, seed=i))
    return float(np.median(rates)), float(np.median(ratios))


def cost_breakdown(n_obstacles: int, delta_d: float, repeats: int = 5) -> tuple[float, float]:
    """Microseconds per step of the unwrapped env (robot holding still, 100 steps from a reset; the
    unwrapped env runs on past a contact) and per reset through ``gym.make``, best of ``repeats``."""
    env = gym.make("DynamicObstacle-v0", scenario="random", n_obstacles=n_obstacles, delta_d=delta_d)
    unwrapped = env.unwrapped

    def steps():
        env.reset(seed=0)
        hold = unwrapped.waypoint_to_action(unwrapped.scenario.start)
        start = time.perf_counter()
        for _ in range(100):
            unwrapped.step(hold)
        return (time.perf_counter() - start) / 100

    def resets():
        start = time.perf_counter()
        for _ in range(100):
            env.reset()
        return (time.perf_counter() - start) / 100

    steps(), resets()  # warm-up
    return 1e6 * min(steps() for _ in range(repeats)), 1e6 * min(resets() for _ in range(repeats))


def episode_split(robot: str, n_obstacles: int, delta_d: float, steps: int, seed: int = 0) -> tuple[float, float, float, float]:
    """``(steps per episode, µs per step, µs per reset, resets' share of the time)`` under random
    actions through ``gym.make``, each call timed with the thread's CPU time (what a paired ratio
    pays for: a robot whose episodes end sooner pays for more resets)."""
    env = gym.make("DynamicObstacle-v0", scenario="random", n_obstacles=n_obstacles, delta_d=delta_d, robot=robot)
    steps_per_second(env, min(steps, 2000), seed=seed)  # warm-up
    env.reset(seed=seed)
    env.action_space.seed(seed)
    actions = [env.action_space.sample() for _ in range(steps)]
    step_time = reset_time = 0.0
    episodes = 0
    for action in actions:
        start = time.thread_time()
        _, _, terminated, truncated, _ = env.step(action)
        step_time += time.thread_time() - start
        if terminated or truncated:
            start = time.thread_time()
            env.reset()
            reset_time += time.thread_time() - start
            episodes += 1
    episodes = max(episodes, 1)
    return steps / episodes, 1e6 * step_time / steps, 1e6 * reset_time / episodes, reset_time / (step_time + reset_time)


def build_parser(prog: str | None = None) -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog=prog, description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--steps", type=int, default=20000)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--delta-d", type=float, default=0.25)
    parser.add_argument("--robots-only", action="store_true", help="only the robot table (holonomic and unicycle, 5 and 20 obstacles)")
    parser.add_argument("--clock", choices=sorted(CLOCKS), default="wall", help="time with the wall clock or this thread's CPU time")
    parser.add_argument("--episode-split", action="store_true", help="only how long episodes last and the resets' share (both robots, 5 obstacles)")
    return parser


def parse_args(argv=None, prog: str | None = None) -> argparse.Namespace:
    return build_parser(prog).parse_args(argv)


def main(argv=None, prog: str | None = None) -> None:
    global clock
    args = parse_args(argv, prog)
    clock = CLOCKS[args.clock]
    print(f"pathplan_env from {os.path.dirname(pathplan_env.__file__)}; clock: {args.clock}")
    if args.episode_split:
        print("| robot | steps per episode | µs per step | µs per reset | resets' share |")
        print("|---|---:|---:|---:|---:|")
        for robot in ("holonomic", "unicycle"):
            length, step_us, reset_us, share = episode_split(robot, 5, args.delta_d, args.steps)
            print(f"| {robot} | {length:.1f} | {step_us:.1f} | {reset_us:.0f} | {share:.2f} |")
        print(f"(CPU time of each call; load average over 1 min: {os.getloadavg()[0]:.1f}; {os.cpu_count()} cores)")
        return
    load_before = os.getloadavg()[0]  # a shared machine's load: what the raw rates below depend on, the ratios far less
    reference = gym.make("CartPole-v1")
    cartpole = best_of(lambda: reference, args.steps, args.repeats)
    print(f"CartPole-v1: {cartpole:10.0f} steps/s (reference; every ratio below is the median of {args.repeats} paired runs)")
    print("\n| robot | obstacles | steps/s | ratio to CartPole-v1 | target |")
    print("|---|---:|---:|---:|---:|")
    for robot, n, target in (("holonomic", 5, ">= 0.5x"), ("unicycle", 5, ">= 0.45x"), ("unicycle", 20, "")):
        make = lambda robot=robot, n=n: gym.make("DynamicObstacle-v0", scenario="random", n_obstacles=n, delta_d=args.delta_d, robot=robot)
        rate, ratio = paired_ratio(make, reference, args.steps, args.repeats)
        print(f"| {robot} | {n} | {rate:.0f} | {ratio:.3f}x | {target} |")
    print(f"\n(load average over 1 min: {load_before:.1f} at the start, {os.getloadavg()[0]:.1f} after the robot table; {os.cpu_count()} cores)")
    if args.robots_only:
        return
    print()
    print("| obstacles | steps/s | ratio to CartPole-v1 | target |")
    print("|---:|---:|---:|---:|")
    targets = {5: 0.5, 50: 0.1}
    for n in (5, 20, 50):
        rate, ratio = paired_ratio(
            lambda n=n: gym.make("DynamicObstacle-v0", scenario="random", n_obstacles=n, delta_d=args.delta_d), reference, args.steps, args.repeats
        )
        target = f">= {targets[n]}x" if n in targets else ""
        print(f"| {n} | {rate:.0f} | {ratio:.3f}x | {target} |")

    # goal-directed crowds: ORCA (or social force) steering every human every step
    print("\n| crowd preset | humans | steps/s | ratio to CartPole-v1 | target |")
    print("|---|---:|---:|---:|---:|")
    for preset, n in (("crowdnav-circle-crossing", 5), ("crowdnav-circle-crossing-visible", 5), ("crowdnav-square-crossing", 5),
                      ("crowdnav-circle-crossing", 10)):  # fmt: skip
        make = lambda preset=preset, n=n: gym.make("DynamicObstacle-v0", scenario=preset, n_obstacles=n, delta_d=None)
        rate, ratio = paired_ratio(make, reference, args.steps, args.repeats)
        target = ">= 0.2x" if n == 5 else ""
        print(f"| {preset} | {n} | {rate:.0f} | {ratio:.3f}x | {target} |")

    cartpole_env = gym.make("CartPole-v1")
    cartpole_env.reset(seed=0)
    start = time.perf_counter()
    for _ in range(10000):
        _, _, terminated, truncated, _ = cartpole_env.step(0)
        if terminated or truncated:
            cartpole_env.reset()
    print(f"\nWhere the time goes, µs (CartPole-v1 through gym.make, resets included: {1e6 * (time.perf_counter() - start) / 10000:.1f} a step)")
    print("| obstacles | step (unwrapped) | reset |")
    print("|---:|---:|---:|")
    for n in (5, 20, 50):
        step_us, reset_us = cost_breakdown(n, args.delta_d)
        print(f"| {n} | {step_us:.1f} | {reset_us:.0f} |")

