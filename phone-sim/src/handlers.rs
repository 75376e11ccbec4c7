//! Incoming robot messages pass a chain of handlers (the seed's chain of
//! responsibility): the first handler that recognises a message handles it
//! and returns `true`; the end of the chain counts and logs what nobody
//! took, instead of failing. Adding a message type is adding a handler.
//!
//! Handlers update the [`Environment`] and fill a [`Relay`] with what must
//! go out to other robots (maps stay decentralised: every robot gets every
//! other robot's node hits and intents).

use crate::environment::Environment;
use core_algo::protocol::Message;
use core_algo::protocol::message::{Broadcast, RobotState};
use core_algo::team::RobotId;

/// Who gets a relayed message.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Recipients {
    /// Every robot but the origin.
    AllBut(RobotId),
    /// One robot.
    To(RobotId),
}

/// Messages to send out after handling.
#[derive(Debug, Default)]
pub struct Relay {
    /// (recipients, message), in order.
    pub out: Vec<(Recipients, Message)>,
}

/// One received message and its context.
#[derive(Debug)]
pub struct Inbound<'a> {
    /// The robot it came from (the link's peer).
    pub from: RobotId,
    /// The message.
    pub message: &'a Message,
}

/// One link of the chain.
pub trait Handler: Send {
    /// Handles `msg` if it is this handler's kind; returns whether it did.
    fn handle(&mut self, env: &mut Environment, msg: &Inbound<'_>, relay: &mut Relay) -> bool;
}

/// The chain.
pub struct Chain {
    handlers: Vec<Box<dyn Handler>>,
}

impl Chain {
    /// An empty chain (everything is unhandled).
    pub fn new() -> Self {
        Chain {
            handlers: Vec::new(),
        }
    }

    /// The phone side's standard handlers.
    pub fn standard() -> Self {
        Chain::new()
            .with(NodeHitHandler)
            .with(IntentHandler)
            .with(StatusHandler)
            .with(EventHandler)
            .with(BroadcastHandler)
    }

    /// Appends a handler.
    pub fn with(mut self, h: impl Handler + 'static) -> Self {
        self.handlers.push(Box::new(h));
        self
    }

