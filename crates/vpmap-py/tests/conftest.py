"""Shared fixtures and the independent references the tests check vpmap against."""

import heapq
import math
import pathlib
from collections import deque

import numpy as np
import pytest

REPO = pathlib.Path(__file__).resolve().parents[3]
EXAMPLE = REPO / "examples" / "office.json"
TRUTH = REPO / "examples" / "office.truth.json"
MOVINGAI = REPO.parent / "shared" / "data" / "movingai" / "maps"
YUD = REPO.parent / "shared" / "data" / "yud-train"


def random_grid(seed, height, width, density):
    """A seeded random grid of 0 (free) and 1 (occupied), int8."""
    rng = np.random.default_rng(seed)
    return (rng.random((height, width)) < density).astype(np.int8)


def bfs_reachable(blocked, start, goal):
    """Breadth-first search over 4-connected free cells: whether goal is reachable from start.

    With no corner cutting, an 8-connected path exists exactly when a 4-connected one does.
    """
    h, w = blocked.shape
    (sx, sy), (gx, gy) = start, goal
    seen = np.zeros_like(blocked, dtype=bool)
    seen[sy, sx] = True
    queue = deque([(sx, sy)])
    while queue:
        x, y = queue.popleft()
        if (x, y) == (gx, gy):
            return True
        for dx, dy in ((1, 0), (-1, 0), (0, 1), (0, -1)):
            nx, ny = x + dx, y + dy
            if 0 <= nx < w and 0 <= ny < h and not blocked[ny, nx] and not seen[ny, nx]:
                seen[ny, nx] = True
                queue.append((nx, ny))
    return False


def octile_optimum(blocked, start, goal):
    """Dijkstra over 8-connected moves, diagonals only between two free orthogonal cells."""
    h, w = blocked.shape
    dist = {tuple(start): 0.0}
    heap = [(0.0, tuple(start))]
    while heap:
        d, (x, y) = heapq.heappop(heap)
        if (x, y) == tuple(goal):
            return d
        if d > dist.get((x, y), math.inf):
            continue
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                if dx == dy == 0:
                    continue
                nx, ny = x + dx, y + dy
                if not (0 <= nx < w and 0 <= ny < h) or blocked[ny, nx]:
                    continue
                if dx and dy and (blocked[y, nx] or blocked[ny, x]):
                    continue
                nd = d + (math.sqrt(2.0) if dx and dy else 1.0)
                if nd < dist.get((nx, ny), math.inf):
                    dist[(nx, ny)] = nd
                    heapq.heappush(heap, (nd, (nx, ny)))
    return None


def segment_clear(blocked_centres, a, b):
    """The collision rule, decided independently: a cell-sized square swept from centre a to
    centre b may touch but not overlap a blocked cell, i.e. the segment a-b misses every open
    2 x 2 square centred on a blocked cell (slab test with strict inequalities)."""
    if len(blocked_centres) == 0:
        return True
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    d = b - a
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
    # Overlap of the open box needs an open interval of t inside [0, 1].
    return not np.any(ok & (lo < hi - 1e-12))


def any_angle_optimum(blocked, start, goal):
    """The exact shortest any-angle path under the collision rule: obstacles in the space of
    cell centres are open 2 x 2 squares around blocked cells, whose corners are cell centres,
    so shortest paths bend only at free cell centres diagonal to a blocked cell; Dijkstra on
    their visibility graph (Lozano-Perez and Wesley 1979)."""
    h, w = blocked.shape
    centres = np.argwhere(blocked)[:, ::-1].astype(float)  # (x, y)
    corners = set()
    for x, y in np.argwhere(blocked)[:, ::-1]:
        for dx in (-1, 1):
            for dy in (-1, 1):
                cx, cy = x + dx, y + dy
                if 0 <= cx < w and 0 <= cy < h and not blocked[cy, cx]:
                    corners.add((int(cx), int(cy)))
    nodes = [tuple(start), tuple(goal)] + sorted(corners - {tuple(start), tuple(goal)})
    dist = {nodes[0]: 0.0}
    heap = [(0.0, nodes[0])]
    done = set()
    while heap:
        d, p = heapq.heappop(heap)
        if p in done:
            continue
        done.add(p)
        if p == nodes[1]:
            return d
        for q in nodes:
            if q in done:
                continue
            nd = d + math.dist(p, q)
            if nd < dist.get(q, math.inf) and segment_clear(centres, p, q):
                dist[q] = nd
                heapq.heappush(heap, (nd, q))
    return None


@pytest.fixture(scope="session")
def office_truth():
    import json

    return json.loads(TRUTH.read_text())
