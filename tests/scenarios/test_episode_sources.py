"""Where an evaluation's episodes come from: one source a split, chosen by name, which the harness
asks instead of testing for a split's name."""

from __future__ import annotations

import pytest

from pathplan_env.scenarios import crowdnav, splits
from pathplan_env.scenarios.episode_sources import SOURCES, gives_scenes, source_of


def test_the_splits_are_the_sources():
    assert list(SOURCES) == list(splits.SPLITS)
    with pytest.raises(ValueError, match=r"split must be one of \['test', 'validation', 'crowdnav'\], got 'train'"):
        source_of("train")


@pytest.mark.parametrize("split", ["test", "validation"])
def test_seeded_splits_draw_their_scenes_from_the_seed_and_take_any_scenario(split):
    source = source_of(split)
    assert not source.gives_scenes and not gives_scenes(split)
    assert source.takes("random") and source.takes("crowdnav-circle-crossing") and source.own_env_options == {}
    assert source.episode_seeds(2, 3) == splits.episode_seeds(split, 2, 3)
    assert source.describe(10) == {}


def test_crowdnav_gives_case_i_to_episode_i_of_its_presets_only():
    source = source_of("crowdnav")
    assert source.gives_scenes and source.takes("crowdnav-square-crossing") and not source.takes("random")
    assert source.episode_seeds(0, 3) == splits.heldout_seeds(0, 3)  # the test split's seeds for the agent
    layout, visible = crowdnav.PRESET_LAYOUTS["crowdnav-circle-crossing"]
    assert source.scene("crowdnav-circle-crossing", 7, None, None) == crowdnav.crowdnav_test_case(layout, 7, None, visible, None)
    assert source.scene("crowdnav-circle-crossing", 7, None, None) != source.scene("crowdnav-circle-crossing", 8, None, None)
    base = crowdnav.TEST_CASE_SEED_BASE
    assert source.describe(500) == {"crowdnav_case_seeds": [base, base + 499]}
    with pytest.raises(ValueError, match="episodes must be <= 500 on split 'crowdnav'"):
        source.episode_seeds(0, 501)
    assert "robot_visible" in source.own_env_options  # its -visible presets set it
