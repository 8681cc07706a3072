//! The Forrestal et al. (1994) shots: depth against the measurements and Forrestal's equation,
//! and the target-size check. Depth error against run time is in `convergence`.

use crate::output::plot::{Chart, Mark};
use crate::scene::{self, ProjectileShape, Scene};
use crate::studies::sweep::{self, RunRecord};

use super::context::{Ask, Context};
use super::data::{self, Shot};
use super::forrestal;
use super::report::{or_dash, pct, table, Check, SectionOut};
use super::{Section, ValidateError};

/// The shots of the convergence and rigid-against-elastic studies (m/s), as the issue names
/// them; the target-size check uses the first.
pub const STUDY_SHOTS: [f64; 2] = [277.0, 642.0];

/// The targets: every shot within 15 % of its measured depth; the target 1.5× larger
/// changes the depth by less than 2 % (CPU against GPU: `convergence`).
const SHOT_TOLERANCE: f64 = 0.15;
const TARGET_SIZE_TOLERANCE: f64 = 0.02;

/// How much larger (radius and thickness) the target of the size check is.
const TARGET_GROWTH: f64 = 1.5;

/// A shot of `forrestal1994.csv` and its scene, `forrestal1994-<velocity>.toml`.
pub(super) struct ShotCase {
    pub file: String,
    pub shot: Shot,
    /// The scene with the run's base overrides (the quick target, in `--quick`).
    pub scene: Scene,
}

impl ShotCase {
    /// Forrestal's equation's inputs: the measured mass and f_c, the scene's shank, nose and
    /// concrete density.
    fn equation(&self) -> Result<forrestal::Inputs, ValidateError> {
        let p = &self.scene.projectile;
        let ProjectileShape::Ogive { crh } = p.shape else {
            return Err(ValidateError::Input(format!(
                "cases/{}: Forrestal's equation needs an ogive nose",
                self.file
            )));
        };
        let density = self
            .scene
            .target
            .as_ref()
            .map_or(0.0, |t| t.concrete.density as f64);
        Ok(forrestal::Inputs {
            mass: self.shot.mass,
            shank_radius: 0.5 * p.diameter,
            crh,
            density,
            fc: self.shot.fc,
        })
    }
}

/// Every shot of the data file with its scene.
pub(super) fn shots(ctx: &Context) -> Result<Vec<ShotCase>, ValidateError> {
    data::forrestal(&ctx.opts.data)?
        .into_iter()
        .map(|shot| shot_case(ctx, shot))
        .collect()
}

/// The shot of the data file struck at `velocity`.
pub(super) fn study_shot(ctx: &Context, velocity: f64) -> Result<ShotCase, ValidateError> {
    let shot = data::forrestal(&ctx.opts.data)?
        .into_iter()
        .find(|s| s.velocity == velocity)
        .ok_or_else(|| {
            ValidateError::Input(format!(
                "{}: no shot at {velocity} m/s, which the studies use",
                ctx.opts.data.join(data::FORRESTAL_FILE).display()
            ))
        })?;
    shot_case(ctx, shot)
}

fn shot_case(ctx: &Context, shot: Shot) -> Result<ShotCase, ValidateError> {
    let file = format!("forrestal1994-{}.toml", shot.velocity);
    let scene = ctx.scene(&file, &ctx.settings.forrestal)?;
    let fc = scene.target.as_ref().map(|t| t.concrete.fc as f64);
    let agrees = fc.is_some_and(|fc| (fc - shot.fc).abs() <= 1e-6 * shot.fc)
        && scene.projectile.velocity == shot.velocity;
    if !agrees {
        return Err(ValidateError::Input(format!(
            "cases/{file} is not the {} m/s shot of {} (striking speed {} m/s and f_c {} MPa \
             there, {} m/s and {} MPa in the data)",
            shot.velocity,
            data::FORRESTAL_FILE,
            scene.projectile.velocity,
            fc.map_or(0.0, |f| f * 1e-6),
            shot.velocity,
            shot.fc * 1e-6
        )));
    }
    Ok(ShotCase { file, shot, scene })
}

