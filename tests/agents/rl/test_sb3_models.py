"""SB3 models as they come (``agents.make("sb3", env, path=...)``, :mod:`agents.rl.sb3_model`): a
model trained through plain stable-baselines3 with VecNormalize scores in the harness exactly as in
the user's own loop, episode by episode; the algorithm and the observations are read from the model."""

import csv
import json
import zipfile
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest
import torch
from stable_baselines3 import A2C, DDPG, PPO, SAC, TD3
from stable_baselines3.common.env_util import make_vec_env
from stable_baselines3.common.evaluation import evaluate_policy
from stable_baselines3.common.vec_env import VecNormalize

import agents
import pathplan_env  # noqa: F401  (registers the env ids)
from agents.evaluation import evaluate
from agents.rl import sb3_model, sb3_zip
from agents.rl.sb3_model import detect_algorithm, statistics_beside
from pathplan_env.scenarios.splits import heldout_seeds

DELTA_D = 0.25
EPISODES = 20
SMALL = dict(net_arch=[16])  # untrained models that only need to load (copy it: SB3 adds to the dict)


@pytest.fixture(scope="module", autouse=True)
def one_torch_thread():
    """Tiny networks on a shared machine: one thread is several times faster than contending ones."""
    threads = torch.get_num_threads()
    torch.set_num_threads(1)
    yield
    torch.set_num_threads(threads)


