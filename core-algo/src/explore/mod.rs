//! Where to go next: the seed's layered explorer and its rivals, behind one
//! [`Strategy`] trait so that the simulator, the benchmark and the robot run
//! exactly the same decision code.
//!
//! A robot standing on a node asks its strategy for a [`Decision`]: the goal
//! (a frontier node, home, or nothing) and the heading to leave the node
//! with. Every strategy costs moves with the one [`Timing`] through
//! turn-aware [`DistField`]s, and every strategy sends the robot home when no
//! frontier is reachable from where it stands (the 2010 code stalled there),
//! so exploration always ends.
//!
//! ## Determinism
//!
//! Strategies hold no randomness. Where candidates cost the same, the one
//! with the smaller storage index of the map window wins: the southernmost,
//! then the westernmost node.

use crate::geometry::{Heading, Pos};
use crate::map::{Block, KnownMap};
use crate::path::{DistField, Flow, Forest, PlanCell, PlanError};
use crate::timing::{Ticks, Timing};

mod assign;
mod frontier_floor;
mod layers;
pub mod legacy;
mod minpos;
mod nearest;
mod shared_columns;
mod tempo;
mod workers;

pub use assign::{Assignment, AssignmentObjective, BurgardGreedy};
pub use layers::{CooperationLayer, Layer, ResidualLayer, SeedConfig, SeedExplorer};
pub use legacy::Legacy2010;
pub use minpos::MinPos;
pub use nearest::{GreedyClaim, NearestFrontier};
pub use shared_columns::SharedColumns;
pub use tempo::{Tempo, TempoConfig};
pub use workers::{InOrder, Workers};

/// The largest team a centralised strategy plans for at once. The seed plans
/// for six robots; sixteen lets the simulator run the large-field teams
/// (a 256 × 256 field with 16 robots).
pub const MAX_ROBOTS: usize = 16;

/// What one robot of the team looks like to a deciding robot.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct RobotView {
    /// The node the robot stands on, or is driving to.
    pub pos: Pos,
    /// Its heading there.
    pub heading: Heading,
    /// Ticks until it stands on `pos` (0 when it is there).
    pub eta: Ticks,
    /// Its start node, where it must end.
    pub home: Pos,
    /// The frontier node it last announced as its target, if any.
    pub target: Option<Pos>,
}

/// Everything a strategy may look at: the shared knowledge of the team.
pub struct Context<'a, M> {
    /// The known map (the robots' maps agree in the node-level model).
    pub map: &'a KnownMap<M>,
    /// The one truth about timing.
    pub timing: Timing,
    /// The whole team, indexed by robot id.
    pub robots: &'a [RobotView],
    /// The deciding robot's index in `robots`; it stands on its `pos`.
    pub me: usize,
    /// Travel times read off the known graph where it is a forest (see
    /// [`Forest`]), instead of searched; `None`:
    /// search.
    pub tree: Option<Forest<&'a [PlanCell]>>,
}

impl<M> Context<'_, M> {
    /// The deciding robot.
    pub fn my(&self) -> Option<&RobotView> {
        self.robots.get(self.me)
    }
}

/// Where a decision sends the robot.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Goal {
    /// Explore this frontier node (announced to the team).
    Frontier(Pos),
    /// Drive home: no reachable frontier is left for this robot.
    Home,
    /// At home with nothing reachable to explore: stay.
    Done,
    /// Nothing to do for now while others explore: stay, and decide again
    /// when the map grows.
    Wait,
}

/// A strategy's answer: the goal and the first move towards it.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Decision {
    /// The goal.
    pub goal: Goal,
    /// The heading to leave the current node with (turning first if it
    /// differs from the robot's heading); `None` to stay.
    pub next: Option<Heading>,
}

impl Decision {
    /// Stay where you are.
    pub const STAY: Decision = Decision {
        goal: Goal::Done,
        next: None,
    };

    /// The announced frontier target, if any.
    pub fn target(&self) -> Option<Pos> {
        match self.goal {
            Goal::Frontier(p) => Some(p),
            _ => None,
        }
    }
}

/// A way of choosing targets, compared by the benchmark on one simulator.
///
/// `fields` is planner scratch lent by the caller: decentralised strategies
/// (the seed's, nearest frontier, greedy claim) use one field; centralised
/// ones (assignment, MinPos) want one per robot and fall back to nearest
/// frontier with fewer.
pub trait Strategy<M, F> {
    /// A short stable name for tables and the command line.
    fn name(&self) -> &'static str;

    /// The decision of robot `ctx.me`, which stands on a node.
    fn decide(
        &mut self,
        ctx: &Context<'_, M>,
        fields: &mut [DistField<F>],
    ) -> Result<Decision, PlanError>;
}

