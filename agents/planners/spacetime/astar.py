"""A* over (step, position) against known obstacle trajectories: the earliest arrival at the goal.

Shared by the privileged clairvoyant oracle (the env's own future obstacle states) and by the
model-based ``astar-spacetime`` planner (obstacles predicted from the observation). Every move is a
waypoint action made exactly as the env makes it (``pathplan_env.robots.holonomic``: float32 action,
clipping, the one-step reach) and checked with the env's swept contact test at every substep, so a
plan found against the env's own trajectory replays bit for bit.

Moves from each node: ``headings`` x ``speed_fractions`` of the robot's step, waiting, and a
waypoint on the goal itself. Nodes are merged per (step, grid cell of ``cell`` metres): the search
is complete only up to that resolution, which is why a failed search is "undetermined" unless
:func:`provably_lost` says otherwise. The heuristic (steps still needed at top speed) is admissible,
so the first goal node popped arrives earliest; ties go to the deeper node. With static geometry
(``SpacetimeProblem.statics``: walls and polygon edges) every move is also swept against it as the
env does, and the heuristic reads the static cost-to-go around it (``SpacetimeProblem.cost_to_go``,
:mod:`agents.planners.costtogo`: a lower bound, so still admissible up to its grid) instead of the
straight line, which led the search into the far side of every wall.

Compiled with numba: one search expands thousands of nodes with dozens of moves each. The kernels
take named records: the problem (:class:`SpacetimeProblem`: what is known of the obstacles' future
and the robot's task) and the search's settings (:class:`SearchSettings`).
"""

from __future__ import annotations

import heapq
import math
from typing import NamedTuple

import numba
import numpy as np

from agents.planners.costtogo import STRAIGHT_LINE, CostToGo, distance_to_goal
from agents.planners.reachable_set import provably_lost
from agents.planners.resting_discs import EVERY_OBSTACLE, RestingSet, obstacles_along, obstacles_near, visited
from pathplan_env.arena import ArenaBox
from pathplan_env.geometry.contacts import swept_pair
from pathplan_env.geometry.walls import swept_capsule
from pathplan_env.robots.holonomic import reach_fraction, robot_move, substep_point

__all__ = ["BUDGET", "EXHAUSTED", "FOUND", "HORIZON", "SearchResult", "SearchSettings", "SearchTree", "SpacetimeProblem",
           "heading_moves", "provably_lost", "replay", "search", "step_paths"]  # provably_lost lives in reachable_set

FOUND, HORIZON, EXHAUSTED, BUDGET = 0, 1, 2, 3  # search outcomes


class SpacetimeProblem(NamedTuple):
    """Known obstacle trajectories and the robot's task: what :func:`search`, :func:`replay` and
    :func:`provably_lost` read."""

    trajectory: np.ndarray  # (S + 1, N, >= 2): obstacle centres (m) after every substep from now
    substeps: int  # substeps a step
    robot_radius: float  # m
    radii: np.ndarray  # (N,) m: the obstacles' contact radii
    start: np.ndarray  # (2,) m: the robot now
    goal: np.ndarray  # (2,) m
    goal_radius: float  # m
    box: ArenaBox  # the env's action mapping and the box where the robot's disc fits
    reach: float  # m: the robot's step at top speed
    statics: np.ndarray = np.zeros((0, 5))  # (M, 5): walls and polygon edges (``World.static_segments`` rows)
    cost_to_go: CostToGo = STRAIGHT_LINE  # the heuristic's distance to the goal (:mod:`agents.planners.costtogo`)
    resting: RestingSet | None = EVERY_OBSTACLE  # the broad phase's resting obstacles (:mod:`agents.planners.resting_discs`)


class SearchSettings(NamedTuple):
    """The A*'s moves, depth, merge grid, budgets and heuristic weight."""

    moves: np.ndarray  # (M, 3): ``(ux, uy, fraction of the robot's step)`` (:func:`heading_moves`)
    max_steps: int  # a node this deep is a leaf (where the trajectory or the episode ends)
    cell: float  # m: nodes are merged per (step, grid cell)
    max_expansions: int  # node budget
    h_weight: float  # heuristic weight (1: plain A*, earliest arrival)
    # work budget: obstacle and wall tests (broad phase, and narrow phase per substep), which track the
    # search's time far better than expansions do (an expansion near 30 fast obstacles costs ~20x one
    # among 8 slow ones) while staying deterministic; inf: expansions alone bound the search
    max_work: float = math.inf
    # among nodes of equal cost and depth, expand first the one nearer the goal by the cost-to-go (m),
    # not the first generated: the heuristic counts whole steps, so every move that keeps the step
    # count ties, and the first heading (east) won them, flying staircases (docs/results/clutter.md)
    tie_break: bool = False


