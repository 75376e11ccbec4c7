//! Carrying a stopped reverse search over to a grown map, and going on with
//! it: see [`DistField::refresh_reverse`].
//!
//! Why: once fewer frontier nodes than robots are left, tempo searches
//! backwards from every frontier node at every decision (`explore::assign`),
//! and a robot decides again whenever the map grows. Most frontier nodes
//! outlive a decision, and most visits change none of their searches: the
//! newly passable node is a dead end of the known graph (a maze's corridor
//! grown by one node), so no way to the goal can pass it, or it closes a
//! loop that is no shortcut to the goal. And the visit that takes a
//! frontier node away hands its search on to the node beyond it
//! ([`DistField::rebase_reverse`]).

use super::scratch::{DIST_MASK, Queues, SETTLED_SHIFT};
use super::{DistField, Flow, PlanCell, PlanError, arms_at, neighbour_index};
use crate::geometry::Heading;
use crate::map::{Block, KnownMap};
use crate::timing::{Ticks, Timing};

impl<S: AsRef<[PlanCell]> + AsMut<[PlanCell]>> DistField<S> {
    /// The goal (storage index) of the last reverse search, if it can be
    /// refreshed and resumed.
    pub fn reverse_goal(&self) -> Option<usize> {
        self.rev_open.map(|(g, _)| g)
    }

