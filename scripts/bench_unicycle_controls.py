"""The unicycle's native metaheuristics (``pso-unicycle``, ``abc-unicycle``: the paper's PSO and ABC over
control sequences) beside ``tracked-pso-spacetime`` (the holonomic planner driven by pure pursuit) and
``dwa``: success, collisions and the median replanning time, on the same episodes for every agent.

Random scenes (8 obstacles), ``robot="unicycle"``; ``--split test`` (default) draws
``pathplan_env.scenarios.splits`` test seeds, never used for tuning (tune on ``--split validation``).
``--scenario`` runs a preset at its own speeds instead (e.g. ``crowdnav-circle-crossing``) and lists
the seeds of the episodes each agent fails (``c``: a collision, ``t``: a timeout).

    python scripts/bench_unicycle_controls.py [--episodes 40] [--deltas 0.25 0.5] [--split test]
        [--agents pso-unicycle,abc-unicycle,tracked-pso-spacetime,dwa] [--set iterations=20 ...]
    python scripts/bench_unicycle_controls.py --scenario crowdnav-circle-crossing --split validation --agents abc-unicycle
"""

from __future__ import annotations

import argparse
import ast
import time

import gymnasium as gym
import numpy as np

import agents
import pathplan_env  # noqa: F401
from pathplan_env.scenarios.splits import episode_seeds

AGENTS = ["pso-unicycle", "abc-unicycle", "tracked-pso-spacetime", "dwa"]


def run_cell(name: str, delta_d: float | None, seeds: list[int], n_obstacles: int | None, overrides: dict, robot: str = "unicycle",
             scenario: str = "random", outcomes: list | None = None) -> tuple[float, float, list[float], list[float]]:  # fmt: skip
    """``(success rate, collision rate, plan times in ms, plan CPU times in ms)`` of one agent on the
    episodes ``seeds`` of ``scenario`` (the CPU time, this process's, is what a shared machine's load
    changes least); ``overrides`` go to the ``*-unicycle`` agents only; ``outcomes``, if given, receives each
    episode's ``(seed, success, collision, steps)``. ``bench_unicycle`` runs it too."""
    env = gym.make("DynamicObstacle-v0", scenario=scenario, n_obstacles=n_obstacles, delta_d=delta_d, robot=robot)
    agent = agents.make(name, env, seed=0, **(overrides if name.endswith(("-unicycle", "-unicycle-crowd")) else {}))
    results, plan_ms, cpu_ms = [], [], []
    for seed in seeds:
        agent.reset()
        obs, info = env.reset(seed=seed)
        steps = 0
        while True:
            steps += 1
            cpu = time.process_time()
            action, _ = agent.predict(obs, deterministic=True)
            cpu_ms.append(1e3 * (time.process_time() - cpu))
            plan_ms.append(1e3 * agent.last_plan_seconds)
            obs, _, terminated, truncated, info = env.step(action)
            if terminated or truncated:
                break
        results.append((info["is_success"], info["collision"]))
        if outcomes is not None:
            outcomes.append((seed, bool(info["is_success"]), bool(info["collision"]), steps))
    won, hit = np.mean(results, axis=0)
    return float(won), float(hit), plan_ms, cpu_ms


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--episodes", type=int, default=40)
    parser.add_argument("--deltas", type=float, nargs="+", default=[0.25, 0.5])
    parser.add_argument("--split", choices=("test", "validation"), default="test")
    parser.add_argument("--agents", default=",".join(AGENTS), help="comma-separated agent names")
    parser.add_argument("--obstacles", type=int, default=8)
    parser.add_argument("--scenario", default="random", help="a preset; any but random runs at its own speeds and obstacle count")
    parser.add_argument("--set", nargs="*", default=[], metavar="KEY=VALUE", help="overrides for the *-unicycle agents")
    return parser


def parse_args(argv=None) -> argparse.Namespace:
    return build_parser().parse_args(argv)


def main(argv=None) -> None:
    args = parse_args(argv)
    overrides = {key: ast.literal_eval(value) for key, value in (item.split("=", 1) for item in args.set)}
    seeds = [int(s) for s in episode_seeds(args.split, 0, args.episodes)]
    own = args.scenario != "random"
    deltas, n_obstacles = ([None], None) if own else (args.deltas, args.obstacles)
    scene = f"{args.scenario} at its own speeds" if own else f"random scenes, {args.obstacles} obstacles"
    print(f"{scene}, unicycle, {args.episodes} {args.split} episodes (seeds {seeds[0]}..{seeds[-1]})"
          + (f", overrides {overrides}" if overrides else ""))  # fmt: skip
    heads = ["success (collisions)"] if own else [f"Δd {d}: success (collisions)" for d in deltas]
    print("| agent | " + " | ".join(heads) + " | median plan ms | median plan CPU ms | wall s |" + (" failed episodes |" if own else ""))
    print("|---|" + "---:|" * (len(deltas) + 3) + ("---|" if own else ""))
    for name in args.agents.split(","):
        begin = time.perf_counter()
        cells, plan_ms, cpu_ms, outcomes = [], [], [], []
        for delta_d in deltas:
            won, hit, times, cpu = run_cell(name, delta_d, seeds, n_obstacles, overrides, scenario=args.scenario, outcomes=outcomes)
            cells.append(f"{won:.3f} ({hit:.3f})")
            plan_ms, cpu_ms = plan_ms + times, cpu_ms + cpu
        wall = time.perf_counter() - begin
        failed = " ".join(f"{seed - seeds[0]}{'c' if hit else 't'}" for seed, won, hit, _ in outcomes if not won)
        print(f"| {name} | " + " | ".join(cells) + f" | {np.median(plan_ms):.2f} | {np.median(cpu_ms):.2f} | {wall:.0f} |"
              + (f" {failed} |" if own else ""), flush=True)  # fmt: skip


if __name__ == "__main__":
    main()
