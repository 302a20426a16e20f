"""pygame renderer: ``rgb_array`` draws off-screen (no display needed); ``human`` opens a window."""

from __future__ import annotations

import numpy as np

BACKGROUND = (250, 250, 247)
WALL = (60, 60, 60)
STATIC = (110, 110, 118)  # the scene's walls and polygons
OBSTACLE = (214, 96, 77)
HIDDEN = (205, 200, 196)  # an obstacle the robot's sensor does not see
BEAM = (170, 205, 235)
ARROW = (120, 40, 30)
ROBOT = (52, 101, 164)
HEADING = (250, 250, 247)  # a light radius across the robot's disc
TRAIL = (120, 160, 210)
GOAL = (46, 160, 67)
WAYPOINT = (240, 170, 20)
PLAN = (150, 90, 190)
CAPTION = (40, 40, 40)


def view_of(scenario, pad: float | None = None) -> tuple[float, float, float, float]:
    """The part of the arena worth drawing: the bounding box of its free space (the arena less its
    polygons and walls), padded by ``pad`` (default: twice the robot's radius) and kept within the
    arena. A map's occupied and unknown cells are polygons, so a map drawn at its image's extent showed
    its rooms in a third of the frame; a scene without statics is drawn whole."""
    bounds = tuple(float(b) for b in scenario.bounds)
    if not scenario.polygons and not scenario.walls:
        return bounds
    from shapely.geometry import LineString, Polygon, box
    from shapely.ops import unary_union

    statics = [Polygon(vertices) for vertices in scenario.polygons]
    statics += [LineString([a, b]).buffer(0.5 * scenario.wall_thickness) for a, b in scenario.walls if scenario.wall_thickness > 0]
    free = box(*bounds).difference(unary_union(statics))  # shapely's exact set difference, not a raster
    if free.is_empty:
        return bounds
    pad = 2 * scenario.robot_radius if pad is None else pad
    xmin, ymin, xmax, ymax = free.bounds
    return (max(bounds[0], xmin - pad), max(bounds[1], ymin - pad), min(bounds[2], xmax + pad), min(bounds[3], ymax + pad))


