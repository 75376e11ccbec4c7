use super::*;

#[test]
fn open_grid_skips_at_most_a_third() {
    // 9 × 9 open grid: 81 nodes, 144 edges, budget 64; 49 interior
    // candidates of degree 4 (cost 3): at most 21 fit, fewer than
    // the 25 of the maximum independent set.
    let lb = lower_bounds(&grid(9, 9), &[Pos::new(0, 0)], 1);
    assert_eq!(lb.explore, 81 - 1 - 21);
    assert!(lb.with_return >= lb.explore);
}
use core_algo::geometry::Arms;

fn grid(w: i16, h: i16) -> Truth {
    let mut nodes = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let mut a = Arms::NONE;
            if y + 1 < h {
                a = a.with(Heading::North);
            }
            if y > 0 {
                a = a.with(Heading::South);
            }
            if x + 1 < w {
                a = a.with(Heading::East);
            }
            if x > 0 {
                a = a.with(Heading::West);
            }
            nodes.push((Pos::new(x, y), a));
        }
    }
    Truth::new(nodes)
}

#[test]
fn corridor_bounds_are_exact() {
    // A corridor of 5 nodes from one end: 4 edges out, 8 with return;
    // no node has four neighbours, so nothing can be skipped.
    let lb = lower_bounds(&grid(5, 1), &[Pos::new(0, 0)], 1);
    assert_eq!((lb.explore, lb.with_return), (4, 8));
    assert_eq!((lb.all_nodes_explore, lb.all_nodes_return), (4, 8));
    // From the middle with two robots: each side is a bridge chain.
    let lb = lower_bounds(&grid(5, 1), &[Pos::new(2, 0), Pos::new(1, 0)], 2);
    assert_eq!(lb.with_return, 4);
}

#[test]
fn skippable_centre_lowers_the_bound() {
    // 3 × 3 open grid from a corner: the centre has four neighbours
    // and may be skipped; 7 other nodes need visiting.
    let lb = lower_bounds(&grid(3, 3), &[Pos::new(0, 0)], 1);
    assert_eq!(lb.all_nodes_explore, 8);
    // Budget: 12 edges − 9 nodes + 1 start = 4 ≥ 3 for the centre.
    assert_eq!(lb.explore, 7);
    // A closed walk around the border visits all 8 border nodes: 8
    // edges, and the bound with return is at most that.
    assert!(lb.with_return <= 8 && lb.with_return >= 7);
    assert!(lb.offline_upper >= lb.explore);
}

/// An augmenting path as long as the field: a snake through a 600 ×
/// 600 grid whose inner nodes are matched in pairs, then both ends
/// added. A recursive search needs 90 000 frames here, more than a
/// test thread's stack holds.
#[test]
fn a_field_long_augmenting_path_is_found() {
    let side = 600i16;
    let truth = grid(side, side);
    let b = truth.bounds();
    let mut path = Vec::new();
    for y in (0..side).step_by(2) {
        let xs: Vec<i16> = if y % 4 == 0 {
            (0..side).collect()
        } else {
            (0..side).rev().collect()
        };
        path.extend(xs.iter().map(|&x| b.index(Pos::new(x, y)).unwrap()));
        if y + 2 < side {
            let x = if y % 4 == 0 { side - 1 } else { 0 };
            path.push(b.index(Pos::new(x, y + 1)).unwrap());
        }
    }
    path.pop();
    assert_eq!(path.len() % 2, 0);
    let mut m = Matching::new(b.area());
    m.add_level(&truth, &path[1..path.len() - 1]);
    m.settle(&truth);
    assert_eq!(m.size, path.len() / 2 - 1);
    m.add_level(&truth, &[path[0], path[path.len() - 1]]);
    m.settle(&truth);
    assert_eq!(m.size, path.len() / 2);
}

proptest::proptest! {
    /// The matching grown level by level stays a matching of lattice
    /// neighbours (so |C| − |M| bounds α from above) and is maximum
    /// after every `settle`: the same size as Kuhn's algorithm from
    /// scratch (one search per vertex of one colour, a fresh stamp
    /// each) on the vertices so far.
    #[test]
    fn levelled_matching_is_maximum(
        w in 1i16..9, h in 1i16..9, seed in proptest::prelude::any::<u64>(), keep in 30u64..100,
    ) {
        let truth = grid(w, h);
        let area = truth.bounds().area();
        let mut s = seed | 1;
        let mut rnd = move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            s
        };
        // Random vertices in random levels of up to 5.
        let mut vs: Vec<usize> = (0..area).filter(|_| rnd() % 100 < keep).collect();
        for i in (1..vs.len()).rev() {
            vs.swap(i, (rnd() % (i as u64 + 1)) as usize);
        }
        let mut m = Matching::new(area);
        let mut so_far = Vec::new();
        let levels = vs.len().div_ceil(5);
        for (n, level) in vs.chunks(5).enumerate() {
            m.add_level(&truth, level);
            so_far.extend_from_slice(level);
            let mut fresh = Matching::new(area);
            for &v in &so_far {
                fresh.present[v] = true;
            }
            let mut size = 0;
            for &v in &so_far {
                let p = truth.bounds().pos(v);
                if (p.x + p.y).rem_euclid(2) == 0 {
                    fresh.round += 1;
                    if fresh.augment(&truth, v) {
                        size += 1;
                    }
                }
            }
            let settled = n + 1 == levels || rnd() % 3 == 0;
            if settled {
                m.settle(&truth);
                proptest::prop_assert_eq!(m.size, size);
            } else {
                proptest::prop_assert!(m.size <= size);
            }
            let mut matched = 0;
            for &v in &so_far {
                let u = m.mate[v];
                if u != NONE {
                    matched += 1;
                    let adjacent = Heading::ALL
                        .iter()
                        .any(|&h| neighbour_index(truth.bounds(), v, h) == Some(u));
                    proptest::prop_assert!(adjacent && m.mate[u] == v && m.present[u]);
                }
            }
            proptest::prop_assert_eq!(matched, 2 * m.size);
        }
    }
}
