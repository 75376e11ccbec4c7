//! The agent's body: the orders it carries out and the reports it sends
//! back, the same whether the body is a real e-puck2 (the behaviour stack,
//! see [`BehaviourBody`]), a node-level simulation on the host, or a
//! simulated body attached to a firmware running in QEMU (over the text
//! channel of [`BodyMsg`]).

use crate::behaviour::{Command as Behave, Event as Sensed, Refused, Robot, Sensors};
use crate::control::Wheels;
use crate::geometry::{Arms, Heading, Turn};

/// An order to a body.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Order {
    /// Turn on the spot.
    Turn(Turn),
    /// Drive to the next node.
    Move,
    /// Turn once around on the spot and classify the node (the initial
    /// scan of the start node).
    Scan,
    /// Drive at this many motor steps per second from the next move on (a
    /// person's speed control); takes effect at once, never queued.
    SetSpeed(u16),
}

/// What a body's sensors report when an action ends.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Report {
    /// Arrived on a node with these arms relative to the body's heading.
    NodeHit {
        /// Bit 0 ahead, 1 right, 2 behind, 3 left.
        relative: Arms,
    },
    /// Met another body; back on the node it left, facing back.
    Collision,
    /// No line ahead; stayed.
    Abyss,
    /// Standing on a node, its proximity sensors saw another robot come
    /// close and turn back (the passive side of a collision).
    Bumped {
        /// Where the other robot came from, relative to the body like the
        /// proximity ring sees it: north ahead, east to the right. Only the
        /// robot's own agent knows how that lies in its frame (see
        /// `docs/localization.md`).
        side: Heading,
    },
    /// The body could not carry out the order (queue full, no calibration,
    /// a scan that found no valid node shape).
    Refused,
}

/// One line of the body channel between an emulated firmware and the
/// simulated body the host attaches to it (QEMU's second serial port).
///
/// Text, one letter (and maybe one argument) and `\n`, so that a person can
/// watch the channel with `socat` or a terminal and type orders by hand.
/// Robot → host: `H` (the body UART is ready), `N<hex>` node hit with
/// relative arms, `C` collision, `A` abyss, `X` refused, `B<NESW>` bumped.
/// Host → robot: `K` keep-alive (the emulated robot exits when the host
/// has been silent too long, so no QEMU outlives its host), `Q` quit,
/// and the orders `M` move, `S` scan, `T<RLU>` turn.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum BodyMsg {
    /// The firmware's body UART is ready.
    Hello,
    /// The host is alive.
    KeepAlive,
    /// End the emulation.
    Quit,
    /// An order for the body.
    Order(Order),
    /// A report from the body.
    Report(Report),
}

/// The longest encoded [`BodyMsg`], newline included.
pub const BODY_MSG_LEN: usize = 6;

const HEX: &[u8; 16] = b"0123456789ABCDEF";

fn turn_letter(t: Turn) -> u8 {
    match t {
        Turn::Right => b'R',
        Turn::Left => b'L',
        Turn::UTurn => b'U',
    }
}

fn heading_letter(h: Heading) -> u8 {
    match h {
        Heading::North => b'N',
        Heading::East => b'E',
        Heading::South => b'S',
        Heading::West => b'W',
    }
}

impl BodyMsg {
    /// The line for this message; the first `len` bytes of the array.
    pub fn encode(self) -> ([u8; BODY_MSG_LEN], usize) {
        let mut line = [0u8; BODY_MSG_LEN];
        let mut n = 0;
        let mut put = |b: u8| {
            if let Some(slot) = line.get_mut(n) {
                *slot = b;
                n += 1;
            }
        };
        match self {
            BodyMsg::Hello => put(b'H'),
            BodyMsg::KeepAlive => put(b'K'),
            BodyMsg::Quit => put(b'Q'),
            BodyMsg::Order(Order::Move) => put(b'M'),
            BodyMsg::Order(Order::Scan) => put(b'S'),
            BodyMsg::Order(Order::Turn(t)) => {
                put(b'T');
                put(turn_letter(t));
            }
            BodyMsg::Order(Order::SetSpeed(s)) => {
                // Four decimal digits: "V0600".
                put(b'V');
                let s = s.min(9999);
                for k in [1000, 100, 10, 1] {
                    put(b'0' + ((s / k) % 10) as u8);
                }
            }
            BodyMsg::Report(Report::NodeHit { relative }) => {
                put(b'N');
                if let Some(&h) = HEX.get(usize::from(relative.bits() & 0xF)) {
                    put(h);
                }
            }
            BodyMsg::Report(Report::Collision) => put(b'C'),
            BodyMsg::Report(Report::Abyss) => put(b'A'),
            BodyMsg::Report(Report::Refused) => put(b'X'),
            BodyMsg::Report(Report::Bumped { side }) => {
                put(b'B');
                put(heading_letter(side));
            }
        }
        put(b'\n');
        (line, n)
    }

