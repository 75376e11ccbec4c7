//! A real serial port, end to end: the phone side's `SerialRobot` opens one
//! end of a pseudo-terminal pair; a robot-side link on the other end says
//! hello, is started, reports a node and finishes.
#![cfg(unix)]

use core_algo::geometry::{Arms, Heading, Pos};
use core_algo::map::Bounds;
use core_algo::protocol::message::{FirmwareVersion, RobotState, Status};
use core_algo::protocol::{Event, Link, LinkConfig, MAX_FRAME_LEN, Message, Pose};
use core_algo::team::RobotId;
use phone_sim::connect_cmd::drive;
use phone_sim::field::StartPose;
use phone_sim::phone::PhoneSide;
use phone_sim::proxy::{RobotProxy, SerialRobot};
use serialport::SerialPort;
use std::io::{Read, Write};
use std::time::{Duration, Instant};

#[test]
fn a_robot_on_a_pty_is_started_and_reports() {
    let (mut master, slave) = serialport::TTYPort::pair().expect("pty pair");
    let name = slave.name().expect("pty name");
    master
        .set_timeout(Duration::from_millis(5))
        .expect("timeout");
    let start = StartPose {
        pos: Pos::new(1, 1),
        heading: Heading::North,
    };
    let arms = Arms::CROSS;
    let robot = std::thread::spawn(move || {
        let mut link = Link::new(LinkConfig::default(), RobotId(0), 0x1234_5678);
        link.send(Message::Hello {
            robot: RobotId(0),
            firmware: FirmwareVersion {
                major: 0,
                minor: 1,
                patch: 0,
            },
        })
        .expect("queue");
        let t0 = Instant::now();
        let mut started = None;
        let mut buf = [0u8; 256];
        let mut frame = [0u8; MAX_FRAME_LEN];
        while t0.elapsed() < Duration::from_secs(20) {
            let now = t0.elapsed().as_millis() as u32;
            if let Ok(n) = master.read(&mut buf) {
                link.on_bytes(now, &buf[..n]);
            }
            link.tick(now);
            while let Some(e) = link.poll_event() {
                if let Event::Received {
                    message: Message::Start { pose, .. },
                    ..
                } = e
                {
                    started = Some(pose);
                    link.send(Message::NodeHit { pose, arms }).expect("queue");
                    link.send(Message::Status(Status {
                        uptime_ms: now,
                        pose,
                        state: RobotState::Finished,
                        floor: 0,
                        proximity: 0,
                    }))
                    .expect("queue");
                }
            }
            while let Some(n) = link.poll_transmit(now, &mut frame) {
                master.write_all(&frame[..n]).expect("write");
            }
            if started.is_some() && link.unacked() == 0 {
                break;
            }
        }
        started
    });
    let robot_port = SerialRobot::open(RobotId(0), &name, LinkConfig::default()).expect("open pty");
    let mut proxies: Vec<Box<dyn RobotProxy>> = vec![Box::new(robot_port)];
    let mut phone = PhoneSide::new(Bounds::new(Pos::new(0, 0), 4, 4), vec![start], 600);
    let done = drive(
        &mut phone,
        &mut proxies,
        Some(Duration::from_secs(20)),
        |_| {},
    );
    let pose = robot.join().expect("robot thread");
    drop(slave);
    assert!(done, "the team never finished");
    assert_eq!(
        pose,
        Some(Pose {
            pos: start.pos,
            heading: start.heading
        })
    );
    assert_eq!(phone.env().map().known_arms(start.pos), Some(arms));
    let r = &phone.env().robots()[0];
    assert!(r.finished && r.link_up);
    assert_eq!(phone.env().stats().conflicts, 0);
}

/// A 2010 e-puck as its firmware behaves (original-system.md §2): OK on
/// connect, STATUS with the node under it, TURN, MOVE to the next node or
/// REJECTED, one request at a time; on a 3 x 3 grid of lines.
fn fake_2010_robot(
    mut port: serialport::TTYPort,
    stop: std::sync::Arc<std::sync::atomic::AtomicBool>,
) -> u32 {
    use core_algo::protocol::legacy::{
        LegacyRequest, LegacyResponse, LegacyStream, index_of_relative,
    };
    let field = phone_sim::field::generate::open(3, 3, 0);
    let (mut pos, mut heading) = (Pos::new(0, 0), Heading::North);
    let mut stream: LegacyStream<LegacyRequest> = LegacyStream::new();
    port.write_all(&LegacyResponse::Ok.encode())
        .expect("greeting");
    let mut moves = 0;
    let mut buf = [0u8; 64];
    while !stop.load(std::sync::atomic::Ordering::Relaxed) {
        let Ok(n) = port.read(&mut buf) else { continue };
        let mut requests = Vec::new();
        stream.push(&buf[..n], |r| requests.push(r));
        for r in requests {
            let here = |p: Pos, h: Heading| {
                index_of_relative(field.arms(p).unwrap().to_relative(h)).unwrap()
            };
            let answer = match r {
                LegacyRequest::Status => LegacyResponse::Status {
                    uptime_ms: 0,
                    abyss: 0,
                    collision: 0,
                    node: here(pos, heading),
                },
                LegacyRequest::Turn(n) => {
                    heading = Heading::from_index((heading.index() as i8 + n).rem_euclid(4) as u8);
                    LegacyResponse::Ok
                }
                LegacyRequest::Move if field.arms(pos).unwrap().has(heading) => {
                    pos = pos.step(heading).unwrap();
                    moves += 1;
                    LegacyResponse::HitNode(here(pos, heading))
                }
                LegacyRequest::Move => LegacyResponse::Rejected,
                _ => LegacyResponse::Ok,
            };
            port.write_all(&answer.encode()).expect("answer");
        }
    }
    moves
}

#[test]
fn a_2010_robot_explores_under_the_phone_sides_agent() {
    use phone_sim::proxy::LegacyRobot;
    use phone_sim::sim::robot::BoxedStrategy;
    let (mut master, slave) = serialport::TTYPort::pair().expect("pty pair");
    master
        .set_timeout(Duration::from_millis(5))
        .expect("timeout");
    let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let stop2 = stop.clone();
    let robot = std::thread::spawn(move || fake_2010_robot(master, stop2));
    let mut port = slave;
    port.set_timeout(Duration::from_millis(1)).expect("timeout");
    let bounds = Bounds::new(Pos::new(-1, -1), 5, 5);
    let strategy = BoxedStrategy(phone_sim::bench::strategy("tempo").expect("tempo"));
    let legacy = LegacyRobot::new(RobotId(0), port, bounds, strategy, Default::default());
    let mut proxies: Vec<Box<dyn RobotProxy>> = vec![Box::new(legacy)];
    let start = StartPose {
        pos: Pos::new(0, 0),
        heading: Heading::North,
    };
    let mut phone = PhoneSide::new(bounds, vec![start], 600);
    let done = drive(
        &mut phone,
        &mut proxies,
        Some(Duration::from_secs(30)),
        |_| {},
    );
    stop.store(true, std::sync::atomic::Ordering::Relaxed);
    let moves = robot.join().expect("robot thread");
    assert!(done, "the 2010 robot never finished");
    let truth = phone_sim::field::generate::open(3, 3, 0);
    for (p, a) in truth.nodes() {
        assert_eq!(phone.env().map().known_arms(*p), Some(*a), "node {p}");
    }
    assert!(moves >= 8, "{moves} moves");
}
