"""Static clutter: ``clutter`` and ``clutter-crowd``, fields of a few hundred small resting cylinders a
robot must thread, the cluttered-navigation benchmarks' worlds (cylinders of radius 0.075 m, a robot
of radius 0.333 m, 10 m from start to goal).

Every episode draws, from the env's seed:

- the start on the field's left edge and the goal on its right (x 1 and 11 m, y in [1.5, 6.5]);
- a corridor of width ``corridor_width`` (default 0.8 m: the robot's 0.666 m and 6.7 cm each side)
  along a bent line from start to goal through three drawn points; no cylinder comes nearer than
  half of it to that line, so every episode is solvable and ``oracle-static``, whose flying margin
  is 2.1 cm at this robot's 0.25 m step, proves it;
- ``n_cylinders`` (default 200) cylinders, *on a grid* (a lattice of pitch ``grid_pitch``, cells drawn
  without repeat, each cylinder jittered inside its cell) or *off it* (drawn uniformly, kept
  ``min_gap`` apart), each layout half of the episodes unless ``layout`` says which; none within
  0.5 m of the robot's start or goal disc. The count is the density: 200 in the 8.8 m x 8 m field
  leave gaps of mostly less than the robot's width outside the corridor.

The moving obstacles (``n_obstacles``, the preset's count) cross the field: ``clutter`` has
bouncing discs of radius 0.2 m drawn in its free space (none by default), ``clutter-crowd`` ORCA
humans (CrowdNav's radius 0.3 m, default 4) walking across it in two lanes kept free of cylinders
(1.4 m wide, at x 4.75 and 7.25 m), across the robot's corridor, each way. Δd moves only them (the
cylinders rest whatever Δd: they are the static geometry), 0.25 unless told.
"""

from __future__ import annotations

import math

import numpy as np

from pathplan_env.arguments import check_count
from pathplan_env.geometry.contacts import point_segment_distance
from pathplan_env.scenarios.crowdnav import HUMAN_ORCA, HUMAN_RADIUS
from pathplan_env.scenarios.scenario import Obstacle, Scenario

BOUNDS = (0.0, 0.0, 12.0, 8.0)
FIELD = (1.6, 0.0, 10.4, 8.0)
CYLINDER_RADIUS = 0.075
ROBOT_RADIUS = 0.333
ROBOT_SPEED = 2.5
DT = 0.1
N_CYLINDERS = 200
CORRIDOR_WIDTH = 0.8
MIN_GAP = 0.0
GRID_PITCH = 0.3
LAYOUTS = ("grid", "scatter")
START_CLEARANCE = 0.5
MOVER_RADIUS = 0.2
LANES = (4.75, 7.25)
LANE_WIDTH = 1.4
DEFAULT_DELTA_D = 0.25


