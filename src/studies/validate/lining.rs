//! The concrete lining the nose, CRH 2 against CRH 6, each with the lining's kernel cut at the
//! projectile and completed by wall images ([`crate::studies::lining`]): kernel completeness,
//! the volumetric rate the step reads against a first-order consistent one, and the pressure,
//! along the nose; and the contact's normal pressure on the nose by bands of radius against the
//! local law behind Forrestal's equation. Measurements (does the cut kernel under-read a
//! slender nose's compaction, and what completing it changes; is the tip near the axis
//! overloaded); no accuracy target. The first row's push toward the nose is split into the
//! stress's and the artificial viscosity's.

use crate::output::plot::{Chart, Mark};
use crate::studies::lining::{band_pressures, study, BandPressure, Lining, Snapshot};

use super::context::Context;
use super::forrestal;
use super::report::{or_dash, table, SectionOut};
use super::{Section, ValidateError};

/// The noses compared (calibres), on the 277 m/s shot's scene.
const NOSES: [f64; 2] = [2.0, 6.0];

/// One run of the section: a nose, and whether wall images complete the lining's kernel.
#[derive(Clone, Copy, Debug)]
struct Case {
    crh: f64,
    images: bool,
}

impl Case {
    fn label(self) -> String {
        if self.images {
            format!("CRH {}, images", self.crh)
        } else {
            format!("CRH {}", self.crh)
        }
    }
}
/// The lining: particles within this many smoothing lengths of the nose's surface.
const BAND: f32 = 1.0;
/// The first row: lining particles within this many smoothing lengths of the surface, those
/// the contact holds off it, whose push toward the nose is the load it passes on.
const FIRST_ROW: f32 = 0.5;
/// Bins along the nose, tip to shoulder.
const BINS: usize = 5;
/// Bands of the nose by r/a for its contact pressure; the first is the axis band.
const BANDS: [f32; 7] = [0.0, 0.3, 0.5, 0.7, 0.8, 0.9, 1.0];

