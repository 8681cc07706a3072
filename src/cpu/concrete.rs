//! `concrete`: per particle, the HJC update (physics.md §3.1) in the OpenRadioss LAW126 order:
//! density from continuity, EOS with crushing, trial deviator (Jaumann), strength with the new
//! pressure and the old damage, radial scaling, damage from Δε_p + Δμ_p (in tension, with the
//! crack band, Δε_p + the crack's opening); then the strain-power energy
//! (`Particles::strain_energy`).

use rayon::prelude::*;

use super::deviator::{
    deviatoric_rate, equivalent_rate, jaumann_trial, largest_principal_rate, von_mises,
};
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
                let rho_old = *rho;
                *rho = continuity.max(floor);
                let mu = *rho / c.density - 1.0;
                let t_d = hjc::tensile_strength(
                    c,
                    params.tension,
                    largest_principal_rate(d_rr, d_zz, d_rz, d_tt),
                );
                let eos = hjc::pressure(c, mu_plock, mu, *mmax, *dmg, t_d);
                *mmax = eos.mu_max;
                *p = eos.p;

                let (dev, _) = deviatoric_rate(d_rr, d_zz, d_rz, d_tt);
                let g = c.shear_modulus;
                let mut s = jaumann_trial([*srr, *szz, *srz, *stt], dev, spin, g, dt);
                let eq_rate = equivalent_rate(&dev);
                let seq = von_mises(&s);
                let sy = hjc::yield_stress(c, eos.p, *dmg, eq_rate, t_d);
                let mut d_eps_p = 0.0;
                if seq > sy {
                    let scale = if seq > 0.0 { sy / seq } else { 0.0 };
                    for v in &mut s {
                        *v *= scale;
                    }
                    d_eps_p = (seq - sy) / (3.0 * g);
                }
                *ep += d_eps_p;
                let d_open = crack_opening(eos.p, t_d, *dmg, rho_old, *rho);
                let d_dmg = hjc::damage_increment(
                    c,
                    params.tension,
                    eos.p,
                    t_d,
                    d_eps_p,
                    eos.d_mu_p,
                    d_open,
                );
                *dmg = (*dmg + d_dmg).min(1.0);
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

/// The crack's opening in this step: the volumetric expansion (ρ_old − ρ)/ρ of a particle held
/// at the tension cut-off −T_d(1 − D), 0 elsewhere (WGSL twin: concrete.wgsl).
fn crack_opening(p: f32, t_d: f32, damage: f32, rho_old: f32, rho: f32) -> f32 {
    let cut = -t_d * (1.0 - damage);
    if cut < 0.0 && p <= cut {
        ((rho_old - rho) / rho).max(0.0)
    } else {
        0.0
    }
}

/// A material point of the concrete strained at constant principal rates until it fails.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PullApart {
    /// The work spent on it per unit volume to failure, ∫ σ:D dt (J/m³).
    pub work: f64,
    /// The largest tension it held, −p (Pa).
    pub peak_tension: f32,
}

