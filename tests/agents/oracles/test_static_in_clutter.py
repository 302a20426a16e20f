"""oracle-static in dense clutter: its path exists exactly where a fine grid search finds room for the
robot with its flying margin, is never longer than the grid's, and its flown episode never touches
a cylinder; where there is no path it says so and holds still."""

import gymnasium as gym
import numpy as np
import pytest
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

import agents
from agents.oracles.static import flying_margin
from pathplan_env import Obstacle, Scenario
from pathplan_env.geometry.contacts import point_segment_distance

CYLINDER, ROBOT, SIDE, STEP = 0.075, 0.333, 8.0, 0.25
START, GOAL = (0.7, SIDE / 2), (SIDE - 0.7, SIDE / 2)


NEED = CYLINDER + ROBOT + float(flying_margin(CYLINDER + ROBOT, STEP))  # the robot centre's least distance to a cylinder's
TIGHT = 2 * NEED + 0.004  # a corridor 2 mm wider each side than the oracle needs


def _clutter(seed: int, n: int, corridor: float = 0.0) -> Scenario:
    """``n`` resting cylinders (radius 0.075 m) drawn uniformly in an 8 m square, none overlapping and
    none within 0.6 m of the robot's start or goal disc: gaps of every width, some a robot's; with a
    ``corridor`` width, none nearer than half of it (plus its radius) to a bent line from start to goal."""
    rng = np.random.default_rng(seed)
    line = np.array([START, (SIDE / 3, rng.uniform(2, SIDE - 2)), (2 * SIDE / 3, rng.uniform(2, SIDE - 2)), GOAL])
    centres = []
    while len(centres) < n:
        p = rng.uniform(CYLINDER, SIDE - CYLINDER, 2)
        if min(np.hypot(*(p - START)), np.hypot(*(p - GOAL))) < ROBOT + CYLINDER + 0.6:
            continue
        if corridor and point_segment_distance(p[None], line[:-1], line[1:]).min() < corridor / 2 + CYLINDER:
            continue
        if all(np.hypot(*(p - q)) >= 2 * CYLINDER for q in centres):
            centres.append(p)
    return Scenario(bounds=(0.0, 0.0, SIDE, SIDE), start=START, goal=GOAL, robot_radius=ROBOT, robot_speed=STEP / 0.1, dt=0.1,
                    obstacles=tuple(Obstacle(center=tuple(c), radius=CYLINDER) for c in centres), name="clutter-test")  # fmt: skip


def _grid_length(scenario: Scenario, clearance: float, h: float = 0.02) -> float:
    """Shortest 8-connected path between the cells of the start and the goal over the cells whose
    centre is at least ``clearance`` from every cylinder's centre and inside the robot's box (inf: none)."""
    xs = np.arange(ROBOT + h / 2, SIDE - ROBOT, h)
    gx, gy = np.meshgrid(xs, xs, indexing="ij")
    pos = scenario.arrays()["positions"]
    free = np.ones(gx.shape, bool)
    for c in pos:
        free &= np.hypot(gx - c[0], gy - c[1]) >= clearance
    index = np.full(gx.shape, -1)
    index[free] = np.arange(free.sum())
    rows, cols, weights = [], [], []
    for di, dj in ((1, 0), (0, 1), (1, 1), (1, -1)):
        m, j0, j1 = len(xs), max(0, -dj), len(xs) - max(0, dj)
        a, b = index[0 : m - di, j0:j1], index[di:m, j0 + dj : j1 + dj]
        both = (a >= 0) & (b >= 0)
        rows.append(a[both]), cols.append(b[both]), weights.append(np.full(both.sum(), h * np.hypot(di, dj)))
    graph = coo_matrix((np.concatenate(weights), (np.concatenate(rows), np.concatenate(cols))), shape=(free.sum(),) * 2)
    cell = lambda p: index[int(round((p[0] - xs[0]) / h)), int(round((p[1] - xs[0]) / h))]
    s, g = cell(START), cell(GOAL)
    assert s >= 0 and g >= 0
    ends = np.hypot(*(np.array(START) - [gx.ravel()[free.ravel()][s], gy.ravel()[free.ravel()][s]])) + np.hypot(
        *(np.array(GOAL) - [gx.ravel()[free.ravel()][g], gy.ravel()[free.ravel()][g]])
    )
    return float(dijkstra(graph, directed=False, indices=s)[g]) + ends


def _oracle_path(scenario: Scenario):
    env = gym.make("DynamicObstacle-v0", scenario=scenario)
    agent = agents.make("oracle-static", env, seed=0)
    obs, _ = env.reset(seed=0)
    agent.predict(obs, deterministic=True)
    return env, agent, obs


