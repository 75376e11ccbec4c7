//! Tempo's memory between decisions: see [`Commitment`].

use crate::explore::Context;
use crate::geometry::Heading;
use crate::map::Block;
use crate::path::{WayAhead, neighbour_index};
use crate::timing::Ticks;

/// A robot's share, or its wait, kept while re-assigning could not change
/// it.
///
/// ## Why an unchanged map keeps the assignment optimal
///
/// Let σ be the min-sum assignment when the robot last decided in full,
/// with costs C. Until the map changes, every robot that follows σ has come
/// τ closer to its share, C'(j, σ(j)) = C(j, σ(j)) − τ, and no robot can
/// have come more than τ closer to any node: C'(j, i) ≥ C(j, i) − τ (a robot
/// that waited, τ = 0, not at all). Every assignment serves the same
/// number of robots, so the sum of any other one has fallen by at most as
/// much as σ's: σ is still optimal. Re-solving would only break ties
/// another way, and late in a large run that re-solving was nearly all of
/// the work: on open 256² with 16 robots, 90 % of the decisions with 16 to
/// 31 frontier nodes left saw the same map as the robot's previous one,
/// each searching 16 near-complete fields (docs/results/system.md).
///
/// A robot that got no share and waits stays unassigned the same way: it
/// has not moved, and every robot that did came closer only to its own
/// share. The share, or the wait, is kept only if the robot stands where
/// the last decision left it (a retreat or a bump breaks it) and the team
/// looks the same: the same robots, and the same ones out of reach (failed
/// or unheard).
///
/// A share is also kept, with the map changed, on a corridor node (see
/// `TempoConfig::corridor_keeps_share`): a heuristic, not the argument
/// above, and measured as one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Commitment {
    revision: u32,
    team: usize,
    away: u32,
    /// The node (index) and heading the robot must decide from next.
    pose: (usize, Heading),
    /// The share, or `None` for a wait.
    share: Option<usize>,
    /// The next poses of the way to the share, read off the robot's field
    /// (see [`WayAhead`]).
    ahead: Option<WayAhead>,
}

/// A team mate at least this far off (in ticks) counts as out of reach:
/// the agent gives failed and unheard robots an ETA of a quarter of the
/// tick range.
const AWAY_ETA: Ticks = u32::MAX / 8;

impl Commitment {
    /// Which robots of the team are out of reach, one bit each.
    fn away<M>(ctx: &Context<'_, M>) -> u32 {
        ctx.robots
            .iter()
            .enumerate()
            .filter(|(_, r)| r.eta >= AWAY_ETA)
            .fold(0, |m, (j, _)| m | (1 << (j % 32)))
    }

    /// The commitment of a decision for `share` (or a wait) that leaves the
    /// robot's node with heading `next` (or keeps it standing).
    pub(super) fn after<M>(
        ctx: &Context<'_, M>,
        share: Option<usize>,
        next: Option<Heading>,
    ) -> Option<Commitment>
    where
        M: AsRef<[Block]> + AsMut<[Block]>,
    {
        let bounds = ctx.map.bounds();
        let me = ctx.my()?;
        let at = bounds.index(me.pos)?;
        let pose = match (share, next) {
            (Some(_), Some(h)) => (neighbour_index(bounds, at, h)?, h),
            (None, None) => (at, me.heading),
            _ => return None,
        };
        Some(Commitment {
            revision: ctx.map.revision(),
            team: ctx.robots.len(),
            away: Self::away(ctx),
            pose,
            share,
            ahead: None,
        })
    }

    /// The same, with the poses of the way ahead read off for it.
    pub(super) fn with_ahead(self, ahead: Option<WayAhead>) -> Commitment {
        Commitment { ahead, ..self }
    }

    /// The poses of the way ahead read off for it, if any.
    pub(super) fn ahead(&self) -> Option<WayAhead> {
        self.ahead
    }

    /// The kept share, `None` for a wait.
    pub(super) fn share(&self) -> Option<usize> {
        self.share
    }

