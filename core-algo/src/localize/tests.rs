//! The localizer on a toy world: bodies that act at once, a message bus
//! that delivers in order, and the truth to check the frames against.

use super::*;
use proptest::prelude::*;
use std::collections::{BTreeMap, BTreeSet, VecDeque};
use std::vec::Vec as StdVec;

type Field = BTreeMap<Pos, Arms>;

/// A grid of `w` × `h` nodes without `holes`, lines between every two
/// neighbours, cut to the component of the first node left.
fn grid(w: i16, h: i16, holes: &[Pos]) -> Field {
    let nodes: BTreeSet<Pos> = (0..w)
        .flat_map(|x| (0..h).map(move |y| Pos::new(x, y)))
        .filter(|p| !holes.contains(p))
        .collect();
    let Some(&first) = nodes.iter().next() else {
        return Field::new();
    };
    let mut seen = BTreeSet::from([first]);
    let mut todo = VecDeque::from([first]);
    while let Some(p) = todo.pop_front() {
        for d in Heading::ALL {
            if let Some(q) = p.step(d).filter(|q| nodes.contains(q))
                && seen.insert(q)
            {
                todo.push_back(q);
            }
        }
    }
    seen.iter()
        .map(|&p| {
            let arms = Heading::ALL
                .into_iter()
                .filter(|d| p.step(*d).is_some_and(|q| seen.contains(&q)))
                .fold(Arms::NONE, |a, d| a.with(d));
            (p, arms)
        })
        .collect()
}

/// How robot `i`'s own frame lies in the true frame.
fn truth(start: (Pos, Heading)) -> Frame {
    Frame {
        quarter_turns: start.1.index(),
        dx: start.0.x,
        dy: start.0.y,
    }
}

enum Input {
    Node(Arms),
    Collision,
    Bumped(Heading),
    News(RobotId, Localize),
}

struct World {
    field: Field,
    starts: StdVec<(Pos, Heading)>,
    bodies: StdVec<(Pos, Heading)>,
    robots: StdVec<Localizer>,
    queue: VecDeque<(usize, Input)>,
    moves: u32,
}

impl World {
    fn new(field: Field, starts: &[(Pos, Heading)], method: LocalizeMethod) -> World {
        let n = starts.len();
        let mut robots: StdVec<Localizer> =
            (0..n).map(|i| Localizer::new(RobotId(i as u8))).collect();
        for r in &mut robots {
            r.start(method, n as u8, 100_000);
        }
        let mut w = World {
            field,
            starts: starts.to_vec(),
            bodies: starts.to_vec(),
            robots,
            queue: VecDeque::new(),
            moves: 0,
        };
        for i in 0..n {
            let arms = w.own_arms(i);
            let mut out = Steps::new();
            w.robots[i].on_scanned(arms, &mut out);
            w.carry_out(i, out);
        }
        w
    }

    fn own_arms(&self, i: usize) -> Arms {
        let arms = self
            .field
            .get(&self.bodies[i].0)
            .copied()
            .unwrap_or_default();
        arms.rotated_cw(4 - self.starts[i].1.index())
    }

    fn own_heading(&self, i: usize, true_heading: Heading) -> Heading {
        Heading::from_index(true_heading.index() + 4 - self.starts[i].1.index())
    }

    fn carry_out(&mut self, i: usize, out: Steps) {
        for s in out {
            match s {
                Step::Turn(t) => self.bodies[i].1 = self.bodies[i].1.turned(t),
                Step::Move => {
                    self.moves += 1;
                    let (p, h) = self.bodies[i];
                    let arms = self.field.get(&p).copied().unwrap_or_default();
                    assert!(arms.has(h), "robot {i} ordered off the line at {p}");
                    let q = p.step(h).unwrap();
                    if let Some(j) =
                        (0..self.bodies.len()).find(|&j| j != i && self.bodies[j].0 == q)
                    {
                        self.bodies[i].1 = h.opposite();
                        let toward = self.own_heading(j, h.opposite());
                        self.queue.push_back((j, Input::Bumped(toward)));
                        self.queue.push_back((i, Input::Collision));
                    } else {
                        self.bodies[i].0 = q;
                        self.queue.push_back((i, Input::Node(self.own_arms(i))));
                    }
                }
                Step::Say(news) => {
                    for j in 0..self.robots.len() {
                        if j != i {
                            self.queue
                                .push_back((j, Input::News(RobotId(i as u8), news)));
                        }
                    }
                }
            }
        }
    }

