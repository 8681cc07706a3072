//! `sph_forces`: particle accelerations, gathered over neighbours and axis ghosts
//! (physics.md §3), in the momentum-conserving ring-mass form (docs/physics.md §3). With ring
//! masses m = 2π r m̃ the force on ring i from ring j is
//! `F_ij = 2π m̃_i m̃_j [w_i σ_i/ρ_i² + w_j σ_j/ρ_j² − r̄_ij Π_ij I (+ artificial stress)] · ∇_i W_ij`,
//! with `w = r` for a neighbour and `w = −r` on both sides for a mirror ghost, and
//! `r̄_ij = (r_i + r_j)/2`. F_ij = −F_ji between neighbours, and between i and j's ghost it is
//! the mirror image of the force between j and i's ghost with its axial part reversed, so the
//! axial momentum Σ m v_z is conserved to round-off. The acceleration is `F/m`; the pair part is
//! `∇·σ/ρ` in the plane plus `σ·e_r/(ρ r)`, so the only hoop source left is
//! `a_r += −σ_θθ/(ρ r) · n_i` with `n_i = Σ_j m̃_j (w_i + w_j − 2 r_i) ∂_r W_ij / ρ_i` (≈ 1;
//! `Particles::hoop_weight`, gathered by `sph_rates` at the same positions).
//! For a uniform stress the pair part is `σ n_i/(ρ r) + 2 σ Σ_j m̃_j ∂_r W_ij / ρ²`: the first
//! term is the `σ·e_r/(ρ r)` the hoop source balances, so a uniform pressure exerts no force
//! where the support is full (the interior, and next to the axis with its ghosts); the second
//! is zero there and, at a free face normal to r (the lateral face, a crater's wall), the push
//! of the particle's own stress against the empty side, the same as the plane's sum gives at a
//! face normal to z. Weighted by `w_i + w_j` alone, the hoop source cancelled that push, and a
//! surface particle's excess pressure pulled it toward its neighbours (the stability suite's
//! `grazing` scene: docs/notes/2026-11-stability-suite.md).
//!
//! Why these ghost weights: `w_j = −r_j` (r σ is odd across the axis) keeps `∂σ_zz/∂z`
//! consistent on the first rows (`w_j = +r_j` would make it 67 % too strong on the first row);
//! conservation then forces the same sign on i's own term. The price: a linear `σ_rz` gives
//! `(1/r)∂(r σ_rz)/∂r` 21 % too strong on the first row and 15 % on the second, exact beyond
//! (tests/sph.rs checks it), and a smooth `σ_rr(r)` carries an error of order `h²/r²` relative
//! to `∂σ_rr/∂r` near the axis. r is `hoop_radius(r)` throughout, as in m̃.
//!
//! The work-conjugate energy rate: the pair forces do work `Σ_i F_i·v_i = ½ Σ_ij F_ij·(v_i − v_j)`
//! (a ghost pair and its mirror image included), so `m_i ė_i = −½ Σ_j F_ij·(v_i − v_j) − m_i h_i·v_i`
//! (h the hoop source) gives each particle half of each pair's work, Galilean invariant, and
//! the particles together exactly what their motion lost. Viscosity and artificial stress are
//! in the bracket and so in it. A mirror ghost enters with its mirrored velocity.
//!
//! With the Balsara switch each pair's Π is scaled by the mean of the two particles' factors
//! (`visc_switch`, from `sph_rates`); the pair stays symmetric, so the conservation above holds.
//! `mu_visc`, which the time step reads, is the unscaled μ: the step does not grow where the
//! switch turns the viscosity off.
//!
//! With `target.viscosity_jump = "reconstructed"` Π reads, instead of the pair's approach
//! `(v_i − v_j)·(x_i − x_j)`, what is left of it at the pair's midpoint once each end's
//! velocity is carried there along its own corrected gradient (`l_visc`), the slopes limited
//! ([`reconstructed_jump`]; docs/physics.md §3): a smooth compression, such as the concrete
//! ahead of a nose being brought up to its speed over a spacing or two, is not read as a
//! shock. The pair stays symmetric and `mu_visc` is still the raw μ.

use rayon::prelude::*;

use super::neighbours::CellGrid;
use super::wall::Wall;

const TWO_PI: f32 = 2.0 * std::f32::consts::PI;
use super::sph_rates::hoop_radius;
use crate::state::{Particles, SphParams};

/// η² of the viscosity's singularity guard, in units of h².
pub(crate) const ETA2: f32 = 0.01;

