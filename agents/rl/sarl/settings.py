"""SARL's settings by name: what a model's joint state and reward are in the scenes it was trained for.

``crowdnav``: CrowdNav's circle crossing, CrowdNav's joint state and reward exactly (the shipped
``sarl_crowdnav`` model). ``random``: random scenes whose obstacles bounce off the arena's edges and
off each other; the joint state adds each obstacle's predicted relative position 3 and 6 steps after
the next one (bounce-aware, from the observation alone) and the robot's free distance to the arena's
edges (the robot cannot leave the arena: the env clips its waypoints to the box, so the edges trap
it), with CrowdNav's reward. ``crowdnav-no-robot-velocity`` and ``random-no-robot-velocity``: the same, the robot's own
velocity columns always 0 (it is worth nothing to a holonomic robot the others do not see). ``crowdnav-local-map``:
``crowdnav-no-robot-velocity`` with LM-SARL's local map around every human (``SARLFeatures.local_map``). A model's sidecar names its setting (``args.setting``).
"""

from __future__ import annotations

from typing import NamedTuple

from agents.rl.sarl.lookahead import CROWDNAV_FEATURES, CROWDNAV_REWARD, CrowdNavReward, SARLFeatures, check_features


class SARLSetting(NamedTuple):
    features: SARLFeatures
    reward: CrowdNavReward


SETTINGS = {
    "crowdnav": SARLSetting(CROWDNAV_FEATURES, CROWDNAV_REWARD),
    "crowdnav-no-robot-velocity": SARLSetting(check_features(SARLFeatures(robot_velocity=False)), CROWDNAV_REWARD),
    "crowdnav-local-map": SARLSetting(check_features(SARLFeatures(robot_velocity=False, local_map=True)), CROWDNAV_REWARD),
    "random": SARLSetting(check_features(SARLFeatures(horizons=(3, 6), walls=True)), CROWDNAV_REWARD),
    "random-no-robot-velocity": SARLSetting(check_features(SARLFeatures(horizons=(3, 6), walls=True, robot_velocity=False)), CROWDNAV_REWARD),
}


def get_setting(name: str) -> SARLSetting:
    """The setting called ``name`` (``ValueError`` naming ``setting`` otherwise)."""
    if name not in SETTINGS:
        raise ValueError(f"setting must be one of {sorted(SETTINGS)}, got {name!r}")
    return SETTINGS[name]
