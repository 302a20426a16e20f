"""``DynamicObstacleEnv.step`` for its common case in one compiled call and a few lines of Python.

The env's step was its world's step and as much again around it: the action's move, the
observation's row and the world's step were three calls across the Python/compiled boundary,
each paying for its arguments and results, and the step passed its values through a dozen small
methods (``scripts/bench_crowds.py --env-split``). When an episode's parts are the plain ones (the
holonomic robot's waypoint action, the ``"state"`` observation without walls, a world whose step is
its compiled call alone, no rendering, the reward and info of :class:`DynamicObstacleEnv` itself),
:class:`FusedStep` does the same step with one compiled call (:func:`fused_step`: the move, the
world's step, the observation's row) and the env's bookkeeping inlined, operation for operation:
every observation, reward, flag and info is the one the general step returns, bit for bit (tested
side by side, ``tests/env/test_fused_step.py``). Anything else (another action's type or dtype, a
bad action, a step after the episode ended) takes the general step, which raises its errors.

The observation's arrays are views of a row of :class:`StateObservation`'s block that no later step
writes, as the general step's are: a policy may keep them.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from pathplan_env._entry_points import entry_point
from pathplan_env.arena import ArenaBox
from pathplan_env.robots.actions import WaypointAction
from pathplan_env.robots.holonomic import move_and_goal
from pathplan_env.sensors.observations import StateObservation, _observation_row, _plain_state
from pathplan_env.world import step_kernel
from pathplan_env.world.chipmunk import address_of, as_pointer, ffi

# the packed array's int64 header: the world's packed array (``World._address``), the observation
# block's address, a row's length (float32), the obstacle rows of the observation, the template's
# address; the float64 constants follow it: the arena's box (8), the robot's reach, the goal, its
# radius, the arena's diagonal, the reward weights the kernel reads
WORLD, BLOCK, ROW_SIZE, N_MAX, TEMPLATE = range(5)
HEADER = 5
BOX, REACH, GOAL_X, GOAL_Y, GOAL_RADIUS, DIAGONAL, W_GOAL, W_COLLISION, W_PROXIMITY, PROXIMITY_DISTANCE = 0, 8, 9, 10, 11, 12, 13, 14, 15, 16
CONSTANTS = 17

_NDARRAY, _FLOAT32, _FLOAT64 = np.ndarray, np.dtype(np.float32), np.dtype(np.float64)
_BLOCK_ROWS = StateObservation.BLOCK_ROWS
_hypot = math.hypot
_ENTRY_FLOAT32 = _ENTRY_FLOAT64 = None  # fused_step's entry points, compiled (or read from numba's cache) by the first FusedStep


@numba.njit(cache=True)
def fused_step(address, action, x0, y0, row):
    """One step of the env whose packed array (:class:`FusedStep`) is at ``address``, for ``action`` (a
    float32 or float64 array of one dimension) from the robot at ``(x0, y0)``, its observation
    written in the block's row ``row``:
    ``WaypointAction.act``'s move (``move_and_goal``), ``World.step``'s compiled call
    (``step_kernel.world_step``), ``StateObservation.observe``'s row (``_observation_row``) and the
    step's facts and reward terms that need no distance to the goal (``DynamicObstacleEnv.step``,
    ``rewards.reward_terms``), in the general step's order and arithmetic. Returns ``(finite,
    waypoint, move, (x, y), (vx, vy), min_gap, success, collision, flown, goal, hit,
    proximity)``: ``waypoint`` and ``move`` the tuples the env keeps, ``flown`` the share of the move
    flown, the last three reward terms; with ``finite`` False (a NaN or infinite action, or not two of
    them) nothing moved and nothing was written."""
    ints = numba.carray(as_pointer(address), HEADER, np.int64)
    c = numba.carray(as_pointer(address + 8 * HEADER), CONSTANTS, np.float64)
    box = ArenaBox(c[BOX], c[BOX + 1], c[BOX + 2], c[BOX + 3], c[BOX + 4], c[BOX + 5], c[BOX + 6], c[BOX + 7])
    if action.shape[0] != 2:
        return False, (0.0, 0.0), (0.0, 0.0, 0.0), (x0, y0), (0.0, 0.0), 0.0, False, False, 0.0, 0.0, 0.0, 0.0
    finite, wx, wy, dx, dy, goal_fraction = move_and_goal(action, box, x0, y0, c[REACH], c[GOAL_X], c[GOAL_Y], c[GOAL_RADIUS])
    if not finite:
        return False, (wx, wy), (dx, dy, goal_fraction), (x0, y0), (0.0, 0.0), 0.0, False, False, 0.0, 0.0, 0.0, 0.0
    world = ints[WORLD]
    xy, velocity, min_gap, first_contact = step_kernel.world_step(world, x0, y0, dx, dy, goal_fraction, False, c[DIAGONAL])
    # the observation of the world as the step left it (StateObservation.observe): its obstacles' state is
    # the first 4 m floats of the world's packed float64 array
    header = numba.carray(as_pointer(world), step_kernel.INT_HEADER, np.int64)
    m = header[step_kernel.COUNT]
    state = numba.carray(as_pointer(header[step_kernel.FLOAT_ARRAY]), (m, 4), np.float64)
    size = ints[ROW_SIZE]
    block_row = numba.carray(as_pointer(ints[BLOCK] + 4 * size * row), size, np.float32)
    template = numba.carray(as_pointer(ints[TEMPLATE]), size, np.float32)
    _observation_row(block_row, template, (xy[0], xy[1], velocity[0], velocity[1]), state, ints[N_MAX])
    # DynamicObstacleEnv.step's facts, and reward_terms' terms that need no distance
    collision = first_contact <= 1.0
    success = goal_fraction <= 1.0 and not collision
    flown = goal_fraction if success else first_contact if collision else 1.0
    goal = c[W_GOAL] if success else 0.0
    hit = c[W_COLLISION] if collision else 0.0
    proximity = 0.0
    if c[W_PROXIMITY] != 0.0:  # (Python's max(0.0, g): 0.0 unless g > 0.0)
        g = 1.0 - min_gap / c[PROXIMITY_DISTANCE]
        proximity = c[W_PROXIMITY] * (g if g > 0.0 else 0.0)
    return True, (wx, wy), (dx, dy, goal_fraction), xy, velocity, min_gap, success, collision, flown, goal, hit, proximity


@numba.njit(cache=True)
def _data_address(array):
    """Where ``array``'s data starts (cffi's ``from_buffer`` cost ~10 µs on a block's first use)."""
    return np.int64(array.ctypes.data)


