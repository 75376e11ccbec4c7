// Cost matrices indexed by robot and node read clearer as index loops.
#![allow(clippy::needless_range_loop)]

use super::*;
use crate::explore::{Goal, RobotView, Strategy};
use crate::explore::assign::Candidates;
use crate::geometry::{Heading, Pos};
use crate::map::KnownMap;
use crate::path::tests::random_known;
use crate::path::{arms_at, min_cells, neighbour_index};
use crate::timing::Timing;
use proptest::prelude::*;
use std::vec;
use std::vec::Vec;

/// The least min-sum total over every frontier node of `map`, with every
/// robot's full field and tempo's default costs; `fixed` gives one robot a
/// node first. `(robots served, total)`.
fn best_total(
    map: &KnownMap<Vec<Block>>,
    robots: &[RobotView],
    fixed: Option<(usize, usize)>,
) -> (usize, i64) {
    let b = map.bounds();
    let timing = Timing::DEFAULT;
    let per_edge = i64::from(timing.edge) * i64::from(TempoConfig::default().home_pull_pct) / 100;
    let frontier: Vec<usize> = (0..b.area()).filter(|&i| map.is_frontier_at(i)).collect();
    let rows: Vec<usize> = (0..robots.len())
        .filter(|&j| fixed.is_none_or(|(me, _)| me != j))
        .collect();
    let cols: Vec<usize> = frontier
        .iter()
        .copied()
        .filter(|&i| fixed.is_none_or(|(_, t)| t != i))
        .collect();
    let cost = |j: usize, i: usize| -> Option<i64> {
        let r = &robots[j];
        let mut f = DistField::new(vec![PlanCell::EMPTY; min_cells(b.area())]);
        f.compute(map, timing, r.pos, r.heading, |_, _| Flow::Continue)
            .unwrap();
        let d = f.dist_at(i)?;
        Some(i64::from(d) + i64::from(r.eta) - per_edge * i64::from(b.pos(i).manhattan(r.home)))
    };
    let mut c = Candidates::empty(rows.len());
    c.m = cols.len();
    for (col, &i) in cols.iter().enumerate() {
        c.nodes[col] = i;
        for (row, &j) in rows.iter().enumerate() {
            if let Some(x) = cost(j, i) {
                c.cost[row][col] = x;
            }
        }
    }
    let (mut n, mut sum) = (0, 0);
    if let Some((me, t)) = fixed {
        n += 1;
        sum += cost(me, t).expect("the kept share is reachable");
    }
    if !rows.is_empty() {
        for (row, col) in hungarian_cols(&c, AssignmentObjective::MinSum)
            .iter()
            .enumerate()
            .take(rows.len())
        {
            if let Some(col) = col {
                n += 1;
                sum += c.cost[row][*col];
            }
        }
    }
    (n, sum)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    /// The commitment's claim: after one move towards its share over an
    /// unchanged map, the share is still part of an optimal assignment
    /// (checked against every robot's full field and every frontier node),
    /// and the kept decision leaves along a cheapest way to it. A robot
    /// that is not where its last decision sent it decides afresh.
    #[test]
    fn a_kept_share_stays_optimal_after_one_move(
        w in 3u16..10, h in 3u16..10, seed in any::<u64>(), frac in 0.2f64..0.9,
        k in 2usize..6, me in 0usize..6,
    ) {
        let area = usize::from(w) * usize::from(h);
        let map = random_known(w, h, seed, (area as f64 * frac) as usize + 1);
        let b = map.bounds();
        let known: Vec<usize> = (0..area).filter(|&i| arms_at(&map, i).is_some()).collect();
        let pick = |j: usize, salt: u64| {
            let x = seed.rotate_left((j * 7) as u32 + salt as u32) ^ salt.wrapping_mul(0x9E37);
            b.pos(known[(x as usize) % known.len()])
        };
        let mut robots: Vec<RobotView> = (0..k)
            .map(|j| RobotView {
                pos: pick(j, 1),
                heading: Heading::from_index((j % 4) as u8),
                eta: 0,
                home: pick(j, 2),
                target: None,
            })
            .collect();
        let me = me % k;
        let timing = Timing::DEFAULT;
        let field = || DistField::new(vec![PlanCell::EMPTY; min_cells(area)]);
        let mut fields: Vec<_> = (0..k).map(|_| field()).collect();
        let mut tempo = Tempo::default();
        let first = {
            let ctx = Context { map: &map, timing, robots: &robots, me };
            tempo.decide(&ctx, &mut fields).unwrap()
        };
        let (Goal::Frontier(t), Some(next)) = (first.goal, first.next) else {
            return Ok(());
        };
        let at = b.index(robots[me].pos).unwrap();
        let p1 = neighbour_index(b, at, next).unwrap();
        let ti = b.index(t).unwrap();
        prop_assume!(p1 != ti);
        // Only a share is kept (a robot without one trails or waits).
        prop_assume!(tempo.kept[me].is_some());
        prop_assert_eq!(best_total(&map, &robots, Some((me, ti))), best_total(&map, &robots, None));
        // Standing still is not where the decision sent it: decide afresh.
        {
            let ctx = Context { map: &map, timing, robots: &robots, me };
            let mut again = tempo;
            let fresh = Tempo::default().decide(&ctx, &mut fields).unwrap();
            prop_assert_eq!(again.decide(&ctx, &mut fields).unwrap(), fresh);
        }
        let (p0, h0) = (robots[me].pos, robots[me].heading);
        robots[me].pos = b.pos(p1);
        robots[me].heading = next;
        let ctx = Context { map: &map, timing, robots: &robots, me };
        let kept = tempo.decide(&ctx, &mut fields).unwrap();
        prop_assert_eq!(kept.goal, Goal::Frontier(t));
        prop_assert_eq!(best_total(&map, &robots, Some((me, ti))), best_total(&map, &robots, None));
        // The kept way is a cheapest one: its first move plus the rest.
        let h1 = kept.next.unwrap();
        let p2 = neighbour_index(b, p1, h1).unwrap();
        let mut from_p1 = field();
        from_p1.compute(&map, timing, b.pos(p1), next, |_, _| Flow::Continue).unwrap();
        let mut from_p2 = field();
        from_p2.compute(&map, timing, b.pos(p2), h1, |_, _| Flow::Continue).unwrap();
        prop_assert_eq!(
            from_p1.dist_at(ti),
            Some(from_p1.dist_pose(b.pos(p2), h1).unwrap() + from_p2.dist_at(ti).unwrap())
        );
        // The robot that decided in full came one move closer.
        let mut from_p0 = field();
        from_p0.compute(&map, timing, p0, h0, |_, _| Flow::Continue).unwrap();
        prop_assert_eq!(
            from_p0.dist_at(ti),
            Some(from_p0.dist_pose(b.pos(p1), next).unwrap() + from_p1.dist_at(ti).unwrap())
        );
    }
}

