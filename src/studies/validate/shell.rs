//! The paper's shell projectile (§5, Fig. 6, 7, 9): a sweep of striking speeds, the critical
//! velocity above which damage appears in the shell's wall (bisection on the largest damage
//! behind the nose), whether and where an element of the wall fails, damage maps on both sides
//! of the critical velocity, and the growth of the damaged area in time.

use crate::output::plot::{Chart, FieldMap, Mark};
use crate::studies::sweep::RunRecord;

use super::bisect::{self, Bracket};
use super::context::{Ask, Context};
use super::frame;
use super::report::{or_dash, table, SectionOut};
use super::{Section, ValidateError};
use crate::output::run_files::history;

/// The shell's scene in the cases folder.
const SHELL_FILE: &str = "shell-projectile.toml";

/// Damage at which an element has failed (physics.md §2.3).
const FAILED: f64 = 1.0;

/// Why the bisection stopped before its tolerance.
enum Stop {
    /// Output could not be written: the validation stops.
    Fatal(ValidateError),
    /// A run gave no summary to judge.
    NoRun(String),
}

/// A run counts as damaged when damage has appeared in an element behind the nose (the shell's
/// wall, `max_damage_shank` > 0): physics.md §8 defines the critical velocity as the one above
/// which damage appears, and the paper finds no damage (损伤破坏) at 250 m/s and some at
/// 300 m/s. The Johnson–Cook damage grows from the first plastic strain, so this is also the
/// speed above which the wall yields. The nose is left out: the contact loads it hardest, and
/// its yielding says nothing of the shell.
fn damaged(r: &RunRecord) -> Option<bool> {
    r.summary().map(|s| s.max_damage_shank > 0.0)
}

/// Whether an element of the wall failed (reported beside the criterion, not bisected on).
fn failed(r: &RunRecord) -> Option<bool> {
    r.summary().map(|s| s.max_damage_shank >= FAILED)
}

fn yes_no(b: bool) -> String {
    if b { "yes" } else { "no" }.into()
}

/// The share of the striking kinetic energy the projectile took as plastic work: a shell whose
/// depth stops growing with its speed has to take a growing share.
fn plastic_share(r: &RunRecord) -> Option<f64> {
    r.summary()
        .filter(|s| s.energy.initial_kinetic > 0.0)
        .map(|s| s.energy.plastic_work_projectile / s.energy.initial_kinetic)
}

fn speed(r: &RunRecord) -> f64 {
    r.scene.projectile.velocity
}

/// Least-squares slope of `points`; `None` for fewer than two distinct x.
fn slope(points: &[(f64, f64)]) -> Option<f64> {
    let n = points.len() as f64;
    let (mx, my) = points
        .iter()
        .fold((0.0, 0.0), |(a, b), p| (a + p.0 / n, b + p.1 / n));
    let sxx: f64 = points.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    (points.len() >= 2 && sxx > 0.0).then(|| sxy / sxx)
}

