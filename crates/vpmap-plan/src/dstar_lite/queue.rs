//! D* Lite's priority queue: an indexed 4-ary min-heap of queue keys and padded cells. Each
//! cell knows its position in the heap, so re-keying and removing are in place and the heap
//! holds no stale entries.

use super::keys::QueueKey;

/// No queue position: the cell is not queued.
const NOT_QUEUED: u32 = u32::MAX;
/// Heap arity of the queue.
const ARITY: usize = 4;

/// The queue of the locally inconsistent cells, keyed by `K` (see the [module docs](self)).
#[derive(Clone, Debug)]
pub(super) struct Queue<K> {
    /// Per padded cell: its position in the heap plus one, 0 when not queued.
    pos: Vec<u32>,
    /// The heap: a 4-ary min-heap of keys and padded cells, positions in [`Queue::pos`].
    heap: Vec<(K, u32)>,
}

impl<K: QueueKey> Queue<K> {
    /// An empty queue for `cells` padded cells (zeroed memory).
    pub(super) fn new(cells: usize) -> Self {
        Self {
            pos: vec![0; cells],
            heap: Vec::new(),
        }
    }

    /// The smallest key and its cell, if any.
    #[inline]
    pub(super) fn first(&self) -> Option<&(K, u32)> {
        self.heap.first()
    }

    /// Empty the heap and return its cells (in heap order); their positions stay recorded
    /// until [`Queue::forget`].
    pub(super) fn take_cells(&mut self) -> Vec<u32> {
        std::mem::take(&mut self.heap)
            .into_iter()
            .map(|(_, u)| u)
            .collect()
    }

    /// Mark `cells`, taken out by [`Queue::take_cells`], as not queued.
    pub(super) fn forget(&mut self, cells: &[u32]) {
        for &u in cells {
            if let Some(p) = self.pos.get_mut(u as usize) {
                *p = 0;
            }
        }
    }

    /// This queue with keys of type `K2`, this one left empty: the cells it held (still
    /// marked queued, to be queued again with their keys computed anew) and the new queue,
    /// which takes over the positions and has room for them.
    pub(super) fn convert<K2: QueueKey>(&mut self) -> (Vec<u32>, Queue<K2>) {
        let cells = self.take_cells();
        let to = Queue {
            pos: std::mem::take(&mut self.pos),
            heap: Vec::with_capacity(cells.len()),
        };
        (cells, to)
    }

    /// Whether `u` is queued.
    pub(super) fn queued(&self, u: usize) -> bool {
        self.pos.get(u).is_some_and(|&p| p != 0)
    }

    /// Queue `u` with `key`, or change its key.
    pub(super) fn set(&mut self, u: usize, key: K) {
        let pos = self.position(u);
        if pos == NOT_QUEUED {
            let at = self.heap.len();
            self.heap.push((key, u as u32));
            self.set_pos(u, at);
            self.sift_up(at);
        } else {
            let at = pos as usize;
            let Some(entry) = self.heap.get_mut(at) else {
                return;
            };
            let old = entry.0;
            if key == old {
                return;
            }
            entry.0 = key;
            if key < old {
                self.sift_up(at);
            } else {
                self.sift_down(at);
            }
        }
    }

    /// Take `u` out of the queue.
    pub(super) fn remove(&mut self, u: usize) {
        let pos = self.position(u);
        if pos == NOT_QUEUED {
            return;
        }
        let at = pos as usize;
        if let Some(p) = self.pos.get_mut(u) {
            *p = 0;
        }
        let Some(last) = self.heap.pop() else {
            return;
        };
        if at < self.heap.len() {
            let old = self.heap.get(at).map(|e| e.0);
            if let Some(slot) = self.heap.get_mut(at) {
                *slot = last;
            }
            self.set_pos(last.1 as usize, at);
            if old.is_some_and(|o| last.0 < o) {
                self.sift_up(at);
            } else {
                self.sift_down(at);
            }
        }
    }

    /// The heap position of `u`, or [`NOT_QUEUED`].
    #[inline]
    fn position(&self, u: usize) -> u32 {
        self.pos
            .get(u)
            .map_or(NOT_QUEUED, |&p| p.checked_sub(1).unwrap_or(NOT_QUEUED))
    }

    #[inline]
    fn set_pos(&mut self, u: usize, at: usize) {
        if let Some(p) = self.pos.get_mut(u) {
            *p = at as u32 + 1;
        }
    }

    fn sift_up(&mut self, mut at: usize) {
        let Some(&item) = self.heap.get(at) else {
            return;
        };
        while at > 0 {
            let parent = (at - 1) / ARITY;
            let Some(&p) = self.heap.get(parent) else {
                break;
            };
            if item.0 >= p.0 {
                break;
            }
            if let Some(slot) = self.heap.get_mut(at) {
                *slot = p;
            }
            self.set_pos(p.1 as usize, at);
            at = parent;
        }
        if let Some(slot) = self.heap.get_mut(at) {
            *slot = item;
        }
        self.set_pos(item.1 as usize, at);
    }

    fn sift_down(&mut self, mut at: usize) {
        let Some(&item) = self.heap.get(at) else {
            return;
        };
        let n = self.heap.len();
        loop {
            let first = at * ARITY + 1;
            if first >= n {
                break;
            }
            let mut best = first;
            let mut best_key = match self.heap.get(first) {
                Some(e) => e.0,
                None => break,
            };
            for c in first + 1..(first + ARITY).min(n) {
                if let Some(e) = self.heap.get(c)
                    && e.0 < best_key
                {
                    best = c;
                    best_key = e.0;
                }
            }
            if best_key >= item.0 {
                break;
            }
            let Some(&child) = self.heap.get(best) else {
                break;
            };
            if let Some(slot) = self.heap.get_mut(at) {
                *slot = child;
            }
            self.set_pos(child.1 as usize, at);
            at = best;
        }
        if let Some(slot) = self.heap.get_mut(at) {
            *slot = item;
        }
        self.set_pos(item.1 as usize, at);
    }
}
