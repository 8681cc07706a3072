//! `penetrate sweep`: one scene run over a range of one key's values (`--vary key=a:b:step`), in
//! process, each run in its own directory and one `sweep.csv` row per run. The validation
//! ([`super::validate`]) runs its studies through the same [`plan`] and [`run_set`]; a sweep
//! run by a cluster's scheduler ([`super::slurm`]) is planned by [`plan_members`] and its
//! `sweep.csv` written by the same [`write_sweep_csv`].

use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{mpsc, Arc, Mutex};

use crate::estimate;
use crate::gpu::batch::{Batch, GpuShare};
use crate::output::summary::{fingerprint, same_build, Summary};
use crate::scene::{self, Backend, Scene, SceneError};
use crate::solver::{self, RunError, RunOptions};

/// Most runs one `--vary` may ask for: beyond it a slip in the step is likelier than a plan.
pub const MAX_RUNS: usize = 200;

/// `--vary key=a:b:step`: a scene key and the values a, a + step, … up to b inclusive.
#[derive(Clone, Debug, PartialEq)]
pub struct Vary {
    pub key: String,
    pub values: Vec<f64>,
}

impl Vary {
    /// Parses `key=a:b:step` (a ≤ b, step > 0, at most [`MAX_RUNS`] values).
    pub fn parse(spec: &str) -> Result<Vary, SweepError> {
        let bad = |why: String| SweepError::Spec(format!("--vary {spec}: {why}"));
        let (key, range) = spec.split_once('=').ok_or_else(|| {
            bad("expected key=a:b:step, e.g. projectile.velocity=200:800:100".into())
        })?;
        let key = key.trim();
        if key.is_empty() || key.contains(char::is_whitespace) {
            return Err(bad(
                "the key before `=` must be a scene key such as projectile.velocity".into(),
            ));
        }
        let parts: Vec<&str> = range.split(':').map(str::trim).collect();
        if parts.len() != 3 {
            return Err(bad(format!(
                "the range must be a:b:step, three numbers separated by colons (found {} part{})",
                parts.len(),
                if parts.len() == 1 { "" } else { "s" }
            )));
        }
        let number = |name: &str, text: &str| -> Result<f64, SweepError> {
            match text.parse::<f64>() {
                Ok(x) if x.is_finite() => Ok(x),
                _ => Err(bad(format!("{name} = `{text}` is not a finite number"))),
            }
        };
        let (a, b, step) = (
            number("a", parts[0])?,
            number("b", parts[1])?,
            number("step", parts[2])?,
        );
        if step <= 0.0 {
            return Err(bad(format!("step = {step} must be > 0")));
        }
        if b < a {
            return Err(bad(format!(
                "empty range: b = {b} is below a = {a}; write the smaller value first"
            )));
        }
        // A relative slack so that 0.1:0.3:0.1 reaches 0.3 despite binary round-off.
        let intervals = ((b - a) / step * (1.0 + 1e-9)).floor();
        let runs = intervals + 1.0;
        if runs > MAX_RUNS as f64 {
            // A count past what one reads in digits (1:1e30:1e-30) in exponent form.
            let shown = match runs < 1e9 {
                true => format!("{runs}"),
                false => format!("{runs:.1e}"),
            };
            return Err(bad(format!(
                "gives {shown} runs, more than the {MAX_RUNS} a sweep allows; use a larger step"
            )));
        }
        let values = (0..=intervals as usize)
            .map(|i| tidy(a + i as f64 * step))
            .collect();
        Ok(Vary {
            key: key.to_string(),
            values,
        })
    }

    /// The `--set` override of value `v`.
    pub fn set(&self, v: f64) -> String {
        format!("{}={}", self.key, scene::number_text(v))
    }

    /// Whether the `--set` override `set` writes the key this sweep varies (or a table holding
    /// it, or a key inside it): the varied value would silently replace it in every run.
    pub fn clashes_with(&self, set: &str) -> bool {
        let key = set.split_once('=').map_or(set, |(k, _)| k);
        let key: Vec<&str> = key.split('.').map(str::trim).collect();
        let key = key.join(".");
        let (short, long) = if key.len() <= self.key.len() {
            (key.as_str(), self.key.as_str())
        } else {
            (self.key.as_str(), key.as_str())
        };
        long == short || long.starts_with(&format!("{short}."))
    }

