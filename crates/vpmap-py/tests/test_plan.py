"""plan and Planner against a breadth-first and an any-angle reference written here."""

import concurrent.futures
import math
import threading
import time

import numpy as np
import pytest

import vpmap
from conftest import any_angle_optimum, bfs_reachable, octile_optimum, random_grid, segment_clear

PLANNERS = ["astar", "astar-ps", "theta-star", "mbpp", "mbpp-closer", "optimal"]


def queries(blocked, seed, n):
    """n seeded (start, goal) pairs of free cells."""
    rng = np.random.default_rng(seed)
    free = np.argwhere(blocked == 0)[:, ::-1]
    picks = rng.choice(len(free), size=(n, 2))
    return [(tuple(int(v) for v in free[i]), tuple(int(v) for v in free[j])) for i, j in picks]


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_planners_against_the_references(seed):
    blocked = random_grid(seed, 18, 22, 0.22)
    grid = vpmap.Grid(blocked)
    centres = np.argwhere(blocked)[:, ::-1].astype(float)
    for start, goal in queries(blocked, seed, 6):
        connected = bfs_reachable(blocked, start, goal)
        paths = {p: vpmap.plan(grid, start, goal, p) for p in PLANNERS}
        for name, path in paths.items():
            assert path.found == connected, (name, start, goal)
            assert path.planner == name and path.units == "cells"
        if not connected:
            assert all(p.length is None and len(p) == 0 for p in paths.values())
            continue
        octile = octile_optimum(blocked, start, goal)
        exact = any_angle_optimum(blocked, start, goal)
        assert paths["astar"].length == pytest.approx(octile, abs=1e-9)
        assert paths["optimal"].length == pytest.approx(exact, abs=1e-9)
        for name, path in paths.items():
            w = path.waypoints
            assert w.dtype == np.float64 and w.ndim == 2 and w.shape[1] == 2
            assert tuple(w[0]) == start and tuple(w[-1]) == goal
            np.testing.assert_array_equal(path.cells, w.astype(np.int64))
            assert path.length == pytest.approx(np.sum(np.hypot(*np.diff(w, axis=0).T)), abs=1e-9)
            assert path.length >= exact - 1e-9, name
            for a, b in zip(w[:-1], w[1:]):
                assert segment_clear(centres, a, b), (name, a, b)
        assert paths["theta-star"].length <= paths["astar"].length + 1e-9
        assert paths["astar-ps"].length <= paths["astar"].length + 1e-9


def test_metres_on_a_grid_with_a_resolution():
    a = np.zeros((10, 20), np.int8)
    a[2:10, 10] = 1
    g = vpmap.Grid(a, resolution=0.5, origin=(-1.0, 0.0))
    path = vpmap.plan(g, (-0.75, 0.25), (8.75, 0.25), "optimal")
    assert path.found and path.units == "m"
    in_cells = vpmap.plan(vpmap.Grid(a), (0, 9), (19, 9), "optimal")
    assert path.length == pytest.approx(0.5 * in_cells.length)
    np.testing.assert_array_equal(path.cells, in_cells.cells)
    np.testing.assert_allclose(path.waypoints[0], (-0.75, 0.25))


def test_mbpp_gives_its_bugs_and_alternatives():
    a = np.zeros((5, 6), np.int8)
    a[1:4, 2] = 1
    p = vpmap.plan(a, (0, 2), (5, 2), "mbpp", tracks=True)
    assert p.found and len(p.bugs) >= 2
    assert p.stats["bugs"] == len(p.bugs) and p.expanded == p.stats["bug_steps"]
    first = p.bugs[0]
    assert first["parent"] is None and tuple(first["cells"][0]) == (0, 2)
    assert {"hits", "leaves", "steps", "fate"} <= set(first)
    for alt in p.alternatives:
        assert isinstance(alt, vpmap.Path) and alt.found and alt.length >= p.length - 1e-9
    quiet = vpmap.plan(a, (0, 2), (5, 2), "mbpp")
    assert all(len(b["cells"]) == 0 for b in quiet.bugs)


def test_robot_radius_inflates_first():
    a = np.zeros((11, 11), np.int8)
    a[5, 5] = 1
    bare = vpmap.plan(a, (0, 5), (10, 5), "optimal")
    wide = vpmap.plan(a, (0, 5), (10, 5), "optimal", robot_radius=1.5)
    assert wide.length > bare.length


def test_a_planner_keeps_its_precomputation_and_answers_as_plan():
    blocked = random_grid(9, 30, 30, 0.2)
    grid = vpmap.Grid(blocked)
    planner = vpmap.Planner(grid, "optimal")
    assert planner.planner == "optimal" and planner.grid == grid
    for start, goal in queries(blocked, 9, 8):
        a = planner.plan(start, goal)
        b = vpmap.plan(grid, start, goal, "optimal")
        assert a.found == b.found and a.length == b.length
    astar = vpmap.Planner(grid, "astar")
    s, g = queries(blocked, 10, 1)[0]
    assert astar.plan(s, g).length == vpmap.plan(grid, s, g, "astar").length


def test_threads_plan_in_parallel():
    blocked = random_grid(11, 256, 256, 0.2)
    grid = vpmap.Grid(blocked)
    qs = queries(blocked, 11, 12)
    serial = [vpmap.plan(grid, s, g, "astar").length for s, g in qs]
    with concurrent.futures.ThreadPoolExecutor(4) as pool:
        parallel = list(pool.map(lambda q: vpmap.plan(grid, q[0], q[1], "astar").length, qs))
    assert parallel == serial


def test_planning_releases_the_gil():
    # While another thread plans, this one keeps running: the longest pause between its
    # loop steps stays far below the time one plan takes (with the GIL held it would be
    # at least that long).
    blocked = random_grid(12, 1024, 1024, 0.3)
    blocked[:, 0] = 0
    blocked[:, -1] = 0
    grid = vpmap.Grid(blocked)
    ends = ((0, 0), (1023, 1023))
    one = min(vpmap.plan(grid, *ends, "astar").time_s for _ in range(3))
    repeats = max(2, math.ceil(0.5 / one))
    done = threading.Event()

    def work():
        for _ in range(repeats):
            vpmap.plan(grid, *ends, "astar")
        done.set()

    worker = threading.Thread(target=work)
    last = time.perf_counter()
    worker.start()
    longest = 0.0
    while not done.is_set():
        now = time.perf_counter()
        longest = max(longest, now - last)
        last = now
    worker.join()
    assert longest < 0.5 * one, (longest, one)
