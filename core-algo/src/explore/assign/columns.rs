//! The reverse endgame's columns: one reverse search per frontier node,
//! each finding that node's cheapest robots, side by side on the
//! decision's [`Workers`]. See `Candidates::reverse_columns`.

use super::{Candidates, INF, hungarian_by};
use crate::explore::{Context, MAX_ROBOTS, SharedColumns, Workers};
use crate::geometry::Heading;
use crate::map::Block;
use crate::path::{CorridorExits, DistField, Flow, PlanCell, PlanError, way_in};
use crate::timing::Ticks;
use core::any::Any;

/// How many cheapest robots each column's reverse search finds before the
/// lazy endgame first assigns the team (see `Candidates::reverse_columns`).
const FIRST_ROBOTS: usize = 1;

/// A robot's cost for a frontier node at a travel (`None`: not allowed);
/// shared by the columns' searches, which may run on several threads.
type Cost<'a> = &'a (dyn Fn(usize, usize, Ticks) -> Option<i64> + Sync);

/// How a column's search goes on.
#[derive(Clone, Copy)]
enum Grow {
    /// The decision's first search of the column: the slot's search
    /// carried over (`held`: it was this column's, or rebased to it) or a
    /// new one, jumping along corridors or not.
    First { held: bool, jumping: bool },
    /// A later round: the search goes on where it stopped.
    On,
}

impl Candidates {
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
    /// Why reverse: the forward way grew team mates' fields until their
    /// costs could no longer matter, most of a 16-robot maze run's time.
    /// On maze 64² with 16 robots the reverse searches gave the same
    /// assignment in all 14 987 decisions of a run in about half the time
    /// (docs/results/performance.md, stop 29).
    ///
    /// Each search stays in a team mate's field slot, and the next decision
    /// carries it over if the map grew only by dead ends (see
    /// [`DistField::refresh_reverse`]): robots it settled already are read
    /// off, and it grows on only if the robots have moved out of it. A
    /// robot decides again whenever the map grows, and most frontier nodes
    /// outlive a decision. Each column's search reads the map and writes
    /// only its own field and column, so the searches of a round run on
    /// `workers`. `false` when the team mates' slots are too few.
    pub(super) fn reverse_columns<M, F>(
        &mut self,
        ctx: &Context<'_, M>,
        fields: &mut [DistField<F>],
        lazy: bool,
        cost: Cost<'_>,
        workers: &dyn Workers,
    ) -> Result<bool, PlanError>
    where
        M: AsRef<[Block]> + AsMut<[Block]> + Sync,
        F: AsRef<[PlanCell]> + AsMut<[PlanCell]> + Send + 'static,
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
        let robots = (&exits, near);
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
        let all = (1u32 << m) - 1;
        let want = |_: &Candidates, _: usize| m.min(k).min(first);
        let grow = |col: usize| match slot.get(col).copied().flatten() {
            Some((_, held)) => Grow::First { held, jumping },
            None => Grow::On,
        };
        let run = (&slot, robots, cost, workers);
        // How far each column's search has settled (the slot may have
        // handed its search back to the host's store, see `search_column`).
        let mut settled_to = [None; MAX_ROBOTS];
        self.grow_columns(ctx, fields, all, run, (want, grow), &mut settled_to)?;
        if !lazy {
            return Ok(true);
        }
        // Lazy: the rounds of the doc comment above. A pair the searches
        // found has its cost in the matrix; the others stay `INF` there.
        // `spent` marks the columns whose search found nobody more when
        // grown: it has settled all it can reach, so the robots not found
        // are out of reach.
        let mut spent = 0u32;
        // Each column's lower bounds for the robots it has not found,
        // worked out again only for the columns grown since (the cost
        // closure is most of a round's work).
        let mut low = [[INF; MAX_ROBOTS]; MAX_ROBOTS];
        let mut stale = u32::MAX;
        loop {
            for col in (0..m).filter(|&col| stale & (1 << col) != 0) {
                let (Some(_), Some(&node), Some(row)) = (
                    slot.get(col).copied().flatten(),
                    self.nodes.get(col),
                    low.get_mut(col),
                ) else {
                    continue;
                };
                let from = settled_to
                    .get(col)
                    .copied()
                    .flatten()
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
            let mut before = [0u32; MAX_ROBOTS];
            for (col, b) in before.iter_mut().enumerate().take(m) {
                *b = self.found_in(col);
            }
            let want = |c: &Candidates, col: usize| c.found_in(col).count_ones() as usize + 1;
            self.grow_columns(
                ctx,
                fields,
                grow,
                run,
                (want, |_| Grow::On),
                &mut settled_to,
            )?;
            for col in (0..m).filter(|&col| grow & (1 << col) != 0) {
                if before.get(col) == Some(&self.found_in(col)) {
                    spent |= 1 << col;
                }
                stale |= 1 << col;
            }
        }
    }

