// Cost matrices indexed by robot and node read clearer as index loops.
#![allow(clippy::needless_range_loop)]

use super::*;
use crate::explore::assign::Candidates;
use crate::explore::tests::random_team;
use crate::explore::{Goal, RobotView, Strategy};
use crate::geometry::{Heading, Pos};
use crate::map::KnownMap;
use crate::path::{min_cells, neighbour_index};
use crate::timing::Timing;
use proptest::prelude::*;
use std::vec;
use std::vec::Vec;

/// The least min-sum total over every frontier node of `map`, with every
/// robot's full field and tempo's default costs, when each robot of
/// `pinned` gets the node given (`Some`) or none (`None`) first.
/// `(robots served, total)`.
fn best_total(
    map: &KnownMap<Vec<Block>>,
    robots: &[RobotView],
    pinned: &[(usize, Option<usize>)],
) -> (usize, i64) {
    let b = map.bounds();
    let timing = Timing::DEFAULT;
    let per_edge = i64::from(timing.edge) * i64::from(TempoConfig::default().home_pull_pct) / 100;
    // Every robot's full field, grown once.
    let full: Vec<_> = robots
        .iter()
        .map(|r| {
            let mut f = fresh_fields(b.area(), 1).remove(0);
            f.compute(map, timing, r.pos, r.heading, |_, _| Flow::Continue)
                .unwrap();
            f
        })
        .collect();
    let cost = |j: usize, i: usize| -> Option<i64> {
        let r = &robots[j];
        let d = full[j].dist_at(i)?;
        Some(i64::from(d) + i64::from(r.eta) - per_edge * i64::from(b.pos(i).manhattan(r.home)))
    };
    let rows: Vec<usize> = (0..robots.len())
        .filter(|&j| pinned.iter().all(|&(p, _)| p != j))
        .collect();
    let cols: Vec<usize> = (0..b.area())
        .filter(|&i| map.is_frontier_at(i) && pinned.iter().all(|&(_, t)| t != Some(i)))
        .collect();
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
    for &(j, t) in pinned {
        if let Some(t) = t {
            n += 1;
            sum += cost(j, t).expect("a pinned share is reachable");
        }
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

/// `k` planner fields for a window of `area` nodes.
fn fresh_fields(area: usize, k: usize) -> Vec<DistField<Vec<PlanCell>>> {
    (0..k)
        .map(|_| DistField::new(vec![PlanCell::EMPTY; min_cells(area)]))
        .collect()
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
        let (map, mut robots) = random_team(w, h, seed, frac, k);
        let b = map.bounds();
        let me = me % k;
        let timing = Timing::DEFAULT;
        let field = || fresh_fields(area, 1).remove(0);
        let mut fields = fresh_fields(area, k);
        let mut tempo = Tempo::default();
        let first = {
            let ctx = Context { map: &map, timing, robots: &robots, me, tree: None };
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
        prop_assume!(tempo.kept[me].is_some_and(|c| c.share().is_some()));
        prop_assert_eq!(best_total(&map, &robots, &[(me, Some(ti))]), best_total(&map, &robots, &[]));
        // Standing still is not where the decision sent it: decide afresh.
        {
            let ctx = Context { map: &map, timing, robots: &robots, me, tree: None };
            let mut again = tempo;
            let fresh = Tempo::default().decide(&ctx, &mut fields).unwrap();
            prop_assert_eq!(again.decide(&ctx, &mut fields).unwrap(), fresh);
        }
        let (p0, h0) = (robots[me].pos, robots[me].heading);
        robots[me].pos = b.pos(p1);
        robots[me].heading = next;
        let ctx = Context { map: &map, timing, robots: &robots, me, tree: None };
        let kept = tempo.decide(&ctx, &mut fields).unwrap();
        prop_assert_eq!(kept.goal, Goal::Frontier(t));
        prop_assert_eq!(best_total(&map, &robots, &[(me, Some(ti))]), best_total(&map, &robots, &[]));
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

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, max_global_rejects: 65536, ..ProptestConfig::default() })]

    /// A robot without a share waits, and its wait is kept: after a team
    /// mate moves one edge towards its own share (of the same optimal
    /// assignment) over an unchanged map, leaving the waiting robot out is
    /// still optimal, and the kept decision is to wait.
    #[test]
    fn a_kept_wait_stays_optimal_while_a_mate_moves(
        w in 3u16..10, h in 3u16..10, seed in any::<u64>(), frac in 0.7f64..1.0,
        k in 2usize..8, me in 0usize..8,
    ) {
        let area = usize::from(w) * usize::from(h);
        let (map, mut robots) = random_team(w, h, seed, frac, k);
        let b = map.bounds();
        let me = me % k;
        let timing = Timing::DEFAULT;
        let mut fields = fresh_fields(area, k);
        // Without trailing a robot with no share waits.
        let config = TempoConfig {
            trail_edges: 0,
            trail_far_nodes_per_robot: 0,
            ..TempoConfig::default()
        };
        let mut tempo = Tempo::new(config);
        let mut decide = |tempo: &mut Tempo, robots: &[RobotView], j: usize| {
            let ctx = Context { map: &map, timing, robots, me: j, tree: None };
            tempo.decide(&ctx, &mut fields).unwrap()
        };
        let waits = decide(&mut tempo, &robots, me);
        prop_assume!(waits.goal == Goal::Wait);
        prop_assert!(tempo.kept[me].is_some_and(|c| c.share().is_none()));
        prop_assert_eq!(best_total(&map, &robots, &[(me, None)]), best_total(&map, &robots, &[]));
        // A team mate with a share in an optimal assignment that leaves
        // `me` out (ties may split the deciders otherwise).
        let mate = (0..k).filter(|&j| j != me).find_map(|j| {
            let d = decide(&mut Tempo::new(config), &robots, j);
            let (Goal::Frontier(t), Some(next)) = (d.goal, d.next) else { return None };
            let ti = b.index(t)?;
            let both = [(me, None), (j, Some(ti))];
            (best_total(&map, &robots, &both) == best_total(&map, &robots, &[])).then_some((j, next))
        });
        prop_assume!(mate.is_some());
        let (j, next) = mate.unwrap();
        let at = b.index(robots[j].pos).unwrap();
        robots[j].pos = b.pos(neighbour_index(b, at, next).unwrap());
        robots[j].heading = next;
        prop_assert_eq!(best_total(&map, &robots, &[(me, None)]), best_total(&map, &robots, &[]));
        prop_assert_eq!(decide(&mut tempo, &robots, me), waits);
    }
}

