//! Centralised re-assignment of the whole team at every decision: Hungarian
//! min-sum, bottleneck min-max, and Burgard's greedy cost–utility.
//!
//! ## Why few candidates suffice
//!
//! In an optimal one-to-one assignment of k robots, every robot can be given
//! one of its own k cheapest frontier nodes: if it had another, one of its k
//! cheapest is free (only k − 1 others are taken) and swapping to it lowers
//! neither the sum nor the maximum. So the assignment runs on the union of
//! each robot's k cheapest frontier nodes, at most k² columns, in fixed
//! arrays without allocation.

use super::{Context, Decision, MAX_ROBOTS, Strategy, Workers, explore_decision, nearest_or_home};
use crate::map::Block;
use crate::path::{DistField, Flow, Forest, PlanCell, PlanError};
use crate::timing::Ticks;

/// Most candidate frontier nodes an assignment considers.
pub const MAX_CANDIDATES: usize = MAX_ROBOTS * MAX_ROBOTS;

/// A forbidden pair's cost: above any real one, tempo's costs scaled by
/// its tie-break (2^16) included, with room for the Hungarian's sums.
const INF: i64 = 1 << 52;

mod burgard;
mod columns;
mod endgame;
mod hungarian;
mod picks;
pub use burgard::BurgardGreedy;
pub(crate) use hungarian::hungarian_cols;
use hungarian::{hungarian, hungarian_by};
pub(crate) use picks::jumps_pay;
use picks::{FIRST_BUDGET, FIRST_PICKS, PICKS, Picks};

/// The cost matrix of a team against candidate frontier nodes.
pub(crate) struct Candidates {
    pub(crate) k: usize,
    pub(crate) m: usize,
    pub(crate) nodes: [usize; MAX_CANDIDATES],
    pub(crate) cost: [[i64; MAX_CANDIDATES]; MAX_ROBOTS],
    /// Robots left out of the assignment (bit j: robot j): not rows of
    /// the problem at all, so that they take no column and their
    /// potentials prove nothing (see [`Candidates::cheapest`]).
    pub(crate) left_out: u32,
}

/// Whether robot `j` is in a `left_out` mask (bit j: robot j; see
/// [`Candidates::cheapest`]).
pub(crate) fn is_left_out(mask: u32, j: usize) -> bool {
    mask & (1 << (j % 32)) != 0
}

impl Candidates {
    /// No candidates yet for a team of `k`: every pair forbidden.
    pub(crate) fn empty(k: usize) -> Candidates {
        Candidates {
            k,
            m: 0,
            nodes: [0; MAX_CANDIDATES],
            cost: [[INF; MAX_CANDIDATES]; MAX_ROBOTS],
            left_out: 0,
        }
    }

    /// Back to [`Candidates::empty`] in place: a decision reuses one
    /// matrix (34 KiB for 16 robots) rather than building one per round
    /// of picks and moving it out through the returns, copies that were
    /// most of the 7.6 % a 16-robot maze run spent in `memcpy`.
    pub(crate) fn clear(&mut self, k: usize) {
        self.k = k;
        self.m = 0;
        self.nodes.fill(0);
        for row in self.cost.iter_mut() {
            row.fill(INF);
        }
        self.left_out = 0;
    }

    /// The team size, if the team can be planned for: some robots, no more
    /// than [`MAX_ROBOTS`], and a field for each.
    fn team_size<M, F>(ctx: &Context<'_, M>, fields: &[DistField<F>]) -> Option<usize> {
        let k = ctx.robots.len();
        (k > 0 && k <= MAX_ROBOTS && fields.len() >= k).then_some(k)
    }

