// `contact_detect` (CPU twin: src/cpu/contact_detect.rs): each preselected slave particle is
// tested against the master triangles; a slave inside one is a hit (the nearest segment AB
// wins) and is appended to the hit list. The append order varies between runs; the host sorts
// the hits by slave index before correcting, so the result does not. Then the hits' slave
// kinematics are gathered for the read-back, and after the host's correction `apply` writes the
// corrected slaves back. Needs params.wgsl and step.wgsl.

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
@group(0) @binding(7) var<storage, read> nr: array<f32>;
@group(0) @binding(8) var<storage, read> nz: array<f32>;
// hits[0]: the count; then (slave, master) pairs.
@group(0) @binding(9) var<storage, read_write> hits: array<atomic<u32>>;
// Per hit: (r, z, vr, vz) of the slave, gathered for the read-back; and, written by the host,
// [count, then per hit (slave, r, z, vr, vz)] for `apply`.
@group(0) @binding(10) var<storage, read_write> hit_data: array<vec4<f32>>;
@group(0) @binding(11) var<storage, read> fixes: array<u32>;
// Bounding box of the projectile: r_max, z_min, z_max.
@group(0) @binding(12) var<storage, read_write> bounds: array<f32>;

var<workgroup> box_r: array<f32, WG>;
var<workgroup> box_lo: array<f32, WG>;
var<workgroup> box_hi: array<f32, WG>;

// One workgroup: the projectile's bounding box, and the hit count reset.
@compute @workgroup_size(WG)
fn bounding_box(@builtin(local_invocation_index) local: u32) {
    var r_max = 0.0;
    var z_lo = 3.4028235e38;
    var z_hi = -3.4028235e38;
    for (var i = local; i < u.n_nodes; i += WG) {
        r_max = max(r_max, nr[i]);
        z_lo = min(z_lo, nz[i]);
        z_hi = max(z_hi, nz[i]);
    }
    box_r[local] = r_max;
    box_lo[local] = z_lo;
    box_hi[local] = z_hi;
    workgroupBarrier();
    for (var stride = WG / 2u; stride > 0u; stride = stride >> 1u) {
        if (local < stride) {
            box_r[local] = max(box_r[local], box_r[local + stride]);
            box_lo[local] = min(box_lo[local], box_lo[local + stride]);
            box_hi[local] = max(box_hi[local], box_hi[local + stride]);
        }
        workgroupBarrier();
    }
    if (local == 0u) {
        bounds[0] = box_r[0];
        bounds[1] = box_lo[0];
        bounds[2] = box_hi[0];
        atomicStore(&hits[0], 0u);
    }
}

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
    if (p.x > bounds[0] || p.y < bounds[1] || p.y > bounds[2]) { return; }
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
        }
    }
}

// Per hit: the slave's position and velocity for the read-back.
@compute @workgroup_size(WG)
fn gather(@builtin(global_invocation_id) gid: vec3<u32>) {
    let k = gid.x;
    if (k >= min(atomicLoad(&hits[0]), u.n_slaves)) { return; }
    let s = atomicLoad(&hits[1u + 2u * k]);
    hit_data[k] = vec4<f32>(pr[s], pz[s], pvr[s], pvz[s]);
}

// Per corrected slave (written by the host): its new position and velocity.
@compute @workgroup_size(WG)
fn apply(@builtin(global_invocation_id) gid: vec3<u32>) {
    let k = gid.x;
    if (k >= fixes[0]) { return; }
    let base = 1u + 5u * k;
    let s = fixes[base];
    pr[s] = bitcast<f32>(fixes[base + 1u]);
    pz[s] = bitcast<f32>(fixes[base + 2u]);
    pvr[s] = bitcast<f32>(fixes[base + 3u]);
    pvz[s] = bitcast<f32>(fixes[base + 4u]);
}
