"""pathplan-env: path planning among moving obstacles, as a Gymnasium environment.

``import pathplan_env`` registers ``DynamicObstacle-v0`` and ``DynamicObstacleFlat-v0`` (the same env
inside the learning wrappers, for rl-zoo3 and other tools that want a flat ``Box`` observation).
"""

from gymnasium.envs.registration import register

from pathplan_env import _moved
from pathplan_env._numba_cache import configure as _configure_numba_cache

_moved.install()  # the import paths of 0.1.0 that moved (pathplan_env.statics, ...) keep working
_configure_numba_cache()  # before any compiled function is defined

from pathplan_env.env import DynamicObstacleEnv  # noqa: E402
from pathplan_env.geometry.shortest_paths import shortest_path  # noqa: E402
from pathplan_env.scenarios.presets import PAPER_CASES, PRESETS, make_scenario, paper_case, sample_random_scenario  # noqa: E402
from pathplan_env.scenarios.scenario import Obstacle, Scenario  # noqa: E402
from pathplan_env.wrappers import EgocentricObservation, EpisodeSchedule, RelativeWaypointAction, make_learning_env  # noqa: E402

#: Episode time limit of the registered env (20 s at dt = 0.1 s): 4-6x the straight-line time.
MAX_EPISODE_STEPS = 200

register(
    id="DynamicObstacle-v0",
    entry_point="pathplan_env.env:DynamicObstacleEnv",
    max_episode_steps=MAX_EPISODE_STEPS,
)
# the same env inside the learning wrappers (flat Box observation): what rl-zoo3's MlpPolicy takes
register(
    id="DynamicObstacleFlat-v0",
    entry_point="pathplan_env.zoo:make_flat_env",
    max_episode_steps=MAX_EPISODE_STEPS,
)

__all__ = [
    "DynamicObstacleEnv",
    "EgocentricObservation",
    "EpisodeSchedule",
    "MAX_EPISODE_STEPS",
    "Obstacle",
    "PAPER_CASES",
    "PRESETS",
    "RelativeWaypointAction",
    "Scenario",
    "make_learning_env",
    "make_scenario",
    "paper_case",
    "sample_random_scenario",
    "shortest_path",
]
__version__ = "0.2.0.dev0"
