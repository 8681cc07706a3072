// `history` (host twin: Model::kinetic_energy, internal_target, momentum_z, fastest and the
// boundary impulse's particle sum, src/solver): what a history row needs of the particles,
// reduced on the GPU so that the row reads eight words per chunk of particles instead of every
// particle. Thread t folds the kinetic energy ½ m |v|², internal energy m e, wall impulse and
// z-momentum m v_z of particles [t·HISTORY_CHUNK, (t + 1)·HISTORY_CHUNK) in index order (the
// same bits every run; no workgroup barrier, which lavapipe makes slow) and finds their fastest
// (the first of the fastest, as the host's fold); the host sums the chunks in order, in f64.
// Thread t also copies slave t's position for the host's check for slaves left inside.

// n_particles, n_slaves.
@group(0) @binding(0) var<storage, read> counts: vec2<u32>;
@group(0) @binding(1) var<storage, read> r: array<f32>;
@group(0) @binding(2) var<storage, read> z: array<f32>;
@group(0) @binding(3) var<storage, read> vr: array<f32>;
@group(0) @binding(4) var<storage, read> vz: array<f32>;
@group(0) @binding(5) var<storage, read> mass: array<f32>;
@group(0) @binding(6) var<storage, read> energy: array<f32>;
@group(0) @binding(7) var<storage, read> impulse: array<f32>;
@group(0) @binding(8) var<storage, read> slaves: array<u32>;
// Per chunk: kinetic, internal, impulse, fastest speed, its index (bits), r, z, z-momentum.
@group(0) @binding(9) var<storage, read_write> partials: array<f32>;
// (r, z) of each slave.
@group(0) @binding(10) var<storage, read_write> slave_at: array<vec2<f32>>;

@compute @workgroup_size(WG)
fn reduce(@builtin(global_invocation_id) gid: vec3<u32>) {
    let t = gid.x;
    if (t < counts.y) {
        let s = slaves[t];
        slave_at[t] = vec2<f32>(r[s], z[s]);
    }
    let first = t * HISTORY_CHUNK;
    if (first >= counts.x) { return; }
    var sums = vec4<f32>(0.0);
    var best = 0.0;
    var best_i = first;
    for (var i = first; i < min(first + HISTORY_CHUNK, counts.x); i++) {
        let m = mass[i];
        let v2 = vr[i] * vr[i] + vz[i] * vz[i];
        sums = sums + vec4<f32>(0.5 * m * v2, m * energy[i], impulse[i], m * vz[i]);
        let speed = sqrt(v2);
        if (speed > best) {
            best = speed;
            best_i = i;
        }
    }
    let at = 8u * t;
    partials[at] = sums.x;
    partials[at + 1u] = sums.y;
    partials[at + 2u] = sums.z;
    partials[at + 3u] = best;
    partials[at + 4u] = bitcast<f32>(best_i);
    partials[at + 5u] = r[best_i];
    partials[at + 6u] = z[best_i];
    partials[at + 7u] = sums.w;
}
