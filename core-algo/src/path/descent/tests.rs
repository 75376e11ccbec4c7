use super::super::tests::{bfs_order, known_prefix, random_arms, tree_arms};
use super::super::*;
use proptest::prelude::*;
use std::vec;
use std::vec::Vec;

fn field_for(area: usize) -> DistField<Vec<PlanCell>> {
    DistField::new(vec![PlanCell::EMPTY; min_cells(area)])
}

/// The nodes of the only way from `from` to `to` in a tree, `to` last and
/// `from` left out.
fn tree_way(b: Bounds, arms: &[Arms], from: usize, to: usize) -> Vec<usize> {
    let mut parent = vec![usize::MAX; b.area()];
    let mut queue = std::collections::VecDeque::from([to]);
    parent[to] = to;
    while let Some(i) = queue.pop_front() {
        for hd in arms[i].iter() {
            if let Some(j) = neighbour_index(b, i, hd) {
                if parent[j] == usize::MAX {
                    parent[j] = i;
                    queue.push_back(j);
                }
            }
        }
    }
    let mut way = Vec::new();
    let mut v = from;
    while v != to {
        v = parent[v];
        way.push(v);
    }
    way
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// In a perfect maze the two walks answer exactly for the only way
    /// between the two nodes, whatever the headings and the timing; on
    /// any map they answer, and with no nodes to look for, say none;
    /// with the first way marked they answer alike.
    #[test]
    fn meeting_descents_answer_for_the_way_between(
        w in 1u16..10, h in 1u16..10, seed in any::<u64>(), tree in any::<bool>(),
        (goal, from, to) in (any::<usize>(), any::<usize>(), any::<usize>()),
        (ha, hb) in (0u8..4, 0u8..4), picks in proptest::collection::vec(any::<usize>(), 0..4),
        edge in 1u32..200, turn in 1u32..128,
    ) {
        let b = Bounds::new(Pos::new(0, 0), w, h);
        let area = b.area();
        let arms = if tree { tree_arms(b, seed) } else { random_arms(b, seed) };
        let map = known_prefix(b, &arms, area);
        let reachable = bfs_order(b, &arms);
        let n = reachable.len();
        let (g, va, vb) = (reachable[goal % n], reachable[from % n], reachable[to % n]);
        let t = Timing { edge, quarter_turn: turn };
        let mut r = field_for(area);
        r.compute_reverse(&map, t, b.pos(g), |_, _, _| Flow::Continue).unwrap();
        let (a, bp) = ((va, Heading::from_index(ha)), (vb, Heading::from_index(hb)));
        let vias: Vec<usize> = picks.iter().map(|p| reachable[p % n]).collect();
        let got = r.descents_meet_passing(&map, a, bp, &vias);
        prop_assert!(got.is_some());
        prop_assert_eq!(r.descents_meet_passing(&map, a, bp, &[]), Some(false));
        // With `a`'s way marked, only `b`'s is walked (where an edge costs
        // more than a U-turn), and the answer is the same on any map, for
        // these nodes and for each node alone.
        let each: Vec<_> = reachable
            .iter()
            .map(|&x| r.descents_meet_passing(&map, a, bp, &[x]))
            .collect();
        prop_assert!(r.mark_descent(&map, va, Heading::from_index(ha)));
        prop_assert_eq!(r.descents_meet_passing(&map, a, bp, &vias), got);
        prop_assert_eq!(r.descents_meet_passing(&map, a, bp, &[]), Some(false));
        for (&x, &want) in reachable.iter().zip(&each) {
            prop_assert_eq!(r.descents_meet_passing(&map, a, bp, &[x]), want, "node {}", x);
        }
        if tree {
            let way = tree_way(b, &arms, va, vb);
            let want = vias.contains(&vb) || way.iter().any(|v| vias.contains(v));
            prop_assert_eq!(got, Some(want), "way {:?} vias {:?}", way, vias);
        }
    }
}
