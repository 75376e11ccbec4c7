use super::*;
use crate::explore::NearestFrontier;
use crate::map::{Bounds, blocks_for};
use crate::path::min_cells;
use std::vec;
use std::vec::Vec as StdVec;

type ThreeFields = Agent<StdVec<Block>, StdVec<PlanCell>, NearestFrontier, 3>;

/// Robot 1 standing at (0, 0), the dead end of a corridor that runs
/// north to (0, 3) with a side arm at (0, 2) to (1, 2); robot 0 stands
/// at (0, 1) and its home is (0, 0): the two are swapped. `homes`
/// lists more team mates' homes (they stand at home).
fn swapped(homes: &[Pos]) -> ThreeFields {
    let ns = Arms::NONE.with(Heading::North).with(Heading::South);
    let nodes = [
        (0, 0, Arms::NONE.with(Heading::North)),
        (0, 1, ns),
        (0, 2, ns.with(Heading::East)),
        (1, 2, Arms::NONE.with(Heading::West)),
        (0, 3, Arms::NONE.with(Heading::South)),
    ];
    let mut a = returning(Bounds::new(Pos::new(0, 0), 2, 4), nodes);
    a.pos = Pos::new(0, 0);
    a.heading = Heading::North;
    a.home = Pos::new(0, 1);
    a.peers[0] = mate(Pos::new(0, 1), Pos::new(0, 0));
    for (i, &home) in homes.iter().enumerate() {
        a.peers[i + 2] = mate(home, home);
    }
    a
}

/// Robot 1 on its way home (no pose or home set yet) on the complete
/// map of `nodes`.
fn returning(bounds: Bounds, nodes: impl IntoIterator<Item = (i16, i16, Arms)>) -> ThreeFields {
    let mut map = KnownMap::new(vec![Block::EMPTY; blocks_for(bounds.area())], bounds).unwrap();
    for (x, y, arms) in nodes {
        map.visit(Pos::new(x, y), arms, RobotId(0)).unwrap();
    }
    assert!(map.is_complete());
    let fields =
        core::array::from_fn(|_| DistField::new(vec![PlanCell::EMPTY; min_cells(bounds.area())]));
    let mut a = Agent::new(
        RobotId(1),
        map,
        fields,
        NearestFrontier,
        AgentConfig::default(),
    );
    a.mode = Mode::Return;
    a
}

/// A retreat's question whether a spot's way drives through the
/// bumper gets the walk's answer whether it walks or reads the spare
/// field's memo: spots asked nearest first as the search grows, as
/// `retreat_spot` does, on random fields and perfect mazes, about a
/// start's neighbour and about far nodes.
#[test]
fn through_bumper_answers_as_the_walk_does() {
    use crate::path::tests::{bfs_order, random_arms, tree_arms};
    let timing = AgentConfig::default().timing;
    let mut fields_tried = 0;
    for seed in 1..=24u64 {
        let bounds = Bounds::new(Pos::new(0, 0), 12, 10);
        let arms = if seed % 2 == 0 {
            random_arms(bounds, seed)
        } else {
            tree_arms(bounds, seed)
        };
        let mut map = KnownMap::new(vec![Block::EMPTY; blocks_for(bounds.area())], bounds).unwrap();
        let order = bfs_order(bounds, &arms);
        if order.len() < 24 {
            continue;
        }
        fields_tried += 1;
        for &i in order.iter().take(order.len() * 3 / 4) {
            map.visit(bounds.pos(i), arms[i], RobotId(0)).unwrap();
        }
        let new_field = || DistField::new(vec![PlanCell::EMPTY; min_cells(bounds.area())]);
        let (mut mine, mut spare, mut walk) = (new_field(), new_field(), new_field());
        let start = order[(seed as usize * 7) % (order.len() / 2)];
        let pose = (bounds.pos(start), Heading::ALL[seed as usize % 4]);
        walk.compute(&map, timing, pose.0, pose.1, |_, _| Flow::Continue)
            .unwrap();
        let near = Heading::ALL
            .into_iter()
            .find_map(|h| crate::path::neighbour_index(bounds, start, h))
            .unwrap();
        for blocked in [near, order[order.len() / 2], order[order.len() * 2 / 3]] {
            let mut asked = ThroughBumper {
                whole: Some(&mut spare),
                walked: 0,
                ready: false,
            };
            let (mut first, mut n, mut through) = (true, 0, 0);
            while let Some(v) = mine
                .next_where(&map, timing, pose, first, |_, _| true)
                .unwrap()
            {
                first = false;
                let answer = asked.ask(&map, timing, pose, &mine, (v, blocked));
                assert_eq!(answer, walk.path_passes(&map, v, blocked), "seed {seed}");
                n += 1;
                through += usize::from(answer);
            }
            assert!(asked.ready, "seed {seed}: {n} spots, yet no whole search");
            // Rent or buy: the walks drove back a map's worth of edges
            // before the whole search, not fewer.
            assert!(asked.walked as usize >= bounds.area(), "seed {seed}");
            if blocked != near {
                assert!(
                    through > 0 || walk.dist_at(blocked).is_none(),
                    "seed {seed}"
                );
            }
        }
    }
    assert!(fields_tried >= 16, "{fields_tried}");
}