SCENES = [(1, 85, 0.0), (2, 95, 0.0), (3, 90, 0.0), (4, 100, 0.0), (5, 200, TIGHT), (6, 250, TIGHT), (7, 300, 0.8)]


@pytest.mark.parametrize("seed, n, corridor", SCENES)
def test_a_path_exactly_where_the_grid_finds_room_and_no_longer(seed, n, corridor):
    scenario = _clutter(seed, n, corridor)
    _, agent, _ = _oracle_path(scenario)
    need, h = NEED, 0.02
    tight = _grid_length(scenario, need + h / np.sqrt(2), h)  # its polyline is free of every inflated disc
    loose = _grid_length(scenario, need - h / np.sqrt(2), h)  # every free path's cells are in it
    path = agent.last_plan
    if np.isfinite(tight):
        assert path is not None
    if path is None:
        assert agent.verdict == "no path" and not np.isfinite(tight)
        return
    assert np.isfinite(loose)
    length = float(np.sum(np.hypot(*np.diff(path, axis=0).T)))
    assert length <= tight + 1e-6  # the exact shortest path is no longer than any feasible grid path
    # free: every point of the polyline keeps the inflated radius (to the arc sampling's sag)
    pos = scenario.arrays()["positions"]
    dense = np.concatenate([np.linspace(a, b, 20) for a, b in zip(path[:-1], path[1:])])
    gaps = np.hypot(dense[:, None, 0] - pos[None, :, 0], dense[:, None, 1] - pos[None, :, 1]).min(axis=1)
    assert gaps.min() >= need - 1e-5


def test_clutter_has_both_outcomes():
    """The scenes above are not all easy: some have no path for the robot, some do."""
    outcomes = {_oracle_path(_clutter(seed, n, corridor))[1].last_plan is None for seed, n, corridor in SCENES}
    assert outcomes == {False, True}


@pytest.mark.parametrize("seed, n, corridor", [(3, 90, 0.0), (5, 200, TIGHT)])
def test_the_flown_episode_never_touches_a_cylinder(seed, n, corridor):
    env, agent, obs = _oracle_path(_clutter(seed, n, corridor))
    solvable = agent.last_plan is not None
    agent.reset()
    obs, _ = env.reset(seed=0)
    for _ in range(200):
        obs, _, terminated, truncated, info = env.step(agent.predict(obs, deterministic=True)[0])
        assert not info["collision"]
        if terminated or truncated:
            break
    assert info["is_success"] == solvable
    assert agent.verdict == ("path" if solvable else "no path")


def test_no_path_holds_still_and_says_so():
    """Boxed in by a ring of touching cylinders: no plan, the robot stays where it is."""
    ring = [(2.0 + 0.6 * np.cos(a), 2.0 + 0.6 * np.sin(a)) for a in np.linspace(0, 2 * np.pi, 24, endpoint=False)]
    scenario = Scenario(bounds=(0.0, 0.0, 6.0, 6.0), start=(2.0, 2.0), goal=(5.0, 5.0), robot_radius=0.3, dt=0.1, robot_speed=2.5,
                        obstacles=tuple(Obstacle(center=c, radius=0.075) for c in ring))  # fmt: skip
    env = gym.make("DynamicObstacle-v0", scenario=scenario)
    agent = agents.make("oracle-static", env, seed=0)
    obs, _ = env.reset(seed=0)
    for _ in range(5):
        obs, _, _, _, info = env.step(agent.predict(obs, deterministic=True)[0])
        assert not info["collision"]
    assert np.allclose(obs["robot_position"], (2.0, 2.0), atol=1e-5)
    assert agent.verdict == "no path" and agent.no_path_steps == 5


def test_among_resting_cylinders_it_flies_on_along_its_plan(monkeypatch):
    """Nothing moved: the rest of the last plan is the shortest path, and no graph is built again;
    once an obstacle moves, every step plans afresh."""
    import agents.oracles.static as static

    calls, original = [], static.shortest_path
    monkeypatch.setattr(static, "shortest_path", lambda *a, **k: calls.append(1) or original(*a, **k))
    for delta_d, built in ((None, 1), (0.5, 10)):
        scenario = _clutter(4, 60) if delta_d is None else _clutter(4, 60).with_delta_d(delta_d, np.random.default_rng(0))
        env = gym.make("DynamicObstacle-v0", scenario=scenario)
        agent = agents.make("oracle-static", env, seed=0)
        obs, _ = env.reset(seed=0)
        calls.clear()
        for _ in range(10):
            obs, *_ = env.step(agent.predict(obs, deterministic=True)[0])
        assert len(calls) == built
