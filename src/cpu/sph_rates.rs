//! `sph_rates`: velocity gradient and density rate of every particle, gathered over its
//! neighbours and axis ghosts (physics.md §3).
//!
//! With per-radian-area masses m̃ = m/(2π r) the planar SPH sums hold in the (r, z) plane:
//! a particle's area is m̃/ρ. `G = Σ_j (m̃_j/ρ_j)(v_j − v_i) ⊗ ∇_i W_ij` is corrected by the
//! inverse of `M = Σ_j (m̃_j/ρ_j)(x_j − x_i) ⊗ ∇_i W_ij` (exact for linear fields) where M is
//! well conditioned; `ρ̇ = −ρ (L_rr + L_zz + v_r/r)`. With the Balsara switch on it also writes
//! each particle's factor on the viscosity from L (see [`balsara`]).
//!
//! With the conjugate gradient (`target.velocity_gradient = "conjugate"`) L is instead
//! `(1/ρ_i) Σ_j m̃_j (v_j − v_i) ⊗ ∇W`, uncorrected: with it `−m_i σ_i : L_i / ρ_i` is the work
//! of the terms in particle i's own stress in all its pair forces (`sph_forces`), so summed
//! over the particles the stress power is the work the pair forces do, and the stress update
//! sees the strain the motion pays for. The hoop rate is then `n_i v_r/r`, n_i the hoop
//! source's weight (`Particles::hoop_weight`, gathered here for `sph_forces` too), because the
//! hoop source does work `n_i σ_θθ v_r/r` per unit mass: near 1 inside, about ½ at a free face
//! normal to r, where L's normal part falls short by the same missing half of the kernel.
//!
//! With the velocity filter on (`target.velocity_filter = "linear"`, [`super::sph_filter`]) L
//! and the hoop rate are taken from each particle's velocity moved by the kernel-weighted mean
//! of its neighbours' departures from the linear field that a first L fits: a linear field
//! passes unchanged, particle-scale scatter is averaged out (docs/physics.md §3).
//!
//! With the reconstructed viscosity (`target.viscosity_jump = "reconstructed"`) it also writes
//! each particle's corrected gradient of its own velocity, `l_visc`, whose slopes
//! `sph_forces` reconstructs each pair's velocities with: L itself unless L is the conjugate
//! gradient, then a second, corrected gather.

use rayon::prelude::*;

use super::neighbours::CellGrid;
use super::wall::Wall;
use crate::state::{Particles, SphParams};

const TWO_PI: f32 = 2.0 * std::f32::consts::PI;

/// det M below which the correction is not applied (near a free surface with few neighbours).
pub(crate) const MIN_CORRECTION_DET: f32 = 0.25;

/// Radius used for 1/r terms: particles are kept ≥ 0.1 h off the axis (physics.md §3).
#[inline]
pub fn hoop_radius(r: f32, h: f32) -> f32 {
    r.max(0.1 * h)
}

/// The hoop strain rate the continuity and stress updates take: `v_r/r`, or with the conjugate
/// gradient `n v_r/r`, n the particle's hoop weight (module header).
#[inline]
pub fn hoop_rate(params: &SphParams, hoop_weight: f32, vr: f32, r: f32) -> f32 {
    let rate = vr / hoop_radius(r, params.h);
    if params.conjugate_gradient {
        hoop_weight * rate
    } else {
        rate
    }
}

pub fn run(particles: &mut Particles, grid: &CellGrid, params: &SphParams, walls: Option<&[Wall]>) {
    let h = params.h;
    let Particles {
        r,
        z,
        vr,
        vz,
        mass,
        rho,
        l_rr,
        l_rz,
        l_zr,
        l_zz,
        drho,
        m_tilde,
        area,
        hoop_weight,
        sound,
        visc_switch,
        l_visc,
        ..
    } = particles;
    m_tilde
        .par_iter_mut()
        .zip(area.par_iter_mut())
        .enumerate()
        .for_each(|(i, (mt, a))| {
            *mt = mass[i] / (TWO_PI * hoop_radius(r[i], h));
            *a = *mt / rho[i];
        });
    let (r, rho, m_tilde, area, sound) = (&*r, &*rho, &*m_tilde, &*area, &*sound);
    let field = Field {
        r,
        z,
        rho,
        m_tilde,
        area,
        h,
        conjugate: params.conjugate_gradient,
        grid,
        kernel: &params.kernel,
        walls,
    };
    let filtered;
    let (vr, vz): (&[f32], &[f32]) = if params.velocity_filter {
        filtered = super::sph_filter::run(&field, vr, vz);
        (&filtered.0, &filtered.1)
    } else {
        (vr, vz)
    };
    l_rr.par_iter_mut()
        .zip(l_rz.par_iter_mut())
        .zip(l_zr.par_iter_mut())
        .zip(l_zz.par_iter_mut())
        .zip(drho.par_iter_mut())
        .zip(visc_switch.par_iter_mut())
        .zip(hoop_weight.par_iter_mut())
        .enumerate()
        .for_each(|(i, ((((((lrr, lrz), lzr), lzz), dr_out), f), n))| {
            let (l, weight) = field.gradient(i, vr, vz);
            *lrr = l[0];
            *lrz = l[1];
            *lzr = l[2];
            *lzz = l[3];
            *n = weight;
            let div = l[0] + l[3] + hoop_rate(params, weight, vr[i], r[i]);
            *dr_out = -rho[i] * div;
            if params.balsara {
                *f = balsara(div, l[1] - l[2], sound[i], h);
            }
        });
    if params.reconstruct_viscosity {
        // The filter is refused with the reconstruction (scene::resolve), so L is of the
        // particles' own velocities.
        let corrected = Field {
            conjugate: false,
            ..field
        };
        let (l_rr, l_rz, l_zr, l_zz) = (&*l_rr, &*l_rz, &*l_zr, &*l_zz);
        // Kept only where a scene asks for the reconstruction (`Particles::from_lattice`):
        // made here for particles that come without it.
        l_visc.resize(l_rr.len(), [0.0; 4]);
        l_visc.par_iter_mut().enumerate().for_each(|(i, out)| {
            *out = if params.conjugate_gradient {
                corrected.gradient(i, vr, vz).0
            } else {
                [l_rr[i], l_rz[i], l_zr[i], l_zz[i]]
            };
        });
    }
}

