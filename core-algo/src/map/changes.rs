//! The last few nodes that became passable, by map revision: see
//! [`KnownMap::passable_since`](super::KnownMap::passable_since).

/// How many changes the log keeps: a visit makes at most five nodes
/// passable (the node and four deduced neighbours), and a planner asks
/// about the last few revisions.
const LOG: usize = 32;

/// A ring of (revision after the change, node index) pairs.
#[derive(Clone, Debug)]
pub(super) struct Changes {
    log: [(u32, u32); LOG],
    /// Changes pushed since the log was cleared.
    pushed: usize,
    /// The log holds every change made after this revision, and no older
    /// ones are asked for.
    floor: u32,
}

impl Changes {
    /// An empty log that answers for changes after `revision`.
    pub(super) fn new(revision: u32) -> Changes {
        Changes {
            log: [(0, 0); LOG],
            pushed: 0,
            floor: revision,
        }
    }

    /// Node `i` became passable, making the map's revision `revision`.
    pub(super) fn push(&mut self, revision: u32, i: usize) {
        let slot = self.pushed % LOG;
        if self.pushed >= LOG {
            // The oldest change falls out: changes of its revision are no
            // longer all here.
            if let Some(&(dropped, _)) = self.log.get(slot) {
                self.floor = dropped;
            }
        }
        if let Some(e) = self.log.get_mut(slot) {
            *e = (revision, i as u32);
        }
        self.pushed = self.pushed.saturating_add(1);
    }

    /// The nodes that became passable after revision `since`, up to
    /// revision `now`; `None` if the log no longer reaches back that far.
    pub(super) fn since(&self, since: u32, now: u32) -> Option<impl Iterator<Item = usize> + '_> {
        // Revisions wrap: compare by age relative to `now`.
        let age = move |r: u32| now.wrapping_sub(r);
        if age(since) > age(self.floor) {
            return None;
        }
        let kept = self.pushed.min(LOG);
        Some(
            (self.pushed - kept..self.pushed)
                .filter_map(move |n| self.log.get(n % LOG).copied())
                .filter(move |&(r, _)| age(r) < age(since))
                .map(|(_, i)| i as usize),
        )
    }
}
