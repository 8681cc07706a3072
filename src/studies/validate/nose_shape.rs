//! Nose shape: the 277 and 642 m/s Forrestal et al. (1994) shots with the CRH 2 nose replaced
//! by a CRH 3 and a CRH 6 one (the same outline length and cavity, so a lighter body), each
//! depth over the CRH 2 shot's against the ratio Forrestal's equation gives at each run's own
//! mass. Nothing is measured for these noses; the equation's band is the check: its two
//! entry-crater rules (4a, Forrestal et al. 1994; Li & Chen 2003, `(0.707 + H/d) d`, H the
//! nose's length) bound the ratio, and the simulated one must lie within 3 % of that band.

use crate::output::plot::{Chart, Mark};
use crate::scene::ProjectileShape;

use super::context::{Ask, Context};
use super::forrestal::{self, Crater};
use super::penetration::{study_shot, STUDY_SHOTS};
use super::report::{or_dash, table, Check, SectionOut};
use super::{Section, ValidateError};

/// The noses set against the shipped CRH 2 (calibre-radius-head).
pub const NOSES: [f64; 2] = [3.0, 6.0];
/// How far outside the equation's band (relative) a simulated ratio may lie.
const BAND_TOLERANCE: f64 = 0.03;

/// One nose at one speed: the run's depth and mass, and the equation's depths at that mass.
struct Nose {
    crh: f64,
    mass: Option<f64>,
    depth: Option<f64>,
    /// The equation's depth at the run's mass with the 4a and the Li–Chen crater.
    equation: [Option<f64>; 2],
}

