//! Node detection and arm classification while driving along a line.
//!
//! The seed's rule: a node begins when the left or the right floor sensor
//! reads clearly black (below 50 % of white) for more than 3 motor steps —
//! the outer sensors sit beside the line, so only a crossing line puts them
//! on black. From then on the robot drives straight (line following off, so
//! a single side arm does not pull it into a stray curve) and notes:
//!
//! - **left / right**: which outer sensor saw the crossing line;
//! - the crossing line's centre: midway between the first and the last
//!   black reading of the outer sensors;
//! - **ahead**: whether any sensor sees black again after the crossing line
//!   (the line continues).
//!
//! The robot stops when its axle is over the node's centre, i.e. the
//! sensors' forward offset past the crossing line's centre, so that a turn
//! on the spot ends on the new line. **Behind** is always an arm: the robot
//! came along it.
//!
//! Two shapes have no crossing line. A dead end: all three sensors leave the
//! line; the node's centre lies a known distance behind that point. A
//! straight piece (ahead and behind only) is invisible to the floor sensors;
//! when the field's node spacing is known, the detector reports one after
//! that distance has been driven without a crossing.

use super::FloorImage;

/// An outer sensor below this (a quarter of its spot on black) may be
/// entering a crossing line.
pub const GREY_BELOW: u16 = 640;
use crate::geometry::Arms;

/// Relative arm bits (bit 0 ahead, 1 right, 2 behind, 3 left).
const AHEAD: u8 = 0b0001;
const RIGHT: u8 = 0b0010;
const BEHIND: u8 = 0b0100;
const LEFT: u8 = 0b1000;

/// Geometry of robot and field, in motor steps of travel.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct NodeConfig {
    /// A sensor must read black for more than this many steps (the seed: 3).
    pub debounce_steps: i32,
    /// Distance from the wheel axle forward to the floor sensors.
    pub sensor_offset_steps: i32,
    /// From the point where the centre sensor leaves a line's end back to
    /// the node centre: half the line width less a quarter of the sensor
    /// spot.
    pub line_end_to_centre_steps: i32,
    /// The outer sensors see the crossing line for at most this long (line
    /// width + spot + 2 mm); black after it belongs to the line ahead, which
    /// a robot arriving at an angle may catch with an outer sensor.
    pub max_crossing_steps: i32,
    /// How long an outer sensor turning grey holds the heading while it is
    /// unclear whether a crossing line comes in (a quarter spot's width
    /// more than the spot takes to go from grey to black).
    pub suspect_steps: i32,
    /// After the outer sensors leave the crossing line, the centre one may
    /// still be on it for up to 10 mm · sin 10° at a 10° approach: black
    /// counts as the line ahead only this far past the last outer black.
    pub clearance_steps: i32,
    /// Node spacing for straight pieces; 0 when unknown (then straight
    /// pieces are driven through unreported).
    pub node_spacing_steps: i32,
}

impl NodeConfig {
    /// The e-puck with sensors 30 mm ahead of the axle on a field with
    /// 12 mm lines (one step ≈ 0.129 mm).
    pub const EPUCK: NodeConfig = NodeConfig {
        debounce_steps: 3,
        sensor_offset_steps: 233,
        line_end_to_centre_steps: 35,
        max_crossing_steps: 170,
        suspect_steps: 40,
        clearance_steps: 24,
        node_spacing_steps: 0,
    };
}

/// What the detector wants from the robot this interval.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum NodeStep {
    /// No node: keep following the line.
    Follow,
    /// Crossing a node: drive straight, line following off.
    Cross,
    /// The axle is over the node's centre; its arms relative to the robot.
    Arrived(Arms),
}

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Phase {
    Following,
    Crossing {
        first_black: i32,
        last_black: i32,
        sides: u8,
        cleared: bool,
        ahead: bool,
    },
    Ending {
        stop_at: i32,
        arms: u8,
    },
}

/// Tracks when one sensor turned black, to apply the step debounce.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
struct Debounce {
    since: Option<i32>,
}

impl Debounce {
    /// Feeds one reading; returns the position where a confirmed black run
    /// began.
    fn feed(&mut self, black: bool, at: i32, steps: i32) -> Option<i32> {
        if !black {
            self.since = None;
            return None;
        }
        let since = *self.since.get_or_insert(at);
        (at.saturating_sub(since) > steps).then_some(since)
    }
}

