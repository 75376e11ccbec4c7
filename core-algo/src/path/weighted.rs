//! Node-weighted distance fields: Dijkstra over nodes, not poses, where
//! entering a node costs whatever the caller says.
//!
//! The turn-aware field of [`DistField::compute`] is the planner of this
//! project. This one exists for cost models that charge per node entered
//! and know nothing of turns, such as the 2010 A*'s (`explore::legacy`):
//! with a consistent heuristic, one such field gives every node the cost
//! a correct A* to that node would return.
//!
//! It runs on the same caller-provided scratch, one [`PlanCell`] per node:
//! the node's distance in `base`, its settled mark in `off[1]`, the heading
//! it was entered with on its cheapest path in `off[0]`, and an indexed
//! binary heap (decrease-key in place, so at most one entry per node: it
//! never needs more cells than the window has nodes) in `ring_a` (slot →
//! node) and `ring_b` (node → slot + 1). The turn-aware queries
//! ([`DistField::first_heading`], [`DistField::dist_pose`], …) see no
//! search after it; [`DistField::dist_at`] and [`DistField::dist`] work, and
//! [`DistField::weighted_first_heading`] follows the cheapest path.

use super::{
    DIST_MASK, DistField, Flow, MAX_DIST, NO_OFF, PlanCell, PlanError, Ticks, arms_at,
    neighbour_index,
};
use crate::geometry::{Heading, Pos};
use crate::map::{Block, KnownMap};
use crate::timing::Timing;

/// The order in which a node's neighbours are relaxed: the 2010 A*'s
/// TOP, LEFT, BOTTOM, RIGHT of its y-down screen frame, which is north,
/// west, south, east here. Among equally cheap paths the first relaxation
/// keeps the predecessor.
const RELAX_ORDER: [Heading; 4] = [Heading::North, Heading::West, Heading::South, Heading::East];

const SETTLED: u8 = 1;

fn dist_of(cells: &[PlanCell], v: usize) -> Ticks {
    cells.get(v).map_or(DIST_MASK, |c| c.base & DIST_MASK)
}

/// Heap order: distance, then storage index.
fn key(cells: &[PlanCell], v: usize) -> (Ticks, usize) {
    (dist_of(cells, v), v)
}

fn node_at(cells: &[PlanCell], slot: usize) -> usize {
    cells.get(slot).map_or(usize::MAX, |c| c.ring_a as usize)
}

fn place(cells: &mut [PlanCell], slot: usize, v: usize) {
    if let Some(c) = cells.get_mut(slot) {
        c.ring_a = v as u32;
    }
    if let Some(c) = cells.get_mut(v) {
        c.ring_b = slot as u32 + 1;
    }
}

/// An indexed binary min-heap of nodes in the queue slots of the scratch.
struct NodeHeap {
    len: usize,
}

impl NodeHeap {
    fn sift_up(&self, cells: &mut [PlanCell], mut i: usize, v: usize) {
        let kv = key(cells, v);
        while i > 0 {
            let p = (i - 1) / 2;
            let pn = node_at(cells, p);
            if key(cells, pn) <= kv {
                break;
            }
            place(cells, i, pn);
            i = p;
        }
        place(cells, i, v);
    }

    fn sift_down(&self, cells: &mut [PlanCell], mut i: usize, v: usize) {
        let kv = key(cells, v);
        loop {
            let l = 2 * i + 1;
            if l >= self.len {
                break;
            }
            let r = l + 1;
            let mut c = node_at(cells, l);
            let mut ci = l;
            if r < self.len {
                let rn = node_at(cells, r);
                if key(cells, rn) < key(cells, c) {
                    c = rn;
                    ci = r;
                }
            }
            if kv <= key(cells, c) {
                break;
            }
            place(cells, i, c);
            i = ci;
        }
        place(cells, i, v);
    }

    /// Inserts `v`, or moves it up after its distance fell.
    fn push_or_decrease(&mut self, cells: &mut [PlanCell], v: usize) -> Result<(), PlanError> {
        let slot = cells.get(v).map_or(0, |c| c.ring_b as usize);
        if slot > 0 {
            self.sift_up(cells, slot - 1, v);
            return Ok(());
        }
        if self.len >= cells.len() {
            return Err(PlanError::QueueFull);
        }
        self.len += 1;
        self.sift_up(cells, self.len - 1, v);
        Ok(())
    }

