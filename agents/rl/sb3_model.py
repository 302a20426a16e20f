"""A stable-baselines3 model file as it comes, as an agent: ``agents.make("sb3", env, path=...)``.

The model needs no sidecar file. What a researcher gets from SB3's ``evaluate_policy`` on a
``VecNormalize(training=False)`` env, rl-zoo3's ``enjoy`` or their own loop, this agent reproduces:

- **the algorithm** is read from the zip's ``data`` JSON without unpickling anything (the policy
  class's module and the algorithm's own hyperparameters: ``clip_range`` is PPO's, ``policy_delay``
  TD3's and DDPG's, ...), or given (``algo="sac"``, rl-zoo3's names, or an algorithm class). The
  model is then loaded as rl-zoo3's ``enjoy`` loads it (schedules replaced by constants, a one-slot
  replay buffer for off-policy algorithms, on the CPU);
- **the observations** follow the model's observation space: ``DynamicObstacle-v0``'s ``Dict``
  (a ``MultiInputPolicy`` trained on the raw env) is passed as it is (zero-shot on scenes with walls:
  a model trained without them gets its own entries only, not ``static_segments`` / ``static_mask``); a flat ``Box`` of
  ``feature_size(k)`` (``DynamicObstacleFlat-v0``, or ``make_learning_env(env, k)``) gets
  ``egocentric_features`` with that ``k`` and its actions mapped back with
  ``relative_action_to_waypoint``, as the learning wrappers do. Anything else is refused, naming
  ``path`` and the spaces;
- **VecNormalize's statistics** found beside the model (:func:`statistics_beside`: SB3's and
  rl-zoo3's file names and layout) or given by path are loaded with SB3's own
  ``VecNormalize.load`` (``training=False``, ``norm_reward=False``, as rl-zoo3's ``enjoy`` does)
  and applied with its ``normalize_obs``: the arithmetic (``obs_rms``, ``epsilon``, ``clip_obs``,
  ``norm_obs_keys``) is SB3's. The model's own record decides what a missing or stray file means
  (:func:`trained_inside_vecnormalize`): a model that learned on normalised observations with no
  statistics beside it, or one that did not with statistics beside it, is refused rather than
  run on the wrong inputs (``vecnormalize=`` a path or ``None`` settles it).

The agent says in one line on stderr (once per process) what it loaded and applied, and keeps the
line as ``agent.description``. Loading a model or its statistics unpickles them: load only files from
sources you trust (as SB3's documentation says). A pickle is read only from the path given or
beside the model named, never from anywhere else. stable-baselines3 and torch are imported only
when a model is loaded.
"""

from __future__ import annotations

import json
import pickle
import re
import sys
import time
from functools import lru_cache
from pathlib import Path

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from agents.base import Agent
from agents.rl.policy import RLAgent
from agents.rl.sb3_zip import detect_algorithm, saved_data
from pathplan_env.wrappers import FEATURE_LIMIT, PER_OBSTACLE, ROBOT_FEATURES, egocentric_features, feature_size, relative_action_to_waypoint

#: rl-zoo3's algorithm names -> (module, class). sb3-contrib's need ``pip install sb3-contrib``.
ALGORITHMS = {
    "a2c": ("stable_baselines3", "A2C"),
    "ddpg": ("stable_baselines3", "DDPG"),
    "dqn": ("stable_baselines3", "DQN"),
    "ppo": ("stable_baselines3", "PPO"),
    "sac": ("stable_baselines3", "SAC"),
    "td3": ("stable_baselines3", "TD3"),
    "ars": ("sb3_contrib", "ARS"),
    "crossq": ("sb3_contrib", "CrossQ"),
    "qrdqn": ("sb3_contrib", "QRDQN"),
    "tqc": ("sb3_contrib", "TQC"),
    "trpo": ("sb3_contrib", "TRPO"),
}
#: the env ids whose folder rl-zoo3 writes the statistics to (``<run>/<env_id>/vecnormalize.pkl``)
ENV_IDS = ("DynamicObstacleFlat-v0", "DynamicObstacle-v0")
_CHECKPOINT = re.compile(r"(.*)_(\d+)_steps")  # SB3's CheckpointCallback: <prefix>_<steps>_steps.zip


