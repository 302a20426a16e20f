"""The harness's record types: one evaluated episode, the name of the agent that gives each cell its
limit, and how a scenario's own speeds are named. Imports nothing else of the harness, so every part
of it can import this."""

from __future__ import annotations

from dataclasses import dataclass, field

#: The privileged agent whose success rate on a cell's episodes is that cell's physical limit.
LIMIT_AGENT = "oracle-clairvoyant"
#: A cell's Δd of ``None``: the scenario's obstacles at their own speeds, written so on the command line and in tables.
OWN_SPEEDS = "own"


def delta_text(delta_d: float | None) -> str:
    return OWN_SPEEDS if delta_d is None else f"{delta_d:g}"


def delta_order(delta_d: float | None) -> tuple:
    """A sort key for Δd values: a scenario's own speeds first, then the numbers."""
    return (0, 0.0) if delta_d is None else (1, delta_d)


@dataclass
class EpisodeResult:
    agent: str  # the agent's label (agents.evaluation.entrants)
    scenario: str  # the scenario's label: a preset's name, a Scenario's name, a file's stem
    delta_d: float | None  # None: the scenario's own speeds
    episode: int
    seed: int
    success: bool
    collision: bool
    timeout: bool
    steps: int
    path_length: float
    shortest_path: float  # exact static shortest path from start to the goal's centre (m)
    path_length_ratio: float
    time_to_goal: float
    min_clearance: float
    plan_ms: list[float] = field(repr=False)
    verdict: str = ""  # the clairvoyant oracle's: plan, lost, undetermined, or reactive (no limit)
    # CrowdNav's discomfort: steps (before the last) whose clearance fell below DISCOMFORT_DISTANCE
    discomfort_steps: int = 0
    discomfort_clearance_sum: float = 0.0  # of those steps' smallest clearances (m)
    seconds: float = 0.0  # the episode's wall time, after the agent's warm-up (what the progress estimate reads)
    scene: str = ""  # a digest of the episode's initial scene (scene_digest): the same scene, the same digest


def scene_digest(scenario) -> str:
    """A short digest of a scene's initial state (start, goal, obstacles, walls): two episodes with the
    same digest started from the same scene."""
    import hashlib

    import numpy as np

    arrays = scenario.arrays()
    parts = [np.asarray(scenario.start + scenario.goal, np.float64), arrays["positions"], arrays["velocities"], arrays["radii"],
             np.asarray(scenario.static_segments, np.float64)]  # fmt: skip
    return hashlib.sha1(b"".join(np.ascontiguousarray(p).tobytes() for p in parts)).hexdigest()[:16]
