use super::*;
use crate::explore::NearestFrontier;
use crate::map::{Bounds, blocks_for};
use crate::path::{PlanError, min_cells};
use crate::timing::Timing;
use std::vec;
use std::vec::Vec as StdVec;

type TestAgent = Agent<StdVec<Block>, StdVec<PlanCell>, NearestFrontier, 1>;

fn agent(id: u8) -> TestAgent {
    let bounds = Bounds::new(Pos::new(-1, -1), 6, 6);
    let map = KnownMap::new(vec![Block::EMPTY; blocks_for(bounds.area())], bounds).unwrap();
    let field = DistField::new(vec![PlanCell::EMPTY; min_cells(bounds.area())]);
    Agent::new(
        RobotId(id),
        map,
        [field],
        NearestFrontier,
        AgentConfig::default(),
    )
}

const N: Heading = Heading::North;
const E: Heading = Heading::East;
const S: Heading = Heading::South;
const W: Heading = Heading::West;

fn arms(hs: &[Heading]) -> Arms {
    hs.iter().fold(Arms::NONE, |a, h| a.with(*h))
}

#[test]
fn start_scan_then_turn_and_move_along_a_known_arm() {
    let mut a = agent(0);
    assert!(
        a.handle(
            0,
            Event::Start {
                pos: Pos::new(0, 0),
                heading: N
            }
        )
        .unwrap()
        .is_empty()
    );
    // The scan sees one arm, to the east: relative to north, that is "right".
    let out = a
        .handle(
            10,
            Event::NodeHit {
                relative: arms(&[E]).to_relative(N),
            },
        )
        .unwrap();
    assert_eq!(
        out[0],
        Command::Report {
            pos: Pos::new(0, 0),
            arms: arms(&[E]),
            heading: N
        }
    );
    assert!(out.contains(&Command::Announce {
        target: Some(Pos::new(1, 0))
    }));
    assert!(out.contains(&Command::Turn(Turn::Right)));
    assert_eq!(out.last(), Some(&Command::Move));
    assert_eq!(a.pose(), (Pos::new(1, 0), E));
}

#[test]
fn nothing_to_explore_means_finished_at_home() {
    let mut a = agent(0);
    a.handle(
        0,
        Event::Start {
            pos: Pos::new(0, 0),
            heading: N,
        },
    )
    .unwrap();
    // A lone dead end: the only frontier is east.
    a.handle(
        1,
        Event::NodeHit {
            relative: arms(&[E]).to_relative(N),
        },
    )
    .unwrap();
    // At (1, 0): arms west and nothing else.
    let out = a
        .handle(
            2,
            Event::NodeHit {
                relative: arms(&[W]).to_relative(E),
            },
        )
        .unwrap();
    assert!(out.contains(&Command::Announce { target: None }));
    assert_eq!(a.mode(), Mode::Return);
    assert_eq!(out.last(), Some(&Command::Move));
    let out = a
        .handle(
            3,
            Event::NodeHit {
                relative: arms(&[E]).to_relative(W),
            },
        )
        .unwrap();
    assert_eq!(out.last(), Some(&Command::Finished));
    assert_eq!(a.mode(), Mode::Finished);
}

#[test]
fn collision_backs_off_then_plans_again() {
    let mut a = agent(3);
    a.handle(
        0,
        Event::Start {
            pos: Pos::new(0, 0),
            heading: E,
        },
    )
    .unwrap();
    a.handle(
        1,
        Event::NodeHit {
            relative: arms(&[E, W]).to_relative(E),
        },
    )
    .unwrap();
    assert_eq!(a.pose().0, Pos::new(1, 0));
    // Met someone: back on (0, 0), facing west, and the team hears so
    // (its shares are planned from where we stand and face).
    let out = a.handle(100, Event::Collision).unwrap();
    assert_eq!(a.pose(), (Pos::new(0, 0), W));
    assert!(
        out.iter()
            .all(|c| !matches!(c, Command::Move | Command::Turn(_))),
        "{out:?}"
    );
    assert!(out.iter().any(|c| matches!(
        c,
        Command::Report {
            pos,
            heading: W,
            ..
        } if *pos == Pos::new(0, 0)
    )));
    assert!(a.is_standing());
    // Nothing happens before the back-off ends...
    assert!(!a.handle(101, Event::Tick).unwrap().contains(&Command::Move));
    // ...then it plans again.
    let out = a.handle(100 + 10_000, Event::Tick).unwrap();
    assert!(out.contains(&Command::Move), "{out:?}");
}

