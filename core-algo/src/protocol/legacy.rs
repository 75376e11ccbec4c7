//! The protocol of the 2010 firmware, so that the phone side can drive an
//! original e-puck (`docs/original-system.md` §2.1–2.6).
//!
//! Every message is exactly 32 bytes: `FF <id>` and 30 payload bytes, no
//! checksum, no sequence number, one request at a time. Node types are
//! indices 0..=9 into a table of shapes *relative to the robot's heading*;
//! [`relative_arms`] and [`global_arms`] convert them into our frame, and
//! [`LegacyResponse::to_message`] / [`LegacyRequest::from_message`] map the
//! 2010 messages onto [`Message`]s so that the rest of the phone side sees
//! only one protocol.
//!
//! The 2010 stream has no resynchronisation: one lost byte shifted every
//! later frame. [`LegacyStream`] does a little better at no cost to the
//! old robot: it skips bytes until `FF` and a known id.

use crate::geometry::{Arms, Heading, Turn};

use super::message::{Message, Pose, RejectReason, RobotState, Status};

/// Length of every 2010 frame.
pub const FRAME_LEN: usize = 32;

/// The node-type index the 2010 firmware sends for "no valid node"
/// (straight pieces and dead ends could not be represented).
pub const INVALID_NODE: u8 = 9;

/// Arms relative to the robot (bit 0 ahead, 1 right, 2 behind, 3 left) of
/// the 2010 node indices 0..=8 (`conquest_types.h`: DOWN_RIGHT, DOWN_LEFT,
/// UP_RIGHT, UP_LEFT, UP_T, RIGHT_T, DOWN_T, LEFT_T, CROSS).
const RELATIVE: [Arms; 9] = [
    Arms::from_bits(0b0110), // DOWN_RIGHT: behind, right
    Arms::from_bits(0b1100), // DOWN_LEFT: behind, left
    Arms::from_bits(0b0011), // UP_RIGHT: ahead, right
    Arms::from_bits(0b1001), // UP_LEFT: ahead, left
    Arms::from_bits(0b1110), // UP_T: right, behind, left
    Arms::from_bits(0b1101), // RIGHT_T: ahead, behind, left
    Arms::from_bits(0b1011), // DOWN_T: ahead, right, left
    Arms::from_bits(0b0111), // LEFT_T: ahead, right, behind
    Arms::CROSS,
];

/// The robot-relative arms of 2010 node index `index`; `None` for
/// [`INVALID_NODE`] and anything out of range.
pub fn relative_arms(index: u8) -> Option<Arms> {
    RELATIVE.get(usize::from(index)).copied()
}

/// The arms in our global frame of node index `index`, reported by a robot
/// facing `heading`.
pub fn global_arms(index: u8, heading: Heading) -> Option<Arms> {
    relative_arms(index).map(|a| Arms::from_relative(a, heading))
}

/// The 2010 index of a robot-relative shape; `None` for shapes the 2010
/// system cannot name (straight pieces, dead ends, no arm).
pub fn index_of_relative(relative: Arms) -> Option<u8> {
    RELATIVE
        .iter()
        .position(|a| *a == relative)
        .and_then(|i| u8::try_from(i).ok())
}

/// A phone → robot request of the 2010 protocol.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub enum LegacyRequest {
    /// `FF 01`: reset all layers.
    Reset,
    /// `FF 02`: report status (in START: scan the node first).
    Status,
    /// `FF 03 n`: turn n × 90°, > 0 clockwise.
    Turn(i8),
    /// `FF 04`: follow the line to the next node.
    Move,
    /// `FF 05 v`: line speed min(10·v, 1000) steps/s.
    SetSpeed(u8),
    /// `FF 06 lo hi`: LED mask (bits 0–7 ring, 8 front, 9 body).
    SetLed(u16),
}

/// A robot → phone response of the 2010 protocol.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub enum LegacyResponse {
    /// `FF 81`: done (connect, reset, turn, speed, LED).
    Ok,
    /// `FF 82`: status.
    Status {
        /// Milliseconds since boot.
        uptime_ms: u32,
        /// Abyss flags of the floor sensors: bit 0 left, 1 middle, 2 right.
        abyss: u8,
        /// Collision flags of IR0..IR7, bit i = IR i.
        collision: u8,
        /// The last node's type index (robot-relative).
        node: u8,
    },
    /// `FF 83`: arrived at a node of this type index (robot-relative).
    HitNode(u8),
    /// `FF 84`: collision; the robot is back on the previous node, turned
    /// round. Bit i = IR i.
    Collision(u8),
    /// `FF 85`: abyss (never sent by the shipped firmware).
    Abyss(u8),
    /// `FF 86`: refused (wrong state, busy, unknown, no arm ahead).
    Rejected,
}

