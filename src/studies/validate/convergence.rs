//! Depth error against run time: the study shots at five resolutions on each backend, and the
//! round-off ensemble that sizes the CPU/GPU difference of single runs.

use crate::output::plot::{Chart, Mark};
use crate::scene::Backend;
use crate::studies::sweep::{self, RunRecord};

use super::context::{Ask, Context};
use super::penetration::{shot_ask, study_shot, ShotCase, STUDY_SHOTS};
use super::report::{or_dash, pct, table, Check, SectionOut};
use super::{Section, ValidateError};

/// The target: CPU and GPU at one resolution within 0.5 %.
const BACKEND_TOLERANCE: f64 = 0.005;

/// The refinement check: the depth at the shipped resolution (factor 1) and at twice it (half
/// the spacing and element size) within 3 % of each other.
pub const REFINEMENT: (f64, f64) = (1.0, 0.5);
const REFINEMENT_TOLERANCE: f64 = 0.03;

/// One convergence run and what it is compared with.
struct Level<'a> {
    velocity: f64,
    measured: f64,
    factor: f64,
    record: &'a RunRecord,
    /// Depth of the finest completed run of the same shot and backend.
    finest: Option<f64>,
}

impl Level<'_> {
    fn depth(&self) -> Option<f64> {
        self.record.completed().map(|s| s.depth_m)
    }

    fn error(&self) -> Option<f64> {
        self.depth().map(|d| d / self.measured - 1.0)
    }

    fn error_vs_finest(&self) -> Option<f64> {
        self.depth().zip(self.finest).map(|(d, f)| d / f - 1.0)
    }
}

/// The run of a shot with the lattice spacing and the element size scaled by `factor`.
fn level_ask(ctx: &Context, c: &ShotCase, factor: f64, backend: Backend) -> Ask {
    let spacing = c.scene.target.as_ref().map_or(0.0, |t| t.spacing);
    let element = c.scene.projectile.element_size;
    let mut a = shot_ask(
        ctx,
        c,
        &[
            format!("target.spacing={}", sweep::tidy(factor * spacing)),
            format!("projectile.element_size={}", sweep::tidy(factor * element)),
        ],
    );
    a.label += &format!("-x{factor}");
    a.backend = backend;
    a
}

