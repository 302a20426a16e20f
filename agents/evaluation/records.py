"""The harness's record types: one evaluated episode, and the name of the agent that gives each
cell its limit. Imports nothing else of the harness, so every part of it can import this."""

from __future__ import annotations

from dataclasses import dataclass, field

#: The privileged agent whose success rate on a cell's episodes is that cell's physical limit.
LIMIT_AGENT = "oracle-clairvoyant"


@dataclass
class EpisodeResult:
    agent: str
    scenario: str
    delta_d: float
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