class SearchTree(NamedTuple):
    """Every node :func:`search` generated (each one's path from the start is free of contact):
    what :mod:`agents.planners.spacetime.anytime` chooses a partial plan from."""

    x: np.ndarray  # (count,) m: the robot after the node's step
    y: np.ndarray
    k: np.ndarray  # (count,) int: the node's step
    parent: np.ndarray  # (count,) int: its parent's index (-1 at the root)
    tx: np.ndarray  # (count,) m: the waypoint aimed at to reach it
    ty: np.ndarray
    h: np.ndarray  # (count,) steps still needed at top speed (the heuristic, unweighted)


class SearchResult(NamedTuple):
    """What :func:`search` returns."""

    outcome: int  # FOUND, HORIZON, EXHAUSTED or BUDGET
    targets: np.ndarray  # (steps, 2) m: the waypoint to aim at in each step
    expansions: int  # nodes expanded
    work: int  # obstacle and wall tests done (:attr:`SearchSettings.max_work`)
    tree: SearchTree  # every node generated


def heading_moves(n_headings: int, speed_fractions) -> np.ndarray:
    """Move directions and lengths as an (M, 3) array ``(ux, uy, fraction of the robot's step)``."""
    angles = 2.0 * np.pi * np.arange(n_headings) / n_headings
    rows = [(math.cos(a), math.sin(a), float(f)) for f in speed_fractions for a in angles]
    return np.array(rows, dtype=np.float64).reshape(-1, 3)


@numba.njit(cache=True, inline="always")
def _to_action(tx, ty, box):
    """``Arena.waypoint_to_action`` for one point, to the bit (float64, then float32): its
    ``2 (x - xmin) / width`` equals ``(x - xmin) / half_width``, scaling by 2 being exact."""
    a = np.empty(2, np.float32)
    a[0] = min(max((tx - box.xmin) / box.half_width - 1.0, -1.0), 1.0)
    a[1] = min(max((ty - box.ymin) / box.half_height - 1.0, -1.0), 1.0)
    return a


@numba.njit(cache=True, inline="always")
def _segment_distance(ax, ay, bx, by, px, py, qx, qy):
    """Distance between the segments ``ab`` and ``pq`` (closest points clamped to both, as in
    Ericson's *Real-Time Collision Detection*, 5.1.9)."""
    ux, uy, vx, vy, wx, wy = bx - ax, by - ay, qx - px, qy - py, ax - px, ay - py
    a, e, f = ux * ux + uy * uy, vx * vx + vy * vy, vx * wx + vy * wy
    if a <= 0.0 and e <= 0.0:
        return math.hypot(wx, wy)
    if a <= 0.0:
        s, t = 0.0, min(max(f / e, 0.0), 1.0)
    else:
        c = ux * wx + uy * wy
        if e <= 0.0:
            s, t = min(max(-c / a, 0.0), 1.0), 0.0
        else:
            b = ux * vx + uy * vy
            denom = a * e - b * b
            s = min(max((b * f - c * e) / denom, 0.0), 1.0) if denom > 0.0 else 0.0
            t = (b * s + f) / e
            if t < 0.0:
                s, t = min(max(-c / a, 0.0), 1.0), 0.0
            elif t > 1.0:
                s, t = min(max((b - c) / a, 0.0), 1.0), 1.0
    return math.hypot(wx + s * ux - t * vx, wy + s * uy - t * vy)


class StepPaths(NamedTuple):
    """Each obstacle's path in each step, summarised for the searches' broad phases (built once a
    problem by :func:`step_paths`)."""

    ends: np.ndarray  # (S, N, 4): the step's first and last centre
    deviation: np.ndarray  # (S, N): farthest substep centre from the segment between those two


