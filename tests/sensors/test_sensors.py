"""Sensing: the compiled lidar against a brute-force float64 reference, thin walls, the "lidar" and
"visible-state" observation types (seeded noise, what counts as visible, validation)."""

import math
import warnings

import gymnasium as gym
import numpy as np
import pytest

import pathplan_env  # noqa: F401  (registers the env)
from pathplan_env import Obstacle, Scenario
from pathplan_env.geometry.rays import ANGLE_SLACK, rough_atan2, scan_beams
from pathplan_env.sensors.lidar import LidarObservation, beam_endpoints
from pathplan_env.sensors.observations import OBSERVATION_TYPES
from pathplan_env.sensors.visible_state import VisibleStateObservation, visible_obstacles

BOUNDS = (0.0, 0.0, 20.0, 20.0)


# -- the brute-force reference: every beam against everything, numpy, float64 -------------------------
def _ray_circle(o, u, c, r):
    f = np.asarray(c, float) - o
    cc = f @ f - r * r
    if cc <= 0.0:
        return np.zeros(len(u))
    b = u @ f
    disc = b * b - cc
    with np.errstate(invalid="ignore"):
        t = b - np.sqrt(disc)  # the textbook root
    return np.where((disc >= 0.0) & (b > 0.0), t, np.inf)


def _ray_segment(o, u, a, b):
    e, w = np.asarray(b, float) - a, np.asarray(a, float) - o
    denom = u[:, 0] * e[1] - u[:, 1] * e[0]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (w[0] * e[1] - w[1] * e[0]) / denom
        s = (w[0] * u[:, 1] - w[1] * u[:, 0]) / denom
    return np.where((denom != 0.0) & (t >= 0.0) & (s >= 0.0) & (s <= 1.0), t, np.inf)


def _segment_distance(p, a, b):
    e = b - a
    s = np.clip((p - a) @ e / (e @ e), 0.0, 1.0) if e @ e > 0 else 0.0
    return np.hypot(*(a + s * e - p))


def _ray_capsule(o, u, row):
    a, b, h = row[:2], row[2:4], row[4]
    if _segment_distance(o, a, b) <= h:
        return np.zeros(len(u))
    if h == 0.0:
        return _ray_segment(o, u, a, b)
    e = b - a
    n = np.array([-e[1], e[0]]) * (h / np.hypot(*e))
    return np.minimum.reduce([_ray_circle(o, u, a, h), _ray_circle(o, u, b, h), _ray_segment(o, u, a + n, b + n), _ray_segment(o, u, a - n, b - n)])


def reference_scan(x, y, heading, fov, beams, max_range, centres, radii, segments, bounds=BOUNDS):
    """Ranges, what each beam hit (-1: the arena or nothing) and by how much the nearest beat the next."""
    angles = heading - fov / 2 + (np.arange(beams) + 0.5) * fov / beams
    u, o = np.column_stack([np.cos(angles), np.sin(angles)]), np.array([x, y])
    with np.errstate(divide="ignore"):
        walls = [np.where(u[:, 0] > 0, (bounds[2] - x) / u[:, 0], np.where(u[:, 0] < 0, (bounds[0] - x) / u[:, 0], np.inf)),
                 np.where(u[:, 1] > 0, (bounds[3] - y) / u[:, 1], np.where(u[:, 1] < 0, (bounds[1] - y) / u[:, 1], np.inf))]  # fmt: skip
    columns = [np.full(beams, max_range), *walls]
    columns += [_ray_circle(o, u, c[:2], r) for c, r in zip(centres, radii)]
    columns += [_ray_capsule(o, u, row) for row in segments]
    table = np.column_stack(columns)
    first, two = np.argmin(table, axis=1), np.sort(table, axis=1)[:, :2]
    arena = (first < 3) | (two[:, 0] >= max_range)
    return two[:, 0], np.where(arena, -1, first - 3), two[:, 1] - two[:, 0]


def ours(x, y, heading, fov, beams, max_range, centres, radii, segments, bounds=BOUNDS):
    directions = np.column_stack([np.cos(a := heading - fov / 2 + (np.arange(beams) + 0.5) * (fov / beams)), np.sin(a)])
    ranges, hits = np.empty(beams), np.empty(beams, np.int64)
    beams_fields = (x, y, heading - fov / 2, fov / beams, max_range, np.ascontiguousarray(directions))
    scan_beams(beams_fields, (centres, radii, segments, *map(float, bounds)), ranges, hits)
    return ranges, hits


