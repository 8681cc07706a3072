//! `penetrate`: the command line. It parses arguments and calls the library.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};

use penetrate::output::fixed;
use penetrate::scene::{self, Backend, Scene};
use penetrate::solver::{self, RunOptions};
use penetrate::studies::{sweep, validate};
use penetrate::{estimate, mesh};

/// `println!` that gives up quietly when stdout is gone (`penetrate run … | head -1`): the run
/// goes on and writes its files; `println!` would panic on the broken pipe.
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout(), $($arg)*);
    }};
}

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
    Run {
        /// Scene file (cases/*.toml).
        case: PathBuf,
        /// Which implementation of the step runs (overrides the scene's run.backend).
        #[arg(long, value_enum)]
        backend: Option<BackendArg>,
        /// Output directory [default: runs/<scene name>].
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
    },
    /// List the GPU adapters wgpu sees and whether each can run the solver.
    Adapters,
    /// Speed of the coupled step at several target sizes (particle-steps/s, ms per pass).
    Bench {
        /// Penetration scene to scale (its target spacing is set per size).
        #[arg(long, default_value = "cases/forrestal1994-277.toml")]
        case: PathBuf,
        /// Target sizes in particles, comma-separated.
        #[arg(long, value_delimiter = ',', default_values_t = [10_000usize, 100_000, 1_000_000])]
        sizes: Vec<usize>,
        /// Which paths to time: cpu, gpu, or auto (both, the GPU where an adapter is found).
        #[arg(long, value_enum, default_value = "auto")]
        backend: BackendArg,
        /// GPU adapter (part of its name).
        #[arg(long)]
        adapter: Option<String>,
        /// Timed steps on the GPU (the CPU takes about 2e6 particle-steps per size).
        #[arg(long, default_value_t = 100)]
        steps: usize,
    },
    /// Run the stability suite (stiff and extreme scenes, CPU and GPU) and write its table.
    CheckStability {
        /// Base scene the suite's scenes override.
        #[arg(long, default_value = "cases/stability.toml")]
        case: PathBuf,
        /// Which paths: cpu, gpu, or auto (both, the GPU where an adapter is found).
        #[arg(long, value_enum, default_value = "auto")]
        backend: BackendArg,
        /// GPU adapter (part of its name).
        #[arg(long)]
        adapter: Option<String>,
        /// The quiescent scene for 10⁴ steps instead of 10⁵.
        #[arg(long)]
        quick: bool,
        /// Only these scenes (comma-separated names from the table).
        #[arg(long, value_delimiter = ',')]
        only: Vec<String>,
        /// Output directory: stability.md and one run directory per scene and backend.
        #[arg(long, default_value = "runs/stability")]
        out: PathBuf,
    },
    /// Run a scene over a range of one key's values: one run directory and one sweep.csv row
    /// per value.
    Sweep {
        /// Scene file (cases/*.toml).
        case: PathBuf,
        /// The key and its values A, A + STEP, … up to B inclusive, e.g.
        /// --vary projectile.velocity=200:800:100.
        #[arg(long, value_name = "KEY=A:B:STEP")]
        vary: String,
        /// Override a scene value in every run (repeatable).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
        /// Which implementation of the step runs (overrides the scene's run.backend).
        #[arg(long, value_enum)]
        backend: Option<BackendArg>,
        /// GPU adapter (part of its name).
        #[arg(long)]
        adapter: Option<String>,
        /// Output directory: sweep.csv and one run directory per value [default:
        /// runs/<case>-<key's last part>].
        #[arg(long)]
        out: Option<PathBuf>,
        /// Do not write VTK frames.
        #[arg(long)]
        no_vtk: bool,
    },
    /// Run the validation cases and the paper's studies; write DIR/report.md with plots and
    /// each section's CSV.
    Validate {
        /// Which paths, in order (comma-separated): cpu, gpu, or auto (gpu then cpu where an
        /// adapter is found, else cpu). The error-against-run-time section runs on each, the
        /// other sections on the first: `cpu,gpu` runs them on the CPU and still compares the
        /// two paths.
        #[arg(long, value_enum, value_delimiter = ',', default_value = "auto")]
        backend: Vec<BackendArg>,
        /// GPU adapter (part of its name).
        #[arg(long)]
        adapter: Option<String>,
        /// Tiny resolutions and short end times: tests the tooling in about a minute; its
        /// numbers are not validation.
        #[arg(long)]
        quick: bool,
        /// Only these sections (comma-separated): taylor, forrestal, target-size, convergence,
        /// rigid-vs-elastic, deformation, shell.
        #[arg(long, value_delimiter = ',')]
        only: Vec<String>,
        /// Output directory: report.md, and per section its CSV, plots and runs.
        #[arg(long, default_value = "runs/validate")]
        out: PathBuf,
        /// Folder of the scenes the sections run.
        #[arg(long, default_value = "cases")]
        cases: PathBuf,
        /// Folder of the measurements (taylor.csv, forrestal1994.csv).
        #[arg(long, default_value = "../shared/data")]
        data: PathBuf,
        /// Take each completed run already in OUT whose resolved scene (its scene.toml),
        /// backend and solver build (this very executable) are the ones asked for, instead of
        /// running it again: an interrupted validation goes on where it stopped.
        #[arg(long)]
        resume: bool,
        /// With --resume, also take runs made by this other build (the 16 hex digits that end
        /// its `solver_build`; comma-separated or repeated), e.g. to write the report again
        /// after a change to the report alone. The report lists the build of every run.
        #[arg(long, value_delimiter = ',')]
        resume_build: Vec<String>,
    },
    /// Validate a scene without running it: resolved values, counts, step and memory estimate.
    Check {
        /// Scene file (cases/*.toml)
        case: PathBuf,
        /// Override a scene value, as in `run` (repeatable)
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
    },
}

