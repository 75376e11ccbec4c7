//! `conquest bench`: every strategy on the same fields and robot counts,
//! through the node-level model, against the lower bound.
//!
//! Why one runner: strategies can only be compared on one simulator, one
//! timing and one completion rule. The runner writes the CSV (columns fixed
//! by the issue), a markdown summary and an SVG plot of makespan / lower
//! bound against team size, one line per strategy.

pub mod bound;
mod report;

use crate::cores::HOST_CORES;
use crate::field::Field;
use crate::field::generate::Kind;
use crate::world::{self, DynStrategy, RunStats, Truth, WorldConfig};
use core_algo::explore::{
    Assignment, AssignmentObjective, BurgardGreedy, GreedyClaim, InOrder, Legacy2010, MinPos,
    NearestFrontier, SeedExplorer, Tempo, TempoConfig, Workers,
};
use core_algo::geometry::{Heading, Pos};
use core_algo::timing::{DEFAULT_NODE_SPACING_MM, DEFAULT_SPEED_STEPS_PER_S, Ticks, Timing};
use indicatif::{ProgressBar, ProgressStyle};
use std::path::PathBuf;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

pub use report::{csv, markdown, paired, svg_plot};

/// The strategies the benchmark knows, in table order, by name.
pub const STRATEGIES: [&str; 9] = [
    "nearest",
    "claim",
    "seed",
    "legacy2010",
    "burgard",
    "hungarian",
    "bottleneck",
    "minpos",
    "tempo",
];

/// A fresh strategy by name, for one run at a time: its searches may use
/// every core (see [`crate::cores`]).
pub fn strategy(name: &str) -> Option<Box<DynStrategy>> {
    strategy_on(name, &HOST_CORES)
}

/// A fresh strategy by name whose searches run on `workers`: one core
/// ([`InOrder`]) where the caller already keeps every core busy with runs
/// of its own, as `conquest bench` does.
pub fn strategy_on(name: &str, workers: &'static dyn Workers) -> Option<Box<DynStrategy>> {
    Some(match name {
        "nearest" => Box::new(NearestFrontier),
        "claim" => Box::new(GreedyClaim),
        "seed" => Box::new(SeedExplorer::default()),
        "legacy2010" => Box::new(Legacy2010),
        "burgard" => Box::new(BurgardGreedy::default()),
        "hungarian" => Box::new(Assignment {
            objective: AssignmentObjective::MinSum,
        }),
        "bottleneck" => Box::new(Assignment {
            objective: AssignmentObjective::MinMax,
        }),
        "minpos" => Box::new(MinPos),
        "tempo" => Box::new(Tempo::default().with_workers(workers)),
        other => {
            // `tempo:<deduce edges>:<endgame 0|1>:<idle: 0 trail, 1 home, 2 stay>:<spread>:<squared 0|1>[:<trail edges>[:<home pull %>[:<trail team>[:<keep share 0|1>[:<trail far, nodes per robot>[:<share slack, map changes>[:<corridor keeps share 0|1>[:<tie-break team>[:<crowd penalty edges>[:<crowd radius>[:<far keeps share, edges>[:<its team>[:<far nearer>[:<cluster radius, edges>[:<its team>[:<far busy, nodes per robot>[:<corridor extends share, team above>]]]]]]]]]]]]]]]]]`
            // for ablations; a field left out is off (keep share and
            // corridor keeps share: on; the crowd radius: 4).
            let rest = other.strip_prefix("tempo:")?;
            let v: Vec<u32> = rest
                .split(':')
                .map(|x| x.parse().ok())
                .collect::<Option<_>>()?;
            // The values of the fields left out: off (a tie-break team of
            // u32::MAX: no team breaks ties), but no team limit on
            // trailing, and keep share and corridor keeps share on.
            #[rustfmt::skip]
            let mut x: [u32; 22] = [0, 0, 0, 0, 0, 0, 0, u32::MAX, 1, 0, 0, 1, u32::MAX, 0, 4, 0, 6, 0, 0, 6, 0, u32::MAX];
            if !(5..=x.len()).contains(&v.len()) {
                return None;
            }
            x.get_mut(..v.len())?.copy_from_slice(&v);
            #[rustfmt::skip]
            let [d, e, i, s, q, t, h, k, c, f, l, r, b, cp, cr, fk, ft, fe, cl, ct, fb, ce] = x;
            Box::new(
                Tempo::new(TempoConfig {
                    keep_share: c != 0,
                    deduce_penalty_edges: d,
                    endgame_return: e != 0,
                    idle_home: i != 0,
                    idle_stay: i == 2,
                    spread: s,
                    squared: q != 0,
                    trail_edges: t,
                    trail_team: usize::try_from(k).unwrap_or(usize::MAX),
                    home_pull_pct: h,
                    trail_far_nodes_per_robot: f,
                    share_slack: l,
                    corridor_keeps_share: r != 0,
                    tie_break_team: usize::try_from(b).unwrap_or(usize::MAX),
                    crowd_penalty_edges: cp,
                    crowd_radius: cr,
                    far_keeps_share: fk,
                    far_keeps_share_team: usize::try_from(ft).unwrap_or(usize::MAX),
                    far_nearer: fe,
                    far_busy_nodes_per_robot: fb,
                    cluster_radius: cl,
                    cluster_team: usize::try_from(ct).unwrap_or(usize::MAX),
                    corridor_extends_team: usize::try_from(ce).unwrap_or(usize::MAX),
                    ..TempoConfig::default()
                })
                .with_workers(workers),
            )
        }
    })
}

