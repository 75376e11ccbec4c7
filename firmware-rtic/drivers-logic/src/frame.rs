//! Bootstrap link framing: COBS-encoded frames ended by a 0x00 byte, and the
//! few messages the firmware understands until core-algo's `protocol` (with
//! its reliable link state machine) is merged.
//!
//! **Placeholder.** Replace [`Request`]/[`Reply`] with `core_algo::protocol`
//! once it exists; the firmware's `link` task only calls
//! [`FrameDecoder::push`] and [`encode_frame`], and those are the seams.
//!
//! Messages (first payload byte = kind):
//!
//! | dir | kind | payload after the kind |
//! |---|---|---|
//! | robot → host | `0x01` HELLO | version u8, robot id u8, mode u8 (0 calibrate, 1 run, 2 emulated) |
//! | host → robot | `0x02` PING | seq u8 → reply `0x82` PONG seq |
//! | host → robot | `0x03` STATUS | → `0x83` selector u8, left steps i32 LE, right steps i32 LE, map nodes visited u16 LE, map capacity u16 LE, ground centre u16 LE |
//! | host → robot | `0x04` SPEED | left i16 LE, right i16 LE → `0x84` applied left i16, right i16 |
//! | host → robot | `0x05` VISIT | x i16 LE, y i16 LE, arms u8 → `0x85` ok u8, visited u16 LE |
//! | host → robot | `0x7F` QUIT | (emulation only) → `0xFF` BYE, then QEMU exits with 0 |
//! | robot → host | `0xEE` ERROR | code u8 (1 unknown kind, 2 bad length, 3 frame too long) |

/// Largest decoded payload accepted.
pub const MAX_PAYLOAD: usize = 64;
/// Largest encoded frame, delimiter included.
pub const MAX_FRAME: usize = MAX_PAYLOAD + MAX_PAYLOAD / 254 + 2;
/// Version announced in HELLO.
pub const LINK_VERSION: u8 = 1;

/// COBS-encodes `data` into `out` and appends the 0x00 delimiter; returns
/// the frame length, or `None` if `out` is too small.
pub fn encode_frame(data: &[u8], out: &mut [u8]) -> Option<usize> {
    let mut code_at = 0usize;
    let mut w = 1usize;
    let mut code = 1u8;
    for &b in data {
        if b == 0 {
            *out.get_mut(code_at)? = code;
            code_at = w;
            w += 1;
            code = 1;
        } else {
            *out.get_mut(w)? = b;
            w += 1;
            code += 1;
            if code == 0xFF {
                *out.get_mut(code_at)? = code;
                code_at = w;
                w += 1;
                code = 1;
            }
        }
    }
    *out.get_mut(code_at)? = code;
    *out.get_mut(w)? = 0;
    Some(w + 1)
}

/// Decodes one COBS block (without the delimiter) into `out`.
pub fn decode_cobs(enc: &[u8], out: &mut [u8]) -> Option<usize> {
    let mut r = 0usize;
    let mut w = 0usize;
    while r < enc.len() {
        let code = enc[r];
        if code == 0 {
            return None;
        }
        r += 1;
        for _ in 1..code {
            let b = *enc.get(r)?;
            if b == 0 {
                return None;
            }
            *out.get_mut(w)? = b;
            w += 1;
            r += 1;
        }
        if code != 0xFF && r < enc.len() {
            *out.get_mut(w)? = 0;
            w += 1;
        }
    }
    Some(w)
}

/// What [`FrameDecoder::push`] found.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum FrameEvent {
    /// A complete frame of this many payload bytes is in [`FrameDecoder::payload`].
    Frame(usize),
    /// A frame was dropped: too long or not valid COBS.
    Dropped,
}

/// Byte-at-a-time frame reassembly for the receive path.
#[derive(Debug)]
pub struct FrameDecoder {
    raw: [u8; MAX_FRAME],
    len: usize,
    overflow: bool,
    payload: [u8; MAX_PAYLOAD],
}

impl Default for FrameDecoder {
    fn default() -> Self {
        Self::new()
    }
}

impl FrameDecoder {
    /// An empty decoder.
    pub const fn new() -> Self {
        FrameDecoder {
            raw: [0; MAX_FRAME],
            len: 0,
            overflow: false,
            payload: [0; MAX_PAYLOAD],
        }
    }

