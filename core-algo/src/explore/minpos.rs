//! MinPos (Bautin, Simonin, Charpillet, ICIRA 2012): each robot ranks
//! itself among the team by travel time to every frontier node and takes a
//! node where its rank is lowest, nearest first. Decentralised in spirit: it
//! needs the others' positions, not their targets.

use super::{Context, Decision, Strategy, explore_decision, go_home, nearest_or_home};
use crate::map::Block;
use crate::path::{DistField, PlanCell, PlanError};
use crate::timing::Ticks;

/// MinPos over frontier nodes. Frontier *clusters* (4-connected runs of
/// frontier nodes) are ranked by their cheapest node, so that a robot does
/// not count a whole frontier line against the others node by node: a
/// node's rank is the number of robots that reach its cluster's
/// representative sooner (ties by robot id).
#[derive(Clone, Copy, Debug, Default)]
pub struct MinPos;

impl<M, F> Strategy<M, F> for MinPos
where
    M: AsRef<[Block]> + AsMut<[Block]>,
    F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
{
    fn name(&self) -> &'static str {
        "minpos"
    }

    fn decide(
        &mut self,
        ctx: &Context<'_, M>,
        fields: &mut [DistField<F>],
    ) -> Result<Decision, PlanError> {
        let k = ctx.robots.len();
        let me = ctx.me;
        if fields.len() < k || me >= k {
            return match fields.first_mut() {
                Some(f) => nearest_or_home(ctx, f),
                None => Ok(Decision::STAY),
            };
        }
        for (r, f) in ctx.robots.iter().zip(fields.iter_mut()) {
            f.compute(ctx.map, ctx.timing, r.pos, r.heading, |_, _| {
                crate::path::Flow::Continue
            })?;
        }
        let eta = |j: usize, i: usize| -> Option<Ticks> {
            let r = ctx.robots.get(j)?;
            Some(fields.get(j)?.dist_at(i)?.saturating_add(r.eta))
        };
        let bounds = ctx.map.bounds();
        let mut best: Option<(usize, Ticks, usize)> = None;
        for p in ctx.map.frontier() {
            let Some(i) = bounds.index(p) else { continue };
            let Some(mine) = eta(me, i) else { continue };
            // The cluster representative: this node and its 4-neighbouring
            // frontier nodes, taken at the best time of each robot.
            let cluster = |j: usize| -> Option<Ticks> {
                let mut t = eta(j, i);
                for h in crate::geometry::Heading::ALL {
                    if let Some(n) = crate::path::neighbour_index(bounds, i, h) {
                        if ctx.map.is_frontier_at(n) {
                            if let Some(x) = eta(j, n) {
                                t = Some(t.map_or(x, |y: Ticks| y.min(x)));
                            }
                        }
                    }
                }
                t
            };
            let Some(my_c) = cluster(me) else { continue };
            let rank = (0..k)
                .filter(|&j| j != me)
                .filter(|&j| cluster(j).is_some_and(|t| t < my_c || (t == my_c && j < me)))
                .count();
            let cand = (rank, mine, i);
            if best.is_none_or(|b| cand < b) {
                best = Some(cand);
            }
        }
        let Some(f) = fields.get_mut(me) else {
            return Ok(Decision::STAY);
        };
        match best {
            Some((_, _, i)) => Ok(explore_decision(ctx, f, i)),
            None => go_home(ctx, f),
        }
    }
}
