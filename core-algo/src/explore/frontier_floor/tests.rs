use super::*;
use crate::geometry::Heading;
use crate::map::{Bounds, blocks_for};
use crate::path::tests::random_arms;
use crate::path::{DistField, Flow, PlanCell, min_cells};
use crate::team::RobotId;
use crate::timing::Timing;
use proptest::prelude::*;
use std::vec;
use std::vec::Vec;

/// A sequence of pseudo-random numbers from `seed`.
fn rng(seed: u64) -> impl FnMut() -> u64 {
    let mut s = seed | 1;
    move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        s
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// For every robot and every travel `d`, the bound is at most the cost
    /// (travel less home pull) of every frontier node the robot reaches at
    /// `d` or later, and it never falls as `d` grows: on windows small
    /// enough for a bucket per edge and wide enough for several.
    #[test]
    fn the_floor_never_exceeds_a_cost_beyond_it(
        w in 1u16..300, h in 1u16..40, seed in any::<u64>(), frac in 0.05f64..1.0,
        edge in 1u32..200, turn in 1u32..128, pct in 0i64..60, robots in 1usize..4,
    ) {
        let b = Bounds::new(Pos::new(-3, 5), w, h);
        let area = b.area();
        let arms = random_arms(b, seed);
        let mut next = rng(seed.rotate_left(29));
        let mut map = KnownMap::new(vec![Block::EMPTY; blocks_for(area)], b).unwrap();
        let mut visited = Vec::new();
        for (i, &a) in arms.iter().enumerate() {
            if (next() % 1000) as f64 / 1000.0 < frac {
                map.visit(b.pos(i), a, RobotId(0)).unwrap();
                visited.push(i);
            }
        }
        prop_assume!(!visited.is_empty());
        let t = Timing { edge, quarter_turn: turn };
        let per_edge = i64::from(edge) * pct / 100;
        let views: Vec<RobotView> = (0..robots)
            .map(|_| RobotView {
                pos: b.pos(visited[(next() % visited.len() as u64) as usize]),
                heading: Heading::from_index((next() % 4) as u8),
                eta: (next() % 300) as Ticks,
                home: b.pos((next() % area as u64) as usize),
                target: None,
            })
            .collect();
        let pull = |j: usize, p: Pos| per_edge * i64::from(p.manhattan(views[j].home));
        let travel = |j: usize, d: Ticks| i64::from(d) + i64::from(views[j].eta);
        FrontierFloor::with(&map, &views, t.edge, (&pull, &travel), |bound| {
            for (j, r) in views.iter().enumerate() {
                let mut field = DistField::new(vec![PlanCell::EMPTY; min_cells(area)]);
                field.compute(&map, t, r.pos, r.heading, |_, _| Flow::Continue).unwrap();
                // Every frontier node reached, by travel.
                let mut reached: Vec<(Ticks, i64)> = (0..area)
                    .filter(|&i| map.is_frontier_at(i))
                    .filter_map(|i| field.dist_at(i).map(|d| (d, travel(j, d) - pull(j, b.pos(i)))))
                    .collect();
                reached.sort();
                // The least cost at travel d or later, for every d that matters.
                let mut least = i64::MAX;
                let mut last = i64::MIN;
                let mut probes: Vec<Ticks> = reached.iter().map(|x| x.0).collect();
                probes.extend((0..40).map(|n| n * edge * 7 / 3));
                probes.sort();
                probes.dedup();
                for &d in &probes {
                    least = reached.iter().filter(|x| x.0 >= d).map(|x| x.1).min().unwrap_or(i64::MAX);
                    let got = bound(j, d);
                    prop_assert!(got <= least, "robot {} at travel {}: bound {} above cost {}", j, d, got, least);
                    prop_assert!(got >= last, "robot {} at travel {}: bound fell from {} to {}", j, d, last, got);
                    last = got;
                }
                let _ = least;
            }
            Ok(())
        })?;
    }
}
