"""A training run's arguments: one dataclass, a docstring under each field (CleanRL's style).

``scripts/train_rl.py`` builds its flags from these fields and their docstrings; the PPO defaults
come from ``pathplan_env.zoo.PPO_SETTINGS``, the one source rl-zoo3's hyperparameters share.
"""

from __future__ import annotations

import argparse
import ast
import dataclasses
import inspect
import json
import shlex
from dataclasses import dataclass

from agents.rl.lidar.features import check_lidar_settings
from agents.rl.obstacle_set.features import check_n_tokens, check_pooling, parse_hidden
from pathplan_env.scenarios.presets import PRESETS
from pathplan_env.scenarios.splits import training_seed_base
from pathplan_env.sensors.range_sensor import SensorParams
from pathplan_env.zoo import PPO_SETTINGS

#: How a run is started from a shell (``Args.command_line``).
SCRIPT = "scripts/train_rl.py"


@dataclass
class Args:
    """A training run on DynamicObstacle-v0 (``agents.rl.training.train``); checked on construction."""

    algo: str = "ppo"
    """ppo or sac"""
    total_timesteps: int = PPO_SETTINGS.n_timesteps
    """PPO (or SAC) env steps after the warm start"""
    seed: int = 0
    """run seed: torch, and the training episode seeds (pathplan_env.scenarios.splits.training_seed_base)"""
    n_envs: int = PPO_SETTINGS.n_envs
    """parallel training envs"""
    vec_env: str = "dummy"
    """dummy (one process; best on 2 cores) or subproc"""
    n_obstacles_min: int = 4
    """fewest obstacles of a training episode (drawn uniformly per episode)"""
    n_obstacles_max: int = 12
    """most obstacles of a training episode"""
    delta_d_start: float = 0.25
    """Δd of training episodes is drawn from [0, this] at first"""
    delta_d_max: float = 1.0
    """... widening to [0, this]"""
    curriculum_fraction: float = 0.3
    """share of training over which the Δd range widens"""
    static_fraction: float = 0.0
    """share of training episodes with Δd = 0 (static obstacles)"""
    k_nearest: int = 8
    """obstacles in the observation features (nearest by surface gap; observation 'state')"""
    observation: str = "state"
    """what the policy sees: 'state' (the k nearest obstacles, an MLP), 'lidar' (a scan, a 1-D convolution encoder; ppo only)
    or 'set' (every obstacle as a token, an attention set encoder; ppo only)"""
    observation_params: str = ""
    """JSON of the 'lidar' observation's parameters (pathplan_env.sensors.range_sensor: lidar_beams, lidar_range, ...); '' = the defaults"""
    lidar_bins: int = 90
    """the scan is min-pooled into this many bins (must divide lidar_beams)"""
    lidar_frames: int = 2
    """scan channels: 1 (the scan) or 2 (and its change since the last step: motion)"""
    conv_channels: str = "16,16,16"
    """output channels of the lidar encoder's stride-2 convolutions"""
    set_tokens: int = 12
    """obstacle tokens of the 'set' observation (the nearest by surface gap; padded and masked)"""
    set_hidden: str = "64,64"
    """widths of the set encoder's token embedding MLP (the last is the pooled width)"""
    set_pooling: str = "attention"
    """the set encoder's pooling: 'attention' (SARL's) or 'mean' (DeepSets')"""
    scenarios: str = "random"
    """comma-separated presets of the training envs, dealt to them in turn (repeat a name to weight it); validation runs one env per distinct name"""
    learning_rate: float = PPO_SETTINGS.learning_rate
    """gentle by default: PPO fine-tunes the behaviour-cloned policy"""
    log_std_init: float = PPO_SETTINGS.log_std_init
    """initial exploration noise (std e^-1 = 0.37 of a step's reach) around the cloned mean action"""
    ent_coef: float = PPO_SETTINGS.ent_coef
    """PPO entropy bonus"""
    n_steps: int = PPO_SETTINGS.n_steps
    """PPO rollout length per env"""
    reward_collision: float = -1.0
    """the env's collision penalty during training (evaluation always uses the env's default)"""
    reward_proximity: float = PPO_SETTINGS.reward_proximity
    """CrowdNav-style discomfort penalty within 0.5 m of an obstacle, for training only (0 = off)"""
    teacher: str = "velocity-obstacle"
    """warm start: behaviour-clone this planner's successful episodes before RL (CrowdNav's IL + RL); '' = none"""
    teacher_steps: int = 200_000
    """env steps of teacher demonstrations"""
    teacher_epochs: int = 20
    """behaviour-cloning epochs over the demonstrations"""
    net_arch: str = ",".join(str(size) for size in PPO_SETTINGS.net_arch)
    """hidden layer sizes of the policy and value MLPs"""
    eval_freq: int = 100_000
    """env steps between validation evaluations"""
    eval_episodes: int = 100
    """validation episodes per evaluation (the same ones every time)"""
    eval_delta_d: float = 0.25
    """Δd of the validation episodes"""
    checkpoint_freq: int = 500_000
    """env steps between checkpoints"""
    budget_minutes: float = 0.0
    """stop RL when this much wall time has passed since the run began (demonstrations and cloning included); 0 = no limit"""
    torch_threads: int = 1
    """torch CPU threads"""
    out: str = "runs/ppo"
    """output directory"""
    ship: str = ""
    """'best' or 'final': copy that model to agents/models/<algo>.zip with its metadata (curve to docs/results/)"""
    progress: bool = True
    """show a progress bar"""

    def __post_init__(self):
        if self.algo not in ("ppo", "sac"):
            raise ValueError(f"algo must be 'ppo' or 'sac', got {self.algo!r}")
        if self.teacher and self.algo != "ppo":
            raise ValueError(f"teacher: the behaviour-cloning warm start is implemented for ppo; pass --teacher '' with algo {self.algo!r}")
        if self.vec_env not in ("dummy", "subproc"):
            raise ValueError(f"vec_env must be 'dummy' or 'subproc', got {self.vec_env!r}")
        if self.ship not in ("", "best", "final"):
            raise ValueError(f"ship must be 'best' or 'final', got {self.ship!r}")
        for name in ("total_timesteps", "n_envs", "eval_freq", "eval_episodes", "checkpoint_freq", "k_nearest"):
            if getattr(self, name) < 1:
                raise ValueError(f"{name} must be >= 1, got {getattr(self, name)!r}")
        if self.eval_freq > self.total_timesteps:
            raise ValueError(
                f"eval_freq ({self.eval_freq}) must be <= total_timesteps ({self.total_timesteps}): "
                "otherwise no validation runs and there is no best model or learning curve"
            )
        if not 0 <= self.n_obstacles_min <= self.n_obstacles_max:
            raise ValueError(f"n_obstacles_min/max must satisfy 0 <= min <= max, got {self.n_obstacles_min}, {self.n_obstacles_max}")
        if not 0 <= self.delta_d_start <= self.delta_d_max:
            raise ValueError(f"delta_d_start/max must satisfy 0 <= start <= max, got {self.delta_d_start}, {self.delta_d_max}")
        if not self.budget_minutes >= 0:
            raise ValueError(f"budget_minutes must be >= 0, got {self.budget_minutes!r}")
        if not 0 <= self.curriculum_fraction <= 1:
            raise ValueError(f"curriculum_fraction must be in [0, 1], got {self.curriculum_fraction}")
        self.hidden_sizes()  # "128,128": checked here, used by build_model
        self.scenario_list()
        self.sensor_params()
        if self.observation == "lidar":
            if self.algo != "ppo":
                raise ValueError(f"observation: 'lidar' (the convolution encoder) is implemented for ppo, got algo {self.algo!r}")
            params = SensorParams.of(self.sensor_params(), SensorParams._fields)
            check_lidar_settings(params.lidar_beams, params.lidar_fov, self.lidar_bins, self.lidar_frames)
            widths = [w.strip() for w in self.conv_channels.split(",")]
            if not all(w.isdigit() and int(w) > 0 for w in widths):
                raise ValueError(f"conv_channels must be comma-separated positive widths such as '16,16,16', got {self.conv_channels!r}")
        if self.observation == "set":
            if self.algo != "ppo":
                raise ValueError(f"observation: 'set' (the set encoder) is implemented for ppo, got algo {self.algo!r}")
            check_n_tokens(self.set_tokens, "set_tokens")
            parse_hidden(self.set_hidden, "set_hidden")
            check_pooling(self.set_pooling, "set_pooling")
        training_seed_base(self.seed)  # range check

    def env_observation(self) -> str:
        """The env's observation type: the set policy reads ``"state"`` (every obstacle's position and velocity)."""
        return "state" if self.observation == "set" else self.observation

    def scenario_list(self) -> list[str]:
        """``scenarios`` as preset names, one per training env in turn."""
        names = [name.strip() for name in self.scenarios.split(",")]
        unknown = [name for name in names if name not in PRESETS]
        if not names or unknown:
            raise ValueError(f"scenarios: unknown presets {unknown} in {self.scenarios!r}; known: {sorted(PRESETS)}")
        return names

    def sensor_params(self) -> dict:
        """``observation_params`` as the env's ``observation_params`` dict (``{}`` for 'state')."""
        if self.observation not in ("state", "lidar", "set"):
            raise ValueError(f"observation must be 'state', 'lidar' or 'set', got {self.observation!r}")
        if not self.observation_params:
            return {}
        if self.observation != "lidar":
            raise ValueError(f"observation_params: observation {self.observation!r} takes none")
        try:
            params = json.loads(self.observation_params)
        except json.JSONDecodeError as error:
            raise ValueError(f"observation_params must be a JSON object, got {self.observation_params!r} ({error})") from None
        if not isinstance(params, dict):
            raise ValueError(f"observation_params must be a JSON object, got {self.observation_params!r}")
        SensorParams.of(params, SensorParams._fields)  # each field checked, named
        return params

    def hidden_sizes(self) -> list[int]:
        """``net_arch`` as layer sizes."""
        try:
            sizes = [int(n) for n in self.net_arch.split(",")]
        except ValueError:
            sizes = []
        if not sizes or min(sizes) < 1:
            raise ValueError(f"net_arch must be comma-separated positive layer sizes such as '128,128', got {self.net_arch!r}")
        return sizes

    def command_line(self) -> str:
        """The shell command that starts this run: ``python scripts/train_rl.py`` and the flags that differ from the defaults."""
        words = ["python", SCRIPT]
        for field in dataclasses.fields(self):
            value = getattr(self, field.name)
            if value == field.default:
                continue
            flag = field.name.replace("_", "-")
            words += [f"--{flag}" if value else f"--no-{flag}"] if isinstance(value, bool) else [f"--{flag}", str(value)]
        return shlex.join(words)