/// What the gather reads of each particle's own state: σ/ρ² and, when it is on, the artificial
/// stress R (the GPU writes them at the end of `concrete`, with the state).
pub fn prologue(particles: &mut Particles, params: &SphParams) {
    let Particles {
        rho,
        p,
        s_rr,
        s_zz,
        s_rz,
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
}

/// Particle accelerations, the viscous heating, the largest μ of each particle's pairs and the
/// work-conjugate energy rate, after `prologue`; and the ring force (N) each particle's wall
/// images exert on it (`wall`), zero where it has none and empty without `walls`.
pub fn run(
    particles: &mut Particles,
    grid: &CellGrid,
    params: &SphParams,
    walls: Option<&[Wall]>,
) -> Vec<[f32; 2]> {
    prologue(particles, params);
    let h = params.h;
    let kernel = &params.kernel;
    let Particles {
        r,
        z,
        vr,
        vz,
        ar,
        az,
        rho,
        p,
        s_tt,
        sound,
        de_visc,
        de_work,
        mu_visc,
        visc_switch,
        m_tilde,
        hoop_weight,
        l_visc,
        stress_rho2,
        art_stress,
        ..
    } = particles;
    let l_visc = &*l_visc;
    let (r, z, vr, vz, rho, p, s_tt, sound, visc_switch, m_tilde, hoop_weight, sigma, art) = (
        &*r,
        &*z,
        &*vr,
        &*vz,
        &*rho,
        &*p,
        &*s_tt,
        &*sound,
        &*visc_switch,
        &*m_tilde,
        &*hoop_weight,
        &*stress_rho2,
        &*art_stress,
    );
    let fields = Fields {
        vr,
        vz,
        sound,
        rho,
        visc_switch,
        m_tilde,
        l_visc,
    };
    let particle = ar
        .par_iter_mut()
        .zip(az.par_iter_mut())
        .zip(de_visc.par_iter_mut())
        .zip(de_work.par_iter_mut())
        .zip(mu_visc.par_iter_mut())
        .enumerate()
        .map(|(i, ((((ar, az), de), work), mu_out))| {
            let mut react = [0.0f32; 2];
            let own = Own {
                i,
                s: sigma[i],
                art: art[i],
                r: hoop_radius(r[i], h),
            };
            let ri = own.r;
            let mut acc = [0.0f32; 2];
            let mut pair_power = 0.0f32;
            let mut sums = PairSums::default();
            for nb in grid.neighbours(i) {
                let j = nb.j();
                let sign = if nb.mirror() { -1.0 } else { 1.0 };
                let rj = hoop_radius(r[j], h);
                let sj = sigma[j];
                // w = ±r: a mirror ghost pair is weighted −r on both sides; the ghost's shear
                // stress and radial velocity change sign.
                let (pair, dvr, dvz) = pair_term(
                    params,
                    &fields,
                    &own,
                    Partner {
                        j,
                        dr: nb.dr,
                        dz: nb.dz,
                        dist: nb.dist,
                        gw: nb.grad(),
                        s: [sj[0], sj[1], sign * sj[2]],
                        w_i: sign * ri,
                        w_j: sign * rj,
                        r: rj,
                        v: [sign * vr[j], vz[j]],
                    },
                    || {
                        let a = art[j];
                        [a[0], a[1], sign * a[2]]
                    },
                    || mirrored(l_visc[j], sign),
                    &mut sums,
                );
                acc[0] += pair[0];
                acc[1] += pair[1];
                pair_power += pair[0] * dvr + pair[1] * dvz;
            }
            if let Some(wall) = walls.map(|w| w[i]).filter(|w| w.on()) {
                let mut image_acc = [0.0f32; 2];
                wall.images(i, r, z, grid, kernel, |im| {
                    let j = im.j;
                    let rg = hoop_radius(im.r, h);
                    let (vrg, vzg) = wall.velocity(vr[j], vz[j]);
                    // w = r on both sides; the image carries its source's stress reflected.
                    let (pair, _, _) = pair_term(
                        params,
                        &fields,
                        &own,
                        Partner {
                            j,
                            dr: im.dr,
                            dz: im.dz,
                            dist: im.dist,
                            gw: im.grad,
                            s: wall.tensor(sigma[j]),
                            w_i: ri,
                            w_j: rg,
                            r: rg,
                            v: [vrg, vzg],
                        },
                        || wall.tensor(art[j]),
                        || wall.gradient(l_visc[j]),
                        &mut sums,
                    );
                    image_acc[0] += pair[0];
                    image_acc[1] += pair[1];
                });
                // The wall takes no heat: the particle books the images' whole work relative to
                // the wall, which is what they and the projectile exchange (`wall`).
                let (ur, uz) = (vr[i] - wall.vr, vz[i] - wall.vz);
                pair_power += 2.0 * (image_acc[0] * ur + image_acc[1] * uz);
                acc[0] += image_acc[0];
                acc[1] += image_acc[1];
                // The ring force is m a = 2π m̃_i · acc (a = acc/r_i).
                let ring = TWO_PI * m_tilde[i];
                react = [ring * image_acc[0], ring * image_acc[1]];
            }
            let hoop_r = -(s_tt[i] - p[i]) * hoop_weight[i] / (rho[i] * ri);
            *work = -pair_power / (2.0 * ri) - hoop_r * vr[i];
            *ar = acc[0] / ri + hoop_r;
            *az = acc[1] / ri;
            *de = sums.heat;
            *mu_out = sums.mu_max;
            react
        });
    // The ring forces are kept only where there are walls to take them.
    let mut reaction = Vec::new();
    match walls {
        Some(_) => particle.collect_into_vec(&mut reaction),
        None => particle.for_each(drop),
    }
    reaction
}

/// The fields the pair term reads of both particles of a pair.
struct Fields<'a> {
    vr: &'a [f32],
    vz: &'a [f32],
    sound: &'a [f32],
    rho: &'a [f32],
    visc_switch: &'a [f32],
    m_tilde: &'a [f32],
    l_visc: &'a [[f32; 4]],
}

