//! Carrying a stopped reverse search over to a grown map, and going on with
//! it: see [`DistField::refresh_reverse`].
//!
//! Why: once fewer frontier nodes than robots are left, tempo searches
//! backwards from every frontier node at every decision (`explore::assign`),
//! and a robot decides again whenever the map grows. Most frontier nodes
//! outlive a decision, and most visits change none of their searches: the
//! newly passable node is a dead end of the known graph (a maze's corridor
//! grown by one node), so no way to the goal can pass it.

use super::{DistField, Flow, PlanCell, PlanError, arms_at, neighbour_index, scratch::Queues};
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
    /// in place), so they need not be expanded. Any other change, a map
    /// that changed too long ago, a window that moved, or marks written
    /// into the queue's slots since (see `mark`) refuse.
    pub fn refresh_reverse<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        timing: Timing,
    ) -> bool {
        let Some((g, since)) = self.rev_open else {
            return false;
        };
        if self.bounds != map.bounds() || self.timing != super::searchable(timing) {
            return false;
        }
        if since == map.revision() {
            return true;
        }
        let Some(changed) = map.passable_since(since) else {
            return false;
        };
        let (bounds, t) = (self.bounds, self.timing);
        let pending = self.queue.pending.map(|(v, h, _)| (v, h));
        // Check every change before settling anything.
        let mut seeds = [(0usize, Heading::North, 0 as Ticks); 8];
        let mut n = 0usize;
        for f in changed {
            let Some(arms) = arms_at(map, f) else {
                return false;
            };
            if f == g {
                return false;
            }
            let mut onward = arms.iter().filter_map(|a| {
                let v = neighbour_index(bounds, f, a)?;
                (v == g || arms_at(map, v).is_some()).then_some((v, a))
            });
            let Some((v, a)) = onward.next() else {
                continue;
            };
            if onward.next().is_some() {
                return false;
            }
            // Facing `a` on `v`, the search has its way on.
            let h = usize::from(a.index());
            let Some(d) = self.cells.as_ref().get(v).and_then(|c| c.pose_dist(h)) else {
                continue;
            };
            if pending == Some((v, h)) {
                continue;
            }
            match seeds.get_mut(n) {
                Some(s) => *s = (f, a, d + t.edge),
                None => return false,
            }
            n += 1;
        }
        for &(f, a, d) in seeds.get(..n).unwrap_or(&[]) {
            for heading in Heading::ALL {
                let turns = Timing::quarter_turns_between(heading.index(), a.index());
                let key = d + t.turn(turns);
                if key > super::MAX_DIST {
                    return self.refuse();
                }
                self.settle(f, usize::from(heading.index()), key);
            }
        }
        self.rev_open = Some((g, map.revision()));
        // Not the search a fresh one would be (see `is_reverse_to`).
        self.reverse = None;
        true
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
        let result = self.run::<M, true>(map, |v, h, key, _| {
            reached(v, Heading::from_index(h as u8), key)
        });
        if result.is_err() {
            self.refuse();
        }
        result
    }

    /// Every state a reverse search has not settled costs at least this
    /// (`None` for a field that is no open reverse search; [`Ticks::MAX`]
    /// once it has settled everything it can reach).
    pub fn reverse_settled_to(&self) -> Option<Ticks> {
        self.rev_open?;
        let q = &self.queue;
        Some(match q.pending {
            Some((_, _, key)) => key,
            None if q.a_len == 0 && q.b_len == 0 => Ticks::MAX,
            None => 0,
        })
    }

    /// Forgets the search's queues: it can no longer be resumed.
    fn refuse(&mut self) -> bool {
        self.rev_open = None;
        self.queue = Queues::default();
        false
    }
}

#[cfg(test)]
mod tests;
