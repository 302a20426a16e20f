"""CrowdNav's protocol (Chen et al. 2019, vita-epfl/CrowdNav): humans crossing under ORCA.

The settings are read from CrowdNav's ``crowd_nav/configs/env.config``, ``crowd_sim/envs/crowd_sim.py``
and ``crowd_sim/envs/policy/orca.py``: 5 humans of radius 0.3 m and preferred speed 1 m/s; a
holonomic robot of radius 0.3 m and speed 1 m/s from (0, -4) to (0, 4); dt 0.25 s; time limit 25 s;
ORCA with neighbour distance 10 m, 10 neighbours, time horizon 5 s, safety space 0 and CrowdNav's
1 cm radius padding. The robot is invisible to the humans unless ``visible=True``.

- ``crowdnav-circle-crossing``: humans start on a circle of radius 4 m (uniform angle, uniform noise
  of +-0.5 m on each coordinate) and head for the antipodal point.
- ``crowdnav-square-crossing``: humans start uniformly on one half of a 10 m square and head for a
  uniform point on the other half.
- ``crowdnav-square-standing`` (not CrowdNav's): the end of a square crossing, every human standing at a
  uniform point of the square from the start (its goal is where it stands). A value trained only on
  walking crowds misjudges such standing groups and can freeze before them (``docs/results/sarl.md``);
  training scenes, not a CrowdNav test layout.

Starts and goals are drawn by CrowdNav's rejection rule: at least the two radii plus its 0.2 m
discomfort distance from the robot and the humans already placed. The differences from CrowdNav
are listed in ``docs/crowdnav.md``.

:func:`crowdnav_test_case` is CrowdNav's own test case ``i`` (its seed ``1000 + i``, its draws, its
rule), the scenes of the evaluation's ``crowdnav`` split.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.linalg import norm

from pathplan_env.arguments import check_count, check_delta_d
from pathplan_env.crowds.behaviours import ORCA
from pathplan_env.scenarios.scenario import Obstacle, Scenario

HUMAN_RADIUS = 0.3
HUMAN_SPEED = 1.0
ROBOT_RADIUS = 0.3
ROBOT_SPEED = 1.0
DT = 0.25
TIME_LIMIT = 25.0
CIRCLE_RADIUS = 4.0
CIRCLE_NOISE = 0.5  # CrowdNav's (rand - 0.5) * v_pref with v_pref = 1 m/s
SQUARE_WIDTH = 10.0
#: CrowdNav's discomfort distance (m): its spawn spacing, and the harness's discomfort metric.
DISCOMFORT_DISTANCE = 0.2
HUMANS = 5
ROBOT_START, ROBOT_GOAL = (0.0, -CIRCLE_RADIUS), (0.0, CIRCLE_RADIUS)
#: CrowdNav has no walls; ours stand 1.5 m beyond the farthest start or goal, where ORCA humans never go.
BOUNDS = (-7.0, -7.0, 7.0, 7.0)
HUMAN_ORCA = ORCA(neighbor_dist=10.0, max_neighbors=10, time_horizon=5.0, safety_space=0.0, radius_padding=0.01)


#: Draws allowed per human before a layout is declared too crowded (CrowdNav would loop forever).
MAX_DRAWS = 10_000


def _clear(point, others, min_dist: float) -> bool:
    return all(math.dist(point, q) >= min_dist for q in others)


def _too_crowded(n: int, placed: int):
    return ValueError(f"n_obstacles={n}: only {placed} humans fit this CrowdNav layout by its spacing rule; use fewer")


def _circle_crossing(rng: np.random.Generator, n: int):
    min_dist = 2 * HUMAN_RADIUS + DISCOMFORT_DISTANCE
    starts, goals = [], []
    draws = 0
    while len(starts) < n:
        draws += 1
        if draws > MAX_DRAWS * (len(starts) + 1):
            raise _too_crowded(n, len(starts))
        angle = rng.random() * 2 * math.pi
        px = CIRCLE_RADIUS * math.cos(angle) + (rng.random() - 0.5) * 2 * CIRCLE_NOISE
        py = CIRCLE_RADIUS * math.sin(angle) + (rng.random() - 0.5) * 2 * CIRCLE_NOISE
        # CrowdNav: the start clear of every agent's position and goal (the robot's included)
        if _clear((px, py), [ROBOT_START, ROBOT_GOAL, *starts, *goals], min_dist):
            starts.append((px, py))
            goals.append((-px, -py))
    return starts, goals


def _square_crossing(rng: np.random.Generator, n: int):
    min_dist = 2 * HUMAN_RADIUS + DISCOMFORT_DISTANCE
    starts, goals = [], []
    for _ in range(n):
        sign = -1.0 if rng.random() > 0.5 else 1.0
        for _ in range(MAX_DRAWS):  # CrowdNav checks starts against positions only; we add the robot's goal (see docs)
            px = rng.random() * SQUARE_WIDTH * 0.5 * sign
            py = (rng.random() - 0.5) * SQUARE_WIDTH
            if _clear((px, py), [ROBOT_START, ROBOT_GOAL, *starts], min_dist):
                break
        else:
            raise _too_crowded(n, len(starts))
        for _ in range(MAX_DRAWS):
            gx = rng.random() * SQUARE_WIDTH * 0.5 * -sign
            gy = (rng.random() - 0.5) * SQUARE_WIDTH
            if _clear((gx, gy), [ROBOT_GOAL, *goals], min_dist):
                break
        else:
            raise _too_crowded(n, len(starts))
        starts.append((px, py))
        goals.append((gx, gy))
    return starts, goals


def _square_standing(rng: np.random.Generator, n: int):
    """Humans standing still at uniform points of the square, clear of the robot's start and goal and of
    each other by CrowdNav's spacing rule; each one's goal is where it stands."""
    min_dist = 2 * HUMAN_RADIUS + DISCOMFORT_DISTANCE
    spots = []
    for _ in range(n):
        for _ in range(MAX_DRAWS):
            spot = ((rng.random() - 0.5) * SQUARE_WIDTH, (rng.random() - 0.5) * SQUARE_WIDTH)
            if _clear(spot, [ROBOT_START, ROBOT_GOAL, *spots], min_dist):
                break
        else:
            raise _too_crowded(n, len(spots))
        spots.append(spot)
    return spots, list(spots)


_LAYOUTS = {"circle-crossing": _circle_crossing, "square-crossing": _square_crossing, "square-standing": _square_standing}


def crowdnav_scenario(layout: str, rng: np.random.Generator, n_humans: int | None = None, visible: bool = False) -> Scenario:
    """One CrowdNav scene (``layout``: ``"circle-crossing"``, ``"square-crossing"`` or ``"square-standing"``), drawn from ``rng``."""
    if layout not in _LAYOUTS:
        raise ValueError(f"layout must be one of {sorted(_LAYOUTS)}, got {layout!r}")
    n = HUMANS if n_humans is None else n_humans
    starts, goals = _LAYOUTS[layout](rng, n)
    return _scene(layout, starts, goals, visible)


def _scene(layout: str, starts, goals, visible: bool, speed: float = HUMAN_SPEED) -> Scenario:
    """The scenario of drawn starts and goals, built without re-validation: CrowdNav's spacing rule
    (0.8 m between starts, between goals, and from the robot's start and goal) and the arena make it
    valid by construction (tested against the validating constructor); validating took a third of a reset."""
    n = len(starts)
    humans = tuple(Obstacle._from_checked((float(x), float(y)), HUMAN_RADIUS, (0.0, 0.0), (float(gx), float(gy)), speed)
                   for (x, y), (gx, gy) in zip(starts, goals))  # fmt: skip
    arrays = {"positions": np.array(starts, np.float64).reshape(n, 2), "velocities": np.zeros((n, 2)), "radii": np.full(n, HUMAN_RADIUS)}
    return Scenario._from_checked(
        arrays, bounds=BOUNDS, start=ROBOT_START, goal=ROBOT_GOAL, obstacles=humans, robot_radius=ROBOT_RADIUS,
        robot_speed=ROBOT_SPEED, dt=DT, goal_radius=ROBOT_RADIUS, behaviour=HUMAN_ORCA, robot_visible=visible,
        time_limit=TIME_LIMIT, name=f"crowdnav-{layout}" + ("-visible" if visible else ""),
    )  # fmt: skip


#: Presets registered in ``pathplan_env.scenarios.presets.PRESETS``: ``(rng, n_obstacles) -> Scenario``.
CROWDNAV_PRESETS = {
    f"crowdnav-{layout}" + ("-visible" if visible else ""): (
        lambda rng, n, layout=layout, visible=visible: crowdnav_scenario(layout, rng, n, visible)
    )
    for layout in _LAYOUTS
    for visible in (False, True)
}


# -- CrowdNav's own test cases ---------------------------------------------------------------------
#: CrowdNav seeds test case i with ``np.random.seed(TEST_CASE_SEED_BASE + i)`` (``crowd_sim.py``'s
#: reset: the test phase's counter offset is the validation split's capacity, 1000).
TEST_CASE_SEED_BASE = 1000
#: CrowdNav's test size (``env.config``); its case counter wraps there.
TEST_CASES = 500


def _legacy_clear(point, others, min_dist: float) -> bool:
    return not any(norm((point[0] - q[0], point[1] - q[1])) < min_dist for q in others)  # CrowdNav's norm and "<"


def _legacy_circle_crossing(state: np.random.RandomState, n: int):
    """``generate_circle_crossing_human`` n times, transcribed (its numpy calls, in its order)."""
    min_dist = 2 * HUMAN_RADIUS + DISCOMFORT_DISTANCE
    starts, goals = [], []
    for _ in range(n):
        for _ in range(MAX_DRAWS):
            angle = state.random_sample() * np.pi * 2
            px_noise = (state.random_sample() - 0.5) * HUMAN_SPEED
            py_noise = (state.random_sample() - 0.5) * HUMAN_SPEED
            px = CIRCLE_RADIUS * np.cos(angle) + px_noise
            py = CIRCLE_RADIUS * np.sin(angle) + py_noise
            if _legacy_clear((px, py), [ROBOT_START, ROBOT_GOAL, *starts, *goals], min_dist):
                break
        else:
            raise _too_crowded(n, len(starts))
        starts.append((px, py))
        goals.append((-px, -py))
    return starts, goals


def _legacy_square_crossing(state: np.random.RandomState, n: int):
    """``generate_square_crossing_human`` n times, transcribed: the side's sign drawn once per human
    (``> 0.5``: the left half), starts kept from positions only (the robot's goal is not checked),
    goals from goals."""
    min_dist = 2 * HUMAN_RADIUS + DISCOMFORT_DISTANCE
    starts, goals = [], []
    for _ in range(n):
        sign = -1 if state.random_sample() > 0.5 else 1
        for _ in range(MAX_DRAWS):
            px = state.random_sample() * SQUARE_WIDTH * 0.5 * sign
            py = (state.random_sample() - 0.5) * SQUARE_WIDTH
            if _legacy_clear((px, py), [ROBOT_START, *starts], min_dist):
                break
        else:
            raise _too_crowded(n, len(starts))
        for _ in range(MAX_DRAWS):
            gx = state.random_sample() * SQUARE_WIDTH * 0.5 * -sign
            gy = (state.random_sample() - 0.5) * SQUARE_WIDTH
            if _legacy_clear((gx, gy), [ROBOT_GOAL, *goals], min_dist):
                break
        else:
            raise _too_crowded(n, len(starts))
        starts.append((px, py))
        goals.append((gx, gy))
    return starts, goals


_LEGACY_LAYOUTS = {"circle-crossing": _legacy_circle_crossing, "square-crossing": _legacy_square_crossing}
#: The presets whose scenes CrowdNav's test cases replace in the ``crowdnav`` split: (layout, visible).
PRESET_LAYOUTS = {f"crowdnav-{layout}" + ("-visible" if visible else ""): (layout, visible) for layout in _LEGACY_LAYOUTS for visible in (False, True)}


def crowdnav_test_case(layout: str, case: int, n_humans: int | None = None, visible: bool = False,
                       delta_d: float | None = None) -> Scenario:  # fmt: skip
    """CrowdNav's test case ``case`` of ``layout`` (``"circle-crossing"`` or ``"square-crossing"``) as
    vita-epfl/CrowdNav (20d6780) draws it: ``np.random.seed(1000 + case)``, then its humans in its
    order and by its rejection rule, here from a private ``np.random.RandomState(1000 + case)`` (the
    same stream; the global generator is never touched).

    ``delta_d`` sets the humans' preferred speed as ``Scenario.with_delta_d`` does (``None``: CrowdNav's
    1 m/s). It is applied here because CrowdNav's square crossing does not keep a start off the robot's
    goal: 30 of its 500 cases start a human on the robot's disc at the goal, which the validating
    ``Scenario`` (and so ``with_delta_d``) refuses; the human walks away at once, and the scene is
    CrowdNav's, so it is built as drawn. Pass it to the env with ``delta_d=None``.
    """
    if layout not in _LEGACY_LAYOUTS:
        raise ValueError(f"layout must be one of {sorted(_LEGACY_LAYOUTS)}, got {layout!r}")
    if isinstance(case, bool) or not isinstance(case, (int, np.integer)) or not 0 <= case < TEST_CASES:
        raise ValueError(f"case must be an integer in [0, {TEST_CASES}) (CrowdNav's test cases), got {case!r}")
    delta_d = check_delta_d(delta_d)
    speed = HUMAN_SPEED if delta_d is None else delta_d * HUMAN_RADIUS / DT  # with_delta_d's expression: the same float
    if speed * DT > math.hypot(BOUNDS[2] - BOUNDS[0], BOUNDS[3] - BOUNDS[1]):
        raise ValueError(f"delta_d {delta_d} makes the humans cross the whole arena in one step; lower delta_d")
    n = HUMANS if n_humans is None else check_count(n_humans, "n_humans")
    starts, goals = _LEGACY_LAYOUTS[layout](np.random.RandomState(TEST_CASE_SEED_BASE + int(case)), n)
    return _scene(layout, starts, goals, bool(visible), speed)
