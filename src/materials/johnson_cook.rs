//! Johnson–Cook strength (paper eq. 13) and damage (eq. 15-16), physics.md §2.1 and §2.3.

/// Johnson–Cook flow-stress constants (physics.md §2.1). Units: Pa, K, 1/s.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JcStrength {
    pub a: f32,
    pub b: f32,
    pub n: f32,
    pub c: f32,
    pub m: f32,
    /// Reference plastic strain rate ε̇₀ (1/s).
    pub eps_rate_ref: f32,
    pub t_room: f32,
    pub t_melt: f32,
}

/// Johnson–Cook failure-strain constants (physics.md §2.3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JcDamage {
    pub d1: f32,
    pub d2: f32,
    pub d3: f32,
    pub d4: f32,
    pub d5: f32,
    /// Tensile mean stress (Pa, positive) beyond which an element spalls at once.
    pub spall_stress: f32,
    /// Failure strain used when the triaxiality σ* ≥ 1.5.
    pub eps_f_min: f32,
}

/// Homologous temperature T* = (T − T_room)/(T_melt − T_room), clamped to [0, 1] (physics.md §2.1).
pub fn homologous_temperature(s: &JcStrength, temperature: f32) -> f32 {
    ((temperature - s.t_room) / (s.t_melt - s.t_room)).clamp(0.0, 1.0)
}

/// Normalised strain rate ε̇* = max(ε̇/ε̇₀, 1).
fn rate_star(eps_rate: f32, eps_rate_ref: f32) -> f32 {
    (eps_rate / eps_rate_ref).max(1.0)
}

/// Flow stress, paper eq. (13): σ_y = (A + B ε_p^n)(1 + C ln ε̇*)(1 − T*^m).
pub fn flow_stress(s: &JcStrength, eps_p: f32, eps_rate: f32, temperature: f32) -> f32 {
    let hardening = s.a + s.b * eps_p.max(0.0).powf(s.n);
    let rate = 1.0 + s.c * rate_star(eps_rate, s.eps_rate_ref).ln();
    let thermal = 1.0 - homologous_temperature(s, temperature).powf(s.m);
    hardening * rate * thermal
}

/// Plastic strain below which the hardening slope is evaluated at this floor: dσ_y/dε_p =
/// nBε_p^(n−1)·… is infinite at ε_p = 0 for n < 1, and the radial return needs a finite slope.
const SLOPE_FLOOR: f32 = 1.0e-4;

/// Hardening modulus H = dσ_y/dε_p at fixed rate and temperature.
pub fn hardening_modulus(s: &JcStrength, eps_p: f32, eps_rate: f32, temperature: f32) -> f32 {
    let e = eps_p.max(SLOPE_FLOOR);
    let rate = 1.0 + s.c * rate_star(eps_rate, s.eps_rate_ref).ln();
    let thermal = 1.0 - homologous_temperature(s, temperature).powf(s.m);
    s.n * s.b * e.powf(s.n - 1.0) * rate * thermal
}

/// Result of a radial return: the plastic strain increment, the factor that scales the trial
/// deviator back onto the yield surface (1 when elastic), and the flow stress at the end.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RadialReturn {
    pub d_eps_p: f32,
    pub scale: f32,
    pub flow_stress: f32,
}

/// Radial return (physics.md §2.1) of a trial equivalent stress σ_trial. One iteration is the
/// linearised step Δε_p = (σ_trial − σ_y)/(3G + H) the GPU uses; more iterations solve
/// f(Δε_p) = σ_trial − 3GΔε_p − σ_y(ε_p + Δε_p) = 0 by Newton's method (the CPU reference).
pub fn radial_return(
    s: &JcStrength,
    shear_modulus: f32,
    sigma_eq_trial: f32,
    eps_p: f32,
    eps_rate: f32,
    temperature: f32,
    iterations: u32,
) -> RadialReturn {
    let sy0 = flow_stress(s, eps_p, eps_rate, temperature);
    if !(sigma_eq_trial > sy0) {
        return RadialReturn {
            d_eps_p: 0.0,
            scale: 1.0,
            flow_stress: sy0,
        };
    }
    let g3 = 3.0 * shear_modulus;
    let mut d = 0.0f32;
    for _ in 0..iterations.max(1) {
        let sy = flow_stress(s, eps_p + d, eps_rate, temperature);
        let f = sigma_eq_trial - g3 * d - sy;
        let step = f / (g3 + hardening_modulus(s, eps_p + d, eps_rate, temperature));
        d = (d + step).max(0.0);
        if step.abs() <= 1.0e-7 * d {
            break;
        }
    }
    let scale = ((sigma_eq_trial - g3 * d) / sigma_eq_trial).clamp(0.0, 1.0);
    RadialReturn {
        d_eps_p: d,
        scale,
        flow_stress: flow_stress(s, eps_p + d, eps_rate, temperature),
    }
}

/// Failure strain, paper eq. (16): ε_f = [D₁ + D₂ exp(D₃ σ*)](1 + D₄ ln ε̇*)(1 + D₅ T*), and
/// ε_f,min when σ* ≥ 1.5 (physics.md §2.3). Floored so that Δε_p/ε_f stays finite.
pub fn failure_strain(
    d: &JcDamage,
    triaxiality: f32,
    eps_rate: f32,
    eps_rate_ref: f32,
    homologous_t: f32,
) -> f32 {
    if triaxiality >= 1.5 {
        return d.eps_f_min;
    }
    let base = d.d1 + d.d2 * (d.d3 * triaxiality).exp();
    let eps_f =
        base * (1.0 + d.d4 * rate_star(eps_rate, eps_rate_ref).ln()) * (1.0 + d.d5 * homologous_t);
    eps_f.max(1.0e-6)
}