pub(super) fn convergence(ctx: &mut Context) -> Result<SectionOut, ValidateError> {
    let section = Section::Convergence;
    let factors = ctx.settings.convergence_factors;
    let cases = STUDY_SHOTS
        .into_iter()
        .map(|v| study_shot(ctx, v))
        .collect::<Result<Vec<_>, _>>()?;
    let mut runs = Vec::new();
    for c in &cases {
        for &backend in &ctx.opts.backends.clone() {
            let asks = factors
                .iter()
                .map(|&f| level_ask(ctx, c, f, backend))
                .collect();
            let records = ctx.run(section, asks, false)?;
            runs.push((c.shot.clone(), records));
        }
    }
    let mut levels = Vec::new();
    for (shot, records) in &runs {
        let finest = factors
            .iter()
            .zip(records)
            .filter(|(_, r)| r.completed().is_some())
            .min_by(|a, b| a.0.total_cmp(b.0))
            .and_then(|(_, r)| r.completed().map(|s| s.depth_m));
        for (&factor, record) in factors.iter().zip(records) {
            levels.push(Level {
                velocity: shot.velocity,
                measured: shot.depth,
                factor,
                record,
                finest,
            });
        }
    }
    let mut rows = Vec::new();
    let mut table_rows = Vec::new();
    for l in &levels {
        let r = l.record;
        let s = r.summary();
        let spacing = r.scene.target.as_ref().map_or(0.0, |t| t.spacing);
        let element = r.scene.projectile.element_size;
        rows.push(vec![
            l.velocity.to_string(),
            r.backend.name().to_string(),
            l.factor.to_string(),
            spacing.to_string(),
            element.to_string(),
            or_dash(s, |s| s.particles.to_string()),
            or_dash(s, |s| s.elements.to_string()),
            or_dash(s, |s| s.steps.to_string()),
            or_dash(s, |s| s.wall_s.to_string()),
            or_dash(s, |s| s.depth_m.to_string()),
            l.measured.to_string(),
            or_dash(l.error(), |e| e.to_string()),
            or_dash(l.error_vs_finest(), |e| e.to_string()),
            r.status().to_string(),
            ctx.rel(&r.dir),
        ]);
        table_rows.push(vec![
            format!("{}", l.velocity),
            r.backend.name().to_string(),
            format!("{:.1} / {:.2}", spacing * 1e3, element * 1e3),
            or_dash(s, |s| s.particles.to_string()),
            or_dash(s, |s| s.elements.to_string()),
            or_dash(s, |s| s.steps.to_string()),
            or_dash(s, |s| format!("{:.1}", s.wall_s)),
            or_dash(l.depth(), |d| format!("{d:.4}")),
            or_dash(l.error(), pct),
            or_dash(l.error_vs_finest(), pct),
            r.status().to_string(),
        ]);
    }
    let csv = ctx.csv(
        section,
        "convergence.csv",
        &[
            "velocity_m_s",
            "backend",
            "factor",
            "spacing_m",
            "element_size_m",
            "particles",
            "elements",
            "steps",
            "wall_s",
            "depth_m",
            "measured_depth_m",
            "error_vs_measured",
            "error_vs_finest",
            "status",
            "dir",
        ],
        &rows,
    )?;
    // One curve per shot and backend, |error| in per cent against wall time (log–log: a
    // zero error, the finest run against itself, has no point).
    let curves = |error: fn(&Level) -> Option<f64>| {
        let mut chart_series = Vec::new();
        for (shot, records) in &runs {
            let Some(backend) = records.first().map(|r| r.backend) else {
                continue;
            };
            let mut points: Vec<(f64, f64)> = levels
                .iter()
                .filter(|l| l.velocity == shot.velocity && l.record.backend == backend)
                .filter_map(|l| {
                    let wall = l.record.completed()?.wall_s;
                    let e = 100.0 * error(l)?.abs();
                    (e > 0.0 && wall > 0.0).then_some((wall, e))
                })
                .collect();
            points.sort_by(|a, b| a.0.total_cmp(&b.0));
            chart_series.push((format!("{} m/s, {}", shot.velocity, backend.name()), points));
        }
        chart_series
    };
    let chart = |title: &str, y: &str, series: Vec<(String, Vec<(f64, f64)>)>| {
        series.into_iter().fold(
            Chart::new(title, "wall time (s)", y).log_x().log_y(),
            |c, (label, points)| c.series(&label, points, Mark::LinePoints),
        )
    };
    let measured_plot = ctx.plot(
        section,
        "error-vs-time.png",
        &chart(
            "Depth error against run time",
            "|depth error vs measured| (%)",
            curves(|l: &Level| l.error()),
        ),
    )?;
    let finest_plot = ctx.plot(
        section,
        "error-vs-finest.png",
        &chart(
            "Depth change from the finest run against run time",
            "|depth − finest depth| / finest depth (%)",
            curves(|l: &Level| l.error_vs_finest()),
        ),
    )?;
    // CPU against GPU at the same shot and resolution, where both completed.
    let mut checks = Vec::new();
    for v in STUDY_SHOTS {
        let pairs: Vec<(f64, f64)> = factors
            .iter()
            .filter_map(|&f| {
                let depth = |b: &str| {
                    levels
                        .iter()
                        .find(|l| l.velocity == v && l.factor == f && l.record.backend.name() == b)
                        .and_then(Level::depth)
                };
                Some((f, depth("gpu")? / depth("cpu")? - 1.0))
            })
            .collect();
        if pairs.is_empty() {
            continue;
        }
        let worst = pairs.iter().map(|p| p.1.abs()).fold(0.0, f64::max);
        checks.push(Check {
            what: format!(
                "{v} m/s: GPU against CPU depth at {} resolution(s)",
                pairs.len()
            ),
            target: format!("within {:.1} %", 100.0 * BACKEND_TOLERANCE),
            result: pairs
                .iter()
                .map(|(f, d)| format!("×{f}: {:+.3} %", 100.0 * d))
                .collect::<Vec<_>>()
                .join(", "),
            pass: Some(worst <= BACKEND_TOLERANCE),
        });
    }
    let mut md = format!(
        "The {} m/s shots with the lattice spacing and the element size scaled together by {} \
         (× the Forrestal section's), on {}. The error against the finest run is against the \
         finest completed run of the same shot and backend. Targets: the depth at ×{} within \
         {:.0} % of the depth at ×{} on each backend; CPU and GPU depths at one resolution \
         within {:.1} % where both ran{}. Raw data: {csv}.\n\n",
        STUDY_SHOTS.map(|v| v.to_string()).join(" and "),
        factors.map(|f| f.to_string()).join(", "),
        ctx.opts
            .backends
            .iter()
            .map(|&b| b.name())
            .collect::<Vec<_>>()
            .join(" and "),
        REFINEMENT.1,
        100.0 * REFINEMENT_TOLERANCE,
        REFINEMENT.0,
        100.0 * BACKEND_TOLERANCE,
        if checks.is_empty() {
            " (one backend ran: not evaluated)"
        } else {
            ""
        }
    );
    md += &table(
        &[
            "speed (m/s)",
            "backend",
            "Δ / element (mm)",
            "particles",
            "elements",
            "steps",
            "wall (s)",
            "depth (m)",
            "vs measured",
            "vs finest",
            "status",
        ],
        &table_rows,
    );
    md += &measured_plot;
    md += "\n";
    md += &finest_plot;
    let coarsest = factors.iter().copied().fold(0.0, f64::max);
    let (roundoff_md, roundoff_checks) = roundoff(ctx, &cases, coarsest)?;
    md += &roundoff_md;
    let checks = refinement_checks(&levels)
        .into_iter()
        .chain(checks)
        .chain(roundoff_checks)
        .collect();
    Ok(SectionOut {
        markdown: md,
        checks,
    })
}

