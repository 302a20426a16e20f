"""The pymunk space lent from one episode's world to the next (``pathplan_env.world.space``): every
episode is the one a new space gives, bit for bit, and a space is lent only where it fits (another
obstacle count, moving pattern or statics builds a new one); copies still continue exactly."""

from __future__ import annotations

import copy

import gymnasium as gym
import numpy as np
import pytest

import pathplan_env.world.space as world_space


def same_step(a, b) -> bool:
    return all(np.array_equal(a[0][k], b[0][k]) for k in a[0]) and a[1:4] == b[1:4] and a[4]["min_clearance"] == b[4]["min_clearance"]


def lockstep(kwargs: dict, steps: int, seed: int = 0, options=()) -> tuple[int, int]:
    """Step an env (worlds recycled) and its twin (a new world, so a new space, every reset) with the
    same actions; resets take ``options[i % len(options)]``. ``(resets, spaces lent)``."""
    env, fresh = gym.make("DynamicObstacle-v0", **kwargs), gym.make("DynamicObstacle-v0", **kwargs)
    env.reset(seed=seed), fresh.reset(seed=seed)
    env.action_space.seed(seed)
    resets = lent = 0
    for step in range(steps):
        action = env.action_space.sample()
        a, b = env.step(action), fresh.step(action)
        assert same_step(a, b), f"{kwargs}: step {step} after {resets} resets differs from a new space's"
        if a[2] or a[3]:
            space = env.unwrapped.world.space
            option = options[resets % len(options)] if options else None
            resets += 1
            fresh.unwrapped._world = None  # (nothing to recycle: a new space)
            env.reset(options=option), fresh.reset(options=option)
            lent += env.unwrapped.world.space is space
    return resets, lent


@pytest.mark.parametrize("kwargs", [
    {"scenario": "random", "n_obstacles": 20, "delta_d": 2.0},  # many contacts at once: Chipmunk's order shows
    {"scenario": "random", "n_obstacles": 5, "delta_d": 3.0, "robot": "unicycle"},
    {"scenario": "maze-crowd", "robot": "unicycle"},  # statics kept in the space, ORCA humans
])  # fmt: skip
def test_lent_spaces_run_the_episodes_new_spaces_run(kwargs):
    resets, lent = lockstep(kwargs, steps=400)
    assert resets >= 5 and lent == resets


def test_a_space_is_lent_only_where_it_fits():
    # another obstacle count, resting obstacles (kinematic bodies) or other statics: a new space each time
    resets, lent = lockstep({"scenario": "random", "n_obstacles": 6, "delta_d": 1.5}, steps=500,
                            options=({"n_obstacles": 7}, {"n_obstacles": 7}, {"delta_d": 0.0, "n_obstacles": 7}, {"delta_d": 1.5}))  # fmt: skip
    assert resets >= 8 and 0 < lent < resets  # only the second of the two 7-obstacle resets in a row reuses
    resets, lent = lockstep({"scenario": "cluttered-room", "delta_d": 1.0}, steps=300)  # its boxes differ every scene
    assert resets >= 3 and lent == 0


def test_the_lending_world_is_left_unusable():
    env = gym.make("DynamicObstacle-v0", n_obstacles=5)
    env.reset(seed=0)
    old = env.unwrapped.world
    space = old.space
    env.reset()
    assert env.unwrapped.world.space is space and old.space is None  # no stale world can step it


def test_a_space_near_its_stamp_budget_is_renewed(monkeypatch):
    monkeypatch.setattr(world_space, "STAMP_BUDGET", 300)  # a few resets' steps and insertions
    resets, lent = lockstep({"scenario": "random", "n_obstacles": 8, "delta_d": 2.0}, steps=400)
    assert resets >= 10 and 0 < lent < resets


def test_copies_continue_exactly_in_lent_spaces():
    env = gym.make("DynamicObstacle-v0", n_obstacles=20, delta_d=2.0, robot="unicycle")
    env.reset(seed=5)
    env.action_space.seed(5)
    for _ in range(6):  # a few lent spaces deep
        env.reset()
        for _ in range(3):
            env.step(env.action_space.sample())
    twin = copy.deepcopy(env)  # (replayed in a new world)
    for step in range(40):
        action = env.action_space.sample()
        a, b = env.step(action), twin.step(action)
        assert same_step(a, b), f"the copy diverged at step {step}"
        if a[2] or a[3]:
            env.reset(), twin.reset()
