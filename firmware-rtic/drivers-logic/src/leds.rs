//! LED levels. The seed addressed 8 ring LEDs (bit 0 = front, clockwise);
//! the e-puck2 has four red ring LEDs on the STM32 (LED1 front, LED3 right,
//! LED5 back, LED7 left, **active-low**) and four RGB ones driven by the ESP32.
//! The red ones show the even bits of the seed's mask, which are exactly the
//! arm directions (front, right, back, left) used to show a node's shape.

/// Pin level for each red ring LED (LED1, LED3, LED5, LED7) for a seed-style
/// 8-bit mask: `false` (low) lights the LED.
pub const fn ring_levels(mask: u8) -> [bool; 4] {
    [
        mask & 0b0000_0001 == 0,
        mask & 0b0000_0100 == 0,
        mask & 0b0001_0000 == 0,
        mask & 0b0100_0000 == 0,
    ]
}

/// The 8-bit ring mask showing node arms given as front, right, back, left.
pub const fn arms_mask(front: bool, right: bool, back: bool, left: bool) -> u8 {
    front as u8 | (right as u8) << 2 | (back as u8) << 4 | (left as u8) << 6
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn active_low() {
        assert_eq!(ring_levels(0), [true; 4]);
        assert_eq!(ring_levels(0xFF), [false; 4]);
        assert_eq!(
            ring_levels(arms_mask(true, false, false, true)),
            [false, true, true, false]
        );
        // Odd bits (the RGB LEDs' places) do not light a red LED.
        assert_eq!(ring_levels(0b1010_1010), [true; 4]);
    }
}