/// Each shot and backend with both [`REFINEMENT`] levels: the depth at the finer against the
/// coarser (not evaluated where either did not complete).
fn refinement_checks(levels: &[Level]) -> Vec<Check> {
    let (coarse, fine) = REFINEMENT;
    let mut checks = Vec::new();
    for l in levels.iter().filter(|l| l.factor == coarse) {
        let Some(f) = levels.iter().find(|f| {
            f.factor == fine && f.velocity == l.velocity && f.record.backend == l.record.backend
        }) else {
            continue;
        };
        let change = l.depth().zip(f.depth()).map(|(c, f)| f / c - 1.0);
        checks.push(Check {
            what: format!(
                "{} m/s on {}: depth at ×{fine} against ×{coarse} (twice the resolution)",
                l.velocity,
                l.record.backend.name()
            ),
            target: format!("within {:.0} %", 100.0 * REFINEMENT_TOLERANCE),
            result: change.map_or_else(
                || "a run did not complete".to_string(),
                |c| format!("{:+.1} %", 100.0 * c),
            ),
            pass: change.map(|c| c.abs() <= REFINEMENT_TOLERANCE),
        });
    }
    checks
}

/// Striking-speed nudges of the round-off ensemble, in units in the last place of the f32 the
/// state holds the speed in (0: the convergence run itself).
pub const NUDGES: [i32; 5] = [-2, -1, 0, 1, 2];

/// `velocity` moved by `ulps` units in the last place of an f32 (`velocity` > 0).
fn nudged(velocity: f64, ulps: i32) -> f64 {
    let v = velocity as f32;
    f64::from(f32::from_bits(v.to_bits().wrapping_add_signed(ulps)))
}

