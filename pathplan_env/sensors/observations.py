"""Observation types: what the policy sees of the world, one small object each, chosen by name.

An observation type has a ``space()``, a per-episode ``reset(world, rng)`` and ``observe(world)``;
the env builds one from ``observation="<name>"`` (:data:`OBSERVATION_TYPES`) and never lays out an
observation itself, so a new type (a lidar, a visible-state view) touches no ``step``.

``"state"`` (:class:`StateObservation`) is the env's ``Dict`` of the world's exact state; the sensing
types register themselves from their own modules (``"lidar"``: ``pathplan_env.sensors.lidar``,
``"visible-state"``: ``pathplan_env.sensors.visible_state``) with :func:`register_observation_type`. A type with
:attr:`ObservationType.parameters` takes them from ``observation_params`` (validated when the env is made).
"""

from __future__ import annotations

from itertools import pairwise
from typing import Any, NamedTuple

import numba
import numpy as np
from gymnasium import spaces

from pathplan_env._entry_points import entry_point
from pathplan_env.arena import Arena


class ObservationType:
    """One way of observing the world.

    :param arena: the arena (fixed for the env's life: it fixes the space).
    :param dt: the control period (s).
    :param max_obstacles: the most obstacles an episode may have.
    """

    #: The name ``observation=`` takes (:data:`OBSERVATION_TYPES`).
    name = ""
    #: Whether ``reset`` needs a random stream (a noisy sensor does): spawning one costs ~40 µs a reset.
    draws = False
    #: The ``observation_params`` keys the type takes (its ``__init__`` then takes them as ``params``).
    parameters: tuple[str, ...] = ()

    def __init__(self, arena: Arena, dt: float, max_obstacles: int):
        self.arena, self.dt, self.max_obstacles = arena, float(dt), int(max_obstacles)

    def space(self) -> spaces.Space:
        """The observation space (built once, when the env is made)."""
        raise NotImplementedError

    def reset(self, world, rng: np.random.Generator | None) -> None:
        """Called on every reset, after the episode's world is built and before its first observation
        (``rng``: for types with ``draws``, e.g. a noisy sensor, a stream of the type's own spawned
        from the env's seed, so drawing from it never changes the episode; ``None`` for the others)."""

    def observe(self, world) -> Any:
        """The observation of the world as it is now (an element of :meth:`space`)."""
        raise NotImplementedError

    def overlay(self, world) -> dict[str, np.ndarray]:
        """What the renderer draws of this sensor after :meth:`observe`: ``beams`` ((B, 2) points where
        a scan's beams end) and ``hidden`` ((N,) bool: obstacles the last observation left out, greyed).
        None by default."""
        return {}

    def check_fits(self, scenario) -> None:
        """Raise ``ValueError`` if the env's space cannot show ``scenario`` (called before a reset
        changes anything); every scenario fits by default."""


class StateLayout(NamedTuple):
    """Where each entry of the state observation starts in its one float32 block, and the block's
    size: robot position (2), robot velocity (2), goal (2), obstacle positions (N, 2), obstacle
    velocities (N, 2), radii (N), mask (N). Built by :func:`state_layout`, the one place the offsets
    are written; the compiled kernels read it there, the views as :meth:`slices`."""

    robot_position: int
    robot_velocity: int
    goal: int
    obstacle_positions: int
    obstacle_velocities: int
    obstacle_radii: int
    obstacle_mask: int
    size: int

    def slices(self) -> StateSlices:
        """Each entry's slice of the block (from its offset to the next)."""
        return StateSlices(*(slice(start, stop) for start, stop in pairwise(self)))


class StateSlices(NamedTuple):
    """:class:`StateLayout`'s entries as slices of the block."""

    robot_position: slice
    robot_velocity: slice
    goal: slice
    obstacle_positions: slice
    obstacle_velocities: slice
    obstacle_radii: slice
    obstacle_mask: slice


