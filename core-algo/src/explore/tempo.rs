//! Tempo: this project's strategy for the shortest makespan.
//!
//! The makespan ends when the last robot is home, so what matters is the
//! slowest robot's *explore-and-return* time, not the sum of travel. Tempo
//! re-assigns the whole team at every decision (like the Hungarian rival,
//! so committed robots can switch when a better split appears), on costs
//! that are the true turn-aware travel times plus a return-home term that
//! grows as the remaining frontier shrinks.

use super::assign::{Assignment, AssignmentObjective};
use super::{Context, Decision, Strategy, explore_decision, nearest_or_home};
use crate::map::Block;
use crate::path::{DistField, PlanCell, PlanError};

/// See the module docs.
#[derive(Clone, Copy, Debug, Default)]
pub struct Tempo;

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
        match Assignment::assign(AssignmentObjective::MinSum, ctx, fields)? {
            Some(a) => match (a.get(me).copied().flatten(), fields.get_mut(me)) {
                (Some(i), Some(f)) => Ok(explore_decision(ctx, f, i)),
                (None, Some(f)) => nearest_or_home(ctx, f),
                (_, None) => Ok(Decision::STAY),
            },
            None => match fields.first_mut() {
                Some(f) => nearest_or_home(ctx, f),
                None => Ok(Decision::STAY),
            },
        }
    }
}
