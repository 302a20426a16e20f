"""Learned policies: trained stable-baselines3 models as agents (``policy``), run through a numpy
forward pass (``numpy_policy``) so that evaluation needs no torch. ``agents.rl.training`` trains them
(not imported here; it imports stable-baselines3 and torch only when a run starts). ``sb3_model``
runs any SB3 model file as it comes (no sidecar; VecNormalize's statistics applied)."""

from agents.rl.policy import MODELS_DIR, RLAgent
from agents.rl.sb3_model import SB3Agent, trained_agent

__all__ = ["MODELS_DIR", "RLAgent", "SB3Agent", "trained_agent"]
