"""A map is drawn cropped to its free space, not at its image's extent."""

import gymnasium as gym
import numpy as np

from pathplan_env import Scenario
from pathplan_env.rendering import view_of

ROOM = (10.0, 12.0, 20.0, 20.0)  # the free rooms of a 30 m image whose margin is unknown (occupied)


def _mapped_scene() -> Scenario:
    x0, y0, x1, y1 = ROOM
    around = [((0, 0), (30, 0), (30, y0), (0, y0)), ((0, y1), (30, y1), (30, 30), (0, 30)),
              ((0, y0), (x0, y0), (x0, y1), (0, y1)), ((x1, y0), (30, y0), (30, y1), (x1, y1))]  # fmt: skip
    return Scenario(bounds=(0, 0, 30, 30), start=(11, 13), goal=(19, 19), polygons=around, robot_radius=0.2)


def test_the_view_is_the_free_space_padded_by_the_robot():
    assert view_of(_mapped_scene()) == (9.6, 11.6, 20.4, 20.4)
    plain = Scenario(bounds=(0, 0, 10, 10), start=(1, 1), goal=(9, 9))
    assert view_of(plain) == (0.0, 0.0, 10.0, 10.0)


def test_a_rendered_map_fills_the_frame_with_its_free_space():
    env = gym.make("DynamicObstacle-v0", scenario=_mapped_scene(), render_mode="rgb_array")
    env.reset(seed=0)
    frame = env.render()
    assert frame.shape == (489, 600, 3)  # 10.8 m x 8.8 m at 600 px on the long side, not 30 m square
    occupied = np.all(frame == (110, 110, 118), axis=-1).mean()  # the polygons' colour
    assert occupied < 0.2  # the padding only; before, the margin took 8/9 of the frame
