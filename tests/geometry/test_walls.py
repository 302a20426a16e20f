"""Walls and polygons: the exact swept test, obstacles bouncing off them, validation, the dict form, episodes."""

from __future__ import annotations

import dataclasses
import json
import math
import pickle

import gymnasium as gym
import numba
import numpy as np
import pytest

import pathplan_env  # noqa: F401  (registers DynamicObstacle-v0)
from pathplan_env import Obstacle, Scenario
from pathplan_env.geometry.walls import DEFAULT_WALL_THICKNESS, swept_capsules
from pathplan_env.scenarios.files import load_scenario
from pathplan_env.world.simulation import World

ARENA = (0.0, 0.0, 10.0, 10.0)
SAMPLES = 4001  # of the reference: t = 0, 1/4000, ..., 1


@numba.njit
def reference_contact(ax, ay, bx, by, reach, segments):
    """The first of ``SAMPLES`` evenly spaced t in [0, 1] at which the centre is within ``reach`` of a
    capsule (nan if none), and the smallest sampled surface gap: brute force, no closed forms
    (compiled only because 10,000 cases x 4,001 samples take minutes in numpy)."""
    first, smallest = np.nan, np.inf
    for k in range(SAMPLES):
        t = k / (SAMPLES - 1)
        px, py = ax + t * (bx - ax), ay + t * (by - ay)
        for m in range(segments.shape[0]):
            x0, y0, x1, y1, half = segments[m]
            dx, dy = x1 - x0, y1 - y0
            u = min(max(((px - x0) * dx + (py - y0) * dy) / (dx * dx + dy * dy), 0.0), 1.0)
            gap = math.hypot(px - x0 - u * dx, py - y0 - u * dy) - half - reach
            smallest = min(smallest, gap)
            if gap <= 0.0 and np.isnan(first):
                first = t
    return first, smallest


def random_case(rng):
    """A robot radius, its move and two capsule rows: a wall (thick, thin or zero; given twice), or a
    polygon's corner (two radius-0 edges meeting at a vertex). Moves reach 4 m, past anything a
    step does, mostly aimed near the geometry."""
    radius = rng.uniform(0.05, 0.5)
    kind = rng.integers(3)
    centre = rng.uniform(-1.0, 1.0, 2)
    if kind == 2:  # a polygon's corner
        angles = rng.uniform(0.0, 2 * math.pi, 2)
        ends = centre + rng.uniform(0.05, 2.0, (2, 1)) * np.stack([np.cos(angles), np.sin(angles)], axis=1)
        segments = np.array([[*ends[0], *centre, 0.0], [*centre, *ends[1], 0.0]])
    else:
        half = rng.choice([0.0, 1e-4, 1e-3]) if kind == 1 else rng.uniform(0.0, 0.3)  # thin walls, or any
        angle, length = rng.uniform(0.0, 2 * math.pi), rng.uniform(0.01, 3.0)
        offset = 0.5 * length * np.array([math.cos(angle), math.sin(angle)])
        segments = np.array([[*(centre - offset), *(centre + offset), half]] * 2)
    a = rng.uniform(-3.0, 3.0, 2)
    aim = centre + rng.uniform(-1.0, 1.0, 2) - a if rng.random() < 0.7 else rng.uniform(-1.0, 1.0, 2)
    b = a + rng.uniform(0.0, 4.0) * aim / max(np.linalg.norm(aim), 1e-12)
    return radius, a, b, segments


