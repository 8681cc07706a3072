//! Holmquist–Johnson–Cook concrete, physics.md §3.1.

/// HJC constants. Pressures and strengths in Pa, density in kg/m³.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hjc {
    pub density: f32,
    pub shear_modulus: f32,
    pub a: f32,
    pub b: f32,
    pub n: f32,
    pub c: f32,
    pub s_max: f32,
    pub fc: f32,
    /// Tensile strength T (Pa, positive).
    pub t: f32,
    pub eps_rate_ref: f32,
    pub ef_min: f32,
    pub d1: f32,
    pub d2: f32,
    pub p_crush: f32,
    pub mu_crush: f32,
    pub k1: f32,
    pub k2: f32,
    pub k3: f32,
    pub p_lock: f32,
    pub mu_lock: f32,
}

impl Hjc {
    /// The 48 MPa reference set of Holmquist, Johnson & Cook (1993), physics.md §3.1.
    pub fn reference_48mpa() -> Hjc {
        Hjc {
            density: 2440.0,
            shear_modulus: 14.86e9,
            a: 0.79,
            b: 1.60,
            n: 0.61,
            c: 0.007,
            s_max: 7.0,
            fc: 48.0e6,
            t: 4.0e6,
            eps_rate_ref: 1.0,
            ef_min: 0.01,
            d1: 0.04,
            d2: 1.0,
            p_crush: 16.0e6,
            mu_crush: 0.001,
            k1: 85.0e9,
            k2: -171.0e9,
            k3: 208.0e9,
            p_lock: 0.8e9,
            mu_lock: 0.10,
        }
    }

    /// The one rule for other strengths (physics.md §3.1): from f_c (Pa) and ρ₀ (kg/m³) keep the
    /// reference A, B, N, C, S_max, D₁, D₂, EF_min, K₁–K₃, P_lock, μ_lock and set
    /// P_crush = f_c/3, E = 4730 √f_c[MPa] MPa (ACI 318), ν = 0.2, G and K_el from E and ν,
    /// μ_crush = P_crush/K_el, T = 0.62 √f_c[MPa] MPa (ACI 318 modulus of rupture).
    pub fn from_fc(fc: f32, density: f32) -> Hjc {
        let fc_mpa = fc / 1.0e6;
        let youngs = 4730.0e6 * fc_mpa.sqrt();
        let nu = 0.2;
        let shear = youngs / (2.0 * (1.0 + nu));
        let bulk_elastic = youngs / (3.0 * (1.0 - 2.0 * nu));
        let p_crush = fc / 3.0;
        Hjc {
            density,
            shear_modulus: shear,
            fc,
            t: 0.62e6 * fc_mpa.sqrt(),
            p_crush,
            mu_crush: p_crush / bulk_elastic,
            ..Hjc::reference_48mpa()
        }
    }
}
/// Result of the HJC equation of state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HjcEos {
    /// Pressure (Pa, compression positive).
    pub p: f32,
    /// Largest volumetric strain μ reached, updated.
    pub mu_max: f32,
    /// Increase of the plastic volumetric strain μ_p in this call (≥ 0), for the damage.
    pub d_mu_p: f32,
    /// Current dp/dμ (loading slope on the loading curve, unloading modulus below it).
    pub tangent: f32,
}

impl Hjc {
    /// Elastic bulk modulus K_el = P_crush/μ_crush.
    pub fn bulk_elastic(&self) -> f32 {
        self.p_crush / self.mu_crush
    }
}

/// Pressure and slope on the loading (virgin) curve at μ: elastic to (μ_crush, P_crush), linear
/// crushing to (μ_lock, P_lock), then fully dense. The fully dense branch is written
/// p = P_lock + K₁μ̄ + K₂μ̄² + K₃μ̄³, μ̄ = (μ − μ_lock)/(1 + μ_lock), so that it joins the crushing
/// line at P_lock: physics.md's literal K₁μ̄ + … would drop to 0 at μ_lock (in HJC 1993 the
/// locking strain of μ̄ is a separate, smaller value chosen to make the curve continuous).
fn loading(h: &Hjc, mu: f32) -> (f32, f32) {
    if mu <= h.mu_crush {
        let k = h.bulk_elastic();
        (k * mu, k)
    } else if mu <= h.mu_lock {
        let k = (h.p_lock - h.p_crush) / (h.mu_lock - h.mu_crush);
        (h.p_crush + k * (mu - h.mu_crush), k)
    } else {
        let m = (mu - h.mu_lock) / (1.0 + h.mu_lock);
        let p = h.p_lock + m * (h.k1 + m * (h.k2 + m * h.k3));
        let slope = (h.k1 + m * (2.0 * h.k2 + 3.0 * h.k3 * m)) / (1.0 + h.mu_lock);
        (p, slope.max(h.bulk_elastic()))
    }
}

