"""RVO2's static obstacles for the compiled ORCA (``orca.py``): the vertex record and the obstacle ORCA lines.

RVO2 holds an obstacle as a ring of vertices, each the start of an edge to the next, with its
convexity; ``Agent::computeNewVelocity`` turns every edge near an agent, seen from outside, into a
hard half-plane of permitted velocities (a vertex or edge already touched: a line through the origin;
otherwise the velocity projected on the edge's truncated velocity obstacle: its cut-off line or circles,
or its legs, which never point into a convex neighbouring edge). This module ports that case for
case; ``orca.py`` solves the linear program over these lines and the agents'. Checked against pyrvo
in ``tests/crowds/test_humans_and_walls.py``.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba
import numpy as np


class ORCAObstacles(NamedTuple):
    """Static obstacles as RVO2 holds them: vertices, each the start of an edge to ``next``.

    A polygon's vertices run counter-clockwise (the obstacle on the left of each edge), a hole's
    clockwise; a two-vertex obstacle is a line, seen from both sides. Built by :func:`obstacle_vertices`.
    """

    point: np.ndarray  # (k, 2) m
    direction: np.ndarray  # (k, 2): unit vector toward the next vertex
    next: np.ndarray  # (k,) int64
    prev: np.ndarray  # (k,) int64
    convex: np.ndarray  # (k,) bool: RVO2's isConvex_ (left turn or straight at the vertex)


#: RVO2's threshold for (almost) parallel constraint lines.
RVO_EPSILON = 1e-5
def obstacle_vertices(rings) -> ORCAObstacles:
    """:class:`ORCAObstacles` of vertex rings (RVO2's ``addObstacle`` for each): a ring of >= 3
    vertices counter-clockwise around an obstacle (clockwise around a hole in one), or 2 vertices for
    a line. Convexity and directions as RVO2 computes them.

    :raises ValueError: naming ``rings`` for a ring of fewer than 2 vertices or a zero-length edge.
    """
    points, nexts, prevs, convex = [], [], [], []
    for r, ring in enumerate(rings):
        ring = [(float(x), float(y)) for x, y in ring]
        n, base = len(ring), len(points)
        if n < 2:
            raise ValueError(f"rings[{r}] must have at least 2 vertices, got {n}")
        for i, (x, y) in enumerate(ring):
            (px, py), (nx, ny) = ring[i - 1], ring[(i + 1) % n]
            points.append((x, y))
            nexts.append(base + (i + 1) % n)
            prevs.append(base + (i - 1) % n)
            # RVO2: leftOf(previous, this, next) >= 0; a line's two ends are convex
            convex.append(n == 2 or (px - nx) * (y - py) - (py - ny) * (x - px) >= 0.0)
    point = np.array(points, np.float64).reshape(-1, 2)
    nxt = np.array(nexts, np.int64)
    edge = point[nxt] - point if len(point) else np.empty((0, 2))
    length = np.hypot(edge[:, 0], edge[:, 1])
    if (length <= 0.0).any():
        raise ValueError("rings: an edge has zero length (repeated vertex)")
    return ORCAObstacles(point, edge / length[:, None] if len(point) else edge, nxt, np.array(prevs, np.int64), np.array(convex, np.bool_))


NO_OBSTACLES = obstacle_vertices([])

@numba.njit(cache=True)
def _det(ax, ay, bx, by):
    return ax * by - ay * bx


@numba.njit(cache=True, inline="always")
def _obstacle_neighbours(x, y, obstacles, range_sq, order, dist_sq):
    """The edges within ``range_sq`` (squared distance to the segment) that the agent sees from their
    outer side, nearest first (RVO2's k-d tree query and ``insertObstacleNeighbor``), into ``order``
    (with ``dist_sq``: scratch of one row per edge); returns their count."""
    point, nxt = obstacles.point, obstacles.next
    k = point.shape[0]
    count = 0
    for e in range(k):
        ax, ay = point[e, 0], point[e, 1]
        ex, ey = point[nxt[e], 0] - ax, point[nxt[e], 1] - ay
        if _det(ax - x, ay - y, ex, ey) >= 0.0:  # leftOf(p1, p2, agent) >= 0: the agent is behind the edge
            continue
        r = ((x - ax) * ex + (y - ay) * ey) / (ex * ex + ey * ey)
        if r < 0.0:
            d = (x - ax) ** 2 + (y - ay) ** 2
        elif r > 1.0:
            d = (x - ax - ex) ** 2 + (y - ay - ey) ** 2
        else:
            d = (x - ax - r * ex) ** 2 + (y - ay - r * ey) ** 2
        if d >= range_sq:
            continue
        i = count
        count += 1
        while i != 0 and d < dist_sq[i - 1]:
            order[i], dist_sq[i] = order[i - 1], dist_sq[i - 1]
            i -= 1
        order[i], dist_sq[i] = e, d
    return count


@numba.njit(cache=True, inline="always")
def _leg(rx, ry, dist_sq, radius, left):
    """Unit direction of the left (or right) tangent from the agent to a disc of ``radius`` at ``r``."""
    leg = math.sqrt(dist_sq - radius * radius)
    if left:
        return (rx * leg - ry * radius) / dist_sq, (rx * radius + ry * leg) / dist_sq
    return (rx * leg + ry * radius) / dist_sq, (-rx * radius + ry * leg) / dist_sq


class Legs(NamedTuple):
    """An edge's velocity obstacle without collision, as RVO2 builds it: its left and right vertices
    ``o1``, ``o2`` (one vertex when viewed obliquely), the unit left and right legs, and whether each
    leg is a neighbouring edge's ("foreign": no line when the velocity projects on it)."""

    o1: int
    o2: int
    llx: float
    lly: float
    rlx: float
    rly: float
    left_foreign: bool
    right_foreign: bool


@numba.njit(cache=True, inline="always")
def _project(agent, inv_horizon, obstacles, legs, line):
    """The end of RVO2's obstacle case without collision: the velocity projected on the left or right
    cut-off circle, the cut-off line or a leg (:class:`Legs`); writes ``line`` and returns 1, or 0
    for a foreign leg."""
    x, y, vx, vy, radius = agent.x, agent.y, agent.vx, agent.vy, agent.radius
    point, direction = obstacles.point, obstacles.direction
    o1, o2, llx, lly, rlx, rly, left_foreign, right_foreign = legs
    lcx, lcy = inv_horizon * (point[o1, 0] - x), inv_horizon * (point[o1, 1] - y)  # cut-off centres
    rcx, rcy = inv_horizon * (point[o2, 0] - x), inv_horizon * (point[o2, 1] - y)
    cx, cy = rcx - lcx, rcy - lcy
    same = o1 == o2
    t = 0.5 if same else ((vx - lcx) * cx + (vy - lcy) * cy) / (cx * cx + cy * cy)
    t_left = (vx - lcx) * llx + (vy - lcy) * lly
    t_right = (vx - rcx) * rlx + (vy - rcy) * rly
    if (t < 0.0 and t_left < 0.0) or (same and t_left < 0.0 and t_right < 0.0):  # the left cut-off circle
        wx, wy = vx - lcx, vy - lcy
        norm = math.hypot(wx, wy)
        ux, uy = wx / norm, wy / norm
        line[0], line[1], line[2], line[3] = lcx + radius * inv_horizon * ux, lcy + radius * inv_horizon * uy, uy, -ux
        return 1
    if t > 1.0 and t_right < 0.0:  # the right cut-off circle
        wx, wy = vx - rcx, vy - rcy
        norm = math.hypot(wx, wy)
        ux, uy = wx / norm, wy / norm
        line[0], line[1], line[2], line[3] = rcx + radius * inv_horizon * ux, rcy + radius * inv_horizon * uy, uy, -ux
        return 1
    # the left leg, the right leg or the cut-off line, whichever is closest to the velocity
    d_cut = math.inf if (t < 0.0 or t > 1.0 or same) else (vx - lcx - t * cx) ** 2 + (vy - lcy - t * cy) ** 2
    d_left = math.inf if t_left < 0.0 else (vx - lcx - t_left * llx) ** 2 + (vy - lcy - t_left * lly) ** 2
    d_right = math.inf if t_right < 0.0 else (vx - rcx - t_right * rlx) ** 2 + (vy - rcy - t_right * rly) ** 2
    if d_cut <= d_left and d_cut <= d_right:
        dx, dy, px, py = -direction[o1, 0], -direction[o1, 1], lcx, lcy
    elif d_left <= d_right:
        if left_foreign:
            return 0
        dx, dy, px, py = llx, lly, lcx, lcy
    else:
        if right_foreign:
            return 0
        dx, dy, px, py = -rlx, -rly, rcx, rcy
    line[0], line[1] = px + radius * inv_horizon * -dy, py + radius * inv_horizon * dx
    line[2], line[3] = dx, dy
    return 1


@numba.njit(cache=True, inline="always")
def _obstacle_lines(agent, obstacles, order, inv_horizon, lines):
    """RVO2's obstacle ORCA lines of the edges ``order`` (neighbours, nearest first) into ``lines``
    (rows ``point_x, point_y, dir_x, dir_y``); returns their count. Follows
    ``Agent::computeNewVelocity`` case for case (the comments name its cases)."""
    x, y, radius = agent.x, agent.y, agent.radius
    point, direction, nxt, prv, convex = obstacles.point, obstacles.direction, obstacles.next, obstacles.prev, obstacles.convex
    count = order.shape[0]
    radius_sq = radius * radius
    n = 0
    for k in range(count):
        o1 = order[k]
        o2 = nxt[o1]
        r1x, r1y = point[o1, 0] - x, point[o1, 1] - y
        r2x, r2y = point[o2, 0] - x, point[o2, 1] - y
        covered = False  # already taken care of by an earlier obstacle line
        for j in range(n):
            px, py, dx, dy = lines[j, 0], lines[j, 1], lines[j, 2], lines[j, 3]
            if (_det(inv_horizon * r1x - px, inv_horizon * r1y - py, dx, dy) - inv_horizon * radius >= -RVO_EPSILON
                    and _det(inv_horizon * r2x - px, inv_horizon * r2y - py, dx, dy) - inv_horizon * radius >= -RVO_EPSILON):  # fmt: skip
                covered = True
                break
        if covered:
            continue
        dist_sq1, dist_sq2 = r1x * r1x + r1y * r1y, r2x * r2x + r2y * r2y
        ox, oy = point[o2, 0] - point[o1, 0], point[o2, 1] - point[o1, 1]
        s = (-r1x * ox - r1y * oy) / (ox * ox + oy * oy)
        dist_sq_line = (-r1x - s * ox) ** 2 + (-r1y - s * oy) ** 2
        if s < 0.0 and dist_sq1 <= radius_sq:  # collision with the left vertex (ignored if non-convex)
            if convex[o1]:
                norm = math.sqrt(dist_sq1)
                lines[n, 0], lines[n, 1], lines[n, 2], lines[n, 3] = 0.0, 0.0, -r1y / norm, r1x / norm
                n += 1
            continue
        if s > 1.0 and dist_sq2 <= radius_sq:  # collision with the right vertex
            if convex[o2] and _det(r2x, r2y, direction[o2, 0], direction[o2, 1]) >= 0.0:
                norm = math.sqrt(dist_sq2)
                lines[n, 0], lines[n, 1], lines[n, 2], lines[n, 3] = 0.0, 0.0, -r2y / norm, r2x / norm
                n += 1
            continue
        if 0.0 <= s <= 1.0 and dist_sq_line <= radius_sq:  # collision with the segment
            lines[n, 0], lines[n, 1], lines[n, 2], lines[n, 3] = 0.0, 0.0, -direction[o1, 0], -direction[o1, 1]
            n += 1
            continue
        # no collision: the legs (both from one vertex when viewed obliquely)
        if s < 0.0 and dist_sq_line <= radius_sq:
            if not convex[o1]:
                continue
            o2 = o1
            llx, lly = _leg(r1x, r1y, dist_sq1, radius, True)
            rlx, rly = _leg(r1x, r1y, dist_sq1, radius, False)
        elif s > 1.0 and dist_sq_line <= radius_sq:
            if not convex[o2]:
                continue
            o1 = o2
            llx, lly = _leg(r2x, r2y, dist_sq2, radius, True)
            rlx, rly = _leg(r2x, r2y, dist_sq2, radius, False)
        else:
            if convex[o1]:
                llx, lly = _leg(r1x, r1y, dist_sq1, radius, True)
            else:  # non-convex left vertex: the left leg extends the cut-off line
                llx, lly = -direction[o1, 0], -direction[o1, 1]
            if convex[o2]:
                rlx, rly = _leg(r2x, r2y, dist_sq2, radius, False)
            else:
                rlx, rly = direction[o1, 0], direction[o1, 1]
        # a leg never points into the neighbouring edge at a convex vertex: take that edge's cut-off
        # line instead, and add no line if the velocity projects on such a "foreign" leg
        left_neighbour = prv[o1]
        left_foreign = right_foreign = False
        if convex[o1] and _det(llx, lly, -direction[left_neighbour, 0], -direction[left_neighbour, 1]) >= 0.0:
            llx, lly = -direction[left_neighbour, 0], -direction[left_neighbour, 1]
            left_foreign = True
        if convex[o2] and _det(rlx, rly, direction[o2, 0], direction[o2, 1]) <= 0.0:
            rlx, rly = direction[o2, 0], direction[o2, 1]
            right_foreign = True
        n += _project(agent, inv_horizon, obstacles, Legs(o1, o2, llx, lly, rlx, rly, left_foreign, right_foreign), lines[n])
    return n