#[test]
fn manual_moves_only_along_known_arms() {
    let mut a = agent(0);
    a.handle(
        0,
        Event::Start {
            pos: Pos::new(0, 0),
            heading: N,
        },
    )
    .unwrap();
    a.handle(
        1,
        Event::NodeHit {
            relative: arms(&[E, S]).to_relative(N),
        },
    )
    .unwrap();
    a.handle(2, Event::Collision).unwrap();
    a.handle(3, Event::Manual(ManualOrder::Take)).unwrap();
    assert_eq!(a.mode(), Mode::Manual);
    let (pos, heading) = a.pose();
    assert_eq!(pos, Pos::new(0, 0));
    // Face north, where there is no arm: the move is refused.
    if let Some(t) = heading.turn_to(N) {
        a.handle(4, Event::Manual(ManualOrder::Turn(t))).unwrap();
    }
    assert_eq!(
        a.handle(5, Event::Manual(ManualOrder::Move)),
        Err(AgentError::Unexpected)
    );
    a.handle(6, Event::Manual(ManualOrder::Turn(Turn::Right)))
        .unwrap();
    assert_eq!(
        a.handle(7, Event::Manual(ManualOrder::Move))
            .unwrap()
            .last(),
        Some(&Command::Move)
    );
    // Handing back explores again once the robot stands on a node.
    a.handle(
        8,
        Event::NodeHit {
            relative: arms(&[W]).to_relative(E),
        },
    )
    .unwrap();
    a.handle(9, Event::Manual(ManualOrder::Release)).unwrap();
    assert_ne!(a.mode(), Mode::Manual);
}

#[test]
fn silent_peers_count_as_failed_and_free_their_target() {
    let mut a = agent(0);
    a.handle(
        0,
        Event::Start {
            pos: Pos::new(0, 0),
            heading: N,
        },
    )
    .unwrap();
    a.handle(
        0,
        Event::Peer(
            RobotId(1),
            PeerNews::Intent {
                target: Some(Pos::new(2, 2)),
            },
        ),
    )
    .unwrap();
    assert_eq!(a.peers[1].target, Some(Pos::new(2, 2)));
    a.handle(40_000, Event::Tick).unwrap();
    assert!(a.peers[1].failed);
    assert_eq!(a.peers[1].target, None);
}

#[test]
fn peer_reports_grow_the_map_and_conflicts_are_ignored() {
    let mut a = agent(0);
    a.handle(
        0,
        Event::Start {
            pos: Pos::new(0, 0),
            heading: N,
        },
    )
    .unwrap();
    let news = PeerNews::NodeHit {
        pos: Pos::new(3, 3),
        heading: N,
        arms: arms(&[S]),
    };
    a.handle(1, Event::Peer(RobotId(2), news)).unwrap();
    assert!(a.map().is_visited(Pos::new(3, 3)));
    let lie = PeerNews::NodeHit {
        pos: Pos::new(3, 3),
        heading: N,
        arms: arms(&[E]),
    };
    a.handle(2, Event::Peer(RobotId(2), lie)).unwrap();
    assert_eq!(a.map().known_arms(Pos::new(3, 3)), Some(arms(&[S])));
    // Our own id and ids beyond the team are refused.
    assert!(a.handle(3, Event::Peer(RobotId(0), news)).is_err());
    assert!(a.handle(3, Event::Peer(RobotId(200), news)).is_err());
}

/// The broadcasts among `out`, as the phone would relay them.
fn said(out: &Commands) -> StdVec<crate::localize::Localize> {
    out.iter()
        .filter_map(|c| match c {
            Command::Localize(l) => Some(*l),
            _ => None,
        })
        .collect()
}

#[test]
fn two_robots_localize_by_one_contact_then_explore_in_robot_0s_frame() {
    use crate::localize::{Localize, LocalizeMethod};
    // Two nodes joined east–west; robot 0 on the west one facing north,
    // robot 1 on the east one facing east (its own north is true east).
    let (mut a0, mut a1) = (agent(0), agent(1));
    let start = Event::StartLocalize {
        method: LocalizeMethod::Local,
        team: 2,
    };
    a0.handle(0, start).unwrap();
    a1.handle(0, start).unwrap();
    assert_eq!(a0.mode(), Mode::Localize);
    let r0 = a0
        .handle(
            10,
            Event::NodeHit {
                relative: arms(&[E]).to_relative(N),
            },
        )
        .unwrap();
    let r1 = a1
        .handle(
            10,
            Event::NodeHit {
                relative: arms(&[W]).to_relative(E),
            },
        )
        .unwrap();
    assert_eq!(said(&r0), [Localize::Ready]);
    assert!(
        a1.handle(
            20,
            Event::Peer(RobotId(0), PeerNews::Localize(Localize::Ready))
        )
        .unwrap()
        .is_empty()
    );
    // Everyone ready: robot 0's turn, its one run goes east.
    let go = a0
        .handle(
            20,
            Event::Peer(RobotId(1), PeerNews::Localize(said(&r1)[0])),
        )
        .unwrap();
    assert_eq!(go.as_slice(), [Command::Turn(Turn::Right), Command::Move]);
    // Robot 1 stands there: it sees robot 0 come from behind (its own
    // south), robot 0 is turned back.
    let passive = a1.handle(30, Event::Bumped { toward: S }).unwrap();
    let active = a0.handle(40, Event::Collision).unwrap();
    let [Localize::Bumped { by, .. }] = said(&passive)[..] else {
        panic!("{passive:?}");
    };
    assert_eq!(by, RobotId(0));
    assert!(matches!(said(&active)[..], [Localize::Collision { .. }]));
    // Each hears the other's half: both join robot 0's frame and explore.
    let out0 = a0
        .handle(
            50,
            Event::Peer(RobotId(1), PeerNews::Localize(said(&passive)[0])),
        )
        .unwrap();
    let out1 = a1
        .handle(
            50,
            Event::Peer(RobotId(0), PeerNews::Localize(said(&active)[0])),
        )
        .unwrap();
    assert!(said(&out0).contains(&Localize::Finished));
    assert!(said(&out1).contains(&Localize::Finished));
    assert_eq!((a0.mode(), a1.mode()), (Mode::Explore, Mode::Explore));
    assert_eq!(a0.home(), Pos::new(0, 0));
    assert_eq!(a1.home(), Pos::new(1, 0));
    // Robot 1 reported its home in the team frame, arms turned into it.
    assert!(out1.contains(&Command::Report {
        pos: Pos::new(1, 0),
        arms: arms(&[W]),
        heading: E
    }));
    // Robot 0 learns robot 1's node from that report: its map is done.
    let (pos, heading) = (Pos::new(1, 0), E);
    a0.handle(
        60,
        Event::Peer(
            RobotId(1),
            PeerNews::NodeHit {
                pos,
                heading,
                arms: arms(&[W]),
            },
        ),
    )
    .unwrap();
    assert!(a0.map().is_complete());
}

