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
#[derive(Default)]
struct Written {
    reached: Vec<Reached>,
    read: Vec<(u32, u8)>,
    cells: Vec<(u32, PlanCell)>,
    queued: [Vec<u32>; 2],
    state: Option<SearchState>,
}

impl SearchRecorder for Written {
    fn reached(&mut self, r: &[Reached]) {
        self.reached.extend_from_slice(r);
    }
    fn read(&mut self, node: u32, mark: u8) {
        self.read.push((node, mark));
    }
    fn cells_written(&mut self, cells: &[(u32, PlanCell)]) {
        self.cells.extend_from_slice(cells);
    }
    fn queued(&mut self, ring: usize, entries: &[u32]) {
        self.queued[ring].extend_from_slice(entries);
    }
    fn cells(&mut self) -> &mut [(u32, PlanCell)] {
        &mut self.cells
    }
    fn finish(&mut self, state: SearchState) {
        self.state = Some(state);
    }
}

impl Written {
    fn rec(&self) -> RecordedSearch<'_> {
        RecordedSearch {
            id: 1,
            after: 0,
            reached: &self.reached,
            read: &self.read,
            cells: &self.cells,
            queued: [&self.queued[0], &self.queued[1]],
            state: self.state.as_ref().expect("written down"),
        }
    }
}

/// [`DistField::compute`] or, `jumping`, [`DistField::compute_jumping`].
fn search(
    f: &mut DistField<Vec<PlanCell>>,
    map: &KnownMap<Vec<Block>>,
    t: Timing,
    ((at, h), jumping): ((Pos, Heading), bool),
    reached: impl FnMut(usize, Ticks) -> Flow,
) -> Result<(), PlanError> {
    if jumping {
        f.compute_jumping(map, t, at, h, reached)
    } else {
        f.compute(map, t, at, h, reached)
    }
}

/// A search's result in a property test. A window of more than
/// `SMALL_WINDOW` nodes has one queue cell a node, and with cheap edges
/// and dear turns its queues may overflow: the search says so, by design
/// (see `min_cells`), and the case is rejected.
fn fits<T>(r: Result<T, PlanError>) -> Result<T, TestCaseError> {
    match r {
        Ok(v) => Ok(v),
        Err(PlanError::QueueFull) => Err(TestCaseError::reject("the queues overflow")),
        Err(e) => Err(TestCaseError::fail(std::format!("{e:?}"))),
    }
}

/// Searches `map` from a pose, `jumping` or plain, stopping after `stop`
/// nodes, and writes it down.
fn write(
    f: &mut DistField<Vec<PlanCell>>,
    map: &KnownMap<Vec<Block>>,
    t: Timing,
    from: ((Pos, Heading), bool),
    stop: usize,
) -> Result<Written, PlanError> {
    let mut w = Written::default();
    search(f, map, t, from, |i, dist| {
        let mark = node_mark(map, i);
        w.reached.push(Reached {
            node: i as u32,
            dist,
            mark,
        });
        if w.reached.len() > stop {
            Flow::Stop
        } else {
            Flow::Continue
        }
    })?;
    assert!(f.write_down(map, &mut w));
    Ok(w)
}

