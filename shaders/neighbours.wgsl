// `neighbours` (CPU twin: src/cpu/neighbours.rs, `run`): bin the particles into the cell grid
// of grid.wgsl with a counting sort, and leave the same `cell_start` and `sorted` as the CPU
// for the same cell size (half the list radius):
//
//   bounds      the cloud's r_max, z_min, z_max (each thread folds a share, then atomics on
//               order-preserving keys: order-independent, so deterministic)
//   setup       one thread: the grid's shape from the bounds; the keys reset for the next step
//   clear       every cell count to zero
//   count       per particle: its cell, its arrival rank in it (atomicAdd), and its position
//               (the lists' reference for the displacement watch)
//   (scan.wgsl)  prefix sum of the counts: cell_start
//   scatter     per particle: sorted[cell_start[cell] + rank] = particle
//   sort_cells  per cell: its short segment sorted by particle index, so the arrival order
//               of the atomics (which varies between runs) leaves no trace (gpu-notes.md)
//   (neighbour_list.wgsl) the lists
//
// That build runs when the lists may have gone stale: they hold every particle within the
// support grown by a skin, so they stay complete until some particle has moved half the skin
// (src/gpu/step.rs LIST_SKIN). Every step `pack` refreshes the packed kinematics the gathers read
// and `displacement`, after the integration, measures how far the particles have moved.
//
// The grid is allocated once for `capacity` cells; a cloud that needs more (it has spread far)
// gets cells coarsened by powers of two until it fits: the 5x5-cell search then still covers
// the support, only with more candidates. Needs grid.wgsl.

@group(0) @binding(0) var<uniform> u: SphUniform;
@group(0) @binding(1) var<storage, read_write> grid: GridBuild;
@group(0) @binding(2) var<storage, read_write> cell_start: array<atomic<u32>>;
@group(0) @binding(3) var<storage, read_write> sorted: array<u32>;
@group(0) @binding(4) var<storage, read_write> cell_of: array<u32>;
@group(0) @binding(5) var<storage, read_write> rank: array<u32>;
@group(0) @binding(6) var<storage, read> r: array<f32>;
@group(0) @binding(7) var<storage, read> z: array<f32>;
@group(0) @binding(8) var<storage, read> vr: array<f32>;
@group(0) @binding(9) var<storage, read> vz: array<f32>;
// (r, z, v_r, v_z) per particle for the gather passes (neighbour_loop.wgsl), written by `pack`.
@group(0) @binding(10) var<storage, read_write> kin: array<vec4<f32>>;
// Each particle's position when the lists were last built (written by `count`).
@group(0) @binding(11) var<storage, read_write> x_build: array<vec2<f32>>;
@group(0) @binding(12) var<storage, read> mass: array<f32>;
@group(0) @binding(13) var<storage, read> rho: array<f32>;
// Written by `pack` for the gathers: the per-radian mass m̃ = m/(2π r) and the planar area m̃/ρ.
@group(0) @binding(14) var<storage, read_write> m_tilde: array<f32>;
@group(0) @binding(15) var<storage, read_write> area: array<f32>;
// And what sph_rates reads of a neighbour, packed for one load: (m̃/ρ, (m̃/ρ) ρ, m̃, r floored as
// hoop_radius floors it).
@group(0) @binding(16) var<storage, read_write> rate_pair: array<vec4<f32>>;

// 2π in f32, as the CPU's 2.0 * std::f32::consts::PI.
const TWO_PI: f32 = 2.0 * PI;

// GridInfo of grid.wgsl with atomic bound keys (the build's view of the same buffer).
struct GridBuild {
    r_max_key: atomic<u32>,
    z_min_key: atomic<u32>,
    z_max_key: atomic<u32>,
    n_r: u32,
    n_z: u32,
    cell: f32,
    z0: f32,
    cells: u32,
    capacity: u32,
    overflow: u32,
    list_radius: f32,
    moved2: atomic<u32>,
}

// Each thread folds the particles gid, gid + stride, … (gpu::Kernel::dispatch_fold), then one
// atomic per bound.
@compute @workgroup_size(WG)
fn bounds(@builtin(global_invocation_id) gid: vec3<u32>,
          @builtin(num_workgroups) groups: vec3<u32>) {
    // Identities of the reduction: r_max starts at 0 as on the CPU.
    var kr = float_key(0.0);
    var klo = 0xffffffffu;
    var khi = 0u;
    for (var i = gid.x; i < u.n; i += groups.x * WG) {
        let kz = float_key(z[i]);
        kr = max(kr, float_key(r[i]));
        klo = min(klo, kz);
        khi = max(khi, kz);
    }
    atomicMax(&grid.r_max_key, kr);
    atomicMin(&grid.z_min_key, klo);
    atomicMax(&grid.z_max_key, khi);
}

