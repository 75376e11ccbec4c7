//! The cores a decision may use: [`Workers`] runs a decision's independent
//! searches side by side where the host has more than one.
//!
//! ## Why
//!
//! Tempo's decision in a team of 16 grows one field per team mate, each
//! from that robot's pose to its cheapest frontier nodes. The searches
//! read the same map and write only their own field, so they can run at
//! once. On a robot there is one core and they run in order ([`InOrder`]);
//! the simulator, which runs every robot's decisions on one machine, hands
//! the strategy a thread pool (`phone_sim::cores`). Which thread runs which
//! search changes nothing a search finds, so the decision is the same.
//!
//! Only the host knows how to run threads, so the pool stays behind this
//! trait and core-algo stays `no_std`.

use super::SharedColumns;
use crate::path::SearchMemo;

/// Runs independent jobs, on more than one core where the host can.
pub trait Workers: Sync {
    /// Calls every job once, on any thread and in any order, and returns
    /// when all have returned. Jobs share nothing mutable, so any order
    /// gives the same result.
    fn run(&self, jobs: &mut [&mut (dyn FnMut() + Send)]);

    /// Where the host keeps searches that the next decisions may take
    /// over instead of searching again (see [`SearchMemo`]), if it does.
    fn memo(&self) -> Option<&dyn SearchMemo> {
        None
    }

    /// Where the host keeps the endgame's column searches for every robot
    /// it runs (see [`SharedColumns`]), if it does.
    fn columns(&self) -> Option<&dyn SharedColumns> {
        None
    }
}

impl core::fmt::Debug for dyn Workers {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str("Workers")
    }
}

/// Hands every job of `jobs` to `workers` at once, and returns when all
/// have returned: the one way a decision's independent searches (the
/// picks, the endgame's columns) reach the cores.
pub(crate) fn run_all<J: FnMut() + Send>(workers: &dyn Workers, jobs: &mut [J]) {
    let mut run = heapless::Vec::<&mut (dyn FnMut() + Send), { super::MAX_ROBOTS }>::new();
    for job in jobs.iter_mut() {
        // Past `MAX_ROBOTS` jobs (no caller has as many), run the rest
        // in turn here.
        if let Err(job) = run.push(job) {
            job();
        }
    }
    workers.run(&mut run);
}

/// One core: every job in turn, first to last. What a robot runs.
#[derive(Clone, Copy, Debug, Default)]
pub struct InOrder;

impl Workers for InOrder {
    fn run(&self, jobs: &mut [&mut (dyn FnMut() + Send)]) {
        for job in jobs {
            job();
        }
    }
}
