"""A trained set-encoder PPO as an agent: every obstacle a token, attention pooling, no torch at run time.

``scripts/train_rl.py --observation set`` trains it: :mod:`agents.rl.obstacle_set.features` turns the
``"state"`` observation into distance-sorted obstacle tokens (with their predicted positions), a
presence mask and an ego token; :mod:`agents.rl.obstacle_set.encoder` pools them (SARL's attention); PPO acts
in the learning wrappers' relative-waypoint space. :mod:`agents.rl.obstacle_set.numpy_net` runs the exported
``.npz`` without torch::

    agent = agents.make("ppo-set", env)                                   # agents/models/ppo_set.zip (.npz)
    agent = agents.make("ppo-set", env, path="runs/ppo_set/best_model.zip", backend="sb3")
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

from agents.rl.obstacle_set.features import check_n_tokens, set_feature_size, set_features
from agents.rl.obstacle_set.numpy_net import NumpySetPolicy
from agents.rl.policy import FeaturePolicyAgent, _load_model, locate_model, model_metadata


@lru_cache(maxsize=8)
def _load_numpy_set_policy(path: Path, mtime: float) -> NumpySetPolicy:
    return NumpySetPolicy(path)


class SetRLAgent(FeaturePolicyAgent):
    """A PPO trained on the set features (``scripts/train_rl.py --observation set``).

    :param path: the model's ``.zip`` (default: the shipped ``agents/models/ppo_set.zip``), with its
        ``.json`` sidecar beside it.
    :param backend: ``"numpy"`` (the exported ``.npz``; no torch), ``"sb3"`` or ``"auto"`` (numpy if the
        ``.npz`` exists).
    :raises ValueError: naming ``backend`` or ``path`` (no model, or one not trained on the set features).
    """

    name = "ppo-set"

    def __init__(self, env, seed: int | None = None, path: str | Path | None = None, backend: str = "auto"):
        super().__init__(env, seed=seed)
        path, exported, backend = locate_model(path, "ppo_set.zip", backend, "scripts/train_rl.py --observation set")
        self.metadata = model_metadata(path)
        args = self.metadata["args"]
        if args.get("observation") != "set":
            raise ValueError(f"path: {path} was trained on observation {args.get('observation', 'state')!r}, not 'set'")
        self.n_tokens = check_n_tokens(int(args["set_tokens"]), "set_tokens")
        self.backend = backend
        if backend == "numpy":
            self.model = _load_numpy_set_policy(exported.resolve(), exported.stat().st_mtime)
            size = self.model.observation_size
        else:
            self.model = _load_model(path.resolve(), "ppo", path.stat().st_mtime)
            size = self.model.observation_space.shape[0]
        if size != set_feature_size(self.n_tokens):
            raise ValueError(f"path: model expects features of size {size}, {self.n_tokens} tokens give {set_feature_size(self.n_tokens)}")

    def features(self, observation, episode_start=None):
        return set_features(observation, self.facts, self.n_tokens)


__all__ = ["SetRLAgent"]
