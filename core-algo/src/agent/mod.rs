//! The robot's brain: events in, commands out.
//!
//! An [`Agent`] owns its robot's [`KnownMap`] (maps stay decentralised: each
//! robot keeps its own copy, built from its own node hits and the reports
//! other robots relay), a planner scratch field and a [`Strategy`]. It is a
//! pure state machine like smoltcp's sockets: the caller feeds it [`Event`]s
//! with the current time and carries out the [`Command`]s it returns. The
//! same code runs in the firmware, in the simulator and on the phone side on
//! behalf of a 2010 robot.
//!
//! ## Life of an agent
//!
//! `Idle` → (start) → `Explore` → (no reachable frontier) → `Return` →
//! (home, team done) → `Finished`; `Manual` while a person steers; `Error`
//! after repeated refusals. The robot decides only while it stands on a
//! node: it reports the node, asks its strategy for a decision, announces a
//! new target, turns if it must and drives one edge.
//!
//! ## Robustness
//!
//! - A move is only ever commanded along an arm the map knows to exist.
//! - A collision sends the robot back to the node it left; it waits a
//!   back-off that grows with each retry and differs by robot id (so two
//!   robots that met head-on do not retry in lockstep), then decides again.
//! - A refused command is retried after a back-off; after
//!   [`MAX_REJECTS`] refusals in a row the agent stops in `Error`.
//! - A teammate not heard from for [`AgentConfig::peer_timeout_ms`] counts
//!   as failed: its target is freed and it no longer holds up the end.
//! - A robot with nothing to do waits and decides again whenever its map
//!   grows, so an unreachable frontier never stalls the team.

use crate::explore::{Context, Decision, Goal, MAX_ROBOTS, RobotView, Strategy};
use crate::geometry::{Arms, Heading, Pos, Turn};
use crate::localize::Localizer;
use crate::map::{Block, KnownMap, MapError};
use crate::path::{DistField, Flow, Forest, PlanCell};
use crate::team::RobotId;
use crate::timing::{TICK_MS, Ticks};
use heapless::Vec;

pub mod body;
mod decide;
mod fill_order;
pub mod firmware;
mod homecoming;
mod io;
mod localizing;
mod peers;
mod retreat;
mod shared;

pub use io::{AgentConfig, AgentError, Command, Event, ManualOrder, Mode, PeerNews};
pub use shared::SharedFields;
#[cfg(test)]
mod tests;

/// Milliseconds since some epoch, wrapping (compare with `wrapping_sub`).
pub type Millis = u32;

/// Refusals in a row after which the agent gives up.
pub const MAX_REJECTS: u8 = 5;

/// The most commands one event can produce.
pub const MAX_COMMANDS: usize = 10;

/// The commands one event produced, in the order to carry them out.
pub type Commands = Vec<Command, MAX_COMMANDS>;

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Motion {
    /// Standing on a node, free to decide.
    Standing,
    /// Waiting for the initial scan of the start node.
    Scanning,
    /// Driving from `from` towards `heading`.
    Driving { from: Pos },
    /// Standing, waiting until `until` before deciding again.
    Waiting { until: Millis },
}

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
struct Peer {
    known: bool,
    failed: bool,
    pos: Pos,
    heading: Heading,
    home: Pos,
    target: Option<Pos>,
    last_heard: Millis,
}

const NO_PEER: Peer = Peer {
    known: false,
    failed: false,
    pos: Pos::new(0, 0),
    heading: Heading::North,
    home: Pos::new(0, 0),
    target: None,
    last_heard: 0,
};

/// A retreat out of a team mate's way home.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
struct Retreat {
    spot: Pos,
    /// Where our way to the spot leaves the bumper's way: once the bumper
    /// is past it, we can only follow it, never meet it head-on. `None`
    /// when the bumper's way does not come through where we stood.
    leave: Option<Pos>,
    bumper: usize,
    /// The bumper stood at home and retreats itself (a chain, see
    /// `on_bumped`): its way is the one to its announced spot, and it
    /// needs it until it is back home with no spot.
    chained: bool,
    /// Where the bumper stood when we last saw it move, and when.
    bumper_at: Pos,
    since: Millis,
}

