"""A unicycle's control sequence, rolled out and scored in compiled code (``pso-unicycle``, ``abc-unicycle``).

A candidate is ``K`` normalised targets ``(a_v, a_ω)`` (the env's own action, ``[-1, 1]^2`` each), each
held for ``hold`` steps: a plan of ``H = K * hold`` steps, flattened to ``2K`` numbers. The rollout is
the env's step operation for operation (``pathplan_env.robots.unicycle_step.step_velocity``: the target
reached within the acceleration limits at each step's start, then one exact arc; the heading
wrapped as the env wraps it), so the plan goes where the env would drive it (tested).

The cost (:func:`control_cost`) is the space-time objective's (``timed_objective.timed_path_cost``) on
arcs: each step's arc is tested against the predicted obstacles at every substep with the env's
exact arc contact (``arc_contact.arc_disc``; pairs farther apart than both can travel are skipped),
and against the walls, polygon edges and the arena's edges (``arc_contact.arc_capsule``: the
arena's edges are walls to the unicycle). Each obstacle touched pays the paper's Eq. 4 (its contact
disc's circumference plus ``penalty_weight`` times the deepest cut), the rest of the horizon after
the touch and ``INFEASIBLE``, as does the first wall touch, so every contact-free plan costs less
than any plan with one. The arrival time counts in steps: where the goal is reached, or past the
horizon the static cost-to-go from where the plan ends (``costtogo.distance_to_goal``) at top
speed, plus the time the robot still needs to turn toward the goal (``turn_weight`` times the
bearing at the top turn rate) and to regain top speed.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba
import numpy as np
from numba.extending import overload

from agents.planners.costtogo import CostToGo, distance_to_goal
from agents.planners.objective import objective
from agents.planners.path_pieces import TWO_PI
from agents.planners.timed_objective import INFEASIBLE
from pathplan_env.geometry.contacts import NO_CONTACT
from pathplan_env.geometry.walls import point_segment
from pathplan_env.robots.arc_contact import Arc, ArcPiece, arc_capsule, arc_disc_between, arc_goal, arc_point
from pathplan_env.robots.unicycle_step import DV, MAX_SPEED, MAX_TURN_RATE, MIN_SPEED, PARAMS_SIZE, pose, step_velocity

#: Metres added to a reach disc's radius (far above rounding, far below any clearance): an obstacle it
#: skips is one its own distance test would skip too, so skipping by disc changes no cost (bit for bit).
REACH_SLACK = 1e-9

#: Columns of :class:`UnicycleScene`'s ``start``: the robot's pose and velocities now.
X, Y, HEADING, SPEED, TURN_RATE = range(5)


class UnicycleScene(NamedTuple):
    """What one control sequence's cost needs (:func:`control_cost`): the predicted obstacles, the
    robot's state, limits and task."""

    trajectory: np.ndarray  # (H * substeps + 1, N, >= 2) predicted obstacle centres (m) at every substep
    substeps: int
    robot_radius: float  # m
    contact_radii: np.ndarray  # (N,) m: obstacle radii with the margin
    start: np.ndarray  # (5,) x, y (m), heading (rad), speed (m/s), turn rate (rad/s): the columns above
    goal: np.ndarray  # (2,) m
    goal_radius: float  # m
    params: np.ndarray  # (PARAMS_SIZE,) the limits in ``pathplan_env.robots.unicycle_step``'s columns
    dt: float  # s
    hold: int  # steps each control is held
    horizon_steps: int  # H = K * hold
    penalty_weight: float  # Eq. 4's weight on the depth of a cut (dimensionless)
    travel: np.ndarray  # (H, N) m: each obstacle's path length in each step
    segments: np.ndarray  # (M, 5) walls, polygon edges and the arena's edges (capsule rows)
    cost_to_go: CostToGo  # the static cost-to-go past the horizon
    turn_weight: float  # weight of the time still needed to face the goal at the horizon
    futures: int  # F predicted futures per obstacle (the cone's 3, else 1): columns o, o + G, .. of one obstacle (N = F G)
    reach_discs: np.ndarray  # (H, G, 3) x, y, radius: a disc per step holding every future's start, travel and contact distance
    near_groups: np.ndarray  # (G',) int: the obstacles (indices into reach_discs) some plan can reach within the horizon


