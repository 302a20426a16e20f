"""The lidar encoder (``agents.rl.lidar.encoder.LidarConvExtractor``) and its PPO actor in numpy: no torch needed.

Stride-2 ``Conv1d + ReLU`` layers with circular padding over the scan channels, flattened
(channel-major, as ``torch.nn.Flatten``), a ``Linear + ReLU``, then the robot's features in front.
Each convolution is one ``einsum`` over ``sliding_window_view``'s windows of the wrapped scan;
equal to the torch forward within 1e-5 (tested).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view

from agents.rl.numpy_policy import NumpyPolicy, write_actor

#: The ``.npz`` keys of an exported encoder start with this (``export_encoder``, ``NumpyConvEncoder``).
PREFIX = "encoder_"


def conv1d_circular(x: np.ndarray, weight: np.ndarray, bias: np.ndarray, stride: int) -> np.ndarray:
    """``torch.nn.Conv1d(..., padding=k // 2, padding_mode="circular")`` of ``x`` (N, C, L) with
    ``weight`` (O, C, k) and ``bias`` (O,): (N, O, L_out)."""
    pad = weight.shape[-1] // 2
    wrapped = np.concatenate([x[..., x.shape[-1] - pad :], x, x[..., :pad]], axis=-1) if pad else x
    windows = sliding_window_view(wrapped, weight.shape[-1], axis=-1)[..., ::stride, :]  # (N, C, L_out, k)
    return np.einsum("nclk,ock->nol", windows, weight, optimize=True) + bias[:, None]


class NumpyConvEncoder:
    """The features extractor's forward pass from an exported ``.npz`` (:func:`export_encoder`'s keys)."""

    def __init__(self, data):
        self.robot_features, self.bins, self.frames = (int(data[PREFIX + name]) for name in ("robot_features", "bins", "frames"))
        layers = int(data[PREFIX + "layers"])
        self.convs = [(data[f"{PREFIX}conv_w{i}"], data[f"{PREFIX}conv_b{i}"], int(data[f"{PREFIX}conv_stride{i}"])) for i in range(layers)]
        self.linear = (data[PREFIX + "linear_w"], data[PREFIX + "linear_b"])  # (in, out), (out,)

    def __call__(self, features: np.ndarray) -> np.ndarray:
        x = np.asarray(features, np.float32)
        single = x.ndim == 1
        x = np.atleast_2d(x)
        robot = x[:, : self.robot_features]
        scan = x[:, self.robot_features :].reshape(len(x), self.frames, self.bins)
        for weight, bias, stride in self.convs:
            scan = np.maximum(conv1d_circular(scan, weight, bias, stride), 0.0)
        encoded = np.maximum(scan.reshape(len(x), -1) @ self.linear[0] + self.linear[1], 0.0)
        out = np.concatenate([robot, encoded], axis=1).astype(np.float32)
        return out[0] if single else out


def export_encoder(extractor) -> dict[str, np.ndarray]:
    """The arrays of a ``LidarConvExtractor`` (torch) as :class:`NumpyConvEncoder` reads them."""
    import torch

    convs = [m for m in extractor.conv if isinstance(m, torch.nn.Conv1d)]
    for conv in convs:
        if conv.padding_mode != "circular" or conv.padding[0] != conv.kernel_size[0] // 2 or conv.dilation[0] != 1:
            raise ValueError(f"model: only circular, undilated convolutions padded by k // 2 export, got {conv}")
    linear = next(m for m in extractor.linear if isinstance(m, torch.nn.Linear))
    arrays = {
        PREFIX + "robot_features": np.array(extractor.features_dim - linear.out_features), PREFIX + "bins": np.array(extractor.bins),
        PREFIX + "frames": np.array(extractor.frames), PREFIX + "layers": np.array(len(convs)),
        PREFIX + "linear_w": linear.weight.detach().cpu().numpy().T.astype(np.float32),
        PREFIX + "linear_b": linear.bias.detach().cpu().numpy().astype(np.float32),
    }  # fmt: skip
    for i, conv in enumerate(convs):
        arrays[f"{PREFIX}conv_w{i}"] = conv.weight.detach().cpu().numpy().astype(np.float32)
        arrays[f"{PREFIX}conv_b{i}"] = conv.bias.detach().cpu().numpy().astype(np.float32)
        arrays[f"{PREFIX}conv_stride{i}"] = np.array(conv.stride[0])
    return arrays


class NumpyLidarPolicy(NumpyPolicy):
    """:class:`~agents.rl.numpy_policy.NumpyPolicy` whose features go through the exported convolution encoder first."""

    encoder_key, encoder_kind = PREFIX + "layers", "lidar"

    def encoder_of(self, data) -> NumpyConvEncoder:
        return NumpyConvEncoder(data)


def export_lidar_policy(model, path: str | Path) -> Path:
    """Write ``model``'s (an SB3 PPO whose ``MlpPolicy`` shares a ``LidarConvExtractor``) actor to
    ``path`` (``.npz``), as :class:`NumpyLidarPolicy` reads it."""
    from agents.rl.lidar.encoder import LidarConvExtractor

    policy = model.policy
    if not isinstance(policy.features_extractor, LidarConvExtractor) or not policy.share_features_extractor:
        raise ValueError(f"model: expected a shared LidarConvExtractor, got {type(policy.features_extractor).__name__}")
    return write_actor(model, path, export_encoder(policy.features_extractor))


__all__ = ["NumpyConvEncoder", "NumpyLidarPolicy", "conv1d_circular", "export_encoder", "export_lidar_policy"]
