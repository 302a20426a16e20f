"""Whether two evaluation runs agree (exit status 1 if not): ``pathplan-env compare`` as a script, with the same flags (``--help``).

The command lives in ``agents/cli/compare.py`` (its docstring is this command's help); this file keeps
``python scripts/compare_runs.py ...`` working as every page of the documentation writes it.
"""

import sys

from agents.cli.compare import build_parser, main, parse_args

__all__ = ["build_parser", "main", "parse_args"]

if __name__ == "__main__":
    sys.exit(main())
