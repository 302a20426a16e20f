"""The ``"lidar"`` observation type: the robot's own state, the goal, and a 2D range scan.

``gym.make("DynamicObstacle-v0", observation="lidar", observation_params={...})`` with the fields of
:class:`pathplan_env.sensors.range_sensor.SensorParams` (any subset; the rest default): ``lidar_beams``
(360), ``lidar_fov`` (2π rad), ``lidar_range`` (10 m), ``lidar_noise`` (0 m), ``lidar_dropout`` (0).

| Key              | Shape    | Observation                                   | Min                | Max               |
|------------------|----------|-----------------------------------------------|--------------------|-------------------|
| `robot_position` | (2,)     | robot centre (as ``"state"``)                 | arena lower corner | arena upper corner|
| `robot_velocity` | (2,)     | robot velocity over the last step             | -V                 | V                 |
| `goal`           | (2,)     | goal position                                 | arena lower corner | arena upper corner|
| `lidar`          | (beams,) | range of beam i (m), from the robot's centre  | 0                  | lidar_range       |

Beam ``i`` points at ``heading - fov/2 + (i + 1/2) * fov/beams`` (world frame; the heading is the
world's ``robot_heading`` if it has one, else 0: today's robot is holonomic). A beam reads the
distance to the nearest obstacle disc, wall (``World.static_segments``) or arena edge, exactly
(``pathplan_env.geometry.rays``), clipped to ``lidar_range``; 0 from inside a disc or a wall. Then, from
the type's own random stream (spawned from the env's seed, so seeded and never shifting the scenes):
Gaussian noise of σ ``lidar_noise`` (clipped to [0, lidar_range]), and with probability
``lidar_dropout`` a beam reads ``lidar_range``. With both 0 (the default) nothing is drawn and no
stream is spawned.
"""

from __future__ import annotations

import numba
import numpy as np
from gymnasium import spaces

from pathplan_env.arena import Arena
from pathplan_env.geometry.rays import Beams, Scene, beam_directions, cast, scan_beams
from pathplan_env.sensors.observations import ObservationType, StateObservation, register_observation_type, state_layout
from pathplan_env.sensors.range_sensor import SensorParams

_NO_SEGMENTS = np.empty((0, 5))


def static_segments(world) -> np.ndarray:
    """The world's walls as ``(M, 5)`` float64 capsule rows (none if it has no ``static_segments``)."""
    segments = getattr(world, "static_segments", None)
    if segments is None or len(segments) == 0:
        return _NO_SEGMENTS
    return np.ascontiguousarray(segments, dtype=np.float64)


def robot_heading(world) -> float:
    """The robot's heading (rad): the world's ``robot_heading`` if it has one, else 0 (holonomic)."""
    return float(getattr(world, "robot_heading", 0.0))


def beam_endpoints(origin, ranges, heading: float, fov: float) -> np.ndarray:
    """Where each beam of a scan ends, ``(beams, 2)`` (m, world frame): for drawing the scan."""
    ranges = np.asarray(ranges, np.float64)
    return np.asarray(origin, np.float64) + ranges[:, None] * beam_directions(heading, fov, len(ranges))