/// The run of a shot at the base settings.
pub(super) fn shot_ask(ctx: &Context, c: &ShotCase, extra: &[String]) -> Ask {
    let mut overrides = ctx.settings.forrestal.clone();
    overrides.extend_from_slice(extra);
    Ask {
        label: format!("v{}", c.shot.velocity),
        case: c.file.clone(),
        overrides,
        backend: ctx.primary(),
    }
}

pub(super) fn forrestal(ctx: &mut Context) -> Result<SectionOut, ValidateError> {
    let section = Section::Forrestal;
    let cases = shots(ctx)?;
    let asks = cases.iter().map(|c| shot_ask(ctx, c, &[])).collect();
    let records = ctx.run(section, asks, false)?;
    let mut rows = Vec::new();
    let mut table_rows = Vec::new();
    let (mut measured, mut equation, mut simulated) = (Vec::new(), Vec::new(), Vec::new());
    let mut errors = Vec::new();
    let mut equation_errors = Vec::new();
    for (c, r) in cases.iter().zip(&records) {
        let v = c.shot.velocity;
        let predicted = c.equation()?.depth(v);
        let depth = r.completed().map(|s| s.depth_m);
        let error = depth.map(|d| d / c.shot.depth - 1.0);
        let vs_equation = depth.zip(predicted).map(|(d, p)| d / p - 1.0);
        errors.push(error);
        if let Some(p) = predicted {
            equation_errors.push(p / c.shot.depth - 1.0);
            equation.push((v, p));
        }
        measured.push((v, c.shot.depth));
        if let Some(d) = depth {
            simulated.push((v, d));
        }
        let s = r.summary();
        rows.push(vec![
            v.to_string(),
            c.shot.mass.to_string(),
            c.shot.fc.to_string(),
            c.shot.depth.to_string(),
            or_dash(predicted, |p| p.to_string()),
            or_dash(s, |s| s.depth_m.to_string()),
            or_dash(error, |e| e.to_string()),
            or_dash(vs_equation, |e| e.to_string()),
            r.status().to_string(),
            or_dash(s, |s| s.particles.to_string()),
            or_dash(s, |s| s.elements.to_string()),
            or_dash(s, |s| s.steps.to_string()),
            or_dash(s, |s| s.wall_s.to_string()),
            ctx.rel(&r.dir),
        ]);
        table_rows.push(vec![
            format!("{v}"),
            format!("{:.1}", c.shot.fc * 1e-6),
            format!("{:.3}", c.shot.depth),
            or_dash(predicted, |p| format!("{p:.3}")),
            or_dash(s, |s| format!("{:.3}", s.depth_m)),
            or_dash(error, pct),
            or_dash(vs_equation, pct),
            or_dash(s, |s| format!("{:.0}", s.wall_s)),
            r.status().to_string(),
        ]);
    }
    let complete: Vec<f64> = errors.iter().flatten().copied().collect();
    let mean_abs = |e: &[f64]| e.iter().map(|x| x.abs()).sum::<f64>() / e.len().max(1) as f64;
    let all_ran = complete.len() == errors.len();
    let check = Check {
        section,
        what: format!("depth of each of the {} shots", errors.len()),
        target: format!(
            "every shot within {:.0} % of measured",
            100.0 * SHOT_TOLERANCE
        ),
        result: format!(
            "{}; mean absolute error {:.1} %",
            errors
                .iter()
                .map(|e| or_dash(*e, pct))
                .collect::<Vec<_>>()
                .join(", "),
            100.0 * mean_abs(&complete)
        ),
        pass: all_ran.then(|| complete.iter().all(|e| e.abs() <= SHOT_TOLERANCE)),
    };
    let csv = ctx.csv(
        section,
        "forrestal.csv",
        &[
            "velocity_m_s",
            "mass_kg",
            "fc_pa",
            "measured_depth_m",
            "equation_depth_m",
            "depth_m",
            "error_vs_measured",
            "error_vs_equation",
            "status",
            "particles",
            "elements",
            "steps",
            "wall_s",
            "dir",
        ],
        &rows,
    )?;
    let plot = ctx.plot(
        section,
        "depth-vs-velocity.png",
        &Chart::new(
            "Forrestal et al. (1994): depth against striking speed",
            "striking speed (m/s)",
            "depth of penetration (m)",
        )
        .series("measured", measured, Mark::Points)
        .series("Forrestal's equation", equation, Mark::LinePoints)
        .series("simulated", simulated, Mark::LinePoints),
    )?;
    let resistance = resistance(ctx, &cases, &records)?;
    let scenes: Vec<&Scene> = cases.iter().map(|c| &c.scene).collect();
    let one_set = one_parameter_set(&scenes);
    let mut md =
        format!(
        "Each shot's scene (`cases/forrestal1994-<speed>.toml`) as shipped{}, on {}. Parameter \
         set: projectile material preset `{}`, λ = {}, concrete from the f_c rule, {}; {}. \
         Forrestal's equation (physics.md §8) takes the measured mass and f_c, the scene's shank \
         radius, CRH and concrete density. Target: every shot within {:.0} %. Mean absolute error of \
         the simulation {:.1} % over {} shot(s) that completed, of the equation {:.1} %. Raw data: \
         {csv}.\n\n",
        if ctx.settings.quick { " with the quick overrides" } else { "" },
        ctx.primary().name(),
        scenes.first().map_or("", |s| s.projectile.material.preset.as_str()),
        scenes.first().map_or(0.0, |s| s.contact.lambda),
        scenes
            .first()
            .and_then(|s| target_options(s))
            .map_or(String::new(), |(ratio, alpha, beta, stress, switch, filter, gradient)| format!(
                "SPH with h = {ratio} Δ, viscosity α = {alpha}, β = {beta}, switch `{switch}`, \
                 velocity filter `{filter}`, velocity gradient `{gradient}`, artificial stress {}",
                if stress { "on" } else { "off" }
            )),
        if one_set {
            "the same projectile material, contact and SPH options in every shot"
        } else {
            "**the scenes differ in projectile material, contact or SPH options: not one \
             parameter set**"
        },
        100.0 * SHOT_TOLERANCE,
        100.0 * mean_abs(&complete),
        complete.len(),
        100.0 * mean_abs(&equation_errors),
    );
    md += &table(
        &[
            "speed (m/s)",
            "f_c (MPa)",
            "measured (m)",
            "equation (m)",
            "simulated (m)",
            "vs measured",
            "vs equation",
            "wall (s)",
            "status",
        ],
        &table_rows,
    );
    md += &plot;
    md += &resistance;
    Ok(SectionOut {
        markdown: md,
        checks: vec![check],
    })
}

