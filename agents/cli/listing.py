"""The registered agent families and presets, as the docs' tables list them (``agents.tables``).

    pathplan-env agents              # the families, one line each
    pathplan-env agents --presets    # every preset with its family and parameters
"""

from __future__ import annotations

import argparse

from agents.tables import family_table, preset_table


def build_parser(prog: str | None = None) -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog=prog, description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--presets", action="store_true", help="list every preset (its family, parameters and robot) instead of the families")
    return parser


def main(argv=None, prog: str | None = None) -> int:
    args = build_parser(prog).parse_args(argv)
    print(preset_table() if args.presets else family_table(), end="")
    return 0