/// [`write`] through [`DistField::compute_written_down`]: the search tells
/// the record what it reaches and reads as it goes.
fn write_as_told(
    f: &mut DistField<Vec<PlanCell>>,
    map: &KnownMap<Vec<Block>>,
    t: Timing,
    ((at, h), jumping): ((Pos, Heading), bool),
    stop: usize,
) -> Result<Written, PlanError> {
    let mut w = Written::default();
    let mut n = 0;
    f.compute_written_down(map, t, (at, h, jumping), &mut w, |_, _| {
        n += 1;
        if n > stop { Flow::Stop } else { Flow::Continue }
    })?;
    assert!(w.state.is_some(), "written down");
    Ok(w)
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

/// A maze (mostly corridors) or a random field, its nodes in the order
/// a search from the first reaches them, and two maps of it that know
/// the first `known` and `other` nodes in that order.
fn two_maps(
    b: Bounds,
    (seed, maze): (u64, bool),
    (known, other): (usize, usize),
) -> (Vec<usize>, KnownMap<Vec<Block>>, KnownMap<Vec<Block>>) {
    let arms = if maze {
        tree_arms(b, seed)
    } else {
        random_arms(b, seed)
    };
    let order = bfs_order(b, &arms);
    (
        order,
        known_prefix(b, &arms, known),
        known_prefix(b, &arms, other),
    )
}

/// A property test's draw: the window, its two maps (see [`two_maps`]),
/// the timing, and a start pose among the first map's known nodes.
type Drawn = (
    Bounds,
    KnownMap<Vec<Block>>,
    KnownMap<Vec<Block>>,
    Timing,
    (Pos, Heading),
);

/// See [`Drawn`].
fn drawn(
    (w, h): (u16, u16),
    (seed, maze): (u64, bool),
    (known, other): (usize, usize),
    (pick, heading): (usize, u8),
    (edge, turn): (u32, u32),
) -> Drawn {
    let b = Bounds::new(Pos::new(0, 0), w, h);
    let (order, a, other) = two_maps(b, (seed, maze), (known, other));
    let t = Timing {
        edge,
        quarter_turn: turn,
    };
    let start = (
        b.pos(order[pick % known.min(order.len())]),
        Heading::from_index(heading),
    );
    (b, a, other, t, start)
}

/// A search's callback that notes what it reaches in `out`, in order,
/// and stops after `stop` nodes.
fn noted(out: &mut Vec<(usize, Ticks)>, stop: usize) -> impl FnMut(usize, Ticks) -> Flow + '_ {
    move |i, d| {
        out.push((i, d));
        if out.len() > stop {
            Flow::Stop
        } else {
            Flow::Continue
        }
    }
}

/// Resumes `f` to the end: what it reaches, in order.
fn rest(
    f: &mut DistField<Vec<PlanCell>>,
    map: &KnownMap<Vec<Block>>,
) -> Result<Vec<(usize, Ticks)>, PlanError> {
    let mut out = Vec::new();
    f.resume(map, noted(&mut out, usize::MAX))?;
    Ok(out)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1024))]

    /// A search recorded on one map and taken over on another where every
    /// node it read reads the same stands where a fresh search there,
    /// stopped at the same node, stands: the same times for every node and
    /// pose, and resumed, the same nodes at the same times in the same
    /// order; and the next search in it finds the field clean. Plain
    /// searches and jumping ones, on mazes (mostly corridors) and random
    /// fields. The second map knows more or fewer nodes than the first;
    /// the field that takes over held another search before, and small
    /// windows (queues of 8 cells a node) and larger ones (one) both run.
    /// Records are written down after the search or, `told`, by the search
    /// as it goes ([`DistField::compute_written_down`]).
    #[test]
    fn a_search_taken_over_goes_on_as_a_fresh_one(
        w in 1u16..16, h in 1u16..16, seed in any::<u64>(), maze in any::<bool>(),
        known in 1usize..256, other in 0usize..256, pick in any::<usize>(), heading in 0u8..4,
        stop in 0usize..256, edge in 1u32..200, turn in 1u32..128, before in any::<usize>(),
        jumping in any::<bool>(), told in any::<bool>(),
    ) {
        let (b, a, other, t, start) =
            drawn((w, h), (seed, maze), (known, other), (pick, heading), (edge, turn));
        let area = b.area();
        let written = fits(if told {
            write_as_told(&mut field_for(area), &a, t, (start, jumping), stop)
        } else {
            write(&mut field_for(area), &a, t, (start, jumping), stop)
        })?;
        if !reads_same(&other, written.rec()) {
            return Ok(());
        }
        let mut fresh = field_for(area);
        fits(search(&mut fresh, &other, t, (start, jumping), noted(&mut Vec::new(), stop)))?;
        let mut taken = field_for(area);
        let was = b.pos(before % area);
        fits(search(&mut taken, &a, t, ((was, Heading::North), !jumping), |_, _| Flow::Continue))?;
        taken.take_over(&other, t, written.rec()).unwrap();
        prop_assert!(taken.is_distance_search_from(&other, t, start.0, start.1));
        prop_assert_eq!(taken.is_search_from(&other, t, start.0, start.1), !jumping);
        prop_assert_eq!(times(&taken, area), times(&fresh, area));
        // Both go on alike, into an overflow too.
        let (r1, r2) = (rest(&mut taken, &other), rest(&mut fresh, &other));
        prop_assert_eq!(&r1, &r2);
        fits(r1)?;
        prop_assert_eq!(times(&taken, area), times(&fresh, area));
        // The next search in the field clears all that the taken-over one wrote.
        for f in [&mut taken, &mut fresh] {
            fits(f.compute(&other, t, was, Heading::South, |_, _| Flow::Continue))?;
        }
        prop_assert_eq!(times(&taken, area), times(&fresh, area));
    }
}