/// Why 32 bytes are not a 2010 frame.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub enum LegacyError {
    /// Byte 0 is not `FF`.
    Marker,
    /// Unknown message id.
    UnknownId,
}

/// Reads `n` flag bytes (non-zero = set) into a bit mask.
fn flags(bytes: &[u8]) -> u8 {
    bytes
        .iter()
        .take(8)
        .enumerate()
        .fold(0, |m, (i, b)| if *b != 0 { m | 1 << i } else { m })
}

/// Writes the low `n` bits of `mask` as 0/1 bytes.
fn write_flags(out: &mut [u8], mask: u8) {
    for (i, b) in out.iter_mut().take(8).enumerate() {
        *b = (mask >> i) & 1;
    }
}

fn check_marker(f: &[u8; FRAME_LEN]) -> Result<u8, LegacyError> {
    match f {
        [0xFF, id, ..] => Ok(*id),
        _ => Err(LegacyError::Marker),
    }
}

impl LegacyRequest {
    /// Whether `id` is a request id (for [`LegacyStream`]).
    pub const fn is_known_id(id: u8) -> bool {
        matches!(id, 1..=6)
    }

    /// The 32-byte frame, unused bytes 0 as the 2010 phone sent them.
    pub fn encode(self) -> [u8; FRAME_LEN] {
        let mut f = [0u8; FRAME_LEN];
        f[0] = 0xFF;
        let (id, payload): (u8, [u8; 2]) = match self {
            LegacyRequest::Reset => (1, [0, 0]),
            LegacyRequest::Status => (2, [0, 0]),
            LegacyRequest::Turn(n) => (3, [n.to_le_bytes()[0], 0]),
            LegacyRequest::Move => (4, [0, 0]),
            LegacyRequest::SetSpeed(v) => (5, [v, 0]),
            LegacyRequest::SetLed(mask) => (6, mask.to_le_bytes()),
        };
        f[1] = id;
        f[2] = payload[0];
        f[3] = payload[1];
        f
    }

    /// Parses a 32-byte frame (the simulated 2010 robot's side).
    pub fn decode(f: &[u8; FRAME_LEN]) -> Result<LegacyRequest, LegacyError> {
        let id = check_marker(f)?;
        let (b2, b3) = (f[2], f[3]);
        Ok(match id {
            1 => LegacyRequest::Reset,
            2 => LegacyRequest::Status,
            3 => LegacyRequest::Turn(i8::from_le_bytes([b2])),
            4 => LegacyRequest::Move,
            5 => LegacyRequest::SetSpeed(b2),
            6 => LegacyRequest::SetLed(u16::from_le_bytes([b2, b3])),
            _ => return Err(LegacyError::UnknownId),
        })
    }

    /// The 2010 request for one of our commands; `None` for commands the
    /// 2010 firmware does not know (start, manual, stop, resync, ...).
    pub fn from_message(m: &Message) -> Option<LegacyRequest> {
        Some(match m {
            Message::Reset => LegacyRequest::Reset,
            Message::RequestStatus => LegacyRequest::Status,
            Message::Turn(t) => LegacyRequest::Turn(t.legacy_code()),
            Message::Move => LegacyRequest::Move,
            Message::SetSpeed { steps_per_s } => {
                // speed = min(10·v, 1000): round to the nearest step of 10.
                let v = steps_per_s.saturating_add(5) / 10;
                LegacyRequest::SetSpeed(u8::try_from(v.min(100)).unwrap_or(100))
            }
            Message::SetLeds { mask } => LegacyRequest::SetLed(mask & 0x03FF),
            _ => return None,
        })
    }

    /// Our turn for a 2010 turn count: ±1 a quarter, ±2 a half turn; `None`
    /// for 0 or counts beyond a half turn, which the phone never sent.
    pub fn turn(count: i8) -> Option<Turn> {
        match count {
            1 => Some(Turn::Right),
            -1 => Some(Turn::Left),
            2 | -2 => Some(Turn::UTurn),
            _ => None,
        }
    }
}

