//! `penetrate check-stability`: the stiff and extreme scenes of the stability suite, each run on
//! the CPU and GPU paths from one base scene (`cases/stability.toml`) with `--set` overrides,
//! and the table of how each ended.

use std::path::{Path, PathBuf};

use crate::output::summary::Summary;
use crate::scene::{self, Backend, Scene};
use crate::solver::{self, RunError, RunOptions};
use crate::studies::sweep::SweepError;

/// One scene of the suite: the base scene (or `file`, beside it) with `overrides`, then its
/// elastic moduli times `moduli_factor` ([`stiffen`]).
#[derive(Clone, Debug)]
pub struct Case {
    pub name: &'static str,
    pub what: String,
    pub file: Option<&'static str>,
    pub overrides: Vec<String>,
    pub moduli_factor: Option<f64>,
}

/// The thin-walled shell's scene, beside the base scene (a cavity cannot be added by `--set`).
pub const SHELL_FILE: &str = "stability-shell.toml";

/// Energy error allowed, as a fraction of the initial kinetic energy.
pub const ENERGY_TOLERANCE: f64 = 0.01;
/// Axial momentum error allowed where no boundary acts (the base target is free).
pub const MOMENTUM_TOLERANCE: f64 = 0.001;
/// Largest speed a scene at rest may reach (m/s): round-off of the zero forces.
pub const REST_SPEED: f64 = 1.0e-6;

/// The suite's scenes. `base` is the loaded base scene (its resolved constants are scaled for
/// the stiff cases); `quick` shortens the quiescent run from 10⁵ to 10⁴ steps.
pub fn cases(base: &Scene, quick: bool) -> Vec<Case> {
    let steel = &base.projectile.material;
    let spacing = base.target.as_ref().map_or(0.0025, |t| t.spacing);
    let radius = 0.5 * base.projectile.diameter;
    let set = |pairs: &[(&str, String)]| -> Vec<String> {
        pairs.iter().map(|(k, v)| format!("{k}={v}")).collect()
    };
    let nu = 0.499;
    let quiet_steps: u64 = if quick { 10_000 } else { 100_000 };
    let v = |x: f64| vec![format!("projectile.velocity={x}")];
    vec![
        Case {
            file: None,
            name: "base",
            what: format!(
                "the base scene: {} m/s, λ = {}",
                base.projectile.velocity, base.contact.lambda
            ),
            overrides: vec![],
            moduli_factor: None,
        },
        Case {
            file: None,
            name: "v100",
            what: "100 m/s".into(),
            overrides: v(100.0),
            moduli_factor: None,
        },
        Case {
            file: None,
            name: "v800",
            what: "800 m/s".into(),
            overrides: v(800.0),
            moduli_factor: None,
        },
        Case {
            file: None,
            name: "v1500",
            what: "1500 m/s, the paper's upper bound".into(),
            overrides: v(1500.0),
            moduli_factor: None,
        },
        Case {
            file: None,
            name: "v2500",
            what: "2500 m/s".into(),
            overrides: v(2500.0),
            moduli_factor: None,
        },
        Case {
            file: None,
            name: "lambda0",
            what: "λ = 0: rigid projectile".into(),
            overrides: vec!["contact.lambda=0".into()],
            moduli_factor: None,
        },
        Case {
            file: None,
            name: "lambda1",
            what: "λ = 1: all of each slave's momentum change onto its two nodes".into(),
            overrides: vec!["contact.lambda=1".into()],
            moduli_factor: None,
        },
        Case {
            file: None,
            name: "stiff10",
            what: "elastic moduli ×10 (steel E, K₁–K₃; concrete G, K₁–K₃, K_el)".into(),
            overrides: vec![],
            moduli_factor: Some(10.0),
        },
        Case {
            file: None,
            name: "stiff100",
            what: "elastic moduli ×100".into(),
            overrides: vec![],
            moduli_factor: Some(100.0),
        },
        Case {
            file: None,
            name: "nu0499",
            what: "nearly incompressible steel: ν = 0.499, K₁ = E/(3(1 − 2ν))".into(),
            overrides: set(&[
                ("projectile.material.poisson_ratio", nu.to_string()),
                (
                    "projectile.material.eos_k1",
                    (steel.youngs_modulus / (3.0 * (1.0 - 2.0 * nu))).to_string(),
                ),
            ]),
            moduli_factor: None,
        },
        Case {
            file: None,
            name: "elements-fine",
            what: "elements 4× finer than the particle spacing".into(),
            overrides: vec![format!("projectile.element_size={}", spacing / 4.0)],
            moduli_factor: None,
        },
        Case {
            file: None,
            name: "elements-coarse",
            what: "elements 4× coarser than the particle spacing (the spacing halved: the \
                   elements are as coarse as the mesher allows)"
                .into(),
            overrides: vec![
                format!("projectile.element_size={}", 2.0 * spacing),
                format!("target.spacing={}", spacing / 2.0),
            ],
            moduli_factor: None,
        },
        Case {
            file: Some(SHELL_FILE),
            name: "thin-shell",
            what: format!(
                "{SHELL_FILE}: the projectile hollowed to a 2 mm wall, 1000 m/s: it fails"
            ),
            overrides: vec![],
            moduli_factor: None,
        },
        Case {
            file: None,
            name: "quiescent",
            what: format!("at rest, 1 cm above the target, for {quiet_steps} steps"),
            overrides: set(&[
                ("projectile.velocity", "0".into()),
                ("projectile.nose_z", "0.01".into()),
                ("run.end_time", "1".into()),
                ("run.stop_at_rest", "false".into()),
                ("run.max_steps", quiet_steps.to_string()),
                ("run.history_interval", "1e-4".into()),
            ]),
            moduli_factor: None,
        },
        Case {
            file: None,
            name: "grazing",
            what: format!(
                "target radius {:.0} mm, the shank's (spacing halved): the nose meets the target's \
                 edge (an axisymmetric projectile cannot be offset from the axis)",
                1e3 * radius
            ),
            overrides: vec![
                format!("target.radius={radius}"),
                format!("target.spacing={}", spacing / 2.0),
            ],
            moduli_factor: None,
        },
    ]
}

