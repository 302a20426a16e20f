"""The passable cost-to-go: the guide of the space-time planners among dense static geometry.

:func:`agents.planners.costtogo.cost_to_go` is a lower bound: it frees a grid cell unless all of it
and a cell more lies inside a shape's reach (0.14 m deep at a 0.333 m robot), so among cylinders a
gap up to 0.28 m narrower than the robot reads open. Among walls that costs a few per cent; in a field
of a few hundred cylinders it opens most gaps, its way runs through gaps the robot does not fit, and the
searches it guides push into them and stall there (docs/results/clutter.md: ``astar-spacetime`` parked
a few centimetres from a cylinder until the episode's end). :func:`passable_cost_to_go` frees a cell only
where the robot's centre fits, and :func:`guiding_cost_to_go` hands the planners that field among resting
discs, and among walls once the lower bound is seen to mislead them (and the lower bound, bit for bit as
before, until then).
"""

from __future__ import annotations

import math

import numpy as np

from agents.planners.costtogo import _MOVES, CostToGo, _blocked, _grid_dijkstra, blocked_beside_static, distance_to_goal, observed_cost_to_go

#: The lower bound misleads where the passable field's way from the robot is longer than this share
#: of it plus :data:`MISLEAD_SLACK`: among walls the two agree to 5.4 % at the families' starts (the
#: lower bound loses a cell a corner), among the clutter family's cylinders they part by up to 32 %.
MISLEAD_SHARE = 0.08
#: The absolute part (m): the lower bound's own additive slack (two half cell diagonals, 0.12 m at a
#: 0.333 m robot) twice over, so that the last metres to the goal never trip the test.
MISLEAD_SLACK = 0.25
#: The share of the reachable cells on which a misleading lower bound is taken for dense static geometry
#: from the first replan: 0.5 % at most in the wall families' first six test episodes, 11.6-63 % in the
#: clutter family's. Among resting discs the passable field guides whatever the share: among 300 cylinders,
#: where every way is long, the share fell under 5 % in most episodes, and the planners stalled in front of
#: gaps the lower bound opens (``scripts/clutter_density.py --seeds 5000:5040``: ``pso-spacetime`` reached 36
#: and ``abc-spacetime`` 38 of 40, ``astar-spacetime`` 40 at 1.083 x the static oracle's length).
MISLEAD_CELLS = 0.05


def passable_cost_to_go(goal, goal_radius: float, box, segments: np.ndarray, robot_radius: float, centers: np.ndarray,
                        reach: np.ndarray, cell: float | None = None, step: float = 0.0) -> CostToGo | None:  # fmt: skip
    """The cost-to-go to the goal's disc through only the gaps the robot's disc passes, on a grid
    (the module docstring says why). A cell is free only when its centre keeps ``sqrt(R**2 + L**2 / 4)`` from every shape, ``R``
    the shape's reach (``reach``: each disc's contact distance from its centre; a capsule's half
    thickness plus ``robot_radius``) and ``L`` the grid's longest move, or the robot's ``step`` if longer
    (so that the robot's own steps between free points keep clear too: a gap the grid's moves pass by a
    centimetre the planners' steps do not thread): a straight move of length ``<= L``
    between two such centres then never comes within ``R`` (the chord bound of
    :func:`agents.oracles.static.flying_margin`), so every grid path is one the robot's centre flies
    without contact and the field is the length of such a path (no lower bound: up to
    :data:`GRID_STRETCH` and a cell longer than the exact one). Cells of an eighth of the robot's
    radius leave the clutter family's narrowest corridor (its 0.8 m: 13 cm for the centre, 9 cm once
    grown for the robot's 0.25 m step) two cells wide. A blocked cell next to free ones reads its free neighbours' value plus the move (a
    robot at a shape's reach stands in such a cell); the rest is ``inf``.

    :return: the field, or ``None`` when the goal's cells are all blocked (no such guide).
    """
    centers = np.asarray(centers, np.float64).reshape(-1, 2)
    reach = np.asarray(reach, np.float64).reshape(-1)
    segments = np.asarray(segments, np.float64).reshape(-1, 5)
    width, height = box.fit_xmax - box.fit_xmin, box.fit_ymax - box.fit_ymin
    if cell is None:
        cell = max(robot_radius / 8.0, math.sqrt(width * height / 250_000.0))
    gx, gy = max(1, math.ceil(width / cell)), max(1, math.ceil(height / cell))
    longest = max(cell * math.sqrt(5.0), step)  # a knight move, or the robot's step
    capsules = segments.copy()
    capsules[:, 4] = np.sqrt((capsules[:, 4] + robot_radius) ** 2 + 0.25 * longest**2)
    grown = np.sqrt(reach**2 + 0.25 * longest**2)
    free = ~_blocked(float(box.fit_xmin), float(box.fit_ymin), float(cell), gx, gy, capsules, centers, grown, 0.0)
    cx = box.fit_xmin + (np.arange(gx) + 0.5) * cell
    cy = box.fit_ymin + (np.arange(gy) + 0.5) * cell
    px, py = np.meshgrid(cx, cy, indexing="ij")
    sources = np.argwhere(free & (np.hypot(px - goal[0], py - goal[1]) <= goal_radius + cell * math.sqrt(0.5)))  # the goal's disc, to a cell
    if len(sources) == 0:
        return None
    field = _grid_dijkstra(free, sources.astype(np.int64), _MOVES, float(cell))
    lengths = cell * np.hypot(*_MOVES.T)
    for _ in range(2):  # two rings of the 16 moves into the blocked cells: where a robot at a shape's reach stands
        padded = np.pad(field, 2, constant_values=np.inf)
        spill = field.copy()
        for (di, dj), length in zip(_MOVES, lengths):
            spill = np.minimum(spill, padded[2 + di : 2 + di + gx, 2 + dj : 2 + dj + gy] + length)
        field = np.where(free, field, spill)
    return CostToGo(np.ascontiguousarray(field), float(box.fit_xmin), float(box.fit_ymin), float(cell))


