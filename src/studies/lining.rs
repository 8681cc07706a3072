//! The concrete lining the projectile's nose: how much of each lining particle's kernel is
//! filled, and how much of the volumetric rate the nose imposes its gradient reads (issue: a
//! kernel cut by the projectile, which has no particles, may under-read the compaction a
//! slender nose makes by pushing material sideways; docs/physics.md §3).
//!
//! A particle lines the nose when its nearest point on the nose's master segments is within a
//! band of the surface and it is not behind it. For each such particle: where along the nose
//! it sits, the nose's normal velocity there, its pressure, and [`KernelReading`] — the kernel
//! completeness and the volumetric rate as the step takes it and as a first-order consistent
//! (corrected) gradient gives it from the same velocities; and the pair forces' push toward the
//! nose with the artificial viscosity's part of it, so the load the contact carries onto the
//! nose can be told apart into the concrete's stress and the viscosity.

use crate::cpu::neighbours::CellGrid;
use crate::cpu::sph_rates::{kernel_readings, KernelReading};
use crate::cpu::wall::Wall;
use crate::scene::Scene;
use crate::solver::{Model, RunError, Simulation};
use crate::state::{Particles, SphParams};

/// One lining particle at one instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lining {
    /// Position along the nose by height: 0 at the tip, 1 at the shoulder.
    pub along: f32,
    /// Its radius over the shank radius a.
    pub radius_ratio: f32,
    /// Distance from the nose surface over the smoothing length h.
    pub distance: f32,
    /// The nose surface's velocity along its outward normal at the nearest point (m/s).
    pub normal_velocity: f32,
    /// Pressure (Pa).
    pub pressure: f32,
    pub kernel: KernelReading,
    /// The pair forces' push on its ring toward the nose, `−F·n` with n the nose's outward
    /// normal at the nearest point (N): for a particle the contact holds off the surface, what
    /// the contact passes on to the nose.
    pub push: f32,
    /// The artificial viscosity's part of `push` (N).
    pub viscous_push: f32,
}

