// `list` (part of the neighbours pass; CPU twin: cpu::neighbours::for_each_neighbour with the
// list radius for the support): per particle, the particles within the list radius in the
// order the gather passes visit them, column-major
// (nbr[k * n + i]: neighbouring threads read neighbouring words), and their count, which
// exceeds NBR_MAX when the list overflowed (the gathers then walk the grid). Needs params.wgsl,
// grid.wgsl and neighbour_loop.wgsl.

@group(0) @binding(0) var<uniform> u: SphUniform;
@group(0) @binding(1) var<storage, read> grid: GridInfo;
@group(0) @binding(2) var<storage, read> cell_start: array<u32>;
@group(0) @binding(3) var<storage, read> sorted: array<u32>;
@group(0) @binding(4) var<storage, read> kin: array<vec4<f32>>;
@group(0) @binding(5) var<storage, read_write> nbr: array<u32>;
@group(0) @binding(6) var<storage, read_write> nbr_count: array<u32>;

struct Gather {
    count: u32,
}

fn neighbour(g: ptr<function, Gather>, i: u32, j: u32, d: vec2<f32>, dist: f32, sign: f32) {
    let k = (*g).count;
    if (k < NBR_MAX) {
        nbr[k * u.n + i] = select(j, j | NBR_MIRROR, sign < 0.0);
    }
    (*g).count = k + 1u;
}

@compute @workgroup_size(WG)
fn list(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if (i >= u.n) { return; }
    var g = Gather(0u);
    let radius = grid.list_radius;
    let xi = kin[i].xy;
    grid_sweeps(&g, i, xi, radius * radius, true, xi.x < radius);
    nbr_count[i] = g.count;
}
