"""What a run evaluates, from whatever the user gave: agents and scenarios as labelled, picklable specs.

An agent may be given as
  * a registered name (``"pso"``, see ``agents.available()``; one registered in a script's
    ``__main__`` works too: its factory travels with the jobs);
  * ``"name?key=value&key=value"``: a registered name with parameters over its own
    (``"pso?iterations=20"``, values Python literals; :func:`agents.registry.split_settings`);
  * ``"name@model_path"``: a learned agent and its checkpoint (``"ppo@runs/a/best_model.zip"``);
  * ``"module:attribute"`` or ``"path/to/file.py:attribute"``: imported here and again in every worker
    (a module is looked up on ``sys.path`` and in the current directory, as ``python -m`` would);
  * a class or factory: called ``factory(env, seed=seed, **kwargs)`` (``seed`` only if it takes one;
    ``env`` only if it takes an argument);
  * any object with SB3's ``predict(observation, state=None, episode_start=None, deterministic=False)``,
    e.g. a loaded SB3 model: every episode gets a fresh copy of it as given.

A scenario may be a preset's name, a :class:`pathplan_env.Scenario`, its dict, or a JSON/YAML file of one.
A preset may carry its own obstacle count as ``"random:n_obstacles=30"`` (the run's ``n_obstacles``
is for the others): a suite then runs one preset at several densities, each a scenario of its own.

Results name each entrant by its label: the registered name or the entry's text, a class's or
function's ``__name__``, an object's ``name`` or type, a scenario's ``name`` (a file's stem by default).
Give another one as ``(label, entry)``, ``{"label": ..., "agent" | "scenario": ...}`` or the text
``"label=entry"``. Two entrants with one label are an error: their episodes would merge into one row.
"""

from __future__ import annotations

import copy
import dataclasses
import functools
import hashlib
import importlib
import importlib.util
import inspect
import json
import os
import re
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from pathplan_env import PRESETS, Scenario
from pathplan_env.arguments import check_n_obstacles
from pathplan_env.facts import EnvFacts
from pathplan_env.scenarios.files import SUFFIXES, is_scenario_file, load_scenario
from pathplan_env.scenarios.map_scenes import MapScenes, is_map_file

_LABELLED = re.compile(r"([\w.+-]+)=(.+)")  # "label=entry": a label has no '/', ':', '@' or '='
AGENT_FORMS = "a registered name, name?key=value, name@model_path, module:attribute or path/to/file.py:attribute"


@dataclass(frozen=True, eq=False)
class AgentSpec:
    """One agent of a run, as it travels to the workers.

    ``kind`` is ``"factory"`` (``target`` a callable building the agent; ``name`` set on the agent as
    ``agents.make`` does, for registered ones), ``"reference"`` (``target`` the text
    ``"module:attribute"`` or ``"/abs/file.py:attribute"``, imported where the episode runs) or
    ``"object"`` (``target`` an object with ``predict``, copied for each episode)."""

    label: str
    kind: str
    target: Any
    name: str | None = None
    kwargs: dict = field(default_factory=dict)  # fixed by the entry itself: a learned agent's model path
    search_path: str | None = None  # the directory a module reference was given in

    @property
    def source(self) -> str:
        """Where the agent comes from, for the run's record (``summary.json``'s config)."""
        if self.kind == "reference":
            return self.target
        if self.name is not None:
            settings = "&".join(f"{k}={v!r}" for k, v in self.kwargs.items() if k != "path")
            return self.name + (f"?{settings}" if settings else "") + (f"@{self.kwargs['path']}" if "path" in self.kwargs else "")
        owner = getattr(self.target, "func", self.target)
        owner = owner if self.kind == "factory" else type(owner)
        return f"{getattr(owner, '__module__', '?')}.{getattr(owner, '__qualname__', type(owner).__name__)}"

    def build(self, env, seed: int | None, overrides: dict | None = None):
        """A fresh agent for one episode on ``env``."""
        target = load_reference(self.target, self.search_path)[1] if self.kind == "reference" else self.target
        if not _is_factory(target):
            if overrides:
                raise TypeError(f"an object with predict takes no keyword arguments, got {sorted(overrides)}")
            facts = getattr(target, "facts", None)  # an agents.Agent made on one env maps actions through its arena
            if facts is not None and facts != EnvFacts.of(env):
                raise ValueError(f"agent {self.label!r} was made for another arena ({facts.bounds}) than this scenario's "
                                 f"{EnvFacts.of(env).bounds}: pass its class or name instead, so each scenario builds its own")
            return copy.deepcopy(target)  # as given, whatever the previous episode left in it
        agent = _call_factory(target, env, seed, {**self.kwargs, **(overrides or {})})
        if self.name is not None:
            agent.name = self.name
        return agent