    /// Grows the search of every column in `cols` (bit `col`) in its slot
    /// until its `want` cheapest robots are proven, the searches side by
    /// side on `workers`; then writes what each found into its column.
    #[allow(clippy::type_complexity)]
    fn grow_columns<M, F>(
        &mut self,
        ctx: &Context<'_, M>,
        fields: &mut [DistField<F>],
        cols: u32,
        (slot, robots, cost, workers): (
            &[Option<(usize, bool)>; MAX_ROBOTS],
            (&[CorridorExits; MAX_ROBOTS], u64),
            Cost<'_>,
            &dyn Workers,
        ),
        (want, grow): (impl Fn(&Candidates, usize) -> usize, impl Fn(usize) -> Grow),
        settled_to: &mut [Option<Ticks>; MAX_ROBOTS],
    ) -> Result<(), PlanError>
    where
        M: AsRef<[Block]> + AsMut<[Block]> + Sync,
        F: AsRef<[PlanCell]> + AsMut<[PlanCell]> + Send + 'static,
    {
        let (k, m) = (self.k, self.m);
        // Each column's costs, copied out so that its search writes only
        // its own, and each column's slot, lent to its search alone.
        let mut costs = [[INF; MAX_ROBOTS]; MAX_ROBOTS];
        let mut lent: [Option<&mut DistField<F>>; MAX_ROBOTS] = [const { None }; MAX_ROBOTS];
        for (s, f) in fields.iter_mut().enumerate() {
            let col = (0..m).find(|&col| {
                cols & (1 << col) != 0 && slot.get(col).copied().flatten().map(|x| x.0) == Some(s)
            });
            if let Some(l) = col.and_then(|col| lent.get_mut(col)) {
                *l = Some(f);
            }
        }
        let mut results = [Ok(None); MAX_ROBOTS];
        let shared = workers.columns();
        // The columns whose search runs: only those are written back.
        let mut ran = 0u32;
        let mut jobs = heapless::Vec::<_, MAX_ROBOTS>::new();
        let columns = lent
            .iter_mut()
            .zip(costs.iter_mut())
            .zip(results.iter_mut());
        for (col, ((rev, out), result)) in columns.enumerate().take(m) {
            let (Some(rev), Some(&node)) = (rev.take(), self.nodes.get(col)) else {
                continue;
            };
            for (j, x) in out.iter_mut().enumerate().take(k) {
                *x = self.at(j, col);
            }
            let (want, how) = (want(self, col), grow(col));
            ran |= 1 << col;
            let job = move || {
                *result = search_column(
                    ctx,
                    rev,
                    (node, how, want),
                    (out, k),
                    (robots, cost, shared),
                );
            };
            // At most one job per column, fewer than `MAX_ROBOTS`.
            if jobs.push(job).is_err() {
                return Err(PlanError::Capacity {
                    needed: m,
                    available: MAX_ROBOTS,
                });
            }
        }
        crate::explore::workers::run_all(workers, &mut jobs);
        drop(jobs);
        for (col, out) in costs.iter().enumerate().take(m) {
            if ran & (1 << col) == 0 {
                continue;
            }
            if let (Some(t), Some(Ok(x))) = (settled_to.get_mut(col), results.get(col)) {
                *t = *x;
            }
            for (j, &x) in out.iter().enumerate().take(k) {
                if let Some(e) = self.cost.get_mut(j).and_then(|r| r.get_mut(col)) {
                    *e = x;
                }
            }
        }
        results.into_iter().try_for_each(|r| r.map(|_| ()))
    }

    /// The robots with a cost in column `col` (bit j: robot j).
    fn found_in(&self, col: usize) -> u32 {
        (0..self.k)
            .filter(|&j| self.at(j, col) < INF)
            .fold(0, |acc, j| acc | (1 << j))
    }
}

