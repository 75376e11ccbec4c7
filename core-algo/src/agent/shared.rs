//! Whole fields of a complete map that a host running a whole team keeps
//! for every agent: see [`SharedFields`].

use crate::geometry::Pos;
use crate::map::KnownMap;
use crate::path::DistField;
use crate::timing::Timing;

/// Whole reverse fields to team mates' homes, kept by a host that runs
/// every agent of a team (the simulator) so that each is searched once,
/// not once per robot. A robot keeps none (it is its own host).
///
/// Once the map is complete every robot searches a whole reverse field to
/// every returning team mate's home, to read the way it drives home
/// (`Agent::keep_out_of_the_way`); the complete maps are alike, so the
/// fields are too. On a 256² maze with 16 robots those searches were a
/// fifth of the homecoming (docs/results/performance.md, stop 51).
///
/// A host hands a field (or a depth) over only for a map with the print
/// of the one it was worked out on ([`crate::map::MapPrint`]: maps that
/// read the same at every node), so what it holds never changes a decision
/// (see [`DistField::copy_reverse_from`]).
pub trait SharedFields<M, F>: Sync {
    /// Makes `field` the whole reverse field to `goal` over `map` with
    /// `timing`, if one is kept for a map that reads the same; whether it
    /// did.
    fn recall_reverse(
        &self,
        map: &KnownMap<M>,
        timing: Timing,
        goal: Pos,
        field: &mut DistField<F>,
    ) -> bool;
    /// Keeps a copy of `field`, the whole reverse field to `goal` just
    /// searched over `map` with `timing`.
    fn keep_reverse(&self, map: &KnownMap<M>, timing: Timing, goal: Pos, field: &DistField<F>);

    /// The depth of `home` (its total time to every node, see
    /// `Agent::fill_ranks`) over a map with `map`'s print and `timing`, if
    /// one is kept. Every robot of a team works out every home's depth once
    /// the map is complete: a whole search per home, 256 of them on a
    /// 16-robot team for 16 numbers (docs/results/performance.md, stop 53).
    fn home_depth(&self, map: &KnownMap<M>, timing: Timing, home: Pos) -> Option<u64> {
        let _ = (map, timing, home);
        None
    }

    /// Keeps `depth`, the depth of `home` just worked out over `map` with
    /// `timing`.
    fn keep_home_depth(&self, map: &KnownMap<M>, timing: Timing, home: Pos, depth: u64) {
        let _ = (map, timing, home, depth);
    }
}