@numba.njit(cache=True)
def state_layout(n_max: int) -> StateLayout:
    """The state observation's layout with room for ``n_max`` obstacles (compiled, so that the
    kernels below call it too)."""
    robot_position = 0
    robot_velocity = robot_position + 2
    goal = robot_velocity + 2
    obstacle_positions = goal + 2
    obstacle_velocities = obstacle_positions + 2 * n_max
    obstacle_radii = obstacle_velocities + 2 * n_max
    obstacle_mask = obstacle_radii + n_max
    size = obstacle_mask + n_max
    return StateLayout(robot_position, robot_velocity, goal, obstacle_positions, obstacle_velocities, obstacle_radii, obstacle_mask, size)


class StateObservation(ObservationType):
    """The world's exact state as a ``Dict`` in the world frame (metres, m/s), every entry float32 with
    finite bounds; rows past the episode's obstacles are padding (zeros at the arena's lower corner,
    mask 0). The table is the env's docstring's.

    Every observation is one float32 row (:class:`StateLayout`) of a block of :data:`BLOCK_ROWS`,
    copied from the episode's template and filled in by one compiled call; the entries are views of it.
    """

    name = "state"
    #: The fewest rows of ``static_segments`` an env whose scenario has walls or polygons reserves
    #: (:func:`static_segment_capacity`): room for a family's varying count (``cluttered-room``: up
    #: to 6 boxes, 24 edges) from the first scene's.
    MIN_STATIC_SEGMENTS = 64
    #: Observations allocated at once: each is a row of a block, its entries views of that row taken
    #: by index from views of the whole block made once (a slice and a reshape per entry were a
    #: fifth of a unicycle's step). A row is never written twice; a used-up block stays alive as
    #: long as observations hold its rows.
    BLOCK_ROWS = 256
    #: The last ``obstacle_state`` seen that :data:`_ROW` may take (``None``: none yet).
    _state_checked = None
    #: The arena whose lower corner ``_low`` holds; the read-only static segments and the arena the static
    #: entries' rows (``_static``, ``_static_mask``) were last written from (``None``: written again).
    _low_of = _low = _static_of = _static_arena = None

    def __init__(self, arena: Arena, dt: float, max_obstacles: int):
        super().__init__(arena, dt, max_obstacles)
        self.layout = StateLayout(*state_layout(self.max_obstacles))
        self._slices = self.layout.slices()
        self._pairs = (self.max_obstacles, 2)
        self._carried: tuple[str, ...] = ()  # the robot's own scalar entries (carry_robot_scalars)
        self._template = np.zeros(self.layout.size, np.float32)
        self._rows_used = self.BLOCK_ROWS  # no block yet: the first observation allocates one
        self.reserve_static_segments(0)

    def carry_robot_scalars(self, names: tuple[str, ...]) -> None:
        """Carry the robot's own scalar entries (a turning robot's heading and turn rate: ``World``
        attributes of these names, each a ``(1,)`` float32 entry after the others) in each
        observation's row, written where the row is: a dict of their own merged into every
        observation cost a tenth of the unicycle's step. Called once, before the first observation."""
        self._carried = tuple(names)
        self._template = np.zeros(self.layout.size + len(self._carried), np.float32)  # (those columns are written every step)
        self._rows_used = self.BLOCK_ROWS

    def reserve_static_segments(self, count: int) -> None:
        """Show the scene's walls and polygons (``World.static_segments``) in ``count`` padded rows:
        the entries ``static_segments`` ``(count, 5)`` (``x0, y0, x1, y1, half_thickness``, m; a
        polygon's edges have half-thickness 0) and ``static_mask`` ``(count,)`` (1 for a real row).
        With ``count = 0`` (an env made with a scene without geometry) neither entry exists and the
        observation is the one it always was. Called before :meth:`space`."""
        if int(count) != count or count < 0:
            raise ValueError(f"max_static_segments must be an integer >= 0, got {count!r}")
        self.max_static_segments = int(count)
        self._static = np.zeros((self.max_static_segments, 5), np.float32)
        self._static_of = self._static_arena = None
        self._static_mask = np.zeros(self.max_static_segments, np.float32)

    def check_fits(self, scenario) -> None:
        count = len(scenario.static_segments)
        if self.max_static_segments and count > self.max_static_segments:
            raise ValueError(f"scenario has {count} static_segments (wall and polygon edges), more than the "
                             f"{self.max_static_segments} rows this env's observation reserved; make a new env for it")  # fmt: skip

    def space(self) -> spaces.Dict:
        xmin, ymin, xmax, ymax = self.arena.bounds
        low, high = np.array([xmin, ymin], np.float32), np.array([xmax, ymax], np.float32)
        vmax = np.float32(self.arena.diagonal / self.dt)  # crossing the arena in one step: no speed is higher
        n = self.max_obstacles
        point = spaces.Box(low, high, dtype=np.float32)
        return spaces.Dict(
            {
                "robot_position": point,
                "robot_velocity": spaces.Box(-vmax, vmax, shape=(2,), dtype=np.float32),
                "goal": point,
                "obstacle_positions": spaces.Box(np.tile(low, (n, 1)), np.tile(high, (n, 1)), dtype=np.float32),
                "obstacle_velocities": spaces.Box(-vmax, vmax, shape=self._pairs, dtype=np.float32),
                "obstacle_radii": spaces.Box(0.0, min(xmax - xmin, ymax - ymin) / 2, shape=(n,), dtype=np.float32),
                "obstacle_mask": spaces.Box(0.0, 1.0, shape=(n,), dtype=np.float32),
            }
            | self._static_spaces()
        )

    def _static_spaces(self) -> dict[str, spaces.Box]:
        m = self.max_static_segments
        if m == 0:
            return {}
        xmin, ymin, xmax, ymax = self.arena.bounds
        low = np.tile(np.array([xmin, ymin, xmin, ymin, 0.0], np.float32), (m, 1))
        high = np.tile(np.array([xmax, ymax, xmax, ymax, self.arena.diagonal], np.float32), (m, 1))
        return {"static_segments": spaces.Box(low, high, dtype=np.float32), "static_mask": spaces.Box(0.0, 1.0, shape=(m,), dtype=np.float32)}

    def reset(self, world, rng: np.random.Generator | None) -> None:
        """The episode's template: its goal and radii, padding rows at the arena's lower corner."""
        _compile_row()
        gx, gy = world.scenario.goal
        arena = self.arena
        if self._low_of is not arena:  # (the arena is the env's for its life: its corner's array made once)
            self._low_of, self._low = arena, arena.low
        _fill_template(self._template, gx, gy, self._low, world.radii, self.max_obstacles)
        if self.max_static_segments:  # padding rows at the arena's lower corner, as the obstacles'
            segments = world.static_segments
            self.check_fits(world.scenario)
            # the rows of the last episode's segments are these when they are the same read-only array (a
            # family's episodes share theirs, wall_families._segments) in the same arena: not written again
            if segments is not self._static_of or self._static_arena is not arena:
                self._static[:] = np.concatenate([self._low, self._low, [0.0]])
                self._static[: len(segments)] = segments
                self._static_mask[:] = 0.0
                self._static_mask[: len(segments)] = 1.0
                frozen = not segments.flags.writeable  # (a scenario's: segments_of's, never written)
                self._static_of, self._static_arena = (segments, arena) if frozen else (None, None)

    def observe(self, world) -> dict[str, np.ndarray]:
        (x, y), (vx, vy) = world.robot_xy, world.robot_velocity_xy
        i = self._rows_used
        if i == self.BLOCK_ROWS:
            self._new_block()
            i = 0
        self._rows_used = i + 1
        carried = self._carried
        in_kernel = len(carried) == 2
        if in_kernel:  # (a unicycle's heading and turn rate written by the same call: setting them from Python cost a twelfth of its step)
            _observation_row_carrying(self._block, i, self._template, (x, y, vx, vy), world.obstacle_state, self.max_obstacles,
                                      (getattr(world, carried[0]), getattr(world, carried[1])))  # fmt: skip
        else:
            state = world.obstacle_state
            if state is not self._state_checked:  # (a World's is the same array all episode: checked once)
                self._state_checked = state if _ROW is not None and _plain_state(state) else None
            if state is self._state_checked:
                _ROW(self._block, i, self._template, (x, y, vx, vy), state, self.max_obstacles)
            else:
                _observation_row(self._block[i], self._template, (x, y, vx, vy), state, self.max_obstacles)
        # the row's seven views made here, per step: made ahead for a whole block they cost the same
        # (~0.1 µs each) but moved into the reset, where a short benchmark did not count them
        position, velocity, goal, positions, velocities, radii, mask = self._entries
        obs = {
            "robot_position": position[i],
            "robot_velocity": velocity[i],
            "goal": goal[i],
            "obstacle_positions": positions[i],
            "obstacle_velocities": velocities[i],
            "obstacle_radii": radii[i],
            "obstacle_mask": mask[i],
        }
        if self.max_static_segments:
            obs.update(self._static_entries())
        if carried:
            block = self._block
            for name, column, view in self._carried_entries:
                if not in_kernel:
                    block[i, column] = getattr(world, name)
                obs[name] = view[i]
        return obs

    def _new_block(self) -> None:
        """A block of :data:`BLOCK_ROWS` observations and each entry's view across it."""
        n, s, (m, _) = self.BLOCK_ROWS, self._slices, self._pairs
        size = self.layout.size
        self._block = block = np.empty((n, size + len(self._carried)), np.float32)
        self._entries = (block[:, s.robot_position], block[:, s.robot_velocity], block[:, s.goal],
                         block[:, s.obstacle_positions].reshape(n, m, 2), block[:, s.obstacle_velocities].reshape(n, m, 2),
                         block[:, s.obstacle_radii], block[:, s.obstacle_mask])  # fmt: skip
        self._carried_entries = tuple((name, size + j, block[:, size + j : size + j + 1]) for j, name in enumerate(self._carried))

    def __getstate__(self):
        state = self.__dict__.copy()  # a copy of the env starts a block of its own
        state.pop("_block", None)
        state.pop("_entries", None)
        state.pop("_carried_entries", None)
        state["_state_checked"] = None
        state["_rows_used"] = self.BLOCK_ROWS
        return state

    def _static_entries(self) -> dict[str, np.ndarray]:
        if not self.max_static_segments:
            return {}
        return {"static_segments": self._static.copy(), "static_mask": self._static_mask.copy()}  # copies: a policy may write to them