class Renderer:
    """Draws the arena, its walls and polygons, obstacles with velocity arrows, the robot and its trail,
    the goal, the waypoint. ``bounds`` is the part of the world drawn (``view_of(scenario)``: a map's free space)."""

    def __init__(self, bounds, render_mode: str, fps: int, size: int = 600):
        import pygame  # lazy: the env runs without pygame's display machinery unless rendering

        self._pygame = pygame
        self.render_mode, self.fps = render_mode, fps
        xmin, ymin, xmax, ymax = bounds
        self.scale = size / max(xmax - xmin, ymax - ymin)
        self.width, self.height = int(round((xmax - xmin) * self.scale)), int(round((ymax - ymin) * self.scale))
        self.origin = (xmin, ymax)
        self.window = None
        self.clock = None
        if render_mode == "human":
            pygame.display.init()  # display only: pygame.init() would also open audio
            pygame.display.set_caption("DynamicObstacle-v0")
            self.window = pygame.display.set_mode((self.width, self.height))
            self.clock = pygame.time.Clock()
        self.canvas = pygame.Surface((self.width, self.height))
        self.font = None

    def to_screen(self, xy) -> tuple[int, int]:
        x, y = xy
        return int(round((x - self.origin[0]) * self.scale)), int(round((self.origin[1] - y) * self.scale))

    def draw(self, scenario, obstacle_state, radii, robot_position, trail, waypoint, plan=None, caption=None, heading=None,
             beams=None, hidden=None):  # fmt: skip
        """One frame. ``plan``: points of a planned path to draw (e.g. a planner's); ``caption``: text at the top
        left; ``heading``: a robot that turns, drawn with a radius toward it (rad); ``beams``: where a
        scan's beams end (drawn from the robot); ``hidden``: obstacles the sensor does not see (greyed)."""
        pygame, canvas, s = self._pygame, self.canvas, self.scale
        canvas.fill(BACKGROUND)
        pygame.draw.rect(canvas, WALL, canvas.get_rect(), width=3)
        if beams is not None:
            origin = self.to_screen(robot_position)
            for end in beams:
                pygame.draw.line(canvas, BEAM, origin, self.to_screen(end), 1)
        self._draw_statics(scenario)
        for i, ((x, y, vx, vy), r) in enumerate(zip(obstacle_state, radii)):
            centre = self.to_screen((x, y))
            pygame.draw.circle(canvas, HIDDEN if hidden is not None and hidden[i] else OBSTACLE, centre, max(2, int(r * s)))
            # the arrow shows where the obstacle will be one step from now
            tip = self.to_screen((x + vx * scenario.dt, y + vy * scenario.dt))
            if tip != centre:
                pygame.draw.line(canvas, ARROW, centre, tip, 2)
                pygame.draw.circle(canvas, ARROW, tip, 3)
        goal = self.to_screen(scenario.goal)  # drawn over the obstacles: one may pass over it
        pygame.draw.circle(canvas, GOAL, goal, max(3, int(scenario.goal_radius * s)), width=2)
        pygame.draw.line(canvas, GOAL, (goal[0] - 6, goal[1]), (goal[0] + 6, goal[1]), 2)
        pygame.draw.line(canvas, GOAL, (goal[0], goal[1] - 6), (goal[0], goal[1] + 6), 2)
        if len(trail) > 1:
            pygame.draw.lines(canvas, TRAIL, False, [self.to_screen(p) for p in trail], 2)
        if plan is not None and len(plan) > 1:
            pygame.draw.lines(canvas, PLAN, False, [self.to_screen(p) for p in np.asarray(plan)[:, :2]], 2)
        if waypoint is not None:
            wp = self.to_screen(waypoint)
            pygame.draw.line(canvas, WAYPOINT, self.to_screen(robot_position), wp, 1)
            pygame.draw.circle(canvas, WAYPOINT, wp, 4)
        pygame.draw.circle(canvas, ROBOT, self.to_screen(robot_position), max(2, int(scenario.robot_radius * s)))
        if heading is not None:
            (x, y), r = robot_position, scenario.robot_radius
            tip = (x + r * np.cos(heading), y + r * np.sin(heading))
            pygame.draw.line(canvas, HEADING, self.to_screen(robot_position), self.to_screen(tip), max(2, int(0.25 * r * s)))
        if caption:
            if self.font is None:
                pygame.font.init()
                self.font = pygame.font.Font(None, 22)
            canvas.blit(self.font.render(caption, True, CAPTION, BACKGROUND), (8, 8))

        if self.render_mode == "human":
            self.window.blit(canvas, (0, 0))
            pygame.event.pump()
            pygame.display.flip()
            self.clock.tick(self.fps)
            return None
        return np.transpose(np.array(pygame.surfarray.pixels3d(canvas)), axes=(1, 0, 2)).copy()

    def _draw_statics(self, scenario) -> None:
        """Walls as the capsules they are (a band of their thickness with round ends), polygons filled."""
        pygame, canvas, s = self._pygame, self.canvas, self.scale
        half = 0.5 * scenario.wall_thickness
        for a, b in scenario.walls:
            ends = np.array([a, b], np.float64)
            along = (ends[1] - ends[0]) / np.linalg.norm(ends[1] - ends[0])
            side = half * np.array([-along[1], along[0]])
            band = [ends[0] + side, ends[1] + side, ends[1] - side, ends[0] - side]
            pygame.draw.polygon(canvas, STATIC, [self.to_screen(p) for p in band])
            pygame.draw.line(canvas, STATIC, self.to_screen(a), self.to_screen(b), 2)  # visible however thin
            for end in (a, b):
                pygame.draw.circle(canvas, STATIC, self.to_screen(end), int(round(half * s)))
        for vertices in scenario.polygons:
            pygame.draw.polygon(canvas, STATIC, [self.to_screen(v) for v in vertices])

    def close(self):
        if self.window is not None:
            self._pygame.display.quit()
            self.window = None
