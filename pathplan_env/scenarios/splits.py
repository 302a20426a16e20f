"""Episode seed splits: RL training, validation (model selection) and test never share a seed.

Training draws episode seeds below ``VALIDATION_SEED_BASE``; validation uses
``[VALIDATION_SEED_BASE, TEST_SEED_BASE)``; the evaluation's test split lives above ``TEST_SEED_BASE``.

The evaluation's splits, seeds and scenes, are :mod:`pathplan_env.scenarios.episode_sources`
(``crowdnav``: CrowdNav's own test cases as the scenes, the test split's seeds for the rest).
"""

from pathplan_env.scenarios.crowdnav import TEST_CASES as CROWDNAV_TEST_CASES

VALIDATION_SEED_BASE = 900_000_000
TEST_SEED_BASE = 1_000_000_000
EPISODES_PER_SPLIT_SEED = 1_000_000
TRAINING_SEEDS_PER_RUN = 10_000_000
#: The evaluation's splits (``scripts/evaluate.py --split``; their sources: ``episode_sources.SOURCES``).
SPLITS = ("test", "validation", "crowdnav")


def heldout_seeds(split_seed: int, episodes: int) -> list[int]:
    """Episode seeds of the test split ``split_seed`` (the evaluation's ``--seed``)."""
    if episodes > EPISODES_PER_SPLIT_SEED:
        raise ValueError(f"episodes must be <= {EPISODES_PER_SPLIT_SEED}, got {episodes}")
    base = TEST_SEED_BASE + int(split_seed) * EPISODES_PER_SPLIT_SEED
    return [base + i for i in range(episodes)]


def validation_seeds(split_seed: int, episodes: int) -> list[int]:
    """Episode seeds of the validation split ``split_seed``, for model selection (never the test split)."""
    if episodes > EPISODES_PER_SPLIT_SEED:
        raise ValueError(f"episodes must be <= {EPISODES_PER_SPLIT_SEED}, got {episodes}")
    base = VALIDATION_SEED_BASE + int(split_seed) * EPISODES_PER_SPLIT_SEED
    if not VALIDATION_SEED_BASE <= base < TEST_SEED_BASE:
        raise ValueError(f"split_seed must be in [0, {(TEST_SEED_BASE - VALIDATION_SEED_BASE) // EPISODES_PER_SPLIT_SEED - 1}], got {split_seed!r}")
    return [base + i for i in range(episodes)]


def episode_seeds(split: str, split_seed: int, episodes: int) -> list[int]:
    """The episode seeds of an evaluation on ``split`` (one of :data:`SPLITS`): the agent's and the
    env's. On ``crowdnav`` the scenes are CrowdNav's cases, at most its 500, and the seeds the test split's
    (the harness asks ``episode_sources.source_of(split)``, which gives the same seeds)."""
    if split not in SPLITS:
        raise ValueError(f"split must be one of {list(SPLITS)}, got {split!r}")
    if split == "crowdnav" and episodes > CROWDNAV_TEST_CASES:
        raise ValueError(f"episodes must be <= {CROWDNAV_TEST_CASES} on split 'crowdnav' (CrowdNav's test cases), got {episodes}")
    return (validation_seeds if split == "validation" else heldout_seeds)(split_seed, episodes)


def training_seed_base(run_seed: int) -> int:
    """First episode seed of the training run ``run_seed``; its episodes take the next ``TRAINING_SEEDS_PER_RUN`` seeds."""
    base = int(run_seed) * TRAINING_SEEDS_PER_RUN
    if not 0 <= base <= VALIDATION_SEED_BASE - TRAINING_SEEDS_PER_RUN:
        raise ValueError(f"seed must be in [0, {VALIDATION_SEED_BASE // TRAINING_SEEDS_PER_RUN - 1}], got {run_seed!r}")
    return base


def is_training_seed(seed: int) -> bool:
    return 0 <= seed < VALIDATION_SEED_BASE


def is_validation_seed(seed: int) -> bool:
    return VALIDATION_SEED_BASE <= seed < TEST_SEED_BASE
