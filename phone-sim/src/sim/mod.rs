//! The node-level discrete-event simulator of the whole system.
//!
//! Every robot is a [`SimFirmware`] (the core-algo agent behind the real
//! reliable link) in a [`Body`](body::Body) on the true field; every robot
//! has a [`SimRobot`] proxy on the phone side, joined to it by two lossy
//! [`Channel`](channel::Channel)s that carry the real encoded frames. The
//! phone side is the same as with real robots: proxies, the handler
//! [`Chain`](crate::handlers::Chain), the relay and the [`Environment`].
//!
//! Time advances from event to event (a body finishing an action, bytes
//! arriving, a fault) and at least every [`SimConfig::tick_ms`] for the
//! links' and agents' timers. Everything is seeded: the same configuration
//! gives the same run.

pub mod body;
pub mod channel;
pub mod localize;
mod outcome;
pub mod robot;
pub mod timeline;
mod wake;

pub use outcome::{Localization, Outcome, RobotOutcome, outcome_of};

use crate::environment::Environment;
use crate::field::Field;
use crate::phone::PhoneSide;
use crate::proxy::{RobotProxy, SimRobot};
use body::{Bodies, Order};
use channel::{ChannelFaults, ChannelStats};
use core_algo::agent::AgentConfig;
use core_algo::agent::Mode;
use core_algo::geometry::Pos;
use core_algo::localize::Progress;
use core_algo::map::Bounds;
use core_algo::protocol::message::LocalizeMethod;
use core_algo::protocol::{LinkConfig, MAX_FRAME_LEN, Message};
use core_algo::team::RobotId;
use core_algo::timing::Timing;
use robot::{BoxedStrategy, SimFirmware, host_agent};
use wake::Wakes;

/// Faults to inject into a run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Faults {
    /// Link faults, the same for every robot.
    pub channel: ChannelFaults,
    /// Robots that die at a time (ms).
    pub kill: Vec<(RobotId, u32)>,
    /// Robots that stall: (robot, from ms, for ms).
    pub stall: Vec<(RobotId, u32, u32)>,
    /// Robots whose link is cut: (robot, from ms, for ms).
    pub cut: Vec<(RobotId, u32, u32)>,
}

/// How to run a simulation.
#[derive(Clone, Debug)]
pub struct SimConfig {
    /// Seed of every random stream.
    pub seed: u64,
    /// Faults to inject.
    pub faults: Faults,
    /// Link timers.
    pub link: LinkConfig,
    /// Agent tunables (its timing is replaced by the field's).
    pub agent: AgentConfig,
    /// Timer granularity, ms.
    pub tick_ms: u32,
    /// Give up after this much simulated time, ms.
    pub max_time_ms: u32,
    /// Line speed, motor steps per second.
    pub speed: u32,
    /// `None`: the phone gives every robot its start pose (the 2010
    /// system's way); otherwise the robots localize by this method first.
    pub localize: Option<LocalizeMethod>,
}

impl Default for SimConfig {
    fn default() -> Self {
        SimConfig {
            seed: 1,
            faults: Faults::default(),
            link: LinkConfig::default(),
            agent: AgentConfig::default(),
            tick_ms: 50,
            max_time_ms: 3_600_000,
            speed: core_algo::timing::DEFAULT_SPEED_STEPS_PER_S,
            localize: None,
        }
    }
}

/// Why a simulation cannot start.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SimError {
    /// More robots than start poses.
    TooManyRobots {
        /// Asked for.
        robots: usize,
        /// Starts in the field.
        starts: usize,
    },
    /// No robot at all.
    NoRobots,
    /// Local localization needs starts on a connected set of neighbours.
    StartsNotAdjacent,
    /// Localization works with teams of up to `max` robots.
    TeamTooLarge {
        /// The most robots localization handles.
        max: usize,
    },
    /// The agents plan for teams of up to `max` robots
    /// (`core_algo::explore::MAX_ROBOTS`).
    TeamBeyondPlanner {
        /// Asked for.
        robots: usize,
        /// The largest team.
        max: usize,
    },
}

impl std::fmt::Display for SimError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SimError::TooManyRobots { robots, starts } => {
                write!(
                    f,
                    "asked for {robots} robots, but the field has {starts} start poses"
                )
            }
            SimError::NoRobots => write!(f, "expected at least one robot"),
            SimError::StartsNotAdjacent => write!(
                f,
                "local localization needs start nodes that form one connected set of \
                 neighbours joined by lines; use --localize global for other starts"
            ),
            SimError::TeamTooLarge { max } => {
                write!(f, "localization works with teams of up to {max} robots")
            }
            SimError::TeamBeyondPlanner { robots, max } => write!(
                f,
                "asked for {robots} robots, but teams have at most {max} (use --robots)"
            ),
        }
    }
}