impl LegacyResponse {
    /// Whether `id` is a response id (for [`LegacyStream`]).
    pub const fn is_known_id(id: u8) -> bool {
        matches!(id, 0x81..=0x86)
    }

    /// The 32-byte frame, unused bytes `FF` as the 2010 firmware sent them.
    pub fn encode(self) -> [u8; FRAME_LEN] {
        let mut f = [0xFFu8; FRAME_LEN];
        f[1] = match self {
            LegacyResponse::Ok => 0x81,
            LegacyResponse::Status {
                uptime_ms,
                abyss,
                collision,
                node,
            } => {
                f[2..6].copy_from_slice(&uptime_ms.to_le_bytes());
                write_flags(&mut f[6..9], abyss);
                write_flags(&mut f[9..17], collision);
                f[17] = node;
                0x82
            }
            LegacyResponse::HitNode(node) => {
                f[2] = node;
                0x83
            }
            LegacyResponse::Collision(mask) => {
                write_flags(&mut f[2..10], mask);
                0x84
            }
            LegacyResponse::Abyss(mask) => {
                write_flags(&mut f[2..5], mask);
                0x85
            }
            LegacyResponse::Rejected => 0x86,
        };
        f
    }

    /// Parses a 32-byte frame from a 2010 robot.
    ///
    /// The collision mask is read from bytes 2..9, where the firmware puts
    /// it (the 2010 phone read bytes 0..7 by mistake).
    pub fn decode(f: &[u8; FRAME_LEN]) -> Result<LegacyResponse, LegacyError> {
        let id = check_marker(f)?;
        Ok(match id {
            0x81 => LegacyResponse::Ok,
            0x82 => LegacyResponse::Status {
                uptime_ms: u32::from_le_bytes([f[2], f[3], f[4], f[5]]),
                abyss: flags(&f[6..9]),
                collision: flags(&f[9..17]),
                node: f[17],
            },
            0x83 => LegacyResponse::HitNode(f[2]),
            0x84 => LegacyResponse::Collision(flags(&f[2..10])),
            0x85 => LegacyResponse::Abyss(flags(&f[2..5])),
            0x86 => LegacyResponse::Rejected,
            _ => return Err(LegacyError::UnknownId),
        })
    }

    /// The response as one of our messages.
    ///
    /// The 2010 robot knows neither its pose nor command numbers, so the
    /// phone supplies them: `pose` is the robot's pose after the command
    /// (for a hit node: on the new node, same heading), `command` the
    /// number the phone gave the request. A hit node the 2010 system cannot
    /// represent ([`INVALID_NODE`]) gives `None`: the phone treats the robot
    /// as failed, as the 2010 phone did.
    pub fn to_message(self, pose: Pose, command: u16) -> Option<Message> {
        Some(match self {
            LegacyResponse::Ok => Message::Ack { command },
            LegacyResponse::Rejected => Message::Reject {
                command,
                reason: RejectReason::WrongState,
            },
            LegacyResponse::HitNode(i) => Message::NodeHit {
                pose,
                arms: global_arms(i, pose.heading)?,
            },
            LegacyResponse::Collision(mask) => Message::Collision { proximity: mask },
            LegacyResponse::Abyss(mask) => Message::Abyss { floor: mask },
            LegacyResponse::Status {
                uptime_ms,
                abyss,
                collision,
                node: _,
            } => Message::Status(Status {
                uptime_ms,
                pose,
                state: RobotState::Stopped,
                floor: abyss,
                proximity: collision,
            }),
        })
    }
}

/// Which side a [`LegacyStream`] decodes.
pub trait LegacyFrame: Sized {
    /// Whether `id` starts a frame of this side.
    fn is_known_id(id: u8) -> bool;
    /// Parses a complete frame.
    fn decode(f: &[u8; FRAME_LEN]) -> Result<Self, LegacyError>;
}

impl LegacyFrame for LegacyRequest {
    fn is_known_id(id: u8) -> bool {
        LegacyRequest::is_known_id(id)
    }
    fn decode(f: &[u8; FRAME_LEN]) -> Result<Self, LegacyError> {
        LegacyRequest::decode(f)
    }
}

impl LegacyFrame for LegacyResponse {
    fn is_known_id(id: u8) -> bool {
        LegacyResponse::is_known_id(id)
    }
    fn decode(f: &[u8; FRAME_LEN]) -> Result<Self, LegacyError> {
        LegacyResponse::decode(f)
    }
}