@numba.njit(cache=True)
def _fill_template(template, gx, gy, arena_low, radii, n_max):
    """The episode's observation template, in one compiled call instead of half a dozen numpy ones
    on a few rows."""
    at = state_layout(n_max)
    n = radii.shape[0]
    template[:] = 0.0
    template[at.goal], template[at.goal + 1] = gx, gy
    for i in range(n, n_max):  # padding rows sit at the arena's lower corner
        template[at.obstacle_positions + 2 * i] = arena_low[0]
        template[at.obstacle_positions + 2 * i + 1] = arena_low[1]
    for i in range(n):
        template[at.obstacle_radii + i] = radii[i]
        template[at.obstacle_mask + i] = 1.0


def _plain_state(state) -> bool:
    """Whether ``state`` is what :data:`_ROW` takes: an (N, 4) native float64 C-contiguous array."""
    return type(state) is np.ndarray and state.dtype is _FLOAT64 and state.ndim == 2 and state.flags.c_contiguous and state.flags.aligned


# _observation_row_at's entry point (pathplan_env._entry_points) for the block, a row, its template,
# the robot's four floats and a plain obstacle state, compiled by the first reset rather than at import
_FLOAT64 = np.dtype(np.float64)
_ROW = None


def _compile_row() -> None:
    global _ROW
    if _ROW is None:
        t = numba.types
        _ROW = entry_point(_observation_row_at, (t.float32[:, ::1], t.int64, t.float32[::1], t.UniTuple(t.float64, 4), t.float64[:, ::1], t.int64))


