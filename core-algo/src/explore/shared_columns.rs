//! The endgame's column searches, kept once for a whole simulated team:
//! see [`SharedColumns`].
//!
//! Why: in the reverse endgame every robot of a team searches backwards
//! from every frontier node to find its cheapest robots (see
//! `Candidates::reverse_columns`). All robots decide on the same map, so
//! they grow the same searches, each in its own slots: on maze 128² with
//! 16 robots those searches settled 193 M states, and only 35 000 of the
//! 675 000 searches were of a node and map that no robot had searched
//! before (docs/results/performance.md, stop 53). A host that runs
//! the whole team keeps each search once and lends it to whichever robot
//! decides on a map that reads the same, so each state is settled once
//! per team. A robot keeps nothing of the kind: it is its own host.

use crate::map::MapPrint;
use core::any::Any;

/// A host's store of open reverse searches, one per frontier node and map
/// print, lent to the robots it runs.
///
/// Searches travel by swapping whole fields: the host's fields are the
/// robots' own type, which only the host knows, so they pass as
/// [`Any`]. A field lent out leaves the store until it is given back, so
/// no two robots ever hold one search. What the store holds never changes
/// a decision: a search is lent only for a map whose print the robot's
/// map had, at a revision where it read as the lender's did, and the
/// robot carries it over from there as if it were its own (see
/// [`DistField::adopt_reverse`](crate::path::DistField::adopt_reverse)).
pub trait SharedColumns: Sync {
    /// Swaps `field` with the kept search to node `goal` whose map print
    /// `revision_of` knows (the newest such revision if several), if one
    /// is kept for a field like `field`; the revision it holds for, if it
    /// did. The search is the caller's until it hands it back with
    /// [`SharedColumns::give`]; what the caller's field held is forgotten.
    fn take(
        &self,
        goal: usize,
        revision_of: &dyn Fn(MapPrint) -> Option<u32>,
        field: &mut dyn Any,
    ) -> Option<u32>;

    /// Keeps the open reverse search to node `goal` in `field`, searched
    /// over a map with `print`, and leaves `field` holding no search.
    fn give(&self, goal: usize, print: MapPrint, field: &mut dyn Any);
}