def clutter_scenario(rng: np.random.Generator, n_obstacles: int | None = None, delta_d: float | None = None, *, crowd: bool = False,
                     n_cylinders: int = N_CYLINDERS, corridor_width: float = CORRIDOR_WIDTH, min_gap: float = MIN_GAP,
                     grid_pitch: float = GRID_PITCH, layout: str | None = None) -> Scenario:  # fmt: skip
    """One clutter episode drawn from ``rng`` (the module docstring says how).

    :param n_obstacles: the moving obstacles (default 0 bouncing discs; 4 humans with ``crowd``).
    :param delta_d: their Δd (default 0.25); the cylinders rest.
    :param n_cylinders: the cylinders' count (the density).
    :param corridor_width: the width of the guaranteed corridor (m), more than the robot's diameter.
    :param min_gap: the least gap between two cylinders off the grid (m; 0: they may touch).
    :param grid_pitch: the lattice's pitch on the grid (m), at least a cylinder's diameter plus ``min_gap``.
    :param layout: ``"grid"``, ``"scatter"``, or ``None`` (drawn: each half of the episodes).
    :raises ValueError: naming the parameter when the field cannot hold the cylinders or the corridor the robot.
    """
    n_movers = (4 if crowd else 0) if n_obstacles is None else check_count(n_obstacles, "n_obstacles")
    delta_d = DEFAULT_DELTA_D if delta_d is None else float(delta_d)
    n_cylinders = check_count(n_cylinders, "n_cylinders")
    if not corridor_width > 2 * ROBOT_RADIUS:
        raise ValueError(f"corridor_width must be more than the robot's diameter {2 * ROBOT_RADIUS}, got {corridor_width!r}")
    if not (min_gap >= 0 and grid_pitch >= 2 * CYLINDER_RADIUS + min_gap):
        raise ValueError(f"min_gap must be >= 0 and grid_pitch >= {2 * CYLINDER_RADIUS} + min_gap, got {min_gap!r}, {grid_pitch!r}")
    if layout is not None and layout not in LAYOUTS:
        raise ValueError(f"layout must be one of {LAYOUTS} or None, got {layout!r}")
    start = (1.0, 1.5 + 5.0 * rng.random())
    goal = (11.0, 1.5 + 5.0 * rng.random())
    line = np.array([start, *((x, 1.2 + 5.6 * rng.random()) for x in (3.5, 6.0, 8.5)), goal])
    on_grid = (rng.random() < 0.5) if layout is None else layout == "grid"
    keep_out = _keep_out(line, corridor_width, start, goal, crowd)
    centres = _grid(rng, n_cylinders, grid_pitch, min_gap, keep_out) if on_grid else _scatter(rng, n_cylinders, min_gap, keep_out)
    cylinders = [Obstacle(center=tuple(c), radius=CYLINDER_RADIUS) for c in centres.tolist()]
    movers = _humans(rng, n_movers, delta_d, start, goal) if crowd else _bouncers(rng, n_movers, delta_d, centres, start, goal)
    return Scenario(bounds=BOUNDS, start=start, goal=goal, obstacles=(*cylinders, *movers), robot_radius=ROBOT_RADIUS,
                    robot_speed=ROBOT_SPEED, dt=DT, name="clutter-crowd" if crowd else "clutter")  # fmt: skip


def _keep_out(line: np.ndarray, corridor_width: float, start, goal, crowd: bool):
    """``points (k, 2) -> mask`` of the cylinder centres that would narrow the corridor, crowd the
    robot's start or goal, or stand in a lane."""
    corridor = corridor_width / 2 + CYLINDER_RADIUS
    ends = ROBOT_RADIUS + START_CLEARANCE + CYLINDER_RADIUS

    def blocked(points: np.ndarray) -> np.ndarray:
        out = point_segment_distance(points[:, None], line[None, :-1], line[None, 1:]).min(axis=1) < corridor
        out |= (np.hypot(*(points - start).T) < ends) | (np.hypot(*(points - goal).T) < ends)
        if crowd:
            for x in LANES:
                out |= np.abs(points[:, 0] - x) < LANE_WIDTH / 2 + CYLINDER_RADIUS
        return out

    return blocked


def _grid(rng, n: int, pitch: float, min_gap: float, blocked) -> np.ndarray:
    """``n`` cells of the field's lattice (drawn without repeat among the cells clear of ``blocked``),
    each cylinder jittered in its cell so that neighbours keep ``min_gap``."""
    xmin, ymin, xmax, ymax = FIELD
    xs = np.arange(xmin + pitch / 2, xmax, pitch)
    ys = np.arange(ymin + pitch / 2, ymax, pitch)
    cells = np.stack(np.meshgrid(xs, ys, indexing="ij"), axis=-1).reshape(-1, 2)
    inside = (cells[:, 0] >= xmin + CYLINDER_RADIUS) & (cells[:, 0] <= xmax - CYLINDER_RADIUS) & (cells[:, 1] >= ymin + CYLINDER_RADIUS) & (
        cells[:, 1] <= ymax - CYLINDER_RADIUS)
    cells = cells[inside & ~blocked(cells)]
    if n > len(cells):
        raise ValueError(f"n_cylinders: {n} cylinders do not fit the {len(cells)} free cells of pitch {pitch} m")
    chosen = cells[np.sort(rng.choice(len(cells), size=n, replace=False))]
    jitter = (pitch - 2 * CYLINDER_RADIUS - min_gap) / 2
    centres = chosen + rng.uniform(-jitter, jitter, size=chosen.shape)
    centres = np.clip(centres, (xmin + CYLINDER_RADIUS, ymin + CYLINDER_RADIUS), (xmax - CYLINDER_RADIUS, ymax - CYLINDER_RADIUS))
    moved = blocked(centres)  # a cylinder jittered into the corridor goes back to its cell's centre (clear of it)
    centres[moved] = chosen[moved]
    return centres


