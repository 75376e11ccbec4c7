//! The `conquest` command line: argument definitions and dispatch.
//!
//! Every command returns a [`CliError`]; `main` prints it as one line and
//! exits with status 2 for bad input (a file that cannot be read as what it
//! claims to be) or 1 for other failures.

use crate::field::{self, Field, LoadOptions, MapReading, ascii, generate::Kind};
use clap::{Args, Parser, Subcommand};
use std::path::{Path, PathBuf};

/// The demo field, built into the binary so that `conquest` runs anywhere.
pub const DEMO_FIELD: &str = include_str!("../../fields/demo.field");

/// e-puck Conquest: cooperative exploration of a grid of lines by up to six
/// e-puck robots, simulated or real.
#[derive(Parser, Debug)]
#[command(name = "conquest", version, about, long_about = None)]
pub struct Cli {
    /// What to do; without a command, explores the demo field.
    #[command(subcommand)]
    pub command: Option<Command>,
}

/// The subcommands.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Explore a field with simulated robots and report (the default).
    Explore(crate::explore_cmd::ExploreArgs),
    /// Run the phone side for real robots on serial ports.
    Connect(crate::connect_cmd::ConnectArgs),
    /// Serve the web UI (Map, Steer, Statistics) for a simulation or for
    /// real robots.
    Serve(crate::serve::ServeArgs),
    /// Check a field file (.field, .sim, .sep, .map) and summarise it.
    Validate(ValidateArgs),
    /// Convert a field between formats (chosen by extension).
    Convert(ConvertArgs),
    /// Draw a field with its start poses to an SVG or PNG file.
    Render(RenderArgs),
    /// Generate a field (maze, rooms, random, open) from a seed.
    Generate(GenerateArgs),
    /// Compare exploration strategies against the lower bound.
    Bench(crate::bench::BenchArgs),
}

/// How to read input fields.
#[derive(Args, Debug, Clone, Copy)]
pub struct ReadArgs {
    /// How Moving AI .map grids become a lattice: `cells` (cells are nodes)
    /// or `corners` (cells are squares of lines).
    #[arg(long, default_value = "cells", value_parser = parse_reading)]
    pub map_reading: MapReading,
}

fn parse_reading(s: &str) -> Result<MapReading, String> {
    s.parse()
}

/// `conquest validate`.
#[derive(Args, Debug)]
pub struct ValidateArgs {
    /// The field file.
    pub file: PathBuf,
    /// Also print the field as a picture.
    #[arg(long)]
    pub show: bool,
    /// How to read the input.
    #[command(flatten)]
    pub read: ReadArgs,
}

/// `conquest convert`.
#[derive(Args, Debug)]
pub struct ConvertArgs {
    /// Input file (.field, .sim, .sep, .map).
    pub input: PathBuf,
    /// Output file (.field, .sim, .sep).
    pub output: PathBuf,
    /// How to read the input.
    #[command(flatten)]
    pub read: ReadArgs,
}

/// `conquest render`.
#[derive(Args, Debug)]
pub struct RenderArgs {
    /// The field file.
    pub file: PathBuf,
    /// The picture to write (.svg or .png).
    #[arg(long, short)]
    pub out: PathBuf,
    /// How to read the input.
    #[command(flatten)]
    pub read: ReadArgs,
}

/// `conquest generate`.
#[derive(Args, Debug)]
pub struct GenerateArgs {
    /// maze, rooms, random or open.
    pub kind: Kind,
    /// Size in nodes, as WIDTHxHEIGHT.
    #[arg(long, default_value = "32x32", value_parser = parse_size)]
    pub size: (u16, u16),
    /// Seed of the random stream.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Number of start poses, packed around the south-west corner (a `.sim`
    /// file holds at most six).
    #[arg(long, default_value_t = 6,
          value_parser = clap::value_parser!(u16).range(1..=core_algo::explore::MAX_ROBOTS as i64))]
    pub starts: u16,
    /// Output file (.field, .sim, .sep); without it, prints native text.
    #[arg(long, short)]
    pub out: Option<PathBuf>,
}

