use super::*;
use crate::geometry::Pos;
use crate::map::Bounds;
use crate::path::tests::{known_prefix, random_arms, tree_arms};
use crate::path::{min_cells, neighbour_index};
use crate::timing::Timing;
use proptest::prelude::*;
use std::vec;
use std::vec::Vec;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    /// Driving a way pose by pose with the kept poses gives, at every pose
    /// and for a pose off the way too, the heading `heading_after` walks
    /// out, from plain and jumping searches on mazes and random fields;
    /// and poses kept from one search are not read off another.
    #[test]
    fn kept_poses_give_the_walk_s_headings(
        w in 1u16..14, h in 1u16..14, seed in any::<u64>(), frac in 0.0f64..1.0,
        maze in any::<bool>(), jumping in any::<bool>(), h0 in 0u8..4, other in any::<usize>(),
    ) {
        let area = usize::from(w) * usize::from(h);
        let b = Bounds::new(Pos::new(0, 0), w, h);
        let arms = if maze { tree_arms(b, seed) } else { random_arms(b, seed) };
        let map = known_prefix(b, &arms, (area as f64 * frac) as usize + 1);
        let t = Timing::DEFAULT;
        let mut f = DistField::new(vec![PlanCell::EMPTY; min_cells(area)]);
        let search = |f: &mut DistField<Vec<PlanCell>>, p: Pos, hd: Heading| {
            if jumping {
                f.compute_jumping(&map, t, p, hd, |_, _| Flow::Continue).unwrap();
            } else {
                f.compute(&map, t, p, hd, |_, _| Flow::Continue).unwrap();
            }
        };
        let hd0 = Heading::from_index(h0);
        search(&mut f, Pos::new(0, 0), hd0);
        let mut stale = None;
        for target in (1..area).filter(|&i| f.dist_at(i).is_some() && f.holds_ways()) {
            let (mut at, mut facing) = (0usize, hd0);
            let mut ahead = None;
            let mut walks = 0;
            for _ in 0..=area {
                let before = ahead;
                let kept = f.heading_after_kept(&map, target, (at, facing), &mut ahead);
                walks += usize::from(ahead != before || kept.is_none());
                prop_assert_eq!(kept, f.heading_after(&map, target, at, facing));
                // Off the way: a pose turned round.
                let mut off = ahead;
                let back = facing.opposite();
                prop_assert_eq!(
                    f.heading_after_kept(&map, target, (at, back), &mut off),
                    f.heading_after(&map, target, at, back)
                );
                let Some(next) = kept else { break };
                at = neighbour_index(b, at, next).unwrap();
                facing = next;
            }
            prop_assert_eq!(at, target);
            let way = f.dist_at(target).unwrap() / t.edge + 1;
            prop_assert!(walks as u32 <= way / WAY_AHEAD as u32 + 2, "{} walks", walks);
            if stale.is_none() && way > 2 {
                stale = Some(target);
            }
        }
        // Poses kept from the search from (0, 0) are not read off a
        // search from elsewhere.
        let p = b.pos(other % area);
        if let (Some(target), true) = (stale, map.known_arms(p).is_some()) {
            let mut ahead = None;
            prop_assert!(f.heading_after_kept(&map, target, (0, hd0), &mut ahead).is_some());
            let mut at = 0;
            let mut facing = hd0;
            let next = f.heading_after(&map, target, at, facing).unwrap();
            at = neighbour_index(b, at, next).unwrap();
            facing = next;
            search(&mut f, p, hd0.opposite());
            prop_assert_eq!(
                f.heading_after_kept(&map, target, (at, facing), &mut ahead),
                f.heading_after(&map, target, at, facing)
            );
        }
    }
}
