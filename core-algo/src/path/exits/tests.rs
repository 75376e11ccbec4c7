use super::super::tests::{known_prefix, random_arms, tree_arms};
use super::super::*;
use proptest::prelude::*;
use std::vec;
use std::vec::Vec;

fn field_for(area: usize) -> DistField<Vec<PlanCell>> {
    DistField::new(vec![PlanCell::EMPTY; min_cells(area)])
}

/// Every visited pose's time to the goal through its exits, as the
/// search `f` proves it (`None`: not proven), at its bound.
pub(crate) fn exit_times(
    f: &DistField<Vec<PlanCell>>,
    map: &KnownMap<Vec<Block>>,
    t: Timing,
) -> Vec<Option<Ticks>> {
    let at = f.reverse_settled_to().unwrap_or(0);
    (0..map.bounds().area())
        .flat_map(|v| {
            Heading::ALL.map(|h| {
                arms_at(map, v)?;
                CorridorExits::of(map, t, v, h).time_in(f, at)
            })
        })
        .collect()
}

/// A plain reverse field's time for every visited pose.
pub(crate) fn pose_times(
    f: &DistField<Vec<PlanCell>>,
    map: &KnownMap<Vec<Block>>,
) -> Vec<Option<Ticks>> {
    (0..map.bounds().area())
        .flat_map(|v| {
            Heading::ALL.map(|h| {
                arms_at(map, v)?;
                f.dist_pose_at(v, h)
            })
        })
        .collect()
}

/// `got` (a jumping search's exit times at bound `at`) against `want` (a
/// plain field's): every time proven is right, and every pose cheaper
/// than the bound is proven.
pub(crate) fn proves_all_below(
    got: &[Option<Ticks>],
    want: &[Option<Ticks>],
    at: Ticks,
) -> Result<(), TestCaseError> {
    for (s, (g, w)) in got.iter().zip(want).enumerate() {
        match (g, w) {
            (Some(_), _) => prop_assert_eq!(g, w, "pose {}", s),
            (None, Some(x)) => prop_assert!(*x >= at, "pose {} at {} not proven by {}", s, x, at),
            (None, None) => {}
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2048))]

    /// A jumping reverse search, stopped anywhere, proves through the
    /// exits every pose's time a plain reverse search gives, up to where
    /// it has settled; resumed to the end, every pose's. On mazes (mostly
    /// corridors) and random fields, with any timing, and with its jump
    /// heap nearly full (drives into corridors go in plain).
    #[test]
    fn a_jumping_reverse_search_proves_every_pose_through_its_exits(
        w in 1u16..12, h in 1u16..12, seed in any::<u64>(), frac in 0.0f64..1.0,
        edge in 1u32..200, turn in 1u32..128, maze in any::<bool>(), pick in any::<usize>(),
        first in 0usize..200, full in any::<bool>(),
    ) {
        let b = Bounds::new(Pos::new(0, 0), w, h);
        let area = b.area();
        let arms = if maze { tree_arms(b, seed) } else { random_arms(b, seed) };
        let known = (area as f64 * frac) as usize + 1;
        let map = known_prefix(b, &arms, known);
        let frontier: Vec<Pos> = map.frontier().collect();
        if frontier.is_empty() {
            return Ok(());
        }
        let goal = frontier[pick % frontier.len()];
        let t = Timing { edge, quarter_turn: turn };
        let mut plain = field_for(area);
        plain.compute_reverse(&map, t, goal, |_, _, _| Flow::Continue).unwrap();
        let want = pose_times(&plain, &map);
        let mut f = field_for(area);
        let mut n = 0;
        let mut last = 0;
        f.compute_reverse_jumping(&map, t, goal, |_, _, key| {
            assert!(key >= last, "{} after {}", key, last);
            last = key;
            n += 1;
            if n > first { Flow::Stop } else { Flow::Continue }
        }).unwrap();
        if full {
            let junk = (f.cells.len() + 1) * 4;
            while f.jumps.len() + 1 < JUMP_SLOTS {
                f.jumps.push((junk / 4, 0, MAX_DIST));
            }
        }
        let at = f.reverse_settled_to().unwrap();
        proves_all_below(&exit_times(&f, &map, t), &want, at)?;
        f.resume_reverse(&map, |_, _, key| {
            assert!(key >= last, "{} after {}", key, last);
            last = key;
            Flow::Continue
        }).unwrap();
        if !full {
            prop_assert_eq!(f.reverse_settled_to(), Some(Ticks::MAX));
        }
        // With junk left in the heap the bound stays; every real state is
        // settled all the same.
        let got: Vec<Option<Ticks>> = (0..area)
            .flat_map(|v| Heading::ALL.map(|h| {
                arms_at(&map, v)?;
                CorridorExits::of(&map, t, v, h).time_in(&f, Ticks::MAX)
            }))
            .collect();
        prop_assert_eq!(got, want);
        // It is never taken for a whole reverse field.
        prop_assert!(!f.is_reverse_to(&map, t, goal));
    }
}

