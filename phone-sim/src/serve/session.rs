//! The run behind the web page: one thread owns the team (a simulation or
//! real robots), takes the page's requests from a channel, paces simulated
//! time against the wall clock, and pushes what changed to every page.
//!
//! Owning everything in one thread keeps the environment free of locks (the
//! seed's MVC: views only ever see copies); the HTTP side talks to it only
//! through [`Request`]s and the push channel.

use super::api::{
    Choices, Command, FieldChoice, Frame, NodeView, Push, RobotView, RunInfo, RunResult, RunStatus,
    Snapshot, StatsView,
};
use super::files::{self, choice};
use super::team::Team;
use crate::environment::Update;
use crate::field::Field;
use core_algo::geometry::Pos;
use core_algo::team::RobotId;
use std::collections::{BTreeMap, VecDeque};
use std::sync::Arc;
use std::sync::mpsc;
use std::time::{Duration, Instant};
use tokio::sync::{broadcast, oneshot};

/// How often the pages get a frame.
const FRAME_INTERVAL: Duration = Duration::from_millis(100);
/// Log lines kept for pages that connect later.
const LOG_LINES: usize = 200;
/// Wall time one round may spend stepping a simulation, so that requests
/// are answered promptly even at full speed.
const STEP_BUDGET: Duration = Duration::from_millis(25);

/// A request from the HTTP side.
pub enum Request {
    /// A person's command; the answer says whether it was taken.
    Command(Command, oneshot::Sender<Result<(), String>>),
    /// The whole state.
    Snapshot(oneshot::Sender<Box<Snapshot>>),
    /// The explored map as a file: `field` or `sep`; answers (file name,
    /// text).
    Export(String, oneshot::Sender<Result<(String, String), String>>),
    /// A field file to offer for new runs: (file name, bytes).
    Import(
        String,
        Vec<u8>,
        oneshot::Sender<Result<FieldChoice, String>>,
    ),
}

/// What a new simulation uses.
#[derive(Clone, Debug, PartialEq)]
pub struct RunSpec {
    /// Field name (from the library).
    pub field: String,
    /// Team size.
    pub robots: usize,
    /// Strategy name.
    pub strategy: String,
    /// Seed.
    pub seed: u64,
}

/// The session; see the module docs.
pub struct Session {
    library: Vec<Field>,
    spec: RunSpec,
    team: Team,
    status: RunStatus,
    rate: f64,
    /// (wall clock, run time ms) when time last started running at `rate`.
    anchor: Option<(Instant, u32)>,
    updates: mpsc::Receiver<Update>,
    changed: BTreeMap<Pos, NodeView>,
    frontier_dirty: bool,
    sent_trail: Vec<usize>,
    sent_coverage: usize,
    log: VecDeque<String>,
    log_add: Vec<String>,
    result: Option<RunResult>,
    push: broadcast::Sender<Arc<str>>,
    last_frame: Instant,
}

impl Session {
    /// A session over `team`, offering `library` for new simulations
    /// (`spec` names what `team` runs), pushing to `push`.
    pub fn new(
        library: Vec<Field>,
        spec: RunSpec,
        mut team: Team,
        push: broadcast::Sender<Arc<str>>,
    ) -> Session {
        let updates = team.env_mut().subscribe();
        let robots = team.robot_count();
        Session {
            library,
            spec,
            team,
            status: RunStatus::Ready,
            rate: 4.0,
            anchor: None,
            updates,
            changed: BTreeMap::new(),
            frontier_dirty: true,
            sent_trail: vec![0; robots],
            sent_coverage: 0,
            log: VecDeque::new(),
            log_add: Vec::new(),
            result: None,
            push,
            last_frame: Instant::now(),
        }
    }

    /// Serves requests until every sender is gone.
    pub fn run(mut self, requests: mpsc::Receiver<Request>) {
        if self.team.is_robots() {
            // Real robots start on their own when they say hello.
            self.set_running();
        }
        loop {
            let wait = if self.clock_runs() {
                Duration::from_millis(5)
            } else {
                Duration::from_millis(50)
            };
            match requests.recv_timeout(wait) {
                Ok(r) => self.handle(r),
                Err(mpsc::RecvTimeoutError::Timeout) => {}
                Err(mpsc::RecvTimeoutError::Disconnected) => return,
            }
            while let Ok(r) = requests.try_recv() {
                self.handle(r);
            }
            self.advance();
            if self.last_frame.elapsed() >= FRAME_INTERVAL {
                self.send_frame();
            }
        }
    }

