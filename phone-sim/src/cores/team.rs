//! A team of helper threads that stay awake between a decision's batches
//! of searches (see [`Team`]).
//!
//! ## Why not rayon here
//!
//! A 16-robot run hands the cores about 280 000 batches of searches
//! (rooms 256²), one per round of a decision, some 46 µs of a single
//! thread's work apart. Rayon's idle workers yield a few dozen times and
//! then sleep, so most batches began by waking one through the kernel:
//! 12 µs on average before the second core ran its first job, and the
//! wake-up calls, yields and sleeps cost both cores another few seconds
//! (docs/results/performance.md, stop 58). A helper here spins a while
//! after its last job before it sleeps, and the jobs of a batch are
//! handed out one at a time, in order, to whichever thread is free.

use std::panic::{AssertUnwindSafe, catch_unwind, resume_unwind};
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard, PoisonError, TryLockError};
use std::time::{Duration, Instant};

/// How long a helper spins for the next batch before it sleeps: longer
/// than most gaps between a decision's batches, short enough that an idle
/// simulation does not keep a core busy.
const SPIN: Duration = Duration::from_micros(200);

/// One job of a batch, as the helpers see it.
type Job<'a> = &'a mut (dyn FnMut() + Send);

/// See the module docs. Dropping it stops its helpers.
#[derive(Debug)]
pub struct Team {
    shared: Arc<Shared>,
    /// Held by the thread whose batch runs: one batch at a time.
    running: Mutex<()>,
    helpers: Vec<std::thread::JoinHandle<()>>,
}

#[derive(Debug)]
struct Shared {
    batch: Mutex<Batch>,
    /// Wakes sleeping helpers for a new batch or to stop.
    wake: Condvar,
    /// The latest batch's number, read while spinning without the lock.
    latest: AtomicU64,
    /// Jobs of the current batch that have returned.
    done: AtomicUsize,
    /// A job on a helper panicked: the batch's owner panics in turn.
    panicked: AtomicBool,
    stop: AtomicBool,
}

/// The batch being handed out.
#[derive(Debug)]
struct Batch {
    number: u64,
    /// The caller's slice of jobs, as an exposed address (a raw pointer
    /// would make the batch neither `Send` nor `Sync`): valid while
    /// `next < len` for this `number`, since the caller waits for every
    /// job to return.
    jobs: usize,
    len: usize,
    next: usize,
    sleeping: usize,
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    // A job panicking is caught before it could poison the lock, and the
    // batch is whole at every unlock: go on with it either way.
    m.lock().unwrap_or_else(PoisonError::into_inner)
}

impl Shared {
    /// Claims the next job of batch `number`: its slice address and index.
    fn claim(&self, number: u64) -> Option<(usize, usize)> {
        let mut b = lock(&self.batch);
        if b.number != number || b.next >= b.len {
            return None;
        }
        b.next += 1;
        Some((b.jobs, b.next - 1))
    }

    /// Runs every job of batch `number` it can claim.
    fn work(&self, number: u64) {
        while let Some((jobs, i)) = self.claim(number) {
            // SAFETY: `jobs` is the address of the caller's `[Job]`, which
            // outlives the batch (the caller returns only when every job
            // has), and index `i` was claimed by this thread alone.
            #[allow(unsafe_code)]
            let job: &mut Job<'_> =
                unsafe { &mut *std::ptr::with_exposed_provenance_mut::<Job<'_>>(jobs).add(i) };
            if catch_unwind(AssertUnwindSafe(&mut **job)).is_err() {
                self.panicked.store(true, Ordering::Relaxed);
            }
            self.done.fetch_add(1, Ordering::Release);
        }
    }

    /// A helper's life: wait for a batch, work on it, again.
    fn help(&self) {
        let mut seen = 0;
        loop {
            let since = Instant::now();
            while self.latest.load(Ordering::Acquire) == seen && since.elapsed() < SPIN {
                std::hint::spin_loop();
            }
            let mut b = lock(&self.batch);
            while b.number == seen && !self.stop.load(Ordering::Relaxed) {
                b.sleeping += 1;
                b = self.wake.wait(b).unwrap_or_else(PoisonError::into_inner);
                b.sleeping -= 1;
            }
            if self.stop.load(Ordering::Relaxed) {
                return;
            }
            seen = b.number;
            drop(b);
            self.work(seen);
        }
    }
}

impl Team {
    /// A team of `helpers` threads besides the callers'.
    pub fn new(helpers: usize) -> Team {
        let shared = Arc::new(Shared {
            batch: Mutex::new(Batch {
                number: 0,
                jobs: 0,
                len: 0,
                next: 0,
                sleeping: 0,
            }),
            wake: Condvar::new(),
            latest: AtomicU64::new(0),
            done: AtomicUsize::new(0),
            panicked: AtomicBool::new(false),
            stop: AtomicBool::new(false),
        });
        let helpers = (0..helpers)
            .filter_map(|n| {
                let s = Arc::clone(&shared);
                std::thread::Builder::new()
                    .name(format!("conquest-helper-{n}"))
                    .spawn(move || s.help())
                    .ok()
            })
            .collect();
        Team {
            shared,
            running: Mutex::new(()),
            helpers,
        }
    }

