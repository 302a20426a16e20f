"""A run's arguments checked before anything is written: a typo must not cost a recorded run."""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field

import numpy as np

from agents.evaluation.entrants import AgentSpec, ScenarioSpec, resolve_agents, resolve_scenarios
from agents.evaluation.records import OWN_SPEEDS, delta_text

#: ``gym.make`` keywords the run sets itself (its scenarios, Δd and counts), and ``render_mode`` (episodes are not drawn).
RUN_OWN_ENV_KEYWORDS = ("scenario", "delta_d", "n_obstacles", "render_mode")


@dataclass
class CheckedRun:
    """What ``check_run`` found valid: the specs, the Δd values (``None``: the scenario's own speeds),
    each agent's keyword arguments, by label, and the env options of every episode."""

    agents: list[AgentSpec]
    scenarios: list[ScenarioSpec]
    deltas: list[float | None]
    overrides: dict[str, dict]
    env_options: dict = field(default_factory=dict)


def resolve_deltas(deltas, argument: str = "deltas") -> list[float | None]:
    """Numbers >= 0, or ``None``/``"own"`` for the scenario's own speeds; no value twice (its episodes would merge)."""
    if isinstance(deltas, str) or not hasattr(deltas, "__len__") or not len(deltas):
        raise ValueError(f"{argument} must be a non-empty list, got {deltas!r}")
    out = []
    for d in deltas:
        if d is None or (isinstance(d, str) and d.strip().lower() == OWN_SPEEDS):
            out.append(None)
        elif isinstance(d, bool) or not isinstance(d, (int, float, np.number)) or not math.isfinite(d) or d < 0:
            raise ValueError(f"{argument}: values must be finite numbers >= 0 or {OWN_SPEEDS!r} (the scenario's own speeds), got {list(deltas)}")
        else:
            out.append(float(d))
    if len(set(out)) < len(out):
        raise ValueError(f"{argument}: a value given more than once, {list(deltas)} (its episodes would merge into one cell)")
    return out


def resolve_env_options(env_options, split: str = "test") -> dict:
    """``gym.make`` keywords for every episode's env (e.g. ``{"observation": "state"}``), as plain JSON
    (``summary.json`` records them and ``--resume`` keys on them). Unknown keywords and bad values are
    the env's to refuse: :func:`check_run` builds every cell with them."""
    if env_options is None:
        return {}
    if not isinstance(env_options, dict) or not all(isinstance(k, str) for k in env_options):
        raise ValueError(f"env_options must be a dict of gym.make keyword arguments, got {env_options!r}")
    own = sorted(set(env_options) & set(RUN_OWN_ENV_KEYWORDS))
    if own:
        raise ValueError(f"env_options: {own} are the run's own (its scenarios, delta_d, n_obstacles; episodes are not rendered)")
    from pathplan_env.scenarios.episode_sources import source_of

    for key, why in source_of(split).own_env_options.items():
        if key in env_options:
            raise ValueError(f"env_options: {key} is not taken on split {split!r}; {why}")
    try:
        plain = json.loads(json.dumps(env_options, allow_nan=False))
    except (TypeError, ValueError) as error:
        raise ValueError(f"env_options must be plain JSON values (summary.json records them): {error}") from None
    if plain != env_options:  # e.g. a tuple would reach the env as a list on resume
        raise ValueError(f"env_options must be plain JSON values (dicts, lists, str, numbers, bools, None), got {env_options!r}")
    return plain


def _check_split(split: str, scenario_specs: list[ScenarioSpec], episodes: int) -> None:
    from pathplan_env.scenarios.episode_sources import source_of

    source = source_of(split)
    others = [s.label for s in scenario_specs if not source.takes(s.scenario)]
    if others:
        raise ValueError(f"split {split!r} (its own scenes) takes only the presets {sorted(source.presets)}; not {others}")
    source.episode_seeds(0, episodes)  # the split's own bound (crowdnav: 500 cases)