@dataclass(frozen=True, eq=False)
class ScenarioSpec:
    """One scenario of a run: a preset's name, the :class:`Scenario` itself (a file is read once, here),
    or a map's :class:`~pathplan_env.scenarios.map_scenes.MapScenes` (episodes drawn on the map).

    ``n_obstacles``: a preset's own obstacle count (``"random:n_obstacles=30"``), which overrides the
    run's; ``None``: the run's (or the preset's default)."""

    label: str
    scenario: str | Scenario | MapScenes
    n_obstacles: int | None = None

    def __post_init__(self):
        if self.n_obstacles is not None:
            if not isinstance(self.scenario, (str, MapScenes)):
                raise ValueError(f"n_obstacles: only a preset or a map takes its own obstacle count, not the scene {self.label!r}")
            check_n_obstacles(self.n_obstacles)

    def obstacles(self, run_n_obstacles: int | None) -> int | None:
        """The obstacle count its episodes run with: its own, else the run's."""
        return run_n_obstacles if self.n_obstacles is None else self.n_obstacles

    @property
    def text(self) -> str:
        """A preset as written on the command line: ``"random"`` or ``"random:n_obstacles=30"``."""
        if not isinstance(self.scenario, str):
            return self.label
        return self.scenario if self.n_obstacles is None else f"{self.scenario}:n_obstacles={self.n_obstacles}"

    @property
    def definition(self) -> dict | None:
        """A custom scene's fields as plain JSON values (``summary.json`` records them); ``None`` for a preset."""
        if isinstance(self.scenario, str):
            return None
        return json.loads(json.dumps(dataclasses.asdict(self.scenario), default=repr))

    @property
    def key(self) -> str:
        """The run's record of it (``--resume``): a preset's name, or the label and a digest of the
        scene, so an edited scene file is not resumed from the episodes of the old one."""
        if isinstance(self.scenario, str):  # a preset's count is in the key (and in each episode's, as before)
            return self.text if self.label == self.text else f"{self.label}#{self.text}"
        text = json.dumps(self.definition, sort_keys=True)
        return f"{self.label}#{hashlib.sha1(text.encode()).hexdigest()[:12]}"


# -- agents -------------------------------------------------------------------------------------
def resolve_agents(entries, *, argument: str = "agent_names", transport: str | None = None) -> list[AgentSpec]:
    """The specs of ``entries`` (any of the module doc's forms), labels unique.

    ``transport``: how the jobs travel, checked here before any work: ``None`` (this process),
    ``"process"`` (pickled to spawned processes) or ``"ray"`` (Ray's cloudpickle).
    :raises ValueError: naming ``argument`` and the entry."""
    specs = [_agent_spec(entry, argument) for entry in _entries(entries, argument)]
    _unique([s.label for s in specs], argument)
    for spec in specs:
        _check_transport(spec, argument, transport)
    return specs