impl std::error::Error for SimError {}

/// The whole simulated system; see the module docs.
pub struct Simulation {
    now: u32,
    next_tick: u32,
    config: SimConfig,
    field: Field,
    bodies: Bodies,
    firmware: Vec<SimFirmware>,
    proxies: Vec<Box<SimRobot>>,
    phone: PhoneSide,
    /// When each robot's parts next need a step's attention.
    wakes: Wakes,
    /// Robots whose bodies reported in this step.
    reported: Vec<bool>,
    paused: bool,
    done_at: Option<u32>,
    /// When the phone's map first had no frontier left.
    mapped_at: Option<u32>,
    linger: bool,
    localized_at: Vec<Option<u32>>,
}

/// The map window every participant uses: the field's bounding box with a
/// margin of one node, so that border nodes have neighbours in the window.
pub fn window(field: &Field) -> Bounds {
    let b = field.bounds();
    Bounds::new(
        Pos::new(b.origin.x.saturating_sub(1), b.origin.y.saturating_sub(1)),
        b.width.saturating_add(2),
        b.height.saturating_add(2),
    )
}

impl Simulation {
    /// A simulation of `robots` robots (the field's first start poses), each
    /// deciding with the strategy `strategy(id)` makes.
    pub fn new(
        field: &Field,
        robots: usize,
        mut strategy: impl FnMut(RobotId) -> BoxedStrategy,
        config: SimConfig,
    ) -> Result<Simulation, SimError> {
        if robots == 0 {
            return Err(SimError::NoRobots);
        }
        if robots > core_algo::explore::MAX_ROBOTS {
            return Err(SimError::TeamBeyondPlanner {
                robots,
                max: core_algo::explore::MAX_ROBOTS,
            });
        }
        if robots > field.starts().len() {
            return Err(SimError::TooManyRobots {
                robots,
                starts: field.starts().len(),
            });
        }
        let timing = Timing::from_hardware(u32::from(field.spacing_mm()), config.speed);
        let starts: Vec<_> = field
            .starts()
            .iter()
            .take(robots)
            .map(|s| (s.pos, s.heading))
            .collect();
        let team_starts: Vec<_> = field.starts().iter().take(robots).copied().collect();
        if config.localize.is_some() && robots > core_algo::explore::MAX_ROBOTS {
            return Err(SimError::TeamTooLarge {
                max: core_algo::explore::MAX_ROBOTS,
            });
        }
        if config.localize == Some(LocalizeMethod::Local)
            && !localize::starts_adjacent(field, &team_starts)
        {
            return Err(SimError::StartsNotAdjacent);
        }
        let bounds = match config.localize {
            None => window(field),
            Some(_) => localize::team_window(field),
        };
        let agent_config = AgentConfig {
            timing,
            ..config.agent
        };
        let firmware = (0..robots)
            .map(|i| {
                let id = RobotId(i as u8);
                SimFirmware::new(
                    id,
                    host_agent(id, bounds, strategy(id), agent_config),
                    config.link,
                    1,
                )
            })
            .collect();
        let proxies = (0..robots)
            .map(|i| {
                Box::new(SimRobot::new(
                    RobotId(i as u8),
                    config.link,
                    config.faults.channel,
                    config.seed.wrapping_add(i as u64 * 7919),
                ))
            })
            .collect();
        Ok(Simulation {
            now: 0,
            next_tick: 0,
            bodies: Bodies::new(field.nodes().clone(), timing, &starts)
                .with_spacing_mm(u32::from(field.spacing_mm())),
            firmware,
            proxies,
            phone: PhoneSide::new(
                bounds,
                team_starts,
                config.speed.min(u32::from(u16::MAX)) as u16,
            )
            .with_localize(config.localize),
            wakes: Wakes::new(robots),
            reported: vec![false; robots],
            paused: false,
            done_at: None,
            mapped_at: None,
            linger: false,
            localized_at: vec![None; robots],
            field: field.clone(),
            config,
        })
    }

    /// Simulated time, ms.
    pub fn now(&self) -> u32 {
        self.now
    }

    /// The phone side's model.
    pub fn env(&self) -> &Environment {
        self.phone.env()
    }

    /// The phone side's model, to subscribe views.
    pub fn env_mut(&mut self) -> &mut Environment {
        self.phone.env_mut()
    }

    /// The bodies.
    pub fn bodies(&self) -> &Bodies {
        &self.bodies
    }

    /// The robots' firmware.
    pub fn firmware(&self) -> &[SimFirmware] {
        &self.firmware
    }

    /// The proxies.
    pub fn proxies(&self) -> &[Box<SimRobot>] {
        &self.proxies
    }

