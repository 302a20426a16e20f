"""Env speed in the wall families (issue 21): steps per second with random actions, as a ratio to
CartPole-v1 measured in the same run (``bench_env.paired_ratio``: each repeat times the family, then
CartPole-v1, back to back); then a step and a reset of each apart (random actions end an episode
every few steps in these narrow scenes, so resets weigh); with ``--profile``, where corridor-crowd's
time goes.

    python scripts/bench_families.py [--steps 5000] [--repeats 3] [--profile] [--clock cpu] [--crowd-only]
    python scripts/bench_families.py --against <checkout> [--preset corridor-crowd] [--clock cpu]
    python scripts/bench_families.py --split [--steps 20000] [--clock cpu]

``--split``: the crowd families' random-action time split into steps and resets (mean episode
length, µs a step, ms a reset, resets' µs a step) beside the µs a step the target ratio allows.

``--clock cpu`` times with this thread's CPU time (as ``bench_env.py``'s); ``--crowd-only`` prints
the crowd rows alone (to compare two versions of the package: ``PYTHONPATH=<dir>``).
``--against <checkout>`` compares two versions in one process: the other checkout's package, imported
from a copy under another name, and this one take turns (``--repeats`` rounds of each, then
CartPole-v1), so that a loaded machine's drift cancels in each round's ratio.

Bouncing families at ``--delta-d``; the crowd families' humans at their own speeds. Targets:
corridor-crowd with 20 humans >= 0.12x CartPole-v1 (robot-sf's profile: 1,718 steps/s with 17
pedestrians), doorway-crowd and maze-crowd >= 0.05x.
"""

from __future__ import annotations

import argparse
import cProfile
import hashlib
import importlib
import os
import pkgutil
import pstats
import re
import shutil
import statistics
import sys
import tempfile
import warnings

import gymnasium as gym

import pathplan_env  # (registers DynamicObstacle-v0; its path is printed)
from agents.cli import bench as bench_env  # pathplan-env bench (scripts/bench_env.py)
from agents.cli.bench import CLOCKS, best_of, paired_ratio, steps_per_second

#: ``(preset, obstacles or None for the family's own count, target ratio or None)``.
FAMILY_ROWS = (
    ("corridor", None, None),
    ("doorway", None, None),
    ("intersection", None, None),
    ("cluttered-room", None, None),
    ("maze", None, None),
    ("corridor-crowd", 20, 0.12),
    ("doorway-crowd", None, 0.05),
    ("maze-crowd", None, 0.05),
)


def make_family(preset: str, n: int | None, delta_d: float):
    """The family's env as the benchmark steps it (crowds at their own speeds)."""
    crowd = preset.endswith("-crowd")
    return gym.make("DynamicObstacle-v0", scenario=preset, n_obstacles=n, delta_d=None if crowd else delta_d)


def family_table(reference: gym.Env, steps: int, repeats: int, delta_d: float, rows=FAMILY_ROWS) -> list[str]:
    """The families' rows (markdown), each paired with ``reference`` (CartPole-v1)."""
    lines = ["| family | obstacles | steps/s | ratio to CartPole-v1 | target |", "|---|---:|---:|---:|---:|"]
    for preset, n, target in rows:
        rate, ratio = paired_ratio(lambda preset=preset, n=n: make_family(preset, n, delta_d), reference, steps, repeats)
        count = n if n is not None else make_family(preset, None, delta_d).unwrapped.scenario.n_obstacles
        lines.append(f"| {preset} | {count} | {rate:.0f} | {ratio:.3f}x | {f'>= {target}x' if target else ''} |")
    return lines


