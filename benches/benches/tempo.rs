//! `tempo/decide16`: one robot's full tempo decision (the whole team's
//! assignment) in a team of 16, on open and maze fields of 64² and 256²
//! nodes, about half known: the cost that dominates large-team runs
//! (docs/results/performance.md, stop 18); `decide16-cores` the same with
//! the team mates' searches on every core (stop 43); on the mazes, where
//! a kept share answers those repeated decisions, `decide16-fresh`
//! decides afresh each time and `decide16-forest` the same with every
//! travel time read off the known tree (stop 57).
//!
//! `tempo/endgame16-*`: the same in a maze once fewer frontier nodes than
//! robots are left (all but the last 12 nodes in BFS order known), where a
//! robot decides again at every visit (stop 29): team mates' forward
//! fields (`forward`, the way of teams up to six), one reverse search per
//! frontier node (`reverse`), and the next decision after one more visit
//! with those searches carried over (`kept`).
use conquest_benches::{bfs_known, half_known};
use core_algo::explore::{Context, RobotView, Strategy, Tempo, TempoConfig};
use core_algo::geometry::{Heading, Pos};
use core_algo::map::{Block, KnownMap};
use core_algo::path::{DistField, Flow, Forest, PlanCell, min_cells};
use core_algo::team::RobotId;
use core_algo::timing::Timing;
use criterion::{BatchSize, BenchmarkId, Criterion, criterion_group, criterion_main};
use phone_sim::field::{Field, generate};
use std::hint::black_box;
use std::time::{Duration, Instant};

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
                tree: None,
            };
            // Without the home pull the floor is exact (cost is travel):
            // the gap between the two is what the pull's slack costs.
            let no_pull = TempoConfig {
                home_pull_pct: 0,
                ..TempoConfig::default()
            };
            // `cores`: the team mates' searches on every core
            // (`phone_sim::cores`), as `conquest explore` runs them.
            for (name, config, cores) in [
                ("decide16", TempoConfig::default(), false),
                ("decide16-cores", TempoConfig::default(), true),
                ("decide16-no-pull", no_pull, false),
            ] {
                let mut tempo = Tempo::new(config);
                if cores {
                    tempo = tempo.with_workers(&phone_sim::cores::HOST_CORES);
                }
                g.bench_function(BenchmarkId::new(name, format!("{kind}-{n}")), |bch| {
                    bch.iter(|| black_box(tempo.decide(&ctx, &mut fields).expect("decide")))
                });
            }
            // On the mazes a kept share answers the repeated decisions
            // above; `fresh` decides afresh every time (a new `Tempo`),
            // by searches, and `forest` the same with the travel times
            // read off the known tree, as a simulated robot reads them on
            // a maze (stop 57).
            if kind == "maze" {
                let mut forest = Forest::new(vec![PlanCell::EMPTY; area]);
                forest.sync(&map);
                assert!(forest.holds(&map), "a maze's known part is a forest");
                let read = Context {
                    tree: Some(forest.view()),
                    ..ctx
                };
                let fresh = |ctx: &Context<'_, Vec<Block>>, fields: &mut Vec<_>| {
                    Tempo::new(TempoConfig::default())
                        .decide(ctx, fields)
                        .expect("decide")
                };
                assert_eq!(fresh(&read, &mut fields), fresh(&ctx, &mut fields));
                // Fresh fields too: a field that holds the search from the
                // same pose on the same map is not searched again, which a
                // changing map never allows.
                let new_fields = || -> Vec<_> {
                    (0..16)
                        .map(|_| DistField::new(vec![PlanCell::EMPTY; min_cells(area)]))
                        .collect()
                };
                for (name, ctx) in [("decide16-fresh", &ctx), ("decide16-forest", &read)] {
                    g.bench_function(BenchmarkId::new(name, format!("{kind}-{n}")), |bch| {
                        bch.iter_batched_ref(
                            new_fields,
                            |fields| black_box(fresh(ctx, fields)),
                            BatchSize::LargeInput,
                        )
                    });
                }
            }
        }
    }
    g.finish();
}

/// All but the last `left` nodes of `f` in BFS order from its first
/// start known, and 16 robots spread over the known nodes; also the next
/// node in that order, the one a robot finds next.
fn endgame_case(f: &Field, left: usize) -> (KnownMap<Vec<Block>>, Vec<RobotView>, Pos) {
    let start = f.starts()[0].pos;
    let order = f.bfs_order(start);
    let known = order.len() - left;
    let map = bfs_known(f, &order, known);
    let robots = (0..16)
        .map(|j| RobotView {
            pos: order[(known - 1) * (16 - j) / 17],
            heading: Heading::from_index((j % 4) as u8),
            eta: 0,
            home: start,
            target: None,
        })
        .collect();
    (map, robots, order[known])
}

fn bench_endgame(c: &mut Criterion) {
    let mut g = c.benchmark_group("tempo");
    g.sample_size(10);
    for n in [64u16, 256] {
        let f = generate::maze(n, n, 1);
        let (map, robots, next) = endgame_case(&f, 12);
        let mut grown = map.clone();
        let _ = grown.visit(next, f.arms(next).unwrap_or_default(), RobotId(0));
        assert!(
            map.frontier_len() < 16,
            "an endgame: fewer frontier nodes than robots"
        );
        let area = map.bounds().area();
        let mut fields: Vec<_> = (0..16)
            .map(|_| DistField::new(vec![PlanCell::EMPTY; min_cells(area)]))
            .collect();
        let ctx = |map| Context {
            map,
            timing: Timing::DEFAULT,
            robots: &robots,
            me: 0,
            tree: None,
        };
        // Every decision in full: no share kept from the last one.
        let full = TempoConfig {
            keep_share: false,
            ..TempoConfig::default()
        };
        // Forgets every field's search (outside the timing).
        let forget = |fields: &mut Vec<DistField<Vec<PlanCell>>>| {
            for fl in fields.iter_mut() {
                let _ = fl.compute(
                    &map,
                    Timing::DEFAULT,
                    robots[0].pos,
                    Heading::North,
                    |_, _| Flow::Stop,
                );
            }
        };
        for (name, config) in [
            // Ties broken only in teams above 16: the forward endgame.
            (
                "endgame16-forward",
                TempoConfig {
                    tie_break_team: 16,
                    ..full
                },
            ),
            ("endgame16-reverse", full),
        ] {
            let mut tempo = Tempo::new(config);
            g.bench_function(BenchmarkId::new(name, format!("maze-{n}")), |bch| {
                bch.iter_custom(|iters| {
                    let mut spent = Duration::ZERO;
                    for _ in 0..iters {
                        forget(&mut fields);
                        let t = Instant::now();
                        black_box(tempo.decide(&ctx(&map), &mut fields).expect("decide"));
                        spent += t.elapsed();
                    }
                    spent
                })
            });
        }
        let mut tempo = Tempo::new(full);
        g.bench_function(
            BenchmarkId::new("endgame16-kept", format!("maze-{n}")),
            |bch| {
                bch.iter_custom(|iters| {
                    let mut spent = Duration::ZERO;
                    for _ in 0..iters {
                        forget(&mut fields);
                        tempo.decide(&ctx(&map), &mut fields).expect("decide");
                        let t = Instant::now();
                        black_box(tempo.decide(&ctx(&grown), &mut fields).expect("decide"));
                        spent += t.elapsed();
                    }
                    spent
                })
            },
        );
    }
    g.finish();
}

criterion_group!(benches, bench_tempo, bench_endgame);
criterion_main!(benches);
