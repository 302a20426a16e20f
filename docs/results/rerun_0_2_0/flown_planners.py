"""The limit on chosen episodes (test split, ``--seed 0``), where it would stay undetermined: its verdict,
what found the plan or what it flew, its outcome, and every planner it flew on a copy of the env
(:mod:`agents.oracles.flown_planners`) with that flight's outcome and steps.

    PYTHONPATH=. python docs/results/rerun_0_2_0/flown_planners.py random:2:46,49 paper-case-3:2:17,34 \
        random:n_obstacles=30:4:3,13,17,23 clutter:4:34,49 --n-obstacles clutter=5
    PYTHONPATH=. python docs/results/rerun_0_2_0/flown_planners.py random:1:3,22,25,39 --robot random=unicycle

Each cell is ``scenario:Δd:episodes`` (the scenario may hold colons of its own: the last two fields are
read from the right).
"""

from __future__ import annotations

import argparse
import time

import agents
from agents.evaluation.entrants import resolve_scenarios
from agents.evaluation.episodes import make_episode_env


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("cells", nargs="+", help="scenario:Δd:episode,episode,...")
    parser.add_argument("--n-obstacles", nargs="*", default=[], metavar="SCENARIO=N", help="a scenario's obstacle count (as --n-obstacles in evaluate.py)")
    parser.add_argument("--robot", nargs="*", default=[], metavar="SCENARIO=ROBOT", help="a scenario's robot (holonomic or unicycle)")
    return parser


def parse_args(argv=None) -> argparse.Namespace:
    return build_parser().parse_args(argv)


def outcome(info: dict) -> str:
    return "success" if info["is_success"] else "collision" if info["collision"] else "timeout"


def main(argv=None) -> int:
    args = parse_args(argv)
    counts = {key: int(value) for key, value in (item.split("=", 1) for item in args.n_obstacles)}
    robots = dict(item.split("=", 1) for item in args.robot)
    print("| scenario | Δd | episode | verdict | found by / flown by | outcome at step | planners flown (outcome, steps) | seconds |")
    print("|---|---:|---:|---|---|---|---|---:|")
    for cell in args.cells:
        scenario, delta_d, episodes = cell.rsplit(":", 2)
        spec = resolve_scenarios([scenario])[0]
        options = {"robot": robots[scenario]} if scenario in robots else None
        for episode in map(int, episodes.split(",")):
            begin, seed = time.perf_counter(), 1_000_000_000 + episode
            env = make_episode_env(spec, float(delta_d), spec.obstacles(counts.get(scenario)), options, "test", episode)
            obs, info = env.reset(seed=seed)
            oracle = agents.make("oracle-clairvoyant", env, seed=seed)
            steps = 0
            while True:
                obs, _, terminated, truncated, info = env.step(oracle.predict(obs)[0])
                steps += 1
                if terminated or truncated:
                    break
            s = oracle.last_search
            flown = ", ".join(f"{name} ({end}, {n})" for name, (end, n) in s["planners"].items()) or "-"
            print(f"| {scenario} | {delta_d} | {episode} | {s['verdict']} | {s['found_by'] or '-'} / {s['flown_by'] or '-'} | {outcome(info)} at {steps} "
                  f"| {flown} | {time.perf_counter() - begin:.0f} |", flush=True)  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
