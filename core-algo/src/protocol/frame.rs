//! One checked frame: header, body and CRC, COBS-encoded between delimiters.
//!
//! ```text
//! raw   = ver_kind sender session peer_session seq:u16le ack:u16le sack:u16le body.. crc32:u32le
//! wire  = 0x00 COBS(raw) 0x00
//! ```
//!
//! COBS removes every 0x00 from the frame, so a 0x00 on the wire is always
//! a frame boundary and a receiver that lost its place resynchronises at
//! the next one. Each frame is wrapped in *two* delimiters: garbage between
//! two frames is then fenced off on both sides and costs no intact frame.
//! The CRC-32C (Castagnoli) covers the whole raw frame. A CRC-16 would
//! detect every single-bit flip of the raw bytes too, but a flipped COBS
//! code byte moves zeros around, i.e. many bits at once, and 16 bits leave
//! a 1 in 65 536 chance per such error; 32 bits make it one in four
//! billion for two more bytes.

use crc::{CRC_32_ISCSI, Crc};

use super::message::{MAX_MESSAGE_LEN, Message, MessageError};
use crate::team::RobotId;

/// The protocol version in the high nibble of byte 0.
///
/// A receiver drops frames of any other version rather than misread them.
pub const VERSION: u8 = 1;

/// The sender address of the phone side (robots use their [`RobotId`]).
pub const PHONE: RobotId = RobotId(0xFE);

/// Bytes before the body.
pub const HEADER_LEN: usize = 10;

/// Bytes of the CRC trailer.
pub const CRC_LEN: usize = 4;

/// Largest raw (un-COBSed) frame: header, largest message, CRC = 78 bytes.
pub const MAX_RAW_LEN: usize = HEADER_LEN + MAX_MESSAGE_LEN + CRC_LEN;

/// Largest COBS-encoded frame without delimiters (one overhead byte per 254).
pub const MAX_ENCODED_LEN: usize = cobs::max_encoding_length(MAX_RAW_LEN);

/// Largest frame on the wire, both delimiters included: 81 bytes.
///
/// This is what a receiver must buffer: the stream decoder holds one frame
/// of [`MAX_ENCODED_LEN`] bytes, the link one raw frame per queued message.
pub const MAX_FRAME_LEN: usize = MAX_ENCODED_LEN + 2;

/// The CRC: CRC-32C, chosen for its Hamming distance on short frames.
pub const CRC: Crc<u32, CrcTables> = Crc::<u32, CrcTables>::new(&CRC_32_ISCSI);

/// How [`CRC`] is computed: a byte at a time from one 1 KiB table on the
/// robot, where flash is scarce and a frame comes every few ms; sixteen
/// bytes at a time from 16 KiB of tables on a host, where the simulator
/// checks 26 million frames in a 16-robot maze 256² run and the byte-wise
/// CRC was a quarter of receiving them (docs/results/performance.md,
/// stop 66). The same checksum either way.
#[cfg(target_os = "none")]
pub type CrcTables = crc::Table<1>;
/// See the embedded variant above.
#[cfg(not(target_os = "none"))]
pub type CrcTables = crc::Table<16>;

/// What a frame carries, with the message where there is one.
#[derive(Clone, PartialEq, Eq, Debug)]
pub enum Body {
    /// A reliable message: acknowledged, retransmitted, delivered once and in
    /// order. `seq` numbers it.
    Data(Message),
    /// A best-effort message (status, log): `seq` is ignored.
    Datagram(Message),
    /// No message; carries only the acknowledgement. Doubles as heartbeat.
    Ack,
    /// "My session is `session`, my next reliable frame is `seq`": sets up
    /// the receiving direction after a start or a restart.
    Sync,
}

impl Body {
    const fn kind(&self) -> u8 {
        match self {
            Body::Data(_) => 0,
            Body::Datagram(_) => 1,
            Body::Ack => 2,
            Body::Sync => 3,
        }
    }
}

/// The fixed header of every frame.
///
/// Every frame carries an acknowledgement so that data in one direction
/// acknowledges data in the other without extra frames.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub struct Header {
    /// Who sent the frame: a robot id or [`PHONE`].
    pub sender: RobotId,
    /// The sender's session, new at every start of its link (never 0).
    pub session: u8,
    /// The receiver's session that `ack` refers to; 0 while the sender has
    /// not yet synchronised to the receiver.
    pub peer_session: u8,
    /// Sequence number of a [`Body::Data`] frame; for [`Body::Sync`] the
    /// sequence number of the next data frame.
    pub seq: u16,
    /// Cumulative acknowledgement: every data frame of session
    /// `peer_session` before `ack` has been delivered.
    pub ack: u16,
    /// Selective acknowledgement: bit i set = data frame `ack + 1 + i` was
    /// received and is buffered, so the sender need not send it again.
    pub sack: u16,
}

/// A decoded frame.
#[derive(Clone, PartialEq, Eq, Debug)]
pub struct Frame {
    /// The header.
    pub header: Header,
    /// The body.
    pub body: Body,
}