    /// Computes one full field per robot (`fields[j]` from robot `j`'s pose)
    /// and collects each robot's `per_robot` cheapest frontier nodes. Returns
    /// `None` when there are too few fields or too many robots.
    pub(crate) fn collect<M, F>(
        ctx: &Context<'_, M>,
        fields: &mut [DistField<F>],
        per_robot: usize,
        spread: u32,
    ) -> Result<Option<Candidates>, PlanError>
    where
        M: AsRef<[Block]> + AsMut<[Block]>,
        F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
    {
        let Some(k) = Self::team_size(ctx, fields) else {
            return Ok(None);
        };
        if ctx.map.is_complete() {
            return Ok(Some(Candidates::empty(k)));
        }
        let mut c = Candidates::empty(k);
        let per_robot = per_robot.clamp(1, MAX_CANDIDATES / k);
        for (r, field) in ctx.robots.iter().zip(fields.iter_mut()) {
            let mut found = 0usize;
            let bounds = ctx.map.bounds();
            field.compute(ctx.map, ctx.timing, r.pos, r.heading, |i, _| {
                if ctx.map.is_frontier_at(i) {
                    let taken = c.nodes.get(..c.m).unwrap_or(&[]);
                    if spread > 0 {
                        // One candidate per neighbourhood: robots get
                        // distinct regions, not neighbouring nodes.
                        let p = bounds.pos(i);
                        if taken.iter().any(|&q| bounds.pos(q).manhattan(p) <= spread) {
                            return Flow::Continue;
                        }
                    }
                    found += 1;
                    if !taken.contains(&i) {
                        if let Some(slot) = c.nodes.get_mut(c.m) {
                            *slot = i;
                            c.m += 1;
                        }
                    }
                    if found >= per_robot {
                        return Flow::Stop;
                    }
                }
                Flow::Continue
            })?;
        }
        // Grow every field only until it has reached every candidate.
        let nodes = c.nodes;
        let m = c.m;
        let cands = nodes.get(..m).unwrap_or(&[]);
        for field in fields.iter_mut().take(k) {
            let mut missing = cands
                .iter()
                .filter(|&&i| field.dist_at(i).is_none())
                .count();
            if missing > 0 {
                field.resume(ctx.map, |i, _| {
                    if ctx.map.is_frontier_at(i) && cands.contains(&i) {
                        missing -= 1;
                        if missing == 0 {
                            return Flow::Stop;
                        }
                    }
                    Flow::Continue
                })?;
            }
        }
        for (j, (r, field)) in ctx.robots.iter().zip(fields.iter()).enumerate() {
            for col in 0..c.m {
                let Some(&node) = c.nodes.get(col) else {
                    continue;
                };
                if let (Some(d), Some(row)) = (field.dist_at(node), c.cost.get_mut(j)) {
                    if let Some(x) = row.get_mut(col) {
                        *x = i64::from(d) + i64::from(r.eta);
                    }
                }
            }
        }
        Ok(Some(c))
    }