def step_and_reset(preset: str, n: int | None, delta_d: float, repeats: int = 3) -> tuple[float, float]:
    """Microseconds per step of the unwrapped env (the robot holding still, 200 steps from a reset;
    the unwrapped env runs on past a contact) and milliseconds per reset, best of ``repeats``."""
    env = make_family(preset, n, delta_d)
    unwrapped = env.unwrapped

    def steps():
        env.reset(seed=0)
        hold = unwrapped.waypoint_to_action(unwrapped.scenario.start)
        start = bench_env.clock()
        for _ in range(200):
            unwrapped.step(hold)
        return (bench_env.clock() - start) / 200

    def resets():
        start = bench_env.clock()
        for seed in range(20):
            env.reset(seed=seed)
        return (bench_env.clock() - start) / 20

    steps(), resets()  # warm-up
    return 1e6 * min(steps() for _ in range(repeats)), 1e3 * min(resets() for _ in range(repeats))


def cost_table(delta_d: float, rows=FAMILY_ROWS) -> list[str]:
    """Where the time goes: a step and a reset of each family, against CartPole-v1's step."""
    cartpole = gym.make("CartPole-v1")
    cartpole.reset(seed=0)
    start = bench_env.clock()
    for _ in range(20000):
        _, _, terminated, truncated, _ = cartpole.step(0)
        if terminated or truncated:
            cartpole.reset()
    cartpole_us = 1e6 * (bench_env.clock() - start) / 20000
    lines = [f"Where the time goes (CartPole-v1 through gym.make, resets included: {cartpole_us:.1f} µs a step)",
             "| family | obstacles | step µs (unwrapped) | CartPole's step ÷ this step | reset ms |", "|---|---:|---:|---:|---:|"]  # fmt: skip
    for preset, n, _ in rows:
        step_us, reset_ms = step_and_reset(preset, n, delta_d)
        count = n if n is not None else make_family(preset, None, delta_d).unwrapped.scenario.n_obstacles
        lines.append(f"| {preset} | {count} | {step_us:.0f} | {cartpole_us / step_us:.3f}x | {reset_ms:.1f} |")
    return lines


def episode_split(preset: str, n: int | None, steps: int, seed: int = 1) -> tuple[float, float, float, float]:
    """``(mean episode length, µs a step without resets, ms a reset, µs a step with resets)`` under
    random actions (``steps_per_second``'s loop, each call timed apart)."""
    env = make_family(preset, n, None)
    steps_per_second(env, min(steps, 1000))  # warm-up
    env.reset(seed=seed)
    env.action_space.seed(seed)
    actions = [env.action_space.sample() for _ in range(steps)]
    clock, stepping, resetting, resets = bench_env.clock, 0.0, 0.0, 0
    for action in actions:
        start = clock()
        _, _, terminated, truncated, _ = env.step(action)
        stepping += clock() - start
        if terminated or truncated:
            start = clock()
            env.reset()
            resetting += clock() - start
            resets += 1
    return steps / max(resets, 1), 1e6 * stepping / steps, 1e3 * resetting / max(resets, 1), 1e6 * (stepping + resetting) / steps


def split_table(reference: gym.Env, steps: int, rows=FAMILY_ROWS) -> list[str]:
    """The crowd families' random-action time split into steps and resets, beside the time a step may
    take at the target ratio (CartPole-v1 timed in the same run)."""
    cartpole = steps_per_second(reference, steps)
    lines = [f"Steps and resets under random actions (CartPole-v1 {cartpole:.0f} steps/s in this run)",
             "| family | obstacles | episode (steps) | step µs | reset ms | resets µs a step | µs a step | µs a step at the target |",
             "|---|---:|---:|---:|---:|---:|---:|---:|"]  # fmt: skip
    for preset, n, target in rows:
        if target is None:
            continue
        length, step_us, reset_ms, total_us = episode_split(preset, n, steps)
        count = n if n is not None else make_family(preset, None, None).unwrapped.scenario.n_obstacles
        budget = 1e6 / (target * cartpole)
        lines.append(f"| {preset} | {count} | {length:.1f} | {step_us:.0f} | {reset_ms:.2f} | {1e3 * reset_ms / length:.0f} | {total_us:.0f} | {budget:.0f} |")
    return lines


