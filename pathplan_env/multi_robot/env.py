"""The multi-robot env: a PettingZoo ``ParallelEnv`` in which every robot is a single env's robot."""

from __future__ import annotations

import math
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces
from gymnasium.utils import seeding
from pettingzoo import ParallelEnv

from pathplan_env.arena import Arena
from pathplan_env.arguments import check_count, check_delta_d
from pathplan_env.multi_robot.motion import make_driver
from pathplan_env.multi_robot.presets import make_multi_scenario
from pathplan_env.multi_robot.scene import ARRIVALS, MultiScenario
from pathplan_env.multi_robot.views import RobotEnv, RobotWorld
from pathplan_env.multi_robot.world import MultiWorld
from pathplan_env.rewards import RewardWeights, reward_terms
from pathplan_env.robots import unicycle  # noqa: F401  (registers the "unicycle" action)
from pathplan_env.robots.actions import make_action_type, with_robot_entries
from pathplan_env.sensors import lidar, visible_state  # noqa: F401  (register the "lidar" and "visible-state" observations)
from pathplan_env.sensors.observations import make_observation_type

#: The Dict entry that flags which moving bodies are robots (1) rather than obstacles (0; padding 0).
ROBOT_FLAG = "obstacle_is_robot"


class MultiRobotEnv(ParallelEnv):
    """
    ## Description
    Several robots, each the single env's robot (``DynamicObstacle-v0``: its start, goal, radius,
    speed, robot model, observation and action types), share one world: the single env's arena,
    bouncing obstacles or ORCA humans, walls and polygons (``pathplan_env.multi_robot.world``). To each
    robot the others are moving bodies: rows of its ``obstacle_*`` entries after the obstacles, with
    ``obstacle_is_robot`` 1; a robot never sees itself. So every single-robot agent drives one robot
    unchanged: ``agents.make(name, env.robot_env(agent), seed=...)``.

    Robot-robot contact is an exact swept test of two moving discs at every physics substep
    (``pathplan_env.multi_robot.contacts``), robot-obstacle and robot-wall contact the single env's.
    A robot that touches anything is out of the episode (terminated, removed from the world and from
    ``agents``); one that arrives terminates and rests at its goal as a body the others must avoid
    (``arrival="stay"``, gym-collision-avoidance's convention) or leaves the world (``"leave"``).
    ORCA humans see every robot in the world when ``robot_visible``.

    ## Spaces
    Per robot, those of the single env with its ``observation``/``robot``; a ``Dict`` observation with
    per-body rows gains ``obstacle_is_robot`` ``(N,)``. ``N`` defaults to ``max(16, obstacles + robots - 1)``.

    ## Rewards and info
    Per robot, the single env's terms (``pathplan_env.rewards``); a contact with a robot is a collision.
    ``infos[agent]``: ``is_success``, ``collision``, ``collision_with`` (``"robot"``, ``"obstacle"``,
    ``"wall"`` or ``None``), ``other_robot`` (the agent touched, or ``None``), ``min_clearance``,
    ``path_length``, ``time``, ``distance_to_goal``, ``waypoint``, ``rewards``.

    ## Episode End
    A robot terminates on arriving or on contact; every robot still moving is truncated after
    ``max_steps`` (default 200) or the scene's ``time_limit``. The episode ends when ``agents`` is empty.

    ## Arguments
    ``parallel_env(scenario="multi-circle-4", delta_d=None, arrival=None, robot_visible=None,
    max_obstacles=None, max_steps=200, render_mode=None, **reward_weights)``: ``scenario`` a preset
    (``pathplan_env.multi_robot.presets``), a ``MultiScenario`` or its dict form (a ``robots:`` list);
    ``arrival`` overrides the scene's.
    """

    metadata = {"name": "multi_robot_v0", "render_modes": ["rgb_array"], "render_fps": 10, "is_parallelizable": True}

    def __init__(self, scenario: str | MultiScenario | dict = "multi-circle-4", delta_d: float | None = None, arrival: str | None = None,
                 robot_visible: bool | None = None, max_obstacles: int | None = None, max_steps: int = 200, render_mode: str | None = None,
                 reward_progress: float = 1.0, reward_goal: float = 1.0, reward_collision: float = -1.0, reward_time: float = -0.005,
                 reward_proximity: float = 0.0, proximity_distance: float = 0.5):  # fmt: skip
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"render_mode must be one of {self.metadata['render_modes']} or None, got {render_mode!r}")
        if arrival is not None and arrival not in ARRIVALS:
            raise ValueError(f"arrival must be one of {list(ARRIVALS)} or None, got {arrival!r}")
        if robot_visible is not None and not isinstance(robot_visible, (bool, np.bool_)):
            raise ValueError(f"robot_visible must be True, False or None, got {robot_visible!r}")
        self.render_mode = render_mode
        self._spec, self._delta_d, self._arrival, self._robot_visible = scenario, check_delta_d(delta_d), arrival, robot_visible
        self.max_steps = check_count(max_steps, "max_steps")
        if self.max_steps < 1:
            raise ValueError(f"max_steps must be >= 1, got {max_steps!r}")
        self.reward_weights = RewardWeights(reward_progress, reward_goal, reward_collision, reward_time, reward_proximity, proximity_distance)
        scene = self._make_scene(np.random.default_rng(0))  # bad input fails here; fixes the spaces
        self.scene = scene
        n = scene.n_robots
        self.possible_agents = [f"robot_{i}" for i in range(n)]
        self.agents: list[str] = []
        bodies = scene.world.n_obstacles + n - 1
        if max_obstacles is None:
            max_obstacles = max(16, bodies)
        if check_count(max_obstacles, "max_obstacles") < bodies:
            raise ValueError(f"max_obstacles must be >= the scene's {bodies} moving bodies (obstacles and other robots), got {max_obstacles!r}")
        self.max_obstacles = int(max_obstacles)
        self.robot_models = [spec.robot for spec in scene.robots]
        self.observation_types, self.action_types, self._observers, self._observation_spaces, self._action_spaces = [], [], [], {}, {}
        self._flagged = []
        for i, (agent, spec) in enumerate(zip(self.possible_agents, scene.robots)):
            robot_scenario = scene.robot_scenario(i)
            arena = Arena.of(robot_scenario)
            try:
                observation_type = make_observation_type(spec.observation, arena, robot_scenario.dt, self.max_obstacles, spec.observation_params,
                                                         static_segments=len(robot_scenario.static_segments))  # fmt: skip
                action_type = make_action_type(None, arena, spec.robot, spec.robot_params)
                action_type.check(robot_scenario)
                space, observe = with_robot_entries(observation_type, action_type, robot_scenario.dt)
            except ValueError as error:
                raise ValueError(f"robots[{i}]: {error}") from None
            flagged = isinstance(space, spaces.Dict) and "obstacle_mask" in space.spaces
            if flagged:
                space = spaces.Dict(dict(space.spaces) | {ROBOT_FLAG: spaces.Box(0.0, 1.0, shape=(self.max_obstacles,), dtype=np.float32)})
            self.observation_types.append(observation_type)
            self.action_types.append(action_type)
            self._observers.append(observe)
            self._flagged.append(flagged)
            self._observation_spaces[agent] = space
            self._action_spaces[agent] = action_type.space()
        self.np_random, self._np_random_seed = seeding.np_random(None)
        self.multi: MultiWorld | None = None
        self._actions_log: list[dict[int, Any]] | None = None
        self._renderer = None

    # -- PettingZoo API ----------------------------------------------------------------------
    def observation_space(self, agent: str) -> spaces.Space:
        return self._observation_spaces[agent]

    def action_space(self, agent: str) -> spaces.Space:
        return self._action_spaces[agent]

    def robot_env(self, agent: str) -> RobotEnv:
        """What an agent reads of ``agent``'s env (its static public facts and spaces): pass it to
        ``agents.make`` to drive that robot with a single-robot agent."""
        if agent not in self.possible_agents:
            raise ValueError(f"agent must be one of {self.possible_agents}, got {agent!r}")
        return RobotEnv(self, agent)

    def robot_scenario(self, agent: str):
        """``agent``'s single-robot scenario in this episode (its start, goal, radius; the shared world)."""
        return self.scene.robot_scenario(self.possible_agents.index(agent))

    def reset(self, seed: int | None = None, options: dict | None = None):
        # options are ignored, as PettingZoo's own envs do (its API test passes some)
        if seed is not None:
            self.np_random, self._np_random_seed = seeding.np_random(seed)
        scene = self._make_scene(self.np_random)
        if scene.n_robots != len(self.possible_agents) or scene.world.bounds != self.scene.world.bounds:
            raise ValueError("scenario: an episode's robots and arena must match the env's (they fix the spaces)")
        self._begin(scene)
        self._actions_log = []
        observations = {agent: self._observe(i) for i, agent in enumerate(self.possible_agents)}
        infos = {agent: self._info(i, None, 0.0, {}) for i, agent in enumerate(self.possible_agents)}
        for i, agent in enumerate(self.possible_agents):
            infos[agent]["rewards"] = dict.fromkeys(self._terms(i, False, False, self._distance[i], 1.0), 0.0)
        return observations, infos

    def step(self, actions: dict[str, Any]):
        multi = self.multi
        if multi is None:
            raise RuntimeError("call reset() before step()")
        unknown = sorted(set(actions) - set(self.agents))
        if unknown:
            raise ValueError(f"actions: {unknown} are not among the live agents {self.agents}")
        missing = [agent for agent in self.agents if agent not in actions]
        if missing:
            raise ValueError(f"actions: no action for the live agents {missing}")
        indices = {self.possible_agents.index(agent): actions[agent] for agent in self.agents}
        self._actions_log.append(indices)
        return self._advance(indices)

    def _moves(self, indices: dict[int, Any]) -> dict:
        moves = {}
        for i, action in indices.items():
            try:
                moves[i] = self._drivers[i].move(action, self.multi.robots[i])
            except ValueError as error:
                raise ValueError(f"actions[{self.possible_agents[i]!r}]: {error}") from None
        return moves

    def _advance(self, indices: dict[int, Any]):
        multi = self.multi
        moves = self._moves(indices)
        results = multi.step(moves)
        self._steps += 1
        observations, rewards, terminations, truncations, infos = {}, {}, {}, {}, {}
        out_of_time = self._steps >= self._step_limit
        for i, step in results.items():
            agent = self.possible_agents[i]
            collision = step.hit is not None
            success = step.goal <= 1.0 and not collision
            fraction = step.goal if success else step.contact if collision else 1.0
            self._path_length[i] += step.length * fraction
            (rx, ry), (gx, gy) = multi.robots[i].xy, self.scene.robot_scenario(i).goal
            distance = 0.0 if success else math.hypot(rx - gx, ry - gy)
            terms = self._terms(i, success, collision, distance, step.min_gap)
            self._distance[i] = distance
            self._waypoints[i] = step.waypoint
            self._trails[i].append(multi.robots[i].xy)
            rewards[agent] = float(sum(terms.values()))
            terminations[agent] = success or collision
            truncations[agent] = out_of_time and not terminations[agent]
            infos[agent] = self._info(i, step, step.min_gap, terms)
        for i in results:  # observed after every robot moved
            observations[self.possible_agents[i]] = self._observe(i)
        self.agents = [a for a in self.agents if not (terminations[a] or truncations[a])]
        return observations, rewards, terminations, truncations, infos

    def render(self):
        if self.render_mode is None:
            gym.logger.warn("render() was called without a render_mode; pass render_mode='rgb_array'")
            return None
        if self.multi is None:
            raise RuntimeError("call reset() before render()")
        from pathplan_env.multi_robot.drawing import draw  # matplotlib is imported lazily

        return draw(self)

    def close(self):
        pass

    def state(self) -> np.ndarray:
        """The global state: every robot's ``(x, y, vx, vy)`` then every obstacle's (float32)."""
        multi = self.multi
        return np.concatenate([multi.robot_rows(range(len(multi.robots))).ravel(), multi.obstacle_state.ravel()]).astype(np.float32)

    # -- helpers -----------------------------------------------------------------------------
    def _make_scene(self, rng) -> MultiScenario:
        scene = make_multi_scenario(self._spec, rng, self._delta_d)
        if self._arrival is not None and scene.arrival != self._arrival:
            scene = scene.with_arrival(self._arrival)
        if self._robot_visible is not None and scene.world.robot_visible != bool(self._robot_visible):
            scene = scene.with_world(scene.world.with_robot_visible(bool(self._robot_visible)))
        return scene

    def _build_world(self, scene: MultiScenario) -> None:
        """The episode's world from ``scene``, its robots' views and drivers (a reset, or a copy)."""
        self.scene = scene
        self.multi = multi = MultiWorld(scene)
        self._views = [RobotWorld(multi, i) for i in range(scene.n_robots)]
        self._drivers = []
        for i, view in enumerate(self._views):
            view.refresh()
            robot_scenario = scene.robot_scenario(i)
            self.action_types[i].reset(view, Arena.of(robot_scenario))
            self._drivers.append(make_driver(self.action_types[i], robot_scenario))

    def _begin(self, scene: MultiScenario) -> None:
        """A new episode of ``scene``."""
        self._build_world(scene)
        multi = self.multi
        self.agents = list(self.possible_agents)
        self._obs_rngs = []
        for i, view in enumerate(self._views):
            # a noisy sensor's own stream, drawn from the episode's generator only if a sensor draws
            rng = np.random.default_rng(self.np_random.integers(2**63)) if self.observation_types[i].draws else None
            self._obs_rngs.append(rng)
            self.observation_types[i].reset(view, rng)
        self._start_distance = [max(math.dist(s.start, s.goal), 1e-9) for s in map(scene.robot_scenario, range(scene.n_robots))]
        self._distance = list(self._start_distance)
        self._path_length = [0.0] * scene.n_robots
        self._waypoints = [None] * scene.n_robots
        self._trails = [[r.xy] for r in multi.robots]
        self._steps = 0
        limit = scene.world.time_limit
        self._step_limit = self.max_steps if limit is None else min(self.max_steps, max(1, math.ceil(limit / scene.world.dt - 1e-9)))

    def _observe(self, i: int):
        view = self._views[i]
        if view.refresh():
            self.observation_types[i].reset(view, self._obs_rngs[i])
        obs = self._observers[i](view)
        if self._flagged[i]:
            flag = np.zeros(self.max_obstacles, np.float32)
            n = self.multi.world.n_obstacles
            flag[n : n + len(view.others)] = 1.0
            obs[ROBOT_FLAG] = flag * obs["obstacle_mask"]
        return obs

    def _terms(self, i, success, collision, distance, min_gap) -> dict[str, float]:
        return reward_terms(self.reward_weights, self._distance[i], distance, self._start_distance[i], success, collision, min_gap)

    def _info(self, i: int, step, min_gap: float, terms: dict) -> dict[str, Any]:
        hit = None if step is None else step.hit
        return {
            "is_success": bool(step is not None and hit is None and step.goal <= 1.0),
            "collision": hit is not None,
            "collision_with": hit,
            "other_robot": self.possible_agents[step.other] if step is not None and step.other >= 0 else None,
            "cost": 1.0 if hit is not None else 0.0,
            "min_clearance": float(self.multi.clearance(i)) if step is None else float(min_gap),
            "path_length": self._path_length[i],
            "time": self.multi.time,
            "distance_to_goal": self._distance[i],
            "waypoint": self._waypoints[i],
            "rewards": terms,
        }

    def __getstate__(self):
        # the world travels as its scene and the actions since reset, replayed on arrival (as the
        # single env's: pymunk's own pickle drops Chipmunk's cache of ongoing contacts)
        state = self.__dict__.copy()
        for key in ("multi", "_views", "_drivers", "_renderer"):
            state[key] = None
        return state

    def __setstate__(self, state):
        self.__dict__.update(state)
        if self._actions_log is not None:
            self._build_world(self.scene)
            for indices in self._actions_log:
                self.multi.step(self._moves(indices))
            for view in self._views:
                view.refresh()  # (the observation types' own state travelled with them)


def parallel_env(**kwargs) -> MultiRobotEnv:
    """PettingZoo's constructor name: ``pathplan_env.multi_robot.parallel_env(scenario=..., ...)``."""
    return MultiRobotEnv(**kwargs)


__all__ = ["ROBOT_FLAG", "MultiRobotEnv", "parallel_env"]
