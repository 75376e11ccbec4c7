//! Ways read from a field: the cheapest path back to the start, its first
//! heading, and marks on the nodes of a way, so that "does this way pass
//! that node?" costs one look-up instead of a walk.

use super::{
    Back, DistField, Flow, MAX_VIAS, Marked, ON_WAY, PlanCell, State, Vias, arms_at, corridor,
    neighbour_index,
};
use crate::geometry::{Heading, Pos};
use crate::map::{Block, KnownMap};
use crate::timing::Ticks;

impl<S: AsRef<[PlanCell]> + AsMut<[PlanCell]>> DistField<S> {
    /// Whether the drive into state (`v`, `h`) at `d` came from (`u`, `h`).
    fn drive_pred<M: AsRef<[Block]> + AsMut<[Block]>>(
        &self,
        map: &KnownMap<M>,
        v: usize,
        h: usize,
        d: Ticks,
    ) -> Option<usize> {
        let hd = Heading::from_index(h as u8);
        let u = neighbour_index(self.bounds, v, hd.opposite())?;
        let du = self.cells.as_ref().get(u)?.pose_dist(h)?;
        (du + self.timing.edge == d && arms_at(map, u)?.has(hd)).then_some(u)
    }

    /// Walks the cheapest path back from node `target` to the start,
    /// calling `step(node, heading driven into it)` for each drive, last
    /// drive first. Returns `false` if `target` was not reached.
    fn walk_back<M: AsRef<[Block]> + AsMut<[Block]>>(
        &self,
        map: &KnownMap<M>,
        target: usize,
        mut step: impl FnMut(usize, Heading),
    ) -> bool {
        self.walk_back_while(map, target, |v, h, _| {
            step(v, h);
            Flow::Continue
        })
    }

    /// [`DistField::walk_back`] that also passes the distance of each state
    /// driven into, and stops (returning `true`) when `step` says so.
    pub(super) fn walk_back_while<M: AsRef<[Block]> + AsMut<[Block]>>(
        &self,
        map: &KnownMap<M>,
        target: usize,
        mut step: impl FnMut(usize, Heading, Ticks) -> Flow,
    ) -> bool {
        let Some(mut state) = self.last_state(target) else {
            return false;
        };
        for _ in 0..self.bounds.area().saturating_add(1) {
            match self.step_back(map, state) {
                Back::Start => return true,
                Back::Lost => return false,
                Back::Drive {
                    into: (v, h, d),
                    from,
                } => {
                    if step(v, Heading::from_index(h as u8), d) == Flow::Stop {
                        return true;
                    }
                    state = from;
                }
                Back::Corridor { into, from } => {
                    let mut stopped = false;
                    let bt = (self.bounds, self.timing);
                    corridor::drives_back(map, bt, into, from.0, |v, h, d| {
                        stopped = stopped || step(v, Heading::from_index(h as u8), d) == Flow::Stop;
                        !stopped
                    });
                    if stopped {
                        return true;
                    }
                    state = from;
                }
            }
        }
        false
    }

    /// The state (node, heading, distance) in which the cheapest path to
    /// node `target` ends: its cheapest heading.
    fn last_state(&self, target: usize) -> Option<State> {
        self.start?;
        if !self.holds_ways() {
            return None;
        }
        let cell = self.cells.as_ref().get(target)?;
        let h = (0..4).find(|&h| cell.pose_dist(h) == cell.dist())?;
        Some((target, h, cell.pose_dist(h)?))
    }

    /// One drive back along the cheapest path from `state`, undoing the
    /// turns on the spot before it (at most three).
    fn step_back<M: AsRef<[Block]> + AsMut<[Block]>>(
        &self,
        map: &KnownMap<M>,
        state: State,
    ) -> Back {
        let Some((s0, h0)) = self.start else {
            return Back::Lost;
        };
        let t = self.timing;
        let (v, mut h, mut d) = state;
        for _ in 0..4 {
            if v == s0 && h == usize::from(h0.index()) && d == 0 {
                return Back::Start;
            }
            if let Some(u) = self.drive_pred(map, v, h, d) {
                return Back::Drive {
                    into: (v, h, d),
                    from: (u, h, d - t.edge),
                };
            }
            if self.jumping {
                let cells = self.cells.as_ref();
                let entered = corridor::back(map, (self.bounds, t), s0, (v, h, d));
                if let Some((x, hx, dx)) = entered {
                    if cells.get(x).and_then(|c| c.pose_dist(hx)) == Some(dx) {
                        return Back::Corridor {
                            into: (v, h, d),
                            from: (x, hx, dx),
                        };
                    }
                }
            }
            let cv = self.cells.as_ref().get(v);
            let turn = [(h + 3) & 3, (h + 1) & 3].into_iter().find(|&hp| {
                cv.and_then(|c| c.pose_dist(hp))
                    .is_some_and(|dp| dp + t.quarter_turn == d)
            });
            let Some(hp) = turn else { break };
            h = hp;
            d -= t.quarter_turn;
        }
        Back::Lost
    }