    fn run(&mut self) {
        let mut events = 0;
        while let Some((i, input)) = self.queue.pop_front() {
            events += 1;
            assert!(events < 2_000_000, "no end");
            let mut out = Steps::new();
            let r = &mut self.robots[i];
            match input {
                Input::Node(a) => r.on_node(a, &mut out).unwrap(),
                Input::Collision => r.on_collision(&mut out).unwrap(),
                Input::Bumped(t) => r.on_bumped(t, &mut out).unwrap(),
                Input::News(from, n) => r.on_news(from, n, &mut out),
            }
            self.carry_out(i, out);
        }
    }

    /// Every robot done with the true relative frame, or the failure.
    fn check(&self) -> Result<(), Failure> {
        let to_true0 = truth(self.starts[0]);
        for (i, r) in self.robots.iter().enumerate() {
            match r.progress() {
                Progress::Done(f) => {
                    let want = to_true0.inverse().after(truth(self.starts[i]));
                    assert_eq!(f, want, "robot {i}'s frame");
                    // And the localizer's pose is the body's.
                    let pose = r.pose();
                    let true_now = truth(self.starts[i]).pose(pose);
                    assert_eq!(
                        (true_now.pos, true_now.heading),
                        self.bodies[i],
                        "robot {i}'s pose"
                    );
                }
                Progress::Failed(why) => return Err(why),
                Progress::Running => panic!("robot {i} still running"),
            }
        }
        Ok(())
    }
}

#[test]
fn frames_compose_and_invert() {
    let a = Frame {
        quarter_turns: 1,
        dx: 3,
        dy: -2,
    };
    let b = Frame {
        quarter_turns: 3,
        dx: -1,
        dy: 5,
    };
    let p = Pos::new(2, 7);
    assert_eq!(a.after(b).pos(p), a.pos(b.pos(p)));
    assert_eq!(a.inverse().pos(a.pos(p)), p);
    assert_eq!(a.after(a.inverse()), Frame::IDENTITY);
    assert_eq!(a.heading(Heading::North), Heading::East);
    let theirs = Pose {
        pos: Pos::new(1, 1),
        heading: Heading::North,
    };
    let seen = Pose {
        pos: Pos::new(0, -1),
        heading: Heading::West,
    };
    assert_eq!(Frame::from_contact(theirs, seen).pose(theirs), seen);
}

#[test]
fn walk_counts_minus_four_round_the_outer_border() {
    // Around a 2 × 2 block clockwise from the bottom-left, north first.
    let field = grid(2, 2, &[]);
    let (mut at, mut h, mut sum) = (Pos::new(0, 0), Heading::North, 0i16);
    for _ in 0..4 {
        at = at.step(h).unwrap();
        let (d, t) = left_first(h, field[&at]).unwrap();
        sum += i16::from(t);
        h = d;
    }
    assert_eq!(at, Pos::new(0, 0));
    assert_eq!(sum, -4);
    // The same cell from inside the 3 × 3 grid's middle is an inner face.
    let field = grid(3, 3, &[]);
    let (mut at, mut h, mut sum) = (Pos::new(1, 1), Heading::East, 0i16);
    for _ in 0..4 {
        at = at.step(h).unwrap();
        let (d, t) = left_first(h, field[&at]).unwrap();
        sum += i16::from(t);
        h = d;
    }
    assert_eq!((at, sum), (Pos::new(1, 1), 4));
}

#[test]
fn team_frames_join_in_the_lowest_ids_frame() {
    let mut t = TeamFrames::new(3);
    assert_eq!(t.groups(), 3);
    let pose = |x, y, h| Pose {
        pos: Pos::new(x, y),
        heading: h,
    };
    // 2 touched 1, then 1 touched 0.
    assert!(t.join(Contact {
        active: RobotId(2),
        theirs: pose(0, 0, Heading::North),
        passive: RobotId(1),
        seen: pose(0, 1, Heading::South),
    }));
    assert_eq!(t.root(RobotId(2)), RobotId(1));
    assert!(t.join(Contact {
        active: RobotId(1),
        theirs: pose(0, 0, Heading::East),
        passive: RobotId(0),
        seen: pose(-1, 0, Heading::East),
    }));
    assert!(t.joined());
    // Robot 1's start is west of 0's, same heading; robot 2's start lies
    // one edge north of 1's in 1's frame, facing south.
    assert_eq!(t.to_root(RobotId(1)).pos(ORIGIN), Pos::new(-1, 0));
    assert_eq!(t.to_root(RobotId(2)).pos(ORIGIN), Pos::new(-1, 1));
    assert_eq!(
        t.to_root(RobotId(2)).heading(Heading::North),
        Heading::South
    );
    // A contact inside one group teaches nothing.
    assert!(!t.join(Contact {
        active: RobotId(0),
        theirs: pose(0, 0, Heading::West),
        passive: RobotId(1),
        seen: pose(1, 0, Heading::West),
    }));
}

