"""Do two evaluation runs agree? (Exit status 1 if not.)

    pathplan-env compare results/large-pool results/large-ray

Compares every ``summary.json`` cell and every ``episodes.csv`` row of two ``evaluate.py`` outputs
(``agents.evaluation.run_diff``): outcomes and the episode's own figures (success, collision, steps,
path length, clearance, seeds, counts and the rates and means of them) exactly; the floats computed
from the exact static shortest path (shortest_path, path_length_ratio, spl, common_length_ratio),
whose last bits differ between CPUs, within a relative tolerance (--rtol); the planning times not
at all. A field the harness has gained since is compared exactly and named in the output. A run
kept without its episodes.csv (reproduce_paper's tables) is compared cell by cell, and the output
says so.

``python scripts/compare_runs.py`` is the same command, with the same flags.
"""

from __future__ import annotations

import argparse
import sys

from agents.evaluation.run_diff import RTOL, diff_runs


def build_parser(prog: str | None = None) -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog=prog, description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("first", help="an evaluate.py --out directory")
    parser.add_argument("second", help="another one")
    parser.add_argument("--ignore", default="", help="comma-separated fields to leave out as well (e.g. min_clearance)")
    parser.add_argument("--rtol", type=float, default=RTOL,
                        help=f"relative tolerance on the shortest-path floats (default {RTOL:g}; 0: exactly)")  # fmt: skip
    return parser


def parse_args(argv=None, prog: str | None = None) -> argparse.Namespace:
    args = build_parser(prog).parse_args(argv)
    args.ignore = [f for f in args.ignore.split(",") if f]
    return args


def main(argv=None, prog: str | None = None) -> int:
    args = parse_args(argv, prog)
    try:
        diff = diff_runs(args.first, args.second, ignore=args.ignore, rtol=args.rtol)
    except ValueError as error:
        sys.exit(f"compare_runs.py: {error}")
    if diff.equal:
        print(f"equal: {diff.cells:,} cell(s) and {diff.episodes:,} episodes agree: {diff.how}")
        return 0
    print("\n".join(diff.differences))
    if diff.differing > len(diff.differences):
        print(f"... and {diff.differing - len(diff.differences):,} more")
    print(f"differ: {diff.differing:,} cells or episodes ({diff.cells:,} cells and {diff.episodes:,} episodes in the first run); "
          f"compared: {diff.how}")  # fmt: skip
    return 1

