//! `sph_forces`: particle accelerations, gathered over neighbours and axis ghosts
//! (physics.md §3): the symmetric planar pair term with per-radian-area masses m̃ = m/(2π r),
//! `a_i = Σ_j m̃_j [σ_i/ρ_i² + σ_j/ρ_j² − Π_ij I (+ R_ij f_ij^n)] · ∇_i W_ij`, plus the hoop
//! sources `a_r += (S_rr − S_θθ)/(ρ r)`, `a_z += S_rz/(ρ r)`. Monaghan–Gingold viscosity Π_ij
//! with its heating, Gray–Monaghan artificial stress R when enabled.
//!
//! The work-conjugate energy rate. With ring masses m = 2π r m̃ the pair term is a force
//! `2π r_i P_ij` on ring i, `P_ij = m̃_i m̃_j T_ij ∇_i W_ij = −P_ji`. The power of all forces,
//! `Σ_i m_i v_i·a_i`, is then `Σ_i [π Σ_j P_ij·(r_i v_i − r_j v_j) + m_i v_i·h_i]` (h the hoop
//! source), so `ė_i = −(r_i v_i·a_i^pair − Σ_j m̃_j r_j (T_ij ∇_i W_ij)·v_j)/(2 r_i) − v_i·h_i`
//! gives each particle half of each pair's work (Galilean invariant to the discretisation
//! error) and the particles together exactly what their motion lost. Viscosity and artificial
//! stress are in T and so in it. A mirror ghost enters with its mirrored velocity.

use rayon::prelude::*;

use super::neighbours::{for_each_neighbour, CellGrid};
use super::sph_rates::hoop_radius;
use crate::state::{Particles, SphParams};

/// η² of the viscosity's singularity guard, in units of h².
const ETA2: f32 = 0.01;

pub fn run(particles: &mut Particles, grid: &CellGrid, params: &SphParams) {
    let h = params.h;
    let kernel = &params.kernel;
    let support = kernel.support();
    let Particles {
        r,
        z,
        vr,
        vz,
        ar,
        az,
        rho,
        p,
        s_rr,
        s_zz,
        s_rz,
        s_tt,
        sound,
        de_visc,
        de_work,
        mu_visc,
        m_tilde,
        stress_rho2,
        art_stress,
        ..
    } = particles;
    let art_on = params.art_stress_eps > 0.0;
    stress_rho2
        .par_iter_mut()
        .zip(art_stress.par_iter_mut())
        .enumerate()
        .for_each(|(j, (sig, art))| {
            let inv = 1.0 / (rho[j] * rho[j]);
            *sig = [
                (s_rr[j] - p[j]) * inv,
                (s_zz[j] - p[j]) * inv,
                s_rz[j] * inv,
            ];
            if art_on {
                *art = artificial_stress(
                    params.art_stress_eps,
                    s_rr[j] - p[j],
                    s_zz[j] - p[j],
                    s_rz[j],
                    rho[j],
                );
            }
        });
    let (r, z, vr, vz, rho, s_rr, s_rz, s_tt, sound, m_tilde, sigma, art) = (
        &*r,
        &*z,
        &*vr,
        &*vz,
        &*rho,
        &*s_rr,
        &*s_rz,
        &*s_tt,
        &*sound,
        &*m_tilde,
        &*stress_rho2,
        &*art_stress,
    );
    ar.par_iter_mut()
        .zip(az.par_iter_mut())
        .zip(de_visc.par_iter_mut())
        .zip(de_work.par_iter_mut())
        .zip(mu_visc.par_iter_mut())
        .enumerate()
        .for_each(|(i, ((((ar, az), de), work), mu_out))| {
            let si = sigma[i];
            let ri_art = art[i];
            let mut acc = [0.0f32; 2];
            // Σ_j m̃_j r_j (T_ij ∇_i W_ij)·v_j, the neighbours' side of the pair work.
            let mut partner_power = 0.0f32;
            let mut heat = 0.0f32;
            let mut mu_max = 0.0f32;
            for_each_neighbour(grid, r, z, i, support, |nb| {
                let j = nb.j;
                let sign = if nb.mirror { -1.0 } else { 1.0 };
                let mj = m_tilde[j];
                let gw = kernel.grad(nb.dr, nb.dz, nb.dist);
                let sj = sigma[j];
                let mut t = [si[0] + sj[0], si[1] + sj[1], si[2] + sign * sj[2]];

                let dvr = vr[i] - sign * vr[j];
                let dvz = vz[i] - vz[j];
                let vx = dvr * nb.dr + dvz * nb.dz;
                if vx < 0.0 {
                    let mu = h * vx / (nb.dist * nb.dist + ETA2 * h * h);
                    let c_mean = 0.5 * (sound[i] + sound[j]);
                    let rho_mean = 0.5 * (rho[i] + rho[j]);
                    let pi = (-params.alpha * c_mean * mu + params.beta * mu * mu) / rho_mean;
                    t[0] -= pi;
                    t[1] -= pi;
                    heat += 0.5 * mj * pi * (dvr * gw[0] + dvz * gw[1]);
                    mu_max = mu_max.max(-mu);
                }
                if art_on {
                    let rj = art[j];
                    let f = (kernel.w(nb.dist) / params.w_spacing).powf(params.art_stress_n);
                    t[0] += f * (ri_art[0] + rj[0]);
                    t[1] += f * (ri_art[1] + rj[1]);
                    t[2] += f * (ri_art[2] + sign * rj[2]);
                }
                let pair = [
                    mj * (t[0] * gw[0] + t[2] * gw[1]),
                    mj * (t[2] * gw[0] + t[1] * gw[1]),
                ];
                acc[0] += pair[0];
                acc[1] += pair[1];
                partner_power += hoop_radius(r[j], h) * (pair[0] * sign * vr[j] + pair[1] * vz[j]);
            });
            let rr = hoop_radius(r[i], h);
            let hoop = [(s_rr[i] - s_tt[i]) / (rho[i] * rr), s_rz[i] / (rho[i] * rr)];
            let own_power = rr * (acc[0] * vr[i] + acc[1] * vz[i]);
            *work = -(own_power - partner_power) / (2.0 * rr) - (hoop[0] * vr[i] + hoop[1] * vz[i]);
            *ar = acc[0] + hoop[0];
            *az = acc[1] + hoop[1];
            *de = heat;
            *mu_out = mu_max;
        });
}

/// Gray–Monaghan (2001) artificial stress over ρ² in (rr, zz, rz): R = −ε σ'/ρ² on each
/// tensile principal stress σ' of the r–z plane, rotated back; zero for compression.
fn artificial_stress(eps: f32, srr: f32, szz: f32, srz: f32, rho: f32) -> [f32; 3] {
    let theta = 0.5 * (2.0 * srz).atan2(srr - szz);
    let (sn, cs) = theta.sin_cos();
    let s1 = cs * cs * srr + 2.0 * cs * sn * srz + sn * sn * szz;
    let s2 = sn * sn * srr - 2.0 * cs * sn * srz + cs * cs * szz;
    let inv = -eps / (rho * rho);
    let r1 = if s1 > 0.0 { inv * s1 } else { 0.0 };
    let r2 = if s2 > 0.0 { inv * s2 } else { 0.0 };
    [
        cs * cs * r1 + sn * sn * r2,
        sn * sn * r1 + cs * cs * r2,
        cs * sn * (r1 - r2),
    ]
}
