//! `sph_filter`: the velocity filter of `target.velocity_filter = "linear"` (docs/physics.md §3),
//! run inside `sph_rates` between its two gradients; the GPU twin is shaders/sph_filter.wgsl.

use rayon::prelude::*;

use super::sph_rates::Field;

/// The filtered velocity of every particle: `v̄_i = v_i + Σ_j A_j W_ij (v_j − v_i − L_i (x_j −
/// x_i)) / Σ_j A_j W_ij`, the sums over the neighbours and axis ghosts and i itself (whose term
/// is zero), L_i the corrected gradient of the particles' own velocities, A = m̃/ρ. Where the
/// field is linear and L exact, v̄ = v; a particle's departure from its neighbourhood's linear
/// field, the scatter a kernel-scale gradient reads as δv/Δ, is replaced by the kernel's mean
/// departure.
pub(crate) fn run(field: &Field, vr: &[f32], vz: &[f32]) -> (Vec<f32>, Vec<f32>) {
    let kernel = field.kernel;
    (0..vr.len())
        .into_par_iter()
        .map(|i| {
            let (l, _) = field.gradient(i, vr, vz);
            let mut weight = kernel.w(0.0) * field.area[i];
            let (mut sum_r, mut sum_z) = (0.0f32, 0.0f32);
            for nb in field.grid.neighbours(i) {
                let j = nb.j();
                let w = kernel.w(nb.dist) * field.area[j];
                let vrj = if nb.mirror() { -vr[j] } else { vr[j] };
                // x_j − x_i = −(dr, dz)
                let dep_r = vrj - vr[i] + l[0] * nb.dr + l[1] * nb.dz;
                let dep_z = vz[j] - vz[i] + l[2] * nb.dr + l[3] * nb.dz;
                weight += w;
                sum_r += w * dep_r;
                sum_z += w * dep_z;
            }
            (vr[i] + sum_r / weight, vz[i] + sum_z / weight)
        })
        .unzip()
}
