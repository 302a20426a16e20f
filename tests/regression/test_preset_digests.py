"""Every preset keeps its episodes through the speed work (issues 21, 23): digests of the crowd
families, the wall families and the unicycle among them, computed on bd388ba before any of it.

Each digest hashes every scene drawn (obstacles, goals, preferred speeds) and every step's
observation, reward and info over random actions, resets included (they come every few steps in
these narrow scenes), so the sampler, the validation fast paths and the step are all covered.
"""

from __future__ import annotations

import hashlib

import gymnasium as gym
import numpy as np
import pytest

import pathplan_env  # noqa: F401  (registers DynamicObstacle-v0)


def preset_digest(scenario: str, steps: int = 120, seed: int = 4, **kwargs) -> str:
    env = gym.make("DynamicObstacle-v0", scenario=scenario, **kwargs)
    env.action_space.seed(seed)
    h = hashlib.sha256()

    def scene():
        s = env.unwrapped.scenario
        h.update(repr((s.start, s.goal, s.walls, s.polygons, s.obstacles, s.n_obstacles)).encode())

    obs, _ = env.reset(seed=seed)
    scene()
    for _ in range(steps):
        obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
        for key in sorted(obs):
            h.update(np.ascontiguousarray(obs[key]).tobytes())
        h.update(repr((reward, terminated, truncated, info["min_clearance"], info["path_length"], info["collision"])).encode())
        if terminated or truncated:
            env.reset()
            scene()
    return h.hexdigest()


PRESET_DIGESTS = [  # computed on bd388ba, before the speed work
    ({'scenario': 'corridor-crowd'}, "a9b366a417d97f4e2af7188980fe26983922c8f5471b828d0467b3c69a8d9a9e"),
    ({'scenario': 'corridor-crowd', 'n_obstacles': 20}, "2ecbf05bf0e82cb11c215229746b52c632c8d1a9ef0ac7a697a1be143a60edfc"),
    ({'scenario': 'doorway-crowd'}, "226ab9ca0139a3e06cc74601423dd3f686379e88119cd3c30c3df1bcbc607b37"),
    ({'scenario': 'intersection-crowd'}, "027892a23272e0a6b0fcaa9eb88dc67f61eaf04f703a3642ca5ed1d51aa6cab4"),
    ({'scenario': 'cluttered-room-crowd', 'delta_d': 0.5}, "dbfe29a669a3fe5ead8710a3168664a20404651a4f25ff09ab617ed79d4c3ff1"),
    ({'scenario': 'maze'}, "fab07f8a9e2cd644dbf56cfe14384f13120eb0949034639cf152f6446e83ce36"),
    ({'scenario': 'maze-crowd'}, "9c5ee8fda62ebc6c78d3a0fe0f7bdeee5d8ceec4bdd8ac7b11b4b221f136d407"),
    ({'scenario': 'corridor-crowd', 'n_obstacles': 20, 'robot': 'unicycle'}, "4d25132250512cb95d33b6392259b2091ed1de84d34398a039200d7d73590798"),
    ({'scenario': 'doorway', 'robot': 'unicycle', 'delta_d': 0.5}, "dcffae00c9e70dc8be893835998715f683c319d2539697669058e43b3890fa0e"),
    ({'scenario': 'random', 'n_obstacles': 5, 'robot': 'unicycle'}, "1751ea1a565f36e412dc9d5dd077976b1140ff2dbf65d967c595cec703d4c51c"),
    ({'scenario': 'crowdnav-circle-crossing', 'robot_visible': True}, "42073b9cc78324ae1bcd622b6a1b620873e2cee7063f8c37345dfc62bf4d2464"),
]


@pytest.mark.parametrize("kwargs, digest", PRESET_DIGESTS)
def test_presets_replay_their_digest(kwargs, digest):
    assert preset_digest(**kwargs) == digest
