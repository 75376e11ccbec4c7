//! Fuzzes the stream decoder. The input is a script that builds a byte
//! stream from well-formed frames and arbitrary garbage, and picks the
//! chunk size it is fed in. Properties: nothing panics, the counters add up
//! to the results reported, and every intact frame comes out, in order,
//! whatever garbage surrounds it (random bytes alone would almost never
//! form a frame with a valid CRC, so the script inserts real ones).
#![no_main]

use core_algo::geometry::{Arms, Heading, Pos};
use core_algo::protocol::frame::{Body, Frame, Header, MAX_FRAME_LEN};
use core_algo::protocol::{Message, Pose, StreamDecoder};
use core_algo::team::RobotId;
use libfuzzer_sys::fuzz_target;

fn frame(b: [u8; 4]) -> Frame {
    let m = Message::NodeHit {
        pose: Pose {
            pos: Pos::new(i16::from(b[2] as i8), i16::from(b[3])),
            heading: Heading::from_index(b[1]),
        },
        arms: Arms::from_bits(b[1] >> 4),
    };
    Frame {
        header: Header {
            sender: RobotId(b[0]),
            session: b[1],
            peer_session: b[2],
            seq: u16::from(b[3]),
            ack: u16::from(b[0]),
            sack: u16::from(b[1]),
        },
        body: match b[0] % 4 {
            0 => Body::Data(m),
            1 => Body::Datagram(m),
            2 => Body::Ack,
            _ => Body::Sync,
        },
    }
}

fuzz_target!(|data: &[u8]| {
    let Some((&chunk, script)) = data.split_first() else {
        return;
    };
    let mut wire = Vec::new();
    let mut expected = Vec::new();
    let mut it = script.iter().copied();
    while let Some(op) = it.next() {
        if op & 1 == 0 {
            let n = usize::from(op >> 1);
            wire.extend(it.by_ref().take(n));
        } else {
            let b = [
                it.next().unwrap_or(0),
                it.next().unwrap_or(0),
                it.next().unwrap_or(0),
                it.next().unwrap_or(0),
            ];
            let f = frame(b);
            let mut out = [0u8; MAX_FRAME_LEN];
            let n = f.encode(&mut out).expect("fits");
            wire.extend_from_slice(&out[..n]);
            expected.push(f);
        }
    }
    let mut d = StreamDecoder::new();
    let (mut got, mut errors) = (Vec::new(), 0u32);
    for c in wire.chunks(usize::from(chunk).max(1)) {
        d.push(c, |r| match r {
            Ok(f) => got.push(f),
            Err(_) => errors += 1,
        });
    }
    let s = d.stats();
    assert_eq!(s.frames as usize, got.len());
    assert_eq!(s.errors(), errors);
    // Every intact frame, in order (garbage could in theory hold a valid
    // frame too, so `expected` need only be a subsequence of `got`).
    let mut rest = got.iter();
    for f in &expected {
        assert!(rest.any(|g| g == f), "intact frame lost: {f:?}");
    }
});