    /// A run's directory name: the key's last part and the value, e.g. `velocity-300`.
    pub fn label(&self, v: f64) -> String {
        let last = self.key.rsplit('.').next().unwrap_or(&self.key);
        format!("{last}-{}", scene::number_text(v))
    }
}

/// `v` rounded to 12 significant digits: drops the binary noise of `a + i·step`
/// (0.30000000000000004) and of scaled resolutions, so overrides and labels read as written.
pub fn tidy(v: f64) -> f64 {
    format!("{v:.11e}").parse().unwrap_or(v)
}

/// Why a sweep (or a set of runs) could not be run. A run that goes unstable is not an error:
/// its record says so.
#[derive(Clone, Debug, PartialEq)]
pub enum SweepError {
    /// A malformed `--vary` specification.
    Spec(String),
    /// A scene that does not load with its overrides.
    Scene(SceneError),
    /// The backend asked for cannot run (no GPU adapter).
    Backend(String),
    /// A folder `--emit` may not write into, or one `--collect` finds no emitted sweep in.
    Folder(String),
    /// Output could not be written.
    Io(String),
    /// Ctrl-C or SIGTERM stopped the sweep ([`crate::interrupt`]).
    Interrupted(String),
    /// A `--batch` whose runs would not fit in memory together.
    Batch(String),
}

impl SweepError {
    /// The command line's exit code: 2 bad input, 3 output not writable, 130 interrupted.
    pub fn exit_code(&self) -> u8 {
        match self {
            SweepError::Io(_) => 3,
            SweepError::Interrupted(_) => crate::interrupt::EXIT_CODE,
            _ => 2,
        }
    }
}

