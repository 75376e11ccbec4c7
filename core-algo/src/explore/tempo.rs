//! Tempo: this project's strategy for the shortest makespan.
//!
//! The makespan ends when the last robot is home, so what matters is the
//! slowest robot's explore-and-return time. Tempo re-assigns the whole team
//! at every decision (min-sum Hungarian on the true turn-aware travel
//! times, so committed robots switch when a better split appears), on
//! partial fields grown only as far as the assignment needs: each robot's
//! field to its own k cheapest frontier nodes under tempo's costs, and, once
//! fewer frontier nodes than robots are left, only the fields of robots that
//! could be among a node's cheapest, or in teams above six one search back
//! from each frontier node to its cheapest robots, kept from decision to
//! decision, the robot's own field then searched only to the node it
//! gets (`Candidates::cheapest`; no optimal assignment is lost, see
//! `assign`). A robot left
//! without a share trails to its nearest frontier node if that is at most 8
//! edges away, or at any distance in a sparse team (at least 48 nodes of
//! the map window per robot), in a team of at most six; else it *waits
//! where it stands*: it decides again whenever the map grows, and goes home
//! once nothing is left. (Driving home at once was measured too: it loses on mazes, where
//! idle robots are soon needed again. Trailing without a limit lost in the
//! system simulator until retreats could push through a team mate: robots
//! that followed each other jammed, and a homecoming deadlocked twice as
//! often. Near trailing now gains 3.6 % on small fields, is even on 32² to
//! 64² ones, and loses 4–8 % on open 128² and 256² fields with 16 robots,
//! where it also doubles the wall time; hence the team limit. Trailing any
//! distance gains 2 % on 16² and 32² fields, 7 % on 32² mazes, but loses
//! 8 % in 12² mazes with five or six robots, where trailers jam; hence the
//! density rule.)
//!
//! Every candidate's cost is lowered by a quarter of its distance from the
//! robot's home (Manhattan, in edges): of two frontier nodes about as far
//! away, the one farther from home goes first, so that what is left at the
//! end lies near home, on the way back. The way home after the map is
//! complete fell from 0.45 to 0.39 lower bounds (docs/results/exploration.md).
//!
//! In teams of up to six, a frontier node at or near a team mate's
//! announced target costs up to two edges more (linearly less out to a
//! Manhattan distance of 4): the min-sum assignment keeps robots off one
//! node, not off one room, and this soft push apart, like Burgard's
//! utility discount, cut the makespan by 3 % in the system simulator and
//! by 1.8 % on 32² fields held out from the tuning
//! (docs/results/exploration.md, stop 34).
//!
//! A robot keeps its share without re-assigning while the map is unchanged
//! (exact, see `Commitment`), and through corridors whatever changed: on a
//! node with two known arms it can only go on or turn back, a fresh
//! decision rarely changed its share, and deciding at every corridor node
//! was a quarter of the decisions in a 16-robot maze, each over most of
//! the map (`corridor_keeps_share`). In teams of more than six on a
//! maze-like map, a robot that reaches its share and finds a corridor
//! node there goes on to the frontier node ahead without re-assigning
//! (`corridor_extends_team`): those were most of the decisions on
//! reaching a share in a 16-robot maze, 40 % of its wall time at 256²,
//! and a fresh decision chose the node ahead anyway (the same makespans
//! on every 16-robot maze measured; docs/results/performance.md,
//! stop 52).
//!
//! In teams of more than six, a robot at least 24 edges (Manhattan) from
//! its share keeps it too, whatever changed, while no team mate has
//! announced it or stands within half that distance of it
//! (`far_keeps_share`). Every robot predicts this alike from the same
//! views, so a deciding robot leaves such team mates out of its
//! assignment, with their shares, and does not search their fields, the
//! costliest of a decision: on 256² fields with 16 robots, random fell
//! from 104 s to 53 s of wall time with a 1 % shorter makespan, open was
//! unchanged, and rooms and mazes, where a far share nearly always has a
//! team mate near it, gained little (docs/results/performance.md,
//! stop 35). On fields of at least 4 096 nodes per robot, a team mate near
//! a far share that heads for something no farther from it does not end
//! the share (`far_busy_nodes_per_robot`): at 256² with 16 robots rooms
//! ran 2.3 to 6 times faster, a maze 2.6 times, random up to 2.7 times,
//! with makespans even or shorter (stop 39).
//!
//! In teams of more than six, every cost carries a tie-break below one
//! tick that every robot computes alike (`tie_break`): the cheapest
//! assignment is then (almost always) unique, so robots deciding on the
//! same map agree on it whichever team mates' fields each searched, and a
//! search that proves less cannot change the outcome.
//!
//! Knobs tried and measured (docs/results/exploration.md), off by default
//! because they did not pay on the benchmark fields:
//! - a penalty on frontier nodes with three visited neighbours (they become
//!   known for free once the fourth is visited);
//! - a return-aware endgame: once candidates are no more than robots,
//!   minimise the largest travel plus way home (bottleneck);
//! - one candidate per neighbourhood (robots split into regions);
//! - squared travel times (balancing shares);
//! - a share kept through a few map changes (`share_slack`): with 16, a
//!   third to a half of the wall time on large mazes and rooms, even on
//!   64² fields, but open 256² with 16 robots took 6.7 % longer and 1.6×
//!   the wall time; on small fields 2 and 8 cost 0.9 % and 1.9 %;
//! - a wait kept while the frontier does not grow (up to two map changes):
//!   a robot that waits decides again at every map change, but keeping the
//!   wait cost 6 % on 40² fields with 10 and 16 robots, and one of 64 runs
//!   did not get home;
//! - clusters (`cluster_radius`): in teams above six a robot assigns only
//!   the team mates it reaches in steps of at most 16 edges between where
//!   robots stand or head, leaving the others and their targets out.
//!   Neutral on 40² to 128² fields and twice as fast on random 256² with
//!   16 robots, but mazes 128² took 14 % longer and rooms 256² 8 %
//!   (one run each): in a maze, Manhattan nearness says little, and robots
//!   of different clusters headed for the same far work
//!   (docs/results/performance.md, stop 38).