pub(super) fn run(ctx: &mut Context) -> Result<SectionOut, ValidateError> {
    let section = Section::NoseShape;
    let mut rows = Vec::new();
    let mut table_rows = Vec::new();
    let mut checks = Vec::new();
    let mut chart = Chart::new(
        "Nose shape: depth over the CRH 2 shot's against CRH",
        "calibre-radius-head of the nose",
        "depth over the CRH 2 shot's",
    );
    for &v in &STUDY_SHOTS {
        let shot = study_shot(ctx, v)?;
        let ProjectileShape::Ogive { crh: base } = shot.scene.projectile.shape else {
            return Err(ValidateError::Input(format!(
                "{}: cases/{} has no ogive nose",
                section.name(),
                shot.file
            )));
        };
        let crhs: Vec<f64> = std::iter::once(base).chain(NOSES).collect();
        let asks = crhs
            .iter()
            .map(|&crh| {
                let mut overrides = shot.overrides.clone();
                let mut label = format!("v{v}");
                if crh != base {
                    overrides.push(format!("projectile.crh={crh}"));
                    label += &format!("-crh{crh}");
                }
                Ask {
                    label,
                    case: shot.file.clone(),
                    overrides,
                    backend: ctx.primary(),
                }
            })
            .collect();
        let records = ctx.run(section, asks, false)?;
        let a = 0.5 * shot.scene.projectile.diameter;
        let density = shot
            .scene
            .target
            .as_ref()
            .map_or(0.0, |t| t.concrete.density as f64);
        let noses: Vec<Nose> = crhs
            .iter()
            .zip(&records)
            .map(|(&crh, r)| {
                let s = r.completed();
                let mass = s.map(|s| s.projectile_mass_kg);
                let depth = s
                    .filter(|s| s.unfinished_penetration(v).is_none() && !ctx.settings.quick)
                    .map(|s| s.depth_m);
                let inputs = mass.map(|mass| forrestal::Inputs {
                    mass,
                    shank_radius: a,
                    crh,
                    density,
                    fc: shot.shot.fc,
                });
                let equation = [Crater::FourRadii, Crater::LiChen]
                    .map(|c| inputs.and_then(|i| i.depth_with_crater(v, c)));
                Nose {
                    crh,
                    mass,
                    depth,
                    equation,
                }
            })
            .collect();
        let (blunt, sharper) = noses.split_first().expect("the shipped nose and two more");
        let mut simulated_points = vec![(blunt.crh, 1.0)];
        let mut band_points = [vec![(blunt.crh, 1.0)], vec![(blunt.crh, 1.0)]];
        for n in sharper {
            let ratio = n.depth.zip(blunt.depth).map(|(d, d2)| d / d2);
            let eq: [Option<f64>; 2] =
                [0, 1].map(|k| n.equation[k].zip(blunt.equation[k]).map(|(d, d2)| d / d2));
            let band = eq[0].zip(eq[1]).map(|(x, y)| widened(x, y));
            if let Some(r) = ratio {
                simulated_points.push((n.crh, r));
            }
            for k in 0..2 {
                if let Some(e) = eq[k] {
                    band_points[k].push((n.crh, e));
                }
            }
            let inside = ratio.zip(band).map(|(r, (lo, hi))| (lo..=hi).contains(&r));
            checks.push(Check {
                what: format!("CRH {} / CRH {} depth at {v} m/s", n.crh, blunt.crh),
                target: format!(
                    "inside the equation's band widened by {:.0} %: {}",
                    100.0 * BAND_TOLERANCE,
                    or_dash(band, |(lo, hi)| format!("{lo:.3}–{hi:.3}"))
                ),
                result: or_dash(ratio, |r| format!("{r:.3}")),
                pass: inside,
            });
            table_rows.push(vec![
                format!("{v}"),
                format!("CRH {} / CRH {}", n.crh, blunt.crh),
                or_dash(n.mass.zip(blunt.mass), |(m, m2)| {
                    format!("{m:.3} / {m2:.3}")
                }),
                or_dash(n.depth.zip(blunt.depth), |(d, d2)| {
                    format!("{d:.4} / {d2:.4}")
                }),
                or_dash(ratio, |r| format!("{r:.3}")),
                or_dash(eq[0], |e| format!("{e:.3}")),
                or_dash(eq[1], |e| format!("{e:.3}")),
                format!(
                    "{}{}",
                    or_dash(band, |(lo, hi)| format!("{lo:.3}–{hi:.3}")),
                    match inside {
                        Some(true) => ": inside",
                        Some(false) => ": outside",
                        None => "",
                    }
                ),
            ]);
        }
        for (n, r) in noses.iter().zip(&records) {
            let s = r.summary();
            rows.push(vec![
                v.to_string(),
                n.crh.to_string(),
                or_dash(n.mass, |m| m.to_string()),
                or_dash(n.depth, |d| d.to_string()),
                or_dash(n.equation[0], |d| d.to_string()),
                or_dash(n.equation[1], |d| d.to_string()),
                r.status().to_string(),
                or_dash(s, |s| s.steps.to_string()),
                or_dash(s, |s| s.wall_s.to_string()),
                ctx.rel(&r.dir),
            ]);
        }
        chart = chart
            .series(
                &format!("simulated, {v} m/s"),
                simulated_points,
                Mark::LinePoints,
            )
            .series(
                &format!("equation, 4a crater, {v} m/s"),
                std::mem::take(&mut band_points[0]),
                Mark::Line,
            )
            .series(
                &format!("equation, Li–Chen crater, {v} m/s"),
                std::mem::take(&mut band_points[1]),
                Mark::Line,
            );
    }
    let csv = ctx.csv(
        section,
        "nose-shape.csv",
        &[
            "velocity_m_s",
            "crh",
            "mass_kg",
            "depth_m",
            "equation_depth_4a_m",
            "equation_depth_li_chen_m",
            "status",
            "steps",
            "wall_s",
            "dir",
        ],
        &rows,
    )?;
    let plot = ctx.plot(section, "depth-ratio-vs-crh.png", &chart)?;
    let mut md = format!(
        "The {} m/s shots' scenes as shipped{}, on {}, with the nose replaced by CRH {} ones \
         (`--set projectile.crh=…`: the outline keeps its length and cavity, so the body is \
         lighter). Each depth is divided by the shipped nose's at the same speed; Forrestal's \
         equation gives the same ratio at each run's own mass with the crater 4a deep \
         (Forrestal et al. 1994) or `(0.707 + H/d) d` deep (Li & Chen 2003, H the nose's \
         length). Target: the simulated ratio within {:.0} % of the band the two give. Raw data: \
         {csv}.\n\n",
        STUDY_SHOTS.map(|v| v.to_string()).join(" and "),
        if ctx.settings.quick {
            " with the quick overrides (cut short: no final depths)"
        } else {
            ""
        },
        ctx.primary().name(),
        NOSES.map(|c| c.to_string()).join(" and "),
        100.0 * BAND_TOLERANCE,
    );
    md += &table(
        &[
            "speed (m/s)",
            "noses",
            "masses (kg)",
            "depths (m)",
            "simulated ratio",
            "equation, 4a crater",
            "equation, Li–Chen crater",
            "the band widened by 3 %",
        ],
        &table_rows,
    );
    md += &plot;
    Ok(SectionOut {
        markdown: md,
        checks,
    })
}

/// The band a simulated ratio must lie in: between the two crater rules' ratios, widened by
/// [`BAND_TOLERANCE`] on each side.
fn widened(a: f64, b: f64) -> (f64, f64) {
    (
        a.min(b) * (1.0 - BAND_TOLERANCE),
        a.max(b) * (1.0 + BAND_TOLERANCE),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 277 m/s CRH 6 row as shipped: the rules give 0.960 and 1.046, so the band is
    /// 0.931–1.077 whichever comes first; 1.284 lies outside it, 1.0 and its edges inside.
    #[test]
    fn the_band_spans_both_rules_and_the_tolerance() {
        let (lo, hi) = widened(1.046, 0.960);
        assert_eq!((lo, hi), widened(0.960, 1.046));
        assert!(
            (lo - 0.9312).abs() < 1e-12 && (hi - 1.07738).abs() < 1e-12,
            "{lo} {hi}"
        );
        let inside = |r: f64| (lo..=hi).contains(&r);
        assert!(inside(1.0) && inside(lo) && inside(hi));
        assert!(!inside(1.284) && !inside(0.93));
    }
}