def train_with_vecnormalize(env_id: str, policy: str, steps: int, folder: Path, model_name: str, stats_path: Path) -> Path:
    """What an SB3 user does: make_vec_env, VecNormalize, PPO, save the model and the statistics."""
    venv = VecNormalize(make_vec_env(env_id, n_envs=2, seed=0))
    model = PPO(policy, venv, n_steps=steps // 2, batch_size=steps // 2, n_epochs=2, seed=0, device="cpu")
    model.learn(steps)
    folder.mkdir(parents=True, exist_ok=True)
    model.save(folder / model_name)
    stats_path.parent.mkdir(parents=True, exist_ok=True)
    venv.save(str(stats_path))
    return folder / f"{model_name}.zip"


@pytest.fixture(scope="module")
def flat_model(tmp_path_factory) -> Path:
    run = tmp_path_factory.mktemp("flat")
    return train_with_vecnormalize("DynamicObstacleFlat-v0", "MlpPolicy", 1024, run, "ppo_flat", run / "vecnormalize.pkl")


def users_own_loop(model_path: Path, stats_path: Path, seeds: list[int]) -> list[tuple]:
    """SB3's evaluate_policy on a VecNormalize(training=False) env, one episode per test seed:
    (success, collision, steps) of each episode."""
    model = PPO.load(model_path, device="cpu")
    venv = make_vec_env("DynamicObstacleFlat-v0", n_envs=1, env_kwargs=dict(scenario="random", delta_d=DELTA_D))
    venv = VecNormalize.load(str(stats_path), venv)
    venv.training, venv.norm_reward = False, False
    outcomes = []
    for seed in seeds:
        last = {}
        venv.seed(seed)  # the next reset's seed: evaluate_policy's own reset
        _, lengths = evaluate_policy(model, venv, n_eval_episodes=1, deterministic=True, return_episode_rewards=True,
                                     callback=lambda local, _, last=last: local["done"] and last.update(local["info"]))  # fmt: skip
        outcomes.append((bool(last["is_success"]), bool(last["collision"]), int(lengths[0])))
    return outcomes


def harness(out: Path, kwargs: dict) -> list[tuple]:
    evaluate(["sb3"], ["random"], [DELTA_D], episodes=EPISODES, out=out, agent_kwargs={"sb3": kwargs}, limit=False, plots=False)
    with open(out / "episodes.csv") as f:
        rows = sorted(csv.DictReader(f), key=lambda row: int(row["episode"]))
    return [(row["success"] == "True", row["collision"] == "True", int(row["steps"])) for row in rows]


@pytest.mark.slow
def test_harness_scores_a_vecnormalize_model_as_the_users_own_loop(flat_model, tmp_path, capfd):
    seeds = heldout_seeds(0, EPISODES)  # the harness's episodes
    own = users_own_loop(flat_model, flat_model.parent / "vecnormalize.pkl", seeds)
    scored = harness(tmp_path / "auto", {"path": str(flat_model)})  # the statistics found beside the model
    assert scored == own  # episode by episode, not only the rate
    assert f"VecNormalize from {flat_model.parent / 'vecnormalize.pkl'}" in capfd.readouterr().err
    # the bug this guards against: the same model without its statistics plays other episodes
    unnormalised = harness(tmp_path / "none", {"path": str(flat_model), "vecnormalize": None})
    differing = sum(a != b for a, b in zip(unnormalised, own))
    assert differing >= EPISODES // 2, differing
    rates = [np.mean([success for success, _, _ in outcomes]) for outcomes in (own, scored, unnormalised)]
    print(f"success over {EPISODES} episodes: own loop {rates[0]:.2f}, harness {rates[1]:.2f}, "
          f"without VecNormalize {rates[2]:.2f} ({differing} episodes end otherwise)")  # fmt: skip


def test_flat_model_loads_from_its_zip_alone_and_says_what_it_applied(flat_model, capfd, monkeypatch):
    monkeypatch.setattr(sb3_model, "_ANNOUNCED", set())  # as in a fresh process
    env = gym.make("DynamicObstacle-v0", delta_d=DELTA_D)
    obs, _ = env.reset(seed=3)
    agent = agents.make("sb3", env, path=flat_model)
    assert agent.k_nearest == 8 and agent.algorithm is PPO and agent.statistics is not None
    again = agents.make("sb3", env, path=str(flat_model)[: -len(".zip")])  # SB3 lets ".zip" be left out
    lines = [line for line in capfd.readouterr().err.splitlines() if line.startswith("sb3:")]
    assert len(lines) == 1 and lines[0] == agent.description  # one line, once per process
    assert "PPO (read from the zip)" in lines[0] and "k=8" in lines[0] and "clip_obs=10" in lines[0]
    action, state = agent.predict(obs, deterministic=True)
    assert env.action_space.contains(action) and state is None
    np.testing.assert_array_equal(action, again.predict(obs, deterministic=True)[0])
    # batched, as evaluate_policy hands observations from a vector env
    batch = {k: np.stack([v, v]) for k, v in obs.items()}
    np.testing.assert_array_equal(agent.predict(batch, deterministic=True)[0], np.stack([action, action]))
    # `ppo` with a path takes a model without a sidecar the same way
    np.testing.assert_array_equal(agents.make("ppo", env, path=flat_model).predict(obs, deterministic=True)[0], action)
    unnormalised = agents.make("sb3", env, path=flat_model, vecnormalize=False)
    assert unnormalised.statistics is None and "VecNormalize: none" in unnormalised.description
    assert not np.array_equal(unnormalised.predict(obs, deterministic=True)[0], action)


def test_dict_model_in_rl_zoo3s_layout_acts_as_in_the_users_loop(tmp_path, flat_model):
    """A MultiInputPolicy on DynamicObstacle-v0, saved as rl-zoo3 saves a run (<run>/<env_id>.zip,
    <run>/<env_id>/vecnormalize.pkl): every Dict key normalised, step for step the user's actions."""
    env_id = "DynamicObstacle-v0"
    path = train_with_vecnormalize(env_id, "MultiInputPolicy", 128, tmp_path, env_id, tmp_path / env_id / "vecnormalize.pkl")
    env = gym.make(env_id)
    agent = agents.make("sb3", env, path=path)
    assert agent.k_nearest is None and "Dict" in agent.description and f"{env_id}/vecnormalize.pkl" in agent.description
    venv = VecNormalize.load(str(tmp_path / env_id / "vecnormalize.pkl"), make_vec_env(env_id, n_envs=1))
    venv.training = False
    venv.seed(7)
    user_obs = venv.reset()
    obs, _ = env.reset(seed=7)
    for _ in range(30):
        expected, _ = agent.model.predict(user_obs, deterministic=True)
        action, _ = agent.predict(obs, deterministic=True)
        np.testing.assert_array_equal(action, expected[0])
        user_obs, _, done, _ = venv.step(expected)
        obs, _, terminated, truncated, _ = env.step(action)
        assert done[0] == (terminated or truncated)
        if done[0]:
            break
    # without its statistics, a model whose space is VecNormalize's is refused, not silently run
    alone = tmp_path / "alone"
    alone.mkdir()
    (alone / "model.zip").write_bytes(path.read_bytes())
    with pytest.raises(ValueError, match="learned inside VecNormalize"):
        agents.make("sb3", env, path=alone / "model.zip")
    assert agents.make("sb3", env, path=alone / "model.zip", vecnormalize=None).statistics is None
    # statistics given by path
    given = agents.make("sb3", env, path=alone / "model.zip", vecnormalize=tmp_path / env_id / "vecnormalize.pkl")
    np.testing.assert_array_equal(given.predict(obs, deterministic=True)[0], agent.predict(obs, deterministic=True)[0])
    with pytest.raises(ValueError, match="do not fit the model"):  # another model's statistics
        agents.make("sb3", env, path=alone / "model.zip", vecnormalize=flat_model.parent / "vecnormalize.pkl")


def test_the_algorithm_is_read_from_the_zip(tmp_path):
    env = gym.make("DynamicObstacle-v0")
    obs, _ = env.reset(seed=0)
    for algorithm in (A2C, SAC, TD3, DDPG):
        kwargs = {} if algorithm is A2C else {"buffer_size": 10}
        algorithm("MlpPolicy", "DynamicObstacleFlat-v0", policy_kwargs=dict(SMALL), device="cpu", **kwargs).save(tmp_path / algorithm.__name__)
        path = tmp_path / f"{algorithm.__name__}.zip"
        assert detect_algorithm(path)[0] == algorithm.__name__.lower()
        agent = agents.make("sb3", env, path=path)
        assert agent.algorithm is algorithm and f"{algorithm.__name__} (read from the zip)" in agent.description
        assert env.action_space.contains(agent.predict(obs, deterministic=True)[0])
    assert agents.make("sb3", env, path=tmp_path / "TD3.zip", algo="ddpg").algorithm is DDPG  # DDPG saves TD3's policy
    with pytest.raises(ValueError, match="saved by SAC, not PPO.*'sb3'"):
        agents.make("ppo", env, path=tmp_path / "SAC.zip")
    with pytest.raises(ValueError, match="saved by SAC, not A2C"):
        agents.make("sb3", env, path=tmp_path / "SAC.zip", algo="a2c")
    with pytest.raises(ValueError, match="algo: unknown"):
        agents.make("sb3", env, path=tmp_path / "SAC.zip", algo="sacc")
    with pytest.raises(TypeError, match="vecnormalize"):  # the shipped PPO takes no statistics
        agents.make("ppo", env, vecnormalize=None)


class _OtherTask(gym.Env):
    observation_space = gym.spaces.Box(-1, 1, (10,), np.float32)
    action_space = gym.spaces.Box(-1, 1, (2,), np.float32)

    def reset(self, *, seed=None, options=None):
        return self.observation_space.sample(), {}

    def step(self, action):
        return self.observation_space.sample(), 0.0, True, False, {}


def test_a_model_of_another_task_or_no_model_is_refused_naming_the_path(tmp_path):
    env = gym.make("DynamicObstacle-v0")
    PPO("MlpPolicy", _OtherTask(), policy_kwargs=dict(SMALL), n_steps=8, batch_size=8, device="cpu").save(tmp_path / "other")
    with pytest.raises(ValueError, match=r"path: the model at .*other.zip takes observations Box\(-1.0, 1.0, \(10,\)"):
        agents.make("sb3", env, path=tmp_path / "other.zip")
    wider = gym.make("DynamicObstacle-v0", max_obstacles=20)  # DynamicObstacle-v0's Dict, with more obstacle rows
    PPO("MultiInputPolicy", wider, policy_kwargs=dict(SMALL), n_steps=8, batch_size=8, device="cpu").save(tmp_path / "wider")
    with pytest.raises(ValueError, match="path: the model at .*wider.zip .* make the env with max_obstacles=20"):
        agents.make("sb3", env, path=tmp_path / "wider.zip")
    assert agents.make("sb3", wider, path=tmp_path / "wider.zip").k_nearest is None
    with pytest.raises(ValueError, match="path: no model at"):
        agents.make("sb3", env, path=tmp_path / "none.zip")
    with pytest.raises(ValueError, match="path: no model at"):
        agents.make("ppo", env, path=tmp_path / "none.zip")
    with pytest.raises(ValueError, match="path: agents.make"):
        agents.make("sb3", env)
    (tmp_path / "notes.zip").write_text("not a zip")
    with pytest.raises(ValueError, match="not a stable-baselines3 model"):
        agents.make("sb3", env, path=tmp_path / "notes.zip")


class _SameWidthOtherTask(_OtherTask):
    """Another task's 65 unbounded inputs: the width of DynamicObstacleFlat-v0's features for k = 8."""

    observation_space = gym.spaces.Box(-np.inf, np.inf, (65,), np.float32)


def test_a_model_of_another_task_with_our_width_is_refused_by_its_bounds(tmp_path):
    assert gym.make("DynamicObstacleFlat-v0").observation_space.shape == (65,)
    PPO("MlpPolicy", _SameWidthOtherTask(), policy_kwargs=dict(SMALL), n_steps=8, batch_size=8, device="cpu").save(tmp_path / "other")
    with pytest.raises(ValueError, match=r"path: the model at .*other.zip takes observations Box\(-inf, inf, \(65,\)"):
        agents.make("sb3", gym.make("DynamicObstacle-v0"), path=tmp_path / "other.zip")


def _zip(path: Path, entries: dict[str, bytes], compression=zipfile.ZIP_STORED) -> Path:
    with zipfile.ZipFile(path, "w", compression=compression) as archive:
        for name, payload in entries.items():
            archive.writestr(name, payload)
    return path


NOT_SB3 = "path: .*odd.zip is not a stable-baselines3 model .*: "


@pytest.mark.parametrize("entries, message", [
    ({"data": b"[1, 2, 3]", "policy.pth": b""}, NOT_SB3 + "its 'data' is a JSON list"),
    ({"data": b'{"policy_class": {}}'}, NOT_SB3 + "no policy.pth in it"),
    ({"policy.pth": b""}, NOT_SB3 + "no data in it"),
    ({"data": b'{"a": 1', "policy.pth": b""}, NOT_SB3 + "Expecting"),
    ({"data": b"\xff\xfe", "policy.pth": b""}, NOT_SB3 + "Expecting value"),
    ({"data": b'{"policy_class": [1]}', "policy.pth": b""}, "path: cannot tell the algorithm of .*odd.zip"),
])  # fmt: skip
def test_a_zip_that_is_not_sb3s_is_a_value_error_naming_the_file(tmp_path, entries, message):
    path = _zip(tmp_path / "odd.zip", entries)
    with pytest.raises(ValueError, match=message):
        agents.make("sb3", gym.make("DynamicObstacle-v0"), path=path)


def test_a_zip_bomb_is_refused_from_the_zips_directory_before_decompressing(tmp_path, monkeypatch):
    bomb = _zip(tmp_path / "bomb.zip", {"data": b" " * (sb3_zip.MAX_DATA_BYTES + 1), "policy.pth": b""}, zipfile.ZIP_DEFLATED)
    assert bomb.stat().st_size < 100_000
    monkeypatch.setattr(zipfile.ZipExtFile, "read", lambda *a, **k: pytest.fail("decompressed"))
    with pytest.raises(ValueError, match=f"path: .*bomb.zip.*its 'data' expands to {sb3_zip.MAX_DATA_BYTES + 1} bytes"):
        agents.make("sb3", gym.make("DynamicObstacle-v0"), path=bomb)
    with pytest.raises(ValueError, match="bomb.zip.*over"):  # the algorithm given: the zip is still checked first
        agents.make("sb3", gym.make("DynamicObstacle-v0"), path=bomb, algo=PPO)


def test_statistics_beside_a_model_can_be_refused(tmp_path, flat_model, capfd):
    agent = agents.make("sb3", gym.make("DynamicObstacle-v0"), path=flat_model, vecnormalize=False)
    assert agent.statistics is None and "VecNormalize: none" in agent.description


def test_statistics_are_looked_for_only_beside_the_model(tmp_path, flat_model):
    run = tmp_path / "run"
    candidates = statistics_beside(run / "checkpoints" / "rl_model_5000_steps.zip")
    assert all(run / "checkpoints" in (c.parent, c.parent.parent) for c in candidates)
    assert candidates[0].name == "rl_model_vecnormalize_5000_steps.pkl"  # SB3's CheckpointCallback(save_vecnormalize=True)
    # a checkpoint's own statistics win; two others are ambiguous and refused
    env = gym.make("DynamicObstacle-v0")
    stats = (flat_model.parent / "vecnormalize.pkl").read_bytes()
    (run / "checkpoints").mkdir(parents=True)
    checkpoint = run / "checkpoints" / "rl_model_5000_steps.zip"
    checkpoint.write_bytes(flat_model.read_bytes())
    for name in ("rl_model_vecnormalize_5000_steps.pkl", "vecnormalize.pkl", "vec_normalize.pkl"):
        (run / "checkpoints" / name).write_bytes(stats)
    assert "rl_model_vecnormalize_5000_steps.pkl" in agents.make("sb3", env, path=checkpoint).description
    (run / "checkpoints" / "rl_model_vecnormalize_5000_steps.pkl").unlink()
    with pytest.raises(ValueError, match="several VecNormalize statistics"):
        agents.make("sb3", env, path=checkpoint)
    with pytest.raises(ValueError, match="no VecNormalize statistics beside"):
        agents.make("sb3", env, path=_copy(flat_model, tmp_path / "bare"), vecnormalize=True)
    with pytest.raises(ValueError, match="vecnormalize: no file"):
        agents.make("sb3", env, path=flat_model, vecnormalize=tmp_path / "none.pkl")
    (tmp_path / "junk.pkl").write_text("not a pickle")
    with pytest.raises(ValueError, match="does not hold VecNormalize statistics"):
        agents.make("sb3", env, path=flat_model, vecnormalize=tmp_path / "junk.pkl")
    # statistics beside a model that did not learn inside VecNormalize are someone else's: refused
    plain = PPO("MlpPolicy", make_vec_env("DynamicObstacleFlat-v0", n_envs=1), policy_kwargs=dict(SMALL), n_steps=32, batch_size=32, device="cpu")
    plain.learn(32)
    (tmp_path / "plain").mkdir()
    plain.save(tmp_path / "plain" / "model")
    (tmp_path / "plain" / "vecnormalize.pkl").write_bytes(stats)
    with pytest.raises(ValueError, match="did not learn inside VecNormalize"):
        agents.make("sb3", env, path=tmp_path / "plain" / "model.zip")
    forced = agents.make("sb3", env, path=tmp_path / "plain" / "model.zip", vecnormalize=tmp_path / "plain" / "vecnormalize.pkl")
    assert forced.statistics is not None


def _copy(path: Path, folder: Path) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    (folder / path.name).write_bytes(path.read_bytes())
    return folder / path.name


def test_ppo_with_a_hand_written_sidecar_still_gets_its_statistics(tmp_path, flat_model):
    """The issue's case: a JSON written by hand beside a VecNormalize model used to route it to the
    sidecar loader, which ignored the statistics; only train_rl.py's own sidecar does now."""
    run = tmp_path / "run"
    model = _copy(flat_model, run)
    _copy(flat_model.parent / "vecnormalize.pkl", run)
    model.with_suffix(".json").write_text(json.dumps({"algo": "ppo", "k_nearest": 8}))
    agent = agents.make("ppo", gym.make("DynamicObstacle-v0"), path=model)
    assert type(agent).__name__ == "SB3Agent" and "vecnormalize.pkl" in agent.description
