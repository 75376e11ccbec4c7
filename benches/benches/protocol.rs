//! Wire protocol cost: frame encode and decode throughput (messages per
//! second), a full link round (send, transmit, receive, acknowledge), and
//! the bytes on the wire per message kind (printed once at start).
use core_algo::geometry::{Arms, Heading, Pos, Turn};
use core_algo::protocol::frame::{Body, Frame, Header, MAX_FRAME_LEN, PHONE};
use core_algo::protocol::message::{RobotState, Status};
use core_algo::protocol::{Link, LinkConfig, Message, Pose, StreamDecoder};
use core_algo::team::RobotId;
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use std::hint::black_box;

fn pose() -> Pose {
    Pose {
        pos: Pos::new(12, -7),
        heading: Heading::East,
    }
}

fn samples() -> [(&'static str, Message); 4] {
    [
        (
            "node_hit",
            Message::NodeHit {
                pose: pose(),
                arms: Arms::CROSS,
            },
        ),
        (
            "status",
            Message::Status(Status {
                uptime_ms: 3_600_000,
                pose: pose(),
                state: RobotState::Driving,
                floor: 0,
                proximity: 0b0000_0011,
            }),
        ),
        ("turn", Message::Turn(Turn::Left)),
        (
            "relayed_node_hit",
            Message::Relayed {
                origin: RobotId(4),
                broadcast: core_algo::protocol::Broadcast::NodeHit {
                    pose: pose(),
                    arms: Arms::from_bits(0b1011),
                },
            },
        ),
    ]
}

fn frame(m: Message) -> Frame {
    Frame {
        header: Header {
            sender: RobotId(3),
            session: 7,
            peer_session: 9,
            seq: 1000,
            ack: 2000,
            sack: 0,
        },
        body: Body::Data(m),
    }
}

fn bench_protocol(c: &mut Criterion) {
    let mut buf = [0u8; MAX_FRAME_LEN];
    for (name, m) in samples() {
        let n = frame(m).encode(&mut buf).expect("fits");
        eprintln!("bytes on the wire: {name} = {n}");
    }
    let ack = Frame {
        header: frame(Message::Move).header,
        body: Body::Ack,
    };
    eprintln!(
        "bytes on the wire: ack/heartbeat = {}",
        ack.encode(&mut buf).expect("fits")
    );

    let mut g = c.benchmark_group("protocol");
    g.throughput(Throughput::Elements(1));
    for (name, m) in samples() {
        let f = frame(m);
        g.bench_with_input(BenchmarkId::new("encode", name), &f, |b, f| {
            let mut out = [0u8; MAX_FRAME_LEN];
            b.iter(|| black_box(f).encode(&mut out).expect("fits"))
        });
        let mut wire = [0u8; MAX_FRAME_LEN];
        let n = f.encode(&mut wire).expect("fits");
        let wire = &wire[..n];
        g.bench_with_input(BenchmarkId::new("decode_stream", name), &wire, |b, w| {
            let mut d = StreamDecoder::new();
            b.iter(|| {
                let mut got = None;
                d.push(black_box(w), |r| got = Some(r));
                got
            })
        });
    }

    // One reliable message from phone to robot, delivered and acknowledged:
    // everything the link does per command.
    g.bench_function("link_round_trip", |b| {
        let mut phone = Link::new(LinkConfig::default(), PHONE, 1);
        let mut robot = Link::new(LinkConfig::default(), RobotId(1), 1);
        let mut out = [0u8; MAX_FRAME_LEN];
        let mut now = 0u32;
        let mut pump = |from: &mut Link, to: &mut Link, now: u32| {
            while let Some(n) = from.poll_transmit(now, &mut out) {
                to.on_bytes(now, &out[..n]);
            }
            while to.poll_event().is_some() {}
        };
        // Handshake.
        for _ in 0..3 {
            pump(&mut phone, &mut robot, now);
            pump(&mut robot, &mut phone, now);
        }
        b.iter(|| {
            now = now.wrapping_add(1);
            phone.send(Message::Move).expect("room");
            pump(&mut phone, &mut robot, now);
            pump(&mut robot, &mut phone, now);
            assert_eq!(phone.unacked(), 0);
        })
    });
    g.finish();
}

criterion_group!(benches, bench_protocol);
criterion_main!(benches);
