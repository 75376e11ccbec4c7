//! Tempo's assignment once fewer frontier nodes than robots are left: see
//! `Candidates::endgame`.

use super::{Candidates, INF, hungarian_by};
use crate::explore::{Context, MAX_ROBOTS};
use crate::geometry::Heading;
use crate::map::Block;
use crate::path::{CorridorExits, DistField, Flow, PlanCell, PlanError, arms_at, way_in};
use crate::timing::Ticks;

/// How many cheapest robots each column's reverse search finds before the
/// lazy endgame first assigns the team (see `Candidates::reverse_columns`).
const FIRST_ROBOTS: usize = 1;

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
        mut cost: impl FnMut(usize, usize, Ticks) -> Option<i64>,
        mut floor: impl FnMut(usize, Ticks) -> i64,
        mut bound: impl FnMut(usize, usize) -> i64,
        c: &mut Candidates,
    ) -> Result<bool, PlanError>
    where
        M: AsRef<[Block]> + AsMut<[Block]>,
        F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
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
            return c.reverse_columns(ctx, fields, lazy, &mut cost);
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

    /// Fills every column's m cheapest robots (m = `self.m` frontier nodes,
    /// in `self.nodes`) from one reverse search per node: from every pose,
    /// the time to reach it. A search stops once its m cheapest robots are
    /// proven: found, and no robot not yet found could still be cheaper, as
    /// a robot's cost only grows with its travel. Other pairs stay
    /// forbidden.
    ///
    /// `lazy` (min-sum only) proves the assignment instead of finding m
    /// robots per node. Each search first proves its node's cheapest
    /// robot. A robot not found yet costs at least what it would at the
    /// travel the search has settled to. The team is then assigned on the
    /// found costs and these lower bounds. An assignment that uses only
    /// found pairs costs exactly its sum, and no other costs less even on
    /// the bounds, so it is optimal. Otherwise each node whose bound was
    /// used grows by one robot, and the team is assigned again. On a
    /// 16-robot maze 128² this settled 21 % fewer states (1.10 G against
    /// 1.40 G), in 7 rounds per decision (docs/results/performance.md,
    /// stop 41).
    ///
    /// Why reverse: the forward way grew team mates' fields until their costs could
    /// no longer matter, most of a 16-robot maze run's time. On maze 64²
    /// with 16 robots the reverse searches gave the same assignment in all
    /// 14 987 decisions of a run in about half the time (docs/results/
    /// performance.md, stop 29).
    ///
    /// Each search stays in a team mate's field slot, and the next decision
    /// carries it over if the map grew only by dead ends (see
    /// [`DistField::refresh_reverse`]): robots it settled already are read
    /// off, and it grows on only if the robots have moved out of it. A
    /// robot decides again whenever the map grows, and most frontier nodes
    /// outlive a decision. `false` when the team mates' slots are too few.
    fn reverse_columns<M, F>(
        &mut self,
        ctx: &Context<'_, M>,
        fields: &mut [DistField<F>],
        lazy: bool,
        cost: &mut dyn FnMut(usize, usize, Ticks) -> Option<i64>,
    ) -> Result<bool, PlanError>
    where
        M: AsRef<[Block]> + AsMut<[Block]>,
        F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
    {
        let (map, k, me, m) = (ctx.map, self.k, ctx.me, self.m);
        let bounds = map.bounds();
        // Where each robot leaves for the rest of the graph, as states
        // outside corridors, which the reverse searches settle (they jump
        // along corridors: see `DistField::compute_reverse_jumping`); a
        // 64-bit mask of their nodes spares most states the comparison
        // with all k.
        let mut exits = [CorridorExits::NONE; MAX_ROBOTS];
        let mut near = 0u64;
        for (x, r) in exits.iter_mut().zip(ctx.robots).take(k) {
            if let Some(i) = bounds.index(r.pos) {
                *x = CorridorExits::of(map, ctx.timing, i, r.heading);
                for (v, _, _) in x.iter() {
                    near |= 1 << (v % 64);
                }
            }
        }
        let exits = &exits;
        let team = |s: usize| s < k && s != me;
        // Each column's slot: the one that holds its search, or the search
        // of the column visited just before it (see
        // `DistField::rebase_reverse`), else any other (every frontier
        // node is a column, so what another slot holds is dead, or a
        // second copy; a visited column's goal is no column).
        let mut slot = [None; MAX_ROBOTS];
        let mut used = [false; MAX_ROBOTS];
        for (col, sl) in slot.iter_mut().enumerate().take(m) {
            let Some(&node) = self.nodes.get(col) else {
                continue;
            };
            let holding = |fields: &[DistField<F>], goal: usize| {
                (0..k).find(|&s| {
                    team(s)
                        && !used.get(s).copied().unwrap_or(true)
                        && fields.get(s).and_then(|f| f.reverse_goal()) == Some(goal)
                })
            };
            let held = holding(fields, node).or_else(|| {
                let (u, _) = way_in(map, node)?;
                let s = holding(fields, u)?;
                fields
                    .get_mut(s)
                    .is_some_and(|f| f.rebase_reverse(map, ctx.timing, node))
                    .then_some(s)
            });
            if let (Some(s), Some(u)) = (held, held.and_then(|s| used.get_mut(s))) {
                *sl = Some((s, true));
                *u = true;
            }
        }
        for col in 0..m {
            if slot.get(col).copied().flatten().is_some() {
                continue;
            }
            let free = (0..k).find(|&s| team(s) && !used.get(s).copied().unwrap_or(true));
            let (Some(s), Some(sl)) = (free, slot.get_mut(col)) else {
                return Ok(false);
            };
            *sl = Some((s, false));
            if let Some(u) = used.get_mut(s) {
                *u = true;
            }
        }
        let first = if lazy { FIRST_ROBOTS } else { k };
        // Jump along corridors where they are most of the map, as the
        // picks do (see `picks::jumps_pay`); a kept search goes on as it
        // began, and the exits price a robot alike either way.
        let jumping = super::picks::jumps_pay(map);
        for col in 0..m {
            let (Some((s, held)), Some(&node)) =
                (slot.get(col).copied().flatten(), self.nodes.get(col))
            else {
                continue;
            };
            let Some(rev) = fields.get_mut(s) else {
                continue;
            };
            let kept = held && rev.refresh_reverse(map, ctx.timing);
            let want = m.min(k).min(first);
            let mut column = Column::new(self, (col, node), want, cost, (exits, near));
            if kept {
                column.read(rev);
                let settled = rev.reverse_settled_to().unwrap_or(0);
                if !column.proven(settled) {
                    rev.resume_reverse(map, |v, h, key| column.settled(v, h, key))?;
                }
            } else {
                let p = bounds.pos(node);
                let reached = |v, h, key| column.settled(v, h, key);
                if jumping {
                    rev.compute_reverse_jumping(map, ctx.timing, p, reached)?;
                } else {
                    rev.compute_reverse(map, ctx.timing, p, reached)?;
                }
            }
            // A search that ran out proves every robot with an exit it
            // settled, though no state came after to say so.
            column.read(rev);
        }
        if !lazy {
            return Ok(true);
        }
        // Lazy: the rounds of the doc comment above. A pair the searches
        // found has its cost in the matrix; the others stay `INF` there.
        // `spent` marks the
        // columns whose search found nobody more when grown: it has settled
        // all it can reach, so the robots not found are out of reach.
        let mut spent = 0u32;
        // Each column's lower bounds for the robots it has not found,
        // worked out again only for the columns grown since (the cost
        // closure is most of a round's work).
        let mut low = [[INF; MAX_ROBOTS]; MAX_ROBOTS];
        let mut stale = u32::MAX;
        loop {
            for col in (0..m).filter(|&col| stale & (1 << col) != 0) {
                let (Some(s), Some(&node), Some(row)) = (
                    slot.get(col).copied().flatten().map(|(s, _)| s),
                    self.nodes.get(col),
                    low.get_mut(col),
                ) else {
                    continue;
                };
                let from = fields
                    .get(s)
                    .and_then(|f| f.reverse_settled_to())
                    .filter(|&t| t < Ticks::MAX && spent & (1 << col) == 0);
                for (j, x) in row.iter_mut().enumerate().take(k) {
                    let stands = exits.get(j).is_some_and(|e| e.iter().next().is_some());
                    *x = match from {
                        Some(at) if stands && self.at(j, col) == INF => {
                            cost(j, node, at).map_or(INF, |x| x.clamp(-INF + 1, INF - 1))
                        }
                        _ => INF,
                    };
                }
            }
            stale = 0;
            // A pair's found cost, else its lower bound.
            let pair = |j: usize, col: usize| match self.at(j, col) {
                INF => low.get(col).and_then(|r| r.get(j)).copied().unwrap_or(INF),
                x => x,
            };
            // Transposed (frontier nodes as rows, fewer than the robots):
            // O(m²·k), not O(k³), as it runs once per round. A node no
            // robot can reach is left out; it would take a robot.
            let mut rows = [0usize; MAX_ROBOTS];
            let mut n = 0;
            for col in 0..m {
                if (0..k).any(|j| pair(j, col) < INF) {
                    if let Some(r) = rows.get_mut(n) {
                        *r = col;
                        n += 1;
                    }
                }
            }
            let at = |r: usize, j: usize| rows.get(r).map_or(INF, |&col| pair(j, col));
            let (robot_of, _) = hungarian_by::<{ MAX_ROBOTS + 1 }>(n, k, 0, at);
            let mut grow = 0u32;
            for (j, &r) in robot_of.iter().enumerate().skip(1).take(k) {
                let Some(&col) = r.checked_sub(1).and_then(|r| rows.get(r)) else {
                    continue;
                };
                let j = j - 1;
                if pair(j, col) < INF && self.at(j, col) == INF {
                    grow |= 1 << col;
                }
            }
            if grow == 0 {
                return Ok(true);
            }
            for col in (0..m).filter(|&col| grow & (1 << col) != 0) {
                let (Some(s), Some(&node)) = (
                    slot.get(col).copied().flatten().map(|(s, _)| s),
                    self.nodes.get(col),
                ) else {
                    continue;
                };
                let Some(rev) = fields.get_mut(s) else {
                    continue;
                };
                let before = self.found_in(col);
                let want = before.count_ones() as usize + 1;
                let mut column = Column::new(self, (col, node), want, cost, (exits, near));
                column.read(rev);
                rev.resume_reverse(map, |v, h, key| column.settled(v, h, key))?;
                column.read(rev);
                if self.found_in(col) == before {
                    spent |= 1 << col;
                }
                stale |= 1 << col;
            }
        }
    }

    /// The robots with a cost in column `col` (bit j: robot j).
    fn found_in(&self, col: usize) -> u32 {
        (0..self.k)
            .filter(|&j| self.at(j, col) < INF)
            .fold(0, |acc, j| acc | (1 << j))
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

/// One column's reverse search under way: see `Candidates::reverse_columns`.
struct Column<'a> {
    c: &'a mut Candidates,
    col: usize,
    node: usize,
    k: usize,
    /// How many cheapest robots the column needs.
    want: usize,
    found: usize,
    /// The want-th cheapest cost found, once want are found.
    cut: Option<i64>,
    /// The last travel at which not every robot was proven.
    proven_at: Option<Ticks>,
    /// The robot not found yet that could still beat the cut at the last
    /// check: a robot's cost only grows with the travel, so it mostly
    /// still can at the next one, and is asked first.
    blocker: Option<usize>,
    cost: &'a mut dyn FnMut(usize, usize, Ticks) -> Option<i64>,
    /// Each robot's exits, and the mask of their nodes (bit `node % 64`).
    exits: &'a [CorridorExits; MAX_ROBOTS],
    near: u64,
    /// Each robot's cheapest time through the exits settled so far, and
    /// which exits those are (bit e: exit e).
    best: [Ticks; MAX_ROBOTS],
    seen: [u8; MAX_ROBOTS],
    /// The robots with an exit settled whose time is not proven yet: an
    /// exit not settled might still be cheaper.
    pending: u32,
}

