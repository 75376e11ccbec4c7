//! Two link endpoints over a simulated, deterministic, hostile channel.

use std::vec::Vec;

use super::frame::{MAX_FRAME_LEN, PHONE};
use super::link::{Event, Link, LinkConfig, WINDOW};
use super::message::{Broadcast, Message, Pose};
use super::resync::{NodeLogEntry, ResyncStream};
use crate::geometry::{Arms, Heading, Pos};
use crate::team::RobotId;

/// splitmix64: a seeded generator, so every run sees the same channel.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    fn chance(&mut self, percent: u64) -> bool {
        self.next() % 100 < percent
    }

    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
}

/// What the channel does to each frame, in percent.
#[derive(Clone, Copy)]
struct Hostility {
    loss: u64,
    duplicate: u64,
    corrupt: u64,
    garbage: u64,
    /// Extra random delay 0..jitter ms on top of 5 ms: reorders frames.
    jitter: u64,
}

const HOSTILE: Hostility = Hostility {
    loss: 20,
    duplicate: 10,
    corrupt: 10,
    garbage: 5,
    jitter: 40,
};

const PERFECT: Hostility = Hostility {
    loss: 0,
    duplicate: 0,
    corrupt: 0,
    garbage: 0,
    jitter: 0,
};

/// One direction of the channel: chunks in flight with arrival times.
struct Channel {
    in_flight: Vec<(u32, Vec<u8>)>,
    blackout: bool,
}

impl Channel {
    fn new() -> Self {
        Channel {
            in_flight: Vec::new(),
            blackout: false,
        }
    }

    fn send(&mut self, now: u32, bytes: &[u8], h: Hostility, rng: &mut Rng) {
        if self.blackout || rng.chance(h.loss) {
            return;
        }
        let copies = if rng.chance(h.duplicate) { 2 } else { 1 };
        for _ in 0..copies {
            let mut b = bytes.to_vec();
            if rng.chance(h.corrupt) {
                let i = rng.below(b.len() as u64) as usize;
                b[i] ^= 1 << rng.below(8);
            }
            if rng.chance(h.garbage) {
                for _ in 0..rng.below(30) {
                    b.push(rng.next() as u8);
                }
            }
            let delay = 5 + if h.jitter > 0 { rng.below(h.jitter) } else { 0 };
            self.in_flight.push((now.wrapping_add(delay as u32), b));
        }
    }

    fn deliver(&mut self, now: u32, link: &mut Link) {
        let mut i = 0;
        while i < self.in_flight.len() {
            if (now.wrapping_sub(self.in_flight[i].0) as i32) >= 0 {
                let (_, b) = self.in_flight.remove(i);
                link.on_bytes(now, &b);
            } else {
                i += 1;
            }
        }
    }
}

struct Sim {
    now: u32,
    phone: Link,
    robot: Link,
    to_robot: Channel,
    to_phone: Channel,
    rng: Rng,
    h: Hostility,
    phone_events: Vec<Event>,
    robot_events: Vec<Event>,
}

impl Sim {
    fn new(seed: u64, h: Hostility, start: u32) -> Self {
        Sim {
            now: start,
            phone: Link::new(LinkConfig::default(), PHONE, 1),
            robot: Link::new(LinkConfig::default(), RobotId(2), 1),
            to_robot: Channel::new(),
            to_phone: Channel::new(),
            rng: Rng(seed),
            h,
            phone_events: Vec::new(),
            robot_events: Vec::new(),
        }
    }

    /// Advances one millisecond.
    fn step(&mut self) {
        self.arrive();
        self.serve();
    }

    /// Advances the clock and hands each end what arrived.
    fn arrive(&mut self) {
        self.now = self.now.wrapping_add(1);
        let now = self.now;
        self.to_robot.deliver(now, &mut self.robot);
        self.to_phone.deliver(now, &mut self.phone);
    }

    /// Runs both ends' timers and transmitters and takes their events.
    fn serve(&mut self) {
        let now = self.now;
        let mut buf = [0u8; MAX_FRAME_LEN];
        self.phone.tick(now);
        while let Some(n) = self.phone.poll_transmit(now, &mut buf) {
            self.to_robot.send(now, &buf[..n], self.h, &mut self.rng);
        }
        self.robot.tick(now);
        while let Some(n) = self.robot.poll_transmit(now, &mut buf) {
            self.to_phone.send(now, &buf[..n], self.h, &mut self.rng);
        }
        while let Some(e) = self.phone.poll_event() {
            self.phone_events.push(e);
        }
        while let Some(e) = self.robot.poll_event() {
            self.robot_events.push(e);
        }
    }

    fn run(&mut self, ms: u32) {
        for _ in 0..ms {
            self.step();
        }
    }
}

