//! `penetrate run` and `penetrate adapters`: one scene, and the GPU adapters it could run on.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;

use super::{fail, BackendArg};
use crate::output::fixed;
use crate::scene::{self, Backend};
use crate::solver::{self, RunOptions};

/// `penetrate run`'s arguments.
#[derive(Args)]
pub struct RunArgs {
    /// Scene file (cases/*.toml).
    case: PathBuf,
    /// Which implementation of the step runs (overrides the scene's run.backend).
    #[arg(long, value_enum)]
    backend: Option<BackendArg>,
    /// Output directory [default: runs/<scene name>; with --restart, the restart file's
    /// folder].
    #[arg(long)]
    out: Option<PathBuf>,
    /// Override a scene value, e.g. --set projectile.velocity=499 (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// No progress display.
    #[arg(long)]
    quiet: bool,
    /// Do not write VTK frames.
    #[arg(long)]
    no_vtk: bool,
    /// GPU adapter to use: part of its name as `penetrate adapters` lists it.
    #[arg(long)]
    adapter: Option<String>,
    /// Write a checkpoint, restart.bin in the output directory, every SECONDS of simulated
    /// time. Each replaces the last whole: a run killed while writing one keeps the one
    /// before. --restart goes on from it.
    #[arg(long, value_name = "SECONDS", value_parser = positive_seconds)]
    checkpoint_every: Option<f64>,
    /// Go on with a run from its checkpoint (restart.bin) instead of starting it: the same
    /// case and --set values, the same build of penetrate, the output directory it was written
    /// in (the default). history.csv and the frames go on from the checkpoint, and the run
    /// ends as it would have without stopping (bit for bit on the CPU). --backend may differ;
    /// --no-vtk must not. Exit code 2 when the file is damaged or does not fit.
    #[arg(long, value_name = "FILE")]
    restart: Option<PathBuf>,
}

/// A time span in seconds: a positive finite number.
fn positive_seconds(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(t) if t.is_finite() && t > 0.0 => Ok(t),
        _ => Err(format!("`{text}` is not a positive number of seconds")),
    }
}

/// Runs the scene and prints how it ended: 0 completed, 1 unstable or stopped, 2 bad scene or
/// restart file, 3 outputs not written.
pub fn run(args: RunArgs) -> ExitCode {
    let RunArgs {
        case,
        backend,
        out,
        set,
        quiet,
        no_vtk,
        adapter,
        checkpoint_every,
        restart,
    } = args;
    let scene = match scene::load(&case, &set) {
        Ok(s) => s,
        Err(e) => return fail(2, &e.to_string()),
    };
    let backend = backend.map_or(scene.run.backend, Backend::from);
    let out = out.unwrap_or_else(|| match restart.as_deref().and_then(|file| file.parent()) {
        Some(folder) if !folder.as_os_str().is_empty() => folder.to_path_buf(),
        Some(_) => PathBuf::from("."),
        None => PathBuf::from("runs").join(&scene.name),
    });
    let opts = RunOptions {
        out: out.clone(),
        quiet,
        vtk: !no_vtk,
        backend: Some(backend),
        adapter,
        checkpoint_every,
        restart,
        share: None,
    };
    match solver::run(&scene, &opts) {
        Ok(outcome) => {
            let s = &outcome.summary;
            // An unstable run has no stop reason: its status says it all.
            let reason = if s.stop_reason.is_empty() {
                String::new()
            } else {
                format!(" ({})", s.stop_reason)
            };
            say!(
                "{}: {}{reason} after {} steps, t = {:.1} µs, {:.1} s wall on {}",
                s.scene,
                s.status,
                s.steps,
                s.time_s * 1e6,
                s.wall_s,
                if s.backend == "gpu" {
                    &s.adapter
                } else {
                    "the CPU"
                }
            );
            if scene.target.is_some() && s.stop_reason == crate::output::summary::PERFORATED {
                say!(
                    "perforated: residual velocity {} m/s; concrete off the rear face {} kg, \
                     off the front face {} kg",
                    fixed(s.projectile_velocity_m_s, 1),
                    fixed(s.rear_ejecta_kg, 3),
                    fixed(s.front_ejecta_kg, 3)
                );
            } else if scene.target.is_some() {
                say!(
                    "depth {} m, projectile velocity {} m/s",
                    fixed(s.depth_m, 4),
                    fixed(s.projectile_velocity_m_s, 1)
                );
                if let Some(v) = s.unfinished_penetration(scene.projectile.velocity) {
                    say!(
                        "warning: the projectile still moves at {} m/s at the end time, so the \
                         depth is not final; raise run.end_time",
                        fixed(v, 1)
                    );
                }
            } else {
                say!(
                    "final length {:.3} mm, max radius {:.3} mm",
                    s.final_length_m * 1e3,
                    s.max_radius_m * 1e3
                );
            }
            say!(
                "max damage {:.3}, max plastic strain {:.3}, energy error {:.2e}, momentum error {:.2e}",
                s.max_damage, s.max_plastic_strain, s.energy_error, s.momentum_error
            );
            if let Some(line) = crate::scope::outside(&scene) {
                say!("note: {line}");
            }
            say!("outputs in {}", out.display());
            if outcome.ok {
                ExitCode::SUCCESS
            } else if crate::interrupt::requested() {
                fail(crate::interrupt::EXIT_CODE, &s.status)
            } else {
                fail(1, &s.status)
            }
        }
        Err(solver::RunError::Output(e)) => fail(3, &e.to_string()),
        Err(solver::RunError::Restart(e)) => fail(2, &e.to_string()),
        Err(solver::RunError::Setup(m)) => fail(2, &format!("{}: {m}", case.display())),
        Err(solver::RunError::Gpu { error, when: None }) => {
            fail(2, &format!("{}: {error}", case.display()))
        }
        Err(e) => fail(1, &e.to_string()),
    }
}

/// Lists the adapters wgpu sees, one line each; 1 where there is none.
pub fn adapters() -> ExitCode {
    let list = crate::gpu::adapters();
    if list.is_empty() {
        return fail(
            1,
            "no GPU adapter found (on Debian, `apt-get install mesa-vulkan-drivers` gives the software adapter lavapipe)",
        );
    }
    for a in list {
        say!(
            "{} | {} | {} | {} | {}",
            a.name,
            a.backend,
            a.device_type,
            a.driver,
            a.unusable
                .map_or("usable".to_string(), |why| format!("not usable: {why}"))
        );
    }
    ExitCode::SUCCESS
}
