"""A* over (step, x, y, heading, v, ω) for the unicycle against known obstacle trajectories.

The unicycle's native counterpart of :mod:`agents.planners.spacetime.astar`, shared the same way by
the privileged clairvoyant oracle (the env's own future) and the ``astar-unicycle`` planner
(obstacles predicted from the observation).

**The state carries the velocities.** The env (``pathplan_env.robots.unicycle``) moves ``(v, ω)`` toward the
action's target by at most ``a dt`` and ``α dt`` at the start of a step, then flies one exact arc; so
what the robot can do next depends on ``(v, ω)`` as much as on the pose, and a search node holds all
five. **Motion primitives are the dynamic window**: from ``(v, ω)`` a move's target is ``v + f dv``
and ``ω + g dω`` for ``f`` in ``speed_steps`` and ``g`` in ``turn_steps`` (fractions of the window in
[-1, 1]; ±1 saturate: the action ±1, whose target is the limit itself). **Exact for the env**: each
target becomes the float32 action the agent will send (:func:`speed_move`, :func:`turn_move`: ``unicycle.to_action``'s
arithmetic, then ``command`` and ``next_velocity``'s), the arc is ``arc_contact.arc_point`` with the
heading wrapped as the env wraps it, and contact is the env's own compiled arc tests
(``arc_contact.arc_goal``, ``arc_capsule``, ``arc_disc``) substep by substep, stopping at the goal or
the first wall as ``unicycle.drive`` does; so a plan found on the env's own trajectory is the path
the env drives. The arena's edges are walls to the unicycle: they are among ``statics``.

Nodes merge per (step, ``cell`` of x and y, ``heading_bin``, velocity bins of the window's finest
step): complete only up to that grid. The heuristic, steps to cover the static cost-to-go
(:mod:`agents.planners.costtogo`) accelerating from ``v`` at ``dv`` a step to the top speed
(:func:`_steps_to_cover`), is a lower bound (turning is left out), so with ``h_weight`` 1 the first goal
node popped arrives earliest up to the grid.
"""

from __future__ import annotations

import heapq
import math
from typing import NamedTuple

import numba
import numpy as np

from agents.planners.costtogo import STRAIGHT_LINE, CostToGo, distance_to_goal
from agents.planners.spacetime.astar import BUDGET, EXHAUSTED, FOUND, HORIZON, Candidates, _near_statics, _segment_distance, step_paths
from pathplan_env.geometry.contacts import NO_CONTACT
from pathplan_env.robots.arc_contact import Arc, arc_capsule, arc_disc, arc_goal, arc_point

#: Columns of a pose row (``UnicycleResult.poses``, ``UnicycleProblem.start``).
X, Y, HEADING, SPEED, TURN_RATE = range(5)


class UnicycleModel(NamedTuple):
    """The robot's limits as the env applies them (``pathplan_env.robots.unicycle.UnicycleLimits`` and ``dt``)."""

    min_speed: float  # m/s: the lowest target
    max_speed: float  # m/s
    max_turn_rate: float  # rad/s
    dv: float  # m/s: max_acceleration * dt, the window's half-width in speed
    dw: float  # rad/s: max_angular_acceleration * dt
    dt: float  # s


class UnicycleProblem(NamedTuple):
    """Known obstacle trajectories and the robot's task: what :func:`search` and :func:`replay` read."""

    trajectory: np.ndarray  # (S + 1, N, >= 2): obstacle centres (m) after every substep from now
    substeps: int
    robot_radius: float  # m
    radii: np.ndarray  # (N,) m: contact radii
    start: np.ndarray  # (5,) the robot now: x, y, heading, v, ω (columns X..TURN_RATE)
    goal: np.ndarray  # (2,) m
    goal_radius: float  # m
    model: UnicycleModel
    statics: np.ndarray  # (M, 5) capsule rows: walls, polygon edges and the arena's edges
    cost_to_go: CostToGo = STRAIGHT_LINE


