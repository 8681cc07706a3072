//! The deviatoric update shared by `fem_stress` and `concrete`: the rate of deformation split
//! into its deviator, the hypoelastic trial with the Jaumann rotation in the r–z plane
//! (physics.md §2), and the equivalent measures. Components are ordered (rr, zz, rz, θθ) with
//! rz the tensor (not engineering) shear.

/// Deviator of the rate of deformation (rr, zz, rz, θθ) and its trace.
#[inline]
pub fn deviatoric_rate(rr: f32, zz: f32, rz: f32, tt: f32) -> ([f32; 4], f32) {
    let vol = rr + zz + tt;
    ([rr - vol / 3.0, zz - vol / 3.0, rz, tt - vol / 3.0], vol)
}

/// Elastic trial deviator after `dt`: S + dt (2G dev ε̇ + Jaumann terms), with
/// `σ̇_r += 2ωτ_rz`, `σ̇_z −= 2ωτ_rz`, `τ̇_rz += ω(σ_z − σ_r)`, ω = ½(∂v_r/∂z − ∂v_z/∂r).
#[inline]
pub fn jaumann_trial(
    s: [f32; 4],
    dev: [f32; 4],
    spin: f32,
    shear_modulus: f32,
    dt: f32,
) -> [f32; 4] {
    let g2 = 2.0 * shear_modulus;
    let [sr, sz, srz, stt] = s;
    [
        sr + dt * (g2 * dev[0] + 2.0 * spin * srz),
        sz + dt * (g2 * dev[1] - 2.0 * spin * srz),
        srz + dt * (g2 * dev[2] + spin * (sz - sr)),
        stt + dt * (g2 * dev[3]),
    ]
}

/// Equivalent strain rate sqrt(2/3 dev:dev).
#[inline]
pub fn equivalent_rate(dev: &[f32; 4]) -> f32 {
    (2.0 / 3.0 * (dev[0] * dev[0] + dev[1] * dev[1] + 2.0 * dev[2] * dev[2] + dev[3] * dev[3]))
        .sqrt()
}

/// Largest principal rate of deformation (1/s), ≥ 0: the in-plane (rr, zz, rz) pair's larger
/// eigenvalue or the hoop rate θθ, whichever is larger; the tensile strain rate that sets
/// concrete's dynamic tensile strength.
#[inline]
pub fn largest_principal_rate(rr: f32, zz: f32, rz: f32, tt: f32) -> f32 {
    let mean = 0.5 * (rr + zz);
    let half = 0.5 * (rr - zz);
    (mean + (half * half + rz * rz).sqrt()).max(tt).max(0.0)
}

/// Von Mises equivalent stress sqrt(3/2 S:S) of a deviator.
#[inline]
pub fn von_mises(s: &[f32; 4]) -> f32 {
    (1.5 * (s[0] * s[0] + s[1] * s[1] + 2.0 * s[2] * s[2] + s[3] * s[3])).sqrt()
}
