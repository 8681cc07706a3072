//! `penetrate validate`: the shipped validation cases and the paper's studies, run in process
//! through [`super::sweep`], written up in `DIR/report.md` with PNG plots ([`super::plot`]) and
//! each section's raw data as CSV.
//!
//! Sections ([`Section`]): Taylor bars at three element sizes; the Forrestal et al. (1994) shots
//! against the measurements and Forrestal's equation; the target-size check; depth error
//! against run time at four resolutions on each backend; and the paper's studies — rigid
//! (λ = 0) against elastic-plastic (λ = 0.2) histories, the projectile's plastic deformation
//! against striking speed, and the shell projectile's critical velocity and damage.
//!
//! Nothing here knows an expected result: measured values come from the data files, accuracy
//! targets are the and stated beside each check. A run that does not complete is
//! reported in its row; [`Outcome::failed`] lists them for the exit code.

pub mod bisect;
mod convergence;
pub mod data;
pub mod forrestal;
mod frame;
mod penetration;
mod shell;
mod solid;
mod taylor;

use std::fmt;
use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::output::summary::{build_id, fingerprint};
use crate::scene::{self, Backend, Scene};
use crate::studies::plot::Chart;
use crate::studies::sweep::{self, RunRecord, RunSettings, RunSpec, SweepError, Vary};

/// A part of the report, runnable alone with `--only`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Section {
    Taylor,
    Forrestal,
    TargetSize,
    Convergence,
    RigidVsElastic,
    Deformation,
    Shell,
}

impl Section {
    pub const ALL: [Section; 7] = [
        Section::Taylor,
        Section::Forrestal,
        Section::TargetSize,
        Section::Convergence,
        Section::RigidVsElastic,
        Section::Deformation,
        Section::Shell,
    ];

    /// The name `--only` takes, also the section's folder under the output directory.
    pub fn name(self) -> &'static str {
        match self {
            Section::Taylor => "taylor",
            Section::Forrestal => "forrestal",
            Section::TargetSize => "target-size",
            Section::Convergence => "convergence",
            Section::RigidVsElastic => "rigid-vs-elastic",
            Section::Deformation => "deformation",
            Section::Shell => "shell",
        }
    }

    /// The section's heading in the report.
    pub fn title(self) -> &'static str {
        match self {
            Section::Taylor => "Taylor bars",
            Section::Forrestal => "Forrestal et al. (1994) shots",
            Section::TargetSize => "Target size",
            Section::Convergence => "Error against run time",
            Section::RigidVsElastic => "Rigid against elastic-plastic projectile (paper Fig. 2-3)",
            Section::Deformation => "Plastic deformation against striking speed (paper Fig. 4)",
            Section::Shell => "Shell projectile: critical velocity and damage (paper Fig. 6, 7, 9)",
        }
    }

    pub fn parse(name: &str) -> Result<Section, ValidateError> {
        Section::ALL
            .into_iter()
            .find(|s| s.name() == name.trim())
            .ok_or_else(|| {
                let names: Vec<&str> = Section::ALL.iter().map(|s| s.name()).collect();
                ValidateError::Input(format!(
                    "--only {name}: no such section; choose from {}",
                    names.join(", ")
                ))
            })
    }
}

/// What `penetrate validate` was asked to do.
#[derive(Clone, Debug)]
pub struct Options {
    /// Folder of the shipped scenes (`cases/`).
    pub cases: PathBuf,
    /// Folder of the measurements (`taylor.csv`, `forrestal1994.csv`).
    pub data: PathBuf,
    pub out: PathBuf,
    /// Backends in order: the error-against-run-time section runs on each, every other section
    /// on the first.
    pub backends: Vec<Backend>,
    /// Part of the GPU adapter's name.
    pub adapter: Option<String>,
    /// Tiny resolutions and short end times: tests the tooling, validates nothing.
    pub quick: bool,
    /// Sections to run; empty: all.
    pub only: Vec<Section>,
    /// Take a completed run already in `out` when its resolved scene and backend are the ones
    /// asked for ([`sweep::completed_run`]) instead of running it again.
    pub resume: bool,
    /// With `resume`, also take runs made by these builds (their fingerprints, 16 hex digits):
    /// the report lists the build of every run it used.
    pub resume_builds: Vec<String>,
}

