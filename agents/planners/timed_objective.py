"""The space-time objective (:func:`timed_path_cost`): a timed path (waypoints and a speed for each
segment) flown step by step against the predicted obstacles, walls and polygons, with the paper's
Eq. 4 on every cut and the contact constraint within the horizon; its problem is a :class:`TimedScene`.
The static and predictive objective, and the dispatch that lets an optimiser be written once for
both, are in :mod:`agents.planners.objective`.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba
import numpy as np

from agents.planners.costtogo import STRAIGHT_LINE, CostToGo, distance_to_goal
from agents.planners.path_pieces import TWO_PI, _segment_origin_distance_sq, capsule_penalty, segment_distance, walk_along
from agents.planners.resting_discs import (
    EVERY_OBSTACLE,
    RestingSet,
    broad_phase_of,
    moving_obstacles,
    obstacles_along,
    off_chord,
)
from pathplan_env.geometry.contacts import swept_pair
from pathplan_env.geometry.disc_grid import span_of
from pathplan_env.geometry.swept_walls import swept_capsule
from pathplan_env.robots.holonomic import reach_fraction, substep_point

#: Added to a timed plan's cost per obstacle it is predicted to touch within the horizon (m): more
#: than any contact-free plan can cost (its arrival and detours are bounded by a few arena crossings).
INFEASIBLE = 1e4
#: What a timed plan's penalty measures (``TimedScene.violation``). ``CONTACTS``: Eq. 4 on every
#: obstacle touched within the horizon, each with the feasibility offset (the planners' first rule).
#: ``FIRST_CONTACT``: how early the first predicted contact comes (the rest of the horizon after it,
#: in metres at top speed, weighted by ``SURVIVAL_WEIGHT``), then Eq. 4 on every contact, with one
#: feasibility offset: where every plan touches something (dense, fast scenes), the plan that stays
#: free longest leaves replanning the most time, however many obstacles it touches later.
CONTACTS, FIRST_CONTACT = 0, 1
SURVIVAL_WEIGHT = 100.0


class TimedScene(NamedTuple):
    """What one plan of the space-time objective needs (:func:`timed_path_cost`): the predicted
    obstacles, the robot's task and its step."""

    trajectory: np.ndarray  # (S * substeps + 1, N, >= 2): predicted obstacle centres (m) at every substep
    substeps: int  # substeps a step
    robot_radius: float  # m
    contact_radii: np.ndarray  # (N,) m: obstacle radii with the margin
    robot: np.ndarray  # (2,) m
    goal: np.ndarray  # (2,) m
    goal_radius: float  # m
    reach: float  # m: the robot's step at top speed
    horizon_steps: int  # steps checked against ``trajectory``
    penalty_weight: float  # penalty per metre of cut depth (dimensionless)
    travel: np.ndarray  # (horizon_steps, N) m: each obstacle's path length in each step
    statics: np.ndarray = np.zeros((0, 5))  # (M, 5) walls and polygon edges (``World.static_segments`` rows)
    cost_to_go: CostToGo = STRAIGHT_LINE  # the rest of the path past the horizon (:mod:`agents.planners.costtogo`)
    violation: int = CONTACTS  # what the penalty measures: ``CONTACTS`` or ``FIRST_CONTACT``
    offset: float = INFEASIBLE  # added once per touched obstacle (``CONTACTS``) or once (``FIRST_CONTACT``)
    # with a cost-to-go field, whether the rest's straight pieces past the horizon pay Eq. 4 on the obstacles
    rest_obstacles: bool = True
    # weight of the running cost: the mean cost-to-go at the end of each step within the horizon (0: none)
    progress_weight: float = 0.0
    # (N,) or empty: obstacles the rest's pieces never pay Eq. 4 on, resting ones the cost-to-go already
    # goes round (as walls: charging both held the planners among a few hundred cylinders)
    rest_exempt: np.ndarray = np.zeros(0, np.bool_)
    # the broad phase: which obstacles rest, in a grid (:mod:`agents.planners.resting_discs`; default: none, visit all)
    resting: RestingSet | None = EVERY_OBSTACLE
    # every resting obstacle of ``resting`` is ``rest_exempt``: the rest's pieces visit the moving ones
    # alone (the grid's would all be skipped; among 300 cylinders a long piece lists a hundred of them)
    rest_skips_resting: bool = False