/// How one scene ended on one backend.
#[derive(Clone, Debug)]
pub struct Row {
    pub case: String,
    pub what: String,
    pub backend: &'static str,
    /// The run's summary, or why there is none (the scene was refused).
    pub outcome: Result<Summary, String>,
}

impl Row {
    /// "pass", or what failed.
    pub fn verdict(&self) -> String {
        let quiescent = self.case == "quiescent";
        let s = match &self.outcome {
            Ok(s) => s,
            Err(e) => return format!("refused: {e}"),
        };
        let mut why = Vec::new();
        let completed =
            s.status == "completed" || (quiescent && s.status.starts_with("stopped: max_steps"));
        if !completed {
            why.push(s.status.clone());
        }
        if s.energy_error.abs() >= ENERGY_TOLERANCE && s.energy.initial_kinetic > 0.0 {
            why.push(format!("energy error {:.2} %", 100.0 * s.energy_error));
        }
        if s.momentum_error >= MOMENTUM_TOLERANCE && s.energy.initial_kinetic > 0.0 {
            why.push(format!("momentum error {:.2} %", 100.0 * s.momentum_error));
        }
        if s.slaves_inside > 0 {
            why.push(format!("{} slaves inside", s.slaves_inside));
        }
        if s.nonfinite_values > 0 {
            why.push(format!("{} non-finite values", s.nonfinite_values));
        }
        if quiescent && s.max_speed_m_s > REST_SPEED {
            why.push(format!("moved: max speed {:.1e} m/s", s.max_speed_m_s));
        }
        if why.is_empty() {
            "pass".into()
        } else {
            why.join("; ")
        }
    }
}

