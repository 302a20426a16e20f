"""The planners the limit knows, flown on a copy of the episode: where its own search is left undetermined. PRIVILEGED.

``oracle-clairvoyant`` searches a grid of positions and a fixed set of moves. Where every search and its
receding scheme fail without a proof that the episode is lost (cornered: no move on their grid is free;
or the episode's steps run out short of the goal), a planner that moves otherwise may still get through
(issue 46: in a clutter world with bouncing discs the limit was cornered and collided where
``astar-spacetime``, ``pso-spacetime`` and ``abc-spacetime`` reached the goal). So the limit keeps
searching where planners have won: :func:`fly` runs one registered planner, with its default settings and
the episode's seed, on a copy of the env from its current state, as the harness would run it from there.

Exact: ``copy.deepcopy`` of a ``DynamicObstacleEnv`` continues its episode bit for bit under the same
actions (``tests/env/test_contract.py``), so the actions recorded on the copy, replayed on the env, fly
the same steps: an arrival without contact on the copy is an arrival without contact in the episode, a
plan proved by its flight. Privileged: the copy is the simulator itself; the planners flown in it read
only their observations.
"""

from __future__ import annotations

import copy
from typing import NamedTuple

import numpy as np

from agents.observation import Observation
from agents.registry import make

#: The planners the holonomic limit flies where it is left undetermined, in the order it tries them.
PLANNERS = ("astar-spacetime", "pso-spacetime", "abc-spacetime")
#: The unicycle's: its own planners over its moves and controls.
UNICYCLE_PLANNERS = ("astar-unicycle", "pso-unicycle", "abc-unicycle")


class Flight(NamedTuple):
    """One planner's flight on a copy of the env, from the state the copy was made in."""

    name: str
    actions: np.ndarray  # (k, action size): every action it sent, as the env received it
    positions: np.ndarray  # (k, 2): the robot's position after each
    arrived: bool  # reached the goal without contact
    collided: bool

    @property
    def free_steps(self) -> int:
        """Steps flown without contact (the last one touched when it collided)."""
        return len(self.actions) - int(self.collided)

    @property
    def outcome(self) -> str:
        return "success" if self.arrived else "collision" if self.collided else "timeout"


def fly(name: str, env, simulator, observation, seed: int | None, remaining: int) -> Flight:
    """Fly the registered agent ``name`` (built for ``env``, seeded with ``seed``) on a copy of
    ``simulator`` (the ``DynamicObstacleEnv`` under ``env``), from ``observation`` (the env's current
    one), until it arrives, touches something, the scenario's time limit ends it or ``remaining`` steps
    have passed. The env itself is not stepped."""
    twin = copy.deepcopy(simulator)
    planner = make(name, env, seed=seed)
    planner.reset()
    obs = observation.raw if isinstance(observation, Observation) else observation
    actions, positions, state, info = [], [], None, {"is_success": False, "collision": False}
    for step in range(remaining):
        action, state = planner.predict(obs, state, np.array([step == 0]))
        action = np.array(action, copy=True)
        obs, _, terminated, truncated, info = twin.step(action)
        actions.append(action)
        positions.append(np.array(twin.world.robot_xy, np.float64))
        if terminated or truncated:
            break
    size = np.shape(env.action_space)
    return Flight(name, np.array(actions, np.float32).reshape(-1, *size), np.array(positions, np.float64).reshape(-1, 2),
                  bool(info["is_success"]), bool(info["collision"]))  # fmt: skip


def best_flight(names, env, simulator, observation, seed: int | None, remaining: int, free_steps: int) -> tuple[Flight | None, dict]:
    """The first of ``names`` whose flight arrives without contact, else the one that flies the most
    steps without contact if that is more than ``free_steps`` (what the caller's own flight is known to
    fly free), else ``None``; and every flight's ``(outcome, steps)`` by name. Stops at the first arrival."""
    best, tried = None, {}
    for name in names:
        flight = fly(name, env, simulator, observation, seed, remaining)
        tried[name] = (flight.outcome, len(flight.actions))
        if flight.arrived:
            return flight, tried
        if flight.free_steps > (free_steps if best is None else best.free_steps):
            best = flight
    return best, tried


__all__ = ["PLANNERS", "UNICYCLE_PLANNERS", "Flight", "best_flight", "fly"]
