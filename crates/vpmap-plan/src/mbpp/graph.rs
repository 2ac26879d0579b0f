//! All `v_list`s as one graph (see "Selection, line-of-sight check and re-planning" in the
//! module docs of [`super`]): the bugs' tree plus the joins of waiting bugs, and its
//! shortest-path searches.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use super::cells::{Xy, dist};
use super::walk::{Join, NONE, Vertex};

/// A segment of the `v_list` graph; `clear` once its line of sight is known to be clear.
#[derive(Clone, Copy, Debug)]
pub(super) struct Edge {
    pub(super) to: u32,
    pub(super) clear: bool,
}

/// One out-edge in [`Graph`]'s shared edge array, linked to the vertex's next out-edge.
#[derive(Clone, Copy, Debug)]
struct Slot {
    edge: Edge,
    /// The next slot of the same vertex (`NONE` at the end).
    next: u32,
}

/// All `v_list`s as one graph: tree edges (clear by construction) and join edges of
/// waiting bugs (clear when the owner had noted the join cell itself).
///
/// Out-edges live in one array, each vertex's as a linked list in insertion order (one
/// allocation for the whole graph instead of one per vertex). The order matters: Dijkstra
/// keeps the first of equally short ways, so it follows the order edges were added in.
/// A removed edge stays in its list as a dead slot (`to == NONE`) that iteration skips.
pub(super) struct Graph {
    pub(super) cells: Vec<Xy>,
    parents: Vec<u32>,
    /// First and last slot of each vertex's out-list (`NONE` when it has none).
    head: Vec<u32>,
    tail: Vec<u32>,
    slots: Vec<Slot>,
}

impl Graph {
    pub(super) fn new(vertices: &[Vertex], joins: &[Join]) -> Self {
        let n = vertices.len();
        let mut graph = Self {
            cells: vertices.iter().map(|v| v.cell).collect(),
            parents: vertices.iter().map(|v| v.parent).collect(),
            head: vec![NONE; n],
            tail: vec![NONE; n],
            slots: Vec::with_capacity(n + joins.len()),
        };
        for (id, v) in vertices.iter().enumerate() {
            graph.push_edge(
                v.parent,
                Edge {
                    to: id as u32,
                    clear: true,
                },
            );
        }
        let mut targets = Vec::new();
        for join in joins {
            targets.clear();
            targets.extend(graph.out(join.owner.anchor).map(|e| e.to));
            if join.vertex as usize >= n {
                continue;
            }
            for &to in &targets {
                if to != join.vertex && !graph.out(join.vertex).any(|e| e.to == to) {
                    graph.push_edge(
                        join.vertex,
                        Edge {
                            to,
                            clear: join.owner.at_cell,
                        },
                    );
                }
            }
        }
        graph
    }

    pub(super) fn cell(&self, v: u32) -> Xy {
        self.cells.get(v as usize).copied().unwrap_or((-1, -1))
    }

    pub(super) fn add_vertex(&mut self, cell: Xy) -> u32 {
        self.cells.push(cell);
        self.parents.push(NONE);
        self.head.push(NONE);
        self.tail.push(NONE);
        (self.cells.len() - 1) as u32
    }

    /// Append `edge` to the out-list of `from` (ignored when `from` is not a vertex).
    pub(super) fn push_edge(&mut self, from: u32, edge: Edge) {
        let Some(&last) = self.tail.get(from as usize) else {
            return;
        };
        let id = self.slots.len() as u32;
        self.slots.push(Slot { edge, next: NONE });
        let link = if last == NONE {
            self.head.get_mut(from as usize)
        } else {
            self.slots.get_mut(last as usize).map(|s| &mut s.next)
        };
        if let Some(link) = link {
            *link = id;
        }
        if let Some(t) = self.tail.get_mut(from as usize) {
            *t = id;
        }
    }

