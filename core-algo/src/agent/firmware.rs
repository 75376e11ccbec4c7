//! The firmware's glue around an [`Agent`]: what the phone's messages and
//! the body's reports mean to the agent, and what the agent's commands mean
//! to the body and the phone.
//!
//! Pure and allocation-free, so that the e-puck2 firmware (and its QEMU
//! build) and the host's simulated firmware run the very same glue: the
//! simulator proves what the robot runs. The caller owns the link and the
//! body; it feeds [`Glue`] the agent's inputs and carries out the
//! [`Effect`]s it collects.

use super::body::{Order, Report};
use super::{Agent, Command, Event, MAX_COMMANDS, ManualOrder, Millis, Mode, PeerNews};
use crate::explore::Strategy;
use crate::geometry::{Arms, Heading, Pos};
use crate::map::Block;
use crate::path::PlanCell;
use crate::protocol::message::{Broadcast, FailureKind, FirmwareVersion, RobotState, Status};
use crate::protocol::{Message, Pose};
use crate::team::RobotId;

/// What the rest of the robot must do for the agent.
#[derive(Clone, PartialEq, Eq, Debug)]
pub enum Effect {
    /// Hand this order to the body.
    Body(Order),
    /// Send this message to the phone reliably, in order.
    Send(Message),
    /// Send this message best-effort (a status answer).
    Datagram(Message),
}

/// The most effects one input can produce: the agent's commands, plus the
/// scan order at the start and the message that goes with a report.
pub const MAX_EFFECTS: usize = MAX_COMMANDS + 2;

/// The effects of one input, in the order to carry them out.
pub type Effects = heapless::Vec<Effect, MAX_EFFECTS>;

/// The firmware version every build of this code reports.
pub const FIRMWARE_VERSION: FirmwareVersion = FirmwareVersion {
    major: 0,
    minor: 2,
    patch: 0,
};

/// The glue's own state: the robot's id and whether it said it finished.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Glue {
    id: RobotId,
    finished: bool,
    dropped: u32,
}

impl Glue {
    /// The glue of robot `id`.
    pub const fn new(id: RobotId) -> Self {
        Glue {
            id,
            finished: false,
            dropped: 0,
        }
    }

    /// The robot's id.
    pub const fn id(&self) -> RobotId {
        self.id
    }

    /// The first message after a (re)start: who this robot is.
    pub const fn hello(&self) -> Message {
        Message::Hello {
            robot: self.id,
            firmware: FIRMWARE_VERSION,
        }
    }

    /// Effects lost to a full [`Effects`] list (never expected: the list
    /// holds the longest sequence one input can produce).
    pub const fn dropped(&self) -> u32 {
        self.dropped
    }

    /// A message from the phone.
    pub fn on_message<M, F, S, const K: usize>(
        &mut self,
        agent: &mut Agent<M, F, S, K>,
        now: Millis,
        message: &Message,
        out: &mut Effects,
    ) where
        M: AsRef<[Block]> + AsMut<[Block]>,
        F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
        S: Strategy<M, F>,
    {
        if *message == Message::RequestStatus {
            let s = self.status(agent, now);
            self.push(out, Effect::Datagram(s));
            return;
        }
        if let Message::SetSpeed { steps_per_s } = *message {
            // The motors' business, not the agent's.
            self.push(out, Effect::Body(Order::SetSpeed(steps_per_s)));
            return;
        }
        if let Some(event) = agent_event(message) {
            self.feed(agent, now, event, out);
        }
    }

    /// The body reports the end of an action.
    pub fn on_report<M, F, S, const K: usize>(
        &mut self,
        agent: &mut Agent<M, F, S, K>,
        now: Millis,
        report: Report,
        out: &mut Effects,
    ) where
        M: AsRef<[Block]> + AsMut<[Block]>,
        F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
        S: Strategy<M, F>,
    {
        let event = match report {
            Report::NodeHit { relative } => Event::NodeHit { relative },
            Report::Collision => {
                self.push(
                    out,
                    Effect::Send(Message::Collision {
                        proximity: 0b1000_0001,
                    }),
                );
                Event::Collision
            }
            Report::Bumped { side } => {
                // The proximity ring sees relative to the body; the agent
                // thinks in its frame.
                let (_, facing) = agent.pose();
                Event::Bumped {
                    toward: Heading::from_index(facing.index() + side.index()),
                }
            }
            Report::Abyss => {
                self.push(out, Effect::Send(Message::Abyss { floor: 0b111 }));
                Event::Rejected
            }
            Report::Refused => Event::Rejected,
        };
        self.feed(agent, now, event, out);
    }