/// The reliable messages among `events`, in order.
fn reliable(events: &[Event]) -> Vec<Message> {
    events
        .iter()
        .filter_map(|e| match e {
            Event::Received {
                seq: Some(_),
                message,
                ..
            } => Some(message.clone()),
            _ => None,
        })
        .collect()
}

fn command(i: u16) -> Message {
    Message::SetLeds { mask: i }
}

fn node_hit(i: u16) -> Message {
    Message::NodeHit {
        pose: Pose {
            pos: Pos::new(i as i16, -(i as i16)),
            heading: Heading::from_index(i as u8),
        },
        arms: Arms::from_bits(i as u8),
    }
}

/// Sends `count` messages each way, as fast as the windows allow, and runs
/// until both sides have everything (or the time budget is spent).
fn exchange(sim: &mut Sim, count: u16, budget_ms: u32) {
    let (mut to_robot, mut to_phone) = (0u16, 0u16);
    for _ in 0..budget_ms {
        while to_robot < count && sim.phone.send(command(to_robot)).is_ok() {
            to_robot += 1;
        }
        while to_phone < count && sim.robot.send(node_hit(to_phone)).is_ok() {
            to_phone += 1;
        }
        sim.step();
        if to_robot == count
            && to_phone == count
            && sim.phone.unacked() == 0
            && sim.robot.unacked() == 0
        {
            return;
        }
    }
}

#[test]
fn hostile_channel_delivers_everything_once_and_in_order() {
    for seed in [1, 2, 3] {
        let mut sim = Sim::new(seed, HOSTILE, 0);
        exchange(&mut sim, 300, 600_000);
        let want_robot: Vec<_> = (0..300).map(command).collect();
        let want_phone: Vec<_> = (0..300).map(node_hit).collect();
        assert_eq!(reliable(&sim.robot_events), want_robot, "seed {seed}");
        assert_eq!(reliable(&sim.phone_events), want_phone, "seed {seed}");
        std::eprintln!(
            "seed {seed}: {} ms simulated, retransmissions phone {} robot {}, \
             rejected chunks at robot {:?}",
            sim.now,
            sim.phone.retransmissions(),
            sim.robot.retransmissions(),
            sim.robot.rx_stats()
        );
        assert!(sim.robot.rx_stats().errors() > 0, "the channel corrupted");
        assert!(sim.phone.retransmissions() > 0, "the channel lost frames");
        assert!(
            !sim.phone_events.contains(&Event::PeerRestarted),
            "no restart happened"
        );
    }
}

#[test]
fn clock_and_sequence_numbers_wrap() {
    // The clock starts just before its wrap; 70 000 messages wrap the
    // 16-bit sequence numbers.
    let mut sim = Sim::new(7, PERFECT, u32::MAX - 500);
    let mut sent = 0u32;
    let mut got = 0u32;
    let mut steps = 0u32;
    while got < 70_000 {
        steps += 1;
        assert!(steps < 500_000, "stalled at {got}");
        while sent < 70_000 && sim.phone.send(command(sent as u16)).is_ok() {
            sent += 1;
        }
        sim.step();
        for e in sim.robot_events.drain(..) {
            if let Event::Received {
                seq: Some(_),
                message,
                ..
            } = e
            {
                assert_eq!(message, command(got as u16));
                got += 1;
            }
        }
    }
}

#[test]
fn heartbeat_keeps_an_idle_link_up_and_silence_loses_it() {
    let mut sim = Sim::new(4, PERFECT, 1000);
    sim.run(10_000);
    assert_eq!(sim.robot_events, [Event::LinkUp]);
    assert_eq!(sim.phone_events, [Event::LinkUp]);
    sim.to_robot.blackout = true;
    sim.to_phone.blackout = true;
    sim.run(3000);
    assert_eq!(sim.robot_events, [Event::LinkUp, Event::LinkLost]);
    assert_eq!(sim.phone_events, [Event::LinkUp, Event::LinkLost]);
}

#[test]
fn commands_survive_a_blackout() {
    let mut sim = Sim::new(5, HOSTILE, 0);
    sim.run(500);
    for i in 0..WINDOW as u16 {
        sim.phone.send(command(i)).unwrap();
    }
    sim.to_robot.blackout = true;
    sim.to_phone.blackout = true;
    sim.run(20_000);
    assert!(sim.phone_events.contains(&Event::LinkLost));
    assert_eq!(
        sim.phone.send(command(99)),
        Err(super::SendError::QueueFull)
    );
    sim.to_robot.blackout = false;
    sim.to_phone.blackout = false;
    sim.run(30_000);
    assert_eq!(sim.phone_events.last(), Some(&Event::LinkUp));
    assert_eq!(sim.phone.unacked(), 0);
    let want: Vec<_> = (0..WINDOW as u16).map(command).collect();
    assert_eq!(reliable(&sim.robot_events), want);
}

