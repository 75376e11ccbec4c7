//! The 2010 numbers on hand-made maps (original-system §3.4–3.5).

use super::*;
use crate::explore::{NearestFrontier, SeedExplorer};
use crate::geometry::Arms;
use crate::map::{Bounds, blocks_for};
use crate::path::min_cells;
use crate::team::RobotId;
use crate::timing::Timing;
use std::vec;
use std::vec::Vec;

fn arms(hs: &[Heading]) -> Arms {
    hs.iter().fold(Arms::NONE, |a, &h| a.with(h))
}

/// A map over `bounds` with `nodes` visited.
fn map_of(bounds: Bounds, nodes: &[(Pos, Arms)]) -> KnownMap<Vec<Block>> {
    let mut m = KnownMap::new(vec![Block::EMPTY; blocks_for(bounds.area())], bounds).unwrap();
    for &(p, a) in nodes {
        m.visit(p, a, RobotId(0)).unwrap();
    }
    m
}

/// Every node of `bounds` visited, joined to all its neighbours in the
/// window: an open grid.
fn open_grid(bounds: Bounds) -> KnownMap<Vec<Block>> {
    let nodes: Vec<(Pos, Arms)> = (0..bounds.area())
        .map(|i| {
            let p = bounds.pos(i);
            let a = Heading::ALL
                .iter()
                .filter(|&&h| p.step(h).is_some_and(|q| bounds.contains(q)))
                .fold(Arms::NONE, |a, &h| a.with(h));
            (p, a)
        })
        .collect();
    map_of(bounds, &nodes)
}

fn view(pos: Pos, heading: Heading) -> RobotView {
    RobotView {
        pos,
        heading,
        eta: 0,
        home: pos,
        target: None,
    }
}

fn fields(m: &KnownMap<Vec<Block>>) -> Vec<DistField<Vec<PlanCell>>> {
    vec![DistField::new(vec![
        PlanCell::EMPTY;
        min_cells(m.bounds().area())
    ])]
}

fn ctx<'a>(m: &'a KnownMap<Vec<Block>>, robots: &'a [RobotView]) -> Context<'a, Vec<Block>> {
    Context {
        map: m,
        timing: Timing::DEFAULT,
        robots,
        me: 0,
        tree: None,
    }
}

/// The 2010 frame: (x, y) there is (x, −y) here, and its UP (+y) is south.
fn p2010(x: i16, y: i16) -> Pos {
    Pos::new(x, -y)
}

#[test]
fn heading_bias_is_two_behind_one_aside_zero_ahead() {
    let o = Pos::new(0, 0);
    // Facing the 2010 UP (+y there, south here).
    let up = Heading::South;
    assert_eq!(heading_bias(o, up, p2010(0, 3)), 0);
    assert_eq!(heading_bias(o, up, p2010(2, 0)), LATERAL);
    assert_eq!(heading_bias(o, up, p2010(2, 5)), LATERAL);
    assert_eq!(heading_bias(o, up, p2010(0, -2)), BEHIND);
    assert_eq!(heading_bias(o, up, p2010(-4, -1)), BEHIND);
    // The same rule for every heading: "behind" wins over "aside".
    for h in Heading::ALL {
        let (dx, dy) = h.delta();
        assert_eq!(heading_bias(o, h, Pos::new(dx, dy)), 0);
        assert_eq!(heading_bias(o, h, Pos::new(-dx, -dy)), BEHIND);
        assert_eq!(heading_bias(o, h, Pos::new(dy, dx)), LATERAL);
        assert_eq!(heading_bias(o, h, Pos::new(dy - dx, dx - dy)), BEHIND);
        assert_eq!(heading_bias(o, h, o), 0);
    }
}