/// What the pair term reads of the gathering particle i: its (σ_rr, σ_zz, σ_rz)/ρ², artificial
/// stress and radius.
struct Own {
    i: usize,
    s: [f32; 3],
    art: [f32; 3],
    r: f32,
}

/// Particle i's sums over its pairs besides the force: the largest μ (for the time step) and
/// the viscous heating.
#[derive(Default)]
struct PairSums {
    mu_max: f32,
    heat: f32,
}

/// One pair's term, a neighbour's (or its axis ghost's) or an image's: the partner as the pair
/// sees it (`Partner`), its artificial stress and velocity gradient in the same frame, asked for
/// only where they are used. Returns the pair's acceleration term and v_i − v_j. A function
/// inlined by force rather than a closure: called from the neighbour and the image loops, the
/// closure was left out of line, a call per pair that made the step a quarter slower.
#[inline(always)]
fn pair_term(
    params: &SphParams,
    f: &Fields,
    own: &Own,
    q: Partner,
    art_j: impl FnOnce() -> [f32; 3],
    l_j: impl FnOnce() -> [f32; 4],
    sums: &mut PairSums,
) -> ([f32; 2], f32, f32) {
    let (i, h, si, ri) = (own.i, params.h, own.s, own.r);
    let (j, gw, mj) = (q.j, q.gw, f.m_tilde[q.j]);
    let (wi, wj) = (q.w_i, q.w_j);
    let mut t = [
        wi * si[0] + wj * q.s[0],
        wi * si[1] + wj * q.s[1],
        wi * si[2] + wj * q.s[2],
    ];
    let (dvr, dvz) = (f.vr[i] - q.v[0], f.vz[i] - q.v[1]);
    let vx = dvr * q.dr + dvz * q.dz;
    if vx < 0.0 {
        // The time step allows for the raw jump.
        sums.mu_max = sums.mu_max.max(-h * vx / (q.dist * q.dist + ETA2 * h * h));
    }
    let jump = if params.reconstruct_viscosity && vx < 0.0 {
        reconstructed_jump(vx, [q.dr, q.dz], f.l_visc[i], l_j())
    } else {
        vx
    };
    if jump < 0.0 {
        let mu = h * jump / (q.dist * q.dist + ETA2 * h * h);
        let c_mean = 0.5 * (f.sound[i] + f.sound[j]);
        let rho_mean = 0.5 * (f.rho[i] + f.rho[j]);
        let mut pi =
            0.5 * (ri + q.r) * (-params.alpha * c_mean * mu + params.beta * mu * mu) / rho_mean;
        if params.balsara {
            pi *= 0.5 * (f.visc_switch[i] + f.visc_switch[j]);
        }
        t[0] -= pi;
        t[1] -= pi;
        sums.heat += 0.5 * mj * pi * (dvr * gw[0] + dvz * gw[1]) / ri;
    }
    if params.art_stress_eps > 0.0 {
        let (ri_art, rj_art) = (own.art, art_j());
        let f_n = (params.kernel.w(q.dist) / params.w_spacing).powf(params.art_stress_n);
        t[0] += f_n * (wi * ri_art[0] + wj * rj_art[0]);
        t[1] += f_n * (wi * ri_art[1] + wj * rj_art[1]);
        t[2] += f_n * (wi * ri_art[2] + wj * rj_art[2]);
    }
    let pair = [
        mj * (t[0] * gw[0] + t[2] * gw[1]),
        mj * (t[2] * gw[0] + t[1] * gw[1]),
    ];
    (pair, dvr, dvz)
}

