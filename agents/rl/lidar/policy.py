"""A trained lidar policy as an agent: it reads the ``"lidar"`` observation (no obstacle list, no map).

``scripts/train_rl.py --observation lidar`` trains it: :mod:`agents.rl.lidar.features` turns the scan
into the goal's frame, :mod:`agents.rl.lidar.encoder` encodes it with 1-D convolutions (NavRep's and
DRL-VO's choice), PPO acts in the learning wrappers' relative-waypoint space. Run it on an env made
with ``observation="lidar"`` and the sensor it was trained with (the sidecar's ``observation_params``):

    env = gym.make("DynamicObstacle-v0", scenario="doorway", observation="lidar")
    agent = agents.make("ppo-lidar", env)                  # agents/models/ppo_lidar.zip (.npz: no torch)
    agent = agents.make("ppo-lidar", env, path="runs/ppo_lidar/best_model.zip", backend="sb3")
"""

from __future__ import annotations

import json
from functools import lru_cache
from pathlib import Path

import numpy as np

from agents.rl.lidar.features import LidarFeatureStack, check_lidar_settings, lidar_feature_size
from agents.rl.lidar.numpy_encoder import NumpyLidarPolicy
from agents.rl.policy import FeaturePolicyAgent, _load_model, locate_model, model_metadata
from pathplan_env.sensors.range_sensor import SensorParams


@lru_cache(maxsize=8)
def _load_numpy_lidar_policy(path: Path, mtime: float) -> NumpyLidarPolicy:
    return NumpyLidarPolicy(path)


class LidarRLAgent(FeaturePolicyAgent):
    """A PPO trained on the ``"lidar"`` observation (``scripts/train_rl.py --observation lidar``).

    It remembers each env's last scan (``lidar_frames = 2``: the scan's change is its motion cue);
    ``reset()`` and ``predict(..., episode_start=...)`` forget it.

    :param path: the model's ``.zip`` (default: the shipped ``agents/models/ppo_lidar.zip``), with its
        ``.json`` sidecar beside it.
    :param backend: ``"numpy"`` (the exported ``.npz``; no torch), ``"sb3"`` or ``"auto"`` (numpy if the
        ``.npz`` exists).
    :raises ValueError: naming ``env`` if its observation is not the lidar the model was trained with.
    """

    name = "ppo-lidar"

    def __init__(self, env, seed: int | None = None, path: str | Path | None = None, backend: str = "auto"):
        super().__init__(env, seed=seed)
        path, exported, backend = locate_model(path, "ppo_lidar.zip", backend, "scripts/train_rl.py --observation lidar")
        self.metadata = model_metadata(path)
        args = self.metadata["args"]
        if args.get("observation") != "lidar":
            raise ValueError(f"path: {path} was trained on observation {args.get('observation', 'state')!r}, not 'lidar'")
        trained = json.loads(args.get("observation_params") or "{}")  # the run's Args field: JSON text
        self._check_sensor(env, SensorParams.of(trained, SensorParams._fields), args)
        self.backend = backend
        if backend == "numpy":
            self.model = _load_numpy_lidar_policy(exported.resolve(), exported.stat().st_mtime)
            size = self.model.observation_size
        else:
            self.model = _load_model(path.resolve(), "ppo", path.stat().st_mtime)
            size = self.model.observation_space.shape[0]
        bins, frames = int(args["lidar_bins"]), int(args["lidar_frames"])
        if size != lidar_feature_size(bins, frames):
            raise ValueError(f"path: model expects features of size {size}, {frames} x {bins} bins give {lidar_feature_size(bins, frames)}")
        self.stack = LidarFeatureStack(self.facts, bins, frames)

    @staticmethod
    def _check_sensor(env, trained: SensorParams, args: dict) -> None:
        space = getattr(env, "observation_space", None)
        lidar = getattr(space, "spaces", {}).get("lidar") if space is not None else None
        if lidar is None:
            raise ValueError("env: ppo-lidar reads the 'lidar' observation; make the env with observation='lidar'")
        if lidar.shape[-1] != trained.lidar_beams or not np.isclose(float(np.max(lidar.high)), trained.lidar_range):
            raise ValueError(f"env: its lidar has {lidar.shape[-1]} beams of range {float(np.max(lidar.high)):g} m; the model was trained "
                             f"with {trained.lidar_beams} beams of {trained.lidar_range:g} m (observation_params)")  # fmt: skip
        check_lidar_settings(trained.lidar_beams, trained.lidar_fov, int(args["lidar_bins"]), int(args["lidar_frames"]))

    def reset(self) -> None:
        super().reset()
        self.stack.reset()

    def features(self, observation, episode_start=None):
        return self.stack(observation, episode_start)


__all__ = ["LidarRLAgent"]
