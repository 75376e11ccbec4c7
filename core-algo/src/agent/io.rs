//! What goes in and out of an agent: events, commands, modes, settings.

use crate::geometry::{Arms, Heading, Pos, Turn};
use crate::localize::{Localize, LocalizeMethod};
use crate::map::MapError;
use crate::team::RobotId;
use crate::timing::Timing;

use super::Millis;

/// What the agent is doing.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Mode {
    /// Not started.
    Idle,
    /// Agreeing on a frame with the team (see `localize`).
    Localize,
    /// Driving to frontier nodes.
    Explore,
    /// Nothing reachable left for this robot: driving home.
    Return,
    /// Home, and the team is done.
    Finished,
    /// A person steers.
    Manual,
    /// Gave up after repeated refusals or an inconsistent start.
    Error,
}

/// News about another robot, relayed by the phone side.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum PeerNews {
    /// It reached node `pos` facing `heading`, and the node has `arms`.
    NodeHit {
        /// The node.
        pos: Pos,
        /// The way it faces.
        heading: Heading,
        /// The node's arms, in the global frame.
        arms: Arms,
    },
    /// It announced its target (`None`: it has none).
    Intent {
        /// The frontier node it is driving to.
        target: Option<Pos>,
    },
    /// It is known to stand at a start pose (sent once at the start).
    Start {
        /// Its start node and home.
        pos: Pos,
        /// Its start heading.
        heading: Heading,
    },
    /// It failed (link lost, stuck): forget its target.
    Failed,
    /// Its part of agreeing on a frame (see `localize`).
    Localize(Localize),
}

/// A manual order from the person steering this robot.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum ManualOrder {
    /// Take over: finish the current edge, then wait for orders.
    Take,
    /// Hand back: explore again.
    Release,
    /// Turn on the node.
    Turn(Turn),
    /// Drive one edge straight on (refused where no arm is known).
    Move,
}

/// Something that happened to or around the robot.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Event {
    /// Begin at a pose of the team's frame.
    Start {
        /// The start node: this robot's home.
        pos: Pos,
        /// The start heading.
        heading: Heading,
    },
    /// Begin without a known pose: agree on a frame with a team of `team`
    /// robots first, by `method`, then explore. The robot's own frame has
    /// its start node at the origin, facing north.
    StartLocalize {
        /// Local (adjacent starts) or global (any starts).
        method: LocalizeMethod,
        /// The team to wait for, this robot included.
        team: u8,
    },
    /// The robot stands on a node, with arms relative to its heading (bit 0
    /// ahead, 1 right, 2 behind, 3 left), as its floor sensors saw them.
    NodeHit {
        /// Arms relative to the robot.
        relative: Arms,
    },
    /// The robot met an obstacle on its edge and is back on the node it
    /// left, facing back the way it came.
    Collision,
    /// The robot refused the last command.
    Rejected,
    /// Standing still, the robot saw another robot come close from
    /// `toward` and turn back: it stands in someone's way.
    Bumped {
        /// Where the other robot came from.
        toward: Heading,
    },
    /// News about another robot.
    Peer(RobotId, PeerNews),
    /// An order from the person steering.
    Manual(ManualOrder),
    /// Time passes: timeouts and back-offs.
    Tick,
}

/// An order to the robot's body or a message for the team.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Command {
    /// Turn on the spot.
    Turn(Turn),
    /// Drive along the line to the next node.
    Move,
    /// Tell the team about this node (relayed to everyone).
    Report {
        /// The node.
        pos: Pos,
        /// Its arms, global frame.
        arms: Arms,
        /// The robot's heading there.
        heading: Heading,
    },
    /// Tell the team this robot's target (`None`: no target).
    Announce {
        /// The frontier node.
        target: Option<Pos>,
    },
    /// Tell the team this robot's part of localization (relayed).
    Localize(Localize),
    /// This robot is home and the team is done.
    Finished,
    /// Stop everything (error).
    Stop,
}

/// Tunables of the agent.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct AgentConfig {
    /// The one truth about timing.
    pub timing: Timing,
    /// A teammate silent for longer counts as failed.
    pub peer_timeout_ms: Millis,
    /// First back-off after a collision or refusal; doubled each retry.
    pub backoff_ms: Millis,
}

impl Default for AgentConfig {
    fn default() -> Self {
        AgentConfig {
            timing: Timing::DEFAULT,
            peer_timeout_ms: 30_000,
            backoff_ms: 400,
        }
    }
}

/// Why the agent could not take an event.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum AgentError {
    /// The map refused the robot's own observation.
    Map(MapError),
    /// The event does not fit the current state (counted, ignored).
    Unexpected,
}
