"""The passable cost-to-go (agents/planners/passable.py): the space-time planners' guide among dense
static geometry, where the lower bound opens gaps the robot does not fit (issue 46, "planners stall")."""

from __future__ import annotations

import gymnasium as gym
import numpy as np

import agents
import pathplan_env  # noqa: F401  (registers the env)
from agents.planners.costtogo import cost_to_go, distance_to_goal
from agents.planners.passable import MISLEAD_CELLS, guiding_cost_to_go, misled_share, passable_cost_to_go
from pathplan_env.arena import Arena
from pathplan_env.facts import EnvFacts
from pathplan_env.geometry.tangent_graph import shortest_path
from pathplan_env.scenarios.clutter import clutter_scenario

ROBOT = 0.333


def _gate(gap: float):
    """Two discs of radius 0.3 across the way from (1, 5) to (9, 5) with a gap of ``gap`` between
    them, and a wall of touching discs above and below, so that the way round is long."""
    column = [(5.0, y) for y in np.arange(0.3, 10.0, 0.6) if abs(y - 5.0) > 0.3 + gap / 2 + 0.3 - 1e-9]
    centres = np.array([(5.0, 5.0 - gap / 2 - 0.3), (5.0, 5.0 + gap / 2 + 0.3), *column])
    return centres, np.full(len(centres), 0.3)


def test_a_gap_narrower_than_the_robot_is_closed_to_it_and_one_wider_is_open():
    box = Arena((0.0, 0.0, 10.0, 10.0), ROBOT).box
    start, goal = np.array([1.0, 5.0]), np.array([9.0, 5.0])
    for gap, fits in ((2 * ROBOT - 0.1, False), (2 * ROBOT + 0.05, True)):
        centres, radii = _gate(gap)
        lower = cost_to_go(goal, 0.0, box, np.zeros((0, 5)), ROBOT, centres, radii)
        passable = passable_cost_to_go(goal, 0.0, box, np.zeros((0, 5)), ROBOT, centres, radii + ROBOT)
        _, exact = shortest_path(start, goal, centres, radii + ROBOT, bounds=(ROBOT, ROBOT, 10 - ROBOT, 10 - ROBOT))
        way = distance_to_goal(passable, *start, *goal, 0.0)
        assert distance_to_goal(lower, *start, *goal, 0.0) < 8.5  # the lower bound goes through either way
        if fits:
            assert exact <= way <= 1.05 * exact
        else:  # no way at all: the column of discs runs from wall to wall
            assert not np.isfinite(exact) and not np.isfinite(way)


def test_the_guide_is_the_lower_bound_among_walls_and_the_passable_field_in_clutter():
    for scenario, passable in (("doorway", False), ("clutter", True)):
        env = gym.make("DynamicObstacle-v0", scenario=scenario)
        obs, _ = env.reset(seed=2)
        memory = {}
        _, first = guiding_cost_to_go(obs, EnvFacts.of(env), memory)
        assert first is memory["cost_to_go"]  # one observation at rest may be a standing start: the lower bound
        _, ctg = guiding_cost_to_go(obs, EnvFacts.of(env), memory)
        assert (ctg is memory["passable"]) is passable and (ctg is memory["cost_to_go"]) is not passable
        if passable:  # the way it reads from the start is the exact static one, to the grid
            u = env.unwrapped
            s = u.scenario
            centres = np.array([o.center for o in s.obstacles])
            reach = np.array([o.radius for o in s.obstacles]) + s.robot_radius
            _, exact = shortest_path(np.array(s.start), np.array(s.goal), centres, reach, bounds=u.arena.robot_box)
            way = distance_to_goal(ctg, *s.start, *s.goal, u.goal_radius)  # to the goal's disc
            assert exact - u.goal_radius <= way <= 1.03 * exact


