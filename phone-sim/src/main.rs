//! `conquest`: see `conquest --help`.

use clap::Parser;
use phone_sim::cli::{Cli, run};

fn main() {
    let cli = Cli::parse();
    if let Err(e) = run(cli) {
        eprintln!("conquest: error: {e}");
        std::process::exit(e.exit_code());
    }
}
