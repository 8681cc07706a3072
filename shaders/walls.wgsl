// `walls` (CPU twin: src/cpu/wall.rs): the wall images' two passes.
//
//   find   per particle: its wall, the nearest point of the master chain within the support
//          and outside the projectile (`find_one`), NO_WALL where it has none. Particles
//          outside the projectile's box (the integration's, before the correction's shift)
//          grown by `box_margin` have none and skip the search.
//   sums   one workgroup per master segment: Σ w_a f and Σ w_b f of the ring forces f the
//          images exerted on the particles whose foot is on it (sph_forces' wall_force),
//          reversed into the segment's entries of the nodal forces past the elements'
//          (`force[6 (n_elements + m) ..]`, which the integration gathers through the node CSR
//          as the CPU's `react` adds them). The candidates are the grid's cells around the
//          segment grown by `grow` (the support and the lists' skin: a particle is within the
//          support of its foot and within half the skin of where the lists binned it); each
//          thread sums its share in the grid's order, then a fixed tree adds the shares, so a
//          run repeats to the bit. Before it overwrites them it books the entries the last
//          integration took over its Δt into `wall_impulse` (as the CPU's `integrate` books
//          them with the contact's impulse).
// Needs params.wgsl, grid.wgsl and wall.wgsl.

struct Master {
    element: u32,
    a: u32,
    b: u32,
    c: u32,
}

@group(0) @binding(0) var<uniform> u: WallUniform;
// The particles' (r, z, v_r, v_z), packed by the neighbours pass this step.
@group(0) @binding(1) var<storage, read> kin: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read> masters: array<Master>;
@group(0) @binding(3) var<storage, read> node_r: array<f32>;
@group(0) @binding(4) var<storage, read> node_z: array<f32>;
@group(0) @binding(5) var<storage, read> node_vr: array<f32>;
@group(0) @binding(6) var<storage, read> node_vz: array<f32>;
// The contact's box keys (r_max, z_min, z_max at 4 box_slot.slot; integrate.wgsl).
@group(0) @binding(7) var<storage, read> box_keys: array<u32>;
@group(0) @binding(8) var<uniform> box_slot: DtSlot;
@group(0) @binding(9) var<storage, read_write> walls: array<Wall>;
@group(0) @binding(10) var<storage, read> grid: GridInfo;
@group(0) @binding(11) var<storage, read> cell_start: array<u32>;
@group(0) @binding(12) var<storage, read> sorted: array<u32>;
@group(0) @binding(13) var<storage, read> wall_force: array<vec2<f32>>;
@group(0) @binding(14) var<storage, read_write> force: array<f32>;
// The step's clock (dt_bits at word 0: the Δt the last integration took), and per segment the
// z-impulse its reaction has given the projectile (N s).
@group(0) @binding(15) var<storage, read> clock: array<u32>;
@group(0) @binding(16) var<storage, read_write> wall_impulse: array<f32>;

@compute @workgroup_size(WG)
fn find(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if (i >= u.n_particles) { return; }
    let p = kin[i].xy;
    let box = 4u * box_slot.slot;
    let reach = u.support + u.box_margin;
    if (p.x > key_float(box_keys[box]) + reach || p.y < key_float(box_keys[box + 1u]) - reach
        || p.y > key_float(box_keys[box + 2u]) + reach) {
        walls[i].seg = NO_WALL;
        return;
    }
    var best = NO_WALL;
    var best_d = 0.0;
    var best_t = 0.0;
    for (var k = 0u; k < u.n_masters; k++) {
        let m = masters[k];
        let a = vec2<f32>(node_r[m.a], node_z[m.a]);
        let e = vec2<f32>(node_r[m.b], node_z[m.b]) - a;
        let t = clamp(((p.x - a.x) * e.x + (p.y - a.y) * e.y) / (e.x * e.x + e.y * e.y), 0.0, 1.0);
        let d = length(vec2<f32>(a.x + t * e.x - p.x, a.y + t * e.y - p.y));
        if (best == NO_WALL || d < best_d) {
            best = k;
            best_d = d;
            best_t = t;
        }
    }
    if (best == NO_WALL || best_d >= u.support || best_d <= 0.0) {
        walls[i] = no_wall();
        return;
    }
    let m = masters[best];
    let a = vec2<f32>(node_r[m.a], node_z[m.a]);
    let e = vec2<f32>(node_r[m.b], node_z[m.b]) - a;
    let t = best_t;
    let len = length(e);
    // The projectile lies left of A → B: the outward normal is (e_z, −e_r)/|e|.
    let s = vec2<f32>(e.y / len, -e.x / len);
    let q = vec2<f32>(a.x + t * e.x, a.y + t * e.y);
    if ((p.x - q.x) * s.x + (p.y - q.y) * s.y <= 0.0) {
        // Inside: the contact's to correct.
        walls[i] = no_wall();
        return;
    }
    // Off a segment's end the nearest point is a node: the normal points at the particle.
    var n = s;
    if (!(t > 0.0 && t < 1.0)) {
        n = vec2<f32>((p.x - q.x) / best_d, (p.y - q.y) / best_d);
    }
    let wa = 1.0 - t;
    let wb = t;
    let v = vec2<f32>(wa * node_vr[m.a] + wb * node_vr[m.b], wa * node_vz[m.a] + wb * node_vz[m.b]);
    walls[i] = Wall(best, m.a, m.b, wa, vec2<f32>(q.x - u.offset * n.x, q.y - u.offset * n.y), n,
        v, wb, 0.0);
}

var<workgroup> shares: array<vec4<f32>, WG>;

@compute @workgroup_size(WG)
fn sums(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) t: u32) {
    let m = wid.x;
    let seg = masters[m];
    let a = vec2<f32>(node_r[seg.a], node_z[seg.a]);
    let b = vec2<f32>(node_r[seg.b], node_z[seg.b]);
    let lo = min(a, b) - vec2<f32>(u.grow);
    let hi = max(a, b) + vec2<f32>(u.grow);
    let info = grid;
    let c_lo = grid_cell(info, lo.x, lo.y);
    let c_hi = grid_cell(info, hi.x, hi.y);
    var s = vec4<f32>(0.0);
    for (var cz = c_lo.y; cz <= c_hi.y; cz++) {
        let row = cz * info.n_r;
        let end = cell_start[row + c_hi.x + 1u];
        for (var k = cell_start[row + c_lo.x] + t; k < end; k += WG) {
            let j = sorted[k];
            if (walls[j].seg == m) {
                let w = walls[j];
                let f = wall_force[j];
                s += vec4<f32>(w.wa * f.x, w.wa * f.y, w.wb * f.x, w.wb * f.y);
            }
        }
    }
    shares[t] = s;
    workgroupBarrier();
    for (var half = WG / 2u; half > 0u; half = half / 2u) {
        if (t < half) {
            shares[t] = shares[t] + shares[t + half];
        }
        workgroupBarrier();
    }
    if (t == 0u) {
        let at = 6u * (u.n_elements + m);
        wall_impulse[m] += (force[at + 1u] + force[at + 3u]) * bitcast<f32>(clock[0]);
        let total = shares[0];
        force[at] = -total.x;
        force[at + 1u] = -total.y;
        force[at + 2u] = -total.z;
        force[at + 3u] = -total.w;
    }
}
