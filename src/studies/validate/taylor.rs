//! Taylor bars (`taylor.csv`): final length and mushroom diameter against the measurement at
//! three element sizes.

use crate::output::plot::{Chart, Mark};
use crate::studies::sweep::{self, RunRecord};

use super::context::{Ask, Context};
use super::report::{or_dash, pct, table, Check, SectionOut};
use super::{data, end_state, Section, ValidateError};

/// One bar of the section: a scene, the `taylor.csv` material it reproduces, and overrides.
pub struct Bar {
    pub file: &'static str,
    pub material: &'static str,
    /// Appended to the scene's name in the tables and run labels ("" for the scene as shipped).
    pub variant: &'static str,
    pub overrides: &'static [&'static str],
    /// Whether the bar is one of the checks; the others are shown for comparison.
    pub checked: bool,
}

/// The shipped Taylor scenes, and copper with the Johnson–Cook constants of the `taylor.csv`
/// header beside them: the shipped copper scene runs Zerilli–Armstrong's law, and the
/// Johnson–Cook law it replaced keeps its result in the report.
pub const CASES: [Bar; 3] = [
    Bar {
        file: "taylor-4340-208.toml",
        material: "steel-4340",
        variant: "",
        overrides: &[],
        checked: true,
    },
    Bar {
        file: "taylor-copper-190.toml",
        material: "copper-ofhc",
        variant: "",
        overrides: &[],
        checked: true,
    },
    Bar {
        file: "taylor-copper-190.toml",
        material: "copper-ofhc",
        variant: "-johnson-cook",
        overrides: &["projectile.material.preset=copper-ofhc"],
        checked: false,
    },
];

/// The targets at the finest mesh: final length within 2 % of the measurement, mushroom
/// diameter within 5 %.
const LENGTH_TOLERANCE: f64 = 0.02;
const DIAMETER_TOLERANCE: f64 = 0.05;