@numba.njit(cache=True)
def _observation_row(block, template, robot, obstacle_state, n_max):
    """``block`` (an observation's row) := the episode's template with the robot's ``(x, y, vx, vy)``
    and the obstacles' state written in (float32), in one compiled call instead of a copy and six
    numpy slice assignments."""
    x, y, vx, vy = robot
    at = state_layout(n_max)
    block[:] = template
    block[at.robot_position], block[at.robot_position + 1] = x, y
    block[at.robot_velocity], block[at.robot_velocity + 1] = vx, vy
    for i in range(obstacle_state.shape[0]):
        block[at.obstacle_positions + 2 * i] = obstacle_state[i, 0]
        block[at.obstacle_positions + 2 * i + 1] = obstacle_state[i, 1]
        block[at.obstacle_velocities + 2 * i] = obstacle_state[i, 2]
        block[at.obstacle_velocities + 2 * i + 1] = obstacle_state[i, 3]


@numba.njit(cache=True)
def _observation_row_at(block, i, template, robot, obstacle_state, n_max):
    """:func:`_observation_row` into ``block[i]`` (the row's view made here, not in Python)."""
    _observation_row(block[i], template, robot, obstacle_state, n_max)


@numba.njit(cache=True)
def _observation_row_carrying(block, i, template, robot, obstacle_state, n_max, carried):
    """:func:`_observation_row` into ``block[i]``, then the two ``carried`` scalars (a unicycle's
    heading and turn rate) in the row's last two columns (float32, as a numpy assignment rounds them)."""
    row = block[i]
    _observation_row(row, template, robot, obstacle_state, n_max)
    size = row.shape[0]
    row[size - 2], row[size - 1] = carried[0], carried[1]