def test_swept_capsules_match_a_sampled_reference_without_a_miss():
    rng = np.random.default_rng(2100)
    hits = grazes = 0
    for _ in range(10_000):
        radius, a, b, segments = random_case(rng)
        gap, t = swept_capsules(a[0], a[1], b[0], b[1], radius, segments)
        ref_t, ref_gap = reference_contact(a[0], a[1], b[0], b[1], radius, segments)
        case = (radius, a, b, segments, t, ref_t, gap, ref_gap)
        spacing = np.linalg.norm(b - a) / (SAMPLES - 1)
        if not np.isnan(ref_t):  # the reference touches: so must we, no later, and within one sample
            hits += 1
            assert ref_t - 1.0 / (SAMPLES - 1) - 1e-12 <= t <= ref_t + 1e-12 and gap <= 0.0, case
        elif t <= 1.0:  # we touch between two samples: only a graze shallower than a sample's chord
            grazes += 1
            assert ref_gap <= spacing**2 / (8 * radius) + 1e-12, case
        else:  # neither touches: the closed-form gap is the sampled one, to within a sample
            assert ref_gap - spacing - 1e-9 <= gap <= ref_gap + 1e-9, case
    assert hits > 3000 and grazes < 10  # the cases touch often, and the closed form agrees with the samples


def _unit(angle):
    return np.array([math.cos(angle), math.sin(angle)])


@pytest.mark.parametrize("offset, touches", [(0.01, False), (-0.01, True)])
def test_a_near_miss_by_one_percent_of_the_radius_is_not_a_hit(offset, touches):
    """Moves that pass the capsule's side, its round end or a polygon's corner at ``R + h ± 1 % R``."""
    rng = np.random.default_rng(7)
    for _ in range(500):
        radius, half = rng.uniform(0.05, 0.5), rng.choice([0.0, 1e-3, rng.uniform(0.0, 0.3)])
        clear = radius + half + offset * radius
        s0 = rng.uniform(-1.0, 1.0, 2)
        along = _unit(rng.uniform(0.0, 2 * math.pi))
        normal = np.array([-along[1], along[0]])
        s1 = s0 + rng.uniform(0.05, 2.0) * along
        # beside the segment, parallel to it
        a, b = s0 + clear * normal - 1.0 * along, s1 + clear * normal + 1.0 * along
        cases = [(a, b, np.array([[*s0, *s1, half]]))]
        # past its end s1, tangent there: the move's normal points away from the segment
        tangent = _unit(rng.uniform(-0.45 * math.pi, 0.45 * math.pi) + math.atan2(along[1], along[0]))
        side = np.array([-tangent[1], tangent[0]])
        point = s1 + clear * (side if side @ along >= 0 else -side)
        cases.append((point - 2.0 * tangent, point + 2.0 * tangent, np.array([[*s0, *s1, half]])))
        # past a convex polygon corner at s0 (edges to s0 + e1 and s0 + e2, on the far side of the move)
        e1 = _unit(math.atan2(-normal[1], -normal[0]) + rng.uniform(-0.4, 0.4) * math.pi) * rng.uniform(0.1, 2.0)
        e2 = _unit(math.atan2(-normal[1], -normal[0]) + rng.uniform(-0.4, 0.4) * math.pi) * rng.uniform(0.1, 2.0)
        corner = np.array([[*(s0 + e1), *s0, 0.0], [*s0, *(s0 + e2), 0.0]])
        point = s0 + (clear - half) * normal
        cases.append((point - 2.0 * along, point + 2.0 * along, corner))
        for a, b, segments in cases:
            gap, t = swept_capsules(a[0], a[1], b[0], b[1], radius, segments)
            assert (t <= 1.0) == touches, (radius, half, a, b, segments)
            if not touches:
                assert gap == pytest.approx(0.01 * radius, rel=1e-6, abs=1e-12)


