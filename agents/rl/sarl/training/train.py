"""Train SARL (:mod:`agents.rl.sarl.policy`): imitation warm start, then value-based RL, CrowdNav's recipe.

1. Imitation: a planner (``orca`` with CrowdNav's 0.15 m safety space by default) plays training
   episodes; every state's value target is its discounted CrowdNav return; ``il_epochs`` of SGD.
2. RL, as CrowdNav's trainer: the agent acts epsilon-greedily on its 81 moves by the one-step
   lookahead (the humans predicted from the observation), each finished episode's states go to a
   replay memory with targets ``r + gamma_bar · V_target(s')`` (a target network synced every
   ``target_update`` episodes), then ``train_batches`` minibatches of SGD.
SB3 does not fit: its algorithms learn a policy or Q(s, a) from the env's transitions, while SARL
learns V(s) and picks actions by a model-based lookahead over predicted next states.

Several layouts (``--scenario crowdnav-circle-crossing,crowdnav-square-crossing``): episodes take turns among
them, the robot the same in each; validation scores each and selects on their mean.

A Δd curriculum (``curriculum_max`` > 0, for bouncing obstacles): every episode draws its Δd
uniformly from [0, d_max], d_max rising linearly from ``delta_d`` to ``curriculum_max`` over the first
``curriculum_episodes`` RL episodes (the imitation episodes draw from [0, ``curriculum_max``]).

With ``drop_timeouts`` only episodes ending at the goal or in a collision enter the memory (CrowdNav's
explorer). With ``ema_decay`` an exponential moving average of the weights is validated beside them
(SGD at a constant rate leaves the weights jittering by more than the few thousandths of value that
separate the five speeds of one heading: ``docs/results/sarl/time_gap.md``).

Model selection: greedy validation episodes (``pathplan_env.scenarios.splits.validation_seeds``) at every Δd
of ``val_delta_d`` every ``val_every`` RL episodes; the best (mean success, then navigation time) is
kept (the averaged weights too, when they are better). A wall-clock budget stops the run; torch uses one thread.
"""

from __future__ import annotations

import copy
import time
from pathlib import Path

import gymnasium as gym
import numpy as np

import agents as registry
import pathplan_env  # noqa: F401  (registers DynamicObstacle-v0)
from agents.provenance import versions
from agents.rl.sarl.lookahead import CROWDNAV_REWARD, N_ACTIONS, CrowdNavReward, action_velocities, best_action, discount, observed_joint_state
from agents.rl.sarl.numpy_net import HUMAN_DIM, SELF_DIM, SARLNumpy
from agents.rl.sarl.settings import SETTINGS, SARLSetting, get_setting
from agents.rl.sarl.training.config import SARLArgs
from agents.rl.sarl.training.outputs import finish
from pathplan_env.facts import EnvFacts
from pathplan_env.scenarios.splits import training_seed_base, validation_seeds


class Memory:
    """A ring buffer of (self_state, humans padded to ``width``, mask, value target); ``dims`` = (self_dim, human_dim)."""

    def __init__(self, capacity: int, width: int, dims: tuple[int, int] = (SELF_DIM, HUMAN_DIM)):
        self.self_state = np.zeros((capacity, dims[0]), np.float32)
        self.humans = np.zeros((capacity, width, dims[1]), np.float32)
        self.mask = np.zeros((capacity, width), np.float32)
        self.target = np.zeros(capacity, np.float32)
        self.size = self.next = 0

    def add(self, self_state: np.ndarray, humans: np.ndarray, target: float) -> None:
        i, n = self.next, humans.shape[1]
        self.self_state[i], self.target[i] = self_state[0], target
        self.humans[i] = 0.0
        self.mask[i] = 0.0
        self.humans[i, :n], self.mask[i, :n] = humans[0], 1.0
        self.next = (i + 1) % len(self.target)
        self.size = min(self.size + 1, len(self.target))

    def sample(self, rng: np.random.Generator, batch: int):
        idx = rng.integers(0, self.size, min(batch, self.size))
        width = max(1, int(self.mask[idx].sum(1).max()))  # present humans come first: drop all-padding columns
        return self.self_state[idx], self.humans[idx, :width], self.mask[idx, :width], self.target[idx]


def crowdnav_reward(info: dict, dt: float, reward: CrowdNavReward = CROWDNAV_REWARD) -> float:
    """CrowdNav's reward of a finished env step, from its info."""
    if info["collision"]:
        return reward.collision
    if info["is_success"]:
        return reward.success
    gap = float(info["min_clearance"])
    return (gap - reward.discomfort_dist) * reward.discomfort_factor * dt if gap < reward.discomfort_dist else 0.0


