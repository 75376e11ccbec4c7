//! Proximity sampling schedule for the 8 IR sensors (TCRT1000).
//!
//! The seed sampled "ambient, then each emitter pair pulsed" in 5 phases of
//! one 1 ms tick each, which gives every sensor a fresh value each 5 ms. The
//! e-puck2 has four pulse lines, each lighting two opposite sensors
//! (PULSE_k → IR k and IR k+4), so the same 5-phase schedule fits: phase 0
//! reads all 8 ambient values with every emitter off and switches pair 0 on;
//! phase k (1..=4) reads the pair lit during the previous tick and switches
//! the next pair on (or all off after the last).
//!
//! The raw ADC value *falls* when more IR arrives, so the proximity value is
//! `ambient − reflected` (≥ 0), minus a per-sensor offset measured with no
//! obstacle (the C firmware's `calibrate_ir`).

/// Number of IR proximity sensors.
pub const SENSORS: usize = 8;

/// Number of phases (ticks) in one full scan.
pub const PHASES: u8 = 5;

/// Value above which a front sensor means "obstacle ahead", in 12-bit units
/// (the seed used 32 on values shifted right by 4, i.e. 512).
pub const COLLISION_THRESHOLD: u16 = 512;

/// What the driver must do with the emitters after a tick.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Emitters {
    /// All pulse lines low.
    AllOff,
    /// Only pulse line `k` (0..4) high.
    Pair(u8),
}

/// The sensors lit by pulse line `pair`.
pub const fn pair_sensors(pair: u8) -> (usize, usize) {
    (pair as usize, pair as usize + 4)
}

/// The scan state machine: call [`ProxScan::tick`] once per millisecond.
#[derive(Clone, Debug)]
pub struct ProxScan {
    phase: u8,
    ambient: [u16; SENSORS],
    reflected: [u16; SENSORS],
    offsets: [u16; SENSORS],
    values: [u16; SENSORS],
    scans: u32,
}

impl Default for ProxScan {
    fn default() -> Self {
        Self::new()
    }
}

impl ProxScan {
    /// A scan about to read ambient light (emitters must be off).
    pub const fn new() -> Self {
        ProxScan {
            phase: 0,
            ambient: [0; SENSORS],
            reflected: [0; SENSORS],
            offsets: [0; SENSORS],
            values: [0; SENSORS],
            scans: 0,
        }
    }

    /// One tick: `read(i)` converts sensor `i` now (with the emitters set by
    /// the previous tick); returns how the emitters must be set until the next
    /// tick.
    pub fn tick(&mut self, mut read: impl FnMut(usize) -> u16) -> Emitters {
        match self.phase {
            0 => {
                for (i, a) in self.ambient.iter_mut().enumerate() {
                    *a = read(i);
                }
                self.phase = 1;
                Emitters::Pair(0)
            }
            p => {
                let (a, b) = pair_sensors(p - 1);
                self.reflected[a] = read(a);
                self.reflected[b] = read(b);
                if p < PHASES - 1 {
                    self.phase = p + 1;
                    Emitters::Pair(p)
                } else {
                    self.finish();
                    self.phase = 0;
                    Emitters::AllOff
                }
            }
        }
    }

    fn finish(&mut self) {
        for i in 0..SENSORS {
            let delta = self.ambient[i].saturating_sub(self.reflected[i]);
            self.values[i] = delta.saturating_sub(self.offsets[i]);
        }
        self.scans = self.scans.wrapping_add(1);
    }

    /// Calibrated proximity values (0 = nothing, larger = closer) of the last
    /// complete scan.
    pub const fn values(&self) -> [u16; SENSORS] {
        self.values
    }

    /// Number of complete scans so far (wraps).
    pub const fn scans(&self) -> u32 {
        self.scans
    }

    /// Sets the no-obstacle offsets subtracted from every delta (measured at
    /// start-up with nothing in range, as the C firmware's `calibrate_ir`).
    pub fn set_offsets(&mut self, offsets: [u16; SENSORS]) {
        self.offsets = offsets;
    }

    /// Bit `i` set when sensor `i` exceeds `threshold`.
    pub fn mask_above(&self, threshold: u16) -> u8 {
        self.values
            .iter()
            .enumerate()
            .filter(|(_, v)| **v > threshold)
            .fold(0, |m, (i, _)| m | (1 << i))
    }
}

/// Whether one of the four front sensors (IR0, IR1, IR6, IR7) sees an obstacle.
pub const fn front_blocked(mask: u8) -> bool {
    mask & 0b1100_0011 != 0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn schedule_lights_each_pair_once_then_all_off() {
        let mut s = ProxScan::new();
        let seq: std::vec::Vec<Emitters> = (0..5).map(|_| s.tick(|_| 0)).collect();
        assert_eq!(
            seq,
            [
                Emitters::Pair(0),
                Emitters::Pair(1),
                Emitters::Pair(2),
                Emitters::Pair(3),
                Emitters::AllOff
            ]
        );
        assert_eq!(s.scans(), 1);
    }

    #[test]
    fn reads_pairs_while_lit() {
        let mut s = ProxScan::new();
        let mut lit: Option<u8> = None;
        for _ in 0..5 {
            let e = s.tick(|i| match lit {
                Some(p) if pair_sensors(p).0 == i || pair_sensors(p).1 == i => 1000,
                Some(_) | None => 3000,
            });
            lit = match e {
                Emitters::Pair(p) => Some(p),
                Emitters::AllOff => None,
            };
        }
        assert_eq!(s.values(), [2000; 8]);
    }

    #[test]
    fn negative_delta_and_offset_saturate() {
        let mut s = ProxScan::new();
        s.set_offsets([100; 8]);
        for phase in 0..5 {
            s.tick(|i| {
                if phase == 0 {
                    500
                } else if i == 2 {
                    450
                } else {
                    900
                }
            });
        }
        let v = s.values();
        assert_eq!(v[2], 0); // delta 50 < offset 100
        assert_eq!(v[0], 0); // reflected > ambient
    }

    #[test]
    fn masks() {
        let mut s = ProxScan::new();
        for phase in 0..5 {
            s.tick(|i| {
                if phase == 0 {
                    4000
                } else if i == 7 {
                    100
                } else {
                    4000
                }
            });
        }
        let m = s.mask_above(COLLISION_THRESHOLD);
        assert_eq!(m, 0b1000_0000);
        assert!(front_blocked(m));
        assert!(!front_blocked(0b0011_1100));
    }
}
