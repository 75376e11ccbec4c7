use super::*;
use proptest::prelude::*;

/// An open `w` × `h` grid: every node has every arm that stays inside.
fn open_grid(w: i16, h: i16) -> BTreeMap<Pos, Arms> {
    let mut truth = BTreeMap::new();
    for x in 0..w {
        for y in 0..h {
            let p = Pos::new(x, y);
            let arms = Heading::ALL
                .into_iter()
                .filter(|&d| {
                    p.step(d)
                        .is_some_and(|q| (0..w).contains(&q.x) && (0..h).contains(&q.y))
                })
                .fold(Arms::default(), Arms::with);
            truth.insert(p, arms);
        }
    }
    truth
}

fn edge_ms() -> u32 {
    Timing::DEFAULT.edge * TICK_MS
}

/// Runs every action to its end and returns the reports.
fn run_out(bodies: &mut Bodies) -> Vec<(RobotId, Report)> {
    let mut reports = Vec::new();
    while let Some(t) = bodies.next_event() {
        bodies.advance(t, &mut reports);
    }
    reports
}

/// No two living bodies hold one node, and none stands on another's node.
fn assert_one_body_per_node(bodies: &Bodies) {
    let held: Vec<Pos> = bodies.bodies().iter().filter_map(Body::held).collect();
    let mut unique = held.clone();
    unique.sort();
    unique.dedup();
    assert_eq!(
        unique.len(),
        held.len(),
        "two bodies hold one node: {held:?}"
    );
}

#[test]
fn a_free_edge_is_driven_to_its_end() {
    let mut b = Bodies::new(
        open_grid(3, 1),
        Timing::DEFAULT,
        &[(Pos::new(0, 0), Heading::East)],
    );
    let mut reports = Vec::new();
    b.order(RobotId(0), Order::Move, 0, &mut reports);
    assert_eq!(
        b.next_event(),
        Some(edge_ms() / 2),
        "the middle is an event"
    );
    reports.extend(run_out(&mut b));
    assert_eq!(b.bodies()[0].pos, Pos::new(1, 0));
    assert_eq!(b.bodies()[0].stats.edges, 1);
    assert!(matches!(
        reports.as_slice(),
        [(RobotId(0), Report::NodeHit { .. })]
    ));
}

#[test]
fn a_body_turns_back_at_the_middle_when_the_node_ahead_is_taken() {
    let starts = [
        (Pos::new(0, 0), Heading::East),
        (Pos::new(1, 0), Heading::North),
    ];
    let mut b = Bodies::new(open_grid(3, 1), Timing::DEFAULT, &starts);
    let mut reports = Vec::new();
    b.order(RobotId(0), Order::Move, 0, &mut reports);
    let mut all = run_out(&mut b);
    all.sort_by_key(|(id, _)| id.0);
    let e = edge_ms();
    assert_eq!(b.bodies()[0].pos, Pos::new(0, 0));
    assert_eq!(b.bodies()[0].heading, Heading::West, "it drove back");
    assert_eq!(b.bodies()[0].stats.collisions, 1);
    assert_eq!(b.bodies()[0].stats.edges, 0);
    // Robot 1 faces north; robot 0 comes from the west: its left.
    assert_eq!(
        all,
        vec![
            (RobotId(0), Report::Collision),
            (
                RobotId(1),
                Report::Bumped {
                    side: Heading::West
                }
            )
        ]
    );
    // Half an edge out, half an edge back.
    let mut b = Bodies::new(open_grid(3, 1), Timing::DEFAULT, &starts);
    b.order(RobotId(0), Order::Move, 0, &mut reports);
    b.advance(e / 2, &mut reports);
    assert_eq!(b.next_event(), Some(e / 2 * 2));
}

#[test]
fn head_on_bodies_both_turn_back() {
    let starts = [
        (Pos::new(0, 0), Heading::East),
        (Pos::new(1, 0), Heading::West),
    ];
    let mut b = Bodies::new(open_grid(2, 1), Timing::DEFAULT, &starts);
    let mut reports = Vec::new();
    b.order(RobotId(0), Order::Move, 0, &mut reports);
    b.order(RobotId(1), Order::Move, 100, &mut reports);
    reports.extend(run_out(&mut b));
    assert_eq!(b.bodies()[0].pos, Pos::new(0, 0));
    assert_eq!(b.bodies()[1].pos, Pos::new(1, 0));
    let collisions = reports
        .iter()
        .filter(|(_, r)| *r == Report::Collision)
        .count();
    assert_eq!(collisions, 2);
}

