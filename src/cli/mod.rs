//! The command line's subcommands: each one's arguments (clap) and one function that calls the
//! library, prints what it found and returns the exit code. `main.rs` only parses and calls.
//!
//! Exit codes: 0 the run completed; 1 it went unstable or was stopped; 2 bad input; 3 output
//! could not be written; [`crate::interrupt::EXIT_CODE`] stopped by a signal.

use std::process::ExitCode;

use clap::ValueEnum;

use crate::scene::Backend;

/// `println!` that gives up quietly when stdout is gone (`penetrate run … | head -1`): the run
/// goes on and writes its files; `println!` would panic on the broken pipe.
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout(), $($arg)*);
    }};
}

mod check;
mod plot;
mod run;
mod studies;

pub use check::{check, CheckArgs};
pub use plot::{plot, PlotArgs};
pub use run::{adapters, run, RunArgs};
pub use studies::{bench, check_stability, sweep, validate};
pub use studies::{BenchArgs, StabilityArgs, SweepArgs, ValidateArgs};

/// `--backend`'s values.
#[derive(Clone, Copy, ValueEnum)]
pub enum BackendArg {
    Cpu,
    Gpu,
    Auto,
}

impl From<BackendArg> for Backend {
    fn from(b: BackendArg) -> Backend {
        match b {
            BackendArg::Cpu => Backend::Cpu,
            BackendArg::Gpu => Backend::Gpu,
            BackendArg::Auto => Backend::Auto,
        }
    }
}

/// The path `arg` means, `auto` resolved as every command resolves it
/// ([`crate::solver::auto_gpu`]); a fall back to the CPU path is said on stderr.
fn backends(arg: BackendArg, adapter: Option<&str>, command: &str) -> Vec<Backend> {
    let (backend, why) = crate::solver::resolve(arg.into(), adapter);
    if let Some(why) = why {
        eprintln!("penetrate {command}: --backend auto: {why}; the CPU path runs");
    }
    vec![backend]
}

/// The backends of a comma-separated `--backend`, each `auto` expanded, in order, each once.
fn backend_list(args: &[BackendArg], adapter: Option<&str>, command: &str) -> Vec<Backend> {
    let mut out = Vec::new();
    for &a in args {
        for b in backends(a, adapter, command) {
            if !out.contains(&b) {
                out.push(b);
            }
        }
    }
    out
}

/// Prints `msg` as the command's error and returns `code` to exit with.
fn fail(code: u8, msg: &str) -> ExitCode {
    eprintln!("penetrate: {msg}");
    ExitCode::from(code)
}
