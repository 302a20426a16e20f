"""Import paths of 0.1.0 that moved in 0.2.0, kept working for users: one table, one import hook.

``import pathplan_env.statics`` (or unpickling a class pickled under an old path) gets the module at
its new home, the same object: ``pathplan_env.statics is pathplan_env.geometry.walls``. A module that
also lost a name to another room (``occupancy.scenario_kwargs``) comes as a thin module that reads
its names from the new homes. The project's own code never uses these paths (ruff's banned-api rule,
``pyproject.toml``). Written by hand: importlib has no alias table, and ``sys.modules`` entries made
up front would import every room at ``import pathplan_env``.
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.util
import sys
import types

#: old module -> new module (both the env's and the agents' rooms: the env imports no agent, it only names them)
MOVED_MODULES = {
    "pathplan_env.statics": "pathplan_env.geometry.walls",
    "pathplan_env.raycast": "pathplan_env.geometry.rays",
    "pathplan_env.world_space": "pathplan_env.world.space",
    "pathplan_env.substeps": "pathplan_env.world.substep_count",
    "pathplan_env.substep_kernels": "pathplan_env.world.substep_kernels",
    "pathplan_env.chipmunk": "pathplan_env.world.chipmunk",
    "pathplan_env.actions": "pathplan_env.robots.actions",
    "pathplan_env.kinematics": "pathplan_env.robots.holonomic",
    "pathplan_env.unicycle": "pathplan_env.robots.unicycle",
    "pathplan_env.unicycle_step": "pathplan_env.robots.unicycle_step",
    "pathplan_env.arc_contact": "pathplan_env.robots.arc_contact",
    "pathplan_env.observations": "pathplan_env.sensors.observations",
    "pathplan_env.lidar": "pathplan_env.sensors.lidar",
    "pathplan_env.visibility": "pathplan_env.sensors.visible_state",
    "pathplan_env.sensor_params": "pathplan_env.sensors.range_sensor",
    "pathplan_env.behaviours": "pathplan_env.crowds.behaviours",
    "pathplan_env.orca": "pathplan_env.crowds.orca",
    "pathplan_env.orca_obstacles": "pathplan_env.crowds.orca_obstacles",
    "pathplan_env.routing": "pathplan_env.crowds.routing",
    "pathplan_env.ros_maps": "pathplan_env.maps.ros_maps",
    "pathplan_env.occupancy": "pathplan_env.maps.occupancy",
    "pathplan_env.presets": "pathplan_env.scenarios.presets",
    "pathplan_env.families": "pathplan_env.scenarios.wall_families",
    "pathplan_env.crowd_families": "pathplan_env.scenarios.crowd_families",
    "pathplan_env.crowdnav": "pathplan_env.scenarios.crowdnav",
    "pathplan_env.scenario_files": "pathplan_env.scenarios.files",
    "pathplan_env.splits": "pathplan_env.scenarios.splits",
    "agents.rl.lidar_encoder": "agents.rl.lidar.encoder",
    "agents.rl.lidar_features": "agents.rl.lidar.features",
    "agents.rl.lidar_policy": "agents.rl.lidar.policy",
    "agents.rl.sarl_kernel": "agents.rl.sarl.kernel",
    "agents.rl.sarl_local_map": "agents.rl.sarl.local_map",
    "agents.rl.sarl_lookahead": "agents.rl.sarl.lookahead",
    "agents.rl.sarl_net": "agents.rl.sarl.net",
    "agents.rl.sarl_numpy": "agents.rl.sarl.numpy_net",
    "agents.rl.sarl_planning": "agents.rl.sarl.planning",
    "agents.rl.sarl_policy": "agents.rl.sarl.policy",
    "agents.rl.sarl_settings": "agents.rl.sarl.settings",
    "agents.rl.sarl_standing": "agents.rl.sarl.standing",
    "agents.rl.training.sarl_config": "agents.rl.sarl.training.config",
    "agents.planners.spacetime_search": "agents.planners.spacetime.astar",
    "agents.planners.spacetime_anytime": "agents.planners.spacetime.anytime",
    "agents.planners.spacetime_seed": "agents.planners.spacetime.seeds",
    "agents.planners.spacetime_metaheuristic": "agents.planners.spacetime.metaheuristic_agent",
    "agents.planners.unicycle_search": "agents.planners.unicycle.astar",
    "agents.planners.unicycle_astar": "agents.planners.unicycle.astar_agent",
    "agents.planners.unicycle_metaheuristic": "agents.planners.unicycle.metaheuristic_agent",
    "agents.planners.unicycle_rollout": "agents.planners.unicycle.rollout",
    "agents.rl.training.sarl_outputs": "agents.rl.sarl.training.outputs",
    "agents.rl.training.sarl_train": "agents.rl.sarl.training.train",
    "agents.rl.set_encoder": "agents.rl.obstacle_set.encoder",
    "agents.rl.set_features": "agents.rl.obstacle_set.features",
    "agents.rl.set_numpy": "agents.rl.obstacle_set.numpy_net",
    "agents.rl.numpy_conv": "agents.rl.lidar.numpy_encoder",
    "agents.rl.set_policy": "agents.rl.obstacle_set.policy",
    "agents.oracles.tangent_graph": "pathplan_env.geometry.tangent_graph",
}
#: old module -> {name: the module it lives in now}, for names that left their module's room
MOVED_NAMES = {
    "pathplan_env.occupancy": {"scenario_kwargs": "pathplan_env.scenarios.on_maps", "Obstacle": "pathplan_env.scenarios.scenario"},
    "pathplan_env.ros_maps": {"scenario_kwargs": "pathplan_env.scenarios.on_maps"},
    "pathplan_env.unicycle": {"Arc": "pathplan_env.robots.arc_contact"},
    "agents.rl.set_numpy": {"export_any_policy": "agents.rl.export"},
    "agents.rl.numpy_policy": {name: "agents.rl.lidar.numpy_encoder" for name in ("NumpyConvEncoder", "PREFIX", "export_encoder")},
    "pathplan_env.env": {"MAX_REWARD_WEIGHT": "pathplan_env.rewards"},
    "agents.base": {**{name: "agents.registry" for name in ("available", "factory", "make", "register", "robots_of")},
                    "covering_rows": "agents.observation"},
    "pathplan_env.wrappers": {"Arena": "pathplan_env.arena", "STEPS_PER_LENGTH_UNIT": "pathplan_env.facts"},
}


def names_of(module: str):
    """A module's ``__getattr__`` (PEP 562) for its names that moved out: ``__getattr__ = names_of(__name__)``."""
    moved = MOVED_NAMES[module]

    def __getattr__(name: str):
        if name not in moved:
            raise AttributeError(f"module {module!r} has no attribute {name!r}")
        return getattr(importlib.import_module(moved[name]), name)

    return __getattr__