def misled_share(lower: CostToGo, passable: CostToGo, goal, goal_radius: float) -> float:
    """The share of the cells ``passable`` reaches (free, finite) where ``lower`` misleads: where the
    passable way is longer than :data:`MISLEAD_SHARE` of the lower bound plus :data:`MISLEAD_SLACK`.
    Both grids start at the box's corner; each passable cell reads the lower cell holding its centre."""
    gx, gy = passable.field.shape
    cx = (np.arange(gx) + 0.5) * passable.cell
    cy = (np.arange(gy) + 0.5) * passable.cell
    i = np.minimum((cx / lower.cell).astype(np.int64), lower.field.shape[0] - 1)
    j = np.minimum((cy / lower.cell).astype(np.int64), lower.field.shape[1] - 1)
    px, py = np.meshgrid(passable.x0 + cx, passable.y0 + cy, indexing="ij")
    bound = np.maximum(np.maximum(np.hypot(px - goal[0], py - goal[1]) - goal_radius, lower.field[np.ix_(i, j)]), 0.0)
    way = passable.field
    reached = np.isfinite(way) & np.isfinite(bound)
    if not reached.any():
        return 0.0
    return float(np.mean(way[reached] > (1.0 + MISLEAD_SHARE) * bound[reached] + MISLEAD_SLACK))