/// The node detector: feed it every control interval while moving.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct NodeDetector {
    config: NodeConfig,
    phase: Phase,
    sensors: [Debounce; 3],
    white: Debounce,
    suspect: Option<i32>,
}

impl NodeDetector {
    /// A detector at the start of an edge (the robot just left a node).
    pub const fn new(config: NodeConfig) -> NodeDetector {
        NodeDetector {
            config,
            phase: Phase::Following,
            sensors: [Debounce { since: None }; 3],
            white: Debounce { since: None },
            suspect: None,
        }
    }

    /// The configuration in use.
    pub const fn config(&self) -> NodeConfig {
        self.config
    }

    /// Starts over on a new edge.
    pub fn reset(&mut self) {
        *self = NodeDetector::new(self.config);
    }

    /// Whether a crossing is under way (line following must stay off).
    pub fn crossing(&self) -> bool {
        !matches!(self.phase, Phase::Following)
    }

    /// One interval: the floor image and the distance `travelled` (steps)
    /// since the robot left the last node.
    pub fn update(&mut self, floor: FloorImage, travelled: i32) -> NodeStep {
        let c = self.config;
        let black = floor.black_mask();
        let mut confirmed = [None; 3];
        for (i, (d, slot)) in self
            .sensors
            .iter_mut()
            .zip(confirmed.iter_mut())
            .enumerate()
        {
            *slot = d.feed(black & (1 << i) != 0, travelled, c.debounce_steps);
        }
        let [left, centre, right] = confirmed;
        let all_white = self.white.feed(black == 0, travelled, c.debounce_steps);
        match &mut self.phase {
            Phase::Following => {
                let side = match (left, right) {
                    (Some(l), Some(r)) => Some(l.min(r)),
                    (l, r) => l.or(r),
                };
                if let Some(first) = side {
                    let sides =
                        (u8::from(left.is_some()) * LEFT) | (u8::from(right.is_some()) * RIGHT);
                    self.phase = Phase::Crossing {
                        first_black: first,
                        last_black: travelled,
                        sides,
                        cleared: false,
                        ahead: false,
                    };
                    return NodeStep::Cross;
                }
                if let Some(end) = all_white {
                    // The line ended: a dead end.
                    let stop_at = end
                        .saturating_add(c.sensor_offset_steps)
                        .saturating_sub(c.line_end_to_centre_steps);
                    self.phase = Phase::Ending {
                        stop_at,
                        arms: BEHIND,
                    };
                    return self.update_ending(travelled);
                }
                if c.node_spacing_steps > 0 && travelled >= c.node_spacing_steps {
                    return self.arrive(AHEAD | BEHIND);
                }
                // An outer sensor turning grey may be a crossing line
                // coming in: then the left−right error measures that line,
                // not the robot's offset, and would kick the robot off its
                // course. Hold the heading for a short distance; a crossing
                // turns the sensor black within it, a slow drift does not
                // (and the PID takes over again).
                let grey = floor.left < GREY_BELOW || floor.right < GREY_BELOW;
                match (grey, self.suspect) {
                    (false, _) => self.suspect = None,
                    (true, None) => self.suspect = Some(travelled),
                    (true, Some(_)) => {}
                }
                match self.suspect {
                    Some(since) if travelled.saturating_sub(since) <= c.suspect_steps => {
                        NodeStep::Cross
                    }
                    _ => NodeStep::Follow,
                }
            }
            Phase::Crossing {
                first_black,
                last_black,
                sides,
                cleared,
                ahead,
            } => {
                let begun = travelled.saturating_sub(*first_black);
                if !*cleared {
                    let outer = black & 0b101 != 0;
                    // Both sides of a crossing line turn black within a few
                    // steps of each other, even at an angle; a side that
                    // turns black later has caught the line ahead.
                    let paired = |since: Option<i32>| {
                        since.is_some_and(|s| s.saturating_sub(*first_black) <= c.suspect_steps)
                    };
                    if paired(left) {
                        *sides |= LEFT;
                    }
                    if paired(right) {
                        *sides |= RIGHT;
                    }
                    if outer {
                        *last_black = travelled;
                    }
                    let past =
                        travelled.saturating_sub(*last_black) > c.debounce_steps.saturating_mul(2);
                    if past || begun > c.max_crossing_steps {
                        *cleared = true;
                    }
                } else if travelled.saturating_sub(*last_black) > c.clearance_steps
                    && left.or(centre).or(right).is_some()
                {
                    // The centre sensor may trail the last outer one off
                    // the crossing line when the robot arrives at an angle;
                    // past that, black is the line going on.
                    *ahead = true;
                }
                if *cleared {
                    let centre_at =
                        first_black.saturating_add(last_black.saturating_sub(*first_black) / 2);
                    let stop_at = centre_at.saturating_add(c.sensor_offset_steps);
                    if travelled >= stop_at {
                        let arms = *sides | BEHIND | if *ahead { AHEAD } else { 0 };
                        return self.arrive(arms);
                    }
                }
                NodeStep::Cross
            }
            Phase::Ending { .. } => self.update_ending(travelled),
        }
    }