/// A lone robot in a two-node dead end turns round and drives home (the
/// firmware's QEMU end-to-end scenario).
#[test]
fn a_lone_robot_comes_home_from_a_dead_end() {
    let bounds = Bounds::new(Pos::new(-16, -16), 32, 32);
    let map = KnownMap::new(vec![Block::EMPTY; blocks_for(bounds.area())], bounds).unwrap();
    let field = DistField::new(vec![PlanCell::EMPTY; min_cells(bounds.area())]);
    let mut a: Agent<_, _, crate::explore::MinPos, 1> = Agent::new(
        RobotId(0),
        map,
        [field],
        crate::explore::MinPos,
        AgentConfig::default(),
    );
    a.handle(
        0,
        Event::Start {
            pos: Pos::new(0, 0),
            heading: N,
        },
    )
    .unwrap();
    let out = a
        .handle(
            10,
            Event::NodeHit {
                relative: arms(&[N]).to_relative(N),
            },
        )
        .unwrap();
    assert!(out.contains(&Command::Move), "{out:?}");
    let out = a
        .handle(
            20,
            Event::NodeHit {
                relative: arms(&[S]).to_relative(N),
            },
        )
        .unwrap();
    assert!(out.contains(&Command::Turn(Turn::UTurn)), "{out:?}");
}

/// A strategy that always says "wait": the worst case of team mates whose
/// views of the team differ, each leaving the work to another.
struct AlwaysWait;

impl<M, F> Strategy<M, F> for AlwaysWait
where
    M: AsRef<[Block]> + AsMut<[Block]>,
    F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
{
    fn name(&self) -> &'static str {
        "always-wait"
    }

    fn decide(
        &mut self,
        _ctx: &Context<'_, M>,
        _fields: &mut [DistField<F>],
    ) -> Result<Decision, PlanError> {
        Ok(Decision {
            goal: Goal::Wait,
            next: None,
        })
    }
}

#[test]
fn a_robot_told_to_wait_while_nothing_changes_goes_exploring_itself() {
    let bounds = Bounds::new(Pos::new(-1, -1), 6, 6);
    let map = KnownMap::new(vec![Block::EMPTY; blocks_for(bounds.area())], bounds).unwrap();
    let field = DistField::new(vec![PlanCell::EMPTY; min_cells(bounds.area())]);
    let mut a: Agent<StdVec<Block>, StdVec<PlanCell>, AlwaysWait, 1> =
        Agent::new(RobotId(0), map, [field], AlwaysWait, AgentConfig::default());
    a.handle(
        0,
        Event::Start {
            pos: Pos::new(0, 0),
            heading: N,
        },
    )
    .unwrap();
    // At home, with an unexplored arm east.
    let out = a
        .handle(
            10,
            Event::NodeHit {
                relative: arms(&[E]).to_relative(N),
            },
        )
        .unwrap();
    assert!(!out.contains(&Command::Move), "{out:?}");
    let edge_ms = Timing::DEFAULT.edge * TICK_MS;
    let mut moved_at = None;
    for t in (20..edge_ms * 60).step_by(100) {
        if a.handle(t, Event::Tick).unwrap().contains(&Command::Move) {
            moved_at = Some(t);
            break;
        }
    }
    let t = moved_at.expect("it never went");
    // Not before its patience ran out, and soon after.
    assert!(t > edge_ms * decide::IDLE_PATIENCE_EDGES, "went at {t} ms");
    assert!(
        t < edge_ms * (decide::IDLE_PATIENCE_EDGES + 3),
        "went at {t} ms"
    );
    assert_eq!(a.pose(), (Pos::new(1, 0), E));
}