/// A robot in a corridor leaves it at both ends, the far one after a
/// U-turn; on a junction it is its own exit.
#[test]
fn a_corridor_robot_leaves_at_both_ends() {
    use crate::geometry::Arms;
    use crate::map::blocks_for;
    use crate::team::RobotId;
    // A row of four nodes: a dead end, two corridor nodes, a dead end.
    let b = Bounds::new(Pos::new(0, 0), 4, 1);
    let mut map = KnownMap::new(vec![Block::EMPTY; blocks_for(b.area())], b).unwrap();
    let (e, w) = (Heading::East, Heading::West);
    let ew = Arms::NONE.with(e).with(w);
    for (x, a) in [
        (0, Arms::NONE.with(e)),
        (1, ew),
        (2, ew),
        (3, Arms::NONE.with(w)),
    ] {
        map.visit(Pos::new(x, 0), a, RobotId(0)).unwrap();
    }
    let t = Timing {
        edge: 10,
        quarter_turn: 3,
    };
    let exits: Vec<_> = CorridorExits::of(&map, t, 1, e).iter().collect();
    assert_eq!(exits, [(3, e, 20), (0, w, 6 + 10)]);
    let own: Vec<_> = CorridorExits::of(&map, t, 0, Heading::North)
        .iter()
        .collect();
    assert_eq!(own, [(0, Heading::North, 0)]);
}

/// Back from the frontier node at the end of a long corridor, a jumping
/// search settles the goal, the node beside it (entered from the goal's
/// own edge) and the dead end at the far end, and nothing between; a
/// plain one settles every state.
#[test]
fn a_jumping_reverse_search_settles_no_corridor_state() {
    use crate::geometry::Arms;
    use crate::map::blocks_for;
    use crate::team::RobotId;
    let b = Bounds::new(Pos::new(0, 0), 12, 1);
    let mut map = KnownMap::new(vec![Block::EMPTY; blocks_for(b.area())], b).unwrap();
    let (e, w) = (Heading::East, Heading::West);
    map.visit(Pos::new(0, 0), Arms::NONE.with(e), RobotId(0))
        .unwrap();
    for x in 1..11 {
        map.visit(Pos::new(x, 0), Arms::NONE.with(e).with(w), RobotId(0))
            .unwrap();
    }
    let t = Timing::DEFAULT;
    let goal = Pos::new(11, 0);
    let count = |jumping: bool| {
        let mut f = field_for(b.area());
        let mut n = 0;
        let r = |_, _, _| {
            n += 1;
            Flow::Continue
        };
        if jumping {
            f.compute_reverse_jumping(&map, t, goal, r).unwrap();
        } else {
            f.compute_reverse(&map, t, goal, r).unwrap();
        }
        (n, f)
    };
    let (plain, pf) = count(false);
    let (jumping, jf) = count(true);
    assert_eq!(plain, 12 * 4);
    assert_eq!(jumping, 3 * 4);
    // A robot at the far dead end, facing the goal: the same time.
    let want = pf.dist_pose(Pos::new(0, 0), e);
    assert_eq!(jf.dist_pose(Pos::new(0, 0), e), want);
    let mid = CorridorExits::of(&map, t, 5, w).time_in(&jf, Ticks::MAX);
    assert_eq!(mid, pf.dist_pose(Pos::new(5, 0), w));
}
