//! `penetrate plot`: PNG pictures of a run's outputs.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;

use super::fail;
use crate::output::run_plots::{self, PlotError};

/// `penetrate plot`'s arguments.
#[derive(Args)]
pub struct PlotArgs {
    /// A run's output folder (what `penetrate run --out` wrote).
    run_dir: PathBuf,
    /// Folder for the pictures [default: RUN_DIR].
    #[arg(long)]
    out: Option<PathBuf>,
}

/// Draws the run's curves and its final fields and says where they went: 0 drawn, 2 the run's
/// folder or files missing or malformed, 3 a picture not written.
pub fn plot(args: PlotArgs) -> ExitCode {
    let out = args.out.unwrap_or_else(|| args.run_dir.clone());
    match run_plots::plot_run(&args.run_dir, &out) {
        Ok(plotted) => {
            let names: Vec<String> = plotted
                .written
                .iter()
                .filter_map(|p| p.file_name())
                .map(|n| n.to_string_lossy().into_owned())
                .collect();
            say!("wrote {} in {}", names.join(", "), out.display());
            if let Some(why) = plotted.no_fields {
                say!("{why}");
            }
            ExitCode::SUCCESS
        }
        Err(PlotError::Input(e)) => fail(2, &e),
        Err(PlotError::Output(e)) => fail(3, &e),
    }
}