/// Searches `map` from `start` plainly, stopping after `stop` nodes.
fn plain_until(
    f: &mut DistField<Vec<PlanCell>>,
    map: &KnownMap<Vec<Block>>,
    t: Timing,
    start: (Pos, Heading),
    stop: usize,
) -> Result<Vec<(usize, Ticks)>, PlanError> {
    let mut out = Vec::new();
    f.compute(map, t, start.0, start.1, noted(&mut out, stop))?;
    Ok(out)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1024))]

    /// A plain search recorded on one map and taken over in part on another
    /// ([`first_read_otherwise`], [`DistField::take_over_before`]) goes on as a fresh
    /// search there: the fresh one reaches the record's first `before`
    /// nodes alike, and the taken-over one, resumed, reaches the rest at
    /// the same times in the same order; stopped anywhere, every node and
    /// pose has the fresh search's time, and written down again it holds
    /// the fresh search's last queue entries (those since the take-over),
    /// enough to be taken over whole.
    #[test]
    fn a_search_taken_over_in_part_goes_on_as_a_fresh_one(
        w in 1u16..16, h in 1u16..16, seed in any::<u64>(), maze in any::<bool>(),
        known in 1usize..120, grow in -6isize..6, pick in any::<usize>(), heading in 0u8..4,
        stop in 0usize..256, more in 0usize..256, edge in 1u32..200, turn in 1u32..128,
        before in any::<usize>(),
    ) {
        let b = Bounds::new(Pos::new(0, 0), w, h);
        let area = b.area();
        let other = known.saturating_add_signed(grow);
        let (order, a, other) = two_maps(b, (seed, maze), (known, other));
        let t = Timing { edge, quarter_turn: turn };
        let start = (b.pos(order[pick % known.min(order.len())]), Heading::from_index(heading));
        let written = fits(write(&mut field_for(area), &a, t, (start, false), stop))?;
        let rec = written.rec();
        let Some(changed) = first_read_otherwise(&other, rec).filter(|_| rec.holds_queues()) else {
            return Ok(());
        };
        let dist = written.reached[changed].dist;
        let k = rec.reached_before(dist);
        if k == 0 {
            // The start reads otherwise.
            return Ok(());
        }
        prop_assert!(k > 0 && k < written.reached.len());
        let mut fresh = field_for(area);
        let all = fits(plain_until(&mut fresh, &other, t, start, usize::MAX))?;
        let head: Vec<_> = written.reached[..k].iter().map(|r| (r.node as usize, r.dist)).collect();
        prop_assert_eq!(&all[..k], &head[..]);
        prop_assert!(all.get(k).is_none_or(|&(_, d)| d >= dist));
        // Another search stood in the field before.
        let mut taken = field_for(area);
        let was = b.pos(before % area);
        fits(search(&mut taken, &a, t, ((was, Heading::North), before % 2 == 0), |_, _| Flow::Continue))?;
        if !taken.take_over_before(&other, t, written.rec(), dist).unwrap() {
            // Refused only where the queues wrapped since.
            let q = written.state.as_ref().unwrap().queue;
            prop_assert!(written.queued[0].len() < q.a_pushed || written.queued[1].len() < q.b_pushed);
            prop_assert!(!taken.is_distance_search_from(&other, t, start.0, start.1));
            return Ok(());
        }
        prop_assert!(taken.is_search_from(&other, t, start.0, start.1));
        let mut n = k;
        let mut went = Vec::new();
        fits(taken.resume(&other, |i, d| {
            went.push((i, d));
            n += 1;
            if n > k + more { Flow::Stop } else { Flow::Continue }
        }))?;
        prop_assert_eq!(&went[..], &all[k..(k + more + 1).min(all.len())]);
        let mut stopped = field_for(area);
        fits(plain_until(&mut stopped, &other, t, start, k + more))?;
        prop_assert_eq!(times(&taken, area), times(&stopped, area));
        let mut again = Written::default();
        prop_assert!(taken.write_down(&other, &mut again));
        let mut want = Written::default();
        prop_assert!(stopped.write_down(&other, &mut want));
        // It may hold fewer of the queues' last entries (none from
        // before the take-over's time), but enough to be taken over whole.
        for (got, all) in again.queued.iter().zip(&want.queued) {
            prop_assert!(all.ends_with(got));
        }
        let mut whole = field_for(area);
        whole.take_over(&other, t, again.rec()).unwrap();
        prop_assert_eq!(times(&whole, area), times(&stopped, area));
        let r0 = rest(&mut whole, &other);
        let (r1, r2) = (rest(&mut taken, &other), rest(&mut stopped, &other));
        prop_assert_eq!(&r1, &r2);
        prop_assert_eq!(&r0, &r2);
        fits(r0)?;
        prop_assert_eq!(times(&taken, area), times(&stopped, area));
        // The next search in the field clears all that was written.
        for f in [&mut taken, &mut stopped] {
            fits(f.compute(&other, t, was, Heading::South, |_, _| Flow::Continue))?;
        }
        prop_assert_eq!(times(&taken, area), times(&stopped, area));
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// A record whose cells were spoilt (any contents, any index), taken
    /// over unchecked on another map and resumed to the end, answers
    /// wrongly perhaps, but nothing panics or loops: what a memo hands back
    /// is input too.
    #[test]
    fn a_spoilt_record_taken_over_panics_nowhere(
        w in 1u16..12, h in 1u16..12, seed in any::<u64>(), known in 1usize..144,
        other in 0usize..144, stop in 0usize..144, jumping in any::<bool>(),
        junk in proptest::collection::vec((any::<u32>(), any::<u32>(), any::<[u8; 4]>(), any::<u32>(), any::<u32>()), 0..64),
    ) {
        let b = Bounds::new(Pos::new(0, 0), w, h);
        let area = b.area();
        let arms = random_arms(b, seed);
        let a = known_prefix(b, &arms, known);
        let other = known_prefix(b, &arms, other);
        let t = Timing { edge: 10, quarter_turn: 5 };
        let start = ((b.pos(0), Heading::East), jumping);
        let mut written = fits(write(&mut field_for(area), &a, t, start, stop))?;
        for (k, &(i, base, off, ring_a, ring_b)) in junk.iter().enumerate() {
            let c = PlanCell { base, off, ring_a, ring_b };
            match written.cells.get_mut(k) {
                Some(slot) if k % 2 == 0 => *slot = (i % (2 * area as u32 + 1), c),
                _ => written.cells.push((i, c)),
            }
        }
        for (k, &(e, ..)) in junk.iter().enumerate() {
            written.queued[k % 2].push(e);
        }
        let mut f = field_for(area);
        f.take_over(&other, t, written.rec()).unwrap();
        let _ = f.resume(&other, |_, _| Flow::Continue);
        let _ = f.dist_at(0);
        // In part, at any time: refused without a queue history.
        let dist = junk.first().map_or(0, |j| j.1 % 2000);
        if matches!(f.take_over_before(&other, t, written.rec(), dist), Ok(true)) {
            let _ = f.resume(&other, |_, _| Flow::Continue);
        }
        let _ = f.dist_at(0);
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
        ((Pos::new(0, 0), Heading::East), false),
        100,
    )
    .unwrap();
    assert_eq!(written.reached.len(), 7);
    assert!(written.state.as_ref().is_some_and(|s| s.ran_out()));
    assert!(reads_same(&map, written.rec()));
    map.visit(Pos::new(6, 0), arms[6], RobotId(0)).unwrap();
    assert!(
        !reads_same(&map, written.rec()),
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
        ((Pos::new(0, 0), Heading::East), false),
        3,
    )
    .unwrap();
    assert!(reads_same(&map, short.rec()));
    let mut f = field_for(b.area());
    f.take_over(&map, t, short.rec()).unwrap();
    let went_on = rest(&mut f, &map).unwrap();
    assert_eq!(went_on.first(), Some(&(4, 40)));
    assert_eq!(
        went_on.last(),
        Some(&(7, 70)),
        "through node 6, visited now"
    );
}

