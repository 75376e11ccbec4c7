//! Arbitrary event sequences into one agent: it never panics, and it never
//! commands a move along an arm its own map does not know to exist.
#![no_main]

use core_algo::agent::{Agent, AgentConfig, Command, Event, ManualOrder, PeerNews};
use core_algo::explore::{GreedyClaim, NearestFrontier, Tempo};
use core_algo::geometry::{Arms, Heading, Pos, Turn};
use core_algo::map::{Block, Bounds, KnownMap, blocks_for};
use core_algo::path::{DistField, PlanCell, min_cells};
use core_algo::team::RobotId;
use libfuzzer_sys::fuzz_target;

/// Reads the fuzz input as a little script of events.
struct Script<'a>(&'a [u8]);

impl Script<'_> {
    fn byte(&mut self) -> Option<u8> {
        let (b, rest) = self.0.split_first()?;
        self.0 = rest;
        Some(*b)
    }
    fn pos(&mut self) -> Option<Pos> {
        Some(Pos::new(i16::from(self.byte()? % 12) - 2, i16::from(self.byte()? % 12) - 2))
    }
    fn heading(&mut self) -> Option<Heading> {
        Some(Heading::from_index(self.byte()?))
    }
    fn turn(&mut self) -> Option<Turn> {
        Some(match self.byte()? % 3 {
            0 => Turn::Left,
            1 => Turn::Right,
            _ => Turn::UTurn,
        })
    }
    fn event(&mut self) -> Option<Event> {
        Some(match self.byte()? % 10 {
            0 => Event::Start { pos: self.pos()?, heading: self.heading()? },
            1 | 2 => Event::NodeHit { relative: Arms::from_bits(self.byte()?) },
            3 => Event::Collision,
            4 => Event::Rejected,
            5 => Event::Bumped { toward: self.heading()? },
            6 => {
                let id = RobotId(self.byte()? % 10);
                let news = match self.byte()? % 4 {
                    0 => PeerNews::NodeHit { pos: self.pos()?, heading: self.heading()?, arms: Arms::from_bits(self.byte()?) },
                    1 => PeerNews::Intent { target: if self.byte()? & 1 == 0 { None } else { Some(self.pos()?) } },
                    2 => PeerNews::Start { pos: self.pos()?, heading: self.heading()? },
                    _ => PeerNews::Failed,
                };
                Event::Peer(id, news)
            }
            7 => Event::Manual(match self.byte()? % 4 {
                0 => ManualOrder::Take,
                1 => ManualOrder::Release,
                2 => ManualOrder::Turn(self.turn()?),
                _ => ManualOrder::Move,
            }),
            _ => Event::Tick,
        })
    }
}

fn run<S: core_algo::explore::Strategy<Vec<Block>, Vec<PlanCell>>>(strategy: S, data: &[u8]) {
    let bounds = Bounds::new(Pos::new(-3, -3), 14, 14);
    let map = KnownMap::new(vec![Block::EMPTY; blocks_for(bounds.area())], bounds).expect("map");
    let fields: [DistField<Vec<PlanCell>>; 3] =
        core::array::from_fn(|_| DistField::new(vec![PlanCell::EMPTY; min_cells(bounds.area())]));
    let mut agent = Agent::new(RobotId(1), map, fields, strategy, AgentConfig::default());
    let mut script = Script(data);
    let mut now: u32 = 0;
    while let Some(event) = script.event() {
        now = now.wrapping_add(u32::from(script.byte().unwrap_or(0)) * 97);
        // Where the robot stands and faces when the event arrives: a Move it
        // commands now must leave along an arm its map knows (after taking
        // the event: a node hit teaches the arms first). A Turn in the same
        // batch comes first.
        let (pos, mut heading) = agent.pose();
        let Ok(commands) = agent.handle(now, event) else { continue };
        let known = agent.map().known_arms(pos);
        for c in commands {
            match c {
                Command::Turn(t) => heading = heading.turned(t),
                Command::Move => {
                    assert!(
                        known.is_some_and(|a| a.has(heading)),
                        "move from {pos} towards {heading} without a known arm ({known:?})"
                    );
                }
                _ => {}
            }
        }
    }
}

fuzz_target!(|data: &[u8]| {
    match data.first().map(|b| b % 3) {
        Some(0) => run(NearestFrontier, data.get(1..).unwrap_or(&[])),
        Some(1) => run(GreedyClaim, data.get(1..).unwrap_or(&[])),
        _ => run(Tempo::default(), data.get(1..).unwrap_or(&[])),
    }
});
