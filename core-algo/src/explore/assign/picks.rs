//! One robot's cheapest frontier nodes for
//! [`Candidates::cheapest`](super::Candidates::cheapest), and
//! why a few of them can be proved enough.

use super::INF;
use crate::explore::{Context, MAX_ROBOTS, RobotView, Workers};
use crate::map::Block;
use crate::path::{
    DistField, Flow, PlanCell, PlanError, Reached, RecordedSearch, SearchKey, SearchMemo,
    node_mark, reads_same,
};
use crate::timing::Ticks;

/// Most picks a robot brings to
/// [`Candidates::cheapest`](super::Candidates::cheapest).
pub(super) const PICKS: usize = MAX_ROBOTS + 4;

/// Picks a robot brings first when they grow lazily (see [`Picks`]).
/// Three, not four (stop 51): the same decisions, as the proof is exact,
/// from 8 % fewer states settled in the picks' searches (maze 128², 16
/// robots), and 3–8 % less wall time on 256² fields with 16 robots
/// (docs/results/performance.md, stop 51). Two took longer: more robots
/// fail the proof and grow again.
pub(super) const FIRST_PICKS: usize = 3;

/// Nodes a robot's first search reaches before it stops with a pick in
/// hand, proved or not (see [`Picks::beyond`]). A robot with two picks
/// beside it and the third far away otherwise searched all the way there:
/// on rooms 128² with 16 robots, 1 009 of the deciding robots' first
/// searches ran through 4 000 nodes or more, mostly to find a third pick
/// the assignment never needed. With 1 024, rooms 256² seed 3's searches
/// settled 6.5 % fewer states and copied 6.4 % fewer cells
/// (docs/results/performance.md, stop 60); on rooms 128², 256 settled
/// more states than no budget at all and 4 096 copied as many cells. The
/// tests' fields are small, so their first searches stop much sooner, to
/// take this way too.
pub(super) const FIRST_BUDGET: usize = if cfg!(test) { 8 } else { 1024 };

/// How much farther each later round may go than the one before.
const BUDGET_GROWTH: usize = 4;

/// One robot's cheapest frontier nodes, cheapest first, found by its field
/// grown only as far as they could change.
///
/// ## Why a few picks can be proved enough
///
/// The Hungarian algorithm ends with potentials `u` (robots) and `v`
/// (columns) such that `u[j] + v[i] ≤ cost[j][i]` for every pair, with
/// equality on the assignment, `v ≤ 0`, and `v = 0` on unassigned
/// columns. Give every frontier node outside the matrix `v = 0` too: if
/// `u[j]` is at most [`Picks::beyond`] for every robot, the inequality
/// holds for every pair of the whole problem (a column robot `j`'s field
/// never reached costs it at least that as well), so these potentials
/// prove the assignment optimal over every frontier node
/// (linear-programming duality). A robot for which it fails brings twice
/// the picks, its field resumed where it stopped, and the assignment runs
/// again. While robots explore at the frontier, their first few mostly
/// settle it: on open 256² with 16 robots such decisions cost a quarter of
/// what 16 picks each did (docs/results/performance.md, stop 19). A first
/// search also stops on a budget of nodes ([`FIRST_BUDGET`]), where the
/// floor it stopped at bounds what it did not reach; where that bound
/// fails the proof, the search goes on four times as far.
#[derive(Clone, Copy)]
pub(super) struct Picks {
    /// Up to [`PICKS`] cheapest found so far: (cost, node).
    best: [(i64, usize); PICKS],
    n: usize,
    /// How many picks the robot brings.
    want: usize,
    /// Frontier nodes its field has not reached yet.
    unseen: usize,
    started: bool,
    /// The kept record (its key and id) whose end the field stands at:
    /// the next round takes over a record that went on from there, or
    /// writes its own down as one (see [`Picks::go_on`]).
    at: Option<(SearchKey, u64)>,
    /// Nodes the search has reached so far, in all rounds.
    seen: usize,
    /// Nodes after which the search stops with a pick in hand, proved or
    /// not (see [`Picks::beyond`]); `usize::MAX`: never.
    budget: usize,
    /// The floor where the search last stopped on its budget: no node it
    /// has not reached costs less.
    cut: Option<i64>,
    /// A travel at which the floor was found no higher than the last pick
    /// wanted, since that pick last changed. 0 at first: the floor at
    /// travel 0 is no higher than any cost.
    open_to: Ticks,
    /// The travel of the last frontier node the search reached: it stops
    /// on its budget only beyond it (see [`Picks::reach_node`]).
    frontier_at: Ticks,
}

