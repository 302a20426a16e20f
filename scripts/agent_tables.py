"""Write the agent tables of README.md and docs/agents.md from the registry (between their markers).

    python scripts/agent_tables.py          # rewrite what is out of date
    python scripts/agent_tables.py --check  # exit 1 if a page is out of date
"""

import argparse
import sys
from pathlib import Path

from agents.tables import filled

ROOT = Path(__file__).resolve().parent.parent
PAGES = ("README.md", "docs/agents.md")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--check", action="store_true", help="only check that the committed tables are current")
    return parser


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    stale = {}
    for page in PAGES:
        text = (ROOT / page).read_text("utf-8")
        new = filled(text, page)
        if new != text:
            stale[page] = new
    for page, text in stale.items():
        if args.check:
            print(f"{page} is out of date: run python scripts/agent_tables.py", file=sys.stderr)
        else:
            (ROOT / page).write_text(text, "utf-8")
            print(f"wrote {page}")
    return 1 if stale and args.check else 0


if __name__ == "__main__":
    sys.exit(main())