/// How a validation ended (its accuracy is in the report, not here).
#[derive(Clone, Debug)]
pub struct Outcome {
    pub report: PathBuf,
    /// Runs made (runs shared between sections count once).
    pub runs: usize,
    /// One line per run that did not complete.
    pub failed: Vec<String>,
    pub wall_s: f64,
}

/// Why a validation could not be carried out.
#[derive(Clone, Debug, PartialEq)]
pub enum ValidateError {
    /// Bad options, a missing or malformed data file, a scene that does not load.
    Input(String),
    /// The backend asked for cannot run.
    Backend(String),
    /// Output could not be written.
    Io(String),
    /// Ctrl-C or SIGTERM stopped the validation ([`crate::interrupt`]).
    Interrupted(String),
}

impl ValidateError {
    /// The command line's exit code: 2 bad input, 3 output not writable, 130 interrupted.
    pub fn exit_code(&self) -> u8 {
        match self {
            ValidateError::Io(_) => 3,
            ValidateError::Interrupted(_) => crate::interrupt::EXIT_CODE,
            _ => 2,
        }
    }
}

impl fmt::Display for ValidateError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ValidateError::Input(m)
            | ValidateError::Backend(m)
            | ValidateError::Io(m)
            | ValidateError::Interrupted(m) => f.write_str(m),
        }
    }
}

impl std::error::Error for ValidateError {}

impl From<SweepError> for ValidateError {
    fn from(e: SweepError) -> ValidateError {
        match e {
            SweepError::Io(m) => ValidateError::Io(m),
            SweepError::Backend(m) => ValidateError::Backend(m),
            SweepError::Interrupted(m) => ValidateError::Interrupted(m),
            other => ValidateError::Input(other.to_string()),
        }
    }
}

/// Resolutions and ranges of a validation: the shipped scenes' (full) or tiny ones (`--quick`).
struct Settings {
    quick: bool,
    /// Overrides of every run of the Forrestal penetrator (none in full).
    forrestal: Vec<String>,
    /// Overrides of every shell run.
    shell: Vec<String>,
    /// Taylor element sizes as multiples of the scene's.
    taylor_factors: [f64; 3],
    /// Lattice spacing and element size together, as multiples of the Forrestal runs'.
    convergence_factors: [f64; 4],
    /// Striking speeds of the deformation study (on the 642 m/s shot's scene).
    deformation: Vary,
    /// Striking speeds of the shell sweep, and the bisection's tolerance (m/s).
    shell_speeds: Vary,
    shell_tolerance: f64,
}

/// The quick target: a 12 mm lattice in a 0.1 m × 0.3 m block, 0.3 ms of flight (about a
/// second of CPU per run on 2 cores).
const QUICK_TARGET: [&str; 4] = [
    "target.spacing=0.012",
    "target.radius=0.1",
    "target.thickness=0.3",
    "run.end_time=3e-4",
];

impl Settings {
    fn new(quick: bool) -> Result<Settings, ValidateError> {
        let with = |extra: &[&str]| -> Vec<String> {
            QUICK_TARGET
                .iter()
                .chain(extra)
                .map(|s| s.to_string())
                .collect()
        };
        let speeds = |spec: &str| Vary::parse(&format!("projectile.velocity={spec}"));
        Ok(if quick {
            Settings {
                quick,
                // The coarsest mesh the mesher allows (diameter/4 = 6.7 mm).
                forrestal: with(&["projectile.element_size=0.0065"]),
                // Two 4 mm elements across a 4.45 mm wall.
                shell: with(&[
                    "projectile.element_size=0.004",
                    "projectile.cavity.diameter=0.018",
                ]),
                taylor_factors: [5.0, 4.0, 3.0],
                convergence_factors: [1.0, 0.85, 0.7, 0.55],
                deformation: speeds("300:800:250")?,
                // Damage appears in the wall between 150 and 200 m/s here: one bisection step.
                shell_speeds: speeds("100:500:100")?,
                shell_tolerance: 60.0,
            }
        } else {
            Settings {
                quick,
                forrestal: vec![],
                shell: vec![],
                taylor_factors: [2.0, 1.0, 0.5],
                convergence_factors: [2.0, 1.5, 1.0, 0.75],
                deformation: speeds("200:800:150")?,
                // From 50 m/s: as shipped the wall is undamaged at 112.5 m/s and damaged at
                // 118.75 m/s (README, the shell study), below the paper's 250 m/s.
                shell_speeds: speeds("50:450:50")?,
                shell_tolerance: 10.0,
            }
        })
    }
}

