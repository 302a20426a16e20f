"""Sensor speed: our compiled lidar beside ir-sim's ``Lidar2D`` on the same scene, in the same run.

The scene (seeded): a 20 m x 20 m arena, the robot at its centre, 50 discs (radius 0.2-0.6 m) and 100
wall segments (0.5-2 m, no thickness), all random; a 360-beam, 360°, 10 m scan. ir-sim builds the
same scene from a YAML world (circles and ``linestring`` obstacles); its circles are shapely buffers
(64-edge polygons) and its beams are ``linspace(-pi, pi, 360)`` (the first and last coincide), so we
compare the scans on its first 359 beams: they differ only where a beam meets a polygon's edge
instead of the circle (by its sagitta, more on grazing beams). ir-sim is in
the ``bench`` extra (``pip install ir-sim``); without it, its rows are skipped.

Also: our 1,080-beam scan against our 360-beam one, and the env's steps/s with the 360-beam
``"lidar"`` observation and 5 obstacles beside CartPole-v1 (``scripts/bench_env.py``'s paired runs).

``--planning N``: what partial observability costs a planner: success rates over N random scenes at
Δd 0.5 (test seeds) on ``"state"`` and on ``"visible-state"`` (360° at 10 m, and at 3 m), beside the
clairvoyant limit (``--limit``).

    python scripts/bench_sensors.py [--repeats 7] [--steps 20000]
    python scripts/bench_sensors.py --skip-timing --planning 40 --agents astar-spacetime,pso-spacetime --limit [--n-obstacles 20]
"""

from __future__ import annotations

import argparse
import math
import tempfile
import time
from pathlib import Path

import gymnasium as gym
import numpy as np

import pathplan_env  # noqa: F401  (registers DynamicObstacle-v0)
from agents.cli.bench import best_of, paired_ratio  # pathplan-env bench (scripts/bench_env.py)
from pathplan_env.geometry.rays import beam_directions, scan_beams
from pathplan_env.sensors.visible_state import visible_obstacles

SIZE, RANGE, BEAMS, ROBOT = 20.0, 10.0, 360, (10.0, 10.0)


def make_scene(seed: int = 0, n_discs: int = 50, n_segments: int = 100):
    """``(centres (N, 4), radii, segments (M, 5))``: none within 0.3 m of the robot."""
    rng = np.random.default_rng(seed)
    centres, radii = [], []
    while len(radii) < n_discs:
        c, r = rng.uniform(0, SIZE, 2), rng.uniform(0.2, 0.6)
        if math.dist(c, ROBOT) > r + 0.3:
            centres.append([*c, 0.0, 0.0])
            radii.append(r)
    segments = []
    while len(segments) < n_segments:
        a, angle, length = rng.uniform(0, SIZE, 2), rng.uniform(0, 2 * math.pi), rng.uniform(0.5, 2.0)
        b = np.clip(a + length * np.array([math.cos(angle), math.sin(angle)]), 0.0, SIZE)
        e, p = b - a, np.array(ROBOT) - a
        closest = a + np.clip(p @ e / (e @ e), 0, 1) * e
        if math.dist(closest, ROBOT) > 0.3:
            segments.append([*a, *b, 0.0])
    return np.array(centres), np.array(radii), np.array(segments)


class OurScan:
    """Our kernel on the scene, ``beams`` beams over 360° starting at ``start`` (default: beam i at
    -pi + (i + 1/2) 2pi/beams, our convention)."""

    def __init__(self, scene, beams: int, step: float | None = None, start: float | None = None):
        self.step = 2 * math.pi / beams if step is None else step
        self.start = -math.pi if start is None else start
        angles = self.start + (np.arange(beams) + 0.5) * self.step
        self.directions = beam_directions(0.0, 2 * math.pi, beams) if step is None else np.column_stack([np.cos(angles), np.sin(angles)])
        self.scene, self.bounds = scene, (0.0, 0.0, float(SIZE), float(SIZE))
        self.ranges, self.hits = np.empty(beams), np.empty(beams, np.int64)

    def __call__(self) -> np.ndarray:
        centres, radii, segments = self.scene
        scan_beams((*ROBOT, self.start, self.step, RANGE, self.directions), (centres, radii, segments, *self.bounds), self.ranges, self.hits)
        return self.ranges


