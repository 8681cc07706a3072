// `sph_rates` (CPU twin: src/cpu/sph_rates.rs): per particle, the velocity gradient
// L = G M⁻¹ gathered over neighbours and axis ghosts with planar areas m̃/ρ (physics.md §3),
// corrected where M is well conditioned, and the density rate ρ̇ = −ρ (L_rr + L_zz + v_r/r);
// with the Balsara switch on, each particle's factor on the viscosity from L. With CONJUGATE,
// L is the conjugate gradient (1/ρ_i) Σ m̃_j (v_j − v_i) ⊗ ∇W, uncorrected, and the hoop rate
// n_i v_r/r (sph_rates.rs). Both modes write the hoop weight
// n_i = Σ m̃_j (w_i + w_j − 2 r_i) ∂_r W_ij / ρ_i, which sph_forces and concrete read.
// With RECONSTRUCT, also each particle's corrected gradient of its own velocity, l_visc, for
// sph_forces' reconstructed viscosity: L itself, or with CONJUGATE a second G gathered with
// m̃_j/ρ_j and corrected by M.
// m̃ and m̃/ρ are the neighbours pass's (`pack`, this step's positions), which packs what a
// neighbour gives here for one load (`rate_pair`: m̃/ρ, (m̃/ρ) ρ, m̃, hoop_radius(r)).
// With IMAGES (contact.kernel = "images") the particles lining the projectile also gather over
// their wall images (wall_images.wgsl): the image of neighbour j moves as j mirrored in the
// wall's frame, sits at j's reflection, and weighs its own radius in the hoop weight.
// Needs params.wgsl, grid.wgsl, gather_bindings.wgsl (bindings 0–6), neighbour_loop.wgsl,
// wall.wgsl and wall_images.wgsl (binding 30).

@group(0) @binding(7) var<storage, read> rho: array<f32>;
@group(0) @binding(8) var<storage, read> sound: array<f32>;
@group(0) @binding(9) var<storage, read> rate_pair: array<vec4<f32>>;
@group(0) @binding(11) var<storage, read_write> l_rr: array<f32>;
@group(0) @binding(12) var<storage, read_write> l_rz: array<f32>;
@group(0) @binding(13) var<storage, read_write> l_zr: array<f32>;
@group(0) @binding(14) var<storage, read_write> l_zz: array<f32>;
@group(0) @binding(15) var<storage, read_write> drho: array<f32>;
@group(0) @binding(16) var<storage, read_write> visc_switch: array<f32>;
@group(0) @binding(17) var<storage, read_write> hoop_weight: array<f32>;
@group(0) @binding(18) var<storage, read_write> l_visc: array<vec4<f32>>;

// The Balsara switch is on (SphParams::balsara): a pipeline constant, as ART_STRESS in
// sph_forces.wgsl. Off, visc_switch keeps the 1 it was uploaded with.
override BALSARA: bool;
// target.velocity_gradient = "conjugate" (SphParams::conjugate_gradient).
override CONJUGATE: bool;
// target.viscosity_jump = "reconstructed" (SphParams::reconstruct_viscosity).
override RECONSTRUCT: bool;
// contact.kernel = "images": the walls pass has found each particle's wall.
override IMAGES: bool;

// G = Σ (m̃_j/ρ_j)(v_j − v_i) ⊗ ∇W and M = Σ (m̃_j/ρ_j)(x_j − x_i) ⊗ ∇W, row-major
// (rr, rz, zr, zz); M always with m̃_j/ρ_j (with CONJUGATE only the corrected gc needs it).
// v is particle i's velocity and rho_i its density, loaded once (a driver may not hoist loads
// out of the loop).
// weight: Σ m̃_j (w_i + w_j − 2 r_i) ∂_r W_ij with w = ±r as in sph_forces; ri: hoop_radius(r_i).
struct Gather {
    g: vec4<f32>,
    gc: vec4<f32>,
    m: vec4<f32>,
    v: vec2<f32>,
    rho_i: f32,
    ri: f32,
    weight: f32,
}

