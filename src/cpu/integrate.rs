//! `integrate`: leapfrog velocities then positions (physics.md §5), the axis constraint and the
//! rigid wall. The stable step that sizes the next one is `timestep`.

use rayon::prelude::*;

use crate::state::{Nodes, Particles, SphParams};

/// Where a run went unstable.
#[derive(Clone, Debug, PartialEq)]
pub struct Blowup {
    pub what: &'static str,
    pub index: usize,
    pub r: f32,
    pub z: f32,
    pub reason: &'static str,
}

/// Advance particles over `dt`: v += a dt (zero for fixed particles), x += v dt, keep them
/// ≥ 0.1 h off the axis. Book the energy: `sph_forces`' work rate at the old velocities, less
/// the rest of the kinetic energy the step gave (½ a² Δt², and what the axis took), so that the
/// particles' energy changes by exactly what their kinetic energy did not. Fails on a
/// non-finite value or a particle beyond `escape` of the origin.
pub fn particles(
    p: &mut Particles,
    params: &SphParams,
    dt: f32,
    escape: f32,
) -> Result<(), Blowup> {
    let r_min = 0.1 * params.h;
    let Particles {
        r,
        z,
        vr,
        vz,
        ar,
        az,
        energy,
        de_work,
        fixed,
        ..
    } = p;
    let (ar, az, de_work, fixed) = (&*ar, &*az, &*de_work, &*fixed);
    let bad = r
        .par_iter_mut()
        .zip(z.par_iter_mut())
        .zip(vr.par_iter_mut())
        .zip(vz.par_iter_mut())
        .zip(energy.par_iter_mut())
        .enumerate()
        .map(|(i, ((((r, z), vr), vz), e))| {
            *e += dt * de_work[i];
            if fixed[i] != 0 {
                *vr = 0.0;
                *vz = 0.0;
                return None;
            }
            *vr += dt * ar[i];
            *vz += dt * az[i];
            *r += dt * *vr;
            *z += dt * *vz;
            let mut axis_lost = 0.0;
            if *r < r_min {
                *r = r_min;
                let kept = vr.max(0.0);
                axis_lost = 0.5 * (*vr * *vr - kept * kept);
                *vr = kept;
            }
            *e += axis_lost - 0.5 * dt * dt * (ar[i] * ar[i] + az[i] * az[i]);
            check("particle", i, *r, *z, *vr, *vz, escape)
        })
        .find_first(|b| b.is_some())
        .flatten();
    bad.map_or(Ok(()), Err)
}

/// Advance projectile nodes over `dt`: v += F/m dt, ṙ = 0 on the axis, x += v dt. The rigid
/// wall `wall_z` is a frictionless constraint: a node resting on it gets no force into it (the
/// wall's reaction), and a node arriving at it is put on it with its normal velocity removed (a
/// perfectly inelastic impact of that node); the kinetic energy so lost is returned (J).
pub fn nodes(n: &mut Nodes, dt: f32, wall_z: Option<f32>, escape: f32) -> Result<f64, Blowup> {
    let Nodes {
        r,
        z,
        vr,
        vz,
        fr,
        fz,
        mass,
        on_axis,
        ..
    } = n;
    let (fr, fz, mass, on_axis) = (&*fr, &*fz, &*mass, &*on_axis);
    let results: Vec<(f64, Option<Blowup>)> = r
        .par_iter_mut()
        .zip(z.par_iter_mut())
        .zip(vr.par_iter_mut())
        .zip(vz.par_iter_mut())
        .enumerate()
        .map(|(i, (((r, z), vr), vz))| {
            let inv_m = 1.0 / mass[i];
            *vr = if on_axis[i] != 0 {
                0.0
            } else {
                *vr + dt * fr[i] * inv_m
            };
            let resting = wall_z.is_some_and(|wz| *z <= wz);
            let f_z = if resting { fz[i].max(0.0) } else { fz[i] };
            *vz += dt * f_z * inv_m;
            *r += dt * *vr;
            *z += dt * *vz;
            let mut lost = 0.0;
            if let Some(wz) = wall_z {
                if *z < wz {
                    *z = wz;
                    if *vz < 0.0 {
                        lost = 0.5 * mass[i] as f64 * (*vz as f64).powi(2);
                        *vz = 0.0;
                    }
                }
            }
            (lost, check("node", i, *r, *z, *vr, *vz, escape))
        })
        .collect();
    let mut lost = 0.0;
    for (l, b) in results {
        if let Some(b) = b {
            return Err(b);
        }
        lost += l;
    }
    Ok(lost)
}

fn check(
    what: &'static str,
    index: usize,
    r: f32,
    z: f32,
    vr: f32,
    vz: f32,
    escape: f32,
) -> Option<Blowup> {
    if !(r.is_finite() && z.is_finite() && vr.is_finite() && vz.is_finite()) {
        return Some(Blowup {
            what,
            index,
            r,
            z,
            reason: "non-finite position or velocity",
        });
    }
    if r.abs() > escape || z.abs() > escape {
        return Some(Blowup {
            what,
            index,
            r,
            z,
            reason: "escaped far beyond the scene",
        });
    }
    None
}

/// Support radius of the kernel for a smoothing length.
pub fn support(params: &SphParams) -> f32 {
    params.kernel.support()
}