/// Arguments of `conquest bench`.
#[derive(clap::Args, Debug, Clone)]
pub struct BenchArgs {
    /// Field files (.sim, native, .map) or folders of them; default: the
    /// generated maze, rooms, random and open fields of each `--sizes`.
    pub inputs: Vec<PathBuf>,
    /// Robot counts to run.
    #[arg(long, value_delimiter = ',', default_values_t = [1usize, 2, 3, 4, 5, 6])]
    pub robots: Vec<usize>,
    /// Strategies to run (default: all).
    #[arg(long, value_delimiter = ',')]
    pub strategy: Vec<String>,
    /// Side lengths of the generated fields.
    #[arg(long, value_delimiter = ',', default_values_t = [32u16, 64])]
    pub sizes: Vec<u16>,
    /// Seed of the generated fields (the first one with `--seeds`).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// How many generated fields of each kind and size, with seeds
    /// `--seed`, `--seed`+1, ...: one field per kind says little when a
    /// single decision can change a run by 10 %, so comparisons want many.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u64).range(1..=10_000))]
    pub seeds: u64,
    /// Node spacing in millimetres (sets the edge time).
    #[arg(long, default_value_t = DEFAULT_NODE_SPACING_MM)]
    pub spacing_mm: u32,
    /// Write the CSV here instead of stdout.
    #[arg(long)]
    pub csv: Option<PathBuf>,
    /// Folder for the markdown table and the plot.
    #[arg(long, default_value = "docs/results")]
    pub out: PathBuf,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub jobs: Option<usize>,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
    /// Which model runs the teams: `world` (the node-level model: shared
    /// map, no bodies; fast) or `system` (the whole system simulator:
    /// agents behind real links, bodies that collide, homecoming).
    #[arg(long, default_value = "world", value_parser = ["world", "system"])]
    pub model: String,
}

/// Runs one team through the whole system simulator (agents behind real
/// links, bodies, relaying) and reports it as the benchmark counts.
pub fn run_system(
    f: &BenchField,
    k: usize,
    name: &str,
    spacing_mm: u32,
    workers: &'static dyn Workers,
) -> Result<RunStats, String> {
    use crate::sim::robot::BoxedStrategy;
    use crate::sim::{SimConfig, Simulation};
    let nodes: std::collections::BTreeMap<Pos, core_algo::geometry::Arms> = f
        .truth
        .indices()
        .filter_map(|i| f.truth.arms_at(i).map(|a| (f.truth.bounds().pos(i), a)))
        .collect();
    let starts = f
        .starts
        .iter()
        .map(|&(pos, heading)| crate::field::StartPose { pos, heading })
        .collect();
    let field = crate::field::Field::new(f.name.clone(), nodes, starts)
        .map_err(|e| format!("{}: {e}", f.name))?
        .with_spacing_mm(spacing_mm.clamp(1, u32::from(u16::MAX)) as u16);
    if strategy(name).is_none() {
        return Err(format!("unknown strategy {name}"));
    }
    // The same time limit as `conquest explore`: five times the lower
    // bound, at least an hour (a fixed hour cut large mazes short).
    let timing = core_algo::timing::Timing::from_hardware(
        spacing_mm,
        core_algo::timing::DEFAULT_SPEED_STEPS_PER_S,
    );
    let room_s = (5.0 * crate::explore_cmd::lower_bound_s(&field, k, timing)).max(3600.0);
    let config = SimConfig {
        max_time_ms: (room_s * 1000.0).clamp(1000.0, f64::from(u32::MAX / 2)) as u32,
        ..SimConfig::default()
    };
    let mut sim = Simulation::new(
        &field,
        k,
        |_| {
            let s = strategy_on(name, workers);
            BoxedStrategy(s.unwrap_or_else(|| Box::new(NearestFrontier)))
        },
        config,
    )
    .map_err(|e| format!("{}: {e}", f.name))?;
    let o = sim.run();
    let visited = sim.env().map().visited_len();
    Ok(RunStats {
        complete: o.complete,
        makespan: o.makespan_ms.div_ceil(core_algo::timing::TICK_MS),
        edges: o.robots.iter().map(|r| r.driven_edges).collect(),
        turns: o.robots.iter().map(|r| r.quarter_turns).collect(),
        revisits: o.robots.iter().map(|r| r.revisits).sum(),
        decisions: o.messages,
        deduced: field.nodes().len().saturating_sub(visited),
        mapped: o
            .mapped_ms
            .map(|ms| ms.div_ceil(core_algo::timing::TICK_MS)),
    })
}

