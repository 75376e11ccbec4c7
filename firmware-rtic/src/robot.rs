//! The robot's logic as the firmware holds it: core-algo's agent (with its
//! map and planner scratch in static memory), the glue and messages between
//! the tasks, and the sensor image the behaviour stack reads.
//!
//! Everything here is plain data and plain functions so that the RTIC tasks
//! in `main.rs` stay a few lines long; the logic itself is core-algo's and
//! tested there (the simulator runs the same glue,
//! `core_algo::agent::firmware`).

use core_algo::agent::body::{BehaviourBody, Order, Report};
use core_algo::agent::{Agent, AgentConfig};
use core_algo::behaviour::{Config, Robot, Sensors};
use core_algo::control::StepCount;
use core_algo::control::calibration::Calibration;
use core_algo::explore::MinPos;
use core_algo::geometry::Pos;
use core_algo::map::{Block, Bounds, KnownMap, blocks_for};
use core_algo::path::{DistField, PlanCell, min_cells};
use core_algo::protocol::Message;
use core_algo::team::RobotId;
use core_algo::timing::{DEFAULT_NODE_SPACING_MM, Timing};
use drivers_logic::proximity::SENSORS;

/// The window the robot's map covers: 32 × 32 = 1024 nodes (the issue's
/// budget) centred on the field's origin, where the phone puts the start
/// poses. A field must fit in it.
pub const MAP_BOUNDS: Bounds = Bounds::new(Pos::new(-16, -16), 32, 32);
/// Map blocks for [`MAP_BOUNDS`] (≈ 4.2 KiB).
pub const MAP_BLOCKS: usize = blocks_for(MAP_BOUNDS.area());
/// Planner cells for [`MAP_BOUNDS`]: 16 B per node, 16 KiB.
pub const PLAN_CELLS: usize = min_cells(MAP_BOUNDS.area());

/// The exploration strategy the firmware runs. MinPos needs one planner
/// field (the team's positions, not a field per robot as the centralised
/// strategies want), so it fits the RAM budget with a 1024-node map.
pub type Strategy = MinPos;

/// The robot's agent: map and planner scratch live in `static` buffers.
pub type FwAgent = Agent<&'static mut [Block], &'static mut [PlanCell], Strategy, 1>;

/// The agent of robot `id` over the static buffers.
pub fn agent(
    id: RobotId,
    blocks: &'static mut [Block; MAP_BLOCKS],
    cells: &'static mut [PlanCell; PLAN_CELLS],
) -> FwAgent {
    let blocks: &'static mut [Block] = blocks;
    let map = KnownMap::new(blocks, MAP_BOUNDS)
        .unwrap_or_else(|_| defmt::panic!("map storage too small for its bounds"));
    Agent::new(
        id,
        map,
        [DistField::new(cells)],
        MinPos,
        AgentConfig::default(),
    )
}

/// The agent's timing once the phone's start message gave the line speed:
/// the robot does not know the field's node spacing, so it assumes the
/// project's default (the phone scales the speed for emulated robots).
pub fn timing_for(speed: u16) -> Timing {
    Timing::from_hardware(DEFAULT_NODE_SPACING_MM, u32::from(speed))
}

/// Robot ids count from 0 (the phone's first robot) and selector positions
/// from 1 (0 calibrates): selector N is robot N − 1.
pub fn robot_id(selector: u8) -> RobotId {
    RobotId(selector.saturating_sub(1))
}

/// What the agent task is told.
#[derive(Clone, Debug)]
pub enum AgentInput {
    /// A message from the phone (the link task).
    Message(Message),
    /// The body finished an action (the control task, or the emulated
    /// board's body channel).
    Report(Report),
}

/// What the link task is asked to send.
#[derive(Clone, Debug)]
pub enum LinkOut {
    /// Reliably, in order.
    Reliable(Message),
    /// Best-effort.
    Datagram(Message),
}

/// What the body is told by the agent.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BodyCmd {
    /// An order to carry out.
    Order(Order),
    /// The line speed the phone asked for, steps/s.
    Speed(u16),
}

/// The behaviour stack of a real robot with the stored floor calibration
/// (raw black and white levels), if it is valid.
pub fn behaviour(black: [u16; 3], white: [u16; 3]) -> BehaviourBody {
    BehaviourBody::new(Robot::new(
        Config::EPUCK,
        Calibration::new(black, white).ok(),
    ))
}

/// What the control step sees, refreshed every 10 ms.
#[derive(Clone, Copy, Debug, Default, defmt::Format)]
pub struct SensorImage {
    /// Raw ground deltas (left, centre, right); zero without the module.
    pub ground_raw: [u16; 3],
    /// Whether the ground read of this cycle succeeded.
    pub ground_ok: bool,
    /// Proximity values IR0..IR7 (0 = nothing).
    pub prox: [u16; SENSORS],
    /// Wheel step counters (left, right).
    pub steps: (i32, i32),
}

impl SensorImage {
    /// The behaviour stack's view of it.
    pub fn sensors(&self) -> Sensors {
        Sensors {
            floor: self.ground_raw,
            proximity: self.prox,
            steps: StepCount {
                left: self.steps.0,
                right: self.steps.1,
            },
        }
    }
}

/// Runs the behaviour stack for `steps` control steps of line following
/// (the common case: PID on the floor sensors, node detector watching,
/// collision and abyss layers checking) and returns the milliseconds of
/// emulated time they took, and whether the robot was still following the
/// line at the end (so that every step did the full work). Under QEMU's `-icount shift=0` one instruction
/// is one nanosecond, so this counts instructions per step; see
/// docs/results/performance.md.
#[cfg(feature = "qemu")]
pub fn bench(steps: u32) -> (u32, bool) {
    use core_algo::agent::body::Order;
    let mut body = behaviour([300; 3], [900; 3]);
    body.robot_mut().place_on_node(StepCount::default());
    let _ = body.order(Order::Move);
    let mut sensors = Sensors {
        floor: [900, 300, 900],
        proximity: [40; 8],
        steps: StepCount::default(),
    };
    let t0 = crate::now_ms();
    for i in 0..steps {
        // Drifting a little left and right of the line, moving 6 steps per
        // 10 ms (600 steps/s).
        let drift = if i % 16 < 8 { 30 } else { 0 };
        sensors.floor = [880 - drift, 300 + drift / 2, 860 + drift];
        sensors.steps.left += 6;
        sensors.steps.right += 6;
        let (w, _) = body.step(core::hint::black_box(&sensors));
        core::hint::black_box(w);
    }
    let ms = crate::now_ms().wrapping_sub(t0);
    (
        ms,
        body.robot().mode() == core_algo::behaviour::Mode::Moving,
    )
}