def random_scene(rng, n_discs=30, n_segments=30, thick=True):
    centres = np.column_stack([rng.uniform(0, 20, (n_discs, 2)), np.zeros((n_discs, 2))])
    radii = rng.uniform(0.05, 1.2, n_discs)
    starts = rng.uniform(0, 20, (n_segments, 2))
    angle, length = rng.uniform(0, 2 * np.pi, n_segments), rng.uniform(0.0, 4.0, n_segments)
    ends = starts + length[:, None] * np.column_stack([np.cos(angle), np.sin(angle)])
    half = rng.choice([0.0, 0.0, 1e-4, 0.05, 0.3], n_segments) if thick else np.zeros(n_segments)
    return centres, radii, np.column_stack([starts, ends, half])


@pytest.mark.parametrize("fov", [2 * np.pi, 4.0, 0.3])
def test_the_scan_equals_the_brute_force_reference_over_random_scenes(fov):
    rng = np.random.default_rng(int(fov * 1000))
    compared = inside = 0
    for _ in range(60):
        centres, radii, segments = random_scene(rng, rng.integers(0, 40), rng.integers(0, 40))
        x, y = rng.uniform(0, 20, 2)  # anywhere: inside a disc or a wall now and then
        heading, beams, max_range = rng.uniform(-10, 10), int(rng.choice([1, 7, 360, 1081])), rng.uniform(0.5, 30)
        expected, labels, margin = reference_scan(x, y, heading, fov, beams, max_range, centres, radii, segments)
        got, hits = ours(x, y, heading, fov, beams, max_range, centres, radii, segments)
        np.testing.assert_allclose(got, expected, rtol=0, atol=1e-9)
        assert np.all(got <= max_range) and np.all(got >= 0)
        clear = margin > 1e-9  # no tie for the nearest: the same shape is hit
        assert np.array_equal(hits[clear], labels[clear])
        compared += beams
        inside += int(np.all(got == 0))
    assert compared > 10_000 and inside >= 1  # the robot-inside case came up


def test_the_broad_phase_angle_is_within_its_slack():
    rng = np.random.default_rng(0)
    for x, y in rng.normal(0, 10, (20_000, 2)).tolist() + [(0.0, 1.0), (-1.0, 0.0), (0.0, -1.0), (1.0, 1e-300)]:
        assert abs(rough_atan2(y, x) - math.atan2(y, x)) < ANGLE_SLACK / 4


@pytest.mark.parametrize("half_thickness", [0.0, 1e-4])
def test_a_wall_thinner_than_the_beam_spacing_is_never_passed_through(half_thickness):
    # at 9 m the beams of a 360-beam scan are 0.16 m apart, a thousand times the wall's thickness
    rng = np.random.default_rng(1)
    for _ in range(200):
        x, y = rng.uniform(5, 15, 2)
        angle = rng.uniform(0, 2 * np.pi)
        mid = np.array([x, y]) + 9.0 * np.array([np.cos(angle), np.sin(angle)])
        tilt = angle + np.pi / 2 + rng.uniform(-0.5, 0.5)  # across the beams
        a, b = mid - 2.0 * np.array([np.cos(tilt), np.sin(tilt)]), mid + 2.0 * np.array([np.cos(tilt), np.sin(tilt)])
        behind = mid + 2.0 * np.array([np.cos(angle), np.sin(angle)])  # a disc behind the wall, its span within the wall's
        segments = np.array([[*a, *b, half_thickness]])
        centres, radii = np.array([[*behind, 0.0, 0.0]]), np.array([0.5])
        got, hits = ours(x, y, 0.0, 2 * np.pi, 360, 30.0, centres, radii, segments, bounds=(-100, -100, 100, 100))
        # every beam that crosses the wall's line between its ends stops on it
        angles = (np.arange(360) + 0.5) * 2 * np.pi / 360 - np.pi
        u = np.column_stack([np.cos(angles), np.sin(angles)])
        crossing = np.isfinite(_ray_segment(np.array([x, y]), u, a, b))
        assert crossing.sum() >= 10
        assert np.all(hits[crossing] == 1) and not np.any(hits == 0)  # the disc behind is never seen
        assert np.all(got[crossing] <= _ray_segment(np.array([x, y]), u, a, b)[crossing] + 1e-12)


