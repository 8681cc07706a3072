//! The concrete lining the projectile's nose: how much of each lining particle's kernel is
//! filled, and how much of the volumetric rate the nose imposes its gradient reads (issue: a
//! kernel cut by the projectile, which has no particles, may under-read the compaction a
//! slender nose makes by pushing material sideways; docs/physics.md §3).
//!
//! A particle lines the nose when its nearest point on the nose's master segments is within a
//! band of the surface and it is not behind it. For each such particle: where along the nose
//! it sits, the nose's normal velocity there, its pressure, and [`KernelReading`] — the kernel
//! completeness and the volumetric rate as the step takes it and as a first-order consistent
//! (corrected) gradient gives it from the same velocities.

use crate::cpu::sph_rates::{kernel_readings, KernelReading};
use crate::scene::Scene;
use crate::solver::{Model, RunError, Simulation};

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
}

/// The particles lining the nose of `model` within `band` smoothing lengths of its surface.
pub fn lining(model: &Model, band: f32) -> Vec<Lining> {
    let Some(sph) = model.sph.as_ref() else {
        return vec![];
    };
    let h = sph.h;
    let n = &model.projectile.nodes;
    let nose: Vec<_> = model
        .projectile
        .masters
        .iter()
        .zip(model.on_nose())
        .filter(|(_, &on)| on)
        .map(|(m, _)| (m.a as usize, m.b as usize))
        .collect();
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
    for i in 0..p.r.len() {
        let (r, z) = (p.r[i], p.z[i]);
        if z < tip - reach || z > shoulder + reach || r > shank_radius + reach {
            continue;
        }
        // The nearest point on the nose: (distance², signed distance, foot's z, normal speed).
        let mut best: Option<(f32, f32, f32, f32)> = None;
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
            best = Some((d2, signed, fz, vr * nr + vz * nz));
        }
        let Some((d2, signed, foot_z, normal_velocity)) = best else {
            continue;
        };
        // Not behind the surface by more than a contact's tolerance, and within the band.
        if signed < -0.25 * h || d2 > reach * reach {
            continue;
        }
        which.push(i);
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
        });
    }
    for (l, k) in found.iter_mut().zip(kernel_readings(p, sph, &which)) {
        l.kernel = k;
    }
    found
}

/// Runs `scene` on the CPU path and reads the lining at each of `times` (s, ascending) once the
/// run has passed it: the readings, each with the time and the nose's depth below the face.
pub fn study(scene: &Scene, times: &[f64], band: f32) -> Result<Vec<Snapshot>, RunError> {
    let mut sim = Simulation::new(scene)?;
    let mut out = Vec::new();
    for &t in times {
        while sim.time() < t {
            sim.step()?;
        }
        let model = sim.model()?;
        let tip = model
            .projectile
            .nodes
            .z
            .iter()
            .fold(f32::MAX, |a, &b| a.min(b));
        out.push(Snapshot {
            time: model.time,
            depth: -tip as f64,
            lining: lining(model, band),
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
    pub lining: Vec<Lining>,
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
        let k = kernel_readings(p, &sph, &[inside, face]);
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
}
