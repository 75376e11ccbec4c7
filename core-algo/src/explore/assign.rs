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

use super::layers::CooperationLayer;
use super::{Context, Decision, MAX_ROBOTS, Strategy, explore_decision, go_home, nearest_or_home};
use crate::geometry::Pos;
use crate::map::Block;
use crate::path::{DistField, Flow, PlanCell, PlanError, arms_at};
use crate::timing::Ticks;

/// Most candidate frontier nodes an assignment considers.
pub const MAX_CANDIDATES: usize = MAX_ROBOTS * MAX_ROBOTS;

const INF: i64 = 1 << 40;

mod picks;
use picks::{FIRST_PICKS, PICKS, Picks};

/// The cost matrix of a team against candidate frontier nodes.
pub(crate) struct Candidates {
    pub(crate) k: usize,
    pub(crate) m: usize,
    pub(crate) nodes: [usize; MAX_CANDIDATES],
    pub(crate) cost: [[i64; MAX_CANDIDATES]; MAX_ROBOTS],
}

impl Candidates {
    /// No candidates yet for a team of `k`: every pair forbidden.
    pub(crate) fn empty(k: usize) -> Candidates {
        Candidates {
            k,
            m: 0,
            nodes: [0; MAX_CANDIDATES],
            cost: [[INF; MAX_CANDIDATES]; MAX_ROBOTS],
        }
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
    /// and proves the assignment optimal instead: see [`Picks`].
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn cheapest<M, F>(
        ctx: &Context<'_, M>,
        fields: &mut [DistField<F>],
        per_robot: usize,
        spread: u32,
        lazy: bool,
        mut cost: impl FnMut(usize, usize, Ticks) -> Option<i64>,
        mut floor: impl FnMut(usize, Ticks) -> i64,
        bound: impl FnMut(usize, usize) -> i64,
    ) -> Result<Option<Candidates>, PlanError>
    where
        M: AsRef<[Block]> + AsMut<[Block]>,
        F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
    {
        let Some(k) = Self::team_size(ctx, fields) else {
            return Ok(None);
        };
        // Nothing to assign: no search (it would also wipe a kept way
        // home, see `go_home`).
        if ctx.map.is_complete() {
            return Ok(Some(Candidates::empty(k)));
        }
        if spread == 0 && ctx.map.frontier_len() < per_robot.min(k) {
            if let Some(c) = Self::endgame(ctx, fields, &mut cost, &mut floor, bound)? {
                return Ok(Some(c));
            }
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
        let mut picks = [Picks::new(first); MAX_ROBOTS];
        let mut stale = [true; MAX_ROBOTS];
        loop {
            let mut c = Candidates::empty(k);
            for (j, (r, field)) in ctx.robots.iter().zip(fields.iter_mut()).enumerate() {
                let (Some(p), Some(s)) = (picks.get_mut(j), stale.get_mut(j)) else {
                    continue;
                };
                if *s {
                    let taken = c.nodes.get(..c.m).unwrap_or(&[]);
                    p.grow(ctx, field, (j, r), (spread, taken), &mut cost, &mut floor)?;
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
                return Ok(Some(c));
            }
            let (_, u) = hungarian(&c, INF - 1);
            let mut grown = false;
            for ((&uj, p), s) in u.iter().zip(picks.iter_mut()).zip(stale.iter_mut()).take(k) {
                if uj > p.beyond() && p.more(per_robot) {
                    *s = true;
                    grown = true;
                }
            }
            if !grown {
                return Ok(Some(c));
            }
        }
    }

    /// [`Candidates::cheapest`] once fewer frontier nodes than robots are
    /// left: then every robot's k cheapest are all of them, and every
    /// field would have to reach the farthest (most of a large map, for
    /// each of 16 robots at every decision: three quarters of a 16-robot
    /// run's searching). The swap argument runs the other way instead:
    /// with m frontier nodes, some optimal assignment gives each node one
    /// of its own m cheapest robots (at most m − 1 of those are busy
    /// elsewhere, so one is free to take it). So the deciding robot's field
    /// finds the m nodes, and another robot's field is grown only if
    /// `bound(j, node)`, a lower bound of its cost for the node, could beat
    /// the m-th cheapest robot found for some node so far, and only as far
    /// as that could still happen. Rows of robots never searched are
    /// forbidden. `None` when the deciding robot cannot reach every
    /// frontier node (team mates in another part of the graph might): then
    /// the nodes it finds are not all the columns.
    fn endgame<M, F>(
        ctx: &Context<'_, M>,
        fields: &mut [DistField<F>],
        mut cost: impl FnMut(usize, usize, Ticks) -> Option<i64>,
        mut floor: impl FnMut(usize, Ticks) -> i64,
        mut bound: impl FnMut(usize, usize) -> i64,
    ) -> Result<Option<Candidates>, PlanError>
    where
        M: AsRef<[Block]> + AsMut<[Block]>,
        F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
    {
        let (map, k, me) = (ctx.map, ctx.robots.len(), ctx.me);
        let mut c = Candidates::empty(k);
        let (Some(r), Some(field)) = (ctx.robots.get(me), fields.get_mut(me)) else {
            return Ok(None);
        };
        let mut unseen = map.frontier_len();
        field.compute(map, ctx.timing, r.pos, r.heading, |i, _| {
            if map.is_frontier_at(i) {
                unseen = unseen.saturating_sub(1);
                if let Some(slot) = c.nodes.get_mut(c.m) {
                    *slot = i;
                    c.m += 1;
                }
            }
            if unseen == 0 {
                Flow::Stop
            } else {
                Flow::Continue
            }
        })?;
        if unseen > 0 {
            return Ok(None);
        }
        let m = c.m;
        // A second lower bound, from every field searched so far (see
        // `learn`): ours first, then each team mate's as it is grown. In a
        // maze, where Manhattan distance says little, it spares growing the
        // fields of team mates that stand behind one already searched, no
        // nearer the frontier (maze 64², 16 robots: 7.8 → 4.7 team mates'
        // fields per decision).
        let mut near = [[i64::MIN; MAX_ROBOTS]; MAX_ROBOTS];
        let u_turn = 2 * field.timing().quarter_turn;
        learn(&mut near, ctx, &c, field, u_turn, &mut cost);
        let mut bound =
            |near: &[[i64; MAX_ROBOTS]; MAX_ROBOTS], j: usize, col: usize, node: usize| {
                let by_field = near.get(j).and_then(|r| r.get(col)).copied();
                bound(j, node).max(by_field.unwrap_or(i64::MIN))
            };
        let mut searched = [false; MAX_ROBOTS];
        let fill = |c: &mut Candidates,
                    j: usize,
                    field: &DistField<F>,
                    cost: &mut dyn FnMut(usize, usize, Ticks) -> Option<i64>| {
            for col in 0..m {
                let node = c.nodes.get(col).copied().unwrap_or(usize::MAX);
                if let (Some(x), Some(v)) = (
                    field.dist_at(node).and_then(|d| cost(j, node, d)),
                    c.cost.get_mut(j).and_then(|row| row.get_mut(col)),
                ) {
                    *v = x.clamp(-INF + 1, INF - 1);
                }
            }
        };
        if let (Some(s), Some(field)) = (searched.get_mut(me), fields.get(me)) {
            *s = true;
            fill(&mut c, me, field, &mut cost);
        }
        if m == 0 {
            return Ok(Some(c));
        }
        // The m-th cheapest searched robot of column `col`: a robot that
        // cannot beat it is not needed there.
        let threshold = |c: &Candidates, col: usize| -> i64 {
            let mut best = [INF; MAX_ROBOTS];
            for (j, b) in best.iter_mut().enumerate().take(k) {
                *b = c.at(j, col);
            }
            let row = best.get_mut(..k).unwrap_or(&mut []);
            row.sort_unstable();
            row.get(m - 1).copied().unwrap_or(INF)
        };
        // The other robots, likeliest to matter first.
        let mut order = [(0i64, 0usize); MAX_ROBOTS];
        for (j, o) in order.iter_mut().enumerate().take(k) {
            let nearest = (0..m)
                .filter_map(|col| c.nodes.get(col).map(|&node| bound(&near, j, col, node)))
                .min()
                .unwrap_or(INF);
            *o = (nearest, j);
        }
        let order = order.get_mut(..k).unwrap_or(&mut []);
        order.sort_unstable();
        for &(_, j) in order.iter() {
            if searched.get(j).copied().unwrap_or(true) {
                continue;
            }
            // How far this robot's costs could matter, if anywhere.
            let mut limit: Option<i64> = None;
            for col in 0..m {
                let node = c.nodes.get(col).copied().unwrap_or(usize::MAX);
                let t = threshold(&c, col);
                if bound(&near, j, col, node) < t {
                    limit = Some(limit.map_or(t, |l: i64| l.max(t)));
                }
            }
            let (Some(limit), Some(r), Some(field)) = (limit, ctx.robots.get(j), fields.get_mut(j))
            else {
                continue;
            };
            let nodes = c.nodes;
            let cols = nodes.get(..m).unwrap_or(&[]);
            let mut missing = m;
            field.compute(map, ctx.timing, r.pos, r.heading, |i, d| {
                if floor(j, d) >= limit {
                    return Flow::Stop;
                }
                if map.is_frontier_at(i) && cols.contains(&i) {
                    missing -= 1;
                    if missing == 0 {
                        return Flow::Stop;
                    }
                }
                Flow::Continue
            })?;
            if let Some(s) = searched.get_mut(j) {
                *s = true;
            }
            fill(&mut c, j, field, &mut cost);
            learn(&mut near, ctx, &c, field, u_turn, &mut cost);
        }
        Ok(Some(c))
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

/// Raises `near[j][col]`, a lower bound of robot `j`'s cost for column
/// `col`, with what `field` (a search from any pose) proves: a robot
/// standing on a node the field reached at `at` is at least
/// `d(node) − at − U-turn` of travel from a column node it reached at
/// `d(node)`, or the field's robot could drive there through its node.
fn learn<M, F>(
    near: &mut [[i64; MAX_ROBOTS]; MAX_ROBOTS],
    ctx: &Context<'_, M>,
    c: &Candidates,
    field: &DistField<F>,
    u_turn: Ticks,
    cost: &mut dyn FnMut(usize, usize, Ticks) -> Option<i64>,
) where
    M: AsRef<[Block]> + AsMut<[Block]>,
    F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
{
    let map = ctx.map;
    for (j, row) in near.iter_mut().enumerate().take(c.k) {
        let at = ctx.robots.get(j).and_then(|q| {
            let i = map.bounds().index(q.pos)?;
            arms_at(map, i)?;
            field.dist_at(i)
        });
        let Some(at) = at else { continue };
        for (col, lb) in row.iter_mut().enumerate().take(c.m) {
            let node = c.nodes.get(col).copied().unwrap_or(usize::MAX);
            if let Some(d) = field.dist_at(node) {
                let least = d.saturating_sub(at).saturating_sub(u_turn);
                if let Some(x) = cost(j, node, least) {
                    *lb = (*lb).max(x);
                }
            }
        }
    }
}

/// Min-sum assignment of `k` rows to `m ≥ k` columns of `cost` (capped at
/// `cap`: costlier pairs count as forbidden): the Hungarian algorithm with
/// potentials, O(k²·m). Returns the column of each row, `None` where only a
/// forbidden pair was left, and each row's potential `u` (see [`Picks`]).
fn hungarian(c: &Candidates, cap: i64) -> ([Option<usize>; MAX_ROBOTS], [i64; MAX_ROBOTS]) {
    let (n, m) = (c.k, c.m.max(c.k));
    // 1-based arrays as in the textbook form; column 0 is the virtual one.
    let mut u = [0i64; MAX_ROBOTS + 1];
    let mut v = [0i64; MAX_CANDIDATES + MAX_ROBOTS + 1];
    let mut p = [0usize; MAX_CANDIDATES + MAX_ROBOTS + 1];
    let mut way = [0usize; MAX_CANDIDATES + MAX_ROBOTS + 1];
    let cost = |i: usize, j: usize| -> i64 {
        if j > c.m {
            // Dummy columns when there are fewer candidates than robots.
            return INF;
        }
        let x = c.at(i - 1, j - 1);
        if x > cap { INF } else { x }
    };
    let get = |a: &[i64], i: usize| a.get(i).copied().unwrap_or(0);
    for i in 1..=n {
        if let Some(x) = p.get_mut(0) {
            *x = i;
        }
        let mut j0 = 0usize;
        let mut minv = [INF * 4; MAX_CANDIDATES + MAX_ROBOTS + 1];
        let mut used = [false; MAX_CANDIDATES + MAX_ROBOTS + 1];
        for _ in 0..=m {
            if let Some(x) = used.get_mut(j0) {
                *x = true;
            }
            let i0 = p.get(j0).copied().unwrap_or(0);
            let mut delta = INF * 4;
            let mut j1 = 0usize;
            for j in 1..=m {
                if used.get(j).copied().unwrap_or(true) {
                    continue;
                }
                let cur = cost(i0, j) - get(&u, i0) - get(&v, j);
                if cur < minv.get(j).copied().unwrap_or(0) {
                    if let Some(x) = minv.get_mut(j) {
                        *x = cur;
                    }
                    if let Some(x) = way.get_mut(j) {
                        *x = j0;
                    }
                }
                let mj = minv.get(j).copied().unwrap_or(0);
                if mj < delta {
                    delta = mj;
                    j1 = j;
                }
            }
            for j in 0..=m {
                let pj = p.get(j).copied().unwrap_or(0);
                if used.get(j).copied().unwrap_or(false) {
                    if let Some(x) = u.get_mut(pj) {
                        *x += delta;
                    }
                    if let Some(x) = v.get_mut(j) {
                        *x -= delta;
                    }
                } else if let Some(x) = minv.get_mut(j) {
                    *x -= delta;
                }
            }
            j0 = j1;
            if p.get(j0).copied().unwrap_or(0) == 0 {
                break;
            }
        }
        loop {
            let j1 = way.get(j0).copied().unwrap_or(0);
            let pj1 = p.get(j1).copied().unwrap_or(0);
            if let Some(x) = p.get_mut(j0) {
                *x = pj1;
            }
            j0 = j1;
            if j0 == 0 {
                break;
            }
        }
    }
    let mut out = [None; MAX_ROBOTS];
    for j in 1..=m {
        let i = p.get(j).copied().unwrap_or(0);
        if i >= 1 && j <= c.m && cost(i, j) < INF {
            if let Some(x) = out.get_mut(i - 1) {
                *x = Some(j - 1);
            }
        }
    }
    let mut rows = [0i64; MAX_ROBOTS];
    for (r, x) in rows.iter_mut().zip(u.iter().skip(1)) {
        *r = *x;
    }
    (out, rows)
}

/// The smallest threshold under which every row can still be matched, for
/// the bottleneck (min-max) objective.
fn bottleneck_threshold(c: &Candidates) -> i64 {
    let mut vals = [INF; MAX_ROBOTS * MAX_CANDIDATES];
    let mut n = 0usize;
    for j in 0..c.k {
        for col in 0..c.m {
            let x = c.at(j, col);
            if x < INF {
                if let Some(s) = vals.get_mut(n) {
                    *s = x;
                    n += 1;
                }
            }
        }
    }
    let Some(vals) = vals.get_mut(..n) else {
        return INF;
    };
    vals.sort_unstable();
    let full = hungarian(c, INF)
        .0
        .iter()
        .take(c.k)
        .filter(|x| x.is_some())
        .count();
    let (mut lo, mut hi) = (0usize, n);
    while lo < hi {
        let mid = (lo + hi) / 2;
        let cap = vals.get(mid).copied().unwrap_or(INF);
        let got = hungarian(c, cap)
            .0
            .iter()
            .take(c.k)
            .filter(|x| x.is_some())
            .count();
        if got >= full { hi = mid } else { lo = mid + 1 }
    }
    vals.get(lo).copied().unwrap_or(INF)
}

/// The column of every row under `objective`.
pub(crate) fn hungarian_cols(
    c: &Candidates,
    objective: AssignmentObjective,
) -> [Option<usize>; MAX_ROBOTS] {
    let cap = match objective {
        AssignmentObjective::MinSum => INF - 1,
        AssignmentObjective::MinMax => bottleneck_threshold(c),
    };
    hungarian(c, cap).0
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

/// Burgard et al.'s coordinated exploration in its greedy form: repeatedly
/// give the (robot, frontier) pair with the least travel time plus the
/// seed's cooperation penalty around targets already given, until every
/// robot has one; the deciding robot takes its share.
#[derive(Clone, Copy, Debug)]
pub struct BurgardGreedy {
    /// The utility discount around assigned targets (the seed's +5 … +1).
    pub penalty: CooperationLayer,
}

impl Default for BurgardGreedy {
    fn default() -> Self {
        BurgardGreedy {
            penalty: CooperationLayer { peak: 5, radius: 4 },
        }
    }
}

impl<M, F> Strategy<M, F> for BurgardGreedy
where
    M: AsRef<[Block]> + AsMut<[Block]>,
    F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
{
    fn name(&self) -> &'static str {
        "burgard"
    }

    fn decide(
        &mut self,
        ctx: &Context<'_, M>,
        fields: &mut [DistField<F>],
    ) -> Result<Decision, PlanError> {
        let k = ctx.robots.len();
        let Some(c) = Candidates::collect(ctx, fields, MAX_CANDIDATES, 0)? else {
            return match fields.first_mut() {
                Some(f) => nearest_or_home(ctx, f),
                None => Ok(Decision::STAY),
            };
        };
        let bounds = ctx.map.bounds();
        let mut given: [Option<usize>; MAX_ROBOTS] = [None; MAX_ROBOTS];
        let mut targets: [Option<Pos>; MAX_ROBOTS] = [None; MAX_ROBOTS];
        for _ in 0..k {
            let mut best: Option<(i64, usize, usize)> = None;
            for j in 0..k {
                if given.get(j).copied().flatten().is_some() {
                    continue;
                }
                for col in 0..c.m {
                    let d = c.at(j, col);
                    if d >= INF {
                        continue;
                    }
                    let Some(&node) = c.nodes.get(col) else {
                        continue;
                    };
                    let p = bounds.pos(node);
                    let mut pen = 0i64;
                    for a in targets.iter().flatten() {
                        let e = self.penalty.penalty_edges(p.manhattan(*a));
                        if e > 0 && CooperationLayer::direct_route_open(ctx.map, *a, p) {
                            pen += i64::from(e) * i64::from(ctx.timing.edge);
                        }
                    }
                    let cand = (d + pen, node, j);
                    if best.is_none_or(|b| cand < b) {
                        best = Some(cand);
                    }
                }
            }
            let Some((_, node, j)) = best else { break };
            if let Some(g) = given.get_mut(j) {
                *g = Some(node);
            }
            if let Some(t) = targets.get_mut(j) {
                *t = Some(bounds.pos(node));
            }
        }
        let me = ctx.me;
        match (given.get(me).copied().flatten(), fields.get_mut(me)) {
            (Some(i), Some(f)) => Ok(explore_decision(ctx, f, i)),
            (None, Some(f)) => {
                if c.m == 0 {
                    go_home(ctx, f)
                } else {
                    nearest_or_home(ctx, f)
                }
            }
            (_, None) => Ok(Decision::STAY),
        }
    }
}

#[cfg(test)]
mod tests;
