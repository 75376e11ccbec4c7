//! A real robot over a serial port: Bluetooth SPP (`/dev/rfcommN`) or USB,
//! through the `serialport` crate, speaking the framed protocol. The same
//! proxy serves any byte stream, such as the TCP socket QEMU connects an
//! emulated robot's UART to.

use super::{LinkEnd, ProxyEvent, ProxyStats, RobotProxy};
use core_algo::protocol::{LinkConfig, MAX_FRAME_LEN, Message};
use core_algo::team::RobotId;
use std::io::{Read, Write};
use std::time::Duration;

/// The e-puck2's UART rate.
pub const BAUD: u32 = 115_200;

/// A byte stream to a robot. Reads must not block for long: they return
/// `TimedOut` or `WouldBlock` when nothing arrived.
pub trait Port: Read + Write + Send {}

impl<T: Read + Write + Send> Port for T {}

/// The proxy of a robot on a serial port (or another byte stream).
pub struct SerialRobot {
    id: RobotId,
    name: String,
    port: Box<dyn Port>,
    end: LinkEnd,
    io_errors: u32,
}

impl SerialRobot {
    /// Opens `path` at 115 200 baud for robot `id`.
    pub fn open(id: RobotId, path: &str, link: LinkConfig) -> Result<Self, String> {
        let port = serialport::new(path, BAUD)
            .timeout(Duration::from_millis(1))
            .open()
            .map_err(|e| format!("{path}: cannot open serial port: {e}"))?;
        Ok(SerialRobot::over(id, path, Box::new(port), link))
    }

    /// The proxy of robot `id` on an open byte stream called `name`.
    pub fn over(id: RobotId, name: &str, port: Box<dyn Port>, link: LinkConfig) -> Self {
        SerialRobot {
            id,
            name: name.to_string(),
            port,
            end: LinkEnd::new(link, core_algo::protocol::PHONE, fresh_nonce()),
            io_errors: 0,
        }
    }

    /// The port's name.
    pub fn name(&self) -> &str {
        &self.name
    }
}

/// A fresh link nonce: the clock's nanoseconds, so that a restarted phone
/// side starts a new session.
pub fn fresh_nonce() -> u32 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(1, |d| d.subsec_nanos() ^ d.as_secs() as u32)
}

impl RobotProxy for SerialRobot {
    fn id(&self) -> RobotId {
        self.id
    }

    fn kind(&self) -> &'static str {
        "serial"
    }

    fn send(&mut self, message: Message) {
        self.end.send(message);
    }

    fn poll(&mut self, now: u32, events: &mut Vec<ProxyEvent>) {
        let mut buf = [0u8; 256];
        loop {
            match self.port.read(&mut buf) {
                Ok(0) => break,
                Ok(n) => self.end.link.on_bytes(now, buf.get(..n).unwrap_or(&[])),
                Err(e)
                    if matches!(
                        e.kind(),
                        std::io::ErrorKind::TimedOut | std::io::ErrorKind::WouldBlock
                    ) =>
                {
                    break;
                }
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
                Err(_) => {
                    self.io_errors += 1;
                    break;
                }
            }
        }
        self.end.link.tick(now);
        self.end.flush();
        self.end.events(events);
        let mut frame = [0u8; MAX_FRAME_LEN];
        while let Some(n) = self.end.link.poll_transmit(now, &mut frame) {
            if self.port.write_all(frame.get(..n).unwrap_or(&[])).is_err() {
                self.io_errors += 1;
            }
        }
    }

    fn stats(&self) -> ProxyStats {
        let mut s = self.end.stats();
        s.link_errors += self.io_errors;
        s
    }
}
