//! The robot's behaviour: the seed's subsumption architecture (§2.2).
//!
//! An ordered stack of layers, one file each, so that a layer can be
//! swapped or added without touching the others. Every 100 Hz control step
//! the [`arbitrate`] walk starts at the top; the first layer that acts
//! decides the wheel speeds (and may report an [`Event`]); the layers below
//! it are skipped for this step. When no layer acts the robot stands still.
//!
//! From the top:
//!
//! 1. [`calibrate`]: floor calibration on order (selector 0 at power-up);
//! 2. [`initial`]: the 360° scan that classifies the start node;
//! 3. [`abyss`]: no floor ahead, stop at once;
//! 4. [`collision`]: a robot or wall ahead, stop before contact;
//! 5. [`node`]: crossing a node, classify it, stop on its centre;
//! 6. [`movement`]: the phone's orders — turns and speed changes — only
//!    while the robot stands on a node;
//! 7. [`line`](mod@line): PID line following, and centring on the line after a turn.
//!
//! The inputs are a plain [`Sensors`] image and the phone's [`Command`]s; the
//! outputs are [`Wheels`] and [`Event`]s. Firmware and simulator drive the
//! same [`Robot`], so a behaviour proven in simulation is the one on the
//! robot.

pub mod abyss;
pub mod calibrate;
pub mod collision;
pub mod initial;
pub mod line;
pub mod movement;
pub mod node;

use crate::control::calibration::{Calibration, CalibrationError, Record};
use crate::control::node_detect::NodeConfig;
use crate::control::pid::{Critical, Fix, Gains};
use crate::control::scan::ScanError;
use crate::control::{FloorImage, StepCount, Wheels};
use crate::geometry::{Arms, Turn};

/// Control steps per second: the 2010 heartbeat.
pub const CONTROL_HZ: i32 = 100;

/// Everything the behaviour reads in one control step.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct Sensors {
    /// Raw floor sensors, left, centre, right, 0..=1023 (bright is high).
    pub floor: [u16; 3],
    /// Proximity sensors IR0..IR7 (IR0 front right, then clockwise), 12-bit
    /// reflection: 0 nothing, 4095 touching.
    pub proximity: [u16; 8],
    /// The motors' step counters.
    pub steps: StepCount,
}

/// An order from the phone.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Command {
    /// Calibrate the floor sensors here (on a line, background ahead).
    Calibrate,
    /// Classify the node the robot stands on by a 360° scan.
    Scan,
    /// Turn on the spot and centre on the new line.
    Turn(Turn),
    /// Follow the line to the next node.
    Move,
    /// Set the line speed in steps/s, taking effect on the next move.
    SetSpeed(i16),
    /// Stop now, whatever the robot is doing; forget queued orders.
    Stop,
    /// Tune the line follower on the spot: drive along a long straight
    /// line under a relay (Åström–Hägglund) until the critical gain and
    /// period are known, then use the Ziegler–Nichols gains.
    Tune,
}

/// What the robot tells the phone.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Event {
    /// Calibration accepted; store this record in flash.
    Calibrated(Record),
    /// Calibration refused; the old one (if any) stays.
    CalibrationRefused(CalibrationError),
    /// The start node's arms, relative to the robot's (corrected) heading.
    StartNode {
        /// Relative arms: bit 0 ahead, 1 right, 2 behind, 3 left.
        arms: Arms,
    },
    /// The scan found no valid shape.
    ScanFailed(ScanError),
    /// Arrived on a node; its arms relative to the robot.
    NodeHit {
        /// Relative arms: bit 0 ahead, 1 right, 2 behind (always), 3 left.
        arms: Arms,
    },
    /// A turn is done and the robot faces its new line.
    Centred,
    /// Stopped before hitting something.
    Collision {
        /// Proximity sensors above the threshold, bit i for IRi.
        mask: u8,
        /// Steps driven since the last node.
        travelled: i32,
    },
    /// The relay experiment finished; these gains are now in use (store
    /// them with the calibration).
    Tuned {
        /// What the experiment measured.
        critical: Critical,
        /// The Ziegler–Nichols gains derived from it.
        gains: Gains,
    },
    /// The relay experiment found no steady oscillation; gains unchanged.
    TuneFailed,
    /// Stopped before the floor's edge.
    Abyss {
        /// Floor sensors that see no floor (bit 0 left, 1 centre, 2 right).
        mask: u8,
    },
}

/// Why an order was not taken.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Refused {
    /// The order queue is full.
    Busy,
    /// Floor orders need a calibration first.
    NotCalibrated,
    /// A speed outside 1..=1000 steps/s.
    BadSpeed,
}

