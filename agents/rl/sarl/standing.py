"""Planning further when every human stands: value iteration over the robot's positions, SARL's value as the payoff.

SARL's greedy lookahead freezes where its value has a local maximum: behind humans standing at their
goals every move scores below staying, and with nothing moving the next state is the same state
(``docs/results/sarl.md``: every timeout of ``sarl-crossings`` on CrowdNav's square cases). A value
consistent with the Bellman equation could not do that: in a still scene staying forever is worth
nothing. When every human stands, the scene is a static one for as long as they stand and the agent's
model of it is exact, so the agent solves it: value iteration over the robot's positions on a grid
(cells half a step wide over the arena; a move reaches any cell within one step; CrowdNav's reward on
entering a cell, humans and walls both; the goal's cells end it), where each cell may also hand over to
the learned value (optimal stopping: a cell is worth the best of its learned value and its best move).
Each of the 81 moves then scores its exact one-step reward plus the discounted grid value where it ends.
The grid is kept while the humans stay where they were; on CrowdNav's arena (11,664 cells) it takes tens of
milliseconds to build, once per still scene (the acting times' p95 in ``docs/results/sarl.md`` include it).

This is planning in a known static model, not learning: the learned value decides wherever anything
moves, and here only where it beats every way on. The agent searches when the humans stand at two steps
running (at a reset everyone is still, about to walk). Off with ``standing_search=False``.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba
import numpy as np

from agents.base import real_obstacles as real_obstacles  # 0.1.0 public path
from agents.base import real_static_segments as real_static_segments
from agents.observation import Observation
from agents.rl.sarl.lookahead import CROWDNAV_FEATURES, CROWDNAV_REWARD, SELF_VELOCITY, CrowdNavReward, SARLFeatures, joint_state, lookahead, predict_humans
from pathplan_env.facts import EnvFacts
from pathplan_env.geometry.contacts import point_segment_distance

#: Humans slower than this fraction of the robot's speed count as standing.
STANDING_SPEED = 0.05
#: The cached grid is rebuilt when a human has moved this far (m) since it was built.
DRIFT = 0.02
#: Sweeps of value iteration at most (each carries values a step further; it stops early when nothing changes).
SWEEPS = 100
#: Cells at most: a larger arena gets a window round the robot and the goal (4 m beyond both), or round the robot
#: alone; CrowdNav's arena (107 × 107 cells) is whole.
MAX_CELLS = 20_000
#: How close (m) the robot may come to a window's edge inside the arena before the grid is rebuilt round it.
EDGE = 1.0


class StandingGrid(NamedTuple):
    origin: np.ndarray
    """the centre of cell (0, 0)"""
    cell: float
    values: np.ndarray
    """(nx, ny) what a move's end is worth: the best of handing over to the learned value there and moving on"""
    humans: np.ndarray
    """(N, 2) the human positions it was built for"""
    inner: tuple[np.ndarray, np.ndarray]
    """where the robot may be for the grid to hold: the window less ``EDGE`` on each side the arena does not close"""


def all_standing(obs: dict, facts: EnvFacts) -> bool:
    """Whether the observation shows humans and every one moves slower than ``STANDING_SPEED`` × the robot's speed."""
    _, vel, radii = Observation.of(obs).obstacles
    return len(radii) > 0 and float(np.hypot(vel[:, 0], vel[:, 1]).max()) < STANDING_SPEED * facts.robot_speed


@numba.njit(cache=True)
def _sweeps(v0, entry_reward, terminal, offsets, gamma_bar, n_sweeps):
    """Value iteration with the learned value as a stopping payoff: a cell is worth the best of ``v0`` there and
    its best move (the entered cell's reward, plus its discounted worth unless it ends the episode), at most
    ``n_sweeps`` sweeps (fewer when nothing changes)."""
    nx, ny = v0.shape
    v = v0.copy()
    for _ in range(n_sweeps):
        changed = False
        for i in range(nx):
            for j in range(ny):
                if terminal[i, j]:
                    continue
                best = v[i, j]
                for k in range(offsets.shape[0]):
                    a, b = i + offsets[k, 0], j + offsets[k, 1]
                    if a < 0 or b < 0 or a >= nx or b >= ny:
                        continue
                    q = entry_reward[a, b] + (0.0 if terminal[a, b] else gamma_bar * v[a, b])
                    if q > best + 1e-12:
                        best = q
                if best > v[i, j]:
                    v[i, j] = best
                    changed = True
        if not changed:
            break
    return v


