"""Helpers the tests share (imported by name: pytest puts tests/ on the path)."""


def random_action_observations(env, seed, steps):
    """The observations of up to ``steps`` steps under random actions from ``env.reset(seed=seed)``,
    the first included, stopping at the episode's end."""
    obs, _ = env.reset(seed=seed)
    env.action_space.seed(seed)  # the same actions, and so the same observations, every run
    seen = [obs]
    for _ in range(steps - 1):
        obs, _, terminated, truncated, _ = env.step(env.action_space.sample())
        if terminated or truncated:
            break
        seen.append(obs)
    return seen