    fn update_ending(&mut self, travelled: i32) -> NodeStep {
        match self.phase {
            Phase::Ending { stop_at, arms } if travelled >= stop_at => self.arrive(arms),
            _ => NodeStep::Cross,
        }
    }

    fn arrive(&mut self, arms: u8) -> NodeStep {
        self.reset();
        NodeStep::Arrived(Arms::from_bits(arms))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::{BACKGROUND_LEVEL as W, LINE_LEVEL as B};

    fn img(l: bool, c: bool, r: bool) -> FloorImage {
        let v = |b: bool| if b { B } else { W };
        FloorImage {
            left: v(l),
            centre: v(c),
            right: v(r),
        }
    }

    /// Drives the detector over a synthetic node at `node_at` steps (sensor
    /// position), 12 mm ≈ 93 steps of crossing line, 4 steps per interval.
    fn run(arms: u8, node_at: i32) -> (Arms, i32) {
        let mut d = NodeDetector::new(NodeConfig::EPUCK);
        let half = 46;
        let mut s = 0;
        while s < 4000 {
            let rel = s - node_at;
            let on_cross = rel.abs() <= half;
            let centre = if rel > half { arms & AHEAD != 0 } else { true };
            let f = img(
                on_cross && arms & LEFT != 0,
                centre || on_cross,
                on_cross && arms & RIGHT != 0,
            );
            if let NodeStep::Arrived(a) = d.update(f, s) {
                return (a, s);
            }
            s += 4;
        }
        panic!("never arrived");
    }

    #[test]
    fn classifies_every_shape_met_along_a_line() {
        for bits in 0..16u8 {
            let arms = bits | BEHIND;
            if arms == BEHIND | AHEAD {
                continue; // invisible without spacing
            }
            let (a, at) = run(arms, 500);
            assert_eq!(a, Arms::from_bits(arms), "shape {bits:04b}");
            if arms & (LEFT | RIGHT) != 0 {
                // Stops with the axle on the node: sensor offset past it.
                assert!((at - (500 + 233)).abs() <= 8, "stopped at {at}");
            } else {
                // Dead end: the line ends at 500 + 46.
                assert!((at - (546 + 233 - 35)).abs() <= 8, "stopped at {at}");
            }
        }
    }

    #[test]
    fn straight_pieces_need_the_spacing() {
        let mut d = NodeDetector::new(NodeConfig {
            node_spacing_steps: 776,
            ..NodeConfig::EPUCK
        });
        let mut got = None;
        for s in (0..1000).step_by(6) {
            if let NodeStep::Arrived(a) = d.update(img(false, true, false), s) {
                got = Some((a, s));
                break;
            }
        }
        assert_eq!(got, Some((Arms::from_bits(AHEAD | BEHIND), 780)));
    }

    #[test]
    fn a_short_blip_is_no_node() {
        let mut d = NodeDetector::new(NodeConfig::EPUCK);
        // Unconfirmed black holds the heading but starts no crossing.
        assert_eq!(d.update(img(true, true, false), 10), NodeStep::Cross);
        assert_eq!(d.update(img(true, true, false), 13), NodeStep::Cross);
        assert!(!d.crossing());
        assert_eq!(d.update(img(false, true, false), 16), NodeStep::Follow);
        assert!(!d.crossing());
        assert_eq!(d.update(img(true, true, false), 20), NodeStep::Cross);
        assert_eq!(d.update(img(true, true, false), 24), NodeStep::Cross);
        assert!(d.crossing());
    }
}