impl fmt::Display for SweepError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SweepError::Spec(m)
            | SweepError::Backend(m)
            | SweepError::Folder(m)
            | SweepError::Io(m)
            | SweepError::Interrupted(m)
            | SweepError::Batch(m) => f.write_str(m),
            SweepError::Scene(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for SweepError {}

/// One run of a set: `case` with `overrides` (applied in order, as `--set`) on `backend`,
/// writing its outputs into `dir`.
#[derive(Clone, Debug)]
pub struct RunSpec {
    pub label: String,
    pub case: PathBuf,
    pub overrides: Vec<String>,
    pub backend: Backend,
    pub dir: PathBuf,
}

/// A run whose scene has been loaded and checked.
#[derive(Clone, Debug)]
pub struct Planned {
    pub spec: RunSpec,
    pub scene: Scene,
}

/// Loads every run's scene, so that a bad file or override stops the set before anything runs.
pub fn plan(specs: Vec<RunSpec>) -> Result<Vec<Planned>, SweepError> {
    specs
        .into_iter()
        .map(|spec| {
            let scene = scene::load(&spec.case, &spec.overrides).map_err(SweepError::Scene)?;
            Ok(Planned { spec, scene })
        })
        .collect()
}

/// What one run produced: its summary (also when it stopped early: `status` says why), or why
/// it could not start.
#[derive(Clone, Debug)]
pub struct RunRecord {
    pub label: String,
    pub dir: PathBuf,
    pub backend: Backend,
    pub scene: Scene,
    pub outcome: Result<Summary, String>,
}

impl RunRecord {
    /// `completed`, the reason the run stopped, or why it could not start.
    pub fn status(&self) -> &str {
        match &self.outcome {
            Ok(s) => &s.status,
            Err(e) => e,
        }
    }

    /// The summary of a run that ended normally.
    pub fn completed(&self) -> Option<&Summary> {
        self.outcome
            .as_ref()
            .ok()
            .filter(|s| s.status == "completed")
    }

    /// The summary, however the run ended (`None` when it could not start).
    pub fn summary(&self) -> Option<&Summary> {
        self.outcome.as_ref().ok()
    }
}

/// How every run of a set is run.
#[derive(Clone, Debug, Default)]
pub struct RunSettings {
    /// Part of the GPU adapter's name (`--adapter`).
    pub adapter: Option<String>,
    /// Write VTK frames.
    pub vtk: bool,
    /// Runs made at a time (`--batch N`; 0 or 1: one after another): on the GPU stepped
    /// together, on the CPU sharing the thread pool ([`run_batched`]).
    pub batch: usize,
    /// Write each run's checkpoint [`CHECKPOINTS_PER_RUN`] times over its end time, removed
    /// once it completes (not the members of a GPU batch: they are not saved).
    pub checkpoint: bool,
    /// Go on from a run folder's checkpoint where it holds one of this build and scene, as a
    /// killed or interrupted run left it (`validate --resume`); otherwise start afresh.
    pub restart: bool,
}

/// How many checkpoints a run with [`RunSettings::checkpoint`] writes over its end time: a
/// killed run loses at most the steps of one such share of its end time.
pub const CHECKPOINTS_PER_RUN: f64 = 20.0;

/// `--backend gpu` needs an adapter: say so before the first run rather than in every row.
/// Returns the adapter's name as run summaries give it (`None` for the other backends).
pub fn check_backend(
    backend: Backend,
    adapter: Option<&str>,
) -> Result<Option<String>, SweepError> {
    if backend != Backend::Gpu {
        return Ok(None);
    }
    let gpu = crate::gpu::Gpu::new(adapter).map_err(|e| {
        SweepError::Backend(format!(
            "--backend gpu: {e} (on Debian, `apt-get install mesa-vulkan-drivers` gives the \
             software adapter lavapipe; or use --backend cpu)"
        ))
    })?;
    Ok(Some(gpu.adapter_name()))
}

/// Runs `planned` in process: one after another, or with `settings.batch` > 1 that many at a
/// time (`run_batched`). A run that goes unstable or cannot start is recorded and the set goes
/// on; only an unwritable output stops it. `progress` sees each record as it is made.
pub fn run_set(
    planned: Vec<Planned>,
    settings: &RunSettings,
    mut progress: impl FnMut(&RunRecord),
) -> Result<Vec<RunRecord>, SweepError> {
    if settings.batch > 1 {
        return run_batched(planned, settings, progress);
    }
    let mut records = Vec::with_capacity(planned.len());
    for Planned { spec, scene } in planned {
        let record = run_one(spec, scene, settings, None)?;
        progress(&record);
        records.push(record);
        if crate::interrupt::requested() {
            break;
        }
    }
    Ok(records)
}

/// One run of a set, on its own device or on the one `share` gives.
fn run_one(
    spec: RunSpec,
    scene: Scene,
    settings: &RunSettings,
    share: Option<Arc<GpuShare>>,
) -> Result<RunRecord, SweepError> {
    let saving = settings.checkpoint && share.is_none();
    let saved = spec.dir.join(crate::output::RESTART_FILE);
    let opts = |restart: Option<PathBuf>| RunOptions {
        out: spec.dir.clone(),
        quiet: true,
        vtk: settings.vtk,
        backend: Some(spec.backend),
        adapter: settings.adapter.clone(),
        checkpoint_every: saving.then(|| scene.run.end_time / CHECKPOINTS_PER_RUN),
        restart,
        share: share.clone(),
    };
    let continued = (settings.restart && saved.is_file())
        .then(|| solver::run(&scene, &opts(Some(saved.clone()))))
        // Another build's or scene's checkpoint is refused before anything is written.
        .filter(|r| !matches!(r, Err(RunError::Restart(_))));
    let result = match continued {
        Some(r) => r,
        None => solver::run(&scene, &opts(None)),
    };
    let outcome = match result {
        Ok(o) => {
            if o.ok && saving {
                // A completed run is taken whole by a later --resume: its checkpoint is dead.
                let _ = std::fs::remove_file(&saved);
            }
            Ok(o.summary)
        }
        Err(RunError::Output(e)) => return Err(SweepError::Io(e.to_string())),
        Err(e) => Err(e.to_string()),
    };
    Ok(RunRecord {
        label: spec.label,
        dir: spec.dir,
        backend: spec.backend,
        scene,
        outcome,
    })
}

/// `settings.batch` runs at a time, each on a thread of its own: as one ends, the next planned
/// run takes its place. Runs on the GPU share one device and its submissions (`gpu::batch`).
/// Runs on the CPU share the thread pool: the threads one run leaves idle (between its passes,
/// in a pass's uneven end) work on the others', and a run left alone at the end has them all.
/// Either way a run does exactly the work it does alone (the CPU path's bits do not depend on
/// how its passes are shared out over threads). The records come back in the planned order.
fn run_batched(
    planned: Vec<Planned>,
    settings: &RunSettings,
    mut progress: impl FnMut(&RunRecord),
) -> Result<Vec<RunRecord>, SweepError> {
    let mut planned = planned;
    for p in &mut planned {
        // `auto` is the GPU where it finds one, as each run alone would resolve it.
        p.spec.backend = solver::resolve(p.spec.backend, settings.adapter.as_deref()).0;
    }
    let workers = settings.batch.min(planned.len());
    check_batch_fits(
        &planned,
        workers,
        settings.batch,
        estimate::available_memory(),
    )?;
    let share = if planned.iter().any(|p| p.spec.backend == Backend::Gpu) {
        let gpu = crate::gpu::Gpu::new(settings.adapter.as_deref())
            .map_err(|e| SweepError::Backend(format!("--batch {}: {e}", settings.batch)))?;
        Some(Arc::new(GpuShare {
            gpu,
            batch: Batch::new(),
        }))
    } else {
        None
    };
    if planned.iter().any(|p| p.spec.backend != Backend::Gpu) {
        eprintln!(
            "--batch {}: runs on the CPU path {workers} at a time, sharing {} threads",
            settings.batch,
            rayon::current_num_threads()
        );
    }
    let n = planned.len();
    let queue = &Mutex::new(planned.into_iter().enumerate());
    // Set when an output cannot be written: the runs under way finish, no new one starts.
    let stop = &AtomicBool::new(false);
    let mut records: Vec<Option<RunRecord>> = vec![None; n];
    let mut error = None;
    let (tx, rx) = mpsc::channel();
    std::thread::scope(|scope| {
        for _ in 0..workers {
            let (tx, share) = (tx.clone(), share.clone());
            scope.spawn(move || loop {
                if stop.load(Ordering::Relaxed) || crate::interrupt::requested() {
                    return;
                }
                let next = queue.lock().unwrap_or_else(|e| e.into_inner()).next();
                let Some((k, Planned { spec, scene })) = next else {
                    return;
                };
                let share = share.clone().filter(|_| spec.backend == Backend::Gpu);
                let result = run_one(spec, scene, settings, share);
                if tx.send((k, result)).is_err() {
                    return;
                }
            });
        }
        drop(tx);
        for (k, result) in rx {
            match result {
                Ok(record) => {
                    progress(&record);
                    records[k] = Some(record);
                }
                Err(e) => {
                    stop.store(true, Ordering::Relaxed);
                    error.get_or_insert(e);
                }
            }
        }
    });
    let (submissions, steps) = share.map_or((0, 0), |s| s.batch.counts());
    if submissions > 0 {
        eprintln!(
            "--batch {}: {steps} steps in {submissions} submissions ({:.2} a submission)",
            settings.batch,
            steps as f64 / submissions as f64
        );
    }
    match error {
        Some(e) => Err(e),
        None => Ok(records.into_iter().flatten().collect()),
    }
}

/// Any `workers` runs of a batch may be under way at once, each holding its state on the host:
/// refuse the batch before any starts when the largest `workers` of them would need more than
/// one run may take alone (`estimate::check_fits`: half of `available` bytes), rather than
/// leave the machine to run out of memory part-way.
fn check_batch_fits(
    planned: &[Planned],
    workers: usize,
    batch: usize,
    available: f64,
) -> Result<(), SweepError> {
    let mut bytes: Vec<f64> = planned
        .iter()
        .map(|p| estimate::footprint(&p.scene).bytes)
        .collect();
    bytes.sort_by(|a, b| b.total_cmp(a));
    let together: f64 = bytes.iter().take(workers).sum();
    if workers > 1 && together > 0.5 * available {
        return Err(SweepError::Batch(format!(
            "--batch {batch}: the {workers} largest runs need ≈ {:.1} GiB together, more than \
             the half of the ≈ {:.1} GiB available that runs may take (each alone needs at \
             most ≈ {:.1} GiB): give a smaller --batch",
            together / estimate::GIB,
            available / estimate::GIB,
            bytes[0] / estimate::GIB,
        )));
    }
    Ok(())
}

/// Why a run folder holds no summary of the run asked for ([`summary_left`]).
#[derive(Clone, Debug, PartialEq)]
pub enum NoSummary {
    /// No `summary.json`: the run has not started, is under way, or was killed.
    Missing,
    /// Its `scene.toml` is missing or lists other values than the scene asked for: the folder
    /// holds another run.
    OtherScene,
    /// `summary.json` is not a run's summary, or its numbers could not come from a run
    /// ([`Summary::is_plausible`]); says which.
    Damaged(String),
}

/// The summary that a run of exactly `scene` left in `dir`, however it ended: its `scene.toml`
/// must list the same resolved values (comment and blank lines aside), and its `summary.json`
/// must read back as a plausible summary. Both files are a few kB; one over the scene limit is
/// not a run's (nor read on: a path such as /dev/zero never ends).
pub fn summary_left(dir: &Path, scene: &Scene) -> Result<Summary, NoSummary> {
    let settings = |text: &str| -> Vec<String> {
        text.lines()
            .map(str::trim)
            .filter(|l| !l.is_empty() && !l.starts_with('#'))
            .map(String::from)
            .collect()
    };
    let small = |name: &str| -> Result<String, String> {
        match scene::read_capped(&dir.join(name), scene::SCENE_FILE_LIMIT) {
            Ok(Some(bytes)) => String::from_utf8(bytes).map_err(|_| "is not UTF-8 text".into()),
            Ok(None) => Err("is too large for a run's file".into()),
            Err(e) => Err(format!("cannot be read ({e})")),
        }
    };
    let json = match small("summary.json") {
        Err(_) if !dir.join("summary.json").exists() => return Err(NoSummary::Missing),
        Err(why) => return Err(NoSummary::Damaged(format!("summary.json {why}"))),
        Ok(json) => json,
    };
    let written = small(solver::SCENE_FILE).map_err(|_| NoSummary::OtherScene)?;
    if settings(&written) != settings(&scene.resolved_table()) {
        return Err(NoSummary::OtherScene);
    }
    let summary: Summary = serde_json::from_str(&json)
        .map_err(|e| NoSummary::Damaged(format!("summary.json is not a run's summary ({e})")))?;
    if !summary.is_plausible() {
        return Err(NoSummary::Damaged(
            "summary.json holds numbers no run gives (edited or damaged)".into(),
        ));
    }
    Ok(summary)
}

/// The summary of a completed run of exactly `scene` on `backend` left in `dir` by an earlier
/// process, for `penetrate validate --resume`: [`summary_left`] must find it, it must say
/// `completed` on the same backend (a GPU run: on the adapter named `gpu_adapter`, as its
/// summary names it), with `vtk` its frames must be there, and it must name this very build of
/// the solver (`solver_build`, [`build_id`](crate::output::summary::build_id)) or one whose
/// fingerprint is in `other_builds` (builds the caller vouches for by name).
pub fn completed_run(
    dir: &Path,
    scene: &Scene,
    backend: Backend,
    gpu_adapter: Option<&str>,
    vtk: bool,
    other_builds: &[String],
) -> Option<Summary> {
    let summary = summary_left(dir, scene).ok()?;
    if vtk && !dir.join("frames.pvd").is_file() {
        return None;
    }
    let same_adapter = backend != Backend::Gpu || gpu_adapter == Some(summary.adapter.as_str());
    (summary.status == "completed"
        && summary.backend == backend.name()
        && same_adapter
        && (same_build(&summary.solver_build)
            || fingerprint(&summary.solver_build)
                .is_some_and(|f| other_builds.iter().any(|o| o == f))))
    .then_some(summary)
}

/// Default output directory of a sweep: `runs/<case file stem>-<key's last part>`.
pub fn default_out(case: &Path, vary: &Vary) -> PathBuf {
    let stem = case
        .file_stem()
        .map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned());
    let last = vary.key.rsplit('.').next().unwrap_or(&vary.key);
    PathBuf::from("runs").join(format!("{stem}-{last}"))
}

