//! The typed messages that cross a link, and their postcard encoding.
//!
//! One enum, [`Message`], covers every direction (robot → phone, phone →
//! robot, and robot → robot broadcasts relayed by the phone) so that one
//! codec, one fuzz target and one round-trip test cover the whole protocol.
//! The byte layout is postcard's (varint integers, zigzag for signed ones,
//! a varint variant index for enums); `docs/protocol.md` spells out every
//! message. Fields use the project's own types ([`Pos`], [`Heading`],
//! [`Arms`], [`RobotId`], [`Turn`]); their serde impls live here, next to the
//! wire format they define, and reject out-of-range values on decode.

use heapless::String;
use serde::{Deserialize, Deserializer, Serialize, Serializer, de};

use crate::geometry::{Arms, Heading, Pos, Turn};
use crate::team::RobotId;

/// Longest log line in bytes.
///
/// Long enough for a short diagnostic ("pid sat l=1000 r=-1000"), short
/// enough that a log frame stays well inside [`MAX_MESSAGE_LEN`].
pub const LOG_TEXT_LEN: usize = 48;

/// Upper bound on the postcard encoding of any [`Message`], in bytes.
///
/// The largest message is a [`Message::Log`] with a full line: variant 1,
/// level 1, length 1 and text 48, i.e. 51 bytes. 64 leaves room for a
/// few more fields without changing the frame limits; a unit test checks
/// the bound against the largest values of every variant.
pub const MAX_MESSAGE_LEN: usize = 64;

/// A robot's pose on the lattice: the node it stands on and where it faces.
///
/// Every report that the phone turns into map knowledge carries the pose,
/// so a lost earlier message cannot shift later ones.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, Serialize, Deserialize)]
pub struct Pose {
    /// The node.
    pub pos: Pos,
    /// The heading.
    pub heading: Heading,
}

/// The firmware version a robot reports in its hello, semver style.
///
/// Lets the phone refuse or adapt to an older firmware instead of
/// misreading its messages.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, Default, Serialize, Deserialize)]
pub struct FirmwareVersion {
    /// Incompatible changes.
    pub major: u8,
    /// Compatible additions.
    pub minor: u8,
    /// Fixes.
    pub patch: u8,
}

/// What a robot is doing, as reported in [`Status`].
///
/// The states of the subsumption stack (seed §2.2) plus the link-level
/// ones the phone needs to show; the phone only displays and logs them.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, Serialize, Deserialize)]
pub enum RobotState {
    /// Powered up, not started.
    Idle,
    /// Calibrating the floor sensors.
    Calibrating,
    /// Scanning the node under it (first status after start).
    Scanning,
    /// Standing on a node, waiting for an order.
    Stopped,
    /// Line following towards the next node.
    Driving,
    /// Turning on a node.
    Turning,
    /// Under manual control from the phone.
    Manual,
    /// Stopped by the abyss layer.
    Abyss,
    /// Stopped by the collision layer.
    Collision,
    /// Exploration finished.
    Finished,
    /// A fault the robot cannot leave by itself.
    Error,
}

/// A robot's periodic report. Sent best-effort: a newer one replaces a
/// lost one, so it never occupies the reliable queue.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, Serialize, Deserialize)]
pub struct Status {
    /// Milliseconds since the robot booted (wraps after 49 days).
    pub uptime_ms: u32,
    /// Where the robot believes it is.
    pub pose: Pose,
    /// What it is doing.
    pub state: RobotState,
    /// Floor sensors seeing an abyss: bit 0 left, 1 middle, 2 right.
    pub floor: u8,
    /// Proximity sensors over threshold: bit i = IR sensor i (0 front,
    /// clockwise).
    pub proximity: u8,
}

/// Why a robot refused a command (the 2010 firmware only said "rejected").
///
/// The reason lets the phone distinguish "try again later" from "never".
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, Serialize, Deserialize)]
pub enum RejectReason {
    /// Another command is still being carried out.
    Busy,
    /// The command is not allowed in the current state.
    WrongState,
    /// A move was ordered but the node has no arm ahead.
    NoArm,
    /// A parameter is out of range.
    BadArgument,
    /// The firmware does not implement the command.
    Unsupported,
}

/// The result of a floor-sensor calibration (seed §2.3): the three sensors'
/// readings on the line and on the background.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, Serialize, Deserialize)]
pub struct Calibration {
    /// Readings on the line: left, middle, right.
    pub line: [u16; 3],
    /// Readings on the background: left, middle, right.
    pub background: [u16; 3],
    /// Whether the robot accepted the values (enough contrast).
    pub ok: bool,
}

/// Severity of a [`Message::Log`] line.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, Serialize, Deserialize)]
pub enum LogLevel {
    /// Something failed.
    Error,
    /// Something looks wrong.
    Warn,
    /// Normal progress.
    Info,
    /// Details for debugging.
    Debug,
}

