use super::*;
use proptest::prelude::*;

use std::vec;
use std::vec::Vec;

fn small_map() -> ArrayMap<4> {
    // 10 x 10 window from (-5, -5): 100 nodes in 4 blocks.
    ArrayMap::<4>::with_bounds(Bounds::new(Pos::new(-5, -5), 10, 10)).unwrap()
}

const N: Heading = Heading::North;
const E: Heading = Heading::East;
const S: Heading = Heading::South;
const W: Heading = Heading::West;

fn arms(hs: &[Heading]) -> Arms {
    hs.iter().fold(Arms::NONE, |a, h| a.with(*h))
}

#[test]
fn a_visit_creates_frontier_along_its_arms_only() {
    let mut m = small_map();
    let v = m.visit(Pos::new(0, 0), arms(&[N, E]), RobotId(0)).unwrap();
    assert!(v.first && !v.was_frontier && !v.arm_leaves_bounds);
    let f: Vec<Pos> = m.frontier().collect();
    assert_eq!(f, [Pos::new(1, 0), Pos::new(0, 1)]);
    assert_eq!(m.frontier_len(), 2);
    assert!(
        !m.is_frontier(Pos::new(-1, 0)),
        "no arm west, so no frontier there"
    );
    let v = m.visit(Pos::new(1, 0), arms(&[W, N]), RobotId(1)).unwrap();
    assert!(v.was_frontier);
    assert_eq!(m.cell(Pos::new(1, 0)).first_visitor(), Some(RobotId(1)));
    assert_eq!(
        m.frontier().collect::<Vec<_>>(),
        [Pos::new(0, 1), Pos::new(1, 1)]
    );
}

#[test]
fn node_with_four_visited_neighbours_is_deduced_not_frontier() {
    let mut m = small_map();
    // A ring of four nodes around (0, 0), each pointing into it.
    m.visit(Pos::new(0, 1), arms(&[S]), RobotId(0)).unwrap();
    m.visit(Pos::new(1, 0), arms(&[W]), RobotId(0)).unwrap();
    m.visit(Pos::new(0, -1), arms(&[N]), RobotId(0)).unwrap();
    assert!(m.is_frontier(Pos::new(0, 0)));
    assert_eq!(m.known_arms(Pos::new(0, 0)), None);
    m.visit(Pos::new(-1, 0), Arms::NONE, RobotId(0)).unwrap();
    assert!(!m.is_frontier(Pos::new(0, 0)));
    assert_eq!(m.known_arms(Pos::new(0, 0)), Some(arms(&[N, E, S])));
    assert!(m.is_complete());
    assert_eq!(m.known_len(), 5);
    // Visiting the deduced node changes no search: the revision stays (a
    // field kept on it stays valid), the map stays complete.
    let revision = m.revision();
    let v = m
        .visit(Pos::new(0, 0), arms(&[N, E, S]), RobotId(1))
        .unwrap();
    assert!(v.first);
    assert_eq!(m.revision(), revision);
    assert!(m.is_complete());
    assert_eq!(m.known_len(), 5);
    // A node that was not deduced moves it.
    m.visit(Pos::new(2, 0), Arms::NONE, RobotId(1)).unwrap();
    assert_ne!(m.revision(), revision);
}

#[test]
fn conflicting_reports_are_refused_and_change_nothing() {
    let mut m = small_map();
    m.visit(Pos::new(0, 0), arms(&[N, E]), RobotId(0)).unwrap();
    let before = m.clone();
    let err = m.visit(Pos::new(0, 0), arms(&[N]), RobotId(1)).unwrap_err();
    assert_eq!(
        err,
        MapError::Conflict(Conflict {
            pos: Pos::new(0, 0),
            expected: arms(&[N, E]),
            determined: Arms::CROSS,
            reported: arms(&[N]),
        })
    );
    // (1, 0) must have an arm west, because (0, 0) has one east.
    let err = m.visit(Pos::new(1, 0), arms(&[N]), RobotId(1)).unwrap_err();
    assert!(
        matches!(err, MapError::Conflict(c) if c.determined == arms(&[W]) && c.expected == arms(&[W]))
    );
    // (-1, 0) must not have an arm east.
    assert!(m.visit(Pos::new(-1, 0), arms(&[E]), RobotId(1)).is_err());
    assert_eq!(
        m.frontier().collect::<Vec<_>>(),
        before.frontier().collect::<Vec<_>>()
    );
    assert_eq!(m.cell(Pos::new(0, 0)).visits(), 1);
    // The same report again is a revisit.
    let v = m.visit(Pos::new(0, 0), arms(&[N, E]), RobotId(1)).unwrap();
    assert!(!v.first);
    assert_eq!(m.cell(Pos::new(0, 0)).visits(), 2);
    assert_eq!(m.cell(Pos::new(0, 0)).first_visitor(), Some(RobotId(0)));
}