    /// Time passes: the agent's timeouts and keep-alives.
    pub fn tick<M, F, S, const K: usize>(
        &mut self,
        agent: &mut Agent<M, F, S, K>,
        now: Millis,
        out: &mut Effects,
    ) where
        M: AsRef<[Block]> + AsMut<[Block]>,
        F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
        S: Strategy<M, F>,
    {
        self.feed(agent, now, Event::Tick, out);
    }

    /// The robot's status as the phone sees it.
    pub fn status<M, F, S, const K: usize>(&self, agent: &Agent<M, F, S, K>, now: Millis) -> Message
    where
        M: AsRef<[Block]> + AsMut<[Block]>,
        F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
        S: Strategy<M, F>,
    {
        let (pos, heading) = agent.pose();
        Message::Status(Status {
            uptime_ms: now,
            pose: Pose { pos, heading },
            state: if self.finished || agent.mode() == Mode::Finished {
                RobotState::Finished
            } else {
                RobotState::Stopped
            },
            floor: 0,
            proximity: 0,
        })
    }

    fn feed<M, F, S, const K: usize>(
        &mut self,
        agent: &mut Agent<M, F, S, K>,
        now: Millis,
        event: Event,
        out: &mut Effects,
    ) where
        M: AsRef<[Block]> + AsMut<[Block]>,
        F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
        S: Strategy<M, F>,
    {
        let Ok(commands) = agent.handle(now, event) else {
            return;
        };
        if matches!(event, Event::Start { .. } | Event::StartLocalize { .. }) {
            // The initial scan classifies the start node (seed §2.5).
            self.push(out, Effect::Body(Order::Scan));
        }
        for c in commands {
            let effect = match c {
                Command::Turn(t) => Effect::Body(Order::Turn(t)),
                Command::Move => Effect::Body(Order::Move),
                Command::Report { pos, arms, heading } => {
                    Effect::Send(node_hit(pos, heading, arms))
                }
                Command::Announce { target } => Effect::Send(Message::Intent { target }),
                Command::Localize(news) => Effect::Send(Message::Relayed {
                    origin: self.id,
                    broadcast: Broadcast::Localize(news),
                }),
                Command::Finished => {
                    self.finished = true;
                    Effect::Send(self.status(agent, now))
                }
                Command::Stop => Effect::Send(Message::Relayed {
                    origin: self.id,
                    broadcast: Broadcast::Failure {
                        kind: FailureKind::NodeObstruction,
                    },
                }),
            };
            self.push(out, effect);
        }
    }

    fn push(&mut self, out: &mut Effects, e: Effect) {
        if out.push(e).is_err() {
            self.dropped = self.dropped.saturating_add(1);
        }
    }
}

/// What a phone → robot message means to the robot's agent, if anything:
/// shared by every body that carries an agent (the firmware, the simulated
/// firmware, the phone-side brain of a 2010 robot).
pub fn agent_event(message: &Message) -> Option<Event> {
    Some(match *message {
        Message::Start { pose, .. } => Event::Start {
            pos: pose.pos,
            heading: pose.heading,
        },
        Message::Relayed {
            origin,
            ref broadcast,
        } => match *broadcast {
            Broadcast::NodeHit { pose, arms } => Event::Peer(
                origin,
                PeerNews::NodeHit {
                    pos: pose.pos,
                    heading: pose.heading,
                    arms,
                },
            ),
            Broadcast::Intent { target } => Event::Peer(origin, PeerNews::Intent { target }),
            Broadcast::Failure { .. } => Event::Peer(origin, PeerNews::Failed),
            Broadcast::Localize(news) => Event::Peer(origin, PeerNews::Localize(news)),
        },
        Message::StartLocalize { method, settings } => Event::StartLocalize {
            method,
            team: settings.team_size,
        },
        Message::Manual { on } => Event::Manual(if on {
            ManualOrder::Take
        } else {
            ManualOrder::Release
        }),
        Message::Turn(t) => Event::Manual(ManualOrder::Turn(t)),
        Message::Move => Event::Manual(ManualOrder::Move),
        _ => return None,
    })
}