/// A corridor 8 nodes long with nodes 2 to 5 visited (frontier at 1 and
/// 6), and a robot at home on node 4 facing east.
fn corridor() -> (KnownMap<Vec<Block>>, RobotView) {
    let b = crate::map::Bounds::new(Pos::new(0, 0), 8, 1);
    let mut map = KnownMap::new(vec![Block::EMPTY; crate::map::blocks_for(b.area())], b).unwrap();
    for x in 2..6 {
        map.visit(Pos::new(x, 0), line(), crate::team::RobotId(0))
            .unwrap();
    }
    let robot = RobotView {
        pos: Pos::new(4, 0),
        heading: Heading::East,
        eta: 0,
        home: Pos::new(4, 0),
        target: None,
    };
    (map, robot)
}

/// Arms east and west.
fn line() -> crate::geometry::Arms {
    crate::geometry::Arms::NONE
        .with(Heading::East)
        .with(Heading::West)
}

/// A changed map ends the commitment: the share is chosen afresh.
#[test]
fn a_new_node_ends_the_commitment() {
    let (mut map, robot) = corridor();
    let b = map.bounds();
    // Frontier at x = 1 and x = 6; the robot at 4 facing east takes 6.
    let mut robots = [robot];
    let mut fields = [DistField::new(vec![PlanCell::EMPTY; min_cells(b.area())])];
    let mut tempo = Tempo::new(TempoConfig {
        home_pull_pct: 0,
        ..TempoConfig::default()
    });
    let d = tempo.decide(&ctx(&map, &robots), &mut fields).unwrap();
    assert_eq!(d.goal, Goal::Frontier(Pos::new(6, 0)));
    assert!(tempo.kept[0].is_some());
    // It drives to 5; meanwhile node 6 becomes known (visited by nobody
    // in this team, as a relayed report would make it), a dead end.
    robots[0].pos = Pos::new(5, 0);
    mate_visits(
        &mut map,
        Pos::new(6, 0),
        crate::geometry::Arms::NONE.with(Heading::West),
    );
    let d = tempo.decide(&ctx(&map, &robots), &mut fields).unwrap();
    assert_eq!(d.goal, Goal::Frontier(Pos::new(1, 0)));
    assert_eq!(d.next, Some(Heading::West));
}

/// A team mate (robot 1) visits `p` and finds `arms`, as a relayed report
/// tells the deciding robot.
fn mate_visits(map: &mut KnownMap<Vec<Block>>, p: Pos, arms: crate::geometry::Arms) {
    map.visit(p, arms, crate::team::RobotId(1)).unwrap();
}

/// Robot 0 deciding in `robots` on `map`.
fn ctx<'a>(map: &'a KnownMap<Vec<Block>>, robots: &'a [RobotView]) -> Context<'a, Vec<Block>> {
    Context {
        map,
        timing: Timing::DEFAULT,
        robots,
        me: 0,
        tree: None,
    }
}

