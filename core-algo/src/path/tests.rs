use super::*;
use crate::geometry::Turn;
use crate::map::blocks_for;
use crate::team::RobotId;
use proptest::prelude::*;
use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::vec;
use std::vec::Vec;

/// A random field of `w` × `h` nodes (reciprocal arms) and a known map of
/// the first `known` nodes reached by BFS from (0, 0).
pub(crate) fn random_known(w: u16, h: u16, seed: u64, known: usize) -> KnownMap<Vec<Block>> {
    let bounds = Bounds::new(Pos::new(0, 0), w, h);
    let arms = random_arms(bounds, seed);
    let mut map = KnownMap::new(vec![Block::EMPTY; blocks_for(bounds.area())], bounds).unwrap();
    for i in bfs_order(bounds, &arms).into_iter().take(known) {
        map.visit(bounds.pos(i), arms[i], RobotId(0)).unwrap();
    }
    map
}

/// Reciprocal random arms, each lattice edge present with 70 % chance.
pub(crate) fn random_arms(bounds: Bounds, seed: u64) -> Vec<Arms> {
    let mut arms = vec![Arms::NONE; bounds.area()];
    let mut s = seed | 1;
    let mut rnd = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        s
    };
    for i in 0..bounds.area() {
        for hd in [Heading::North, Heading::East] {
            if let Some(j) = neighbour_index(bounds, i, hd) {
                if rnd() % 100 < 70 {
                    arms[i] = arms[i].with(hd);
                    arms[j] = arms[j].with(hd.opposite());
                }
            }
        }
    }
    arms
}

/// A perfect maze: a random depth-first spanning tree of the lattice.
pub(crate) fn tree_arms(bounds: Bounds, seed: u64) -> Vec<Arms> {
    let mut s = seed | 1;
    let mut rnd = move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        s
    };
    let mut arms = vec![Arms::NONE; bounds.area()];
    let mut seen = vec![false; bounds.area()];
    let mut stack = vec![0usize];
    seen[0] = true;
    while let Some(&i) = stack.last() {
        let open: Vec<(Heading, usize)> = Heading::ALL
            .into_iter()
            .filter_map(|h| neighbour_index(bounds, i, h).map(|j| (h, j)))
            .filter(|&(_, j)| !seen[j])
            .collect();
        if open.is_empty() {
            stack.pop();
            continue;
        }
        let (h, j) = open[(rnd() % open.len() as u64) as usize];
        arms[i] = arms[i].with(h);
        arms[j] = arms[j].with(h.opposite());
        seen[j] = true;
        stack.push(j);
    }
    arms
}

/// The nodes reachable from node 0 along `arms`, in BFS order.
pub(crate) fn bfs_order(bounds: Bounds, arms: &[Arms]) -> Vec<usize> {
    let mut seen = vec![false; bounds.area()];
    let mut queue = std::collections::VecDeque::from([0usize]);
    seen[0] = true;
    let mut order = Vec::new();
    while let Some(i) = queue.pop_front() {
        order.push(i);
        for hd in arms[i].iter() {
            if let Some(j) = neighbour_index(bounds, i, hd) {
                if !seen[j] {
                    seen[j] = true;
                    queue.push_back(j);
                }
            }
        }
    }
    order
}

/// Brute-force Dijkstra over (node, heading) states with a binary heap.
fn brute(map: &KnownMap<Vec<Block>>, t: Timing, s0: usize, h0: usize) -> Vec<Option<u32>> {
    brute_avoiding(map, t, (s0, h0), &[])
}

/// [`brute`] that never drives on from (nor turns on) a node in `avoid`
/// but the start.
fn brute_avoiding(
    map: &KnownMap<Vec<Block>>,
    t: Timing,
    (s0, h0): (usize, usize),
    avoid: &[usize],
) -> Vec<Option<u32>> {
    let b = map.bounds();
    let mut dist = vec![None; b.area() * 4];
    let mut heap = BinaryHeap::new();
    heap.push(Reverse((0u32, s0 * 4 + h0)));
    while let Some(Reverse((d, s))) = heap.pop() {
        if dist[s].is_some() {
            continue;
        }
        dist[s] = Some(d);
        let (v, h) = (s / 4, s % 4);
        if v != s0 && avoid.contains(&v) {
            continue;
        }
        let Some(a) = arms_at(map, v) else { continue };
        let hd = Heading::from_index(h as u8);
        if a.has(hd) {
            if let Some(w) = neighbour_index(b, v, hd) {
                heap.push(Reverse((d + t.edge, w * 4 + h)));
            }
        }
        heap.push(Reverse((d + t.quarter_turn, v * 4 + (h + 1) % 4)));
        heap.push(Reverse((d + t.quarter_turn, v * 4 + (h + 3) % 4)));
    }
    dist
}

fn field_for(area: usize) -> DistField<Vec<PlanCell>> {
    DistField::new(vec![PlanCell::EMPTY; min_cells(area)])
}