/// What the robot is doing: the 2010 "conquest state", shared by all layers.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Mode {
    /// No floor calibration: only [`Command::Calibrate`] is possible.
    Uncalibrated,
    /// Running the calibration.
    Calibrating,
    /// Standing still, position on the field unknown.
    Ready,
    /// Scanning the start node.
    Scanning,
    /// Standing on a node, waiting for the phone's order.
    OnNode,
    /// Turning on the spot.
    Turning(Turn),
    /// Turning onto the line after a turn or scan.
    Centring,
    /// Following the line to the next node.
    Moving,
    /// Driving along a line under the relay experiment.
    Tuning,
    /// Stopped before an obstacle.
    Blocked,
    /// Stopped before the floor's edge.
    AtAbyss,
}

impl Mode {
    /// Driving forward along a line, where the abyss and collision layers
    /// must watch.
    pub const fn driving(self) -> bool {
        matches!(self, Mode::Moving | Mode::Tuning)
    }

    /// Standing still and ready for an order.
    pub const fn waiting(self) -> bool {
        matches!(
            self,
            Mode::Ready | Mode::OnNode | Mode::Blocked | Mode::AtAbyss | Mode::Uncalibrated
        )
    }
}

/// Tunable parameters of the behaviour.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Config {
    /// Line-following gains.
    pub gains: Gains,
    /// Proportional gain of the centring turn.
    pub centre_gain: Fix,
    /// Node geometry.
    pub node: NodeConfig,
    /// Default line speed, steps/s (2010: 600).
    pub speed: i16,
    /// Wheel steps of a full turn on the spot (π · axle / step length).
    pub full_turn_steps: i32,
    /// A scan's arm must lie this close to a quarter turn, in steps.
    pub scan_tolerance: i32,
    /// A front proximity reading above this means an obstacle ahead (about
    /// 15 mm on the e-puck2's curve).
    pub collision_threshold: u16,
}

impl Config {
    /// The e-puck2 with the 2010 gains.
    pub const EPUCK: Config = Config {
        gains: Gains::LEGACY,
        centre_gain: Fix::lit("1.5"),
        node: NodeConfig::EPUCK,
        speed: 600,
        full_turn_steps: 1292,
        scan_tolerance: 60,
        collision_threshold: 600,
    };

    /// Wheel steps of a quarter turn.
    pub const fn quarter_turn_steps(&self) -> i32 {
        self.full_turn_steps / 4
    }
}

const QUEUE: usize = 4;

/// The phone's orders not yet carried out, oldest first.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct Orders {
    slots: [Option<Command>; QUEUE],
    len: usize,
}

impl Orders {
    /// The oldest order.
    pub fn peek(&self) -> Option<Command> {
        self.slots.first().copied().flatten()
    }

    /// Removes and returns the oldest order.
    pub fn pop(&mut self) -> Option<Command> {
        let first = self.peek()?;
        self.slots.rotate_left(1);
        if let Some(last) = self.slots.last_mut() {
            *last = None;
        }
        self.len = self.len.saturating_sub(1);
        Some(first)
    }

    /// Appends an order; `Err` when full.
    pub fn push(&mut self, c: Command) -> Result<(), Refused> {
        let slot = self.slots.get_mut(self.len).ok_or(Refused::Busy)?;
        *slot = Some(c);
        self.len += 1;
        Ok(())
    }

    /// Forgets every order.
    pub fn clear(&mut self) {
        *self = Orders::default();
    }
}

/// The state all layers share.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct State {
    /// What the robot is doing.
    pub mode: Mode,
    /// Parameters.
    pub config: Config,
    /// The floor calibration, once there is one.
    pub calibration: Option<Calibration>,
    /// Current line speed, steps/s.
    pub speed: i16,
    /// Orders waiting.
    pub orders: Orders,
    /// Step counters where the current edge began (the last node's centre).
    pub departed: StepCount,
    /// Step counters when the current mode began.
    pub mode_start: StepCount,
    /// Step counters at the latest control step.
    pub now: StepCount,
    /// Counts mode changes, so that a layer can tell a new run of its mode
    /// and reset itself.
    pub epoch: u32,
}

impl State {
    /// Switches mode, noting where it began.
    pub fn enter(&mut self, mode: Mode, steps: StepCount) {
        self.mode = mode;
        self.mode_start = steps;
        self.epoch = self.epoch.wrapping_add(1);
    }
}

/// One control step's view for the layers.
pub struct Context<'a> {
    /// This step's sensor image.
    pub sensors: &'a Sensors,
    /// The calibrated floor image, if calibrated.
    pub floor: Option<FloorImage>,
    /// The shared state.
    pub state: &'a mut State,
}

/// What an acting layer decides.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Act {
    /// Wheel speeds for this step.
    pub wheels: Wheels,
    /// An event for the phone, if any.
    pub event: Option<Event>,
}

impl Act {
    /// Drive, report nothing.
    pub const fn drive(wheels: Wheels) -> Act {
        Act {
            wheels,
            event: None,
        }
    }

    /// Stand still and report `event`.
    pub const fn stop_with(event: Event) -> Act {
        Act {
            wheels: Wheels::STOP,
            event: Some(event),
        }
    }
}