    /// The heading the robot must face to leave the start node on the
    /// cheapest path to node `target`; `None` when `target` is the start
    /// node or was not reached.
    pub fn first_heading<M: AsRef<[Block]> + AsMut<[Block]>>(
        &self,
        map: &KnownMap<M>,
        target: usize,
    ) -> Option<Heading> {
        let mut first = None;
        self.walk_back(map, target, |_, h| first = Some(h))
            .then_some(first)
            .flatten()
    }

    /// The heading to leave node `at` on the cheapest path to node
    /// `target`, when that path passes the pose (`at`, `heading`) or starts
    /// there; `None` otherwise. A robot that keeps its share stands on
    /// the path its last decision found, and on an unchanged map the rest
    /// of a cheapest path is a cheapest path: this walk replaces a new
    /// search (an A* in a maze settles most of it; a sixth of a 16-robot
    /// run on a 128² maze).
    pub fn heading_after<M: AsRef<[Block]> + AsMut<[Block]>>(
        &self,
        map: &KnownMap<M>,
        target: usize,
        at: usize,
        heading: Heading,
    ) -> Option<Heading> {
        // One walk, kept in `path::ahead`, which also keeps its next poses.
        self.heading_after_kept(map, target, (at, heading), &mut None)
    }

    /// The distance below which a walk back cannot meet node `via` any
    /// more: its own, or 0 for a node a jumping search did not reach (it
    /// may lie inside a corridor the way passes); `None` if no way can
    /// pass it.
    fn walk_floor(&self, via: usize) -> Option<Ticks> {
        match self.dist_at(via) {
            None if self.jumping && self.holds_ways() => Some(0),
            d => d,
        }
    }

    /// Whether the cheapest path to node `target` drives through node
    /// `via` (the target counts, the start does not). Used to keep out of a
    /// team mate's way home.
    pub fn path_passes<M: AsRef<[Block]> + AsMut<[Block]>>(
        &self,
        map: &KnownMap<M>,
        target: usize,
        via: usize,
    ) -> bool {
        // Distances fall along the walk back: once below `via`'s own, the
        // walk cannot meet it any more (homecoming asks this for many nodes
        // near the end of long paths).
        let Some(dv) = self.walk_floor(via) else {
            return false;
        };
        if self.way == Some((Marked::Way(target), map.revision())) {
            return self
                .cells
                .as_ref()
                .get(via)
                .is_some_and(|c| c.ring_b & ON_WAY != 0);
        }
        let mut hit = false;
        let walked = self.walk_back_while(map, target, |v, _, d| {
            hit |= v == via;
            if hit || d < dv {
                Flow::Stop
            } else {
                Flow::Continue
            }
        });
        walked && hit
    }

    /// Whether the cheapest path to node `target` drives through any of the
    /// nodes `vias`, as [`DistField::path_passes`] says for each: one walk
    /// back for all of them. A retreat asks it of every spot it looks at
    /// with every team mate's place, in a crowded maze a quarter of a run
    /// when each walked alone (docs/results/performance.md, stop 29).
    pub fn path_passes_any<M: AsRef<[Block]> + AsMut<[Block]>>(
        &self,
        map: &KnownMap<M>,
        target: usize,
        vias: &[usize],
    ) -> bool {
        if self.way == Some((Marked::Way(target), map.revision())) {
            return vias.iter().any(|&via| self.path_passes(map, target, via));
        }
        // Distances fall along the walk back: below the nearest via's, it
        // cannot meet any of them any more.
        let Some(dv) = vias.iter().filter_map(|&via| self.walk_floor(via)).min() else {
            return false;
        };
        let mut hit = false;
        let walked = self.walk_back_while(map, target, |v, _, d| {
            hit |= vias.contains(&v);
            if hit || d < dv {
                Flow::Stop
            } else {
                Flow::Continue
            }
        });
        walked && hit
    }