def test_a_robot_touching_a_disc_reads_zero_into_it_and_zero_everywhere_from_inside():
    centres, radii, none = np.array([[10.0, 10.0, 0, 0]]), np.array([1.0]), np.empty((0, 5))
    for gap in (1e-12, 1e-9):  # one beam, straight at the disc's centre
        got, hits = ours(10.0 - 1.0 - gap, 10.0, 0.0, 0.1, 1, 10.0, centres, radii, none)
        assert 0.0 < got[0] <= gap * 1.01 and hits[0] == 0
    for x, y in ((10.0, 10.0), (10.5, 10.2), (9.0, 10.0)):  # inside or on the boundary
        got, hits = ours(x, y, 0.0, 2 * np.pi, 90, 10.0, centres, radii, none)
        assert np.all(got == 0.0) and np.all(hits == 0)
    wall = np.array([[5.0, 5.0, 15.0, 5.0, 0.2]])
    got, hits = ours(9.0, 5.1, 0.0, 2 * np.pi, 90, 10.0, centres[:0], radii[:0], wall)
    assert np.all(got == 0.0) and np.all(hits == 0)


def test_beam_endpoints_lie_at_each_range_along_each_beam():
    ranges = np.linspace(1, 3, 8)
    ends = beam_endpoints((1.0, 2.0), ranges, heading=0.5, fov=np.pi)
    np.testing.assert_allclose(np.hypot(*(ends - [1.0, 2.0]).T), ranges)
    first = 0.5 - np.pi / 2 + 0.5 * np.pi / 8
    np.testing.assert_allclose(np.arctan2(ends[0, 1] - 2.0, ends[0, 0] - 1.0), first)


# -- the "lidar" observation type ------------------------------------------------------------------
def rollout(env, seed, steps=40):
    """Observations and the world's obstacle states over a fixed sequence of actions."""
    obs, _ = env.reset(seed=seed)
    actions = np.random.default_rng(seed).uniform(-1, 1, (steps, 2)).astype(np.float32)
    out, worlds = [obs], [env.unwrapped.world.obstacle_state.copy()]
    for action in actions:
        obs, _, terminated, truncated, _ = env.step(action)
        out.append(obs)
        worlds.append(env.unwrapped.world.obstacle_state.copy())
        if terminated or truncated:
            break
    return out, worlds


def test_the_lidar_reads_the_world_the_state_observation_shows_and_changes_no_episode():
    lidar = gym.make("DynamicObstacle-v0", observation="lidar", delta_d=0.5)
    state = gym.make("DynamicObstacle-v0", delta_d=0.5)
    assert lidar.unwrapped.observation_type.draws is False  # an exact sensor spawns no stream
    for seed in (0, 5):
        scans, worlds = rollout(lidar, seed)
        full, full_worlds = rollout(state, seed)
        assert len(scans) == len(full) > 5
        for a, b, wa, wb in zip(scans, full, worlds, full_worlds):
            np.testing.assert_array_equal(wa, wb)  # the same world trajectory, bit for bit
            for key in ("robot_position", "robot_velocity", "goal"):
                np.testing.assert_array_equal(a[key], b[key])
            assert lidar.observation_space.contains(a)
    # and the scan is the reference's, cast to float32
    world, p = lidar.unwrapped.world, lidar.unwrapped.observation_type.params
    expected, *_ = reference_scan(*world.robot_xy, 0.0, p.lidar_fov, p.lidar_beams, p.lidar_range, world.obstacle_state, world.radii,
                                  np.empty((0, 5)), bounds=world.scenario.bounds)  # fmt: skip
    np.testing.assert_array_equal(scans[-1]["lidar"], expected.astype(np.float32))


