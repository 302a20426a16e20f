"""Evaluate agents on multi-robot scenes and print the Markdown table (docs/results/multi_robot.md).

    python scripts/evaluate_multi.py --agents astar-spacetime,pso-spacetime,abc-spacetime,orca,oracle-prioritized \\
        --scenarios multi-circle-4,multi-circle-10 --bouncing multi-circle-4-bouncing,multi-circle-10-bouncing \\
        --episodes 20 --workers 2 --out results/multi_robot

Every robot is driven by its own instance of the agent (seeded ``seed + robot``); ``--scenarios`` run at
their own speeds (no obstacles on the circle), ``--bouncing`` at ``--delta-d`` (default 0.25). Episodes
use the test split's seeds (``--split validation`` the validation seeds), as ``scripts/evaluate.py`` does.
``--record`` keeps every episode in ``<out>/own/multi_episodes.h5`` (and ``bouncing/``), replayed by
``scripts/render_multi_robot.py --record``. Each out folder has ``report.html``: the table, the episode
list and, with ``--record``, a player of every robot (docs/records.md).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from agents.evaluation.multi_robot import evaluate_multi, table


def names(text: str) -> list[str]:
    return [part for part in text.split(",") if part]


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--agents", type=names, required=True, help="agent names, comma-separated (oracle-prioritized too)")
    parser.add_argument("--scenarios", type=names, default=[], help="multi-robot presets at their own speeds")
    parser.add_argument("--bouncing", type=names, default=[], help="multi-robot presets with obstacles, run at --delta-d")
    parser.add_argument("--delta-d", type=float, default=0.25, help="the obstacles' Δd in the --bouncing scenes")
    parser.add_argument("--episodes", type=int, default=20)
    parser.add_argument("--seed", type=int, default=0, help="the split's seed (as scripts/evaluate.py)")
    parser.add_argument("--split", default="test", choices=["test", "validation"])
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument("--backend", choices=("process", "ray"), default="process",
                        help='where episodes run: a local process pool (--workers) or Ray (pip install -e ".[ray]")')  # fmt: skip
    parser.add_argument("--address", help="with --backend ray: a running cluster's address (default: a local Ray)")
    parser.add_argument("--out", type=Path, default=None, help="folder for multi_episodes.jsonl, multi_summary.json and report.html")
    parser.add_argument("--resume", action="store_true", help="keep the episodes on record in --out and run the rest")
    parser.add_argument("--record", action="store_true",
                        help="keep every episode in --out's multi_episodes.h5 (replay: render_multi_robot.py --record; docs/records.md)")  # fmt: skip
    return parser


def main(argv=None) -> None:
    args = build_parser().parse_args(argv)
    rows = []
    for label, scenarios, delta in (("own", args.scenarios, None), ("bouncing", args.bouncing, args.delta_d)):
        if scenarios:
            out = None if args.out is None else args.out / label
            try:
                rows += evaluate_multi(args.agents, scenarios, [delta], args.episodes, out, seed=args.seed, split=args.split,
                                       workers=args.workers, resume=args.resume, backend=args.backend, address=args.address,
                                       record=args.record)  # fmt: skip
            except ValueError as error:  # bad input, named by the harness: one line, as scripts/evaluate.py
                raise SystemExit(f"evaluate_multi.py: {error}") from None
    print(table(rows))


if __name__ == "__main__":
    main()
