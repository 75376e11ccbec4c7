//! Full turn-aware fields for instruction counts: `KIND SIZE REPS` (open,
//! maze or rooms; default open 256 50) computes REPS fields over the
//! half-known map of the explore bench, from starts spread over the
//! visited half. Under `valgrind --tool=cachegrind`, the count with REPS
//! less the count with 0 is what the searches cost (criterion's wall
//! times on this shared host swing by a quarter; instruction counts do
//! not).
use conquest_benches::half_known;
use core_algo::geometry::Heading;
use core_algo::path::{DistField, Flow, PlanCell, min_cells};
use core_algo::timing::Timing;
use phone_sim::field::generate;
use std::process::ExitCode;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let kind = args.first().map_or("open", String::as_str);
    let (Ok(n), Ok(reps)) = (
        args.get(1).map_or(Ok(256), |s| s.parse::<u16>()),
        args.get(2).map_or(Ok(50), |s| s.parse::<usize>()),
    ) else {
        eprintln!("usage: search_count [open|maze|rooms] [SIZE] [REPS]");
        return ExitCode::FAILURE;
    };
    let f = match kind {
        "maze" => generate::maze(n, n, 1),
        "rooms" => generate::rooms(n, n, 1),
        _ => generate::open(n, n, 1),
    };
    let (map, order, half) = half_known(&f);
    let mut field = DistField::new(vec![PlanCell::EMPTY; min_cells(map.bounds().area())]);
    let (mut nodes, mut sum) = (0u64, 0u64);
    for r in 0..reps {
        let start = order[(half - 1) * (r + 1) / reps];
        let searched = field.compute(&map, Timing::DEFAULT, start, Heading::North, |_, d| {
            nodes += 1;
            sum += u64::from(d);
            Flow::Continue
        });
        if let Err(e) = searched {
            eprintln!("search failed: {e}");
            return ExitCode::FAILURE;
        }
    }
    // The sum pins the result: a change that alters a field shows here.
    println!("{kind} {n}² × {reps}: {nodes} nodes reached, distance sum {sum}");
    ExitCode::SUCCESS
}
