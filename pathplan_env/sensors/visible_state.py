"""The ``"visible-state"`` observation type: the ``"state"`` Dict with only the obstacles the robot can see.

``gym.make("DynamicObstacle-v0", observation="visible-state", observation_params={"lidar_fov": ...,
"lidar_range": ...})`` (defaults: 2π rad, 10 m). Same space as ``"state"``; an obstacle that is not
visible is absent exactly as a padding row is (centre at the arena's lower corner, velocity 0,
radius 0, mask 0) and keeps its row, so planners that read the mask (``agents.base.real_obstacles``)
leave it out of their model with no change.

**Visible**, exactly: obstacle ``j`` is visible iff some ray from the robot's centre whose direction
lies in the field of view (``heading ± fov/2``, closed) reaches a point of disc ``j`` at distance
``<= lidar_range`` before entering any other obstacle or wall (``World.static_segments``, as
capsules); a ray that only grazes another shape is not blocked (shapes block with their interior).
The arena's walls never hide an obstacle (both robot and obstacles are inside the convex arena). An
obstacle whose disc holds the robot's centre is visible; one the robot is inside hides the others.

How, exactly and cheaply: along the directions in disc ``j``'s angular span, which shape a ray
enters first can only change where a shape's span begins or ends or where two boundaries cross
(there two shapes' entry points coincide); the range limit and the field of view cut the span at
known angles. So testing one ray at each of those angles and one between each neighbouring pair
decides ``j`` exactly (floating point aside), with no sampling: a few rays per obstacle, against
only the shapes whose spans overlap ``j``'s. Deterministic: no randomness at all.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba
import numpy as np

from pathplan_env.arena import Arena
from pathplan_env.geometry.rays import TWO_PI, capsule_span, disc_span, ray_capsule, ray_disc, segment_distance_squared, wrap
from pathplan_env.sensors.lidar import LidarObservation, robot_heading, static_segments
from pathplan_env.sensors.observations import StateObservation, register_observation_type
from pathplan_env.sensors.range_sensor import SensorParams

#: Relative slack on the range test at the ends of a range-limited span (where the entry is at the range).
_RANGE_SLACK = 1e-12


class Sensor(NamedTuple):
    """Where the robot looks from and how far: its centre, heading, field of view (rad), range (m)."""

    x: float
    y: float
    heading: float
    fov: float
    max_range: float


class Shapes(NamedTuple):
    """What can be seen or stand in the way: discs (centres in the first two columns, radii), then
    capsules (``(M, 5)`` rows as ``World.static_segments``); shape ``k >= N`` is capsule ``k - N``."""

    centres: np.ndarray
    radii: np.ndarray
    segments: np.ndarray


class Spans(NamedTuple):
    """Each shape's directions from the robot: centre angle, half width, whether the robot is inside
    it (then every direction), and its nearest distance."""

    alpha: np.ndarray
    half: np.ndarray
    inside: np.ndarray
    near: np.ndarray


class Window(NamedTuple):
    """The directions being searched: offsets in (lo, hi) from the angle ``alpha``."""

    alpha: float
    lo: float
    hi: float


@numba.njit(cache=True)
def _spans(sensor, shapes):
    x, y, centres, radii, segments = sensor.x, sensor.y, shapes.centres, shapes.radii, shapes.segments
    n, m = radii.shape[0], segments.shape[0]
    alpha, half, near = np.empty(n + m), np.empty(n + m), np.empty(n + m)
    inside = np.zeros(n + m, np.bool_)
    for k in range(n):
        alpha[k], half[k], inside[k] = disc_span(x, y, centres[k, 0], centres[k, 1], radii[k])
        near[k] = max(math.hypot(centres[k, 0] - x, centres[k, 1] - y) - radii[k], 0.0)
    for i in range(m):
        s = segments[i]
        alpha[n + i], half[n + i], inside[n + i] = capsule_span(x, y, s[0], s[1], s[2], s[3], s[4])
        near[n + i] = max(math.sqrt(segment_distance_squared(x, y, s[0], s[1], s[2], s[3])) - s[4], 0.0)
    return Spans(alpha, half, inside, near)


@numba.njit(cache=True)
def _entry(shapes, k, sensor, ux, uy):
    """Distance along the ray from the sensor to shape ``k``'s boundary (0 from inside, inf if missed)."""
    n = shapes.radii.shape[0]
    if k < n:
        return ray_disc(sensor.x, sensor.y, ux, uy, shapes.centres[k, 0], shapes.centres[k, 1], shapes.radii[k])
    s = shapes.segments[k - n]
    return ray_capsule(sensor.x, sensor.y, ux, uy, s[0], s[1], s[2], s[3], s[4])


@numba.njit(cache=True)
def _add_direction(px, py, sensor, window, out, count):
    """Append the direction of point ``p`` (as an offset from ``window.alpha``) if it lies in the window."""
    u = wrap(math.atan2(py - sensor.y, px - sensor.x) - window.alpha)
    if window.lo < u < window.hi:
        out[count] = u
        count += 1
    return count


