//! The LEDs on the STM32: red ring LED1/3/5/7 on PD5, PD6, PD10, PD11
//! (active-low), body LED PB2 and front LED PD14 (active-high). The RGB LEDs
//! belong to the ESP32 and are not driven here.

use drivers_logic::leds::ring_levels;
use stm32f4xx_hal::gpio::{AnyPin, Output, PushPull};

type Pin = AnyPin<Output<PushPull>>;

/// All LEDs driven by the STM32.
pub struct Leds {
    /// LED1, LED3, LED5, LED7 (front, right, back, left).
    pub ring: [Pin; 4],
    /// Green body LED.
    pub body: Pin,
    /// Red front LED.
    pub front: Pin,
}

impl Leds {
    /// Shows a seed-style 8-bit ring mask (even bits = the red LEDs).
    pub fn set_ring(&mut self, mask: u8) {
        for (pin, level) in self.ring.iter_mut().zip(ring_levels(mask)) {
            pin.set_state(level.into());
        }
    }

    /// Body LED on or off.
    pub fn set_body(&mut self, on: bool) {
        self.body.set_state(on.into());
    }

    /// Front LED on or off.
    pub fn set_front(&mut self, on: bool) {
        self.front.set_state(on.into());
    }
}