def guiding_cost_to_go(obs: dict, facts, memory: dict, margin: float = 0.0) -> tuple[np.ndarray, CostToGo]:
    """The scene's walls and the cost-to-go a space-time planner is guided by: the lower bound
    (:func:`~agents.planners.costtogo.observed_cost_to_go`), bit for bit as before, unless it
    misleads; then the :func:`passable_cost_to_go` field, while the static scene stays (both kept in
    ``memory``). Static geometry is the walls and the discs at rest in every observation from the
    episode's first on: the passable field is weighed from the second replan (a crowd's humans stand
    still at the start, then walk: the field goes round the discs that still rest, the cylinders of
    ``clutter-crowd``) and never once a body has started or stopped where no disc has rested
    throughout (the wall crowd families). From that replan on it guides wherever discs rest (the
    gaps between them are what the lower bound opens, up to 0.28 m too narrow at a 0.333 m robot); among
    walls alone, where the lower bound misleads: on that replan, on more than :data:`MISLEAD_CELLS` of the
    cells the robot can reach (:func:`misled_share`), or, at a later replan, where the robot stands. ``margin`` is
    the planner's relative margin on the contact distance, which resting discs get as moving ones do
    (the walls none)."""
    from agents.observation import Observation

    segments, lower = observed_cost_to_go(obs, facts, memory)
    if lower.field.size == 0 or memory.get("passable_off"):
        return segments, lower
    centers, velocities, radii = Observation.of(obs).obstacles
    still = (velocities == 0.0).all(axis=1)
    rows = memory.setdefault("passable_rows", still)  # the discs at rest in every observation so far
    rows = rows & still if len(rows) == len(still) else np.zeros(len(still), np.bool_)
    memory["passable_rows"] = rows
    key = memory["cost_to_go_key"]
    if key != memory.setdefault("passable_first_key", key) and not rows.any():  # a body started or stopped, none rests throughout
        memory["passable_off"] = True
        return segments, lower
    memory["passable_replans"] = memory.get("passable_replans", 0) + 1
    if memory["passable_replans"] < 2:  # resting on one observation may be a standing start (humans)
        return segments, lower
    goal = np.asarray(obs["goal"], np.float64)
    static_key = (segments.tobytes(), centers[rows].tobytes(), radii[rows].tobytes(), goal.tobytes())
    if memory.get("passable_key") != static_key:
        reach = (radii[rows] + facts.robot_radius) * (1.0 + margin)
        passable = passable_cost_to_go(goal, facts.goal_radius, facts.arena.box, segments, facts.robot_radius, centers[rows], reach,
                                       step=facts.robot_speed * facts.dt)  # fmt: skip
        memory["passable_key"], memory["passable"] = static_key, passable
        # among resting discs from the start (the gaps between them are what the lower bound opens) at once
        memory["passable_engaged"] = memory["passable_switched"] = passable is not None and (
            bool(rows.any()) or misled_share(lower, passable, goal, facts.goal_radius) > MISLEAD_CELLS)
    passable = memory["passable"]
    if passable is None:
        return segments, lower
    (x, y), (gx, gy) = obs["robot_position"], goal
    way = distance_to_goal(passable, float(x), float(y), float(gx), float(gy), facts.goal_radius)
    if not memory["passable_engaged"]:
        bound = distance_to_goal(lower, float(x), float(y), float(gx), float(gy), facts.goal_radius)
        memory["passable_engaged"] = memory["passable_switched"] = bool(math.isfinite(way) and way > (1.0 + MISLEAD_SHARE) * bound + MISLEAD_SLACK)
    # where the grid closes the robot's own gap (narrower than its cells resolve) the lower bound leads on
    memory["passable_in_use"] = memory["passable_engaged"] and math.isfinite(way)
    return segments, passable if memory["passable_in_use"] else lower


def guided_by_passable(memory: dict) -> bool:
    """Whether :func:`guiding_cost_to_go`'s last call handed this episode's planner the passable field."""
    return bool(memory.get("passable_in_use", False)) and not memory.get("passable_off", False)


def guide_switched(memory: dict) -> bool:
    """Whether the last :func:`guiding_cost_to_go` call switched to the passable field (asked once:
    a plan made on the lower bound is not to be flown on after it)."""
    return bool(memory.pop("passable_switched", False))


def passable_around(static: CostToGo, obs: dict, facts, margin: float, centers: np.ndarray, radii: np.ndarray) -> CostToGo:
    """The passable field ``static`` (this episode's, :func:`guiding_cost_to_go`) with the moving discs
    ``centers`` / ``radii`` (their own radii) standing where they are, as
    :func:`agents.planners.costtogo.around_obstacles` does for the lower bound: the way round them
    where there is one; a place they cut off from the goal costs more than any they leave a way from
    (they will move on)."""
    from agents.observation import Observation

    if len(radii) == 0:
        return static
    parsed = Observation.of(obs)
    still_c, velocities, still_r = parsed.obstacles
    still = (velocities == 0.0).all(axis=1)
    centres = np.vstack([still_c[still], np.asarray(centers, np.float64).reshape(-1, 2)])
    reach = np.concatenate([still_r[still], np.asarray(radii, np.float64)]) + facts.robot_radius
    segments = parsed.walls
    blocked = passable_cost_to_go(np.asarray(obs["goal"], np.float64), facts.goal_radius, facts.arena.box, segments, facts.robot_radius,
                                  centres, reach * (1.0 + margin), static.cell, facts.robot_speed * facts.dt)  # fmt: skip
    return blocked_beside_static(static, blocked)