@numba.njit(cache=True)
def _circle_circle(cx, cy, r, qx, qy, q, sensor, window, out, count):
    """Directions of the points where circle ``(c, r)`` meets circle ``(q, q_r)``."""
    dx, dy = qx - cx, qy - cy
    d = math.hypot(dx, dy)
    if d == 0.0 or d > r + q or d < abs(r - q):
        return count
    a = (d * d + r * r - q * q) / (2.0 * d)
    h = math.sqrt(max(r * r - a * a, 0.0))
    mx, my = cx + a * dx / d, cy + a * dy / d
    count = _add_direction(mx - h * dy / d, my + h * dx / d, sensor, window, out, count)
    return _add_direction(mx + h * dy / d, my - h * dx / d, sensor, window, out, count)


@numba.njit(cache=True)
def _circle_segment(circle, segment, sensor, window, out, count):
    """Directions of the points where ``circle`` ``(cx, cy, r)`` meets ``segment`` ``(ax, ay, bx, by)``."""
    cx, cy, r = circle
    ax, ay, bx, by = segment
    ex, ey = bx - ax, by - ay
    fx, fy = ax - cx, ay - cy
    qa, qb, qc = ex * ex + ey * ey, fx * ex + fy * ey, fx * fx + fy * fy - r * r
    disc = qb * qb - qa * qc
    if qa == 0.0 or disc < 0.0:
        return count
    root = math.sqrt(disc)
    for s in ((-qb - root) / qa, (-qb + root) / qa):
        if 0.0 <= s <= 1.0:
            count = _add_direction(ax + s * ex, ay + s * ey, sensor, window, out, count)
    return count


@numba.njit(cache=True)
def _crossings(shapes, j, k, sensor, window, out, count):
    """Directions in the window where disc ``j``'s boundary meets shape ``k``'s."""
    n, cx, cy, r = shapes.radii.shape[0], shapes.centres[j, 0], shapes.centres[j, 1], shapes.radii[j]
    if k < n:
        return _circle_circle(cx, cy, r, shapes.centres[k, 0], shapes.centres[k, 1], shapes.radii[k], sensor, window, out, count)
    ax, ay, bx, by, h = shapes.segments[k - n]
    if h == 0.0:
        return _circle_segment((cx, cy, r), (ax, ay, bx, by), sensor, window, out, count)
    count = _circle_circle(cx, cy, r, ax, ay, h, sensor, window, out, count)
    count = _circle_circle(cx, cy, r, bx, by, h, sensor, window, out, count)
    length = math.hypot(bx - ax, by - ay)
    if length > 0.0:
        nx, ny = -(by - ay) * h / length, (bx - ax) * h / length
        count = _circle_segment((cx, cy, r), (ax + nx, ay + ny, bx + nx, by + ny), sensor, window, out, count)
        count = _circle_segment((cx, cy, r), (ax - nx, ay - ny, bx - nx, by - ny), sensor, window, out, count)
    return count


@numba.njit(cache=True)
def _seen_along(shapes, j, angle, sensor, others, n_others):
    """Whether the ray at ``angle`` reaches disc ``j`` within range before entering any of ``others``."""
    ux, uy = math.cos(angle), math.sin(angle)
    t = _entry(shapes, j, sensor, ux, uy)
    if not t <= sensor.max_range * (1.0 + _RANGE_SLACK):
        return False
    for i in range(n_others):  # noqa: SIM110 (a loop: numba compiles no generator into all())
        if _entry(shapes, others[i], sensor, ux, uy) < t:
            return False
    return True


@numba.njit(cache=True)
def _pieces(alpha, w, sensor, out):
    """The parts of ``[-w, w]`` (offsets from ``alpha``) inside the field of view, into ``out``
    (up to two intervals); returns how many."""
    if sensor.fov >= TWO_PI:
        out[0, 0], out[0, 1] = -w, w
        return 1
    centre, half, count = wrap(alpha - sensor.heading), 0.5 * sensor.fov, 0
    for turn in (-TWO_PI, 0.0, TWO_PI):
        lo, hi = max(-w, -half - centre + turn), min(w, half - centre + turn)
        if lo <= hi and count < 2:
            out[count, 0], out[count, 1] = lo, hi
            count += 1
    return count


