"""Trained stable-baselines3 policies as agents: the learning wrappers' transforms applied to raw observations.

A policy trained on ``pathplan_env.wrappers.make_learning_env`` sees ``egocentric_features`` and acts in
the relative-waypoint action space; this agent applies the same two functions to the raw env's
observations (single or batched), so it runs wherever the planners run.

Walls are zero-shot: ``egocentric_features`` reads the obstacles and the arena's edges, not the
observation's ``static_segments`` (the shipped model was trained without walls and never saw them).
"""

from __future__ import annotations

import json
import time
from functools import lru_cache
from pathlib import Path

from agents.base import Agent
from agents.rl.numpy_policy import NumpyPolicy
from pathplan_env.wrappers import egocentric_features, feature_size, relative_action_to_waypoint

MODELS_DIR = Path(__file__).parent.parent / "models"


def model_metadata(path: str | Path) -> dict:
    """The JSON written beside a model by ``scripts/train_rl.py`` (algorithm, k_nearest, command, ...)."""
    sidecar = Path(path).with_suffix(".json")
    if not sidecar.exists():
        raise ValueError(f"path: no metadata file {sidecar} beside the model (scripts/train_rl.py writes it)")
    return json.loads(sidecar.read_text())


def locate_model(path: str | Path | None, default: str, backend: str, trainer: str) -> tuple[Path, Path, str]:
    """``(path, exported, backend)`` for a learned agent: the model's ``.zip`` (``default`` in
    ``agents/models`` when ``path`` is None), its numpy export beside it (``.npz``) and the backend
    ``"auto"`` resolves to (numpy when the export exists).

    :raises ValueError: naming ``backend`` (not auto, numpy or sb3) or ``path`` (no model there;
        ``trainer`` is the command that makes one).
    """
    if backend not in ("auto", "numpy", "sb3"):
        raise ValueError(f"backend must be 'auto', 'numpy' or 'sb3', got {backend!r}")
    path = Path(path) if path is not None else MODELS_DIR / default
    exported = path.with_suffix(".npz")
    if backend == "auto":
        backend = "numpy" if exported.exists() else "sb3"
    if not (exported if backend == "numpy" else path).exists():
        raise ValueError(f"path: no model at {exported if backend == 'numpy' else path}; train one with {trainer}"
                         + (" (scripts/export_policy.py writes the .npz)" if backend == "numpy" else ""))  # fmt: skip
    return path, exported, backend


@lru_cache(maxsize=8)
def _load_numpy_policy(path: Path, mtime: float) -> NumpyPolicy:
    return NumpyPolicy(path)


@lru_cache(maxsize=8)
def _load_model(path: Path, algo: str, mtime: float):
    """Load once per process (an evaluation makes one agent per episode); ``predict`` never mutates it."""
    import stable_baselines3

    classes = {"ppo": stable_baselines3.PPO, "sac": stable_baselines3.SAC}
    if algo not in classes:
        raise ValueError(f"algo: unknown algorithm {algo!r}; known: {sorted(classes)}")
    return classes[algo].load(path, device="cpu")


class FeaturePolicyAgent(Agent):
    """A policy over features of the observation that acts in the learning wrappers' relative-waypoint
    space (``ppo``, ``ppo-set``, ``ppo-lidar``): a subclass loads ``self.model`` (an exported
    :class:`~agents.rl.numpy_policy.NumpyPolicy` when ``self.backend == "numpy"``, else an SB3 model)
    and says how it reads an observation (:meth:`features`)."""

    backend: str = "numpy"

    def features(self, observation, episode_start=None):
        raise NotImplementedError

    def predict(self, observation, state=None, episode_start=None, deterministic: bool = False):
        begin = time.perf_counter()
        features = self.features(observation, episode_start)
        if self.backend == "numpy":
            relative = self.model.predict(features, deterministic=deterministic, rng=self.rng)
        else:
            relative, _ = self.model.predict(features, deterministic=deterministic)
        frame = {"robot_position": observation["robot_position"], "goal": observation["goal"]}  # all the mapping reads
        waypoints = relative_action_to_waypoint(frame, relative, self.facts)
        self.last_plan_seconds = time.perf_counter() - begin
        return self.waypoint_to_action(waypoints), state


class RLAgent(FeaturePolicyAgent):
    """A stable-baselines3 model trained on the learning wrappers (``scripts/train_rl.py``).

    ``path`` is the model's ``.zip`` (default: the shipped ``agents/models/<algo>.zip``). Actions
    are the policy's mean unless ``predict(..., deterministic=False)`` asks for samples.

    :param backend: ``"numpy"`` runs the actor exported beside the ``.zip`` (``.npz``,
        :mod:`agents.rl.numpy_policy`; no torch needed), ``"sb3"`` loads the ``.zip`` with
        stable-baselines3, ``"auto"`` (default) takes numpy when the ``.npz`` exists.
    """

    def __init__(self, env, seed: int | None = None, algo: str = "ppo", path: str | Path | None = None, backend: str = "auto"):
        super().__init__(env, seed=seed)
        path, exported, backend = locate_model(path, f"{algo}.zip", backend, "scripts/train_rl.py")
        self.metadata = model_metadata(path)
        self.k_nearest = int(self.metadata["k_nearest"])
        self.backend = backend
        expected = feature_size(self.k_nearest)
        if backend == "numpy":
            self.model = _load_numpy_policy(exported.resolve(), exported.stat().st_mtime)
            size = self.model.observation_size
        else:
            self.model = _load_model(path.resolve(), self.metadata.get("algo", algo), path.stat().st_mtime)
            size = self.model.observation_space.shape[0]
        if size != expected:
            raise ValueError(f"path: model expects observations of size {size}, the wrappers give {expected}")

    def features(self, observation, episode_start=None):
        return egocentric_features(observation, self.facts, self.k_nearest)
