//! `penetrate validate`: the shipped validation cases and the paper's studies, run in process
//! through [`super::sweep`], written up in `DIR/report.md` with PNG plots
//! ([`crate::output::plot`]) and each section's raw data as CSV, and summed up in
//! `DIR/summary.md`, one table of the checks. Each section's part is also kept in its folder
//! ([`report::Part`]), so that sections made a few at a time into one folder end as one report.
//!
//! Sections ([`Section`]): Taylor bars at three element sizes; the Forrestal et al. (1994) shots
//! and the CRH 3 rods against the measurements and Forrestal's equation, with the accuracy rule
//! over every shot of both; the target-size check; depth error
//! against run time at five resolutions on each backend; and the paper's studies — rigid
//! (λ = 0) against elastic-plastic (λ = 0.2) histories, the projectile's plastic deformation
//! against striking speed, and the shell projectile's critical velocity and damage; a reading of
//! the concrete lining a CRH 2 and a CRH 6 nose (kernel completeness, volumetric rate,
//! pressure); the depth ratios of CRH 3 and CRH 6 noses to CRH 2 against Forrestal's equation;
//! and concrete in tension.
//!
//! Nothing here knows an expected result: measured values come from the data files, accuracy
//! targets are the and stated beside each check. A run that does not complete is
//! reported in its row; [`Outcome::failed`] lists them for the exit code.

pub mod bisect;
mod context;
mod convergence;
pub mod data;
mod end_state;
pub mod forrestal;
mod frame;
mod lining;
mod nose_shape;
mod penetration;
mod report;
mod shell;
mod solid;
mod taylor;
mod tension;

use std::fmt;
use std::path::PathBuf;
use std::time::Instant;

use crate::output::summary::fingerprint;
use crate::scene::Backend;
use crate::studies::sweep::{self, SweepError, Vary};

use context::Context;
use report::{render, render_summary, Part};

/// A part of the report, runnable alone with `--only`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Section {
    Taylor,
    Forrestal,
    Crh3Rods,
    TargetSize,
    Convergence,
    RigidVsElastic,
    Deformation,
    Shell,
    Lining,
    NoseShape,
    Tension,
}

impl Section {
    pub const ALL: [Section; 11] = [
        Section::Taylor,
        Section::Forrestal,
        Section::Crh3Rods,
        Section::TargetSize,
        Section::Convergence,
        Section::RigidVsElastic,
        Section::Deformation,
        Section::Shell,
        Section::Lining,
        Section::NoseShape,
        Section::Tension,
    ];