#[test]
fn worked_examples_of_original_system_3_5() {
    // Robot at (0, 0) heading UP (+y in the 2010 frame), open grid:
    // (0, 3) costs 30, (2, 0) costs 22, (0, −2) costs 24.
    let b = Bounds::new(Pos::new(-4, -5), 9, 11);
    let m = open_grid(b);
    let robots = [view(Pos::new(0, 0), Heading::South)];
    let c = ctx(&m, &robots);
    let mut f = fields(&m);
    let o = Pos::new(0, 0);
    f[0].compute_weighted(
        &m,
        o,
        |i| entry_cost(&c, o, Heading::South, b.pos(i)),
        |_, _| Flow::Continue,
    )
    .unwrap();
    assert_eq!(f[0].dist(p2010(0, 3)), Some(30));
    assert_eq!(f[0].dist(p2010(2, 0)), Some(22));
    assert_eq!(f[0].dist(p2010(0, -2)), Some(24));
    // The bias is measured from the robot, not along the path: to (2, 3)
    // the cheapest path runs ahead first, 3 × 10 + 2 × 11.
    assert_eq!(f[0].dist(p2010(2, 3)), Some(52));
    assert_eq!(
        f[0].weighted_first_heading(b.index(p2010(2, 3)).unwrap()),
        Some(Heading::South)
    );
    // Another robot on (0, 1) adds 50 to that node; the path to (0, 3)
    // then goes round it, back onto the robot's line as soon as it can:
    // (1, 0), (1, 1), (1, 2), (0, 2), (0, 3) = 11 + 11 + 11 + 10 + 10 = 53
    // < 30 + 50.
    let robots = [view(o, Heading::South), view(p2010(0, 1), Heading::North)];
    let c = ctx(&m, &robots);
    f[0].compute_weighted(
        &m,
        o,
        |i| entry_cost(&c, o, Heading::South, b.pos(i)),
        |_, _| Flow::Continue,
    )
    .unwrap();
    assert_eq!(f[0].dist(p2010(0, 1)), Some(60));
    assert_eq!(f[0].dist(p2010(0, 3)), Some(53));
    // Robot 1 sees robot 0 on (0, 0), straight ahead of it.
    assert_eq!(
        entry_cost(&Context { me: 1, ..c }, p2010(0, 1), Heading::North, o),
        10 + 50
    );
}

#[test]
fn cooperative_values_and_their_overwrite() {
    assert_eq!(
        (0..10).map(cooperative_penalty).collect::<Vec<_>>(),
        [100, 90, 80, 70, 60, 50, 40, 30, 0, 0]
    );
    // A row y = 1 visited from x = 0 to 5 (crosses), frontier above and
    // below. Another robot announced (2, 2), the cheapest node for robot 0
    // at (2, 1) facing north. The 2010 Distance layer overwrote the +100:
    // robot 0 still picks it; the seed's design avoids it.
    let b = Bounds::new(Pos::new(0, 0), 8, 3);
    let row: Vec<(Pos, Arms)> = (0..6)
        .map(|x| {
            let a = Arms::CROSS;
            (
                Pos::new(x, 1),
                if x == 0 { a.without(Heading::West) } else { a },
            )
        })
        .collect();
    let m = map_of(b, &row);
    let mut other = view(Pos::new(5, 1), Heading::West);
    other.target = Some(Pos::new(2, 2));
    let robots = [view(Pos::new(2, 1), Heading::North), other];
    let c = ctx(&m, &robots);
    let mut f = fields(&m);
    let d = Legacy2010.decide(&c, &mut f).unwrap();
    assert_eq!(d.goal, Goal::Frontier(Pos::new(2, 2)));
    assert_eq!(d.next, Some(Heading::North));
    assert_eq!(
        Legacy2010::choose(&c, Heading::North, &mut f[0]).unwrap(),
        Some((b.index(Pos::new(2, 2)).unwrap(), 10))
    );
    let d = SeedExplorer::default().decide(&c, &mut f).unwrap();
    assert_ne!(d.goal, Goal::Frontier(Pos::new(2, 2)));
}

#[test]
fn map_keys_are_the_2010_make_key() {
    // Utility.makeKey(x, y) = ((x ^ y) << 16) | (x & 0xFFFF), 2010 frame.
    assert_eq!(legacy_key(p2010(0, 0)), 0);
    assert_eq!(legacy_key(p2010(1, 2)), (3 << 16) | 1);
    assert_eq!(legacy_key(p2010(-1, 0)), -1);
    assert_eq!(legacy_key(p2010(0, -1)), -65536);
    assert_eq!(legacy_key(p2010(3, -5)), -524285);
    assert_eq!(legacy_key(p2010(2, -2)), -262142);
    assert_eq!(legacy_key(p2010(2, 0)), 131074);
    assert_eq!(legacy_key(p2010(2, 2)), 2);
}