/// `penetrate sweep`'s runs: `case` with the overrides `set`, then each value of `vary`, on
/// `backend` (`None`: the scene's `run.backend`), each run in `out/<label>/`. Every scene is
/// loaded here, so that a bad key or value stops the sweep before anything runs or is
/// announced.
pub fn plan_sweep(
    case: &Path,
    vary: &Vary,
    set: &[String],
    backend: Option<Backend>,
    settings: &RunSettings,
    out: &Path,
) -> Result<Vec<Planned>, SweepError> {
    let specs = sweep_specs(case, vary, set, backend, out)?;
    if let Some(first) = specs.first() {
        check_backend(first.backend, settings.adapter.as_deref())?;
    }
    plan(specs)
}

/// The runs [`plan_sweep`] plans, the same values, scenes and folders, without opening the
/// backend: for a sweep that runs on other machines (`--emit`), which open it themselves.
pub fn plan_members(
    case: &Path,
    vary: &Vary,
    set: &[String],
    backend: Option<Backend>,
    out: &Path,
) -> Result<Vec<Planned>, SweepError> {
    plan(sweep_specs(case, vary, set, backend, out)?)
}

/// The run of each value of `vary`, its scene not yet loaded; the base scene is, for its
/// `run.backend` and so that a bad `--set` is named once rather than per run.
fn sweep_specs(
    case: &Path,
    vary: &Vary,
    set: &[String],
    backend: Option<Backend>,
    out: &Path,
) -> Result<Vec<RunSpec>, SweepError> {
    if let Some(clash) = set.iter().find(|s| vary.clashes_with(s)) {
        return Err(SweepError::Spec(format!(
            "--set {clash}: sets what --vary {} sweeps, whose values would replace it in every \
             run; drop one of the two",
            vary.key
        )));
    }
    let base = scene::load(case, set).map_err(SweepError::Scene)?;
    let backend = backend.unwrap_or(base.run.backend);
    Ok(vary
        .values
        .iter()
        .map(|&v| {
            let mut overrides = set.to_vec();
            overrides.push(vary.set(v));
            RunSpec {
                label: vary.label(v),
                case: case.to_path_buf(),
                overrides,
                backend,
                dir: out.join(vary.label(v)),
            }
        })
        .collect())
}

