"""What turning costs: success of the unicycle's agents beside the same planners on the holonomic robot,
against each robot's own clairvoyant limit, and the unicycle env's speed beside CartPole-v1.

Random scenes (8 obstacles), validation seeds (``pathplan_env.scenarios.splits.validation_seeds``, never the
test split), the same episodes for every agent; ``tracked-<planner>`` is the planner driven by pure
pursuit (``agents.reactive.tracker``), ``dwa`` the dynamic window approach (``agents.reactive.dwa``),
``astar-unicycle`` the space-time A* over the unicycle's own moves (``agents.planners.unicycle.astar``).

``--limit`` runs the evaluation harness instead (``agents.evaluation.evaluate``, ``--split test`` by
default): each robot's agents and its clairvoyant limit (``oracle-clairvoyant``, which searches the
unicycle's own moves when the robot is one) on random scenes at ``--deltas``, on CrowdNav's circle
crossing at its own speeds and on a wall family (``--scenarios``; doorway by default) at ``--wall-delta``.
The holonomic robot runs its best planner (``astar-spacetime``; ``astar-crowd`` on the crowd), the
unicycle its native agents (space-time A* over its moves, ``pso-unicycle``, ``abc-unicycle``, ``dwa``;
on the crowd their ``-crowd`` variants, which predict a cone of futures with a larger margin). It writes the harness's outputs to ``--out/<robot>-<scenario>``
as each finishes (``--resume`` continues them), prints one row per agent and cell with success ÷ limit and
the replanning time, then the scene table for the README: both limits and each agent's success ÷ its
own robot's limit. ``--tables-only`` prints both tables from the ``summary.json`` files under ``--out``
(the committed results; ``--resume`` needs the git-ignored ``episodes.jsonl`` records).

    python scripts/bench_unicycle.py [--episodes 40] [--deltas 0.25 0.5] [--steps 20000]
    python scripts/bench_unicycle.py --limit --episodes 40 --deltas 0.25 0.5 1 --wall-delta 0.25 --workers 2 --out docs/results/unicycle [--resume]
    python scripts/bench_unicycle.py --tables-only --out docs/results/unicycle
"""

from __future__ import annotations

import argparse
import json
import time

import gymnasium as gym
import numpy as np
from bench_unicycle_controls import run_cell  # the episode loop both scripts use

import pathplan_env  # noqa: F401
from pathplan_env.scenarios.splits import validation_seeds
from pathplan_env.scenarios.wall_families import FAMILIES

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
            won, hit, cell_ms, _ = run_cell(name, delta_d, seeds, n_obstacles, {}, robot=robot)
            plan_ms += cell_ms
            cells.append(f"{won:.3f} ({hit:.3f})")
        print(f"| {label} | {robot} | " + " | ".join(cells) + f" | {np.median(plan_ms):.1f} |", flush=True)


#: ``--limit``: per robot and kind of scene, its agents (each run against its own robot's limit): the best
#: holonomic planner (the crowd-aware A* where humans walk toward goals), and the unicycle's native agents.
LIMIT_AGENTS = {
    "holonomic": {"random": ["astar-spacetime"], "crowd": ["astar-crowd"], "walls": ["astar-spacetime"]},
    "unicycle": {
        "random": ["astar-unicycle", "pso-unicycle", "abc-unicycle", "dwa"],
        "crowd": ["astar-unicycle-crowd", "pso-unicycle-crowd", "abc-unicycle-crowd", "dwa"],
        "walls": ["astar-unicycle", "pso-unicycle", "abc-unicycle", "dwa"],
    },
}
#: (scenario, kind, cells): "deltas" runs ``--deltas``, "wall" ``--wall-delta``, None the scenario's own speeds
LIMIT_SCENARIOS = [("random", "random", "deltas"), ("crowdnav-circle-crossing", "crowd", None)] + [(family, "walls", "wall") for family in FAMILIES]
DEFAULT_SCENARIOS = ["random", "crowdnav-circle-crossing", "doorway"]
#: the scene table's columns: (heading, robot, the agents filling it, one per kind of scene)
COLUMNS = [
    ("holonomic: space-time A* ÷ limit", "holonomic", ("astar-spacetime", "astar-crowd")),
    ("unicycle: space-time A* ÷ limit", "unicycle", ("astar-unicycle", "astar-unicycle-crowd")),
    ("pso-unicycle ÷ limit", "unicycle", ("pso-unicycle", "pso-unicycle-crowd")),
    ("abc-unicycle ÷ limit", "unicycle", ("abc-unicycle", "abc-unicycle-crowd")),
    ("dwa ÷ limit", "unicycle", ("dwa",)),
]


