//! One robot's cheapest frontier nodes for
//! [`Candidates::cheapest`](super::Candidates::cheapest), and
//! why a few of them can be proved enough.

use super::INF;
use crate::explore::{Context, MAX_ROBOTS, RobotView, Workers};
use crate::map::Block;
use crate::path::{DistField, Flow, PlanCell, PlanError};
use crate::timing::Ticks;

/// Most picks a robot brings to
/// [`Candidates::cheapest`](super::Candidates::cheapest).
pub(super) const PICKS: usize = MAX_ROBOTS + 4;

/// Picks a robot brings first when they grow lazily (see [`Picks`]).
pub(super) const FIRST_PICKS: usize = 4;

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
/// again. While robots explore at the frontier, their first 4 mostly
/// settle it: on open 256² with 16 robots such decisions cost a quarter of
/// what 16 picks each did (docs/results/performance.md, stop 19).
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
}

/// Whether the picks' searches (and the endgame's reverse searches) jump
/// along corridors: when at least half the visited nodes have two arms.
/// On a maze (four in five) a jumping search costs half a plain one; on
/// rooms fields (one in ten) the check at every drive costs more than the
/// few jumps save: a 16-robot run on rooms 128² took 79 s jumping against
/// 62 s (docs/results/performance.md, stop 42). Every robot decides it
/// alike from its own map, so their predictions of each other agree.
pub(super) fn jumps_pay<M: AsRef<[Block]> + AsMut<[Block]>>(map: &crate::map::KnownMap<M>) -> bool {
    2 * map.two_armed_len() >= map.visited_len()
}

impl Picks {
    pub(super) fn new(want: usize) -> Picks {
        Picks {
            best: [(INF, usize::MAX); PICKS],
            n: 0,
            want: want.clamp(1, PICKS),
            unseen: usize::MAX,
            started: false,
        }
    }

    /// The picks the robot brings.
    pub(super) fn brought(&self) -> &[(i64, usize)] {
        self.best.get(..self.n.min(self.want)).unwrap_or(&[])
    }

    /// A lower bound of the robot's cost for every frontier node it does
    /// not bring: nodes found but not brought cost at least the last pick,
    /// and so do the ones never reached (`floor` passed it); with fewer
    /// picks than wanted, every reachable frontier node is brought.
    pub(super) fn beyond(&self) -> i64 {
        if self.n >= self.want {
            self.best.get(self.want - 1).map_or(INF, |&(b, _)| b)
        } else {
            INF
        }
    }

    /// Grows robot `j`'s (at pose `r`) field until its `want` cheapest
    /// frontier nodes are known: from scratch the first time, resumed after
    /// [`Picks::more`]. With `spread`, nodes that near a `taken` one are
    /// skipped (then picks must not grow: `taken` changes).
    pub(super) fn grow<M, F>(
        &mut self,
        ctx: &Context<'_, M>,
        field: &mut DistField<F>,
        (j, r): (usize, &RobotView),
        (spread, taken): (u32, &[usize]),
        cost: &impl Fn(usize, usize, Ticks) -> Option<i64>,
        floor: &impl Fn(usize, Ticks) -> i64,
    ) -> Result<(), PlanError>
    where
        M: AsRef<[Block]> + AsMut<[Block]>,
        F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
    {
        let map = ctx.map;
        let bounds = map.bounds();
        let start = !self.started;
        if start {
            self.started = true;
            self.unseen = map.frontier_len();
        } else if self.unseen == 0 {
            return Ok(());
        }
        let p = self;
        let reached = |i: usize, d: Ticks| {
            if map.is_frontier_at(i) {
                p.unseen = p.unseen.saturating_sub(1);
                let at = bounds.pos(i);
                let crowded = spread > 0
                    && taken
                        .iter()
                        .any(|&q| q != i && bounds.pos(q).manhattan(at) <= spread);
                if let (false, Some(x)) = (crowded, cost(j, i, d)) {
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
                    }
                }
            }
            // No frontier node at travel d or beyond can beat the last pick.
            let done = p.n >= p.want
                && p.best
                    .get(p.want - 1)
                    .is_some_and(|&(b, _)| floor(j, d) > b);
            if done || p.unseen == 0 {
                Flow::Stop
            } else {
                Flow::Continue
            }
        };
        if start && jumps_pay(map) {
            field.compute_jumping(map, ctx.timing, r.pos, r.heading, reached)
        } else if start {
            field.compute(map, ctx.timing, r.pos, r.heading, reached)
        } else {
            field.resume(map, reached)
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
        let mut jobs = heapless::Vec::<_, MAX_ROBOTS>::new();
        let robots = ctx.robots.iter().zip(fields.iter_mut());
        let own = picks
            .iter_mut()
            .zip(stale.iter_mut())
            .zip(results.iter_mut());
        for (j, ((r, field), ((p, s), result))) in robots.zip(own).enumerate() {
            if !core::mem::take(s) {
                continue;
            }
            let job = move || *result = p.grow(ctx, field, (j, r), (0, &[]), cost, floor);
            // At most one job per robot: `jobs` holds them all.
            if jobs.push(job).is_err() {
                return Err(PlanError::Capacity {
                    needed: ctx.robots.len(),
                    available: MAX_ROBOTS,
                });
            }
        }
        crate::explore::workers::run_all(workers, &mut jobs);
        drop(jobs);
        results.into_iter().collect()
    }

    /// Twice the picks, up to `most`; whether that is more.
    pub(super) fn more(&mut self, most: usize) -> bool {
        let want = (self.want * 2).min(most).min(PICKS);
        let grew = want > self.want;
        self.want = want.max(self.want);
        grew
    }
}
