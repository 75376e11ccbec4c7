//! `conquest explore`: runs the whole system in the simulator and reports.
//!
//! With no arguments (and so `cargo run --release`), it explores the
//! built-in demo field with all its start poses and the project's best
//! strategy.

use crate::bench::bound::lower_bounds;
use crate::cli::{CliError, ReadArgs, demo_field, load};
use crate::field::Field;
use crate::sim::channel::ChannelFaults;
use crate::sim::robot::BoxedStrategy;
use crate::sim::{Faults, Outcome, SimConfig, Simulation};
use crate::world::Truth;
use core_algo::geometry::Pos;
use core_algo::protocol::message::LocalizeMethod;
use core_algo::team::RobotId;
use core_algo::timing::Timing;
use std::path::PathBuf;

/// The strategy `explore` uses unless told otherwise.
pub const BEST_STRATEGY: &str = "tempo";

mod reporting;
pub use reporting::{Report, RobotReport, finish, report};

/// Arguments of `conquest explore`.
#[derive(clap::Args, Debug, Clone)]
pub struct ExploreArgs {
    /// The field (.field, .sim, .map); without it, the built-in demo field.
    pub field: Option<PathBuf>,
    /// Team size (default: one robot per start pose of the field).
    #[arg(long)]
    pub robots: Option<usize>,
    /// Exploration strategy (see `conquest bench --help` for the list).
    #[arg(long, default_value = BEST_STRATEGY)]
    pub strategy: String,
    /// Seed of every random stream of the run.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Fault: probability that a link loses a frame.
    #[arg(long, default_value_t = 0.0)]
    pub loss: f64,
    /// Fault: probability that a link duplicates a frame.
    #[arg(long, default_value_t = 0.0)]
    pub duplicate: f64,
    /// Fault: probability that a link flips a bit in a frame.
    #[arg(long, default_value_t = 0.0)]
    pub corrupt: f64,
    /// One-way link latency in ms.
    #[arg(long, default_value_t = 10)]
    pub latency_ms: u32,
    /// Fault: robot ID dies at SECONDS, written ID@SECONDS (repeatable).
    #[arg(long, value_parser = parse_kill)]
    pub kill: Vec<(RobotId, u32)>,
    /// Fault: robot ID stalls from SECONDS for DURATION, written
    /// ID@SECONDS+DURATION (repeatable).
    #[arg(long, value_parser = parse_stall)]
    pub stall: Vec<(RobotId, u32, u32)>,
    /// Line speed in motor steps per second (e-puck: up to about 1000).
    #[arg(long, default_value_t = core_algo::timing::DEFAULT_SPEED_STEPS_PER_S)]
    pub speed: u32,
    /// How the robots learn their start poses: `known` (the phone tells
    /// them, the 2010 way), `local` (they localize from adjacent starts,
    /// seed §4.2) or `global` (from any starts, seed §4.3).
    #[arg(long, default_value = "known", value_parser = parse_localize)]
    pub localize: Localize,
    /// Replace the field's start poses by random distinct nodes and
    /// headings drawn from this seed (one per robot): arbitrary starts for
    /// `--localize global`.
    #[arg(long)]
    pub random_starts: Option<u64>,
    /// Give up after this much simulated time, seconds (default: an hour,
    /// or five times the lower bound on fields that need longer; three
    /// times that when localizing).
    #[arg(long)]
    pub max_time_s: Option<f64>,
    /// Pace the run to the wall clock: FACTOR simulated seconds per wall
    /// second (1 without a value), with a progress bar of the nodes known.
    #[arg(long, value_name = "FACTOR", num_args = 0..=1, default_missing_value = "1",
          value_parser = parse_factor)]
    pub realtime: Option<f64>,
    /// Print one JSON object instead of the report.
    #[arg(long)]
    pub json: bool,
    /// Draw the final map to this .svg or .png file.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// How to read the field.
    #[command(flatten)]
    pub read: ReadArgs,
    /// Run N robots as the real firmware emulated in QEMU, with simulated
    /// bodies attached, instead of simulated firmware.
    #[arg(long, value_name = "N")]
    pub qemu: Option<usize>,
    /// The firmware ELF built with `--features qemu` (default:
    /// firmware-rtic/target/firmware-qemu.elf as firmware-rtic/ci.sh writes
    /// it, else cargo's output path).
    #[arg(long, value_name = "PATH")]
    pub qemu_firmware: Option<PathBuf>,
    /// Emulated robots drive this many times faster than real ones (the
    /// report gives times at the real speed).
    #[arg(long, default_value_t = 10)]
    pub qemu_scale: u32,
    /// Give up an emulated run after this many wall-clock seconds.
    #[arg(long, default_value_t = 240)]
    pub qemu_timeout: u32,
}