class UnicycleSettings(NamedTuple):
    """The search's primitives, depth, merge grid, budget and heuristic weight."""

    speed_steps: np.ndarray  # fractions of dv in [-1, 1]
    turn_steps: np.ndarray  # fractions of dw in [-1, 1]
    max_steps: int  # a node this deep is a leaf
    cell: float  # m
    heading_bin: float  # rad
    max_expansions: int
    h_weight: float


class UnicycleResult(NamedTuple):
    """What :func:`search` returns: the actions to send, one a step, and the poses they lead to."""

    outcome: int  # FOUND, HORIZON, EXHAUSTED or BUDGET (spacetime_search's)
    actions: np.ndarray  # (steps, 2) float32: the env's actions
    poses: np.ndarray  # (steps + 1, 5): the start, then the pose and velocities after each step
    expansions: int


def settings(speed_steps=(-1.0, 0.0, 1.0), turn_steps=(-1.0, -0.5, 0.0, 0.5, 1.0), max_steps: int = 20, cell: float = 0.05,
             heading_bin: float = 0.1, max_expansions: int = 2000, h_weight: float = 3.0) -> UnicycleSettings:  # fmt: skip
    """A checked :class:`UnicycleSettings`.

    :raises ValueError: naming the field.
    """
    steps = {}
    for name, values in (("speed_steps", speed_steps), ("turn_steps", turn_steps)):
        arr = np.asarray(values, np.float64).reshape(-1)
        if arr.size == 0 or not np.all(np.isfinite(arr)) or np.any(np.abs(arr) > 1.0):
            raise ValueError(f"{name} must be fractions of the dynamic window in [-1, 1], got {values!r}")
        steps[name] = np.unique(arr)
    for name, value in (("max_steps", max_steps), ("max_expansions", max_expansions)):
        if isinstance(value, bool) or int(value) != value or value < 1:
            raise ValueError(f"{name} must be a positive integer, got {value!r}")
    for name, value in (("cell", cell), ("heading_bin", heading_bin)):
        if not (math.isfinite(value) and value > 0):
            raise ValueError(f"{name} must be a finite number > 0, got {value!r}")
    if not (math.isfinite(h_weight) and h_weight >= 1.0):
        raise ValueError(f"h_weight must be a finite number >= 1, got {h_weight!r}")
    return UnicycleSettings(steps["speed_steps"], steps["turn_steps"], int(max_steps), float(cell), float(heading_bin),
                            int(max_expansions), float(h_weight))  # fmt: skip


@numba.njit(cache=True)
def speed_move(v, fraction, model):
    """``(a_v, v')``: the float32 action for the target ``v + fraction dv`` (``unicycle.to_action``; ±1 sends
    ±1, the limit itself, which saturates the window exactly) and the speed the env makes of it."""
    lo, span = model.min_speed, model.max_speed - model.min_speed
    if fraction >= 1.0:
        a = np.float32(1.0)
    elif fraction <= -1.0:
        a = np.float32(-1.0)
    else:
        target = min(max(v + fraction * model.dv, lo), model.max_speed)
        a = np.float32(min(max(2.0 * (target - lo) / span - 1.0, -1.0), 1.0)) if span > 0.0 else np.float32(1.0)
    target = lo + 0.5 * (float(a) + 1.0) * span  # unicycle.command
    return a, v + min(max(target - v, -model.dv), model.dv)  # unicycle.next_velocity


@numba.njit(cache=True)
def turn_move(w, fraction, model):
    """The turn rate's ``(a_ω, ω')``, as :func:`speed_move`."""
    if fraction >= 1.0:
        a = np.float32(1.0)
    elif fraction <= -1.0:
        a = np.float32(-1.0)
    else:
        target = min(max(w + fraction * model.dw, -model.max_turn_rate), model.max_turn_rate)
        a = np.float32(min(max(target / model.max_turn_rate, -1.0), 1.0))
    target = float(a) * model.max_turn_rate
    return a, w + min(max(target - w, -model.dw), model.dw)


