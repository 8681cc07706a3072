//! `timestep`: the stable step, a min-reduction over the particles' and the elements' own
//! stable steps (physics.md §5); the GPU folds them where sph_forces and fem_stress make them
//! (shaders/step.wgsl) and the integration takes the least.

use rayon::prelude::*;

use crate::state::{Elements, Particles, SphParams};

/// Stable step of the particles: h / (c + |v| + 1.2 (α c + β μ_max)) (Monaghan 1992, with the
/// viscosity refinement of physics.md §3).
pub fn particle_dt(p: &Particles, params: &SphParams) -> f32 {
    (0..p.len())
        .into_par_iter()
        .map(|i| particle_step(p, params, i))
        .reduce(|| f32::MAX, f32::min)
}

/// Stable step of particle `i` alone (the term [`particle_dt`] takes the least of).
pub fn particle_step(p: &Particles, params: &SphParams, i: usize) -> f32 {
    let c = p.sound[i];
    let v = (p.vr[i] * p.vr[i] + p.vz[i] * p.vz[i]).sqrt();
    params.h / (c + v + 1.2 * (params.alpha * c + params.beta * p.mu_visc[i]))
}

/// Stable step of the elements (computed by `fem_stress`).
pub fn element_dt(e: &Elements) -> f32 {
    e.dt.par_iter().copied().reduce(|| f32::MAX, f32::min)
}