/// A run a section asks for: `case` (a file in the cases folder) with `overrides`.
struct Ask {
    label: String,
    case: String,
    overrides: Vec<String>,
    backend: Backend,
}

/// A pass/fail line of the report's summary.
struct Check {
    section: Section,
    what: String,
    target: String,
    result: String,
    /// `None`: not evaluated (a run it needs did not complete).
    pass: Option<bool>,
}

/// A section's part of the report.
struct SectionOut {
    markdown: String,
    checks: Vec<Check>,
}

/// The state of one validation: options, settings, and every run made so far.
struct Context<'a> {
    opts: &'a Options,
    settings: Settings,
    /// Runs made so far; a run asked again with the same resolved scene and backend is reused.
    done: Vec<RunRecord>,
    failed: Vec<String>,
    reused: usize,
    /// Runs taken from an earlier process's output (`--resume`).
    resumed: usize,
    /// With a GPU backend: the adapter's name as run summaries give it; `--resume` takes only
    /// GPU runs made on it.
    gpu_adapter: Option<String>,
    estimate: usize,
    progress: &'a mut dyn FnMut(&str),
}

impl Context<'_> {
    /// The backend every section but the convergence study runs on.
    fn primary(&self) -> Backend {
        self.opts.backends[0]
    }

    fn case(&self, file: &str) -> PathBuf {
        self.opts.cases.join(file)
    }

    /// A scene of the cases folder with `overrides`.
    fn scene(&self, file: &str, overrides: &[String]) -> Result<Scene, ValidateError> {
        scene::load(&self.case(file), overrides).map_err(|e| ValidateError::Input(e.to_string()))
    }

    fn dir(&self, section: Section) -> PathBuf {
        self.opts.out.join(section.name())
    }

    /// Runs `asks` in order, reusing any earlier run of the same resolved scene on the same
    /// backend. Every scene is loaded before the first run.
    fn run(
        &mut self,
        section: Section,
        asks: Vec<Ask>,
        vtk: bool,
    ) -> Result<Vec<RunRecord>, ValidateError> {
        let runs = self.dir(section).join("runs");
        let specs = asks
            .into_iter()
            .map(|a| RunSpec {
                dir: runs.join(format!("{}-{}", a.label, a.backend.name())),
                label: a.label,
                case: self.case(&a.case),
                overrides: a.overrides,
                backend: a.backend,
            })
            .collect();
        let planned = sweep::plan(specs)
            .map_err(|e| ValidateError::Input(format!("{}: {e}", section.name())))?;
        let settings = RunSettings {
            adapter: self.opts.adapter.clone(),
            vtk,
        };
        let mut records = Vec::with_capacity(planned.len());
        for p in planned {
            let earlier = self
                .done
                .iter()
                .find(|r| r.backend == p.spec.backend && r.scene == p.scene);
            if let Some(r) = earlier {
                self.reused += 1;
                records.push(r.clone());
                continue;
            }
            let (label, backend) = (p.spec.label.clone(), p.spec.backend);
            let made = self.done.len() + 1;
            let estimate = self.estimate.max(made);
            let earlier_process = self
                .opts
                .resume
                .then(|| {
                    let adapter = self.gpu_adapter.as_deref();
                    let other = &self.opts.resume_builds;
                    self.resume_candidates(&p.spec.dir)
                        .into_iter()
                        .find_map(|dir| {
                            sweep::completed_run(&dir, &p.scene, backend, adapter, vtk, other)
                                .map(|summary| (dir, summary))
                        })
                })
                .flatten();
            let progress = &mut *self.progress;
            if let Some((dir, summary)) = earlier_process {
                let r = RunRecord {
                    label,
                    dir,
                    backend,
                    scene: p.scene,
                    outcome: Ok(summary),
                };
                progress(&format!(
                    "[{made}/≤{estimate}] {} {} on {}: {} (resumed from {})",
                    section.name(),
                    r.label,
                    backend.name(),
                    describe(&r),
                    r.dir.display()
                ));
                self.resumed += 1;
                self.done.push(r.clone());
                records.push(r);
                continue;
            }
            let mut new = sweep::run_set(vec![p], &settings, |r| {
                progress(&format!(
                    "[{made}/≤{estimate}] {} {label} on {}: {}",
                    section.name(),
                    backend.name(),
                    describe(r)
                ))
            })?;
            if crate::interrupt::requested() {
                return Err(ValidateError::Interrupted(format!(
                    "interrupted in {} {label} on {} (its run stopped where it was); run the \
                     same command with --resume to go on",
                    section.name(),
                    backend.name()
                )));
            }
            let Some(r) = new.pop() else { continue };
            if r.completed().is_none() {
                self.failed.push(format!(
                    "{} {label} on {}: {}",
                    section.name(),
                    backend.name(),
                    r.status()
                ));
            }
            self.done.push(r.clone());
            records.push(r);
        }
        Ok(records)
    }

    /// Where `--resume` looks for an earlier process's run that `own` would hold: `own` first,
    /// then every run folder of every section, since sections share runs (the Forrestal shots
    /// are also the rigid-vs-elastic study's λ = 0.2 runs) and an earlier process may have made
    /// a run for another section than the one now asking.
    fn resume_candidates(&self, own: &Path) -> Vec<PathBuf> {
        let mut others: Vec<PathBuf> = Section::ALL
            .into_iter()
            .filter_map(|s| std::fs::read_dir(self.dir(s).join("runs")).ok())
            .flatten()
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|d| d.is_dir() && d != own)
            .collect();
        others.sort();
        std::iter::once(own.to_path_buf()).chain(others).collect()
    }

    /// Writes `rows` under `header` to the section's `file`; returns the report's link to it.
    fn csv(
        &self,
        section: Section,
        file: &str,
        header: &[&str],
        rows: &[Vec<String>],
    ) -> Result<String, ValidateError> {
        let path = self.dir(section).join(file);
        crate::output::write_csv(&path, header, rows)
            .map_err(|e| ValidateError::Io(format!("{}: {e}", path.display())))?;
        Ok(format!("[{file}]({}/{file})", section.name()))
    }

    /// Draws `chart` into the section's `file`; returns the report's image link.
    fn plot(&self, section: Section, file: &str, chart: &Chart) -> Result<String, ValidateError> {
        let path = self.dir(section).join(file);
        chart
            .write_png(&path)
            .map_err(|e| ValidateError::Io(format!("{}: {e}", path.display())))?;
        Ok(format!("![{}]({}/{file})\n", chart.title, section.name()))
    }

    /// `path` relative to the output directory, for the report and the CSVs.
    fn rel(&self, path: &Path) -> String {
        path.strip_prefix(&self.opts.out)
            .unwrap_or(path)
            .display()
            .to_string()
    }
}

