use super::*;
use crate::geometry::{Heading, Pos};
use crate::map::{Block, Bounds, blocks_for};
use crate::path::tests::{bfs_order, random_arms};
use crate::path::{Flow, min_cells, node_mark};
use crate::team::RobotId;
use crate::timing::Timing;
use proptest::prelude::*;
use std::vec;
use std::vec::Vec;

fn field(area: usize) -> DistField<Vec<PlanCell>> {
    DistField::new(vec![PlanCell::EMPTY; min_cells(area)])
}

/// The known map of the nodes `order` names, visited in that order.
fn visited(
    bounds: Bounds,
    arms: &[crate::geometry::Arms],
    order: &[usize],
) -> KnownMap<Vec<Block>> {
    let mut map = KnownMap::new(vec![Block::EMPTY; blocks_for(bounds.area())], bounds).unwrap();
    for &i in order {
        map.visit(bounds.pos(i), arms[i], RobotId(0)).unwrap();
    }
    map
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// A whole reverse field copied over a map that reads the same, but
    /// was learnt in another order (another revision), is the field a
    /// search over that map leaves: every state's time, every way out, and
    /// it counts as that map's reverse field. The copy clears what the
    /// field held before; a forward field, a marked one or one of another
    /// window is refused.
    #[test]
    fn a_copied_reverse_field_is_the_one_searched_over_the_map(
        w in 1u16..12, h in 1u16..12, seed in any::<u64>(), frac in 0.0f64..1.0,
        goal in any::<usize>(), edge in 1u32..200, turn in 1u32..128,
    ) {
        let bounds = Bounds::new(Pos::new(0, 0), w, h);
        let area = bounds.area();
        let arms = random_arms(bounds, seed);
        let order: Vec<usize> = bfs_order(bounds, &arms)
            .into_iter()
            .take((area as f64 * frac) as usize + 1)
            .collect();
        let a = visited(bounds, &arms, &order);
        // The same nodes learnt backwards, after a map that was forgotten:
        // the same marks, another revision.
        let mut b = visited(bounds, &arms, &order);
        b.clear();
        for &i in order.iter().rev() {
            b.visit(bounds.pos(i), arms[i], RobotId(1)).unwrap();
        }
        prop_assert!((0..area).all(|i| node_mark(&a, i) == node_mark(&b, i)));
        prop_assert_ne!(a.revision(), b.revision());
        let t = Timing { edge, quarter_turn: turn };
        let g = bounds.pos(order[goal % order.len()]);
        let mut from = field(area);
        from.compute_reverse(&a, t, g, |_, _, _| Flow::Continue).unwrap();
        // The copy first holds something else: a forward field over `b`.
        let mut copy = field(area);
        copy.compute(&b, t, bounds.pos(order[0]), Heading::East, |_, _| Flow::Continue).unwrap();
        prop_assert!(copy.copy_reverse_from(&from, &b));
        let mut fresh = field(area);
        fresh.compute_reverse(&b, t, g, |_, _, _| Flow::Continue).unwrap();
        prop_assert!(copy.is_reverse_to(&b, t, g));
        for v in 0..area {
            for hd in Heading::ALL {
                prop_assert_eq!(copy.dist_pose_at(v, hd), fresh.dist_pose_at(v, hd));
                prop_assert_eq!(copy.way_out(&b, v, hd), fresh.way_out(&b, v, hd));
            }
        }
        // Refused: a forward field, a marked one, another window.
        let mut other = field(area);
        let mut forward = field(area);
        forward.compute(&a, t, g, Heading::North, |_, _| Flow::Continue).unwrap();
        prop_assert!(!other.copy_reverse_from(&forward, &b));
        let mut marked = field(area);
        marked.compute_reverse(&a, t, g, |_, _, _| Flow::Continue).unwrap();
        let at = order[order.len() - 1];
        if marked.mark_descent(&a, at, Heading::North) {
            prop_assert!(!other.copy_reverse_from(&marked, &b));
        }
        let wider = Bounds::new(Pos::new(0, 0), w + 1, h);
        let c = KnownMap::new(vec![Block::EMPTY; blocks_for(wider.area())], wider).unwrap();
        prop_assert!(!other.copy_reverse_from(&from, &c));
    }
}
