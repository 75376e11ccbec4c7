use super::super::exits::tests::{exit_times, pose_times, proves_all_below};
use super::super::tests::{bfs_order, random_arms, tree_arms};
use super::super::*;
use crate::geometry::Arms;
use crate::map::blocks_for;
use crate::team::RobotId;
use proptest::prelude::*;
use std::vec;
use std::vec::Vec;

fn field_for(area: usize) -> DistField<Vec<PlanCell>> {
    DistField::new(vec![PlanCell::EMPTY; min_cells(area)])
}

/// Every state's time to the goal (`None`: not settled).
fn states(f: &DistField<Vec<PlanCell>>, b: Bounds) -> Vec<Option<Ticks>> {
    (0..b.area())
        .flat_map(|i| Heading::ALL.map(|h| f.dist_pose(b.pos(i), h)))
        .collect()
}

/// A map of `b` with its first `known` nodes (in BFS order) visited, and
/// a reverse search to one of its frontier nodes (`pick`) stopped after
/// `first` states; also the true arms and the visiting order. `None`
/// without a frontier node.
#[allow(clippy::type_complexity)]
fn stopped_search(
    b: Bounds,
    (seed, tree, jumping): (u64, bool, bool),
    known: usize,
    pick: usize,
    first: usize,
) -> Option<(
    Vec<Arms>,
    Vec<usize>,
    KnownMap<Vec<Block>>,
    Pos,
    DistField<Vec<PlanCell>>,
)> {
    let arms = if tree {
        tree_arms(b, seed)
    } else {
        random_arms(b, seed)
    };
    let order = bfs_order(b, &arms);
    let mut map = KnownMap::new(vec![Block::EMPTY; blocks_for(b.area())], b).unwrap();
    for &i in order.iter().take(known) {
        map.visit(b.pos(i), arms[i], RobotId(0)).unwrap();
    }
    let frontier: Vec<Pos> = map.frontier().collect();
    let goal = *frontier.get(pick % frontier.len().max(1))?;
    let mut kept = field_for(b.area());
    if jumping {
        kept.compute_reverse_jumping(&map, Timing::DEFAULT, goal, stop_after(first))
    } else {
        kept.compute_reverse(&map, Timing::DEFAULT, goal, stop_after(first))
    }
    .unwrap();
    Some((arms, order, map, goal, kept))
}

/// A search callback that lets `limit` states settle, then stops.
fn stop_after(limit: usize) -> impl FnMut(usize, Heading, Ticks) -> Flow {
    let mut n = 0;
    move |_, _, _| {
        n += 1;
        if n > limit {
            Flow::Stop
        } else {
            Flow::Continue
        }
    }
}

/// `kept`, carried over to `map`, against `want`, a fresh search's states:
/// what is settled holds already and what is not costs at least the
/// search's bound; resumed for `second` states and then to the end, it
/// still holds, and at the end it is the fresh search.
fn agrees_on(
    kept: &mut DistField<Vec<PlanCell>>,
    map: &KnownMap<Vec<Block>>,
    fresh: &DistField<Vec<PlanCell>>,
    second: usize,
) -> Result<(), TestCaseError> {
    if kept.jumping {
        return jumping_agrees_on(kept, map, &pose_times(fresh, map), second);
    }
    let want = &states(fresh, map.bounds());
    let b = map.bounds();
    let bound = kept.reverse_settled_to().unwrap();
    for (s, (got, want)) in states(kept, b).iter().zip(want).enumerate() {
        match got {
            Some(_) => prop_assert_eq!(got, want, "state {} settled wrong", s),
            None => prop_assert!(
                want.is_none_or(|x| x >= bound),
                "state {} below {}",
                s,
                bound
            ),
        }
    }
    kept.resume_reverse(map, stop_after(second)).unwrap();
    for (got, want) in states(kept, b).iter().zip(want) {
        if got.is_some() {
            prop_assert_eq!(got, want);
        }
    }
    kept.resume_reverse(map, |_, _, _| Flow::Continue).unwrap();
    prop_assert_eq!(&states(kept, b), want);
    Ok(())
}

/// [`agrees_on`] for a jumping search, which settles no corridor state:
/// every pose's time as its exits prove it, against `want`, a fresh plain
/// search's.
fn jumping_agrees_on(
    kept: &mut DistField<Vec<PlanCell>>,
    map: &KnownMap<Vec<Block>>,
    want: &[Option<Ticks>],
    second: usize,
) -> Result<(), TestCaseError> {
    let t = Timing::DEFAULT;
    let bound = kept.reverse_settled_to().unwrap();
    proves_all_below(&exit_times(kept, map, t), want, bound)?;
    kept.resume_reverse(map, stop_after(second)).unwrap();
    let bound = kept.reverse_settled_to().unwrap();
    proves_all_below(&exit_times(kept, map, t), want, bound)?;
    kept.resume_reverse(map, |_, _, _| Flow::Continue).unwrap();
    prop_assert_eq!(kept.reverse_settled_to(), Some(Ticks::MAX));
    prop_assert_eq!(exit_times(kept, map, t), want);
    Ok(())
}