@numba.njit(cache=True, inline="always", error_model="numpy")
def _wall_contact(scene, px, py, qx, qy, goal_t, step, touch, touch_depth):
    """The robot's chord ``p -> q`` in step ``step`` (at most ``scene.reach`` long) against the
    scene's walls (``scene.statics``) as the env tests them (one swept test of the whole move):
    ``(when it first touches, in steps, and the deepest overlap)``; ``(touch, touch_depth)`` as given
    if an earlier step touched already or this one does not before the goal (at ``goal_t``)."""
    if touch >= 0.0:  # only the first touch counts, as for an obstacle
        return touch, touch_depth
    robot_radius, statics, reach = scene.robot_radius, scene.statics, scene.reach
    t_first, depth = 2.0, 0.0
    for w in range(statics.shape[0]):
        x0, y0, x1, y1, half = statics[w, 0], statics[w, 1], statics[w, 2], statics[w, 3], statics[w, 4]
        if segment_distance(px, py, px, py, x0, y0, x1, y1) - robot_radius - half > reach:
            continue
        gap, t_hit = swept_capsule(px, py, qx, qy, robot_radius, x0, y0, x1, y1, half)
        if t_hit <= 1.0:
            t_first, depth = min(t_first, t_hit), max(depth, -gap)
    if t_first <= 1.0 and t_first <= goal_t:
        return step + t_first, depth
    return touch, touch_depth


@numba.njit(cache=True, inline="always", error_model="numpy")
def _running_to_go(scene, x, y):
    """The running cost's term for a step that ends at ``(x, y)``: its cost-to-go (0 without
    ``progress_weight``, and inside a wall, where it is inf: a wall contact, which the penalty ranks)."""
    if scene.progress_weight <= 0.0:
        return 0.0
    to_go = distance_to_goal(scene.cost_to_go, x, y, scene.goal[0], scene.goal[1], scene.goal_radius)
    return to_go if to_go < math.inf else 0.0


@numba.njit(cache=True, inline="always", error_model="numpy")
def _contact_penalty(scene, near, hits, n_hits, first_touch, depth, wall_touch, wall_depth):
    """The constraint: the penalty of the contacts within the horizon, as ``scene.violation`` measures it.

    Each contact (a wall's, or of the obstacles touched, ``hits[:n_hits]`` ascending, a ``near`` one) pays Eq. 4 and the rest of the horizon after
    it (a later touch costs less); ``CONTACTS`` adds the feasibility offset to each, ``FIRST_CONTACT``
    adds it once, with ``SURVIVAL_WEIGHT`` times the rest of the horizon after the earliest contact."""
    horizon_steps, reach, robot_radius, penalty_weight = scene.horizon_steps, scene.reach, scene.robot_radius, scene.penalty_weight
    first = scene.violation == FIRST_CONTACT
    offset = 0.0 if first else scene.offset
    survival = float(horizon_steps)
    penalty = 0.0
    if wall_touch >= 0.0:
        penalty = TWO_PI * robot_radius + penalty_weight * wall_depth + (horizon_steps - wall_touch) * reach + offset
        survival = wall_touch
    for q in range(n_hits):
        o = hits[q]
        if near[o]:
            penalty += (TWO_PI * (scene.contact_radii[o] + robot_radius) + penalty_weight * depth[o]
                        + (horizon_steps - first_touch[o]) * reach) + offset  # fmt: skip
            survival = min(survival, first_touch[o])
    if first and penalty > 0.0:
        penalty += SURVIVAL_WEIGHT * (horizon_steps - survival) * reach + scene.offset
    return penalty


@numba.njit(cache=True, inline="always")
def _touch(o, touched, depth, hits, n_hits):
    """Mark obstacle ``o`` touched: on its first touch its depth starts at 0 and it joins ``hits[:n_hits]``; the new count."""
    if touched[o]:
        return n_hits
    touched[o] = True
    depth[o] = 0.0
    hits[n_hits] = o
    return n_hits + 1


@numba.njit(cache=True, inline="always")
def _rest_visits(scene, no_movers, ax, ay, bx, by, visit):
    """The obstacles a piece ``a``-``b`` of the rest visits (written to ``visit``, :func:`visited`): the moving
    ones alone where every resting one is exempt (:attr:`TimedScene.rest_skips_resting`), none without a
    mover (``no_movers``: a broad phase's grid holds every obstacle; no compiled call a piece); their count."""
    if scene.rest_skips_resting:
        if no_movers:
            return 0
        return moving_obstacles(scene.resting, scene.contact_radii.shape[0], visit)
    return obstacles_along(scene.resting, scene.contact_radii.shape[0], ax, ay, bx, by, scene.robot_radius, visit)


