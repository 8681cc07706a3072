// `sph_forces` (CPU twin: src/cpu/sph_forces.rs): particle accelerations gathered over
// neighbours and axis ghosts (physics.md §3) in the momentum-conserving ring-mass form derived
// in the CPU twin's header: a_i = (1/r_i) Σ_j m̃_j [w_i σ_i/ρ_i² + w_j σ_j/ρ_j² − r̄_ij Π_ij I
// (+ R_ij f_ij^n)] · ∇_i W_ij with w = r for a neighbour and −r for a mirror ghost pair, plus the
// hoop source a_r += −σ_θθ n_i/(ρ r) (n_i: hoop_weight, from sph_rates); Monaghan–Gingold
// viscosity Π_ij with its heating, Gray–Monaghan artificial stress R when enabled, the Balsara
// switch on Π when enabled, and the work-conjugate energy rate. With RECONSTRUCT Π reads the
// approach left at the pair's midpoint after a limited linear reconstruction from both ends'
// l_visc (sph_forces.rs `reconstructed_jump`); the time step still the raw one.
// It also folds each particle's stable step into the clock (step.wgsl).
// With IMAGES a particle lining the projectile also gathers over its wall images
// (wall_images.wgsl; sph_forces.rs's image loop): each carries its source's stress reflected
// (R σ R) and moves as it mirrored in the wall's frame; the particle books their whole work
// relative to the wall, and the ring force they exert, 2π m̃_i Σ, goes to wall_force for the
// walls pass to hand to the nodes.
// Needs params.wgsl, step.wgsl, grid.wgsl, gather_bindings.wgsl (bindings 0–6),
// neighbour_loop.wgsl, wall.wgsl and wall_images.wgsl (binding 30).

@group(0) @binding(8) var<storage, read> p: array<f32>;
@group(0) @binding(12) var<storage, read> s_tt: array<f32>;
@group(0) @binding(16) var<storage, read> hoop_weight: array<f32>;
// Written by `concrete` with the state: R, and what a neighbour contributes packed for one load
// each, (σ_rr, σ_zz, σ_rz)/ρ² with m̃, and (c, ρ, factor on Π).
@group(0) @binding(18) var<storage, read> art_stress: array<array<f32, 3>>;
@group(0) @binding(19) var<storage, read> pair_s: array<vec4<f32>>;
@group(0) @binding(20) var<storage, read> pair_c: array<vec4<f32>>;
@group(0) @binding(21) var<storage, read_write> ar: array<f32>;
@group(0) @binding(22) var<storage, read_write> az: array<f32>;
@group(0) @binding(23) var<storage, read_write> de_visc: array<f32>;
@group(0) @binding(24) var<storage, read_write> mu_visc: array<f32>;
@group(0) @binding(25) var<storage, read_write> de_work: array<f32>;
// The clock's running minima of the slot `fold_slot` (step.wgsl).
@group(0) @binding(26) var<storage, read_write> clock: ClockAtomic;
@group(0) @binding(27) var<uniform> fold_slot: DtSlot;
@group(0) @binding(28) var<storage, read> l_visc: array<vec4<f32>>;
// With IMAGES: the ring force (N) each particle's images exert on it, where it has a wall.
@group(0) @binding(31) var<storage, read_write> wall_force: array<vec2<f32>>;

// The Gray–Monaghan artificial stress is on (SphParams::art_stress_eps > 0): a pipeline
// constant, so a scene without it compiles without it (a branch not taken still costs on a
// SIMD-on-CPU adapter such as lavapipe, which runs both sides under a mask).
override ART_STRESS: bool;
// The Balsara switch is on (SphParams::balsara): Π is scaled by the pair's mean visc_switch.
override BALSARA: bool;
// target.viscosity_jump = "reconstructed" (SphParams::reconstruct_viscosity).
override RECONSTRUCT: bool;
// contact.kernel = "images": the walls pass has found each particle's wall.
override IMAGES: bool;

// Smallest base handed to pow (undefined for a base <= 0); W > 0 inside the support anyway.
const POW_BASE_FLOOR: f32 = 1.0e-30;

fn vec3_of(a: array<f32, 3>) -> vec3<f32> {
    return vec3<f32>(a[0], a[1], a[2]);
}

