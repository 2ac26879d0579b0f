"""Bad input raises VpmapError (a ValueError) naming the value, never crashes."""

import json
import os
import subprocess

import numpy as np
import pytest

import vpmap
from conftest import EXAMPLE, REPO


def raises(fn, *args, match=None, **kwargs):
    with pytest.raises(vpmap.VpmapError, match=match) as info:
        fn(*args, **kwargs)
    assert isinstance(info.value, ValueError)
    return str(info.value)


def test_vpmap_error_is_a_value_error():
    assert issubclass(vpmap.VpmapError, ValueError)


def test_scenes_that_cannot_be_read_or_built(tmp_path):
    raises(vpmap.build, 42, match="neither a dict, JSON text nor a file path")
    raises(vpmap.build, str(tmp_path / "missing.json"), match="missing.json")
    bad = tmp_path / "bad.json"
    bad.write_text("{\"version\": ")
    assert raises(vpmap.build, bad).startswith(f"{bad}: scene file is malformed: ")
    bad.write_text("[1]")
    assert raises(vpmap.build, bad) == f"{bad}: scene file is malformed: it must be a JSON object ({{ ... }})"
    raises(vpmap.build, "{\"version\": ", match="not valid JSON")
    raises(vpmap.build, {"version": 1, "vanishing_points": "up"}, match="\"up\"")
    raises(vpmap.build, {"version": 1, "x": object()}, match="cannot be written as JSON")
    raises(vpmap.build, EXAMPLE, method="magic", match='unknown method "magic"')
    scene = json.loads(EXAMPLE.read_text())
    scene["image"]["width"] = "wide"
    raises(vpmap.build, scene, match='"wide"')
    scene = json.loads(EXAMPLE.read_text())
    scene["scael"] = 2
    warnings = vpmap.build(scene).warnings
    assert warnings[0] == 'unknown field "scael" is ignored (see docs/scene-format.md)'
    assert warnings[1:] == vpmap.build(EXAMPLE).warnings
    raises(vpmap.build, EXAMPLE, click_sigma=-1.0, match="click_sigma must be a non-negative number of pixels, at most 100, got -1")
    raises(vpmap.build, EXAMPLE, click_sigma=float("nan"), match="click_sigma")


def test_occupancy_options_out_of_range():
    m = vpmap.build(EXAMPLE)
    raises(m.occupancy, resolution=float("nan"), match="resolution must be a positive number of metres, from 0.001 to 100, got NaN")
    raises(m.occupancy, resolution=0.0, match="resolution must be .* got 0$")
    raises(m.occupancy, robot_radius=-1.0, match="robot_radius must be a non-negative number of metres, at most 1000, got -1")
    raises(m.occupancy, grow_confidence=2.0, match="grow_confidence")
    side = vpmap.build(EXAMPLE, method="sideview")
    raises(side.occupancy, grow_confidence=0.95, match="only the fit method")


def test_arrays_of_the_wrong_form():
    raises(vpmap.Grid, np.zeros((2, 3, 4), np.int8), match=r"must be 2-D .* got shape \(2, 3, 4\)")
    raises(vpmap.Grid, np.zeros(5, np.int8), match="must be 2-D")
    raises(vpmap.Grid, np.zeros((3, 3)), match="dtype float64 is not a grid; give integers or bools")
    a = np.zeros((3, 4), np.int8)
    a[2, 1] = 7
    raises(vpmap.Grid, a, match="holds 7 at row 2, column 1")
    raises(vpmap.Grid, np.zeros((0, 4), np.int8), match="4 x 0 cells is empty")
    raises(vpmap.Grid, np.zeros((3, 3), np.int8), resolution=float("nan"), match="NaN")
    raises(vpmap.Grid, [[0, 1], [0]], match="not an array")
    raises(vpmap.Grid, np.array(["a", "b"]).reshape(1, 2), match="dtype <U1")


def test_files_that_are_not_maps(tmp_path):
    assert raises(vpmap.Grid.load, "floor.png") == (
        "floor.png: unknown map type; give a Moving AI .map, a ROS map .yaml or a vpmap map.json"
    )
    raises(vpmap.Grid.load, tmp_path / "missing.map", match="missing.map")
    (tmp_path / "x.json").write_text("{}")
    raises(vpmap.Grid.load, tmp_path / "x.json", match="not a vpmap map.json")
    raises(vpmap.Grid.load, 3.5, match="not a file path")


