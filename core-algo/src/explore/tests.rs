use super::*;
use crate::geometry::Arms;
use crate::map::{Bounds, blocks_for};
use crate::path::min_cells;
use crate::team::RobotId;
use std::vec;
use std::vec::Vec;

fn open_row_map() -> KnownMap<Vec<Block>> {
    // A 12 × 3 window; the middle row y = 1 from x = 0..=5 visited, every
    // node a cross, so the frontier runs along y = 0, y = 2 and x = 6.
    let b = Bounds::new(Pos::new(0, 0), 12, 3);
    let mut m = KnownMap::new(vec![Block::EMPTY; blocks_for(b.area())], b).unwrap();
    for x in 0..6 {
        m.visit(
            Pos::new(x, 1),
            Arms::CROSS
                .without(if x == 0 {
                    Heading::West
                } else {
                    Heading::North
                })
                .with(Heading::North),
            RobotId(0),
        )
        .unwrap();
    }
    m
}

fn view(pos: Pos, target: Option<Pos>) -> RobotView {
    RobotView {
        pos,
        heading: Heading::East,
        eta: 0,
        home: pos,
        target,
    }
}

#[test]
fn cooperation_penalty_follows_the_seed_numbers() {
    let m = open_row_map();
    let layer = CooperationLayer { peak: 5, radius: 4 };
    assert_eq!(
        (0..6).map(|d| layer.penalty_edges(d)).collect::<Vec<_>>(),
        [5, 4, 3, 2, 1, 0]
    );
    // Another robot announced (3, 2). Its own node +5; (4, 2) is one step
    // along the unknown row above the known row: +4 (an edge between two
    // unknown nodes does not block); (3, 0) is two away across the known
    // node (3, 1): +3; (6, 1) lies three away but the direct routes pass
    // unknown nodes (4, 2), (5, 2), (6, 2) or known ones with arms: the
    // route (3,2)→(4,2) is open, (4,2)→(4,1) needs (4,1)'s north arm.
    let robots = [
        view(Pos::new(0, 1), None),
        view(Pos::new(5, 1), Some(Pos::new(3, 2))),
    ];
    let ctx = Context {
        map: &m,
        timing: Timing::DEFAULT,
        robots: &robots,
        me: 0,
        tree: None,
    };
    let e = Timing::DEFAULT.edge;
    let cost = |p: Pos| layer.cost(&ctx, m.bounds().index(p).unwrap(), p);
    assert_eq!(cost(Pos::new(3, 2)), 5 * e);
    assert_eq!(cost(Pos::new(3, 0)), 3 * e);
    assert_eq!(cost(Pos::new(8, 2)), 0, "beyond the radius");
    // Robot 0 ignores its own announcement.
    let ctx_self = Context { me: 1, ..ctx };
    assert_eq!(
        layer.cost(
            &ctx_self,
            m.bounds().index(Pos::new(3, 2)).unwrap(),
            Pos::new(3, 2)
        ),
        0
    );
}

#[test]
fn a_wall_blocks_the_direct_route() {
    // Two known nodes side by side without an arm between them: the route
    // from the frontier north of one to the frontier north of the other
    // (Manhattan 1) is open (both unknown), but from north of one to south
    // of the other (Manhattan 3) every monotone route crosses the wall.
    let b = Bounds::new(Pos::new(0, 0), 2, 3);
    let mut m = KnownMap::new(vec![Block::EMPTY; 1], b).unwrap();
    let ns = Arms::NONE.with(Heading::North).with(Heading::South);
    m.visit(Pos::new(0, 1), ns, RobotId(0)).unwrap();
    m.visit(Pos::new(1, 1), ns, RobotId(0)).unwrap();
    assert!(CooperationLayer::direct_route_open(
        &m,
        Pos::new(0, 2),
        Pos::new(1, 2)
    ));
    assert!(!CooperationLayer::direct_route_open(
        &m,
        Pos::new(0, 2),
        Pos::new(1, 0)
    ));
    assert!(CooperationLayer::direct_route_open(
        &m,
        Pos::new(0, 2),
        Pos::new(0, 0)
    ));
}

