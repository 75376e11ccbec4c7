//! `tempo/decide16`: one robot's full tempo decision (the whole team's
//! assignment) in a team of 16, on open and maze fields of 64² and 256²
//! nodes, about half known: the cost that dominates large-team runs
//! (docs/results/performance.md, stop 18).
use conquest_benches::half_known;
use core_algo::explore::{Context, RobotView, Strategy, Tempo, TempoConfig};
use core_algo::geometry::Heading;
use core_algo::map::{Block, KnownMap};
use core_algo::path::{DistField, PlanCell, min_cells};
use core_algo::timing::Timing;
use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use phone_sim::field::{Field, generate};
use std::hint::black_box;

/// Half of `f` known, visited in BFS order from its first start; 16 robots
/// spread over the known half, all with that start as home.
fn case(f: &Field) -> (KnownMap<Vec<Block>>, Vec<RobotView>) {
    let start = f.starts()[0].pos;
    let (map, order, half) = half_known(f);
    let robots = (0..16)
        .map(|j| RobotView {
            pos: order[half - 1 - (half - 1) * j / 16],
            heading: Heading::from_index((j % 4) as u8),
            eta: 0,
            home: start,
            target: None,
        })
        .collect();
    (map, robots)
}

fn bench_tempo(c: &mut Criterion) {
    let mut g = c.benchmark_group("tempo");
    g.sample_size(10);
    for n in [64u16, 256] {
        for (kind, f) in [
            ("open", generate::open(n, n, 1)),
            ("maze", generate::maze(n, n, 1)),
        ] {
            let (map, robots) = case(&f);
            let area = map.bounds().area();
            let mut fields: Vec<_> = (0..16)
                .map(|_| DistField::new(vec![PlanCell::EMPTY; min_cells(area)]))
                .collect();
            let ctx = Context {
                map: &map,
                timing: Timing::DEFAULT,
                robots: &robots,
                me: 0,
            };
            // Without the home pull the floor is exact (cost is travel):
            // the gap between the two is what the pull's slack costs.
            let no_pull = TempoConfig {
                home_pull_pct: 0,
                ..TempoConfig::default()
            };
            for (name, config) in [
                ("decide16", TempoConfig::default()),
                ("decide16-no-pull", no_pull),
            ] {
                let mut tempo = Tempo::new(config);
                g.bench_function(BenchmarkId::new(name, format!("{kind}-{n}")), |bch| {
                    bch.iter(|| black_box(tempo.decide(&ctx, &mut fields).expect("decide")))
                });
            }
        }
    }
    g.finish();
}

criterion_group!(benches, bench_tempo);
criterion_main!(benches);