    /// Brings a stopped (or finished) [`DistField::compute_reverse`] over to
    /// `map` as it is now, if its settled states still hold there; whether
    /// they do. If not, search again.
    ///
    /// The known graph only gains passable nodes (see
    /// [`KnownMap::passable_since`]). A way through a new node `f` needs two
    /// of its neighbours to drive on to (passable ones, or the goal); with
    /// at most one, `f` is a dead end: no settled state gets cheaper, and
    /// `f`'s own states cost the way to that neighbour plus the turn and the
    /// edge. They are settled at once if that neighbour's state is settled
    /// and expanded already (the search would never come back to them);
    /// else the search reaches them as usual. A dead end's states never
    /// make another state cheaper (out and back costs more than a U-turn
    /// in place), so they need not be expanded. A node with two ways on
    /// or more changes nothing while the search has expanded none of them:
    /// it reaches the node when it does, as if the node had always been
    /// passable. One with all of them expanded (a loop closed where the
    /// search has been) is settled at once like a dead end if no state
    /// beside it, facing it, gets cheaper through it: every way through
    /// the node passes one of those. Any other change (a shortcut, a node
    /// beside a state not settled yet, some ways on expanded and some
    /// not), a map that changed too long ago, a window that moved, or
    /// marks written into the queue's slots since (see `mark`) refuse.
    pub fn refresh_reverse<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        timing: Timing,
    ) -> bool {
        let Some(open) = self.open_on(map, timing) else {
            return false;
        };
        self.carry_over(map, open, None)
    }

    /// The open reverse search's goal and the revision its settled states
    /// hold for, if it ran in `map`'s window with this timing.
    fn open_on<M: AsRef<[Block]> + AsMut<[Block]>>(
        &self,
        map: &KnownMap<M>,
        timing: Timing,
    ) -> Option<(usize, u32)> {
        let same = self.bounds == map.bounds() && self.timing == super::searchable(timing);
        self.rev_open.filter(|_| same)
    }

    /// [`DistField::refresh_reverse`] of the search to `g` whose settled
    /// states hold for revision `since`, leaving out the change at `skip`
    /// (one [`DistField::rebase_reverse`] has accounted for).
    fn carry_over<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        (g, since): (usize, u32),
        skip: Option<usize>,
    ) -> bool {
        if since == map.revision() {
            return true;
        }
        let Some(changed) = map.passable_since(since) else {
            return false;
        };
        let (bounds, t) = (self.bounds, self.timing);
        let pending = self.queue.pending.map(|(v, h, _)| (v, h));
        // Check every change before settling anything: each new node
        // that the search has been beside, with its four states' times.
        let mut seeds = [(0usize, [0 as Ticks; 4]); 8];
        let mut n = 0usize;
        // The time of state (`v`, facing `h`), if it is settled.
        let settled = |v: usize, h: Heading| {
            let cell = self.cells.as_ref().get(v)?;
            cell.pose_dist(usize::from(h.index()))
        };
        for f in changed.filter(|&f| Some(f) != skip) {
            let Some(arms) = arms_at(map, f) else {
                return false;
            };
            if f == g {
                return false;
            }
            // Facing `a` on `v`, the search has its way on: the time of
            // that state, if it is settled and expanded already (its
            // expansion missed `f`).
            let expanded = |v: usize, a: Heading| {
                let d = settled(v, a)?;
                (pending != Some((v, usize::from(a.index())))).then_some(d)
            };
            // The ways on from `f` (to a passable node or the goal), each
            // with its time if expanded.
            let mut ways = [(0usize, Heading::North, None::<Ticks>); 4];
            let mut m = 0usize;
            for a in arms.iter() {
                let Some(v) = neighbour_index(bounds, f, a) else {
                    continue;
                };
                if v != g && arms_at(map, v).is_none() {
                    continue;
                }
                if let Some(w) = ways.get_mut(m) {
                    *w = (v, a, expanded(v, a));
                    m += 1;
                }
            }
            let ways = ways.get(..m).unwrap_or(&[]);
            // None expanded: the search reaches `f` when it expands one, as
            // if `f` had always been passable (a loop closed beyond what
            // the search settled was most of the refusals on maze 64²
            // with 16 robots). Some but not all: refuse.
            let expanded_ways = ways.iter().filter(|w| w.2.is_some()).count();
            if expanded_ways == 0 {
                continue;
            }
            if expanded_ways < ways.len() {
                return false;
            }
            // `f`'s time facing `h`: its cheapest way on, turn included.
            let time = |h: Heading| {
                ways.iter()
                    .filter_map(|&(_, a, d)| {
                        let turns = Timing::quarter_turns_between(h.index(), a.index());
                        Some(d? + t.turn(turns) + t.edge)
                    })
                    .min()
            };
            let mut keys = [0 as Ticks; 4];
            for (k, h) in keys.iter_mut().zip(Heading::ALL) {
                match time(h) {
                    Some(x) if x <= super::MAX_DIST => *k = x,
                    _ => return false,
                }
            }
            // A loop closed where the search has been: it still holds if
            // no state beside `f` gets cheaper through it. A robot on `v`
            // facing `f` drives in and on; any other state's way through
            // `f` passes one of those (or turns on `f`, which `keys`
            // counts). A dead end (one way on) has none cheaper: out and
            // back costs more than a U-turn in place.
            if ways.len() > 1 {
                for &(v, a, _) in ways {
                    let facing = a.opposite();
                    let through = keys.get(usize::from(facing.index())).map(|&k| k + t.edge);
                    match (settled(v, facing), through) {
                        (Some(x), Some(y)) if x <= y => {}
                        _ => return false,
                    }
                }
            }
            match seeds.get_mut(n) {
                Some(s) => *s = (f, keys),
                None => return false,
            }
            n += 1;
        }
        for &(f, keys) in seeds.get(..n).unwrap_or(&[]) {
            for (h, key) in keys.into_iter().enumerate() {
                self.settle(f, h, key);
            }
        }
        self.rev_open = Some((g, map.revision()));
        // Not the search a fresh one would be (see `is_reverse_to`).
        self.reverse = None;
        true
    }

    /// Carries a stopped (or finished) reverse search to node `u` over to
    /// node `x`, once `u` is visited, if `x` is a frontier node whose only
    /// way in is from `u` and `u`'s only way in is from one node `w`: every
    /// way to `x` then ends w → u → x, so every state's time to `x` is its
    /// time to `u` plus the same turn on `u` and the same edge, but for
    /// `u`'s own states. Then brought over to the map as it is now, as
    /// [`DistField::refresh_reverse`] does; whether the search holds. If
    /// not, it is spent: search again.
    ///
    /// Why: once fewer frontier nodes than robots are left, a visit takes
    /// a frontier node away and adds the ones beyond it, each of which
    /// needed a search of its own, back to its cheapest robots (half of
    /// the fresh reverse searches on maze 64² with 16 robots). A corridor
    /// grown by one node carries its search on instead, for the price of
    /// one pass over what it settled.
    pub fn rebase_reverse<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        timing: Timing,
        x: usize,
    ) -> bool {
        let Some((u, since)) = self.open_on(map, timing) else {
            return false;
        };
        let t = self.timing;
        let (Some((ux, a)), Some((_, into_u))) = (way_in(map, x), way_in(map, u)) else {
            return false;
        };
        if ux != u || !map.is_frontier_at(x) || arms_at(map, u).is_none() {
            return false;
        }
        let turn = |from: Heading, to: Heading| {
            t.turn(Timing::quarter_turns_between(from.index(), to.index()))
        };
        let c = turn(into_u, a) + t.edge;
        if self.dirty.reach().saturating_add(c) > super::MAX_DIST
            || self.queue.pending.is_some_and(|(v, _, _)| v == u)
            || !self.jumps.shift(c)
        {
            return false;
        }
        // Every settled time grows by `c`; the queues name the settled
        // states their entries came from, so their keys grow with them
        // (the jump heap's keys were shifted above).
        let cells = self.cells.as_mut();
        self.dirty.for_each_row(|r| {
            let start = r.start;
            for (i, cell) in cells.get_mut(r).unwrap_or(&mut []).iter_mut().enumerate() {
                if let (Some(d), false) = (cell.dist(), start + i == u) {
                    cell.base = (cell.base & !DIST_MASK) | (d + c);
                }
            }
        });
        if let Some(p) = self.queue.pending.as_mut() {
            p.2 += c;
        }
        let all = ALL_SETTLED << SETTLED_SHIFT;
        if let Some(cell) = cells.get_mut(u) {
            cell.base = all | t.edge;
            for (o, h) in cell.off.iter_mut().zip(Heading::ALL) {
                *o = turn(h, a) as u8;
            }
        }
        if let Some(cell) = cells.get_mut(x) {
            cell.base = all;
            cell.off = [0; 4];
        }
        self.dirty = self.dirty.rebased(x, c);
        self.rev_open = Some((x, since));
        self.reverse = None;
        if self.carry_over(map, (x, since), Some(u)) {
            true
        } else {
            self.refuse()
        }
    }

    /// Goes on with a stopped reverse search over the map it was refreshed
    /// to ([`DistField::refresh_reverse`]): `reached` sees every state as
    /// it settles, cheapest first, as in [`DistField::compute_reverse`].
    /// Does nothing for a field that is no such search.
    pub fn resume_reverse<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        mut reached: impl FnMut(usize, Heading, Ticks) -> Flow,
    ) -> Result<(), PlanError> {
        if self.rev_open.is_none_or(|(_, r)| r != map.revision()) {
            return Ok(());
        }
        let settled = |v, h, key, _| reached(v, Heading::from_index(h as u8), key);
        let result = if self.jumping {
            self.run_jumping::<M, true>(map, (|_| true, |_| {}), settled)
        } else {
            self.run::<M, true>(map, |_| true, settled)
        };
        if result.is_err() {
            self.refuse();
        }
        result
    }

    /// Takes an open reverse search that another robot's planner kept for
    /// a map reading as `map` did at revision `rev` (equal
    /// [`MapPrint`](crate::map::MapPrint)s, which the caller vouches for),
    /// as if it had been searched over `map` at `rev`: it can then be
    /// refreshed and resumed as this map's own (see
    /// [`DistField::refresh_reverse`]). A reverse search reads nothing of
    /// the map but what the prints agree on. Whether it could: only a
    /// plain open reverse search, without marks or memos (their
    /// revisions would say more than the prints).
    pub fn adopt_reverse(&mut self, rev: u32) -> bool {
        if self.rev_open.is_none() || self.way.is_some() || self.memo.is_some() || self.weighted {
            return false;
        }
        self.tree = self.tree.map(|_| rev);
        self.reverse = self.reverse.map(|(g, _)| (g, rev));
        self.rev_open = self.rev_open.map(|(g, _)| (g, rev));
        true
    }

    /// Forgets what the last search was: nothing in the field is taken
    /// for a kept search any more, and the next search clears its cells
    /// as usual. What a field handed back by a host holds (see
    /// `explore::SharedColumns`): its stamps were another map's.
    pub fn forget(&mut self) {
        self.tree = None;
        self.way = None;
        self.reverse = None;
        self.memo = None;
        self.start = None;
        self.refuse();
    }

    /// Every state a reverse search has not settled costs at least this
    /// (`None` for a field that is no open reverse search; [`Ticks::MAX`]
    /// once it has settled everything it can reach).
    pub fn reverse_settled_to(&self) -> Option<Ticks> {
        self.rev_open?;
        let q = &self.queue;
        Some(match q.pending {
            Some((_, _, key)) => key,
            None if q.a_len == 0 && q.b_len == 0 && self.jumps.is_empty() => Ticks::MAX,
            None => 0,
        })
    }

    /// Forgets the search's queues: it can no longer be resumed.
    fn refuse(&mut self) -> bool {
        self.rev_open = None;
        self.queue = Queues::default();
        self.jumps.reset(self.jumps.start());
        false
    }
}

/// All four headings' settled bits.
const ALL_SETTLED: u32 = 0xF;

/// The one known way into node `i`: the passable neighbour with an arm to
/// it, and the heading of that arm; `None` with none or several.
pub fn way_in<M: AsRef<[Block]> + AsMut<[Block]>>(
    map: &KnownMap<M>,
    i: usize,
) -> Option<(usize, Heading)> {
    let bounds = map.bounds();
    let mut ways = Heading::ALL.into_iter().filter_map(|b| {
        let v = neighbour_index(bounds, i, b)?;
        let h = b.opposite();
        arms_at(map, v)?.has(h).then_some((v, h))
    });
    let one = ways.next();
    match ways.next() {
        Some(_) => None,
        None => one,
    }
}

#[cfg(test)]
mod tests;
