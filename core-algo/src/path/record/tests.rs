use super::super::tests::{bfs_order, known_prefix, random_arms, tree_arms};
use super::super::*;
use crate::team::RobotId;
use proptest::prelude::*;
use std::vec;
use std::vec::Vec;

fn field_for(area: usize) -> DistField<Vec<PlanCell>> {
    DistField::new(vec![PlanCell::EMPTY; min_cells(area)])
}

/// A search written down as a memo would keep it.
struct Written {
    reached: Vec<Reached>,
    cells: Vec<(u32, PlanCell)>,
    state: Option<SearchState>,
}

impl Written {
    fn rec(&self) -> RecordedSearch<'_> {
        RecordedSearch {
            reached: &self.reached,
            cells: &self.cells,
            state: self.state.expect("written down"),
        }
    }
}

/// Searches `map` from `pose`, stopping after `stop` nodes, and writes it
/// down.
fn write(
    f: &mut DistField<Vec<PlanCell>>,
    map: &KnownMap<Vec<Block>>,
    t: Timing,
    (at, h): (Pos, Heading),
    stop: usize,
) -> Written {
    let mut reached = Vec::new();
    f.compute(map, t, at, h, |i, dist| {
        let mark = node_mark(map, i);
        reached.push(Reached {
            node: i as u32,
            dist,
            mark,
        });
        if reached.len() > stop {
            Flow::Stop
        } else {
            Flow::Continue
        }
    })
    .unwrap();
    let mut cells = Vec::new();
    let state = f.write_down(|i, c| cells.push((i, c)));
    Written {
        reached,
        cells,
        state,
    }
}

/// Every node's reached time and every pose's settled time.
fn times(f: &DistField<Vec<PlanCell>>, area: usize) -> Vec<Option<Ticks>> {
    (0..area)
        .flat_map(|i| {
            let mut v = vec![f.dist_at(i)];
            v.extend(Heading::ALL.map(|h| f.dist_pose_at(i, h)));
            v
        })
        .collect()
}

/// Resumes `f` to the end: what it reaches, in order.
fn rest(f: &mut DistField<Vec<PlanCell>>, map: &KnownMap<Vec<Block>>) -> Vec<(usize, Ticks)> {
    let mut out = Vec::new();
    f.resume(map, |i, d| {
        out.push((i, d));
        Flow::Continue
    })
    .unwrap();
    out
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1024))]

    /// A search recorded on one map and taken over on another where every
    /// node it reached reads the same stands where a fresh search there,
    /// stopped at the same node, stands: the same times for every node and
    /// pose, and resumed, the same nodes at the same times in the same
    /// order; and the next search in it finds the field clean. The second
    /// map knows more or fewer nodes than the first; the field that takes
    /// over held another search before, and small windows (queues of 8
    /// cells a node) and larger ones (one) both run.
    #[test]
    fn a_search_taken_over_goes_on_as_a_fresh_one(
        w in 1u16..16, h in 1u16..16, seed in any::<u64>(), maze in any::<bool>(),
        known in 1usize..256, other in 0usize..256, pick in any::<usize>(), heading in 0u8..4,
        stop in 0usize..256, edge in 1u32..200, turn in 1u32..128, before in any::<usize>(),
    ) {
        let b = Bounds::new(Pos::new(0, 0), w, h);
        let area = b.area();
        let arms = if maze { tree_arms(b, seed) } else { random_arms(b, seed) };
        let order = bfs_order(b, &arms);
        let a = known_prefix(b, &arms, known);
        let other = known_prefix(b, &arms, other);
        let t = Timing { edge, quarter_turn: turn };
        let start = (b.pos(order[pick % known.min(order.len())]), Heading::from_index(heading));
        let written = write(&mut field_for(area), &a, t, start, stop);
        if !reads_same(&other, &written.reached) {
            return Ok(());
        }
        let mut fresh = field_for(area);
        let mut n = 0;
        fresh.compute(&other, t, start.0, start.1, |_, _| {
            n += 1;
            if n > stop { Flow::Stop } else { Flow::Continue }
        }).unwrap();
        let mut taken = field_for(area);
        let was = b.pos(before % area);
        taken.compute(&a, t, was, Heading::North, |_, _| Flow::Continue).unwrap();
        taken.take_over(&other, t, written.rec()).unwrap();
        prop_assert!(taken.is_search_from(&other, t, start.0, start.1));
        prop_assert_eq!(times(&taken, area), times(&fresh, area));
        let (r1, r2) = (rest(&mut taken, &other), rest(&mut fresh, &other));
        prop_assert_eq!(r1, r2);
        prop_assert_eq!(times(&taken, area), times(&fresh, area));
        // The next search in the field clears all that the taken-over one wrote.
        for f in [&mut taken, &mut fresh] {
            f.compute(&other, t, was, Heading::South, |_, _| Flow::Continue).unwrap();
        }
        prop_assert_eq!(times(&taken, area), times(&fresh, area));
    }
}