/// Runs the field of robot `me` and picks the frontier node with the least
/// `distance + extra(index, pos, distance)`, where `extra` returns `None` to
/// exclude a node. Extras are never negative, so the search stops as soon
/// as the distance alone exceeds the best total found (branch and bound):
/// one partial field per decision, never one search per frontier.
///
/// Ties go to the smaller storage index. Returns the index and total.
pub fn cheapest_frontier<M, F>(
    ctx: &Context<'_, M>,
    field: &mut DistField<F>,
    mut extra: impl FnMut(usize, Pos, Ticks) -> Option<Ticks>,
) -> Result<Option<(usize, Ticks)>, PlanError>
where
    M: AsRef<[Block]> + AsMut<[Block]>,
    F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
{
    let Some(me) = ctx.my() else {
        return Ok(None);
    };
    let map = ctx.map;
    let bounds = map.bounds();
    // Nothing to find: no search (it would also wipe a kept way home).
    if map.is_complete() {
        return Ok(None);
    }
    let mut best: Option<(Ticks, usize)> = None;
    // Once every frontier node is reached there is nothing left to find: late
    // in a run, with a few frontier nodes left, this saves searching the rest
    // of a large map.
    let mut unseen = map.frontier_len();
    field.compute(map, ctx.timing, me.pos, me.heading, |i, d| {
        if best.is_some_and(|(b, _)| d > b) || unseen == 0 {
            return Flow::Stop;
        }
        if map.is_frontier_at(i) {
            unseen -= 1;
            if let Some(x) = extra(i, bounds.pos(i), d) {
                let cand = (d.saturating_add(x), i);
                if best.is_none_or(|b| cand < b) {
                    best = Some(cand);
                }
            }
        }
        if unseen == 0 {
            Flow::Stop
        } else {
            Flow::Continue
        }
    })?;
    Ok(best.map(|(t, i)| (i, t)))
}

/// The decision to explore the frontier node `i` of `field` (computed from
/// the deciding robot's pose).
pub fn explore_decision<M, F>(ctx: &Context<'_, M>, field: &DistField<F>, i: usize) -> Decision
where
    M: AsRef<[Block]> + AsMut<[Block]>,
    F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
{
    let p = ctx.map.bounds().pos(i);
    Decision {
        goal: Goal::Frontier(p),
        next: field.first_heading(ctx.map, i),
    }
}

/// The decision to drive home (or to stay, when home or when home cannot be
/// reached). Used by every strategy once no frontier is reachable.
pub fn go_home<M, F>(ctx: &Context<'_, M>, field: &mut DistField<F>) -> Result<Decision, PlanError>
where
    M: AsRef<[Block]> + AsMut<[Block]>,
    F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
{
    let Some(me) = ctx.my() else {
        return Ok(Decision::STAY);
    };
    if me.pos == me.home {
        return Ok(Decision::STAY);
    }
    let bounds = ctx.map.bounds();
    let (Some(h), Some(at)) = (bounds.index(me.home), bounds.index(me.pos)) else {
        return Ok(Decision::STAY);
    };
    // Once the map is complete the way home never changes: a reverse field
    // rooted at home, searched once and kept, gives it from wherever the
    // robot stands, and team mates predict it from the same field
    // (`path::descent`). A forward field had to be grown again after every
    // step: 13 % of a 16-robot run on open 256².
    if ctx.map.is_complete() {
        if !field.is_reverse_to(ctx.map, ctx.timing, me.home) {
            field.compute_reverse(ctx.map, ctx.timing, me.home, |_, _, _| Flow::Continue)?;
        }
        if let Some(next) = field.way_out(ctx.map, at, me.heading) {
            return Ok(Decision {
                goal: Goal::Home,
                next: Some(next),
            });
        }
    }
    field.compute_to(ctx.map, ctx.timing, me.pos, me.heading, h)?;
    Ok(match field.first_heading(ctx.map, h) {
        Some(next) => Decision {
            goal: Goal::Home,
            next: Some(next),
        },
        None => Decision::STAY,
    })
}

/// Nearest frontier for robot `me`, home when none is reachable: the common
/// fallback.
pub fn nearest_or_home<M, F>(
    ctx: &Context<'_, M>,
    field: &mut DistField<F>,
) -> Result<Decision, PlanError>
where
    M: AsRef<[Block]> + AsMut<[Block]>,
    F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
{
    match cheapest_frontier(ctx, field, |_, _, _| Some(0))? {
        Some((i, _)) => Ok(explore_decision(ctx, field, i)),
        None => go_home(ctx, field),
    }
}

#[cfg(test)]
mod tests;
