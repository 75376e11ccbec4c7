//! The robot's low-level control: turning floor-sensor readings into wheel
//! speeds and node reports.
//!
//! Everything here is a pure state machine fed once per 100 Hz control step,
//! in integers and [`fixed`] point only, so that the firmware, the
//! sensor-level simulator and the host benches run the very same arithmetic.
//! The [`crate::behaviour`] layers combine these parts.
//!
//! Units used throughout:
//! - floor readings: raw 0..=1023 from the ground-sensor module; calibrated
//!   to the 2010 scale where the line reads 256 and the background 768;
//! - wheel speeds: motor steps per second (one step ≈ 0.129 mm of travel);
//! - distances along the path: motor steps (mean of both wheels).

pub mod calibration;
pub mod line_follow;
pub mod node_detect;
pub mod pid;
pub mod scan;

/// A pair of wheel speed commands in motor steps per second.
///
/// This is the only thing the control asks of the motors, so firmware and
/// simulator need nothing else to move the robot. Positive is forward.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct Wheels {
    /// Left wheel, steps/s.
    pub left: i16,
    /// Right wheel, steps/s.
    pub right: i16,
}

impl Wheels {
    /// Both wheels still: the safe output when no layer acts.
    pub const STOP: Wheels = Wheels { left: 0, right: 0 };

    /// Straight ahead at `speed`.
    pub const fn straight(speed: i16) -> Wheels {
        Wheels {
            left: speed,
            right: speed,
        }
    }

    /// The 2010 firmware's `setSpeed(linear, angular)`: left = v + ω,
    /// right = v − ω, so a positive ω turns clockwise (to the right).
    pub fn from_linear_angular(linear: i32, angular: i32) -> Wheels {
        Wheels {
            left: clamp_speed(linear.saturating_add(angular)),
            right: clamp_speed(linear.saturating_sub(angular)),
        }
    }
}

/// The e-puck's motor limit: about one wheel turn per second.
pub const MAX_SPEED: i16 = 1000;

/// Clamps a speed to ±[`MAX_SPEED`].
pub fn clamp_speed(speed: i32) -> i16 {
    let max = i32::from(MAX_SPEED);
    // The clamp keeps the value inside i16, so the conversion cannot fail.
    i16::try_from(speed.clamp(-max, max)).unwrap_or(0)
}

/// The robot's motor step counters, as the motor driver reports them.
///
/// Counters are absolute and may wrap; the control only ever uses
/// differences taken with wrapping arithmetic.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct StepCount {
    /// Left wheel, steps (forward positive).
    pub left: i32,
    /// Right wheel, steps (forward positive).
    pub right: i32,
}

impl StepCount {
    /// Distance driven since `start`: the mean of both wheels, in steps.
    pub fn travelled_since(self, start: StepCount) -> i32 {
        let l = i64::from(self.left.wrapping_sub(start.left));
        let r = i64::from(self.right.wrapping_sub(start.right));
        // The mean of two i32 values fits in i32.
        i32::try_from((l + r) / 2).unwrap_or(0)
    }

    /// Clockwise rotation on the spot since `start`, in wheel steps (half
    /// the difference of the wheels).
    pub fn rotated_since(self, start: StepCount) -> i32 {
        let l = i64::from(self.left.wrapping_sub(start.left));
        let r = i64::from(self.right.wrapping_sub(start.right));
        i32::try_from((l - r) / 2).unwrap_or(0)
    }
}

/// One calibrated floor image: left, centre, right on the 2010 scale
/// (line 256, background 768, clamped to 0..=1023).
///
/// Calibrating first makes every threshold below independent of the light
/// and of the individual sensor.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct FloorImage {
    /// Left floor sensor.
    pub left: u16,
    /// Centre floor sensor.
    pub centre: u16,
    /// Right floor sensor.
    pub right: u16,
}

/// Calibrated value of the line.
pub const LINE_LEVEL: u16 = 256;
/// Calibrated value of the background.
pub const BACKGROUND_LEVEL: u16 = 768;
/// A reading counts as clearly black below 50 % of the white value (the
/// seed's robust node threshold). On the calibrated scale the line is 256 and
/// white 768, so 50 % of white is 384 when black reads a third of white.
pub const BLACK_BELOW: u16 = 384;
/// A reading this far below the line value means no floor at all: the abyss.
/// Half the line level leaves a wide margin against noise on the line.
pub const ABYSS_BELOW: u16 = 128;

impl FloorImage {
    /// The three values in sensor order (left, centre, right).
    pub const fn values(self) -> [u16; 3] {
        [self.left, self.centre, self.right]
    }

    /// Which sensors see clearly black: bit 0 left, 1 centre, 2 right.
    pub fn black_mask(self) -> u8 {
        mask(self.values(), |v| v < BLACK_BELOW)
    }

    /// Which sensors see no floor at all (same bit order).
    pub fn abyss_mask(self) -> u8 {
        mask(self.values(), |v| v < ABYSS_BELOW)
    }
}

fn mask(values: [u16; 3], test: impl Fn(u16) -> bool) -> u8 {
    values
        .iter()
        .enumerate()
        .filter(|(_, v)| test(**v))
        .fold(0, |m, (i, _)| m | (1 << i))
}
