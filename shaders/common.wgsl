// Shared helpers of every pass (src/gpu/shader.rs puts them after its prelude in every program).
// The prelude declares, from their Rust definitions, the uniform blocks (KernelUniform,
// SphUniform, FemUniform, StepUniform, DtSlot, ScanLevel: src/gpu/params.rs) and the constants the
// shaders share with the CPU path (WG = gpu::WORKGROUP, the material floors, the status words).
// Every pass uses @workgroup_size(WG): WG.

// The SPH kernel of src/kernel.rs: the 2-D cubic B-spline, support 2h.

fn kernel_w(k: KernelUniform, dist: f32) -> f32 {
    let q = dist * k.inv_h;
    if (q < 1.0) {
        return k.norm * (1.0 - 1.5 * q * q + 0.75 * q * q * q);
    } else if (q < 2.0) {
        let t = 2.0 - q;
        return k.norm * 0.25 * t * t * t;
    }
    return 0.0;
}

fn kernel_dw(k: KernelUniform, dist: f32) -> f32 {
    let q = dist * k.inv_h;
    if (q < 1.0) {
        return k.dnorm * (-3.0 * q + 2.25 * q * q);
    } else if (q < 2.0) {
        let t = 2.0 - q;
        return k.dnorm * (-0.75 * t * t);
    }
    return 0.0;
}

// grad_i W(x_i - x_j) for the separation d = x_i - x_j at distance dist.
fn kernel_grad(k: KernelUniform, d: vec2<f32>, dist: f32) -> vec2<f32> {
    if (dist <= 1.0e-12 * k.h) {
        return vec2<f32>(0.0, 0.0);
    }
    return (kernel_dw(k, dist) / dist) * d;
}

// sph_rates::hoop_radius: r floored at 0.1 h (particles are kept that far off the axis), so the
// 1/r terms of the SPH passes stay finite.
fn hoop_radius(ri: f32, h: f32) -> f32 {
    return max(ri, 0.1 * h);
}

// sph_rates::hoop_rate: the hoop strain rate v_r/r, weighted by the hoop weight n with the
// conjugate gradient.
fn hoop_rate(vr: f32, ri: f32, h: f32, n: f32, conjugate: bool) -> f32 {
    let rate = vr / hoop_radius(ri, h);
    return select(rate, n * rate, conjugate);
}

// Order-preserving map of an f32 to a u32 (for atomicMin/atomicMax on floats).
fn float_key(x: f32) -> u32 {
    let b = bitcast<u32>(x);
    if ((b & 0x80000000u) != 0u) {
        return ~b;
    }
    return b | 0x80000000u;
}

fn key_float(k: u32) -> f32 {
    if ((k & 0x80000000u) != 0u) {
        return bitcast<f32>(k & 0x7fffffffu);
    }
    return bitcast<f32>(~k);
}