#[test]
fn window_edges_are_reported() {
    let mut m = small_map();
    assert_eq!(
        m.visit(Pos::new(5, 0), Arms::CROSS, RobotId(0)),
        Err(MapError::OutOfBounds(Pos::new(5, 0)))
    );
    let v = m.visit(Pos::new(4, 4), Arms::CROSS, RobotId(0)).unwrap();
    assert!(v.arm_leaves_bounds);
    assert_eq!(m.frontier_len(), 2);
    assert!(matches!(
        ArrayMap::<1>::with_bounds(Bounds::new(Pos::new(0, 0), 8, 8)),
        Err(MapError::Capacity {
            needed: 64,
            available: 32
        })
    ));
}

#[test]
fn merge_takes_new_nodes_and_counts_conflicts() {
    let mut a = small_map();
    let mut b = small_map();
    a.visit(Pos::new(0, 0), arms(&[E]), RobotId(0)).unwrap();
    b.visit(Pos::new(0, 0), arms(&[N]), RobotId(1)).unwrap();
    b.visit(Pos::new(3, 3), arms(&[S]), RobotId(1)).unwrap();
    b.visit(Pos::new(3, 3), arms(&[S]), RobotId(1)).unwrap();
    let s = a.merge_map(&b);
    assert_eq!(s.added, 1);
    assert_eq!(s.conflicts, 1);
    assert_eq!(s.first_conflict.map(|c| c.pos), Some(Pos::new(0, 0)));
    assert_eq!(a.cell(Pos::new(3, 3)).visits(), 2);
    assert_eq!(a.known_arms(Pos::new(0, 0)), Some(arms(&[E])));
    // Merging again adds nothing and keeps the larger count.
    let s = a.merge_map(&b);
    assert_eq!((s.added, a.cell(Pos::new(3, 3)).visits()), (0, 2));
}

#[test]
fn memory_per_node_is_within_budget() {
    assert_eq!(core::mem::size_of::<NodeCell>(), 4);
    assert_eq!(core::mem::size_of::<Block>(), 4 * BLOCK_NODES + 4);
    // The firmware's 1024-node map.
    assert!(core::mem::size_of::<ArrayMap<32>>() <= 1024 * 8);
}

/// A random true field on a 6 x 6 lattice: arms are consistent by
/// construction (each undirected edge sets both ends).
fn truth() -> impl Strategy<Value = Vec<Arms>> {
    proptest::collection::vec(any::<bool>(), 60).prop_map(|edges| {
        let mut a = std::vec![Arms::NONE; 36];
        let mut k = 0;
        for y in 0..6 {
            for x in 0..6 {
                if x < 5 {
                    if edges[k] {
                        a[y * 6 + x] = a[y * 6 + x].with(E);
                        a[y * 6 + x + 1] = a[y * 6 + x + 1].with(W);
                    }
                    k += 1;
                }
                if y < 5 {
                    if edges[k] {
                        a[y * 6 + x] = a[y * 6 + x].with(N);
                        a[(y + 1) * 6 + x] = a[(y + 1) * 6 + x].with(S);
                    }
                    k += 1;
                }
            }
        }
        a
    })
}

#[derive(Clone, Debug)]
enum Op {
    Visit(usize, u8),
    /// A report with made-up arms: kept if it fits what is known.
    Lie(usize, u8),
    Merge(Vec<usize>),
}

fn ops() -> impl Strategy<Value = Vec<Op>> {
    proptest::collection::vec(
        prop_oneof![
            6 => (0..36usize, 0..6u8).prop_map(|(k, r)| Op::Visit(k, r)),
            1 => (0..36usize, 0..16u8).prop_map(|(k, b)| Op::Lie(k, b)),
            1 => proptest::collection::vec(0..36usize, 0..12).prop_map(Op::Merge),
        ],
        0..80,
    )
}

fn pos_of(k: usize) -> Pos {
    Pos::new((k % 6) as i16 - 2, (k / 6) as i16 - 3)
}

/// The seed's frontier, recomputed from the visited cells alone.
fn frontier_from_scratch(m: &ArrayMap<2>) -> Vec<Pos> {
    let b = m.bounds();
    (0..b.area())
        .map(|i| b.pos(i))
        .filter(|&p| {
            if m.is_visited(p) {
                return false;
            }
            let mut visited = 0;
            let mut into = false;
            for h in Heading::ALL {
                if let Some(a) = p.step(h).and_then(|q| m.cell(q).arms()) {
                    visited += 1;
                    into |= a.has(h.opposite());
                }
            }
            into && visited < 4
        })
        .collect()
}

