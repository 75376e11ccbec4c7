//! Border following (seed §4.3): the walk rule and the turn count.
//!
//! The walk keeps the line network on its right hand: on each node it
//! takes the first arm of left, straight on, right, back. This traces the
//! face of the line graph lying to the robot's left, the outer border
//! clockwise. Counting each left turn +1, each right turn −1 and a U-turn
//! −2, a closed walk sums to **−4 on the outer border** and **+4 around an
//! inner face** (a hole, or a single grid cell): the seed's numbers.

use crate::geometry::{Arms, Heading, Pos, Turn};

/// The walk's choice on a node reached heading `arrival` with arms `open`:
/// the heading to leave by and its turn count. `None` on a node without
/// arms.
pub fn left_first(arrival: Heading, open: Arms) -> Option<(Heading, i8)> {
    [
        (arrival.turned(Turn::Left), 1),
        (arrival, 0),
        (arrival.turned(Turn::Right), -1),
        (arrival.opposite(), -2),
    ]
    .into_iter()
    .find(|(h, _)| open.has(*h))
}

/// Whether `a` lies further north than `b` (ties: further west): the
/// order that picks the topmost node of an inner face.
pub fn higher(a: Pos, b: Pos) -> bool {
    a.y > b.y || (a.y == b.y && a.x < b.x)
}

/// Tracing one face: where it began and what it has counted.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Trace {
    /// The node the trace began on.
    pub start: Pos,
    /// The heading it left `start` by.
    pub first: Heading,
    /// Turns counted so far (left +1, right −1, back −2).
    pub sum: i16,
    /// The topmost node seen on the face.
    pub top: Pos,
    /// Whether it has left `start` yet.
    pub moved: bool,
    /// The turn count of the departure under way (taken back if a robot
    /// turns the robot back).
    pub pending: i8,
}

impl Trace {
    /// A trace about to leave `start` by `first`.
    pub fn new(start: Pos, first: Heading) -> Self {
        Trace {
            start,
            first,
            sum: 0,
            top: start,
            moved: false,
            pending: 0,
        }
    }

    /// Whether leaving `at` by `by` closes the trace.
    pub fn closes(&self, at: Pos, by: Heading) -> bool {
        self.moved && at == self.start && by == self.first
    }
}