    /// Feeds one received byte.
    pub fn push(&mut self, byte: u8) -> Option<FrameEvent> {
        if byte != 0 {
            if self.len < MAX_FRAME {
                self.raw[self.len] = byte;
                self.len += 1;
            } else {
                self.overflow = true;
            }
            return None;
        }
        let (len, overflow) = (self.len, self.overflow);
        self.len = 0;
        self.overflow = false;
        if len == 0 {
            return None; // empty frames resynchronise; not an error
        }
        if overflow {
            return Some(FrameEvent::Dropped);
        }
        match decode_cobs(&self.raw[..len], &mut self.payload) {
            Some(n) => Some(FrameEvent::Frame(n)),
            None => Some(FrameEvent::Dropped),
        }
    }

    /// The payload of the last [`FrameEvent::Frame`].
    pub fn payload(&self, len: usize) -> &[u8] {
        &self.payload[..len.min(MAX_PAYLOAD)]
    }
}

/// A request from the host (bootstrap protocol).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Request {
    /// Echo `seq` back.
    Ping(u8),
    /// Report selector, step counters and the map fill.
    Status,
    /// Set wheel speeds (full steps per second).
    Speed(i16, i16),
    /// Record a visited node in the robot's map (stands in for the agent).
    Visit {
        /// Node x.
        x: i16,
        /// Node y.
        y: i16,
        /// Arms bitmask (N = bit 0, E, S, W).
        arms: u8,
    },
    /// Stop the emulator (ignored on hardware).
    Quit,
}

/// Why a payload is not a request.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ParseError {
    /// Unknown kind byte.
    UnknownKind = 1,
    /// Wrong length for the kind.
    BadLength = 2,
    /// The frame was too long or corrupt.
    BadFrame = 3,
}

impl Request {
    /// Parses a decoded payload.
    pub fn parse(p: &[u8]) -> Result<Request, ParseError> {
        let (&kind, rest) = p.split_first().ok_or(ParseError::BadLength)?;
        let i16_at = |i: usize| i16::from_le_bytes([rest[i], rest[i + 1]]);
        let need = |n: usize| {
            if rest.len() == n {
                Ok(())
            } else {
                Err(ParseError::BadLength)
            }
        };
        match kind {
            0x02 => need(1).map(|_| Request::Ping(rest[0])),
            0x03 => need(0).map(|_| Request::Status),
            0x04 => need(4).map(|_| Request::Speed(i16_at(0), i16_at(2))),
            0x05 => need(5).map(|_| Request::Visit {
                x: i16_at(0),
                y: i16_at(2),
                arms: rest[4],
            }),
            0x7F => need(0).map(|_| Request::Quit),
            _ => Err(ParseError::UnknownKind),
        }
    }
}

/// Robot status for the STATUS reply.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Status {
    /// Selector position.
    pub selector: u8,
    /// Left wheel full steps.
    pub left_steps: i32,
    /// Right wheel full steps.
    pub right_steps: i32,
    /// Nodes visited in the robot's map.
    pub visited: u16,
    /// Map capacity in nodes.
    pub capacity: u16,
    /// Calibrated centre floor sensor.
    pub ground_centre: u16,
}

/// A message from the robot (bootstrap protocol).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Reply {
    /// Ready announcement, sent once the UART receiver is enabled.
    Hello {
        /// Robot id (selector position in run mode).
        robot: u8,
        /// 0 calibrate, 1 run, 2 emulated.
        mode: u8,
    },
    /// Answer to PING.
    Pong(u8),
    /// Answer to STATUS.
    Status(Status),
    /// Speeds applied.
    Speed(i16, i16),
    /// Visit recorded (`ok`) and the number of nodes visited now.
    Visited(bool, u16),
    /// Answer to QUIT.
    Bye,
    /// A request was refused.
    Error(ParseError),
}

