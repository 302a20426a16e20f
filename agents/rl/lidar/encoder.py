"""A 1-D convolution encoder of the lidar scan for SB3 policies, as NavRep's and DRL-VO's (torch).

:class:`LidarConvExtractor` reads :mod:`agents.rl.lidar.features`' flat ``Box``: the robot's
features pass through, the scan (``frames`` channels of ``bins``) goes through ``Conv1d + ReLU``
layers with stride 2 and *circular* padding (a 360° scan has no ends: the sector behind the robot
borders both ends of the array), is flattened, then a ``Linear + ReLU`` to ``scan_features``; the
two are concatenated, and SB3's usual policy and value MLPs follow. A flat ``Box`` (not a ``Dict``
under ``MultiInputPolicy``) because the features are already one goal-frame vector, and it keeps
PPO's ``"MlpPolicy"`` with only ``features_extractor_class`` changed.

``agents.rl.lidar.numpy_encoder`` computes the same forward pass in numpy (tested equal within 1e-5).
"""

from __future__ import annotations

import gymnasium as gym
import torch
from stable_baselines3.common.torch_layers import BaseFeaturesExtractor
from torch import nn

from agents.rl.lidar.features import ROBOT_FEATURES


def parse_channels(text: str) -> list[int]:
    """``"16,32,32"`` as layer widths; a ``ValueError`` naming ``conv_channels`` otherwise."""
    try:
        widths = [int(n) for n in str(text).split(",")]
    except ValueError:
        widths = []
    if not widths or min(widths) < 1:
        raise ValueError(f"conv_channels must be comma-separated positive widths such as '16,16,16', got {text!r}")
    return widths


class LidarConvExtractor(BaseFeaturesExtractor):
    """Conv1d encoder of the scan part of a lidar feature vector, concatenated with the robot part.

    :param bins: scan values per channel.
    :param frames: scan channels (1: the scan; 2: the scan and its change since the last step).
    :param channels: output channels of each convolution (kernel 5 for the first, 3 after; stride 2).
    :param scan_features: width of the linear layer after the convolutions.
    """

    def __init__(self, observation_space: gym.spaces.Box, bins: int, frames: int, channels: str = "16,16,16", scan_features: int = 128):
        widths = parse_channels(channels)
        if observation_space.shape != (ROBOT_FEATURES + frames * bins,):
            raise ValueError(f"observation_space: expected shape ({ROBOT_FEATURES + frames * bins},) for {frames} x {bins} bins, got {observation_space.shape}")
        super().__init__(observation_space, features_dim=ROBOT_FEATURES + scan_features)
        self.bins, self.frames = bins, frames
        layers, width, length = [], frames, bins
        for i, out in enumerate(widths):
            kernel = 5 if i == 0 else 3
            layers += [nn.Conv1d(width, out, kernel, stride=2, padding=kernel // 2, padding_mode="circular"), nn.ReLU()]
            width, length = out, (length + 2 * (kernel // 2) - kernel) // 2 + 1
        self.conv = nn.Sequential(*layers, nn.Flatten())
        self.linear = nn.Sequential(nn.Linear(width * length, scan_features), nn.ReLU())

    def forward(self, observations: torch.Tensor) -> torch.Tensor:
        robot = observations[:, :ROBOT_FEATURES]
        scan = observations[:, ROBOT_FEATURES:].reshape(-1, self.frames, self.bins)
        return torch.cat([robot, self.linear(self.conv(scan))], dim=1)


__all__ = ["LidarConvExtractor", "parse_channels"]
