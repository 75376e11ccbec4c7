//! A simulated robot's firmware: the core-algo [`Agent`] behind the real
//! reliable [`Link`], with the body's sensors as its input. This is what
//! runs on an e-puck2, minus the line following (the body model drives
//! edges whole).

use super::body::{Order, Report};
use crate::proxy::LinkEnd;
use core_algo::agent::{Agent, AgentConfig, Command, Event as AgentEvent, ManualOrder, PeerNews};
use core_algo::explore::{Context, Decision, MAX_ROBOTS, Strategy};
use core_algo::geometry::{Arms, Heading, Pos};
use core_algo::map::{Block, Bounds, KnownMap, blocks_for};
use core_algo::path::{DistField, PlanCell, PlanError, min_cells};
use core_algo::protocol::link::Event as LinkEvent;
use core_algo::protocol::message::{Broadcast, FailureKind, FirmwareVersion, RobotState, Status};
use core_algo::protocol::{LinkConfig, Message, Pose};
use core_algo::team::RobotId;

/// A strategy chosen at run time, as the simulator and the phone side hold
/// them.
pub struct BoxedStrategy(pub Box<dyn Strategy<Vec<Block>, Vec<PlanCell>> + Send>);

impl Strategy<Vec<Block>, Vec<PlanCell>> for BoxedStrategy {
    fn name(&self) -> &'static str {
        self.0.name()
    }

    fn decide(
        &mut self,
        ctx: &Context<'_, Vec<Block>>,
        fields: &mut [DistField<Vec<PlanCell>>],
    ) -> Result<Decision, PlanError> {
        self.0.decide(ctx, fields)
    }
}

/// Planner fields of a host-side agent: one per robot of a team of up to
/// [`MAX_ROBOTS`], so that centralised strategies plan for everyone.
pub const HOST_FIELDS: usize = MAX_ROBOTS;

/// The agent type every host-side robot runs.
pub type HostAgent = Agent<Vec<Block>, Vec<PlanCell>, BoxedStrategy, HOST_FIELDS>;

/// An agent for robot `id` whose map covers `bounds`.
pub fn host_agent(
    id: RobotId,
    bounds: Bounds,
    strategy: BoxedStrategy,
    config: AgentConfig,
) -> HostAgent {
    let map = KnownMap::new(vec![Block::EMPTY; blocks_for(bounds.area())], bounds)
        .unwrap_or_else(|e| unreachable!("storage sized for the bounds: {e}"));
    let fields =
        core::array::from_fn(|_| DistField::new(vec![PlanCell::EMPTY; min_cells(bounds.area())]));
    Agent::new(id, map, fields, strategy, config)
}

/// The firmware version simulated robots report.
pub const SIM_FIRMWARE: FirmwareVersion = FirmwareVersion {
    major: 0,
    minor: 1,
    patch: 0,
};

/// Counters of one simulated robot.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FirmwareStats {
    /// Agent events refused as unexpected.
    pub ignored_events: u32,
    /// Reports the reliable queue could not take at once (sent later).
    pub deferred: u32,
}

/// The firmware of one simulated robot.
pub struct SimFirmware {
    id: RobotId,
    agent: HostAgent,
    end: LinkEnd,
    finished: bool,
    dead: bool,
    stats: FirmwareStats,
    hello_sent: bool,
}

impl SimFirmware {
    /// Robot `id` with its agent.
    pub fn new(id: RobotId, agent: HostAgent, link_config: LinkConfig, nonce: u32) -> Self {
        SimFirmware {
            id,
            agent,
            end: LinkEnd::new(link_config, id, nonce),
            finished: false,
            dead: false,
            stats: FirmwareStats::default(),
            hello_sent: false,
        }
    }

    /// The robot's id.
    pub fn id(&self) -> RobotId {
        self.id
    }

    /// The agent (read only).
    pub fn agent(&self) -> &HostAgent {
        &self.agent
    }

    /// Whether the agent says the team is done (it may take it back when a
    /// team mate thought failed turns up again).
    pub fn finished(&self) -> bool {
        self.agent.mode() == core_algo::agent::Mode::Finished
    }

    /// The robot stops working (its processor died).
    pub fn kill(&mut self) {
        self.dead = true;
    }

    /// Whether it is dead.
    pub fn is_dead(&self) -> bool {
        self.dead
    }

    /// Counters.
    pub fn stats(&self) -> FirmwareStats {
        FirmwareStats {
            ignored_events: self.agent.ignored(),
            ..self.stats
        }
    }

    /// Bytes arrived from the phone.
    pub fn on_bytes(&mut self, now: u32, bytes: &[u8], orders: &mut Vec<Order>) {
        if self.dead {
            return;
        }
        self.end.link.on_bytes(now, bytes);
        self.drain_link(now, orders);
    }

