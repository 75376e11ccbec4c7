//! Turn-aware distance fields and A* over the known map.
//!
//! A robot's time is spent driving edges *and turning on nodes*: a U-turn
//! costs almost an edge. So the planner searches (node, heading) states: a
//! quarter turn costs [`Timing::quarter_turn`], driving on along the current
//! heading costs [`Timing::edge`], and a path is only as cheap as the robot
//! can actually drive it.
//!
//! ## Why two FIFO queues and no heap
//!
//! With only two move costs, Dijkstra needs no priority queue: every move of
//! one kind adds the same constant to a key that is popped in non-decreasing
//! order, so the entries of one kind arrive in a FIFO already sorted. Popping
//! the smaller head of the two FIFOs is exact Dijkstra in O(1) per
//! operation (a two-bucket form of Dial's algorithm).
//!
//! ## Memory: 16 bytes per node, caller-provided
//!
//! One [`PlanCell`] per node of the map window: the node's distance (the
//! cheapest over its four headings, 28 bits, plus four "settled" bits), one
//! byte per heading for that heading's extra cost over the node's distance
//! (at most a U-turn, so a byte suffices: see
//! [`MAX_TURN_TICKS`](crate::timing::MAX_TURN_TICKS)), and one slot in each
//! of the two FIFOs. Keys are never stored: a queue entry names the settled
//! state it came from, whose distance is final.
//!
//! ## What is passable
//!
//! A node whose arms are known (visited, or deduced from four visited
//! neighbours) can be driven through. A frontier node can be reached, along
//! a known arm of a neighbour, but never driven through: nobody knows where
//! its arms go.

use crate::geometry::{Arms, Heading, Pos};
use crate::map::{Block, Bounds, KnownMap};
use crate::timing::{Ticks, Timing};
use core::fmt;

const DIST_MASK: u32 = 0x0FFF_FFFF;
const SETTLED_SHIFT: u32 = 28;
const NO_OFF: u8 = u8::MAX;
/// A node on the marked way (see [`DistField::mark_way`]): the top bit of a
/// cell's second ring slot, which a queue entry (below 8 × area < 2^31)
/// never sets.
const ON_WAY: u32 = 1 << 31;

/// The largest distance a field holds (about 31 days at 10 ms ticks);
/// farther states are left unreached.
pub const MAX_DIST: Ticks = DIST_MASK - 1;

/// The planner's scratch for one node: 16 bytes. See the module docs.
#[derive(Clone, Copy, Debug)]
pub struct PlanCell {
    base: u32,
    off: [u8; 4],
    ring_a: u32,
    ring_b: u32,
}

impl PlanCell {
    /// A cell that nothing has reached.
    pub const EMPTY: PlanCell = PlanCell {
        base: DIST_MASK,
        off: [NO_OFF; 4],
        ring_a: 0,
        ring_b: 0,
    };

    /// All bits zero: only a placeholder for `static` storage, which
    /// [`DistField::new`] clears to [`PlanCell::EMPTY`]. A zero initialiser
    /// puts the firmware's planner scratch in `.bss` instead of `.data`,
    /// whose initial image would cost 16 KiB of flash.
    pub const ZEROED: PlanCell = PlanCell {
        base: 0,
        off: [0; 4],
        ring_a: 0,
        ring_b: 0,
    };

    fn dist(&self) -> Option<Ticks> {
        let d = self.base & DIST_MASK;
        (d != DIST_MASK).then_some(d)
    }

    fn settled(&self, h: usize) -> bool {
        self.base & (1 << (SETTLED_SHIFT + h as u32)) != 0
    }

    fn pose_dist(&self, h: usize) -> Option<Ticks> {
        if self.settled(h) {
            Some((self.base & DIST_MASK) + u32::from(*self.off.get(h)?))
        } else {
            None
        }
    }
}

impl Default for PlanCell {
    fn default() -> Self {
        PlanCell::EMPTY
    }
}

