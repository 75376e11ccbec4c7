//! The node-level multi-robot exploration model: the true field, robots
//! that drive edge by edge and turn on nodes in the time [`Timing`] says,
//! and one [`Strategy`] deciding for every robot.
//!
//! Why this model: it is the smallest one in which strategies differ the way
//! they differ on the floor (travel *time*, with turns, until the last robot
//! is home) and it is fast enough to compare many strategies on many fields.
//! The full world simulator of a later issue reuses the same [`Strategy`]
//! trait and [`Timing`].
//!
//! Rules of the model:
//! - The robots share one map (perfect relaying of every report).
//! - A robot reports a node the moment it arrives there, then decides.
//! - Moves are a turn on the spot (0, 1 or 2 quarter turns) and one edge.
//! - Robots do not collide (several may share a node or an edge).
//! - Events are processed in time order, ties by robot id: deterministic.
//! - A robot with nothing to do waits, and decides again whenever the map
//!   grows, or when every robot waits and somebody has moved since the
//!   last such moment; the run ends when every robot waits after that.

use core_algo::explore::{Context, Decision, RobotView, Strategy};
use core_algo::geometry::{Arms, Heading, Pos};
use core_algo::map::{Block, Bounds, KnownMap, blocks_for};
use core_algo::path::{DistField, PlanCell, PlanError, min_cells, neighbour_index};
use core_algo::team::RobotId;
use core_algo::timing::{Ticks, Timing};
use std::fmt;

/// The field as it really is, indexed like a [`KnownMap`] over its bounding
/// box.
#[derive(Clone, Debug)]
pub struct Truth {
    bounds: Bounds,
    arms: Vec<Option<Arms>>,
    nodes: usize,
}

impl Truth {
    /// The field of `nodes`, over their bounding box. Arms are taken as
    /// given (the field loader validates reciprocity).
    pub fn new(nodes: impl IntoIterator<Item = (Pos, Arms)>) -> Truth {
        let nodes: Vec<(Pos, Arms)> = nodes.into_iter().collect();
        let bounds = if nodes.is_empty() {
            Bounds::new(Pos::new(0, 0), 0, 0)
        } else {
            crate::field::bounding_box(nodes.iter().map(|(p, _)| *p))
        };
        let mut arms = vec![None; bounds.area()];
        for (p, a) in &nodes {
            if let Some(slot) = bounds.index(*p).and_then(|i| arms.get_mut(i)) {
                *slot = Some(*a);
            }
        }
        Truth {
            bounds,
            arms,
            nodes: nodes.len(),
        }
    }

    /// The bounding box.
    pub fn bounds(&self) -> Bounds {
        self.bounds
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.nodes
    }

    /// Whether the field has no node.
    pub fn is_empty(&self) -> bool {
        self.nodes == 0
    }

    /// The arms of node `i` (storage index), `None` where there is no node.
    pub fn arms_at(&self, i: usize) -> Option<Arms> {
        self.arms.get(i).copied().flatten()
    }

    /// The arms of `p`, `None` where there is no node.
    pub fn arms(&self, p: Pos) -> Option<Arms> {
        self.arms_at(self.bounds.index(p)?)
    }

    /// The storage indices of the nodes.
    pub fn indices(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.arms.len()).filter(|&i| self.arms.get(i).is_some_and(|a| a.is_some()))
    }

    /// The neighbour of node `i` along its arm `h`, if the arm and the node
    /// exist.
    pub fn along(&self, i: usize, h: Heading) -> Option<usize> {
        if !self.arms_at(i)?.has(h) {
            return None;
        }
        let j = neighbour_index(self.bounds, i, h)?;
        self.arms_at(j).map(|_| j)
    }
}

/// The shared map type of the model.
pub type Map = KnownMap<Vec<Block>>;
/// The planner scratch type of the model.
pub type Field = DistField<Vec<PlanCell>>;