def test_starts_and_goals_outside_or_blocked():
    a = np.zeros((4, 5), np.int8)
    a[1, 1] = 1
    a[2, 2] = -1
    g = vpmap.Grid(a)
    assert raises(vpmap.plan, g, (9, 0), (0, 0)) == "start (9, 0) is outside the 5 x 4 map"
    assert raises(vpmap.plan, g, (0, 0), (1, 1)) == "goal (1, 1) cells lies on an obstacle: cell (1, 1)"
    raises(vpmap.plan, g, (0, 0), (2, 2), match="goal .* unknown")
    raises(vpmap.plan, g, (0.5, 0), (0, 0), match="whole cell coordinates")
    raises(vpmap.plan, g, (float("nan"), 0), (0, 0), match="NaN")
    raises(vpmap.plan, g, (0, 0, 0), (1, 0), match=r"start \(0, 0, 0\) is not a point")
    raises(vpmap.plan, g, "ab", (1, 0), match="is not a point")
    raises(vpmap.plan, g, (0, 0), (4, 3), "dijkstra", match="dijkstra")
    m = vpmap.Grid(a, resolution=0.5)
    raises(vpmap.plan, m, (-3.0, 0.2), (0.2, 0.2), match=r"start \(-3, 0.2\) m is outside the map")
    raises(vpmap.plan, g, (0, 0), (4, 3), robot_radius=-1.0, match="robot_radius -1")
    raises(vpmap.plan, g, (0, 0), (4, 3), timeout=0.0, match="timeout 0 is not a time limit")
    raises(vpmap.Planner, g, "nope", match="nope")


def test_budgets_name_the_keyword():
    a = np.zeros((40, 40), np.int8)
    raises(vpmap.plan, a, (0, 0), (39, 39), "astar", max_expansions=3, match="with max_expansions$")


def test_images_that_are_not_photos(tmp_path):
    raises(vpmap.detect, tmp_path / "missing.jpg", match="missing.jpg")
    (tmp_path / "x.png").write_bytes(b"not a png")
    raises(vpmap.detect, tmp_path / "x.png", match="x.png")
    raises(vpmap.detect, np.zeros((20, 30, 3)), match="dtype float64 is not an image; give a uint8 array")
    raises(vpmap.detect, np.zeros((20, 30, 4), np.uint8), match=r"shape \[20, 30, 4\]")
    raises(vpmap.detect, np.zeros((4, 4, 3), np.uint8), match="no vanishing points found in the image")


ROOM_EXAMPLE = EXAMPLE.with_name("room.json")


def room_with_swapped_names():
    """The bundled room with photo 2's "box0" and "box1" named the other way round."""
    room = json.loads(ROOM_EXAMPLE.read_text())
    for o in room["photos"][1]["objects"]:
        o["name"] = {"box0": "box1", "box1": "box0"}.get(o["name"], o["name"])
    return room


def test_an_inconsistent_room_is_refused_with_the_words_of_vpmap_build(tmp_path):
    """Issue 39: the CLI, the server and the Python module say the same thing."""
    room = room_with_swapped_names()
    said = raises(vpmap.build, room)
    assert said.startswith("the room's photos do not fit together: ")
    assert "photo 2" in said and '"box0"' in said and '"box1"' in said
    path = tmp_path / "swapped.json"
    path.write_text(json.dumps(room))
    assert raises(vpmap.build, path) == f"building {path}: {said}"
    # `vpmap build` on the same file, when a binary is given (VPMAP_BIN): its one line is the
    # same text, and it writes nothing.
    binary = os.environ.get("VPMAP_BIN")
    if binary:
        out = tmp_path / "out"
        r = subprocess.run([binary, "build", str(path), "--out", str(out)], capture_output=True, text=True)
        assert r.returncode == 1
        assert r.stderr.strip() == f"error: building {path}: {said}"
        assert not out.exists() or not any(out.iterdir())


def tied_room():
    """The room fit's fixture with photo 2 tied to photo 1 by one box and no floor outlines."""
    room = json.loads((REPO / "crates" / "vpmap-metrology" / "tests" / "fixtures" / "room-mv00.json").read_text())
    for o in room["photos"][1]["objects"]:
        if o["name"] == "box3":
            o["name"] = "box3-seen-from-2"
    for p in room["photos"]:
        p["floor"] = []
    return room


def test_a_room_takes_a_pinned_placement_and_refuses_a_bad_one_by_name():
    room = tied_room()
    free = json.loads(vpmap.build(room).to_json())
    [alt] = free["alternatives"]
    assert alt["photo"] == 2 and alt["turn_deg"] == 180
    room["photos"][1]["placement_turn_deg"] = alt["placement_turn_deg"]
    m = vpmap.build(room)
    pinned = json.loads(m.to_json())
    assert "alternatives" not in pinned
    assert any("photo 2's placement is pinned" in w for w in m.warnings)
    moved = np.subtract(pinned["cameras"][1]["position"][:2], free["cameras"][1]["position"][:2])
    assert np.hypot(*moved) > 0.5
    room["photos"][1]["placement_turn_deg"] = 45
    said = raises(vpmap.build, room)
    assert "`photos[1].placement_turn_deg`" in said and "45 is not a quarter turn" in said
