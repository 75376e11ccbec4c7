//! The observable model of the phone side (the seed's `Environment`): the
//! team's merged map, what every robot is doing, and the statistics.
//!
//! Views never touch it directly: they [`Environment::subscribe`] and
//! receive [`Update`]s over a channel, so the model can live in one thread
//! (the simulation's or the server's) with no shared mutable state.

use core_algo::geometry::{Arms, Pos};
use core_algo::map::{Block, Bounds, KnownMap, MapError, blocks_for};
use core_algo::protocol::Pose;
use core_algo::protocol::message::RobotState;
use core_algo::protocol::resync::NodeLogEntry;
use core_algo::team::RobotId;
use std::sync::mpsc;

/// What the phone side knows about one robot.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RobotInfo {
    /// Its id.
    pub id: RobotId,
    /// Last reported pose.
    pub pose: Option<Pose>,
    /// Its start node.
    pub home: Option<Pos>,
    /// Its announced target.
    pub target: Option<Pos>,
    /// Last reported state.
    pub state: RobotState,
    /// Whether its link is up.
    pub link_up: bool,
    /// Whether a person steers it.
    pub manual: bool,
    /// Nodes it was the first to report.
    pub explored: u32,
    /// Nodes it reported (every arrival).
    pub driven: u32,
    /// Arrivals at nodes it had reported before.
    pub revisits: u32,
    /// Collisions it reported.
    pub collisions: u32,
    /// Messages received from it.
    pub messages: u32,
    /// It said the team is done.
    pub finished: bool,
    /// Considered failed (link lost for good, or it gave up).
    pub failed: bool,
    /// The path it drove, node by node (for the map's trails).
    pub trail: Vec<Pos>,
    /// The nodes it reported, to count revisits in O(1).
    pub seen: std::collections::HashSet<Pos>,
}

impl RobotInfo {
    fn new(id: RobotId) -> Self {
        RobotInfo {
            id,
            pose: None,
            home: None,
            target: None,
            state: RobotState::Idle,
            link_up: false,
            manual: false,
            explored: 0,
            driven: 0,
            revisits: 0,
            collisions: 0,
            messages: 0,
            finished: false,
            failed: false,
            trail: Vec::new(),
            seen: std::collections::HashSet::new(),
        }
    }
}

/// Team-wide counters.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Statistics {
    /// Messages received from robots.
    pub received: u64,
    /// Messages relayed to robots.
    pub relayed: u64,
    /// Messages no handler took.
    pub unhandled: u64,
    /// Reports that contradicted the map (logged, not applied).
    pub conflicts: u64,
    /// Messages from robot ids the phone does not know.
    pub unknown_robots: u64,
    /// Corrupt frames dropped by the links.
    pub link_errors: u64,
    /// Frames sent again by the links.
    pub retransmissions: u64,
    /// Times a link was lost.
    pub link_losses: u64,
    /// (time in ms, nodes with known shape) after every change.
    pub coverage: Vec<(u32, u32)>,
}

/// A change the views should show.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Update {
    /// A node became known or was visited again.
    Node {
        /// The node.
        pos: Pos,
        /// Its arms.
        arms: Arms,
        /// Visits so far.
        visits: u8,
    },
    /// A robot's info changed.
    Robot(Box<RobotInfo>),
    /// The team is done.
    Finished {
        /// Time of the last robot's finish, ms.
        at_ms: u32,
    },
    /// A line for the log view.
    Log(String),
}

/// The phone side's model; see the module docs.
pub struct Environment {
    map: KnownMap<Vec<Block>>,
    log: Vec<NodeLogEntry>,
    robots: Vec<RobotInfo>,
    stats: Statistics,
    subscribers: Vec<mpsc::Sender<Update>>,
    finished_at: Option<u32>,
    now: u32,
}

impl Environment {
    /// A model for `robots` robots whose map covers `bounds`.
    pub fn new(bounds: Bounds, robots: usize) -> Self {
        let map = KnownMap::new(vec![Block::EMPTY; blocks_for(bounds.area())], bounds)
            .unwrap_or_else(|e| unreachable!("storage sized for the bounds: {e}"));
        Environment {
            map,
            log: Vec::new(),
            robots: (0..robots)
                .map(|i| RobotInfo::new(RobotId(i as u8)))
                .collect(),
            stats: Statistics::default(),
            subscribers: Vec::new(),
            finished_at: None,
            now: 0,
        }
    }

