"""Exact contact of a disc robot flying a circular arc, against moving discs and static capsules.

A unicycle holding ``(v, ω)`` flies a circular arc (:class:`Arc`); within a physics substep an
obstacle moves in a straight line (Chipmunk's integration). Two facts make the test exact and cheap:

* **Chord bound.** Parametrise both by the same ``u`` in [0, 1]. The robot's arc point ``p(u)`` and
  the chord point ``c(u)`` (linear between the arc's ends) differ by ``e(u)``, with ``e(0) = e(1) = 0``
  and ``|e''(u)| = L φ`` (the centripetal acceleration of an arc of length ``L`` and turn ``φ``
  flown at constant speed; ``c'' = 0``). Linear interpolation's error bound gives
  ``|e(u)| <= u (1 - u) / 2 * L |φ| <= L |φ| / 8 =: δ``. So a contact on the arc means a contact of the
  chord with the reach inflated by ``δ``, and the chord's first such time is no later than the
  arc's: the exact straight swept tests (``geometry.swept_pair``, ``statics.swept_capsule``)
  bracket every contact from below and clear most pairs outright.
* **Conservative advancement** from that time on. The gap ``g(u) = |o(u) - p(u)| - reach`` changes
  at most as fast as the relative position, ``|o'(u) - p'(u)| <= |o'| + |p'| =: B`` (``|p'|`` is the
  arc's length ``L``, the robot's speed being constant on it; ``|o'|`` the obstacle's substep
  displacement; a capsule's ``|o'| = 0``). No root lies before ``u + g(u) / B``, so stepping by
  ``g / B`` never skips a contact; it stops where ``g <= tol`` (a relative ``CONTACT_TOLERANCE``
  of the reach, a nanometre on a metre: far below any near miss that matters). At every step the
  chord bound is tried again over the rest of the interval (its ``δ`` shrinks with the square of the
  rest): it clears the rest or moves ``u`` up to its own lower bracket, so a graze along a straight
  or gently curved path, where ``g / B`` would crawl, ends in a few steps.

Everything is compiled with numba; an arc is a named record (:class:`Arc`).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba
import numpy as np

from pathplan_env.geometry.contacts import NO_CONTACT, swept_pair
from pathplan_env.geometry.walls import point_segment, swept_capsule
from pathplan_env.world.substep_kernels import restore_speeds  # the world's speed restoration, reused from inside the kernel

#: Relative to the reach: a gap at or below ``CONTACT_TOLERANCE * reach`` is a contact.
CONTACT_TOLERANCE = 1e-9
#: Conservative-advancement steps before giving up. A tangent graze within ``tol`` may need many;
#: if the budget runs out the pair counts as touching there (a false hit, never a miss).
MAX_ADVANCES = 100_000


class Arc(NamedTuple):
    """The robot's motion over one step: pose at its start, constant speed ``v`` (m/s) and turn
    rate ``ω`` (rad/s) for ``duration`` seconds (``ω = 0``: a straight line)."""

    x: float
    y: float
    heading: float
    speed: float
    turn_rate: float
    duration: float


@numba.njit(cache=True, inline="always")
def _sinc(x):
    return 1.0 - x * x / 6.0 if abs(x) < 1e-4 else math.sin(x) / x  # (the series' next term: x^4/120 < 1e-18)


@numba.njit(cache=True)
def arc_point(arc, f):
    """``(x, y, heading)`` at fraction ``f`` of the arc's duration (exact integration of constant
    ``v, ω``; written as chord length and mid-heading, stable as ``ω -> 0``)."""
    s = f * arc.duration
    half = 0.5 * arc.turn_rate * s
    chord = arc.speed * s * _sinc(half)
    mid = arc.heading + half
    return arc.x + chord * math.cos(mid), arc.y + chord * math.sin(mid), arc.heading + 2.0 * half


@numba.njit(cache=True, inline="always")
def _bound(arc, f0, f1):
    """``(L, δ)``: length of the arc between fractions ``f0`` and ``f1`` and its chord bound ``L |φ| / 8``."""
    span = (f1 - f0) * arc.duration
    length = abs(arc.speed) * span
    return length, length * abs(arc.turn_rate * span) / 8.0


class ArcPiece(NamedTuple):
    """The piece of an arc from fraction ``f0`` to ``f1``: its ends ``a``, ``b`` (``arc_point`` at both),
    its length and chord bound ``δ = L |φ| / 8`` (``_bound``), computed once and tested against every
    obstacle and capsule of a substep."""

    f0: float
    f1: float
    ax: float
    ay: float
    bx: float
    by: float
    length: float
    delta: float


@numba.njit(cache=True, inline="always")
def arc_piece(arc, f0, f1):
    """The :class:`ArcPiece` of ``arc`` from ``f0`` to ``f1``."""
    ax, ay, _ = arc_point(arc, f0)
    bx, by, _ = arc_point(arc, f1)
    length, delta = _bound(arc, f0, f1)
    return ArcPiece(f0, f1, ax, ay, bx, by, length, delta)


@numba.njit(cache=True)
def arc_disc(arc, f0, f1, oax, oay, obx, oby, reach):
    """The robot on the arc from fraction ``f0`` to ``f1`` against a disc moving from ``oa`` to ``ob``
    over the same interval (``u`` in [0, 1]), contact at centre distance ``reach``.

    :return: ``(gap, u_contact)``: a gap no larger than the true smallest one (within ``δ`` of it;
        exact on a straight move; ``<= 0`` on contact) and the first contact's ``u`` (``NO_CONTACT``: none).
    """
    return arc_disc_between(arc, arc_piece(arc, f0, f1), oax, oay, obx, oby, reach)


@numba.njit(cache=True)
def arc_disc_between(arc, piece, oax, oay, obx, oby, reach):
    """:func:`arc_disc` on an :class:`ArcPiece` (computed once for every obstacle of a substep, by the
    env and by planners that roll the robot out)."""
    f0, f1, ax, ay, bx, by, length, delta = piece
    tol = CONTACT_TOLERANCE * reach
    chord_gap, u = swept_pair(ax, ay, bx, by, reach + delta + tol, oax, oay, obx, oby, 0.0)
    if u > 1.0:
        return chord_gap + tol, NO_CONTACT  # |o - p| >= |o - c| - δ: a lower bound
    bound = math.hypot(obx - oax, oby - oay) + length
    best = np.inf
    for _ in range(MAX_ADVANCES):
        px, py, _ = arc_point(arc, f0 + u * (f1 - f0))
        ox = oax + u * (obx - oax)
        oy = oay + u * (oby - oay)
        gap = math.hypot(ox - px, oy - py) - reach
        best = min(best, gap)
        if gap <= tol:
            return min(gap, 0.0), u
        if bound <= 0.0:
            break
        # the chord bound again over what is left (its δ shrinks with the square of the rest): it
        # clears the rest, or brackets its first contact from below (a graze along a straight or
        # gently curved path, where g / B crawls, ends here)
        rest = delta * (1.0 - u) * (1.0 - u)
        chord_gap, t = swept_pair(px, py, bx, by, reach + rest + tol, ox, oy, obx, oby, 0.0)
        if t > 1.0:
            return min(best, chord_gap + tol), NO_CONTACT
        u = max(u + gap / bound, u + t * (1.0 - u))
        if u > 1.0:
            return best, NO_CONTACT
    return (best, NO_CONTACT) if bound <= 0.0 else (0.0, u)  # budget spent: a conservative hit


@numba.njit(cache=True)
def arc_capsule(arc, f_end, robot_radius, x0, y0, x1, y1, half):
    """The robot on the arc from fraction 0 to ``f_end`` against a static capsule (segment ``x0 y0 x1 y1``,
    half-thickness ``half``): ``(gap, f_contact)`` as :func:`arc_disc`, the contact as a fraction of the arc."""
    return _arc_capsule(arc, arc_piece(arc, 0.0, f_end), robot_radius, x0, y0, x1, y1, half)


@numba.njit(cache=True)
def _arc_capsule(arc, piece, robot_radius, x0, y0, x1, y1, half):
    """:func:`arc_capsule` on the :class:`ArcPiece` from 0 to ``f_end`` (computed once for every capsule)."""
    _, f_end, ax, ay, bx, by, length, delta = piece
    reach = robot_radius + half
    tol = CONTACT_TOLERANCE * reach
    chord_gap, u = swept_capsule(ax, ay, bx, by, robot_radius + delta + tol, x0, y0, x1, y1, half)
    if u > 1.0:
        return chord_gap + tol, NO_CONTACT
    best = np.inf
    for _ in range(MAX_ADVANCES):
        px, py, _ = arc_point(arc, u * f_end)
        gap = point_segment(px, py, x0, y0, x1, y1) - reach
        best = min(best, gap)
        if gap <= tol:
            return min(gap, 0.0), u * f_end
        if length <= 0.0:
            break
        rest = delta * (1.0 - u) * (1.0 - u)  # the chord bound over what is left, as in arc_disc
        chord_gap, t = swept_capsule(px, py, bx, by, robot_radius + rest + tol, x0, y0, x1, y1, half)
        if t > 1.0:
            return min(best, chord_gap + tol), NO_CONTACT
        u = max(u + gap / length, u + t * (1.0 - u))  # a static capsule: the closing speed is at most the robot's
        if u > 1.0:
            return best, NO_CONTACT
    return (best, NO_CONTACT) if length <= 0.0 else (0.0, u * f_end)


@numba.njit(cache=True)
def arc_capsules(arc, f_end, robot_radius, segments):
    """:func:`arc_capsule` against ``(M, 5)`` capsule rows: ``(min_gap, f_contact)`` (``(inf, NO_CONTACT)`` with none)."""
    min_gap = np.inf
    f_contact = NO_CONTACT
    piece = arc_piece(arc, 0.0, f_end)
    for i in range(segments.shape[0]):
        gap, f = _arc_capsule(arc, piece, robot_radius, segments[i, 0], segments[i, 1], segments[i, 2], segments[i, 3], segments[i, 4])
        min_gap = min(min_gap, gap)
        f_contact = min(f_contact, f)
    return min_gap, f_contact


@numba.njit(cache=True)
def arc_goal(arc, gx, gy, goal_radius):
    """First fraction of the arc at which the robot's centre is within ``goal_radius`` of the goal
    (``NO_CONTACT`` if it never is): a disc contact with a resting disc of reach ``goal_radius``."""
    return arc_disc(arc, 0.0, 1.0, gx, gy, gx, gy, goal_radius)[1]


class StepStatics(NamedTuple):
    """What a step's arc meets that does not move: ``goal`` (fraction where the goal is reached),
    ``wall`` (fraction of the first contact with a wall, polygon edge or the arena's edge, up to the
    goal) and ``gap`` (their smallest gap up to where the robot stops); ``NO_CONTACT`` for none."""

    goal: float
    wall: float
    gap: float


@numba.njit(cache=True)
def step_statics(robot, segments, goal_x, goal_y, goal_radius):
    """:class:`StepStatics`' values of the arc ``robot`` (an :class:`Arc`'s values as an array plus the robot
    radius, see :func:`_arc`) against the capsules, in one call."""
    arc, radius = _arc(robot)
    return step_statics_between(arc, radius, arc_piece(arc, 0.0, 1.0), segments, goal_x, goal_y, goal_radius)


@numba.njit(cache=True)
def step_statics_between(arc, radius, whole, segments, goal_x, goal_y, goal_radius):
    """:func:`step_statics` given the whole arc's :class:`ArcPiece` (0 to 1): :func:`arc_goal` then
    :func:`arc_capsules` up to the goal, the same operations without computing the ends again (each
    is three sines and cosines)."""
    goal = arc_disc_between(arc, whole, goal_x, goal_y, goal_x, goal_y, goal_radius)[1]
    f_end = min(goal, 1.0)
    piece = whole
    if f_end != 1.0:  # the goal part-way: the walls count up to there
        bx, by, _ = arc_point(arc, f_end)
        length, delta = _bound(arc, 0.0, f_end)
        piece = ArcPiece(0.0, f_end, whole.ax, whole.ay, bx, by, length, delta)
    gap = np.inf
    wall = NO_CONTACT
    for i in range(segments.shape[0]):
        g, f = _arc_capsule(arc, piece, radius, segments[i, 0], segments[i, 1], segments[i, 2], segments[i, 3], segments[i, 4])
        gap = min(gap, g)
        wall = min(wall, f)
    if wall > 1.0:
        wall = NO_CONTACT
    return goal, wall, 0.0 if wall <= 1.0 else gap  # (a plain tuple: boxing a NamedTuple costs a microsecond)


#: Columns of the ``robot`` array the kernels take from Python: an :class:`Arc` and the robot radius
#: (an array: numba types a NamedTuple argument in Python on every call, an array in C).
X, Y, HEADING, SPEED, TURN_RATE, DURATION, RADIUS = range(7)


@numba.njit(cache=True, inline="always")
def _arc(robot):
    return Arc(robot[X], robot[Y], robot[HEADING], robot[SPEED], robot[TURN_RATE], robot[DURATION]), robot[RADIUS]


@numba.njit(cache=True)
def arc_substep(robot, k, n, u_end, state, new_state, radii, speeds):
    """Substep ``k`` of ``n`` (1-based) of the arc ``robot`` against every obstacle moving linearly from
    ``state`` to ``new_state``, the robot flying only the first ``u_end`` of it (``< 0``: it rests),
    then the world's speed restoration (``substep_kernels.restore_speeds``: bounces keep directions).

    :return: ``(min_gap, u_contact, restored)``: ``u_contact`` in the substep's own [0, 1] (``NO_CONTACT``: none).
    """
    arc, robot_radius = _arc(robot)
    f0 = (k - 1) / n
    f1 = f0 + u_end / n
    piece = arc_piece(arc, f0, f1) if u_end >= 0.0 else ArcPiece(f0, f1, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    return arc_substep_between(arc, robot_radius, piece, u_end, state, new_state, radii, speeds)


@numba.njit(cache=True)
def arc_substep_between(arc, robot_radius, piece, u_end, state, new_state, radii, speeds):
    """:func:`arc_substep` given the substep's :class:`ArcPiece` (``f0 = (k - 1) / n``, ``f1 = f0 + u_end / n``),
    for a caller that has it already (unused when the robot rests, ``u_end < 0``)."""
    min_gap = np.inf
    u_contact = NO_CONTACT
    if u_end >= 0.0:
        for i in range(radii.shape[0]):
            oax, oay = state[i, 0], state[i, 1]
            obx = oax + u_end * (new_state[i, 0] - oax)
            oby = oay + u_end * (new_state[i, 1] - oay)
            gap, u = arc_disc_between(arc, piece, oax, oay, obx, oby, robot_radius + radii[i])
            min_gap = min(min_gap, gap)
            if u <= 1.0:
                u_contact = min(u_contact, u * u_end)
    restored = restore_speeds(state, new_state, speeds)
    return min_gap, u_contact, restored


__all__ = [
    "Arc", "ArcPiece", "CONTACT_TOLERANCE", "StepStatics", "arc_capsule", "arc_capsules", "arc_disc", "arc_disc_between", "arc_goal",
    "arc_piece", "arc_point", "arc_substep", "arc_substep_between", "step_statics", "step_statics_between",
]  # fmt: skip