@numba.njit(cache=True)
def fly_arc(problem, first, arc, candidates, ends, deviation):
    """One step of the :class:`UnicycleProblem` on ``arc`` from substep ``first``, as
    ``unicycle.drive`` flies it: 1 goal, 0 free, -1 contact.

    Only the obstacles ``near[:n_near]`` (:class:`~agents.planners.spacetime.astar.Candidates`) are
    tested, and of those the ones whose step path (``ends``, within ``deviation``) comes within the
    contact distance of the arc (its chord, inflated by the chord bound ``L |φ| / 8``, as in
    ``arc_contact``); the static capsules ``near_s[:n_near_s]``."""
    traj, n, robot_radius, radii, statics = problem.trajectory, problem.substeps, problem.robot_radius, problem.radii, problem.statics
    gx, gy, goal_radius = problem.goal[0], problem.goal[1], problem.goal_radius
    near, n_near, near_s, n_near_s = candidates
    goal = arc_goal(arc, gx, gy, goal_radius)
    f_end = min(goal, 1.0)
    for q in range(n_near_s):
        w = near_s[q]
        _, f = arc_capsule(arc, f_end, robot_radius, statics[w, 0], statics[w, 1], statics[w, 2], statics[w, 3], statics[w, 4])
        if f <= 1.0:
            return -1  # the robot stops touching a wall (drive: wall <= goal)
    stop = goal  # NO_CONTACT (> 1) when the goal is not reached
    ax, ay, _ = arc_point(arc, 0.0)
    bx, by, _ = arc_point(arc, 1.0)
    length = arc.speed * arc.duration
    bulge = length * abs(arc.turn_rate * arc.duration) / 8.0
    slack = 1e-9 * (1.0 + abs(ax) + abs(ay) + length)
    for q in range(n_near):
        o = near[q]
        if _segment_distance(ax, ay, bx, by, ends[o, 0], ends[o, 1], ends[o, 2], ends[o, 3]) > robot_radius + radii[o] + deviation[o] + bulge + slack:
            continue  # could not touch at any instant of the step
        for k in range(1, n + 1):
            u_end = 1.0 if stop >= k / n else max(stop * n - (k - 1), 0.0)
            f0 = (k - 1) / n
            f1 = f0 + u_end / n
            a, b = traj[first + k - 1], traj[first + k]
            oax, oay = a[o, 0], a[o, 1]
            _, u = arc_disc(arc, f0, f1, oax, oay, oax + u_end * (b[o, 0] - oax), oay + u_end * (b[o, 1] - oay), robot_radius + radii[o])
            if u <= 1.0:
                return -1
            if u_end < 1.0 or stop == k / n:
                break
    return 1 if goal <= 1.0 else 0


@numba.njit(cache=True, inline="always")
def _steps_to_cover(d, v, model):
    """Fewest steps in which a robot at speed ``v`` accelerating at ``dv`` a step can fly ``d`` metres."""
    if d <= 0.0:
        return 0.0
    k, covered = 0, 0.0
    while v < model.max_speed and covered < d:
        v = min(v + model.dv, model.max_speed)
        covered += v * model.dt
        k += 1
    if covered >= d:
        return float(k)
    return k + math.ceil((d - covered) / (model.max_speed * model.dt) - 1e-9)


@numba.njit(cache=True, inline="always")
def _next_pose(x, y, heading, v, w, dt):
    """The pose after one step of ``(v, ω)``, as the env computes and wraps it."""
    nx, ny, nh = arc_point(Arc(x, y, heading, v, w, dt), 1.0)
    return nx, ny, math.atan2(math.sin(nh), math.cos(nh))


@numba.njit(cache=True)
def _finest(steps):
    """The smallest nonzero ``|step|`` (1 if none): the velocity bin, in units of the window."""
    finest = 1.0
    for f in steps:
        if f != 0.0:
            finest = min(finest, abs(f))
    return finest


