//! The known map: what one participant has learnt of the field so far.
//!
//! Each robot keeps its own copy (the seed's decentralised maps), so the map
//! must fit a robot's RAM and update in constant time per report. It covers a
//! rectangular window of the lattice ([`Bounds`]) over caller-provided
//! storage: a fixed array of [`Block`]s on the robot, a boxed slice on the
//! host. No allocation happens here.
//!
//! ## The frontier
//!
//! A node is a *frontier* node (the seed's "unknown node") when it is not
//! visited, a visited neighbour has a known arm into it, and fewer than four
//! of its lattice neighbours are visited. An unvisited node with four visited
//! neighbours is *deduced*: its arms follow from theirs, so nobody needs to
//! drive there. Every cell counts its visited neighbours and the known arms
//! pointing into it, so a visit updates the frontier membership of at most
//! five cells and never rescans the map.
//!
//! ## Memory
//!
//! A node costs 4 bytes of [`NodeCell`] plus one frontier bit, kept as one
//! `u32` per 32-node [`Block`]: 4.125 bytes per node. A 1024-node window
//! takes 4 224 bytes, plus about 270 bytes for the log of the last 32
//! nodes that became passable ([`KnownMap::passable_since`]) and about
//! 220 bytes for its fingerprint and the last eight ([`KnownMap::print`]),
//! and 256 bytes for an index of the blocks that hold frontier nodes, so
//! that reading the frontier of a large map skips the empty blocks.

use crate::geometry::{Arms, Heading, Pos};
use crate::team::RobotId;
use core::fmt;

mod cell;
mod changes;
mod frontier_index;
mod print;
use cell::{ARMS_MASK, INTO_SHIFT, VISITED, is_deduced};
pub use cell::{BLOCK_NODES, Block, NodeCell, blocks_for};
use changes::Changes;
use frontier_index::FrontierIndex;
pub use print::MapPrint;
use print::Prints;

/// The rectangle of the lattice a map covers: `width` × `height` nodes from
/// `origin` (its south-west corner).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Bounds {
    /// South-west corner.
    pub origin: Pos,
    /// Nodes along x.
    pub width: u16,
    /// Nodes along y.
    pub height: u16,
}

impl Bounds {
    /// The window of `width` × `height` nodes from `origin`.
    pub const fn new(origin: Pos, width: u16, height: u16) -> Self {
        Bounds {
            origin,
            width,
            height,
        }
    }

    /// Number of nodes in the window.
    pub const fn area(self) -> usize {
        self.width as usize * self.height as usize
    }

    /// The storage index of `p`, if the window holds it.
    pub fn index(self, p: Pos) -> Option<usize> {
        let dx = i32::from(p.x) - i32::from(self.origin.x);
        let dy = i32::from(p.y) - i32::from(self.origin.y);
        if dx < 0 || dy < 0 || dx >= i32::from(self.width) || dy >= i32::from(self.height) {
            return None;
        }
        // Both are non-negative and below u16::MAX here.
        Some(dy as usize * usize::from(self.width) + dx as usize)
    }

    /// The node at storage index `i` (no range check beyond the arithmetic).
    pub fn pos(self, i: usize) -> Pos {
        let w = usize::from(self.width.max(1));
        let x = i32::from(self.origin.x) + (i % w) as i32;
        let y = i32::from(self.origin.y) + (i / w) as i32;
        Pos::new(x as i16, y as i16)
    }

    /// Whether the window holds `p`.
    pub fn contains(self, p: Pos) -> bool {
        self.index(p).is_some()
    }
}

/// Two reports disagree about a node's arms.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Conflict {
    /// The node.
    pub pos: Pos,
    /// The arms the map already implies, on the headings in `determined`.
    pub expected: Arms,
    /// The headings the map already determines (all four for a visited
    /// node; those towards visited neighbours for a new one).
    pub determined: Arms,
    /// The arms of the rejected report.
    pub reported: Arms,
}

impl fmt::Display for Conflict {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "node {} reported with arms {} but the map implies {} on {}",
            self.pos, self.reported, self.expected, self.determined
        )
    }
}