/// The particles lining the nose of `model` within `band` smoothing lengths of its surface.
pub fn lining(model: &Model, band: f32) -> Vec<Lining> {
    let Some(sph) = model.sph.as_ref() else {
        return vec![];
    };
    let h = sph.h;
    let n = &model.projectile.nodes;
    let nose: Vec<_> = nose_masters(model).map(|(_, a, b)| (a, b)).collect();
    if nose.is_empty() {
        return vec![];
    }
    let ends = nose.iter().flat_map(|&(a, b)| [a, b]);
    let tip = ends.clone().map(|k| n.z[k]).fold(f32::MAX, f32::min);
    let shoulder = ends.clone().map(|k| n.z[k]).fold(f32::MIN, f32::max);
    let shank_radius = ends.map(|k| n.r[k]).fold(0.0, f32::max);
    let reach = band * h;
    let p = &model.particles;
    let mut found = Vec::new();
    let mut which = Vec::new();
    let mut normals = Vec::new();
    for i in 0..p.r.len() {
        let (r, z) = (p.r[i], p.z[i]);
        if z < tip - reach || z > shoulder + reach || r > shank_radius + reach {
            continue;
        }
        // The nearest point on the nose: (distance², signed distance, foot's z, normal speed,
        // outward normal).
        let mut best: Option<(f32, f32, f32, f32, [f32; 2])> = None;
        for &(a, b) in &nose {
            let (dr, dz) = (n.r[b] - n.r[a], n.z[b] - n.z[a]);
            let len2 = dr * dr + dz * dz;
            if len2 <= 0.0 {
                continue;
            }
            let t = (((r - n.r[a]) * dr + (z - n.z[a]) * dz) / len2).clamp(0.0, 1.0);
            let (fr, fz) = (n.r[a] + t * dr, n.z[a] + t * dz);
            let d2 = (r - fr).powi(2) + (z - fz).powi(2);
            if best.is_some_and(|b| b.0 <= d2) {
                continue;
            }
            // Outward normal (Δz, −Δr)/|AB| (mesh::MasterSegment).
            let len = len2.sqrt();
            let (nr, nz) = (dz / len, -dr / len);
            let vr = n.vr[a] + t * (n.vr[b] - n.vr[a]);
            let vz = n.vz[a] + t * (n.vz[b] - n.vz[a]);
            let signed = (r - fr) * nr + (z - fz) * nz;
            best = Some((d2, signed, fz, vr * nr + vz * nz, [nr, nz]));
        }
        let Some((d2, signed, foot_z, normal_velocity, normal)) = best else {
            continue;
        };
        // Not behind the surface by more than a contact's tolerance, and within the band.
        if signed < -0.25 * h || d2 > reach * reach {
            continue;
        }
        which.push(i);
        normals.push(normal);
        found.push(Lining {
            along: (foot_z - tip) / (shoulder - tip).max(f32::MIN_POSITIVE),
            radius_ratio: r / shank_radius,
            distance: d2.sqrt() / h,
            normal_velocity,
            pressure: p.p[i],
            kernel: KernelReading {
                completeness: 0.0,
                divergence: 0.0,
                divergence_corrected: 0.0,
            },
            push: 0.0,
            viscous_push: 0.0,
        });
    }
    let mut grid = CellGrid::default();
    crate::cpu::neighbours::run(&mut grid, &p.r, &p.z, &sph.kernel);
    // With wall images, the walls the last force evaluation found, at these positions.
    let walls = model.walls.found();
    for (l, k) in found
        .iter_mut()
        .zip(kernel_readings(p, &grid, sph, walls, &which))
    {
        l.kernel = k;
    }
    let (with, without) = pair_forces(p, &grid, sph, walls);
    for ((l, &i), n) in found.iter_mut().zip(&which).zip(&normals) {
        let push = |a: &Particles| -p.mass[i] * (a.ar[i] * n[0] + a.az[i] * n[1]);
        l.push = push(&with);
        l.viscous_push = l.push - push(&without);
    }
    found
}

/// The particles with `sph_forces`' accelerations at their present positions, with the
/// artificial viscosity and without it (α = β = 0, everything else the same): their difference
/// is the viscosity's part, the pair sums being otherwise the same terms in the same order.
/// `grid` is the neighbour list of the present positions; `walls` the particles' walls where
/// the scene has wall images (their pairs count as a neighbour's).
fn pair_forces(
    p: &Particles,
    grid: &CellGrid,
    sph: &SphParams,
    walls: Option<&[Wall]>,
) -> (Particles, Particles) {
    let forces = |params: &SphParams| {
        let mut q = p.clone();
        crate::cpu::sph_forces::run(&mut q, grid, params, walls);
        q
    };
    let dry = SphParams {
        alpha: 0.0,
        beta: 0.0,
        ..*sph
    };
    (forces(sph), forces(&dry))
}

/// Runs `scene` on the CPU path and reads the lining at each of `times` (s, ascending) once the
/// run has passed it: the readings, each with the time and the nose's depth below the face.
pub fn study(scene: &Scene, times: &[f64], band: f32) -> Result<Vec<Snapshot>, RunError> {
    let mut sim = Simulation::new(scene)?;
    let mut out = Vec::new();
    // Per master segment, the normal impulse the wall images' reaction gave it and the axial
    // impulse of the rest of that reaction, along the segment (N s): each step's integration
    // takes the segments' last sums over its Δt (`Model::walls`).
    let mut images = vec![[0.0f64; 2]; sim.model()?.projectile.masters.len()];
    for &t in times {
        while sim.time() < t {
            let m = sim.model()?;
            let n = &m.projectile.nodes;
            for (k, s) in m.walls.sums.iter().enumerate() {
                let seg = &m.projectile.masters[k];
                let (a, b) = (seg.a as usize, seg.b as usize);
                let (dr, dz) = (n.r[b] - n.r[a], n.z[b] - n.z[a]);
                let len = dr.hypot(dz);
                if len > 0.0 {
                    // Outward normal (Δz, −Δr)/|AB|; the particles' push along it presses on
                    // the segment, whose axial part on the projectile is push · Δr/|AB|.
                    let push = ((s[0] + s[2]) * dz - (s[1] + s[3]) * dr) / len;
                    let axial = -(s[1] + s[3]) - push * dr / len;
                    images[k][0] += push as f64 * m.dt as f64;
                    images[k][1] += axial as f64 * m.dt as f64;
                }
            }
            sim.step()?;
        }
        let model = sim.model()?;
        out.push(Snapshot {
            time: model.time,
            depth: model.depth(),
            speed: -model.projectile_velocity(),
            nose_impulse: model.account.nose_impulse,
            lining: lining(model, band),
            nose: nose_segments(model, &images),
        });
    }
    Ok(out)
}

