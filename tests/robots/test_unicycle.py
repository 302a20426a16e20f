"""The unicycle robot: its parameters, kinematics, exact contact along arcs, and its agents."""

from __future__ import annotations

import hashlib
import pickle

import gymnasium as gym
import numpy as np
import pytest

import pathplan_env  # noqa: F401
from pathplan_env.geometry.contacts import NO_CONTACT
from pathplan_env.robots.arc_contact import Arc, arc_capsule, arc_disc, arc_point
from pathplan_env.robots.unicycle import default_limits

SAMPLES = 2001  # reference grid per case, then a ternary refinement of its best bracket
CASES = 12000


def _arc_points(x, y, heading, speed, turn, duration, f):
    """Reference positions ``(..., 2)`` along arcs (arrays broadcast against ``f``), by plain
    trigonometry, not the kernel's chord form."""
    s = f * duration
    straight = np.abs(turn) < 1e-12
    safe = np.where(straight, 1.0, turn)
    th = heading + turn * s
    px = np.where(straight, x + speed * s * np.cos(heading), x + speed / safe * (np.sin(th) - np.sin(heading)))
    py = np.where(straight, y + speed * s * np.sin(heading), y - speed / safe * (np.cos(th) - np.cos(heading)))
    return np.stack([px, py], -1)


def _random_arcs(rng, k):
    kind = rng.integers(3, size=k)
    turn = np.where(kind == 0, 0.0, np.where(kind == 1, rng.uniform(-30, 30, k), rng.uniform(-3, 3, k)))
    return (rng.uniform(-1, 1, k), rng.uniform(-1, 1, k), rng.uniform(-np.pi, np.pi, k), rng.uniform(0, 5, k), turn, rng.uniform(0.05, 0.25, k))


def _smallest(distance, k):
    """Smallest of ``distance(u)`` ((k, m) for u (k, m)) over [0, 1] per case: a grid, then a ternary
    search of the best grid bracket (the distance is smooth and unimodal there)."""
    grid = np.broadcast_to(np.linspace(0, 1, SAMPLES), (k, SAMPLES))
    values = distance(grid)
    i = np.argmin(values, axis=1)
    lo, hi = np.maximum(i - 1, 0) / (SAMPLES - 1), np.minimum(i + 1, SAMPLES - 1) / (SAMPLES - 1)
    for _ in range(80):
        a, b = lo + (hi - lo) / 3, hi - (hi - lo) / 3
        va, vb = distance(np.stack([a, b], 1)).T
        lo, hi = np.where(va < vb, lo, a), np.where(va < vb, b, hi)
    return np.minimum(values.min(axis=1), distance(((lo + hi) / 2)[:, None])[:, 0])


def test_arc_point_matches_trigonometry():
    rng = np.random.default_rng(1)
    arcs = _random_arcs(rng, 200)
    f = rng.uniform(0, 1, 200)
    reference = _arc_points(*arcs, f)
    for j in range(200):
        x, y, heading = arc_point(Arc(*(float(a[j]) for a in arcs)), f[j])
        assert np.allclose((x, y), reference[j], atol=1e-9)
        assert heading == pytest.approx(arcs[2][j] + arcs[4][j] * f[j] * arcs[5][j])


def test_arc_disc_contact_matches_a_finely_sampled_reference():
    """12,000 random arc pieces against linearly moving discs, each at three radii: as drawn, grazing
    by 1 % of the disc's radius (must hit: 0 misses) and missing by 1 % (must not hit)."""
    rng = np.random.default_rng(0)
    arcs = _random_arcs(rng, CASES)
    f0 = rng.uniform(0, 0.8, CASES)
    f1 = np.minimum(1.0, f0 + rng.uniform(0, 0.5, CASES))
    robot_r = rng.uniform(0.1, 0.5, CASES)
    d = rng.normal(size=(CASES, 2)) * rng.uniform(0, 3.0, (CASES, 1))  # the disc's displacement over the piece
    u_star = rng.uniform(0, 1, CASES)
    angle = rng.uniform(-np.pi, np.pi, CASES)
    near = _arc_points(*arcs, f0 + u_star * (f1 - f0)) + rng.uniform(0.3, 1.5, (CASES, 1)) * np.stack([np.cos(angle), np.sin(angle)], 1)
    oa = near - u_star[:, None] * d

    def distance(u):  # (K, m)
        p = _arc_points(*(a[:, None] for a in arcs), f0[:, None] + u * (f1 - f0)[:, None])
        return np.hypot(*np.moveaxis(oa[:, None] + u[..., None] * d[:, None] - p, -1, 0))

    smallest = _smallest(distance, CASES)
    radius = rng.uniform(0.05, 1.0, CASES)
    miss_radius = (smallest - robot_r) / 1.01  # the smallest gap is then 1 % of the disc's radius
    misses = false_hits = hits = checked_near = 0
    for j in range(CASES):
        arc = Arc(*(float(a[j]) for a in arcs))
        ob = oa[j] + d[j]

        def hit(r, arc=arc, j=j, ob=ob):
            return arc_disc(arc, f0[j], f1[j], oa[j, 0], oa[j, 1], ob[0], ob[1], robot_r[j] + r)[1] <= 1.0

        if smallest[j] - robot_r[j] - radius[j] < -1e-9:
            hits += 1
            misses += not hit(radius[j])
        graze = (smallest[j] - robot_r[j]) / 0.99  # overlapping by 1 % of this radius at the closest point
        if graze > 0:
            misses += not hit(graze)
        if miss_radius[j] > 0:
            checked_near += 1
            false_hits += hit(miss_radius[j])
    assert misses == 0 and false_hits == 0
    assert hits > 5000 and checked_near > 9000  # (a disc drawn inside the robot has no 1 % variant)


