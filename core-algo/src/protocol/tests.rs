//! Codec tests: round trips, corruption, truncation, garbage, limits.

use proptest::prelude::*;
use std::vec;
use std::vec::Vec;

use super::frame::*;
use super::message::*;
use super::stream::StreamDecoder;
use crate::geometry::{Arms, Heading, Pos, Turn};
use crate::team::RobotId;

pub(crate) fn pos() -> impl Strategy<Value = Pos> {
    (any::<i16>(), any::<i16>()).prop_map(|(x, y)| Pos::new(x, y))
}

pub(crate) fn pose() -> impl Strategy<Value = Pose> {
    (pos(), 0u8..4).prop_map(|(pos, h)| Pose {
        pos,
        heading: Heading::from_index(h),
    })
}

fn arms() -> impl Strategy<Value = Arms> {
    (0u8..16).prop_map(Arms::from_bits)
}

fn robot_state() -> impl Strategy<Value = RobotState> {
    prop::sample::select(
        &[
            RobotState::Idle,
            RobotState::Calibrating,
            RobotState::Scanning,
            RobotState::Stopped,
            RobotState::Driving,
            RobotState::Turning,
            RobotState::Manual,
            RobotState::Abyss,
            RobotState::Collision,
            RobotState::Finished,
            RobotState::Error,
        ][..],
    )
}

fn text() -> impl Strategy<Value = heapless::String<LOG_TEXT_LEN>> {
    "\\PC{0,16}".prop_map(|s| {
        let mut t = heapless::String::new();
        for c in s.chars() {
            if t.push(c).is_err() {
                break;
            }
        }
        t
    })
}

fn broadcast() -> impl Strategy<Value = Broadcast> {
    prop_oneof![
        (pose(), arms()).prop_map(|(pose, arms)| Broadcast::NodeHit { pose, arms }),
        prop::option::of(pos()).prop_map(|target| Broadcast::Intent { target }),
        prop::sample::select(
            &[
                FailureKind::Abyss,
                FailureKind::LinkLost,
                FailureKind::NodeObstruction,
                FailureKind::InconsistentMap,
            ][..]
        )
        .prop_map(|kind| Broadcast::Failure { kind }),
        pose().prop_map(|pose| Broadcast::Localize(Localize::Collision { pose })),
        pose().prop_map(|pose| Broadcast::Localize(Localize::Pass { pose })),
        Just(Broadcast::Localize(Localize::Finished)),
        (any::<u8>(), pose()).prop_map(|(by, seen)| Broadcast::Localize(Localize::Bumped {
            by: RobotId(by),
            seen
        })),
        Just(Broadcast::Localize(Localize::Ready)),
    ]
}

