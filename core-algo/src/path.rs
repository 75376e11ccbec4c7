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
pub use ahead::{SearchId, WAY_AHEAD, WayAhead};
use core::fmt;
pub use corridor::JUMP_SLOTS;
pub use exits::CorridorExits;
pub use forest::Forest;
pub use record::{
    Reached, RecordedSearch, SearchKey, SearchMemo, SearchRecorder, SearchState,
    first_read_otherwise, node_mark, reads_same,
};
pub use refresh::way_in;
use scratch::{DIST_MASK, Dirty, NO_OFF, ON_WAY, Queues, SETTLED_SHIFT};
pub use scratch::{MAX_DIST, PlanCell, SMALL_WINDOW, min_cells};

/// Most nodes [`DistField::passes_any`] memoises answers for at once (a
/// team of 16 and a goal); asked about more, it walks.
pub const MAX_VIAS: usize = 17;

/// The nodes a memo of [`DistField::passes_any`] answers for.
type Vias = heapless::Vec<usize, MAX_VIAS>;

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

/// A (node, heading, distance) state of a field.
type State = (usize, usize, Ticks);

/// One drive back along a cheapest path (see `DistField::step_back`).
enum Back {
    /// At the start pose.
    Start,
    /// The path drove into state `into` (after undoing any turns on the
    /// spot) from state `from`.
    Drive { into: State, from: State },
    /// A jumping search's path drove into state `into` through a corridor
    /// from state `from`, at its other end (see `corridor::back`).
    Corridor { into: State, from: State },
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

/// The storage index of the neighbour of node `i` towards `h` within
/// `bounds`, without converting to a [`Pos`].
pub fn neighbour_index(bounds: Bounds, i: usize, h: Heading) -> Option<usize> {
    let w = usize::from(bounds.width);
    if w == 0 || i >= bounds.area() {
        return None;
    }
    // Windows hold fewer than 2^32 nodes (a u16 square): a 32-bit
    // remainder is exact and much cheaper than a 64-bit one, and only a
    // step east or west needs it.
    let x = || (i as u32) % u32::from(bounds.width);
    match h {
        Heading::North => {
            let j = i + w;
            (j < bounds.area()).then_some(j)
        }
        Heading::South => i.checked_sub(w),
        Heading::East => (x() + 1 < u32::from(bounds.width)).then_some(i + 1),
        Heading::West => (x() > 0).then(|| i - 1),
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

/// Moves a node's distance down to `key`, below its settled states.
///
/// Only A* with a heuristic that differs between a node's headings
/// (`astar_by_landmark`) settles a cheaper heading after a dearer one: the
/// node's distance moves down to it and the settled offsets up (still
/// within a U-turn, so within a byte). Tentative offsets of unsettled
/// headings only spare A* duplicate heap entries; they are dropped.
#[cold]
fn lower_base(c: &mut PlanCell, key: Ticks) {
    let shift = (c.base & DIST_MASK).saturating_sub(key);
    for (k, o) in c.off.iter_mut().enumerate() {
        *o = if c.base & (1 << (SETTLED_SHIFT + k as u32)) != 0 {
            (u32::from(*o) + shift).min(u32::from(NO_OFF - 1)) as u8
        } else {
            NO_OFF
        };
    }
    c.base = (c.base & !DIST_MASK) | key;
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
    /// A diamond round the start that holds every cell the last search
    /// settled: the next search clears only those. A search that stops
    /// early on a large map touches a small diamond, and clearing the
    /// whole scratch (16 bytes a node) would cost more than the search
    /// itself.
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
    /// The goal of the last [`DistField::compute_reverse`], stopped or
    /// completed, and the map revision its settled states hold for: it can
    /// be refreshed and resumed (see `refresh`).
    rev_open: Option<(usize, u32)>,
    /// The nodes that [`DistField::passes_any`] memoises answers for, and
    /// the map revision.
    memo: Option<(Vias, u32)>,
    /// Whether a [`DistField::compute_weighted`] search stands in the
    /// scratch, whose cells mean something else (see `weighted`).
    weighted: bool,
    /// Whether the search jumps along corridors (see `corridor`): it
    /// holds no corridor states, so its ways are read through corridors
    /// (`way`), and it keeps no marks or memos.
    jumping: bool,
    /// Jump arrivals not settled yet.
    jumps: corridor::Jumps,
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
            rev_open: None,
            weighted: false,
            jumping: false,
            jumps: corridor::Jumps::default(),
        }
    }

    /// How many cells the scratch holds: a field can only stand in for
    /// one of the same size.
    pub fn capacity(&self) -> usize {
        self.cells.as_ref().len()
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

    /// [`DistField::dist_pose`] of node `i` (storage index).
    pub fn dist_pose_at(&self, i: usize, h: Heading) -> Option<Ticks> {
        if i >= self.bounds.area() {
            return None;
        }
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
        self.rev_open = None;
        self.weighted = false;
        self.jumping = false;
        self.jumps.reset(s0);
        self.bounds = bounds;
        self.queue = Queues::default();
        self.start = Some((s0, heading));
        self.timing = searchable(timing);
        self.dirty = Dirty::start(s0, usize::from(bounds.width), self.timing.edge);
        Ok(s0)
    }

    /// Settles state (`i`, `h`) at `key`; see `search::settle_in`.
    #[inline]
    fn settle(&mut self, i: usize, h: usize, key: Ticks) -> Option<bool> {
        search::settle_in(self.cells.as_mut(), &mut self.dirty, i, h, key)
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
        reached: impl FnMut(usize, Ticks) -> Flow,
    ) -> Result<(), PlanError> {
        self.compute_kept(map, timing, (start, heading, false), reached)
    }

    /// [`DistField::compute`] for callers that ask only distances of nodes
    /// outside corridors (frontier nodes, junctions, dead ends). It jumps
    /// along corridors and settles none of their states (see `corridor`),
    /// so a corridor node is not reached, or, when the jump heap was full,
    /// may be reached dearer than it is. Every other node is reported
    /// cheapest first with the distance a plain search gives it (nodes at
    /// the same distance may come in another order), and ways are read
    /// back through corridors as a plain search gives them, unless
    /// [`DistField::holds_ways`] says otherwise. [`DistField::resume`]
    /// goes on jumping.
    pub fn compute_jumping<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        timing: Timing,
        start: Pos,
        heading: Heading,
        reached: impl FnMut(usize, Ticks) -> Flow,
    ) -> Result<(), PlanError> {
        self.compute_kept(map, timing, (start, heading, true), reached)
    }

    /// [`DistField::compute`] or, `jumping`, [`DistField::compute_jumping`]:
    /// a search from the start that the map's revision vouches for
    /// afterwards (see [`DistField::is_distance_search_from`]).
    fn compute_kept<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        timing: Timing,
        pose: (Pos, Heading, bool),
        reached: impl FnMut(usize, Ticks) -> Flow,
    ) -> Result<(), PlanError> {
        self.compute_kept_reading(map, timing, pose, (reached, |_| {}))
    }

