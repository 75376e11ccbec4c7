//! Exploration decision cost against its floor and its peers.
//!
//! - `explorer/decide`: one robot's full seed decision (layers 0–2) with five
//!   other robots' announced targets, on open and maze fields of 64², 256²
//!   and 1024² nodes, about half known.
//! - `field/bfs`: a plain node BFS over the same known graph (the floor).
//! - `field/full`: the full turn-aware field from the robot (what a
//!   centralised strategy pays per robot).
//! - `field/jumping`: the same field jumping along corridors (what the
//!   middle game's picks search).
//! - `legacy/astar_per_frontier`: the 2010 approach, one A* per frontier
//!   node (64² and 256²).
//! - `peer/dijkstra_all`: `pathfinding::dijkstra_all` over the same
//!   (node, heading) state graph with the same costs.
use conquest_benches::half_known;
use core_algo::explore::{Context, RobotView, SeedExplorer, Strategy};
use core_algo::geometry::{Heading, Pos};
use core_algo::map::{Block, KnownMap};
use core_algo::path::{DistField, Flow, PlanCell, arms_at, min_cells, neighbour_index};
use core_algo::timing::Timing;
use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use phone_sim::field::{Field, generate};
use std::hint::black_box;

struct Case {
    name: String,
    map: KnownMap<Vec<Block>>,
    robots: Vec<RobotView>,
}

/// Half of `f` known, visited in BFS order from its first start; the deciding
/// robot stands on the last visited node, five others on earlier ones with
/// targets on frontier nodes.
fn case(kind: &str, f: &Field) -> Case {
    let b = f.bounds();
    let start = f.starts()[0].pos;
    let (map, order, half) = half_known(f);
    let frontier: Vec<Pos> = map.frontier().collect();
    let me = order[half - 1];
    let mut robots = vec![RobotView {
        pos: me,
        heading: Heading::North,
        eta: 0,
        home: start,
        target: None,
    }];
    for j in 1..6 {
        robots.push(RobotView {
            pos: order[half * j / 7],
            heading: Heading::East,
            eta: 0,
            home: start,
            target: Some(frontier[frontier.len() * j / 7]),
        });
    }
    Case {
        name: format!("{kind}-{}", b.width),
        map,
        robots,
    }
}

fn plain_bfs(map: &KnownMap<Vec<Block>>, start: usize, dist: &mut [u32], queue: &mut [u32]) -> u32 {
    dist.fill(u32::MAX);
    let b = map.bounds();
    let (mut head, mut tail) = (0usize, 0usize);
    dist[start] = 0;
    queue[tail] = start as u32;
    tail += 1;
    let mut far = 0;
    while head < tail {
        let v = queue[head] as usize;
        head += 1;
        let Some(a) = arms_at(map, v) else { continue };
        for h in a.iter() {
            if let Some(w) = neighbour_index(b, v, h)
                && dist[w] == u32::MAX
            {
                dist[w] = dist[v] + 1;
                far = dist[w];
                queue[tail] = w as u32;
                tail += 1;
            }
        }
    }
    far
}

fn bench_explore(c: &mut Criterion) {
    let t = Timing::DEFAULT;
    let mut cases = Vec::new();
    for n in [64u16, 256, 1024] {
        cases.push(case("open", &generate::open(n, n, 1)));
        cases.push(case("maze", &generate::maze(n, n, 1)));
    }
    let mut g = c.benchmark_group("explore");
    g.sample_size(20);
    for cs in &cases {
        let area = cs.map.bounds().area();
        let mut fields = vec![DistField::new(vec![PlanCell::EMPTY; min_cells(area)])];
        let ctx = Context {
            map: &cs.map,
            timing: t,
            robots: &cs.robots,
            me: 0,
            tree: None,
        };
        let mut seed = SeedExplorer::default();
        g.bench_function(BenchmarkId::new("explorer/decide", &cs.name), |bch| {
            bch.iter(|| black_box(seed.decide(&ctx, &mut fields).expect("decide")))
        });
        g.bench_function(BenchmarkId::new("field/full", &cs.name), |bch| {
            bch.iter(|| {
                fields[0]
                    .compute(&cs.map, t, cs.robots[0].pos, Heading::North, |_, _| {
                        Flow::Continue
                    })
                    .expect("field");
                black_box(fields[0].dist_at(0))
            })
        });
        g.bench_function(BenchmarkId::new("field/jumping", &cs.name), |bch| {
            bch.iter(|| {
                fields[0]
                    .compute_jumping(&cs.map, t, cs.robots[0].pos, Heading::North, |_, _| {
                        Flow::Continue
                    })
                    .expect("field");
                black_box(fields[0].dist_at(0))
            })
        });
        let start = cs.map.bounds().index(cs.robots[0].pos).expect("in bounds");
        let mut dist = vec![0u32; area];
        let mut queue = vec![0u32; area];
        g.bench_function(BenchmarkId::new("field/bfs", &cs.name), |bch| {
            bch.iter(|| black_box(plain_bfs(&cs.map, start, &mut dist, &mut queue)))
        });
        if area <= 256 * 256 {
            let frontier: Vec<Pos> = cs.map.frontier().collect();
            let mut a = DistField::new(vec![PlanCell::EMPTY; min_cells(area)]);
            g.bench_function(
                BenchmarkId::new("legacy/astar_per_frontier", &cs.name),
                |bch| {
                    bch.iter(|| {
                        let mut best = None;
                        for f in &frontier {
                            let d = a
                                .astar(&cs.map, t, cs.robots[0].pos, Heading::North, *f)
                                .expect("astar");
                            if d.is_some() && (best.is_none() || d < best) {
                                best = d;
                            }
                        }
                        black_box(best)
                    })
                },
            );
            let map = &cs.map;
            let b = map.bounds();
            g.bench_function(BenchmarkId::new("peer/dijkstra_all", &cs.name), |bch| {
                bch.iter(|| {
                    let r =
                        pathfinding::directed::dijkstra::dijkstra_all(&(start, 0u8), |&(v, h)| {
                            let mut out = Vec::with_capacity(3);
                            if let Some(a) = arms_at(map, v) {
                                let hd = Heading::from_index(h);
                                if a.has(hd)
                                    && let Some(w) = neighbour_index(b, v, hd)
                                {
                                    out.push(((w, h), t.edge));
                                }
                                out.push(((v, (h + 1) & 3), t.quarter_turn));
                                out.push(((v, (h + 3) & 3), t.quarter_turn));
                            }
                            out
                        });
                    black_box(r.len())
                })
            });
        }
    }
    g.finish();
}

criterion_group!(benches, bench_explore);
criterion_main!(benches);