/// Run every case (those named in `only`, when it is not empty) on every backend; `progress`
/// hears of each run as it ends.
pub fn run(
    base_path: &Path,
    backends: &[Backend],
    quick: bool,
    only: &[String],
    out: &Path,
    adapter: Option<&str>,
    mut progress: impl FnMut(&Row),
) -> Result<Vec<Row>, SweepError> {
    let base = scene::load(base_path, &[]).map_err(SweepError::Scene)?;
    let mut rows = Vec::new();
    let all = cases(&base, quick);
    if let Some(unknown) = only
        .iter()
        .find(|n| !all.iter().any(|c| c.name == n.as_str()))
    {
        let names: Vec<&str> = all.iter().map(|c| c.name).collect();
        return Err(SweepError::Spec(format!(
            "no scene `{unknown}` in the suite; it has {}",
            names.join(", ")
        )));
    }
    for case in all {
        if !only.is_empty() && !only.iter().any(|n| n == case.name) {
            continue;
        }
        for &backend in backends {
            let name = if backend == Backend::Gpu {
                "gpu"
            } else {
                "cpu"
            };
            let outcome = match scene_of(base_path, &case) {
                Err(e) => Err(e.to_string()),
                Ok(scene) => {
                    let opts = RunOptions {
                        out: run_dir(out, case.name, name),
                        quiet: true,
                        vtk: false,
                        backend: Some(backend),
                        adapter: adapter.map(str::to_string),
                        checkpoint_every: None,
                        restart: None,
                        share: None,
                    };
                    match solver::run(&scene, &opts) {
                        Ok(o) => Ok(o.summary),
                        Err(RunError::Output(e)) => return Err(SweepError::Io(e.to_string())),
                        Err(e) => Err(e.to_string()),
                    }
                }
            };
            let row = Row {
                case: case.name.to_string(),
                what: case.what.clone(),
                backend: name,
                outcome,
            };
            progress(&row);
            rows.push(row);
            if crate::interrupt::requested() {
                return Ok(rows);
            }
        }
    }
    Ok(rows)
}

/// The scene of `case` on the base scene at `base_path`.
pub fn scene_of(base_path: &Path, case: &Case) -> Result<Scene, scene::SceneError> {
    let path = case
        .file
        .map_or_else(|| base_path.to_path_buf(), |f| base_path.with_file_name(f));
    let mut scene = scene::load(&path, &case.overrides)?;
    if let Some(f) = case.moduli_factor {
        stiffen(&mut scene, f);
    }
    Ok(scene)
}

/// Every elastic modulus of `scene` times `f`: the steel's E and K₁–K₃, the concrete's G,
/// K₁–K₃ and K_el (μ_crush / f at the same P_crush). Done to the loaded scene, not by `--set`:
/// a steel 10 or 100 times stiffer is no material a scene file accepts
/// (`projectile.material.youngs_modulus` ≤ 1.2e12 Pa), but a test of the step.
fn stiffen(scene: &mut Scene, f: f64) {
    let steel = &mut scene.projectile.material;
    steel.youngs_modulus *= f;
    let g = f as f32;
    steel.eos.k1 *= g;
    steel.eos.k2 *= g;
    steel.eos.k3 *= g;
    if let Some(t) = scene.target.as_mut() {
        let c = &mut t.concrete;
        c.shear_modulus *= g;
        c.k1 *= g;
        c.k2 *= g;
        c.k3 *= g;
        c.mu_crush /= g;
    }
}

fn run_dir(out: &Path, case: &str, backend: &str) -> PathBuf {
    out.join(format!("{case}-{backend}"))
}

/// The suite's table in Markdown.
pub fn table(rows: &[Row]) -> String {
    let mut t = String::from(
        "| scene | backend | steps | Δt min–max (s) | energy error | momentum error | \
         penetration corrected (m) | slaves inside | non-finite | max damage | depth (m) | \
         wall (s) | verdict |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let verdict = r.verdict();
        match &r.outcome {
            Ok(s) => t += &format!(
                "| {} | {} | {} | {:.2e}–{:.2e} | {:.2e} | {:.2e} | {:.1e} | {} | {} | {:.2} | {:.4} | {:.1} | {} |\n",
                r.case,
                r.backend,
                s.steps,
                s.min_dt_s,
                s.max_dt_s,
                s.energy_error,
                s.momentum_error,
                s.max_slave_penetration_m,
                s.slaves_inside,
                s.nonfinite_values,
                s.max_damage,
                s.depth_m,
                s.wall_s,
                verdict
            ),
            Err(_) => {
                t += &format!(
                    "| {} | {} | – | – | – | – | – | – | – | – | – | – | {} |\n",
                    r.case, r.backend, verdict
                )
            }
        }
    }
    t += "\nScenes:\n";
    let mut seen = Vec::new();
    for r in rows {
        if !seen.contains(&r.case) {
            t += &format!("- `{}`: {}\n", r.case, r.what);
            seen.push(r.case.clone());
        }
    }
    t
}
