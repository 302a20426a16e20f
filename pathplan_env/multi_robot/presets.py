"""Multi-robot scenes by name, each drawn from the env's ``np_random`` (small seeded jitter).

- ``multi-circle-<n>``: gym-collision-avoidance's circle: ``n`` robots evenly on a circle of radius 4 m
  (each angle jittered by up to a tenth of the spacing, each radius by up to 0.1 m), each swapping to
  its antipode, in a 12 m x 12 m arena; ``multi-circle-<n>-bouncing`` adds 8 bouncing obstacles
  (radii 0.4-0.6 m, Δd 0.25 unless given), clear of every start and goal by 0.5 m.
- ``multi-swap-2``: gym-collision-avoidance's swap: two robots 6 m apart head-on (lateral jitter up to 0.05 m).
- ``multi-crossing-<n>``: two groups of ``n / 2`` crossing at right angles (west to east, south to north).
- ``multi-crowd-<n>``: ``n`` robots on a circle of radius 3 m among CrowdNav's 5 ORCA humans on
  their circle of 4 m (the humans see the robots), at CrowdNav's speeds, dt and 25 s.
- ``multi-corridor-<n>``, ``multi-doorway-<n>``: the single env's corridor and doorway walls, half
  the robots going each way (no obstacles); ``multi-maze-<n>``: the shipped maze map, each robot
  between two points drawn in its free space.

The robots are the random preset's: radius 0.2 m, 2.5 m/s, dt 0.1 s (CrowdNav's in ``multi-crowd``).
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np

from pathplan_env.multi_robot.scene import MultiScenario, RobotSpec
from pathplan_env.scenarios.crowdnav import crowdnav_scenario
from pathplan_env.scenarios.files import MAX_SCENE_BYTES, is_scenario_file
from pathplan_env.scenarios.presets import RANDOM_RADIUS_RANGE, RANDOM_ROBOT_SPEED
from pathplan_env.scenarios.scenario import Obstacle, Scenario
from pathplan_env.scenarios.wall_families import corridor, doorway
from pathplan_env.validation import load_json, load_yaml, read_text

CIRCLE_RADIUS = 4.0
ARENA = (-6.0, -6.0, 6.0, 6.0)
ROBOT_RADIUS, DT = 0.2, 0.1
MAX_ROBOTS = 32
#: The Δd of the bouncing obstacles when the env's ``delta_d`` is None (the random preset's).
BOUNCING_DELTA_D = 0.25
BOUNCING_OBSTACLES = 8
_TRIES = 200


def _world(bounds, start, goal, **fields) -> Scenario:
    return Scenario(bounds=bounds, start=start, goal=goal, robot_radius=ROBOT_RADIUS, robot_speed=RANDOM_ROBOT_SPEED, dt=DT, **fields)


def _robots(starts, goals) -> tuple[RobotSpec, ...]:
    return tuple(RobotSpec(tuple(map(float, s)), tuple(map(float, g))) for s, g in zip(starts, goals))


def circle(rng: np.random.Generator, n: int, radius: float = CIRCLE_RADIUS) -> tuple[np.ndarray, np.ndarray]:
    """Starts on a circle and goals at their antipodes (angles and radii jittered)."""
    angles = 2 * math.pi * np.arange(n) / n + rng.uniform(-0.1, 0.1, n) * (2 * math.pi / n)
    radii = radius + rng.uniform(-0.1, 0.1, n)
    starts = np.stack([radii * np.cos(angles), radii * np.sin(angles)], axis=1)
    return starts, -starts


def multi_circle(rng: np.random.Generator, n: int) -> MultiScenario:
    starts, goals = circle(rng, n)
    return MultiScenario(_world(ARENA, starts[0], goals[0], name=f"multi-circle-{n}"), _robots(starts, goals), name=f"multi-circle-{n}")


def multi_circle_bouncing(rng: np.random.Generator, n: int) -> MultiScenario:
    """The circle among 8 bouncing obstacles (at rest here: the env gives them Δd 0.25 or its ``delta_d``)."""
    starts, goals = circle(rng, n)
    ends = np.concatenate([starts, goals])
    obstacles: list[tuple[np.ndarray, float]] = []
    xmin, ymin, xmax, ymax = ARENA
    for _ in range(_TRIES * BOUNCING_OBSTACLES):
        if len(obstacles) == BOUNCING_OBSTACLES:
            break
        r = float(rng.uniform(*RANDOM_RADIUS_RANGE))
        c = rng.uniform([xmin + r, ymin + r], [xmax - r, ymax - r])
        if np.min(np.hypot(*(ends - c).T)) < r + ROBOT_RADIUS + 0.5:
            continue
        if any(math.dist(c, o) < r + ro + 0.1 for o, ro in obstacles):
            continue
        obstacles.append((c, r))
    name = f"multi-circle-{n}-bouncing"
    world = _world(ARENA, starts[0], goals[0], obstacles=tuple(Obstacle(tuple(map(float, c)), r) for c, r in obstacles), name=name)
    return MultiScenario(world, _robots(starts, goals), name=name)


def multi_swap(rng: np.random.Generator, n: int) -> MultiScenario:
    if n != 2:
        raise ValueError(f"scenario: multi-swap takes 2 robots, got {n}")
    jitter = rng.uniform(-0.05, 0.05, 2)
    starts = np.array([[-3.0, jitter[0]], [3.0, jitter[1]]])
    goals = np.array([[3.0, jitter[0]], [-3.0, jitter[1]]])
    return MultiScenario(_world((-5.0, -3.0, 5.0, 3.0), starts[0], goals[0], name="multi-swap-2"), _robots(starts, goals), name="multi-swap-2")


def multi_crossing(rng: np.random.Generator, n: int) -> MultiScenario:
    if n % 2:
        raise ValueError(f"scenario: multi-crossing takes an even number of robots, got {n}")
    half = n // 2
    lanes = np.linspace(-2.0, 2.0, half) if half > 1 else np.zeros(1)
    lanes = lanes + rng.uniform(-0.05, 0.05, half)
    west = np.stack([np.full(half, -5.0) + rng.uniform(-0.3, 0.3, half), lanes], axis=1)
    south = np.stack([lanes[::-1], np.full(half, -5.0) + rng.uniform(-0.3, 0.3, half)], axis=1)
    starts = np.concatenate([west, south])
    goals = np.concatenate([west * [-1, 1], south * [1, -1]])
    name = f"multi-crossing-{n}"
    return MultiScenario(_world(ARENA, starts[0], goals[0], name=name), _robots(starts, goals), name=name)


def multi_crowd(rng: np.random.Generator, n: int, humans: int | None = None) -> MultiScenario:
    """Robots on a 3 m circle among CrowdNav's circle-crossing humans (its 5, or ``humans``), who see them."""
    crowd = humans
    for _ in range(_TRIES):
        humans = crowdnav_scenario("circle-crossing", rng, crowd, visible=True)
        starts, goals = circle(rng, n, 3.0)
        positions = humans.arrays()["positions"]
        reach = humans.robot_radius + humans.arrays()["radii"][0]
        clear = all(np.min(np.hypot(*(positions - p).T)) > reach + 0.1 for p in np.concatenate([starts, goals]))
        if clear:
            name = f"multi-crowd-{n}"
            import dataclasses

            world = dataclasses.replace(humans, start=tuple(starts[0]), goal=tuple(goals[0]), name=name)
            return MultiScenario(world, _robots(starts, goals), name=name)
    raise ValueError(f"scenario: could not place {n} robots clear of the humans")