#[test]
fn seed_explorer_prefers_unclaimed_ground_and_ties_go_south_west() {
    let m = open_row_map();
    let mut fields = vec![DistField::new(vec![
        PlanCell::EMPTY;
        min_cells(m.bounds().area())
    ])];
    // Alone at (2, 1) facing east: (2, 0) and (2, 2) both cost one quarter
    // turn and an edge; the southern one wins the tie.
    let robots = [view(Pos::new(2, 1), None)];
    let ctx = Context {
        map: &m,
        timing: Timing::DEFAULT,
        robots: &robots,
        me: 0,
        tree: None,
    };
    let d = SeedExplorer::default().decide(&ctx, &mut fields).unwrap();
    assert_eq!(d.goal, Goal::Frontier(Pos::new(2, 0)));
    assert_eq!(d.next, Some(Heading::South));
    // With another robot's target at (2, 0): (2, 0) costs T + E + 5E and
    // (2, 2) costs T + E + 3E (open route through the known (2, 1)), while
    // (4, 0) costs 3E + T with no penalty: the route along y = 0 crosses
    // the unknown (3, 0).
    let robots = [
        view(Pos::new(2, 1), None),
        view(Pos::new(0, 1), Some(Pos::new(2, 0))),
    ];
    let ctx = Context {
        map: &m,
        timing: Timing::DEFAULT,
        robots: &robots,
        me: 0,
        tree: None,
    };
    let d = SeedExplorer::default().decide(&ctx, &mut fields).unwrap();
    assert_eq!(d.goal, Goal::Frontier(Pos::new(4, 0)));
    assert_eq!(d.next, Some(Heading::East));
    // Nearest frontier ignores the other robot.
    let d = NearestFrontier.decide(&ctx, &mut fields).unwrap();
    assert_eq!(d.goal, Goal::Frontier(Pos::new(2, 0)));
}

/// A corridor x = 0..=6 at y = 0 with x = 1..=5 visited: the frontier is
/// (0, 0) and (6, 0).
fn corridor() -> (Bounds, KnownMap<Vec<Block>>) {
    let b = Bounds::new(Pos::new(0, 0), 7, 1);
    let mut m = KnownMap::new(vec![Block::EMPTY; blocks_for(b.area())], b).unwrap();
    let ew = Arms::NONE.with(Heading::East).with(Heading::West);
    for x in 1..=5 {
        m.visit(Pos::new(x, 0), ew, RobotId(0)).unwrap();
    }
    (b, m)
}

/// Tempo's home pull: of two frontier nodes equally far from the robot,
/// the one farther from its home goes first; move the home and the choice
/// follows.
#[test]
fn tempo_explores_away_from_home_first() {
    // Three edges and one quarter turn from (3, 0) to either end.
    let (b, m) = corridor();
    let choose = |home: Pos, pull: u32| {
        let robots = [RobotView {
            pos: Pos::new(3, 0),
            heading: Heading::North,
            eta: 0,
            home,
            target: None,
        }];
        let ctx = Context {
            map: &m,
            timing: Timing::DEFAULT,
            robots: &robots,
            me: 0,
            tree: None,
        };
        let mut fields = [DistField::new(vec![PlanCell::EMPTY; min_cells(b.area())])];
        let mut t = Tempo::new(TempoConfig {
            home_pull_pct: pull,
            ..TempoConfig::default()
        });
        t.decide(&ctx, &mut fields).unwrap()
    };
    assert_eq!(TempoConfig::default().home_pull_pct, 25);
    let east = choose(Pos::new(1, 0), 25);
    assert_eq!(east.goal, Goal::Frontier(Pos::new(6, 0)));
    assert_eq!(east.next, Some(Heading::East));
    let west = choose(Pos::new(5, 0), 25);
    assert_eq!(west.goal, Goal::Frontier(Pos::new(0, 0)));
    assert_eq!(west.next, Some(Heading::West));
    // Without the pull both cost the same and the tie-break decides,
    // wherever home is.
    assert_eq!(choose(Pos::new(1, 0), 0), choose(Pos::new(5, 0), 0));
}

/// Tempo's near trailing: a robot left without a share (two frontier nodes,
/// each taken by a nearer team mate) drives to its nearest frontier node
/// when it is at most 8 edges away, so that it is there if a share
/// appears; in a team larger than `trail_team` it waits where it stands.
#[test]
fn tempo_trails_a_near_frontier_only_in_a_small_team() {
    let (b, m) = corridor();
    let at = |x| RobotView {
        pos: Pos::new(x, 0),
        heading: Heading::North,
        eta: 0,
        home: Pos::new(x, 0),
        target: None,
    };
    let robots = [at(3), at(1), at(5)];
    let ctx = Context {
        map: &m,
        timing: Timing::DEFAULT,
        robots: &robots,
        me: 0,
        tree: None,
    };
    let mut fields: [_; 3] =
        core::array::from_fn(|_| DistField::new(vec![PlanCell::EMPTY; min_cells(b.area())]));
    let trails = Tempo::default().decide(&ctx, &mut fields).unwrap();
    assert!(
        matches!(trails.goal, Goal::Frontier(p) if p == Pos::new(0, 0) || p == Pos::new(6, 0)),
        "{trails:?}"
    );
    let mut big_team = Tempo::default();
    big_team.config.trail_team = 2;
    let waits = big_team.decide(&ctx, &mut fields).unwrap();
    assert_eq!(waits.goal, Goal::Wait);
    assert_eq!(waits.next, None);
}

