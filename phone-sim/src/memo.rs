//! The simulator's memo of forward searches (see
//! [`core_algo::path::SearchMemo`]): the team mates' searches that every
//! robot of a simulated team repeats, kept for the decisions that follow.
//!
//! A search is taken over only where every node it read reads the same
//! in the deciding robot's map, or in part, as far as every node it
//! reached reads the same; so what the memo holds, or which search
//! recorded it (another robot's, another run's), never changes a
//! decision: it saves the search, nothing else.

use core_algo::path::{
    PlanCell, Reached, RecordedSearch, SearchKey, SearchMemo, SearchRecorder, SearchState,
};
use std::collections::{BTreeMap, VecDeque};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

/// Searches kept per start pose: a team mate's pose is searched again
/// while it drives an edge, on maps that grow elsewhere. As many rests of
/// a search are kept per record they go on from.
const PER_KEY: usize = 4;

/// Bytes of records kept at most; the oldest go first. A team mate's pose
/// is searched again within a few decisions, so a few thousand records
/// (rooms 256², 16 robots: about 30 KiB each) keep nearly every search
/// that is taken over.
const MAX_BYTES: usize = 64 << 20;

/// Nodes a record may hold: a search that reaches more (a whole 1024²
/// window) is not kept.
const MAX_REACHED: usize = 1 << 18;

/// What a [`HostMemo`] did so far (see [`HostMemo::counts`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MemoCounts {
    /// Searches taken over, whole or in part.
    pub taken_over: u64,
    /// Of those, the ones taken over in part.
    pub in_part: u64,
    /// Rests of searches taken over, that went on where a field stood (see
    /// [`SearchMemo::record_after`]).
    pub after: u64,
    /// Searches written down.
    pub recorded: u64,
    /// Rests of searches written down.
    pub recorded_after: u64,
}

/// See the module docs.
#[derive(Debug)]
pub struct HostMemo {
    store: Mutex<Store>,
    taken_over: AtomicU64,
    in_part: AtomicU64,
    after: AtomicU64,
    recorded: AtomicU64,
    recorded_after: AtomicU64,
    /// The last record's id: ids are never 0 nor used twice.
    last_id: AtomicU64,
}

#[derive(Debug)]
struct Store {
    by_key: BTreeMap<SearchKey, Vec<Arc<Record>>>,
    /// The rests of searches, by the record they go on from.
    by_after: BTreeMap<u64, Vec<Arc<Record>>>,
    /// Every record kept, oldest first, for eviction. One pushed out of
    /// its pose's list by newer ones stays here, and counted in `bytes`,
    /// until it is evicted.
    order: VecDeque<Arc<Record>>,
    bytes: usize,
}

#[derive(Debug)]
struct Record {
    key: SearchKey,
    id: u64,
    after: u64,
    reached: Vec<Reached>,
    read: Vec<(u32, u8)>,
    cells: Vec<(u32, PlanCell)>,
    queued: [Vec<u32>; 2],
    state: SearchState,
}

impl Record {
    /// What it holds on the heap and inline, by capacity.
    fn bytes(&self) -> usize {
        size_of::<Record>()
            + self.reached.capacity() * size_of::<Reached>()
            + self.read.capacity() * size_of::<(u32, u8)>()
            + self.cells.capacity() * size_of::<(u32, PlanCell)>()
            + self.queued.iter().map(Vec::capacity).sum::<usize>() * size_of::<u32>()
    }
}

impl HostMemo {
    /// An empty memo.
    pub const fn new() -> HostMemo {
        HostMemo {
            store: Mutex::new(Store {
                by_key: BTreeMap::new(),
                by_after: BTreeMap::new(),
                order: VecDeque::new(),
                bytes: 0,
            }),
            taken_over: AtomicU64::new(0),
            in_part: AtomicU64::new(0),
            after: AtomicU64::new(0),
            recorded: AtomicU64::new(0),
            recorded_after: AtomicU64::new(0),
            last_id: AtomicU64::new(0),
        }
    }

