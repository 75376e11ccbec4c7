//! A lower bound of a robot's cost for the frontier nodes its search has
//! not reached yet, from where those nodes lie: see [`FrontierFloor`].
//!
//! ## Why
//!
//! Tempo's cost for a frontier node is the robot's travel to it less a
//! home pull, a quarter edge per edge of Manhattan distance between the
//! node and the robot's home. A robot's picks search stops once no node
//! at its travel or beyond can beat its last pick, and the generic floor
//! assumes a node that far away pulls as hard as the triangle inequality
//! allows. A robot whose nearest work lies 100 edges away then searches
//! a third farther than its picks lie; on rooms 256² with 16 robots the
//! 3.6 % of the searches that reached 16 384 nodes or more held 60 % of
//! all the nodes the searches reached (docs/results/performance.md,
//! stop 58). The frontier nodes themselves say how hard
//! each can pull, and none can be reached in less than its Manhattan
//! distance, so a robot's floor can count what is really out there.

use super::{MAX_ROBOTS, RobotView};
use crate::geometry::Pos;
use crate::map::{Block, KnownMap};
use crate::timing::Ticks;

/// A cost by robot and travel: a robot's cost of a travel, or a bound.
pub(crate) type Travel<'a> = dyn Fn(usize, Ticks) -> i64 + Sync + 'a;

/// Buckets of Manhattan distance per robot. 256 keep one edge per bucket
/// up to 128² windows and two on 256²; the table is 32 KiB, built on the
/// stack of [`FrontierFloor::with`] alone, which only teams above the
/// tie-break size call (never the six robots of a lab).
const BUCKETS: usize = 256;

/// For each robot and each bucket of Manhattan distance `m` from the
/// robot (`width` edges per bucket, enough buckets for the window):
/// - `pull_within[b]`: the strongest home pull of a frontier node in
///   buckets `0..=b`;
/// - `beyond[b]`: the least of `travel(edge × m) − pull` over the frontier
///   nodes in buckets `b..`.
///
/// A node not reached at travel `d` is reached at `d' ≥ d` and
/// `d' ≥ edge × m`, so its cost is at least `travel(max(d, edge × m)) −
/// pull`. With `a = ⌊d / edge⌋`, a node in a bucket that lies wholly
/// within `a` costs at least `travel(d) − pull` (`pull_within`), and any
/// other node at least `travel(edge × m) − pull` (`beyond`). The bound is
/// the least of the two: at least the generic floor (the pull of a node
/// is at most a quarter edge per edge beyond the robot's own distance
/// from home, and at most the farthest node's), and non-decreasing in
/// `d`: a bucket passes from `beyond` to `pull_within` only once all its
/// nodes lie within `a`, where `travel(d)` is no less than theirs.
pub(crate) struct FrontierFloor {
    pull_within: [[i32; BUCKETS]; MAX_ROBOTS],
    beyond: [[i32; BUCKETS]; MAX_ROBOTS],
    width: u32,
    edge: Ticks,
}

/// Saturates towards the smaller value, so that a clamped bound stays a
/// lower bound (`beyond`) and a clamped pull is never weaker than the
/// real one (pulls are far below `i32::MAX`).
fn down(x: i64) -> i32 {
    i32::try_from(x).unwrap_or(if x > 0 { i32::MAX } else { i32::MIN })
}

impl FrontierFloor {
    /// Builds the table for `robots` on `map` and hands `run` the bound:
    /// `bound(j, d)` for robot `j` at travel `d`, to be scaled like the
    /// costs. `pull(j, node)` is robot `j`'s home pull for a node and
    /// `travel(j, d)` its cost of travel `d`, both as the costs count them.
    /// The table lives in this call's frame only (see [`BUCKETS`]).
    #[inline(never)]
    pub(crate) fn with<M, R>(
        map: &KnownMap<M>,
        robots: &[RobotView],
        edge: Ticks,
        (pull, travel): (
            &impl Fn(usize, Pos) -> i64,
            &(impl Fn(usize, Ticks) -> i64 + Sync),
        ),
        run: impl for<'t> FnOnce(&'t Travel<'t>) -> R,
    ) -> R
    where
        M: AsRef<[Block]> + AsMut<[Block]>,
    {
        let b = map.bounds();
        // Every Manhattan distance in the window (below `span`) has a
        // bucket of its own: no bucket is clamped.
        let span = u32::from(b.width) + u32::from(b.height);
        let width = span.div_ceil(BUCKETS as u32).max(1);
        let mut t = FrontierFloor {
            pull_within: [[i32::MIN; BUCKETS]; MAX_ROBOTS],
            beyond: [[i32::MAX; BUCKETS]; MAX_ROBOTS],
            width,
            edge: edge.max(1),
        };
        // One pass over the frontier (a scan of the map's blocks) for all
        // robots, then the running extremes per robot.
        let k = robots.len().min(MAX_ROBOTS);
        for f in map.frontier() {
            let rows = t.pull_within.iter_mut().zip(t.beyond.iter_mut());
            for (j, ((within, beyond), r)) in rows.zip(robots).enumerate() {
                let m = r.pos.manhattan(f);
                let bucket = ((m / width) as usize).min(BUCKETS - 1);
                let p = pull(j, f);
                if let (Some(w), Some(x)) = (within.get_mut(bucket), beyond.get_mut(bucket)) {
                    *w = (*w).max(down(p));
                    *x = (*x).min(down(travel(j, m.saturating_mul(edge)).saturating_sub(p)));
                }
            }
        }
        let rows = t.pull_within.iter_mut().zip(t.beyond.iter_mut());
        for (within, beyond) in rows.take(k) {
            // Running maximum up, running minimum down.
            let mut most = i32::MIN;
            for w in within.iter_mut() {
                most = most.max(*w);
                *w = most;
            }
            let mut least = i32::MAX;
            for x in beyond.iter_mut().rev() {
                least = least.min(*x);
                *x = least;
            }
        }
        let t = &t;
        run(&|j: usize, d: Ticks| t.at(j, d, travel(j, d)))
    }

    /// Robot `j`'s bound at travel `d`, whose cost is `travel_d`.
    fn at(&self, j: usize, d: Ticks, travel_d: i64) -> i64 {
        let (Some(within), Some(beyond)) = (self.pull_within.get(j), self.beyond.get(j)) else {
            return i64::MIN;
        };
        // Buckets wholly within a = ⌊d / edge⌋ edges.
        let full = ((d / self.edge).saturating_add(1) / self.width) as usize;
        let near = match full
            .checked_sub(1)
            .and_then(|b| within.get(b.min(BUCKETS - 1)))
        {
            Some(&w) if w != i32::MIN => travel_d.saturating_sub(i64::from(w)),
            _ => i64::MAX,
        };
        let far = beyond.get(full).map_or(i64::MAX, |&x| i64::from(x));
        near.min(far)
    }
}

#[cfg(test)]
mod tests;
