//! How long the robot takes to do things: the one truth about timing.
//!
//! The planner, the explorer, the node-level world model and the benchmark
//! all cost moves with [`Timing`], so a plan that is cheaper here is faster
//! on the floor. Costs are integer [`Ticks`] of [`TICK_MS`] milliseconds:
//! small integers let the planner use FIFO queues instead of a heap.

/// Motor steps per wheel revolution (e-puck stepper motors).
pub const STEPS_PER_WHEEL_TURN: u32 = 1000;
/// Wheel diameter in micrometres (about 41 mm).
pub const WHEEL_DIAMETER_UM: u32 = 41_000;
/// Distance between the wheels in micrometres (about 53 mm).
pub const AXLE_UM: u32 = 53_000;
/// The default line-following speed in motor steps per second.
pub const DEFAULT_SPEED_STEPS_PER_S: u32 = 600;
/// Motor steps of each wheel for a 90° turn on the spot (measured; the
/// geometric value π·53/4 mm ≈ 323 steps plus slip).
pub const TURN_90_STEPS: u32 = 330;
/// The default distance between two nodes of the field in millimetres. A
/// field parameter: the 2010 fields used 10 cm and more.
pub const DEFAULT_NODE_SPACING_MM: u32 = 100;
/// The length of one tick in milliseconds.
pub const TICK_MS: u32 = 10;
/// The largest quarter-turn cost the planner accepts, in ticks: two quarter
/// turns must fit the planner's one-byte per-heading offsets.
pub const MAX_TURN_TICKS: Ticks = 127;

/// A duration in ticks of [`TICK_MS`] milliseconds.
pub type Ticks = u32;

/// The cost of the two primitive moves, from which every plan is costed: a
/// U-turn is two quarter turns, as the firmware performs it.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Timing {
    /// Driving one edge, from node to node.
    pub edge: Ticks,
    /// Turning 90° on the spot.
    pub quarter_turn: Ticks,
}

impl Default for Timing {
    fn default() -> Self {
        Timing::DEFAULT
    }
}

impl Timing {
    /// The e-puck at its default speed on a field of 100 mm spacing:
    /// 129 ticks per edge, 55 ticks per quarter turn.
    pub const DEFAULT: Timing =
        Timing::from_hardware(DEFAULT_NODE_SPACING_MM, DEFAULT_SPEED_STEPS_PER_S);

    /// The timing for a field with `spacing_mm` between nodes, driving and
    /// turning at `speed` motor steps per second (at least 1). A quarter
    /// turn is capped at [`MAX_TURN_TICKS`]; an edge costs at least a tick.
    pub const fn from_hardware(spacing_mm: u32, speed: u32) -> Timing {
        let speed = if speed == 0 { 1 } else { speed } as u64;
        // Steps per edge = spacing / (π · diameter / steps per turn), with
        // π ≈ 355/113.
        let edge_steps = (spacing_mm as u64 * 1000 * STEPS_PER_WHEEL_TURN as u64 * 113)
            / (355 * WHEEL_DIAMETER_UM as u64);
        let edge_ms = edge_steps * 1000 / speed;
        let turn_ms = TURN_90_STEPS as u64 * 1000 / speed;
        let edge = edge_ms.div_ceil(TICK_MS as u64);
        let turn = turn_ms.div_ceil(TICK_MS as u64);
        Timing {
            edge: if edge == 0 {
                1
            } else if edge > u32::MAX as u64 / 2 {
                u32::MAX / 2
            } else {
                edge as u32
            },
            quarter_turn: if turn > MAX_TURN_TICKS as u64 {
                MAX_TURN_TICKS
            } else {
                turn as u32
            },
        }
    }

    /// The cost of turning by `quarter_turns` clockwise quarter turns
    /// (mod 4): 0, one quarter turn, a U-turn (two), or one (left).
    pub const fn turn(self, quarter_turns: u8) -> Ticks {
        match quarter_turns & 3 {
            0 => 0,
            2 => 2 * self.quarter_turn,
            _ => self.quarter_turn,
        }
    }

    /// Quarter turns needed to go from heading index `from` to `to`: 0, 1
    /// or 2.
    pub const fn quarter_turns_between(from: u8, to: u8) -> u8 {
        match (to + 4 - (from & 3)) & 3 {
            0 => 0,
            2 => 2,
            _ => 1,
        }
    }

    /// `ticks` in seconds, for reports.
    pub fn seconds(ticks: u64) -> f64 {
        ticks as f64 * f64::from(TICK_MS) / 1000.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_timing_matches_the_hardware_numbers() {
        // 100 mm / (π · 41 mm / 1000) ≈ 776 steps ≈ 1.29 s at 600 steps/s.
        assert_eq!(Timing::DEFAULT.edge, 130);
        // 330 steps at 600 steps/s = 550 ms.
        assert_eq!(Timing::DEFAULT.quarter_turn, 55);
        assert_eq!(Timing::DEFAULT.turn(2), 110);
        assert_eq!(Timing::DEFAULT.turn(3), 55);
        assert_eq!(Timing::quarter_turns_between(3, 1), 2);
        assert_eq!(Timing::quarter_turns_between(3, 0), 1);
    }

    #[test]
    fn slow_turns_are_capped() {
        let t = Timing::from_hardware(100, 100);
        assert_eq!(t.quarter_turn, MAX_TURN_TICKS);
        assert!(Timing::from_hardware(0, 0).edge >= 1);
    }
}