pub(super) fn run(ctx: &mut Context) -> Result<SectionOut, ValidateError> {
    let section = Section::Lining;
    // Full: from when the CRH 6 nose (64.5 mm) is buried at 277 m/s to well into the tunnel;
    // quick: inside the quick run's 0.3 ms.
    let times: &[f64] = if ctx.settings.quick {
        &[1.5e-4, 2.0e-4, 2.5e-4]
    } else {
        &[3.5e-4, 4.0e-4, 4.5e-4, 5.0e-4]
    };
    let mut readings = Vec::new();
    let mut loads = Vec::new();
    // With wall images: per nose, the share of the nose's axial impulse over the window that
    // the images' shear along it gave.
    let mut drags = Vec::new();
    // Why the images were not run, where a scene cannot take them (a rigid projectile).
    let mut no_images = None;
    let cases: Vec<Case> = [false, true]
        .into_iter()
        .flat_map(|images| NOSES.map(|crh| Case { crh, images }))
        .collect();
    for (k, &wanted) in cases.iter().enumerate() {
        let crh = wanted.crh;
        let mut overrides = ctx.settings.forrestal.clone();
        overrides.push(format!("projectile.crh={crh}"));
        let kernel = if wanted.images { "images" } else { "cut" };
        overrides.push(format!("contact.kernel=\"{kernel}\""));
        let scene = match ctx.scene("forrestal1994-277.toml", &overrides) {
            Ok(scene) => scene,
            Err(e) if wanted.images => {
                no_images = Some(format!("this scene cannot take them: {e}"));
                continue;
            }
            Err(e) => return Err(e),
        };
        // What ran: validate's --set comes last and may fix the kernel for every run.
        let case = Case {
            crh,
            images: scene.contact.kernel == crate::scene::SurfaceKernel::Images,
        };
        if readings
            .iter()
            .any(|(c, _): &(Case, _)| c.crh == crh && c.images == case.images)
        {
            no_images = Some("--set fixes contact.kernel for every run".into());
            continue;
        }
        let (fc, density) = scene.target.as_ref().map_or((0.0, 0.0), |t| {
            (t.concrete.fc as f64, t.concrete.density as f64)
        });
        // The local law behind Forrestal's equation (physics.md §8): S f_c + ρ (V n_z)².
        let strength = forrestal::Inputs {
            mass: 0.0,
            shank_radius: 0.0,
            crh,
            density,
            fc,
        }
        .strength_factor()
            * fc;
        let law = move |n_z: f64, v: f64| strength + density * (v * n_z).powi(2);
        let started = std::time::Instant::now();
        let snapshots = study(&scene, times, BAND).map_err(|e| {
            ValidateError::Input(format!("{}: {}: {e}", section.name(), case.label()))
        })?;
        (ctx.progress)(&format!(
            "[lining {}/{}] {} on cpu: {} lining readings at {} instants, {:.1} s",
            k + 1,
            cases.len(),
            case.label(),
            snapshots.iter().map(|s| s.lining.len()).sum::<usize>(),
            snapshots.len(),
            started.elapsed().as_secs_f64()
        ));
        if let (Some(first), Some(last)) = (snapshots.first(), snapshots.last()) {
            loads.push((case, band_pressures(first, last, &BANDS, &law)));
            if case.images {
                let drag: f64 = first
                    .nose
                    .iter()
                    .zip(&last.nose)
                    .map(|(a, b)| b.drag - a.drag)
                    .sum();
                drags.push((case, drag / (last.nose_impulse - first.nose_impulse)));
            }
        }
        readings.push((case, snapshots));
    }
    let mut rows = Vec::new();
    for (case, snapshots) in &readings {
        for s in snapshots {
            for l in &s.lining {
                rows.push(vec![
                    case.crh.to_string(),
                    s.time.to_string(),
                    s.depth.to_string(),
                    l.along.to_string(),
                    l.radius_ratio.to_string(),
                    l.distance.to_string(),
                    l.normal_velocity.to_string(),
                    l.pressure.to_string(),
                    l.kernel.completeness.to_string(),
                    l.kernel.divergence.to_string(),
                    l.kernel.divergence_corrected.to_string(),
                    l.push.to_string(),
                    l.viscous_push.to_string(),
                    u8::from(case.images).to_string(),
                ]);
            }
        }
    }
    let csv = ctx.csv(
        section,
        "lining.csv",
        &[
            "crh",
            "time_s",
            "depth_m",
            "along_nose",
            "r_over_a",
            "distance_over_h",
            "normal_velocity_m_s",
            "pressure_pa",
            "completeness",
            "divergence_1_s",
            "divergence_corrected_1_s",
            "push_n",
            "viscous_push_n",
            "images",
        ],
        &rows,
    )?;
    let binned: Vec<(Case, Vec<Bin>)> = readings.iter().map(|(c, s)| (*c, bins(s))).collect();
    let chart = |title: &str, y: &str, f: &dyn Fn(&Bin) -> Option<f64>| {
        binned.iter().fold(
            Chart::new(title, "position along the nose (0 tip, 1 shoulder)", y),
            |c, (case, b)| {
                let points = b
                    .iter()
                    .filter_map(|bin| f(bin).map(|y| (bin.centre, y)))
                    .collect();
                c.series(&case.label(), points, Mark::LinePoints)
            },
        )
    };
    let completeness = ctx.plot(
        section,
        "completeness.png",
        &chart(
            "Kernel completeness of the concrete lining the nose",
            "Σ (m/ρ) W",
            &|b| b.completeness,
        ),
    )?;
    let rate_chart = binned.iter().fold(
        Chart::new(
            "Volumetric rate of the concrete lining the nose (medians)",
            "position along the nose (0 tip, 1 shoulder)",
            "−ρ̇/ρ (1/ms)",
        ),
        |c, (case, b)| {
            let of = |f: &dyn Fn(&Bin) -> Option<f64>| {
                b.iter()
                    .filter_map(|bin| f(bin).map(|y| (bin.centre, y * 1e-3)))
                    .collect()
            };
            c.series(
                &format!("{}, as stepped", case.label()),
                of(&|b| b.divergence),
                Mark::LinePoints,
            )
            .series(
                &format!("{}, corrected gradient", case.label()),
                of(&|b| b.divergence_corrected),
                Mark::LinePoints,
            )
        },
    );
    let rate = ctx.plot(section, "volumetric-rate.png", &rate_chart)?;
    let pressure = ctx.plot(
        section,
        "pressure.png",
        &chart(
            "Pressure in the concrete lining the nose",
            "pressure (MPa)",
            &|b| b.pressure.map(|p| p * 1e-6),
        ),
    )?;
    let mut table_rows = Vec::new();
    for (case, b) in &binned {
        for bin in b {
            table_rows.push(vec![
                case.label(),
                format!(
                    "{:.1}–{:.1}",
                    bin.centre - 0.5 / BINS as f64,
                    bin.centre + 0.5 / BINS as f64
                ),
                bin.count.to_string(),
                or_dash(bin.normal_velocity, |v| format!("{v:.0}")),
                or_dash(bin.completeness, |c| format!("{c:.2}")),
                or_dash(bin.divergence, |d| format!("{:.2}", d * 1e-3)),
                or_dash(bin.divergence_corrected, |d| format!("{:.2}", d * 1e-3)),
                or_dash(bin.pressure, |p| format!("{:.0}", p * 1e-6)),
                or_dash(bin.viscous_share, |x| format!("{:.0} %", 100.0 * x)),
            ]);
        }
    }
    let mut md = format!(
        "The 277 m/s shot's scene{} with a CRH 2 and a CRH 6 nose (same body otherwise), each \
         with the lining's kernel cut at the projectile, as the paper has it, and completed by \
         wall images (`contact.kernel = \"images\"`, physics.md §4: the completeness, the \
         step's rate, the push and the nose's pressure count them){}, on the CPU path, read at t = {} ms: every particle within {BAND} h of the nose's surface and \
         not behind it. Per bin along the nose: readings (all instants), the nose's mean normal \
         velocity, the kernel completeness `Σ (m̃/ρ) W` (1 in the bulk, ½–¾ at a free face; above 1 where the particles are packed tighter than their density says), the \
         volumetric rate `−ρ̇/ρ` as the step takes it and as a first-order consistent gradient \
         (`G M⁻¹`, full hoop rate) reads it from the same velocities (medians: a few particles \
         at the axis read rates ten times the others'), the mean pressure, and the artificial \
         viscosity's share of the push toward the nose on the first row (within {FIRST_ROW} h \
         of the surface: the particles the contact holds off it, whose push it passes on to the \
         nose; the pair forces at the same instant with and without the viscosity, Σ over the \
         row's readings). Raw data: {csv}.\n\n",
        if ctx.settings.quick {
            " with the quick overrides"
        } else {
            ""
        },
        no_images.map_or(String::new(), |why| {
            format!(" (one of the two was not run: {why})")
        }),
        times
            .iter()
            .map(|t| format!("{}", t * 1e3))
            .collect::<Vec<_>>()
            .join(", "),
    );
    md += &table(
        &[
            "nose",
            "along the nose",
            "readings",
            "v_n (m/s)",
            "completeness",
            "−ρ̇/ρ as stepped (1/ms)",
            "corrected (1/ms)",
            "pressure (MPa)",
            "viscous share of the push",
        ],
        &table_rows,
    );
    for (case, snapshots) in &readings {
        if let Some(share) = viscous_share(snapshots.iter().flat_map(|s| &s.lining)) {
            md += &format!(
                "\n{}, the whole nose: the viscosity carries {:.0} % of the first row's push \
                 toward the nose.\n",
                case.label(),
                100.0 * share
            );
        }
    }
    md += "\n";
    md += &completeness;
    md += &rate;
    md += &pressure;
    md += &nose_load(ctx, section, times, &loads)?;
    for (case, share) in drags {
        md += &format!(
            "\n{}: the images' shear along the nose gave {:.0} % of its axial impulse over the \
             window (their normal push is in the pressures above).\n",
            case.label(),
            100.0 * share
        );
    }
    Ok(SectionOut {
        markdown: md,
        checks: vec![],
    })
}

