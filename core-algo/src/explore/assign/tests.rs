// Cost matrices indexed by robot and node read clearer as index loops.
#![allow(clippy::needless_range_loop)]

use super::*;
use crate::explore::tests::random_team_in;
use crate::explore::{InOrder, RobotView};
use crate::geometry::{Arms, Heading, Pos};
use crate::map::{Bounds, KnownMap, blocks_for};
use crate::path::tests::{bfs_order, random_arms, tree_arms};
use crate::path::{arms_at, min_cells};
use crate::team::RobotId;
use crate::timing::Timing;
use proptest::prelude::*;
use std::vec;
use std::vec::Vec;

/// Runs jobs last to first: a search's outcome must not depend on which
/// ran before it (see `Workers`).
struct Backwards;

impl Workers for Backwards {
    fn run(&self, jobs: &mut [&mut (dyn FnMut() + Send)]) {
        for job in jobs.iter_mut().rev() {
            job();
        }
    }
}

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

/// Every robot's cost for every node from a full field searched afresh
/// (`None`: not a frontier node, or out of reach), and the min-sum
/// optimum over every frontier node: (robots assigned, total); `None`
/// when the frontier is too large for one matrix.
#[allow(clippy::type_complexity)]
fn full_costs(
    map: &KnownMap<Vec<Block>>,
    timing: Timing,
    robots: &[RobotView],
    cost: impl Fn(usize, usize, Ticks) -> Option<i64>,
) -> (Vec<Vec<Option<i64>>>, Option<(usize, i64)>) {
    let (area, k) = (map.bounds().area(), robots.len());
    let mut full = vec![vec![None; area]; k];
    for (j, r) in robots.iter().enumerate() {
        let mut f = DistField::new(vec![PlanCell::EMPTY; min_cells(area)]);
        f.compute(map, timing, r.pos, r.heading, |_, _| Flow::Continue)
            .unwrap();
        for i in 0..area {
            if map.is_frontier_at(i) {
                full[j][i] = f.dist_at(i).and_then(|d| cost(j, i, d));
            }
        }
    }
    let frontier: Vec<usize> = (0..area).filter(|&i| map.is_frontier_at(i)).collect();
    if frontier.len() > MAX_CANDIDATES {
        return (full, None);
    }
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
    let best = total(
        &hungarian_cols(&all, AssignmentObjective::MinSum),
        &all.nodes,
        &full,
    );
    (full, Some(best))
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
        reverse in any::<bool>(), out in any::<u16>(), maze in any::<bool>(),
    ) {
        let area = usize::from(w) * usize::from(h);
        // Team mates left out of the assignment (never the decider), as
        // tempo leaves out those that keep a far share; the endgame takes
        // everyone, so only outside it.
        let left_out = u32::from(out) & !(1 << (me % k)) & ((1 << k) - 1);
        // On a maze the picks jump along corridors.
        let (map, mut robots) = random_team_in(w, h, (seed, maze), frac, k);
        let b = map.bounds();
        for (j, r) in robots.iter_mut().enumerate() {
            r.eta = (j as u32 * 13) % 40;
        }
        let timing = Timing::DEFAULT;
        let ctx = Context { map: &map, timing, robots: &robots, me: me % k, tree: None };
        let edge = i64::from(timing.edge);
        let per_edge = edge * i64::from(pull) / 100;
        let left_out = if map.frontier_len() < k { 0 } else { left_out };
        let cost = |j: usize, i: usize, d: Ticks| -> Option<i64> {
            if left_out & (1 << j) != 0 {
                return None;
            }
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
        let mut c = Candidates::empty(k);
        prop_assert!(Candidates::cheapest(&ctx, &mut fields, k, 0, (lazy, reverse, left_out), cost, floor, bound, (&mut c, &InOrder)).unwrap());
        // The same matrix whatever order the searches ran in.
        let mut fresh: Vec<_> = (0..k).map(|_| field()).collect();
        let mut back = Candidates::empty(k);
        prop_assert!(Candidates::cheapest(&ctx, &mut fresh, k, 0, (lazy, reverse, left_out), cost, floor, bound, (&mut back, &Backwards)).unwrap());
        prop_assert_eq!(back.nodes.get(..back.m), c.nodes.get(..c.m));
        prop_assert_eq!(back.cost, c.cost);
        let (full, best) = full_costs(&map, timing, &robots, cost);
        prop_assume!(best.is_some());
        let cols = hungarian_cols(&c, AssignmentObjective::MinSum);
        let got = total(&cols, &c.nodes, &full);
        prop_assert_eq!(Some(got), best);
        // A left-out robot gets nothing, and nobody searched its field.
        for j in 0..k {
            if left_out & (1 << j) != 0 {
                prop_assert_eq!(cols[j], None);
                prop_assert!(!fields[j].is_distance_search_from(&map, timing, robots[j].pos, robots[j].heading));
            }
        }
        // The decider's field is its own search (jumping along corridors,
        // so tempo then searches its way), and it reaches every node the
        // decider may be given. The reverse endgame searches no field of
        // the decider's.
        let (mine, r) = (me % k, &robots[me % k]);
        let endgame = reverse && map.frontier_len() < k;
        prop_assert!(
            endgame || c.m == 0 || fields[mine].is_distance_search_from(&map, timing, r.pos, r.heading)
        );
        for col in 0..c.m {
            if !endgame && c.cost[mine][col] < INF {
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

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Decisions in a row on one robot's fields, the map growing a node or
    /// two and robots moving in between: the endgame's reverse searches,
    /// carried over from decision to decision where the map allows, still
    /// find a min-sum optimum over every frontier node (against full
    /// fields searched afresh each time), lazy (each column grown only as
    /// far as the assignment needs) or not.
    #[test]
    fn kept_reverse_searches_lose_no_optimal_assignment(
        w in 2u16..10, h in 2u16..10, seed in any::<u64>(), tree in any::<bool>(),
        known in 2usize..60, k in 2usize..17, me in 0usize..16, steps in 1usize..8,
        grow in 0usize..3, moves in any::<u64>(), lazy in any::<bool>(),
    ) {
        let b = Bounds::new(Pos::new(0, 0), w, h);
        let area = b.area();
        let arms = if tree { tree_arms(b, seed) } else { random_arms(b, seed) };
        let order = bfs_order(b, &arms);
        let mut map = KnownMap::new(vec![Block::EMPTY; blocks_for(area)], b).unwrap();
        let mut visited = 0;
        for &i in order.iter().take(known) {
            map.visit(b.pos(i), arms[i], RobotId(0)).unwrap();
            visited += 1;
        }
        let timing = Timing::DEFAULT;
        let me = me % k;
        let mut fields: Vec<_> = (0..k).map(|_| DistField::new(vec![PlanCell::EMPTY; min_cells(area)])).collect();
        let mut rnd = moves | 1;
        let mut next = move || {
            rnd ^= rnd << 13;
            rnd ^= rnd >> 7;
            rnd ^= rnd << 17;
            rnd
        };
        let mut robots: Vec<RobotView> = Vec::new();
        // One matrix for every step, as a decision reuses it: what an
        // earlier step wrote must not leak into a later one.
        let mut c = Candidates::empty(k);
        for step in 0..steps {
            if map.is_complete() {
                break;
            }
            let passable: Vec<usize> = (0..area).filter(|&i| arms_at(&map, i).is_some()).collect();
            // Robots stand on passable nodes; a few move between decisions.
            for j in 0..k {
                if step == 0 || next() % 3 == 0 {
                    let pos = b.pos(passable[(next() % passable.len() as u64) as usize]);
                    let view = RobotView {
                        pos,
                        heading: Heading::from_index((next() % 4) as u8),
                        eta: (next() % 30) as u32,
                        home: pos,
                        target: None,
                    };
                    if step == 0 { robots.push(view) } else { robots[j] = RobotView { home: robots[j].home, ..view } }
                }
            }
            let ctx = Context { map: &map, timing, robots: &robots, me, tree: None };
            let per_edge = i64::from(timing.edge) / 4;
            let cost = |j: usize, i: usize, d: Ticks| -> Option<i64> {
                let r = robots.get(j)?;
                Some(i64::from(d) + i64::from(r.eta) - per_edge * i64::from(b.pos(i).manhattan(r.home)))
            };
            let floor = |j: usize, d: Ticks| -> i64 {
                let r = &robots[j];
                let by_travel = (per_edge * i64::from(d) + i64::from(timing.edge) - 1) / i64::from(timing.edge)
                    + per_edge * i64::from(r.pos.manhattan(r.home));
                let by_extent = map.farthest_visited(r.home).map_or(i64::MAX, |f| per_edge * (i64::from(f) + 1));
                i64::from(d) + i64::from(r.eta) - by_travel.min(by_extent)
            };
            let bound = |_: usize, _: usize| i64::MIN;
            prop_assert!(
                Candidates::cheapest(&ctx, &mut fields, k, 0, (lazy, true, 0), cost, floor, bound, (&mut c, &InOrder)).unwrap()
            );
            let (full, best) = full_costs(&map, timing, &robots, cost);
            prop_assume!(best.is_some());
            let got = total(&hungarian_cols(&c, AssignmentObjective::MinSum), &c.nodes, &full);
            prop_assert_eq!(Some(got), best, "step {}", step);
            for j in 0..k {
                for col in 0..c.m {
                    if c.cost[j][col] < INF {
                        prop_assert_eq!(Some(c.cost[j][col]), full[j][c.nodes[col]]);
                    }
                }
            }
            // The map grows by the next nodes a robot would find.
            for _ in 0..grow.max(1) {
                if let Some(&i) = order.get(visited) {
                    map.visit(b.pos(i), arms[i], RobotId(0)).unwrap();
                    visited += 1;
                }
            }
        }
    }
}

/// The lazy endgame grows each frontier node's reverse search only until
/// the assignment is proven: on a corridor with a frontier node at each
/// end and two robots near each, the nearest robot at each end is the
/// optimum, and neither search needs the second robot, which the eager
/// endgame (each node's m cheapest robots) finds. Both give the optimum.
/// The robots stand on junctions (a dead end south of each), so that each
/// is found where it stands; in a corridor it is found as soon as either
/// end of it is.
#[test]
fn the_lazy_endgame_searches_only_as_far_as_the_assignment_needs() {
    let b = Bounds::new(Pos::new(0, 0), 14, 2);
    let mut map = KnownMap::new(vec![Block::EMPTY; blocks_for(b.area())], b).unwrap();
    let through = Arms::NONE.with(Heading::East).with(Heading::West);
    let stands = [2, 4, 9, 11];
    for x in 1..=12 {
        let arms = if stands.contains(&x) {
            map.visit(Pos::new(x, 0), Arms::NONE.with(Heading::North), RobotId(0))
                .unwrap();
            through.with(Heading::South)
        } else {
            through
        };
        map.visit(Pos::new(x, 1), arms, RobotId(0)).unwrap();
    }
    assert_eq!(map.frontier_len(), 2);
    let robots: Vec<RobotView> = stands
        .iter()
        .map(|&x| RobotView {
            pos: Pos::new(x, 1),
            heading: Heading::East,
            eta: 0,
            home: Pos::new(x, 1),
            target: None,
        })
        .collect();
    let timing = Timing::DEFAULT;
    let ctx = Context {
        map: &map,
        timing,
        robots: &robots,
        me: 1,
        tree: None,
    };
    let searched = |lazy: bool| {
        let mut fields: Vec<_> = (0..4)
            .map(|_| DistField::new(vec![PlanCell::EMPTY; min_cells(b.area())]))
            .collect();
        let mut c = Candidates::empty(4);
        let cost = |_: usize, _: usize, d: Ticks| Some(i64::from(d));
        let planned = Candidates::cheapest(
            &ctx,
            &mut fields,
            4,
            0,
            (lazy, true, 0),
            cost,
            |_, d| i64::from(d),
            |_, _| i64::MIN,
            (&mut c, &InOrder),
        )
        .unwrap();
        assert!(planned);
        let cols = hungarian_cols(&c, AssignmentObjective::MinSum);
        let got: Vec<Option<u16>> = cols
            .iter()
            .take(4)
            .map(|col| col.map(|col| b.pos(c.nodes[col]).x as u16))
            .collect();
        assert_eq!(got, vec![Some(0), None, None, Some(13)], "lazy {lazy}");
        assert!(c.nodes[..2].iter().all(|&i| b.pos(i).y == 1));
        // How far each frontier node's search went.
        let mut reach: Vec<(usize, Ticks)> = fields
            .iter()
            .filter_map(|f| Some((f.reverse_goal()?, f.reverse_settled_to()?)))
            .collect();
        reach.sort_unstable();
        reach
    };
    let (lazy, eager) = (searched(true), searched(false));
    assert_eq!(lazy.len(), 2);
    assert_eq!(eager.len(), 2);
    for (l, e) in lazy.iter().zip(&eager) {
        assert_eq!(l.0, e.0);
        assert!(l.1 <= e.1, "lazy {lazy:?} against eager {eager:?}");
    }
    // At the west end both robots face away: the second one's U-turn
    // lies well beyond the first's, and only the eager search goes there.
    assert!(
        lazy[0].1 < eager[0].1,
        "lazy {lazy:?} against eager {eager:?}"
    );
}