@numba.njit(cache=True, error_model="numpy")
def broad_phase(scene):
    """``(reach_discs, segments, near_groups)`` for a :class:`UnicycleScene` whose other fields are set.

    Each obstacle's disc per step is centred on its middle future at the step's start, wide enough to
    hold every future's start plus its contact distance and travel that step: one distance to it skips
    all the obstacle's futures at once (the cone triples them). The robot moves at most ``|v| dt`` a
    step (``|v|`` bounded by its limits and its speed now), so a capsule or an obstacle farther from
    the start than that (by ``REACH_SLACK``) at every step fails :func:`control_cost`'s own distance
    tests at every step: it is left out (``segments``, ``near_groups``), which changes no cost (bit for
    bit) and saves those tests in every evaluation. One call a replan (numpy took ten times longer)."""
    traj, n, futures, travel = scene.trajectory, scene.substeps, scene.futures, scene.travel
    params, start, rr, horizon = scene.params, scene.start, scene.robot_radius, scene.horizon_steps
    contact_radii, segments = scene.contact_radii, scene.segments
    groups = contact_radii.shape[0] // futures
    step = scene.dt * max(abs(params[MIN_SPEED]), params[MAX_SPEED], abs(start[SPEED]))
    discs = np.empty((horizon, groups, 3))
    near = np.zeros(groups, np.bool_)
    for s in range(horizon):
        row = s * n
        for g in range(groups):
            middle = g + (futures // 2) * groups
            cx, cy = traj[row, middle, 0], traj[row, middle, 1]
            radius = 0.0
            for k in range(futures):
                o = g + k * groups
                spread = math.hypot(traj[row, o, 0] - cx, traj[row, o, 1] - cy)
                radius = max(radius, spread + travel[s, o] + (rr + contact_radii[o]))
            discs[s, g, 0], discs[s, g, 1], discs[s, g, 2] = cx, cy, radius
            # at step s the robot is at most s steps from the start, and its arc one step long
            if math.hypot(cx - start[X], cy - start[Y]) <= (s + 1) * step + radius + REACH_SLACK:
                near[g] = True
    keep = np.zeros(segments.shape[0], np.bool_)
    for k in range(segments.shape[0]):
        gap = point_segment(start[X], start[Y], segments[k, 0], segments[k, 1], segments[k, 2], segments[k, 3]) - rr - segments[k, 4]
        keep[k] = gap <= horizon * step + REACH_SLACK
    return discs, np.ascontiguousarray(segments[keep]), np.flatnonzero(near)


def unicycle_params(limits, dt: float) -> np.ndarray:
    """A ``pathplan_env.robots.unicycle.UnicycleLimits`` as the kernels' ``params`` array (the env's own)."""
    params = np.zeros(PARAMS_SIZE)
    params[:5] = limits.min_speed, limits.max_speed, limits.max_turn_rate, limits.max_acceleration * dt, limits.max_angular_acceleration * dt
    return params


@numba.njit(cache=True, inline="always")
def _wrap(angle):
    return math.atan2(math.sin(angle), math.cos(angle))


@numba.njit(cache=True)
def rollout(x, scene):
    """The states ``(H + 1, 5)`` (the ``start`` columns) after every step of the controls ``x``, flown
    in full (no stop at a contact or the goal), as the env flies them."""
    out = np.empty((scene.horizon_steps + 1, 5))
    px, py, heading, v, w = scene.start[X], scene.start[Y], scene.start[HEADING], scene.start[SPEED], scene.start[TURN_RATE]
    out[0] = px, py, heading, v, w
    for step in range(scene.horizon_steps):
        c = step // scene.hold
        v, w = step_velocity(x[2 * c], x[2 * c + 1], v, w, scene.params)
        px, py, heading = pose(px, py, heading, v, w, scene.dt, 1.0)
        heading = _wrap(heading)
        out[step + 1] = px, py, heading, v, w
    return out


@numba.njit(cache=True, inline="always", error_model="numpy")
def _obstacle_contacts(arc, end_x, end_y, step, goal_f, scene, depth, first_touch, sx, sy):
    """Step ``step``'s arc against every predicted obstacle at every substep (before the goal, at
    ``goal_f``): the first touch (steps) and the deepest cut of each, updated in place. ``sx, sy``:
    room for the arc's points at the substeps' ends, computed once if any obstacle is within reach
    (its ends are the arc's start and ``end_x, end_y``, the step's pose: ``arc_point`` at 0 and 1 gives
    the same numbers, the same operations as ``pose``)."""
    traj, n, rr, radii = scene.trajectory, scene.substeps, scene.robot_radius, scene.contact_radii
    length = abs(arc.speed) * arc.duration  # the arc's length: none of it is farther from its start
    first = step * n
    ready = False
    sub_length = sub_delta = 0.0
    discs, futures = scene.reach_discs, scene.futures
    groups = discs.shape[1]
    for g in scene.near_groups:
        # one squared distance for all of an obstacle's futures; REACH_SLACK makes this skip strictly
        # rarer than each future's own test below, so the pairs tested are the same as without it
        dx, dy, far = arc.x - discs[step, g, 0], arc.y - discs[step, g, 1], length + discs[step, g, 2] + REACH_SLACK
        if dx * dx + dy * dy > far * far:
            continue
        for k in range(futures):
            o = g + k * groups
            contact = rr + radii[o]
            if math.hypot(arc.x - traj[first, o, 0], arc.y - traj[first, o, 1]) - contact > length + scene.travel[step, o]:
                continue
            if not ready:
                sx[0], sy[0], sx[n], sy[n] = arc.x, arc.y, end_x, end_y
                for j in range(1, n):
                    sx[j], sy[j], _ = arc_point(arc, j / n)
                sub_length = length / n
                sub_delta = sub_length * abs(arc.turn_rate * arc.duration / n) / 8.0  # arc_contact's chord bound L |phi| / 8
                ready = True
            for j in range(1, n + 1):
                a, b = first + j - 1, first + j
                piece = ArcPiece((j - 1) / n, j / n, sx[j - 1], sy[j - 1], sx[j], sy[j], sub_length, sub_delta)
                gap, u = arc_disc_between(arc, piece, traj[a, o, 0], traj[a, o, 1], traj[b, o, 0], traj[b, o, 1], contact)
                if u <= 1.0 and (j - 1 + u) / n <= goal_f:  # a contact before the goal counts
                    if first_touch[o] < 0.0:
                        first_touch[o] = step + (j - 1 + u) / n
                    depth[o] = max(depth[o], -gap)


@numba.njit(cache=True, inline="always", error_model="numpy")
def _first_wall(arc, f_end, robot_radius, segments):
    """The fraction of the arc (up to ``f_end``) at which it first touches a capsule (``NO_CONTACT``: none)."""
    length = abs(arc.speed) * arc.duration
    first = NO_CONTACT
    for s in range(segments.shape[0]):
        x0, y0, x1, y1, half = segments[s, 0], segments[s, 1], segments[s, 2], segments[s, 3], segments[s, 4]
        if point_segment(arc.x, arc.y, x0, y0, x1, y1) - robot_radius - half > length:
            continue
        _, f = arc_capsule(arc, f_end, robot_radius, x0, y0, x1, y1, half)
        if f <= f_end:
            first = min(first, f)
    return first


@numba.njit(cache=True, inline="always", error_model="numpy")
def _steps_to_go(scene, px, py, heading, v):
    """Steps past the horizon: the static cost-to-go at top speed, the turn toward the goal at the top
    turn rate (weighted) and the time lost regaining top speed, ``(V - v)^2 / (2 a V)``."""
    params, dt = scene.params, scene.dt
    gx, gy = scene.goal[0], scene.goal[1]
    to_go = distance_to_goal(scene.cost_to_go, px, py, gx, gy, scene.goal_radius)
    bearing = abs(_wrap(math.atan2(gy - py, gx - px) - heading))
    lost = params[MAX_SPEED] - v
    ramp = lost * lost / (2.0 * (params[DV] / dt) * params[MAX_SPEED]) if params[DV] > 0.0 else 0.0
    return to_go / (params[MAX_SPEED] * dt) + scene.turn_weight * bearing / (params[MAX_TURN_RATE] * dt) + ramp / dt


@numba.njit(cache=True, inline="always", error_model="numpy")
def control_cost(x, scene):
    """``(cost, penalty)`` of the controls ``x`` (2K) for a :class:`UnicycleScene`, in metres at top
    speed (the module's doc); the penalty counts the predicted contacts (the constraint the modified
    ABC's scouts test).

    Hot (a replan evaluates about a thousand): the goal, an obstacle or a capsule farther than the
    step's arc length (plus the obstacle's travel) is skipped with one distance, the arc's substep
    points are computed once for every obstacle that is not, and the heading is wrapped only at the
    end (the rollout wraps it every step as the env does; the arcs are the same to rounding)."""
    n, rr, radii = scene.substeps, scene.robot_radius, scene.contact_radii
    gx, gy, goal_radius, params, dt = scene.goal[0], scene.goal[1], scene.goal_radius, scene.params, scene.dt
    horizon, segments = scene.horizon_steps, scene.segments
    reach = params[MAX_SPEED] * dt
    px, py, heading, v, w = scene.start[X], scene.start[Y], scene.start[HEADING], scene.start[SPEED], scene.start[TURN_RATE]
    n_obs = radii.shape[0]
    work = np.empty(2 * n_obs + 2 * (n + 1))  # one allocation an evaluation
    depth, first_touch = work[:n_obs], work[n_obs : 2 * n_obs]  # deepest cut; when first touched (steps; -1: not)
    sx, sy = work[2 * n_obs : 2 * n_obs + n + 1], work[2 * n_obs + n + 1 :]  # the arc's points at the substeps' ends
    depth[:] = 0.0
    first_touch[:] = -1.0
    wall_touch = -1.0
    arrival = -1.0
    for step in range(horizon):
        c = step // scene.hold
        v, w = step_velocity(x[2 * c], x[2 * c + 1], v, w, params)
        arc = Arc(px, py, heading, v, w, dt)
        goal_f = NO_CONTACT
        if math.hypot(px - gx, py - gy) - goal_radius <= abs(v) * dt:  # within the arc's length
            goal_f = arc_goal(arc, gx, gy, goal_radius)
        end_x, end_y, end_heading = pose(px, py, heading, v, w, dt, 1.0)
        _obstacle_contacts(arc, end_x, end_y, step, goal_f, scene, depth, first_touch, sx, sy)
        if wall_touch < 0.0:  # only the first touch counts, as the env stops there
            f = _first_wall(arc, min(goal_f, 1.0), rr, segments)
            if f <= 1.0:
                wall_touch = step + f
        px, py, heading = end_x, end_y, end_heading
        if goal_f <= 1.0:
            arrival = step + goal_f
            break
    if arrival < 0.0:
        arrival = horizon + _steps_to_go(scene, px, py, heading, v)
    penalty = 0.0
    if wall_touch >= 0.0:  # Eq. 4 for the wall, the rest of the horizon, the feasibility offset
        penalty = TWO_PI * rr + (horizon - wall_touch) * reach + INFEASIBLE
    for o in range(n_obs):
        if first_touch[o] >= 0.0:
            penalty += TWO_PI * (radii[o] + rr) + scene.penalty_weight * depth[o] + (horizon - first_touch[o]) * reach + INFEASIBLE
    return arrival * reach + penalty, penalty


@overload(objective)
def _unicycle_objective(x, problem):
    """``objective`` for a :class:`UnicycleScene`: the optimisers (``pso_run``, ``abc_run``) run on it
    unchanged (numba tries every overload of ``objective``; the others refuse this record)."""
    if getattr(problem, "instance_class", None) is UnicycleScene:
        return lambda x, problem: control_cost(x, problem)
    return None


@numba.njit(cache=True, error_model="numpy")
def population_cost(X, scene):
    """Costs and penalties of candidates ``X`` (P, 2K) in one call."""
    cost, penalty = np.empty(X.shape[0]), np.empty(X.shape[0])
    for i in range(X.shape[0]):
        cost[i], penalty[i] = control_cost(X[i], scene)
    return cost, penalty


__all__ = ["UnicycleScene", "broad_phase", "control_cost", "population_cost", "rollout", "unicycle_params"]
