//! Tempo: this project's strategy for the shortest makespan.
//!
//! The makespan ends when the last robot is home, so what matters is the
//! slowest robot's explore-and-return time, not the sum of travel. Tempo:
//!
//! 1. re-assigns the whole team at every decision (min-sum Hungarian on the
//!    true turn-aware travel times, so committed robots switch when a better
//!    split appears), on partial fields grown only as far as the candidates;
//! 2. exploits the completion rule: a frontier node with three visited
//!    neighbours becomes known for free once its fourth neighbour is
//!    visited, so it costs a little more and robots prefer nodes that open
//!    new ground;
//! 3. is return-aware in the endgame: once there are no more candidates
//!    than robots, it minimises the *largest* travel-plus-way-home
//!    (bottleneck), and a robot without a share goes home instead of
//!    trailing another robot.

use super::assign::{AssignmentObjective, Candidates, hungarian_cols};
use super::{Context, Decision, Strategy, explore_decision, go_home, nearest_or_home};
use crate::map::Block;
use crate::path::{DistField, Flow, PlanCell, PlanError};

/// Tempo's knobs; [`Default`] holds the benchmarked values.
#[derive(Clone, Copy, Debug)]
pub struct TempoConfig {
    /// Extra cost, in edges, of a frontier node with three visited
    /// neighbours.
    pub deduce_penalty_edges: u32,
    /// In the endgame, minimise the largest travel plus way home.
    pub endgame_return: bool,
    /// A robot without a share goes home.
    pub idle_home: bool,
}

impl Default for TempoConfig {
    fn default() -> Self {
        TempoConfig {
            deduce_penalty_edges: 1,
            endgame_return: true,
            idle_home: true,
        }
    }
}

/// See the module docs.
#[derive(Clone, Copy, Debug, Default)]
pub struct Tempo {
    /// Its knobs.
    pub config: TempoConfig,
}

impl<M, F> Strategy<M, F> for Tempo
where
    M: AsRef<[Block]> + AsMut<[Block]>,
    F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
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
        let Some(mut c) = Candidates::collect(ctx, fields, k)? else {
            return match fields.first_mut() {
                Some(f) => nearest_or_home(ctx, f),
                None => Ok(Decision::STAY),
            };
        };
        if c.m == 0 {
            return match fields.get_mut(me) {
                Some(f) => go_home(ctx, f),
                None => Ok(Decision::STAY),
            };
        }
        let pen = i64::from(self.config.deduce_penalty_edges) * i64::from(ctx.timing.edge);
        for col in 0..c.m {
            let Some(&node) = c.nodes.get(col) else {
                continue;
            };
            if ctx
                .map
                .cell_at(node)
                .is_some_and(|x| x.visited_neighbours() == 3)
            {
                for j in 0..k {
                    c.add(j, col, pen);
                }
            }
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
                        Some(d) => c.add(j, col, i64::from(d)),
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
            Some(i) => Ok(explore_decision(ctx, f, i)),
            None if self.config.idle_home => go_home(ctx, f),
            None => nearest_or_home(ctx, f),
        }
    }
}
