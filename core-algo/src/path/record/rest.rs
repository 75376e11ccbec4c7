//! The rest of a search: resumed where a kept record stopped, written
//! down as what that part wrote, and taken over by a field that stands
//! at the same end (see the module docs of `record`).

use super::{Reached, RecordedSearch, Run, SearchRecorder, SearchState, node_mark};
use crate::map::{Block, KnownMap};
use crate::path::{DistField, Flow, PlanCell, PlanError};
use crate::timing::Ticks;

impl<S: AsRef<[PlanCell]> + AsMut<[PlanCell]>> DistField<S> {
    /// [`DistField::resume`] written down as the rest of the search (see
    /// [`SearchMemo::record_after`](super::SearchMemo::record_after)):
    /// `rec` is told every node it reaches and every node its corridor
    /// walks read, the cells it writes (those of the states it settles and
    /// of the state it expands first) with what they hold at the end, the
    /// entries its queues receive, and where the search then stands. A field that is not a forward
    /// search from a start its map vouched for is resumed and not written
    /// down.
    pub fn resume_written_down<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        rec: &mut dyn SearchRecorder,
        mut reached: impl FnMut(usize, Ticks) -> Flow,
    ) -> Result<(), PlanError> {
        if self.start.is_none() {
            return Ok(());
        }
        // The marks and memos share the ring slots: cleared first, as a
        // resumed search clears them, so that they are no part of the rest.
        self.unmark_way(map);
        if self.memo.take().is_some() {
            self.clear_memo();
        }
        let Some(key) = self.key().filter(|_| self.recordable(map)) else {
            return self.resume(map, reached);
        };
        let from = self.queue;
        // The cells it writes go to `rec` in runs, given their contents
        // once it stopped.
        let told = core::cell::RefCell::new((rec, Run::new((0, PlanCell::EMPTY))));
        if let Some((v, _, _)) = from.pending {
            let (rec, run) = &mut *told.borrow_mut();
            run.push((v as u32, PlanCell::EMPTY), |r| rec.cells_written(r));
        }
        let settled = |v: usize, _, d, first| {
            let mut t = told.borrow_mut();
            let (rec, run) = &mut *t;
            run.push((v as u32, PlanCell::EMPTY), |r| rec.cells_written(r));
            if first {
                rec.reached(&[Reached::at(map, v, d)]);
                drop(t);
                reached(v, d)
            } else {
                Flow::Continue
            }
        };
        let read = |v: usize| told.borrow_mut().0.read(v as u32, node_mark(map, v));
        if self.jumping {
            self.run_jumping::<M, false>(map, (|_| true, read), settled)?;
        } else {
            self.run::<M, false>(map, |_| true, settled)?;
        }
        let (rec, mut run) = told.into_inner();
        run.flush(|r| rec.cells_written(r));
        let cells = self.cells.as_ref();
        for (i, c) in rec.cells() {
            if let Some(now) = cells.get(*i as usize) {
                *c = *now;
            }
        }
        // The entries the queues received meanwhile, in order: their slots
        // follow from the counts.
        let cap = cells.len();
        let q = self.queue;
        let rings = [(from.a_pushed, q.a_pushed), (from.b_pushed, q.b_pushed)];
        for (ring, (before, after)) in rings.into_iter().enumerate() {
            super::tell_queued(
                rec,
                cells,
                ring,
                before.max(after.saturating_sub(cap))..after,
            );
        }
        rec.finish(SearchState {
            dirty: self.dirty,
            queue: q,
            jumps: self.jumps.clone(),
            key,
            history: false,
            from: Some(from),
        });
        Ok(())
    }

    /// Takes over `rec`, the rest of a search that went on where this
    /// field stands ([`DistField::resume_written_down`]): the caller has
    /// checked that every node it read reads the same in `map`. Afterwards
    /// the field is where resuming it would have left it had its callback
    /// stopped where the recorded one did. Whether it stood where `rec`
    /// began (the same search, its queues as they were): if not, nothing
    /// is changed.
    pub fn take_over_after<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        rec: RecordedSearch<'_>,
    ) -> bool {
        let Some(from) = rec.state.from else {
            return false;
        };
        let q = self.queue;
        let stands = (q.a_head, q.a_len, q.a_pushed, q.b_head, q.b_len, q.b_pushed)
            == (
                from.a_head,
                from.a_len,
                from.a_pushed,
                from.b_head,
                from.b_len,
                from.b_pushed,
            )
            && q.pending == from.pending;
        let forward = !self.weighted && self.reverse.is_none() && self.rev_open.is_none();
        let same = self.key() == Some(rec.state.key) && self.tree == Some(map.revision());
        if !(stands && forward && same) {
            return false;
        }
        self.unmark_way(map);
        if self.memo.take().is_some() {
            self.clear_memo();
        }
        let cells = self.cells.as_mut();
        for &(i, c) in rec.cells {
            if let Some(slot) = cells.get_mut(i as usize) {
                *slot = c;
            }
        }
        let to = rec.state.queue;
        let cap = cells.len();
        let rings = [(q.a_pushed, to.a_pushed), (q.b_pushed, to.b_pushed)];
        for (ring, ((before, after), kept)) in rings.into_iter().zip(rec.queued).enumerate() {
            let first = before.max(after.saturating_sub(cap));
            for (n, &e) in (first..after).zip(kept) {
                if let Some(c) = cells.get_mut(n % cap) {
                    *c.ring_mut(ring) = e;
                }
            }
        }
        // The slots hold the queues' entries from where both searches'
        // did: the cells brought hold the other search's.
        let mut to = to;
        to.a_from = to.a_from.max(q.a_from);
        to.b_from = to.b_from.max(q.b_from);
        self.queue = to;
        self.dirty = rec.state.dirty;
        self.jumps = rec.state.jumps.clone();
        true
    }
}
