//! Homecoming: robots cannot pass each other on a line, so the way home is
//! where they get in each other's way. Two behaviours keep the team moving:
//! a robot standing in someone's way makes way when bumped, and a returning
//! robot whose home lies on a team mate's way home waits off that way.

use super::*;

impl<M, F, S, const K: usize> Agent<M, F, S, K>
where
    M: AsRef<[Block]> + AsMut<[Block]>,
    F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
    S: Strategy<M, F>,
{
    /// Makes way: a robot standing idle on someone's route (typically at
    /// home, where another robot's way home may lead through) drives one
    /// edge away from the other robot, waits, and plans again.
    pub(super) fn on_bumped(
        &mut self,
        toward: Heading,
        out: &mut Commands,
    ) -> Result<(), AgentError> {
        if !self.is_standing()
            || !matches!(self.mode, Mode::Explore | Mode::Return | Mode::Finished)
        {
            return Err(AgentError::Unexpected);
        }
        if self.mode == Mode::Finished {
            // Someone still moves: we were wrong that the team is done.
            self.mode = Mode::Return;
            self.finished_sent = false;
        }
        let occupied = |p: Pos| {
            self.peers
                .iter()
                .any(|q| q.known && !q.failed && q.pos == p)
        };
        let candidates = [
            toward.opposite(),
            toward.turned(Turn::Right),
            toward.turned(Turn::Left),
        ];
        let escape = candidates
            .into_iter()
            .filter(|h| self.can_move(*h))
            .min_by_key(|h| self.pos.step(*h).is_some_and(occupied));
        let Some(h) = escape else {
            return Err(AgentError::Unexpected);
        };
        self.escaping = true;
        if let Some(t) = self.heading.turn_to(h) {
            self.heading = h;
            push(out, Command::Turn(t));
        }
        self.start_move(out);
        Ok(())
    }

    /// Homecoming without deadlock: robots cannot pass each other on a
    /// line, so a robot whose home lies on a returning team mate's way home
    /// waits off every returning team mate's way, as near to its home as it
    /// can, until they are in. Needs one planner field per team mate
    /// (`K > 1`); with a single field the decision is kept as it is.
    pub(super) fn keep_out_of_the_way(&mut self, decision: Decision) -> Decision {
        let bounds = self.map.bounds();
        let Some(my_home) = bounds.index(self.home) else {
            return decision;
        };
        let me = self.id.index();
        let (timing, pos, heading) = (self.config.timing, self.pos, self.heading);
        let map = &self.map;
        let Some((mine, rest)) = self.fields.split_first_mut() else {
            return decision;
        };
        // (field in `rest`, peer home index, peer goes first) of every
        // returning team mate.
        let mut pending: Vec<(usize, usize, bool), MAX_ROBOTS> = Vec::new();
        let mut homes: Vec<Pos, MAX_ROBOTS> = Vec::new();
        for (i, p) in self.peers.iter().enumerate() {
            if i == me || !p.known || p.failed {
                continue;
            }
            let _ = homes.push(p.home);
            let slot = pending.len();
            let (false, Some(h), Some(field)) =
                (p.pos == p.home, bounds.index(p.home), rest.get_mut(slot))
            else {
                continue;
            };
            // A total order (by id), so that robots never wait for each
            // other in a circle; a lower id whose way home is blocked by a
            // higher id already home is handled by making way.
            let first = i < me;
            let result = field.compute(map, timing, p.pos, p.heading, |v, _| {
                if v == h { Flow::Stop } else { Flow::Continue }
            });
            if result.is_ok() {
                let _ = pending.push((slot, h, first));
            }
        }
        let rest = &*rest;
        let on_way = |v: usize, only_first: bool| {
            pending
                .iter()
                .filter(|e| e.2 || !only_first)
                .any(|&(s, h, _)| rest.get(s).is_some_and(|f| f.path_passes(map, h, v)))
        };
        let on_someones_way = |v: usize| on_way(v, false);
        let gated = on_way(my_home, true);
        // Never wait for ever: after a while, go and let the make-way
        // behaviour sort it out.
        let now = self.now;
        let since = *self.gated_since.get_or_insert(now);
        let patience = timing.edge.saturating_mul(TICK_MS).saturating_mul(40);
        if !gated || now.wrapping_sub(since) > patience {
            if !gated {
                self.gated_since = None;
            }
            return decision;
        }
        // Gated: find the nearest node off every returning robot's way that
        // is nobody's home, and go there (or stay, if here).
        let mut spot = None;
        let computed = mine.compute(map, timing, pos, heading, |v, _| {
            if v != my_home && !homes.contains(&bounds.pos(v)) && !on_someones_way(v) {
                spot = Some(v);
                return Flow::Stop;
            }
            Flow::Continue
        });
        match (computed, spot) {
            (Ok(()), Some(v)) => Decision {
                goal: Goal::Home,
                next: mine.first_heading(map, v),
            },
            _ => Decision::STAY,
        }
    }
}