/// One field of the benchmark with its start poses.
#[derive(Clone, Debug)]
pub struct BenchField {
    /// Name for the `map` column.
    pub name: String,
    /// The field.
    pub truth: Truth,
    /// Start poses; a run with k robots uses the first k.
    pub starts: Vec<(Pos, Heading)>,
}

/// One row of results.
#[derive(Clone, Debug)]
pub struct Row {
    /// Field name.
    pub map: String,
    /// Team size.
    pub robots: usize,
    /// Strategy name.
    pub strategy: String,
    /// The run's statistics.
    pub stats: RunStats,
    /// Lower bound with return, in edges.
    pub lower_bound_edges: u64,
    /// The edge time used.
    pub timing: Timing,
}

impl Row {
    /// Makespan in seconds.
    pub fn makespan_s(&self) -> f64 {
        Timing::seconds(u64::from(self.stats.makespan))
    }

    /// Lower bound in seconds (edge time only).
    pub fn lower_bound_s(&self) -> f64 {
        Timing::seconds(self.lower_bound_edges * u64::from(self.timing.edge))
    }

    /// makespan / lower bound in time.
    pub fn ratio(&self) -> f64 {
        self.makespan_s() / self.lower_bound_s().max(f64::MIN_POSITIVE)
    }

    /// busiest robot's edges / lower bound in edges.
    pub fn edge_ratio(&self) -> f64 {
        f64::from(self.stats.max_edges()) / (self.lower_bound_edges.max(1) as f64)
    }
}

