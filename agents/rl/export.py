"""Export any shipped kind of PPO to numpy: the exporter chosen by the model's features extractor."""

from __future__ import annotations

from pathlib import Path

from agents.rl.lidar.numpy_encoder import export_lidar_policy
from agents.rl.numpy_policy import export_policy
from agents.rl.obstacle_set.numpy_net import export_set_policy


def export_any_policy(model, path: str | Path) -> Path:
    """Write ``model``'s actor to ``path`` (``.npz``): :func:`~agents.rl.obstacle_set.numpy_net.export_set_policy`
    for a set encoder, :func:`~agents.rl.lidar.numpy_encoder.export_lidar_policy` for the lidar's
    convolutions, :func:`~agents.rl.numpy_policy.export_policy` for flat features."""
    from stable_baselines3.common.torch_layers import FlattenExtractor

    from agents.rl.lidar.encoder import LidarConvExtractor
    from agents.rl.obstacle_set.encoder import SetAttentionExtractor

    extractor = model.policy.features_extractor
    if isinstance(extractor, SetAttentionExtractor):
        return export_set_policy(model, path)
    if isinstance(extractor, LidarConvExtractor):
        return export_lidar_policy(model, path)
    if isinstance(extractor, FlattenExtractor):
        return export_policy(model, path)
    raise ValueError(f"model: no numpy exporter for the features extractor {type(extractor).__name__}")
