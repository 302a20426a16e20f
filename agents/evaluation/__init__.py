"""The evaluation harness: every agent on the same test episodes, each cell beside its physical limit.

``evaluate`` runs a set of cells and writes the results (``harness``), made as its ``settings``
record says (``settings``); ``entrants`` turns the agents and scenarios a user gives (names, classes, objects with ``predict``, ``module:attribute``, scenario
objects and files) into labelled specs the workers can receive; one episode is
``episodes.run_episode``, run by the local pool (``executors``) or Ray (``ray_backend``);
``statistics`` summarises, ``reporting`` prints and plots, ``run_diff`` compares two runs.
``records`` holds the types all of them share and imports none of them.
"""

from agents.evaluation.entrants import AgentSpec, ScenarioSpec, resolve_agents, resolve_scenarios
from agents.evaluation.episodes import run_episode
from agents.evaluation.harness import evaluate
from agents.evaluation.records import LIMIT_AGENT, EpisodeResult
from agents.evaluation.settings import EvaluationSettings
from agents.evaluation.suites import SUITES

__all__ = [
    "LIMIT_AGENT", "SUITES", "AgentSpec", "EpisodeResult", "EvaluationSettings", "ScenarioSpec",
    "evaluate", "resolve_agents", "resolve_scenarios", "run_episode",
]  # fmt: skip