    /// The true field.
    pub fn field(&self) -> &Field {
        &self.field
    }

    /// Pauses or resumes the clock.
    pub fn set_paused(&mut self, paused: bool) {
        self.paused = paused;
    }

    /// Sends `message` to robot `id` through its proxy (manual control).
    pub fn send(&mut self, id: RobotId, message: Message) -> bool {
        let Some(p) = self.proxies.get_mut(id.index()) else {
            return false;
        };
        p.send(message);
        self.wakes.proxy_now(id.index());
        true
    }

    /// Keeps the world going after the team is done, so that a person
    /// can still steer robots (the web UI); the outcome keeps the time the
    /// team was first done.
    pub fn set_linger(&mut self, linger: bool) {
        self.linger = linger;
    }

    /// Cuts robot `id`'s link both ways from now for `for_ms` (a fault a
    /// person injects while watching).
    pub fn cut_link(&mut self, id: RobotId, for_ms: u32) {
        self.config
            .faults
            .cut
            .push((id, self.now, for_ms.min(u32::MAX - self.now)));
    }

    /// Whether the run is over: the team finished, everyone died, or time
    /// ran out.
    pub fn is_over(&self) -> bool {
        self.done_at.is_some() || self.now >= self.config.max_time_ms
    }

    /// Every robot is dead or has said the team is done and stands still;
    /// or every living robot gave up (nothing will happen any more).
    fn team_done(&self) -> bool {
        let robots = || self.firmware.iter().zip(self.bodies.bodies());
        robots().all(|(f, b)| f.is_dead() || (f.finished() && b.is_idle()))
            || robots()
                .all(|(f, b)| f.is_dead() || (f.agent().mode() == Mode::Error && b.is_idle()))
    }

    /// Notes when each robot joined the team frame.
    fn note_localized(&mut self) {
        if self.config.localize.is_none() {
            return;
        }
        for (at, f) in self.localized_at.iter_mut().zip(&self.firmware) {
            if at.is_none() && matches!(f.agent().localizer().progress(), Progress::Done(_)) {
                *at = Some(self.now);
            }
        }
    }

    /// How the true frame maps into the team's frame: robot 0's own frame
    /// when localizing, the true frame itself otherwise.
    pub fn true_to_team(&self) -> core_algo::localize::Frame {
        match self.config.localize {
            None => core_algo::localize::Frame::IDENTITY,
            Some(_) => localize::true_to_team(self.field.starts()),
        }
    }

    /// Advances to the next event; returns `false` once the run is over.
    pub fn step(&mut self) -> bool {
        if self.is_over() && !self.linger {
            return false;
        }
        if self.paused {
            return true;
        }
        let next = [
            Some(self.next_tick),
            self.bodies.next_event(),
            self.wakes.next_arrival(),
        ]
        .into_iter()
        .flatten()
        .min()
        .unwrap_or(self.next_tick)
        .max(self.now);
        self.now = next;
        self.phone.env_mut().set_now(self.now);
        self.apply_faults();
        let now = self.now;
        let mut reports = Vec::new();
        self.bodies.advance(now, &mut reports);
        let mut orders = Vec::new();
        self.reported.fill(false);
        for (id, r) in reports {
            if let Some(seen) = self.reported.get_mut(id.index()) {
                *seen = true;
            }
            if let Some(f) = self.firmware.get_mut(id.index()) {
                f.on_report(now, r, &mut orders);
                self.order(id, &mut orders);
            }
        }
        let tick = now >= self.next_tick;
        if tick {
            self.next_tick = now + self.config.tick_ms.max(1);
        }
        for i in 0..self.firmware.len() {
            // Most steps are one frame's arrival at one robot: the others
            // have nothing to do (see `wake`).
            let reported = self.reported.get(i).copied().unwrap_or(true);
            if !(tick || reported || self.wakes.firmware_due(i, now)) {
                debug_assert!(
                    self.firmware.get(i).is_none_or(|f| f.is_quiet(now))
                        && self
                            .proxies
                            .get(i)
                            .is_none_or(|p| { p.down.next_arrival().is_none_or(|t| t > now) }),
                    "robot {i} left alone at {now} with something to do"
                );
                continue;
            }
            let id = RobotId(i as u8);
            while let Some(bytes) = self.proxies.get_mut(i).and_then(|p| p.down.receive(now)) {
                if let Some(f) = self.firmware.get_mut(i) {
                    f.on_bytes(now, &bytes, &mut orders);
                }
                self.order(id, &mut orders);
            }
            if tick && let Some(f) = self.firmware.get_mut(i) {
                f.tick(now, &mut orders);
                self.order(id, &mut orders);
            }
            let mut buf = [0u8; MAX_FRAME_LEN];
            if let (Some(f), Some(p)) = (self.firmware.get_mut(i), self.proxies.get_mut(i)) {
                while let Some(n) = f.poll_transmit(now, &mut buf) {
                    p.up.send(now, buf.get(..n).unwrap_or(&[]));
                }
                let arrivals = (p.up.next_arrival(), p.down.next_arrival());
                self.wakes
                    .firmware_served(i, now, f.quiet_for(now), arrivals);
            }
        }
        let wakes = &self.wakes;
        debug_assert!(
            self.proxies
                .iter()
                .enumerate()
                .all(|(i, p)| wakes.proxy_due(i, now) || p.is_quiet(now)),
            "a proxy left alone at {now} with something to do"
        );
        let sent = self
            .phone
            .process_due(now, &mut self.proxies, |_, i| wakes.proxy_due(i, now));
        for (i, p) in self.proxies.iter().enumerate() {
            if sent || self.wakes.proxy_due(i, now) {
                let arrivals = (p.up.next_arrival(), p.down.next_arrival());
                self.wakes
                    .proxy_served(i, now, p.link_quiet_for(now), arrivals);
            }
        }
        self.note_localized();
        if self.mapped_at.is_none() {
            let map = self.phone.env().map();
            if map.visited_len() > 0 && map.is_complete() {
                self.mapped_at = Some(now);
            }
        }
        if self.done_at.is_none() && self.team_done() {
            self.done_at = Some(now);
        }
        true
    }