    fn clock_runs(&self) -> bool {
        matches!(self.status, RunStatus::Running | RunStatus::Finished)
    }

    fn handle(&mut self, r: Request) {
        match r {
            Request::Command(c, reply) => {
                let result = self.command(c);
                let _ = reply.send(result);
            }
            Request::Snapshot(reply) => {
                let s = self.snapshot();
                let _ = reply.send(Box::new(s));
            }
            Request::Export(format, reply) => {
                let _ = reply.send(self.export(&format));
            }
            Request::Import(name, bytes, reply) => {
                let _ = reply.send(self.import(&name, &bytes));
            }
        }
    }

    /// Carries out a person's command.
    pub fn command(&mut self, c: Command) -> Result<(), String> {
        match c {
            Command::Start {
                field,
                robots,
                strategy,
                seed,
            } => self.start(field, robots, strategy, seed),
            Command::Pause => {
                if self.status == RunStatus::Running {
                    self.team.pause(true);
                    self.status = RunStatus::Paused;
                    self.anchor = None;
                }
                Ok(())
            }
            Command::Resume => {
                if self.status == RunStatus::Paused {
                    self.team.pause(false);
                    self.set_running();
                }
                Ok(())
            }
            Command::Stop => {
                // A finished run keeps its result; the world stops anyway.
                self.team.pause(true);
                self.status = RunStatus::Stopped;
                self.anchor = None;
                Ok(())
            }
            Command::Rate { x } => {
                if !(0.0..=1000.0).contains(&x) {
                    return Err(format!("expected a rate in 0..=1000, found {x}"));
                }
                self.rate = x;
                if self.anchor.is_some() {
                    self.anchor = Some((Instant::now(), self.team.now()));
                }
                Ok(())
            }
            Command::Manual { robot, on } => {
                self.check_robot(robot)?;
                self.team.manual(RobotId(robot), on);
                self.note(format!(
                    "robot {robot}: manual control {}",
                    if on { "taken" } else { "handed back" }
                ));
                Ok(())
            }
            Command::Turn { robot, turn } => {
                self.check_manual(robot)?;
                self.team.turn(RobotId(robot), turn.into());
                Ok(())
            }
            Command::Move { robot } => {
                self.check_manual(robot)?;
                self.team.drive(RobotId(robot));
                Ok(())
            }
            Command::Speed { robot, steps_per_s } => {
                self.check_robot(robot)?;
                if !(100..=1000).contains(&steps_per_s) {
                    return Err(format!(
                        "expected a speed of 100..=1000 steps/s, found {steps_per_s}"
                    ));
                }
                self.team.speed(RobotId(robot), steps_per_s);
                Ok(())
            }
            Command::CutLink { robot, seconds } => {
                self.check_robot(robot)?;
                if !(0.0..=600.0).contains(&seconds) {
                    return Err(format!("expected 0..=600 seconds, found {seconds}"));
                }
                self.team
                    .cut_link(RobotId(robot), (seconds * 1000.0) as u32)?;
                self.note(format!("robot {robot}: link cut for {seconds} s"));
                Ok(())
            }
        }
    }

    fn check_robot(&self, robot: u8) -> Result<(), String> {
        if usize::from(robot) < self.team.robot_count() {
            Ok(())
        } else {
            Err(format!(
                "no robot {robot}: the team has robots 0..{}",
                self.team.robot_count()
            ))
        }
    }

    fn check_manual(&self, robot: u8) -> Result<(), String> {
        self.check_robot(robot)?;
        if self.team.is_manual(RobotId(robot)) {
            Ok(())
        } else {
            Err(format!("take manual control of robot {robot} first"))
        }
    }

    fn start(
        &mut self,
        field: Option<String>,
        robots: Option<usize>,
        strategy: Option<String>,
        seed: Option<u64>,
    ) -> Result<(), String> {
        if self.team.is_robots() {
            return Err("real robots start by themselves when they say hello".into());
        }
        let spec = RunSpec {
            field: field.unwrap_or_else(|| self.spec.field.clone()),
            robots: robots.unwrap_or(self.spec.robots),
            strategy: strategy.unwrap_or_else(|| self.spec.strategy.clone()),
            seed: seed.unwrap_or(self.spec.seed),
        };
        let f = self
            .library
            .iter()
            .find(|f| f.name() == spec.field)
            .ok_or_else(|| format!("no field named '{}'", spec.field))?;
        // A field with fewer starts takes fewer robots.
        let spec = RunSpec {
            robots: spec.robots.clamp(1, f.starts().len().max(1)),
            ..spec
        };
        let team = Team::simulate(f, &spec)?;
        *self = Session::new(
            std::mem::take(&mut self.library),
            spec,
            team,
            self.push.clone(),
        )
        .with_rate(self.rate);
        self.set_running();
        let snap = self.snapshot();
        self.send(&Push::Snapshot(Box::new(snap)));
        Ok(())
    }

