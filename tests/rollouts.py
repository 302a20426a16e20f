"""Helpers the tests share (imported by name: tests/conftest.py puts tests/ on the path)."""

import numpy as np

from pathplan_env import Obstacle, Scenario

#: A wall across the straight line from start to goal; the goal lies behind it.
WALLED = Scenario(bounds=(0.0, 0.0, 10.0, 10.0), start=(2.0, 5.0), goal=(8.0, 5.0), walls=(((5.0, 2.5), (5.0, 7.5)),), name="walled")
#: Resting discs on the way (Δd 0: nothing moves).
RESTING = Scenario(bounds=(0.0, 0.0, 10.0, 10.0), start=(1.0, 5.0), goal=(9.0, 5.0), name="resting",
                   obstacles=(Obstacle((4.0, 5.0), 0.8), Obstacle((6.5, 4.2), 0.6), Obstacle((6.5, 6.0), 0.5)))  # fmt: skip


def fly_unicycle(agent, env, seed):
    """One episode: ``(info, driven poses after every step, the plans' poses as held at each step, actions)``."""
    agent.reset()
    obs, info = env.reset(seed=seed)
    world, driven, actions = env.unwrapped.world, [], []
    while True:
        action, _ = agent.predict(obs, deterministic=True)
        actions.append(np.array(action))
        obs, _, terminated, truncated, info = env.step(action)
        driven.append((*world.robot_xy, world.robot_heading, world.robot_forward_speed, world.robot_angular_velocity))
        if terminated or truncated:
            return info, np.array(driven), np.array(actions)



def random_action_observations(env, seed, steps):
    """The observations of up to ``steps`` steps under random actions from ``env.reset(seed=seed)``,
    the first included, stopping at the episode's end."""
    obs, _ = env.reset(seed=seed)
    env.action_space.seed(seed)  # the same actions, and so the same observations, every run
    seen = [obs]
    for _ in range(steps - 1):
        obs, _, terminated, truncated, _ = env.step(env.action_space.sample())
        if terminated or truncated:
            break
        seen.append(obs)
    return seen
