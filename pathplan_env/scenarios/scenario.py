"""Scenarios: the frozen description of one episode's world, validated, and Δd (presets: ``presets.py``).

A :class:`Scenario` is pure data (no simulator state): arena bounds, start, goal, robot size and
speed, the control period ``dt``, the obstacles with their initial velocities, and the static geometry
(walls and polygons, ``statics.py``). The env turns a
scenario into a pymunk world at every reset; ``env.unwrapped.scenario`` is the one in use.

Δd (the paper's Eq. 8) is the distance an obstacle moves in one env step divided by its radius:
``delta_d = |v| * dt / radius``. :meth:`Scenario.with_delta_d` sets every obstacle's speed to that.
"""

from __future__ import annotations

import copy
import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from pathplan_env.arena import Arena
from pathplan_env.arguments import check_delta_d, check_n_obstacles
from pathplan_env.crowds.behaviours import BOUNCE, Behaviour, make_behaviour
from pathplan_env.geometry.walls import DEFAULT_WALL_THICKNESS, as_point, check_static_geometry, normalise_polygons, normalise_walls, segments_of
from pathplan_env.validation import MAX_COORDINATE, is_number, short
from pathplan_env.validation import name as check_name

Vec2 = tuple[float, float]


_vec2 = as_point  # a finite (x, y) of floats, or a ValueError naming the field


#: Smallest length (m) accepted for radii and distances: below it, masses r² and squared distances
#: underflow toward subnormals and zero.
MIN_LENGTH = 1e-6
#: Most obstacles a scenario holds: its checks compare every pair (in blocks of rows, so memory stays
#: bounded), and no observation or physics step is meant for more.
MAX_OBSTACLES = 5000
#: How far (m) two shapes may seem to overlap and still count as touching: discs placed exactly two
#: radii apart (cylinders in a row, coordinates written as decimals) read as overlapping by a few
#: 1e-16 m of rounding; a nanometre is far above that and far below any physical size.
TOUCHING_TOLERANCE = 1e-9
#: Rows of the pairwise gap matrix computed at once (a block is ``_GAP_ROWS x n`` floats).
_GAP_ROWS = 256


def _positive(value, name: str, allow_zero: bool = False, minimum: float = 0.0) -> float:
    if not is_number(value):  # not float(): "0.5", True and "15" are not numbers
        raise ValueError(f"{name} must be a number, got {short(value)}")
    value = float(value)
    ok = value >= 0 if allow_zero else value > minimum
    if not (math.isfinite(value) and ok):
        bound = ">= 0" if allow_zero else f"> {minimum:g}"
        raise ValueError(f"{name} must be finite and {bound}, got {value!r}")
    return value


@dataclass(frozen=True)
class Obstacle:
    """A circular obstacle: centre (m), radius (m) and initial velocity (m/s).

    Goal-directed obstacles (behaviour ``"orca"`` or ``"social-force"``, here or the scenario's)
    head for ``goal`` at up to ``preferred_speed`` (m/s); ``behaviour=None`` takes the scenario's.
    """

    center: Vec2
    radius: float
    velocity: Vec2 = (0.0, 0.0)
    goal: Vec2 | None = None
    preferred_speed: float = 0.0
    behaviour: Behaviour | None = None

    def __post_init__(self):
        object.__setattr__(self, "center", _vec2(self.center, "Obstacle.center"))
        object.__setattr__(self, "radius", _positive(self.radius, "Obstacle.radius", minimum=MIN_LENGTH))
        object.__setattr__(self, "velocity", _vec2(self.velocity, "Obstacle.velocity"))
        if self.goal is not None:
            object.__setattr__(self, "goal", _vec2(self.goal, "Obstacle.goal"))
        object.__setattr__(self, "preferred_speed", _positive(self.preferred_speed, "Obstacle.preferred_speed", allow_zero=True))
        if self.behaviour is not None:
            object.__setattr__(self, "behaviour", make_behaviour(self.behaviour, "Obstacle.behaviour"))

    @property
    def speed(self) -> float:
        return math.hypot(*self.velocity)

    @classmethod
    def _from_checked(cls, center: Vec2, radius: float, velocity: Vec2, goal: Vec2 | None = None, preferred_speed: float = 0.0) -> Obstacle:
        """Build from values that are already valid float tuples (sampling, ``with_delta_d``): no re-validation."""
        ob = object.__new__(cls)
        if goal is None:  # (the class defaults: no goal, no preferred speed; the __dict__ written at once, as a frozen dataclass's setattr per field cost more)
            ob.__dict__.update(center=center, radius=radius, velocity=velocity)
        else:
            ob.__dict__.update(center=center, radius=radius, velocity=velocity, goal=goal, preferred_speed=preferred_speed)
        return ob


