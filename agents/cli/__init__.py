"""``pathplan-env``: the console command a ``pip install`` gives, one subcommand a job.

    pathplan-env evaluate --suite default --out results/default
    pathplan-env render --agent pso-spacetime --scenario random --delta-d 0.5 --out episode.gif
    pathplan-env bench --robots-only
    pathplan-env compare results/a results/b
    pathplan-env agents

Each subcommand is a module of this package (``build_parser`` and ``main(argv)``); the scripts in
``scripts/`` (``evaluate.py``, ``render_episode.py``, ``bench_env.py``, ``compare_runs.py``) are thin
wrappers over the same functions, so a flag means the same in both.
"""

from __future__ import annotations

import argparse
import importlib
import sys

#: subcommand -> (module, one line for ``pathplan-env --help``)
COMMANDS = {
    "evaluate": ("agents.cli.evaluate", "agents x scenarios x Δd on fixed episodes, each cell beside its physical limit"),
    "render": ("agents.cli.render", "one episode of an agent to a GIF or MP4"),
    "bench": ("agents.cli.bench", "the env's steps per second as a ratio to CartPole-v1"),
    "compare": ("agents.cli.compare", "do two evaluation runs agree? (exit status 1 if not)"),
    "agents": ("agents.cli.listing", "the registered agent families and presets"),
}


def build_parser() -> argparse.ArgumentParser:
    """The top-level parser: lists the subcommands (each reads its own flags: ``pathplan-env evaluate --help``)."""
    from pathplan_env import __version__

    parser = argparse.ArgumentParser(prog="pathplan-env", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--version", action="version", version=f"pathplan-env {__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name, (_, summary) in COMMANDS.items():
        commands.add_parser(name, help=summary, add_help=False)
    return parser


def command_parser(name: str) -> argparse.ArgumentParser:
    """A subcommand's own parser, as ``pathplan-env NAME --help`` shows it."""
    return importlib.import_module(COMMANDS[name][0]).build_parser(prog=f"pathplan-env {name}")


def main(argv: list[str] | None = None) -> int:
    """Run ``pathplan-env``; returns the exit status (bad input: a one-line message naming the argument)."""
    argv = sys.argv[1:] if argv is None else list(argv)
    if not argv or argv[0] not in COMMANDS:
        build_parser().parse_args(argv)  # --help, --version, or argparse's error naming the commands
        return 2
    name = argv[0]
    module = importlib.import_module(COMMANDS[name][0])
    try:
        status = module.main(argv[1:], prog=f"pathplan-env {name}")
    except ValueError as error:
        raise SystemExit(f"pathplan-env {name}: {error}") from None
    return status if isinstance(status, int) else 0