/// One bin along the nose over every instant's readings.
struct Bin {
    centre: f64,
    count: usize,
    normal_velocity: Option<f64>,
    completeness: Option<f64>,
    /// Medians of the volumetric rate as stepped and from the corrected gradient (1/s).
    divergence: Option<f64>,
    divergence_corrected: Option<f64>,
    pressure: Option<f64>,
    /// The viscosity's share of the first row's push toward the nose.
    viscous_share: Option<f64>,
}

/// The artificial viscosity's share of the first row's push toward the nose, over `lining`;
/// none where the row does not push.
fn viscous_share<'a>(lining: impl Iterator<Item = &'a Lining>) -> Option<f64> {
    let (push, viscous) = lining
        .filter(|l| l.distance <= FIRST_ROW)
        .fold((0.0, 0.0), |(p, v), l| {
            (p + l.push as f64, v + l.viscous_push as f64)
        });
    (push > 0.0).then(|| viscous / push)
}

fn bins(snapshots: &[Snapshot]) -> Vec<Bin> {
    (0..BINS)
        .map(|k| {
            let (lo, hi) = (k as f32 / BINS as f32, (k + 1) as f32 / BINS as f32);
            let inside: Vec<_> = snapshots
                .iter()
                .flat_map(|s| &s.lining)
                .filter(|l| l.along >= lo && (l.along < hi || (k + 1 == BINS && l.along <= hi)))
                .collect();
            let count = inside.len();
            let mean = |f: &dyn Fn(&&Lining) -> f32| {
                (count > 0).then(|| inside.iter().map(|l| f(l) as f64).sum::<f64>() / count as f64)
            };
            let median = |f: &dyn Fn(&&Lining) -> f32| {
                let mut v: Vec<f64> = inside.iter().map(|l| f(l) as f64).collect();
                v.sort_by(f64::total_cmp);
                (count > 0).then(|| {
                    if count % 2 == 1 {
                        v[count / 2]
                    } else {
                        0.5 * (v[count / 2 - 1] + v[count / 2])
                    }
                })
            };
            Bin {
                centre: (lo + hi) as f64 / 2.0,
                count,
                normal_velocity: mean(&|l| l.normal_velocity),
                completeness: mean(&|l| l.kernel.completeness),
                divergence: median(&|l| l.kernel.divergence),
                divergence_corrected: median(&|l| l.kernel.divergence_corrected),
                pressure: mean(&|l| l.pressure),
                viscous_share: viscous_share(inside.iter().copied()),
            }
        })
        .collect()
}

