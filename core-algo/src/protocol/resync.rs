//! Bringing a robot that comes back up to date with the team's map.
//!
//! The phone side keeps every node hit of the team in one append-only log,
//! in the order it relayed them. A robot counts the entries it has applied.
//! After [`Event::LinkUp`](super::Event::LinkUp) following a loss (or after a
//! reboot, with a count of 0) the robot sends
//! [`Message::ResyncRequest`]` { have }`; the phone answers with a
//! [`ResyncStream`] that relays entries `have..` as
//! [`Broadcast::NodeHit`]s over the reliable link and ends with
//! [`Message::ResyncDone`]` { total }`. Because the link delivers in order,
//! the robot's count is exact when `ResyncDone` arrives; a request during a
//! running stream simply restarts it from the robot's count.
//!
//! Entries are map facts (pose and arms), and merging a fact twice is
//! harmless, so a resync that overlaps live relays costs bytes, not
//! correctness.

use super::link::Link;
use super::message::{Broadcast, Message, Pose};
use crate::geometry::Arms;
use crate::team::RobotId;

/// One entry of the phone's team node log.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub struct NodeLogEntry {
    /// The robot that reported the node.
    pub origin: RobotId,
    /// Its pose on arrival.
    pub pose: Pose,
    /// The node's arms, global frame.
    pub arms: Arms,
}

impl NodeLogEntry {
    /// The relayed message for this entry.
    pub fn to_message(self) -> Message {
        Message::Relayed {
            origin: self.origin,
            broadcast: Broadcast::NodeHit {
                pose: self.pose,
                arms: self.arms,
            },
        }
    }
}

/// The phone side's cursor through its node log for one robot's resync.
///
/// It holds only a position, not the log, so the phone may keep appending
/// to the log while the stream runs: entries added meanwhile are streamed
/// too, and `total` counts them.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub struct ResyncStream {
    next: usize,
    done: bool,
}

impl ResyncStream {
    /// A stream for a robot that already has the first `have` entries.
    pub fn new(have: u32) -> Self {
        ResyncStream {
            next: usize::try_from(have).unwrap_or(usize::MAX),
            done: false,
        }
    }

    /// Whether `ResyncDone` has been queued.
    pub fn is_done(&self) -> bool {
        self.done
    }

    /// The next message to send, without consuming it.
    pub fn peek(&self, log: &[NodeLogEntry]) -> Option<Message> {
        if self.done {
            return None;
        }
        Some(match log.get(self.next) {
            Some(e) => e.to_message(),
            None => Message::ResyncDone {
                total: u32::try_from(log.len()).unwrap_or(u32::MAX),
            },
        })
    }

    /// Marks the message from [`ResyncStream::peek`] as sent.
    pub fn advance(&mut self, log: &[NodeLogEntry]) {
        if self.next < log.len() {
            self.next += 1;
        } else {
            self.done = true;
        }
    }

    /// Queues as many messages on `link` as it accepts; returns whether the
    /// stream is complete. Call it again when the link has room.
    pub fn pump(&mut self, log: &[NodeLogEntry], link: &mut Link) -> bool {
        while let Some(m) = self.peek(log) {
            if link.send(m).is_err() {
                break;
            }
            self.advance(log);
        }
        self.done
    }
}