def profile(preset: str, n: int | None, delta_d: float, steps: int, top: int = 15) -> None:
    """cProfile of ``steps`` random steps (resets included), the ``top`` functions by own time."""
    env = make_family(preset, n, delta_d)
    steps_per_second(env, min(steps, 1000))  # warm-up: numba cache, routes
    profiler = cProfile.Profile()
    profiler.enable()
    steps_per_second(env, steps, seed=1)
    profiler.disable()
    print(f"\nWhere {preset} ({n if n is not None else 'own count'} obstacles) spends {steps} random steps, by own time:")
    pstats.Stats(profiler).sort_stats("tottime").print_stats(top)
    print("... and by cumulative time (resets and steps, then their parts):")
    pstats.Stats(profiler).sort_stats("cumtime").print_stats(2 * top)


def import_other(checkout: str) -> str:
    """The package of another ``checkout`` imported as ``pathplan_before`` from a copy (one per version
    of its sources, so numba's cache is kept); returns its env id (``Before-DynamicObstacle-v0``).

    Every ``pathplan_env`` in the copy's sources reads ``pathplan_before``: its modules import each other
    (not this checkout's), and ``_moved``'s tables name its own modules (``names_of(__name__)``)."""
    source = os.path.join(checkout, "pathplan_env")
    digest = hashlib.sha256(b"renamed")  # (copies of before the renaming are not reused)
    for d, _, files in sorted(os.walk(source)):
        for f in sorted(files):
            if f.endswith(".py"):
                with open(os.path.join(d, f), "rb") as text:
                    digest.update(text.read())
    root = os.path.join(tempfile.gettempdir(), f"pathplan_before_{digest.hexdigest()[:12]}")
    if not os.path.isdir(root):
        package = os.path.join(root, "pathplan_before")
        shutil.copytree(source, package, ignore=shutil.ignore_patterns("__pycache__"))
        for d, _, files in os.walk(package):
            for f in files:
                if f.endswith(".py"):
                    with open(os.path.join(d, f)) as text:
                        code = re.sub(r"\bpathplan_env\b", "pathplan_before", text.read())
                    if d == package and f == "__init__.py":
                        code = code.replace('id="DynamicObstacle', 'id="Before-DynamicObstacle')
                    with open(os.path.join(d, f), "w") as text:
                        text.write(code)
    sys.path.insert(0, root)
    package = importlib.import_module("pathplan_before")
    distinguish_named_tuples(package)
    return "Before-DynamicObstacle-v0"