class _ModuleWithMovedNames(types.ModuleType):
    def __init__(self, name: str, home: str, names: dict[str, str]):
        super().__init__(name, f"The names of {name}: moved to {home} (and {', '.join(sorted(set(names.values())))}).")
        self.__home, self.__names = home, names

    def __getattr__(self, name: str):
        module = self.__names.get(name, self.__home)
        return getattr(importlib.import_module(module), name)

    def __dir__(self):
        return sorted(set(dir(importlib.import_module(self.__home))) | set(self.__names))


class _MovedLoader(importlib.abc.Loader):
    def __init__(self, home: str):
        self.home = home

    def create_module(self, spec):
        return None  # a placeholder: exec_module puts the real module in its place

    def exec_module(self, module) -> None:
        # the import system returns whatever sys.modules holds after exec_module: the new home itself
        name = module.__name__
        if name in MOVED_NAMES:
            sys.modules[name] = _ModuleWithMovedNames(name, self.home, MOVED_NAMES[name])
        else:
            sys.modules[name] = importlib.import_module(self.home)


class _MovedFinder(importlib.abc.MetaPathFinder):
    def find_spec(self, fullname, path, target=None):
        home = MOVED_MODULES.get(fullname)
        return None if home is None else importlib.util.spec_from_loader(fullname, _MovedLoader(home))


def install() -> None:
    """Put the hook on ``sys.meta_path`` once (``import pathplan_env`` does)."""
    if not any(isinstance(finder, _MovedFinder) for finder in sys.meta_path):
        sys.meta_path.insert(0, _MovedFinder())
