//! Jumping along corridors: a forward search that settles no state inside
//! a corridor (see [`DistField::compute_jumping`]).
//!
//! ## Why
//!
//! Four in five nodes of a maze are corridor nodes: two known arms, one in
//! and one out. A plain search settles up to four states on each (the
//! arrival, two quarter turns, the U-turn) and expands every one, yet no
//! cheapest way to a node outside a corridor turns inside one: driving in
//! and back costs more than a U-turn before entering. So a drive into a
//! corridor can go on to its far end at once, adding an edge per node and
//! a quarter turn per bend, and push only the state it arrives in. With
//! 16 robots on a 128² maze, 82 % of the states the plain searches settled
//! were corridor states (docs/results/performance.md, stop 42).
//!
//! ## The queue for jumps
//!
//! A jump costs many edges, so its arrival cannot join the two FIFOs,
//! whose keys grow by one edge or one turn per entry. Arrivals wait in a
//! small min-heap of (key, state) instead; ties go to the lower state
//! index, so the search stays deterministic. When it is full a drive
//! simply goes into the corridor's first node as in a plain search, which
//! is slower but exact.

use super::scratch::PlanCell;
use super::{MAX_DIST, arms_at, neighbour_index};
use crate::geometry::Heading;
use crate::map::{Block, Bounds, KnownMap};
use crate::timing::{Ticks, Timing};

/// Jump arrivals a field holds in flight at once (8 bytes each).
pub const JUMP_SLOTS: usize = 128;

/// The jump arrivals of a search not settled yet, least key first.
#[derive(Clone, Debug, Default)]
pub(super) struct Jumps {
    /// `key << 32 | node * 4 + heading`.
    heap: heapless::BinaryHeap<u64, heapless::binary_heap::Min, JUMP_SLOTS>,
    /// The start node: a walk stops there.
    start: usize,
    /// Whether a drive went into a corridor plain since the start (the
    /// heap was full): then a walk also stops at corridor nodes that hold
    /// a settled state. Until then only the start can, and a walk need not
    /// read the scratch at all.
    spilled: bool,
}

impl Jumps {
    /// No arrivals, for a search from node `start`.
    pub(super) fn reset(&mut self, start: usize) {
        self.heap.clear();
        self.start = start;
        self.spilled = false;
    }

    /// Queues state (`v`, `h`) at `key`; `false` when full.
    #[inline]
    pub(super) fn push(&mut self, (v, h, key): (usize, usize, Ticks)) -> bool {
        self.heap
            .push((u64::from(key) << 32) | (v * 4 + h) as u64)
            .is_ok()
    }

    /// Whether no arrival can be queued: then the drive goes in plain, and
    /// the search has spilled.
    #[inline]
    pub(super) fn spill_if_full(&mut self) -> bool {
        self.spilled |= self.heap.is_full();
        self.heap.is_full()
    }

    /// The least key queued.
    #[inline]
    pub(super) fn least(&self) -> Option<Ticks> {
        self.heap.peek().map(|&e| (e >> 32) as Ticks)
    }

    /// The least arrival (node, heading, key), taken off the queue.
    #[inline]
    pub(super) fn pop(&mut self) -> Option<(usize, usize, Ticks)> {
        let e = self.heap.pop()?;
        let s = (e & 0xFFFF_FFFF) as usize;
        Some((s / 4, s % 4, (e >> 32) as Ticks))
    }

    /// Whether a drive went into a corridor plain: then corridor nodes
    /// may hold states dearer than they are, and no way is read.
    pub(super) fn spilled(&self) -> bool {
        self.spilled
    }

    /// The node a walk stops at: the start (forward), the goal (reverse).
    #[inline]
    pub(super) fn start(&self) -> usize {
        self.start
    }

    /// Whether no arrival is queued.
    pub(super) fn is_empty(&self) -> bool {
        self.heap.is_empty()
    }