/// The round-off ensemble: each study shot at the convergence level `factor`, struck
/// [`NUDGES`] ulps faster, on each backend. A change of the striking speed by a few parts in
/// 10⁷ is far below any physical uncertainty, so the range of those depths is how far
/// round-off alone, carried through the contact and the failing concrete, moves one run: the
/// scale a CPU/GPU difference of single runs is to be read against. Checks that the two
/// backends' mean depths agree within the backend tolerance.
fn roundoff(
    ctx: &mut Context,
    cases: &[ShotCase],
    factor: f64,
) -> Result<(String, Vec<Check>), ValidateError> {
    let section = Section::Convergence;
    let mut rows = Vec::new();
    let mut table_rows = Vec::new();
    // (shot speed, backend, mean depth) of every ensemble with at least two completed runs.
    let mut means: Vec<(f64, Backend, f64)> = Vec::new();
    for c in cases {
        let v = c.shot.velocity;
        for &backend in &ctx.opts.backends.clone() {
            let asks = NUDGES
                .iter()
                .map(|&n| {
                    let mut a = level_ask(ctx, c, factor, backend);
                    if n != 0 {
                        a.overrides
                            .push(format!("projectile.velocity={}", nudged(v, n)));
                        a.label += &format!("-ulp{n:+}");
                    }
                    a
                })
                .collect();
            let records = ctx.run(section, asks, false)?;
            let mut depths = Vec::new();
            for (&n, r) in NUDGES.iter().zip(&records) {
                let s = r.summary();
                rows.push(vec![
                    v.to_string(),
                    backend.name().to_string(),
                    factor.to_string(),
                    n.to_string(),
                    r.scene.projectile.velocity.to_string(),
                    or_dash(s, |s| s.depth_m.to_string()),
                    or_dash(s, |s| s.wall_s.to_string()),
                    r.status().to_string(),
                    ctx.rel(&r.dir),
                ]);
                depths.extend(r.completed().map(|s| s.depth_m));
            }
            let mean = depths.iter().sum::<f64>() / depths.len().max(1) as f64;
            let (lo, hi) = depths
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &d| {
                    (lo.min(d), hi.max(d))
                });
            let enough = depths.len() >= 2;
            if enough {
                means.push((v, backend, mean));
            }
            table_rows.push(vec![
                v.to_string(),
                backend.name().to_string(),
                format!("{} of {}", depths.len(), NUDGES.len()),
                depths
                    .iter()
                    .map(|d| format!("{d:.4}"))
                    .collect::<Vec<_>>()
                    .join(", "),
                or_dash(enough.then_some(mean), |m| format!("{m:.4}")),
                or_dash(enough.then(|| (hi - lo) / mean), |r| {
                    format!("{:.2} %", 100.0 * r)
                }),
            ]);
        }
    }
    let csv = ctx.csv(
        section,
        "roundoff.csv",
        &[
            "velocity_m_s",
            "backend",
            "factor",
            "ulps",
            "striking_speed_m_s",
            "depth_m",
            "wall_s",
            "status",
            "dir",
        ],
        &rows,
    )?;
    let mut checks = Vec::new();
    for c in cases {
        let v = c.shot.velocity;
        let mean = |b: Backend| means.iter().find(|m| m.0 == v && m.1 == b).map(|m| m.2);
        let Some((cpu, gpu)) = mean(Backend::Cpu).zip(mean(Backend::Gpu)) else {
            continue;
        };
        let d = gpu / cpu - 1.0;
        checks.push(Check {
            what: format!(
                "{v} m/s: GPU against CPU mean depth of the round-off ensemble at ×{factor}"
            ),
            target: format!("within {:.1} %", 100.0 * BACKEND_TOLERANCE),
            result: format!("{:+.3} %", 100.0 * d),
            pass: Some(d.abs() <= BACKEND_TOLERANCE),
        });
    }
    let mut md = format!(
        "\n### Round-off\n\nThe same shots at ×{factor}, the striking speed moved by {} units \
         in the last place of the f32 it is held in: a change of a few parts in 10⁷, far below \
         any physical uncertainty, so the range of the depths is how far round-off alone moves \
         a run. A difference between two single runs, the backends' above included, is to be \
         read against it. Where both backends ran, a check compares their mean depths. Raw \
         data: {csv}.\n\n",
        NUDGES.map(|n| n.to_string()).join(", "),
    );
    md += &table(
        &[
            "speed (m/s)",
            "backend",
            "completed",
            "depths (m)",
            "mean (m)",
            "range / mean",
        ],
        &table_rows,
    );
    Ok((md, checks))
}