/// One line on how a run ended.
fn describe(r: &RunRecord) -> String {
    match &r.outcome {
        Ok(s) if s.particles > 0 => format!(
            "{}, depth {:.4} m, max damage {:.2}, {:.1} s",
            s.status, s.depth_m, s.max_damage, s.wall_s
        ),
        Ok(s) => format!(
            "{}, length {:.3} mm, {:.1} s",
            s.status,
            s.final_length_m * 1e3,
            s.wall_s
        ),
        Err(e) => e.clone(),
    }
}

fn sections(opts: &Options) -> Vec<Section> {
    Section::ALL
        .into_iter()
        .filter(|s| opts.only.is_empty() || opts.only.contains(s))
        .collect()
}

/// Upper bound on the runs `opts` asks for (runs shared between sections are made once).
pub fn estimate_runs(opts: &Options) -> Result<usize, ValidateError> {
    let settings = Settings::new(opts.quick)?;
    let shots = match data::forrestal(&opts.data) {
        Ok(s) => s.len(),
        Err(_) if !sections(opts).contains(&Section::Forrestal) => 0,
        Err(e) => return Err(e),
    };
    let shell_width = settings
        .shell_speeds
        .values
        .windows(2)
        .map(|w| w[1] - w[0])
        .fold(0.0, f64::max);
    Ok(sections(opts)
        .into_iter()
        .map(|s| match s {
            Section::Taylor => taylor::CASES.len() * settings.taylor_factors.len(),
            Section::Forrestal => shots,
            Section::TargetSize => 2,
            Section::Convergence => {
                // The levels, and the round-off ensemble's nudged runs at the coarsest one.
                penetration::STUDY_SHOTS.len()
                    * (settings.convergence_factors.len() + convergence::NUDGES.len() - 1)
                    * opts.backends.len()
            }
            Section::RigidVsElastic => 2 * penetration::STUDY_SHOTS.len(),
            Section::Deformation => settings.deformation.values.len(),
            Section::Shell => {
                settings.shell_speeds.values.len()
                    + bisect::steps(shell_width, settings.shell_tolerance)
            }
        })
        .sum())
}

