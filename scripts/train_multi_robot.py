"""Train one PPO policy for every robot of a multi-robot preset (parameter sharing), with SB3 through
SuperSuit's PettingZoo vector adapter, warm-started from the shipped single-robot PPO.

    python scripts/train_multi_robot.py --scenario multi-circle-4 --budget-minutes 57 --out runs/ppo_multi

Writes ``training_curve.csv``, ``validation.csv``, ``learning_curve.png``, ``best_model.zip`` and
``final_model.zip`` (with sidecars: ``agents.make("ppo", env.robot_env(robot), path=...)`` runs them)
to ``--out``; the library is ``agents.rl.multi_robot.training``.
"""

from __future__ import annotations

import argparse
import dataclasses
import shlex
import sys

from agents.rl.multi_robot.training import SharedArgs, train_shared
from agents.rl.training import field_docs


def build_parser() -> argparse.ArgumentParser:
    """Flags from the dataclass's fields (``--total-timesteps``, ``--warm-start``, ...), with their docs."""
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    docs = field_docs(SharedArgs)
    for f in dataclasses.fields(SharedArgs):
        kind = {"int": int, "float": float}.get(f.type, str)
        text = docs.get(f.name, "").replace("%", "%%") + " (default: %(default)r)"
        parser.add_argument("--" + f.name.replace("_", "-"), type=kind, default=f.default, help=text)
    return parser


def parse_args(argv=None) -> SharedArgs:
    parser = build_parser()
    try:
        return SharedArgs(**vars(parser.parse_args(argv)))
    except ValueError as error:  # a bad combination: one line, before any work
        parser.error(str(error))


if __name__ == "__main__":
    train_shared(parse_args(), command="python " + " ".join(shlex.quote(a) for a in sys.argv))