/// Why a search could not run. Nothing panics on bad input.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum PlanError {
    /// The start lies outside the map window.
    OutOfBounds(Pos),
    /// The scratch holds fewer cells than the map window has nodes (or the
    /// window is too large to index).
    Capacity {
        /// Cells needed.
        needed: usize,
        /// Cells provided.
        available: usize,
    },
    /// A queue ran out of its share of the scratch. Give the scratch more
    /// cells than the window has nodes (see [`min_cells`]).
    QueueFull,
}

impl fmt::Display for PlanError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PlanError::OutOfBounds(p) => write!(f, "start {p} lies outside the map window"),
            PlanError::Capacity { needed, available } => {
                write!(f, "planner scratch holds {available} cells, needs {needed}")
            }
            PlanError::QueueFull => f.write_str("planner queue full"),
        }
    }
}

/// Where a search settled cells: storage indices `lo..hi`, and no farther
/// than `reach / edge` columns from the start column `sx` (a settled node
/// at distance `d` is at most `d / edge` lattice steps away), in a window
/// `width` wide. The next search clears only that box: rows of a wide map
/// are much longer than a search that stops early is wide, and finding the
/// columns this way costs no division per settled state.
#[derive(Clone, Copy, Debug, Default)]
struct Dirty {
    lo: usize,
    hi: usize,
    reach: Ticks,
    sx: usize,
    edge: Ticks,
    width: usize,
}

impl Dirty {
    /// Nothing settled yet by a search from storage index `s0` with edges
    /// of `edge` ticks in a window `width` wide.
    fn start(s0: usize, width: usize, edge: Ticks) -> Dirty {
        let width = width.max(1);
        Dirty {
            lo: 0,
            hi: 0,
            reach: 0,
            sx: s0 % width,
            edge,
            width,
        }
    }

    /// The whole of a window of `area` nodes, `width` wide (a search whose
    /// costs are not edge times).
    fn all(area: usize, width: usize) -> Dirty {
        Dirty {
            lo: 0,
            hi: area,
            reach: 0,
            sx: 0,
            edge: 0,
            width: width.max(1),
        }
    }

    /// Index `i` settled at distance `key`.
    fn add(&mut self, i: usize, key: Ticks) {
        if self.lo >= self.hi {
            self.lo = i;
            self.hi = i + 1;
        } else {
            self.lo = self.lo.min(i);
            self.hi = self.hi.max(i + 1);
        }
        self.reach = self.reach.max(key);
    }

    /// Calls `f` with the storage range of each row of the box.
    fn for_each_row(self, mut f: impl FnMut(core::ops::Range<usize>)) {
        if self.lo >= self.hi || self.width == 0 {
            return;
        }
        let (x0, x1) = match (self.reach / self.edge.max(1)) as usize {
            _ if self.edge == 0 => (0, self.width),
            r => (
                self.sx.saturating_sub(r),
                self.sx.saturating_add(r + 1).min(self.width),
            ),
        };
        for row in self.lo / self.width..=(self.hi - 1) / self.width {
            let base = row * self.width;
            f(base + x0..base + x1);
        }
    }
}

/// A (node, heading, distance) state of a field.
type State = (usize, usize, Ticks);

/// One drive back along a cheapest path (see `DistField::step_back`).
enum Back {
    /// At the start pose.
    Start,
    /// The path drove into state `into` (after undoing any turns on the
    /// spot) from state `from`.
    Drive { into: State, from: State },
    /// No predecessor: the path is broken (not reached).
    Lost,
}

/// Whether a search goes on after a node is reached.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Flow {
    /// Keep searching.
    Continue,
    /// Stop now: everything reached so far keeps its final distance.
    Stop,
}

/// Windows up to this many nodes get scratch enough that the planner's
/// queues can never overflow (see [`min_cells`]).
pub const SMALL_WINDOW: usize = 128;

