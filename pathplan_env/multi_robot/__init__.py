"""Many robots in one world: a PettingZoo ``ParallelEnv`` in which every robot is the single env's
robot (``pathplan_env.multi_robot.parallel_env(scenario="multi-circle-4")``).

PettingZoo is an optional dependency (``pip install pathplan-env[multi]``): it is imported only
when the env is made, so the scenes, the world and the core install do without it.
"""

from __future__ import annotations

from pathplan_env.multi_robot.presets import PRESETS, make_multi_scenario
from pathplan_env.multi_robot.scene import ARRIVALS, MultiScenario, RobotSpec


def parallel_env(**kwargs):
    """The multi-robot ``ParallelEnv`` (``pathplan_env.multi_robot.env.MultiRobotEnv``'s arguments)."""
    try:
        from pathplan_env.multi_robot.env import MultiRobotEnv
    except ModuleNotFoundError as error:
        if error.name != "pettingzoo":
            raise
        raise ModuleNotFoundError("the multi-robot env needs PettingZoo: pip install 'pathplan-env[multi]'", name="pettingzoo") from None
    return MultiRobotEnv(**kwargs)


__all__ = ["ARRIVALS", "PRESETS", "MultiScenario", "RobotSpec", "make_multi_scenario", "parallel_env"]