/// Runs the sections `opts` asks for and writes `report.md`, the CSVs and the plots under
/// `opts.out`. `progress` gets one line per run.
pub fn run(opts: &Options, progress: &mut dyn FnMut(&str)) -> Result<Outcome, ValidateError> {
    let started = Instant::now();
    if opts.backends.is_empty() {
        return Err(ValidateError::Input("no backend to run on".into()));
    }
    if let Some(bad) = opts
        .resume_builds
        .iter()
        .find(|b| fingerprint(b.as_str()) != Some(b.as_str()))
    {
        return Err(ValidateError::Input(format!(
            "--resume-build {bad}: a build's fingerprint is the 16 hex digits that end its \
             `solver_build` (summary.json)"
        )));
    }
    if !opts.resume_builds.is_empty() && !opts.resume {
        return Err(ValidateError::Input(
            "--resume-build takes earlier runs: it needs --resume".into(),
        ));
    }
    let mut gpu_adapter = None;
    for &b in &opts.backends {
        gpu_adapter = gpu_adapter.or(sweep::check_backend(b, opts.adapter.as_deref())?);
    }
    let chosen = sections(opts);
    for s in &chosen {
        let dir = opts.out.join(s.name());
        crate::output::create_folder(&dir).map_err(ValidateError::Io)?;
    }
    let estimate = estimate_runs(opts)?;
    let names: Vec<&str> = chosen.iter().map(|s| s.name()).collect();
    progress(&format!(
        "validate: {} run, sections {}: at most {estimate} runs",
        if opts.quick { "quick" } else { "full" },
        names.join(", ")
    ));
    let mut ctx = Context {
        opts,
        settings: Settings::new(opts.quick)?,
        done: Vec::new(),
        failed: Vec::new(),
        reused: 0,
        resumed: 0,
        gpu_adapter,
        estimate,
        progress,
    };
    let mut parts = Vec::new();
    for &s in &chosen {
        let out = match s {
            Section::Taylor => taylor::run(&mut ctx)?,
            Section::Forrestal => penetration::forrestal(&mut ctx)?,
            Section::TargetSize => penetration::target_size(&mut ctx)?,
            Section::Convergence => convergence::convergence(&mut ctx)?,
            Section::RigidVsElastic => solid::rigid_vs_elastic(&mut ctx)?,
            Section::Deformation => solid::deformation(&mut ctx)?,
            Section::Shell => shell::run(&mut ctx)?,
        };
        parts.push((s, out));
    }
    let wall_s = started.elapsed().as_secs_f64();
    let report = opts.out.join("report.md");
    std::fs::write(&report, render(&ctx, &chosen, &parts, wall_s))
        .map_err(|e| ValidateError::Io(format!("{}: {e}", report.display())))?;
    Ok(Outcome {
        report,
        runs: ctx.done.len(),
        failed: ctx.failed,
        wall_s,
    })
}