pub(super) fn run(ctx: &mut Context) -> Result<SectionOut, ValidateError> {
    let section = Section::Taylor;
    let tests = data::taylor(&ctx.opts.data)?;
    let mut rows = Vec::new();
    let mut table_rows = Vec::new();
    let mut checks = Vec::new();
    let mut checked_runs = Vec::new();
    let mut length_series = Vec::new();
    let mut diameter_series = Vec::new();
    for bar in &CASES {
        let (file, material) = (bar.file, bar.material);
        let test = tests
            .iter()
            .find(|t| t.material == material)
            .ok_or_else(|| {
                ValidateError::Input(format!(
                    "{}: no row for {material} (the measurement of cases/{file})",
                    ctx.opts.data.join(data::TAYLOR_FILE).display()
                ))
            })?;
        let fixed: Vec<String> = bar.overrides.iter().map(|o| o.to_string()).collect();
        let base = ctx.scene(file, &fixed)?;
        let name = format!("{}{}", base.name, bar.variant);
        let p = &base.projectile;
        let agrees = |a: f64, b: f64| (a - b).abs() <= 1e-6 * b.abs();
        if !(agrees(p.diameter, test.diameter)
            && agrees(p.length, test.length)
            && agrees(p.velocity, test.velocity))
        {
            return Err(ValidateError::Input(format!(
                "cases/{file} ({} mm × {} mm at {} m/s) is not the {material} test of {} \
                 ({} mm × {} mm at {} m/s)",
                p.diameter * 1e3,
                p.length * 1e3,
                p.velocity,
                data::TAYLOR_FILE,
                test.diameter * 1e3,
                test.length * 1e3,
                test.velocity
            )));
        }
        let sizes: Vec<f64> = ctx
            .settings
            .taylor_factors
            .iter()
            .map(|f| sweep::tidy(f * p.element_size))
            .collect();
        let asks = sizes
            .iter()
            .map(|&h| Ask {
                label: format!("{name}-{}mm", sweep::tidy(h * 1e3)),
                case: file.to_string(),
                overrides: fixed
                    .iter()
                    .cloned()
                    .chain([format!("projectile.element_size={h}")])
                    .collect(),
                backend: ctx.primary(),
            })
            .collect();
        let records = ctx.run(section, asks, false)?;
        let mut lengths = Vec::new();
        let mut diameters = Vec::new();
        for (&h, r) in sizes.iter().zip(&records) {
            let done = r.completed();
            let length_error = done.map(|s| s.final_length_m / test.final_length - 1.0);
            let diameter_error = done.map(|s| 2.0 * s.max_radius_m / test.mushroom_diameter - 1.0);
            if let (Some(l), Some(d)) = (length_error, diameter_error) {
                lengths.push((h * 1e3, 100.0 * l));
                diameters.push((h * 1e3, 100.0 * d));
            }
            let s = r.summary();
            rows.push(vec![
                name.clone(),
                material.to_string(),
                h.to_string(),
                or_dash(s, |s| s.elements.to_string()),
                or_dash(s, |s| s.steps.to_string()),
                or_dash(s, |s| s.wall_s.to_string()),
                r.status().to_string(),
                or_dash(s, |s| s.final_length_m.to_string()),
                test.final_length.to_string(),
                or_dash(length_error, |e| e.to_string()),
                or_dash(s, |s| (2.0 * s.max_radius_m).to_string()),
                test.mushroom_diameter.to_string(),
                or_dash(diameter_error, |e| e.to_string()),
                ctx.rel(&r.dir),
            ]);
            table_rows.push(vec![
                name.clone(),
                format!("{:.3}", h * 1e3),
                or_dash(s, |s| s.elements.to_string()),
                or_dash(s, |s| format!("{:.3}", s.final_length_m * 1e3)),
                format!("{:.2}", test.final_length * 1e3),
                or_dash(length_error, pct),
                or_dash(s, |s| format!("{:.2}", 2e3 * s.max_radius_m)),
                format!("{:.2}", test.mushroom_diameter * 1e3),
                or_dash(diameter_error, pct),
                or_dash(s, |s| format!("{:.1}", s.wall_s)),
                r.status().to_string(),
            ]);
        }
        let finest = sizes.iter().zip(&records).min_by(|a, b| a.0.total_cmp(b.0));
        if let Some((&h, r)) = finest.filter(|_| bar.checked) {
            let done = r.completed();
            let measures = [
                (
                    "final length",
                    done.map(|s| s.final_length_m),
                    test.final_length,
                    LENGTH_TOLERANCE,
                ),
                (
                    "mushroom diameter",
                    done.map(|s| 2.0 * s.max_radius_m),
                    test.mushroom_diameter,
                    DIAMETER_TOLERANCE,
                ),
            ];
            for (what, simulated, measured, tolerance) in measures {
                let error = simulated.map(|x| x / measured - 1.0);
                checks.push(Check {
                    what: format!("{name} {what}, {:.3} mm elements", h * 1e3),
                    target: format!(
                        "within {:.0} % of {:.2} mm",
                        100.0 * tolerance,
                        measured * 1e3
                    ),
                    result: or_dash(error, pct),
                    pass: error.map(|e| e.abs() <= tolerance),
                });
            }
        }
        if bar.checked {
            // The end state is judged on the shipped mesh and the finer ones (the finest alone
            // where all are coarser, as in a quick run).
            let shipped_or_finer = sizes
                .iter()
                .zip(&records)
                .filter(|(&h, _)| h <= p.element_size * (1.0 + 1e-9))
                .map(|(_, r)| r.clone())
                .collect::<Vec<_>>();
            if shipped_or_finer.is_empty() {
                checked_runs.extend(finest.map(|(_, r)| r.clone()));
            } else {
                checked_runs.extend(shipped_or_finer);
            }
        }
        length_series.push((name.clone(), lengths));
        diameter_series.push((name, diameters));
    }
    let csv = ctx.csv(
        section,
        "taylor.csv",
        &[
            "scene",
            "material",
            "element_size_m",
            "elements",
            "steps",
            "wall_s",
            "status",
            "final_length_m",
            "measured_final_length_m",
            "length_error",
            "mushroom_diameter_m",
            "measured_mushroom_diameter_m",
            "diameter_error",
            "dir",
        ],
        &rows,
    )?;
    let chart = |title: &str, y: &str, series: Vec<(String, Vec<(f64, f64)>)>| {
        series.into_iter().fold(
            Chart::new(title, "element size (mm)", y),
            |c, (label, points)| c.series(&label, points, Mark::LinePoints),
        )
    };
    let length_plot = ctx.plot(
        section,
        "final-length.png",
        &chart(
            "Taylor bars: final length against element size",
            "final length error vs measured (%)",
            length_series,
        ),
    )?;
    let diameter_plot = ctx.plot(
        section,
        "mushroom-diameter.png",
        &chart(
            "Taylor bars: mushroom diameter against element size",
            "mushroom diameter error vs measured (%)",
            diameter_series,
        ),
    )?;
    let mut md = format!(
        "Bars onto a rigid wall at three element sizes ({}× the shipped scene's), on {}. \
         The mushroom diameter is twice the largest nodal radius. Targets at the finest mesh: \
         final length within {:.0} %, mushroom diameter within {:.0} %; at the shipped mesh and \
         finer, {}. The copper scene's strength is Zerilli & Armstrong's \
         (1987) fcc law with their published constants; `taylor-copper-190-johnson-cook` is \
         the same bar with the Johnson–Cook constants of the taylor.csv header, shown for \
         comparison and not a check. Raw data: {csv}.\n\n",
        ctx.settings
            .taylor_factors
            .iter()
            .map(|f| f.to_string())
            .collect::<Vec<_>>()
            .join(", "),
        ctx.primary().name(),
        100.0 * LENGTH_TOLERANCE,
        100.0 * DIAMETER_TOLERANCE,
        end_state::targets()
    );
    md += &table(
        &[
            "scene",
            "element (mm)",
            "elements",
            "final length (mm)",
            "measured (mm)",
            "error",
            "mushroom Ø (mm)",
            "measured (mm)",
            "error",
            "wall (s)",
            "status",
        ],
        &table_rows,
    );
    md += &length_plot;
    md += "\n";
    md += &diameter_plot;
    let runs: Vec<&RunRecord> = checked_runs.iter().collect();
    checks.extend(end_state::checks(
        "the checked bars at the shipped mesh and finer",
        &runs,
    ));
    Ok(SectionOut {
        markdown: md,
        checks,
    })
}
