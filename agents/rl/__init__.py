"""Learned policies: trained stable-baselines3 models as agents (``policy``), run through a numpy
forward pass (``numpy_policy``) so that evaluation needs no torch."""

from .policy import MODELS_DIR, RLAgent

__all__ = ["MODELS_DIR", "RLAgent"]
