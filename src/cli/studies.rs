//! The commands that run many scenes: `bench`, `check-stability`, `sweep` and `validate`
//! ([`crate::studies`]).

use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Args;

use super::{backend_list, backends, fail, BackendArg};
use crate::studies;

/// `penetrate bench`'s arguments.
#[derive(Args)]
pub struct BenchArgs {
    /// Penetration scene to scale (its target spacing is set per size).
    #[arg(long, default_value = "cases/forrestal1994-277.toml")]
    case: PathBuf,
    /// Target sizes in particles, comma-separated.
    #[arg(long, value_delimiter = ',', default_values_t = [10_000usize, 100_000, 1_000_000])]
    sizes: Vec<usize>,
    /// Which paths to time, in order (comma-separated): cpu, gpu, or auto (a hardware GPU
    /// where wgpu finds one, else the CPU); `cpu,gpu` times both.
    #[arg(long, value_enum, value_delimiter = ',', default_value = "auto")]
    backend: Vec<BackendArg>,
    /// GPU adapter (part of its name).
    #[arg(long)]
    adapter: Option<String>,
    /// Timed steps on the GPU (the CPU takes about 2e6 particle-steps per size).
    #[arg(long, default_value_t = 100)]
    steps: usize,
}

/// `penetrate check-stability`'s arguments.
#[derive(Args)]
pub struct StabilityArgs {
    /// Base scene the suite's scenes override.
    #[arg(long, default_value = "cases/stability.toml")]
    case: PathBuf,
    /// Which paths, in order (comma-separated): cpu, gpu, or auto (a hardware GPU where wgpu
    /// finds one, else the CPU); `cpu,gpu` runs the suite on both.
    #[arg(long, value_enum, value_delimiter = ',', default_value = "auto")]
    backend: Vec<BackendArg>,
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
}

/// `penetrate sweep`'s arguments: a sweep run here, one written for a cluster's scheduler to
/// run (`--emit slurm DIR`), or the collection of one that ran there (`--collect DIR`).
#[derive(Args)]
pub struct SweepArgs {
    /// Scene file (cases/*.toml).
    #[arg(required_unless_present = "collect")]
    case: Option<PathBuf>,
    /// The key and its values A, A + STEP, … up to B inclusive, e.g.
    /// --vary projectile.velocity=200:800:100.
    #[arg(long, value_name = "KEY=A:B:STEP", required_unless_present = "collect")]
    vary: Option<String>,
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
    #[arg(long, conflicts_with = "emit")]
    out: Option<PathBuf>,
    /// Do not write VTK frames.
    #[arg(long)]
    no_vtk: bool,
    /// Run nothing: write into DIR one scene per run, members.csv and sweep.sbatch, a Slurm
    /// job array of the runs (`--emit slurm DIR`; submit with `sbatch DIR/sweep.sbatch`).
    #[arg(long, num_args = 2, value_names = ["SCHEDULER", "DIR"])]
    emit: Option<Vec<OsString>>,
    /// Make N runs at a time: on the GPU stepped together, sharing each step's submission
    /// and wait; on the CPU sharing the cores (each run's results are its own run's
    /// alone, to the bit) [default: 1].
    #[arg(
        long,
        value_name = "N",
        conflicts_with = "emit",
        value_parser = clap::value_parser!(u32).range(1..=64)
    )]
    batch: Option<u32>,
    /// With --emit: the runs each array task makes one after the other [default: 1].
    #[arg(
        long,
        value_name = "N",
        requires = "emit",
        value_parser = clap::value_parser!(u32).range(1..)
    )]
    members_per_task: Option<u32>,
    /// With --emit: extra #SBATCH options, e.g. --sbatch "--partition=gpu --gres=gpu:1"
    /// (repeatable; each word one line).
    #[arg(
        long,
        value_name = "OPTIONS",
        allow_hyphen_values = true,
        requires = "emit"
    )]
    sbatch: Vec<String>,
    /// Merge the summaries of the sweep emitted into DIR into DIR/sweep.csv, naming the runs
    /// that are missing or did not complete.
    #[arg(
        long,
        value_name = "DIR",
        conflicts_with_all = ["case", "vary", "set", "backend", "adapter", "out", "no_vtk", "emit", "batch"]
    )]
    collect: Option<PathBuf>,
}