/// Every variant, with arbitrary field values.
pub(crate) fn message() -> impl Strategy<Value = Message> {
    prop_oneof![
        (any::<u8>(), any::<[u8; 3]>()).prop_map(|(r, [major, minor, patch])| Message::Hello {
            robot: RobotId(r),
            firmware: FirmwareVersion {
                major,
                minor,
                patch
            }
        }),
        (
            any::<u32>(),
            pose(),
            robot_state(),
            any::<u8>(),
            any::<u8>()
        )
            .prop_map(
                |(uptime_ms, pose, state, floor, proximity)| Message::Status(Status {
                    uptime_ms,
                    pose,
                    state,
                    floor,
                    proximity
                })
            ),
        (pose(), arms()).prop_map(|(pose, arms)| Message::NodeHit { pose, arms }),
        prop::option::of(pos()).prop_map(|target| Message::Intent { target }),
        any::<u8>().prop_map(|proximity| Message::Collision { proximity }),
        any::<u8>().prop_map(|floor| Message::Abyss { floor }),
        any::<u16>().prop_map(|command| Message::Ack { command }),
        (any::<u16>(), 0usize..5).prop_map(|(command, r)| Message::Reject {
            command,
            reason: [
                RejectReason::Busy,
                RejectReason::WrongState,
                RejectReason::NoArm,
                RejectReason::BadArgument,
                RejectReason::Unsupported
            ][r]
        }),
        (any::<[u16; 3]>(), any::<[u16; 3]>(), any::<bool>()).prop_map(|(line, background, ok)| {
            Message::Calibrated(Calibration {
                line,
                background,
                ok,
            })
        }),
        (0usize..4, text()).prop_map(|(l, text)| Message::Log {
            level: [
                LogLevel::Error,
                LogLevel::Warn,
                LogLevel::Info,
                LogLevel::Debug
            ][l],
            text
        }),
        any::<u32>().prop_map(|have| Message::ResyncRequest { have }),
        Just(Message::Reset),
        (pose(), 0usize..3, any::<u8>(), any::<u16>()).prop_map(|(pose, k, team_size, speed)| {
            Message::Start {
                pose,
                settings: StrategySettings {
                    kind: [
                        StrategyKind::NearestFrontier,
                        StrategyKind::Coordinated,
                        StrategyKind::Remote,
                    ][k],
                    team_size,
                    speed,
                },
            }
        }),
        prop::sample::select(&[Turn::Left, Turn::Right, Turn::UTurn][..]).prop_map(Message::Turn),
        Just(Message::Move),
        any::<u16>().prop_map(|steps_per_s| Message::SetSpeed { steps_per_s }),
        any::<u16>().prop_map(|mask| Message::SetLeds { mask }),
        any::<bool>().prop_map(|on| Message::Manual { on }),
        Just(Message::Stop),
        Just(Message::Resume),
        Just(Message::RequestStatus),
        any::<u32>().prop_map(|total| Message::ResyncDone { total }),
        (any::<u8>(), broadcast()).prop_map(|(o, broadcast)| Message::Relayed {
            origin: RobotId(o),
            broadcast
        }),
        (any::<bool>(), any::<u8>(), any::<u16>()).prop_map(|(global, team_size, speed)| {
            Message::StartLocalize {
                method: if global {
                    LocalizeMethod::Global
                } else {
                    LocalizeMethod::Local
                },
                settings: StrategySettings {
                    kind: StrategyKind::Coordinated,
                    team_size,
                    speed,
                },
            }
        }),
    ]
}

pub(crate) fn frame() -> impl Strategy<Value = Frame> {
    (
        any::<u8>(),
        any::<u8>(),
        any::<u8>(),
        any::<u16>(),
        any::<u16>(),
        (0u8..4, any::<u16>()),
        message(),
    )
        .prop_map(
            |(s, session, peer_session, seq, ack, (kind, sack), m)| Frame {
                header: Header {
                    sender: RobotId(s),
                    session,
                    peer_session,
                    seq,
                    ack,
                    sack,
                },
                body: match kind {
                    0 => Body::Data(m),
                    1 => Body::Datagram(m),
                    2 => Body::Ack,
                    _ => Body::Sync,
                },
            },
        )
}

fn encode(f: &Frame) -> Vec<u8> {
    let mut buf = [0u8; MAX_FRAME_LEN];
    let n = f.encode(&mut buf).unwrap();
    buf[..n].to_vec()
}

/// The frames on the wire, each after a run of garbage, and the last
/// run of garbage after them all.
fn wire_with_garbage(frames: &[Frame], garbage: &[Vec<u8>]) -> Vec<u8> {
    let mut wire = Vec::new();
    for (f, g) in frames.iter().zip(garbage) {
        wire.extend_from_slice(g);
        wire.extend(encode(f));
    }
    wire.extend_from_slice(garbage.last().map_or(&[][..], |g| g));
    wire
}

