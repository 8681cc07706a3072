// The stable time step (CPU twin: src/cpu/timestep.rs, the minimum taken by
// Simulation::stable_dt): a min-reduction over particles and elements into the clock's running
// minima of one slot, each thread folding a strided share of both first so that few atomics
// reach the clock. The minimum is order-independent, so the result is deterministic. The next
// integration (integrate.wgsl `step_dt`) makes the step of them and empties the other slot,
// which the next fold fills: the two alternate, so no pass of its own resets them.
// Needs params.wgsl and step.wgsl.

@group(0) @binding(0) var<uniform> u: StepUniform;
@group(0) @binding(1) var<storage, read_write> clock: ClockAtomic;
@group(0) @binding(2) var<uniform> target_slot: DtSlot;
@group(0) @binding(3) var<storage, read> sound: array<f32>;
@group(0) @binding(4) var<storage, read> vr: array<f32>;
@group(0) @binding(5) var<storage, read> vz: array<f32>;
@group(0) @binding(6) var<storage, read> mu_visc: array<f32>;
@group(0) @binding(7) var<storage, read> element_dt: array<f32>;

// A candidate as bits that order like the value; NaN and negatives never win.
fn candidate_bits(x: f32) -> u32 {
    if (x >= 0.0 && x <= 3.4028235e38) {
        return bitcast<u32>(x);
    }
    return F32_MAX_BITS;
}

// Particle i's stable step, h / (c + |v| + 1.2 (alpha c + beta mu_max)) (Monaghan 1992).
fn particle_bits(i: u32) -> u32 {
    let cs = sound[i];
    let v = sqrt(vr[i] * vr[i] + vz[i] * vz[i]);
    return candidate_bits(u.h / (cs + v + 1.2 * (u.alpha * cs + u.beta * mu_visc[i])));
}

// Each thread folds the particles and the elements gid, gid + stride, … (gpu::Kernel::
// dispatch_fold over the larger count), then one atomic for each. The elements take part only
// where they are deformable.
@compute @workgroup_size(WG)
fn fold(@builtin(global_invocation_id) gid: vec3<u32>,
        @builtin(num_workgroups) groups: vec3<u32>) {
    let stride = groups.x * WG;
    let s = 2u * target_slot.slot;
    var sph = F32_MAX_BITS;
    for (var i = gid.x; i < u.n_particles; i += stride) {
        sph = min(sph, particle_bits(i));
    }
    atomicMin(&clock.next[s], sph);
    if (u.has_fem != 0u) {
        var fem = F32_MAX_BITS;
        for (var i = gid.x; i < u.n_elements; i += stride) {
            fem = min(fem, candidate_bits(element_dt[i]));
        }
        atomicMin(&clock.next[s + 1u], fem);
    }
}