/// History rows either side of each point of the resistance's least-squares slope.
const RESISTANCE_HALF_WINDOW: usize = 10;

/// The speed at which the shots' resistances are compared in the report's table (m/s).
const RESISTANCE_SPEED: f64 = 200.0;

/// The forrestal section's resistance part: the axial stress on the buried projectile against
/// its speed for each completed shot ([`forrestal::tunnel_resistance`]) beside Forrestal's law
/// `S f_c + N ρ v²`, as a plot, a CSV and a table at [`RESISTANCE_SPEED`].
fn resistance(
    ctx: &Context,
    cases: &[ShotCase],
    records: &[RunRecord],
) -> Result<String, ValidateError> {
    let section = Section::Forrestal;
    let mut chart = Chart::new(
        "Resistance of the target along the tunnel",
        "projectile speed (m/s)",
        "axial stress m|dv/dt|/(πa²) (MPa)",
    );
    let mut rows = Vec::new();
    let mut table_rows = Vec::new();
    let mut notes = String::new();
    let mut laws = Vec::new();
    for (c, r) in cases.iter().zip(records) {
        let Some(summary) = r.completed() else {
            continue;
        };
        let inputs = c.equation()?;
        let a = inputs.shank_radius;
        let nose_length = scene::ogive_nose_length(2.0 * a, inputs.crh);
        let h = match crate::output::run_files::history(
            &r.dir,
            &["time_s", "depth_m", "projectile_velocity_m_s"],
        ) {
            Ok(h) => h,
            Err(e) => {
                notes += &format!("- {} m/s: no history ({e})\n", c.shot.velocity);
                continue;
            }
        };
        // `projectile_velocity_m_s` is the speed into the target.
        let points = forrestal::tunnel_resistance(
            &h[0],
            &h[1],
            &h[2],
            summary.projectile_mass_kg,
            a,
            nose_length,
            RESISTANCE_HALF_WINDOW,
        );
        for &(v, sigma) in &points {
            rows.push(vec![
                c.shot.velocity.to_string(),
                v.to_string(),
                sigma.to_string(),
            ]);
        }
        laws.push(inputs);
        let near = points.iter().min_by(|p, q| {
            (p.0 - RESISTANCE_SPEED)
                .abs()
                .total_cmp(&(q.0 - RESISTANCE_SPEED).abs())
        });
        if let Some(&(v, sigma)) = near {
            table_rows.push(vec![
                format!("{}", c.shot.velocity),
                format!("{v:.0}"),
                format!("{:.0}", sigma * 1e-6),
                format!("{:.0}", inputs.tunnel_stress(v) * 1e-6),
                pct(sigma / inputs.tunnel_stress(v) - 1.0),
            ]);
        }
        let mpa: Vec<(f64, f64)> = points.iter().map(|&(v, s)| (v, s * 1e-6)).collect();
        chart = chart.series(
            &format!("simulated, {} m/s shot", c.shot.velocity),
            mpa,
            Mark::Line,
        );
    }
    // Forrestal's law averaged over the shots drawn (their f_c differ by a few per cent).
    if !laws.is_empty() {
        let mean = |f: &dyn Fn(&forrestal::Inputs) -> f64| {
            laws.iter().map(f).sum::<f64>() / laws.len() as f64
        };
        let fc = mean(&|l| l.fc);
        let top = cases.iter().map(|c| c.shot.velocity).fold(0.0, f64::max);
        let curve = (0..=40)
            .map(|i| {
                let v = top * i as f64 / 40.0;
                (v, mean(&|l| l.tunnel_stress(v)) * 1e-6)
            })
            .collect();
        chart = chart.series(
            &format!("Forrestal: S f_c + Nρv² (f_c {:.1} MPa)", fc * 1e-6),
            curve,
            Mark::Line,
        );
    }
    let csv = ctx.csv(
        section,
        "resistance.csv",
        &["shot_velocity_m_s", "speed_m_s", "axial_stress_pa"],
        &rows,
    )?;
    let plot = ctx.plot(section, "resistance-vs-speed.png", &chart)?;
    let mut md = format!(
        "\n### Resistance along the tunnel\n\nThe axial stress resisting each projectile once \
         its nose is buried, `m|dv/dt|/(πa²)` from `history.csv` (slope over {} rows either \
         side), against its speed, beside the law Forrestal's equation integrates, \
         `S f_c + N ρ v²`, which is the same at every depth. Raw data: {csv}.\n\n",
        RESISTANCE_HALF_WINDOW
    );
    md += &notes;
    if !table_rows.is_empty() {
        md += &table(
            &[
                "shot (m/s)",
                "speed (m/s)",
                "simulated (MPa)",
                "S f_c + Nρv² (MPa)",
                "difference",
            ],
            &table_rows,
        );
    }
    md += &plot;
    Ok(md)
}