proptest! {
    // 16 384 cases (a fraction of a second): with the check for unsettled
    // states beside a loop left out, 1 024 rarely failed; this many fail
    // in two runs of three, besides the saved cases.
    #![proptest_config(ProptestConfig::with_cases(16384))]

    /// A reverse search stopped anywhere, carried over to a map grown by a
    /// few visits and resumed, settles every state at the time a fresh
    /// search of the grown map gives it: where it stops again, and once it
    /// has run to the end. Where it refuses, nothing is claimed.
    #[test]
    fn a_refreshed_reverse_search_agrees_with_a_fresh_one(
        w in 2u16..10, h in 2u16..10, seed in any::<u64>(), tree in any::<bool>(),
        known in 1usize..80, more in 1usize..6, pick in any::<usize>(),
        first in 0usize..300, second in 0usize..300, jumping in any::<bool>(),
    ) {
        let b = Bounds::new(Pos::new(0, 0), w, h);
        refreshed_agrees(b, (seed, tree, jumping), known, more, pick, (first, second))?;
    }
}

/// The case of [`a_refreshed_reverse_search_agrees_with_a_fresh_one`]:
/// `more` visits after a search stopped after `first` states; whether the
/// search was kept.
fn refreshed_agrees(
    b: Bounds,
    arms_seed: (u64, bool, bool),
    known: usize,
    more: usize,
    pick: usize,
    (first, second): (usize, usize),
) -> Result<bool, TestCaseError> {
    let Some((arms, order, mut map, goal, mut kept)) =
        stopped_search(b, arms_seed, known, pick, first)
    else {
        return Ok(false);
    };
    let t = Timing::DEFAULT;
    for &i in order.iter().skip(known).take(more) {
        map.visit(b.pos(i), arms[i], RobotId(0)).unwrap();
    }
    let mut fresh = field_for(b.area());
    fresh
        .compute_reverse(&map, t, goal, |_, _, _| Flow::Continue)
        .unwrap();
    if !kept.refresh_reverse(&map, t) {
        return Ok(false);
    }
    prop_assert!(map.is_frontier_at(b.index(goal).unwrap()));
    agrees_on(&mut kept, &map, &fresh, second)?;
    Ok(true)
}

/// A loop closed beside a state the stopped search has not settled: a
/// robot there, facing the new node, could drive through it more cheaply
/// than the search would find without expanding it. Found by the property
/// test above with that check left out (1 case in about 100 000).
#[test]
fn a_loop_beside_an_unsettled_state_is_refused() {
    let b = Bounds::new(Pos::new(0, 0), 6, 9);
    let case = (10_064_411_082_706_577_908, false, false);
    let kept = refreshed_agrees(b, case, 35, 2, 4_020_568_598_058_815_244, (89, 0));
    assert!(!kept.unwrap());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1024))]

    /// A reverse search to a frontier node `u`, stopped anywhere, carried
    /// over to a node `x` beyond `u` once `u` is visited (and a few more
    /// nodes), settles every state at the time a fresh search to `x` gives
    /// it, where it stops again and once it has run to the end. Where it
    /// refuses, nothing is claimed.
    #[test]
    fn a_rebased_reverse_search_agrees_with_a_fresh_one(
        w in 2u16..10, h in 2u16..10, seed in any::<u64>(), tree in any::<bool>(),
        known in 1usize..80, more in 0usize..4, pick in any::<usize>(), child in any::<usize>(),
        first in 0usize..300, second in 0usize..300, jumping in any::<bool>(),
    ) {
        let b = Bounds::new(Pos::new(0, 0), w, h);
        let Some((arms, order, mut map, u, mut kept)) =
            stopped_search(b, (seed, tree, jumping), known, pick, first) else {
            return Ok(());
        };
        let t = Timing::DEFAULT;
        let ui = b.index(u).unwrap();
        map.visit(u, arms[ui], RobotId(0)).unwrap();
        for &i in order.iter().skip(known).filter(|&&i| i != ui).take(more) {
            map.visit(b.pos(i), arms[i], RobotId(0)).unwrap();
        }
        let beyond: Vec<usize> = map
            .frontier()
            .filter_map(|p| b.index(p))
            .filter(|&i| way_in(&map, i).is_some_and(|(v, _)| v == ui))
            .collect();
        if beyond.is_empty() {
            return Ok(());
        }
        let x = beyond[child % beyond.len()];
        let mut fresh = field_for(b.area());
        fresh.compute_reverse(&map, t, b.pos(x), |_, _, _| Flow::Continue).unwrap();
        let before = kept.reverse_settled_to();
        if !kept.rebase_reverse(&map, t, x) {
            // Untouched (still the search to `u`), or spent.
            prop_assert!(kept.reverse_goal().is_none_or(|g| g == ui));
            return Ok(());
        }
        prop_assert_eq!(kept.reverse_goal(), Some(x));
        prop_assert!(kept.refresh_reverse(&map, t));
        // The bound moves on with the times (at least an edge), if the
        // search had stopped part way.
        let bound = kept.reverse_settled_to().unwrap();
        if let Some(b0) = before.filter(|&b0| b0 > 0 && b0 < Ticks::MAX) {
            prop_assert!(bound >= b0 + t.edge, "bound {} after {}", bound, b0);
        }
        agrees_on(&mut kept, &map, &fresh, second)?;
        // What the rebased search touched, the next search clears.
        kept.compute_reverse(&map, t, b.pos(x), |_, _, _| Flow::Continue).unwrap();
        prop_assert_eq!(states(&kept, b), states(&fresh, b));
    }
}