/// The contact's normal pressure on the nose by bands of r/a over the window between the first
/// and last instants, against the local law behind Forrestal's equation: the axis band is where
/// a near-axis overload shows.
fn nose_load(
    ctx: &mut Context,
    section: Section,
    times: &[f64],
    loads: &[(Case, Vec<BandPressure>)],
) -> Result<String, ValidateError> {
    let mut rows = Vec::new();
    let mut table_rows = Vec::new();
    for (case, bands) in loads {
        for b in bands {
            rows.push(vec![
                case.crh.to_string(),
                b.lo.to_string(),
                b.hi.to_string(),
                b.share.to_string(),
                b.pressure.to_string(),
                b.law.to_string(),
                u8::from(case.images).to_string(),
            ]);
            let finite = |x: f64| x.is_finite().then_some(x);
            table_rows.push(vec![
                case.label(),
                format!("{:.1}–{:.1}", b.lo, b.hi),
                format!("{:.2}", b.share),
                or_dash(finite(b.pressure), |p| format!("{:.0}", p * 1e-6)),
                or_dash(finite(b.law), |p| format!("{:.0}", p * 1e-6)),
                or_dash(finite(b.pressure / b.law), |x| format!("{x:.2}")),
            ]);
        }
    }
    let csv = ctx.csv(
        section,
        "nose-pressure.csv",
        &[
            "crh",
            "r_over_a_from",
            "r_over_a_to",
            "share_of_cross_section",
            "pressure_pa",
            "law_pa",
            "images",
        ],
        &rows,
    )?;
    let chart = loads.iter().fold(
        Chart::new(
            "Contact pressure on the nose by radius, against the local law",
            "r/a (band centre)",
            "normal pressure (MPa)",
        ),
        |c, (case, bands)| {
            let of = |f: &dyn Fn(&BandPressure) -> f64| {
                bands
                    .iter()
                    .filter(|b| f(b).is_finite())
                    .map(|b| (0.5 * (b.lo + b.hi) as f64, f(b) * 1e-6))
                    .collect()
            };
            let c = c.series(
                &format!("{}, simulated", case.label()),
                of(&|b| b.pressure),
                Mark::LinePoints,
            );
            // The law is the nose's, whatever the kernel: drawn once.
            if case.images {
                c
            } else {
                c.series(
                    &format!("CRH {}, S f_c + ρ(V n_z)²", case.crh),
                    of(&|b| b.law),
                    Mark::Line,
                )
            }
        },
    );
    let plot = ctx.plot(section, "nose-pressure.png", &chart)?;
    let mut md = format!(
        "\n**Contact pressure on the nose** between t = {} and {} ms: each band's master segments' \
         normal impulse (the λ correction's m_S δ and, with wall images, the normal part of the \
         images' reaction, summed over the window) over their rings' area \
         2π r̄ l and the window, against the local law behind Forrestal's equation, \
         `σ_n = S f_c + ρ (V n_z)²` (S = 82.6 f_c^−0.544, V the window's mean speed, n_z the \
         segment normal's axial part), averaged over the same area. `share` is the band's part \
         of πa². Raw data: {csv}.\n\n",
        times.first().map_or(0.0, |t| t * 1e3),
        times.last().map_or(0.0, |t| t * 1e3),
    );
    md += &table(
        &[
            "nose",
            "r/a",
            "share",
            "simulated (MPa)",
            "law (MPa)",
            "ratio",
        ],
        &table_rows,
    );
    for (case, bands) in loads {
        let (tip, rest) = bands.split_at(1.min(bands.len()));
        let ratio = |b: &[BandPressure]| or_dash(weighted_ratio(b), |x| format!("{x:.2}"));
        md += &format!(
            "\n{}: the whole nose carries {} times its law, the nose beyond the axis band \
             {} times, the axis band {} times (bands weighted by their shares of πa²).\n",
            case.label(),
            ratio(bands),
            ratio(rest),
            ratio(tip)
        );
    }
    md += "\n";
    md += &plot;
    Ok(md)
}