def play(env, seed: int, act, setting: SARLSetting = SETTINGS["crowdnav"], delta_d: float | None = None) -> tuple[list, list[float], dict]:
    """One episode from ``reset(seed=seed)`` (at ``delta_d`` if given); ``act(obs) -> env action``. Returns
    each step's joint state (before its move), CrowdNav rewards, the last info."""
    obs, info = env.reset(seed=seed, options=None if delta_d is None else {"delta_d": float(delta_d)})
    facts = EnvFacts.of(env)
    states, rewards = [], []
    while True:
        states.append(observed_joint_state(obs, facts, setting.features))
        obs, _, terminated, truncated, info = env.step(act(obs))
        rewards.append(crowdnav_reward(info, facts.dt, setting.reward))
        if terminated or truncated:
            return states, rewards, info


def move(obs: dict, facts: EnvFacts, velocities: np.ndarray, k: int) -> np.ndarray:
    """The env action that flies move ``k`` (its waypoint is one step away at most: the robot stops on it)."""
    return facts.arena.waypoint_to_action(obs["robot_position"] + velocities[k] * facts.dt)


def greedy(facts: EnvFacts, values, gamma: float, setting: SARLSetting):
    """The greedy lookahead as ``act(obs) -> env action`` in the env of ``facts``."""
    velocities, gamma_bar = action_velocities(facts.robot_speed), discount(gamma, facts)
    return lambda o: move(o, facts, velocities, best_action(o, facts, velocities, values, gamma_bar, setting.reward, setting.features))


def _values(model):
    """The model's current weights as a numpy value function (twice as fast as torch on 81 rows; the shipped agent's own forward)."""
    return SARLNumpy(model.export()).values


def _fit(model, optimizer, batch) -> float:
    import torch

    s, h, m, y = (torch.from_numpy(a) for a in batch)
    loss = torch.nn.functional.mse_loss(model(s, h, m), y)
    optimizer.zero_grad()
    loss.backward()
    optimizer.step()
    return loss.item()


def validate(envs: dict, model, args: SARLArgs) -> dict:
    """Greedy episodes on the validation split in every scenario (``envs``: name -> env) at every
    ``val_delta_d``: success, collision and timeout rates (means over them), mean navigation time of
    successes, and with several scenarios or Δd each one's success."""
    setting = get_setting(args.setting)
    several = len(args.validation_delta_d) > 1
    ends, times, per_cell = [], [], {}
    for name, env in envs.items():
        act = greedy(EnvFacts.of(env), _values(model), args.gamma, setting)
        for delta_d in args.validation_delta_d:
            for seed in validation_seeds(0, args.val_episodes):
                _, _, info = play(env, seed, act, setting, delta_d if several or args.curriculum_max else None)
                ends.append("success" if info["is_success"] else "collision" if info["collision"] else "timeout")
                if info["is_success"]:
                    times.append(float(info["time"]))
            label = "_".join(([name] if len(envs) > 1 else []) + ([f"{delta_d:g}"] if several else []))
            per_cell[f"success_{label}"] = ends[-args.val_episodes :].count("success") / args.val_episodes
    n = len(ends)
    return {"success": ends.count("success") / n, "collision": ends.count("collision") / n, "timeout": ends.count("timeout") / n,
            "navigation_time": float(np.mean(times)) if times else None, **(per_cell if len(per_cell) > 1 else {})}  # fmt: skip


def kept(info: dict, args: SARLArgs) -> bool:
    """Whether a finished episode goes to the replay memory: with ``drop_timeouts`` only a success or a collision (CrowdNav's rule)."""
    return not args.drop_timeouts or bool(info["is_success"] or info["collision"])


def next_values(values, states: list) -> np.ndarray:
    """``values`` of ``states[1:]`` in one batched call (humans padded, masked), a 0 for the last: ``V(s_{t+1})`` per step."""
    following = np.zeros(len(states), np.float32)
    if len(states) > 1:
        width = max(1, max(h.shape[1] for _, h in states[1:]))
        self_state = np.concatenate([s for s, _ in states[1:]])
        humans = np.zeros((len(states) - 1, width, states[1][1].shape[2]), np.float32)
        mask = np.zeros((len(states) - 1, width), np.float32)
        for i, (_, h) in enumerate(states[1:]):
            humans[i, : h.shape[1]], mask[i, : h.shape[1]] = h[0], 1.0
        following[:-1] = values(self_state, humans, mask)
    return following


