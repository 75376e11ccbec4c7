//! The search loop every field grows by: two FIFO queues, one for edges
//! and one for quarter turns, over the scratch cells (see the `path`
//! module docs for the layout).

use super::corridor::{self, Jumps};
use super::scratch::{DIST_MASK, Dirty, NO_OFF, Queues, SETTLED_SHIFT};
use super::{
    DistField, Flow, MAX_DIST, PlanCell, PlanError, arms_at, lower_base, neighbour_index, wrap,
};
use crate::geometry::Heading;
use crate::map::{Block, Bounds, KnownMap};
use crate::timing::{Ticks, Timing};

impl<S: AsRef<[PlanCell]> + AsMut<[PlanCell]>> DistField<S> {
    /// The search loop of [`DistField::resume`] (`REV` false: from the
    /// start) and [`DistField::compute_reverse`] (`REV` true: towards the
    /// goal, each edge driven backwards). `settled(node, heading, key,
    /// first)` sees every settled state; `first` marks the node's first.
    /// Forward searches drive on from a node only if `passable(node)`.
    ///
    /// Everything the loop touches at every state (the queues, the dirty
    /// box, the heads' keys) lives in locals, written back once: as fields
    /// behind `&mut self` they were stored and reloaded at every state,
    /// 13 % more instructions for a full field on open and maze 256²
    /// (docs/results/performance.md, stop 38).
    ///
    pub(super) fn run<M: AsRef<[Block]> + AsMut<[Block]>, const REV: bool>(
        &mut self,
        map: &KnownMap<M>,
        passable: impl Fn(usize) -> bool,
        mut settled: impl FnMut(usize, usize, Ticks, bool) -> Flow,
    ) -> Result<(), PlanError> {
        // The marks share the ring slots that the queues are about to use.
        self.unmark_way(map);
        if self.memo.take().is_some() {
            self.clear_memo();
        }
        let t = self.timing;
        let bounds = self.bounds;
        let mut q = self.queue;
        let mut dirty = self.dirty;
        let cells = self.cells.as_mut();
        let cap = cells.len();
        let key_of = |cells: &[PlanCell], state: usize| -> Option<Ticks> {
            cells.get(state / 4).and_then(|c| c.pose_dist(state % 4))
        };
        // The queues' heads as (entry, key), read once per head: a head's
        // key stays what it was until that head is popped (its source
        // state is settled, so final). `NO_KEY`: not read yet.
        let (mut entry_a, mut key_a) = (0usize, NO_KEY);
        let (mut entry_b, mut key_b) = (0usize, NO_KEY);
        let result = loop {
            if let Some(state) = q.pending.take() {
                let queues = (&mut q, None);
                let walk = (&passable, &mut |_| {});
                if let Err(e) = expand::<M, REV>(cells, queues, map, (bounds, t), walk, state) {
                    break Err(e);
                }
            }
            if key_a == NO_KEY && q.a_len > 0 {
                entry_a = cells
                    .get(q.a_head)
                    .map_or(usize::MAX, |c| c.ring_a as usize);
                match key_of(cells, entry_a) {
                    Some(k) => key_a = k + t.edge,
                    None => {
                        // A corrupt entry: drop it rather than loop forever.
                        q.a_head = wrap(q.a_head + 1, cap);
                        q.a_len -= 1;
                        continue;
                    }
                }
            }
            if key_b == NO_KEY && q.b_len > 0 {
                entry_b = cells
                    .get(q.b_head)
                    .map_or(usize::MAX, |c| c.ring_b as usize);
                match key_of(cells, entry_b / 2) {
                    Some(k) => key_b = k + t.quarter_turn,
                    None => {
                        q.b_head = wrap(q.b_head + 1, cap);
                        q.b_len -= 1;
                        continue;
                    }
                }
            }
            if key_a == NO_KEY && key_b == NO_KEY {
                break Ok(());
            }
            // Ties go to the edge queue.
            let (v, h, key) = if key_a <= key_b {
                let key = key_a;
                key_a = NO_KEY;
                q.a_head = wrap(q.a_head + 1, cap);
                q.a_len -= 1;
                let s = entry_a;
                let h = s % 4;
                let toward = if REV { (h + 2) & 3 } else { h };
                let Some(w) = neighbour_index(bounds, s / 4, Heading::from_index(toward as u8))
                else {
                    continue;
                };
                (w, h, key)
            } else {
                let key = key_b;
                key_b = NO_KEY;
                q.b_head = wrap(q.b_head + 1, cap);
                q.b_len -= 1;
                let s = entry_b / 2;
                let h2 = if entry_b % 2 == 0 {
                    (s + 1) & 3
                } else {
                    (s + 3) & 3
                };
                (s / 4, h2, key)
            };
            let Some(first) = settle_in(cells, &mut dirty, v, h, key) else {
                continue;
            };
            q.pending = Some((v, h, key));
            if settled(v, h, key, first) == Flow::Stop {
                break Ok(());
            }
        };
        self.queue = q;
        self.dirty = dirty;
        result
    }

