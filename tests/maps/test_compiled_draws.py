"""scenarios.draws: numpy's Generator draws made in compiled code are numpy's, value for value, and leave
the generator in numpy's state (the buffered 32-bit half of PCG64 included), whatever came before."""

import numpy as np
import pytest

from pathplan_env.maps.draws import bit_source, integers, uniform


def same_state(a, b) -> bool:
    """Bit generator states (dicts, MT19937's key an array) equal."""
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(same_state(a[k], b[k]) for k in a)
    return bool(np.array_equal(a, b)) if isinstance(a, np.ndarray) else a == b


BOUNDS = (1, 2, 3, 7, 64, 4999, 5000, 25597, 2**31 - 1, 2**31, 2**31 + 5, 3 * 2**30 + 1, 2**32 - 1, 2**32)


@pytest.mark.parametrize("bit_generator", [np.random.PCG64, np.random.PCG64DXSM, np.random.MT19937, np.random.Philox, np.random.SFC64])
def test_draws_are_numpy_draws(bit_generator):
    for seed in range(40):
        ours, theirs = np.random.Generator(bit_generator(seed)), np.random.Generator(bit_generator(seed))
        source = bit_source(ours)
        for n in BOUNDS:
            for k in (0, 1, 2, 63, 64, 384):  # odd counts leave half a 64-bit draw buffered
                got, expected = integers(source, n, k), theirs.integers(n, size=k)
                assert got.dtype == expected.dtype and np.array_equal(got, expected)
                assert np.array_equal(uniform(source, 2 * k + 1), theirs.random(2 * k + 1))
                if k % 7 == 1:  # numpy's own draws in between see the state ours left
                    assert ours.integers(1000, size=3).tolist() == theirs.integers(1000, size=3).tolist()
                    assert ours.random() == theirs.random()
        assert same_state(ours.bit_generator.state, theirs.bit_generator.state)


def test_rejections_are_numpy_rejections():
    """Bounds just above 2**31 reject almost half the draws: the loop's extra draws are numpy's."""
    ours, theirs = np.random.default_rng(5), np.random.default_rng(5)
    source = bit_source(ours)
    for _ in range(50):
        assert np.array_equal(integers(source, 2**31 + 1, 257), theirs.integers(2**31 + 1, size=257))
    assert same_state(ours.bit_generator.state, theirs.bit_generator.state)


def test_the_maze_draw_is_numpys():
    """crowd_families._maze_draws: the maze-crowd's candidates as its numpy draw made them."""
    from pathplan_env.scenarios.crowd_families import _maze_draws, _maze_map

    occupancy = _maze_map()
    cells, cols = occupancy.free_cells(0.4), occupancy.occupied.shape[1]
    for seed in range(30):
        ours, theirs = np.random.default_rng(seed), np.random.default_rng(seed)
        for k in (384, 64, 1):
            starts, angle, reach = _maze_draws(cells, bit_source(ours), k, cols, float(occupancy.resolution), *map(float, occupancy.origin))
            picks = cells[theirs.integers(len(cells), size=k)]
            expected = (np.column_stack([picks % cols, picks // cols]) + theirs.random((k, 2))) * occupancy.resolution + occupancy.origin
            assert np.array_equal(starts, expected)
            assert np.array_equal(angle, 2.0 * np.pi * theirs.random(k)) and np.array_equal(reach, 2.0 + 3.0 * theirs.random(k))
        assert ours.bit_generator.state == theirs.bit_generator.state
