// `concrete` (CPU twin: src/cpu/concrete.rs): per particle, the HJC update (physics.md §3.1) in
// the OpenRadioss LAW126 order: density from continuity, EOS with crushing, trial deviator
// (Jaumann), strength with the new pressure and the old damage, radial scaling, damage from
// Δε_p + Δμ_p (in tension, with the crack band, Δε_p + the crack's opening); then the energy;
// then what sph_forces reads of the new state (its CPU twin's prologue): σ/ρ², packed with what
// a neighbour contributes for one load each, and the artificial stress when it is on.
// Needs params.wgsl, deviator.wgsl and hjc.wgsl.

@group(0) @binding(0) var<uniform> u: SphUniform;
@group(0) @binding(1) var<storage, read> clock: Clock;
@group(0) @binding(2) var<storage, read> r: array<f32>;
@group(0) @binding(3) var<storage, read> vr: array<f32>;
@group(0) @binding(4) var<storage, read> l_rr: array<f32>;
@group(0) @binding(5) var<storage, read> l_rz: array<f32>;
@group(0) @binding(6) var<storage, read> l_zr: array<f32>;
@group(0) @binding(7) var<storage, read> l_zz: array<f32>;
@group(0) @binding(8) var<storage, read> drho: array<f32>;
@group(0) @binding(9) var<storage, read> de_visc: array<f32>;
@group(0) @binding(10) var<storage, read> hoop_weight: array<f32>;
@group(0) @binding(11) var<storage, read_write> rho: array<f32>;
@group(0) @binding(12) var<storage, read_write> strain_energy: array<f32>;
@group(0) @binding(13) var<storage, read_write> p: array<f32>;
@group(0) @binding(14) var<storage, read_write> s_rr: array<f32>;
@group(0) @binding(15) var<storage, read_write> s_zz: array<f32>;
@group(0) @binding(16) var<storage, read_write> s_rz: array<f32>;
@group(0) @binding(17) var<storage, read_write> s_tt: array<f32>;
@group(0) @binding(18) var<storage, read_write> damage: array<f32>;
@group(0) @binding(19) var<storage, read_write> mu_max: array<f32>;
@group(0) @binding(20) var<storage, read_write> eps_p: array<f32>;
@group(0) @binding(21) var<storage, read_write> sound: array<f32>;
@group(0) @binding(22) var<storage, read> m_tilde: array<f32>;
@group(0) @binding(23) var<storage, read> visc_switch: array<f32>;
// For sph_forces: σ/ρ² (the state's, for the host), R, and (σ_rr, σ_zz, σ_rz)/ρ² with m̃, and
// (c, ρ, factor on Π).
@group(0) @binding(24) var<storage, read_write> stress_rho2: array<array<f32, 3>>;
@group(0) @binding(25) var<storage, read_write> art_stress: array<array<f32, 3>>;
@group(0) @binding(26) var<storage, read_write> pair_s: array<vec4<f32>>;
@group(0) @binding(27) var<storage, read_write> pair_c: array<vec4<f32>>;

// target.velocity_gradient = "conjugate" (SphParams::conjugate_gradient).
override CONJUGATE: bool;
// The Gray–Monaghan artificial stress is on (SphParams::art_stress_eps > 0), as in
// sph_forces.wgsl.
override ART_STRESS: bool;

// Gray–Monaghan (2001) artificial stress over ρ² in (rr, zz, rz): R = −ε σ'/ρ² on each tensile
// principal stress σ' of the r–z plane, rotated back; zero for compression.
fn artificial_stress(eps: f32, srr: f32, szz: f32, srz: f32, density: f32) -> vec3<f32> {
    let theta = 0.5 * atan2(2.0 * srz, srr - szz);
    let sn = sin(theta);
    let cs = cos(theta);
    let s1 = cs * cs * srr + 2.0 * cs * sn * srz + sn * sn * szz;
    let s2 = sn * sn * srr - 2.0 * cs * sn * srz + cs * cs * szz;
    let inv = -eps / (density * density);
    let r1 = select(0.0, inv * s1, s1 > 0.0);
    let r2 = select(0.0, inv * s2, s2 > 0.0);
    return vec3<f32>(cs * cs * r1 + sn * sn * r2, sn * sn * r1 + cs * cs * r2, cs * sn * (r1 - r2));
}