/// The simulated pressure over the law's on `bands` taken together, each weighted by its share
/// of πa² (the axial force each would carry at a uniform normal pressure); none where no band
/// has both.
fn weighted_ratio(bands: &[BandPressure]) -> Option<f64> {
    let (simulated, law) = bands
        .iter()
        .filter(|b| b.pressure.is_finite() && b.law.is_finite())
        .fold((0.0, 0.0), |(s, l), b| {
            (s + b.share * b.pressure, l + b.share * b.law)
        });
    (law > 0.0).then(|| simulated / law)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn band(share: f64, pressure: f64, law: f64) -> BandPressure {
        BandPressure {
            lo: 0.0,
            hi: 1.0,
            share,
            pressure,
            law,
        }
    }

    /// Bands that each carry k times their law carry k times it together; a band without a
    /// segment (NaN) is left out; the shares weight the bands.
    #[test]
    fn the_weighted_ratio_weighs_the_bands_by_their_shares() {
        let k = [band(0.2, 300.0, 100.0), band(0.8, 150.0, 50.0)];
        assert!((weighted_ratio(&k).unwrap() - 3.0).abs() < 1e-12);
        let with_empty = [k[0], band(0.0, f64::NAN, f64::NAN), k[1]];
        assert_eq!(weighted_ratio(&with_empty), weighted_ratio(&k));
        // 0.5·200 + 0.5·100 over 0.5·100 + 0.5·100.
        let mixed = [band(0.5, 200.0, 100.0), band(0.5, 100.0, 100.0)];
        assert!((weighted_ratio(&mixed).unwrap() - 1.5).abs() < 1e-12);
        assert_eq!(weighted_ratio(&[]), None);
    }
}