/// Why the map refused an operation. A refused operation changes nothing.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum MapError {
    /// The node lies outside the map's [`Bounds`].
    OutOfBounds(Pos),
    /// The report contradicts what the map knows.
    Conflict(Conflict),
    /// The storage holds fewer nodes than the bounds cover.
    Capacity {
        /// Nodes the bounds cover.
        needed: usize,
        /// Nodes the storage holds.
        available: usize,
    },
}

impl fmt::Display for MapError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MapError::OutOfBounds(p) => write!(f, "node {p} lies outside the map window"),
            MapError::Conflict(c) => write!(f, "conflict: {c}"),
            MapError::Capacity { needed, available } => {
                write!(
                    f,
                    "map storage holds {available} nodes, bounds need {needed}"
                )
            }
        }
    }
}

/// What a successful [`KnownMap::visit`] changed.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct Visit {
    /// The node was not visited before.
    pub first: bool,
    /// The node was a frontier node before.
    pub was_frontier: bool,
    /// An arm of the node leads out of the map window: the map cannot hold
    /// the node behind it, so exploration there is impossible.
    pub arm_leaves_bounds: bool,
}

/// The outcome of [`KnownMap::merge_map`].
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct MergeSummary {
    /// Nodes that were new to this map.
    pub added: u32,
    /// Nodes whose reports conflicted and were not taken.
    pub conflicts: u32,
    /// The first conflict, for the log.
    pub first_conflict: Option<Conflict>,
    /// Nodes of the other map outside this map's window.
    pub out_of_bounds: u32,
}

/// One participant's knowledge of the field; see the module docs.
///
/// `S` is the storage, any owned slice of [`Block`]s: `[Block; N]` on the
/// robot, `Box<[Block]>` or `Vec<Block>` on the host.
#[derive(Clone)]
pub struct KnownMap<S> {
    blocks: S,
    bounds: Bounds,
    visited: u32,
    /// Visited nodes with exactly two arms (see
    /// [`KnownMap::two_armed_len`]).
    two_armed: u32,
    frontier: u32,
    /// Which blocks hold frontier nodes (see [`FrontierIndex`]).
    frontier_blocks: FrontierIndex,
    deduced: u32,
    revision: u32,
    /// The largest x + y, x − y, −x + y and −x − y of the visited nodes:
    /// the farthest visited node from any point, in O(1).
    diagonals: Option<[i32; 4]>,
    /// The nodes that became passable lately (see
    /// [`KnownMap::passable_since`]).
    changes: Changes,
    /// See [`KnownMap::print`].
    print: MapPrint,
    /// The last prints, by revision (see [`KnownMap::revision_of`]).
    prints: Prints,
}

impl<S: AsRef<[Block]> + AsMut<[Block]>> KnownMap<S> {
    /// An empty map over `storage`, covering `bounds`. Clears the storage.
    pub fn new(mut storage: S, bounds: Bounds) -> Result<Self, MapError> {
        let available = storage.as_ref().len() * BLOCK_NODES;
        if available < bounds.area() {
            return Err(MapError::Capacity {
                needed: bounds.area(),
                available,
            });
        }
        storage.as_mut().fill(Block::EMPTY);
        let frontier_blocks = FrontierIndex::new(storage.as_ref().len());
        Ok(KnownMap {
            blocks: storage,
            bounds,
            visited: 0,
            two_armed: 0,
            frontier: 0,
            frontier_blocks,
            deduced: 0,
            diagonals: None,
            revision: 0,
            changes: Changes::new(0),
            print: MapPrint::default(),
            prints: Prints::new(0, MapPrint::default()),
        })
    }

    /// Forgets everything, keeping the window.
    pub fn clear(&mut self) {
        self.blocks.as_mut().fill(Block::EMPTY);
        self.visited = 0;
        self.two_armed = 0;
        self.frontier = 0;
        self.frontier_blocks.clear();
        self.deduced = 0;
        self.diagonals = None;
        self.revision = self.revision.wrapping_add(1);
        self.changes = Changes::new(self.revision);
        self.print = MapPrint::default();
        self.prints = Prints::new(self.revision, self.print);
    }