    /// Helper threads running.
    pub fn helpers(&self) -> usize {
        self.helpers.len()
    }

    /// Calls every job once, on this thread and the helpers, and returns
    /// when all have returned: `true`; `false`, no job called, when
    /// another thread's batch is running (the caller runs them some other
    /// way).
    pub fn run(&self, jobs: &mut [&mut (dyn FnMut() + Send)]) -> bool {
        let _running = match self.running.try_lock() {
            Ok(g) => g,
            Err(TryLockError::Poisoned(e)) => e.into_inner(),
            Err(TryLockError::WouldBlock) => return false,
        };
        let s = &*self.shared;
        let len = jobs.len();
        let number = {
            let mut b = lock(&s.batch);
            b.number += 1;
            b.jobs = jobs.as_mut_ptr().expose_provenance();
            b.len = len;
            b.next = 0;
            s.done.store(0, Ordering::Relaxed);
            s.latest.store(b.number, Ordering::Release);
            if b.sleeping > 0 {
                s.wake.notify_all();
            }
            b.number
        };
        s.work(number);
        // The helpers' last jobs: one search, seldom long.
        while s.done.load(Ordering::Acquire) < len {
            std::hint::spin_loop();
        }
        lock(&s.batch).len = 0;
        if s.panicked.swap(false, Ordering::Relaxed) {
            resume_unwind(Box::new("a job of the batch panicked"));
        }
        true
    }
}

impl Drop for Team {
    fn drop(&mut self) {
        self.shared.stop.store(true, Ordering::Relaxed);
        {
            let _b = lock(&self.shared.batch);
            self.shared.wake.notify_all();
        }
        for h in self.helpers.drain(..) {
            let _ = h.join();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_job_runs_once_in_every_batch() {
        let team = Team::new(3);
        for batch in 0..2000usize {
            let n = batch % 17;
            let counts: Vec<AtomicUsize> = (0..n).map(|_| AtomicUsize::new(0)).collect();
            let mut closures: Vec<_> = counts
                .iter()
                .map(|c| {
                    move || {
                        c.fetch_add(1, Ordering::Relaxed);
                    }
                })
                .collect();
            let mut jobs: Vec<Job<'_>> = closures.iter_mut().map(|c| c as Job<'_>).collect();
            assert!(team.run(&mut jobs));
            assert!(
                counts.iter().all(|c| c.load(Ordering::Relaxed) == 1),
                "batch {batch}"
            );
        }
    }

    #[test]
    fn a_batch_while_another_runs_is_handed_back() {
        let team = Team::new(1);
        let inner_refused = AtomicBool::new(false);
        let mut outer = || {
            let mut nothing = || {};
            let mut jobs: [Job<'_>; 1] = [&mut nothing];
            inner_refused.store(!team.run(&mut jobs), Ordering::Relaxed);
        };
        let mut jobs: [Job<'_>; 1] = [&mut outer];
        assert!(team.run(&mut jobs));
        assert!(inner_refused.load(Ordering::Relaxed));
    }

    #[test]
    fn a_panicking_job_panics_its_batch_and_the_team_goes_on() {
        let team = Team::new(1);
        let hit = std::panic::catch_unwind(AssertUnwindSafe(|| {
            let mut bad = || panic!("spoilt");
            let mut fine = || {};
            let mut jobs: [Job<'_>; 2] = [&mut fine, &mut bad];
            let _ = team.run(&mut jobs);
        }));
        assert!(hit.is_err());
        let ran = AtomicUsize::new(0);
        let mut a = || {
            ran.fetch_add(1, Ordering::Relaxed);
        };
        let mut b = || {
            ran.fetch_add(1, Ordering::Relaxed);
        };
        let mut jobs: [Job<'_>; 2] = [&mut a, &mut b];
        assert!(team.run(&mut jobs));
        assert_eq!(ran.load(Ordering::Relaxed), 2);
    }
}