/// `share_slack`: a kept share survives that many map changes and no
/// more; a kept wait survives none (corridors aside: see below).
#[test]
fn a_share_survives_as_many_map_changes_as_its_slack() {
    let (mut map, robot) = corridor();
    let b = map.bounds();
    let mut robots = [robot];
    let share = Commitment::after(
        &ctx(&map, &robots),
        b.index(Pos::new(6, 0)),
        Some(Heading::East),
    )
    .unwrap();
    let wait = Commitment::after(&ctx(&map, &robots), None, None).unwrap();
    assert!(wait.holds(&ctx(&map, &robots), 3, false, far(0, 0)));
    // It drives to 5, where the share's decision left it; far behind it,
    // node 1 becomes known (one change), then node 0 (two).
    robots[0].pos = Pos::new(5, 0);
    mate_visits(&mut map, Pos::new(1, 0), line());
    assert!(!share.holds(&ctx(&map, &robots), 0, false, far(0, 0)));
    assert!(share.holds(&ctx(&map, &robots), 1, false, far(0, 0)));
    mate_visits(
        &mut map,
        Pos::new(0, 0),
        crate::geometry::Arms::NONE.with(Heading::East),
    );
    assert!(!share.holds(&ctx(&map, &robots), 1, false, far(0, 0)));
    assert!(share.holds(&ctx(&map, &robots), 2, false, far(0, 0)));
    robots[0].pos = Pos::new(4, 0);
    assert!(!wait.holds(&ctx(&map, &robots), 3, false, far(0, 0)));
}

/// The far-share rule of `far_keeps_share` `edges` and `far_nearer`
/// `nearer`.
fn far(edges: u32, nearer: u32) -> FarRule {
    FarRule {
        edges,
        nearer,
        nearer_busy: false,
    }
}

/// A corridor along y = 0 with x = 2..end visited and a junction at 4 (an
/// arm north), in a window two nodes high and `end + 2` wide.
fn corridor_with_junction(end: i16) -> (KnownMap<Vec<Block>>, crate::map::Bounds) {
    let b = crate::map::Bounds::new(Pos::new(0, 0), (end + 2) as u16, 2);
    let mut map = KnownMap::new(vec![Block::EMPTY; crate::map::blocks_for(b.area())], b).unwrap();
    for x in 2..end {
        let arms = if x == 4 {
            line().with(Heading::North)
        } else {
            line()
        };
        map.visit(Pos::new(x, 0), arms, crate::team::RobotId(0))
            .unwrap();
    }
    (map, b)
}

/// `corridor_keeps_share`: on a corridor node a share survives any map
/// change; at a junction it does not, nor does a wait anywhere.
#[test]
fn a_share_is_kept_through_a_corridor_but_not_at_a_junction() {
    // x = 2..=5 visited, a junction at 4 (an arm north); frontier nodes at
    // 1, 6 and (4, 1).
    let (mut map, b) = corridor_with_junction(6);
    let mut robots = [RobotView {
        pos: Pos::new(2, 0),
        heading: Heading::East,
        eta: 0,
        home: Pos::new(2, 0),
        target: None,
    }];
    let share = b.index(Pos::new(6, 0));
    // Decided at 2 and at 3, both driving east to 6; and a wait at 3.
    let from_2 = Commitment::after(&ctx(&map, &robots), share, Some(Heading::East)).unwrap();
    robots[0].pos = Pos::new(3, 0);
    let from_3 = Commitment::after(&ctx(&map, &robots), share, Some(Heading::East)).unwrap();
    let wait = Commitment::after(&ctx(&map, &robots), None, None).unwrap();
    // Behind the robot, node 1 becomes known: one map change.
    mate_visits(&mut map, Pos::new(1, 0), line());
    // At 3, a corridor node.
    assert!(from_2.holds(&ctx(&map, &robots), 0, true, far(0, 0)));
    assert!(!from_2.holds(&ctx(&map, &robots), 0, false, far(0, 0)));
    assert!(!wait.holds(&ctx(&map, &robots), 0, true, far(0, 0)));
    // At 4, a junction.
    robots[0].pos = Pos::new(4, 0);
    assert!(!from_3.holds(&ctx(&map, &robots), 0, true, far(0, 0)));
    assert!(from_3.holds(&ctx(&map, &robots), 1, true, far(0, 0)));
    // The share explored by a team mate: not even a corridor keeps it.
    robots[0].pos = Pos::new(3, 0);
    mate_visits(
        &mut map,
        Pos::new(6, 0),
        crate::geometry::Arms::NONE.with(Heading::West),
    );
    assert!(!from_2.holds(&ctx(&map, &robots), 0, true, far(0, 0)));
}