#[test]
fn a_body_that_turns_back_finds_its_node_free() {
    // 0 drives to 1's node just after 1 leaves it for a node that 2 holds.
    // Deciding on arrival used to put 0 and 1 on one node.
    let starts = [
        (Pos::new(0, 0), Heading::East),
        (Pos::new(1, 0), Heading::East),
        (Pos::new(2, 0), Heading::North),
    ];
    let mut b = Bodies::new(open_grid(3, 1), Timing::DEFAULT, &starts);
    let mut reports = Vec::new();
    b.order(RobotId(1), Order::Move, 0, &mut reports);
    b.order(RobotId(0), Order::Move, 10, &mut reports);
    while let Some(t) = b.next_event() {
        b.advance(t, &mut reports);
        assert_one_body_per_node(&b);
    }
    let pos: Vec<Pos> = b.bodies().iter().map(|x| x.pos).collect();
    assert_eq!(pos, vec![Pos::new(0, 0), Pos::new(1, 0), Pos::new(2, 0)]);
    assert_eq!(b.bodies()[0].stats.collisions, 1);
    assert_eq!(b.bodies()[1].stats.collisions, 1);
}

#[test]
fn a_follower_that_leaves_after_its_leader_is_not_stopped() {
    let starts = [
        (Pos::new(0, 0), Heading::East),
        (Pos::new(1, 0), Heading::East),
    ];
    let mut b = Bodies::new(open_grid(3, 1), Timing::DEFAULT, &starts);
    let mut reports = Vec::new();
    b.order(RobotId(1), Order::Move, 0, &mut reports);
    b.order(RobotId(0), Order::Move, 10, &mut reports);
    reports.extend(run_out(&mut b));
    assert_eq!(b.bodies()[0].pos, Pos::new(1, 0));
    assert_eq!(b.bodies()[1].pos, Pos::new(2, 0));
    assert!(
        reports
            .iter()
            .all(|(_, r)| matches!(r, Report::NodeHit { .. }))
    );
}

#[test]
fn a_returning_body_is_drawn_on_its_edge() {
    let starts = [
        (Pos::new(0, 0), Heading::East),
        (Pos::new(1, 0), Heading::North),
    ];
    let mut b = Bodies::new(open_grid(2, 1), Timing::DEFAULT, &starts);
    let mut reports = Vec::new();
    b.order(RobotId(0), Order::Move, 0, &mut reports);
    let e = edge_ms();
    b.advance(e / 2, &mut reports);
    let (from, to, f) = b.bodies()[0].between(e / 2).expect("on the edge");
    assert_eq!((from, to), (Pos::new(0, 0), Pos::new(1, 0)));
    assert!((f - 0.5).abs() < 0.01, "{f}");
    let (_, _, f) = b.bodies()[0].between(e * 3 / 4).expect("on the edge");
    assert!((f - 0.25).abs() < 0.01, "{f}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Random orders for random bodies on an open grid: at every event no
    /// two bodies hold one node, and every body ends on a node of its own.
    #[test]
    fn no_two_bodies_ever_hold_one_node(
        starts in proptest::sample::subsequence((0..16u8).collect::<Vec<_>>(), 2..=6),
        orders in proptest::collection::vec((0..6usize, 0..4u8, 0..400u32), 1..120),
    ) {
        let starts: Vec<(Pos, Heading)> = starts
            .iter()
            .map(|&c| (Pos::new(i16::from(c % 4), i16::from(c / 4)), Heading::from_index(c)))
            .collect();
        let mut b = Bodies::new(open_grid(4, 4), Timing::DEFAULT, &starts);
        let mut reports = Vec::new();
        let mut now = 0u32;
        for (who, what, wait) in orders {
            let id = RobotId((who % starts.len()) as u8);
            let order = match what {
                0 => Order::Turn(Turn::Left),
                1 => Order::Turn(Turn::Right),
                _ => Order::Move,
            };
            b.order(id, order, now, &mut reports);
            now += wait * 10;
            while let Some(t) = b.next_event().filter(|&t| t <= now) {
                b.advance(t, &mut reports);
                assert_one_body_per_node(&b);
            }
        }
        run_out(&mut b);
        assert_one_body_per_node(&b);
        let mut pos: Vec<Pos> = b.bodies().iter().map(|x| x.pos).collect();
        pos.sort();
        pos.dedup();
        prop_assert_eq!(pos.len(), starts.len());
    }
}