def _agent_spec(entry, argument: str) -> AgentSpec:
    import agents

    if isinstance(entry, AgentSpec):
        return entry
    label, entry = _split_label(entry, "agent", argument)
    if isinstance(entry, str):
        spec = _agent_from_text(entry.strip(), argument)
    elif _is_factory(entry):
        named = getattr(entry, "func", entry)  # a functools.partial by its function's name
        spec = AgentSpec(getattr(named, "__name__", None) or type(entry).__name__, "factory", entry)
    elif callable(getattr(entry, "predict", None)):
        try:
            copy.deepcopy(entry)
        except Exception as error:  # each episode starts from a copy: one that cannot be made is named now
            raise ValueError(f"{argument}: {type(entry).__name__} object: cannot be copied for each episode ({error})") from None
        own = getattr(entry, "name", None)
        spec = AgentSpec(own if isinstance(own, str) and own and own != agents.Agent.name else type(entry).__name__, "object", entry)
    else:
        raise ValueError(f"{argument}: {entry!r} is not an agent: give {AGENT_FORMS}, a class or factory, or an object with predict")
    return dataclasses.replace(spec, label=label) if label else spec


def _agent_from_text(text: str, argument: str) -> AgentSpec:
    import agents

    known = agents.available()  # the factories themselves travel with the jobs: a registration in __main__ too
    if text in known:
        return AgentSpec(text, "factory", agents.registry.factory(text), name=text)
    if "?" in text:  # a registered name with parameters: checked against every scenario's env before any work
        try:
            name, settings = agents.registry.split_settings(text)
        except ValueError as error:
            raise ValueError(f"{argument}: {error}") from None
        if name not in known:
            raise ValueError(f"{argument}: {text!r}: unknown agent {name!r}; available: {known}")
        return AgentSpec(text, "factory", agents.registry.factory(name), name=name, kwargs=settings)
    name, at, model = text.partition("@")
    if at:
        if name not in known:
            raise ValueError(f"{argument}: {text!r}: unknown agent {name!r}; available: {known}")
        if not Path(model).exists():
            raise ValueError(f"{argument}: {text!r}: no model file {model}")
        return AgentSpec(text, "factory", agents.registry.factory(name), name=name, kwargs={"path": str(Path(model).resolve())})
    module, colon, attribute = text.rpartition(":")
    if colon and module and attribute and not module.endswith(("\\", "/")):
        if module.endswith(".py"):
            reference, search = f"{Path(module).resolve()}:{attribute}", None
        else:
            reference, search = text, os.getcwd()
        try:
            load_reference(reference, search)
        except ValueError as error:
            raise ValueError(f"{argument}: {text!r}: {error}") from None
        return AgentSpec(text, "reference", reference, search_path=search)
    raise ValueError(f"{argument}: unknown agent {text!r}; give {AGENT_FORMS}; available: {agents.available()}")


@functools.cache
def load_reference(reference: str, search_path: str | None = None) -> tuple[str, Any]:
    """Import ``"module:attribute"`` (``search_path`` appended to ``sys.path`` if missing) or
    ``"/abs/file.py:attribute"`` (under a module name of its own, stable for the file), once per process.

    :raises ValueError: saying what is missing, or what importing raised."""
    module_name, _, attribute = reference.rpartition(":")
    try:
        if module_name.endswith(".py"):
            module = _import_file(Path(module_name))
        else:
            if search_path and search_path not in sys.path:
                sys.path.append(search_path)
            module = importlib.import_module(module_name)
    except ValueError:
        raise
    except ModuleNotFoundError as error:
        where = f" (looked on sys.path and in {search_path})" if error.name == module_name and search_path else ""
        raise ValueError(f"no module named {error.name!r}{where}") from None
    except Exception as error:  # the user's module failed while importing: say how, in one line
        raise ValueError(f"importing {module_name} raised {type(error).__name__}: {error}") from None
    try:
        target = functools.reduce(getattr, attribute.split("."), module)
    except AttributeError:
        raise ValueError(f"module {module_name} has no attribute {attribute!r}") from None
    if not (_is_factory(target) or callable(getattr(target, "predict", None))):
        raise ValueError(f"{attribute} is neither a class or factory nor an object with predict")
    return module_name, target


