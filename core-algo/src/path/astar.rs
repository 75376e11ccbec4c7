//! A* from a pose to one node, over the same turn-aware costs as the
//! fields: see [`DistField::astar`].
//!
//! A robot that needs one way (to a waiting spot, to a kept share) should
//! not grow a whole field for it. The heap lives in the scratch's queue
//! slots, so A* needs no memory beyond the field's 16 bytes a node.

use super::{
    DIST_MASK, DistField, MAX_DIST, NO_OFF, PlanCell, PlanError, arms_at, index_manhattan,
    neighbour_index, searchable,
};
use crate::geometry::{Heading, Pos};
use crate::map::{Block, KnownMap};
use crate::timing::{Ticks, Timing};

impl<S: AsRef<[PlanCell]> + AsMut<[PlanCell]>> DistField<S> {
    /// A* from the pose (`start`, `heading`) to node `goal` with the same
    /// costs as [`DistField::compute`] and the admissible, consistent
    /// heuristic `edge × Manhattan distance`. Returns the cost of the
    /// cheapest path (arriving with any heading), or `None` when the goal
    /// cannot be reached. Afterwards [`DistField::path`] and
    /// [`DistField::first_heading`] work towards `goal`.
    ///
    /// The heap lives in the queue slots of the scratch; it holds at most
    /// one entry per scratch cell. Lazy deletion can need more (expensive
    /// turns on a cheap-edge field push many stale entries); then the search
    /// is finished by the FIFO Dijkstra of [`DistField::compute`], which
    /// gives the same cost with no extra memory.
    pub fn astar<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        timing: Timing,
        start: Pos,
        heading: Heading,
        goal: Pos,
    ) -> Result<Option<Ticks>, PlanError> {
        let w = usize::from(map.bounds().width);
        let g = map.bounds().index(goal);
        let edge = searchable(timing).edge;
        let manhattan =
            |i: usize, _| g.map_or(0, |g| index_manhattan(w, i, g).saturating_mul(edge));
        self.astar_with(map, timing, start, heading, goal, manhattan)
    }

    /// [`DistField::astar`] guided by `landmark`, a completed reverse field
    /// (see [`DistField::compute_reverse`]) of the same map: the heuristic
    /// of a pose is how much farther from the landmark's goal it is than
    /// the goal node is (the triangle inequality of the ALT method), which
    /// is admissible and consistent pose by pose. Where the way runs
    /// towards the landmark's goal, as a robot's way to a waiting spot near
    /// its home does, the search settles little more than the way itself;
    /// Manhattan distance, by contrast, knows nothing of a maze's walls.
    /// Falls back to Manhattan distance when `landmark` is no completed
    /// reverse search of `map`.
    pub fn astar_by_landmark<M, L>(
        &mut self,
        map: &KnownMap<M>,
        timing: Timing,
        start: Pos,
        heading: Heading,
        goal: Pos,
        landmark: &DistField<L>,
    ) -> Result<Option<Ticks>, PlanError>
    where
        M: AsRef<[Block]> + AsMut<[Block]>,
        L: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
    {
        let guide = landmark.reverse.filter(|&(_, rev)| {
            rev == map.revision()
                && landmark.bounds == map.bounds()
                && landmark.timing == searchable(timing)
        });
        let Some(cells) = guide.and_then(|_| {
            let i = map.bounds().index(goal)?;
            landmark.cells.as_ref().get(i)
        }) else {
            return self.astar(map, timing, start, heading, goal);
        };
        // The goal's farthest pose from the landmark's goal: whatever the
        // heading the way arrives with, the rest is at least this much
        // shorter than from a pose p: h(p) = max(0, L(p) − L_max(goal)).
        // A goal the landmark's field does not reach (a frontier node)
        // gives no bound.
        let Some(far) = (0..4).filter_map(|h| cells.pose_dist(h)).max() else {
            return self.astar(map, timing, start, heading, goal);
        };
        let lm = landmark.cells.as_ref();
        let hfn = |i: usize, h: usize| {
            lm.get(i)
                .and_then(|c| c.pose_dist(h))
                .map_or(0, |d| d.saturating_sub(far))
        };
        self.astar_with(map, timing, start, heading, goal, hfn)
    }

    /// A* with the heuristic `hfn` (see `astar_heap`), finished by the
    /// FIFO Dijkstra of [`DistField::compute_to`] when the heap outgrows
    /// the scratch (see [`DistField::astar`]).
    fn astar_with<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        timing: Timing,
        start: Pos,
        heading: Heading,
        goal: Pos,
        hfn: impl Fn(usize, usize) -> Ticks,
    ) -> Result<Option<Ticks>, PlanError> {
        match self.astar_heap(map, timing, start, heading, goal, hfn) {
            Err(PlanError::QueueFull) => {
                let Some(g) = map.bounds().index(goal) else {
                    return Ok(None);
                };
                self.compute_to(map, timing, start, heading, g)?;
                Ok(self.dist_at(g))
            }
            other => other,
        }
    }

    /// A* with the heuristic `hfn(node, heading)`, admissible and
    /// consistent over the turn-aware moves.
    fn astar_heap<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        timing: Timing,
        start: Pos,
        heading: Heading,
        goal: Pos,
        hfn: impl Fn(usize, usize) -> Ticks,
    ) -> Result<Option<Ticks>, PlanError> {
        self.tree = None;
        let s0 = self.prepare(map, timing, start, heading)?;
        let Some(g) = self.bounds.index(goal) else {
            return Ok(None);
        };
        let t = self.timing;
        let bounds = self.bounds;
        let mut heap = Heap { len: 0 };
        // Entries: (f, state); the g of a popped entry is f − h(state).
        let h0 = usize::from(heading.index());
        heap.push(self.cells.as_mut(), hfn(s0, h0), (s0 * 4 + h0) as u32)?;
        while let Some((f, state)) = heap.pop(self.cells.as_mut()) {
            let state = state as usize;
            let (v, h) = (state / 4, state % 4);
            let d = f.saturating_sub(hfn(v, h));
            let Some(_) = self.settle(v, h, d) else {
                continue;
            };
            if v == g {
                return Ok(Some(d));
            }
            let Some(arms) = arms_at(map, v) else {
                continue;
            };
            let hd = Heading::from_index(h as u8);
            if arms.has(hd) && d + t.edge <= MAX_DIST {
                if let Some(nb) = neighbour_index(bounds, v, hd) {
                    let cells = self.cells.as_mut();
                    if !cells.get(nb).is_some_and(|c| c.settled(h)) {
                        heap.push(cells, d + t.edge + hfn(nb, h), (nb * 4 + h) as u32)?;
                    }
                }
            }
            let cells = self.cells.as_mut();
            let Some(cv) = cells.get_mut(v) else { continue };
            let off = u32::from(cv.off.get(h).copied().unwrap_or(0)) + t.quarter_turn;
            let base = cv.base & DIST_MASK;
            let mut pushes = [None, None];
            for (k, h2) in [(h + 1) & 3, (h + 3) & 3].into_iter().enumerate() {
                if cv.settled(h2) || off >= u32::from(NO_OFF) {
                    continue;
                }
                let Some(o) = cv.off.get_mut(h2) else {
                    continue;
                };
                if off as u8 >= *o {
                    continue;
                }
                *o = off as u8;
                if let Some(p) = pushes.get_mut(k) {
                    *p = Some((base + off + hfn(v, h2), (v * 4 + h2) as u32));
                }
            }
            for (key, s) in pushes.into_iter().flatten() {
                heap.push(cells, key, s)?;
            }
        }
        Ok(None)
    }
}