def test_arc_capsule_contact_matches_a_finely_sampled_reference():
    """10,000+ random arcs against static capsules (a wall, a polygon edge), each grazed by 1 % of the
    robot's radius (must hit) and missed by 1 % (must not)."""
    rng = np.random.default_rng(2)
    arcs = _random_arcs(rng, CASES)
    f_end = rng.uniform(0, 1, CASES)
    robot_r = rng.uniform(0.1, 0.5, CASES)
    at = _arc_points(*arcs, f_end * rng.uniform(0, 1, CASES))
    angle = rng.uniform(-np.pi, np.pi, CASES)
    along = np.stack([np.cos(angle), np.sin(angle)], 1)
    length = np.where(rng.uniform(size=CASES) < 0.1, 0.0, rng.uniform(0, 2, CASES))
    a = at + rng.uniform(0.3, 1.2, (CASES, 1)) * along[:, ::-1] * [-1, 1] - along * rng.uniform(0, 1, (CASES, 1)) * length[:, None]
    ab = along * length[:, None]

    def distance(u):
        p = _arc_points(*(x[:, None] for x in arcs), u * f_end[:, None])
        rel = p - a[:, None]
        t = np.clip(np.einsum("kmi,ki->km", rel, ab) / np.maximum(length**2, 1e-300)[:, None], 0, 1)
        return np.hypot(*np.moveaxis(rel - t[..., None] * ab[:, None], -1, 0))

    smallest = _smallest(distance, CASES)
    misses = false_hits = checked = 0
    for j in range(CASES):
        arc = Arc(*(float(x[j]) for x in arcs))
        b = a[j] + ab[j]

        def hit(half, arc=arc, j=j, b=b):
            return arc_capsule(arc, f_end[j], robot_r[j], a[j, 0], a[j, 1], b[0], b[1], half)[1] <= 1.0

        near_half, graze_half = smallest[j] - 1.01 * robot_r[j], smallest[j] - 0.99 * robot_r[j]
        if near_half >= 0.0:
            checked += 1
            false_hits += hit(near_half)
            misses += not hit(graze_half)
    assert misses == 0 and false_hits == 0
    assert checked > 10000


def test_straight_arc_gap_is_exact():
    arc = Arc(0.0, 0.0, 0.0, 2.0, 0.0, 1.0)  # from (0, 0) to (2, 0)
    gap, u = arc_disc(arc, 0.0, 1.0, 1.0, 1.0, 1.0, 1.0, 0.5)
    assert gap == pytest.approx(0.5, abs=1e-12) and u == NO_CONTACT


# -- the env ---------------------------------------------------------------------------------------
def test_holonomic_default_is_unchanged():
    a = gym.make("DynamicObstacle-v0")
    b = gym.make("DynamicObstacle-v0", robot="holonomic", action="waypoint")
    oa, _ = a.reset(seed=4)
    ob, _ = b.reset(seed=4)
    assert set(oa) == set(ob) and "robot_heading" not in oa
    for _ in range(20):
        action = a.action_space.sample()
        oa, *_ = a.step(action)
        ob, *_ = b.step(action)
    assert all(np.array_equal(oa[k], ob[k]) for k in oa)


@pytest.mark.parametrize(
    "params, field",
    [
        ({"max_speed": -1.0}, "max_speed"),
        ({"max_turn_rate": float("nan")}, "max_turn_rate"),
        ({"max_acceleration": float("inf")}, "max_acceleration"),
        ({"max_angular_acceleration": 0.0}, "max_angular_acceleration"),
        ({"min_speed": -0.1}, "min_speed"),
        ({"min_speed": 3.0}, "min_speed"),  # above the default max_speed 2.5
        ({"min_speed": 1.0, "max_speed": 0.5}, "min_speed"),
        ({"max_speed": True}, "max_speed"),
        ({"max_turn_rate": 1000.0}, "max_turn_rate"),
        ({"wheelbase": 1.0}, "robot_params"),
    ],
)
def test_bad_robot_params_raise_naming_the_field(params, field):
    with pytest.raises(ValueError, match=field):
        gym.make("DynamicObstacle-v0", robot="unicycle", robot_params=params)


