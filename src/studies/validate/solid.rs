//! The paper's studies of the solid Forrestal penetrator: rigid (λ = 0) against elastic-plastic
//! (λ = 0.2) penetration histories (Fig. 2-3), and its final plastic deformation against
//! striking speed (Fig. 4). Both are qualitative: no accuracy target, the numbers are reported.

use crate::output::plot::{Chart, Mark};

use super::context::{Ask, Context};
use super::penetration::{study_shot, STUDY_SHOTS};
use super::report::{or_dash, pct, table, SectionOut};
use super::{Section, ValidateError};
use crate::output::run_files::history;

/// λ of the rigid limit and the paper's elastic-plastic projectile (physics.md §4).
const LAMBDAS: [f64; 2] = [0.0, 0.2];

pub(super) fn rigid_vs_elastic(ctx: &mut Context) -> Result<SectionOut, ValidateError> {
    let section = Section::RigidVsElastic;
    let mut depth_series = Vec::new();
    let mut speed_series = Vec::new();
    let mut rows = Vec::new();
    let mut table_rows = Vec::new();
    let mut notes = String::new();
    for v in STUDY_SHOTS {
        let c = study_shot(ctx, v)?;
        let asks = LAMBDAS
            .iter()
            .map(|l| {
                let mut overrides = ctx.settings.forrestal.clone();
                overrides.push(format!("contact.lambda={l}"));
                Ask {
                    label: format!("v{v}-lambda{l}"),
                    case: c.file.clone(),
                    overrides,
                    backend: ctx.primary(),
                }
            })
            .collect();
        let records = ctx.run(section, asks, false)?;
        for (&lambda, r) in LAMBDAS.iter().zip(&records) {
            let label = format!("{v} m/s, λ = {lambda}");
            match history(&r.dir, &["time_s", "depth_m", "projectile_velocity_m_s"]) {
                Ok(h) => {
                    let ms: Vec<f64> = h[0].iter().map(|t| t * 1e3).collect();
                    depth_series.push((
                        label.clone(),
                        ms.iter().copied().zip(h[1].clone()).collect(),
                    ));
                    speed_series.push((label, ms.into_iter().zip(h[2].clone()).collect()));
                }
                Err(e) => notes += &format!("- {label}: no history ({e})\n"),
            }
            let s = r.summary();
            rows.push(vec![
                v.to_string(),
                lambda.to_string(),
                r.status().to_string(),
                or_dash(s, |s| s.stop_reason.clone()),
                or_dash(s, |s| s.time_s.to_string()),
                or_dash(s, |s| s.depth_m.to_string()),
                or_dash(s, |s| s.projectile_velocity_m_s.to_string()),
                or_dash(s, |s| s.max_plastic_strain.to_string()),
                or_dash(s, |s| s.max_damage.to_string()),
                or_dash(s, |s| s.steps.to_string()),
                or_dash(s, |s| s.wall_s.to_string()),
                ctx.rel(&r.dir),
            ]);
        }
        let depth = |k: usize| {
            records
                .get(k)
                .and_then(|r| r.completed())
                .map(|s| s.depth_m)
        };
        let difference = depth(0)
            .zip(depth(1))
            .map(|(rigid, elastic)| elastic / rigid - 1.0);
        for (&lambda, r) in LAMBDAS.iter().zip(&records) {
            let s = r.summary();
            table_rows.push(vec![
                format!("{v}"),
                format!("{lambda}"),
                or_dash(s, |s| format!("{:.4}", s.depth_m)),
                or_dash(s, |s| format!("{:.3}", s.time_s * 1e3)),
                or_dash(s, |s| format!("{:.1}", s.projectile_velocity_m_s)),
                or_dash(s, |s| format!("{:.3}", s.max_plastic_strain)),
                if lambda == LAMBDAS[1] {
                    or_dash(difference, pct)
                } else {
                    String::new()
                },
                r.status().to_string(),
            ]);
        }
    }
    let csv = ctx.csv(
        section,
        "rigid-vs-elastic.csv",
        &[
            "velocity_m_s",
            "lambda",
            "status",
            "stop_reason",
            "time_s",
            "depth_m",
            "projectile_velocity_m_s",
            "max_plastic_strain",
            "max_damage",
            "steps",
            "wall_s",
            "dir",
        ],
        &rows,
    )?;
    let chart = |title: &str, y: &str, series: Vec<(String, Vec<(f64, f64)>)>| {
        series
            .into_iter()
            .fold(Chart::new(title, "time (ms)", y), |c, (label, points)| {
                c.series(&label, points, Mark::Line)
            })
    };
    let depth_plot = ctx.plot(
        section,
        "depth-history.png",
        &chart(
            "Penetration history: rigid (λ = 0) and elastic-plastic (λ = 0.2)",
            "depth (m)",
            depth_series,
        ),
    )?;
    let speed_plot = ctx.plot(
        section,
        "velocity-history.png",
        &chart(
            "Projectile velocity: rigid (λ = 0) and elastic-plastic (λ = 0.2)",
            "projectile velocity (m/s)",
            speed_series,
        ),
    )?;
    let mut md = format!(
        "The Forrestal penetrator at {} m/s with λ = 0 (the rigid limit: no stress pass) and \
         λ = 0.2 (the paper's), on {}; histories from each run's `history.csv`. The paper finds \
         nearly the same final depth, the rigid one slightly deeper, with different histories. \
         No accuracy target. Raw data: {csv}.\n\n",
        STUDY_SHOTS.map(|v| v.to_string()).join(" and "),
        ctx.primary().name(),
    );
    md += &table(
        &[
            "speed (m/s)",
            "λ",
            "depth (m)",
            "end (ms)",
            "final velocity (m/s)",
            "max plastic strain",
            "depth vs λ = 0",
            "status",
        ],
        &table_rows,
    );
    md += &notes;
    md += &depth_plot;
    md += "\n";
    md += &speed_plot;
    Ok(SectionOut {
        markdown: md,
        checks: vec![],
    })
}

