//! Localization: robots that start without a common frame agree on one.
//!
//! Every robot starts in its own frame (its start node the origin, its
//! start heading north). Robots sense each other only by contact: a robot
//! that drives into a node where another robot stands is turned back by its
//! proximity sensors, and the standing robot sees it come. Each side
//! reports its half of the contact (see [`Localize`]) and every robot joins
//! the halves into a [`Contact`], which tells how the two frames lie
//! ([`TeamFrames`]). When every robot is in robot 0's frame, the team frame
//! is known and exploration starts.
//!
//! The [`Localizer`] is a pure state machine like the agent: the agent
//! feeds it what the body and the team said, and carries out its [`Step`]s.
//! Every robot runs the same deterministic rules on the same broadcasts, so
//! every robot knows whose turn it is without a coordinator; only the robot
//! whose turn it is moves, so every contact has one active and one passive
//! robot.
//!
//! - **Local** (seed §4.2, robots on adjacent nodes): the lowest-id robot
//!   already in robot 0's frame that has not had its turn drives one edge
//!   along each arm of its start node not known to lead to a placed robot,
//!   and back (or is turned back by a partner, which reports).
//! - **Global** (seed §4.3, robots anywhere): in id order each robot finds
//!   the outer border (drive north, follow the face with the turn count,
//!   climb over inner faces) and stays there; then the lowest id circles
//!   the border until it touches a robot, whose turn it then is. A turn
//!   that meets nobody new hands over to the next group; when every group
//!   had such a turn in a row, localization fails with
//!   [`Failure::NeverMet`] instead of hanging.
//!
//! `docs/localization.md` gives the termination argument.

mod border;
mod frame;
mod turns;
mod walk;

#[cfg(test)]
mod tests;

pub use crate::protocol::message::{Localize, LocalizeMethod};
pub use frame::{Contact, Frame, TeamFrames};
pub use walk::{Trace, higher, left_first};

use crate::explore::MAX_ROBOTS;
use crate::geometry::{Arms, Heading, Pos, Turn};
use crate::protocol::Pose;
use crate::team::RobotId;
use heapless::Vec;

/// The most steps one input can produce.
pub const MAX_STEPS_OUT: usize = 6;

/// The steps one input produced, in the order to carry them out.
pub type Steps = Vec<Step, MAX_STEPS_OUT>;

/// The start node of every robot's own frame.
pub const ORIGIN: Pos = Pos::new(0, 0);

/// What the localizer wants done.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Step {
    /// Turn on the node.
    Turn(Turn),
    /// Drive one edge straight on.
    Move,
    /// Tell the team (relayed to everyone else).
    Say(Localize),
}

/// An input that does not fit the state (a node reached while no move was
/// under way, a bump while nobody should move): refused, nothing changed.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Unexpected;

/// Why localization gave up.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Failure {
    /// Local: every placed robot had its turn and some robot is still
    /// unplaced — the starts were not adjacent.
    NotAdjacent,
    /// Global: every group circled without meeting anyone new.
    NeverMet,
    /// More moves than the budget allows (a safety net; the procedures
    /// end well inside it).
    StepBudget,
    /// The body refused an order (no line where the walk expected one).
    Refused,
    /// More robots than the team tables hold.
    TooManyRobots,
}

/// Where localization stands.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Progress {
    /// Not started, or still agreeing.
    Running,
    /// Done: the robot's own frame maps into the team frame by this.
    Done(Frame),
    /// Gave up.
    Failed(Failure),
}

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Phase {
    /// Waiting until every robot scanned its start node.
    Gather,
    /// Local: synchronisation runs.
    Runs,
    /// Global: each robot in turn finds the outer border.
    Border,
    /// Global: circling the border.
    Circle,
    /// Done or failed.
    Over,
}

/// What this robot does in its turn.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Task {
    /// Not its turn (or the turn has not begun).
    None,
    /// Local: runs along the start node's arms; `tried` so far.
    Runs { tried: Arms },
    /// Global: driving north to a node without a north arm.
    Climb,
    /// Global: tracing the face north of where the climb stopped.
    Trace(Trace),
    /// Global: back round an inner face to its topmost node.
    ToTop { top: Pos },
    /// Global: circling the border.
    Circle(Trace),
}

