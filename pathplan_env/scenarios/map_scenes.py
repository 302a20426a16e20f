"""A map file is a scenario: seeded episodes on a ROS map_server map.

    gym.make("DynamicObstacle-v0", scenario="my_map.yaml")                       # a map_server YAML
    gym.make("DynamicObstacle-v0", scenario={"map": "my_map.yaml", "n_obstacles": 8, "behaviour": "orca"})

A YAML file is a map when it holds map_server's fields (``image``, ``resolution``, ``origin``), not
by a guess from its name; any other YAML or JSON is a scene file (:mod:`.files`). Each episode draws
from the env's seed (:func:`pathplan_env.scenarios.on_maps.scenario_kwargs`): the start and goal in
free space with the robot's radius plus ``clearance`` to every wall, at least
``min_start_goal_distance`` apart (default 0.4 of the map's diagonal) and connected (the exact
shortest path between them exists; up to 20 draws), unless given; then ``n_obstacles`` discs
(default 5) of ``obstacle_radius`` in free space, bouncing (``behaviour="bounce"``) or ORCA humans
(``"orca"``, each with a goal drawn in free space, routed around the walls as in the crowd
families), moving at Δd (0.25 unless told) as everywhere. The episodes are named by the map's stem.
A map whose free space cannot hold the robot is a ``ValueError`` naming it.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np

from pathplan_env.arguments import check_count
from pathplan_env.crowds.behaviours import make_behaviour
from pathplan_env.validation import load_yaml, read_text

#: map_server's fields that make a YAML a map.
MAP_FIELDS = frozenset({"image", "resolution", "origin"})
DEFAULT_OBSTACLES = 5
DEFAULT_DELTA_D = 0.25
_CONNECT_TRIES = 20


def is_map_file(spec) -> bool:
    """Whether ``spec`` names an existing YAML file holding map_server's fields."""
    if not isinstance(spec, (str, Path)) or Path(spec).suffix.lower() not in (".yaml", ".yml") or not Path(spec).is_file():
        return False
    return _fields_of(str(Path(spec).resolve()), Path(spec).stat().st_mtime_ns) >= MAP_FIELDS


@lru_cache(maxsize=64)
def _fields_of(path: str, mtime: int) -> frozenset:
    try:
        data = load_yaml(read_text(Path(path), 1 << 20, "map file"))
    except Exception:  # not YAML we can read: not a map (the scene-file loader gives the error)
        return frozenset()
    return frozenset(data) if isinstance(data, dict) else frozenset()


@lru_cache(maxsize=16)
def _load(path: str, mtime: int):
    from pathplan_env.maps.ros_maps import load_ros_map

    return load_ros_map(path)  # immutable: one load a file version per process