#[test]
fn robot_reboot_is_reported_and_the_queue_goes_to_the_new_session() {
    let mut sim = Sim::new(6, HOSTILE, 0);
    exchange(&mut sim, 20, 60_000);
    assert_eq!(reliable(&sim.robot_events).len(), 20);
    // The robot reboots: a new link with a new session; the phone has two
    // commands waiting.
    sim.robot = Link::new(LinkConfig::default(), RobotId(2), 2);
    sim.robot_events.clear();
    sim.phone.send(command(1000)).unwrap();
    sim.phone.send(command(1001)).unwrap();
    sim.run(20_000);
    assert!(sim.phone_events.contains(&Event::PeerRestarted));
    assert_eq!(reliable(&sim.robot_events), [command(1000), command(1001)]);
    assert_eq!(sim.phone.unacked(), 0);
}

#[test]
fn reconnected_robot_gets_the_map_it_missed() {
    let log: Vec<NodeLogEntry> = (0..30)
        .map(|i| NodeLogEntry {
            origin: RobotId((i % 3) as u8),
            pose: Pose {
                pos: Pos::new(i, 2 * i),
                heading: Heading::North,
            },
            arms: Arms::CROSS,
        })
        .collect();
    let mut sim = Sim::new(8, HOSTILE, 0);
    sim.run(300);
    // The robot has applied 10 entries and asks for the rest.
    sim.robot.send(Message::ResyncRequest { have: 10 }).unwrap();
    let mut stream = None;
    for _ in 0..60_000 {
        sim.step();
        for e in sim.phone_events.drain(..) {
            if let Event::Received {
                message: Message::ResyncRequest { have },
                ..
            } = e
            {
                stream = Some(ResyncStream::new(have));
            }
        }
        if let Some(s) = stream.as_mut() {
            s.pump(&log, &mut sim.phone);
        }
        if stream.is_some_and(|s| s.is_done()) && sim.phone.unacked() == 0 {
            break;
        }
    }
    let got = reliable(&sim.robot_events);
    let mut want: Vec<_> = log[10..].iter().map(|e| e.to_message()).collect();
    want.push(Message::ResyncDone { total: 30 });
    assert_eq!(got, want);
    assert!(matches!(
        got[0],
        Message::Relayed {
            origin: RobotId(1),
            broadcast: Broadcast::NodeHit { .. }
        }
    ));
}

#[test]
fn datagrams_are_best_effort_and_newest_wins() {
    let mut sim = Sim::new(9, PERFECT, 0);
    sim.run(100);
    sim.robot.send_datagram(Message::RequestStatus);
    let status = Message::Status(super::message::Status {
        uptime_ms: 1,
        pose: Pose {
            pos: Pos::new(0, 0),
            heading: Heading::North,
        },
        state: super::message::RobotState::Stopped,
        floor: 0,
        proximity: 0,
    });
    assert_eq!(sim.robot.submit(status.clone()), Ok(None));
    assert_eq!(sim.robot.submit(Message::Move), Ok(Some(0)));
    sim.robot.send_datagram(status.clone());
    sim.run(100);
    let got: Vec<_> = sim
        .phone_events
        .iter()
        .filter_map(|e| match e {
            Event::Received {
                seq: None, message, ..
            } => Some(message.clone()),
            _ => None,
        })
        .collect();
    assert_eq!(got, [status]);
    assert_eq!(reliable(&sim.phone_events), [Message::Move]);
}

/// The traffic budget of `docs/protocol.md`, measured: 24 reliable
/// messages per second to the robot (commands and relays of five team
/// mates), 8 reliable and 2 status datagrams per second back, over the
/// hostile channel. Prints bytes per second on the wire each way.
#[test]
fn budget_load_over_the_hostile_channel() {
    let mut sim = Sim::new(11, HOSTILE, 0);
    sim.run(1000);
    let (p0, r0) = (sim.phone.tx_bytes(), sim.robot.tx_bytes());
    let seconds = 60u32;
    let (mut to_robot, mut to_phone) = (0u16, 0u16);
    for t in 0..seconds * 1000 {
        if t % 42 == 0 && sim.phone.send(command(to_robot)).is_ok() {
            to_robot += 1;
        }
        if t % 125 == 0 && sim.robot.send(node_hit(to_phone)).is_ok() {
            to_phone += 1;
        }
        if t % 500 == 0 {
            sim.robot.send_datagram(Message::RequestStatus);
        }
        sim.step();
    }
    sim.run(20_000);
    let phone_bps = (sim.phone.tx_bytes() - p0) / seconds;
    let robot_bps = (sim.robot.tx_bytes() - r0) / seconds;
    std::eprintln!(
        "budget load: phone->robot {phone_bps} B/s ({} msgs), robot->phone {robot_bps} B/s \
         ({} msgs), retransmissions {} / {}",
        to_robot,
        to_phone,
        sim.phone.retransmissions(),
        sim.robot.retransmissions()
    );
    assert_eq!(reliable(&sim.robot_events).len(), usize::from(to_robot));
    assert_eq!(reliable(&sim.phone_events).len(), usize::from(to_phone));
    assert!(to_robot > 1400, "the window kept up with the offered load");
    // 5x headroom on a 115 200 baud link (11 520 B/s).
    assert!(phone_bps * 5 < 11_520 && robot_bps * 5 < 11_520);
}

