"""vpmap.build and Map against the bundled example's known truth."""

import json

import numpy as np
import pytest

import vpmap
from conftest import EXAMPLE


def test_the_example_builds_from_a_path_a_dict_and_text_alike():
    from_path = vpmap.build(str(EXAMPLE))
    from_pathlib = vpmap.build(EXAMPLE)
    from_dict = vpmap.build(json.loads(EXAMPLE.read_text()))
    from_text = vpmap.build(EXAMPLE.read_text())
    assert from_path.to_json() == from_pathlib.to_json() == from_dict.to_json() == from_text.to_json()
    # The desk and the chair stand 6.3-6.6 m away: at the default 1 px clicks their depth is
    # known to about +-0.3 m (95 %), which the map says in words.
    assert [w.split(": its place is uncertain by")[0] for w in from_path.warnings] == [
        'object "desk"',
        'object "chair"',
    ]
    assert from_path.method == "fit" and from_path.units == "m"


def test_the_fit_meets_the_examples_truth(office_truth):
    m = vpmap.build(EXAMPLE)
    cam, true_cam = m.camera, office_truth["camera"]
    assert cam["focal_px"] == pytest.approx(true_cam["focal_px"], abs=1e-6)
    assert cam["pitch_deg"] == pytest.approx(true_cam["pitch_deg"], abs=1e-6)
    assert cam["roll_deg"] == pytest.approx(true_cam["roll_deg"], abs=1e-6)
    assert cam["height"] == pytest.approx(true_cam["height"], abs=1e-6)
    assert len(m.objects) == len(office_truth["objects"])
    for got, want in zip(m.objects, office_truth["objects"]):
        assert got["name"] == want["name"]
        np.testing.assert_allclose(got["footprint"], want["footprint"], atol=1e-6)
        assert got["height"] == pytest.approx(want["height"], abs=1e-6)
        assert {"centroid", "area", "uncertainty"} <= set(got)
        if got["kind"] == "box":
            assert got["size"]["length"] > 0 and got["size"]["breadth"] > 0
        np.testing.assert_allclose(got["centroid"], np.mean(want["footprint"], axis=0), atol=1e-6)
    floor = m.floor
    assert floor.dtype == np.float64 and floor.shape == (len(office_truth["floor"]), 2)
    np.testing.assert_allclose(floor, office_truth["floor"], atol=1e-6)


def test_to_json_is_map_json():
    m = vpmap.build(EXAMPLE)
    parsed = json.loads(m.to_json())
    assert parsed == m.to_dict()
    assert parsed["version"] == 1 and parsed["method"] == "fit"
    assert parsed["camera"] == m.camera and parsed["objects"] == m.objects


def test_methods_and_click_sigma():
    fit = vpmap.build(EXAMPLE, click_sigma=2.0)
    assert fit.fit["click_sigma_px"] == 2.0
    side = vpmap.build(EXAMPLE, method="sideview")
    assert side.method == "sideview" and side.fit is None
    assert side.camera["pitch_deg"] == pytest.approx(fit.camera["pitch_deg"], abs=1e-6)


def test_occupancy_grids_as_vpmap_build_writes_them():
    m = vpmap.build(EXAMPLE)
    g = m.occupancy()
    assert g.resolution == 0.05 and g.units == "m" and g.robot_radius == 0.2
    free, occupied, unknown = g.counts
    assert free > 0 and occupied > 0 and unknown > 0
    a = g.array
    assert a.shape == g.shape and a.dtype == np.int8
    assert set(np.unique(a)) <= {-1, 0, 1}
    assert (a == 0).sum() == free and (a == 1).sum() == occupied
    coarse = m.occupancy(resolution=0.1, robot_radius=0.0)
    assert coarse.width < g.width and coarse.robot_radius == 0.0
    bare = m.occupancy(robot_radius=0.0)
    assert bare.shape == g.shape and bare.counts[1] < occupied
    grown = m.occupancy(grow_confidence=0.95, robot_radius=0.0)
    assert grown.counts[1] >= bare.counts[1]
    assert np.all(grown.array[bare.array == 1] == 1)
    hidden_free = m.occupancy(hidden_free=True)
    assert hidden_free.counts[2] < unknown
    # The build's own grid is the default one.
    assert m.occupancy() == g


def test_the_example_is_planned_across():
    m = vpmap.build(EXAMPLE)
    g = m.occupancy()
    path = vpmap.plan(g, (-1.5, 2.0), (2.0, 7.5), "mbpp")
    assert path.found and path.units == "m"
    assert path.waypoints[0] == pytest.approx(g.world_from_cell(*path.cells[0]))
    assert np.linalg.norm(path.waypoints[0] - [-1.5, 2.0]) < 0.05
    assert np.linalg.norm(path.waypoints[-1] - [2.0, 7.5]) < 0.05
    assert path.length >= np.hypot(3.5, 5.5) - 0.1


ROOM = EXAMPLE.parents[1] / "crates" / "vpmap-metrology" / "tests" / "fixtures" / "room-mv00.json"


def test_a_room_file_builds_one_map_with_every_camera():
    """A room of two photos (an independent simulator's, exact clicks) against its truth."""
    truth = json.loads(ROOM.with_name("room-mv00.truth.json").read_text())
    m = vpmap.build(ROOM)
    cameras = json.loads(m.to_json())["cameras"]
    assert len(cameras) == 2
    for got, want in zip(cameras, truth["cameras"]):
        np.testing.assert_allclose(got["position"][:2], want["position"], atol=1e-9)
        assert got["height"] == pytest.approx(want["height"], abs=1e-9)
    names = {o["name"]: o for o in m.objects}
    for want in truth["objects"]:
        got = names[want["name"]]
        assert got["height"] == pytest.approx(want["height"], abs=1e-9)
    grid = m.occupancy(resolution=0.05, robot_radius=0.2)
    assert (grid.array == 0).any()