    /// [`DistField::run`], driving through corridors in one move, their
    /// arrivals queued in the jump heap (see `corridor`): forward, or
    /// (`REV`) back from the goal. A loop of its own: one loop for both,
    /// the jump queue folded away by a const parameter when plain, ran
    /// every plain search slower (rooms 128², 16 robots, no search
    /// jumping: 68 against 58 s; docs/results/performance.md, stop 42).
    /// `read` is told every node a forward walk reads the arms of.
    pub(super) fn run_jumping<M: AsRef<[Block]> + AsMut<[Block]>, const REV: bool>(
        &mut self,
        map: &KnownMap<M>,
        (passable, mut read): (impl Fn(usize) -> bool, impl FnMut(usize)),
        mut settled: impl FnMut(usize, usize, Ticks, bool) -> Flow,
    ) -> Result<(), PlanError> {
        // The marks share the ring slots that the queues are about to use.
        self.unmark_way(map);
        if self.memo.take().is_some() {
            self.clear_memo();
        }
        let t = self.timing;
        let bounds = self.bounds;
        let mut q = self.queue;
        let mut dirty = self.dirty;
        let jumps = &mut self.jumps;
        let cells = self.cells.as_mut();
        let cap = cells.len();
        let key_of = |cells: &[PlanCell], state: usize| -> Option<Ticks> {
            cells.get(state / 4).and_then(|c| c.pose_dist(state % 4))
        };
        // The queues' heads as (entry, key), read once per head: a head's
        // key stays what it was until that head is popped (its source
        // state is settled, so final). `NO_KEY`: not read yet.
        let (mut entry_a, mut key_a) = (0usize, NO_KEY);
        let (mut entry_b, mut key_b) = (0usize, NO_KEY);
        let result = loop {
            if let Some(state) = q.pending.take() {
                let queues = (&mut q, Some(&mut *jumps));
                let walk = (&passable, &mut read);
                if let Err(e) = expand::<M, REV>(cells, queues, map, (bounds, t), walk, state) {
                    break Err(e);
                }
            }
            if key_a == NO_KEY && q.a_len > 0 {
                entry_a = cells
                    .get(q.a_head)
                    .map_or(usize::MAX, |c| c.ring_a as usize);
                match key_of(cells, entry_a) {
                    Some(k) => key_a = k + t.edge,
                    None => {
                        // A corrupt entry: drop it rather than loop forever.
                        q.a_head = wrap(q.a_head + 1, cap);
                        q.a_len -= 1;
                        continue;
                    }
                }
            }
            if key_b == NO_KEY && q.b_len > 0 {
                entry_b = cells
                    .get(q.b_head)
                    .map_or(usize::MAX, |c| c.ring_b as usize);
                match key_of(cells, entry_b / 2) {
                    Some(k) => key_b = k + t.quarter_turn,
                    None => {
                        q.b_head = wrap(q.b_head + 1, cap);
                        q.b_len -= 1;
                        continue;
                    }
                }
            }
            // A push can put a cheaper arrival on top: read it every time.
            let key_j = jumps.least().unwrap_or(NO_KEY);
            if key_a == NO_KEY && key_b == NO_KEY && key_j == NO_KEY {
                break Ok(());
            }
            // Ties go to the edge queue, then the turn queue.
            let (v, h, key) = if key_j < key_a.min(key_b) {
                match jumps.pop() {
                    Some(state) => state,
                    None => continue,
                }
            } else if key_a <= key_b {
                let key = key_a;
                key_a = NO_KEY;
                q.a_head = wrap(q.a_head + 1, cap);
                q.a_len -= 1;
                let s = entry_a;
                let h = s % 4;
                let toward = if REV { (h + 2) & 3 } else { h };
                let Some(w) = neighbour_index(bounds, s / 4, Heading::from_index(toward as u8))
                else {
                    continue;
                };
                (w, h, key)
            } else {
                let key = key_b;
                key_b = NO_KEY;
                q.b_head = wrap(q.b_head + 1, cap);
                q.b_len -= 1;
                let s = entry_b / 2;
                let h2 = if entry_b % 2 == 0 {
                    (s + 1) & 3
                } else {
                    (s + 3) & 3
                };
                (s / 4, h2, key)
            };
            let Some(first) = settle_in(cells, &mut dirty, v, h, key) else {
                continue;
            };
            q.pending = Some((v, h, key));
            if settled(v, h, key, first) == Flow::Stop {
                break Ok(());
            }
        };
        self.queue = q;
        self.dirty = dirty;
        result
    }
}

/// A queue head whose key is not read yet (above every real key).
const NO_KEY: Ticks = Ticks::MAX;