@numba.njit(cache=True, inline="always")
def _step_visits(scene, broad, n_moving, shape, start, items, px, py, visit, span):
    """The obstacles a step from ``p`` may touch (:func:`~agents.planners.resting_discs.obstacles_near`'s list, reusing the last step's) (``broad``,
    ``n_moving``, ``shape``: what :func:`broad_phase_of` read; ``start``, ``items``: the grid's arrays,
    :func:`broad_phase_of`; ``visit[:n_moving]`` holds the moving ones already): where the step's grid cells
    are the last one's, its count is read here; else the cells' discs are collected here, in the same
    order (a compiled call taking the record cost more than a step's tests)."""
    n_obs, distance = scene.contact_radii.shape[0], scene.reach + scene.robot_radius
    if not broad:
        return n_obs
    i0, i1, j0, j1 = span_of(shape, px, py, px, py, distance)
    if i0 == span[0] and i1 == span[1] and j0 == span[2] and j1 == span[3]:
        return n_moving + span[4]
    ny = shape[4]
    count = n_moving
    for i in range(i0, i1 + 1):
        for c in range(start[i * ny + j0], start[i * ny + j1 + 1]):
            visit[count] = items[c]
            count += 1
    span[0], span[1], span[2], span[3], span[4] = i0, i1, j0, j1, count - n_moving
    return count


@numba.njit(cache=True, inline="always", error_model="numpy")
def _out_of_reach(scene, rests, o, step, px, py, dx, dy, ee):
    """Whether the robot's step ``step`` from ``p`` by ``d`` (``ee``: ``|d|^2``) cannot touch obstacle
    ``o``, so that its substep tests are passed over: a resting one (``rests``) off the chord
    (:func:`off_chord`: one test for ``substeps``), or one that starts farther than both move."""
    robot_radius, contact_radius = scene.robot_radius, scene.contact_radii[o]
    if rests and off_chord(scene.trajectory[0, o, 0], scene.trajectory[0, o, 1], px, py, dx, dy, ee, robot_radius + contact_radius):
        return True
    first = step * scene.substeps
    ox, oy = scene.trajectory[first, o, 0], scene.trajectory[first, o, 1]
    gap0 = math.sqrt((px - ox) * (px - ox) + (py - oy) * (py - oy)) - robot_radius - contact_radius
    return gap0 > scene.reach + scene.travel[step, o]


@numba.njit(cache=True, inline="always")
def _sort_ascending(values, count):
    """Sort ``values[:count]`` in place (insertion sort: a plan touches a few obstacles)."""
    for i in range(1, count):
        v = values[i]
        j = i - 1
        while j >= 0 and values[j] > v:
            values[j + 1] = values[j]
            j -= 1
        values[j + 1] = v