/// Cuts a 2010 byte stream into frames, skipping bytes until `FF` and a
/// known id so that a lost or stray byte costs one frame, not all later
/// ones (the 2010 code lost sync for good).
#[derive(Clone, Debug)]
pub struct LegacyStream<T> {
    buf: [u8; FRAME_LEN],
    len: usize,
    skipped: u32,
    _side: core::marker::PhantomData<T>,
}

impl<T: LegacyFrame> Default for LegacyStream<T> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T: LegacyFrame> LegacyStream<T> {
    /// An empty stream decoder.
    pub const fn new() -> Self {
        LegacyStream {
            buf: [0; FRAME_LEN],
            len: 0,
            skipped: 0,
            _side: core::marker::PhantomData,
        }
    }

    /// Bytes skipped while looking for a frame start.
    pub fn skipped(&self) -> u32 {
        self.skipped
    }

    /// Takes one byte; returns a frame when it completes one.
    pub fn push_byte(&mut self, byte: u8) -> Option<T> {
        match self.len {
            0 if byte != 0xFF => {
                self.skipped = self.skipped.saturating_add(1);
                return None;
            }
            1 if !T::is_known_id(byte) => {
                // `FF` followed by an unknown id: drop the `FF`, and let this
                // byte start a frame if it is an `FF` itself.
                self.skipped = self.skipped.saturating_add(1);
                if byte != 0xFF {
                    self.skipped = self.skipped.saturating_add(1);
                    self.len = 0;
                }
                return None;
            }
            _ => {}
        }
        if let Some(slot) = self.buf.get_mut(self.len) {
            *slot = byte;
            self.len += 1;
        }
        if self.len < FRAME_LEN {
            return None;
        }
        self.len = 0;
        T::decode(&self.buf).ok()
    }

