//! Boots the emulated firmware in QEMU (`netduinoplus2`), waits for its
//! HELLO ready announcement on USART3 (wired to a TCP socket this test
//! listens on), exchanges a few frames and checks the answers, then asks the
//! firmware to end the emulation and checks QEMU's exit status.
//!
//! Needs `qemu-system-arm` and the ELF from `cargo build --release --features
//! qemu` (path in `FIRMWARE_QEMU_ELF`, default `../target/firmware-qemu.elf`,
//! which ci.sh writes). Without them the test reports a skip and passes,
//! unless `REQUIRE_QEMU=1` (set by ci.sh), where it fails.

use drivers_logic::frame::{FrameDecoder, FrameEvent, LINK_VERSION, encode_frame};
use std::io::{ErrorKind, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// Whole-run limit handed to timeout(1) around QEMU.
const QEMU_TIMEOUT_S: u32 = 30;

struct Link {
    stream: TcpStream,
    decoder: FrameDecoder,
}

impl Link {
    fn send(&mut self, payload: &[u8]) {
        let mut buf = [0u8; 128];
        let n = encode_frame(payload, &mut buf).expect("frame fits");
        self.stream.write_all(&buf[..n]).expect("send");
    }

    fn recv(&mut self) -> Vec<u8> {
        let mut byte = [0u8; 1];
        loop {
            match self.stream.read(&mut byte) {
                Ok(0) => panic!("firmware closed the link"),
                Ok(_) => match self.decoder.push(byte[0]) {
                    Some(FrameEvent::Frame(n)) => return self.decoder.payload(n).to_vec(),
                    Some(FrameEvent::Dropped) => panic!("firmware sent a corrupt frame"),
                    None => {}
                },
                Err(e) if e.kind() == ErrorKind::WouldBlock || e.kind() == ErrorKind::TimedOut => {
                    panic!("no frame from the firmware within the read timeout")
                }
                Err(e) => panic!("read: {e}"),
            }
        }
    }

    fn request(&mut self, payload: &[u8]) -> Vec<u8> {
        self.send(payload);
        self.recv()
    }
}

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

fn i32_at(b: &[u8], i: usize) -> i32 {
    i32::from_le_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]])
}

fn u16_at(b: &[u8], i: usize) -> u16 {
    u16::from_le_bytes([b[i], b[i + 1]])
}

/// Starts QEMU with the firmware's USART3 connected to a socket we listen on
/// (QEMU is the client of its third serial port) and accepts the connection.
fn boot(elf: &Path, append: Option<&str>) -> (Qemu, Link, Instant) {
    let listener = TcpListener::bind("127.0.0.1:0").expect("bind");
    let port = listener.local_addr().expect("addr").port();
    let started = Instant::now();
    let mut cmd = Command::new("timeout");
    cmd.arg(QEMU_TIMEOUT_S.to_string())
        .arg("qemu-system-arm")
        .args(["-machine", "netduinoplus2"])
        .args(["-display", "none", "-monitor", "none"])
        .args(["-semihosting-config", "enable=on,target=native"])
        .args(["-serial", "null", "-serial", "null", "-serial"])
        .arg(format!("tcp:127.0.0.1:{port}"))
        .arg("-kernel")
        .arg(elf);
    if let Some(a) = append {
        cmd.args(["-append", a]);
    }
    let mut qemu = Qemu(cmd.stdin(Stdio::null()).spawn().expect("start qemu"));

    listener.set_nonblocking(true).expect("nonblocking");
    let stream = loop {
        match listener.accept() {
            Ok((s, _)) => break s,
            Err(e) if e.kind() == ErrorKind::WouldBlock => {
                if let Some(status) = qemu.0.try_wait().expect("wait") {
                    panic!("qemu exited before connecting: {status}");
                }
                assert!(
                    started.elapsed() < Duration::from_secs(10),
                    "qemu did not connect"
                );
                std::thread::sleep(Duration::from_millis(10));
            }
            Err(e) => panic!("accept: {e}"),
        }
    };
    stream.set_nonblocking(false).expect("blocking");
    stream
        .set_read_timeout(Some(Duration::from_secs(5)))
        .expect("timeout");
    let link = Link {
        stream,
        decoder: FrameDecoder::new(),
    };
    (qemu, link, started)
}

