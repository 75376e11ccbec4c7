use super::sample::random_field;
use super::*;
use crate::bench::{STRATEGIES, bound::lower_bounds, strategy};
use proptest::prelude::*;

#[test]
fn every_strategy_explores_a_small_field_and_comes_home() {
    let (truth, starts) = random_field(8, 8, 7, 20, 3);
    for name in STRATEGIES {
        for k in 1..=3 {
            let mut s = strategy(name).unwrap();
            let st = run(&truth, &starts[..k], s.as_mut(), WorldConfig::default()).unwrap();
            assert!(st.complete, "{name} k={k}: {st:?}");
        }
    }
}

#[test]
fn unreachable_frontier_sends_robots_home() {
    // A map whose only frontier cannot be reached: a relayed report of a
    // far node. The robot must go home instead of stalling.
    use core_algo::explore::{Context, Goal, NearestFrontier, RobotView, Strategy};
    use core_algo::geometry::Arms;
    let bounds = core_algo::map::Bounds::new(Pos::new(0, 0), 6, 1);
    let mut map = KnownMap::new(vec![Block::EMPTY; 1], bounds).unwrap();
    let ew = Arms::NONE.with(Heading::East).with(Heading::West);
    map.visit(Pos::new(0, 0), Arms::NONE.with(Heading::East), RobotId(0))
        .unwrap();
    map.visit(Pos::new(1, 0), Arms::NONE.with(Heading::West), RobotId(0))
        .unwrap();
    // Node (4, 0) is known with an arm into (5, 0), but (2, 0) and (3, 0)
    // are unknown and (1, 0) has no arm east: (5, 0) is unreachable.
    map.visit(Pos::new(4, 0), ew, RobotId(1)).unwrap();
    assert!(map.is_frontier(Pos::new(5, 0)));
    let robots = [RobotView {
        pos: Pos::new(1, 0),
        heading: Heading::East,
        eta: 0,
        home: Pos::new(0, 0),
        target: None,
    }];
    let ctx = Context {
        map: &map,
        timing: Timing::DEFAULT,
        robots: &robots,
        me: 0,
        tree: None,
    };
    let mut fields = vec![DistField::new(vec![PlanCell::EMPTY; 64])];
    let d = NearestFrontier.decide(&ctx, &mut fields).unwrap();
    assert_eq!(d.goal, Goal::Home);
    assert_eq!(d.next, Some(Heading::West));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn all_complete_and_the_bound_holds(
        w in 2u16..9, h in 2u16..9, seed in any::<u64>(), extra in 0u32..60, k in 1usize..5,
    ) {
        let (truth, starts) = random_field(w, h, seed, extra, k);
        let k = starts.len();
        let homes: Vec<Pos> = starts.iter().map(|s| s.0).collect();
        let lb = lower_bounds(&truth, &homes, k);
        prop_assert!(lb.explore <= lb.with_return);
        prop_assert!(lb.explore <= lb.all_nodes_explore);
        for name in STRATEGIES {
            let mut s = strategy(name).unwrap();
            let st = run(&truth, &starts, s.as_mut(), WorldConfig::default()).unwrap();
            prop_assert!(st.complete, "{} incomplete: {:?}", name, st);
            prop_assert!(u64::from(st.max_edges()) >= lb.with_return, "{}: {} < {}", name, st.max_edges(), lb.with_return);
            prop_assert!(u64::from(st.makespan) >= lb.with_return * u64::from(Timing::DEFAULT.edge));
            // Identical inputs give identical runs.
            let mut s2 = strategy(name).unwrap();
            let again = run(&truth, &starts, s2.as_mut(), WorldConfig::default()).unwrap();
            prop_assert_eq!(&st, &again);
        }
    }
}