@compute @workgroup_size(WG)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if (i >= u.n) { return; }
    let dt = clock.dt;

    let d_tt = hoop_rate(vr[i], r[i], u.kernel.h, hoop_weight[i], CONJUGATE);
    let d_rr = l_rr[i];
    let d_zz = l_zz[i];
    let d_rz = 0.5 * (l_rz[i] + l_zr[i]);
    let spin = 0.5 * (l_rz[i] - l_zr[i]);
    let p_old = p[i];
    let s_old = vec4<f32>(s_rr[i], s_zz[i], s_rz[i], s_tt[i]);
    let old_power = (s_old.x - p_old) * d_rr
        + (s_old.y - p_old) * d_zz
        + 2.0 * s_old.z * d_rz
        + (s_old.w - p_old) * d_tt;

    let floor = MIN_DENSITY_RATIO * u.density;
    let continuity = rho[i] + dt * drho[i];
    let rho_new = max(continuity, floor);
    let mu = rho_new / u.density - 1.0;
    // A particle continuity would take below the floor has separated: it fails.
    let dmg = select(damage[i], 1.0, continuity < floor);
    let t_d = hjc_tensile_strength(
        u,
        largest_principal_rate(vec4<f32>(d_rr, d_zz, d_rz, d_tt)),
    );
    let eos = hjc_pressure(u, mu, mu_max[i], dmg, t_d);

    let dev = deviatoric_rate(vec4<f32>(d_rr, d_zz, d_rz, d_tt));
    let g = u.shear_modulus;
    var s = jaumann_trial(s_old, dev, spin, g, dt);
    let eq_rate = equivalent_rate(dev);
    let seq = von_mises(s);
    let sy = hjc_yield_stress(u, eos.p, dmg, eq_rate, t_d);
    var d_eps_p = 0.0;
    if (seq > sy) {
        let scale = select(0.0, sy / seq, seq > 0.0);
        s = s * scale;
        d_eps_p = (seq - sy) / (3.0 * g);
    }

    // The crack's opening: the expansion of a particle held at the cut-off (concrete.rs
    // `crack_opening`).
    let cut = -t_d * (1.0 - dmg);
    let d_open = select(0.0, max((rho[i] - rho_new) / rho_new, 0.0), cut < 0.0 && eos.p <= cut);
    rho[i] = rho_new;
    mu_max[i] = eos.mu_max;
    p[i] = eos.p;
    eps_p[i] = eps_p[i] + d_eps_p;
    damage[i] = min(dmg + hjc_damage_increment(u, eos.p, t_d, d_eps_p, eos.d_mu_p, d_open), 1.0);
    s_rr[i] = s.x;
    s_zz[i] = s.y;
    s_rz[i] = s.z;
    s_tt[i] = s.w;
    let c = hjc_sound_speed(u, eos.tangent);
    sound[i] = c;

    // ė = σ:ε̇/ρ (θθ included), trapezoidal in the stress, plus viscous heating.
    let new_power = (s.x - eos.p) * d_rr
        + (s.y - eos.p) * d_zz
        + 2.0 * s.z * d_rz
        + (s.w - eos.p) * d_tt;
    strain_energy[i] = strain_energy[i] + dt * (0.5 * (old_power + new_power) / rho_new + de_visc[i]);

    let inv = 1.0 / (rho_new * rho_new);
    let sr = vec3<f32>((s.x - eos.p) * inv, (s.y - eos.p) * inv, s.z * inv);
    stress_rho2[i] = array<f32, 3>(sr.x, sr.y, sr.z);
    pair_s[i] = vec4<f32>(sr, m_tilde[i]);
    pair_c[i] = vec4<f32>(c, rho_new, visc_switch[i], 0.0);
    if (ART_STRESS) {
        let a = artificial_stress(u.art_stress_eps, s.x - eos.p, s.y - eos.p, s.z, rho_new);
        art_stress[i] = array<f32, 3>(a.x, a.y, a.z);
    }
}