proptest! {
    #[test]
    fn frontier_always_equals_recomputation(field in truth(), ops in ops()) {
        // An 8 x 8 window (two blocks) around the 6 x 6 field, so that the
        // field's border nodes have neighbours inside the window.
        let bounds = Bounds::new(Pos::new(-3, -4), 8, 8);
        let mut m = ArrayMap::<2>::with_bounds(bounds).unwrap();
        for op in ops {
            match op {
                Op::Visit(k, r) => {
                    let _ = m.visit(pos_of(k), field[k], RobotId(r));
                }
                Op::Lie(k, bits) => {
                    let _ = m.visit(pos_of(k), Arms::from_bits(bits), RobotId(9));
                }
                Op::Merge(ks) => {
                    let mut other = ArrayMap::<2>::with_bounds(bounds).unwrap();
                    for k in ks {
                        let _ = other.visit(pos_of(k), field[k], RobotId(7));
                    }
                    let before = m.visited_len();
                    let s = m.merge_map(&other);
                    prop_assert_eq!(m.visited_len(), before + s.added as usize);
                }
            }
            let expected = frontier_from_scratch(&m);
            prop_assert_eq!(m.frontier().collect::<Vec<_>>(), expected.clone());
            prop_assert_eq!(m.frontier_len(), expected.len());
            prop_assert_eq!(m.visited_len(), m.visited().count());
            let two = m.visited().filter(|(_, c)| c.arms().is_some_and(|a| a.count() == 2)).count();
            prop_assert_eq!(m.two_armed_len(), two);
            // The farthest visited node from anywhere, and no frontier node
            // more than one step beyond it.
            for from in [Pos::new(-3, -4), Pos::new(4, 3), Pos::new(0, 0), Pos::new(-3, 3)] {
                let far = m.visited().map(|(p, _)| p.manhattan(from)).max();
                prop_assert_eq!(m.farthest_visited(from), far);
                for p in &expected {
                    prop_assert!(p.manhattan(from) <= far.unwrap_or(0) + 1);
                }
            }
            let b = m.bounds();
            let known = (0..b.area()).map(|i| b.pos(i)).filter(|p| m.known_arms(*p).is_some_and(|a| m.is_visited(*p) || a.count() > 0)).count();
            prop_assert_eq!(m.known_len(), known);
            // The map never holds two visited neighbours that disagree.
            for (p, c) in m.visited() {
                let a = c.arms().unwrap();
                for h in Heading::ALL {
                    if let Some(b) = p.step(h).and_then(|q| m.cell(q).arms()) {
                        prop_assert_eq!(a.has(h), b.has(h.opposite()));
                    }
                }
            }
        }
    }
}

/// The change log names each node that became passable, visited or
/// deduced, after a revision, and refuses once it no longer reaches back.
#[test]
fn passable_since_names_visited_and_deduced_nodes() {
    let mut m = small_map();
    let b = m.bounds();
    let idx = |x, y| b.index(Pos::new(x, y)).unwrap();
    let r0 = m.revision();
    // Around (1, 1): its four neighbours, the last visit deduces it.
    m.visit(Pos::new(1, 0), arms(&[N]), RobotId(0)).unwrap();
    m.visit(Pos::new(0, 1), arms(&[E]), RobotId(0)).unwrap();
    m.visit(Pos::new(2, 1), arms(&[W]), RobotId(0)).unwrap();
    let r3 = m.revision();
    m.visit(Pos::new(1, 2), arms(&[S]), RobotId(0)).unwrap();
    let since = |m: &ArrayMap<4>, r| m.passable_since(r).map(|i| i.collect::<Vec<_>>());
    assert_eq!(since(&m, r3), Some(vec![idx(1, 2), idx(1, 1)]));
    assert_eq!(since(&m, r0).map(|v| v.len()), Some(5));
    assert_eq!(since(&m, m.revision()), Some(vec![]));
    // A deduced node visited later changes nothing.
    let r4 = m.revision();
    m.visit(Pos::new(1, 1), arms(&[N, E, S, W]), RobotId(0))
        .unwrap();
    assert_eq!(since(&m, r4), Some(vec![]));
    // Forty more visits overflow the log: the old revisions are gone.
    for x in -5..5 {
        for y in [-5, -3, 3] {
            m.visit(Pos::new(x, y), Arms::NONE, RobotId(0)).unwrap();
        }
    }
    assert_eq!(since(&m, r0), None);
    assert_eq!(since(&m, m.revision()), Some(vec![]));
}