/// A pair's partner as the pair sees it: `j`, the separation x_i − x_j, its length and ∇_i W,
/// j's (σ_rr, σ_zz, σ_rz)/ρ² in the pair's frame, the ring weights w_i and w_j, j's radius
/// in the viscosity's mean and its velocity in the pair's frame.
struct Partner {
    j: usize,
    dr: f32,
    dz: f32,
    dist: f32,
    gw: [f32; 2],
    s: [f32; 3],
    w_i: f32,
    w_j: f32,
    r: f32,
    v: [f32; 2],
}

/// A velocity gradient (rr, rz, zr, zz) as a mirror ghost across the axis has it (`sign` −1):
/// `∂v_r/∂z` and `∂v_z/∂r` change sign.
#[inline]
pub(crate) fn mirrored(l: [f32; 4], sign: f32) -> [f32; 4] {
    [l[0], sign * l[1], sign * l[2], l[3]]
}

/// The approach `vx = (v_i − v_j)·x` (< 0) of a pair at separation `x = x_i − x_j` that is left
/// at the pair's midpoint once each end's velocity is carried there along its own gradient:
/// `vx − ½ φ (q_i + q_j)` with `q = x·(L x)` each end's slope along the pair and φ van Leer's
/// limiter of their ratio, `4r/(1 + r)²` (0 where the slopes disagree in sign: an extremum
/// keeps the raw jump). Frontiere, Raskin & Owen (2017); docs/physics.md §3. Never more
/// negative than `vx`, and 0 (no viscosity) where the reconstruction leaves no approach: a
/// linear field's pairs read none, a jump between uniform states all of it.
#[inline]
pub(crate) fn reconstructed_jump(vx: f32, x: [f32; 2], l_i: [f32; 4], l_j: [f32; 4]) -> f32 {
    let slope =
        |l: [f32; 4]| x[0] * (l[0] * x[0] + l[1] * x[1]) + x[1] * (l[2] * x[0] + l[3] * x[1]);
    let (qi, qj) = (slope(l_i), slope(l_j));
    let ratio = if qj != 0.0 { qi / qj } else { 0.0 };
    let phi = if ratio > 0.0 {
        (4.0 * ratio / ((1.0 + ratio) * (1.0 + ratio))).min(1.0)
    } else {
        0.0
    };
    let left = vx - 0.5 * phi * (qi + qj);
    if left < 0.0 {
        left.max(vx)
    } else {
        0.0
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// `reconstructed_jump` on a pair at separation x: a linear field's approach is wholly
    /// carried by the slopes; flat ends keep the whole jump, as do ends sloping opposite ways
    /// (an extremum); unequal slopes of one sign keep part; the result lies in [vx, 0].
    #[test]
    fn reconstructed_jump_limits() {
        let x = [0.6e-3f32, -1.1e-3];
        let l = [-2.0e3f32, 0.5e3, 0.3e3, -4.0e3];
        let v = [l[0] * x[0] + l[1] * x[1], l[2] * x[0] + l[3] * x[1]];
        let vx = v[0] * x[0] + v[1] * x[1];
        assert!(vx < 0.0);
        assert_eq!(reconstructed_jump(vx, x, l, l), 0.0);
        assert_eq!(reconstructed_jump(vx, x, [0.0; 4], [0.0; 4]), vx);
        let negated = l.map(|a| -a);
        assert_eq!(reconstructed_jump(vx, x, l, negated), vx);
        let half = l.map(|a| 0.5 * a);
        let part = reconstructed_jump(2.0 * vx, x, l, half);
        // r = 2: φ = 8/9, so the jump left is 2vx − (8/9)(3/4)vx = (4/3)vx.
        assert!((part / vx - 4.0 / 3.0).abs() < 1e-5, "{}", part / vx);
        for scale in [0.1f32, 1.0, 3.0, 30.0] {
            let j = reconstructed_jump(scale * vx, x, l, half);
            assert!(j >= scale * vx && j <= 0.0, "{scale}: {j}");
        }
    }

    /// A mirror ghost's gradient: the shears change sign, the normal rates do not.
    #[test]
    fn mirrored_gradient_flips_the_shears() {
        assert_eq!(mirrored([1.0, 2.0, 3.0, 4.0], -1.0), [1.0, -2.0, -3.0, 4.0]);
        assert_eq!(mirrored([1.0, 2.0, 3.0, 4.0], 1.0), [1.0, 2.0, 3.0, 4.0]);
    }
}