/// A strategy the model can run.
pub type DynStrategy = dyn Strategy<Vec<Block>, Vec<PlanCell>> + Send;

/// What went wrong in a run.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum WorldError {
    /// A start is not a node of the field.
    BadStart(Pos),
    /// The planner failed.
    Plan(PlanError),
    /// The strategy sent a robot along an arm that does not exist.
    OffField {
        /// The robot.
        robot: usize,
        /// Where it stood.
        pos: Pos,
        /// Where it was sent.
        heading: Heading,
    },
}

impl fmt::Display for WorldError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            WorldError::BadStart(p) => write!(f, "start {p} is not a node of the field"),
            WorldError::Plan(e) => write!(f, "planner: {e}"),
            WorldError::OffField {
                robot,
                pos,
                heading,
            } => write!(
                f,
                "robot {robot} sent off the field at {pos} towards {heading}"
            ),
        }
    }
}

impl std::error::Error for WorldError {}

impl From<PlanError> for WorldError {
    fn from(e: PlanError) -> Self {
        WorldError::Plan(e)
    }
}

/// How a run went.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RunStats {
    /// Every node's shape known and every robot home.
    pub complete: bool,
    /// Ticks until the last robot was home (its last arrival).
    pub makespan: Ticks,
    /// Edge traversals per robot.
    pub edges: Vec<u32>,
    /// Quarter turns per robot (a U-turn counts two).
    pub turns: Vec<u32>,
    /// Arrivals on nodes that were already visited, all robots.
    pub revisits: u32,
    /// Decisions taken.
    pub decisions: u64,
    /// Nodes that were never visited but are known (deduced).
    pub deduced: usize,
    /// Ticks until the map was complete (no frontier left); the rest of
    /// the makespan is the way home. `None`: it never was.
    pub mapped: Option<Ticks>,
}

impl RunStats {
    /// Edge traversals of the robot that drove most.
    pub fn max_edges(&self) -> u32 {
        self.edges.iter().copied().max().unwrap_or(0)
    }

    /// All edge traversals.
    pub fn moves(&self) -> u64 {
        self.edges.iter().map(|&e| u64::from(e)).sum()
    }

    /// All quarter turns.
    pub fn total_turns(&self) -> u64 {
        self.turns.iter().map(|&e| u64::from(e)).sum()
    }
}

/// Parameters of a run.
#[derive(Clone, Copy, Debug)]
pub struct WorldConfig {
    /// The one truth about timing.
    pub timing: Timing,
    /// Safety net: the run stops (incomplete) after this many decisions per
    /// node and robot.
    pub decisions_per_node: u64,
}

impl Default for WorldConfig {
    fn default() -> Self {
        WorldConfig {
            timing: Timing::DEFAULT,
            decisions_per_node: 40,
        }
    }
}

#[derive(Clone, Copy, Debug)]
struct Bot {
    pos: Pos,
    heading: Heading,
    /// When it stands on `pos` and decides.
    t: Ticks,
    home: Pos,
    target: Option<Pos>,
    waiting: bool,
    arriving: bool,
}

