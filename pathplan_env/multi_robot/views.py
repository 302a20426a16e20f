"""What one robot sees of the world of several: its observation's world, and its env's public facts.

:class:`RobotWorld` is the single env's ``World`` as robot ``i``'s observation type reads it: the robot
is robot ``i``, and the moving bodies are the obstacles followed by the other robots in the world
(never itself), so every observation type of the single env observes it unchanged.
:class:`RobotEnv` is what an agent reads of robot ``i``'s env (``pathplan_env.facts.EnvFacts``: the
bounds, dt, its radius, speed, goal radius, model and limits; its spaces and arena), so every
single-robot agent (``agents.make(name, env.robot_env(agent))``) drives one robot unchanged.
"""

from __future__ import annotations

import numpy as np

from pathplan_env.arena import Arena


class RobotWorld:
    """Robot ``index``'s view of a ``MultiWorld``: what its observation and action types read."""

    def __init__(self, multi, index: int):
        self.multi, self.index = multi, index
        self.scenario = multi.scenarios[index]
        self.static_segments = multi.world.static_segments
        self.others: tuple[int, ...] = ()
        self._rows: list[int] = []
        self._seen = None
        self.radii = multi.world.radii

    def refresh(self) -> bool:
        """Follow the robots in the world; ``True`` if the set of others changed (the caller resets
        the observation type, whose padding and radii are set once per set of bodies)."""
        present = self.multi.present()
        if present is self._seen:  # (the same list object: nothing left the world since the last look)
            return False
        self._seen = present
        others = tuple(j for j in present if j != self.index)
        if others == self.others and len(self.radii) == self.multi.world.n_obstacles + len(others):
            return False
        self.others = others
        self._rows = list(others)
        self.radii = np.concatenate([self.multi.world.radii, self.multi.radii[list(others)]])
        return True

    @property
    def n_obstacles(self) -> int:
        return len(self.radii)

    @property
    def obstacle_state(self) -> np.ndarray:
        world = self.multi.world
        if not self.others:
            return world.obstacle_state
        return np.concatenate([world.obstacle_state, self.multi.robot_states[self._rows]])

    @property
    def time(self) -> float:
        return self.multi.world.time

    def _robot(self):
        return self.multi.robots[self.index]

    robot_xy = property(lambda self: self._robot().xy)
    robot_velocity_xy = property(lambda self: self._robot().velocity)
    robot_position = property(lambda self: np.array(self._robot().xy))
    robot_velocity = property(lambda self: np.array(self._robot().velocity))
    robot_heading = property(lambda self: self._robot().heading, lambda self, v: None)
    robot_forward_speed = property(lambda self: self._robot().forward_speed, lambda self, v: None)
    robot_angular_velocity = property(lambda self: self._robot().turn_rate, lambda self, v: None)

    def __getattr__(self, name):  # the shared World's internals (a unicycle's action type binds them)
        if name in ("multi", "__getstate__", "__setstate__"):
            raise AttributeError(name)
        return getattr(self.multi.world, name)


class RobotEnv:
    """Robot ``agent``'s env as an agent reads it: the static public facts, its spaces and arena."""

    def __init__(self, env, agent: str):
        self._env, self.agent = env, agent
        self.index = env.possible_agents.index(agent)

    @property
    def unwrapped(self) -> RobotEnv:
        return self

    scenario = property(lambda self: self._env.robot_scenario(self.agent))
    bounds = property(lambda self: self.scenario.bounds)
    dt = property(lambda self: self.scenario.dt)
    robot_radius = property(lambda self: self.scenario.robot_radius)
    robot_speed = property(lambda self: self.scenario.robot_speed)
    goal_radius = property(lambda self: self.scenario.goal_radius)
    robot = property(lambda self: self._env.robot_models[self.index])
    robot_limits = property(lambda self: self._env.action_types[self.index].limits_for(self.scenario))
    robot_step_length = property(lambda self: self.scenario.robot_speed * self.scenario.dt)
    arena = property(lambda self: Arena.of(self.scenario))
    observation_space = property(lambda self: self._env.observation_space(self.agent))
    action_space = property(lambda self: self._env.action_space(self.agent))

    def action_to_waypoint(self, action) -> np.ndarray:
        return self.arena.action_to_waypoint(action)

    def waypoint_to_action(self, waypoint) -> np.ndarray:
        return self.arena.waypoint_to_action(waypoint)


__all__ = ["RobotEnv", "RobotWorld"]
