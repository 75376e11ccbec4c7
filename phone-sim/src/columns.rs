//! The host's store of the endgame's column searches, one per frontier
//! node and map print for every robot it runs (see
//! [`core_algo::explore::SharedColumns`]).
//!
//! A search is lent only to a robot whose map had the print it was
//! searched for, and the robot carries it over from that revision as its
//! own, so what this holds (another robot's search, another run's) never
//! changes a decision: it saves the search, nothing else.

use core_algo::explore::SharedColumns;
use core_algo::map::MapPrint;
use core_algo::path::{DistField, PlanCell};
use std::any::Any;
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};

/// The host's field type: what every simulated robot plans in.
type Field = DistField<Vec<PlanCell>>;

/// Bytes of kept searches at most, oldest out first: a 16-robot endgame
/// on 256² keeps a few dozen fields of 1 MiB.
const MAX_BYTES: usize = 128 << 20;

/// Bytes of fields holding nothing, kept for robots to swap in, at most
/// (takes and gives alternate, so a few are enough).
const MAX_SPARE_BYTES: usize = 64 << 20;

/// See the module docs.
#[derive(Debug, Default)]
pub struct HostColumns {
    store: Mutex<Store>,
    taken: AtomicU64,
    given: AtomicU64,
}

#[derive(Default)]
struct Store {
    /// Searches kept, oldest first.
    kept: Vec<Kept>,
    /// Fields that hold no search, to hand back for a search given.
    spare: Vec<Field>,
}

impl std::fmt::Debug for Store {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Store")
            .field("kept", &self.kept.len())
            .field("spare", &self.spare.len())
            .finish()
    }
}

/// One open reverse search to `goal` over a map with `print`.
struct Kept {
    goal: usize,
    print: MapPrint,
    field: Field,
}

fn bytes(f: &Field) -> usize {
    f.capacity() * size_of::<PlanCell>()
}

impl Store {
    /// Keeps `f`, which holds no search, for a later swap.
    fn spare(&mut self, mut f: Field) {
        let held: usize = self.spare.iter().map(bytes).sum();
        if held + bytes(&f) <= MAX_SPARE_BYTES {
            f.forget();
            self.spare.push(f);
        }
    }
}

impl HostColumns {
    /// Nothing kept yet.
    pub const fn new() -> HostColumns {
        HostColumns {
            store: Mutex::new(Store {
                kept: Vec::new(),
                spare: Vec::new(),
            }),
            taken: AtomicU64::new(0),
            given: AtomicU64::new(0),
        }
    }

    /// Searches lent out and searches given back, so far.
    pub fn counts(&self) -> (u64, u64) {
        (
            self.taken.load(Ordering::Relaxed),
            self.given.load(Ordering::Relaxed),
        )
    }

    fn store(&self) -> std::sync::MutexGuard<'_, Store> {
        // A poisoned lock only means another thread panicked while holding
        // it: every entry in it is whole.
        self.store.lock().unwrap_or_else(|e| e.into_inner())
    }
}

impl SharedColumns for HostColumns {
    fn take(
        &self,
        goal: usize,
        revision_of: &dyn Fn(MapPrint) -> Option<u32>,
        field: &mut dyn Any,
    ) -> Option<u32> {
        let field = field.downcast_mut::<Field>()?;
        let mut store = self.store();
        let (at, rev) = store
            .kept
            .iter()
            .enumerate()
            .rev()
            .filter(|(_, k)| k.goal == goal && k.field.capacity() == field.capacity())
            .find_map(|(at, k)| Some((at, revision_of(k.print)?)))?;
        let mut kept = store.kept.remove(at);
        std::mem::swap(field, &mut kept.field);
        store.spare(kept.field);
        self.taken.fetch_add(1, Ordering::Relaxed);
        Some(rev)
    }

    fn give(&self, goal: usize, print: MapPrint, field: &mut dyn Any) {
        let Some(field) = field.downcast_mut::<Field>() else {
            return;
        };
        let cap = field.capacity();
        let mut store = self.store();
        let spare = match store.spare.iter().position(|f| f.capacity() == cap) {
            Some(at) => store.spare.swap_remove(at),
            None => Field::new(vec![PlanCell::EMPTY; cap]),
        };
        let search = std::mem::replace(field, spare);
        // One search per goal and print: the one given last has grown
        // the farthest.
        if let Some(at) = store
            .kept
            .iter()
            .position(|k| k.goal == goal && k.print == print && k.field.capacity() == cap)
        {
            let old = store.kept.remove(at);
            store.spare(old.field);
        }
        store.kept.push(Kept {
            goal,
            print,
            field: search,
        });
        let mut total: usize = store.kept.iter().map(|k| bytes(&k.field)).sum();
        while total > MAX_BYTES && !store.kept.is_empty() {
            let old = store.kept.remove(0);
            total -= bytes(&old.field);
            store.spare(old.field);
        }
        self.given.fetch_add(1, Ordering::Relaxed);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shared_fields::tests::corridor;
    use core_algo::geometry::{Heading, Pos};
    use core_algo::path::{Flow, min_cells};
    use core_algo::timing::Timing;

    fn field(cells: usize) -> Field {
        DistField::new(vec![PlanCell::EMPTY; cells])
    }

    /// A search given back is lent once, to a robot whose map reads the
    /// same (learnt in another order), for a field of its size; that robot
    /// goes on with it as with its own, to the same field a search of its
    /// own finds.
    #[test]
    fn a_column_search_is_lent_once_to_a_map_that_reads_the_same() {
        let host = HostColumns::new();
        let t = Timing {
            edge: 10,
            quarter_turn: 5,
        };
        let (a, b) = (corridor(12, true), corridor(12, false));
        let goal = 3;
        let cells = min_cells(12);
        // Stopped after a few states: an open search.
        let mut given = field(cells);
        let mut n = 0;
        given
            .compute_reverse(&a, t, Pos::new(3, 0), |_, _, _| {
                n += 1;
                if n < 5 { Flow::Continue } else { Flow::Stop }
            })
            .unwrap();
        assert_eq!(given.reverse_goal(), Some(goal));
        host.give(goal, a.print(), &mut given);
        assert_eq!(given.reverse_goal(), None, "the giver keeps nothing");
        assert_eq!(given.capacity(), cells);

        let other = corridor(11, true);
        let mut mine = field(cells);
        assert_eq!(host.take(goal, &|p| other.revision_of(p), &mut mine), None);
        assert_eq!(host.take(4, &|p| b.revision_of(p), &mut mine), None);
        let mut larger = field(cells + 64);
        assert_eq!(host.take(goal, &|p| b.revision_of(p), &mut larger), None);

        let rev = host.take(goal, &|p| b.revision_of(p), &mut mine);
        assert_eq!(rev, Some(b.revision()));
        assert_eq!(
            host.take(goal, &|p| b.revision_of(p), &mut field(cells)),
            None
        );
        assert!(mine.adopt_reverse(b.revision()));
        assert!(mine.refresh_reverse(&b, t));
        mine.resume_reverse(&b, |_, _, _| Flow::Continue).unwrap();
        let mut fresh = field(cells);
        fresh
            .compute_reverse(&b, t, Pos::new(3, 0), |_, _, _| Flow::Continue)
            .unwrap();
        for v in 0..12 {
            for h in Heading::ALL {
                assert_eq!(mine.dist_pose_at(v, h), fresh.dist_pose_at(v, h));
            }
        }
        assert_eq!(host.counts(), (1, 1));
    }
}