pub(super) fn deformation(ctx: &mut Context) -> Result<SectionOut, ValidateError> {
    let section = Section::Deformation;
    let c = study_shot(ctx, STUDY_SHOTS[1])?;
    let speeds = ctx.settings.deformation.clone();
    let asks = speeds
        .values
        .iter()
        .map(|&v| {
            let mut overrides = ctx.settings.forrestal.clone();
            overrides.push(speeds.set(v));
            Ask {
                label: speeds.label(v),
                case: c.file.clone(),
                overrides,
                backend: ctx.primary(),
            }
        })
        .collect();
    let records = ctx.run(section, asks, false)?;
    let length0 = c.scene.projectile.length;
    let mut rows = Vec::new();
    let mut table_rows = Vec::new();
    let (mut strain, mut strain_shank, mut work, mut shortening) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for (&v, r) in speeds.values.iter().zip(&records) {
        let s = r.summary();
        let change = s.map(|s| 1.0 - s.final_length_m / length0);
        if let (Some(s), Some(x)) = (r.completed(), change) {
            strain.push((v, s.max_plastic_strain));
            strain_shank.push((v, s.max_plastic_strain_shank));
            work.push((v, s.energy.plastic_work_projectile));
            shortening.push((v, 100.0 * x));
        }
        rows.push(vec![
            v.to_string(),
            r.status().to_string(),
            or_dash(s, |s| s.depth_m.to_string()),
            or_dash(s, |s| s.max_plastic_strain.to_string()),
            or_dash(s, |s| s.max_plastic_strain_shank.to_string()),
            or_dash(s, |s| s.energy.plastic_work_projectile.to_string()),
            or_dash(s, |s| s.max_damage.to_string()),
            length0.to_string(),
            or_dash(s, |s| s.final_length_m.to_string()),
            or_dash(change, |x| x.to_string()),
            or_dash(s, |s| s.wall_s.to_string()),
            ctx.rel(&r.dir),
        ]);
        table_rows.push(vec![
            format!("{v}"),
            or_dash(s, |s| format!("{:.4}", s.depth_m)),
            or_dash(s, |s| format!("{:.3}", s.max_plastic_strain)),
            or_dash(s, |s| format!("{:.4}", s.max_plastic_strain_shank)),
            or_dash(s, |s| format!("{:.1}", s.energy.plastic_work_projectile)),
            or_dash(s, |s| format!("{:.2}", s.max_damage)),
            or_dash(s, |s| format!("{:.2}", s.final_length_m * 1e3)),
            or_dash(change, |x| format!("{:.2} %", 100.0 * x)),
            r.status().to_string(),
        ]);
    }
    let csv = ctx.csv(
        section,
        "deformation.csv",
        &[
            "velocity_m_s",
            "status",
            "depth_m",
            "max_plastic_strain",
            "max_plastic_strain_shank",
            "plastic_work_j",
            "max_damage",
            "initial_length_m",
            "final_length_m",
            "shortening",
            "wall_s",
            "dir",
        ],
        &rows,
    )?;
    let strain_plot = ctx.plot(
        section,
        "plastic-strain.png",
        &Chart::new(
            "Largest plastic strain of the projectile against striking speed",
            "striking speed (m/s)",
            "max plastic strain",
        )
        .series("whole projectile", strain, Mark::LinePoints)
        .series("behind the nose", strain_shank, Mark::LinePoints),
    )?;
    let work_plot = ctx.plot(
        section,
        "plastic-work.png",
        &Chart::new(
            "Plastic work in the projectile against striking speed",
            "striking speed (m/s)",
            "plastic work (J)",
        )
        .series("whole projectile", work, Mark::LinePoints),
    )?;
    let length_plot = ctx.plot(
        section,
        "shortening.png",
        &Chart::new(
            "Projectile shortening against striking speed",
            "striking speed (m/s)",
            "shortening (% of the initial length)",
        )
        .series("1 − final/initial length", shortening, Mark::LinePoints),
    )?;
    let mut md = format!(
        "The Forrestal penetrator into the {} m/s shot's target (`cases/{}`, the thicker one) at \
         {} m/s, on {}: its final plastic deformation, as the largest element plastic strain \
         (over the whole projectile, and behind the nose: the elements whose centroid started \
         in the shank, which leaves out the nose, where the contact's load is highest), \
         the plastic work done in it (the whole projectile's, a measure that does not hang \
         on one element) and the shortening of its axial extent (initial {:.1} mm). The \
         paper finds the deformation growing with speed. No accuracy target. Raw data: \
         {csv}.\n\n",
        c.shot.velocity,
        c.file,
        speeds
            .values
            .iter()
            .map(|v| v.to_string())
            .collect::<Vec<_>>()
            .join(", "),
        ctx.primary().name(),
        length0 * 1e3,
    );
    md += &table(
        &[
            "speed (m/s)",
            "depth (m)",
            "max plastic strain",
            "behind the nose",
            "plastic work (J)",
            "max damage",
            "final length (mm)",
            "shortening",
            "status",
        ],
        &table_rows,
    );
    md += &strain_plot;
    md += "\n";
    md += &work_plot;
    md += "\n";
    md += &length_plot;
    Ok(SectionOut {
        markdown: md,
        checks: vec![],
    })
}
