//! `penetrate`: the command line. It parses arguments and calls the library's [`cli`], one
//! function per subcommand, which prints and returns the exit code.

use std::process::ExitCode;

use clap::{Parser, Subcommand};

use penetrate::cli;

#[derive(Parser)]
#[command(
    name = "penetrate",
    version,
    about = "Steel projectile into concrete: axisymmetric FEM + SPH, sliding-surface contact"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scene and write summary.json, history.csv and VTK frames.
    Run(cli::RunArgs),
    /// List the GPU adapters wgpu sees and whether each can run the solver.
    Adapters,
    /// Speed of the coupled step at several target sizes (particle-steps/s, ms per pass).
    Bench(cli::BenchArgs),
    /// Run the stability suite (stiff and extreme scenes, CPU and GPU) and write its table.
    CheckStability(cli::StabilityArgs),
    /// Run a scene over a range of one key's values: one run directory and one sweep.csv row
    /// per value.
    Sweep(cli::SweepArgs),
    /// Run the validation cases and the paper's studies; write DIR/report.md with plots and
    /// each section's CSV.
    Validate(cli::ValidateArgs),
    /// Validate a scene without running it: resolved values, counts, step and memory estimate.
    Check(cli::CheckArgs),
    /// Draw a run's history (depth, velocity, deceleration, contact force) and its final
    /// fields (damage, pressure) as PNGs in its folder.
    Plot(cli::PlotArgs),
}

/// Exit codes: 0 the run completed; 1 it went unstable or was stopped; 2 bad input; 3 output
/// could not be written.
fn main() -> ExitCode {
    let cli = Cli::parse();
    if let Err(e) = penetrate::interrupt::install() {
        // The command still runs; only a stop by signal loses its outputs.
        eprintln!("penetrate: {e}; a signal ends the process without its outputs");
    }
    match cli.command {
        Command::Run(args) => cli::run(args),
        Command::Adapters => cli::adapters(),
        Command::Bench(args) => cli::bench(args),
        Command::CheckStability(args) => cli::check_stability(args),
        Command::Sweep(args) => cli::sweep(args),
        Command::Validate(args) => cli::validate(args),
        Command::Check(args) => cli::check(args),
        Command::Plot(args) => cli::plot(args),
    }
}
