// `fem_stress` (CPU twin: src/cpu/fem_stress.rs, `run`): one thread per pressure cell, which
// first sums the cell's shared EOS state (`cell_eos`) and then updates its elements in order
// (`update_element`): geometry and strain rates of the linear triangle, the Jaumann trial,
// Johnson–Cook radial return with adiabatic heating and damage, the EOS with the energy
// predictor, bulk viscosity, the energy, the nodal forces and the stable step (physics.md §2,
// §2.4). Needs params.wgsl, step.wgsl, deviator.wgsl, johnson_cook.wgsl and steel_eos.wgsl.

@group(0) @binding(0) var<uniform> u: FemUniform;
// Δt, and the running minima of the slot `fold_slot` the elements' stable steps fold into
// (step.wgsl).
@group(0) @binding(1) var<storage, read_write> clock: ClockAtomic;
@group(0) @binding(2) var<storage, read_write> status: array<atomic<u32>>;
@group(0) @binding(3) var<storage, read> r: array<f32>;
@group(0) @binding(4) var<storage, read> z: array<f32>;
@group(0) @binding(5) var<storage, read> vr: array<f32>;
@group(0) @binding(6) var<storage, read> vz: array<f32>;
// Elements.nodes, [u32; 3] per element.
@group(0) @binding(7) var<storage, read> nodes: array<u32>;
@group(0) @binding(8) var<storage, read> volume0: array<f32>;
@group(0) @binding(9) var<storage, read_write> s_rr: array<f32>;
@group(0) @binding(10) var<storage, read_write> s_zz: array<f32>;
@group(0) @binding(11) var<storage, read_write> s_rz: array<f32>;
@group(0) @binding(12) var<storage, read_write> s_tt: array<f32>;
@group(0) @binding(13) var<storage, read_write> p: array<f32>;
@group(0) @binding(14) var<storage, read_write> energy: array<f32>;
@group(0) @binding(15) var<storage, read_write> eps_p: array<f32>;
@group(0) @binding(16) var<storage, read_write> temperature: array<f32>;
@group(0) @binding(17) var<storage, read_write> damage: array<f32>;
@group(0) @binding(18) var<storage, read_write> failed: array<u32>;
// Elements.force, [f32; 6] per element: r_i, z_i, r_j, z_j, r_m, z_m.
@group(0) @binding(19) var<storage, read_write> force: array<f32>;
// The element's stable step (not the clock's Δt).
@group(0) @binding(20) var<storage, read_write> dt: array<f32>;
@group(0) @binding(21) var<storage, read_write> plastic_work: array<f32>;
// Running sum of plastic_work over the steps (J), summed by the host at output time.
@group(0) @binding(22) var<storage, read_write> plastic_total: array<f32>;
// Elements.cells: cell c is elements cells[c]..cells[c + 1].
@group(0) @binding(23) var<storage, read> cells: array<u32>;
@group(0) @binding(24) var<uniform> fold_slot: DtSlot;

// The material has a Johnson–Cook damage model (FemParams::damage): a pipeline constant, so a
// material without one compiles without the damage update.
override DAMAGE: bool;

// fem_stress::Geometry: shape data at the current position, b_i = z_j − z_m, c_i = r_m − r_j.
struct Geometry {
    r: vec3<f32>,
    z: vec3<f32>,
    b: vec3<f32>,
    c: vec3<f32>,
    two_area: f32,
    r_mean: f32,
}

fn geometry(e: u32) -> Geometry {
    let n = vec3<u32>(nodes[3u * e], nodes[3u * e + 1u], nodes[3u * e + 2u]);
    let rr = vec3<f32>(r[n.x], r[n.y], r[n.z]);
    let zz = vec3<f32>(z[n.x], z[n.y], z[n.z]);
    let b = vec3<f32>(zz.y - zz.z, zz.z - zz.x, zz.x - zz.y);
    let c = vec3<f32>(rr.z - rr.y, rr.x - rr.z, rr.y - rr.x);
    // From the edge vectors: translation invariant, better in f32 than Σ r_i b_i.
    let two_area = (rr.y - rr.x) * (zz.z - zz.x) - (rr.z - rr.x) * (zz.y - zz.x);
    return Geometry(rr, zz, b, c, two_area, (rr.x + rr.y + rr.z) / 3.0);
}

// Smallest altitude: 2A over the longest edge.
fn min_altitude(g: Geometry) -> f32 {
    var longest = 0.0;
    for (var k = 0u; k < 3u; k++) {
        longest = max(longest, sqrt(g.b[k] * g.b[k] + g.c[k] * g.c[k]));
    }
    return g.two_area / longest;
}

// fem_stress::StrainRate: ε̇_r, ε̇_z, engineering γ̇_rz, ε̇_θ and the spin ω.
struct StrainRate {
    rr: f32,
    zz: f32,
    gamma_rz: f32,
    tt: f32,
    spin: f32,
}