/// The scratch cells a window of `area` nodes needs.
///
/// Each of the two FIFO rings holds one entry per scratch cell. Over a
/// whole search the edge ring receives at most one entry per (node,
/// heading) state and the turn ring at most two per settled state, so
/// 8 × area cells can never overflow. Small windows get that: their
/// wavefront can be most of the window (cheap edges, dear turns). Larger
/// windows get one cell per node, which holds a wavefront of `area` states,
/// far more than a search at the robots' timing keeps in flight; should it
/// ever fill, the search says [`PlanError::QueueFull`] rather than answer
/// wrongly.
pub const fn min_cells(area: usize) -> usize {
    if area <= SMALL_WINDOW {
        8 * if area < 8 { 8 } else { area }
    } else {
        area
    }
}

/// The storage index of the neighbour of node `i` towards `h` within
/// `bounds`, without converting to a [`Pos`].
pub fn neighbour_index(bounds: Bounds, i: usize, h: Heading) -> Option<usize> {
    let w = usize::from(bounds.width);
    if w == 0 || i >= bounds.area() {
        return None;
    }
    // Windows hold fewer than 2^32 nodes (a u16 square): a 32-bit
    // remainder is exact and much cheaper than a 64-bit one.
    let x = (i as u32) % u32::from(bounds.width);
    match h {
        Heading::North => {
            let j = i + w;
            (j < bounds.area()).then_some(j)
        }
        Heading::South => i.checked_sub(w),
        Heading::East => (x + 1 < u32::from(bounds.width)).then_some(i + 1),
        Heading::West => (x > 0).then(|| i - 1),
    }
}

/// The known arms of node `i`: visited, or deduced from four visited
/// neighbours. `None` for unknown (frontier or unseen) nodes.
pub fn arms_at<M: AsRef<[Block]> + AsMut<[Block]>>(map: &KnownMap<M>, i: usize) -> Option<Arms> {
    map.cell_at(i)?.known_arms()
}

/// `i mod cap` for `i < 2 cap`: ring arithmetic without a division.
#[inline]
fn wrap(i: usize, cap: usize) -> usize {
    if i >= cap { i - cap } else { i }
}

/// The timing a search runs with: no free edges, turns within what a
/// cell's heading offsets hold.
fn searchable(timing: Timing) -> Timing {
    Timing {
        edge: timing.edge.max(1),
        quarter_turn: timing.quarter_turn.clamp(1, crate::timing::MAX_TURN_TICKS),
    }
}

/// Manhattan distance of two storage indices in a window of width `w`.
fn index_manhattan(w: usize, a: usize, b: usize) -> u32 {
    let (ax, ay) = (a % w, a / w);
    let (bx, by) = (b % w, b / w);
    (ax.abs_diff(bx) + ay.abs_diff(by)) as u32
}

/// A distance field over (node, heading) states from one robot pose, or the
/// result of an A* search; see the module docs.
///
/// `S` is the scratch: `[PlanCell; N]` on the robot, a `Vec` or boxed slice
/// on the host. The field stays readable until the next search.
pub struct DistField<S> {
    cells: S,
    /// A box that holds every cell the last search settled: the next
    /// search clears only those. A search that stops early on a large map
    /// touches a small box, and clearing the whole scratch (16 bytes a
    /// node) would cost more than the search itself.
    dirty: Dirty,
    /// The map revision a completed or stopped Dijkstra search ran on
    /// (`None` after A*, whose settled states are not a shortest-path tree
    /// in search order, or after an error).
    tree: Option<u32>,
    queue: Queues,
    bounds: Bounds,
    start: Option<(usize, Heading)>,
    timing: Timing,
    /// The way that is marked, and the map revision it was marked on (see
    /// [`DistField::mark_way`] and [`DistField::mark_descent`]).
    way: Option<(Marked, u32)>,
    /// The goal of a completed [`DistField::compute_reverse`], and the map
    /// revision it ran on.
    reverse: Option<(usize, u32)>,
    /// The node that [`DistField::passes`] memoises answers for, and the
    /// map revision.
    memo: Option<(usize, u32)>,
}

