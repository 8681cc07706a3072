// Holmquist–Johnson–Cook concrete, physics.md §3.1: the WGSL twin of src/materials/hjc.rs,
// function for function, same formulas in the same order. The constants come from
// SphUniform (src/gpu/params.rs); μ_plock (materials::hjc::lock_strain) is precomputed there.

// materials::hjc::HjcEos.
struct HjcEos {
    // Pressure (Pa, compression-positive) after the tension cut-off.
    p: f32,
    // Largest μ reached so far, including this call.
    mu_max: f32,
    // Increase (>= 0) of the plastic volumetric strain μ_p in this call.
    d_mu_p: f32,
    // dp/dμ for the sound speed (Pa), >= K_el.
    tangent: f32,
}

// Fully dense curve K1 μ̄ + K2 μ̄² + K3 μ̄³.
fn hjc_dense_pressure(u: SphUniform, mu_bar: f32) -> f32 {
    return (u.k1 + (u.k2 + u.k3 * mu_bar) * mu_bar) * mu_bar;
}

// Its slope K1 + 2 K2 μ̄ + 3 K3 μ̄².
fn hjc_dense_slope(u: SphUniform, mu_bar: f32) -> f32 {
    return u.k1 + (2.0 * u.k2 + 3.0 * u.k3 * mu_bar) * mu_bar;
}

// Loading pressure p_env and unloading modulus K_unload at a largest compression m <= μ_plock.
fn hjc_crush_envelope(u: SphUniform, m: f32, k_el: f32) -> vec2<f32> {
    let span = max(u.mu_plock - u.mu_crush, MIN_POSITIVE);
    let frac = clamp((m - u.mu_crush) / span, 0.0, 1.0);
    let crushing = u.p_crush + (u.p_lock - u.p_crush) * frac;
    let p_env = select(crushing, k_el * m, m <= u.mu_crush);
    return vec2<f32>(p_env, k_el + (u.k1 - k_el) * frac);
}

// Plastic volumetric strain left after unloading from a largest compression mu_max.
fn hjc_plastic_volumetric_strain(u: SphUniform, mu_max: f32, k_el: f32) -> f32 {
    let m = min(max(mu_max, u.mu_crush), u.mu_plock);
    let env = hjc_crush_envelope(u, m, k_el);
    return m - env.x / env.y;
}

// Dynamic increase of the tensile strength at the tensile strain rate (hjc.rs
// `tensile_rate_factor`, fib Model Code 2010, held at 300/s beyond).
fn hjc_tensile_rate_factor(rate: f32) -> f32 {
    let ratio = max(min(rate, HJC_TENSILE_RATE_LIMIT) / HJC_TENSILE_RATE_REF, 1.0);
    return select(
        HJC_TENSILE_RATE_COEFFICIENT * pow(ratio, 1.0 / 3.0),
        pow(ratio, HJC_TENSILE_RATE_EXPONENT),
        rate <= HJC_TENSILE_RATE_KNEE,
    );
}

// Tensile strength at the tensile strain rate: T, or T times the rate factor with the crack
// band (u.crack_band > 0; hjc.rs `tensile_strength`).
fn hjc_tensile_strength(u: SphUniform, rate: f32) -> f32 {
    return select(u.t, u.t * hjc_tensile_rate_factor(rate), u.crack_band > 0.0);
}

// Three-part EOS with compaction history and tension cut-off at t_d (hjc.rs `pressure`).
fn hjc_pressure(u: SphUniform, mu: f32, mu_max: f32, damage: f32, t_d: f32) -> HjcEos {
    let k_el = u.p_crush / u.mu_crush;
    let new_max = max(mu, mu_max);

    let env = hjc_crush_envelope(u, min(new_max, u.mu_plock), k_el);
    let crushing_slope = (u.p_lock - u.p_crush) / max(u.mu_plock - u.mu_crush, MIN_POSITIVE);
    let p_crushable = env.x - env.y * (new_max - mu);
    let k_crushable = max(env.y, crushing_slope);

    let mu_bar = (mu - u.mu_lock) / (1.0 + u.mu_lock);
    let locked = new_max >= u.mu_plock;
    var p = p_crushable;
    var tangent = k_crushable;
    if (locked) {
        p = hjc_dense_pressure(u, mu_bar);
        tangent = hjc_dense_slope(u, mu_bar) / (1.0 + u.mu_lock);
    }

    let d_mu_p = max(
        hjc_plastic_volumetric_strain(u, new_max, k_el)
            - hjc_plastic_volumetric_strain(u, mu_max, k_el),
        0.0,
    );
    let d = clamp(damage, 0.0, 1.0);
    return HjcEos(max(p, -t_d * (1.0 - d)), new_max, d_mu_p, max(tangent, k_el));
}

// Rate factor 1 + C ln ε̇*, ε̇* = max(ε̇/ε̇₀, 1).
fn hjc_rate_factor(u: SphUniform, eps_rate: f32) -> f32 {
    return 1.0 + u.c * log(max(eps_rate / u.eps_rate_ref, 1.0));
}

// Equivalent yield stress σ_y = f_c σ* (Pa, >= 0).
fn hjc_yield_stress(u: SphUniform, p: f32, damage: f32, eps_rate: f32, t_d: f32) -> f32 {
    let d = clamp(damage, 0.0, 1.0);
    let rate = hjc_rate_factor(u, eps_rate);
    let p_star = p / u.fc;
    let hardening = u.b * pow(max(p_star, HJC_POW_BASE_FLOOR), u.n_exp);
    let compressive = min((u.a * (1.0 - d) + hardening) * rate, u.s_max);
    let tensile = max(u.a * (1.0 + p / t_d) * (1.0 - d) * rate, 0.0);
    return u.fc * select(tensile, compressive, p_star >= 0.0);
}

// Damage increment; the caller caps D at 1. In tension with the crack band
// (Δε_p + Δε_o)/ε_ft, ε_ft = 2 G_f/(T_d l); else HJC's (Δε_p + Δμ_p)/max(D1 (P* + T*)^D2, EF_min).
fn hjc_damage_increment(
    u: SphUniform,
    p: f32,
    t_d: f32,
    d_eps_p: f32,
    d_mu_p: f32,
    d_open: f32,
) -> f32 {
    if (u.crack_band > 0.0 && p < 0.0) {
        let eps_ft = max(2.0 * u.g_f / (t_d * u.crack_band), HJC_FAILURE_STRAIN_FLOOR);
        return (d_eps_p + d_open) / eps_ft;
    }
    let base = (p + u.t) / u.fc;
    let eps_f = max(
        max(u.d1 * pow(max(base, HJC_POW_BASE_FLOOR), u.d2), u.ef_min),
        HJC_FAILURE_STRAIN_FLOOR,
    );
    return (d_eps_p + d_mu_p) / eps_f;
}

// Sound speed sqrt((dp/dμ + 4G/3)/ρ₀) (m/s).
fn hjc_sound_speed(u: SphUniform, tangent: f32) -> f32 {
    return sqrt(max((tangent + 4.0 / 3.0 * u.shear_modulus) / u.density, 0.0));
}