/// Which exploration strategy a robot runs, chosen by the phone at start.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, Serialize, Deserialize)]
pub enum StrategyKind {
    /// Drive to the nearest frontier node (Yamauchi 1998).
    NearestFrontier,
    /// Nearest frontier, penalising targets announced by team mates.
    Coordinated,
    /// Do nothing by itself; the phone sends every turn and move.
    Remote,
}

/// Settings sent with [`Message::Start`].
///
/// Grouped in one struct so that adding a setting changes one type, not the
/// variant list.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, Serialize, Deserialize)]
pub struct StrategySettings {
    /// The strategy.
    pub kind: StrategyKind,
    /// Number of robots in the team (for id-based tie-breaking).
    pub team_size: u8,
    /// Line speed in motor steps per second.
    pub speed: u16,
}

/// Why a robot gave up (relayed to the team so that it plans around it).
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, Serialize, Deserialize)]
pub enum FailureKind {
    /// It stands at an abyss.
    Abyss,
    /// Its link to the phone was lost.
    LinkLost,
    /// An obstacle blocks its node.
    NodeObstruction,
    /// It reported a shape that contradicts the map.
    InconsistentMap,
}

/// The localization exchange between robots (seed §4.2–4.3; see
/// `docs/localization.md`). Only the robot holding the turn moves, so every
/// contact has one active robot (it drove) and one passive partner (it
/// stood); each side reports its half and every robot joins the two halves.
/// Poses are in the sender's own frame (its start node the origin, its
/// start heading north).
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, Serialize, Deserialize)]
pub enum Localize {
    /// Active half of a contact: "driving from `pose` I touched a robot".
    Collision {
        /// The sender's pose when it set off towards the partner.
        pose: Pose,
    },
    /// The sender's turn is over; it now stands at `pose`.
    Pass {
        /// Where it stands and faces.
        pose: Pose,
    },
    /// The sender has joined the team frame and explores.
    Finished,
    /// Passive half of a contact: "robot `by` touched me; it stood at
    /// `seen`".
    Bumped {
        /// The robot that drove into the sender.
        by: RobotId,
        /// The driving robot's pose, the sender's own frame.
        seen: Pose,
    },
    /// The sender scanned its start node and waits for its turn.
    Ready,
}

/// A robot-to-robot broadcast, relayed by the phone inside
/// [`Message::Relayed`] with the origin robot's id.
#[derive(Clone, PartialEq, Eq, Hash, Debug, Serialize, Deserialize)]
pub enum Broadcast {
    /// Another robot reached a node (also used to stream missed map
    /// entries during a resync).
    NodeHit {
        /// Its pose on arrival.
        pose: Pose,
        /// The node's arms in the global frame.
        arms: Arms,
    },
    /// Another robot announced (or, with `None`, withdrew) its target.
    Intent {
        /// The announced target node.
        target: Option<Pos>,
    },
    /// Another robot failed.
    Failure {
        /// Why.
        kind: FailureKind,
    },
    /// A localization message.
    Localize(Localize),
}

/// Everything that crosses a link.
///
/// Variant order is the wire's variant index: append new variants at the end
/// of their group's numbering (see `docs/protocol.md`), never reorder.
#[derive(Clone, PartialEq, Eq, Hash, Debug, Serialize, Deserialize)]
pub enum Message {
    // ---- robot → phone -------------------------------------------------
    /// First message after (re)connecting: who I am, which firmware.
    Hello {
        /// The robot's id.
        robot: RobotId,
        /// Its firmware version.
        firmware: FirmwareVersion,
    },
    /// Periodic status report.
    Status(Status),
    /// Arrived at a node (global frame).
    NodeHit {
        /// Pose on arrival.
        pose: Pose,
        /// The node's arms in the global frame.
        arms: Arms,
    },
    /// The target the robot now heads for (`None`: no target).
    Intent {
        /// The announced target node.
        target: Option<Pos>,
    },
    /// A collision is imminent; the robot stopped.
    Collision {
        /// Proximity sensors over threshold, bit i = IR i.
        proximity: u8,
    },
    /// The floor sensors see an abyss; the robot stopped.
    Abyss {
        /// Floor sensors over the abyss: bit 0 left, 1 middle, 2 right.
        floor: u8,
    },
    /// The command sent in reliable frame `command` was carried out.
    Ack {
        /// The link sequence number of the command's frame.
        command: u16,
    },
    /// The command sent in reliable frame `command` was refused.
    Reject {
        /// The link sequence number of the command's frame.
        command: u16,
        /// Why.
        reason: RejectReason,
    },
    /// Floor-sensor calibration finished.
    Calibrated(Calibration),
    /// A log line for the phone's console.
    Log {
        /// Severity.
        level: LogLevel,
        /// The text, at most [`LOG_TEXT_LEN`] bytes of UTF-8.
        text: String<LOG_TEXT_LEN>,
    },
    /// After a reconnect: "I hold the first `have` entries of the team's
    /// node log; send me the rest". The phone answers with
    /// [`Broadcast::NodeHit`]s and [`Message::ResyncDone`].
    ResyncRequest {
        /// Number of node-log entries the robot already has.
        have: u32,
    },

