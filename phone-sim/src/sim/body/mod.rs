//! Robot bodies on the true field: node-level kinematics with the robot's
//! real timing, and the collisions the firmware would report.
//!
//! A body stands on a node, turns on the spot, or drives one edge. Orders
//! queue and run one after another. Times come from the one [`Timing`] of
//! core-algo, so the planner's costs are the simulator's costs.
//!
//! **The midpoint rule.** Every living body *holds* exactly one node: the
//! node it stands or turns on; while it drives, the node it left up to the
//! middle of the edge and the node ahead after it; while it turns back, the
//! node it returns to. At the middle of an edge a body looks ahead (with
//! nodes 100 mm apart and an e-puck 70 mm wide, a robot on the next node is
//! well inside its proximity sensors' range by then): if another body holds
//! the node ahead it turns back, else it takes the node ahead. So no two
//! bodies ever hold one node, and no two bodies ever stand on one node.
//! (Deciding only on arrival, as this module once did, let a body that
//! turned back find its node taken by another: two bodies on one node.)
//!
//! Collisions (what the e-puck's proximity layer does: stop, report,
//! return to the node it left):
//! - **Ahead is taken**: a body turns back at the middle of its edge, drives
//!   back to the node it left and reports a collision there. A body
//!   standing on the node ahead feels it coming (a bump on the side it came
//!   from).
//! - **Head-on**: two bodies driving one edge towards each other both hold
//!   their own end until the middle, so both turn back there.
//! - A dead robot is lifted off the field and blocks nobody.
//! - **No line**: a move along an arm the node does not have finds no line:
//!   the body stays and reports an abyss (the field's border).

use core_algo::geometry::{Arms, Heading, Pos, Turn};
use core_algo::team::RobotId;
use core_algo::timing::{TICK_MS, Timing};
use std::collections::{BTreeMap, VecDeque};

pub use core_algo::agent::body::{Order, Report};

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Action {
    Idle,
    Turning {
        until: u32,
    },
    Scanning {
        until: u32,
    },
    /// Driving `from` → `to`; holds `to` once `past_middle`.
    Driving {
        from: Pos,
        to: Pos,
        depart: u32,
        arrive: u32,
        past_middle: bool,
    },
    /// Driving back to `to` after turning at time `turned`, a fraction
    /// `turned_at` (in thousandths) of the way towards `away`.
    Returning {
        to: Pos,
        away: Pos,
        turned: u32,
        turned_at: u32,
        arrive: u32,
    },
}

/// Counters of one body.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct BodyStats {
    /// Edges driven to the end.
    pub edges: u32,
    /// Quarter turns made.
    pub quarter_turns: u32,
    /// Collisions reported.
    pub collisions: u32,
    /// Arrivals at a node this body had already visited.
    pub revisits: u32,
    /// Moves ordered along an arm the node does not have.
    pub abysses: u32,
}

/// One robot's body.
#[derive(Clone, Debug)]
pub struct Body {
    /// Node it stands on (or last stood on while driving).
    pub pos: Pos,
    /// The way it faces.
    pub heading: Heading,
    action: Action,
    queue: VecDeque<Order>,
    alive: bool,
    stalled_until: u32,
    /// Counters.
    pub stats: BodyStats,
    visited: std::collections::HashSet<Pos>,
    /// Its own timing when a person set its speed apart from the team's.
    own_timing: Option<Timing>,
}

impl Body {
    /// Whether it is idle on a node with nothing queued.
    pub fn is_idle(&self) -> bool {
        self.action == Action::Idle && self.queue.is_empty()
    }

    /// Whether it still works.
    pub fn is_alive(&self) -> bool {
        self.alive
    }

    /// Where it is in between nodes, as (from, to, fraction 0..=1) at `now`.
    pub fn between(&self, now: u32) -> Option<(Pos, Pos, f64)> {
        match self.action {
            Action::Driving {
                from,
                to,
                depart,
                arrive,
                ..
            } => {
                let f = f64::from(now.saturating_sub(depart))
                    / f64::from(arrive.saturating_sub(depart).max(1));
                Some((from, to, f.clamp(0.0, 1.0)))
            }
            Action::Returning {
                to,
                away,
                turned,
                turned_at,
                arrive,
            } => {
                let left = f64::from(arrive.saturating_sub(now))
                    / f64::from(arrive.saturating_sub(turned).max(1));
                let f = f64::from(turned_at) / 1000.0 * left;
                Some((to, away, f.clamp(0.0, 1.0)))
            }
            _ => None,
        }
    }

    /// The node this body holds (see the module docs): no other body may
    /// stand on it or take it at the middle of an edge.
    fn held(&self) -> Option<Pos> {
        match self.action {
            _ if !self.alive => None,
            Action::Idle | Action::Turning { .. } | Action::Scanning { .. } => Some(self.pos),
            Action::Driving {
                from,
                to,
                past_middle,
                ..
            } => Some(if past_middle { to } else { from }),
            Action::Returning { to, .. } => Some(to),
        }
    }

