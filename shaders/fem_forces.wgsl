// `fem_forces` (CPU twin: src/cpu/fem_forces.rs): per node, the forces of its elements through
// the node → element CSR, in CSR order. A gather, not a scatter: no float atomics, the same
// bits every run and the same sum as the CPU. FemUniform comes from the prelude
// (src/gpu/params.rs).

@group(0) @binding(0) var<uniform> u: FemUniform;
@group(0) @binding(1) var<storage, read> elem_offsets: array<u32>;
// 3·element + local index.
@group(0) @binding(2) var<storage, read> elem_refs: array<u32>;
// Elements.force, [f32; 6] per element.
@group(0) @binding(3) var<storage, read> force: array<f32>;
@group(0) @binding(4) var<storage, read_write> fr: array<f32>;
@group(0) @binding(5) var<storage, read_write> fz: array<f32>;

@compute @workgroup_size(WG)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let n = gid.x;
    if (n >= u.n_nodes) { return; }
    var sum = vec2<f32>(0.0);
    for (var k = elem_offsets[n]; k < elem_offsets[n + 1u]; k++) {
        let code = elem_refs[k];
        let at = 6u * (code / 3u) + 2u * (code % 3u);
        sum = sum + vec2<f32>(force[at], force[at + 1u]);
    }
    fr[n] = sum.x;
    fz[n] = sum.y;
}
