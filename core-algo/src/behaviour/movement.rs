//! Layer 5: movement — the phone's orders.
//!
//! Orders are carried out only while the robot stands still (on a node
//! after the phone answered a node report, or stopped by a collision or the
//! abyss): turns on the spot, speed changes, the start of a move, the
//! start-node scan. A turn ends in centring on the new line (line layer).

use super::{Act, Command, Context, Layer, Mode, approach_speed};
use crate::control::Wheels;
use crate::geometry::Turn;

/// The movement layer.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct MovementLayer;

impl MovementLayer {
    /// The layer (its state is the shared mode).
    pub const fn new() -> MovementLayer {
        MovementLayer
    }
}

impl Layer for MovementLayer {
    fn act(&mut self, ctx: &mut Context<'_>) -> Option<Act> {
        let steps = ctx.sensors.steps;
        let state = &mut *ctx.state;
        if let Mode::Turning(turn) = state.mode {
            let quarter = state.config.quarter_turn_steps();
            let (target, clockwise) = match turn {
                Turn::Right => (quarter, true),
                Turn::Left => (quarter, false),
                Turn::UTurn => (2 * quarter, true),
            };
            let rotated = steps.rotated_since(state.mode_start);
            let done = if clockwise { rotated } else { -rotated };
            let v = approach_speed(target - done, state.speed);
            if v == 0 {
                state.enter(Mode::Centring, steps);
                return Some(Act::drive(Wheels::STOP));
            }
            let v = if clockwise { v } else { -v };
            return Some(Act::drive(Wheels { left: v, right: -v }));
        }
        if !state.mode.waiting() || state.mode == Mode::Uncalibrated {
            return None;
        }
        let order = state.orders.peek()?;
        match order {
            // The calibration layer takes these; a refused one is dropped.
            Command::Calibrate | Command::Stop => {
                state.orders.pop();
            }
            Command::SetSpeed(s) => {
                state.orders.pop();
                state.speed = s;
            }
            Command::Turn(t) => {
                state.orders.pop();
                state.enter(Mode::Turning(t), steps);
            }
            Command::Move => {
                state.orders.pop();
                state.enter(Mode::Moving, steps);
                state.departed = steps;
            }
            Command::Scan => {
                state.orders.pop();
                state.enter(Mode::Scanning, steps);
            }
            Command::Tune => {
                state.orders.pop();
                state.enter(Mode::Tuning, steps);
                state.departed = steps;
            }
        }
        Some(Act::drive(Wheels::STOP))
    }
}