/// Decodes a whole stream, returning the frames and the error count.
fn decode_stream(bytes: &[u8], chunk: usize) -> (Vec<Frame>, u32) {
    let mut d = StreamDecoder::new();
    let mut out = Vec::new();
    for c in bytes.chunks(chunk.max(1)) {
        d.push(c, |r| {
            if let Ok(f) = r {
                out.push(f)
            }
        });
    }
    (out, d.stats().errors())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn message_round_trip(m in message()) {
        let mut buf = [0u8; MAX_MESSAGE_LEN];
        let n = m.encode(&mut buf).unwrap().len();
        prop_assert!(n <= MAX_MESSAGE_LEN);
        prop_assert_eq!(Message::decode(&buf[..n]), Ok(m));
    }

    #[test]
    fn frame_round_trip_in_any_chunking(f in frame(), chunk in 1usize..20) {
        let wire = encode(&f);
        prop_assert!(wire.len() <= MAX_FRAME_LEN);
        prop_assert_eq!(wire[0], 0);
        prop_assert_eq!(wire[wire.len() - 1], 0);
        prop_assert!(!wire[1..wire.len() - 1].contains(&0));
        prop_assert_eq!(Frame::decode(&wire[1..wire.len() - 1]), Ok(f.clone()));
        let (frames, errors) = decode_stream(&wire, chunk);
        prop_assert_eq!(frames, std::vec![f]);
        prop_assert_eq!(errors, 0);
    }

    #[test]
    fn every_single_bit_flip_is_detected(f in frame()) {
        let wire = encode(&f);
        for i in 0..wire.len() {
            for bit in 0..8 {
                let mut w = wire.clone();
                w[i] ^= 1 << bit;
                let (frames, _) = decode_stream(&w, w.len());
                prop_assert!(frames.is_empty(), "flip at byte {} bit {} accepted", i, bit);
            }
        }
    }

    #[test]
    fn every_truncation_is_detected(f in frame()) {
        let wire = encode(&f);
        // Cut the frame short and close it with a delimiter anyway.
        for keep in 0..wire.len() - 1 {
            let mut w = wire[..keep].to_vec();
            w.push(0);
            let (frames, _) = decode_stream(&w, 7);
            prop_assert!(frames.is_empty(), "truncation to {} accepted", keep);
        }
    }

    #[test]
    fn arbitrary_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..300)) {
        let _ = Frame::decode(&bytes);
        let _ = Frame::decode_raw(&bytes);
        let _ = Message::decode(&bytes);
        let (_, _) = decode_stream(&bytes, 5);
    }

    #[test]
    fn runs_are_taken_as_bytes_are(
        frames in prop::collection::vec(frame(), 0..4),
        garbage in prop::collection::vec(prop::collection::vec(any::<u8>(), 0..400), 5),
        chunk in 1usize..200,
    ) {
        // Frames, garbage (overlong runs too) and stray delimiters, cut
        // anywhere: chunk by chunk the decoder reports what it reports
        // byte by byte, and counts the same.
        let wire = wire_with_garbage(&frames, &garbage);
        let mut by_byte = StreamDecoder::new();
        let want: Vec<_> = wire.iter().filter_map(|&b| by_byte.push_byte(b)).collect();
        let mut by_run = StreamDecoder::new();
        let mut got = Vec::new();
        for c in wire.chunks(chunk) {
            by_run.push(c, |r| got.push(r));
        }
        prop_assert_eq!(got, want);
        prop_assert_eq!(by_run.stats(), by_byte.stats());
    }

    #[test]
    fn garbage_between_frames_costs_no_intact_frame(
        frames in prop::collection::vec(frame(), 1..6),
        garbage in prop::collection::vec(prop::collection::vec(any::<u8>(), 0..120), 6),
        chunk in 1usize..64,
    ) {
        let wire = wire_with_garbage(&frames, &garbage);
        let (got, _) = decode_stream(&wire, chunk);
        prop_assert_eq!(got, frames);
    }
}

#[test]
fn largest_messages_fit_the_bound() {
    let mut text = heapless::String::<LOG_TEXT_LEN>::new();
    while text.push('\u{7f}').is_ok() {}
    let far = Pose {
        pos: Pos::new(i16::MIN, i16::MIN),
        heading: Heading::West,
    };
    let big = [
        Message::Log {
            level: LogLevel::Debug,
            text,
        },
        Message::Status(Status {
            uptime_ms: u32::MAX,
            pose: far,
            state: RobotState::Error,
            floor: 0xFF,
            proximity: 0xFF,
        }),
        Message::Calibrated(Calibration {
            line: [u16::MAX; 3],
            background: [u16::MAX; 3],
            ok: true,
        }),
        Message::Relayed {
            origin: RobotId(0xFF),
            broadcast: Broadcast::Localize(Localize::Collision { pose: far }),
        },
        Message::Relayed {
            origin: RobotId(0xFF),
            broadcast: Broadcast::Localize(Localize::Bumped {
                by: RobotId(0xFF),
                seen: far,
            }),
        },
        Message::StartLocalize {
            method: LocalizeMethod::Global,
            settings: StrategySettings {
                kind: StrategyKind::Remote,
                team_size: 0xFF,
                speed: u16::MAX,
            },
        },
        Message::Start {
            pose: far,
            settings: StrategySettings {
                kind: StrategyKind::Remote,
                team_size: 0xFF,
                speed: u16::MAX,
            },
        },
    ];
    for m in big {
        let mut buf = [0u8; 256];
        let n = m.encode(&mut buf).unwrap().len();
        assert!(n <= MAX_MESSAGE_LEN, "{m:?} takes {n} bytes");
    }
    assert_eq!(MAX_FRAME_LEN, 81);
}