/// A changed map ends the commitment: the share is chosen afresh.
#[test]
fn a_new_node_ends_the_commitment() {
    let b = crate::map::Bounds::new(Pos::new(0, 0), 8, 1);
    let mut map = KnownMap::new(vec![Block::EMPTY; crate::map::blocks_for(b.area())], b).unwrap();
    let line = crate::geometry::Arms::NONE
        .with(Heading::East)
        .with(Heading::West);
    for x in 2..6 {
        map.visit(Pos::new(x, 0), line, crate::team::RobotId(0))
            .unwrap();
    }
    // Frontier at x = 1 and x = 6; the robot at 4 facing east takes 6.
    let mut robots = [RobotView {
        pos: Pos::new(4, 0),
        heading: Heading::East,
        eta: 0,
        home: Pos::new(4, 0),
        target: None,
    }];
    let mut fields = [DistField::new(vec![PlanCell::EMPTY; min_cells(b.area())])];
    let mut tempo = Tempo::new(TempoConfig {
        home_pull_pct: 0,
        ..TempoConfig::default()
    });
    let ctx = Context {
        map: &map,
        timing: Timing::DEFAULT,
        robots: &robots,
        me: 0,
    };
    let d = tempo.decide(&ctx, &mut fields).unwrap();
    assert_eq!(d.goal, Goal::Frontier(Pos::new(6, 0)));
    assert!(tempo.kept[0].is_some());
    // It drives to 5; meanwhile node 6 becomes known (visited by nobody
    // in this team, as a relayed report would make it), a dead end.
    robots[0].pos = Pos::new(5, 0);
    map.visit(
        Pos::new(6, 0),
        crate::geometry::Arms::NONE.with(Heading::West),
        crate::team::RobotId(1),
    )
    .unwrap();
    let ctx = Context {
        map: &map,
        timing: Timing::DEFAULT,
        robots: &robots,
        me: 0,
    };
    let d = tempo.decide(&ctx, &mut fields).unwrap();
    assert_eq!(d.goal, Goal::Frontier(Pos::new(1, 0)));
    assert_eq!(d.next, Some(Heading::West));
}