/// `far_keeps_share`: at a junction, whatever changed, a share at least
/// `far` edges off is kept, until a team mate announces it (or, with
/// `far_nearer`, comes near it, and with its busy rule is not busy
/// nearer by).
#[test]
fn a_far_share_is_kept_at_a_junction_until_a_team_mate_announces_it() {
    // x = 2..=13 visited, a junction at 4 (an arm north); frontier nodes
    // at 1, 14 and (4, 1).
    let (mut map, b) = corridor_with_junction(14);
    let view = |x: i16| RobotView {
        pos: Pos::new(x, 0),
        heading: Heading::East,
        eta: 0,
        home: Pos::new(x, 0),
        target: None,
    };
    let mut robots = [view(3), view(2)];
    let far_node = Pos::new(14, 0);
    let share =
        Commitment::after(&ctx(&map, &robots), b.index(far_node), Some(Heading::East)).unwrap();
    mate_visits(&mut map, Pos::new(1, 0), line());
    // At the junction 4, ten edges from the share.
    robots[0].pos = Pos::new(4, 0);
    assert!(!share.holds(&ctx(&map, &robots), 0, true, far(0, 0)));
    assert!(share.holds(&ctx(&map, &robots), 0, true, far(10, 0)));
    assert!(!share.holds(&ctx(&map, &robots), 0, true, far(11, 0)));
    // The robot's own announcement does not count; a team mate's does.
    robots[0].target = Some(far_node);
    assert!(share.holds(&ctx(&map, &robots), 0, true, far(10, 0)));
    robots[1].target = Some(far_node);
    assert!(!share.holds(&ctx(&map, &robots), 0, true, far(10, 0)));
    // With `far_nearer` 2, a team mate within half the distance of the
    // share ends it, one farther off does not.
    robots[1].target = None;
    assert!(share.holds(&ctx(&map, &robots), 0, true, far(10, 2)));
    robots[1].pos = Pos::new(11, 0);
    assert!(share.holds(&ctx(&map, &robots), 0, true, far(10, 0)));
    assert!(!share.holds(&ctx(&map, &robots), 0, true, far(10, 2)));
    // With the busy rule (`far_busy_nodes_per_robot`), it does not end
    // it while it heads for a target no farther from it than the share
    // (3 edges); it does while idle or heading farther.
    let busy = FarRule {
        nearer_busy: true,
        ..far(10, 2)
    };
    assert!(!share.holds(&ctx(&map, &robots), 0, true, busy));
    robots[1].target = Some(Pos::new(13, 1));
    assert!(share.holds(&ctx(&map, &robots), 0, true, busy));
    assert!(!share.holds(&ctx(&map, &robots), 0, true, far(10, 2)));
    robots[1].target = Some(Pos::new(4, 1));
    assert!(!share.holds(&ctx(&map, &robots), 0, true, busy));
    robots[1].target = None;
    // Nor is a wait kept so.
    let wait = Commitment::after(&ctx(&map, &robots), None, None).unwrap();
    mate_visits(
        &mut map,
        Pos::new(0, 0),
        crate::geometry::Arms::NONE.with(Heading::East),
    );
    assert!(!wait.holds(&ctx(&map, &robots), 0, true, far(1, 0)));
}

