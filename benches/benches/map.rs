//! `KnownMap` update cost: a whole open field visited node by node, and one
//! frontier enumeration on a half-known map.
use core_algo::geometry::{Arms, Pos};
use core_algo::map::{Block, Bounds, KnownMap, blocks_for};
use core_algo::team::RobotId;
use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use std::hint::black_box;

fn open_arms(x: i16, y: i16, n: i16) -> Arms {
    use core_algo::geometry::Heading::*;
    let mut a = Arms::NONE;
    if y + 1 < n {
        a = a.with(North);
    }
    if x + 1 < n {
        a = a.with(East);
    }
    if y > 0 {
        a = a.with(South);
    }
    if x > 0 {
        a = a.with(West);
    }
    a
}

fn new_map(n: i16) -> KnownMap<Vec<Block>> {
    let bounds = Bounds::new(Pos::new(0, 0), n as u16, n as u16);
    KnownMap::new(vec![Block::EMPTY; blocks_for(bounds.area())], bounds).expect("capacity")
}

fn bench_map(c: &mut Criterion) {
    let mut g = c.benchmark_group("map");
    for n in [64i16, 256] {
        // Nodes, in i32: 256² overflows an i16 (the label read 0 before).
        let nodes = i32::from(n) * i32::from(n);
        g.bench_with_input(BenchmarkId::new("visit_all", nodes), &n, |b, &n| {
            let mut m = new_map(n);
            b.iter(|| {
                m.clear();
                for y in 0..n {
                    for x in 0..n {
                        let _ = m.visit(Pos::new(x, y), open_arms(x, y, n), RobotId(0));
                    }
                }
                black_box(m.frontier_len())
            })
        });
        let mut half = new_map(n);
        for y in 0..n / 2 {
            for x in 0..n {
                let _ = half.visit(Pos::new(x, y), open_arms(x, y, n), RobotId(0));
            }
        }
        g.bench_with_input(BenchmarkId::new("frontier_iter", nodes), &half, |b, m| {
            b.iter(|| black_box(m.frontier().count()))
        });
    }
    g.finish();
}

criterion_group!(benches, bench_map);
criterion_main!(benches);
