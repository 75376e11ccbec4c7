//! The on-the-spot 360° scan that classifies the start node.
//!
//! A robot put down on a node does not know the node's shape, and the
//! driving detector needs a line to arrive along. So the robot turns once
//! clockwise on the spot; its centre floor sensor, ahead of the axle, sweeps
//! a circle around the node and crosses every arm once. The middle of each
//! black interval is an arm's direction. The robot was set down roughly
//! aligned, so the first arm's offset from the nearest quarter turn is taken
//! as the misalignment and removed from all arms before each is assigned to
//! ahead, right, behind or left (the 2010 algorithm, with its ±50-step
//! tolerance scaled to the turn).

use crate::geometry::Arms;

/// The most black intervals a scan records: four arms, one spare for a
/// split interval.
pub const MAX_ARMS: usize = 6;

/// Why a scan gave no shape.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum ScanError {
    /// No arm, or more intervals than a node can have.
    ArmCount(u8),
    /// An interval lies between two quarter-turn directions.
    Misaligned,
}

impl ScanError {
    /// One-byte code for the phone and the LEDs.
    pub const fn code(self) -> u8 {
        match self {
            ScanError::ArmCount(n) => 0x30 | (n & 0x0f),
            ScanError::Misaligned => 0x40,
        }
    }
}

/// The scan's result: the node's arms relative to the direction the robot
/// faces after correcting `misalignment` (steps, clockwise positive: turn
/// back by this much to face the grid).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct ScanResult {
    /// Arms relative to the corrected heading.
    pub arms: Arms,
    /// The robot's heading error in wheel steps of on-the-spot rotation.
    pub misalignment: i32,
}

/// Records black intervals of the centre sensor over one full turn.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Scan {
    full_turn: i32,
    tolerance: i32,
    started_black: Option<bool>,
    black_since: Option<i32>,
    white_since: Option<i32>,
    /// (start, end) of each closed interval, in rotation steps.
    intervals: [(i32, i32); MAX_ARMS],
    count: usize,
    overflow: bool,
    debounce: i32,
}

impl Scan {
    /// A scan for a robot whose full on-the-spot turn takes `full_turn`
    /// wheel steps; arms must lie within `tolerance` steps of a quarter turn.
    pub const fn new(full_turn: i32, tolerance: i32) -> Scan {
        Scan {
            full_turn,
            tolerance,
            started_black: None,
            black_since: None,
            white_since: None,
            intervals: [(0, 0); MAX_ARMS],
            count: 0,
            overflow: false,
            debounce: 3,
        }
    }

    /// Feeds whether the centre sensor sees black at `rotation` steps
    /// (clockwise) since the scan began.
    pub fn update(&mut self, black: bool, rotation: i32) {
        if self.started_black.is_none() {
            self.started_black = Some(black);
            if black {
                self.black_since = Some(rotation);
            }
            return;
        }
        if black {
            self.white_since = None;
            if self.black_since.is_none() {
                self.black_since = Some(rotation);
            }
        } else if let Some(start) = self.black_since {
            let end = *self.white_since.get_or_insert(rotation);
            if rotation.saturating_sub(end) > self.debounce {
                self.black_since = None;
                self.white_since = None;
                self.push(start, end);
            }
        }
    }

    fn push(&mut self, start: i32, end: i32) {
        match self.intervals.get_mut(self.count) {
            Some(slot) => {
                *slot = (start, end);
                self.count += 1;
            }
            None => self.overflow = true,
        }
    }

    /// Closes the scan after the full turn and classifies the arms.
    pub fn finish(mut self, rotation: i32) -> Result<ScanResult, ScanError> {
        if let Some(start) = self.black_since {
            // Black at the end: joins an interval that was black at the start.
            let end = self.white_since.unwrap_or(rotation);
            if self.started_black == Some(true) && self.count > 0 {
                let (_, first_end) = self.intervals[0];
                self.intervals[0] = (start.saturating_sub(self.full_turn), first_end);
            } else {
                self.push(start, end);
            }
        }
        if self.overflow || self.count == 0 || self.count > 4 {
            return Err(ScanError::ArmCount(
                self.count as u8 + u8::from(self.overflow),
            ));
        }
        let quarter = (self.full_turn / 4).max(1);
        let mut centres = [0i32; 4];
        for (c, (s, e)) in centres
            .iter_mut()
            .zip(self.intervals.iter())
            .take(self.count)
        {
            *c = s.saturating_add(e.saturating_sub(*s) / 2);
        }
        // Misalignment: the first arm's offset from its nearest quarter.
        let first = centres[0].rem_euclid(quarter.max(1));
        let misalignment = if first > quarter / 2 {
            first - quarter
        } else {
            first
        };
        let mut bits = 0u8;
        for c in centres.iter().take(self.count) {
            let a = c
                .saturating_sub(misalignment)
                .rem_euclid(self.full_turn.max(4));
            let q = (a + quarter / 2) / quarter.max(1);
            let off = a - q * quarter;
            if off.abs() > self.tolerance {
                return Err(ScanError::Misaligned);
            }
            bits |= 1 << (q & 3);
        }
        Ok(ScanResult {
            arms: Arms::from_bits(bits),
            misalignment,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TURN: i32 = 1292;

    fn sweep(arms: u8, offset: i32, width: i32) -> Result<ScanResult, ScanError> {
        let mut s = Scan::new(TURN, 60);
        let mut r = 0;
        while r < TURN {
            let black = (0..4).any(|q| {
                arms & (1 << q) != 0 && {
                    let d = (r - (q * TURN / 4 + offset)).rem_euclid(TURN);
                    d <= width / 2 || d >= TURN - width / 2
                }
            });
            s.update(black, r);
            r += 5;
        }
        s.finish(r)
    }

    #[test]
    fn every_shape_in_every_alignment() {
        for bits in 1..16u8 {
            for offset in [-40, -10, 0, 17, 45] {
                let got = sweep(bits, offset, 70).unwrap();
                assert_eq!(got.arms, Arms::from_bits(bits), "{bits:04b} at {offset}");
                assert!(
                    (got.misalignment - offset).abs() <= 5,
                    "{got:?} vs {offset}"
                );
            }
        }
    }

    #[test]
    fn no_arm_is_an_error() {
        assert_eq!(sweep(0, 0, 70), Err(ScanError::ArmCount(0)));
        assert_eq!(ScanError::ArmCount(0).code(), 0x30);
    }
}
