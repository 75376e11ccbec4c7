//! The e-puck's body: differential-drive kinematics with stepper motors,
//! and where its floor and proximity sensors sit.

use core_algo::control::{StepCount, Wheels};

/// The robot's dimensions (from the e-puck2 hardware notes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Geometry {
    /// Travel per motor step: a 41 mm wheel, 1000 steps a turn.
    pub step_mm: f64,
    /// Distance between the wheels.
    pub axle_mm: f64,
    /// Body radius (the e-puck is a 74 mm disc).
    pub radius_mm: f64,
    /// Floor sensors ahead of the axle.
    pub floor_forward_mm: f64,
    /// Outer floor sensors beside the centre one.
    pub floor_side_mm: f64,
    /// Side of the square spot each floor sensor averages over.
    pub floor_spot_mm: f64,
    /// Proximity sensor directions, degrees clockwise from ahead (IR0..IR7).
    pub proximity_deg: [f64; 8],
}

impl Geometry {
    /// The e-puck2.
    pub const EPUCK: Geometry = Geometry {
        step_mm: 0.128_81,
        axle_mm: 53.0,
        radius_mm: 37.0,
        floor_forward_mm: 30.0,
        floor_side_mm: 10.0,
        floor_spot_mm: 6.0,
        proximity_deg: [15.0, 45.0, 90.0, 150.0, 210.0, 270.0, 315.0, 345.0],
    };

    /// Wheel steps of a full turn on the spot.
    pub fn full_turn_steps(&self) -> f64 {
        std::f64::consts::PI * self.axle_mm / self.step_mm
    }
}

/// Where a robot is: axle centre in mm and heading in radians,
/// counter-clockwise from east (so north is π/2).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Pose {
    /// East, mm.
    pub x: f64,
    /// North, mm.
    pub y: f64,
    /// Heading, rad, counter-clockwise from east.
    pub theta: f64,
}

impl Pose {
    /// The point `forward` mm ahead and `right` mm to the right of the axle
    /// centre.
    pub fn point(&self, forward: f64, right: f64) -> (f64, f64) {
        let (s, c) = self.theta.sin_cos();
        (
            self.x + forward * c + right * s,
            self.y + forward * s - right * c,
        )
    }
}

/// A simulated body: pose and step counters.
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    /// Where it is.
    pub pose: Pose,
    /// The motors' step counters.
    pub steps: StepCount,
    fraction: [f64; 2],
}

impl Body {
    /// A body at `pose` with zeroed counters.
    pub fn new(pose: Pose) -> Body {
        Body {
            pose,
            steps: StepCount::default(),
            fraction: [0.0; 2],
        }
    }

    /// Runs the motors at `wheels` for `dt` seconds. `slip` scales each
    /// wheel's actual travel (1.0 = none): the counters count steps, the
    /// floor sees the travel.
    pub fn drive(&mut self, g: &Geometry, wheels: Wheels, dt: f64, slip: [f64; 2]) {
        let mut moved = [0.0; 2];
        for (i, speed) in [wheels.left, wheels.right].into_iter().enumerate() {
            self.fraction[i] += f64::from(speed) * dt;
            let whole = self.fraction[i].trunc();
            self.fraction[i] -= whole;
            moved[i] = whole * g.step_mm * slip[i];
            let n = whole as i32;
            if i == 0 {
                self.steps.left = self.steps.left.wrapping_add(n);
            } else {
                self.steps.right = self.steps.right.wrapping_add(n);
            }
        }
        let ds = (moved[0] + moved[1]) / 2.0;
        let dtheta = (moved[1] - moved[0]) / g.axle_mm;
        let mid = self.pose.theta + dtheta / 2.0;
        self.pose.x += ds * mid.cos();
        self.pose.y += ds * mid.sin();
        self.pose.theta += dtheta;
    }
}

/// The e-puck2 proximity curve (reflection → distance, Cyberbotics'
/// calibration in the hardware notes), as (mm, value) points.
const PROXIMITY_CURVE: [(f64, f64); 8] = [
    (0.0, 4095.0),
    (5.0, 2133.0),
    (10.0, 1466.0),
    (15.0, 601.0),
    (20.0, 384.0),
    (30.0, 235.0),
    (40.0, 158.0),
    (50.0, 120.0),
];

/// The reflection value for an obstacle `mm` away (0 beyond 70 mm).
pub fn proximity_value(mm: f64) -> f64 {
    if mm <= 0.0 {
        return 4095.0;
    }
    for w in PROXIMITY_CURVE.windows(2) {
        let ((d0, v0), (d1, v1)) = (w[0], w[1]);
        if mm <= d1 {
            return v0 + (v1 - v0) * (mm - d0) / (d1 - d0);
        }
    }
    // Fade from 120 at 50 mm to 0 at 70 mm.
    (120.0 * (70.0 - mm) / 20.0).max(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_quarter_turn_takes_323_steps() {
        let g = Geometry::EPUCK;
        assert!((g.full_turn_steps() / 4.0 - 323.0).abs() < 1.0);
        let mut b = Body::new(Pose::default());
        for _ in 0..100 {
            b.drive(
                &g,
                Wheels {
                    left: 323,
                    right: -323,
                },
                0.01,
                [1.0; 2],
            );
        }
        assert_eq!(
            b.steps,
            StepCount {
                left: 323,
                right: -323
            }
        );
        assert!((b.pose.theta + std::f64::consts::FRAC_PI_2).abs() < 0.01);
        let mut b = Body::new(Pose::default());
        b.drive(&g, Wheels::straight(1000), 1.0, [1.0; 2]);
        assert!((b.pose.x - 128.81).abs() < 1e-6);
    }

    #[test]
    fn sensor_points_and_curve() {
        let p = Pose {
            x: 0.0,
            y: 0.0,
            theta: std::f64::consts::FRAC_PI_2,
        };
        let (x, y) = p.point(30.0, 10.0);
        assert!((x - 10.0).abs() < 1e-9 && (y - 30.0).abs() < 1e-9);
        assert_eq!(proximity_value(15.0), 601.0);
        assert_eq!(proximity_value(100.0), 0.0);
    }
}