def test_a_thin_wall_stops_the_fastest_robot():
    """2 m a step against a 1 mm wall: a test at the step's ends would see the robot jump over it."""
    scenario = Scenario(bounds=ARENA, start=(1.0, 5.0), goal=(9.0, 5.0), robot_speed=20.0, walls=(((5.0, 1.0), (5.0, 9.0)),),
                        wall_thickness=1e-3)  # fmt: skip
    env = gym.make("DynamicObstacle-v0", scenario=scenario)
    _, info = env.reset(seed=0)
    assert info["min_clearance"] == pytest.approx(4.0 - 0.2 - 5e-4)
    action = env.unwrapped.waypoint_to_action(scenario.goal)
    steps, terminated = 0, False
    while not terminated and steps < 10:
        _, _, terminated, _, info = env.step(action)
        steps += 1
    assert steps == 2 and info["collision"] and not info["is_success"] and info["min_clearance"] == 0.0
    x, y = env.unwrapped._world.robot_xy
    assert x == pytest.approx(5.0 - 5e-4 - 0.2, abs=1e-9) and y == pytest.approx(5.0)
    assert info["path_length"] == pytest.approx(x - 1.0)


def test_driving_straight_at_a_wall_between_start_and_goal_is_a_collision():
    scenario = Scenario(bounds=ARENA, start=(1.0, 5.0), goal=(9.0, 5.0), walls=(((5.0, 2.0), (5.0, 8.0)),),
                        polygons=(((7.0, 0.5), (8.0, 0.5), (8.0, 1.5), (7.5, 1.0), (7.0, 1.5)),))  # fmt: skip
    env = gym.make("DynamicObstacle-v0", scenario=scenario)
    env.reset(seed=0)
    action = env.unwrapped.waypoint_to_action(scenario.goal)
    for _ in range(200):
        _, reward, terminated, truncated, info = env.step(action)
        if terminated or truncated:
            break
    assert terminated and info["collision"] and reward < 0
    assert env.unwrapped._world.robot_xy[0] == pytest.approx(5.0 - DEFAULT_WALL_THICKNESS / 2 - 0.2, abs=1e-9)
    world = env.unwrapped._world
    np.testing.assert_array_equal(world.static_segments[0], [5.0, 2.0, 5.0, 8.0, DEFAULT_WALL_THICKNESS / 2])
    assert world.static_segments.shape == (6, 5) and (world.static_segments[1:, 4] == 0.0).all()
    # the robot goes around the wall's end: no contact
    env.reset(seed=0)
    for waypoint in [(3.0, 9.0), (7.0, 9.0), (9.0, 5.0)]:
        for _ in range(60):
            _, _, terminated, _, info = env.step(env.unwrapped.waypoint_to_action(waypoint))
            if terminated or math.dist(env.unwrapped._world.robot_xy, waypoint) < 1e-3:
                break
    assert info["is_success"] and not info["collision"]


def _bouncing(walls=(), polygons=(), velocity=(1.0, 0.0), center=(3.0, 5.0), radius=0.5):
    return Scenario(bounds=ARENA, start=(1.0, 1.0), goal=(1.0, 9.0), obstacles=(Obstacle(center, radius, velocity),),
                    walls=walls, wall_thickness=0.2, polygons=polygons)  # fmt: skip


@pytest.mark.parametrize(
    "geometry",
    [
        {"walls": (((5.0, 2.0), (5.0, 8.0)),)},
        {"walls": (((5.0, 5.0), (8.0, 5.0)),), "center": (5.0, 3.0), "velocity": (0.3, 1.7)},  # its round end
        {"polygons": (((5.0, 3.0), (7.0, 5.0), (5.0, 7.0), (6.0, 5.0)),), "velocity": (2.0, 0.5)},  # non-convex
    ],
)
def test_an_obstacle_bounces_off_static_geometry_and_keeps_its_speed(geometry):
    scenario = _bouncing(**geometry)
    world = World(scenario)
    speed = math.hypot(*scenario.obstacles[0].velocity)
    segments = world.static_segments
    turned = False
    for _ in range(80):
        before = world.obstacle_state[0].copy()
        world.step(0.0, 0.0)
        state = world.obstacle_state[0]
        assert math.hypot(state[2], state[3]) == pytest.approx(speed, rel=1e-9)
        # Δd stays exact: every step moves the obstacle its speed x dt (or less, where it turned)
        assert math.dist(before[:2], state[:2]) <= speed * scenario.dt * (1 + 1e-9)
        s0, s1 = segments[:, 0:2], segments[:, 2:4]
        d = s1 - s0
        u = np.clip(np.einsum("mi,mi->m", state[:2] - s0, d) / np.einsum("mi,mi->m", d, d), 0.0, 1.0)
        gaps = np.linalg.norm(state[:2] - (s0 + u[:, None] * d), axis=1) - segments[:, 4] - 0.5
        # never deeper than a substep's move (Chipmunk finds a contact once it overlaps), never through
        assert gaps.min() > -speed * scenario.dt / world.substeps
        turned |= state[2] * scenario.obstacles[0].velocity[0] < 0 or state[3] * scenario.obstacles[0].velocity[1] < 0
    assert turned