#[test]
fn node_hit_frame_size() {
    let f = Frame {
        header: Header {
            sender: RobotId(3),
            session: 7,
            peer_session: 9,
            seq: 1000,
            ack: 2000,
            sack: 0,
        },
        body: Body::Data(Message::NodeHit {
            pose: Pose {
                pos: Pos::new(12, -7),
                heading: Heading::East,
            },
            arms: Arms::CROSS,
        }),
    };
    // 10 header + 5 message + 4 CRC = 19 raw, +1 COBS, +2 delimiters.
    assert_eq!(encode(&f).len(), 22);
}

#[test]
fn out_of_range_fields_are_rejected() {
    // NodeHit (variant 2): pos (0,0), heading 4 (invalid), arms 0.
    assert!(Message::decode(&[2, 0, 0, 4, 0]).is_err());
    // NodeHit with arms 16.
    assert!(Message::decode(&[2, 0, 0, 0, 16]).is_err());
    assert_eq!(
        Message::decode(&[2, 0, 0, 0, 15]),
        Ok(Message::NodeHit {
            pose: Pose {
                pos: Pos::new(0, 0),
                heading: Heading::North
            },
            arms: Arms::CROSS
        })
    );
    // Trailing byte.
    assert_eq!(
        Message::decode(&[2, 0, 0, 0, 15, 0]),
        Err(MessageError::TrailingBytes)
    );
    // Turn 0 is no turn.
    assert!(Message::decode(&[13, 0]).is_err());
}

#[test]
fn wrong_version_and_kind_are_rejected() {
    let f = Frame {
        header: Header {
            sender: PHONE,
            session: 1,
            peer_session: 2,
            seq: 3,
            ack: 4,
            sack: 5,
        },
        body: Body::Ack,
    };
    let mut raw = [0u8; MAX_RAW_LEN];
    let n = f.encode_raw(&mut raw).unwrap();
    let reseal = |raw: &mut [u8]| {
        let c = CRC.checksum(&raw[..n - CRC_LEN]);
        raw[n - CRC_LEN..n].copy_from_slice(&c.to_le_bytes());
    };
    let mut r = raw;
    r[0] = 2 << 4 | 2;
    reseal(&mut r);
    assert_eq!(Frame::decode_raw(&r[..n]), Err(FrameError::Version));
    let mut r = raw;
    r[0] = 1 << 4 | 5;
    reseal(&mut r);
    assert_eq!(Frame::decode_raw(&r[..n]), Err(FrameError::Kind));
    assert_eq!(Frame::decode_raw(&raw[..n]), Ok(f));
}

#[test]
fn overlong_chunk_is_dropped_and_decoder_recovers() {
    let f = Frame {
        header: Header {
            sender: RobotId(0),
            session: 1,
            peer_session: 0,
            seq: 0,
            ack: 0,
            sack: 0,
        },
        body: Body::Data(Message::Move),
    };
    let mut wire = std::vec![0x55u8; 1000];
    wire.extend(encode(&f));
    let mut d = StreamDecoder::new();
    let mut got = Vec::new();
    d.push(&wire, |r| got.push(r));
    assert_eq!(got, std::vec![Err(FrameError::TooLong), Ok(f)]);
    assert_eq!(d.stats().too_long, 1);
    assert_eq!(d.stats().frames, 1);
}

#[test]
fn the_crc_is_crc32c_however_it_is_computed() {
    // The catalogue's check value: the robot's byte-wise tables and the
    // host's sixteen-byte ones must agree with each other and with it.
    assert_eq!(CRC.checksum(b"123456789"), 0xE306_9283);
    let bytewise = crc::Crc::<u32, crc::Table<1>>::new(&crc::CRC_32_ISCSI);
    let data: Vec<u8> = (0..200u32).map(|i| (i * 37 + 11) as u8).collect();
    for n in 0..data.len() {
        assert_eq!(
            CRC.checksum(&data[..n]),
            bytewise.checksum(&data[..n]),
            "{n} bytes"
        );
    }
}