impl Reply {
    /// Writes the payload into `out`; returns its length (`out` must hold
    /// [`MAX_PAYLOAD`] bytes).
    pub fn encode(&self, out: &mut [u8; MAX_PAYLOAD]) -> usize {
        let mut n = 0usize;
        let mut put = |bytes: &[u8]| {
            out[n..n + bytes.len()].copy_from_slice(bytes);
            n += bytes.len();
        };
        match *self {
            Reply::Hello { robot, mode } => put(&[0x01, LINK_VERSION, robot, mode]),
            Reply::Pong(seq) => put(&[0x82, seq]),
            Reply::Status(s) => {
                put(&[0x83, s.selector]);
                put(&s.left_steps.to_le_bytes());
                put(&s.right_steps.to_le_bytes());
                put(&s.visited.to_le_bytes());
                put(&s.capacity.to_le_bytes());
                put(&s.ground_centre.to_le_bytes());
            }
            Reply::Speed(l, r) => {
                put(&[0x84]);
                put(&l.to_le_bytes());
                put(&r.to_le_bytes());
            }
            Reply::Visited(ok, v) => {
                put(&[0x85, ok as u8]);
                put(&v.to_le_bytes());
            }
            Reply::Bye => put(&[0xFF]),
            Reply::Error(e) => put(&[0xEE, e as u8]),
        }
        n
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::vec::Vec;

    fn roundtrip(data: &[u8]) {
        let mut enc = [0u8; 600];
        let n = encode_frame(data, &mut enc).unwrap();
        assert_eq!(enc[n - 1], 0);
        assert!(!enc[..n - 1].contains(&0), "{:?}", &enc[..n]);
        let mut dec = [0u8; 600];
        let m = decode_cobs(&enc[..n - 1], &mut dec).unwrap();
        assert_eq!(&dec[..m], data);
    }

    #[test]
    fn cobs_known_vectors() {
        let mut enc = [0u8; 16];
        let n = encode_frame(&[0x11, 0x22, 0x00, 0x33], &mut enc).unwrap();
        assert_eq!(&enc[..n], &[0x03, 0x11, 0x22, 0x02, 0x33, 0x00]);
        let n = encode_frame(&[0x00], &mut enc).unwrap();
        assert_eq!(&enc[..n], &[0x01, 0x01, 0x00]);
        let n = encode_frame(&[], &mut enc).unwrap();
        assert_eq!(&enc[..n], &[0x01, 0x00]);
    }

    #[test]
    fn cobs_roundtrips() {
        roundtrip(&[]);
        roundtrip(&[0, 0, 0]);
        roundtrip(&[1, 2, 3, 0, 4]);
        let long: Vec<u8> = (0..300).map(|i| (i % 255 + 1) as u8).collect();
        roundtrip(&long);
        let long0: Vec<u8> = (0..300).map(|i| (i % 7) as u8).collect();
        roundtrip(&long0);
    }

    #[test]
    fn encode_refuses_small_buffer() {
        let mut enc = [0u8; 3];
        assert_eq!(encode_frame(&[1, 2, 3], &mut enc), None);
    }

    #[test]
    fn decoder_reassembles_and_resyncs() {
        let mut d = FrameDecoder::new();
        let mut enc = [0u8; 16];
        let n = encode_frame(&[0x02, 0x00], &mut enc).unwrap();
        let mut got = None;
        for &b in [0u8, 0].iter().chain(&enc[..n]) {
            if let Some(e) = d.push(b) {
                got = Some(e);
            }
        }
        assert_eq!(got, Some(FrameEvent::Frame(2)));
        assert_eq!(d.payload(2), &[0x02, 0x00]);
        assert_eq!(Request::parse(d.payload(2)), Ok(Request::Ping(0)));
        // An over-long frame is dropped, and the next one is fine again.
        for _ in 0..200 {
            assert_eq!(d.push(7), None);
        }
        assert_eq!(d.push(0), Some(FrameEvent::Dropped));
        for &b in &enc[..n] {
            d.push(b);
        }
        assert_eq!(d.payload(2), &[0x02, 0x00]);
    }

    #[test]
    fn parse_requests() {
        assert_eq!(Request::parse(&[0x03]), Ok(Request::Status));
        assert_eq!(
            Request::parse(&[0x04, 0x58, 0x02, 0xA8, 0xFD]),
            Ok(Request::Speed(600, -600))
        );
        assert_eq!(
            Request::parse(&[0x05, 1, 0, 0xFF, 0xFF, 0b1010]),
            Ok(Request::Visit {
                x: 1,
                y: -1,
                arms: 0b1010
            })
        );
        assert_eq!(Request::parse(&[0x02]), Err(ParseError::BadLength));
        assert_eq!(Request::parse(&[0x42]), Err(ParseError::UnknownKind));
        assert_eq!(Request::parse(&[]), Err(ParseError::BadLength));
    }

    #[test]
    fn encode_replies() {
        let mut b = [0u8; MAX_PAYLOAD];
        let n = Reply::Hello { robot: 3, mode: 2 }.encode(&mut b);
        assert_eq!(&b[..n], &[0x01, LINK_VERSION, 3, 2]);
        let s = Status {
            selector: 1,
            left_steps: -2,
            right_steps: 3,
            visited: 4,
            capacity: 1024,
            ground_centre: 768,
        };
        let n = Reply::Status(s).encode(&mut b);
        assert_eq!(n, 16);
        assert_eq!(&b[..6], &[0x83, 1, 0xFE, 0xFF, 0xFF, 0xFF]);
        let n = Reply::Error(ParseError::BadLength).encode(&mut b);
        assert_eq!(&b[..n], &[0xEE, 2]);
    }
}
