// Polynomial EOS of the steel, paper eq. (14), physics.md §2.2: the WGSL twin of
// src/materials/steel_eos.rs, function for function. The constants come from FemUniform
// (src/gpu/params.rs).

// p = K₁μ + K₂μ² + K₃μ³ + ΓE(1 + μ) for μ >= 0, K₁μ + ΓE(1 + μ) for μ < 0 (Pa);
// E per unit reference volume.
fn steel_eos_pressure(u: FemUniform, mu: f32, e_vol: f32) -> f32 {
    let mc = max(mu, 0.0);
    return u.eos_k1 * mu + (u.eos_k2 + u.eos_k3 * mc) * mc * mc + u.eos_gamma * e_vol * (1.0 + mu);
}

// dp/dμ of the cold curve (Pa), floored at EOS_BULK_TANGENT_FLOOR·K₁.
fn steel_eos_bulk_tangent(u: FemUniform, mu: f32) -> f32 {
    let mc = max(mu, 0.0);
    let tangent = u.eos_k1 + (2.0 * u.eos_k2 + 3.0 * u.eos_k3 * mc) * mc;
    return max(tangent, EOS_BULK_TANGENT_FLOOR * u.eos_k1);
}