/// `Commitment::onward`: a robot that reaches its share and finds a
/// corridor node there goes on to the frontier node ahead, round a bend
/// too; not at a junction or a dead end, not onto a node a team mate has
/// announced or that is known, and not after a bump.
#[test]
fn a_reached_share_goes_on_through_a_corridor_only() {
    // x = 2..=5 visited, a junction at 4; frontier nodes at 1, 6, (4, 1).
    let (base, b) = corridor_with_junction(6);
    let at_5 = RobotView {
        pos: Pos::new(5, 0),
        heading: Heading::East,
        eta: 0,
        home: Pos::new(2, 0),
        target: None,
    };
    let mate = RobotView {
        pos: Pos::new(2, 0),
        ..at_5
    };
    let share = Commitment::after(
        &ctx(&base, &[at_5, mate]),
        b.index(Pos::new(6, 0)),
        Some(Heading::East),
    )
    .unwrap();
    // The robot reaches 6 and finds `arms` there.
    let reach = |arms: crate::geometry::Arms| {
        let mut map = base.clone();
        map.visit(Pos::new(6, 0), arms, crate::team::RobotId(0))
            .unwrap();
        map
    };
    let at_6 = RobotView {
        pos: Pos::new(6, 0),
        ..at_5
    };
    let ahead = |map: &KnownMap<Vec<Block>>, robots: &[RobotView]| {
        share.onward(&ctx(map, robots)).map(|(i, h)| (b.pos(i), h))
    };
    let straight = reach(line());
    assert_eq!(
        ahead(&straight, &[at_6, mate]),
        Some((Pos::new(7, 0), Heading::East))
    );
    let bend = reach(
        crate::geometry::Arms::NONE
            .with(Heading::West)
            .with(Heading::North),
    );
    assert_eq!(
        ahead(&bend, &[at_6, mate]),
        Some((Pos::new(6, 1), Heading::North))
    );
    let junction = reach(line().with(Heading::North));
    assert_eq!(ahead(&junction, &[at_6, mate]), None);
    let dead_end = reach(crate::geometry::Arms::NONE.with(Heading::West));
    assert_eq!(ahead(&dead_end, &[at_6, mate]), None);
    // A team mate announced the node ahead.
    let heading_there = RobotView {
        target: Some(Pos::new(7, 0)),
        ..mate
    };
    assert_eq!(ahead(&straight, &[at_6, heading_there]), None);
    // The node ahead is known already.
    let mut known = straight.clone();
    mate_visits(
        &mut known,
        Pos::new(7, 0),
        crate::geometry::Arms::NONE.with(Heading::West),
    );
    assert_eq!(ahead(&known, &[at_6, mate]), None);
    // Bumped back to 5, or turned round on 6: not where the share's
    // decision left it.
    assert_eq!(ahead(&straight, &[at_5, mate]), None);
    let turned = RobotView {
        heading: Heading::West,
        ..at_6
    };
    assert_eq!(ahead(&straight, &[turned, mate]), None);
    // Tempo decides so in teams above `corridor_extends_team` only, and
    // keeps the new share.
    let mut fields = fresh_fields(b.area(), 2);
    let mut tempo = Tempo::new(TempoConfig {
        corridor_extends_team: 1,
        ..TempoConfig::default()
    });
    tempo.kept[0] = Some(share);
    let d = tempo
        .decide(&ctx(&straight, &[at_6, mate]), &mut fields)
        .unwrap();
    assert_eq!(d.goal, Goal::Frontier(Pos::new(7, 0)));
    assert_eq!(d.next, Some(Heading::East));
    let kept = tempo.kept[0].unwrap();
    assert_eq!(kept.share(), b.index(Pos::new(7, 0)));
}

/// Busy team mates leave far shares alone only on large fields: at 256²
/// with 16 robots (a window of 258² nodes), not at 128², nor in a team
/// that keeps no far shares at all.
#[test]
fn busy_team_mates_leave_far_shares_only_on_large_fields() {
    let cfg = TempoConfig::default();
    let big = cfg.far_rule(258 * 258, 16);
    assert_eq!(
        big,
        FarRule {
            edges: 24,
            nearer: 2,
            nearer_busy: true,
        }
    );
    assert_eq!(
        cfg.far_rule(130 * 130, 16),
        FarRule {
            nearer_busy: false,
            ..big
        }
    );
    assert_eq!(cfg.far_rule(258 * 258, 6), FarRule::default());
    let off = TempoConfig {
        far_busy_nodes_per_robot: 0,
        ..cfg
    };
    assert!(!off.far_rule(258 * 258, 16).nearer_busy);
}

/// A robot without a share trails to a far frontier node only in a sparse
/// team (enough of the map window per robot), and waits in a crowded one.
#[test]
fn a_sparse_team_trails_far_and_a_crowded_one_waits() {
    // A corridor x = 2..=60, a dead end at 2, the only frontier node at 61;
    // the window is 100 nodes, 50 per robot.
    let b = crate::map::Bounds::new(Pos::new(0, 0), 100, 1);
    let mut map = KnownMap::new(vec![Block::EMPTY; crate::map::blocks_for(b.area())], b).unwrap();
    let line = crate::geometry::Arms::NONE
        .with(Heading::East)
        .with(Heading::West);
    let end = crate::geometry::Arms::NONE.with(Heading::East);
    map.visit(Pos::new(2, 0), end, crate::team::RobotId(0))
        .unwrap();
    for x in 3..=60 {
        map.visit(Pos::new(x, 0), line, crate::team::RobotId(0))
            .unwrap();
    }
    let robot = |x: i16| RobotView {
        pos: Pos::new(x, 0),
        heading: Heading::East,
        eta: 0,
        home: Pos::new(x, 0),
        target: None,
    };
    // Robot 0 stands next to the frontier node and takes it; robot 1 is
    // 51 edges away, far beyond `trail_edges`.
    let robots = [robot(60), robot(10)];
    let decide = |per_robot: u32| {
        let mut fields = fresh_fields(b.area(), 2);
        let mut tempo = Tempo::new(TempoConfig {
            trail_far_nodes_per_robot: per_robot,
            ..TempoConfig::default()
        });
        let ctx = Context {
            map: &map,
            timing: Timing::DEFAULT,
            robots: &robots,
            me: 1,
            tree: None,
        };
        tempo.decide(&ctx, &mut fields).unwrap()
    };
    let sparse = decide(48);
    assert_eq!(sparse.goal, Goal::Frontier(Pos::new(61, 0)));
    assert_eq!(sparse.next, Some(Heading::East));
    assert_eq!(decide(51).goal, Goal::Wait);
    assert_eq!(decide(0).goal, Goal::Wait);
}