/// What a robot's picks rank the nodes their search reaches by (see
/// [`Picks::grow`]).
struct Reach<'a, C, Fl> {
    j: usize,
    bounds: crate::map::Bounds,
    spread: u32,
    taken: &'a [usize],
    cost: &'a C,
    floor: &'a Fl,
}

/// Whether the picks' searches (and the endgame's reverse searches) jump
/// along corridors: when at least half the visited nodes have two arms.
/// On a maze (four in five) a jumping search costs half a plain one; on
/// rooms fields (one in ten) the check at every drive costs more than the
/// few jumps save: a 16-robot run on rooms 128² took 79 s jumping against
/// 62 s (docs/results/performance.md, stop 42). Every robot decides it
/// alike from its own map, so their predictions of each other agree.
/// Tempo's robots go on through corridors without a team decision on
/// such maps only (`TempoConfig::corridor_extends_team`).
pub(crate) fn jumps_pay<M: AsRef<[Block]> + AsMut<[Block]>>(map: &crate::map::KnownMap<M>) -> bool {
    2 * map.two_armed_len() >= map.visited_len()
}

impl Picks {
    pub(super) fn new(want: usize, budget: usize) -> Picks {
        Picks {
            best: [(INF, usize::MAX); PICKS],
            n: 0,
            want: want.clamp(1, PICKS),
            unseen: usize::MAX,
            started: false,
            at: None,
            seen: 0,
            budget: budget.max(1),
            cut: None,
            open_to: 0,
            frontier_at: 0,
        }
    }

    /// The picks the robot brings.
    pub(super) fn brought(&self) -> &[(i64, usize)] {
        self.best.get(..self.n.min(self.want)).unwrap_or(&[])
    }

    /// A lower bound of the robot's cost for every frontier node it does
    /// not bring: nodes found but not brought cost at least the last pick,
    /// and so do the ones never reached (`floor` passed it); with fewer
    /// picks than wanted, every reachable frontier node is brought. A
    /// search stopped on its budget proves less: no node it has not
    /// reached costs less than the floor where it stopped (the floor never
    /// falls as the travel grows), so that floor bounds them instead.
    pub(super) fn beyond(&self) -> i64 {
        let last = if self.n >= self.want {
            self.best.get(self.want - 1).map_or(INF, |&(b, _)| b)
        } else {
            INF
        };
        self.cut.map_or(last, |c| c.min(last))
    }

