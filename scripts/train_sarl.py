"""Train SARL (value network with attention, one-step lookahead on predicted humans): imitation then RL.

    python scripts/train_sarl.py --budget-minutes 60        # CrowdNav's circle crossing -> agents/models/sarl_crowdnav.npz

Every field of ``agents.rl.sarl.training.config.SARLArgs`` is a flag (``--il-episodes 1000``).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import shlex
import sys

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):  # one core: BLAS threads only contend on small matrices
    os.environ.setdefault(_var, "1")

from agents.rl.sarl.training.config import SARLArgs  # noqa: E402  (after the thread settings)
from agents.rl.sarl.training.train import train  # noqa: E402


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    for f in dataclasses.fields(SARLArgs):
        default = f.default if f.default is not dataclasses.MISSING else f.default_factory()
        flag = "--" + f.name.replace("_", "-")
        if isinstance(default, bool):
            parser.add_argument(flag, type=lambda v: v.lower() in ("1", "true", "yes"), default=default, help=f"(default {default})")
        elif isinstance(default, dict):
            parser.add_argument(flag, type=json.loads, default=default, help=f"JSON (default {json.dumps(default)})")
        else:
            parser.add_argument(flag, type=type(default), default=default, help=f"(default {default})")
    return parser


def parse_args(argv: list[str] | None = None) -> SARLArgs:
    parser = build_parser()
    return SARLArgs(**vars(parser.parse_args(argv)))


def main(argv: list[str] | None = None) -> None:
    args = parse_args(argv)
    train(args, command=shlex.join(["python", "scripts/train_sarl.py", *(sys.argv[1:] if argv is None else argv)]))


if __name__ == "__main__":
    main()