// What the neighbour loop accumulates for particle i, and i's own values it reads (loaded
// once: a driver may not hoist loads out of the loop, lavapipe does not).
struct Gather {
    acc: vec2<f32>,
    // Σ_j m̃_j (T_ij ∇_i W_ij)·(v_i − v_j): the pair work, over 2π m̃_i.
    pair_power: f32,
    heat: f32,
    mu_max: f32,
    s: vec3<f32>,
    art: vec3<f32>,
    v: vec2<f32>,
    sound: f32,
    rho: f32,
    visc_switch: f32,
    // hoop_radius(r_i)
    ri: f32,
    // l_visc[i], with RECONSTRUCT
    l: vec4<f32>,
    // Σ over the images of their pair terms, with IMAGES.
    image_acc: vec2<f32>,
}

// sph_forces.rs `reconstructed_jump`, in its order of operations: the approach vx < 0 left at
// the pair's midpoint, van Leer-limited; never below vx, 0 where none is left.
fn reconstructed_jump(vx: f32, x: vec2<f32>, li: vec4<f32>, lj: vec4<f32>) -> f32 {
    let qi = x.x * (li.x * x.x + li.y * x.y) + x.y * (li.z * x.x + li.w * x.y);
    let qj = x.x * (lj.x * x.x + lj.y * x.y) + x.y * (lj.z * x.x + lj.w * x.y);
    var ratio = 0.0;
    if (qj != 0.0) {
        ratio = qi / qj;
    }
    var phi = 0.0;
    if (ratio > 0.0) {
        phi = min(4.0 * ratio / ((1.0 + ratio) * (1.0 + ratio)), 1.0);
    }
    let left = vx - 0.5 * phi * (qi + qj);
    if (left < 0.0) {
        return max(left, vx);
    }
    return 0.0;
}

// One pair's term, a neighbour's (or its axis ghost's) or an image's (sph_forces.rs `term`):
// partner j at separation d = x_i − x_j with its stress s_j/ρ² in the pair's frame, ring
// weights w_i and w_j, radius r_j in the viscosity's mean and velocity v_j in the pair's frame;
// its artificial stress and gradient are taken into the same frame here, where they are used
// (mirrored across the axis when sign = −1, reflected across `wall` when `image`). Folds the
// pair's μ into mu_max and its heating into heat; returns the pair's acceleration term.
fn pair_term(g: ptr<function, Gather>, j: u32, d: vec2<f32>, dist: f32, s_j: vec3<f32>,
             w_i: f32, w_j: f32, r_j: f32, v_j: vec2<f32>, sign: f32, wall: Wall,
             image: bool) -> vec2<f32> {
    let h = u.kernel.h;
    let pj = pair_s[j];
    let mj = pj.w;
    let gw = kernel_grad(u.kernel, d, dist);
    let si = (*g).s;
    let ri = (*g).ri;
    var t = vec3<f32>(w_i * si.x + w_j * s_j.x, w_i * si.y + w_j * s_j.y,
        w_i * si.z + w_j * s_j.z);
    let dvr = (*g).v.x - v_j.x;
    let dvz = (*g).v.y - v_j.y;
    let vx = dvr * d.x + dvz * d.y;
    if (vx < 0.0) {
        // The time step allows for the raw jump.
        (*g).mu_max = max((*g).mu_max, -h * vx / (dist * dist + ETA2 * h * h));
    }
    var jump = vx;
    if (RECONSTRUCT && vx < 0.0) {
        let lj = l_visc[j];
        var l_seen = vec4<f32>(lj.x, sign * lj.y, sign * lj.z, lj.w);
        if (image) {
            l_seen = wall_gradient(wall, lj);
        }
        jump = reconstructed_jump(vx, d, (*g).l, l_seen);
    }
    if (jump < 0.0) {
        let mu = h * jump / (dist * dist + ETA2 * h * h);
        let cj = pair_c[j];
        let c_mean = 0.5 * ((*g).sound + cj.x);
        let rho_mean = 0.5 * ((*g).rho + cj.y);
        var pi = 0.5 * (ri + r_j) * (-u.alpha * c_mean * mu + u.beta * mu * mu) / rho_mean;
        if (BALSARA) {
            pi *= 0.5 * ((*g).visc_switch + cj.z);
        }
        t.x -= pi;
        t.y -= pi;
        (*g).heat += 0.5 * mj * pi * (dvr * gw.x + dvz * gw.y) / ri;
    }
    if (ART_STRESS) {
        let ri_art = (*g).art;
        let a = vec3_of(art_stress[j]);
        var rj_art = vec3<f32>(a.x, a.y, sign * a.z);
        if (image) {
            rj_art = wall_tensor(wall, a);
        }
        let f = pow(max(kernel_w(u.kernel, dist) / u.w_spacing, POW_BASE_FLOOR), u.art_stress_n);
        t.x += f * (w_i * ri_art.x + w_j * rj_art.x);
        t.y += f * (w_i * ri_art.y + w_j * rj_art.y);
        t.z += f * (w_i * ri_art.z + w_j * rj_art.z);
    }
    return vec2<f32>(mj * (t.x * gw.x + t.z * gw.y), mj * (t.z * gw.x + t.y * gw.y));
}

