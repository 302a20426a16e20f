"""Do two evaluation runs agree, timing aside? (Exit status 1 if not.)

    python scripts/compare_runs.py results/large-pool results/large-ray

Compares every ``summary.json`` cell and every ``episodes.csv`` row of two ``evaluate.py`` outputs
on every field but the planning times (``agents.evaluation.run_diff``).
"""

from __future__ import annotations

import argparse
import sys

from agents.evaluation.run_diff import diff_runs


def parse_args(argv=None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("first", help="an evaluate.py --out directory")
    parser.add_argument("second", help="another one")
    parser.add_argument("--ignore", default="", help="comma-separated fields to leave out as well (e.g. min_clearance)")
    args = parser.parse_args(argv)
    args.ignore = [f for f in args.ignore.split(",") if f]
    return args


def main(argv=None) -> int:
    args = parse_args(argv)
    try:
        diff = diff_runs(args.first, args.second, ignore=args.ignore)
    except ValueError as error:
        sys.exit(f"compare_runs.py: {error}")
    if diff.equal:
        but = "the timings" + "".join(f", {f}" for f in args.ignore)
        print(f"equal: {diff.cells:,} cell(s) and {diff.episodes:,} episodes agree on every field but {but}")
        return 0
    print("\n".join(diff.differences))
    print(f"differ: {diff.differing:,} cells or episodes ({diff.cells:,} cells and {diff.episodes:,} episodes in the first run)")
    return 1


if __name__ == "__main__":
    sys.exit(main())
