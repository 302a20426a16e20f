"""Each robot's move over one step, from its action: a straight line (holonomic) or an arc (unicycle).

A move knows where it is at any fraction of the step and where it stops before any moving body is
considered: at its goal or at its first contact with a wall, a polygon or (a unicycle) the arena's
edge. The single env's own arithmetic decides both: the waypoint action's ``act`` and
``geometry.walls.static_stop`` for a line, ``arc_contact.arc_goal``/``arc_capsules`` for an arc.
"""

from __future__ import annotations

import math

import numpy as np

from pathplan_env.geometry.contacts import NO_CONTACT
from pathplan_env.geometry.walls import static_stop
from pathplan_env.robots.actions import parse_action
from pathplan_env.robots.arc_contact import Arc, arc_capsules, arc_goal, arc_point
from pathplan_env.robots.holonomic import substep_point
from pathplan_env.robots.unicycle import arena_edges, command, next_velocity


class LineMove:
    """A straight move by ``(dx, dy)`` from ``(x0, y0)`` (the holonomic robot's step, as ``World.step``)."""

    __slots__ = ("x0", "y0", "dx", "dy", "stop", "wall", "wall_gap", "waypoint", "length", "record")
    turns = False

    def __init__(self, x0, y0, dx, dy, stop, wall, wall_gap, waypoint):
        self.x0, self.y0, self.dx, self.dy = x0, y0, dx, dy
        self.stop, self.wall, self.wall_gap, self.waypoint = stop, wall, wall_gap, waypoint
        self.length = math.hypot(dx, dy)

    def substep(self, k: int, n: int) -> tuple[float, float]:
        """The centre after substep ``k`` of ``n`` (``World.step``'s arithmetic)."""
        return substep_point(self.x0, self.dx, k, n), substep_point(self.y0, self.dy, k, n)

    def at(self, f: float) -> tuple[float, float]:
        return self.x0 + f * self.dx, self.y0 + f * self.dy

    def widening(self, n: int) -> float:
        return 0.0  # a chord is the path

    def end_state(self, moved_whole: bool, dt: float, heading: float) -> tuple[float, float, float, float, float]:
        """``(vx, vy, heading, forward_speed, turn_rate)`` at the step's end."""
        return (self.dx / dt, self.dy / dt, heading, 0.0, 0.0) if moved_whole else (0.0, 0.0, heading, 0.0, 0.0)


class ArcMove:
    """A unicycle's arc (``pathplan_env.robots.unicycle``): speed ``v`` and turn rate ``ω`` held for the step."""

    __slots__ = ("arc", "stop", "wall", "wall_gap", "waypoint", "length", "v", "w")
    turns = True

    def __init__(self, arc, stop, wall, wall_gap):
        self.arc, self.stop, self.wall, self.wall_gap = arc, stop, wall, wall_gap
        self.v, self.w = arc.speed, arc.turn_rate
        self.length = arc.speed * arc.duration
        end = arc_point(arc, 1.0)
        self.waypoint = (end[0], end[1])

    def substep(self, k: int, n: int) -> tuple[float, float]:
        x, y, _ = arc_point(self.arc, k / n)
        return x, y

    def at(self, f: float) -> tuple[float, float]:
        x, y, _ = arc_point(self.arc, f)
        return x, y

    def widening(self, n: int) -> float:
        """The chord bound of one substep (``arc_contact``'s ``L |φ| / 8``): the most the arc strays
        from the substep's chord, by which its reach is widened (a contact is never missed; a miss by
        less than this counts as one: 2 mm a step at the defaults, less per substep)."""
        return (self.length / n) * abs(self.w * self.arc.duration / n) / 8.0

    def end_state(self, moved_whole: bool, dt: float, heading: float) -> tuple[float, float, float, float, float]:
        h = arc_point(self.arc, 1.0)[2]
        h = math.atan2(math.sin(h), math.cos(h))
        if not moved_whole:
            return 0.0, 0.0, heading, 0.0, 0.0
        return self.v * math.cos(h), self.v * math.sin(h), h, self.v, self.w


class LineDriver:
    """Turns the holonomic robot's action into a :class:`LineMove` (its action type's ``act``)."""

    def __init__(self, action_type, scenario):
        self.action_type, self.radius, self.segments = action_type, scenario.robot_radius, scenario.static_segments

    def move(self, action, state) -> LineMove:
        x0, y0 = state.xy
        dx, dy, goal_fraction, waypoint = self.action_type.act(action, (x0, y0))
        stop, wall, gap = goal_fraction, False, np.inf
        if len(self.segments):
            stop, wall, gap = static_stop(x0, y0, dx, dy, goal_fraction, self.radius, self.segments)
        return LineMove(x0, y0, dx, dy, stop, wall, gap, waypoint)


class ArcDriver:
    """Turns the unicycle's action into an :class:`ArcMove` (its limits: the action type's)."""

    def __init__(self, action_type, scenario):
        self.action_type, self.scenario = action_type, scenario
        self.limits = action_type.limits_for(scenario)
        self.segments = np.ascontiguousarray(np.vstack([scenario.static_segments.reshape(-1, 5), arena_edges(scenario.bounds)]))

    def move(self, action, state) -> ArcMove:
        if type(action) is not np.ndarray or action.shape != (2,) or action.dtype.char not in "fd":
            action = parse_action(action)
        if not np.all(np.isfinite(action)):
            raise ValueError(f"action must be finite, got {action!r} (NaN or infinite)")
        s = self.scenario
        v, w = next_velocity(state.forward_speed, state.turn_rate, command(action, self.limits), self.limits, s.dt)
        (x, y), heading = state.xy, state.heading
        arc = Arc(x, y, heading, v, w, s.dt)
        goal = arc_goal(arc, s.goal[0], s.goal[1], s.goal_radius)
        gap, wall = arc_capsules(arc, min(goal, 1.0), s.robot_radius, self.segments)
        if wall <= 1.0 and wall <= goal:
            return ArcMove(arc, wall, True, 0.0)
        return ArcMove(arc, goal if goal <= 1.0 else NO_CONTACT, False, gap)


def make_driver(action_type, scenario):
    """The driver of a robot driven by ``action_type`` (its ``turns`` says which)."""
    return (ArcDriver if action_type.turns else LineDriver)(action_type, scenario)


__all__ = ["ArcDriver", "ArcMove", "LineDriver", "LineMove", "make_driver"]
