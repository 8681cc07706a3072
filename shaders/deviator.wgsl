// The deviatoric update shared by `fem_stress` and `concrete`: the WGSL twin of
// src/cpu/deviator.rs. Components are (rr, zz, rz, θθ) with rz the tensor (not engineering)
// shear, packed as vec4 (x, y, z, w).

// Trace of the rate of deformation (the volumetric rate), returned by deviator.rs's
// `deviatoric_rate` together with the deviator.
fn volumetric_rate(d: vec4<f32>) -> f32 {
    return d.x + d.y + d.w;
}

// Deviator of the rate of deformation.
fn deviatoric_rate(d: vec4<f32>) -> vec4<f32> {
    let vol = volumetric_rate(d);
    return vec4<f32>(d.x - vol / 3.0, d.y - vol / 3.0, d.z, d.w - vol / 3.0);
}

// Elastic trial deviator after dt with the Jaumann terms of the r–z spin ω.
fn jaumann_trial(s: vec4<f32>, dev: vec4<f32>, spin: f32, g: f32, dt: f32) -> vec4<f32> {
    let g2 = 2.0 * g;
    return vec4<f32>(
        s.x + dt * (g2 * dev.x + 2.0 * spin * s.z),
        s.y + dt * (g2 * dev.y - 2.0 * spin * s.z),
        s.z + dt * (g2 * dev.z + spin * (s.y - s.x)),
        s.w + dt * (g2 * dev.w),
    );
}

// Equivalent strain rate sqrt(2/3 dev:dev).
fn equivalent_rate(dev: vec4<f32>) -> f32 {
    return sqrt(2.0 / 3.0
        * (dev.x * dev.x + dev.y * dev.y + 2.0 * dev.z * dev.z + dev.w * dev.w));
}

// Largest principal rate of deformation, >= 0 (deviator.rs `largest_principal_rate`).
fn largest_principal_rate(d: vec4<f32>) -> f32 {
    let mean = 0.5 * (d.x + d.y);
    let half = 0.5 * (d.x - d.y);
    return max(max(mean + sqrt(half * half + d.z * d.z), d.w), 0.0);
}

// Von Mises stress sqrt(3/2 S:S) of a deviator.
fn von_mises(s: vec4<f32>) -> f32 {
    return sqrt(1.5 * (s.x * s.x + s.y * s.y + 2.0 * s.z * s.z + s.w * s.w));
}
