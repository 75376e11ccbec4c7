//! One proxy per robot (seed §3.1): the only way the phone side talks to a
//! robot. Every kind of robot, simulated, real over a serial port, or a 2010
//! e-puck, sits behind the one [`RobotProxy`] trait, so the environment,
//! the handlers and the UI never know which kind they talk to.

pub mod legacy;
pub mod serial;
pub mod sim;

use core_algo::protocol::Message;
use core_algo::team::RobotId;

pub use legacy::LegacyRobot;
pub use serial::SerialRobot;
pub use sim::SimRobot;

/// What a proxy heard from its robot.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ProxyEvent {
    /// A message from the robot.
    Message(Message),
    /// The link came (back) up.
    LinkUp,
    /// The link went silent.
    LinkLost,
    /// The robot restarted: it forgot everything.
    Restarted,
}

/// Counters of one proxy's link.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ProxyStats {
    /// Frames sent again.
    pub retransmissions: u32,
    /// Corrupt frames dropped.
    pub link_errors: u32,
    /// Messages waiting for room in the link's window.
    pub queued: usize,
    /// Frames sent to the robot.
    pub tx_frames: u32,
    /// Valid frames received from the robot.
    pub rx_frames: u32,
}

/// The phone side's handle on one robot.
pub trait RobotProxy: Send {
    /// The robot's id.
    fn id(&self) -> RobotId;

    /// What kind of robot this is ("sim", "serial", "legacy").
    fn kind(&self) -> &'static str;

    /// Queues a message for reliable delivery.
    fn send(&mut self, message: Message);

    /// Does the proxy's I/O and timers at `now` (ms) and collects what the
    /// robot said.
    fn poll(&mut self, now: u32, events: &mut Vec<ProxyEvent>);

    /// Link counters.
    fn stats(&self) -> ProxyStats;

    /// Whether [`RobotProxy::poll`] at `now` would do nothing: no bytes
    /// in, no timer due, nothing to send. A caller may skip a quiet
    /// proxy. Only a proxy that can tell without doing I/O says so.
    fn is_quiet(&self, _now: u32) -> bool {
        false
    }
}

/// The link-level part every protocol-speaking endpoint on the host shares
/// (proxies, and the simulated robots' firmware): a reliable
/// [`Link`](core_algo::protocol::Link) and an unbounded outbox in front of
/// its fixed window.
pub(crate) struct LinkEnd {
    pub link: core_algo::protocol::Link,
    outbox: std::collections::VecDeque<Message>,
}

impl LinkEnd {
    pub fn new(config: core_algo::protocol::LinkConfig, local: RobotId, nonce: u32) -> Self {
        LinkEnd {
            link: core_algo::protocol::Link::new(config, local, nonce),
            outbox: std::collections::VecDeque::new(),
        }
    }

    pub fn send(&mut self, m: Message) {
        self.outbox.push_back(m);
        self.flush();
    }

    /// Whether flushing, the link's timers and its transmitter would all do
    /// nothing at `now` (see [`Link::is_quiet`](core_algo::protocol::Link::is_quiet)).
    pub fn is_quiet(&self, now: u32) -> bool {
        self.quiet_for(now) > 0
    }

    /// For how long from `now` it stays quiet unless something arrives or
    /// is sent (see [`Link::quiet_for`](core_algo::protocol::Link::quiet_for)).
    pub fn quiet_for(&self, now: u32) -> u32 {
        if self.outbox.is_empty() {
            self.link.quiet_for(now)
        } else {
            0
        }
    }

    /// Messages still waiting for room in the window.
    pub fn queued(&self) -> usize {
        self.outbox.len()
    }

    pub fn flush(&mut self) {
        while let Some(m) = self.outbox.front() {
            if self.link.send(m.clone()).is_err() {
                break;
            }
            self.outbox.pop_front();
        }
    }

    pub fn events(&mut self, events: &mut Vec<ProxyEvent>) {
        use core_algo::protocol::Event;
        while let Some(e) = self.link.poll_event() {
            events.push(match e {
                Event::Received { message, .. } => ProxyEvent::Message(message),
                Event::LinkUp => ProxyEvent::LinkUp,
                Event::LinkLost => ProxyEvent::LinkLost,
                Event::PeerRestarted => ProxyEvent::Restarted,
            });
        }
    }

    pub fn stats(&self) -> ProxyStats {
        ProxyStats {
            retransmissions: self.link.retransmissions(),
            link_errors: self.link.rx_stats().errors(),
            queued: self.outbox.len(),
            tx_frames: self.link.tx_frames(),
            rx_frames: self.link.rx_stats().frames,
        }
    }
}
