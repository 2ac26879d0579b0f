//! The interval search of one query (see "Search" in the [module docs](super)): nodes, roots
//! and the open list, the cone and flat expansions, root-level and intermediate pruning, and
//! the path traced back through the roots.

use std::collections::{BinaryHeap, HashSet};
use std::hash::{BuildHasherDefault, Hash, Hasher};

use crate::budget::Budget;
use crate::error::Result;
use crate::grid::CellXy;
use crate::plan::PlanStats;

use super::space::FreeSpace;

/// The planner's name in errors.
pub(super) const PLANNER: &str = "the exact any-angle planner";

/// Tolerance of interval ends, cells (see the [module docs](super)).
const EPS: f64 = 1e-9;

/// Tolerance of root-level pruning on path lengths, cells.
const G_EPS: f64 = 1e-9;

/// What a search node's interval is to its root.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    /// The root is on another row; expand away from it (`+1`: towards larger `y`).
    Cone(i32),
    /// The root is on the interval's row.
    Flat,
    /// The goal, seen from the root.
    Final,
}

/// A search node: an interval `[l, u]` of row line `y` seen from root `root`.
#[derive(Clone, Copy, Debug)]
struct Node {
    root: u32,
    y: i32,
    l: f64,
    u: f64,
    kind: Kind,
}

/// An open-list entry: the heap pops the largest, so the smallest `f` (non-negative, so
/// its IEEE bits order like the value; complemented), then the node pushed last.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
struct Entry {
    key: u64,
    node: u32,
}

impl Entry {
    /// The entry of node `node` with `f` (cells).
    fn new(f: f64, node: u32) -> Self {
        Self {
            key: !f.to_bits(),
            node,
        }
    }
}

/// A root: a cell centre with the length of the path reaching it and its parent root.
#[derive(Clone, Copy, Debug)]
pub(super) struct Root {
    x: i32,
    y: i32,
    g: f64,
    parent: u32,
    /// Whether its cell centre has since become a root with a shorter path (its nodes are
    /// then dropped when taken off the open list).
    superseded: bool,
}

/// One search's buffers, kept between queries so that a query allocates nothing once
/// they have grown.
#[derive(Clone, Debug, Default)]
pub(super) struct Scratch {
    pub(super) roots: Vec<Root>,
    nodes: Vec<Node>,
    /// Every node pushed: equal arrivals at a root share it, so their equal successors
    /// are pushed once.
    seen: HashSet<NodeKey, WordHash>,
    open: BinaryHeap<Entry>,
    /// A cone expansion's successors `(turning point, l, u)`.
    successors: Vec<(Option<i32>, f64, f64)>,
}

impl Scratch {
    /// Empty the buffers for a new query (keeping their memory).
    pub(super) fn clear(&mut self) {
        self.roots.clear();
        self.nodes.clear();
        self.seen.clear();
        self.open.clear();
    }
}

/// The path to `goal` through the chain of roots ending at `last`, start first.
pub(super) fn trace(roots: &[Root], last: u32, goal: (usize, usize)) -> Vec<CellXy> {
    let mut chain = vec![CellXy::from(goal)];
    let mut index = last;
    // A chain of parents is at most as long as the number of roots.
    for _ in 0..=roots.len() {
        let Some(root) = roots.get(index as usize) else {
            break;
        };
        let cell = CellXy::new(root.x as usize, root.y as usize);
        if chain.last() != Some(&cell) {
            chain.push(cell);
        }
        if root.parent == index {
            break;
        }
        index = root.parent;
    }
    chain.reverse();
    chain
}

/// One query's search state.
pub(super) struct Search<'a> {
    pub(super) space: &'a FreeSpace,
    /// Per cell, the index of its root with the least `g` in the current search, valid only
    /// when that root is at this cell (so nothing is reset between queries, and the zeroed
    /// table costs no pass over the grid to build).
    pub(super) root_of: &'a mut [u32],
    pub(super) goal: (i32, i32),
    /// The buffers, taken from the planner for the query.
    pub(super) s: Scratch,
    pub(super) stats: PlanStats,
}

