// `integrate` (CPU twin: src/cpu/integrate.rs): leapfrog velocities then positions, the axis
// constraint, the rigid wall, instability flags, and the stable time step as a min-reduction.
// Needs params.wgsl and step.wgsl.

@group(0) @binding(0) var<uniform> u: StepUniform;
@group(0) @binding(1) var<storage, read_write> clock: ClockAtomic;
@group(0) @binding(2) var<storage, read_write> status: array<atomic<u32>>;
@group(0) @binding(3) var<storage, read_write> r: array<f32>;
@group(0) @binding(4) var<storage, read_write> z: array<f32>;
@group(0) @binding(5) var<storage, read_write> vr: array<f32>;
@group(0) @binding(6) var<storage, read_write> vz: array<f32>;
// Particles: ar, az (accelerations); nodes: fr, fz (forces).
@group(0) @binding(7) var<storage, read> ar: array<f32>;
@group(0) @binding(8) var<storage, read> az: array<f32>;
@group(0) @binding(9) var<storage, read> mass: array<f32>;
// Particles: `fixed`; nodes: `on_axis`.
@group(0) @binding(10) var<storage, read> flag: array<u32>;
// Running z-impulse of the boundary on the model (N s), per entity; nodes also accumulate the
// kinetic energy the wall took (J) in `lost`.
@group(0) @binding(11) var<storage, read_write> impulse: array<f32>;
@group(0) @binding(12) var<storage, read_write> lost: array<f32>;
// Particles only: sph_forces' work-conjugate energy rate, and the energy it books into.
@group(0) @binding(13) var<storage, read> de_work: array<f32>;
@group(0) @binding(14) var<storage, read_write> energy: array<f32>;

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

@compute @workgroup_size(WG)
fn particles(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if (i >= u.n_particles) { return; }
    let dt = bitcast<f32>(atomicLoad(&clock.dt_bits));
    var e = energy[i] + dt * de_work[i];
    if (flag[i] != 0u) {
        energy[i] = e;
        // What the fixed particle would have gained from its neighbours is the boundary's
        // reaction on the rest (solver.rs: boundary_impulse).
        impulse[i] -= mass[i] * az[i] * dt;
        vr[i] = 0.0;
        vz[i] = 0.0;
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
}

@compute @workgroup_size(WG)
fn nodes(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if (i >= u.n_nodes) { return; }
    let dt = bitcast<f32>(atomicLoad(&clock.dt_bits));
    let inv_m = 1.0 / mass[i];
    var nvr = 0.0;
    if (flag[i] == 0u) {
        nvr = vr[i] + dt * ar[i] * inv_m;
    }
    let vz_before = vz[i];
    var f_z = az[i];
    if (u.has_wall != 0u && z[i] <= u.wall_z) {
        f_z = max(f_z, 0.0);
    }
    var nvz = vz_before + dt * f_z * inv_m;
    let nr = r[i] + dt * nvr;
    var nz = z[i] + dt * nvz;
    if (u.has_wall != 0u) {
        if (nz < u.wall_z) {
            nz = u.wall_z;
            if (nvz < 0.0) {
                lost[i] += 0.5 * mass[i] * nvz * nvz;
                nvz = 0.0;
            }
        }
        impulse[i] += mass[i] * (nvz - vz_before) - az[i] * dt;
    }
    r[i] = nr;
    z[i] = nz;
    vr[i] = nvr;
    vz[i] = nvz;
    check(i, vec4<f32>(nr, nz, nvr, nvz), STATUS_NODE_NONFINITE, STATUS_NODE_ESCAPED);
}