/// A known team mate at `pos`, heading south, whose home is `home`.
fn mate(pos: Pos, home: Pos) -> Peer {
    Peer {
        known: true,
        pos,
        home,
        heading: Heading::South,
        ..NO_PEER
    }
}

/// Shut in behind the team mate it must make way for, a robot pushes
/// through it: past the first node where the team mate can step aside,
/// (0, 2), to (0, 3), not to (0, 2) itself (the team mate, with
/// nowhere to go, would only stand in our way again).
#[test]
fn shut_in_behind_the_bumper_pushes_past_a_node_with_room_aside() {
    let mut a = swapped(&[]);
    let goal = a.map.bounds().index(Pos::new(0, 0)).unwrap();
    assert_eq!(
        a.retreat_spot(goal, Pos::new(0, 1)),
        Some((Pos::new(0, 3), None))
    );
    assert!(a.plan_retreat(0, false));
    let mut out = Commands::new();
    a.decide(&mut out);
    assert_eq!(
        out.first(),
        Some(&Command::Announce {
            target: Some(Pos::new(0, 3))
        })
    );
    assert!(out.contains(&Command::Move), "{out:?}");
}

/// A corridor home, (0, `len`) down to the dead end (0, 0), with side
/// arms at (0, 2) to (1, 2) and at (0, 0) to (1, 0). Robot 1 (home
/// (0, 1)) stands at (0, `len` - 2), robot 0 (home (0, 0), deeper)
/// right behind it, robot 2 (home (1, 2)) far behind at (0, `len`).
fn corridor_home(len: i16) -> ThreeFields {
    let ns = Arms::NONE.with(Heading::North).with(Heading::South);
    let west = Arms::NONE.with(Heading::West);
    let sides = [
        (0, 0, Arms::NONE.with(Heading::North).with(Heading::East)),
        (1, 0, west),
        (0, 2, ns.with(Heading::East)),
        (1, 2, west),
        (0, len, Arms::NONE.with(Heading::South)),
    ];
    let corridor = (1..len).filter(|&y| y != 2).map(|y| (0, y, ns));
    let bounds = Bounds::new(Pos::new(0, 0), 2, len as u16 + 1);
    let mut a = returning(bounds, sides.into_iter().chain(corridor));
    a.pos = Pos::new(0, len - 2);
    a.heading = Heading::South;
    a.home = Pos::new(0, 1);
    a.peers[0] = mate(Pos::new(0, len - 1), Pos::new(0, 0));
    a.peers[2] = mate(Pos::new(0, len), Pos::new(1, 2));
    a
}

/// Ahead of the bumper on its way home and far from our own, with no
/// spot that passes every check (the side arm is a team mate's home), a
/// robot steps into that empty home ahead rather than pushing back
/// through the bumper: in a maze corridor the push had three robots
/// dance until the time limit. Never behind the bumper's goal, though
/// (shut in for good once it is home), never through a team mate, and
/// never near home, where such steps swapped robots in a cycle of homes.
#[test]
fn ahead_of_the_bumper_steps_aside_ahead_not_back_through_it() {
    let mut a = corridor_home(13);
    // The bumper's way home, in the first field, as `plan_retreat` plans it.
    let (_, goal) = a.plan_way_of(0, false).unwrap();
    assert_eq!(goal, a.map.bounds().index(Pos::new(0, 0)).unwrap());
    assert_eq!(
        a.retreat_spot(goal, Pos::new(0, 12)),
        Some((Pos::new(1, 2), Some(Pos::new(0, 2))))
    );
    // Someone standing on that home: the only spot ahead, (1, 0), lies
    // behind the bumper's goal, and there is no room to push.
    a.peers[2].pos = Pos::new(1, 2);
    a.plan_way_of(0, false).unwrap();
    assert_eq!(a.retreat_spot(goal, Pos::new(0, 12)), None);
    // A team mate standing in the corridor ahead: no spot through it.
    let mut a = corridor_home(13);
    a.peers[3] = mate(Pos::new(0, 6), Pos::new(0, 6));
    let (_, goal) = a.plan_way_of(0, false).unwrap();
    assert_eq!(a.retreat_spot(goal, Pos::new(0, 12)), None);
    // Near home (3 edges), not even the empty home.
    let mut a = corridor_home(6);
    let (_, goal) = a.plan_way_of(0, false).unwrap();
    assert_eq!(a.retreat_spot(goal, Pos::new(0, 5)), None);
}

/// With the side arm someone's home there is no room aside anywhere:
/// no push (it would only squeeze the two together).
#[test]
fn no_push_without_room_for_the_bumper_to_step_aside() {
    let mut a = swapped(&[Pos::new(1, 2)]);
    let goal = a.map.bounds().index(Pos::new(0, 0)).unwrap();
    assert_eq!(a.retreat_spot(goal, Pos::new(0, 1)), None);
}