impl<'a> Column<'a> {
    /// Column `col` (frontier node `node`) of `c`, its robots found so far
    /// read off it, to be searched until its `want` cheapest are proven.
    fn new(
        c: &'a mut Candidates,
        (col, node): (usize, usize),
        want: usize,
        cost: &'a mut dyn FnMut(usize, usize, Ticks) -> Option<i64>,
        (exits, near): (&'a [CorridorExits; MAX_ROBOTS], u64),
    ) -> Column<'a> {
        let found = c.found_in(col).count_ones() as usize;
        let k = c.k;
        Column {
            c,
            col,
            node,
            k,
            want,
            found,
            cut: None,
            proven_at: None,
            blocker: None,
            cost,
            exits,
            near,
            best: [Ticks::MAX; MAX_ROBOTS],
            seen: [0; MAX_ROBOTS],
            pending: 0,
        }
    }

    /// Reads the exits that `rev`, this column's search (carried over,
    /// stopped or run out), has settled; records the robots it proves.
    fn read<F: AsRef<[PlanCell]> + AsMut<[PlanCell]>>(&mut self, rev: &DistField<F>) {
        let Some(at) = rev.reverse_settled_to() else {
            return;
        };
        for j in 0..self.k {
            let Some(x) = self.exits.get(j) else { continue };
            if self.c.at(j, self.col) != INF {
                continue;
            }
            for (e, (v, h, off)) in x.iter().enumerate() {
                if let Some(d) = rev.dist_pose_at(v, h) {
                    self.reached(j, e, off + d);
                }
            }
        }
        self.promote(at);
    }