/// What a gather over the particles reads besides the field gathered.
pub(crate) struct Field<'a> {
    pub(super) r: &'a [f32],
    pub(super) z: &'a [f32],
    pub(super) rho: &'a [f32],
    pub(super) m_tilde: &'a [f32],
    pub(super) area: &'a [f32],
    pub(super) h: f32,
    /// Gather the conjugate gradient instead of the corrected one.
    pub(super) conjugate: bool,
    /// The neighbour list of the positions gathered at.
    pub(super) grid: &'a CellGrid,
    pub(super) kernel: &'a crate::kernel::Kernel,
    /// Each particle's wall, whose images complete its kernel at the projectile (`wall`).
    pub(super) walls: Option<&'a [Wall]>,
}

impl Field<'_> {
    /// L = G M⁻¹ at particle i of the velocity field (vr, vz); the conjugate gradient, G with
    /// m̃_j/ρ_i for m̃_j/ρ_j and uncorrected, where `conjugate`. And i's hoop weight
    /// `n_i = Σ_j m̃_j (w_i + w_j − 2 r_i) ∂_r W_ij / ρ_i` (w = ±r as in `sph_forces`).
    pub(crate) fn gradient(&self, i: usize, vr: &[f32], vz: &[f32]) -> ([f32; 4], f32) {
        let mut sums = GradientSums::default();
        let ri = hoop_radius(self.r[i], self.h);
        for nb in self.grid.neighbours(i) {
            let j = nb.j();
            let sign = if nb.mirror() { -1.0 } else { 1.0 };
            let rj = hoop_radius(self.r[j], self.h);
            // A mirror ghost: radial velocity reversed, w = −r.
            let vrj = if nb.mirror() { -vr[j] } else { vr[j] };
            let w_sum = sign * ri + sign * rj - 2.0 * ri;
            sums.pair(
                self,
                i,
                vr,
                vz,
                j,
                (nb.dr, nb.dz),
                nb.grad(),
                (vrj, vz[j]),
                w_sum,
            );
        }
        if let Some(wall) = self.walls.map(|w| w[i]).filter(|w| w.on()) {
            wall.images(i, self.r, self.z, self.grid, self.kernel, |im| {
                // Moving as its source mirrored in the wall's frame, w = r of its own radius.
                let rg = hoop_radius(im.r, self.h);
                let v = wall.velocity(vr[im.j], vz[im.j]);
                sums.pair(self, i, vr, vz, im.j, (im.dr, im.dz), im.grad, v, rg - ri);
            });
        }
        let GradientSums { g, m, weight } = sums;
        let l = if self.conjugate { g } else { correct(g, m) };
        (l, weight / self.rho[i])
    }
}

/// The sums of `Field::gradient` at one particle.
#[derive(Default)]
struct GradientSums {
    /// G_rr, G_rz, G_zr, G_zz.
    g: [f32; 4],
    /// M_rr, M_rz, M_zr, M_zz.
    m: [f32; 4],
    /// The hoop weight's sum.
    weight: f32,
}