/// Runs a planned sweep (`plan_sweep`) and writes `out/sweep.csv`.
pub fn sweep(
    planned: Vec<Planned>,
    vary: &Vary,
    settings: &RunSettings,
    out: &Path,
    progress: impl FnMut(&RunRecord),
) -> Result<Vec<RunRecord>, SweepError> {
    crate::output::create_folder(out).map_err(|e| SweepError::Io(e.to_string()))?;
    let planned_runs = planned.len();
    let records = run_set(planned, settings, progress)?;
    let path = out.join("sweep.csv");
    write_sweep_csv(&path, vary, &records)
        .map_err(|e| SweepError::Io(format!("{}: {e}", path.display())))?;
    if crate::interrupt::requested() {
        return Err(SweepError::Interrupted(format!(
            "interrupted after {} of {planned_runs} runs (a run under way stopped where it was); \
             {} has their rows",
            records.len(),
            path.display()
        )));
    }
    Ok(records)
}

/// The summary fields of a sweep row, after the varied value.
const SUMMARY_COLUMNS: [&str; 14] = [
    "status",
    "depth_m",
    "projectile_velocity_m_s",
    "max_damage",
    "max_plastic_strain",
    "final_length_m",
    "steps",
    "particles",
    "elements",
    "wall_s",
    "energy_error",
    "momentum_error",
    "backend",
    "dir",
];