    /// [`DistField::compute_kept`] telling `read` every node a jumping
    /// search's walks read (see `record`).
    pub(super) fn compute_kept_reading<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        timing: Timing,
        pose: (Pos, Heading, bool),
        (reached, read): (impl FnMut(usize, Ticks) -> Flow, impl FnMut(usize)),
    ) -> Result<(), PlanError> {
        self.tree = None;
        let result = self.search_from(map, timing, pose, (|_| true, read), reached);
        if result.is_ok() {
            self.tree = Some(map.revision());
        }
        result
    }

    /// The forward search of [`DistField::compute`] and
    /// [`DistField::compute_avoiding`] (and, `jumping`, of
    /// [`DistField::compute_jumping`]): drives on only from the start and
    /// from nodes for which `passable` holds, and tells `read` every node
    /// its corridor walks read (see `corridor::walk`).
    fn search_from<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        timing: Timing,
        (start, heading, jumping): (Pos, Heading, bool),
        (passable, read): (impl Fn(usize) -> bool, impl FnMut(usize)),
        mut reached: impl FnMut(usize, Ticks) -> Flow,
    ) -> Result<(), PlanError> {
        let s0 = self.prepare(map, timing, start, heading)?;
        self.jumping = jumping;
        let h0 = usize::from(heading.index());
        self.settle(s0, h0, 0);
        self.queue.pending = Some((s0, h0, 0));
        if reached(s0, 0) == Flow::Stop {
            return Ok(());
        }
        self.run_forward(map, (|v| v == s0 || passable(v), read), reached)
    }

    /// [`DistField::run`] from the start, reporting each node once, when
    /// its first state settles.
    fn run_forward<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        (passable, read): (impl Fn(usize) -> bool, impl FnMut(usize)),
        mut reached: impl FnMut(usize, Ticks) -> Flow,
    ) -> Result<(), PlanError> {
        let settled = |v, _, key, first| {
            if first {
                reached(v, key)
            } else {
                Flow::Continue
            }
        };
        if self.jumping {
            self.run_jumping::<M, false>(map, (passable, read), settled)
        } else {
            self.run::<M, false>(map, passable, settled)
        }
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
        !self.jumping && self.is_distance_search_from(map, timing, start, heading)
    }

    /// Whether ways can be read from this field: not from a jumping search
    /// that went into a corridor plain (its heap full), whose corridor
    /// nodes may hold states dearer than they are.
    pub fn holds_ways(&self) -> bool {
        !(self.jumping && self.jumps.spilled())
    }

    /// Whether this field is a search by [`DistField::compute`] or
    /// [`DistField::compute_jumping`] from the pose (`start`, `heading`)
    /// over `map` as it is now: the distances it settled hold (a jumping
    /// search's outside corridors).
    pub fn is_distance_search_from<M: AsRef<[Block]> + AsMut<[Block]>>(
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

    /// [`DistField::is_search_from`] for a search that ran
    /// to the end (nothing left in its queues): the whole field, which a
    /// caller that needs all of it need not search again. A retreat asks
    /// it of its search from home, the same on a complete map at every
    /// retreat (maze 256², 16 robots: 3 % of the run).
    pub fn is_complete_search_from<M: AsRef<[Block]> + AsMut<[Block]>>(
        &self,
        map: &KnownMap<M>,
        timing: Timing,
        start: Pos,
        heading: Heading,
    ) -> bool {
        self.is_search_from(map, timing, start, heading) && self.queue.ran_out()
    }

    /// Continues a search that its callback stopped, over the same `map`
    /// (unchanged since): nodes already reported are not reported again.
    /// Lets a caller grow a field only as far as a question needs.
    pub fn resume<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        reached: impl FnMut(usize, Ticks) -> Flow,
    ) -> Result<(), PlanError> {
        if self.start.is_none() {
            return Ok(());
        }
        self.run_forward(map, (|_| true, |_| {}), reached)
    }

    /// [`DistField::compute`] that never drives through the nodes `avoid`
    /// names: they are reached, as frontier nodes are, but not passed (the
    /// start may always be left). It answers "which nodes can be reached
    /// without passing these?", which one cheapest path cannot: the
    /// cheapest way may pass such a node where a dearer one does not.
    /// Afterwards the field answers distances only ([`DistField::dist_at`]):
    /// a way read back could step through an avoided node where its
    /// distance ties, so the field keeps no start to read ways from, and it
    /// is neither resumed nor reused as a plain search.
    pub fn compute_avoiding<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        timing: Timing,
        pose: (Pos, Heading),
        avoid: impl Fn(usize) -> bool,
        reached: impl FnMut(usize, Ticks) -> Flow,
    ) -> Result<(), PlanError> {
        self.tree = None;
        let walk = (|v| !avoid(v), |_| {});
        let result = self.search_from(map, timing, (pose.0, pose.1, false), walk, reached);
        // A resume would go on without `avoid`.
        self.queue = Queues::default();
        self.start = None;
        result
    }
}

mod ahead;
mod astar;
mod copy;
mod corridor;
mod descent;
mod exits;
mod forest;
mod record;
mod refresh;
mod reverse;
mod scratch;
mod search;
mod way;
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
