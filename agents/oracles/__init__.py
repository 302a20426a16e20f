"""Oracles: references, not deployable policies. ``static`` plans the exact shortest path among the
obstacles as they stand; ``clairvoyant`` is PRIVILEGED: it reads the simulator to give each episode
its physical limit."""

from agents.oracles.clairvoyant import ClairvoyantOracle
from agents.oracles.static import StaticOracleAgent

__all__ = ["ClairvoyantOracle", "StaticOracleAgent"]