def test_noise_and_dropout_are_seeded_deterministic_and_change_no_episode():
    params = {"lidar_noise": 0.05, "lidar_dropout": 0.1, "lidar_beams": 90}
    make = lambda: gym.make("DynamicObstacle-v0", observation="lidar", observation_params=params, delta_d=0.5)
    first, worlds = rollout(make(), 3)
    again, _ = rollout(make(), 3)  # a fresh env, the same seed
    for a, b in zip(first, again):
        np.testing.assert_array_equal(a["lidar"], b["lidar"])
    other, _ = rollout(make(), 4)
    assert not np.array_equal(first[0]["lidar"], other[0]["lidar"])
    exact, exact_worlds = rollout(gym.make("DynamicObstacle-v0", observation="lidar", observation_params={"lidar_beams": 90}, delta_d=0.5), 3)
    for wa, wb in zip(worlds, exact_worlds):
        np.testing.assert_array_equal(wa, wb)
    scans, clean = np.array([o["lidar"] for o in first]), np.array([o["lidar"] for o in exact])
    dropped = (scans == 10.0) & (clean < 10.0)
    assert 0.05 < dropped.mean() < 0.15  # about lidar_dropout of the beams read the maximum range
    noise = (scans - clean)[~dropped & (clean > 0.5) & (clean < 9.5)]
    assert 0.04 < noise.std() < 0.06 and abs(noise.mean()) < 0.01
    assert np.all((scans >= 0) & (scans <= 10.0))


@pytest.mark.parametrize("kwargs", [dict(observation="lidar"), dict(observation="visible-state"),
                                    dict(observation="lidar", observation_params={"lidar_noise": 0.1, "lidar_dropout": 0.2, "lidar_fov": 3.0})])  # fmt: skip
def test_gymnasiums_env_checker_passes(kwargs):
    from gymnasium.utils.env_checker import check_env

    env = gym.make("DynamicObstacle-v0", **kwargs)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_env(env.unwrapped)
    assert type(env.unwrapped.observation_type) is OBSERVATION_TYPES[kwargs["observation"]]


@pytest.mark.parametrize("observation, params, field", [
    ("lidar", {"lidar_beams": 0}, "lidar_beams"), ("lidar", {"lidar_beams": -3}, "lidar_beams"),
    ("lidar", {"lidar_beams": 2.5}, "lidar_beams"), ("lidar", {"lidar_beams": True}, "lidar_beams"),
    ("lidar", {"lidar_beams": "360"}, "lidar_beams"), ("lidar", {"lidar_range": 0}, "lidar_range"),
    ("lidar", {"lidar_range": -1.0}, "lidar_range"), ("lidar", {"lidar_range": math.inf}, "lidar_range"),
    ("lidar", {"lidar_range": math.nan}, "lidar_range"), ("lidar", {"lidar_fov": 0.0}, "lidar_fov"),
    ("lidar", {"lidar_fov": 2 * math.pi + 1e-9}, "lidar_fov"), ("lidar", {"lidar_fov": -1.0}, "lidar_fov"),
    ("lidar", {"lidar_fov": math.nan}, "lidar_fov"), ("lidar", {"lidar_noise": -0.1}, "lidar_noise"),
    ("lidar", {"lidar_noise": math.inf}, "lidar_noise"), ("lidar", {"lidar_dropout": 1.5}, "lidar_dropout"),
    ("lidar", {"lidar_dropout": -0.1}, "lidar_dropout"), ("lidar", {"lidar_dropout": math.nan}, "lidar_dropout"),
    ("visible-state", {"lidar_range": 0}, "lidar_range"), ("visible-state", {"lidar_fov": 7.0}, "lidar_fov"),
    ("visible-state", {"lidar_beams": 90}, "observation_params"), ("lidar", {"range": 5}, "observation_params"),
    ("state", {"lidar_range": 5}, "observation_params"), ("lidar", [("lidar_range", 5)], "observation_params"),
])  # fmt: skip
def test_bad_sensor_parameters_are_rejected_naming_the_field(observation, params, field):
    with pytest.raises(ValueError, match=rf"^{field}"):
        gym.make("DynamicObstacle-v0", observation=observation, observation_params=params)


def test_good_sensor_parameters_shape_the_space():
    env = gym.make("DynamicObstacle-v0", observation="lidar", observation_params={"lidar_beams": np.int64(7), "lidar_fov": 2 * math.pi,
                                                                                   "lidar_range": 4, "lidar_dropout": 1})  # fmt: skip
    space = env.observation_space["lidar"]
    assert space.shape == (7,) and space.high.max() == 4.0 and env.unwrapped.observation_type.draws
    obs, _ = env.reset(seed=0)
    assert np.all(obs["lidar"] == 4.0)  # every beam dropped
    assert isinstance(env.unwrapped.observation_type, LidarObservation)