use super::assign::{AssignmentObjective, Candidates, hungarian_cols, is_left_out};
use super::frontier_floor::FrontierFloor;
use super::{
    Context, Decision, InOrder, Strategy, Workers, explore_decision, go_home, nearest_or_home,
};
use crate::map::Block;
use crate::path::{DistField, Flow, PlanCell, PlanError};
use crate::timing::Ticks;
use commitment::{Commitment, FarRule};
use left_out::{keeping_far, outside_cluster};

mod commitment;
mod config;
mod left_out;

pub use config::TempoConfig;

/// See the module docs.
#[derive(Clone, Copy, Debug)]
pub struct Tempo {
    /// Its knobs.
    pub config: TempoConfig,
    /// Each robot's share, or wait, from its last full decision (the
    /// strategy may decide for a whole simulated team), see [`Commitment`].
    kept: [Option<Commitment>; super::MAX_ROBOTS],
    /// Where the team mates' searches run (see [`Workers`]).
    workers: &'static dyn Workers,
}

impl Default for Tempo {
    fn default() -> Self {
        Tempo::new(TempoConfig::default())
    }
}

impl Tempo {
    /// Tempo with these knobs and nothing remembered yet, searching on one
    /// core.
    pub fn new(config: TempoConfig) -> Tempo {
        Tempo {
            config,
            kept: [None; super::MAX_ROBOTS],
            workers: &InOrder,
        }
    }

    /// The same, its team mates' searches run by `workers`: the same
    /// decisions, sooner on a host with cores to spare.
    pub fn with_workers(self, workers: &'static dyn Workers) -> Tempo {
        Tempo { workers, ..self }
    }
}

