// Johnson–Cook strength (paper eq. 13) and damage (eq. 15-16), physics.md §2.1 and §2.3: the
// WGSL twin of src/materials/johnson_cook.rs, with the law dispatch, hardening floor and radial
// return of src/materials/flow.rs and the law of src/materials/zerilli_armstrong.rs, function
// for function, same formulas in the same order, with the same floors and caps (every
// pow/exp/log argument guarded as there). The constants come from FemUniform
// (src/gpu/params.rs).

// materials::flow::RadialReturn.
struct JcReturn {
    // Plastic strain increment Δε_p >= 0 of this step.
    d_eps_p: f32,
    // Factor on the trial deviator in [0, 1]; 1 when elastic.
    scale: f32,
    // Yield stress σ_y(ε_p + Δε_p) at the end of the step (Pa).
    flow_stress: f32,
}

// T* = (T − T_room)/(T_melt − T_room), clamped to [0, 1].
fn jc_homologous_temperature(u: FemUniform, temperature: f32) -> f32 {
    return clamp((temperature - u.t_room) / (u.t_melt - u.t_room), 0.0, 1.0);
}

// 1 + C ln ε̇*, ε̇* = max(ε̇/ε̇₀, 1).
fn jc_rate_factor(c: f32, eps_rate: f32, eps_rate_ref: f32) -> f32 {
    return 1.0 + c * log(max(eps_rate / eps_rate_ref, 1.0));
}

// 1 − T*^m.
fn jc_thermal_factor(u: FemUniform, temperature: f32) -> f32 {
    return 1.0 - pow(max(jc_homologous_temperature(u, temperature), JC_POW_BASE_FLOOR), u.jc_m);
}

// zerilli_armstrong.rs activation: exp(−C₃T + C₄T ln ε̇*), ε̇* = max(ε̇/ε̇₀, 1), the exponent
// held at or below 0 (the 0 K value 1; no overflow, no ∞·0).
fn za_activation(u: FemUniform, eps_rate: f32, temperature: f32) -> f32 {
    let ln_rate = log(max(eps_rate / u.eps_rate_ref, 1.0));
    return exp(min(max(temperature, 0.0) * (u.za_c4 * ln_rate - u.za_c3), 0.0));
}

// σ_y = (A + B ε_p^n)(1 + C ln ε̇*)(1 − T*^m) (Pa), ε_p < 0 read as 0; with flow_law 1,
// Zerilli–Armstrong's σ_y = C₀ + C₂ √ε_p exp(−C₃T + C₄T ln ε̇*) (zerilli_armstrong.rs).
fn jc_flow_stress(u: FemUniform, eps_p: f32, eps_rate: f32, temperature: f32) -> f32 {
    if (u.flow_law == 1u) {
        return u.za_c0 + u.za_c2 * sqrt(max(eps_p, 0.0)) * za_activation(u, eps_rate, temperature);
    }
    let hardening = u.jc_a + u.jc_b * pow(max(eps_p, JC_POW_BASE_FLOOR), u.jc_n);
    return hardening * jc_rate_factor(u.jc_c, eps_rate, u.eps_rate_ref)
        * jc_thermal_factor(u, temperature);
}

// H = n B ε_p^(n−1)(1 + C ln ε̇*)(1 − T*^m) (Pa), ε_p floored at JC_HARDENING_EPS_FLOOR; with
// flow_law 1, H = C₂ exp(−C₃T + C₄T ln ε̇*)/(2√ε_p), ε_p floored the same.
fn jc_hardening_modulus(u: FemUniform, eps_p: f32, eps_rate: f32, temperature: f32) -> f32 {
    if (u.flow_law == 1u) {
        let root = sqrt(max(eps_p, JC_HARDENING_EPS_FLOOR));
        return 0.5 * u.za_c2 * za_activation(u, eps_rate, temperature) / root;
    }
    let slope = u.jc_n * u.jc_b * pow(max(eps_p, JC_HARDENING_EPS_FLOOR), u.jc_n - 1.0);
    return slope * jc_rate_factor(u.jc_c, eps_rate, u.eps_rate_ref)
        * jc_thermal_factor(u, temperature);
}

// J2 radial return: Newton on f(Δε_p) = σ_trial − 3GΔε_p − σ_y(ε_p + Δε_p) from 0, kept in
// the bracket [lo, hi] ∋ root (bisection when a step leaves it), `iterations` at most; 1 is
// the single linearised step. The same iteration as the CPU's, so both land on the same root.
fn jc_radial_return(
    u: FemUniform,
    shear_modulus: f32,
    sigma_eq_trial: f32,
    eps_p_in: f32,
    eps_rate: f32,
    temperature: f32,
    iterations: u32,
) -> JcReturn {
    let eps_p = max(eps_p_in, 0.0);
    let yield_now = jc_flow_stress(u, eps_p, eps_rate, temperature);
    if (sigma_eq_trial <= yield_now) {
        return JcReturn(0.0, 1.0, yield_now);
    }
    let three_g = 3.0 * shear_modulus;
    var lo = 0.0;
    var hi = sigma_eq_trial / max(three_g, MIN_POSITIVE);
    var d_eps_p = 0.0;
    let n = max(iterations, 1u);
    for (var k = 0u; k < n; k++) {
        let eps = eps_p + d_eps_p;
        let f = sigma_eq_trial - three_g * d_eps_p - jc_flow_stress(u, eps, eps_rate, temperature);
        if (f > 0.0) {
            lo = d_eps_p;
        } else {
            hi = d_eps_p;
        }
        let newton = d_eps_p
            + f / (three_g + jc_hardening_modulus(u, eps, eps_rate, temperature));
        d_eps_p = select(0.5 * (lo + hi), newton, newton > lo && newton <= hi);
        if (abs(f) <= JC_RETURN_TOLERANCE * sigma_eq_trial) {
            break;
        }
    }
    let scale = clamp(
        (sigma_eq_trial - three_g * d_eps_p) / max(sigma_eq_trial, MIN_POSITIVE),
        0.0,
        1.0,
    );
    let flow = jc_flow_stress(u, eps_p + d_eps_p, eps_rate, temperature);
    return JcReturn(d_eps_p, scale, flow);
}

// ε_f = [D₁ + D₂ exp(D₃σ*)](1 + D₄ ln ε̇*)(1 + D₅T*); ε_f,min when σ* >= 1.5; floored.
fn jc_failure_strain(
    u: FemUniform,
    triaxiality: f32,
    eps_rate: f32,
    eps_rate_ref: f32,
    homologous_t: f32,
) -> f32 {
    let stress_term = u.d1 + u.d2 * exp(min(u.d3 * triaxiality, JC_DAMAGE_EXP_CAP));
    let eps_f = stress_term
        * (1.0 + u.d4 * log(max(eps_rate / eps_rate_ref, 1.0)))
        * (1.0 + u.d5 * homologous_t);
    return max(select(eps_f, u.eps_f_min, triaxiality >= 1.5), JC_FAILURE_STRAIN_FLOOR);
}

// ΔD = Δε_p/ε_f (eq. 15); the caller sums it and fails the element at D = 1.
fn jc_damage_increment(
    u: FemUniform,
    d_eps_p: f32,
    triaxiality: f32,
    eps_rate: f32,
    eps_rate_ref: f32,
    homologous_t: f32,
) -> f32 {
    return d_eps_p / jc_failure_strain(u, triaxiality, eps_rate, eps_rate_ref, homologous_t);
}

// Spall: the tension-positive mean stress exceeds σ_spall.
fn jc_spalls(u: FemUniform, mean_stress: f32) -> bool {
    return mean_stress > u.spall_stress;
}