    /// Robot `j`'s exit `e` is settled: it can get to the goal in `time`.
    fn reached(&mut self, j: usize, e: usize, time: Ticks) {
        if let (Some(b), Some(s)) = (self.best.get_mut(j), self.seen.get_mut(j)) {
            *b = (*b).min(time);
            *s |= 1 << e;
            self.pending |= 1 << j;
        }
    }

    /// Records every pending robot whose time is proven once every state
    /// not settled costs at least `at` (see `CorridorExits::time_in`).
    fn promote(&mut self, at: Ticks) {
        let mut rest = self.pending;
        while rest != 0 {
            let j = rest.trailing_zeros() as usize;
            rest &= rest - 1;
            let (Some(x), Some(&best), Some(&seen)) =
                (self.exits.get(j), self.best.get(j), self.seen.get(j))
            else {
                continue;
            };
            let unseen = x
                .iter()
                .enumerate()
                .filter(|&(e, _)| seen & (1 << e) == 0)
                .map(|(_, (_, _, off))| off)
                .min()
                .unwrap_or(Ticks::MAX);
            if best > at.saturating_add(unseen) {
                continue;
            }
            self.pending &= !(1 << j);
            if let (Some(x), Some(e)) = (
                (self.cost)(j, self.node, best),
                self.c.cost.get_mut(j).and_then(|r| r.get_mut(self.col)),
            ) {
                if *e == INF {
                    *e = x.clamp(-INF + 1, INF - 1);
                    self.found += 1;
                    self.cut = None;
                    self.proven_at = None;
                }
            }
        }
    }