def _import_file(path: Path):
    if not path.is_file():
        raise ValueError(f"no file {path}")
    stem = re.sub(r"\W", "_", path.stem)
    name = f"_agent_file_{stem}_{hashlib.sha1(str(path).encode()).hexdigest()[:8]}"
    if name in sys.modules:
        return sys.modules[name]
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module  # before running it: its classes pickle by reference to this name
    try:
        spec.loader.exec_module(module)
    except BaseException:
        del sys.modules[name]
        raise
    return module


def _is_factory(target) -> bool:
    """A class, or a callable that is not itself a policy (a function, a ``functools.partial``)."""
    return isinstance(target, type) or (callable(target) and not callable(getattr(target, "predict", None)))


def _call_factory(factory, env, seed, kwargs):
    try:
        parameters = inspect.signature(factory).parameters.values()
    except (TypeError, ValueError):  # no signature to read (a builtin): the full call
        return factory(env, seed=seed, **kwargs)
    kinds = {p.kind for p in parameters}
    takes_seed = inspect.Parameter.VAR_KEYWORD in kinds or any(p.name == "seed" for p in parameters)
    positional = (inspect.Parameter.POSITIONAL_ONLY, inspect.Parameter.POSITIONAL_OR_KEYWORD)
    takes_env = inspect.Parameter.VAR_POSITIONAL in kinds or any(p.kind in positional and p.name != "seed" for p in parameters)
    seeded = {"seed": seed} if takes_seed else {}
    return factory(env, **seeded, **kwargs) if takes_env else factory(**seeded, **kwargs)


def _check_transport(spec: AgentSpec, argument: str, transport: str | None) -> None:
    """Workers build the agent from what is sent: a class, function or object must reach them."""
    if transport is None or spec.kind == "reference":  # a reference is text: each worker imports it
        return
    target = spec.target
    if transport == "ray":
        from ray import cloudpickle as pickler  # sends what __main__ defines by value
    else:
        import pickle as pickler

        owner = getattr(getattr(target, "func", target), "__module__", None) or type(target).__module__
        if owner == "__main__" and not getattr(sys.modules["__main__"], "__file__", None):
            raise ValueError(f"{argument}: {spec.label!r} is defined in an interactive session, which worker processes "
                             f"cannot import: define it in a module (then module:attribute), or use workers=1")  # fmt: skip
    try:
        pickler.dumps(target)
    except Exception as error:  # pickle's errors vary by type: PicklingError, AttributeError, TypeError
        raise ValueError(f"{argument}: {spec.label!r} cannot be sent to the worker processes ({type(error).__name__}: {error}): "
                         f"define it at a module's top level, or use workers=1") from None  # fmt: skip


# -- scenarios ----------------------------------------------------------------------------------
def resolve_scenarios(entries, *, argument: str = "scenarios") -> list[ScenarioSpec]:
    """The specs of ``entries``: presets, Scenarios, their dicts or files (read now), labels unique.

    :raises ValueError: naming ``argument`` and the entry."""
    specs = [_scenario_spec(entry, argument) for entry in _entries(entries, argument)]
    _unique([s.label for s in specs], argument)
    return specs


