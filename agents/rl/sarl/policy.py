"""SARL (Chen et al. 2019) as an agent: a value network with attention over the humans and a
lookahead over 81 moves, one step (SARL's) or two along the best few (RGL's), run with numpy (no torch).

``scripts/train_sarl.py`` trains it (:mod:`agents.rl.sarl.training.train`); the lookahead is
:mod:`agents.rl.sarl.lookahead` (the humans' next state predicted from the observation, never read
from the simulator), the network :mod:`agents.rl.sarl.numpy_net`:

    env = gym.make("DynamicObstacle-v0", scenario="crowdnav-circle-crossing")
    agent = agents.make("sarl", env)                       # agents/models/sarl_crowdnav.npz
    agent = agents.make("sarl", env, path="runs/sarl/best.npz")
    agent = agents.make("sarl-random", gym.make("DynamicObstacle-v0", scenario="random", delta_d=1))  # sarl_random.npz
    agent = agents.make("sarl-crossings", gym.make("DynamicObstacle-v0", scenario="crowdnav-square-crossing"))  # sarl_crowdnav_crossings.npz
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from agents.base import Agent
from agents.rl.policy import MODELS_DIR
from agents.rl.sarl.lookahead import action_velocities, discount
from agents.rl.sarl.numpy_net import SARLNumpy
from agents.rl.sarl.planning import best_action_two_steps, check_width
from agents.rl.sarl.settings import get_setting
from agents.rl.sarl.standing import all_standing, standing_scores

#: ``velocity`` names: the robot's velocity features (goal frame, robot speeds) every move's next state shows; None: the move's own.
VELOCITY_FEATURES = {"move": None, "goal": (1.0, 0.0), "zero": (0.0, 0.0)}
#: The shipped model per setting (``agents/models/sarl_<setting>.npz``).
DEFAULT_SETTING = "crowdnav"


class SARLAgent(Agent):
    """A trained SARL value network acting by one-step lookahead (greedy: ``deterministic`` changes nothing).

    :param path: the model's ``.npz`` (default ``agents/models/<model>.npz``); its ``.json``
        sidecar, when present, gives ``gamma`` and the setting it was trained in.
    :param model: a shipped model's name in ``agents/models/`` (default ``sarl_<setting>``), used without ``path``.
    :param gamma: the discount per second of travel at the robot's speed (default: the sidecar's, else 0.9).
    :param setting: ``agents.rl.sarl.settings`` name: the joint state's features and the reward (default:
        the sidecar's, else ``crowdnav``).
    :param velocity: the robot's velocity shown in each move's next state: ``"move"`` (the move's own, CrowdNav's)
        or ``"goal"`` (full speed at the goal for every move; ``"zero"``: standing; for a holonomic robot the humans do not see, the
        value should not depend on it, and the learned dependence otherwise picks slow moves; validation on the first
        circle model, trained with the velocity: 0.99 at 11.19 s against 11.62 s, ``docs/results/sarl/time_gap.md``).
    :param planning_width: ``w`` > 0: RGL's two-step planning over the ``w`` best moves (:mod:`agents.rl.sarl.planning`;
        about ``1 + w`` forwards a step); 0: CrowdNav's one-step lookahead, as the models were trained. The default 3 was
        chosen on validation episodes (``docs/results/sarl.md``, commit fc33d36); the value is the same network either way.
    :param standing_search: when every human stands (slower than 5 % of the robot's speed, and at the step before), solve the still scene by
        value iteration on a grid with the learned value as a stopping payoff (:mod:`agents.rl.sarl.standing`), so
        that the robot does not freeze on a local maximum of its value; False: the lookahead alone (as with LM-SARL's
        local map, whose grid this does not build).
    :raises ValueError: naming ``path`` if no model is there or its inputs do not fit the setting's
        features, ``gamma`` if it is not in (0, 1], ``setting`` or ``velocity`` if unknown, ``velocity`` if not
        ``"move"`` for a model trained without the robot's velocity (``crowdnav-no-robot-velocity``: nothing to substitute),
        ``planning_width`` if not an int >= 0, ``standing_search`` if not a bool.
    """

    name = "sarl"

    def __init__(self, env, seed: int | None = None, path: str | Path | None = None, gamma: float | None = None,
                 setting: str | None = None, model: str | None = None, velocity: str = "move", planning_width: int = 3,
                 standing_search: bool = True):  # fmt: skip
        super().__init__(env, seed=seed)
        if velocity not in VELOCITY_FEATURES:
            raise ValueError(f"velocity must be one of {sorted(VELOCITY_FEATURES)}, got {velocity!r}")
        self.planning_width = check_width(planning_width)
        if not isinstance(standing_search, bool):
            raise ValueError(f"standing_search must be True or False, got {standing_search!r}")
        self.standing_search = standing_search
        self.velocity_features = VELOCITY_FEATURES[velocity]
        if setting is not None:
            get_setting(setting)  # a ValueError naming setting, before the path's
        path = Path(path) if path is not None else MODELS_DIR / f"{model or 'sarl_' + (setting or DEFAULT_SETTING)}.npz"
        if not path.exists():
            raise ValueError(f"path: no model at {path}; train one with scripts/train_sarl.py")
        sidecar = path.with_suffix(".json")
        self.metadata = json.loads(sidecar.read_text()) if sidecar.exists() else {}
        trained = self.metadata.get("args", {})
        self.setting = get_setting(setting or trained.get("setting", DEFAULT_SETTING))
        gamma = float(trained.get("gamma", 0.9)) if gamma is None else gamma
        if isinstance(gamma, bool) or not isinstance(gamma, (int, float)) or not 0 < gamma <= 1:
            raise ValueError(f"gamma must be in (0, 1], got {gamma!r}")
        self.network = SARLNumpy.load(path)
        if (self.network.self_dim, self.network.human_dim) != self.setting.features.dims:
            raise ValueError(f"path: {path} takes joint states of {(self.network.self_dim, self.network.human_dim)} features, "
                             f"its setting {self.setting.features.dims}")  # fmt: skip
        if self.velocity_features is not None and not self.setting.features.robot_velocity:
            raise ValueError(f"velocity: the model's setting shows the value no robot velocity; only 'move' applies, got {velocity!r}")
        self.gamma_bar = discount(float(gamma), self.facts)
        self.velocities = action_velocities(self.facts.robot_speed)
        self.reward = self.setting.reward

    def plan(self, obs, memory):
        robot = np.asarray(obs["robot_position"], np.float64)
        # standing now and at the last step: at a reset everyone is still, about to walk
        stood_before, memory["stood"] = memory.get("stood", False), all_standing(obs, self.facts)
        if self.standing_search and not self.setting.features.local_map and stood_before and memory["stood"]:
            k = int(np.argmax(standing_scores(obs, self.facts, self.velocities, self.network.values, self.gamma_bar, memory,
                                              self.reward, self.setting.features, self.velocity_features)))  # fmt: skip
        else:
            k = best_action_two_steps(obs, self.facts, self.velocities, self.network.values, self.gamma_bar, self.planning_width,
                                  self.reward, self.setting.features, self.velocity_features)  # fmt: skip
        waypoint = robot + self.velocities[k] * self.facts.dt
        self.last_plan = np.stack([robot, waypoint])
        return waypoint