/// `tie_break`: in a large team every robot, deciding alone on the same
/// map and poses, finds the same cheapest assignment, so no frontier node
/// is the goal of two robots. Without the tie-break (`tie_break_team`
/// above the team), the Hungarian's order depends on who decides and how
/// far each field grew, and some of these teams send two robots to one
/// node. Fixed seeds: a residual tie (two tie-break sums alike) is rare
/// but possible, and must not make the test flaky.
#[test]
fn a_large_team_decides_alike_whoever_decides() {
    let duplicates = |config: TempoConfig| {
        let mut teams = 0;
        for seed in 0..150u64 {
            let k = 7 + (seed % 10) as usize;
            let (map, robots) = random_team(9, 9, seed, 0.45, k);
            let mut goals = Vec::new();
            for me in 0..k {
                let ctx = Context {
                    map: &map,
                    timing: Timing::DEFAULT,
                    robots: &robots,
                    me,
                    tree: None,
                };
                let mut fields = fresh_fields(81, k);
                let d = Tempo::new(config).decide(&ctx, &mut fields).unwrap();
                if let Goal::Frontier(p) = d.goal {
                    goals.push(p);
                }
            }
            let n = goals.len();
            goals.sort_unstable_by_key(|p| (p.x, p.y));
            goals.dedup();
            teams += usize::from(goals.len() < n);
        }
        teams
    };
    assert_eq!(duplicates(TempoConfig::default()), 0);
    let untied = TempoConfig {
        tie_break_team: usize::MAX,
        ..TempoConfig::default()
    };
    assert!(duplicates(untied) > 0, "no team here has a tie to break");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// `search_to` leaves the decider's field holding the way a whole
    /// search holds, ties included, to every reachable frontier node,
    /// also after a jumping search from the same pose.
    #[test]
    fn search_to_holds_the_whole_search_s_way(
        w in 2u16..12, h in 2u16..12, seed in any::<u64>(), frac in 0.05f64..1.0,
        k in 1usize..5, me in 0usize..4,
    ) {
        let (map, robots) = random_team(w, h, seed, frac, k);
        let me = me % k;
        let ctx = Context { map: &map, timing: Timing::DEFAULT, robots: &robots, me, tree: None };
        let r = &robots[me];
        let mut fields = fresh_fields(map.bounds().area(), 2);
        let (whole, part) = fields.split_at_mut(1);
        let (whole, part) = (&mut whole[0], &mut part[0]);
        whole
            .compute(&map, ctx.timing, r.pos, r.heading, |_, _| Flow::Continue)
            .unwrap();
        let b = map.bounds();
        for p in map.frontier() {
            let i = b.index(p).unwrap();
            if whole.dist_at(i).is_none() {
                continue;
            }
            // After another search, and after the middle game's picks (a
            // jumping search from the same pose, which holds no way).
            for jumped in [false, true] {
                if jumped {
                    part.compute_jumping(&map, ctx.timing, r.pos, r.heading, |_, _| Flow::Continue)
                        .unwrap();
                    prop_assert_eq!(part.dist_at(i), whole.dist_at(i));
                } else {
                    part.compute_reverse(&map, ctx.timing, p, |_, _, _| Flow::Continue).unwrap();
                }
                search_to(&ctx, part, i).unwrap();
                prop_assert!(part.is_distance_search_from(&map, ctx.timing, r.pos, r.heading));
                prop_assert_eq!(part.first_heading(&map, i), whole.first_heading(&map, i));
                prop_assert_eq!(part.dist_at(i), whole.dist_at(i));
            }
        }
    }
}