    /// When its current action next needs the simulator: its end, or the
    /// middle of an edge.
    fn due(&self) -> Option<u32> {
        match self.action {
            Action::Idle if !self.queue.is_empty() => Some(self.stalled_until),
            Action::Idle => None,
            Action::Turning { until } | Action::Scanning { until } => Some(until),
            Action::Driving {
                depart,
                arrive,
                past_middle: false,
                ..
            } => Some(depart + (arrive - depart) / 2),
            Action::Driving { arrive, .. } | Action::Returning { arrive, .. } => Some(arrive),
        }
    }
}

/// The heading from `a` to its lattice neighbour `b`.
fn from_heading(a: Pos, b: Pos) -> Option<Heading> {
    Heading::ALL.into_iter().find(|h| a.step(*h) == Some(b))
}

/// All bodies on the true field.
#[derive(Clone, Debug)]
pub struct Bodies {
    truth: BTreeMap<Pos, Arms>,
    timing: Timing,
    spacing_mm: u32,
    bodies: Vec<Body>,
}

impl Bodies {
    /// Bodies at `starts` on the field `truth`, moving with `timing`.
    pub fn new(truth: BTreeMap<Pos, Arms>, timing: Timing, starts: &[(Pos, Heading)]) -> Self {
        let bodies = starts
            .iter()
            .map(|&(pos, heading)| Body {
                pos,
                heading,
                action: Action::Idle,
                queue: VecDeque::new(),
                alive: true,
                stalled_until: 0,
                stats: BodyStats::default(),
                visited: [pos].into_iter().collect(),
                own_timing: None,
            })
            .collect();
        Bodies {
            truth,
            timing,
            spacing_mm: core_algo::timing::DEFAULT_NODE_SPACING_MM,
            bodies,
        }
    }

    /// The same bodies on a field whose nodes are `spacing_mm` apart (what
    /// a speed order needs to compute its timing).
    pub fn with_spacing_mm(mut self, spacing_mm: u32) -> Self {
        self.spacing_mm = spacing_mm;
        self
    }

    /// The bodies, indexed by robot id.
    pub fn bodies(&self) -> &[Body] {
        &self.bodies
    }

    /// The timing in use.
    pub fn timing(&self) -> Timing {
        self.timing
    }

    /// Changes the timing (a new speed) for actions that start from now on.
    pub fn set_timing(&mut self, timing: Timing) {
        self.timing = timing;
    }

    /// Gives robot `id` its own timing (a person set its speed) for actions
    /// that start from now on; `None` returns it to the team's.
    pub fn set_robot_timing(&mut self, id: RobotId, timing: Option<Timing>) {
        if let Some(b) = self.bodies.get_mut(id.index()) {
            b.own_timing = timing;
        }
    }

    /// The timing robot `i` moves with.
    fn timing_of(&self, i: usize) -> Timing {
        self.bodies
            .get(i)
            .and_then(|b| b.own_timing)
            .unwrap_or(self.timing)
    }

    /// The true arms of `p`.
    pub fn truth(&self, p: Pos) -> Option<Arms> {
        self.truth.get(&p).copied()
    }

    /// The body stops working. A person lifts a dead robot off the field,
    /// so it no longer blocks anyone.
    pub fn kill(&mut self, id: RobotId) {
        if let Some(b) = self.bodies.get_mut(id.index()) {
            b.alive = false;
            b.queue.clear();
        }
    }

    /// The body starts nothing new before `until`.
    pub fn stall(&mut self, id: RobotId, until: u32) {
        if let Some(b) = self.bodies.get_mut(id.index()) {
            b.stalled_until = b.stalled_until.max(until);
        }
    }

    /// Queues an order; it starts at once if the body is idle.
    pub fn order(
        &mut self,
        id: RobotId,
        order: Order,
        now: u32,
        reports: &mut Vec<(RobotId, Report)>,
    ) {
        let Some(b) = self.bodies.get_mut(id.index()) else {
            return;
        };
        if !b.alive {
            return;
        }
        if let Order::SetSpeed(steps) = order {
            b.own_timing = Some(Timing::from_hardware(
                self.spacing_mm,
                u32::from(steps).clamp(1, 2000),
            ));
            return;
        }
        b.queue.push_back(order);
        self.start_next(id.index(), now, reports);
    }

    /// The time of the next action to end, if any.
    pub fn next_event(&self) -> Option<u32> {
        self.bodies
            .iter()
            .filter(|b| b.alive)
            .filter_map(Body::due)
            .min()
    }

    /// Ends every action due by `now`, in (time, robot id) order, and
    /// collects the sensors' reports.
    pub fn advance(&mut self, now: u32, reports: &mut Vec<(RobotId, Report)>) {
        loop {
            let due = self
                .bodies
                .iter()
                .enumerate()
                .filter(|(_, b)| b.alive)
                .filter_map(|(i, b)| b.due().filter(|&t| t <= now).map(|t| (t, i)))
                .min();
            let Some((t, i)) = due else { break };
            self.finish(i, t, reports);
        }
    }

