//! A forward search written down, so that another field can take it over
//! on another map where it reads the same: see [`SearchMemo`].
//!
//! ## Why
//!
//! In a simulated team of 16 every robot, at every decision, grows a field
//! from each team mate's pose to that mate's cheapest frontier nodes
//! (`explore::assign`). A mate's pose holds while it drives an edge, and
//! the other robots decide in that time, each growing the same field again
//! on a map that has grown elsewhere. Counted on rooms 128² with 16
//! robots: 89 % of these searches read exactly the nodes, with the same
//! known arms and frontier marks, that one of the 64 searches before them
//! had read.
//!
//! ## Why a taken-over search is exact
//!
//! A plain forward search reads, of the map, only the nodes it reaches:
//! whether each is a frontier node, and the known arms of those it drives
//! on from. A jumping one also reads the corridor nodes its walks pass and
//! the nodes they end on. Everything else it does follows from its start,
//! the timing and its own cells. So if every node a recorded search read
//! reads the same ([`node_mark`]) in another map, a search there from the
//! same pose reaches the same nodes at the same times in the same order,
//! and stands where the recorded one stopped with the same cells and
//! queues. Resumed from there, it goes on as the fresh search would.
//!
//! A plain search can be taken over in part too: see `part`.
//!
//! ## The rest of a search
//!
//! A decision grows some team mates' picks in later rounds, resuming
//! their fields, and the next decision grows them alike. Where a field
//! stands at the end of a kept record, the rest it is resumed for is
//! written down too ([`DistField::resume_written_down`]): what it reached
//! and read, the cells it wrote, the entries its queues received and
//! where it stopped. A field that stands at the same end (it took that
//! record over, or wrote it down) takes a rest that reads the same over
//! ([`DistField::take_over_after`]) for the same reason a whole search is
//! exact: the rest's reads and the state it started from are all it
//! depends on. It costs the cells the rest wrote, not the whole field.

use super::corridor::{Jumps, other_arm};
use super::scratch::{DIST_MASK, Dirty, Queues};
use super::{DistField, Flow, PlanCell, PlanError, arms_at, neighbour_index};
use crate::geometry::Heading;
use crate::map::{Block, Bounds, KnownMap};
use crate::timing::{Ticks, Timing};

/// Which search a record is of: the window, the scratch's size (the queues
/// wrap at it), the timing and the start pose.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct SearchKey {
    /// The window's origin and size.
    window: (i16, i16, u16, u16),
    cells: usize,
    timing: (Ticks, Ticks),
    start: usize,
    heading: u8,
    jumping: bool,
}

impl SearchKey {
    /// The key of a search in a window of a scratch that many cells long,
    /// with a timing as searches run it (`searchable`), from a start
    /// (storage index and heading).
    fn new(
        (b, cells, t): (Bounds, usize, Timing),
        (start, heading): (usize, Heading),
        jumping: bool,
    ) -> SearchKey {
        SearchKey {
            window: (b.origin.x, b.origin.y, b.width, b.height),
            cells,
            timing: (t.edge, t.quarter_turn),
            start,
            heading: heading.index(),
            jumping,
        }
    }
}

/// One node a recorded search reached, in the order it reached them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Reached {
    /// Storage index.
    pub node: u32,
    /// The time the search reached it at.
    pub dist: Ticks,
    /// What the search read of it ([`node_mark`]).
    pub mark: u8,
}

impl Reached {
    /// Only a placeholder for a buffer's unused slots.
    const NONE: Reached = Reached {
        node: 0,
        dist: 0,
        mark: 0,
    };

    /// Node `i` of `map`, reached at travel `d`, as a search reads it.
    pub fn at<M: AsRef<[Block]> + AsMut<[Block]>>(
        map: &KnownMap<M>,
        i: usize,
        d: Ticks,
    ) -> Reached {
        Reached {
            node: i as u32,
            dist: d,
            mark: node_mark(map, i),
        }
    }

    /// Whether the search read the node as a frontier node: what
    /// `KnownMap::is_frontier_at` says of it in every map the record reads
    /// the same in, without a look at the map.
    pub fn is_frontier(&self) -> bool {
        self.mark & FRONTIER_MARK != 0
    }
}

/// The bit of a [`node_mark`] that says the node is a frontier node.
const FRONTIER_MARK: u8 = 0x20;