    /// Whether no robot not found yet, standing at travel `at` or more, can
    /// beat the want-th cheapest found. A pending robot stands there too:
    /// its exits settled so far cost more than that, or it would be found.
    fn proven(&mut self, at: Ticks) -> bool {
        if self.found < self.want {
            return false;
        }
        let (c, col, k) = (&*self.c, self.col, self.k);
        let cut = *self
            .cut
            .get_or_insert_with(|| c.nth_cheapest(col, self.want));
        let (node, cost) = (self.node, &mut self.cost);
        let mut beats =
            |j: usize| c.at(j, col) == INF && cost(j, node, at).is_some_and(|x| x < cut);
        if self.blocker.is_some_and(&mut beats) {
            return false;
        }
        self.blocker = (0..k).find(|&j| beats(j));
        self.blocker.is_none()
    }

    /// The search settled state (`v`, `h`) at `key`: finds the robots
    /// that leave through it, and stops once the column is proven.
    fn settled(&mut self, v: usize, h: Heading, key: Ticks) -> Flow {
        if self.near & (1 << (v % 64)) != 0 {
            for j in 0..self.k {
                let Some(x) = self.exits.get(j) else { continue };
                for (e, (xv, xh, off)) in x.iter().enumerate() {
                    if (xv, xh) == (v, h) && self.c.at(j, self.col) == INF {
                        self.reached(j, e, off + key);
                    }
                }
            }
        }
        if self.pending != 0 {
            self.promote(key);
        }
        // Keys only grow, so one check per key.
        if self.found < self.want || self.proven_at == Some(key) {
            return Flow::Continue;
        }
        self.proven_at = Some(key);
        if self.proven(key) {
            Flow::Stop
        } else {
            Flow::Continue
        }
    }
}