/// The crowd penalty: a frontier node at a team mate's announced target
/// costs `crowd_penalty_edges` more (less farther off), so a split that
/// sends robots apart can beat one that is a little shorter. Robot 0 and
/// a team mate stand on node 4 of the corridor, facing east and west, and
/// the team mate has announced node 6. Without the penalty the team takes
/// the shorter split (robot 0 to 6 ahead of it, the team mate to 1 ahead
/// of it); with it, robot 0 turns to 1 and leaves 6 to the team mate, as
/// long as the penalty outweighs the two U-turns.
#[test]
fn the_crowd_penalty_sends_robots_away_from_a_team_mate_s_target() {
    let (map, robot) = corridor();
    let b = map.bounds();
    let mate = RobotView {
        heading: Heading::West,
        target: Some(Pos::new(6, 0)),
        ..robot
    };
    let robots = [robot, mate];
    let timing = Timing::DEFAULT;
    let u_turn = 2 * i64::from(timing.quarter_turn);
    let edge = i64::from(timing.edge);
    let goal = |penalty: u32| {
        let mut fields = fresh_fields(b.area(), 2);
        let mut tempo = Tempo::new(TempoConfig {
            home_pull_pct: 0,
            crowd_penalty_edges: penalty,
            ..TempoConfig::default()
        });
        tempo.decide(&ctx(&map, &robots), &mut fields).unwrap().goal
    };
    assert_eq!(goal(0), Goal::Frontier(Pos::new(6, 0)));
    // The penalty must outweigh two U-turns for the other split to win.
    let enough = u32::try_from((2 * u_turn) / edge + 1).unwrap();
    assert_eq!(goal(enough), Goal::Frontier(Pos::new(1, 0)));
    // Only in teams of at most `crowd_team`.
    let mut fields = fresh_fields(b.area(), 2);
    let mut tempo = Tempo::new(TempoConfig {
        home_pull_pct: 0,
        crowd_penalty_edges: enough,
        crowd_team: 1,
        ..TempoConfig::default()
    });
    let d = tempo.decide(&ctx(&map, &robots), &mut fields).unwrap();
    assert_eq!(d.goal, Goal::Frontier(Pos::new(6, 0)));
}

/// A corridor along y = 0 from x = 0 to `len` − 1, visited, each node with
/// an arm north too: every node (x, 1) is a frontier node.
fn combed_corridor(len: i16) -> KnownMap<Vec<Block>> {
    use crate::geometry::Arms;
    let b = crate::map::Bounds::new(Pos::new(0, 0), len as u16, 2);
    let mut map = KnownMap::new(vec![Block::EMPTY; crate::map::blocks_for(b.area())], b).unwrap();
    for x in 0..len {
        let mut arms = Arms::NONE.with(Heading::North);
        if x > 0 {
            arms = arms.with(Heading::West);
        }
        if x + 1 < len {
            arms = arms.with(Heading::East);
        }
        mate_visits(&mut map, Pos::new(x, 0), arms);
    }
    map
}

/// Robots on the corridor at `xs`, the ones given heading for (x, 1).
fn standing(xs: &[(i16, Option<i16>)]) -> Vec<RobotView> {
    xs.iter()
        .map(|&(x, t)| RobotView {
            pos: Pos::new(x, 0),
            heading: Heading::East,
            eta: 0,
            home: Pos::new(x, 0),
            target: t.map(|t| Pos::new(t, 1)),
        })
        .collect()
}

