//! A simulated serial link: bytes from one end arrive at the other after a
//! latency, unless the channel loses, duplicates or corrupts them.
//!
//! Faults act on whole transmissions (one `poll_transmit` burst, usually one
//! frame), as a Bluetooth SPP link loses or repeats packets, not lone bits.
//! Everything is drawn from a seeded ChaCha8 stream, so a run reproduces.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// How a channel misbehaves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChannelFaults {
    /// Probability that a transmission is lost.
    pub loss: f64,
    /// Probability that a transmission arrives twice.
    pub duplicate: f64,
    /// Probability that one byte of a transmission is flipped.
    pub corrupt: f64,
    /// Fixed one-way latency in milliseconds.
    pub latency_ms: u32,
    /// Extra random latency, uniform in 0..=jitter_ms (reorders bursts).
    pub jitter_ms: u32,
}

impl ChannelFaults {
    /// A perfect link with the latency of a Bluetooth serial hop.
    pub const CLEAN: ChannelFaults = ChannelFaults {
        loss: 0.0,
        duplicate: 0.0,
        corrupt: 0.0,
        latency_ms: 10,
        jitter_ms: 0,
    };

    /// Whether the channel only delays: nothing is lost, repeated,
    /// corrupted or jittered.
    pub fn is_clean(&self) -> bool {
        self.loss <= 0.0 && self.duplicate <= 0.0 && self.corrupt <= 0.0 && self.jitter_ms == 0
    }
}

impl Default for ChannelFaults {
    fn default() -> Self {
        ChannelFaults::CLEAN
    }
}

/// Counters of what the channel did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ChannelStats {
    /// Transmissions offered.
    pub sent: u64,
    /// Transmissions lost.
    pub lost: u64,
    /// Transmissions duplicated.
    pub duplicated: u64,
    /// Transmissions corrupted.
    pub corrupted: u64,
    /// Bytes offered.
    pub bytes: u64,
}

/// One direction of a simulated link.
#[derive(Debug)]
pub struct Channel {
    faults: ChannelFaults,
    rng: ChaCha8Rng,
    /// (arrival time, sequence for stable order, bytes)
    in_flight: BinaryHeap<Reverse<(u32, u64, Vec<u8>)>>,
    seq: u64,
    stats: ChannelStats,
    cut: bool,
}

impl Channel {
    /// A channel with `faults`, seeded.
    pub fn new(faults: ChannelFaults, seed: u64) -> Self {
        Channel {
            faults,
            rng: ChaCha8Rng::seed_from_u64(seed),
            in_flight: BinaryHeap::new(),
            seq: 0,
            stats: ChannelStats::default(),
            cut: false,
        }
    }

    /// Cuts or restores the channel (a robot out of radio range, or dead).
    pub fn set_cut(&mut self, cut: bool) {
        self.cut = cut;
    }

    /// Offers `bytes` at time `now`.
    pub fn send(&mut self, now: u32, bytes: &[u8]) {
        self.stats.sent += 1;
        self.stats.bytes += bytes.len() as u64;
        if self.cut {
            self.stats.lost += 1;
            return;
        }
        // A channel without faults draws nothing: its draws could change
        // nothing, and they were a tenth of the channel's time.
        if self.faults.is_clean() {
            self.seq += 1;
            let at = now.saturating_add(self.faults.latency_ms);
            self.in_flight.push(Reverse((at, self.seq, bytes.to_vec())));
            return;
        }
        if self.rng.random_bool(self.faults.loss.clamp(0.0, 1.0)) {
            self.stats.lost += 1;
            return;
        }
        let copies = if self.rng.random_bool(self.faults.duplicate.clamp(0.0, 1.0)) {
            self.stats.duplicated += 1;
            2
        } else {
            1
        };
        for _ in 0..copies {
            let mut data = bytes.to_vec();
            if !data.is_empty() && self.rng.random_bool(self.faults.corrupt.clamp(0.0, 1.0)) {
                self.stats.corrupted += 1;
                let i = self.rng.random_range(0..data.len());
                data[i] ^= 1 << self.rng.random_range(0..8);
            }
            let jitter = if self.faults.jitter_ms > 0 {
                self.rng.random_range(0..=self.faults.jitter_ms)
            } else {
                0
            };
            let at = now
                .saturating_add(self.faults.latency_ms)
                .saturating_add(jitter);
            self.seq += 1;
            self.in_flight.push(Reverse((at, self.seq, data)));
        }
    }

    /// Takes the next transmission due by `now`.
    pub fn receive(&mut self, now: u32) -> Option<Vec<u8>> {
        match self.in_flight.peek() {
            Some(Reverse((at, _, _))) if *at <= now => {
                self.in_flight.pop().map(|Reverse((_, _, d))| d)
            }
            _ => None,
        }
    }

    /// When the next transmission arrives, if any is in flight.
    pub fn next_arrival(&self) -> Option<u32> {
        self.in_flight.peek().map(|Reverse((at, _, _))| *at)
    }

    /// What the channel did so far.
    pub fn stats(&self) -> ChannelStats {
        self.stats
    }
}
