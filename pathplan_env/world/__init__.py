"""The simulated world: pymunk's space (``space``, driven through ``chipmunk``), the step (``simulation.World``),
its substeps (how many: ``substep_count``; the arithmetic of one: ``substep_kernels``)."""

# the names of pathplan_env.world in 0.1.0, when it was one module, from their homes

from pathplan_env.crowds.routing import drivers_statics
from pathplan_env.geometry.contacts import NO_CONTACT
from pathplan_env.geometry.walls import capsules_clearance, static_stop
from pathplan_env.scenarios.scenario import Scenario
from pathplan_env.world.chipmunk import BatchBuffer
from pathplan_env.world.simulation import World
from pathplan_env.world.space import SpaceKeeper
from pathplan_env.world.substep_count import MAX_SUBSTEP_DISPLACEMENT, MAX_SUBSTEPS, SUBSTEP_SLACK, scenario_substeps, substeps_for
from pathplan_env.world.substep_kernels import SPEED_TOLERANCE, restore_speeds

__all__ = [
    "BatchBuffer", "MAX_SUBSTEPS", "MAX_SUBSTEP_DISPLACEMENT", "NO_CONTACT", "SPEED_TOLERANCE", "SUBSTEP_SLACK", "Scenario", "SpaceKeeper",
    "World", "capsules_clearance", "drivers_statics", "restore_speeds", "scenario_substeps", "static_stop", "substeps_for",
]  # fmt: skip
