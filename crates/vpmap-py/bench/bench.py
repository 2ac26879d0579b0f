"""vpmap's planners from Python against other Python path finders, side by side in one run.

    python crates/vpmap-py/bench/bench.py [--maps ../shared/data/movingai/maps] [--queries 20]
        [--pathfinding-queries 20] [--repeats 3]

needs the release wheel (`pip install ./crates/vpmap-py`) and the comparison packages
`pip install scikit-image pathfinding extremitypathfinder shapely` (not installed by CI).
Prints a Markdown table of ratios (docs/python.md):

- `vpmap.plan(grid, s, g, "astar")` against scikit-image's `graph.route_through_array`
  (geometric costs, fully connected; it may cut corners, which vpmap's grid model forbids, so
  its paths can be a little shorter) and the `pathfinding` package's A* (diagonal moves only
  between free cells, as vpmap), on Moving AI maps and a seeded 512 x 512 random grid: each
  package's queries in a loop of its own, every query timed `--repeats` times (the median),
  and vpmap's A* also timed once right after each scikit-image query ("after another
  package": its arrays and the grid then come cold from memory);
- `vpmap.Planner(grid, "optimal").plan` (the exact any-angle path, precomputation kept)
  against `extremitypathfinder` (exact shortest paths among polygons, on the same
  configuration space: each blocked cell's 2 x 2 square of cell centres), per query, its
  visibility-graph preparation and vpmap's first query reported apart;
- the Python call's overhead: `vpmap.plan` against the same Rust call's own time
  (`Path.time_s`, measured inside the library call with the GIL released) on the 512 x 512
  grid.
"""

import argparse
import math
import pathlib
import statistics
import time

import numpy as np

import vpmap

HERE = pathlib.Path(__file__).resolve()
DEFAULT_MAPS = HERE.parents[4] / "shared" / "data" / "movingai" / "maps"

ASTAR_MAPS = [
    "random/random512-10-0.map",
    "random/random512-20-0.map",
    "dao/den520d.map",
    "bg512/AR0500SR.map",
    "rooms/32room_000.map",
    "mazes/maze512-32-0.map",
    "cities/Berlin_0_256.map",
]
EXACT_MAPS = [
    "mapf/empty-48-48.map",
    "mapf/random-64-64-20.map",
    "mapf/room-64-64-8.map",
    "mapf/maze-128-128-2.map",
]


def octile_length(cells):
    cells = np.asarray(cells, dtype=float)
    if len(cells) < 2:
        return 0.0
    d = np.abs(np.diff(cells, axis=0))
    return float(np.sum(np.max(d, axis=1) + (math.sqrt(2) - 1) * np.min(d, axis=1)))


def queries(grid, seed, n):
    """n seeded start/goal pairs (x, y) that vpmap's A* connects, far apart."""
    rng = np.random.default_rng(seed)
    free = np.argwhere(grid.array == 0)[:, ::-1]
    out = []
    tries = 0
    while len(out) < n and tries < 50 * n:
        tries += 1
        i, j = rng.choice(len(free), size=2)
        s, g = tuple(int(v) for v in free[i]), tuple(int(v) for v in free[j])
        if math.dist(s, g) < 0.3 * max(grid.shape):
            continue
        if vpmap.plan(grid, s, g, "astar").found:
            out.append((s, g))
    return out


def cuts_a_corner(blocked, cells):
    """Whether a path of (row, column) cells steps diagonally past a blocked cell, which
    vpmap's grid model (and pathfinding's only_when_no_obstacle) forbids."""
    for (r0, c0), (r1, c1) in zip(cells[:-1], cells[1:]):
        if r0 != r1 and c0 != c1 and (blocked[r0, c1] or blocked[r1, c0]):
            return True
    return False


def ratio(x):
    """A ratio as the table prints it: one decimal below 100 (so 9.6 is not printed 10)."""
    return f"{x:.1f}x" if x < 100 else f"{x:.0f}x"


def timed(fn, *args, **kwargs):
    began = time.perf_counter()
    result = fn(*args, **kwargs)
    return time.perf_counter() - began, result


def timed_median(repeats, fn, *args, fresh=None, **kwargs):
    """The median wall time of `repeats` calls and the last call's result; `fresh()`, when
    given, makes the arguments of each call (outside the timing)."""
    times = []
    for _ in range(repeats):
        call_args = fresh() if fresh else args
        dt, result = timed(fn, *call_args, **kwargs)
        times.append(dt)
    return statistics.median(times), result