def _walled(layout: Scenario, name: str, left, right, n: int, rng: np.random.Generator) -> MultiScenario:
    """``n`` robots in ``layout``'s walls: half from the ``left`` box to the ``right`` one, half back."""
    half = n - n // 2

    def column(box, k):
        x0, y0, x1, y1 = box
        ys = np.linspace(y0, y1, k) if k > 1 else np.array([(y0 + y1) / 2])
        return np.stack([np.full(k, (x0 + x1) / 2) + rng.uniform(-0.1, 0.1, k), ys], axis=1)

    a, b = column(left, half), column(right, half)
    starts = np.concatenate([a, b[: n // 2]])
    goals = np.concatenate([b, a[: n // 2]])
    world = Scenario(bounds=layout.bounds, start=tuple(starts[0]), goal=tuple(goals[0]), robot_radius=ROBOT_RADIUS, robot_speed=RANDOM_ROBOT_SPEED,
                     dt=DT, walls=layout.walls, wall_thickness=layout.wall_thickness, name=name)  # fmt: skip
    return MultiScenario(world, _robots(starts, goals), name=name)


def multi_corridor(rng: np.random.Generator, n: int) -> MultiScenario:
    return _walled(corridor(rng, 0), f"multi-corridor-{n}", (0.6, 1.6, 1.4, 4.4), (14.6, 1.6, 15.4, 4.4), n, rng)


def multi_doorway(rng: np.random.Generator, n: int) -> MultiScenario:
    return _walled(doorway(rng, 0), f"multi-doorway-{n}", (1.5, 1.0, 2.5, 7.0), (9.5, 1.0, 10.5, 7.0), n, rng)


def multi_maze(rng: np.random.Generator, n: int) -> MultiScenario:
    """``n`` robots in the shipped maze (``pathplan_env.maps``), starts and goals drawn in its free
    space with 0.1 m of clearance and apart from each other; robot ``i`` goes from start ``i`` to goal ``i``."""
    from pathplan_env.maps.ros_maps import load_shipped_map

    occupancy = load_shipped_map("maze")
    points = occupancy.sample_free(rng, 2 * n, ROBOT_RADIUS + 0.1, min_separation=2 * ROBOT_RADIUS + 0.1)
    starts, goals = points[:n], points[n:]
    name = f"multi-maze-{n}"
    world = Scenario(bounds=occupancy.bounds, start=tuple(starts[0]), goal=tuple(goals[0]), polygons=occupancy.polygons, robot_radius=ROBOT_RADIUS,
                     robot_speed=RANDOM_ROBOT_SPEED, dt=DT, name=name)  # fmt: skip
    return MultiScenario(world, _robots(starts, goals), name=name)


#: The families by prefix: ``<prefix>-<n>`` draws ``n`` robots.
FAMILIES = {"multi-circle": multi_circle, "multi-swap": multi_swap, "multi-crossing": multi_crossing, "multi-crowd": multi_crowd,
            "multi-corridor": multi_corridor, "multi-doorway": multi_doorway, "multi-maze": multi_maze}  # fmt: skip
_NAME = re.compile(r"^(multi-[a-z]+)-(\d+)(-bouncing)?$")
#: The names the docs and tests list (any ``n`` from 2 to :data:`MAX_ROBOTS` works).
PRESETS = (
    tuple(f"multi-circle-{n}" for n in (2, 4, 10, 20))
    + tuple(f"multi-circle-{n}-bouncing" for n in (4, 10))
    + ("multi-swap-2", "multi-crossing-4", "multi-crossing-10", "multi-crowd-4", "multi-corridor-4", "multi-doorway-4", "multi-maze-4")
)


def load_multi_scenario(path) -> MultiScenario:
    """The :class:`MultiScenario` a JSON or YAML file describes: a single-robot scenario file's fields
    (``pathplan_env.scenarios.files``) with a ``robots:`` list in place of the start and goal.

    :raises ValueError: naming the file, and the robot and field where it is invalid.
    """
    path = Path(path)
    text = read_text(path, MAX_SCENE_BYTES, "scenario file")
    try:
        data = load_json(text) if path.suffix.lower() == ".json" else load_yaml(text)
    except RecursionError:
        raise ValueError(f"scenario file {path}: nested too deeply") from None
    except Exception as error:  # a parse error or a duplicate key: the message says where
        raise ValueError(f"scenario file {path}: not valid {path.suffix[1:].upper()}: {error}") from None
    if not isinstance(data, dict):
        raise ValueError(f"scenario file {path}: expected a mapping with a 'robots' list, got {type(data).__name__}")
    data = {"name": path.stem, **data}
    if isinstance(data.get("bounds"), list):
        data["bounds"] = tuple(data["bounds"])
    obstacles = data.get("obstacles", ())
    if isinstance(obstacles, list):
        data["obstacles"] = [{k: tuple(v) if isinstance(v, list) else v for k, v in ob.items()} if isinstance(ob, dict) else ob for ob in obstacles]
    try:
        return MultiScenario.from_dict(data)
    except (ValueError, TypeError) as error:
        raise ValueError(f"scenario file {path}: {error}") from None


def make_multi_scenario(spec, rng: np.random.Generator, delta_d: float | None = None) -> MultiScenario:
    """Resolve a preset name, a :class:`MultiScenario`, its dict form or a JSON/YAML file of it, then apply ``delta_d`` to
    its obstacles (``None``: the scene's own; Δd 0.25 for the ``-bouncing`` presets).

    :raises ValueError: naming ``scenario`` for an unknown name or a robot count out of range.
    """
    if is_scenario_file(spec):
        spec = load_multi_scenario(spec)
    if isinstance(spec, dict):
        spec = MultiScenario.from_dict(spec)
    if isinstance(spec, MultiScenario):
        scene = spec
    elif isinstance(spec, str):
        match = _NAME.match(spec)
        if not match or match.group(1) not in FAMILIES or (match.group(3) and match.group(1) != "multi-circle"):
            raise ValueError(f"scenario: unknown multi-robot preset {spec!r}; known: {list(PRESETS)} (any robot count 2-{MAX_ROBOTS})")
        n = int(match.group(2))
        if not 2 <= n <= MAX_ROBOTS:
            raise ValueError(f"scenario: {spec!r} has {n} robots; presets take 2 to {MAX_ROBOTS}")
        scene = (multi_circle_bouncing if match.group(3) else FAMILIES[match.group(1)])(rng, n)
        if match.group(3) and delta_d is None:
            delta_d = BOUNCING_DELTA_D
    else:
        raise ValueError(f"scenario must be a multi-robot preset name, a MultiScenario or its dict form, got {type(spec).__name__}")
    if delta_d is not None and scene.world.n_obstacles:
        scene = scene.with_world(scene.world.with_delta_d(delta_d, rng))
    return scene


__all__ = ["FAMILIES", "PRESETS", "load_multi_scenario", "make_multi_scenario"]