/// A corridor grown at its far end keeps the search, and so does a visit
/// that closes a loop through which no way gets shorter; a loop that is a
/// shortcut refuses it.
#[test]
fn a_dead_end_or_a_loop_that_shortens_nothing_keeps_the_search() {
    let b = Bounds::new(Pos::new(0, 0), 4, 2);
    let map_with = |visits: &[(Pos, Arms)]| {
        let mut map = KnownMap::new(vec![Block::EMPTY; blocks_for(b.area())], b).unwrap();
        for &(p, a) in visits {
            map.visit(p, a, RobotId(0)).unwrap();
        }
        map
    };
    let (n, e, s, w) = (Heading::North, Heading::East, Heading::South, Heading::West);
    let arms = |hs: &[Heading]| hs.iter().fold(Arms::NONE, |a, &h| a.with(h));
    let t = Timing::DEFAULT;
    let fresh_states = |map: &KnownMap<Vec<Block>>, goal: Pos| {
        let mut fresh = field_for(b.area());
        fresh
            .compute_reverse(map, t, goal, |_, _, _| Flow::Continue)
            .unwrap();
        states(&fresh, b)
    };
    // The bottom row (0,0)-(1,0)-(2,0), the goal (3,0) to the east, and
    // (1,1) and (2,1) above the middle frontier too.
    let goal = Pos::new(3, 0);
    let mut map = map_with(&[
        (Pos::new(0, 0), arms(&[e])),
        (Pos::new(1, 0), arms(&[e, w, n])),
        (Pos::new(2, 0), arms(&[e, w, n])),
    ]);
    let mut f = field_for(b.area());
    f.compute_reverse(&map, t, goal, |_, _, _| Flow::Continue)
        .unwrap();
    // Visiting `p` keeps the search, which resumed agrees with a fresh one.
    let mut keeps = |p: Pos, a: Arms| {
        map.visit(p, a, RobotId(0)).unwrap();
        assert!(f.refresh_reverse(&map, t));
        f.resume_reverse(&map, |_, _, _| Flow::Continue).unwrap();
        assert_eq!(states(&f, b), fresh_states(&map, goal));
        assert!(f.dist(p).is_some());
    };
    // (1,1) turns out a dead end: its arm east leads to the frontier (2,1).
    keeps(Pos::new(1, 1), arms(&[s, e]));
    // (2,1) joins (1,1) to (2,0): a loop, but from (1,1) facing east the
    // way through it (three edges, two quarter turns) is no shorter than
    // the way down and along.
    keeps(Pos::new(2, 1), arms(&[w, s]));

    // A shortcut: the goal (0,1) is three edges and a turn from (2,1)
    // round the bottom row, and two straight ones through (1,1), the node
    // that closes the loop.
    let mut map = map_with(&[
        (Pos::new(0, 0), arms(&[e, n])),
        (Pos::new(1, 0), arms(&[e, w])),
        (Pos::new(2, 0), arms(&[w, n])),
        (Pos::new(2, 1), arms(&[s, w])),
    ]);
    let mut f = field_for(b.area());
    f.compute_reverse(&map, t, Pos::new(0, 1), |_, _, _| Flow::Continue)
        .unwrap();
    map.visit(Pos::new(1, 1), arms(&[e, w]), RobotId(0))
        .unwrap();
    assert!(!f.refresh_reverse(&map, t));
}