/// Why a frame was rejected. Each kind has its own counter in
/// [`super::stream::Stats`].
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub enum FrameError {
    /// The output buffer is too small (encoding only).
    BufferFull,
    /// More bytes than [`MAX_ENCODED_LEN`] without a delimiter.
    TooLong,
    /// Invalid COBS.
    Cobs,
    /// Shorter than header and CRC.
    TooShort,
    /// The CRC does not match.
    Crc,
    /// Another protocol version.
    Version,
    /// Unknown frame kind, or a body where none belongs.
    Kind,
    /// The body is not a valid message.
    Message,
}

impl Frame {
    /// Encodes the frame, delimiters included, into `out` and returns its
    /// length (at most [`MAX_FRAME_LEN`]).
    pub fn encode(&self, out: &mut [u8]) -> Result<usize, FrameError> {
        let mut raw = [0u8; MAX_RAW_LEN];
        let raw_len = self.encode_raw(&mut raw)?;
        let raw = raw.get(..raw_len).ok_or(FrameError::BufferFull)?;
        let (first, rest) = out.split_first_mut().ok_or(FrameError::BufferFull)?;
        *first = 0;
        let n = cobs::try_encode(raw, rest).map_err(|_| FrameError::BufferFull)?;
        let last = rest.get_mut(n).ok_or(FrameError::BufferFull)?;
        *last = 0;
        Ok(n + 2)
    }

    /// Writes the raw frame (header, body, CRC; no COBS) into `raw` and
    /// returns its length.
    pub fn encode_raw(&self, raw: &mut [u8; MAX_RAW_LEN]) -> Result<usize, FrameError> {
        let h = &self.header;
        let [s0, s1] = h.seq.to_le_bytes();
        let [a0, a1] = h.ack.to_le_bytes();
        let [k0, k1] = h.sack.to_le_bytes();
        let header = [
            VERSION << 4 | self.body.kind(),
            h.sender.0,
            h.session,
            h.peer_session,
            s0,
            s1,
            a0,
            a1,
            k0,
            k1,
        ];
        let (head, tail) = raw.split_at_mut(HEADER_LEN);
        head.copy_from_slice(&header);
        let body_len = match &self.body {
            Body::Data(m) | Body::Datagram(m) => {
                let space = tail
                    .get_mut(..MAX_MESSAGE_LEN)
                    .ok_or(FrameError::BufferFull)?;
                m.encode(space).map_err(|_| FrameError::BufferFull)?.len()
            }
            Body::Ack | Body::Sync => 0,
        };
        let len = HEADER_LEN + body_len;
        let crc = CRC.checksum(raw.get(..len).ok_or(FrameError::BufferFull)?);
        raw.get_mut(len..len + CRC_LEN)
            .ok_or(FrameError::BufferFull)?
            .copy_from_slice(&crc.to_le_bytes());
        Ok(len + CRC_LEN)
    }

    /// Decodes one COBS-encoded frame (the bytes between two delimiters),
    /// in place: `encoded` is overwritten.
    pub fn decode_in_place(encoded: &mut [u8]) -> Result<Frame, FrameError> {
        if encoded.len() > MAX_ENCODED_LEN {
            return Err(FrameError::TooLong);
        }
        let n = cobs::decode_in_place(encoded).map_err(|_| FrameError::Cobs)?;
        Frame::decode_raw(encoded.get(..n).ok_or(FrameError::Cobs)?)
    }

    /// Decodes one COBS-encoded frame from a shared slice (copies it first).
    pub fn decode(encoded: &[u8]) -> Result<Frame, FrameError> {
        let mut buf = [0u8; MAX_ENCODED_LEN];
        let dst = buf.get_mut(..encoded.len()).ok_or(FrameError::TooLong)?;
        dst.copy_from_slice(encoded);
        Frame::decode_in_place(dst)
    }

    /// Decodes a raw frame (header, body, CRC; no COBS).
    pub fn decode_raw(raw: &[u8]) -> Result<Frame, FrameError> {
        if raw.len() < HEADER_LEN + CRC_LEN {
            return Err(FrameError::TooShort);
        }
        let (covered, crc) = raw.split_at(raw.len() - CRC_LEN);
        let crc = u32::from_le_bytes(crc.try_into().map_err(|_| FrameError::TooShort)?);
        if CRC.checksum(covered) != crc {
            return Err(FrameError::Crc);
        }
        let (head, body) = covered.split_at(HEADER_LEN);
        let &[vk, sender, session, peer_session, s0, s1, a0, a1, k0, k1] = head else {
            return Err(FrameError::TooShort);
        };
        if vk >> 4 != VERSION {
            return Err(FrameError::Version);
        }
        let message = |b: &[u8]| {
            Message::decode(b).map_err(|e| match e {
                MessageError::BufferFull | MessageError::Invalid | MessageError::TrailingBytes => {
                    FrameError::Message
                }
            })
        };
        let body = match (vk & 0x0F, body.is_empty()) {
            (0, _) => Body::Data(message(body)?),
            (1, _) => Body::Datagram(message(body)?),
            (2, true) => Body::Ack,
            (3, true) => Body::Sync,
            _ => return Err(FrameError::Kind),
        };
        Ok(Frame {
            header: Header {
                sender: RobotId(sender),
                session,
                peer_session,
                seq: u16::from_le_bytes([s0, s1]),
                ack: u16::from_le_bytes([a0, a1]),
                sack: u16::from_le_bytes([k0, k1]),
            },
            body,
        })
    }
}