#[test]
fn straight_corridor_costs_edges_and_turns() {
    let bounds = Bounds::new(Pos::new(0, 0), 4, 1);
    let mut map = KnownMap::new(vec![Block::EMPTY; 1], bounds).unwrap();
    let ew = Arms::NONE.with(Heading::East).with(Heading::West);
    map.visit(Pos::new(0, 0), Arms::NONE.with(Heading::East), RobotId(0))
        .unwrap();
    map.visit(Pos::new(1, 0), ew, RobotId(0)).unwrap();
    map.visit(Pos::new(2, 0), ew, RobotId(0)).unwrap();
    let t = Timing::DEFAULT;
    let mut f = field_for(4);
    f.compute(&map, t, Pos::new(0, 0), Heading::North, |_, _| {
        Flow::Continue
    })
    .unwrap();
    // One right turn, then three edges; (3, 0) is a frontier node.
    assert_eq!(f.dist(Pos::new(3, 0)), Some(t.quarter_turn + 3 * t.edge));
    assert_eq!(
        f.dist_pose(Pos::new(0, 0), Heading::South),
        Some(2 * t.quarter_turn)
    );
    assert_eq!(
        f.dist_pose(Pos::new(3, 0), Heading::West),
        None,
        "frontier is not expanded"
    );
    assert_eq!(f.first_heading(&map, 3), Some(Heading::East));
    let mut out = [Pos::new(0, 0); 8];
    let n = f.path(&map, 3, &mut out).unwrap();
    assert_eq!(
        &out[..n],
        &[
            Pos::new(0, 0),
            Pos::new(1, 0),
            Pos::new(2, 0),
            Pos::new(3, 0)
        ]
    );
    assert_eq!(f.first_heading(&map, 0), None);
    // Walking back from (3, 0): the target first, the start last.
    assert_eq!(f.first_back(&map, 3, |_| true), Some(3));
    assert_eq!(f.first_back(&map, 3, |v| v < 2), Some(1));
    assert_eq!(f.first_back(&map, 3, |v| v == 0), Some(0));
    assert_eq!(f.first_back(&map, 2, |v| v == 3), None, "not on the path");
}

#[test]
fn only_a_search_run_to_the_end_is_complete() {
    let mut map = random_known(8, 8, 5, 30);
    let (t, home) = (Timing::DEFAULT, Pos::new(0, 0));
    let mut f = field_for(64);
    let mut n = 0;
    f.compute(&map, t, home, Heading::North, |_, _| {
        n += 1;
        if n < 5 { Flow::Continue } else { Flow::Stop }
    })
    .unwrap();
    assert!(f.is_distance_search_from(&map, t, home, Heading::North));
    assert!(
        !f.is_complete_search_from(&map, t, home, Heading::North),
        "stopped early"
    );
    f.resume(&map, |_, _| Flow::Continue).unwrap();
    assert!(
        f.is_complete_search_from(&map, t, home, Heading::North),
        "resumed to the end"
    );
    assert!(
        !f.is_complete_search_from(&map, t, home, Heading::East),
        "another start"
    );
    // Marks and memos leave it whole.
    let far = (0..64).rev().find(|&i| f.dist_at(i).is_some()).unwrap();
    f.mark_way(&map, far);
    assert!(f.passes_any(&map, far, &[far]), "the target counts");
    assert!(f.is_complete_search_from(&map, t, home, Heading::North));
    let before: Vec<_> = (0..64).map(|i| f.dist_at(i)).collect();
    let mut fresh = field_for(64);
    fresh
        .compute(&map, t, home, Heading::North, |_, _| Flow::Continue)
        .unwrap();
    assert_eq!(
        before,
        (0..64).map(|i| fresh.dist_at(i)).collect::<Vec<_>>()
    );
    // A grown map needs a new search.
    let frontier = map.frontier().next().unwrap();
    let arms = random_arms(map.bounds(), 5)[map.bounds().index(frontier).unwrap()];
    map.visit(frontier, arms, RobotId(0)).unwrap();
    assert!(
        !f.is_complete_search_from(&map, t, home, Heading::North),
        "the map grew"
    );
    f.compute_jumping(&map, t, home, Heading::North, |_, _| Flow::Continue)
        .unwrap();
    assert!(
        !f.is_complete_search_from(&map, t, home, Heading::North),
        "a jumping search"
    );
}

#[test]
fn too_small_scratch_is_an_error_not_a_panic() {
    let map = random_known(10, 10, 3, 50);
    let mut f = DistField::new(vec![PlanCell::EMPTY; 10]);
    let r = f.compute(
        &map,
        Timing::DEFAULT,
        Pos::new(0, 0),
        Heading::North,
        |_, _| Flow::Continue,
    );
    assert!(matches!(r, Err(PlanError::Capacity { .. })));
    let mut f = field_for(100);
    let r = f.compute(
        &map,
        Timing::DEFAULT,
        Pos::new(-1, 0),
        Heading::North,
        |_, _| Flow::Continue,
    );
    assert_eq!(r, Err(PlanError::OutOfBounds(Pos::new(-1, 0))));
}

