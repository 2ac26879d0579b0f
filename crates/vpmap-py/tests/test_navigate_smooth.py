"""vpmap.navigate(..., planner="smooth") checked from its poses alone, without vpmap's validator.

The driven poses must be what a car-like robot can drive: at most a quarter cell apart, the
first the asked start, the last the goal when it was reached, the heading turning no faster
than 1 / turning_radius along the way, each step running along the heading (forward) or
against it (reverse, each change of direction a cusp), and every pose's unit square clear of
the true map's blocked cells. The drive is the one `vpmap navigate --planner smooth` makes:
with VPMAP_BIN set, the command's navigate.json is compared with the dict.
"""

import json
import math
import os
import subprocess

import numpy as np
import pytest

import vpmap
from conftest import TRUTH


def room_with_a_wall():
    """40 x 24 cells, a wall down from the top at column 20 (rows 0-15), as the CLI's test."""
    blocked = np.zeros((24, 40), dtype=np.int8)
    blocked[:16, 20] = 1
    return blocked


def angle_between(a_deg, b_deg):
    """The smallest difference of two headings, degrees."""
    return abs((a_deg - b_deg + 180.0) % 360.0 - 180.0)


def gears_of(poses):
    """+1 (forward) or -1 (reverse) for each step of non-zero length, from the poses alone.

    A step runs along the mean of its end headings or against it; anything else is not a
    drivable step and fails the test.
    """
    gears = []
    for (x0, y0, h0), (x1, y1, h1) in zip(poses[:-1], poses[1:]):
        if math.hypot(x1 - x0, y1 - y0) < 1e-9:
            continue
        going = math.degrees(math.atan2(y1 - y0, x1 - x0))
        mid = h0 + ((h1 - h0 + 180.0) % 360.0 - 180.0) / 2.0
        if angle_between(going, mid) < 1.0:
            gears.append(1)
        elif angle_between(going, mid + 180.0) < 1.0:
            gears.append(-1)
        else:
            pytest.fail(f"a step from {(x0, y0, h0)} to {(x1, y1, h1)} runs neither along nor against its heading")
    return gears


def check_driven(blocked, report, start, radius):
    """The checks of the module docstring on a cells grid; returns the independent cusp count."""
    poses = report["poses"]
    assert isinstance(poses, np.ndarray) and poses.dtype == np.float64
    assert poses.ndim == 2 and poses.shape[1] == 3 and len(poses) >= 2
    assert report["moves"] == len(poses) - 1
    assert tuple(poses[0, :2]) == pytest.approx(start[:2], abs=1e-9)
    if len(start) == 3:
        assert angle_between(poses[0, 2], start[2]) < 1e-9
    steps = np.hypot(*np.diff(poses[:, :2], axis=0).T)
    assert steps.max() <= 0.25 + 1e-9
    # A chord of an arc is shorter than the arc: the turn over a chord is at most chord / R
    # times (1 + a quarter cell's second-order term).
    turns = np.radians([angle_between(a, b) for a, b in zip(poses[:-1, 2], poses[1:, 2])])
    assert np.all(turns <= steps / radius * 1.001 + 1e-9), (turns.max(), radius)
    rows, cols = np.nonzero(blocked)
    for x, y, _ in poses:
        gap = np.maximum(np.abs(cols - x), np.abs(rows - y))
        assert gap.min() >= 1.0 - 1e-6, (x, y)
    assert report["length"] >= np.sum(steps) - 1e-9
    assert report["max_curvature"] <= 1.0 / radius + 1e-9
    gears = gears_of(poses)
    return sum(a != b for a, b in zip(gears[:-1], gears[1:]))


def test_a_smooth_drive_into_the_unknown_is_drivable_and_reaches_the_goal():
    blocked = room_with_a_wall()
    start, goal = (5.0, 8.0, 90.0), (35.0, 8.0)
    report = vpmap.navigate(
        None,
        vpmap.Grid(blocked),
        start[:2],
        goal,
        planner="smooth",
        turning_radius=2.0,
        start_heading=90.0,
        sensor_range=10.0,
    )
    assert report["planner"] == "smooth" and report["units"] == "cells"
    assert report["outcome"] == "reached" and report["reached"], report["reason"]
    assert report["replans"] >= 1, "the wall was unknown at the start"
    assert report["turning_radius"] == 2.0 and report["reverse"] is False
    cusps = check_driven(blocked, report, start, 2.0)
    assert cusps == report["cusps"] == 0
    assert tuple(report["poses"][-1, :2]) == pytest.approx(goal, abs=1e-6)
    # Around the wall: no shorter than the exact any-angle path on the true map.
    assert report["length"] >= report["optimum_any_angle"] - 1e-9
    assert report["length"] > 30.0 + 1.0
    kinds = {s["type"] for s in report["segments"]}
    assert kinds <= {"line", "arc"} and "arc" in kinds
    assert all(s["radius"] >= 2.0 - 1e-9 for s in report["segments"] if s["type"] == "arc")


