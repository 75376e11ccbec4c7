//! Prints one simulated run as a timeline: every time a robot's body
//! reaches a node or its agent changes mode, target or retreat, one line
//! with the time, the robot, its node, heading, mode and target. For
//! finding where a run loses time (waiting, backing off, queueing at home).
//! Takes the arguments of `conquest explore` and sets the run up the same
//! way, so a run seen there can be read here step by step.
//!
//! `cargo run --release -p phone-sim --example timeline -- [FIELD] [--robots N] [--strategy S] ...`

use clap::Parser;
use phone_sim::explore_cmd::{ExploreArgs, build};
use phone_sim::sim::timeline::Timeline;

#[derive(Parser)]
struct Args {
    #[command(flatten)]
    explore: ExploreArgs,
}

fn main() {
    let a = Args::parse().explore;
    let field = match &a.field {
        Some(p) => phone_sim::field::load(p).expect("a field"),
        None => phone_sim::cli::demo_field().expect("the demo field"),
    };
    let mut sim = build(&field, &a).expect("a simulation");
    let mut timeline = Timeline::new(&sim);
    while sim.step() {
        timeline.print_changes(&sim);
    }
    let o = sim.outcome();
    println!(
        "complete {} makespan {:.1} s, map complete at {:?} s",
        o.complete,
        f64::from(o.makespan_ms) / 1000.0,
        o.mapped_ms.map(|ms| f64::from(ms) / 1000.0)
    );
}