/// A jumping search reaches only the corridor's end, a frontier node, but
/// it read every corridor node on the way: the record holds them, so the
/// frontier node visited shows, and so does a map that does not know the
/// corridor yet.
#[test]
fn a_jumping_search_reads_the_corridors_it_passes() {
    let b = Bounds::new(Pos::new(0, 0), 12, 1);
    let line = |x: i16| {
        let mut bits = 0;
        if x > 0 {
            bits |= 1 << Heading::West.index();
        }
        if x < 11 {
            bits |= 1 << Heading::East.index();
        }
        crate::geometry::Arms::from_bits(bits)
    };
    let t = Timing {
        edge: 10,
        quarter_turn: 5,
    };
    let known = |n: i16| {
        let mut map =
            KnownMap::new(vec![Block::EMPTY; crate::map::blocks_for(b.area())], b).unwrap();
        for x in 0..n {
            map.visit(Pos::new(x, 0), line(x), RobotId(0)).unwrap();
        }
        map
    };
    let map = known(6);
    let start = ((Pos::new(0, 0), Heading::East), true);
    for told in [false, true] {
        let f = &mut field_for(b.area());
        let written = if told {
            write_as_told(f, &map, t, start, 100)
        } else {
            write(f, &map, t, start, 100)
        }
        .unwrap();
        let reached: Vec<u32> = written.reached.iter().map(|r| r.node).collect();
        assert_eq!(reached, vec![0, 6], "the start and the frontier node");
        let read: Vec<u32> = written.read.iter().map(|r| r.0).collect();
        assert_eq!(read, vec![1, 2, 3, 4, 5, 6]);
        assert!(reads_same(&map, written.rec()));
        assert!(!reads_same(&known(7), written.rec()), "node 6 visited");
        assert!(
            !reads_same(&known(4), written.rec()),
            "nodes 4 and 5 not known"
        );
    }
}

