"""Reactive policies that choose a velocity from the current observation: straight at the goal,
velocity obstacles, and ORCA (CrowdNav's baseline)."""

from agents.reactive.classical import StraightAgent, VelocityObstacleAgent
from agents.reactive.orca import ORCAAgent

__all__ = ["ORCAAgent", "StraightAgent", "VelocityObstacleAgent"]
