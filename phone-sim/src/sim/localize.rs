//! The simulator's side of localization: the map window that covers the
//! field in any robot's frame, the check that local starts are adjacent,
//! and the truth that localization results are checked against.

use crate::field::{Field, StartPose};
use core_algo::geometry::{Heading, Pos};
use core_algo::localize::Frame;
use core_algo::map::Bounds;
use std::collections::{BTreeSet, VecDeque};

/// The map window for a team that does not know where it starts: the
/// team frame is robot 0's own frame, so the field may lie anywhere within
/// its largest extent of the origin, in any orientation. The window spans
/// that extent in every direction plus a margin of one node.
pub fn team_window(field: &Field) -> Bounds {
    let b = field.bounds();
    let m = b.width.max(b.height).min(i16::MAX as u16 / 2 - 1) as i16;
    let side = (2 * m + 1) as u16;
    Bounds::new(Pos::new(-m, -m), side, side)
}

/// How a robot starting at `start` has its own frame in the true frame
/// (its start node the origin, its start heading north).
pub fn own_to_true(start: StartPose) -> Frame {
    Frame {
        quarter_turns: start.heading.index(),
        dx: start.pos.x,
        dy: start.pos.y,
    }
}

/// The true frame into the team frame (robot 0's own frame).
pub fn true_to_team(starts: &[StartPose]) -> Frame {
    starts
        .first()
        .map(|s| own_to_true(*s).inverse())
        .unwrap_or(Frame::IDENTITY)
}

/// The frame robot `i` must end localization with: its own frame into the
/// team frame, by the truth.
pub fn expected_frame(starts: &[StartPose], i: usize) -> Option<Frame> {
    let s = starts.get(i)?;
    Some(true_to_team(starts).after(own_to_true(*s)))
}

/// Whether the start nodes form one connected set of neighbours joined by
/// lines: what local localization needs (seed §4.2).
pub fn starts_adjacent(field: &Field, starts: &[StartPose]) -> bool {
    let set: BTreeSet<Pos> = starts.iter().map(|s| s.pos).collect();
    let Some(first) = starts.first().map(|s| s.pos) else {
        return true;
    };
    let mut seen = BTreeSet::from([first]);
    let mut todo = VecDeque::from([first]);
    while let Some(p) = todo.pop_front() {
        let arms = field.nodes().get(&p).copied().unwrap_or_default();
        for h in Heading::ALL.into_iter().filter(|h| arms.has(*h)) {
            if let Some(q) = p.step(h).filter(|q| set.contains(q))
                && seen.insert(q)
            {
                todo.push_back(q);
            }
        }
    }
    seen.len() == set.len()
}

/// `k` distinct start nodes of `field` with random headings, drawn from
/// `seed`: the arbitrary starts global localization is for.
pub fn random_starts(field: &Field, k: usize, seed: u64) -> Vec<StartPose> {
    use rand::seq::SliceRandom;
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let mut nodes: Vec<Pos> = field.nodes().keys().copied().collect();
    nodes.shuffle(&mut rng);
    nodes
        .into_iter()
        .take(k)
        .map(|pos| StartPose {
            pos,
            heading: Heading::from_index(rng.random_range(0..4u8)),
        })
        .collect()
}
