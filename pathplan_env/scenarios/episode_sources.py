"""Where an evaluation's episodes come from: one :class:`EpisodeSource` a split.

``test`` and ``validation`` draw each episode's scene from the env's seed (their seeds differ);
``crowdnav`` gives episode ``i`` of a CrowdNav preset its test case ``i`` as the scene
(``pathplan_env.scenarios.crowdnav.crowdnav_test_case``), so a result compares case by case with a
model evaluated in CrowdNav. The harness asks the source and never names a split: a new source is a
new entry in :data:`SOURCES`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field


@dataclass(frozen=True)
class EpisodeSource:
    """A split: its episode seeds, and (``scene`` given) the scene of each episode."""

    name: str
    seeds: Callable[[int, int], list[int]]  # (split_seed, episodes) -> the episodes' env and agent seeds
    max_episodes: int | None = None
    #: (preset, episode, n_obstacles, delta_d) -> the episode's Scenario; None: the env draws it from the seed
    scene: Callable | None = None
    presets: frozenset[str] = frozenset()  # the only scenarios a scene source takes
    #: gym.make keywords the source sets itself, with why
    own_env_options: dict[str, str] = field(default_factory=dict)
    describe: Callable[[int], dict] = lambda episodes: {}  # what summary.json records of it

    @property
    def gives_scenes(self) -> bool:
        return self.scene is not None

    def takes(self, preset) -> bool:
        return not self.gives_scenes or (isinstance(preset, str) and preset in self.presets)

    def episode_seeds(self, split_seed: int, episodes: int) -> list[int]:
        if self.max_episodes is not None and episodes > self.max_episodes:
            raise ValueError(f"episodes must be <= {self.max_episodes} on split {self.name!r}, got {episodes}")
        return self.seeds(split_seed, episodes)


def _crowdnav() -> EpisodeSource:
    from pathplan_env.scenarios import crowdnav
    from pathplan_env.scenarios.splits import heldout_seeds

    def scene(preset: str, episode: int, n_obstacles, delta_d):
        layout, visible = crowdnav.PRESET_LAYOUTS[preset]
        return crowdnav.crowdnav_test_case(layout, episode, n_obstacles, visible, delta_d)

    base = crowdnav.TEST_CASE_SEED_BASE
    return EpisodeSource("crowdnav", heldout_seeds, crowdnav.TEST_CASES, scene, frozenset(crowdnav.PRESET_LAYOUTS),
                         {"robot_visible": "its -visible presets are CrowdNav's cases with a visible robot"},
                         lambda episodes: {"crowdnav_case_seeds": [base, base + episodes - 1]})  # fmt: skip


def _drawn(name: str) -> EpisodeSource:
    from pathplan_env.scenarios import splits

    return EpisodeSource(name, splits.heldout_seeds if name == "test" else splits.validation_seeds, splits.EPISODES_PER_SPLIT_SEED)


#: The splits by name, built on first use (CrowdNav's module loads only when asked for).
SOURCES: dict[str, Callable[[], EpisodeSource]] = {"test": lambda: _drawn("test"), "validation": lambda: _drawn("validation"),
                                                   "crowdnav": _crowdnav}  # fmt: skip


def source_of(split: str) -> EpisodeSource:
    """The episode source of ``split``; a ``ValueError`` naming the splits for another name."""
    if split not in SOURCES:
        raise ValueError(f"split must be one of {list(SOURCES)}, got {split!r}")
    return SOURCES[split]()


def gives_scenes(split: str) -> bool:
    """Whether ``split``'s scenes come from its source rather than the seed (its records say so)."""
    return source_of(split).gives_scenes