def check_run(agent_names, scenarios, deltas, episodes, *, seed=0, split="test", n_obstacles=None, workers=1,
              agent_kwargs=None, transport: str | None = None, env_options=None) -> CheckedRun:  # fmt: skip
    """Refuse a run that could not finish, naming the argument, before anything is written: an agent
    or scenario that cannot be resolved or built, a label given twice, a bad count, and any scene the
    env would reject (every scenario and Δd is built once, at the run's first episode seed), with
    ``env_options`` too (the env's own error for a bad option).

    ``transport`` is how jobs reach the workers (:func:`entrants.resolve_agents`)."""
    from agents.evaluation.episodes import make_episode_env
    from pathplan_env.scenarios.splits import episode_seeds

    def whole(value, name, minimum):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
            raise ValueError(f"{name} must be an integer >= {minimum}, got {value!r}")

    agents = resolve_agents(agent_names, argument="agent_names", transport=transport)
    scenario_specs = resolve_scenarios(scenarios, argument="scenarios")
    deltas = resolve_deltas(deltas)
    whole(episodes, "episodes", 1)
    whole(seed, "seed", 0)
    whole(workers, "workers", 1)
    _check_split(split, scenario_specs, episodes)
    options = resolve_env_options(env_options, split)
    first_seed = episode_seeds(split, seed, 1)[0]
    first_env, scene_envs = None, []
    for spec in scenario_specs:
        for delta_d in deltas:
            try:
                env = make_episode_env(spec, delta_d, spec.obstacles(n_obstacles), None, split)
                env.reset(seed=first_seed)
            except ValueError as error:
                raise ValueError(f"scenario {spec.label!r} at delta_d {delta_text(delta_d)}: {error}") from None
            if options:  # the scene is fine without them: an error now is the options'
                try:
                    env = make_episode_env(spec, delta_d, spec.obstacles(n_obstacles), options, split)
                    env.reset(seed=first_seed)
                except (ValueError, TypeError) as error:  # TypeError: a keyword the env does not take
                    raise ValueError(f"env_options {options}: {error}") from None
            if first_env is None:
                first_env = env
        scene_envs.append(env)
    check_needs(agents, scenario_specs, scene_envs, agent_kwargs or {})
    overrides = resolve_agent_kwargs(agents, agent_kwargs or {}, first_env)
    for agent in agents:  # an object is used as given: it must fit every scene (an Agent's arena)
        if agent.kind == "object":
            for env in scene_envs[1:]:
                agent.build(env, 0)
    return CheckedRun(agents, scenario_specs, deltas, overrides, options)


def check_needs(agents: list[AgentSpec], scenario_specs: list[ScenarioSpec], scene_envs: list, agent_kwargs: dict) -> None:
    """Every registered agent against every scenario's env (its robot, its observation keys), before the
    first episode: a run must not die part-way on an agent that cannot read a cell's observation.

    :raises ValueError: naming the agent, the scenario and what its env offers (:mod:`agents.requirements`)."""
    from agents.registry import check

    per_agent = bool(agent_kwargs) and all(isinstance(v, dict) for v in agent_kwargs.values())
    for spec in agents:
        if spec.kind != "factory" or spec.name is None:
            continue  # an agent of one's own states nothing: building it is its check
        kwargs = {**spec.kwargs, **(agent_kwargs.get(spec.label, {}) if per_agent else agent_kwargs)}
        for scenario, env in zip(scenario_specs, scene_envs):
            try:
                check(spec.name, env, **kwargs)
            except ValueError as error:
                raise ValueError(f"scenario {scenario.label!r}: {error}") from None


def resolve_agent_kwargs(agents: list[AgentSpec], agent_kwargs: dict, env) -> dict[str, dict]:
    """Per-agent overrides from either form, checked by building each agent once on ``env`` (before any work).

    ``{"n_waypoints": 3}`` goes to every agent; ``{"pso": {"n_waypoints": 3}}`` to the one labelled ``pso`` only.
    :raises ValueError: naming the agent and the argument it does not take, or what building it raised.
    """
    if not isinstance(agent_kwargs, dict):
        raise ValueError(f"agent kwargs must be a JSON object, got {agent_kwargs!r}")
    labels = [spec.label for spec in agents]
    per_agent = bool(agent_kwargs) and all(isinstance(v, dict) for v in agent_kwargs.values())
    if per_agent:
        unknown = sorted(set(agent_kwargs) - set(labels))
        if unknown:
            raise ValueError(f"agent kwargs for agents not in the run: {unknown}; the run's: {labels}")
        own = {label: dict(agent_kwargs.get(label, {})) for label in labels}
    else:
        own = {label: dict(agent_kwargs) for label in labels}
    for spec in agents:
        kwargs = own[spec.label]
        try:
            agent = spec.build(env, 0, kwargs)
        except TypeError as error:
            if kwargs:
                raise ValueError(f"agent {spec.label!r} does not take {sorted(kwargs)}: {error}") from None
            raise ValueError(f"agent {spec.label!r}: building it raised TypeError: {error}") from None
        except Exception as error:  # the user's code: named in one line, before any work
            raise ValueError(f"agent {spec.label!r}: building it raised {type(error).__name__}: {error}") from None
        if not callable(getattr(agent, "predict", None)):
            raise ValueError(f"agent {spec.label!r}: built a {type(agent).__name__}, which has no "
                             f"predict(observation, state=None, episode_start=None, deterministic=False)")  # fmt: skip
    return own