impl<S: AsRef<[PlanCell]> + AsMut<[PlanCell]>> DistField<S> {
    /// A field over `storage`, with nothing reached.
    pub fn new(mut storage: S) -> Self {
        storage.as_mut().fill(PlanCell::EMPTY);
        DistField {
            cells: storage,
            dirty: Dirty::default(),
            tree: None,
            queue: Queues::default(),
            bounds: Bounds::new(Pos::new(0, 0), 0, 0),
            start: None,
            timing: Timing::DEFAULT,
            way: None,
            memo: None,
            reverse: None,
        }
    }

    /// The window of the last search.
    pub fn bounds(&self) -> Bounds {
        self.bounds
    }

    /// The start pose of the last search, as (storage index, heading).
    pub fn start(&self) -> Option<(usize, Heading)> {
        self.start
    }

    /// The timing of the last search.
    pub fn timing(&self) -> Timing {
        self.timing
    }

    /// The cheapest time to reach node `i` with any heading, if reached.
    pub fn dist_at(&self, i: usize) -> Option<Ticks> {
        if i >= self.bounds.area() {
            return None;
        }
        self.cells.as_ref().get(i)?.dist()
    }

    /// The cheapest time to reach `p` with any heading, if reached.
    pub fn dist(&self, p: Pos) -> Option<Ticks> {
        self.dist_at(self.bounds.index(p)?)
    }

    /// The cheapest time to stand on `p` facing `h`, if that state was
    /// settled.
    pub fn dist_pose(&self, p: Pos, h: Heading) -> Option<Ticks> {
        let i = self.bounds.index(p)?;
        self.cells
            .as_ref()
            .get(i)?
            .pose_dist(usize::from(h.index()))
    }

