//! `conquest serve`: the web UI (Map, Steer, Statistics) over HTTP and a
//! WebSocket, for a simulation or for real robots.
//!
//! One thread runs the [`Session`] (the model and the
//! team); the async side only routes requests to it and fans its pushes out
//! to every page. The page itself is three files built into the binary, so
//! it needs nothing from the internet and works on a phone on the same
//! network (`--bind 0.0.0.0`).

pub mod api;
pub mod files;
mod routes;
pub mod session;
pub mod team;

use crate::cli::{CliError, ReadArgs, demo_field, load};
use crate::field::Field;
use crate::field::generate::Kind;
use session::{Request, RunSpec, Session};
use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::{Arc, mpsc};
use team::Team;
use tokio::sync::broadcast;

/// Arguments of `conquest serve`.
#[derive(clap::Args, Debug, Clone)]
pub struct ServeArgs {
    /// Field of the first simulation (.field, .sim, .sep, .map); default:
    /// the built-in demo field. With --connect: the field the robots stand
    /// on.
    #[arg(long)]
    pub field: Option<PathBuf>,
    /// Team size of the first simulation (default: one per start pose).
    #[arg(long)]
    pub robots: Option<usize>,
    /// Strategy of the first simulation.
    #[arg(long, default_value = crate::explore_cmd::BEST_STRATEGY)]
    pub strategy: String,
    /// Seed of the first simulation.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Real robots on these serial ports (robot i on the i-th) instead of
    /// a simulation.
    #[arg(long, num_args = 1..)]
    pub connect: Vec<String>,
    /// Line speed of real robots, motor steps per second.
    #[arg(long, default_value_t = 600)]
    pub speed: u16,
    /// TCP port; 0 picks a free one (the address is printed).
    #[arg(long, default_value_t = 8080)]
    pub port: u16,
    /// Address to listen on; 0.0.0.0 lets a phone on the network connect.
    #[arg(long, default_value = "127.0.0.1")]
    pub bind: std::net::IpAddr,
    /// How to read the field.
    #[command(flatten)]
    pub read: ReadArgs,
}

/// What the HTTP handlers share.
#[derive(Clone)]
pub struct AppState {
    /// Requests to the session thread.
    pub requests: mpsc::Sender<Request>,
    /// Pushes from the session thread.
    pub push: broadcast::Sender<Arc<str>>,
}

/// The fields a page can choose: the one given, the demo field, and a few
/// generated ones of different character.
pub fn library(first: Option<Field>) -> Result<Vec<Field>, CliError> {
    let mut fields = Vec::new();
    if let Some(f) = first {
        fields.push(f);
    }
    let demo = demo_field()?;
    if !fields.iter().any(|f| f.name() == demo.name()) {
        fields.push(demo);
    }
    for (kind, w, h) in [
        (Kind::Maze, 8, 8),
        (Kind::Random, 12, 12),
        (Kind::Open, 6, 6),
        (Kind::Rooms, 24, 16),
        (Kind::Maze, 24, 24),
    ] {
        let f = kind.generate(w, h, 1);
        let f = f.with_name(format!("{} {w}x{h}", kind.name()));
        if !f.starts().is_empty() {
            fields.push(f);
        }
    }
    Ok(fields)
}

/// Starts the session thread for `a`; returns the handle the HTTP side
/// uses.
pub fn start_session(a: &ServeArgs) -> Result<AppState, CliError> {
    let first = match &a.field {
        Some(p) => Some(load(p, a.read)?),
        None => None,
    };
    let library = library(first)?;
    let Some(field) = library.first().cloned() else {
        return Err(CliError::Failed("no field to run".into()));
    };
    let robots = a
        .robots
        .unwrap_or(if a.connect.is_empty() {
            field.starts().len()
        } else {
            a.connect.len()
        })
        .clamp(1, field.starts().len().max(1));
    if crate::bench::strategy(&a.strategy).is_none() {
        return Err(CliError::BadInput(format!(
            "unknown strategy '{}': expected one of {}",
            a.strategy,
            crate::bench::STRATEGIES.join(", ")
        )));
    }
    let spec = RunSpec {
        field: field.name().to_string(),
        robots,
        strategy: a.strategy.clone(),
        seed: a.seed,
    };
    let (push, _) = broadcast::channel(256);
    let (tx, rx) = mpsc::channel();
    let push2 = push.clone();
    let connect = a.connect.clone();
    let speed = a.speed;
    let (ready_tx, ready_rx) = mpsc::channel();
    // The team is built in its thread: strategies are not `Send`.
    std::thread::Builder::new()
        .name("session".into())
        .spawn(move || {
            let team = if connect.is_empty() {
                Team::simulate(&field, &spec)
            } else {
                Team::connect(&field, &connect, speed)
            };
            match team {
                Ok(team) => {
                    let _ = ready_tx.send(Ok(()));
                    Session::new(library, spec, team, push2).run(rx);
                }
                Err(e) => {
                    let _ = ready_tx.send(Err(e));
                }
            }
        })
        .map_err(|e| CliError::Failed(format!("cannot start the session thread: {e}")))?;
    match ready_rx.recv() {
        Ok(Ok(())) => Ok(AppState { requests: tx, push }),
        Ok(Err(e)) => Err(CliError::BadInput(e)),
        Err(_) => Err(CliError::Failed("the session thread ended".into())),
    }
}

/// `conquest serve`.
pub fn run(a: &ServeArgs) -> Result<(), CliError> {
    let state = start_session(a)?;
    let rt = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .map_err(|e| CliError::Failed(format!("cannot start the async runtime: {e}")))?;
    rt.block_on(async move {
        let addr = SocketAddr::new(a.bind, a.port);
        let listener = tokio::net::TcpListener::bind(addr)
            .await
            .map_err(|e| CliError::BadInput(format!("cannot listen on {addr}: {e}")))?;
        let local = listener
            .local_addr()
            .map_err(|e| CliError::Failed(format!("no local address: {e}")))?;
        // Tests and scripts read this line to find the port.
        crate::outln!("conquest serve: listening on http://{local}/");
        use std::io::Write as _;
        let _ = std::io::stdout().flush();
        axum::serve(listener, routes::router(state))
            .with_graceful_shutdown(async {
                let _ = tokio::signal::ctrl_c().await;
            })
            .await
            .map_err(|e| CliError::Failed(format!("server: {e}")))
    })
}
