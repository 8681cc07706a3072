//! Johnson–Cook strength (paper eq. 13) and damage (eq. 15-16), physics.md §2.1 and §2.3: the
//! law's own formulas, pure functions of its constants, the rate and the homologous temperature
//! T*. Which law a material takes, T* itself, the hardening floor and the radial return are
//! flow.rs's, which calls into this module, never the other way round.

/// Johnson–Cook flow-stress constants, paper eq. (13), physics.md §2.1. Units: Pa.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct JcFlow {
    pub a: f32,
    pub b: f32,
    pub n: f32,
    pub c: f32,
    pub m: f32,
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

/// Smallest base handed to `powf`: WGSL's `pow(x, y)` is undefined for x ≤ 0, so every power of a
/// quantity that may be 0 (ε_p, T*) is taken of `max(x, POW_BASE_FLOOR)`. (1e-30)^0.26·B is far below
/// one f32 ulp of A, so the flow stress at ε_p = 0 is still A to the last bit.
pub(crate) const POW_BASE_FLOOR: f32 = 1.0e-30;

/// Failure strain never drops below this, so Δε_p/ε_f stays finite (no Inf in the damage sum).
pub const FAILURE_STRAIN_FLOOR: f32 = 1.0e-6;

/// Largest exponent D₃σ* handed to `exp`: e^80 ≈ 5.5e34 keeps ε_f finite in f32 even for extreme
/// compressive triaxiality (where ε_f is effectively infinite anyway).
pub(crate) const DAMAGE_EXP_CAP: f32 = 80.0;

/// Rate factor 1 + C ln ε̇*, ε̇* = max(ε̇/ε̇₀, 1) (paper eq. 13).
fn rate_factor(c: f32, eps_rate: f32, eps_rate_ref: f32) -> f32 {
    1.0 + c * (eps_rate / eps_rate_ref).max(1.0).ln()
}

/// Thermal softening factor 1 − T*^m (paper eq. 13), T* the homologous temperature in [0, 1].
fn thermal_factor(j: &JcFlow, homologous_t: f32) -> f32 {
    1.0 - homologous_t.max(POW_BASE_FLOOR).powf(j.m)
}

/// Flow stress, paper eq. (13), physics.md §2.1:
/// σ_y = (A + B ε_p^n)(1 + C ln ε̇*)(1 − T*^m), ε̇* = max(ε̇/ε̇₀, 1), ε_p < 0 read as 0. Pa.
pub fn flow_stress(
    j: &JcFlow,
    eps_p: f32,
    eps_rate: f32,
    eps_rate_ref: f32,
    homologous_t: f32,
) -> f32 {
    let hardening = j.a + j.b * eps_p.max(POW_BASE_FLOOR).powf(j.n);
    hardening * rate_factor(j.c, eps_rate, eps_rate_ref) * thermal_factor(j, homologous_t)
}

/// Hardening modulus H = dσ_y/dε_p = n B ε_p^(n−1)(1 + C ln ε̇*)(1 − T*^m) (derivative of
/// eq. 13), Pa. Infinite at ε_p = 0 for n < 1: the caller floors ε_p first
/// (`flow::hardening_modulus`), so it must be > 0.
pub fn hardening_modulus(
    j: &JcFlow,
    eps_p: f32,
    eps_rate: f32,
    eps_rate_ref: f32,
    homologous_t: f32,
) -> f32 {
    debug_assert!(
        eps_p > 0.0,
        "Johnson–Cook H at ε_p = {eps_p}: floor it first"
    );
    let slope = j.n * j.b * eps_p.powf(j.n - 1.0);
    slope * rate_factor(j.c, eps_rate, eps_rate_ref) * thermal_factor(j, homologous_t)
}

/// Failure strain, paper eq. (16), physics.md §2.3:
/// ε_f = [D₁ + D₂ exp(D₃σ*)](1 + D₄ ln ε̇*)(1 + D₅T*), ε̇* = max(ε̇/ε̇₀, 1), σ* = σ_mean/σ_eq
/// (tension-positive); ε_f = ε_f,min when σ* ≥ 1.5. Floored at [`FAILURE_STRAIN_FLOOR`].
pub fn failure_strain(
    d: &JcDamage,
    triaxiality: f32,
    eps_rate: f32,
    eps_rate_ref: f32,
    homologous_t: f32,
) -> f32 {
    let stress_term = d.d1 + d.d2 * (d.d3 * triaxiality).min(DAMAGE_EXP_CAP).exp();
    let eps_f = stress_term
        * (1.0 + d.d4 * (eps_rate / eps_rate_ref).max(1.0).ln())
        * (1.0 + d.d5 * homologous_t);
    let eps_f = if triaxiality >= 1.5 {
        d.eps_f_min
    } else {
        eps_f
    };
    eps_f.max(FAILURE_STRAIN_FLOOR)
}

/// Damage increment, paper eq. (15), physics.md §2.3: ΔD = Δε_p/ε_f with ε_f from eq. (16)
/// ([`failure_strain`]). The caller sums it and fails the element at D = 1.
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

/// Spall, physics.md §2.3: true when the tension-positive mean stress σ_mean > σ_spall; the
/// element then fails at once.
pub fn spalls(d: &JcDamage, mean_stress: f32) -> bool {
    mean_stress > d.spall_stress
}

#[cfg(test)]
mod tests {
    use super::super::assert_rel;
    use super::*;