/// What a recorded search holds besides its cells: where its queues and
/// jump arrivals stand, and the box of cells it wrote.
#[derive(Clone, Debug)]
pub struct SearchState {
    dirty: Dirty,
    queue: Queues,
    jumps: Jumps,
    key: SearchKey,
    /// Whether the record holds its queues' last entries
    /// ([`RecordedSearch::queued`]), so that it can be taken over in part.
    history: bool,
    /// Of a record that goes on from another: where the queues stood
    /// when it began, which the field that takes it over must match.
    from: Option<Queues>,
}

impl SearchState {
    /// Whether the search ran to the end: nothing was left to reach.
    pub fn ran_out(&self) -> bool {
        self.queue.ran_out() && self.jumps.is_empty()
    }
}

/// A recorded search, as a [`SearchMemo`] hands it back.
#[derive(Clone, Copy, Debug)]
pub struct RecordedSearch<'a> {
    /// The memo's name for it, never 0: a field that stands where it
    /// stopped can ask for a record that goes on from there
    /// ([`SearchMemo::recall_after`]).
    pub id: u64,
    /// The record where this one goes on ([`SearchMemo::record_after`]),
    /// or 0 for a whole search. A record that goes on holds only what its
    /// own part reached and read, the cells that part wrote, and where
    /// the search stands after it: it is taken over only by a field that
    /// stands where the other stopped ([`DistField::take_over_after`]).
    pub after: u64,
    /// Every node it reached, in order.
    pub reached: &'a [Reached],
    /// Nodes it read without reaching them, with what it read of each
    /// ([`node_mark`]): a jumping search's corridor nodes, and where its
    /// walks through them end.
    pub read: &'a [(u32, u8)],
    /// Every cell it wrote: (storage index, contents).
    pub cells: &'a [(u32, PlanCell)],
    /// The last entries its edge queue and its turn queue received, in
    /// order, up to the queue's size (a plain search's; a jumping one
    /// keeps none): its queues at any time late enough are a run of them.
    /// The rest of a search keeps those it received, plain or jumping.
    pub queued: [&'a [u32]; 2],
    /// Its queues and box.
    pub state: &'a SearchState,
}

/// Where a search is written down while it runs (see [`SearchMemo::record`]).
pub trait SearchRecorder {
    /// Nodes the search reached, in order.
    fn reached(&mut self, r: &[Reached]);
    /// The search read a node it did not reach (see [`RecordedSearch::read`]).
    fn read(&mut self, node: u32, mark: u8);
    /// Cells the search wrote: (storage index, contents), in order.
    fn cells_written(&mut self, cells: &[(u32, PlanCell)]);
    /// The next entries its edge queue (`ring` 0) or turn queue (1)
    /// received, in order (see [`RecordedSearch::queued`]).
    fn queued(&mut self, ring: usize, entries: &[u32]);
    /// The cells told so far, to be given their contents: a search that
    /// goes on from a record tells which cells it writes as it writes
    /// them, and what they hold once it stopped.
    fn cells(&mut self) -> &mut [(u32, PlanCell)];
    /// The search is written down whole: without this call it is dropped.
    fn finish(&mut self, state: SearchState);
}