/// The nodes a search reached are what tells whether it still holds: a
/// node visited beyond where it stopped changes nothing, one it reached as
/// a frontier node does.
#[test]
fn a_search_reads_the_same_until_a_node_it_reached_changes() {
    let b = Bounds::new(Pos::new(0, 0), 12, 1);
    let mut arms = vec![crate::geometry::Arms::NONE; b.area()];
    for (x, a) in arms.iter_mut().enumerate() {
        let mut bits = 0;
        if x > 0 {
            bits |= 1 << Heading::West.index();
        }
        if x < 11 {
            bits |= 1 << Heading::East.index();
        }
        *a = crate::geometry::Arms::from_bits(bits);
    }
    let t = Timing {
        edge: 10,
        quarter_turn: 5,
    };
    let mut map = KnownMap::new(vec![Block::EMPTY; crate::map::blocks_for(b.area())], b).unwrap();
    for x in 0..6 {
        map.visit(Pos::new(x, 0), arms[x as usize], RobotId(0))
            .unwrap();
    }
    // Reaches nodes 0..=6: node 6 is the frontier node.
    let written = write(
        &mut field_for(b.area()),
        &map,
        t,
        (Pos::new(0, 0), Heading::East),
        100,
    );
    assert_eq!(written.reached.len(), 7);
    assert!(written.state.is_some_and(|s| s.ran_out()));
    assert!(reads_same(&map, &written.reached));
    map.visit(Pos::new(6, 0), arms[6], RobotId(0)).unwrap();
    assert!(
        !reads_same(&map, &written.reached),
        "node 6 is no frontier node now"
    );
    // Stopped at node 3, the search never reached node 6.
    let mut before =
        KnownMap::new(vec![Block::EMPTY; crate::map::blocks_for(b.area())], b).unwrap();
    for x in 0..6 {
        before
            .visit(Pos::new(x, 0), arms[x as usize], RobotId(0))
            .unwrap();
    }
    let short = write(
        &mut field_for(b.area()),
        &before,
        t,
        (Pos::new(0, 0), Heading::East),
        3,
    );
    assert!(reads_same(&map, &short.reached));
    let mut f = field_for(b.area());
    f.take_over(&map, t, short.rec()).unwrap();
    let went_on = rest(&mut f, &map);
    assert_eq!(went_on.first(), Some(&(4, 40)));
    assert_eq!(
        went_on.last(),
        Some(&(7, 70)),
        "through node 6, visited now"
    );
}

/// A field that holds anything but a plain forward search writes nothing
/// down.
#[test]
fn only_a_plain_forward_search_is_written_down() {
    let b = Bounds::new(Pos::new(0, 0), 6, 6);
    let arms = random_arms(b, 7);
    let map = known_prefix(b, &arms, 20);
    let t = Timing {
        edge: 10,
        quarter_turn: 5,
    };
    let mut f = field_for(b.area());
    f.compute_jumping(&map, t, Pos::new(0, 0), Heading::North, |_, _| {
        Flow::Continue
    })
    .unwrap();
    assert!(f.write_down(|_, _| {}).is_none());
    let goal = map.frontier().next().unwrap();
    f.compute_reverse(&map, t, goal, |_, _, _| Flow::Continue)
        .unwrap();
    assert!(f.write_down(|_, _| {}).is_none());
    f.compute_avoiding(
        &map,
        t,
        (Pos::new(0, 0), Heading::North),
        |_| false,
        |_, _| Flow::Continue,
    )
    .unwrap();
    assert!(f.write_down(|_, _| {}).is_none());
    f.compute(&map, t, Pos::new(0, 0), Heading::North, |_, _| {
        Flow::Continue
    })
    .unwrap();
    assert!(f.write_down(|_, _| {}).is_some());
}