#[test]
fn link_fits_the_robot_ram() {
    let size = core::mem::size_of::<Link>();
    std::eprintln!("size_of::<Link>() = {size}");
    assert!(size < 4096, "{size} bytes");
}

#[test]
fn reboot_that_draws_the_same_session_byte_is_still_detected() {
    let mut sim = Sim::new(12, HOSTILE, 0);
    exchange(&mut sim, 20, 60_000);
    // Same session byte (1) as before, another first sequence number.
    sim.robot = Link::new(LinkConfig::default(), RobotId(2), 0x00_9A_31_01);
    sim.robot_events.clear();
    sim.phone.send(command(500)).unwrap();
    sim.robot.send(node_hit(7)).unwrap();
    sim.run(20_000);
    assert!(sim.phone_events.contains(&Event::PeerRestarted));
    assert_eq!(reliable(&sim.robot_events), [command(500)]);
    assert_eq!(reliable(&sim.phone_events).last(), Some(&node_hit(7)));
    assert_eq!(sim.phone.unacked() + sim.robot.unacked(), 0);
}

/// A quiet link's timers and transmitter must do nothing: the simulator
/// skips quiet links, and its runs must not change by it.
fn assert_quiet_is_a_no_op(link: &Link, now: u32) {
    let mut copy = link.clone();
    copy.tick(now);
    let mut buf = [0u8; MAX_FRAME_LEN];
    assert_eq!(copy.poll_transmit(now, &mut buf), None, "at {now}");
    assert_eq!(copy.poll_event(), None, "at {now}");
    assert_eq!(
        std::format!("{copy:?}"),
        std::format!("{link:?}"),
        "at {now}"
    );
}

/// [`Link::quiet_for`] names the instant a timer runs out: the link is
/// still quiet a millisecond before, and a copy left alone till then has
/// something to do at it.
fn assert_quiet_ends_on_time(link: &Link, now: u32) {
    let d = link.quiet_for(now);
    assert!(d > 0 && d < u32::MAX, "a heartbeat always runs, at {now}");
    assert_quiet_is_a_no_op(link, now.wrapping_add(d - 1));
    let at = now.wrapping_add(d);
    let mut copy = link.clone();
    copy.tick(at);
    let mut buf = [0u8; MAX_FRAME_LEN];
    let sent = copy.poll_transmit(at, &mut buf).is_some();
    let heard = copy.poll_event().is_some();
    assert!(
        sent || heard || std::format!("{copy:?}") != std::format!("{link:?}"),
        "quiet for {d} ms from {now}, but nothing to do then"
    );
}

#[test]
fn a_quiet_link_has_nothing_to_do() {
    // Hostile, so that every timer runs (resends, syncs, silence), across
    // the clock's wrap.
    let mut sim = Sim::new(11, HOSTILE, u32::MAX - 3_000);
    let (mut quiet, mut busy) = (0u32, 0u32);
    let mut sent = 0u16;
    for ms in 0..8_000u32 {
        // A message each way every 20 ms, as a relaying phone and an
        // exploring robot send them.
        if ms % 20 == 0 && sim.phone.send(command(sent)).is_ok() {
            sent += 1;
            let _ = sim.robot.send(node_hit(sent));
        }
        // A status now and then: a datagram waits for the next poll.
        if ms % 170 == 0 {
            sim.robot.send_datagram(node_hit(ms as u16));
        }
        // A blackout in the middle: the links time out and resync.
        sim.to_robot.blackout = (3_000..5_500).contains(&ms);
        // Asked both before and after what arrived is handed over: a host
        // asks either way (the simulator's robots after, its phone before).
        let now = sim.now.wrapping_add(1);
        for link in [&sim.phone, &sim.robot] {
            if link.is_quiet(now) {
                quiet += 1;
                assert_quiet_is_a_no_op(link, now);
                assert_quiet_ends_on_time(link, now);
            } else {
                busy += 1;
            }
        }
        sim.arrive();
        for link in [&sim.phone, &sim.robot] {
            if link.is_quiet(now) {
                assert_quiet_is_a_no_op(link, now);
            }
        }
        sim.serve();
    }
    assert!(quiet > 4_000 && busy > 300, "quiet {quiet}, busy {busy}");
    assert!(reliable(&sim.robot_events).len() > 200);
}