/// Parses `WxH` with both sides in 1..=4096.
pub fn parse_size(s: &str) -> Result<(u16, u16), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("expected WIDTHxHEIGHT such as 32x32, found '{s}'"))?;
    let side = |v: &str| {
        v.trim()
            .parse::<u16>()
            .ok()
            .filter(|n| (1..=4096).contains(n))
            .ok_or_else(|| format!("expected a side of 1..=4096 nodes, found '{v}'"))
    };
    Ok((side(w)?, side(h)?))
}

/// A failed command.
#[derive(Debug)]
pub enum CliError {
    /// The user gave input that cannot be used (exit status 2).
    BadInput(String),
    /// Something else went wrong (exit status 1).
    Failed(String),
}

impl CliError {
    /// The process exit status for this error.
    pub fn exit_code(&self) -> i32 {
        match self {
            CliError::BadInput(_) => 2,
            CliError::Failed(_) => 1,
        }
    }
}

impl std::fmt::Display for CliError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            CliError::BadInput(m) | CliError::Failed(m) => f.write_str(m),
        }
    }
}

impl From<field::FieldError> for CliError {
    fn from(e: field::FieldError) -> Self {
        CliError::BadInput(e.to_string())
    }
}

/// Loads a field for a command.
pub fn load(path: &Path, read: ReadArgs) -> Result<Field, CliError> {
    Ok(field::load_with(
        path,
        LoadOptions {
            map_reading: read.map_reading,
        },
    )?)
}

/// The built-in demo field.
pub fn demo_field() -> Result<Field, CliError> {
    field::native::parse(DEMO_FIELD, "fields/demo.field")
        .map_err(|e| CliError::Failed(format!("built-in demo field: {e}")))
}

/// One line describing a field.
pub fn summary(f: &Field) -> String {
    let b = f.bounds();
    format!(
        "{}: {} nodes, {} edges, {}x{} lattice from {}, {} start(s), spacing {} mm",
        if f.name().is_empty() {
            "(unnamed)"
        } else {
            f.name()
        },
        f.nodes().len(),
        f.edge_count(),
        b.width,
        b.height,
        b.origin,
        f.starts().len(),
        f.spacing_mm()
    )
}

/// Runs a parsed command line.
pub fn run(cli: Cli) -> Result<(), CliError> {
    match cli.command {
        None => {
            let f = demo_field()?;
            crate::outln!("{}", summary(&f));
            crate::out!("{}", ascii::field(&f));
            crate::outln!();
            let args = crate::explore_cmd::ExploreArgs::default();
            crate::explore_cmd::run(&args)?;
            crate::outln!("(see `conquest --help` for every command)");
            Ok(())
        }
        Some(Command::Explore(a)) => crate::explore_cmd::run(&a),
        Some(Command::Connect(a)) => crate::connect_cmd::run(&a),
        Some(Command::Serve(a)) => crate::serve::run(&a),
        Some(Command::Validate(a)) => {
            let f = load(&a.file, a.read)?;
            crate::outln!("{}: ok: {}", a.file.display(), summary(&f));
            if a.show {
                crate::out!("{}", ascii::field(&f));
            }
            Ok(())
        }
        Some(Command::Convert(a)) => {
            let f = load(&a.input, a.read)?;
            field::save(&f, &a.output)?;
            crate::outln!(
                "{} -> {}: {}",
                a.input.display(),
                a.output.display(),
                summary(&f)
            );
            Ok(())
        }
        Some(Command::Render(a)) => {
            let f = load(&a.file, a.read)?;
            crate::render::render(&f, &a.out).map_err(CliError::BadInput)?;
            crate::outln!("{} -> {}", a.file.display(), a.out.display());
            Ok(())
        }
        Some(Command::Bench(a)) => {
            crate::bench::main(a).map_err(|e| CliError::Failed(e.to_string()))
        }
        Some(Command::Generate(a)) => {
            let f = a.kind.generate(a.size.0, a.size.1, a.seed);
            let starts = field::default_starts(f.nodes(), usize::from(a.starts));
            let f = f
                .with_starts(starts)
                .map_err(|e| CliError::Failed(e.to_string()))?;
            match a.out {
                Some(out) => {
                    field::save(&f, &out)?;
                    crate::outln!("{}: {}", out.display(), summary(&f));
                }
                None => crate::out!("{}", field::native::write(&f)),
            }
            Ok(())
        }
    }
}