    /// A channel that receives every later [`Update`].
    pub fn subscribe(&mut self) -> mpsc::Receiver<Update> {
        let (tx, rx) = mpsc::channel();
        self.subscribers.push(tx);
        rx
    }

    fn publish(&mut self, u: Update) {
        if self.subscribers.is_empty() {
            return;
        }
        self.subscribers.retain(|s| s.send(u.clone()).is_ok());
    }

    /// Sets the clock (ms) used to stamp statistics.
    pub fn set_now(&mut self, now: u32) {
        self.now = now;
    }

    /// The merged map.
    pub fn map(&self) -> &KnownMap<Vec<Block>> {
        &self.map
    }

    /// The team's node log, in relay order (for resynchronisation).
    pub fn node_log(&self) -> &[NodeLogEntry] {
        &self.log
    }

    /// Every robot.
    pub fn robots(&self) -> &[RobotInfo] {
        &self.robots
    }

    /// One robot.
    pub fn robot(&self, id: RobotId) -> Option<&RobotInfo> {
        self.robots.get(id.index())
    }

    /// The counters.
    pub fn stats(&self) -> &Statistics {
        &self.stats
    }

    /// Counters, for the parts of the phone side that count (links,
    /// handlers).
    pub fn stats_mut(&mut self) -> &mut Statistics {
        &mut self.stats
    }

    /// When the team finished, if it did.
    pub fn finished_at(&self) -> Option<u32> {
        self.finished_at
    }

    /// Changes a robot's info and tells the views.
    pub fn update_robot(&mut self, id: RobotId, f: impl FnOnce(&mut RobotInfo)) -> bool {
        let Some(r) = self.robots.get_mut(id.index()) else {
            self.stats.unknown_robots += 1;
            return false;
        };
        f(r);
        // Snapshots cost a copy of the robot's trail: only for listeners.
        if !self.subscribers.is_empty() {
            let snapshot = Box::new(r.clone());
            self.publish(Update::Robot(snapshot));
        }
        true
    }

    /// Records a node report of robot `id`; returns whether the map took it
    /// (a conflicting report is counted and not applied).
    pub fn node_hit(&mut self, id: RobotId, pose: Pose, arms: Arms) -> bool {
        if self.robot(id).is_none() {
            self.stats.unknown_robots += 1;
            return false;
        }
        let known_before = self.map.cell(pose.pos).is_visited();
        let result = self.map.visit(pose.pos, arms, id);
        let ok = match result {
            Ok(_) => true,
            Err(MapError::Conflict(c)) => {
                self.stats.conflicts += 1;
                self.publish(Update::Log(format!(
                    "robot {id}: conflicting report, not applied: {c}"
                )));
                false
            }
            Err(e) => {
                self.stats.conflicts += 1;
                self.publish(Update::Log(format!("robot {id}: {e}")));
                false
            }
        };
        let visits = self.map.cell(pose.pos).visits();
        self.update_robot(id, |r| {
            // The same node again is a robot telling its new heading (after
            // a collision), not a drive.
            let moved = r.pose.map(|p| p.pos) != Some(pose.pos);
            r.pose = Some(pose);
            r.home.get_or_insert(pose.pos);
            if moved {
                r.driven += 1;
                if !r.seen.insert(pose.pos) {
                    r.revisits += 1;
                }
            }
            if ok && !known_before {
                r.explored += 1;
            }
            if r.trail.last() != Some(&pose.pos) {
                r.trail.push(pose.pos);
            }
        });
        if ok {
            self.log.push(NodeLogEntry {
                origin: id,
                pose,
                arms,
            });
            self.publish(Update::Node {
                pos: pose.pos,
                arms,
                visits,
            });
            let known = self.known_nodes();
            self.stats.coverage.push((self.now, known));
        }
        ok
    }

    /// Nodes whose shape is known: visited, or deduced from four visited
    /// neighbours.
    pub fn known_nodes(&self) -> u32 {
        self.map.known_len() as u32
    }

    /// Marks the team done at `now` once every robot finished or failed.
    pub fn check_finished(&mut self) {
        if self.finished_at.is_none()
            && !self.robots.is_empty()
            && self.robots.iter().all(|r| r.finished || r.failed)
        {
            self.finished_at = Some(self.now);
            self.publish(Update::Finished { at_ms: self.now });
        }
    }

    /// A line for the log view.
    pub fn log_line(&mut self, line: String) {
        self.publish(Update::Log(line));
    }
}