/// Two maps that learnt the same nodes in another order, from other
/// robots, have one print; a map's print of a few revisions ago names
/// that revision; a different shape or node gives another print.
#[test]
fn maps_that_read_the_same_have_one_print() {
    let visits = [
        (Pos::new(0, 0), arms(&[N, E])),
        (Pos::new(1, 0), arms(&[W, N])),
        (Pos::new(0, 1), arms(&[S, E])),
        (Pos::new(1, 1), arms(&[S, W])),
    ];
    let mut a = small_map();
    let mut b = small_map();
    let mut revs = Vec::new();
    for (i, &(p, x)) in visits.iter().enumerate() {
        a.visit(p, x, RobotId(0)).unwrap();
        revs.push((a.revision(), a.print()));
        let (q, y) = visits[visits.len() - 1 - i];
        b.visit(q, y, RobotId(i as u8)).unwrap();
        // A repeated report changes nothing.
        b.visit(q, y, RobotId(3)).unwrap();
    }
    assert_eq!(a.print(), b.print());
    assert_ne!(a.print(), MapPrint::default());
    for &(rev, print) in &revs {
        assert_eq!(a.revision_of(print), Some(rev));
    }
    // b never had a's first prints (it learnt the nodes the other way).
    assert_eq!(b.revision_of(revs[0].1), None);
    assert_eq!(b.revision_of(a.print()), Some(b.revision()));
    let mut c = small_map();
    c.visit(Pos::new(0, 0), arms(&[N]), RobotId(0)).unwrap();
    let mut d = small_map();
    d.visit(Pos::new(0, 0), arms(&[N, E]), RobotId(0)).unwrap();
    assert_ne!(c.print(), d.print());
    assert_eq!(d.print(), revs[0].1);
    d.clear();
    assert_eq!(d.print(), MapPrint::default());
    assert_eq!(d.revision_of(revs[0].1), None);
}

/// A block that runs out of frontier nodes leaves its group's index bit
/// set while another block of the group still holds some.
#[test]
fn a_group_keeps_its_index_bit_while_one_block_holds_frontier() {
    // 4 375 blocks of 32 nodes: an index bit per four blocks, so blocks
    // 64 to 67 (row 1, x = 48..=175) share one bit.
    let bounds = Bounds::new(Pos::new(0, 0), 2000, 70);
    let mut m = KnownMap::new(vec![Block::EMPTY; blocks_for(bounds.area())], bounds).unwrap();
    for x in 112..=150 {
        m.visit(Pos::new(x, 1), arms(&[E, W]), RobotId(0)).unwrap();
    }
    assert_eq!(
        m.frontier().collect::<Vec<_>>(),
        [Pos::new(111, 1), Pos::new(151, 1)]
    );
    // Block 65 (x = 80..=111) empties; block 67 still holds x = 151.
    m.visit(Pos::new(111, 1), arms(&[E]), RobotId(0)).unwrap();
    assert_eq!(m.frontier().collect::<Vec<_>>(), [Pos::new(151, 1)]);
    m.visit(Pos::new(151, 1), arms(&[W]), RobotId(0)).unwrap();
    assert_eq!(m.frontier().count(), 0);
    assert!(m.is_complete());
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]
    /// On a map with more blocks than the frontier index has bits, a bit
    /// stands for a group of four blocks: the frontier read through the
    /// index is still every frontier node, in storage order, as visits
    /// add and remove them across the groups' edges.
    #[test]
    fn the_frontier_index_finds_every_frontier_block_in_groups(
        visits in proptest::collection::vec((0..70i16, any::<bool>(), 0..32u8), 1..120),
    ) {
        let bounds = Bounds::new(Pos::new(0, 0), 2000, 70);
        // 4 375 blocks: a bit per four, the last bit for three.
        let blocks = blocks_for(bounds.area());
        prop_assert!(blocks > 2 * frontier_index::INDEX_BITS && blocks % 4 == 3);
        let mut m = KnownMap::new(vec![Block::EMPTY; blocks], bounds).unwrap();
        for (x, last, bits) in visits {
            // Mostly a line along x, so that the frontier runs along rows
            // and empties blocks while others of their group keep some.
            let arms = if bits < 16 { arms(&[E, W]) } else { Arms::from_bits(bits - 16) };
            // Near the first groups, or in the last one, which is short.
            let at = if last { Pos::new(1998 - x, 69) } else { Pos::new(100 + x, 1) };
            let _ = m.visit(at, arms, RobotId(0));
            let scan: Vec<Pos> = (0..bounds.area())
                .filter(|&i| m.is_frontier_at(i))
                .map(|i| bounds.pos(i))
                .collect();
            prop_assert_eq!(m.frontier().collect::<Vec<_>>(), scan);
        }
    }
}