def test_static_geometry_changes_no_episode_without_it():
    """Default walls and polygons are empty: the scenario is the one before walls existed."""
    a = Scenario(bounds=ARENA, start=(1.0, 1.0), goal=(9.0, 9.0))
    assert a.walls == () and a.polygons == () and a.static_segments.shape == (0, 5)
    assert World(a).static_segments.shape == (0, 5)


def _error(**fields):
    base = {"bounds": ARENA, "start": (1.0, 5.0), "goal": (9.0, 5.0)}
    with pytest.raises(ValueError) as error:
        Scenario(**{**base, **fields})
    return str(error.value)


def test_bad_geometry_is_a_value_error_naming_the_field():
    assert "Scenario.walls[0]" in _error(walls=(((5.0, 2.0), (5.0, math.nan)),))
    assert "Scenario.walls[1]" in _error(walls=(((5.0, 2.0), (5.0, 3.0)), ((4.0, 4.0), (4.0, 4.0))))  # degenerate
    assert "Scenario.walls[0]" in _error(walls=(((5.0, 2.0),),))
    assert "Scenario.walls[0]" in _error(walls=(((5.0, 2.0), (5.0, 12.0)),))  # outside the arena
    assert "Scenario.wall_thickness" in _error(walls=(((5.0, 2.0), (5.0, 3.0)),), wall_thickness=-0.1)
    assert "Scenario.polygons[0]" in _error(polygons=(((5.0, 2.0), (6.0, 2.0)),))  # two vertices
    assert "Scenario.polygons[0]" in _error(polygons=(((4.0, 2.0), (6.0, 4.0), (6.0, 2.0), (4.0, 4.0)),))  # a bow tie
    assert "Scenario.polygons[0][1]" in _error(polygons=(((4.0, 2.0), (6.0, math.inf), (6.0, 2.0)),))
    assert "Scenario.polygons[0]" in _error(polygons=(((4.0, 2.0), (11.0, 4.0), (6.0, 2.0)),))
    assert "Scenario.start" in _error(walls=(((1.2, 2.0), (1.2, 8.0)),))  # within the robot radius of the start
    assert "Scenario.goal" in _error(polygons=(((8.0, 4.0), (10.0, 4.0), (10.0, 6.0), (8.0, 6.0)),))  # inside
    message = _error(walls=(((5.0, 2.0), (5.0, 8.0)),), obstacles=(Obstacle((5.4, 5.0), 0.5),))
    assert "Scenario.obstacles[0]" in message and "Scenario.walls[0]" in message
    message = _error(polygons=(((4.0, 4.0), (6.0, 4.0), (6.0, 6.0), (4.0, 6.0)),), obstacles=(Obstacle((5.0, 5.0), 0.3),))
    assert "Scenario.obstacles[0]" in message and "Scenario.polygons[0]" in message
    # touching is not overlapping; a closed ring's repeated vertex is dropped
    Scenario(bounds=ARENA, start=(1.0, 5.0), goal=(9.0, 5.0), walls=(((5.0, 2.0), (5.0, 8.0)),), obstacles=(Obstacle((5.551, 5.0), 0.5),))
    square = Scenario(bounds=ARENA, start=(1.0, 5.0), goal=(9.0, 5.0), polygons=([[4, 7], [6, 7], [6, 9], [4, 9], [4, 7]],))
    assert square.polygons == (((4.0, 7.0), (6.0, 7.0), (6.0, 9.0), (4.0, 9.0)),)


