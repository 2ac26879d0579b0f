"""Grid: numpy round trips, files, and the forms an array may come in."""

import numpy as np
import pytest

import vpmap
from conftest import MOVINGAI, random_grid


def test_int8_round_trip_and_array_is_kept_without_copies():
    a = random_grid(1, 7, 11, 0.3)
    a[0, 0] = -1
    g = vpmap.Grid(a)
    assert g.shape == (7, 11) and g.width == 11 and g.height == 7
    assert g.resolution is None and g.origin is None and g.units == "cells"
    out = g.array
    np.testing.assert_array_equal(out, a)
    assert out.dtype == np.int8 and out.flags.c_contiguous
    assert not out.flags.writeable
    with pytest.raises(ValueError):
        out[0, 0] = 1
    assert g.array is out or np.shares_memory(g.array, out)
    assert g.counts == ((a == 0).sum(), (a == 1).sum(), (a == -1).sum())


@pytest.mark.parametrize("dtype", [np.uint8, np.int16, np.uint16, np.int32, np.uint32, np.int64, np.uint64])
def test_every_integer_dtype_converts(dtype):
    a = random_grid(2, 5, 6, 0.4).astype(dtype)
    a[1, 2] = 255
    g = vpmap.Grid(a)
    want = a.astype(np.int64)
    want[want == 255] = -1
    np.testing.assert_array_equal(g.array, want)


def test_bool_lists_and_memory_orders_convert():
    b = random_grid(3, 6, 9, 0.5).astype(bool)
    np.testing.assert_array_equal(vpmap.Grid(b).array, b.astype(np.int8))
    base = random_grid(4, 8, 10, 0.3)
    np.testing.assert_array_equal(vpmap.Grid(np.asfortranarray(base)).array, base)
    np.testing.assert_array_equal(vpmap.Grid(base[::2, ::3]).array, base[::2, ::3])
    np.testing.assert_array_equal(vpmap.Grid(base.T).array, base.T)
    np.testing.assert_array_equal(vpmap.Grid(base.tolist()).array, base)


def test_a_metric_frame():
    g = vpmap.Grid(np.zeros((4, 4), np.int8), resolution=0.5, origin=(-1.0, 2.0))
    assert g.resolution == 0.5 and g.origin == (-1.0, 2.0) and g.units == "m"
    # Row 0 is the top: the highest y.
    assert g.world_from_cell(0, 0) == (-0.75, 3.75)
    assert g.world_from_cell(3, 3) == (0.75, 2.25)


def test_ros_files_round_trip(tmp_path):
    a = random_grid(5, 12, 9, 0.25)
    a[0, :] = -1
    g = vpmap.Grid(a, resolution=0.05, origin=(1.0, -2.0))
    image = g.save_ros(tmp_path / "room.yaml")
    assert image.endswith(".pgm")
    back = vpmap.Grid.load(tmp_path / "room.yaml")
    assert back == g
    np.testing.assert_array_equal(back.array, a)
    assert back.resolution == 0.05 and back.origin == (1.0, -2.0)


def test_moving_ai_and_map_json_files(tmp_path):
    text = "type octile\nheight 3\nwidth 4\nmap\n..@.\n.T..\n....\n"
    (tmp_path / "tiny.map").write_text(text)
    g = vpmap.Grid.load(tmp_path / "tiny.map")
    assert g.units == "cells" and g.resolution is None
    np.testing.assert_array_equal(g.array, [[0, 0, 1, 0], [0, 1, 0, 0], [0, 0, 0, 0]])
    from conftest import EXAMPLE

    m = vpmap.build(EXAMPLE)
    (tmp_path / "map.json").write_text(m.to_json())
    assert vpmap.Grid.load(tmp_path / "map.json") == m.occupancy()
    assert vpmap.Grid.load(tmp_path / "map.json", robot_radius=0.0) == m.occupancy(robot_radius=0.0)


@pytest.mark.skipif(not MOVINGAI.is_dir(), reason="../shared/data is absent")
def test_a_moving_ai_benchmark_map():
    g = vpmap.Grid.load(MOVINGAI / "random" / "random512-10-0.map")
    assert g.shape == (512, 512) and g.units == "cells"
    assert 0.05 < g.counts[1] / (512 * 512) < 0.15


def test_inflation():
    a = np.zeros((9, 9), np.int8)
    a[4, 4] = 1
    g = vpmap.Grid(a).inflate(1.0)
    assert g.counts[1] == 9 and g.robot_radius == 1.0