def _algorithm_class(name: str):
    import importlib

    module, cls = ALGORITHMS[name]
    try:
        return getattr(importlib.import_module(module), cls)
    except ImportError:
        raise ValueError(f"algo: {cls} needs {module.replace('_', '-')} (pip install {module.replace('_', '-')})") from None


def statistics_beside(path: str | Path) -> list[Path]:
    """Where SB3 and rl-zoo3 users keep the VecNormalize statistics of the model at ``path``, in the
    order looked at (existing or not). Only the model's folder and rl-zoo3's subfolder of it:

    - ``<prefix>_vecnormalize_<N>_steps.pkl`` beside ``<prefix>_<N>_steps.zip`` (SB3's
      ``CheckpointCallback(save_vecnormalize=True)``): a checkpoint's own statistics;
    - ``vecnormalize.pkl`` (rl-zoo3's ``SaveVecNormalizeCallback``) and ``vec_normalize.pkl``
      (SB3's documentation) in the model's folder;
    - ``<stem>/vecnormalize.pkl`` and ``<env_id>/vecnormalize.pkl`` (rl-zoo3: ``<run>/<env_id>.zip``,
      ``<run>/best_model.zip`` and checkpoints beside ``<run>/<env_id>/vecnormalize.pkl``).
    """
    path = Path(path)
    folder, found = path.parent, []
    checkpoint = _CHECKPOINT.fullmatch(path.stem)
    if checkpoint:
        found.append(folder / f"{checkpoint[1]}_vecnormalize_{checkpoint[2]}_steps.pkl")
    found += [folder / "vecnormalize.pkl", folder / "vec_normalize.pkl"]
    for sub in dict.fromkeys((path.stem, *ENV_IDS)):
        found.append(folder / sub / "vecnormalize.pkl")
    return found


def _find_statistics(path: Path) -> Path | None:
    """The statistics beside the model: a checkpoint's own first; otherwise the one file found, and an
    error if several are (which one the model was trained with is the user's to say)."""
    candidates = statistics_beside(path)
    if _CHECKPOINT.fullmatch(path.stem) and candidates[0].is_file():
        return candidates[0]
    existing = [c for c in candidates if c.is_file()]
    if len(existing) > 1:
        raise ValueError(f"vecnormalize: several VecNormalize statistics beside {path}: {[str(e) for e in existing]}; pass vecnormalize=<the one>")
    return existing[0] if existing else None


@lru_cache(maxsize=8)
def _load_model(path: Path, algorithm: type, mtime: float):
    """Load as rl-zoo3's ``enjoy`` does: schedules replaced (they need not unpickle across Python
    versions), a one-slot replay buffer; once per process (the harness makes an agent per episode)."""
    from stable_baselines3.common.off_policy_algorithm import OffPolicyAlgorithm

    custom_objects = {"learning_rate": 0.0, "lr_schedule": lambda _: 0.0, "clip_range": lambda _: 0.0}
    kwargs = {"buffer_size": 1, "optimize_memory_usage": False} if issubclass(algorithm, OffPolicyAlgorithm) else {}
    return algorithm.load(path, device="cpu", custom_objects=custom_objects, **kwargs)


class _SpacesOnly(gym.Env):
    """An env that only holds a model's spaces: what ``VecNormalize.load`` checks its statistics against. Never stepped."""

    def __init__(self, observation_space: spaces.Space, action_space: spaces.Space):
        self.observation_space, self.action_space = observation_space, action_space


@lru_cache(maxsize=8)
def _load_statistics(path: Path, mtime: float, model_path: Path, algorithm: type, model_mtime: float):
    """SB3's ``VecNormalize.load`` on a vector env of the model's spaces, set for evaluation."""
    from stable_baselines3.common.vec_env import DummyVecEnv, VecNormalize

    model = _load_model(model_path, algorithm, model_mtime)
    venv = DummyVecEnv([lambda: _SpacesOnly(model.observation_space, model.action_space)])
    try:
        statistics = VecNormalize.load(str(path), venv)
    except AssertionError as error:  # SB3's check that the statistics' shapes are the model's
        raise ValueError(f"vecnormalize: the statistics in {path} do not fit the model {model_path}: {error}") from None
    except (AttributeError, pickle.UnpicklingError, EOFError):  # not a pickle, or not of VecNormalize
        statistics = None
    if not isinstance(statistics, VecNormalize):
        raise ValueError(f"vecnormalize: {path} does not hold VecNormalize statistics (VecNormalize.save writes them)")
    statistics.training, statistics.norm_reward = False, False
    return statistics


