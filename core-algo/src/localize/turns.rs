//! Whose turn it is: the rules every robot applies to the same broadcasts,
//! so that all agree without a coordinator.

use super::*;

impl Localizer {
    pub(super) fn on_pass(&mut self, from: RobotId, pose: Pose) {
        if let Some(r) = self.rest.get_mut(from.index()) {
            *r = pose;
        }
        match self.phase {
            Phase::Gather | Phase::Runs | Phase::Border => {
                if let Some(p) = self.passed.get_mut(from.index()) {
                    *p = true;
                }
            }
            Phase::Circle if self.holder == Some(from) => {
                if let Some(partner) = self.turn_met.take() {
                    // The partner goes on (seed §4.3).
                    self.fruitless = 0;
                    self.holder = Some(partner);
                } else {
                    self.fruitless = self.fruitless.saturating_add(1);
                    self.holder = Some(self.next_group(from));
                }
            }
            Phase::Circle | Phase::Over => {}
        }
    }

    /// The lowest id of the group after `id`'s, in cyclic id order of the
    /// groups' lowest ids.
    pub(super) fn next_group(&self, id: RobotId) -> RobotId {
        let mine = self.frames.root(id).0;
        let roots = (0..self.team).filter(|&i| self.frames.root(RobotId(i)).0 == i);
        let next = roots
            .clone()
            .find(|&r| r > mine)
            .or_else(|| roots.clone().next())
            .unwrap_or(mine);
        RobotId(next)
    }

    /// Whose turn it is, by the shared rules.
    pub(super) fn holder_now(&self) -> Option<RobotId> {
        let placed = |i: u8| self.frames.root(RobotId(i)).0 == 0;
        let waiting = |i: u8| !self.passed.get(usize::from(i)).copied().unwrap_or(true);
        match self.phase {
            Phase::Runs => (0..self.team)
                .find(|&i| placed(i) && waiting(i))
                .map(RobotId),
            Phase::Border => (0..self.team).find(|&i| waiting(i)).map(RobotId),
            Phase::Circle => self.holder,
            Phase::Gather | Phase::Over => None,
        }
    }
}