def bench_astar(name, grid, qs, pathfinding_queries, repeats):
    """Each package's queries in a loop of its own (as a user's loop of queries runs them),
    every query timed `repeats` times (the median), and the median over the queries; vpmap
    is also timed once right after each scikit-image query (its arrays and the grid then
    come cold from memory), reported apart."""
    from pathfinding.core.diagonal_movement import DiagonalMovement
    from pathfinding.core.grid import Grid as PfGrid
    from pathfinding.finder.a_star import AStarFinder
    from skimage.graph import route_through_array

    blocked = grid.array != 0
    costs = np.where(blocked, np.inf, 1.0)
    t_vp, t_sk, t_pf, t_cold = [], [], [], []
    paths = []
    for s, g in qs:
        dt, path = timed_median(repeats, vpmap.plan, grid, s, g, "astar")
        t_vp.append(dt)
        paths.append(path)
    worse_than_sk = worse_than_pf = sk_cuts = 0
    for (s, g), path in zip(qs, paths):
        dt, (cells, _) = timed_median(
            repeats, route_through_array, costs, (s[1], s[0]), (g[1], g[0]), fully_connected=True, geometric=True
        )
        t_sk.append(dt)
        if cuts_a_corner(blocked, cells):
            sk_cuts += 1
        elif path.length > octile_length(cells) + 1e-6:
            worse_than_sk += 1
        dt, _ = timed(vpmap.plan, grid, s, g, "astar")
        t_cold.append(dt)
    matrix = (~blocked).astype(int).tolist()
    finder = AStarFinder(diagonal_movement=DiagonalMovement.only_when_no_obstacle)

    def fresh_pathfinding(s, g):
        # pathfinding marks its nodes while searching: a new grid for every call.
        pf_grid = PfGrid(matrix=matrix)
        return pf_grid.node(*s), pf_grid.node(*g), pf_grid

    for (s, g), path in list(zip(qs, paths))[:pathfinding_queries]:
        dt, (pf_path, _) = timed_median(repeats, finder.find_path, fresh=lambda: fresh_pathfinding(s, g))
        t_pf.append(dt)
        if path.length > octile_length([(n.x, n.y) for n in pf_path]) + 1e-6:
            worse_than_pf += 1
    vp = statistics.median(t_vp)
    return {
        "map": name,
        "queries": len(qs),
        "vpmap_ms": 1e3 * vp,
        "vpmap_cold_ms": 1e3 * statistics.median(t_cold),
        "skimage_x": statistics.median(t_sk) / vp,
        "skimage_cold_x": statistics.median(t_sk) / statistics.median(t_cold),
        "pathfinding_x": statistics.median(t_pf) / statistics.median(t_vp[: len(t_pf)]) if t_pf else math.nan,
        "pathfinding_cold_x": statistics.median(t_pf) / statistics.median(t_cold[: len(t_pf)]) if t_pf else math.nan,
        "pathfinding_queries": len(t_pf),
        "longer_than_skimage": worse_than_sk,
        "skimage_cuts": sk_cuts,
        "longer_than_pathfinding": worse_than_pf,
    }


def configuration_space(blocked):
    """Free space of cell centres as polygons: each blocked cell blocks the open 2 x 2 square
    around its centre; the grid's cell centres span [0, w-1] x [0, h-1]."""
    from shapely.geometry import box
    from shapely.ops import unary_union

    h, w = blocked.shape
    squares = [box(x - 1, y - 1, x + 1, y + 1) for y, x in np.argwhere(blocked)]
    frame = box(0, 0, w - 1, h - 1)
    free = frame.difference(unary_union(squares)) if squares else frame
    return free


def segment_clear(blocked_centres, a, b):
    """vpmap's collision rule, decided independently (as in tests/conftest.py): the segment
    between cell centres a and b misses every open 2 x 2 square around a blocked cell."""
    a = np.asarray(a, dtype=float)
    d = np.asarray(b, dtype=float) - a
    lo = np.zeros(len(blocked_centres))
    hi = np.ones(len(blocked_centres))
    ok = np.ones(len(blocked_centres), dtype=bool)
    for axis in range(2):
        c = blocked_centres[:, axis]
        if d[axis] == 0.0:
            ok &= np.abs(a[axis] - c) < 1.0
        else:
            t1 = (c - 1.0 - a[axis]) / d[axis]
            t2 = (c + 1.0 - a[axis]) / d[axis]
            lo = np.maximum(lo, np.minimum(t1, t2))
            hi = np.minimum(hi, np.maximum(t1, t2))
    return not np.any(ok & (lo < hi - 1e-9))


