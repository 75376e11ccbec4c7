//! The phone side's loop, the same for simulated and real robots: poll every
//! proxy, pass what the robots said down the handler chain, relay the
//! broadcasts, start each robot when it says hello, and keep the link
//! statistics in the environment.

use crate::environment::Environment;
use crate::field::StartPose;
use crate::handlers::{Chain, Inbound, Recipients, Relay};
use crate::proxy::{ProxyEvent, RobotProxy};
use core_algo::map::Bounds;
use core_algo::protocol::message::{
    Broadcast, FailureKind, LocalizeMethod, StrategyKind, StrategySettings,
};
use core_algo::protocol::{Message, Pose};
use core_algo::team::RobotId;

/// The phone side of a team; see the module docs.
pub struct PhoneSide {
    env: Environment,
    chain: Chain,
    starts: Vec<StartPose>,
    started: Vec<bool>,
    speed: u16,
    localize: Option<LocalizeMethod>,
    events: Vec<ProxyEvent>,
}

impl PhoneSide {
    /// The phone side of a team that starts at `starts` (robot `i` at
    /// `starts[i]`), its map covering `bounds`, driving at `speed` steps/s.
    pub fn new(bounds: Bounds, starts: Vec<StartPose>, speed: u16) -> Self {
        PhoneSide {
            env: Environment::new(bounds, starts.len()),
            chain: Chain::standard(),
            started: vec![false; starts.len()],
            starts,
            speed,
            localize: None,
            events: Vec::new(),
        }
    }

    /// Starts the robots without telling them their poses: they agree on a
    /// frame by `method` first. The phone's map is then in the team frame
    /// (robot 0's own frame), so `bounds` must cover the field wherever
    /// robot 0 starts.
    pub fn with_localize(mut self, method: Option<LocalizeMethod>) -> Self {
        self.localize = method;
        self
    }

    /// The model.
    pub fn env(&self) -> &Environment {
        &self.env
    }

    /// The model, to subscribe views or stamp the time.
    pub fn env_mut(&mut self) -> &mut Environment {
        &mut self.env
    }

    /// One round at `now` (ms) over every proxy; `proxies[i]` is robot `i`.
    pub fn process<P: RobotProxy + ?Sized>(&mut self, now: u32, proxies: &mut [Box<P>]) {
        self.process_due(now, proxies, |p, _| !p.is_quiet(now));
    }

    /// [`PhoneSide::process`] polling only the proxies `due(proxy, i)`
    /// names: a caller that knows when each proxy is next due (the
    /// simulator) need not ask each. Whether it sent anything to a proxy
    /// (a relay), which may then be due at once.
    pub fn process_due<P: RobotProxy + ?Sized>(
        &mut self,
        now: u32,
        proxies: &mut [Box<P>],
        due: impl Fn(&P, usize) -> bool,
    ) -> bool {
        self.env.set_now(now);
        let mut relay = Relay::default();
        let mut polled = false;
        for i in 0..proxies.len() {
            if proxies.get(i).is_some_and(|p| !due(p, i)) {
                continue;
            }
            polled = true;
            let id = RobotId(i as u8);
            let mut events = std::mem::take(&mut self.events);
            events.clear();
            if let Some(p) = proxies.get_mut(i) {
                p.poll(now, &mut events);
            }
            for e in events.drain(..) {
                match e {
                    ProxyEvent::Message(m) => {
                        if matches!(m, Message::Hello { .. })
                            && !self.started.get(i).copied().unwrap_or(true)
                        {
                            self.start_robot(id, proxies);
                        }
                        self.chain.dispatch(
                            &mut self.env,
                            &Inbound {
                                from: id,
                                message: &m,
                            },
                            &mut relay,
                        );
                    }
                    ProxyEvent::LinkUp => {
                        self.env.update_robot(id, |r| {
                            r.link_up = true;
                            r.failed = false;
                        });
                    }
                    ProxyEvent::LinkLost => {
                        self.env.stats_mut().link_losses += 1;
                        // Failed until it is heard again; the team plans
                        // around it meanwhile.
                        self.env.update_robot(id, |r| {
                            r.link_up = false;
                            r.failed = true;
                        });
                        relay.out.push((
                            Recipients::AllBut(id),
                            Message::Relayed {
                                origin: id,
                                broadcast: Broadcast::Failure {
                                    kind: FailureKind::LinkLost,
                                },
                            },
                        ));
                    }
                    ProxyEvent::Restarted => {
                        self.env.log_line(format!("robot {id} restarted"));
                    }
                }
            }
            self.events = events;
        }
        self.env.stats_mut().relayed += relay.out.len() as u64;
        let sent = !relay.out.is_empty();
        for (to, m) in relay.out.drain(..) {
            match to {
                Recipients::To(id) => {
                    if let Some(p) = proxies.get_mut(id.index()) {
                        p.send(m);
                    }
                }
                Recipients::AllBut(origin) => {
                    for (j, p) in proxies.iter_mut().enumerate() {
                        if j != origin.index() {
                            p.send(m.clone());
                        }
                    }
                }
            }
        }
        // A proxy's counters change only as it is polled.
        if polled {
            let (mut retx, mut errors) = (0u64, 0u64);
            for p in proxies.iter() {
                let s = p.stats();
                retx += u64::from(s.retransmissions);
                errors += u64::from(s.link_errors);
            }
            let stats = self.env.stats_mut();
            stats.retransmissions = retx;
            stats.link_errors = errors;
        }
        self.env.check_finished();
        sent
    }

    fn start_robot<P: RobotProxy + ?Sized>(&mut self, id: RobotId, proxies: &mut [Box<P>]) {
        let Some(s) = self.starts.get(id.index()).copied() else {
            return;
        };
        if let Some(flag) = self.started.get_mut(id.index()) {
            *flag = true;
        }
        let settings = StrategySettings {
            kind: StrategyKind::Coordinated,
            team_size: self.starts.len() as u8,
            speed: self.speed,
        };
        if let Some(method) = self.localize {
            // The robot learns its home in the team frame by itself; its
            // first node report tells the phone.
            if let Some(p) = proxies.get_mut(id.index()) {
                p.send(Message::StartLocalize { method, settings });
            }
            return;
        }
        self.env.update_robot(id, |r| r.home = Some(s.pos));
        if let Some(p) = proxies.get_mut(id.index()) {
            p.send(Message::Start {
                pose: Pose {
                    pos: s.pos,
                    heading: s.heading,
                },
                settings,
            });
        }
    }
}