pub(super) fn target_size(ctx: &mut Context) -> Result<SectionOut, ValidateError> {
    let section = Section::TargetSize;
    let c = study_shot(ctx, STUDY_SHOTS[0])?;
    let (radius, thickness) = c
        .scene
        .target
        .as_ref()
        .map_or((0.0, 0.0), |t| (t.radius, t.thickness));
    let (big_r, big_t) = (
        sweep::tidy(TARGET_GROWTH * radius),
        sweep::tidy(TARGET_GROWTH * thickness),
    );
    let mut large = shot_ask(
        ctx,
        &c,
        &[
            format!("target.radius={big_r}"),
            format!("target.thickness={big_t}"),
        ],
    );
    large.label += "-large";
    let asks = vec![shot_ask(ctx, &c, &[]), large];
    let records = ctx.run(section, asks, false)?;
    let sizes = [(radius, thickness), (big_r, big_t)];
    let mut rows = Vec::new();
    let mut table_rows = Vec::new();
    for ((r, t), rec) in sizes.iter().zip(&records) {
        let s = rec.summary();
        rows.push(vec![
            r.to_string(),
            t.to_string(),
            or_dash(s, |s| s.particles.to_string()),
            or_dash(s, |s| s.depth_m.to_string()),
            rec.status().to_string(),
            or_dash(s, |s| s.wall_s.to_string()),
            ctx.rel(&rec.dir),
        ]);
        table_rows.push(vec![
            format!("{r}"),
            format!("{t}"),
            or_dash(s, |s| s.particles.to_string()),
            or_dash(s, |s| format!("{:.4}", s.depth_m)),
            or_dash(s, |s| format!("{:.1}", s.wall_s)),
            rec.status().to_string(),
        ]);
    }
    let depth = |k: usize| {
        records
            .get(k)
            .and_then(RunRecord::completed)
            .map(|s| s.depth_m)
    };
    let change = depth(0).zip(depth(1)).map(|(a, b)| b / a - 1.0);
    let csv = ctx.csv(
        section,
        "target-size.csv",
        &[
            "radius_m",
            "thickness_m",
            "particles",
            "depth_m",
            "status",
            "wall_s",
            "dir",
        ],
        &rows,
    )?;
    let check = Check {
        section,
        what: format!(
            "{} m/s shot, target radius and thickness ×{TARGET_GROWTH}",
            c.shot.velocity
        ),
        target: format!("depth changes < {:.0} %", 100.0 * TARGET_SIZE_TOLERANCE),
        result: or_dash(change, pct),
        pass: change.map(|x| x.abs() < TARGET_SIZE_TOLERANCE),
    };
    let mut md = format!(
        "The {} m/s shot in its target and in one {TARGET_GROWTH}× wider and thicker, on {} \
         (boundary conditions as in the scene). Depth change {} ({}). Raw data: {csv}.\n\n",
        c.shot.velocity,
        ctx.primary().name(),
        or_dash(change, pct),
        match check.pass {
            Some(true) => "pass",
            Some(false) => "fail",
            None => "not evaluated: a run did not complete",
        }
    );
    md += &table(
        &[
            "radius (m)",
            "thickness (m)",
            "particles",
            "depth (m)",
            "wall (s)",
            "status",
        ],
        &table_rows,
    );
    Ok(SectionOut {
        markdown: md,
        checks: vec![check],
    })
}