def limit_table(episodes: int, deltas: list[float], split: str, workers: int, out: str, only: list[str] | None = None,
                robots: list[str] | None = None, scenarios: list[str] | None = None, wall_delta: float = 0.25,
                resume: bool = False) -> list[dict]:  # fmt: skip
    """Run the harness per robot and scenario (outputs under ``out/<robot>-<scenario>``); print one row per
    (agent, scenario, Δd) with success ÷ limit, then the scene table (:func:`scene_table`)."""
    from agents.evaluation import EvaluationSettings, evaluate

    rows = []
    chosen = [entry for entry in LIMIT_SCENARIOS if entry[0] in (scenarios or DEFAULT_SCENARIOS)]
    for scenario, kind, cell in chosen:  # scene by scene, both robots: a cut-short run still has whole rows
        cells = deltas if cell == "deltas" else [wall_delta] if cell == "wall" else [None]
        for robot in robots or list(LIMIT_AGENTS):
            names = [n for n in LIMIT_AGENTS[robot][kind] if not only or n in only]
            options = {"robot": robot} if robot != "holonomic" else None
            settings = EvaluationSettings(split=split, workers=workers, env_options=options, plots=False, resume=resume)
            rows += [r | {"robot": robot} for r in evaluate(names, [scenario], cells, episodes, f"{out}/{robot}-{scenario}", settings)]
    print_tables(rows, f"{episodes} {split} episodes a cell")
    return rows


def rows_on_record(out: str) -> list[dict]:
    """The summary rows of every ``out/<robot>-<scenario>/summary.json``, each with its robot, in the run's order."""
    from pathlib import Path

    rows = []
    for scenario, _, _ in LIMIT_SCENARIOS:
        for robot in LIMIT_AGENTS:
            path = Path(out) / f"{robot}-{scenario}" / "summary.json"
            if path.exists():
                rows += [r | {"robot": robot} for r in json.loads(path.read_text())["results"]]
    return rows