/// One column's search (to frontier node `node`, in `rev`), grown as
/// `how` says until its `want` cheapest robots are proven; what it finds
/// goes into `costs` (robot j's cost, `INF` if not found). How far the
/// search has settled (see [`DistField::reverse_settled_to`]).
///
/// With a host's store (`shared`), the search is the team's: taken from
/// the store if it keeps one for this map, and given back after.
#[allow(clippy::type_complexity)]
fn search_column<M, F>(
    ctx: &Context<'_, M>,
    rev: &mut DistField<F>,
    (node, how, want): (usize, Grow, usize),
    (costs, k): (&mut [i64; MAX_ROBOTS], usize),
    ((exits, near), cost, shared): (
        (&[CorridorExits; MAX_ROBOTS], u64),
        Cost<'_>,
        Option<&dyn SharedColumns>,
    ),
) -> Result<Option<Ticks>, PlanError>
where
    M: AsRef<[Block]> + AsMut<[Block]>,
    F: AsRef<[PlanCell]> + AsMut<[PlanCell]> + 'static,
{
    let map = ctx.map;
    let mut column = Column::new((costs, k), node, want, cost, (exits, near));
    // The team's search of this node, or of the node before it on its
    // corridor (the column visited last, see `DistField::rebase_reverse`).
    let taken = shared.and_then(|s| {
        let revision_of = |p| map.revision_of(p);
        let mut take = |goal: usize| match s.take(goal, &revision_of, rev as &mut dyn Any) {
            Some(r) if rev.adopt_reverse(r) => true,
            Some(_) => {
                rev.forget();
                false
            }
            None => false,
        };
        if take(node) {
            return Some(rev.refresh_reverse(map, ctx.timing));
        }
        let (u, _) = way_in(map, node)?;
        take(u).then(|| rev.rebase_reverse(map, ctx.timing, node))
    });
    let kept = match (taken, how) {
        (Some(kept), _) => kept,
        (None, Grow::First { held, .. }) => held && rev.refresh_reverse(map, ctx.timing),
        // A later round goes on with the search the first one left, ours
        // or, with a store, one given back to it and gone since.
        (None, Grow::On) => {
            rev.reverse_goal() == Some(node) && rev.refresh_reverse(map, ctx.timing)
        }
    };
    if kept {
        column.read(rev);
        let settled = rev.reverse_settled_to().unwrap_or(0);
        if !column.proven(settled) {
            rev.resume_reverse(map, |v, h, key| column.settled(v, h, key))?;
        }
    } else {
        let p = map.bounds().pos(node);
        let reached = |v, h, key| column.settled(v, h, key);
        if matches!(how, Grow::First { jumping: true, .. }) {
            rev.compute_reverse_jumping(map, ctx.timing, p, reached)?;
        } else {
            rev.compute_reverse(map, ctx.timing, p, reached)?;
        }
    }
    // A search that ran out proves every robot with an exit it settled,
    // though no state came after to say so.
    column.read(rev);
    let settled = rev.reverse_settled_to();
    if let Some(s) = shared.filter(|_| rev.reverse_goal() == Some(node)) {
        s.give(node, map.print(), rev as &mut dyn Any);
    }
    Ok(settled)
}

/// One column's reverse search under way: see `Candidates::reverse_columns`.
struct Column<'a> {
    /// The column's costs (robot j's, `INF` if not found yet), for the
    /// first `k` robots.
    costs: &'a mut [i64; MAX_ROBOTS],
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
    cost: Cost<'a>,
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
    /// The column of frontier node `node` with the costs found so far, to
    /// be searched until its `want` cheapest are proven.
    fn new(
        (costs, k): (&'a mut [i64; MAX_ROBOTS], usize),
        node: usize,
        want: usize,
        cost: Cost<'a>,
        (exits, near): (&'a [CorridorExits; MAX_ROBOTS], u64),
    ) -> Column<'a> {
        let found = costs.iter().take(k).filter(|&&x| x < INF).count();
        Column {
            costs,
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

    /// Robot `j`'s cost found so far (`INF`: none).
    fn at(&self, j: usize) -> i64 {
        self.costs.get(j).copied().unwrap_or(INF)
    }

    /// Reads the exits that `rev`, this column's search (carried over,
    /// stopped or run out), has settled; records the robots it proves.
    fn read<F: AsRef<[PlanCell]> + AsMut<[PlanCell]>>(&mut self, rev: &DistField<F>) {
        let Some(at) = rev.reverse_settled_to() else {
            return;
        };
        for j in 0..self.k {
            let Some(x) = self.exits.get(j) else { continue };
            if self.at(j) != INF {
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
            if let (Some(x), Some(e)) = ((self.cost)(j, self.node, best), self.costs.get_mut(j)) {
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
        let (costs, k, want) = (&*self.costs, self.k, self.want);
        let cut = *self.cut.get_or_insert_with(|| nth_cheapest(costs, k, want));
        let (node, cost) = (self.node, self.cost);
        let mut beats = |j: usize| {
            costs.get(j).copied().unwrap_or(INF) == INF
                && cost(j, node, at).is_some_and(|x| x < cut)
        };
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
                    if (xv, xh) == (v, h) && self.at(j) == INF {
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

/// The `n`-th cheapest of the first `k` costs (`INF` if fewer are found):
/// a robot that cannot beat it is not needed in the column.
fn nth_cheapest(costs: &[i64; MAX_ROBOTS], k: usize, n: usize) -> i64 {
    let mut row = *costs;
    let row = row.get_mut(..k).unwrap_or(&mut []);
    row.sort_unstable();
    n.checked_sub(1)
        .and_then(|i| row.get(i))
        .copied()
        .unwrap_or(INF)
}