/// Unloading modulus after crushing to μ_max: K_el interpolated to K₁ as μ_max goes from
/// μ_crush to μ_lock (physics.md §3.1).
fn unloading_modulus(h: &Hjc, mu_max: f32) -> f32 {
    let f = ((mu_max - h.mu_crush) / (h.mu_lock - h.mu_crush)).clamp(0.0, 1.0);
    (1.0 - f) * h.bulk_elastic() + f * h.k1
}

/// Plastic volumetric strain left after crushing to μ_max: μ_max − p(μ_max)/K_unload(μ_max).
fn plastic_volumetric_strain(h: &Hjc, mu_max: f32) -> f32 {
    if mu_max <= h.mu_crush {
        return 0.0;
    }
    (mu_max - loading(h, mu_max).0 / unloading_modulus(h, mu_max)).max(0.0)
}

/// Three-part HJC EOS with crushing history and tension cut-off p ≥ −T(1 − D) (physics.md §3.1,
/// the OpenRadioss LAW126 arrangement): on the loading curve when μ ≥ μ_max, else unloading
/// from (μ_max, p(μ_max)) along K_unload.
pub fn pressure(h: &Hjc, mu: f32, mu_max: f32, damage: f32) -> HjcEos {
    let new_max = mu.max(mu_max);
    let (p_max, slope) = loading(h, new_max);
    let (p, tangent) = if mu >= new_max {
        (p_max, slope)
    } else {
        let k = unloading_modulus(h, new_max);
        (p_max - k * (new_max - mu), k)
    };
    let d_mu_p =
        (plastic_volumetric_strain(h, new_max) - plastic_volumetric_strain(h, mu_max)).max(0.0);
    HjcEos {
        p: p.max(-h.t * (1.0 - damage)),
        mu_max: new_max,
        d_mu_p,
        tangent: tangent.max(h.bulk_elastic()),
    }
}

/// Allowed equivalent stress (Pa): P* ≥ 0: f_c·min([A(1 − D) + B P*^N](1 + C ln ε̇*), S_max);
/// P* < 0: f_c·A(1 + p/T)(1 − D)(1 + C ln ε̇*), floored at 0 (physics.md §3.1).
pub fn yield_stress(h: &Hjc, p: f32, damage: f32, eps_rate: f32) -> f32 {
    let rate = 1.0 + h.c * (eps_rate / h.eps_rate_ref).max(1.0).ln();
    let p_star = p / h.fc;
    let s = if p_star >= 0.0 {
        ((h.a * (1.0 - damage) + h.b * p_star.powf(h.n)) * rate).min(h.s_max)
    } else {
        h.a * (1.0 + p / h.t) * (1.0 - damage) * rate
    };
    h.fc * s.max(0.0)
}

/// Damage increment (Δε_p + Δμ_p)/max(D₁(P* + T*)^D₂, EF_min), T* = T/f_c (physics.md §3.1).
pub fn damage_increment(h: &Hjc, p: f32, d_eps_p: f32, d_mu_p: f32) -> f32 {
    let x = ((p + h.t) / h.fc).max(0.0);
    (d_eps_p + d_mu_p) / (h.d1 * x.powf(h.d2)).max(h.ef_min)
}