def irsim_lidar(scene, directory: Path):
    """ir-sim's Lidar2D among the same discs and segments (None if ir-sim is not installed)."""
    try:
        import irsim
        import yaml
    except ImportError:
        return None
    centres, radii, segments = scene
    world = {
        "world": {"height": SIZE, "width": SIZE, "step_time": 0.1, "collision_mode": "unobstructed"},
        "robot": [{"kinematics": {"name": "omni"}, "shape": {"name": "circle", "radius": 0.2}, "state": [*ROBOT, 0.0],
                   "sensors": [{"name": "lidar2d", "range_min": 0, "range_max": RANGE, "angle_range": 2 * math.pi, "number": BEAMS}]}],
        "obstacle": [{"shape": {"name": "circle", "radius": float(r)}, "state": [float(c[0]), float(c[1]), 0.0]} for c, r in zip(centres, radii)]
        + [{"shape": {"name": "linestring", "vertices": [s[:2].tolist(), s[2:4].tolist()]}, "state": [0.0, 0.0, 0.0]} for s in segments],
    }  # fmt: skip
    path = directory / "bench_sensors_world.yaml"
    path.write_text(yaml.safe_dump(world))
    env = irsim.make(str(path), headless=True, log_level="WARNING")
    robot = env.robot
    lidar = robot.sensors[0]

    def scan() -> np.ndarray:
        lidar.step(robot.state)
        return np.array(lidar.get_scan()["ranges"])

    return scan


def per_call_us(function, calls: int, repeats: int) -> float:
    """Microseconds per call, best of ``repeats`` batches (the least disturbed by a shared machine)."""
    function()  # warm-up (numba's cache load)
    best = math.inf
    for _ in range(repeats):
        start = time.perf_counter()
        for _ in range(calls):
            function()
        best = min(best, (time.perf_counter() - start) / calls)
    return 1e6 * best


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--steps", type=int, default=20000, help="env steps per timed run")
    parser.add_argument("--planning", type=int, default=0, metavar="N", help="also run planners on N episodes per observation")
    parser.add_argument("--agents", default="astar-spacetime", help="comma-separated planners for --planning")
    parser.add_argument("--limit", action="store_true", help="with --planning: the clairvoyant oracle's success too")
    parser.add_argument("--n-obstacles", type=int, default=None, help="with --planning: obstacles per random scene (default: the preset's)")
    parser.add_argument("--skip-timing", action="store_true", help="only --planning")
    return parser


def parse_args(argv=None) -> argparse.Namespace:
    return build_parser().parse_args(argv)


def main(argv=None) -> None:
    args = parse_args(argv)
    if not args.skip_timing:
        timing(args)
    if args.planning:
        planning(args.planning, args.agents.split(","), args.limit, args.n_obstacles)


