"""The space-time planners' predictor among 30 fast obstacles: how far ahead it can be trusted.

docs/results/dense_planners/delta_d4.md measures it over 40 validation episodes: at Δd 4 the error is
millimetres for 3 steps and a whole obstacle after 5-6 (a chaotic billiard); these are the same
figures on a few recorded episodes, so a change to the predictor that loses accuracy fails here.
"""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

import pathplan_env  # noqa: F401  (registers the env)
from agents.planners.prediction import predict_among, substeps_for
from pathplan_env.scenarios.splits import episode_seeds
from pathplan_env.world.simulation import World

HORIZON = 6


def errors_by_step(delta_d: float, episodes: int = 3, starts: int = 12) -> np.ndarray:
    """(HORIZON, episodes * starts * 30) position errors (m) of the prediction from the observation's
    float32 states against the env's own future, from each of the first ``starts`` steps."""
    env = gym.make("DynamicObstacle-v0", scenario="random", delta_d=delta_d, n_obstacles=30)
    rows = [[] for _ in range(HORIZON)]
    for seed in episode_seeds("validation", 0, episodes):
        env.reset(seed=seed)
        scenario = env.unwrapped.scenario
        world = World(scenario)
        n = world.substeps
        truth = world.obstacle_trajectory(starts + HORIZON)
        radii = np.asarray(world.radii, np.float64)
        for t in range(starts):
            state = truth[t * n].astype(np.float32).astype(np.float64)  # what the observation carries
            positions, velocities = np.ascontiguousarray(state[:, :2]), np.ascontiguousarray(state[:, 2:])
            m = substeps_for(velocities, radii, scenario.dt)
            assert m == n  # the env's substep rule, read from the observation
            pred = predict_among(positions, velocities, radii, np.array(scenario.bounds, np.float64), np.zeros((0, 5)), scenario.dt, HORIZON, m)
            for k in range(1, HORIZON + 1):
                rows[k - 1].append(np.hypot(*(pred[k * m, :, :2] - truth[(t + k) * n, :, :2]).T))
    return np.array([np.concatenate(r) for r in rows])


@pytest.mark.parametrize("delta_d", [2.0, 4.0])
def test_prediction_is_exact_for_a_step_and_close_for_three(delta_d):
    errors = errors_by_step(delta_d)
    assert np.median(errors[0]) < 1e-6  # one step ahead: the float32 rounding, nothing more
    assert np.percentile(errors[0], 99) < 1e-3
    assert errors[:3].mean() < 0.005  # 3 steps ahead: millimetres on average
    assert np.percentile(errors[2], 95) < 0.01


def test_prediction_drifts_by_an_obstacle_within_six_steps_at_delta_d_4():
    """The chaos that caps every planner at Δd 4 (delta_d4.md): it grows with the horizon and by
    step 6 some obstacles are a radius or more off (the predictor cannot see what drives it)."""
    errors = errors_by_step(4.0)
    means = errors.mean(axis=1)
    assert np.all(np.diff(means) > 0)
    assert errors[5].max() > 0.4