@numba.njit(cache=True)
def step_paths(traj, n):
    """:class:`StepPaths` of a trajectory with ``n`` substeps a step."""
    steps, count = (traj.shape[0] - 1) // n, traj.shape[1]
    ends = np.empty((steps, count, 4))
    deviation = np.zeros((steps, count))
    for k in range(steps):
        first = k * n
        for o in range(count):
            px, py, qx, qy = traj[first, o, 0], traj[first, o, 1], traj[first + n, o, 0], traj[first + n, o, 1]
            ends[k, o, 0], ends[k, o, 1], ends[k, o, 2], ends[k, o, 3] = px, py, qx, qy
            for j in range(1, n):
                cx, cy = traj[first + j, o, 0], traj[first + j, o, 1]
                deviation[k, o] = max(deviation[k, o], _segment_distance(cx, cy, cx, cy, px, py, qx, qy))
    return StepPaths(ends, deviation)


class Candidates(NamedTuple):
    """What a step's broad phase left to test: the obstacles ``near[:n_near]`` and the static
    capsules ``near_s[:n_near_s]`` (rows of the problem's ``statics``)."""

    near: np.ndarray
    n_near: int
    near_s: np.ndarray
    n_near_s: int


@numba.njit(cache=True)
def _fly(problem, first, move, candidates, ends, deviation, close):
    """One step of the :class:`SpacetimeProblem` from ``(x, y)`` by ``(dx, dy)`` (``move``) starting
    at substep ``first``: ``(result, pairs)``, result 1 goal, 0 free, -1 contact, and the pairs tested
    substep by substep.

    Only the obstacles ``near[:n_near]`` (:class:`Candidates`) are tested (the others cannot reach the robot this step),
    and of those only the ones whose path this step (``ends``: its first and last centre; every
    substep centre within ``deviation`` of that segment, hence every point between them too) comes
    within the contact distance of the robot's straight move: the rest could not touch at any
    instant, let alone at the same one. For the pairs left (written to ``close``) the test is the
    env's ``swept_contact``, substep by substep. The static capsules ``near_s[:n_near_s]`` (rows of
    ``statics``) are tested as the env tests them: one exact swept test of the whole move
    (``pathplan_env.geometry.walls.static_stop``)."""
    traj, n, robot_radius, radii, statics = problem.trajectory, problem.substeps, problem.robot_radius, problem.radii, problem.statics
    gx, gy, goal_radius = problem.goal[0], problem.goal[1], problem.goal_radius
    x, y, dx, dy = move
    near, n_near, near_s, n_near_s = candidates
    slack = 1e-9 * (1.0 + abs(x) + abs(y) + abs(dx) + abs(dy))  # far above rounding, far below a miss
    pairs = 0
    for q in range(n_near):
        o = near[q]
        if _segment_distance(x, y, x + dx, y + dy, ends[o, 0], ends[o, 1], ends[o, 2], ends[o, 3]) <= robot_radius + radii[o] + deviation[o] + slack:
            close[pairs] = o
            pairs += 1
    contact = 2.0
    if pairs > 0:
        ax, ay = x, y
        for j in range(1, n + 1):
            bx, by = substep_point(x, dx, j, n), substep_point(y, dy, j, n)
            a, b = traj[first + j - 1], traj[first + j]
            t = 2.0
            for q in range(pairs):
                o = close[q]
                _, t_hit = swept_pair(ax, ay, bx, by, robot_radius, a[o, 0], a[o, 1], b[o, 0], b[o, 1], radii[o])
                t = min(t, t_hit)
            if t <= 1.0:
                contact = (j - 1 + t) / n
                break
            ax, ay = bx, by
    for q in range(n_near_s):
        w = near_s[q]
        _, t = swept_capsule(x, y, x + dx, y + dy, robot_radius, statics[w, 0], statics[w, 1], statics[w, 2], statics[w, 3], statics[w, 4])
        contact = min(contact, t)
    goal = reach_fraction(x, y, dx, dy, gx, gy, goal_radius)
    if contact <= 1.0 and contact <= goal:
        return -1, pairs
    return (1 if goal <= 1.0 else 0), pairs