    /// Grows robot `j`'s (at pose `r`) field until its `want` cheapest
    /// frontier nodes are known: from scratch the first time, resumed after
    /// [`Picks::more`]. With `spread`, nodes that near a `taken` one are
    /// skipped (then picks must not grow: `taken` changes). With a `memo`,
    /// on a map where searches do not jump ([`jumps_pay`]),
    /// a search from scratch takes over a recorded one where it can (see
    /// [`Picks::take_over`]), or a plain one in part (see
    /// `DistField::take_over_before`), and is written down where it
    /// cannot take one over whole; later rounds resume the field either
    /// way.
    pub(super) fn grow<M, F>(
        &mut self,
        ctx: &Context<'_, M>,
        field: &mut DistField<F>,
        (j, r): (usize, &RobotView),
        (spread, taken): (u32, &[usize]),
        (cost, floor): (
            &impl Fn(usize, usize, Ticks) -> Option<i64>,
            &impl Fn(usize, Ticks) -> i64,
        ),
        memo: Option<&dyn SearchMemo>,
    ) -> Result<(), PlanError>
    where
        M: AsRef<[Block]> + AsMut<[Block]>,
        F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
    {
        let map = ctx.map;
        let start = !self.started;
        self.cut = None;
        self.open_to = 0;
        if start {
            self.started = true;
            self.unseen = map.frontier_len();
        } else if self.unseen == 0 {
            return Ok(());
        }
        let to = Reach {
            j,
            bounds: map.bounds(),
            spread,
            taken,
            cost,
            floor,
        };
        let (timing, pos, heading) = (ctx.timing, r.pos, r.heading);
        if !start {
            return self.go_on(map, &to, field, memo);
        }
        let jumping = jumps_pay(map);
        // A jumping search (a maze-like map) is neither kept nor taken
        // over: in a maze the map changes somewhere along most searches
        // before a team mate could take them over, and writing every one
        // down cost more than the few taken over saved (maze 256², 16
        // robots: 93.5 s without against 98.3 s; docs/results/
        // performance.md, stop 56). The same decisions either way.
        let memo = memo.filter(|_| !jumping);
        let key = field.search_key(map, timing, (pos, heading), jumping);
        let (Some(memo), Some(key)) = (memo, key) else {
            return if jumping {
                field.compute_jumping(map, timing, pos, heading, |i, d| self.reach(map, &to, i, d))
            } else {
                field.compute(map, timing, pos, heading, |i, d| self.reach(map, &to, i, d))
            };
        };
        let fresh = *self;
        let mut taken = Ok(true);
        let found = memo.recall(key, &mut |rec| {
            *self = fresh;
            match self.take_over(map, &to, field, (timing, rec)) {
                Some(r) => {
                    self.at = Some((key, rec.id));
                    taken = r;
                    true
                }
                None => false,
            }
        });
        if found {
            // Picks that go on past the record's end go on as a later
            // round does.
            return match taken {
                Ok(true) => Ok(()),
                Ok(false) => self.go_on(map, &to, field, Some(memo)),
                Err(e) => Err(e),
            };
        }
        let mut result = Ok(());
        // None stands where a search of their own would: take one over in
        // part, up to the first node that reads otherwise or that the picks
        // stop at, where that spares at least half of its search
        // (rebuilding the field is a pass over all the record's cells),
        // and write down the search that goes on from there.
        let found = memo.recall(key, &mut |rec| {
            if !rec.holds_queues() {
                return false;
            }
            let reached = rec.reached;
            // One pass to the first node that reads otherwise
            // (`first_read_otherwise`) or where the picks stop: a record
            // that went farther than they do reads the same to its end.
            let mut probe = fresh;
            let upto = reached.iter().position(|x| {
                let i = x.node as usize;
                node_mark(map, i) != x.mark || probe.reach_read(&to, x) == Flow::Stop
            });
            let Some(dist) = reached.get(upto.unwrap_or(reached.len())).map(|x| x.dist) else {
                return false;
            };
            let before = rec.reached_before(dist);
            let head = match reached.get(..before) {
                Some(head) if before > 0 && 2 * before >= reached.len() => head,
                _ => return false,
            };
            // Nodes before `dist` come before the stop: none stops.
            *self = fresh;
            for x in head {
                self.reach_read(&to, x);
            }
            match field.take_over_before(map, timing, rec, dist) {
                Ok(true) => memo.taken_over_in_part(),
                Ok(false) => return false,
                Err(e) => {
                    result = Err(e);
                    return true;
                }
            }
            let end = memo.record(key, &mut |out| {
                out.reached(head);
                result = field.resume(map, |i, d| {
                    out.reached(&[Reached::at(map, i, d)]);
                    self.reach(map, &to, i, d)
                });
                if result.is_ok() {
                    field.write_down(map, out);
                }
            });
            self.at = end.map(|id| (key, id));
            true
        });
        if found {
            return result;
        }
        *self = fresh;
        let end = memo.record(key, &mut |rec| {
            let pose = (pos, heading, jumping);
            result = field
                .compute_written_down(map, timing, pose, rec, |i, d| self.reach(map, &to, i, d));
        });
        self.at = end.map(|id| (key, id));
        result
    }

