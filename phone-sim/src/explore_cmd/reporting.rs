//! What `conquest explore` prints: the report (text or one JSON object)
//! and the drawn map.

use super::{ExploreArgs, lower_bound_s};
use crate::cli::CliError;
use crate::environment::Environment;
use crate::field::{Field, ascii};
use crate::sim::Outcome;
use crate::sim::body::Bodies;
use core_algo::geometry::Pos;
use core_algo::timing::Timing;
use serde::Serialize;

/// Per-robot figures in the report.
#[derive(Serialize, Debug)]
pub struct RobotReport {
    /// Robot id.
    pub id: u8,
    /// Survived the run.
    pub alive: bool,
    /// Nodes it reported first.
    pub explored: u32,
    /// Edges it drove.
    pub driven: u32,
    /// explored / driven.
    pub explored_driven_ratio: f64,
    /// Arrivals at nodes it had visited before.
    pub revisits: u32,
    /// Quarter turns.
    pub quarter_turns: u32,
    /// Collisions.
    pub collisions: u32,
}

/// The machine-readable result of `conquest explore --json`.
#[derive(Serialize, Debug)]
pub struct Report {
    /// Field name.
    pub field: String,
    /// Strategy name.
    pub strategy: String,
    /// Team size.
    pub robots: usize,
    /// Seed.
    pub seed: u64,
    /// Every reachable node's shape known (seed rule), the map right, every
    /// living robot home.
    pub complete: bool,
    /// The phone's map equals the true field.
    pub map_correct: bool,
    /// Every living robot home.
    pub all_home: bool,
    /// Until the team was done, seconds.
    pub makespan_s: f64,
    /// Until the phone's map was complete, seconds (the rest of the
    /// makespan is the way home; `null`: the map never was).
    pub mapped_s: Option<f64>,
    /// The run was given up at its time limit (`--max-time-s`) before the
    /// team was done.
    pub timed_out: bool,
    /// Lower bound with return to the starts (edge time only), seconds.
    pub lower_bound_s: f64,
    /// makespan / lower bound.
    pub ratio: f64,
    /// Messages the phone received.
    pub messages: u64,
    /// Messages the phone relayed.
    pub relayed: u64,
    /// Frames put on the links.
    pub frames_sent: u64,
    /// Frames the links lost.
    pub frames_lost: u64,
    /// Frames sent again.
    pub retransmissions: u64,
    /// Conflicting reports.
    pub conflicts: u64,
    /// How the robots learned their poses: known, local or global.
    pub localize: String,
    /// Until the last robot joined the team frame, seconds (`null`: poses
    /// were known, or localization did not finish).
    pub localize_s: Option<f64>,
    /// Every robot's pose relative to robot 0 right (`null`: poses were
    /// known).
    pub poses_correct: Option<bool>,
    /// Why localization gave up, if it did.
    pub localize_failure: Option<String>,
    /// Moves the team made while localizing.
    pub localize_moves: Option<u32>,
    /// Wall time of the simulation, seconds.
    pub wall_s: f64,
    /// Team-mate searches taken over from the host's memo rather than
    /// searched again, since the process started (see `phone_sim::memo`).
    pub searches_taken_over: u64,
    /// Of those, the searches taken over in part: up to the first node
    /// that read otherwise, searched on from there.
    pub searches_taken_over_in_part: u64,
    /// Rests of searches taken over: later rounds of a team mate's picks
    /// that went on where its field stood (`SearchMemo::record_after`).
    pub searches_taken_over_after: u64,
    /// Searches written down into the memo, since the process started.
    pub searches_recorded: u64,
    /// Rests of searches written down: later rounds of a team mate's
    /// picks, resumed where a kept record stopped.
    pub searches_recorded_after: u64,
    /// The endgame's column searches lent to a robot from the team's store
    /// (see `phone_sim::columns`), since the process started.
    pub column_searches_lent: u64,
    /// Column searches given back to the store.
    pub column_searches_given: u64,
    /// Per robot.
    pub per_robot: Vec<RobotReport>,
}

/// The report of a finished run whose bodies moved with `timing`.
pub fn report(field: &Field, a: &ExploreArgs, timing: Timing, o: &Outcome, wall_s: f64) -> Report {
    let k = o.robots.len();
    let lower_bound_s = lower_bound_s(field, k, timing);
    let makespan_s = f64::from(o.makespan_ms) / 1000.0;
    let memo = crate::cores::HOST_CORES.memo().counts();
    let (lent, given) = crate::cores::HOST_CORES.columns().counts();
    Report {
        field: field.name().to_string(),
        strategy: a.strategy.clone(),
        robots: k,
        seed: a.seed,
        complete: o.complete,
        map_correct: o.map_correct,
        all_home: o.all_home,
        makespan_s,
        mapped_s: o.mapped_ms.map(|ms| f64::from(ms) / 1000.0),
        timed_out: o.timed_out,
        lower_bound_s,
        ratio: makespan_s / lower_bound_s.max(f64::MIN_POSITIVE),
        messages: o.messages,
        relayed: o.relayed,
        frames_sent: o.frames_sent,
        frames_lost: o.frames_lost,
        retransmissions: o.retransmissions,
        conflicts: o.conflicts,
        localize: a.localize.name().to_string(),
        localize_s: o
            .localization
            .as_ref()
            .and_then(|l| l.localized_ms)
            .map(|ms| f64::from(ms) / 1000.0),
        poses_correct: o.localization.as_ref().map(|l| l.poses_correct),
        localize_failure: o
            .localization
            .as_ref()
            .and_then(|l| l.failure)
            .map(|f| format!("{f:?}")),
        localize_moves: o.localization.as_ref().map(|l| l.moves),
        wall_s,
        searches_taken_over: memo.taken_over,
        searches_taken_over_in_part: memo.in_part,
        searches_taken_over_after: memo.after,
        searches_recorded: memo.recorded,
        searches_recorded_after: memo.recorded_after,
        column_searches_lent: lent,
        column_searches_given: given,
        per_robot: o
            .robots
            .iter()
            .map(|r| RobotReport {
                id: r.id.0,
                alive: r.alive,
                explored: r.explored,
                driven: r.driven_edges,
                explored_driven_ratio: f64::from(r.explored) / f64::from(r.driven_edges.max(1)),
                revisits: r.revisits,
                quarter_turns: r.quarter_turns,
                collisions: r.collisions,
            })
            .collect(),
    }
}