    /// The body's sensors report the end of an action.
    pub fn on_report(&mut self, now: u32, report: Report, orders: &mut Vec<Order>) {
        if self.dead {
            return;
        }
        let event = match report {
            Report::NodeHit { relative } => AgentEvent::NodeHit { relative },
            Report::Collision => {
                self.queue(Message::Collision {
                    proximity: 0b1000_0001,
                });
                AgentEvent::Collision
            }
            Report::Bumped { side } => {
                // The proximity ring sees relative to the body; the agent
                // thinks in its frame.
                let (_, facing) = self.agent.pose();
                AgentEvent::Bumped {
                    toward: Heading::from_index(facing.index() + side.index()),
                }
            }
            Report::Abyss => {
                self.queue(Message::Abyss { floor: 0b111 });
                AgentEvent::Rejected
            }
        };
        self.feed(now, event, orders);
    }

    /// Periodic work: link timers and the agent's timeouts.
    pub fn tick(&mut self, now: u32, orders: &mut Vec<Order>) {
        if self.dead {
            return;
        }
        if !self.hello_sent {
            // Announce readiness first, as the real firmware does.
            self.hello_sent = true;
            self.queue(Message::Hello {
                robot: self.id,
                firmware: SIM_FIRMWARE,
            });
        }
        self.end.link.tick(now);
        self.drain_link(now, orders);
        self.feed(now, AgentEvent::Tick, orders);
    }

    /// The next bytes to send to the phone, if any.
    pub fn poll_transmit(&mut self, now: u32, buf: &mut [u8]) -> Option<usize> {
        if self.dead {
            return None;
        }
        self.end.flush();
        self.end.link.poll_transmit(now, buf)
    }

    fn status(&self, now: u32) -> Message {
        let (pos, heading) = self.agent.pose();
        Message::Status(Status {
            uptime_ms: now,
            pose: Pose { pos, heading },
            state: if self.finished {
                RobotState::Finished
            } else {
                RobotState::Stopped
            },
            floor: 0,
            proximity: 0,
        })
    }

    fn drain_link(&mut self, now: u32, orders: &mut Vec<Order>) {
        while let Some(ev) = self.end.link.poll_event() {
            let LinkEvent::Received { message, .. } = ev else {
                continue;
            };
            if message == Message::RequestStatus {
                let s = self.status(now);
                self.end.link.send_datagram(s);
                continue;
            }
            let Some(event) = agent_event(&message) else {
                continue;
            };
            self.feed(now, event, orders);
        }
    }

    fn feed(&mut self, now: u32, event: AgentEvent, orders: &mut Vec<Order>) {
        let Ok(commands) = self.agent.handle(now, event) else {
            return;
        };
        if matches!(
            event,
            AgentEvent::Start { .. } | AgentEvent::StartLocalize { .. }
        ) {
            // The initial scan classifies the start node (seed §2.5).
            orders.push(Order::Scan);
        }
        for c in commands {
            match c {
                Command::Turn(t) => orders.push(Order::Turn(t)),
                Command::Move => orders.push(Order::Move),
                Command::Report { pos, arms, heading } => self.queue(node_hit(pos, heading, arms)),
                Command::Announce { target } => self.queue(Message::Intent { target }),
                Command::Localize(news) => self.queue(Message::Relayed {
                    origin: self.id,
                    broadcast: Broadcast::Localize(news),
                }),
                Command::Finished => {
                    self.finished = true;
                    let s = self.status(now);
                    self.queue(s);
                }
                Command::Stop => {
                    self.queue(Message::Relayed {
                        origin: self.id,
                        broadcast: Broadcast::Failure {
                            kind: FailureKind::NodeObstruction,
                        },
                    });
                }
            }
        }
    }

    fn queue(&mut self, m: Message) {
        self.end.send(m);
        if self.end.queued() > 0 {
            self.stats.deferred += 1;
        }
    }
}

/// What a phone → robot message means to the robot's agent, if anything:
/// shared by every body that carries an agent (the simulated firmware, the
/// phone-side brain of a 2010 robot).
pub fn agent_event(message: &Message) -> Option<AgentEvent> {
    Some(match *message {
        Message::Start { pose, .. } => AgentEvent::Start {
            pos: pose.pos,
            heading: pose.heading,
        },
        Message::Relayed {
            origin,
            ref broadcast,
        } => match *broadcast {
            Broadcast::NodeHit { pose, arms } => AgentEvent::Peer(
                origin,
                PeerNews::NodeHit {
                    pos: pose.pos,
                    heading: pose.heading,
                    arms,
                },
            ),
            Broadcast::Intent { target } => AgentEvent::Peer(origin, PeerNews::Intent { target }),
            Broadcast::Failure { .. } => AgentEvent::Peer(origin, PeerNews::Failed),
            Broadcast::Localize(news) => AgentEvent::Peer(origin, PeerNews::Localize(news)),
        },
        Message::StartLocalize { method, settings } => AgentEvent::StartLocalize {
            method,
            team: settings.team_size,
        },
        Message::Manual { on } => AgentEvent::Manual(if on {
            ManualOrder::Take
        } else {
            ManualOrder::Release
        }),
        Message::Turn(t) => AgentEvent::Manual(ManualOrder::Turn(t)),
        Message::Move => AgentEvent::Manual(ManualOrder::Move),
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