/// A field that holds anything but a forward search from a start, on the
/// map it is asked about, writes nothing down.
#[test]
fn only_a_forward_search_on_its_own_map_is_written_down() {
    let b = Bounds::new(Pos::new(0, 0), 6, 6);
    let arms = random_arms(b, 7);
    let map = known_prefix(b, &arms, 20);
    let grown = known_prefix(b, &arms, 21);
    let t = Timing {
        edge: 10,
        quarter_turn: 5,
    };
    let from = (Pos::new(0, 0), Heading::North);
    let mut f = field_for(b.area());
    let mut w = Written::default();
    let goal = map.frontier().next().unwrap();
    f.compute_reverse(&map, t, goal, |_, _, _| Flow::Continue)
        .unwrap();
    assert!(!f.write_down(&map, &mut w));
    f.compute_avoiding(&map, t, from, |_| false, |_, _| Flow::Continue)
        .unwrap();
    assert!(!f.write_down(&map, &mut w));
    assert!(w.state.is_none() && w.cells.is_empty());
    for jumping in [false, true] {
        search(&mut f, &map, t, (from, jumping), |_, _| Flow::Continue).unwrap();
        assert!(!f.write_down(&grown, &mut w), "another map");
        assert!(f.write_down(&map, &mut w));
    }
}

mod rest;
mod runs;