/// Sound speed from the EOS tangent: c = sqrt((dp/dμ + 4G/3)/ρ₀).
pub fn sound_speed(h: &Hjc, tangent: f32) -> f32 {
    ((tangent + 4.0 / 3.0 * h.shear_modulus) / h.density).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f32, b: f64, rel: f64) -> bool {
        ((a as f64 - b) / b).abs() < rel
    }

    const R: fn() -> Hjc = Hjc::reference_48mpa;

    /// Reference set: K_el = 16e6/0.001 = 16 GPa; crushing slope (0.8e9 − 16e6)/(0.099) = 7.91919 GPa.
    #[test]
    fn eos_branches_by_hand() {
        let h = R();
        // Elastic: p = 16e9 · 5e-4 = 8 MPa.
        let e = pressure(&h, 5e-4, 0.0, 0.0);
        assert!(
            close(e.p, 8e6, 1e-5)
                && e.mu_max == 5e-4
                && e.d_mu_p == 0.0
                && close(e.tangent, 16e9, 1e-5)
        );
        // Crushing, loading: μ = 0.05: 16e6 + 7.91919e9 · 0.049 = 404.040 MPa.
        let c = pressure(&h, 0.05, 0.0, 0.0);
        assert!(close(c.p, 404.0404e6, 1e-5), "{}", c.p);
        // μ_p(0.05): K_unload = 16e9 + (0.049/0.099)(85e9 − 16e9) = 50.1515e9;
        // μ_p = 0.05 − 404.0404e6/50.1515e9 = 0.05 − 0.0080563 = 0.0419437.
        assert!(close(c.d_mu_p, 0.0419437, 1e-4), "{}", c.d_mu_p);
        // Unloading from μ_max = 0.05 to μ = 0.045: 404.0404e6 − 50.1515e9·0.005 = 153.283 MPa.
        let u = pressure(&h, 0.045, 0.05, 0.0);
        assert!(
            close(u.p, 153.283e6, 1e-4) && u.mu_max == 0.05 && u.d_mu_p == 0.0,
            "{u:?}"
        );
        assert!(close(u.tangent, 50.1515e9, 1e-4));
        // Fully dense: μ = 0.12: μ̄ = 0.02/1.1 = 0.0181818;
        // p = 0.8e9 + 85e9·0.0181818 − 171e9·3.30579e-4 + 208e9·6.01052e-6 = 0.8e9 + 1.545455e9 − 0.056529e9 + 0.001250e9 = 2.290176e9.
        assert!(close(pressure(&h, 0.12, 0.1, 0.0).p, 2.290176e9, 1e-5));
        // Tension cut-off: −T(1 − D) = −4 MPa undamaged, −2 MPa at D = 0.5.
        assert_eq!(pressure(&h, -0.01, 0.0, 0.0).p, -4e6);
        assert_eq!(pressure(&h, -0.01, 0.0, 0.5).p, -2e6);
        // Continuity at μ_lock.
        let below = pressure(&h, 0.1 - 1e-6, 0.0, 0.0).p;
        let above = pressure(&h, 0.1 + 1e-6, 0.0, 0.0).p;
        assert!((above - below).abs() < 1e6, "{below} {above}");
    }

    /// Strength by hand: P* = 1 (p = 48 MPa): (0.79 + 1.6) · 48 = 114.72 MPa;
    /// with D = 1: 1.6 · 48 = 76.8 MPa; capped at S_max f_c = 336 MPa for P* = 50;
    /// tension p = −2 MPa: 0.79 (1 − 0.5) · 48 = 18.96 MPa; rate 100/s: × (1 + 0.007 ln 100) = 1.032236.
    #[test]
    fn strength_by_hand() {
        let h = R();
        assert!(close(yield_stress(&h, 48e6, 0.0, 1.0), 114.72e6, 1e-5));
        assert!(close(yield_stress(&h, 48e6, 1.0, 1.0), 76.8e6, 1e-5));
        assert!(close(yield_stress(&h, 50.0 * 48e6, 0.0, 1.0), 336e6, 1e-5));
        assert!(close(yield_stress(&h, -2e6, 0.0, 1.0), 18.96e6, 1e-5));
        assert!(close(
            yield_stress(&h, 48e6, 0.0, 100.0),
            114.72e6 * 1.032236,
            1e-5
        ));
        assert_eq!(yield_stress(&h, -5e6, 0.0, 1.0), 0.0);
    }

    /// Damage: P* + T* = 1 + 4/48: D₁ (1.083333)^1 = 0.0433333 → ΔD = 0.01/0.0433333 = 0.230769;
    /// at low pressure the floor EF_min = 0.01 rules: ΔD = 0.001/0.01 = 0.1.
    #[test]
    fn damage_by_hand() {
        let h = R();
        assert!(close(
            damage_increment(&h, 48e6, 0.006, 0.004),
            0.230769,
            1e-5
        ));
        assert!(close(damage_increment(&h, -4e6, 0.001, 0.0), 0.1, 1e-5));
    }

    /// The f_c rule of physics.md §3.1 at 48 MPa: E = 4730 √48 = 32.7703 GPa, G = E/2.4,
    /// K_el = E/1.8, P_crush = 16 MPa, μ_crush = 16e6/K_el, T = 0.62 √48 = 4.29545 MPa.
    #[test]
    fn fc_rule() {
        let h = Hjc::from_fc(48e6, 2440.0);
        let e = 4730e6 * 48f64.sqrt();
        assert!(close(h.shear_modulus, e / 2.4, 1e-5));
        assert!(close(h.p_crush, 16e6, 1e-6));
        assert!(close(h.mu_crush, 16e6 / (e / 1.8), 1e-5));
        assert!(close(h.t, 0.62e6 * 48f64.sqrt(), 1e-5));
        assert_eq!(
            (h.a, h.b, h.n, h.k1, h.p_lock, h.mu_lock),
            (0.79, 1.6, 0.61, 85e9, 0.8e9, 0.1)
        );
    }
}