/// A random known map (`frac` of its `w` × `h` nodes known, see
/// `random_known`) and a team of `k` standing on known nodes, with homes
/// on known nodes, all of them drawn from `seed`.
pub(super) fn random_team(
    w: u16,
    h: u16,
    seed: u64,
    frac: f64,
    k: usize,
) -> (KnownMap<Vec<Block>>, Vec<RobotView>) {
    random_team_in(w, h, (seed, false), frac, k)
}

/// [`random_team`] on a perfect maze (mostly corridors, where the picks'
/// searches jump) if `maze`.
pub(super) fn random_team_in(
    w: u16,
    h: u16,
    (seed, maze): (u64, bool),
    frac: f64,
    k: usize,
) -> (KnownMap<Vec<Block>>, Vec<RobotView>) {
    let area = usize::from(w) * usize::from(h);
    let known = (area as f64 * frac) as usize + 1;
    let map = if maze {
        let b = crate::map::Bounds::new(Pos::new(0, 0), w, h);
        crate::path::tests::known_prefix(b, &crate::path::tests::tree_arms(b, seed), known)
    } else {
        crate::path::tests::random_known(w, h, seed, known)
    };
    let b = map.bounds();
    let known: Vec<usize> = (0..area)
        .filter(|&i| crate::path::arms_at(&map, i).is_some())
        .collect();
    let pick = |j: usize, salt: u64| {
        let x = seed.rotate_left((j * 7) as u32 + salt as u32) ^ salt.wrapping_mul(0x9E37);
        b.pos(known[(x as usize) % known.len()])
    };
    let robots = (0..k)
        .map(|j| RobotView {
            pos: pick(j, 1),
            heading: Heading::from_index((j % 4) as u8),
            eta: 0,
            home: pick(j, 2),
            target: None,
        })
        .collect();
    (map, robots)
}

/// Once the map is complete, `go_home` reads the way from one reverse
/// field kept across decisions, and driving its answers is a cheapest way.
#[test]
fn the_way_home_on_a_complete_map_is_cheapest_and_searched_once() {
    let b = Bounds::new(Pos::new(0, 0), 5, 4);
    let mut map = KnownMap::new(vec![Block::EMPTY; blocks_for(b.area())], b).unwrap();
    for i in 0..b.area() {
        let p = b.pos(i);
        let arms = Heading::ALL
            .into_iter()
            .filter(|&h| p.step(h).is_some_and(|q| b.index(q).is_some()))
            // A wall between (1, y) and (2, y) for y < 3: the way bends.
            .filter(|&h| {
                !(p.y < 3 && ((p.x == 1 && h == Heading::East) || (p.x == 2 && h == Heading::West)))
            })
            .fold(Arms::NONE, |a, h| a.with(h));
        map.visit(p, arms, RobotId(0)).unwrap();
    }
    assert!(map.is_complete());
    let timing = Timing {
        edge: 100,
        quarter_turn: 40,
    };
    let home = Pos::new(0, 0);
    let (mut pos, mut heading) = (Pos::new(4, 0), Heading::South);
    let mut forward = DistField::new(vec![PlanCell::EMPTY; min_cells(b.area())]);
    forward
        .compute(&map, timing, pos, heading, |_, _| Flow::Continue)
        .unwrap();
    let cheapest = forward.dist_at(b.index(home).unwrap()).unwrap();
    let mut field = DistField::new(vec![PlanCell::EMPTY; min_cells(b.area())]);
    let mut time = 0;
    for step in 0.. {
        assert!(step < 20, "never home");
        let robots = [RobotView {
            pos,
            heading,
            eta: 0,
            home,
            target: None,
        }];
        let ctx = Context {
            map: &map,
            timing,
            robots: &robots,
            me: 0,
            tree: None,
        };
        if step > 0 {
            assert!(field.is_reverse_to(&map, timing, home), "searched again");
        }
        let d = go_home(&ctx, &mut field).unwrap();
        let Some(next) = d.next else { break };
        assert_eq!(d.goal, Goal::Home);
        time += match heading.turn_to(next) {
            None => 0,
            Some(crate::geometry::Turn::UTurn) => 2 * timing.quarter_turn,
            Some(_) => timing.quarter_turn,
        } + timing.edge;
        pos = pos.step(next).unwrap();
        heading = next;
    }
    assert_eq!(pos, home);
    assert_eq!(time, cheapest);
}