def build_grid(obs: dict, facts: EnvFacts, values, gamma_bar: float, reward: CrowdNavReward, features: SARLFeatures,
               sweeps: int = SWEEPS, velocity_features: tuple[float, float] | None = None) -> StandingGrid:  # fmt: skip
    """The grid over the arena's robot box (or a window of it, ``MAX_CELLS``) for the humans standing where ``obs`` shows them."""
    step = facts.robot_speed * facts.dt
    cell = step / 2
    goal = np.asarray(obs["goal"], np.float64)
    robot = np.asarray(obs["robot_position"], np.float64)
    box_lo, box_hi = np.array(facts.arena.robot_box[:2]), np.array(facts.arena.robot_box[2:])
    lo, hi = box_lo, box_hi
    if np.prod((hi - lo) / cell + 1) > MAX_CELLS:  # round the robot and the goal, else round the robot
        lo, hi = np.maximum(np.minimum(robot, goal) - 4.0, box_lo), np.minimum(np.maximum(robot, goal) + 4.0, box_hi)
        if np.prod((hi - lo) / cell + 1) > MAX_CELLS:
            half = 0.5 * cell * (np.sqrt(MAX_CELLS) - 1)
            lo, hi = np.maximum(robot - half, box_lo), np.minimum(robot + half, box_hi)
    nx, ny = int((hi[0] - lo[0]) // cell) + 1, int((hi[1] - lo[1]) // cell) + 1
    xs, ys = lo[0] + cell * np.arange(nx), lo[1] + cell * np.arange(ny)
    points = np.stack(np.meshgrid(xs, ys, indexing="ij"), axis=-1).reshape(-1, 2)
    pos, _, next_pos, next_vel, radii, ahead = predict_humans(obs, facts, features.horizons)
    gap = (np.hypot(*(points[:, None, :] - next_pos[None]).transpose(2, 0, 1)) - radii - facts.robot_radius).min(axis=1)
    walls = Observation.of(obs).covering_walls
    if len(walls):
        to_walls = point_segment_distance(points[:, None, :], walls[None, :, 0:2], walls[None, :, 2:4]) - walls[None, :, 4]
        gap = np.minimum(gap, to_walls.min(axis=1) - facts.robot_radius)
    at_goal = np.hypot(*(points - goal).T) < facts.goal_radius
    entry = np.where(gap < 0, reward.collision, np.where(at_goal, reward.success,
                     np.where(gap < reward.discomfort_dist, (gap - reward.discomfort_dist) * reward.discomfort_factor * facts.dt, 0.0)))  # fmt: skip
    terminal = (gap < 0) | at_goal
    self_state, humans = joint_state(points, np.zeros_like(points), goal, next_pos, next_vel, radii, facts, ahead[:, 1:], features)
    if velocity_features is not None:  # as the lookahead shows the value every move's next state
        self_state[:, SELF_VELOCITY] = velocity_features
    learned = np.asarray(values(self_state, humans, np.ones(humans.shape[:2], np.float32)), np.float64)
    # no state is worth more than arriving now (every other reward is <= 0); a learned value above it, as by
    # the goal, would have the robot circle there for it
    v0 = np.where(terminal, -np.inf, np.minimum(learned, reward.success))
    r = int(math.floor(step / cell + 1e-9))
    offsets = np.array([(a, b) for a in range(-r, r + 1) for b in range(-r, r + 1) if math.hypot(a, b) * cell <= step + 1e-9], np.int64)
    v = _sweeps(v0.reshape(nx, ny), entry.reshape(nx, ny), terminal.reshape(nx, ny), offsets, gamma_bar, sweeps)
    v[terminal.reshape(nx, ny)] = entry[terminal]  # what reaching them is worth, for the interpolation beside them
    inner = (np.where(lo > box_lo, lo + EDGE, -np.inf), np.where(hi < box_hi, hi - EDGE, np.inf))
    return StandingGrid(lo, cell, v, pos, inner)


def grid_value(grid: StandingGrid, points: np.ndarray) -> np.ndarray:
    """The grid's value at ``points`` (M, 2), bilinear between cell centres (a terminal cell holds its reward)."""
    nx, ny = grid.values.shape
    u = np.clip((points - grid.origin) / grid.cell, 0.0, [nx - 1, ny - 1])
    i0 = np.minimum(np.floor(u).astype(np.int64), [nx - 2, ny - 2]).clip(0)
    f = u - i0
    v = grid.values
    i, j = i0[:, 0], i0[:, 1]
    i1, j1 = np.minimum(i + 1, nx - 1), np.minimum(j + 1, ny - 1)
    return (v[i, j] * (1 - f[:, 0]) * (1 - f[:, 1]) + v[i1, j] * f[:, 0] * (1 - f[:, 1]) + v[i, j1] * (1 - f[:, 0]) * f[:, 1]
            + v[i1, j1] * f[:, 0] * f[:, 1])  # fmt: skip


def standing_scores(obs: dict, facts: EnvFacts, velocities: np.ndarray, values, gamma_bar: float, memory: dict,
                    reward: CrowdNavReward = CROWDNAV_REWARD, features: SARLFeatures = CROWDNAV_FEATURES,
                    velocity_features: tuple[float, float] | None = None) -> np.ndarray:  # fmt: skip
    """Every move's score in a standing scene: its one-step reward, plus (if it does not end the episode) the
    discounted grid value where it ends. The grid is cached in ``memory`` while the humans stay put."""
    pos, _, _ = Observation.of(obs).obstacles
    grid = memory.get("standing_grid")
    robot = np.asarray(obs["robot_position"], np.float64)
    stale = (grid is None or grid.humans.shape != pos.shape or np.abs(grid.humans - pos).max() > DRIFT
             or np.any(robot < grid.inner[0]) or np.any(robot > grid.inner[1]))  # fmt: skip
    if stale:
        grid = memory["standing_grid"] = build_grid(obs, facts, values, gamma_bar, reward, features, velocity_features=velocity_features)
    _, _, rewards = lookahead(obs, facts, velocities, reward, features)
    xmin, ymin, xmax, ymax = facts.arena.robot_box
    ends = np.clip(robot + np.asarray(velocities) * facts.dt, [xmin, ymin], [xmax, ymax])
    terminal = (rewards <= reward.collision) | (rewards >= reward.success)
    return np.where(terminal, rewards, rewards + gamma_bar * grid_value(grid, ends))