def bench_exact(name, grid, qs):
    from extremitypathfinder import PolygonEnvironment
    from shapely.geometry import Point
    from shapely.geometry.polygon import orient

    blocked = grid.array != 0
    free = configuration_space(blocked)
    parts = list(getattr(free, "geoms", [free]))
    planner = vpmap.Planner(grid, "optimal")
    first_s, _ = timed(planner.plan, *qs[0])
    t_vp, t_ep, prep = [], [], 0.0
    longer = invalid = failed = 0
    centres = np.argwhere(blocked)[:, ::-1].astype(float)
    envs = {}
    for s, g in qs:
        part = next((i for i, p in enumerate(parts) if p.buffer(1e-9).contains(Point(s))), None)
        if part is None:
            continue
        if part not in envs:
            # Collinear vertices (every cell corner along a wall) make its visibility tests
            # singular: simplify(0) keeps the polygon and drops them.
            poly = orient(parts[part].simplify(0), sign=1.0)
            env = PolygonEnvironment()
            boundary = list(poly.exterior.coords)[:-1]
            holes = [list(r.coords)[:-1] for r in poly.interiors]
            try:
                dt, _ = timed(env.store, boundary, holes, validate=False)
                dt2, _ = timed(env.prepare)
            except Exception:  # polygons its preparation cannot handle
                env = None
                dt = dt2 = 0.0
            prep += dt + dt2
            envs[part] = env
        if envs[part] is None:
            failed += 1
            continue
        dt, path = timed(planner.plan, s, g)
        t_vp.append(dt)
        try:
            dt, (ep_path, length) = timed(envs[part].find_shortest_path, s, g, verify=False)
        except Exception:  # extremitypathfinder fails on some points on its polygons' edges
            failed += 1
            t_vp.pop()
            continue
        t_ep.append(dt)
        if length is None:
            continue
        if not all(segment_clear(centres, a, b) for a, b in zip(ep_path[:-1], ep_path[1:])):
            invalid += 1
        elif path.length > length + 1e-6:
            longer += 1
    vp = statistics.median(t_vp)
    return {
        "map": name,
        "queries": len(t_vp),
        "vpmap_ms": 1e3 * vp,
        "vpmap_first_ms": 1e3 * first_s,
        "extremity_x": statistics.median(t_ep) / vp,
        "extremity_prepare_s": prep,
        "longer": longer,
        "invalid": invalid,
        "failed": failed,
    }


def bench_overhead(grid, qs, repeats=5):
    """Median of (wall time of vpmap.plan) / (the library call's own time)."""
    ratios = []
    for s, g in qs:
        for _ in range(repeats):
            dt, path = timed(vpmap.plan, grid, s, g, "astar")
            ratios.append(dt / path.time_s)
    return statistics.median(ratios) - 1.0


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--maps", type=pathlib.Path, default=DEFAULT_MAPS)
    ap.add_argument("--queries", type=int, default=20)
    ap.add_argument("--pathfinding-queries", type=int, default=20)
    ap.add_argument("--repeats", type=int, default=3, help="timings of every A* query (the median)")
    args = ap.parse_args()

    rows = []
    random512 = vpmap.Grid((np.random.default_rng(512).random((512, 512)) < 0.2).astype(np.int8))
    grids = [("512 x 512 random (20 %)", random512)]
    for rel in ASTAR_MAPS:
        path = args.maps / rel
        if path.exists():
            grids.append((path.name, vpmap.Grid.load(path)))
    print("| map | queries | vpmap A* (ms) | scikit-image / vpmap | pathfinding / vpmap (queries) | vpmap after another package (ms) | scikit-image / that | pathfinding / that | scikit-image paths that cut a corner | vpmap longer than scikit-image (other paths) / pathfinding |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for name, grid in grids:
        qs = queries(grid, 1, args.queries)
        r = bench_astar(name, grid, qs, args.pathfinding_queries, args.repeats)
        rows.append(r)
        print(
            f"| {r['map']} | {r['queries']} | {r['vpmap_ms']:.2f} | {ratio(r['skimage_x'])} | "
            f"{ratio(r['pathfinding_x'])} ({r['pathfinding_queries']}) | {r['vpmap_cold_ms']:.2f} | "
            f"{ratio(r['skimage_cold_x'])} | {ratio(r['pathfinding_cold_x'])} | {r['skimage_cuts']} | "
            f"{r['longer_than_skimage']} / {r['longer_than_pathfinding']} |",
            flush=True,
        )
    print()
    print("| map | queries | vpmap optimal per query (ms) | vpmap first query (ms) | extremitypathfinder / vpmap per query | extremitypathfinder preparation (s) | vpmap longer | extremitypathfinder paths that cut a blocked cell / failed |")
    print("|---|---|---|---|---|---|---|---|")
    for rel in EXACT_MAPS:
        path = args.maps / rel
        if not path.exists():
            continue
        grid = vpmap.Grid.load(path)
        qs = queries(grid, 2, args.queries)
        try:
            r = bench_exact(path.name, grid, qs)
        except Exception as e:  # a map whose polygons extremitypathfinder refuses
            print(f"| {path.name} | - | - | - | failed: {type(e).__name__}: {e} | - | - | - |", flush=True)
            continue
        print(
            f"| {r['map']} | {r['queries']} | {r['vpmap_ms']:.3f} | {r['vpmap_first_ms']:.1f} | "
            f"{ratio(r['extremity_x'])} | {r['extremity_prepare_s']:.1f} | {r['longer']} | {r['invalid']} / {r['failed']} |",
            flush=True,
        )
    print()
    overhead = bench_overhead(random512, queries(random512, 3, 10))
    print(f"Python call overhead over the library call, 512 x 512 random grid, A*: {100 * overhead:.1f} %")


if __name__ == "__main__":
    main()