#: Observation types by the name ``DynamicObstacleEnv(observation=...)`` takes.
OBSERVATION_TYPES: dict[str, type[ObservationType]] = {StateObservation.name: StateObservation}


def register_observation_type(cls: type[ObservationType]) -> type[ObservationType]:
    """Make ``cls`` available as ``observation=cls.name`` (usable as a class decorator)."""
    if not isinstance(cls.name, str) or not cls.name:
        raise ValueError(f"an observation type needs a name, got {cls.name!r}")
    OBSERVATION_TYPES[cls.name] = cls
    return cls


def static_segment_capacity(count: int) -> int:
    """The rows of ``static_segments`` an env reserves when its first scene has ``count``: none for a
    scene without walls or polygons (its observation stays as it always was), else
    ``max(count, StateObservation.MIN_STATIC_SEGMENTS)``. A later scene with more is a ``ValueError``."""
    return 0 if count == 0 else max(int(count), StateObservation.MIN_STATIC_SEGMENTS)


def make_observation_type(name, arena: Arena, dt: float, max_obstacles: int, params=None, static_segments: int = 0) -> ObservationType:
    """The observation type registered as ``name``, with its ``params`` (``observation_params``);
    a state-based type reserves :func:`static_segment_capacity` rows for ``static_segments``, the
    wall and polygon edges of the env's first scene.

    :raises ValueError: naming the ``observation`` argument and the known types, or
        ``observation_params`` (not a dict, or a key the type does not take), or a parameter's field.
    """
    if not isinstance(name, str) or name not in OBSERVATION_TYPES:
        raise ValueError(f"observation must be one of {sorted(OBSERVATION_TYPES)}, got {name!r}")
    if params is None:
        params = {}
    if not isinstance(params, dict):
        raise ValueError(f"observation_params must be a dict or None, got {params!r}")
    cls = OBSERVATION_TYPES[name]
    if cls.parameters:
        made = cls(arena, dt, max_obstacles, params=params)
    elif params:
        raise ValueError(f"observation_params: observation {name!r} takes no parameters, got keys {sorted(params, key=str)}")
    else:
        made = cls(arena, dt, max_obstacles)
    if isinstance(made, StateObservation):
        made.reserve_static_segments(static_segment_capacity(static_segments))
    return made


__all__ = [
    "OBSERVATION_TYPES",
    "ObservationType",
    "StateLayout",
    "StateObservation",
    "make_observation_type",
    "register_observation_type",
    "state_layout",
    "static_segment_capacity",
]