    /// Searches taken over (whole or in part), of those taken over in
    /// part, and searches recorded (fresh ones and those that went on
    /// from a part taken over), so far.
    pub fn counts(&self) -> MemoCounts {
        MemoCounts {
            taken_over: self.taken_over.load(Ordering::Relaxed),
            in_part: self.in_part.load(Ordering::Relaxed),
            after: self.after.load(Ordering::Relaxed),
            recorded: self.recorded.load(Ordering::Relaxed),
            recorded_after: self.recorded_after.load(Ordering::Relaxed),
        }
    }

    fn insert(&self, record: Record) {
        let record = Arc::new(record);
        // A poisoned lock only means another thread panicked mid-insert:
        // every record in it is whole, so go on with it.
        let mut s = self.store.lock().unwrap_or_else(|e| e.into_inner());
        s.bytes += record.bytes();
        let list = s.list(&record);
        list.push(Arc::clone(&record));
        if list.len() > PER_KEY {
            list.remove(0);
        }
        s.order.push_back(record);
        while s.bytes > MAX_BYTES {
            let Some(old) = s.order.pop_front() else {
                break;
            };
            s.bytes -= old.bytes();
            let list = s.list(&old);
            list.retain(|r| !Arc::ptr_eq(r, &old));
            if list.is_empty() {
                if old.after == 0 {
                    s.by_key.remove(&old.key);
                } else {
                    s.by_after.remove(&old.after);
                }
            }
        }
    }