    /// Every queued key grows by `c` (a rebased reverse search, see
    /// `refresh`); `false`, leaving the queue as it was, if one would pass
    /// `MAX_DIST`. Adding the same to every key keeps the heap's order.
    pub(super) fn shift(&mut self, c: Ticks) -> bool {
        if self.heap.iter().any(|&e| (e >> 32) as Ticks + c > MAX_DIST) {
            return false;
        }
        for e in self.heap.iter_mut() {
            *e += u64::from(c) << 32;
        }
        true
    }

    /// How many arrivals are queued.
    #[cfg(test)]
    pub(super) fn len(&self) -> usize {
        self.heap.len()
    }
}

/// Where a drive into node `w` facing `h`, arriving at `key`, ends when it
/// goes on through every corridor node it meets: the state it arrives in,
/// and whether it passed any corridor node. A node is passed only if it
/// has exactly two known arms, one of them back the way it came, is
/// `passable`, and holds no settled state yet (the start, or a node a full
/// heap sent the search into, is searched as usual). `read` is told every
/// node whose arms it reads, the last one too.
#[inline]
pub(super) fn walk<M: AsRef<[Block]> + AsMut<[Block]>>(
    (cells, jumps): (&[PlanCell], &Jumps),
    map: &KnownMap<M>,
    (bounds, t): (Bounds, Timing),
    (passable, read): (&impl Fn(usize) -> bool, &mut impl FnMut(usize)),
    (w, h, key): (usize, usize, Ticks),
) -> ((usize, usize, Ticks), bool) {
    let (mut v, mut h, mut key) = (w, h, key);
    let mut jumped = false;
    // A walk can only close a loop at the node it started from, where it
    // stops (no corridor node, or the start, or one gone into plain); the
    // bound guards a corrupt map.
    for _ in 0..bounds.area() {
        read(v);
        let Some(out) = other_arm(map, jumps.start, v, (h + 2) & 3) else {
            break;
        };
        if (jumps.spilled && cells.get(v).is_none_or(|c| c.dist().is_some())) || !passable(v) {
            break;
        }
        let turn = if out == h { 0 } else { t.quarter_turn };
        let next = key + turn + t.edge;
        let Some(n) = neighbour_index(bounds, v, Heading::from_index(out as u8)) else {
            break;
        };
        if next > MAX_DIST {
            break;
        }
        (v, h, key) = (n, out, next);
        jumped = true;
    }
    ((v, h, key), jumped)
}

/// [`walk`] for a reverse search: where the way back from state (`w`,
/// `h`), whose time to the goal is `key`, ends when it goes back through
/// every corridor node it meets. A robot on `w` facing `h` came through
/// `w`'s other arm, so its time there facing in is `key` plus the turn it
/// makes on `w`, and one node back it is an edge more. The walk stops at
/// a node that is no corridor node, and also at one whose node behind has
/// no arm back to it (a frontier node): from there the way back is no way
/// at all, and the node's own states are settled as usual. It reads no
/// scratch: a corridor node that holds settled states (a full heap sent a
/// search into it) is passed all the same, as only the states outside
/// corridors are ever read from a jumping reverse search (see
/// `CorridorExits`).
#[inline(always)]
pub(super) fn walk_back<M: AsRef<[Block]> + AsMut<[Block]>>(
    map: &KnownMap<M>,
    (bounds, t): (Bounds, Timing),
    goal: usize,
    (w, h, key): (usize, usize, Ticks),
) -> ((usize, usize, Ticks), bool) {
    let (mut w, mut h, mut key) = (w, h, key);
    // The arms of `w`, carried from one node to the next: each node's
    // cell is read once.
    let mut bits = arms_at(map, w).map_or(0, |a| a.bits());
    let mut jumped = false;
    // A walk back can only close a loop at a node that is no corridor
    // node; the bound guards a corrupt map.
    for _ in 0..bounds.area() {
        let toward = 1u8 << (h & 3);
        if w == goal || bits.count_ones() != 2 || bits & toward == 0 {
            break;
        }
        let o = (bits & !toward).trailing_zeros() as usize;
        let into = (o + 2) & 3;
        let Some(u) = neighbour_index(bounds, w, Heading::from_index(o as u8)) else {
            break;
        };
        let behind = arms_at(map, u).map_or(0, |a| a.bits());
        if behind & (1 << into) == 0 {
            break;
        }
        let turn = if into == h { 0 } else { t.quarter_turn };
        let next = key + turn + t.edge;
        if next > MAX_DIST {
            break;
        }
        (w, h, key, bits) = (u, into, next, behind);
        jumped = true;
    }
    ((w, h, key), jumped)
}

