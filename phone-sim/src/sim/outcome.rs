//! What a run measured: completion, the map against the truth, makespan,
//! per-robot figures, link statistics and how localization went.

use super::Simulation;
use super::body::Bodies;
use super::localize;
use crate::environment::Environment;
use crate::field::Field;
use core_algo::localize::{Failure, Progress};
use core_algo::team::RobotId;

/// The result of a run on `field` from the phone's model `env` and the
/// `bodies` on the true field: shared by the simulator and the runs with
/// emulated firmware (`crate::qemu`). `frames` is (sent, lost); `to_team`
/// maps the true frame into the team's (the identity with known poses).
pub fn outcome_of(
    field: &Field,
    env: &Environment,
    bodies: &Bodies,
    alive: &[bool],
    makespan_ms: u32,
    frames: (u64, u64),
    to_team: core_algo::localize::Frame,
) -> Outcome {
    let map = env.map();
    let map_correct = field
        .nodes()
        .iter()
        .all(|(p, a)| map.known_arms(to_team.pos(*p)) == Some(a.rotated_cw(to_team.quarter_turns)));
    let all_home = bodies
        .bodies()
        .iter()
        .zip(field.starts())
        .zip(alive)
        .all(|((b, s), alive)| !alive || (b.pos == s.pos && b.is_idle()));
    let robots = bodies
        .bodies()
        .iter()
        .zip(env.robots())
        .zip(alive)
        .map(|((b, r), alive)| RobotOutcome {
            id: r.id,
            alive: *alive,
            explored: r.explored,
            driven_edges: b.stats.edges,
            quarter_turns: b.stats.quarter_turns,
            revisits: b.stats.revisits,
            collisions: b.stats.collisions,
        })
        .collect();
    let stats = env.stats();
    Outcome {
        complete: map_correct && all_home && map.is_complete(),
        map_correct,
        all_home,
        makespan_ms,
        robots,
        frames_sent: frames.0,
        frames_lost: frames.1,
        retransmissions: stats.retransmissions,
        messages: stats.received,
        relayed: stats.relayed,
        conflicts: stats.conflicts,
        unhandled: stats.unhandled,
        localization: None,
        mapped_ms: None,
        timed_out: false,
    }
}

impl Simulation {
    /// How localization went, checked against the truth.
    pub(super) fn localization(&self) -> Localization {
        let starts = self.field.starts();
        let mut poses_correct = true;
        let mut failure = None;
        for (i, f) in self.firmware.iter().enumerate() {
            match f.agent().localizer().progress() {
                Progress::Done(frame) => {
                    poses_correct &= localize::expected_frame(starts, i) == Some(frame);
                }
                Progress::Failed(why) => {
                    poses_correct = false;
                    failure.get_or_insert(why);
                }
                Progress::Running => poses_correct = false,
            }
        }
        let localized_ms = self
            .localized_at
            .iter()
            .copied()
            .collect::<Option<Vec<u32>>>()
            .and_then(|t| t.into_iter().max());
        Localization {
            localized_ms,
            poses_correct,
            failure,
            moves: self
                .firmware
                .iter()
                .map(|f| f.agent().localizer().steps())
                .sum(),
        }
    }
}

/// How localization went in a run.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Localization {
    /// When the last robot joined the team frame, ms (`None`: not all
    /// did).
    pub localized_ms: Option<u32>,
    /// Every robot ended with its true pose relative to robot 0.
    pub poses_correct: bool,
    /// Why localization gave up, if it did.
    pub failure: Option<Failure>,
    /// Moves the team made while localizing.
    pub moves: u32,
}

/// Per-robot figures of a run.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RobotOutcome {
    /// The robot.
    pub id: RobotId,
    /// Whether it survived.
    pub alive: bool,
    /// Nodes it reported first.
    pub explored: u32,
    /// Edges it drove.
    pub driven_edges: u32,
    /// Quarter turns it made.
    pub quarter_turns: u32,
    /// Arrivals at nodes it had visited before.
    pub revisits: u32,
    /// Collisions it had.
    pub collisions: u32,
}

/// The result of a run.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Outcome {
    /// Every node's shape known correctly, no frontier left, every living
    /// robot home.
    pub complete: bool,
    /// The phone's merged map equals the true field.
    pub map_correct: bool,
    /// Every living robot stands on its start node.
    pub all_home: bool,
    /// Until every living robot said the team is done and stood still (or
    /// the run stopped), ms.
    pub makespan_ms: u32,
    /// Per robot.
    pub robots: Vec<RobotOutcome>,
    /// Frames offered to the channels.
    pub frames_sent: u64,
    /// Frames the channels lost.
    pub frames_lost: u64,
    /// Frames the links sent again.
    pub retransmissions: u64,
    /// Messages the phone received.
    pub messages: u64,
    /// Messages the phone relayed.
    pub relayed: u64,
    /// Conflicting reports.
    pub conflicts: u64,
    /// Messages no handler took.
    pub unhandled: u64,
    /// How localization went (`None`: start poses were given).
    pub localization: Option<Localization>,
    /// When the phone's merged map first had no frontier left, ms (`None`:
    /// never, or not tracked). The rest of the makespan is the way home.
    pub mapped_ms: Option<u32>,
    /// The run reached `SimConfig::max_time_ms` before the team was done.
    pub timed_out: bool,
}