#: The entries a scene with walls adds to the ``Dict`` (``StateObservation.reserve_static_segments``):
#: a model that never saw them runs zero-shot without them.
MAP_KEYS = ("static_segments", "static_mask")


def _without_map(space: spaces.Space) -> spaces.Space:
    if isinstance(space, spaces.Dict):
        return spaces.Dict({k: v for k, v in space.spaces.items() if k not in MAP_KEYS})
    return space


def _same_shapes(model_space: spaces.Space, env_space: spaces.Space) -> bool:
    if isinstance(model_space, spaces.Dict) and isinstance(env_space, spaces.Dict):
        if not any(k in model_space.spaces for k in MAP_KEYS):  # a model trained without walls: zero-shot
            env_space = _without_map(env_space)
        # shapes and dtypes, not bounds: the positions' bounds are the arena's, and a model may run
        # zero-shot in another arena
        return model_space.spaces.keys() == env_space.spaces.keys() and all(
            model_space[k].shape == env_space[k].shape and model_space[k].dtype == env_space[k].dtype for k in env_space.spaces
        )
    return False


def trained_inside_vecnormalize(model) -> bool | None:
    """Whether ``model`` learned inside a ``VecNormalize`` that normalised its observations, as far
    as the model itself tells (``None``: it does not, e.g. it never learned).

    SB3 saves the last observation the model saw (``_last_obs``, normalised) and, for on-policy
    algorithms only when trained inside VecNormalize, the raw one (``_last_original_obs``); the
    off-policy algorithms keep the raw one always, equal to the other without normalisation."""
    seen, raw = getattr(model, "_last_obs", None), getattr(model, "_last_original_obs", None)
    if seen is None:
        return None
    if raw is None:
        return False
    if isinstance(seen, dict):
        return not all(np.array_equal(seen[key], raw[key]) for key in seen)
    return not np.array_equal(seen, raw)