    /// Hands `take` the records of the list `of` picks (newest first)
    /// until it returns true, and counts one in `took` if it did; whether
    /// it did.
    fn hand(
        &self,
        of: impl FnOnce(&Store) -> Option<&Vec<Arc<Record>>>,
        took: &AtomicU64,
        take: &mut dyn FnMut(RecordedSearch<'_>) -> bool,
    ) -> bool {
        // Out of the lock before trying them: trying one replays the search.
        let list: Vec<Arc<Record>> = {
            let s = self.store.lock().unwrap_or_else(|e| e.into_inner());
            of(&s).cloned().unwrap_or_default()
        };
        for r in list.iter().rev() {
            let rec = RecordedSearch {
                id: r.id,
                after: r.after,
                reached: &r.reached,
                read: &r.read,
                cells: &r.cells,
                queued: [&r.queued[0], &r.queued[1]],
                state: &r.state,
            };
            if take(rec) {
                took.fetch_add(1, Ordering::Relaxed);
                return true;
            }
        }
        false
    }

    /// Runs `search` into a recorder and keeps what it wrote down, if
    /// whole: its id.
    fn keep(
        &self,
        key: SearchKey,
        after: u64,
        search: &mut dyn FnMut(&mut dyn SearchRecorder),
    ) -> Option<u64> {
        let written = SCRATCH.with(|scratch| {
            let mut rec = scratch.take();
            rec.clear();
            search(&mut rec);
            let out = match (rec.state.take(), rec.too_long) {
                (Some(state), false) => Some((rec.to_owned_exact(), state)),
                _ => None,
            };
            scratch.set(rec);
            out
        });
        let (rec, state) = written?;
        let count = if after == 0 {
            &self.recorded
        } else {
            &self.recorded_after
        };
        count.fetch_add(1, Ordering::Relaxed);
        let id = self.last_id.fetch_add(1, Ordering::Relaxed) + 1;
        self.insert(Record {
            key,
            id,
            after,
            reached: rec.reached,
            read: rec.read,
            cells: rec.cells,
            queued: rec.queued,
            state,
        });
        Some(id)
    }
}

impl Store {
    /// The list `r` is kept in.
    fn list(&mut self, r: &Record) -> &mut Vec<Arc<Record>> {
        if r.after == 0 {
            self.by_key.entry(r.key).or_default()
        } else {
            self.by_after.entry(r.after).or_default()
        }
    }
}

impl Default for HostMemo {
    fn default() -> Self {
        HostMemo::new()
    }
}

impl SearchMemo for HostMemo {
    fn recall(&self, key: SearchKey, take: &mut dyn FnMut(RecordedSearch<'_>) -> bool) -> bool {
        self.hand(|s| s.by_key.get(&key), &self.taken_over, take)
    }

    fn recall_after(&self, after: u64, take: &mut dyn FnMut(RecordedSearch<'_>) -> bool) -> bool {
        self.hand(|s| s.by_after.get(&after), &self.after, take)
    }

    fn taken_over_in_part(&self) {
        self.in_part.fetch_add(1, Ordering::Relaxed);
    }

    fn record(
        &self,
        key: SearchKey,
        search: &mut dyn FnMut(&mut dyn SearchRecorder),
    ) -> Option<u64> {
        self.keep(key, 0, search)
    }

    fn record_after(
        &self,
        key: SearchKey,
        after: u64,
        search: &mut dyn FnMut(&mut dyn SearchRecorder),
    ) -> Option<u64> {
        self.keep(key, after, search)
    }
}

thread_local! {
    /// Each thread's recorder, kept between searches with its capacity:
    /// a search is written down into it and copied out at its exact size,
    /// rather than grown by doubling in a fresh one, whose copies and spare
    /// capacity cost time and the memo's room (rooms 128², 16 robots:
    /// 17.6 s against 16.9 s; docs/results/performance.md, stop 56). It
    /// holds at most one search of `MAX_REACHED` nodes.
    static SCRATCH: std::cell::Cell<Recorder> = std::cell::Cell::new(Recorder::default());
}

/// A search being written down.
#[derive(Default)]
struct Recorder {
    reached: Vec<Reached>,
    read: Vec<(u32, u8)>,
    cells: Vec<(u32, PlanCell)>,
    queued: [Vec<u32>; 2],
    state: Option<SearchState>,
    too_long: bool,
}

impl Recorder {
    /// Empty, its capacity kept.
    fn clear(&mut self) {
        self.reached.clear();
        self.read.clear();
        self.cells.clear();
        for q in &mut self.queued {
            q.clear();
        }
        self.state = None;
        self.too_long = false;
    }

    /// What it wrote down, in buffers of the exact size.
    fn to_owned_exact(&self) -> Recorder {
        Recorder {
            reached: self.reached.clone(),
            read: self.read.clone(),
            cells: self.cells.clone(),
            queued: self.queued.clone(),
            state: None,
            too_long: false,
        }
    }
}

impl SearchRecorder for Recorder {
    fn reached(&mut self, r: &[Reached]) {
        if self.reached.len() + r.len() <= MAX_REACHED {
            self.reached.extend_from_slice(r);
        } else {
            self.too_long = true;
        }
    }

    fn read(&mut self, node: u32, mark: u8) {
        if self.read.len() < MAX_REACHED {
            self.read.push((node, mark));
        } else {
            self.too_long = true;
        }
    }

    fn cells_written(&mut self, cells: &[(u32, PlanCell)]) {
        if !self.too_long {
            self.cells.extend_from_slice(cells);
        }
    }

    fn queued(&mut self, ring: usize, entries: &[u32]) {
        if let (false, Some(q)) = (self.too_long, self.queued.get_mut(ring)) {
            q.extend_from_slice(entries);
        }
    }

    fn cells(&mut self) -> &mut [(u32, PlanCell)] {
        &mut self.cells
    }

    fn finish(&mut self, state: SearchState) {
        self.state = Some(state);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use core_algo::geometry::{Arms, Heading, Pos};
    use core_algo::map::{Block, Bounds, KnownMap, blocks_for};
    use core_algo::path::{DistField, Flow, min_cells};
    use core_algo::team::RobotId;
    use core_algo::timing::Timing;

    /// A corridor 12 nodes long, known whole; a timing; a field for it.
    fn corridor() -> (KnownMap<Vec<Block>>, Timing, DistField<Vec<PlanCell>>) {
        let b = Bounds::new(Pos::new(0, 0), 12, 1);
        let mut map = KnownMap::new(vec![Block::EMPTY; blocks_for(b.area())], b).unwrap();
        for x in 0..12 {
            let bits = u8::from(x > 0) << Heading::West.index()
                | u8::from(x < 11) << Heading::East.index();
            map.visit(Pos::new(x, 0), Arms::from_bits(bits), RobotId(0))
                .unwrap();
        }
        let t = Timing {
            edge: 10,
            quarter_turn: 5,
        };
        let f = DistField::new(vec![PlanCell::EMPTY; min_cells(b.area())]);
        (map, t, f)
    }

    /// A search's callback that stops after `stop` nodes.
    fn until(stop: usize) -> impl FnMut(usize, u32) -> Flow {
        let mut seen = 0;
        move |_, _| {
            seen += 1;
            if seen > stop {
                Flow::Stop
            } else {
                Flow::Continue
            }
        }
    }

    /// The rests of a search are kept by the record they go on from,
    /// newest first, and never handed back as whole searches.
    #[test]
    fn rests_are_kept_by_the_record_they_go_on_from() {
        let (map, t, mut f) = corridor();
        let pose = (Pos::new(0, 0), Heading::East);
        let key = f.search_key(&map, t, pose, false).unwrap();
        let memo = HostMemo::new();
        let first = memo.record(key, &mut |rec| {
            f.compute_written_down(&map, t, (pose.0, pose.1, false), rec, until(1))
                .unwrap();
        });
        let first = first.expect("kept");
        for more in 0..5 {
            f.compute(&map, t, pose.0, pose.1, until(1)).unwrap();
            let rest = memo.record_after(key, first, &mut |rec| {
                f.resume_written_down(&map, rec, until(more)).unwrap();
            });
            assert!(rest.is_some_and(|id| id != first));
        }
        let mut lens = Vec::new();
        memo.recall_after(first, &mut |r| {
            assert_eq!(r.after, first);
            lens.push(r.reached.len());
            false
        });
        assert_eq!(lens, vec![5, 4, 3, 2]);
        let mut whole = Vec::new();
        memo.recall(key, &mut |r| {
            whole.push((r.id, r.after));
            true
        });
        assert_eq!(whole, vec![(first, 0)]);
        assert!(!memo.recall_after(first + 100, &mut |_| true));
        let counts = MemoCounts {
            taken_over: 1,
            in_part: 0,
            after: 0,
            recorded: 1,
            recorded_after: 5,
        };
        assert_eq!(memo.counts(), counts);
    }

    /// Records `n` searches from one pose, each stopped one node later
    /// than the one before; what `recall` hands back, as node counts.
    fn kept(n: usize) -> (HostMemo, Vec<usize>) {
        let (map, t, mut f) = corridor();
        let pose = (Pos::new(0, 0), Heading::East);
        let key = f.search_key(&map, t, pose, false).unwrap();
        let memo = HostMemo::new();
        for stop in 0..n {
            memo.record(key, &mut |rec| {
                let mut seen = 0;
                f.compute(&map, t, pose.0, pose.1, |i, dist| {
                    rec.reached(&[Reached {
                        node: i as u32,
                        dist,
                        mark: 0,
                    }]);
                    seen += 1;
                    if seen > stop {
                        Flow::Stop
                    } else {
                        Flow::Continue
                    }
                })
                .unwrap();
                assert!(f.write_down(&map, rec));
            });
        }
        let mut lens = Vec::new();
        memo.recall(key, &mut |r| {
            lens.push(r.reached.len());
            false
        });
        (memo, lens)
    }

    /// A pose keeps its newest records, handed back newest first.
    #[test]
    fn a_pose_keeps_its_newest_records_newest_first() {
        let (memo, lens) = kept(6);
        assert_eq!(lens, vec![6, 5, 4, 3]);
        let counts = MemoCounts {
            taken_over: 0,
            in_part: 0,
            after: 0,
            recorded: 6,
            recorded_after: 0,
        };
        assert_eq!(memo.counts(), counts);
    }
}