    fn with_rate(mut self, rate: f64) -> Session {
        self.rate = rate;
        self
    }

    fn set_running(&mut self) {
        self.team.pause(false);
        self.status = RunStatus::Running;
        self.anchor = Some((Instant::now(), self.team.now()));
    }

    /// Moves the run's clock on as far as the wall clock says.
    fn advance(&mut self) {
        if !self.clock_runs() {
            return;
        }
        let Some((wall, run)) = self.anchor else {
            return;
        };
        let t0 = Instant::now();
        // Once the team is done, the world runs on only for steering by
        // hand: in real time when the run went as fast as it could.
        let rate = if self.status == RunStatus::Finished && self.rate == 0.0 {
            1.0
        } else {
            self.rate
        };
        let target = if rate > 0.0 {
            let ms = wall.elapsed().as_secs_f64() * 1000.0 * rate;
            Some(
                u64::from(run)
                    .saturating_add(ms as u64)
                    .min(u64::from(u32::MAX)) as u32,
            )
        } else {
            None
        };
        self.team.advance(target, || t0.elapsed() < STEP_BUDGET);
        if self.status == RunStatus::Running
            && let Some(r) = self.team.result()
        {
            self.status = RunStatus::Finished;
            self.anchor = Some((Instant::now(), self.team.now()));
            self.note(format!(
                "team done after {:.1} s{}",
                r.makespan_s,
                if r.complete { "" } else { " (incomplete)" }
            ));
            self.result = Some(r);
        }
        if self.team.is_robots() {
            self.anchor = Some((Instant::now(), self.team.now()));
        }
    }

    fn note(&mut self, line: String) {
        self.log_add.push(line);
    }

    fn drain_updates(&mut self) {
        while let Ok(u) = self.updates.try_recv() {
            match u {
                Update::Node { pos, arms, visits } => {
                    self.changed.insert(
                        pos,
                        [
                            i32::from(pos.x),
                            i32::from(pos.y),
                            i32::from(arms.bits()),
                            i32::from(visits),
                        ],
                    );
                    self.frontier_dirty = true;
                    // Neighbours may now be known without a visit.
                    for h in core_algo::geometry::Heading::ALL {
                        if let Some(q) = pos.step(h)
                            && let Some(v) = self.deduced(q)
                        {
                            self.changed.insert(q, v);
                        }
                    }
                }
                Update::Log(line) => self.log_add.push(line),
                Update::Finished { .. } | Update::Robot(_) => {}
            }
        }
    }

    /// `q` as a node known only by deduction, if it is one.
    fn deduced(&self, q: Pos) -> Option<NodeView> {
        let map = self.team.env().map();
        let cell = map.cell(q);
        if cell.is_visited() {
            return None;
        }
        map.known_arms(q)
            .map(|a| [i32::from(q.x), i32::from(q.y), i32::from(a.bits()), 0])
    }

    fn send(&self, p: &Push) {
        if let Ok(text) = serde_json::to_string(p) {
            // No page listening is fine.
            let _ = self.push.send(Arc::from(text));
        }
    }

    fn send_frame(&mut self) {
        self.drain_updates();
        self.last_frame = Instant::now();
        let env = self.team.env();
        let mut trail_add = Vec::new();
        for (i, r) in env.robots().iter().enumerate() {
            let Some(sent) = self.sent_trail.get_mut(i) else {
                continue;
            };
            for p in r.trail.iter().skip(*sent) {
                trail_add.push([i as i32, i32::from(p.x), i32::from(p.y)]);
            }
            *sent = r.trail.len();
        }
        let coverage = &env.stats().coverage;
        let coverage_add = coverage
            .iter()
            .skip(self.sent_coverage)
            .map(|&(t, k)| [t, k])
            .collect();
        self.sent_coverage = coverage.len();
        let frontier = self.frontier_dirty.then(|| self.frontier());
        self.frontier_dirty = false;
        let log_add = std::mem::take(&mut self.log_add);
        for l in &log_add {
            if self.log.len() == LOG_LINES {
                self.log.pop_front();
            }
            self.log.push_back(l.clone());
        }
        let frame = Frame {
            t_ms: self.team.now(),
            status: Some(self.status),
            nodes: std::mem::take(&mut self.changed).into_values().collect(),
            frontier,
            robots: self.robots(),
            trail_add,
            stats: self.stats(),
            coverage_add,
            log_add,
            result: self.result.clone(),
        };
        self.send(&Push::Frame(Box::new(frame)));
    }