    // ---- phone → robot -------------------------------------------------
    /// Forget everything and go back to idle.
    Reset,
    /// Start exploring from `pose`.
    Start {
        /// The robot's start pose.
        pose: Pose,
        /// How to explore.
        settings: StrategySettings,
    },
    /// Turn on the spot.
    Turn(Turn),
    /// Follow the line ahead to the next node.
    Move,
    /// Set the line speed.
    SetSpeed {
        /// Motor steps per second.
        steps_per_s: u16,
    },
    /// Set the LEDs: bits 0..=7 ring LEDs (0 front, clockwise), bit 8 front
    /// LED, bit 9 body LED.
    SetLeds {
        /// The LED mask.
        mask: u16,
    },
    /// Switch manual control on or off.
    Manual {
        /// On?
        on: bool,
    },
    /// Stop where you are (after the current node).
    Stop,
    /// Resume after [`Message::Stop`].
    Resume,
    /// Send a [`Message::Status`] now.
    RequestStatus,
    /// End of a resync stream: the team's node log now has `total` entries.
    ResyncDone {
        /// Length of the node log, including what was just streamed.
        total: u32,
    },

    // ---- relayed -------------------------------------------------------
    /// A broadcast from robot `origin`, relayed by the phone.
    Relayed {
        /// The robot that sent the broadcast.
        origin: RobotId,
        /// What it said.
        broadcast: Broadcast,
    },

    // ---- phone → robot, appended --------------------------------------
    /// Start without a known pose: agree on a frame with the team first
    /// (seed §4.2–4.3), then explore. The robot's own frame has its start
    /// node at the origin and its start heading north.
    StartLocalize {
        /// Local (adjacent starts) or global (any starts).
        method: LocalizeMethod,
        /// How to explore afterwards; `team_size` is the team to wait for.
        settings: StrategySettings,
    },
}

/// How a team started with [`Message::StartLocalize`] finds its frame.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, Serialize, Deserialize)]
pub enum LocalizeMethod {
    /// The robots stand on adjacent nodes (seed §4.2).
    Local,
    /// The robots stand anywhere (seed §4.3).
    Global,
}

/// Why a message could not be encoded or decoded.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub enum MessageError {
    /// The output buffer is too small.
    BufferFull,
    /// The bytes are not a valid message.
    Invalid,
    /// The bytes hold a valid message followed by extra bytes.
    TrailingBytes,
}

impl Message {
    /// Whether the message needs reliable, in-order delivery.
    ///
    /// Status and log lines are superseded by the next one, so they are sent
    /// as best-effort datagrams and never block commands in the queue.
    pub fn is_reliable(&self) -> bool {
        !matches!(self, Message::Status(_) | Message::Log { .. })
    }

    /// Encodes into `buf`, returning the used prefix.
    pub fn encode<'b>(&self, buf: &'b mut [u8]) -> Result<&'b mut [u8], MessageError> {
        postcard::to_slice(self, buf).map_err(|_| MessageError::BufferFull)
    }

    /// Decodes exactly one message that fills all of `bytes`.
    ///
    /// Trailing bytes are an error so that every message has exactly one
    /// encoding the receiver accepts.
    pub fn decode(bytes: &[u8]) -> Result<Message, MessageError> {
        match postcard::take_from_bytes::<Message>(bytes) {
            Ok((m, [])) => Ok(m),
            Ok(_) => Err(MessageError::TrailingBytes),
            Err(_) => Err(MessageError::Invalid),
        }
    }
}

// ---- serde for the geometry types --------------------------------------
// They live in this crate, so the impls may live here, beside the wire
// format they define, instead of spreading serde over the geometry module.

impl Serialize for Pos {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        (self.x, self.y).serialize(s)
    }
}

impl<'de> Deserialize<'de> for Pos {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let (x, y) = <(i16, i16)>::deserialize(d)?;
        Ok(Pos::new(x, y))
    }
}

impl Serialize for Heading {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_u8(self.index())
    }
}

impl<'de> Deserialize<'de> for Heading {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let i = u8::deserialize(d)?;
        if i < 4 {
            Ok(Heading::from_index(i))
        } else {
            Err(de::Error::custom("heading out of range"))
        }
    }
}

impl Serialize for Arms {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_u8(self.bits())
    }
}

impl<'de> Deserialize<'de> for Arms {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let b = u8::deserialize(d)?;
        if b < 16 {
            Ok(Arms::from_bits(b))
        } else {
            Err(de::Error::custom("arms out of range"))
        }
    }
}

impl Serialize for RobotId {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_u8(self.0)
    }
}

impl<'de> Deserialize<'de> for RobotId {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        Ok(RobotId(u8::deserialize(d)?))
    }
}

impl Serialize for Turn {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_u8(self.quarter_turns())
    }
}

impl<'de> Deserialize<'de> for Turn {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        match u8::deserialize(d)? {
            1 => Ok(Turn::Right),
            2 => Ok(Turn::UTurn),
            3 => Ok(Turn::Left),
            _ => Err(de::Error::custom("turn out of range")),
        }
    }
}
