"""The crowd scenes built twice: in our world and in navground (PyPI ``navground``, a C++ core), the
fastest peer that simulates ORCA crowds, from the same lists of starts, goals, radii and speeds, to
compare the two step for step (``scripts/bench_crowds.py``).

The scenes: CrowdNav's circle crossing drawn by our rule (``scenarios.crowdnav``) at dt 0.1 s, and
``corridor-crowd``. Both simulators run ORCA with neighbour distance 10 m, 10 neighbours, 5 s
horizons (agents and walls) and CrowdNav's 1 cm radius padding; navground's agents have ``Omni``
kinematics at their preferred speed and ``Bounded`` state estimation of range 10 m (its neighbour
distance), and see the walls as the line segments of our RVO2 obstacle outlines. Our humans also
route around walls (``crowds.routing``); navground's head straight for their goals.

navground is optional (the ``crowds-bench`` extra): it is imported when a navground world is built.
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Callable

import numpy as np

from pathplan_env.crowds.routing import orca_obstacles
from pathplan_env.scenarios.crowd_families import corridor_crowd
from pathplan_env.scenarios.crowdnav import crowdnav_scenario
from pathplan_env.scenarios.scenario import Scenario

#: The control period of the comparison (s): navground's and the crowd families' 0.1 s.
DT = 0.1
#: ORCA's parameters in both simulators (CrowdNav's): neighbour distance (m, navground's ``Bounded``
#: range), neighbours, time horizon for agents and for walls (s), radius padding (m).
NEIGHBOR_DIST, MAX_NEIGHBORS, TIME_HORIZON, RADIUS_PADDING = 10.0, 10, 5.0, 0.01
#: Crowd sizes of the circle crossing.
CROWD_SIZES = (2, 5, 10, 15, 20)
#: Humans in the corridor.
CORRIDOR_HUMANS = 20


def crowd_scene(kind: str, n: int, seed: int = 0) -> Scenario:
    """``kind`` ``"circle"`` (CrowdNav's circle crossing at dt 0.1 s) or ``"corridor"`` (``corridor-crowd``
    at its own speeds) with ``n`` humans, drawn from ``seed``.

    :raises ValueError: naming ``kind`` when it is neither.
    """
    rng = np.random.default_rng(seed)
    if kind == "circle":
        return dataclasses.replace(crowdnav_scenario("circle-crossing", rng, n), dt=DT)
    if kind == "corridor":
        return corridor_crowd(rng, n)
    raise ValueError(f"kind must be 'circle' or 'corridor', got {kind!r}")


def navground_world(scenario: Scenario):
    """``scenario``'s humans and walls as a ``navground.sim.World`` (the robot is not in it: it is
    invisible to our humans)."""
    import navground.core as core
    import navground.sim as sim

    world = sim.World()
    obstacles = orca_obstacles(scenario) if len(scenario.static_segments) else None
    if obstacles is not None:
        for i, j in enumerate(obstacles.next.tolist()):
            two_vertex_line = obstacles.next[j] == i  # a line: its two edges are one wall
            if not two_vertex_line or i < j:
                world.add_wall(sim.Wall(obstacles.point[i], obstacles.point[j]))
    for ob in scenario.obstacles:
        behavior = core.behaviors.ORCABehavior()
        behavior.time_horizon = behavior.static_time_horizon = TIME_HORIZON
        behavior.max_number_of_neighbors = MAX_NEIGHBORS
        behavior.safety_margin = RADIUS_PADDING
        behavior.optimal_speed = ob.preferred_speed
        agent = sim.Agent(
            radius=ob.radius, behavior=behavior, kinematics=core.kinematics.OmnidirectionalKinematics(ob.preferred_speed),
            task=sim.tasks.WaypointsTask([ob.goal], False, 0.01),
            state_estimations=[sim.state_estimations.BoundedStateEstimation(range=NEIGHBOR_DIST)], control_period=scenario.dt,
        )  # fmt: skip
        agent.position = ob.center
        world.add_agent(agent)
    return world


def navground_positions(world) -> np.ndarray:
    """(N, 2) agent positions of a navground world (float64 copies of its float32 state)."""
    return np.array([agent.position for agent in world.agents], np.float64).reshape(-1, 2)


def agreement(scenario: Scenario, seconds: float = 1.0, goal_seconds: float = 20.0) -> dict:
    """How far the two simulators agree on ``scenario``: the largest distance between a human's
    position in ours and in navground's after ``seconds`` (m), and each one's share of humans
    within a radius of their goals after ``goal_seconds``."""
    from pathplan_env.world.simulation import World

    ours, peer = World(scenario), navground_world(scenario)
    goals = np.array([ob.goal for ob in scenario.obstacles])
    radii = np.array([ob.radius for ob in scenario.obstacles])
    deviation = math.nan
    steps_1, steps_goal = round(seconds / scenario.dt), round(goal_seconds / scenario.dt)
    for k in range(1, max(steps_1, steps_goal) + 1):
        ours.step(0.0, 0.0)
        peer.update(scenario.dt)
        if k == steps_1:
            deviation = float(np.hypot(*(ours.obstacle_state[:, :2] - navground_positions(peer)).T).max())
    at_goal = lambda xy: float(np.mean(np.hypot(*(xy - goals).T) <= radii))
    return {"deviation": deviation, "ours_at_goal": at_goal(ours.obstacle_state[:, :2]), "navground_at_goal": at_goal(navground_positions(peer))}


def cpu_seconds(step: Callable[[], object], steps: int) -> float:
    """Process CPU time of ``steps`` calls of ``step`` (s)."""
    start = time.process_time()
    for _ in range(steps):
        step()
    return time.process_time() - start


def paired_ratio(make_ours: Callable[[], Callable], make_peer: Callable[[], Callable], steps: int, repeats: int) -> tuple[float, float, float]:
    """``(median ratio, our µs a step, navground's µs a step)``: each repeat builds both anew
    (``make_*`` return a step function), times ``steps`` steps of each in process CPU time, ours
    first on even repeats and navground first on odd ones; the ratio is our step time ÷ navground's
    (> 1: navground is faster). One warm-up round is not counted."""
    ratios, ours_us, peer_us = [], [], []
    for repeat in range(-1, repeats):
        order = (make_ours, make_peer) if repeat % 2 == 0 else (make_peer, make_ours)
        times = {}
        for make in order:
            times[make] = cpu_seconds(make(), steps)
        if repeat < 0:
            continue
        ratios.append(times[make_ours] / times[make_peer])
        ours_us.append(1e6 * times[make_ours] / steps)
        peer_us.append(1e6 * times[make_peer] / steps)
    return float(np.median(ratios)), float(np.median(ours_us)), float(np.median(peer_us))


def world_stepper(scenario: Scenario) -> Callable:
    """A fresh world of ``scenario`` and its step, the robot holding still."""
    from pathplan_env.world.simulation import World

    world = World(scenario)
    return lambda: world.step(0.0, 0.0)


def navground_stepper(scenario: Scenario) -> Callable:
    """A fresh navground world of ``scenario`` and its step (one ``World.update(dt)`` call)."""
    world = navground_world(scenario)
    dt = scenario.dt
    return lambda: world.update(dt)


def step_split(scenario: Scenario, steps: int = 100, worlds: int = 200) -> dict:
    """What one ``World.step`` of ``scenario`` is made of (µs a step, process CPU time over ``steps``
    steps of each of ``worlds`` fresh worlds, their building left out): the whole step; the compiled
    step called directly (its Python wrapper left out); a call of a compiled function that does
    nothing with the same eight arguments (the boundary's cost); ``cpSpaceStep`` of the same space
    through cffi (Chipmunk's step, a cffi call included)."""
    from pathplan_env.world import simulation
    from pathplan_env.world.chipmunk import space_step
    from pathplan_env.world.simulation import World

    boundary = _nothing_entry()

    def parts(world):
        _world_step = simulation._world_step  # (compiled by the first World)
        args = (world._address, *world.robot_xy, 0.0, 0.0, 2.0, False, scenario.arena_diagonal)
        space, dt = world.space._space, scenario.dt
        return {
            "World.step": lambda: world.step(0.0, 0.0),
            "compiled step": lambda: _world_step(*args),
            "call boundary": lambda: boundary(*args),
            "cpSpaceStep": lambda: space_step(space, dt),
        }

    totals = dict.fromkeys(parts(World(scenario)), 0.0)
    for _ in range(worlds):
        for name in totals:
            world = World(scenario)  # (kept here: the compiled step reads its space through raw addresses)
            totals[name] += cpu_seconds(parts(world)[name], steps)
    return {name: 1e6 * total / (worlds * steps) for name, total in totals.items()}


def _nothing_entry():
    """A compiled function of ``world_step``'s signature that returns at once (its entry point)."""
    import numba
    from numba import types

    @numba.njit
    def nothing(address, x0, y0, dx, dy, goal_fraction, static_contact, min_gap):
        return (x0, y0), (dx, dy), min_gap, goal_fraction

    signature = (types.int64, *[types.float64] * 5, types.boolean, types.float64)
    nothing.compile(signature)
    return nothing.overloads[signature].entry_point