    /// The slots of the live out-edges of `v`, in insertion order.
    pub(super) fn out_slots(&self, v: u32) -> impl Iterator<Item = u32> + '_ {
        let mut at = self.head.get(v as usize).copied().unwrap_or(NONE);
        std::iter::from_fn(move || {
            loop {
                let slot = self.slots.get(at as usize)?;
                let id = at;
                at = slot.next;
                if slot.edge.to != NONE {
                    return Some(id);
                }
            }
        })
    }

    /// The live out-edges of `v`, in insertion order.
    pub(super) fn out(&self, v: u32) -> impl Iterator<Item = Edge> + '_ {
        self.out_slots(v)
            .filter_map(|id| self.slots.get(id as usize).map(|s| s.edge))
    }

    pub(super) fn edge_mut(&mut self, from: u32, to: u32) -> Option<&mut Edge> {
        let id = self
            .out_slots(from)
            .find(|&id| self.slots.get(id as usize).is_some_and(|s| s.edge.to == to))?;
        self.slots.get_mut(id as usize).map(|s| &mut s.edge)
    }

    pub(super) fn remove_edge(&mut self, from: u32, to: u32) {
        let mut at = self.head.get(from as usize).copied().unwrap_or(NONE);
        while let Some(slot) = self.slots.get_mut(at as usize) {
            if slot.edge.to == to {
                slot.edge.to = NONE;
            }
            at = slot.next;
        }
    }

    pub(super) fn add_edge(&mut self, from: u32, to: u32) {
        self.push_edge(from, Edge { to, clear: true });
    }

    /// The tree path from the start to `v` (parent links).
    pub(super) fn tree_path(&self, v: u32) -> Vec<u32> {
        let mut path = vec![v];
        let mut at = v;
        while let Some(&p) = self.parents.get(at as usize) {
            if p == NONE {
                break;
            }
            path.push(p);
            at = p;
        }
        path.reverse();
        path
    }

    /// Shortest path (Dijkstra, Euclidean lengths) from vertex 0 to a vertex at `goal`,
    /// over clear edges only or over all.
    pub(super) fn shortest(&self, goal: Xy, clear_only: bool) -> Option<Vec<u32>> {
        let n = self.cells.len();
        let mut best = vec![f64::INFINITY; n];
        let mut parent = vec![NONE; n];
        let mut heap = BinaryHeap::new();
        *best.first_mut()? = 0.0;
        heap.push(HeapEntry { cost: 0.0, node: 0 });
        while let Some(HeapEntry { cost, node }) = heap.pop() {
            if cost > best.get(node as usize).copied().unwrap_or(f64::INFINITY) {
                continue;
            }
            let here = self.cell(node);
            if here == goal {
                let mut path = vec![node];
                let mut at = node;
                while let Some(&p) = parent.get(at as usize) {
                    if p == NONE {
                        break;
                    }
                    path.push(p);
                    at = p;
                }
                path.reverse();
                return Some(path);
            }
            for e in self.out(node) {
                if clear_only && !e.clear {
                    continue;
                }
                let c = cost + dist(here, self.cell(e.to));
                if let Some(slot) = best.get_mut(e.to as usize)
                    && c < *slot
                {
                    *slot = c;
                    if let Some(p) = parent.get_mut(e.to as usize) {
                        *p = node;
                    }
                    heap.push(HeapEntry {
                        cost: c,
                        node: e.to,
                    });
                }
            }
        }
        None
    }

    /// Shortest distance from every vertex to a vertex at `goal` over clear edges, and the
    /// next vertex on that way.
    pub(super) fn to_goal(&self, goal: Xy) -> (Vec<f64>, Vec<u32>) {
        let n = self.cells.len();
        // The reversed clear edges in compressed rows: the sources of the edges into `v`
        // are `sources[offsets[v]..offsets[v + 1]]`, in order of source, then of out-list.
        let mut offsets = vec![0u32; n + 1];
        for from in 0..n as u32 {
            for e in self.out(from).filter(|e| e.clear) {
                if let Some(o) = offsets.get_mut(e.to as usize + 1) {
                    *o += 1;
                }
            }
        }
        for v in 1..=n {
            let before = offsets.get(v - 1).copied().unwrap_or(0);
            if let Some(o) = offsets.get_mut(v) {
                *o += before;
            }
        }
        let mut fill = offsets.clone();
        let mut sources = vec![NONE; offsets.last().copied().unwrap_or(0) as usize];
        for from in 0..n as u32 {
            for e in self.out(from).filter(|e| e.clear) {
                if let Some(f) = fill.get_mut(e.to as usize)
                    && let Some(slot) = sources.get_mut(*f as usize)
                {
                    *slot = from;
                    *f += 1;
                }
            }
        }
        let into = |v: u32| {
            let lo = offsets.get(v as usize).copied().unwrap_or(0) as usize;
            let hi = offsets.get(v as usize + 1).copied().unwrap_or(0) as usize;
            sources.get(lo..hi).unwrap_or(&[])
        };
        let mut best = vec![f64::INFINITY; n];
        let mut next = vec![NONE; n];
        let mut heap = BinaryHeap::new();
        for (v, &c) in self.cells.iter().enumerate() {
            if c == goal
                && let Some(slot) = best.get_mut(v)
            {
                *slot = 0.0;
                heap.push(HeapEntry {
                    cost: 0.0,
                    node: v as u32,
                });
            }
        }
        while let Some(HeapEntry { cost, node }) = heap.pop() {
            if cost > best.get(node as usize).copied().unwrap_or(f64::INFINITY) {
                continue;
            }
            let here = self.cell(node);
            for &from in into(node) {
                let c = cost + dist(here, self.cell(from));
                if let Some(slot) = best.get_mut(from as usize)
                    && c < *slot
                {
                    *slot = c;
                    if let Some(nx) = next.get_mut(from as usize) {
                        *nx = node;
                    }
                    heap.push(HeapEntry {
                        cost: c,
                        node: from,
                    });
                }
            }
        }
        (best, next)
    }
}

/// A min-heap entry (the heap is a max-heap, so the order is reversed).
#[derive(Clone, Copy, Debug)]
struct HeapEntry {
    cost: f64,
    node: u32,
}

impl PartialEq for HeapEntry {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for HeapEntry {}

impl PartialOrd for HeapEntry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for HeapEntry {
    fn cmp(&self, other: &Self) -> Ordering {
        other
            .cost
            .total_cmp(&self.cost)
            .then_with(|| other.node.cmp(&self.node))
    }
}