impl GradientSums {
    /// One pair's terms at particle i, a neighbour's (or its axis ghost's) or an image's:
    /// partner j at x_i − x_j = (dr, dz) with velocity (vr_j, vz_j) in the pair's frame and
    /// ring weight sum w_i + w_j − 2 r_i. Inlined by force, as `sph_forces::pair_term`: a
    /// closure called from the neighbour and the image loops was left out of line.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn pair(
        &mut self,
        field: &Field,
        i: usize,
        vr: &[f32],
        vz: &[f32],
        j: usize,
        (dr, dz): (f32, f32),
        gw: [f32; 2],
        (vrj, vzj): (f32, f32),
        w_sum: f32,
    ) {
        let (g, m) = (&mut self.g, &mut self.m);
        let area = if field.conjugate {
            field.area[j] * field.rho[j] / field.rho[i]
        } else {
            field.area[j]
        };
        let dvr = vrj - vr[i];
        let dvz = vzj - vz[i];
        // x_j − x_i = −(dr, dz)
        g[0] += area * dvr * gw[0];
        g[1] += area * dvr * gw[1];
        g[2] += area * dvz * gw[0];
        g[3] += area * dvz * gw[1];
        m[0] -= area * dr * gw[0];
        m[1] -= area * dr * gw[1];
        m[2] -= area * dz * gw[0];
        m[3] -= area * dz * gw[1];
        self.weight += field.m_tilde[j] * w_sum * gw[0];
    }
}

/// Balsara's (1995) factor on the viscosity, `|∇·v|/(|∇·v| + |∇×v| + 10⁻⁴ c/h)`: near 1 where
/// the flow compresses or expands, near 0 where it shears. In the r–z plane of an axisymmetric
/// flow the curl has one component, `∂v_r/∂z − ∂v_z/∂r`; the divergence has the hoop rate
/// `v_r/r`. The `10⁻⁴ c/h` keeps the ratio defined at rest (where it gives 0).
pub fn balsara(div: f32, curl: f32, sound: f32, h: f32) -> f32 {
    let div = div.abs();
    div / (div + curl.abs() + BALSARA_FLOOR * sound / h)
}

/// The floor of the Balsara denominator, in units of c/h.
pub(crate) const BALSARA_FLOOR: f32 = 1.0e-4;

/// L = G M⁻¹ where det M is large enough, else G.
fn correct(g: [f32; 4], m: [f32; 4]) -> [f32; 4] {
    let det = m[0] * m[3] - m[1] * m[2];
    if det < MIN_CORRECTION_DET {
        return g;
    }
    let inv = [m[3] / det, -m[1] / det, -m[2] / det, m[0] / det];
    [
        g[0] * inv[0] + g[1] * inv[2],
        g[0] * inv[1] + g[1] * inv[3],
        g[2] * inv[0] + g[3] * inv[2],
        g[2] * inv[1] + g[3] * inv[3],
    ]
}

/// What a particle's neighbourhood gives it, for the nose-lining study (`studies::lining`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KernelReading {
    /// Kernel completeness `Σ_j (m̃_j/ρ_j) W_ij` over the particle itself, its neighbours and
    /// the axis ghosts (and its wall images): 1 inside the material, ½–¾ at a free face (the
    /// face's own row counts whole).
    pub completeness: f32,
    /// The volumetric rate `−ρ̇/ρ` as the step takes it (this scene's gradient and hoop rate).
    pub divergence: f32,
    /// The same rate from the corrected gradient `G M⁻¹`, exact for a linear field however
    /// much of the kernel is cut, with the full hoop rate `v_r/r`.
    pub divergence_corrected: f32,
}

/// [`KernelReading`] at the particles `which`, from the current positions and velocities;
/// `grid` is the neighbour list of those positions, `walls` the particles' walls where the
/// scene has wall images (the step's readings and the completeness then count the images; the
/// corrected rate reads the particles alone).
pub fn kernel_readings(
    particles: &Particles,
    grid: &CellGrid,
    params: &SphParams,
    walls: Option<&[Wall]>,
    which: &[usize],
) -> Vec<KernelReading> {
    let h = params.h;
    let kernel = &params.kernel;
    let p = particles;
    let m_tilde: Vec<f32> = (0..p.r.len())
        .map(|i| p.mass[i] / (TWO_PI * hoop_radius(p.r[i], h)))
        .collect();
    let area: Vec<f32> = m_tilde.iter().zip(&p.rho).map(|(m, rho)| m / rho).collect();
    let field = |conjugate, walls| Field {
        r: &p.r,
        z: &p.z,
        rho: &p.rho,
        m_tilde: &m_tilde,
        area: &area,
        h,
        conjugate,
        grid,
        kernel,
        walls,
    };
    let (stepped, corrected) = (field(params.conjugate_gradient, walls), field(false, None));
    which
        .iter()
        .map(|&i| {
            let mut completeness = area[i] * kernel.w(0.0);
            for nb in grid.neighbours(i) {
                completeness += area[nb.j()] * kernel.w(nb.dist);
            }
            if let Some(wall) = walls.map(|w| w[i]).filter(|w| w.on()) {
                wall.images(i, &p.r, &p.z, grid, kernel, |im| {
                    completeness += area[im.j] * kernel.w(im.dr.hypot(im.dz));
                });
            }
            let (l, weight) = stepped.gradient(i, &p.vr, &p.vz);
            let (lc, _) = corrected.gradient(i, &p.vr, &p.vz);
            KernelReading {
                completeness,
                divergence: l[0] + l[3] + hoop_rate(params, weight, p.vr[i], p.r[i]),
                divergence_corrected: lc[0] + lc[3] + p.vr[i] / hoop_radius(p.r[i], h),
            }
        })
        .collect()
}