/// One behaviour layer.
pub trait Layer {
    /// Acts (returns `Some`) to suppress every lower layer this step, or
    /// passes (`None`).
    fn act(&mut self, ctx: &mut Context<'_>) -> Option<Act>;
}

/// The subsumption walk: the first layer, from the top, that acts wins.
pub fn arbitrate(layers: &mut [&mut dyn Layer], ctx: &mut Context<'_>) -> Option<Act> {
    layers.iter_mut().find_map(|layer| layer.act(ctx))
}

/// Speed that reaches `remaining` steps exactly at the end of a control step
/// instead of overshooting it, capped at `speed`.
pub fn approach_speed(remaining: i32, speed: i16) -> i16 {
    let cap = remaining.saturating_mul(CONTROL_HZ).max(0);
    crate::control::clamp_speed(cap.min(i32::from(speed)))
}

/// The whole behaviour stack of one robot.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Robot {
    state: State,
    calibrate: calibrate::CalibrationLayer,
    initial: initial::InitialLayer,
    abyss: abyss::AbyssLayer,
    collision: collision::CollisionLayer,
    node: node::NodeLayer,
    movement: movement::MovementLayer,
    line: line::LineLayer,
}

/// The step's result: wheel speeds and maybe an event.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Output {
    /// Wheel speeds to set now.
    pub wheels: Wheels,
    /// Something to tell the phone.
    pub event: Option<Event>,
}

impl Robot {
    /// A robot fresh from power-up; `calibration` from flash if it had one.
    pub fn new(config: Config, calibration: Option<Calibration>) -> Robot {
        let mode = if calibration.is_some() {
            Mode::Ready
        } else {
            Mode::Uncalibrated
        };
        Robot {
            state: State {
                mode,
                config,
                calibration,
                speed: config.speed,
                orders: Orders::default(),
                departed: StepCount::default(),
                mode_start: StepCount::default(),
                now: StepCount::default(),
                epoch: 0,
            },
            calibrate: calibrate::CalibrationLayer::new(),
            initial: initial::InitialLayer::new(config.full_turn_steps, config.scan_tolerance),
            abyss: abyss::AbyssLayer::new(),
            collision: collision::CollisionLayer::new(),
            node: node::NodeLayer::new(config.node),
            movement: movement::MovementLayer::new(),
            line: line::LineLayer::new(config.gains),
        }
    }

    /// What the robot is doing.
    pub const fn mode(&self) -> Mode {
        self.state.mode
    }

    /// The floor calibration in use.
    pub const fn calibration(&self) -> Option<Calibration> {
        self.state.calibration
    }

    /// The shared state (for displays and tests).
    pub const fn state(&self) -> &State {
        &self.state
    }

    /// Tells the robot it stands on a node (for a phone that knows, or a
    /// test), skipping the scan.
    pub fn place_on_node(&mut self, steps: StepCount) {
        self.state.enter(Mode::OnNode, steps);
    }

    /// Replaces the line-following gains (after tuning).
    pub fn set_gains(&mut self, gains: Gains) {
        self.state.config.gains = gains;
        self.line = line::LineLayer::new(gains);
    }

    /// Takes an order from the phone. [`Command::Stop`] acts at once; the
    /// others wait in a queue for the layer that carries them out.
    pub fn order(&mut self, command: Command) -> Result<(), Refused> {
        match command {
            Command::Stop => {
                self.state.orders.clear();
                if !self.state.mode.waiting() {
                    let steps = self.state.now;
                    let next = if self.state.calibration.is_some() {
                        Mode::Ready
                    } else {
                        Mode::Uncalibrated
                    };
                    self.state.enter(next, steps);
                }
                Ok(())
            }
            Command::SetSpeed(s) if !(1..=crate::control::MAX_SPEED).contains(&s) => {
                Err(Refused::BadSpeed)
            }
            Command::Calibrate => self.state.orders.push(command),
            _ if self.state.calibration.is_none() => Err(Refused::NotCalibrated),
            _ => self.state.orders.push(command),
        }
    }

    /// One 100 Hz control step.
    pub fn step(&mut self, sensors: &Sensors) -> Output {
        self.state.now = sensors.steps;
        let floor = self.state.calibration.map(|c| c.apply(sensors.floor));
        let mut ctx = Context {
            sensors,
            floor,
            state: &mut self.state,
        };
        let mut layers: [&mut dyn Layer; 7] = [
            &mut self.calibrate,
            &mut self.initial,
            &mut self.abyss,
            &mut self.collision,
            &mut self.node,
            &mut self.movement,
            &mut self.line,
        ];
        match arbitrate(&mut layers, &mut ctx) {
            Some(act) => Output {
                wheels: act.wheels,
                event: act.event,
            },
            None => Output {
                wheels: Wheels::STOP,
                event: None,
            },
        }
    }
}

#[cfg(test)]
mod tests;