@numba.njit(cache=True, inline="always")
def _near_obstacles(x, y, ends, deviation, radii, robot_radius, reach, near):
    """Write to ``near`` the obstacles whose step path (``ends``, within ``deviation``) comes within
    ``reach`` plus the contact distance of ``(x, y)`` (every arc of the step stays within ``reach``); their count."""
    count = 0
    for o in range(radii.shape[0]):
        if _segment_distance(x, y, x, y, ends[o, 0], ends[o, 1], ends[o, 2], ends[o, 3]) - robot_radius - radii[o] <= reach + deviation[o]:
            near[count] = o
            count += 1
    return count


@numba.njit(cache=True)
def _unwind(last, node, node_k, node_parent, node_action):
    """``(actions, poses)`` from the root to node ``last``."""
    steps = node_k[last]
    actions = np.empty((steps, 2), np.float32)
    poses = np.empty((steps + 1, 5))
    j = last
    for s in range(steps, -1, -1):
        poses[s] = node[j]
        if s > 0:
            actions[s - 1] = node_action[j]
        j = node_parent[j]
    return actions, poses


@numba.njit(cache=True)
def search(problem, settings):
    """Earliest-arrival A* from ``problem.start`` at substep 0 (a :class:`UnicycleProblem`, :class:`UnicycleSettings`).

    A node at depth ``max_steps`` is a leaf: when one is popped before any goal node the search stops
    there (``HORIZON``). :return: a :class:`UnicycleResult` (the found plan, the horizon leaf, or the
    deepest node reached when the search fails)."""
    traj, n, robot_radius, radii, model = problem.trajectory, problem.substeps, problem.robot_radius, problem.radii, problem.model
    goal, goal_radius, statics, ctg = problem.goal, problem.goal_radius, problem.statics, problem.cost_to_go
    speed_steps, turn_steps = settings.speed_steps, settings.turn_steps
    cell, heading_bin, max_steps = settings.cell, settings.heading_bin, settings.max_steps
    v_bin, w_bin = _finest(speed_steps) * model.dv, _finest(turn_steps) * model.dw
    reach = model.max_speed * model.dt
    xs, ys = problem.start[X], problem.start[Y]
    x0, y0 = xs - (max_steps + 1) * reach, ys - (max_steps + 1) * reach  # every node lies within this box
    span_cells = int(2 * (max_steps + 1) * reach / cell) + 2
    n_head = int(2 * math.pi / heading_bin) + 2
    n_v = int(model.max_speed / v_bin + 0.5) + 2
    n_w = int(2 * model.max_turn_rate / w_bin + 0.5) + 2
    m_total = speed_steps.shape[0] * turn_steps.shape[0]
    cap = min(settings.max_expansions * m_total + 1, 4_000_000)
    node = np.empty((cap, 5))
    node_k = np.empty(cap, np.int64)
    node_parent = np.empty(cap, np.int64)
    node_action = np.empty((cap, 2), np.float32)
    seen = numba.typed.Dict.empty(numba.types.int64, numba.types.int64)
    near = np.empty(radii.shape[0], np.int64)
    near_s = np.empty(statics.shape[0], np.int64)
    paths = step_paths(traj, n)

    def h(x, y, v):
        d = min(distance_to_goal(ctg, x, y, goal[0], goal[1], goal_radius), 1e9 * reach)  # inf: walled off
        return _steps_to_cover(d, v, model)

    node[0] = problem.start[:5]
    node_k[0], node_parent[0] = 0, -1
    count = 1
    h0 = h(xs, ys, problem.start[SPEED])
    heap = [(settings.h_weight * h0, 0, 0)]
    deepest, deepest_k, deepest_h = 0, 0, h0
    expansions, found, outcome = 0, -1, EXHAUSTED
    while len(heap) > 0:
        _, _, i = heapq.heappop(heap)
        k = node_k[i]
        if k == max_steps:
            found, outcome = i, HORIZON
            break
        if expansions >= settings.max_expansions:
            outcome = BUDGET
            break
        expansions += 1
        x, y, heading, v, w = node[i, 0], node[i, 1], node[i, 2], node[i, 3], node[i, 4]
        first = k * n
        ends, deviation = paths.ends[k], paths.deviation[k]
        slack = 1e-9 * (1.0 + abs(x) + abs(y) + reach)
        n_near = _near_obstacles(x, y, ends, deviation, radii, robot_radius, reach + slack, near)
        n_near_s = _near_statics(x, y, statics, robot_radius, reach + slack, near_s)
        for si in range(speed_steps.shape[0]):
            a_v, nv = speed_move(v, speed_steps[si], model)
            for ti in range(turn_steps.shape[0]):
                a_w, nw = turn_move(w, turn_steps[ti], model)
                arc = Arc(x, y, heading, nv, nw, model.dt)
                result = fly_arc(problem, first, arc, Candidates(near, n_near, near_s, n_near_s), ends, deviation)
                if result < 0:
                    continue
                nx, ny, nh = _next_pose(x, y, heading, nv, nw, model.dt)
                if result == 0:
                    key = ((k + 1) * span_cells + int((nx - x0) / cell)) * span_cells + int((ny - y0) / cell)
                    key = (key * n_head + int((nh + math.pi) / heading_bin)) * n_v + int(nv / v_bin + 0.5)
                    key = key * n_w + int((nw + model.max_turn_rate) / w_bin + 0.5)
                    if key in seen or count >= cap:
                        continue
                    seen[key] = 1
                node[count, 0], node[count, 1], node[count, 2], node[count, 3], node[count, 4] = nx, ny, nh, nv, nw
                node_k[count], node_parent[count] = k + 1, i
                node_action[count, 0], node_action[count, 1] = a_v, a_w
                if result == 1:
                    found, outcome = count, FOUND
                    count += 1
                    break
                hn = h(nx, ny, nv)
                heapq.heappush(heap, (k + 1 + settings.h_weight * hn, -(k + 1), count))
                if k + 1 > deepest_k or (k + 1 == deepest_k and hn < deepest_h):
                    deepest, deepest_k, deepest_h = count, k + 1, hn
                count += 1
            if outcome == FOUND:
                break
        if outcome == FOUND:
            break
    actions, poses = _unwind(found if found >= 0 else deepest, node, node_k, node_parent, node_action)
    return UnicycleResult(outcome, actions, poses, expansions)