@dataclass(frozen=True)
class Scenario:
    """Everything that defines an episode's initial world. Validated on construction.

    :param bounds: arena ``(xmin, ymin, xmax, ymax)`` in metres; walls stand on its edges.
    :param start: robot start position; the robot's disc must fit inside the arena.
    :param goal: goal position; reached when the robot centre comes within ``goal_radius`` of it.
    :param obstacles: the obstacles; none may overlap the robot's disc at the start or the goal.
    :param robot_radius: robot radius (m).
    :param robot_speed: the robot's maximum speed (m/s).
    :param dt: control period (s): one env step advances the world by ``dt``.
    :param goal_radius: goal tolerance (m); ``None`` means the robot radius.
    :param name: a label (the preset's name), used in logs and results.
    :param behaviour: the obstacles' motion model where their own ``behaviour`` is ``None``
        (``pathplan_env.crowds.behaviours``: ``"bounce"``, ``"orca"``, ``"social-force"``).
    :param robot_visible: whether goal-directed obstacles see the robot and avoid it.
    :param time_limit: episode time limit (s): the env truncates once it has passed; ``None``
        leaves only the registration's step limit.
    :param walls: straight walls inside the arena, ``((x0, y0), (x1, y1))`` each: capsules (round
        ends) ``wall_thickness`` thick. The robot must start and end clear of them, and obstacles
        start clear of them and bounce off them as off the arena's edges.
    :param wall_thickness: the thickness of every wall (m), default 0.1 (an interior wall, half the
        default robot radius); 0 makes them lines.
    :param polygons: closed static polygons, convex or not, each a sequence of at least 3 vertices
        (a repeated closing vertex is dropped); simple (not self-intersecting), inside the arena.

    >>> from pathplan_env import Obstacle, Scenario
    >>> scene = Scenario(bounds=(0, 0, 10, 10), start=(1, 5), goal=(9, 5), obstacles=(Obstacle((5, 5), 0.5, (0, 1)),))
    >>> scene.name, scene.robot_radius, len(scene.obstacles)
    ('custom', 0.2, 1)
    >>> Scenario(bounds=(0, 0, 10, 10), start=(1, 5), goal=(19, 5))
    Traceback (most recent call last):
    ...
    ValueError: Scenario.goal ...
    """

    bounds: tuple[float, float, float, float]
    start: Vec2
    goal: Vec2
    obstacles: tuple[Obstacle, ...] = ()
    robot_radius: float = 0.2
    robot_speed: float = 2.5
    dt: float = 0.1
    goal_radius: float | None = None
    name: str = "custom"
    behaviour: Behaviour = BOUNCE
    robot_visible: bool = False
    time_limit: float | None = None
    walls: tuple[tuple[Vec2, Vec2], ...] = ()
    wall_thickness: float = DEFAULT_WALL_THICKNESS
    polygons: tuple[tuple[Vec2, ...], ...] = ()

    def __post_init__(self):
        bounds = self.bounds
        if isinstance(bounds, (str, bytes, dict)) or not hasattr(bounds, "__len__") or len(bounds) != 4 or not all(map(is_number, bounds)):
            raise ValueError(f"Scenario.bounds must be four numbers (xmin, ymin, xmax, ymax), got {short(bounds)}")
        xmin, ymin, xmax, ymax = (float(b) for b in bounds)
        if not all(map(math.isfinite, (xmin, ymin, xmax, ymax))) or xmax <= xmin or ymax <= ymin:
            raise ValueError(f"Scenario.bounds must be finite with xmin < xmax and ymin < ymax, got {self.bounds!r}")
        if max(map(abs, (xmin, ymin, xmax, ymax))) > MAX_COORDINATE:
            raise ValueError(f"Scenario.bounds must lie within +-{MAX_COORDINATE:g} m (observations are float32), got {self.bounds!r}")
        set_ = lambda k, v: object.__setattr__(self, k, v)  # frozen dataclass normalisation
        set_("bounds", (xmin, ymin, xmax, ymax))
        check_name(self.name, "Scenario.name")
        set_("start", _vec2(self.start, "Scenario.start"))
        set_("goal", _vec2(self.goal, "Scenario.goal"))
        set_("robot_radius", _positive(self.robot_radius, "Scenario.robot_radius", minimum=MIN_LENGTH))
        set_("robot_speed", _positive(self.robot_speed, "Scenario.robot_speed"))
        set_("dt", _positive(self.dt, "Scenario.dt"))
        goal_radius = self.robot_radius if self.goal_radius is None else self.goal_radius
        set_("goal_radius", _positive(goal_radius, "Scenario.goal_radius", minimum=MIN_LENGTH))
        set_("behaviour", make_behaviour(self.behaviour, "Scenario.behaviour"))
        if not isinstance(self.robot_visible, (bool, np.bool_)):
            raise ValueError(f"Scenario.robot_visible must be True or False, got {self.robot_visible!r}")
        set_("robot_visible", bool(self.robot_visible))
        if self.time_limit is not None:
            set_("time_limit", _positive(self.time_limit, "Scenario.time_limit"))
        if isinstance(self.obstacles, (str, bytes, dict)) or not hasattr(self.obstacles, "__len__"):
            raise ValueError(f"Scenario.obstacles must be a sequence of obstacles, got {short(self.obstacles)}")
        if len(self.obstacles) > MAX_OBSTACLES:
            raise ValueError(f"Scenario.obstacles: {len(self.obstacles)} obstacles, more than the {MAX_OBSTACLES} a scenario may hold")
        obstacles = tuple(self.obstacles)
        for i, ob in enumerate(obstacles):
            if not isinstance(ob, Obstacle):
                raise ValueError(f"Scenario.obstacles[{i}] must be an Obstacle, got {type(ob).__name__}")
        set_("obstacles", obstacles)
        set_("walls", normalise_walls(self.walls, MIN_LENGTH))
        set_("wall_thickness", _positive(self.wall_thickness, "Scenario.wall_thickness", allow_zero=True))
        polygons, shapes = normalise_polygons(self.polygons, MIN_LENGTH)
        set_("polygons", polygons)
        set_("_polygon_shapes", shapes)
        set_("_segments", segments_of(self.walls, self.wall_thickness, self.polygons))
        n = len(obstacles)
        arrays = {
            "positions": np.array([ob.center for ob in obstacles], dtype=np.float64).reshape(n, 2),
            "velocities": np.array([ob.velocity for ob in obstacles], dtype=np.float64).reshape(n, 2),
            "radii": np.array([ob.radius for ob in obstacles], dtype=np.float64).reshape(n),
        }
        for a in arrays.values():
            a.flags.writeable = False  # shared by every arrays() call: a frozen scenario stays frozen
        set_("_arrays", arrays)
        self._check_geometry()

    @classmethod
    def _from_checked(cls, arrays: dict[str, np.ndarray], segments: np.ndarray | None = None, **fields) -> Scenario:
        """Build from fields that are already valid and normalised, with their obstacle arrays.

        For the random sampler, whose output is valid by construction: validating it again cost
        about a fifth of a reset with 50 obstacles. Fields left out take their defaults; ``segments``,
        when given, are ``static_segments`` of the same walls and polygons (a fixed map's, kept).
        """
        scenario = object.__new__(cls)
        values = {**_SCENARIO_DEFAULTS, **fields}  # (the instance's __dict__ written at once: a frozen dataclass's setattr per field cost more)
        if len(values) != len(_SCENARIO_DEFAULTS):
            raise TypeError(f"unknown Scenario fields {sorted(set(fields) - set(_SCENARIO_DEFAULTS))}")
        if not _SCENARIO_REQUIRED.issubset(fields):
            raise TypeError(f"Scenario fields {sorted(_SCENARIO_REQUIRED - set(fields))} are required")
        for a in arrays.values():
            a.flags.writeable = False
        values["_arrays"] = arrays
        values["_segments"] = segments_of(values["walls"], values["wall_thickness"], values["polygons"]) if segments is None else segments
        scenario.__dict__.update(values)
        return scenario

    def _check_geometry(self) -> None:
        xmin, ymin, xmax, ymax = self.bounds
        r = self.robot_radius
        fit_xmin, fit_ymin, fit_xmax, fit_ymax = Arena.of(self).robot_box
        for label, (x, y) in (("start", self.start), ("goal", self.goal)):
            if not (fit_xmin <= x <= fit_xmax and fit_ymin <= y <= fit_ymax):
                raise ValueError(
                    f"Scenario.{label} {(x, y)} is outside the arena {self.bounds} "
                    f"(the robot's disc of radius {r} must fit inside)"
                )
        if math.dist(self.start, self.goal) <= self.goal_radius:
            raise ValueError(f"Scenario.goal {self.goal} is within goal_radius {self.goal_radius} of the start {self.start}: nothing to plan")
        max_step = math.hypot(xmax - xmin, ymax - ymin)
        if self.robot_speed * self.dt > max_step:
            raise ValueError(f"Scenario.robot_speed {self.robot_speed} crosses the whole arena in one step")
        check_static_geometry(self)
        if not self.obstacles:
            return
        # all obstacles at once; the error names the first offender
        pos, vel, rad = self._arrays["positions"], self._arrays["velocities"], self._arrays["radii"]
        outside = (pos[:, 0] < xmin + rad) | (pos[:, 0] > xmax - rad) | (pos[:, 1] < ymin + rad) | (pos[:, 1] > ymax - rad)
        for i in np.flatnonzero(outside)[:1]:
            ob = self.obstacles[i]
            raise ValueError(f"Scenario.obstacles[{i}] at {ob.center} with radius {ob.radius} is not inside the arena {self.bounds}")
        for label, point in (("start", self.start), ("goal", self.goal)):
            overlap = np.hypot(pos[:, 0] - point[0], pos[:, 1] - point[1]) <= rad + r
            for i in np.flatnonzero(overlap)[:1]:
                raise ValueError(f"Scenario.obstacles[{i}] at {self.obstacles[i].center} overlaps the robot at the {label} {point}")
        for first in range(0, len(pos), _GAP_ROWS):  # in blocks of rows: the first overlap in row order, memory bounded
            block = slice(first, first + _GAP_ROWS)
            gaps = np.hypot(pos[block, None, 0] - pos[None, :, 0], pos[block, None, 1] - pos[None, :, 1]) - rad[block, None] - rad[None, :]
            rows = np.arange(gaps.shape[0])
            gaps[rows, rows + first] = np.inf
            for i, j in np.argwhere(gaps < -TOUCHING_TOLERANCE)[:1]:  # touching is allowed
                i += first
                raise ValueError(f"Scenario.obstacles[{i}] at {self.obstacles[i].center} overlaps Scenario.obstacles[{j}] at {self.obstacles[j].center}")
        too_fast = np.hypot(vel[:, 0], vel[:, 1]) * self.dt > max_step
        for i in np.flatnonzero(too_fast)[:1]:
            raise ValueError(
                f"Scenario.obstacles[{i}].velocity {self.obstacles[i].velocity} crosses the whole arena in one step; "
                f"lower the speed or delta_d"
            )
        for i, ob in enumerate(self.obstacles):
            if not self.behaviour_of(i).goal_directed:
                continue
            if ob.goal is None:
                raise ValueError(f"Scenario.obstacles[{i}]: behaviour {self.behaviour_of(i).model!r} needs a goal (Obstacle.goal)")
            gx, gy = ob.goal
            if not (xmin + ob.radius <= gx <= xmax - ob.radius and ymin + ob.radius <= gy <= ymax - ob.radius):
                raise ValueError(f"Scenario.obstacles[{i}].goal {ob.goal} is not inside the arena {self.bounds} (radius {ob.radius})")
            if ob.preferred_speed * self.dt > max_step:
                raise ValueError(f"Scenario.obstacles[{i}].preferred_speed {ob.preferred_speed} crosses the whole arena in one step")

    # -- derived facts -------------------------------------------------------------------------
    @property
    def n_obstacles(self) -> int:
        return len(self.obstacles)

    @property
    def arena_diagonal(self) -> float:
        xmin, ymin, xmax, ymax = self.bounds
        return math.hypot(xmax - xmin, ymax - ymin)

    @property
    def static_segments(self) -> np.ndarray:
        """The walls and polygons as read-only capsule rows ``(x0, y0, x1, y1, half_thickness)``
        (``statics.py``): walls first, then each polygon's edges; ``(0, 5)`` without any."""
        return self._segments

    def behaviour_of(self, i: int) -> Behaviour:
        """Obstacle ``i``'s motion model: its own, else the scenario's."""
        own = self.obstacles[i].behaviour
        return self.behaviour if own is None else own

    @property
    def goal_directed(self) -> bool:
        """Whether any obstacle steers itself (then its moves depend on the others, and maybe the robot)."""
        if self.behaviour.goal_directed:
            return True
        return any(ob.behaviour is not None and ob.behaviour.goal_directed for ob in self.obstacles) if self.obstacles else False

    def top_speeds(self) -> np.ndarray:
        """The fastest each obstacle can move (m/s): its speed, or for a goal-directed one the larger
        of that and its preferred speed (what sizes the physics substeps)."""
        v = self._arrays["velocities"]
        speeds = np.hypot(v[:, 0], v[:, 1])
        if self.goal_directed:
            for i, ob in enumerate(self.obstacles):
                if self.behaviour_of(i).goal_directed:
                    speeds[i] = max(speeds[i], ob.preferred_speed)
        return speeds

    @property
    def delta_d(self) -> float:
        """The largest Δd among the obstacles (all equal once set by :meth:`with_delta_d`); 0 if none move.
        For goal-directed obstacles, ``preferred_speed * dt / radius``."""
        if self.goal_directed:
            return max((self.top_speeds() * self.dt / self._arrays["radii"]).tolist(), default=0.0)
        return max((ob.speed * self.dt / ob.radius for ob in self.obstacles), default=0.0)

    def with_robot_visible(self, visible: bool) -> Scenario:
        """This scene with the robot seen by the humans or not; nothing else changes, so nothing is
        checked again (CrowdNav's square crossing may start a human on the robot's goal, which a new
        scene would refuse: ``pathplan_env.scenarios.crowdnav.crowdnav_test_case`` keeps such cases as CrowdNav draws them)."""
        if not isinstance(visible, (bool, np.bool_)):
            raise ValueError(f"visible must be True or False, got {visible!r}")
        copy = object.__new__(Scenario)
        object.__setattr__(copy, "__dict__", dict(self.__dict__))
        object.__setattr__(copy, "robot_visible", bool(visible))
        return copy

    def _alike(self) -> tuple | None:
        """``(obstacles, radius, preferred speed, goals (n, 2), never written)`` when every obstacle of this
        scene has that radius and preferred speed (a Python float), its goal the row of ``goals``, no
        behaviour of its own and a scenario's goal-directed behaviour: what a crowd family records when
        it builds the scene (``crowd_placement._crowd``), so that a reset reads its humans once. A
        record whose obstacles are not this scene's (a copy given new obstacles) is none."""
        kept = self.__dict__.get("_humans_alike")
        return kept if kept is not None and kept[0] is self.obstacles else None

    def with_delta_d(self, delta_d: float, rng: np.random.Generator) -> Scenario:
        """A copy whose every obstacle moves exactly ``delta_d`` radii per step.

        Obstacles that already move keep their direction; resting ones get a direction from ``rng``.
        Goal-directed obstacles get that preferred speed instead (their velocity is theirs to choose).
        """
        delta_d = float(delta_d)
        if not (math.isfinite(delta_d) and delta_d >= 0):
            raise ValueError(f"delta_d must be finite and >= 0, got {delta_d!r}")
        angles = rng.uniform(0.0, 2 * math.pi, size=len(self.obstacles))
        velocities, radii = self._arrays["velocities"], self._arrays["radii"]
        alike = self._alike()  # (a crowd family's humans: one radius, one speed, no behaviour of their own)
        if len(radii) and delta_d * (alike[1] if alike is not None else float(radii.max())) > self.arena_diagonal:
            raise ValueError(f"delta_d {delta_d} makes obstacles cross the whole arena in one step; lower delta_d")
        if self.behaviour.goal_directed and (alike is not None or all(ob.behaviour is None for ob in self.obstacles)):
            return self._with_preferred_speeds(delta_d, None)  # a crowd: no obstacle bounces, no bounce velocity to compute
        speeds = np.hypot(velocities[:, 0], velocities[:, 1])
        moving = speeds > 0
        units = np.where(
            moving[:, None], velocities / np.where(moving, speeds, 1.0)[:, None], np.stack([np.cos(angles), np.sin(angles)], axis=1)
        )
        new_velocities = (delta_d * radii / self.dt)[:, None] * units
        if self.goal_directed:
            return self._with_preferred_speeds(delta_d, new_velocities)
        moved = tuple(
            Obstacle._from_checked(ob.center, ob.radius, (vx, vy)) for ob, (vx, vy) in zip(self.obstacles, new_velocities.tolist())
        )
        # only the velocities change, and they were just checked: copy without re-validating the geometry
        scenario = copy.copy(self)
        object.__setattr__(scenario, "obstacles", moved)
        new_velocities.flags.writeable = False
        object.__setattr__(scenario, "_arrays", {**self._arrays, "velocities": new_velocities})
        return scenario

    def _with_preferred_speeds(self, delta_d: float, bounce_velocities: np.ndarray | None) -> Scenario:
        """The goal-directed obstacles at Δd's preferred speed, the others at ``bounce_velocities``:
        a copy that is not validated again (a third of a crowd family's reset): only speeds change,
        and :meth:`with_delta_d` has checked them against the arena (the fields are the values
        ``dataclasses.replace`` would normalise them to: tested)."""
        if bounce_velocities is None and self._speeds_hold(delta_d):
            # every human already walks at Δd's speed (a crowd family draws them so): nothing changes,
            # so the obstacles and their arrays are shared (rebuilding them was a tenth of a crowd's reset)
            scenario = object.__new__(Scenario)
            scenario.__dict__.update(self.__dict__)
            return scenario
        obstacles, velocities = [], None if bounce_velocities is None else bounce_velocities.tolist()
        for i, ob in enumerate(self.obstacles):
            if self.behaviour_of(i).goal_directed:
                speed, velocity = delta_d * ob.radius / self.dt, ob.velocity
            else:
                speed, velocity = ob.preferred_speed, tuple(velocities[i])
            moved = object.__new__(Obstacle)  # copy.copy of a frozen dataclass costs ten times this
            moved.__dict__.update(ob.__dict__, preferred_speed=speed, velocity=velocity)
            obstacles.append(moved)
        scenario = object.__new__(Scenario)  # a copy (copy.copy of a frozen dataclass costs ten times this)
        scenario.__dict__.update(self.__dict__)
        object.__setattr__(scenario, "obstacles", tuple(obstacles))
        n = len(obstacles)
        new_velocities = np.array([ob.velocity for ob in obstacles], dtype=np.float64).reshape(n, 2)
        new_velocities.flags.writeable = False
        object.__setattr__(scenario, "_arrays", {**self._arrays, "velocities": new_velocities})
        return scenario

    def _speeds_hold(self, delta_d: float) -> bool:
        """Whether every obstacle's preferred speed is already ``delta_d * radius / dt``, bit for bit
        (a Python float, the sign of a zero included): :meth:`_with_preferred_speeds` of a crowd would change nothing."""
        dt = self.dt
        alike = self._alike()
        for ob in self.obstacles if alike is None else self.obstacles[:1]:  # (alike: every one's is the first's)
            speed = delta_d * ob.radius / dt
            kept = ob.preferred_speed
            if type(kept) is not float or kept != speed or (speed == 0.0 and math.copysign(1.0, kept) != math.copysign(1.0, speed)):
                return False
        return True

    @classmethod
    def from_dict(cls, data: dict) -> Scenario:
        """A scenario from its ``dataclasses.asdict`` form (what a JSON ``EnvSpec`` holds), validated."""
        if not isinstance(data, dict):
            raise ValueError(f"scenario must be a preset name, a Scenario or its dict form, got {type(data).__name__}")
        fields = {f.name for f in dataclasses.fields(cls)}
        unknown = [key for key in data if key not in fields]
        if unknown:
            raise ValueError(f"scenario dict: unknown fields {sorted(map(short, unknown))}; known: {sorted(fields)}")
        raw = data.get("obstacles", ())
        if not isinstance(raw, (list, tuple)):
            raise ValueError(f"Scenario.obstacles must be a list of obstacles, got {short(raw)}")
        if len(raw) > MAX_OBSTACLES:  # before any obstacle is built, let alone their pairs compared
            raise ValueError(f"Scenario.obstacles: {len(raw)} obstacles, more than the {MAX_OBSTACLES} a scenario may hold")
        obstacle_fields = {f.name for f in dataclasses.fields(Obstacle)}
        obstacles = []
        for i, ob in enumerate(raw):
            if isinstance(ob, dict):
                unknown = [key for key in ob if key not in obstacle_fields]
                if unknown:
                    raise ValueError(f"Scenario.obstacles[{i}]: unknown fields {sorted(map(short, unknown))}; known: {sorted(obstacle_fields)}")
                try:
                    ob = Obstacle(**ob)
                except TypeError as error:
                    raise ValueError(f"Scenario.obstacles[{i}]: {error}") from None
                except ValueError as error:
                    raise ValueError(f"Scenario.obstacles[{i}]: {error}") from None
            elif not isinstance(ob, Obstacle):
                raise ValueError(f"Scenario.obstacles[{i}] must be a mapping of Obstacle fields, got {short(ob)}")
            obstacles.append(ob)
        missing = sorted(f.name for f in dataclasses.fields(cls) if f.default is dataclasses.MISSING and f.name not in data)
        if missing:
            raise ValueError(f"scenario dict: missing fields {missing}")
        return cls(**{**data, "obstacles": tuple(obstacles)})

    def arrays(self) -> dict[str, np.ndarray]:
        """Obstacle data as read-only float64 arrays: ``positions`` (N, 2), ``velocities`` (N, 2), ``radii`` (N,)."""
        return dict(self._arrays)


_SCENARIO_DEFAULTS = {f.name: f.default for f in dataclasses.fields(Scenario)}
_SCENARIO_REQUIRED = frozenset(name for name, default in _SCENARIO_DEFAULTS.items() if default is dataclasses.MISSING)


__all__ = ["MAX_COORDINATE", "MAX_OBSTACLES", "MIN_LENGTH", "Obstacle", "Scenario", "check_delta_d", "check_n_obstacles"]
