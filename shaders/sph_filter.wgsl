// `sph_filter` (CPU twin: src/cpu/sph_filter.rs): with
// `target.velocity_filter = "linear"`, each particle's velocity moved by the kernel-weighted
// mean of its neighbours' departures from the linear field that the first `gradient` dispatch
// fitted at it, v̄_i = v_i + Σ_j A_j W_ij (v_j − v_i − L_i (x_j − x_i)) / Σ_j A_j W_ij (i itself
// in the weights, with no departure). Written as (r, z, v̄_r, v̄_z), the layout of `kin`, so
// that the second `gradient` dispatch reads it in kin's place.
// Needs params.wgsl, grid.wgsl, gather_bindings.wgsl (bindings 0–6) and
// neighbour_loop.wgsl.

@group(0) @binding(7) var<storage, read> area: array<f32>;
@group(0) @binding(8) var<storage, read> l_rr: array<f32>;
@group(0) @binding(9) var<storage, read> l_rz: array<f32>;
@group(0) @binding(10) var<storage, read> l_zr: array<f32>;
@group(0) @binding(11) var<storage, read> l_zz: array<f32>;
@group(0) @binding(12) var<storage, read_write> kin_filtered: array<vec4<f32>>;

// L at i (rr, rz, zr, zz) and v_i, loaded once; the weights and weighted departures summed.
struct Gather {
    l: vec4<f32>,
    v: vec2<f32>,
    weight: f32,
    sum: vec2<f32>,
}

fn neighbour(acc: ptr<function, Gather>, i: u32, j: u32, d: vec2<f32>, dist: f32, sign: f32) {
    let w = kernel_w(u.kernel, dist) * area[j];
    let vj = kin[j].zw;
    let l = (*acc).l;
    // x_j − x_i = −d, in the CPU's order.
    let dep_r = sign * vj.x - (*acc).v.x + l.x * d.x + l.y * d.y;
    let dep_z = vj.y - (*acc).v.y + l.z * d.x + l.w * d.y;
    (*acc).weight += w;
    (*acc).sum += vec2<f32>(w * dep_r, w * dep_z);
}

@compute @workgroup_size(WG)
fn filter_velocity(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if (i >= u.n) { return; }
    let ki = kin[i];
    var acc = Gather(
        vec4<f32>(l_rr[i], l_rz[i], l_zr[i], l_zz[i]),
        ki.zw,
        kernel_w(u.kernel, 0.0) * area[i],
        vec2<f32>(0.0),
    );
    for_each_neighbour(&acc, i);
    kin_filtered[i] = vec4<f32>(ki.xy, ki.zw + acc.sum / acc.weight);
}