    /// Resumes the field where its search stopped. Where that is the end
    /// of a kept record, a record that went on from there is taken over
    /// instead, if it reads the same and these picks, told what it reached
    /// after that end, stop where it stopped or go on past it (then on from
    /// its end); else the search goes on, written down as such a record.
    /// Either way is exact for the reason a search taken over whole is
    /// (see `path::record`).
    fn go_on<M, F>(
        &mut self,
        map: &crate::map::KnownMap<M>,
        to: &Reach<'_, impl Fn(usize, usize, Ticks) -> Option<i64>, impl Fn(usize, Ticks) -> i64>,
        field: &mut DistField<F>,
        memo: Option<&dyn SearchMemo>,
    ) -> Result<(), PlanError>
    where
        M: AsRef<[Block]> + AsMut<[Block]>,
        F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
    {
        loop {
            let (Some(memo), Some((key, at))) = (memo, self.at.take()) else {
                return field.resume(map, |i, d| self.reach(map, to, i, d));
            };
            let fresh = *self;
            let mut stopped = true;
            let found = memo.recall_after(at, &mut |rec| {
                *self = fresh;
                match self.take_over_after(map, to, field, rec) {
                    Some(stop) => {
                        self.at = Some((key, rec.id));
                        stopped = stop;
                        true
                    }
                    None => false,
                }
            });
            if found {
                if stopped {
                    return Ok(());
                }
                continue;
            }
            *self = fresh;
            let mut result = Ok(());
            let id = memo.record_after(key, at, &mut |out| {
                result = field.resume_written_down(map, out, |i, d| self.reach(map, to, i, d));
            });
            self.at = id.map(|id| (key, id));
            return result;
        }
    }

    /// Takes the recorded search `rec` over into `field` if its nodes read
    /// the same in `map` and these picks, told what it reached in order,
    /// stop where it stopped or go on past it: then they are what a search
    /// of their own would have found, and the field is where that search
    /// would stand (see `path::record`). Whether the picks stopped there;
    /// `None` if not taken over; the picks are then spoilt, and the
    /// caller starts them again.
    fn take_over<M, F>(
        &mut self,
        map: &crate::map::KnownMap<M>,
        to: &Reach<'_, impl Fn(usize, usize, Ticks) -> Option<i64>, impl Fn(usize, Ticks) -> i64>,
        field: &mut DistField<F>,
        (timing, rec): (crate::timing::Timing, RecordedSearch<'_>),
    ) -> Option<Result<bool, PlanError>>
    where
        M: AsRef<[Block]> + AsMut<[Block]>,
        F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
    {
        if rec.after != 0 || !reads_same(map, rec) {
            return None;
        }
        let stop = self.told(to, rec)?;
        Some(field.take_over(map, timing, rec).map(|()| stop))
    }

    /// [`Picks::take_over`] of the rest of a search that went on where
    /// the field stands ([`DistField::take_over_after`]): whether the
    /// picks stopped where it did, `None` if not taken over (the picks
    /// are then spoilt).
    fn take_over_after<M, F>(
        &mut self,
        map: &crate::map::KnownMap<M>,
        to: &Reach<'_, impl Fn(usize, usize, Ticks) -> Option<i64>, impl Fn(usize, Ticks) -> i64>,
        field: &mut DistField<F>,
        rec: RecordedSearch<'_>,
    ) -> Option<bool>
    where
        M: AsRef<[Block]> + AsMut<[Block]>,
        F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
    {
        if !reads_same(map, rec) {
            return None;
        }
        let stop = self.told(to, rec)?;
        field.take_over_after(map, rec).then_some(stop)
    }

    /// Tells these picks what `rec` reached, in order: `None` if they
    /// stop before its last node, or at it where the recorded search went
    /// on and ran out (a search of their own would stop with its last
    /// state not expanded yet); else whether they stopped. The caller has
    /// checked that `rec` reads the same ([`reads_same`]).
    fn told(
        &mut self,
        to: &Reach<'_, impl Fn(usize, usize, Ticks) -> Option<i64>, impl Fn(usize, Ticks) -> i64>,
        rec: RecordedSearch<'_>,
    ) -> Option<bool> {
        let (last, before) = rec.reached.split_last()?;
        for x in before {
            if self.reach_read(to, x) == Flow::Stop {
                return None;
            }
        }
        let stop = self.reach_read(to, last) == Flow::Stop;
        if stop && rec.state.ran_out() {
            return None;
        }
        Some(stop)
    }

    /// The picks' answer to their search reaching node `i` at travel `d`:
    /// a frontier node is ranked by its cost, and the search stops once
    /// no node at `d` or beyond can beat the last pick wanted.
    fn reach<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &crate::map::KnownMap<M>,
        to: &Reach<'_, impl Fn(usize, usize, Ticks) -> Option<i64>, impl Fn(usize, Ticks) -> i64>,
        i: usize,
        d: Ticks,
    ) -> Flow {
        self.reach_node(to, (i, d, map.is_frontier_at(i)))
    }

