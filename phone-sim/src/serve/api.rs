//! What the page and `conquest serve` say to each other, as JSON.
//!
//! The page sends [`Command`]s (over the WebSocket, or `POST /api/control`);
//! the server pushes one [`Snapshot`] when a page connects and then a
//! [`Frame`] of changes about ten times a second. Frames only ever add or
//! replace, so a page that missed some asks for a new snapshot and is whole
//! again. Positions are lattice coordinates (x east, y north).

use core_algo::geometry::Turn;
use serde::{Deserialize, Serialize};

/// A person's request.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum Command {
    /// Start a new simulation (fields left out keep their current values).
    Start {
        /// Field name from the list the server offers.
        #[serde(default)]
        field: Option<String>,
        /// Team size.
        #[serde(default)]
        robots: Option<usize>,
        /// Strategy name.
        #[serde(default)]
        strategy: Option<String>,
        /// Seed of the run.
        #[serde(default)]
        seed: Option<u64>,
    },
    /// Freeze the run.
    Pause,
    /// Go on after a pause.
    Resume,
    /// End the run; the map stays on screen.
    Stop,
    /// Simulated seconds per wall-clock second; 0 runs as fast as the
    /// machine can.
    Rate {
        /// The factor, 0..=1000.
        x: f64,
    },
    /// Take or hand back manual control of a robot.
    Manual {
        /// The robot.
        robot: u8,
        /// Take (true) or hand back (false).
        on: bool,
    },
    /// Turn a manually steered robot on its node.
    Turn {
        /// The robot.
        robot: u8,
        /// Which way.
        turn: TurnName,
    },
    /// Drive a manually steered robot one edge straight on.
    Move {
        /// The robot.
        robot: u8,
    },
    /// Set a robot's line speed.
    Speed {
        /// The robot.
        robot: u8,
        /// Motor steps per second, 100..=1000.
        steps_per_s: u16,
    },
    /// Cut a robot's link for a while (simulation only: shows how the team
    /// copes and the page shows the loss).
    CutLink {
        /// The robot.
        robot: u8,
        /// For how long, seconds.
        seconds: f64,
    },
}

/// A turn, as the page names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum TurnName {
    /// 90° counter-clockwise.
    Left,
    /// 90° clockwise.
    Right,
    /// 180°.
    Back,
}

impl From<TurnName> for Turn {
    fn from(t: TurnName) -> Turn {
        match t {
            TurnName::Left => Turn::Left,
            TurnName::Right => Turn::Right,
            TurnName::Back => Turn::UTurn,
        }
    }
}

/// Where the run is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RunStatus {
    /// Set up, waiting for Start.
    Ready,
    /// Time runs.
    Running,
    /// Frozen by a person.
    Paused,
    /// The team is done (the world still runs for manual steering).
    Finished,
    /// Stopped by a person.
    Stopped,
}

/// What is being run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunInfo {
    /// `sim` (the simulator) or `robots` (real robots on serial ports).
    pub mode: String,
    /// Field name.
    pub field: String,
    /// Team size.
    pub robots: usize,
    /// Strategy name.
    pub strategy: String,
    /// Seed.
    pub seed: u64,
    /// Reachable nodes of the true field, when known (simulation).
    pub total_nodes: Option<u32>,
    /// The map window: x, y of the south-west corner, width, height.
    pub bounds: [i32; 4],
    /// Lower bound of the makespan with return home, seconds (simulation).
    pub lower_bound_s: Option<f64>,
}

/// The choices the page offers for a new run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Choices {
    /// Field names, with their start-pose counts.
    pub fields: Vec<FieldChoice>,
    /// Strategy names.
    pub strategies: Vec<String>,
}

/// One field the page can choose.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FieldChoice {
    /// Its name.
    pub name: String,
    /// Start poses (the most robots it takes).
    pub starts: usize,
    /// Nodes.
    pub nodes: usize,
}

/// One node of the map: x, y, arms (bit 0 north, 1 east, 2 south, 3 west),
/// visits (0 for a node deduced from its four visited neighbours).
pub type NodeView = [i32; 4];

/// One robot as the page draws and lists it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RobotView {
    /// Id.
    pub id: u8,
    /// Where to draw it (between two nodes while driving).
    pub x: f64,
    /// Where to draw it.
    pub y: f64,
    /// Heading: 0 north, 1 east, 2 south, 3 west.
    pub heading: u8,
    /// The node it stands on or last left.
    pub node: Option<[i32; 2]>,
    /// Its announced target.
    pub target: Option<[i32; 2]>,
    /// Its home.
    pub home: Option<[i32; 2]>,
    /// What it says it does.
    pub state: String,
    /// Link up.
    pub link_up: bool,
    /// Steered by a person.
    pub manual: bool,
    /// Given up on (link lost, or it stopped).
    pub failed: bool,
    /// It said the team is done.
    pub finished: bool,
    /// Nodes it reported first.
    pub explored: u32,
    /// Node arrivals it reported.
    pub driven: u32,
    /// Arrivals at nodes it had reported before.
    pub revisits: u32,
    /// Collisions.
    pub collisions: u32,
    /// Messages received from it.
    pub messages: u32,
    /// Its line speed, motor steps per second.
    pub speed: u16,
}

