//! Concrete in tension (physics.md §3.1, "Tension"): the work a crack spends per unit area at
//! three lattice spacings, the crack band's against HJC's static cut-off, and the shipped
//! free-backed slab perforated at two resolutions under each. No measured perforation ships:
//! the check is against the fracture energy the crack band must spend.

use crate::cpu::concrete::{pull_apart, PullApart};
use crate::materials::hjc::Tension;
use crate::state::SphParams;

use super::context::{Ask, Context};
use super::report::{or_dash, pct, table, Check, SectionOut};
use super::{Section, ValidateError};

/// The scene perforated.
const CASE: &str = "slab-perforation.toml";
/// The strain rate (1/s) of the material points pulled apart: a spall's.
const RATE: f32 = 100.0;
/// The crack band must spend G_f per unit area within this share at every spacing (the
/// trapezoidal work of 200 steps to the cut-off is within a few tenths of a per cent).
const FRACTURE_TOLERANCE: f64 = 0.02;
/// The two tension models, as `target.tension` names them.
const MODELS: [&str; 2] = ["crack-band", "static"];

pub(super) fn run(ctx: &mut Context) -> Result<SectionOut, ValidateError> {
    let section = Section::Tension;
    let scene = ctx.scene(CASE, &[])?;
    let Some(target) = scene.target.as_ref() else {
        return Err(ValidateError::Input(format!(
            "{}: {CASE} has no target",
            section.name()
        )));
    };
    let spacing = target.spacing;
    let params = SphParams::new(target);
    let c = params.concrete;

    // The material points: pure opening and uniaxial strain at Δ/2, Δ and 2Δ.
    let bands = [0.5 * spacing, spacing, 2.0 * spacing].map(|b| b as f32);
    let paths: [(&str, [f32; 3]); 2] = [
        ("opening (equal principal rates)", [RATE; 3]),
        ("uniaxial strain", [0.0, RATE, 0.0]),
    ];
    let mut point_rows = Vec::new();
    let mut csv_rows = Vec::new();
    let mut opening_error: Option<f64> = Some(0.0);
    let t_d = c.t * crate::materials::hjc::tensile_rate_factor(RATE);
    let k_el = c.p_crush / c.mu_crush;
    for (path, rates) in paths {
        for model in MODELS {
            for &band in &bands {
                let tension = match model {
                    "static" => Tension::Static,
                    _ => Tension::CrackBand { band },
                };
                let point = pull_apart(&SphParams { tension, ..params }, rates);
                let per_area = point.map(|p| p.work * f64::from(band));
                if model == "crack-band" && rates == [RATE; 3] {
                    // Less the elastic energy stored before the crack opens.
                    let elastic = f64::from(t_d * t_d / (2.0 * k_el) * band);
                    let error = per_area.map(|w| (w - elastic) / f64::from(c.g_f) - 1.0);
                    opening_error = opening_error
                        .zip(error)
                        .map(|(worst, e): (f64, f64)| worst.max(e.abs()));
                }
                let peak = point.map(|p: PullApart| p.peak_tension);
                point_rows.push(vec![
                    path.to_string(),
                    model.to_string(),
                    format!("{:.1}", 1e3 * band),
                    or_dash(peak, |p| format!("{:.2}", p * 1e-6)),
                    or_dash(point, |p| format!("{:.1}", p.work * 1e-3)),
                    or_dash(per_area, |w| format!("{w:.1}")),
                ]);
                csv_rows.push(vec![
                    path.to_string(),
                    model.to_string(),
                    band.to_string(),
                    or_dash(peak, |p| p.to_string()),
                    or_dash(point, |p| p.work.to_string()),
                    or_dash(per_area, |w| w.to_string()),
                ]);
            }
        }
    }
    let points_csv = ctx.csv(
        section,
        "material-points.csv",
        &[
            "path",
            "tension",
            "band_m",
            "peak_tension_pa",
            "work_j_m3",
            "work_per_area_j_m2",
        ],
        &csv_rows,
    )?;

    // The slab at two resolutions, under each model.
    // Quick: as coarse as the rod's radius allows two elements across it.
    let factors: [f64; 2] = if ctx.settings.quick {
        [2.0, 1.5]
    } else {
        [2.0, 1.0]
    };
    let element = scene.projectile.element_size;
    let mut asks = Vec::new();
    for model in MODELS {
        for f in factors {
            asks.push(Ask {
                label: format!("{model}-x{f}"),
                case: CASE.into(),
                overrides: vec![
                    format!("target.tension=\"{model}\""),
                    format!(
                        "target.spacing={}",
                        crate::studies::sweep::tidy(f * spacing)
                    ),
                    format!(
                        "projectile.element_size={}",
                        crate::studies::sweep::tidy(f * element)
                    ),
                ],
                backend: ctx.primary(),
            });
        }
    }
    let records = ctx.run(section, asks, false)?;
    let mut slab_rows = Vec::new();
    let mut slab_csv = Vec::new();
    let mut perforated = Some(true);
    for (k, rec) in records.iter().enumerate() {
        let (model, f) = (MODELS[k / factors.len()], factors[k % factors.len()]);
        let s = rec.completed();
        let through = s.map(|s| s.stop_reason == crate::output::summary::PERFORATED);
        if model == "crack-band" {
            perforated = perforated.zip(through).map(|(a, b)| a && b);
        }
        slab_rows.push(vec![
            model.to_string(),
            format!("{:.1}", 1e3 * f * spacing),
            or_dash(s, |s| s.stop_reason.clone()),
            or_dash(s, |s| format!("{:.1}", s.projectile_velocity_m_s)),
            or_dash(s, |s| format!("{:.3}", s.front_ejecta_kg)),
            or_dash(s, |s| format!("{:.3}", s.rear_ejecta_kg)),
            or_dash(s, |s| format!("{:.2}", 100.0 * s.energy_error)),
            rec.status().to_string(),
        ]);
        slab_csv.push(vec![
            model.to_string(),
            (f * spacing).to_string(),
            or_dash(s, |s| s.stop_reason.clone()),
            or_dash(s, |s| s.projectile_velocity_m_s.to_string()),
            or_dash(s, |s| s.front_ejecta_kg.to_string()),
            or_dash(s, |s| s.rear_ejecta_kg.to_string()),
            or_dash(s, |s| s.energy_error.to_string()),
            rec.status().to_string(),
            ctx.rel(&rec.dir),
        ]);
    }
    let slab_csv = ctx.csv(
        section,
        "slab.csv",
        &[
            "tension",
            "spacing_m",
            "stop_reason",
            "residual_velocity_m_s",
            "front_ejecta_kg",
            "rear_ejecta_kg",
            "energy_error",
            "status",
            "dir",
        ],
        &slab_csv,
    )?;

    let checks = vec![
        Check {
            what: format!(
                "crack band's work per crack area, opening at {RATE}/s, bands {}–{} mm",
                1e3 * bands[0],
                1e3 * bands[2]
            ),
            target: format!(
                "G_f = {:.1} J/m² within {:.0} %",
                c.g_f,
                100.0 * FRACTURE_TOLERANCE
            ),
            result: or_dash(opening_error, |e| format!("worst {}", pct(e))),
            pass: opening_error.map(|e| e <= FRACTURE_TOLERANCE),
        },
        Check {
            what: format!(
                "{} m/s into the {} mm free-backed slab, crack band",
                scene.projectile.velocity,
                1e3 * target.thickness
            ),
            target: "the projectile leaves the slab at both resolutions".into(),
            result: match perforated {
                Some(true) => "perforated".into(),
                Some(false) => "stopped in the slab".into(),
                None => "—".into(),
            },
            pass: perforated,
        },
    ];
    let mut md = format!(
        "A material point of the slab's concrete (f_c {:.1} MPa, G_f {:.1} J/m², T {:.2} MPa, \
         {:.2} MPa at {RATE}/s) strained at {RATE}/s from rest until it fails, through the \
         concrete update itself (`cpu::concrete::pull_apart`): the work spent per unit volume, \
         and times the band (the spacing) per unit crack area. Under the crack band that is \
         G_f plus the elastic energy stored before the crack opens ({:.2} J/m² per mm of band) \
         along an opening, whatever the band; under HJC's static cut-off an opening without \
         shear never fails (no entry), and along uniaxial strain the work per volume is the same at \
         every spacing, so per crack area it grows with the spacing. Raw data: {points_csv}.\n\n",
        c.fc * 1e-6,
        c.g_f,
        c.t * 1e-6,
        t_d * 1e-6,
        f64::from(t_d * t_d / (2.0 * k_el)) * 1e-3,
    );
    md += &table(
        &[
            "path",
            "tension",
            "band (mm)",
            "peak tension (MPa)",
            "work (kJ/m³)",
            "per crack area (J/m²)",
        ],
        &point_rows,
    );
    md += &format!(
        "\nThe shipped slab ({CASE}: {} m/s, a {} mm rod through {} mm of {:.0} MPa concrete, \
         free rear face) at {} and {} mm spacing (elements scaled alike) under each model, on \
         {}. No measured residual velocity ships with it. Ejecta: concrete more than one \
         spacing outside the slab's faces when the run stops. Raw data: {slab_csv}.\n\n",
        scene.projectile.velocity,
        1e3 * scene.projectile.diameter,
        1e3 * target.thickness,
        c.fc * 1e-6,
        1e3 * factors[0] * spacing,
        1e3 * factors[1] * spacing,
        ctx.primary().name(),
    );
    md += &table(
        &[
            "tension",
            "spacing (mm)",
            "stop",
            "residual velocity (m/s)",
            "front ejecta (kg)",
            "rear ejecta (kg)",
            "energy error (%)",
            "status",
        ],
        &slab_rows,
    );
    Ok(SectionOut {
        markdown: md,
        checks,
    })
}