/// Damage increment, paper eq. (15): ΔD = Δε_p/ε_f.
pub fn damage_increment(
    d: &JcDamage,
    d_eps_p: f32,
    triaxiality: f32,
    eps_rate: f32,
    eps_rate_ref: f32,
    homologous_t: f32,
) -> f32 {
    d_eps_p / failure_strain(d, triaxiality, eps_rate, eps_rate_ref, homologous_t)
}

/// Spall: a tensile mean stress (tension positive) beyond σ_spall fails the element at once.
pub fn spalls(d: &JcDamage, mean_stress: f32) -> bool {
    mean_stress > d.spall_stress
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The paper's 4340 constants (physics.md §2.1, §2.3).
    const S: JcStrength = JcStrength {
        a: 792e6,
        b: 510e6,
        n: 0.26,
        c: 0.014,
        m: 1.03,
        eps_rate_ref: 1.0,
        t_room: 293.0,
        t_melt: 1793.0,
    };
    const D: JcDamage = JcDamage {
        d1: 0.05,
        d2: 3.44,
        d3: -2.12,
        d4: 0.002,
        d5: 0.61,
        spall_stress: 6.0e9,
        eps_f_min: 0.19,
    };

    fn close(a: f32, b: f64, rel: f64) -> bool {
        ((a as f64 - b) / b).abs() < rel
    }

    /// ε_p = 0.1, ε̇ = 1000/s, T = 500 K by hand:
    /// 0.1^0.26 = 0.549541; A + B·0.549541 = 792 + 280.266 = 1072.266 MPa;
    /// 1 + 0.014 ln 1000 = 1.0967086; T* = 207/1500 = 0.138, 0.138^1.03 = 0.130040 → 0.869960;
    /// σ_y = 1072.266 · 1.0967086 · 0.869960 = 1023.04 MPa.
    #[test]
    fn flow_stress_by_hand() {
        assert!(
            close(flow_stress(&S, 0.1, 1000.0, 500.0), 1023.04e6, 2e-5),
            "{}",
            flow_stress(&S, 0.1, 1000.0, 500.0)
        );
        // Quasi-static, room temperature, no strain: A.
        assert!(close(flow_stress(&S, 0.0, 0.5, 293.0), 792e6, 1e-6));
        // Melted: no strength.
        assert_eq!(flow_stress(&S, 0.1, 1.0, 2000.0), 0.0);
    }

    /// The iterated return lands on the yield surface; the single linearised step is close.
    #[test]
    fn radial_return_lands_on_the_yield_surface() {
        let g = 81.8e9;
        let trial = 1.5e9;
        let it = radial_return(&S, g, trial, 0.05, 1e3, 400.0, 20);
        let f = trial - 3.0 * g * it.d_eps_p - flow_stress(&S, 0.05 + it.d_eps_p, 1e3, 400.0);
        assert!((f / trial).abs() < 1e-5, "residual {f}");
        assert!(close(it.scale * trial, it.flow_stress as f64, 1e-5));
        let one = radial_return(&S, g, trial, 0.05, 1e3, 400.0, 1);
        let sy = flow_stress(&S, 0.05, 1e3, 400.0);
        let expected = (trial - sy) / (3.0 * g + hardening_modulus(&S, 0.05, 1e3, 400.0));
        assert!(close(one.d_eps_p, expected as f64, 1e-6));
        // Measured: the single step differs from the converged one by < 1 % here.
        assert!(
            ((one.d_eps_p - it.d_eps_p) / it.d_eps_p).abs() < 0.01,
            "{} vs {}",
            one.d_eps_p,
            it.d_eps_p
        );
        // Elastic trial: nothing happens.
        assert_eq!(
            radial_return(&S, g, 0.5e9, 0.0, 1.0, 293.0, 5),
            RadialReturn {
                d_eps_p: 0.0,
                scale: 1.0,
                flow_stress: 792e6
            }
        );
    }

    /// Failure strain by hand at ε̇* = 1, T* = 0:
    /// σ* = −0.5: 0.05 + 3.44 e^{1.06} = 0.05 + 3.44·2.886371 = 9.979116;
    /// σ* = 0.33: 0.05 + 3.44 e^{−0.6996} = 0.05 + 3.44·0.496786 = 1.758944;
    /// σ* = 1.0: 0.05 + 3.44 e^{−2.12} = 0.05 + 3.44·0.120032 = 0.462910;
    /// σ* ≥ 1.5: ε_f,min = 0.19.
    #[test]
    fn failure_strain_by_hand() {
        assert!(close(
            failure_strain(&D, -0.5, 1.0, 1.0, 0.0),
            9.979116,
            1e-5
        ));
        assert!(close(
            failure_strain(&D, 0.33, 1.0, 1.0, 0.0),
            1.758944,
            1e-5
        ));
        assert!(close(
            failure_strain(&D, 1.0, 1.0, 1.0, 0.0),
            0.462910,
            1e-5
        ));
        assert_eq!(failure_strain(&D, 1.5, 1.0, 1.0, 0.0), 0.19);
        assert_eq!(failure_strain(&D, 3.0, 1e5, 1.0, 0.5), 0.19);
        // Rate and temperature factors: (1 + 0.002 ln 1000)(1 + 0.61·0.5) = 1.013816 · 1.305.
        assert!(close(
            failure_strain(&D, 1.0, 1000.0, 1.0, 0.5),
            0.462910 * 1.013816 * 1.305,
            1e-5
        ));
        assert!(close(
            damage_increment(&D, 0.01, 1.0, 1.0, 1.0, 0.0),
            0.01 / 0.462910,
            1e-5
        ));
        assert!(spalls(&D, 6.1e9) && !spalls(&D, 5.9e9) && !spalls(&D, -10e9));
    }
}