    /// The Manhattan distance from `from` to the farthest visited node
    /// (`None` before any visit); frontier nodes lie at most one step
    /// farther. A planner bounds how far from a robot's home any frontier
    /// node can be without searching for it.
    pub fn farthest_visited(&self, from: Pos) -> Option<u32> {
        let (x, y) = (i32::from(from.x), i32::from(from.y));
        let d = self.diagonals?;
        let far = [
            d[0] - (x + y),
            d[1] - (x - y),
            d[2] - (-x + y),
            d[3] - (-x - y),
        ];
        Some(far.into_iter().max().unwrap_or(0).max(0) as u32)
    }

    /// Changes whenever the known graph does (a node visited for the first
    /// time, unless it was deduced, or the map cleared): a planner may reuse
    /// a field computed at the same revision instead of searching again.
    pub fn revision(&self) -> u32 {
        self.revision
    }

    /// The nodes whose arms became known (visited, or deduced from four
    /// visited neighbours) after revision `since`; `None` when that is too
    /// long ago to tell. The known graph only ever gains such nodes, so a
    /// planner can check whether a search of an older revision still holds
    /// instead of searching again (see `DistField::refresh_reverse`).
    pub fn passable_since(&self, since: u32) -> Option<impl Iterator<Item = usize> + '_> {
        self.changes.since(since, self.revision)
    }

    /// A fingerprint of everything this map knows (see [`MapPrint`]): two
    /// maps of one window with the same print read the same at every node.
    pub fn print(&self) -> MapPrint {
        self.print
    }

    /// The revision this map had when its print was `print`, if that was
    /// lately: a search another map's planner kept for that print holds
    /// for this map at that revision, and can be carried over from there
    /// (see [`KnownMap::passable_since`]).
    pub fn revision_of(&self, print: MapPrint) -> Option<u32> {
        self.prints.revision_of(print)
    }

    /// The window this map covers.
    pub fn bounds(&self) -> Bounds {
        self.bounds
    }

    /// Number of visited nodes.
    pub fn visited_len(&self) -> usize {
        self.visited as usize
    }

    /// Number of visited nodes with exactly two arms: corridor nodes, bends
    /// included. Four in five of a maze's nodes, one in ten of a rooms
    /// field's: a planner chooses by it whether jumping along corridors
    /// pays (see `DistField::compute_jumping`).
    pub fn two_armed_len(&self) -> usize {
        self.two_armed as usize
    }

    /// Number of nodes whose shape is known: visited, or deduced (four
    /// visited neighbours, at least one arm into the node). Kept
    /// incrementally.
    pub fn known_len(&self) -> usize {
        (self.visited + self.deduced) as usize
    }

    /// Number of frontier nodes.
    pub fn frontier_len(&self) -> usize {
        self.frontier as usize
    }

    /// Everything known about `p` (an empty cell outside the window).
    pub fn cell(&self, p: Pos) -> NodeCell {
        self.bounds
            .index(p)
            .and_then(|i| self.cell_at(i))
            .unwrap_or(NodeCell::EMPTY)
    }

    /// The cell at storage index `i`.
    pub fn cell_at(&self, i: usize) -> Option<NodeCell> {
        let block = self.blocks.as_ref().get(i / BLOCK_NODES)?;
        block.cells.get(i % BLOCK_NODES).copied()
    }

    /// Whether `p` has been visited.
    pub fn is_visited(&self, p: Pos) -> bool {
        self.cell(p).is_visited()
    }

    /// Whether `p` is a frontier node.
    pub fn is_frontier(&self, p: Pos) -> bool {
        self.bounds.index(p).is_some_and(|i| self.is_frontier_at(i))
    }

    /// Whether storage index `i` is a frontier node: one bit test.
    pub fn is_frontier_at(&self, i: usize) -> bool {
        self.blocks
            .as_ref()
            .get(i / BLOCK_NODES)
            .is_some_and(|b| b.frontier & (1 << (i % BLOCK_NODES)) != 0)
    }

    /// The arms of `p` if they are known: visited, or deduced from four
    /// visited neighbours.
    pub fn known_arms(&self, p: Pos) -> Option<Arms> {
        self.cell(p).known_arms()
    }

    /// Whether everything reachable is known: no frontier left.
    pub fn is_complete(&self) -> bool {
        self.frontier == 0
    }

    /// Records that `robot` found node `p` with `arms` (its own observation
    /// or another robot's relayed report).
    ///
    /// A report that contradicts the map (a different shape for a visited
    /// node, or an arm missing towards a visited neighbour that has one) is
    /// refused with [`MapError::Conflict`] and changes nothing.
    pub fn visit(&mut self, p: Pos, arms: Arms, robot: RobotId) -> Result<Visit, MapError> {
        self.record(p, arms, robot, 1)
    }

    fn record(
        &mut self,
        p: Pos,
        arms: Arms,
        robot: RobotId,
        visits: u8,
    ) -> Result<Visit, MapError> {
        let i = self.bounds.index(p).ok_or(MapError::OutOfBounds(p))?;
        let cell = self.cell_at(i).ok_or(MapError::OutOfBounds(p))?;
        if let Some(known) = cell.arms() {
            if known != arms {
                return Err(MapError::Conflict(Conflict {
                    pos: p,
                    expected: known,
                    determined: Arms::CROSS,
                    reported: arms,
                }));
            }
            self.update_cell(i, |c| c.visits = c.visits.saturating_add(visits));
            return Ok(Visit::default());
        }
        let (expected, determined) = self.implied_arms(p);
        if arms.bits() & determined.bits() != expected.bits() {
            return Err(MapError::Conflict(Conflict {
                pos: p,
                expected,
                determined,
                reported: arms,
            }));
        }
        let was_frontier = self.is_frontier_at(i);
        let was_deduced = is_deduced(cell);
        if was_deduced {
            self.deduced -= 1;
        }
        self.update_cell(i, |c| {
            c.flags = VISITED | arms.bits();
            c.visits = visits;
            c.first_visitor = robot.0;
        });
        self.visited += 1;
        self.two_armed += u32::from(arms.count() == 2);
        let (x, y) = (i32::from(p.x), i32::from(p.y));
        let here = [x + y, x - y, -x + y, -x - y];
        self.diagonals = Some(match self.diagonals {
            None => here,
            Some(d) => [
                d[0].max(here[0]),
                d[1].max(here[1]),
                d[2].max(here[2]),
                d[3].max(here[3]),
            ],
        });
        // A deduced node's four neighbours are visited and its arms known
        // already, so visiting it changes no search, no frontier and no
        // deduction: the revision stays, and so do fields kept on it (robots
        // driving home through deduced nodes made every team mate search
        // its kept way home again).
        if !was_deduced {
            self.revision = self.revision.wrapping_add(1);
            self.changes.push(self.revision, i);
        }
        self.print = self.print.with(i, arms.bits());
        self.prints.push(self.revision, self.print);
        self.refresh_frontier(i);
        let mut arm_leaves_bounds = false;
        for h in Heading::ALL {
            let Some(j) = p.step(h).and_then(|q| self.bounds.index(q)) else {
                arm_leaves_bounds |= arms.has(h);
                continue;
            };
            let into = u8::from(arms.has(h)) << INTO_SHIFT;
            let before = self.cell_at(j).is_some_and(is_deduced);
            self.update_cell(j, |c| c.counts += 1 + into);
            let now = self.cell_at(j).unwrap_or(NodeCell::EMPTY);
            if !now.is_visited() && now.visited_neighbours() == 4 {
                // Its shape is settled now: its neighbours' arms into it.
                let (deduced, _) = self.implied_arms(self.bounds.pos(j));
                self.update_cell(j, |c| c.flags = deduced.bits() & ARMS_MASK);
            }
            if !before && is_deduced(now) {
                self.deduced += 1;
                self.changes.push(self.revision, j);
            }
            self.refresh_frontier(j);
        }
        Ok(Visit {
            first: true,
            was_frontier,
            arm_leaves_bounds,
        })
    }

    /// Takes every visited node of `other` into this map (a robot that was
    /// offline catches up). Visit counts become the larger of the two.
    /// Conflicting nodes are skipped and counted, never overwritten.
    pub fn merge_map<T: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        other: &KnownMap<T>,
    ) -> MergeSummary {
        let mut summary = MergeSummary::default();
        for (p, cell) in other.visited() {
            let Some(arms) = cell.arms() else { continue };
            let mine = self.cell(p);
            let result = if mine.is_visited() {
                let extra = cell.visits.saturating_sub(mine.visits);
                self.record(p, arms, RobotId(cell.first_visitor), extra)
            } else {
                self.record(p, arms, RobotId(cell.first_visitor), cell.visits.max(1))
            };
            match result {
                Ok(v) if v.first => summary.added += 1,
                Ok(_) => {}
                Err(MapError::Conflict(c)) => {
                    summary.conflicts += 1;
                    summary.first_conflict.get_or_insert(c);
                }
                Err(_) => summary.out_of_bounds += 1,
            }
        }
        summary
    }

    /// The frontier nodes, in storage order (row by row from the south-west).
    /// Reads only the blocks that an index of 2 048 bits marks as holding
    /// frontier nodes, not every block of a large map.
    pub fn frontier(&self) -> impl Iterator<Item = Pos> + '_ {
        let bounds = self.bounds;
        let blocks = self.blocks.as_ref();
        self.frontier_blocks
            .blocks(blocks.len())
            .filter_map(move |bi| blocks.get(bi).map(|b| (bi, b.frontier)))
            // A marked group's other blocks may hold none; skipping them
            // here also kept 64² at its speed (map/frontier_iter).
            .filter(|&(_, f)| f != 0)
            .flat_map(move |(bi, f)| {
                frontier_index::ones(u64::from(f)).map(move |k| bounds.pos(bi * BLOCK_NODES + k))
            })
    }

    /// The visited nodes with their cells, in storage order.
    pub fn visited(&self) -> impl Iterator<Item = (Pos, NodeCell)> + '_ {
        let bounds = self.bounds;
        let area = bounds.area();
        self.blocks
            .as_ref()
            .iter()
            .flat_map(|b| b.cells.iter())
            .take(area)
            .enumerate()
            .filter(|(_, c)| c.is_visited())
            .map(move |(i, c)| (bounds.pos(i), *c))
    }

    /// The arms of `p` implied by its visited neighbours, and on which
    /// headings they are implied.
    fn implied_arms(&self, p: Pos) -> (Arms, Arms) {
        let mut expected = Arms::NONE;
        let mut determined = Arms::NONE;
        for h in Heading::ALL {
            let Some(q) = p.step(h) else { continue };
            if let Some(a) = self.cell(q).arms() {
                determined = determined.with(h);
                if a.has(h.opposite()) {
                    expected = expected.with(h);
                }
            }
        }
        (expected, determined)
    }

    fn update_cell(&mut self, i: usize, f: impl FnOnce(&mut NodeCell)) {
        if let Some(c) = self
            .blocks
            .as_mut()
            .get_mut(i / BLOCK_NODES)
            .and_then(|b| b.cells.get_mut(i % BLOCK_NODES))
        {
            f(c);
        }
    }

    /// Brings the frontier bit of index `i` in line with the rule: O(1).
    fn refresh_frontier(&mut self, i: usize) {
        let Some(cell) = self.cell_at(i) else { return };
        let should = cell.is_frontier_by_rule();
        let Some(block) = self.blocks.as_mut().get_mut(i / BLOCK_NODES) else {
            return;
        };
        let bit = 1u32 << (i % BLOCK_NODES);
        let is = block.frontier & bit != 0;
        let b = i / BLOCK_NODES;
        if should && !is {
            if block.frontier == 0 {
                self.frontier_blocks.set(b);
            }
            block.frontier |= bit;
            self.frontier += 1;
        } else if !should && is {
            block.frontier &= !bit;
            self.frontier -= 1;
            if block.frontier == 0 {
                let blocks = self.blocks.as_ref();
                let holds = |o: usize| blocks.get(o).is_some_and(|x| x.frontier != 0);
                self.frontier_blocks.unset(b, holds);
            }
        }
    }
}

/// A map with its storage inline: `N` blocks of 32 nodes. The firmware's
/// 1024-node map is `ArrayMap<32>`.
pub type ArrayMap<const N: usize> = KnownMap<[Block; N]>;

impl<const N: usize> KnownMap<[Block; N]> {
    /// An empty inline map covering `bounds`.
    pub fn with_bounds(bounds: Bounds) -> Result<Self, MapError> {
        KnownMap::new([Block::EMPTY; N], bounds)
    }
}

#[cfg(test)]
mod tests;
