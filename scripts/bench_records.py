"""What recording costs: the size of a 200-step episode with 8 obstacles, and the harness's time with
and without ``record=True`` in alternating runs (so a busy machine slows both alike).

    python scripts/bench_records.py --rounds 3 --episodes 10

Prints the size (KiB an episode, and what the arrays are) and each round's wall times, then the
median ratio recorded / not recorded, of wall time and of this process's CPU time (one worker: the
episodes run in this process; a machine shared with other work moves the wall times, less the CPU's).
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
import warnings
from pathlib import Path

import gymnasium as gym
import numpy as np

import pathplan_env  # noqa: F401
from pathplan_env.records import EpisodeRecorder
from pathplan_env.records.store import RecordWriter


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--rounds", type=int, default=3, help="alternating pairs of runs")
    parser.add_argument("--episodes", type=int, default=10, help="episodes per cell of the timed runs")
    parser.add_argument("--agents", default="pso-predictive,velocity-obstacle")
    parser.add_argument("--scenarios", default="random,crowdnav-circle-crossing")
    return parser


def parse_args(argv=None) -> argparse.Namespace:
    return build_parser().parse_args(argv)


def wander(seed: int, steps: int, obstacles: int):
    """A ``steps``-step episode among ``obstacles`` discs, recorded: a robot taking small random actions (so the episode
    lasts), with a 6-point plan a step."""
    env = gym.make("DynamicObstacle-v0", scenario="random", n_obstacles=obstacles, delta_d=0.5, max_episode_steps=None)
    env.reset(seed=seed)
    recorder, rng = EpisodeRecorder(env), np.random.default_rng(seed)
    warnings.filterwarnings("ignore", message=".*after the episode terminated")  # the wandering robot is hit, and carries on
    for _ in range(steps):
        action = rng.uniform(-0.2, 0.2, 2).astype(np.float32)
        recorder.before_step(action, plan=np.cumsum(rng.normal(0, 0.3, (6, 2)), axis=0))
        recorder.after_step(env.step(action)[4])
    return recorder.finish({"agent": "wander", "steps": steps})


def episode_size(folder: Path, steps: int = 200, obstacles: int = 8, count: int = 5) -> tuple[float, float, str]:
    """KiB on disk a ``steps``-step episode among ``obstacles`` discs costs, and ms to append it (flushed): the file's
    growth and the time per episode over ``count`` of them after the first (which also pays for the file's own structure)."""
    episodes = [wander(seed, steps, obstacles) for seed in range(count + 1)]
    with RecordWriter(folder / "size.h5") as writer:
        writer.append(episodes[0], "0")
        before, start = writer.path.stat().st_size, time.perf_counter()
        for n, episode in enumerate(episodes[1:], 1):
            writer.append(episode, str(n))
        seconds, size = (time.perf_counter() - start) / count, (writer.path.stat().st_size - before) / count
    episode = episodes[0]
    shapes = f"steps {episode.steps}, obstacles {episode.obstacles.shape}, plan points {episode.plan_points.shape}"
    return size / 1024, seconds * 1e3, shapes


def main(argv=None) -> None:
    args = parse_args(argv)
    from agents.evaluation import evaluate

    with tempfile.TemporaryDirectory() as folder:
        kib, ms, shapes = episode_size(Path(folder))
        print(f"a 200-step episode with 8 obstacles: {kib:.1f} KiB on disk, {ms:.1f} ms to append ({shapes}; float64, not compressed)")
        agents, scenarios = args.agents.split(","), args.scenarios.split(",")
        evaluate(agents, scenarios, [0.5], 1, Path(folder) / "warm", limit=False, plots=False, record=True)  # compile, cache, import h5py before timing
        times, cpu = {False: [], True: []}, {False: [], True: []}
        for r in range(args.rounds):
            for record in (False, True) if r % 2 == 0 else (True, False):
                start, start_cpu = time.perf_counter(), time.process_time()
                evaluate(agents, scenarios, [0.5], args.episodes, Path(folder) / f"run{r}{record}", limit=False, plots=False, record=record)
                times[record].append(time.perf_counter() - start)
                cpu[record].append(time.process_time() - start_cpu)
        for r in range(args.rounds):
            print(f"round {r}: not recorded {times[False][r]:.2f} s, recorded {times[True][r]:.2f} s ({times[True][r] / times[False][r]:.3f}; "
                  f"CPU {cpu[True][r] / cpu[False][r]:.3f})")  # fmt: skip
        ratio = statistics.median(t / f for t, f in zip(times[True], times[False]))
        cpu_ratio = statistics.median(t / f for t, f in zip(cpu[True], cpu[False]))
        episodes = len(agents) * len(scenarios) * args.episodes
        each = statistics.mean(times[False]) / episodes * 1e3
        print(f"recording: {ratio:.3f} x the time of the same run unrecorded, {cpu_ratio:.3f} x its CPU time "
              f"(medians of {args.rounds} alternating pairs, {episodes} episodes a run, {each:.0f} ms an episode unrecorded)")  # fmt: skip


if __name__ == "__main__":
    main()