/// Found by the property below (CI, 2026-11-23): cheap edges and dear
/// turns kept more states in flight than a 64-cell scratch could queue.
#[test]
fn small_window_with_dear_turns_never_overflows() {
    let (w, h) = (9u16, 7u16);
    let area = usize::from(w) * usize::from(h);
    let map = random_known(
        w,
        h,
        5_133_438_870_701_904_914,
        (area as f64 * 0.89) as usize + 1,
    );
    let t = Timing {
        edge: 1,
        quarter_turn: 5,
    };
    let mut f = field_for(area);
    let r = f.compute(&map, t, Pos::new(0, 0), Heading::North, |_, _| {
        Flow::Continue
    });
    assert_eq!(r, Ok(()));
    let want = brute(&map, t, 0, 0);
    for v in 0..area {
        let p = map.bounds().pos(v);
        let node = (0..4).filter_map(|k| want[v * 4 + k]).min();
        assert_eq!(f.dist(p), node, "node {p:?}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    #[test]
    fn field_agrees_with_brute_force_dijkstra(
        w in 1u16..12, h in 1u16..12, seed in any::<u64>(), frac in 0.0f64..1.0, h0 in 0u8..4,
        edge in 1u32..200, turn in 1u32..128,
    ) {
        let area = usize::from(w) * usize::from(h);
        let map = random_known(w, h, seed, (area as f64 * frac) as usize + 1);
        let t = Timing { edge, quarter_turn: turn };
        let mut f = field_for(area);
        let mut order = Vec::new();
        f.compute(&map, t, Pos::new(0, 0), Heading::from_index(h0), |i, d| {
            order.push((i, d));
            Flow::Continue
        }).unwrap();
        let want = brute(&map, t, 0, usize::from(h0));
        for v in 0..area {
            let p = map.bounds().pos(v);
            for hd in Heading::ALL {
                let s = v * 4 + usize::from(hd.index());
                // Frontier nodes are reached but not turned on.
                if arms_at(&map, v).is_some() || want[s].is_none() {
                    prop_assert_eq!(f.dist_pose(p, hd), want[s], "state {:?} {:?}", p, hd);
                }
            }
            let node = (0..4).filter_map(|k| want[v * 4 + k]).min();
            prop_assert_eq!(f.dist_at(v), node);
        }
        // A search stopped anywhere and resumed gives the same field, also
        // on scratch that other searches used before (only what they
        // touched is cleared).
        let stop_after = (seed % 7) as usize + 1;
        let mut r = field_for(area);
        let last = map.bounds().pos(area - 1);
        r.compute_weighted(&map, last, |_| 3, |_, _| Flow::Continue).unwrap();
        r.compute(&map, t, last, Heading::from_index(h0 ^ 2), |_, _| Flow::Continue).unwrap();
        let _ = r.astar(&map, t, last, Heading::North, Pos::new(0, 0)).unwrap();
        // One stopped early from the middle: the next search clears only
        // the diamond it settled.
        let mut n = 0;
        r.compute(&map, t, map.bounds().pos(area / 2), Heading::from_index(h0), |_, _| {
            n += 1;
            if n == stop_after { Flow::Stop } else { Flow::Continue }
        }).unwrap();
        let mut seen = Vec::new();
        r.compute(&map, t, Pos::new(0, 0), Heading::from_index(h0), |i, d| {
            seen.push((i, d));
            if seen.len() == stop_after { Flow::Stop } else { Flow::Continue }
        }).unwrap();
        r.resume(&map, |i, d| {
            seen.push((i, d));
            Flow::Continue
        }).unwrap();
        prop_assert_eq!(&seen, &order);
        // Nodes are reported once each, nearest first.
        prop_assert!(order.windows(2).all(|p| p[0].1 <= p[1].1));
        // A* agrees with the field on every reachable node, and paths cost
        // what the field says.
        let mut a = field_for(area);
        for v in 0..area {
            let got = a.astar(&map, t, Pos::new(0, 0), Heading::from_index(h0), map.bounds().pos(v)).unwrap();
            prop_assert_eq!(got, f.dist_at(v));
            if got.is_some() {
                let mut out = vec![Pos::new(0, 0); area + 1];
                let n = a.path(&map, v, &mut out).unwrap();
                prop_assert_eq!(out[n - 1], map.bounds().pos(v));
                prop_assert!(n as u32 - 1 <= got.unwrap() / t.edge);
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    /// A field that avoids some nodes prices every node as a search of
    /// the map without driving through them does, gives no ways, cannot
    /// be resumed, and the scratch it leaves serves a plain search cleanly.
    #[test]
    fn avoiding_field_agrees_with_brute_force_without_those_nodes(
        w in 1u16..10, h in 1u16..10, seed in any::<u64>(), frac in 0.3f64..1.0, h0 in 0u8..4,
        edge in 1u32..200, turn in 1u32..128, n_avoid in 0usize..6,
    ) {
        let area = usize::from(w) * usize::from(h);
        let map = random_known(w, h, seed, (area as f64 * frac) as usize + 1);
        let t = Timing { edge, quarter_turn: turn };
        // The start (node 0) among them too: it may always be left.
        let avoid: Vec<usize> = (0..n_avoid).map(|k| (seed as usize >> (k * 7)) % area).collect();
        let mut f = field_for(area);
        let mut order = Vec::new();
        f.compute_avoiding(&map, t, (Pos::new(0, 0), Heading::from_index(h0)), |v| avoid.contains(&v), |i, d| {
            order.push((i, d));
            Flow::Continue
        }).unwrap();
        let want = brute_avoiding(&map, t, (0, usize::from(h0)), &avoid);
        for v in 0..area {
            let node = (0..4).filter_map(|k| want[v * 4 + k]).min();
            prop_assert_eq!(f.dist_at(v), node, "node {:?}", map.bounds().pos(v));
            prop_assert_eq!(f.first_heading(&map, v), None);
        }
        prop_assert!(order.windows(2).all(|p| p[0].1 <= p[1].1));
        let mut more = 0;
        f.resume(&map, |_, _| { more += 1; Flow::Continue }).unwrap();
        prop_assert_eq!(more, 0);
        prop_assert!(!f.is_search_from(&map, t, Pos::new(0, 0), Heading::from_index(h0)));
        // Nor is it taken for a node-weighted field, which keeps no start
        // either.
        prop_assert!((0..area).all(|v| f.weighted_first_heading(v).is_none()));
        f.compute(&map, t, Pos::new(0, 0), Heading::from_index(h0), |_, _| Flow::Continue).unwrap();
        let plain = brute(&map, t, 0, usize::from(h0));
        for v in 0..area {
            prop_assert_eq!(f.dist_at(v), (0..4).filter_map(|k| plain[v * 4 + k]).min());
        }
    }

    /// The reverse field of a node prices every pose as a forward search
    /// from that pose does, settles states cheapest first, each once, and
    /// leaves scratch that a forward search reuses cleanly.
    #[test]
    fn reverse_field_agrees_with_every_forward_search(
        w in 1u16..9, h in 1u16..9, seed in any::<u64>(), frac in 0.0f64..1.0,
        goal in any::<usize>(), edge in 1u32..200, turn in 1u32..128,
    ) {
        let area = usize::from(w) * usize::from(h);
        let map = random_known(w, h, seed, (area as f64 * frac) as usize + 1);
        let t = Timing { edge, quarter_turn: turn };
        let b = map.bounds();
        let g = goal % area;
        let mut r = field_for(area);
        // Dirty scratch first: a forward search from elsewhere.
        r.compute(&map, t, b.pos(area - 1), Heading::East, |_, _| Flow::Continue).unwrap();
        let mut got = vec![None; area * 4];
        let mut keys = Vec::new();
        r.compute_reverse(&map, t, b.pos(g), |v, hd, d| {
            let s = v * 4 + usize::from(hd.index());
            assert!(got[s].is_none(), "state {s} settled twice");
            got[s] = Some(d);
            keys.push(d);
            Flow::Continue
        }).unwrap();
        prop_assert!(keys.windows(2).all(|k| k[0] <= k[1]));
        let mut f = field_for(area);
        for v in 0..area {
            for hd in Heading::ALL {
                f.compute(&map, t, b.pos(v), hd, |_, _| Flow::Continue).unwrap();
                let s = v * 4 + usize::from(hd.index());
                prop_assert_eq!(got[s], f.dist_at(g), "pose {:?} {:?}", b.pos(v), hd);
            }
            let node = (0..4).filter_map(|k| got[v * 4 + k]).min();
            prop_assert_eq!(r.dist_at(v), node);
        }
        // No path from a reverse field; a forward search after it is whole.
        prop_assert!(r.first_heading(&map, 0).is_none());
        r.compute(&map, t, Pos::new(0, 0), Heading::North, |_, _| Flow::Continue).unwrap();
        f.compute(&map, t, Pos::new(0, 0), Heading::North, |_, _| Flow::Continue).unwrap();
        for v in 0..area {
            prop_assert_eq!(r.dist_at(v), f.dist_at(v));
        }
    }
}

#[test]
fn planner_state_is_sixteen_bytes_per_node() {
    assert_eq!(core::mem::size_of::<PlanCell>(), 16);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// The node-weighted field against a brute-force node Dijkstra, and its
    /// first heading leads along a path of that cost.
    #[test]
    fn weighted_field_agrees_with_brute_force(
        w in 1u16..12, h in 1u16..12, seed in any::<u64>(), frac in 0.0f64..1.0,
        base in 1u32..20, spread in 0u32..60,
    ) {
        let area = usize::from(w) * usize::from(h);
        let map = random_known(w, h, seed, (area as f64 * frac) as usize + 1);
        let b = map.bounds();
        let cost = |i: usize| base + ((i as u64).wrapping_mul(seed | 1) >> 7) as u32 % (spread + 1);
        let mut want = vec![None; area];
        let mut heap = BinaryHeap::new();
        heap.push(Reverse((0u32, 0usize)));
        while let Some(Reverse((d, v))) = heap.pop() {
            if want[v].is_some() {
                continue;
            }
            want[v] = Some(d);
            let Some(a) = arms_at(&map, v) else { continue };
            for hd in a.iter() {
                if let Some(u) = neighbour_index(b, v, hd) {
                    heap.push(Reverse((d + cost(u), u)));
                }
            }
        }
        // Scratch used by the turn-aware searches first: their leftovers
        // must not leak into the weighted search.
        let mut f = field_for(area);
        let last = b.pos(area - 1);
        f.compute(&map, Timing::DEFAULT, last, Heading::East, |_, _| Flow::Continue).unwrap();
        let _ = f.astar(&map, Timing::DEFAULT, last, Heading::West, Pos::new(0, 0)).unwrap();
        let mut order = Vec::new();
        f.compute_weighted(&map, Pos::new(0, 0), cost, |i, d| {
            order.push((i, d));
            Flow::Continue
        }).unwrap();
        prop_assert!(order.windows(2).all(|p| p[0].1 <= p[1].1));
        prop_assert_eq!(order.len(), want.iter().flatten().count());
        // No turn-aware search stands in the scratch.
        prop_assert_eq!(f.first_heading(&map, 0), None);
        for (v, &wv) in want.iter().enumerate() {
            prop_assert_eq!(f.dist_at(v), wv);
            let first = f.weighted_first_heading(v);
            match wv {
                None | Some(0) => prop_assert_eq!(first, None),
                Some(d) => {
                    // The first step lands on a node from which the rest
                    // of the path costs what is left.
                    let hd = first.unwrap();
                    prop_assert!(arms_at(&map, 0).unwrap().has(hd));
                    let n = neighbour_index(b, 0, hd).unwrap();
                    let mut g = field_for(area);
                    g.compute_weighted(&map, b.pos(n), cost, |_, _| Flow::Continue).unwrap();
                    prop_assert_eq!(g.dist_at(v).map(|r| r + cost(n)), Some(d));
                }
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// A marked way answers `path_passes` exactly as walking it does, and
    /// the marks (kept in the ring slots) never disturb a resumed search.
    #[test]
    fn marked_way_agrees_with_the_walk_and_resumes_cleanly(
        w in 1u16..12, h in 1u16..12, seed in any::<u64>(), frac in 0.0f64..1.0,
        stop_after in 1usize..40,
    ) {
        let area = usize::from(w) * usize::from(h);
        let map = random_known(w, h, seed, (area as f64 * frac) as usize + 1);
        let t = Timing::DEFAULT;
        let mut full = field_for(area);
        let mut order = Vec::new();
        full.compute(&map, t, Pos::new(0, 0), Heading::East, |i, d| {
            order.push((i, d));
            Flow::Continue
        }).unwrap();
        let mut f = field_for(area);
        let mut seen = Vec::new();
        f.compute(&map, t, Pos::new(0, 0), Heading::East, |i, d| {
            seen.push((i, d));
            if seen.len() == stop_after { Flow::Stop } else { Flow::Continue }
        }).unwrap();
        // Mark two ways in turn among the nodes reached so far; the second
        // replaces the first.
        let reached: Vec<usize> = seen.iter().map(|&(i, _)| i).collect();
        for &target in reached.iter().rev().take(2) {
            let want: Vec<bool> = (0..area).map(|v| f.path_passes(&map, target, v)).collect();
            prop_assert!(f.mark_way(&map, target));
            for (v, &wv) in want.iter().enumerate() {
                prop_assert_eq!(f.path_passes(&map, target, v), wv, "target {} via {}", target, v);
            }
        }
        f.resume(&map, |i, d| {
            seen.push((i, d));
            Flow::Continue
        }).unwrap();
        prop_assert_eq!(&seen, &order);
        // After the resume the marks are gone: answers come from the walk
        // again and agree with a fresh field.
        if let Some(&target) = reached.last() {
            for v in 0..area {
                prop_assert_eq!(f.path_passes(&map, target, v), full.path_passes(&map, target, v));
            }
        }
    }
}

proptest! {
    /// Following `heading_after` from the start, pose by pose, drives a
    /// cheapest path to the target and ends there: the rest of a way is
    /// read from the field that found it.
    #[test]
    fn the_rest_of_a_way_is_a_cheapest_way(
        w in 1u16..12, h in 1u16..12, seed in any::<u64>(), frac in 0.0f64..1.0,
    ) {
        let area = usize::from(w) * usize::from(h);
        let map = random_known(w, h, seed, (area as f64 * frac) as usize + 1);
        let t = Timing::DEFAULT;
        let b = map.bounds();
        let mut f = field_for(area);
        f.compute(&map, t, Pos::new(0, 0), Heading::East, |_, _| Flow::Continue).unwrap();
        for target in (1..area).filter(|&i| f.dist_at(i).is_some()) {
            let (mut at, mut facing, mut spent) = (0usize, Heading::East, 0u32);
            while at != target {
                let next = f.heading_after(&map, target, at, facing);
                prop_assert!(next.is_some(), "lost at {} on the way to {}", at, target);
                let next = next.unwrap();
                spent += match facing.turn_to(next) {
                    None => 0,
                    Some(Turn::UTurn) => 2 * t.quarter_turn,
                    Some(_) => t.quarter_turn,
                } + t.edge;
                at = neighbour_index(b, at, next).unwrap();
                facing = next;
            }
            prop_assert_eq!(Some(spent), f.dist_at(target));
            // Arrived: no way on.
            prop_assert_eq!(f.heading_after(&map, target, at, facing), None);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// The memoised `passes` of a complete field answers as the walk does,
    /// for every node, in any order and for a second `via`; a search
    /// stopped early just walks; and new searches on the scratch are clean.
    #[test]
    fn memoised_passes_agree_with_the_walk(
        w in 1u16..12, h in 1u16..12, seed in any::<u64>(), frac in 0.0f64..1.0,
        h0 in 0u8..4,
    ) {
        let area = usize::from(w) * usize::from(h);
        let map = random_known(w, h, seed, (area as f64 * frac) as usize + 1);
        let t = Timing::DEFAULT;
        let start = map.bounds().pos((seed as usize) % area);
        let mut f = field_for(area);
        f.compute(&map, t, start, Heading::from_index(h0), |_, _| Flow::Continue).unwrap();
        let reference = |f: &DistField<Vec<PlanCell>>, via: usize| -> Vec<bool> {
            (0..area).map(|v| f.path_passes(&map, v, via)).collect()
        };
        for via in [(seed as usize / 7) % area, (seed as usize / 13) % area] {
            let want = reference(&f, via);
            // Far nodes first, then near: the memo fills from both ends.
            let got: Vec<bool> = (0..area).rev().map(|v| f.passes(&map, v, via)).collect();
            let got: Vec<bool> = got.into_iter().rev().collect();
            prop_assert_eq!(&got, &want);
            let again: Vec<bool> = (0..area).map(|v| f.passes(&map, v, via)).collect();
            prop_assert_eq!(&again, &want);
        }
        // Several vias at once answer as "any of them", memo or not.
        let vias: Vec<usize> = (1..=3).map(|k| (seed as usize / (5 * k + 1)) % area).collect();
        let want: Vec<bool> = (0..area)
            .map(|v| vias.iter().any(|&via| f.path_passes(&map, v, via)))
            .collect();
        let got: Vec<bool> = (0..area).rev().map(|v| f.passes_any(&map, v, &vias)).collect();
        let got: Vec<bool> = got.into_iter().rev().collect();
        prop_assert_eq!(&got, &want);
        let too_many: Vec<usize> = (0..crate::path::MAX_VIAS + 1).map(|k| vias[k % 3]).collect();
        let walked: Vec<bool> = (0..area).map(|v| f.passes_any(&map, v, &too_many)).collect();
        prop_assert_eq!(&walked, &want);
        // Stopped early: no memo, same answers as the walk.
        let mut g = field_for(area);
        let mut n = 0;
        g.compute(&map, t, start, Heading::from_index(h0), |_, _| {
            n += 1;
            if n == 3 { Flow::Stop } else { Flow::Continue }
        }).unwrap();
        let via = (seed as usize / 7) % area;
        let want = reference(&g, via);
        let got: Vec<bool> = (0..area).map(|v| g.passes(&map, v, via)).collect();
        prop_assert_eq!(got, want);
        // The memo's bits do not leak into the next search on the scratch.
        let mut order = Vec::new();
        f.compute(&map, t, Pos::new(0, 0), Heading::North, |i, d| {
            order.push((i, d));
            Flow::Continue
        }).unwrap();
        let mut fresh = field_for(area);
        let mut want_order = Vec::new();
        fresh.compute(&map, t, Pos::new(0, 0), Heading::North, |i, d| {
            want_order.push((i, d));
            Flow::Continue
        }).unwrap();
        prop_assert_eq!(order, want_order);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    /// Driving a reverse field's `way_out` from any pose reaches the goal
    /// in exactly the time a forward search from that pose finds, and the
    /// marked descent answers as the walk does for every node.
    #[test]
    fn descent_is_a_cheapest_way_and_its_marks_agree(
        w in 1u16..9, h in 1u16..9, seed in any::<u64>(), frac in 0.0f64..1.0,
        goal in any::<usize>(), from in any::<usize>(), hd in 0u8..4,
        edge in 1u32..200, turn in 1u32..128,
    ) {
        let area = usize::from(w) * usize::from(h);
        let map = random_known(w, h, seed, (area as f64 * frac) as usize + 1);
        let t = Timing { edge, quarter_turn: turn };
        let b = map.bounds();
        let (g, v0, h0) = (goal % area, from % area, Heading::from_index(hd));
        let mut r = field_for(area);
        r.compute_reverse(&map, t, b.pos(g), |_, _, _| Flow::Continue).unwrap();
        prop_assert!(r.is_reverse_to(&map, t, b.pos(g)));
        let mut f = field_for(area);
        f.compute(&map, t, b.pos(v0), h0, |_, _| Flow::Continue).unwrap();
        // Drive it, adding up the time.
        let (mut v, mut heading, mut time, mut way) = (v0, h0, 0u32, Vec::new());
        let mut poses = Vec::new();
        while let Some(out) = r.way_out(&map, v, heading) {
            prop_assert!(arms_at(&map, v).is_some_and(|a| a.has(out)), "no arm");
            let turns = match heading.turn_to(out) {
                None => 0,
                Some(Turn::UTurn) => 2,
                Some(_) => 1,
            };
            time += turns * t.quarter_turn + t.edge;
            v = neighbour_index(b, v, out).unwrap();
            heading = out;
            way.push(v);
            poses.push((v, out));
            prop_assert!(way.len() <= area * 4, "the descent loops");
        }
        if v0 == g {
            prop_assert!(way.is_empty());
        } else if f.dist_at(g).is_some() {
            prop_assert_eq!(v, g);
            prop_assert_eq!(Some(time), f.dist_at(g));
        } else {
            prop_assert!(way.is_empty());
        }
        // Walked and marked answers agree for every node.
        let walked: Vec<bool> = (0..area).map(|x| r.descent_passes(&map, v0, h0, x)).collect();
        for (x, &p) in walked.iter().enumerate() {
            prop_assert_eq!(p, way.contains(&x) && (v == g), "node {}", x);
        }
        // One walk for several nodes answers as the walks for each do.
        for n in 0..area.min(8) {
            let vias: Vec<usize> = (0..area).filter(|x| (x + n + seed as usize) % 5 == 0).take(n).collect();
            let each = vias.iter().any(|&x| walked[x]);
            prop_assert_eq!(r.descent_passes_any(&map, v0, h0, &vias), each, "vias {:?}", vias);
        }
        // The first node found along the way is the first of the walk.
        let first = way.iter().copied().find(|&x| x % 3 == seed as usize % 3);
        prop_assert_eq!(r.descent_find(&map, v0, h0, |x| x % 3 == seed as usize % 3), first);
        r.mark_descent(&map, v0, h0);
        for (x, &p) in walked.iter().enumerate() {
            prop_assert_eq!(r.descent_passes(&map, v0, h0, x), p);
            prop_assert_eq!(r.descent_passes_any(&map, v0, h0, &[x]), p);
        }
        // Marks slid a few steps along the way (a team mate drove on)
        // answer as a fresh walk from there does.
        let mut fresh = field_for(area);
        fresh.compute_reverse(&map, t, b.pos(g), |_, _, _| Flow::Continue).unwrap();
        for &(vk, hk) in poses.iter().take(20) {
            r.mark_descent(&map, vk, hk);
            for x in 0..area {
                prop_assert_eq!(
                    r.descent_passes(&map, vk, hk, x),
                    fresh.descent_passes(&map, vk, hk, x),
                    "slid to {} node {}", vk, x
                );
            }
        }
        // Marks of another pose replace them cleanly.
        r.mark_descent(&map, g, Heading::North);
        for x in 0..area {
            prop_assert!(!r.descent_passes(&map, g, Heading::North, x));
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    /// A* guided by a reverse field (any goal, any known part of the map)
    /// finds the cheapest time to every node, its path costs that much,
    /// and it settles no more poses than Manhattan-guided A* when the
    /// landmark is the goal itself.
    #[test]
    fn landmark_astar_agrees_with_the_field(
        w in 1u16..10, h in 1u16..10, seed in any::<u64>(), frac in 0.0f64..1.0, h0 in 0u8..4,
        mark in any::<usize>(), edge in 1u32..200, turn in 1u32..128,
    ) {
        let area = usize::from(w) * usize::from(h);
        let map = random_known(w, h, seed, (area as f64 * frac) as usize + 1);
        let t = Timing { edge, quarter_turn: turn };
        let b = map.bounds();
        let mut f = field_for(area);
        f.compute(&map, t, Pos::new(0, 0), Heading::from_index(h0), |_, _| Flow::Continue).unwrap();
        let mut landmark = field_for(area);
        landmark.compute_reverse(&map, t, b.pos(mark % area), |_, _, _| Flow::Continue).unwrap();
        let mut a = field_for(area);
        for v in 0..area {
            let got = a
                .astar_by_landmark(&map, t, Pos::new(0, 0), Heading::from_index(h0), b.pos(v), &landmark)
                .unwrap();
            prop_assert_eq!(got, f.dist_at(v), "node {}", v);
            if let Some(d) = got {
                // The path drives through known nodes only, ends at v, and
                // its edges and turns add up to no more than the cost.
                let mut out = vec![Pos::new(0, 0); area + 1];
                let n = a.path(&map, v, &mut out).unwrap();
                prop_assert_eq!(out[n - 1], b.pos(v));
                prop_assert!(n as u32 - 1 <= d / t.edge);
                let first = a.first_heading(&map, v);
                prop_assert_eq!(first.is_none(), v == 0);
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    /// One walk back for many nodes answers as one walk for each would,
    /// with the way marked or not.
    #[test]
    fn path_passes_any_agrees_with_each_alone(
        w in 2u16..10, h in 2u16..10, seed in any::<u64>(), known in 1usize..80,
        start in any::<usize>(), target in any::<usize>(),
        vias in proptest::collection::vec(any::<usize>(), 0..6), mark in any::<bool>(),
    ) {
        let map = random_known(w, h, seed, known);
        let b = map.bounds();
        let area = b.area();
        let passable: Vec<usize> = (0..area).filter(|&i| arms_at(&map, i).is_some()).collect();
        let s0 = passable[start % passable.len()];
        let mut f = field_for(area);
        f.compute(&map, Timing::DEFAULT, b.pos(s0), Heading::East, |_, _| Flow::Continue).unwrap();
        let target = target % area;
        let vias: Vec<usize> = vias.iter().map(|v| v % area).collect();
        if mark {
            f.mark_way(&map, target);
        }
        let each = vias.iter().any(|&v| f.path_passes(&map, target, v));
        prop_assert_eq!(f.path_passes_any(&map, target, &vias), each);
    }
}

/// A known map of the first `known` nodes, by BFS from node 0, of a field
/// with `arms`.
pub(crate) fn known_prefix(bounds: Bounds, arms: &[Arms], known: usize) -> KnownMap<Vec<Block>> {
    let mut map = KnownMap::new(vec![Block::EMPTY; blocks_for(bounds.area())], bounds).unwrap();
    for i in bfs_order(bounds, arms).into_iter().take(known) {
        map.visit(bounds.pos(i), arms[i], RobotId(0)).unwrap();
    }
    map
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1024))]

    /// A jumping search reports every node outside corridors (frontier
    /// nodes, junctions, dead ends, the start) at the distance a plain
    /// search gives it, cheapest first, each once, stopped and resumed
    /// anywhere, on mazes (mostly corridors) and open random fields, from
    /// any known node. With its jump heap full it falls back to plain
    /// drives and still agrees; it gives no ways; and a plain search
    /// reuses its scratch cleanly.
    #[test]
    fn jumping_field_agrees_on_every_node_outside_corridors(
        w in 1u16..14, h in 1u16..14, seed in any::<u64>(), frac in 0.0f64..1.0, h0 in 0u8..4,
        edge in 1u32..200, turn in 1u32..128, maze in any::<bool>(), start in any::<usize>(),
        free_slots in 0usize..4, stop_after in 1usize..8,
    ) {
        let area = usize::from(w) * usize::from(h);
        let b = Bounds::new(Pos::new(0, 0), w, h);
        let arms = if maze { tree_arms(b, seed) } else { random_arms(b, seed) };
        let known = (area as f64 * frac) as usize + 1;
        let map = known_prefix(b, &arms, known);
        let order = bfs_order(b, &arms);
        let s0 = order[start % order.len().min(known)];
        let (p0, hd0) = (b.pos(s0), Heading::from_index(h0));
        let t = Timing { edge, quarter_turn: turn };
        let want = brute(&map, t, s0, usize::from(h0));
        let mut plain = field_for(area);
        plain.compute(&map, t, p0, hd0, |_, _| Flow::Continue).unwrap();
        // Full: a heap with `free_slots` left (none: every drive plain).
        for full in [false, true] {
            // Filled before its first expansion, a heap with no slot left
            // sends every drive in plain.
            let all_plain = full && free_slots == 0;
            let stop_after = if all_plain { 1 } else { stop_after };
            let mut f = field_for(area);
            let mut seen = Vec::new();
            f.compute_jumping(&map, t, p0, hd0, |i, d| {
                seen.push((i, d));
                if seen.len() == stop_after { Flow::Stop } else { Flow::Continue }
            }).unwrap();
            if full {
                // Entries for states beyond the scratch, dropped when popped.
                let junk = (f.cells.len() + 1) * 4;
                while f.jumps.len() + free_slots < JUMP_SLOTS {
                    f.jumps.push((junk / 4, 0, MAX_DIST));
                }
            }
            f.resume(&map, |i, d| {
                seen.push((i, d));
                Flow::Continue
            }).unwrap();
            prop_assert!(seen.windows(2).all(|p| p[0].1 <= p[1].1), "{:?}", seen);
            let mut once = seen.iter().map(|&(i, _)| i).collect::<Vec<_>>();
            once.sort_unstable();
            once.dedup();
            prop_assert_eq!(once.len(), seen.len());
            // A corridor node the search went into plain (the heap full)
            // after a jump passed it may be dearer than it is.
            let corridor = |v: usize| v != s0 && arms_at(&map, v).is_some_and(|a| a.count() == 2);
            for &(i, d) in seen.iter().filter(|&&(i, _)| !corridor(i)) {
                prop_assert_eq!(Some(d), plain.dist_at(i), "node {:?}", b.pos(i));
            }
            for v in 0..area {
                let reached = (0..4).filter_map(|k| want[v * 4 + k]).min();
                if !corridor(v) {
                    prop_assert_eq!(f.dist_at(v), reached, "node {:?}", b.pos(v));
                    prop_assert_eq!(reached.is_some(), seen.iter().any(|&(i, _)| i == v));
                }
                // Ways read through corridors are the plain search's, ties
                // included, unless the heap spilled.
                if corridor(v) || !f.holds_ways() {
                    prop_assert_eq!(f.first_heading(&map, v), None);
                    continue;
                }
                prop_assert_eq!(f.first_heading(&map, v), plain.first_heading(&map, v));
                let mut way = vec![Pos::new(0, 0); area + 1];
                let mut got = vec![Pos::new(0, 0); area + 1];
                let n = plain.path(&map, v, &mut way);
                prop_assert_eq!(f.path(&map, v, &mut got), n);
                prop_assert_eq!(&got[..n.unwrap_or(0)], &way[..n.unwrap_or(0)]);
                // Every state driven into, with its distance.
                let drives = |g: &DistField<Vec<PlanCell>>| {
                    let mut all = Vec::new();
                    g.walk_back_while(&map, v, |u, hd, d| { all.push((u, hd, d)); Flow::Continue });
                    all
                };
                prop_assert_eq!(drives(&f), drives(&plain));
                // Which nodes it passes, corridor nodes too.
                for via in (0..area).step_by(3) {
                    prop_assert_eq!(f.path_passes(&map, v, via), plain.path_passes(&map, v, via));
                    let vias = [via, (via * 7 + 1) % area];
                    prop_assert_eq!(
                        f.path_passes_any(&map, v, &vias),
                        plain.path_passes_any(&map, v, &vias)
                    );
                }
                prop_assert_eq!(
                    f.first_back(&map, v, &corridor),
                    plain.first_back(&map, v, &corridor)
                );
                // From every pose on the way, the rest of it.
                for &p in &way[..n.unwrap_or(0)] {
                    for hd in Heading::ALL {
                        let at = b.index(p).unwrap();
                        prop_assert_eq!(
                            f.heading_after(&map, v, at, hd),
                            plain.heading_after(&map, v, at, hd),
                            "to {:?} from {:?} {:?}", b.pos(v), p, hd
                        );
                    }
                }
            }
            // With no slot free it is the plain search, in the same order.
            if all_plain {
                let mut all = Vec::new();
                plain.compute(&map, t, p0, hd0, |i, d| { all.push((i, d)); Flow::Continue }).unwrap();
                prop_assert_eq!(&seen, &all);
            }
            prop_assert!(!f.is_search_from(&map, t, p0, hd0));
            prop_assert!(f.is_distance_search_from(&map, t, p0, hd0));
            prop_assert!(full || f.holds_ways());
            f.compute(&map, t, p0, hd0, |_, _| Flow::Continue).unwrap();
            for v in 0..area {
                prop_assert_eq!(f.dist_at(v), plain.dist_at(v));
                prop_assert_eq!(f.first_heading(&map, v), plain.first_heading(&map, v));
            }
        }
    }
}