/// The robot's brain; see the module docs.
///
/// `K` planner fields: one is enough for decentralised strategies (the
/// firmware's choice, 16 bytes per node each); centralised ones (assignment,
/// tempo) plan for the whole team and want one per robot. Their storage
/// (`M`, `F`) lives for the whole program, as a robot's static buffers and
/// a host's vectors do, so that a host's [`SharedFields`] can serve it.
pub struct Agent<M: 'static, F: 'static, S, const K: usize> {
    id: RobotId,
    config: AgentConfig,
    map: KnownMap<M>,
    fields: [DistField<F>; K],
    strategy: S,
    mode: Mode,
    motion: Motion,
    pos: Pos,
    heading: Heading,
    home: Pos,
    target: Option<Pos>,
    peers: [Peer; MAX_ROBOTS],
    retries: u8,
    rejects: u8,
    escaping: bool,
    yielding: bool,
    /// The team mate we last stepped aside for (see `on_bumped`), while
    /// the yield wait lasts.
    made_way_for: Option<usize>,
    gated_since: Option<Millis>,
    /// Since when (and at which map revision) the strategy has told us to
    /// wait for work: see `decide`.
    idle_since: Option<(u32, Millis)>,
    /// A digest of where the team mates we wait for stand and who is home:
    /// waiting lasts while it changes (see `keep_out_of_the_way`).
    gated_progress: u32,
    /// Fill rank of every robot's home: the larger fills first (see
    /// `fill_order`), computed once the map is complete.
    depth: [u64; MAX_ROBOTS],
    /// `depth` is computed; whether the agent acts on it yet is
    /// `depth_known` (see `made_way_for_a_holding_retreat`).
    depth_ready: bool,
    depth_known: bool,
    /// Making way for a team mate whose home fills first: where to, whom
    /// for, since when (see `on_bumped`).
    retreat: Option<Retreat>,
    finished_sent: bool,
    map_grew: bool,
    now: Millis,
    last_said: Millis,
    ignored: u32,
    localizer: Localizer,
    /// Where a host keeps whole fields for every agent it runs (see
    /// [`SharedFields`]); `None` on a robot.
    shared: Option<&'static dyn SharedFields<M, F>>,
    /// The known graph as a forest, kept up with every visit, where a
    /// host gives it storage: on a maze the strategy reads travel times
    /// off it instead of searching (see [`Forest`]). `None` on a robot.
    forest: Option<Forest<F>>,
}

