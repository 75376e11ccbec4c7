//! Who is who in a team of robots.

use core::fmt;

/// A robot's id within its team, 0-based.
///
/// The seed plans teams of up to six; the simulator and the benchmark run
/// larger teams, so the id is a full byte and only [`RobotId::NONE`] is
/// reserved.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug, Default)]
pub struct RobotId(pub u8);

impl RobotId {
    /// The reserved "nobody" value, used where a slot has no robot.
    pub const NONE: RobotId = RobotId(u8::MAX);

    /// The id as an index into per-robot tables.
    pub const fn index(self) -> usize {
        self.0 as usize
    }
}

impl fmt::Display for RobotId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "#{}", self.0)
    }
}