def print_tables(rows: list[dict], episodes: str) -> None:
    """One row per agent and cell with success ÷ limit and the replanning time, then :func:`scene_table`."""
    print(f"\n{episodes} (8 obstacles on random scenes); limit: oracle-clairvoyant on the same robot")
    print("| agent | robot | scenario | Δd | success | limit | success ÷ limit | plan ms median | p95 |")
    print("|---|---|---|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        if r["agent"] == "oracle-clairvoyant":
            continue
        over = r.get("success_over_limit")
        delta = "own" if r["delta_d"] is None else f"{r['delta_d']:g}"
        print(f"| {r['agent']} | {r['robot']} | {r['scenario']} | {delta} | {r['success_rate']:.3f} | {r.get('limit', float('nan')):.3f} | "
              f"{'-' if over is None else f'{over:.3f}'} | {r['plan_ms_median']:.2f} | {r['plan_ms_p95']:.1f} |", flush=True)  # fmt: skip
    print()
    print(scene_table(rows))


def scene_table(rows: list[dict]) -> str:
    """Markdown: one row per scene (scenario, Δd), each robot's limit (oracle-clairvoyant's success) and
    each agent's success ÷ its own robot's limit ("-" where not run, "n/a" where there is no limit)."""
    by = {(r["robot"], r["agent"], r["scenario"], r["delta_d"]): r for r in rows}
    scenes = list(dict.fromkeys((r["scenario"], r["delta_d"]) for r in rows))

    def limit(robot, scene):
        return next((r["limit"] for (rb, _, s, d), r in by.items() if rb == robot and (s, d) == scene and "limit" in r), None)

    def ratio(robot, agents, scene):
        found = [by[(robot, a, *scene)] for a in agents if (robot, a, *scene) in by]
        over = found[0].get("success_over_limit") if found else None
        return "-" if not found else "n/a" if over is None else f"{over:.2f}"

    lines = ["| scene | holonomic limit | unicycle limit | " + " | ".join(c[0] for c in COLUMNS) + " |",
             "|---|" + "---:|" * (2 + len(COLUMNS))]  # fmt: skip
    for scene in scenes:
        name = scene[0] + ("" if scene[1] is None else f", Δd {scene[1]:g}")
        limits = [limit(robot, scene) for robot in ("holonomic", "unicycle")]
        lines.append(f"| {name} | " + " | ".join("-" if v is None else f"{v:.2f}" for v in limits) + " | "
                     + " | ".join(ratio(robot, agents, scene) for _, robot, agents in COLUMNS) + " |")  # fmt: skip
    return "\n".join(lines)


def speed_table(steps: int, repeats: int) -> None:
    from agents.cli.bench import best_of, paired_ratio  # pathplan-env bench (scripts/bench_env.py)

    reference = gym.make("CartPole-v1")
    cartpole = best_of(lambda: reference, steps, repeats)
    print(f"\nCartPole-v1: {cartpole:.0f} steps/s; ratios are medians of {repeats} paired runs (random actions, 5 obstacles, Δd 0.25)")
    print("| robot | steps/s | ratio to CartPole-v1 |")
    print("|---|---:|---:|")
    for robot in ("holonomic", "unicycle"):
        make = lambda robot=robot: gym.make("DynamicObstacle-v0", scenario="random", n_obstacles=5, delta_d=0.25, robot=robot)
        rate, ratio = paired_ratio(make, reference, steps, repeats)
        print(f"| {robot} | {rate:.0f} | {ratio:.3f}x |", flush=True)


def build_parser() -> argparse.ArgumentParser:
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
    parser.add_argument(
        "--scenarios",
        nargs="+",
        choices=[s for s, _, _ in LIMIT_SCENARIOS],
        help=f"--limit: the scenarios (default: {' '.join(DEFAULT_SCENARIOS)}; a wall family at --wall-delta)",
    )
    parser.add_argument("--wall-delta", type=float, default=0.25, help="--limit: the wall family's Δd")
    parser.add_argument("--resume", action="store_true", help="--limit: continue the harness's runs under --out")
    parser.add_argument("--tables-only", action="store_true", help="print the --limit tables from the summary.json files under --out")
    parser.add_argument("--out", default="results/bench_unicycle", help="--limit: the harness's output directory")
    return parser


def parse_args(argv=None) -> argparse.Namespace:
    return build_parser().parse_args(argv)


def main(argv=None) -> None:
    args = parse_args(argv)
    start = time.perf_counter()
    if args.tables_only:
        rows = rows_on_record(args.out)
        print_tables(rows, "episodes as on record in each cell's summary.json")
        return
    if args.limit:
        limit_table(args.episodes, args.deltas, args.split, args.workers, args.out, args.only, args.robots, args.scenarios, args.wall_delta, args.resume)
        print(f"\n({time.perf_counter() - start:.0f} s)")
        return
    if not args.skip_speed:
        speed_table(args.steps, args.repeats)
    if not args.skip_success:
        success_table(args.episodes, args.deltas, only=args.only)
    print(f"\n({time.perf_counter() - start:.0f} s)")


if __name__ == "__main__":
    main()