/// `cluster_radius`: robots chained by where they stand or head form a
/// cluster; the deciding robot leaves out the others, their announced
/// targets with them, but not in the endgame.
#[test]
fn a_large_team_assigns_only_the_deciding_robot_s_cluster() {
    let map = combed_corridor(64);
    let b = map.bounds();
    let at = |x: i16| b.index(Pos::new(x, 1));
    // Two groups 24 apart (0, 4, 8, 12 and 36, 44, 52), radius 16.
    let mut robots = standing(&[
        (0, None),
        (4, None),
        (8, None),
        (12, None),
        (36, Some(40)),
        (44, None),
        (52, Some(56)),
    ]);
    let cut = |robots: &[RobotView], me: usize, radius: u32| {
        let ctx = Context {
            map: &map,
            timing: Timing::DEFAULT,
            robots,
            me,
            tree: None,
        };
        let (mut out, mut shares) = (0u32, [None; crate::explore::MAX_ROBOTS]);
        outside_cluster(&ctx, radius, &mut out, &mut shares);
        (out, shares)
    };
    let (out, shares) = cut(&robots, 0, 16);
    assert_eq!(out, 0b111_0000);
    assert_eq!(&shares[4..7], &[at(40), None, at(56)]);
    assert_eq!(shares[..4], [None; 4]);
    // Either side finds the same cut (the relation is symmetric).
    assert_eq!(cut(&robots, 5, 16).0, 0b000_1111);
    // A target within reach joins the groups: robot 4 heads for (20, 1).
    robots[4].target = Some(Pos::new(20, 1));
    assert_eq!(cut(&robots, 0, 16).0, 0);
    robots[4].target = Some(Pos::new(40, 1));
    // Radius 0 is off; a smaller radius cuts more.
    assert_eq!(cut(&robots, 0, 0).0, 0);
    assert_eq!(cut(&robots, 0, 4).0, 0b111_0000);
    assert_eq!(cut(&robots, 0, 3).0, 0b111_1110);
    // The endgame (fewer frontier nodes than robots) assigns everyone.
    let short = combed_corridor(6);
    let few = standing(&[
        (0, None),
        (1, None),
        (2, None),
        (3, None),
        (4, None),
        (5, None),
        (5, None),
    ]);
    let ctx = Context {
        map: &short,
        timing: Timing::DEFAULT,
        robots: &few,
        me: 0,
        tree: None,
    };
    let (mut out, mut shares) = (0u32, [None; crate::explore::MAX_ROBOTS]);
    outside_cluster(&ctx, 1, &mut out, &mut shares);
    assert_eq!(out, 0);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Robots of one cluster decide alike, whoever decides: no two of
    /// them head for the same frontier node, and none heads for a target
    /// that a robot outside its cluster announced.
    #[test]
    fn a_cluster_decides_alike_and_leaves_other_clusters_targets(
        seed in 0u64..1_000_000,
        k in 7usize..=16,
    ) {
        let (map, mut robots) = random_team(40, 40, seed, 0.35, k);
        let frontier: Vec<Pos> = map.frontier().collect();
        prop_assume!(frontier.len() >= k);
        // Every third robot has announced a frontier node.
        for (j, r) in robots.iter_mut().enumerate().filter(|(j, _)| j % 3 == 0) {
            r.target = Some(frontier[(seed as usize + j * 7) % frontier.len()]);
        }
        // Far shares kept (`far_keeps_share`) need the keeping robot's
        // commitment, which a fresh strategy has not: off here.
        let config = TempoConfig {
            cluster_radius: 6,
            far_keeps_share: 0,
            ..TempoConfig::default()
        };
        let mut goals = Vec::new();
        let mut outs = Vec::new();
        for me in 0..k {
            let ctx = Context { map: &map, timing: Timing::DEFAULT, robots: &robots, me, tree: None };
            let (mut out, mut shares) = (0u32, [None; crate::explore::MAX_ROBOTS]);
            outside_cluster(&ctx, config.cluster_radius, &mut out, &mut shares);
            let mut fields = fresh_fields(1600, k);
            let d = Tempo::new(config).decide(&ctx, &mut fields).unwrap();
            if let Goal::Frontier(p) = d.goal {
                for (o, r) in robots.iter().enumerate() {
                    if out & (1 << o) != 0 && r.target == Some(p) {
                        prop_assert!(false, "robot {me} heads for robot {o}'s target");
                    }
                }
                goals.push((me, p));
            }
            outs.push(out);
        }
        for &(a, pa) in &goals {
            for &(b, pb) in &goals {
                if a < b && outs[a] & (1 << b) == 0 {
                    prop_assert_eq!(outs[a], outs[b], "clusters differ");
                    prop_assert_ne!(pa, pb, "robots {} and {} of one cluster", a, b);
                }
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    /// On a maze, a large team's decisions read off the known graph's
    /// forest (`Context::tree`) are the searches' decisions, whoever
    /// decides, with announced targets or without.
    #[test]
    fn decisions_read_off_the_forest_are_the_searches(
        w in 3u16..20, h in 3u16..20, seed in any::<u64>(), frac in 0.1f64..0.9,
        k in 7usize..17, targets in any::<bool>(),
    ) {
        let (map, mut robots) = crate::explore::tests::random_team_in(w, h, (seed, true), frac, k);
        if targets {
            let frontier: Vec<Pos> = map.frontier().collect();
            for (j, r) in robots.iter_mut().enumerate().filter(|(j, _)| j % 3 == 0) {
                r.target = frontier.get(j % frontier.len().max(1)).copied();
            }
        }
        let area = map.bounds().area();
        let mut forest = crate::path::Forest::new(vec![PlanCell::EMPTY; area]);
        forest.sync(&map);
        prop_assert!(forest.holds(&map));
        for me in 0..k {
            let plain = Context { map: &map, timing: Timing::DEFAULT, robots: &robots, me, tree: None };
            let read = Context { tree: Some(forest.view()), ..plain };
            let a = Tempo::new(TempoConfig::default()).decide(&plain, &mut fresh_fields(area, k + 1));
            let b = Tempo::new(TempoConfig::default()).decide(&read, &mut fresh_fields(area, k + 1));
            prop_assert_eq!(a, b, "robot {}", me);
        }
    }
}
