use super::*;
use crate::geometry::{Arms, Pos};
use crate::map::blocks_for;
use crate::path::tests::{random_arms, tree_arms};
use crate::path::{DistField, Flow};
use crate::team::RobotId;
use proptest::prelude::*;
use std::vec;
use std::vec::Vec;

/// A map of the nodes `order` names, visited in that order with their
/// true `arms`, the forest brought up to it after every visit (as an
/// agent does) or, `at_end`, once built from scratch.
fn grown(
    bounds: Bounds,
    arms: &[Arms],
    order: &[usize],
    at_end: bool,
) -> (KnownMap<Vec<Block>>, Forest<Vec<PlanCell>>) {
    let mut map = KnownMap::new(vec![Block::EMPTY; blocks_for(bounds.area())], bounds).unwrap();
    let mut forest = Forest::new(vec![PlanCell::EMPTY; bounds.area()]);
    for &i in order {
        map.visit(bounds.pos(i), arms[i], RobotId(0)).unwrap();
        if !at_end {
            forest.sync(&map);
        }
    }
    forest.sync(&map);
    (map, forest)
}

/// Some nodes of the window in a scrambled order (not connected as they
/// come: trees are joined as they meet).
fn scrambled(area: usize, seed: u64, frac: f64) -> Vec<usize> {
    let mut s = seed | 1;
    let mut order: Vec<usize> = (0..area).collect();
    for i in (1..area).rev() {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        order.swap(i, (s % (i as u64 + 1)) as usize);
    }
    order.truncate(((area as f64) * frac) as usize + 1);
    order
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// On a maze (a tree) known in any order, the forest's time from any
    /// known pose to every node equals a search's: frontier nodes,
    /// passable nodes, and nodes out of reach (in another known tree, or
    /// unknown) alike, grown visit by visit or built at once.
    #[test]
    fn forest_travel_agrees_with_a_search_on_mazes(
        w in 1u16..32, h in 1u16..32, seed in any::<u64>(), frac in 0.0f64..1.0,
        edge in 1u32..200, turn in 1u32..128, at_end in any::<bool>(), pick in any::<usize>(),
        h0 in 0u8..4,
    ) {
        let b = Bounds::new(Pos::new(0, 0), w, h);
        let area = b.area();
        let arms = tree_arms(b, seed);
        let order = scrambled(area, seed.rotate_left(17), frac);
        let (map, forest) = grown(b, &arms, &order, at_end);
        prop_assert!(forest.holds(&map));
        let t = Timing { edge, quarter_turn: turn };
        let s0 = order[pick % order.len()];
        let hd = Heading::from_index(h0);
        let mut field = DistField::new(vec![PlanCell::EMPTY; super::super::min_cells(area)]);
        field.compute(&map, t, b.pos(s0), hd, |_, _| Flow::Continue).unwrap();
        for i in 0..area {
            let want = field.dist_at(i);
            let got = forest.travel(&map, t, (s0, hd), i);
            prop_assert_eq!(got, want, "node {} from {} facing {:?}", i, s0, hd);
        }
    }

    /// On a maze known in any order, the forest's first heading from any
    /// known pose to every frontier node is a search's
    /// (`DistField::first_heading`): on a tree there is one way, so the
    /// forest always tells, for nodes out of reach too (`None`). On a
    /// field with loops, while what is known is still a forest, a
    /// frontier node may be entered from two nodes of one tree: the
    /// forest then tells the cheaper way's heading, or nothing on a tie.
    #[test]
    fn forest_first_heading_agrees_with_a_search(
        w in 1u16..32, h in 1u16..32, seed in any::<u64>(), frac in 0.0f64..1.0,
        edge in 1u32..200, turn in 1u32..128, at_end in any::<bool>(), pick in any::<usize>(),
        h0 in 0u8..4, maze in any::<bool>(),
    ) {
        let b = Bounds::new(Pos::new(0, 0), w, h);
        let area = b.area();
        let arms = if maze { tree_arms(b, seed) } else { random_arms(b, seed) };
        // Few nodes known on a field with loops, or they would close one.
        let frac = if maze { frac } else { frac / 4.0 };
        let order = scrambled(area, seed.rotate_left(17), frac);
        let (map, forest) = grown(b, &arms, &order, at_end);
        if !forest.holds(&map) {
            return Ok(());
        }
        let t = Timing { edge, quarter_turn: turn };
        let s0 = order[pick % order.len()];
        let hd = Heading::from_index(h0);
        let mut field = DistField::new(vec![PlanCell::EMPTY; super::super::min_cells(area)]);
        field.compute(&map, t, b.pos(s0), hd, |_, _| Flow::Continue).unwrap();
        for i in (0..area).filter(|&i| map.is_frontier_at(i)) {
            let want = field.first_heading(&map, i);
            let got = forest.first_heading(&map, t, (s0, hd), i);
            if maze || got.is_some() {
                prop_assert_eq!(got, want, "node {} from {} facing {:?}", i, s0, hd);
            }
        }
    }

    /// A known graph with a loop is no forest: the forest answers nothing.
    #[test]
    fn a_loop_makes_the_forest_answer_nothing(
        w in 2u16..10, h in 2u16..10, seed in any::<u64>(),
    ) {
        let b = Bounds::new(Pos::new(0, 0), w, h);
        let area = b.area();
        let arms = random_arms(b, seed);
        let order: Vec<usize> = (0..area).collect();
        let (map, forest) = grown(b, &arms, &order, false);
        let edges: usize = arms.iter().map(|a| a.count() as usize).sum::<usize>() / 2;
        // Components of the whole graph, by a flood fill.
        let mut seen = vec![false; area];
        let mut parts = 0;
        for s in 0..area {
            if seen[s] {
                continue;
            }
            parts += 1;
            let mut stack = vec![s];
            seen[s] = true;
            while let Some(i) = stack.pop() {
                for hd in arms[i].iter() {
                    if let Some(j) = neighbour_index(b, i, hd) {
                        if !seen[j] {
                            seen[j] = true;
                            stack.push(j);
                        }
                    }
                }
            }
        }
        let looped = edges + parts > area;
        prop_assert_eq!(forest.holds(&map), !looped);
        if looped {
            prop_assert_eq!(forest.travel(&map, Timing::DEFAULT, (0, Heading::North), area - 1), None);
        }
    }
}

#[test]
fn a_stale_forest_answers_nothing_until_synced() {
    let b = Bounds::new(Pos::new(0, 0), 6, 6);
    let arms = tree_arms(b, 7);
    let order: Vec<usize> = (0..20).collect();
    let (mut map, mut forest) = grown(b, &arms, &order, false);
    assert!(forest.holds(&map));
    map.visit(b.pos(30), arms[30], RobotId(0)).unwrap();
    assert!(!forest.holds(&map));
    assert_eq!(
        forest.travel(&map, Timing::DEFAULT, (0, Heading::North), 1),
        None
    );
    forest.sync(&map);
    assert!(forest.holds(&map));
}