fn strain_rate(g: Geometry, v_r: vec3<f32>, v_z: vec3<f32>) -> StrainRate {
    let inv = 1.0 / g.two_area;
    // Velocities relative to node 0 (Σ b_k = Σ c_k = 0): a rigid translation gives exactly 0.
    let ur = vec2<f32>(v_r.y - v_r.x, v_r.z - v_r.x);
    let uz = vec2<f32>(v_z.y - v_z.x, v_z.z - v_z.x);
    let rr = g.b.y * ur.x + g.b.z * ur.y;
    let zz = g.c.y * uz.x + g.c.z * uz.y;
    let drdz = g.c.y * ur.x + g.c.z * ur.y;
    let dzdr = g.b.y * uz.x + g.b.z * uz.y;
    let r_sum = g.r.x + g.r.y + g.r.z;
    return StrainRate(
        rr * inv,
        zz * inv,
        (drdz + dzdr) * inv,
        (v_r.x + v_r.y + v_r.z) / r_sum,
        0.5 * (drdz - dzdr) * inv,
    );
}

// fem_stress::total_stress: σ = S − p I, (rr, zz, rz, θθ).
fn total_stress(s: vec4<f32>, pressure: f32) -> vec4<f32> {
    return vec4<f32>(s.x - pressure, s.y - pressure, s.z, s.w - pressure);
}

// Stress::power: σ:ε̇ (W/m³) with the engineering shear rate.
fn stress_power(s: vec4<f32>, d: StrainRate) -> f32 {
    return s.x * d.rr + s.y * d.zz + s.z * d.gamma_rz + s.w * d.tt;
}

// fem_stress::nodal_forces, physics.md §2 eq. (1)-(2) in the power-consistent form:
// F_r,k = −π r̄ (σ_r b_k + τ c_k) − 2πA σ_θ/3, F_z,k = −π r̄ (σ_z c_k + τ b_k).
fn write_nodal_forces(e: u32, g: Geometry, s: vec4<f32>) {
    let pr = PI * g.r_mean;
    // 2πAσ_θ/3 with 2A = two_area.
    let hoop = PI * g.two_area * s.w / 3.0;
    for (var k = 0u; k < 3u; k++) {
        force[6u * e + 2u * k] = -pr * (s.x * g.b[k] + s.z * g.c[k]) - hoop;
        force[6u * e + 2u * k + 1u] = -pr * (s.y * g.c[k] + s.z * g.b[k]);
    }
}

fn element_rate(e: u32, g: Geometry) -> StrainRate {
    let n = vec3<u32>(nodes[3u * e], nodes[3u * e + 1u], nodes[3u * e + 2u]);
    return strain_rate(g, vec3<f32>(vr[n.x], vr[n.y], vr[n.z]),
        vec3<f32>(vz[n.x], vz[n.y], vz[n.z]));
}

// fem_stress::CellEos: the cell's V/V₀ and predicted energy per reference volume; `grouped`
// false for a cell of one element or one with a failed or inverted element.
struct CellEos {
    grouped: bool,
    rel_volume: f32,
    e_pred: f32,
}

// fem_stress::cell_eos: summed in element order, as on the CPU.
fn cell_eos(first: u32, last: u32, step_dt: f32) -> CellEos {
    var out = CellEos(false, 0.0, 0.0);
    if (last - first < 2u) { return out; }
    var v = 0.0;
    var v0 = 0.0;
    var en = 0.0;
    for (var e = first; e < last; e++) {
        let g = geometry(e);
        if (failed[e] != 0u || !(g.two_area > 0.0)) { return out; }
        let d = element_rate(e, g);
        let volume = PI * g.r_mean * g.two_area;
        let s_old = vec4<f32>(s_rr[e], s_zz[e], s_rz[e], s_tt[e]);
        let old_power = stress_power(total_stress(s_old, p[e]), d);
        v = v + volume;
        v0 = v0 + volume0[e];
        en = en + (energy[e] * volume0[e] + step_dt * volume * old_power);
    }
    out = CellEos(true, v / v0, en / v0);
    return out;
}

@compute @workgroup_size(WG)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let c = gid.x;
    if (c >= u.n_cells) { return; }
    let first = cells[c];
    let last = cells[c + 1u];
    let step_dt = bitcast<f32>(atomicLoad(&clock.dt_bits));
    // Every element's shared state is read before any of them is written.
    let cell = cell_eos(first, last, step_dt);
    var least = F32_MAX_BITS;
    for (var e = first; e < last; e++) {
        update_element(e, cell, step_dt);
        // Its stable step, new or (an element left as it was) old.
        least = min(least, candidate_bits(dt[e]));
    }
    let w = 2u * fold_slot.slot + 1u;
    if (least < atomicLoad(&clock.next[w])) {
        atomicMin(&clock.next[w], least);
    }
}