def _compile() -> None:
    global _ENTRY_FLOAT32, _ENTRY_FLOAT64
    if _ENTRY_FLOAT64 is None:
        # the action typed unaligned, of any strides and shape[0]: no array of one dimension is read amiss
        t = numba.types
        action = lambda dtype: t.Array(dtype, 1, "A", aligned=False)
        _ENTRY_FLOAT32 = entry_point(fused_step, (t.int64, action(t.float32), t.float64, t.float64, t.int64))
        _ENTRY_FLOAT64 = entry_point(fused_step, (t.int64, action(t.float64), t.float64, t.float64, t.int64))


class FusedStep:
    """The step of one episode of ``env`` (a ``DynamicObstacleEnv`` just reset), made by :meth:`of`
    where the episode's parts allow it; the env calls its :meth:`step` first and takes its general
    step when that returns ``None``."""

    @classmethod
    def of(cls, env, base: type) -> FusedStep | None:
        """The episode's fused step, or ``None`` where the general step must run: another action or
        observation type, walls, a world stepped partly in Python (steering outside the compiled
        call, humans who see the robot), rendering, or rewards or info other than those of ``base``
        (``DynamicObstacleEnv``, whose step this one inlines: a subclass may add reward terms)."""
        world, observation = env._world, env.observation_type
        kind = type(env)
        plain = (
            type(env.action_type) is WaypointAction
            and type(observation) is StateObservation
            and not observation.max_static_segments
            and not observation._carried
            and env._observe == observation.observe
            and env._advance == env.action_type.advance
            and world._plain
            and _plain_state(world.obstacle_state)
            and env.render_mode is None
            and kind._rewards is base._rewards
            and kind._info is base._info
        )
        return cls(env) if plain else None

    def __init__(self, env):
        _compile()
        self.env, self.world, self.observation = env, env._world, env.observation_type
        world, scenario, observation = self.world, env.scenario, self.observation
        self._weights = w = env.reward_weights
        # (the two parts written whole: a reset paid ~1 µs for each element written into a numpy array)
        packed = np.empty(HEADER + CONSTANTS, np.int64)
        packed[:HEADER] = world._address, 0, observation.layout.size, observation.max_obstacles, address_of(ffi.from_buffer(observation._template))
        packed[HEADER:].view(np.float64)[:] = (*env.arena.box, scenario.robot_speed * scenario.dt, *scenario.goal, scenario.goal_radius,
                                               world._diagonal, w.goal, w.collision, w.proximity, w.proximity_distance)  # fmt: skip
        self._packed, self._address = packed, address_of(ffi.from_buffer(packed))
        self._block = None  # the observation block whose address the header holds
        self._goal, self._start_distance = env._goal_xy, env._start_distance
        limit = env._step_limit
        self._limit = math.inf if limit is None else limit

    def _set_block(self, block) -> None:
        self._block = block
        self._packed[BLOCK] = _data_address(block)

    def step(self, action):
        """The step's ``(observation, reward, terminated, truncated, info)``, or ``None`` for an action
        this step does not take (the general step then takes it, and raises its errors)."""
        if type(action) is not _NDARRAY or action.ndim != 1:
            return None
        dtype = action.dtype
        if dtype is _FLOAT32:
            entry = _ENTRY_FLOAT32
        elif dtype is _FLOAT64:
            entry = _ENTRY_FLOAT64
        else:
            return None
        env, world, observation = self.env, self.world, self.observation
        w = self._weights
        if env.reward_weights is not w or env.render_mode is not None:  # (set since the reset: the general step reads them)
            return None
        i = observation._rows_used
        if i == _BLOCK_ROWS:
            observation._new_block()
            i = observation._rows_used = 0
        if observation._block is not self._block:
            self._set_block(observation._block)
        x0, y0 = world.robot_xy
        finite, waypoint, move, xy, velocity, min_gap, success, collision, flown, goal, hit, proximity = entry(self._address, action, x0, y0, i)
        if not finite:
            return None  # (the general step raises the ValueError)
        observation._rows_used = i + 1
        world.robot_xy, world.robot_velocity_xy = xy, velocity
        world.time = now = world.time + world._dt  # (World.step's `self.time += self._dt`)
        # DynamicObstacleEnv.step from here, operation for operation (the distances: Python's hypot)
        env.waypoint = waypoint
        env._moves.append(move)
        dx, dy, _ = move
        env._path_length = path_length = env._path_length + _hypot(dx, dy) * flown
        (rx, ry), (gx, gy) = xy, self._goal
        distance = 0.0 if success else _hypot(rx - gx, ry - gy)
        progress = w.progress * (env._distance - distance) / self._start_distance
        env._distance = distance
        terminated = success or collision
        if terminated:
            env._ended = True
            env._fused = None  # (a step after the end warns: the general step's)
        env._steps = steps = env._steps + 1
        truncated = not terminated and steps >= self._limit
        time = w.time
        info = {
            "is_success": success,
            "collision": collision,
            "cost": 1.0 if collision else 0.0,
            "min_clearance": min_gap,
            "path_length": path_length,
            "time": now,
            "distance_to_goal": distance,
            "waypoint": waypoint,
            "rewards": {"progress": progress, "goal": goal, "collision": hit, "time": time, "proximity": proximity},
        }
        position, velocity, goal_xy, positions, velocities, radii, mask = observation._entries
        obs = {
            "robot_position": position[i],
            "robot_velocity": velocity[i],
            "goal": goal_xy[i],
            "obstacle_positions": positions[i],
            "obstacle_velocities": velocities[i],
            "obstacle_radii": radii[i],
            "obstacle_mask": mask[i],
        }
        return obs, -0.0 + progress + goal + hit + time + proximity, terminated, truncated, info  # (rewards.total: left to right)


__all__ = ["FusedStep", "fused_step"]
