"""Crowd steps beside navground (PyPI ``navground``, C++): the same scenes built in both from the same
lists (``pathplan_env.world.navground_peer``), their agreement, then our step time ÷ navground's
(process CPU time, median of ``--repeats``; > 1: navground is faster) for ``World.step`` and for
``DynamicObstacle-v0.step`` (the unwrapped env, the robot holding still), per crowd size of
CrowdNav's circle crossing and for the corridor with 20 humans, from one process, the two taking
turns at going first.

    python scripts/bench_crowds.py [--steps 100] [--repeats 9] [--sizes 2 5 10 15 20]
    python scripts/bench_crowds.py --split [--sizes 2 5]
    python scripts/bench_crowds.py --env-split [--sizes 5]

``--split``: what our ``World.step`` is made of at those sizes (no navground needed): the whole step,
the compiled step called directly, the Python/compiled boundary alone, Chipmunk's step alone.
``--env-split``: what ``DynamicObstacle-v0.step`` adds to it (µs): the general step's pieces (the
action's move, the observation, the reward terms, the info), the fused step's one compiled call
(``pathplan_env.fused_step``, which replaces them and ``World.step`` where it applies), and the
least any Gymnasium step of this env can cost: the world's step (or the fused call) and the three
dicts the API returns (the observation's seven arrays, the reward terms, the info) built from ready
values; with navground installed, its step timed alike and the env step's and the floor's ratios to it
(the means' ratio).

navground is in the ``crowds-bench`` extra (``pip install -e .[crowds-bench]``); without it the
script says so and stops.
"""

from __future__ import annotations

import argparse
import importlib.util
import sys

import gymnasium as gym

import pathplan_env  # noqa: F401  (registers DynamicObstacle-v0)
from pathplan_env.world.navground_peer import (
    CORRIDOR_HUMANS,
    CROWD_SIZES,
    agreement,
    cpu_seconds,
    crowd_scene,
    navground_stepper,
    paired_ratio,
    step_split,
    world_stepper,
)


def env_stepper(scenario):
    """A fresh env of ``scenario`` (reset) and its unwrapped step, the robot holding still."""
    env = gym.make("DynamicObstacle-v0", scenario=scenario)
    env.reset(seed=0)
    unwrapped = env.unwrapped
    hold = unwrapped.waypoint_to_action(scenario.start)
    return lambda: unwrapped.step(hold)


def env_split(scenario, steps: int = 100, envs: int = 200, with_peer: bool = False) -> dict:
    """What one ``DynamicObstacle-v0.step`` of ``scenario`` is made of (µs a step, process CPU time
    over ``steps`` steps of each of ``envs`` fresh envs, the robot holding still): the whole step;
    ``World.step``; the general step's pieces (``DynamicObstacleEnv.step`` where the fused step does
    not apply: the action's move, the observation, the reward terms, the info); the fused step's
    one compiled call (``pathplan_env.fused_step``: the move, the world's step, the observation's
    row, the reward terms that need no distance); the least any Gymnasium step of this env can cost
    with ``World.step`` (its step and the three dicts the API returns, built from ready values and the
    observation's seven fresh views of a row), and with the fused call in its place; with
    ``with_peer``, navground's step of the same scene (a fresh world each time, timed alike)."""
    from pathplan_env import fused_step

    def parts():
        env = gym.make("DynamicObstacle-v0", scenario=scenario)
        env.reset(seed=0)
        u = env.unwrapped
        world, hold = u.world, u.waypoint_to_action(scenario.start)
        rewards = u._rewards(False, False, 1.0, 1.0)
        entries = u.observation_type._entries  # the block's seven entries: an observation's arrays are views of one row
        fused = u._fused
        if fused is not None:
            fused._set_block(u.observation_type._block)
            entry, address = fused_step._ENTRY_FLOAT32, fused._address
            compiled = lambda: entry(address, hold, *world.robot_xy, 1)  # (the world's state steps; the robot holds)
        else:
            compiled = lambda: world.step(0.0, 0.0)

        def dicts(min_gap):  # the API's three dicts from ready values (the observation's seven fresh views of a row)
            p, v, g, ps, vs, r, m = entries
            obs = {"robot_position": p[1], "robot_velocity": v[1], "goal": g[1], "obstacle_positions": ps[1], "obstacle_velocities": vs[1],
                   "obstacle_radii": r[1], "obstacle_mask": m[1]}  # fmt: skip
            terms = {"progress": 0.0, "goal": 0.0, "collision": 0.0, "time": -0.005, "proximity": 0.0}
            info = {"is_success": False, "collision": False, "cost": 0.0, "min_clearance": min_gap, "path_length": 0.0, "time": world.time,
                    "distance_to_goal": 1.0, "waypoint": (0.0, 0.0), "rewards": terms}  # fmt: skip
            return obs, -0.005, False, False, info

        def floor():  # World.step and the API's three dicts, nothing else
            min_gap, _ = world.step(0.0, 0.0)
            return dicts(min_gap)

        def fused_floor():  # the fused step's compiled call and the API's three dicts, nothing else
            compiled()
            return dicts(1.0)

        return {
            "env step": lambda: u.step(hold),
            "World.step": lambda: world.step(0.0, 0.0),
            "action's move": lambda: u.action_type.act(hold, world.robot_xy),
            "observation": lambda: u._observe(world),
            "reward terms": lambda: u._rewards(False, False, 1.0, 1.0),
            "info": lambda: u._info(False, False, 1.0, rewards),
            "floor: World.step + the API's dicts": floor,
            "fused compiled call": compiled,
            "floor: fused call + the API's dicts": fused_floor,
            **({"navground's step": navground_stepper(scenario)} if with_peer else {}),
        }

    totals = dict.fromkeys(parts(), 0.0)
    for part in parts().values():
        cpu_seconds(part, steps)  # warm-up: numba's cache loads on the first call of each kernel
    for _ in range(envs):
        for name in totals:
            totals[name] += cpu_seconds(parts()[name], steps)
    return {name: 1e6 * total / (envs * steps) for name, total in totals.items()}


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--steps", type=int, default=100, help="steps timed per repeat from a fresh scene (100: 10 s, the crossing)")
    parser.add_argument("--repeats", type=int, default=9)
    parser.add_argument("--sizes", type=int, nargs="+", default=list(CROWD_SIZES))
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--split", action="store_true", help="only what World.step is made of (µs), per size")
    parser.add_argument("--env-split", action="store_true", help="only what DynamicObstacle-v0.step is made of (µs), per size")
    return parser