def distinguish_named_tuples(package) -> None:
    """Suffix ``_before`` to the ``__name__`` of every NamedTuple class of ``package`` (every module
    imported). numba's dispatcher caches an argument's type by a fingerprint that names a named
    tuple's class by ``__name__`` alone (not its module): the two packages' ``Queue``, ``GridGraph``,
    ``RouteRows``... collide, and every call of the kernels of the package typed second missed the
    cache and was typed again in Python (about 140 µs a call of ``extend_rows``): the side built second
    ran the routes at about half speed."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # (old module paths warn when imported)
        for info in pkgutil.walk_packages(package.__path__, package.__name__ + "."):
            try:
                importlib.import_module(info.name)
            except ImportError:
                continue
    for name, module in list(sys.modules.items()):
        if name == package.__name__ or name.startswith(package.__name__ + "."):
            for value in vars(module).values():
                named_tuple = isinstance(value, type) and issubclass(value, tuple) and hasattr(value, "_fields")
                if named_tuple and value.__module__ == name and not value.__name__.endswith("_before"):
                    value.__name__ += "_before"


def against(checkout: str, preset: str, n: int | None, steps: int, rounds: int) -> None:
    """Interleaved rounds of the other checkout's env and this one's (random actions, resets included),
    each round followed by CartPole-v1: per round, each one's ratio to CartPole-v1 and after ÷ before."""
    other = import_other(checkout)
    envs = {name: gym.make(env_id, scenario=preset, n_obstacles=n, delta_d=None) for name, env_id in (("before", other), ("after", "DynamicObstacle-v0"))}
    cartpole = gym.make("CartPole-v1")
    for env in (*envs.values(), cartpole):
        steps_per_second(env, min(steps, 2000))  # warm-up (numba cache load, allocator)
    print(f"{preset} ({n if n is not None else 'own count'} obstacles): before = {checkout}, after = this checkout; {steps} random steps each")
    print("| round | before steps/s | after steps/s | before ÷ CartPole | after ÷ CartPole | after time ÷ before time |\n|---:|---:|---:|---:|---:|---:|")
    speedups, ratios = [], {"before": [], "after": []}
    for r in range(rounds):
        order = ("before", "after") if r % 2 == 0 else ("after", "before")
        rate = {name: steps_per_second(envs[name], steps, seed=r) for name in order}
        reference = steps_per_second(cartpole, steps, seed=r)
        for name in rate:
            ratios[name].append(rate[name] / reference)
        speedups.append(rate["before"] / rate["after"])
        print(f"| {r + 1} | {rate['before']:.0f} | {rate['after']:.0f} | {ratios['before'][-1]:.3f}x | {ratios['after'][-1]:.3f}x | {speedups[-1]:.3f} |")
    med = statistics.median
    print(f"| median | | | {med(ratios['before']):.3f}x | {med(ratios['after']):.3f}x | {med(speedups):.3f} |")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--steps", type=int, default=5000)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--delta-d", type=float, default=0.25)
    parser.add_argument("--profile", action="store_true", help="also profile --preset (corridor-crowd with 20 humans by default)")
    parser.add_argument("--clock", choices=sorted(CLOCKS), default="wall", help="time with the wall clock or this thread's CPU time")
    parser.add_argument("--crowd-only", action="store_true", help="only the crowd rows: corridor-crowd with 20 humans, doorway-crowd, maze-crowd")
    parser.add_argument("--split", action="store_true", help="only the crowd families' time under random actions split into steps and resets")
    parser.add_argument("--against", metavar="CHECKOUT", help="compare with another checkout's package in this process (interleaved rounds)")
    parser.add_argument("--preset", default="corridor-crowd", help="the family --against compares and --profile profiles (default corridor-crowd)")
    parser.add_argument("--obstacles", default="20", help="its obstacle count, or 'own' for the family's default")
    return parser


def parse_args(argv=None) -> argparse.Namespace:
    return build_parser().parse_args(argv)


def main(argv=None) -> None:
    args = parse_args(argv)
    bench_env.clock = CLOCKS[args.clock]  # steps_per_second reads bench_env's
    print(f"pathplan_env from {os.path.dirname(pathplan_env.__file__)}; clock: {args.clock}; load average (1 min) {os.getloadavg()[0]:.1f}")
    if args.against:
        against(args.against, args.preset, None if args.obstacles == "own" else int(args.obstacles), args.steps, args.repeats)
        print(f"(load average (1 min) {os.getloadavg()[0]:.1f} after; {os.cpu_count()} cores)")
        return
    if args.split:
        print("\n".join(split_table(gym.make("CartPole-v1"), args.steps)))
        print(f"(load average (1 min) {os.getloadavg()[0]:.1f} after; {os.cpu_count()} cores)")
        return
    reference = gym.make("CartPole-v1")
    cartpole = best_of(lambda: reference, args.steps, args.repeats)
    print(f"CartPole-v1: {cartpole:10.0f} steps/s (reference; every ratio below is the median of {args.repeats} paired runs)")
    rows = [row for row in FAMILY_ROWS if row[0].endswith("-crowd")] if args.crowd_only else FAMILY_ROWS
    print("\n".join(family_table(reference, args.steps, args.repeats, args.delta_d, rows)))
    print(f"(load average (1 min) {os.getloadavg()[0]:.1f} after; {os.cpu_count()} cores)")
    print("\n" + "\n".join(cost_table(args.delta_d, rows)))
    if args.profile:
        profile(args.preset, None if args.obstacles == "own" else int(args.obstacles), args.delta_d, args.steps)


if __name__ == "__main__":
    main()