def remember_returns(memory: Memory, states: list, rewards: list, gamma_bar: float) -> None:
    """An imitation episode's states into ``memory``, each with its discounted CrowdNav return."""
    ret = 0.0
    for (s, h), r in zip(reversed(states), reversed(rewards)):
        ret = r + gamma_bar * ret
        memory.add(s, h, ret)


def averaged_copy(model, decay: float):
    """A copy of ``model`` to hold its weights' moving average, or ``None`` when ``decay`` is 0 (off)."""
    if not decay:
        return None
    return copy.deepcopy(model)


def update_average(average, model, decay: float) -> None:
    """``average`` <- ``decay`` · ``average`` + (1 - ``decay``) · ``model``, weight by weight (nothing if ``average`` is None)."""
    if average is None:
        return
    import torch

    with torch.no_grad():
        for mean, weight in zip(average.parameters(), model.parameters()):
            mean.lerp_(weight, 1.0 - decay)


def select(best: dict, candidates: list, path: Path) -> dict:
    """The best of ``best`` and the validated ``candidates`` (``(row, weights)``) by :func:`score`; a better one's weights saved to ``path``."""
    for row, weights in candidates:
        if score(row) > score(best):
            best = row
            np.savez(path, **weights.export())
    return best


def remember(memory: Memory, states: list, rewards: list, target_values, gamma_bar: float) -> None:
    """An RL episode's states into ``memory``, targets ``r + gamma_bar · V_target(s_{t+1})``; the last step is
    terminal (or a timeout, as CrowdNav)."""
    following = next_values(target_values, states)
    for t, (st, r) in enumerate(zip(states, rewards)):
        memory.add(st[0], st[1], r + gamma_bar * following[t] if t < len(states) - 1 else r)


def validate_both(envs: dict, model, average, args: SARLArgs, row: dict) -> list:
    """Validates ``model`` into ``row`` and, if given, the averaged weights ``average`` on the same episodes (as
    ``ema_*`` keys of ``row``); returns the candidates for selection, ``(row, weights)`` each."""
    row.update(validate(envs, model, args))
    candidates = [(dict(row), model)]
    if average is not None:
        averaged = validate(envs, average, args)
        row.update({f"ema_{k}": v for k, v in averaged.items()})
        candidates.append(({**row, **averaged, "weights": "ema"}, average))
    return candidates


def score(row: dict) -> tuple:
    """Model selection's key: success, then the shorter navigation time."""
    return row["success"], -(row["navigation_time"] or 1e9)


def curriculum_delta_d(args: SARLArgs, rng: np.random.Generator, rl_episode: int) -> float | None:
    """The Δd of RL episode ``rl_episode`` (0: an imitation episode); ``None``: the env's own (no curriculum)."""
    if not args.curriculum_max:
        return None
    top = args.curriculum_max if rl_episode == 0 else args.delta_d + (args.curriculum_max - args.delta_d) * min(1.0, rl_episode / args.curriculum_episodes)
    return float(rng.uniform(0.0, top))


