"""DynamicObstacle-v0: a circular robot reaches a goal among moving circular obstacles."""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import gymnasium as gym
import numpy as np

from pathplan_env import _moved
from pathplan_env.arena import Arena
from pathplan_env.arguments import check_count, check_delta_d, check_n_obstacles
from pathplan_env.fused_step import FusedStep
from pathplan_env.rewards import RewardWeights, reward_terms
from pathplan_env.robots import unicycle  # noqa: F401  (registers the "unicycle" action)
from pathplan_env.robots.actions import make_action_type, with_robot_entries
from pathplan_env.scenarios.presets import make_scenario
from pathplan_env.scenarios.scenario import Scenario
from pathplan_env.sensors import lidar, visible_state  # noqa: F401  (register the "lidar" and "visible-state" observations)
from pathplan_env.sensors.observations import make_observation_type
from pathplan_env.world.simulation import World
from pathplan_env.world.substep_count import scenario_substeps

__getattr__ = _moved.names_of(__name__)  # the names of 0.1.0 that live elsewhere now


class DynamicObstacleEnv(gym.Env):
    """
    ## Description
    A circular robot must reach a goal in a walled 2D arena among circular obstacles that move in
    straight lines and bounce elastically off the walls and off each other (pymunk simulates them;
    each keeps its own speed). It is the dynamic path-planning benchmark of the paper "A Constraint
    Optimization path planning for Dynamic Environment" (modified ABC, adaptive constraint PSO),
    made a Gymnasium environment: a policy picks a waypoint every step, and the robot heads for it.

    The physics, for planners that predict it (``agents.planners.prediction`` does, from observations
    alone): obstacles are frictionless discs of mass ``r²`` (equal density) that move at constant
    speed and bounce with restitution 1 off the arena's walls and off each other, Chipmunk solving
    simultaneous contacts by sequential impulses; after every substep each obstacle gets its own
    speed back, so only directions change. Resting obstacles are immovable (infinite mass). No
    overlap correction: no obstacle ever moves farther than ``speed * dt`` in a step.

    Obstacles may instead be goal-directed agents (``pathplan_env.crowds.behaviours``): ORCA or social-force
    humans that head for goals of their own and avoid one another, and the robot when
    ``robot_visible``; the CrowdNav presets use ORCA humans (``docs/crowdnav.md``). pymunk still
    integrates them; their behaviour sets their velocities at the start of every step.

    The obstacles' speed is set by **Δd** (``delta_d``), the paper's Eq. 8: the distance an obstacle
    moves in one step divided by its radius (for goal-directed obstacles, at their preferred speed).
    The robot covers half an obstacle radius per step by default, so at Δd = 0.5 the obstacles move
    as fast as the robot.

    Robot-obstacle contact is detected continuously within a step (an exact swept-circle test at
    every physics substep), so no obstacle, however fast, crosses the robot unseen, and a near miss
    is not a hit.

    ## Action Space
    ``action="waypoint"`` (``pathplan_env.robots.actions``): ``Box(-1, 1, (2,), float32)``, a waypoint mapped
    linearly onto the arena: ``-1`` is the arena's lower edge and ``+1`` its upper edge on each axis.
    Each step the robot moves straight toward the waypoint at its maximum speed, stopping on it if it
    is closer than one step. The waypoint is clipped so that the robot's disc stays inside the arena.
    Out-of-range actions are clipped to [-1, 1]; a NaN or infinite action raises ``ValueError``.
    Convert with ``env.unwrapped.waypoint_to_action(xy)`` and ``env.unwrapped.action_to_waypoint(a)``.

    ``robot="unicycle"`` (``pathplan_env.robots.unicycle``; ``robot`` picks the action type): ``Box(-1, 1, (2,))``,
    a normalised target (forward speed in ``[min_speed, max_speed]``, turn rate ``± max_turn_rate``)
    reached within ``max_acceleration * dt`` and ``max_angular_acceleration * dt`` at each step's start and
    held over the step (one exact arc; no reversing). ``robot_params`` sets any of the five; defaults
    for robot speed ``V`` and radius ``r``: ``max_speed = V``, ``max_turn_rate = max_speed / (2 r)``, both
    reached from rest in 0.5 s, ``min_speed = 0``. It starts at rest facing the goal; the arena's edges are walls
    to it; the observation adds ``robot_heading`` (1,) and ``robot_angular_velocity`` (1,), and
    ``robot_velocity`` is its velocity now. ``env.unwrapped.action_type.limits`` holds the episode's limits.

    ## Observation Space
    ``observation="state"`` (``pathplan_env.sensors.observations``): a ``Dict`` in the world frame (metres,
    m/s), every entry float32 with finite bounds. ``N`` is ``max_obstacles``; rows past the scenario's
    obstacles are padding (zeros at the arena's lower corner, mask 0).

    | Key                   | Shape  | Observation                            | Min                | Max               |
    |-----------------------|--------|----------------------------------------|--------------------|-------------------|
    | `robot_position`      | (2,)   | robot centre                           | arena lower corner | arena upper corner|
    | `robot_velocity`      | (2,)   | robot velocity over the last step      | -V                 | V                 |
    | `goal`                | (2,)   | goal position                          | arena lower corner | arena upper corner|
    | `obstacle_positions`  | (N, 2) | obstacle centres                       | arena lower corner | arena upper corner|
    | `obstacle_velocities` | (N, 2) | obstacle velocities                    | -V                 | V                 |
    | `obstacle_radii`      | (N,)   | obstacle radii                         | 0                  | half the arena    |
    | `obstacle_mask`       | (N,)   | 1 for a real obstacle, 0 for padding   | 0                  | 1                 |

    ``V`` is the arena diagonal divided by ``dt`` (crossing the arena in one step): no speed is higher.
    Static public facts for planners: ``env.unwrapped.bounds``, ``dt``, ``robot_radius``, ``robot_speed``,
    ``goal_radius``, ``robot`` and ``robot_limits`` (``pathplan_env.facts.EnvFacts``), ``robot_step_length`` and ``arena``
    (``pathplan_env.arena.Arena``: the box where the robot's disc fits). ``env.unwrapped.world`` is the
    simulator's state, read by privileged oracles only.

    ## Rewards
    The sum of the components reported in ``info["rewards"]`` (``pathplan_env.rewards``):
    - ``progress``: ``reward_progress * (d_before - d_after) / d_start``, with ``d`` the distance to the
      goal; over a successful episode the progress rewards sum to ``reward_progress``.
    - ``goal``: ``reward_goal`` (default 1.0) on reaching the goal.
    - ``collision``: ``reward_collision`` (default -1.0) on touching an obstacle.
    - ``time``: ``reward_time`` (default -0.005) every step.
    - ``proximity``: ``reward_proximity * max(0, 1 - min_clearance / proximity_distance)``, a
      discomfort penalty near obstacles as in CrowdNav, for shaping RL training. Off by default
      (``reward_proximity=0``), so the default reward is the four terms above.

    ## Starting State
    The robot rests at the scenario's start. Presets: ``"paper-case-1"``, ``"paper-case-2"``,
    ``"paper-case-3"`` (the paper's Table 1 obstacle centres; see ``pathplan_env.scenarios.presets`` and
    ``docs/paper_assumptions.md`` for the assumed start, goal, radii and arena) and ``"random"``
    (``n_obstacles`` non-overlapping obstacles, start and goal at least 6 m apart, all drawn from
    ``np_random``), ``"crowdnav-circle-crossing"`` and ``"crowdnav-square-crossing"`` (CrowdNav's
    protocol: 5 ORCA humans, robot invisible; the ``-visible`` forms show them the robot).
    Obstacles that rest in the scenario get directions from ``np_random`` once ``delta_d`` (or a
    preset's own Δd) makes them move.

    ## Episode End
    - Termination: the robot reaches the goal (``info["is_success"]``), or touches an obstacle
      (``info["collision"]``); whichever happens first within the step decides. The robot stops
      there, and the final step is read at its end like every other: the robot rests at the goal
      (or where it touched), ``path_length`` counts the distance to that point, ``time`` whole steps.
    - Truncation: the registration's time limit, ``max_episode_steps=200`` (20 s at dt = 0.1 s), or
      the scenario's own ``time_limit`` if it is shorter (the CrowdNav presets: 25 s, 100 steps),
      counted in whole steps (``ceil(time_limit / dt)``), so a long limit never ends a step late.
    - A ``step`` after the episode terminated is undefined in Gymnasium; here it warns once an
      episode (the world carries on: the robot may collide again and pay for it) until ``reset``.

    ## Info
    The same keys after ``reset`` and every ``step``: ``is_success``, ``collision``, ``cost`` (1.0 on a
    step with contact, as Safety-Gymnasium reports constraint costs), ``min_clearance`` (smallest
    surface gap to any obstacle during the step up to where the robot stopped, m: 0 on contact; the
    arena diagonal with no obstacles, so that every field is finite), ``path_length`` (m flown so
    far), ``time`` (s), ``distance_to_goal``, ``waypoint`` (the ``(x, y)`` the robot headed for; ``None``
    after a reset) and ``rewards`` (all 0.0 after a reset).

    ## Arguments
    ```python
    gym.make("DynamicObstacle-v0", scenario="random", delta_d=None, n_obstacles=None, max_obstacles=None,
             robot_visible=None, observation="state", observation_params=None, action=None, robot="holonomic",
             robot_params=None, render_mode=None)
    ```
    - ``scenario``: a preset name, a ``pathplan_env.Scenario`` or its dict form
      (``pathplan_env.scenarios.files.load_scenario`` reads one from a JSON or YAML file).
    - ``delta_d``: obstacle displacement per step in radii, applied to every obstacle (directions
      kept; resting obstacles get random ones); ``0`` freezes the obstacles. ``None`` (the default)
      keeps the scenario's own speeds: Δd 0.25 for ``"random"`` and the paper's cases, 1 m/s for
      CrowdNav's humans, a hand-built ``Scenario``'s own velocities.
    - ``n_obstacles``: obstacle count of the ``"random"`` preset (default 8; at most 100: its arena
      grows with the count, and past 100 it outgrows what the robot can cross in the 200-step time
      limit) and of the CrowdNav presets (default 5); a ``ValueError`` for a scene with its own
      obstacles (the paper's cases, a ``Scenario``).
    - ``max_obstacles``: padding size ``N`` of the obstacle arrays; default ``max(16, obstacles)``.
    - ``robot_visible``: overrides the scenario's: whether goal-directed obstacles see the robot.
    - ``reward_progress``, ``reward_goal``, ``reward_collision``, ``reward_time``, ``reward_proximity``:
      reward weights; ``proximity_distance`` (m, default 0.5) is the surface gap below which the
      proximity penalty starts.
    - ``observation``, ``action``: the observation and action types by name
      (``pathplan_env.sensors.observations.OBSERVATION_TYPES``, ``pathplan_env.robots.actions.ACTION_TYPES``): also
      ``"lidar"`` (a range scan: ``pathplan_env.sensors.lidar``) and ``"visible-state"`` (``"state"`` with only
      the obstacles in sight: ``pathplan_env.sensors.visible_state``), with their ``observation_params``.
    - ``render_mode``: ``"human"`` (a pygame window) or ``"rgb_array"`` (works with no display).

    ``reset(options={"scenario": ..., "delta_d": ..., "n_obstacles": ...})`` reconfigures the env from
    that episode on (the arena bounds must stay the same: they define the observation space).

    ## Version History
    - v0: initial release; goal-directed obstacle behaviours and the CrowdNav presets added without
      changing any episode of the existing presets (tested by a digest). Observation and action
      types (``observation=``, ``action=``) added, and ``delta_d`` defaults to each scenario's own
      speeds (CrowdNav's humans at their 1 m/s, no longer Δd 0.25), with every episode of
      ``"random"`` and the paper's cases unchanged (tested by a digest).
    """

    metadata = {"render_modes": ["human", "rgb_array"], "render_fps": 10}

    def __init__(
        self,
        scenario: str | Scenario = "random",
        delta_d: float | None = None,
        n_obstacles: int | None = None,
        max_obstacles: int | None = None,
        robot_visible: bool | None = None,
        reward_progress: float = 1.0,
        reward_goal: float = 1.0,
        reward_collision: float = -1.0,
        reward_time: float = -0.005,
        reward_proximity: float = 0.0,
        proximity_distance: float = 0.5,
        observation: str = "state",
        observation_params: dict | None = None,
        action: str | None = None,
        robot: str = "holonomic",
        robot_params: dict | None = None,
        render_mode: str | None = None,
    ):
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"render_mode must be one of {self.metadata['render_modes']} or None, got {render_mode!r}")
        self.render_mode = render_mode
        self._scenario_spec = scenario
        self._delta_d = check_delta_d(delta_d)
        self._n_obstacles = check_n_obstacles(n_obstacles)
        if robot_visible is not None and not isinstance(robot_visible, (bool, np.bool_)):
            raise ValueError(f"robot_visible must be True, False or None, got {robot_visible!r}")
        self._robot_visible = None if robot_visible is None else bool(robot_visible)
        #: The reward terms' weights (``pathplan_env.rewards.RewardWeights``, validated).
        self.reward_weights = RewardWeights(reward_progress, reward_goal, reward_collision, reward_time, reward_proximity, proximity_distance)
        # Build one scenario now so that bad input fails when the env is made, and to fix the spaces.
        self.scenario: Scenario = self._make_scenario(scenario, np.random.default_rng(0), self._n_obstacles, self._delta_d)
        scenario_substeps(self.scenario)
        self.bounds = self.scenario.bounds
        if max_obstacles is None:
            max_obstacles = max(16, self._n_obstacles or 0, self.scenario.n_obstacles)
        if check_count(max_obstacles, "max_obstacles") < self.scenario.n_obstacles:
            raise ValueError(f"max_obstacles must be an integer >= the scenario's {self.scenario.n_obstacles} obstacles, got {max_obstacles!r}")
        self.max_obstacles = int(max_obstacles)
        #: The arena's bounds, the box where the robot's disc fits, and the waypoint <-> action mapping.
        self.arena = Arena.of(self.scenario)
        self.observation_type = make_observation_type(observation, self.arena, self.scenario.dt, self.max_obstacles, observation_params,
                                                      static_segments=len(self.scenario.static_segments))  # fmt: skip
        self.action_type = make_action_type(action, self.arena, robot, robot_params)
        self.action_type.check(self.scenario)
        self.robot = robot
        self.action_space = self.action_type.space()
        # bound once: step calls them (a robot that turns adds its heading and turn rate to the observation)
        self.observation_space, self._observe = with_robot_entries(self.observation_type, self.action_type, self.scenario.dt)
        self._advance = self.action_type.advance
        self._world: World | None = None
        self._fused: FusedStep | None = None  # the episode's step in one compiled call, where its parts allow (fused_step.py)
        self._moves: list[tuple] | None = None
        self._renderer = None
        self.trail: list[tuple[float, float]] = []
        self.waypoint: tuple[float, float] | None = None
        #: Drawn by render() when set: a planned path (points, e.g. an agent's ``last_plan``) and a caption.
        self.planned_path = None
        self.caption: str | None = None

    # -- static public facts (what planners may read besides the observation) -------------------
    dt = property(lambda self: self.scenario.dt, doc="The control period (s): one step advances the world by it.")
    robot_radius = property(lambda self: self.scenario.robot_radius, doc="The robot's radius (m).")
    robot_speed = property(lambda self: self.scenario.robot_speed, doc="The robot's top speed (m/s).")
    robot_limits = property(lambda self: self.action_type.limits_for(self.scenario), doc="The robot's limits beyond its top speed (None: none).")
    goal_radius = property(lambda self: self.scenario.goal_radius, doc="The goal is reached within this distance (m).")
    proximity_distance = property(lambda self: self.reward_weights.proximity_distance, doc="Where the proximity term starts (m).")

    @property
    def delta_d(self) -> float | None:
        """The Δd this env applies to its scenarios (``None``: each scenario's own speeds)."""
        return self._delta_d

    @property
    def robot_step_length(self) -> float:
        """The farthest the robot moves in one step (m): ``robot_speed * dt``."""
        return self.scenario.robot_speed * self.scenario.dt

    @property
    def world(self) -> World | None:
        """The episode's simulator state (``None`` before the first reset). Policies must not read it:
        only privileged oracles do (``agents.oracles.clairvoyant``), and say so in their name."""
        return self._world

    # -- action mapping ------------------------------------------------------------------------
    def action_to_waypoint(self, action) -> np.ndarray:
        """Map an action in [-1, 1]^2 (clipped) to a waypoint in the arena (float64 metres)."""
        return self.arena.action_to_waypoint(action)

    def waypoint_to_action(self, waypoint) -> np.ndarray:
        """Map waypoints (..., 2) in the arena to actions in [-1, 1]^2 (float32, clipped)."""
        return self.arena.waypoint_to_action(waypoint)

    # -- Gymnasium API -------------------------------------------------------------------------
    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None):
        spec, delta_d, n_obstacles = self._scenario_spec, self._delta_d, self._n_obstacles
        if options:  # validated in full before anything changes: a rejected reset leaves the env as it was
            spec, delta_d, n_obstacles = self._parse_options(options)
            self._check_fits(self._make_scenario(spec, np.random.default_rng(0), n_obstacles, delta_d), physics=True)
        generator = self._np_random  # a seed replaces it; without one the draws below advance it
        saved = (generator, self._np_random_seed, generator.bit_generator.state if seed is None and generator is not None else None)
        super().reset(seed=seed)
        try:  # a draw can still fail (a random scene that does not fit): then the generator is put back
            scenario = self._make_scenario(spec, self.np_random, n_obstacles, delta_d)
            self._check_fits(scenario)
            self._fused = None  # (it holds the addresses of the old world, which the new one may empty)
            world = World(scenario, recycle=self._world)  # checks the substeps before it touches the old world
        except ValueError:
            self._np_random, self._np_random_seed = saved[0], saved[1]
            if saved[2] is not None:
                generator.bit_generator.state = saved[2]
            raise
        self._scenario_spec, self._delta_d, self._n_obstacles = spec, delta_d, n_obstacles
        self.scenario, self._world = scenario, world
        if self.arena.robot_radius != scenario.robot_radius:  # the bounds are checked equal above
            self.arena = Arena.of(scenario)
        self._goal_xy = scenario.goal
        self._start_distance = max(float(np.hypot(self._goal_xy[0] - scenario.start[0], self._goal_xy[1] - scenario.start[1])), 1e-9)
        self._distance = self._start_distance
        self._path_length = 0.0
        self.action_type.reset(world, self.arena)
        # a stream of its own, spawned from the episode's seed: a noisy sensor never shifts the scenes
        self.observation_type.reset(world, self.np_random.spawn(1)[0] if self.observation_type.draws else None)
        self.waypoint = None
        self.trail = [scenario.start]
        self._moves = []  # what a copy of this env replays
        self._steps, self._ended, self._warned_after_end = 0, False, False
        # the scenario's time limit in whole steps: a running sum of dt drifts over long episodes
        limit = scenario.time_limit
        self._step_limit = None if limit is None else max(1, math.ceil(limit / scenario.dt - 1e-9))
        if self.render_mode == "human":
            self.render()
        self._fused = FusedStep.of(self, DynamicObstacleEnv)
        clearance = world.clearance()
        rewards = dict.fromkeys(self._rewards(False, False, self._distance, clearance), 0.0)  # the step's terms, zero
        return self._observe(world), self._info(False, False, clearance, rewards)

    def step(self, action):
        fused = self._fused
        if fused is not None:
            result = fused.step(action)  # (a method: calling an instance's __call__ cost a step 70 ns more)
            if result is not None:
                return result
        world = self._world
        if world is None:
            raise RuntimeError("call reset() before step()")
        if self._ended and not self._warned_after_end:
            gym.logger.warn("step() called after the episode terminated (the goal or a collision); the world "
                            "carries on and a collision is paid again: call reset()")
            self._warned_after_end = True
        # act and simulate (the action validated first): the robot stops where the episode ends (the
        # goal, or the first contact); the step's quantities are read at its end: the robot resting there
        length, goal_fraction, min_gap, contact_fraction, self.waypoint, move = self._advance(action, world)
        self._moves.append(move)
        collision = contact_fraction <= 1.0
        success = goal_fraction <= 1.0 and not collision
        self._path_length += length * (goal_fraction if success else contact_fraction if collision else 1.0)
        (rx, ry), (gx, gy) = world.robot_xy, self._goal_xy
        distance = 0.0 if success else math.hypot(rx - gx, ry - gy)
        rewards = self._rewards(success, collision, distance, min_gap)
        self._distance = distance
        terminated = success or collision
        self._ended = self._ended or terminated
        if terminated:
            self._fused = None  # (the next step warns)
        # the scenario's own time limit (CrowdNav's 25 s); the registration's step limit is TimeLimit's
        self._steps += 1
        truncated = self._step_limit is not None and not terminated and self._steps >= self._step_limit
        info = self._info(success, collision, min_gap, rewards)
        if self.render_mode is not None:
            self.trail.append(world.robot_xy)
            if self.render_mode == "human":
                self.render()
        reward = -0.0  # rewards.total(rewards), inlined on the hot path: the terms added left to right
        for term in rewards.values():
            reward += term
        return self._observe(world), reward, terminated, truncated, info

    def render(self):
        if self.render_mode is None:
            gym.logger.warn("render() was called without a render_mode; pass render_mode='rgb_array' or 'human' to gym.make")
            return None
        if self._world is None:
            raise RuntimeError("call reset() before render()")
        if self._renderer is None:
            from pathplan_env.rendering import Renderer, view_of  # pygame is imported lazily, only when rendering

            self._renderer = Renderer(view_of(self.scenario), self.render_mode, self.metadata["render_fps"])
        world = self._world
        return self._renderer.draw(scenario=self.scenario, obstacle_state=world.obstacle_state, radii=world.radii,
                                   robot_position=world.robot_position, trail=self.trail, waypoint=self.waypoint,
                                   plan=self.planned_path, caption=self.caption,
                                   heading=world.robot_heading if self.action_type.turns else None,
                                   **self.observation_type.overlay(world))  # fmt: skip

    def close(self):
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None

    # -- the step's reward and info ------------------------------------------------------------
    def _rewards(self, success: bool, collision: bool, distance: float, min_gap: float) -> dict[str, float]:
        """The step's reward terms (``info["rewards"]``; the reward is their total): a subclass that
        adds a term adds it here. ``distance`` is the robot's new distance to the goal."""
        return reward_terms(self.reward_weights, self._distance, distance, self._start_distance, success, collision, min_gap)

    def _info(self, success: bool, collision: bool, min_clearance: float, rewards: dict[str, float]) -> dict[str, Any]:
        """The info of a reset (nothing happened yet) or of a step."""
        return {
            "is_success": success,
            "collision": collision,
            "cost": 1.0 if collision else 0.0,
            "min_clearance": min_clearance,
            "path_length": self._path_length,
            "time": self._world.time,
            "distance_to_goal": self._distance,
            "waypoint": self.waypoint,
            "rewards": rewards,
        }

    # -- helpers -------------------------------------------------------------------------------
    def _make_scenario(self, spec, rng, n_obstacles, delta_d) -> Scenario:
        scenario = make_scenario(spec, rng, n_obstacles, delta_d)
        if self._robot_visible is not None and scenario.robot_visible != self._robot_visible:
            scenario = dataclasses.replace(scenario, robot_visible=self._robot_visible)
        return scenario

    def _parse_options(self, options: dict[str, Any]):
        unknown = set(options) - {"scenario", "delta_d", "n_obstacles"}
        if unknown:
            raise ValueError(f"reset options: unknown keys {sorted(unknown)}; known: scenario, delta_d, n_obstacles")
        spec = options.get("scenario", self._scenario_spec)
        delta_d = check_delta_d(options["delta_d"]) if "delta_d" in options else self._delta_d
        n_obstacles = check_n_obstacles(options["n_obstacles"]) if "n_obstacles" in options else self._n_obstacles
        return spec, delta_d, n_obstacles

    def _check_fits(self, scenario: Scenario, physics: bool = False) -> None:
        """A scenario this env can run: its arena (which fixes the observation space), its obstacle
        count within ``max_obstacles``, and (``physics``) within the substep bound."""
        if scenario.bounds != self.bounds:
            raise ValueError(
                f"scenario bounds {scenario.bounds} differ from this env's arena {self.bounds}; "
                "the arena fixes the observation space, so make a new env for another arena"
            )
        if scenario.n_obstacles > self.max_obstacles:
            raise ValueError(f"scenario has {scenario.n_obstacles} obstacles, more than max_obstacles={self.max_obstacles}")
        self.observation_type.check_fits(scenario)  # e.g. its walls within the rows the observation reserved
        if physics:
            scenario_substeps(scenario)  # (World checks it again when built)
            self.action_type.check(scenario)  # (a robot's limits that the scenario's defaults break)

    def __getstate__(self):
        # The world travels as its scenario and the robot's moves since reset, and is replayed on
        # arrival: pymunk's own pickle drops Chipmunk's cache of ongoing contacts, so a copy made
        # while two bodies touched used to drift from the original.
        state = self.__dict__.copy()
        state["_renderer"] = None  # a pygame window does not pickle; it reopens on the next render()
        state["_world"] = None
        state["_fused"] = None  # (it holds the world's addresses)
        return state

    def __setstate__(self, state):
        self._fused = None  # (a pickle of 0.2.0 and earlier has none)
        self.__dict__.update(state)
        if self._moves is not None:
            world = World(self.scenario)
            self.action_type.reset(world, self.arena)
            for move in self._moves:
                self.action_type.replay(world, move)
            self._world = world
            if not self._ended:
                self._fused = FusedStep.of(self, DynamicObstacleEnv)