/// Sends QUIT, expects BYE, and waits for QEMU to exit with status 0.
fn quit(qemu: &mut Qemu, link: &mut Link) {
    assert_eq!(link.request(&[0x7F]), [0xFF]);
    let deadline = Instant::now() + Duration::from_secs(5);
    let status = loop {
        if let Some(s) = qemu.0.try_wait().expect("wait") {
            break s;
        }
        assert!(Instant::now() < deadline, "qemu did not exit after QUIT");
        std::thread::sleep(Duration::from_millis(10));
    };
    assert!(status.success(), "qemu exit status {status}");
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

#[test]
fn boots_announces_ready_and_talks() {
    let Some(elf) = setup() else { return };
    let (mut qemu, mut link, started) = boot(&elf, None);

    // Ready announcement first, before we send anything.
    let hello = link.recv();
    let boot = started.elapsed();
    assert_eq!(
        hello,
        [0x01, LINK_VERSION, 1, 2],
        "HELLO: version, robot 1, mode emulated"
    );

    for seq in [0u8, 7, 255] {
        assert_eq!(
            link.request(&[0x02, seq]),
            [0x82, seq],
            "PONG echoes the sequence number"
        );
    }
    assert_eq!(link.request(&[0x42]), [0xEE, 1], "unknown kind");
    assert_eq!(link.request(&[0x02]), [0xEE, 2], "PING without its byte");

    // Drive forward-left, let the virtual steppers run, then read the status.
    let driving = Instant::now();
    assert_eq!(
        link.request(&[0x04, 0x58, 0x02, 0x2C, 0x01]),
        [0x84, 0x58, 0x02, 0x2C, 0x01]
    );
    std::thread::sleep(Duration::from_millis(300));
    let st = link.request(&[0x03]);
    let drove = driving.elapsed();
    assert_eq!(st.len(), 16, "STATUS length: {st:?}");
    assert_eq!(st[0], 0x83);
    assert_eq!(st[1], 1, "selector");
    let (left, right) = (i32_at(&st, 2), i32_at(&st, 6));
    assert!(
        left > 0 && right > 0 && left > right,
        "steps {left} {right} after 600/300 steps/s"
    );
    assert_eq!(u16_at(&st, 10), 0, "nothing visited yet");
    assert_eq!(u16_at(&st, 12), 1024, "map capacity");
    assert_eq!(u16_at(&st, 14), 256, "virtual floor: centre on black");

    // Record nodes in the robot's 1024-node map.
    assert_eq!(link.request(&[0x05, 0, 0, 0, 0, 0b1111]), [0x85, 1, 1, 0]);
    assert_eq!(link.request(&[0x05, 1, 0, 0, 0, 0b1111]), [0x85, 1, 2, 0]);
    // (0,1) without a south arm contradicts (0,0)'s north arm: refused.
    assert_eq!(
        link.request(&[0x05, 0, 0, 1, 0, 0b0001]),
        [0x85, 0, 2, 0],
        "conflict"
    );
    assert_eq!(
        link.request(&[0x05, 100, 0, 0, 0, 0b0101]),
        [0x85, 0, 2, 0],
        "outside the map"
    );
    assert_eq!(u16_at(&link.request(&[0x03]), 10), 2);

    // Stop: BYE, then QEMU exits with the firmware's status 0.
    quit(&mut qemu, &mut link);
    eprintln!(
        "qemu e2e: HELLO after {:?}, whole run {:?}; left wheel {} steps in {:?} of host time at 600 steps/s ({:.0}% of real time)",
        boot,
        started.elapsed(),
        left,
        drove,
        left as f64 / 600.0 / drove.as_secs_f64() * 100.0
    );
}

/// Two emulated robots get their ids from `-append selector=N`; selector 0
/// boots into the calibration run, which drives forward on its own.
#[test]
fn selector_from_command_line_and_calibration_mode() {
    let Some(elf) = setup() else { return };

    let (mut qemu, mut link, _) = boot(&elf, Some("selector=2"));
    assert_eq!(link.recv(), [0x01, LINK_VERSION, 2, 2], "HELLO as robot 2");
    assert_eq!(link.request(&[0x03])[1], 2, "STATUS selector");
    quit(&mut qemu, &mut link);

    let (mut qemu, mut link, _) = boot(&elf, Some("selector=0"));
    assert_eq!(link.recv(), [0x01, LINK_VERSION, 0, 2], "HELLO as robot 0");
    // Settling takes 100 ms of emulated time, then both wheels drive forward
    // at 300 steps/s without any SPEED request.
    std::thread::sleep(Duration::from_millis(600));
    let st = link.request(&[0x03]);
    let (left, right) = (i32_at(&st, 2), i32_at(&st, 6));
    assert!(
        left > 0 && left == right,
        "calibration drives straight: {left} {right}"
    );
    quit(&mut qemu, &mut link);
}
