"""Physics substeps per step: sized from the obstacles' speeds and radii (scale-free), bounded."""

from __future__ import annotations

import math

import numpy as np

from pathplan_env.scenarios.scenario import Scenario

#: Largest obstacle displacement per substep, in units of the smallest obstacle radius. Keeps
#: Chipmunk's discrete collision detection from missing obstacle-obstacle and obstacle-wall
#: contacts; robot contacts are exact at any substep size.
MAX_SUBSTEP_DISPLACEMENT = 0.5
#: Most substeps a step may take. A scene past it (an obstacle much faster than the smallest one is
#: large) is rejected with a ``ValueError`` rather than simulated for seconds a step.
MAX_SUBSTEPS = 200
#: Relative slack of the substep rule: far above float32's rounding, far below any physical effect.
SUBSTEP_SLACK = 1e-6


def substeps_for(speeds: np.ndarray, radii: np.ndarray, dt: float) -> int:
    """Substeps per step: the fastest obstacle moves at most ``MAX_SUBSTEP_DISPLACEMENT`` of the
    smallest radius in one (scale-free: only the ratio of displacement to radius counts).

    :raises ValueError: when more than ``MAX_SUBSTEPS`` would be needed.
    """
    if len(radii) == 0:
        return 1
    ratio = max(speeds.tolist()) * dt / min(radii.tolist())  # Python's max: numpy 2's reductions cost more on a few rows
    # the relative slack keeps round Δd values (ratio 2.0000000000000004 in float64, 2.0000001 from
    # float32 observations) on one side of the ceiling, so planners derive the env's count
    needed = max(1, math.ceil(ratio / MAX_SUBSTEP_DISPLACEMENT * (1.0 - SUBSTEP_SLACK)))
    if needed > MAX_SUBSTEPS:
        raise ValueError(
            f"Scenario.obstacles: the fastest obstacle moves {ratio:.3g} radii of the smallest one per step, which needs "
            f"{needed} physics substeps (at most {MAX_SUBSTEPS}); lower delta_d or make the radii more alike"
        )
    return needed


def scenario_substeps(scenario: Scenario) -> int:
    """:func:`substeps_for` a scenario's fastest obstacles (what ``World`` takes), without building it.

    :raises ValueError: when more than ``MAX_SUBSTEPS`` would be needed.
    """
    return substeps_for(scenario.top_speeds(), scenario.arrays()["radii"], scenario.dt)