#[test]
fn local_places_a_row_of_three() {
    let field = grid(4, 3, &[]);
    let starts = [
        (Pos::new(1, 1), Heading::North),
        (Pos::new(2, 1), Heading::West),
        (Pos::new(2, 2), Heading::South),
    ];
    let mut w = World::new(field, &starts, LocalizeMethod::Local);
    w.run();
    assert_eq!(w.check(), Ok(()));
    // Everyone back on its start.
    assert_eq!(
        w.bodies.iter().map(|b| b.0).collect::<StdVec<_>>(),
        starts.map(|s| s.0)
    );
}

#[test]
fn local_reports_starts_that_are_not_adjacent() {
    let field = grid(4, 4, &[]);
    let starts = [
        (Pos::new(0, 0), Heading::North),
        (Pos::new(3, 3), Heading::North),
    ];
    let mut w = World::new(field, &starts, LocalizeMethod::Local);
    w.run();
    assert_eq!(w.check(), Err(Failure::NotAdjacent));
}

#[test]
fn global_finds_robots_inside_and_round_a_hole() {
    // A 6 × 6 grid with a 2 × 2 hole; one robot starts right under the
    // hole, so its first trace goes round the hole (+4) before it climbs.
    let holes = [
        Pos::new(2, 2),
        Pos::new(3, 2),
        Pos::new(2, 3),
        Pos::new(3, 3),
    ];
    let field = grid(6, 6, &holes);
    let starts = [
        (Pos::new(2, 1), Heading::North),
        (Pos::new(4, 4), Heading::East),
        (Pos::new(0, 0), Heading::South),
    ];
    let mut w = World::new(field, &starts, LocalizeMethod::Global);
    w.run();
    assert_eq!(w.check(), Ok(()));
}

#[test]
fn a_single_robot_is_its_own_team() {
    let mut w = World::new(
        grid(3, 3, &[]),
        &[(Pos::new(1, 1), Heading::West)],
        LocalizeMethod::Global,
    );
    w.run();
    assert_eq!(w.check(), Ok(()));
    assert_eq!(w.moves, 0);
}

fn heading() -> impl Strategy<Value = Heading> {
    (0u8..4).prop_map(Heading::from_index)
}

/// A random field (a grid with random holes) and random distinct starts.
fn scene() -> impl Strategy<Value = (Field, StdVec<(Pos, Heading)>)> {
    (
        3i16..9,
        3i16..9,
        prop::collection::vec((0i16..9, 0i16..9), 0..12),
        2usize..=6,
    )
        .prop_flat_map(|(w, h, holes, n)| {
            let holes: StdVec<Pos> = holes.into_iter().map(|(x, y)| Pos::new(x, y)).collect();
            let field = grid(w, h, &holes);
            let nodes: StdVec<Pos> = field.keys().copied().collect();
            let n = n.min(nodes.len());
            (
                Just(field),
                prop::sample::subsequence(nodes, n).prop_shuffle(),
                prop::collection::vec(heading(), n),
            )
        })
        .prop_map(|(field, starts, headings)| (field, starts.into_iter().zip(headings).collect()))
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 200,
        rng_seed: prop::test_runner::RngSeed::Fixed(0x10CA_112E),
        ..ProptestConfig::default()
    })]

    /// Global localization from any starts ends: either every robot holds
    /// the true relative frame, or every robot says the team never met —
    /// never a wrong frame, never a hang.
    #[test]
    fn global_ends_right_or_says_so((field, starts) in scene()) {
        let mut w = World::new(field, &starts, LocalizeMethod::Global);
        w.run();
        match w.check() {
            Ok(()) => {}
            Err(why) => prop_assert_eq!(why, Failure::NeverMet),
        }
    }

    /// Local localization from any connected set of adjacent starts places
    /// every robot, back on its start.
    #[test]
    fn local_places_adjacent_starts((field, seeds) in scene(), n in 2usize..=6) {
        // Grow a connected set of starts from the first random start.
        let mut starts = StdVec::from([seeds[0]]);
        let mut k = 0;
        while starts.len() < n && k < starts.len() {
            let (p, _) = starts[k];
            for d in field[&p].iter() {
                let q = p.step(d).unwrap();
                if starts.len() < n && !starts.iter().any(|s| s.0 == q) {
                    starts.push((q, Heading::from_index(starts.len() as u8 * 3 + d.index())));
                }
            }
            k += 1;
        }
        let mut w = World::new(field, &starts, LocalizeMethod::Local);
        w.run();
        prop_assert_eq!(w.check(), Ok(()));
        prop_assert!(w.bodies.iter().zip(&starts).all(|(b, s)| b.0 == s.0));
    }
}