pub(super) fn run(ctx: &mut Context) -> Result<SectionOut, ValidateError> {
    let section = Section::Shell;
    let speeds = ctx.settings.shell_speeds.clone();
    let tolerance = ctx.settings.shell_tolerance;
    let base_overrides = ctx.settings.shell.clone();
    let backend = ctx.primary();
    let base = ctx.scene(SHELL_FILE, &base_overrides)?;
    let ask = |v: f64| {
        let mut overrides = base_overrides.clone();
        overrides.push(speeds.set(v));
        Ask {
            label: speeds.label(v),
            case: SHELL_FILE.into(),
            overrides,
            backend,
        }
    };
    // Every shell run writes its first and last VTK frame: the damage maps read the last.
    let sweep_records = ctx.run(
        section,
        speeds.values.iter().map(|&v| ask(v)).collect(),
        true,
    )?;
    let known: Vec<(f64, bool)> = sweep_records
        .iter()
        .filter_map(|r| Some((speed(r), damaged(r)?)))
        .collect();
    let start = match known.iter().position(|k| k.1) {
        _ if known.is_empty() => Err("no run of the sweep gave a result".to_string()),
        Some(i) if i > 0 => Ok((known[i - 1].0, known[i].0)),
        Some(_) => Err(format!(
            "the wall was damaged at every speed tried: the critical velocity is below {} m/s",
            known[0].0
        )),
        None => Err(format!(
            "the wall was not damaged at any speed tried: the critical velocity is above {} m/s",
            known.last().map_or(0.0, |k| k.0)
        )),
    };
    let mut bisection_records = Vec::new();
    let mut stop_note = String::new();
    let bracket: Result<Bracket, String> = match start {
        Err(why) => Err(why),
        Ok((below, above)) => {
            let found = bisect::bisect(below, above, tolerance, |v| {
                let r = ctx
                    .run(section, vec![ask(v)], true)
                    .map_err(Stop::Fatal)?
                    .pop()
                    .ok_or_else(|| Stop::NoRun(format!("{v} m/s: no run")))?;
                let d = damaged(&r);
                bisection_records.push(r);
                d.ok_or_else(|| Stop::NoRun(format!("{v} m/s did not run")))
            });
            match found {
                Ok(b) => Ok(b),
                Err(Stop::Fatal(e)) => return Err(e),
                Err(Stop::NoRun(why)) => {
                    stop_note = format!(" The bisection stopped early: {why}.");
                    // The bracket as far as it got: the bisection's runs lie inside it.
                    let tried: Vec<(f64, bool)> = bisection_records
                        .iter()
                        .filter_map(|r| Some((speed(r), damaged(r)?)))
                        .collect();
                    let below = tried
                        .iter()
                        .filter(|t| !t.1)
                        .map(|t| t.0)
                        .fold(below, f64::max);
                    let above = tried
                        .iter()
                        .filter(|t| t.1)
                        .map(|t| t.0)
                        .fold(above, f64::min);
                    Ok(Bracket { below, above })
                }
            }
        }
    };
    let mut all: Vec<(&str, &RunRecord)> = sweep_records
        .iter()
        .map(|r| ("sweep", r))
        .chain(bisection_records.iter().map(|r| ("bisection", r)))
        .collect();
    all.sort_by(|a, b| speed(a.1).total_cmp(&speed(b.1)));

    let mut rows = Vec::new();
    let mut table_rows = Vec::new();
    let (mut depths, mut damages) = (Vec::new(), Vec::new());
    for (role, r) in &all {
        let s = r.summary();
        if let Some(s) = r.completed() {
            depths.push((speed(r), s.depth_m));
            damages.push((speed(r), s.max_damage_shank));
        }
        rows.push(vec![
            speed(r).to_string(),
            role.to_string(),
            r.status().to_string(),
            or_dash(s, |s| s.depth_m.to_string()),
            or_dash(s, |s| s.max_damage.to_string()),
            or_dash(s, |s| s.max_damage_shank.to_string()),
            or_dash(damaged(r), |d| d.to_string()),
            or_dash(failed(r), |d| d.to_string()),
            or_dash(s, |s| s.max_plastic_strain.to_string()),
            or_dash(s, |s| s.max_plastic_strain_shank.to_string()),
            or_dash(s, |s| s.final_length_m.to_string()),
            or_dash(plastic_share(r), |x| x.to_string()),
            or_dash(s, |s| s.steps.to_string()),
            or_dash(s, |s| s.wall_s.to_string()),
            ctx.rel(&r.dir),
        ]);
        table_rows.push(vec![
            format!("{}", speed(r)),
            role.to_string(),
            or_dash(s, |s| format!("{:.4}", s.depth_m)),
            or_dash(s, |s| format!("{:.3}", s.max_damage)),
            or_dash(s, |s| format!("{:.2e}", s.max_damage_shank)),
            or_dash(damaged(r), yes_no),
            or_dash(failed(r), yes_no),
            or_dash(s, |s| format!("{:.3}", s.max_plastic_strain_shank)),
            or_dash(plastic_share(r), |x| format!("{:.2} %", 100.0 * x)),
            or_dash(s, |s| format!("{:.1}", s.wall_s)),
            r.status().to_string(),
        ]);
    }
    let csv = ctx.csv(
        section,
        "shell.csv",
        &[
            "velocity_m_s",
            "role",
            "status",
            "depth_m",
            "max_damage",
            "max_damage_shank",
            "wall_damaged",
            "wall_failed",
            "max_plastic_strain",
            "max_plastic_strain_shank",
            "final_length_m",
            "plastic_work_share",
            "steps",
            "wall_s",
            "dir",
        ],
        &rows,
    )?;

    // Depth and damage against speed, the critical velocity marked.
    let top = |p: &[(f64, f64)]| p.iter().map(|x| x.1).fold(0.0, f64::max);
    let mut depth_chart = Chart::new(
        "Shell projectile: depth against striking speed",
        "striking speed (m/s)",
        "depth of penetration (m)",
    )
    .series("depth", depths.clone(), Mark::LinePoints);
    let mut damage_chart = Chart::new(
        "Shell projectile: largest damage behind the nose against striking speed",
        "striking speed (m/s)",
        "max damage behind the nose",
    )
    .series(
        "max damage behind the nose",
        damages.clone(),
        Mark::LinePoints,
    );
    if let Ok(b) = &bracket {
        depth_chart = depth_chart.series(
            "critical velocity",
            vec![(b.mid(), 0.0), (b.mid(), top(&depths))],
            Mark::Line,
        );
        damage_chart = damage_chart.series(
            "critical velocity",
            vec![(b.mid(), 0.0), (b.mid(), top(&damages))],
            Mark::Line,
        );
    }
    let depth_plot = ctx.plot(section, "depth-vs-velocity.png", &depth_chart)?;
    let damage_plot = ctx.plot(section, "damage-vs-velocity.png", &damage_chart)?;

    // Damage maps on both sides of the critical velocity (the sweep's ends without one), and
    // at the fastest speed run, on one colour scale: from 0 to the largest damage among them.
    let fastest = all.iter().map(|(_, r)| speed(r)).fold(f64::NAN, f64::max);
    let mut sides = match &bracket {
        Ok(b) => vec![b.below, b.above],
        Err(_) => vec![
            speeds.values.first().copied().unwrap_or(0.0),
            speeds.values.last().copied().unwrap_or(0.0),
        ],
    };
    if fastest.is_finite() && !sides.contains(&fastest) {
        sides.push(fastest);
    }
    let mut frames = Vec::new();
    let mut maps = String::new();
    for v in sides {
        let Some((_, r)) = all.iter().find(|(_, r)| speed(r) == v) else {
            continue;
        };
        match frame::last_projectile_frame(&r.dir) {
            Ok(f) => frames.push((v, f)),
            Err(e) => maps += &format!("- {v} m/s: no damage map ({e})\n"),
        }
    }
    let largest = frames
        .iter()
        .flat_map(|(_, f)| f.damage.iter().copied())
        .filter(|d| d.is_finite())
        .fold(0.0, f64::max);
    let range = (0.0, if largest > 0.0 { largest } else { 1.0 });
    for (v, f) in frames {
        // The projectile lying along x, mirrored about its axis: the whole section.
        let mut triangles = Vec::with_capacity(2 * f.triangles.len());
        for sign in [1.0, -1.0] {
            triangles.extend(
                f.triangles
                    .iter()
                    .map(|t| t.map(|k| [f.z[k] * 1e3, sign * f.r[k] * 1e3])),
            );
        }
        let map = FieldMap {
            title: format!("Shell projectile damage at {v} m/s (end of run)"),
            x_label: "z (mm)".into(),
            y_label: "r (mm)".into(),
            value_label: "damage".into(),
            triangles,
            values: [f.damage.clone(), f.damage].concat(),
            squares: Vec::new(),
            range,
        };
        let file = format!("damage-map-{v}.png");
        let path = ctx.dir(section).join(&file);
        map.write_png(&path)
            .map_err(|e| ValidateError::Io(format!("{}: {e}", path.display())))?;
        maps += &format!("![{}]({}/{file})\n", map.title, section.name());
    }

    // Damaged area against time, one curve per sweep speed.
    let mut area_rows = Vec::new();
    let mut area_chart = Chart::new(
        "Shell projectile: damaged area against time",
        "time (ms)",
        "damaged area Σ D·A (mm²)",
    );
    let mut area_notes = String::new();
    for r in &sweep_records {
        match history(&r.dir, &["time_s", "damage_area_m2"]) {
            Ok(h) => {
                for (t, a) in h[0].iter().zip(&h[1]) {
                    area_rows.push(vec![speed(r).to_string(), t.to_string(), a.to_string()]);
                }
                let points = h[0]
                    .iter()
                    .zip(&h[1])
                    .map(|(t, a)| (t * 1e3, a * 1e6))
                    .collect();
                area_chart = area_chart.series(&format!("{} m/s", speed(r)), points, Mark::Line);
            }
            Err(e) => area_notes += &format!("- {} m/s: no history ({e})\n", speed(r)),
        }
    }
    let area_csv = ctx.csv(
        section,
        "damage-area.csv",
        &["velocity_m_s", "time_s", "damage_area_m2"],
        &area_rows,
    )?;
    let area_plot = ctx.plot(section, "damage-area.png", &area_chart)?;

    let p = &base.projectile;
    let wall = p
        .cavity
        .map_or(0.5 * p.diameter, |c| 0.5 * (p.diameter - c.diameter));
    let (critical, efficiency) = match &bracket {
        Ok(b) => {
            let below: Vec<(f64, f64)> =
                depths.iter().copied().filter(|d| d.0 <= b.below).collect();
            let above: Vec<(f64, f64)> =
                depths.iter().copied().filter(|d| d.0 >= b.above).collect();
            (
                format!(
                    "**critical velocity ≈ {:.0} m/s**: no damage in the wall at {} m/s, damage at \
                     {} m/s.{stop_note}",
                    b.mid(),
                    b.below,
                    b.above
                ),
                format!(
                    " Depth gained per m/s of striking speed (least squares over the completed \
                     runs): {} below the critical velocity, {} above it.",
                    or_dash(slope(&below), |s| format!("{:.2} mm", s * 1e3)),
                    or_dash(slope(&above), |s| format!("{:.2} mm", s * 1e3)),
                ),
            )
        }
        Err(why) => (
            format!("critical velocity not found: {why}."),
            String::new(),
        ),
    };
    // Failure of the wall, beside the criterion: the slowest run in which an element failed.
    let judged: Vec<(f64, bool)> = all
        .iter()
        .filter_map(|(_, r)| Some((speed(r), failed(r)?)))
        .collect();
    let failure = match judged.iter().find(|j| j.1) {
        Some(j) => format!(" An element of the wall failed first at {} m/s.", j.0),
        None => judged.last().map_or(String::new(), |j| {
            format!(
                " No element of the wall failed at any speed run (up to {} m/s).",
                j.0
            )
        }),
    };
    // The energy the shell took: the paper's loss of efficiency needs a growing share of it.
    let shares: Vec<(f64, f64)> = all
        .iter()
        .filter_map(|(_, r)| Some((speed(r), plastic_share(r)?)))
        .collect();
    let absorbed = match shares
        .iter()
        .copied()
        .reduce(|a, b| if b.1 > a.1 { b } else { a })
    {
        Some((v, x)) => format!(
            " The projectile's plastic work took at most {:.2} % of the striking kinetic energy \
             (at {v} m/s); a depth that stops growing with the speed needs the shell to take a \
             growing share of it.",
            100.0 * x
        ),
        None => String::new(),
    };
    let mut md = format!(
        "`cases/{SHELL_FILE}`{}: the Forrestal outline hollowed to a {:.2} mm wall (cavity \
         {:.1} mm across), {:.3} kg, material preset `{}`, into {:.1} MPa concrete, on {}. \
         Striking speeds {} m/s, then bisection on the largest damage behind the nose (the \
         shell's wall; the nose, where the contact's load is highest, is left out): \
         a run counts as damaged when that damage is above 0 (damage has appeared in the wall, \
         physics.md §8; the Johnson–Cook damage grows from the first plastic strain; a run that \
         stopped early counts by the damage it reached); the bisection stops \
         when the bracket is at most {tolerance} m/s wide. Result: {critical}{failure}{efficiency}{absorbed} \
         (The paper finds ≈ 250 m/s for its shell and concrete: no damage at 250 m/s, damage \
         at 300 m/s.) Raw data: {csv}, {area_csv}.\n\n",
        if ctx.settings.quick {
            " with the quick overrides"
        } else {
            ""
        },
        wall * 1e3,
        p.cavity.map_or(0.0, |c| c.diameter * 1e3),
        all.iter()
            .find_map(|(_, r)| r.summary().map(|s| s.projectile_mass_kg))
            .unwrap_or(0.0),
        p.material.preset,
        base.target
            .as_ref()
            .map_or(0.0, |t| t.concrete.fc as f64 * 1e-6),
        backend.name(),
        speeds
            .values
            .iter()
            .map(|v| v.to_string())
            .collect::<Vec<_>>()
            .join(", "),
    );
    md += &table(
        &[
            "speed (m/s)",
            "run",
            "depth (m)",
            "max damage",
            "behind the nose",
            "wall damaged",
            "wall failed",
            "plastic strain behind the nose",
            "plastic work / striking energy",
            "wall (s)",
            "status",
        ],
        &table_rows,
    );
    md += &depth_plot;
    md += "\n";
    md += &damage_plot;
    md += &format!(
        "\nDamage of the projectile's elements at the end of the runs either side of the \
         critical velocity and of the fastest run (the deformed r–z section, mirrored about the \
         axis; one colour scale, from 0 to {:.3}, the largest damage among them):\n\n",
        range.1
    );
    md += &maps;
    md += "\nDamaged area (Σ damage × element r–z area, the `damage_area_m2` column of \
           `history.csv`) against time:\n\n";
    md += &area_notes;
    md += &area_plot;
    Ok(SectionOut {
        markdown: md,
        checks: vec![],
    })
}