#[derive(Clone, Copy, ValueEnum)]
enum BackendArg {
    Cpu,
    Gpu,
    Auto,
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
        Command::Sweep {
            case,
            vary,
            set,
            backend,
            adapter,
            out,
            no_vtk,
        } => {
            let vary = match sweep::Vary::parse(&vary) {
                Ok(v) => v,
                Err(e) => return fail(e.exit_code(), &format!("sweep: {e}")),
            };
            let backend = backend.map(Backend::from);
            let out = out.unwrap_or_else(|| sweep::default_out(&case, &vary));
            let settings = sweep::RunSettings {
                adapter,
                vtk: !no_vtk,
            };
            let planned = match sweep::plan_sweep(&case, &vary, &set, backend, &settings, &out) {
                Ok(p) => p,
                Err(e) => return fail(e.exit_code(), &format!("sweep: {e}")),
            };
            let total = planned.len();
            eprintln!(
                "penetrate sweep: {total} runs of {} over {}",
                case.display(),
                vary.key
            );
            let mut done = 0;
            let result = sweep::sweep(planned, &vary, &settings, &out, |r| {
                done += 1;
                let depth = r.summary().map_or(String::new(), |s| {
                    format!(", depth {:.4} m, {:.1} s", s.depth_m, s.wall_s)
                });
                eprintln!("[{done}/{total}] {}: {}{depth}", r.label, r.status());
            });
            match result {
                Ok(records) => {
                    say!("{}", out.join("sweep.csv").display());
                    let failed = records.iter().filter(|r| r.completed().is_none()).count();
                    if failed == 0 {
                        ExitCode::SUCCESS
                    } else {
                        fail(
                            1,
                            &format!("sweep: {failed} of {total} runs did not complete"),
                        )
                    }
                }
                Err(e) => fail(e.exit_code(), &format!("sweep: {e}")),
            }
        }
        Command::Validate {
            backend,
            adapter,
            quick,
            only,
            out,
            cases,
            data,
            resume,
            resume_build,
        } => {
            let only = match only
                .iter()
                .map(|s| validate::Section::parse(s))
                .collect::<Result<Vec<_>, _>>()
            {
                Ok(o) => o,
                Err(e) => return fail(e.exit_code(), &format!("validate: {e}")),
            };
            let opts = validate::Options {
                cases,
                data,
                out,
                backends: backend_list(&backend, adapter.as_deref(), "validate"),
                adapter,
                quick,
                only,
                resume,
                resume_builds: resume_build,
            };
            match validate::run(&opts, &mut |line| eprintln!("{line}")) {
                Ok(o) => {
                    say!(
                        "{} ({} runs, {:.0} s)",
                        o.report.display(),
                        o.runs,
                        o.wall_s
                    );
                    if o.failed.is_empty() {
                        ExitCode::SUCCESS
                    } else {
                        fail(
                            1,
                            &format!(
                                "validate: {} run(s) did not complete: {}",
                                o.failed.len(),
                                o.failed.join("; ")
                            ),
                        )
                    }
                }
                Err(e) => fail(e.exit_code(), &format!("validate: {e}")),
            }
        }
        Command::CheckStability {
            case,
            backend,
            adapter,
            quick,
            only,
            out,
        } => {
            let backends = backends(backend, adapter.as_deref(), "check-stability");
            if let Err(e) = penetrate::output::create_folder(&out) {
                return fail(3, &format!("check-stability: {e}"));
            }
            let result = penetrate::studies::stability::run(
                &case,
                &backends,
                quick,
                &only,
                &out,
                adapter.as_deref(),
                |row| eprintln!("{} on {}: {}", row.case, row.backend, row.verdict()),
            );
            match result {
                Ok(rows) => {
                    let table = penetrate::studies::stability::table(&rows);
                    print!("{table}");
                    let path = out.join("stability.md");
                    if let Err(e) = std::fs::write(&path, &table) {
                        return fail(3, &format!("{}: {e}", path.display()));
                    }
                    if penetrate::interrupt::requested() {
                        return fail(
                            penetrate::interrupt::EXIT_CODE,
                            &format!(
                                "check-stability: interrupted; {} has the scenes run so far",
                                path.display()
                            ),
                        );
                    }
                    let failed: Vec<String> = rows
                        .iter()
                        .filter(|r| r.verdict() != "pass")
                        .map(|r| format!("{} on {}", r.case, r.backend))
                        .collect();
                    if !failed.is_empty() {
                        return fail(
                            1,
                            &format!(
                                "check-stability: {} of {} runs did not pass ({}); {} says why",
                                failed.len(),
                                rows.len(),
                                failed.join(", "),
                                path.display()
                            ),
                        );
                    }
                    ExitCode::SUCCESS
                }
                Err(e) => fail(e.exit_code(), &format!("check-stability: {e}")),
            }
        }
        Command::Bench {
            case,
            sizes,
            backend,
            adapter,
            steps,
        } => {
            let backends = backends(backend, adapter.as_deref(), "bench");
            match penetrate::studies::bench::run(
                &case,
                &sizes,
                &backends,
                adapter.as_deref(),
                steps,
                |m| eprintln!("{m}"),
            ) {
                Ok(rows) => {
                    print!("{}", penetrate::studies::bench::table(&rows));
                    ExitCode::SUCCESS
                }
                Err(e) => fail(1, &format!("bench: {e}")),
            }
        }
        Command::Adapters => {
            let list = penetrate::gpu::adapters();
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
        Command::Check { case, set } => match scene::load(&case, &set) {
            Ok(s) => match check_report(&s) {
                Ok(report) => {
                    print!("{report}");
                    ExitCode::SUCCESS
                }
                Err(e) => fail(2, &format!("{}: {e}", case.display())),
            },
            Err(e) => fail(2, &e.to_string()),
        },
        Command::Run {
            case,
            backend,
            out,
            set,
            quiet,
            no_vtk,
            adapter,
        } => {
            let scene = match scene::load(&case, &set) {
                Ok(s) => s,
                Err(e) => return fail(2, &e.to_string()),
            };
            let backend = backend.map_or(scene.run.backend, Backend::from);
            let out = out.unwrap_or_else(|| PathBuf::from("runs").join(&scene.name));
            let opts = RunOptions {
                out: out.clone(),
                quiet,
                vtk: !no_vtk,
                backend: Some(backend),
                adapter,
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
                    if scene.target.is_some() {
                        say!(
                            "depth {} m, projectile velocity {} m/s",
                            fixed(s.depth_m, 4),
                            fixed(s.projectile_velocity_m_s, 1)
                        );
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
                    say!("outputs in {}", out.display());
                    if outcome.ok {
                        ExitCode::SUCCESS
                    } else if penetrate::interrupt::requested() {
                        fail(penetrate::interrupt::EXIT_CODE, &s.status)
                    } else {
                        fail(1, &s.status)
                    }
                }
                Err(solver::RunError::Io(m)) => fail(3, &m),
                Err(solver::RunError::Setup(m)) => fail(2, &format!("{}: {m}", case.display())),
                Err(e) => fail(1, &e.to_string()),
            }
        }
    }
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

/// The paths a multi-run command uses: `auto` is both where wgpu finds an adapter.
fn backends(arg: BackendArg, adapter: Option<&str>, command: &str) -> Vec<Backend> {
    match arg {
        BackendArg::Cpu => vec![Backend::Cpu],
        BackendArg::Gpu => vec![Backend::Gpu],
        BackendArg::Auto => match penetrate::gpu::Gpu::new(adapter) {
            Ok(_) => vec![Backend::Gpu, Backend::Cpu],
            Err(e) => {
                eprintln!("penetrate {command}: no GPU ({e}); the CPU path only");
                vec![Backend::Cpu]
            }
        },
    }
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

fn fail(code: u8, msg: &str) -> ExitCode {
    eprintln!("penetrate: {msg}");
    ExitCode::from(code)
}

/// `check`'s line on the lattice column nearest the shank of radius `shank` (m), with a note
/// where it lies within 5 % of the spacing and the projectile is rigid (λ = 0): there such a
/// column made the 277 m/s shot scatter 4 % from one ulp of its speed, against 0.1–0.3 % with
/// the column 0.4–0.5 mm off (README, "Known shortcomings"; a deforming projectile scattered
/// as far either way).
fn shank_column_line(shank: f64, spacing: f64, lambda: f64) -> String {
    let (column, gap) = mesh::target::nearest_column(shank, spacing);
    let side = if gap >= 0.0 { "outside" } else { "inside" };
    let mut line = format!(
        "# lattice: the column nearest the shank at r = {:.3} mm, {:.3} mm {side} it ({:.1} % of the spacing)",
        column * 1e3,
        gap.abs() * 1e3,
        100.0 * gap.abs() / spacing
    );
    if lambda == 0.0 && gap.abs() < 0.05 * spacing {
        line += "; with a rigid projectile a column this close to the shank amplifies round-off \
                 (README, Known shortcomings): a spacing a few % larger or smaller moves it off";
    }
    line + "\n"
}

fn check_report(s: &Scene) -> Result<String, String> {
    let mut out = s.resolved_table();
    estimate::check_fits(s)?;
    match mesh::projectile::build(&s.model_projectile()) {
        Ok(m) => {
            let e = estimate::estimate(s, &m);
            out += &format!(
                "\n# projectile: {} nodes, {} elements, mass {:.4} kg (filler {:.4} kg)\n",
                m.node_r.len(),
                m.elements.len(),
                m.total_mass,
                m.filler_mass
            );
            out += &match &s.wall {
                Some(w) => format!("# target: none, a rigid wall at z = {} m\n", w.z),
                None => format!(
                    "# target: {} particles, {} slaves (approx.)\n",
                    e.particles, e.slaves
                ),
            };
            if let Some(t) = &s.target {
                out += &shank_column_line(s.projectile.diameter / 2.0, t.spacing, s.contact.lambda);
            }
            let cap = if e.dt <= f64::from(solver::MIN_STEP) {
                format!(
                    "; not above {:e} s, under which a run takes its step as collapsed and stops",
                    solver::MIN_STEP
                )
            } else if e.steps > s.run.max_steps {
                format!(
                    "; more than run.max_steps = {}, which would stop the run",
                    s.run.max_steps
                )
            } else {
                String::new()
            };
            let sph = if s.target.is_some() {
                format!(
                    ", SPH {:.3e} at the stiffest EOS tangent up to locking",
                    e.dt_sph
                )
            } else {
                String::new()
            };
            out += &format!(
                "# stable step ≈ {:.3e} s (FEM {:.3e}, its smallest element {:.3e} m high{sph}) → {} steps to end_time{cap}\n",
                e.dt,
                e.dt_fem,
                e.fem_altitude,
                e.steps_text()
            );
            out += &format!("# memory ≈ {:.1} MiB\n", e.bytes as f64 / estimate::MIB);
            out += &format!(
                "# frames: {} to the run's end (none with --no-vtk), ≈ {:.1} MiB of ASCII VTU\n",
                e.frames,
                e.frames_bytes() / estimate::MIB
            );
            out += &format!(
                "# history: {} rows to the run's end, ≈ {:.1} MiB\n",
                e.history_rows,
                e.history_bytes() / estimate::MIB
            );
        }
        Err(e) => return Err(format!("projectile mesh: {e}")),
    }
    Ok(out)
}