/// The lining at one instant.
#[derive(Clone, Debug)]
pub struct Snapshot {
    pub time: f64,
    /// The nose tip's depth below the target's face (m).
    pub depth: f64,
    /// The projectile's speed into the target (m/s).
    pub speed: f64,
    /// The axial impulse the contact gave the nose since the run began (N s).
    pub nose_impulse: f64,
    pub lining: Vec<Lining>,
    /// The nose's master segments, tip first.
    pub nose: Vec<NoseSegment>,
}

/// One master segment of the nose at one instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NoseSegment {
    /// Its midpoint's radius over the shank radius a.
    pub radius_ratio: f32,
    /// Its ring's area 2π r̄ l (m²).
    pub ring_area: f64,
    /// Its ring's area projected on the axis, 2π r̄ |Δr| (m²).
    pub frontal_area: f64,
    /// The axial part of its outward normal, |n_z|.
    pub normal_z: f64,
    /// The normal impulse the contact gave it since the run began (N s): its closing hits' and,
    /// with wall images, the images' reaction's.
    pub impulse: f64,
    /// With wall images, the axial impulse of their reaction along the segment (N s): the
    /// images' shear on it.
    pub drag: f64,
}

/// The nose's master segments of `model`: (master index, node a, node b).
fn nose_masters(model: &Model) -> impl Iterator<Item = (usize, usize, usize)> + '_ {
    let masters = &model.projectile.masters;
    (0..masters.len())
        .filter(|&k| model.on_nose()[k])
        .map(|k| (k, masters[k].a as usize, masters[k].b as usize))
}

/// The nose's master segments of `model`, tip first, with their impulses so far.
/// `images`: per master segment, the normal impulse of the wall images' reaction so far and the
/// axial impulse of the rest of it.
pub fn nose_segments(model: &Model, images: &[[f64; 2]]) -> Vec<NoseSegment> {
    let n = &model.projectile.nodes;
    let shank_radius = nose_masters(model)
        .flat_map(|(_, a, b)| [a, b])
        .map(|i| n.r[i])
        .fold(0.0f32, f32::max);
    let mut segments: Vec<(f32, NoseSegment)> = nose_masters(model)
        .map(|(k, a, b)| {
            let (dr, dz) = ((n.r[b] - n.r[a]) as f64, (n.z[b] - n.z[a]) as f64);
            let length = dr.hypot(dz);
            let mid_r = 0.5 * (n.r[a] + n.r[b]) as f64;
            let ring = 2.0 * std::f64::consts::PI * mid_r;
            let segment = NoseSegment {
                radius_ratio: (mid_r / shank_radius as f64) as f32,
                ring_area: ring * length,
                frontal_area: ring * dr.abs(),
                normal_z: if length > 0.0 { dr.abs() / length } else { 0.0 },
                impulse: model.account.segment_impulse[k] + images[k][0],
                drag: images[k][1],
            };
            (0.5 * (n.z[a] + n.z[b]), segment)
        })
        .collect();
    segments.sort_by(|x, y| x.0.total_cmp(&y.0));
    segments.into_iter().map(|(_, s)| s).collect()
}

