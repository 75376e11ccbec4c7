//! A simulated robot's firmware: the core-algo [`Agent`] behind the real
//! reliable [`Link`](core_algo::protocol::link::Link), with the body's sensors as its input. This is what
//! runs on an e-puck2, minus the line following (the body model drives
//! edges whole).

use super::body::{Order, Report};
use crate::proxy::LinkEnd;
use core_algo::agent::firmware::{Effect, Effects, Glue};
use core_algo::agent::{Agent, AgentConfig};
use core_algo::explore::{Context, Decision, MAX_ROBOTS, Strategy};
use core_algo::map::{Block, Bounds, KnownMap, blocks_for};
use core_algo::path::{DistField, PlanCell, PlanError, min_cells};
use core_algo::protocol::link::Event as LinkEvent;
use core_algo::protocol::message::FirmwareVersion;
use core_algo::protocol::{LinkConfig, Message};
use core_algo::team::RobotId;

pub use core_algo::agent::firmware::{agent_event, node_hit};

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
/// [`MAX_ROBOTS`], so that centralised strategies plan for everyone, and
/// one more, so that the homecoming's kept ways of team mates never share
/// the field a strategy plans our own way in, and one for the homecoming's
/// waiting spots, so that searching them does not throw away the way home
/// a strategy keeps in the first field (see `agent::homecoming`), and one
/// for a retreat's search from home, kept from one retreat to the next
/// (see `agent::retreat`).
pub const HOST_FIELDS: usize = MAX_ROBOTS + 3;

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
        .with_shared_fields(&crate::shared_fields::HOST_FIELDS)
        .with_forest(vec![PlanCell::EMPTY; bounds.area()])
}

/// The firmware version simulated robots report: the same glue as the
/// real firmware, so the same version.
pub const SIM_FIRMWARE: FirmwareVersion = core_algo::agent::firmware::FIRMWARE_VERSION;

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
    glue: Glue,
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
            glue: Glue::new(id),
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
        let mut out = Effects::new();
        self.glue.on_report(&mut self.agent, now, report, &mut out);
        self.apply(out, orders);
    }

    /// Periodic work: link timers and the agent's timeouts.
    pub fn tick(&mut self, now: u32, orders: &mut Vec<Order>) {
        if self.dead {
            return;
        }
        if !self.hello_sent {
            // Announce readiness first, as the real firmware does.
            self.hello_sent = true;
            self.queue(self.glue.hello());
        }
        self.end.link.tick(now);
        self.drain_link(now, orders);
        let mut out = Effects::new();
        self.glue.tick(&mut self.agent, now, &mut out);
        self.apply(out, orders);
    }

    /// The next bytes to send to the phone, if any.
    pub fn poll_transmit(&mut self, now: u32, buf: &mut [u8]) -> Option<usize> {
        if self.dead {
            return None;
        }
        self.end.flush();
        self.end.link.poll_transmit(now, buf)
    }

    /// Whether [`SimFirmware::poll_transmit`] would send nothing at `now`
    /// (see [`Link::is_quiet`](core_algo::protocol::Link::is_quiet)).
    pub fn is_quiet(&self, now: u32) -> bool {
        self.quiet_for(now) > 0
    }

    /// For how long from `now` it stays quiet unless a frame arrives, a
    /// tick comes or its body reports (u32::MAX: dead, for good).
    pub fn quiet_for(&self, now: u32) -> u32 {
        if self.dead {
            u32::MAX
        } else {
            self.end.quiet_for(now)
        }
    }

    fn drain_link(&mut self, now: u32, orders: &mut Vec<Order>) {
        while let Some(ev) = self.end.link.poll_event() {
            let LinkEvent::Received { message, .. } = ev else {
                continue;
            };
            let mut out = Effects::new();
            self.glue
                .on_message(&mut self.agent, now, &message, &mut out);
            self.apply(out, orders);
        }
    }

    /// Carries out the glue's effects: orders to the body, messages to the
    /// link.
    fn apply(&mut self, effects: Effects, orders: &mut Vec<Order>) {
        for e in effects {
            match e {
                Effect::Body(o) => orders.push(o),
                Effect::Send(m) => self.queue(m),
                Effect::Datagram(m) => self.end.link.send_datagram(m),
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