/// The summary fields of `r` in the order of [`SUMMARY_COLUMNS`] (empty where it could not
/// start).
fn summary_fields(r: &RunRecord) -> Vec<String> {
    let dir = r.dir.display().to_string();
    match &r.outcome {
        Ok(s) => vec![
            s.status.clone(),
            s.depth_m.to_string(),
            s.projectile_velocity_m_s.to_string(),
            s.max_damage.to_string(),
            s.max_plastic_strain.to_string(),
            s.final_length_m.to_string(),
            s.steps.to_string(),
            s.particles.to_string(),
            s.elements.to_string(),
            s.wall_s.to_string(),
            s.energy_error.to_string(),
            s.momentum_error.to_string(),
            s.backend.clone(),
            dir,
        ],
        Err(e) => {
            let mut row = vec![e.clone()];
            row.resize(SUMMARY_COLUMNS.len() - 2, String::new());
            row.extend([r.backend.name().to_string(), dir]);
            row
        }
    }
}

/// `sweep.csv`: the varied value and the summary fields of each run, to `path` (the in-process
/// sweep's and `--collect`'s).
pub(crate) fn write_sweep_csv(
    path: &Path,
    vary: &Vary,
    records: &[RunRecord],
) -> std::io::Result<()> {
    let mut header = vec![vary.key.clone()];
    header.extend(SUMMARY_COLUMNS.iter().map(|c| c.to_string()));
    let rows: Vec<Vec<String>> = vary
        .values
        .iter()
        .zip(records)
        .map(|(v, r)| {
            let mut row = vec![scene::number_text(*v)];
            row.extend(summary_fields(r));
            row
        })
        .collect();
    crate::output::write_csv(path, &header, &rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `--resume` reads a run's `scene.toml` and `summary.json` only up to the scene-file
    /// limit: a folder whose files are junk, or never end (/dev/zero), holds no completed run.
    #[cfg(unix)]
    #[test]
    fn junk_in_a_run_folder_is_no_completed_run() {
        let scene = scene::shipped_case("smoke.toml", &[]);
        let dir = std::env::temp_dir().join(format!("penetrate-junk-run-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let scene_file = dir.join(solver::SCENE_FILE);
        let summary = dir.join("summary.json");
        let zero = Path::new("/dev/zero");
        let check = || completed_run(&dir, &scene, Backend::Cpu, None, false, &[]).is_none();

        std::os::unix::fs::symlink(zero, &scene_file).unwrap();
        assert!(check(), "scene.toml that never ends");
        std::fs::remove_file(&scene_file).unwrap();
        std::fs::write(&scene_file, scene.resolved_table()).unwrap();
        std::os::unix::fs::symlink(zero, &summary).unwrap();
        assert!(check(), "summary.json that never ends");
        std::fs::remove_file(&summary).unwrap();
        std::fs::write(&summary, b"{\"status\": \xff").unwrap();
        assert!(check(), "summary.json not UTF-8");
        std::fs::write(&summary, b"{\"status\": \"completed\"").unwrap();
        assert!(check(), "summary.json cut short");
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// A completed run is taken by `--resume` until a number in its summary is made
    /// impossible (a bar −10³⁰⁰ m long, damage 2): then it is run again, not reported.
    #[test]
    fn a_summary_with_impossible_numbers_is_no_completed_run() {
        let scene = scene::shipped_case("smoke.toml", &["run.end_time=2e-6"]);
        let dir = std::env::temp_dir().join(format!("penetrate-tampered-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let opts = RunOptions {
            out: dir.clone(),
            quiet: true,
            vtk: false,
            backend: Some(Backend::Cpu),
            adapter: None,
            checkpoint_every: None,
            restart: None,
            share: None,
        };
        solver::run(&scene, &opts).unwrap();
        let taken = || completed_run(&dir, &scene, Backend::Cpu, None, false, &[]);
        let good = taken().expect("the run just made is taken");
        let path = dir.join("summary.json");
        let write = |s: &Summary| std::fs::write(&path, serde_json::to_string(s).unwrap()).unwrap();
        let mut bad = good.clone();
        bad.final_length_m = -1e300;
        write(&bad);
        assert!(taken().is_none(), "a negative length");
        let mut bad = good.clone();
        bad.max_damage = 2.0;
        write(&bad);
        assert!(taken().is_none(), "damage above 1");
        write(&good);
        assert!(taken().is_some(), "the summary written back");
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// A batch is refused when the runs it would make at once need more memory together than
    /// one run may take alone, and only then: the largest runs are counted, as many as the
    /// batch makes at once.
    #[test]
    fn a_batch_that_would_not_fit_in_memory_is_refused() {
        let run = |spacing: &str| {
            let scene = scene::shipped_case("smoke.toml", &[spacing]);
            Planned {
                spec: RunSpec {
                    label: spacing.into(),
                    case: PathBuf::from("cases/smoke.toml"),
                    overrides: vec![spacing.into()],
                    backend: Backend::Cpu,
                    dir: PathBuf::from("unused"),
                },
                scene,
            }
        };
        let planned = vec![
            run("target.spacing=0.004"),
            run("target.spacing=0.002"),
            run("target.spacing=0.003"),
        ];
        let bytes: Vec<f64> = planned
            .iter()
            .map(|p| estimate::footprint(&p.scene).bytes)
            .collect();
        assert!(bytes[1] > bytes[2] && bytes[2] > bytes[0], "{bytes:?}");
        // Room for the two largest together, but not a byte more.
        let room = 2.0 * (bytes[1] + bytes[2]);
        assert!(check_batch_fits(&planned, 2, 2, room).is_ok());
        assert!(check_batch_fits(&planned, 3, 4, room).is_err());
        let err = check_batch_fits(&planned, 2, 2, 0.99 * room).unwrap_err();
        assert!(matches!(err, SweepError::Batch(_)), "{err:?}");
        let said = err.to_string();
        assert!(said.contains("--batch 2: the 2 largest runs"), "{said}");
        assert!(said.contains("give a smaller --batch"), "{said}");
        // Alone, a run is for `check_fits` to judge.
        assert!(check_batch_fits(&planned, 1, 1, bytes[0]).is_ok());
    }

    #[test]
    fn a_range_includes_both_ends_without_round_off() {
        let v = Vary::parse("projectile.velocity=200:800:100").unwrap();
        assert_eq!(v.key, "projectile.velocity");
        assert_eq!(
            v.values,
            vec![200.0, 300.0, 400.0, 500.0, 600.0, 700.0, 800.0]
        );
        let v = Vary::parse("target.spacing=0.1:0.3:0.1").unwrap();
        assert_eq!(v.values, vec![0.1, 0.2, 0.3]);
        assert_eq!(v.label(0.3), "spacing-0.3");
        assert_eq!(v.set(0.3), "target.spacing=0.3");
        // Far from 1, in exponent form: a scene reads it as a number, and a label stays short.
        assert_eq!(v.set(1e20), "target.spacing=1e20");
        assert_eq!(v.label(2.5e-9), "spacing-2.5e-9");
        assert_eq!(v.label(1e-6), "spacing-0.000001");
        // b need not be on the grid; a single value is a range too.
        assert_eq!(Vary::parse("k=1:2.5:1").unwrap().values, vec![1.0, 2.0]);
        assert_eq!(Vary::parse("k=5:5:1").unwrap().values, vec![5.0]);
    }

    #[test]
    fn malformed_specs_say_what_is_wrong() {
        for (spec, says) in [
            ("projectile.velocity", "expected key=a:b:step"),
            ("=1:2:1", "scene key"),
            ("k=1:2", "three numbers"),
            ("k=1:2:3:4", "three numbers"),
            ("k=a:2:1", "not a finite number"),
            ("k=1:inf:1", "not a finite number"),
            ("k=1:2:0", "must be > 0"),
            ("k=1:2:-1", "must be > 0"),
            ("k=3:2:1", "empty range"),
            ("k=0:1000:1", "gives 1001 runs, more than the 200"),
            ("k=1:1e30:1e-30", "gives 1.0e60 runs, more than the 200"),
        ] {
            let e = Vary::parse(spec).unwrap_err().to_string();
            assert!(e.contains(says), "{spec}: {e}");
            assert!(e.starts_with(&format!("--vary {spec}")), "{e}");
        }
    }

    #[test]
    fn a_set_of_the_swept_key_is_caught() {
        let vary = Vary::parse("projectile.velocity=200:300:100").unwrap();
        for set in [
            "projectile.velocity=5",
            " projectile . velocity =5",
            "projectile={velocity=5}",
            "projectile.velocity.x=1",
        ] {
            assert!(vary.clashes_with(set), "{set}");
        }
        for set in [
            "projectile.velocity_x=5",
            "projectile.diameter=0.02",
            "run.cfl=0.3",
        ] {
            assert!(!vary.clashes_with(set), "{set}");
        }
    }
}
