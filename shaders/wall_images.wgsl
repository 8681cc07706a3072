// The image loop of the gathers that complete the lining's kernel (sph_rates, sph_forces;
// CPU twin: src/cpu/wall.rs `images`): particle i's own image, then its listed neighbours'
// (mirror entries skipped), each on the concrete's side of i's wall and within the support.
// An image is never nearer to i than its source, so i's neighbours hold every image in reach.
// Needs wall.wgsl, gather_bindings.wgsl and neighbour_loop.wgsl; the pass declares
//   fn image(g: ptr<function, Gather>, i: u32, j: u32, w: Wall, d: vec2<f32>, dist: f32,
//            r_image: f32)
// called with d = x_i − x_image and the image's radius (≥ 0).

// Each particle's wall (walls.wgsl `find`), binding 30 of every gather that takes images.
@group(0) @binding(30) var<storage, read> walls: array<Wall>;

fn image_visit(g: ptr<function, Gather>, i: u32, xi: vec2<f32>, w: Wall, j: u32, s2: f32) {
    let xj = kin[j].xy;
    let side = (xj.x - w.q.x) * w.n.x + (xj.y - w.q.y) * w.n.y;
    if (side <= 0.0) {
        return;
    }
    let gr = xj.x - 2.0 * side * w.n.x;
    let gz = xj.y - 2.0 * side * w.n.y;
    let d = vec2<f32>(xi.x - gr, xi.y - gz);
    let d2 = d.x * d.x + d.y * d.y;
    if (d2 < s2) {
        image(g, i, j, w, d, sqrt(d2), max(gr, 0.0));
    }
}

fn for_each_image(g: ptr<function, Gather>, i: u32, w: Wall) {
    let support = 2.0 * u.kernel.h;
    let s2 = support * support;
    let xi = kin[i].xy;
    image_visit(g, i, xi, w, i, s2);
    let count = nbr_count[i];
    let listed = select(count, 0u, count > NBR_MAX);
    for (var k = 0u; k < listed; k++) {
        let e = nbr[k * u.n + i];
        if ((e & NBR_MIRROR) == 0u) {
            image_visit(g, i, xi, w, e, s2);
        }
    }
    // An overflowed list: the grid's candidates, as neighbour_loop.wgsl's real sweep.
    let overflow = count > NBR_MAX;
    let info = grid;
    let cells = grid_window(info, grid_cell(info, xi.x, xi.y));
    let end_row = select(cells.z, cells.w + 1u, overflow);
    for (var cz = cells.z; cz < end_row; cz++) {
        let row = cz * info.n_r;
        let end = cell_start[row + cells.y + 1u];
        for (var k = cell_start[row + cells.x]; k < end; k++) {
            let j = sorted[k];
            if (j != i) {
                image_visit(g, i, xi, w, j, s2);
            }
        }
    }
}

// Particle i's wall, if it has one and the scene takes images.
fn wall_of(i: u32) -> Wall {
    var w = no_wall();
    if (IMAGES) {
        w = walls[i];
    }
    return w;
}
