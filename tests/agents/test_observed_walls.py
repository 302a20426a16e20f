"""The walls a planner reads from the observation (float32) cover the env's own (float64) ones
(``agents.base.real_static_segments(obs, covering=True)``): each observed capsule, grown by the
rounding's bound, contains the exact capsule, so a plan clear of the observed walls is clear of the
env's (issue 21: pso-crowd cleared the float32 walls by 2.5e-7 m and overlapped the exact ones)."""

import hashlib

import gymnasium as gym
import numpy as np
import pytest

import agents
import pathplan_env  # noqa: F401  (registers the env)
from agents.base import real_static_segments
from agents.observation import covering_rows


def _point_segment(p: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """Distance from each point ``p`` (M, 2) to the segment of the same row of ``rows`` (M, 5)."""
    a, ab = rows[:, 0:2], rows[:, 2:4] - rows[:, 0:2]
    t = np.clip(((p - a) * ab).sum(axis=1) / np.maximum((ab * ab).sum(axis=1), 1e-300), 0.0, 1.0)
    return np.hypot(*(p - a - t[:, None] * ab).T)


def _contains(outer: np.ndarray, inner: np.ndarray) -> np.ndarray:
    """Whether each capsule row of ``outer`` contains the same row of ``inner``: the distance to a
    segment is convex along the other segment, so its largest is at one of the inner row's ends."""
    far = np.maximum(_point_segment(inner[:, 0:2], outer), _point_segment(inner[:, 2:4], outer))
    return far + inner[:, 4] <= outer[:, 4]


@pytest.mark.parametrize("scenario", ["maze-crowd", "maze"])
def test_observed_walls_cover_the_exact_ones(scenario):
    env = gym.make("DynamicObstacle-v0", scenario=scenario)
    uncovered = 0
    for seed in range(5):
        obs, _ = env.reset(seed=seed)
        exact = np.asarray(env.unwrapped._world.static_segments, np.float64)  # read here only to compare
        observed, covered = real_static_segments(obs), real_static_segments(obs, covering=True)
        assert covered.shape == exact.shape == observed.shape and len(exact) > 0
        assert np.array_equal(covered[:, :4], observed[:, :4]) and (covered[:, 4] > observed[:, 4]).all()
        assert _contains(covered, exact).all(), seed
        uncovered += int((~_contains(observed, exact)).sum())
        assert (covered[:, 4] - observed[:, 4]).max() < 1e-5  # a few float32 ulps, not a margin
    env.close()
    assert uncovered > 0  # the plain float32 rows do miss the exact ones: the test has teeth


def test_the_bound_holds_far_from_the_origin():
    """Random rows up to 1 km from the origin, rounded to float32 as the observation rounds them."""
    rng = np.random.default_rng(21)
    for scale in (1.0, 10.0, 1000.0):
        ends = rng.uniform(-scale, scale, (200, 2))
        exact = np.column_stack([ends, ends + rng.uniform(-3, 3, (200, 2)), rng.choice([0.0, 0.05, 0.1], 200)])
        obs = {"static_segments": exact.astype(np.float32), "static_mask": np.ones(200, np.float32),
               "robot_position": np.zeros(2, np.float32)}  # fmt: skip
        assert _contains(real_static_segments(obs, covering=True), exact).all(), scale


def test_nothing_changes_without_walls():
    env = gym.make("DynamicObstacle-v0")
    obs, _ = env.reset(seed=0)
    assert real_static_segments(obs, covering=True).shape == (0, 5)
    assert covering_rows(obs, np.zeros((0, 5))).shape == (0, 5)
    env.close()


def _actions_digest(name: str) -> str:
    env = gym.make("DynamicObstacle-v0", delta_d=1.0)
    agent, digest = agents.make(name, env, seed=0), hashlib.sha256()
    obs, _ = env.reset(seed=0)
    for _ in range(20):
        action, _ = agent.predict(obs, deterministic=True)
        digest.update(np.asarray(action).tobytes())
        obs, _, terminated, truncated, _ = env.step(action)
        if terminated or truncated:
            break
    env.close()
    return digest.hexdigest()


@pytest.mark.parametrize("name, digest", [
    ("pso-crowd", "19613e45cc38b01b46766d87faa2eadf696efe1c2732a32b6ec8daa06aa57a0b"),
    ("oracle-static", "23e9c48867c5bd960d414a32578ff603f5c97af1cd7ea6576eaad538f3c8e0b0"),  # its derived margins (0.2.0)
])  # fmt: skip
def test_wall_free_episodes_keep_their_actions(name, digest):
    """The default scene's actions as before the covering rows (digests taken on e878c33)."""
    assert _actions_digest(name) == digest
