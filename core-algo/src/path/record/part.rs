//! A plain search taken over in part, up to the first node that reads
//! otherwise: see [`DistField::take_over_before`].
//!
//! Where a node reads otherwise, a plain search still did alike all it
//! did before the time it reached that node: it reads a node only when it
//! drives on from it. [`DistField::take_over_before`] rebuilds the field
//! as it stood then: the cells with their later states unsettled, and the
//! two FIFO queues, which at any time hold a run of the entries they
//! received (a plain search's record keeps the last ones, up to the
//! queue's size). Counted on rooms 128² with 16 robots: the first node
//! that read otherwise came, on average, 89 % of the way into a rejected
//! record.

use super::super::scratch::{DIST_MASK, NO_OFF, Queues, SETTLED_SHIFT};
use super::super::{DistField, PlanCell, PlanError, arms_at, neighbour_index};
use super::{RecordedSearch, node_mark};
use crate::geometry::Heading;
use crate::map::{Block, KnownMap};
use crate::timing::{Ticks, Timing};

impl RecordedSearch<'_> {
    /// Whether it can be taken over in part
    /// ([`DistField::take_over_before`]): a plain search's, that holds
    /// its queues' last entries (the rest of one holds none, see
    /// [`RecordedSearch::after`]).
    pub fn holds_queues(&self) -> bool {
        self.state.history
    }

    /// How many of its nodes it reached before `dist`.
    pub fn reached_before(&self, dist: Ticks) -> usize {
        self.reached.partition_point(|r| r.dist < dist)
    }
}

/// The first node `rec` reached that reads otherwise in `map` (an index
/// into [`RecordedSearch::reached`]), if one does.
pub fn first_read_otherwise<M: AsRef<[Block]> + AsMut<[Block]>>(
    map: &KnownMap<M>,
    rec: RecordedSearch<'_>,
) -> Option<usize> {
    rec.reached
        .iter()
        .position(|r| node_mark(map, r.node as usize) != r.mark)
}

impl PlanCell {
    /// This cell of a finished search as it stood before the search
    /// settled anything at `dist` or later: its later states unsettled,
    /// each with the offset its settled neighbours' quarter turns
    /// (`turn` ticks) gave it, as `search::expand` writes them.
    fn before(self, dist: Ticks, turn: Ticks) -> PlanCell {
        let base = self.base & DIST_MASK;
        let mut out = PlanCell {
            base: DIST_MASK,
            off: [NO_OFF; 4],
            ..self
        };
        if base == DIST_MASK || base >= dist {
            return out;
        }
        out.base = base;
        let kept = |h: usize| {
            self.settled(h) && base + u32::from(self.off.get(h).copied().unwrap_or(NO_OFF)) < dist
        };
        for h in 0..4 {
            if kept(h) {
                out.off[h] = self.off[h];
                out.base |= 1 << (SETTLED_SHIFT + h as u32);
            } else {
                let turned = [(h + 1) & 3, (h + 3) & 3]
                    .into_iter()
                    .filter(|&n| kept(n))
                    .map(|n| u32::from(self.off[n]) + turn)
                    .min()
                    .unwrap_or(u32::MAX);
                if turned < u32::from(NO_OFF) {
                    out.off[h] = turned as u8;
                }
            }
        }
        out
    }
}