    /// Whether this still holds for the robot deciding in `ctx`; a share
    /// (not a wait) survives up to `slack` map changes (0: none, exact),
    /// and any number of them on a corridor node if `corridors` (see
    /// `TempoConfig::corridor_keeps_share`), or while [`keeps_far`] holds
    /// (see `TempoConfig::far_keeps_share`).
    pub(super) fn holds<M>(
        &self,
        ctx: &Context<'_, M>,
        slack: u32,
        corridors: bool,
        far: FarRule,
    ) -> bool
    where
        M: AsRef<[Block]> + AsMut<[Block]>,
    {
        let Some(me) = ctx.my() else { return false };
        let bounds = ctx.map.bounds();
        let changes = ctx.map.revision().wrapping_sub(self.revision);
        let slack = if self.share.is_some() { slack } else { 0 };
        // Two known arms: the only ways on are ahead and back.
        let corridor = || {
            ctx.map
                .known_arms(me.pos)
                .is_some_and(|arms| arms.iter().count() == 2)
        };
        let kept_anyway = match self.share {
            Some(i) => corridors && corridor() || keeps_far(ctx, ctx.me, bounds.pos(i), far),
            None => false,
        };
        (changes <= slack || kept_anyway)
            && self.team == ctx.robots.len()
            && self.away == Self::away(ctx)
            && bounds.index(me.pos) == Some(self.pose.0)
            && me.heading == self.pose.1
            && self.share.is_none_or(|i| ctx.map.is_frontier_at(i))
    }
}

impl Commitment {
    /// The frontier node just ahead, and the heading to it, when the robot
    /// has reached its share and that share turned out to be a corridor
    /// node leading on into the unknown: the way in behind it, one other
    /// arm, and a frontier node at its end that no team mate has
    /// announced (see `TempoConfig::corridor_extends_team`). A heuristic,
    /// like `corridor_keeps_share`: in a corridor the robot can only go on
    /// or turn back, and the node ahead is one edge away from it while
    /// every team mate is farther.
    pub(super) fn onward<M>(&self, ctx: &Context<'_, M>) -> Option<(usize, Heading)>
    where
        M: AsRef<[Block]> + AsMut<[Block]>,
    {
        let me = ctx.my()?;
        let map = ctx.map;
        let bounds = map.bounds();
        let at = bounds.index(me.pos)?;
        let reached = self.share == Some(at) && !map.is_frontier_at(at);
        let followed = self.pose == (at, me.heading)
            && self.team == ctx.robots.len()
            && self.away == Self::away(ctx);
        if !(reached && followed) {
            return None;
        }
        let arms = map.known_arms(me.pos)?;
        let back = me.heading.opposite();
        if arms.count() != 2 || !arms.has(back) {
            return None;
        }
        let ahead = arms.without(back).iter().next()?;
        let next = neighbour_index(bounds, at, ahead)?;
        let p = bounds.pos(next);
        let free = ctx
            .robots
            .iter()
            .enumerate()
            .all(|(j, r)| j == ctx.me || r.target != Some(p));
        (map.is_frontier_at(next) && free).then_some((next, ahead))
    }
}

/// When a robot keeps a far share whatever changed in the map (see
/// [`keeps_far`] and `TempoConfig::far_keeps_share`); the default never.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(super) struct FarRule {
    /// The share lies at least this many edges (Manhattan) away; 0: never.
    pub edges: u32,
    /// n > 0: no other robot stands within 1/n of that distance of the
    /// share (one that could take it over sooner)...
    pub nearer: u32,
    /// ...unless that robot heads for an announced target no farther from
    /// it than the share (busy nearer by).
    pub nearer_busy: bool,
}

/// Whether robot `j` keeps its share `share` whatever changed in the map,
/// as every robot of the team predicts alike from the same views: it is
/// at least `rule.edges` away, no other robot has announced it, and no
/// other robot stands near it as `rule.nearer` and `rule.nearer_busy` say.
/// Robots on a long way to work rarely changed their shares in a fresh
/// decision, yet their fields were the costliest to search
/// (docs/results/performance.md, stop 35).
pub(super) fn keeps_far<M>(
    ctx: &Context<'_, M>,
    j: usize,
    share: crate::geometry::Pos,
    rule: FarRule,
) -> bool
where
    M: AsRef<[Block]> + AsMut<[Block]>,
{
    let Some(r) = ctx.robots.get(j) else {
        return false;
    };
    let d = r.pos.manhattan(share);
    let near = |x: &crate::explore::RobotView| {
        let from = x.pos.manhattan(share);
        rule.nearer > 0
            && rule.nearer.saturating_mul(from) < d
            && !(rule.nearer_busy && x.target.is_some_and(|t| x.pos.manhattan(t) <= from))
    };
    rule.edges > 0
        && d >= rule.edges
        && ctx
            .robots
            .iter()
            .enumerate()
            .filter(|&(o, _)| o != j)
            .all(|(_, x)| x.target != Some(share) && !near(x))
}
