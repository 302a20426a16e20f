"""The arguments of a SARL training run (:mod:`agents.rl.sarl.training.train`), checked on creation:
every field is a flag of ``scripts/train_sarl.py``."""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from agents.rl.sarl.settings import get_setting
from pathplan_env import PRESETS
from pathplan_env.scenarios.splits import training_seed_base


@dataclass
class SARLArgs:
    setting: str = "crowdnav"
    """agents.rl.sarl.settings name (joint-state features, reward) and the shipped model's: agents/models/sarl_<setting>.npz"""
    scenario: str = "crowdnav-circle-crossing"
    """preset name, or comma-separated names: episodes take turns among them (imitation, RL), and validation
    plays ``val_episodes`` in each (CrowdNav trains a model per layout; one model here can cover both)"""
    delta_d: float = 0.8333333333333334
    """CrowdNav's 1 m/s humans (the crowdnav suite's value)"""
    curriculum_max: float = 0.0
    """0: every episode at delta_d; else each draws Δd from [0, d_max], d_max rising from delta_d to this"""
    curriculum_episodes: int = 1500
    """RL episodes over which d_max rises"""
    val_delta_d: str = ""
    """comma-separated Δd of the validation episodes (val_episodes at each); empty: delta_d"""
    seed: int = 0
    """the run's training seeds (pathplan_env.scenarios.splits.training_seed_base) and torch's seed"""
    teacher: str = "orca"
    teacher_kwargs: dict = field(default_factory=lambda: {"safety_space": 0.15})
    il_episodes: int = 1000
    il_epochs: int = 20
    """CrowdNav: 50; the loss levels off by 10 here"""
    il_lr: float = 0.01
    rl_episodes: int = 10000
    rl_lr: float = 0.001
    gamma: float = 0.9
    """discount per second at the robot's speed (CrowdNav's; per step gamma ** (dt · v_pref))"""
    batch_size: int = 100
    train_batches: int = 50
    """SGD minibatches after every RL episode (CrowdNav: 100)"""
    capacity: int = 100_000
    target_update: int = 50
    drop_timeouts: bool = False
    """keep only the episodes that end at the goal or in a collision in the replay memory, imitation's and RL's
    (CrowdNav's explorer rule); False: every episode, a timeout's last step taken as terminal"""
    ema_decay: float = 0.0
    """0: off; else an exponential moving average of the weights (this factor on the old average, updated after
    every RL episode's minibatches) is validated beside the trained weights, and the better on validation is kept"""
    epsilon_start: float = 0.5
    epsilon_end: float = 0.1
    epsilon_decay: int = 2000
    """RL episodes over which epsilon falls linearly"""
    val_every: int = 250
    val_episodes: int = 100
    budget_minutes: float = 58.0
    """wall clock for the whole run (demonstrations, imitation, RL, validations)"""
    out: str = "runs/sarl_crowdnav"
    ship: bool = True
    """copy the best model to agents/models/ and its curve to docs/results/sarl/"""
    model_name: str = ""
    """the shipped files' name: agents/models/<model_name>.npz (empty: sarl_<setting>, the agent's default)"""

    def __post_init__(self):
        for name in ("il_episodes", "il_epochs", "rl_episodes", "train_batches"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or value < 0:
                raise ValueError(f"{name} must be an int >= 0, got {value!r}")
        for name in ("batch_size", "capacity", "target_update", "epsilon_decay", "val_every", "val_episodes", "curriculum_episodes"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or value < 1:
                raise ValueError(f"{name} must be an int >= 1, got {value!r}")
        for name in ("il_lr", "rl_lr", "budget_minutes"):
            if not getattr(self, name) > 0:
                raise ValueError(f"{name} must be positive, got {getattr(self, name)!r}")
        if not 0 < self.gamma <= 1:
            raise ValueError(f"gamma must be in (0, 1], got {self.gamma!r}")
        if isinstance(self.ema_decay, bool) or not isinstance(self.ema_decay, (int, float)) or not 0 <= self.ema_decay < 1:
            raise ValueError(f"ema_decay must be in [0, 1), got {self.ema_decay!r}")
        for name in ("epsilon_start", "epsilon_end"):
            if not 0 <= getattr(self, name) <= 1:
                raise ValueError(f"{name} must be in [0, 1], got {getattr(self, name)!r}")
        training_seed_base(self.seed)  # a ValueError naming seed
        if self.model_name and not re.fullmatch(r"[A-Za-z0-9_.-]+", self.model_name):
            raise ValueError(f"model_name must be a file stem (letters, digits, _ . -), got {self.model_name!r}")
        if any(name not in PRESETS for name in self.scenarios) or len(set(self.scenarios)) != len(self.scenarios):
            raise ValueError(f"scenario must be preset names (pathplan_env.PRESETS), comma-separated, none repeated, got {self.scenario!r}")
        get_setting(self.setting)  # a ValueError naming setting
        for name in ("delta_d", "curriculum_max"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not 0 <= value < float("inf"):
                raise ValueError(f"{name} must be a finite number >= 0, got {value!r}")
        if self.curriculum_max and self.curriculum_max < self.delta_d:
            raise ValueError(f"curriculum_max must be 0 or >= delta_d ({self.delta_d}), got {self.curriculum_max!r}")
        try:
            values = self.validation_delta_d
        except ValueError:
            values = None
        if not values or any(not 0 <= v < float("inf") for v in values):
            raise ValueError(f"val_delta_d must be comma-separated Δd >= 0 (or empty), got {self.val_delta_d!r}")

    @property
    def shipped_name(self) -> str:
        return self.model_name or f"sarl_{self.setting}"

    @property
    def scenarios(self) -> list[str]:
        return [name.strip() for name in self.scenario.split(",")]

    @property
    def validation_delta_d(self) -> list[float]:
        return [float(v) for v in self.val_delta_d.split(",")] if self.val_delta_d.strip() else [float(self.delta_d)]
