"""Benchmark agents x scenarios x Δd on a fixed test split: ``pathplan-env evaluate`` as a script, with the same flags (``--help``).

The command lives in ``agents/cli/evaluate.py`` (its docstring is this command's help); this file keeps
``python scripts/evaluate.py ...`` working as every page of the documentation writes it.
"""

from agents.cli.evaluate import ENV_OPTION_FLAGS, build_parser, main, parse_args

__all__ = ["ENV_OPTION_FLAGS", "build_parser", "main", "parse_args"]

if __name__ == "__main__":
    main()