impl<M, F> Strategy<M, F> for Tempo
where
    M: AsRef<[Block]> + AsMut<[Block]> + Sync,
    F: AsRef<[PlanCell]> + AsMut<[PlanCell]> + Send + 'static,
{
    fn name(&self) -> &'static str {
        "tempo"
    }

    fn decide(
        &mut self,
        ctx: &Context<'_, M>,
        fields: &mut [DistField<F>],
    ) -> Result<Decision, PlanError> {
        let me = ctx.me;
        let k = ctx.robots.len();
        let cfg = self.config;
        let kept = self.kept.get_mut(me).and_then(Option::take);
        let far = cfg.far_rule(ctx.map.bounds().area(), k);
        if let (true, Some(c)) = (cfg.keep_share, kept) {
            if let Some(d) = self.kept_share(ctx, fields, c, far)? {
                return Ok(d);
            }
        }
        let edge = i64::from(ctx.timing.edge.max(1));
        let pen = i64::from(cfg.deduce_penalty_edges) * edge;
        let per_edge = edge * i64::from(cfg.home_pull_pct) / 100;
        let bounds = ctx.map.bounds();
        let robots = ctx.robots;
        // Large teams break ties alike in every robot (see `tie_break`).
        let ties = k > cfg.tie_break_team;
        let scale = if ties { TIE_SCALE } else { 1 };
        let travel = |j: usize, d: Ticks| -> i64 {
            let t = i64::from(d) + robots.get(j).map_or(0, |r| i64::from(r.eta));
            if cfg.squared {
                t.saturating_mul(t) / edge
            } else {
                t
            }
        };
        let (mut left_out, mut kept_far) = keeping_far(ctx, far);
        if k > cfg.cluster_team {
            outside_cluster(ctx, cfg.cluster_radius, &mut left_out, &mut kept_far);
        }
        // A robot's home pull for a node: what its cost takes off, and
        // what the frontier floor counts with.
        let pull = |j: usize, p: crate::geometry::Pos| -> i64 {
            robots
                .get(j)
                .map_or(0, |r| per_edge * i64::from(p.manhattan(r.home)))
        };
        let cost = |j: usize, i: usize, d: Ticks| -> Option<i64> {
            // The far shares are only scanned when some team mate keeps one
            // (this closure runs for every frontier node a search reaches).
            if left_out != 0 && (is_left_out(left_out, j) || kept_far.contains(&Some(i))) {
                return None;
            }
            robots.get(j)?;
            let deduce = pen > 0
                && ctx
                    .map
                    .cell_at(i)
                    .is_some_and(|x| x.visited_neighbours() == 3);
            let p = bounds.pos(i);
            // A cousin of the seed's `CooperationLayer`, not that layer:
            // a fractional fall-off from the nearest announced target, no
            // route check, no sum over targets; the form that was measured.
            let crowd = if cfg.crowd_penalty_edges > 0 && k <= cfg.crowd_team {
                let near = robots
                    .iter()
                    .enumerate()
                    .filter(|&(o, _)| o != j)
                    .filter_map(|(_, o)| o.target)
                    .map(|t| t.manhattan(p))
                    .min()
                    .unwrap_or(u32::MAX);
                let r = cfg.crowd_radius.saturating_add(1);
                i64::from(r.saturating_sub(near)) * i64::from(cfg.crowd_penalty_edges) * edge
                    / i64::from(r)
            } else {
                0
            };
            let x = travel(j, d) + if deduce { pen } else { 0 } + crowd - pull(j, p);
            Some(if ties {
                x.saturating_mul(TIE_SCALE) + tie_break(j, p)
            } else {
                x
            })
        };
        // No frontier node at travel d or beyond costs less: it lies at most
        // d / edge edges from the robot, so at most that much farther from
        // home than the robot is; and at most one step beyond the visited
        // node farthest from home (far tighter while the robot explores at
        // the edge of what is known).
        let mut farthest = [u32::MAX; super::MAX_ROBOTS];
        for (f, r) in farthest.iter_mut().zip(robots) {
            if let Some(x) = ctx.map.farthest_visited(r.home) {
                *f = x.saturating_add(1);
            }
        }
        // Both bounds must hold for every travel d' ≥ d, so each is kept
        // non-decreasing in d: the first as a rational slope below one
        // (rounded up), the second constant; with squared travel times
        // only the second is.
        let floor = |j: usize, d: Ticks| -> i64 {
            let from_home = robots
                .get(j)
                .map_or(0, |r| i64::from(r.pos.manhattan(r.home)));
            let by_travel = (per_edge * i64::from(d) + edge - 1) / edge + per_edge * from_home;
            let by_extent = farthest
                .get(j)
                .map_or(i64::MAX, |&f| per_edge * i64::from(f));
            let pull = if cfg.squared {
                by_extent
            } else {
                by_travel.min(by_extent)
            };
            travel(j, d).saturating_sub(pull).saturating_mul(scale)
        };
        // A lower bound of a robot's cost for a node at any travel: it is at
        // least `edge` per edge of Manhattan distance away.
        let bound = |j: usize, i: usize| -> i64 {
            let Some(r) = robots.get(j) else {
                return i64::MAX;
            };
            let p = bounds.pos(i);
            let least = r.pos.manhattan(p).saturating_mul(ctx.timing.edge);
            (travel(j, least) - per_edge * i64::from(p.manhattan(r.home))).saturating_mul(scale)
        };
        // Lazy picks are proved by the min-sum duals; the return-aware
        // endgame changes the costs after collecting, so it needs them all.
        let lazy = !cfg.endgame_return && k > cfg.eager_team;
        let mut c = Candidates::empty(k);
        let mut plan = |frontier: &(dyn Fn(usize, Ticks) -> i64 + Sync)| {
            let floor = |j: usize, d: Ticks| floor(j, d).max(frontier(j, d).saturating_mul(scale));
            let workers = self.workers;
            let ways = (lazy, ties, left_out);
            Candidates::cheapest(
                ctx,
                fields,
                k,
                cfg.spread,
                ways,
                cost,
                floor,
                bound,
                (&mut c, workers),
            )
        };
        // Where the frontier lies tightens the floor (see `FrontierFloor`):
        // searches stop sooner with the same picks. Only where the
        // tie-break makes the optimum unique, since a robot's row then
        // holds fewer columns its search reached; only with linear travel
        // times, which the table assumes; not where the forest answers
        // without a search, nor on a large frontier.
        let on_tree = ctx.tree.as_ref().is_some_and(|t| t.holds(ctx.map));
        let sparse = ctx.map.frontier_len() <= FRONTIER_FLOOR_NODES;
        let planned = if lazy && ties && !cfg.squared && sparse && !on_tree {
            FrontierFloor::with(ctx.map, robots, ctx.timing.edge, (&pull, &travel), plan)
        } else {
            plan(&|_, _| i64::MIN)
        }?;
        if !planned {
            return match fields.first_mut() {
                Some(f) => nearest_or_home(ctx, f),
                None => Ok(Decision::STAY),
            };
        }
        if c.m == 0 {
            return match fields.get_mut(me) {
                Some(f) => go_home(ctx, f),
                None => Ok(Decision::STAY),
            };
        }
        let endgame = self.config.endgame_return && c.m <= k && fields.len() >= 2 * k;
        if endgame {
            // Way home from every candidate, for every robot: fields from
            // the homes (the graph is symmetric; the heading at home is
            // free, so the cheapest over headings is used).
            let (_, home_fields) = fields.split_at_mut(k);
            for (j, (r, hf)) in ctx.robots.iter().zip(home_fields.iter_mut()).enumerate() {
                let nodes = c.nodes;
                let cands = nodes.get(..c.m).unwrap_or(&[]);
                let mut missing = cands.len();
                hf.compute(ctx.map, ctx.timing, r.home, r.heading, |i, _| {
                    if cands.contains(&i) {
                        missing -= 1;
                        if missing == 0 {
                            return Flow::Stop;
                        }
                    }
                    Flow::Continue
                })?;
                for (col, &node) in cands.iter().enumerate() {
                    match hf.dist_at(node) {
                        Some(d) => c.add(j, col, i64::from(d) * scale),
                        None => c.forbid(j, col),
                    }
                }
            }
        }
        let cols = if endgame {
            hungarian_cols(&c, AssignmentObjective::MinMax)
        } else {
            hungarian_cols(&c, AssignmentObjective::MinSum)
        };
        let mine = cols
            .get(me)
            .copied()
            .flatten()
            .and_then(|x| c.nodes.get(x).copied());
        let Some(f) = fields.get_mut(me) else {
            return Ok(Decision::STAY);
        };
        match mine {
            Some(i) => {
                let d = match first_heading_on_tree(ctx, i) {
                    Some(h) => Decision {
                        goal: super::Goal::Frontier(bounds.pos(i)),
                        next: Some(h),
                    },
                    None => {
                        // The reverse endgame searched no field of ours.
                        search_to(ctx, f, i)?;
                        explore_decision(ctx, f, i)
                    }
                };
                if !endgame {
                    self.keep(ctx, Some(i), d);
                }
                Ok(d)
            }
            None if self.config.idle_stay => {
                let limit = if cfg.trails_far(ctx.map.bounds().area(), k) {
                    Ticks::MAX
                } else {
                    cfg.trail_edges.saturating_mul(ctx.timing.edge)
                };
                if limit > 0 && k <= cfg.trail_team {
                    if let Some((i, d)) = super::cheapest_frontier(ctx, f, |_, _, _| Some(0))? {
                        if d <= limit {
                            return Ok(explore_decision(ctx, f, i));
                        }
                    }
                }
                if !endgame {
                    self.keep(ctx, None, WAIT);
                }
                Ok(WAIT)
            }
            None if self.config.idle_home => go_home(ctx, f),
            None => nearest_or_home(ctx, f),
        }
    }
}

