//! A simulated robot's proxy: the phone's end of a simulated serial link,
//! speaking the real framed protocol through lossy [`Channel`]s.

use super::{LinkEnd, ProxyEvent, ProxyStats, RobotProxy};
use crate::sim::channel::{Channel, ChannelFaults, ChannelStats};
use core_algo::protocol::{LinkConfig, MAX_FRAME_LEN, Message};
use core_algo::team::RobotId;

/// The proxy of a robot in the simulator.
pub struct SimRobot {
    id: RobotId,
    end: LinkEnd,
    /// Phone → robot.
    pub down: Channel,
    /// Robot → phone.
    pub up: Channel,
}

impl SimRobot {
    /// The proxy of robot `id`, its channels with `faults`, seeded.
    pub fn new(id: RobotId, link: LinkConfig, faults: ChannelFaults, seed: u64) -> Self {
        SimRobot {
            id,
            end: LinkEnd::new(link, core_algo::protocol::PHONE, nonce(seed, 0x9E37_79B9)),
            down: Channel::new(faults, seed ^ 0x5eed_d0e5),
            up: Channel::new(faults, seed ^ 0x0005_eed0),
        }
    }

    /// For how long from `now` the phone's link end stays quiet unless a
    /// frame arrives or a message is sent (see `LinkEnd::quiet_for`); the
    /// simulator keeps the channels' arrivals itself.
    pub fn link_quiet_for(&self, now: u32) -> u32 {
        self.end.quiet_for(now)
    }

    /// Counters of both channels (down, up).
    pub fn channel_stats(&self) -> (ChannelStats, ChannelStats) {
        (self.down.stats(), self.up.stats())
    }
}

/// A link nonce drawn deterministically from a run's seed (a real endpoint
/// draws a fresh random one at every start).
pub fn nonce(seed: u64, salt: u32) -> u32 {
    let x = seed ^ (u64::from(salt) << 17);
    let x = x.wrapping_mul(0x9E37_79B9_7F4A_7C15);
    (x >> 32) as u32 ^ x as u32
}

impl RobotProxy for SimRobot {
    fn id(&self) -> RobotId {
        self.id
    }

    fn kind(&self) -> &'static str {
        "sim"
    }

    fn send(&mut self, message: Message) {
        self.end.send(message);
    }

    fn poll(&mut self, now: u32, events: &mut Vec<ProxyEvent>) {
        while let Some(bytes) = self.up.receive(now) {
            self.end.link.on_bytes(now, &bytes);
        }
        self.end.link.tick(now);
        self.end.flush();
        self.end.events(events);
        let mut buf = [0u8; MAX_FRAME_LEN];
        while let Some(n) = self.end.link.poll_transmit(now, &mut buf) {
            self.down.send(now, buf.get(..n).unwrap_or(&[]));
        }
    }

    fn stats(&self) -> ProxyStats {
        self.end.stats()
    }

    fn is_quiet(&self, now: u32) -> bool {
        self.up.next_arrival().is_none_or(|t| t > now) && self.end.is_quiet(now)
    }
}