/// Runs every (field, robots, strategy) job, in parallel, in a
/// deterministic output order.
pub fn run_jobs(
    fields: &[BenchField],
    robots: &[usize],
    strategies: &[String],
    timing: Timing,
    jobs: usize,
    progress: bool,
    system: Option<u32>,
) -> Result<Vec<Row>, String> {
    let mut list = Vec::new();
    for (fi, f) in fields.iter().enumerate() {
        for &k in robots {
            if k == 0 || k > f.starts.len() {
                continue;
            }
            let starts: Vec<Pos> = f.starts.iter().take(k).map(|s| s.0).collect();
            let lb = bound::lower_bounds(&f.truth, &starts, k).with_return;
            for s in strategies {
                list.push((fi, k, s.clone(), lb));
            }
        }
    }
    let bar = if progress {
        let b = ProgressBar::new(list.len() as u64);
        b.set_style(
            ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {pos}/{len} {msg}")
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        b
    } else {
        ProgressBar::hidden()
    };
    // Runs on every core already keep them busy; a run's searches fanned
    // out too only paid the hand-over (the 800-run system bench: 3.7 s
    // against 4.8 s).
    let workers: &'static dyn Workers = if jobs > 1 { &InOrder } else { &HOST_CORES };
    let next = AtomicUsize::new(0);
    let results: Mutex<Vec<Option<Result<Row, String>>>> = Mutex::new(vec![None; list.len()]);
    std::thread::scope(|scope| {
        for _ in 0..jobs.max(1) {
            scope.spawn(|| {
                loop {
                    let n = next.fetch_add(1, Ordering::Relaxed);
                    let Some((fi, k, name, lb)) = list.get(n) else {
                        break;
                    };
                    let f = &fields[*fi];
                    let out = match (strategy_on(name, workers), system) {
                        (None, _) => Err(format!("unknown strategy {name}")),
                        (Some(_), Some(spacing)) => {
                            run_system(f, *k, name, spacing, workers).map(|stats| Row {
                                map: f.name.clone(),
                                robots: *k,
                                strategy: name.clone(),
                                stats,
                                lower_bound_edges: *lb,
                                timing,
                            })
                        }
                        (Some(mut s), None) => world::run(
                            &f.truth,
                            &f.starts[..*k],
                            s.as_mut(),
                            WorldConfig {
                                timing,
                                ..WorldConfig::default()
                            },
                        )
                        .map(|stats| Row {
                            map: f.name.clone(),
                            robots: *k,
                            strategy: name.clone(),
                            stats,
                            lower_bound_edges: *lb,
                            timing,
                        })
                        .map_err(|e| format!("{} k={k} {name}: {e}", f.name)),
                    };
                    bar.set_message(format!("{} k={k} {name}", f.name));
                    bar.inc(1);
                    if let Ok(mut r) = results.lock() {
                        r[n] = Some(out);
                    }
                }
            });
        }
    });
    bar.finish_and_clear();
    let results = results.into_inner().map_err(|e| e.to_string())?;
    results
        .into_iter()
        .map(|r| r.unwrap_or_else(|| Err("job lost".into())))
        .collect()
}

/// The project's generated default fields: maze, rooms, random and open of
/// each size, with their six starts, for `seeds` seeds from `seed` on. With
/// one seed the names are `kind-size`, with more `kind-size-sSEED`.
pub fn default_fields(sizes: &[u16], seed: u64, seeds: u64) -> Vec<BenchField> {
    let mut out = Vec::new();
    for &n in sizes {
        for kind in Kind::ALL {
            for s in seed..seed.saturating_add(seeds.max(1)) {
                let f = kind.generate(n, n, s);
                let name = if seeds > 1 {
                    format!("{}-{n}-s{s}", kind.name())
                } else {
                    format!("{}-{n}", kind.name())
                };
                out.push(BenchField::from_field(&f, name));
            }
        }
    }
    out
}

impl BenchField {
    /// A benchmark field from a validated field.
    pub fn from_field(f: &Field, name: String) -> BenchField {
        BenchField {
            name,
            truth: Truth::new(f.nodes().iter().map(|(p, a)| (*p, *a))),
            starts: f.starts().iter().map(|s| (s.pos, s.heading)).collect(),
        }
    }
}

/// `conquest bench`.
pub fn main(args: BenchArgs) -> Result<(), Box<dyn std::error::Error>> {
    let timing = Timing::from_hardware(args.spacing_mm, DEFAULT_SPEED_STEPS_PER_S);
    let strategies: Vec<String> = if args.strategy.is_empty() {
        STRATEGIES.iter().map(|s| s.to_string()).collect()
    } else {
        args.strategy.clone()
    };
    for s in &strategies {
        if strategy(s).is_none() {
            return Err(format!("unknown strategy {s}; known: {}", STRATEGIES.join(",")).into());
        }
    }
    let fields = if args.inputs.is_empty() {
        default_fields(&args.sizes, args.seed, args.seeds)
    } else {
        load_inputs(&args.inputs)?
    };
    let jobs = args
        .jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    let rows = run_jobs(
        &fields,
        &args.robots,
        &strategies,
        timing,
        jobs,
        !args.quiet,
        (args.model == "system").then_some(args.spacing_mm),
    )?;
    let text = csv(&rows);
    match &args.csv {
        Some(p) => {
            if let Some(dir) = p.parent().filter(|d| !d.as_os_str().is_empty()) {
                std::fs::create_dir_all(dir)?;
            }
            std::fs::write(p, &text)?
        }
        None => crate::out!("{text}"),
    }
    std::fs::create_dir_all(&args.out)?;
    std::fs::write(args.out.join("bench.md"), markdown(&rows, &strategies))?;
    std::fs::write(args.out.join("bench.svg"), svg_plot(&rows, &strategies))?;
    Ok(())
}

/// Loads field files and the field files of folders (sorted by name).
fn load_inputs(inputs: &[PathBuf]) -> Result<Vec<BenchField>, Box<dyn std::error::Error>> {
    let mut files = Vec::new();
    for p in inputs {
        if p.is_dir() {
            let mut inner: Vec<PathBuf> = std::fs::read_dir(p)?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|f| {
                    f.extension()
                        .and_then(|x| x.to_str())
                        .is_some_and(|x| ["sim", "sep", "field", "map"].contains(&x))
                })
                .collect();
            inner.sort();
            files.extend(inner);
        } else {
            files.push(p.clone());
        }
    }
    let mut out = Vec::new();
    for f in files {
        let field = crate::field::load(&f).map_err(|e| e.to_string())?;
        let mut bf = BenchField::from_field(&field, field.name().to_string());
        if bf.starts.is_empty() {
            bf.starts = crate::field::default_starts(field.nodes(), 6)
                .iter()
                .map(|s| (s.pos, s.heading))
                .collect();
        }
        out.push(bf);
    }
    Ok(out)
}

/// Ticks per edge of a timing, for reports.
pub fn edge_ticks(t: Timing) -> Ticks {
    t.edge
}