def _walled():
    return Scenario(bounds=ARENA, start=(1.0, 5.0), goal=(9.0, 5.0), walls=(((5.0, 2.0), (5.0, 8.0)), ((2.0, 9.0), (8.0, 9.5))),
                    wall_thickness=0.25, polygons=(((7.0, 0.5), (8.0, 0.5), (8.0, 1.5), (7.5, 1.0)),),
                    obstacles=(Obstacle((3.0, 3.0), 0.4, (0.5, 0.2)),), name="walled")  # fmt: skip


def test_the_dict_form_json_and_yaml_round_trip(tmp_path):
    scenario = _walled()
    data = json.loads(json.dumps(dataclasses.asdict(scenario)))  # what an EnvSpec and the entrants record
    assert data["walls"] == [[[5.0, 2.0], [5.0, 8.0]], [[2.0, 9.0], [8.0, 9.5]]] and data["wall_thickness"] == 0.25
    again = Scenario.from_dict(data)
    assert again == scenario
    np.testing.assert_array_equal(again.static_segments, scenario.static_segments)
    yaml = pytest.importorskip("yaml")
    (tmp_path / "walled.yaml").write_text(yaml.safe_dump(data))
    assert load_scenario(tmp_path / "walled.yaml") == scenario
    env = gym.make("DynamicObstacle-v0", scenario=data, delta_d=None)
    env.reset(seed=0)
    assert env.unwrapped.scenario == scenario
    assert pickle.loads(pickle.dumps(scenario)) == scenario


def test_episodes_with_walls_are_deterministic_and_survive_a_copy():
    def rollout(env, steps=40):
        out = []
        rng = np.random.default_rng(0)
        for _ in range(steps):
            obs, reward, terminated, truncated, info = env.step(rng.uniform(-1, 1, 2).astype(np.float32))
            out.append(([np.asarray(v).tobytes() for v in obs.values()], reward, info["min_clearance"]))
            if terminated or truncated:
                break
        return out

    env = gym.make("DynamicObstacle-v0", scenario=_walled(), delta_d=1.0)
    env.reset(seed=3)
    first = rollout(env)
    env.reset(seed=3)
    env.step(np.zeros(2, np.float32))
    copy = pickle.loads(pickle.dumps(env.unwrapped))
    assert rollout(env) == rollout(copy)
    env.reset(seed=3)
    assert rollout(env) == first


def test_the_renderer_draws_walls_and_polygons():
    pytest.importorskip("pygame")
    from pathplan_env import rendering

    scenario = Scenario(bounds=ARENA, start=(1.0, 5.0), goal=(9.0, 5.0), walls=(((5.0, 2.0), (5.0, 8.0)),), wall_thickness=0.3,
                        polygons=(((7.0, 7.0), (9.0, 7.0), (9.0, 9.0)),))  # fmt: skip
    env = gym.make("DynamicObstacle-v0", scenario=scenario, render_mode="rgb_array")
    env.reset(seed=0)
    frame = env.render()
    scale = frame.shape[1] / 10.0

    def pixel(x, y):
        return tuple(frame[int(round((10.0 - y) * scale)), int(round(x * scale))])

    assert pixel(5.0, 5.0) == rendering.STATIC and pixel(5.12, 3.0) == rendering.STATIC  # the wall, its thickness
    assert pixel(5.3, 5.0) == rendering.BACKGROUND
    assert pixel(8.6, 7.5) == rendering.STATIC and pixel(7.5, 8.6) == rendering.BACKGROUND  # inside the triangle, outside


