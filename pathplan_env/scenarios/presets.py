"""Scenario presets: the paper's three cases, random scenes (sampled from the env's ``np_random``), and
``make_scenario``, which resolves a preset name, a :class:`Scenario` or its dict form and applies Δd."""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path
from typing import NamedTuple

import numba
import numpy as np

from pathplan_env.arguments import check_count
from pathplan_env.scenarios.clutter import CLUTTER_PRESETS
from pathplan_env.scenarios.crowd_families import CROWD_FAMILIES
from pathplan_env.scenarios.crowdnav import CROWDNAV_PRESETS
from pathplan_env.scenarios.map_scenes import MapScenes, is_map_file
from pathplan_env.scenarios.scenario import Obstacle, Scenario, Vec2
from pathplan_env.scenarios.variation import VariedScenario
from pathplan_env.scenarios.wall_families import FAMILIES

#: The paper's Table 1 obstacle centres. The paper states nothing else; our assumptions
#: (documented in docs/paper_assumptions.md): start (0, 0), goal (5, 5), arena [-1, 6]^2, so the
#: straight line y = x runs through the obstacles as in the paper's Fig. 1. Radius 1.0 in cases 1-2
#: ("the big circle" of Fig. 1); 0.45 in case 3, where centres (2, 3) and (2, 4) are 1.0 apart and
#: larger discs would overlap.
PAPER_CASES: dict[str, tuple[tuple[Vec2, ...], float]] = {
    "paper-case-1": (((2.0, 3.0),), 1.0),
    "paper-case-2": (((1.0, 2.0), (3.0, 4.0)), 1.0),
    "paper-case-3": (((2.0, 4.0), (1.0, 1.5), (2.0, 3.0), (3.0, 2.0), (4.5, 4.0)), 0.45),
}
PAPER_BOUNDS = (-1.0, -1.0, 6.0, 6.0)
PAPER_START, PAPER_GOAL = (0.0, 0.0), (5.0, 5.0)
ROBOT_RADIUS = 0.2
DT = 0.1
#: Default robot speed: the robot covers half an obstacle radius per step, so at Δd = 0.5 the
#: obstacles move exactly as fast as the robot (CrowdNav's humans and robot share one speed).
ROBOT_STEP_IN_RADII = 0.5


def paper_case(name: str) -> Scenario:
    centers, radius = PAPER_CASES[name]
    return Scenario(
        bounds=PAPER_BOUNDS,
        start=PAPER_START,
        goal=PAPER_GOAL,
        obstacles=tuple(Obstacle(center=c, radius=radius) for c in centers),
        robot_radius=ROBOT_RADIUS,
        robot_speed=ROBOT_STEP_IN_RADII * radius / DT,
        dt=DT,
        name=name,
    )


#: The random preset: a 10 m x 10 m arena (larger beyond 12 obstacles, keeping 12 per 100 m^2),
#: obstacle radii uniform in [0.4, 0.6] m (mean 0.5 m), start and goal at least 6 m apart,
#: obstacles at least 0.1 m apart and clear of the robot's start and goal by 0.5 m.
RANDOM_ARENA_SIDE = 10.0
RANDOM_DENSITY_OBSTACLES = 12
RANDOM_RADIUS_RANGE = (0.4, 0.6)
RANDOM_MIN_START_GOAL = 6.0
RANDOM_OBSTACLE_GAP = 0.1
RANDOM_START_CLEARANCE = 0.5
#: Most obstacles of the random preset: 100 make a 28.9 m arena whose diagonal (41 m) the robot
#: crosses in 163 of the 200 steps; more would make most episodes impossible in time.
RANDOM_MAX_OBSTACLES = 100
RANDOM_ROBOT_SPEED = ROBOT_STEP_IN_RADII * 0.5 * (RANDOM_RADIUS_RANGE[0] + RANDOM_RADIUS_RANGE[1]) / DT  # half a mean radius a step
_CANDIDATES = 64


def random_arena_bounds(n_obstacles: int) -> tuple[float, float, float, float]:
    side = RANDOM_ARENA_SIDE * math.sqrt(max(1.0, n_obstacles / RANDOM_DENSITY_OBSTACLES))
    return (0.0, 0.0, side, side)


class Placement(NamedTuple):
    """Where the random preset's obstacles may go: inside the box ``(xmin, ymin, xmax, ymax)``, more
    than ``endpoint_clearance`` beyond their radius from the start ``(sx, sy)`` and the goal
    ``(gx, gy)``, and more than ``gap`` apart."""

    xmin: float
    ymin: float
    xmax: float
    ymax: float
    sx: float
    sy: float
    gx: float
    gy: float
    endpoint_clearance: float
    gap: float