    /// [`Picks::reach`] for a node a recorded search reached, where the
    /// caller has checked that it reads the same: its mark says whether it
    /// is a frontier node. Taken-over searches tell their picks every node
    /// they reached, and the second look at the map for each was a third
    /// of the time spent telling them (rooms 256², 16 robots;
    /// docs/results/performance.md, stop 60).
    fn reach_read(
        &mut self,
        to: &Reach<'_, impl Fn(usize, usize, Ticks) -> Option<i64>, impl Fn(usize, Ticks) -> i64>,
        x: &Reached,
    ) -> Flow {
        self.reach_node(to, (x.node as usize, x.dist, x.is_frontier()))
    }

    /// [`Picks::reach`] told whether node `i` is a frontier node.
    #[inline(always)]
    fn reach_node(
        &mut self,
        to: &Reach<'_, impl Fn(usize, usize, Ticks) -> Option<i64>, impl Fn(usize, Ticks) -> i64>,
        (i, d, frontier): (usize, Ticks, bool),
    ) -> Flow {
        let p = self;
        let j = to.j;
        if frontier {
            p.unseen = p.unseen.saturating_sub(1);
            p.frontier_at = d;
            let bounds = to.bounds;
            let at = bounds.pos(i);
            let crowded = to.spread > 0
                && to
                    .taken
                    .iter()
                    .any(|&q| q != i && bounds.pos(q).manhattan(at) <= to.spread);
            if let (false, Some(x)) = (crowded, (to.cost)(j, i, d)) {
                // Insert in order; ties keep the earlier (nearer) node.
                let n = p.n;
                let slot = p
                    .best
                    .get(..n)
                    .unwrap_or(&[])
                    .iter()
                    .position(|&(b, _)| x < b)
                    .unwrap_or(n);
                if slot < PICKS {
                    let end = n.min(PICKS - 1);
                    if let Some(s) = p.best.get_mut(slot..=end) {
                        s.rotate_right(1);
                    }
                    if let Some(s) = p.best.get_mut(slot) {
                        *s = (x, i);
                    }
                    p.n = (n + 1).min(PICKS);
                    if slot < p.want {
                        // The last pick wanted may have changed.
                        p.open_to = 0;
                    }
                }
            }
        }
        // No frontier node at travel d or beyond can beat the last pick.
        // The floor never falls as d grows, so below a travel where it
        // was found no higher than the last pick it need not be read.
        let done = p.n >= p.want
            && d > p.open_to
            && p.best.get(p.want - 1).is_some_and(|&(b, _)| {
                let beaten = (to.floor)(j, d) > b;
                if !beaten {
                    p.open_to = d;
                }
                beaten
            });
        p.seen = p.seen.saturating_add(1);
        // On its budget the search stops only past the travel of every
        // frontier node it reached, as a stop on the floor does past every
        // pick's: the states as cheap as the node it is given are then all
        // settled, and its way there, ties included, is a whole search's
        // (see `tempo::search_to`).
        if done || p.unseen == 0 {
            p.cut = None;
            Flow::Stop
        } else if p.n > 0 && p.seen >= p.budget && d > p.frontier_at {
            p.cut = Some((to.floor)(j, d));
            Flow::Stop
        } else {
            Flow::Continue
        }
    }