@numba.njit(cache=True, inline="always")
def _near_statics(x, y, statics, robot_radius, reach, near_s):
    """Write to ``near_s`` the capsules within ``reach`` plus the contact distance of ``(x, y)``; their count."""
    count = 0
    for w in range(statics.shape[0]):
        if _segment_distance(x, y, x, y, statics[w, 0], statics[w, 1], statics[w, 2], statics[w, 3]) - robot_radius - statics[w, 4] <= reach:
            near_s[count] = w
            count += 1
    return count


@numba.njit(cache=True)
def search(problem, settings):
    """Earliest-arrival A* from ``problem.start`` at substep 0 of ``problem.trajectory`` (a
    :class:`SpacetimeProblem`), with :class:`SearchSettings`.

    A node at depth ``max_steps`` (where the trajectory or the episode ends) counts as a leaf: when one is
    popped before any goal node, the search stops there (``HORIZON``), its path the most promising.

    :return: a :class:`SearchResult`: its ``targets`` are the waypoints to aim at, one per step
        (found plan, horizon leaf, or the deepest node reached when the search fails).
    """
    traj, n, robot_radius, radii = problem.trajectory, problem.substeps, problem.robot_radius, problem.radii
    start, goal, goal_radius, box, reach = problem.start, problem.goal, problem.goal_radius, problem.box, problem.reach
    statics, ctg = problem.statics, problem.cost_to_go
    moves, max_steps, cell = settings.moves, settings.max_steps, settings.cell
    max_expansions, h_weight, max_work = settings.max_expansions, settings.h_weight, settings.max_work
    bx0, by0 = box.fit_xmin, box.fit_ymin
    gx_cells = int((box.fit_xmax - bx0) / cell) + 2
    gy_cells = int((box.fit_ymax - by0) / cell) + 2
    capacity = max_expansions * (moves.shape[0] + 2) + 1
    cap = min(capacity, 2_000_000)
    node_x = np.empty(cap)
    node_y = np.empty(cap)
    node_k = np.empty(cap, np.int64)
    node_parent = np.empty(cap, np.int64)
    node_tx = np.empty(cap)
    node_ty = np.empty(cap)
    node_h = np.empty(cap)
    seen = numba.typed.Dict.empty(numba.types.int64, numba.types.int64)
    near = np.empty(radii.shape[0], np.int64)
    close = np.empty(radii.shape[0], np.int64)
    near_s = np.empty(statics.shape[0], np.int64)
    visit = np.empty(radii.shape[0], np.int64)  # the obstacles the broad phase visits (the others cannot reach)
    paths = step_paths(traj, n)

    def distance(x, y):  # along the static cost-to-go (m)
        return min(distance_to_goal(ctg, x, y, goal[0], goal[1], goal_radius), 1e9 * reach)  # inf: walled off

    def h(x, y):  # steps still needed at top speed along the static cost-to-go (a lower bound)
        d = distance(x, y)
        return 0.0 if d <= 0.0 else math.ceil(d / reach - 1e-9)

    node_x[0], node_y[0], node_k[0], node_parent[0] = start[0], start[1], 0, -1
    node_tx[0], node_ty[0], node_h[0] = start[0], start[1], h(start[0], start[1])
    count = 1
    tie_break = settings.tie_break
    heap = [(h_weight * h(start[0], start[1]), 0, 0.0, 0)]
    deepest, deepest_k, deepest_h = 0, 0, h(start[0], start[1])
    expansions = 0
    work = 0
    found = -1
    outcome = EXHAUSTED
    while len(heap) > 0:
        f, negk, _, i = heapq.heappop(heap)
        k = node_k[i]
        if k == max_steps:
            found, outcome = i, HORIZON
            break
        if expansions >= max_expansions or work >= max_work:
            outcome = BUDGET
            break
        expansions += 1
        work += radii.shape[0] + statics.shape[0]  # the broad phases below
        x, y = node_x[i], node_y[i]
        first = k * n
        # broad phase: every move stays within ``reach`` of (x, y), every obstacle within its
        # deviation of its step's segment; one farther than both plus the contact distance is out of reach
        n_near = 0
        ends, deviation = paths.ends[k], paths.deviation[k]
        slack = 1e-9 * (1.0 + abs(x) + abs(y) + reach)
        for q in range(obstacles_near(problem.resting, radii.shape[0], x, y, reach + robot_radius + slack, visit)):
            o = visited(problem.resting, visit, q)
            gap = _segment_distance(x, y, x, y, ends[o, 0], ends[o, 1], ends[o, 2], ends[o, 3]) - robot_radius - radii[o]
            if gap <= reach + deviation[o] + slack:
                near[n_near] = o
                n_near += 1
        n_near_s = _near_statics(x, y, statics, robot_radius, reach + slack, near_s)
        m_total = moves.shape[0] + 2
        for m in range(m_total):
            if m < moves.shape[0]:
                tx = x + moves[m, 0] * moves[m, 2] * reach
                ty = y + moves[m, 1] * moves[m, 2] * reach
            elif m == moves.shape[0]:
                tx, ty = x, y  # wait
            else:
                tx, ty = goal[0], goal[1]
            action = _to_action(tx, ty, box)
            _, _, _, dx, dy = robot_move(action, box, x, y, reach)
            result, pairs = _fly(problem, first, (x, y, dx, dy), Candidates(near, n_near, near_s, n_near_s), ends, deviation, close)
            work += n_near + pairs * n + n_near_s
            if result < 0:
                continue
            nx, ny = x + dx, y + dy
            if result == 0:
                key = ((k + 1) * gx_cells + int((nx - bx0) / cell)) * gy_cells + int((ny - by0) / cell)
                if key in seen or count >= cap:
                    continue
                seen[key] = 1
            node_x[count], node_y[count], node_k[count], node_parent[count] = nx, ny, k + 1, i
            node_tx[count], node_ty[count] = tx, ty
            if result == 1:
                found, outcome = count, FOUND
                node_h[count] = 0.0
                count += 1
                break
            hn = h(nx, ny)
            node_h[count] = hn
            heapq.heappush(heap, (k + 1 + h_weight * hn, -(k + 1), distance(nx, ny) if tie_break else 0.0, count))
            if k + 1 > deepest_k or (k + 1 == deepest_k and hn < deepest_h):
                deepest, deepest_k, deepest_h = count, k + 1, hn
            count += 1
        if outcome == FOUND:
            break
    last = found if found >= 0 else deepest
    steps = node_k[last]
    targets = np.empty((steps, 2))
    j = last
    for s in range(steps - 1, -1, -1):
        targets[s, 0], targets[s, 1] = node_tx[j], node_ty[j]
        j = node_parent[j]
    tree = SearchTree(node_x[:count], node_y[:count], node_k[:count], node_parent[:count], node_tx[:count], node_ty[:count], node_h[:count])
    return SearchResult(outcome, targets, expansions, work, tree)


