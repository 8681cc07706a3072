// The cell grid of the neighbour search (src/cpu/neighbours.rs, shaders/neighbours.wgsl):
// square cells of half the list radius (the kernel support, plus the skin on the GPU), numbered row by row (z outer, r inner); a neighbour
// loop visits the 5x5 cells around a particle's cell, row by row, and within a row the
// particles sorted[cell_start[row + r_lo] .. cell_start[row + r_hi + 1]] (ascending index
// inside each cell), exactly as CellGrid::for_each_candidate does on the CPU.

struct GridInfo {
    // Bounds of the particle cloud as order-preserving u32 keys (float_key), built by atomics.
    r_max_key: u32,
    z_min_key: u32,
    z_max_key: u32,
    n_r: u32,
    n_z: u32,
    cell: f32,
    z0: f32,
    // Cells in use (n_r * n_z) and the capacity cell_start was allocated for (minus one).
    cells: u32,
    capacity: u32,
    // 1 when the cloud needed more cells than the capacity and the grid was coarsened.
    overflow: u32,
    // Radius of the neighbour lists: the support grown by the skin (src/gpu/neighbours.rs),
    // set once by the host; the cells are half of it.
    list_radius: f32,
    // Largest squared displacement of a particle since the lists were built (f32 bits;
    // integrate.wgsl `watch`), read back every step to decide the next rebuild.
    moved2: u32,
}

// Cell (ir, iz) of a position, clamped into the grid as on the CPU.
fn grid_cell(g: GridInfo, r: f32, z: f32) -> vec2<u32> {
    let ir = min(u32(max(r / g.cell, 0.0)), g.n_r - 1u);
    let iz = min(u32(max((z - g.z0) / g.cell, 0.0)), g.n_z - 1u);
    return vec2<u32>(ir, iz);
}

// The cells a neighbour sweep around cell c visits, GRID_REACH each way clipped to the grid:
// (r_lo, r_hi, z_lo, z_hi), inclusive.
fn grid_window(g: GridInfo, c: vec2<u32>) -> vec4<u32> {
    let r_lo = select(c.x - GRID_REACH, 0u, c.x < GRID_REACH);
    let r_hi = min(c.x + GRID_REACH, g.n_r - 1u);
    let z_lo = select(c.y - GRID_REACH, 0u, c.y < GRID_REACH);
    let z_hi = min(c.y + GRID_REACH, g.n_z - 1u);
    return vec4<u32>(r_lo, r_hi, z_lo, z_hi);
}