def test_bad_robot_and_action_combinations():
    with pytest.raises(ValueError, match="robot must be"):
        gym.make("DynamicObstacle-v0", robot="tank")
    with pytest.raises(ValueError, match="does not drive"):
        gym.make("DynamicObstacle-v0", robot="unicycle", action="waypoint")
    with pytest.raises(ValueError, match="robot_params"):
        gym.make("DynamicObstacle-v0", robot_params={"max_speed": 1.0})
    env = gym.make("DynamicObstacle-v0", robot="unicycle")
    env.reset(seed=0)
    with pytest.raises(ValueError, match="finite"):
        env.step(np.array([np.nan, 0.0]))


def _unicycle(**params):
    return gym.make("DynamicObstacle-v0", robot="unicycle", robot_params=params or None).unwrapped


def unicycle_digest(scenario="random", steps=150, seed=3, **kwargs) -> str:
    env = gym.make("DynamicObstacle-v0", scenario=scenario, robot="unicycle", **kwargs)
    rng = np.random.default_rng(seed)
    env.reset(seed=seed)
    h = hashlib.sha256()
    for _ in range(steps):
        obs, reward, terminated, truncated, info = env.step(np.array([rng.uniform(-0.2, 1.0), rng.uniform(-1.0, 1.0)], np.float32))
        for key in sorted(obs):
            h.update(obs[key].tobytes())
        h.update(repr((reward, terminated, truncated, info["min_clearance"], info["path_length"], info["collision"], info["waypoint"])).encode())
        if terminated or truncated:
            env.reset()
    return h.hexdigest()


UNICYCLE_DIGESTS = [  # computed before the step was compiled (pathplan_env/robots/unicycle_step.py): the same episodes bit for bit
    ({}, "88b4ab7c23c4a5c33a83b671e33ec333bbc6462c1f601e405d6b91d3660266ca"),
    ({"delta_d": 1.0}, "4de8baa009d948e1e1fefdd70bf7812f2e0ab2ccbcab9aade4838c14d9a38fd4"),
    ({"delta_d": 4.0, "n_obstacles": 20}, "d6d1e7d286c192edbeed78e524b189681bed1f024c8b4cc6fc60305925a033ee"),
    ({"delta_d": 0.0, "n_obstacles": 12}, "0d9a9e586f926a604dcaa622f971b3f698d9878d52836fb274140bdee144df56"),
    ({"scenario": "corridor"}, "c56783b8994f92015899524f6a9222d7ae2d7df11b4d8fb8b59d3606b4bbc66f"),
    ({"scenario": "cluttered-room", "delta_d": 1.0}, "1362badab2cdbbe76eaff56d3cca35d00be8dde5332b2e4880e704cef503b144"),
    ({"scenario": "crowdnav-circle-crossing-visible"}, "e76d89a67fed3afd4caa8238ef0a779d32afbaf0b5eaf398dd002e99e3e4b544"),
]


@pytest.mark.parametrize("kwargs, digest", UNICYCLE_DIGESTS)
def test_unicycle_episodes_replay_their_digest(kwargs, digest):
    """Substeps (Δd 1, 4), resting obstacles, walls and a visible crowd: observations, rewards and info."""
    assert unicycle_digest(**kwargs) == digest


def test_acceleration_and_turn_limits_hold():
    env = _unicycle(max_acceleration=2.0, max_angular_acceleration=4.0, max_turn_rate=3.0, max_speed=2.0)
    env.reset(seed=3)
    dt = env.dt
    speeds, turns, headings = [0.0], [0.0], [float(env.world.robot_heading)]
    rng = np.random.default_rng(0)
    for _ in range(40):
        _, _, terminated, _, _ = env.step(rng.uniform(-1, 1, 2))
        if terminated:
            break
        speeds.append(env.world.robot_forward_speed)
        turns.append(env.world.robot_angular_velocity)
        headings.append(env.world.robot_heading)
    assert len(speeds) > 5
    assert np.all(np.abs(np.diff(speeds)) <= 2.0 * dt + 1e-12) and np.all(np.abs(np.diff(turns)) <= 4.0 * dt + 1e-12)
    assert min(speeds) >= 0.0 and max(speeds) <= 2.0 and max(np.abs(turns)) <= 3.0
    turned = np.angle(np.exp(1j * np.diff(headings)))
    assert np.allclose(turned, np.array(turns[1:]) * dt, atol=1e-9)  # the heading integrates the turn rate