/// Team counters.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct StatsView {
    /// Nodes whose shape is known.
    pub known: u32,
    /// Frontier nodes.
    pub frontier: u32,
    /// Messages received from robots.
    pub received: u64,
    /// Messages relayed.
    pub relayed: u64,
    /// Messages no handler took.
    pub unhandled: u64,
    /// Conflicting reports.
    pub conflicts: u64,
    /// Corrupt frames dropped.
    pub link_errors: u64,
    /// Frames sent again.
    pub retransmissions: u64,
    /// Link losses.
    pub link_losses: u64,
}

/// The result of a finished run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunResult {
    /// Every reachable node known, the map right, every living robot home.
    pub complete: bool,
    /// Until the team was done, seconds.
    pub makespan_s: f64,
    /// The lower bound with return home, seconds (simulation).
    pub lower_bound_s: Option<f64>,
}

/// Everything the page shows, sent when it connects.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Snapshot {
    /// What runs.
    pub run: RunInfo,
    /// Where the run is.
    pub status: RunStatus,
    /// Run time, ms (simulated time in a simulation).
    pub t_ms: u32,
    /// Simulated seconds per wall second (0: as fast as possible).
    pub rate: f64,
    /// Every known node.
    pub nodes: Vec<NodeView>,
    /// Every frontier node.
    pub frontier: Vec<[i32; 2]>,
    /// Every robot.
    pub robots: Vec<RobotView>,
    /// Each robot's path, node by node.
    pub trails: Vec<Vec<[i32; 2]>>,
    /// Counters.
    pub stats: StatsView,
    /// (time ms, known nodes) samples.
    pub coverage: Vec<[u32; 2]>,
    /// The last log lines.
    pub log: Vec<String>,
    /// The result, once done.
    pub result: Option<RunResult>,
    /// What a new run may use.
    pub choices: Choices,
}

/// Changes since the last frame.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Frame {
    /// Run time, ms.
    pub t_ms: u32,
    /// Where the run is.
    pub status: Option<RunStatus>,
    /// Nodes that became known or were visited again.
    pub nodes: Vec<NodeView>,
    /// The whole frontier, when it changed.
    pub frontier: Option<Vec<[i32; 2]>>,
    /// Every robot.
    pub robots: Vec<RobotView>,
    /// New trail nodes: (robot, x, y).
    pub trail_add: Vec<[i32; 3]>,
    /// Counters.
    pub stats: StatsView,
    /// New coverage samples.
    pub coverage_add: Vec<[u32; 2]>,
    /// New log lines.
    pub log_add: Vec<String>,
    /// The result, once done.
    pub result: Option<RunResult>,
}

/// What the server pushes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum Push {
    /// The whole state (on connect, after Start).
    Snapshot(Box<Snapshot>),
    /// Changes.
    Frame(Box<Frame>),
    /// A request failed; only the page that sent it gets this.
    Error {
        /// Why.
        message: String,
    },
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn commands_read_from_the_json_the_page_sends() {
        let c: Command = serde_json::from_str(r#"{"type":"turn","robot":2,"turn":"left"}"#)
            .expect("valid command");
        assert_eq!(
            c,
            Command::Turn {
                robot: 2,
                turn: TurnName::Left
            }
        );
        let c: Command = serde_json::from_str(r#"{"type":"start","robots":3}"#).expect("start");
        assert_eq!(
            c,
            Command::Start {
                field: None,
                robots: Some(3),
                strategy: None,
                seed: None
            }
        );
        assert_eq!(Turn::from(TurnName::Back), Turn::UTurn);
    }

    #[test]
    fn malformed_commands_are_errors_not_panics() {
        for bad in [
            "",
            "{}",
            r#"{"type":"fly"}"#,
            r#"{"type":"turn","robot":2,"turn":"up"}"#,
            r#"{"type":"move","robot":-1}"#,
            r#"{"type":"move","robot":256}"#,
            "[1,2,3]",
        ] {
            assert!(serde_json::from_str::<Command>(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn pushes_are_tagged_by_type() {
        let p = Push::Error {
            message: "no".into(),
        };
        let text = serde_json::to_string(&p).expect("serialises");
        assert_eq!(text, r#"{"type":"error","message":"no"}"#);
        let f = Push::Frame(Box::default());
        let v: serde_json::Value =
            serde_json::from_str(&serde_json::to_string(&f).expect("serialises")).expect("json");
        assert_eq!(v["type"], "frame");
        assert!(v["robots"].is_array());
    }
}