    /// Collects each robot's cheapest frontier nodes under
    /// `cost(j, node, travel)` (`None` excludes a node), growing robot `j`'s
    /// field only until `floor(j, d)` (no frontier node at travel `d` or
    /// beyond costs less) exceeds its last pick. A robot's row holds its
    /// cost to every column its field reached; columns it never reached are
    /// forbidden to it.
    ///
    /// With `per_robot` = k picks each this loses no optimal assignment: by
    /// the module docs' swap argument, which holds for any cost, some
    /// optimal assignment gives every robot one of its own k cheapest
    /// nodes, and those are all in its row. Unlike [`Candidates::collect`]
    /// no field grows to reach every other robot's candidates, which at 16
    /// robots on a large field meant 16 near-complete searches per decision.
    ///
    /// `lazy` (for the min-sum objective only) starts from fewer picks
    /// and proves the assignment optimal instead: see [`Picks`]. `reverse`
    /// chooses how the endgame finds its costs (see
    /// [`Candidates::endgame`]). Robots in the `left_out` mask (bit j:
    /// robot j) bring no picks and get no column, their fields not
    /// searched, outside the endgame; `cost` must exclude them too, as the
    /// endgame asks it.
    ///
    /// The matrix is written into `c`; `false` when the team cannot be
    /// planned for (no robots, too many, or too few fields). Without
    /// spread, the robots' picks grow side by side on `workers` (see
    /// [`Workers`]); each search writes only its own field and picks.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn cheapest<M, F>(
        ctx: &Context<'_, M>,
        fields: &mut [DistField<F>],
        per_robot: usize,
        spread: u32,
        (lazy, reverse, left_out): (bool, bool, u32),
        cost: impl Fn(usize, usize, Ticks) -> Option<i64> + Sync,
        floor: impl Fn(usize, Ticks) -> i64 + Sync,
        bound: impl FnMut(usize, usize) -> i64,
        (c, workers): (&mut Candidates, &dyn Workers),
    ) -> Result<bool, PlanError>
    where
        M: AsRef<[Block]> + AsMut<[Block]> + Sync,
        F: AsRef<[PlanCell]> + AsMut<[PlanCell]> + Send + 'static,
    {
        let Some(k) = Self::team_size(ctx, fields) else {
            return Ok(false);
        };
        // Nothing to assign: no search (it would also wipe a kept way
        // home, see `go_home`).
        if ctx.map.is_complete() {
            c.clear(k);
            return Ok(true);
        }
        // On a forest (a maze), every robot's time to every frontier node
        // is read off the tree: the same costs the searches find, so the
        // same optimum, which the tie-break (`reverse`) makes the one the
        // lazy picks prove (see `Forest`).
        if let Some(tree) = ctx
            .tree
            .filter(|t| reverse && lazy && spread == 0 && t.holds(ctx.map))
        {
            if Self::from_forest(ctx, &tree, (k, left_out), &cost, c) {
                return Ok(true);
            }
        }
        if spread == 0
            && ctx.map.frontier_len() < per_robot.min(k)
            && Self::endgame(
                ctx,
                fields,
                (lazy, reverse),
                &cost,
                &floor,
                bound,
                (c, workers),
            )?
        {
            return Ok(true);
        }
        let per_robot = per_robot.clamp(1, (MAX_CANDIDATES / k).min(PICKS));
        // Spread makes a robot's picks depend on the robots' before it, so
        // one robot's picks cannot grow alone.
        let lazy = lazy && spread == 0;
        let first = if lazy {
            per_robot.min(FIRST_PICKS)
        } else {
            per_robot
        };
        let budget = if lazy { FIRST_BUDGET } else { usize::MAX };
        let mut picks = [Picks::new(first, budget); MAX_ROBOTS];
        let mut stale = [true; MAX_ROBOTS];
        let out = |j: usize| is_left_out(left_out, j);
        for (j, s) in stale.iter_mut().enumerate() {
            *s = !out(j);
        }
        loop {
            c.clear(k);
            c.left_out = left_out;
            if spread == 0 {
                Picks::grow_all(
                    ctx,
                    fields,
                    (&mut picks, &mut stale),
                    (&cost, &floor),
                    workers,
                )?;
            }
            for (j, (r, field)) in ctx.robots.iter().zip(fields.iter_mut()).enumerate() {
                let (Some(p), Some(s)) = (picks.get_mut(j), stale.get_mut(j)) else {
                    continue;
                };
                if *s {
                    // Spread: the picks depend on those taken before.
                    let taken = c.nodes.get(..c.m).unwrap_or(&[]);
                    p.grow(ctx, field, (j, r), (spread, taken), (&cost, &floor), None)?;
                    *s = false;
                }
                for &(_, i) in p.brought() {
                    if !c.nodes.get(..c.m).unwrap_or(&[]).contains(&i) {
                        if let Some(slot) = c.nodes.get_mut(c.m) {
                            *slot = i;
                            c.m += 1;
                        }
                    }
                }
            }
            for (j, field) in fields.iter().take(k).enumerate() {
                if out(j) {
                    continue;
                }
                for col in 0..c.m {
                    let Some(&node) = c.nodes.get(col) else {
                        continue;
                    };
                    let x = field.dist_at(node).and_then(|d| cost(j, node, d));
                    if let (Some(x), Some(v)) = (x, c.cost.get_mut(j).and_then(|r| r.get_mut(col)))
                    {
                        *v = x.clamp(-INF + 1, INF - 1);
                    }
                }
            }
            if !lazy {
                return Ok(true);
            }
            let (_, u) = hungarian(c, INF - 1);
            let mut grown = false;
            let rows = u.iter().zip(picks.iter_mut()).zip(stale.iter_mut());
            for (j, ((&uj, p), s)) in rows.enumerate().take(k) {
                // A left-out row is all forbidden: its potential proves
                // nothing and it has no field to grow.
                if !out(j) && uj > p.beyond() && p.more(per_robot) {
                    *s = true;
                    grown = true;
                }
            }
            if !grown {
                return Ok(true);
            }
        }
    }

    /// Fills `c` with every frontier node as a column and every robot's
    /// cost for it, its travel read off `tree` (robots in `left_out`
    /// excluded, as `cost` excludes them); `false`, `c` spoilt, where the
    /// tree cannot tell (a robot outside it, more frontier nodes than
    /// columns).
    fn from_forest<M: AsRef<[Block]> + AsMut<[Block]>>(
        ctx: &Context<'_, M>,
        tree: &Forest<&[PlanCell]>,
        (k, left_out): (usize, u32),
        cost: &impl Fn(usize, usize, Ticks) -> Option<i64>,
        c: &mut Candidates,
    ) -> bool {
        let (map, bounds) = (ctx.map, ctx.map.bounds());
        if map.frontier_len() > MAX_CANDIDATES {
            return false;
        }
        let mut starts = [None; MAX_ROBOTS];
        for (j, (r, s)) in ctx.robots.iter().zip(starts.iter_mut()).enumerate().take(k) {
            if is_left_out(left_out, j) {
                continue;
            }
            match bounds.index(r.pos).filter(|&i| tree.holds_start(map, i)) {
                Some(i) => *s = Some((i, r.heading)),
                None => return false,
            }
        }
        c.clear(k);
        c.left_out = left_out;
        for i in map.frontier().filter_map(|p| bounds.index(p)) {
            let col = c.m;
            let Some(slot) = c.nodes.get_mut(col) else {
                return false;
            };
            *slot = i;
            c.m += 1;
            for (j, s) in starts.iter().enumerate().take(k) {
                let x = s
                    .and_then(|s| tree.travel(map, ctx.timing, s, i))
                    .and_then(|d| cost(j, i, d));
                if let (Some(x), Some(v)) = (x, c.cost.get_mut(j).and_then(|r| r.get_mut(col))) {
                    *v = x.clamp(-INF + 1, INF - 1);
                }
            }
        }
        true
    }

    /// Adds `x` to the cost of robot `j` for column `col` (forbidden pairs
    /// stay forbidden).
    pub(crate) fn add(&mut self, j: usize, col: usize, x: i64) {
        if let Some(v) = self.cost.get_mut(j).and_then(|r| r.get_mut(col)) {
            if *v < INF {
                *v = (*v + x).min(INF);
            }
        }
    }

    /// Forbids robot `j` column `col`.
    pub(crate) fn forbid(&mut self, j: usize, col: usize) {
        if let Some(v) = self.cost.get_mut(j).and_then(|r| r.get_mut(col)) {
            *v = INF;
        }
    }

    fn at(&self, j: usize, col: usize) -> i64 {
        self.cost
            .get(j)
            .and_then(|r| r.get(col))
            .copied()
            .unwrap_or(INF)
    }
}