@dataclass(frozen=True)
class MapScenes:
    """Episodes on the map ``map`` (a map_server YAML); the module docstring says how they are drawn.

    :param n_obstacles: moving discs when the run gives no count.
    :param behaviour: ``"bounce"`` or ``"orca"`` (humans with goals).
    :param start: the robot's start, fixed (``None``: drawn); ``goal`` likewise.
    """

    map: str
    n_obstacles: int = DEFAULT_OBSTACLES
    obstacle_radius: float = 0.3
    behaviour: str = "bounce"
    robot_radius: float = 0.2
    robot_speed: float = 2.5
    dt: float = 0.1
    clearance: float = 0.1
    min_start_goal_distance: float | None = None
    start: tuple[float, float] | None = None
    goal: tuple[float, float] | None = None
    name: str | None = None

    def __post_init__(self):
        path = Path(self.map)
        if not is_map_file(path):
            raise ValueError(f"map {self.map!r}: not a map_server YAML with {sorted(MAP_FIELDS)}")
        object.__setattr__(self, "map", str(path))
        check_count(self.n_obstacles, "n_obstacles")
        if self.behaviour not in ("bounce", "orca"):
            raise ValueError(f"map {path.name}: behaviour must be 'bounce' or 'orca', got {self.behaviour!r}")
        for field in ("obstacle_radius", "robot_radius", "robot_speed", "dt"):
            value = getattr(self, field)
            if not (isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value) and value > 0):
                raise ValueError(f"map {path.name}: {field} must be a finite number > 0, got {value!r}")
        if self.name is None:
            object.__setattr__(self, "name", path.stem)
        occupancy = self.occupancy
        if not (occupancy._free_distance >= self.robot_radius).any():
            raise ValueError(f"map {path.name}: its free space cannot hold the robot (radius {self.robot_radius} m)")

    @classmethod
    def from_dict(cls, data: dict) -> MapScenes:
        """The dict form: ``{"map": path, ...}`` with this class's fields."""
        unknown = set(data) - {f.name for f in dataclasses.fields(cls)}
        if unknown:
            raise ValueError(f"map scenario: unknown fields {sorted(unknown)}; known: {[f.name for f in dataclasses.fields(cls)]}")
        fields = {k: tuple(v) if isinstance(v, list) else v for k, v in data.items()}
        return cls(**fields)

    @property
    def occupancy(self):
        return _load(str(Path(self.map).resolve()), Path(self.map).stat().st_mtime_ns)

    def __call__(self, rng: np.random.Generator, n_obstacles: int | None = None, delta_d: float | None = None):
        """One episode's :class:`~pathplan_env.Scenario`, drawn from ``rng``."""
        from pathplan_env.scenarios.crowdnav import HUMAN_ORCA
        from pathplan_env.scenarios.on_maps import scenario_kwargs
        from pathplan_env.scenarios.scenario import Obstacle, Scenario

        n = self.n_obstacles if n_obstacles is None else check_count(n_obstacles, "n_obstacles")
        occupancy = self.occupancy
        for _ in range(_CONNECT_TRIES):
            kwargs = scenario_kwargs(occupancy, rng, n_obstacles=0, obstacle_radius=self.obstacle_radius, robot_radius=self.robot_radius,
                                     margin=self.clearance, min_start_goal_distance=self.min_start_goal_distance)  # fmt: skip
            kwargs["start"] = kwargs["start"] if self.start is None else tuple(map(float, self.start))
            kwargs["goal"] = kwargs["goal"] if self.goal is None else tuple(map(float, self.goal))
            layout = Scenario(**kwargs, robot_radius=self.robot_radius, robot_speed=self.robot_speed, dt=self.dt, name=self.name)
            if self._connected(layout):
                break
        else:
            raise ValueError(f"map {Path(self.map).name}: no connected start and goal in {_CONNECT_TRIES} draws")
        keep = self.robot_radius + self.obstacle_radius + self.clearance
        avoid = [(layout.start, keep), (layout.goal, keep)]
        centres = occupancy.sample_free(rng, n, self.obstacle_radius + self.clearance, avoid=avoid, min_separation=2 * self.obstacle_radius + self.clearance)
        if self.behaviour == "orca":
            goals = occupancy.sample_free(rng, n, self.obstacle_radius + self.clearance, min_separation=2 * self.obstacle_radius + self.clearance)
            obstacles = tuple(Obstacle(center=tuple(map(float, c)), radius=self.obstacle_radius, goal=tuple(map(float, g))) for c, g in zip(centres, goals))
            behaviour = HUMAN_ORCA
        else:
            obstacles = tuple(Obstacle(center=tuple(map(float, c)), radius=self.obstacle_radius) for c in centres)
            behaviour = make_behaviour("bounce")
        scenario = dataclasses.replace(layout, obstacles=obstacles, behaviour=behaviour)
        return scenario.with_delta_d(DEFAULT_DELTA_D if delta_d is None else delta_d, rng)

    @staticmethod
    def _connected(layout) -> bool:
        from pathplan_env.geometry.reference_path import shortest_path_to_goal

        return math.isfinite(shortest_path_to_goal(layout))