/// Whether the shots share one parameter set: the projectile's material, the contact and the
/// target's numerical options ([`target_options`]) alike in every scene.
fn one_parameter_set(scenes: &[&Scene]) -> bool {
    scenes.windows(2).all(|w| {
        w[0].projectile.material == w[1].projectile.material
            && w[0].contact == w[1].contact
            && target_options(w[0]) == target_options(w[1])
    })
}

/// The target's numerical options, which one parameter set keeps alike in every shot: h/Δ,
/// α, β, artificial stress, the viscosity switch, the velocity filter and gradient. The
/// concrete is not compared: its constants differ between shots by design, through each shot's
/// f_c and the rule (explicit `[target.concrete]` overrides are therefore not checked here
/// either).
type TargetOptions = (
    f64,
    f64,
    f64,
    bool,
    &'static str,
    &'static str,
    &'static str,
);

fn target_options(scene: &Scene) -> Option<TargetOptions> {
    scene.target.as_ref().map(|t| {
        (
            t.smoothing_ratio,
            t.viscosity_alpha,
            t.viscosity_beta,
            t.artificial_stress,
            t.viscosity_switch.name(),
            t.velocity_filter.name(),
            t.velocity_gradient.name(),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn forrestal(overrides: &[&str]) -> Scene {
        crate::scene::shipped_case("forrestal1994-277.toml", overrides)
    }

    #[test]
    fn one_parameter_set_allows_each_shot_its_own_speed_and_concrete_only() {
        let base = forrestal(&[]);
        let other_shot = forrestal(&["projectile.velocity=642", "target.fc=34.7e6"]);
        assert!(one_parameter_set(&[&base, &other_shot]));
        for change in [
            "target.velocity_gradient=\"corrected\"",
            "target.viscosity_switch=\"none\"",
            "target.viscosity_alpha=0.5",
            "target.smoothing_ratio=2.0",
            "contact.lambda=0",
            "projectile.material.jc_a=1e9",
        ] {
            let changed = forrestal(&[change]);
            assert!(
                !one_parameter_set(&[&base, &changed]),
                "{change} went unnoticed"
            );
        }
    }
}
