//! The uncoordinated floor and the simplest coordination.

use super::{Context, Decision, Strategy, cheapest_frontier, explore_decision, go_home};
use crate::map::Block;
use crate::path::{DistField, PlanCell, PlanError};

/// Yamauchi's nearest frontier: each robot drives to the frontier node it
/// reaches soonest, ignoring the others. The floor every coordinated
/// strategy must beat.
#[derive(Clone, Copy, Debug, Default)]
pub struct NearestFrontier;

impl<M, F> Strategy<M, F> for NearestFrontier
where
    M: AsRef<[Block]> + AsMut<[Block]>,
    F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
{
    fn name(&self) -> &'static str {
        "nearest"
    }

    fn decide(
        &mut self,
        ctx: &Context<'_, M>,
        fields: &mut [DistField<F>],
    ) -> Result<Decision, PlanError> {
        let Some(field) = fields.first_mut() else {
            return Ok(Decision::STAY);
        };
        super::nearest_or_home(ctx, field)
    }
}

/// Greedy claim: the nearest frontier node that no other robot has
/// announced; the nearest announced one when all are claimed (a robot never
/// idles while work remains).
#[derive(Clone, Copy, Debug, Default)]
pub struct GreedyClaim;

impl<M, F> Strategy<M, F> for GreedyClaim
where
    M: AsRef<[Block]> + AsMut<[Block]>,
    F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
{
    fn name(&self) -> &'static str {
        "claim"
    }

    fn decide(
        &mut self,
        ctx: &Context<'_, M>,
        fields: &mut [DistField<F>],
    ) -> Result<Decision, PlanError> {
        let Some(field) = fields.first_mut() else {
            return Ok(Decision::STAY);
        };
        let claimed = |p| {
            ctx.robots
                .iter()
                .enumerate()
                .any(|(j, r)| j != ctx.me && r.target == Some(p))
        };
        if let Some((i, _)) = cheapest_frontier(ctx, field, |_, p, _| (!claimed(p)).then_some(0))? {
            return Ok(explore_decision(ctx, field, i));
        }
        match cheapest_frontier(ctx, field, |_, _, _| Some(0))? {
            Some((i, _)) => Ok(explore_decision(ctx, field, i)),
            None => go_home(ctx, field),
        }
    }
}
