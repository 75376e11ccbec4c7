//! Layer 3: collision — an obstacle close ahead.
//!
//! Any of the four front proximity sensors (IR0, IR1, IR6, IR7) above the
//! threshold stops the robot at once and reports which sensors fired, with
//! the distance driven since the last node, so that the phone can decide
//! between waiting, going back (U-turn, then move: the node layer reports
//! the node it returns to) or re-planning. Stepper motors stop within one
//! control step, so a threshold of about 15 mm keeps a gap.

use super::{Act, Context, Event, Layer, Mode};

/// IR0, IR1, IR6, IR7: the sensors that look forward.
const FRONT: u8 = 0b1100_0011;

/// The collision layer.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct CollisionLayer;

impl CollisionLayer {
    /// The layer (it keeps no state).
    pub const fn new() -> CollisionLayer {
        CollisionLayer
    }
}

/// Proximity sensors above `threshold`, bit i for IRi.
pub fn proximity_mask(proximity: &[u16; 8], threshold: u16) -> u8 {
    proximity
        .iter()
        .enumerate()
        .filter(|(_, v)| **v > threshold)
        .fold(0, |m, (i, _)| m | (1 << i))
}

impl Layer for CollisionLayer {
    fn act(&mut self, ctx: &mut Context<'_>) -> Option<Act> {
        if !ctx.state.mode.driving() {
            return None;
        }
        let mask = proximity_mask(&ctx.sensors.proximity, ctx.state.config.collision_threshold);
        if mask & FRONT == 0 {
            return None;
        }
        let steps = ctx.sensors.steps;
        let travelled = steps.travelled_since(ctx.state.departed);
        ctx.state.enter(Mode::Blocked, steps);
        Some(Act::stop_with(Event::Collision { mask, travelled }))
    }
}
