"""What turning costs: success of the unicycle's agents beside the same planners on the holonomic robot,
against each robot's own clairvoyant limit, and the unicycle env's speed beside CartPole-v1.

Random scenes (8 obstacles), validation seeds (``pathplan_env.splits.validation_seeds``, never the
test split), the same episodes for every agent; ``tracked-<planner>`` is the planner driven by pure
pursuit (``agents.reactive.tracker``), ``dwa`` the dynamic window approach (``agents.reactive.dwa``),
``astar-unicycle`` the space-time A* over the unicycle's own moves (``agents.planners.unicycle_search``).

``--limit`` runs the evaluation harness instead (``agents.evaluation.evaluate``, ``--split test`` by
default): each robot's agents and its clairvoyant limit (``oracle-clairvoyant``, which searches the
unicycle's own moves when the robot is one) on random scenes at ``--deltas`` and on CrowdNav's circle
crossing at its own speeds, and prints success ÷ limit with the median and p95 replanning time.

    python scripts/bench_unicycle.py [--episodes 40] [--deltas 0.25 0.5] [--steps 20000]
    python scripts/bench_unicycle.py --limit --episodes 40 --deltas 0.25 0.5 1 [--workers 2] [--out results/unicycle]
"""

from __future__ import annotations

import argparse
import time

import gymnasium as gym
import numpy as np

import agents
import pathplan_env  # noqa: F401
from pathplan_env.splits import validation_seeds

#: (label, agent, robot)
ENTRIES = [
    ("astar-unicycle", "astar-unicycle", "unicycle"),
    ("dwa", "dwa", "unicycle"),
    ("tracked-astar-spacetime", "tracked-astar-spacetime", "unicycle"),
    ("tracked-pso-spacetime", "tracked-pso-spacetime", "unicycle"),
    ("astar-spacetime (holonomic)", "astar-spacetime", "holonomic"),
    ("pso-spacetime (holonomic)", "pso-spacetime", "holonomic"),
]


def success_table(episodes: int, deltas: list[float], n_obstacles: int = 8, only: list[str] | None = None) -> None:
    seeds = [int(s) for s in validation_seeds(0, episodes)]
    print(f"random scenes, {n_obstacles} obstacles, {episodes} validation episodes (seeds {seeds[0]}..{seeds[-1]})")
    print("| agent | robot | " + " | ".join(f"Δd {d}: success (collisions)" for d in deltas) + " | median plan ms |")
    print("|---|---|" + "---:|" * (len(deltas) + 1))
    for label, name, robot in ENTRIES:
        if only and label not in only:
            continue
        cells, plan_ms = [], []
        for delta_d in deltas:
            env = gym.make("DynamicObstacle-v0", scenario="random", n_obstacles=n_obstacles, delta_d=delta_d, robot=robot)
            agent = agents.make(name, env, seed=0)
            outcomes = []
            for seed in seeds:
                agent.reset()
                obs, info = env.reset(seed=seed)
                while True:
                    action, _ = agent.predict(obs, deterministic=True)
                    plan_ms.append(1e3 * agent.last_plan_seconds)
                    obs, _, terminated, truncated, info = env.step(action)
                    if terminated or truncated:
                        break
                outcomes.append((info["is_success"], info["collision"]))
            won, hit = np.mean(outcomes, axis=0)
            cells.append(f"{won:.3f} ({hit:.3f})")
        print(f"| {label} | {robot} | " + " | ".join(cells) + f" | {np.median(plan_ms):.1f} |", flush=True)


#: ``--limit``: each robot's agents, each run against its own robot's limit.
LIMIT_AGENTS = {"unicycle": ["astar-unicycle", "astar-unicycle-crowd", "dwa", "tracked-astar-spacetime"], "holonomic": ["astar-spacetime", "astar-crowd"]}
LIMIT_SCENARIOS = [("random", "deltas"), ("crowdnav-circle-crossing", None)]  # None: the scenario's own speeds