/// The contact's mean normal pressure on a band of the nose between two instants, against a
/// local law's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BandPressure {
    /// The band, lo ≤ r̄/a < hi (the last band's hi included).
    pub lo: f32,
    pub hi: f32,
    /// The band's share of the shank's cross-section πa².
    pub share: f64,
    /// Its segments' normal impulse over their rings' area and the time between (Pa).
    pub pressure: f64,
    /// The law's normal stress at the mean speed, averaged over the same rings' area (Pa).
    pub law: f64,
}

/// The contact pressure on each band of the nose between `from` and `to` (the same run), bands
/// by r̄/a between consecutive `edges`; `law(|n_z|, V)` is a local law's normal stress on a
/// segment whose normal has axial part n_z at speed V, evaluated at the two instants' mean speed.
pub fn band_pressures(
    from: &Snapshot,
    to: &Snapshot,
    edges: &[f32],
    law: &dyn Fn(f64, f64) -> f64,
) -> Vec<BandPressure> {
    let window = to.time - from.time;
    let speed = 0.5 * (from.speed + to.speed);
    let cross_section: f64 = to.nose.iter().map(|s| s.frontal_area).sum();
    edges
        .windows(2)
        .enumerate()
        .map(|(k, e)| {
            let last = k + 2 == edges.len();
            let inside = |s: &&(&NoseSegment, &NoseSegment)| {
                let x = s.1.radius_ratio;
                x >= e[0] && (x < e[1] || (last && x <= e[1]))
            };
            let pairs: Vec<_> = from.nose.iter().zip(&to.nose).collect();
            let band: Vec<_> = pairs.iter().filter(inside).collect();
            let area: f64 = band.iter().map(|(_, s)| s.ring_area).sum();
            let impulse: f64 = band.iter().map(|(a, b)| b.impulse - a.impulse).sum();
            let law_area: f64 = band
                .iter()
                .map(|(_, s)| law(s.normal_z, speed) * s.ring_area)
                .sum();
            let frontal: f64 = band.iter().map(|(_, s)| s.frontal_area).sum();
            let per_area = |x: f64| if area > 0.0 { x / area } else { f64::NAN };
            BandPressure {
                lo: e[0],
                hi: e[1],
                // (+ 0.0: an empty band's sum is −0.0.)
                share: frontal / cross_section + 0.0,
                pressure: per_area(impulse / window),
                law: per_area(law_area),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cpu::sph_rates::kernel_readings;

    /// The Forrestal scene on a coarse lattice (12 mm, h = 18 mm): fast, and wide enough that
    /// the block has a bulk.
    fn coarse(extra: &[&str]) -> Scene {
        let mut overrides = vec![
            "target.spacing=0.012",
            "target.radius=0.2",
            "target.thickness=0.3",
            "projectile.element_size=0.0065",
        ];
        overrides.extend_from_slice(extra);
        crate::scene::shipped_case("forrestal1994-277.toml", &overrides)
    }

    /// At rest: a particle deep in the block has a full kernel, one on the front face about
    /// half to three quarters of one (its own row counts whole). With a linear velocity field
    /// the corrected rate is the field's divergence everywhere, the face included; the
    /// conjugate one misreads the face (its normal part sees half a kernel).
    #[test]
    fn readings_are_one_inside_half_at_a_face_and_exact_for_a_linear_field() {
        let mut model = Simulation::new(&coarse(&[])).unwrap().into_model().unwrap();
        let sph = model.sph.unwrap();
        let p = &mut model.particles;
        // Off the axis and the side, deep inside; and the front face's particle at the same r.
        let nearest = |p: &crate::state::Particles, r: f32, z: f32| {
            (0..p.r.len())
                .min_by(|&i, &j| {
                    let d = |k: usize| (p.r[k] - r).powi(2) + (p.z[k] - z).powi(2);
                    d(i).total_cmp(&d(j))
                })
                .unwrap()
        };
        let inside = nearest(p, 0.1, -0.15);
        let face = nearest(p, 0.1, 0.0);
        let (a, b) = (30.0f32, -50.0f32);
        for i in 0..p.r.len() {
            p.vr[i] = a * p.r[i];
            p.vz[i] = b * p.z[i];
        }
        let mut grid = CellGrid::default();
        crate::cpu::neighbours::run(&mut grid, &p.r, &p.z, &sph.kernel);
        let k = kernel_readings(p, &grid, &sph, None, &[inside, face]);
        assert!((k[0].completeness - 1.0).abs() < 0.05, "{:?}", k[0]);
        assert!((0.5..0.8).contains(&k[1].completeness), "{:?}", k[1]);
        let div = 2.0 * a + b;
        for reading in &k {
            assert!(
                (reading.divergence_corrected / div - 1.0).abs() < 1e-3,
                "{reading:?} against {div}"
            );
        }
        assert!((k[0].divergence / div - 1.0).abs() < 0.05, "{:?}", k[0]);
        assert!((k[1].divergence / div - 1.0).abs() > 0.2, "{:?}", k[1]);
    }

    /// Once the nose is in: lining readings along the whole nose, within the band, the nose
    /// pushing into the concrete (positive normal speed) at the tip.
    #[test]
    fn the_buried_nose_is_lined() {
        let snapshots = study(&coarse(&[]), &[1.5e-4], 1.0).unwrap();
        let s = &snapshots[0];
        assert!(s.depth > 0.03, "{}", s.depth);
        assert!(s.lining.len() >= 5, "{:?}", s.lining);
        for l in &s.lining {
            assert!((0.0..=1.0).contains(&l.along), "{l:?}");
            assert!(l.distance <= 1.0 + 1e-6, "{l:?}");
            assert!(l.kernel.completeness.is_finite() && l.pressure.is_finite());
        }
        let tip = s.lining.iter().filter(|l| l.along < 0.2);
        assert!(tip.clone().count() > 0 && tip.clone().all(|l| l.normal_velocity > 0.0));
    }

    /// With wall images the readings count them: at one state, each particle with an image in
    /// its kernel reads a larger completeness and another step's rate than without its images,
    /// one without the same; the corrected rate, which reads the particles alone, the same.
    #[test]
    fn with_wall_images_the_readings_count_them() {
        let mut sim = Simulation::new(&coarse(&["contact.kernel=\"images\""])).unwrap();
        while sim.time() < 1.5e-4 {
            sim.step().unwrap();
        }
        let model = sim.model().unwrap();
        let (p, sph) = (&model.particles, model.sph.as_ref().unwrap());
        let walls = model
            .walls
            .found()
            .expect("the walls are found at every step");
        let mut grid = CellGrid::default();
        crate::cpu::neighbours::run(&mut grid, &p.r, &p.z, &sph.kernel);
        let which: Vec<usize> = (0..p.r.len()).filter(|&i| p.r[i] < 0.05).collect();
        let with = kernel_readings(p, &grid, sph, Some(walls), &which);
        let without = kernel_readings(p, &grid, sph, None, &which);
        let mut walled = 0;
        for ((&i, a), b) in which.iter().zip(&with).zip(&without) {
            assert_eq!(a.divergence_corrected, b.divergence_corrected);
            let mut images = 0;
            if walls[i].on() {
                walls[i].images(i, &p.r, &p.z, &grid, &sph.kernel, |im| {
                    images += usize::from(sph.kernel.w(im.dr.hypot(im.dz)) > 0.0);
                });
            }
            if images > 0 {
                walled += 1;
                assert!(a.completeness > b.completeness, "{a:?} against {b:?}");
                assert_ne!(a.divergence, b.divergence);
            } else {
                assert_eq!(a, b);
            }
        }
        assert!(walled > 0, "no particle has an image in its kernel");
    }

    /// The first row's push toward the nose: the concrete presses on the nose, the viscosity
    /// has a part in it while the nose drives the concrete aside, and none once it is off.
    #[test]
    fn the_viscosity_has_its_part_of_the_push() {
        let first_row = |extra: &[&str]| {
            let s = study(&coarse(extra), &[1.5e-4], 1.0).unwrap().remove(0);
            let row: Vec<_> = s.lining.into_iter().filter(|l| l.distance < 0.5).collect();
            assert!(!row.is_empty());
            row
        };
        let on = first_row(&[]);
        let push: f32 = on.iter().map(|l| l.push).sum();
        let viscous: f32 = on.iter().map(|l| l.viscous_push).sum();
        assert!(
            push > 0.0 && viscous > 0.0,
            "{push} N, of it viscous {viscous} N"
        );
        let off = first_row(&["target.viscosity_alpha=0", "target.viscosity_beta=0"]);
        assert!(off.iter().all(|l| l.viscous_push == 0.0));
        assert!(off.iter().map(|l| l.push).sum::<f32>() > 0.0);
    }

    /// The segments' normal impulses are the contact's: their axial parts add up to the nose's
    /// axial impulse (frictionless, so the hits push along the normals), and the bands' pressures
    /// over their areas and the window give the segments' impulse back. The law's band value is
    /// its own average.
    #[test]
    fn the_bands_carry_the_nose_impulse() {
        bands_carry_the_nose_impulse(&[]);
    }

    /// The same with wall images: the segments' impulses then count the images' reaction.
    #[test]
    fn with_wall_images_the_bands_carry_the_nose_impulse() {
        bands_carry_the_nose_impulse(&["contact.kernel=\"images\""]);
    }

    fn bands_carry_the_nose_impulse(extra: &[&str]) {
        let snapshots = study(&coarse(extra), &[1.0e-4, 1.5e-4], 1.0).unwrap();
        let (from, to) = (&snapshots[0], &snapshots[1]);
        assert!(!to.nose.is_empty() && to.nose.len() == from.nose.len());
        let axial: f64 = from
            .nose
            .iter()
            .zip(&to.nose)
            .map(|(a, b)| (b.impulse - a.impulse) * b.normal_z + b.drag - a.drag)
            .sum();
        let nose = to.nose_impulse - from.nose_impulse;
        assert!(nose > 0.0, "{nose}");
        // The normals turn a little as the nose deforms between the hits and the reading.
        assert!((axial / nose - 1.0).abs() < 0.01, "{axial} against {nose}");
        let edges = [0.0, 0.3, 0.6, 1.0];
        let bands = band_pressures(from, to, &edges, &|_, v| 1e6 * v);
        let window = to.time - from.time;
        let total: f64 = from
            .nose
            .iter()
            .zip(&to.nose)
            .map(|(a, b)| b.impulse - a.impulse)
            .sum();
        let mut from_bands = 0.0;
        for (k, b) in bands.iter().enumerate() {
            let area: f64 = to
                .nose
                .iter()
                .filter(|s| s.radius_ratio >= b.lo && (s.radius_ratio < b.hi || k == 2))
                .map(|s| s.ring_area)
                .sum();
            if area == 0.0 {
                // No segment's midpoint in the band (a long tip segment).
                assert!(b.pressure.is_nan() && b.share == 0.0, "{b:?}");
                continue;
            }
            from_bands += b.pressure * area * window;
            let speed = 0.5 * (from.speed + to.speed);
            assert!((b.law / (1e6 * speed) - 1.0).abs() < 1e-9, "{b:?}");
        }
        assert!(
            (from_bands / total - 1.0).abs() < 1e-9,
            "{from_bands} against {total}"
        );
        let shares: f64 = bands.iter().map(|b| b.share).sum();
        assert!((shares - 1.0).abs() < 1e-9, "{shares}");
    }
}