impl<S: AsRef<[PlanCell]> + AsMut<[PlanCell]>> DistField<S> {
    /// Makes this field the plain search `rec` as it stood before it
    /// settled anything at `dist` or later, over `map` as it is now: the
    /// caller has checked that every node it reached before `dist` reads
    /// the same there (`dist` at most that of the
    /// [`first_read_otherwise`]). Afterwards the field is where a search
    /// of its own from the same pose stands at that time, its callback
    /// told of the record's nodes reached before `dist`
    /// ([`RecordedSearch::reached_before`]); resume it to go on (see the
    /// module docs for why). False, and the field cleared, where the record does
    /// not hold its queues as they were then (a jumping search, or one
    /// whose queues wrapped since). A record of another window, scratch
    /// size or timing is refused with [`PlanError::OutOfBounds`] of its
    /// start.
    ///
    /// The queues then are a run of the entries they received: those
    /// queued by states settled before `dist` (states settle in time
    /// order), less those that arrive before `dist`, which were taken off
    /// by then.
    pub fn take_over_before<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        timing: Timing,
        rec: RecordedSearch<'_>,
        dist: Ticks,
    ) -> Result<bool, PlanError> {
        let key = rec.state.key;
        let b = map.bounds();
        let (start, heading) = (b.pos(key.start), Heading::from_index(key.heading));
        if self.search_key(map, timing, (start, heading), false) != Some(key) {
            return Err(PlanError::OutOfBounds(start));
        }
        self.tree = None;
        self.prepare(map, timing, start, heading)?;
        if !rec.holds_queues() {
            return Ok(false);
        }
        let t = self.timing;
        let mut dirty = self.dirty;
        let cells = self.cells.as_mut();
        for &(i, c) in rec.cells {
            if let Some(slot) = cells.get_mut(i as usize) {
                *slot = c.before(dist, t.quarter_turn);
            }
        }
        for &(i, _) in rec.cells {
            let i = i as usize;
            let Some(base) = cells.get(i).and_then(PlanCell::dist) else {
                continue;
            };
            // A node the search did not drive on from turns nowhere: its
            // headings come only by edges, perhaps long after the first,
            // where the offset saturates (see `settle_in`). Whether such a
            // heading was settled before `dist` follows from the state it
            // came from.
            if arms_at(map, i).is_none() {
                for h in Heading::ALL {
                    let hi = usize::from(h.index());
                    let saturated = cells
                        .get(i)
                        .is_some_and(|c| c.settled(hi) && c.off[hi] == NO_OFF - 1);
                    let late = saturated
                        && neighbour_index(b, i, h.opposite())
                            .and_then(|u| cells.get(u))
                            .and_then(|c| c.pose_dist(hi))
                            .is_none_or(|k| k.saturating_add(t.edge) >= dist);
                    let Some(c) = cells.get_mut(i) else {
                        break;
                    };
                    if late {
                        c.base &= !(1 << (SETTLED_SHIFT + hi as u32));
                    }
                    if !c.settled(hi) {
                        c.off[hi] = NO_OFF;
                    }
                }
            }
            let last = cells.get(i).map_or(0, |c| {
                (0..4)
                    .filter(|&h| c.settled(h))
                    .map(|h| u32::from(c.off[h]))
                    .max()
                    .unwrap_or(0)
            });
            dirty.add(i, base + last);
        }
        let cap = cells.len();
        let settled = |cells: &[PlanCell], state: u32| {
            let s = state as usize;
            cells.get(s / 4).and_then(|c| c.pose_dist(s % 4))
        };
        let q = rec.state.queue;
        let mut ends = [(0, 0); 2];
        // The edge ring holds source states, the turn ring source states
        // with the turn's side in the low bit.
        let rings = [(q.a_pushed, 1, t.edge), (q.b_pushed, 2, t.quarter_turn)];
        for (ring, (pushed, per, step)) in rings.into_iter().enumerate() {
            let all = rec.queued.get(ring).copied().unwrap_or(&[]);
            let kept = all.get(..cap).unwrap_or(all);
            let first = pushed.saturating_sub(kept.len());
            let source = |e: &u32| *e / per;
            let gone =
                |e: &u32| settled(cells, source(e)).is_some_and(|k| k.saturating_add(step) < dist);
            // The entries before the kept ones must have been taken off
            // by then: the first kept one was.
            if first > 0 && !kept.first().is_some_and(gone) {
                // Clear what was written: the next search clears the box.
                self.dirty = dirty;
                self.start = None;
                return Ok(false);
            }
            let queued = kept.partition_point(|e| settled(cells, source(e)).is_some());
            let popped = kept.get(..queued).unwrap_or(&[]).partition_point(gone);
            for n in popped..queued {
                if let (Some(c), Some(&e)) = (cells.get_mut((first + n) % cap), kept.get(n)) {
                    *c.ring_mut(ring) = e;
                }
            }
            if let Some(end) = ends.get_mut(ring) {
                *end = (first + popped, first + queued);
            }
        }
        let [(a_popped, a_pushed), (b_popped, b_pushed)] = ends;
        self.queue = Queues {
            a_head: a_popped % cap,
            a_len: a_pushed - a_popped,
            b_head: b_popped % cap,
            b_len: b_pushed - b_popped,
            a_pushed,
            b_pushed,
            a_from: a_popped,
            b_from: b_popped,
            pending: None,
        };
        self.dirty = dirty;
        self.tree = Some(map.revision());
        Ok(true)
    }
}
