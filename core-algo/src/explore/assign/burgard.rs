//! Burgard et al.'s greedy cost–utility assignment, on the same cost
//! matrix as the Hungarian one.

use super::{Candidates, INF, MAX_CANDIDATES};
use crate::explore::layers::CooperationLayer;
use crate::explore::{
    Context, Decision, MAX_ROBOTS, Strategy, explore_decision, go_home, nearest_or_home,
};
use crate::geometry::Pos;
use crate::map::Block;
use crate::path::{DistField, PlanCell, PlanError};

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
