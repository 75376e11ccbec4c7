//! Tempo's assignment once fewer frontier nodes than robots are left: see
//! `Candidates::endgame`.

use super::{Candidates, INF};
use crate::explore::{Context, MAX_ROBOTS, Workers};
use crate::map::Block;
use crate::path::{DistField, Flow, PlanCell, PlanError, arms_at};
use crate::timing::Ticks;

impl Candidates {
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
    /// forbidden. The matrix is written into `c`; `false` when the deciding
    /// robot cannot reach every frontier node (team mates in another part
    /// of the graph might): then the nodes it finds are not all the columns.
    ///
    /// With `reverse`, each frontier node's m cheapest robots come from one
    /// reverse search instead (see [`Candidates::reverse_columns`]): the same
    /// optimum in about half the time, but other forbidden pairs, so where
    /// several assignments cost the same the Hungarian may pick another one.
    /// Tempo uses it where its tie-break makes the optimum unique. Its
    /// columns are read off the map, so it searches no field of the
    /// deciding robot's and never returns `false` for want of one: the
    /// caller searches as far as the node it gets. With `lazy` too (the
    /// min-sum objective only), each node's search grows only as far as
    /// the assignment needs, which the assignment proves.
    pub(super) fn endgame<M, F>(
        ctx: &Context<'_, M>,
        fields: &mut [DistField<F>],
        (lazy, reverse): (bool, bool),
        mut cost: impl Fn(usize, usize, Ticks) -> Option<i64> + Sync,
        mut floor: impl FnMut(usize, Ticks) -> i64,
        mut bound: impl FnMut(usize, usize) -> i64,
        (c, workers): (&mut Candidates, &dyn Workers),
    ) -> Result<bool, PlanError>
    where
        M: AsRef<[Block]> + AsMut<[Block]> + Sync,
        F: AsRef<[PlanCell]> + AsMut<[PlanCell]> + Send + 'static,
    {
        let (map, k, me) = (ctx.map, ctx.robots.len(), ctx.me);
        c.clear(k);
        if reverse {
            // Every frontier node is a column, read off the map: the
            // reverse searches find each one's robots, ours too, and a
            // node we cannot reach is just forbidden to us. A search of
            // ours to find them went to the farthest one, most of the map
            // at every decision (maze 128², 16 robots: 14 % of the run);
            // the decision searches only as far as the node it gets (see
            // `tempo`), and a robot that waits not at all.
            let bounds = map.bounds();
            for i in map.frontier().filter_map(|p| bounds.index(p)) {
                if let Some(slot) = c.nodes.get_mut(c.m) {
                    *slot = i;
                    c.m += 1;
                }
            }
            return c.reverse_columns(ctx, fields, lazy, &cost, workers);
        }
        let (Some(r), Some(field)) = (ctx.robots.get(me), fields.get_mut(me)) else {
            return Ok(false);
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
            return Ok(false);
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
        learn(&mut near, ctx, c, field, u_turn, &mut cost);
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
            fill(c, me, field, &mut cost);
        }
        if m == 0 {
            return Ok(true);
        }
        // The m-th cheapest searched robot of column `col`: a robot that
        // cannot beat it is not needed there.
        let threshold = |c: &Candidates, col: usize| c.nth_cheapest(col, m);
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
                let t = threshold(c, col);
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
            fill(c, j, field, &mut cost);
            learn(&mut near, ctx, c, field, u_turn, &mut cost);
        }
        Ok(true)
    }

    /// The `n`-th cheapest cost in column `col` (`INF` if fewer robots have
    /// one): a robot that cannot beat it is not needed there.
    fn nth_cheapest(&self, col: usize, n: usize) -> i64 {
        let mut row = [INF; MAX_ROBOTS];
        for (j, x) in row.iter_mut().enumerate().take(self.k) {
            *x = self.at(j, col);
        }
        let row = row.get_mut(..self.k).unwrap_or(&mut []);
        row.sort_unstable();
        n.checked_sub(1)
            .and_then(|i| row.get(i))
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