    /// Parses one line without its newline; `None` for anything else.
    pub fn decode(line: &[u8]) -> Option<BodyMsg> {
        Some(match line {
            [b'H'] => BodyMsg::Hello,
            [b'K'] => BodyMsg::KeepAlive,
            [b'Q'] => BodyMsg::Quit,
            [b'M'] => BodyMsg::Order(Order::Move),
            [b'S'] => BodyMsg::Order(Order::Scan),
            [b'V', digits @ ..] if digits.len() == 4 => {
                let mut s = 0u16;
                for &d in digits {
                    if !d.is_ascii_digit() {
                        return None;
                    }
                    s = s * 10 + u16::from(d - b'0');
                }
                BodyMsg::Order(Order::SetSpeed(s))
            }
            [b'T', t] => BodyMsg::Order(Order::Turn(match t {
                b'R' => Turn::Right,
                b'L' => Turn::Left,
                b'U' => Turn::UTurn,
                _ => return None,
            })),
            [b'N', h] => {
                let bits = HEX.iter().position(|c| c == h)?;
                BodyMsg::Report(Report::NodeHit {
                    relative: Arms::from_bits(u8::try_from(bits).ok()?),
                })
            }
            [b'C'] => BodyMsg::Report(Report::Collision),
            [b'A'] => BodyMsg::Report(Report::Abyss),
            [b'X'] => BodyMsg::Report(Report::Refused),
            [b'B', h] => BodyMsg::Report(Report::Bumped {
                side: Heading::ALL
                    .into_iter()
                    .find(|x| heading_letter(*x) == *h)?,
            }),
            _ => return None,
        })
    }
}

/// Cuts the body channel's byte stream into [`BodyMsg`]s. Anything that is
/// not a valid line (garbage, bytes lost) is counted and dropped; the next
/// newline starts afresh.
#[derive(Clone, Copy, Debug, Default)]
pub struct BodyDecoder {
    buf: [u8; BODY_MSG_LEN],
    len: usize,
    overflow: bool,
    errors: u32,
}

impl BodyDecoder {
    /// An empty decoder.
    pub const fn new() -> Self {
        BodyDecoder {
            buf: [0; BODY_MSG_LEN],
            len: 0,
            overflow: false,
            errors: 0,
        }
    }

    /// Takes one byte; returns a message when it ends a valid line.
    pub fn push(&mut self, byte: u8) -> Option<BodyMsg> {
        if byte == b'\r' {
            return None;
        }
        if byte != b'\n' {
            match self.buf.get_mut(self.len) {
                Some(slot) if !self.overflow => {
                    *slot = byte;
                    self.len += 1;
                }
                _ => self.overflow = true,
            }
            return None;
        }
        let len = core::mem::take(&mut self.len);
        let overflow = core::mem::take(&mut self.overflow);
        if len == 0 && !overflow {
            return None;
        }
        let msg = if overflow {
            None
        } else {
            self.buf.get(..len).and_then(BodyMsg::decode)
        };
        if msg.is_none() {
            self.errors = self.errors.saturating_add(1);
        }
        msg
    }

    /// Lines dropped as invalid so far.
    pub fn errors(&self) -> u32 {
        self.errors
    }
}

/// A real body: the behaviour stack ([`Robot`]) carrying out the agent's
/// orders and turning its events into [`Report`]s.
///
/// The agent expects a collision to end with the robot back on the node it
/// left, facing back (what the simulator's bodies do). The behaviour's
/// collision layer only stops the robot, so this adapter then orders a
/// U-turn and a move itself (the recovery the collision layer's docs
/// describe) and reports [`Report::Collision`] when the node layer reports
/// the node it came back to.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct BehaviourBody {
    robot: Robot,
    returning: bool,
    refused: bool,
}

impl BehaviourBody {
    /// Wraps a behaviour stack.
    pub fn new(robot: Robot) -> Self {
        BehaviourBody {
            robot,
            returning: false,
            refused: false,
        }
    }

    /// The behaviour stack (read only, for displays and tests).
    pub fn robot(&self) -> &Robot {
        &self.robot
    }

    /// The behaviour stack, to set its speed or gains.
    pub fn robot_mut(&mut self) -> &mut Robot {
        &mut self.robot
    }

    /// Takes an order from the agent. A refused order is also reported as
    /// [`Report::Refused`] at the next step, so the agent hears of it.
    pub fn order(&mut self, order: Order) -> Result<(), Refused> {
        let command = match order {
            Order::Turn(t) => Behave::Turn(t),
            Order::Move => Behave::Move,
            Order::Scan => Behave::Scan,
            Order::SetSpeed(s) => Behave::SetSpeed(s.min(1000) as i16),
        };
        let r = self.robot.order(command);
        if r.is_err() {
            self.refused = true;
        }
        r
    }