    /// Passes `msg` down the chain; returns whether a handler took it.
    pub fn dispatch(
        &mut self,
        env: &mut Environment,
        msg: &Inbound<'_>,
        relay: &mut Relay,
    ) -> bool {
        env.stats_mut().received += 1;
        if env.robot(msg.from).is_none() {
            env.stats_mut().unknown_robots += 1;
            env.log_line(format!(
                "message from unknown robot {}: {:?}",
                msg.from, msg.message
            ));
            return false;
        }
        env.update_robot(msg.from, |r| r.messages += 1);
        for h in &mut self.handlers {
            if h.handle(env, msg, relay) {
                return true;
            }
        }
        env.stats_mut().unhandled += 1;
        env.log_line(format!("robot {}: unhandled {:?}", msg.from, msg.message));
        false
    }
}

impl Default for Chain {
    fn default() -> Self {
        Chain::standard()
    }
}

/// Node hits: into the merged map and out to the team.
pub struct NodeHitHandler;

impl Handler for NodeHitHandler {
    fn handle(&mut self, env: &mut Environment, msg: &Inbound<'_>, relay: &mut Relay) -> bool {
        let Message::NodeHit { pose, arms } = msg.message else {
            return false;
        };
        if env.node_hit(msg.from, *pose, *arms) {
            relay.out.push((
                Recipients::AllBut(msg.from),
                Message::Relayed {
                    origin: msg.from,
                    broadcast: Broadcast::NodeHit {
                        pose: *pose,
                        arms: *arms,
                    },
                },
            ));
        }
        true
    }
}

/// Announced targets: shown and relayed.
pub struct IntentHandler;

impl Handler for IntentHandler {
    fn handle(&mut self, env: &mut Environment, msg: &Inbound<'_>, relay: &mut Relay) -> bool {
        let Message::Intent { target } = msg.message else {
            return false;
        };
        env.update_robot(msg.from, |r| r.target = *target);
        relay.out.push((
            Recipients::AllBut(msg.from),
            Message::Relayed {
                origin: msg.from,
                broadcast: Broadcast::Intent { target: *target },
            },
        ));
        true
    }
}

/// Status and hello: the robot's state.
pub struct StatusHandler;

impl Handler for StatusHandler {
    fn handle(&mut self, env: &mut Environment, msg: &Inbound<'_>, _relay: &mut Relay) -> bool {
        match msg.message {
            Message::Status(s) => {
                let finished = s.state == RobotState::Finished;
                env.update_robot(msg.from, |r| {
                    r.state = s.state;
                    r.pose = Some(s.pose);
                    r.finished |= finished;
                });
                if finished {
                    env.check_finished();
                }
                true
            }
            Message::Hello { robot, firmware } => {
                env.log_line(format!(
                    "robot {robot} says hello, firmware {}.{}.{}",
                    firmware.major, firmware.minor, firmware.patch
                ));
                env.update_robot(msg.from, |r| r.link_up = true);
                true
            }
            _ => false,
        }
    }
}

/// Collisions, abysses, logs, acks and rejects: counted and logged.
pub struct EventHandler;

impl Handler for EventHandler {
    fn handle(&mut self, env: &mut Environment, msg: &Inbound<'_>, _relay: &mut Relay) -> bool {
        match msg.message {
            Message::Collision { .. } => {
                env.update_robot(msg.from, |r| {
                    r.collisions += 1;
                    r.state = RobotState::Collision;
                });
                true
            }
            Message::Abyss { .. } => {
                env.update_robot(msg.from, |r| r.state = RobotState::Abyss);
                env.log_line(format!("robot {}: abyss", msg.from));
                true
            }
            Message::Log { level, text } => {
                env.log_line(format!("robot {} {level:?}: {text}", msg.from));
                true
            }
            Message::Ack { .. } => true,
            Message::Reject { command, reason } => {
                env.log_line(format!(
                    "robot {} refused command {command}: {reason:?}",
                    msg.from
                ));
                true
            }
            Message::Calibrated(c) => {
                env.log_line(format!("robot {} calibrated: {c:?}", msg.from));
                true
            }
            _ => false,
        }
    }
}

/// Broadcasts a robot addresses to the team (failure, localization).
pub struct BroadcastHandler;

impl Handler for BroadcastHandler {
    fn handle(&mut self, env: &mut Environment, msg: &Inbound<'_>, relay: &mut Relay) -> bool {
        let Message::Relayed { origin, broadcast } = msg.message else {
            return false;
        };
        if *origin != msg.from {
            // A robot may only speak for itself.
            return false;
        }
        if let Broadcast::Failure { kind } = broadcast {
            env.update_robot(msg.from, |r| {
                r.failed = true;
                r.state = RobotState::Error;
            });
            env.log_line(format!("robot {} failed: {kind:?}", msg.from));
            env.check_finished();
        }
        relay
            .out
            .push((Recipients::AllBut(msg.from), msg.message.clone()));
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use core_algo::geometry::{Arms, Heading, Pos};
    use core_algo::map::Bounds;
    use core_algo::protocol::Pose;

    fn env() -> Environment {
        Environment::new(Bounds::new(Pos::new(0, 0), 4, 4), 2)
    }

    fn hit(pos: Pos, arms: Arms) -> Message {
        Message::NodeHit {
            pose: Pose {
                pos,
                heading: Heading::North,
            },
            arms,
        }
    }

    #[test]
    fn node_hits_go_into_the_map_and_out_to_the_others() {
        let (mut env, mut chain, mut relay) = (env(), Chain::standard(), Relay::default());
        let m = hit(Pos::new(1, 1), Arms::CROSS);
        assert!(chain.dispatch(
            &mut env,
            &Inbound {
                from: RobotId(0),
                message: &m
            },
            &mut relay
        ));
        assert_eq!(env.map().known_arms(Pos::new(1, 1)), Some(Arms::CROSS));
        assert_eq!(relay.out.len(), 1);
        assert_eq!(relay.out[0].0, Recipients::AllBut(RobotId(0)));
        assert_eq!(env.node_log().len(), 1);
        assert_eq!(env.robot(RobotId(0)).map(|r| r.explored), Some(1));
    }

    #[test]
    fn bad_input_is_counted_and_the_run_goes_on() {
        let (mut env, mut chain, mut relay) = (env(), Chain::standard(), Relay::default());
        let updates = env.subscribe();
        // An unknown robot id.
        let m = hit(Pos::new(1, 1), Arms::CROSS);
        assert!(!chain.dispatch(
            &mut env,
            &Inbound {
                from: RobotId(7),
                message: &m
            },
            &mut relay
        ));
        assert_eq!(env.stats().unknown_robots, 1);
        // A shape that conflicts with the map: logged, counted, not applied,
        // not relayed.
        chain.dispatch(
            &mut env,
            &Inbound {
                from: RobotId(0),
                message: &m,
            },
            &mut relay,
        );
        let lie = hit(Pos::new(1, 1), Arms::NONE.with(Heading::North));
        relay.out.clear();
        assert!(chain.dispatch(
            &mut env,
            &Inbound {
                from: RobotId(1),
                message: &lie
            },
            &mut relay
        ));
        assert_eq!(env.stats().conflicts, 1);
        assert!(relay.out.is_empty());
        assert_eq!(env.map().known_arms(Pos::new(1, 1)), Some(Arms::CROSS));
        // A message the phone does not expect from a robot: unhandled, counted.
        assert!(!chain.dispatch(
            &mut env,
            &Inbound {
                from: RobotId(0),
                message: &Message::Move
            },
            &mut relay
        ));
        assert_eq!(env.stats().unhandled, 1);
        assert!(
            updates
                .try_iter()
                .any(|u| matches!(u, crate::environment::Update::Log(l) if l.contains("conflict")))
        );
    }

    #[test]
    fn a_robot_may_only_speak_for_itself() {
        let (mut env, mut chain, mut relay) = (env(), Chain::standard(), Relay::default());
        let forged = Message::Relayed {
            origin: RobotId(1),
            broadcast: Broadcast::Failure {
                kind: core_algo::protocol::message::FailureKind::Abyss,
            },
        };
        assert!(!chain.dispatch(
            &mut env,
            &Inbound {
                from: RobotId(0),
                message: &forged
            },
            &mut relay
        ));
        assert!(relay.out.is_empty());
        assert_eq!(env.robot(RobotId(1)).map(|r| r.failed), Some(false));
    }
}