// Cells along one axis for an extent, as the CPU: (extent / cell) as u32 + 1, capped.
fn axis_cells(extent: f32, cell: f32) -> u32 {
    return min(u32(clamp(extent / cell, 0.0, f32(MAX_CELLS_PER_AXIS))) + 1u, MAX_CELLS_PER_AXIS);
}

@compute @workgroup_size(1)
fn setup() {
    let r_max = key_float(atomicLoad(&grid.r_max_key));
    let z_min = key_float(atomicLoad(&grid.z_min_key));
    let z_max = key_float(atomicLoad(&grid.z_max_key));
    // Half the list radius: with no skin, half the support (2h), the CPU's cell.
    var cell = 0.5 * grid.list_radius;
    var n_r = axis_cells(r_max, cell);
    var n_z = axis_cells(z_max - z_min, cell);
    var overflow = 0u;
    // n_r, n_z ≤ 2^14, so the product fits a u32. 40 doublings shrink any finite cloud to one
    // cell; the cap only matters for a non-finite one (the step stops on it anyway), which
    // must still leave the arrays in bounds.
    for (var k = 0u; k < 40u && n_r * n_z > grid.capacity; k++) {
        cell = 2.0 * cell;
        n_r = axis_cells(r_max, cell);
        n_z = axis_cells(z_max - z_min, cell);
        overflow = 1u;
    }
    if (n_r * n_z > grid.capacity) {
        n_r = min(n_r, grid.capacity);
        n_z = max(grid.capacity / n_r, 1u);
    }
    grid.n_r = n_r;
    grid.n_z = n_z;
    grid.cell = cell;
    grid.z0 = z_min;
    grid.cells = n_r * n_z;
    grid.overflow = overflow;
    atomicStore(&grid.r_max_key, float_key(0.0));
    atomicStore(&grid.z_min_key, 0xffffffffu);
    atomicStore(&grid.z_max_key, 0u);
}

// Grid-stride loops below: the cell arrays may need more threads than one dispatch dimension
// has workgroups. Only the cells in use are cleared: what the scan leaves beyond them is stale
// but never read, and a prefix sum carries nothing backwards.
@compute @workgroup_size(WG)
fn clear(@builtin(global_invocation_id) gid: vec3<u32>,
         @builtin(num_workgroups) groups: vec3<u32>) {
    for (var c = gid.x; c <= grid.cells; c += groups.x * WG) {
        atomicStore(&cell_start[c], 0u);
    }
}

// The GridInfo view of the build's state, for grid_cell.
fn info() -> GridInfo {
    return GridInfo(0u, 0u, 0u, grid.n_r, grid.n_z, grid.cell, grid.z0, grid.cells,
                    grid.capacity, grid.overflow, grid.list_radius, 0u);
}

// Cell c counts into slot c + 1, so that the inclusive scan of the slots (scan.wgsl) leaves
// cell_start[c] = Σ_{k<c} count[k], with cell_start[0] = 0 and cell_start[cells] = n.
@compute @workgroup_size(WG)
fn count(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if (i >= u.n) { return; }
    let g = info();
    let c = grid_cell(g, r[i], z[i]);
    let cell = c.y * g.n_r + c.x;
    cell_of[i] = cell;
    rank[i] = atomicAdd(&cell_start[cell + 1u], 1u);
    x_build[i] = vec2<f32>(r[i], z[i]);
}

// Every step, before the gathers: the packed kinematics, the areas (cpu::sph_rates::run's
// first loop) and sph_rates' packed neighbour data, and the displacement watch reset.
@compute @workgroup_size(WG)
fn pack(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if (i == 0u) {
        atomicStore(&grid.moved2, 0u);
    }
    if (i >= u.n) { return; }
    kin[i] = vec4<f32>(r[i], z[i], vr[i], vz[i]);
    let ri = hoop_radius(r[i], u.kernel.h);
    let mt = mass[i] / (TWO_PI * ri);
    let a = mt / rho[i];
    m_tilde[i] = mt;
    area[i] = a;
    rate_pair[i] = vec4<f32>(a, a * rho[i], mt, ri);
}

@compute @workgroup_size(WG)
fn scatter(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if (i >= u.n) { return; }
    sorted[atomicLoad(&cell_start[cell_of[i]]) + rank[i]] = i;
}

// Insertion sort of each cell's segment (a few particles) by index.
@compute @workgroup_size(WG)
fn sort_cells(@builtin(global_invocation_id) gid: vec3<u32>,
              @builtin(num_workgroups) groups: vec3<u32>) {
    for (var c = gid.x; c < grid.cells; c += groups.x * WG) {
        let start = atomicLoad(&cell_start[c]);
        let end = atomicLoad(&cell_start[c + 1u]);
        for (var k = start + 1u; k < end; k++) {
            let v = sorted[k];
            var m = k;
            while (m > start && sorted[m - 1u] > v) {
                sorted[m] = sorted[m - 1u];
                m -= 1u;
            }
            sorted[m] = v;
        }
    }
}