/// One robot's localization; see the module docs.
#[derive(Clone, Debug)]
pub struct Localizer {
    me: RobotId,
    method: Option<LocalizeMethod>,
    team: u8,
    frames: TeamFrames,
    pos: Pos,
    heading: Heading,
    driving: Option<Pos>,
    arrival: Heading,
    attempted: Heading,
    here: Arms,
    left_arms: Arms,
    home_arms: Arms,
    ready: [bool; MAX_ROBOTS],
    passed: [bool; MAX_ROBOTS],
    rest: [Pose; MAX_ROBOTS],
    phase: Phase,
    holder: Option<RobotId>,
    fruitless: u8,
    turn_met: Option<RobotId>,
    hit: Option<(RobotId, Pose)>,
    bump: Option<(RobotId, RobotId, Pose)>,
    awaiting: bool,
    task: Task,
    blocked: Vec<Pos, 8>,
    walk_next: Option<Heading>,
    steps: u32,
    max_steps: u32,
    contacts: u32,
    progress: Progress,
}

const START: Pose = Pose {
    pos: ORIGIN,
    heading: Heading::North,
};

impl Localizer {
    /// Robot `me`, not started. Broadcasts heard before the start are
    /// kept (a team mate may be ready before this robot is started).
    pub fn new(me: RobotId) -> Self {
        Localizer {
            me,
            method: None,
            team: 1,
            frames: TeamFrames::new(1),
            pos: ORIGIN,
            heading: Heading::North,
            driving: None,
            arrival: Heading::East,
            attempted: Heading::North,
            here: Arms::NONE,
            left_arms: Arms::NONE,
            home_arms: Arms::NONE,
            ready: [false; MAX_ROBOTS],
            passed: [false; MAX_ROBOTS],
            rest: [START; MAX_ROBOTS],
            phase: Phase::Gather,
            holder: None,
            fruitless: 0,
            turn_met: None,
            hit: None,
            bump: None,
            awaiting: false,
            task: Task::None,
            blocked: Vec::new(),
            walk_next: None,
            steps: 0,
            max_steps: u32::MAX,
            contacts: 0,
            progress: Progress::Running,
        }
    }

    /// Starts with `method` for a team of `team` robots; at most
    /// `max_steps` moves (a safety net against a wrong field, not part of
    /// the procedure). The robot stands on its start node and scans it
    /// next ([`Localizer::on_scanned`]).
    pub fn start(&mut self, method: LocalizeMethod, team: u8, max_steps: u32) {
        self.method = Some(method);
        self.max_steps = max_steps;
        if usize::from(team) > MAX_ROBOTS || team == 0 {
            self.fail(Failure::TooManyRobots);
            return;
        }
        self.team = team;
        self.frames = TeamFrames::new(team);
    }

    /// Where localization stands.
    pub fn progress(&self) -> Progress {
        self.progress
    }

    /// The robot's pose in its own frame (after a move: where it drives to).
    pub fn pose(&self) -> Pose {
        Pose {
            pos: self.pos,
            heading: self.heading,
        }
    }

    /// Whether a move is under way.
    pub fn is_driving(&self) -> bool {
        self.driving.is_some()
    }

    /// The arms of the node the robot stands on, its own frame.
    pub fn here(&self) -> Arms {
        self.here
    }

    /// The arms of the start node, its own frame.
    pub fn home_arms(&self) -> Arms {
        self.home_arms
    }

    /// How the team's frames are joined so far.
    pub fn frames(&self) -> &TeamFrames {
        &self.frames
    }

    /// Where robot `id` last said it stands, its own frame.
    pub fn rest(&self, id: RobotId) -> Pose {
        self.rest.get(id.index()).copied().unwrap_or(START)
    }

    /// Moves this robot made.
    pub fn steps(&self) -> u32 {
        self.steps
    }

    /// Contacts this robot has joined (its own and others').
    pub fn contacts(&self) -> u32 {
        self.contacts
    }

    /// The start node's scan: the robot stands at the origin facing north
    /// with `arms` (own frame). It says it is ready.
    pub fn on_scanned(&mut self, arms: Arms, out: &mut Steps) {
        self.here = arms;
        self.home_arms = arms;
        self.say(Localize::Ready, out);
        self.advance(out);
    }