    /// The name `--only` takes, also the section's folder under the output directory.
    pub fn name(self) -> &'static str {
        match self {
            Section::Taylor => "taylor",
            Section::Forrestal => "forrestal",
            Section::Crh3Rods => "crh3-rods",
            Section::TargetSize => "target-size",
            Section::Convergence => "convergence",
            Section::RigidVsElastic => "rigid-vs-elastic",
            Section::Deformation => "deformation",
            Section::Shell => "shell",
            Section::Lining => "nose-lining",
            Section::NoseShape => "nose-shape",
            Section::Tension => "tension",
        }
    }

    /// The section's heading in the report.
    pub fn title(self) -> &'static str {
        match self {
            Section::Taylor => "Taylor bars",
            Section::Forrestal => "Forrestal et al. (1994) shots",
            Section::Crh3Rods => "CRH 3 rods into concrete and grout",
            Section::TargetSize => "Target size",
            Section::Convergence => "Error against run time",
            Section::RigidVsElastic => "Rigid against elastic-plastic projectile (paper Fig. 2-3)",
            Section::Deformation => "Plastic deformation against striking speed (paper Fig. 4)",
            Section::Shell => "Shell projectile: critical velocity and damage (paper Fig. 6, 7, 9)",
            Section::Lining => {
                "Concrete lining the nose: CRH 2 against CRH 6, cut and with wall images"
            }
            Section::NoseShape => "Nose shape: CRH 3 and CRH 6 against CRH 2",
            Section::Tension => "Concrete in tension: the crack band and a free-backed slab",
        }
    }

    /// Where the section's reference values come from: a measurement file of `--data` with its
    /// source, or the paper's findings where there is nothing measured.
    pub fn source(self) -> &'static str {
        match self {
            Section::Taylor => {
                "`taylor.csv`: Taylor impacts of 4340 steel and OFHC copper bars, Johnson & Cook \
                 (1983), digitised (±0.1–0.2 mm)"
            }
            Section::Forrestal | Section::TargetSize | Section::Convergence => {
                "`forrestal1994.csv`: Forrestal, Altman, Cargile & Hanchak (1994), Int. J. \
                 Impact Engng 15(4):395–405, CRH 2.0 ogive 4340 projectiles into plain concrete"
            }
            Section::Crh3Rods => {
                "`crh3-rods.csv`: CRH 3.0 ogive 4340 rods, 30.5 mm into 58.4 MPa concrete (Frew, \
                 Hanchak, Green & Forrestal 1998) and 12.9 mm into 13.5 MPa grout (Forrestal, \
                 Frew, Hanchak & Brar 1996), attributions inferred by the compiled source"
            }
            Section::RigidVsElastic | Section::Deformation | Section::Shell => {
                "none measured: the paper's findings (Song, Cai & Wang 2006), compared in kind"
            }
            Section::Lining => {
                "none measured: a reading of the solver's own fields (the kernel cut at the \
                 projectile, and completed by wall images), for the nose-shape question"
            }
            Section::NoseShape => {
                "none measured for these noses: Forrestal's equation (`forrestal1994.csv`'s \
                 shots, each run's own mass) with two entry-crater rules"
            }
            Section::Tension => {
                "none measured: the fracture energy G_f (fib Model Code 2010) the crack band must \
                 spend, and a perforation of the geometry of Hanchak et al. (1992) without its \
                 measured residual velocity"
            }
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
    /// Folder of the measurements (`taylor.csv`, `forrestal1994.csv`, `crh3-rods.csv`).
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
    /// Runs made this many at a time (`sweep --batch`).
    pub batch: usize,
    /// Scene values (`KEY=VALUE`, as `run --set`) set in every run whose scene has the key's
    /// table (`target.` and `contact.` keys: the runs with a target): a changed parameter set
    /// validated whole.
    pub set: Vec<String>,
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
    /// Lattice spacing and element size together, as multiples of the Forrestal runs'; 1 and
    /// 0.5 among them (the refinement check, `convergence::REFINEMENT`).
    convergence_factors: [f64; 5],
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
    /// Overrides of every run of a CRH 3 rod `diameter` across: none in full; in quick, the
    /// quick target with its lattice at most half the diameter (the coarsest the scene takes),
    /// and elements of a fifth of the diameter (at most the Forrestal runs'), which the 64 g
    /// rod's cavity wall still takes.
    fn rod_overrides(&self, diameter: f64) -> Vec<String> {
        if !self.quick {
            return vec![];
        }
        let size = sweep::tidy((0.2 * diameter).min(0.0065));
        let spacing = sweep::tidy((0.5 * diameter).min(0.012));
        QUICK_TARGET
            .iter()
            .map(|s| s.to_string())
            .chain([
                format!("target.spacing={spacing}"),
                format!("projectile.element_size={size}"),
            ])
            .collect()
    }

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
                convergence_factors: [1.0, 0.85, 0.7, 0.6, 0.5],
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
                convergence_factors: [2.0, 1.5, 1.0, 0.75, 0.5],
                deformation: speeds("200:800:150")?,
                // From 50 m/s: on a lattice as fine as the shipped one the wall first takes damage
                // between 200 and 250 m/s, on a 4 mm one near 150 m/s (docs/limitations.md).
                shell_speeds: speeds("50:450:50")?,
                shell_tolerance: 10.0,
            }
        })
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
    let rods = match data::crh3_rods(&opts.data) {
        Ok(s) => s.len(),
        Err(_) if !sections(opts).contains(&Section::Crh3Rods) => 0,
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
            Section::Crh3Rods => rods,
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
            // Stepped in process to read the model, not through the run folders.
            Section::Lining => 0,
            // Each study shot with the shipped nose (the forrestal section's runs) and two more.
            Section::NoseShape => penetration::STUDY_SHOTS.len() * (1 + nose_shape::NOSES.len()),
            // Two tension models at two resolutions.
            Section::Tension => 4,
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
    if !opts.set.is_empty() {
        // Every value must suit a penetration scene (which has every table) before any run.
        let probe = opts.cases.join("forrestal1994-277.toml");
        crate::scene::load(&probe, &opts.set)
            .map_err(|e| ValidateError::Input(format!("--set: {e}")))?;
    }
    let mut gpu_adapter = None;
    for &b in &opts.backends {
        gpu_adapter = gpu_adapter.or(sweep::check_backend(b, opts.adapter.as_deref())?);
    }
    let chosen = sections(opts);
    for s in &chosen {
        let dir = opts.out.join(s.name());
        crate::output::create_folder(&dir).map_err(|e| ValidateError::Io(e.to_string()))?;
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
        builds: Vec::new(),
        resumed: 0,
        gpu_adapter,
        estimate,
        progress,
    };
    let mut parts = Vec::new();
    // Every penetration shot's errors, for the accuracy rule over all sets.
    let mut shot_errors = Vec::new();
    for &s in &chosen {
        let out = match s {
            Section::Taylor => taylor::run(&mut ctx)?,
            Section::Forrestal => {
                let (out, errors) = penetration::forrestal(&mut ctx)?;
                shot_errors.extend(errors);
                out
            }
            Section::Crh3Rods => {
                let (mut out, errors) = penetration::crh3_rods(&mut ctx)?;
                shot_errors.extend(errors);
                // Over every set only when the Forrestal shots ran too: one set alone is
                // already its own check.
                if chosen.contains(&Section::Forrestal) {
                    out.checks.push(penetration::all_shots_check(&shot_errors));
                }
                out
            }
            Section::TargetSize => penetration::target_size(&mut ctx)?,
            Section::Convergence => convergence::convergence(&mut ctx)?,
            Section::RigidVsElastic => solid::rigid_vs_elastic(&mut ctx)?,
            Section::Deformation => solid::deformation(&mut ctx)?,
            Section::Shell => shell::run(&mut ctx)?,
            Section::Lining => lining::run(&mut ctx)?,
            Section::NoseShape => nose_shape::run(&mut ctx)?,
            Section::Tension => tension::run(&mut ctx)?,
        };
        let part = Part::new(&ctx, s, &out);
        part.write(&ctx.dir(s)).map_err(ValidateError::Io)?;
        parts.push((s, part));
    }
    // The sections not made now that an earlier run left in this folder with the same
    // settings: a validation made a few sections at a time keeps one whole report.
    let made_with = report::MadeWith::of(opts);
    let mut kept = Vec::new();
    for s in Section::ALL.into_iter().filter(|s| !chosen.contains(s)) {
        if let Some(part) = Part::kept(&ctx.dir(s), s, &made_with) {
            kept.push(s);
            parts.push((s, part));
        }
    }
    parts.sort_by_key(|(s, _)| Section::ALL.iter().position(|t| t == s));
    let wall_s = started.elapsed().as_secs_f64();
    let report = opts.out.join("report.md");
    std::fs::write(&report, render(&ctx, &chosen, &kept, &parts, wall_s))
        .map_err(|e| ValidateError::Io(format!("{}: {e}", report.display())))?;
    let summary = opts.out.join("summary.md");
    std::fs::write(&summary, render_summary(&ctx, &kept, &parts))
        .map_err(|e| ValidateError::Io(format!("{}: {e}", summary.display())))?;
    Ok(Outcome {
        report,
        runs: ctx.done.len(),
        failed: ctx.failed,
        wall_s,
    })
}