/// A binary min-heap of (key, state) in the queue slots of the scratch.
struct Heap {
    len: usize,
}

impl Heap {
    fn entry(cells: &[PlanCell], i: usize) -> (u32, u32) {
        cells
            .get(i)
            .map_or((u32::MAX, u32::MAX), |c| (c.ring_a, c.ring_b))
    }

    fn set(cells: &mut [PlanCell], i: usize, e: (u32, u32)) {
        if let Some(c) = cells.get_mut(i) {
            c.ring_a = e.0;
            c.ring_b = e.1;
        }
    }

    fn push(&mut self, cells: &mut [PlanCell], key: u32, state: u32) -> Result<(), PlanError> {
        if self.len >= cells.len() {
            return Err(PlanError::QueueFull);
        }
        let mut i = self.len;
        self.len += 1;
        let e = (key, state);
        while i > 0 {
            let p = (i - 1) / 2;
            let pe = Self::entry(cells, p);
            if pe <= e {
                break;
            }
            Self::set(cells, i, pe);
            i = p;
        }
        Self::set(cells, i, e);
        Ok(())
    }

    fn pop(&mut self, cells: &mut [PlanCell]) -> Option<(u32, u32)> {
        if self.len == 0 {
            return None;
        }
        let top = Self::entry(cells, 0);
        self.len -= 1;
        let last = Self::entry(cells, self.len);
        let mut i = 0;
        loop {
            let l = 2 * i + 1;
            if l >= self.len {
                break;
            }
            let r = l + 1;
            let mut c = l;
            if r < self.len && Self::entry(cells, r) < Self::entry(cells, l) {
                c = r;
            }
            let ce = Self::entry(cells, c);
            if last <= ce {
                break;
            }
            Self::set(cells, i, ce);
            i = c;
        }
        Self::set(cells, i, last);
        Some(top)
    }
}