/// A robot whose home fills first stepped aside for a team mate that
/// retreats (for it): it waits only until that team mate holds its
/// spot, not for the whole yield wait, provided every home that fills
/// before ours is taken and no other retreat is still on its way. On
/// test.sim with 4 and 5 robots it stood out the whole wait while
/// everyone waited for it (docs/results/system.md, stop 33).
#[test]
fn a_yield_to_a_retreat_ends_once_it_holds_its_spot() {
    // Robot 1 (home (0, 0), the dead end: it fills first) stepped aside
    // to (0, 3); robot 0 (home (0, 1)) retreats to (0, 6), robot 2
    // stands at home (1, 2).
    let setup = || {
        let mut a = corridor_home(8);
        a.pos = Pos::new(0, 3);
        a.home = Pos::new(0, 0);
        a.depth[..3].copy_from_slice(&[2, 3, 1]);
        a.depth_ready = true;
        a.depth_known = true;
        a.peers[0] = Peer {
            target: Some(Pos::new(0, 6)),
            ..mate(Pos::new(0, 5), Pos::new(0, 1))
        };
        a.peers[2] = mate(Pos::new(1, 2), Pos::new(1, 2));
        a.yielding = true;
        a.made_way_for = Some(0);
        a.motion = Motion::Waiting { until: 20_000 };
        a
    };
    // Still in the yield wait (a decision may wait for other reasons).
    let waits = |a: &mut ThreeFields, now: Millis| {
        a.handle(now, Event::Tick).unwrap();
        a.yielding
    };
    // On its way to the spot: wait.
    let mut a = setup();
    assert!(waits(&mut a, 100));
    // Holding it: come back now, not at 20 s.
    a.peers[0].pos = Pos::new(0, 6);
    assert!(!waits(&mut a, 200));
    assert_eq!(a.made_way_for, None);
    // Not while a team mate whose home fills first is out...
    let mut a = setup();
    a.peers[0].pos = Pos::new(0, 6);
    a.depth[2] = 4;
    a.peers[2].pos = Pos::new(0, 7);
    assert!(waits(&mut a, 100));
    // ...nor while another retreat is still on its way...
    let mut a = setup();
    a.peers[0].pos = Pos::new(0, 6);
    a.peers[2].target = Some(Pos::new(0, 7));
    assert!(waits(&mut a, 100));
    // ...nor for a team mate we did not step aside for.
    let mut a = setup();
    a.peers[0].pos = Pos::new(0, 6);
    a.made_way_for = Some(2);
    assert!(waits(&mut a, 100));
    // Made way before deciding once on the complete map: the fill order
    // is worked out for the question (the dead end fills first; the
    // decision that follows learns it for good)...
    let unknown_order = || {
        let mut a = setup();
        a.peers[0].pos = Pos::new(0, 6);
        a.depth = [0; MAX_ROBOTS];
        a.depth_ready = false;
        a.depth_known = false;
        a
    };
    let mut a = unknown_order();
    assert!(!waits(&mut a, 100));
    assert!(a.depth_known && !a.goes_first(0), "{:?}", a.depth);
    // ...but not kept by it: the robot goes on making way as before.
    let mut a = unknown_order();
    a.peers[2].target = Some(Pos::new(0, 7));
    assert!(waits(&mut a, 100));
    assert!(!a.depth_known);
}

/// A retreat spot that a team mate holds (its own retreat ends there) is
/// no spot: it will not leave for us. The retreat looks for another one,
/// or ends; a team mate that only passes the spot does not count. On maze
/// 64² with 16 robots (claim), a robot kept retreating into the spot a
/// team mate held for it (docs/results/system.md, stop 34).
#[test]
fn a_retreat_spot_a_team_mate_holds_is_given_up() {
    let mut a = swapped(&[]);
    assert!(a.plan_retreat(0, false));
    let spot = Pos::new(0, 3);
    assert_eq!(a.retreat.map(|r| r.spot), Some(spot));
    // Passing through (no announced spot there): the spot stays.
    a.peers[2] = mate(spot, Pos::new(1, 2));
    assert!(a.retreat_decision().is_some());
    assert_eq!(a.retreat.map(|r| r.spot), Some(spot));
    // Announced but elsewhere: the spot stays.
    a.peers[2].target = Some(Pos::new(1, 2));
    assert!(a.retreat_decision().is_some());
    assert_eq!(a.retreat.map(|r| r.spot), Some(spot));
    // Holding there: another spot, off the bumper's way, or none.
    a.peers[2].target = Some(spot);
    let d = a.retreat_decision();
    assert_ne!(a.retreat.map(|r| r.spot), Some(spot));
    assert_eq!(d.is_some(), a.retreat.is_some());
    if let Some(r) = a.retreat {
        assert_ne!(r.spot, Pos::new(0, 0));
        assert_ne!(r.spot, Pos::new(0, 1));
    }
}