    /// The robot arrived on the next node, whose arms are `arms` (own
    /// frame). `Err` when no move was under way.
    pub fn on_node(&mut self, arms: Arms, out: &mut Steps) -> Result<(), Unexpected> {
        if self.driving.take().is_none() {
            return Err(Unexpected);
        }
        self.here = arms;
        self.arrival = self.heading;
        match self.task {
            Task::Runs { .. } => {
                if self.pos == ORIGIN {
                    self.next_run(out);
                } else {
                    // An empty node: back to the start.
                    self.go(self.heading.opposite(), out);
                }
            }
            Task::Climb => self.climb(out),
            Task::Trace(mut t) => {
                t.moved = true;
                if higher(self.pos, t.top) {
                    t.top = self.pos;
                }
                self.trace_step(t, out);
            }
            Task::ToTop { top } => {
                if self.pos == top {
                    self.climb(out);
                } else {
                    self.walk_on(out);
                }
            }
            Task::Circle(t) => match left_first(self.arrival, self.here) {
                Some((d, _)) if t.closes(self.pos, d) => {
                    self.walk_next = Some(d);
                    self.pass(out);
                }
                Some((d, _)) => self.go(d, out),
                None => self.fail(Failure::Refused),
            },
            Task::None => {}
        }
        self.advance(out);
        Ok(())
    }

    /// The robot touched another robot and is back on the node it left,
    /// facing back. It reports its half of the contact and waits for the
    /// partner's. `Err` when no move was under way.
    pub fn on_collision(&mut self, out: &mut Steps) -> Result<(), Unexpected> {
        let Some(from) = self.driving.take() else {
            return Err(Unexpected);
        };
        self.attempted = self.heading;
        self.pos = from;
        self.heading = self.heading.opposite();
        self.here = self.left_arms;
        self.awaiting = true;
        let pose = Pose {
            pos: from,
            heading: self.attempted,
        };
        self.say(Localize::Collision { pose }, out);
        self.advance(out);
        Ok(())
    }

    /// Standing, the robot saw another robot come from `toward` (own
    /// frame) and turn back: it is the passive partner of the robot whose
    /// turn it is, and reports. `Err` when nobody should be moving.
    pub fn on_bumped(&mut self, toward: Heading, out: &mut Steps) -> Result<(), Unexpected> {
        let Some(by) = self.holder_now().filter(|h| *h != self.me) else {
            return Err(Unexpected);
        };
        if self.driving.is_some() {
            return Err(Unexpected);
        }
        let Some(pos) = self.pos.step(toward) else {
            return Err(Unexpected);
        };
        let seen = Pose {
            pos,
            heading: toward.opposite(),
        };
        self.say(Localize::Bumped { by, seen }, out);
        self.advance(out);
        Ok(())
    }

    /// The body refused an order: the walk's idea of the field is wrong.
    pub fn on_refused(&mut self) {
        if let Some(from) = self.driving.take() {
            self.pos = from;
        }
        self.fail(Failure::Refused);
    }

    /// Robot `from` said `news`.
    pub fn on_news(&mut self, from: RobotId, news: Localize, out: &mut Steps) {
        if from.0 >= self.team.max(MAX_ROBOTS as u8) || from == self.me {
            return;
        }
        self.hear(from, news, out);
        self.advance(out);
    }

    fn say(&mut self, news: Localize, out: &mut Steps) {
        let _ = out.push(Step::Say(news));
        self.hear(self.me, news, out);
    }

    /// Takes one broadcast (ours or a team mate's) into the shared state.
    fn hear(&mut self, from: RobotId, news: Localize, out: &mut Steps) {
        let i = from.index();
        match news {
            Localize::Ready => {
                if let Some(r) = self.ready.get_mut(i) {
                    *r = true;
                }
            }
            Localize::Pass { pose } => self.on_pass(from, pose),
            Localize::Collision { pose } => {
                self.hit = Some((from, pose));
                if let Some(r) = self.rest.get_mut(i) {
                    *r = pose;
                }
            }
            Localize::Bumped { by, seen } => self.bump = Some((from, by, seen)),
            Localize::Finished => {}
        }
        self.join_halves(out);
    }

    fn join_halves(&mut self, out: &mut Steps) {
        let (Some((active, theirs)), Some((passive, by, seen))) = (self.hit, self.bump) else {
            return;
        };
        if by != active {
            return;
        }
        self.hit = None;
        self.bump = None;
        self.contacts = self.contacts.saturating_add(1);
        let met = self.frames.join(Contact {
            active,
            theirs,
            passive,
            seen,
        });
        if met && self.phase == Phase::Circle {
            self.turn_met = Some(passive);
        }
        if active == self.me && self.awaiting {
            self.awaiting = false;
            self.after_contact(out);
        }
    }