def field_docs(cls) -> dict[str, str]:
    """The docstring under each dataclass field (CleanRL's style), read from the source."""
    body = ast.parse(inspect.getsource(cls)).body[0].body
    docs = {}
    for node, after in zip(body, body[1:], strict=False):
        if isinstance(node, ast.AnnAssign) and isinstance(after, ast.Expr) and isinstance(after.value, ast.Constant):
            docs[node.target.id] = " ".join(str(after.value.value).split())
    return docs


def dataclass_parser(cls, description: str) -> argparse.ArgumentParser:
    """A command line whose flags are ``cls``'s fields (``--total-timesteps``; a bool gives ``--x`` and
    ``--no-x``), each with its field's docstring and default."""
    parser = argparse.ArgumentParser(description=description, formatter_class=argparse.RawDescriptionHelpFormatter)
    docs = field_docs(cls)
    for f in dataclasses.fields(cls):
        flag = "--" + f.name.replace("_", "-")
        text = docs.get(f.name, "").replace("%", "%%") + " (default: %(default)r)"
        if f.type == "bool":
            parser.add_argument(flag, action=argparse.BooleanOptionalAction, default=f.default, help=text)
        else:
            parser.add_argument(flag, type={"int": int, "float": float}.get(f.type, str), default=f.default, help=text)
    return parser


def parse_dataclass(cls, parser: argparse.ArgumentParser, argv=None):
    """``cls`` from the command line; a bad combination (the dataclass's ``ValueError``) is one line, before any work."""
    try:
        return cls(**vars(parser.parse_args(argv)))
    except ValueError as error:
        parser.error(str(error))
