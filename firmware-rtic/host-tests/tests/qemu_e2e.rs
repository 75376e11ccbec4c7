//! Boots the emulated firmware in QEMU (`netduinoplus2`) and plays both the
//! phone (core-algo's reliable link on USART3, QEMU's third `-serial`) and
//! the robot's body (the text body channel on USART2, the second
//! `-serial`), both wired to TCP sockets this test listens on.
//!
//! Needs `qemu-system-arm` and the ELF from `cargo build --release --features
//! qemu` (path in `FIRMWARE_QEMU_ELF`, default `../target/firmware-qemu.elf`,
//! which ci.sh writes). Without them the test reports a skip and passes,
//! unless `REQUIRE_QEMU=1` (set by ci.sh), where it fails.
//!
//! The whole exploration with several emulated robots and simulated bodies
//! is `conquest explore --qemu N` (phone-sim), run by ci.sh.

use core_algo::agent::body::{BodyDecoder, BodyMsg, Order, Report};
use core_algo::agent::firmware::FIRMWARE_VERSION;
use core_algo::geometry::{Arms, Heading, Pos, Turn};
use core_algo::protocol::link::Event;
use core_algo::protocol::message::{RobotState, Status, StrategyKind, StrategySettings};
use core_algo::protocol::{Link, LinkConfig, MAX_FRAME_LEN, Message, PHONE, Pose};
use core_algo::team::RobotId;
use std::io::{ErrorKind, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

/// Whole-run limit handed to timeout(1) around QEMU.
const QEMU_TIMEOUT_S: u32 = 60;

/// QEMU under `timeout(1)`, so it cannot outlive a hung test.
struct Qemu(Child);

impl Drop for Qemu {
    fn drop(&mut self) {
        if let Ok(None) = self.0.try_wait() {
            // SIGTERM (not SIGKILL) so that timeout(1) passes it on to QEMU
            // instead of leaving it orphaned. The child is not reaped yet, so
            // its pid is still ours.
            let _ = Command::new("kill")
                .args(["-TERM", &self.0.id().to_string()])
                .status();
        }
        let _ = self.0.wait();
    }
}

impl Qemu {
    fn wait_exit(&mut self, limit: Duration) -> ExitStatus {
        let deadline = Instant::now() + limit;
        loop {
            if let Some(s) = self.0.try_wait().expect("wait") {
                return s;
            }
            assert!(Instant::now() < deadline, "qemu did not exit in {limit:?}");
            std::thread::sleep(Duration::from_millis(10));
        }
    }
}

/// What the firmware said.
#[derive(Debug, PartialEq)]
enum Heard {
    Phone(Message),
    Body(BodyMsg),
}

/// The phone's and the body's ends of one emulated robot.
struct Robot {
    qemu: Qemu,
    link: Link,
    link_io: TcpStream,
    body_io: TcpStream,
    body: BodyDecoder,
    t0: Instant,
    heard: Vec<Heard>,
}

impl Robot {
    fn now(&self) -> u32 {
        self.t0.elapsed().as_millis() as u32
    }

    fn body_send(&mut self, m: BodyMsg) {
        let (buf, n) = m.encode();
        self.body_io.write_all(&buf[..n]).expect("body write");
    }

    /// One round of I/O: reads both sockets, runs the host link's timers,
    /// sends what it has.
    fn pump(&mut self) {
        let mut buf = [0u8; 256];
        let now = self.now();
        match self.link_io.read(&mut buf) {
            Ok(n) => self.link.on_bytes(now, &buf[..n]),
            Err(e) if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) => {}
            Err(e) => panic!("link read: {e}"),
        }
        match self.body_io.read(&mut buf) {
            Ok(n) => {
                for &b in &buf[..n] {
                    if let Some(m) = self.body.push(b) {
                        self.heard.push(Heard::Body(m));
                    }
                }
            }
            Err(e) if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) => {}
            Err(e) => panic!("body read: {e}"),
        }
        self.link.tick(now);
        while let Some(ev) = self.link.poll_event() {
            if let Event::Received { message, .. } = ev {
                self.heard.push(Heard::Phone(message));
            }
        }
        let mut frame = [0u8; MAX_FRAME_LEN];
        while let Some(n) = self.link.poll_transmit(now, &mut frame) {
            self.link_io.write_all(&frame[..n]).expect("link write");
        }
    }

    /// Pumps (keeping the body channel alive) until `want` matches
    /// something heard; returns it and takes it out of what was heard.
    fn expect(&mut self, what: &str, mut want: impl FnMut(&Heard) -> bool) -> Heard {
        let deadline = Instant::now() + Duration::from_secs(15);
        let mut keep_alive = Instant::now();
        loop {
            // Only the match is taken: the link and the body channel are
            // two UARTs, so a body order may arrive before the report the
            // firmware sent first, and must not be thrown away with it.
            if let Some(i) = self.heard.iter().position(&mut want) {
                return self.heard.remove(i);
            }
            assert!(
                Instant::now() < deadline,
                "no {what}; heard {:?}",
                self.heard
            );
            if keep_alive.elapsed() > Duration::from_millis(500) {
                keep_alive = Instant::now();
                self.body_send(BodyMsg::KeepAlive);
            }
            self.pump();
        }
    }

    fn order(&mut self, o: Order) {
        let want = Heard::Body(BodyMsg::Order(o));
        self.expect(&format!("{o:?}"), |h| *h == want);
    }

    fn node_hit(&mut self, pos: Pos, heading: Heading, arms: Arms) {
        let want = Heard::Phone(Message::NodeHit {
            pose: Pose { pos, heading },
            arms,
        });
        self.expect(&format!("node hit at {pos:?}"), |h| *h == want);
    }

    fn report(&mut self, relative: u8) {
        self.body_send(BodyMsg::Report(Report::NodeHit {
            relative: Arms::from_bits(relative),
        }));
    }
}

