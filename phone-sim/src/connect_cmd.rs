//! `conquest connect`: the phone side for real robots on serial ports
//! (Bluetooth SPP `/dev/rfcommN`, or USB), in real time.
//!
//! Robot `i` is on the `i`-th port and starts at the field's `i`-th start
//! pose. Each robot is started when it says hello; the phone relays node
//! hits and intents between the robots, shows progress, and ends when the
//! team is done (or at `--timeout-s`).

use crate::cli::{CliError, ReadArgs, demo_field, load};
use crate::environment::Update;
use crate::field::ascii;
use crate::phone::PhoneSide;
use crate::proxy::{RobotProxy, SerialRobot};
use crate::sim::window;
use core_algo::protocol::LinkConfig;
use core_algo::team::RobotId;
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// Arguments of `conquest connect`.
#[derive(clap::Args, Debug, Clone)]
pub struct ConnectArgs {
    /// Serial ports, one per robot, in robot id order.
    #[arg(required = true)]
    pub ports: Vec<String>,
    /// The field whose start poses the robots stand on (and whose extent
    /// bounds the map); default: the built-in demo field.
    #[arg(long)]
    pub field: Option<PathBuf>,
    /// Line speed in motor steps per second.
    #[arg(long, default_value_t = 600)]
    pub speed: u16,
    /// Give up after this many seconds (default: until the team is done).
    #[arg(long)]
    pub timeout_s: Option<f64>,
    /// How to read the field.
    #[command(flatten)]
    pub read: ReadArgs,
}

/// Runs the phone side over `proxies` until the team is done or
/// `deadline` passes, calling `show` with every update; returns whether
/// the team finished.
pub fn drive(
    phone: &mut PhoneSide,
    proxies: &mut [Box<dyn RobotProxy>],
    deadline: Option<Duration>,
    mut show: impl FnMut(&Update),
) -> bool {
    let updates = phone.env_mut().subscribe();
    let t0 = Instant::now();
    loop {
        let now = t0.elapsed();
        phone.process(now.as_millis().min(u128::from(u32::MAX)) as u32, proxies);
        for u in updates.try_iter() {
            show(&u);
        }
        if phone.env().finished_at().is_some() {
            return true;
        }
        if deadline.is_some_and(|d| now >= d) {
            return false;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// `conquest connect`.
pub fn run(a: &ConnectArgs) -> Result<(), CliError> {
    let field = match &a.field {
        Some(p) => load(p, a.read)?,
        None => demo_field()?,
    };
    if a.ports.len() > field.starts().len() {
        return Err(CliError::BadInput(format!(
            "{} ports but the field {} has only {} start poses",
            a.ports.len(),
            field.name(),
            field.starts().len()
        )));
    }
    let mut proxies: Vec<Box<dyn RobotProxy>> = Vec::new();
    for (i, port) in a.ports.iter().enumerate() {
        let robot = SerialRobot::open(RobotId(i as u8), port, LinkConfig::default())
            .map_err(CliError::BadInput)?;
        proxies.push(Box::new(robot));
    }
    let starts = field.starts().iter().take(a.ports.len()).copied().collect();
    let mut phone = PhoneSide::new(window(&field), starts, a.speed);
    let deadline = a
        .timeout_s
        .map(|s| Duration::from_secs_f64(s.clamp(0.0, 1e7)));
    crate::outln!("waiting for {} robot(s) to say hello...", proxies.len());
    let done = drive(&mut phone, &mut proxies, deadline, |u| match u {
        Update::Log(line) => crate::outln!("{line}"),
        Update::Node { pos, arms, visits } if *visits == 1 => crate::outln!("node {pos}: {arms}"),
        Update::Finished { at_ms } => {
            crate::outln!("team done after {:.1} s", f64::from(*at_ms) / 1000.0)
        }
        _ => {}
    });
    let nodes = phone
        .env()
        .map()
        .visited()
        .filter_map(|(p, c)| c.arms().map(|a| (p, a)))
        .collect();
    crate::out!("{}", ascii::nodes(&nodes, &[]));
    let s = phone.env().stats();
    crate::outln!(
        "{} messages received, {} relayed, {} link errors, {} retransmissions, {} conflicts",
        s.received,
        s.relayed,
        s.link_errors,
        s.retransmissions,
        s.conflicts
    );
    if done {
        Ok(())
    } else {
        Err(CliError::Failed(
            "timed out before the team was done".into(),
        ))
    }
}