impl Tempo {
    /// The decision a kept share gives without re-assigning the team
    /// (`Commitment::onward`, then `Commitment::holds`): `None` where the
    /// team must be assigned afresh.
    fn kept_share<M, F>(
        &mut self,
        ctx: &Context<'_, M>,
        fields: &mut [DistField<F>],
        c: Commitment,
        far: FarRule,
    ) -> Result<Option<Decision>, PlanError>
    where
        M: AsRef<[Block]> + AsMut<[Block]>,
        F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
    {
        let (me, k, cfg) = (ctx.me, ctx.robots.len(), self.config);
        if k > cfg.corridor_extends_team && super::assign::jumps_pay(ctx.map) {
            if let Some((i, h)) = c.onward(ctx) {
                let d = Decision {
                    goal: super::Goal::Frontier(ctx.map.bounds().pos(i)),
                    next: Some(h),
                };
                self.keep(ctx, Some(i), d);
                return Ok(Some(d));
            }
        }
        if c.holds(ctx, cfg.share_slack, cfg.corridor_keeps_share, far) {
            match (c.share(), fields.get_mut(me), ctx.my()) {
                (None, ..) => {
                    self.keep(ctx, None, WAIT);
                    return Ok(Some(WAIT));
                }
                (Some(i), Some(f), Some(r)) => {
                    let bounds = ctx.map.bounds();
                    let goal = bounds.pos(i);
                    if let Some(h) = first_heading_on_tree(ctx, i) {
                        let d = Decision {
                            goal: super::Goal::Frontier(goal),
                            next: Some(h),
                        };
                        self.keep(ctx, Some(i), d);
                        return Ok(Some(d));
                    }
                    // The way found last time, if the field still
                    // holds it, before a new search: on an unchanged
                    // map the rest of a cheapest way is a cheapest
                    // way, and in a corridor it is kept with the share
                    // (maze 64², 16 robots: the same run, and 4.5 s of
                    // A* fell to 0.3 s).
                    // Its next poses are kept with the share (see
                    // `WayAhead`).
                    let mut ahead = c.ahead();
                    let on_way = bounds.index(r.pos).and_then(|at| {
                        f.heading_after_kept(ctx.map, i, (at, r.heading), &mut ahead)
                    });
                    if let Some(h) = on_way {
                        let d = Decision {
                            goal: super::Goal::Frontier(goal),
                            next: Some(h),
                        };
                        self.keep(ctx, Some(i), d);
                        if let Some(Some(kept)) = self.kept.get_mut(me) {
                            *kept = kept.with_ahead(ahead);
                        }
                        return Ok(Some(d));
                    }
                    if f.astar(ctx.map, ctx.timing, r.pos, r.heading, goal)?
                        .is_some()
                    {
                        let d = explore_decision(ctx, f, i);
                        self.keep(ctx, Some(i), d);
                        return Ok(Some(d));
                    }
                }
                _ => {}
            }
        }
        Ok(None)
    }