/// Euclidean distance between `(ax, ay)` and `(bx, by)` (a square root, not
/// `f64::hypot`: the coordinates are at most a few thousand cells, far from overflow).
#[inline]
fn dist(ax: f64, ay: f64, bx: f64, by: f64) -> f64 {
    let (dx, dy) = (ax - bx, ay - by);
    (dx * dx + dy * dy).sqrt()
}

/// The integer nearest `x` (either one at a tie), by truncation: `f64::round` is a
/// library call on the baseline x86-64 target. `x` is a coordinate on the grid or a
/// projection near it, far inside `i64`.
#[inline]
fn nearest(x: f64) -> f64 {
    let t = x as i64 as f64;
    if x - t >= 0.5 {
        t + 1.0
    } else if t - x >= 0.5 {
        t - 1.0
    } else {
        t
    }
}

/// `x` rounded when it is within [`EPS`] of an integer.
#[inline]
fn snap(x: f64) -> f64 {
    let r = nearest(x);
    if (x - r).abs() < EPS { r } else { x }
}

/// `x` as an integer when it is one (within [`EPS`]).
#[inline]
fn integral(x: f64) -> Option<i32> {
    let r = nearest(x);
    ((x - r).abs() < EPS).then_some(r as i32)
}

/// A node as the duplicate check sees it: root, row, the interval ends' bits and the
/// kind's tag.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct NodeKey {
    root: u32,
    y: i32,
    l: u64,
    u: u64,
    tag: i32,
}

impl Hash for NodeKey {
    fn hash<H: Hasher>(&self, state: &mut H) {
        state.write_u64((u64::from(self.root) << 32) | u64::from(self.y.cast_unsigned()));
        state.write_u64(self.l);
        state.write_u64(self.u);
        state.write_u32(self.tag.cast_unsigned());
    }
}

/// A multiply-rotate hash of the words written (the scheme of rustc's `FxHasher`): the
/// keys are the search's own numbers, not an adversary's, so `SipHash`'s protection is
/// not needed and its cost is (about a tenth of a query, measured).
#[derive(Clone, Copy, Debug, Default)]
struct WordHasher(u64);

impl WordHasher {
    #[inline]
    fn add(&mut self, word: u64) {
        self.0 = (self.0 ^ word).wrapping_mul(0xf135_7aea_2e62_a9c5);
    }
}

impl Hasher for WordHasher {
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.add(u64::from(b));
        }
    }

    fn write_u32(&mut self, word: u32) {
        self.add(u64::from(word));
    }

    fn write_u64(&mut self, word: u64) {
        self.add(word);
    }

    fn finish(&self) -> u64 {
        // The product's entropy is in its high bits; the table indexes by the low ones.
        self.0.rotate_left(26)
    }
}

/// Builds [`WordHasher`]s.
type WordHash = BuildHasherDefault<WordHasher>;