impl Default for ExploreArgs {
    /// The defaults of the command line (explore the demo field).
    fn default() -> Self {
        #[derive(clap::Parser)]
        struct Wrap {
            #[command(flatten)]
            args: ExploreArgs,
        }
        <Wrap as clap::Parser>::parse_from(["explore"]).args
    }
}

/// How a run's robots learn their start poses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Localize {
    /// The phone tells them.
    Known,
    /// They localize by this method.
    By(LocalizeMethod),
}

impl Localize {
    /// The method, `None` for known poses.
    pub fn method(self) -> Option<LocalizeMethod> {
        match self {
            Localize::Known => None,
            Localize::By(m) => Some(m),
        }
    }

    /// The command line's word for it.
    pub fn name(self) -> &'static str {
        match self {
            Localize::Known => "known",
            Localize::By(LocalizeMethod::Local) => "local",
            Localize::By(LocalizeMethod::Global) => "global",
        }
    }
}

fn parse_localize(s: &str) -> Result<Localize, String> {
    match s {
        "known" => Ok(Localize::Known),
        "local" => Ok(Localize::By(LocalizeMethod::Local)),
        "global" => Ok(Localize::By(LocalizeMethod::Global)),
        _ => Err(format!("expected known, local or global, found '{s}'")),
    }
}

fn parse_factor(s: &str) -> Result<f64, String> {
    let v: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("expected a factor, found '{s}'"))?;
    if !(v.is_finite() && v > 0.0 && v <= 1e6) {
        return Err(format!("expected a factor in (0, 1000000], found '{s}'"));
    }
    Ok(v)
}

fn parse_kill(s: &str) -> Result<(RobotId, u32), String> {
    let (id, at) = s
        .split_once('@')
        .ok_or_else(|| format!("expected ID@SECONDS, found '{s}'"))?;
    Ok((parse_id(id)?, parse_secs(at)?))
}

fn parse_stall(s: &str) -> Result<(RobotId, u32, u32), String> {
    let (id, rest) = s
        .split_once('@')
        .ok_or_else(|| format!("expected ID@SECONDS+DURATION, found '{s}'"))?;
    let (at, dur) = rest
        .split_once('+')
        .ok_or_else(|| format!("expected ID@SECONDS+DURATION, found '{s}'"))?;
    Ok((parse_id(id)?, parse_secs(at)?, parse_secs(dur)?))
}

fn parse_id(s: &str) -> Result<RobotId, String> {
    s.trim()
        .parse::<u8>()
        .map(RobotId)
        .map_err(|_| format!("expected a robot id 0..=255, found '{s}'"))
}

fn parse_secs(s: &str) -> Result<u32, String> {
    let v: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("expected seconds, found '{s}'"))?;
    if !(0.0..=4_000_000.0).contains(&v) {
        return Err(format!("expected seconds in 0..=4000000, found '{s}'"));
    }
    Ok((v * 1000.0).round() as u32)
}