/// What an [`Assignment`] minimises.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum AssignmentObjective {
    /// The sum of the robots' travel times (Hungarian).
    MinSum,
    /// The largest travel time, then the sum (bottleneck assignment).
    MinMax,
}

/// Re-assigns every robot at every decision (Hungarian or bottleneck) and
/// sends the deciding robot to its share. Robots left without a candidate
/// take their nearest frontier node.
#[derive(Clone, Copy, Debug)]
pub struct Assignment {
    /// The objective.
    pub objective: AssignmentObjective,
}

impl Assignment {
    /// The assigned frontier node of every robot, from fields computed for
    /// the whole team (`fields[j]` holds robot `j`'s field afterwards).
    pub(crate) fn assign<M, F>(
        objective: AssignmentObjective,
        ctx: &Context<'_, M>,
        fields: &mut [DistField<F>],
    ) -> Result<Option<[Option<usize>; MAX_ROBOTS]>, PlanError>
    where
        M: AsRef<[Block]> + AsMut<[Block]>,
        F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
    {
        let k = ctx.robots.len();
        let Some(c) = Candidates::collect(ctx, fields, k, 0)? else {
            return Ok(None);
        };
        if c.m == 0 {
            return Ok(Some([None; MAX_ROBOTS]));
        }
        let cols = hungarian_cols(&c, objective);
        let mut out = [None; MAX_ROBOTS];
        for (o, col) in out.iter_mut().zip(cols.iter()) {
            *o = col.and_then(|x| c.nodes.get(x).copied());
        }
        Ok(Some(out))
    }
}

impl<M, F> Strategy<M, F> for Assignment
where
    M: AsRef<[Block]> + AsMut<[Block]>,
    F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
{
    fn name(&self) -> &'static str {
        match self.objective {
            AssignmentObjective::MinSum => "hungarian",
            AssignmentObjective::MinMax => "bottleneck",
        }
    }

    fn decide(
        &mut self,
        ctx: &Context<'_, M>,
        fields: &mut [DistField<F>],
    ) -> Result<Decision, PlanError> {
        let me = ctx.me;
        match Self::assign(self.objective, ctx, fields)? {
            Some(a) => match (a.get(me).copied().flatten(), fields.get_mut(me)) {
                (Some(i), Some(f)) => Ok(explore_decision(ctx, f, i)),
                (None, Some(f)) => nearest_or_home(ctx, f),
                (_, None) => Ok(Decision::STAY),
            },
            None => match fields.first_mut() {
                Some(f) => nearest_or_home(ctx, f),
                None => Ok(Decision::STAY),
            },
        }
    }
}

#[cfg(test)]
mod tests;