def timing(args) -> None:
    scene = make_scene()
    ours = per_call_us(OurScan(scene, BEAMS), 500, args.repeats)
    print(f"Scene: 50 discs, 100 wall segments, {BEAMS} beams over 360°, {RANGE:g} m range (seed 0)\n")
    print("| scan | µs per scan | ratio |")
    print("|---|---:|---:|")
    print(f"| ours, {BEAMS} beams | {ours:.1f} | 1 |")
    with tempfile.TemporaryDirectory() as directory:
        theirs = irsim_lidar(scene, Path(directory))
        if theirs is None:
            print("| ir-sim Lidar2D | (not installed: pip install ir-sim) | |")
        else:
            their_us = per_call_us(theirs, 3, max(3, args.repeats // 2))
            print(f"| ir-sim {_irsim_version()} Lidar2D, {BEAMS} beams | {their_us:.0f} | {their_us / ours:.0f}x slower (target >= 50x) |")
            # the same directions as ir-sim's first 359 beams: -pi + i 2pi/359
            step = 2 * math.pi / (BEAMS - 1)
            same = OurScan(scene, BEAMS - 1, step=step, start=-math.pi - step / 2)()
            gap = np.abs(theirs()[: BEAMS - 1] - same)
            print(f"\nAgreement with ir-sim on its first {BEAMS - 1} beams: median |Δ| {np.median(gap):.2g} m, "
                  f"95th percentile {np.percentile(gap, 95):.2g} m, max {gap.max():.2g} m (its circles are 64-gons)")  # fmt: skip
    many = per_call_us(OurScan(scene, 3 * BEAMS), 500, args.repeats)
    print(f"\n| ours, {3 * BEAMS} beams | {many:.1f} | {many / ours:.2f}x our {BEAMS}-beam time (target < 3x) |")
    visible, witness = np.zeros(len(scene[1]), np.bool_), np.zeros(len(scene[1]))
    exact = per_call_us(lambda: visible_obstacles(*ROBOT, 0.0, 2 * math.pi, RANGE, *scene, visible, witness), 20, args.repeats)
    print(f"| \"visible-state\"'s exact visibility, same scene ({visible.sum()} of 50 discs visible) | {exact:.0f} | |")

    reference = gym.make("CartPole-v1")
    cartpole = best_of(lambda: reference, args.steps, 3)
    lidar = {"observation": "lidar", "observation_params": {"lidar_beams": BEAMS}}
    make = lambda: gym.make("DynamicObstacle-v0", scenario="random", n_obstacles=5, delta_d=0.25, **lidar)
    rate, ratio = paired_ratio(make, reference, args.steps, 5)
    state_rate, state_ratio = paired_ratio(lambda: gym.make("DynamicObstacle-v0", scenario="random", n_obstacles=5, delta_d=0.25), reference, args.steps, 5)
    seen = lambda: gym.make("DynamicObstacle-v0", scenario="random", n_obstacles=5, delta_d=0.25, observation="visible-state")
    seen_rate, seen_ratio = paired_ratio(seen, reference, args.steps, 5)
    print(f"\nCartPole-v1: {cartpole:.0f} steps/s (reference; ratios are medians of 5 paired runs)")
    print("| env, 5 obstacles | steps/s | ratio to CartPole-v1 | target |")
    print("|---|---:|---:|---:|")
    print(f"| observation=\"lidar\", {BEAMS} beams | {rate:.0f} | {ratio:.3f}x | >= 0.35x |")
    print(f"| observation=\"state\" | {state_rate:.0f} | {state_ratio:.3f}x | |")
    print(f"| observation=\"visible-state\" (360°, 10 m) | {seen_rate:.0f} | {seen_ratio:.3f}x | |")


def planning(episodes: int, names: list[str], limit: bool, n_obstacles: int | None = None) -> None:
    """Success rates on "state" and "visible-state" over the same test-split episodes."""
    import agents
    from pathplan_env.scenarios.splits import heldout_seeds

    seeds = heldout_seeds(0, episodes)
    sensors = [("state", None), ("visible-state", 10.0), ("visible-state", 3.0)]  # (observation, a 360° sensor's range)
    rates = {}
    for name in (["oracle-clairvoyant"] if limit else []) + names:
        for observation, reach in sensors if name != "oracle-clairvoyant" else sensors[:1]:
            params = None if reach is None else {"lidar_range": reach}
            env = gym.make("DynamicObstacle-v0", scenario="random", n_obstacles=n_obstacles, delta_d=0.5, observation=observation,
                           observation_params=params)  # fmt: skip
            agent = agents.make(name, env, seed=0)
            rates[name, observation, reach] = np.mean([agents.rollout(agent, env, seed=seed)["is_success"] for seed in seeds])
    top = rates.get(("oracle-clairvoyant", "state", None))
    count = "the preset's 8" if n_obstacles is None else n_obstacles
    print(f"\nPlanning on what is seen: random scenes ({count} obstacles), Δd 0.5, {episodes} test episodes (seeds {seeds[0]}..{seeds[-1]})")
    print("| agent | observation | success | ÷ clairvoyant limit |")
    print("|---|---|---:|---:|")
    for (name, observation, reach), rate in rates.items():
        sensor = "" if reach is None else f" (360°, {reach:g} m)"
        share = f"{rate / top:.3f}" if top else ""
        print(f"| {name} | {observation}{sensor} | {rate:.3f} | {share} |")


def _irsim_version() -> str:
    from importlib.metadata import version

    return version("ir-sim")


if __name__ == "__main__":
    main()
