//! Fuzzes the link state machine with a script of operations read from
//! the input: raw bytes, well-formed frames with arbitrary header fields
//! (random bytes alone would rarely pass the CRC), time steps, sends and
//! polls. Invariants: nothing panics, the queue stays within its window,
//! and every frame the link emits decodes.
#![no_main]

use core_algo::protocol::frame::{Body, Frame, Header, MAX_FRAME_LEN};
use core_algo::protocol::link::WINDOW;
use core_algo::protocol::{Link, LinkConfig, Message};
use core_algo::team::RobotId;
use libfuzzer_sys::fuzz_target;

fn message(i: u8) -> Message {
    match i % 4 {
        0 => Message::Move,
        1 => Message::SetLeds { mask: u16::from(i) },
        2 => Message::RequestStatus,
        _ => Message::Ack { command: u16::from(i) },
    }
}

fuzz_target!(|data: &[u8]| {
    let mut it = data.iter().copied();
    // The nonce picks the session and the first sequence number; a small
    // one keeps the sequence numbers near those of the injected frames.
    let nonce = u32::from(it.next().unwrap_or(0)) | u32::from(it.next().unwrap_or(0) % 4) << 20;
    let mut link = Link::new(LinkConfig::default(), RobotId(1), nonce);
    let mut now: u32 = u32::MAX - 3000;
    let mut out = [0u8; MAX_FRAME_LEN];
    while let Some(op) = it.next() {
        match op % 8 {
            0 => {
                let n = usize::from(it.next().unwrap_or(0) % 64);
                let bytes: Vec<u8> = it.by_ref().take(n).collect();
                link.on_bytes(now, &bytes);
            }
            1 => {
                let b: Vec<u8> = it.by_ref().take(8).collect();
                let g = |i: usize| b.get(i).copied().unwrap_or(0);
                let body = match g(0) % 4 {
                    0 => Body::Data(message(g(6))),
                    1 => Body::Datagram(message(g(6))),
                    2 => Body::Ack,
                    _ => Body::Sync,
                };
                let frame = Frame {
                    header: Header {
                        sender: RobotId(0xFE),
                        session: g(1) % 4,
                        peer_session: g(2) % 5,
                        seq: u16::from(g(3) % 16),
                        ack: u16::from(g(4) % 16),
                        sack: u16::from(g(7)) << 1 | u16::from(g(7) >> 4),
                    },
                    body,
                };
                let n = frame.encode(&mut out).expect("fits");
                let split = usize::from(g(5)) % n;
                link.on_bytes(now, &out[..split]);
                link.on_bytes(now, &out[split..n]);
            }
            2 => {
                let dt = u32::from(it.next().unwrap_or(0));
                now = now.wrapping_add(dt * dt);
                link.tick(now);
            }
            3 => {
                let _ = link.send(message(it.next().unwrap_or(0)));
            }
            4 => link.send_datagram(message(it.next().unwrap_or(0))),
            5 | 6 => {
                while let Some(n) = link.poll_transmit(now, &mut out) {
                    assert!(n <= MAX_FRAME_LEN);
                    Frame::decode(&out[1..n - 1]).expect("emitted frames decode");
                }
            }
            _ => while link.poll_event().is_some() {},
        }
        assert!(link.unacked() <= WINDOW);
    }
});