#[test]
fn ties_go_to_the_least_2010_key() {
    // Robot at (2, 1) facing east on the row of the previous test: (2, 0)
    // and (2, 2) both cost 11 (one node aside). The 2010 keys: (2, 0) here
    // is (2, 0) there, key 131074; (2, 2) here is (2, −2) there, key
    // −262142: (2, 2) wins, where the south-west rule of the other
    // strategies picks (2, 0).
    let b = Bounds::new(Pos::new(0, 0), 8, 3);
    let row: Vec<(Pos, Arms)> = (0..6)
        .map(|x| {
            let a = Arms::CROSS;
            (
                Pos::new(x, 1),
                if x == 0 { a.without(Heading::West) } else { a },
            )
        })
        .collect();
    let m = map_of(b, &row);
    let robots = [view(Pos::new(2, 1), Heading::East)];
    let c = ctx(&m, &robots);
    let mut f = fields(&m);
    assert_eq!(
        Legacy2010::choose(&c, Heading::East, &mut f[0]).unwrap(),
        Some((b.index(Pos::new(2, 2)).unwrap(), 11))
    );
    let d = Legacy2010.decide(&c, &mut f).unwrap();
    assert_eq!(d.goal, Goal::Frontier(Pos::new(2, 2)));
    assert_eq!(d.next, Some(Heading::North));
    let d = NearestFrontier.decide(&c, &mut f).unwrap();
    assert_eq!(d.goal, Goal::Frontier(Pos::new(2, 0)));
}

#[test]
fn deduced_nodes_are_still_targets() {
    // A ring of eight visited nodes around (1, 1); only (0, 1) has an arm
    // into it. This project deduces (1, 1) (a dead end west) and calls the
    // map complete; the 2010 GridMap kept it as a frontier node and drove
    // there: 10 ahead to (0, 1), then 11 aside.
    use Heading::{East as E, North as N, South as S, West as W};
    let b = Bounds::new(Pos::new(0, 0), 3, 3);
    let m = map_of(
        b,
        &[
            (Pos::new(0, 0), arms(&[N, E])),
            (Pos::new(1, 0), arms(&[W, E])),
            (Pos::new(2, 0), arms(&[W, N])),
            (Pos::new(2, 1), arms(&[S, N])),
            (Pos::new(2, 2), arms(&[S, W])),
            (Pos::new(1, 2), arms(&[E, W])),
            (Pos::new(0, 2), arms(&[E, S])),
            (Pos::new(0, 1), arms(&[N, S, E])),
        ],
    );
    assert!(m.is_complete());
    let robots = [view(Pos::new(0, 0), N)];
    let c = ctx(&m, &robots);
    let mut f = fields(&m);
    assert_eq!(
        Legacy2010::choose(&c, N, &mut f[0]).unwrap(),
        Some((b.index(Pos::new(1, 1)).unwrap(), 21))
    );
    let d = Legacy2010.decide(&c, &mut f).unwrap();
    assert_eq!(d.goal, Goal::Frontier(Pos::new(1, 1)));
    assert_eq!(d.next, Some(N));
    assert_eq!(NearestFrontier.decide(&c, &mut f).unwrap(), Decision::STAY);
}

#[test]
fn a_turn_is_followed_by_a_new_decision() {
    // The robot stands at (0, 0) facing north with arms east and south.
    // North of it, reached only round (1, 0), (1, 1), lies T1 = (0, 6);
    // south, down a corridor, T2 = (0, −7).
    // Facing north: T1 costs 11 + 11 + 6 × 10 = 82, T2 7 × 12 = 84: T1,
    // turn east. Facing east: T1 costs 10 + 11 + 6 × 11 = 87, T2 7 × 11 =
    // 77: T2, turn south. Facing south: T2 70, stays. The 2010 robot made
    // both turns, each followed by a new run of its chain.
    use Heading::{East as E, North as N, South as S, West as W};
    let b = Bounds::new(Pos::new(0, -7), 2, 15);
    let mut nodes = vec![
        (Pos::new(0, 0), arms(&[E, S])),
        (Pos::new(1, 0), arms(&[W, N])),
        (Pos::new(1, 1), arms(&[S, W])),
        (Pos::new(0, 1), arms(&[E, N])),
    ];
    nodes.extend((2..6).map(|y| (Pos::new(0, y), arms(&[N, S]))));
    nodes.extend((1..7).map(|y| (Pos::new(0, -y), arms(&[N, S]))));
    let m = map_of(b, &nodes);
    let t1 = b.index(Pos::new(0, 6)).unwrap();
    let t2 = b.index(Pos::new(0, -7)).unwrap();
    assert!(m.is_frontier_at(t1) && m.is_frontier_at(t2));
    let robots = [view(Pos::new(0, 0), N)];
    let c = ctx(&m, &robots);
    let mut f = fields(&m);
    assert_eq!(
        Legacy2010::choose(&c, N, &mut f[0]).unwrap(),
        Some((t1, 82))
    );
    assert_eq!(f[0].weighted_first_heading(t1), Some(E));
    assert_eq!(
        Legacy2010::choose(&c, E, &mut f[0]).unwrap(),
        Some((t2, 77))
    );
    assert_eq!(
        Legacy2010::choose(&c, S, &mut f[0]).unwrap(),
        Some((t2, 70))
    );
    let d = Legacy2010.decide(&c, &mut f).unwrap();
    assert_eq!(d.goal, Goal::Frontier(Pos::new(0, -7)));
    assert_eq!(d.next, Some(S));
}

