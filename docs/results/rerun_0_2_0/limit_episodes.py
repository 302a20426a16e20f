"""Fly again every episode a committed run's limit called undetermined, and print each one's verdict and
outcome then and now (the run's test split, ``--seed 0``, no agent kwargs or env options, as committed).

    PYTHONPATH=. python docs/results/rerun_0_2_0/limit_episodes.py docs/results/maps_suite/other_agents
"""

from __future__ import annotations

import csv
import json
import sys
import time

from agents.evaluation.episodes import run_episode
from agents.evaluation.records import LIMIT_AGENT


def outcome(success: bool, collision: bool) -> str:
    return "success" if success else "collision" if collision else "timeout"


def main(run: str) -> int:
    with open(f"{run}/summary.json") as f:
        n_obstacles = json.load(f)["config"].get("n_obstacles")
    with open(f"{run}/episodes.csv") as f:
        rows = [r for r in csv.DictReader(f) if r["agent"] == LIMIT_AGENT and r["verdict"] == "undetermined"]
    for r in rows:
        begin = time.perf_counter()
        now = run_episode(LIMIT_AGENT, r["scenario"], float(r["delta_d"]), int(r["episode"]), int(r["seed"]), n_obstacles, {})
        then = outcome(r["success"] == "True", r["collision"] == "True")
        print(f"{r['scenario']} Δd {r['delta_d']} episode {r['episode']}: undetermined, {then} at step {r['steps']} -> "
              f"{now.verdict}, {outcome(now.success, now.collision)} at step {now.steps} ({time.perf_counter() - begin:.0f} s)", flush=True)  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1]))