@pytest.mark.parametrize("family", ["corridor", "doorway", "intersection", "cluttered-room"])
def test_preset_families_are_seeded_valid_and_keep_obstacles_out_of_the_walls(family):
    from pathplan_env.geometry.reference_path import shortest_path_to_goal
    from pathplan_env.scenarios.presets import make_scenario
    from pathplan_env.scenarios.wall_families import FAMILIES

    scenarios = [make_scenario(family, np.random.default_rng(seed)) for seed in range(30)]
    assert make_scenario(family, np.random.default_rng(4)) == scenarios[4]  # seeded: the same scene again
    assert len({(s.start, s.goal) for s in scenarios}) == 30 and len(scenarios[0].static_segments) > 0
    for s in scenarios[:10]:
        assert s.delta_d == pytest.approx(0.25) and Scenario.from_dict(dataclasses.asdict(s)) == s  # valid as built
        assert shortest_path_to_goal(s) < math.inf  # no scene starts blocked
    assert make_scenario(family, np.random.default_rng(0), n_obstacles=3).n_obstacles == 3
    with pytest.raises(ValueError, match="n_obstacles"):
        FAMILIES[family](np.random.default_rng(0), -1)
    env = gym.make("DynamicObstacle-v0", scenario=family, delta_d=1.0)
    env.reset(seed=0)
    env.action_space.seed(0)
    world = env.unwrapped._world
    for _ in range(150):
        _, _, terminated, truncated, _ = env.step(env.action_space.sample())
        world = env.unwrapped._world
        segments = world.static_segments
        s0, d = segments[None, :, 0:2], segments[None, :, 2:4] - segments[None, :, 0:2]
        p = world.obstacle_state[:, None, :2]
        u = np.clip(np.sum((p - s0) * d, axis=-1) / np.sum(d * d, axis=-1), 0.0, 1.0)
        gaps = np.linalg.norm(p - (s0 + u[..., None] * d), axis=-1) - segments[None, :, 4] - world.radii[:, None]
        moves = np.hypot(world.obstacle_state[:, 2], world.obstacle_state[:, 3]) * env.unwrapped.scenario.dt / world.substeps
        assert (gaps.min(axis=1) > -moves - 1e-9).all()  # a bounce, never a pass through
        if terminated or truncated:
            env.reset()


def _around_a_corner(a, centre, reach):
    """From ``a`` to the top of the circle (``centre``, ``reach``) above it, leaving it heading +x:
    the tangent, then the arc."""
    d = math.dist(a, centre)
    phi = (math.atan2(a[1] - centre[1], a[0] - centre[0]) % (2 * math.pi)) - math.acos(reach / d) - math.pi / 2
    return math.sqrt(d * d - reach * reach) + reach * phi


def test_the_static_shortest_path_goes_around_walls_and_polygons():
    from pathplan_env.geometry.reference_path import shortest_path_to_goal
    from pathplan_env.scenarios.presets import make_scenario

    base = {"bounds": ARENA, "start": (1.0, 5.0), "goal": (9.0, 5.0)}
    wall = Scenario(**base, walls=(((5.0, 2.0), (5.0, 8.0)),))  # over the wall's round end (reach 0.05 + 0.2)
    assert shortest_path_to_goal(wall) + 0.2 == pytest.approx(2 * _around_a_corner((1.0, 5.0), (5.0, 8.0), 0.25), rel=1e-12)
    block = Scenario(**base, polygons=(((4.0, 4.0), (6.0, 4.0), (6.0, 6.0), (4.0, 6.0)),))  # over its top side
    assert shortest_path_to_goal(block) + 0.2 == pytest.approx(2 * _around_a_corner((1.0, 5.0), (4.0, 6.0), 0.2) + 2.0, rel=1e-12)
    assert shortest_path_to_goal(Scenario(**base, walls=(((5.0, 0.0), (5.0, 10.0)),))) == math.inf  # no way through
    for seed in range(5):
        door = make_scenario("doorway", np.random.default_rng(seed))
        assert math.dist(door.start, door.goal) - 0.2 <= shortest_path_to_goal(door) < math.inf