@numba.njit(cache=True)
def replay(problem, actions):
    """Fly ``actions`` from ``problem.start`` through ``problem.trajectory`` as the env would.

    :return: ``(steps, reached)``: the steps flown free of contact (all of them if none touches) and
        whether the goal is reached within them."""
    traj, n, radii, model = problem.trajectory, problem.substeps, problem.radii, problem.model
    statics = problem.statics
    x, y, heading, v, w = problem.start[X], problem.start[Y], problem.start[HEADING], problem.start[SPEED], problem.start[TURN_RATE]
    steps = min(actions.shape[0], (traj.shape[0] - 1) // n)
    near = np.arange(radii.shape[0])
    every_static = np.arange(statics.shape[0])
    paths = step_paths(traj, n)
    lo, span = model.min_speed, model.max_speed - model.min_speed
    for k in range(steps):
        target_v = lo + 0.5 * (float(actions[k, 0]) + 1.0) * span  # unicycle.command, next_velocity
        target_w = float(actions[k, 1]) * model.max_turn_rate
        v = v + min(max(target_v - v, -model.dv), model.dv)
        w = w + min(max(target_w - w, -model.dw), model.dw)
        arc = Arc(x, y, heading, v, w, model.dt)
        candidates = Candidates(near, radii.shape[0], every_static, statics.shape[0])
        result = fly_arc(problem, k * n, arc, candidates, paths.ends[k], paths.deviation[k])
        if result < 0:
            return k, False
        if result == 1:
            return k + 1, True
        x, y, heading = _next_pose(x, y, heading, v, w, model.dt)
    return steps, False


__all__ = ["BUDGET", "EXHAUSTED", "FOUND", "HORIZON", "NO_CONTACT", "UnicycleModel", "UnicycleProblem", "UnicycleResult",
           "UnicycleSettings", "fly_arc", "replay", "search", "settings", "speed_move", "turn_move"]  # fmt: skip