@numba.njit(cache=True)
def _visible_disc(shapes, j, sensor, spans, others, pieces, events):
    """``(visible, a direction that sees it)`` for disc ``j``, the robot outside it (``others``,
    ``pieces``, ``events``: scratch space)."""
    alpha, half, inside, near = spans
    d = math.hypot(shapes.centres[j, 0] - sensor.x, shapes.centres[j, 1] - sensor.y)
    r, reach = shapes.radii[j], sensor.max_range
    if d - r > reach:
        return False, 0.0
    tangent = math.sqrt(max(d * d - r * r, 0.0))
    w = half[j]
    if tangent > reach:  # only the part of its near side within range: up to where the circles meet
        w = math.acos(min(1.0, max(-1.0, (d * d + reach * reach - r * r) / (2.0 * d * reach))))
    n_pieces = _pieces(alpha[j], w, sensor, pieces)
    if n_pieces == 0:
        return False, 0.0
    far = min(reach, tangent)  # no entry point of j lies farther
    n_others = 0
    for k in range(alpha.shape[0]):
        if k != j and near[k] < far and (inside[k] or abs(wrap(alpha[k] - alpha[j])) <= w + half[k] + 1e-9):
            others[n_others] = k
            n_others += 1
    if n_others == 0:  # nothing can stand in front of it: the middle of its first piece in view sees it
        return True, alpha[j] + 0.5 * (pieces[0, 0] + pieces[0, 1])
    for p in range(n_pieces):
        window = Window(alpha[j], pieces[p, 0], pieces[p, 1])
        events[0], events[1], count = window.lo, window.hi, 2
        for i in range(n_others):
            k = others[i]
            if not inside[k]:
                for edge in (alpha[k] - half[k], alpha[k] + half[k]):
                    u = wrap(edge - alpha[j])
                    if window.lo < u < window.hi:
                        events[count] = u
                        count += 1
            count = _crossings(shapes, j, k, sensor, window, events, count)
        ordered = np.sort(events[:count])
        for i in range(count - 1):  # between events first (robust), then the events themselves
            u = 0.5 * (ordered[i] + ordered[i + 1])
            if _seen_along(shapes, j, alpha[j] + u, sensor, others, n_others):
                return True, alpha[j] + u
        for i in range(count):
            if _seen_along(shapes, j, alpha[j] + ordered[i], sensor, others, n_others):
                return True, alpha[j] + ordered[i]
    return False, 0.0


@numba.njit(cache=True)
def visible_obstacles(x, y, heading, fov, max_range, centres, radii, segments, visible, witness):
    """Fill ``visible`` (bool, per disc; the module's definition) and ``witness`` (a ray direction
    that sees each visible disc, rad; 0 for the others). Floats and arrays, not records: numba types
    a NamedTuple argument in Python on every call (~10 µs), so the records are built here."""
    sensor, shapes = Sensor(x, y, heading, fov, max_range), Shapes(centres, radii, segments)
    spans = _spans(sensor, shapes)
    count = spans.alpha.shape[0]
    others, pieces, events = np.empty(count, np.int64), np.empty((2, 2)), np.empty(2 + 10 * count)
    for j in range(radii.shape[0]):
        if spans.inside[j]:
            visible[j], witness[j] = True, heading
        else:
            visible[j], witness[j] = _visible_disc(shapes, j, sensor, spans, others, pieces, events)


@numba.njit(cache=True)
def _hide(positions, velocities, radii, mask, visible, low_x, low_y):
    """Turn the rows of the obstacles that are not visible into padding rows."""
    for i in range(visible.shape[0]):
        if not visible[i]:
            positions[i, 0], positions[i, 1] = low_x, low_y
            velocities[i, 0], velocities[i, 1] = 0.0, 0.0
            radii[i], mask[i] = 0.0, 0.0


@register_observation_type
class VisibleStateObservation(StateObservation):
    """``"state"`` with only the visible obstacles (the module's docstring defines visible)."""

    name = "visible-state"
    parameters = ("lidar_fov", "lidar_range")

    def __init__(self, arena: Arena, dt: float, max_obstacles: int, params: dict | None = None):
        super().__init__(arena, dt, max_obstacles)
        self.params = SensorParams.of(params or {}, self.parameters)
        #: Which obstacles the last observation showed (for drawing the others greyed), and a ray
        #: direction that saw each of them.
        self.visible, self.witness = np.zeros(0, np.bool_), np.zeros(0)
        self._display_scan: LidarObservation | None = None  # made on the first rendered frame

    def reset(self, world, rng: np.random.Generator | None) -> None:
        super().reset(world, rng)
        self.visible, self.witness = np.zeros(world.n_obstacles, np.bool_), np.zeros(world.n_obstacles)

    def observe(self, world) -> dict[str, np.ndarray]:
        obs = super().observe(world)
        p, (x, y) = self.params, world.robot_xy
        visible_obstacles(x, y, robot_heading(world), p.lidar_fov, p.lidar_range, world.obstacle_state, world.radii,
                          static_segments(world), self.visible, self.witness)  # fmt: skip
        low_x, low_y = self.arena.bounds[:2]
        _hide(obs["obstacle_positions"], obs["obstacle_velocities"], obs["obstacle_radii"], obs["obstacle_mask"], self.visible, low_x, low_y)
        return obs

    #: Beams drawn over a frame to show the sensor's reach (display only: visibility is exact, not sampled).
    OVERLAY_BEAMS = 180

    def overlay(self, world) -> dict[str, np.ndarray]:
        if len(self.visible) != world.n_obstacles:  # rendered before any observation
            return {}
        if self._display_scan is None:
            params = {"lidar_beams": self.OVERLAY_BEAMS, "lidar_fov": self.params.lidar_fov, "lidar_range": self.params.lidar_range}
            self._display_scan = LidarObservation(self.arena, self.dt, 0, params)
            self._display_scan.reset(world, None)
        return {"hidden": ~self.visible, "beams": self._display_scan.overlay(world)["beams"]}


__all__ = ["VisibleStateObservation", "visible_obstacles"]