/// A node-hit message.
pub fn node_hit(pos: Pos, heading: Heading, arms: Arms) -> Message {
    Message::NodeHit {
        pose: Pose { pos, heading },
        arms,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::agent::AgentConfig;
    use crate::explore::NearestFrontier;
    use crate::map::{Bounds, KnownMap, blocks_for};
    use crate::path::{DistField, min_cells};
    use crate::protocol::message::{StrategyKind, StrategySettings};
    use std::vec;
    use std::vec::Vec;

    type TestAgent = Agent<Vec<Block>, Vec<PlanCell>, NearestFrontier, 1>;

    fn agent(id: u8) -> TestAgent {
        let bounds = Bounds::new(Pos::new(-1, -1), 4, 4);
        let map = KnownMap::new(vec![Block::EMPTY; blocks_for(bounds.area())], bounds);
        assert!(map.is_ok());
        let Ok(map) = map else { unreachable!() };
        let field = DistField::new(vec![PlanCell::EMPTY; min_cells(bounds.area())]);
        Agent::new(
            RobotId(id),
            map,
            [field],
            NearestFrontier,
            AgentConfig::default(),
        )
    }

    fn start() -> Message {
        Message::Start {
            pose: Pose {
                pos: Pos::new(0, 0),
                heading: Heading::North,
            },
            settings: StrategySettings {
                kind: StrategyKind::Coordinated,
                team_size: 1,
                speed: 600,
            },
        }
    }

    #[test]
    fn start_scans_then_the_start_node_is_reported_and_explored() {
        let mut a = agent(0);
        let mut g = Glue::new(RobotId(0));
        let mut out = Effects::new();
        g.on_message(&mut a, 0, &start(), &mut out);
        assert_eq!(out.as_slice(), [Effect::Body(Order::Scan)]);
        out.clear();
        // The start node has an arm ahead (north) and one to the right.
        g.on_report(
            &mut a,
            10,
            Report::NodeHit {
                relative: Arms::from_bits(0b0011),
            },
            &mut out,
        );
        assert!(out.contains(&Effect::Send(node_hit(
            Pos::new(0, 0),
            Heading::North,
            Arms::from_bits(0b0011)
        ))));
        assert!(out.iter().any(|e| matches!(e, Effect::Body(Order::Move))));
    }

    #[test]
    fn status_requests_are_answered_best_effort() {
        let mut a = agent(2);
        let mut g = Glue::new(RobotId(2));
        let mut out = Effects::new();
        g.on_message(&mut a, 77, &Message::RequestStatus, &mut out);
        assert!(matches!(
            out.as_slice(),
            [Effect::Datagram(Message::Status(Status {
                uptime_ms: 77,
                ..
            }))]
        ));
        assert_eq!(
            g.hello(),
            Message::Hello {
                robot: RobotId(2),
                firmware: FIRMWARE_VERSION
            }
        );
    }

    #[test]
    fn reports_out_of_turn_are_ignored_but_collisions_are_told() {
        let mut a = agent(0);
        let mut g = Glue::new(RobotId(0));
        let mut out = Effects::new();
        g.on_report(&mut a, 0, Report::Collision, &mut out);
        // Not driving: the agent ignores it, the phone still hears it.
        assert_eq!(
            out.as_slice(),
            [Effect::Send(Message::Collision {
                proximity: 0b1000_0001
            })]
        );
        assert_eq!(a.ignored(), 1);
        out.clear();
        g.on_message(&mut a, 0, &Message::Reset, &mut out);
        assert!(out.is_empty());
        assert_eq!(g.dropped(), 0);
    }

    /// The firmware's QEMU scenario: a lone MinPos robot in a two-node dead
    /// end turns round and drives home.
    #[test]
    fn a_lone_firmware_robot_comes_home_from_a_dead_end() {
        let bounds = Bounds::new(Pos::new(-16, -16), 32, 32);
        let map = KnownMap::new(vec![Block::EMPTY; blocks_for(bounds.area())], bounds);
        let Ok(map) = map else { unreachable!() };
        let field = DistField::new(vec![PlanCell::EMPTY; min_cells(bounds.area())]);
        let mut a: Agent<_, _, crate::explore::MinPos, 1> = Agent::new(
            RobotId(0),
            map,
            [field],
            crate::explore::MinPos,
            AgentConfig::default(),
        );
        let mut g = Glue::new(RobotId(0));
        let mut out = Effects::new();
        let start = Message::Start {
            pose: Pose {
                pos: Pos::new(0, 0),
                heading: Heading::North,
            },
            settings: StrategySettings {
                kind: StrategyKind::Coordinated,
                team_size: 1,
                speed: 6000,
            },
        };
        g.on_message(&mut a, 100, &start, &mut out);
        out.clear();
        g.on_report(
            &mut a,
            300,
            Report::NodeHit {
                relative: Arms::from_bits(0b0001),
            },
            &mut out,
        );
        assert!(
            out.iter().any(|e| matches!(e, Effect::Body(Order::Move))),
            "{out:?}"
        );
        out.clear();
        g.tick(&mut a, 400, &mut out);
        out.clear();
        g.on_report(
            &mut a,
            600,
            Report::NodeHit {
                relative: Arms::from_bits(0b0100),
            },
            &mut out,
        );
        assert!(
            out.iter()
                .any(|e| matches!(e, Effect::Body(Order::Turn(crate::geometry::Turn::UTurn)))),
            "{out:?}"
        );
    }
}