/// Runs a simulation of `field` as the arguments say (paced to the wall
/// clock with `--realtime`).
pub fn simulate(field: &Field, a: &ExploreArgs) -> Result<(Simulation, Outcome, f64), CliError> {
    let mut sim = build(field, a)?;
    let t0 = std::time::Instant::now();
    let outcome = match a.realtime {
        Some(factor) => run_paced(&mut sim, field.nodes().len(), factor),
        None => crate::cores::on_pool(|| sim.run()),
    };
    Ok((sim, outcome, t0.elapsed().as_secs_f64()))
}

/// Runs `sim` no faster than `factor` simulated seconds per wall second:
/// before each step it sleeps until the wall clock has caught up with the
/// simulated time, so a person can watch robots move at their real pace
/// (or faster, or slower). The bar counts the nodes the phone knows of the
/// field's `nodes`; it draws on stderr and hides itself when that is not a
/// terminal. Pacing only delays steps, so the run is the same as unpaced.
pub fn run_paced(sim: &mut Simulation, nodes: usize, factor: f64) -> Outcome {
    use indicatif::{ProgressBar, ProgressStyle};
    use std::time::{Duration, Instant};
    let bar = ProgressBar::new(nodes as u64);
    bar.set_style(
        ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {pos}/{len} nodes {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let start = Instant::now();
    let mut drawn = start;
    let draw = |sim: &Simulation, bar: &ProgressBar| {
        let known = sim
            .env()
            .map()
            .visited()
            .filter(|(_, c)| c.arms().is_some())
            .count();
        bar.set_position(known as u64);
        let home = sim
            .bodies()
            .bodies()
            .iter()
            .zip(sim.field().starts())
            .filter(|(b, s)| b.pos == s.pos)
            .count();
        bar.set_message(format!(
            "simulated {:.1} s, {home}/{} robots home",
            f64::from(sim.now()) / 1000.0,
            sim.bodies().bodies().len()
        ));
    };
    loop {
        let due = Duration::from_secs_f64(f64::from(sim.now()) / 1000.0 / factor);
        if let Some(wait) = due.checked_sub(start.elapsed()) {
            std::thread::sleep(wait);
        }
        if !sim.step() {
            break;
        }
        if drawn.elapsed() >= Duration::from_millis(100) {
            drawn = Instant::now();
            draw(sim, &bar);
        }
    }
    draw(sim, &bar);
    bar.finish();
    sim.outcome()
}

/// Sets up (without running) a simulation of `field` as the arguments say.
pub fn build(field: &Field, a: &ExploreArgs) -> Result<Simulation, CliError> {
    let robots = a.robots.unwrap_or(field.starts().len());
    if crate::bench::strategy(&a.strategy).is_none() {
        return Err(CliError::BadInput(format!(
            "unknown strategy '{}': expected one of {}",
            a.strategy,
            crate::bench::STRATEGIES.join(", ")
        )));
    }
    let config = SimConfig {
        seed: a.seed,
        faults: Faults {
            channel: ChannelFaults {
                loss: a.loss,
                duplicate: a.duplicate,
                corrupt: a.corrupt,
                latency_ms: a.latency_ms,
                jitter_ms: a.latency_ms / 2,
            },
            kill: a.kill.clone(),
            stall: a.stall.clone(),
            cut: Vec::new(),
        },
        speed: a.speed.clamp(1, 2000),
        localize: a.localize.method(),
        max_time_ms: max_time_ms(field, robots, a),
        ..SimConfig::default()
    };
    let name = a.strategy.clone();
    Simulation::new(
        field,
        robots,
        |_| {
            BoxedStrategy(
                crate::bench::strategy(&name)
                    .unwrap_or_else(|| Box::new(core_algo::explore::NearestFrontier)),
            )
        },
        config,
    )
    .map_err(|e| CliError::BadInput(e.to_string()))
}

/// How long a run may take before it is given up, ms: `--max-time-s`, or
/// enough for big fields (the fixed hour used to cut 64×64 mazes short of
/// their own lower bound).
fn max_time_ms(field: &Field, robots: usize, a: &ExploreArgs) -> u32 {
    let secs = a.max_time_s.unwrap_or_else(|| {
        let k = robots.clamp(1, field.starts().len().max(1));
        let timing = Timing::from_hardware(u32::from(field.spacing_mm()), a.speed.clamp(1, 2000));
        let room = (5.0 * lower_bound_s(field, k, timing)).max(3600.0);
        if a.localize.method().is_some() {
            3.0 * room
        } else {
            room
        }
    });
    if secs * 1000.0 > f64::from(MAX_SIM_MS) {
        eprintln!(
            "warning: {} s of simulated time asked for (five times the lower bound, or \
             --max-time-s), but the simulator's clock holds {} s ({:.1} days): a run that \
             needs longer stops there, incomplete",
            secs.round(),
            MAX_SIM_MS / 1000,
            f64::from(MAX_SIM_MS) / 86_400_000.0
        );
    }
    (secs * 1000.0).clamp(1000.0, f64::from(MAX_SIM_MS)) as u32
}

/// The longest run the simulator's millisecond clock holds (u32, with
/// room for wrapping arithmetic on times): about 24.8 days, which a 1024²
/// maze explored by one robot needs more than.
const MAX_SIM_MS: u32 = u32::MAX / 2;

/// The lower bound of the makespan with return home (edge time only) for
/// the first `k` start poses of `field` at `timing`, seconds.
///
/// The bound in edges is remembered for the last field and team asked
/// for: a run asks twice (its time limit, its report), and a 1024² maze's
/// bound takes seconds.
pub fn lower_bound_s(field: &Field, k: usize, timing: Timing) -> f64 {
    use std::hash::{Hash, Hasher};
    use std::sync::Mutex;
    static LAST: Mutex<Option<(u64, u64)>> = Mutex::new(None);
    let starts: Vec<Pos> = field.starts().iter().take(k).map(|s| s.pos).collect();
    let mut h = std::collections::hash_map::DefaultHasher::new();
    (field.nodes(), &starts, k).hash(&mut h);
    let key = h.finish();
    let remembered = LAST
        .lock()
        .ok()
        .and_then(|last| last.filter(|&(seen, _)| seen == key).map(|(_, b)| b));
    let bound = remembered.unwrap_or_else(|| {
        let truth = Truth::new(field.nodes().iter().map(|(p, a)| (*p, *a)));
        let bound = lower_bounds(&truth, &starts, k).with_return;
        if let Ok(mut last) = LAST.lock() {
            *last = Some((key, bound));
        }
        bound
    });
    Timing::seconds(bound * u64::from(timing.edge))
}

/// `conquest explore`.
pub fn run(a: &ExploreArgs) -> Result<(), CliError> {
    let field = match &a.field {
        Some(p) => load(p, a.read)?,
        None => demo_field()?,
    };
    let field = match a.random_starts {
        None => field,
        Some(seed) => {
            let k = a.robots.unwrap_or(field.starts().len());
            let starts = crate::sim::localize::random_starts(&field, k, seed);
            Field::new(field.name(), field.nodes().clone(), starts)
                .map_err(|e| CliError::BadInput(format!("random starts: {e}")))?
        }
    };
    if a.qemu.is_some() {
        if a.localize != Localize::Known {
            return Err(CliError::BadInput(
                "--localize works with the simulator only, not with --qemu".to_string(),
            ));
        }
        return crate::qemu::run(&field, a);
    }
    let (sim, outcome, wall) = simulate(&field, a)?;
    if outcome.timed_out {
        eprintln!(
            "warning: the run was given up at its time limit, {:.0} s of simulated time, \
             before the team was done (raise it with --max-time-s)",
            f64::from(outcome.makespan_ms) / 1000.0
        );
    }
    let r = report(&field, a, sim.bodies().timing(), &outcome, wall);
    finish(&field, a, sim.env(), sim.bodies(), &r, sim.true_to_team())
}
