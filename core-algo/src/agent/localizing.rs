//! The agent in [`Mode::Localize`]: it carries the body's and the team's
//! news to its [`Localizer`] and the localizer's steps to the body, and,
//! once the team shares a frame, moves everything it knows into that frame
//! and starts exploring exactly as after a known start.

use super::*;
use crate::localize::{Frame, LocalizeMethod, ORIGIN, Progress, Step, Steps};

/// Moves allowed per node of the map window before localization gives up
/// (a safety net: the procedures need a few per node).
const STEPS_PER_NODE: u32 = 64;

impl<M, F, S, const K: usize> Agent<M, F, S, K>
where
    M: AsRef<[Block]> + AsMut<[Block]>,
    F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
    S: Strategy<M, F>,
{
    /// Starts localizing: the robot stands at the origin of its own frame,
    /// facing north, and scans its start node first.
    pub(super) fn on_start_localize(
        &mut self,
        method: LocalizeMethod,
        team: u8,
    ) -> Result<(), AgentError> {
        if self.mode != Mode::Idle {
            return Err(AgentError::Unexpected);
        }
        self.pos = ORIGIN;
        self.heading = Heading::North;
        self.home = ORIGIN;
        self.mode = Mode::Localize;
        self.motion = Motion::Scanning;
        let area = u32::try_from(self.map.bounds().area()).unwrap_or(u32::MAX);
        let budget = area.saturating_mul(STEPS_PER_NODE);
        self.localizer.start(method, team, budget);
        Ok(())
    }

    /// Every event while localizing.
    pub(super) fn on_localize_event(
        &mut self,
        event: Event,
        out: &mut Commands,
    ) -> Result<(), AgentError> {
        let mut steps = Steps::new();
        match event {
            Event::NodeHit { relative } => {
                let arms = Arms::from_relative(relative, self.heading);
                match self.motion {
                    Motion::Scanning => self.localizer.on_scanned(arms, &mut steps),
                    Motion::Driving { .. } => self
                        .localizer
                        .on_node(arms, &mut steps)
                        .map_err(|_| AgentError::Unexpected)?,
                    _ => return Err(AgentError::Unexpected),
                }
                self.motion = Motion::Standing;
            }
            Event::Collision => {
                self.localizer
                    .on_collision(&mut steps)
                    .map_err(|_| AgentError::Unexpected)?;
                self.motion = Motion::Standing;
            }
            Event::Bumped { toward } => self
                .localizer
                .on_bumped(toward, &mut steps)
                .map_err(|_| AgentError::Unexpected)?,
            Event::Rejected => {
                self.localizer.on_refused();
                self.motion = Motion::Standing;
            }
            Event::Peer(id, news) => return self.on_peer(id, news, out),
            Event::Tick => return self.on_tick(out),
            Event::Start { .. } | Event::StartLocalize { .. } | Event::Manual(_) => {
                return Err(AgentError::Unexpected);
            }
        }
        self.apply_localize(steps, out);
        Ok(())
    }

    /// Carries out the localizer's steps and follows its progress.
    pub(super) fn apply_localize(&mut self, steps: Steps, out: &mut Commands) {
        for s in steps {
            match s {
                Step::Turn(t) => push(out, Command::Turn(t)),
                Step::Move => {
                    self.motion = Motion::Driving { from: self.pos };
                    push(out, Command::Move);
                }
                Step::Say(news) => push(out, Command::Localize(news)),
            }
        }
        let pose = self.localizer.pose();
        self.pos = pose.pos;
        self.heading = pose.heading;
        match self.localizer.progress() {
            Progress::Running => {}
            Progress::Done(frame) => self.join_team_frame(frame, out),
            Progress::Failed(_) => {
                self.mode = Mode::Error;
                self.motion = Motion::Standing;
                push(out, Command::Stop);
            }
        }
    }

    /// The team shares a frame: this robot's own frame maps into it by
    /// `frame`. Everything moves into the team frame (the robot's pose and
    /// home, the nodes it stands on and started from, its team mates'
    /// homes and poses), and exploration starts as after a known start.
    fn join_team_frame(&mut self, frame: Frame, out: &mut Commands) {
        let turn = |a: Arms| a.rotated_cw(frame.quarter_turns);
        self.pos = frame.pos(self.pos);
        self.heading = frame.heading(self.heading);
        self.home = frame.pos(ORIGIN);
        let bounds = self.map.bounds();
        if !bounds.contains(self.pos) || !bounds.contains(self.home) {
            // The map window is smaller than the field said it would be.
            self.mode = Mode::Error;
            push(out, Command::Stop);
            return;
        }
        let here = turn(self.localizer.here());
        let nodes = [
            (
                self.home,
                turn(self.localizer.home_arms()),
                frame.heading(Heading::North),
            ),
            (self.pos, here, self.heading),
        ];
        for (i, (pos, arms, heading)) in nodes.into_iter().enumerate() {
            if i == 1 && pos == self.home {
                break;
            }
            let _ = self.map.visit(pos, arms, self.id);
            self.keep_forest();
            push(out, Command::Report { pos, arms, heading });
        }
        let frames = *self.localizer.frames();
        for j in 0..frames.team() {
            let id = RobotId(j);
            if id == self.id {
                continue;
            }
            let to_team = frames.to_root(id);
            let rest = self.localizer.rest(id);
            if let Some(p) = self.peers.get_mut(id.index()) {
                *p = Peer {
                    known: true,
                    failed: false,
                    pos: to_team.pos(rest.pos),
                    heading: to_team.heading(rest.heading),
                    home: to_team.pos(ORIGIN),
                    target: None,
                    last_heard: self.now,
                };
            }
        }
        self.mode = Mode::Explore;
        self.motion = Motion::Standing;
        self.decide(out);
    }
}