fn update_element(e: u32, cell: CellEos, step_dt: f32) {
    let g = geometry(e);
    // Inverted or degenerate (NaN fails the comparison): the host stops the run and names the
    // smallest such element; its state is left as it was, as on the CPU.
    if (!(g.two_area > 0.0)) {
        atomicMin(&status[STATUS_INVERTED_ELEMENT], e);
        return;
    }
    let d = element_rate(e, g);
    let volume = PI * g.r_mean * g.two_area;
    let rel_volume = volume / volume0[e];

    let s_old = vec4<f32>(s_rr[e], s_zz[e], s_rz[e], s_tt[e]);
    let p_old = p[e];
    let old_power = stress_power(total_stress(s_old, p_old), d);
    let e_old = energy[e];
    // The pressure's volume and energy: the cell's, or the element's own with the energy
    // predicted from the old stress power, eq. (14).
    var eos_rel = rel_volume;
    var e_pred = e_old + step_dt * rel_volume * old_power;
    if (cell.grouped) {
        eos_rel = cell.rel_volume;
        e_pred = cell.e_pred;
    }
    let rho = u.density / eos_rel;
    let mu = 1.0 / eos_rel - 1.0;
    let g_mod = u.shear_modulus;

    let rate = vec4<f32>(d.rr, d.zz, 0.5 * d.gamma_rz, d.tt);
    let dev = deviatoric_rate(rate);
    let vol = volumetric_rate(rate);
    let eq_rate = equivalent_rate(dev);
    var s = jaumann_trial(s_old, dev, d.spin, g_mod, step_dt);
    var work = 0.0;
    var eps = eps_p[e];
    var temp = temperature[e];
    var dmg = damage[e];
    var is_failed = failed[e] != 0u;
    if (is_failed) {
        s = vec4<f32>(0.0);
    } else {
        let ret = jc_radial_return(u, g_mod, von_mises(s), eps, eq_rate, temp, u.return_iterations);
        if (ret.d_eps_p > 0.0) {
            s = s * ret.scale;
            eps = eps + ret.d_eps_p;
            // Adiabatic heating ΔT = β σ_y Δε_p /(ρ c_p), physics.md §2.1.
            let work_density = ret.flow_stress * ret.d_eps_p;
            temp = temp + u.taylor_quinney * work_density / (rho * u.specific_heat);
            work = work_density * volume;
        }
        if (DAMAGE) {
            let seq_new = von_mises(s);
            // Mean stress of the start of the step, as on the CPU (the new p comes later).
            let mean = -p_old;
            // select evaluates both: the discarded mean/0 of a zero deviator is harmless.
            let triax = select(0.0, mean / seq_new, seq_new > 0.0);
            let t_star = jc_homologous_temperature(u, temp);
            dmg = dmg + jc_damage_increment(u, ret.d_eps_p, triax, eq_rate, u.eps_rate_ref, t_star);
            if (dmg >= 1.0 || jc_spalls(u, mean)) {
                dmg = min(dmg, 1.0);
                is_failed = true;
                s = vec4<f32>(0.0);
            }
        }
    }

    let p_eos = steel_eos_pressure(u, mu, e_pred);
    let k_t = steel_eos_bulk_tangent(u, mu);
    var p_new = p_eos;
    if (is_failed) {
        // A failed element takes no tension.
        p_new = max(p_new, 0.0);
    } else if (cell.grouped) {
        // fem_stress::cell_mode_pressure: what holds the cell's centre-node mode.
        p_new = p_eos + CELL_MODE_STIFFNESS * k_t * (eos_rel - rel_volume);
    }
    // An open failed element (cpu::fem_stress::OPEN_RELATIVE_VOLUME) carries no stress and
    // limits the step only by the time it would take to close.
    let open = is_failed && eos_rel >= OPEN_RELATIVE_VOLUME && p_eos <= 0.0;

    // Bulk viscosity on compression only: it spreads shocks, which only compression forms.
    let length = min_altitude(g);
    let c = sqrt((k_t + 4.0 / 3.0 * g_mod) / rho);
    var q = 0.0;
    if (vol < 0.0 && !open) {
        q = rho * length * (u.q_quad * length * vol * vol - u.q_lin * c * vol);
    }

    s_rr[e] = s.x;
    s_zz[e] = s.y;
    s_rz[e] = s.z;
    s_tt[e] = s.w;
    p[e] = p_new;
    eps_p[e] = eps;
    temperature[e] = temp;
    damage[e] = dmg;
    failed[e] = select(0u, 1u, is_failed);
    // Per reference volume: trapezoidal in the stress, plus the viscous heating −q tr ε̇.
    let power = 0.5 * (old_power + stress_power(total_stress(s, p_new), d)) - q * vol;
    energy[e] = e_old + step_dt * rel_volume * power;
    write_nodal_forces(e, g, total_stress(s, p_new + q));

    let q_hat = u.q_quad * length * max(-vol, 0.0) + u.q_lin * c;
    var dt_el = length / (q_hat + sqrt(q_hat * q_hat + c * c));
    if (open) {
        // Time to close: p_eos rises at k_t μ̇, μ̇ = −(1 + μ) tr ε̇.
        let closing = k_t * (1.0 + mu) * -vol;
        if (closing > 0.0) {
            dt_el = max(dt_el, -p_eos / closing);
        } else {
            dt_el = bitcast<f32>(F32_MAX_BITS);
        }
    }
    dt[e] = dt_el;
    plastic_work[e] = work;
    plastic_total[e] = plastic_total[e] + work;
}