@numba.njit(cache=True)
def _place_obstacles(unit, radii, placement):
    """Rejection sampling: obstacle ``i`` takes the first of its candidate points ``unit[i]`` that keeps
    clear of the start, the goal and the obstacles placed before it (a :class:`Placement`). Compiled:
    with 50 obstacles the loop over candidates and placed obstacles dominated the reset.

    :return: ``(centers, placed)``; ``placed < len(radii)`` when some obstacle found no free candidate.
    """
    xmin, ymin, xmax, ymax, sx, sy, gx, gy, endpoint_clearance, gap = placement
    n, m = unit.shape[0], unit.shape[1]
    centers = np.empty((n, 2))
    for i in range(n):
        rad = radii[i]
        found = False
        for c in range(m):
            x = xmin + rad + unit[i, c, 0] * (xmax - xmin - 2 * rad)
            y = ymin + rad + unit[i, c, 1] * (ymax - ymin - 2 * rad)
            ok = math.hypot(x - sx, y - sy) > rad + endpoint_clearance
            ok = ok and math.hypot(x - gx, y - gy) > rad + endpoint_clearance
            j = 0
            while ok and j < i:
                ok = math.hypot(x - centers[j, 0], y - centers[j, 1]) > radii[j] + rad + gap
                j += 1
            if ok:
                centers[i, 0], centers[i, 1] = x, y
                found = True
                break
        if not found:
            return centers, i
    return centers, n


def sample_random_scenario(rng: np.random.Generator, n_obstacles: int = 8, delta_d: float | None = None) -> Scenario:
    """Draw a random scenario from ``rng`` (the env passes its ``np_random``).

    Obstacles rest unless ``delta_d`` is given; then they move in random directions at that Δd (the
    same draws and values as ``sample_random_scenario(rng, n).with_delta_d(delta_d, rng)``).
    """
    check_count(n_obstacles, "n_obstacles")
    if n_obstacles > RANDOM_MAX_OBSTACLES:
        raise ValueError(
            f"n_obstacles must be <= {RANDOM_MAX_OBSTACLES} for the random preset, got {n_obstacles}: its arena grows with the "
            f"count (side 10 m x sqrt(n / 12)) and past that outgrows what the robot can cross in the 200-step time limit"
        )
    n = int(n_obstacles)
    bounds = random_arena_bounds(n)
    xmin, ymin, xmax, ymax = bounds
    r = ROBOT_RADIUS
    margin = r + 0.3
    # Generator.uniform's own draws, written as low + (high - low) * random() (bit-identical): under
    # numpy 2, uniform() with array bounds costs 5x this, and the start-goal loop draws a few times.
    # Scalars here are Python floats, the same IEEE operations numpy did on 2-element arrays (whose
    # per-call cost was a tenth of a reset).
    lx, ly = xmin + margin, ymin + margin
    wx, wy = (xmax - margin) - lx, (ymax - margin) - ly
    while True:
        u0, u1, u2, u3 = rng.random(4).tolist()  # (the draws of rng.random((2, 2)), in the same order)
        sx, sy, gx, gy = lx + wx * u0, ly + wy * u1, lx + wx * u2, ly + wy * u3
        if math.hypot(sx - gx, sy - gy) >= RANDOM_MIN_START_GOAL:
            break
    r_low, r_high = RANDOM_RADIUS_RANGE
    draws = rng.random(n + n * _CANDIDATES * 2)  # the radii's draws then the candidates', as two calls drew them (one call: a reset's tenth)
    radii = r_low + (r_high - r_low) * draws[:n]
    unit = draws[n:].reshape(n, _CANDIDATES, 2)
    placement = Placement(xmin, ymin, xmax, ymax, sx, sy, gx, gy, r + RANDOM_START_CLEARANCE, RANDOM_OBSTACLE_GAP)
    centers, placed = _place_obstacles(unit, radii, placement)
    if placed < n:
        raise ValueError(f"n_obstacles: could not place {n} obstacles in the random arena {bounds} (placed {placed})")
    radius_list = radii.tolist()
    if delta_d is None:
        moves = [(0.0, 0.0)] * n
    else:
        angles = (2 * math.pi) * rng.random(n)
        # speed * (cos, sin) per obstacle, in Python floats: the products numpy's broadcast made
        # (np.stack and two broadcasts on a few rows were a tenth of a reset)
        speeds = (delta_d * radii / DT).tolist()
        moves = [(s * c, s * si) for s, c, si in zip(speeds, np.cos(angles).tolist(), np.sin(angles).tolist())]
        if n and delta_d * max(radius_list) > math.hypot(xmax - xmin, ymax - ymin):
            raise ValueError(f"delta_d {delta_d} makes obstacles cross the whole arena in one step; lower delta_d")
    velocities = np.array(moves, np.float64).reshape(n, 2)
    obstacles = tuple(Obstacle._from_checked(tuple(c), rad, v) for c, rad, v in zip(centers.tolist(), radius_list, moves))
    return Scenario._from_checked(
        {"positions": centers, "velocities": velocities, "radii": radii},
        bounds=bounds, start=(sx, sy), goal=(gx, gy), obstacles=obstacles, robot_radius=r,
        robot_speed=RANDOM_ROBOT_SPEED, dt=DT, goal_radius=r, name="random",
    )  # fmt: skip


