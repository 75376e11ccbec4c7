//! A seeded hunt for runs that do not complete (homecoming deadlocks,
//! stalls): random generated fields of 4..=12 × 4..=12 nodes of every kind,
//! 1..=6 robots on the generator's packed starts, 15 ± 7 ms link latency,
//! the whole system simulator. Prints every incomplete case and a summary.
//!
//! `cargo run --release -p phone-sim --example homecoming_hunt -- RUNS [STRATEGY] [FIRST_SEED]`

use phone_sim::field::generate::Kind;
use phone_sim::sim::robot::BoxedStrategy;
use phone_sim::sim::timeline::Timeline;
use phone_sim::sim::{SimConfig, Simulation};

fn main() {
    let mut args = std::env::args().skip(1);
    let runs: u64 = args.next().and_then(|s| s.parse().ok()).unwrap_or(200);
    let strategy = args.next().unwrap_or_else(|| "tempo".into());
    let first: u64 = args.next().and_then(|s| s.parse().ok()).unwrap_or(1);
    let mut incomplete = 0;
    let mut wrong_map = 0;
    for seed in first..first + runs {
        // SplitMix64 of the seed picks the case.
        let mut z = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15);
        let mut next = |n: u64| {
            z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut x = z;
            x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            (x ^ (x >> 31)) % n
        };
        let kind = Kind::ALL[next(4) as usize];
        let (w, h) = (4 + next(9) as u16, 4 + next(9) as u16);
        let f = kind.generate(w, h, seed);
        let robots = (1 + next(6) as usize).min(f.starts().len());
        let mut config = SimConfig {
            seed,
            ..SimConfig::default()
        };
        config.faults.channel.latency_ms = 15;
        config.faults.channel.jitter_ms = 7;
        let name = strategy.clone();
        let Ok(mut sim) = Simulation::new(
            &f,
            robots,
            move |_| BoxedStrategy(phone_sim::bench::strategy(&name).expect("known strategy")),
            config,
        ) else {
            continue;
        };
        // `HUNT_TRACE=1` prints every run's timeline (as `examples/timeline.rs`
        // does), for reading one case: run it with RUNS 1 and its seed.
        let o = if std::env::var_os("HUNT_TRACE").is_some() {
            let mut timeline = Timeline::new(&sim);
            while sim.step() {
                timeline.print_changes(&sim);
            }
            sim.outcome()
        } else {
            sim.run()
        };
        if !o.complete {
            incomplete += 1;
            wrong_map += usize::from(!o.map_correct);
            let bodies = sim.bodies().bodies();
            let shared = bodies.iter().enumerate().any(|(i, a)| {
                bodies
                    .iter()
                    .skip(i + 1)
                    .any(|b| a.is_alive() && b.is_alive() && a.pos == b.pos)
            });
            println!(
                "incomplete: seed {seed}, {} {w}x{h}, {robots} robots (map correct: {}, all home: {}{})",
                kind.name(),
                o.map_correct,
                o.all_home,
                if shared {
                    ", two bodies on one node"
                } else {
                    ""
                }
            );
        }
    }
    println!(
        "{runs} runs of {strategy}: {incomplete} incomplete ({:.1} %), {wrong_map} with a wrong map",
        100.0 * incomplete as f64 / runs.max(1) as f64
    );
}
