//! The seams where core-algo's robot logic plugs into the firmware.
//!
//! Three pieces are being written on other branches and will be merged later;
//! each has one marked place here (search for `PLUG-IN`):
//!
//! * **behaviour** (`core_algo::control` + `core_algo::behaviour`): the
//!   subsumption stack, stepped once per 100 Hz control cycle with a
//!   [`SensorImage`], returning a [`MotorCommand`] and maybe a node event.
//!   Replace [`Behaviour::step`]'s body.
//! * **link** (`core_algo::protocol`): frames, messages and the reliable link
//!   state machine. Replace the bootstrap `drivers_logic::frame` messages used
//!   by the `link` task in `main.rs`; the byte rings stay.
//! * **agent** (`core_algo::agent` with `explore`/`path`): decides at nodes,
//!   lowest priority, owns the [`Map`]. Replace [`Agent::on_event`]'s body.
//!
//! Everything here is plain data and plain functions so the RTIC tasks stay
//! a few lines long.

use core_algo::geometry::{Arms, Pos};
use core_algo::map::{ArrayMap, Bounds};
use core_algo::team::RobotId;
use drivers_logic::proximity::{COLLISION_THRESHOLD, SENSORS, front_blocked};

/// Blocks of 32 nodes in the robot's map: 32 × 32 = 1024 nodes, the budget
/// the issue asks for (≈ 4.2 KiB of static RAM).
pub const MAP_BLOCKS: usize = 32;
/// The robot's known map.
pub type Map = ArrayMap<MAP_BLOCKS>;
/// The window the map covers until the phone sends the field's bounds:
/// 32 × 32 nodes centred on the start node.
pub const MAP_BOUNDS: Bounds = Bounds::new(Pos::new(-16, -16), 32, 32);

/// What the control step sees, refreshed every 10 ms.
#[derive(Clone, Copy, Debug, Default, defmt::Format)]
pub struct SensorImage {
    /// Raw ground deltas (left, centre, right); zero without the module.
    pub ground_raw: [u16; 3],
    /// Calibrated ground values, black ≈ 256, white ≈ 768.
    pub ground: [u16; 3],
    /// Whether the ground read of this cycle succeeded.
    pub ground_ok: bool,
    /// Proximity values IR0..IR7 (0 = nothing).
    pub prox: [u16; SENSORS],
    /// Wheel step counters (left, right).
    pub steps: (i32, i32),
}

impl SensorImage {
    /// Bit i set when IR i sees an obstacle.
    pub fn collision_mask(&self) -> u8 {
        self.prox
            .iter()
            .enumerate()
            .filter(|(_, v)| **v > COLLISION_THRESHOLD)
            .fold(0, |m, (i, _)| m | (1 << i))
    }
}

/// Wheel speeds in full steps per second.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, defmt::Format)]
pub struct MotorCommand {
    /// Left wheel.
    pub left: i16,
    /// Right wheel.
    pub right: i16,
}

/// Something the agent must hear about.
#[derive(Clone, Copy, Debug, defmt::Format)]
pub enum AgentEvent {
    /// The robot stands on a node and has classified it.
    Node {
        /// Where (in the robot's frame).
        x: i16,
        /// Where.
        y: i16,
        /// Arms bitmask (N = bit 0, E, S, W).
        arms: u8,
    },
}

/// The behaviour stack's state.
#[derive(Default)]
pub struct Behaviour {
    /// Speeds last requested over the link (bootstrap only).
    pub manual: MotorCommand,
}

impl Behaviour {
    /// One 100 Hz step.
    ///
    /// PLUG-IN(behaviour): call core-algo's subsumption stack here. Until
    /// then: drive the speeds requested over the link, but stop when a front
    /// sensor sees an obstacle (the collision layer's first duty).
    pub fn step(&mut self, image: &SensorImage) -> (MotorCommand, Option<AgentEvent>) {
        let forward = self.manual.left > 0 || self.manual.right > 0;
        if forward && front_blocked(image.collision_mask()) {
            return (MotorCommand::default(), None);
        }
        (self.manual, None)
    }
}

/// The deciding part of the robot.
pub struct Agent {
    /// This robot's id.
    pub robot: RobotId,
}

impl Agent {
    /// Handles one event with the map borrowed.
    ///
    /// PLUG-IN(agent): core-algo's agent decides the next move here and
    /// returns it (to be sent to the control task). Until then: record the
    /// node in the map. Returns whether the map accepted the event.
    pub fn on_event(&mut self, map: &mut Map, event: AgentEvent) -> bool {
        match event {
            AgentEvent::Node { x, y, arms } => {
                match map.visit(Pos::new(x, y), Arms::from_bits(arms), self.robot) {
                    Ok(_) => true,
                    Err(e) => {
                        defmt::warn!(
                            "map refused node ({}, {}): {}",
                            x,
                            y,
                            defmt::Debug2Format(&e)
                        );
                        false
                    }
                }
            }
        }
    }
}