def limit_table(episodes: int, deltas: list[float], split: str, workers: int, out: str, only: list[str] | None = None,
                robots: list[str] | None = None, scenarios: list[str] | None = None) -> list[dict]:  # fmt: skip
    """Run the harness per robot and scenario; print one row per (agent, scenario, Δd) with success ÷ limit."""
    from agents.evaluation import evaluate

    rows = []
    for robot in robots or list(LIMIT_AGENTS):
        names = [n for n in LIMIT_AGENTS[robot] if not only or n in only]
        for scenario, cell in [(s, c) for s, c in LIMIT_SCENARIOS if not scenarios or s in scenarios]:
            cells = deltas if cell == "deltas" else [None]
            options = {"robot": robot} if robot != "holonomic" else None
            rows += [r | {"robot": robot} for r in evaluate(names, [scenario], cells, episodes, f"{out}/{robot}-{scenario}", split=split,
                                                            workers=workers, env_options=options, plots=False)]  # fmt: skip
    print(f"\n{episodes} {split} episodes a cell (8 obstacles on random scenes); limit: oracle-clairvoyant on the same robot")
    print("| agent | robot | scenario | Δd | success | limit | success ÷ limit | plan ms median | p95 |")
    print("|---|---|---|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        if r["agent"] == "oracle-clairvoyant":
            continue
        over = r.get("success_over_limit")
        delta = "own" if r["delta_d"] is None else f"{r['delta_d']:g}"
        print(f"| {r['agent']} | {r['robot']} | {r['scenario']} | {delta} | {r['success_rate']:.3f} | {r.get('limit', float('nan')):.3f} | "
              f"{'-' if over is None else f'{over:.3f}'} | {r['plan_ms_median']:.2f} | {r['plan_ms_p95']:.1f} |", flush=True)  # fmt: skip
    return rows


def speed_table(steps: int, repeats: int) -> None:
    from bench_env import best_of, paired_ratio  # scripts/bench_env.py, next to this file

    reference = gym.make("CartPole-v1")
    cartpole = best_of(lambda: reference, steps, repeats)
    print(f"\nCartPole-v1: {cartpole:.0f} steps/s; ratios are medians of {repeats} paired runs (random actions, 5 obstacles, Δd 0.25)")
    print("| robot | steps/s | ratio to CartPole-v1 |")
    print("|---|---:|---:|")
    for robot in ("holonomic", "unicycle"):
        make = lambda robot=robot: gym.make("DynamicObstacle-v0", scenario="random", n_obstacles=5, delta_d=0.25, robot=robot)
        rate, ratio = paired_ratio(make, reference, steps, repeats)
        print(f"| {robot} | {rate:.0f} | {ratio:.3f}x |", flush=True)


def parse_args(argv=None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--episodes", type=int, default=40)
    parser.add_argument("--deltas", type=float, nargs="+", default=[0.25, 0.5])
    parser.add_argument("--steps", type=int, default=20000)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--skip-success", action="store_true")
    parser.add_argument("--skip-speed", action="store_true")
    parser.add_argument("--only", nargs="+", help="labels of the rows to run (default: all)")
    parser.add_argument("--limit", action="store_true", help="the harness with each robot's clairvoyant limit (the module's doc)")
    parser.add_argument("--split", default="test", help="--limit: the seeds' split (test, validation)")
    parser.add_argument("--robots", nargs="+", choices=sorted(LIMIT_AGENTS), help="--limit: the robots (default: both)")
    parser.add_argument("--workers", type=int, default=1, help="--limit: harness processes")
    parser.add_argument("--scenarios", nargs="+", choices=[s for s, _ in LIMIT_SCENARIOS], help="--limit: the scenarios (default: all)")
    parser.add_argument("--out", default="results/bench_unicycle", help="--limit: the harness's output directory")
    return parser.parse_args(argv)


def main(argv=None) -> None:
    args = parse_args(argv)
    start = time.perf_counter()
    if args.limit:
        limit_table(args.episodes, args.deltas, args.split, args.workers, args.out, args.only, args.robots, args.scenarios)
        print(f"\n({time.perf_counter() - start:.0f} s)")
        return
    if not args.skip_speed:
        speed_table(args.steps, args.repeats)
    if not args.skip_success:
        success_table(args.episodes, args.deltas, only=args.only)
    print(f"\n({time.perf_counter() - start:.0f} s)")


if __name__ == "__main__":
    main()