# -- the "visible-state" observation type ----------------------------------------------------------
ROBOT = (3.0, 5.0)
SCENE = {  # seen from ROBOT, facing +x, with a 180° field of view and a 6 m range
    "near": Obstacle(center=(5.0, 5.0), radius=0.5),  # in plain sight
    "hidden": Obstacle(center=(8.0, 5.0), radius=0.4),  # wholly behind "near"
    "partly": Obstacle(center=(8.0, 6.2), radius=0.5),  # its lower part behind "near", its upper part not
    "behind": Obstacle(center=(1.0, 5.0), radius=0.4),  # outside the field of view
    "far": Obstacle(center=(9.5, 1.0), radius=0.3),  # out of range
    "edge": Obstacle(center=(3.0, 8.5), radius=0.4),  # centre on the fov's edge: half of it in view
    "reach": Obstacle(center=(3.0 + 6.3 * 0.8, 5.0 - 6.3 * 0.6), radius=0.5),  # centre out of range, its near side in
    "walled": Obstacle(center=(4.0, 2.0), radius=0.4),  # visible until a wall is put in front of it
}


def visible_state_env(fov=math.pi, max_range=6.0):
    scenario = Scenario(bounds=(0.0, 0.0, 12.0, 10.0), start=ROBOT, goal=(11.0, 9.0), obstacles=tuple(SCENE.values()))
    env = gym.make("DynamicObstacle-v0", scenario=scenario, observation="visible-state",
                   observation_params={"lidar_fov": fov, "lidar_range": max_range})  # fmt: skip
    return env


def test_what_is_visible_hidden_outside_the_fov_or_out_of_range():
    env = visible_state_env()
    obs, _ = env.reset(seed=0)
    assert isinstance(env.unwrapped.observation_type, VisibleStateObservation)
    shown = dict(zip(SCENE, obs["obstacle_mask"][: len(SCENE)] > 0))
    assert shown == {"near": True, "hidden": False, "partly": True, "behind": False, "far": False, "edge": True, "reach": True, "walled": True}
    state = gym.make("DynamicObstacle-v0", scenario=env.unwrapped.scenario)
    full, _ = state.reset(seed=0)
    for key in full:  # the visible rows are the state's; the others are padding rows
        rows = np.array(list(shown.values()) + [False] * (len(full["obstacle_mask"]) - len(SCENE))) if key.startswith("obstacle") else None
        if rows is None:
            np.testing.assert_array_equal(obs[key], full[key])
        else:
            np.testing.assert_array_equal(obs[key][rows], full[key][rows])
            padding = {"obstacle_positions": [0.0, 0.0], "obstacle_velocities": [0.0, 0.0]}.get(key, 0.0)
            np.testing.assert_array_equal(obs[key][~rows], np.broadcast_to(padding, obs[key][~rows].shape))
    assert env.observation_space == state.observation_space and env.observation_space.contains(obs)
    # a wide enough sensor sees what the fov and the range left out, but still not what is occluded
    wide, _ = visible_state_env(fov=2 * math.pi, max_range=20.0).reset(seed=0)
    assert (wide["obstacle_mask"][: len(SCENE)] > 0).tolist() == [True, False, True, True, True, True, True, True]


def test_walls_hide_what_is_behind_them():
    env = visible_state_env()
    env.reset(seed=0)
    world, observation = env.unwrapped.world, env.unwrapped.observation_type
    world.static_segments = np.array([[3.0, 3.5, 5.0, 3.0, 0.05]])  # between the robot and "walled"
    obs = observation.observe(world)
    assert obs["obstacle_mask"][list(SCENE).index("walled")] == 0 and obs["obstacle_mask"][list(SCENE).index("near")] == 1
    world.static_segments = np.array([[3.5, 4.0, 3.5, 6.0, 0.0]])  # a plain segment across "near"'s whole span
    obs = observation.observe(world)
    assert obs["obstacle_mask"][list(SCENE).index("near")] == 0 and obs["obstacle_mask"][list(SCENE).index("walled")] == 1


def _first_hit(x, y, angle, centres, radii, segments):
    """The reference's (distance, index) of the first shape a ray enters (index N + m for wall m)."""
    o, u = np.array([x, y]), np.array([[math.cos(angle), math.sin(angle)]])
    t = [_ray_circle(o, u, c[:2], r)[0] for c, r in zip(centres, radii)] + [_ray_capsule(o, u, row)[0] for row in segments]
    return (min(t), int(np.argmin(t))) if t else (np.inf, -1)