@numba.njit(cache=True)
def replay(problem, targets):
    """Fly ``targets`` (one waypoint a step) from ``problem.start`` through ``problem.trajectory``
    (a :class:`SpacetimeProblem`) as the search would.

    :return: ``(steps, reached)``: how many steps stay free of contact (all of them if none
        touches) and whether the goal is reached within them.
    """
    traj, n, radii = problem.trajectory, problem.substeps, problem.radii
    start, box, reach = problem.start, problem.box, problem.reach
    x, y = start[0], start[1]
    steps = min(targets.shape[0], (traj.shape[0] - 1) // n)
    near = np.arange(radii.shape[0])  # every obstacle, or the broad phase's (written per step)
    close = np.empty(radii.shape[0], np.int64)
    statics = problem.statics
    every_static = np.arange(statics.shape[0])
    paths = step_paths(traj, n)
    for k in range(steps):
        action = _to_action(targets[k, 0], targets[k, 1], box)
        _, _, _, dx, dy = robot_move(action, box, x, y, reach)
        slack = 1e-9 * (1.0 + abs(x) + abs(y) + abs(dx) + abs(dy))  # _fly's
        n_near = obstacles_along(problem.resting, radii.shape[0], x, y, x + dx, y + dy, problem.robot_radius + slack, near)
        candidates = Candidates(near, n_near, every_static, statics.shape[0])
        result, _ = _fly(problem, k * n, (x, y, dx, dy), candidates, paths.ends[k], paths.deviation[k], close)
        if result < 0:
            return k, False
        if result == 1:
            return k + 1, True
        x, y = x + dx, y + dy
    return steps, False