fn render(
    ctx: &Context,
    chosen: &[Section],
    parts: &[(Section, SectionOut)],
    wall_s: f64,
) -> String {
    let opts = ctx.opts;
    let mut md = String::from("# Validation report\n\n");
    if opts.quick {
        md += "> **Quick run** (`--quick`): every section at a tiny resolution (12 mm lattice, \
               6.5 mm elements, a 0.1 m × 0.3 m target) and 0.3 ms of flight, the Taylor bars at \
               3–5× the shipped element size. Its numbers test the tooling; **they are not \
               validation**.\n\n";
    }
    let names = |list: &[Section]| -> String {
        let n: Vec<&str> = list.iter().map(|s| s.name()).collect();
        if n.is_empty() {
            "none".into()
        } else {
            n.join(", ")
        }
    };
    let skipped: Vec<Section> = Section::ALL
        .into_iter()
        .filter(|s| !chosen.contains(s))
        .collect();
    let backends: Vec<String> = opts
        .backends
        .iter()
        .map(|&b| {
            let adapter = ctx
                .done
                .iter()
                .filter(|r| r.backend == b && b == Backend::Gpu)
                .find_map(|r| r.summary().map(|s| format!(" ({})", s.adapter)))
                .unwrap_or_default();
            format!("{}{adapter}", b.name())
        })
        .collect();
    md += &format!("- Sections run: {}\n", names(chosen));
    md += &format!("- Sections not run: {}\n", names(&skipped));
    md += &format!(
        "- Backends: {} (the error-against-run-time section runs on each, the others on the first)\n",
        backends.join(", ")
    );
    md += &format!("- Data: `{}`\n", opts.data.display());
    md += &format!(
        "- Runs: {} ({} of them resumed from earlier output in this folder; {} more asked again \
         and reused), {} did not complete\n",
        ctx.done.len(),
        ctx.resumed,
        ctx.reused,
        ctx.failed.len()
    );
    md += &builds_line(ctx);
    md += &format!("- Wall time: {wall_s:.0} s\n\n");
    if !ctx.failed.is_empty() {
        md += "Runs that did not complete:\n\n";
        for f in &ctx.failed {
            md += &format!("- {f}\n");
        }
        md += "\n";
    }
    md += "## Checks\n\n";
    let rows: Vec<Vec<String>> = parts
        .iter()
        .flat_map(|(_, p)| &p.checks)
        .map(|c| {
            vec![
                c.section.name().to_string(),
                c.what.clone(),
                c.target.clone(),
                c.result.clone(),
                match c.pass {
                    Some(true) => "pass".into(),
                    Some(false) => "**fail**".into(),
                    None => "n/a".into(),
                },
            ]
        })
        .collect();
    if rows.is_empty() {
        md += "No section with an accuracy target ran.\n\n";
    } else {
        md += &table(&["section", "check", "target", "result", "verdict"], &rows);
    }
    for (s, p) in parts {
        md += &format!("\n## {}\n\n{}", s.title(), p.markdown);
    }
    md
}

/// The report's line naming the solver build of every run it used, this executable's first.
fn builds_line(ctx: &Context) -> String {
    let this = build_id();
    let mut counts: Vec<(String, usize)> = vec![(this.to_string(), 0)];
    for s in ctx.done.iter().filter_map(|r| r.summary()) {
        match counts.iter_mut().find(|(b, _)| *b == s.solver_build) {
            Some((_, n)) => *n += 1,
            None => counts.push((s.solver_build.clone(), 1)),
        }
    }
    let parts: Vec<String> = counts
        .iter()
        .enumerate()
        .filter(|(i, (_, n))| *i == 0 || *n > 0)
        .map(|(i, (b, n))| {
            let whose = if i == 0 {
                "this executable"
            } else {
                "taken with --resume-build"
            };
            format!("`{b}` ({whose}): {n}")
        })
        .collect();
    format!("- Solver builds of the runs: {}\n", parts.join("; "))
}

/// A Markdown table (a `|` in a cell is escaped).
fn table<S: AsRef<str>>(header: &[&str], rows: &[Vec<S>]) -> String {
    let line = |cells: Vec<String>| format!("| {} |\n", cells.join(" | "));
    let escape = |c: &str| c.replace('|', "\\|");
    let mut t = line(header.iter().map(|h| escape(h)).collect());
    t += &format!("|{}\n", "---|".repeat(header.len()));
    for r in rows {
        t += &line(r.iter().map(|c| escape(c.as_ref())).collect());
    }
    t + "\n"
}

/// A signed relative error in per cent.
fn pct(x: f64) -> String {
    format!("{:+.1} %", 100.0 * x)
}

