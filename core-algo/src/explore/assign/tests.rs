// Cost matrices indexed by robot and node read clearer as index loops.
#![allow(clippy::needless_range_loop)]

use super::*;
use crate::explore::tests::random_team;
use crate::path::min_cells;
use crate::timing::Timing;
use proptest::prelude::*;
use std::vec;
use std::vec::Vec;

fn total(cols: &[Option<usize>], nodes: &[usize], full: &[Vec<Option<i64>>]) -> (usize, i64) {
    let mut n = 0;
    let mut sum = 0;
    for (j, col) in cols.iter().enumerate().take(full.len()) {
        if let Some(c) = col {
            n += 1;
            sum += full[j][nodes[*c]].expect("assigned pair is reachable");
        }
    }
    (n, sum)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2048))]

    /// `Candidates::cheapest` grows each field only to its robot's k
    /// cheapest nodes, yet the min-sum assignment over what it collects is
    /// as good as the one over every frontier node with every robot's full
    /// field (tempo's costs: travel, waiting time, home pull).
    #[test]
    fn cheapest_candidates_lose_no_optimal_assignment(
        w in 2u16..12, h in 2u16..12, seed in any::<u64>(), frac in 0.05f64..1.0,
        k in 1usize..17, pull in 0u32..60, me in 0usize..16, lazy in any::<bool>(),
        reverse in any::<bool>(),
    ) {
        let area = usize::from(w) * usize::from(h);
        let (map, mut robots) = random_team(w, h, seed, frac, k);
        let b = map.bounds();
        for (j, r) in robots.iter_mut().enumerate() {
            r.eta = (j as u32 * 13) % 40;
        }
        let timing = Timing::DEFAULT;
        let ctx = Context { map: &map, timing, robots: &robots, me: me % k };
        let edge = i64::from(timing.edge);
        let per_edge = edge * i64::from(pull) / 100;
        let cost = |j: usize, i: usize, d: Ticks| -> Option<i64> {
            let r = robots.get(j)?;
            Some(i64::from(d) + i64::from(r.eta) - per_edge * i64::from(b.pos(i).manhattan(r.home)))
        };
        // Tempo's floor: the pull is bounded by the travel and by the
        // farthest visited node from home.
        let floor = |j: usize, d: Ticks| -> i64 {
            let r = &robots[j];
            let by_travel = (per_edge * i64::from(d) + edge - 1) / edge
                + per_edge * i64::from(r.pos.manhattan(r.home));
            let by_extent = map
                .farthest_visited(r.home)
                .map_or(i64::MAX, |f| per_edge * (i64::from(f) + 1));
            i64::from(d) + i64::from(r.eta) - by_travel.min(by_extent)
        };
        let bound = |j: usize, i: usize| -> i64 {
            let r = &robots[j];
            let p = b.pos(i);
            i64::from(r.pos.manhattan(p) * timing.edge) + i64::from(r.eta)
                - per_edge * i64::from(p.manhattan(r.home))
        };
        let field = || DistField::new(vec![PlanCell::EMPTY; min_cells(area)]);
        let mut fields: Vec<_> = (0..k).map(|_| field()).collect();
        let c = Candidates::cheapest(&ctx, &mut fields, k, 0, (lazy, reverse), cost, floor, bound).unwrap().unwrap();
        // Every robot's full field, every frontier node.
        let mut full = vec![vec![None; area]; k];
        for (j, r) in robots.iter().enumerate() {
            let mut f = field();
            f.compute(&map, timing, r.pos, r.heading, |_, _| Flow::Continue).unwrap();
            for i in 0..area {
                if map.is_frontier_at(i) {
                    full[j][i] = f.dist_at(i).and_then(|d| cost(j, i, d));
                }
            }
        }
        let frontier: Vec<usize> = (0..area).filter(|&i| map.is_frontier_at(i)).collect();
        prop_assume!(frontier.len() <= MAX_CANDIDATES);
        let mut all = Candidates::empty(k);
        all.m = frontier.len();
        for (col, &i) in frontier.iter().enumerate() {
            all.nodes[col] = i;
            for j in 0..k {
                if let Some(x) = full[j][i] {
                    all.cost[j][col] = x;
                }
            }
        }
        let best = total(&hungarian_cols(&all, AssignmentObjective::MinSum), &all.nodes, &full);
        let got = total(&hungarian_cols(&c, AssignmentObjective::MinSum), &c.nodes, &full);
        prop_assert_eq!(got, best);
        // The decider's field is its own search, and it reaches every node
        // the decider may be given: tempo takes the way from it.
        let (mine, r) = (me % k, &robots[me % k]);
        prop_assert!(c.m == 0 || fields[mine].is_search_from(&map, timing, r.pos, r.heading));
        for col in 0..c.m {
            if c.cost[mine][col] < INF {
                let d = fields[mine].dist_at(c.nodes[col]);
                prop_assert_eq!(d.and_then(|d| cost(mine, c.nodes[col], d)), full[mine][c.nodes[col]]);
            }
        }
        // The collected costs are the true ones where present.
        for j in 0..k {
            for col in 0..c.m {
                if c.cost[j][col] < INF {
                    prop_assert_eq!(Some(c.cost[j][col]), full[j][c.nodes[col]]);
                }
            }
        }
    }
}
