//! Reverse fields: from every pose, the time to one goal node (see
//! [`DistField::compute_reverse`]), plain or jumping along corridors.

use super::scratch::Queues;
use super::{DistField, Flow, PlanCell, PlanError, arms_at, neighbour_index, wrap};
use crate::geometry::{Heading, Pos};
use crate::map::{Block, KnownMap};
use crate::timing::{Ticks, Timing};

impl<S: AsRef<[PlanCell]> + AsMut<[PlanCell]>> DistField<S> {
    /// The reverse field of node `goal`: for every (node, heading) state,
    /// the cheapest time from that pose to reach `goal` (with any heading),
    /// over the same moves and costs as [`DistField::compute`]. Calls
    /// `reached(node, heading, time)` for every state as it settles,
    /// cheapest first; stop early with [`Flow::Stop`]. Rooted at a robot's
    /// home on a complete map it never changes again: every way home, the
    /// robot's own and the one team mates predict for it, is read from it
    /// (see the `descent` module).
    ///
    /// Afterwards [`DistField::dist_at`] holds each node's cheapest time
    /// over its headings and, if the search ran to the end,
    /// [`DistField::way_out`] the way from any pose; the field has no
    /// start, so it gives no forward path. A stopped search can go on
    /// with [`DistField::resume_reverse`], also after the map has grown
    /// (see [`DistField::refresh_reverse`]).
    pub fn compute_reverse<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        timing: Timing,
        goal: Pos,
        reached: impl FnMut(usize, Heading, Ticks) -> Flow,
    ) -> Result<(), PlanError> {
        self.reverse_search(map, timing, (goal, false), reached)
    }

    /// [`DistField::compute_reverse`] for callers that ask only the times
    /// of states outside corridors, as a robot anywhere reads them through
    /// its [`CorridorExits`](super::CorridorExits): it jumps along
    /// corridors (see `corridor`), and a corridor state is not settled, or
    /// may be settled dearer than it is. Every other state is reported
    /// cheapest first with the time a plain search gives it (states at the
    /// same time may come in another order). It can be refreshed, rebased
    /// and resumed as the plain one can, and goes on jumping; it is never a
    /// whole reverse field ([`DistField::way_out`] reads none from it).
    ///
    /// Why: once fewer frontier nodes than robots are left, tempo searches
    /// back from every frontier node at every decision, and late in a maze
    /// run each search settles about half the map (maze 256², 16 robots:
    /// 139 k states a decision; docs/results/performance.md, stop 44).
    /// Four in five of a maze's nodes are corridor nodes.
    pub fn compute_reverse_jumping<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        timing: Timing,
        goal: Pos,
        reached: impl FnMut(usize, Heading, Ticks) -> Flow,
    ) -> Result<(), PlanError> {
        self.reverse_search(map, timing, (goal, true), reached)
    }

    /// [`DistField::compute_reverse`], or (`jumping`)
    /// [`DistField::compute_reverse_jumping`].
    fn reverse_search<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        timing: Timing,
        (goal, jumping): (Pos, bool),
        mut reached: impl FnMut(usize, Heading, Ticks) -> Flow,
    ) -> Result<(), PlanError> {
        self.tree = None;
        let g = self.prepare(map, timing, goal, Heading::North)?;
        self.jumping = jumping;
        let cap = self.cells.as_ref().len();
        let bounds = self.bounds;
        self.queue = Queues::default();
        let mut stop = false;
        for h in 0..4 {
            self.settle(g, h, 0);
        }
        for heading in Heading::ALL {
            let h = usize::from(heading.index());
            // The edges that arrive at the goal heading `h`.
            let from = neighbour_index(bounds, g, heading.opposite());
            if from
                .and_then(|u| arms_at(map, u))
                .is_some_and(|a| a.has(heading))
            {
                let q = &mut self.queue;
                if let Some(c) = self.cells.as_mut().get_mut(wrap(q.a_head + q.a_len, cap)) {
                    c.ring_a = (g * 4 + h) as u32;
                    q.a_len += 1;
                    q.a_pushed += 1;
                }
            }
            stop = stop || reached(g, heading, 0) == Flow::Stop;
        }
        let result = if stop {
            Ok(())
        } else {
            let settled = |v, h, key, _| {
                let flow = reached(v, Heading::from_index(h as u8), key);
                stop |= flow == Flow::Stop;
                flow
            };
            if jumping {
                self.run_jumping::<M, true>(map, (|_| true, |_| {}), settled)
            } else {
                self.run::<M, true>(map, |_| true, settled)
            }
        };
        self.start = None;
        match result {
            Ok(()) => {
                self.rev_open = Some((g, map.revision()));
                if !stop && !jumping {
                    self.reverse = Some((g, map.revision()));
                }
            }
            Err(_) => {
                self.queue = Queues::default();
                self.jumps.reset(g);
            }
        }
        result
    }
}
