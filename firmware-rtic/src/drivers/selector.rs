//! The 16-position selector on PC13, PC14, PC15, PD4 (inputs with pull-down).

use stm32f4xx_hal::gpio::{Input, PC13, PC14, PC15, PD4};

/// The four selector inputs.
pub struct Selector {
    /// SEL0..SEL3.
    pub pins: (PC13<Input>, PC14<Input>, PC15<Input>, PD4<Input>),
}

impl Selector {
    /// Current position, 0..=15.
    pub fn read(&self) -> u8 {
        let (a, b, c, d) = &self.pins;
        drivers_logic::selector::decode([a.is_high(), b.is_high(), c.is_high(), d.is_high()])
    }
}
