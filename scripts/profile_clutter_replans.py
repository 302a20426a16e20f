"""Where a ``pso-spacetime`` / ``abc-spacetime`` replan spends its time among 300 resting cylinders,
beside 8 moving obstacles (issue 46 item 4: a replan within 2 x its 8-obstacle time).

1. Parts of a replan: each replan's time (this process's CPU) in the agent's parts over clutter
   episodes (``clutter_scenario(n_cylinders=300)``, seeds 1, 2, ...; after a warm-up episode), the
   median over the replans (most are the ones refining the last best where nothing moved): the
   whole ``predict``, the optimiser's compiled run (``pso_run`` / ``abc_run``), the seeds, the problem
   and the other Python round them.
2. The optimiser's runs replayed: every run of those episodes and of as many test episodes among 8
   moving obstacles (random, Δd 0.5) recorded, then run again from the same arguments, each set
   ``--passes`` times, the least CPU time kept (the least a shared machine's load adds): microseconds a
   run and nanoseconds an objective evaluation, and whether every replayed best is the recorded one.

    python scripts/profile_clutter_replans.py [--planner pso-spacetime] [--episodes 3] [--passes 7]
"""

from __future__ import annotations

import argparse
import functools
import time

import gymnasium as gym
import numpy as np

import agents
import agents.planners.metaheuristic as metaheuristic
import pathplan_env  # noqa: F401  (registers the env)
from agents.planners.spacetime import metaheuristic_agent
from pathplan_env.scenarios.clutter import clutter_scenario
from pathplan_env.scenarios.splits import heldout_seeds

PARTS = (("predict", agents.Agent, "predict"), ("optimiser run", metaheuristic, "pso_run"), ("optimiser run", metaheuristic, "abc_run"),
         ("run_optimizer", metaheuristic.MetaheuristicAgent, "run_optimizer"),
         ("seed_paths", metaheuristic_agent.SpacetimeMetaheuristicAgent, "seed_paths"),
         ("timed_problem", metaheuristic_agent.SpacetimeMetaheuristicAgent, "timed_problem"))  # fmt: skip


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--planner", default="pso-spacetime", choices=("pso-spacetime", "abc-spacetime"))
    parser.add_argument("--episodes", type=int, default=3, help="clutter episodes, and as many 8-obstacle test episodes")
    parser.add_argument("--passes", type=int, default=7, help="replays of the recorded runs; the least time kept")
    return parser


def parse_args(argv=None) -> argparse.Namespace:
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.episodes < 1 or args.passes < 1:
        parser.error("--episodes and --passes must be >= 1")
    return args


def _timed(spent: dict, label: str, fn):
    @functools.wraps(fn)
    def wrapper(*args, **kwargs):
        begin = time.process_time()
        try:
            return fn(*args, **kwargs)
        finally:
            spent[label] = spent.get(label, 0.0) + time.process_time() - begin

    return wrapper


def _fly(agent, env, seed: int, spent: dict, rows: list | None) -> None:
    agent.reset()
    obs, _ = env.reset(seed=seed)
    while True:
        spent.clear()
        action, _ = agent.predict(obs, deterministic=True)
        if rows is not None:
            rows.append(dict(spent))
        obs, _, terminated, truncated, _ = env.step(action)
        if terminated or truncated:
            return


def main(argv=None) -> None:
    args = parse_args(argv)
    spent: dict[str, float] = {}
    originals = [(owner, name, getattr(owner, name)) for _, owner, name in PARTS]
    for label, owner, name in PARTS:
        setattr(owner, name, _timed(spent, label, getattr(owner, name)))
    raw = {name: fn for owner, name, fn in originals if owner is metaheuristic}  # the compiled runs, replayed without the timers
    runs: list = []
    for name in ("pso_run", "abc_run"):  # recorded inside the timers: what run_optimizer calls
        timed = getattr(metaheuristic, name)

        def recording(*run_args, timed=timed, name=name):
            result = timed(*run_args)
            runs.append((raw[name], run_args, result.best.copy(), int(result.evaluations)))
            return result

        setattr(metaheuristic, name, recording)
    try:
        rows: list[dict] = []
        recorded = {}
        for label, seeds in (("300 cylinders", range(args.episodes + 1)), ("8 obstacles", heldout_seeds(0, args.episodes + 1))):
            for i, seed in enumerate(seeds):
                if label == "300 cylinders":
                    env = gym.make("DynamicObstacle-v0", scenario=clutter_scenario(np.random.default_rng(seed), n_cylinders=300))
                else:
                    env = gym.make("DynamicObstacle-v0", scenario="random", delta_d=0.5)
                agent = agents.make(args.planner, env, seed=0)
                if i == 0:  # the warm-up: numba's cache loads here
                    _fly(agent, env, seed, spent, None)
                    runs.clear()
                    continue
                _fly(agent, env, seed, spent, rows if label == "300 cylinders" else None)
            recorded[label], runs[:] = list(runs), []
    finally:
        for owner, name, fn in originals:
            setattr(owner, name, fn)
    print(f"\n{args.planner}: the parts of a replan among 300 resting cylinders, median over {len(rows)} replans "
          f"of {args.episodes} episodes, us of CPU")  # fmt: skip
    print("| part | median | mean |\n|---|---:|---:|")
    medians = {label: float(np.median([r.get(label, 0.0) for r in rows])) for label, _, _ in PARTS}
    for label, median in medians.items():
        print(f"| {label} | {1e6 * median:.0f} | {1e6 * np.mean([r.get(label, 0.0) for r in rows]):.0f} |")
    print(f"| predict less the optimiser's run (its Python) | {1e6 * (medians['predict'] - medians['optimiser run']):.0f} | |")
    print(f"\nThe optimiser's runs replayed, the least CPU time of {args.passes} passes")
    print("| scene | runs | evaluations a run (mean) | us a run | ns an evaluation | every best the recorded one |\n|---|---:|---:|---:|---:|---|")
    for label, calls in recorded.items():
        least, same = np.inf, True
        evaluations = sum(spent_evaluations for *_, spent_evaluations in calls)
        for _ in range(args.passes):
            begin = time.process_time()
            for fn, run_args, best, spent_evaluations in calls:
                result = fn(*run_args)
                same &= bool(np.array_equal(result.best, best)) and int(result.evaluations) == spent_evaluations
            least = min(least, time.process_time() - begin)
        print(f"| {label} | {len(calls)} | {evaluations / len(calls):.0f} | {1e6 * least / len(calls):.0f} | {1e9 * least / evaluations:.0f} | {same} |")


if __name__ == "__main__":
    main()