/// `f(x)`, or a dash where there is no value.
fn or_dash<T>(x: Option<T>, f: impl FnOnce(T) -> String) -> String {
    x.map_or_else(|| "–".into(), f)
}

/// The most `validate` reads of one file a run wrote (`history.csv`, a projectile frame). A
/// shipped case writes about 500 history rows (0.2 MB) and frames of a few MB; the limit is far
/// above both, and keeps a file that never ends (a run folder's file replaced by a link to
/// /dev/zero, say) from being read until memory runs out.
const RUN_FILE_LIMIT: u64 = 1 << 30;

/// A text file a run wrote, read whole: a regular file of at most [`RUN_FILE_LIMIT`] bytes of
/// UTF-8, or an error naming the path and what is wrong with it.
fn read_run_file(path: &Path) -> Result<String, String> {
    let fail = |why: String| format!("{}: {why}", path.display());
    let meta = std::fs::metadata(path).map_err(|e| fail(e.to_string()))?;
    let too_large = || {
        fail(format!(
            "larger than {} GiB, not read",
            RUN_FILE_LIMIT >> 30
        ))
    };
    if !meta.is_file() {
        return Err(fail("not a regular file".into()));
    }
    if meta.len() > RUN_FILE_LIMIT {
        return Err(too_large());
    }
    // Capped again while reading: the file may grow after the look.
    let bytes = scene::read_capped(path, RUN_FILE_LIMIT)
        .map_err(|e| fail(e.to_string()))?
        .ok_or_else(too_large)?;
    String::from_utf8(bytes).map_err(|_| fail("not UTF-8 text".into()))
}

/// Columns of a run's `history.csv`, by header name.
fn history(dir: &Path, columns: &[&str]) -> Result<Vec<Vec<f64>>, String> {
    let path = dir.join("history.csv");
    let text = read_run_file(&path)?;
    crate::output::history::read_columns(&path, text.as_bytes(), columns)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A run's file that never ends, is too large or is not text is refused with its path
    /// named, before it is read; a good one is read.
    #[test]
    fn a_run_file_that_never_ends_is_refused() {
        let dir = std::env::temp_dir().join(format!("penetrate-run-file-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let csv = dir.join("history.csv");
        let refused = |why: &str| {
            let e = history(&dir, &["time_s"]).unwrap_err();
            assert!(
                e.starts_with(&csv.display().to_string()) && e.contains(why),
                "{e}"
            );
        };

        std::fs::write(&csv, "time_s,depth_m\n0,0\n1e-6,0.5\n").unwrap();
        assert_eq!(
            history(&dir, &["depth_m", "time_s"]).unwrap(),
            vec![vec![0.0, 0.5], vec![0.0, 1e-6]]
        );
        std::fs::remove_file(&csv).unwrap();
        std::os::unix::fs::symlink("/dev/zero", &csv).unwrap();
        refused("not a regular file");
        std::fs::remove_file(&csv).unwrap();
        // Sparse: one byte over the limit takes no disk and no time to make.
        let file = std::fs::File::create(&csv).unwrap();
        file.set_len(RUN_FILE_LIMIT + 1).unwrap();
        refused("larger than 1 GiB");
        file.set_len(0).unwrap();
        std::fs::write(&csv, b"time_s\n\xff\n").unwrap();
        refused("not UTF-8");
        // A malformed row is named by its line, not a panic.
        std::fs::write(&csv, "depth_m,time_s\n0,0\n0.5\n").unwrap();
        refused(":3: the row has no `time_s` field");
        std::fs::write(&csv, "time_s,depth_m\n0,0\n1e-6,deep\n").unwrap();
        let e = history(&dir, &["depth_m"]).unwrap_err();
        assert!(
            e.ends_with("history.csv:3: depth_m = `deep` is not a number"),
            "{e}"
        );
        std::fs::write(&csv, "depth_m\n0\n").unwrap();
        refused("no column time_s");

        let vtu = dir.join("projectile_00007.vtu");
        std::os::unix::fs::symlink("/dev/zero", &vtu).unwrap();
        let e = frame::last_projectile_frame(&dir).unwrap_err();
        assert!(
            e.contains("projectile_00007.vtu: not a regular file"),
            "{e}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