def _scenario_spec(entry, argument: str) -> ScenarioSpec:
    if isinstance(entry, ScenarioSpec):
        return entry
    label, entry = _split_label(entry, "scenario", argument)
    try:
        if isinstance(entry, str) and entry.strip() in PRESETS:
            spec = ScenarioSpec(entry.strip(), entry.strip())
        elif isinstance(entry, str) and entry.strip().partition(":")[0] in PRESETS and not Path(entry.strip()).exists():
            spec = preset_with_fields(entry.strip())
        elif isinstance(entry, (str, Path)) and is_map_file(str(entry).strip()):  # a map_server YAML: episodes drawn on the map
            scenes = MapScenes(str(entry).strip())
            spec = ScenarioSpec(scenes.name, scenes)
        elif isinstance(entry, dict) and "map" in entry:
            scenes = MapScenes.from_dict(entry)
            spec = ScenarioSpec(scenes.name, scenes)
        elif isinstance(entry, (str, Path)) and (is_scenario_file(entry) or Path(entry).is_file()):
            scenario = load_scenario(entry)
            spec = ScenarioSpec(scenario.name, scenario)
        elif isinstance(entry, (Scenario, dict)):
            scenario = entry if isinstance(entry, Scenario) else Scenario.from_dict(entry)
            spec = ScenarioSpec(scenario.name, scenario)
        else:
            raise ValueError(f"unknown {entry!r}; presets: {sorted(PRESETS)}; or a Scenario, its dict, or a {'/'.join(SUFFIXES)} file")
    except (ValueError, TypeError) as error:
        raise ValueError(f"{argument}: {error}") from None
    return dataclasses.replace(spec, label=label) if label else spec


#: The fields a preset's text takes after a colon (``"random:n_obstacles=30"``).
PRESET_FIELDS = ("n_obstacles",)


def preset_with_fields(text: str) -> ScenarioSpec:
    """``"preset:field=value"`` -> its spec, labelled by the text in canonical form.

    :raises ValueError: naming the field that is unknown, repeated or malformed."""
    preset, _, rest = text.partition(":")
    fields: dict[str, int] = {}
    for item in rest.split(":"):
        name, equals, value = (part.strip() for part in item.partition("="))
        if name not in PRESET_FIELDS:
            raise ValueError(f"{text!r}: unknown field {name!r}; a preset takes {', '.join(PRESET_FIELDS)} (e.g. {preset}:n_obstacles=30)")
        if name in fields:
            raise ValueError(f"{text!r}: field {name!r} given twice")
        if not equals or not re.fullmatch(r"\d+", value):
            raise ValueError(f"{text!r}: {name} must be a whole number >= 0, got {value!r}")
        fields[name] = int(value)
    spec = ScenarioSpec(preset, preset, **fields)
    return dataclasses.replace(spec, label=spec.text)


# -- shared -------------------------------------------------------------------------------------
def _entries(entries, argument: str) -> list:
    if isinstance(entries, (str, Path, dict, Scenario)) or not hasattr(entries, "__iter__"):
        raise ValueError(f"{argument} must be a non-empty list, got {entries!r}")
    entries = list(entries)
    if not entries:
        raise ValueError(f"{argument} must be a non-empty list, got []")
    return entries


def _split_label(entry, what: str, argument: str) -> tuple[str | None, Any]:
    """``(label, entry)``, ``{"label": ..., what: ...}`` or ``"label=entry"`` -> (label, entry); else (None, entry)."""
    if isinstance(entry, tuple) and len(entry) == 2 and isinstance(entry[0], str):
        label, entry = entry
    elif isinstance(entry, dict) and "label" in entry:
        if set(entry) != {"label", what}:
            raise ValueError(f"{argument}: a labelled entry is {{'label': ..., '{what}': ...}}, got keys {sorted(entry)}")
        label, entry = entry["label"], entry[what]
    elif isinstance(entry, str) and (match := _LABELLED.fullmatch(entry.strip())) and not Path(entry.strip()).exists():
        label, entry = match.groups()
    else:
        return None, entry
    if not isinstance(label, str) or not label.strip():
        raise ValueError(f"{argument}: a label must be a non-empty string, got {label!r}")
    return label.strip(), entry


def _unique(labels: list[str], argument: str) -> None:
    repeated = sorted({label for label in labels if labels.count(label) > 1})
    if repeated:
        raise ValueError(f"{argument}: label {', '.join(map(repr, repeated))} given more than once (its episodes would merge "
                         f"into one row): give each entrant its own label, e.g. ('mine-a', entry) or mine-a=entry")  # fmt: skip