/// Prints the report (or its JSON) and draws the map if asked: the end of
/// every `explore` run, simulated or emulated.
pub fn finish(
    field: &Field,
    a: &ExploreArgs,
    env: &Environment,
    bodies: &Bodies,
    r: &Report,
    to_team: core_algo::localize::Frame,
) -> Result<(), CliError> {
    if a.json {
        let text = serde_json::to_string(r).map_err(|e| CliError::Failed(e.to_string()))?;
        crate::outln!("{text}");
    } else {
        print_report(env, bodies, r, to_team);
    }
    if let Some(out) = &a.out {
        let known: Vec<(Pos, core_algo::geometry::Arms)> = env
            .map()
            .visited()
            .filter_map(|(p, c)| c.arms().map(|a| (p, a)))
            .collect();
        let map_field = Field::new(
            format!("{} (explored)", field.name()),
            known.into_iter().collect(),
            field
                .starts()
                .iter()
                .take(r.robots)
                .map(|s| crate::field::StartPose {
                    pos: to_team.pos(s.pos),
                    heading: to_team.heading(s.heading),
                })
                .collect(),
        )
        .map_err(|e| CliError::Failed(format!("explored map: {e}")))?;
        crate::render::render(&map_field, out).map_err(CliError::Failed)?;
    }
    Ok(())
}

fn print_report(
    env: &Environment,
    bodies: &Bodies,
    r: &Report,
    to_team: core_algo::localize::Frame,
) {
    let nodes: std::collections::BTreeMap<_, _> = env
        .map()
        .visited()
        .filter_map(|(p, c)| c.arms().map(|a| (p, a)))
        .collect();
    let marks: Vec<(Pos, char)> = bodies
        .bodies()
        .iter()
        .map(|b| (to_team.pos(b.pos), ascii::arrow(to_team.heading(b.heading))))
        .collect();
    crate::outln!(
        "explored map of {} ({} robots, strategy {}, seed {}):",
        r.field,
        r.robots,
        r.strategy,
        r.seed
    );
    crate::out!("{}", ascii::nodes(&nodes, &marks));
    crate::outln!();
    crate::outln!(
        "complete: {} (map correct: {}, all home: {})",
        r.complete,
        r.map_correct,
        r.all_home
    );
    if let Some(correct) = r.poses_correct {
        let took = r
            .localize_s
            .map_or_else(|| "did not finish".to_string(), |s| format!("{s:.1} s"));
        crate::outln!(
            "localization {}: {took}, {} moves, poses correct: {correct}{}",
            r.localize,
            r.localize_moves.unwrap_or(0),
            r.localize_failure
                .as_ref()
                .map(|f| format!(" (gave up: {f})"))
                .unwrap_or_default()
        );
    }
    crate::outln!(
        "makespan {:.1} s ({}), lower bound {:.1} s, ratio {:.2}; simulated in {:.3} s",
        r.makespan_s,
        r.mapped_s.map_or_else(
            || "the map was never complete".to_string(),
            |s| format!("map complete at {s:.1} s")
        ),
        r.lower_bound_s,
        r.ratio,
        r.wall_s
    );
    if r.searches_taken_over + r.searches_recorded > 0 {
        crate::outln!(
            "team-mate searches: {} taken over ({} in part), {} written down; \
             rests of them: {} taken over, {} written down",
            r.searches_taken_over,
            r.searches_taken_over_in_part,
            r.searches_recorded,
            r.searches_taken_over_after,
            r.searches_recorded_after
        );
    }
    if r.column_searches_given > 0 {
        crate::outln!(
            "endgame column searches: {} lent from the team's store, {} given back",
            r.column_searches_lent,
            r.column_searches_given
        );
    }
    crate::outln!(
        "messages {} received, {} relayed; frames {} sent, {} lost, {} retransmitted; {} conflicts",
        r.messages,
        r.relayed,
        r.frames_sent,
        r.frames_lost,
        r.retransmissions,
        r.conflicts
    );
    crate::outln!("robot  alive  explored  driven  expl/driven  revisits  turns  collisions");
    for p in &r.per_robot {
        crate::outln!(
            "{:>5}  {:>5}  {:>8}  {:>6}  {:>11.2}  {:>8}  {:>5}  {:>10}",
            p.id,
            p.alive,
            p.explored,
            p.driven,
            p.explored_driven_ratio,
            p.revisits,
            p.quarter_turns,
            p.collisions
        );
    }
}
