"""Episode seed splits: the evaluation's test episodes never share a seed with RL training.

Training draws episode seeds below ``TEST_SEED_BASE``; the test split lives above it.
"""

TEST_SEED_BASE = 1_000_000_000
EPISODES_PER_SPLIT_SEED = 1_000_000


def heldout_seeds(split_seed: int, episodes: int) -> list[int]:
    """Episode seeds of the test split ``split_seed`` (the evaluation's ``--seed``)."""
    if episodes > EPISODES_PER_SPLIT_SEED:
        raise ValueError(f"episodes must be <= {EPISODES_PER_SPLIT_SEED}, got {episodes}")
    base = TEST_SEED_BASE + int(split_seed) * EPISODES_PER_SPLIT_SEED
    return [base + i for i in range(episodes)]


def is_training_seed(seed: int) -> bool:
    return 0 <= seed < TEST_SEED_BASE
