// `integrate` (CPU twin: src/cpu/integrate.rs): leapfrog velocities then positions, the axis
// constraint, the rigid wall, instability flags; particles and nodes in one dispatch (thread i
// takes particle i and node i). It also ends the Δt reduction (step.wgsl): every thread
// takes the step from the running minima the fold filled, thread 0 stores it in the clock and
// empties the other slot for the next step's fold. And it folds what contact detection and
// the neighbour lists' watch need: the particles' largest squared displacement since the lists
// were built into the grid's moved2 (reset by `pack`), and the nodes' bounding box into the
// box slot of this integration's parity (thread 0 empties the other, and the hit list).
// Each node first gathers its elements' forces (CPU twin: src/cpu/fem_forces.rs) through the
// node → element CSR, in CSR order: a gather, no float atomics, the CPU's sum to the bit; it
// stores them in fr, fz for the read-back.
// Needs params.wgsl and step.wgsl.

@group(0) @binding(0) var<uniform> u: StepUniform;
@group(0) @binding(1) var<storage, read_write> clock: ClockAtomic;
@group(0) @binding(2) var<storage, read_write> status: array<atomic<u32>>;
@group(0) @binding(3) var<uniform> source: DtSlot;
@group(0) @binding(4) var<storage, read_write> r: array<f32>;
@group(0) @binding(5) var<storage, read_write> z: array<f32>;
@group(0) @binding(6) var<storage, read_write> vr: array<f32>;
@group(0) @binding(7) var<storage, read_write> vz: array<f32>;
@group(0) @binding(8) var<storage, read> ar: array<f32>;
@group(0) @binding(9) var<storage, read> az: array<f32>;
@group(0) @binding(10) var<storage, read> mass: array<f32>;
@group(0) @binding(11) var<storage, read> fixed: array<u32>;
// Running z-impulse of the fixed particles on the rest (N s), per particle.
@group(0) @binding(12) var<storage, read_write> impulse: array<f32>;
// sph_forces' work-conjugate energy rate, and the energy it books into.
@group(0) @binding(13) var<storage, read> de_work: array<f32>;
@group(0) @binding(14) var<storage, read_write> energy: array<f32>;
// Positions at the last list build, and the grid's words (moved2 at MOVED2_WORD).
@group(0) @binding(15) var<storage, read> x_build: array<vec2<f32>>;
@group(0) @binding(16) var<storage, read_write> grid_words: array<atomic<u32>>;
// The nodes: forces fr, fz; on_axis; the wall's z-impulse (N s) and the kinetic energy it
// took (J), per node.
@group(0) @binding(17) var<storage, read_write> node_r: array<f32>;
@group(0) @binding(18) var<storage, read_write> node_z: array<f32>;
@group(0) @binding(19) var<storage, read_write> node_vr: array<f32>;
@group(0) @binding(20) var<storage, read_write> node_vz: array<f32>;
@group(0) @binding(21) var<storage, read_write> node_fr: array<f32>;
@group(0) @binding(22) var<storage, read_write> node_fz: array<f32>;
@group(0) @binding(23) var<storage, read> node_mass: array<f32>;
@group(0) @binding(24) var<storage, read> on_axis: array<u32>;
@group(0) @binding(25) var<storage, read_write> node_impulse: array<f32>;
@group(0) @binding(26) var<storage, read_write> node_lost: array<f32>;
// The contact's: the projectile's bounding box as ordered keys (common.wgsl float_key), r_max,
// z_min, z_max at 4 p for the parity p; and the hit list, whose count is word 0.
@group(0) @binding(27) var<storage, read_write> box_keys: array<atomic<u32>>;
@group(0) @binding(28) var<storage, read_write> hits: array<atomic<u32>>;
// The elements' nodal forces, [f32; 6] per element, and the node → element CSR (3·element +
// local index).
@group(0) @binding(29) var<storage, read> elem_offsets: array<u32>;
@group(0) @binding(30) var<storage, read> elem_refs: array<u32>;
@group(0) @binding(31) var<storage, read> force: array<f32>;

// This integration's parity: the slot its Δt is in (DT_FROM_CLOCK comes only before the first
// fold, at parity 0).
fn parity() -> u32 {
    return source.slot & 1u;
}

fn finite(x: f32) -> bool {
    // NaN fails every comparison; ±inf exceeds the largest f32.
    return abs(x) <= 3.4028235e38;
}

fn check(i: u32, x: vec4<f32>, nonfinite_slot: u32, escaped_slot: u32) {
    if (!(finite(x.x) && finite(x.y) && finite(x.z) && finite(x.w))) {
        atomicMin(&status[nonfinite_slot], i);
    } else if (abs(x.x) > u.escape || abs(x.y) > u.escape) {
        atomicMin(&status[escaped_slot], i);
    }
}

// Thread 0: what the next integration's parity fills empties (the running minima and the box),
// and the hit list.
fn empty_the_other_parity() {
    let other = 1u - parity();
    atomicStore(&clock.next[2u * other], F32_MAX_BITS);
    atomicStore(&clock.next[2u * other + 1u], F32_MAX_BITS);
    if (u.n_slaves > 0u) {
        atomicStore(&box_keys[4u * other], float_key(0.0));
        atomicStore(&box_keys[4u * other + 1u], float_key(3.4028235e38));
        atomicStore(&box_keys[4u * other + 2u], float_key(-3.4028235e38));
        atomicStore(&hits[0], 0u);
    }
}