    /// Takes a chunk and calls `on_frame` for every completed frame.
    pub fn push(&mut self, bytes: &[u8], mut on_frame: impl FnMut(T)) {
        for &b in bytes {
            if let Some(f) = self.push_byte(b) {
                on_frame(f);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Pos, legacy};
    use proptest::prelude::*;
    use std::vec::Vec;

    #[test]
    fn node_indices_match_the_2010_names() {
        // The 2010 phone's canonical heading UP is +y on a y-down screen,
        // i.e. south in our frame; there index i is NodeType ordinal i.
        for (i, (name, arms)) in legacy::NAMES.iter().enumerate() {
            assert_eq!(global_arms(i as u8, Heading::South), Some(*arms), "{name}");
        }
        assert_eq!(global_arms(INVALID_NODE, Heading::North), None);
        assert_eq!(global_arms(200, Heading::North), None);
        // Facing north, "behind and right" is south and east: a ┌.
        assert_eq!(
            global_arms(0, Heading::North),
            Some(legacy::BOTTOMRIGHTEDGE)
        );
    }

    #[test]
    fn relative_shapes_round_trip() {
        for i in 0..9 {
            assert_eq!(index_of_relative(relative_arms(i).unwrap()), Some(i));
        }
        assert_eq!(index_of_relative(Arms::from_bits(0b0101)), None);
        assert_eq!(index_of_relative(Arms::from_bits(0b0100)), None);
    }

    #[test]
    fn captured_scripts() {
        let turn_left = LegacyRequest::Turn(-1).encode();
        assert_eq!(turn_left[..3], [0xFF, 0x03, 0xFF]);
        assert_eq!(
            LegacyRequest::SetSpeed(50).encode()[..3],
            [0xFF, 0x05, 0x32]
        );
        assert_eq!(
            LegacyRequest::SetLed(255).encode()[..4],
            [0xFF, 0x06, 0xFF, 0x00]
        );
        assert_eq!(LegacyRequest::Turn(-2).encode()[2], 0xFE);
        assert!(LegacyRequest::Move.encode()[2..].iter().all(|b| *b == 0));
        assert!(LegacyResponse::Ok.encode()[2..].iter().all(|b| *b == 0xFF));
    }

    #[test]
    fn collision_mask_is_read_from_bytes_2_to_9() {
        let mut f = [0xFFu8; FRAME_LEN];
        f[1] = 0x84;
        f[2..10].copy_from_slice(&[0, 0, 1, 0, 0, 0, 0, 1]);
        assert_eq!(
            LegacyResponse::decode(&f),
            Ok(LegacyResponse::Collision(0b1000_0100))
        );
    }

    #[test]
    fn messages_map_to_2010_requests_and_back() {
        assert_eq!(
            LegacyRequest::from_message(&Message::Turn(Turn::Left)),
            Some(LegacyRequest::Turn(-1))
        );
        assert_eq!(
            LegacyRequest::from_message(&Message::SetSpeed { steps_per_s: 600 }),
            Some(LegacyRequest::SetSpeed(60))
        );
        assert_eq!(
            LegacyRequest::from_message(&Message::SetSpeed { steps_per_s: 65535 }),
            Some(LegacyRequest::SetSpeed(100))
        );
        assert_eq!(LegacyRequest::from_message(&Message::Stop), None);
        for t in [Turn::Left, Turn::Right, Turn::UTurn] {
            assert_eq!(LegacyRequest::turn(t.legacy_code()), Some(t));
        }
        let pose = Pose {
            pos: Pos::new(3, 4),
            heading: Heading::East,
        };
        // Facing east, a UP_T (no arm ahead) has arms N, S and W.
        assert_eq!(
            LegacyResponse::HitNode(4).to_message(pose, 0),
            Some(Message::NodeHit {
                pose,
                arms: Arms::from_bits(0b1101)
            })
        );
        assert_eq!(
            LegacyResponse::HitNode(INVALID_NODE).to_message(pose, 0),
            None
        );
        assert_eq!(
            LegacyResponse::Ok.to_message(pose, 7),
            Some(Message::Ack { command: 7 })
        );
    }

    #[test]
    fn stream_skips_stray_bytes() {
        let a = LegacyResponse::HitNode(8).encode();
        let b = LegacyResponse::Ok.encode();
        let mut wire = std::vec![0x12, 0xFF, 0x00, 0xFF];
        wire.extend_from_slice(&a);
        wire.extend_from_slice(&b[1..]); // b lost its first byte
        wire.extend_from_slice(&a);
        let mut s = LegacyStream::<LegacyResponse>::new();
        let mut got = Vec::new();
        s.push(&wire, |f| got.push(f));
        assert_eq!(got[0], LegacyResponse::HitNode(8));
        assert_eq!(*got.last().unwrap(), LegacyResponse::HitNode(8));
        assert!(s.skipped() > 0);
    }

    fn request() -> impl Strategy<Value = LegacyRequest> {
        prop_oneof![
            Just(LegacyRequest::Reset),
            Just(LegacyRequest::Status),
            any::<i8>().prop_map(LegacyRequest::Turn),
            Just(LegacyRequest::Move),
            any::<u8>().prop_map(LegacyRequest::SetSpeed),
            any::<u16>().prop_map(LegacyRequest::SetLed),
        ]
    }

    fn response() -> impl Strategy<Value = LegacyResponse> {
        prop_oneof![
            Just(LegacyResponse::Ok),
            (any::<u32>(), 0u8..8, any::<u8>(), 0u8..10).prop_map(
                |(uptime_ms, abyss, collision, node)| {
                    LegacyResponse::Status {
                        uptime_ms,
                        abyss,
                        collision,
                        node,
                    }
                }
            ),
            (0u8..10).prop_map(LegacyResponse::HitNode),
            any::<u8>().prop_map(LegacyResponse::Collision),
            (0u8..8).prop_map(LegacyResponse::Abyss),
            Just(LegacyResponse::Rejected),
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(256))]

        #[test]
        fn requests_round_trip(r in request()) {
            prop_assert_eq!(LegacyRequest::decode(&r.encode()), Ok(r));
        }

        #[test]
        fn responses_round_trip(r in response()) {
            prop_assert_eq!(LegacyResponse::decode(&r.encode()), Ok(r));
        }

        #[test]
        fn arbitrary_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..200)) {
            let mut s = LegacyStream::<LegacyResponse>::new();
            s.push(&bytes, |_| {});
            let mut s = LegacyStream::<LegacyRequest>::new();
            s.push(&bytes, |_| {});
            if let Ok(f) = <[u8; FRAME_LEN]>::try_from(&bytes[..bytes.len().min(FRAME_LEN)]) {
                let _ = LegacyResponse::decode(&f);
                let _ = LegacyRequest::decode(&f);
            }
        }
    }
}
