"""swept_walls.swept_capsules_near: walls.swept_capsules' floats, bit for bit (signed zeros included), on the
maze's polygon edges and on random capsules, for moves far, near, grazing and through them."""

import math

import numpy as np

from pathplan_env.geometry.swept_walls import static_stop, swept_capsules, swept_capsules_near
from pathplan_env.scenarios.presets import make_scenario


def same(a, b) -> bool:
    return all(np.float64(x).tobytes() == np.float64(y).tobytes() for x, y in zip(a, b))


def test_the_maze_edges():
    segments = make_scenario("maze-crowd", np.random.default_rng(0), None, None).static_segments
    rng = np.random.default_rng(1)
    contacts = 0
    for _ in range(20000):
        ax, ay = rng.uniform(-0.2, 10.0, 2)
        step = rng.uniform(0.0, 0.6) * np.array([math.cos(a := rng.uniform(0, 2 * math.pi)), math.sin(a)])
        radius = float(rng.choice([0.2, 0.3, 0.05]))
        expected = swept_capsules(ax, ay, ax + step[0], ay + step[1], radius, segments)
        assert same(swept_capsules_near(ax, ay, ax + step[0], ay + step[1], radius, segments), expected)
        contacts += expected[1] <= 1.0
        fraction = float(rng.uniform(0.0, 1.5))
        assert static_stop(ax, ay, step[0], step[1], fraction, radius, segments) == _static_stop_all(ax, ay, step[0], step[1], fraction, radius, segments)
    assert contacts > 1000


def _static_stop_all(x0, y0, dx, dy, goal_fraction, robot_radius, segments):
    """static_stop over every capsule (swept_capsules)."""
    gap, t = swept_capsules(x0, y0, x0 + dx, y0 + dy, robot_radius, segments)
    if t <= 1.0 and t <= goal_fraction:
        return t, True, 0.0
    if goal_fraction < 1.0:
        gap = swept_capsules(x0, y0, x0 + goal_fraction * dx, y0 + goal_fraction * dy, robot_radius, segments)[0]
    return goal_fraction, False, gap


def test_random_capsules_and_grazes():
    rng = np.random.default_rng(2)
    for _ in range(3000):
        m = int(rng.integers(0, 12))
        segments = np.column_stack([rng.uniform(0, 5, (m, 4)), rng.choice([0.0, 0.05, 0.2], m)])
        ax, ay, bx, by = rng.uniform(0, 5, 4)
        if m and rng.random() < 0.5:  # a move ending exactly at a capsule's reach of an end point, or along its line
            x0, y0, x1, y1, half = segments[0]
            ax, ay, bx, by = x0 - 2.0, y0 + 0.2 + half, x0 + 3.0, y0 + 0.2 + half
            if rng.random() < 0.5:
                segments[0, 1] = segments[0, 3] = y0
        assert same(swept_capsules_near(ax, ay, bx, by, 0.2, segments), swept_capsules(ax, ay, bx, by, 0.2, segments))