/// Strains one particle of `params`' concrete, from rest, at the constant principal rates
/// `rates` = (rr, zz, θθ) (1/s, at least one positive) through this module's update, until it
/// fails (D = 1) or has expanded by half its volume (`None`: it holds its tension, as HJC's
/// static cut-off does under an opening without shear). Each step strains it by 1/200 of the
/// smaller of the elastic strain at the cut-off and the crack band's failure strain, so the
/// softening is resolved. For the crack band's fracture work (physics.md §3.1, "Tension").
pub fn pull_apart(params: &SphParams, rates: [f32; 3]) -> Option<PullApart> {
    let c = &params.concrete;
    let lattice = crate::mesh::TargetLattice {
        r: vec![1.0],
        z: vec![0.0],
        mass: vec![1.0],
        rear: vec![false],
        lateral: vec![false],
        site: vec![0],
    };
    let mut ps = Particles::at_rest(&lattice, c, vec![0]);
    let [rr, zz, tt] = rates;
    let (vol, largest) = (rr + zz + tt, rr.max(zz).max(tt));
    if vol <= 0.0 || largest <= 0.0 {
        return None;
    }
    // A hoop rate θθ at r = 1 is v_r; the hoop weight is 1, so either gradient reads it.
    (ps.l_rr[0], ps.l_zz[0], ps.vr[0]) = (rr, zz, tt);
    let t_d = hjc::tensile_strength(c, params.tension, largest);
    let elastic = t_d / (c.p_crush / c.mu_crush);
    let step_strain = match params.tension {
        hjc::Tension::CrackBand { band } => elastic.min(hjc::crack_failure_strain(c, t_d, band)),
        hjc::Tension::Static => elastic.min(c.ef_min),
    } / 200.0;
    let dt = step_strain / vol;
    let (mut work, mut peak) = (0.0f64, 0.0f32);
    let power = |ps: &Particles| {
        f64::from(
            (ps.s_rr[0] - ps.p[0]) * rr + (ps.s_zz[0] - ps.p[0]) * zz + (ps.s_tt[0] - ps.p[0]) * tt,
        )
    };
    while ps.rho[0] > 0.5 * c.density {
        let before = power(&ps);
        ps.drho[0] = -vol * ps.rho[0];
        run(&mut ps, params, dt);
        work += f64::from(dt) * 0.5 * (before + power(&ps));
        peak = peak.max(-ps.p[0]);
        if ps.damage[0] >= 1.0 {
            return Some(PullApart {
                work,
                peak_tension: peak,
            });
        }
    }
    None
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

    /// A crack band spends the fracture energy per unit crack area whatever its width: pulled
    /// apart at 100/s, a particle holds T times the rate factor, then softens, and the work
    /// per unit volume times the band, less the elastic energy T_d²/(2K_el) stored before the
    /// crack opens, is G_f within 2 % for bands of 2 and 8 mm (four times apart).
    #[test]
    fn a_crack_band_spends_the_fracture_energy_whatever_its_width() {
        let sim = smoke(0, &[]);
        let base = sim.sph.expect("smoke has a target");
        let rate = 100.0;
        let c = base.concrete;
        let t_d = c.t * hjc::tensile_rate_factor(rate);
        let k_el = c.p_crush / c.mu_crush;
        for band in [0.002, 0.008] {
            let sph = SphParams {
                tension: hjc::Tension::CrackBand { band },
                ..base
            };
            let PullApart {
                work,
                peak_tension: peak,
            } = pull_apart(&sph, [rate; 3]).expect("the crack band fails");
            assert!(
                (peak / t_d - 1.0).abs() < 1.0e-3,
                "band {band}: peak tension {peak} against T_d {t_d}"
            );
            let elastic = f64::from(t_d * t_d / (2.0 * k_el));
            let spent = (work - elastic) * f64::from(band);
            let g_f = f64::from(c.g_f);
            eprintln!("band {band} m: fracture work {spent:.2} J/m² against G_f {g_f:.2}");
            assert!(
                (spent / g_f - 1.0).abs() < 0.02,
                "band {band}: {spent} J/m² against G_f {g_f}"
            );
        }
    }

    /// The static cut-off of HJC as published holds −T and takes no damage from an opening
    /// without shear: the particle never fails, and it does under uniaxial strain, where the
    /// deviator's plastic strain damages it.
    #[test]
    fn the_static_cut_off_does_not_soften_without_shear() {
        let sim = smoke(0, &[]);
        let sph = SphParams {
            tension: hjc::Tension::Static,
            ..sim.sph.expect("smoke has a target")
        };
        assert_eq!(pull_apart(&sph, [100.0; 3]), None);
        // Shear damage lowers the cut-off −T(1 − D) before the tension reaches T.
        let uniaxial = pull_apart(&sph, [0.0, 100.0, 0.0]).expect("fails in shear");
        assert!(
            uniaxial.peak_tension > 0.0 && uniaxial.peak_tension <= sph.concrete.t,
            "{uniaxial:?}"
        );
    }
}