class SB3Agent(Agent):
    """Any stable-baselines3 model trained on ``DynamicObstacleFlat-v0`` or ``DynamicObstacle-v0``,
    from its ``.zip`` alone, with the VecNormalize statistics beside it (see the module doc).

    Actions are the policy's mean unless ``predict(..., deterministic=False)`` asks for samples
    (drawn by the model's torch generator, as in SB3).

    :param path: the model's ``.zip`` (``".zip"`` may be left out, as SB3 allows).
    :param algo: the algorithm, rl-zoo3's name (``"ppo"``, ``"sac"``, ...; see :data:`ALGORITHMS`)
        or an SB3 algorithm class; ``None`` (default) reads it from the zip. A name the zip
        contradicts is refused.
    :param vecnormalize: ``"auto"`` (default) applies the statistics beside the model
        (:func:`statistics_beside`) if the model learned inside VecNormalize or does not tell,
        and refuses a contradiction; ``True`` requires them; ``None`` or ``False`` applies none;
        a path applies those.
    """

    def __init__(self, env, seed: int | None = None, path: str | Path | None = None, algo=None, vecnormalize="auto"):
        super().__init__(env, seed=seed)
        if path is None:
            raise ValueError("path: agents.make('sb3', env, path=...) needs the model's .zip")
        path = Path(path)
        if not path.is_file() and path.with_name(path.name + ".zip").is_file():
            path = path.with_name(path.name + ".zip")
        if not path.is_file():
            raise ValueError(f"path: no model at {path}")
        env_space = getattr(env, "single_observation_space", env.observation_space)
        if not isinstance(env_space, spaces.Dict):
            raise ValueError(f"env: the agent acts on DynamicObstacle-v0's Dict observations, got {env_space}")
        self.path = path
        saved_data(path)  # SB3's entries, of a bounded size, before torch unpickles anything
        #: the algorithm's class (``stable_baselines3.PPO``, ...)
        self.algorithm, algo_text = self._resolve_algorithm(path, algo)
        key = (path.resolve(), self.algorithm, path.stat().st_mtime)
        self.model = _load_model(*key)
        self.k_nearest, observation_text = self._read_observation_space(env_space)
        self._check_action_space()
        self.statistics, statistics_text = self._load_vecnormalize(vecnormalize, key)
        #: what was loaded and applied, in one line (printed once per process)
        self.description = f"sb3: {algo_text} from {path}; observations: {observation_text}; {statistics_text}"
        _announce(self.description)

    # -- construction ---------------------------------------------------------------------------
    @staticmethod
    def _resolve_algorithm(path: Path, algo):
        if isinstance(algo, type):
            return algo, f"{algo.__name__} (given)"
        candidates = detect_algorithm(path)
        if algo is None:
            if not candidates:
                raise ValueError(f"path: cannot tell the algorithm of {path} (its policy class is not SB3's); pass algo=, one of {sorted(ALGORITHMS)}")
            return _algorithm_class(candidates[0]), f"{ALGORITHMS[candidates[0]][1]} (read from the zip)"
        name = str(algo).lower()
        if name not in ALGORITHMS:
            raise ValueError(f"algo: unknown algorithm {algo!r}; known: {sorted(ALGORITHMS)}, or pass an SB3 algorithm class")
        if candidates and name not in candidates:
            raise ValueError(f"path: {path} was saved by {ALGORITHMS[candidates[0]][1]}, not {ALGORITHMS[name][1]} (algo={algo!r})"
                             + ("; load it with agents.make('sb3', env, path=...)" if name == "ppo" else ""))  # fmt: skip
        return _algorithm_class(name), f"{ALGORITHMS[name][1]} (given)"

    def _check_action_space(self) -> None:
        space = self.model.action_space
        if not (isinstance(space, spaces.Box) and space.shape == (2,) and np.all(space.low == -1.0) and np.all(space.high == 1.0)):
            raise ValueError(f"path: the model at {self.path} acts in {space}; the env and its learning wrappers take Box(-1, 1, (2,))")

    def _read_observation_space(self, env_space: spaces.Dict) -> tuple[int | None, str]:
        """``None`` (raw ``Dict`` observations) or the ``k`` of the flat features the model takes."""
        space = self.model.observation_space
        if _same_shapes(space, env_space):
            return None, "DynamicObstacle-v0's Dict, as they come"
        if isinstance(space, spaces.Box) and len(space.shape) == 1:
            k = (space.shape[0] - ROBOT_FEATURES) // PER_OBSTACLE
            # the bounds too: another task's model of the same width takes other features
            ours = np.all(space.low == -FEATURE_LIMIT) and np.all(space.high == FEATURE_LIMIT)
            if k >= 1 and feature_size(k) == space.shape[0] and ours:
                return k, f"DynamicObstacleFlat-v0's features (k={k}), actions relative waypoints"
        hint = ""
        if isinstance(space, spaces.Dict) and space.spaces.keys() == env_space.spaces.keys():
            rows = space["obstacle_mask"].shape[0]
            hint = f" (obstacle rows: the model's {rows}, this env's {env_space['obstacle_mask'].shape[0]}; make the env with max_obstacles={rows})"
        raise ValueError(f"path: the model at {self.path} takes observations {space}, neither this env's {env_space}{hint} "
                         f"nor DynamicObstacleFlat-v0's Box(-{FEATURE_LIMIT:g}, {FEATURE_LIMIT:g}, ({ROBOT_FEATURES} + {PER_OBSTACLE} k,))")  # fmt: skip

    def _load_vecnormalize(self, vecnormalize, key):
        normalised = trained_inside_vecnormalize(self.model)
        if vecnormalize is None or vecnormalize is False:
            return None, "VecNormalize: none (vecnormalize=None)"
        if vecnormalize in ("auto", True):
            found = _find_statistics(self.path)
            looked = ", ".join(str(p.relative_to(self.path.parent)) for p in statistics_beside(self.path))
            if found is None and (vecnormalize is True or normalised):
                raise ValueError(f"vecnormalize: no VecNormalize statistics beside {self.path} (looked for {looked})"
                                 + ("; the model learned inside VecNormalize (its saved observations are normalised): pass "
                                    "vecnormalize=<the statistics' path>, or vecnormalize=None to run it without" if normalised else ""))  # fmt: skip
            if found is None:
                return None, f"VecNormalize: none found beside the model (looked for {looked})"
            if normalised is False:
                raise ValueError(f"vecnormalize: {found} is beside {self.path}, but the model did not learn inside VecNormalize "
                                 f"(its saved observations are not normalised): pass vecnormalize={str(found)!r} to apply them "
                                 "anyway, or vecnormalize=None")  # fmt: skip
            vecnormalize = found
        stats_path = Path(vecnormalize)
        if not stats_path.is_file():
            raise ValueError(f"vecnormalize: no file {stats_path}")
        statistics = _load_statistics(stats_path.resolve(), stats_path.stat().st_mtime, *key)
        if not statistics.norm_obs:
            return statistics, f"VecNormalize from {stats_path} (norm_obs=False: observations unchanged)"
        keys = f", keys {statistics.norm_obs_keys}" if statistics.norm_obs_keys is not None else ""
        return statistics, f"VecNormalize from {stats_path} (clip_obs={statistics.clip_obs:g}, epsilon={statistics.epsilon:g}{keys}, training=False)"

    # -- SB3 contract ---------------------------------------------------------------------------
    def predict(self, observation, state=None, episode_start=None, deterministic: bool = False):
        begin = time.perf_counter()
        if self.k_nearest is None:  # only the entries the model knows (a wall scene's map is new to it)
            model_input = {k: observation[k] for k in self.model.observation_space.spaces}
        else:
            model_input = egocentric_features(observation, self.facts, self.k_nearest)
        if self.statistics is not None:
            model_input = self.statistics.normalize_obs(model_input)
        action, _ = self.model.predict(model_input, deterministic=deterministic)
        if self.k_nearest is not None:
            action = self.waypoint_to_action(relative_action_to_waypoint(observation, action, self.facts))
        self.last_plan_seconds = time.perf_counter() - begin
        return np.asarray(action, dtype=np.float32), state