/// `penetrate validate`'s arguments.
#[derive(Args)]
pub struct ValidateArgs {
    /// Which paths, in order (comma-separated): cpu, gpu, or auto (a hardware GPU where wgpu
    /// finds one, else the CPU). The error-against-run-time section runs on each, the other
    /// sections on the first: `cpu,gpu` runs them on the CPU and still compares the two
    /// paths.
    #[arg(long, value_enum, value_delimiter = ',', default_value = "auto")]
    backend: Vec<BackendArg>,
    /// GPU adapter (part of its name).
    #[arg(long)]
    adapter: Option<String>,
    /// Tiny resolutions and short end times: tests the tooling in about a minute; its
    /// numbers are not validation.
    #[arg(long)]
    quick: bool,
    /// Only these sections (comma-separated): taylor, forrestal, crh3-rods, target-size,
    /// convergence, rigid-vs-elastic, deformation, shell, nose-lining, nose-shape, tension.
    #[arg(long, value_delimiter = ',')]
    only: Vec<String>,
    /// Output directory: report.md, and per section its CSV, plots and runs.
    #[arg(long, default_value = "runs/validate")]
    out: PathBuf,
    /// Folder of the scenes the sections run.
    #[arg(long, default_value = "cases")]
    cases: PathBuf,
    /// Folder of the measurements (taylor.csv, forrestal1994.csv).
    #[arg(long, default_value = "data")]
    data: PathBuf,
    /// Take each completed run already in OUT whose resolved scene (its scene.toml),
    /// backend and solver build (this very executable) are the ones asked for, instead of
    /// running it again, and continue a run that was under way from its last checkpoint
    /// (each run writes 20): an interrupted or killed validation goes on where it stopped.
    #[arg(long)]
    resume: bool,
    /// With --resume, also take runs made by this other build (the 16 hex digits that end
    /// its `solver_build`; comma-separated or repeated), e.g. to write the report again
    /// after a change to the report alone. The report lists the build of every run.
    #[arg(long, value_delimiter = ',')]
    resume_build: Vec<String>,
    /// Make the runs N at a time: on the GPU stepped together, sharing each step's submission
    /// and wait; on the CPU sharing the cores (each run's results are its own run's
    /// alone, to the bit).
    #[arg(long, value_name = "N", default_value_t = 1,
          value_parser = clap::value_parser!(u32).range(1..=64))]
    batch: u32,
    /// Set a scene value in every run whose scene has its table, e.g. --set
    /// target.viscosity_jump='"reconstructed"' (repeatable; `target.` and `contact.` keys in
    /// the runs with a target): validates a changed parameter set whole. The report says so.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
}

/// Times the step at each size and prints the table: 0, or 1 where a size could not be run.
pub fn bench(args: BenchArgs) -> ExitCode {
    let BenchArgs {
        case,
        sizes,
        backend,
        adapter,
        steps,
    } = args;
    let backends = backend_list(&backend, adapter.as_deref(), "bench");
    match studies::bench::run(&case, &sizes, &backends, adapter.as_deref(), steps, |m| {
        eprintln!("{m}")
    }) {
        Ok(rows) => {
            print!("{}", studies::bench::table(&rows));
            ExitCode::SUCCESS
        }
        Err(e) => fail(1, &format!("bench: {e}")),
    }
}