impl Search<'_> {
    /// Run the search from `start`; the root the goal was reached from, if it was.
    pub(super) fn run(&mut self, start: (i32, i32), budget: &Budget) -> Result<Option<u32>> {
        let s = self.new_root(start, 0.0, None);
        let Some(s) = s else { return Ok(None) };
        if start == self.goal {
            return Ok(Some(s));
        }
        let (sx, sy) = start;
        // Flat nodes along the start's run, cone nodes into the rectangles holding it.
        if let Some((a, b)) = self.space.run_at(sx, sy) {
            if a < sx {
                self.push(s, sy, f64::from(a), f64::from(sx), Kind::Flat);
            }
            if sx < b {
                self.push(s, sy, f64::from(sx), f64::from(b), Kind::Flat);
            }
        }
        for dir in [1, -1] {
            let strip = if dir > 0 { sy } else { sy - 1 };
            if let Some((i, &(a, b))) = self
                .space
                .strip(strip)
                .iter()
                .enumerate()
                .find(|&(_, &(a, b))| a <= sx && sx <= b)
                && !self.space.dead_end(strip, i, dir, self.goal)
            {
                self.push(s, sy + dir, f64::from(a), f64::from(b), Kind::Cone(dir));
            }
        }
        while let Some(Entry { node, .. }) = self.s.open.pop() {
            let Some(&n) = self.s.nodes.get(node as usize) else {
                continue;
            };
            let Some(&root) = self.s.roots.get(n.root as usize) else {
                continue;
            };
            if root.superseded {
                continue; // the root has since been reached by a shorter path
            }
            self.stats.expanded += 1;
            budget.check(PLANNER, self.stats.expanded, 0, self.stats.expanded)?;
            match n.kind {
                Kind::Final => return Ok(Some(n.root)),
                Kind::Cone(dir) => self.expand_cone(n, root, dir, budget)?,
                Kind::Flat => self.expand_flat(n, root),
            }
        }
        Ok(None)
    }

    /// The root of cell centre `(x, y)` with the least `g` so far and that `g`, if it is a
    /// root in this search. `root_of` may hold an index from an earlier search; it is this
    /// search's only when the root it names is at `(x, y)` (every root made sets its
    /// cell's entry, so a root at `(x, y)` named there was named by this search).
    fn root_at(&self, x: i32, y: i32) -> Option<(u32, f64)> {
        if x < 0 || y < 0 || x >= self.space.width || y >= self.space.height {
            return None;
        }
        let index = *self.root_of.get((y * self.space.width + x) as usize)?;
        let root = self.s.roots.get(index as usize)?;
        (root.x == x && root.y == y).then_some((index, root.g))
    }

    /// The root at `at` reached with length `g` from `parent` (the start when `None`):
    /// a new one when `g` is the least so far, the existing one when `g` equals its length
    /// (an equally short path; its successors are still generated), `None` when `at` is
    /// already a root with a shorter path (root-level pruning).
    fn new_root(&mut self, at: (i32, i32), g: f64, parent: Option<u32>) -> Option<u32> {
        if at.0 < 0 || at.1 < 0 || at.0 >= self.space.width || at.1 >= self.space.height {
            return None;
        }
        if let Some((existing, best)) = self.root_at(at.0, at.1) {
            if g > best + G_EPS {
                return None;
            }
            if g >= best - G_EPS {
                return Some(existing);
            }
            if let Some(old) = self.s.roots.get_mut(existing as usize) {
                old.superseded = true;
            }
        }
        let index = self.s.roots.len() as u32;
        *self
            .root_of
            .get_mut((at.1 * self.space.width + at.0) as usize)? = index;
        self.s.roots.push(Root {
            x: at.0,
            y: at.1,
            g,
            parent: parent.unwrap_or(index),
            superseded: false,
        });
        Some(index)
    }

    /// A successor rooted at `c` (a cell centre on row `y`) of a node rooted at `parent`.
    fn push_turn(&mut self, parent: Root, parent_index: u32, c: i32, y: i32, node: Node) {
        // A shortest path bends only at corner cells (crate::optimal's proof).
        if !self.space.is_corner(c, y) {
            return;
        }
        let g = parent.g
            + dist(
                f64::from(parent.x),
                f64::from(parent.y),
                f64::from(c),
                f64::from(y),
            );
        if let Some(root) = self.new_root((c, y), g, Some(parent_index)) {
            self.push(root, node.y, node.l, node.u, node.kind);
        }
    }

    /// Push the node (or, when its interval holds the goal, the final entry).
    fn push(&mut self, root: u32, y: i32, l: f64, u: f64, kind: Kind) {
        let Some(&r) = self.s.roots.get(root as usize) else {
            return;
        };
        let (rx, ry) = (f64::from(r.x), f64::from(r.y));
        let (gx, gy) = (f64::from(self.goal.0), f64::from(self.goal.1));
        let yf = f64::from(y);
        let (kind, f) = if y == self.goal.1 && l - EPS <= gx && gx <= u + EPS {
            (Kind::Final, r.g + dist(rx, ry, gx, gy))
        } else if r.y == y {
            let h = [l, u]
                .map(|q| dist(rx, ry, q, yf) + dist(q, yf, gx, gy))
                .into_iter()
                .fold(f64::INFINITY, f64::min);
            (kind, r.g + h)
        } else {
            // Mirror the goal through the row when it lies on the root's side.
            let gy = if (gy - yf) * (ry - yf) > 0.0 {
                2.0 * yf - gy
            } else {
                gy
            };
            let t = (yf - ry) / (gy - ry);
            let cross = (rx + t * (gx - rx)).clamp(l, u);
            (
                kind,
                r.g + dist(rx, ry, cross, yf) + dist(cross, yf, gx, gy),
            )
        };
        let tag = match kind {
            Kind::Cone(dir) => dir,
            Kind::Flat => 0,
            Kind::Final => 2,
        };
        let key = NodeKey {
            root,
            y,
            l: l.to_bits(),
            u: u.to_bits(),
            tag,
        };
        if !self.s.seen.insert(key) {
            return;
        }
        let index = self.s.nodes.len() as u32;
        self.s.nodes.push(Node {
            root,
            y,
            l,
            u,
            kind,
        });
        self.s.open.push(Entry::new(f, index));
        self.stats.generated += 1;
    }

    /// Expand a cone node into the strip beyond its row (direction `dir`), and on, row
    /// after row, while its only successor is the observable one (no turning point, not
    /// the goal's row): those nodes are expanded at once instead of going through the open
    /// list (Polyanya's intermediate pruning, Cui et al. 2017 section 5; expanding a node
    /// early only adds nodes, and the answer is still the first final entry taken off the
    /// open list). Each counts as an expansion.
    fn expand_cone(&mut self, mut n: Node, r: Root, dir: i32, budget: &Budget) -> Result<()> {
        let mut successors = std::mem::take(&mut self.s.successors);
        let result = self.cone_rows(&mut n, r, dir, budget, &mut successors);
        if result.is_ok() {
            for &(c, l, u) in &successors {
                let node = Node {
                    root: n.root,
                    y: n.y + dir,
                    l,
                    u,
                    kind: Kind::Cone(dir),
                };
                match c {
                    None => self.push(n.root, node.y, l, u, node.kind),
                    Some(c) => self.push_turn(r, n.root, c, n.y, node),
                }
            }
            self.push_flat_turns(n, r);
        }
        self.s.successors = successors;
        result
    }

    /// Step the cone node `n` over the rows where its only successor is the observable
    /// one; leave in `successors` the cone successors `(turning point, l, u)` of the
    /// node it stops at, which `n` then is.
    fn cone_rows(
        &mut self,
        n: &mut Node,
        r: Root,
        dir: i32,
        budget: &Budget,
        successors: &mut Vec<(Option<i32>, f64, f64)>,
    ) -> Result<()> {
        let rx = f64::from(r.x);
        let (gx, gy) = (f64::from(self.goal.0), self.goal.1);
        loop {
            successors.clear();
            let y = n.y;
            let next = y + dir;
            let strip = if dir > 0 { y } else { y - 1 };
            let k = f64::from(next - r.y) / f64::from(y - r.y);
            let project = |x: f64| snap(rx + (x - rx) * k);
            let space = self.space;
            // A shortest path bends only at corner cells (crate::optimal's proof).
            let turn = |x: f64| integral(x).filter(|&c| space.is_corner(c, y));
            let rects = space.strip(strip);
            let first = rects.partition_point(|&(_, b)| f64::from(b) < n.l - EPS);
            for (i, &(a, b)) in rects.iter().enumerate().skip(first) {
                let (af, bf) = (f64::from(a), f64::from(b));
                if af > n.u + EPS {
                    break;
                }
                if space.dead_end(strip, i, dir, self.goal) {
                    continue;
                }
                let (lr, ur) = (n.l.max(af), n.u.min(bf));
                if lr > ur + EPS {
                    continue;
                }
                let (jl, ju) = (project(lr).max(af), project(ur).min(bf));
                if jl <= ju + EPS {
                    successors.push((None, jl, ju.max(jl)));
                    if jl > af + EPS
                        && let Some(c) = turn(lr)
                    {
                        successors.push((Some(c), af, jl));
                    }
                    if ju < bf - EPS
                        && let Some(c) = turn(ur)
                    {
                        successors.push((Some(c), ju, bf));
                    }
                } else {
                    let (cl, cu) = (turn(lr), turn(ur));
                    if cl.is_some() {
                        successors.push((cl, af, bf));
                    }
                    if cu.is_some() && cu != cl {
                        successors.push((cu, af, bf));
                    }
                }
            }
            let &[(None, l, u)] = successors.as_slice() else {
                return Ok(());
            };
            if (next == gy && l - EPS <= gx && gx <= u + EPS) || self.flat_turns(*n, r) != [None; 2]
            {
                return Ok(());
            }
            self.stats.expanded += 1;
            budget.check(PLANNER, self.stats.expanded, 0, self.stats.expanded)?;
            *n = Node {
                y: next,
                l,
                u,
                ..*n
            };
        }
    }

    /// The turns of cone node `n` onto its own row at an integer end of its interval that
    /// is a corner cell: `(turning point, l, u)` of the flat successor, beyond the upper
    /// end and beyond the lower end.
    fn flat_turns(&self, n: Node, r: Root) -> [Option<(i32, i32, i32)>; 2] {
        let space = self.space;
        let y = n.y;
        let upper = integral(n.u)
            .filter(|&u| r.x <= u && space.is_corner(u, y))
            .and_then(|u| {
                let (_, last) = space.run_at(u, y)?;
                (last > u).then_some((u, u, last))
            });
        let lower = integral(n.l)
            .filter(|&l| r.x >= l && space.is_corner(l, y))
            .and_then(|l| {
                let (first, _) = space.run_at(l, y)?;
                (first < l).then_some((l, first, l))
            });
        [upper, lower]
    }

    /// Push the flat successors of cone node `n` (see [`Self::flat_turns`]).
    fn push_flat_turns(&mut self, n: Node, r: Root) {
        for (c, l, u) in self.flat_turns(n, r).into_iter().flatten() {
            let node = Node {
                root: n.root,
                y: n.y,
                l: f64::from(l),
                u: f64::from(u),
                kind: Kind::Flat,
            };
            self.push_turn(r, n.root, c, n.y, node);
        }
    }

    /// Expand a flat node: turn into every rectangle above or below whose near side lies
    /// on the interval beyond the root.
    fn expand_flat(&mut self, n: Node, r: Root) {
        let y = n.y;
        let rightward = n.u > f64::from(r.x);
        let side_of = |&(a, b): &(i32, i32)| if rightward { a } else { b };
        for dir in [1, -1] {
            let strip = if dir > 0 { y } else { y - 1 };
            // The rectangles are disjoint and sorted, so their sides are too.
            let first = self
                .space
                .strip(strip)
                .partition_point(|rect| f64::from(side_of(rect)) < n.l - EPS);
            for i in first.. {
                let Some(&(a, b)) = self.space.strip(strip).get(i) else {
                    break;
                };
                let side = side_of(&(a, b));
                if f64::from(side) > n.u + EPS {
                    break;
                }
                if self.space.dead_end(strip, i, dir, self.goal) {
                    continue;
                }
                let beyond = if rightward { side > r.x } else { side < r.x };
                if beyond {
                    let node = Node {
                        root: n.root,
                        y: y + dir,
                        l: f64::from(a),
                        u: f64::from(b),
                        kind: Kind::Cone(dir),
                    };
                    self.push_turn(r, n.root, side, y, node);
                }
            }
        }
    }
}