    /// The active robot heard its partner: on with the turn.
    fn after_contact(&mut self, out: &mut Steps) {
        if self.frames.joined() {
            // Everyone is placed: nothing left to do in this turn.
            return;
        }
        let blocked = self.pos.step(self.attempted);
        match self.task {
            Task::Runs { .. } => self.next_run(out),
            Task::Climb => {
                self.block(blocked);
                self.begin_trace(out);
            }
            Task::ToTop { .. } => {
                self.block(blocked);
                self.walk_on(out);
            }
            Task::Trace(mut t) => {
                self.block(blocked);
                if t.moved {
                    t.sum = t.sum.saturating_sub(i16::from(t.pending));
                    t.pending = 0;
                    self.trace_step(t, out);
                } else {
                    self.begin_trace(out);
                }
            }
            Task::Circle(_) => {
                self.walk_next = Some(self.attempted);
                self.pass(out);
            }
            Task::None => {}
        }
    }

    /// Moves the shared state on and, when it is this robot's turn,
    /// begins it.
    fn advance(&mut self, out: &mut Steps) {
        if self.method.is_none() || self.phase == Phase::Over {
            return;
        }
        if self.phase == Phase::Gather {
            if !(0..usize::from(self.team)).all(|i| self.ready.get(i).copied().unwrap_or(false)) {
                return;
            }
            self.phase = match self.method {
                Some(LocalizeMethod::Global) => Phase::Border,
                _ => Phase::Runs,
            };
        }
        if self.frames.joined() {
            if self.driving.is_none() && !self.awaiting {
                let to_team = self.frames.to_root(self.me);
                self.phase = Phase::Over;
                self.progress = Progress::Done(to_team);
                self.say(Localize::Finished, out);
            }
            return;
        }
        if self.phase == Phase::Border && self.holder_now().is_none() {
            self.phase = Phase::Circle;
            self.holder = Some(RobotId(0));
            self.fruitless = 0;
            self.turn_met = None;
        }
        if self.phase == Phase::Circle && self.fruitless >= self.frames.groups() {
            self.fail(Failure::NeverMet);
            return;
        }
        let Some(holder) = self.holder_now() else {
            if self.phase == Phase::Runs {
                self.fail(Failure::NotAdjacent);
            }
            return;
        };
        if holder != self.me || self.task != Task::None || self.driving.is_some() || self.awaiting {
            return;
        }
        match self.phase {
            Phase::Runs => {
                self.task = Task::Runs { tried: Arms::NONE };
                self.next_run(out);
            }
            Phase::Border => {
                self.task = Task::Climb;
                self.climb(out);
            }
            Phase::Circle => match self.walk_next {
                Some(d) => {
                    let mut t = Trace::new(self.pos, d);
                    t.moved = true;
                    self.task = Task::Circle(t);
                    self.go(d, out);
                }
                None => self.pass(out),
            },
            Phase::Gather | Phase::Over => {}
        }
    }

    /// Local: the next synchronisation run, or the end of the turn.
    fn next_run(&mut self, out: &mut Steps) {
        let Task::Runs { tried } = self.task else {
            return;
        };
        let me = self.frames.to_root(self.me);
        let known = |d: Heading| {
            ORIGIN.step(d).is_some_and(|q| {
                let q = me.pos(q);
                (0..self.team).any(|j| {
                    let j = RobotId(j);
                    self.frames.root(j) == self.frames.root(self.me)
                        && self.frames.to_root(j).pos(ORIGIN) == q
                })
            })
        };
        let next = self.home_arms.iter().find(|d| !tried.has(*d) && !known(*d));
        match next {
            Some(d) => {
                self.task = Task::Runs {
                    tried: tried.with(d),
                };
                self.go(d, out);
            }
            None => self.pass(out),
        }
    }

    fn pass(&mut self, out: &mut Steps) {
        self.task = Task::None;
        let pose = self.pose();
        self.say(Localize::Pass { pose }, out);
    }

    /// Turns to `h` and drives one edge.
    fn go(&mut self, h: Heading, out: &mut Steps) {
        let Some(next) = self.pos.step(h) else {
            self.fail(Failure::Refused);
            return;
        };
        if self.steps >= self.max_steps {
            self.fail(Failure::StepBudget);
            return;
        }
        self.steps += 1;
        if let Some(t) = self.heading.turn_to(h) {
            let _ = out.push(Step::Turn(t));
            self.heading = h;
        }
        let _ = out.push(Step::Move);
        self.driving = Some(self.pos);
        self.left_arms = self.here;
        self.pos = next;
    }

    fn fail(&mut self, why: Failure) {
        self.phase = Phase::Over;
        self.task = Task::None;
        self.progress = Progress::Failed(why);
    }
}