def test_defaults_follow_the_given_limits():
    limits = _unicycle(max_speed=1.0, min_speed=0.2).action_type
    env = _unicycle(max_speed=1.0, min_speed=0.2)
    env.reset(seed=0)
    assert env.action_type.limits == (1.0, 1.0 / (2 * env.robot_radius), 2.0, 1.0 / (2 * env.robot_radius) / 0.5, 0.2)
    assert limits.params == {"max_speed": 1.0, "min_speed": 0.2}


def test_full_action_reaches_top_speed_and_observation_reports_it():
    env = gym.make("DynamicObstacle-v0", robot="unicycle", scenario="random", delta_d=0.0, n_obstacles=1)
    obs, _ = env.reset(seed=1)
    limits = default_limits(env.unwrapped.robot_speed, env.unwrapped.robot_radius)
    assert obs["robot_heading"].shape == (1,) and env.observation_space.contains(obs)
    for _ in range(5):  # 0.5 s ramp
        obs, _, terminated, _, _ = env.step(np.array([1.0, 0.0]))
    assert np.hypot(*obs["robot_velocity"]) == pytest.approx(limits.max_speed, rel=1e-6) or terminated


def test_unicycle_episode_is_deterministic_and_pickles():
    def run(env, seed):
        env.reset(seed=seed)
        rng = np.random.default_rng(seed)
        out = []
        for _ in range(30):
            obs, _, term, trunc, info = env.step(rng.uniform(-1, 1, 2).astype(np.float32))
            out.append(np.concatenate([obs["robot_position"], obs["robot_heading"], [info["min_clearance"]]]))
            if term or trunc:
                break
        return np.array(out)

    a = gym.make("DynamicObstacle-v0", robot="unicycle", delta_d=1.0)
    assert np.array_equal(run(a, 5), run(gym.make("DynamicObstacle-v0", robot="unicycle", delta_d=1.0), 5))
    a.reset(seed=6)
    for _ in range(10):
        a.step(np.array([0.8, 0.4], np.float32))
    b = pickle.loads(pickle.dumps(a))
    for _ in range(10):
        oa, *_ = a.step(np.array([0.6, -0.5], np.float32))
        ob, *_ = b.step(np.array([0.6, -0.5], np.float32))
    assert all(np.array_equal(oa[k], ob[k]) for k in oa)


def test_a_contact_stops_the_robot_touching():
    """Driving in circles among resting obstacles (the obstacles finish a step after a contact, so
    only resting ones keep the contact pose): every contact leaves the robot touching an obstacle or
    the arena's edge, every other step leaves it clear."""
    env = gym.make("DynamicObstacle-v0", robot="unicycle", delta_d=0.0, n_obstacles=12).unwrapped
    contacts = 0
    for seed in range(30):
        env.reset(seed=seed)
        xmin, ymin, xmax, ymax = env.bounds
        for _ in range(60):
            _, _, terminated, _, info = env.step(np.array([1.0, 0.6]))
            (x, y), r = env.world.robot_xy, env.robot_radius
            gap = min(env.world.clearance(), x - xmin - r, xmax - x - r, y - ymin - r, ymax - y - r)
            if info["collision"]:
                contacts += 1
                assert gap == pytest.approx(0.0, abs=1e-6)
            else:
                assert gap > 0.0
            if terminated:
                break
    assert contacts > 5


def test_renders_the_heading():
    env = gym.make("DynamicObstacle-v0", robot="unicycle", render_mode="rgb_array")
    env.reset(seed=0)
    frame = env.render()
    assert frame.shape[2] == 3


# -- agents ----------------------------------------------------------------------------------------
@pytest.mark.parametrize("name", ["dwa", "tracked-astar-spacetime", "tracked-straight"])
def test_unicycle_agents_drive_an_episode(name):
    import agents

    env = gym.make("DynamicObstacle-v0", robot="unicycle", delta_d=0.0, n_obstacles=0)
    agent = agents.make(name, env, seed=0)
    info = agents.rollout(agent, env, seed=0)
    assert info["is_success"]  # an empty arena: every one reaches the goal
    assert agent.last_plan is not None


def test_unicycle_agents_need_a_unicycle():
    import agents

    with pytest.raises(ValueError, match="unicycle"):
        agents.make("dwa", gym.make("DynamicObstacle-v0"))


def test_the_harness_runs_the_unicycle_without_the_limit(tmp_path):  # with it: tests/agents/planners/test_unicycle_search.py
    from agents.evaluation import EvaluationSettings, evaluate

    summary = evaluate(["dwa"], ["random"], [0.25], 2, tmp_path / "b", EvaluationSettings(env_options={"robot": "unicycle"}, limit=False, plots=False))
    assert summary is not None and (tmp_path / "b" / "summary.json").exists()
