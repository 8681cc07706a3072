// `contact_detect` (CPU twin: src/cpu/contact_detect.rs): each preselected slave particle inside
// the projectile's bounding box (the integration's, which also empties the hit list) is tested
// against the master triangles; a slave inside one is a hit (the nearest segment AB wins) and
// is appended to the hit list with its kinematics and its segment's two nodes' for the
// read-back. The append order varies between runs; the host sorts the hits by slave index before
// correcting, so the result does not. After the host's correction `apply` writes back the
// corrected slaves and the nodes it touched, and adds the global shift to every other node;
// `recentre` then moves every position as `Model::recentre` does on the host.
// Needs params.wgsl and step.wgsl.

struct Master {
    element: u32,
    a: u32,
    b: u32,
    c: u32,
}

@group(0) @binding(0) var<uniform> u: StepUniform;
@group(0) @binding(1) var<storage, read> slaves: array<u32>;
@group(0) @binding(2) var<storage, read> masters: array<Master>;
@group(0) @binding(3) var<storage, read_write> pr: array<f32>;
@group(0) @binding(4) var<storage, read_write> pz: array<f32>;
@group(0) @binding(5) var<storage, read_write> pvr: array<f32>;
@group(0) @binding(6) var<storage, read_write> pvz: array<f32>;
@group(0) @binding(7) var<storage, read_write> nr: array<f32>;
@group(0) @binding(8) var<storage, read_write> nz: array<f32>;
// hits[0]: the count; then (slave, master) pairs.
@group(0) @binding(9) var<storage, read_write> hits: array<atomic<u32>>;
// Per hit, for the read-back: (r, z, vr, vz) of the slave, then of its segment's nodes A and B.
@group(0) @binding(10) var<storage, read_write> hit_data: array<vec4<f32>>;
// Written by the host for `apply`: [count, then per corrected slave (slave, r, z, vr, vz)].
@group(0) @binding(11) var<storage, read> fixes: array<u32>;
// The projectile's bounding box after this step's integration, as ordered keys (common.wgsl
// float_key): r_max, z_min, z_max at 4 box_slot.slot (integrate.wgsl `node` folds it there).
@group(0) @binding(12) var<storage, read> box_keys: array<u32>;
@group(0) @binding(13) var<uniform> box_slot: DtSlot;
@group(0) @binding(14) var<storage, read_write> nvr: array<f32>;
@group(0) @binding(15) var<storage, read_write> nvz: array<f32>;
// Written by the host for `apply`: [count, shift, shift·Δt (f32 bits), then per touched node in
// ascending order (node, r, z, vr, vz)]: the touched nodes' corrected values, the global shift
// already in them (contact.rs).
@group(0) @binding(16) var<storage, read> node_fixes: array<u32>;
// Written by the host for `recentre`: the shift along z.
@group(0) @binding(17) var<storage, read> recentre_by: array<f32>;

// Twice the signed area of (a, b, p): positive when p is left of a -> b.
fn orient(a: vec2<f32>, b: vec2<f32>, p: vec2<f32>) -> f32 {
    return (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
}

@compute @workgroup_size(WG)
fn detect(@builtin(global_invocation_id) gid: vec3<u32>) {
    let k = gid.x;
    if (k >= u.n_slaves) { return; }
    let s = slaves[k];
    let p = vec2<f32>(pr[s], pz[s]);
    let box = 4u * box_slot.slot;
    if (p.x > key_float(box_keys[box]) || p.y < key_float(box_keys[box + 1u])
        || p.y > key_float(box_keys[box + 2u])) {
        return;
    }
    var best = 0xffffffffu;
    var best_depth = 0.0;
    for (var m = 0u; m < u.n_masters; m++) {
        let seg = masters[m];
        let a = vec2<f32>(nr[seg.a], nz[seg.a]);
        let b = vec2<f32>(nr[seg.b], nz[seg.b]);
        let c = vec2<f32>(nr[seg.c], nz[seg.c]);
        // Material lies left of A -> B, so ABC is counter-clockwise.
        let d_ab = orient(a, b, p);
        if (d_ab < 0.0) { continue; }
        // Under AB, no deeper than C (the strip of AB: see the CPU twin).
        let e = b - a;
        let t = dot(p - a, e) / dot(e, e);
        if (t < 0.0 || t > 1.0 || d_ab > orient(a, b, c)) { continue; }
        let depth = d_ab / length(b - a);
        if (best == 0xffffffffu || depth < best_depth) {
            best = m;
            best_depth = depth;
        }
    }
    if (best != 0xffffffffu) {
        let slot = atomicAdd(&hits[0], 1u);
        if (slot < u.n_slaves) {
            atomicStore(&hits[1u + 2u * slot], s);
            atomicStore(&hits[2u + 2u * slot], best);
            let seg = masters[best];
            hit_data[3u * slot] = vec4<f32>(p, pvr[s], pvz[s]);
            hit_data[3u * slot + 1u] = vec4<f32>(nr[seg.a], nz[seg.a], nvr[seg.a], nvz[seg.a]);
            hit_data[3u * slot + 2u] = vec4<f32>(nr[seg.b], nz[seg.b], nvr[seg.b], nvz[seg.b]);
        }
    }
}

// Thread k writes back corrected slave k, and node k: its corrected values where the host
// touched it, else the global shift added as the host adds it (`v + s`, `z + s Δt` with s Δt
// rounded once on the host), so that the nodes are the host's to the bit. Dispatched over the
// larger of the two counts, once after each correction.
@compute @workgroup_size(WG)
fn apply(@builtin(global_invocation_id) gid: vec3<u32>) {
    let k = gid.x;
    if (k < fixes[0]) {
        let base = 1u + 5u * k;
        let s = fixes[base];
        pr[s] = bitcast<f32>(fixes[base + 1u]);
        pz[s] = bitcast<f32>(fixes[base + 2u]);
        pvr[s] = bitcast<f32>(fixes[base + 3u]);
        pvz[s] = bitcast<f32>(fixes[base + 4u]);
    }
    if (k >= u.n_nodes) { return; }
    let touched = node_fixes[0];
    for (var t = 0u; t < touched; t++) {
        let base = 3u + 5u * t;
        let node = node_fixes[base];
        if (node == k) {
            nr[k] = bitcast<f32>(node_fixes[base + 1u]);
            nz[k] = bitcast<f32>(node_fixes[base + 2u]);
            nvr[k] = bitcast<f32>(node_fixes[base + 3u]);
            nvz[k] = bitcast<f32>(node_fixes[base + 4u]);
            return;
        }
        if (node > k) { break; }
    }
    let shift = bitcast<f32>(node_fixes[1]);
    // The host skips a zero shift, which would turn a −0 velocity into +0.
    if (shift != 0.0) {
        nvz[k] = nvz[k] + shift;
        nz[k] = nz[k] + bitcast<f32>(node_fixes[2]);
    }
}

// Thread k moves particle k and node k along z by the host's shift of the model's origin
// (`Model::recentre`), after `apply` in the same submission, as the host moves its copies.
@compute @workgroup_size(WG)
fn recentre(@builtin(global_invocation_id) gid: vec3<u32>) {
    let k = gid.x;
    let by = recentre_by[0];
    if (k < u.n_particles) {
        pz[k] = pz[k] + by;
    }
    if (k < u.n_nodes) {
        nz[k] = nz[k] + by;
    }
}