    /// The paper's 4340 set (physics.md §2.1).
    fn steel() -> JcFlow {
        JcFlow {
            a: 792.0e6,
            b: 510.0e6,
            n: 0.26,
            c: 0.014,
            m: 1.03,
        }
    }

    /// The paper's damage set (physics.md §2.3).
    fn damage() -> JcDamage {
        JcDamage {
            d1: 0.05,
            d2: 3.44,
            d3: -2.12,
            d4: 0.002,
            d5: 0.61,
            spall_stress: 6.0e9,
            eps_f_min: 0.19,
        }
    }

    /// T* of 500 K for 4340: (500 − 293)/(1793 − 293) = 207/1500.
    const T_STAR: f32 = 0.138;

    #[test]
    fn flow_stress_matches_hand_value() {
        // 0.1^0.26 = e^(0.26·ln 0.1) = e^(−0.5986721) = 0.5495409 → A + B·0.5495409 = 1072.2658 MPa
        // 1 + 0.014·ln 1000 = 1 + 0.014·6.9077553 = 1.0967086
        // T*^m = 0.138^1.03 = e^(1.03·(−1.9805016)) = e^(−2.0399166) = 0.1300396 → 0.8699604
        // 1072.2658e6 · 1.0967086 · 0.8699604 = 1023.0414 MPa
        assert_rel(
            flow_stress(&steel(), 0.1, 1.0e3, 1.0, T_STAR),
            1023.0414e6,
            1e-5,
        );
        // ε_p = 0, ε̇ below ε̇₀ (ε̇* = 1), T* = 0: exactly A; negative ε_p reads as 0.
        assert_rel(flow_stress(&steel(), 0.0, 0.5, 1.0, 0.0), 792.0e6, 1e-7);
        assert_rel(flow_stress(&steel(), -0.3, 0.5, 1.0, 0.0), 792.0e6, 1e-7);
        // At the melt (T* = 1) the strength is zero.
        assert_eq!(flow_stress(&steel(), 0.1, 1.0e3, 1.0, 1.0), 0.0);
    }

    #[test]
    fn hardening_modulus_matches_hand_value() {
        // nB ε_p^(n−1) = 0.26·510e6·0.1^(−0.74) = 132.6e6·5.4954087 = 728.6912 MPa
        // × 1.0967086 × 0.8699604 = 695.2392 MPa
        assert_rel(
            hardening_modulus(&steel(), 0.1, 1.0e3, 1.0, T_STAR),
            695.2392e6,
            1e-5,
        );
        // At 1e-4 (flow.rs's floor): 132.6e6·(1e-4)^(−0.74) = 132.6e6·912.01084 = 120.93264 GPa
        assert_rel(
            hardening_modulus(&steel(), 1.0e-4, 1.0, 1.0, 0.0),
            120.93264e9,
            1e-5,
        );
    }

    #[test]
    fn failure_strain_matches_eq_16() {
        let d = damage();
        // ε̇* = 1, T* = 0: ε_f = D₁ + D₂ e^(D₃σ*)
        // σ* = −0.5: 0.05 + 3.44·e^(1.06) = 0.05 + 3.44·2.8863710 = 9.9791162
        assert_rel(failure_strain(&d, -0.5, 1.0, 1.0, 0.0), 9.9791162, 1e-5);
        // σ* = 0.33: 0.05 + 3.44·e^(−0.6996) = 0.05 + 3.44·0.4967840 = 1.7589369
        assert_rel(failure_strain(&d, 0.33, 1.0, 1.0, 0.0), 1.7589369, 1e-5);
        // σ* = 1.0: 0.05 + 3.44·e^(−2.12) = 0.05 + 3.44·0.1200316 = 0.4629088
        assert_rel(failure_strain(&d, 1.0, 1.0, 1.0, 0.0), 0.4629088, 1e-5);
        // Rate and temperature: 1.7589369·(1 + 0.002·ln 1000)(1 + 0.61·0.138)
        //   = 1.7589369·1.0138155·1.08418 = 1.9333504
        assert_rel(failure_strain(&d, 0.33, 1.0e3, 1.0, 0.138), 1.9333504, 1e-5);
        // σ* ≥ 1.5: ε_f,min.
        assert_rel(failure_strain(&d, 1.5, 1.0, 1.0, 0.0), 0.19, 1e-7);
        assert_rel(failure_strain(&d, 4.0, 1.0e3, 1.0, 0.5), 0.19, 1e-7);
        // Extreme compression stays finite.
        assert!(failure_strain(&d, -1.0e6, 1.0, 1.0, 0.0).is_finite());
    }

    #[test]
    fn damage_increment_and_spall() {
        let d = damage();
        // 0.01/0.4629088 = 0.0216025
        assert_rel(
            damage_increment(&d, 0.01, 1.0, 1.0, 1.0, 0.0),
            0.0216025,
            1e-5,
        );
        // A zero failure strain is floored: the increment stays finite.
        let brittle = JcDamage {
            d1: 0.0,
            d2: 0.0,
            eps_f_min: 0.0,
            ..d
        };
        assert!(damage_increment(&brittle, 0.01, 0.0, 1.0, 1.0, 0.0).is_finite());
        assert!(damage_increment(&brittle, 0.01, 2.0, 1.0, 1.0, 0.0).is_finite());
        assert!(spalls(&d, 6.1e9));
        assert!(!spalls(&d, 5.9e9));
        assert!(!spalls(&d, -7.0e9));
    }
}