@register_observation_type
class LidarObservation(ObservationType):
    """The robot's state, the goal and a range scan (the module's docstring has the table)."""

    name = "lidar"
    parameters = SensorParams._fields

    def __init__(self, arena: Arena, dt: float, max_obstacles: int, params: dict | None = None):
        super().__init__(arena, dt, max_obstacles)
        self.params = p = SensorParams.of(params or {}, self.parameters)
        self.draws = p.lidar_noise > 0.0 or p.lidar_dropout > 0.0  # an exact sensor spawns no stream
        self._robot_part = StateObservation(arena, dt, 0).space()  # the "state" type's robot and goal entries
        at = state_layout(0)
        self._slices = (slice(at.robot_position, at.robot_velocity), slice(at.robot_velocity, at.goal), slice(at.goal, at.size))
        self._template = np.zeros(at.size + p.lidar_beams, np.float32)
        self._goal_at, self._scan_at = at.goal, at.size
        #: The arena's (xmin, ymin, xmax, ymax) and the scan's (start angle, step, range): the last
        #: fields of the kernels' Scene and Beams records.
        self._edges = tuple(float(b) for b in arena.bounds)
        self._fan = (0.0, 0.0, 0.0)
        self._ranges, self._hits = np.empty(p.lidar_beams), np.empty(p.lidar_beams, np.int64)
        self._heading, self._directions = None, None
        self._rng: np.random.Generator | None = None

    def space(self) -> spaces.Dict:
        p = self.params
        return spaces.Dict(
            {
                "robot_position": self._robot_part["robot_position"],
                "robot_velocity": self._robot_part["robot_velocity"],
                "goal": self._robot_part["goal"],
                "lidar": spaces.Box(0.0, np.float32(p.lidar_range), shape=(p.lidar_beams,), dtype=np.float32),
            }
        )

    def reset(self, world, rng: np.random.Generator | None) -> None:
        self._template[self._goal_at : self._goal_at + 2] = world.scenario.goal
        self._edges = tuple(float(b) for b in world.scenario.bounds)
        self._rng = rng

    def _aim(self, world) -> None:
        """The beams' directions, computed once per heading (today: once)."""
        heading = robot_heading(world)
        if heading != self._heading:
            p = self.params
            self._heading, self._directions = heading, beam_directions(heading, p.lidar_fov, p.lidar_beams)
            self._fan = (float(heading - 0.5 * p.lidar_fov), float(p.lidar_fov / p.lidar_beams), float(p.lidar_range))

    def scan(self, world) -> np.ndarray:
        """The exact ranges (float64, before noise and the float32 cast) of the world as it is now;
        ``self.hits`` then says what each beam hit (``pathplan_env.geometry.rays.cast``)."""
        self._aim(world)
        scan_beams(self._beams(world), self._scene(world), self._ranges, self._hits)
        return self._ranges

    def _beams(self, world) -> tuple:
        """The fields of the scan's :class:`~pathplan_env.geometry.rays.Beams` as a plain tuple (numba
        types a NamedTuple argument in Python on every call, a plain tuple in C)."""
        x, y = world.robot_xy
        return (float(x), float(y), *self._fan, self._directions)

    def _scene(self, world) -> tuple:
        """The fields of the :class:`~pathplan_env.geometry.rays.Scene` it scans, as a plain tuple."""
        return (world.obstacle_state, world.radii, static_segments(world), *self._edges)

    def overlay(self, world) -> dict[str, np.ndarray]:
        p = self.params
        return {"beams": beam_endpoints(world.robot_xy, self.scan(world), robot_heading(world), p.lidar_fov)}

    @property
    def hits(self) -> np.ndarray:
        """What each beam of the last scan hit first: obstacle ``k``, ``N + m`` for wall ``m``, -1 for
        the arena's edge or nothing within range."""
        return self._hits

    def observe(self, world) -> dict[str, np.ndarray]:
        (x, y), (vx, vy) = world.robot_xy, world.robot_velocity_xy
        position, velocity, goal = self._slices
        if self.draws:
            block = self._template.copy()
            block[position], block[velocity] = (x, y), (vx, vy)
            block[self._scan_at :] = self._noisy(self.scan(world))
        else:  # one compiled call: the scan cast into a copy of the template, the robot's state written in
            self._aim(world)
            block = _exact_block(self._template, (vx, vy), self._beams(world), self._scene(world), self._hits)
        return {"robot_position": block[position], "robot_velocity": block[velocity], "goal": block[goal], "lidar": block[self._scan_at :]}

    def _noisy(self, ranges: np.ndarray) -> np.ndarray:
        p, rng = self.params, self._rng
        if p.lidar_noise > 0.0:
            ranges = np.clip(ranges + rng.normal(0.0, p.lidar_noise, ranges.shape[0]), 0.0, p.lidar_range)
        if p.lidar_dropout > 0.0:
            ranges = np.where(rng.random(ranges.shape[0]) < p.lidar_dropout, p.lidar_range, ranges)
        return ranges


@numba.njit(cache=True)
def _exact_block(template, velocity, beams, scene, hits):
    """A copy of the template with the robot's position (the beams' origin) and ``velocity`` (where
    the state layout puts them) and the scan (its last ``beams`` entries, float32) written in.
    ``beams``, ``scene``: a :class:`Beams` and a :class:`Scene`, or plain tuples of their fields."""
    beams, scene = Beams(*beams), Scene(*scene)
    at = state_layout(0)
    block = template.copy()
    block[at.robot_position], block[at.robot_position + 1] = beams.x, beams.y
    block[at.robot_velocity], block[at.robot_velocity + 1] = velocity[0], velocity[1]
    count = beams.directions.shape[0]
    ranges = np.empty(count)
    cast(beams, scene, ranges, hits)
    offset = block.shape[0] - count
    for i in range(count):
        block[offset + i] = ranges[i]
    return block


__all__ = ["LidarObservation", "beam_endpoints", "robot_heading", "static_segments"]