/// Runs `strategy` for robots starting at `starts` on `truth` until every
/// robot waits. Deterministic.
pub fn run<S: Strategy<Vec<Block>, Vec<PlanCell>> + ?Sized>(
    truth: &Truth,
    starts: &[(Pos, Heading)],
    strategy: &mut S,
    config: WorldConfig,
) -> Result<RunStats, WorldError> {
    let bounds = truth.bounds();
    let mut map = KnownMap::new(vec![Block::EMPTY; blocks_for(bounds.area())], bounds)
        .map_err(|_| WorldError::BadStart(Pos::new(0, 0)))?;
    let k = starts.len();
    let mut fields: Vec<Field> = (0..2 * k.max(1))
        .map(|_| DistField::new(vec![PlanCell::EMPTY; min_cells(bounds.area())]))
        .collect();
    let mut bots: Vec<Bot> = Vec::with_capacity(k);
    for &(p, h) in starts {
        if truth.arms(p).is_none() {
            return Err(WorldError::BadStart(p));
        }
        bots.push(Bot {
            pos: p,
            heading: h,
            t: 0,
            home: p,
            target: None,
            waiting: false,
            arriving: true,
        });
    }
    let mut stats = RunStats {
        complete: false,
        makespan: 0,
        edges: vec![0; k],
        turns: vec![0; k],
        revisits: 0,
        decisions: 0,
        deduced: 0,
        mapped: None,
    };
    let limit = config
        .decisions_per_node
        .saturating_mul(truth.len() as u64 + 1)
        .saturating_mul(k as u64 + 1);
    let mut views: Vec<RobotView> = Vec::with_capacity(k);
    let mut clock: Ticks = 0;
    let mut moved = true;
    while stats.decisions < limit {
        let Some(me) = (0..k)
            .filter(|&j| !bots[j].waiting)
            .min_by_key(|&j| (bots[j].t, j))
        else {
            // Everybody waits. If somebody moved since the last such
            // moment, let everybody decide once more (a robot may have
            // stood aside for another that then stood aside too);
            // otherwise the run is over.
            if !moved {
                break;
            }
            moved = false;
            for b in bots.iter_mut() {
                b.waiting = false;
                b.t = clock;
            }
            continue;
        };
        let now = bots[me].t;
        clock = clock.max(now);
        if bots[me].arriving {
            bots[me].arriving = false;
            let p = bots[me].pos;
            let arms = truth.arms(p).ok_or(WorldError::BadStart(p))?;
            let was_visited = map.is_visited(p);
            match map.visit(p, arms, RobotId(me as u8)) {
                Ok(v) if v.first => {
                    for b in bots.iter_mut().filter(|b| b.waiting) {
                        b.waiting = false;
                        b.t = now;
                    }
                }
                _ => {}
            }
            if was_visited {
                stats.revisits += 1;
            }
            if stats.mapped.is_none() && map.is_complete() {
                stats.mapped = Some(now);
            }
        }
        views.clear();
        views.extend(bots.iter().map(|b| RobotView {
            pos: b.pos,
            heading: b.heading,
            eta: b.t.saturating_sub(now),
            home: b.home,
            target: b.target,
        }));
        let ctx = Context {
            map: &map,
            timing: config.timing,
            robots: &views,
            me,
            tree: None,
        };
        let d: Decision = strategy.decide(&ctx, &mut fields)?;
        stats.decisions += 1;
        let bot = &mut bots[me];
        bot.target = d.target();
        match d.next {
            Some(h) => {
                let i = bounds.index(bot.pos).unwrap_or(usize::MAX);
                let Some(j) = truth.along(i, h) else {
                    return Err(WorldError::OffField {
                        robot: me,
                        pos: bot.pos,
                        heading: h,
                    });
                };
                let q = Timing::quarter_turns_between(bot.heading.index(), h.index());
                bot.t = now + config.timing.turn(q) + config.timing.edge;
                bot.pos = bounds.pos(j);
                bot.heading = h;
                bot.arriving = true;
                moved = true;
                stats.edges[me] += 1;
                stats.turns[me] += u32::from(q);
                stats.makespan = stats.makespan.max(bot.t);
            }
            None => bot.waiting = true,
        }
    }
    let all_known = truth
        .indices()
        .all(|i| core_algo::path::arms_at(&map, i).is_some());
    stats.deduced = truth
        .indices()
        .filter(|&i| {
            map.cell_at(i).is_some_and(|c| !c.is_visited())
                && core_algo::path::arms_at(&map, i).is_some()
        })
        .count();
    let all_home = bots.iter().all(|b| b.pos == b.home && b.waiting);
    stats.complete = all_known && all_home;
    Ok(stats)
}

pub mod sample;

#[cfg(test)]
mod tests;