/// Forward searches kept to be taken over (see the module docs). A
/// robot keeps none: its own searches rarely repeat (on rooms 128² with
/// 16 robots, 4 % of a robot's searches of a team mate's picks came from
/// the pose its last decision had searched, on a map that read the same).
/// The simulator, which runs every robot's decisions, keeps them for all.
pub trait SearchMemo: Sync {
    /// Hands `take` the searches recorded under `key`, newest first, until
    /// it returns true; whether one did.
    fn recall(&self, key: SearchKey, take: &mut dyn FnMut(RecordedSearch<'_>) -> bool) -> bool;
    /// Writes a search down: `search` runs it, telling the recorder it is
    /// handed what it reaches, its cells and its state. The record's id,
    /// where it is kept.
    fn record(
        &self,
        key: SearchKey,
        search: &mut dyn FnMut(&mut dyn SearchRecorder),
    ) -> Option<u64>;
    /// Hands `take` the records that go on where record `after` stopped,
    /// newest first, until it returns true; whether one did.
    fn recall_after(&self, after: u64, take: &mut dyn FnMut(RecordedSearch<'_>) -> bool) -> bool;
    /// Writes down the rest of a search that goes on where the kept record
    /// `after` stopped (a field that took it over, or wrote it down,
    /// resumed; see [`DistField::resume_written_down`]). A later decision
    /// whose field stands there takes it over instead of resuming: in a
    /// team, the rounds that grow a team mate's picks repeat from decision
    /// to decision as its first search does. `search` runs whether or not
    /// the record is kept; its id, where it is.
    fn record_after(
        &self,
        key: SearchKey,
        after: u64,
        search: &mut dyn FnMut(&mut dyn SearchRecorder),
    ) -> Option<u64>;
    /// The search `recall` just handed over was taken over in part
    /// ([`DistField::take_over_before`]), for the memo's counts.
    fn taken_over_in_part(&self) {}
}

/// What a forward search reads of node `i`: its known arms (bits 0..4),
/// whether they are known (bit 4), whether it is a frontier node (bit 5).
pub fn node_mark<M: AsRef<[Block]> + AsMut<[Block]>>(map: &KnownMap<M>, i: usize) -> u8 {
    let arms = arms_at(map, i).map_or(0, |a| 0x10 | a.bits());
    let frontier = if map.is_frontier_at(i) {
        FRONTIER_MARK
    } else {
        0
    };
    arms | frontier
}

/// Whether every node `rec` read reads in `map` as it did. Last reached
/// first: a search reaches the frontier, where maps change, last.
pub fn reads_same<M: AsRef<[Block]> + AsMut<[Block]>>(
    map: &KnownMap<M>,
    rec: RecordedSearch<'_>,
) -> bool {
    rec.reached
        .iter()
        .rev()
        .all(|r| node_mark(map, r.node as usize) == r.mark)
        && rec
            .read
            .iter()
            .all(|&(i, m)| node_mark(map, i as usize) == m)
}

impl<S: AsRef<[PlanCell]> + AsMut<[PlanCell]>> DistField<S> {
    /// The key a search from (`start`, `heading`) over `map` with `timing`
    /// in this field, `jumping` or plain, is recorded under, if the start
    /// lies in the window.
    pub fn search_key<M: AsRef<[Block]> + AsMut<[Block]>>(
        &self,
        map: &KnownMap<M>,
        timing: Timing,
        (start, heading): (crate::geometry::Pos, Heading),
        jumping: bool,
    ) -> Option<SearchKey> {
        let b = map.bounds();
        let cells = self.cells.as_ref().len();
        let t = super::searchable(timing);
        Some(SearchKey::new(
            (b, cells, t),
            (b.index(start)?, heading),
            jumping,
        ))
    }

    /// Writes the last search down into `rec`, if it is a forward search
    /// from a start that a map vouched for ([`DistField::compute`] or
    /// [`DistField::compute_jumping`]) and `map` is that map: every cell it
    /// wrote (those it settled, and the queue slots still waiting), the
    /// nodes a jumping search read without reaching them, and its state.
    /// Whether it did.
    pub fn write_down<M: AsRef<[Block]> + AsMut<[Block]>>(
        &self,
        map: &KnownMap<M>,
        rec: &mut dyn SearchRecorder,
    ) -> bool {
        self.write_down_walking(map, rec, self.jumping)
    }

    /// A search from (`start`, `heading`), [`DistField::compute_jumping`]
    /// if `jumping` else [`DistField::compute`], that tells `rec` every
    /// node it reaches, and then, unless it failed, is written down there
    /// as [`DistField::write_down`] would. A jumping search tells `rec`
    /// the nodes its walks read as it walks them: exactly what it read,
    /// where `write_down` walks every corridor again from every settled
    /// state (a tenth of a 16-robot run on a 256² maze, and more than the
    /// search read).
    pub fn compute_written_down<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        timing: Timing,
        (start, heading, jumping): (crate::geometry::Pos, Heading, bool),
        rec: &mut dyn SearchRecorder,
        mut reached: impl FnMut(usize, Ticks) -> Flow,
    ) -> Result<(), PlanError> {
        // Both callbacks tell `rec`: the nodes reached in runs.
        let told = core::cell::RefCell::new((rec, Run::new(Reached::NONE)));
        let result = self.compute_kept_reading(
            map,
            timing,
            (start, heading, jumping),
            (
                |i: usize, d: Ticks| {
                    let (rec, run) = &mut *told.borrow_mut();
                    run.push(Reached::at(map, i, d), |r| rec.reached(r));
                    reached(i, d)
                },
                |v: usize| told.borrow_mut().0.read(v as u32, node_mark(map, v)),
            ),
        );
        let (rec, mut run) = told.into_inner();
        run.flush(|r| rec.reached(r));
        if result.is_ok() {
            self.write_down_walking(map, rec, false);
        }
        result
    }

    /// Whether this field holds a forward search from a start that `map`
    /// vouched for, plain or jumping, unmarked: one that can be written
    /// down.
    fn recordable<M: AsRef<[Block]> + AsMut<[Block]>>(&self, map: &KnownMap<M>) -> bool {
        self.tree == Some(map.revision())
            && self.bounds == map.bounds()
            && !self.weighted
            && self.reverse.is_none()
            && self.rev_open.is_none()
            && self.way.is_none()
            && self.memo.is_none()
    }

    /// [`DistField::write_down`], the corridors walked again only if
    /// `walks` (the search did not tell the recorder as it went).
    fn write_down_walking<M: AsRef<[Block]> + AsMut<[Block]>>(
        &self,
        map: &KnownMap<M>,
        rec: &mut dyn SearchRecorder,
        walks: bool,
    ) -> bool {
        let Some(key) = self.key() else {
            return false;
        };
        if !self.recordable(map) {
            return false;
        }
        let cells = self.cells.as_ref();
        let mut written = Run::new((0, PlanCell::EMPTY));
        self.dirty.for_each_row(|row| {
            let start = row.start;
            for (k, c) in cells.get(row).unwrap_or(&[]).iter().enumerate() {
                if c.base & DIST_MASK != DIST_MASK {
                    written.push(((start + k) as u32, *c), |r| rec.cells_written(r));
                    if walks {
                        self.write_walks(map, (start + k, c), rec);
                    }
                }
            }
        });
        let cap = cells.len();
        let q = self.queue;
        // A plain search's queues' slots still hold their last entries:
        // written down, they let another map take the search over in part
        // (see `take_over_before`). A jumping one writes down only the
        // slots still waiting, as cells.
        let history = !self.jumping;
        if history {
            for (ring, (from, pushed)) in [(q.a_from, q.a_pushed), (q.b_from, q.b_pushed)]
                .into_iter()
                .enumerate()
            {
                tell_queued(
                    rec,
                    cells,
                    ring,
                    from.max(pushed.saturating_sub(cap))..pushed,
                );
            }
        } else {
            for (head, len) in [(q.a_head, q.a_len), (q.b_head, q.b_len)] {
                for k in 0..len {
                    let i = super::wrap(head + k, cap);
                    if let Some(c) = cells.get(i) {
                        written.push((i as u32, *c), |r| rec.cells_written(r));
                    }
                }
            }
        }
        written.flush(|r| rec.cells_written(r));
        rec.finish(SearchState {
            dirty: self.dirty,
            queue: self.queue,
            jumps: self.jumps.clone(),
            key,
            history,
            from: None,
        });
        true
    }

    /// Tells `rec` every node the walks from node `v`'s settled states (in
    /// `c`) could have read: each walk from where it enters a corridor to
    /// the node it ends on. A walk that went no farther (a full jump heap,
    /// a node settled already) read less, so this is all it read and
    /// maybe more, which only makes a taken-over search rarer.
    fn write_walks<M: AsRef<[Block]> + AsMut<[Block]>>(
        &self,
        map: &KnownMap<M>,
        (v, c): (usize, &PlanCell),
        rec: &mut dyn SearchRecorder,
    ) {
        let Some(arms) = arms_at(map, v) else {
            return;
        };
        let bounds = self.bounds;
        for h in Heading::ALL {
            let hi = usize::from(h.index());
            if !c.settled(hi) || !arms.has(h) {
                continue;
            }
            let (mut w, mut back) = match neighbour_index(bounds, v, h) {
                Some(w) => (w, (hi + 2) & 3),
                None => continue,
            };
            for _ in 0..bounds.area() {
                rec.read(w as u32, node_mark(map, w));
                let Some(out) = other_arm(map, self.jumps.start(), w, back) else {
                    break;
                };
                match neighbour_index(bounds, w, Heading::from_index(out as u8)) {
                    Some(n) => (w, back) = (n, (out + 2) & 3),
                    None => break,
                }
            }
        }
    }

    /// The key of the last search, if it has a start.
    fn key(&self) -> Option<SearchKey> {
        let cells = self.cells.as_ref().len();
        let window = (self.bounds, cells, self.timing);
        Some(SearchKey::new(window, self.start?, self.jumping))
    }

    /// Makes this field the search `rec`, over `map` as it is now: the
    /// caller has checked that every node it read reads the same there
    /// ([`reads_same`]). Afterwards the field is what a search of the
    /// record's kind ([`DistField::compute`] or
    /// [`DistField::compute_jumping`]) from the same pose would have left
    /// had its callback stopped where the recorded one did; resume it to
    /// go on. A record of another window, scratch size or timing, or the
    /// rest of a search ([`RecordedSearch::after`]), is refused with
    /// [`PlanError::OutOfBounds`] of its start.
    pub fn take_over<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        timing: Timing,
        rec: RecordedSearch<'_>,
    ) -> Result<(), PlanError> {
        let key = rec.state.key;
        let b = map.bounds();
        let (start, heading) = (b.pos(key.start), Heading::from_index(key.heading));
        // The rest of a search (see `take_over_after`) is no whole one.
        let whole = rec.state.from.is_none();
        if !whole || self.search_key(map, timing, (start, heading), key.jumping) != Some(key) {
            return Err(PlanError::OutOfBounds(start));
        }
        self.tree = None;
        // Clears the last search's cells, its marks and memos with them.
        self.prepare(map, timing, start, heading)?;
        let cells = self.cells.as_mut();
        for &(i, c) in rec.cells {
            if let Some(slot) = cells.get_mut(i as usize) {
                *slot = c;
            }
        }
        let mut q = rec.state.queue;
        if rec.state.history {
            // The entries still waiting, each to its slot.
            let cap = cells.len();
            let rings = [(q.a_len, q.a_pushed), (q.b_len, q.b_pushed)];
            for (ring, ((len, pushed), kept)) in rings.into_iter().zip(rec.queued).enumerate() {
                let first = pushed.saturating_sub(kept.len());
                for n in pushed.saturating_sub(len)..pushed {
                    if let (Some(c), Some(&e)) = (cells.get_mut(n % cap), kept.get(n - first)) {
                        *c.ring_mut(ring) = e;
                    }
                }
            }
            q.a_from = q.a_pushed.saturating_sub(q.a_len);
            q.b_from = q.b_pushed.saturating_sub(q.b_len);
        }
        self.dirty = rec.state.dirty;
        self.queue = q;
        self.jumping = key.jumping;
        self.jumps = rec.state.jumps.clone();
        self.tree = Some(map.revision());
        Ok(())
    }
}

mod part;
mod rest;

pub use part::first_read_otherwise;

/// Entries a recorder is handed at once. Writing a search down tells it
/// every node reached, every cell written and every entry the queues
/// received; one `dyn` call each cost more than the copying it did
/// (rooms 64², 16 robots: 4 % of all instructions; docs/results/
/// performance.md, stop 61).
const RUN: usize = 128;

/// Entries gathered on the stack into runs of [`RUN`], each handed on
/// whole.
struct Run<T> {
    buf: [T; RUN],
    len: usize,
}

impl<T: Copy> Run<T> {
    /// An empty run; `fill` only initialises the buffer.
    fn new(fill: T) -> Run<T> {
        Run {
            buf: [fill; RUN],
            len: 0,
        }
    }

    /// Adds `x`, handing the run to `out` once it is full.
    #[inline]
    fn push(&mut self, x: T, out: impl FnOnce(&[T])) {
        if let Some(slot) = self.buf.get_mut(self.len) {
            *slot = x;
            self.len += 1;
        }
        if self.len == RUN {
            out(&self.buf);
            self.len = 0;
        }
    }

    /// Hands what is left to `out`, if anything.
    fn flush(&mut self, out: impl FnOnce(&[T])) {
        if let Some(rest) = self.buf.get(..self.len).filter(|r| !r.is_empty()) {
            out(rest);
        }
        self.len = 0;
    }
}

/// Tells `rec` the entries ring `ring` received with the numbers `n` in
/// `range`, read from the slots they went to (`n % cells.len()`): at most
/// two runs of slots, the second from slot 0 on. Only the last
/// `cells.len()` entries are still in their slots, so a longer `range`
/// tells those.
fn tell_queued(
    rec: &mut dyn SearchRecorder,
    cells: &[PlanCell],
    ring: usize,
    range: core::ops::Range<usize>,
) {
    let cap = cells.len();
    if range.is_empty() || cap == 0 {
        return;
    }
    let first = range.start % cap;
    let len = range.len().min(cap);
    let head = cells.get(first..cap.min(first + len)).unwrap_or(&[]);
    let tail = cells.get(..len - head.len()).unwrap_or(&[]);
    let mut buf = [0; RUN];
    for chunk in head.chunks(RUN).chain(tail.chunks(RUN)) {
        for (b, c) in buf.iter_mut().zip(chunk) {
            *b = c.ring(ring);
        }
        rec.queued(ring, buf.get(..chunk.len()).unwrap_or(&[]));
    }
}

#[cfg(test)]
mod tests;