    fn prepare<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        timing: Timing,
        start: Pos,
        heading: Heading,
    ) -> Result<usize, PlanError> {
        let bounds = map.bounds();
        let area = bounds.area();
        let available = self.cells.as_ref().len();
        if available < min_cells(area) || area >= 1 << 28 {
            return Err(PlanError::Capacity {
                needed: min_cells(area),
                available,
            });
        }
        let s0 = bounds.index(start).ok_or(PlanError::OutOfBounds(start))?;
        let cells = self.cells.as_mut();
        // Marks and memos live on settled cells only, so this clears them too.
        core::mem::take(&mut self.dirty).for_each_row(|r| {
            if let Some(row) = cells.get_mut(r) {
                row.fill(PlanCell::EMPTY);
            }
        });
        self.way = None;
        self.memo = None;
        self.reverse = None;
        self.bounds = bounds;
        self.queue = Queues::default();
        self.start = Some((s0, heading));
        self.timing = searchable(timing);
        self.dirty = Dirty::start(s0, usize::from(bounds.width), self.timing.edge);
        Ok(s0)
    }

    /// Settles state (`i`, `h`) at `key`; returns whether it was the node's
    /// first settled state (then `key` is the node's distance), or `None` if
    /// the state was settled already.
    fn settle(&mut self, i: usize, h: usize, key: Ticks) -> Option<bool> {
        let c = self.cells.as_mut().get_mut(i)?;
        if c.settled(h) {
            return None;
        }
        self.dirty.add(i, key);
        let first = match c.dist() {
            None => {
                c.base = key & DIST_MASK;
                true
            }
            Some(_) => false,
        };
        let mut base = c.base & DIST_MASK;
        if key < base {
            // Only A* with a heuristic that differs between a node's
            // headings (`astar_by_landmark`) settles a cheaper heading
            // after a dearer one: the node's distance moves down to it and
            // the settled offsets up (still within a U-turn, so within a
            // byte). Tentative offsets of unsettled headings only spare
            // A* duplicate heap entries; they are dropped.
            let shift = base - key;
            for (k, o) in c.off.iter_mut().enumerate() {
                *o = if c.base & (1 << (SETTLED_SHIFT + k as u32)) != 0 {
                    (u32::from(*o) + shift).min(u32::from(NO_OFF - 1)) as u8
                } else {
                    NO_OFF
                };
            }
            c.base = (c.base & !DIST_MASK) | key;
            base = key;
        }
        let off = key.saturating_sub(base).min(u32::from(NO_OFF - 1)) as u8;
        if let Some(o) = c.off.get_mut(h) {
            *o = off;
        }
        c.base |= 1 << (SETTLED_SHIFT + h as u32);
        Some(first)
    }

    /// Computes the field from the pose (`start`, `heading`) over `map`,
    /// calling `reached(i, dist)` once for every node `i` when its distance
    /// becomes final, nearest first (ties: queue order, deterministic). Stop
    /// early by returning [`Flow::Stop`].
    pub fn compute<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        timing: Timing,
        start: Pos,
        heading: Heading,
        mut reached: impl FnMut(usize, Ticks) -> Flow,
    ) -> Result<(), PlanError> {
        self.tree = None;
        let s0 = self.prepare(map, timing, start, heading)?;
        let h0 = usize::from(heading.index());
        self.queue = Queues::default();
        self.settle(s0, h0, 0);
        self.queue.pending = Some((s0, h0, 0));
        if reached(s0, 0) == Flow::Stop {
            self.tree = Some(map.revision());
            return Ok(());
        }
        let result = self.resume(map, reached);
        if result.is_ok() {
            self.tree = Some(map.revision());
        }
        result
    }

    /// [`DistField::compute`] grown only until node `goal` is reached (or
    /// the reachable graph is exhausted): most questions about one way (a
    /// team mate's way home, ours to a spot) need no more of the field.
    /// Whether `goal` was reached: [`DistField::dist_at`].
    pub fn compute_to<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        timing: Timing,
        start: Pos,
        heading: Heading,
        goal: usize,
    ) -> Result<(), PlanError> {
        self.compute(map, timing, start, heading, |v, _| {
            if v == goal {
                Flow::Stop
            } else {
                Flow::Continue
            }
        })
    }

    /// The next node, nearest first, for which `wanted(node, dist)` holds:
    /// the search from the pose (`start`, `heading`) begins anew if
    /// `restart`, else it resumes where the last call stopped (over the
    /// same map). `None` once the reachable graph is exhausted. For callers
    /// that must check each candidate against the field itself (does its
    /// way pass a team mate?), which the search's callback cannot: find,
    /// check, go on.
    pub fn next_where<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        timing: Timing,
        (start, heading): (Pos, Heading),
        restart: bool,
        mut wanted: impl FnMut(usize, Ticks) -> bool,
    ) -> Result<Option<usize>, PlanError> {
        let mut found = None;
        let reached = |v: usize, d: Ticks| {
            if wanted(v, d) {
                found = Some(v);
                Flow::Stop
            } else {
                Flow::Continue
            }
        };
        if restart {
            self.compute(map, timing, start, heading, reached)?;
        } else {
            self.resume(map, reached)?;
        }
        Ok(found)
    }

    /// Whether this field is a search by [`DistField::compute`] from the
    /// pose (`start`, `heading`) over `map` as it is now: then it holds the
    /// same shortest-path tree a new search would grow (the search order is
    /// deterministic), as far as it went, and need not be searched again.
    pub fn is_search_from<M: AsRef<[Block]> + AsMut<[Block]>>(
        &self,
        map: &KnownMap<M>,
        timing: Timing,
        start: Pos,
        heading: Heading,
    ) -> bool {
        let bounds = map.bounds();
        self.tree == Some(map.revision())
            && self.bounds == bounds
            && self.start == bounds.index(start).map(|i| (i, heading))
            && self.timing == searchable(timing)
    }

    /// Continues a search that its callback stopped, over the same `map`
    /// (unchanged since): nodes already reported are not reported again.
    /// Lets a caller grow a field only as far as a question needs.
    pub fn resume<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        mut reached: impl FnMut(usize, Ticks) -> Flow,
    ) -> Result<(), PlanError> {
        if self.start.is_none() {
            return Ok(());
        }
        self.run::<M, false>(map, |v, _, key, first| {
            if first {
                reached(v, key)
            } else {
                Flow::Continue
            }
        })
    }

    /// The reverse field of node `goal`: for every (node, heading) state,
    /// the cheapest time from that pose to reach `goal` (with any heading),
    /// over the same moves and costs as [`DistField::compute`]. Calls
    /// `reached(node, heading, time)` for every state as it settles,
    /// cheapest first; stop early with [`Flow::Stop`]. Rooted at a robot's
    /// home on a complete map it never changes again: every way home, the
    /// robot's own and the one team mates predict for it, is read from it
    /// (see the `descent` module).
    ///
    /// Afterwards [`DistField::dist_at`] holds each node's cheapest time
    /// over its headings and, if the search ran to the end,
    /// [`DistField::way_out`] the way from any pose; the field has no
    /// start, so it gives no forward path and cannot be resumed.
    pub fn compute_reverse<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        timing: Timing,
        goal: Pos,
        mut reached: impl FnMut(usize, Heading, Ticks) -> Flow,
    ) -> Result<(), PlanError> {
        self.tree = None;
        let g = self.prepare(map, timing, goal, Heading::North)?;
        let cap = self.cells.as_ref().len();
        let bounds = self.bounds;
        self.queue = Queues::default();
        let mut stop = false;
        for h in 0..4 {
            self.settle(g, h, 0);
        }
        for heading in Heading::ALL {
            let h = usize::from(heading.index());
            // The edges that arrive at the goal heading `h`.
            let from = neighbour_index(bounds, g, heading.opposite());
            if from
                .and_then(|u| arms_at(map, u))
                .is_some_and(|a| a.has(heading))
            {
                let q = &mut self.queue;
                if let Some(c) = self.cells.as_mut().get_mut(wrap(q.a_head + q.a_len, cap)) {
                    c.ring_a = (g * 4 + h) as u32;
                    q.a_len += 1;
                }
            }
            stop = stop || reached(g, heading, 0) == Flow::Stop;
        }
        let result = if stop {
            Ok(())
        } else {
            self.run::<M, true>(map, |v, h, key, _| {
                let flow = reached(v, Heading::from_index(h as u8), key);
                stop |= flow == Flow::Stop;
                flow
            })
        };
        self.start = None;
        self.queue = Queues::default();
        if result.is_ok() && !stop {
            self.reverse = Some((g, map.revision()));
        }
        result
    }

    /// The search loop of [`DistField::resume`] (`REV` false: from the
    /// start) and [`DistField::compute_reverse`] (`REV` true: towards the
    /// goal, each edge driven backwards). `settled(node, heading, key,
    /// first)` sees every settled state; `first` marks the node's first.
    fn run<M: AsRef<[Block]> + AsMut<[Block]>, const REV: bool>(
        &mut self,
        map: &KnownMap<M>,
        mut settled: impl FnMut(usize, usize, Ticks, bool) -> Flow,
    ) -> Result<(), PlanError> {
        // The marks share the ring slots that the queues are about to use.
        self.unmark_way(map);
        if self.memo.take().is_some() {
            self.clear_memo();
        }
        let t = self.timing;
        let bounds = self.bounds;
        let cap = self.cells.as_ref().len();
        let Queues {
            mut a_head,
            mut a_len,
            mut b_head,
            mut b_len,
            mut pending,
        } = self.queue;
        let result = (|| {
            loop {
                if let Some((v, h, d)) = pending.take() {
                    // Expand the settled state (v, h) at distance d.
                    let heading = Heading::from_index(h as u8);
                    // Forward: drive on from v, if v is passable. Reverse:
                    // the state (w, h) one edge back, if w is passable and
                    // has the arm; every node a reverse search settles
                    // (but the goal, whose states are all settled at 0) was
                    // entered that way, so it is passable and may turn.
                    let (drive, arms_ok) = if REV {
                        let w = neighbour_index(bounds, v, heading.opposite());
                        let ok = w
                            .and_then(|w| arms_at(map, w))
                            .is_some_and(|a| a.has(heading));
                        (w, ok)
                    } else {
                        let Some(arms) = arms_at(map, v) else {
                            continue;
                        };
                        (neighbour_index(bounds, v, heading), arms.has(heading))
                    };
                    let cells = self.cells.as_mut();
                    if arms_ok && d + t.edge <= MAX_DIST {
                        if let Some(w) = drive {
                            if !cells.get(w).is_some_and(|c| c.settled(h)) {
                                if a_len == cap {
                                    return Err(PlanError::QueueFull);
                                }
                                if let Some(c) = cells.get_mut(wrap(a_head + a_len, cap)) {
                                    c.ring_a = (v * 4 + h) as u32;
                                }
                                a_len += 1;
                            }
                        }
                    }
                    for (dir, h2) in [(0usize, (h + 1) & 3), (1, (h + 3) & 3)] {
                        let Some(cv) = cells.get_mut(v) else { continue };
                        let off = u32::from(cv.off.get(h).copied().unwrap_or(0)) + t.quarter_turn;
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
                        if b_len == cap {
                            return Err(PlanError::QueueFull);
                        }
                        let entry = ((v * 4 + h) * 2 + dir) as u32;
                        if let Some(c) = cells.get_mut(wrap(b_head + b_len, cap)) {
                            c.ring_b = entry;
                        }
                        b_len += 1;
                    }
                    continue;
                }
                if a_len == 0 && b_len == 0 {
                    return Ok(());
                }
                let cells = self.cells.as_ref();
                let key_of = |state: usize| -> Option<Ticks> {
                    cells.get(state / 4).and_then(|c| c.pose_dist(state % 4))
                };
                let a = if a_len > 0 {
                    cells
                        .get(a_head)
                        .map(|c| c.ring_a as usize)
                        .and_then(|s| Some((s, key_of(s)? + t.edge)))
                } else {
                    None
                };
                let b = if b_len > 0 {
                    cells
                        .get(b_head)
                        .map(|c| c.ring_b as usize)
                        .and_then(|e| Some((e, key_of(e / 2)? + t.quarter_turn)))
                } else {
                    None
                };
                let take_a = match (a, b) {
                    (Some((_, ka)), Some((_, kb))) => ka <= kb,
                    (Some(_), None) => true,
                    (None, Some(_)) => false,
                    (None, None) => {
                        // Corrupt entries: drop them rather than loop forever.
                        a_len = a_len.saturating_sub(1);
                        b_len = b_len.saturating_sub(1);
                        a_head = wrap(a_head + 1, cap);
                        b_head = wrap(b_head + 1, cap);
                        continue;
                    }
                };
                let (v, h, key) = if take_a {
                    a_head = wrap(a_head + 1, cap);
                    a_len -= 1;
                    let Some((s, key)) = a else { continue };
                    let h = s % 4;
                    let toward = Heading::from_index(h as u8);
                    let toward = if REV { toward.opposite() } else { toward };
                    let Some(w) = neighbour_index(bounds, s / 4, toward) else {
                        continue;
                    };
                    (w, h, key)
                } else {
                    b_head = wrap(b_head + 1, cap);
                    b_len -= 1;
                    let Some((e, key)) = b else { continue };
                    let s = e / 2;
                    let h2 = if e % 2 == 0 { (s + 1) & 3 } else { (s + 3) & 3 };
                    (s / 4, h2, key)
                };
                let Some(first) = self.settle(v, h, key) else {
                    continue;
                };
                pending = Some((v, h, key));
                if settled(v, h, key, first) == Flow::Stop {
                    return Ok(());
                }
            }
        })();
        self.queue = Queues {
            a_head,
            a_len,
            b_head,
            b_len,
            pending,
        };
        result
    }

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
    fn walk_back_while<M: AsRef<[Block]> + AsMut<[Block]>>(
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
            }
        }
        false
    }

    /// The state (node, heading, distance) in which the cheapest path to
    /// node `target` ends: its cheapest heading.
    fn last_state(&self, target: usize) -> Option<State> {
        self.start?;
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
        let Some(dv) = self.dist_at(via) else {
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

    /// Marks the cheapest path to node `target`, so that
    /// [`DistField::path_passes`] answers for it in O(1) until the field or
    /// the map changes. Homecoming and retreats ask whether each of many
    /// nodes lies on one team mate's way; walking the way back for every
    /// node cost O(way length) each, and in a large maze, where ways run
    /// hundreds of edges, that was most of a run. One way per field is
    /// marked at a time; the marks live in a bit of the settled cells' ring
    /// slots, which the next search clears. Returns whether `target` was
    /// reached.
    pub fn mark_way<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        target: usize,
    ) -> bool {
        self.mark(map, Marked::Way(target))
    }

    /// Marks `marked` (see [`DistField::mark_way`]) unless it is marked
    /// already; whether its walk reached its end.
    fn mark<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        marked: Marked,
    ) -> bool {
        if self.way == Some((marked, map.revision())) {
            return true;
        }
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
    /// as [`DistField::path_passes`] says, for many `v` and one `via`:
    /// once the search has run to completion its queues are empty, and
    /// each (node, heading) state's answer is memoised in its first ring
    /// slot, so that asking for every node of the map costs O(map) in all
    /// rather than O(way) each. A retreat asks it for every node it might
    /// retreat to (is it behind the bumper's goal, seen from home?); in a
    /// crowded maze the walks were most of the run. A search still in
    /// progress just walks.
    pub fn passes<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        v: usize,
        via: usize,
    ) -> bool {
        let q = &self.queue;
        let complete = q.a_len == 0 && q.b_len == 0 && q.pending.is_none();
        if !complete || self.tree != Some(map.revision()) {
            return self.path_passes(map, v, via);
        }
        if self.memo != Some((via, map.revision())) {
            self.clear_memo();
            self.memo = Some((via, map.revision()));
        }
        let (Some(dv), Some(first)) = (self.dist_at(via), self.last_state(v)) else {
            return false;
        };
        let limit = self.bounds.area().saturating_add(1);
        // Walk back to the answer: `via` driven into, fallen below its
        // distance (it cannot come any more), the start, or a state whose
        // answer is known.
        let mut state = first;
        let mut answer = false;
        for _ in 0..limit {
            if let Some(a) = self.memo_at(state) {
                answer = a;
                break;
            }
            match self.step_back(map, state) {
                Back::Start | Back::Lost => break,
                Back::Drive { into, from } => {
                    if into.0 == via {
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
                Back::Start | Back::Lost => break,
                Back::Drive { into, from } => {
                    if into.0 == via || into.2 < dv {
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
    fn clear_memo(&mut self) {
        let cells = self.cells.as_mut();
        self.dirty.for_each_row(|r| {
            for c in cells.get_mut(r).unwrap_or(&mut []) {
                c.ring_a = 0;
            }
        });
    }

    /// Clears the marks of [`DistField::mark_way`].
    fn unmark_way<M: AsRef<[Block]> + AsMut<[Block]>>(&mut self, map: &KnownMap<M>) {
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
                Back::Lost => return false,
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

/// Where a stopped search stands: the two FIFOs and the settled state
/// still to expand.
#[derive(Clone, Copy, Debug, Default)]
struct Queues {
    a_head: usize,
    a_len: usize,
    b_head: usize,
    b_len: usize,
    pending: Option<(usize, usize, Ticks)>,
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

mod descent;
mod weighted;

/// Which way a field's marks follow.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Marked {
    /// The cheapest path from the start to this node.
    Way(usize),
    /// The descent of a reverse field from this state (node × 4 + heading).
    Descent(usize),
}

#[cfg(test)]
pub(crate) mod tests;