/// Expands the settled state (`v`, `h`) at distance `d` for
/// [`DistField::run`]: the edge on (forward: from `v` if it is passable
/// and has the arm; reverse: the state one edge back, if that node has
/// the arm) into the edge ring, and quarter turns either way that improve
/// on a heading's tentative offset into the turn ring. Every node a
/// reverse search settles (but the goal, whose states are all settled at
/// 0) was entered along an edge, so it is passable and may turn.
///
/// With `jumps`, an edge into a corridor goes on to its far end (see
/// `corridor::walk`, which tells `read` every node it reads; reverse: back
/// to where a robot would enter it, see `corridor::walk_back`) and queues
/// the arrival there, unless it is full.
#[inline(always)]
fn expand<M: AsRef<[Block]> + AsMut<[Block]>, const REV: bool>(
    cells: &mut [PlanCell],
    (q, jumps): (&mut Queues, Option<&mut Jumps>),
    map: &KnownMap<M>,
    (bounds, t): (Bounds, Timing),
    (passable, read): (&impl Fn(usize) -> bool, &mut impl FnMut(usize)),
    (v, h, d): (usize, usize, Ticks),
) -> Result<(), PlanError> {
    let cap = cells.len();
    let heading = Heading::from_index(h as u8);
    let drive = if REV {
        neighbour_index(bounds, v, heading.opposite())
            .filter(|&w| arms_at(map, w).is_some_and(|a| a.has(heading)))
    } else {
        match arms_at(map, v) {
            Some(arms) if passable(v) => {
                if arms.has(heading) {
                    neighbour_index(bounds, v, heading)
                } else {
                    None
                }
            }
            _ => return Ok(()),
        }
    };
    if let Some(w) = drive.filter(|_| d + t.edge <= MAX_DIST) {
        let jump = match jumps {
            Some(jumps) => {
                if jumps.spill_if_full() {
                    None
                } else {
                    let into = (w, h, d + t.edge);
                    let walked = if REV {
                        corridor::walk_back(map, (bounds, t), jumps.start(), into)
                    } else {
                        let walk = (passable, read);
                        corridor::walk((&*cells, &*jumps), map, (bounds, t), walk, into)
                    };
                    match walked {
                        (end, true) => Some((end, jumps)),
                        (_, false) => None,
                    }
                }
            }
            None => None,
        };
        if let Some(((x, hx, key), jumps)) = jump {
            if !cells.get(x).is_some_and(|c| c.settled(hx)) {
                // Not full: checked above.
                jumps.push((x, hx, key));
            }
        } else if !cells.get(w).is_some_and(|c| c.settled(h)) {
            if q.a_len == cap {
                return Err(PlanError::QueueFull);
            }
            if let Some(c) = cells.get_mut(wrap(q.a_head + q.a_len, cap)) {
                c.ring_a = (v * 4 + h) as u32;
            }
            q.a_len += 1;
            q.a_pushed += 1;
        }
    }
    let Some(cv) = cells.get_mut(v) else {
        return Ok(());
    };
    let turned = u32::from(cv.off[h & 3]) + t.quarter_turn;
    if turned >= u32::from(NO_OFF) {
        return Ok(());
    }
    let turned = turned as u8;
    let mut up = [false; 2];
    for (dir, h2) in [(0usize, (h + 1) & 3), (1, (h + 3) & 3)] {
        if !cv.settled(h2) && turned < cv.off[h2] {
            cv.off[h2] = turned;
            up[dir] = true;
        }
    }
    for (dir, up) in up.into_iter().enumerate() {
        if !up {
            continue;
        }
        if q.b_len == cap {
            return Err(PlanError::QueueFull);
        }
        if let Some(c) = cells.get_mut(wrap(q.b_head + q.b_len, cap)) {
            c.ring_b = ((v * 4 + h) * 2 + dir) as u32;
        }
        q.b_len += 1;
        q.b_pushed += 1;
    }
    Ok(())
}

/// Settles state (`i`, `h`) of `cells` at `key`, growing the `dirty` box;
/// returns whether it was the node's first settled state (then `key` is
/// the node's distance), or `None` if the state was settled already.
#[inline(always)]
pub(super) fn settle_in(
    cells: &mut [PlanCell],
    dirty: &mut Dirty,
    i: usize,
    h: usize,
    key: Ticks,
) -> Option<bool> {
    let c = cells.get_mut(i)?;
    let h = h & 3;
    let bit = 1 << (SETTLED_SHIFT + h as u32);
    if c.base & bit != 0 {
        return None;
    }
    dirty.add(i, key);
    let dist = c.base & DIST_MASK;
    let first = dist == DIST_MASK;
    if first {
        c.base = key & DIST_MASK;
    } else if key < dist {
        lower_base(c, key);
    }
    let off = key
        .saturating_sub(c.base & DIST_MASK)
        .min(u32::from(NO_OFF - 1)) as u8;
    c.off[h] = off;
    c.base |= bit;
    Some(first)
}
