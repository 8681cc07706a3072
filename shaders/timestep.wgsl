// The stable time step (CPU twin: src/cpu/timestep.rs, the minimum taken by
// Simulation::stable_dt): a min-reduction over particles and elements into the clock, each
// thread folding a strided share first so that few atomics reach the clock. The minimum is
// order-independent, so the result is deterministic. Needs params.wgsl and step.wgsl.

@group(0) @binding(0) var<uniform> u: StepUniform;
@group(0) @binding(1) var<storage, read_write> clock: ClockAtomic;
// Particles: sound, vr, vz, mu_visc. Elements: dt in `a` (the others unused but bound).
@group(0) @binding(2) var<storage, read> a: array<f32>;
@group(0) @binding(3) var<storage, read> b: array<f32>;
@group(0) @binding(4) var<storage, read> c: array<f32>;
@group(0) @binding(5) var<storage, read> d: array<f32>;

// A candidate as bits that order like the value; NaN and negatives never win.
fn candidate_bits(x: f32) -> u32 {
    if (x >= 0.0 && x <= 3.4028235e38) {
        return bitcast<u32>(x);
    }
    return F32_MAX_BITS;
}

// Particle i's stable step, h / (c + |v| + 1.2 (alpha c + beta mu_max)) (Monaghan 1992).
fn particle_bits(i: u32) -> u32 {
    let cs = a[i];
    let v = sqrt(b[i] * b[i] + c[i] * c[i]);
    return candidate_bits(u.h / (cs + v + 1.2 * (u.alpha * cs + u.beta * d[i])));
}

// Each thread folds the items gid, gid + stride, … (gpu::Kernel::dispatch_fold), then one atomic.
@compute @workgroup_size(WG)
fn particle_dt(@builtin(global_invocation_id) gid: vec3<u32>,
               @builtin(num_workgroups) groups: vec3<u32>) {
    var bits = F32_MAX_BITS;
    for (var i = gid.x; i < u.n_particles; i += groups.x * WG) {
        bits = min(bits, particle_bits(i));
    }
    atomicMin(&clock.dt_next_bits, bits);
}

@compute @workgroup_size(WG)
fn element_dt(@builtin(global_invocation_id) gid: vec3<u32>,
              @builtin(num_workgroups) groups: vec3<u32>) {
    var bits = F32_MAX_BITS;
    for (var i = gid.x; i < u.n_elements; i += groups.x * WG) {
        bits = min(bits, candidate_bits(a[i]));
    }
    atomicMin(&clock.fem_next_bits, bits);
}

// One thread: the next step is the least candidate times the CFL number, set by the elements
// when theirs is no larger (as Model::stable_dt counts it); the running minima reset.
@compute @workgroup_size(1)
fn finish() {
    let sph = atomicLoad(&clock.dt_next_bits);
    let fem = atomicLoad(&clock.fem_next_bits);
    let dt = bitcast<f32>(min(sph, fem)) * u.cfl;
    atomicStore(&clock.dt_bits, bitcast<u32>(dt));
    atomicStore(&clock.fem_limited, select(0u, 1u, fem <= sph && fem != F32_MAX_BITS));
    atomicStore(&clock.dt_next_bits, F32_MAX_BITS);
    atomicStore(&clock.fem_next_bits, F32_MAX_BITS);
}