@numba.njit(cache=True, inline="always", error_model="numpy")
def timed_path_cost(x, scene):
    """Space-time objective of ``x`` = ``k`` waypoints (2k) then ``k + 1`` segment speeds (fractions of
    the robot's top speed) for a :class:`TimedScene`: ``(cost, penalty)`` in metres (arrival time x
    top speed), the penalty counting only contacts within the horizon (the constraint the modified
    ABC's scouts test).

    The robot flies robot -> w1 -> ... -> goal, each step a straight chord of ``speed x reach``
    along the path. For the first ``horizon_steps`` steps every chord is checked against the
    predicted obstacle states ``trajectory`` at every substep (the env's swept test, pairs beyond
    reach skipped by ``travel``, each obstacle's path length per step); past the horizon the rest of the
    path is flown at top speed and checked against the obstacles where the prediction leaves them.
    Each obstacle cut into pays the paper's Eq. 4 penalty once: its circumference (of the contact
    disc) plus ``penalty_weight`` times the deepest cut. A contact within the horizon is the
    constraint: it also pays the rest of the horizon after it (as metres at top speed; a touch
    predicted later leaves replanning more time to avoid it) and ``INFEASIBLE``, so that every
    plan free of predicted contact costs less than any plan with one (Deb's feasibility rule in
    penalty form: in space-time a plan can always wait, and waiting must never look dearer than a
    touch). A cut past the horizon, where the prediction is a guess, adds to the cost only.

    With ``violation=FIRST_CONTACT`` the penalty ranks by how early the first contact comes
    (:func:`_contact_penalty`) and the walk stops at the end of that contact's step: past it, Eq. 4 and
    the arrival only break ties between infeasible plans, and a dense scene's infeasible plans cost
    a few steps' checks instead of the whole horizon's.

    Walls and polygon edges (``statics``) are tested as the env tests them (each step's chord swept
    against every capsule within reach): a touch within the horizon is the same constraint, and the
    rest of the path cutting into a capsule inflated by the robot radius pays Eq. 4 (its perimeter
    plus ``penalty_weight`` times the depth). The rest of the path counts as at least the static
    cost-to-go (``cost_to_go``) from where the horizon leaves the robot, so that a path past the
    horizon straight through a wall is not the cheap one; without walls that is the straight line,
    never longer than the path's own rest, and the cost is the one it always was. With a cost-to-go
    field and ``rest_obstacles=False`` the rest's straight pieces pay Eq. 4 on the obstacles neither.

    ``progress_weight`` > 0 adds a running cost (an MPC's stage cost): that weight times the mean cost-to-go
    where each step of the horizon ends (0 from the goal on). The arrival alone ties every plan that ends
    the horizon at the same place, one that wanders as one that closes in and waits.
    """
    traj, n, robot_radius, contact_radii = scene.trajectory, scene.substeps, scene.robot_radius, scene.contact_radii
    robot, goal, goal_radius, reach = scene.robot, scene.goal, scene.goal_radius, scene.reach
    horizon_steps, penalty_weight = scene.horizon_steps, scene.penalty_weight
    statics = scene.statics
    k = (x.shape[0] - 1) // 3
    pts = np.empty((k + 2, 2))
    pts[0, 0], pts[0, 1] = robot[0], robot[1]
    for i in range(k):
        pts[i + 1, 0], pts[i + 1, 1] = x[2 * i], x[2 * i + 1]
    pts[k + 1, 0], pts[k + 1, 1] = goal[0], goal[1]
    n_obs = contact_radii.shape[0]
    # per obstacle, read only once ``touched`` (its first touch writes them): among hundreds of resting
    # discs, zeroing them and summing over every obstacle cost more than a plan's few contacts
    # (three allocations, not six: an evaluation among 8 obstacles costs under a microsecond)
    floats, flags, indices = np.empty(2 * n_obs), np.zeros(2 * n_obs, np.bool_), np.empty(2 * n_obs + 5, np.int64)
    depth, first_touch = floats[:n_obs], floats[n_obs:]  # when first touched, in steps
    touched, near = flags[:n_obs], flags[n_obs:]  # near: touched within the horizon, against the step-by-step prediction
    hits = indices[:n_obs]  # the obstacles touched, in the order first touched
    n_hits = 0
    wall_touch = -1.0  # the first predicted contact with a wall within the horizon (steps), if any
    wall_depth = 0.0
    seg, px, py = 0, robot[0], robot[1]
    arrival = -1.0
    # ranked by the first contact, a plan needs no steps past it: its Eq. 4 and arrival only break ties
    stop_at_contact = scene.violation == FIRST_CONTACT
    contact = False
    running = 0.0  # the sum of the cost-to-go where each step ends (``progress_weight``)
    # the obstacles a test visits (the broad phase: the others cannot reach; unused without one)
    visit = indices[n_obs : 2 * n_obs]
    span = indices[2 * n_obs :]  # the grid cells ``visit`` holds for the horizon's steps (none yet)
    span[:] = -2
    broad, n_moving, chord, shape, (moving, start, items) = broad_phase_of(scene.resting, n_obs)
    visit[: moving.shape[0]] = moving  # the moving ones head every step's list (:func:`_step_visits`)
    for step in range(horizon_steps):
        nseg, qx, qy = walk_along(pts, seg, px, py, x[2 * k + seg] * reach)
        dx, dy = qx - px, qy - py
        goal_t = reach_fraction(px, py, dx, dy, goal[0], goal[1], goal_radius)
        first = step * n
        ee = dx * dx + dy * dy
        for q in range(_step_visits(scene, broad, n_moving, shape, start, items, px, py, visit, span)):
            o = visit[q] if broad else q  # (:func:`visited`, read here: a compiled call a visit cost more than the test)
            if _out_of_reach(scene, chord and q >= n_moving, o, step, px, py, dx, dy, ee):
                continue
            ax, ay = px, py
            sub_reach = math.sqrt(dx * dx + dy * dy) / n
            for j in range(1, n + 1):
                bx, by = substep_point(px, dx, j, n), substep_point(py, dy, j, n)
                a, b = traj[first + j - 1], traj[first + j]
                # the same skip per substep: farther apart than both move in it
                sx, sy = a[o, 0] - ax, a[o, 1] - ay
                ox_move = math.sqrt((b[o, 0] - a[o, 0]) ** 2 + (b[o, 1] - a[o, 1]) ** 2)
                if math.sqrt(sx * sx + sy * sy) - robot_radius - contact_radii[o] > sub_reach + ox_move:
                    ax, ay = bx, by
                    continue
                gap, t_hit = swept_pair(ax, ay, bx, by, robot_radius, a[o, 0], a[o, 1], b[o, 0], b[o, 1], contact_radii[o])
                if t_hit <= 1.0 and (j - 1 + t_hit) / n <= goal_t:  # a contact before the goal counts
                    if not near[o]:
                        first_touch[o] = step + (j - 1 + t_hit) / n
                    n_hits = _touch(o, touched, depth, hits, n_hits)
                    near[o] = contact = True
                    depth[o] = max(depth[o], -gap)
                ax, ay = bx, by
        wall_touch, wall_depth = _wall_contact(scene, px, py, qx, qy, goal_t, step, wall_touch, wall_depth)
        if goal_t <= 1.0:
            arrival = step + goal_t
            break
        running += _running_to_go(scene, qx, qy)
        seg, px, py = nseg, qx, qy
        if stop_at_contact and (contact or wall_touch >= 0.0):
            break
    detour = 0.0  # past the horizon, a soft cost: where the obstacles will be is a guess
    if arrival < 0.0:  # past the horizon: the rest of the path at top speed, against the horizon's obstacles
        last = traj[horizon_steps * n]
        rest = 0.0
        # the walls the rest's straight pieces cut pay Eq. 4 only without a cost-to-go: with one, the
        # rest costs at least the way around them (charging both held the planners at local minima).
        # ``rest_obstacles=False`` leaves the obstacles they pass there unpaid too: those pieces may cut
        # walls, and charging the slow humans on them (Eq. 4, 100 per metre of depth) held the robot
        # behind them in maze-crowd; among fast ones the charge is a useful look further ahead
        # (docs/results/maps_first_look/README.md)
        field = scene.cost_to_go.field.size > 0
        rest_statics = statics[:0] if field else statics
        rest_obstacles = 0 if field and not scene.rest_obstacles else n_obs
        ax, ay = px, py
        for s in range(seg + 1, k + 2):
            bx, by = pts[s, 0], pts[s, 1]
            rest += math.sqrt((bx - ax) * (bx - ax) + (by - ay) * (by - ay))
            for q in range(_rest_visits(scene, broad and n_moving == 0, ax, ay, bx, by, visit) if rest_obstacles else 0):
                o = visit[q] if broad else q  # (:func:`visited`)
                if o < scene.rest_exempt.shape[0] and scene.rest_exempt[o]:
                    continue
                r = contact_radii[o] + robot_radius
                d2 = _segment_origin_distance_sq(ax - last[o, 0], ay - last[o, 1], bx - last[o, 0], by - last[o, 1])
                if d2 < r * r:
                    n_hits = _touch(o, touched, depth, hits, n_hits)
                    depth[o] = max(depth[o], r - math.sqrt(d2))
            detour += capsule_penalty(ax, ay, bx, by, rest_statics, robot_radius, penalty_weight)  # through a wall: Eq. 4
            ax, ay = bx, by
        # and it is at least the static cost-to-go from where the horizon leaves the robot (the
        # straight line without walls: then the path's own rest, always as long, decides as before)
        to_go = distance_to_goal(scene.cost_to_go, px, py, goal[0], goal[1], goal_radius)
        arrival = horizon_steps + max(rest - goal_radius, to_go, 0.0) / reach
    _sort_ascending(hits, n_hits)  # the sums below in the obstacles' order, as a loop over all of them adds
    for q in range(n_hits):
        o = hits[q]
        if not near[o]:
            detour += TWO_PI * (contact_radii[o] + robot_radius) + penalty_weight * depth[o]
    penalty = _contact_penalty(scene, near, hits, n_hits, first_touch, depth, wall_touch, wall_depth)
    detour += scene.progress_weight * running / horizon_steps  # 0.0 without a running cost
    return arrival * reach + detour + penalty, penalty
