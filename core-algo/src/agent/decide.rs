//! Deciding at a node: asking the strategy with the team as this robot
//! sees it, following its answer (announce, turn, drive or wait), and
//! knowing when the team is done.

use super::*;

/// See [`Agent::idle_patience`]: long against the time a report or an
/// intent takes to reach the team, short against a run.
pub(super) const IDLE_PATIENCE_EDGES: u32 = 30;

impl<M, F, S, const K: usize> Agent<M, F, S, K>
where
    M: AsRef<[Block]> + AsMut<[Block]>,
    F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
    S: Strategy<M, F>,
{
    /// Says `Finished` once, when this robot stands at home, its map is
    /// complete and every living teammate is home.
    pub(super) fn check_finished(&mut self, out: &mut Commands) {
        if self.finished_sent
            || !matches!(self.motion, Motion::Standing)
            || !matches!(self.mode, Mode::Explore | Mode::Return)
            || self.pos != self.home
            || !self.team_done()
        {
            return;
        }
        self.finished_sent = true;
        self.mode = Mode::Finished;
        push(out, Command::Finished);
    }

    /// The team as this robot sees it, for the strategy.
    pub(super) fn views(&self) -> ([RobotView; MAX_ROBOTS], usize) {
        let far: Ticks = u32::MAX / 4;
        let mut views = [RobotView {
            pos: self.pos,
            heading: self.heading,
            eta: far,
            home: self.home,
            target: None,
        }; MAX_ROBOTS];
        let mut n = self.id.index() + 1;
        for (i, (v, p)) in views.iter_mut().zip(self.peers.iter()).enumerate() {
            if i == self.id.index() {
                v.eta = 0;
                v.target = self.target;
            } else if p.known {
                n = n.max(i + 1);
                *v = RobotView {
                    pos: p.pos,
                    heading: p.heading,
                    eta: if p.failed { far } else { 0 },
                    home: p.home,
                    target: if p.failed { None } else { p.target },
                };
            }
        }
        (views, n.min(MAX_ROBOTS))
    }

    /// Asks the strategy and acts on its answer. Only called while standing.
    pub(super) fn decide(&mut self, out: &mut Commands) {
        if matches!(
            self.mode,
            Mode::Idle | Mode::Error | Mode::Manual | Mode::Localize
        ) {
            return;
        }
        if let Some(decision) = self.retreat_decision() {
            // The spot is announced as our target: a team mate standing on
            // our way there learns where we go and retreats off it in turn
            // (see `on_bumped`), so that a chain of robots can make way.
            let spot = self.retreat.map(|r| r.spot);
            self.follow_to(decision, spot, out);
            return;
        }
        let (views, n) = self.views();
        let robots = views.get(..n).unwrap_or(&views);
        if let Some(f) = self.forest.as_mut() {
            f.sync(&self.map);
        }
        let ctx = Context {
            map: &self.map,
            timing: self.config.timing,
            robots,
            me: self.id.index(),
            tree: self.forest.as_ref().map(|f| f.view()),
        };
        let decision = self
            .strategy
            .decide(&ctx, &mut self.fields)
            .unwrap_or(Decision::STAY);
        // A strategy that shares the work out may tell every robot to wait
        // when their views of the team differ (a heading not yet reported,
        // an intent still in flight): each thinks another takes the last
        // frontier, and nobody moves, so nothing changes. After a long wait
        // with no map growth, go to the nearest frontier anyway.
        let decision = if decision.goal == Goal::Wait {
            let (now, revision, patience) = (self.now, self.map.revision(), self.idle_patience());
            let since = match self.idle_since {
                Some((r, t)) if r == revision => t,
                _ => {
                    self.idle_since = Some((revision, now));
                    now
                }
            };
            match self.fields.first_mut() {
                Some(field) if now.wrapping_sub(since) > patience => {
                    crate::explore::nearest_or_home(&ctx, field).unwrap_or(decision)
                }
                _ => decision,
            }
        } else {
            self.idle_since = None;
            decision
        };
        let decision = if matches!(decision.goal, Goal::Home | Goal::Done) && self.map.is_complete()
        {
            let decision = self.round_settled_mates(decision);
            self.keep_out_of_the_way(decision)
        } else {
            decision
        };
        self.follow(decision, out);
    }

    /// Acts on a decision: announces a new target, sets the mode, turns and
    /// drives, or waits.
    pub(super) fn follow(&mut self, decision: Decision, out: &mut Commands) {
        self.follow_to(decision, decision.target(), out);
    }

    /// Follows a decision and announces `target` (a frontier node, a
    /// retreat spot, or none).
    pub(super) fn follow_to(
        &mut self,
        decision: Decision,
        target: Option<Pos>,
        out: &mut Commands,
    ) {
        if target != self.target {
            self.target = target;
            push(out, Command::Announce { target });
        }
        match decision.goal {
            Goal::Frontier(_) => self.mode = Mode::Explore,
            Goal::Home => self.mode = Mode::Return,
            Goal::Done => {
                if self.mode == Mode::Explore && self.map.is_complete() {
                    self.mode = Mode::Return;
                }
            }
            // Standing aside while others explore: keep the mode.
            Goal::Wait => {}
        }
        let Some(h) = decision.next else {
            let edge_ms = self.config.timing.edge.saturating_mul(TICK_MS);
            if self.pos != self.home && (self.mode == Mode::Return || decision.goal == Goal::Wait) {
                // Held back (or home unreachable for now): look again soon.
                self.motion = Motion::Waiting {
                    until: self.now.wrapping_add(edge_ms),
                };
            } else if decision.goal == Goal::Wait {
                // Waiting for work at home: the map's growth wakes us, and
                // so does the end of our patience (see `decide`).
                self.motion = Motion::Waiting {
                    until: self
                        .now
                        .wrapping_add(self.idle_patience().saturating_add(edge_ms)),
                };
            }
            self.check_finished(out);
            return;
        };
        if !self.can_move(h) {
            // A strategy must not send us along an unknown arm; stay safe.
            return;
        }
        match self.heading.turn_to(h) {
            None => self.start_move(out),
            Some(t) => {
                // Turn and move go out together: the body turns on the node,
                // then drives, without another round trip.
                self.heading = h;
                push(out, Command::Turn(t));
                self.start_move(out);
            }
        }
    }

    /// How long a robot waits for work while the map does not grow before
    /// it goes to the nearest frontier itself.
    pub(super) fn idle_patience(&self) -> Millis {
        self.config
            .timing
            .edge
            .saturating_mul(TICK_MS)
            .saturating_mul(IDLE_PATIENCE_EDGES)
    }

    pub(super) fn start_move(&mut self, out: &mut Commands) {
        let Some(next) = self.pos.step(self.heading) else {
            return;
        };
        if !self.can_move(self.heading) {
            self.motion = Motion::Standing;
            return;
        }
        self.motion = Motion::Driving { from: self.pos };
        self.pos = next;
        push(out, Command::Move);
    }

    /// Whether the map knows an arm from the current node towards `h`.
    pub(super) fn can_move(&self, h: Heading) -> bool {
        self.map.known_arms(self.pos).is_some_and(|a| a.has(h))
    }

    /// Every living teammate is home (as far as we know) and nothing is
    /// left to explore.
    pub(super) fn team_done(&self) -> bool {
        self.map.is_complete() && self.peers_home()
    }

    /// Every living teammate reported being on its home node.
    pub(super) fn peers_home(&self) -> bool {
        self.peers
            .iter()
            .enumerate()
            .filter(|(i, p)| *i != self.id.index() && p.known && !p.failed)
            .all(|(_, p)| p.pos == p.home)
    }

    pub(super) fn backoff(&self) -> Millis {
        let shift = u32::from(self.retries.min(5));
        let base = self.config.backoff_ms.max(TICK_MS);
        let span = base.saturating_mul(1 << shift);
        span / 2 + base.saturating_mul(u32::from(self.id.0 % 8)) / 2 + self.jitter(span, self.now)
    }

    /// A pseudo-random wait in `0..span` while the team comes home (zero
    /// before): robots that make way for each other on fixed timings can
    /// repeat the same dance for ever, and random waits break such cycles,
    /// as Ethernet's random back-off breaks repeated collisions. Drawn
    /// from the robot, the place and a moment (`at`: now, or when a wait
    /// began, so that the draw holds while it lasts), so a seeded run
    /// repeats.
    pub(super) fn jitter(&self, span: Millis, at: Millis) -> Millis {
        if !self.map.is_complete() {
            return 0;
        }
        draw(self.id, self.pos, at, span)
    }
}

/// A pseudo-random number in `0..span` (zero if `span` is) from a robot,
/// a place and a moment: SplitMix64's finaliser over them.
pub(super) fn draw(id: RobotId, pos: Pos, at: Millis, span: Millis) -> Millis {
    if span == 0 {
        return 0;
    }
    let mut x = (u64::from(at) << 24)
        ^ (u64::from(id.0) << 56)
        ^ (u64::from(pos.x as u16) << 8)
        ^ u64::from(pos.y as u16);
    x = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    x ^= x >> 31;
    (x % u64::from(span)) as Millis
}