    /// Runs to the end.
    pub fn run(&mut self) -> Outcome {
        while self.step() {}
        self.outcome()
    }

    /// Hands `orders` to robot `id`'s body. An order can end at once (no
    /// line ahead): its report goes back to the firmware, whose answer is
    /// ordered in turn, until nothing more happens at this instant.
    fn order(&mut self, id: RobotId, orders: &mut Vec<Order>) {
        let mut pending: Vec<(RobotId, Order)> = orders.drain(..).map(|o| (id, o)).collect();
        let mut reports = Vec::new();
        let mut more = Vec::new();
        while !pending.is_empty() {
            for (rid, o) in pending.drain(..) {
                self.bodies.order(rid, o, self.now, &mut reports);
            }
            for (rid, r) in reports.drain(..) {
                if let Some(f) = self.firmware.get_mut(rid.index()) {
                    f.on_report(self.now, r, &mut more);
                }
                pending.extend(more.drain(..).map(|o| (rid, o)));
            }
        }
    }

    fn apply_faults(&mut self) {
        let now = self.now;
        for &(id, at) in &self.config.faults.kill {
            if now >= at && self.firmware.get(id.index()).is_some_and(|f| !f.is_dead()) {
                if let Some(f) = self.firmware.get_mut(id.index()) {
                    f.kill();
                }
                self.bodies.kill(id);
                self.phone
                    .env_mut()
                    .log_line(format!("fault: robot {id} dies at {now} ms"));
            }
        }
        for &(id, at, dur) in &self.config.faults.stall {
            if now >= at && now < at + dur {
                self.bodies.stall(id, at + dur);
            }
        }
        // A robot's link is cut while any of its cuts lasts. (Most runs cut
        // none: they need not allocate at every step to learn it.)
        if self.config.faults.cut.is_empty() {
            return;
        }
        let mut cut: Vec<Option<bool>> = vec![None; self.proxies.len()];
        for &(id, at, dur) in &self.config.faults.cut {
            if let Some(c) = cut.get_mut(id.index()) {
                let active = now >= at && now - at < dur;
                *c = Some(c.unwrap_or(false) || active);
            }
        }
        for (p, c) in self.proxies.iter_mut().zip(cut) {
            if let Some(c) = c {
                p.up.set_cut(c);
                p.down.set_cut(c);
            }
        }
    }

    /// The run's result so far.
    pub fn outcome(&self) -> Outcome {
        let alive: Vec<bool> = self.firmware.iter().map(|f| !f.is_dead()).collect();
        let (mut down, mut up) = (ChannelStats::default(), ChannelStats::default());
        for p in &self.proxies {
            let (d, u) = p.channel_stats();
            down.sent += d.sent;
            down.lost += d.lost;
            up.sent += u.sent;
            up.lost += u.lost;
        }
        let mut o = outcome_of(
            &self.field,
            self.phone.env(),
            &self.bodies,
            &alive,
            self.done_at.unwrap_or(self.now),
            (down.sent + up.sent, down.lost + up.lost),
            self.true_to_team(),
        );
        o.localization = self.config.localize.map(|_| self.localization());
        o.mapped_ms = self.mapped_at;
        o.timed_out = self.done_at.is_none() && self.now >= self.config.max_time_ms;
        o
    }
}
