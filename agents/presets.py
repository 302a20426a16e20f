"""The named presets: each a family with parameters (the names of 0.1.0, kept for every committed
run, label and ``--resume`` key). ``agents.presets()`` lists them; ``docs/agents.md`` shows them
(``scripts/agent_tables.py`` writes it from the registry)."""

from __future__ import annotations

from agents.registry import register_preset

TRACKED = ("astar-spacetime", "astar-crowd", "pso-spacetime", "abc-spacetime", "pso", "abc", "velocity-obstacle", "orca",
           "oracle-static", "straight")  # fmt: skip

#: name -> (family, parameters, note): the parameters a preset sets; every other is the family's default.
PRESETS: dict[str, tuple[str, dict, str]] = {
    "straight": ("straight", {}, ""),
    "velocity-obstacle": ("velocity-obstacle", {}, ""),
    "orca": ("orca", {}, ""),
    "dwa": ("dwa", {}, ""),
    "dwa-lidar": ("dwa", {"sensor": "lidar"}, "reads the lidar's scan (observation='lidar'), its returns as still points"),
    "oracle-static": ("oracle-static", {}, ""),
    "oracle-clairvoyant": ("oracle-clairvoyant", {}, "privileged: reads the simulator; the harness's limit"),
    "sb3": ("sb3", {}, "path= required"),
    "pso": ("pso", {"plan": "waypoint"}, "the paper's adaptive constraint PSO"),
    "abc": ("abc", {"plan": "waypoint"}, "the paper's modified ABC"),
    "pso-vanilla": ("pso", {"plan": "waypoint", "variant": "vanilla"}, "ablation: constant inertia"),
    "abc-vanilla": ("abc", {"plan": "waypoint", "variant": "vanilla"}, "ablation: the original ABC"),
    "pso-predictive": ("pso", {"plan": "waypoint", "prediction": "constant-velocity"}, "the paper's objective in space-time"),
    "abc-predictive": ("abc", {"plan": "waypoint", "prediction": "constant-velocity"}, "the paper's objective in space-time"),
    "pso-spacetime": ("pso", {"plan": "spacetime"}, "a timed path over 10 steps on the physics' prediction"),
    "abc-spacetime": ("abc", {"plan": "spacetime"}, "a timed path over 10 steps on the physics' prediction"),
    "pso-crowd": ("pso", {"plan": "spacetime", "tuning": "crowd"}, "for crowds among walls"),
    "abc-crowd": ("abc", {"plan": "spacetime", "tuning": "crowd"}, "for crowds among walls"),
    "astar-spacetime": ("astar", {"plan": "spacetime"}, "A* over (step, position), a 20-step horizon"),
    "astar-crowd": ("astar", {"plan": "spacetime", "tuning": "crowd"}, "for crowds that steer"),
    "astar-unicycle": ("astar", {"plan": "controls"}, "A* over the unicycle's own moves"),
    "astar-unicycle-crowd": ("astar", {"plan": "controls", "tuning": "crowd"}, "for crowds that steer"),
    "pso-unicycle": ("pso", {"plan": "controls"}, "the unicycle's (v, ω) controls"),
    "abc-unicycle": ("abc", {"plan": "controls"}, "the unicycle's (v, ω) controls"),
    "pso-unicycle-crowd": ("pso", {"plan": "controls", "tuning": "crowd"}, "for crowds that steer"),
    "abc-unicycle-crowd": ("abc", {"plan": "controls", "tuning": "crowd"}, "for crowds that steer"),
    "ppo": ("ppo", {"observation": "state"}, "the shipped PPO (agents/models/ppo.*)"),
    "ppo-lidar": ("ppo", {"observation": "lidar"}, "the shipped lidar PPO (observation='lidar')"),
    "ppo-set": ("ppo", {"observation": "set"}, "the shipped set-encoder PPO"),
    "ppo-multi": ("ppo", {"observation": "state", "model": "ppo_multi"}, "one policy for every robot, trained on multi-circle-4 (agents/models/ppo_multi.*)"),
    "sarl": ("sarl", {}, "trained on CrowdNav's circle crossing (sarl_crowdnav)"),
    "sarl-random": ("sarl", {"model": "sarl_random"}, "trained on random scenes, bouncing obstacles"),
    "sarl-crossings": ("sarl", {"model": "sarl_crowdnav_crossings"}, "trained on CrowdNav's circle and square crossings"),
    "tracked": ("tracked", {}, "planner= any waypoint planner (default astar-spacetime)"),
}


def register_presets() -> None:
    """Register :data:`PRESETS` and ``tracked-<planner>`` for each of :data:`TRACKED` (``import agents`` does)."""
    for name, (family, parameters, note) in PRESETS.items():
        register_preset(name, family, note, **parameters)
    for planner in TRACKED:
        family, parameters, _ = PRESETS[planner]
        register_preset(f"tracked-{planner}", family, f"{planner} driven by pure pursuit", **parameters, drive="pure-pursuit")