    /// One 100 Hz control step: wheel speeds, and a report when an action
    /// ended.
    pub fn step(&mut self, sensors: &Sensors) -> (Wheels, Option<Report>) {
        let out = self.robot.step(sensors);
        if core::mem::take(&mut self.refused) {
            return (out.wheels, Some(Report::Refused));
        }
        let report = match out.event {
            Some(Sensed::StartNode { arms }) => Some(Report::NodeHit { relative: arms }),
            Some(Sensed::NodeHit { arms }) => Some(if core::mem::take(&mut self.returning) {
                Report::Collision
            } else {
                Report::NodeHit { relative: arms }
            }),
            Some(Sensed::Collision { .. }) if !self.returning => {
                self.returning = true;
                let back = self
                    .robot
                    .order(Behave::Turn(Turn::UTurn))
                    .and_then(|()| self.robot.order(Behave::Move));
                match back {
                    Ok(()) => None,
                    Err(_) => {
                        self.returning = false;
                        Some(Report::Refused)
                    }
                }
            }
            // Blocked on the way back as well: give up, the agent waits and
            // decides again.
            Some(Sensed::Collision { .. }) => {
                self.returning = false;
                Some(Report::Refused)
            }
            Some(Sensed::Abyss { .. }) => {
                self.returning = false;
                Some(Report::Abyss)
            }
            Some(Sensed::ScanFailed(_)) => Some(Report::Refused),
            _ => None,
        };
        (out.wheels, report)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::behaviour::{Config, Mode};
    use crate::control::StepCount;
    use crate::control::calibration::Calibration;

    fn all_messages() -> [BodyMsg; 17] {
        [
            BodyMsg::Order(Order::SetSpeed(600)),
            BodyMsg::Order(Order::SetSpeed(9999)),
            BodyMsg::Hello,
            BodyMsg::KeepAlive,
            BodyMsg::Quit,
            BodyMsg::Order(Order::Move),
            BodyMsg::Order(Order::Scan),
            BodyMsg::Order(Order::Turn(Turn::Right)),
            BodyMsg::Order(Order::Turn(Turn::Left)),
            BodyMsg::Order(Order::Turn(Turn::UTurn)),
            BodyMsg::Report(Report::NodeHit {
                relative: Arms::from_bits(0b1011),
            }),
            BodyMsg::Report(Report::NodeHit {
                relative: Arms::from_bits(0),
            }),
            BodyMsg::Report(Report::Collision),
            BodyMsg::Report(Report::Abyss),
            BodyMsg::Report(Report::Refused),
            BodyMsg::Report(Report::Bumped {
                side: Heading::West,
            }),
            BodyMsg::Report(Report::Bumped {
                side: Heading::North,
            }),
        ]
    }

    #[test]
    fn every_message_survives_the_channel() {
        let mut d = BodyDecoder::new();
        for m in all_messages() {
            let (buf, n) = m.encode();
            let mut got = None;
            for &b in &buf[..n] {
                got = d.push(b).or(got);
            }
            assert_eq!(got, Some(m));
        }
        assert_eq!(d.errors(), 0);
    }

    #[test]
    fn garbage_is_counted_and_the_decoder_recovers() {
        let mut d = BodyDecoder::new();
        let mut got = std::vec::Vec::new();
        for &b in b"ZZ\nTQ\nN\nMMMMMMMM\n\n\r\nC\r\nTU\n" {
            if let Some(m) = d.push(b) {
                got.push(m);
            }
        }
        assert_eq!(
            got,
            [
                BodyMsg::Report(Report::Collision),
                BodyMsg::Order(Order::Turn(Turn::UTurn))
            ]
        );
        assert_eq!(d.errors(), 4);
    }

    fn calibrated_robot() -> BehaviourBody {
        let cal = Calibration::new([300; 3], [900; 3]).ok();
        assert!(cal.is_some());
        BehaviourBody::new(Robot::new(Config::EPUCK, cal))
    }

    #[test]
    fn a_collision_turns_back_and_is_reported_on_the_node_it_left() {
        let mut body = calibrated_robot();
        body.robot_mut().place_on_node(StepCount::default());
        assert_eq!(body.order(Order::Move), Ok(()));
        let clear = Sensors {
            floor: [900, 300, 900],
            ..Sensors::default()
        };
        // The movement layer starts the move.
        let (_, r) = body.step(&clear);
        assert_eq!(r, None);
        assert_eq!(body.robot().mode(), Mode::Moving);
        // Something close ahead: the collision layer stops the robot; the
        // adapter turns it back instead of reporting at once.
        let blocked = Sensors {
            proximity: [4000, 0, 0, 0, 0, 0, 0, 4000],
            ..clear
        };
        let (w, r) = body.step(&blocked);
        assert_eq!((w, r), (Wheels::STOP, None));
        assert_eq!(body.robot().mode(), Mode::Blocked);
        let (_, r) = body.step(&clear);
        assert_eq!(r, None);
        assert!(matches!(body.robot().mode(), Mode::Turning(Turn::UTurn)));
    }

    #[test]
    fn refused_orders_are_reported() {
        let mut body = BehaviourBody::new(Robot::new(Config::EPUCK, None));
        assert!(body.order(Order::Move).is_err());
        let (w, r) = body.step(&Sensors::default());
        assert_eq!((w, r), (Wheels::STOP, Some(Report::Refused)));
        let (_, r) = body.step(&Sensors::default());
        assert_eq!(r, None);
    }
}