    fn pop(&mut self, cells: &mut [PlanCell]) -> Option<usize> {
        if self.len == 0 {
            return None;
        }
        let top = node_at(cells, 0);
        if let Some(c) = cells.get_mut(top) {
            c.ring_b = 0;
        }
        self.len -= 1;
        if self.len > 0 {
            let last = node_at(cells, self.len);
            self.sift_down(cells, 0, last);
        }
        Some(top)
    }
}

impl<S: AsRef<[PlanCell]> + AsMut<[PlanCell]>> DistField<S> {
    /// Computes a node-weighted field from node `start` over `map`: driving
    /// into node `i` (along a known arm, as in [`DistField::compute`];
    /// frontier nodes are reached, never driven through) costs `enter(i)`,
    /// turns cost nothing. Calls `reached(i, dist)` once for every node when
    /// its distance becomes final, nearest first (ties: smaller storage
    /// index); stop early with [`Flow::Stop`]. See the module docs.
    pub fn compute_weighted<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        start: Pos,
        mut enter: impl FnMut(usize) -> Ticks,
        mut reached: impl FnMut(usize, Ticks) -> Flow,
    ) -> Result<(), PlanError> {
        let s0 = self.prepare(map, Timing::DEFAULT, start, Heading::North)?;
        // No turn-aware search stands in the scratch now.
        self.start = None;
        self.tree = None;
        self.weighted = true;
        let bounds = self.bounds;
        // The node → heap-slot index in `ring_b` must start at zero, and the
        // turn-aware searches leave their ring slots behind (they clear only
        // what they settled): clear the whole window, and have the next
        // search clear it again.
        let area = bounds.area();
        self.dirty = super::Dirty::all(area, usize::from(bounds.width));
        let cells = self.cells.as_mut();
        if let Some(window) = cells.get_mut(..area) {
            window.fill(PlanCell::EMPTY);
        }
        if let Some(c) = cells.get_mut(s0) {
            c.base = 0;
        }
        let mut heap = NodeHeap { len: 0 };
        heap.push_or_decrease(cells, s0)?;
        while let Some(v) = heap.pop(cells) {
            let d = dist_of(cells, v);
            if let Some(c) = cells.get_mut(v) {
                if let Some(s) = c.off.get_mut(1) {
                    *s = SETTLED;
                }
            }
            if reached(v, d) == Flow::Stop {
                return Ok(());
            }
            let Some(arms) = arms_at(map, v) else {
                continue;
            };
            for h in RELAX_ORDER {
                if !arms.has(h) {
                    continue;
                }
                let Some(w) = neighbour_index(bounds, v, h) else {
                    continue;
                };
                let Some(cw) = cells.get_mut(w) else {
                    continue;
                };
                if cw.off.get(1) == Some(&SETTLED) {
                    continue;
                }
                let nd = d.saturating_add(enter(w)).min(MAX_DIST);
                if nd < cw.base & DIST_MASK {
                    cw.base = nd;
                    if let Some(p) = cw.off.get_mut(0) {
                        *p = h.index();
                    }
                    heap.push_or_decrease(cells, w)?;
                }
            }
        }
        Ok(())
    }

    /// After [`DistField::compute_weighted`]: the heading to leave the start
    /// with on the cheapest path to node `target`; `None` when `target` is
    /// the start or was not reached.
    pub fn weighted_first_heading(&self, target: usize) -> Option<Heading> {
        if !self.weighted {
            // A turn-aware search stands in the scratch (a reverse or an
            // avoiding one keeps no start either).
            return None;
        }
        let cells = self.cells.as_ref();
        let mut v = target;
        let mut first = None;
        for _ in 0..=self.bounds.area() {
            let c = cells.get(v)?;
            c.dist()?;
            let p = c.off.first().copied().unwrap_or(NO_OFF);
            if p == NO_OFF {
                return first;
            }
            let h = Heading::from_index(p);
            first = Some(h);
            v = neighbour_index(self.bounds, v, h.opposite())?;
        }
        None
    }
}
