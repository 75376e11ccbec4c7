//! Layer 2: the abyss — no floor under a floor sensor.
//!
//! The floor sensors sit ahead of the wheels, so stopping as soon as two
//! successive readings see no floor leaves the wheels on the table. The
//! robot reports and waits for the phone's next order (a U-turn, usually).

use super::{Act, Context, Event, Layer, Mode};

/// Successive readings needed, so a single noisy sample does not stop the
/// robot.
const CONFIRM: u8 = 2;

/// The abyss layer.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct AbyssLayer {
    seen: u8,
}

impl AbyssLayer {
    /// A layer that has seen nothing.
    pub const fn new() -> AbyssLayer {
        AbyssLayer { seen: 0 }
    }
}

impl Layer for AbyssLayer {
    fn act(&mut self, ctx: &mut Context<'_>) -> Option<Act> {
        if !ctx.state.mode.driving() {
            self.seen = 0;
            return None;
        }
        let mask = ctx.floor?.abyss_mask();
        if mask == 0 {
            self.seen = 0;
            return None;
        }
        self.seen = self.seen.saturating_add(1);
        if self.seen < CONFIRM {
            return None;
        }
        self.seen = 0;
        ctx.state.enter(Mode::AtAbyss, ctx.sensors.steps);
        Some(Act::stop_with(Event::Abyss { mask }))
    }
}