    /// [`Picks::grow`] without spread for every robot marked `stale`
    /// (then unmarked), the searches run by `workers`: each reads the map
    /// and writes only its own field and picks, so they may run at once.
    pub(super) fn grow_all<M, F>(
        ctx: &Context<'_, M>,
        fields: &mut [DistField<F>],
        (picks, stale): (&mut [Picks; MAX_ROBOTS], &mut [bool; MAX_ROBOTS]),
        (cost, floor): (
            &(impl Fn(usize, usize, Ticks) -> Option<i64> + Sync),
            &(impl Fn(usize, Ticks) -> i64 + Sync),
        ),
        workers: &dyn Workers,
    ) -> Result<(), PlanError>
    where
        M: AsRef<[Block]> + AsMut<[Block]> + Sync,
        F: AsRef<[PlanCell]> + AsMut<[PlanCell]> + Send,
    {
        let mut results = [Ok(()); MAX_ROBOTS];
        let memo = workers.memo();
        let mut jobs = heapless::Vec::<_, MAX_ROBOTS>::new();
        let robots = ctx.robots.iter().zip(fields.iter_mut());
        let own = picks
            .iter_mut()
            .zip(stale.iter_mut())
            .zip(results.iter_mut());
        let mut mine = None;
        for (j, ((r, field), ((p, s), result))) in robots.zip(own).enumerate() {
            if !core::mem::take(s) {
                continue;
            }
            if j == ctx.me {
                mine = Some(jobs.len());
            }
            let job = move || *result = p.grow(ctx, field, (j, r), (0, &[]), (cost, floor), memo);
            // At most one job per robot: `jobs` holds them all.
            if jobs.push(job).is_err() {
                return Err(PlanError::Capacity {
                    needed: ctx.robots.len(),
                    available: MAX_ROBOTS,
                });
            }
        }
        // The deciding robot's search goes first. It stands on a node it
        // has just reached, so its search is seldom one a record holds and
        // is often the batch's longest; handed out last, it ran alone while
        // the other cores waited (rooms 256² seed 3, 16 robots: 91.1 s
        // against 96.9 s; docs/results/performance.md, stop 61). Which
        // thread runs which job changes nothing a search finds.
        if let Some(m) = mine.and_then(|m| jobs.get_mut(..=m)) {
            m.rotate_right(1);
        }
        crate::explore::workers::run_all(workers, &mut jobs);
        drop(jobs);
        results.into_iter().collect()
    }

    /// Twice the picks, up to `most`; whether that is more. A search that
    /// stopped on its budget always has more to give: it goes on, four
    /// times as far.
    pub(super) fn more(&mut self, most: usize) -> bool {
        let want = (self.want * 2).min(most).min(PICKS);
        let grew = want > self.want;
        self.want = want.max(self.want);
        if self.cut.is_some() {
            self.budget = self.budget.saturating_mul(BUDGET_GROWTH);
            return true;
        }
        grew
    }
}