// The pair term of neighbour j (its mirror image when sign = −1) at separation d = x_i − x_j:
// w = ±r, a mirror ghost pair weighted −r on both sides, its shear stress and radial velocity
// reversed.
fn neighbour(g: ptr<function, Gather>, i: u32, j: u32, d: vec2<f32>, dist: f32, sign: f32) {
    let sj = pair_s[j].xyz;
    let kj = kin[j];
    let rj = hoop_radius(kj.x, u.kernel.h);
    let vj = vec2<f32>(sign * kj.z, kj.w);
    let pair = pair_term(g, j, d, dist, vec3<f32>(sj.x, sj.y, sign * sj.z), sign * (*g).ri,
        sign * rj, rj, vj, sign, no_wall(), false);
    (*g).acc += pair;
    (*g).pair_power += pair.x * ((*g).v.x - vj.x) + pair.y * ((*g).v.y - vj.y);
}

// The image of neighbour j (of i itself when j = i) across i's wall w, at d = x_i − x_image:
// w = r on both sides, the source's stress reflected, its velocity mirrored in the wall's frame.
fn image(g: ptr<function, Gather>, i: u32, j: u32, w: Wall, d: vec2<f32>, dist: f32,
         r_image: f32) {
    let rg = hoop_radius(r_image, u.kernel.h);
    let sg = wall_tensor(w, pair_s[j].xyz);
    let vg = wall_velocity(w, kin[j].zw);
    (*g).image_acc += pair_term(g, j, d, dist, sg, (*g).ri, rg, rg, vg, 1.0, w, true);
}

// Per particle: the gather over neighbours and axis ghosts (neighbour_loop.wgsl), then the
// hoop source.
@compute @workgroup_size(WG)
fn forces(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if (i >= u.n) { return; }
    let ki = kin[i];
    let ci = pair_c[i];
    var g = Gather(vec2<f32>(0.0, 0.0), 0.0, 0.0, 0.0, pair_s[i].xyz, vec3<f32>(0.0), ki.zw,
        ci.x, ci.y, ci.z, hoop_radius(ki.x, u.kernel.h), vec4<f32>(0.0), vec2<f32>(0.0));
    if (RECONSTRUCT) {
        g.l = l_visc[i];
    }
    if (ART_STRESS) {
        g.art = vec3_of(art_stress[i]);
    }
    for_each_neighbour(&g, i);
    let wall = wall_of(i);
    if (wall.seg != NO_WALL) {
        for_each_image(&g, i, wall);
        // The wall takes no heat: the particle books the images' whole work relative to it,
        // which is what they and the projectile exchange (wall.rs).
        let u_rel = ki.zw - wall.v;
        g.pair_power += 2.0 * (g.image_acc.x * u_rel.x + g.image_acc.y * u_rel.y);
        g.acc += g.image_acc;
        // The ring force is m a = 2π m̃_i · acc (a = acc/r_i).
        wall_force[i] = 2.0 * PI * pair_s[i].w * g.image_acc;
    }

    let ri = g.ri;
    let hoop_r = -(s_tt[i] - p[i]) * hoop_weight[i] / (ci.y * ri);
    de_work[i] = -g.pair_power / (2.0 * ri) - hoop_r * ki.z;
    ar[i] = g.acc.x / ri + hoop_r;
    az[i] = g.acc.y / ri;
    de_visc[i] = g.heat;
    mu_visc[i] = g.mu_max;
    let bits = particle_dt_bits(u.kernel.h, u.alpha, u.beta, ci.x, ki.zw, g.mu_max);
    let w = 2u * fold_slot.slot;
    if (bits < atomicLoad(&clock.next[w])) {
        atomicMin(&clock.next[w], bits);
    }
}
