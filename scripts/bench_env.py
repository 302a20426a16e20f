"""Env speed: steps per second as a ratio to CartPole-v1: ``pathplan-env bench`` as a script, with the same flags (``--help``).

The command lives in ``agents/cli/bench.py`` (its docstring is this command's help); this file keeps
``python scripts/bench_env.py ...`` working as every page of the documentation writes it.
"""

from agents.cli.bench import build_parser, main, parse_args

__all__ = ["build_parser", "main", "parse_args"]

if __name__ == "__main__":
    main()
