//! Line following: the two outer floor sensors steer the robot along its
//! line with the positional PID.
//!
//! The outer sensors sit just beside the line: when the robot drifts, one of
//! them starts to see the line's edge and the difference left − right grows
//! with the drift. That difference is the control error; the PID output is
//! the angular part ω of the 2010 `setSpeed(v, ω)` (left = v + ω,
//! right = v − ω), so a brighter left sensor (line to the right) turns right.

use super::pid::{Fix, Gains, Pid};
use super::{FloorImage, MAX_SPEED, Wheels};

/// The 2010 error-sum limit, in calibrated floor units.
pub const INTEGRAL_LIMIT: i32 = 5000;

/// The control error of a floor image: left − right, calibrated units.
pub fn line_error(floor: FloorImage) -> i32 {
    i32::from(floor.left) - i32::from(floor.right)
}

/// A PID line follower producing wheel speeds.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct LineFollower {
    pid: Pid,
}

impl LineFollower {
    /// A follower with `gains`, the 2010 anti-wind-up limit and the motors'
    /// speed limit as output limit.
    pub const fn new(gains: Gains) -> LineFollower {
        LineFollower {
            pid: Pid::new(gains, INTEGRAL_LIMIT, MAX_SPEED as i32),
        }
    }

    /// The gains in use.
    pub const fn gains(&self) -> Gains {
        self.pid.gains()
    }

    /// Replaces the gains.
    pub fn set_gains(&mut self, gains: Gains) {
        self.pid.set_gains(gains);
    }

    /// Forgets the controller's history (a new line).
    pub fn reset(&mut self) {
        self.pid.reset();
    }

    /// One control interval at forward `speed`: the forward part is cut so
    /// that v + |ω| stays within the motors' limit, as in 2010, because a
    /// steering command that the motors cannot carry out loses the line.
    pub fn drive(&mut self, floor: FloorImage, speed: i16) -> Wheels {
        let omega = self.pid.update(line_error(floor));
        let room = i32::from(MAX_SPEED) - omega.abs();
        let v = i32::from(speed).min(room).max(0);
        Wheels::from_linear_angular(v, omega)
    }

    /// Turning on the spot onto the line after a turn: proportional only,
    /// with its own `gain`, because rotating on the spot moves the sensors
    /// sideways at a different rate than steering while driving does; the
    /// turn is limited to ±`max_speed`.
    pub fn centre(floor: FloorImage, gain: Fix, max_speed: i16) -> Wheels {
        let omega = gain
            .saturating_mul(Fix::saturating_from_num(line_error(floor)))
            .saturating_to_num::<i32>();
        let m = i32::from(max_speed.max(0));
        Wheels::from_linear_angular(0, omega.clamp(-m, m))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p_only() -> LineFollower {
        LineFollower::new(Gains {
            kp: Fix::ONE,
            ki: Fix::ZERO,
            kd: Fix::ZERO,
        })
    }

    #[test]
    fn brighter_left_turns_right() {
        let mut f = p_only();
        let w = f.drive(
            FloorImage {
                left: 768,
                centre: 256,
                right: 600,
            },
            600,
        );
        assert_eq!(
            w,
            Wheels {
                left: 768,
                right: 432
            }
        );
    }

    #[test]
    fn forward_speed_yields_to_steering() {
        let mut f = p_only();
        let w = f.drive(
            FloorImage {
                left: 1023,
                centre: 0,
                right: 0,
            },
            1000,
        );
        assert!(w.left <= MAX_SPEED && w.right >= -MAX_SPEED);
        assert_eq!(i32::from(w.left) - i32::from(w.right), 2 * 1000);
        let c = LineFollower::centre(FloorImage::default(), Fix::from_num(2), 300);
        assert_eq!(c, Wheels::STOP);
        let c = LineFollower::centre(
            FloorImage {
                left: 768,
                centre: 256,
                right: 256,
            },
            Fix::from_num(2),
            300,
        );
        assert_eq!(
            c,
            Wheels {
                left: 300,
                right: -300
            }
        );
    }
}
