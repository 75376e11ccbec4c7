//! The host's cores for a decision's independent searches (see
//! [`core_algo::explore::Workers`]): a [`Team`] of helper threads, one job
//! per search.
//!
//! A simulated team's robots decide one after another on one machine,
//! where real robots would think side by side; the searches inside one
//! decision (a field per team mate) are what a host can spread over its
//! cores. Across robots there is less to gain: robots that decide at the
//! same instant, side by side, would save at most 19 % of a 16-robot
//! run's deciding time on rooms 128² and 7 % on maze 128²
//! (docs/results/performance.md, stop 43).

use crate::columns::HostColumns;
use crate::memo::HostMemo;
use core_algo::explore::{SharedColumns, Workers};
use core_algo::path::SearchMemo;
use rayon::prelude::*;
use std::sync::OnceLock;

mod team;

pub use team::Team;

/// Runs jobs on a [`Team`] of helpers, one per core besides the caller's,
/// each job handed out on its own, since one search can cost a thousand
/// times another (on rayon's global pool while another thread's batch
/// holds the team); and keeps the searches that the next decisions may
/// take over ([`HostMemo`]) and the endgame's column searches for every
/// robot ([`HostColumns`]).
#[derive(Debug, Default)]
pub struct HostCores {
    team: OnceLock<Team>,
    memo: HostMemo,
    columns: HostColumns,
}

impl HostCores {
    /// The pool, with a memo of its own.
    pub const fn new() -> HostCores {
        HostCores {
            team: OnceLock::new(),
            memo: HostMemo::new(),
            columns: HostColumns::new(),
        }
    }

    /// The memo of searches the strategies share.
    pub fn memo(&self) -> &HostMemo {
        &self.memo
    }

    /// The column searches the strategies share.
    pub fn columns(&self) -> &HostColumns {
        &self.columns
    }
}

/// The pool every host-side strategy shares.
pub static HOST_CORES: HostCores = HostCores::new();

impl Workers for HostCores {
    fn memo(&self) -> Option<&dyn SearchMemo> {
        Some(&self.memo)
    }

    fn columns(&self) -> Option<&dyn SharedColumns> {
        Some(&self.columns)
    }

    fn run(&self, jobs: &mut [&mut (dyn FnMut() + Send)]) {
        if jobs.len() < 2 {
            // Nothing to share: spare the hand-over.
            for job in jobs {
                job();
            }
            return;
        }
        let team = self.team.get_or_init(|| {
            let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
            Team::new(cores.saturating_sub(1))
        });
        if team.helpers() == 0 || !team.run(jobs) {
            jobs.par_iter_mut().with_max_len(1).for_each(|job| job());
        }
    }
}

/// Runs `op` on a thread of the pool: the searches it hands out then run
/// on that thread too, where a thread outside the pool would sleep until
/// the pool had run them all (rooms 128², 16 robots, 2 cores: 35.3 s
/// against 37.0 s; docs/results/performance.md, stop 43).
pub fn on_pool<R: Send>(op: impl FnOnce() -> R + Send) -> R {
    rayon::scope(|_| op())
}
