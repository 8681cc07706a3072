//! `concrete`: per particle, the HJC update (physics.md §3.1) in the OpenRadioss LAW126 order:
//! density from continuity, EOS with crushing, trial deviator (Jaumann), strength with the new
//! pressure and the old damage, radial scaling, damage from Δε_p + Δμ_p; then the strain-power energy (`Particles::strain_energy`).

use rayon::prelude::*;

use super::deviator::{deviatoric_rate, equivalent_rate, jaumann_trial, von_mises};
use super::sph_rates::hoop_rate;
use crate::materials::hjc;
use crate::state::{Particles, SphParams};

/// The least density the continuity update may give a particle, as a share of the concrete's
/// reference density (WGSL twin: concrete.wgsl). A particle the update would take below it has
/// separated from its neighbours: it is held there and fails (D = 1), so it carries no stress.
/// Without the floor the conjugate gradient's density rate, whose in-plane part `−Σ_j m̃_j (v_j
/// − v_i)·∇W` does not shrink with ρ_i, carries a separating particle through zero to a
/// negative density; without the failure an undamaged particle held there keeps the tension
/// cut-off −T, which its neighbours feel as σ/ρ², 10⁴ times what it would be at the
/// reference density (docs/physics.md §3.1).
pub const MIN_DENSITY_RATIO: f32 = 0.01;

/// The density floor of concrete `c` (kg/m³): [`MIN_DENSITY_RATIO`] of its reference density.
pub fn density_floor(c: &hjc::Hjc) -> f32 {
    MIN_DENSITY_RATIO * c.density
}

pub fn run(particles: &mut Particles, params: &SphParams, dt: f32) {
    let c = &params.concrete;
    let Particles {
        r,
        vr,
        rho,
        strain_energy,
        p,
        s_rr,
        s_zz,
        s_rz,
        s_tt,
        damage,
        mu_max,
        eps_p,
        sound,
        l_rr,
        l_rz,
        l_zr,
        l_zz,
        drho,
        de_visc,
        hoop_weight,
        ..
    } = particles;
    let (r, vr, l_rr, l_rz, l_zr, l_zz, drho, de_visc, hoop_weight) = (
        &*r,
        &*vr,
        &*l_rr,
        &*l_rz,
        &*l_zr,
        &*l_zz,
        &*drho,
        &*de_visc,
        &*hoop_weight,
    );
    let floor = density_floor(c);
    let mu_plock = hjc::lock_strain(c);
    rho.par_iter_mut()
        .zip(strain_energy.par_iter_mut())
        .zip(p.par_iter_mut())
        .zip(s_rr.par_iter_mut())
        .zip(s_zz.par_iter_mut())
        .zip(s_rz.par_iter_mut())
        .zip(s_tt.par_iter_mut())
        .zip(damage.par_iter_mut())
        .zip(mu_max.par_iter_mut())
        .zip(eps_p.par_iter_mut())
        .zip(sound.par_iter_mut())
        .enumerate()
        .for_each(
            |(i, ((((((((((rho, e), p), srr), szz), srz), stt), dmg), mmax), ep), snd))| {
                let d_tt = hoop_rate(params, hoop_weight[i], vr[i], r[i]);
                let d_rr = l_rr[i];
                let d_zz = l_zz[i];
                let d_rz = 0.5 * (l_rz[i] + l_zr[i]);
                let spin = 0.5 * (l_rz[i] - l_zr[i]);
                let old_power = (*srr - *p) * d_rr
                    + (*szz - *p) * d_zz
                    + 2.0 * *srz * d_rz
                    + (*stt - *p) * d_tt;

                let continuity = *rho + dt * drho[i];
                if continuity < floor {
                    *dmg = 1.0;
                }
                *rho = continuity.max(floor);
                let mu = *rho / c.density - 1.0;
                let eos = hjc::pressure(c, mu_plock, mu, *mmax, *dmg);
                *mmax = eos.mu_max;
                *p = eos.p;

                let (dev, _) = deviatoric_rate(d_rr, d_zz, d_rz, d_tt);
                let g = c.shear_modulus;
                let mut s = jaumann_trial([*srr, *szz, *srz, *stt], dev, spin, g, dt);
                let eq_rate = equivalent_rate(&dev);
                let seq = von_mises(&s);
                let sy = hjc::yield_stress(c, eos.p, *dmg, eq_rate);
                let mut d_eps_p = 0.0;
                if seq > sy {
                    let scale = if seq > 0.0 { sy / seq } else { 0.0 };
                    for v in &mut s {
                        *v *= scale;
                    }
                    d_eps_p = (seq - sy) / (3.0 * g);
                }
                *ep += d_eps_p;
                *dmg = (*dmg + hjc::damage_increment(c, eos.p, d_eps_p, eos.d_mu_p)).min(1.0);
                *srr = s[0];
                *szz = s[1];
                *srz = s[2];
                *stt = s[3];
                *snd = hjc::sound_speed(c, eos.tangent);

                // ė = σ:ε̇/ρ (θθ included), trapezoidal in the stress, plus viscous heating: the
                // diagnostic estimate; the account's energy is booked by `integrate`.
                let new_power = (s[0] - eos.p) * d_rr
                    + (s[1] - eos.p) * d_zz
                    + 2.0 * s[2] * d_rz
                    + (s[3] - eos.p) * d_tt;
                *e += dt * (0.5 * (old_power + new_power) / *rho + de_visc[i]);
            },
        );
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::concrete::tests::{smoke, SMOKE_STEPS};

    /// A particle whose continuity step would remove three times its density (a separating
    /// particle under the conjugate gradient) is held at the floor, positive, failed and free
    /// of stress; every other particle's density takes the plain continuity step.
    #[test]
    fn a_separating_particle_keeps_a_positive_density() {
        let mut sim = smoke(SMOKE_STEPS, &[]);
        let sph = sim.sph.expect("smoke has a target");
        let dt = sim.dt;
        let before = sim.particles.clone();
        let k = before.len() / 2;
        sim.particles.drho[k] = -3.0 * before.rho[k] / dt;
        run(&mut sim.particles, &sph, dt);
        let after = &sim.particles;
        let floor = density_floor(&sph.concrete);
        assert!(floor > 0.0);
        assert_eq!(after.rho[k], floor, "held particle");
        assert!(after.p[k].is_finite() && after.strain_energy[k].is_finite());
        assert_eq!(after.damage[k], 1.0, "a held particle fails");
        let stress = [
            after.p[k],
            after.s_rr[k],
            after.s_zz[k],
            after.s_rz[k],
            after.s_tt[k],
        ];
        // Zero to round-off against the stress it held at the tension cut-off.
        let tol = 1.0e-6 * sph.concrete.t;
        assert!(
            stress.iter().all(|&x| x.abs() <= tol),
            "held particle's stress {stress:?}"
        );
        for i in (0..after.len()).filter(|&i| i != k) {
            assert_eq!(
                after.rho[i],
                before.rho[i] + dt * before.drho[i],
                "particle {i}"
            );
        }
    }
}
