//! Layer 1: the initial 360° scan of the start node.
//!
//! On [`super::Command::Scan`] (queued by the movement layer as a mode
//! change) the robot turns once clockwise on the spot while
//! [`Scan`] records the arms, then turns back by the measured misalignment
//! so that it faces along the grid, reports the node, and — when there is an
//! arm ahead — centres on it.

use super::{Act, Context, Event, Layer, Mode, approach_speed};
use crate::control::scan::Scan;
use crate::control::{BLACK_BELOW, Wheels};
use crate::geometry::Heading;

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Phase {
    Sweeping,
    Aligning { by: i32 },
}

/// The initial-scan layer.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct InitialLayer {
    scan: Scan,
    phase: Phase,
    epoch: u32,
    full_turn: i32,
    tolerance: i32,
    arms: crate::geometry::Arms,
}

impl InitialLayer {
    /// A layer for a robot with `full_turn` steps per revolution.
    pub const fn new(full_turn: i32, tolerance: i32) -> InitialLayer {
        InitialLayer {
            scan: Scan::new(full_turn, tolerance),
            phase: Phase::Sweeping,
            epoch: u32::MAX,
            full_turn,
            tolerance,
            arms: crate::geometry::Arms::NONE,
        }
    }
}

impl Layer for InitialLayer {
    fn act(&mut self, ctx: &mut Context<'_>) -> Option<Act> {
        if ctx.state.mode != Mode::Scanning {
            return None;
        }
        let floor = ctx.floor?;
        if self.epoch != ctx.state.epoch {
            *self = InitialLayer::new(self.full_turn, self.tolerance);
            self.epoch = ctx.state.epoch;
        }
        let steps = ctx.sensors.steps;
        let rotation = steps.rotated_since(ctx.state.mode_start);
        let speed = ctx.state.speed;
        match self.phase {
            Phase::Sweeping => {
                self.scan.update(floor.centre < BLACK_BELOW, rotation);
                let v = approach_speed(self.full_turn - rotation, speed);
                if v > 0 {
                    return Some(Act::drive(Wheels { left: v, right: -v }));
                }
                match self.scan.finish(rotation) {
                    Ok(result) => {
                        self.arms = result.arms;
                        self.phase = Phase::Aligning {
                            by: self.full_turn + result.misalignment,
                        };
                        Some(Act::drive(Wheels::STOP))
                    }
                    Err(e) => {
                        ctx.state.enter(Mode::Ready, steps);
                        Some(Act::stop_with(Event::ScanFailed(e)))
                    }
                }
            }
            Phase::Aligning { by } => {
                let remaining = by - rotation;
                let v = approach_speed(remaining.abs(), speed);
                if v > 0 {
                    let v = if remaining > 0 { v } else { -v };
                    return Some(Act::drive(Wheels { left: v, right: -v }));
                }
                let next = if self.arms.has(Heading::North) {
                    Mode::Centring
                } else {
                    Mode::OnNode
                };
                ctx.state.enter(next, steps);
                ctx.state.departed = steps;
                Some(Act::stop_with(Event::StartNode { arms: self.arms }))
            }
        }
    }
}