    fn frontier(&self) -> Vec<[i32; 2]> {
        self.team
            .env()
            .map()
            .frontier()
            .map(|p| [i32::from(p.x), i32::from(p.y)])
            .collect()
    }

    fn stats(&self) -> StatsView {
        let env = self.team.env();
        let s = env.stats();
        StatsView {
            known: env.known_nodes(),
            frontier: env.map().frontier_len() as u32,
            received: s.received,
            relayed: s.relayed,
            unhandled: s.unhandled,
            conflicts: s.conflicts,
            link_errors: s.link_errors,
            retransmissions: s.retransmissions,
            link_losses: s.link_losses,
        }
    }

    fn robots(&self) -> Vec<RobotView> {
        (0..self.team.robot_count())
            .filter_map(|i| self.team.robot_view(RobotId(i as u8)))
            .collect()
    }

    /// Everything a page shows.
    pub fn snapshot(&mut self) -> Snapshot {
        // Whatever is pending goes out in the next frame too; frames only
        // add or replace, so a page that gets both stays right.
        self.drain_updates();
        let env = self.team.env();
        let map = env.map();
        let b = map.bounds();
        let mut nodes: Vec<NodeView> = map
            .visited()
            .filter_map(|(p, c)| {
                c.arms().map(|a| {
                    [
                        i32::from(p.x),
                        i32::from(p.y),
                        i32::from(a.bits()),
                        i32::from(c.visits()),
                    ]
                })
            })
            .collect();
        for y in 0..i32::from(b.height) {
            for x in 0..i32::from(b.width) {
                let q = Pos::new(
                    (i32::from(b.origin.x) + x) as i16,
                    (i32::from(b.origin.y) + y) as i16,
                );
                if let Some(v) = self.deduced(q) {
                    nodes.push(v);
                }
            }
        }
        let trails = env
            .robots()
            .iter()
            .map(|r| {
                r.trail
                    .iter()
                    .map(|p| [i32::from(p.x), i32::from(p.y)])
                    .collect()
            })
            .collect();
        let coverage = env.stats().coverage.iter().map(|&(t, k)| [t, k]).collect();
        let log = self.log.iter().cloned().collect();
        Snapshot {
            run: RunInfo {
                mode: if self.team.is_robots() {
                    "robots"
                } else {
                    "sim"
                }
                .into(),
                field: self.spec.field.clone(),
                robots: self.team.robot_count(),
                strategy: self.spec.strategy.clone(),
                seed: self.spec.seed,
                total_nodes: self.team.total_nodes(),
                bounds: [
                    i32::from(b.origin.x),
                    i32::from(b.origin.y),
                    i32::from(b.width),
                    i32::from(b.height),
                ],
                lower_bound_s: self.team.lower_bound_s(),
            },
            status: self.status,
            t_ms: self.team.now(),
            rate: self.rate,
            nodes,
            frontier: self.frontier(),
            robots: self.robots(),
            trails,
            stats: self.stats(),
            coverage,
            log,
            result: self.result.clone(),
            choices: Choices {
                fields: self.library.iter().map(choice).collect(),
                strategies: crate::bench::STRATEGIES
                    .iter()
                    .map(|s| s.to_string())
                    .collect(),
            },
        }
    }

    /// The explored map as a file of `format` (`field` or `sep`); see
    /// [`files::export`].
    pub fn export(&self, format: &str) -> Result<(String, String), String> {
        files::export(
            self.team.env().map(),
            self.team.starts(),
            &self.spec.field,
            format,
        )
    }

    /// Adds an uploaded field file to the library; see [`files::import`].
    pub fn import(&mut self, name: &str, bytes: &[u8]) -> Result<FieldChoice, String> {
        let c = files::import(&mut self.library, name, bytes)?;
        self.note(format!("field {} imported", c.name));
        Ok(c)
    }
}
