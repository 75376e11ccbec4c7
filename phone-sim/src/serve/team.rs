//! The team a web session runs: simulated robots in the world simulator, or
//! real robots on serial ports behind the same phone side. Everything the
//! session asks of it is the same for both, so the page cannot tell them
//! apart except by what the robots do.

use super::api::{RobotView, RunResult};
use super::session::RunSpec;
use crate::environment::{Environment, RobotInfo};
use crate::explore_cmd::{ExploreArgs, build, lower_bound_s};
use crate::field::{Field, StartPose};
use crate::phone::PhoneSide;
use crate::proxy::{RobotProxy, SerialRobot};
use crate::sim::{Simulation, window};
use core_algo::geometry::Turn;
use core_algo::protocol::{LinkConfig, Message};
use core_algo::team::RobotId;
use std::time::Instant;

/// A team; see the module docs.
pub enum Team {
    /// Simulated robots.
    Sim {
        /// The simulation.
        sim: Box<Simulation>,
        /// Its start poses.
        starts: Vec<StartPose>,
        /// Nodes of the true field.
        total_nodes: u32,
        /// The makespan's lower bound, seconds.
        lower_bound_s: f64,
        /// Each robot's speed, steps/s.
        speeds: Vec<u16>,
    },
    /// Real robots.
    Robots {
        /// The phone side.
        phone: Box<PhoneSide>,
        /// One proxy per robot.
        proxies: Vec<Box<dyn RobotProxy>>,
        /// Their start poses.
        starts: Vec<StartPose>,
        /// When the session began.
        t0: Instant,
        /// Each robot's speed, steps/s.
        speeds: Vec<u16>,
    },
}

impl Team {
    /// A simulation of `field` as `spec` says.
    pub fn simulate(field: &Field, spec: &RunSpec) -> Result<Team, String> {
        let args = ExploreArgs {
            robots: Some(spec.robots),
            strategy: spec.strategy.clone(),
            seed: spec.seed,
            ..ExploreArgs::default()
        };
        let mut sim = build(field, &args).map_err(|e| e.to_string())?;
        sim.set_linger(true);
        sim.set_paused(true);
        let k = spec.robots;
        let lower_bound_s = lower_bound_s(field, k, sim.bodies().timing());
        Ok(Team::Sim {
            sim: Box::new(sim),
            starts: field.starts().iter().take(k).copied().collect(),
            total_nodes: field.nodes().len() as u32,
            lower_bound_s,
            speeds: vec![args.speed.min(u32::from(u16::MAX)) as u16; k],
        })
    }

    /// Real robots on `ports` (robot `i` on the `i`-th) standing on the
    /// first start poses of `field`.
    pub fn connect(field: &Field, ports: &[String], speed: u16) -> Result<Team, String> {
        if ports.len() > field.starts().len() {
            return Err(format!(
                "{} ports but the field {} has only {} start poses",
                ports.len(),
                field.name(),
                field.starts().len()
            ));
        }
        let mut proxies: Vec<Box<dyn RobotProxy>> = Vec::new();
        for (i, port) in ports.iter().enumerate() {
            proxies.push(Box::new(SerialRobot::open(
                RobotId(i as u8),
                port,
                LinkConfig::default(),
            )?));
        }
        let starts: Vec<StartPose> = field.starts().iter().take(ports.len()).copied().collect();
        Ok(Team::Robots {
            phone: Box::new(PhoneSide::new(window(field), starts.clone(), speed)),
            proxies,
            starts,
            t0: Instant::now(),
            speeds: vec![speed; ports.len()],
        })
    }

    /// Real robots or a simulation?
    pub fn is_robots(&self) -> bool {
        matches!(self, Team::Robots { .. })
    }

    /// The phone side's model.
    pub fn env(&self) -> &Environment {
        match self {
            Team::Sim { sim, .. } => sim.env(),
            Team::Robots { phone, .. } => phone.env(),
        }
    }

    /// The phone side's model, to subscribe.
    pub fn env_mut(&mut self) -> &mut Environment {
        match self {
            Team::Sim { sim, .. } => sim.env_mut(),
            Team::Robots { phone, .. } => phone.env_mut(),
        }
    }

    /// Team size.
    pub fn robot_count(&self) -> usize {
        self.env().robots().len()
    }

    /// The start poses.
    pub fn starts(&self) -> Vec<StartPose> {
        match self {
            Team::Sim { starts, .. } | Team::Robots { starts, .. } => starts.clone(),
        }
    }

    /// Run time, ms.
    pub fn now(&self) -> u32 {
        match self {
            Team::Sim { sim, .. } => sim.now(),
            Team::Robots { t0, .. } => t0.elapsed().as_millis().min(u128::from(u32::MAX)) as u32,
        }
    }

    /// Nodes of the true field, when known.
    pub fn total_nodes(&self) -> Option<u32> {
        match self {
            Team::Sim { total_nodes, .. } => Some(*total_nodes),
            Team::Robots { .. } => None,
        }
    }

    /// The makespan's lower bound, when known.
    pub fn lower_bound_s(&self) -> Option<f64> {
        match self {
            Team::Sim { lower_bound_s, .. } => Some(*lower_bound_s),
            Team::Robots { .. } => None,
        }
    }

    /// Freezes or thaws the team: the simulator's clock, or real robots
    /// told to stop after their node and to resume.
    pub fn pause(&mut self, paused: bool) {
        match self {
            Team::Sim { sim, .. } => sim.set_paused(paused),
            Team::Robots { proxies, .. } => {
                for p in proxies.iter_mut() {
                    p.send(if paused {
                        Message::Stop
                    } else {
                        Message::Resume
                    });
                }
            }
        }
    }

