//! An original 2010 e-puck, still running its 2010 firmware: it only turns,
//! drives to the next node and reports what it found, over 32-byte frames
//! with strict request/response. Its brain, the same core-algo agent the
//! new robots carry, runs here on the phone side; to the rest of the phone
//! side the robot looks like any other (it "sends" node hits and intents).

use super::{ProxyEvent, ProxyStats, RobotProxy};
use crate::sim::robot::{
    BoxedStrategy, HostAgent, SIM_FIRMWARE, agent_event, host_agent, node_hit,
};
use core_algo::agent::{AgentConfig, Command, Event as AgentEvent};
use core_algo::map::Bounds;
use core_algo::protocol::legacy::{
    FRAME_LEN, LegacyRequest, LegacyResponse, LegacyStream, relative_arms,
};
use core_algo::protocol::message::{RobotState, Status};
use core_algo::protocol::{Message, Pose};
use core_algo::team::RobotId;
use std::collections::VecDeque;
use std::io::{Read, Write};

/// How long to wait for a 2010 answer before asking again, ms: a move over
/// a long edge at low speed takes several seconds.
pub const ANSWER_TIMEOUT_MS: u32 = 15_000;

/// The proxy of a 2010 e-puck on any byte transport (a serial port, a
/// pseudo-terminal in tests).
pub struct LegacyRobot<T> {
    id: RobotId,
    io: T,
    stream: LegacyStream<LegacyResponse>,
    agent: HostAgent,
    /// Requests waiting for the robot (one in flight at a time).
    queue: VecDeque<LegacyRequest>,
    in_flight: Option<(LegacyRequest, u32)>,
    events: Vec<ProxyEvent>,
    connected: bool,
    finished: bool,
    io_errors: u32,
    timeouts: u32,
}

impl<T: Read + Write + Send> LegacyRobot<T> {
    /// Robot `id` on `io`, its map covering `bounds`, deciding with
    /// `strategy`.
    pub fn new(
        id: RobotId,
        io: T,
        bounds: Bounds,
        strategy: BoxedStrategy,
        config: AgentConfig,
    ) -> Self {
        LegacyRobot {
            id,
            io,
            stream: LegacyStream::new(),
            agent: host_agent(id, bounds, strategy, config),
            queue: VecDeque::new(),
            in_flight: None,
            events: Vec::new(),
            connected: false,
            finished: false,
            io_errors: 0,
            timeouts: 0,
        }
    }

    /// The agent that decides for the robot.
    pub fn agent(&self) -> &HostAgent {
        &self.agent
    }

    fn feed(&mut self, now: u32, event: AgentEvent) {
        let Ok(commands) = self.agent.handle(now, event) else {
            return;
        };
        for c in commands {
            match c {
                Command::Turn(t) => self.queue.push_back(LegacyRequest::Turn(t.legacy_code())),
                Command::Move => self.queue.push_back(LegacyRequest::Move),
                Command::Report { pos, arms, heading } => {
                    self.events
                        .push(ProxyEvent::Message(node_hit(pos, heading, arms)));
                }
                Command::Announce { target } => self
                    .events
                    .push(ProxyEvent::Message(Message::Intent { target })),
                Command::Finished => {
                    self.finished = true;
                    self.queue.push_back(LegacyRequest::SetLed(0x00FF));
                    let (pos, heading) = self.agent.pose();
                    self.events
                        .push(ProxyEvent::Message(Message::Status(Status {
                            uptime_ms: now,
                            pose: Pose { pos, heading },
                            state: RobotState::Finished,
                            floor: 0,
                            proximity: 0,
                        })));
                }
                Command::Localize(news) => {
                    self.events.push(ProxyEvent::Message(Message::Relayed {
                        origin: self.id,
                        broadcast: core_algo::protocol::Broadcast::Localize(news),
                    }))
                }
                Command::Stop => {}
            }
        }
    }

