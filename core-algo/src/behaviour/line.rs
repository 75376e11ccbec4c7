//! Layer 6 (bottom): line following, and centring after a turn.
//!
//! While moving, the PID keeps the robot on its line whenever no higher
//! layer acts. After a turn (or a scan with an arm ahead) the robot turns on
//! the spot until the line lies between its outer sensors — the error is
//! small for a few steps in a row — or a short time limit passes; then it
//! reports [`Event::Centred`] and waits on the node. On
//! [`super::Command::Tune`] it runs the relay experiment instead of the PID
//! and switches to the Ziegler–Nichols gains it yields.

use super::{Act, Context, Event, Layer, Mode};
use crate::control::Wheels;
use crate::control::line_follow::{LineFollower, line_error};
use crate::control::pid::{Gains, Relay, RelayTuner};

/// The relay's output: ±120 steps/s of turning keeps the oscillation
/// within the outer sensors' linear range at line speed.
const RELAY_AMPLITUDE: i32 = 120;
/// Hysteresis against floor-sensor noise, calibrated units.
const RELAY_HYSTERESIS: i32 = 40;

/// |left − right| below this counts as centred.
const CENTRED_ERROR: i32 = 48;
/// Successive centred steps needed.
const CENTRED_STEPS: u8 = 3;
/// Give up centring after this many steps (0.6 s) and wait anyway.
const CENTRE_LIMIT: u16 = 60;

/// The line layer.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct LineLayer {
    follower: LineFollower,
    epoch: u32,
    centred: u8,
    ticks: u16,
    tuner: RelayTuner,
}

impl LineLayer {
    /// A layer with the given gains.
    pub const fn new(gains: Gains) -> LineLayer {
        LineLayer {
            follower: LineFollower::new(gains),
            epoch: u32::MAX,
            centred: 0,
            ticks: 0,
            tuner: RelayTuner::new(RELAY_AMPLITUDE, RELAY_HYSTERESIS, 2, 5),
        }
    }
}

impl Layer for LineLayer {
    fn act(&mut self, ctx: &mut Context<'_>) -> Option<Act> {
        let floor = ctx.floor?;
        if self.epoch != ctx.state.epoch {
            self.follower.reset();
            self.centred = 0;
            self.ticks = 0;
            self.tuner = RelayTuner::new(RELAY_AMPLITUDE, RELAY_HYSTERESIS, 2, 5);
            self.epoch = ctx.state.epoch;
        }
        match ctx.state.mode {
            Mode::Moving => Some(Act::drive(self.follower.drive(floor, ctx.state.speed))),
            Mode::Tuning => match self.tuner.update(line_error(floor)) {
                Relay::Drive(u) => Some(Act::drive(Wheels::from_linear_angular(
                    i32::from(ctx.state.speed),
                    u,
                ))),
                Relay::Done(critical) => {
                    let gains = critical.gains();
                    self.follower.set_gains(gains);
                    ctx.state.config.gains = gains;
                    ctx.state.enter(Mode::Ready, ctx.sensors.steps);
                    Some(Act::stop_with(Event::Tuned { critical, gains }))
                }
                Relay::Failed => {
                    ctx.state.enter(Mode::Ready, ctx.sensors.steps);
                    Some(Act::stop_with(Event::TuneFailed))
                }
            },
            Mode::Centring => {
                self.ticks = self.ticks.saturating_add(1);
                if line_error(floor).abs() < CENTRED_ERROR {
                    self.centred = self.centred.saturating_add(1);
                } else {
                    self.centred = 0;
                }
                if self.centred >= CENTRED_STEPS || self.ticks > CENTRE_LIMIT {
                    ctx.state.enter(Mode::OnNode, ctx.sensors.steps);
                    return Some(Act::stop_with(Event::Centred));
                }
                let speed = ctx.state.speed / 2;
                Some(Act::drive(LineFollower::centre(
                    floor,
                    ctx.state.config.centre_gain,
                    speed,
                )))
            }
            _ => None,
        }
    }
}