    /// Remembers the share (`Some` frontier node) or the wait of the robot
    /// deciding `d`.
    fn keep<M>(&mut self, ctx: &Context<'_, M>, share: Option<usize>, d: Decision)
    where
        M: AsRef<[Block]> + AsMut<[Block]>,
    {
        if let (true, Some(slot)) = (self.config.keep_share, self.kept.get_mut(ctx.me)) {
            *slot = Commitment::after(ctx, share, d.next);
        }
    }
}

/// The heading the deciding robot drives off in towards frontier node `i`,
/// read off the known forest where it tells (see
/// [`crate::path::Forest::first_heading`]): the heading a search to `i`
/// gives, without the search.
fn first_heading_on_tree<M>(ctx: &Context<'_, M>, i: usize) -> Option<crate::geometry::Heading>
where
    M: AsRef<[Block]> + AsMut<[Block]>,
{
    let tree = ctx.tree.as_ref()?;
    let r = ctx.my()?;
    let at = ctx.map.bounds().index(r.pos)?;
    tree.first_heading(ctx.map, ctx.timing, (at, r.heading), i)
}

/// Makes `field` a search from the deciding robot's pose that holds its
/// cheapest way to node `i`, if it is not one already: grown until every
/// state as cheap as `i`'s cheapest is settled, so that the way, ties
/// included, is the one a whole search holds.
fn search_to<M, F>(
    ctx: &Context<'_, M>,
    field: &mut DistField<F>,
    i: usize,
) -> Result<(), PlanError>
where
    M: AsRef<[Block]> + AsMut<[Block]>,
    F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
{
    let Some(r) = ctx.my() else {
        return Ok(());
    };
    if field.is_search_from(ctx.map, ctx.timing, r.pos, r.heading) && field.dist_at(i).is_some() {
        return Ok(());
    }
    // The middle game's picks: a jumping search from this pose, whose ways
    // are read through corridors. Grown as far as the plain search below
    // would go, it holds the same way, ties included (maze 128², 16
    // robots: that search was 29 M of the 215 M states plain searches
    // settled).
    if field.is_distance_search_from(ctx.map, ctx.timing, r.pos, r.heading) && field.holds_ways() {
        if let Some(at) = field.dist_at(i) {
            return field.resume(
                ctx.map,
                |_, d| if d > at { Flow::Stop } else { Flow::Continue },
            );
        }
    }
    let mut at = None;
    field.compute(ctx.map, ctx.timing, r.pos, r.heading, |v, d| {
        if at.is_some_and(|a| d > a) {
            return Flow::Stop;
        }
        if v == i {
            at = Some(d);
        }
        Flow::Continue
    })
}

/// Tempo's costs are travel times scaled by this, plus a tie-break below
/// it ([`tie_break`]): no sum of up to [`super::MAX_ROBOTS`] tie-breaks
/// reaches one tick.
const TIE_SCALE: i64 = 1 << 16;

/// The tie-break's bits.
const TIE_MASK: u32 = 0xFFF;
const _: () = assert!(super::MAX_ROBOTS as i64 * (TIE_MASK as i64 + 1) <= TIE_SCALE);

/// A fixed pseudo-random tie-break of robot `j` for node `p`, below
/// `TIE_SCALE / MAX_ROBOTS`.
///
/// Why: where two assignments cost the same, the Hungarian picks one by
/// the shape of its matrix, and that shape depends on who decides (which
/// team mates' fields were searched, and how far). Two robots deciding on
/// the same map could then each leave a frontier node to the other, or
/// both take it. With a tie-break that every robot computes alike the
/// cheapest assignment is (almost always) unique: every robot finds the
/// same one, whichever fields it searched.
fn tie_break(j: usize, p: crate::geometry::Pos) -> i64 {
    let mut h = (j as u32).wrapping_mul(0x9E37_79B1)
        ^ (p.x as u16 as u32).wrapping_mul(0x85EB_CA77)
        ^ (p.y as u16 as u32).wrapping_mul(0xC2B2_AE3D);
    h ^= h >> 15;
    h = h.wrapping_mul(0x2C1B_3C6D);
    h ^= h >> 12;
    i64::from(h & TIE_MASK)
}

/// Most frontier nodes for which a decision builds its
/// [`FrontierFloor`]: the table costs a pass over every frontier node per
/// robot, and where the frontier is large the robots stand near work and
/// search little. Built at every decision, it took random 256² with 16
/// robots from 10.5 to 48.3 s and maze 256² (where the forest answers)
/// from 48.0 to 57.6 s; at up to 256 nodes both are as before and rooms
/// 256² seed 2 goes from 67–70 s to 58–59 s (docs/results/
/// performance.md, stop 58).
const FRONTIER_FLOOR_NODES: usize = 256;

/// A robot without a share waits where it stands.
const WAIT: Decision = Decision {
    goal: super::Goal::Wait,
    next: None,
};

#[cfg(test)]
mod tests;