#: Obstacle count of the random preset when none is given.
RANDOM_DEFAULT_OBSTACLES = 8

#: Δd of the paper's cases and the random preset when none is given: their own default (their
#: obstacles rest until a Δd moves them). CrowdNav's presets keep their humans' own 1 m/s.
DEFAULT_DELTA_D = 0.25

#: Every preset: ``(rng, n_obstacles or None for the preset's own count) -> Scenario``.
PRESETS: dict[str, Callable[[np.random.Generator, int | None], Scenario]] = {
    **{name: (lambda rng, n, name=name: paper_case(name)) for name in PAPER_CASES},
    "random": lambda rng, n: sample_random_scenario(rng, RANDOM_DEFAULT_OBSTACLES if n is None else n),
    **CROWDNAV_PRESETS,
    **FAMILIES,  # static geometry: corridor, doorway, intersection, cluttered-room (families.py)
    **CROWD_FAMILIES,  # their -crowd versions (ORCA humans), maze and maze-crowd (crowd_families.py)
    **CLUTTER_PRESETS,  # clutter and clutter-crowd: a few hundred resting cylinders, movers crossing (clutter.py)
}
#: The presets whose obstacle count ``n_obstacles`` sets; every other scenario has its own obstacles.
COUNTED_PRESETS = frozenset({"random", *CROWDNAV_PRESETS, *FAMILIES, *CROWD_FAMILIES, *CLUTTER_PRESETS})
#: The presets' own Δd, applied when ``make_scenario`` gets none (presets not listed keep their speeds).
PRESET_DELTA_D: dict[str, float] = {**dict.fromkeys(PAPER_CASES, DEFAULT_DELTA_D), "random": DEFAULT_DELTA_D, **dict.fromkeys(FAMILIES, DEFAULT_DELTA_D),
                                 **dict.fromkeys(CROWD_FAMILIES, DEFAULT_DELTA_D), **dict.fromkeys(CLUTTER_PRESETS, DEFAULT_DELTA_D)}  # fmt: skip


def make_scenario(
    spec: str | Scenario, rng: np.random.Generator, n_obstacles: int | None = None, delta_d: float | None = None
) -> Scenario:
    """Resolve a preset name, a :class:`Scenario` or its dict form, then apply ``delta_d``.

    ``delta_d=None`` keeps the scenario's own speeds: a preset's own Δd (:data:`PRESET_DELTA_D`: 0.25
    for the paper's cases and ``random``; CrowdNav's humans their 1 m/s), a :class:`Scenario`'s own
    velocities. ``n_obstacles`` sets the random and CrowdNav presets' counts (``None``: their own)."""
    if isinstance(spec, dict):
        spec = MapScenes.from_dict(spec) if "map" in spec else Scenario.from_dict(spec)
    elif isinstance(spec, (str, Path)) and not (isinstance(spec, str) and spec in PRESETS) and is_map_file(spec):
        spec = MapScenes(str(spec))
    if isinstance(spec, MapScenes):
        return spec(rng, n_obstacles, delta_d)
    if n_obstacles is not None and not (isinstance(spec, str) and spec in COUNTED_PRESETS):
        named = repr(spec) if isinstance(spec, str) else "a Scenario"
        raise ValueError(f"n_obstacles: {named} has its own obstacles (leave n_obstacles None); it applies to the presets {sorted(COUNTED_PRESETS)}")
    if isinstance(spec, Scenario):
        scenario = spec
    elif isinstance(spec, VariedScenario):  # a scene file's variation: a scene of its own each reset
        scenario = spec.draw(rng)
    elif isinstance(spec, str):
        if spec not in PRESETS:
            raise ValueError(f"scenario: unknown preset {spec!r}; known presets: {sorted(PRESETS)}")
        if delta_d is None:
            delta_d = PRESET_DELTA_D.get(spec)
        if spec == "random":  # Δd applied while sampling: the same draws, without a second copy
            return sample_random_scenario(rng, RANDOM_DEFAULT_OBSTACLES if n_obstacles is None else n_obstacles, delta_d)
        if spec in CLUTTER_PRESETS:  # Δd moves their movers only: the cylinders are static geometry
            return CLUTTER_PRESETS[spec](rng, n_obstacles, delta_d)
        scenario = PRESETS[spec](rng, n_obstacles)
    else:
        raise ValueError(f"scenario must be a preset name or a Scenario, got {type(spec).__name__}")
    if delta_d is not None:
        scenario = scenario.with_delta_d(delta_d, rng)
    return scenario