// The step: the least candidate of the slot times the CFL number, set by the elements when
// theirs is no larger (as Model::stable_dt counts it); or the clock's, as the host set it, when
// no fold has run yet (DT_FROM_CLOCK). Thread 0 stores it.
fn step_dt(thread: u32) -> f32 {
    if (thread == 0u) {
        empty_the_other_parity();
    }
    if (source.slot == DT_FROM_CLOCK) {
        return bitcast<f32>(atomicLoad(&clock.dt_bits));
    }
    let s = 2u * parity();
    let sph = atomicLoad(&clock.next[s]);
    let fem = atomicLoad(&clock.next[s + 1u]);
    let dt = bitcast<f32>(min(sph, fem)) * u.cfl;
    if (thread == 0u) {
        atomicStore(&clock.dt_bits, bitcast<u32>(dt));
        atomicStore(&clock.fem_limited, select(0u, 1u, fem <= sph && fem != F32_MAX_BITS));
    }
    return dt;
}

fn particle(i: u32, dt: f32) {
    var e = energy[i] + dt * de_work[i];
    if (fixed[i] != 0u) {
        energy[i] = e;
        // What the fixed particle would have gained from its neighbours is the boundary's
        // reaction on the rest (solver.rs: boundary_impulse).
        impulse[i] -= mass[i] * az[i] * dt;
        vr[i] = 0.0;
        vz[i] = 0.0;
        watch(i, r[i], z[i]);
        return;
    }
    let a = vec2<f32>(ar[i], az[i]);
    var pvr = vr[i] + dt * a.x;
    var pvz = vz[i] + dt * a.y;
    var pr = r[i] + dt * pvr;
    let pz = z[i] + dt * pvz;
    var axis_lost = 0.0;
    if (pr < u.r_min) {
        pr = u.r_min;
        let kept = max(pvr, 0.0);
        axis_lost = 0.5 * (pvr * pvr - kept * kept);
        pvr = kept;
    }
    // The rest of the kinetic energy the step gave: ½ a² Δt², less what the axis took.
    energy[i] = e + (axis_lost - 0.5 * dt * dt * (a.x * a.x + a.y * a.y));
    r[i] = pr;
    z[i] = pz;
    vr[i] = pvr;
    vz[i] = pvz;
    check(i, vec4<f32>(pr, pz, pvr, pvz), STATUS_PARTICLE_NONFINITE, STATUS_PARTICLE_ESCAPED);
    watch(i, pr, pz);
}

// The displacement watch: non-negative f32 bits order like the values; a load first keeps the
// atomics to the few threads that raise the maximum.
fn watch(i: u32, pr: f32, pz: f32) {
    let d = vec2<f32>(pr, pz) - x_build[i];
    let bits = bitcast<u32>(dot(d, d));
    if (bits > atomicLoad(&grid_words[MOVED2_WORD])) {
        atomicMax(&grid_words[MOVED2_WORD], bits);
    }
}

fn node(i: u32, dt: f32) {
    var f = vec2<f32>(0.0);
    for (var k = elem_offsets[i]; k < elem_offsets[i + 1u]; k++) {
        let code = elem_refs[k];
        let at = 6u * (code / 3u) + 2u * (code % 3u);
        f = f + vec2<f32>(force[at], force[at + 1u]);
    }
    node_fr[i] = f.x;
    node_fz[i] = f.y;
    let inv_m = 1.0 / node_mass[i];
    var nvr = 0.0;
    if (on_axis[i] == 0u) {
        nvr = node_vr[i] + dt * f.x * inv_m;
    }
    let vz_before = node_vz[i];
    var f_z = f.y;
    if (u.has_wall != 0u && node_z[i] <= u.wall_z) {
        f_z = max(f_z, 0.0);
    }
    var nvz = vz_before + dt * f_z * inv_m;
    let nr = node_r[i] + dt * nvr;
    var nz = node_z[i] + dt * nvz;
    if (u.has_wall != 0u) {
        if (nz < u.wall_z) {
            nz = u.wall_z;
            if (nvz < 0.0) {
                node_lost[i] += 0.5 * node_mass[i] * nvz * nvz;
                nvz = 0.0;
            }
        }
        node_impulse[i] += node_mass[i] * (nvz - vz_before) - f.y * dt;
    }
    node_r[i] = nr;
    node_z[i] = nz;
    node_vr[i] = nvr;
    node_vz[i] = nvz;
    check(i, vec4<f32>(nr, nz, nvr, nvz), STATUS_NODE_NONFINITE, STATUS_NODE_ESCAPED);
    if (u.n_slaves > 0u) {
        // A load first keeps the atomics to the few nodes that widen the box.
        let b = 4u * parity();
        let kr = float_key(nr);
        let kz = float_key(nz);
        if (kr > atomicLoad(&box_keys[b])) {
            atomicMax(&box_keys[b], kr);
        }
        if (kz < atomicLoad(&box_keys[b + 1u])) {
            atomicMin(&box_keys[b + 1u], kz);
        }
        if (kz > atomicLoad(&box_keys[b + 2u])) {
            atomicMax(&box_keys[b + 2u], kz);
        }
    }
}

@compute @workgroup_size(WG)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if (i >= max(u.n_particles, u.n_nodes)) { return; }
    let dt = step_dt(i);
    if (i < u.n_particles) {
        particle(i, dt);
    }
    if (i < u.n_nodes) {
        node(i, dt);
    }
}