def _scatter(rng, n: int, min_gap: float, blocked) -> np.ndarray:
    """``n`` centres drawn uniformly in the field, clear of ``blocked``, ``2 r + min_gap`` apart (each
    takes the first of its candidates that fits; written as a loop: one comparison row a candidate)."""
    xmin, ymin, xmax, ymax = FIELD
    r, spacing = CYLINDER_RADIUS, 2 * CYLINDER_RADIUS + min_gap
    centres = np.empty((n, 2))
    placed = 0
    for _ in range(40):
        candidates = np.array([xmin + r, ymin + r]) + rng.random((4 * n + 64, 2)) * np.array([xmax - xmin - 2 * r, ymax - ymin - 2 * r])
        for p in candidates[~blocked(candidates)]:
            if placed == n:
                break
            if placed == 0 or np.hypot(*(centres[:placed] - p).T).min() >= spacing - 1e-12:
                centres[placed] = p
                placed += 1
        if placed == n:
            return centres
    raise ValueError(f"n_cylinders: could not place {n} cylinders {min_gap} m apart off the grid (placed {placed})")


def _bouncers(rng, n: int, delta_d: float, cylinders: np.ndarray, start, goal) -> list[Obstacle]:
    """``n`` discs of radius 0.2 m in the field's free space, clear of the cylinders and each other by 0.1 m
    and of the robot's start and goal by 0.5 m, moving at ``delta_d`` in drawn directions."""
    xmin, ymin, xmax, ymax = BOUNDS
    r, speed = MOVER_RADIUS, delta_d * MOVER_RADIUS / DT
    out: list[np.ndarray] = []
    for _ in range(200 * max(n, 1)):
        if len(out) == n:
            break
        p = np.array([xmin + r + 0.1, ymin + r + 0.1]) + rng.random(2) * np.array([xmax - xmin - 2 * r - 0.2, ymax - ymin - 2 * r - 0.2])
        far = min(math.dist(p, start), math.dist(p, goal)) > r + ROBOT_RADIUS + START_CLEARANCE
        clear = len(cylinders) == 0 or np.hypot(*(cylinders - p).T).min() > r + CYLINDER_RADIUS + 0.1
        if far and clear and all(math.dist(p, q) > 2 * r + 0.1 for q in out):
            out.append(p)
    if len(out) < n:
        raise ValueError(f"n_obstacles: could not place {n} bouncing discs in the clutter (placed {len(out)})")
    angles = 2 * math.pi * rng.random(n)
    return [Obstacle(center=tuple(p.tolist()), radius=r, velocity=(speed * math.cos(a), speed * math.sin(a))) for p, a in zip(out, angles)]


def _humans(rng, n: int, delta_d: float, start, goal) -> list[Obstacle]:
    """``n`` ORCA humans walking the lanes across the field, alternately up and down, 0.8 m apart."""
    speed = delta_d * HUMAN_RADIUS / DT
    out: list[tuple[np.ndarray, np.ndarray]] = []
    for k in range(n):
        lane, up = LANES[k % 2], (k // 2) % 2 == 0
        for _ in range(200):
            x = lane + (LANE_WIDTH / 2 - HUMAN_RADIUS - 0.1) * (2 * rng.random() - 1)
            y = 0.5 + 3.0 * rng.random()
            p, g = np.array([x, y if up else 8.0 - y]), np.array([x, 7.5 if up else 0.5])
            if all(math.dist(p, q) > 2 * HUMAN_RADIUS + 0.2 and math.dist(g, h) > 2 * HUMAN_RADIUS + 0.2 for q, h in out):
                out.append((p, g))
                break
        else:
            raise ValueError(f"n_obstacles: could not place {n} humans in the clutter's lanes (placed {k})")
    return [Obstacle(center=tuple(p.tolist()), radius=HUMAN_RADIUS, goal=tuple(g.tolist()), preferred_speed=speed, behaviour=HUMAN_ORCA)
            for p, g in out]  # fmt: skip


#: The presets: ``(rng, n_obstacles or None, delta_d or None) -> Scenario``; they apply Δd to their movers themselves.
CLUTTER_PRESETS = {
    "clutter": lambda rng, n, delta_d=None: clutter_scenario(rng, n, delta_d),
    "clutter-crowd": lambda rng, n, delta_d=None: clutter_scenario(rng, n, delta_d, crowd=True),
}
