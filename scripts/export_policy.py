"""Export a trained PPO's actor to numpy (``.npz`` beside the ``.zip``), so it runs without torch.

    python scripts/export_policy.py agents/models/ppo.zip [--resave]
    python scripts/export_policy.py agents/models/ppo_set.zip     # a set encoder (--observation set) exports too

``--resave`` also saves the ``.zip`` again with the installed numpy and SB3, so that it loads
without "Could not deserialize object" warnings (the shipped one was pickled under numpy 1.26).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from agents.rl.export import export_any_policy


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("model", help="an SB3 PPO .zip written by scripts/train_rl.py")
    parser.add_argument("--resave", action="store_true", help="save the .zip again with the installed versions")
    return parser


def parse_args(argv=None) -> argparse.Namespace:
    parser = build_parser()
    args = parser.parse_args(argv)
    if not Path(args.model).is_file():
        parser.error(f"model: no file {args.model}")
    return args


def main(argv=None) -> None:
    args = parse_args(argv)
    import warnings

    from stable_baselines3 import PPO

    path = Path(args.model)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # an old pickle's warnings: what --resave cures
        model = PPO.load(path, device="cpu")
    if args.resave:
        model.save(path)
        print(f"re-saved {path}")
    print(f"wrote {export_any_policy(model, path.with_suffix('.npz'))}")


if __name__ == "__main__":
    try:
        main()
    except ValueError as error:  # bad input, named by the library: one line, not a traceback
        sys.exit(f"export_policy.py: {error}")