    /// Marks the cheapest path to node `target`, so that
    /// [`DistField::path_passes`] answers for it in O(1) until the field or
    /// the map changes. Homecoming and retreats ask whether each of many
    /// nodes lies on one team mate's way; walking the way back for every
    /// node cost O(way length) each, and in a large maze, where ways run
    /// hundreds of edges, that was most of a run. One way per field is
    /// marked at a time; the marks live in a bit of the settled cells' ring
    /// slots, which the next search clears. Returns whether `target` was
    /// reached; a jumping search is never marked (its corridor cells are
    /// not its own to write).
    pub fn mark_way<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        target: usize,
    ) -> bool {
        self.mark(map, Marked::Way(target))
    }

    /// Marks `marked` (see [`DistField::mark_way`]) unless it is marked
    /// already; whether its walk reached its end.
    pub(super) fn mark<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        marked: Marked,
    ) -> bool {
        if self.way == Some((marked, map.revision())) {
            return true;
        }
        // Marks live in the ring slots a stopped reverse search keeps its
        // queues in.
        self.rev_open = None;
        if let (Some((Marked::Descent(from), rev)), Marked::Descent(to)) = (self.way, marked) {
            if rev == map.revision() && self.unmark_descent_prefix(map, from, to) {
                self.way = Some((marked, rev));
                return true;
            }
        }
        self.unmark_way(map);
        if !self.set_marks(map, marked, true) {
            // Not reached (or the walk broke off): clear what was set.
            self.set_marks(map, marked, false);
            return false;
        }
        self.way = Some((marked, map.revision()));
        true
    }

    /// Sets or clears the marks along `marked`; whether its walk reached
    /// its end.
    fn set_marks<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        marked: Marked,
        on: bool,
    ) -> bool {
        match marked {
            Marked::Way(target) => self.set_way_bits(map, target, on),
            Marked::Descent(state) => self.set_descent_bits(map, state, on),
        }
    }

    /// Whether the cheapest path to node `v` drives through node `via`,
    /// as [`DistField::path_passes`] says, for many `v` and one `via`: see
    /// [`DistField::passes_any`].
    pub fn passes<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        v: usize,
        via: usize,
    ) -> bool {
        self.passes_any(map, v, &[via])
    }

    /// Whether the cheapest path to node `v` drives through any of the
    /// nodes `vias`, for many `v` and the same `vias`: once the search has
    /// run to completion its queues are empty, and each (node, heading)
    /// state's answer is memoised in its first ring slot, so that asking
    /// for every node of the map costs O(map) in all rather than O(way)
    /// each. A retreat asks it for every node it might retreat to (is it
    /// behind the bumper's goal, or behind a team mate's home that fills
    /// before ours, seen from home?); in a crowded maze the walks were most
    /// of the run. A search still in progress, or more than [`MAX_VIAS`]
    /// nodes, just walk.
    pub fn passes_any<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        v: usize,
        vias: &[usize],
    ) -> bool {
        let complete = self.queue.ran_out();
        let rev = map.revision();
        if !complete || self.jumping || self.tree != Some(rev) || vias.len() > MAX_VIAS {
            return self.path_passes_any(map, v, vias);
        }
        let same = matches!(&self.memo, Some((k, r)) if *r == rev && k.as_slice() == vias);
        if !same {
            self.clear_memo();
            self.memo = Vias::from_slice(vias).ok().map(|k| (k, rev));
            self.rev_open = None;
        }
        // Distances fall along the walk back: below the nearest via's, it
        // cannot meet any of them any more.
        let (Some(dv), Some(first)) = (
            vias.iter().filter_map(|&via| self.dist_at(via)).min(),
            self.last_state(v),
        ) else {
            return false;
        };
        let limit = self.bounds.area().saturating_add(1);
        // Walk back to the answer: a via driven into, fallen below their
        // distances, the start, or a state whose answer is known.
        let mut state = first;
        let mut answer = false;
        for _ in 0..limit {
            if let Some(a) = self.memo_at(state) {
                answer = a;
                break;
            }
            match self.step_back(map, state) {
                // Memos are never kept on jumping searches.
                Back::Start | Back::Lost | Back::Corridor { .. } => break,
                Back::Drive { into, from } => {
                    if vias.contains(&into.0) {
                        answer = true;
                        break;
                    }
                    if into.2 < dv {
                        break;
                    }
                    state = from;
                }
            }
        }
        // Every state walked has the same answer: the rest of its way is
        // the rest of this one.
        let mut state = first;
        for _ in 0..limit {
            if self.memo_at(state).is_some() {
                break;
            }
            self.set_memo(state, answer);
            match self.step_back(map, state) {
                Back::Start | Back::Lost | Back::Corridor { .. } => break,
                Back::Drive { into, from } => {
                    if vias.contains(&into.0) || into.2 < dv {
                        break;
                    }
                    state = from;
                }
            }
        }
        answer
    }

    /// The memoised answer of state `(node, heading, _)`, if any: two bits
    /// per heading (known, answer) in the node's first ring slot.
    fn memo_at(&self, (v, h, _): State) -> Option<bool> {
        let bits = self.cells.as_ref().get(v)?.ring_a >> (2 * h);
        (bits & 1 != 0).then_some(bits & 2 != 0)
    }

    fn set_memo(&mut self, (v, h, _): State, answer: bool) {
        if let Some(c) = self.cells.as_mut().get_mut(v) {
            c.ring_a |= (1 | (u32::from(answer) << 1)) << (2 * h);
        }
    }

    /// Clears every settled cell's first ring slot (the memo's bits).
    pub(super) fn clear_memo(&mut self) {
        let cells = self.cells.as_mut();
        self.dirty.for_each_row(|r| {
            for c in cells.get_mut(r).unwrap_or(&mut []) {
                c.ring_a = 0;
            }
        });
    }

    /// Clears the marks of [`DistField::mark_way`].
    pub(super) fn unmark_way<M: AsRef<[Block]> + AsMut<[Block]>>(&mut self, map: &KnownMap<M>) {
        let Some((marked, revision)) = self.way.take() else {
            return;
        };
        if revision == map.revision() {
            self.set_marks(map, marked, false);
        } else {
            // The map changed, so the walk back might take another way:
            // clear every settled cell.
            let cells = self.cells.as_mut();
            self.dirty.for_each_row(|r| {
                for c in cells.get_mut(r).unwrap_or(&mut []) {
                    c.ring_b &= !ON_WAY;
                }
            });
        }
    }

    /// Sets or clears the mark on every node driven into on the cheapest
    /// path to `target`; whether the walk reached the start. Its own loop
    /// over [`DistField::step_back`], not `walk_back_while`: it writes the
    /// cells it walks, which that borrow-shared walk cannot.
    fn set_way_bits<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        target: usize,
        on: bool,
    ) -> bool {
        let Some(mut state) = self.last_state(target) else {
            return false;
        };
        for _ in 0..self.bounds.area().saturating_add(1) {
            match self.step_back(map, state) {
                Back::Start => return true,
                // Marks live on settled cells, which a corridor's are not.
                Back::Lost | Back::Corridor { .. } => return false,
                Back::Drive { into, from } => {
                    if let Some(c) = self.cells.as_mut().get_mut(into.0) {
                        if on {
                            c.ring_b |= ON_WAY;
                        } else {
                            c.ring_b &= !ON_WAY;
                        }
                    }
                    state = from;
                }
            }
        }
        false
    }

    /// The first node, walking the cheapest path back from node `target`
    /// (included) towards the start (included), for which `pred` holds;
    /// `None` if none does or `target` was not reached. A retreat uses it
    /// to find where its way leaves a team mate's.
    pub fn first_back<M: AsRef<[Block]> + AsMut<[Block]>>(
        &self,
        map: &KnownMap<M>,
        target: usize,
        mut pred: impl FnMut(usize) -> bool,
    ) -> Option<usize> {
        let mut found = None;
        let walked = self.walk_back_while(map, target, |v, _, _| {
            if pred(v) {
                found = Some(v);
                Flow::Stop
            } else {
                Flow::Continue
            }
        });
        if !walked {
            return None;
        }
        found.or_else(|| self.start.map(|(s0, _)| s0).filter(|&s0| pred(s0)))
    }

    /// Writes the nodes of the cheapest path to node `target` into `out`,
    /// start node first; returns their number, or `None` if `target` was
    /// not reached or `out` is too short.
    pub fn path<M: AsRef<[Block]> + AsMut<[Block]>>(
        &self,
        map: &KnownMap<M>,
        target: usize,
        out: &mut [Pos],
    ) -> Option<usize> {
        let mut n = 0usize;
        let mut fits = true;
        let bounds = self.bounds;
        let ok = self.walk_back(map, target, |v, _| {
            if let Some(slot) = out.get_mut(n) {
                *slot = bounds.pos(v);
            } else {
                fits = false;
            }
            n += 1;
        });
        let (s0, _) = self.start?;
        if !ok || !fits {
            return None;
        }
        let slot = out.get_mut(n)?;
        *slot = bounds.pos(s0);
        n += 1;
        out.get_mut(..n)?.reverse();
        Some(n)
    }
}
