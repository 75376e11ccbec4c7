//! Layer 0 (top): floor calibration.
//!
//! Runs the seed's procedure on [`Command::Calibrate`]: sample the line
//! under the sensors, drive [`DRIVE_STEPS`] forward, sample the background,
//! drive back to where it started. It acts during the whole procedure, so
//! nothing else moves the robot meanwhile.

use super::{Act, Command, Context, Event, Layer, Mode, approach_speed};
use crate::control::calibration::{Calibration, DRIVE_STEPS, LevelSampler};
use crate::control::{StepCount, Wheels};

/// Driving speed while calibrating: slow, so the samples are not smeared.
const SPEED: i16 = 300;

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Phase {
    Line,
    Forward,
    Background,
    Back,
}

/// The calibration layer.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct CalibrationLayer {
    phase: Phase,
    sampler: LevelSampler,
    line: [u16; 3],
    background: [u16; 3],
    start: StepCount,
}

impl CalibrationLayer {
    /// An idle layer.
    pub const fn new() -> CalibrationLayer {
        CalibrationLayer {
            phase: Phase::Line,
            sampler: LevelSampler {
                sums: [0; 3],
                count: 0,
            },
            line: [0; 3],
            background: [0; 3],
            start: StepCount { left: 0, right: 0 },
        }
    }
}

impl Default for CalibrationLayer {
    fn default() -> Self {
        CalibrationLayer::new()
    }
}

impl Layer for CalibrationLayer {
    fn act(&mut self, ctx: &mut Context<'_>) -> Option<Act> {
        let steps = ctx.sensors.steps;
        if ctx.state.mode != Mode::Calibrating {
            let stationary = matches!(
                ctx.state.mode,
                Mode::Uncalibrated | Mode::Ready | Mode::OnNode
            );
            if !(stationary && ctx.state.orders.peek() == Some(Command::Calibrate)) {
                return None;
            }
            ctx.state.orders.pop();
            ctx.state.enter(Mode::Calibrating, steps);
            *self = CalibrationLayer::new();
            self.start = steps;
        }
        let travelled = steps.travelled_since(self.start);
        let act = match self.phase {
            Phase::Line => {
                if let Some(mean) = self.sampler.add(ctx.sensors.floor) {
                    self.line = mean;
                    self.phase = Phase::Forward;
                }
                Act::drive(Wheels::STOP)
            }
            Phase::Forward => {
                let v = approach_speed(DRIVE_STEPS - travelled, SPEED);
                if v == 0 {
                    self.phase = Phase::Background;
                }
                Act::drive(Wheels::straight(v))
            }
            Phase::Background => {
                if let Some(mean) = self.sampler.add(ctx.sensors.floor) {
                    self.background = mean;
                    self.phase = Phase::Back;
                }
                Act::drive(Wheels::STOP)
            }
            Phase::Back => {
                let v = approach_speed(travelled, SPEED);
                if v != 0 {
                    return Some(Act::drive(Wheels::straight(-v)));
                }
                let event = match Calibration::new(self.line, self.background) {
                    Ok(c) => {
                        ctx.state.calibration = Some(c);
                        Event::Calibrated(c.record())
                    }
                    Err(e) => Event::CalibrationRefused(e),
                };
                let next = if ctx.state.calibration.is_some() {
                    Mode::Ready
                } else {
                    Mode::Uncalibrated
                };
                ctx.state.enter(next, steps);
                Act::stop_with(event)
            }
        };
        Some(act)
    }
}
