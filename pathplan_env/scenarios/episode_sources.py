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
from functools import cache

from pathplan_env.scenarios import splits


@dataclass(frozen=True)
class EpisodeSource:
    """A split: its episode seeds (:func:`pathplan_env.scenarios.splits.episode_seeds`) and, ``scene``
    given, the scene of each episode."""

    name: str
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
        """The episodes' env and agent seeds, within the split's bound."""
        return splits.episode_seeds(self.name, split_seed, episodes)


def _crowdnav() -> EpisodeSource:
    from pathplan_env.scenarios import crowdnav

    def scene(preset: str, episode: int, n_obstacles, delta_d):
        layout, visible = crowdnav.PRESET_LAYOUTS[preset]
        return crowdnav.crowdnav_test_case(layout, episode, n_obstacles, visible, delta_d)

    base = crowdnav.TEST_CASE_SEED_BASE
    return EpisodeSource("crowdnav", scene, frozenset(crowdnav.PRESET_LAYOUTS),
                         {"robot_visible": "its -visible presets are CrowdNav's cases with a visible robot"},
                         lambda episodes: {"crowdnav_case_seeds": [base, base + episodes - 1]})  # fmt: skip


#: The splits by name, each built on first use.
SOURCES: dict[str, Callable[[], EpisodeSource]] = {"test": lambda: EpisodeSource("test"), "validation": lambda: EpisodeSource("validation"),
                                                   "crowdnav": _crowdnav}  # fmt: skip


def source_of(split: str) -> EpisodeSource:
    """The episode source of ``split``; a ``ValueError`` naming the splits for another name."""
    if not isinstance(split, str) or split not in SOURCES:
        raise ValueError(f"split must be one of {list(SOURCES)}, got {split!r}")
    return _built(split)


@cache  # once a split: a run asks for every job's key
def _built(split: str) -> EpisodeSource:
    return SOURCES[split]()


def gives_scenes(split: str) -> bool:
    """Whether ``split``'s scenes come from its source rather than the seed (its records say so)."""
    return source_of(split).gives_scenes