def parse_args(argv=None) -> argparse.Namespace:
    return build_parser().parse_args(argv)


def main(argv=None) -> None:
    args = parse_args(argv)
    if args.split:
        print("| humans | `World.step` µs | compiled step | call boundary | `cpSpaceStep` |\n|---:|---:|---:|---:|---:|")
        for n in args.sizes:
            parts = step_split(crowd_scene("circle", n, args.seed))
            print(f"| {n} | " + " | ".join(f"{us:.2f}" for us in parts.values()) + " |", flush=True)
        return
    if args.env_split:
        with_peer = importlib.util.find_spec("navground") is not None
        for n in args.sizes:
            parts = env_split(crowd_scene("circle", n, args.seed), with_peer=with_peer)
            if with_peer:  # the env's step and its floor (no bookkeeping at all) against navground's step
                peer = parts["navground's step"]
                parts["env step ÷ navground"] = parts["env step"] / peer
                parts["floor ÷ navground"] = parts["floor: fused call + the API's dicts"] / peer
            if n == args.sizes[0]:
                print("| humans | " + " | ".join(parts) + " |\n|---:|" + "---:|" * len(parts))
            print(f"| {n} | " + " | ".join(f"{us:.2f}" for us in parts.values()) + " |", flush=True)
        if not with_peer:
            print("(navground is not installed: no ratios to its step)")
        return
    if importlib.util.find_spec("navground") is None:
        print("bench_crowds: navground is not installed (pip install -e .[crowds-bench]); nothing to compare, skipped")
        return
    scenes = [(f"circle, {n}", crowd_scene("circle", n, args.seed)) for n in args.sizes]
    scenes.append((f"corridor, {CORRIDOR_HUMANS}", crowd_scene("corridor", CORRIDOR_HUMANS, args.seed)))
    print(f"dt {scenes[0][1].dt} s, {args.steps} steps a repeat, median of {args.repeats}; ratio = our step time / navground's (> 1: navground faster)\n")
    print("| scene, humans | max deviation after 1 s (mm) | at goal after 20 s: ours / navground |")
    print("|---|---:|---:|")
    for name, scenario in scenes:
        a = agreement(scenario)
        print(f"| {name} | {1e3 * a['deviation']:.1f} | {a['ours_at_goal']:.2f} / {a['navground_at_goal']:.2f} |")
    print("\n| scene, humans | navground µs/step | `World.step` µs | ratio | `DynamicObstacle-v0.step` µs | ratio |")
    print("|---|---:|---:|---:|---:|---:|")
    for name, scenario in scenes:
        world, world_us, peer_us = paired_ratio(lambda s=scenario: world_stepper(s), lambda s=scenario: navground_stepper(s), args.steps, args.repeats)
        env, env_us, _ = paired_ratio(lambda s=scenario: env_stepper(s), lambda s=scenario: navground_stepper(s), args.steps, args.repeats)
        print(f"| {name} | {peer_us:.1f} | {world_us:.1f} | {world:.2f} | {env_us:.1f} | {env:.2f} |", flush=True)


if __name__ == "__main__":
    sys.exit(main())
