//! The team mates a tempo decision leaves out of its assignment: those
//! that keep a far share, and those outside the deciding robot's cluster.

use super::{FarRule, commitment};
use crate::explore::assign::is_left_out;
use crate::explore::{Context, RobotView};
use crate::map::Block;

/// The team mates that keep a far share, as each will (see
/// `Commitment::holds`): the frontier node each announced, where
/// `commitment::keeps_far` holds for it (far from it, no other robot
/// announcing it or, with `far.1`, standing near it). They are left out
/// of the deciding robot's assignment (bit j: robot j), their shares with
/// them, and their fields are not searched: robots on a long way to work
/// cost most to search and, keeping their shares, would not change. Never
/// in the endgame (fewer frontier nodes than robots), where the reverse
/// searches look for every robot.
pub(super) fn keeping_far<M>(
    ctx: &Context<'_, M>,
    far: FarRule,
) -> (u32, [Option<usize>; crate::explore::MAX_ROBOTS])
where
    M: AsRef<[Block]> + AsMut<[Block]>,
{
    let mut left_out = 0u32;
    let mut shares = [None; crate::explore::MAX_ROBOTS];
    let map = ctx.map;
    if far.edges == 0 || map.frontier_len() < ctx.robots.len() {
        return (left_out, shares);
    }
    for (j, r) in ctx.robots.iter().enumerate() {
        let Some(t) = r.target.filter(|_| j != ctx.me) else {
            continue;
        };
        let share = map.bounds().index(t).filter(|&i| map.is_frontier_at(i));
        if let (Some(i), Some(slot)) = (share, shares.get_mut(j)) {
            if commitment::keeps_far(ctx, j, t, far) {
                *slot = Some(i);
                left_out |= 1 << (j % 32);
            }
        }
    }
    (left_out, shares)
}

/// Leaves out of the deciding robot's assignment (bit j in `left_out`,
/// the announced target in `shares`) every team mate outside its cluster:
/// the robots it reaches by steps of at most `radius` edges (Manhattan)
/// from robot to robot. Every robot of a cluster finds the same cluster
/// from the same views, so they agree on its assignment; robots of
/// different clusters stand far apart, and each leaves the others'
/// announced targets to them. Not in the endgame (fewer frontier nodes
/// than robots), as with `keeping_far`.
pub(super) fn outside_cluster<M>(
    ctx: &Context<'_, M>,
    radius: u32,
    left_out: &mut u32,
    shares: &mut [Option<usize>; crate::explore::MAX_ROBOTS],
) where
    M: AsRef<[Block]> + AsMut<[Block]>,
{
    let map = ctx.map;
    let robots = ctx.robots;
    if radius == 0 || map.frontier_len() < robots.len() {
        return;
    }
    // Two robots are close if where they stand or where they head lie
    // within `radius` of each other.
    let close = |a: &RobotView, b: &RobotView| {
        let pa = [Some(a.pos), a.target];
        let pb = [Some(b.pos), b.target];
        pa.iter()
            .flatten()
            .any(|p| pb.iter().flatten().any(|q| p.manhattan(*q) <= radius))
    };
    // One bit per robot, as in `left_out`: the cluster grows from the
    // deciding robot, each member looked at once for the robots close to it.
    let holds = |mask: u32, j: usize| is_left_out(mask, j);
    let mut inside = 1u32 << (ctx.me % 32);
    let mut todo = inside;
    while todo != 0 {
        let o = todo.trailing_zeros() as usize;
        todo &= todo - 1;
        let Some(x) = robots.get(o) else { continue };
        for (j, r) in robots.iter().enumerate() {
            if !holds(inside, j) && close(x, r) {
                inside |= 1 << (j % 32);
                todo |= 1 << (j % 32);
            }
        }
    }
    for (j, r) in robots.iter().enumerate() {
        if holds(inside, j) || holds(*left_out, j) {
            continue;
        }
        *left_out |= 1 << (j % 32);
        let share = r
            .target
            .and_then(|t| map.bounds().index(t))
            .filter(|&i| map.is_frontier_at(i));
        if let Some(slot) = shares.get_mut(j) {
            *slot = share;
        }
    }
}