#[test]
fn unreachable_frontier_sends_the_robot_home_along_2010_costs() {
    // (0, 0)–(1, 0) known; (4, 0) known from a relayed report with an arm
    // into (5, 0), which no path reaches. The 2010 code stayed in EXPLORE
    // for ever; here the robot goes home.
    let b = Bounds::new(Pos::new(0, 0), 6, 1);
    let ew = arms(&[Heading::East, Heading::West]);
    let m = map_of(
        b,
        &[
            (Pos::new(0, 0), arms(&[Heading::East])),
            (Pos::new(1, 0), arms(&[Heading::West])),
            (Pos::new(4, 0), ew),
        ],
    );
    let mut me = view(Pos::new(1, 0), Heading::East);
    me.home = Pos::new(0, 0);
    let robots = [me];
    let c = ctx(&m, &robots);
    let mut f = fields(&m);
    let d = Legacy2010.decide(&c, &mut f).unwrap();
    assert_eq!(d.goal, Goal::Home);
    assert_eq!(d.next, Some(Heading::West));
    // At home: stay.
    let robots = [view(Pos::new(0, 0), Heading::West)];
    let c = ctx(&m, &robots);
    assert_eq!(Legacy2010.decide(&c, &mut f).unwrap(), Decision::STAY);
}

#[test]
fn a_robot_counts_where_it_last_reported() {
    // The 2010 position of a robot was the node it last reported: one on
    // its way to a node still counts on the node it left.
    let t = Timing::DEFAULT;
    let mut r = view(Pos::new(3, 3), Heading::East);
    assert_eq!(reported_pos(&r, t), Pos::new(3, 3));
    r.eta = t.edge;
    assert_eq!(reported_pos(&r, t), Pos::new(2, 3));
    r.eta = t.edge + t.turn(2);
    assert_eq!(reported_pos(&r, t), Pos::new(2, 3));
    // Far off (the agent's failed or unknown team mates): where it stands.
    r.eta = u32::MAX / 4;
    assert_eq!(reported_pos(&r, t), Pos::new(3, 3));
    // So a robot driving to the cheapest frontier node does not claim it:
    // robot 1 left (3, 1) for (3, 2); robot 0 at (2, 1) facing north still
    // takes (2, 2) (10), and (3, 1) costs 50 more to pass.
    let b = Bounds::new(Pos::new(0, 0), 8, 3);
    let row: Vec<(Pos, Arms)> = (0..6)
        .map(|x| {
            let a = Arms::CROSS;
            (
                Pos::new(x, 1),
                if x == 0 { a.without(Heading::West) } else { a },
            )
        })
        .collect();
    let m = map_of(b, &row);
    let mut other = view(Pos::new(2, 2), Heading::North);
    other.eta = t.edge;
    let robots = [view(Pos::new(2, 1), Heading::North), other];
    let c = ctx(&m, &robots);
    assert_eq!(
        entry_cost(&c, Pos::new(2, 1), Heading::North, Pos::new(2, 2)),
        10
    );
    let mut f = fields(&m);
    assert_eq!(
        Legacy2010::choose(&c, Heading::North, &mut f[0]).unwrap(),
        Some((b.index(Pos::new(2, 2)).unwrap(), 10))
    );
    other.eta = 0;
    let robots = [view(Pos::new(2, 1), Heading::North), other];
    let c = ctx(&m, &robots);
    assert_eq!(
        entry_cost(&c, Pos::new(2, 1), Heading::North, Pos::new(2, 2)),
        60
    );
}