/// Runs the stability suite, prints and writes its table: 0 when every run passed, else 1.
pub fn check_stability(args: StabilityArgs) -> ExitCode {
    let StabilityArgs {
        case,
        backend,
        adapter,
        quick,
        only,
        out,
    } = args;
    let backends = backend_list(&backend, adapter.as_deref(), "check-stability");
    if let Err(e) = crate::output::create_folder(&out) {
        return fail(3, &format!("check-stability: {e}"));
    }
    let result = studies::stability::run(
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
            let table = studies::stability::table(&rows);
            print!("{table}");
            let path = out.join("stability.md");
            if let Err(e) = std::fs::write(&path, &table) {
                return fail(3, &format!("{}: {e}", path.display()));
            }
            if crate::interrupt::requested() {
                return fail(
                    crate::interrupt::EXIT_CODE,
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

/// Runs the sweep, one progress line per run, writes it for Slurm (`--emit`), or collects
/// what Slurm ran (`--collect`): 0 when every run completed (or the sweep was written), else 1.
pub fn sweep(args: SweepArgs) -> ExitCode {
    let SweepArgs {
        case,
        vary,
        set,
        backend,
        adapter,
        out,
        no_vtk,
        emit,
        members_per_task,
        sbatch,
        collect,
        batch,
    } = args;
    if let Some(dir) = collect {
        return sweep_collect(&dir);
    }
    let (Some(case), Some(vary)) = (case, vary) else {
        return fail(2, "sweep: give CASE and --vary, or --collect DIR");
    };
    let vary = match studies::sweep::Vary::parse(&vary) {
        Ok(v) => v,
        Err(e) => return fail(e.exit_code(), &format!("sweep: {e}")),
    };
    if let Some(emit) = emit {
        let per_task = members_per_task.map_or(1, |n| n as usize);
        let opts = studies::slurm::EmitOptions {
            // As given: `auto` is for the node that runs to resolve.
            backend: backend.map(Into::into),
            adapter,
            vtk: !no_vtk,
            per_task,
            sbatch,
            job_name: job_name(&case, &vary),
            penetrate: std::env::current_exe()
                .ok()
                .and_then(|p| p.to_str().map(String::from))
                .unwrap_or_else(|| "penetrate".into()),
        };
        return sweep_emit(&case, &vary, &set, &emit, &opts);
    }
    let backend = backend.map(|b| backends(b, adapter.as_deref(), "sweep")[0]);
    let out = out.unwrap_or_else(|| studies::sweep::default_out(&case, &vary));
    let settings = studies::sweep::RunSettings {
        adapter,
        vtk: !no_vtk,
        batch: batch.map_or(1, |n| n as usize),
        checkpoint: false,
        restart: false,
    };
    let planned = match studies::sweep::plan_sweep(&case, &vary, &set, backend, &settings, &out) {
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
    let result = studies::sweep::sweep(planned, &vary, &settings, &out, |r| {
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

/// The Slurm job's name: `penetrate-` and the in-process sweep's default folder name.
fn job_name(case: &Path, vary: &studies::sweep::Vary) -> String {
    let out = studies::sweep::default_out(case, vary);
    let name = out.file_name().map(|n| n.to_string_lossy().into_owned());
    format!("penetrate-{}", name.unwrap_or_default())
}

/// `--emit SCHEDULER DIR`: plans the sweep as a run here would, writes it for the scheduler and
/// says how to submit and collect it.
fn sweep_emit(
    case: &Path,
    vary: &studies::sweep::Vary,
    set: &[String],
    emit: &[OsString],
    opts: &studies::slurm::EmitOptions,
) -> ExitCode {
    let [scheduler, dir] = emit else {
        return fail(2, "sweep: --emit takes two values: --emit slurm DIR");
    };
    if scheduler != "slurm" {
        return fail(
            2,
            &format!(
                "sweep: --emit {}: unknown scheduler; `--emit slurm DIR` is the one written",
                scheduler.to_string_lossy()
            ),
        );
    }
    let dir = PathBuf::from(dir);
    let planned = match studies::sweep::plan_members(case, vary, set, opts.backend, &dir) {
        Ok(p) => p,
        Err(e) => return fail(e.exit_code(), &format!("sweep: {e}")),
    };
    match studies::slurm::emit(&planned, vary, opts, &dir) {
        Ok(e) => {
            eprintln!(
                "penetrate sweep: {} runs of {} over {}, written for Slurm: array tasks 0-{}",
                e.members,
                case.display(),
                vary.key,
                e.tasks - 1
            );
            say!("{}/: {} scenes", e.scenes.display(), e.members);
            say!("{}", e.manifest.display());
            say!("{}", e.script.display());
            say!("submit with:  sbatch {}", e.script.display());
            say!("then collect: penetrate sweep --collect {}", dir.display());
            ExitCode::SUCCESS
        }
        Err(e) => fail(e.exit_code(), &format!("sweep: {e}")),
    }
}

/// `--collect DIR`: writes DIR/sweep.csv and names the members without a completed run: 0 when
/// every member completed on one build, else 1.
fn sweep_collect(dir: &Path) -> ExitCode {
    let c = match studies::slurm::collect(dir) {
        Ok(c) => c,
        Err(e) => return fail(e.exit_code(), &format!("sweep --collect: {e}")),
    };
    for u in &c.missing {
        eprintln!("missing: {} (array task {}): {}", u.label, u.task, u.why);
    }
    for u in &c.failed {
        eprintln!("failed: {} (array task {}): {}", u.label, u.task, u.why);
    }
    if c.builds.len() > 1 {
        for (build, labels) in &c.builds {
            let build = if build.is_empty() {
                "an unnamed build"
            } else {
                build
            };
            eprintln!("ran on {build}: {}", labels.join(", "));
        }
    }
    let completed: usize = c.builds.values().map(Vec::len).sum();
    eprintln!(
        "penetrate sweep --collect: {} members over {}: {completed} completed, {} missing, {} \
         failed",
        c.members,
        c.key,
        c.missing.len(),
        c.failed.len()
    );
    say!("{}", c.csv.display());
    if c.complete() {
        return ExitCode::SUCCESS;
    }
    let script = dir.join(studies::slurm::SCRIPT);
    let tasks = c.tasks_to_rerun();
    let rerun = match tasks.is_empty() {
        true => String::new(),
        false => {
            let list: Vec<String> = tasks.iter().map(usize::to_string).collect();
            format!(
                "; rerun their array tasks with `sbatch --array={} {}`, then collect again",
                list.join(","),
                script.display()
            )
        }
    };
    let unfinished = c.missing.len() + c.failed.len();
    if unfinished > 0 {
        fail(
            1,
            &format!(
                "sweep --collect: {unfinished} of {} members did not complete{rerun}",
                c.members
            ),
        )
    } else {
        fail(
            1,
            &format!(
                "sweep --collect: the members ran on {} builds of penetrate (above), not one; \
                 rerun the odd ones with one build (`PENETRATE=… sbatch --array=… {}`)",
                c.builds.len(),
                script.display()
            ),
        )
    }
}

/// Runs the validation and names its report: 0 when every run completed, else 1.
pub fn validate(args: ValidateArgs) -> ExitCode {
    let ValidateArgs {
        backend,
        adapter,
        quick,
        only,
        out,
        cases,
        data,
        resume,
        resume_build,
        batch,
        set,
    } = args;
    let only = match only
        .iter()
        .map(|s| studies::validate::Section::parse(s))
        .collect::<Result<Vec<_>, _>>()
    {
        Ok(o) => o,
        Err(e) => return fail(e.exit_code(), &format!("validate: {e}")),
    };
    let opts = studies::validate::Options {
        cases,
        data,
        out,
        backends: backend_list(&backend, adapter.as_deref(), "validate"),
        adapter,
        quick,
        only,
        resume,
        resume_builds: resume_build,
        batch: batch as usize,
        set,
    };
    match studies::validate::run(&opts, &mut |line| eprintln!("{line}")) {
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