fn elf_path() -> PathBuf {
    std::env::var_os("FIRMWARE_QEMU_ELF")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target/firmware-qemu.elf")
        })
}

fn have_qemu() -> bool {
    Command::new("qemu-system-arm")
        .arg("--version")
        .stdout(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

fn accept(listener: &TcpListener, qemu: &mut Qemu) -> TcpStream {
    listener.set_nonblocking(true).expect("nonblocking");
    let t0 = Instant::now();
    loop {
        match listener.accept() {
            Ok((s, _)) => {
                s.set_nonblocking(false).expect("blocking");
                s.set_read_timeout(Some(Duration::from_millis(2)))
                    .expect("timeout");
                return s;
            }
            Err(e) if e.kind() == ErrorKind::WouldBlock => {
                if let Some(status) = qemu.0.try_wait().expect("wait") {
                    panic!("qemu exited before connecting: {status}");
                }
                assert!(
                    t0.elapsed() < Duration::from_secs(10),
                    "qemu did not connect"
                );
                std::thread::sleep(Duration::from_millis(5));
            }
            Err(e) => panic!("accept: {e}"),
        }
    }
}

/// Starts QEMU with USART2 and USART3 connected to sockets we listen on
/// (QEMU is the client of its serial ports) and accepts both connections.
fn boot(elf: &Path, append: &str) -> Robot {
    let body_l = TcpListener::bind("127.0.0.1:0").expect("bind");
    let link_l = TcpListener::bind("127.0.0.1:0").expect("bind");
    let port = |l: &TcpListener| l.local_addr().expect("addr").port();
    let mut cmd = Command::new("timeout");
    cmd.arg(QEMU_TIMEOUT_S.to_string())
        .arg("qemu-system-arm")
        .args(["-machine", "netduinoplus2"])
        .args(["-display", "none", "-monitor", "none"])
        .args(["-semihosting-config", "enable=on,target=native"])
        .args(["-serial", "null", "-serial"])
        .arg(format!("tcp:127.0.0.1:{}", port(&body_l)))
        .arg("-serial")
        .arg(format!("tcp:127.0.0.1:{}", port(&link_l)))
        .arg("-kernel")
        .arg(elf)
        .args(["-append", append]);
    let mut qemu = Qemu(cmd.stdin(Stdio::null()).spawn().expect("start qemu"));
    let body_io = accept(&body_l, &mut qemu);
    let link_io = accept(&link_l, &mut qemu);
    Robot {
        qemu,
        link: Link::new(LinkConfig::default(), PHONE, 0x00C0_FFEE),
        link_io,
        body_io,
        body: BodyDecoder::new(),
        t0: Instant::now(),
        heard: Vec::new(),
    }
}

/// The ELF, or `None` (test skipped) when it or QEMU is missing and
/// `REQUIRE_QEMU=1` is not set.
fn setup() -> Option<PathBuf> {
    let elf = elf_path();
    let required = std::env::var("REQUIRE_QEMU").is_ok_and(|v| v == "1");
    if !elf.exists() || !have_qemu() {
        assert!(
            !required,
            "REQUIRE_QEMU=1 but qemu-system-arm or {} is missing",
            elf.display()
        );
        eprintln!("SKIPPED: needs qemu-system-arm and {}", elf.display());
        return None;
    }
    Some(elf)
}

/// A whole exploration of a two-node field (a dead end north of the start)
/// by one emulated robot: link up, hello, start, scan, move, turn back,
/// home, finished; with garbage on both channels on the way and a status
/// request; then QUIT ends QEMU with status 0.
#[test]
fn explores_a_dead_end_through_link_and_body_channel() {
    let Some(elf) = setup() else { return };
    let mut r = boot(&elf, "selector=1 nonce=12345");
    let started = Instant::now();

    // Both channels announce readiness before we send anything.
    r.expect("body hello", |h| *h == Heard::Body(BodyMsg::Hello));
    let hello = Heard::Phone(Message::Hello {
        robot: RobotId(0),
        firmware: FIRMWARE_VERSION,
    });
    r.expect("link hello", |h| *h == hello);
    let ready = started.elapsed();

    // Corrupt input is counted and dropped, never acted on.
    r.link_io
        .write_all(b"\x05garbage\x00\x00\x13\x37\x00")
        .expect("write");
    r.body_io.write_all(b"ZZZ\nT\n\n").expect("write");

    r.link
        .send(Message::Start {
            pose: Pose {
                pos: Pos::new(0, 0),
                heading: Heading::North,
            },
            settings: StrategySettings {
                kind: StrategyKind::Coordinated,
                team_size: 1,
                speed: 6000,
            },
        })
        .expect("queue");
    r.order(Order::Scan);
    // The start node: one arm, ahead.
    r.report(0b0001);
    r.node_hit(Pos::new(0, 0), Heading::North, Arms::from_bits(0b0001));
    r.order(Order::Move);
    // (0, 1): a dead end, its only arm behind.
    r.report(0b0100);
    r.node_hit(Pos::new(0, 1), Heading::North, Arms::from_bits(0b0100));
    r.order(Order::Turn(Turn::UTurn));
    r.order(Order::Move);
    // Home, facing south: the north arm is behind.
    r.report(0b0100);
    r.node_hit(Pos::new(0, 0), Heading::South, Arms::from_bits(0b0001));
    r.expect("finished status", |h| {
        matches!(
            h,
            Heard::Phone(Message::Status(Status {
                state: RobotState::Finished,
                ..
            }))
        )
    });

    r.link.send_datagram(Message::RequestStatus);
    let status = r.expect("status answer", |h| {
        matches!(h, Heard::Phone(Message::Status(_)))
    });
    let Heard::Phone(Message::Status(s)) = status else {
        unreachable!()
    };
    assert_eq!(s.pose.pos, Pos::new(0, 0));
    assert_eq!(s.state, RobotState::Finished);
    assert!(s.uptime_ms > 0);
    assert_eq!(
        r.link.rx_stats().errors(),
        0,
        "the firmware sent no corrupt frame"
    );

    r.body_send(BodyMsg::Quit);
    let status = r.qemu.wait_exit(Duration::from_secs(10));
    assert!(status.success(), "qemu exit status {status}");
    eprintln!(
        "qemu e2e: ready after {ready:?}, whole exploration {:?}",
        started.elapsed()
    );
}

/// `-append selector=3` makes robot 2; a host that falls silent (no
/// keep-alives on the body channel) makes the firmware end QEMU with a
/// failure, so no emulator outlives its host.
#[test]
fn selector_from_command_line_and_silent_host_ends_qemu() {
    let Some(elf) = setup() else { return };
    let mut r = boot(&elf, "selector=3");
    let hello = Heard::Phone(Message::Hello {
        robot: RobotId(2),
        firmware: FIRMWARE_VERSION,
    });
    r.expect("link hello as robot 2", |h| *h == hello);
    let silent = Instant::now();
    let status = r.qemu.wait_exit(Duration::from_secs(45));
    assert!(!status.success(), "silent host: qemu exit status {status}");
    assert!(
        silent.elapsed() >= Duration::from_secs(5),
        "exited too early: {:?}",
        silent.elapsed()
    );
    eprintln!(
        "qemu e2e: silent host ended QEMU after {:?}",
        silent.elapsed()
    );
}
