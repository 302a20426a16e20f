"""The holonomic robot's lost proof by straight one-step moves (:mod:`agents.planners.straight_lost`):
it never calls lost a scene where a search of the robot's own moves finds a free path, and it proves
lost where the robot is cornered."""

from __future__ import annotations

import numpy as np
import pytest

from agents.planners.spacetime.astar import FOUND, SearchSettings, SpacetimeProblem, heading_moves, search
from agents.planners.spacetime.astar import HORIZON as HORIZON_REACHED
from agents.planners.straight_lost import provably_lost_straight
from pathplan_env.arena import Arena

BOX = Arena((0.0, 0.0, 10.0, 10.0), 0.2).box
REACH, SUBSTEPS, HORIZON = 0.25, 6, 3


def _scene(rng) -> SpacetimeProblem:
    """Discs crowding the robot at (5, 5), each flying straight, some fast; the goal out of reach."""
    n = int(rng.integers(6, 14))
    centre = np.array([5.0, 5.0]) + rng.uniform(-0.9, 0.9, (n, 2))
    velocity = rng.uniform(-0.06, 0.06, (n, 2))  # m a substep
    steps = np.arange(10 * SUBSTEPS + 1)[:, None, None]
    trajectory = centre[None] + steps * velocity[None]
    radii = rng.uniform(0.15, 0.35, n)
    start = np.array([5.0, 5.0])
    keep = np.hypot(*(centre - start).T) > radii + 0.2  # none touching the robot already
    return SpacetimeProblem(trajectory[:, keep], SUBSTEPS, 0.2, radii[keep], start, np.array([9.0, 9.0]), 0.3, BOX, REACH)


def test_never_lost_where_a_search_of_straight_moves_finds_a_free_path():
    rng = np.random.default_rng(46)
    moves = heading_moves(64, (1.0, 0.75, 0.5, 0.25))
    lost_count = free_count = 0
    for _ in range(40):
        problem = _scene(rng)
        lost, _ = provably_lost_straight(problem, cell=0.02, move_cell=0.02, max_steps=HORIZON)
        result = search(problem, SearchSettings(moves, HORIZON, 0.005, 200_000, 1.0))
        free = result.outcome in (FOUND, HORIZON_REACHED)  # a path of HORIZON free steps (each replayed with the env's test)
        free_count += free
        lost_count += lost is True
        assert not (lost is True and free), "called lost where a free path exists"
    assert lost_count >= 3 and free_count >= 3  # both kinds of scene were tried


@pytest.mark.parametrize("cells", [(0.0, 0.01), (0.2, 0.2)])
def test_bad_grids_are_refused(cells):
    problem = _scene(np.random.default_rng(0))
    with pytest.raises(ValueError, match="cell"):
        provably_lost_straight(problem, *cells)


@pytest.mark.parametrize("straight_lost", [(0.0, 4), (0.005, 0), (0.005, 2.5), (0.005,)])
def test_the_limit_refuses_a_bad_straight_lost(straight_lost):
    import gymnasium as gym

    import pathplan_env  # noqa: F401
    from agents.oracles.clairvoyant import ClairvoyantOracle

    with pytest.raises(ValueError, match="straight_lost"):
        ClairvoyantOracle(gym.make("DynamicObstacle-v0"), straight_lost=straight_lost)
