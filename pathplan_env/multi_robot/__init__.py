"""Many robots in one world: a PettingZoo ``ParallelEnv`` in which every robot is the single env's
robot (``pathplan_env.multi_robot.parallel_env(scenario="multi-circle-4")``).

PettingZoo is an optional dependency (``pip install pathplan-env[multi]``): where it is installed
this module registers the env with its registry; the scenes, the world and the core install do
without it, and only making the env asks for it.
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


def aec_env(**kwargs):
    """The same env in PettingZoo's turn-based (AEC) form, as PettingZoo's own environments offer an
    ``env()`` beside ``parallel_env()`` (named ``aec_env`` here: ``env`` is this package's module of the
    ``ParallelEnv``): the robots act one after another and the world steps once all have
    (``pettingzoo.utils.parallel_to_aec``)."""
    from pettingzoo.utils.conversions import parallel_to_aec

    return parallel_to_aec(parallel_env(**kwargs))


#: The id under which PettingZoo's registry (``pettingzoo.make``, PettingZoo >= 1.27) makes the env in
#: either form once this module is imported: ``pettingzoo.make("parallel", ENV_ID, scenario="multi-circle-4")``.
ENV_ID = "pathplan/MultiRobot-v0"


def _register() -> None:
    """Register both forms with PettingZoo's Gymnasium-style registry where PettingZoo has one."""
    try:
        import pettingzoo
    except ModuleNotFoundError:
        return
    if not hasattr(pettingzoo, "register"):  # (before 1.27: only the module-level constructors)
        return
    for env_type, constructor in (("parallel", "parallel_env"), ("aec", "aec_env")):
        if ENV_ID not in getattr(pettingzoo, f"{env_type}_registry", {}):
            pettingzoo.register(env_type, ENV_ID, entry_point=f"pathplan_env.multi_robot:{constructor}")


_register()

__all__ = ["ARRIVALS", "ENV_ID", "PRESETS", "MultiScenario", "RobotSpec", "aec_env", "make_multi_scenario", "parallel_env"]
