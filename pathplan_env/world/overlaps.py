"""How deep obstacles dip into each other: the measure behind the overlap bound in the docs.

Chipmunk detects contacts between substeps and runs with its overlap correction off (a correction
would move a body farther than speed x dt), so two obstacles can overlap for a substep or a few
before the elastic impulse parts them. ``scripts/measure_overlaps.py`` prints these figures.
"""

from __future__ import annotations

import numpy as np

from pathplan_env.scenarios.scenario import Scenario
from pathplan_env.world.simulation import World


def pair_overlaps(positions: np.ndarray, radii: np.ndarray) -> np.ndarray:
    """Every pair's overlap depth divided by the smaller radius of the pair (0 where apart), for
    positions shaped ``(..., N, 2)``; returns ``(..., P)`` over the ``P = N (N - 1) / 2`` pairs."""
    i, j = np.triu_indices(len(radii), k=1)
    gaps = np.linalg.norm(positions[..., i, :] - positions[..., j, :], axis=-1) - radii[i] - radii[j]
    return np.maximum(-gaps, 0.0) / np.minimum(radii[i], radii[j])


def scene_overlaps(scenario: Scenario, steps: int) -> np.ndarray:
    """The deepest relative overlap at every substep of ``steps`` steps of ``scenario``'s obstacles."""
    world = World(scenario)
    trajectory = world.obstacle_trajectory(steps)  # (substeps, N, 4): the state after every substep
    deepest = np.zeros(len(trajectory))
    for s, state in enumerate(trajectory):  # one substep at a time: (P,) pairs, bounded memory
        deepest[s] = pair_overlaps(state[:, :2], world.radii).max(initial=0.0)
    return deepest
