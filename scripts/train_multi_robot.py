"""Train one PPO policy for every robot of a multi-robot preset (parameter sharing), with SB3 through
SuperSuit's PettingZoo vector adapter, warm-started from the shipped single-robot PPO.

    python scripts/train_multi_robot.py --scenario multi-circle-4 --budget-minutes 57 --out runs/ppo_multi

Writes ``training_curve.csv``, ``validation.csv``, ``learning_curve.png``, ``best_model.zip`` and
``final_model.zip`` (with sidecars: ``agents.make("ppo", env.robot_env(robot), path=...)`` runs them)
to ``--out``; the library is ``agents.rl.multi_robot.training``.
"""

from __future__ import annotations

import argparse
import shlex
import sys

from agents.rl.multi_robot.training import SharedArgs, train_shared
from agents.rl.training import dataclass_parser, parse_dataclass


def build_parser() -> argparse.ArgumentParser:
    """Flags from the dataclass's fields (``--total-timesteps``, ``--warm-start``, ...), with their docs."""
    return dataclass_parser(SharedArgs, __doc__)


def parse_args(argv=None) -> SharedArgs:
    return parse_dataclass(SharedArgs, build_parser(), argv)


if __name__ == "__main__":
    train_shared(parse_args(), command="python " + " ".join(shlex.quote(a) for a in sys.argv))