def test_backing_out_of_a_wall_needs_reverse_and_gives_cusps():
    # Facing the wall 6 cells ahead with a turning radius of 5 and a short sensor: driving
    # forward, the robot is caught; allowed to reverse, it backs up and gets there.
    blocked = room_with_a_wall()
    kwargs = dict(planner="smooth", turning_radius=5.0, start_heading=0.0, sensor_range=2.0)
    start = (14.0, 6.0, 0.0)
    forward = vpmap.navigate(None, vpmap.Grid(blocked), start[:2], (35.0, 6.0), **kwargs)
    assert forward["outcome"] == "no drivable path from the robot's pose", forward["outcome"]
    assert not forward["reached"] and "radius" in forward["reason"]
    assert check_driven(blocked, forward, start, 5.0) == forward["cusps"] == 0
    backing = vpmap.navigate(None, vpmap.Grid(blocked), start[:2], (35.0, 6.0), reverse=True, **kwargs)
    assert backing["reached"], backing["reason"]
    assert backing["reverse"] is True
    cusps = check_driven(blocked, backing, start, 5.0)
    assert cusps >= 1 and cusps == backing["cusps"]
    assert tuple(backing["poses"][-1, :2]) == pytest.approx((35.0, 6.0), abs=1e-6)


def test_the_picture_adds_only_the_svg():
    blocked = room_with_a_wall()
    args = (None, vpmap.Grid(blocked), (5.0, 8.0), (35.0, 8.0))
    plain = vpmap.navigate(*args, planner="smooth", turning_radius=2.0)
    drawn = vpmap.navigate(*args, planner="smooth", turning_radius=2.0, svg=True)
    assert "svg" not in plain
    picture = drawn.pop("svg")
    assert "smooth-path" in picture and picture.rstrip().endswith("</svg>")
    assert np.array_equal(drawn.pop("poses"), plain.pop("poses"))
    for key in ("length", "cusps", "replans", "segments", "outcome"):
        assert drawn[key] == plain[key], key


def test_a_smooth_drive_in_metres():
    # The example's room, known to nobody at the start; poses in metres, y up.
    report = vpmap.navigate(
        None, TRUTH, (1.5, 3.0), (-1.5, 6.0), planner="smooth", turning_radius=0.3, goal_heading=90.0
    )
    assert report["units"] == "m" and report["reached"], report["reason"]
    poses = report["poses"]
    assert tuple(poses[0, :2]) == pytest.approx((1.5, 3.0), abs=0.025 + 1e-9)
    assert tuple(poses[-1]) == pytest.approx((-1.5, 6.0, 90.0), abs=0.025 + 1e-6)
    steps = np.hypot(*np.diff(poses[:, :2], axis=0).T)
    assert steps.max() <= 0.25 * 0.05 + 1e-9
    turns = np.radians([angle_between(a, b) for a, b in zip(poses[:-1, 2], poses[1:, 2])])
    assert np.all(turns <= steps / 0.3 * 1.001 + 1e-9)
    assert report["length"] >= report["optimum_any_angle"] - 1e-9


@pytest.mark.parametrize(
    "kwargs, words",
    [
        ({"planner": "smooth", "turning_radius": 0.0}, ["turning_radius", "positive", "got 0"]),
        ({"planner": "smooth", "turning_radius": -1.5}, ["turning_radius", "got -1.5"]),
        ({"planner": "smooth", "turning_radius": float("nan")}, ["turning_radius", "NaN"]),
        ({"planner": "smooth", "turning_radius": 1e6}, ["turning_radius", "larger than the map"]),
        ({"planner": "smooth"}, ["needs turning_radius"]),
        ({"planner": "smooth", "turning_radius": 2.0, "goal_heading": float("nan")}, ["heading", "finite", "NaN"]),
        ({"planner": "dstar-lite", "start_heading": 90.0}, ['planner="smooth"', '"dstar-lite"']),
        ({"planner": "astar", "reverse": True}, ['planner="smooth"', '"astar"']),
        ({"turning_radius": 2.0}, ['planner="smooth"']),
        ({"planner": "smoooth", "turning_radius": 2.0}, ["smoooth", "smooth"]),
    ],
)
def test_bad_smooth_input_is_refused_by_name(kwargs, words):
    with pytest.raises(ValueError) as e:
        vpmap.navigate(None, vpmap.Grid(room_with_a_wall()), (5, 8), (35, 8), **kwargs)
    assert isinstance(e.value, vpmap.VpmapError)
    for w in words:
        assert w in str(e.value), str(e.value)


def movingai_text(blocked):
    rows = ["".join("@" if v else "." for v in row) for row in blocked]
    height, width = blocked.shape
    return f"type octile\nheight {height}\nwidth {width}\nmap\n" + "\n".join(rows) + "\n"


@pytest.mark.skipif(not os.environ.get("VPMAP_BIN"), reason="VPMAP_BIN (the vpmap binary) not given")
def test_the_drive_is_the_command_lines(tmp_path):
    blocked = room_with_a_wall()
    truth = tmp_path / "truth.map"
    truth.write_text(movingai_text(blocked))
    out = tmp_path / "out"
    r = subprocess.run(
        [os.environ["VPMAP_BIN"], "navigate", "--unknown", "--truth", str(truth), "--planner", "smooth",
         "--from", "5,8,90", "--to", "35,8", "--turning-radius", "2", "--reverse", "--out", str(out)],
        capture_output=True,
        text=True,
    )
    assert r.returncode == 0, r.stderr
    cli = json.loads((out / "navigate.json").read_text())
    py = vpmap.navigate(
        None, truth, (5, 8), (35, 8), planner="smooth", turning_radius=2.0, start_heading=90.0, reverse=True
    )
    assert np.array_equal(py.pop("poses"), np.array(cli.pop("poses")))
    for key in ("length", "cusps", "replans", "segments", "outcome", "moves", "max_curvature", "min_clearance"):
        assert py[key] == cli[key], key
