//! `conquest explore --qemu N`: the real firmware, emulated in QEMU, with
//! simulated bodies attached.
//!
//! Every robot is one `qemu-system-arm -machine netduinoplus2` process
//! running the firmware's `qemu` build. QEMU connects two of the emulated
//! STM32's USARTs to TCP sockets this process listens on:
//!
//! * USART3 (QEMU's third `-serial`) carries the real robot ↔ phone link
//!   protocol, exactly what an e-puck2 sends over Bluetooth; the phone side
//!   talks to it through an ordinary [`SerialRobot`] proxy;
//! * USART2 (the second `-serial`) is the body channel
//!   ([`BodyMsg`] text lines): the
//!   firmware's agent sends its orders (turn, move, scan) and a simulated
//!   [`Bodies`] on the true field carries them out and reports node hits,
//!   collisions and bumps back.
//!
//! QEMU runs in real time, so the bodies move `--qemu-scale` times faster
//! than a real e-puck (the robots are told the scaled speed, so their agents
//! cost moves the same way), and the report converts the makespan back to
//! the real speed. The phone side, the handlers and the report are those of
//! the simulator. Every QEMU child is killed when the run ends, however it
//! ends; and the firmware ends QEMU itself when the host falls silent.

use crate::cli::CliError;
use crate::explore_cmd::{ExploreArgs, finish, report};
use crate::field::Field;
use crate::phone::PhoneSide;
use crate::proxy::{RobotProxy, SerialRobot};
use crate::sim::body::{Bodies, Report};
use crate::sim::{outcome_of, window};
use core_algo::agent::body::{BodyDecoder, BodyMsg};
use core_algo::protocol::LinkConfig;
use core_algo::team::RobotId;
use core_algo::timing::Timing;
use std::io::{ErrorKind, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

/// The emulator binary.
pub const QEMU: &str = "qemu-system-arm";

/// How long QEMU may take to connect its serial ports.
const CONNECT_TIMEOUT: Duration = Duration::from_secs(20);
/// How often the host tells each firmware it is alive.
const KEEP_ALIVE: Duration = Duration::from_millis(500);
/// How long a robot may take to announce its body channel after connecting.
const HELLO_TIMEOUT: Duration = Duration::from_secs(20);

/// The QEMU command line of one emulated robot (printed by `--verbose`
/// runs and documented in docs/firmware.md): the firmware's USART2 and
/// USART3 go to TCP ports the host listens on.
pub fn qemu_args(
    elf: &Path,
    body_port: u16,
    link_port: u16,
    selector: u8,
    nonce: u32,
) -> Vec<String> {
    [
        "-machine",
        "netduinoplus2",
        "-display",
        "none",
        "-monitor",
        "none",
        "-semihosting-config",
        "enable=on,target=native",
        "-serial",
        "null",
    ]
    .iter()
    .map(|s| s.to_string())
    .chain([
        "-serial".into(),
        format!("tcp:127.0.0.1:{body_port}"),
        "-serial".into(),
        format!("tcp:127.0.0.1:{link_port}"),
        "-kernel".into(),
        elf.display().to_string(),
        "-append".into(),
        format!("selector={selector} nonce={nonce}"),
    ])
    .collect()
}

/// The firmware ELF: `--qemu-firmware`, else what firmware-rtic/ci.sh
/// writes, else cargo's output path of `cargo build --release --features
/// qemu`.
pub fn firmware_path(given: Option<&Path>) -> PathBuf {
    if let Some(p) = given {
        return p.to_path_buf();
    }
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    let ci = root.join("firmware-rtic/target/firmware-qemu.elf");
    if ci.exists() {
        return ci;
    }
    root.join("firmware-rtic/target/thumbv7em-none-eabihf/release/firmware-rtic")
}

/// One QEMU child; killed and reaped when dropped, so no emulator outlives
/// the run.
struct Emulator {
    child: Child,
    /// Its exit status, once reaped.
    status: Option<ExitStatus>,
}

impl Emulator {
    /// The exit status if it has ended.
    fn ended(&mut self) -> Option<ExitStatus> {
        if self.status.is_none() {
            self.status = self.child.try_wait().ok().flatten();
        }
        self.status
    }

    /// Waits up to `limit` for it to end by itself, then kills it.
    fn stop(&mut self, limit: Duration) -> Option<ExitStatus> {
        let t0 = Instant::now();
        while t0.elapsed() < limit {
            if let Some(s) = self.ended() {
                return Some(s);
            }
            std::thread::sleep(Duration::from_millis(10));
        }
        let _ = self.child.kill();
        self.status = self.child.wait().ok();
        None
    }
}

impl Drop for Emulator {
    fn drop(&mut self) {
        if self.ended().is_none() {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

/// The host's end of one robot's body channel.
struct BodyChannel {
    stream: TcpStream,
    decoder: BodyDecoder,
    ready: bool,
    errors: u32,
}

impl BodyChannel {
    fn send(&mut self, msg: BodyMsg) {
        let (buf, n) = msg.encode();
        if self.stream.write_all(buf.get(..n).unwrap_or(&[])).is_err() {
            self.errors += 1;
        }
    }

    /// Everything the firmware said since the last call.
    fn receive(&mut self, out: &mut Vec<BodyMsg>) {
        let mut buf = [0u8; 256];
        loop {
            match self.stream.read(&mut buf) {
                Ok(0) => break,
                Ok(n) => {
                    for &b in buf.get(..n).unwrap_or(&[]) {
                        if let Some(m) = self.decoder.push(b) {
                            out.push(m);
                        }
                    }
                    if n < buf.len() {
                        break;
                    }
                }
                Err(e) if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) => break,
                Err(e) if e.kind() == ErrorKind::Interrupted => {}
                Err(_) => {
                    self.errors += 1;
                    break;
                }
            }
        }
    }
}

/// Accepts QEMU's connection on `listener`, watching the child meanwhile.
fn accept(listener: &TcpListener, emu: &mut Emulator, what: &str) -> Result<TcpStream, CliError> {
    listener
        .set_nonblocking(true)
        .map_err(|e| CliError::Failed(format!("listen: {e}")))?;
    let t0 = Instant::now();
    loop {
        match listener.accept() {
            Ok((s, _)) => {
                s.set_nonblocking(false)
                    .and_then(|()| s.set_read_timeout(Some(Duration::from_millis(1))))
                    .and_then(|()| s.set_nodelay(true))
                    .map_err(|e| CliError::Failed(format!("{what}: {e}")))?;
                return Ok(s);
            }
            Err(e) if e.kind() == ErrorKind::WouldBlock => {
                if let Some(s) = emu.ended() {
                    return Err(CliError::Failed(format!(
                        "{QEMU} exited ({s}) before connecting its {what}"
                    )));
                }
                if t0.elapsed() > CONNECT_TIMEOUT {
                    return Err(CliError::Failed(format!(
                        "{QEMU} did not connect its {what}"
                    )));
                }
                std::thread::sleep(Duration::from_millis(5));
            }
            Err(e) => return Err(CliError::Failed(format!("accept {what}: {e}"))),
        }
    }
}

/// One emulated robot as the host holds it.
struct Robot {
    emu: Emulator,
    body: BodyChannel,
}

/// Starts robot `i`'s QEMU and connects to it.
fn launch(elf: &Path, i: usize, link: LinkConfig) -> Result<(Robot, SerialRobot), CliError> {
    let bind =
        || TcpListener::bind("127.0.0.1:0").map_err(|e| CliError::Failed(format!("listen: {e}")));
    let (body_l, link_l) = (bind()?, bind()?);
    let port = |l: &TcpListener| {
        l.local_addr()
            .map(|a| a.port())
            .map_err(|e| CliError::Failed(format!("listen: {e}")))
    };
    let selector = u8::try_from(i + 1).unwrap_or(u8::MAX);
    let nonce = crate::proxy::serial::fresh_nonce() ^ (i as u32).rotate_left(16);
    let args = qemu_args(elf, port(&body_l)?, port(&link_l)?, selector, nonce);
    let child = Command::new(QEMU)
        .args(&args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .spawn()
        .map_err(|e| CliError::Failed(format!("cannot start {QEMU}: {e}")))?;
    let mut emu = Emulator {
        child,
        status: None,
    };
    // QEMU opens its serial ports in order: USART2 (body) before USART3.
    let body = accept(&body_l, &mut emu, "body channel (USART2)")?;
    let link_stream = accept(&link_l, &mut emu, "link (USART3)")?;
    let id = RobotId(i as u8);
    let proxy = SerialRobot::over(id, &format!("qemu robot {i}"), Box::new(link_stream), link);
    Ok((
        Robot {
            emu,
            body: BodyChannel {
                stream: body,
                decoder: BodyDecoder::new(),
                ready: false,
                errors: 0,
            },
        },
        proxy,
    ))
}

fn check_qemu() -> Result<(), CliError> {
    let ok = Command::new(QEMU)
        .arg("--version")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if ok {
        Ok(())
    } else {
        Err(CliError::Failed(format!(
            "{QEMU} not found: install QEMU (Debian/Ubuntu: apt-get install qemu-system-arm)"
        )))
    }
}

/// `conquest explore --qemu N`: runs the exploration and prints the report.
pub fn run(field: &Field, a: &ExploreArgs) -> Result<(), CliError> {
    let n = a.qemu.unwrap_or(1);
    if n == 0 || n > field.starts().len() || n > usize::from(u8::MAX) - 1 {
        return Err(CliError::BadInput(format!(
            "--qemu {n}: expected 1..={} robots (the field's start poses)",
            field.starts().len()
        )));
    }
    check_qemu()?;
    let elf = firmware_path(a.qemu_firmware.as_deref());
    if !elf.is_file() {
        return Err(CliError::Failed(format!(
            "{}: no QEMU firmware; build it with `cd firmware-rtic && cargo build --release --features qemu` or pass --qemu-firmware",
            elf.display()
        )));
    }
    let scale = a.qemu_scale.clamp(1, 50);
    let speed = a.speed.clamp(1, 1000);
    let nominal = Timing::from_hardware(u32::from(field.spacing_mm()), speed);
    let fast = Timing::from_hardware(u32::from(field.spacing_mm()), speed * scale);
    // QEMU's clock lags the host's under load: give the links slack.
    let link = LinkConfig {
        link_timeout_ms: 5_000,
        ..LinkConfig::default()
    };

    let mut robots = Vec::new();
    let mut proxies: Vec<Box<SerialRobot>> = Vec::new();
    for i in 0..n {
        let (r, p) = launch(&elf, i, link)?;
        robots.push(r);
        proxies.push(Box::new(p));
    }
    let starts: Vec<_> = field.starts().iter().take(n).copied().collect();
    let mut bodies = Bodies::new(
        field.nodes().clone(),
        fast,
        &starts
            .iter()
            .map(|s| (s.pos, s.heading))
            .collect::<Vec<_>>(),
    );
    let mut phone = PhoneSide::new(
        window(field),
        starts,
        u16::try_from(speed * scale).unwrap_or(u16::MAX),
    );

    let t0 = Instant::now();
    let limit = Duration::from_secs(u64::from(a.qemu_timeout.max(1)));
    let mut last_keep_alive: Option<Instant> = None;
    let mut done_at = None;
    let mut mapped_at: Option<u32> = None;
    let mut inbox = Vec::new();
    let mut reports: Vec<(RobotId, Report)> = Vec::new();
    let mut failure = None;
    while t0.elapsed() < limit {
        let now = u32::try_from(t0.elapsed().as_millis()).unwrap_or(u32::MAX);
        if last_keep_alive.is_none_or(|t| t.elapsed() >= KEEP_ALIVE) {
            last_keep_alive = Some(Instant::now());
            for r in &mut robots {
                r.body.send(BodyMsg::KeepAlive);
            }
        }
        for (i, r) in robots.iter_mut().enumerate() {
            if let Some(s) = r.emu.ended() {
                failure = Some(format!("robot {i}: {QEMU} exited early ({s})"));
            }
            if !r.body.ready && t0.elapsed() > HELLO_TIMEOUT {
                failure = Some(format!("robot {i}: no body channel hello"));
            }
            inbox.clear();
            r.body.receive(&mut inbox);
            for m in inbox.drain(..) {
                match m {
                    BodyMsg::Hello => r.body.ready = true,
                    BodyMsg::Order(o) => bodies.order(RobotId(i as u8), o, now, &mut reports),
                    _ => r.body.errors += 1,
                }
            }
        }
        if failure.is_some() {
            break;
        }
        bodies.advance(now, &mut reports);
        for (id, rep) in reports.drain(..) {
            if let Some(r) = robots.get_mut(id.index()) {
                r.body.send(BodyMsg::Report(rep));
            }
        }
        phone.process(now, &mut proxies);
        let map = phone.env().map();
        if mapped_at.is_none() && map.visited_len() > 0 && map.is_complete() {
            mapped_at = Some(now);
        }
        let idle = bodies.bodies().iter().all(|b| b.is_idle());
        if done_at.is_none() && phone.env().finished_at().is_some() && idle {
            done_at = Some(now);
            break;
        }
        std::thread::sleep(Duration::from_millis(1));
    }
    let wall = t0.elapsed().as_secs_f64();
    let end = u32::try_from(t0.elapsed().as_millis()).unwrap_or(u32::MAX);

    // Ask every firmware to end the emulation; a healthy one exits 0.
    for r in &mut robots {
        r.body.send(BodyMsg::Quit);
    }
    let mut bad_exit = Vec::new();
    for (i, r) in robots.iter_mut().enumerate() {
        match r.emu.stop(Duration::from_secs(3)) {
            Some(s) if s.success() => {}
            Some(s) => bad_exit.push(format!("robot {i}: {QEMU} exited with {s}")),
            None => bad_exit.push(format!("robot {i}: {QEMU} did not quit, killed")),
        }
        if r.body.errors > 0 {
            eprintln!("robot {i}: {} body channel errors", r.body.errors);
        }
    }
    if let Some(f) = failure {
        return Err(CliError::Failed(f));
    }
    // Both directions of every link; TCP loses nothing.
    let frames = proxies
        .iter()
        .map(|p| {
            let s = p.stats();
            u64::from(s.tx_frames) + u64::from(s.rx_frames)
        })
        .sum::<u64>();
    let alive = vec![true; n];
    let mut outcome = outcome_of(
        field,
        phone.env(),
        &bodies,
        &alive,
        done_at.unwrap_or(end).saturating_mul(scale),
        (frames, 0),
        core_algo::localize::Frame::IDENTITY,
    );
    outcome.mapped_ms = mapped_at.map(|t| t.saturating_mul(scale));
    let mut r = report(field, a, nominal, &outcome, wall);
    r.robots = n;
    r.strategy = "firmware (minpos)".into();
    finish(
        field,
        a,
        phone.env(),
        &bodies,
        &r,
        core_algo::localize::Frame::IDENTITY,
    )?;
    if !bad_exit.is_empty() {
        return Err(CliError::Failed(bad_exit.join("; ")));
    }
    if done_at.is_none() {
        return Err(CliError::Failed(format!(
            "the emulated team did not finish within {} s",
            limit.as_secs()
        )));
    }
    Ok(())
}
