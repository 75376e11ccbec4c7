//! The uncoordinated floor and the simplest coordination.

use super::{Context, Decision, Strategy, cheapest_frontier, explore_decision, go_home};
use crate::map::Block;
use crate::path::{DistField, PlanCell, PlanError};
use crate::timing::Ticks;

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
        // One search for both: the nearest claimed node is only wanted when
        // no unclaimed one exists, and then the search has seen them all.
        let mut nearest: Option<(Ticks, usize)> = None;
        let unclaimed = cheapest_frontier(ctx, field, |i, p, d| {
            if nearest.is_none_or(|b| (d, i) < b) {
                nearest = Some((d, i));
            }
            (!claimed(p)).then_some(0)
        })?;
        match unclaimed.map(|(i, _)| i).or(nearest.map(|(_, i)| i)) {
            Some(i) => Ok(explore_decision(ctx, field, i)),
            None => go_home(ctx, field),
        }
    }
}