/// The arm of node `v` other than `toward` (a heading index), if `v` is a
/// node a walk passes (two known arms, one of them `toward`, not the
/// `start`).
#[inline]
pub(super) fn other_arm<M: AsRef<[Block]> + AsMut<[Block]>>(
    map: &KnownMap<M>,
    start: usize,
    v: usize,
    toward: usize,
) -> Option<usize> {
    let bits = arms_at(map, v)?.bits();
    let to = 1u8 << (toward & 3);
    (v != start && bits.count_ones() == 2 && bits & to != 0)
        .then(|| (bits & !to).trailing_zeros() as usize)
}

/// The state a walk began from to arrive in state (`v`, `h`) at `d`, if
/// the node behind `v` is a corridor node: (entry node, the heading it
/// drove into the corridor with, the key that state must hold). The walk
/// back mirrors [`walk`]: an edge per node and a quarter turn per bend.
pub(super) fn back<M: AsRef<[Block]> + AsMut<[Block]>>(
    map: &KnownMap<M>,
    (bounds, t): (Bounds, Timing),
    start: usize,
    (v, h, d): (usize, usize, Ticks),
) -> Option<(usize, usize, Ticks)> {
    let mut cur = neighbour_index(bounds, v, Heading::from_index(((h + 2) & 3) as u8))?;
    let mut out = h;
    let mut other = other_arm(map, start, cur, out)?;
    let mut cost = t.edge;
    for _ in 0..bounds.area() {
        let into = (other + 2) & 3;
        let turn = if into == out { 0 } else { t.quarter_turn };
        cost = cost.checked_add(turn + t.edge)?;
        let prev = neighbour_index(bounds, cur, Heading::from_index(other as u8))?;
        match other_arm(map, start, prev, into) {
            Some(o) => (cur, out, other) = (prev, into, o),
            None => {
                let enters = arms_at(map, prev)?.has(Heading::from_index(into as u8));
                return enters.then_some((prev, into, d.checked_sub(cost)?));
            }
        }
    }
    None
}

/// Calls `drive(node, heading, key)` for every state driven into on the
/// corridor way back from state `into` (that one first) to node `entry`
/// (not included), as [`back`] found it, until `drive` says `false`.
pub(super) fn drives_back<M: AsRef<[Block]> + AsMut<[Block]>>(
    map: &KnownMap<M>,
    (bounds, t): (Bounds, Timing),
    (v, h, d): (usize, usize, Ticks),
    entry: usize,
    mut drive: impl FnMut(usize, usize, Ticks) -> bool,
) {
    if !drive(v, h, d) {
        return;
    }
    let back =
        |v: usize, h: usize| neighbour_index(bounds, v, Heading::from_index(((h + 2) & 3) as u8));
    let (mut cur, mut out, mut key) = (back(v, h), h, d.saturating_sub(t.edge));
    for _ in 0..bounds.area() {
        let Some(c) = cur.filter(|&c| c != entry) else {
            return;
        };
        // The start never lies inside a corridor (`back` stops there).
        let Some(other) = other_arm(map, usize::MAX, c, out) else {
            return;
        };
        let into = (other + 2) & 3;
        let turn = if into == out { 0 } else { t.quarter_turn };
        let arrival = key.saturating_sub(turn);
        if !drive(c, into, arrival) {
            return;
        }
        (cur, out, key) = (back(c, into), into, arrival.saturating_sub(t.edge));
    }
}