@pytest.mark.parametrize("fov, scenes, rays", [
    (2 * math.pi, 25, 4000), (2.0, 25, 4000),
    pytest.param(2 * math.pi, 100, 20_000, marks=pytest.mark.slow), pytest.param(2.0, 100, 20_000, marks=pytest.mark.slow),
    pytest.param(0.7, 100, 20_000, marks=pytest.mark.slow), pytest.param(5.5, 100, 20_000, marks=pytest.mark.slow),
])  # fmt: skip
def test_visibility_is_exact_against_dense_rays(fov, scenes, rays):
    """Every obstacle called visible has a witness ray that the reference confirms; every obstacle a
    dense fan of reference rays sees is called visible."""
    rng = np.random.default_rng(7)
    found = 0
    for _ in range(scenes):
        centres, radii, segments = random_scene(rng, 25, 8)
        x, y, heading, max_range = *rng.uniform(0, 20, 2), rng.uniform(-4, 4), rng.uniform(1, 15)
        visible, witness = np.zeros(25, np.bool_), np.zeros(25)
        visible_obstacles(x, y, heading, fov, max_range, centres, radii, segments, visible, witness)
        for j in np.flatnonzero(visible):
            if math.hypot(centres[j, 0] - x, centres[j, 1] - y) <= radii[j]:
                continue  # the robot is inside it
            assert abs((witness[j] - heading + math.pi) % (2 * math.pi) - math.pi) <= fov / 2 + 1e-9
            t, first = _first_hit(x, y, witness[j], centres, radii, segments)
            assert first == j and t <= max_range * (1 + 1e-9)
        angles = heading - fov / 2 + (np.arange(rays) + 0.5) * fov / rays
        o, u = np.array([x, y]), np.column_stack([np.cos(angles), np.sin(angles)])
        table = np.column_stack([_ray_circle(o, u, c[:2], r) for c, r in zip(centres, radii)] + [_ray_capsule(o, u, row) for row in segments])
        first = np.argmin(table, axis=1)
        seen = set(first[(table[np.arange(len(first)), first] <= max_range) & (first < 25)].tolist())
        assert seen <= set(np.flatnonzero(visible).tolist())
        found += len(seen)
    assert found > scenes


def test_planners_run_unchanged_on_what_they_see():
    import agents

    env = gym.make("DynamicObstacle-v0", observation="visible-state", observation_params={"lidar_range": 4.0}, delta_d=0.5)
    agent = agents.make("astar-spacetime", env, seed=0)
    obs, _ = env.reset(seed=2)
    for _ in range(15):
        action, _ = agent.predict(obs, deterministic=True)
        obs, _, terminated, truncated, _ = env.step(action)
        assert env.observation_space.contains(obs)
        if terminated or truncated:
            break


@pytest.mark.parametrize("kwargs", [dict(observation="lidar", observation_params={"lidar_noise": 0.1}), dict(observation="visible-state")])
def test_a_pickled_sensing_env_observes_as_the_original(kwargs):
    import pickle

    env = gym.make("DynamicObstacle-v0", delta_d=0.5, **kwargs).unwrapped
    env.reset(seed=1)
    for _ in range(5):
        env.step(np.float32([0.3, 0.2]))
    copy = pickle.loads(pickle.dumps(env))
    a, b = env.step(np.float32([0.1, 0.9]))[0], copy.step(np.float32([0.1, 0.9]))[0]
    for key in a:
        np.testing.assert_array_equal(a[key], b[key])


def test_the_renderer_draws_the_scan_and_greys_what_the_sensor_does_not_see():
    from pathplan_env.rendering import BEAM, HIDDEN

    def colours(observation, params=None):
        env = gym.make("DynamicObstacle-v0", scenario="cluttered-room", observation=observation, observation_params=params,
                       render_mode="rgb_array")  # fmt: skip
        env.reset(seed=2)
        frame = env.render()
        return {tuple(c) for c in frame.reshape(-1, 3)}, env

    lidar, _ = colours("lidar", {"lidar_range": 4.0})
    assert BEAM in lidar
    seen, env = colours("visible-state", {"lidar_range": 2.0})
    hidden = ~env.unwrapped.observation_type.visible
    assert hidden.any() and HIDDEN in seen
    plain, _ = colours("state")
    assert BEAM not in plain and HIDDEN not in plain
