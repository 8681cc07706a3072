// The neighbour loop of the gather passes (sph_rates, sph_forces), in the order of
// cpu::neighbours::for_each_neighbour: the candidates in the 5x5 cells around particle i row by
// row as real neighbours (j != i), then, near the axis, the same candidates as mirror ghosts
// across r = 0 (j = i too; a ghost is never nearer than its particle, so the same candidates
// hold them).
//
// The `list` entry point (neighbour_list.wgsl) walks the grid once per step and stores what it
// finds; the gather passes then walk that list, so their bodies run for the ~30 neighbours
// only, not for every one of the ~56 candidates (on a SIMD-on-CPU adapter such as lavapipe a
// masked-off lane still costs the body). A particle with more than NBR_MAX neighbours is walked
// on the grid instead: the same neighbours in the same order.
//
// Needs grid.wgsl. Declared before it (gather_bindings.wgsl for the gather passes,
// neighbour_list.wgsl for the list pass, which writes the lists): `u: SphUniform`, `grid: GridInfo`,
// `cell_start`, `sorted`, `kin` (each particle's (r, z, v_r, v_z), packed by the neighbours
// pass so that a neighbour's position and velocity come in one load), `nbr`, `nbr_count`, a
// struct `Gather` and
//   fn neighbour(g: ptr<function, Gather>, i: u32, j: u32, d: vec2<f32>, dist: f32, sign: f32)
// called with the separation d = x_i − x_j (x_j mirrored when sign = −1).

// A list entry's flag for a mirror ghost; the rest of the word is the particle.
const NBR_MIRROR: u32 = 0x80000000u;

// The pair term of particle j (mirrored when `mirror`), if within the support of i at xi.
fn visit(g: ptr<function, Gather>, i: u32, xi: vec2<f32>, j: u32, mirror: bool, s2: f32) {
    let sign = select(1.0, -1.0, mirror);
    let xj = kin[j].xy;
    let dr = xi.x - sign * xj.x;
    let dz = xi.y - xj.y;
    let d2 = dr * dr + dz * dz;
    if (d2 < s2 && (mirror || j != i)) {
        neighbour(g, i, j, vec2<f32>(dr, dz), sqrt(d2), sign);
    }
}

// Walk the grid's 5x5 cells: the real sweep for `rows` rows from z_lo, then the ghost sweep for
// `ghost_rows`. The sweeps are loops, not ifs, so that a sweep of no rows costs nothing on a
// masked SIMD adapter.
fn grid_sweeps(g: ptr<function, Gather>, i: u32, xi: vec2<f32>, s2: f32, real: bool,
               ghosts: bool) {
    let info = grid;
    let w = grid_window(info, grid_cell(info, xi.x, xi.y));
    let r_lo = w.x;
    let r_hi = w.y;
    let z_lo = w.z;
    let z_hi = w.w;
    let real_end = select(z_lo, z_hi + 1u, real);
    for (var cz = z_lo; cz < real_end; cz++) {
        let row = cz * info.n_r;
        let end = cell_start[row + r_hi + 1u];
        for (var k = cell_start[row + r_lo]; k < end; k++) {
            visit(g, i, xi, sorted[k], false, s2);
        }
    }
    let ghost_end = select(z_lo, z_hi + 1u, ghosts);
    for (var cz = z_lo; cz < ghost_end; cz++) {
        let row = cz * info.n_r;
        let end = cell_start[row + r_hi + 1u];
        for (var k = cell_start[row + r_lo]; k < end; k++) {
            visit(g, i, xi, sorted[k], true, s2);
        }
    }
}

// Every neighbour of i: from its list, or from the grid when the list overflowed.
fn for_each_neighbour(g: ptr<function, Gather>, i: u32) {
    let support = 2.0 * u.kernel.h;
    let s2 = support * support;
    let xi = kin[i].xy;
    let count = nbr_count[i];
    let listed = select(count, 0u, count > NBR_MAX);
    for (var k = 0u; k < listed; k++) {
        let e = nbr[k * u.n + i];
        visit(g, i, xi, e & ~NBR_MIRROR, (e & NBR_MIRROR) != 0u, s2);
    }
    let overflow = count > NBR_MAX;
    grid_sweeps(g, i, xi, s2, overflow, overflow && xi.x < support);
}
