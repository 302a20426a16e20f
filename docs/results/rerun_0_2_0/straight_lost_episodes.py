"""The straight-move lost proof (:mod:`agents.planners.straight_lost`) on the episodes where the limit is
cornered but not proved lost: each episode's start and true future as ``oracle-clairvoyant`` searches them,
the proof on a few grids, the cells it keeps after every step (0 at the end: lost).

    PYTHONPATH=. python docs/results/rerun_0_2_0/straight_lost_episodes.py
"""

from __future__ import annotations

import time

from agents.evaluation.entrants import resolve_scenarios
from agents.evaluation.episodes import make_episode_env
from agents.oracles.clairvoyant import ClairvoyantOracle
from agents.planners.straight_lost import provably_lost_straight

#: (scenario, Δd, episode): the committed runs' cornered undetermined episodes (seed 1e9 + episode, test split)
EPISODES = (("doorway", 1.0, 63), ("corridor", 1.0, 57), ("random", 2.0, 46), ("paper-case-3", 2.0, 17))
GRIDS, STEPS = (0.01, 0.005, 0.003), 3


def main() -> int:
    for name, delta_d, episode in EPISODES:
        env = make_episode_env(resolve_scenarios([name])[0], delta_d, None, None, "test", episode)
        env.reset(seed=1_000_000_000 + episode)
        problem = ClairvoyantOracle(env, seed=1_000_000_000 + episode).problem()[0]
        for cell in GRIDS:
            sizes, begin = [], time.perf_counter()
            lost, step = provably_lost_straight(problem, cell, cell, STEPS, history=sizes)
            verdict = "lost" if lost else "goal within reach" if lost is False else "not proved"
            print(f"{name} Δd {delta_d} episode {episode}, grid {cell * 1e3:g} mm: {verdict} (step {step}), "
                  f"cells kept {sizes} ({time.perf_counter() - begin:.0f} s)", flush=True)  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
