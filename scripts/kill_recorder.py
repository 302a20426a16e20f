"""What a killed run leaves of its episode records: a child process appends episodes to a record file
until it is killed (SIGKILL, at a random moment), then the file is salvaged as ``--resume`` does, an
episode appended, and every kept episode checked against what was written. Repeated ``--kills`` times.

    python scripts/kill_recorder.py --kills 30

Prints each outcome (kept, torn) and how many files were left readable.
"""

from __future__ import annotations

import argparse
import random
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_records import wander

from pathplan_env.records.store import RecordWriter, open_records, salvage

EPISODES = [(seed, 40, 8) for seed in range(8)]  # (seed, steps, obstacles): what the child appends, over and over


def child(path: str) -> None:
    episodes = [wander(*e) for e in EPISODES]
    with RecordWriter(path) as writer:
        print("writing", flush=True)
        for n in range(10**6):
            writer.append(episodes[n % len(episodes)], str(n))


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--kills", type=int, default=30, help="how many writers to kill")
    parser.add_argument("--seed", type=int, default=0, help="for the moments of the kills")
    parser.add_argument("--child", help=argparse.SUPPRESS)
    return parser


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    if args.child:
        child(args.child)
        return 0
    rng, episodes, readable = random.Random(args.seed), [wander(*e) for e in EPISODES], 0
    with tempfile.TemporaryDirectory() as folder:
        for k in range(args.kills):
            path = Path(folder) / f"kill{k}.h5"
            writer = subprocess.Popen([sys.executable, __file__, "--child", str(path)], stdout=subprocess.PIPE, text=True)
            writer.stdout.readline()
            time.sleep(rng.uniform(0.05, 0.5))
            writer.send_signal(signal.SIGKILL)
            writer.wait()
            try:
                kept, torn = salvage(path)
                with RecordWriter(path) as again:
                    again.append(episodes[0], "after")
                with open_records(path) as records:
                    for number, key in enumerate(records.header_keys()[:-1]):
                        episode, written = records.episode(number), episodes[int(key) % len(episodes)]
                        assert np.array_equal(episode.obstacles, written.obstacles) and np.array_equal(episode.robot, written.robot)
                    records.episode(len(records) - 1)
                readable += 1
                print(f"kill {k}: {kept} episodes kept, {torn} torn (left out, to run again)")
            except (ValueError, OSError, RuntimeError, AssertionError) as error:
                print(f"kill {k}: not recovered: {type(error).__name__}: {error}")
    print(f"{readable} of {args.kills} killed writers left a file that salvage read, appended to and read back whole")
    return 0 if readable == args.kills else 1


if __name__ == "__main__":
    sys.exit(main())