def train(args: SARLArgs, command: str = "") -> dict:
    import torch

    from agents.rl.sarl.net import SARLValue

    start = time.perf_counter()
    provenance = versions()  # the commit the run starts from
    budget = args.budget_minutes * 60.0
    torch.set_num_threads(1)
    torch.manual_seed(args.seed)
    rng = np.random.default_rng(args.seed)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    envs = {name: gym.make("DynamicObstacle-v0", scenario=name, delta_d=args.delta_d) for name in args.scenarios}
    scenario_of = lambda episode: args.scenarios[episode % len(envs)]  # episodes take turns among the scenarios
    env = envs[scenario_of(0)]
    facts = EnvFacts.of(env)
    for name, other in envs.items():  # one action set and discount for all: the robot must be the same
        other_facts = EnvFacts.of(other)
        if (other_facts.robot_speed, other_facts.dt) != (facts.robot_speed, facts.dt):
            raise ValueError(f"scenario: {name}'s robot speed or dt differs from {args.scenarios[0]}'s; train on one robot at a time")
    setting = get_setting(args.setting)
    velocities, gamma_bar = action_velocities(facts.robot_speed), discount(args.gamma, facts)
    width = max(e.observation_space["obstacle_mask"].shape[0] for e in envs.values())
    memory = Memory(args.capacity, width, setting.features.dims)
    model = SARLValue(dims=setting.features.dims)
    seed = training_seed_base(args.seed)
    log = lambda msg: print(f"[{time.perf_counter() - start:7.1f} s] {msg}", flush=True)

    # 1. imitation: discounted CrowdNav returns of the teacher's episodes (at most a quarter of the budget)
    teachers = {name: registry.make(args.teacher, e, seed=seed, **args.teacher_kwargs) for name, e in envs.items()}
    il_played, il_success = 0, 0
    for il_episode in range(args.il_episodes):
        if time.perf_counter() - start > 0.25 * budget:
            break
        teacher = teachers[scenario_of(il_episode)]
        teacher.reset()
        states, rewards, info = play(envs[scenario_of(il_episode)], seed, lambda o, teacher=teacher: teacher.predict(o, deterministic=True)[0], setting,
                                     curriculum_delta_d(args, rng, 0))  # fmt: skip
        seed += 1
        il_played, il_success = il_played + 1, il_success + bool(info["is_success"])
        if kept(info, args):
            remember_returns(memory, states, rewards, gamma_bar)
    log(f"imitation: {il_played} {args.teacher} episodes, success {il_success / max(il_played, 1):.3f}, {memory.size} states")
    optimizer = torch.optim.SGD(model.parameters(), lr=args.il_lr, momentum=0.9)
    for epoch in range(args.il_epochs if memory.size else 0):
        order = rng.permutation(memory.size)
        losses = []
        for i in range(0, memory.size, args.batch_size):
            idx = order[i : i + args.batch_size]
            w = max(1, int(memory.mask[idx].sum(1).max()))
            losses.append(_fit(model, optimizer, (memory.self_state[idx], memory.humans[idx, :w], memory.mask[idx, :w], memory.target[idx])))
        if epoch % 10 == 9 or epoch == args.il_epochs - 1:
            log(f"imitation epoch {epoch + 1}: loss {np.mean(losses):.5f}")
    begin = time.perf_counter()
    curve = [{"rl_episode": 0, "seconds": round(begin - start, 1), **validate(envs, model, args)}]
    val_cost = time.perf_counter() - begin  # how long one validation takes: the budget keeps room for the last
    log(f"validation after imitation: {curve[-1]}")
    best = dict(curve[-1])
    np.savez(out / "best.npz", **model.export())
    np.savez(out / "imitation.npz", **model.export())

    # 2. RL: epsilon-greedy lookahead, replay memory, target network
    target = SARLValue(dims=setting.features.dims)
    target.load_state_dict(model.state_dict())
    average = averaged_copy(model, args.ema_decay)
    optimizer = torch.optim.SGD(model.parameters(), lr=args.rl_lr, momentum=0.9)
    values, target_values = _values(model), _values(target)
    episode = 0
    for episode in range(1, args.rl_episodes + 1):
        if time.perf_counter() - start + val_cost + 5 > budget:
            episode -= 1
            break
        epsilon = args.epsilon_end + (args.epsilon_start - args.epsilon_end) * max(0.0, 1 - (episode - 1) / args.epsilon_decay)

        episode_env = envs[scenario_of(episode)]
        episode_facts = EnvFacts.of(episode_env)
        episode_greedy = greedy(episode_facts, values, args.gamma, setting)

        def act(o, epsilon=epsilon, greedy_act=episode_greedy, facts=episode_facts):
            return move(o, facts, velocities, int(rng.integers(N_ACTIONS))) if rng.random() < epsilon else greedy_act(o)

        states, rewards, info = play(episode_env, seed, act, setting, curriculum_delta_d(args, rng, episode))
        seed += 1
        if kept(info, args):
            remember(memory, states, rewards, target_values, gamma_bar)
        for _ in range(args.train_batches):
            _fit(model, optimizer, memory.sample(rng, args.batch_size))
        values = _values(model)
        update_average(average, model, args.ema_decay)
        if episode % args.target_update == 0:
            target.load_state_dict(model.state_dict())
            target_values = _values(target)
        if episode % args.val_every == 0:
            begin = time.perf_counter()
            row = {"rl_episode": episode, "seconds": round(time.perf_counter() - start, 1), "epsilon": round(epsilon, 3)}
            candidates = validate_both(envs, model, average, args, row)
            val_cost = time.perf_counter() - begin
            curve.append(row)
            log(f"validation: {row}")
            best = select(best, candidates, out / "best.npz")
    np.savez(out / "final.npz", **model.export())
    seconds = time.perf_counter() - start
    log(f"done: {episode} RL episodes, best {best}, wall time {seconds / 60:.1f} min")
    return finish(args, command, out, curve, best, seconds, episode, il_played, il_success, provenance)
