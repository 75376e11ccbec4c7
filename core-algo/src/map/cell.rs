//! A node's 4 bytes ([`NodeCell`]) and the 32-node [`Block`] that stores
//! them with their frontier bits: see the `map` module docs.

use crate::geometry::Arms;
use crate::team::RobotId;
use core::fmt;

/// Nodes per storage [`Block`].
pub const BLOCK_NODES: usize = 32;

pub(super) const ARMS_MASK: u8 = 0b0000_1111;
pub(super) const VISITED: u8 = 0b0001_0000;
pub(super) const NBR_MASK: u8 = 0b0000_0111;
pub(super) const INTO_SHIFT: u8 = 3;

/// What the map knows about one node, packed into four bytes.
#[derive(Clone, Copy, PartialEq, Eq, Default)]
pub struct NodeCell {
    /// Bits 0..4: arms (when visited); bit 4: visited.
    pub(super) flags: u8,
    /// Visits by any robot, saturating at 255.
    pub(super) visits: u8,
    /// The robot that first reported the node ([`RobotId::NONE`] if none).
    pub(super) first_visitor: u8,
    /// Bits 0..3: visited lattice neighbours (0..=4); bits 3..6: known arms
    /// of visited neighbours that point into this node (0..=4).
    pub(super) counts: u8,
}

impl NodeCell {
    pub(super) const EMPTY: NodeCell = NodeCell {
        flags: 0,
        visits: 0,
        first_visitor: u8::MAX,
        counts: 0,
    };

    /// Whether some robot has reported this node.
    pub const fn is_visited(self) -> bool {
        self.flags & VISITED != 0
    }

    /// The node's arms if it is visited.
    pub const fn arms(self) -> Option<Arms> {
        if self.is_visited() {
            Some(Arms::from_bits(self.flags & ARMS_MASK))
        } else {
            None
        }
    }

    /// The node's arms if they are known: visited, or deduced from four
    /// visited neighbours (stored when the fourth is recorded, so that a
    /// search through a deduced node does not look at its neighbours again).
    pub const fn known_arms(self) -> Option<Arms> {
        if self.is_visited() || self.visited_neighbours() == 4 {
            Some(Arms::from_bits(self.flags & ARMS_MASK))
        } else {
            None
        }
    }

    /// How often robots reported this node (saturates at 255).
    pub const fn visits(self) -> u8 {
        self.visits
    }

    /// The robot that first reported this node.
    pub const fn first_visitor(self) -> Option<RobotId> {
        if self.is_visited() {
            Some(RobotId(self.first_visitor))
        } else {
            None
        }
    }

    /// Visited lattice neighbours, 0..=4.
    pub const fn visited_neighbours(self) -> u8 {
        self.counts & NBR_MASK
    }

    /// Arms of visited neighbours that point into this node, 0..=4.
    pub const fn arms_into(self) -> u8 {
        (self.counts >> INTO_SHIFT) & NBR_MASK
    }

    /// The seed's frontier rule, from this cell alone.
    pub(super) const fn is_frontier_by_rule(self) -> bool {
        !self.is_visited() && self.arms_into() > 0 && self.visited_neighbours() < 4
    }
}

impl fmt::Debug for NodeCell {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("NodeCell")
            .field("arms", &self.arms())
            .field("visits", &self.visits)
            .field("visited_neighbours", &self.visited_neighbours())
            .field("arms_into", &self.arms_into())
            .finish()
    }
}

/// An unvisited node whose shape follows from four visited neighbours, at
/// least one of which has an arm into it (otherwise there is no node).
pub(super) const fn is_deduced(c: NodeCell) -> bool {
    !c.is_visited() && c.visited_neighbours() == 4 && c.arms_into() > 0
}

/// 32 nodes and their frontier bits: the unit of map storage.
#[derive(Clone, Copy, Debug)]
pub struct Block {
    pub(super) cells: [NodeCell; BLOCK_NODES],
    pub(super) frontier: u32,
}

impl Block {
    /// A block with nothing known.
    pub const EMPTY: Block = Block {
        cells: [NodeCell::EMPTY; BLOCK_NODES],
        frontier: 0,
    };

    /// All bits zero: only a placeholder for `static` storage, which
    /// [`KnownMap::new`](super::KnownMap::new) clears to [`Block::EMPTY`]. A zero initialiser puts
    /// the firmware's map in `.bss` instead of `.data`, whose initial image
    /// would cost as much flash as the map's RAM.
    pub const ZEROED: Block = Block {
        cells: [NodeCell {
            flags: 0,
            visits: 0,
            first_visitor: 0,
            counts: 0,
        }; BLOCK_NODES],
        frontier: 0,
    };
}

impl Default for Block {
    fn default() -> Self {
        Block::EMPTY
    }
}

/// Blocks needed to hold `nodes` nodes.
pub const fn blocks_for(nodes: usize) -> usize {
    nodes.div_ceil(BLOCK_NODES)
}
