//! Where a robot standing in a corridor leaves it: see [`CorridorExits`].

use super::corridor::other_arm;
use super::{DistField, MAX_DIST, PlanCell, arms_at, neighbour_index, searchable};
use crate::geometry::Heading;
use crate::map::{Block, KnownMap};
use crate::timing::{Ticks, Timing};

/// The states outside corridors through which a robot at a pose leaves
/// for the rest of the known graph, each with the time it takes to get
/// there. On a node with two known arms (a corridor node) the robot turns
/// to one of them and drives on to the corridor's end: a node with other
/// than two arms (a junction, a dead end, a frontier node). Anywhere else
/// its own pose is its one exit, at no cost.
///
/// Why: a jumping reverse search ([`DistField::compute_reverse_jumping`])
/// settles no corridor state, yet robots stand in corridors most of the
/// time on a maze. No cheapest way turns back inside a corridor (out and
/// back costs more than a U-turn where the robot stands), so a robot's
/// time to the goal is the cheapest of its exits' times plus theirs
/// ([`CorridorExits::time_in`]). On any other node this is its own state.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CorridorExits {
    /// (node, heading, time to get there); only the first `len` count.
    exits: [(usize, Heading, Ticks); 2],
    len: u8,
}

impl CorridorExits {
    /// No exit: a robot that stands nowhere in the window.
    pub const NONE: CorridorExits = CorridorExits {
        exits: [(0, Heading::North, 0); 2],
        len: 0,
    };

    /// The exits of a robot on node `v` (storage index) facing `h`, with
    /// `timing`'s moves (as a search counts them).
    pub fn of<M: AsRef<[Block]> + AsMut<[Block]>>(
        map: &KnownMap<M>,
        timing: Timing,
        v: usize,
        h: Heading,
    ) -> CorridorExits {
        let mut out = CorridorExits::NONE;
        let own = CorridorExits {
            exits: [(v, h, 0); 2],
            len: 1,
        };
        let Some(arms) = arms_at(map, v).filter(|a| a.bits().count_ones() == 2) else {
            return own;
        };
        let t = searchable(timing);
        let bounds = map.bounds();
        for a in arms.iter() {
            let turns = Timing::quarter_turns_between(h.index(), a.index());
            let mut key = t.turn(turns) + t.edge;
            let (mut cur, mut hd) = (neighbour_index(bounds, v, a), usize::from(a.index()));
            // The walk of `corridor::walk`, from a robot's own node; it
            // comes back to `v` only round a loop of corridor nodes, which
            // leads nowhere.
            for _ in 0..bounds.area() {
                let Some(c) = cur.filter(|&c| c != v && key <= MAX_DIST) else {
                    cur = None;
                    break;
                };
                let Some(o) = other_arm(map, usize::MAX, c, (hd + 2) & 3) else {
                    break;
                };
                key += if o == hd { 0 } else { t.quarter_turn } + t.edge;
                (cur, hd) = (neighbour_index(bounds, c, Heading::from_index(o as u8)), o);
            }
            let exit = cur.filter(|&c| c != v && key <= MAX_DIST);
            if let (Some(c), Some(slot)) = (exit, out.exits.get_mut(usize::from(out.len))) {
                *slot = (c, Heading::from_index(hd as u8), key);
                out.len += 1;
            }
        }
        out
    }

    /// Each exit as (node, heading, time to get there).
    pub fn iter(&self) -> impl Iterator<Item = (usize, Heading, Ticks)> + '_ {
        self.exits.iter().take(usize::from(self.len)).copied()
    }

    /// The robot's time to the goal of the reverse search `field`, once it
    /// is proven: the cheapest settled exit, if no exit not settled could
    /// be cheaper, as each of those costs at least `at` (a search settles
    /// cheapest first: see [`DistField::reverse_settled_to`]).
    pub fn time_in<S: AsRef<[PlanCell]> + AsMut<[PlanCell]>>(
        &self,
        field: &DistField<S>,
        at: Ticks,
    ) -> Option<Ticks> {
        let mut best = None::<Ticks>;
        let mut unseen = Ticks::MAX;
        for (v, h, off) in self.iter() {
            match field.dist_pose_at(v, h) {
                Some(d) => best = Some(best.map_or(off + d, |b| b.min(off + d))),
                None => unseen = unseen.min(off),
            }
        }
        best.filter(|&b| b <= at.saturating_add(unseen))
    }
}

#[cfg(test)]
pub(super) mod tests;