    fn on_response(&mut self, now: u32, r: LegacyResponse) {
        if !self.connected {
            // The 2010 firmware greets a new connection with OK.
            self.connected = true;
            self.events.push(ProxyEvent::LinkUp);
            self.events.push(ProxyEvent::Message(Message::Hello {
                robot: self.id,
                firmware: SIM_FIRMWARE,
            }));
            if r == LegacyResponse::Ok && self.in_flight.is_none() {
                return;
            }
        }
        self.in_flight = None;
        match r {
            LegacyResponse::Ok => {}
            LegacyResponse::Status { node, .. } | LegacyResponse::HitNode(node) => {
                match relative_arms(node) {
                    Some(relative) => self.feed(now, AgentEvent::NodeHit { relative }),
                    None => self.feed(now, AgentEvent::Rejected),
                }
            }
            LegacyResponse::Collision(mask) => {
                self.events
                    .push(ProxyEvent::Message(Message::Collision { proximity: mask }));
                self.feed(now, AgentEvent::Collision);
            }
            LegacyResponse::Abyss(mask) => {
                self.events
                    .push(ProxyEvent::Message(Message::Abyss { floor: mask }));
                self.feed(now, AgentEvent::Rejected);
            }
            LegacyResponse::Rejected => self.feed(now, AgentEvent::Rejected),
        }
    }
}

impl<T: Read + Write + Send> RobotProxy for LegacyRobot<T> {
    fn id(&self) -> RobotId {
        self.id
    }

    fn kind(&self) -> &'static str {
        "legacy"
    }

    fn send(&mut self, message: Message) {
        // `now` is not known here; events that need it are fed at 0 and
        // the agent's next tick carries the clock on.
        let Some(event) = agent_event(&message) else {
            if let Some(r) = LegacyRequest::from_message(&message) {
                self.queue.push_back(r);
            }
            return;
        };
        if matches!(event, AgentEvent::Start { .. }) {
            // The 2010 robot scans the node under it when asked its status.
            self.queue.push_back(LegacyRequest::Status);
        }
        let now = self.in_flight.map_or(0, |(_, t)| t);
        self.feed(now, event);
    }

    fn poll(&mut self, now: u32, events: &mut Vec<ProxyEvent>) {
        let mut buf = [0u8; 128];
        loop {
            match self.io.read(&mut buf) {
                Ok(0) => break,
                Ok(n) => {
                    let mut frames = Vec::new();
                    self.stream
                        .push(buf.get(..n).unwrap_or(&[]), |f| frames.push(f));
                    for f in frames {
                        self.on_response(now, f);
                    }
                }
                Err(e)
                    if matches!(
                        e.kind(),
                        std::io::ErrorKind::TimedOut | std::io::ErrorKind::WouldBlock
                    ) =>
                {
                    break;
                }
                Err(_) => {
                    self.io_errors += 1;
                    break;
                }
            }
        }
        if let Some((req, at)) = self.in_flight
            && now.wrapping_sub(at) > ANSWER_TIMEOUT_MS
        {
            // No answer: the 2010 protocol has no retransmission, so ask
            // for the status, which every state answers.
            self.timeouts += 1;
            self.in_flight = None;
            if req != LegacyRequest::Status {
                self.queue.push_front(LegacyRequest::Status);
            }
        }
        if self.in_flight.is_none()
            && self.connected
            && let Some(req) = self.queue.pop_front()
        {
            let frame: [u8; FRAME_LEN] = req.encode();
            if self.io.write_all(&frame).is_err() {
                self.io_errors += 1;
            }
            self.in_flight = Some((req, now));
        }
        self.feed(now, AgentEvent::Tick);
        events.append(&mut self.events);
    }

    fn stats(&self) -> ProxyStats {
        ProxyStats {
            retransmissions: self.timeouts,
            link_errors: self.io_errors + self.stream.skipped(),
            queued: self.queue.len(),
            ..ProxyStats::default()
        }
    }
}
