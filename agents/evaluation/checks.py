"""A run's arguments checked before anything is written: a typo must not cost a recorded run."""

from __future__ import annotations

import math

import numpy as np

def check_run(agent_names, scenarios, deltas, episodes, *, seed=0, split="test", n_obstacles=None, workers=1) -> None:
    """Refuse a run that could not finish, naming the argument, before anything is written: an
    unknown agent or preset, a bad count, and any scene the env would reject (every scenario and Δd
    is built once, at the run's first episode seed)."""
    import gymnasium as gym

    import agents
    import pathplan_env
    from pathplan_env.splits import heldout_seeds, validation_seeds

    def whole(value, name, minimum):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
            raise ValueError(f"{name} must be an integer >= {minimum}, got {value!r}")

    for name, values in (("agent_names", agent_names), ("scenarios", scenarios), ("deltas", deltas)):
        if isinstance(values, str) or not len(values):
            raise ValueError(f"{name} must be a non-empty list, got {values!r}")
    unknown = [a for a in agent_names if a not in agents.available()]
    if unknown:
        raise ValueError(f"agent_names: unknown {unknown}; available: {agents.available()}")
    unknown = [s for s in scenarios if s not in pathplan_env.PRESETS]
    if unknown:
        raise ValueError(f"scenarios: unknown {unknown}; presets: {sorted(pathplan_env.PRESETS)}")
    if any(isinstance(d, bool) or not isinstance(d, (int, float, np.number)) or not math.isfinite(d) or d < 0 for d in deltas):
        raise ValueError(f"deltas: values must be finite numbers >= 0, got {list(deltas)}")
    whole(episodes, "episodes", 1)
    whole(seed, "seed", 0)
    whole(workers, "workers", 1)
    if split not in ("test", "validation"):
        raise ValueError(f"split must be 'test' or 'validation', got {split!r}")
    first_seed = (heldout_seeds if split == "test" else validation_seeds)(seed, 1)[0]
    for scenario in scenarios:
        for delta_d in deltas:
            try:
                gym.make("DynamicObstacle-v0", scenario=scenario, delta_d=float(delta_d), n_obstacles=n_obstacles).reset(seed=first_seed)
            except ValueError as error:
                raise ValueError(f"scenario {scenario!r} at delta_d {delta_d}: {error}") from None


def resolve_agent_kwargs(agent_names: list[str], agent_kwargs: dict) -> dict[str, dict]:
    """Per-agent overrides from either form, checked by building each agent once (before any work).

    ``{"n_waypoints": 3}`` goes to every agent; ``{"pso": {"n_waypoints": 3}}`` to ``pso`` only.
    :raises ValueError: naming the agent and the argument it does not take.
    """
    import gymnasium as gym

    import agents

    if not isinstance(agent_kwargs, dict):
        raise ValueError(f"agent kwargs must be a JSON object, got {agent_kwargs!r}")
    per_agent = bool(agent_kwargs) and all(isinstance(v, dict) for v in agent_kwargs.values())
    if per_agent:
        unknown = sorted(set(agent_kwargs) - set(agent_names))
        if unknown:
            raise ValueError(f"agent kwargs for agents not in the run: {unknown}")
        own = {name: dict(agent_kwargs.get(name, {})) for name in agent_names}
    else:
        own = {name: dict(agent_kwargs) for name in agent_names}
    env = gym.make("DynamicObstacle-v0")
    for name, kwargs in own.items():
        if kwargs:
            try:
                agents.make(name, env, seed=0, **kwargs)
            except TypeError as error:
                raise ValueError(f"agent {name!r} does not take {sorted(kwargs)}: {error}") from None
    return own
