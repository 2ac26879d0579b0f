"""vpmap.plan(..., planner="smooth") checked here, pose by pose, without vpmap's own validator.

A drivable path: its poses at most a quarter cell apart, the first and last the asked ones,
headings changing no faster than 1 / turning_radius along the way and pointing where the
path goes, every pose's unit square clear of the blocked cells, and no shorter than the
exact any-angle path (conftest's visibility-graph reference).
"""

import math

import numpy as np
import pytest

import vpmap
from conftest import any_angle_optimum


def room_with_a_wall():
    """40 x 30 cells, a border, and a wall from the top down to row 18 at column 20."""
    blocked = np.zeros((30, 40), dtype=np.int8)
    blocked[0, :] = blocked[-1, :] = 1
    blocked[:, 0] = blocked[:, -1] = 1
    blocked[:19, 20] = 1
    return blocked


def angle_between(a_deg, b_deg):
    """The smallest difference of two headings, degrees."""
    return abs((a_deg - b_deg + 180.0) % 360.0 - 180.0)


def check_drivable(blocked, path, start, goal, radius, scale=1.0, y_up=False):
    """The checks of the module docstring; `scale` map units a cell."""
    poses = path.poses
    assert poses.dtype == np.float64 and poses.ndim == 2 and poses.shape[1] == 3
    assert len(path) == len(poses) >= 2
    assert tuple(poses[0, :2]) == pytest.approx(start[:2], abs=1e-9)
    assert tuple(poses[-1, :2]) == pytest.approx(goal[:2], abs=1e-9)
    if len(start) == 3:
        assert angle_between(poses[0, 2], start[2]) < 1e-6
    if len(goal) == 3:
        assert angle_between(poses[-1, 2], goal[2]) < 1e-6
    steps = np.hypot(*np.diff(poses[:, :2], axis=0).T)
    assert steps.max() <= 0.25 * scale + 1e-9
    # A chord of an arc is shorter than the arc, so the turn over a chord is at most
    # chord / R times (1 + a quarter cell's second-order term).
    turns = np.array([angle_between(a, b) for a, b in zip(poses[:-1, 2], poses[1:, 2])])
    assert np.all(np.radians(turns) <= steps / radius * 1.001 + 1e-9)
    # Forward driving: each step runs along the headings at its ends.
    for (x0, y0, h0), (x1, y1, h1), step in zip(poses[:-1], poses[1:], steps):
        if step < 1e-9:
            continue
        going = math.degrees(math.atan2(y1 - y0, x1 - x0))
        mid = h0 + ((h1 - h0 + 180.0) % 360.0 - 180.0) / 2.0
        assert angle_between(going, mid) < 1.0, (going, h0, h1)
    # Every pose's unit square (one cell) clear of every blocked cell's interior.
    rows, cols = np.nonzero(blocked)
    height = blocked.shape[0]
    for x, y, _ in poses:
        if y_up:
            cx, cy = x / scale - 0.5, height - y / scale - 0.5
        else:
            cx, cy = x / scale, y / scale
        gap = np.maximum(np.abs(cols - cx), np.abs(rows - cy))
        assert gap.min() >= 1.0 - 1e-6, (x, y)
    assert path.max_curvature <= 1.0 / radius + 1e-9
    assert path.length >= np.sum(steps) - 1e-9
    assert path.cusps == 0


def test_a_smooth_path_is_drivable_and_no_shorter_than_the_any_angle_path():
    blocked = room_with_a_wall()
    start, goal = (5.0, 5.0, 0.0), (34.0, 5.0, 180.0)
    path = vpmap.plan(
        blocked, start[:2], goal[:2], "smooth", turning_radius=3.0, start_heading=0.0, goal_heading=180.0
    )
    assert isinstance(path, vpmap.SmoothPath)
    assert path.found and path.reason is None and path.units == "cells"
    check_drivable(blocked, path, start, goal, 3.0)
    exact = any_angle_optimum(blocked, (5, 5), (34, 5))
    assert path.length >= exact - 1e-9
    kinds = {s["type"] for s in path.segments}
    assert kinds <= {"line", "arc"} and "arc" in kinds
    assert all(s["radius"] >= 3.0 - 1e-9 for s in path.segments if s["type"] == "arc")
    assert path.answer["found"] is True and path.answer["planner"] == "smooth"


def test_free_headings_and_a_grid_in_metres():
    blocked = room_with_a_wall()
    grid = vpmap.Grid(blocked, resolution=0.1, origin=(0.0, 0.0))
    # Cell (5, 25) is 0.55 m across and 0.45 m up (row 25 of 30, y up).
    start, goal = (0.55, 0.45), (3.45, 0.45)
    path = vpmap.plan(grid, start, goal, "smooth", turning_radius=0.3)
    assert path.found and path.units == "m"
    check_drivable(blocked, path, start, goal, 0.3, scale=0.1, y_up=True)


def test_no_room_to_turn_says_which_pose_and_how_much_room():
    # A corridor one cell wide, the start against its closed end and facing it: no turn of
    # radius 2 and no straight line leaves it (a turn needs about 2 R + 1 = 5 cells).
    blocked = np.ones((9, 30), dtype=np.int8)
    blocked[4, 1:29] = 0
    path = vpmap.plan(blocked, (1, 4), (25, 4), "smooth", turning_radius=2.0, start_heading=180.0)
    assert not path.found
    assert path.length is None and len(path) == 0 and path.poses.shape == (0, 3)
    assert "start pose (1, 4)" in path.reason and "about 5 cells wide" in path.reason, path.reason
    # Facing down the corridor, the straight line to the goal is drivable.
    path = vpmap.plan(blocked, (1, 4), (25, 4), "smooth", turning_radius=2.0, start_heading=0.0)
    assert path.found and path.length == pytest.approx(24.0, abs=1e-9)


@pytest.mark.parametrize(
    "kwargs, words",
    [
        ({"planner": "smooth", "turning_radius": 0.0}, ["turning_radius", "positive"]),
        ({"planner": "smooth", "turning_radius": float("nan")}, ["turning_radius"]),
        ({"planner": "smooth", "turning_radius": 1e6}, ["turning_radius", "larger than the map"]),
        ({"planner": "smooth"}, ["needs turning_radius"]),
        ({"planner": "smooth", "turning_radius": 2.0, "start_heading": float("inf")}, ["heading", "finite"]),
        ({"planner": "astar", "turning_radius": 2.0}, ["planner=\"smooth\""]),
        ({"planner": "optimal", "goal_heading": 90.0}, ["planner=\"smooth\""]),
    ],
)
def test_bad_smooth_input_is_refused_by_name(kwargs, words):
    blocked = room_with_a_wall()
    with pytest.raises(vpmap.VpmapError) as e:
        vpmap.plan(blocked, (5, 5), (34, 5), **kwargs)
    for w in words:
        assert w in str(e.value), str(e.value)


def test_a_planner_object_does_not_take_smooth():
    with pytest.raises(vpmap.VpmapError, match="smooth"):
        vpmap.Planner(room_with_a_wall(), "smooth")
