"""Learned policies: trained stable-baselines3 models as agents (``policy``), run through a numpy
forward pass (``numpy_policy``) so that evaluation needs no torch. ``agents.rl.training`` trains them
(not imported here; it imports stable-baselines3 and torch only when a run starts)."""

from .policy import MODELS_DIR, RLAgent

__all__ = ["MODELS_DIR", "RLAgent"]