impl<M, F, S, const K: usize> Agent<M, F, S, K>
where
    M: AsRef<[Block]> + AsMut<[Block]>,
    F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
    S: Strategy<M, F>,
{
    /// An idle agent for robot `id` with an empty `map` (its window must hold
    /// the field), planner scratch `fields` and a strategy.
    pub fn new(
        id: RobotId,
        map: KnownMap<M>,
        fields: [DistField<F>; K],
        strategy: S,
        config: AgentConfig,
    ) -> Self {
        Agent {
            id,
            config,
            map,
            fields,
            strategy,
            mode: Mode::Idle,
            motion: Motion::Standing,
            pos: Pos::new(0, 0),
            heading: Heading::North,
            home: Pos::new(0, 0),
            target: None,
            peers: [NO_PEER; MAX_ROBOTS],
            retries: 0,
            rejects: 0,
            escaping: false,
            yielding: false,
            made_way_for: None,
            gated_since: None,
            idle_since: None,
            gated_progress: 0,
            depth: [0; MAX_ROBOTS],
            depth_ready: false,
            depth_known: false,
            retreat: None,
            finished_sent: false,
            map_grew: false,
            now: 0,
            last_said: 0,
            ignored: 0,
            localizer: Localizer::new(id),
            shared: None,
            forest: None,
        }
    }

    /// The same agent, keeping its known graph as a [`Forest`] in
    /// `storage` (one planner cell per node of the map window): the same
    /// decisions, sooner, on mazes.
    pub fn with_forest(self, storage: F) -> Self {
        Agent {
            forest: Some(Forest::new(storage)),
            ..self
        }
    }

    /// Brings the forest up to the map after a visit (a visit at a time,
    /// so the map's log of changes always reaches back to the last one).
    fn keep_forest(&mut self) {
        if let Some(f) = self.forest.as_mut() {
            f.sync(&self.map);
        }
    }

    /// The same agent, taking whole fields of the complete map from
    /// `shared` and keeping those it searches there (see
    /// [`SharedFields`]): the same decisions, sooner, on a host that runs
    /// the whole team.
    pub fn with_shared_fields(self, shared: &'static dyn SharedFields<M, F>) -> Self {
        Agent {
            shared: Some(shared),
            ..self
        }
    }

    /// This robot's id.
    pub fn id(&self) -> RobotId {
        self.id
    }

    /// Replaces the timing the strategy costs moves with: a robot learns
    /// its line speed (and so its timing) only from the phone's start
    /// message, after the agent was built.
    pub fn set_timing(&mut self, timing: crate::timing::Timing) {
        self.config.timing = timing;
    }

    /// The current mode.
    pub fn mode(&self) -> Mode {
        self.mode
    }

    /// Where the robot believes it stands (or last stood), and its heading.
    pub fn pose(&self) -> (Pos, Heading) {
        (self.pos, self.heading)
    }

    /// The robot's home (start node).
    pub fn home(&self) -> Pos {
        self.home
    }

    /// The announced target.
    pub fn target(&self) -> Option<Pos> {
        self.target
    }

    /// The spot it retreats to out of a team mate's way home, and that team
    /// mate, while it does (for views and traces).
    pub fn retreating(&self) -> Option<(Pos, RobotId)> {
        self.retreat.map(|r| (r.spot, RobotId(r.bumper as u8)))
    }

    /// The robot's own map.
    pub fn map(&self) -> &KnownMap<M> {
        &self.map
    }

    /// The localization state (meaningful after a `StartLocalize`).
    pub fn localizer(&self) -> &Localizer {
        &self.localizer
    }

    /// Events that did not fit the state and were ignored.
    pub fn ignored(&self) -> u32 {
        self.ignored
    }

    /// Whether the robot stands on a node waiting for nothing but a decision
    /// or a timer (not driving, not turning).
    pub fn is_standing(&self) -> bool {
        matches!(self.motion, Motion::Standing | Motion::Waiting { .. })
    }

    /// Takes one event at time `now`; returns the commands to carry out.
    pub fn handle(&mut self, now: Millis, event: Event) -> Result<Commands, AgentError> {
        self.now = now;
        let mut out = Commands::new();
        let result = match event {
            Event::Start { pos, heading } => self.on_start(pos, heading, &mut out),
            Event::StartLocalize { method, team } => self.on_start_localize(method, team),
            _ if self.mode == Mode::Localize => self.on_localize_event(event, &mut out),
            Event::NodeHit { relative } => self.on_node(relative, &mut out),
            Event::Collision => self.on_collision(&mut out),
            Event::Rejected => self.on_rejected(&mut out),
            Event::Bumped { toward } => self.on_bumped(toward, &mut out),
            Event::Peer(id, news) => self.on_peer(id, news, &mut out),
            Event::Manual(order) => self.on_manual(order, &mut out),
            Event::Tick => self.on_tick(&mut out),
        };
        if result.is_err() {
            self.ignored = self.ignored.saturating_add(1);
        }
        if out
            .iter()
            .any(|c| matches!(c, Command::Report { .. } | Command::Announce { .. }))
        {
            self.last_said = now;
        }
        result.map(|()| out)
    }

    fn on_start(
        &mut self,
        pos: Pos,
        heading: Heading,
        out: &mut Commands,
    ) -> Result<(), AgentError> {
        if self.mode != Mode::Idle {
            return Err(AgentError::Unexpected);
        }
        if !self.map.bounds().contains(pos) {
            self.mode = Mode::Error;
            push(out, Command::Stop);
            return Err(AgentError::Map(MapError::OutOfBounds(pos)));
        }
        self.pos = pos;
        self.heading = heading;
        self.home = pos;
        self.mode = Mode::Explore;
        // The robot stands on its start node: the initial scan's node hit
        // tells its shape, then the first decision follows.
        self.motion = Motion::Scanning;
        Ok(())
    }

    fn on_node(&mut self, relative: Arms, out: &mut Commands) -> Result<(), AgentError> {
        if !matches!(self.motion, Motion::Driving { .. } | Motion::Scanning) {
            return Err(AgentError::Unexpected);
        }
        let arms = Arms::from_relative(relative, self.heading);
        self.motion = Motion::Standing;
        let escaped = core::mem::take(&mut self.escaping);
        self.retries = 0;
        let visited = self.map.visit(self.pos, arms, self.id);
        self.keep_forest();
        match visited {
            Ok(_) => {}
            Err(MapError::Conflict(_)) => {
                // Our own sensors disagree with the team's map: trust the
                // map (a misread is likelier than a changed floor), but say
                // what we saw so the phone side can count it.
            }
            Err(e) => {
                self.mode = Mode::Error;
                push(out, Command::Stop);
                return Err(AgentError::Map(e));
            }
        }
        push(
            out,
            Command::Report {
                pos: self.pos,
                arms,
                heading: self.heading,
            },
        );
        if escaped {
            // Leave the other robots time to get home first: wait until
            // every living teammate reported being home, or a time-out
            // that differs by id so that two robots that both made way do
            // not come back together.
            let edge_ms = self.config.timing.edge.saturating_mul(TICK_MS);
            let edges = 6 + 4 * u32::from(self.id.0 % 8);
            let wait =
                edge_ms.saturating_mul(edges) + self.jitter(edge_ms.saturating_mul(8), self.now);
            self.yielding = true;
            self.motion = Motion::Waiting {
                until: self.now.wrapping_add(wait),
            };
        } else {
            self.decide(out);
        }
        Ok(())
    }

    fn on_collision(&mut self, out: &mut Commands) -> Result<(), AgentError> {
        let Motion::Driving { from } = self.motion else {
            return Err(AgentError::Unexpected);
        };
        let blocked = self.pos;
        // Back on the node it left, facing back.
        self.pos = from;
        self.heading = self.heading.opposite();
        self.retries = self.retries.saturating_add(1);
        let wait = self.backoff();
        self.motion = Motion::Waiting {
            until: self.now.wrapping_add(wait),
        };
        // Homecoming: ran into a team mate. If its home fills first, get
        // out of its way; if ours does but it keeps standing there (it has
        // nowhere to go), make way for it instead, or both wait for ever.
        if self.retreat.is_none() && self.mode == Mode::Return && self.map.is_complete() {
            let b = self
                .peers
                .iter()
                .position(|q| q.known && !q.failed && q.pos == blocked);
            if let Some(b) = b.filter(|&b| self.goes_first(b) || self.retries >= 3) {
                self.plan_retreat(b, false);
            }
        }
        // Tell the team where we stand and which way we face now: a team
        // mate that still sees us on the node ahead, facing it, plans the
        // team's shares with the wrong costs. Two robots that each think
        // the other is nearer the last frontier node both wait for ever.
        if let Some(arms) = self.map.known_arms(from) {
            push(
                out,
                Command::Report {
                    pos: from,
                    arms,
                    heading: self.heading,
                },
            );
        }
        Ok(())
    }

    fn on_rejected(&mut self, out: &mut Commands) -> Result<(), AgentError> {
        self.rejects = self.rejects.saturating_add(1);
        if self.rejects >= MAX_REJECTS {
            self.mode = Mode::Error;
            self.motion = Motion::Standing;
            push(out, Command::Stop);
            return Ok(());
        }
        // Whatever was refused did not happen: stand, wait, decide again.
        if let Motion::Driving { from } = self.motion {
            self.pos = from;
        }
        self.motion = Motion::Waiting {
            until: self.now.wrapping_add(self.backoff()),
        };
        Ok(())
    }

    fn on_manual(&mut self, order: ManualOrder, out: &mut Commands) -> Result<(), AgentError> {
        match order {
            ManualOrder::Take => {
                if matches!(self.mode, Mode::Idle | Mode::Error | Mode::Localize) {
                    return Err(AgentError::Unexpected);
                }
                self.mode = Mode::Manual;
                if self.target.take().is_some() {
                    push(out, Command::Announce { target: None });
                }
                if let Motion::Waiting { .. } = self.motion {
                    self.motion = Motion::Standing;
                }
                Ok(())
            }
            ManualOrder::Release => {
                if self.mode != Mode::Manual {
                    return Err(AgentError::Unexpected);
                }
                self.mode = Mode::Explore;
                self.finished_sent = false;
                if matches!(self.motion, Motion::Standing) {
                    self.decide(out);
                }
                Ok(())
            }
            ManualOrder::Turn(t) => {
                if self.mode != Mode::Manual || !matches!(self.motion, Motion::Standing) {
                    return Err(AgentError::Unexpected);
                }
                self.heading = self.heading.turned(t);
                push(out, Command::Turn(t));
                Ok(())
            }
            ManualOrder::Move => {
                if self.mode != Mode::Manual || !matches!(self.motion, Motion::Standing) {
                    return Err(AgentError::Unexpected);
                }
                if !self.can_move(self.heading) {
                    return Err(AgentError::Unexpected);
                }
                self.start_move(out);
                Ok(())
            }
        }
    }
}

fn push(out: &mut Commands, c: Command) {
    // MAX_COMMANDS covers the longest sequence one event can produce
    // (report, announce, turn, move, finished); a full outbox drops the
    // least important tail rather than panicking.
    let _ = out.push(c);
}