    fn finish(&mut self, i: usize, t: u32, reports: &mut Vec<(RobotId, Report)>) {
        let id = RobotId(i as u8);
        let Some(action) = self.bodies.get(i).map(|b| b.action) else {
            return;
        };
        match action {
            Action::Idle => {}
            Action::Turning { .. } => {
                if let Some(b) = self.bodies.get_mut(i) {
                    b.action = Action::Idle;
                }
            }
            Action::Scanning { .. } => {
                if let Some(b) = self.bodies.get_mut(i) {
                    b.action = Action::Idle;
                    let arms = self.truth.get(&b.pos).copied().unwrap_or_default();
                    reports.push((
                        id,
                        Report::NodeHit {
                            relative: arms.to_relative(b.heading),
                        },
                    ));
                }
            }
            Action::Driving {
                from,
                to,
                depart,
                arrive,
                past_middle: false,
            } => {
                // The middle of the edge: look ahead.
                let blocker = self
                    .bodies
                    .iter()
                    .enumerate()
                    .find(|(j, o)| *j != i && o.held() == Some(to))
                    .map(|(j, o)| (j, o.is_idle(), o.heading));
                if let (Some((j, true, facing)), Some(toward)) = (blocker, from_heading(to, from)) {
                    let side = Heading::from_index(toward.index() + 4 - facing.index());
                    reports.push((RobotId(j as u8), Report::Bumped { side }));
                }
                if let Some(b) = self.bodies.get_mut(i) {
                    if blocker.is_some() {
                        let span = arrive.saturating_sub(depart).max(1);
                        let done = t.saturating_sub(depart);
                        b.heading = b.heading.opposite();
                        b.action = Action::Returning {
                            to: from,
                            away: to,
                            turned: t,
                            turned_at: done * 1000 / span,
                            arrive: t + done,
                        };
                    } else {
                        b.action = Action::Driving {
                            from,
                            to,
                            depart,
                            arrive,
                            past_middle: true,
                        };
                    }
                }
            }
            Action::Driving { to, .. } => {
                if let Some(b) = self.bodies.get_mut(i) {
                    b.pos = to;
                    b.action = Action::Idle;
                    b.stats.edges += 1;
                    if !b.visited.insert(to) {
                        b.stats.revisits += 1;
                    }
                    let arms = self.truth.get(&to).copied().unwrap_or_default();
                    reports.push((
                        id,
                        Report::NodeHit {
                            relative: arms.to_relative(b.heading),
                        },
                    ));
                }
            }
            Action::Returning { to, .. } => {
                if let Some(b) = self.bodies.get_mut(i) {
                    b.pos = to;
                    b.action = Action::Idle;
                    b.stats.collisions += 1;
                    b.queue.clear();
                    reports.push((id, Report::Collision));
                }
            }
        }
        self.start_next(i, t, reports);
    }

    fn edge_ms(&self, i: usize) -> u32 {
        self.timing_of(i).edge * TICK_MS
    }

    fn start_next(&mut self, i: usize, now: u32, reports: &mut Vec<(RobotId, Report)>) {
        let edge = self.edge_ms(i);
        let quarter = self.timing_of(i).quarter_turn * TICK_MS;
        let Some(b) = self.bodies.get(i) else { return };
        if b.action != Action::Idle || !b.alive || b.stalled_until > now {
            return;
        }
        let (pos, heading) = (b.pos, b.heading);
        let Some(order) = self.bodies.get_mut(i).and_then(|b| b.queue.pop_front()) else {
            return;
        };
        match order {
            Order::Turn(t) => {
                if let Some(b) = self.bodies.get_mut(i) {
                    b.heading = heading.turned(t);
                    let q = if t == Turn::UTurn { 2 } else { 1 };
                    b.stats.quarter_turns += q;
                    b.action = Action::Turning {
                        until: now + quarter * q,
                    };
                }
            }
            // Never queued (see `order`).
            Order::SetSpeed(_) => {}
            Order::Scan => {
                if let Some(b) = self.bodies.get_mut(i) {
                    b.stats.quarter_turns += 4;
                    b.action = Action::Scanning {
                        until: now + quarter * 4,
                    };
                }
            }
            Order::Move => {
                let arms = self.truth.get(&pos).copied().unwrap_or_default();
                let Some(to) = pos.step(heading).filter(|_| arms.has(heading)) else {
                    if let Some(b) = self.bodies.get_mut(i) {
                        b.queue.clear();
                        b.stats.abysses += 1;
                    }
                    reports.push((RobotId(i as u8), Report::Abyss));
                    return;
                };
                if let Some(b) = self.bodies.get_mut(i) {
                    b.action = Action::Driving {
                        from: pos,
                        to,
                        depart: now,
                        arrive: now + edge,
                        past_middle: false,
                    };
                }
            }
        }
    }
}

#[cfg(test)]
mod tests;