    fn send(&mut self, id: RobotId, m: Message) {
        match self {
            Team::Sim { sim, .. } => {
                sim.send(id, m);
            }
            Team::Robots { proxies, .. } => {
                if let Some(p) = proxies.get_mut(id.index()) {
                    p.send(m);
                }
            }
        }
    }

    /// Takes or hands back manual control of `id`.
    pub fn manual(&mut self, id: RobotId, on: bool) {
        self.send(id, Message::Manual { on });
        self.env_mut().update_robot(id, |r| r.manual = on);
    }

    /// Whether a person steers `id`.
    pub fn is_manual(&self, id: RobotId) -> bool {
        self.env().robot(id).is_some_and(|r| r.manual)
    }

    /// Turns `id` on its node.
    pub fn turn(&mut self, id: RobotId, t: Turn) {
        self.send(id, Message::Turn(t));
    }

    /// Drives `id` one edge on.
    pub fn drive(&mut self, id: RobotId) {
        self.send(id, Message::Move);
    }

    /// Sets `id`'s line speed.
    pub fn speed(&mut self, id: RobotId, steps_per_s: u16) {
        self.send(id, Message::SetSpeed { steps_per_s });
        if let Team::Sim { speeds, .. } | Team::Robots { speeds, .. } = self
            && let Some(s) = speeds.get_mut(id.index())
        {
            *s = steps_per_s;
        }
    }

    /// Cuts `id`'s link for `ms` (simulation only).
    pub fn cut_link(&mut self, id: RobotId, ms: u32) -> Result<(), String> {
        match self {
            Team::Sim { sim, .. } => {
                sim.cut_link(id, ms);
                Ok(())
            }
            Team::Robots { .. } => Err("a real robot's link cannot be cut from here".into()),
        }
    }

    /// Runs the team on: a simulation up to run time `target` (as far as
    /// it can when `None`) while `more` says there is wall time left; real
    /// robots for one round of the phone side.
    pub fn advance(&mut self, target: Option<u32>, more: impl Fn() -> bool) {
        match self {
            Team::Sim { sim, .. } => {
                // Stop at the moment the team is done, so that the page
                // sees the end at its true time even at full speed.
                let over = sim.is_over();
                while more() {
                    if target.is_some_and(|t| sim.now() >= t) || !sim.step() {
                        break;
                    }
                    if !over && sim.is_over() {
                        break;
                    }
                }
            }
            Team::Robots {
                phone, proxies, t0, ..
            } => {
                let now = t0.elapsed().as_millis().min(u128::from(u32::MAX)) as u32;
                phone.process(now, proxies);
            }
        }
    }

    /// The result, once the team is done.
    pub fn result(&self) -> Option<RunResult> {
        match self {
            Team::Sim {
                sim, lower_bound_s, ..
            } => sim.is_over().then(|| {
                let o = sim.outcome();
                RunResult {
                    complete: o.complete,
                    makespan_s: f64::from(o.makespan_ms) / 1000.0,
                    lower_bound_s: Some(*lower_bound_s),
                }
            }),
            Team::Robots { phone, .. } => phone.env().finished_at().map(|at| RunResult {
                complete: phone.env().map().is_complete(),
                makespan_s: f64::from(at) / 1000.0,
                lower_bound_s: None,
            }),
        }
    }

    /// Robot `id` as the page shows it: a simulated robot where its body
    /// is (between nodes while driving), a real one where it last said.
    pub fn robot_view(&self, id: RobotId) -> Option<RobotView> {
        let r = self.env().robot(id)?;
        let mut v = base_view(r);
        match self {
            Team::Sim { sim, speeds, .. } => {
                let b = sim.bodies().bodies().get(id.index())?;
                let (x, y) = match b.between(sim.now()) {
                    Some((a, c, f)) => (
                        f64::from(a.x) + (f64::from(c.x) - f64::from(a.x)) * f,
                        f64::from(a.y) + (f64::from(c.y) - f64::from(a.y)) * f,
                    ),
                    None => (f64::from(b.pos.x), f64::from(b.pos.y)),
                };
                v.x = x;
                v.y = y;
                v.heading = b.heading.index();
                v.node = Some([i32::from(b.pos.x), i32::from(b.pos.y)]);
                let fw = sim.firmware().get(id.index())?;
                v.state = if fw.is_dead() {
                    "dead".into()
                } else {
                    format!("{:?}", fw.agent().mode()).to_lowercase()
                };
                v.speed = speeds.get(id.index()).copied().unwrap_or(0);
            }
            Team::Robots { speeds, .. } => {
                v.speed = speeds.get(id.index()).copied().unwrap_or(0);
            }
        }
        Some(v)
    }
}

fn base_view(r: &RobotInfo) -> RobotView {
    let pos = r.pose.map(|p| p.pos).or(r.home);
    RobotView {
        id: r.id.0,
        x: pos.map_or(0.0, |p| f64::from(p.x)),
        y: pos.map_or(0.0, |p| f64::from(p.y)),
        heading: r.pose.map_or(0, |p| p.heading.index()),
        node: pos.map(|p| [i32::from(p.x), i32::from(p.y)]),
        target: r.target.map(|p| [i32::from(p.x), i32::from(p.y)]),
        home: r.home.map(|p| [i32::from(p.x), i32::from(p.y)]),
        state: format!("{:?}", r.state).to_lowercase(),
        link_up: r.link_up,
        manual: r.manual,
        failed: r.failed,
        finished: r.finished,
        explored: r.explored,
        driven: r.driven,
        revisits: r.revisits,
        collisions: r.collisions,
        messages: r.messages,
        speed: 0,
    }
}
