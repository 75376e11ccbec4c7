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
    // edges. The bound meets it: 7 nodes to visit, rounded up to an even
    // walk on the bipartite lattice.
    assert_eq!(lb.with_return, 8);
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

/// The least makespan, in edge traversals of the busiest robot, of a team
/// that knows the field (offline): breadth first over (positions, visited
/// nodes) in lock step, each robot driving one edge or standing per step.
/// Complete once every reachable node is visited or has its four lattice
/// neighbours visited, and (`home`) every robot stands on its start.
fn exact_makespan(truth: &Truth, starts: &[Pos], home: bool) -> u64 {
    let b = truth.bounds();
    let sources: Vec<usize> = starts.iter().map(|&p| b.index(p).unwrap()).collect();
    let dist = bfs(truth, &sources);
    let nodes: Vec<usize> = truth.indices().filter(|&i| dist[i] != u32::MAX).collect();
    let n = nodes.len();
    assert!(n <= 20, "too many nodes for the exact search");
    let id = |i: usize| nodes.iter().position(|&v| v == i);
    let moves: Vec<Vec<usize>> = nodes
        .iter()
        .map(|&v| {
            let mut m = vec![id(v).unwrap()];
            m.extend(
                Heading::ALL
                    .iter()
                    .filter_map(|&h| truth.along(v, h).and_then(id)),
            );
            m
        })
        .collect();
    // The lattice neighbours that make a node known, if all are nodes.
    let lattice: Vec<Option<u32>> = nodes
        .iter()
        .map(|&v| {
            Heading::ALL.iter().try_fold(0u32, |mask, &h| {
                let j = neighbour_index(b, v, h)?;
                Some(mask | 1 << id(j)?)
            })
        })
        .collect();
    let full = (1u32 << n) - 1;
    let known =
        |vis: u32| (0..n).all(|v| vis & 1 << v != 0 || lattice[v].is_some_and(|m| vis & m == m));
    let k = starts.len();
    let homes: Vec<usize> = sources.iter().map(|&s| id(s).unwrap()).collect();
    let encode =
        |pos: &[usize], vis: u32| pos.iter().fold(0usize, |c, &p| c * n + p) << n | vis as usize;
    let mut seen = vec![false; n.pow(k as u32) << n];
    let vis0 = homes.iter().fold(0u32, |m, &h| m | 1 << h);
    let mut layer = vec![(homes.clone(), vis0)];
    seen[encode(&homes, vis0)] = true;
    for steps in 0.. {
        let mut next = Vec::new();
        for (pos, vis) in &layer {
            if known(*vis) && (!home || *pos == homes) {
                return steps;
            }
            // Every combination of one move per robot.
            let mut choice = vec![0usize; k];
            loop {
                let to: Vec<usize> = (0..k).map(|r| moves[pos[r]][choice[r]]).collect();
                let v = to.iter().fold(*vis, |m, &p| m | 1 << p) & full;
                let code = encode(&to, v);
                if !seen[code] {
                    seen[code] = true;
                    next.push((to, v));
                }
                let Some(r) = (0..k).find(|&r| choice[r] + 1 < moves[pos[r]].len()) else {
                    break;
                };
                choice[r] += 1;
                choice[..r].fill(0);
            }
        }
        assert!(!next.is_empty(), "the exact search ran out of states");
        layer = next;
    }
    unreachable!()
}

/// A random field on a `w` × `h` lattice: each node present with
/// probability 7/8, each lattice edge between present nodes with
/// probability `edge_pct` %.
fn random_field(w: i16, h: i16, edge_pct: u64, rnd: &mut impl FnMut() -> u64) -> Truth {
    let present: Vec<bool> = (0..w * h).map(|_| rnd() % 8 != 0).collect();
    let mut arms = vec![Arms::NONE; (w * h) as usize];
    for y in 0..h {
        for x in 0..w {
            let i = (y * w + x) as usize;
            for (dx, dy, a, back) in [
                (1, 0, Heading::East, Heading::West),
                (0, 1, Heading::North, Heading::South),
            ] {
                let (x2, y2) = (x + dx, y + dy);
                if x2 >= w || y2 >= h {
                    continue;
                }
                let j = (y2 * w + x2) as usize;
                if present[i] && present[j] && rnd() % 100 < edge_pct {
                    arms[i] = arms[i].with(a);
                    arms[j] = arms[j].with(back);
                }
            }
        }
    }
    let nodes = (0..h).flat_map(|y| (0..w).map(move |x| (x, y)));
    Truth::new(
        nodes
            .filter(|&(x, y)| present[(y * w + x) as usize])
            .map(|(x, y)| (Pos::new(x, y), arms[(y * w + x) as usize]))
            .collect::<Vec<_>>(),
    )
}

/// Both bounds under the skipping rule against the true optimum, found by
/// exhaustive search on small random fields: never above it, and equal to
/// it on some (a bound that is valid only by being slack would not be).
#[test]
fn bounds_never_exceed_the_exact_optimum() {
    let mut s = 0x9E37_79B9_7F4A_7C15u64;
    let mut rnd = move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        s
    };
    let (mut cases, mut tight_return, mut tight_explore) = (0, 0, 0);
    for (w, h, k, runs) in [
        (3, 3, 1, 60),
        (3, 3, 2, 60),
        (3, 3, 3, 20),
        (4, 3, 2, 40),
        (4, 4, 1, 1000),
        (5, 3, 1, 600),
        (5, 4, 1, 100),
        (4, 4, 2, 20),
    ] {
        for _ in 0..runs {
            let truth = random_field(w, h, 40 + rnd() % 60, &mut rnd);
            let all: Vec<usize> = truth.indices().collect();
            if all.is_empty() {
                continue;
            }
            let starts: Vec<Pos> = (0..k)
                .map(|_| truth.bounds().pos(all[(rnd() % all.len() as u64) as usize]))
                .collect();
            let lb = lower_bounds(&truth, &starts, k);
            let (ret, exp) = (
                exact_makespan(&truth, &starts, true),
                exact_makespan(&truth, &starts, false),
            );
            assert!(
                lb.with_return % 2 == 0 && lb.all_nodes_return % 2 == 0,
                "odd return bound: {lb:?}"
            );
            assert!(
                lb.with_return <= ret,
                "with return {} > {ret}: {w}×{h}, {starts:?}",
                lb.with_return
            );
            assert!(
                lb.explore <= exp,
                "explore {} > {exp}: {w}×{h}, {starts:?}",
                lb.explore
            );
            cases += 1;
            tight_return += usize::from(lb.with_return == ret);
            tight_explore += usize::from(lb.explore == exp);
        }
    }
    eprintln!("{cases} cases, {tight_return} tight with return, {tight_explore} explore only");
    // Parity and the cycle's drive (stop 64) made the bound with return
    // tight on 1 759 of these 1 900 fields (885 before): keep it so.
    assert!(
        cases >= 250 && tight_return * 10 >= cases * 9 && tight_explore >= cases / 4,
        "{cases} cases, {tight_return} tight with return, {tight_explore} explore only"
    );
}
