//! Team mates: what the phone side relays about them (starts, node hits,
//! announced targets, failures), and the tick that notices when one falls
//! silent, ends waits and keeps a robot standing still heard.

use super::*;

impl<M, F, S, const K: usize> Agent<M, F, S, K>
where
    M: AsRef<[Block]> + AsMut<[Block]>,
    F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
    S: Strategy<M, F>,
{
    pub(super) fn on_peer(
        &mut self,
        id: RobotId,
        news: PeerNews,
        out: &mut Commands,
    ) -> Result<(), AgentError> {
        if id == self.id {
            return Err(AgentError::Unexpected);
        }
        let now = self.now;
        let Some(peer) = self.peers.get_mut(id.index()) else {
            return Err(AgentError::Unexpected);
        };
        peer.last_heard = now;
        match news {
            PeerNews::Start { pos, heading } => {
                peer.known = true;
                peer.failed = false;
                peer.pos = pos;
                peer.home = pos;
                peer.heading = heading;
            }
            PeerNews::NodeHit { pos, heading, arms } => {
                if !peer.known {
                    peer.known = true;
                    peer.home = pos;
                }
                peer.failed = false;
                peer.pos = pos;
                peer.heading = heading;
                if let Ok(v) = self.map.visit(pos, arms, id) {
                    self.map_grew |= v.first;
                    self.keep_forest();
                }
            }
            PeerNews::Intent { target } => {
                peer.known = true;
                peer.target = target;
            }
            PeerNews::Failed => {
                peer.failed = true;
                peer.target = None;
            }
            PeerNews::Localize(news) => {
                // Kept even before this robot is started: a team mate may
                // be ready first.
                let mut steps = crate::localize::Steps::new();
                self.localizer.on_news(id, news, &mut steps);
                if self.mode == Mode::Localize {
                    self.apply_localize(steps, out);
                }
                return Ok(());
            }
        }
        // A robot waiting for work looks again when the map grew.
        if self.map_grew && matches!(self.motion, Motion::Standing) && self.mode != Mode::Manual {
            self.map_grew = false;
            self.decide(out);
        } else if matches!(news, PeerNews::NodeHit { .. })
            && self.mode == Mode::Return
            && matches!(self.motion, Motion::Standing)
            && self.pos == self.home
            && self.map.is_complete()
        {
            // Home already, but a team mate on its way may need to pass
            // through here to a deeper home: leave before it arrives, or
            // the corridor stays plugged.
            let decision = self.keep_out_of_the_way(Decision::STAY);
            if decision.next.is_some() {
                self.follow(decision, out);
            }
        }
        self.check_finished(out);
        Ok(())
    }

    pub(super) fn on_tick(&mut self, out: &mut Commands) -> Result<(), AgentError> {
        let now = self.now;
        let timeout = self.config.peer_timeout_ms;
        let mut freed = false;
        for p in self.peers.iter_mut().filter(|p| p.known && !p.failed) {
            let silent = now.wrapping_sub(p.last_heard);
            if silent > timeout && silent < u32::MAX / 2 {
                p.failed = true;
                p.target = None;
                freed = true;
            }
        }
        let manual = self.mode == Mode::Manual;
        // Yielded: come back early once everyone is in, but not while a
        // team mate standing at home is on its way to a retreat spot (it
        // may be the one we made way for, pushing through); or once the
        // one we made way for holds its retreat spot, waiting for us.
        if self.yielding
            && matches!(self.motion, Motion::Waiting { .. })
            && (self.peers_home() && (0..self.peers.len()).all(|i| !self.retreating_peer(i))
                || self.made_way_for_a_holding_retreat())
        {
            self.motion = Motion::Waiting { until: now };
        }
        match self.motion {
            Motion::Waiting { until } if now.wrapping_sub(until) < u32::MAX / 2 => {
                self.motion = Motion::Standing;
                self.yielding = false;
                self.made_way_for = None;
                if !manual {
                    self.decide(out);
                }
            }
            Motion::Standing if (freed || self.map_grew) && !manual => {
                self.map_grew = false;
                self.decide(out);
            }
            _ => {}
        }
        // A robot standing still says nothing; a keep-alive tells the team
        // it is alive, so that it is not taken for failed.
        let quiet = now.wrapping_sub(self.last_said);
        if self.is_standing()
            && !matches!(self.mode, Mode::Idle | Mode::Error)
            && quiet > timeout / 3
            && quiet < u32::MAX / 2
        {
            self.last_said = now;
            push(
                out,
                Command::Announce {
                    target: self.target,
                },
            );
        }
        self.check_finished(out);
        Ok(())
    }
}