def _written_by_train_rl(path: Path) -> bool:
    """Whether ``train_rl.py``'s sidecar lies beside the model (a JSON with its keys), not just any JSON."""
    sidecar = path.with_suffix(".json")
    try:
        metadata = json.loads(sidecar.read_text())
    except (OSError, ValueError):
        return False
    return isinstance(metadata, dict) and {"k_nearest", "command"} <= set(metadata)


_ANNOUNCED: set[str] = set()


def _announce(description: str) -> None:
    """One line on stderr per loaded configuration and process (the harness makes an agent per episode)."""
    if description not in _ANNOUNCED:
        _ANNOUNCED.add(description)
        print(description, file=sys.stderr)


def trained_agent(env, seed: int | None = None, algo: str = "ppo", path: str | Path | None = None, backend: str = "auto", **options):
    """``agents.make("ppo", env, ...)``: the shipped model, or one from ``scripts/train_rl.py`` (its
    JSON sidecar beside it), runs as :class:`RLAgent`; any other model file of that algorithm as it
    comes (:class:`SB3Agent`; ``options``: its ``vecnormalize``)."""
    if path is None and options:
        raise TypeError(f"{sorted(options)} apply to a model file given by path=")
    if path is None or (not options and _written_by_train_rl(Path(path)) and not any(p.is_file() for p in statistics_beside(path))):
        return RLAgent(env, seed=seed, algo=algo, path=path, backend=backend)
    if backend == "numpy":
        raise ValueError(f"backend: 'numpy' runs a model exported by scripts/export_policy.py, with its sidecar {Path(path).with_suffix('.json')}")
    return SB3Agent(env, seed=seed, path=path, algo=algo, **options)