def test_among_resting_discs_the_passable_field_guides_where_the_lower_bound_reads_close_to_it():
    # 300 cylinders, seed 5010: every way is long, the two fields part on a few cells only, and abc-spacetime,
    # guided by the lower bound, crept toward a gap it opens until the time limit (pso-spacetime too)
    env = gym.make("DynamicObstacle-v0", scenario=clutter_scenario(np.random.default_rng(5010), n_cylinders=300))
    obs, _ = env.reset(seed=5010)
    facts, memory = EnvFacts.of(env), {}
    for _ in range(2):
        _, ctg = guiding_cost_to_go(obs, facts, memory)
    assert misled_share(memory["cost_to_go"], memory["passable"], obs["goal"], facts.goal_radius) < MISLEAD_CELLS
    assert ctg is memory["passable"]
    for name in ("abc-spacetime", "pso-spacetime"):
        info = agents.rollout(agents.make(name, env, seed=0), env, seed=5010)
        assert info["is_success"] and not info["collision"], name


def test_once_humans_walk_the_passable_field_goes_round_the_discs_that_still_rest():
    # clutter-crowd: humans and cylinders rest on the first observation, the humans walk from the second
    for scenario, passable in (("clutter-crowd", True), ("doorway-crowd", False)):
        env = gym.make("DynamicObstacle-v0", scenario=scenario)
        obs, _ = env.reset(seed=1)
        facts, memory = EnvFacts.of(env), {}
        guides = []
        for _ in range(3):
            guides.append(guiding_cost_to_go(obs, facts, memory)[1])
            obs, *_ = env.step(np.zeros(2, np.float32))
        assert guides[0] is not memory.get("passable")  # one observation at rest may be a standing start
        if passable:  # the cylinders alone, not the humans who stood at the start
            assert guides[1] is guides[2] is memory["passable"] and not memory.get("passable_off")
            assert memory["passable_rows"].sum() == len(env.unwrapped.scenario.obstacles) - 4  # the preset's 4 humans
        else:  # walls alone once the humans walk: the lower bound, as before
            assert memory["passable_off"] and guides[2] is memory["cost_to_go"]


def test_astar_spacetime_threads_the_clutter_it_stalled_in():
    # episode 2 of the test split (seed 0): astar-spacetime parked in front of a cylinder until the time limit
    env = gym.make("DynamicObstacle-v0", scenario="clutter")
    info = agents.rollout(agents.make("astar-spacetime", env, seed=1000000002), env, seed=1000000002)
    assert info["is_success"] and not info["collision"]


def test_the_passable_field_round_the_movers_goes_round_a_disc_in_the_gap():
    from agents.planners.passable import passable_around
    from pathplan_env import Scenario
    from pathplan_env.scenarios.scenario import Obstacle

    centres, radii = _gate(2 * ROBOT + 0.05)
    # in the arena, none overlapping the gate's pair: the gaps left by those dropped stay narrower than the robot
    keep = (centres[:, 1] + radii <= 10.0) & ((np.hypot(*(centres[:, None] - centres[None, :2]).transpose(2, 0, 1)) >= 0.6).all(axis=1))
    keep[:2] = True
    centres, radii = centres[keep], radii[keep]
    resting = tuple(Obstacle(center=tuple(c), radius=float(r)) for c, r in zip(centres.tolist(), radii))
    scene = Scenario(bounds=(0, 0, 10, 10), start=(1.0, 5.0), goal=(9.0, 5.0), robot_radius=ROBOT,
                     obstacles=(*resting, Obstacle(center=(2.0, 2.0), radius=0.2, velocity=(0.0, 0.5))))  # fmt: skip
    env = gym.make("DynamicObstacle-v0", scenario=scene, delta_d=None)
    obs, _ = env.reset(seed=0)
    facts = EnvFacts.of(env)
    static = passable_cost_to_go(np.asarray(obs["goal"], float), facts.goal_radius, facts.arena.box, np.zeros((0, 5)), ROBOT,
                                 centres, radii + ROBOT)  # fmt: skip
    through = distance_to_goal(static, 1.0, 5.0, 9.0, 5.0, facts.goal_radius)
    assert passable_around(static, obs, facts, 0.0, np.zeros((0, 2)), np.zeros(0)) is static  # no movers: the field itself
    around = passable_around(static, obs, facts, 0.0, np.array([[5.0, 5.0]]), np.array([0.2]))  # the mover stands in the gap
    assert distance_to_goal(around, 1.0, 5.0, 9.0, 5.0, facts.goal_radius) > through + 1.0
