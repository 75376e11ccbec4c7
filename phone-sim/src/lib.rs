//! # phone-sim
//!
//! The phone side and the simulator of e-puck Conquest, behind the binary
//! `conquest`: field files and generators ([`field`]), pictures of fields
//! ([`render`]), and, as the project grows, the world simulator, the robot
//! proxies, the observable environment, the web UI and the benchmark runner.
//! Robot decisions are not made here: they live in `core-algo`, shared with
//! the firmware.

/// `print!` to standard output that ends the process quietly when the
/// reader has gone (`conquest explore --json | head`), as Unix tools do,
/// instead of panicking like `print!`.
#[macro_export]
macro_rules! out {
    ($($arg:tt)*) => { $crate::stdout_or_exit(format_args!($($arg)*)) };
}

/// [`out!`] with a newline.
#[macro_export]
macro_rules! outln {
    () => { $crate::out!("\n") };
    ($($arg:tt)*) => { $crate::stdout_or_exit(format_args!("{}\n", format_args!($($arg)*))) };
}

/// Writes to standard output; a closed pipe ends the process with the
/// status a shell reports for SIGPIPE (141), any other error is reported.
pub fn stdout_or_exit(args: std::fmt::Arguments<'_>) {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    if let Err(e) = out.write_fmt(args) {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            std::process::exit(141);
        }
        eprintln!("conquest: cannot write to standard output: {e}");
        std::process::exit(1);
    }
}

pub mod bench;
pub mod cli;
pub mod columns;
pub mod connect_cmd;
pub mod cores;
pub mod environment;
pub mod explore_cmd;
pub mod field;
pub mod handlers;
pub mod memo;
pub mod phone;
pub mod proxy;
pub mod qemu;
pub mod render;
pub mod sensor_world;
pub mod serve;
pub mod shared_fields;
pub mod sim;
pub mod world;
