// Bindings 0–6 of every pass that gathers over the neighbour lists (sph_rates, sph_filter,
// sph_forces): what neighbour_loop.wgsl walks, read-only. The host binds them with
// GpuGrid::walk_bindings (src/gpu/neighbours.rs); each pass declares its own from 7 on.
// (The list pass, neighbour_list.wgsl, writes nbr and nbr_count and declares its own.)

@group(0) @binding(0) var<uniform> u: SphUniform;
@group(0) @binding(1) var<storage, read> grid: GridInfo;
@group(0) @binding(2) var<storage, read> cell_start: array<u32>;
@group(0) @binding(3) var<storage, read> sorted: array<u32>;
// Each particle's (r, z, v_r, v_z), packed by the neighbours pass (or filtered by sph_filter).
@group(0) @binding(4) var<storage, read> kin: array<vec4<f32>>;
@group(0) @binding(5) var<storage, read> nbr: array<u32>;
@group(0) @binding(6) var<storage, read> nbr_count: array<u32>;
