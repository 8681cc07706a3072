// What the step's own passes share: the clock with atomic access and the stable-step
// candidates. StepUniform and the status words (STATUS_*, which src/gpu/step.rs reads back
// every step) are in shader.rs's prelude.

// `Clock` of params.wgsl with atomic words: dt_bits is the step being taken, fem_limited whether
// the elements set it, and `next` two slots of running minima of the candidates for the next
// step (the particles' at 2 s, the elements' at 2 s + 1; positive f32 bits order like the
// floats). The candidates' producers fold them into the slot of the coming integration's
// parity (sph_forces per particle, fem_stress per pressure cell: an atomicMin only where one
// lowers the minimum), the integration makes the step of them and empties the other slot
// (integrate.wgsl). The minimum is order-independent, so the result is deterministic; CPU
// twin: src/cpu/timestep.rs, the minimum Simulation::stable_dt takes.
struct ClockAtomic {
    dt_bits: atomic<u32>,
    fem_limited: atomic<u32>,
    next: array<atomic<u32>, 4>,
}

// A candidate as bits that order like the value; NaN and negatives never win.
fn candidate_bits(x: f32) -> u32 {
    if (x >= 0.0 && x <= 3.4028235e38) {
        return bitcast<u32>(x);
    }
    return F32_MAX_BITS;
}

// A particle's stable step, h / (c + |v| + 1.2 (alpha c + beta mu_max)) (Monaghan 1992), as
// candidate bits.
fn particle_dt_bits(h: f32, alpha: f32, beta: f32, cs: f32, v: vec2<f32>, mu_max: f32) -> u32 {
    let speed = sqrt(v.x * v.x + v.y * v.y);
    return candidate_bits(h / (cs + speed + 1.2 * (alpha * cs + beta * mu_max)));
}