// One pair's terms, a neighbour's (or its axis ghost's) or an image's: partner j at
// separation d = x_i − x_j with velocity v_j in the pair's frame and ring weight sum
// w_i + w_j − 2 r_i for the hoop weight.
fn pair(acc: ptr<function, Gather>, j: u32, d: vec2<f32>, dist: f32, v_j: vec2<f32>,
        w_sum: f32) {
    let nb = rate_pair[j];
    var a = nb.x;
    if (CONJUGATE) {
        // sph_rates.rs: m̃_j/ρ_i, in the CPU's order (area ρ_j)/ρ_i.
        a = nb.y / (*acc).rho_i;
    }
    let gw = kernel_grad(u.kernel, d, dist);
    let dvr = v_j.x - (*acc).v.x;
    let dvz = v_j.y - (*acc).v.y;
    // Products in the CPU's order, (a v) w, for the closest agreement.
    (*acc).g += vec4<f32>(a * dvr * gw.x, a * dvr * gw.y, a * dvz * gw.x, a * dvz * gw.y);
    let c = nb.x;
    if (RECONSTRUCT && CONJUGATE) {
        (*acc).gc += vec4<f32>(c * dvr * gw.x, c * dvr * gw.y, c * dvz * gw.x, c * dvz * gw.y);
    }
    (*acc).m -= vec4<f32>(c * d.x * gw.x, c * d.x * gw.y, c * d.y * gw.x, c * d.y * gw.y);
    (*acc).weight += nb.z * w_sum * gw.x;
}

// Neighbour j (its mirror ghost when sign = −1: radial velocity reversed, w = −r).
fn neighbour(acc: ptr<function, Gather>, i: u32, j: u32, d: vec2<f32>, dist: f32, sign: f32) {
    let vj = kin[j].zw;
    let ri = (*acc).ri;
    let rj = rate_pair[j].w;
    pair(acc, j, d, dist, vec2<f32>(sign * vj.x, vj.y), sign * ri + sign * rj - 2.0 * ri);
}

// The image of neighbour j (of i itself when j = i) across i's wall w, at d = x_i − x_image:
// moving as j mirrored in the wall's frame, w = r with the image's own radius.
fn image(acc: ptr<function, Gather>, i: u32, j: u32, w: Wall, d: vec2<f32>, dist: f32,
         r_image: f32) {
    let rg = hoop_radius(r_image, u.kernel.h);
    pair(acc, j, d, dist, wall_velocity(w, kin[j].zw), rg - (*acc).ri);
}

// sph_rates.rs `correct`: L = G M⁻¹ where det M is large enough, else G.
fn correct(g: vec4<f32>, m: vec4<f32>) -> vec4<f32> {
    let det = m.x * m.w - m.y * m.z;
    if (det < MIN_CORRECTION_DET) {
        return g;
    }
    let inv = vec4<f32>(m.w / det, -m.y / det, -m.z / det, m.x / det);
    return vec4<f32>(
        g.x * inv.x + g.y * inv.z,
        g.x * inv.y + g.y * inv.w,
        g.z * inv.x + g.w * inv.z,
        g.z * inv.y + g.w * inv.w,
    );
}

@compute @workgroup_size(WG)
fn gradient(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if (i >= u.n) { return; }
    let ki = kin[i];
    var acc = Gather(vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0), ki.zw, rho[i], hoop_radius(ki.x, u.kernel.h), 0.0);
    for_each_neighbour(&acc, i);
    let w = wall_of(i);
    if (w.seg != NO_WALL) {
        for_each_image(&acc, i, w);
    }
    var l = acc.g;
    if (!CONJUGATE) {
        l = correct(acc.g, acc.m);
    }
    l_rr[i] = l.x;
    l_rz[i] = l.y;
    l_zr[i] = l.z;
    l_zz[i] = l.w;
    if (RECONSTRUCT) {
        if (CONJUGATE) {
            l_visc[i] = correct(acc.gc, acc.m);
        } else {
            l_visc[i] = l;
        }
    }
    let n = acc.weight / rho[i];
    hoop_weight[i] = n;
    let div = l.x + l.w + hoop_rate(ki.z, ki.x, u.kernel.h, n, CONJUGATE);
    drho[i] = -rho[i] * div;
    if (BALSARA) {
        // sph_rates.rs `balsara`.
        let d = abs(div);
        visc_switch[i] = d / (d + abs(l.y - l.z) + BALSARA_FLOOR * sound[i] / u.kernel.h);
    }
}
