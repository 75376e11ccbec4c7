//! A whole reverse field copied from another field: see
//! [`DistField::copy_reverse_from`].
//!
//! Why: once the map is complete, every robot of a team knows the same
//! graph, and each searches a whole reverse field to every team mate's
//! home to read the ways they drive home (`agent::homecoming`). A host
//! that runs the whole team (the simulator) can search each home's field
//! once and hand copies out: on a 256² maze with 16 robots those searches
//! were a fifth of the homecoming, 240 of them for 16 distinct fields
//! (docs/results/performance.md, stop 51).

use super::{DistField, PlanCell};
use crate::map::{Block, KnownMap};

impl<S: AsRef<[PlanCell]> + AsMut<[PlanCell]>> DistField<S> {
    /// Makes this field a copy of `from`, a completed
    /// [`DistField::compute_reverse`] without marks, as if it had been
    /// searched over `map`. The caller vouches that `map` reads exactly as
    /// the map `from` was searched over ([`node_mark`](super::node_mark)
    /// of every node, as equal [`MapPrint`](crate::map::MapPrint)s tell):
    /// a reverse search reads nothing else of the map, so
    /// the copy is what a search over `map` would have left. Whether it
    /// copied: `from` must be such a field, of the same window and scratch
    /// size as this one.
    pub fn copy_reverse_from<T, M>(&mut self, from: &DistField<T>, map: &KnownMap<M>) -> bool
    where
        T: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
        M: AsRef<[Block]> + AsMut<[Block]>,
    {
        let whole = from.reverse.is_some()
            && from.way.is_none()
            && from.memo.is_none()
            && !from.weighted
            && !from.jumping
            && from.bounds == map.bounds()
            && from.cells.as_ref().len() == self.cells.as_ref().len();
        if !whole {
            return false;
        }
        let cells = self.cells.as_mut();
        core::mem::take(&mut self.dirty).for_each_row(|r| {
            if let Some(row) = cells.get_mut(r) {
                row.fill(PlanCell::EMPTY);
            }
        });
        let source = from.cells.as_ref();
        from.dirty.for_each_row(|r| {
            if let (Some(to), Some(src)) = (cells.get_mut(r.clone()), source.get(r)) {
                to.copy_from_slice(src);
            }
        });
        let rev = map.revision();
        self.dirty = from.dirty;
        self.tree = from.tree.map(|_| rev);
        self.queue = from.queue;
        self.bounds = from.bounds;
        self.start = from.start;
        self.timing = from.timing;
        self.way = None;
        self.reverse = from.reverse.map(|(g, _)| (g, rev));
        self.rev_open = from.rev_open.map(|(g, _)| (g, rev));
        self.memo = None;
        self.weighted = false;
        self.jumping = false;
        self.jumps = from.jumps.clone();
        true
    }
}

#[cfg(test)]
mod tests;
